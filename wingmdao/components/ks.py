"""Kreisselmeier-Steinhauser (KS) aggregation of constraint arrays over space and time.

Dissertation Eq. 4.43-4.44 (space, then space-time) and Eq. 4.53-4.55 (box beam: four
stress points j, n stations k, n_T + 1 time steps t, all in one sum):

    KS(g) = m + ln( sum_k exp(rho_KS (g_k - m)) ) / rho_KS,      m = max_k g_k

The max shift m keeps every exponent <= 0, so large rho_KS and large ``|g|`` cannot overflow.
The sum runs over *every* entry of the array, whatever its shape. See ``docs/ks.md``; the
formula itself: :mod:`wingmdao.utils.ks`.
"""

from __future__ import annotations

import numbers

import numpy as np
import openmdao.api as om

from wingmdao import DISSERTATION
from wingmdao.utils.digest import ArrayStamp
from wingmdao.utils.ks import ks_gradient, ks_value, shifted_exp  # noqa: F401 - ks_value: public here too
from wingmdao.components.pointwise import check_connected_shapes, input_stamp, same_point
from wingmdao.utils.sparse import scatter_matrix

#: constraint entries (all families of a KSAggregate) above which it is matrix-free by default:
#: declared partials keep a value, a row and a column index per entry, and OpenMDAO copies them
#: (~10 MB for the 20-node x 4001-step PEGASUS vm history, 320 080 entries)
KS_MATRIX_FREE_ABOVE = 100_000


def _check_finite(name: str, g: np.ndarray) -> None:
    """A non-finite constraint value comes from a failed upstream analysis: ``om.AnalysisError``,
    so a driver backs off instead of stopping."""
    bad = ~np.isfinite(g)
    if np.any(bad):
        idx = np.unravel_index(int(np.flatnonzero(bad)[0]), g.shape)
        raise om.AnalysisError(
            f"{name}: non-finite value {g[idx]} at index {tuple(int(i) for i in idx)}; "
            "constraint values must be finite real numbers"
        )


