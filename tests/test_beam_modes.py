"""Small-vibration modes of the beam residual linearised at the jig: (dR/dx + lambda dR/dxdot) v = 0.

Independent of the time integrator: checks the mass, rotary inertia and kinematic rows of the
residual against closed-form cantilever frequencies.
"""

import numpy as np
import pytest
import scipy.linalg as sla

from wingmdao.beam.residual import forcing_specs, jig_state
from wingmdao.beam.static import BeamModel, beam_forcing, beam_parameters, straight_beam
from wingmdao.timemarch.system import pack

L, EI, MU = 10.0, 2.0e6, 20.0


def frequencies(model):
    n = model.num_nodes
    x = jig_state(model.params).ravel()
    q = pack(forcing_specs(n), beam_forcing(n))
    A, B = (m.toarray() for m in model.system.jac_state(x, np.zeros_like(x), model.p, q))
    lam = sla.eigvals(A, -B)
    lam = lam[np.isfinite(lam)]
    lam = lam[np.argsort(np.abs(lam))][:40]
    assert np.max(np.abs(lam.real)) < 1e-6 * np.max(np.abs(lam))  # undamped: purely imaginary
    return np.unique(np.round(np.abs(lam.imag[lam.imag > 0]), 9))


def test_bending_and_torsion_frequencies():
    n = 41
    GJ, i_ss = 1.5e6, 0.4
    r0, th0 = straight_beam(n, L)
    model = BeamModel(beam_parameters(r0, th0, EI_cc=EI, GJ=GJ, EI_nn=9 * EI, EA=1e11, mass_per_length=MU,
                                      inertia_per_length=np.diag([1e-9, i_ss, 1e-9])))
    w = frequencies(model)
    bending = 1.8751**2 * np.sqrt(EI / (MU * L**4))       # first flapwise (EI_cc)
    inplane = 1.8751**2 * np.sqrt(9 * EI / (MU * L**4))   # first in-plane (EI_nn)
    torsion = np.pi / 2 * np.sqrt(GJ / (i_ss * L**2))     # first torsion
    for ref in (bending, inplane, torsion):
        assert np.min(np.abs(w / ref - 1.0)) < 5e-3
    assert w[0] == pytest.approx(bending, rel=5e-3)
