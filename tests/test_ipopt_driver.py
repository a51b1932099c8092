"""IpoptDriver (IPOPT through cyipopt, no pyoptsparse): constrained paraboloids against SciPy
SLSQP on the same functions, design-variable scaling, back-off from failed analyses, recording,
make_driver's choice, and the PEGASUS maneuver sizing against SLSQP."""

import subprocess
import sys

import numpy as np
import openmdao.api as om
import pytest
from scipy.optimize import minimize

pytest.importorskip("cyipopt")

from wingmdao.drivers.ipopt import IpoptDriver  # noqa: E402
from wingmdao.optimize import ProgressPrinter, make_driver, pyoptsparse_available  # noqa: E402


def f_parab(x, y):
    return (x - 3.0) ** 2 + x * y + (y + 4.0) ** 2 - 3.0


def _slsqp(constraints, x0=(1.0, 1.0), bounds=((-50, 50), (-50, 50))):
    """The optimum computed independently: SciPy SLSQP on the functions written out here."""
    res = minimize(lambda v: f_parab(*v), x0, method="SLSQP", bounds=bounds, constraints=constraints,
                   options={"ftol": 1e-10, "maxiter": 500})
    assert res.success, res.message
    return res.x


def _paraboloid(*, dv_scaling=None, obj_scaler=1.0, eq=False, x0=(1.0, 1.0), driver=None):
    """Paraboloid f(x, y); linear constraint 0 <= x + y <= 10; nonlinear x^2 + y^2 <= 20 (or, with
    ``eq``, the equality x^2 + y = 3)."""
    prob = om.Problem(reports=False)
    m = prob.model
    m.add_subsystem("parab", om.ExecComp("f = (x-3.0)**2 + x*y + (y+4.0)**2 - 3.0"), promotes=["*"])
    m.add_subsystem("lin", om.ExecComp("s = x + y"), promotes=["*"])
    m.add_subsystem("circ", om.ExecComp("r2 = x**2 + y**2"), promotes=["*"])
    m.add_subsystem("curve", om.ExecComp("q = x**2 + y"), promotes=["*"])
    dv_scaling = dv_scaling or {}
    m.add_design_var("x", lower=-50, upper=50, **dv_scaling.get("x", {}))
    m.add_design_var("y", lower=-50, upper=50, **dv_scaling.get("y", {}))
    m.add_objective("f", scaler=obj_scaler)
    if eq:
        m.add_constraint("q", equals=3.0, ref=10.0)
    else:
        m.add_constraint("s", lower=0.0, upper=10.0, linear=True)
        m.add_constraint("r2", upper=20.0, ref=20.0)
    prob.driver = driver or IpoptDriver(disp=False, tol=1e-9)
    prob.setup()
    prob.set_val("x", x0[0])
    prob.set_val("y", x0[1])
    return prob


LIN_NL = [{"type": "ineq", "fun": lambda v: v[0] + v[1]},
          {"type": "ineq", "fun": lambda v: 10.0 - v[0] - v[1]},
          {"type": "ineq", "fun": lambda v: 20.0 - v[0] ** 2 - v[1] ** 2}]


def _xy(prob):
    return np.array([prob.get_val("x")[0], prob.get_val("y")[0]])


def test_linear_and_nonlinear_constraints_reach_the_slsqp_optimum():
    ref = _slsqp(LIN_NL)
    prob = _paraboloid()
    result = prob.run_driver()
    assert result.success
    np.testing.assert_allclose(_xy(prob), ref, atol=1e-5)
    assert prob.get_val("f")[0] == pytest.approx(f_parab(*ref), abs=1e-6)
    # both constraints are active at this optimum: the test exercises them
    assert prob.get_val("s")[0] == pytest.approx(0.0, abs=1e-6)
    assert prob.get_val("r2")[0] == pytest.approx(20.0, abs=1e-5)
    res = prob.driver.optimize_result
    assert res.success and res.status == 0 and res.nit > 0 and "success" in res.message.lower()
    assert prob.driver.result.exit_status == res.message
    assert prob.driver.result.model_evals >= res.nit and prob.driver.result.deriv_evals >= res.nit


def test_equality_constraint():
    ref = _slsqp([{"type": "eq", "fun": lambda v: v[0] ** 2 + v[1] - 3.0}])
    prob = _paraboloid(eq=True)
    assert prob.run_driver().success
    np.testing.assert_allclose(_xy(prob), ref, atol=1e-5)
    assert prob.get_val("q")[0] == pytest.approx(3.0, abs=1e-7)


def test_design_variable_and_objective_scaling_give_the_same_optimum():
    ref = _slsqp(LIN_NL)
    prob = _paraboloid(dv_scaling={"x": {"ref": 20.0, "ref0": -5.0}, "y": {"ref": -3.0, "ref0": 7.0}},
                       obj_scaler=0.01)
    assert prob.run_driver().success
    np.testing.assert_allclose(_xy(prob), ref, atol=1e-5)
    # IPOPT saw scaled values: its x is the driver-scaled design
    x_scaled = prob.driver.optimize_result.x
    np.testing.assert_allclose(x_scaled, [(ref[0] + 5.0) / 25.0, (ref[1] - 7.0) / -10.0], atol=1e-5)


