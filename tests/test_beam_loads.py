"""BeamInternalLoads: csn resultants from the beam state."""

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.components.beam_loads import BeamInternalLoads


def _prob(nt, n, states):
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("loads", BeamInternalLoads(num_times=nt, num_nodes=n), promotes=["*"])
    prob.setup(force_alloc_complex=False)
    prob.set_val("states", states)
    return prob


def test_check_partials():
    nt, n = 3, 4
    rng = np.random.default_rng(5)
    x = rng.normal(size=(nt, n, 18)) * np.r_[np.ones(3), 0.8 * np.ones(3), 1e3 * np.ones(6), np.ones(6)]
    prob = _prob(nt, n, x)
    prob.run_model()
    data = prob.check_partials(method="fd", form="central", step=1e-6, out_stream=None)
    assert_check_partials(data, atol=1e-6, rtol=1e-7)


def test_values_by_hand():
    """Swept node (psi = -30 deg, s leaning aft): body force along s is axial, z force is F_n."""
    a = np.radians(30.0)
    x = np.zeros((1, 2, 18))
    x[0, :, 5] = -a  # psi
    s_axis = np.array([np.sin(a), np.cos(a), 0.0])
    c_axis = np.array([np.cos(a), -np.sin(a), 0.0])
    x[0, 0, 6:9] = 100.0 * s_axis + 5.0 * c_axis + [0, 0, 7.0]
    x[0, 1, 9:12] = 3.0 * s_axis  # pure torque
    prob = _prob(1, 2, x)
    prob.run_model()
    np.testing.assert_allclose(prob.get_val("F_csn")[0, 0], [5.0, 100.0, 7.0], atol=1e-12)
    np.testing.assert_allclose(prob.get_val("M_csn")[0, 1], [0.0, 3.0, 0.0], atol=1e-12)


def test_nan_state_raises():
    x = np.zeros((2, 3, 18))
    x[1, 2, 7] = np.nan
    prob = _prob(2, 3, x)
    with pytest.raises(ValueError, match="time index 1, node 2, state 7"):
        prob.run_model()


def _prob_by_conn(nt, n, states, shape=None, **opts):
    """BeamInternalLoads with inputs_by_conn=True: its states input shaped by the connected IVC."""
    prob = om.Problem(reports=False)
    ivc = prob.model.add_subsystem("ivc", om.IndepVarComp())
    ivc.add_output("states", val=np.zeros(shape or states.shape))
    prob.model.add_subsystem("loads", BeamInternalLoads(num_times=nt, num_nodes=n, inputs_by_conn=True, **opts))
    prob.model.connect("ivc.states", "loads.states")
    prob.setup(force_alloc_complex=False)
    if shape is None:
        prob.set_val("ivc.states", states)
    return prob


@pytest.mark.parametrize("matrix_free", [False, True])
def test_inputs_by_conn_give_the_same_loads_and_partials(matrix_free):
    """inputs_by_conn (shape_by_conn per-point inputs, no default copy): same outputs bitwise,
    check_partials passes with declared partials and matrix-free products."""
    nt, n = 3, 4
    rng = np.random.default_rng(7)
    x = rng.normal(size=(nt, n, 18)) * np.r_[np.ones(3), 0.8 * np.ones(3), 1e3 * np.ones(6), np.ones(6)]
    ref = _prob(nt, n, x)
    ref.run_model()
    prob = _prob_by_conn(nt, n, x, matrix_free=matrix_free)
    prob.run_model()
    for name in ("F_csn", "M_csn"):
        np.testing.assert_array_equal(prob.get_val(f"loads.{name}"), ref.get_val(name))
    data = prob.check_partials(method="fd", form="central", step=1e-6, out_stream=None, includes=["loads"])
    assert_check_partials(data, atol=1e-6, rtol=1e-7)


def test_inputs_by_conn_connected_with_the_wrong_shape_is_rejected():
    prob = _prob_by_conn(3, 4, None, shape=(2, 4, 18))
    with pytest.raises(ValueError, match="connected with shape"):
        prob.final_setup()    # setup_partials checks the resolved shape
