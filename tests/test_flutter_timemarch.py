"""Eigenvalues of the linearised aeroelastic HALE wing against a BDF2 time march of the full
nonlinear coupled system (beam + Wagner/Kuessner strip theory, :func:`wingmdao.timemarch.bdf.march`)
started on the flutter eigenvector with a small amplitude, just below and just above the flutter
speed (0.97 and 1.03 x the published 32.21 m/s of Patil, Hodges & Cesnik, J. Aircraft 38(1), 2001).

The decay / growth rate and frequency of the free response come from a Prony fit of one sampled
state, h[k+2] = 2 Re z h[k+1] - |z|^2 h[k], z = exp(lambda dt). BDF2 adds a damping error of about
-omega^4 dt^3 / 4 (5e-4 1/s here) and a relative frequency error of order (omega dt)^2 / 12.
"""

import numpy as np
import pytest

from wingmdao.cases import hale
from wingmdao.stability import eigenmodes
from wingmdao.stability.cases import flutter_problem
from wingmdao.timemarch.bdf import march

pytestmark = pytest.mark.slow


def prony_eigenvalue(h, dt):
    A = np.column_stack([h[1:-1], h[:-2]])
    c1, c2 = np.linalg.lstsq(A, h[2:], rcond=None)[0]
    z = np.roots([1.0, -c1, -c2])
    return np.log(z[np.argmax(z.imag)]) / dt


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
    dt = 2e-3
    t = np.arange(0.0, 4 * 2 * np.pi / abs(lam.imag), dt)
    x_init = m.x0 + 1e-4 * np.real(v) / np.max(np.abs(v[w > 0]))
    hist = march(prob.system, t, p, np.tile(q, (t.size, 1)), initial="state", x_init=x_init)
    X = hist.states.reshape(t.size, -1)
    k = int(np.argmax(np.abs(np.real(v)) * w))
    lam_march = prony_eigenvalue(X[:, k] - m.x0[k], dt)
    assert lam_march.imag == pytest.approx(lam.imag, rel=2e-3)
    assert lam_march.real == pytest.approx(lam.real, abs=1e-3 * abs(lam))
    assert np.sign(lam_march.real) == np.sign(lam.real) == (1 if factor > 1 else -1)