def test_jacobian_structure_linear_exact_nonlinear_relevant_blocks():
    """Linear rows: the nonzeros of the constant Jacobian; nonlinear rows: dense over the design
    variables the constraint depends on (none dropped for being zero at the start)."""
    prob = om.Problem(reports=False)
    m = prob.model
    m.add_subsystem("obj", om.ExecComp("f = x**2 + y**2 + z**2"), promotes=["*"])
    m.add_subsystem("gx", om.ExecComp("g = x**3"), promotes=["*"])  # zero derivative at x = 0
    m.add_subsystem("ly", om.ExecComp("h = 2*y"), promotes=["*"])
    for v in "xyz":
        m.add_design_var(v, lower=-1, upper=1)
    m.add_objective("f")
    m.add_constraint("g", upper=0.5)
    m.add_constraint("h", lower=-1.0, linear=True)
    prob.driver = IpoptDriver(disp=False)
    prob.setup()
    prob.set_val("x", 0.0)
    prob.set_val("y", 0.3)
    prob.set_val("z", 0.2)
    assert prob.run_driver().success
    rows, cols = prob.driver._structure
    assert sorted(zip(rows.tolist(), cols.tolist())) == [(0, 0), (1, 1)]


def test_opt_settings_are_passed_verbatim_and_failure_is_reported():
    prob = _paraboloid()
    prob.driver.opt_settings["max_iter"] = 2
    result = prob.run_driver()
    assert not result.success and prob.driver.fail
    res = prob.driver.optimize_result
    assert res.status == -1 and "maximum number of iterations" in res.message.lower() and res.nit == 2


class _FailingParaboloid(om.ExplicitComponent):
    """The paraboloid whose analysis fails (om.AnalysisError) for x > 7; the unconstrained
    optimum (20/3, -22/3) is just short of that region, so IPOPT's steps overshoot into it."""

    def setup(self):
        self.add_input("x")
        self.add_input("y")
        self.add_output("f")
        self.declare_partials("f", ["x", "y"])

    def compute(self, inputs, outputs):
        x, y = inputs["x"][0], inputs["y"][0]
        if x > 7.0:
            raise om.AnalysisError(f"no solution at x = {x}")
        outputs["f"] = f_parab(x, y)

    def compute_partials(self, inputs, J):
        x, y = inputs["x"][0], inputs["y"][0]
        J["f", "x"] = 2 * (x - 3.0) + y
        J["f", "y"] = x + 2 * (y + 4.0)


def _failing_problem(x0, path=None):
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("p", _FailingParaboloid(), promotes=["*"])
    prob.model.add_design_var("x", lower=-50, upper=50)
    prob.model.add_design_var("y", lower=-50, upper=50)
    prob.model.add_objective("f")
    prob.driver = IpoptDriver(disp=False)
    if path:
        prob.driver.add_recorder(om.SqliteRecorder(path))
    prob.setup()
    prob.set_val("x", x0[0])
    prob.set_val("y", x0[1])
    return prob


def test_analysis_error_makes_ipopt_back_off_and_converge(tmp_path):
    path = str(tmp_path / "fail.sql")
    prob = _failing_problem((-40.0, 40.0), path)
    assert prob.run_driver().success
    np.testing.assert_allclose(_xy(prob), [20 / 3, -22 / 3], atol=1e-6)
    failed = prob.driver.failed_evaluations
    assert failed and all(f["design_vars"]["x"][0] > 7.0 for f in failed)
    assert "no solution" in failed[0]["message"]
    prob.cleanup()
    cases = om.CaseReader(path).list_cases("driver", out_stream=None)
    reader = om.CaseReader(path)
    flags = [reader.get_case(c).success for c in cases]
    assert flags.count(0) == len(failed) and flags[-1] == 1


def test_analysis_error_at_the_initial_design_is_raised():
    prob = _failing_problem((8.0, 0.0))
    with pytest.raises(om.AnalysisError, match="no solution"):
        prob.run_driver()


def test_every_evaluation_is_recorded_and_progress_printed(tmp_path):
    import io

    path = str(tmp_path / "run.sql")
    stream = io.StringIO()
    prob = _paraboloid()
    prob.driver.add_recorder(om.SqliteRecorder(path))
    prob.driver.add_recorder(ProgressPrinter(stream=stream, objective="f", units=""))
    prob.driver.recording_options["record_derivatives"] = True
    prob.run_driver()
    evals = prob.driver.iter_count  # every model evaluation the driver made
    prob.cleanup()
    cases = om.CaseReader(path).list_cases("driver", out_stream=None)
    assert len(cases) == evals > prob.driver.optimize_result.nit
    assert len(stream.getvalue().splitlines()) == evals
    # the last recorded case is the optimum
    last = om.CaseReader(path).get_case(cases[-1])
    assert last.get_val("x")[0] == pytest.approx(prob.get_val("x")[0])


def test_make_driver_ipopt_is_the_cyipopt_driver_here():
    driver, desc = make_driver("IPOPT", maxiter=33, tol=1e-5, disp=False)
    if pyoptsparse_available():
        assert isinstance(driver, om.pyOptSparseDriver)
    else:
        assert isinstance(driver, IpoptDriver) and desc == "IpoptDriver/IPOPT (cyipopt)"
        assert driver.options["max_iter"] == 33 and driver.options["tol"] == 1e-5
        assert not driver.options["disp"]


def test_without_cyipopt_wingmdao_imports_and_make_driver_names_the_extra():
    code = (
        "import sys; sys.modules['cyipopt'] = None\n"
        "import wingmdao, wingmdao.optimize, wingmdao.sizing, wingmdao.drivers.ipopt\n"
        "from wingmdao.optimize import make_driver, pyoptsparse_available\n"
        "assert not wingmdao.drivers.ipopt.cyipopt_available()\n"
        "if not pyoptsparse_available():\n"
        "    try:\n"
        "        make_driver('IPOPT')\n"
        "    except ValueError as exc:\n"
        "        assert 'wingmdao[ipopt]' in str(exc), exc\n"
        "    else:\n"
        "        raise AssertionError('no ValueError')\n"
        "print('ok')\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr
