"""Swept strips on the velocity normal to their beam (wingmdao.aero.joined, ``normal_flow``)
against simple sweep theory: R. T. Jones, "Wing plan-forms for high-speed flight", NACA Report
863, 1947 (independence principle), and the strip theory of sections normal to the elastic axis
of J. G. Barmby, H. J. Cunningham, I. E. Garrick, NACA Report 1014, 1951."""

import numpy as np
import pytest

from wingmdao.aero.joined import build_joined_aeroelastic_system, pack_aero_forcing, pack_aero_parameters, sweep_cosine
from wingmdao.beam.joints import Beam
from wingmdao.beam.rotations import euler_from_axis
from wingmdao.beam.static import beam_parameters

V, RHO, CHORD, SPAN, N = 50.0, 1.2, 0.6, 4.0, 3
SUPPORTS = (("wing", 0, "x"), ("wing", 0, "z"), ("wing", -1, "z"))
#: exponents b_k of exp(-b_k s), s = V t / b, of the two-term approximations of Wagner's function
#: (R. T. Jones, NACA Report 681, 1940: 1 - 0.165 e^-0.0455 s - 0.335 e^-0.3 s) and of
#: Kuessner's (1 - 0.5 e^-0.13 s - 0.5 e^-s)
WAGNER_EXPONENTS = (0.0455, 0.3)
KUSSNER_EXPONENTS = (0.13, 1.0)


def _swept_wing(sweep_deg, normal_flow):
    lam = np.radians(sweep_deg)
    d = np.array([np.sin(lam), np.cos(lam), 0.0])           # aft-swept beam axis (body x aft)
    r = np.linspace(0.0, SPAN, N)[:, None] * d
    params = beam_parameters(r, np.tile(euler_from_axis(d), (N, 1)), EI_cc=1e6, GJ=1e6, EI_nn=1e7, EA=1e9,
                             mass_per_length=1.0, inertia_per_length=np.diag([1e-3] * 3))
    s = build_joined_aeroelastic_system([Beam("wing", N, root="free")], [], lifting=("wing",), wing="wing",
                                        tail=None, supports=SUPPORTS, normal_flow=normal_flow)
    p = pack_aero_parameters(s, {"wing": params}, {"wing": {"chord": CHORD, "ref_point": 0.25}},
                             airspeed=V, density=RHO)
    return s, p, lam


def _steady_lift(s, p, alpha=0.0, gust=0.0):
    """Lift per beam length (N/m) at the jig with every lag state at its steady value: the lag
    rows are tau dx/dt + x - input, so at x = 0 the residual is -input."""
    x = s.jig_state(p)
    x[s.trim_index["alpha_trim"]] = alpha
    q = pack_aero_forcing(s, {"wing": np.full(N, gust)})
    xdot = np.zeros_like(x)
    lag = s.lag_index["wing"]
    x[lag] = -s.residual(x, xdot, p, q)[lag]
    assert np.allclose(s.residual(x, xdot, p, q)[lag], 0.0, atol=1e-14)
    return s.section_loads(x, xdot, p, q)["wing"][0]


@pytest.mark.parametrize("sweep_deg", [30.0, 45.0])
def test_swept_strip_lift_is_simple_sweep_theory(sweep_deg):
    """Steady lift per beam length of a swept strip at the aircraft's angle alpha, and in a gust
    w = V alpha: 1/2 rho (V cos L)^2 c_n a (alpha / cos L) = 1/2 rho V^2 c_n a alpha cos L
    (per unit span the lift slope a cos L on the streamwise chord c_n / cos L)."""
    s, p, lam = _swept_wing(sweep_deg, True)
    alpha = 0.02
    closed = 0.5 * RHO * V ** 2 * CHORD * 2 * np.pi * alpha * np.cos(lam)
    np.testing.assert_allclose(_steady_lift(s, p, alpha=alpha), closed, rtol=1e-10)
    np.testing.assert_allclose(_steady_lift(s, p, gust=V * alpha), closed, rtol=1e-10)


def test_swept_strip_lag_time_constants_run_on_the_normal_velocity():
    """Wagner's and Kuessner's lag time constants of a swept strip are b / (b_k V cos L)
    (the reduced time of the normal section, s = V cos(L) t / b, b the normal semichord)."""
    s, p, lam = _swept_wing(30.0, True)
    x = s.jig_state(p)
    q = pack_aero_forcing(s)
    jx, jxdot = s.jac_state(x, 0 * x, p, q)
    jx, jxdot = jx.toarray(), jxdot.toarray()
    b = 0.5 * CHORD
    for row in s.lag_index["wing"]:
        for k, e in enumerate(WAGNER_EXPONENTS + KUSSNER_EXPONENTS):
            tau = jxdot[row[k], row[k]] / jx[row[k], row[k]]
            assert tau == pytest.approx(b / (e * V * np.cos(lam)), rel=1e-12)


def test_normal_flow_leaves_an_unswept_strip_unchanged():
    """A beam normal to the free stream (cos L = 1): the same residual with and without the option."""
    s0, p0, _ = _swept_wing(0.0, False)
    s1, p1, _ = _swept_wing(0.0, True)
    assert float(sweep_cosine(np.zeros(3))) == 1.0
    x = s0.jig_state(p0)
    x[s0.trim_index["alpha_trim"]] = 0.03
    q = pack_aero_forcing(s0, {"wing": np.full(N, 1.5)})
    xdot = np.linspace(-1.0, 1.0, x.size)
    np.testing.assert_array_equal(s0.residual(x, xdot, p0, q), s1.residual(x, xdot, p1, q))


def test_normal_flow_with_trim_rotation_is_refused():
    with pytest.raises(ValueError, match="normal_flow=True with trim_rotation=True"):
        build_joined_aeroelastic_system([Beam("wing", N, root="free")], [], lifting=("wing",), wing="wing",
                                        tail=None, supports=SUPPORTS, normal_flow=True, trim_rotation=True)
