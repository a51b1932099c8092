"""OpenMDAO implicit component: the whole BDF time history of a residual system.

The output is the state history ``x_0..x_N``; the residuals are the stacked discrete
equations of ``wingmdao.timemarch.bdf`` (step 0 static or given state, BDF1, then BDF2,
Eq. 3.4-3.7). The component solves itself (time marching), and its ``solve_linear`` is the
discrete tangent sweep (fwd) or adjoint sweep (rev) of ``wingmdao.timemarch.adjoint``
(Eq. 3.9-3.11), so a gradient costs one backward sweep, not a solve of the whole stacked
system.
"""

from __future__ import annotations

import numbers

import numpy as np
import openmdao.api as om

from wingmdao.timemarch.adjoint import LinearizedHistory, checkpoint_interval
from wingmdao.timemarch.bdf import march, state_rates, time_step
from wingmdao.timemarch.system import ResidualSystem, layout
from wingmdao.limits import ADJOINT_MEMORY_MB, march_progress
from wingmdao.utils.digest import ArrayStamp
from wingmdao import DISSERTATION


#: Above this many stacked unknowns (n_time * n_state) the component is matrix-free by default:
#: declared partials of a 20-node beam over 4000 steps cost +1.1 GB and 10 s more setup than
#: the matrix-free products, and even at 500 steps the matrix-free gradient is 12 % faster
#: (measured, docs/time-marching.md).
MATRIX_FREE_ABOVE = 50_000

#: Budget (MB) of the SuperLU factors kept between sweeps (``store_factors="auto"``). SuperLU
#: reserves ~720 bytes per nonzero of ``A_n`` (2.8 MB per step of the 20-node beam, 3906 nonzeros;
#: measured with mallinfo2), far more than it fills. Kept factors survive until the next
#: linearization, and as every design point's factors land on other heap pages the resident
#: memory grew by ~200 MB per 101-step gust case over an optimization (docs/gust-envelope.md,
#: "Memory"); one adjoint sweep per linearization (a reverse-mode sizing with one KS per case) has
#: no use for them. So "auto" keeps them only when they fit this budget (small systems).
FACTOR_MEMORY_MB = 16.0
#: SuperLU's reserve per nonzero of the Newton matrix (bytes, measured, see FACTOR_MEMORY_MB).
SUPERLU_BYTES_PER_NONZERO = 720.0


