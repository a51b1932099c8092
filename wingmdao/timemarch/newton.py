"""Newton's method with a backtracking line search and sparse LU (Eq. 3.6-3.7).

A solve that fails raises :class:`openmdao.api.AnalysisError` with the label of the solve
(e.g. the time step), the residual norm and the worst equation, so that an optimizer can
back off instead of receiving NaNs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from openmdao.core.analysis_error import AnalysisError
from scipy.linalg.lapack import dgetrf, dgetrs
import scipy.sparse as sp
import scipy.sparse.linalg as spla

#: Systems up to this size are factored densely (LAPACK), larger ones with SuperLU.
DENSE_MAX = 40
#: SuperLU column ordering. Node-major beam and chain systems are already banded: the natural
#: order halves the factorization time against COLAMD (0.33 vs 0.67 ms, 20-node beam) with
#: less fill. Use "COLAMD" for systems whose unknowns are not ordered by locality.
PERMC_SPEC = "NATURAL"


class _DenseLU:
    """Dense LU with the ``solve(b, trans)`` interface of SuperLU (small systems)."""

    def __init__(self, mat):
        self.lu, self.piv, info = dgetrf(mat)
        if info > 0 or not np.all(np.isfinite(self.lu)):
            raise RuntimeError("Factor is exactly singular")

    def solve(self, b, trans="N"):
        x, _ = dgetrs(self.lu, self.piv, b, trans=0 if trans == "N" else 1)
        return x


def factor(jac):
    """LU factors of a square matrix (sparse or dense ndarray) with ``.solve(b, trans='N'|'T')``.

    Dense LAPACK below :data:`DENSE_MAX` unknowns (less overhead), SuperLU above. Raises
    ``RuntimeError`` when the matrix is exactly singular.

    Parameters
    ----------
    jac : ndarray or scipy.sparse matrix, shape (n, n)
        The square matrix.

    Returns
    -------
    object
        Factors with ``solve(b, trans="N")`` (dense LAPACK LU or ``scipy.sparse.linalg.SuperLU``).
    """
    if isinstance(jac, np.ndarray):
        return _DenseLU(jac)
    if jac.shape[0] <= DENSE_MAX:
        return _DenseLU(jac.toarray())
    jac = sp.csc_matrix(jac, copy=True)
    jac.eliminate_zeros()   # CasADi patterns are structural: many entries are zero (2.5x faster)
    return spla.splu(jac, permc_spec=PERMC_SPEC)


@dataclass
class NewtonInfo:
    """Convergence record of :func:`newton_solve`.

    Parameters
    ----------
    iterations : int
        Newton iterations taken.
    residual_norm : float
        Final ``max|R|``.
    converged : bool
        Whether the solve converged.
    """
    iterations: int
    residual_norm: float
    converged: bool


def _factor(jac, label):
    try:
        return factor(jac)
    except RuntimeError as exc:  # exactly singular
        raise AnalysisError(f"{label}: singular Jacobian ({exc})") from exc


def newton_solve(residual, jacobian, x0, *, atol=1e-9, rtol=1e-12, xtol=1e-12, max_iter=30,
                 max_backtracks=10, label="Newton solve", describe=None):
    """Solve ``residual(x) = 0`` from ``x0``.

    ``jacobian(x)`` returns the sparse Jacobian. Converged when ``max|R| <= atol``, or when
    a full Newton step is at most ``xtol (1 + max|x|)`` (the step is then applied: with an exact
    Jacobian the remaining error is of the order of its square), or when the relative Newton
    step is below ``xtol`` and ``max|R| <= rtol * max|R(x0)|``-ish progress has been made.
    Residuals of mixed units (forces, curvatures) make ``atol`` alone unreliable: pass
    ``atol=0`` to converge on the step. ``describe(i)`` names equation ``i`` in error
    messages. Returns ``(x, NewtonInfo)``.

    Parameters
    ----------
    residual : callable
        ``residual(x) -> ndarray, shape (n,)``.
    jacobian : callable
        ``jacobian(x)`` returning the Jacobian (sparse or dense), shape (n, n).
    x0 : array_like, shape (n,)
        Initial guess (copied).
    atol : float
        Absolute tolerance on ``max|R|``.
    rtol : float
        Relative tolerance on ``max|R|`` against its initial value (with a small step).
    xtol : float
        Tolerance on the Newton step relative to ``1 + max|x|``.
    max_iter : int
        Most Newton iterations.
    max_backtracks : int
        Most halvings of the step in the line search.
    label : str
        Name of the solve in error messages.
    describe : callable, optional
        ``describe(i) -> str`` names equation ``i`` in error messages.

    Returns
    -------
    x : ndarray, shape (n,)
        The solution.
    info : NewtonInfo
        Iterations, final residual norm and convergence flag.

    Raises
    ------
    openmdao.api.AnalysisError
        When the residual or step is not finite, the Jacobian is singular, or the solve does
        not converge.
    """
    x = np.array(x0, dtype=float, copy=True)
    r = residual(x)
    norm0 = norm = float(np.max(np.abs(r))) if r.size else 0.0
    if not np.isfinite(norm):
        raise AnalysisError(f"{label}: residual is not finite at the initial guess")
    for it in range(1, max_iter + 1):
        if norm <= atol:
            return x, NewtonInfo(it - 1, norm, True)
        lu = _factor(jacobian(x), label)
        dx = -lu.solve(r)
        if not np.all(np.isfinite(dx)):
            raise AnalysisError(f"{label}: Newton step is not finite (ill-conditioned Jacobian)")
        dx_max, scale = float(np.max(np.abs(dx))), 1.0 + float(np.max(np.abs(x)))
        if dx_max <= xtol * scale:
            x = x + dx
            r = residual(x)
            return x, NewtonInfo(it, float(np.max(np.abs(r))), True)
        step, merit = 1.0, float(r @ r)
        for _ in range(max_backtracks + 1):
            x_try = x + step * dx
            r_try = residual(x_try)
            merit_try = float(r_try @ r_try)
            if np.isfinite(merit_try) and merit_try <= (1.0 - 1e-4 * step) * merit:
                break
            step *= 0.5
        else:
            # no decrease: at the round-off floor (a step within 1000 xtol that cannot reduce
            # the residual) the current point is the solution
            if dx_max <= 1e3 * xtol * scale:
                return x, NewtonInfo(it, norm, True)
            # otherwise accept a full step only if we are already at round-off level
            if not (np.isfinite(merit_try) and norm <= max(atol, rtol * norm0) * 1e3):
                _fail(label, it, norm, r, describe, "line search found no decrease")
        x, r = x_try, r_try
        norm = float(np.max(np.abs(r)))
        small_step = step * np.max(np.abs(dx)) <= xtol * (1.0 + np.max(np.abs(x)))
        if small_step and norm <= max(atol, rtol * max(norm0, 1.0)) * 1e3:
            return x, NewtonInfo(it, norm, True)
    if norm <= atol:
        return x, NewtonInfo(max_iter, norm, True)
    _fail(label, max_iter, norm, r, describe, f"no convergence in {max_iter} iterations")


def _fail(label, it, norm, r, describe, why):
    worst = int(np.argmax(np.abs(r)))
    name = describe(worst) if describe else f"equation {worst}"
    raise AnalysisError(
        f"{label}: {why} (iteration {it}, max |residual| = {norm:.3e}, worst: {name})"
    )
