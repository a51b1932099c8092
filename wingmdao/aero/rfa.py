"""Rational-function approximation of tabulated generalized aerodynamic forces (no OpenMDAO).

Roger's form (K. L. Roger, "Airplane math modeling methods for active control design", AGARD
CP-228, 1977): in the reduced Laplace variable ``p = s b_ref / V`` (``p = i k`` on the frequency
axis)

    Q(p) ~ A_0 + A_1 p + A_2 p^2 + sum_l A_(l+2) p / (p + gamma_l),

each matrix entry fitted independently by linear least squares over the tabulated k, real and
imaginary parts together, with ``A_0 = Q(0)`` exactly when k = 0 is tabulated (the static
aeroelastic loads of the state-space model are then those of the doublet lattice). The lag roots
``gamma_l > 0`` are chosen, not fitted (default: spread over the tabulated k, :func:`default_lags`).
In the time domain every lag root adds one state per mode,
``z_l' = -gamma_l (V / b_ref) z_l + q'``, a first-order filter whose pole ``-gamma_l V / b_ref``
is stable for every airspeed because ``gamma_l > 0`` (:func:`fit` refuses others).

Why Roger and not Karpel's minimum-state form (M. Karpel, "Design for active flutter suppression
and gust alleviation using state-space aeroelastic modeling", J. Aircraft 19(3), 1982, 221-227):
the minimum-state fit ``Q = A_0 + A_1 p + A_2 p^2 + D (p I - R)^-1 E p`` needs fewer states but an
iterative nonlinear fit of ``D`` and ``E`` whose convergence and error depend on the starting
guess; Roger's fit is one linear least-squares solve per entry, its error is the smallest of the
two for a given set of lag roots, and with a modal basis of a few modes the lag states it adds
(lags x modes, 36 for 6 lags and 6 modes) cost nothing in the eigen-analysis or a time march.
The gust column is fitted in the same form with its own lag states (driven by ``w_g / V``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wingmdao.aero.dlm import GeneralizedForces

#: default number of lag roots
N_LAGS = 6


@dataclass(frozen=True, eq=False)
class RogerApproximation:
    """Roger's approximation of generalized forces (module docstring).

    ``lags`` (L,) the lag roots gamma_l (> 0); ``A`` (3 + L, modes, modes) real: A_0, A_1, A_2,
    then one matrix per lag; ``gust`` (3 + L, modes) real: the same for the gust column;
    ``b_ref`` m; ``k`` the fitted reduced frequencies; ``error`` the fit error: max over k of
    ``||Q_fit(ik) - Q(ik)||_F / max_k ||Q(ik)||_F``; ``gust_error`` the same for the gust column;
    ``low_k_slope``: the fit also matches the slope at k = 0 (:func:`fit`).

    Parameters
    ----------
    lags : numpy.ndarray
        Lag roots gamma_l (> 0), shape (L,).
    A : numpy.ndarray
        Real coefficient matrices A_0, A_1, A_2 and one per lag, shape (3 + L, modes, modes).
    gust : numpy.ndarray
        The same for the gust column, shape (3 + L, modes).
    b_ref : float
        Reference semi-chord (m).
    k : numpy.ndarray
        The fitted reduced frequencies.
    error : float
        Fit error of the generalized forces (relative Frobenius norm).
    gust_error : float
        Fit error of the gust column.
    low_k_slope : bool
        Whether the fit matches the slope at k = 0.
    """

    lags: np.ndarray
    A: np.ndarray
    gust: np.ndarray
    b_ref: float
    k: np.ndarray
    error: float
    gust_error: float
    low_k_slope: bool = False

    def __call__(self, k):
        """``(Q (modes, modes), gust (modes,))`` of the approximation at reduced frequency ``k``."""
        w = _basis(np.atleast_1d(float(k)), self.lags)[0]
        return np.tensordot(w, self.A, axes=1), np.tensordot(w, self.gust, axes=1)

    @property
    def n_lags(self) -> int:
        return int(self.lags.size)


def default_lags(k, n_lags: int = N_LAGS) -> np.ndarray:
    """Lag roots spread over the tabulated reduced frequencies: ``gamma_l = 1.7 k_max (l / (L + 1))^2``
    (the spacing of Tiffany & Adams, "Nonlinear programming extensions to rational function
    approximation methods for unsteady aerodynamic forces", NASA TP-2776, 1988, Sec. 2).

    Parameters
    ----------
    k : array_like
        Tabulated reduced frequencies.
    n_lags : int
        Number of lag roots L.

    Returns
    -------
    numpy.ndarray
        Lag roots, shape (L,).
    """
    kmax = float(np.max(k))
    if not kmax > 0.0:
        raise ValueError(f"the reduced frequencies must include k > 0 to choose lag roots, got {np.asarray(k).tolist()}")
    n = int(n_lags)
    return 1.7 * kmax * (np.arange(1, n + 1) / (n + 1.0)) ** 2


def _basis(k, lags):
    """(nk, 3 + L) complex: 1, ik, (ik)^2, ik / (ik + gamma_l)."""
    p = 1j * np.asarray(k, dtype=float)[:, None]
    return np.column_stack([np.ones(p.shape[0]), p[:, 0], p[:, 0] ** 2, (p / (p + lags[None, :]))])


def _fit_entries(k, values, lags, low_k_slope=False):
    """Least-squares coefficients (3 + L, entries) of ``values`` (nk, entries) complex; A_0 pinned
    to the k = 0 value when tabulated; with ``low_k_slope`` also ``A_1 + sum_l A_(l+2) / gamma_l``
    (the approximation's ``dQ/dp`` at p = 0) pinned to ``Im Q(k_1) / k_1``, k_1 the smallest
    tabulated k > 0 (the quasi-steady damping of a slow motion)."""
    W = _basis(k, lags)
    pinned = np.isclose(k, 0.0)
    if np.any(pinned):
        a0 = values[np.flatnonzero(pinned)[0]].real
        rhs = values - a0[None, :]
        cols = W[:, 1:]
    else:
        a0, rhs, cols = None, values, W
    if low_k_slope:
        if a0 is None:
            raise ValueError("low_k_slope needs k = 0 among the reduced frequencies")
        k1 = np.flatnonzero(~pinned)[np.argmin(k[~pinned])]
        s = values[k1].imag / k[k1]
        p = 1j * np.asarray(k, dtype=float)[:, None]
        # A_1 = s - sum_l A_(l+2) / gamma_l eliminated: unknowns A_2 and the lag terms
        rhs = rhs - p * s[None, :]
        cols = np.column_stack([cols[:, 1], cols[:, 2:] - p / lags[None, :]])
    Ar = np.vstack([cols.real, cols.imag])
    br = np.vstack([rhs.real, rhs.imag])
    coef, *_ = np.linalg.lstsq(Ar, br, rcond=None)
    if low_k_slope:
        a1 = s - np.sum(coef[1:] / lags[:, None], axis=0)
        coef = np.vstack([a1[None, :], coef])
    return coef if a0 is None else np.vstack([a0[None, :], coef])


def fit(gaf: GeneralizedForces, lags=None, *, n_lags: int = N_LAGS, low_k_slope: bool = False) -> RogerApproximation:
    """Roger's approximation of ``gaf`` (:class:`wingmdao.aero.dlm.GeneralizedForces`) with the lag
    roots ``lags`` (default :func:`default_lags`). ``low_k_slope``: each entry also matches the
    slope ``dQ/dp`` at p = 0 of the data (:func:`_fit_entries`; the rigid-body modes of a free
    aircraft, whose slow motion the unweighted fit's error at small k would mis-damp). ValueError: a
    lag root <= 0 (an unstable or static lag state), repeated roots, or fewer tabulated k than
    coefficients to fit.

    Parameters
    ----------
    gaf : wingmdao.aero.dlm.GeneralizedForces
        Tabulated generalized forces.
    lags : array_like or None
        Lag roots (> 0, distinct); None: :func:`default_lags`.
    n_lags : int
        Number of lag roots when ``lags`` is None.
    low_k_slope : bool
        Also match the slope at p = 0.

    Returns
    -------
    RogerApproximation
        The approximation.
    """
    k = np.asarray(gaf.k, dtype=float)
    lags = default_lags(k, n_lags) if lags is None else np.atleast_1d(np.asarray(lags, dtype=float))
    if lags.size and not np.all(np.isfinite(lags) & (lags > 0.0)):
        raise ValueError(f"lag roots must be > 0 (stable lag states, poles -gamma V / b_ref), got {lags.tolist()}")
    if np.unique(lags).size != lags.size:
        raise ValueError(f"lag roots must be distinct, got {lags.tolist()}")
    unknowns = 2 + lags.size            # A_1, A_2, lags (A_0 from k = 0 or fitted with them)
    if 2 * k.size < unknowns + 1:
        raise ValueError(f"{k.size} reduced frequencies cannot fit {unknowns + 1} coefficients per entry; "
                         f"tabulate at least {(unknowns + 2) // 2} or use fewer lags")
    nm = gaf.Q.shape[1]
    A = _fit_entries(k, gaf.Q.reshape(k.size, -1), lags, low_k_slope).reshape(-1, nm, nm)
    G = _fit_entries(k, gaf.gust, lags, low_k_slope)
    W = _basis(k, lags)
    err_q = np.linalg.norm(np.tensordot(W, A, axes=1) - gaf.Q, axis=(1, 2)).max() / np.linalg.norm(gaf.Q, axis=(1, 2)).max()
    err_g = np.linalg.norm(W @ G - gaf.gust, axis=1).max() / np.linalg.norm(gaf.gust, axis=1).max()
    return RogerApproximation(lags=lags, A=A, gust=G, b_ref=gaf.b_ref, k=k, error=float(err_q), gust_error=float(err_g),
                              low_k_slope=bool(low_k_slope))


def pole_real_parts(rfa: RogerApproximation, airspeed) -> np.ndarray:
    """Real parts (1/s) of the lag states' poles ``-gamma_l V / b_ref`` at ``airspeed`` (m/s): all
    negative, so the lag states are stable on their own.

    Parameters
    ----------
    rfa : RogerApproximation
        The approximation.
    airspeed : float or array_like
        Airspeed (m/s).

    Returns
    -------
    numpy.ndarray
        Real parts (1/s).
    """
    return -rfa.lags * float(airspeed) / rfa.b_ref


def fit_columns(rfa: RogerApproximation, k, values) -> tuple[np.ndarray, float]:
    """Roger coefficients (3 + L, ...) of further tabulated outputs ``values`` (nk, ...) complex
    (station loads, say) with the lag roots of ``rfa``, so that they are recovered in the time
    domain from the same lag states; and their fit error (max over k of the Frobenius norm of the
    misfit over the largest tabulated norm). The slope at k = 0 is matched when ``rfa`` matches it.

    Parameters
    ----------
    rfa : RogerApproximation
        The approximation whose lag roots are used.
    k : array_like
        Reduced frequencies of ``values``, shape (nk,).
    values : array_like
        Complex tabulated outputs, shape (nk, ...).

    Returns
    -------
    numpy.ndarray
        Coefficients, shape (3 + L, ...).
    float
        The fit error.
    """
    k = np.asarray(k, dtype=float)
    v = np.asarray(values, dtype=complex)
    flat = v.reshape(k.size, -1)
    coef = _fit_entries(k, flat, rfa.lags, rfa.low_k_slope)
    misfit = _basis(k, rfa.lags) @ coef - flat
    scale = np.linalg.norm(flat, axis=1).max()
    err = float(np.linalg.norm(misfit, axis=1).max() / scale) if scale > 0 else 0.0
    return coef.reshape((coef.shape[0],) + v.shape[1:]), err
