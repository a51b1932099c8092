"""Oscillatory increment of the subsonic doublet-lattice influence coefficients, all reduced
frequencies in one call (numpy, no OpenMDAO).

The formulas are those of PanelAero's ``DLM.calc_Ajj`` with ``method="quartic"`` (DLR, BSD-3;
:mod:`wingmdao.aero.dlm` used it, and the tests check this module against it): the incremental
kernel ``K - K_0`` of Landahl's form (Rodden, Giesing & Kalman, "Refinement of the nonplanar
aspects of the subsonic doublet-lattice lifting surface method", J. Aircraft 9(1), 1972, 69-73,
eqs. 4-16, 27b, 36b), its integrals ``I_1``, ``I_2`` by Desmarais's 12-term exponential fit
(ibid. appendix, eqs. A.1-A.9), and the quartic approximation of the kernel across each doublet
line, integrated in closed form (Rodden, Taylor & McIntosh, "Further refinement of the subsonic
doublet-lattice method", J. Aircraft 35(5), 1998, 720-727, eqs. 15-34).

What is faster than PanelAero's loop over reduced frequencies:

* everything that does not depend on ``k`` (geometry, the kernel's ``r_1``, ``R``, ``u_1``, the
  steady kernel ``K_0``, the fit's 12 exponentials ``exp(-c_n u_1)``, the quadrature weights of
  the quartic) is computed once; per ``k`` only the fit's rational terms and the phases remain,
  in real arithmetic;
* the planar part's quadrature is one weighted sum of the five kernel values per pair;
* the nonplanar part (and its second kernel ``K_2``) only on the pairs that are not coplanar
  (``|z| / e > 0.001``; none on a flat wing);
* ``rows``: the receiving panels only (for a mirror-symmetric wing, those of one half).
"""

from __future__ import annotations

import numpy as np

__all__ = ["oscillatory_aic"]

#: Desmarais's fit of 1 - u / sqrt(1 + u^2) = sum a_n exp(-c_n u), c_n = 2^n b (as PanelAero's)
_A = np.array([0.000319759140, -0.000055461471, 0.002726074362, 0.005749551566, 0.031455895072,
               0.106031126212, 0.406838011567, 0.798112357155, -0.417749229098, 0.077480713894,
               -0.012677284771, 0.001787032960])
_C = 2.0 ** np.arange(1, 13) * 0.009054814793
_C2 = _C ** 2
#: |z| / e at or below which a pair is coplanar (Nastran's, as PanelAero's)
_PLANAR = 0.001
#: spanwise stations of the quartic: -e, -e/2, 0, e/2, e
_STATIONS = (-1.0, -0.5, 0.0, 0.5, 1.0)


