"""BDF time marching and static solves against closed forms."""

import casadi as ca
import numpy as np
import openmdao.api as om
import pytest

from wingmdao.timemarch.bdf import march, solve_static, state_rates, time_step
from wingmdao.timemarch.examples import (SMD_TABLE_4_18, nonlinear_chain_system,
                                         potential_energy_integral, spring_mass_damper_response,
                                         spring_mass_damper_system)
from wingmdao.timemarch.system import CasadiResidualSystem, VarSpec

SMD_P = [SMD_TABLE_4_18["mass"], SMD_TABLE_4_18["damping"], SMD_TABLE_4_18["stiffness"]]


def _smd_march(dt, t_final, **kw):
    t = np.linspace(0.0, t_final, int(round(t_final / dt)) + 1)
    h = march(spring_mass_damper_system(), t, SMD_P, np.zeros((t.size, 1)), initial="state",
              x_init=[1.0, 0.0], **kw)
    return t, h


def test_time_grid_validation():
    assert time_step([0.0]) == 0.0
    assert time_step(np.linspace(0, 1, 11)) == pytest.approx(0.1)
    with pytest.raises(ValueError, match=r"time\[0\] must be 0"):
        time_step([0.1, 0.2])
    with pytest.raises(ValueError, match="increasing"):
        time_step([0.0, 0.2, 0.1])
    with pytest.raises(ValueError, match="uniform.*step 2"):
        time_step([0.0, 0.1, 0.25, 0.3])
    with pytest.raises(ValueError, match="not finite"):
        time_step([0.0, np.nan])


def test_bdf2_converges_at_second_order_to_closed_form():
    """Error at t = 2 s halves twice per halving of dt -> observed order ~2."""
    errors = []
    dts = [0.02, 0.01, 0.005, 0.0025]
    for dt in dts:
        t, h = _smd_march(dt, 2.0)
        x_exact, v_exact = spring_mass_damper_response(t, *SMD_P)
        errors.append(np.max(np.abs(h.states[:, 0] - x_exact)))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(orders > 1.9) and np.all(orders < 2.1), orders
    assert errors[-1] < 2e-5


def test_table_4_19_functional_value():
    """Published f = 8.666966423590475 (Table 4.19): 10 s from x = 1 m, dt = 1 ms."""
    t, h = _smd_march(SMD_TABLE_4_18["dt"], SMD_TABLE_4_18["t_final"], modified_newton=True)
    f, _, _ = potential_energy_integral(h.states, 1e-3, SMD_P[2])
    assert f == pytest.approx(8.666966423590475, rel=1e-9)


def test_modified_newton_matches_full_newton_with_fewer_factorizations():
    sysm = nonlinear_chain_system(6)
    p = np.r_[1.0, 0.5, 2.0, np.linspace(3.0, 5.0, 6)]
    t = np.linspace(0.0, 1.0, 101)
    forcing = np.outer(np.sin(6 * t), np.linspace(1.0, 2.0, 6))
    full = march(sysm, t, p, forcing)
    mod = march(sysm, t, p, forcing, modified_newton=True)
    np.testing.assert_allclose(mod.states, full.states, atol=1e-9)
    assert mod.factorizations < full.factorizations / 3
    np.testing.assert_allclose(state_rates(full.states, 0.01), full.rates)


def test_static_solve_with_load_steps_matches_hand_solution():
    # cubic spring chain with 1 mass: k (u + g u^3) = F, k = 2, g = 0.5, F = 12 -> u = 2
    sysm = nonlinear_chain_system(1)
    p = [1.0, 0.1, 0.5, 2.0]
    for steps in (1, 4):
        x, info = solve_static(sysm, p, [12.0], load_steps=steps)
        assert x[0] == pytest.approx(2.0, rel=1e-12) and x[1] == 0.0
        assert info.converged


def test_static_solve_bisects_a_failing_load_step():
    # strongly nonlinear x^5 + x = F: from 0 at F = 1e4 Newton needs ~40 iterations, more
    # than allowed, so the load step is halved until the first increment converges
    x, xd = ca.SX.sym("x"), ca.SX.sym("xd")
    p, q = ca.SX.sym("p", 0), ca.SX.sym("q")
    sysm = CasadiResidualSystem(x, xd, p, q, x**5 + x - q, param_specs=[],
                                forcing_specs=[VarSpec("load", (), "N")])
    with pytest.raises(om.AnalysisError, match="load fraction 1"):
        solve_static(sysm, [], [1e4], load_steps=1, max_iter=20, max_halvings=0)
    sol, _ = solve_static(sysm, [], [1e4], load_steps=1, max_iter=20)
    assert sol[0] ** 5 + sol[0] == pytest.approx(1e4, rel=1e-10)


def test_failed_step_raises_analysis_error_with_step_time_and_equation():
    # an overdriven cubic chain with too few iterations must fail with a clear message
    sysm = nonlinear_chain_system(2)
    t = np.linspace(0.0, 0.2, 3)
    forcing = np.array([[0.0, 0.0], [0.0, 0.0], [1e9, 0.0]])
    with pytest.raises(om.AnalysisError, match=r"step 2 \(t = 0.2 s\).*max \|residual\| = \d\.\d{3}e[+-]\d+, worst: mass \d"):
        march(sysm, t, [1.0, 0.1, 1.0, 1.0, 1.0], forcing, max_iter=3)


def test_progress_callback_and_single_instant():
    seen = []
    sysm = nonlinear_chain_system(1)
    h = march(sysm, [0.0], [1.0, 0.1, 0.5, 2.0], [[12.0]], callback=lambda n, t, x: seen.append(n))
    assert seen == [0] and h.states[0, 0] == pytest.approx(2.0)


def test_static_load_stepping_of_named_forcing_only():
    sysm = nonlinear_chain_system(2)
    p = [1.0, 0.1, 0.5, 2.0, 3.0]
    x_all, _ = solve_static(sysm, p, [2.0, 10.0], load_steps=3)
    x_named, _ = solve_static(sysm, p, [2.0, 10.0], load_steps=3, scaled=["force"])
    np.testing.assert_allclose(x_named, x_all, rtol=1e-12)
    with pytest.raises(ValueError, match="unknown forcing.*gust"):
        solve_static(sysm, p, [2.0, 10.0], scaled=["gust"])
    with pytest.raises(ValueError, match="load_steps"):
        solve_static(sysm, p, [2.0, 10.0], load_steps=0)
