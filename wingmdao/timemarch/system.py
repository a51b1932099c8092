"""Residual systems R(x, xdot, p, q) = 0 for one time instant, and their sparse Jacobians.

A *residual system* is the unit the time marcher, the static solver and the discrete
adjoint work on (Sec. 3.5.2): ``x`` is the state at one instant, ``xdot`` its time
derivative, ``p`` the time-invariant parameters (design-dependent data such as section
stiffness and geometry) and ``q`` the forcing at that instant (loads). The layouts of ``p``
and ``q`` are described by :class:`VarSpec` lists so that an OpenMDAO component can
expose each piece as a named, unit-carrying input.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np
import scipy.sparse as sp

from wingmdao.utils.casadi_cache import JitCall, compile_calls
from wingmdao.timemarch import fast_step, static_lu


#: CasADi systems up to this many states return a dense Newton matrix (less overhead).
DENSE_NEWTON_MAX = 40


@dataclass(frozen=True)
class VarSpec:
    """A named block of a flat parameter or forcing vector (shape, units, description).

    Parameters
    ----------
    name : str
        Name of the block.
    shape : tuple of int
        Shape of the block (``()`` for a scalar).
    units : str, optional
        OpenMDAO units string.
    desc : str
        Description.
    """

    name: str
    shape: tuple = ()
    units: str | None = None
    desc: str = ""

    @property
    def size(self) -> int:
        return math.prod(int(d) for d in self.shape) if self.shape else 1   # (np.prod: ~5 us per call)


def layout(specs) -> dict[str, slice]:
    """Slices of each :class:`VarSpec` in the flat vector made by concatenating them in order.

    Parameters
    ----------
    specs : sequence of VarSpec
        The blocks, in order.

    Returns
    -------
    dict of str to slice
        Slice of each block's name in the flat vector.
    """
    out, start = {}, 0
    for s in specs:
        out[s.name] = slice(start, start + s.size)
        start += s.size
    return out


def pack(specs, values: dict) -> np.ndarray:
    """Flatten ``{name: array}`` into one vector in the order of ``specs``.

    Parameters
    ----------
    specs : sequence of VarSpec
        The blocks, in order.
    values : dict
        ``{name: array_like}``, each reshaped to the block's size.

    Returns
    -------
    ndarray
        The flat vector (empty without specs).
    """
    if not specs:
        return np.zeros(0)
    return np.concatenate([np.asarray(values[s.name], dtype=float).reshape(s.size) for s in specs])


def derived(system, name: str, build):
    """``build(system)``, made once per system and kept on it (in ``system._derived[name]``):
    what is derived from a system (its pencil and eigenvalue-gradient functions, its parameter
    blocks) lives and dies with the system, instead of in a module cache keyed by ``id``. A
    :class:`ResidualSystem` pickles without them (an OpenMDAO recorder pickles the components'
    options, which hold the system; compiled functions do not pickle).

    Parameters
    ----------
    system : ResidualSystem
        The system that keeps the result.
    name : str
        Key of the result.
    build : callable
        ``build(system)`` makes it (called once).

    Returns
    -------
    object
        The stored result of ``build(system)``.
    """
    store = vars(system).setdefault("_derived", {})
    if name not in store:
        store[name] = build(system)
    return store[name]


class ResidualSystem:
    """Interface of a first-order implicit system R(x, xdot, p, q) = 0 at one instant.

    Attributes set by implementations: ``n_state``, ``state_shape`` (how the flat state is
    shown to users, e.g. ``(n_node, 18)``), ``param_specs`` and ``forcing_specs`` (lists of
    :class:`VarSpec`), ``n_param``, ``n_forcing``.
    """

    n_state: int
    state_shape: tuple
    param_specs: list
    forcing_specs: list

    def __getstate__(self):
        state = self.__dict__.copy()
        state.pop("_derived", None)       # rebuilt on demand (:func:`derived`)
        return state

    @property
    def n_param(self) -> int:
        return sum(s.size for s in self.param_specs)

    @property
    def n_forcing(self) -> int:
        return sum(s.size for s in self.forcing_specs)

    def residual(self, x, xdot, p, q) -> np.ndarray:
        """Residual ``R(x, xdot, p, q)`` at one instant.

        Parameters
        ----------
        x : ndarray, shape (n_state,)
            State.
        xdot : ndarray, shape (n_state,)
            State rate.
        p : ndarray, shape (n_param,)
            Packed parameters.
        q : ndarray, shape (n_forcing,)
            Packed forcing.

        Returns
        -------
        ndarray, shape (n_state,)
            The residual R.
        """
        raise NotImplementedError

    def jac_state(self, x, xdot, p, q) -> tuple[sp.csc_matrix, sp.csc_matrix]:
        """(dR/dx, dR/dxdot), sparse.

        Parameters
        ----------
        x : ndarray, shape (n_state,)
            State.
        xdot : ndarray, shape (n_state,)
            State rate.
        p : ndarray, shape (n_param,)
            Packed parameters.
        q : ndarray, shape (n_forcing,)
            Packed forcing.

        Returns
        -------
        dR_dx, dR_dxdot : scipy.sparse.csc_matrix, shape (n_state, n_state)
            The state Jacobians.
        """
        raise NotImplementedError

    def jac_inputs(self, x, xdot, p, q) -> tuple[sp.csc_matrix, sp.csc_matrix]:
        """(dR/dp, dR/dq), sparse.

        Parameters
        ----------
        x : ndarray, shape (n_state,)
            State.
        xdot : ndarray, shape (n_state,)
            State rate.
        p : ndarray, shape (n_param,)
            Packed parameters.
        q : ndarray, shape (n_forcing,)
            Packed forcing.

        Returns
        -------
        dR_dp : scipy.sparse.csc_matrix, shape (n_state, n_param)
            Parameter Jacobian.
        dR_dq : scipy.sparse.csc_matrix, shape (n_state, n_forcing)
            Forcing Jacobian.
        """
        raise NotImplementedError

    def describe_equation(self, index: int) -> str:
        """Human-readable name of residual ``index`` (used in convergence diagnostics).

        Parameters
        ----------
        index : int
            Index of the residual in the flat vector.

        Returns
        -------
        str
            The name.
        """
        return f"equation {index}"

    # ---- optional fast paths; the defaults below only use the methods above -------------
    def count_march_steps(self, n_steps: int) -> None:
        """A march of ``n_steps`` steps is about to run (systems that compile their functions
        after a number of evaluations count it; nothing here).

        Parameters
        ----------
        n_steps : int
            Number of BDF steps of the march.
        """

    def lu_column_order(self):
        """Fill-reducing column order Q of the adjoint's static-pivot LU of the Newton matrices,
        ``P A Q = L U`` (:mod:`wingmdao.timemarch.static_lu`), an int array of the states; None:
        natural order. Any permutation gives the same solutions (each solve is checked by its
        backward error); a good one lowers the factorization work."""
        return None

    def initial_guess(self, p, q) -> np.ndarray:
        """Starting point of a static Newton solve (zeros unless the system knows better).

        Parameters
        ----------
        p : ndarray, shape (n_param,)
            Packed parameters.
        q : ndarray, shape (n_forcing,)
            Packed forcing.

        Returns
        -------
        ndarray, shape (n_state,)
            The guess.
        """
        return np.zeros(self.n_state)

    def residual_and_newton_matrix(self, x, xdot, p, q, alpha):
        """``R`` and the Newton matrix ``dR/dx + alpha dR/dxdot`` (Eq. 3.7).

        Sparse CSC, or a dense ndarray for systems of at most ``DENSE_NEWTON_MAX`` states.

        Parameters
        ----------
        x : ndarray, shape (n_state,)
            State.
        xdot : ndarray, shape (n_state,)
            State rate.
        p : ndarray, shape (n_param,)
            Packed parameters.
        q : ndarray, shape (n_forcing,)
            Packed forcing.
        alpha : float
            Leading BDF coefficient divided by dt (1/s).

        Returns
        -------
        R : ndarray, shape (n_state,)
            The residual.
        matrix : scipy.sparse.csc_matrix or ndarray, shape (n_state, n_state)
            ``dR/dx + alpha dR/dxdot``.
        """
        jx, jxd = self.jac_state(x, xdot, p, q)
        return self.residual(x, xdot, p, q), sp.csc_matrix(jx + alpha * jxd)

    def jacobian_patterns(self) -> dict:
        """Fixed sparsity of the four Jacobians: ``{"x"|"xdot"|"p"|"q": (rows, cols, shape)}``.

        The default declares them dense; CasADi systems return their exact patterns.
        """
        out = {}
        for key, n in (("x", self.n_state), ("xdot", self.n_state), ("p", self.n_param),
                       ("q", self.n_forcing)):
            rows, cols = np.meshgrid(np.arange(self.n_state), np.arange(n), indexing="ij")
            # column-major (CSC) order, like the CasADi patterns
            out[key] = (rows.T.ravel(), cols.T.ravel(), (self.n_state, n))
        return out

    def residual_history(self, X, Xdot, p, Q) -> np.ndarray:
        """Residuals at every instant: ``X, Xdot`` (n_time, n_state), ``Q`` (n_time, n_forcing).

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            States at every instant.
        Xdot : ndarray, shape (n_time, n_state)
            State rates at every instant.
        p : ndarray, shape (n_param,)
            Packed parameters (time-invariant).
        Q : ndarray, shape (n_time, n_forcing)
            Packed forcing at every instant.

        Returns
        -------
        ndarray, shape (n_time, n_state)
            The residuals.
        """
        return np.array([self.residual(X[i], Xdot[i], p, Q[i]) for i in range(X.shape[0])])

    def jacobian_history(self, X, Xdot, p, Q) -> dict:
        """Nonzeros of the four Jacobians at every instant, in :meth:`jacobian_patterns` order.

        Returns ``{"x"|"xdot"|"p"|"q": array (n_time, nnz)}``.

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            States at every instant.
        Xdot : ndarray, shape (n_time, n_state)
            State rates at every instant.
        p : ndarray, shape (n_param,)
            Packed parameters (time-invariant).
        Q : ndarray, shape (n_time, n_forcing)
            Packed forcing at every instant.
        """
        pats = self.jacobian_patterns()
        out = {k: np.zeros((X.shape[0], pats[k][0].size)) for k in pats}
        for i in range(X.shape[0]):
            jx, jxd = self.jac_state(X[i], Xdot[i], p, Q[i])
            jp, jq = self.jac_inputs(X[i], Xdot[i], p, Q[i])
            for key, mat in (("x", jx), ("xdot", jxd), ("p", jp), ("q", jq)):
                rows, cols, _ = pats[key]
                if rows.size:
                    out[key][i] = np.asarray(sp.csr_matrix(mat)[rows, cols]).ravel()
        return out

    def state_jacobian_history(self, X, Xdot, p, Q) -> dict:
        """Nonzeros of dR/dx and dR/dxdot at every instant (``{"x", "xdot"}``, as
        :meth:`jacobian_history`): what the sweeps of
        :class:`~wingmdao.timemarch.adjoint.LinearizedHistory` factor. The default is
        :meth:`jacobian_history`, whose "p" and "q" entries the caller then keeps.

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            States at every instant.
        Xdot : ndarray, shape (n_time, n_state)
            State rates at every instant.
        p : ndarray, shape (n_param,)
            Packed parameters (time-invariant).
        Q : ndarray, shape (n_time, n_forcing)
            Packed forcing at every instant.

        Returns
        -------
        dict
            ``{key: ndarray (n_time, nnz)}`` of nonzeros, in :meth:`jacobian_patterns` order.
        """
        return self.jacobian_history(X, Xdot, p, Q)

    def input_jacobian_history(self, X, Xdot, p, Q) -> dict:
        """Nonzeros of dR/dp and dR/dq at every instant (``{"p", "q"}``); default
        :meth:`jacobian_history`.

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            States at every instant.
        Xdot : ndarray, shape (n_time, n_state)
            State rates at every instant.
        p : ndarray, shape (n_param,)
            Packed parameters (time-invariant).
        Q : ndarray, shape (n_time, n_forcing)
            Packed forcing at every instant.

        Returns
        -------
        dict
            ``{key: ndarray (n_time, nnz)}`` of nonzeros, in :meth:`jacobian_patterns` order.
        """
        return self.jacobian_history(X, Xdot, p, Q)

    def input_vjp_history(self, X, Xdot, p, Q, Lam):
        """``(sum_n dR_n/dp^T lam_n, [dR_n/dq_n^T lam_n]_n)`` of weights ``Lam`` (n_time, n_state)
        without forming dR/dp, dR/dq (reverse mode), or None when the system has no such product
        (the caller then uses :meth:`input_jacobian_history`).

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            States at every instant.
        Xdot : ndarray, shape (n_time, n_state)
            State rates at every instant.
        p : ndarray, shape (n_param,)
            Packed parameters (time-invariant).
        Q : ndarray, shape (n_time, n_forcing)
            Packed forcing at every instant.
        Lam : ndarray, shape (n_time, n_state)
            Weights of the residuals at every instant (e.g. adjoint vectors).

        Returns
        -------
        tuple or None
            ``(gp (n_param,), gq (n_time, n_forcing))``, or None without the product.
        """
        return None


class _SparseJacobian:
    """Evaluate a CasADi Jacobian into a scipy CSC matrix with a fixed sparsity pattern."""

    def __init__(self, fun: ca.Function, expr, wrt, args, tag: str, jac=None):
        """``jac``: ``ca.jacobian(expr, wrt)`` when the caller has it already (a stored build)."""
        jac = ca.jacobian(expr, wrt) if jac is None else jac
        if jac.shape != (expr.numel(), wrt.numel()):
            raise ValueError(f"dR/d{tag}: shape {jac.shape}, expected {(expr.numel(), wrt.numel())}")
        spty = jac.sparsity()
        colind, row = spty.get_ccs()
        self.shape = (spty.size1(), spty.size2())
        self.indptr = np.asarray(colind, dtype=np.int64)
        self.indices = np.asarray(row, dtype=np.int64)
        self.nnz = spty.nnz()
        self.expr = jac
        self._fun, self._fun_def = None, (f"{fun.name()}_jac_{tag}", args)

    @property
    def fun(self) -> ca.Function:
        """The CasADi function of this Jacobian, made at first use (the fused Newton and
        Jacobian-history functions serve the solvers; making all four up front cost ~0.1 s)."""
        if self._fun is None:
            name, args = self._fun_def
            self._fun = ca.Function(name, args, [self.expr])
        return self._fun

    def __call__(self, *vals) -> sp.csc_matrix:
        data = np.asarray(self.fun(*vals).nonzeros(), dtype=float)
        return sp.csc_matrix((data, self.indices, self.indptr), shape=self.shape)

    def pattern(self):
        """(rows, cols, shape) of the nonzeros in CSC order."""
        cols = np.repeat(np.arange(self.shape[1]), np.diff(self.indptr))
        return self.indices.copy(), cols, self.shape


#: Evaluations of a system function after which it is compiled in the background (module docs of
#: wingmdao.utils.casadi_cache); about two 500-step marches of a beam.
JIT_THRESHOLD = 2000


class CasadiResidualSystem(ResidualSystem):
    """A :class:`ResidualSystem` from symbolic CasADi expressions.

    ``x, xdot, p, q`` are CasADi symbols (SX or MX column vectors) and ``R`` the residual
    expression. Jacobians are exact (CasADi AD) and sparse; their patterns are fixed once.
    ``definition``: what defines the expressions (``wingmdao.utils.casadi_cache.definition_key``
    of the builder), the key of their compiled libraries; None keys them by serialization.
    ``lu_column_order``: the column order of the adjoint's static LU (:meth:`lu_column_order`).
    ``jacobians``: ``{"x", "xdot", "p", "q"}`` -> ``ca.jacobian(R, x)``, ... in these symbols, when
    the builder has them already (stored by definition: the coupled aeroelastic beam's take 3.8 s
    to form); None forms them here.

    Parameters
    ----------
    x : casadi.SX or casadi.MX
        State symbol (column vector).
    xdot : casadi.SX or casadi.MX
        State-rate symbol, same size as ``x``.
    p : casadi.SX or casadi.MX
        Parameter symbol.
    q : casadi.SX or casadi.MX
        Forcing symbol.
    R : casadi.SX or casadi.MX
        Residual expression, one equation per state.
    param_specs : sequence of VarSpec
        Blocks of ``p`` (their sizes must add up to its size).
    forcing_specs : sequence of VarSpec
        Blocks of ``q``.
    state_shape : tuple of int, optional
        How the flat state is shown to users; default ``(n_state,)``.
    name : str
        Name of the CasADi functions.
    describe : callable, optional
        ``describe(i) -> str`` names residual ``i``.
    initial_guess : callable, optional
        ``initial_guess(p, q)`` returns the start of a static solve; default zeros.
    definition : optional
        Key of the expressions' compiled libraries (see above); None keys them by serialization.
    lu_column_order : array_like of int, optional
        Column order of the adjoint's static LU; None: natural order.
    jacobians : dict, optional
        Symbolic Jacobians ``{"x", "xdot", "p", "q"}`` already formed; None forms them.
    """

    #: the static LU's column order (None: natural; subclasses that build lazily set it themselves)
    _lu_column_order = None

    def __init__(self, x, xdot, p, q, R, *, param_specs, forcing_specs, state_shape=None,
                 name="residual", describe=None, initial_guess=None, definition=None, lu_column_order=None,
                 jacobians=None):
        self.n_state = int(x.numel())
        self.state_shape = tuple(state_shape) if state_shape else (self.n_state,)
        self.param_specs = list(param_specs)
        self.forcing_specs = list(forcing_specs)
        if self.n_param != p.numel() or self.n_forcing != q.numel():
            raise ValueError("parameter/forcing specs do not match the sizes of p and q")
        if R.numel() != self.n_state:
            raise ValueError(f"residual has {R.numel()} equations for {self.n_state} states")
        args = [x, xdot, p, q]
        self._R = ca.Function(name, args, [R])
        jac = jacobians or {}
        self._dx = _SparseJacobian(self._R, R, x, args, "x", jac.get("x"))
        self._dxdot = _SparseJacobian(self._R, R, xdot, args, "xdot", jac.get("xdot"))
        self._dp = _SparseJacobian(self._R, R, p, args, "p", jac.get("p"))
        self._dq = _SparseJacobian(self._R, R, q, args, "q", jac.get("q"))
        self._describe = describe
        self._initial_guess = initial_guess
        self._lu_column_order = None if lu_column_order is None else np.asarray(lu_column_order, dtype=np.int64)
        # one call per Newton iteration: residual and the Newton matrix dR/dx + alpha dR/dxdot
        alpha = ca.SX.sym("alpha") if isinstance(x, ca.SX) else ca.MX.sym("alpha")
        newton = self._dx.expr + alpha * self._dxdot.expr   # the same Jacobians, not recomputed
        spty = newton.sparsity()
        colind, row = spty.get_ccs()
        self._newton_pattern = (np.asarray(row, dtype=np.int64), np.asarray(colind, dtype=np.int64))
        self._newton = ca.Function(f"{name}_newton", args + [alpha], [R, newton.nz[:]])
        self._all_jac = ca.Function(f"{name}_jacobians", args,
                                    [j.expr.nz[:] for j in (self._dx, self._dxdot, self._dp, self._dq)])
        self._R_args = args
        self._newton_dense_index = None
        self.jit_threshold = JIT_THRESHOLD
        self.definition = definition
        self._fast_R = JitCall(self._R, self.jit_threshold, definition=definition)
        self._fast_newton = JitCall(self._newton, self.jit_threshold, definition=definition)
        self._maps = {"R": self._fast_R, "J": JitCall(self._all_jac, self.jit_threshold, definition=definition)}

    def set_jit_threshold(self, evaluations: int) -> None:
        """Evaluations after which each function is compiled in the background (0: at first use).

        Parameters
        ----------
        evaluations : int
            The threshold.
        """
        self.jit_threshold = int(evaluations)
        for call in (self._fast_R, self._fast_newton, *self._maps.values()):
            call.jit.threshold = self.jit_threshold

    def compile(self, wait: bool = True) -> dict:
        """Compile (or load from the cache) the residual, the Newton-matrix function and the
        history functions (:data:`HISTORY_PARTS`: the four Jacobians and the input
        vector-Jacobian product) now instead of after ``jit_threshold`` evaluations; returns their
        states.

        Parameters
        ----------
        wait : bool
            Wait for the compilations to finish.

        Returns
        -------
        dict
            State of each function's compilation, by name.
        """
        calls = {"residual": self._fast_R, "newton": self._fast_newton}
        calls.update({f"history_{k}": self._part_call(k) for k in HISTORY_PARTS})
        return compile_calls(calls, wait)

    def _part_function(self, key) -> ca.Function:
        """The CasADi function of history part ``key`` (:data:`HISTORY_PARTS`): the nonzeros of one
        Jacobian (dense vector, CSC order of :meth:`jacobian_patterns`), or for ``"vjp"``
        ``(dR/dp^T lam, dR/dq^T lam)`` of ``(x, xdot, p, q, lam)`` by one reverse sweep of the
        residual expression (CasADi ``jtimes``, transposed)."""
        name = self._R.name()
        args = self._R_args
        if key != "vjp":
            jac = {"x": self._dx, "xdot": self._dxdot, "p": self._dp, "q": self._dq}[key]
            return ca.Function(f"{name}_jacobian_{key}", args, [jac.expr.nz[:]])
        x, _, p, q = args
        R = self._R(*args)
        sym = ca.SX if isinstance(x, ca.SX) else ca.MX
        lam = sym.sym("lam", self.n_state)
        if sym is ca.SX:           # one reverse sweep for both (SX: a stack of symbols is an argument)
            both = ca.densify(ca.jtimes(R, ca.vertcat(p, q), lam, True))
            outs = [both[:p.numel()], both[p.numel():]]
        else:
            outs = [ca.densify(ca.jtimes(R, a, lam, True)) if a.numel() else sym(0, 1) for a in (p, q)]
        return ca.Function(f"{name}_input_vjp", args + [lam], outs)

    def _part_call(self, key) -> JitCall:
        """The buffered evaluator of history part ``key`` (made at first use)."""
        call = self._maps.get(f"H_{key}")
        if call is None:
            call = self._maps[f"H_{key}"] = JitCall(self._part_function(key), self.jit_threshold,
                                                    definition=self.definition)
        return call

    def _history(self, key, fun, X, Xdot, p, Q):
        """Evaluate ``fun(x, xdot, p, q)`` at every instant through one buffered evaluator.

        (A CasADi ``map`` over the history was slower: building it took ~1.7 ms per instant for
        the 20-node beam, more than the evaluations themselves.)
        """
        if key not in self._maps:
            self._maps[key] = JitCall(fun, self.jit_threshold, definition=self.definition)
        call = self._maps[key]
        fc = call.refresh()
        n = X.shape[0]
        call.jit.count(n)
        outs = [np.empty((n, fun.nnz_out(k))) for k in range(fun.n_out())]
        fc.inp[2][:] = np.ravel(p)
        x_buf, xd_buf, q_buf = fc.inp[0], fc.inp[1], fc.inp[3]
        for i in range(n):
            x_buf[:] = X[i]
            xd_buf[:] = Xdot[i]
            q_buf[:] = Q[i]
            fc.eval()
            for out, res in zip(outs, fc.out):
                out[i] = res
        return outs

    def _eval_history(self, call, X, Xdot, p, Q, extra=None):
        """Outputs of ``call`` (a :class:`JitCall` of ``f(x, xdot, p, q[, extra])``) at every
        instant, ``[array (n_time, nnz_out)]``. Compiled: one C loop over the instants that writes
        each instant's outputs straight into the rows of the result (``eval_history`` of the
        adjoint's C kernel, :mod:`wingmdao.timemarch.static_lu`); else one buffered evaluator."""
        n = X.shape[0]
        call.jit.count(n)          # (first count: a warm cache is loaded)
        fc = call.refresh()
        fun = call.jit.current
        outs = [np.empty((n, fun.nnz_out(k))) for k in range(fun.n_out())]
        ins = [X, Xdot, np.ravel(p), Q] + ([] if extra is None else [extra])
        if n and _history_loop(call, ins, outs, n):
            return outs
        fc.inp[2][:] = np.ravel(p)
        bufs = [fc.inp[0], fc.inp[1], fc.inp[3]] + ([] if extra is None else [fc.inp[4]])
        rows = [X, Xdot, Q] + ([] if extra is None else [extra])
        for i in range(n):
            for b, r in zip(bufs, rows):
                b[:] = r[i]
            fc.eval()
            for out, res in zip(outs, fc.out):
                out[i] = res
        return outs

    def residual(self, x, xdot, p, q):
        """Residual ``R(x, xdot, p, q)`` at one instant (compiled once past the threshold).

        Parameters
        ----------
        x : ndarray, shape (n_state,)
            State.
        xdot : ndarray, shape (n_state,)
            State rate.
        p : ndarray, shape (n_param,)
            Packed parameters.
        q : ndarray, shape (n_forcing,)
            Packed forcing.

        Returns
        -------
        ndarray, shape (n_state,)
            The residual R.
        """
        return self._fast_R(x, xdot, p, q)[0]

    def residual_call(self) -> JitCall:
        """The buffered evaluator of ``R`` (inputs ``x, xdot, p, q``), for loops that keep their
        inputs in its buffers (the BDF march); call its ``refresh()`` and ``jit.count()``."""
        return self._fast_R

    def count_march_steps(self, n_steps: int) -> None:
        """Record a march of ``n_steps`` BDF steps towards the compile threshold of the residual and
        Newton-matrix functions: the compiled march (:mod:`wingmdao.timemarch.fast_step`) uses
        both at every step, but the Python march evaluates the Newton matrix only when modified
        Newton refactors (a few times per march), so counting evaluations alone left a system
        that is only marched (the coupled aeroelastic beam) interpreted for good.

        Parameters
        ----------
        n_steps : int
            Number of BDF steps of the march.
        """
        for call in (self._fast_R, self._fast_newton):
            call.jit.count(int(n_steps))

    def lu_column_order(self):
        """The ``lu_column_order`` given at construction (None: natural order); see
        :meth:`ResidualSystem.lu_column_order`."""
        return self._lu_column_order

    def compiled_step_functions(self):
        """``(residual JitFunction, Newton JitFunction, rows, indptr)`` of the Newton-matrix CSC
        pattern when both functions are compiled libraries, else None: the entry points of the
        compiled march (:mod:`wingmdao.timemarch.fast_step`). None as well for subclasses that
        redefine the residual or the Newton matrix (the libraries would not be their equations)."""
        cls = type(self)
        if (cls.residual is not CasadiResidualSystem.residual
                or cls.residual_and_newton_matrix is not CasadiResidualSystem.residual_and_newton_matrix):
            return None
        for call in (self._fast_R, self._fast_newton):
            call.jit.count(0)   # a warm cache is loaded at the first evaluation
            call.refresh()
        if self._fast_R.jit.state != "compiled" or self._fast_newton.jit.state != "compiled":
            return None
        rows, indptr = self._newton_pattern
        return self._fast_R.jit, self._fast_newton.jit, rows, indptr

    @property
    def residual_function(self) -> ca.Function:
        """The CasADi function ``R(x, xdot, p, q)`` (for derived symbolic quantities, e.g. the
        eigenvalue derivatives of :mod:`wingmdao.stability.sensitivity`)."""
        return self._R

    def jac_state(self, x, xdot, p, q):
        """Exact sparse ``(dR/dx, dR/dxdot)`` (CasADi AD).

        Parameters
        ----------
        x : ndarray, shape (n_state,)
            State.
        xdot : ndarray, shape (n_state,)
            State rate.
        p : ndarray, shape (n_param,)
            Packed parameters.
        q : ndarray, shape (n_forcing,)
            Packed forcing.

        Returns
        -------
        dR_dx, dR_dxdot : scipy.sparse.csc_matrix, shape (n_state, n_state)
            The state Jacobians.
        """
        return self._dx(x, xdot, p, q), self._dxdot(x, xdot, p, q)

    def jac_inputs(self, x, xdot, p, q):
        """Exact sparse ``(dR/dp, dR/dq)`` (CasADi AD).

        Parameters
        ----------
        x : ndarray, shape (n_state,)
            State.
        xdot : ndarray, shape (n_state,)
            State rate.
        p : ndarray, shape (n_param,)
            Packed parameters.
        q : ndarray, shape (n_forcing,)
            Packed forcing.

        Returns
        -------
        dR_dp : scipy.sparse.csc_matrix, shape (n_state, n_param)
            Parameter Jacobian.
        dR_dq : scipy.sparse.csc_matrix, shape (n_state, n_forcing)
            Forcing Jacobian.
        """
        return self._dp(x, xdot, p, q), self._dq(x, xdot, p, q)

    def describe_equation(self, index):
        """Name of residual ``index`` (the ``describe`` given at construction, if any).

        Parameters
        ----------
        index : int
            Index of the residual in the flat vector.

        Returns
        -------
        str
            The name.
        """
        return self._describe(index) if self._describe else super().describe_equation(index)

    def initial_guess(self, p, q):
        """Starting point of a static solve (the ``initial_guess`` given at construction, else zeros).

        Parameters
        ----------
        p : ndarray, shape (n_param,)
            Packed parameters.
        q : ndarray, shape (n_forcing,)
            Packed forcing.

        Returns
        -------
        ndarray, shape (n_state,)
            The guess.
        """
        if self._initial_guess is not None:
            return np.asarray(self._initial_guess(p, q), dtype=float).reshape(self.n_state)
        return super().initial_guess(p, q)

    def residual_and_newton_matrix(self, x, xdot, p, q, alpha):
        """``R`` and the Newton matrix ``dR/dx + alpha dR/dxdot`` in one call (Eq. 3.7).

        Parameters
        ----------
        x : ndarray, shape (n_state,)
            State.
        xdot : ndarray, shape (n_state,)
            State rate.
        p : ndarray, shape (n_param,)
            Packed parameters.
        q : ndarray, shape (n_forcing,)
            Packed forcing.
        alpha : float
            Leading BDF coefficient divided by dt (1/s).

        Returns
        -------
        R : ndarray, shape (n_state,)
            The residual.
        matrix : scipy.sparse.csc_matrix or ndarray, shape (n_state, n_state)
            ``dR/dx + alpha dR/dxdot``.
        """
        r, nz = self._fast_newton(x, xdot, p, q, alpha)
        rows, indptr = self._newton_pattern
        if self.n_state <= DENSE_NEWTON_MAX:  # small systems: dense, no sparse-matrix overhead
            if self._newton_dense_index is None:
                cols = np.repeat(np.arange(self.n_state), np.diff(indptr))
                self._newton_dense_index = rows * self.n_state + cols
            jac = np.zeros((self.n_state, self.n_state))
            jac.ravel()[self._newton_dense_index] = nz
            return r, jac
        return r, sp.csc_matrix((nz, rows, indptr), shape=(self.n_state, self.n_state))

    def jacobian_patterns(self):
        """The exact sparsity patterns of the four Jacobians.

        Returns
        -------
        dict
            ``{"x"|"xdot"|"p"|"q": (rows, cols, shape)}``.
        """
        return {"x": self._dx.pattern(), "xdot": self._dxdot.pattern(), "p": self._dp.pattern(),
                "q": self._dq.pattern()}

    def residual_history(self, X, Xdot, p, Q):
        """Residuals at every instant.

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            States at every instant.
        Xdot : ndarray, shape (n_time, n_state)
            State rates at every instant.
        p : ndarray, shape (n_param,)
            Packed parameters (time-invariant).
        Q : ndarray, shape (n_time, n_forcing)
            Packed forcing at every instant.

        Returns
        -------
        ndarray, shape (n_time, n_state)
            The residuals.
        """
        return self._history("R", self._R, X, Xdot, p, Q)[0]

    def jacobian_history(self, X, Xdot, p, Q):
        """The four Jacobians, each its own function over the whole history (the fused
        four-output function of the 20-node beam is 2 MB of compiled code and ran ~2x slower per
        instant than its parts kept hot one at a time: docs/time-marching.md).

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            States at every instant.
        Xdot : ndarray, shape (n_time, n_state)
            State rates at every instant.
        p : ndarray, shape (n_param,)
            Packed parameters (time-invariant).
        Q : ndarray, shape (n_time, n_forcing)
            Packed forcing at every instant.

        Returns
        -------
        dict
            ``{key: ndarray (n_time, nnz)}`` of nonzeros, in :meth:`jacobian_patterns` order.
        """
        return {k: self._eval_history(self._part_call(k), X, Xdot, p, Q)[0] for k in ("x", "xdot", "p", "q")}

    def _own_history_parts(self) -> bool:
        """False for subclasses that redefine :meth:`jacobian_history` (their Jacobians, and the
        functions their ``compile`` prepares, are those): the state/input variants and the
        reverse-mode products then defer to it."""
        return type(self).jacobian_history is CasadiResidualSystem.jacobian_history

    def state_jacobian_history(self, X, Xdot, p, Q):
        """Nonzeros of dR/dx and dR/dxdot at every instant (``{"x", "xdot"}``).

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            States at every instant.
        Xdot : ndarray, shape (n_time, n_state)
            State rates at every instant.
        p : ndarray, shape (n_param,)
            Packed parameters (time-invariant).
        Q : ndarray, shape (n_time, n_forcing)
            Packed forcing at every instant.

        Returns
        -------
        dict
            ``{key: ndarray (n_time, nnz)}`` of nonzeros, in :meth:`jacobian_patterns` order.
        """
        if not self._own_history_parts():
            return self.jacobian_history(X, Xdot, p, Q)
        return {k: self._eval_history(self._part_call(k), X, Xdot, p, Q)[0] for k in ("x", "xdot")}

    def input_jacobian_history(self, X, Xdot, p, Q):
        """Nonzeros of dR/dp and dR/dq at every instant (``{"p", "q"}``).

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            States at every instant.
        Xdot : ndarray, shape (n_time, n_state)
            State rates at every instant.
        p : ndarray, shape (n_param,)
            Packed parameters (time-invariant).
        Q : ndarray, shape (n_time, n_forcing)
            Packed forcing at every instant.

        Returns
        -------
        dict
            ``{key: ndarray (n_time, nnz)}`` of nonzeros, in :meth:`jacobian_patterns` order.
        """
        if not self._own_history_parts():
            return self.jacobian_history(X, Xdot, p, Q)
        return {k: self._eval_history(self._part_call(k), X, Xdot, p, Q)[0] for k in ("p", "q")}

    def input_vjp_history(self, X, Xdot, p, Q, Lam):
        """Reverse-mode products of :meth:`ResidualSystem.input_vjp_history`: one evaluation of
        the compiled ``jtimes`` function per instant, no dR/dp or dR/dq stored (None for a
        subclass with its own :meth:`jacobian_history`).

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            States at every instant.
        Xdot : ndarray, shape (n_time, n_state)
            State rates at every instant.
        p : ndarray, shape (n_param,)
            Packed parameters (time-invariant).
        Q : ndarray, shape (n_time, n_forcing)
            Packed forcing at every instant.
        Lam : ndarray, shape (n_time, n_state)
            Weights of the residuals at every instant (e.g. adjoint vectors).

        Returns
        -------
        tuple or None
            ``(gp (n_param,), gq (n_time, n_forcing))``, or None without the product.
        """
        if not self._own_history_parts():
            return None
        gp, gq = self._eval_history(self._part_call("vjp"), X, Xdot, p, Q, np.ascontiguousarray(Lam, dtype=float))
        return gp.sum(axis=0), gq


