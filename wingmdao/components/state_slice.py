"""``BeamStateSlice``: the 18 beam states per node out of a state history (the aeroelastic beam's, or one beam of a joined system).

The aeroelastic beam (:func:`wingmdao.aero.system.build_aeroelastic_system`) marches
22 states per node (18 beam, 4 aerodynamic lag), node-major, then the plunge and trim states;
the internal loads need the (n_time, n, 18) beam block. A selection: the partials are a sparse
identity pattern (value 1).
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om

from wingmdao.aero.system import state_layout

N_BEAM = 18
N_AERO = 22


class BeamStateSlice(om.ExplicitComponent):
    """``beam_states[t, i, k] = states.flat[t, columns[18 i + k]]``: the 18 beam states per node out
    of a state history. ``columns`` default: the aeroelastic beam's node blocks (22 states per node,
    ``beam_states[t, i, k] = states.flat[t, 22 i + k]`` for k < 18); a joined system's beam gives its
    contiguous block, ``offset + arange(18 n)`` (:attr:`wingmdao.beam.joints.JoinedBeamSystem.offsets`).
    ``num_times=None``: one state without a time axis (``beam_states[i, k] = states.flat[columns[18 i + k]]``,
    the static or MPhys coupling use); ``input_name``/``output_name`` rename the two variables."""

    def initialize(self):
        self.options.declare("num_times", types=int, lower=1, allow_none=True,
                             desc="number of time instants; None: one state, no time axis")
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes")
        self.options.declare("state_shape", types=tuple, desc="state shape of the system per instant")
        self.options.declare("columns", default=None, allow_none=True, types=np.ndarray,
                             desc="(18 n,) state indices of the beam states per instant, node-major; None: the "
                                  "aeroelastic beam's (22 states per node)")
        self.options.declare("input_name", default="states", types=str, desc="name of the state input")
        self.options.declare("output_name", default="beam_states", types=str, desc="name of the beam-state output")

    def setup(self):
        n, timed = self.options["num_nodes"], self.options["num_times"] is not None
        nt = self.options["num_times"] if timed else 1
        shape = tuple(self.options["state_shape"])
        size = int(np.prod(shape))
        cols_one = self.options["columns"]
        if cols_one is None:
            if size < N_AERO * n:
                raise ValueError(f"state_shape {shape} has fewer than 22 * num_nodes = {N_AERO * n} states")
            cols_one = state_layout(n).beam.ravel()   # body states follow the node blocks
        cols_one = np.asarray(cols_one, dtype=int).ravel()
        if cols_one.size != N_BEAM * n or cols_one.min() < 0 or cols_one.max() >= size:
            raise ValueError(f"columns: need {N_BEAM * n} state indices in [0, {size}), got {cols_one.size} "
                             f"in [{cols_one.min()}, {cols_one.max()}]")
        lead = (nt,) if timed else ()
        iname, oname = self.options["input_name"], self.options["output_name"]
        self.add_input(iname, shape=lead + shape, desc="state history (n_time first)" if timed else "state (SI)")
        self.add_output(oname, shape=lead + (n, N_BEAM), desc="beam states r, theta, F, M, u, omega per node (SI)")
        cols = (np.arange(nt)[:, None] * size + cols_one[None, :]).ravel()
        rows = np.arange(nt * n * N_BEAM)
        self._cols_one, self._size, self._nt = cols_one, size, nt
        self.declare_partials(oname, iname, rows=rows, cols=cols, val=1.0)

    def compute(self, inputs, outputs):
        """Select the beam states (a copy of the state entries named by ``columns``).

        Parameters
        ----------
        inputs : openmdao.vectors.default_vector.DefaultVector
            The state (history) under ``input_name``.
        outputs : openmdao.vectors.default_vector.DefaultVector
            The beam states under ``output_name``.
        """
        iname, oname = self.options["input_name"], self.options["output_name"]
        flat = np.asarray(inputs[iname]).reshape(self._nt, self._size)
        outputs[oname] = flat[:, self._cols_one].reshape(outputs[oname].shape)
