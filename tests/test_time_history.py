"""TimeHistoryComponent: partials, totals in fwd/rev mode, static solve, input checks."""

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.components.time_history import TimeHistoryComponent
from wingmdao.timemarch.examples import (nonlinear_chain_system, spring_mass_damper_response,
                                         spring_mass_damper_system)


def _smd_problem(t, initial="state", matrix_free=False, mode="rev"):
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("smd", TimeHistoryComponent(system=spring_mass_damper_system(), time=t,
                                                         initial=initial, matrix_free=matrix_free),
                             promotes=["*"])
    prob.setup(mode=mode, force_alloc_complex=False)
    prob.set_val("mass", 2.5)
    prob.set_val("damping", 0.2)
    prob.set_val("stiffness", 5.0)
    if initial == "state":
        prob.set_val("initial_state", [1.0, 0.0])
    return prob


def _chain_problem(n_time, initial="static", matrix_free=False, mode="rev", seed=0, set_force=True, **opts):
    rng = np.random.default_rng(seed)
    sysm = nonlinear_chain_system(3)
    t = np.linspace(0.0, 0.3, n_time)
    prob = om.Problem(reports=False)
    model = prob.model
    model.add_subsystem("chain", TimeHistoryComponent(system=sysm, time=t, initial=initial,
                                                      matrix_free=matrix_free, **opts), promotes=["*"])
    w = rng.uniform(0.5, 2.0, (n_time, 3, 2))
    model.add_subsystem("energy", om.ExecComp("f = sum(w * states**2)", w={"val": w, "shape": w.shape},
                                              states={"shape": (n_time, 3, 2)}), promotes=["*"])
    prob.setup(mode=mode)
    prob.set_val("mass", 1.1)
    prob.set_val("damping", 0.35)
    prob.set_val("hardening", 0.7)
    prob.set_val("stiffness", rng.uniform(2.0, 4.0, 3))
    force = np.outer(1.0 + np.sin(9 * t), rng.uniform(0.5, 1.5, 3))
    if set_force:
        prob.set_val("force", force)
    if initial == "state":
        prob.set_val("initial_state", rng.normal(scale=0.3, size=(3, 2)))
    return prob


def test_smd_solution_matches_closed_form():
    t = np.linspace(0.0, 1.0, 401)
    prob = _smd_problem(t)
    prob.run_model()
    x_exact, v_exact = spring_mass_damper_response(t, 2.5, 0.2, 5.0)
    states = prob.get_val("states")
    assert states.shape == (401, 2)
    assert np.max(np.abs(states[:, 0] - x_exact)) < 3e-5  # BDF2, dt = 2.5 ms
    assert np.max(np.abs(states[:, 1] - v_exact)) < 3e-5


@pytest.mark.parametrize("matrix_free", [False, True])
def test_check_partials_smd(matrix_free):
    prob = _smd_problem(np.linspace(0.0, 0.05, 6), matrix_free=matrix_free)
    prob.set_val("mass", 2.3)
    prob.set_val("damping", 0.7)
    prob.set_val("stiffness", 4.1)
    prob.set_val("initial_state", [0.8, -0.3])
    prob.run_model()
    # perturb the states off the solution so the check is at a non-trivial point
    prob.set_val("states", prob.get_val("states") + np.random.default_rng(2).normal(scale=0.1, size=(6, 2)))
    data = prob.check_partials(method="fd", step=1e-7, form="central", out_stream=None)
    assert_check_partials(data, atol=1e-6, rtol=1e-6)


@pytest.mark.parametrize("initial", ["static", "state"])
@pytest.mark.parametrize("matrix_free", [False, True])
def test_check_partials_nonlinear_chain(initial, matrix_free):
    prob = _chain_problem(5, initial=initial, matrix_free=matrix_free, seed=4)
    prob.run_model()
    prob.set_val("states", prob.get_val("states") + np.random.default_rng(5).normal(scale=0.2, size=(5, 3, 2)))
    data = prob.check_partials(method="fd", step=1e-7, form="central", out_stream=None,
                               includes=["chain"])
    assert_check_partials(data, atol=1e-6, rtol=1e-6)


