"""``wingmdao loads CASE --matrix FILE.yaml`` (wingmdao.cli.loads): its JSON and files, the refusal
of existing outputs and bad matrix files before any solve, and Ctrl-C keeping the cases done."""

import json
import os

import pytest

from wingmdao.cli import main
from wingmdao.loads import database as ldb
from wingmdao.loads import matrix as lm

pytest.importorskip("yaml")
pytest.importorskip("h5py")

TINY = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "loads-matrix-tiny.yaml")


def test_loads_writes_database_cards_and_json(tmp_path, capsys):
    out, js = tmp_path / "out", tmp_path / "r.json"
    assert main(["loads", "pegasus", "--matrix", TINY, "--out", str(out), "--json", str(js)]) == 0
    res = json.loads(js.read_text())
    assert res["status"] == "complete" and res["case_count"] == res["evaluated_count"] == 2 + 1 + 2
    assert res["wall_time_s"] > 0 and res["ranks"] == 1
    db = ldb.read_database(res["database"])
    assert db.status == "complete" and len(db.cases) == 5 and db.matrix_file == open(TINY).read()
    assert os.path.isfile(res["cards"]["nastran"]) and os.path.isfile(res["cards"]["calculix"])
    assert res["cards"]["load_sets"] >= 1
    # critical cases at the monitoring stations (default root, mid, 3/4 span of 5 nodes): 3 loads each
    rows = res["critical_cases"]
    assert [r["station"] for r in rows] == [0] * 3 + [2] * 3 + [3] * 3
    names = db.case_names
    for r in rows:
        j = lm.COMPONENTS.index(r["component"])
        assert r["max"]["value"] == db.envelope_max[r["station"], j]
        assert r["max"]["case"] == names[db.max_case[r["station"], j]]
    err = capsys.readouterr().err
    assert "5 load cases" in err and "5/5 cases" in err
    # a second run refuses to replace the first one's files without --overwrite
    js.unlink()
    assert main(["loads", "pegasus", "--matrix", TINY, "--out", str(out), "--json", str(js)]) == 2
    assert "pass --overwrite" in capsys.readouterr().err
    assert main(["loads", "pegasus", "--matrix", TINY, "--out", str(out), "--json", str(js), "--overwrite"]) == 0


@pytest.mark.parametrize("text,message", [
    ("speeds: {V_C: {mach: 0.5}}\n", "missing key 'altitudes_ft'"),
    (open(TINY).read().replace("cg_mac: 0.25", "cg_mac: 1.25"), "the CG is outside the chord"),
    (open(TINY).read().replace("[20000]", "[-500]"), "outside the atmosphere"),
    (open(TINY).read() + "gust: {}\n", "unknown key 'gust'"),
])
def test_bad_matrix_is_one_line_before_any_solve(tmp_path, capsys, monkeypatch, text, message):
    path = tmp_path / "m.yaml"
    path.write_text(text)

    def no_solve(*args, **kwargs):
        raise AssertionError("solved")

    monkeypatch.setattr(lm, "evaluate_case", no_solve)
    assert main(["loads", "pegasus", "--matrix", str(path), "--out", str(tmp_path), "--json", "-"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("wingmdao loads: error: --matrix") and message in err[0]


def test_ctrl_c_keeps_the_cases_done(tmp_path, capsys, monkeypatch):
    real, calls = lm.evaluate_case, {"n": 0}

    def interrupted_after_two(module, model, case):
        calls["n"] += 1
        if calls["n"] > 2:
            raise KeyboardInterrupt
        return real(module, model, case)

    monkeypatch.setattr(lm, "evaluate_case", interrupted_after_two)
    js = tmp_path / "r.json"
    assert main(["loads", "pegasus", "--matrix", TINY, "--out", str(tmp_path), "--json", str(js)]) == 130
    res = json.loads(js.read_text())
    assert res["status"] == "interrupted" and res["evaluated_count"] == 2 and res["case_count"] == 5
    db = ldb.read_database(res["database"])
    assert db.status == "interrupted" and db.cases["evaluated"].tolist() == [True, True, False, False, False]


EXAMPLES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "docs", "examples")


def test_docs_example_matrices_are_valid():
    m = lm.read_matrix(os.path.join(EXAMPLES, "pegasus-loads-matrix.yaml"))
    assert len(lm.expand(m)) == 132  # docs/loads-matrix.md
    m = lm.read_matrix(os.path.join(EXAMPLES, "pegasus-load-iteration.yaml"))
    assert len(lm.expand(m)) == 40 and m.num_nodes == 20


@pytest.mark.slow
def test_docs_example_runs_as_it_stands(tmp_path):
    js = tmp_path / "r.json"
    path = os.path.join(EXAMPLES, "pegasus-loads-matrix.yaml")
    assert main(["loads", "pegasus", "--matrix", path, "--out", str(tmp_path), "--json", str(js)]) == 0
    res = json.loads(js.read_text())
    assert res["case_count"] == res["evaluated_count"] == 132 and res["status"] == "complete"


def test_design_thicknesses_change_the_wing(tmp_path):
    """--design: a sizing result's walls (as many stations as model.num_nodes) make a heavier wing,
    whose inertia relieves the maneuver's root shear; a wrong station count is refused."""
    walls = ("upper_skin", "lower_skin", "front_spar", "rear_spar")
    design = tmp_path / "d.json"
    design.write_text(json.dumps({"case": "pegasus", "thickness": {w: [0.02] * 5 for w in walls}}))
    shear = {}
    for tag, extra in (("initial", []), ("thick", ["--design", str(design)])):
        js = tmp_path / f"{tag}.json"
        assert main(["loads", "pegasus", "--matrix", TINY, "--out", str(tmp_path / tag), "--json", str(js), *extra]) == 0
        db = ldb.read_database(json.loads(js.read_text())["database"])
        i = db.case_names.index("h20000_V_C_mtow_maneuver_+2.5g")
        shear[tag] = db.loads_max[i, 0, lm.COMPONENTS.index("vertical_shear")]
    assert shear["thick"] < shear["initial"]  # twice the 10 mm walls: more wing mass at 2.5 g
    design.write_text(json.dumps({"case": "pegasus", "thickness": {w: [0.02] * 20 for w in walls}}))
    assert main(["loads", "pegasus", "--matrix", TINY, "--out", str(tmp_path / "x"), "--design", str(design),
                 "--json", "-"]) == 2
