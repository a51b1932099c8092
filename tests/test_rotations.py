"""Euler-angle frame T(theta) and the rate/curvature matrix K (Eq. A.1, A.3)."""

import casadi as ca
import numpy as np
import pytest

from wingmdao.beam.rotations import body_to_csn, euler_from_axis, rate_matrix


def skew(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


@pytest.mark.parametrize("theta", [(0.3, -0.7, 0.4), (2.5, 1.1, -1.2), (6.2, -3.0, 1.5)])
def test_T_is_a_proper_rotation(theta):
    T = body_to_csn(np.array(theta))
    np.testing.assert_allclose(T @ T.T, np.eye(3), atol=1e-14)
    assert np.linalg.det(T) == pytest.approx(1.0)
    # csn right-handed: c x s = n (rows of T are c, s, n in body components)
    np.testing.assert_allclose(np.cross(T[0], T[1]), T[2], atol=1e-14)


def test_sequence_phi_then_psi_then_twist():
    """Hand-built: phi about x (dihedral) lifts the s axis, psi turns it forward, twist keeps s."""
    phi, twist, psi = 0.2, 0.3, -0.4
    s_axis = body_to_csn(np.array([phi, twist, psi]))[1]
    expected = np.array([-np.sin(psi), np.cos(psi) * np.cos(phi), np.cos(psi) * np.sin(phi)])
    np.testing.assert_allclose(s_axis, expected, atol=1e-14)
    np.testing.assert_allclose(body_to_csn(np.array([phi, 0.0, 0.0]))[1], [0, np.cos(phi), np.sin(phi)])


@pytest.mark.parametrize("theta", [(0.3, -0.7, 0.4), (2.5, 1.1, -1.2), (6.2, -3.0, 1.45)])
def test_K_gives_angular_velocity(theta):
    """dT/dt = -[omega_csn x] T for a passive T; check K against central differences of T."""
    theta = np.array(theta)
    rate = np.array([0.7, -1.3, 0.4])
    h = 1e-6
    dT = (body_to_csn(theta + h * rate) - body_to_csn(theta - h * rate)) / (2 * h)
    W = -dT @ body_to_csn(theta).T
    omega_fd = np.array([W[2, 1], W[0, 2], W[1, 0]])
    np.testing.assert_allclose(rate_matrix(theta) @ rate, omega_fd, rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(W, -W.T, atol=1e-8)


def test_K_singular_only_at_psi_90_degrees():
    for phi in np.linspace(0.0, 2 * np.pi, 7):  # full roll-up about x: regular
        for twist in (-2.0, 0.5, 3.0):
            assert np.linalg.det(rate_matrix(np.array([phi, twist, 0.3]))) == pytest.approx(np.cos(0.3))
    assert abs(np.linalg.det(rate_matrix(np.array([0.4, 0.2, np.pi / 2])))) < 1e-15


def test_casadi_and_numpy_agree():
    th = ca.SX.sym("th", 3)
    f = ca.Function("f", [th], [body_to_csn(th), rate_matrix(th)])
    val = np.array([0.4, -0.2, 0.9])
    T, K = f(val)
    np.testing.assert_allclose(np.array(T), body_to_csn(val), atol=1e-15)
    np.testing.assert_allclose(np.array(K), rate_matrix(val), atol=1e-15)


def test_euler_from_axis_round_trip():
    rng = np.random.default_rng(1)
    for _ in range(5):
        t = rng.normal(size=3)
        t[1] = abs(t[1]) + 0.1
        ang = euler_from_axis(t, twist=0.3)
        np.testing.assert_allclose(body_to_csn(ang)[1], t / np.linalg.norm(t), atol=1e-14)
        assert ang[1] == 0.3
    with pytest.raises(ValueError, match="euler_sequence"):
        body_to_csn(np.zeros(3), "fuselage-xyz")
