"""Static-pivot complex LU of shifted pencils ``A + s B`` and the inverse iteration on them, in C.

The flutter constraint's warm start refines ~9 modes per evaluation (``refine_pair``: one LU of
the complex ``A + s B`` per shift, then inverse-iteration steps with it and with its conjugate
transpose). For the 441-state PEGASUS pencil SciPy's SuperLU spends 0.75-0.95 ms per
factorization (its per-call analysis; the factors have only ~11k nonzeros) and the Python loop
around the solves as much again. As :mod:`wingmdao.timemarch.static_lu` does for the real adjoint,
:class:`Pencil` does the analysis once:

1. *pattern*: the union of the patterns of A and B (``A + s B`` has it for every s, and the
   CasADi Jacobians keep it for every design), with A's and B's values scattered onto it;
2. *pivot order*: SuperLU's row permutation of the first matrix factored (partial pivoting,
   natural column order, as :func:`superlu`), kept while the solves' backward errors stay
   small; *symbolic factorization* of the row-permuted pattern (``lu_symbolic`` of
   ``lu_kernel.c``);
3. *numeric factorization, checked solves with M and M^H, and the whole inverse-iteration loop of
   one shift* in C (``pencil_lu.c``, C99 ``double complex``), compiled once per machine by
   :mod:`wingmdao.utils.c_library`; its triangular solves are those of the real kernel
   (``timemarch/lu_triangular.h``, one source for both scalar types).

Exactness: every solve's normwise backward error ``max |b - M x| / max (|M| |x| + |b|)`` must
be at most :data:`BACKWARD_TOL` (after one step of iterative refinement), i.e. the solve is as
backward stable as SuperLU's (whose errors on these pencils are 3e-17 - 8e-15; not the
componentwise error of the real kernel: inverse iteration solves nearly singular systems, where
SuperLU's componentwise errors are 1e-6 - 1e-2); a shift where one is not (bad static pivots)
is redone with SuperLU, whose row order the kernel takes for the next shifts
(:meth:`Pencil.repivot`). Results agree with the SuperLU path to round-off
(``tests/test_stability_lu.py``).

Interface. Callers use :class:`ShiftedPencil` (``factor(s)`` -> :class:`ShiftLU`, whose
``solve(b, trans)`` solves with M, M^T or M^H; ``refine``: the inverse-iteration steps of one
shift; ``products``) and :func:`factor` for any real or complex sparse matrix: the kernel when it
is compiled and its pivots hold, else SuperLU, and they never see which. Without the compiled
kernels (``WINGMDAO_JIT=0``, no gcc; ``WINGMDAO_LU_KERNEL`` as in
:mod:`~wingmdao.timemarch.static_lu`) everything runs on SuperLU; :class:`Pencil` and
:func:`pencil` (None without the kernel) are the kernel's own layer.

Why the kernel is kept. Replay of a recorded PEGASUS maneuver sizing's flutter constraint
(``python benchmarks/bench_flutter.py --record SEQ.pkl``, then ``OMP_NUM_THREADS=1
WINGMDAO_LU_KERNEL=1`` or ``=0 python benchmarks/bench_flutter.py --replay SEQ.pkl --no-cold
--refresh 100``: 149 calls, 97 designs, 874 refinements, 1061 lazy estimates, the same on both
paths): 5.28 and 4.23 s CPU with the kernel, 6.88 and 6.06 s with SuperLU (two runs each,
alternated, on a shared machine), i.e. 1.6-1.8 s per sizing, 25-30 % of the constraint's time.
With this interface keeping it costs the callers nothing (no branch on the kernel), and its C
is only what is complex-specific (the numeric factorization with its growth check, the normwise
backward error, the inverse-iteration loop, the sparse products): the triangular solves are the
real kernel's source.
"""

from __future__ import annotations

import ctypes
import os
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.timemarch import static_lu
from wingmdao.utils import c_library
from wingmdao.utils import casadi_cache as cc

