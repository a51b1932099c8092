"""Jacobian histories one function at a time, the compiled history loop and the reverse-mode
products ``lam^T dR/dp``, ``lam^T dR/dq`` of the adjoint (``CasadiResidualSystem.jacobian_history``,
``input_vjp_history``; ``LinearizedHistory.param_product`` / ``forcing_product``).

References are independent of the new code: the per-instant sparse Jacobians of
``jac_state`` / ``jac_inputs`` (CasADi ``jacobian`` evaluated one instant at a time into SciPy
matrices), and products with the stored dR/dp, dR/dq. The suite runs interpreted
(tests/conftest.py); ``compiled_beam`` compiles a 3-node beam into a temporary cache with the C
kernel forced on, so the C loop over the instants is exercised.
"""

import numpy as np
import pytest

from wingmdao.beam.residual import build_beam_system
from wingmdao.beam.static import beam_forcing, beam_parameters, straight_beam
from wingmdao.timemarch import static_lu
from wingmdao.timemarch.adjoint import LinearizedHistory
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.examples import nonlinear_chain_system
from wingmdao.timemarch.system import HISTORY_PARTS, pack
from wingmdao.utils import casadi_cache as cc


def _beam_case(system, n_time=5, seed=2):
    n = system.state_shape[0]
    r0, th0 = straight_beam(n, 2.0)
    p = pack(system.param_specs, beam_parameters(r0, th0, EI_cc=5e4, GJ=4e4, EI_nn=2e5, EA=1e7, GK_c=1e7,
                                                  GK_n=1e7, mass_per_length=3.0,
                                                  inertia_per_length=np.diag([0.01, 0.02, 0.01])))
    rng = np.random.default_rng(seed)
    X, Xd = rng.normal(size=(n_time, system.n_state)), rng.normal(size=(n_time, system.n_state))
    Q = np.tile(pack(system.forcing_specs, beam_forcing(n, point_force=[1.0, 2.0, 3.0])), (n_time, 1))
    Q = Q + 0.1 * rng.normal(size=Q.shape)
    return X, Xd, p, Q, rng.normal(size=X.shape)


def _reference(system, X, Xd, p, Q, L):
    """Per-instant SciPy Jacobians: their nonzeros in pattern order and the products with L."""
    pats = system.jacobian_patterns()
    nz = {k: [] for k in pats}
    gp, gq = np.zeros(system.n_param), np.zeros((X.shape[0], system.n_forcing))
    for i in range(X.shape[0]):
        jx, jxd = system.jac_state(X[i], Xd[i], p, Q[i])
        jp, jq = system.jac_inputs(X[i], Xd[i], p, Q[i])
        for k, m in (("x", jx), ("xdot", jxd), ("p", jp), ("q", jq)):
            nz[k].append(np.asarray(m.tocsr()[pats[k][0], pats[k][1]]).ravel())
        gp += jp.T @ L[i]
        gq[i] = jq.T @ L[i]
    return {k: np.array(v) for k, v in nz.items()}, gp, gq


def _assert_history_matches(system, X, Xd, p, Q, L, rtol):
    ref, gp, gq = _reference(system, X, Xd, p, Q, L)
    hist = system.jacobian_history(X, Xd, p, Q)
    assert set(hist) == {"x", "xdot", "p", "q"}
    for k in hist:
        np.testing.assert_allclose(hist[k], ref[k], rtol=rtol, atol=rtol * np.max(np.abs(ref[k])), err_msg=k)
    for k, v in system.state_jacobian_history(X, Xd, p, Q).items():
        np.testing.assert_array_equal(v, hist[k])
    for k, v in system.input_jacobian_history(X, Xd, p, Q).items():
        np.testing.assert_array_equal(v, hist[k])
    vp, vq = system.input_vjp_history(X, Xd, p, Q, L)
    assert vp.shape == (system.n_param,) and vq.shape == (X.shape[0], system.n_forcing)
    np.testing.assert_allclose(vp, gp, rtol=1e-12, atol=1e-12 * np.max(np.abs(gp)))
    np.testing.assert_allclose(vq, gq, rtol=1e-12, atol=1e-12 * np.max(np.abs(gq)))


def test_split_history_and_reverse_products_equal_per_instant_jacobians():
    system = build_beam_system(3, defer=False)
    _assert_history_matches(system, *_beam_case(system), rtol=1e-14)


def test_fused_and_split_histories_agree():
    """The four-output function of one instant (kept for callers of ``_all_jac``) gives the same
    nonzeros as the four functions over the history."""
    system = build_beam_system(3, defer=False)
    X, Xd, p, Q, _ = _beam_case(system)
    fused = system._history("J", system._all_jac, X, Xd, p, Q)
    split = system.jacobian_history(X, Xd, p, Q)
    for k, v in zip(("x", "xdot", "p", "q"), fused):
        np.testing.assert_array_equal(split[k], v)


