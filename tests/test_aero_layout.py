"""State layout of the aeroelastic system (wingmdao.aero.system.state_layout) and its
structural-only limit: at vanishing air density the coupled march and its adjoint totals are
those of the structural beam (BeamDynamics' system), read through the layout's beam indices."""

import numpy as np
import pytest

from wingmdao.aero.system import (N_AEROELASTIC_STATES, aero_parameters, build_aeroelastic_system,
                                  cached_aeroelastic_system, describe_aeroelastic_equation, state_layout)
from wingmdao.beam.residual import build_beam_system
from wingmdao.beam.static import beam_parameters, straight_beam
from wingmdao.timemarch.adjoint import LinearizedHistory
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import layout, pack


@pytest.mark.parametrize("plunge,trim", [(False, False), (True, False), (False, True), (True, True)])
def test_layout_matches_system(plunge, trim):
    n = 4
    lay = state_layout(n, plunge, trim)
    system = cached_aeroelastic_system(n, plunge=plunge, trim=trim)
    np.testing.assert_array_equal(system.layout.beam, lay.beam)
    np.testing.assert_array_equal(system.layout.aero, lay.aero)
    assert system.layout.body == lay.body and system.layout.size == lay.size
    assert lay.size == system.n_state == N_AEROELASTIC_STATES * n + plunge + trim
    # every state exactly once
    every = np.concatenate([lay.beam.ravel(), lay.aero.ravel(), list(lay.body.values())])
    np.testing.assert_array_equal(np.sort(every), np.arange(lay.size))
    # equation names at the layout's positions (rows ordered as the states)
    for i in range(n):
        assert "aerodynamic" in describe_aeroelastic_equation(int(lay.aero[i, 0]), n, plunge)
        assert "aerodynamic" not in describe_aeroelastic_equation(int(lay.beam[i, 0]), n, plunge)
    if plunge:
        assert "plunge" in describe_aeroelastic_equation(lay.body["plunge"], n, plunge)
    if trim:
        assert system.trim_index == lay.body["trim"]
        assert "trim" in describe_aeroelastic_equation(lay.body["trim"], n, plunge)
    # beam_states / aero_states of flat and (n, 22)-shaped histories
    X = np.arange(3 * lay.size, dtype=float).reshape(3, lay.size)
    np.testing.assert_array_equal(lay.beam_states(X)[:, 1, 9], X[:, 22 + 9])
    np.testing.assert_array_equal(lay.aero_states(X)[:, 2, 0], X[:, 2 * 22 + 18])
    if not (plunge or trim):
        np.testing.assert_array_equal(lay.beam_states(X.reshape(3, n, 22)), lay.beam_states(X))
    assert lay.mask("aero").sum() == 4 * n and lay.mask("beam").sum() == 18 * n


def _histories(n=6, nt=40, dt=5e-3):
    r0, th0 = straight_beam(n, 6.0)
    bp = beam_parameters(r0, th0, EI_cc=2e5, GJ=1.6e5, EI_nn=1e6, EA=1e8, mass_per_length=8.0,
                         inertia_per_length=np.diag([0.05, 0.1, 0.05]), shear_center=(0.02, 0.0),
                         mass_center=(0.03, 0.01))
    t = np.arange(nt) * dt
    beam = build_beam_system(n)
    aero = build_aeroelastic_system(n)
    tip = np.zeros((nt, n, 3))
    tip[:, -1] = np.array([20.0, 50.0, 300.0]) * np.sin(np.pi * np.clip(t / 0.1, 0, 1))[:, None] ** 2
    out = {}
    for key, system, extra in (("beam", beam, {}),
                               ("aero", aero, aero_parameters(n, chord=0.5, airspeed=40.0, density=1e-12))):
        p = pack(system.param_specs, {**bp, **extra})
        ql = layout(system.forcing_specs)
        Q = np.zeros((nt, system.n_forcing))
        Q[:, ql["point_force"]] = tip.reshape(nt, -1)
        Q[:, ql["gravity"].start + 2] = -9.81
        X = march(system, t, p, Q, modified_newton=True).states
        out[key] = (system, t, p, Q, X)
    return out