SOURCE = Path(__file__).with_name("pencil_lu.c")
#: ``-fcx-fortran-rules``: complex products and quotients without C99 Annex G's NaN/inf recovery
#: (SuperLU's own complex arithmetic does none either).
FLAGS = tuple(c_library.C_FLAGS) + ("-fcx-fortran-rules",)
#: Largest accepted growth ``|| |L| |U| || / || A + s B ||`` (infinity norms) of a factorization:
#: the backward error of every solve with it is at most ~n eps times this (Higham, "Accuracy and
#: stability of numerical algorithms", 2nd ed., Thm 9.3).
GROWTH_MAX = 1e3
#: Accepted normwise backward error of a solve (SuperLU's: 3e-17 - 8e-15 on the PEGASUS pencils).
BACKWARD_TOL = 1e-13

_P = ctypes.c_void_p
_I = ctypes.c_int
_D = ctypes.c_double


class _Pattern(ctypes.Structure):
    _fields_ = [("n", _I), ("nnz", _I)] + [(k, _P) for k in ("indptr", "rows", "prow", "perm", "lp", "li", "up",
                                                            "ui")]


_SIGNATURES = {
    "pencil_lu_version": ([], _I),
    "pencil_factor": ([_P, _P, _P, _D, _D, _P, _P, _P, _P, _P], _I),
    "pencil_solve": ([_P, _P, _P, _I, _P], None),
    "pencil_berr": ([_P, _P, _P, _P, _P, _I, _P, _P], _D),
    "pencil_solve_checked": ([_P, _P, _P, _P, _P, _P, _I, _D, _P], _D),
    "pencil_products": ([_P, _P, _P, _P, _I, _I, _P, _P], None),
    "pencil_iterate": ([_P, _P, _P, _P, _P, _P, _P, _P, _P, _P, _P, _I, _D, _D, _I, _P, _P, _P], _I),
}
_KERNELS: dict = {}


def kernel():
    """The compiled ``pencil_lu.c`` (``ctypes.CDLL``), or None (``WINGMDAO_LU_KERNEL``: 1 on, 0 off,
    unset: as ``WINGMDAO_JIT``; None also when the real kernel, whose symbolic step it uses, is off)."""
    env = os.environ.get(static_lu.ENV_KERNEL, "").strip().lower()
    if env in ("0", "false", "no", "off"):
        return None
    key = (env, os.environ.get(cc.ENV_JIT), os.environ.get(cc.ENV_CACHE), os.environ.get("CC"))
    if key in _KERNELS:
        return _KERNELS[key]
    lib = None
    if static_lu.kernel() is not None:
        lib = c_library.load(SOURCE, "pencil_lu", FLAGS, force=env in ("1", "true", "yes", "on"))
    if lib is not None and not getattr(lib, "_wingmdao_typed", False):
        for name, (args, res) in _SIGNATURES.items():
            fn = getattr(lib, name)
            fn.argtypes, fn.restype = args, res
        lib._wingmdao_typed = True
    _KERNELS[key] = lib
    return lib


def _ptr(a):
    return a.ctypes.data


def _c128(a):
    return np.array(a, dtype=complex, order="C")      # a copy: the kernel writes in place


class _Structure:
    """A CSC pattern (``indptr``, ``rows``; sorted linear ``keys`` = column n + row) holding the
    patterns of pencils' A and B, and the symbolic factorizations of its pivot orders. The
    pencils' patterns vary a little with the design (``linearize`` drops the Jacobians' numerical
    zeros), so a structure is the growing union of the patterns seen: a pencil whose A and B fit in
    one takes it (its other entries are zero), else a new one is the union of the two."""

    def __init__(self, n, keys):
        self.n = n
        self.keys = keys
        cols = keys // n
        self.rows = np.ascontiguousarray(keys - cols * n, dtype=np.int32)
        self.indptr = np.ascontiguousarray(np.searchsorted(cols, np.arange(n + 1)), dtype=np.int32)
        self.nnz = int(keys.size)
        # the pattern alone (no pivots: for pencil_products)
        self._plain = _Pattern(n, self.nnz, _ptr(self.indptr), _ptr(self.rows), *([None] * 6))
        self.pp = ctypes.addressof(self._plain)
        self.symbolic: dict = {}      # perm bytes -> _Symbolic
        self.current = None           # the _Symbolic in use (None: not chosen yet)

    def locate(self, keys):
        """Positions of ``keys`` in the structure, or None when one is not in it."""
        at = np.searchsorted(self.keys, keys)
        if at.size and (at[-1] >= self.nnz or not np.array_equal(self.keys[np.minimum(at, self.nnz - 1)], keys)):
            return None
        return at

    def values(self, data, where):
        out = np.zeros(self.nnz)
        out[where] = data
        return out

    def use(self, perm_r):
        """Take the row order ``perm_r`` (SuperLU's ``perm_r`` of a matrix of this pattern)."""
        perm = np.ascontiguousarray(perm_r, dtype=np.int32)
        key = perm.tobytes()
        sym = self.symbolic.get(key)
        if sym is None:
            if len(self.symbolic) >= 8:
                self.symbolic.pop(next(iter(self.symbolic)))
            sym = self.symbolic[key] = _Symbolic(self, perm)
        self.current = sym
        return sym


