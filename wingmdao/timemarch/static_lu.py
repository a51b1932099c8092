"""Sparse LU with a fixed pivot order, generated once per sparsity pattern and compiled.

The adjoint (and tangent) sweep of a BDF history needs the exact factors of every step's
Newton matrix ``A_n`` (Eq. 3.7; ``docs/time-marching.md``). All ``A_n`` share one sparsity
pattern and change slowly from step to step, but SuperLU redoes its whole analysis for each
(0.25 ms for the 360-unknown, 20-node beam, of which the 11k multiply-adds are a small part).

:class:`StaticPivotLU` does the analysis once:

1. *pivot order*: SuperLU's row permutation ``P`` of a reference matrix (partial pivoting,
   natural column order, which is banded for node-major systems);
2. *symbolic factorization* of ``P A`` (left-looking, Gilbert-Peierls: the structure of column j
   of L and U is the reach of A(:, j) in the graph of L);
3. *numeric factorization and triangular solves* written out as CasADi SX expressions of the
   nonzeros: ``factor(a) -> lu``, ``solve(lu, b)``, ``solve_t(lu, b)`` (``A^T x = b``), mapped over
   all steps for the factorization and compiled to C like the residual functions
   (:mod:`wingmdao.utils.casadi_cache`).

Static pivoting is safe only while the pivots chosen for the reference stay good for every step.
Callers check that a-posteriori with the componentwise backward error (Oettli-Prager) of the
result and refine or fall back to SuperLU (:class:`~wingmdao.timemarch.adjoint.LinearizedHistory`).
"""

from __future__ import annotations

import hashlib

import casadi as ca
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.utils.casadi_cache import JitCall, compile_calls, definition_key


def symbolic_lu(n, rows, indptr):
    """Column structures of unit-lower L (below the diagonal) and U (above) of a CSC pattern.

    No pivoting: the pattern is that of the already row-permuted matrix, whose diagonal must be
    structurally nonzero. Returns ``(l_struct, u_struct)``, lists of sorted row-index arrays.
    """
    l_struct, u_struct = [], []
    for j in range(n):
        col = set(rows[indptr[j]:indptr[j + 1]].tolist())
        upper = []
        k = -1
        while True:       # the next-smallest k < j in the growing column: L(:, k) fills it in
            above = [i for i in col if k < i < j]
            if not above:
                break
            k = min(above)
            upper.append(k)
            col.update(l_struct[k])
        if j not in col:
            raise ValueError(f"column {j}: zero pivot in the structure of the permuted matrix")
        u_struct.append(np.array(upper, dtype=int))
        l_struct.append(np.array(sorted(i for i in col if i > j), dtype=int))
    return l_struct, u_struct


def _sparse_product(vals, x, out_idx, in_idx, n, absolute=False):
    """SX ``M x`` for ``M`` with nonzeros ``vals`` at (out_idx[k], in_idx[k]); with ``absolute``
    also ``|M| |x|``."""
    terms = [[] for _ in range(n)]
    for k, i in enumerate(out_idx):
        terms[int(i)].append(k)
    prod, absprod = [], []
    for t in terms:
        if not t:
            prod.append(ca.SX(0))
            absprod.append(ca.SX(0))
            continue
        vk = ca.vertcat(*[vals[k] for k in t])
        xk = ca.vertcat(*[x[int(in_idx[k])] for k in t])
        prod.append(ca.dot(vk, xk))
        if absolute:
            absprod.append(ca.dot(ca.fabs(vk), ca.fabs(xk)))
    if absolute:
        return ca.vertcat(*prod), ca.vertcat(*absprod)
    return ca.vertcat(*prod)


