"""The BDF march's Newton iterations in compiled code (``bdf_step.c``), for compiled systems.

:func:`wingmdao.timemarch.bdf.march` spends ~240 us per step of the 20-node beam in Python around
compiled CasADi functions of ~5 us (docs/time-marching.md, Sec. 7). When the residual and Newton
functions of a :class:`~wingmdao.timemarch.system.CasadiResidualSystem` are compiled libraries,
:class:`FastStepper` calls them through their C entry points (``int NAME(const double** arg,
double** res, long long* iw, double* w, int mem)``, sizes from ``NAME_work``) from a small C
routine that runs the whole march: predictor and BDF history, the Newton iteration of
``_StepSolver.solve`` (the same tests in the same floating-point order) and a sparse LU with
partial pivoting of its own in place of SuperLU. Python is re-entered only between chunks of
steps (a progress callback) and on failure, which is then reported with the messages of the
interpreted path.

The C source is compiled once per machine with gcc by :mod:`wingmdao.utils.c_library` (the
cache folder and safety rules of :mod:`wingmdao.utils.casadi_cache`: keyed by its SHA-256, the
flags and the compiler, written atomically, manifest and ownership checked before loading).
"""

from __future__ import annotations

import ctypes as C
import threading
from pathlib import Path

import numpy as np

from wingmdao.timemarch import lu_orders
from wingmdao.utils import casadi_cache as cc
from wingmdao.utils.c_library import open_compiled

SOURCE = Path(__file__).with_name("bdf_step.c")
#: -O2 (a 300-line file compiles in ~0.3 s); no fused multiply-adds, so the arithmetic of the
#: convergence tests rounds like numpy's
FLAGS = ("-O2", "-ffp-contract=off")
#: status codes of ``wm_bdf_step``
OK, RES_NONFINITE, STEP_NONFINITE, SINGULAR, NO_CONVERGENCE, CAPACITY, FUNCTION = range(7)

_lib = None
_lib_lock = threading.Lock()

_p = C.c_void_p
_i = C.c_int
_d = C.c_double


class _Step(C.Structure):
    """Mirror of ``wm_step`` in bdf_step.c (same order)."""

    _fields_ = [("n", _i),
                ("res_f", _p), ("res_arg", _p), ("res_res", _p), ("res_iw", _p), ("res_w", _p),
                ("jac_f", _p), ("jac_arg", _p), ("jac_res", _p), ("jac_iw", _p), ("jac_w", _p),
                ("Ap", _p), ("Ai", _p), ("Ax", _p), ("p", _p), ("q", _p),
                ("xdot", _p), ("r", _p), ("dx", _p), ("alpha_buf", _d),
                ("Lp", _p), ("Li", _p), ("Up", _p), ("Ui", _p), ("pinv", _p), ("Lx", _p), ("Ux", _p),
                ("cap_L", _i), ("cap_U", _i), ("work", _p), ("xi", _p), ("mark", _p), ("stamp", _i),
                ("atol", _d), ("xtol", _d), ("contraction", _d), ("max_iter", _i), ("modified", _i),
                ("lu_valid", _i), ("lu_alpha", _d), ("factorizations", _i),
                ("iterations", _i), ("fail_iteration", _i), ("hist", _p), ("qcol", _p)]


def library() -> C.CDLL:
    """The compiled ``bdf_step.c`` (compiled into the cache at first use, ~0.3 s)."""
    global _lib
    with _lib_lock:
        if _lib is None:
            _lib = open_compiled(SOURCE, "wm_bdf_step", FLAGS)[0]   # (rebuilt if the cached one does not load)
            _lib.wm_bdf_step.argtypes = [C.POINTER(_Step), _p, _p, _d]
            _lib.wm_bdf_step.restype = _i
            _lib.wm_march.argtypes = [C.POINTER(_Step), _p, _p, _i, _d, _i, _i, _p, C.POINTER(_i)]
            _lib.wm_march.restype = _i
            _lib.wm_lu_test.argtypes = [C.POINTER(_Step), _p, _p]
            _lib.wm_lu_test.restype = _i
        return _lib


