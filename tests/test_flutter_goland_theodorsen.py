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

BETA_L = (1.8751040687, 4.6940911330, 7.8547574382, 10.995540734, 14.137168391)


def theodorsen(k):
    """C(k) = H1(2)(k) / (H1(2)(k) + i H0(2)(k))."""
    return hankel2(1, k) / (hankel2(1, k) + 1j * hankel2(0, k))


def galerkin_k_method(n_bend=3, n_tors=3, n_quad=60, wing=goland):
    """Return modes(k) -> (omega, g) of a uniform wing (a case module's data), and the semichord b."""
    L, c, rho = wing.SEMI_SPAN, wing.CHORD, wing.DENSITY
    b, a = c / 2, 2 * wing.ELASTIC_AXIS - 1
    m = wing.MASS
    S = m * (getattr(wing, "MASS_CENTRE", wing.ELASTIC_AXIS) - wing.ELASTIC_AXIS) * c
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
    M = np.block([[m * Phh, S * Pha], [S * Pha.T, wing.INERTIA * Paa]])
    K = np.block([[wing.EI_FLAP * inner(phi2, phi2), Z], [Z.T, wing.GJ * inner(th1, th1)]])

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


#: per case: the k bracket of the flutter crossing and the index (by frequency) of its mode
FLUTTER_BRACKET = {"goland": (0.3, 0.6, 1), "hale": (0.25, 0.5, 2)}


def flutter_point(n_bend=3, n_tors=3, case="goland"):
    import importlib

    wing = importlib.import_module(f"wingmdao.cases.{case}")
    k0, k1, j = FLUTTER_BRACKET[case]
    modes, b = galerkin_k_method(n_bend, n_tors, wing=wing)
    k_f = brentq(lambda k: modes(k)[1][j], k0, k1, xtol=1e-12)
    omega = modes(k_f)[0][j]
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


def test_hale_exact_theodorsen_vs_published():
    """HALE (no CG offset, 20 km): exact C(k) 32.51 m/s / 22.37 rad/s; Patil et al. (finite-state
    inflow) 32.21 / 22.61: within 1 % and 1.2 %."""
    v3, w3 = flutter_point(3, 3, "hale")
    v5, w5 = flutter_point(5, 5, "hale")
    assert v5 == pytest.approx(v3, rel=1e-4) and w5 == pytest.approx(w3, rel=1e-4)
    from wingmdao.cases import hale

    assert v5 == pytest.approx(hale.PUBLISHED["flutter_speed_m_s"], rel=1e-2)
    assert w5 == pytest.approx(hale.PUBLISHED["flutter_frequency_rad_s"], rel=1.2e-2)


@pytest.mark.slow
@pytest.mark.parametrize("case, speeds", [("goland", (100.0, 160.0)), ("hale", (25.0, 36.0))])
def test_beam_strip_theory_flutter_vs_exact_theodorsen(case, speeds):
    """Our beam + two-state Jones aerodynamics against the exact-C(k) Galerkin solution
    (Goland +0.3 % / -0.9 %, HALE +0.5 % / -1.3 % in speed / frequency)."""
    from wingmdao.stability import critical_speeds, sweep
    from wingmdao.stability.cases import flutter_problem

    v_exact, w_exact = flutter_point(4, 4, case)
    prob = flutter_problem(case, 21)
    res = sweep(prob.system, prob.params_at, np.linspace(*speeds, 4), n_track=4,
                weights=prob.beam_weights(), **prob.eig_options)
    crit = critical_speeds(res, xtol=1e-4)
    assert crit["flutter_speed"] == pytest.approx(v_exact, rel=8e-3)
    assert crit["flutter_frequency"] == pytest.approx(w_exact, rel=1.8e-2)
