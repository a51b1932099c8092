"""``wingmdao flutter``: bad input is rejected before any solve; the JSON of a short sweep."""

import json

import pytest

from wingmdao.cli import main
from wingmdao.cli.flutter import parse_speeds


@pytest.mark.parametrize("speeds, match", [
    (["100", "50", "5"], "increasing"),
    (["-10", "50", "5"], r"--speeds V0 = -10 m/s; allowed range \[0, inf\)"),
    (["10", "50", "1"], r"--speeds N = 1; allowed an integer in \[2, 1000\]"),
    (["10", "50", "0"], r"--speeds N = 0; allowed an integer in \[2, 1000\]"),
    (["a", "50", "3"], "two speeds"),
])
def test_bad_sweep(speeds, match):
    with pytest.raises(ValueError, match=match):
        parse_speeds(speeds)


def test_bad_input_exit_code_before_solve(capsys, monkeypatch):
    import wingmdao.cli.flutter as fl

    monkeypatch.setattr(fl, "analyse", lambda *a, **k: pytest.fail("solve started"))
    assert main(["flutter", "goland", "--speeds", "100", "100", "4"]) == 2
    assert "--speeds V1 = 100.0 m/s; allowed range (V0 = 100.0, inf) m/s" in capsys.readouterr().err
    assert main(["flutter", "crm"]) == 2
    assert "no aerodynamic" in capsys.readouterr().err
    assert main(["flutter", "pegasus", "--speeds", "20", "330", "3"]) == 2
    assert "subsonic" in capsys.readouterr().err
    assert main(["flutter", "goland", "--design", "x.json"]) == 2
    assert "--design applies to the sized pegasus wing" in capsys.readouterr().err


@pytest.mark.parametrize("content, match", [
    ("not json", "not a JSON file"),
    ('{"mass_kg": 1}', "not a box sizing result"),
    ('{"case": "crm", "thickness": {"upper_skin": [0.01], "lower_skin": [0.01], "front_spar": [0.01], '
     '"rear_spar": [0.01]}}', "case 'crm'"),
    ('{"thickness": {"upper_skin": [0.01, 0.01], "lower_skin": [0.01], "front_spar": [0.01], '
     '"rear_spar": [0.01]}}', "has 2 stations; the 20-node PEGASUS beam needs 20"),
])
def test_design_file_errors_before_solve(tmp_path, capsys, monkeypatch, content, match):
    import wingmdao.cli.flutter as fl

    monkeypatch.setattr(fl, "analyse", lambda *a, **k: pytest.fail("solve started"))
    f = tmp_path / "r.json"
    f.write_text(content)
    assert main(["flutter", "pegasus", "--design", str(f)]) == 2
    assert match in capsys.readouterr().err


def test_design_file_thicknesses_reach_the_problem(tmp_path, monkeypatch):
    """--design passes the JSON's per-station walls to the analysis (no solve here)."""
    import wingmdao.cli.flutter as fl

    seen = {}

    def fake(case, speeds, num_nodes, n_modes, thickness, aero_theory="strip"):
        seen.update(thickness)
        raise SystemExit(0)

    monkeypatch.setattr(fl, "analyse", fake)
    walls = {w: [0.002 + 1e-4 * i for i in range(20)] for w in ("upper_skin", "lower_skin", "front_spar",
                                                                  "rear_spar")}
    f = tmp_path / "r.json"
    f.write_text(json.dumps({"case": "pegasus", "thickness": walls, "mass_kg": 300.0}))
    with pytest.raises(SystemExit):
        main(["flutter", "pegasus", "--design", str(f), "--no-plots"])
    assert list(seen["front_spar"]) == pytest.approx(walls["front_spar"])


@pytest.mark.slow
def test_flutter_json_goland(tmp_path, capsys):
    out = tmp_path / "f.json"
    assert main(["flutter", "goland", "--speeds", "100", "280", "4", "--num-nodes", "11",
                 "--json", str(out), "--out", str(tmp_path)]) == 0
    d = json.loads(out.read_text())
    for key in ("flutter_speed_m_s", "flutter_frequency_rad_s", "divergence_speed_m_s",
                "natural_frequencies_rad_s", "speeds", "damping", "frequency_rad_s"):
        assert key in d
    assert len(d["natural_frequencies_rad_s"]) == 6
    assert d["flutter_speed_m_s"] == pytest.approx(137.2, rel=0.02)
    assert (tmp_path / "flutter_goland.png").exists()


def test_json_dash_writes_only_json_to_stdout(capsys):
    assert main(["flutter", "goland", "--num-nodes", "5", "--speeds", "100", "150", "2", "--json", "-",
                 "--no-plots"]) == 0
    cap = capsys.readouterr()
    d = json.loads(cap.out)  # nothing else on stdout
    assert d["case"] == "goland" and "flutter" in cap.err


def test_dlm_refusals_before_solve(capsys, monkeypatch):
    """--aero-theory dlm with --deformed is refused before any solve."""
    import wingmdao.cli.flutter as fl

    monkeypatch.setattr(fl, "analyse", lambda *a, **k: pytest.fail("solve started"))
    monkeypatch.setattr(fl, "analyse_dlm", lambda *a, **k: pytest.fail("solve started"))
    assert main(["flutter", "goland", "--aero-theory", "dlm", "--deformed"]) == 2
    assert "--deformed: the deformed-state sweep uses strip theory" in capsys.readouterr().err


@pytest.mark.slow
def test_flutter_json_goland_dlm(tmp_path):
    """--aero-theory dlm: the doublet lattice's p-k flutter speed on top, the state space within 1 %,
    above strip theory's (the 3-D lift lag of the finite wing), with the fit error reported."""
    out = tmp_path / "f.json"
    assert main(["flutter", "goland", "--aero-theory", "dlm", "--speeds", "100", "220", "7", "--num-nodes", "11",
                 "--json", str(out), "--no-plots"]) == 0
    d = json.loads(out.read_text())
    assert d["aero_theory"] == "dlm" and d["divergence_speed_m_s"] is None
    assert d["flutter_speed_m_s"] == d["dlm"]["pk"]["flutter_speed_m_s"]
    assert d["dlm"]["state_space"]["flutter_speed_m_s"] == pytest.approx(d["flutter_speed_m_s"], rel=0.01)
    assert d["flutter_speed_m_s"] > 1.05 * d["strip"]["flutter_speed_m_s"]
    assert 0.0 < d["dlm"]["rfa"]["fit_error"] < 0.02