class _Kernel:
    """The k-independent part of the incremental kernel at one spanwise station of every pair
    (flat arrays); :meth:`value` the kernel ``P_1`` (or ``P_2``) at one ``omega / V``."""

    def __init__(self, xbar, ybar, zbar, gamma_sr, tan_sweep, eta, mach, second):
        beta2 = 1.0 - mach ** 2
        with np.errstate(all="ignore"):
            r1 = np.sqrt((ybar - eta) ** 2 + zbar ** 2)
            xp = xbar - eta * tan_sweep
            R = np.sqrt(xp ** 2 + beta2 * r1 ** 2)
            u1 = (mach * R - xp) / (beta2 * r1)
            u = np.abs(u1)
            one_u2 = 1.0 + u ** 2
            sq = np.sqrt(one_u2)
            self.base = 1.0 - u / sq
            self.exps = _A[:, None] * np.exp(-_C[:, None] * u[None, :])
            if second:
                self.g1 = (mach ** 2) * r1 ** 2 / R ** 2 / sq
                self.g2 = mach * r1 * (one_u2 * beta2 * r1 ** 2 / R ** 2 + 2.0 + mach * r1 * u1 / R) / R / one_u2 ** 1.5
                self.w3 = u / one_u2 ** 1.5
                self.steady = 2.0 + xp * (2.0 + beta2 * r1 ** 2 / R ** 2) / R
                self.T = zbar * (zbar * np.cos(gamma_sr) + (ybar - eta) * np.sin(gamma_sr))
            else:
                self.g1 = mach * r1 / R / sq
                self.steady = -1.0 - xp / R
                self.T = np.cos(gamma_sr)
        self.second = second
        self.r1, self.xp, self.u, self.u1 = r1, xp, u, u1
        self.neg = u1 < 0.0
        self.sign = np.where(self.neg, -1.0, 1.0)
        zero = r1 == 0.0
        ahead = zero & (xbar >= 0.0)
        self.fix = np.flatnonzero(zero)                       # r1 = 0: K from its limit
        self.fix_value = np.where(ahead[self.fix], 4.0 if second else -2.0, 0.0)

    def value(self, k):
        """``P_1`` (first kernel) or ``P_2`` (second) of every pair at ``omega / V = k`` (1/m)."""
        k1 = k * self.r1
        k1s = k1 * k1
        n = k1.size
        S0, S1, Z0, inv, t = (np.zeros(n) for _ in range(5))
        if self.second:
            S2, S3, Z2, t2, d = (np.zeros(n) for _ in range(5))
        with np.errstate(all="ignore"):
            for a, c, c2, E in zip(_A, _C, _C2, self.exps):     # Desmarais's 12 terms, real arithmetic
                np.add(k1s, c2, out=inv)
                np.reciprocal(inv, out=inv)
                np.multiply(E, inv, out=t)
                S0 += t
                t *= c
                S1 += t
                Z0 += a * inv
                if self.second:
                    np.multiply(E, inv, out=t2)
                    t2 *= inv
                    np.subtract(c2, k1s, out=d)
                    S2 += d * t2
                    S3 += c * t2
                    Z2 += a * d * inv * inv
            # I(|u|) = (re + i im) exp(-i k1 |u|) (Rodden 1972 eqs. A.1, A.6 with Desmarais's I_0, J_0)
            if self.second:
                re = 2.0 * self.base - self.w3 - k1s * S0 + k1s * (S2 + self.u * S1)
                im = k1 * self.u * self.base - k1 * S1 - k1s * k1 * (2.0 * S3 + self.u * S0)
                re, im = re / 3.0, im / 3.0
                re0 = (2.0 - k1s * Z0 + k1s * Z2) / 3.0              # Re I_2 at u = 0
            else:
                re = self.base - k1s * S0
                im = -k1 * S1
                re0 = 1.0 - k1s * Z0                                 # Re I_1 at u = 0
            ph = k1 * self.u
            cs, sn = np.cos(ph), np.sin(ph)
            Ire = re * cs + im * sn
            Iim = im * cs - re * sn
            Ire = np.where(self.neg, 2.0 * re0 - Ire, Ire)         # u < 0: eqs. A.5, A.9
            ejku = cs - 1j * (self.sign * sn)                      # exp(-i k1 u1)
            if self.second:
                K = 3.0 * (Ire + 1j * Iim) + ejku * (1j * k1 * self.g1 + self.g2)
            else:
                K = -(Ire + 1j * Iim) - ejku * self.g1
            K[self.fix] = self.fix_value
            return -(K * np.exp(-1j * k * self.xp) - self.steady) * self.T


