"""Base class for components that evaluate the same CasADi expression at every point.

Section properties (one point = one spanwise station) and stress recovery (one point =
one station at one time step) are *pointwise*: the outputs at a point depend only on the
inputs at that point. The Jacobian is then block diagonal, with the sparsity of one point
repeated. This base class builds the expression once with CasADi SX symbols, maps it over
all points, and declares exactly those sparse partials (analytic, from CasADi's AD).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np
import openmdao.api as om

from wingmdao.errors import InputRangeError

from wingmdao.timemarch.system import VarSpec
from wingmdao.utils.digest import ArrayStamp
from wingmdao.utils.sparse import scatter_matrix
from wingmdao.utils import function_store
from wingmdao.utils.casadi_cache import FastCall, JitFunction, definition_key
from wingmdao.utils.function_store import module_closure


@dataclass(frozen=True)
class Var(VarSpec):
    """One variable of a pointwise component: its shape *at one point*, units, description
    (:class:`~wingmdao.timemarch.system.VarSpec`), plus a default value and sharing rule.

    Parameters
    ----------
    name : str
        Variable name.
    shape : tuple, optional
        Shape at one point.
    units : str or None, optional
        OpenMDAO units.
    desc : str, optional
        Description.
    val : float, optional
        Default value.
    per_last_axis : bool, optional
        Input shared by every point with the same last grid index.
    """

    val: float = 1.0
    per_last_axis: bool = False
    """Input only: the variable is shaped ``grid_shape[-1:] + shape`` and shared by every
    point with the same last grid index (e.g. per-station section data used at every time
    step of a (n_time, n_station) grid)."""


class PointwiseCasadiComponent(om.ExplicitComponent):
    """Explicit component whose outputs at each point are a CasADi function of its inputs there.

    Subclasses implement

    * ``pointwise_inputs()`` and ``pointwise_outputs()``: lists of :class:`Var`;
    * ``pointwise_expressions(sym)``: given ``{input name: SX of shape Var.shape}``, return
      ``{output name: SX expression}`` for one point;
    * optionally ``check_inputs(inputs)`` to raise a clear ``ValueError`` on bad input.

    The option ``grid_shape`` gives the leading shape of every variable, e.g.
    ``(n_station,)`` or ``(n_time, n_station)``.
    """

    def initialize(self):
        self.options.declare("grid_shape", default=None, allow_none=True, types=tuple,
                             desc="leading shape of all variables (points); subclasses derive it (point_grid)")
        self.options.declare("matrix_free", default=None, types=bool, allow_none=True,
                             desc="Jacobian-vector products from the per-point nonzeros instead of declared "
                                  "partials (no row/column index arrays); None: above "
                                  "POINTWISE_MATRIX_FREE_ABOVE Jacobian nonzeros")
        self.options.declare("inputs_by_conn", default=False, types=bool,
                             desc="the per-point inputs (not per_last_axis) take their shape from the "
                                  "connected output (shape_by_conn; checked in setup_partials): no "
                                  "default value of their own (memory, docs/gust-envelope.md); they must "
                                  "be connected")

    # ----------------------------------------------------------------- subclass API
    def pointwise_inputs(self) -> list[Var]:
        """The per-point inputs (subclasses implement it).

        Returns
        -------
        list of Var
            The inputs.
        """
        raise NotImplementedError

    def pointwise_outputs(self) -> list[Var]:
        """The per-point outputs (subclasses implement it).

        Returns
        -------
        list of Var
            The outputs.
        """
        raise NotImplementedError

    def pointwise_expressions(self, sym: dict) -> dict:
        """The outputs at one point as CasADi expressions of the inputs (subclasses implement it).

        Parameters
        ----------
        sym : dict
            Input name -> SX symbol of the input's shape at one point.

        Returns
        -------
        dict
            Output name -> SX expression.
        """
        raise NotImplementedError

    def check_inputs(self, inputs) -> None:
        """Raise ``ValueError`` naming the input and point when an input is out of range.

        Parameters
        ----------
        inputs : dict-like
            The component's inputs.
        """

    def declares_point_partials(self) -> bool:
        """Whether the per-point outputs carry declared partials (True; False for a component
        that differentiates only an aggregate of them, :class:`wingmdao.components.ks.KSOfPointwise`)."""
        return True

    # ----------------------------------------------------------------- machinery
    def point_grid(self) -> tuple:
        """Leading shape of every variable: the ``grid_shape`` option (subclasses derive it)."""
        if self.options["grid_shape"] is None:
            raise ValueError(f"{self.msginfo}: the 'grid_shape' option is not set")
        return tuple(self.options["grid_shape"])

    @property
    def num_points(self) -> int:
        return int(np.prod(self.grid_shape))

    def setup(self):
        #: leading shape of every variable (derived in setup from the options)
        self.grid_shape = grid = self.point_grid()
        self._in_vars = self.pointwise_inputs()
        self._out_vars = self.pointwise_outputs()
        by_conn = self.options["inputs_by_conn"]
        #: {input name: expected shape} of the inputs shaped by their connection
        self._by_conn = {}
        for v in self._in_vars:
            lead = grid[-1:] if v.per_last_axis else grid
            if by_conn and not v.per_last_axis:
                self._by_conn[v.name] = lead + v.shape
                self.add_input(v.name, val=v.val, shape_by_conn=True, units=v.units, desc=v.desc)
            else:
                self.add_input(v.name, val=v.val, shape=lead + v.shape, units=v.units, desc=v.desc)
        for v in self._out_vars:
            self.add_output(v.name, val=0.0, shape=grid + v.shape, units=v.units, desc=v.desc)
        self._build_functions()

    def setup_partials(self):
        """The inputs shaped by their connection (``inputs_by_conn``) have the grid's shape."""
        check_connected_shapes(self, self._by_conn)

    def expression_options(self):
        """What, beside the inputs' and outputs' names and shapes, ``pointwise_expressions``
        depends on (a ``repr``-stable value, e.g. a tuple of option values), or None (the
        default): then the functions are built at every setup instead of being persisted
        (:mod:`wingmdao.utils.function_store`)."""
        return None

    def _expression_key(self):
        """Definition key of this component's functions (``definition_key`` of the class, the
        variables, :meth:`expression_options` and the source of the class's modules and what
        they import), or None when not persisted."""
        opts = self.expression_options()
        if opts is None:
            return None
        cls = type(self)
        try:
            mods = module_closure(__name__, *(c.__module__ for c in cls.__mro__ if c.__module__.startswith("wingmdao")),
                                  cls.__module__)
            sig = ([(v.name, tuple(v.shape), v.per_last_axis) for v in self._in_vars],
                   [(v.name, tuple(v.shape)) for v in self._out_vars])
            return definition_key(f"{cls.__module__}.{cls.__qualname__}", (sig, opts), mods)
        except Exception:   # noqa: BLE001 - e.g. a class defined interactively: build every time
            return None

    def _function_data(self) -> dict:
        """Build the per-point function ``f``, the per-pair Jacobian nonzeros function ``jac``
        and the pairs' sparsity (``pairs`` (k, 2) names, ``pair_r``/``pair_c`` concatenated
        triplets in CasADi's column-major order, ``pair_ptr`` offsets)."""
        syms = {v.name: ca.SX.sym(v.name, v.size) for v in self._in_vars}
        shaped = {}
        for v in self._in_vars:
            s = syms[v.name]
            if len(v.shape) == 2:  # row-major (numpy) reshape of the flat symbol
                s = ca.reshape(s, v.shape[1], v.shape[0]).T
            shaped[v.name] = s
        exprs = self.pointwise_expressions(shaped)
        flat_out = []
        for v in self._out_vars:
            e = ca.SX(exprs[v.name])
            if len(v.shape) == 2:
                e = ca.reshape(e.T, v.size, 1)
            else:
                e = ca.reshape(e, v.size, 1)
            flat_out.append(e)
        in_list = [syms[v.name] for v in self._in_vars]
        f = ca.Function(f"{self.__class__.__name__}_f", in_list, flat_out)
        jac_vals, pairs, rs, cs = [], [], [], []
        for j, vo in enumerate(self._out_vars):
            for vi in self._in_vars:
                jac = ca.jacobian(flat_out[j], syms[vi.name])
                sp = jac.sparsity()
                if sp.nnz() == 0:
                    continue
                r, c = sp.get_triplet()
                pairs.append((vo.name, vi.name))
                rs.append(np.asarray(r, dtype=np.int64))
                cs.append(np.asarray(c, dtype=np.int64))
                jac_vals.append(ca.vertcat(*jac.nonzeros()))
        self._pairs = pairs
        fj = ca.Function(f"{self.__class__.__name__}_jac", in_list, jac_vals)
        ptr = np.cumsum([0] + [r.size for r in rs])
        return {"f": f, "jac": fj, "pairs": np.array(pairs, dtype=str).reshape(len(pairs), 2),
                "pair_ptr": ptr, "pair_r": np.concatenate(rs) if rs else np.zeros(0, np.int64),
                "pair_c": np.concatenate(cs) if cs else np.zeros(0, np.int64)}

    def _build_functions(self):
        n = self.num_points
        key = self._expression_key()
        data = function_store.get(type(self).__name__, key, self._function_data)
        f, fj = data["f"], data["jac"]
        #: points per evaluation: the per-point functions are mapped over this many points (all
        #: of them up to POINT_CHUNK; longer grids are evaluated chunk by chunk, so no CasADi
        #: function, sparsity or buffer spans the whole grid)
        self._chunk = m = max(1, min(int(POINT_CHUNK), n))
        self._f = _mapped(f, m)
        self._jit_f = _PointJit(f, m, definition=key)

        self._pairs = [(str(o), str(i)) for o, i in data["pairs"]]
        self._pair_patterns = []
        ptr = data["pair_ptr"]
        per_point = int(ptr[-1])
        mf = self.options["matrix_free"]
        self.matrix_free = bool(per_point * n > POINTWISE_MATRIX_FREE_ABOVE) if mf is None else mf
        self._jac_point, self._jac_values = None, None
        self._fast_calls = {}  # role -> FastCall of the current mapped function (_evaluate)
        self._jac_bytes = 8.0 * per_point * n
        self._shared = {v.name: v.per_last_axis for v in self._in_vars}
        sizes = {v.name: v.size for v in self._in_vars + self._out_vars}
        pts = np.arange(n)[:, None]
        for j, (oname, iname) in enumerate(self._pairs):
            r, c = data["pair_r"][ptr[j]:ptr[j + 1]], data["pair_c"][ptr[j]:ptr[j + 1]]
            shared = self._shared[iname]
            if self.matrix_free:   # the scatter matrices serve the matrix-free products only
                self._pair_patterns.append((r, c, scatter_matrix(r, sizes[oname]), scatter_matrix(c, sizes[iname]), shared))
                continue
            self._pair_patterns.append((r, c, None, None, shared))
            if not self.declares_point_partials():
                continue
            src = pts % self.grid_shape[-1] if shared else pts
            rows = (pts * sizes[oname] + r[None, :]).ravel()
            cols = (src * sizes[iname] + c[None, :]).ravel()
            self.declare_partials(oname, iname, rows=rows, cols=cols)
        self._fjac = _mapped(fj, m)
        self._jit_fjac = _PointJit(fj, m, definition=key)

    def _stacked_inputs(self, inputs):
        n = self.num_points
        n_last = self.grid_shape[-1]
        stacked = []
        for v in self._in_vars:
            if v.per_last_axis:
                a = np.asarray(inputs[v.name]).reshape(n_last, v.size)
                a = np.tile(a, (n // n_last, 1))
            else:
                a = np.asarray(inputs[v.name]).reshape(n, v.size)
            stacked.append(a.T)
        return stacked

    def _point_inputs(self, inputs, points=None):
        """Per input variable its values at the points ``points`` (default: all), ``(len, size)``
        each, point-major: per-station inputs are looked up at each point's station."""
        n, n_last = self.num_points, self.grid_shape[-1]
        rows = []
        for v in self._in_vars:
            a = np.asarray(inputs[v.name]).reshape(n_last if v.per_last_axis else n, v.size)
            if points is not None:
                a = a[points % n_last] if v.per_last_axis else a[points]
            rows.append(a)
        return rows

    def _evaluate(self, role, fun, inputs, points=None):
        """Evaluate ``fun`` (the per-point function mapped over all points, or over ``len(points)``)
        through preallocated buffers (:class:`~wingmdao.utils.casadi_cache.FastCall`): no CasADi
        DM is made for inputs or outputs, ~10x faster than a call with numpy arrays for the
        251 x 20 PEGASUS stress grid. Returns per output its dense values ``(points, size)``,
        views of the buffers (overwritten by the next evaluation of ``role``)."""
        fc = self._fast_calls.get(role)
        if fc is None or fc.fun is not fun:
            fc = FastCall(fun, copy_outputs=False)
            dense = []  # per output: None when dense, else (flat indices of the nonzeros, size)
            for j in range(fun.n_out()):
                sp = fun.sparsity_out(j)
                if sp.is_dense():
                    dense.append(None)
                else:
                    r, c = sp.get_triplet()
                    dense.append((np.asarray(c, dtype=int) * sp.size1() + np.asarray(r, dtype=int), sp.numel()))
            fc.dense_maps = dense
            self._fast_calls[role] = fc
        n, n_last = self.num_points, self.grid_shape[-1]
        if points is None:
            for buf, v in zip(fc.inp, self._in_vars):
                if v.per_last_axis:  # the per-station values repeated over the leading grid axes
                    buf.reshape(n // n_last, n_last, v.size)[...] = np.reshape(inputs[v.name], (n_last, v.size))
                else:
                    buf[...] = np.ravel(inputs[v.name])
            npts = n
        else:
            for buf, a in zip(fc.inp, self._point_inputs(inputs, points)):
                buf[...] = a.ravel()
            npts = len(points)
        fc.eval()
        out = []
        for buf, dmap in zip(fc.out, fc.dense_maps):
            if dmap is not None:
                full = np.zeros(dmap[1])
                full[dmap[0]] = buf
                buf = full
            out.append(buf.reshape(npts, -1))
        return out

    def compute(self, inputs, outputs):
        try:
            self.check_inputs(inputs)
        except ValueError as exc:  # inside a solve: also an AnalysisError, so drivers back off
            raise InputRangeError(str(exc)) from None
        self._f = self._jit_f.update(self._f)
        n = self.num_points
        if self._chunk == n:
            for v, val in zip(self._out_vars, self._evaluate("f", self._f, inputs)):
                outputs[v.name] = val.reshape(outputs[v.name].shape)
            return
        dst = [outputs[v.name].reshape(n, v.size) for v in self._out_vars]  # views of the vector
        for p0, p1, vals in self._chunks("f", self._f, inputs):
            for d, val in zip(dst, vals):
                d[p0:p1] = val

    def _chunks(self, role, fun, inputs):
        """``(p0, p1, [per-output values (p1 - p0, size)])`` of ``fun`` (mapped over
        ``self._chunk`` points) over consecutive chunks of the grid, the last one padded with
        copies of its last point; the values are views of evaluation buffers (valid until the
        next chunk)."""
        n, m = self.num_points, self._chunk
        for p0 in range(0, n, m):
            p1 = min(p0 + m, n)
            points = np.minimum(np.arange(p0, p0 + m), p1 - 1)
            yield p0, p1, [v[:p1 - p0] for v in self._evaluate(role, fun, inputs, points)]

    def _jacobian_nonzeros(self, inputs) -> list:
        """Per-pair Jacobian nonzeros at every point, ``(num_points, nnz per point)`` each (views
        of evaluation buffers, valid until the next Jacobian evaluation, when one chunk spans
        the grid)."""
        self._fjac = self._jit_fjac.update(self._fjac)
        if self._chunk == self.num_points:
            return self._evaluate("jac", self._fjac, inputs)
        full = None
        for p0, p1, vals in self._chunks("jac", self._fjac, inputs):
            if full is None:
                full = [np.empty((self.num_points, v.shape[1])) for v in vals]
            for d, v in zip(full, vals):
                d[p0:p1] = v
        return full

    def compute_partials(self, inputs, partials):
        if self.matrix_free:
            return
        for (oname, iname), val in zip(self._pairs, self._jacobian_nonzeros(inputs)):
            partials[oname, iname] = val.ravel()

    def _jacobian_chunks(self, inputs, keep=False):
        """``(p0, p1, [per-pair nonzeros (p1 - p0, nnz per point)])`` over chunks of
        ``self._chunk`` points (:meth:`_chunks`: no full-grid CasADi buffers); ``keep``: copies,
        else views valid until the next chunk."""
        self._fjac = self._jit_fjac.update(self._fjac)       # counts calls, swaps in the compiled one
        for p0, p1, vals in self._chunks("jac_chunk", self._fjac, inputs):
            yield p0, p1, [v.copy() for v in vals] if keep else vals

    def _jacobian_values(self, inputs):
        """The chunks of :meth:`_jacobian_chunks`. A second product at the same inputs keeps
        them (when they take at most ``POINTWISE_JAC_CACHE_BYTES``) for the following ones; a
        single product (one reverse seed: one KS output per case) keeps nothing. The inputs are
        recognised by their stamps (:func:`same_point`), not a copy of a long history."""
        if not same_point(self._jac_point, inputs):
            self._jac_point, self._jac_values = input_stamp(inputs), None
            return self._jacobian_chunks(inputs)
        if self._jac_values is None and self._jac_bytes <= POINTWISE_JAC_CACHE_BYTES:
            self._jac_values = list(self._jacobian_chunks(inputs, keep=True))
        return self._jac_values if self._jac_values is not None else self._jacobian_chunks(inputs)

    def compute_jacvec_product(self, inputs, d_inputs, d_outputs, mode):
        """Products with the block-diagonal Jacobian (``matrix_free``): per pair, the per-point
        nonzeros ``J[p, r_k, c_k]`` times the input seeds at ``c_k`` summed into the outputs at
        ``r_k`` ('fwd'), or the transpose ('rev'; shared per-station inputs summed over time)."""
        n, n_last = self.num_points, self.grid_shape[-1]
        active = [(j, o, i) for j, (o, i) in enumerate(self._pairs) if o in d_outputs and i in d_inputs]
        if not active:
            return
        src = np.arange(n) % n_last
        seeds, acc = {}, {}
        for _j, oname, iname in active:
            if mode == "fwd":
                if iname not in seeds:
                    din = np.asarray(d_inputs[iname]).reshape(n_last if self._shared[iname] else n, -1)
                    seeds[iname] = din[src] if self._shared[iname] else din
                acc.setdefault(oname, np.zeros((n, int(np.prod(d_outputs[oname].shape)) // n)))
            else:
                seeds.setdefault(oname, np.asarray(d_outputs[oname]).reshape(n, -1))
                acc.setdefault(iname, np.zeros((n, int(np.prod(d_inputs[iname].shape)) // (n_last if self._shared[iname] else n))))
        for p0, p1, vals in self._jacobian_values(inputs):
            for j, oname, iname in active:
                r, c, s_r, s_c, _ = self._pair_patterns[j]
                if mode == "fwd":
                    acc[oname][p0:p1] += np.asarray((vals[j] * seeds[iname][p0:p1, c]) @ s_r)
                else:
                    acc[iname][p0:p1] += np.asarray((vals[j] * seeds[oname][p0:p1, r]) @ s_c)
        if mode == "fwd":
            for oname, a in acc.items():
                d_outputs[oname] += a.reshape(d_outputs[oname].shape)
        else:
            for iname, a in acc.items():
                if self._shared[iname]:
                    a = a.reshape(n // n_last, n_last, -1).sum(axis=0)
                d_inputs[iname] += a.reshape(d_inputs[iname].shape)


def _mapped(fun, m):
    """``fun`` mapped (serially) over ``m`` points."""
    return fun.map(m, "serial") if m > 1 else fun


def input_stamp(inputs) -> dict:
    """Identity of an input point: per variable name its :class:`~wingmdao.utils.digest.ArrayStamp`,
    always a digest: the per-step inputs of a long history can each be below the copy limit
    (internal loads of 20 stations x 4001 steps: 1.9 MB) but are many, and their copies would add
    up at the size where memory counts.

    Parameters
    ----------
    inputs : mapping
        ``{name: array}`` of a component's inputs (their units).

    Returns
    -------
    dict
        ``{name: ArrayStamp}``, for :func:`same_point`.
    """
    return {k: ArrayStamp(v, copy_below=0) for k, v in inputs.items()}


def same_point(stamp, inputs) -> bool:
    """Whether ``inputs`` are the point of ``stamp``.

    Parameters
    ----------
    stamp : dict or None
        :func:`input_stamp` of an earlier point; None: no point yet.
    inputs : mapping
        ``{name: array}`` of the current inputs (their units).

    Returns
    -------
    bool
        True when the names and every array's contents match.
    """
    if stamp is None:
        return False
    items = list(inputs.items())
    return [k for k, _ in items] == list(stamp) and all(stamp[k].matches(v) for k, v in items)


class _PointJit:
    """Compiles the per-point function in the background after :data:`POINT_JIT_THRESHOLD`
    calls (wingmdao.utils.casadi_cache) and maps the compiled version over the grid."""

    def __init__(self, fun, num_points, definition=None):
        self.jit = JitFunction(fun, threshold=POINT_JIT_THRESHOLD, definition=definition)
        self.num_points = num_points

    def update(self, mapped):
        """``mapped``, or the compiled per-point function mapped over the points once ready."""
        self.jit.count()
        if self.jit.poll():
            return _mapped(self.jit.current, self.num_points)
        return mapped


#: Jacobian nonzeros (all points) above which a pointwise component is matrix-free by default:
#: declared partials keep 24 bytes per nonzero (value, row, column) and OpenMDAO allocates them
#: again at final_setup. The 20-station PEGASUS stress history has ~4700 nonzeros per time step:
#: declared up to ~430 steps, matrix-free above (docs/time-marching.md, "Memory").
POINTWISE_MATRIX_FREE_ABOVE = 2_000_000

#: Matrix-free: from the second product at one point on, the Jacobian nonzeros are kept when they
#: take at most this (bytes), else re-evaluated in chunks in every product.
#: ``POINT_CHUNK``: points per evaluation of a pointwise function (grids above it are evaluated
#: in chunks of this many points; read at setup).
POINTWISE_JAC_CACHE_BYTES = 64e6
POINT_CHUNK = 1024

#: Calls of a pointwise component's function (or Jacobian) after which it is compiled.
POINT_JIT_THRESHOLD = 10


def check_connected_shapes(component, expected: dict) -> None:
    """Raise ValueError when an input declared ``shape_by_conn`` got another shape than
    ``expected[name]`` from its connection (public ``get_io_metadata``, after setup).

    Parameters
    ----------
    component : openmdao.api.Component
        A set-up component.
    expected : dict
        Input name -> expected shape.
    """
    if not expected:
        return
    meta = component.get_io_metadata(iotypes=("input",), metadata_keys=["shape"])
    for name, shape in expected.items():
        got = tuple(meta[name]["shape"])
        if got != tuple(shape):
            raise ValueError(f"{component.msginfo}: input '{name}' connected with shape {got}, expected {tuple(shape)}")
