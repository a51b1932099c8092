"""``BeamStateSlice``: the 18 beam states per node out of the aeroelastic state history.

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
    """``beam_states[t, i, k] = states.flat[t, 22 i + k]`` for k < 18."""

    def initialize(self):
        self.options.declare("num_times", types=int, lower=1, desc="number of time instants")
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes")
        self.options.declare("state_shape", types=tuple, desc="state shape of the aeroelastic system per instant")

    def setup(self):
        nt, n = self.options["num_times"], self.options["num_nodes"]
        shape = tuple(self.options["state_shape"])
        size = int(np.prod(shape))
        if size < N_AERO * n:
            raise ValueError(f"state_shape {shape} has fewer than 22 * num_nodes = {N_AERO * n} states")
        self.add_input("states", shape=(nt,) + shape, desc="aeroelastic states (beam, lag, plunge, trim)")
        self.add_output("beam_states", shape=(nt, n, N_BEAM), desc="beam states r, theta, F, M, u, omega per node")
        cols_one = state_layout(n).beam.ravel()   # body states follow the node blocks
        cols = (np.arange(nt)[:, None] * size + cols_one[None, :]).ravel()
        rows = np.arange(nt * n * N_BEAM)
        self._cols_one, self._size = cols_one, size
        self.declare_partials("beam_states", "states", rows=rows, cols=cols, val=1.0)

    def compute(self, inputs, outputs):
        nt, n = self.options["num_times"], self.options["num_nodes"]
        flat = inputs["states"].reshape(nt, self._size)
        outputs["beam_states"] = flat[:, self._cols_one].reshape(nt, n, N_BEAM)


class StateBlockSlice(om.ExplicitComponent):
    """``beam_states[t, i, k] = states.flat[t, offset + 18 i + k]``: one beam's 18 states per node out of
    a state history whose beam block is contiguous (a beam of the joined system,
    :attr:`wingmdao.beam.joints.JoinedBeamSystem.offsets`). A selection: sparse identity partials."""

    def initialize(self):
        self.options.declare("num_times", types=int, lower=1, desc="number of time instants")
        self.options.declare("num_nodes", types=int, lower=2, desc="number of nodes of the beam")
        self.options.declare("state_size", types=int, lower=1, desc="number of states per instant")
        self.options.declare("offset", types=int, lower=0, desc="first state of the beam's block")

    def setup(self):
        nt, n = self.options["num_times"], self.options["num_nodes"]
        size, offset = self.options["state_size"], self.options["offset"]
        if offset + N_BEAM * n > size:
            raise ValueError(f"StateBlockSlice: offset {offset} + 18 * num_nodes {n} exceeds state_size {size}")
        self.add_input("states", shape=(nt, size), desc="state history (n_time first)")
        self.add_output("beam_states", shape=(nt, n, N_BEAM), desc="beam states r, theta, F, M, u, omega per node")
        cols_one = offset + np.arange(N_BEAM * n)
        cols = (np.arange(nt)[:, None] * size + cols_one[None, :]).ravel()
        self._cols_one = cols_one
        self.declare_partials("beam_states", "states", rows=np.arange(nt * n * N_BEAM), cols=cols, val=1.0)

    def compute(self, inputs, outputs):
        nt, n = self.options["num_times"], self.options["num_nodes"]
        outputs["beam_states"] = inputs["states"][:, self._cols_one].reshape(nt, n, N_BEAM)
