"""Small-vibration modes of the beam about a state (the jig by default).

The residual R(x, xdot) linearised at a static state x0 gives (A + lambda B) v = 0 with
A = dR/dx, B = dR/dxdot; the undamped natural frequencies are ``|Im lambda| / (2 pi)``. Used to set
structural damping at a reference frequency (:class:`~wingmdao.beam.residual.StrainRateDamping`)
and to report the first bending mode.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla


def natural_frequencies(system, p, q, x0=None, count: int = 6, max_abs: float = 1e6) -> np.ndarray:
    """Lowest ``count`` natural frequencies (Hz, ascending) of ``system`` linearised at ``x0``.

    ``p``, ``q``: packed parameter and forcing vectors; ``x0`` defaults to the system's initial
    guess (the jig shape for the beam). Dense generalised eigenproblem: fine for the beam sizes
    of sizing problems (18 n unknowns, n <= ~100). Eigenvalues with ``|lambda|`` of ``max_abs``
    (1/s) or more are the pencil's infinite ones (constraint rows: clamps, joints), computed as
    large finite numbers, and are dropped first, as :func:`wingmdao.stability.eigen.eigenmodes` does.
    """
    if count < 1:
        raise ValueError(f"count must be >= 1, got {count}")
    p = np.asarray(p, dtype=float)
    q = np.asarray(q, dtype=float)
    x = np.asarray(system.initial_guess(p, q) if x0 is None else x0, dtype=float).ravel()
    A, B = (m.toarray() for m in system.jac_state(x, np.zeros_like(x), p, q))
    lam = sla.eigvals(A, -B)
    lam = lam[np.isfinite(lam) & (np.abs(lam) < max_abs)]
    lam = lam[lam.imag > 1e-9 * np.max(np.abs(lam), initial=1.0)]
    if lam.size == 0:
        raise ValueError("no oscillatory modes: is mass_per_length zero?")
    freqs = np.sort(np.abs(lam)) / (2 * np.pi)
    return freqs[:count]