class StaticPivotLU:
    """LU factors ``P A = L U`` of many matrices with one pattern, one pivot order.

    Parameters
    ----------
    n : size; rows, indptr : CSC pattern (sorted rows per column)
    reference : nonzero values (CSC order) from which the row pivot order is chosen
    threshold : evaluations before the functions are compiled (see ``JitFunction``)
    """

    def __init__(self, n, rows, indptr, reference, threshold=2000):
        self.n = int(n)
        self.rows = np.asarray(rows, dtype=int)
        self.indptr = np.asarray(indptr, dtype=int)
        self.nnz = self.rows.size
        ref = sp.csc_matrix((np.asarray(reference, dtype=float), self.rows, self.indptr), shape=(n, n))
        lu = spla.splu(ref, permc_spec="NATURAL")
        self.perm_r = np.asarray(lu.perm_r, dtype=int)       # row i of A is row perm_r[i] of P A
        self.inv_perm = np.argsort(self.perm_r)                # row r of P A is row inv_perm[r] of A
        # pattern of P A: permute the row indices, keep the nonzero numbering of A
        prow = self.perm_r[self.rows]
        order = np.lexsort((prow, np.repeat(np.arange(n), np.diff(self.indptr))))
        self._pa_rows = prow[order]
        self._pa_source = order                                # PA nonzero k = A nonzero order[k]
        self.l_struct, self.u_struct = symbolic_lu(n, self._pa_rows, self.indptr)
        self._build_functions(threshold)

    # ------------------------------------------------------------------ generation
    def _build_functions(self, threshold):
        n = self.n
        a = ca.SX.sym("a", self.nnz)
        # dense working column of SX (zeros where structurally zero), left-looking elimination
        l_val, u_val, diag = [], [], []
        for j in range(n):
            x = {}
            for k in range(self.indptr[j], self.indptr[j + 1]):
                x[int(self._pa_rows[k])] = a[int(self._pa_source[k])]
            for k in self.u_struct[j]:
                xk = x.get(int(k), 0)
                for i, lik in zip(self.l_struct[k], l_val[k]):
                    x[int(i)] = x.get(int(i), 0) - lik * xk
            piv = x[j]
            diag.append(piv)
            u_val.append([x.get(int(k), ca.SX(0)) for k in self.u_struct[j]])
            l_val.append([x.get(int(i), ca.SX(0)) / piv for i in self.l_struct[j]])
        self._l_off = np.cumsum([0] + [len(s) for s in self.l_struct])
        self._u_off = np.cumsum([0] + [len(s) for s in self.u_struct])
        lu = ca.vertcat(*[v for col in l_val for v in col], *[v for col in u_val for v in col], *diag)
        self.n_lu = lu.shape[0]
        name = "static_lu_" + self.key()
        self.factor_fun = ca.Function(name + "_factor", [a], [lu])

        # triangular solves on the symbolic factors
        f = ca.SX.sym("lu", self.n_lu)
        nl, nu = int(self._l_off[-1]), int(self._u_off[-1])
        L = [f[int(self._l_off[j]):int(self._l_off[j + 1])] for j in range(n)]
        U = [f[nl + int(self._u_off[j]):nl + int(self._u_off[j + 1])] for j in range(n)]
        D = [f[nl + nu + j] for j in range(n)]
        b = ca.SX.sym("b", n)
        # A x = b:  L y = P b, U x = y
        y = [b[int(self.inv_perm[r])] for r in range(n)]
        for j in range(n):
            for t, i in enumerate(self.l_struct[j]):
                y[i] = y[i] - L[j][t] * y[j]
        for j in range(n - 1, -1, -1):
            y[j] = y[j] / D[j]
            for t, i in enumerate(self.u_struct[j]):
                y[i] = y[i] - U[j][t] * y[j]
        raw_solve = ca.Function("raw_solve", [f, b], [ca.vertcat(*y)])
        # A^T x = b:  U^T z = b, L^T w = z, x = P^T w
        z = [b[j] for j in range(n)]
        for j in range(n):
            s = z[j]
            for t, i in enumerate(self.u_struct[j]):
                s = s - U[j][t] * z[i]
            z[j] = s / D[j]
        for j in range(n - 1, -1, -1):
            s = z[j]
            for t, i in enumerate(self.l_struct[j]):
                s = s - L[j][t] * z[i]
            z[j] = s
        raw_solve_t = ca.Function("raw_solve_t", [f, b], [ca.vertcat(*[z[int(self.perm_r[i])] for i in range(n)])])
        self._raw_t = raw_solve_t
        self._name = name
        self._threshold = threshold
        self._steps = {}
        a = ca.SX.sym("a", self.nnz)
        cols = np.repeat(np.arange(n), np.diff(self.indptr))
        self.solve_fun = self._checked(name + "_solve", raw_solve, f, a, b, self.rows, cols)
        self.solve_t_fun = self._checked(name + "_solve_t", raw_solve_t, f, a, b, cols, self.rows)
        # what defines the generated functions (key of their compiled libraries; no serialization)
        self._definition = definition_key("StaticPivotLU", (self.n, self._pattern_digest()), (__name__,))
        self._calls = {k: JitCall(fun, threshold, copy_outputs=False, definition=self._definition)
                       for k, fun in (("factor", self.factor_fun), ("solve", self.solve_fun),
                                      ("solve_t", self.solve_t_fun))}

    def _checked(self, name, raw, f, a, b, out_idx, in_idx, extra_inputs=(), rhs=None):
        """``(lu, a, b, *extra) -> (x, r, berr)``: the solve ``M x = rhs`` (``rhs`` defaults to
        ``b``), its residual ``r = rhs - M x`` and its componentwise backward error
        max_i |r_i| / (|M| |x| + |rhs|)_i, with M = A (``out_idx`` = rows, ``in_idx`` = cols) or
        A^T (swapped)."""
        rhs = b if rhs is None else rhs
        x = raw(f, rhs)
        prod, absprod = _sparse_product(a, x, out_idx, in_idx, self.n, absolute=True)
        res = rhs - prod
        scale = absprod + ca.fabs(rhs)
        berr = ca.mmax(ca.if_else(scale > 0, ca.fabs(res) / ca.fmax(scale, 1e-300), ca.fabs(res) * 1e300))
        return ca.Function(name, [f, a, b, *extra_inputs], [x, res, berr])

    def adjoint_step(self, rate_rows, rate_cols):
        """Compiled step of the BDF adjoint sweep (``LinearizedHistory.solve_adjoint``)::

            (lu_n, a_n, g_n, lam1, r1, c1, lam2, r2, c2) -> (lam_n, residual, berr)
            A_n^T lam_n = g_n - c1 R1^T lam1 - c2 R2^T lam2

        with R1, R2 the rate Jacobians dR/dxdot of steps n+1, n+2 (nonzeros ``r1``, ``r2`` on the
        pattern ``rate_rows, rate_cols``) and c1, c2 their BDF coefficients; the residual and
        backward error are those of the ``A_n^T`` solve. Cached per rate pattern."""
        h = hashlib.sha256()
        for arr in (rate_rows, rate_cols):
            h.update(np.ascontiguousarray(arr, dtype=np.int64).tobytes())
        full = h.hexdigest()
        key = full[:12]
        call = self._steps.get(key)
        if call is None:
            n, m = self.n, len(rate_rows)
            f, a, g = ca.SX.sym("lu", self.n_lu), ca.SX.sym("a", self.nnz), ca.SX.sym("g", n)
            lam1, lam2 = ca.SX.sym("lam1", n), ca.SX.sym("lam2", n)
            r1, r2 = ca.SX.sym("r1", m), ca.SX.sym("r2", m)
            c1, c2 = ca.SX.sym("c1"), ca.SX.sym("c2")
            b = (g - c1 * _sparse_product(r1, lam1, rate_cols, rate_rows, n)
                 - c2 * _sparse_product(r2, lam2, rate_cols, rate_rows, n))
            cols = np.repeat(np.arange(n), np.diff(self.indptr))
            fun = self._checked(f"{self._name}_adjoint_{key}", self._raw_t, f, a, g, cols, self.rows,
                                extra_inputs=(lam1, r1, c1, lam2, r2, c2), rhs=b)
            call = self._steps[key] = JitCall(fun, self._threshold, copy_outputs=False,
                                              definition=f"{self._definition}:{full}")
        return call

    def _pattern_digest(self) -> str:
        """SHA-256 of the pattern and pivot order."""
        h = hashlib.sha256()
        for arr in (self.rows, self.indptr, self.perm_r):
            h.update(np.ascontiguousarray(arr, dtype=np.int64).tobytes())
        return h.hexdigest()

    def key(self) -> str:
        """Hash of the pattern and pivot order (names the generated functions)."""
        return self._pattern_digest()[:12]

    # ------------------------------------------------------------------ evaluation
    def compile(self, wait=True) -> dict:
        """Compile (or load from the cache) all functions made so far now; returns their states."""
        return compile_calls({**self._calls, **{f"adjoint_{k}": c for k, c in self._steps.items()}}, wait)

    def factor(self, values) -> np.ndarray:
        """Factors of one matrix (nonzeros in CSC order) -> (n_lu,)."""
        return self._calls["factor"](values)[0].copy()

    def factor_many(self, values) -> np.ndarray:
        """Factors of a stack of matrices (m, nnz) -> (m, n_lu)."""
        values = np.asarray(values, dtype=float)
        call = self._calls["factor"]
        fast = call.refresh()
        call.jit.count(values.shape[0])
        out = np.empty((values.shape[0], self.n_lu))
        arg, res = fast.inp[0], fast.out[0]
        for k in range(values.shape[0]):
            arg[:] = values[k]
            fast.eval()
            out[k] = res
        return out

    def solve(self, lu, values, b, trans="N"):
        """``A x = b`` (``trans="N"``) or ``A^T x = b`` (``"T"``) with the factors ``lu`` of the
        matrix with nonzeros ``values``; returns ``(x, residual, backward_error)``."""
        x, res, berr = self._calls["solve" if trans == "N" else "solve_t"](lu, values, b)
        return x.copy(), res.copy(), float(berr[0])

    def backward_error(self, values, x, b, trans="N") -> float:
        """Componentwise backward error max_i |b - M x|_i / (|M| |x| + |b|)_i (M = A or A^T)."""
        cols = np.repeat(np.arange(self.n), np.diff(self.indptr))
        out, inp = (self.rows, cols) if trans == "N" else (cols, self.rows)
        res = b - np.bincount(out, values * x[inp], minlength=self.n)
        scale = np.bincount(out, np.abs(values) * np.abs(x[inp]), minlength=self.n) + np.abs(b)
        return float(np.max(np.abs(res) / np.where(scale > 0, scale, 1e-300)))


_CACHE: dict = {}
#: Patterns kept by :func:`for_pattern` (each holds three CasADi functions).
CACHE_SIZE = 8


def for_pattern(n, rows, indptr, reference):
    """The :class:`StaticPivotLU` of a pattern (cached per pattern; the first reference matrix
    fixes the pivot order), or None when the reference cannot be factored."""
    h = hashlib.sha256()
    for arr in (rows, indptr):
        h.update(np.ascontiguousarray(arr, dtype=np.int64).tobytes())
    key = (int(n), h.hexdigest())
    slu = _CACHE.get(key)
    if slu is None:
        try:
            slu = StaticPivotLU(n, rows, indptr, reference)
        except (RuntimeError, ValueError):   # singular reference or a structural zero pivot
            return None
        if len(_CACHE) >= CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = slu
    return slu