def test_structural_limit_history_and_totals():
    """Coupled system at density 1e-12 kg/m^3 against the structural beam: same beam histories
    and the same adjoint totals of sum_n M_x,root(t_n)^2 w.r.t. every beam parameter."""
    h = _histories()
    sb, t, pb, Qb, Xb = h["beam"]
    sa, _, pa, Qa, Xa = h["aero"]
    n = sa.num_nodes
    beam_a = sa.layout.beam_states(Xa)
    Xb3 = Xb.reshape(t.size, n, 18)
    scale = np.max(np.abs(Xb3), axis=(0, 1))
    assert np.max(np.abs(Xb3[:, -1, 2] - Xb3[0, -1, 2])) > 1e-3   # the tip moves
    np.testing.assert_allclose(beam_a, Xb3, rtol=0, atol=1e-9 * max(scale.max(), 1.0))
    assert np.max(np.abs(sa.layout.aero_states(Xa))) > 1e-3   # the lag states follow the motion (their loads ~ rho)

    grads = {}
    for key, system, p, Q, X, i_mx in (("beam", sb, pb, Qb, Xb, 9), ("aero", sa, pa, Qa, Xa, int(sa.layout.beam[0, 9]))):
        lin = LinearizedHistory(system, t, X, p, Q)
        dfdx = np.zeros_like(X)
        dfdx[:, i_mx] = 2.0 * X[:, i_mx]
        grads[key] = lin.gradient(dfdx)[0]
    nb = sb.n_param
    assert np.max(np.abs(grads["beam"])) > 0
    np.testing.assert_allclose(grads["aero"][:nb], grads["beam"], rtol=0, atol=1e-7 * np.max(np.abs(grads["beam"])))


def test_jacobian_history_per_jacobian_equals_fused():
    """The aeroelastic system's jacobian_history (the base class': one Jacobian at a time over the
    history) gives the fused four-output function's values, on a trimmed free-plunge system."""

    n, nt = 4, 5
    system = build_aeroelastic_system(n, plunge=True, trim=True)
    rng = np.random.default_rng(3)
    X = system.initial_guess(np.zeros(system.n_param), None) + 0.01 * rng.normal(size=(nt, system.n_state))
    Xd = rng.normal(size=(nt, system.n_state))
    p = rng.uniform(0.5, 1.5, size=system.n_param)
    Q = rng.normal(size=(nt, system.n_forcing))
    mine = system.jacobian_history(X, Xd, p, Q)
    fused = dict(zip(("x", "xdot", "p", "q"), system._history("J", system._all_jac, X, Xd, p, Q)))
    assert set(mine) == set(fused) == {"x", "xdot", "p", "q"}
    for key in fused:
        assert mine[key].shape == (nt, system.jacobian_patterns()[key][0].size)
        np.testing.assert_allclose(mine[key], fused[key], rtol=1e-14, atol=1e-14)
        assert np.any(mine[key] != 0)


def test_compiled_jacobian_history_matches_interpreted(tmp_path, monkeypatch):
    """compile() compiles the residual, Newton and the history functions; the compiled
    jacobian_history equals the interpreted one (3-node clamped system, private cache)."""
    import wingmdao.utils.casadi_cache as cc

    monkeypatch.setenv(cc.ENV_CACHE, str(tmp_path / "cache"))
    if cc.compiler() is None:
        pytest.skip("no C compiler")
    n, nt = 3, 4
    interp, comp = build_aeroelastic_system(n), build_aeroelastic_system(n)
    rng = np.random.default_rng(5)
    X = interp.initial_guess(np.zeros(interp.n_param), None) + 0.01 * rng.normal(size=(nt, interp.n_state))
    Xd, Q = rng.normal(size=(nt, interp.n_state)), rng.normal(size=(nt, interp.n_forcing))
    p = rng.uniform(0.5, 1.5, size=interp.n_param)
    monkeypatch.setenv(cc.ENV_JIT, "0")
    a = interp.jacobian_history(X, Xd, p, Q)
    monkeypatch.setenv(cc.ENV_JIT, "1")
    states = comp.compile(wait=True)
    from wingmdao.timemarch.system import HISTORY_PARTS

    assert set(states) == {"residual", "newton", *(f"history_{k}" for k in HISTORY_PARTS)}
    assert set(states.values()) == {"compiled"}
    b = comp.jacobian_history(X, Xd, p, Q)
    for key in a:
        np.testing.assert_allclose(b[key], a[key], rtol=1e-12, atol=1e-12)
