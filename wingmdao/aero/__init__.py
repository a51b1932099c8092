"""Unsteady strip-theory aerodynamics on the deforming beam (issue 13; docs/aeroelasticity.md).

* :mod:`wingmdao.aero.strip` - section model: Jones' Wagner and Sears-Sparks Kuessner finite
  states, Theodorsen apparent mass, Prandtl-Glauert; C(k) exact and of the approximation;
* :mod:`wingmdao.aero.system` - :func:`build_aeroelastic_system`, :class:`AeroelasticBeamSystem`;
* :mod:`wingmdao.aero.controls` - control surfaces (Theodorsen's flap functions, hinge moments),
  actuators and linear feedback laws of the coupled residual (docs/controls.md);
* :mod:`wingmdao.aero.coupled` - :class:`CoupledAero`, the aerodynamics of a coupled ``LoadCase``;
* :mod:`wingmdao.aero.weissinger` - spanwise lift slopes of a swept, tapered planform (Weissinger's
  vortex lattice, Prandtl-Glauert), for the strips' ``lift_slope``;
* :mod:`wingmdao.aero.roll` - the antisymmetric half wing on a fuselage free to roll (the
  25.349(a) rolling conditions, docs/maneuvers.md);
* :mod:`wingmdao.aero.vlm` - the vortex-lattice influence of every station's angle on every
  station's lift and moment (``aero_theory="vlm"``, docs/aerodynamics-3d.md).
"""

import importlib

#: Public name -> its module. Loaded on first access (PEP 562), so that importing a light submodule
#: (``strip``, ``pitch``, ``weissinger``) does not load the coupled model and OpenMDAO with it.
_EXPORTS = {
    "CoupledAero": "coupled",
    **dict.fromkeys(("check_aero_inputs", "kussner_sears_sparks", "station_gust_history", "theodorsen_exact",
                     "theodorsen_jones", "wagner_jones"), "strip"),
    **dict.fromkeys(("AeroelasticBeamSystem", "aero_forcing_specs", "aero_param_specs", "aero_parameters",
                     "build_aeroelastic_system", "cached_aeroelastic_system", "three_dimensional_parameters"),
                    "system"),
}

__all__ = ["CoupledAero", "AeroelasticBeamSystem", "build_aeroelastic_system", "cached_aeroelastic_system", "aero_param_specs",
           "aero_forcing_specs", "aero_parameters", "check_aero_inputs", "station_gust_history",
           "wagner_jones", "kussner_sears_sparks", "theodorsen_exact", "theodorsen_jones",
           "three_dimensional_parameters"]


def __getattr__(name):
    """The public name ``name`` from its submodule (:data:`_EXPORTS`), imported on first use."""
    if name in _EXPORTS:
        value = getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
