"""`wingmdao size` / `wingmdao n2`: JSON contract of a sizing run, N2 diagram, help."""

import json

import pytest

from wingmdao.cli import main


def test_size_json_contract(tmp_path):
    out = tmp_path / "c.json"
    rc = main(["size", "cantilever", "--stations", "5", "--out", str(tmp_path), "--json", str(out),
               "--no-plots", "--quiet"])
    res = json.loads(out.read_text())
    assert rc == 0 and res["success"]
    for key in ("success", "mass_kg", "ks", "iterations", "wall_s", "driver", "recording"):
        assert key in res
    assert set(res["ks"]["static"]) == {"ss_tension", "ss_compression"}
    assert len(res["width"]) == 5


def test_box_case_json_has_thickness_per_wall(tmp_path):
    out = tmp_path / "p.json"
    assert main(["size", "pegasus", "--analysis-only", "--out", str(tmp_path), "--json", str(out)]) == 0
    res = json.loads(out.read_text())
    assert set(res["thickness"]) == {"upper_skin", "lower_skin", "front_spar", "rear_spar"}
    assert all(len(v) == 20 for v in res["thickness"].values())
    # V_D = V_C / 0.8 (14 CFR 25.335(b)(1)), V_C = Mach 0.5 at 20 000 ft, ISA a = sqrt(1.4 R T)
    t_isa = 288.15 - 0.0065 * 20000 * 0.3048
    assert res["dive_speed_m_s"] == pytest.approx(0.5 * (1.4 * 287.053 * t_isa) ** 0.5 / 0.8, rel=1e-4)
    # the 10 mm initial design: no flutter and no divergence below the search's end
    assert res["flutter_speed_m_s"] is None and res["divergence_speed_m_s"] is None
    assert res["flutter_search_max_speed_m_s"] == 300.0


def test_flutter_margin_analysis_json(tmp_path):
    """--flutter-margin adds flutter_ks (negative: the initial design does not flutter below 1.15 V_D)."""
    out = tmp_path / "p.json"
    assert main(["size", "pegasus", "--analysis-only", "--flutter-margin", "1.15", "--no-flutter-search",
                 "--out", str(tmp_path), "--json", str(out), "--no-plots"]) == 0
    res = json.loads(out.read_text())
    assert res["flutter_ks"] < 0.0 and res["flutter_margin"] == 1.15
    assert res["flutter_constraint_speeds_m_s"][-1] == pytest.approx(1.15 * res["dive_speed_m_s"])
    assert "flutter_speed_m_s" not in res


def test_n2_is_written(tmp_path, capsys):
    assert main(["n2", "pegasus", "--out", str(tmp_path)]) == 0
    html = (tmp_path / "pegasus_n2.html").read_text()
    assert "cases" in html and "section" in html


def test_help_lists_cases(capsys):
    try:
        main(["size", "--help"])
    except SystemExit:
        pass
    assert "pegasus" in capsys.readouterr().out


PEGASUS_ANALYSIS = ["size", "pegasus", "--analysis-only", "--no-plots", "--quiet"]


def test_flutter_search_runs_after_the_json_and_ctrl_c_keeps_it(tmp_path, monkeypatch):
    """The flutter search runs last, with the sizing problem freed: the JSON is written before it,
    and Ctrl-C during the search keeps that result, marked interrupted."""
    import wingmdao.cli.size as size_command  # the command's flutter_search (wingmdao.stability.cases)

    out = tmp_path / "p.json"
    seen = {}

    def interrupted_search(*args, **kwargs):
        seen["json"] = json.loads(out.read_text())  # written before the search
        raise KeyboardInterrupt

    monkeypatch.setattr(size_command, "flutter_search", interrupted_search)
    assert main([*PEGASUS_ANALYSIS, "--out", str(tmp_path), "--json", str(out)]) == 130
    assert "thickness" in seen["json"] and "flutter_speed_m_s" not in seen["json"]
    res = json.loads(out.read_text())
    assert res["interrupted"] is True and res["thickness"] == seen["json"]["thickness"]
    assert "dive_speed_m_s" in res and "flutter_speed_m_s" not in res


def test_flutter_result_on_standard_output_is_one_document(tmp_path, monkeypatch, capsys):
    import wingmdao.cli.size as size_command  # the command's flutter_search (wingmdao.stability.cases)

    found = {"flutter_speed": 250.0, "flutter_frequency": 30.0, "divergence_speed": None,
             "sweep_max_speed": 300.0, "dive_speed": 197.5}
    monkeypatch.setattr(size_command, "flutter_search", lambda *a, **k: found)
    assert main([*PEGASUS_ANALYSIS, "--out", str(tmp_path), "--json", "-"]) == 0
    res = json.loads(capsys.readouterr().out)  # one JSON document, the search's result in it
    assert res["flutter_speed_m_s"] == 250.0 and res["flutter_search_max_speed_m_s"] == 300.0