#: The functions evaluated over a whole history, one at a time: the four Jacobians and the
#: vector-Jacobian product with p and q (:meth:`CasadiResidualSystem._part_function`).
HISTORY_PARTS = ("x", "xdot", "p", "q", "vjp")


def _history_loop(call, ins, outs, n) -> bool:
    """Evaluate the compiled library of ``call`` at ``n`` instants in one C call (inputs of one
    instant: rows of the 2-D ``ins``, 1-D ones shared); False when it is not compiled, the C kernel
    is off, or the library's calling convention is not the expected one."""
    jit = call.jit
    if jit.state != "compiled":
        return False
    lib = static_lu.kernel()
    if lib is None:
        return False
    cached = getattr(call, "_history_entry", None)
    if cached is None or cached[0] is not jit.current:
        fun = jit.interpreted
        ok = all(fun.sparsity_out(k).is_dense() for k in range(fun.n_out()))
        entry = fast_step._casadi_entry(jit) if ok else None
        cached = call._history_entry = (jit.current, entry)
    entry = cached[1]
    if entry is None:
        return False
    _, fptr, arg, res, iw, w = entry
    ins = [np.ascontiguousarray(a, dtype=float) for a in ins]
    in_ptr = np.array([a.ctypes.data for a in ins], dtype=np.uintp)
    in_stride = np.array([a.shape[1] if a.ndim == 2 else 0 for a in ins], dtype=np.int64)
    out_ptr = np.array([o.ctypes.data for o in outs], dtype=np.uintp)
    out_stride = np.array([o.shape[1] for o in outs], dtype=np.int64)
    status = lib.eval_history(fptr, n, len(ins), in_ptr.ctypes.data, in_stride.ctypes.data, len(outs),
                              out_ptr.ctypes.data, out_stride.ctypes.data, arg.ctypes.data, res.ctypes.data,
                              iw.ctypes.data, w.ctypes.data)
    if status:
        raise RuntimeError(f"{jit.interpreted.name()}: evaluation failed at instant {status - 1}")
    return True
