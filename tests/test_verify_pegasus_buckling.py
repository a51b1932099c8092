"""``wingmdao verify pegasus --buckling``: the stiffened PEGASUS wingbox in CalculiX linear buckling
(docs/verification-calculix.md, "The sized stiffened PEGASUS wingbox in linear buckling").

The design JSON is written here from the package: the stiffened sizing problem analysed at a
tapered design (walls and stiffeners varying along the span), its ``panels`` block and mass as
``wingmdao size pegasus --panels stiffened`` writes them. The deck checks run without ``ccx``;
the solve is skipped without it."""

import json
import shutil
from types import SimpleNamespace

import numpy as np
import pytest

from wingmdao.cli import main

needs_ccx = pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX ccx not installed")
COARSE = ["--span-size", "0.5", "--bay-elements", "1", "--height-elements", "2", "--buckling-modes", "3"]


def _design():
    """A stiffened PEGASUS design as a sizing result JSON (dict), built with the package."""
    from wingmdao.cases import pegasus
    from wingmdao.panel_results import mass_breakdown, panel_summary
    from wingmdao.sizing import build_problem

    setup = pegasus.build(loads="maneuver", panels="stiffened")
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False,
                            section="stiffened", panels=setup.panels)
    nd = int(np.max(setup.geometry.station_map)) + 1
    values = {"t_upper_skin": (0.012, 0.004), "t_lower_skin": (0.008, 0.003), "t_front_spar": (0.006, 0.003),
              "t_rear_spar": (0.005, 0.003), "h_upper_stiffener": (0.06, 0.03), "t_upper_stiffener": (0.005, 0.0025),
              "h_lower_stiffener": (0.045, 0.025), "t_lower_stiffener": (0.004, 0.002)}
    for k, (a, b) in values.items():
        prob.set_val(k, np.linspace(a, b, nd), units="m")
    prob.run_model()
    panels = panel_summary(prob, setup.load_cases, setup.panels)
    mass = float(prob.get_val("box_mass", units="kg")[0] + prob.get_val("rib_mass", units="kg")[0])
    return {"case": "pegasus", "success": False, "mass_kg": mass,
            "thickness": {w: panels[w]["skin_thickness_m"] for w in ("upper_skin", "lower_skin", "front_spar",
                                                                      "rear_spar")},
            "panels": panels, "mass_breakdown_kg": mass_breakdown(prob, setup.geometry, setup.panels)}


@pytest.fixture(scope="module")
def design_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("design") / "stiffened.json"
    path.write_text(json.dumps(_design()))
    return str(path)


def _args(design, **kw):
    from wingmdao.cli._verify_pegasus import verify_pegasus_args

    a = verify_pegasus_args(design=design, buckling=True, span_size=0.5, **kw)
    a.height_elements = kw.get("height_elements", 2)
    return a


def test_deck_strips_ribs_and_mass(design_file):
    """Deck of the stiffened box: round(w / p) = 8 blades on each skin (16 strips), 20 ribs (the
    centreline rib and stations 1-19), every strip as long as the span; FE mass (element area x
    thickness x density) within 1 % of the sizing's mass_kg, and each part within 3 % of the
    sizing's mass breakdown (the ribs: mid-surface against outer box dimensions)."""
    from wingmdao.cli._verify_buckling import build_model, case_setup, design_variables
    from wingmdao.fe.stiffened_box import shell_mass

    data = json.loads(open(design_file).read())
    setup = case_setup(data)
    design = design_variables(data, setup.geometry)
    model, sec = build_model(data, setup, design, SimpleNamespace(
        stiffeners=None, bay_elements=1, web_elements=1, height_elements=2, span_size=0.5), 0.002)
    assert model.count == 8 and model.num_webs == 16 and model.num_ribs == 20
    ribs = [name for _, name, _ in model.deck.elements if name.startswith("RIB")]
    assert len(ribs) == 20
    assert np.allclose(model.thickness_scale, sec.widths / (8 * 0.15))
    # every strip runs root to tip: its elements cover the span once per strip
    for side in ("upper", "lower"):
        ids = set(model.part_elements[f"{side}_stiffeners"])
        ys = [model.deck.nodes[c[0]][1] for _, _, b in model.deck.elements for e, c in b.items() if e in ids]
        assert len(ids) == 8 * (len(model.box.span_y) - 1) // 2
        assert min(ys) == pytest.approx(0.0) and max(ys) < setup.geometry.span_coordinate[-1]
    mass = shell_mass(model.deck, setup.material.rho)
    total = mass["total"] - model.overlap_kg
    assert total == pytest.approx(data["mass_kg"], rel=0.01)
    br = data["mass_breakdown_kg"]
    assert mass["walls"] == pytest.approx(br["skins"] + br["spars"], rel=0.03)
    assert mass["stiffeners"] - model.overlap_kg == pytest.approx(br["stiffeners"], rel=0.03)
    assert mass["ribs"] == pytest.approx(br["ribs"], rel=0.03)


def test_model_factor_per_case_matches_the_panels_block(design_file):
    """The per-case model factors recomputed from the design agree with the JSON's
    ``factored_ratio`` (the worst over both maneuvers): safety factor / max ratio."""
    from wingmdao.cli._verify_buckling import case_setup, design_variables, model_buckling

    data = json.loads(open(design_file).read())
    setup = case_setup(data)
    design = design_variables(data, setup.geometry)
    res = {c: model_buckling(setup, design, c) for c in ("maneuver_pos", "maneuver_neg")}
    for f in ("skin_buckling", "panel_buckling", "stiffener_column"):
        worst = max(max(data["panels"][w]["factored_ratio"][f]) for w in ("upper_skin", "lower_skin"))
        assert min(r["families"][f]["factor"] for r in res.values()) == pytest.approx(1.5 / worst, rel=1e-9)
    worst = max(max(data["panels"][w]["factored_ratio"]["web_buckling"]) for w in ("front_spar", "rear_spar"))
    assert min(r["families"]["web_buckling"]["factor"] for r in res.values()) == pytest.approx(1.5 / worst, rel=1e-9)
    for r in res.values():
        assert r["factor"] == min(r["families"][f]["factor"] for f in ("skin_buckling", "panel_buckling",
                                                                        "web_buckling"))
        assert r["mass_kg"] == pytest.approx(data["mass_kg"], rel=1e-9)


