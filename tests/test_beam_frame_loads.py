"""Inertial loads of the beam in a moving frame (Alg. 2-3), statics, and the kinematic equations."""

import numpy as np
import pytest

from wingmdao.beam.residual import build_beam_system, forcing_specs, jig_state
from wingmdao.beam.rotations import body_to_csn, rate_matrix
from wingmdao.beam.static import BeamModel, beam_forcing, beam_parameters, straight_beam
from wingmdao.timemarch.system import pack

L, EI, MU = 10.0, 2.0e6, 5.0


def model(n=21, **kw):
    r0, th0 = straight_beam(n, L)
    return BeamModel(beam_parameters(r0, th0, EI_cc=EI, GJ=1e6, EI_nn=5 * EI, EA=1e10, mass_per_length=MU, **kw))


def test_frame_acceleration_equals_reversed_gravity():
    """Accelerating the frame up by a equals gravity -a (d'Alembert): same tip deflection."""
    m = model()
    a = m.solve(frame_acceleration=[0.0, 0.0, 9.81])
    g = m.solve(gravity=[0.0, 0.0, -9.81])
    np.testing.assert_allclose(a["r"], g["r"], atol=1e-14)
    assert a["r"][-1, 2] == pytest.approx(-MU * 9.81 * L**4 / (8 * EI), rel=5e-3)


def test_spinning_beam_centrifugal_tension():
    """Spin Omega about z: root axial force mu Omega^2 L^2 / 2 (rigid axially, small strain)."""
    m = model()
    Om = 2.0
    out = m.solve(frame_angular_velocity=[0.0, 0.0, Om])
    assert out["F"][0, 1] == pytest.approx(MU * Om**2 * L**2 / 2, rel=5e-3)
    np.testing.assert_allclose(out["r"][:, 0], 0.0, atol=1e-12)


def test_frame_angular_acceleration_bends_in_plane():
    """alpha0 about z: inertial load -mu alpha0 x r = mu alpha0 y e_x (linear in y): root M_z."""
    m = model()
    al = 0.5
    out = m.solve(frame_angular_acceleration=[0.0, 0.0, al])
    # force per length f_x = mu * al * y; root moment about z: -int y f_x dy = -mu al L^3 / 3
    assert out["M"][0, 2] == pytest.approx(-MU * al * L**3 / 3, rel=5e-3)
    assert out["F"][0, 0] == pytest.approx(MU * al * L**2 / 2, rel=5e-3)


def test_kinematic_residuals_use_T_transpose_K():
    """Nodal rows: u - dr/dt and omega_body - T^T K dtheta/dt vanish for consistent rates."""
    n = 3
    s = build_beam_system(n)
    r0, th0 = straight_beam(n, 2.0)
    params = beam_parameters(r0, th0, EI_cc=1.0, GJ=1.0, EI_nn=1.0, EA=1.0)
    p = pack(s.param_specs, params)
    q = pack(forcing_specs(n), beam_forcing(n))
    rng = np.random.default_rng(0)
    x = jig_state(params) + rng.normal(scale=0.3, size=(n, 18))
    xdot = rng.normal(size=(n, 18))
    for i in range(n):
        th = x[i, 3:6]
        x[i, 12:15] = xdot[i, 0:3]
        x[i, 15:18] = body_to_csn(th).T @ rate_matrix(th) @ xdot[i, 3:6]
    res = s.residual(x.ravel(), xdot.ravel(), p, q).reshape(n, 18)
    np.testing.assert_allclose(res[:, 12:18], 0.0, atol=1e-13)


def test_rotary_inertia_torque_under_frame_angular_acceleration():
    """alpha0 along the beam axis: inertial torque -i_ss alpha0 per length, root M_y = -i_ss alpha0 L
    (mass centre on the axis, so the translational part gives no torque)."""
    i_ss, al = 0.8, 1.5
    m = model(inertia_per_length=np.diag([0.1, i_ss, 0.3]))
    out = m.solve(frame_angular_acceleration=[0.0, al, 0.0])
    assert out["M"][0, 1] == pytest.approx(-i_ss * al * L, rel=1e-6)
