"""Sparse LU with a fixed pivot order: symbolic analysis once per pattern, numeric work in C.

The adjoint (and tangent) sweep of a BDF history needs the exact factors of every step's
Newton matrix ``A_n`` (Eq. 3.7; ``docs/time-marching.md``). All ``A_n`` share one sparsity
pattern and change slowly from step to step, but SuperLU redoes its whole analysis for each
(0.25 ms for the 360-unknown, 20-node beam, of which the 11k multiply-adds are a small part).

:class:`StaticPivotLU` does the analysis once:

1. *pivot order*: SuperLU's row permutation ``P`` of a reference matrix (partial pivoting,
   natural column order, which is banded for node-major systems);
2. *symbolic factorization* of ``P A`` (left-looking, Gilbert-Peierls: the structure of column j
   of L and U is the reach of A(:, j) in the graph of L), in the C kernel (``lu_symbolic``,
   0.7 ms for the coupled aeroelastic beam; :func:`symbolic_lu` is the Python reference, 0.17 s:
   a coupled sizing, whose pivot order changes from design to design, spent 5 s in it);
3. *numeric factorization, triangular solves and backward errors* in one hand-written C file
   (``lu_kernel.c``), compiled once per machine (:mod:`wingmdao.utils.c_library`) and driven by
   the integer arrays of steps 1-2, so a new pattern costs no code generation; the whole sweep of
   :class:`~wingmdao.timemarch.adjoint.LinearizedHistory` (right-hand sides, factorization,
   checked solve, one refinement) runs in one C call per stretch of steps.

Static pivoting is safe only while the pivots chosen for the reference stay good for every step.
Each solve is checked a posteriori with the componentwise backward error (Oettli-Prager) of the
result, refined once, and reported to the caller when still too large (the caller then uses
SuperLU for that step: :class:`~wingmdao.timemarch.adjoint.LinearizedHistory`).

Without the compiled kernel (``WINGMDAO_JIT=0``, no gcc) :func:`kernel` is None, :func:`for_pattern`
returns None and the callers use SuperLU. ``WINGMDAO_LU_KERNEL=1`` turns the kernel on whatever
``WINGMDAO_JIT`` says (the tests, which run the CasADi functions interpreted), ``=0`` off.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.utils import c_library
from wingmdao.utils import casadi_cache as cc

SOURCE = Path(__file__).with_name("lu_kernel.c")
ENV_KERNEL = "WINGMDAO_LU_KERNEL"
_KERNELS: dict = {}

#: Matrices factored together (the SIMD lanes of ``lu_factor_lanes`` in lu_kernel.c, ``LU_W``).
LANES = 4

_P = ctypes.c_void_p
_I = ctypes.c_int


class _Pattern(ctypes.Structure):
    _fields_ = [("n", _I), ("nnz", _I)] + [(k, _P) for k in ("indptr", "rows", "prow", "perm", "lp", "li", "up", "ui",
                                                            "qcol")]


class _Sweep(ctypes.Structure):
    _fields_ = [("n_time", _I), ("off", _I), ("nd", _I), ("njd", _I), ("a", _P), ("jd", _P),
                ("src", _P), ("drow", _P), ("dcol", _P), ("coef", _P), ("same", _P), ("tol", ctypes.c_double)]


_SIGNATURES = {
    "lu_kernel_version": ([], _I),
    "lu_factor_batch": ([_P, _I, _P, _P, _P, _P], None),
    "lu_solve": ([_P, _P, _P, _I, _P], None),
    "lu_berr": ([_P, _P, _P, _P, _I, _P, _P], ctypes.c_double),
    "lu_solve_checked": ([_P, _P, _P, _P, _P, _P, _I, _P], ctypes.c_double),
    "adjoint_sweep": ([_P, _P, _I, _I, _P, _P, _P, _P, _P, _P], _I),
    "tangent_sweep": ([_P, _P, _I, _I, _P, _P, _P, _P, _P, _P], _I),
    "hist_product": ([_I, _I, _P, _P, _P, _P, _I, _P, _I, _I, _P], None),
    "assemble_newton": ([_I, _P, _I, _P, _P, _I, _P, _I, _P, _P, _I, _P, _P, _I, _P, _P, _P, _P, _P], _I),
    "nonzero_columns": ([_I, _I, _P, _P], None),
    "eval_history": ([_P, _I, _I, _P, _P, _I, _P, _P, _P, _P, _P, _P], _I),
    "lu_symbolic": ([_I, _P, _P, _P, _P, _I, _P, _P, _I, _P], _I),
}


def kernel():
    """The compiled kernel (``ctypes.CDLL``), or None when compilation is off or impossible
    (``WINGMDAO_LU_KERNEL``: 1 on, 0 off, unset: as ``WINGMDAO_JIT``)."""
    env = os.environ.get(ENV_KERNEL, "").strip().lower()
    if env in ("0", "false", "no", "off"):
        return None
    key = (env, os.environ.get(cc.ENV_JIT), os.environ.get(cc.ENV_CACHE), os.environ.get("CC"))
    if key in _KERNELS:                 # (c_library.load resolves paths: ~16 stat calls)
        return _KERNELS[key]
    lib = _KERNELS[key] = c_library.load(SOURCE, "lu_kernel", force=env in ("1", "true", "yes", "on"))
    if lib is not None and not getattr(lib, "_wingmdao_typed", False):
        for name, (args, res) in _SIGNATURES.items():
            fn = getattr(lib, name)
            fn.argtypes, fn.restype = args, res
        lib._wingmdao_typed = True
    return lib


def _ptr(a):
    return a.ctypes.data


def _i32(a):
    return np.ascontiguousarray(a, dtype=np.int32)


def _f64(a):
    a = np.asarray(a, dtype=float)
    return a if a.flags.c_contiguous else np.ascontiguousarray(a)


def symbolic_lu(n, rows, indptr):
    """Column structures of unit-lower L (below the diagonal) and U (above) of a CSC pattern
    (the Python reference of the kernel's ``lu_symbolic``, :func:`symbolic_lu_compiled`).

    No pivoting: the pattern is that of the already row-permuted matrix, whose diagonal must be
    structurally nonzero. Returns ``(l_struct, u_struct)``, lists of sorted row-index arrays.

    Parameters
    ----------
    n : int
        Order of the square matrix.
    rows : numpy.ndarray
        Row indices of the nonzeros in CSC order (already row-permuted).
    indptr : numpy.ndarray
        (n + 1,) CSC column pointers.

    Returns
    -------
    l_struct : list of numpy.ndarray
        Per column, the sorted rows of L below the diagonal.
    u_struct : list of numpy.ndarray
        Per column, the sorted rows of U above the diagonal.

    Raises
    ------
    ValueError
        When a column has a structural zero pivot.
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


def symbolic_lu_compiled(lib, n, rows, indptr):
    """:func:`symbolic_lu` in the C kernel (``lu_symbolic``, ~250x faster: 0.17 s -> 0.7 ms for
    the 441-unknown coupled aeroelastic beam): ``(lp, li, up, ui)`` int32 arrays, the column
    pointers and rows of L (below the diagonal, ascending) and U (above, ascending).

    Parameters
    ----------
    lib : ctypes.CDLL
        The compiled kernel (:func:`kernel`).
    n : int
        Order of the square matrix.
    rows : numpy.ndarray
        Row indices of the nonzeros in CSC order (already row-permuted).
    indptr : numpy.ndarray
        (n + 1,) CSC column pointers.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lp, li, up, ui)``, int32: column pointers (n + 1,) and rows of L, then of U.
    """
    n = int(n)
    indptr, rows = _i32(indptr), _i32(rows)
    lp, up, work = np.zeros(n + 1, np.int32), np.zeros(n + 1, np.int32), np.zeros(3 * max(n, 1), np.int32)
    cap = max(4 * rows.size, 16)
    while True:
        li, ui = np.zeros(cap, np.int32), np.zeros(cap, np.int32)
        status = lib.lu_symbolic(n, _ptr(indptr), _ptr(rows), _ptr(lp), _ptr(li), cap, _ptr(up), _ptr(ui), cap,
                                 _ptr(work))
        if status == 0:
            return lp, li[:lp[-1]].copy(), up, ui[:up[-1]].copy()
        if status < 0:
            raise ValueError(f"column {-1 - status}: zero pivot in the structure of the permuted matrix")
        if cap >= n * n:
            raise RuntimeError("lu_symbolic: the structure does not fit n**2 entries")
        cap = min(4 * cap, n * n)


#: Power of two on the rows of the leading block of :func:`pivot_order` (``diagonal``): exact
#: scaling, large enough that partial pivoting takes their entries first in their columns.
LEADING_ROW_SCALE = 2.0 ** 300


def pivot_order(n, rows, indptr, reference, col_order=None, diagonal=0) -> np.ndarray:
    """SuperLU's row permutation (partial pivoting) of the reference matrix with its columns in
    ``col_order`` (None: natural): row i of A is row ``perm_r[i]`` of ``P A Q``. Raises
    RuntimeError when singular.

    ``diagonal`` = k > 0: the first k columns of ``P A Q`` pivot among the rows of the same k
    unknowns (rows ``q[:k]``; on their own rows when that block ``A_11`` is diagonal, as for the
    aerodynamic lag states), eliminated before the rest; the other rows are then SuperLU's
    partial pivoting of what remains, the Schur complement ``S = A_22 - A_21 A_11^-1 A_12``.
    Done by one SuperLU factorization with the rows ``q[:k]`` scaled by
    :data:`LEADING_ROW_SCALE`: a power of two changes no rounding (``A_21 (s A_11)^-1 (s A_12)`` is
    ``A_21 A_11^-1 A_12`` bit for bit), it only makes those rows win the pivot search in the
    first k columns. The factors are the pivoted elimination of ``P A Q`` in this order, so any
    k gives the same solutions (each solve is still checked by its backward error).

    Parameters
    ----------
    n : int
        Order of the square matrix.
    rows : numpy.ndarray
        Row indices of the nonzeros in CSC order.
    indptr : numpy.ndarray
        (n + 1,) CSC column pointers.
    reference : numpy.ndarray
        (nnz,) nonzero values of the reference matrix in CSC order.
    col_order : numpy.ndarray, optional
        (n,) column order Q; None keeps the natural order.
    diagonal : int, optional
        Number k of leading columns of ``P A Q`` that pivot among their own unknowns' rows.

    Returns
    -------
    numpy.ndarray
        (n,) int row permutation ``perm_r``.
    """
    a = np.asarray(reference, dtype=float)
    k = int(diagonal)
    q = np.arange(n) if col_order is None else np.asarray(col_order)
    if k > 0:
        scale = np.ones(n)
        scale[q[:k]] = LEADING_ROW_SCALE
        a = a * scale[np.asarray(rows)]
    ref = sp.csc_matrix((a, rows, indptr), shape=(n, n))
    if col_order is not None:
        ref = ref[:, q]
    return np.asarray(spla.splu(ref, permc_spec="NATURAL").perm_r, dtype=int)


def permuted_columns(indptr, col_order):
    """``(indptr_q, take)`` of the CSC pattern with its columns in ``col_order``: column j of the
    permuted pattern holds the nonzeros ``take[indptr_q[j]:indptr_q[j + 1]]`` of the original.

    Parameters
    ----------
    indptr : numpy.ndarray
        (n + 1,) CSC column pointers of the original pattern.
    col_order : numpy.ndarray
        (n,) column order: column j of the result is column ``col_order[j]`` of the original.

    Returns
    -------
    indptr_q : numpy.ndarray
        (n + 1,) int64 column pointers of the permuted pattern.
    take : numpy.ndarray
        (nnz,) int64 index of each permuted nonzero in the original nonzeros.
    """
    indptr = np.asarray(indptr, dtype=np.int64)
    q = np.asarray(col_order, dtype=np.int64)
    counts = indptr[q + 1] - indptr[q]
    indptr_q = np.concatenate([[0], np.cumsum(counts)])
    take = np.repeat(indptr[q] - indptr_q[:-1], counts) + np.arange(indptr_q[-1])
    return indptr_q, take


def factorization_work(n, rows, indptr, reference, col_order=None, diagonal=0) -> int:
    """Multiply-adds of one numeric factorization ``P A Q = L U`` with the pivots of ``reference``
    (``sum_j sum_{k in U(:, j)} |L(:, k)|``, what :class:`StaticPivotLU` spends per matrix;
    ``diagonal``: leading diagonal pivots, :func:`pivot_order`).

    Parameters
    ----------
    n : int
        Order of the square matrix.
    rows : numpy.ndarray
        Row indices of the nonzeros in CSC order.
    indptr : numpy.ndarray
        (n + 1,) CSC column pointers.
    reference : numpy.ndarray
        (nnz,) nonzero values (CSC order) that fix the pivot order.
    col_order : numpy.ndarray, optional
        (n,) column order Q; None keeps the natural order.
    diagonal : int, optional
        Number of leading diagonal pivots (:func:`pivot_order`).

    Returns
    -------
    int
        Multiply-adds of one numeric factorization.

    Raises
    ------
    RuntimeError
        When the kernel is not compiled.
    """
    lib = kernel()
    if lib is None:
        raise RuntimeError("the static-pivot LU kernel is not compiled (WINGMDAO_JIT=0 or no gcc)")
    q = np.arange(int(n)) if col_order is None else check_column_order(int(n), col_order)
    perm = pivot_order(int(n), np.asarray(rows), np.asarray(indptr), reference, q, diagonal)
    _, (lp, _, up, ui) = permuted_symbolic(lib, int(n), rows, indptr, perm, q)
    return int(np.diff(lp)[ui].sum())


def permuted_symbolic(lib, n, rows, indptr, perm_r, col_order):
    """``(prow, (lp, li, up, ui))``: the rows of the nonzeros in ``P A`` and the structure of L
    and U of ``P A Q`` (:func:`symbolic_lu_compiled` of the column-permuted pattern).

    Parameters
    ----------
    lib : ctypes.CDLL
        The compiled kernel (:func:`kernel`).
    n : int
        Order of the square matrix.
    rows : numpy.ndarray
        Row indices of the nonzeros in CSC order.
    indptr : numpy.ndarray
        (n + 1,) CSC column pointers.
    perm_r : numpy.ndarray
        (n,) row permutation (:func:`pivot_order`).
    col_order : numpy.ndarray
        (n,) column order Q.

    Returns
    -------
    prow : numpy.ndarray
        (nnz,) rows of the nonzeros in ``P A``.
    structure : tuple of numpy.ndarray
        ``(lp, li, up, ui)`` of ``P A Q`` (:func:`symbolic_lu_compiled`).
    """
    prow = np.asarray(perm_r)[np.asarray(rows)]
    indptr_q, take = permuted_columns(indptr, col_order)
    return prow, symbolic_lu_compiled(lib, n, prow[take], indptr_q)


def block_column_order(local, block, n):
    """The column order that orders the unknowns of every full block of ``block`` consecutive
    unknowns (a node of a node-major system) by the within-block permutation ``local``; the
    unknowns after the last full block (body states) keep their place at the end.

    Parameters
    ----------
    local : array_like
        (block,) permutation of 0..block-1 applied within every block.
    block : int
        Unknowns per block (per node).
    n : int
        Total number of unknowns.

    Returns
    -------
    numpy.ndarray
        (n,) int64 column order.
    """
    local = check_column_order(int(block), local)
    n_full = int(n) // int(block)
    return np.concatenate([local + b * int(block) for b in range(n_full)]
                          + [np.arange(n_full * int(block), int(n))]).astype(np.int64)


def search_block_order(n, rows, indptr, reference, block, passes=3, start=None):
    """Within-block column order that lowers :func:`factorization_work`: greedy pairwise swaps
    of the block-local permutation (applied to every block), first improvement, up to ``passes``
    sweeps over the pairs. Returns ``(local, work)``. A design-time tool (seconds): its result
    is stored as a system's ``lu_column_order`` (``benchmarks/lu_column_order.py``).

    Parameters
    ----------
    n : int
        Order of the square matrix.
    rows : numpy.ndarray
        Row indices of the nonzeros in CSC order.
    indptr : numpy.ndarray
        (n + 1,) CSC column pointers.
    reference : numpy.ndarray
        (nnz,) nonzero values (CSC order) that fix the pivot order.
    block : int
        Unknowns per block (per node).
    passes : int, optional
        Maximum number of sweeps over the pairs.
    start : array_like, optional
        (block,) starting within-block permutation; None: identity.

    Returns
    -------
    local : numpy.ndarray
        (block,) the best within-block permutation found.
    work : int
        Its multiply-adds (:func:`factorization_work`).
    """
    local, works = search_joint_block_order([(n, rows, indptr, reference)], block, passes, start)
    return local, works[0]


def search_joint_block_order(matrices, block, passes=3, start=None, scale=None):
    """:func:`search_block_order` over several matrices ``[(n, rows, indptr, reference), ...]``
    with one within-block order: minimises ``sum_k work_k / scale_k`` (``scale``: each matrix's
    natural-order work when None), so no model's order is bought with another's fill. Returns
    ``(local, [work_k])``.

    Parameters
    ----------
    matrices : list of tuple
        ``(n, rows, indptr, reference)`` of each matrix (CSC pattern and values).
    block : int
        Unknowns per block (per node), common to all matrices.
    passes : int, optional
        Maximum number of sweeps over the pairs.
    start : array_like, optional
        (block,) starting within-block permutation; None: identity.
    scale : sequence of float, optional
        Per-matrix work that normalises the objective; None: natural-order work.

    Returns
    -------
    local : numpy.ndarray
        (block,) the best within-block permutation found.
    works : list of int
        Multiply-adds of each matrix with that order.
    """
    def works(loc):
        return [factorization_work(n, r, ip, a, block_column_order(loc, block, n)) for n, r, ip, a in matrices]

    def score(w):
        return float(sum(wk / sk for wk, sk in zip(w, scale)))

    if scale is None:
        scale = works(np.arange(block))
    best = np.arange(block) if start is None else check_column_order(block, start)
    best_w = works(best)
    best_s = score(best_w)
    for _ in range(int(passes)):
        improved = False
        for i in range(block):
            for j in range(i + 1, block):
                cand = best.copy()
                cand[i], cand[j] = cand[j], cand[i]
                w = works(cand)
                s = score(w)
                if s < best_s:
                    best, best_w, best_s, improved = cand, w, s, True
        if not improved:
            break
    return best, best_w


def check_column_order(n, col_order) -> np.ndarray:
    """``col_order`` as an int array, checked to be a permutation of 0..n-1 (ValueError).

    Parameters
    ----------
    n : int
        Expected number of unknowns.
    col_order : array_like
        The column order to check.

    Returns
    -------
    numpy.ndarray
        (n,) int64 column order.

    Raises
    ------
    ValueError
        When ``col_order`` is not a permutation of 0..n-1.
    """
    q = np.asarray(col_order, dtype=np.int64).ravel()
    if q.size != n or not np.array_equal(np.sort(q), np.arange(n)):
        raise ValueError(f"col_order must be a permutation of 0..{n - 1} (got {q.size} entries)")
    return q


class StaticPivotLU:
    """LU factors ``P A = L U`` of many matrices with one pattern, one pivot order (C kernel).

    Parameters
    ----------
    n : int
        Order of the square matrices.
    rows : array_like
        Row indices of the nonzeros in CSC order (sorted rows per column).
    indptr : array_like
        (n + 1,) CSC column pointers.
    reference : array_like, optional
        (nnz,) nonzero values (CSC order) from which the row pivot order is chosen.
    perm_r : array_like, optional
        (n,) the row permutation itself instead of ``reference`` (see :func:`pivot_order`).
    col_order : array_like, optional
        (n,) fill-reducing column order Q (``P A Q = L U``; None: natural), e.g. a system's
        ``lu_column_order`` (:func:`block_column_order`).

    Raises
    ------
    RuntimeError
        Without the compiled kernel (:func:`kernel`).
    """

    def __init__(self, n, rows, indptr, reference=None, perm_r=None, col_order=None):
        self.lib = kernel()
        if self.lib is None:
            raise RuntimeError("the static-pivot LU kernel is not compiled (WINGMDAO_JIT=0 or no gcc)")
        self.n = int(n)
        self.rows = np.asarray(rows, dtype=int)
        self.indptr = np.asarray(indptr, dtype=int)
        self.nnz = self.rows.size
        self.col_order = np.arange(self.n) if col_order is None else check_column_order(self.n, col_order)
        if perm_r is None:
            perm_r = pivot_order(self.n, self.rows, self.indptr, reference, col_order)
        self.perm_r = np.asarray(perm_r, dtype=int)         # row i of A is row perm_r[i] of P A Q
        prow, (lp, li, up, ui) = permuted_symbolic(self.lib, self.n, self.rows, self.indptr, self.perm_r,
                                                   self.col_order)
        self.n_lu = int(lp[-1] + up[-1] + self.n)
        # the kernel's arrays (kept alive with the structure that points to them)
        self._arrays = {"indptr": _i32(self.indptr), "rows": _i32(self.rows), "prow": _i32(prow),
                        "perm": _i32(self.perm_r), "lp": lp, "li": li, "up": up, "ui": ui,
                        "qcol": _i32(self.col_order)}
        self._pattern = _Pattern(self.n, self.nnz, *(_ptr(self._arrays[k]) for k, _ in _Pattern._fields_[2:]))
        self._pp = ctypes.addressof(self._pattern)
        # sweeps: checked solves 4 n, the lanes' work column LANES n (zero between calls), the
        # tangent's history n; factors: LANES slots and the interleaved factors of LANES matrices
        self._work = np.zeros((5 + LANES) * self.n)
        self._f = np.zeros(2 * LANES * self.n_lu)
        self._b = np.zeros(self.n)
        self._lanes_x = np.zeros(LANES * self.n)
        self._lanes_f = np.zeros(LANES * self.n_lu)

    # ------------------------------------------------------------------ single matrices
    def factor(self, values) -> np.ndarray:
        """Factors of one matrix (nonzeros in CSC order) -> (n_lu,): L, U by columns, diag(U).

        Parameters
        ----------
        values : numpy.ndarray
            (nnz,) nonzeros of the matrix in CSC order.

        Returns
        -------
        numpy.ndarray
            (n_lu,) the factors.
        """
        return self.factor_many(np.reshape(values, (1, -1)))[0]

    def factor_many(self, values) -> np.ndarray:
        """Factors of a stack of matrices (m, nnz) -> (m, n_lu).

        Parameters
        ----------
        values : numpy.ndarray
            (m, nnz) nonzeros of m matrices in CSC order.

        Returns
        -------
        numpy.ndarray
            (m, n_lu) the factors of each matrix.
        """
        values = _f64(values)
        if values.ndim != 2 or values.shape[1] != self.nnz:
            raise ValueError(f"values must have shape (m, {self.nnz}), got {values.shape}")
        out = np.empty((values.shape[0], self.n_lu))
        self.lib.lu_factor_batch(self._pp, values.shape[0], _ptr(values), _ptr(out), _ptr(self._lanes_x),
                                 _ptr(self._lanes_f))
        return out

    def solve(self, lu, values, b, trans="N"):
        """``A x = b`` (``trans="N"``) or ``A^T x = b`` (``"T"``) with the factors ``lu`` of the
        matrix with nonzeros ``values``; returns ``(x, residual, backward_error)``.

        Parameters
        ----------
        lu : numpy.ndarray
            (n_lu,) factors of the matrix (:meth:`factor`).
        values : numpy.ndarray
            (nnz,) nonzeros of the same matrix in CSC order (for the residual).
        b : numpy.ndarray
            (n,) right-hand side.
        trans : {"N", "T"}, optional
            Solve with A ("N") or its transpose ("T").

        Returns
        -------
        x : numpy.ndarray
            (n,) the solution.
        residual : numpy.ndarray
            (n,) the residual of the solve.
        backward_error : float
            Componentwise backward error of ``x``.
        """
        lu, values, b = _f64(lu), _f64(values), _f64(b)
        x, res = np.empty(self.n), np.empty(self.n)
        berr = self.lib.lu_solve_checked(self._pp, _ptr(lu), _ptr(values), _ptr(b), _ptr(x), _ptr(res),
                                         0 if trans == "N" else 1, _ptr(self._work))
        return x, res, float(berr)

    def backward_error(self, values, x, b, trans="N") -> float:
        """Componentwise backward error ``max_i |b - M x|_i / (|M| |x| + |b|)_i`` (M = A or A^T).

        Parameters
        ----------
        values : numpy.ndarray
            (nnz,) nonzeros of A in CSC order.
        x : numpy.ndarray
            (n,) candidate solution.
        b : numpy.ndarray
            (n,) right-hand side.
        trans : {"N", "T"}, optional
            M = A ("N") or A^T ("T").

        Returns
        -------
        float
            The componentwise backward error.
        """
        values, x, b = _f64(values), _f64(x), _f64(b)
        res = np.empty(self.n)
        return float(self.lib.lu_berr(self._pp, _ptr(values), _ptr(x), _ptr(b), 0 if trans == "N" else 1,
                                      _ptr(res), _ptr(self._work)))

    # ------------------------------------------------------------------ sweeps
    def sweep_data(self, n_time, off, a, jd, src, drow, dcol, coef, same, tol):
        """The history seen by :meth:`adjoint_sweep` and :meth:`tangent_sweep`: Newton-matrix
        nonzeros ``a`` (steps off.., nnz), rate-Jacobian nonzeros ``jd`` (steps off..), of which
        ``jd[:, src]`` sit at ``(drow, dcol)``; ``coef`` (n_time, 3) the BDF coefficients / dt,
        ``same[n]``: ``A_n == A_{n-1}``; ``tol`` the accepted backward error. The returned object
        keeps its arrays alive.

        Parameters
        ----------
        n_time : int
            Number of time steps of the history.
        off : int
            First step held in ``a`` and ``jd``.
        a : numpy.ndarray
            (steps, nnz) Newton-matrix nonzeros from step ``off``.
        jd : numpy.ndarray
            (steps, njd) rate-Jacobian (dR/dxdot) nonzeros from step ``off``.
        src : numpy.ndarray
            Columns of ``jd`` used by the sweeps.
        drow : numpy.ndarray
            Rows of the used rate-Jacobian nonzeros.
        dcol : numpy.ndarray
            Columns of the used rate-Jacobian nonzeros.
        coef : numpy.ndarray
            (n_time, 3) BDF coefficients divided by the time step (1/s).
        same : numpy.ndarray
            (n_time,) bool, ``A_n == A_{n-1}``.
        tol : float
            Accepted componentwise backward error.

        Returns
        -------
        ctypes.Structure
            The kernel's sweep description (it keeps its arrays alive).
        """
        keep = [_f64(a), _f64(jd), _i32(src), _i32(drow), _i32(dcol), _f64(coef),
                np.ascontiguousarray(same, dtype=np.uint8)]
        if keep[0].shape[1] != self.nnz:
            raise ValueError(f"a must have {self.nnz} columns, got {keep[0].shape}")
        s = _Sweep(int(n_time), int(off), int(keep[2].size), int(keep[1].shape[1]),
                   *(_ptr(k) for k in keep), float(tol))
        s._keep = keep
        return s

    def adjoint_sweep(self, data, hi, lo, rhs, lam):
        """Steps ``hi, hi-1, .., lo`` (lo >= 1) of ``A_n^T lam_n = rhs_n - c(n+1,1) R_{n+1}^T
        lam_{n+1} - c(n+2,2) R_{n+2}^T lam_{n+2}`` into ``lam`` (n_time, n; C-contiguous) in place.
        Returns ``(stop, refined, factored)``: the step whose refined solve failed (its right-hand
        side in ``self.rhs_buffer``) or ``lo - 1``, the number of refined steps and of factored
        matrices (``LANES`` at a time; steps equal to the step before reuse its factors).

        Parameters
        ----------
        data : ctypes.Structure
            History from :meth:`sweep_data`.
        hi : int
            First (latest) step of the sweep.
        lo : int
            Last (earliest) step, >= 1.
        rhs : numpy.ndarray
            (n_time, n) C-contiguous right-hand sides.
        lam : numpy.ndarray
            (n_time, n) C-contiguous adjoint history, written in place.

        Returns
        -------
        stop : int
            The step whose refined solve failed, or ``lo - 1`` when all succeeded.
        refined : int
            Number of refined steps.
        factored : int
            Number of factored matrices.
        """
        counts = (ctypes.c_int * 2)(0, 0)
        stop = self.lib.adjoint_sweep(self._pp, ctypes.addressof(data), int(hi), int(lo), _ptr(rhs), _ptr(lam),
                                      _ptr(self._f), _ptr(self._b), _ptr(self._work), counts)
        return int(stop), int(counts[0]), int(counts[1])

    def tangent_sweep(self, data, lo, hi, rhs, dx):
        """Steps ``lo..hi`` (lo >= 1) of ``A_n dx_n = rhs_n - R_n (c(n,1) dx_{n-1} + c(n,2)
        dx_{n-2})`` into ``dx`` in place. Returns ``(stop, refined, factored)`` (stop ``hi + 1``:
        all done).

        Parameters
        ----------
        data : ctypes.Structure
            History from :meth:`sweep_data`.
        lo : int
            First step of the sweep, >= 1.
        hi : int
            Last step of the sweep.
        rhs : numpy.ndarray
            (n_time, n) C-contiguous right-hand sides.
        dx : numpy.ndarray
            (n_time, n) C-contiguous tangent history, written in place.

        Returns
        -------
        stop : int
            The step whose refined solve failed, or ``hi + 1`` when all succeeded.
        refined : int
            Number of refined steps.
        factored : int
            Number of factored matrices.
        """
        counts = (ctypes.c_int * 2)(0, 0)
        stop = self.lib.tangent_sweep(self._pp, ctypes.addressof(data), int(lo), int(hi), _ptr(rhs), _ptr(dx),
                                      _ptr(self._f), _ptr(self._b), _ptr(self._work), counts)
        return int(stop), int(counts[0]), int(counts[1])

    @property
    def rhs_buffer(self) -> np.ndarray:
        """The right-hand side of the step at which a sweep stopped."""
        return self._b


def nonzero_columns(lib, data) -> np.ndarray:
    """Columns of ``data`` (nt, m) with a nonzero in some row (bool, (m,)); the C kernel.

    Parameters
    ----------
    lib : ctypes.CDLL
        The compiled kernel (:func:`kernel`).
    data : numpy.ndarray
        (nt, m) values.

    Returns
    -------
    numpy.ndarray
        (m,) bool, True where the column has a nonzero.
    """
    data = _f64(data)
    out = np.zeros(data.shape[1], dtype=np.uint8)
    lib.nonzero_columns(data.shape[0], data.shape[1], _ptr(data), _ptr(out))
    return out.view(bool)


def hist_product(lib, data, out_idx, in_idx, vec, n_out, sum_time=False, out=None):
    """``out[t, out_idx[k]] += data[t, k] vec[t, in_idx[k]]`` (the C kernel; ``out`` zero if not
    given); with ``sum_time`` one row summed over t. ``out_idx``, ``in_idx`` int32.

    Parameters
    ----------
    lib : ctypes.CDLL
        The compiled kernel (:func:`kernel`).
    data : numpy.ndarray
        (nt, nnz) Jacobian nonzeros per step.
    out_idx : numpy.ndarray
        (nnz,) int32 output index of each nonzero.
    in_idx : numpy.ndarray
        (nnz,) int32 input index of each nonzero.
    vec : numpy.ndarray
        (nt, n_in) input history.
    n_out : int
        Width of the output.
    sum_time : bool, optional
        Sum the products over time into one (n_out,) row.
    out : numpy.ndarray, optional
        Accumulator, (nt, n_out) or (n_out,) with ``sum_time``; zeros when None.

    Returns
    -------
    numpy.ndarray
        ``out``, (nt, n_out) or (n_out,) with ``sum_time``.
    """
    data, vec = _f64(data), _f64(vec)
    nt, nnz = data.shape
    if out is None:
        out = np.zeros(n_out if sum_time else (nt, n_out))
    acc = np.zeros(nnz) if sum_time else None
    lib.hist_product(nt, nnz, _ptr(data), _ptr(out_idx), _ptr(in_idx), _ptr(vec), vec.shape[1], _ptr(out),
                     n_out, 1 if sum_time else 0, None if acc is None else _ptr(acc))
    return out


_CACHE: dict = {}
#: Patterns (with pivot orders) kept by :func:`for_pattern`.
CACHE_SIZE = 16


def for_pattern(n, rows, indptr, reference, col_order=None, diagonal=0):
    """The :class:`StaticPivotLU` of a pattern with the pivot order of ``reference`` and the
    column order ``col_order`` (None: natural; ``diagonal``: leading columns pivoting on their own
    rows, :func:`pivot_order`; cached per pattern, column and pivot order: a new reference with
    the same pivots costs one SuperLU factorization), or None when the kernel is not compiled or
    the reference cannot be factored.

    Parameters
    ----------
    n : int
        Order of the square matrix.
    rows : numpy.ndarray
        Row indices of the nonzeros in CSC order.
    indptr : numpy.ndarray
        (n + 1,) CSC column pointers.
    reference : numpy.ndarray
        (nnz,) nonzero values (CSC order) that fix the pivot order.
    col_order : numpy.ndarray, optional
        (n,) column order Q; None keeps the natural order.
    diagonal : int, optional
        Number of leading diagonal pivots (:func:`pivot_order`).

    Returns
    -------
    StaticPivotLU or None
        The (cached) factorizer, or None.
    """
    if kernel() is None:
        return None
    q = np.arange(int(n)) if col_order is None else check_column_order(int(n), col_order)
    try:
        perm = pivot_order(int(n), np.asarray(rows), np.asarray(indptr), reference, q, diagonal)
    except RuntimeError:     # singular reference
        return None
    h = hashlib.sha256()
    for arr in (rows, indptr, perm, q):
        h.update(np.ascontiguousarray(arr, dtype=np.int64).tobytes())
    key = (int(n), h.hexdigest())
    slu = _CACHE.get(key)
    if slu is None:
        try:
            slu = StaticPivotLU(n, rows, indptr, perm_r=perm, col_order=q)
        except ValueError:   # a structural zero pivot
            return None
        if len(_CACHE) >= CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = slu
    return slu
