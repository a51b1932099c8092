"""``CoupledAero``: the aerodynamic description of a load case on the aeroelastic beam.

A load case that carries one (``LoadCase.aero``) is analysed by
:class:`~wingmdao.components.aeroelastic.AeroelasticBeamDynamics` (unsteady strip theory on the
deforming beam, docs/aeroelasticity.md) instead of the structural ``BeamDynamics``; its gust
velocity history per station goes through the case's forcing ``gust_velocity`` (n_time, n) m/s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Aerodynamic forcing of a coupled case, shapes per instant ("n" = number of nodes).
AERO_FORCING_SHAPES = {"gust_velocity": ("n",), "frame_velocity": (3,), "frame_velocity_rate": (3,),
                       "trim_active": ()}
AERO_FORCING_META = {"gust_velocity": ("m/s", "gust velocity (body +z) at each station, penetration delay included"),
                     "frame_velocity": ("m/s", "velocity of the body-axes origin relative to the trimmed flight"),
                     "frame_velocity_rate": ("m/s**2", "rate of frame_velocity (apparent mass)"),
                     "trim_active": (None, "1: solve alpha_trim for trim_lift; 0: hold alpha_trim")}


@dataclass
class CoupledAero:
    """Per-station aerodynamic parameters (SI) of a coupled load case.

    ``chord`` (m), ``ref_point`` (beam axis, fraction of chord aft of the leading edge),
    ``lift_slope`` (1/rad), ``alpha_zero_lift`` (rad), ``cm0`` per node (scalars broadcast);
    ``airspeed`` (m/s TAS), ``density`` (kg/m**3), ``mach``; ``plunge`` frees the aircraft in
    plunge (``body_mass`` kg outside both half-wings), ``trim`` solves the aircraft angle of
    attack for ``trim_lift`` (N, both half-wings) wherever the forcing ``trim_active`` is 1.
    """

    chord: object
    airspeed: float
    density: float
    ref_point: object = 0.4
    lift_slope: object = 2 * np.pi
    alpha_zero_lift: object = 0.0
    cm0: object = 0.0
    mach: float = 0.0
    plunge: bool = False
    trim: bool = False
    body_mass: float = 0.0
    trim_lift: float = 0.0

    def parameters(self, num_nodes: int) -> dict:
        """The aerodynamic input values (validated; ValueError naming a bad input)."""
        from wingmdao.aero.system import aero_parameters

        out = aero_parameters(num_nodes, chord=self.chord, ref_point=self.ref_point, lift_slope=self.lift_slope,
                              alpha_zero_lift=self.alpha_zero_lift, cm0=self.cm0, airspeed=self.airspeed,
                              density=self.density, mach=self.mach)
        if self.plunge:
            if not (np.isfinite(self.body_mass) and self.body_mass > 0):
                raise ValueError(f"CoupledAero: body_mass must be > 0 kg with plunge=True, got {self.body_mass}")
            out["body_mass"] = float(self.body_mass)
        if self.trim:
            if not np.isfinite(self.trim_lift):
                raise ValueError(f"CoupledAero: trim_lift must be finite (N), got {self.trim_lift}")
            out["trim_lift"] = float(self.trim_lift)
        return out