def _keys(M):
    """Sorted linear indices column n + row of the nonzeros of a canonical CSC matrix."""
    n = M.shape[0]
    cols = np.repeat(np.arange(n, dtype=np.int64), np.diff(M.indptr))
    return cols * n + M.indices.astype(np.int64)


class _Symbolic:
    """Row order and the structures of L and U of ``P (A + s B)`` (the kernel's pattern struct)."""

    def __init__(self, st: _Structure, perm):
        lib = static_lu.kernel()
        prow, (lp, li, up, ui) = static_lu.permuted_symbolic(lib, st.n, st.rows, st.indptr, perm, np.arange(st.n))
        self.perm = perm
        self.n_lu = int(lp[-1] + up[-1] + st.n)
        self._arrays = {"indptr": st.indptr, "rows": st.rows, "prow": np.ascontiguousarray(prow, dtype=np.int32),
                        "perm": perm, "lp": lp, "li": li, "up": up, "ui": ui}
        self._pattern = _Pattern(st.n, st.nnz, *(_ptr(self._arrays[k]) for k, _ in _Pattern._fields_[2:]))
        self.pp = ctypes.addressof(self._pattern)
        self.buffers = _Buffers(st.n, st.nnz, self.n_lu)


_STRUCTURES: list = []                # the structures, most recent last
_MAPS: dict = {}                      # (A, B patterns) -> (structure, positions of A's, of B's nonzeros)
_LAST: list = [None, None, None]      # (A, B, Pencil) of the last call: the same pencil is refined many times


def _structure_for(A, B):
    key = (A.shape, A.indptr.tobytes(), A.indices.tobytes(), B.indptr.tobytes(), B.indices.tobytes())
    hit = _MAPS.get(key)
    if hit is not None:
        return hit
    n = A.shape[0]
    ka, kb = _keys(A), _keys(B)
    for st in reversed(_STRUCTURES):
        if st.n == n:
            ia, ib = st.locate(ka), st.locate(kb)
            if ia is not None and ib is not None:
                break
    else:
        keys = np.union1d(ka, kb)
        same = [s for s in _STRUCTURES if s.n == n]
        if same:
            keys = np.union1d(keys, same[-1].keys)
        st = _Structure(n, keys)
        _STRUCTURES.append(st)
        if len(_STRUCTURES) > 8:
            _STRUCTURES.pop(0)
        ia, ib = st.locate(ka), st.locate(kb)
    if len(_MAPS) >= 256:
        _MAPS.pop(next(iter(_MAPS)))
    hit = _MAPS[key] = (st, ia, ib)
    return hit


