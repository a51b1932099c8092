"""Driver selection: falls back to SciPy SLSQP without pyoptsparse; bad names fail clearly."""

import numpy as np
import openmdao.api as om
import pytest

from wingmdao.optimize import make_driver, pyoptsparse_available


def test_fallback_or_pyoptsparse():
    driver, desc = make_driver("SLSQP")
    if pyoptsparse_available():
        assert isinstance(driver, om.pyOptSparseDriver) and desc.endswith("SLSQP")
    else:
        assert isinstance(driver, om.ScipyOptimizeDriver) and desc == "ScipyOptimizeDriver/SLSQP"


def test_unknown_optimizer_is_rejected():
    with pytest.raises(ValueError, match="optimizer must be one of"):
        make_driver("GRADIENT-FREE")


def test_paraboloid_minimum_recorded(tmp_path):
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("f", om.ExecComp("y = (x - 3.0)**2 + 1.0"), promotes=["*"])
    prob.model.add_design_var("x", lower=-10, upper=10)
    prob.model.add_objective("y")
    prob.driver, _ = make_driver("SLSQP", disp=False)
    from wingmdao.optimize import add_recorder
    add_recorder(prob, str(tmp_path / "run.sql"))
    prob.setup()
    prob.run_driver()
    assert abs(prob.get_val("x")[0] - 3.0) < 1e-4
    cr = om.CaseReader(str(tmp_path / "run.sql"))
    assert len(cr.list_cases("driver", out_stream=None)) >= 2


def test_recording_is_write_ahead_logged_while_running_and_one_plain_file_after(tmp_path):
    """add_recorder's WalSqliteRecorder: WAL journal while the driver runs (no sync per record),
    every case readable (also before cleanup, from the log), and after cleanup a plain SQLite file
    in the default journal mode with no -wal file left."""
    import sqlite3

    from wingmdao.optimize import add_recorder

    path = tmp_path / "run.sql"
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("f", om.ExecComp("y = (x - 3.0)**2 + 1.0"), promotes=["*"])
    prob.model.add_design_var("x", lower=-10, upper=10)
    prob.model.add_objective("y")
    prob.driver, _ = make_driver("SLSQP", disp=False)
    rec = add_recorder(prob, str(path))
    prob.setup()
    prob.run_driver()
    assert rec.connection.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    assert rec.connection.execute("PRAGMA synchronous").fetchone()[0] == 1  # NORMAL
    n_running = len(om.CaseReader(str(path)).list_cases("driver", out_stream=None))
    assert n_running >= 2
    prob.cleanup()
    assert not (tmp_path / "run.sql-wal").exists()
    with sqlite3.connect(path) as con:
        assert con.execute("PRAGMA journal_mode").fetchone()[0] == "delete"
    cr = om.CaseReader(str(path))
    assert len(cr.list_cases("driver", out_stream=None)) == n_running
    assert abs(cr.get_case(cr.list_cases("driver", out_stream=None)[-1]).get_val("x")[0] - 3.0) < 1e-4


def test_progress_printer_prints_one_line_per_evaluation():
    import io

    from wingmdao.optimize import ProgressPrinter

    prob = om.Problem(reports=False)
    prob.model.add_subsystem("f", om.ExecComp("mass = (x - 3.0)**2 + 1.0"), promotes=["*"])
    prob.model.add_design_var("x", lower=-10, upper=10)
    prob.model.add_objective("mass")
    prob.driver, _ = make_driver("SLSQP", disp=False)
    buf = io.StringIO()
    prob.driver.add_recorder(ProgressPrinter(stream=buf))
    prob.setup()
    prob.run_driver()
    lines = buf.getvalue().splitlines()
    assert len(lines) == prob.driver.iter_count and "mass" in lines[-1] and "1.0000 kg" in lines[-1]


class _FailsBeyond(om.ExplicitComponent):
    """f = 10 (x - 1)^2 + (y - 2)^2 with an analysis that fails (om.AnalysisError) for x > limit,
    like a beam whose Newton solve diverges for a too-flexible design."""

    def initialize(self):
        self.options.declare("limit", types=float, desc="x beyond which the analysis fails")

    def setup(self):
        self.add_input("x", 0.0)
        self.add_input("y", 0.0)
        self.add_output("f", 0.0)
        self.add_output("g", 0.0)
        self.declare_partials(["f", "g"], ["x", "y"])
        self.evaluations = []

    def compute(self, inputs, outputs):
        x, y = float(inputs["x"][0]), float(inputs["y"][0])
        self.evaluations.append(x)
        if x > self.options["limit"]:
            raise om.AnalysisError(f"no convergence at x = {x:.3g}")
        outputs["f"] = 10.0 * (x - 1.0) ** 2 + (y - 2.0) ** 2
        outputs["g"] = x + y

    def compute_partials(self, inputs, partials):
        x, y = float(inputs["x"][0]), float(inputs["y"][0])
        partials["f", "x"] = 20.0 * (x - 1.0)
        partials["f", "y"] = 2.0 * (y - 2.0)
        partials["g", "x"] = 1.0
        partials["g", "y"] = 1.0


def _failing_problem(limit, x0, tmp_path=None, **driver_options):
    prob = om.Problem(reports=False)
    comp = prob.model.add_subsystem("c", _FailsBeyond(limit=limit), promotes=["*"])
    prob.model.add_design_var("x", lower=-50.0, upper=50.0)
    prob.model.add_design_var("y", lower=-50.0, upper=50.0)
    prob.model.add_objective("f")
    prob.model.add_constraint("g", upper=10.0)
    prob.driver, _ = make_driver("SLSQP", disp=False)
    prob.driver.options.update(driver_options)
    if tmp_path is not None:
        from wingmdao.optimize import add_recorder

        add_recorder(prob, str(tmp_path / "run.sql"))
    prob.setup()
    prob.set_val("x", x0)
    prob.set_val("y", 0.0)
    return prob, comp


def test_scipy_slsqp_alone_ends_the_run_when_it_steps_into_a_failing_region():
    """The reason for BackoffSLSQPDriver: om.ScipyOptimizeDriver re-raises the AnalysisError."""
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("c", _FailsBeyond(limit=5.0), promotes=["*"])
    prob.model.add_design_var("x", lower=-50.0, upper=50.0)
    prob.model.add_design_var("y", lower=-50.0, upper=50.0)
    prob.model.add_objective("f")
    prob.driver = om.ScipyOptimizeDriver(optimizer="SLSQP", disp=False)
    prob.setup()
    prob.set_val("x", -1.0)
    with pytest.raises(om.AnalysisError, match="no convergence"):
        prob.run_driver()


def test_backoff_steps_back_from_a_failing_region_and_converges(tmp_path):
    """From x = -1 SLSQP's first step (identity Hessian: x - grad f = -1 + 40) lands at x = 39,
    where the analysis fails; the driver backs off and still finds the minimum (1, 2) (closed form),
    which lies inside the solvable region x <= 5."""
    prob, comp = _failing_problem(5.0, -1.0, tmp_path)
    prob.run_driver()
    assert max(comp.evaluations) > 5.0  # it did step into the failing region
    assert prob.driver.result.success
    np.testing.assert_allclose([prob.get_val("x")[0], prob.get_val("y")[0]], [1.0, 2.0], atol=1e-4)
    failed = prob.driver.failed_evaluations
    assert failed and all(f["design_vars"]["x"][0] > 5.0 and "no convergence" in f["message"] for f in failed)
    # failed evaluations are in the recording, marked success = 0 with the error
    cr = om.CaseReader(str(tmp_path / "run.sql"))
    cases = [cr.get_case(c) for c in cr.list_cases("driver", out_stream=None)]
    bad = [c for c in cases if not c.success]
    assert len(bad) == len(failed) and all("no convergence" in c.msg for c in bad)
    assert cases[-1].success  # the run ends on a solved design


def test_backoff_stops_cleanly_after_consecutive_failures():
    """Every design but the start fails: after max_failures shortened steps the run stops with
    success False, a message saying why, and the model at the start (the last solved design)."""
    prob, comp = _failing_problem(-0.99, -1.0, max_failures=4)
    prob.run_driver()
    assert not prob.driver.result.success
    assert "4 consecutive failed analyses" in prob.driver.stop_message
    res = prob.driver.optimize_result
    assert res.success is False and res.message == prob.driver.stop_message
    assert len(prob.driver.failed_evaluations) == 4
    assert prob.get_val("x")[0] == pytest.approx(-1.0)
    assert prob.get_val("f")[0] == pytest.approx(10.0 * 4.0 + 4.0)  # solved at the start, not stale


def test_failure_of_the_initial_design_is_raised():
    """There is nothing to back off to: the AnalysisError reaches the caller (the CLI prints it)."""
    prob, _ = _failing_problem(-5.0, -1.0)
    with pytest.raises(om.AnalysisError, match="no convergence"):
        prob.run_driver()