def oscillatory_aic(control, inner, outer, chord, mach, omega_over_v, rows=None) -> np.ndarray:
    """Oscillatory increment of the doublet-lattice normalwash per unit pressure jump.

    The steady (vortex-lattice) part is not included: ``w / V = (A_0 + A(k)) dcp``, ``A_0`` the
    vortex lattice's (PanelAero's ``VLM.calc_Ajj``), ``A(k)`` this. Equal to PanelAero's
    ``DLM.calc_Ajj(aerogrid, Ma, k, method="quartic")`` at each ``k`` (rows ``rows``) to round-off.

    Parameters
    ----------
    control : array_like, shape (n, 3)
        Each panel's normalwash point (three-quarter chord, mid-span), m.
    inner, outer : array_like, shape (n, 3)
        The ends of each panel's doublet line (quarter chord), from the lower-y end ``inner``
        (PanelAero's ``P1``) to ``outer`` (``P3``), m.
    chord : array_like, shape (n,)
        Each panel's streamwise chord, m.
    mach : float
        Mach number, in [0, 1).
    omega_over_v : array_like, shape (nk,)
        Circular frequency over airspeed ``omega / V = k / b_ref`` (1/m), each >= 0; a zero gives
        a zero increment.
    rows : array_like of int, optional
        The receiving panels (rows of the result); default all.

    Returns
    -------
    numpy.ndarray, shape (nk, len(rows), n), complex
        ``A(k)[i, j]``: the normalwash ``w / V`` at receiving panel ``rows[i]`` of a unit pressure
        jump on panel ``j``.
    """
    control = np.asarray(control, dtype=float)
    inner = np.asarray(inner, dtype=float)
    outer = np.asarray(outer, dtype=float)
    chord = np.asarray(chord, dtype=float)
    kb = np.atleast_1d(np.asarray(omega_over_v, dtype=float))
    mach = float(mach)
    n = inner.shape[0]
    rows = np.arange(n) if rows is None else np.asarray(rows, dtype=int)
    out = np.zeros((kb.size, rows.size, n), dtype=complex)
    if not np.any(kb > 0.0):
        return out
    mid = 0.5 * (inner + outer)
    span = outer - inner
    e = np.abs(0.5 * np.sqrt(span[:, 2] ** 2 + span[:, 1] ** 2))           # semi-width per sender
    sin_g, cos_g, tan_sweep = span[:, 2] / (2.0 * e), span[:, 1] / (2.0 * e), span[:, 0] / (2.0 * e)
    gamma = np.arcsin(sin_g)
    shape = (rows.size, n)
    xsr = control[rows, 0][:, None] - mid[None, :, 0]
    ysr = control[rows, 1][:, None] - mid[None, :, 1]
    zsr = control[rows, 2][:, None] - mid[None, :, 2]
    gamma_sr = gamma[None, :] - gamma[rows][:, None]
    ybar = ysr * cos_g + zsr * sin_g
    zbar = zsr * cos_g - ysr * sin_g
    E = np.broadcast_to(e, shape)
    tan_l = np.broadcast_to(tan_sweep, shape)
    C = np.broadcast_to(chord, shape)
    e2, e3, e4 = E ** 2, E ** 3, E ** 4
    y2, z2 = ybar ** 2, zbar ** 2
    y4, z4 = y2 ** 2, z2 ** 2
    q = y2 + z2 - e2
    with np.errstate(all="ignore"):
        ratio = 2.0 * E * np.abs(zbar) / q
        L = np.log(((ybar - E) ** 2 + z2) / ((ybar + E) ** 2 + z2))
        planar = np.abs(zbar) / E <= _PLANAR
        ia = (np.abs(ratio) <= 0.3) & ~planar
        series = sum((-1.0) ** m / (2.0 * m - 1.0) * ratio ** (2.0 * m - 4.0) for m in range(2, 8))
        d1 = np.where(q == 0.0, 0.0, 1.0)
        d2 = np.where(q > 0.0, 0.0, np.where(q == 0.0, 0.5, 1.0))
        eps = np.where(planar, 2.0 * E / (y2 - e2),
                       np.where(ia, 4.0 * e4 / q ** 2 * series, e2 / z2 * (1.0 - np.arctan(ratio) / ratio)))
        F = np.where(planar, d1 * 2.0 * E / (y2 - e2),
                     d1 * 2.0 * E / q * (1.0 - eps * z2 / e2) + d2 * np.pi / np.abs(zbar))
        # the planar part (Rodden 1998 eq. 20) is linear in the five kernel values: weights W
        cA = (y2 - z2) * F + ybar * L + 2.0 * E
        cB = ybar * F + 0.5 * L
        cD = ybar * (y2 - 3.0 * z2) * F + 0.5 * (3.0 * y2 - z2) * L + 4.0 * E * ybar
        cE = (y4 - 6.0 * y2 * z2 + z4) * F + 2.0 * ybar * (y2 - z2) * L + 2.0 * E * (3.0 * y2 - z2 + e2 / 3.0)
        stencil_a = np.array([1.0, -16.0, 30.0, -16.0, 1.0]) * (-1.0 / 6.0)       # eq. 15 times e^2
        stencil_b = np.array([1.0, -8.0, 0.0, 8.0, -1.0]) / 6.0                   # eq. 16 times e
        stencil_d = np.array([1.0, -2.0, 0.0, 2.0, -1.0]) * (-2.0 / 3.0)           # eq. 18 times e^3
        stencil_e = np.array([1.0, -4.0, 6.0, -4.0, 1.0]) * (2.0 / 3.0)            # eq. 19 times e^4
        W = [C / (8.0 * np.pi) * (cA * stencil_a[s] / e2 + cB * stencil_b[s] / E + (F if s == 2 else 0.0)
                                  + cD * stencil_d[s] / e3 + cE * stencil_e[s] / e4) for s in range(5)]
    flat = (xsr.ravel(), ybar.ravel(), zbar.ravel(), gamma_sr.ravel(), tan_l.ravel())
    first = [_Kernel(*flat, f * E.ravel(), mach, second=False) for f in _STATIONS]
    W = [w.ravel() for w in W]
    nonplanar = np.flatnonzero(~planar.ravel())
    if nonplanar.size:
        sub = tuple(v[nonplanar] for v in flat)
        es = E.ravel()[nonplanar]
        second = [_Kernel(*sub, f * es, mach, second=True) for f in _STATIONS]
        g = {name: v.ravel()[nonplanar] for name, v in
             dict(e=E, e2=e2, e3=e3, e4=e4, y=ybar, y2=y2, y4=y4, z=zbar, z2=z2, z4=z4, L=L, F=F, eps=eps,
                  d1=d1, d2=d2, ratio=ratio, c=C).items()}
        with np.errstate(all="ignore"):
            ib = np.abs(1.0 / g["ratio"]) <= 0.1
    for i, k in enumerate(kb):
        if k == 0.0:
            continue
        P = [kern.value(k) for kern in first]
        D = W[0] * P[0]
        for s in range(1, 5):
            D += W[s] * P[s]
        if nonplanar.size:
            D[nonplanar] += _nonplanar(g, ib, [kern.value(k) for kern in second])
        out[i] = D.reshape(shape)
    return out