def pencil(A, B):
    """The :class:`Pencil` of the real sparse ``(A, B)`` (cached: the last pair by identity, the
    structure by the two patterns), or None without the compiled kernel.

    Parameters
    ----------
    A, B : scipy.sparse.spmatrix
        Real sparse matrices of the pencil (same shape).

    Returns
    -------
    Pencil or None
        The pencil.
    """
    lib = kernel()
    if lib is None:
        return None
    if _LAST[0] is A and _LAST[1] is B:
        return _LAST[2]
    A0, B0 = A, B
    A = A if sp.isspmatrix_csc(A) else sp.csc_matrix(A)
    B = B if sp.isspmatrix_csc(B) else sp.csc_matrix(B)
    if not (A.has_canonical_format and B.has_canonical_format):
        A, B = A.copy(), B.copy()
        A.sum_duplicates()
        B.sum_duplicates()
    st, ia, ib = _structure_for(A, B)
    pen = Pencil(lib, st, st.values(A.data, ia), st.values(B.data, ib))
    _LAST[:] = [A0, B0, pen]
    return pen


class Pencil:
    """``A + s B`` of one design and speed on its union pattern: factorizations and the
    inverse iteration of :func:`wingmdao.stability.sensitivity.refine_pair` in C.

    Parameters
    ----------
    lib : ctypes.CDLL
        The compiled kernel.
    st : _Structure
        Symbolic structure of the union pattern.
    a, b : numpy.ndarray
        Values of A and B on the union pattern.
    """

    def __init__(self, lib, st: _Structure, a, b):
        self.lib, self.st = lib, st
        self.n = st.n
        self.a, self.b = a, b
        self._pa, self._pb = _ptr(a), _ptr(b)
        self._x = np.zeros(self.n, dtype=complex)
        self._work = np.zeros(8 * self.n, dtype=complex)
        self.berr = 0.0
        self.growth = 0.0

    @property
    def has_pivots(self) -> bool:
        return self.st.current is not None

    def repivot(self, perm_r):
        """Use the row order of a SuperLU factorization of a matrix of this pattern from now on.

        Parameters
        ----------
        perm_r : numpy.ndarray
            SuperLU's row permutation.
        """
        self.st.use(perm_r)

    def products(self, X, trans=False):
        """``(A X, B X)`` (``trans``: ``(A^T X, B^T X)``) of an (n, k) complex X, in C
        (``pencil_products``: the summation order of SciPy's sparse products).

        Parameters
        ----------
        X : numpy.ndarray
            (n, k) complex matrix.
        trans : bool, optional
            Multiply by the transposes.

        Returns
        -------
        tuple
            (A X, B X).
        """
        X = np.ascontiguousarray(X, dtype=complex)
        k = X.shape[1]
        YA, YB = np.empty((self.n, k), dtype=complex), np.empty((self.n, k), dtype=complex)
        self.lib.pencil_products(self.st.pp, self._pa, self._pb, _ptr(X), int(k), 1 if trans else 0, _ptr(YA),
                                 _ptr(YB))
        return YA, YB

    def factor(self, s):
        """``(symbolic, factors, values of M, |values|)`` of ``M = A + s B`` with the current pivot
        order, or None when a pivot is zero or not finite (or no pivot order is chosen yet).

        Parameters
        ----------
        s : complex
            The shift.

        Returns
        -------
        tuple or None
            The factorization, or None.
        """
        sym = self.st.current
        if sym is None:
            return None
        f = np.empty(sym.n_lu, dtype=complex)
        m, ma = np.empty(self.st.nnz, dtype=complex), np.empty(self.st.nnz)
        s = complex(s)
        growth = np.zeros(1)
        bad = self.lib.pencil_factor(sym.pp, _ptr(self.a), _ptr(self.b), s.real, s.imag, _ptr(f), _ptr(m), _ptr(ma),
                                     _ptr(self._x), _ptr(growth))
        self.growth = float(growth[0])
        return None if bad or not self.growth <= GROWTH_MAX else (sym, f, m, ma)

    def solve(self, lu, rhs, trans="N", tol=BACKWARD_TOL):
        """``(x, berr)``: ``(A + s B) x = rhs`` (``trans="N"``) or ``(A + s B)^H x = rhs`` (``"H"``),
        refined once when the backward error is above ``tol``.

        Parameters
        ----------
        lu : tuple
            A factorization of :meth:`factor`.
        rhs : numpy.ndarray
            Right-hand side.
        trans : {"N", "H"}, optional
            Solve with M or with its conjugate transpose.
        tol : float, optional
            Backward error above which the solution is refined.

        Returns
        -------
        tuple
            (x, backward error).
        """
        sym, f, m, ma = lu
        rhs = _c128(rhs)
        x = np.empty(self.n, dtype=complex)
        e = self.lib.pencil_solve_checked(sym.pp, _ptr(m), _ptr(ma), _ptr(f), _ptr(rhs), _ptr(x),
                                          0 if trans == "N" else 1, float(tol), _ptr(self._work))
        return x, float(e)

    def iterate(self, s, v, u, bv, lam, lam_old, iterations, tol, btol=BACKWARD_TOL, checked=1):
        """One shift of ``refine_pair``: factor ``A + s B``, then up to ``iterations`` two-sided
        inverse-iteration steps (``pencil_iterate`` in pencil_lu.c; the solves of the first ``checked``
        steps checked a posteriori, every one bounded by the growth check). Returns ``(v, u, bv, lam,
        lam_old, converged)`` (new arrays), or None when the static pivots are bad for this shift
        (a zero pivot, growth above :data:`GROWTH_MAX` or a backward error above ``btol``): redo the
        shift with SuperLU.

        Parameters
        ----------
        s : complex
            The shift.
        v, u : numpy.ndarray
            Right and left vectors (unit 2-norm).
        bv : numpy.ndarray
            B v.
        lam, lam_old : complex
            The last two Rayleigh quotients (1/s).
        iterations : int
            Most inverse-iteration steps.
        tol : float
            Relative agreement of two quotients for convergence (< 0: every step).
        btol : float, optional
            Largest accepted backward error of a checked solve.
        checked : int, optional
            Steps whose solves are checked a posteriori.

        Returns
        -------
        tuple or None
            ``(v, u, bv, lam, lam_old, converged)``, or None.
        """
        sym = self.st.current
        if sym is None:
            return None
        bf = sym.buffers
        s = complex(s)
        bad = self.lib.pencil_factor(sym.pp, self._pa, self._pb, s.real, s.imag, bf.pf, bf.pm, bf.pma, bf.px, bf.pg)
        self.growth = float(bf.g[0])
        if bad or not self.growth <= GROWTH_MAX:
            return None
        bf.v[:], bf.u[:], bf.bv[:] = v, u, bv
        lam, lam_old = complex(lam), complex(lam_old)
        bf.lam[:] = lam.real, lam.imag, lam_old.real, lam_old.imag
        bf.berr[0] = 0.0
        status = self.lib.pencil_iterate(sym.pp, self._pa, self._pb, bf.pm, bf.pma, bf.pf, bf.pv, bf.pu, bf.pbv,
                                         bf.plam, bf.plo, int(iterations), float(tol), float(btol), int(checked),
                                         bf.pw, bf.pberr, bf.steps)
        if status < 0:
            return None
        self.berr = max(self.berr, float(bf.berr[0]))
        lr = bf.lam
        return (bf.v.copy(), bf.u.copy(), bf.bv.copy(), complex(lr[0], lr[1]), complex(lr[2], lr[3]),
                status == 1)