@needs_ccx
@pytest.mark.slow
def test_coarse_run_positive_factor(design_file, tmp_path, capsys):
    """A coarse run (0.5 m span elements, one element per bay) returns a positive first factor,
    the model's factor, where both are, and the counts; ``--running-loads`` adds the static
    state's skin running loads (-1 g: the upper skin in tension, the lower in compression at
    the root, as the model has them)."""
    out = tmp_path / "b.json"
    png = tmp_path / "verify_pegasus_buckling.png"
    assert main(["verify", "pegasus", "--buckling", "--design", design_file, *COARSE, "--json", str(out),
                 "--loads", "maneuver-neg", "--out", str(png.parent), "--running-loads"]) == 0
    assert png.stat().st_size > 0
    r = json.loads(out.read_text())
    assert r["loads_case"] == "maneuver_neg" and r["loads"]["load_factor"] == pytest.approx(-1.0)
    assert r["fe_buckling_factor"] > 0 and r["fe_buckling_factor"] == min(f for f in r["fe_buckling_factors"] if f > 0)
    assert r["model_buckling_factor"] > 0 and r["safety_factor"] == 1.5
    assert r["fe_mode_location"]["wall"] in ("upper_skin", "lower_skin", "front_spar", "rear_spar",
                                             "upper_stiffeners", "lower_stiffeners", "ribs")
    assert 0 <= r["fe_mode_location"]["station"] <= 19
    assert r["model_critical"]["mode"] in ("skin_buckling", "panel_buckling", "web_buckling")
    assert r["mesh"]["num_stiffener_strips"] == 16 and r["mesh"]["num_ribs"] == 20
    assert r["mesh"]["num_elements"] > 0 and r["mesh"]["num_nodes"] > 0 and r["fe_time_s"] > 0
    assert abs(r["mass_kg"]["difference_percent"]) < 1.0
    by_station = r["model_factor_by_station"]
    assert min(min(f for f in v if f is not None) for v in by_station.values()) == \
        pytest.approx(r["model_buckling_factor"], rel=1e-9)
    fe_rows, model = r["fe_running_loads"], r["model_running_loads"]
    assert fe_rows["upper_skin"][0]["n_span_mid"] > 0 > fe_rows["lower_skin"][0]["n_span_mid"]
    assert model["upper_skin"]["n_span_front"][0] > 0 > model["lower_skin"]["n_span_front"][0]
    assert len(model["lower_skin"]["n_chord"]) == 20


def _fails(argv, capsys, flag):
    assert main(["verify", "pegasus", *argv]) == 2
    err = capsys.readouterr().err
    assert flag in err and len(err.strip().splitlines()) == 1, err
    return err


def test_bad_input_exit_code_2(design_file, tmp_path, capsys):
    """An unstiffened design, a missing file, no --design, an unknown load case: exit code 2, one
    line naming the flag, before any solve."""
    unstiffened = tmp_path / "u.json"
    data = json.loads(open(design_file).read())
    data.pop("panels")
    unstiffened.write_text(json.dumps(data))
    assert "not a stiffened design" in _fails(["--buckling", "--design", str(unstiffened)], capsys, "--design")
    assert "no such file" in _fails(["--buckling", "--design", str(tmp_path / "none.json")], capsys, "--design")
    _fails(["--buckling"], capsys, "--design")
    _fails(["--buckling", "--design", design_file, "--loads", "gust-peak"], capsys, "--buckling --loads = gust-peak")
    _fails(["--buckling", "--design", design_file, "--fidelity", "solid"], capsys, "--fidelity")
    _fails(["--buckling", "--design", design_file, "--bay-elements", "0"], capsys, "--bay-elements")


def test_fe_ribs_take_the_designs_sized_thickness(design_file):
    """Each FE rib takes the thickness of the design's rib at its position (the ``ribs`` block of
    the sizing result, sized for crushing); a rib the block does not list takes the minimum; the
    deck's rib sections carry those thicknesses."""
    from wingmdao.cli._verify_buckling import build_model, case_setup, design_variables, rib_thicknesses
    from wingmdao.fe.stiffened_box import _section_thickness

    data = json.loads(open(design_file).read())
    setup = case_setup(data)
    ribs_y = list(setup.panels.rib_positions)
    sized = [0.002 + 0.0001 * k for k in range(len(ribs_y) - 1)]
    data["ribs"] = {"positions_m": ribs_y[1:], "thickness_m": sized}
    t = rib_thicknesses(data, ribs_y, 0.002)
    assert t == [0.002] + sized
    model, _ = build_model(data, setup, design_variables(data, setup.geometry), SimpleNamespace(
        stiffeners=None, bay_elements=1, web_elements=1, height_elements=2, span_size=0.5), t)
    thick = _section_thickness(model.deck)
    assert [thick[f"RIB{k + 1}"] for k in range(len(ribs_y))] == pytest.approx(t, rel=1e-9)
    data["ribs"]["thickness_m"] = sized[:-1]
    with pytest.raises(ValueError, match="ribs.thickness_m"):
        rib_thicknesses(data, ribs_y, 0.002)