def _nonplanar(g, ib, P):
    """The nonplanar part of the pairs that are not coplanar (Rodden 1998 eqs. 28-34)."""
    Pm, Pmh, Ps, Pph, Pp = P
    e, e2, e3, e4 = g["e"], g["e2"], g["e3"], g["e4"]
    y, y2, y4, z2, z4, L, F = g["y"], g["y2"], g["y4"], g["z2"], g["z4"], g["L"], g["F"]
    A2 = -1.0 / (6.0 * e2) * (Pm - 16.0 * Pmh + 30.0 * Ps - 16.0 * Pph + Pp)
    B2 = 1.0 / (6.0 * e) * (Pm - 8.0 * Pmh + 8.0 * Pph - Pp)
    C2 = Ps
    D2 = -2.0 / (3.0 * e3) * (Pm - 2.0 * Pmh + 2.0 * Pph - Pp)
    E2 = 2.0 / (3.0 * e4) * (Pm - 4.0 * Pmh + 6.0 * Ps - 4.0 * Pph + Pp)
    common = (y2 + z2) * A2 + y * B2 + C2 + y * (y2 + 3.0 * z2) * D2 + (y4 + 6.0 * y2 * z2 - 3.0 * z4) * E2
    with np.errstate(all="ignore"):
        near = g["c"] / (16.0 * np.pi * z2) * (
            F * common
            + 1.0 / ((y + e) ** 2 + z2)
            * (((y2 + z2) * y + (y2 - z2) * e) * A2 + (y2 + z2 + y * e) * B2 + (y + e) * C2
               + (y4 - z4 + (y2 - 3.0 * z2) * y * e) * D2
               + ((y4 - 2.0 * y2 * z2 - 3.0 * z4) * y + (y4 - 6.0 * y2 * z2 + z4) * e) * E2)
            - 1.0 / ((y - e) ** 2 + z2)
            * (((y2 + z2) * y - (y2 - z2) * e) * A2 + (y2 + z2 - y * e) * B2 + (y - e) * C2
               + (y4 - z4 - (y2 - 3.0 * z2) * y * e) * D2
               + ((y4 - 2.0 * y2 * z2 - 3.0 * z4) * y - (y4 - 6.0 * y2 * z2 + z4) * e) * E2)
            + z2 * L * D2 + 4.0 * z2 * (e + y * L) * E2)
        d1, d2, eps, ratio, c = g["d1"], g["d2"], g["eps"], g["ratio"], g["c"]
        far = c * e / (8.0 * np.pi * (y2 + z2 - e2)) * (
            1.0 / (((y + e) ** 2 + z2) * ((y - e) ** 2 + z2))
            * (2.0 * (y2 + z2 + e2) * (e2 * A2 + C2) + 4.0 * y * e2 * B2
               + 2.0 * y * (y4 - 2.0 * e2 * y2 + 2.0 * y2 * z2 + 3.0 * e4 + 2.0 * e2 * z2 + z4) * D2
               + 2.0 * (3.0 * y ** 6 - 7.0 * e2 * y4 + 5.0 * y4 * z2 + 6.0 * e4 * y2 + 6.0 * e2 * y2 * z2
                        - 3.0 * e2 * z4 - g["z"] ** 6 + y2 * z4 - 2.0 * e4 * z2) * E2)
            - (d1 * eps + e2 / z2 * (1.0 - d1 - d2 * np.pi / ratio)) / e2 * common) \
            + c / (8.0 * np.pi) * (D2 / 2.0 * L + 2.0 * (e + y * L) * E2)
    return np.where(ib, near, far)