class _Buffers:
    """The kernel's in / out arrays of one pattern and pivot order, with their addresses (taken
    once: ``ndarray.ctypes`` costs ~5 us per array and call)."""

    def __init__(self, n, nnz, n_lu):
        self.f = np.zeros(n_lu, dtype=complex)
        self.m, self.ma = np.zeros(nnz, dtype=complex), np.zeros(nnz)
        self.x = np.zeros(n, dtype=complex)
        self.g = np.zeros(1)
        self.v, self.u, self.bv = (np.zeros(n, dtype=complex) for _ in range(3))
        self.lam = np.zeros(4)
        self.w = np.zeros(8 * n, dtype=complex)
        self.berr = np.zeros(1)
        self.steps = (ctypes.c_int * 1)(0)
        for k in ("f", "m", "ma", "x", "g", "v", "u", "bv", "lam", "w", "berr"):
            setattr(self, "p" + k, _ptr(getattr(self, k)))
        self.plo = self.plam + 2 * 8


# ---------------------------------------------------------------------- the interface of the callers
def superlu(M):
    """SciPy's SuperLU of a sparse matrix in natural column order (the node-by-node beam ordering
    has the fill of COLAMD's and factors ~2x faster, 0.9 ms for the 440-state PEGASUS pencil).

    Parameters
    ----------
    M : scipy.sparse.spmatrix
        Square sparse matrix.

    Returns
    -------
    scipy.sparse.linalg.SuperLU
        The factorization.
    """
    return spla.splu(sp.csc_matrix(M), permc_spec="NATURAL")


