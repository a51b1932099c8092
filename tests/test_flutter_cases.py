"""In vacuo natural frequencies of the Goland and HALE wings through wingmdao.stability.

References: the closed forms of a uniform cantilever (bending 1.8751^2 sqrt(EI / (m L^4)),
torsion pi/2 sqrt(GJ / (I L^2))), a Rayleigh-Ritz solution of the coupled bending-torsion
cantilever written here (polynomial bending and sine torsion shapes; M. Goland, "The flutter of a
uniform cantilever wing", J. Appl. Mech. 12(4), 1945, solves the same equations exactly) and the
published HALE frequencies (M. J. Patil, D. H. Hodges, C. E. S. Cesnik, J. Aircraft 38(1), 2001),
and the exact solution of the coupled bending-torsion cantilever (Goland 1945; Bisplinghoff,
Ashley & Halfman, "Aeroelasticity", 1955): its transcendental frequency equation solved here.
"""

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.optimize as sopt

from wingmdao.beam.residual import forcing_specs
from wingmdao.beam.static import BeamModel, beam_forcing
from wingmdao.cases import goland, hale
from wingmdao.stability import eigenmodes
from wingmdao.timemarch.system import pack


def beam_frequencies(params, count=6):
    m = BeamModel(params)
    n = m.num_nodes
    q = pack(forcing_specs(n), beam_forcing(n))
    modes = eigenmodes(m.system, m.p, q, m.jig().ravel())
    osc = np.flatnonzero(modes.frequency > 1e-6)
    low = osc[np.argsort(modes.frequency[osc])][:count]
    assert np.max(np.abs(modes.damping[low])) < 1e-6 * np.max(modes.frequency[low])  # undamped
    return modes.frequency[low]


def rayleigh_ritz_bending_torsion(L, EI, GJ, m, I_ea, d, nw=7, nt=7):
    """Coupled bending (w) - torsion (theta) cantilever, mass centre d aft of the elastic axis.

    T = 1/2 int m w'^2 - 2 m d w' theta' + I_ea theta'^2, U = 1/2 int EI w''^2 + GJ theta'^2;
    w = sum a_i (y/L)^(i+1), theta = sum b_j sin((2j-1) pi y / (2L)).
    """
    xg, wg = np.polynomial.legendre.leggauss(40)
    y = 0.5 * L * (xg + 1)
    wq = 0.5 * L * wg
    e = y / L
    W = np.array([e ** (i + 2) for i in range(nw)])
    W2 = np.array([(i + 2) * (i + 1) * e ** i / L**2 for i in range(nw)])
    k = (2 * np.arange(1, nt + 1) - 1) * np.pi / (2 * L)
    Th = np.sin(np.outer(k, y))
    Th1 = k[:, None] * np.cos(np.outer(k, y))
    integ = lambda A, B: (A * wq) @ B.T
    M = np.block([[m * integ(W, W), -m * d * integ(W, Th)], [-m * d * integ(Th, W), I_ea * integ(Th, Th)]])
    K = np.block([[EI * integ(W2, W2), np.zeros((nw, nt))], [np.zeros((nt, nw)), GJ * integ(Th1, Th1)]])
    return np.sqrt(np.sort(sla.eigvalsh(K, M)))


def test_goland_in_vacuo_vs_rayleigh_ritz_and_closed_forms():
    w = beam_frequencies(goland.beam_params(21))
    d = (goland.MASS_CENTRE - goland.ELASTIC_AXIS) * goland.CHORD
    ref = rayleigh_ritz_bending_torsion(goland.SEMI_SPAN, goland.EI_FLAP, goland.GJ, goland.MASS,
                                        goland.INERTIA, d)
    # first bending, first torsion, second bending (coupled); the in-plane modes are far above
    np.testing.assert_allclose(w[:3], ref[:3], rtol=0.01)
    # uncoupled limits bracket the coupled pair (coupling pushes them apart)
    L = goland.SEMI_SPAN
    bend = 1.8751**2 * np.sqrt(goland.EI_FLAP / (goland.MASS * L**4))
    tors = np.pi / 2 * np.sqrt(goland.GJ / (goland.INERTIA * L**2))
    assert w[0] < bend and w[1] > tors