@pytest.mark.parametrize("initial", ["static", "state"])
@pytest.mark.parametrize("matrix_free", [False, True])
def test_totals_fwd_and_rev_agree_and_match_central_differences(initial, matrix_free):
    wrt = ["mass", "damping", "hardening", "stiffness", "force"] + (["initial_state"] if initial == "state" else [])
    totals = {}
    for mode in ("fwd", "rev"):
        prob = _chain_problem(21, initial=initial, matrix_free=matrix_free, mode=mode, seed=1)
        prob.run_model()
        data = prob.check_totals(of=["f"], wrt=wrt, method="fd", form="central", step=1e-6,
                                 out_stream=None)
        for key, d in data.items():
            j_fd = d["J_fd"]
            j = d["J_fwd"] if mode == "fwd" else d["J_rev"]
            scale = np.max(np.abs(j_fd))
            np.testing.assert_allclose(j, j_fd, rtol=1e-6, atol=1e-6 * scale, err_msg=str(key))
        totals[mode] = prob.compute_totals(of=["f"], wrt=wrt)
    for key in totals["fwd"]:
        np.testing.assert_allclose(totals["fwd"][key], totals["rev"][key], rtol=1e-10, atol=1e-12)


def test_one_entry_time_is_a_static_solve():
    prob = _chain_problem(1)
    prob.set_val("hardening", 0.5)
    prob.set_val("stiffness", [2.0, 1e6, 1e6])
    prob.set_val("force", [[12.0, 0.0, 0.0]])
    prob.run_model()
    # k (u + g u^3) = F with k = 2, g = 0.5, F = 12 -> u = 2 (stiff outer springs carry no load)
    assert prob.get_val("states")[0, 0, 0] == pytest.approx(2.0, rel=1e-10)
    totals = prob.compute_totals(of=["f"], wrt=["stiffness"])
    assert np.all(np.isfinite(totals["f", "stiffness"]))


def test_non_finite_forcing_raises_value_error_naming_input_and_step():
    prob = _chain_problem(4)
    force = prob.get_val("force")
    force[2, 1] = np.nan
    prob.set_val("force", force)
    with pytest.raises(ValueError, match=r"input 'force': entry 1 at time step 2 is not finite"):
        prob.run_model()


def test_bad_time_grid_is_rejected_at_setup():
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("smd", TimeHistoryComponent(system=spring_mass_damper_system(),
                                                         time=[0.0, 0.1, 0.3]))
    with pytest.raises(ValueError, match="uniform"):
        prob.setup()


@pytest.mark.filterwarnings("ignore::openmdao.utils.om_warnings.DerivativesWarning")  # mass and damping do not act in statics
def test_drop_time_axis_gives_plain_static_shapes_and_partials():
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("chain", TimeHistoryComponent(system=nonlinear_chain_system(2), time=[0.0],
                                                           drop_time_axis=True), promotes=["*"])
    prob.setup()
    prob.set_val("hardening", 0.5)
    prob.set_val("stiffness", [2.0, 3.0])
    prob.set_val("force", [2.0, 10.0])
    prob.run_model()
    states = prob.get_val("states")
    assert states.shape == (2, 2)
    # outer spring carries 10 N: 3 (s + 0.5 s^3) = 10; inner carries 12 N: u0 = 2
    assert states[0, 0] == pytest.approx(2.0, rel=1e-10)
    s = states[1, 0] - states[0, 0]
    assert 3.0 * (s + 0.5 * s**3) == pytest.approx(10.0, rel=1e-10)
    data = prob.check_partials(method="fd", step=1e-7, form="central", out_stream=None)
    assert_check_partials(data, atol=1e-6, rtol=1e-6)