class TimeHistoryComponent(om.ImplicitComponent):
    """Time history of any :class:`~wingmdao.timemarch.system.ResidualSystem` (Sec. 3.5.2).

    Inputs: one per parameter ``VarSpec`` of the system (its shape, units, desc), one per
    forcing ``VarSpec`` with a leading ``n_time`` axis, and ``initial_state`` when
    ``initial="state"``. Output: ``state_name`` shaped ``(n_time,) + system.state_shape``.

    ``solve_nonlinear`` time-marches; ``apply_nonlinear`` returns the stacked BDF residuals;
    ``linearize`` stores the per-step Jacobian blocks; ``solve_linear`` runs the forward
    (tangent) sweep in 'fwd' mode and the backward adjoint sweep in 'rev' mode.

    Partials are declared sparse (rows/cols) for states, parameters and forcing. With
    ``matrix_free=True`` (default for more than ``MATRIX_FREE_ABOVE`` stacked unknowns) the
    component instead provides ``apply_linear`` from the stored blocks, with no assembled
    Jacobian (memory, see ``docs/time-marching.md``).

    The parent group must use ``om.LinearRunOnce`` (the default) as its linear solver: a
    ``DirectSolver`` above would assemble and factor the whole stacked Jacobian and bypass
    this component's own sweeps. A one-entry ``time`` (``[0.0]``) is a static solve.
    """

    def initialize(self):
        self.cite = DISSERTATION  # OpenMDAO lists it in its citations report
        self.options.declare("system", types=ResidualSystem, desc="the residual system R(x, xdot, p, q)")
        self.options.declare("time", types=(np.ndarray, list, tuple), desc="uniform time grid (s), time[0] = 0; [0.0] for a static solve")
        self.options.declare("initial", default="static", values=("static", "state"),
                             desc="step 0: static equilibrium under q_0, or the input initial_state")
        self.options.declare("state_name", default="states", types=str, desc="name of the output")
        self.options.declare("state_units", default=None, allow_none=True, types=str,
                             desc="units of the state output (None: mixed)")
        self.options.declare("modified_newton", default=False, types=bool,
                             desc="reuse LU factors across Newton iterations and steps")
        self.options.declare("atol", default=0.0, types=numbers.Real, desc="per-step absolute residual tolerance (0: converge on the step)")
        self.options.declare("xtol", default=1e-12, types=numbers.Real, desc="per-step relative Newton-step tolerance")
        self.options.declare("max_iter", default=25, types=int, desc="Newton iterations per step")
        self.options.declare("static_options", default=None, allow_none=True, types=dict,
                             desc="keyword arguments of solve_static for step 0 (e.g. load_steps)")
        self.options.declare("matrix_free", default=None, types=bool, allow_none=True,
                             desc="apply_linear from stored blocks instead of declared partials; "
                                  "None: when n_time * n_state > MATRIX_FREE_ABOVE")
        self.options.declare("store_factors", default="auto", types=(bool, str),
                             desc="keep every LU factor between sweeps (True/False/'auto': when their "
                                  "estimated reserve fits FACTOR_MEMORY_MB)")
        self.options.declare("lu", default="static", values=("static", "superlu"),
                             desc="sparse LU of the tangent/adjoint sweeps: the static-pivot LU of the "
                             "compiled C kernel (wingmdao.timemarch.static_lu; SuperLU without gcc or "
                             "with WINGMDAO_JIT=0), or SuperLU per step")
        self.options.declare("adjoint_memory", default="auto", values=("auto", "full", "checkpoint"),
                             desc="Jacobian blocks of the tangent/adjoint sweeps: 'full' keeps every step's; "
                                  "'checkpoint' keeps only the states and re-evaluates checkpoint_every steps "
                                  "at a time in each sweep (same totals to round-off); 'auto': checkpoint "
                                  "when full storage would exceed adjoint_memory_mb (matrix-free only)")
        self.options.declare("checkpoint_every", default=None, types=int, allow_none=True, lower=1,
                             desc="segment length (steps) of the checkpointed sweeps; None: the longest "
                                  "that fits adjoint_memory_mb")
        self.options.declare("adjoint_memory_mb", default=ADJOINT_MEMORY_MB, types=(int, float), lower=0.0,
                             desc="memory budget (MB) of the stored Jacobian blocks (adjoint_memory "
                                  "'auto' and the default segment length)")
        self.options.declare("drop_time_axis", default=False, types=bool,
                             desc="one instant only: forcing inputs and the output without the time axis")
        self.options.declare("forcing_data", default=None, allow_none=True, types=dict,
                             desc="{forcing name: its history, shape of the input}: forcing held as data of "
                                  "the component, not declared as an input (a fixed load history: no "
                                  "OpenMDAO vectors, transfers or default copies of it; no derivatives "
                                  "with respect to it)")
        self.recording_options["options_excludes"] = ["forcing_data"]   # large arrays

    # ------------------------------------------------------------------ setup
    def build_system(self) -> ResidualSystem:
        """The residual system to march: the ``system`` option (subclasses build one from their options)."""
        if self.options["system"] is None:
            raise ValueError(f"{self.msginfo}: the 'system' option is not set")
        return self.options["system"]

    def setup(self):
        #: the residual system marched by this component (derived from the options in setup)
        self.system = sysm = self.build_system()
        t = np.asarray(self.options["time"], dtype=float)
        time_step(t)
        self._time = t
        self._n_time = n_time = t.size
        drop = self.options["drop_time_axis"]
        if drop and n_time != 1:
            raise ValueError(f"drop_time_axis needs a one-entry time, got {n_time} entries")
        lead = () if drop else (n_time,)
        name = self.options["state_name"]
        names = [s.name for s in sysm.param_specs + sysm.forcing_specs]
        if self.options["initial"] == "state":
            names.append("initial_state")
        if name in names or len(set(names)) != len(names):
            raise ValueError(f"TimeHistoryComponent: variable names must be unique, got state "
                             f"'{name}' and inputs {names}")
        for s in sysm.param_specs:
            self.add_input(s.name, val=1.0, shape=s.shape or (1,), units=s.units, desc=s.desc or s.name)
        self._q_data = self._forcing_data(sysm, lead)
        for s in sysm.forcing_specs:
            if s.name not in self._q_data:
                self.add_input(s.name, val=0.0, shape=(lead + tuple(s.shape)) or (1,), units=s.units,
                               desc=(s.desc or s.name) + ("" if drop else " (at every instant)"))
        if self.options["initial"] == "state":
            self.add_input("initial_state", val=0.0, shape=sysm.state_shape, units=self.options["state_units"],
                           desc="state at time 0")
        self.add_output(name, val=0.0, shape=lead + tuple(sysm.state_shape),
                        units=self.options["state_units"], desc="state history (n_time first)")
        self._p_slices = layout(sysm.param_specs)
        self._q_slices = layout(sysm.forcing_specs)
        # sizes once (``VarSpec.size`` and ``system.n_param`` are recomputed at every access)
        self._p_sizes = [(s.name, s.size) for s in sysm.param_specs]
        self._q_sizes = [(s.name, s.size) for s in sysm.forcing_specs]
        self._n_param = sum(size for _, size in self._p_sizes)
        self._n_forcing = sum(size for _, size in self._q_sizes)
        self._n_state = sysm.n_state
        self._lin = None
        self._lin_inputs = None     # stamps of the states and input vector at the linearization
        mf = self.options["matrix_free"]
        self._matrix_free = bool(n_time * sysm.n_state > MATRIX_FREE_ABOVE) if mf is None else mf
        self.matrix_free = self._matrix_free
        self.checkpoint_every = self._checkpoint_interval()
        self.store_factors = self._store_factors()

    def _forcing_data(self, sysm, lead):
        """The ``forcing_data`` option checked against the forcing specs: {name: (n_time, size) floats}."""
        data = self.options["forcing_data"] or {}
        specs = {s.name: s for s in sysm.forcing_specs}
        out = {}
        for name, val in data.items():
            if name not in specs:
                raise ValueError(f"{self.msginfo}: forcing_data '{name}' is not a forcing of the system "
                                 f"(forcing: {sorted(specs)})")
            shape = (lead + tuple(specs[name].shape)) or (1,)
            arr = np.asarray(val, dtype=float)
            if arr.shape != shape:
                raise ValueError(f"{self.msginfo}: forcing_data '{name}' has shape {arr.shape}, expected {shape}")
            out[name] = arr.reshape(self._n_time, specs[name].size)
        return out

    def _store_factors(self) -> bool:
        """The ``store_factors`` option resolved: 'auto' keeps the factors of every step when
        SuperLU's estimated reserve (:data:`SUPERLU_BYTES_PER_NONZERO` per nonzero of the union
        pattern of dR/dx, dR/dxdot and the diagonal, an upper bound) fits :data:`FACTOR_MEMORY_MB`."""
        store = self.options["store_factors"]
        if store != "auto":
            if not isinstance(store, bool):
                raise ValueError(f"{self.msginfo}: store_factors = {store!r}; allowed: True, False, 'auto'")
            return store
        rows, _ = _newton_pattern(self.system.jacobian_patterns(), self.system.n_state)
        return self._n_time * rows.size * SUPERLU_BYTES_PER_NONZERO <= 1e6 * FACTOR_MEMORY_MB

    def _checkpoint_interval(self):
        """Segment length of the checkpointed sweeps, None for full storage (docs/time-marching.md)."""
        mode, k = self.options["adjoint_memory"], self.options["checkpoint_every"]
        budget = 1e6 * float(self.options["adjoint_memory_mb"])
        if mode == "full" or self._n_time == 1:
            return None
        if not self._matrix_free:
            if mode == "checkpoint":
                raise ValueError(f"{self.msginfo}: adjoint_memory='checkpoint' needs matrix_free=True "
                                 "(declared partials store every step's Jacobian blocks)")
            return None
        if mode == "auto" and checkpoint_interval(self.system, self._n_time, budget) is None:
            return None
        if k is not None:
            return k
        # a segment gets an eighth of the budget (25 MB by default, as before the budget was
        # raised for full storage): two are alive while the next one is built, and the Jacobian
        # evaluation has its own buffers
        return checkpoint_interval(self.system, self._n_time, budget / 8) or max(1, self._n_time // 8)

    def setup_partials(self):
        if self._matrix_free:
            return
        sysm = self.system
        n, N = sysm.n_state, self._n_time
        name = self.options["state_name"]
        pats = sysm.jacobian_patterns()
        a_rows, a_cols = _newton_pattern(pats, n)
        steps = np.arange(N)[:, None]
        rd, cd, _ = pats["xdot"]
        rows = [(steps * n + a_rows).ravel()]
        cols = [(steps * n + a_cols).ravel()]
        for k in (1, 2):
            s = steps[k:]
            rows.append((s * n + rd).ravel())
            cols.append(((s - k) * n + cd).ravel())
        self.declare_partials(name, name, rows=np.concatenate(rows), cols=np.concatenate(cols))
        # dR/dp: every step's rows against the (time-invariant) parameter block;
        # dR/dq: step n's rows against step n's forcing entries
        self._p_masks = self._declare_input_partials(
            name, sysm.param_specs, self._p_slices, pats["p"], steps,
            lambda spec, c: np.broadcast_to(c, (N, c.size)))
        self._q_masks = self._declare_input_partials(
            name, [s for s in sysm.forcing_specs if s.name not in self._q_data], self._q_slices, pats["q"], steps,
            lambda spec, c: steps * spec.size + c)
        if self.options["initial"] == "state":
            self.declare_partials(name, "initial_state", rows=np.arange(n), cols=np.arange(n), val=-1.0)

    def _declare_input_partials(self, name, specs, slices, pattern, steps, cols_of):
        """Declare d(states residual)/d(input) for each input block of ``specs`` from the system's
        Jacobian ``pattern`` (rows, cols, shape at one step) repeated over ``steps``;
        ``cols_of(spec, local_cols)`` maps a step's columns into the input's flat index.
        Returns ``{input name: mask of the pattern's nonzeros that belong to it}``."""
        n = self.system.n_state
        rows, cols, _ = pattern
        masks = {}
        for spec in specs:
            sl = slices[spec.name]
            m = (cols >= sl.start) & (cols < sl.stop)
            masks[spec.name] = m
            if np.any(m):
                self.declare_partials(name, spec.name, rows=(steps * n + rows[m]).ravel(),
                                      cols=np.asarray(cols_of(spec, cols[m] - sl.start)).ravel())
        return masks

    # ------------------------------------------------------------------ packing
    def _params(self, inputs):
        sysm = self.system
        if not self._p_sizes:
            return np.zeros(0)
        p = np.concatenate([np.asarray(inputs[name], dtype=float).ravel() for name, _ in self._p_sizes])
        _check_finite(p, sysm.param_specs, self._p_slices, None)
        return p

    def _forcing(self, inputs):
        sysm = self.system
        N = self._n_time
        if not self._q_sizes:
            return np.zeros((N, 0))
        data = self._q_data
        Q = np.hstack([data[name] if name in data else np.asarray(inputs[name], dtype=float).reshape(N, size)
                       for name, size in self._q_sizes])
        _check_finite(Q, sysm.forcing_specs, self._q_slices, N)
        return Q

    def _x_init(self, inputs):
        if self.options["initial"] != "state":
            return None
        return np.asarray(inputs["initial_state"], dtype=float).ravel()

    def _history(self, outputs):
        n = self.system.n_state
        return np.asarray(outputs[self.options["state_name"]], dtype=float).reshape(self._n_time, n)

    # ------------------------------------------------------------------ nonlinear
    def solve_nonlinear(self, inputs, outputs):
        sysm = self.system
        self._lin = self._lin_inputs = None   # the linearization uses the states this solve changes
        p, Q = self._params(inputs), self._forcing(inputs)

        def run(guess):
            return march(sysm, self._time, p, Q, initial=self.options["initial"], x_init=self._x_init(inputs),
                         x_guess=guess, modified_newton=self.options["modified_newton"],
                         atol=self.options["atol"], xtol=self.options["xtol"], max_iter=self.options["max_iter"],
                         static_options=self.options["static_options"],
                         callback=march_progress(len(self._time), self.pathname or "march"))

        if self.options["initial"] != "static":
            h = run(None)
        else:
            x0_prev = self._history(outputs)[0]
            if np.any(x0_prev != 0.0):  # warm start: the previous design's solution
                try:
                    h = run(x0_prev.copy())
                except om.AnalysisError:  # far from the previous design: retry from the cold guess
                    h = run(self.initial_guess(p, Q[0]))
            else:
                h = run(self.initial_guess(p, Q[0]))
        outputs[self.options["state_name"]] = h.states.reshape(outputs[self.options["state_name"]].shape)
        # Newton work of the last march (iterations per step, factorizations); the states are the
        # output, so the history's own copies (states and rates: 2 x n_time x n_state) are dropped
        h.states = h.rates = None
        self.last_history = h

    def initial_guess(self, p, q0):
        """Starting point of the static solve of step 0 (the previous solution is used when
        there is one). Default: ``system.initial_guess``; subclasses may know better.

        Parameters
        ----------
        p : numpy.ndarray
            Packed parameters.
        q0 : numpy.ndarray
            Packed forcing at t = 0.

        Returns
        -------
        numpy.ndarray
            The guess.
        """
        return self.system.initial_guess(p, q0)

    def apply_nonlinear(self, inputs, outputs, residuals):
        sysm = self.system
        X = self._history(outputs)
        dt = time_step(self._time)
        p, Q = self._params(inputs), self._forcing(inputs)
        R = sysm.residual_history(X, state_rates(X, dt) if self._n_time > 1 else np.zeros_like(X), p, Q)
        if self.options["initial"] == "state":
            R[0] = X[0] - self._x_init(inputs)
        residuals[self.options["state_name"]] = R.reshape(residuals[self.options["state_name"]].shape)

    # ------------------------------------------------------------------ linear
    def linearize(self, inputs, outputs, partials):
        sysm = self.system
        p, Q = self._params(inputs), self._forcing(inputs)
        X = self._history(outputs)
        # drop the previous design point's linearization first: the two are not alive together
        self._lin = self._lin_inputs = None
        # the linearization uses the output vector's states (no copy) and, when every forcing is
        # data (forcing_data), keeps no forcing products; the linearization point is kept as
        # stamps of the states and of the input vector (wingmdao.utils.digest), and a new
        # solve_nonlinear drops the linearization before it changes the states
        lin = LinearizedHistory(sysm, self._time, X, p, Q,
                                initial=self.options["initial"], store_factors=self.store_factors,
                                lu=self.options["lu"], checkpoint_every=self.checkpoint_every,
                                copy_states=False, keep_forcing_product=len(self._q_data) < len(self._q_sizes))
        self._lin = lin
        self._lin_inputs = (ArrayStamp(X), ArrayStamp(inputs.asarray()))
        if self._matrix_free:
            return
        name = self.options["state_name"]
        vals = [lin.a_data.ravel()]
        for k in (1, 2):
            vals.append((lin.coef[k:, k:k + 1] * lin.jxd[k:]).ravel())
        partials[name, name] = np.concatenate(vals)
        for spec in sysm.param_specs:
            m = self._p_masks[spec.name]
            if np.any(m):
                partials[name, spec.name] = lin.jp[:, m].ravel()
        for spec in sysm.forcing_specs:
            m = self._q_masks.get(spec.name)    # None: forcing_data, not an input
            if m is not None and np.any(m):
                partials[name, spec.name] = lin.jq[:, m].ravel()

    def solve_linear(self, d_outputs, d_residuals, mode):
        name = self.options["state_name"]
        shape = (self._n_time, self.system.n_state)
        if mode == "fwd":
            rhs = np.asarray(d_residuals[name]).reshape(shape)
            d_outputs[name] = self._lin.solve_tangent(rhs).reshape(d_outputs[name].shape)
        else:
            rhs = np.asarray(d_outputs[name]).reshape(shape)
            d_residuals[name] = self._lin.solve_adjoint(rhs).reshape(d_residuals[name].shape)

    def apply_linear(self, inputs, outputs, d_inputs, d_outputs, d_residuals, mode):
        """Matrix-free products with the stored blocks (only with ``matrix_free=True``); the
        products with dR/dp and dR/dq are formed only when one of their inputs is in ``d_inputs``
        (OpenMDAO leaves out the inputs no total depends on)."""
        if not self._linearized_at(inputs, outputs):
            self.linearize(inputs, outputs, None)
        lin = self._lin
        name = self.options["state_name"]
        shape = (self._n_time, self._n_state)
        if name not in d_residuals:
            return
        p_in = [(n, self._p_slices[n]) for n, _ in self._p_sizes if n in d_inputs]
        q_in = [(n, self._q_slices[n]) for n, _ in self._q_sizes if n in d_inputs]
        if mode == "fwd":
            out = np.zeros(shape)
            if name in d_outputs:
                out += lin.apply(np.asarray(d_outputs[name]).reshape(shape))
            if p_in:
                dp = np.zeros(self._n_param)
                for n, sl in p_in:
                    dp[sl] = np.asarray(d_inputs[n]).ravel()
                if np.any(dp):
                    out += lin.param_apply(dp)
            if q_in:
                dq = np.zeros((self._n_time, self._n_forcing))
                for n, sl in q_in:
                    dq[:, sl] = np.asarray(d_inputs[n]).reshape(self._n_time, sl.stop - sl.start)
                if np.any(dq):
                    out += lin.forcing_apply(dq)
            if "initial_state" in d_inputs:
                out[0] -= np.asarray(d_inputs["initial_state"]).ravel()
            d_residuals[name] += out.reshape(d_residuals[name].shape)
        else:
            r = np.asarray(d_residuals[name]).reshape(shape)
            if name in d_outputs:
                d_outputs[name] += lin.apply_transpose(r).reshape(d_outputs[name].shape)
            if p_in:
                gp = lin.param_product(r)
                for n, sl in p_in:
                    d_inputs[n] += gp[sl].reshape(d_inputs[n].shape)
            if q_in:
                gq = lin.forcing_product(r)
                for n, sl in q_in:
                    d_inputs[n] += gq[:, sl].reshape(d_inputs[n].shape)
            if "initial_state" in d_inputs:
                d_inputs["initial_state"] -= r[0].reshape(d_inputs["initial_state"].shape)

    def _linearized_at(self, inputs, outputs):
        """Whether the stored linearization is at these inputs and outputs: the history and the
        whole input vector against their stamps made in ``linearize`` (no packing or finiteness
        checks made again)."""
        if self._lin is None or self._lin_inputs is None:
            return False
        states, vector = self._lin_inputs
        return states.matches(self._history(outputs)) and vector.matches(inputs.asarray())


def _newton_pattern(pats, n):
    """Union pattern of dR/dx, dR/dxdot and the diagonal, CSC order (as LinearizedHistory)."""
    rx, cx, _ = pats["x"]
    rd, cd, _ = pats["xdot"]
    eye = np.arange(n)
    keys = np.unique(np.concatenate([cx * n + rx, cd * n + rd, eye * n + eye]))
    return keys % n, keys // n


def _check_finite(values, specs, slices, n_time):
    """Raise ValueError naming the input and index of the first non-finite entry."""
    bad = ~np.isfinite(values)
    if not np.any(bad):
        return
    flat = np.flatnonzero(bad)[0]
    if n_time is None:
        step, col = None, int(flat)
    else:
        step, col = divmod(int(flat), values.shape[1])
    for s in specs:
        sl = slices[s.name]
        if sl.start <= col < sl.stop:
            where = f"entry {col - sl.start}" + (f" at time step {step}" if step is not None else "")
            raise ValueError(f"input '{s.name}': {where} is not finite ({values.ravel()[flat]}); "
                             f"it must be a finite real number in {s.units or 'its units'}")
