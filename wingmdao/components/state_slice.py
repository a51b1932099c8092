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
    contiguous block, ``offset + arange(18 n)`` (:attr:`wingmdao.beam.joints.JoinedBeamSystem.offsets`)."""

    def initialize(self):
        self.options.declare("num_times", types=int, lower=1, desc="number of time instants")
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes")
        self.options.declare("state_shape", types=tuple, desc="state shape of the system per instant")
        self.options.declare("columns", default=None, allow_none=True, types=np.ndarray,
                             desc="(18 n,) state indices of the beam states per instant, node-major; None: the "
                                  "aeroelastic beam's (22 states per node)")

    def setup(self):
        nt, n = self.options["num_times"], self.options["num_nodes"]
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
        self.add_input("states", shape=(nt,) + shape, desc="state history (n_time first)")
        self.add_output("beam_states", shape=(nt, n, N_BEAM), desc="beam states r, theta, F, M, u, omega per node")
        cols = (np.arange(nt)[:, None] * size + cols_one[None, :]).ravel()
        rows = np.arange(nt * n * N_BEAM)
        self._cols_one, self._size = cols_one, size
        self.declare_partials("beam_states", "states", rows=rows, cols=cols, val=1.0)

    def compute(self, inputs, outputs):
        nt, n = self.options["num_times"], self.options["num_nodes"]
        flat = inputs["states"].reshape(nt, self._size)
        outputs["beam_states"] = flat[:, self._cols_one].reshape(nt, n, N_BEAM)