class ShiftLU:
    """The LU factors of one ``M = A + s B`` (:meth:`ShiftedPencil.factor`, :func:`factor`):
    :meth:`solve` with M, M^T or M^H, in the kernel when its static pivots are good for this
    shift (every solve checked by its backward error), else with SuperLU. The caller does not
    see which.

    Parameters
    ----------
    pencil : ShiftedPencil
        The pencil.
    s : complex
        The shift.
    """

    def __init__(self, pencil: ShiftedPencil, s):
        self.pencil, self.s = pencil, complex(s)
        self._kernel = None if pencil._pen is None else pencil._pen.factor(self.s)
        self._superlu = None
        if self._kernel is None:
            self._fallback()

    def _fallback(self):
        if self._superlu is None:
            p = self.pencil
            self._superlu = superlu(sp.csc_matrix(p.A + self.s * p.B, dtype=complex))
            if p._pen is not None:     # its row order for the kernel's next factorizations
                p._pen.repivot(self._superlu.perm_r)
        return self._superlu

    @property
    def compiled(self) -> bool:
        """True when the factors are the kernel's."""
        return self._kernel is not None

    def solve(self, b, trans: str = "N") -> np.ndarray:
        """``x`` of ``M x = b`` (``trans`` "N"), ``M^T x = b`` ("T") or ``M^H x = b`` ("H"); ``b``
        real or complex, (n,) or (n, k).

        Parameters
        ----------
        b : numpy.ndarray
            (n,) or (n, k) right-hand side, real or complex.
        trans : {"N", "T", "H"}, optional
            Solve with M, its transpose or its conjugate transpose.

        Returns
        -------
        numpy.ndarray
            The solution.
        """
        if trans not in ("N", "T", "H"):
            raise ValueError(f"trans = {trans!r}; allowed: 'N', 'T', 'H'")
        b = np.asarray(b, dtype=complex)
        if b.ndim == 2:
            return np.column_stack([self.solve(b[:, j], trans) for j in range(b.shape[1])]) if b.shape[1] else b
        if self._kernel is not None:
            pen = self.pencil._pen
            if trans == "T":            # M^T x = b  <=>  M^H conj(x) = conj(b)
                x, e = pen.solve(self._kernel, b.conj(), "H")
                x = x.conj()
            else:
                x, e = pen.solve(self._kernel, b, trans)
            if e <= BACKWARD_TOL:
                return x
        return self._fallback().solve(b, trans=trans)