def exact_bending_torsion_matrix(w, L, EI, GJ, m, I_ea, d):
    """Boundary-condition matrix of the exact coupled bending-torsion cantilever at frequency w.

    EI W'''' - m w^2 W + m d w^2 T = 0 and -GJ T'' - I_ea w^2 T + m d w^2 W = 0 (mass centre d aft
    of the elastic axis, W up, T nose up); W, T ~ exp(s y) with
    -EI GJ s^6 - EI I_ea w^2 s^4 + m GJ w^2 s^2 + (m I_ea - m^2 d^2) w^4 = 0 and
    T / W = -(EI s^4 - m w^2) / (m d w^2); clamped root W = W' = T = 0, free tip W'' = W''' = T' = 0.
    Columns scaled to unit norm (the exponentials span many decades).
    """
    z = np.roots([-EI * GJ, -EI * I_ea * w**2, m * GJ * w**2, (m * I_ea - (m * d) ** 2) * w**4]).astype(complex)
    s = np.concatenate([np.sqrt(z), -np.sqrt(z)])
    beta = -(EI * s**4 - m * w**2) / (m * d * w**2)
    e = np.exp(s * L)
    M = np.array([np.ones(6), s, beta, s**2 * e, s**3 * e, beta * s * e])
    return M / np.linalg.norm(M, axis=0)


def exact_bending_torsion_frequencies(L, EI, GJ, m, I_ea, d, w_max, count):
    """The first ``count`` zeros (rad/s) of the smallest singular value of the BC matrix."""
    def smin(w):
        return np.linalg.svd(exact_bending_torsion_matrix(w, L, EI, GJ, m, I_ea, d), compute_uv=False)[-1]

    ws = np.linspace(0.02 * w_max, w_max, 1500)
    vals = np.array([smin(w) for w in ws])
    out = []
    for i in np.flatnonzero((vals[1:-1] < vals[:-2]) & (vals[1:-1] < vals[2:])) + 1:
        r = sopt.minimize_scalar(smin, bracket=(ws[i - 1], ws[i], ws[i + 1]), tol=1e-12)
        assert r.fun < 1e-8                        # a true zero, not a shallow dip
        out.append(r.x)
    return np.array(out[:count])


def test_goland_in_vacuo_vs_exact_transcendental_solution():
    d = (goland.MASS_CENTRE - goland.ELASTIC_AXIS) * goland.CHORD
    exact = exact_bending_torsion_frequencies(goland.SEMI_SPAN, goland.EI_FLAP, goland.GJ, goland.MASS,
                                              goland.INERTIA, d, 300.0, 3)
    assert exact.size == 3
    # the case's quoted exact values (48.16 / 95.72 / 243.8 rad/s = 7.66 / 15.23 / 38.80 Hz)
    np.testing.assert_allclose(exact, goland.EXACT_FREQUENCIES_RAD_S, rtol=1e-3)
    w = beam_frequencies(goland.beam_params(21))
    np.testing.assert_allclose(w[:3], exact, rtol=0.01)


def test_goland_zero_offset_is_uncoupled_closed_form():
    p = goland.beam_params(21)
    p["mass_center"][:] = 0.0
    p["inertia_per_length"][:, 1, 1] = goland.INERTIA
    w = beam_frequencies(p)
    L = goland.SEMI_SPAN
    bend = 1.8751**2 * np.sqrt(goland.EI_FLAP / (goland.MASS * L**4))
    tors = np.pi / 2 * np.sqrt(goland.GJ / (goland.INERTIA * L**2))
    assert w[0] == pytest.approx(bend, rel=0.01)
    assert np.min(np.abs(w / tors - 1)) < 0.01


def test_hale_in_vacuo_vs_published_and_closed_forms():
    w = beam_frequencies(hale.beam_params(21))
    L = hale.SEMI_SPAN
    flap = 1.8751**2 * np.sqrt(hale.EI_FLAP / (hale.MASS * L**4))
    flap2 = 4.6941**2 * np.sqrt(hale.EI_FLAP / (hale.MASS * L**4))
    tors = np.pi / 2 * np.sqrt(hale.GJ / (hale.INERTIA * L**2))
    lag = 1.8751**2 * np.sqrt(hale.EI_LAG / (hale.MASS * L**4))
    np.testing.assert_allclose(w[:4], [flap, flap2, tors, lag], rtol=0.01)
    np.testing.assert_allclose(w[:4], hale.PUBLISHED["natural_frequencies_rad_s"], rtol=0.01)


def test_case_input_errors():
    with pytest.raises(ValueError, match="num_nodes"):
        hale.beam_params(2)
    with pytest.raises(ValueError, match="inertia_axis"):
        goland.beam_params(5, inertia_axis="qc")
