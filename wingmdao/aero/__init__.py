"""Unsteady strip-theory aerodynamics on the deforming beam (issue 13; docs/aeroelasticity.md).

* :mod:`wingmdao.aero.strip` - section model: Jones' Wagner and Sears-Sparks Kuessner finite
  states, Theodorsen apparent mass, Prandtl-Glauert; C(k) exact and of the approximation;
* :mod:`wingmdao.aero.system` - :func:`build_aeroelastic_system`, :class:`AeroelasticBeamSystem`;
* :mod:`wingmdao.aero.controls` - control surfaces (Theodorsen's flap functions, hinge moments),
  actuators and linear feedback laws of the coupled residual (docs/controls.md);
* :mod:`wingmdao.aero.coupled` - :class:`CoupledAero`, the aerodynamics of a coupled ``LoadCase``;
* :mod:`wingmdao.aero.weissinger` - spanwise lift slopes of a swept, tapered planform (Weissinger's
  vortex lattice, Prandtl-Glauert), for the strips' ``lift_slope``;
* :mod:`wingmdao.aero.vlm` - the vortex-lattice influence of every station's angle on every
  station's lift and moment (``aero_theory="vlm"``, docs/aerodynamics-3d.md).
"""

from wingmdao.aero.coupled import CoupledAero
from wingmdao.aero.strip import (check_aero_inputs, kussner_sears_sparks, station_gust_history,
                                 theodorsen_exact, theodorsen_jones, wagner_jones)
from wingmdao.aero.system import (AeroelasticBeamSystem, aero_forcing_specs, aero_param_specs, aero_parameters,
                                  build_aeroelastic_system, cached_aeroelastic_system, three_dimensional_parameters)

__all__ = ["CoupledAero", "AeroelasticBeamSystem", "build_aeroelastic_system", "cached_aeroelastic_system", "aero_param_specs",
           "aero_forcing_specs", "aero_parameters", "check_aero_inputs", "station_gust_history",
           "wagner_jones", "kussner_sears_sparks", "theodorsen_exact", "theodorsen_jones",
           "three_dimensional_parameters"]