_ENTRIES: dict = {}


def _casadi_entry(jit: cc.JitFunction):
    """``(library, function pointer, arg, res, iw, w arrays)`` of a compiled JitFunction's
    library (fresh work arrays), or None when it is not compiled or its calling convention is
    not the one of bdf_step.c. The library is verified and opened once per process and path."""
    if jit.state != "compiled":
        return None
    path = cc.library_path(jit.interpreted, jit.flags, jit.key())
    if path not in _ENTRIES:
        _ENTRIES[path] = _open_entry(jit.interpreted, path)
    entry = _ENTRIES[path]
    if entry is None:
        return None
    lib, fptr, sizes = entry
    n_arg, n_res, n_iw, n_w = sizes
    return (lib, fptr, np.zeros(n_arg, dtype=np.uintp), np.zeros(n_res, dtype=np.uintp),
            np.zeros(n_iw, dtype=np.int64), np.zeros(n_w))


def _open_entry(fun, path):
    for i in range(fun.n_in()):
        if not fun.sparsity_in(i).is_dense():
            return None
    if not fun.sparsity_out(0).is_dense():
        return None
    try:
        cc.verify(path)
        lib = C.CDLL(str(path))
        name = fun.name()
        f = getattr(lib, name)
        work = getattr(lib, name + "_work")
        isize = getattr(lib, name + "_casadi_int_size")
        rsize = getattr(lib, name + "_casadi_real_size")
    except (OSError, AttributeError, cc.CompileError):
        return None
    if isize() != 8 or rsize() != 8:
        return None
    sz = [C.c_longlong() for _ in range(4)]
    work.argtypes = [C.POINTER(C.c_longlong)] * 4
    if work(*[C.byref(s) for s in sz]) != 0:
        return None
    n_arg, n_res, n_iw, n_w = (max(int(s.value), 1) for s in sz)
    return lib, C.cast(f, _p).value, (max(n_arg, fun.n_in()), max(n_res, fun.n_out()), n_iw, n_w)


