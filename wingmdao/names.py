"""Names and defaults that ``wingmdao COMMAND --help`` shows, in the one module that holds them.

Importing this module loads nothing but Python itself (no NumPy, CasADi, SciPy or OpenMDAO), so the
command-line parsers (:mod:`wingmdao.cli.parsers`) build every ``--help`` without the numerical
stack; the modules that compute with these names import them from here.
"""

from __future__ import annotations

#: the four walls of a box section, in the order of every wall array: upper and lower skin, front and
#: rear spar web (wingmdao.section.box)
WALL_NAMES = ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")

#: the quasi-steady lift of the coupled loads (trim, maneuvers, gusts, turbulence) when --aero-theory
#: is unset: the vortex lattice of the planform (wingmdao.aero.vlm). The flutter constraint of sizing and
#: ``wingmdao flutter`` keep strip theory unless asked (the lattice with 2-D lags is not a flutter
#: model; docs/aerodynamics-3d.md).
DEFAULT_COUPLED_THEORY = "vlm"

#: the aerodynamic theories of a coupled case (CoupledAero.aero_theory; --aero-theory): the lifting
#: line changes the strips' lift_slope (wingmdao.aero.system.three_dimensional_parameters)
AERO_THEORY_CHOICES = ("strip", "lifting-line", "vlm")

#: the cases of ``wingmdao flutter`` (wingmdao.stability.cases)
FLUTTER_CASES = ("goland", "hale", "pegasus")

#: stiffener shapes of a stiffened panel (wingmdao.panels.stiffened)
STIFFENERS = ("blade", "tee")
#: tee stiffener: flange width / web height
DEFAULT_FLANGE_RATIO = 1.0

#: App. D.1 wing box, Table E.2: spar and skin thickness in the streamwise cut (m)
WING_BOX_T_SPAR, WING_BOX_T_SKIN = 0.2, 0.1
#: App. D.1 wing box, Table D.2: widths (m), leading-edge sweeps per segment (deg), dihedral (deg)
WING_BOX_GEOMETRIES = {
    "prismatic": {"widths": (3.0, 3.0, 3.0, 3.0), "sweeps_deg": (0.0, 0.0, 0.0), "dihedral_deg": 0.0},
    "taper": {"widths": (3.0, 2.5, 2.0, 1.5), "sweeps_deg": (0.0, 0.0, 0.0), "dihedral_deg": 0.0},
    "sweep": {"widths": (3.0, 3.0, 3.0, 3.0), "sweeps_deg": (10.0, 15.0, 20.0), "dihedral_deg": 0.0},
    "dihedral": {"widths": (3.0, 3.0, 3.0, 3.0), "sweeps_deg": (0.0, 0.0, 0.0), "dihedral_deg": 5.0},
    "combined": {"widths": (3.0, 2.5, 2.0, 1.5), "sweeps_deg": (10.0, 15.0, 20.0), "dihedral_deg": 5.0},
}

#: the shipped sizing cases (``wingmdao size CASE``): name -> module (wingmdao.cases.available_cases)
CASE_MODULES = {
    "cantilever": "wingmdao.cases.cantilever",
    "wing-box": "wingmdao.cases.wing_box",
    "pegasus": "wingmdao.cases.pegasus",
    "crm": "wingmdao.cases.crm",
    "stw": "wingmdao.cases.stw",
}

#: each shipped case's one-line help (its module's ``HELP``)
CASE_HELP = {
    "cantilever": "solid rectangular cantilever of Sec. 4.7.1 (width/height design variables, tip load)",
    "wing-box": "App. D.1 'wing-like' box beam, Sec. 4.7.2 studies 1-3 (tip loads, 16 thickness variables)",
    "pegasus": "PEGASUS wing (App. D.2): 76 thickness variables, 2.5 g / -1.0 g maneuvers and/or a 25.341 gust",
    "crm": "CRM wing (App. D.3): thickness sizing for the 2.5 g and -1.0 g maneuvers",
    "stw": ("Simple Transonic Wing (MDO Aeroelastic Benchmark) Case 1: 14 m semi-span, 28 deg sweep, RAE 2822, "
            "T-stiffened wingbox between spars at 0.15 and 0.65 chord, 23 ribs; trimmed aeroelastic 2.5 g / -1 g "
            "maneuvers at sea level, M 0.458, landing gross mass"),
}
