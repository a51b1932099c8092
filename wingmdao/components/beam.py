"""Nonlinear beam components: BDF2 time history (``BeamDynamics``) and statics (``BeamStatic``).

Both are :class:`~wingmdao.components.time_history.TimeHistoryComponent` instances over the
beam residual system of ``wingmdao.beam.residual.build_beam_system`` (App. A): 18 states per
node (r, theta, F, M, u, omega; docs/conventions.md). Inputs are the beam's parameter blocks
(``node_positions``, ``node_euler_angles``, ``stiffness_csn``, ``compliance_csn``, ...) and
forcing blocks (``force_per_length``, ``point_force``, ``gravity``, ...); the output is
``states``, ``(n_time, n_node, 18)`` for ``BeamDynamics`` and ``(n_node, 18)`` for
``BeamStatic``. Gradients come from the generic discrete adjoint (Eq. 3.9-3.11).

As for every TimeHistoryComponent, parent groups must use ``LinearRunOnce`` (the default).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from wingmdao.beam.residual import STATE_BLOCKS  # per-node state layout (docs/conventions.md)
from wingmdao.components.time_history import TimeHistoryComponent
from wingmdao.timemarch.system import ResidualSystem, layout
from wingmdao.beam.static import cached_beam_system


@lru_cache(maxsize=16)
def beam_system(num_nodes: int, euler_sequence: str = "surface") -> ResidualSystem:
    """The beam residual system for ``num_nodes`` nodes, built once per size (CasADi build cached,
    shared with ``wingmdao.beam.static``)."""
    return cached_beam_system(int(num_nodes), euler_sequence)


def jig_guess(system, p) -> np.ndarray:
    """Unloaded jig state: r = node_positions, theta = node_euler_angles, F = M = u = omega = 0.

    Parameters
    ----------
    system : ResidualSystem
        The beam system.
    p : numpy.ndarray
        Packed parameters (node positions and Euler angles).

    Returns
    -------
    numpy.ndarray
        The jig state.
    """
    sl = layout(system.param_specs)
    n = system.state_shape[0]
    x = np.zeros((n, 18))
    x[:, STATE_BLOCKS["r"]] = np.asarray(p[sl["node_positions"]]).reshape(n, 3)
    x[:, STATE_BLOCKS["theta"]] = np.asarray(p[sl["node_euler_angles"]]).reshape(n, 3)
    return x.ravel()


class _BeamMixin:
    def _declare_beam_options(self):
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes (root first)")
        self.options.declare("euler_sequence", default="surface", types=str,
                             desc="Euler-angle sequence of wingmdao.beam.residual")
        # the system is built from num_nodes; do not require it as an option
        self.options.declare("system", default=None, allow_none=True, types=ResidualSystem,
                             desc="a prebuilt beam residual system (None: built from num_nodes)")

    def build_system(self):
        """The ``system`` option when given, else the beam of ``num_nodes`` nodes (cached)."""
        system = self.options["system"] or beam_system(self.options["num_nodes"], self.options["euler_sequence"])
        n_sys = system.state_shape[0]
        if n_sys != self.options["num_nodes"]:
            raise ValueError(f"system has {n_sys} nodes but num_nodes = {self.options['num_nodes']}")
        return system

    def initial_guess(self, p, q0):
        """The jig state (the beam's unloaded shape) starts the static solve of step 0."""
        guess = self.system.initial_guess(p, q0)
        return guess if np.any(guess != 0.0) else jig_guess(self.system, p)


class BeamDynamics(_BeamMixin, TimeHistoryComponent):
    """Nonlinear beam time history (BDF2, Sec. 3.5.2) with discrete-adjoint derivatives.

    Options: ``num_nodes``, ``time`` (uniform, s), ``initial`` ('static': equilibrium under the
    forcing at t = 0; 'state': input ``initial_state``), plus the TimeHistoryComponent solver
    options (``atol``, ``max_iter``, ``modified_newton`` (default True here), ``static_options``
    e.g. ``{"load_steps": 5}``, ``matrix_free``). A one-entry ``time`` is a static solve with the
    time axis kept.
    """

    def initialize(self):
        super().initialize()
        self._declare_beam_options()
        # modified Newton: 3.5x faster march of a 20-node beam (docs/time-marching.md)
        self.options.declare("modified_newton", default=True, types=bool,
                             desc="reuse LU factors across Newton iterations and steps")




class BeamStatic(_BeamMixin, TimeHistoryComponent):
    """Static equilibrium of the nonlinear beam: forcing inputs and ``states`` without a time axis.

    Options: ``num_nodes``; ``static_options`` (e.g. ``{"load_steps": 10}`` for large
    deflections) and the Newton tolerances of TimeHistoryComponent.
    """

    def initialize(self):
        super().initialize()
        self._declare_beam_options()
        self.options.declare("time", default=np.zeros(1), types=np.ndarray, desc="single instant (fixed)")
        self.options.declare("drop_time_axis", default=True, types=bool, desc="fixed: True")

    def setup(self):
        if np.asarray(self.options["time"]).size != 1:
            raise ValueError("BeamStatic solves one instant: leave the time option unset")
        super().setup()
