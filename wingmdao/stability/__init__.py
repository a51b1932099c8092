"""Linear stability of any :class:`~wingmdao.timemarch.system.ResidualSystem` about a static state:
eigenvalues of the pencil (dR/dx, dR/dxdot), mode tracking over an airspeed sweep, flutter and
divergence speeds (see docs/flutter.md)."""

from wingmdao.stability.eigen import (Modes, StabilitySweep, critical_speeds, eigenmodes, linearize,
                                      mac_matrix, static_state, sweep, track_modes)

__all__ = ["Modes", "StabilitySweep", "critical_speeds", "eigenmodes", "linearize", "mac_matrix",
           "static_state", "sweep", "track_modes"]
