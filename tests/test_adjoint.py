"""Discrete adjoint of the BDF march: against central differences and the tangent (forward) mode."""

import numpy as np
import pytest

from wingmdao.timemarch.adjoint import LinearizedHistory
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.examples import (SMD_TABLE_4_18, nonlinear_chain_system,
                                         potential_energy_integral, spring_mass_damper_system)

SMD_P = np.array([SMD_TABLE_4_18["mass"], SMD_TABLE_4_18["damping"], SMD_TABLE_4_18["stiffness"]])
T_SMD = np.linspace(0.0, SMD_TABLE_4_18["t_final"], 10001)


def _smd_f(p):
    sysm = spring_mass_damper_system()
    h = march(sysm, T_SMD, p, np.zeros((T_SMD.size, 1)), initial="state", x_init=[1.0, 0.0],
              modified_newton=True)
    return sysm, h, potential_energy_integral(h.states, T_SMD[1], p[2])


def test_smd_adjoint_matches_central_differences_and_tangent():
    """Table 4.18 case, f of Eq. 4.33: gradient w.r.t. m, c, k."""
    sysm, h, (f, dfdx, dfdk) = _smd_f(SMD_P)
    lin = LinearizedHistory(sysm, T_SMD, h.states, SMD_P, np.zeros((T_SMD.size, 1)), initial="state")
    dfdp, _, _ = lin.gradient(dfdx, dfdp=[0.0, 0.0, dfdk])
    fd = np.zeros(3)
    for j in range(3):
        step = np.zeros(3)
        step[j] = 1e-5 * SMD_P[j]
        fd[j] = (_smd_f(SMD_P + step)[2][0] - _smd_f(SMD_P - step)[2][0]) / (2 * step[j])
    np.testing.assert_allclose(dfdp, fd, rtol=1e-6)
    # Table 4.19 published finite difference of df/dk (their step size is unknown)
    assert dfdp[2] == pytest.approx(1.160819927186196, rel=2e-5)
    for j in range(3):
        direction = np.eye(3)[j]
        dx = lin.tangent(dp=direction)
        fwd = np.sum(dfdx * dx) + (dfdk if j == 2 else 0.0)
        assert fwd == pytest.approx(dfdp[j], rel=1e-10, abs=1e-12)


def _chain_case(n_time=41, initial="static"):
    sysm = nonlinear_chain_system(4)
    rng = np.random.default_rng(7)
    p = np.r_[1.3, 0.4, 0.8, rng.uniform(2.0, 4.0, 4)]
    t = np.linspace(0.0, 0.8, n_time)
    Q = np.outer(1.0 + np.sin(5 * t), rng.uniform(0.5, 1.5, 4))
    x_init = rng.normal(scale=0.2, size=8)
    return sysm, t, p, Q, x_init


def _chain_functional(h):
    # sum over time of displacements^2 and velocities (asymmetric weights)
    w = np.arange(1, h.states.shape[1] + 1, dtype=float)
    return float(np.sum(w * h.states**2)), 2 * w * h.states


