"""Goland wing flutter by an independent method: Galerkin assumed modes + exact Theodorsen.

Uniform cantilever, bending h (positive down) and twist alpha about the elastic axis
(Goland, J. Appl. Mech. 12(4), 1945; Bisplinghoff, Ashley & Halfman, *Aeroelasticity*, 1955,
Sec. 9.3 set the problem up the same way):

    m h_tt + S alpha_tt + EI h'''' = -L,      S h_tt + I alpha_tt - GJ alpha'' = M_ea,

with Theodorsen's harmonic lift and moment (NACA Rep. 496, 1935) and the exact C(k) from Hankel
functions, projected on clamped-free bending modes and sin((2j-1) pi y / 2L) torsion modes and
solved by the k-method: (M + A(k)) q = lambda K q, lambda = (1 + i g) / omega^2; flutter where the
required structural damping g of a mode crosses zero. Nothing here shares code with the beam,
the finite-state (R. T. Jones) aerodynamics or the eigen-solver of wingmdao: it tests both the
published figures (137.2 m/s, 70.7 rad/s, as quoted by Patil, Hodges & Cesnik and Palacios &
Epureanu) against the tabulated data and our strip-theory beam against an exact-C(k) solution.
"""

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import hankel2

from wingmdao.cases import goland

BETA_L = (1.8751040687, 4.6940911330, 7.8547574382, 10.995540734)


def theodorsen(k):
    """C(k) = H1(2)(k) / (H1(2)(k) + i H0(2)(k))."""
    return hankel2(1, k) / (hankel2(1, k) + 1j * hankel2(0, k))


def galerkin_k_method(n_bend=3, n_tors=3, n_quad=60):
    """Return modes(k) -> (omega, g) of the Goland wing, and the semichord b."""
    L, c, rho = goland.SEMI_SPAN, goland.CHORD, goland.DENSITY
    b, a = c / 2, 2 * goland.ELASTIC_AXIS - 1
    m, S = goland.MASS, goland.MASS * (goland.MASS_CENTRE - goland.ELASTIC_AXIS) * c
    xq, wq = np.polynomial.legendre.leggauss(n_quad)
    y, w = (0.5 * L * (xq + 1))[:, None], 0.5 * L * wq
    bl = np.array(BETA_L[:n_bend]) / L
    sig = (np.cosh(bl * L) + np.cos(bl * L)) / (np.sinh(bl * L) + np.sin(bl * L))
    phi = np.cosh(bl * y) - np.cos(bl * y) - sig * (np.sinh(bl * y) - np.sin(bl * y))
    phi2 = bl**2 * (np.cosh(bl * y) + np.cos(bl * y) - sig * (np.sinh(bl * y) + np.sin(bl * y)))
    gam = (2 * np.arange(1, n_tors + 1) - 1) * np.pi / (2 * L)
    th, th1 = np.sin(gam * y), gam * np.cos(gam * y)

    def inner(f, g):
        return (f * w[:, None]).T @ g

    Phh, Pha, Paa = inner(phi, phi), inner(phi, th), inner(th, th)
    Z = np.zeros((n_bend, n_tors))
    M = np.block([[m * Phh, S * Pha], [S * Pha.T, goland.INERTIA * Paa]])
    K = np.block([[goland.EI_FLAP * inner(phi2, phi2), Z], [Z.T, goland.GJ * inner(th1, th1)]])

    def modes(k):
        C, p = theodorsen(k), np.pi * rho * b**2
        # harmonic lift / moment over omega^2: L = Lh h + La alpha, M_ea = Mh h + Ma alpha
        Lh = p * (-1 + 2j * C / k)
        La = p * b * (1j / k + a + 2 * C / k**2 + 2j * C * (0.5 - a) / k)
        Mh = p * b * (-a + 2j * (a + 0.5) * C / k)
        Ma = p * b**2 * (-1j * (0.5 - a) / k + 0.125 + a**2
                         + 2 * (a + 0.5) * C * (1 / k**2 + 1j * (0.5 - a) / k))
        # generalized forces: -L on the bending modes, M_ea on the torsion modes; K q = omega^2 (M + A) q
        A = np.block([[-Lh * Phh, -La * Pha], [Mh * Pha.T, Ma * Paa]])
        mu = np.linalg.eigvals(np.linalg.solve(K, M + A))
        order = np.argsort(mu.real)[::-1]                 # ascending frequency
        return 1 / np.sqrt(mu.real[order]), mu.imag[order] / mu.real[order]

    return modes, b


def flutter_point(n_bend=3, n_tors=3):
    modes, b = galerkin_k_method(n_bend, n_tors)
    k_f = brentq(lambda k: modes(k)[1][1], 0.3, 0.6, xtol=1e-12)   # the torsion-branch mode
    omega = modes(k_f)[0][1]
    return omega * b / k_f, omega


def test_theodorsen_function_limits():
    assert theodorsen(1e-6) == pytest.approx(1.0, abs=1e-4)
    assert theodorsen(50.0) == pytest.approx(0.5, abs=1e-2)
    assert theodorsen(0.1) == pytest.approx(0.8319 - 0.1723j, abs=1e-3)   # tabulated C(0.1)


def test_galerkin_converged_and_matches_published_goland_flutter():
    v2, w2 = flutter_point(2, 2)
    v4, w4 = flutter_point(4, 4)
    assert v4 == pytest.approx(v2, rel=1e-4) and w4 == pytest.approx(w2, rel=1e-4)
    # exact strip theory on the tabulated data: 137.0 m/s, 70.03 rad/s
    assert v4 == pytest.approx(goland.PUBLISHED["flutter_speed_m_s"], rel=3e-3)
    assert w4 == pytest.approx(goland.PUBLISHED["flutter_frequency_rad_s"], rel=1.5e-2)


@pytest.mark.slow
def test_beam_strip_theory_flutter_vs_exact_theodorsen():
    """Our beam + two-state Jones aerodynamics against the exact-C(k) Galerkin solution."""
    from wingmdao.stability import critical_speeds, sweep
    from wingmdao.stability.cases import flutter_problem

    v_exact, w_exact = flutter_point(4, 4)
    prob = flutter_problem("goland", 21)
    res = sweep(prob.system, prob.params_at, np.linspace(100.0, 160.0, 4), n_track=4,
                weights=prob.beam_weights(), **prob.eig_options)
    crit = critical_speeds(res, xtol=1e-4)
    assert crit["flutter_speed"] == pytest.approx(v_exact, rel=6e-3)
    assert crit["flutter_frequency"] == pytest.approx(w_exact, rel=1.5e-2)
