"""Eigenvalues of the linearised aeroelastic HALE wing against a BDF2 time march of the full
nonlinear coupled system (beam + Wagner/Kuessner strip theory, :func:`wingmdao.timemarch.bdf.march`)
started on the flutter eigenvector with a small amplitude, just below and just above the flutter
speed (0.97 and 1.03 x the published 32.21 m/s of Patil, Hodges & Cesnik, J. Aircraft 38(1), 2001).

A linear mode x(t) = Re(v e^{lambda t}) marched by BDF2,
(3 x[k+2] - 4 x[k+1] + x[k]) / (2 dt) = lambda x[k+2], grows by the root z of
(3 - 2 dt lambda) z^2 - 4 z + 1 = 0 per step: the march must reproduce that discrete image of the
eigenvalue, not lambda itself (they differ by about (omega dt)^2 / 3 = 7e-4 in frequency here).
The march's z comes from a fourth-order Prony (linear-prediction) fit of one sampled state, which
also absorbs the BDF1 start-up's spurious root; the samples of the start-up steps are skipped.
"""

import numpy as np
import pytest

from wingmdao.cases import hale
from wingmdao.stability import eigenmodes
from wingmdao.stability.cases import flutter_problem
from wingmdao.timemarch.bdf import march

pytestmark = pytest.mark.slow


def bdf2_image(lam, dt):
    """Continuous eigenvalue of the BDF2 amplification root z: log(z) / dt."""
    z = np.roots([3.0 - 2.0 * dt * lam, -4.0, 1.0])
    return np.log(z[np.argmax(np.abs(z))]) / dt


def prony_eigenvalue(h, dt, target, order=4):
    """Root nearest ``target`` of an order-``order`` linear-prediction fit of the samples h."""
    A = np.column_stack([h[order - 1 - i:h.size - 1 - i] for i in range(order)])
    c = np.linalg.lstsq(A, h[order:], rcond=None)[0]
    s = np.log(np.roots(np.r_[1.0, -c]).astype(complex)) / dt
    return s[np.argmin(np.abs(s - target))]


def test_bdf2_image_of_an_eigenvalue():
    """The image's frequency error is -(omega dt)^2 / 3 to leading order (BDF2 error constant)."""
    lam, dt = -0.01 + 20.0j, 1e-3
    assert bdf2_image(lam, dt).imag == pytest.approx(lam.imag * (1 - (20.0 * dt) ** 2 / 3), rel=1e-6)


@pytest.mark.parametrize("factor", [0.97, 1.03])
def test_hale_flutter_eigenvalue_vs_free_response(factor):
    prob = flutter_problem("hale", 11)
    V = factor * hale.PUBLISHED["flutter_speed_m_s"]
    p, q = prob.params_at(V)
    m = eigenmodes(prob.system, p, q, **prob.eig_options)
    sel = np.flatnonzero((m.frequency > 15.0) & (m.frequency < 30.0))   # the bending-torsion flutter mode
    j = sel[np.argmax(m.damping[sel])]
    lam, v = m.eigenvalues[j], m.vectors[:, j]
    w = prob.beam_weights()
    v = v * np.exp(-1j * np.angle(v[np.argmax(np.abs(v) * w)]))   # fix the arbitrary phase
    dt = 2e-3
    t = np.arange(0.0, 4 * 2 * np.pi / abs(lam.imag), dt)
    x_init = m.x0 + 1e-4 * np.real(v) / np.max(np.abs(v[w > 0]))
    hist = march(prob.system, t, p, np.tile(q, (t.size, 1)), initial="state", x_init=x_init)
    X = hist.states.reshape(t.size, -1)
    k = int(np.argmax(np.abs(np.real(v)) * w))
    lam_dt = bdf2_image(lam, dt)
    lam_march = prony_eigenvalue(X[2:, k] - m.x0[k], dt, lam_dt)
    assert lam_march.imag == pytest.approx(lam_dt.imag, rel=1e-5)
    assert lam_march.real == pytest.approx(lam_dt.real, abs=1e-5 * abs(lam))
    assert np.sign(lam_march.real) == np.sign(lam.real) == (1 if factor > 1 else -1)