@pytest.mark.parametrize("initial", ["static", "state"])
def test_nonlinear_chain_gradients_wrt_params_forcing_and_initial_state(initial):
    sysm, t, p, Q, x_init = _chain_case(initial=initial)
    run = lambda p_, Q_, x0_: march(sysm, t, p_, Q_, initial=initial, x_init=x0_, atol=1e-13,
                                      static_options={"atol": 1e-13})
    h = run(p, Q, x_init)
    f, dfdx = _chain_functional(h)
    lin = LinearizedHistory(sysm, t, h.states, p, Q, initial=initial)
    dfdp, dfdq, lam = lin.gradient(dfdx)
    eps = 1e-4  # f ~ 1e2: a larger step keeps the round-off of the difference below 1e-9
    scale = max(np.max(np.abs(dfdp)), np.max(np.abs(dfdq)))  # small entries: absolute 1e-7 of the largest
    for j in range(p.size):
        e = np.zeros(p.size)
        e[j] = eps
        fd = (_chain_functional(run(p + e, Q, x_init))[0] - _chain_functional(run(p - e, Q, x_init))[0]) / (2 * eps)
        assert dfdp[j] == pytest.approx(fd, rel=1e-6, abs=1e-7 * scale)
    for (n, j) in [(0, 1), (7, 2), (40, 3)]:
        e = np.zeros_like(Q)
        e[n, j] = eps
        fd = (_chain_functional(run(p, Q + e, x_init))[0] - _chain_functional(run(p, Q - e, x_init))[0]) / (2 * eps)
        assert dfdq[n, j] == pytest.approx(fd, rel=1e-6, abs=1e-7 * scale)
    if initial == "state":
        e = np.zeros(8)
        e[3] = eps
        fd = (_chain_functional(run(p, Q, x_init + e))[0] - _chain_functional(run(p, Q, x_init - e))[0]) / (2 * eps)
        assert lam[0, 3] == pytest.approx(fd, rel=1e-6)
    # forward mode agrees with reverse to round-off
    rng = np.random.default_rng(3)
    dp, dq = rng.normal(size=p.size), rng.normal(size=Q.shape)
    dx = lin.tangent(dp=dp, dq=dq)
    assert np.sum(dfdx * dx) == pytest.approx(dfdp @ dp + np.sum(dfdq * dq), rel=1e-10)


def test_sweeps_invert_the_stacked_jacobian_and_transposes_agree():
    sysm, t, p, Q, x_init = _chain_case(n_time=12)
    h = march(sysm, t, p, Q)
    for store in (True, False):
        lin = LinearizedHistory(sysm, t, h.states, p, Q, store_factors=store)
        rng = np.random.default_rng(5)
        a, b = rng.normal(size=h.states.shape), rng.normal(size=h.states.shape)
        np.testing.assert_allclose(lin.apply(lin.solve_tangent(a)), a, atol=1e-11)
        np.testing.assert_allclose(lin.apply_transpose(lin.solve_adjoint(a)), a, atol=1e-11)
        assert np.sum(lin.apply(a) * b) == pytest.approx(np.sum(a * lin.apply_transpose(b)), rel=1e-12)
    # dense check of J against central differences of the stacked residual
    dt = t[1] - t[0]
    from wingmdao.timemarch.bdf import state_rates

    def stacked(X):
        return sysm.residual_history(X, state_rates(X, dt), p, Q)

    direction = np.random.default_rng(9).normal(size=h.states.shape)
    fd = (stacked(h.states + 1e-6 * direction) - stacked(h.states - 1e-6 * direction)) / 2e-6
    np.testing.assert_allclose(lin.apply(direction), fd, rtol=1e-6, atol=1e-8)


def test_rate_dependent_functional_chains_through_bdf():
    """f = sum_n |xdot_n|^2 (kinetic-like): the dF/dxdot terms of Eq. 3.10."""
    sysm, t, p, Q, _ = _chain_case(n_time=15)
    from wingmdao.timemarch.bdf import state_rates
    dt = t[1] - t[0]

    def f_of(p_):
        h = march(sysm, t, p_, Q, atol=1e-13, static_options={"atol": 1e-13})
        r = state_rates(h.states, dt)
        return float(np.sum(r**2)), h, 2 * r

    f, h, dfdxdot = f_of(p)
    lin = LinearizedHistory(sysm, t, h.states, p, Q)
    dfdp, _, _ = lin.gradient(np.zeros_like(h.states), dfdxdot=dfdxdot)
    e = np.zeros(p.size)
    e[4] = 1e-4
    fd = (f_of(p + e)[0] - f_of(p - e)[0]) / 2e-4
    assert dfdp[4] == pytest.approx(fd, rel=1e-6)