class ShiftedPencil:
    """The real sparse pencil ``(A, B)`` of one design and speed, for the shifted matrices
    ``A + s B`` (complex s): factorizations (:meth:`factor`), the inverse-iteration steps of one
    shift (:meth:`refine`) and the products ``A X, B X`` (:meth:`products`). With the compiled
    kernel they run in C with a static pivot order (:class:`Pencil`); a shift it refuses, and
    every shift without the kernel, runs with SuperLU, whose row order the kernel then takes.
    Callers never branch on the kernel.

    Parameters
    ----------
    A, B : scipy.sparse.spmatrix
        Real sparse matrices of the pencil (same shape).
    """

    def __init__(self, A, B):
        self.A, self.B = sp.csc_matrix(A), sp.csc_matrix(B)
        self._pen = pencil(A, B)

    @property
    def compiled(self) -> bool:
        """True when the kernel is on (a shift may still run with SuperLU)."""
        return self._pen is not None

    def factor(self, s) -> ShiftLU:
        """The factors of ``A + s B``.

        Parameters
        ----------
        s : complex
            The shift.

        Returns
        -------
        ShiftLU
            The factors.
        """
        return ShiftLU(self, s)

    def products(self, X, trans=False):
        """``(A X, B X)`` (``trans``: ``(A^T X, B^T X)``) of an (n, k) complex X (the kernel's
        summation order is SciPy's).

        Parameters
        ----------
        X : numpy.ndarray
            (n, k) complex matrix.
        trans : bool, optional
            Multiply by the transposes.

        Returns
        -------
        tuple
            (A X, B X).
        """
        if self._pen is not None:
            return self._pen.products(X, trans=trans)
        return (self.A @ X, self.B @ X) if not trans else (self.A.T @ X, self.B.T @ X)

    def refine(self, s, v, u, bv, lam, lam_old, iterations, tol):
        """Two-sided inverse iteration with the one shift ``s`` (the loop of
        :func:`wingmdao.stability.modes.refine_pair`): up to ``iterations`` steps ``v <- (A + s
        B)^-1 B v``, ``u <- (A + s B)^-H B^H u`` (unit 2-norm), each followed by the two-sided
        Rayleigh quotient ``lam = -u^H A v / u^H B v``; converged when two quotients agree to
        ``tol`` relative and the vectors to ``sqrt(tol)`` (``tol < 0``: every step). Returns
        ``(v, u, B v, lam, lam_old, converged)``.

        Parameters
        ----------
        s : complex
            The shift.
        v, u : numpy.ndarray
            Right and left vectors (unit 2-norm).
        bv : numpy.ndarray
            B v.
        lam, lam_old : complex
            The last two Rayleigh quotients (1/s).
        iterations : int
            Most inverse-iteration steps.
        tol : float
            Relative agreement of two quotients for convergence (< 0: every step).

        Returns
        -------
        tuple
            ``(v, u, B v, lam, lam_old, converged)``.
        """
        pen = self._pen
        if pen is not None and pen.has_pivots:    # the kernel: the same steps in C
            step = pen.iterate(s, v, u, bv, lam, lam_old, iterations, tol)
            if step is not None:
                return step
        lu = superlu(sp.csc_matrix(self.A + s * self.B, dtype=complex))
        if pen is not None:       # no pivot order yet, or it failed this shift: take SuperLU's
            pen.repivot(lu.perm_r)
        A, B = self.A, self.B
        BH = B.conj().T
        for _ in range(int(iterations)):
            v_new = lu.solve(np.asarray(bv))
            v_new /= np.linalg.norm(v_new)
            u_new = lu.solve(np.asarray(BH @ u), trans="H")
            u_new /= np.linalg.norm(u_new)
            dv = max(_change(v_new, v), _change(u_new, u))
            v, u = v_new, u_new
            bv = B @ v        # the quotient's and the next step's
            lam = complex(-np.vdot(u, A @ v) / np.vdot(u, bv))
            # converged: the quotient to tol and the vectors (the gradient needs them; the
            # quotient is second order in their errors) to sqrt(tol)
            if abs(lam - lam_old) <= tol * abs(lam) and dv <= np.sqrt(tol):
                return v, u, bv, lam, lam_old, True
            lam_old = lam
        return v, u, bv, lam, lam_old, False


def _change(a, b):
    """Phase-aligned change of a unit vector."""
    ph = np.vdot(b, a)
    return np.linalg.norm(a - b * (ph / abs(ph) if ph != 0 else 1.0))


def factor(M) -> ShiftLU:
    """The LU of a sparse real or complex matrix ``M`` (``Re M + 1j Im M``: the pencil
    ``(Re M, Im M)`` at the shift 1j), for repeated solves with M, M^T or M^H
    (:meth:`ShiftLU.solve`): the kernel when it is on and its pivots hold, else SuperLU.

    Parameters
    ----------
    M : scipy.sparse.spmatrix
        Square sparse matrix, real or complex.

    Returns
    -------
    ShiftLU
        The factors.
    """
    M = sp.csc_matrix(M)
    if np.iscomplexobj(M.data):
        return ShiftedPencil(sp.csc_matrix(M.real), sp.csc_matrix(M.imag)).factor(1j)
    return ShiftedPencil(M, sp.csc_matrix(M.shape)).factor(0.0)
