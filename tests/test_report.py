"""`wingmdao report` on a small recorded optimization: history printed, plots written."""

import os

import numpy as np
import openmdao.api as om

from wingmdao.cli import main
from wingmdao.optimize import add_recorder, make_driver


def _record(path):
    prob = om.Problem(reports=False)
    walls = ["t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar"]
    expr = " + ".join(f"sum(({w} - 0.01*{k + 1})**2)" for k, w in enumerate(walls))
    prob.model.add_subsystem("f", om.ExecComp(f"mass = {expr}", **{w: np.ones(3) for w in walls}),
                             promotes=["*"])
    for w in walls:
        prob.model.add_design_var(w, lower=0.0, upper=1.0)
    prob.model.add_objective("mass")
    prob.driver, _ = make_driver("SLSQP", disp=False)
    add_recorder(prob, path)
    prob.setup()
    prob.run_driver()
    prob.cleanup()


def test_report_prints_history_and_writes_plots(tmp_path, capsys):
    rec = str(tmp_path / "run.sql")
    _record(rec)
    assert main(["report", rec, "--plots", str(tmp_path / "p")]) == 0
    out = capsys.readouterr().out
    assert "objective" in out and "iterations.png" in out
    assert os.path.getsize(tmp_path / "p" / "thickness_final.png") > 1000


def test_report_missing_file_is_a_clean_error(tmp_path, capsys):
    assert main(["report", str(tmp_path / "nope.sql")]) == 2
    assert "does not exist" in capsys.readouterr().err


def test_report_compares_several_recordings(tmp_path, capsys):
    a, b = str(tmp_path / "maneuver.sql"), str(tmp_path / "gust.sql")
    _record(a)
    _record(b)
    assert main(["report", a, b, "--plots", str(tmp_path / "p")]) == 0
    out = capsys.readouterr().out
    assert out.count("driver iterations") == 2
    assert os.path.getsize(tmp_path / "p" / "thickness_comparison.png") > 1000
    assert os.path.getsize(tmp_path / "p" / "gust" / "iterations.png") > 1000


def test_constraint_margin_of_equality_lower_and_upper_bounds():
    """read_history's worst constraint: value - upper, lower - value, |value - equals| (<= 0 holds)."""
    import numpy as np

    from wingmdao.report import constraint_margin

    np.testing.assert_allclose(constraint_margin([0.49, 0.5], {"equals": 0.5}), [0.01, 0.0], atol=1e-15)
    np.testing.assert_allclose(constraint_margin([-0.2], {"upper": 0.0, "lower": -1e30}), [-0.2])
    np.testing.assert_allclose(constraint_margin([3.0], {"lower": 1.0, "upper": 2.0}), [1.0])
    np.testing.assert_allclose(constraint_margin([0.5], {"lower": 1.0}), [0.5])
    np.testing.assert_allclose(constraint_margin([0.7], {}), [0.7])


def test_report_refuses_to_replace_earlier_plots_without_overwrite(tmp_path, capsys):
    rec = str(tmp_path / "run.sql")
    _record(rec)
    out = tmp_path / "p"
    assert main(["report", rec, "--out", str(out)]) == 0
    before = os.path.getmtime(out / "iterations.png")
    capsys.readouterr()
    assert main(["report", rec, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "iterations.png" in err and "--overwrite" in err
    assert os.path.getmtime(out / "iterations.png") == before
    assert main(["report", rec, "--out", str(out), "--overwrite"]) == 0