@pytest.mark.parametrize("initial", ["static", "state"])
@pytest.mark.parametrize("k", [1, 3, 7, 40])
def test_checkpointed_history_equals_full_storage(initial, k):
    """checkpoint_every=k keeps only the states and re-evaluates the Jacobians segment by segment:
    gradients, tangents and every product equal the full storage's to round-off (1e-10)."""
    sysm, t, p, Q, x_init = _chain_case(initial=initial)
    h = march(sysm, t, p, Q, initial=initial, x_init=x_init)
    f, dfdx = _chain_functional(h)
    full = LinearizedHistory(sysm, t, h.states, p, Q, initial=initial)
    lean = LinearizedHistory(sysm, t, h.states, p, Q, initial=initial, checkpoint_every=k)
    assert lean.checkpoint_every == k and not hasattr(lean, "jp")    # no per-step blocks kept
    for a, b in zip(lean.gradient(dfdx), full.gradient(dfdx)):
        np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-10 * np.max(np.abs(b)))
    v = np.random.default_rng(2).normal(size=h.states.shape)
    for name in ("solve_tangent", "solve_adjoint", "apply", "apply_transpose", "param_product",
                 "forcing_product"):
        a, b = getattr(lean, name)(v), getattr(full, name)(v)
        np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-10 * np.max(np.abs(b)), err_msg=name)
    np.testing.assert_allclose(lean.param_apply(p), full.param_apply(p), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(lean.forcing_apply(Q), full.forcing_apply(Q), rtol=1e-12, atol=1e-12)


def test_checkpointed_history_with_static_lu_and_bad_interval(tmp_path, monkeypatch):
    from wingmdao.timemarch import static_lu
    from wingmdao.utils import casadi_cache as cc

    if cc.compiler() is None:
        pytest.skip("needs gcc")
    monkeypatch.setenv(static_lu.ENV_KERNEL, "1")      # the compiled static-pivot LU kernel
    monkeypatch.setenv(cc.ENV_CACHE, str(tmp_path))
    sysm, t, p, Q, _ = _chain_case(n_time=30)
    h = march(sysm, t, p, Q)
    f, dfdx = _chain_functional(h)
    ref = LinearizedHistory(sysm, t, h.states, p, Q).gradient(dfdx)
    lean = LinearizedHistory(sysm, t, h.states, p, Q, lu="static", checkpoint_every=4)
    for a, b in zip(lean.gradient(dfdx), ref):
        np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9 * np.max(np.abs(b)))
    assert lean.lu_method == "static"
    with pytest.raises(ValueError, match="checkpoint_every must be an integer >= 1"):
        LinearizedHistory(sysm, t, h.states, p, Q, checkpoint_every=0)


def test_reused_csc_factors_solve_each_step_against_dense():
    """The per-step factors from the reused CSC matrix (``_factor_step``) solve A_n x = b and
    A_n^T x = b to 1e-12 of a dense solve (chain of 50 states, above DENSE_MAX)."""
    m = 25                                  # 50 states: above DENSE_MAX, the SuperLU path
    sysm = nonlinear_chain_system(m)
    rng = np.random.default_rng(3)
    p = np.r_[1.3, 0.4, 0.8, rng.uniform(2.0, 4.0, m)]
    t = np.linspace(0.0, 0.8, 41)
    Q = np.outer(1.0 + np.sin(5 * t), rng.uniform(0.5, 1.5, m))
    X = march(sysm, t, p, Q).states
    lin = LinearizedHistory(sysm, t, X, p, Q)
    assert lin.n_state > 40
    for n in (1, 2, lin.n_time // 2, lin.n_time - 1):
        A = lin.newton_matrix(n).toarray()
        lu = lin._factor_step(n)
        b = rng.standard_normal(lin.n_state)
        for trans, M in (("N", A), ("T", A.T)):
            x = lu.solve(b, trans=trans)
            ref = np.linalg.solve(M, b)
            assert np.max(np.abs(x - ref)) <= 1e-12 * max(1.0, np.max(np.abs(ref)))
