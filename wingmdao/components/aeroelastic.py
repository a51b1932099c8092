"""``AeroelasticBeamDynamics``: BDF2 time history of the beam with unsteady strip-theory loads.

A :class:`~wingmdao.components.time_history.TimeHistoryComponent` over
:func:`wingmdao.aero.system.build_aeroelastic_system` (docs/aeroelasticity.md). Inputs are the
beam parameter blocks (as ``BeamDynamics``), the aerodynamic parameters ``chord``, ``ref_point``,
``lift_slope``, ``alpha_zero_lift``, ``cm0``, ``airspeed``, ``density``, ``mach``, the beam forcing
blocks and ``gust_velocity`` (n_time, n_node), ``frame_velocity`` (n_time, 3). Output ``states``
(n_time, n_node, 22): 18 beam states then 4 aerodynamic lag states per node. Derivatives with
respect to every input (chord, airspeed, density included) come from the generic discrete adjoint
(or the forward tangent sweep), the same code as the structural beam.

Aerodynamic inputs are checked before any solve (ValueError naming the input, value and range).
"""

from __future__ import annotations

import numpy as np

from wingmdao.aero.system import AeroelasticBeamSystem, cached_aeroelastic_system, check_aero_parameters
from wingmdao.components.time_history import TimeHistoryComponent


class AeroelasticBeamDynamics(TimeHistoryComponent):
    """Aeroelastic beam time history (options as ``BeamDynamics``: ``num_nodes``, ``time``, ...)."""

    def initialize(self):
        super().initialize()
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes (root first)")
        self.options.declare("euler_sequence", default="surface", types=str,
                             desc="Euler-angle sequence of wingmdao.beam.residual")
        self.options.declare("system", default=None, allow_none=True, types=AeroelasticBeamSystem,
                             desc="a prebuilt aeroelastic system (None: built from num_nodes)")
        self.options.declare("plunge", default=False, types=bool,
                             desc="free plunge of the aircraft (input body_mass); clamped root otherwise")
        self.options.declare("trim", default=False, types=bool,
                             desc="trim state alpha_trim (input trim_lift, forcing trim_active)")
        self.options.declare("modified_newton", default=True, types=bool,
                             desc="reuse LU factors across Newton iterations and steps")

    def build_system(self):
        """The ``system`` option when given, else the aeroelastic beam of ``num_nodes`` nodes (cached)."""
        system = self.options["system"] or cached_aeroelastic_system(
            self.options["num_nodes"], self.options["euler_sequence"], plunge=self.options["plunge"],
            trim=self.options["trim"])
        if system.num_nodes != self.options["num_nodes"]:
            raise ValueError(f"system has {system.num_nodes} nodes but num_nodes = {self.options['num_nodes']}")
        return system

    def solve_nonlinear(self, inputs, outputs):
        # checked before the march (not in apply_nonlinear/linearize: finite-difference checks
        # may step mach = 0 to a tiny negative value, where the equations are still defined)
        check_aero_parameters({k: np.asarray(inputs[k]) for k in
                               ("chord", "ref_point", "airspeed", "density", "mach", "lift_slope")})
        super().solve_nonlinear(inputs, outputs)

    def initial_guess(self, p, q0):
        return self.system.initial_guess(p, q0)
