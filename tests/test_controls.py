"""Control surfaces (wingmdao.aero.controls): flap aerodynamics against thin-airfoil closed forms
(Glauert) and Theodorsen's harmonic flap lift, input checks."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from wingmdao.aero.controls import (ControlLaw, ControlSurface, control_spec, flap_harmonic_loads,
                                    flap_lift_effectiveness, hinge_moment_coefficients, pid_state_space)
from wingmdao.aero.strip import theodorsen_exact

HINGES = (0.6, 0.7, 0.75, 0.8, 0.9)


def _theta_f(hinge):
    return math.acos(1.0 - 2.0 * hinge)


@pytest.mark.parametrize("hinge", HINGES)
def test_flap_lift_effectiveness_glauert(hinge):
    # Glauert, The Elements of Aerofoil and Airscrew Theory (1926), Ch. VII: dCl/d delta = 2 (pi - theta_f + sin theta_f)
    th = _theta_f(hinge)
    assert flap_lift_effectiveness(hinge) == pytest.approx(2.0 * (math.pi - th + math.sin(th)), rel=1e-12)


def _thin_airfoil_hinge_coefficient(hinge, alpha, delta):
    """C_h (TE down +) by integrating thin-airfoil theory's load over the flap: the Fourier series of
    the flap camber summed in closed form, Delta C_p = 4 [A_0 cot(theta/2) + delta/pi ln|sin((theta+theta_f)/2)
    / sin((theta-theta_f)/2)|], A_0 = alpha + delta (pi - theta_f) / pi."""
    th_f = _theta_f(hinge)
    a0 = alpha + delta * (math.pi - th_f) / math.pi

    def dcp(th):
        return 4.0 * (a0 / math.tan(th / 2) + delta / math.pi * math.log(abs(math.sin((th + th_f) / 2)
                                                                              / math.sin((th - th_f) / 2))))

    def integrand(th):  # -(x/c - x_h) Delta C_p d(x/c)
        x = 0.5 * (1 - math.cos(th))
        return -dcp(th) * (x - hinge) * 0.5 * math.sin(th)

    val, _ = quad(integrand, th_f, math.pi, limit=200, points=None)
    return val


@pytest.mark.parametrize("hinge", HINGES)
def test_hinge_moment_coefficients_thin_airfoil(hinge):
    c_ha, c_hd = hinge_moment_coefficients(hinge)
    assert c_ha == pytest.approx(_thin_airfoil_hinge_coefficient(hinge, 1.0, 0.0), rel=1e-7)
    assert c_hd == pytest.approx(_thin_airfoil_hinge_coefficient(hinge, 0.0, 1.0), rel=1e-6)
    assert c_ha < 0 and c_hd < 0  # the load pushes the trailing edge up


@pytest.mark.parametrize("hinge", (0.7, 0.8))
def test_harmonic_flap_lift_theodorsen(hinge):
    """L / (rho V^2 b) of beta = e^{i omega t}: Theodorsen (NACA Rep. 496, 1935) written in theta_f,
    L = rho b^2 (-V T4 dbeta/dt - b T1 d2beta/dt2) + 2 pi rho V b C(k) (V T10 beta / pi + b T11 dbeta/dt / (2 pi))."""
    th = _theta_f(hinge)
    s, c = math.sin(th), math.cos(th)
    T4 = -(math.pi - th) - c * s
    T1 = -s * (2 + c * c) / 3 - c * (math.pi - th)
    T10 = s + math.pi - th
    T11 = (math.pi - th) * (1 + 2 * c) + s * (2 + c)
    k = np.array([0.05, 0.1, 0.3, 0.5, 1.0])
    Ck = theodorsen_exact(k)
    expected = -1j * k * T4 + k ** 2 * T1 + 2 * Ck * (T10 + 0.5j * k * T11)
    lift, moment, hinge_m = flap_harmonic_loads(k, hinge, theodorsen_exact)
    np.testing.assert_allclose(lift, expected, rtol=1e-12)
    # k -> 0: Glauert's Cm_c/4 = -sin(theta_f) (1 - cos theta_f) / 2 on 1/2 rho V^2 c^2 = 2 rho V^2 b^2, moved to midchord;
    # the steady hinge moment (on rho V^2 b^2: 2 C_h)
    l0, m0, h0 = flap_harmonic_loads(np.array([1e-9]), hinge, theodorsen_exact)
    assert m0[0].real == pytest.approx(-s * (1 - c) + 0.5 * l0[0].real, rel=1e-6)
    assert h0[0].real == pytest.approx(2 * hinge_moment_coefficients(hinge)[1], rel=1e-6)


def test_surface_input_errors():
    with pytest.raises(ValueError, match="hinge = 1.2 is outside the chord"):
        ControlSurface("aileron", hinge=1.2, span=(0.7, 1.0))
    with pytest.raises(ValueError, match=r"span = \[0.7, 1.3\] is outside the semi-span"):
        ControlSurface("aileron", hinge=0.75, span=(0.7, 1.3))
    with pytest.raises(ValueError, match="actuator_order"):
        ControlSurface("aileron", hinge=0.75, span=(0.7, 1.0), actuator_order=3)
    s = ControlSurface("aileron", hinge=0.75, nodes=(5, 12))
    with pytest.raises(ValueError, match="outside the span"):
        s.node_indices(np.linspace(0, 10, 8))
    assert ControlSurface("a", hinge=0.75, span=(0.7, 1.0)).node_indices(np.linspace(0, 10, 11)) == (7, 8, 9, 10)


def test_law_input_errors():
    with pytest.raises(ValueError, match="open-loop controller is unstable"):
        ControlLaw(("root_bending",), A=[[0.5]], B=[[1.0]], C=[[1.0]], D=[[0.0]])
    with pytest.raises(ValueError, match=r"D has shape \(1, 2\); allowed \(1, 1\)"):
        ControlLaw(("root_bending",), A=np.zeros((0, 0)), B=[], C=[], D=[[1.0, 2.0]])
    with pytest.raises(ValueError, match="output 'g_load' unknown"):
        ControlLaw(("g_load",), A=[], B=[], C=[], D=[[1.0]])
    ControlLaw(("root_bending",), *pid_state_space(1.0, 0.5, 0.1))  # integrator: eigenvalue 0 allowed
    law = ControlLaw(("root_bending",), A=[], B=[], C=[], D=[[1.0], [1.0]], n_surfaces=2)
    surf = [ControlSurface("a", hinge=0.75, span=(0.7, 1.0))]
    with pytest.raises(ValueError, match="2 commands for 1 surfaces"):
        control_spec(surf, np.linspace(0, 10, 11), law)
