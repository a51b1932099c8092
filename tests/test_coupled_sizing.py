"""Coupled (aeroelastic) load cases in the sizing model: WingStructure with LoadCase.aero runs on
AeroelasticBeamDynamics; the state slice partials; the adjoint totals of the coupled PEGASUS gust KS
w.r.t. thicknesses against central finite differences; bad aero input."""

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.aero.coupled import CoupledAero
from wingmdao.cases import pegasus
from wingmdao.components.state_slice import BeamStateSlice
from wingmdao.groups.load_case import LoadCase
from wingmdao.sizing import build_problem


def test_state_slice_values_and_partials():
    nt, n = 3, 4
    prob = om.Problem()
    prob.model.add_subsystem("s", BeamStateSlice(num_times=nt, num_nodes=n, state_shape=(22 * n + 2,)), promotes=["*"])
    prob.setup(force_alloc_complex=True)
    x = np.random.default_rng(1).normal(size=(nt, 22 * n + 2))
    prob.set_val("states", x)
    prob.run_model()
    np.testing.assert_array_equal(prob.get_val("beam_states"), x[:, :22 * n].reshape(nt, n, 22)[:, :, :18])
    assert_check_partials(prob.check_partials(method="cs", out_stream=None), atol=1e-12, rtol=1e-12)


def test_state_slice_of_a_joined_beam_block():
    """One beam's contiguous block (a joined system's offsets): values and partials."""
    nt, n, size, offset = 2, 3, 100, 37
    prob = om.Problem()
    prob.model.add_subsystem("s", BeamStateSlice(num_times=nt, num_nodes=n, state_shape=(size,),
                                                 columns=offset + np.arange(18 * n)), promotes=["*"])
    prob.setup(force_alloc_complex=True)
    x = np.random.default_rng(2).normal(size=(nt, size))
    prob.set_val("states", x)
    prob.run_model()
    np.testing.assert_array_equal(prob.get_val("beam_states"), x[:, offset:offset + 18 * n].reshape(nt, n, 18))
    assert_check_partials(prob.check_partials(method="cs", out_stream=None), atol=1e-12, rtol=1e-12)
    with pytest.raises(ValueError, match="columns: need 54 state indices"):
        bad = om.Problem()
        bad.model.add_subsystem("s", BeamStateSlice(num_times=nt, num_nodes=n, state_shape=(40,),
                                                    columns=offset + np.arange(18 * n)))
        bad.setup()


def test_bad_aero_inputs():
    with pytest.raises(ValueError, match="chord"):
        CoupledAero(chord=-1.0, airspeed=100.0, density=1.0).parameters(3)
    with pytest.raises(ValueError, match="aero"):
        LoadCase("g", np.zeros(1), aero={"chord": 1.0})
    with pytest.raises(ValueError, match="gust_velocity"):
        LoadCase("g", np.zeros(1), forcing={"gust_velocity": np.zeros(3)})  # only with aero


@pytest.fixture(scope="module")
def coupled_gust():
    args = pegasus.PegasusOptions(loads="gust", aero="coupled", t_final=0.3, dt=0.03, gust_start=0.0)
    setup = pegasus.build(args)
    setup.options.disp = False
    assert setup.load_cases[0].aero is not None
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
    prob.run_model()
    return prob


def test_coupled_gust_runs_from_trimmed_state(coupled_gust):
    prob = coupled_gust
    st = prob.get_val("cases.gust.states")
    assert st.shape == (11, 22 * 20 + 1)  # 22 states per node + alpha_trim (clamped root)
    assert np.all(np.isfinite(st))
    alpha = st[:, -1]
    assert 0.0 < alpha[0] < 0.2  # a positive trim angle of attack for 1 g
    np.testing.assert_allclose(alpha, alpha[0], rtol=1e-9)  # held after t = 0
    assert np.isfinite(prob.get_val("cases.gust.ks_vm")[0])


def test_coupled_gust_ks_totals_vs_fd(coupled_gust):
    data = coupled_gust.check_totals(of=["cases.gust.ks_vm"], wrt=["t_upper_skin", "t_front_spar"], method="fd",
                                     form="central", step=1e-7, step_calc="rel_avg", out_stream=None)
    for key, d in data.items():
        J = d["J_fwd"] if "J_fwd" in d else d["J_rev"]
        err = np.abs(J - d["J_fd"]).max() / np.abs(d["J_fd"]).max()
        assert err < 1e-5, (key, err)


@pytest.mark.slow
def test_coupled_maneuvers_trim_to_n_w_and_totals():
    """--aero coupled maneuvers: static trim to n W; positive alpha at +2.5 g, negative at -1 g; KS totals vs FD."""
    setup = pegasus.build(loads="maneuver", aero="coupled")
    setup.options.disp = False
    assert all(c.aero is not None and c.aero.trim for c in setup.load_cases)
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
    prob.run_model()
    a_pos = prob.get_val("cases.maneuver_pos.states").reshape(-1)[-1]
    a_neg = prob.get_val("cases.maneuver_neg.states").reshape(-1)[-1]
    assert a_pos > 0 > a_neg
    data = prob.check_totals(of=["cases.maneuver_pos.ks_vm"], wrt=["t_upper_skin"], method="fd", form="central",
                             step=1e-7, step_calc="rel_avg", out_stream=None)
    for key, d in data.items():
        J = d["J_fwd"] if "J_fwd" in d else d["J_rev"]
        assert np.abs(J - d["J_fd"]).max() / np.abs(d["J_fd"]).max() < 1e-5, key


def test_size_cli_coupled_short(tmp_path):
    """`wingmdao size pegasus --aero coupled`: a short coupled gust, 2 SLSQP iterations, JSON written."""
    import json

    from wingmdao.cli import main

    out = tmp_path / "r.json"
    rc = main(["size", "pegasus", "--loads", "gust", "--aero", "coupled",
               "--t-final", "0.3", "--dt", "0.03", "--gust-start", "0", "--maxiter", "2", "--presize", "0",
               "--out", str(tmp_path), "--no-plots", "--json", str(out)])
    assert rc == (0 if json.loads(out.read_text())["success"] else 1)   # 1: not converged in maxiter
    res = json.loads(out.read_text())
    assert res["iterations"] == 2 and np.isfinite(res["mass_kg"]) and "gust" in res["ks"]
