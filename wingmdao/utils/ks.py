"""Kreisselmeier-Steinhauser (KS) aggregation, numerically: the one home of the formula.

    KS_rho(g) = m + ln( sum_k exp(rho (g_k - m)) ) / rho,      m = max_k g_k

(dissertation Eq. 4.44; G. Kreisselmeier and R. Steinhauser, "Systematic control design by
optimizing a vector performance index", IFAC Proc. 12(7), 1979). The max shift m keeps every
exponent <= 0, so large rho and large ``|g|`` cannot overflow; max g <= KS <= max g + ln(N) / rho.
The sum runs over every entry of ``g``, whatever its shape. Used by the OpenMDAO component
(:class:`wingmdao.components.ks.KSAggregate`) and the flutter-damping constraint
(:func:`wingmdao.stability.sensitivity.damping_constraint`).
"""

from __future__ import annotations

import numpy as np


def shifted_exp(g, rho_ks: float):
    """The terms shared by the KS value and its gradient, over all entries of ``g`` (flattened).

    Parameters
    ----------
    g : array_like
        Constraint values, any shape (all entries aggregated; the unit of ``g``).
    rho_ks : float
        KS aggregation parameter (1 / the unit of ``g``), > 0.

    Returns
    -------
    m : float
        ``max g``.
    w : ndarray
        ``w_k = exp(rho_KS (g_k - m))``, flattened.
    s : float
        ``sum_k w_k``.
    """
    g = np.asarray(g, dtype=float).ravel()
    m = np.max(g)
    w = np.exp(rho_ks * (g - m))
    return m, w, np.sum(w)


def ks_value(g, rho_ks: float) -> float:
    """KS aggregate of all entries of ``g``, max-shifted.

    Parameters
    ----------
    g : array_like
        Constraint values, any shape (all entries aggregated; the unit of ``g``).
    rho_ks : float
        KS aggregation parameter (1 / the unit of ``g``), > 0.

    Returns
    -------
    float
        KS value, between ``max g`` and ``max g + ln(N) / rho_ks`` (the unit of ``g``).
    """
    m, _, s = shifted_exp(g, rho_ks)
    return float(m + np.log(s) / rho_ks)


def ks_gradient(g, rho_ks: float) -> np.ndarray:
    """dKS/dg_k = exp(rho_KS (g_k - m)) / sum_j exp(rho_KS (g_j - m)): the softmax weights.

    Parameters
    ----------
    g : array_like
        Constraint values, any shape (all entries aggregated; the unit of ``g``).
    rho_ks : float
        KS aggregation parameter (1 / the unit of ``g``), > 0.

    Returns
    -------
    ndarray
        dKS/dg, flattened (dimensionless; the ratio of sums of Eq. 4.46-4.51, before the chain rule).
    """
    _, w, s = shifted_exp(g, rho_ks)
    return w / s


def ks_aggregate(g, rho_ks: float):
    """KS value and gradient of all entries of ``g`` (one exponential for both).

    Parameters
    ----------
    g : array_like
        Constraint values, any shape (all entries aggregated; the unit of ``g``).
    rho_ks : float
        KS aggregation parameter (1 / the unit of ``g``), > 0.

    Returns
    -------
    ks : float
        KS value (:func:`ks_value`).
    dks_dg : ndarray
        dKS/dg, flattened (:func:`ks_gradient`).
    """
    m, w, s = shifted_exp(g, rho_ks)
    return float(m + np.log(s) / rho_ks), w / s
