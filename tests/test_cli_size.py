"""`wingmdao size` / `wingmdao n2`: JSON contract of a sizing run, N2 diagram, help."""

import json

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
