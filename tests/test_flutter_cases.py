"""In vacuo natural frequencies of the Goland and HALE wings through wingmdao.stability.

References: the closed forms of a uniform cantilever (bending 1.8751^2 sqrt(EI / (m L^4)),
torsion pi/2 sqrt(GJ / (I L^2))), a Rayleigh-Ritz solution of the coupled bending-torsion
cantilever written here (polynomial bending and sine torsion shapes; M. Goland, "The flutter of a
uniform cantilever wing", J. Appl. Mech. 12(4), 1945, solves the same equations exactly) and the
published HALE frequencies (M. J. Patil, D. H. Hodges, C. E. S. Cesnik, J. Aircraft 38(1), 2001).
"""

import numpy as np
import pytest
import scipy.linalg as sla

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