def test_static_solve_that_fails_from_the_warm_start_is_retried_from_the_cold_guess(monkeypatch):
    """A static step-0 solve starts from the previous design's solution; when that Newton solve
    fails (a design far from the previous one), it is retried once from the cold guess, and the
    result equals a fresh problem's. A cold failure still raises."""
    import wingmdao.components.time_history as th

    prob = _chain_problem(4)
    prob.run_model()
    prob.set_val("hardening", 1.4)
    fresh = _chain_problem(4)
    fresh.set_val("hardening", 1.4)
    fresh.run_model()
    guesses = []
    march = th.march

    def warm_fails(*args, x_guess=None, **kw):
        warm = x_guess is not None and np.any(x_guess != 0.0) and len(guesses) == 0
        guesses.append("warm" if warm else "cold")
        if warm:
            raise om.AnalysisError("no convergence from the warm start (test)")
        return march(*args, x_guess=x_guess, **kw)

    monkeypatch.setattr(th, "march", warm_fails)
    prob.run_model()
    assert guesses == ["warm", "cold"]
    np.testing.assert_allclose(prob.get_val("states"), fresh.get_val("states"), rtol=1e-9, atol=1e-12)

    def always_fails(*args, **kw):
        raise om.AnalysisError("no convergence (test)")

    monkeypatch.setattr(th, "march", always_fails)
    with pytest.raises(om.AnalysisError, match="no convergence"):
        prob.run_model()


@pytest.mark.parametrize("initial", ["static", "state"])
def test_checkpointed_adjoint_totals_equal_full_storage_and_central_differences(initial):
    """adjoint_memory='checkpoint' (states only, Jacobians re-evaluated 4 steps at a time):
    totals equal the full storage's to 1e-10 and central differences to 1e-6."""
    wrt = ["mass", "damping", "hardening", "stiffness", "force"] + (["initial_state"] if initial == "state" else [])
    totals = {}
    for memory in ("full", "checkpoint"):
        prob = _chain_problem(21, initial=initial, matrix_free=True, seed=1, adjoint_memory=memory,
                              checkpoint_every=4)
        prob.run_model()
        assert prob.model.chain.checkpoint_every == (4 if memory == "checkpoint" else None)
        totals[memory] = prob.compute_totals(of=["f"], wrt=wrt)
        if memory == "checkpoint":
            data = prob.check_totals(of=["f"], wrt=wrt, method="fd", form="central", step=1e-6,
                                     out_stream=None)
            for key, d in data.items():
                scale = np.max(np.abs(d["J_fd"]))
                np.testing.assert_allclose(d["J_rev"], d["J_fd"], rtol=1e-6, atol=1e-6 * scale, err_msg=str(key))
    for key in totals["full"]:
        np.testing.assert_allclose(totals["checkpoint"][key], totals["full"][key], rtol=1e-10,
                                   atol=1e-10 * np.max(np.abs(totals["full"][key])), err_msg=str(key))


def test_adjoint_memory_auto_checkpoints_above_the_budget_and_needs_matrix_free():
    prob = _chain_problem(21, matrix_free=True, adjoint_memory_mb=0.002)   # ~10 steps of blocks
    assert 1 <= prob.model.chain.checkpoint_every < 21
    prob = _chain_problem(21, matrix_free=True)                           # 200 MB: full storage
    assert prob.model.chain.checkpoint_every is None
    with pytest.raises(ValueError, match="adjoint_memory='checkpoint' needs matrix_free=True"):
        _chain_problem(21, matrix_free=False, adjoint_memory="checkpoint")