class KSAggregate(om.ExplicitComponent):
    """KS aggregation of one or more constraint families (Eq. 4.44, 4.53-4.55).

    ``KSAggregate(families={"vm": (n_time, n_station, 4), "ss_tension": (n_time, n_station, 4)},
    rho_ks=50.0)`` has inputs ``g_vm``, ``g_ss_tension`` (unitless, ``g <= 0`` feasible) and
    scalar outputs ``ks_vm``, ``ks_ss_tension``. Each output depends on its own family only;
    its partials are one dense row, declared with rows/cols. With ``add_constraints=True``
    every ``ks_<family>`` is added as a constraint ``ks <= 0``.
    """

    def initialize(self):
        self.cite = DISSERTATION  # OpenMDAO lists it in its citations report
        self.options.declare(
            "families", types=dict, desc="{family name: shape of its constraint array g}"
        )
        self.options.declare(
            "rho_ks", default=100.0, lower=0.0, types=numbers.Real, desc="KS aggregation parameter rho_KS (> 0)"
        )
        self.options.declare(
            "add_constraints", default=False, types=bool,
            desc="add each ks_<family> as a constraint ks <= 0 (like om.KSComp's add_constraint)",
        )
        self.options.declare(
            "g_by_conn", default=False, types=bool,
            desc="the g_<family> inputs take their shape from the connected output (shape_by_conn, "
                 "checked against families in setup_partials): no default value of their own "
                 "(memory, docs/gust-envelope.md); they must be connected",
        )
        self.options.declare(
            "matrix_free", default=None, types=bool, allow_none=True,
            desc="products with dKS/dg (compute_jacvec_product) instead of declared partials (no "
                 "row/column arrays); None: above KS_MATRIX_FREE_ABOVE constraint entries in all",
        )

    def setup(self):
        rho = self.options["rho_ks"]
        by_conn = self.options["g_by_conn"]
        if not rho > 0.0 or not np.isfinite(rho):
            raise ValueError(f"KSAggregate: rho_ks = {rho}; allowed range (0, inf)")
        if not self.options["families"]:
            raise ValueError("KSAggregate: families is empty; give at least one {name: shape}")
        self._terms = {}    # {family: (stamp of g, w, s)} of the last compute (see compute_partials)
        shapes = {}
        for name, shape in self.options["families"].items():
            shape = (int(shape),) if np.isscalar(shape) else tuple(int(s) for s in shape)
            size = int(np.prod(shape)) if shape else 1
            if size < 1:
                raise ValueError(f"KSAggregate: family '{name}' has shape {shape} with no entries")
            shapes[name] = shape, size
        mf = self.options["matrix_free"]
        self.matrix_free = sum(sz for _, sz in shapes.values()) > KS_MATRIX_FREE_ABOVE if mf is None else mf
        self._by_conn = {f"g_{name}": shape for name, (shape, _) in shapes.items()} if by_conn else {}
        for name, (shape, size) in shapes.items():
            self.add_input(
                f"g_{name}", val=0.0, **({"shape_by_conn": True} if by_conn else {"shape": shape}), units=None,
                desc=f"'{name}' constraint values (feasible where <= 0)",
            )
            self.add_output(
                f"ks_{name}", val=0.0, units=None,
                desc=f"KS aggregate of all '{name}' constraints (space and time)",
            )
            if not self.matrix_free:
                self.declare_partials(
                    f"ks_{name}", f"g_{name}", rows=np.zeros(size, dtype=int), cols=np.arange(size)
                )
            if self.options["add_constraints"]:
                self.add_constraint(f"ks_{name}", upper=0.0)

    def setup_partials(self):
        """The g inputs shaped by their connection (``g_by_conn``) have the families' shapes."""
        check_connected_shapes(self, self._by_conn)

    def compute(self, inputs, outputs):
        rho = self.options["rho_ks"]
        self._terms = {}
        for name in self.options["families"]:
            g = np.asarray(inputs[f"g_{name}"])
            _check_finite(f"g_{name}", g)
            m, w, s = shifted_exp(g, rho)
            outputs[f"ks_{name}"] = float(m + np.log(s) / rho)     # ks_value
            # kept for compute_partials at the same g (run_model, then compute_totals): the
            # weights w / s of ks_gradient without a second exp over the family (1.5 ms of a
            # 20-node x 500-step beam gradient, 180 000 entries)
            # (g recognised by its stamp, wingmdao.utils.digest: no copy of a long history)
            self._terms[name] = (ArrayStamp(g), w, s)

    def _weights(self, name, inputs) -> np.ndarray:
        """dKS/dg of family ``name``, flattened: :func:`ks_gradient`, from the terms of the last
        ``compute`` when ``g`` is the same (bitwise the same values)."""
        g = np.asarray(inputs[f"g_{name}"])
        kept = self._terms.get(name)
        if kept is not None and kept[0].matches(g):
            return kept[1] / kept[2]
        return ks_gradient(g, self.options["rho_ks"])

    def compute_partials(self, inputs, partials):
        """dKS/dg (Eq. 4.46-4.51 before the chain rule), :meth:`_weights`."""
        if self.matrix_free:
            return
        for name in self.options["families"]:
            partials[f"ks_{name}", f"g_{name}"] = self._weights(name, inputs)

    def compute_jacvec_product(self, inputs, d_inputs, d_outputs, mode):
        """``matrix_free``: ``d ks = dKS/dg . d g`` ('fwd') or ``d g += d ks dKS/dg`` ('rev'), the
        weights of :meth:`_weights` (the same values as the declared partials)."""
        for name in self.options["families"]:
            o, i = f"ks_{name}", f"g_{name}"
            if o not in d_outputs or i not in d_inputs:
                continue
            wts = self._weights(name, inputs)
            if mode == "fwd":
                d_outputs[o] += np.dot(wts, np.ravel(d_inputs[i]))
            else:
                d_inputs[i] += (np.ravel(d_outputs[o])[0] * wts).reshape(d_inputs[i].shape)


