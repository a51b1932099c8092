"""``wingmdao gust``: JSON keys, bad input, and the Pratt-Walker check on the stiffened PEGASUS wing."""

import json

import numpy as np
import pytest

from wingmdao.cli import main


def test_gust_bad_gradient(capsys):
    assert main(["gust", "pegasus", "--gust-gradient-ft", "20", "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert "--gust-gradient-ft = 20.0 ft; allowed range [30, 350] ft" in err


def test_gust_bad_stiffness_scale(capsys):
    assert main(["gust", "pegasus", "--stiffness-scale", "0", "--no-plots"]) == 2
    assert "--stiffness-scale" in capsys.readouterr().err


@pytest.mark.slow
def test_gust_pegasus_stiff_free_plunge_pratt_walker(tmp_path, capsys):
    """Stiffened (x1000) PEGASUS wing in free plunge, 1-cos gust of 12.5 mean chords: peak dn over
    the quasi-steady dn = K_g = 0.88 mu / (5.3 + mu) (NACA Rep. 1206) within 5 % (ours +2.3 %)."""
    mean_chord_ft = 586.3328 / 80.58962
    out = tmp_path / "g.json"
    rc = main(["gust", "pegasus", "--gust-gradient-ft", f"{12.5 * mean_chord_ft:.4f}", "--stiffness-scale", "1000",
               "--t-final", "1.5", "--dt", "0.005", "--gust-start", "0.1", "--json", str(out), "--out", str(tmp_path)])
    assert rc == 0
    res = json.loads(out.read_text())
    for key in ("time", "load_factor", "peak_incremental_load_factor", "quasi_steady_incremental_load_factor",
                "wing_lift_slope_per_rad", "mass_parameter", "mean_chord_m", "wing_loading_pa",
                "root_bending_moment", "tip_displacement"):
        assert key in res
    assert len(res["load_factor"]) == len(res["time"]) == len(res["root_bending_moment"])
    mu = res["mass_parameter"]
    ratio = res["peak_incremental_load_factor"] / res["quasi_steady_incremental_load_factor"]
    assert abs(ratio / (0.88 * mu / (5.3 + mu)) - 1) < 0.05
    assert np.isclose(res["mean_chord_m"], mean_chord_ft * 0.3048, rtol=1e-9)
    assert (tmp_path / "pegasus_gust.png").exists()


def test_gust_strip_peak_equals_quasi_steady_closed_form(tmp_path):
    """--aero strip: the sizing's rigid-wing quasi-steady strip loads on the clamped beam; on the
    unswept PEGASUS wing (one leading-edge x, no penetration lag) the peak incremental load factor is
    the closed form rho0 U_de V_e a / (2 W/S) with a = 2 int 2 pi c dy / S (Pratt-Walker without K_g)."""
    out = tmp_path / "s.json"
    rc = main(["gust", "pegasus", "--aero", "strip", "--t-final", "1.6", "--dt", "0.02", "--no-plots",
               "--json", str(out)])
    assert rc == 0
    res = json.loads(out.read_text())
    assert res["aero"] == "strip" and res["plunge"] is False and res["trim_alpha_rad"] is None
    np.testing.assert_allclose(res["load_factor"][0], 1.0, rtol=1e-9)  # Schrenk 1 g start
    rho0, V_e = 1.225, res["airspeed_tas_m_s"] * np.sqrt(res["density_kg_m3"] / 1.225)
    dn = rho0 * res["u_ds_eas_m_s"] * V_e * res["wing_lift_slope_per_rad"] / (2 * res["wing_loading_pa"])
    np.testing.assert_allclose(res["peak_incremental_load_factor"], dn, rtol=1e-3)
    assert max(res["root_bending_moment"]) > 1.5 * res["root_bending_moment"][0]


def test_gust_plunge_spelling_and_strip_plunge_error(capsys):
    assert main(["gust", "pegasus", "--aero", "strip", "--plunge", "free", "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert "--plunge free needs --aero coupled" in err
    assert main(["gust", "pegasus", "--aero", "strip", "--lifting-line", "--no-plots"]) == 2
    assert "--lifting-line" in capsys.readouterr().err


def test_gust_dlm_refusals_before_solve(capsys, monkeypatch):
    """--aero-theory dlm: --tail-lag (its tail is quasi-steady), an unreadable --alleviation file, --aero strip, the
    deprecated --lifting-line beside it, and --modes out of range or without dlm are refused
    before any solve."""
    import wingmdao.cli.gust as gust_command

    monkeypatch.setattr(gust_command, "dlm_gust_response", lambda *a, **k: pytest.fail("solve started"))
    pitch = ["--pitch", "free", "--pitch-inertia", "1e6", "--cg-x", "5", "--tail-arm", "15", "--tail-area", "20",
             "--tail-lift-slope", "4"]
    for argv, msg in ((["--aero-theory", "dlm", *pitch, "--tail-lag"], "--tail-lag: the doublet lattice's tail"),
                      (["--aero-theory", "dlm", "--alleviation", "x.yaml"], "--alleviation x.yaml"),
                      (["--aero", "strip", "--aero-theory", "dlm"], "applies to --aero coupled"),
                      (["--aero-theory", "dlm", "--clamped", "--lifting-line"], "two aerodynamic theories"),
                      (["--aero-theory", "dlm", "--clamped", "--modes", "1"], "--modes = 1; allowed range [2, 20]"),
                      (["--clamped", "--modes", "4"], "--modes = 4 applies to --aero-theory dlm only")):
        assert main(["gust", "pegasus", "--no-plots", *argv]) == 2
        assert msg in capsys.readouterr().err


@pytest.mark.slow
def test_gust_pegasus_dlm_against_vortex_lattice(tmp_path):
    """PEGASUS, clamped, 1-cos gust of H = 350 ft (reduced frequency pi b / H ~ 0.02, nearly
    quasi-steady): the doublet lattice in the modal basis (6 modes, Roger lags, force summation)
    against the coupled beam with the vortex lattice's steady lift and per-station Wagner/Kuessner
    lags (another model and code path): wing lift slope within 1 % (the doublet lattice at k = 0
    is a vortex lattice), peak root-bending increment and peak load-factor increment within 5 %;
    the JSON carries the station load histories and the fit errors."""
    out = {}
    for theory in ("dlm", "vlm"):
        path = tmp_path / f"{theory}.json"
        assert main(["gust", "pegasus", "--aero-theory", theory, "--clamped", "--t-final", "1.6",
                     "--no-plots", "--json", str(path)]) == 0
        out[theory] = json.loads(path.read_text())
    d, v = out["dlm"], out["vlm"]
    assert d["loads_include_1g"] is False and v["loads_include_1g"] is True
    assert d["wing_lift_slope_per_rad"] == pytest.approx(v["wing_lift_slope_per_rad"], rel=0.01)
    assert d["peak_incremental_root_bending_moment"] == pytest.approx(v["peak_incremental_root_bending_moment"], rel=0.05)
    assert d["peak_incremental_load_factor"] == pytest.approx(v["peak_incremental_load_factor"], rel=0.05)
    M = np.asarray(d["station_bending_moment"])
    assert M.shape == (len(d["time"]), len(d["station_y_m"]))
    np.testing.assert_allclose(M[:, 0], d["root_bending_moment"])
    assert np.abs(M[:, -1]).max() < 1e-3 * np.abs(M[:, 0]).max()      # the free tip carries no moment
    assert d["dlm"]["fit_error"] < 0.02 and d["dlm"]["station_load_fit_error"] < 0.02


@pytest.mark.slow
def test_gust_pegasus_dlm_free_plunge_and_pitch_against_vortex_lattice(tmp_path):
    """PEGASUS free in plunge, then in plunge and pitch (the illustrative ATR 42-class tail and inertia
    of docs/aeroelasticity.md), Table 5.3 gust: the doublet lattice with the rigid-body modes in its
    modal basis (increments on 1 g) against the coupled beam with the vortex lattice trimmed at 1 g
    (another model and code path): peak up and down load-factor increments, the pitch attitude's
    minimum and the peak root-bending increment within 3 % (0.3 %, 0.6 %, 0.2 %, 1.6 % in the 5 s runs of
    docs/aerodynamics-3d.md)."""
    pitch = ["--pitch", "free", "--pitch-inertia", "345000", "--cg-x", "0.67", "--tail-arm", "12", "--tail-area",
             "11.7", "--tail-lift-slope", "4"]
    for extra, t_final in (([], "1.6"), (pitch, "3.0")):
        out = {}
        for theory in ("dlm", "vlm"):
            path = tmp_path / f"{theory}.json"
            assert main(["gust", "pegasus", "--aero-theory", theory, *extra, "--t-final", t_final, "--no-plots",
                         "--overwrite", "--json", str(path)]) == 0
            out[theory] = json.loads(path.read_text())
        d, v = out["dlm"], out["vlm"]
        assert d["plunge"] and d["dlm"]["rigid_body_modes"] == (["plunge", "pitch"] if extra else ["plunge"])
        for key in ("peak_up_incremental_load_factor", "peak_incremental_root_bending_moment"):
            assert d[key] == pytest.approx(v[key], rel=0.03)
        if extra:
            assert d["peak_down_incremental_load_factor"] == pytest.approx(v["peak_down_incremental_load_factor"],
                                                                           rel=0.03)
            assert min(d["pitch_angle_rad"]) == pytest.approx(min(v["pitch_angle_rad"]), rel=0.03)


@pytest.mark.parametrize("argv, msg", [
    (["gust", "crm", "--model", "stick"], "--model stick: case 'crm' has no stick model; allowed: pegasus"),
    (["gust", "pegasus", "--model", "stick", "--clamped"], "--model stick does not take --clamped"),
    (["gust", "pegasus", "--model", "stick", "--aero-theory", "vlm"], "--model stick does not take --aero-theory vlm"),
])
def test_gust_stick_model_refuses_the_lone_wing_options(argv, msg, capsys):
    assert main(argv + ["--no-plots"]) == 2
    assert msg in capsys.readouterr().err


@pytest.mark.slow
def test_gust_pegasus_stick_model_json(tmp_path):
    """--model stick: trimmed start (the aerodynamic force balances the half aircraft's weight, whose
    mass comes from the beams and lumped masses, not the aerodynamics), monitoring-station loads with
    their envelopes."""
    out = tmp_path / "s.json"
    rc = main(["gust", "pegasus", "--model", "stick", "--t-final", "1.0", "--dt", "0.02", "--json", str(out),
               "--no-plots"])
    assert rc == 0
    res = json.loads(out.read_text())
    assert res["model"] == "stick"
    assert abs(res["load_factor"][0] - 1.0) < 1e-6
    assert res["peak_up_incremental_load_factor"] > 0.3
    labels = list(res["monitoring_loads"])
    assert labels[0] == "wing root" and labels[-1] == "tail root" and any(k.startswith("fuselage") for k in labels)
    for v in res["monitoring_loads"].values():
        m = np.asarray(v["moment_n_m"])
        assert m.shape == (len(res["time"]), 3)
        np.testing.assert_allclose(v["moment_max_n_m"], m.max(axis=0))
    # 1 g wing root bending (M_x at the root rib) is positive (lift outboard of it exceeds the wing's weight)
    assert res["monitoring_loads"]["wing root"]["moment_n_m"][0][0] > 0
    # potato plots: wing root bending (M_x) with torsion (M_y); the fuselage in symmetric flight has
    # one moment (pitch, M_y), paired with its vertical shear
    loads = res["monitoring_loads"]
    assert loads["wing root"]["potato_components"] == ["M_x", "M_y"]
    fus = next(v for k, v in loads.items() if k.startswith("fuselage"))
    assert fus["potato_components"] == ["M_y", "F_z"]
    hull = np.asarray(loads["wing root"]["potato_hull"])
    np.testing.assert_array_equal(hull[0], hull[-1])
    assert hull[:, 0].max() == pytest.approx(loads["wing root"]["moment_max_n_m"][0], rel=1e-12)


def test_stick_stiffness_scale_scales_the_elastic_frequencies_by_its_square_root():
    """Every beam's stiffness times S, masses unchanged: each elastic frequency of the free half aircraft
    (a linear pencil K - omega^2 M about the unloaded jig, rigid joints and symmetry rows unscaled)
    times sqrt(S) exactly."""
    from wingmdao.cases import pegasus_stick
    from wingmdao.cli.gust import scale_stick_stiffness

    aircraft = pegasus_stick.build(6)
    before = pegasus_stick.natural_frequencies(aircraft, count=4)
    scale_stick_stiffness(aircraft, 4.0)
    after = pegasus_stick.natural_frequencies(aircraft, count=4)
    assert after["rigid"] == before["rigid"] == 3
    np.testing.assert_allclose(after["hz"] / before["hz"], 2.0, rtol=1e-6)


_WALLS = {w: [0.004 + 2e-4 * i for i in range(20)] for w in ("upper_skin", "lower_skin", "front_spar", "rear_spar")}


@pytest.mark.parametrize("content, extra, match", [
    ("not json", [], "not a JSON file"),
    ('{"mass_kg": 1}', [], "not a box sizing result"),
    ('{"case": "crm", "thickness": {"upper_skin": [0.01], "lower_skin": [0.01], "front_spar": [0.01], '
     '"rear_spar": [0.01]}}', [], "case 'crm'"),
    ('{"thickness": {"upper_skin": [0.01, 0.01], "lower_skin": [0.01], "front_spar": [0.01], '
     '"rear_spar": [0.01]}}', [], "has 2 stations; the 20-node beam"),
    (json.dumps({"case": "pegasus", "thickness": _WALLS}), ["--stiffness-scale", "0"],
     "--stiffness-scale = 0.0; allowed range [0.001, 1e+06]"),
    (json.dumps({"case": "pegasus", "thickness": _WALLS}), ["--stiffness-scale", "1e5"],
     "--stiffness-scale = 100000.0; allowed range [0.1, 100] with --model stick"),
])
def test_gust_stick_design_and_stiffness_scale_errors_before_solve(tmp_path, capsys, monkeypatch, content, extra,
                                                                     match):
    from wingmdao.cases import pegasus_stick

    monkeypatch.setattr(pegasus_stick, "build", lambda *a, **k: pytest.fail("stick model built"))
    f = tmp_path / "r.json"
    f.write_text(content)
    assert main(["gust", "pegasus", "--model", "stick", "--design", str(f), *extra, "--no-plots"]) == 2
    assert match in capsys.readouterr().err


def test_gust_stick_design_and_stiffness_scale_reach_the_model(tmp_path, monkeypatch):
    """--design: the stick model's wing has the sizing result's walls (its section stiffness that of
    those walls, not the initial ones); --stiffness-scale multiplies every beam's stiffness (no march)."""
    from wingmdao.cases import pegasus_stick

    seen = {}

    def fake(aircraft, *a, **k):
        seen["aircraft"] = aircraft
        raise SystemExit(0)

    monkeypatch.setattr(pegasus_stick, "gust_response", fake)
    f = tmp_path / "r.json"
    f.write_text(json.dumps({"case": "pegasus", "thickness": _WALLS, "mass_kg": 300.0}))
    with pytest.raises(SystemExit):
        main(["gust", "pegasus", "--model", "stick", "--design", str(f), "--stiffness-scale", "3", "--no-plots"])
    got = seen["aircraft"].model.params
    designed = pegasus_stick.build(20, thickness=_WALLS).model.params
    initial = pegasus_stick.build(20).model.params
    for beam in ("wing", "fuselage", "fin", "tail"):
        np.testing.assert_allclose(got[beam]["stiffness_csn"], 3.0 * np.asarray(designed[beam]["stiffness_csn"]),
                                   rtol=1e-12)
        np.testing.assert_allclose(got[beam]["compliance_csn"], np.asarray(designed[beam]["compliance_csn"]) / 3.0,
                                   rtol=1e-12)
    assert not np.allclose(designed["wing"]["stiffness_csn"], initial["wing"]["stiffness_csn"], rtol=1e-3)


_SET = {"flight_points": [{"altitude_ft": 25000, "mach": 0.5, "u_ref_fps": 30}], "gradients_ft": [350],
        "signs": "both"}


@pytest.mark.parametrize("argv, content, match", [
    (["--model", "wing"], _SET, "--gust-set {f}: applies to --model stick"),
    (["--model", "stick", "--gust-gradient-ft", "100"], _SET,
     "--gust-set {f} gives the flight points, gradients and U_ref; drop --gust-gradient-ft"),
    (["--model", "stick", "--mach", "0.4"], _SET, "drop --mach"),
    (["--model", "stick"], None, "--gust-set '{f}' does not exist"),
    (["--model", "stick"], {**_SET, "flight_points": [{"altitude_ft": 25000, "mach": 0.5, "weight_lb": 30000}]},
     "has weight_lb = 30000; the stick model weighs the TOGW"),
    (["--model", "stick"], {**_SET, "flight_points": [{"altitude_ft": 25000, "v_tas_m_s": 400.0}]},
     "flight point 0 has Mach 1.29; allowed range (0, 1)"),
    (["--model", "stick"], {**_SET, "gradients_ft": [20]}, "gradient"),
])
def test_gust_stick_gust_set_errors_before_solve(tmp_path, capsys, monkeypatch, argv, content, match):
    from wingmdao.cases import pegasus_stick

    monkeypatch.setattr(pegasus_stick, "build", lambda *a, **k: pytest.fail("stick model built"))
    f = tmp_path / "set.json"
    if content is not None:
        f.write_text(json.dumps(content))
    assert main(["gust", "pegasus", *argv, "--gust-set", str(f), "--no-plots"]) == 2
    assert match.format(f=f) in capsys.readouterr().err


def test_stick_set_envelope_extremes_owners_and_hull():
    """The set's envelope is the extreme over every instant of every gust, named by the gust that gives
    it; its potato hull holds every gust's correlated pairs."""
    from wingmdao.envelope import stick_set_envelope
    from wingmdao.envelope import monitoring_potatoes

    rng = np.random.default_rng(7)
    gusts = [{"name": f"g{k}", "monitoring_loads": {"root": {"force_n": rng.normal(size=(30, 3)) * 1e3,
                                                             "moment_n_m": rng.normal(size=(30, 3)) * [5e4, 1e4, 1e2]}}}
             for k in range(3)]
    gusts[1]["monitoring_loads"]["root"]["moment_n_m"][7, 0] = 9e5      # the largest bending: gust g1
    gusts[2]["monitoring_loads"]["root"]["force_n"][3, 2] = -8e3        # the lowest F_z: gust g2
    env = stick_set_envelope(gusts)["root"]
    assert env["moment_max_n_m"][0] == 9e5 and env["moment_max_gust"][0] == "g1"
    assert env["force_min_n"][2] == -8e3 and env["force_min_gust"][2] == "g2"
    for key, fn, comp in (("moment_min_n_m", np.min, "moment_n_m"), ("force_max_n", np.max, "force_n")):
        np.testing.assert_array_equal(env[key], fn(np.vstack([g["monitoring_loads"]["root"][comp] for g in gusts]),
                                                   axis=0))
    assert env["potato_components"] == ["M_x", "M_y"]
    hull = np.asarray(env["potato_hull"])
    for g in gusts:        # every point inside the closed counter-clockwise hull (cross products >= 0)
        pts = monitoring_potatoes({"r": {"moment": g["monitoring_loads"]["root"]["moment_n_m"],
                                         "force": g["monitoring_loads"]["root"]["force_n"]}})["r"]["values"]
        e = np.diff(hull, axis=0)
        for p in pts:
            cross = e[:, 0] * (p[1] - hull[:-1, 1]) - e[:, 1] * (p[0] - hull[:-1, 0])
            assert np.all(cross >= -1e-6 * np.abs(hull).max())


@pytest.mark.slow
def test_gust_stick_gust_set_run(tmp_path):
    """--gust-set on the stick model: the set's up gust (25 000 ft, M 0.5, U_ref 30 ft/s, H = 350 ft; F_g = 1
    at Z_mo) is the single-gust command's gust (U_ds from the gust-set module against the command's
    U_ref (H/350)^(1/6)): the same load factor history; the down gust's increment mirrors the up gust's
    (small gusts on a trimmed aircraft: linear to a few per cent); the envelope over the set holds
    each gust's extremes."""
    f = tmp_path / "set.json"
    f.write_text(json.dumps(_SET))
    out, single = tmp_path / "set_out.json", tmp_path / "single.json"
    common = ["--t-final", "1.0", "--dt", "0.02", "--no-plots"]
    assert main(["gust", "pegasus", "--model", "stick", "--gust-set", str(f), "--json", str(out), *common]) == 0
    assert main(["gust", "pegasus", "--model", "stick", "--json", str(single), *common]) == 0
    res, one = json.loads(out.read_text()), json.loads(single.read_text())
    up, down = res["gusts"]
    assert up["sign"] == 1 and down["sign"] == -1 and up["name"].endswith("up")
    assert up["u_ds_eas_m_s"] == pytest.approx(one["u_ds_eas_m_s"], rel=1e-12)
    np.testing.assert_allclose(up["load_factor"], one["load_factor"], rtol=1e-9)
    dn_up = np.asarray(up["load_factor"]) - up["load_factor"][0]
    dn_down = np.asarray(down["load_factor"]) - down["load_factor"][0]
    assert np.abs(dn_up + dn_down).max() < 0.05 * np.abs(dn_up).max()
    assert res["peak_up_gust"] == up["name"] and res["peak_down_gust"] == down["name"]
    for label, env in res["monitoring_envelope"].items():
        for key in ("moment_max_n_m", "force_max_n"):
            both = np.maximum(up["monitoring_loads"][label][key], down["monitoring_loads"][label][key])
            np.testing.assert_allclose(env[key], both, rtol=0, atol=0)
        assert env["moment_min_gust"][0] in (up["name"], down["name"])
