"""Compiled BDF steps (wingmdao.timemarch.fast_step): same march as the Python path, own LU."""

import numpy as np
import openmdao.api as om
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.timemarch import fast_step as fs
from wingmdao.timemarch.bdf import _StepSolver, march
from wingmdao.timemarch.examples import nonlinear_chain_system
from wingmdao.utils import casadi_cache as cc

pytestmark = pytest.mark.skipif(cc.compiler() is None, reason="needs gcc")

N_MASS = 25


@pytest.fixture
def jit_env(tmp_path, monkeypatch):
    monkeypatch.setenv(cc.ENV_JIT, "1")
    monkeypatch.setenv(cc.ENV_CACHE, str(tmp_path / "cache"))
    monkeypatch.setattr(cc._warn_once, "issued", False)
    return tmp_path / "cache"


@pytest.fixture
def chain(jit_env):
    sysm = nonlinear_chain_system(N_MASS)
    assert set(sysm.compile(wait=True).values()) == {"compiled"}
    return sysm


def _case(amp, hardening, n_time=201):
    t = np.linspace(0.0, 1.0, n_time)
    p = np.concatenate([[1.0, 0.5, hardening], np.full(N_MASS, 200.0)])
    Q = np.zeros((t.size, N_MASS))
    Q[:, -1] = amp * np.sin(8.0 * t)
    return t, p, Q


@pytest.mark.parametrize("modified", [True, False])
def test_compiled_march_equals_python_march(chain, modified):
    # strongly nonlinear: modified Newton refactors within BDF2 steps (not only at alpha changes)
    t, p, Q = _case(300.0, 300.0)
    ref = march(chain, t, p, Q, modified_newton=modified, fast=False)
    new = march(chain, t, p, Q, modified_newton=modified, fast=True)
    assert new.info["compiled_steps"] and not ref.info["compiled_steps"]
    if modified:
        assert ref.factorizations > 10        # 2 would be the alpha changes only
    np.testing.assert_array_equal(new.iterations, ref.iterations)
    assert new.factorizations == ref.factorizations
    scale = np.abs(ref.states).max()
    assert scale > 5.0
    np.testing.assert_allclose(new.states, ref.states, rtol=0, atol=1e-10 * scale)
    np.testing.assert_allclose(new.rates, ref.rates, rtol=0, atol=1e-10 * np.abs(ref.rates).max())
    # the default (fast=None) uses the compiled steps for this 50-state system
    assert march(chain, t, p, Q, modified_newton=modified).info["compiled_steps"]


def test_callback_and_capacity_growth_in_march(chain, monkeypatch):
    """Step by step (a callback) and with factor buffers far too small at first: the same march."""
    t, p, Q = _case(300.0, 300.0, 61)
    ref = march(chain, t, p, Q, modified_newton=True, fast=False)
    monkeypatch.setattr(fs.FastStepper, "initial_capacity", chain.n_state)
    seen = []
    new = march(chain, t, p, Q, modified_newton=True, fast=True,
                callback=lambda n, tn, x: seen.append((n, tn, x.copy())))
    assert [s[0] for s in seen] == list(range(t.size))
    np.testing.assert_array_equal(np.array([s[2] for s in seen]), new.states)
    np.testing.assert_array_equal(new.iterations, ref.iterations)
    np.testing.assert_allclose(new.states, ref.states, rtol=0, atol=1e-10 * np.abs(ref.states).max())


def test_given_initial_state(chain):
    t, p, Q = _case(100.0, 100.0, 51)
    x0 = np.zeros(chain.n_state)
    x0[-2] = 0.3
    ref = march(chain, t, p, Q, initial="state", x_init=x0, modified_newton=True, fast=False)
    new = march(chain, t, p, Q, initial="state", x_init=x0, modified_newton=True, fast=True)
    np.testing.assert_allclose(new.states, ref.states, rtol=0, atol=1e-10 * np.abs(ref.states).max())


def test_no_convergence_reports_like_python_path(chain):
    t, p, Q = _case(300.0, 300.0, 21)
    msgs = []
    for fast in (False, True):
        with pytest.raises(om.AnalysisError, match="no convergence in 2 iterations") as err:
            march(chain, t, p, Q, max_iter=2, fast=fast)
        msgs.append(str(err.value))
    assert msgs[0] == msgs[1]
    assert "step 1 (t = 0.05 s)" in msgs[1] and "worst: mass" in msgs[1]


def test_nonfinite_residual_reported(chain):
    t, p, Q = _case(30.0, 40.0, 11)
    Q[5, 3] = np.nan
    with pytest.raises(om.AnalysisError, match=r"step 5 .*residual is not finite"):
        march(chain, t, p, Q, fast=True)


def test_factor_capacity_grows(chain):
    """Factors that do not fit the buffers: buffers doubled, the step redone from its start."""
    t, p, Q = _case(300.0, 300.0)
    x0 = march(chain, t[:1], p, Q[:1]).states[0]
    kw = dict(atol=0.0, xtol=1e-12, max_iter=25, modified=True, contraction=0.3)
    stepper = fs.FastStepper.create(chain, p, **kw)
    stepper._set_capacity(chain.n_state)          # far too small for L and U
    dt = t[1] - t[0]
    hist = -x0 / dt
    x_fast = x0.copy()
    status, it = stepper.solve(x_fast, hist, 1.0 / dt, Q[1].copy())
    assert status == fs.OK and stepper.s.cap_L > chain.n_state
    x_ref, it_ref = _StepSolver(chain, p, **kw).solve(x0.copy(), hist, 1.0 / dt, Q[1], lambda: "step 1")
    assert it == it_ref
    np.testing.assert_allclose(x_fast, x_ref, rtol=0, atol=1e-12 * np.abs(x_ref).max())