class KSOfPointwise:
    """Mixin for a :class:`~wingmdao.components.pointwise.PointwiseCasadiComponent` whose outputs
    ``g_<family>`` are constraints: with the option ``ks_rho`` it also outputs ``ks_<family>``,
    the KS aggregate of each (Eq. 4.44, over every point and entry: the same value as
    :class:`KSAggregate` on ``g_<family>``), and only these carry partials.

    Why: the KS rows are all a driver differentiates. Declared per point, the partials of
    ``g`` are every point's nonzeros (time steps x stations x entries x inputs), which every
    reverse solve multiplies, one solve per constraint; aggregated here, dKS/dx = sum_p w_p
    dg_p/dx is formed once per linearisation from the per-point nonzeros and each reverse solve
    multiplies one dense row per input (docs/panels.md, "Sizing time"). The ``g`` outputs stay (result summaries read them) without
    partials: nothing may differentiate through them. ``ks_constraints`` adds each ``ks_<family>``
    as a constraint ``<= 0`` (as :class:`KSAggregate`'s ``add_constraints``).
    """

    def initialize(self):
        """Declare the ``ks_rho`` and ``ks_constraints`` options beside the component's own."""
        super().initialize()
        self.options.declare("ks_rho", default=None, allow_none=True, types=numbers.Real, lower=0.0,
                             desc="rho_KS of the ks_<family> aggregates of the g_<family> outputs (None: no "
                                  "aggregates; the g outputs carry the partials)")
        self.options.declare("ks_constraints", default=False, types=bool,
                             desc="add each ks_<family> as a constraint ks <= 0 (with ks_rho)")

    @property
    def aggregated(self) -> bool:
        """Whether the component outputs and differentiates the KS aggregates (``ks_rho`` set)."""
        return self.options["ks_rho"] is not None

    def declares_point_partials(self) -> bool:
        """Whether the per-point outputs ``g_<family>`` carry declared partials.

        Returns
        -------
        bool
            False when the aggregates carry the partials (``ks_rho`` set).
        """
        return not self.aggregated

    def setup(self):
        """The component's variables, plus ``ks_<family>`` for every constraint output when aggregated (and their constraints with ``ks_constraints``)."""
        if self.aggregated:
            self.options["matrix_free"] = False   # the KS rows are declared (one dense row per input)
        super().setup()
        if not self.aggregated:
            return
        rho = self.options["ks_rho"]
        if not (rho > 0.0 and np.isfinite(rho)):
            raise ValueError(f"{self.msginfo}: ks_rho = {rho}; allowed range (0, inf)")
        n, n_last = self.num_points, self.grid_shape[-1]
        sizes = {v.name: v.size for v in self._in_vars}
        self._ks_names = {}
        for v in self._out_vars:
            if not v.name.startswith("g_"):
                raise ValueError(f"{self.msginfo}: ks_rho aggregates outputs named g_<family>, got {v.name!r}")
            ks = "ks_" + v.name[2:]
            self._ks_names[v.name] = ks
            self.add_output(ks, val=0.0, units=None, desc=f"KS aggregate of {v.name} over all points (feasible <= 0)")
            if self.options["ks_constraints"]:
                self.add_constraint(ks, upper=0.0)
        # per pair a dense (nnz, input size) 0/1 matrix: the nonzeros' columns (a few per point)
        self._ks_scatter = [scatter_matrix(c, sizes[i]).toarray() for (_, c, _, _, _), (_, i)
                            in zip(self._pair_patterns, self._pairs)]
        for oname, iname in self._pairs:
            size = (n_last if self._shared[iname] else n) * sizes[iname]
            self.declare_partials(self._ks_names[oname], iname, rows=np.zeros(size, dtype=int), cols=np.arange(size))
        self._ks_point, self._ks_weights = None, {}

    def compute(self, inputs, outputs):
        """The per-point outputs, then the KS aggregate of every ``g_<family>`` when aggregated.

        Parameters
        ----------
        inputs : dict-like
            The component's inputs.
        outputs : dict-like
            The component's outputs.
        """
        super().compute(inputs, outputs)
        if not self.aggregated:
            return
        rho = self.options["ks_rho"]
        n = self.num_points
        for v in self._out_vars:
            g = np.asarray(outputs[v.name])
            _check_finite(f"{self.pathname}.{v.name}", g)
            m, w, s = shifted_exp(g, rho)
            outputs[self._ks_names[v.name]] = float(m + np.log(s) / rho)
            self._ks_weights[v.name] = (w / s).reshape(n, v.size)
        self._ks_point = input_stamp(inputs)

    def _weights_at(self, inputs) -> dict:
        """dKS/dg per output, (points, size), of the last compute; recomputed when the inputs
        are not those of the last compute (recognised by their stamps)."""
        if not same_point(self._ks_point, inputs):
            rho, n = self.options["ks_rho"], self.num_points
            vals = self._evaluate("f", self._f, inputs) if self._chunk == n else None
            if vals is None:
                vals = [np.empty((n, v.size)) for v in self._out_vars]
                for p0, p1, chunk in self._chunks("f", self._f, inputs):
                    for d, c in zip(vals, chunk):
                        d[p0:p1] = c
            for v, g in zip(self._out_vars, vals):
                self._ks_weights[v.name] = ks_gradient(g, rho).reshape(n, v.size)
            self._ks_point = input_stamp(inputs)
        return self._ks_weights

    def compute_partials(self, inputs, partials):
        """dKS/dx = sum over points p and entries k of w_pk dg_pk/dx: the per-point Jacobian
        nonzeros (CasADi AD) weighted by the KS weights and summed into each input's entries
        (over the time steps for the per-station inputs).

        Parameters
        ----------
        inputs : dict-like
            The component's inputs.
        partials : dict-like
            The component's partials.
        """
        if not self.aggregated:
            return super().compute_partials(inputs, partials)
        w = self._weights_at(inputs)
        n, n_last = self.num_points, self.grid_shape[-1]
        acc = [None] * len(self._pairs)
        for p0, p1, vals in self._jacobian_chunks(inputs):
            for j, (oname, _iname) in enumerate(self._pairs):
                r = self._pair_patterns[j][0]
                part = (w[oname][p0:p1][:, r] * vals[j]) @ self._ks_scatter[j]
                if acc[j] is None:
                    acc[j] = np.zeros((n, part.shape[1]))
                acc[j][p0:p1] += part
        for j, (oname, iname) in enumerate(self._pairs):
            a = acc[j]
            if self._shared[iname]:
                a = a.reshape(n // n_last, n_last, -1).sum(axis=0)
            partials[self._ks_names[oname], iname] = a.ravel()
