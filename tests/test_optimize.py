"""Driver selection: falls back to SciPy SLSQP without pyoptsparse; bad names fail clearly."""

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