@pytest.mark.parametrize("column_order", [False, True])
def test_lu_against_scipy(chain, column_order):
    """The C LU on the Newton-matrix pattern with random values that need row pivoting,
    some entries exactly zero (skipped), against SuperLU's solve; in natural column order and
    in a random one (``P A Q = L U``, the system's ``lu_column_order``)."""
    kw = dict(atol=0.0, xtol=1e-12, max_iter=25, modified=True, contraction=0.3)
    stepper = fs.FastStepper.create(chain, np.ones(chain.n_param), **kw)
    n, rows, indptr = chain.n_state, stepper.Ai, stepper.Ap
    rng = np.random.default_rng(3)
    if column_order:
        stepper.qcol = np.ascontiguousarray(rng.permutation(n), dtype=np.int32)
        stepper.s.qcol = stepper.qcol.ctypes.data
    solved = 0
    for _trial in range(20):
        vals = rng.normal(size=rows.size)
        vals[rng.random(rows.size) < 0.1] = 0.0
        A = sp.csc_matrix((vals, rows, indptr), shape=(n, n))
        try:
            if abs(spla.splu(A.copy()).U.diagonal()).min() < 1e-8:
                continue
        except RuntimeError:   # singular draw
            continue
        solved += 1
        b = rng.normal(size=n)
        status, x = stepper.lu_test(vals, b)
        assert status == fs.OK
        ref = spla.spsolve(A, b)
        np.testing.assert_allclose(x, ref, rtol=1e-9, atol=1e-9 * np.abs(ref).max())
        np.testing.assert_allclose(A @ x, b, atol=1e-9 * (abs(A) @ abs(x) + abs(b)).max())
        assert np.any(stepper.pinv != np.arange(n))     # rows were exchanged
    assert solved >= 3
    # a structurally singular matrix (an empty column)
    vals = rng.normal(size=rows.size)
    vals[indptr[4]:indptr[5]] = 0.0
    status, _ = stepper.lu_test(vals, np.ones(n))
    assert status == fs.SINGULAR


def test_fast_true_needs_compiled_functions(monkeypatch):
    monkeypatch.setenv(cc.ENV_JIT, "0")
    sysm = nonlinear_chain_system(N_MASS)
    t, p, Q = _case(30.0, 40.0, 5)
    with pytest.raises(ValueError, match="fast=True"):
        march(sysm, t, p, Q, fast=True)
    assert not march(sysm, t, p, Q).info["compiled_steps"]    # default: the Python path


def test_time_history_component_uses_compiled_steps(chain, monkeypatch):
    """TimeHistoryComponent marches with the compiled steps by default; outputs and adjoint
    totals equal those of the Python steps (the adjoint only reads the states)."""
    from wingmdao.components.time_history import TimeHistoryComponent
    from wingmdao.timemarch.bdf import ENV_COMPILED_STEPS

    t, p, Q = _case(100.0, 100.0, 41)
    res = {}
    for env in ("1", "0"):
        monkeypatch.setenv(ENV_COMPILED_STEPS, env)
        prob = om.Problem(reports=False)
        prob.model.add_subsystem("chain", TimeHistoryComponent(system=chain, time=t, modified_newton=True),
                                 promotes=["*"])
        prob.model.add_subsystem("f", om.ExecComp("f = sum(states**2)", states={"shape": (t.size, N_MASS, 2)}),
                                 promotes=["*"])
        prob.setup(mode="rev")
        prob.set_val("mass", p[0])
        prob.set_val("damping", p[1])
        prob.set_val("hardening", p[2])
        prob.set_val("stiffness", p[3:])
        prob.set_val("force", Q)
        prob.run_model()
        assert prob.model.chain.last_history.info["compiled_steps"] == (env == "1")
        tot = prob.compute_totals(of=["f"], wrt=["stiffness", "hardening"])
        res[env] = (prob.get_val("states").copy(), tot)
    (s1, t1), (s0, t0) = res["1"], res["0"]
    np.testing.assert_allclose(s1, s0, rtol=0, atol=1e-10 * np.abs(s0).max())
    for key in t0:
        np.testing.assert_allclose(t1[key], t0[key], rtol=1e-9, atol=1e-12 * np.abs(t0[key]).max())


def test_compiled_march_with_a_column_order_equals_python_march(jit_env):
    """A system with a column order (as the beam and the aeroelastic systems have): the compiled
    march factors P A Q = L U and still follows the Python march (SuperLU) step by step."""
    base = nonlinear_chain_system(N_MASS)
    order = np.arange(base.n_state).reshape(-1, 2)[:, ::-1].ravel()     # v before u in every mass
    base._lu_column_order = order
    assert np.array_equal(base.lu_column_order(), order)
    assert set(base.compile(wait=True).values()) == {"compiled"}
    t, p, Q = _case(300.0, 300.0)
    ref = march(base, t, p, Q, fast=False)
    new = march(base, t, p, Q, fast=True)
    assert new.info["compiled_steps"]
    np.testing.assert_array_equal(new.iterations, ref.iterations)
    scale = np.abs(ref.states).max()
    np.testing.assert_allclose(new.states, ref.states, rtol=0, atol=1e-10 * scale)