@pytest.fixture
def compiled_beam(tmp_path, monkeypatch):
    if cc.compiler() is None:
        pytest.skip("needs gcc")
    monkeypatch.setenv(cc.ENV_JIT, "1")
    monkeypatch.setenv(static_lu.ENV_KERNEL, "1")
    monkeypatch.setenv(cc.ENV_CACHE, str(tmp_path / "cache"))
    monkeypatch.setattr(cc._warn_once, "issued", False)
    system = build_beam_system(3, defer=False)
    states = system.compile(wait=True)
    assert states == {"residual": "compiled", "newton": "compiled",
                      **{f"history_{k}": "compiled" for k in HISTORY_PARTS}}
    return system


def test_compiled_history_loop_equals_the_per_instant_jacobians(compiled_beam):
    """Compiled parts evaluated by the kernel's C loop (outputs written into the history rows)."""
    system = compiled_beam
    args = _beam_case(system, n_time=6)
    _assert_history_matches(system, *args, rtol=1e-13)
    for k in HISTORY_PARTS:
        call = system._part_call(k)
        assert call.jit.state == "compiled"
        assert call._history_entry[1] is not None, k      # the C loop was used
    # no instants: empty arrays, no call into C
    empty = system.jacobian_history(*(a[:0] for a in args[:2]), args[2], args[3][:0])
    assert all(v.shape[0] == 0 for v in empty.values())


def _chain_history(initial):
    sysm = nonlinear_chain_system(4)
    rng = np.random.default_rng(7)
    p = np.r_[1.3, 0.4, 0.8, rng.uniform(2.0, 4.0, 4)]
    t = np.linspace(0.0, 0.8, 31)
    Q = np.outer(1.0 + np.sin(5 * t), rng.uniform(0.5, 1.5, 4))
    x_init = rng.normal(scale=0.2, size=8)
    h = march(sysm, t, p, Q, initial=initial, x_init=x_init)
    return sysm, t, h.states, p, Q


@pytest.mark.parametrize("initial", ["static", "state"])
def test_adjoint_products_without_stored_input_jacobians(initial):
    """The gradient evaluates no dR/dp, dR/dq (reverse-mode products); the products equal those
    with the stored Jacobians (evaluated at first use by ``jp`` / the forward products)."""
    sysm, t, X, p, Q = _chain_history(initial)
    lam = np.random.default_rng(3).normal(size=X.shape)
    lin = LinearizedHistory(sysm, t, X, p, Q, initial=initial)
    dfdp, dfdq, _ = lin.gradient(lam)
    assert lin._jp is None and lin._jq is None          # never formed
    gp, gq = lin.param_product(lam), lin.forcing_product(lam)
    ref = LinearizedHistory(sysm, t, X, p, Q, initial=initial)
    assert ref.jp.shape == (t.size, sysm.jacobian_patterns()["p"][0].size)   # stored from here on
    rp, rq = ref.param_product(lam), ref.forcing_product(lam)
    np.testing.assert_allclose(gp, rp, rtol=1e-12, atol=1e-12 * np.max(np.abs(rp)))
    np.testing.assert_allclose(gq, rq, rtol=1e-12, atol=1e-12 * np.max(np.abs(rq)))
    if initial == "state":
        assert np.all(gq[0] == 0.0)                       # step 0 is x_0 - x_init: no forcing
    rdp, rdq, _ = ref.gradient(lam)
    np.testing.assert_allclose(dfdp, rdp, rtol=1e-12, atol=1e-12 * np.max(np.abs(rdp)))
    np.testing.assert_allclose(dfdq, rdq, rtol=1e-12, atol=1e-12 * np.max(np.abs(rdq)))
    # forward products need dR/dp: evaluated then, equal to the reference
    dp = np.random.default_rng(4).normal(size=p.size)
    np.testing.assert_allclose(lin.param_apply(dp), ref.param_apply(dp), rtol=1e-13, atol=1e-13)
    assert lin._jp is not None


@pytest.mark.parametrize("checkpoint_every", [None, 4])
def test_gradient_never_evaluates_input_jacobians(checkpoint_every, monkeypatch):
    """Full storage and checkpointed segments: the adjoint gradient uses only the reverse-mode
    products (dR/dp, dR/dq evaluation made to fail) and equals the stored-Jacobian gradient."""
    sysm, t, X, p, Q = _chain_history("state")
    g = np.random.default_rng(5).normal(size=X.shape)
    ref = LinearizedHistory(sysm, t, X, p, Q, initial="state")
    ref.jp  # noqa: B018                                                # stored products from here on
    expected = ref.gradient(g)

    def fail(*args):
        raise AssertionError("dR/dp, dR/dq evaluated")

    monkeypatch.setattr(sysm, "input_jacobian_history", fail)
    monkeypatch.setattr(sysm, "jacobian_history", fail)
    lin = LinearizedHistory(sysm, t, X, p, Q, initial="state", checkpoint_every=checkpoint_every)
    for a, b in zip(lin.gradient(g), expected):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.max(np.abs(b)))