class FastStepper:
    """State of the compiled march of one system (see the module docstring).

    ``FastStepper.create(system, p, ...)`` returns None when the system's residual or Newton
    function is not compiled (interpreted CasADi, ``WINGMDAO_JIT=0``), or bdf_step.c cannot be
    compiled; the caller then uses the Python path.

    Parameters
    ----------
    system : CasadiResidualSystem
        The system, with compiled residual and Newton-matrix functions.
    p : array_like, shape (n_param,)
        Packed parameters (fixed for the march).
    res_entry : tuple
        ``(library, function pointer, arg, res, iw, w)`` of the compiled residual function.
    jac_entry : tuple
        The same for the compiled Newton-matrix function.
    rows : array_like of int, shape (nnz,)
        Row indices of the Newton-matrix pattern (CSC).
    indptr : array_like of int, shape (n_state + 1,)
        Column pointers of the Newton-matrix pattern (CSC).
    atol : float
        Absolute tolerance on ``max|R|``.
    xtol : float
        Tolerance on the Newton step relative to ``1 + max|x|``.
    max_iter : int
        Most Newton iterations per step.
    modified : bool
        Reuse the LU across iterations and steps while the iteration contracts (modified Newton).
    contraction : float
        Modified Newton keeps its LU while each step is at most this fraction of the previous one.
    """

    #: entries of L and of U the buffers hold at first (None: n (n + 1) / 2 up to 1200 states)
    initial_capacity = None

    def __init__(self, system, p, res_entry, jac_entry, rows, indptr, *, atol, xtol, max_iter,
                 modified, contraction):
        n = system.n_state
        self.system, self.n, self.lib = system, n, library()
        self._keep = [res_entry, jac_entry]           # libraries and their work arrays
        self.p = np.array(p, dtype=float).reshape(system.n_param)
        self.Ap = np.ascontiguousarray(indptr, dtype=np.int32)
        self.Ai = np.ascontiguousarray(rows, dtype=np.int32)
        nnz = self.Ai.size
        self.Ax = np.zeros(nnz)
        self.xdot, self.r, self.dx, self.work = (np.zeros(n) for _ in range(4))
        self.Lp, self.Up, self.pinv = np.zeros(n + 1, np.int32), np.zeros(n + 1, np.int32), np.zeros(n, np.int32)
        self.xi, self.mark = np.zeros(2 * n, np.int32), np.zeros(n, np.int32)
        self.hist = np.zeros(n)
        order = lu_orders.system_lu_column_order(system)     # fill-reducing column order (None: natural)
        self.qcol = None if order is None else np.ascontiguousarray(order, dtype=np.int32)
        s = self.s = _Step()
        s.n = n
        s.res_f, s.jac_f = res_entry[1], jac_entry[1]
        for pre, e in (("res", res_entry), ("jac", jac_entry)):
            for name, arr in zip(("arg", "res", "iw", "w"), e[2:]):
                setattr(s, f"{pre}_{name}", arr.ctypes.data)
        for name in ("Ap", "Ai", "Ax", "p", "xdot", "r", "dx", "Lp", "Up", "pinv", "work", "xi", "mark", "hist"):
            setattr(s, name, getattr(self, name).ctypes.data)
        s.qcol = None if self.qcol is None else self.qcol.ctypes.data
        # worst case (dense triangles) for moderate sizes; larger systems grow on demand
        cap = self.initial_capacity or (n * (n + 1) // 2 if n <= 1200 else max(20 * nnz, 4 * n))
        self._set_capacity(cap)
        s.atol, s.xtol, s.contraction = float(atol), float(xtol), float(contraction)
        s.max_iter, s.modified = int(max_iter), int(bool(modified))
        s.stamp, s.lu_valid, s.lu_alpha, s.factorizations = 0, 0, 0.0, 0

    @classmethod
    def create(cls, system, p, **opts):
        """A stepper for ``system``, or None when its functions or bdf_step.c are not compiled.

        Parameters
        ----------
        system : ResidualSystem
            The system; only one with ``compiled_step_functions()`` returning compiled functions
            gives a stepper.
        p : array_like, shape (n_param,)
            Packed parameters.
        **opts
            Keyword arguments of the constructor (``atol``, ``xtol``, ``max_iter``, ``modified``,
            ``contraction``).

        Returns
        -------
        FastStepper or None
            The stepper, or None (the caller then uses the Python path).
        """
        getter = getattr(system, "compiled_step_functions", None)
        if getter is None:
            return None
        funcs = getter()
        if funcs is None:
            return None
        res_jit, jac_jit, rows, indptr = funcs
        res_entry, jac_entry = _casadi_entry(res_jit), _casadi_entry(jac_jit)
        if res_entry is None or jac_entry is None:
            return None
        try:
            library()
        except (OSError, cc.CompileError) as exc:
            cc._warn_once(exc)
            return None
        return cls(system, p, res_entry, jac_entry, rows, indptr, **opts)

    def _set_capacity(self, cap):
        self.Li, self.Ui = np.zeros(cap, np.int32), np.zeros(cap, np.int32)
        self.Lx, self.Ux = np.zeros(cap), np.zeros(cap)
        s = self.s
        s.Li, s.Ui, s.Lx, s.Ux = (a.ctypes.data for a in (self.Li, self.Ui, self.Lx, self.Ux))
        s.cap_L = s.cap_U = int(cap)

    @property
    def factorizations(self) -> int:
        return int(self.s.factorizations)

    def solve(self, x, hist, alpha, q):
        """Newton iterations of one step from ``x`` (contiguous float array, updated in place);
        returns ``(status, iterations)``; on failure ``self.r`` is the residual to report and
        ``self.s.fail_iteration`` the iteration.

        Parameters
        ----------
        x : ndarray of float64, shape (n_state,)
            Predicted state, C-contiguous; overwritten with the solution.
        hist : ndarray, shape (n_state,)
            BDF history term, so that ``xdot = alpha x + hist`` (1/s units of the state).
        alpha : float
            Leading BDF coefficient divided by dt (1/s).
        q : ndarray of float64, shape (n_forcing,)
            Packed forcing of the step, C-contiguous.

        Returns
        -------
        status : int
            Status code (:data:`OK` on success).
        iterations : int
            Newton iterations.
        """
        for name, arr, size in (("x", x, self.n), ("q", q, self.system.n_forcing)):
            if arr.dtype != np.float64 or arr.size != size or not arr.flags.c_contiguous:
                raise ValueError(f"{name}: need a C-contiguous float64 array of {size} entries, "
                                 f"got {arr.dtype} {arr.shape}")
        s = self.s
        s.q = q.ctypes.data
        self.hist[:] = hist
        x0 = x.copy()
        while True:
            status = self.lib.wm_bdf_step(C.byref(s), x.ctypes.data, self.hist.ctypes.data, float(alpha))
            if status != CAPACITY:
                return status, int(s.iterations)
            # the factors did not fit: larger buffers, the step again from its start (the LU
            # kept from earlier steps was overwritten, so this step refactors first)
            self._set_capacity(2 * s.cap_L)
            x[:] = x0
            s.lu_valid = 0

    def march(self, X, Q, dt, iters, first, end):
        """Steps ``first .. end - 1`` of a march into ``X`` (n_time, n) C-contiguous float, rows
        before ``first`` known; ``Q`` (n_time, n_forcing) C-contiguous float; ``iters`` int64.
        Returns ``(status, step)``: the failed step, or ``end`` on success.

        Parameters
        ----------
        X : ndarray of float64, shape (n_time, n_state)
            State history, C-contiguous; rows before ``first`` are known, later rows are written.
        Q : ndarray of float64, shape (n_time, n_forcing)
            Packed forcing history, C-contiguous.
        dt : float
            Time step (s).
        iters : ndarray of int64, shape (n_time,)
            Newton iterations per step (written).
        first : int
            First step to march (at least 1).
        end : int
            One past the last step to march (at most n_time).

        Returns
        -------
        status : int
            Status code (:data:`OK` on success).
        step : int
            The failed step, or ``end`` on success.
        """
        n_time = X.shape[0]
        for name, arr, dtype, shape in (("X", X, np.float64, (n_time, self.n)),
                                        ("Q", Q, np.float64, (n_time, self.system.n_forcing)),
                                        ("iters", iters, np.int64, (n_time,))):
            if arr.dtype != dtype or arr.shape != shape or not arr.flags.c_contiguous:
                raise ValueError(f"{name}: need a C-contiguous {np.dtype(dtype).name} array of shape {shape}, "
                                 f"got {arr.dtype} {arr.shape}")
        if not 1 <= first <= end <= n_time:
            raise ValueError(f"steps {first}..{end - 1}: need 1 <= first <= end <= {n_time}")
        s, failed = self.s, _i(end)
        while True:
            status = self.lib.wm_march(C.byref(s), X.ctypes.data, Q.ctypes.data, int(Q.shape[1]), float(dt),
                                       int(first), int(end), iters.ctypes.data, C.byref(failed))
            if status != CAPACITY:
                return status, (end if status == OK else int(failed.value))
            # the factors did not fit: larger buffers, that step again from its predictor (the LU
            # kept from earlier steps was overwritten, so the step refactors first)
            self._set_capacity(2 * s.cap_L)
            s.lu_valid = 0
            first = int(failed.value)

    def lu_test(self, values, b):
        """Factor the Newton-matrix pattern with ``values`` and solve for ``b`` (tests).

        Parameters
        ----------
        values : array_like, shape (nnz,)
            Entries of the Newton matrix in the order of its CSC pattern.
        b : array_like, shape (n_state,)
            Right-hand side.

        Returns
        -------
        status : int
            Status code of the factorization.
        x : ndarray, shape (n_state,)
            The solution.
        """
        self.Ax[:] = values
        b = np.ascontiguousarray(b, dtype=float).copy()
        out = np.zeros(self.n)
        status = self.lib.wm_lu_test(C.byref(self.s), b.ctypes.data, out.ctypes.data)
        return status, out