def test_store_factors_auto_follows_the_factor_budget_and_keeps_the_totals(monkeypatch):
    """'auto' keeps the LU factors between sweeps only when SuperLU's estimated reserve fits
    FACTOR_MEMORY_MB (a 3-mass chain does, a zero budget does not); the totals of several
    tangent sweeps at one linearization (fwd mode) are the same with and without kept factors."""
    from wingmdao.components import time_history

    wrt = ["mass", "damping", "hardening", "stiffness"]
    totals = {}
    for budget, keep in ((16.0, True), (0.0, False)):
        monkeypatch.setattr(time_history, "FACTOR_MEMORY_MB", budget)
        prob = _chain_problem(21, mode="fwd", seed=2)
        assert prob.model.chain.store_factors is keep
        prob.run_model()
        totals[keep] = prob.compute_totals(of=["f"], wrt=wrt)
    for key, val in totals[True].items():
        np.testing.assert_allclose(totals[False][key], val, rtol=1e-12, atol=1e-14, err_msg=str(key))
    with pytest.raises(ValueError, match="store_factors = 'yes'; allowed: True, False, 'auto'"):
        _chain_problem(5, store_factors="yes")


def test_store_factors_auto_does_not_keep_the_factors_of_a_beam_history():
    """SuperLU reserves ~2.8 MB per factor of a 20-node beam: a 101-step history keeps none."""
    from wingmdao.components.beam import BeamDynamics

    prob = om.Problem(reports=False)
    prob.model.add_subsystem("beam", BeamDynamics(num_nodes=20, time=np.linspace(0.0, 1.0, 101)))
    prob.setup()
    assert prob.model.beam.store_factors is False


def _chain_force(n_time, seed):
    """The force history _chain_problem sets (same random stream)."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 0.3, n_time)
    rng.uniform(0.5, 2.0, (n_time, 3, 2))
    rng.uniform(2.0, 4.0, 3)
    return np.outer(1.0 + np.sin(9 * t), rng.uniform(0.5, 1.5, 3))


@pytest.mark.parametrize("mode", ["fwd", "rev"])
@pytest.mark.parametrize("matrix_free", [False, True])
def test_forcing_data_gives_the_states_and_totals_of_the_forcing_input(mode, matrix_free):
    """A forcing given as data (option forcing_data, not an input): same history, same totals
    with respect to the parameters (1e-12) and check_partials of the remaining inputs passes."""
    n_time, seed = 9, 3
    wrt = ["mass", "damping", "hardening", "stiffness"]
    ref = _chain_problem(n_time, matrix_free=matrix_free, mode=mode, seed=seed)
    ref.run_model()
    force = _chain_force(n_time, seed)
    np.testing.assert_array_equal(ref.get_val("force"), force)
    prob = _chain_problem(n_time, matrix_free=matrix_free, mode=mode, seed=seed, forcing_data={"force": force},
                          set_force=False)
    prob.run_model()
    assert "chain.force" not in prob.model.get_io_metadata(iotypes=("input",), return_rel_names=False)
    np.testing.assert_array_equal(prob.get_val("states"), ref.get_val("states"))
    t_ref, t_data = ref.compute_totals(of=["f"], wrt=wrt), prob.compute_totals(of=["f"], wrt=wrt)
    for key in t_ref:
        np.testing.assert_allclose(t_data[key], t_ref[key], rtol=1e-12, atol=0.0, err_msg=str(key))
    prob.set_val("states", prob.get_val("states") + np.random.default_rng(5).normal(scale=0.2, size=(n_time, 3, 2)))
    data = prob.check_partials(method="fd", step=1e-7, form="central", out_stream=None, includes=["chain"])
    assert_check_partials(data, atol=1e-6, rtol=1e-6)


def test_forcing_data_of_an_unknown_forcing_or_of_the_wrong_shape_is_rejected():
    force = _chain_force(5, 0)
    with pytest.raises(ValueError, match="not a forcing"):
        _chain_problem(5, forcing_data={"push": force}, set_force=False)
    with pytest.raises(ValueError, match="expected"):
        _chain_problem(5, forcing_data={"force": force[1:]}, set_force=False)
