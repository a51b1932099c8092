"""The design of a wall sizing: its design variables per section kind, their bounds and start
(:class:`SizingOptions`), and the beam properties and natural frequencies of a design, computed
directly from the section functions (App. A, F) without the OpenMDAO sizing model.

The case modules (``wingmdao.cases``) build their sizing setups from these;
:mod:`wingmdao.sizing` (the OpenMDAO problem) and :mod:`wingmdao.groups.wing` import them from here.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from wingmdao.beam.modes import natural_frequencies
from wingmdao.beam.static import beam_forcing, cached_beam_system
from wingmdao.beam.geometry import WingGeometry
from wingmdao.panels.layout import STIFFENER_VARS, PanelLayout, panel_families, smeared_stringer
from wingmdao.section.box import WALL_NAMES, beam_params_from_rows, box_properties, validate_box
from wingmdao.section.solid import solid_properties, validate_solid
from wingmdao.stress.box_stress import SECTION_PROPERTIES
from wingmdao.timemarch.system import pack

WALL_VARS = WALL_NAMES  # the one table of wall names: wingmdao.section.box


@dataclass
class SizingOptions:
    """Bounds, start, driver and scaling settings of a wall sizing.

    Parameters
    ----------
    lower : dict
        Lower bound (m) per design variable name; default 1 mm on each wall thickness.
    upper : dict
        Upper bound (m) per design variable name; default 0.1 m on each wall thickness.
    initial : dict
        Starting values (m) per design variable name; missing names start at their upper bound.
    optimizer : str
        Driver name passed to :func:`wingmdao.optimize.make_driver` (default ``"SLSQP"``).
    maxiter : int
        Largest number of optimizer iterations.
    tol : float
        Optimizer convergence tolerance.
    rho_ks : float
        KS aggregation parameter of the stress constraints.
    recording : str or None
        Path of the driver's case recorder file; None records nothing.
    mass_scale : float or None
        Objective scale (kg): objective = mass / mass_scale; None uses
        :data:`OBJECTIVE_SCALE` times the initial mass.
    disp : bool
        Let the optimizer print its own messages.
    dv_ref : dict or None
        Design-variable scaling reference (m) per name; None uses the upper bounds.
    progress : bool
        Print a line per driver evaluation (objective, worst KS, time).
    presize : int
        Number of fully stressed design passes before the optimizer (box sections, ``vm`` family).
    """
    lower: dict = field(default_factory=lambda: {w: 1e-3 for w in WALL_VARS})  # m
    upper: dict = field(default_factory=lambda: {w: 0.1 for w in WALL_VARS})  # m
    initial: dict = field(default_factory=dict)  # m, default: upper bounds
    optimizer: str = "SLSQP"
    maxiter: int = 200
    tol: float = 1e-6
    rho_ks: float = 100.0
    recording: str | None = None
    mass_scale: float | None = None  # kg, objective = mass / mass_scale (default: OBJECTIVE_SCALE x initial mass)
    disp: bool = True
    dv_ref: dict | None = None  # design-variable scaling (default: the upper bounds)
    progress: bool = False  # print a line per driver evaluation (objective, worst KS, time)
    presize: int = 0  # fully-stressed-design passes before the optimizer (box sections, vm family)


#: Default objective scaling: objective = mass / (OBJECTIVE_SCALE x initial mass), so ~0.03 at a
#: sized design. SLSQP's first quadratic subproblem uses the identity as Hessian in the scaled design
#: variables (Kraft 1988), so its step is ~ the objective gradient: with the objective ~1 the full
#: steps overshoot into the infeasible region (PEGASUS gust: KS jumps from 0.06 to 1-4) and the line
#: search backtracks two or three times per iteration. A tenfold smaller objective, same optimum
#: (PEGASUS, docs/cases.md "Objective scaling"): gust 53 -> 45 iterations and 125 -> 87 analyses,
#: maneuver 63 -> 52 and 130 -> 97; masses equal to 2e-6 (332.057 kg, 344.970 kg).
OBJECTIVE_SCALE = 10.0

#: Smallest KS parameter accepted: KS over N points exceeds the maximum by at most ln(N)/rho_KS
#: (Kreisselmeier & Steinhauser 1979; Eq. 4.53-4.55), i.e. 0.5 of the allowable for N = 150 at
#: rho_KS = 10; below, the constraint is meaningless.
RHO_KS_MIN = 10.0


#: Section kinds: the per-station inputs of the stress component (also the design variables
#: of a sizing problem are the thicknesses for a box, width and height for a solid section).
SECTION_KINDS = {
    "box": {"stress_inputs": ("width", "height") + WALL_NAMES, "design_vars": WALL_NAMES,
            "section_to_stress": SECTION_PROPERTIES},
    "solid": {"stress_inputs": ("width", "height"), "design_vars": ("width", "height"), "section_to_stress": ()},
    # the box with stiffened skins (wingmdao.panels): the stress of the box plus the panel modes
    "stiffened": {"stress_inputs": ("width", "height") + WALL_NAMES, "design_vars": WALL_NAMES + STIFFENER_VARS,
                  "section_to_stress": SECTION_PROPERTIES},
}

#: section kinds whose walls are a box's (thickness design variables, box stress recovery)
BOX_KINDS = ("box", "stiffened")


def _stringers(dv: dict, panels: PanelLayout | None):
    """The smeared stiffener layers of a per-station design (None without panels)."""
    if panels is None:
        return None
    return tuple(smeared_stringer(dv[f"h_{s}_stiffener"], dv[f"t_{s}_stiffener"], panels.stiffener_pitch,
                                  panels.shape, panels.flange_ratio) for s in ("upper", "lower"))


def station_design(geometry: WingGeometry, design: dict, design_vars) -> dict:
    """Per-node values ``{name: (n,)}`` of a design given per design station (1 or n_dv values each).

    Parameters
    ----------
    geometry : WingGeometry
        The wing; its ``station_map`` maps nodes to design stations.
    design : dict
        ``{name: values}``, 1 or n_dv values per design variable (m).
    design_vars : sequence of str
        The design variable names to expand.
    """
    n = geometry.num_nodes
    smap = np.arange(n) if geometry.station_map is None else np.asarray(geometry.station_map)
    return {w: np.asarray(np.broadcast_to(np.asarray(design[w], dtype=float), (int(smap.max()) + 1,)))[smap]
            for w in design_vars}


def design_beam_params(geometry: WingGeometry, material, design: dict, section: str = "box",
                       panels: PanelLayout | None = None) -> dict:
    """Beam parameters of a design, computed directly from the section functions (App. A, F):
    what the sizing model's section component feeds its beam. ``design`` maps the design
    variables to values per design station (1 or n_dv values each).

    Parameters
    ----------
    geometry : WingGeometry
        The wing's nodes, sections and station map.
    material : wingmdao.materials.Material
        The wall material.
    design : dict
        ``{name: values}`` per design station (m).
    section : str
        Section kind (``"box"``, ``"solid"``, ``"stiffened"``).
    panels : PanelLayout or None
        The stiffened panels (section ``"stiffened"``).
    """
    n = geometry.num_nodes
    dv = station_design(geometry, design, SECTION_KINDS[section]["design_vars"])
    if section in BOX_KINDS:
        validate_box(geometry.width, geometry.height, *(dv[w] for w in WALL_VARS), source="design: ")
    else:
        validate_solid(dv["width"], dv["height"], source="design: ")
    R = np.broadcast_to(np.eye(3), (n, 3, 3)) if geometry.section_to_csn is None else geometry.section_to_csn
    nsm = np.zeros(n) if geometry.nonstructural_mass_per_length is None else geometry.nonstructural_mass_per_length
    if section in BOX_KINDS:
        stringers = _stringers(dv, panels)
        rows = [box_properties(geometry.width[i], geometry.height[i], *(dv[w][i] for w in WALL_VARS), material,
                               section_to_csn=R[i], nonstructural_mass_per_length=nsm[i],
                               stringers=None if stringers is None else tuple(tuple(np.asarray(x)[i] for x in layer)
                                                                              for layer in stringers))
                for i in range(n)]
    else:
        rows = [solid_properties(dv["width"][i], dv["height"][i], material, section_to_csn=R[i],
                                 nonstructural_mass_per_length=nsm[i]) for i in range(n)]
    return beam_params_from_rows(rows, geometry.node_positions, geometry.node_euler_angles)


def initial_design(options: SizingOptions, design_vars) -> dict:
    """The starting design ``{name: values}``: ``options.initial``, else the upper bounds.

    Parameters
    ----------
    options : SizingOptions
        Its ``initial`` values and upper bounds.
    design_vars : sequence of str
        The design variable names.
    """
    return {w: options.initial.get(w, options.upper[w]) for w in design_vars}


def initial_frequencies(geometry: WingGeometry, material, options: SizingOptions, count: int = 3,
                        section: str = "box") -> np.ndarray:
    """Lowest natural frequencies (Hz) of the initial design's beam about its jig shape.

    Used to place structural damping (:class:`~wingmdao.beam.residual.StrainRateDamping`) at the
    first bending mode; the beam parameters come directly from :func:`design_beam_params`.

    Parameters
    ----------
    geometry : WingGeometry
        The wing's nodes, sections and station map.
    material : wingmdao.materials.Material
        The wall material.
    options : SizingOptions
        Its ``initial`` values (else upper bounds) are the initial design.
    count : int
        Number of frequencies.
    section : str
        Section kind (``"box"`` or ``"solid"``).
    """
    params = design_beam_params(geometry, material, initial_design(options, SECTION_KINDS[section]["design_vars"]),
                                section)
    system = cached_beam_system(geometry.num_nodes)
    p = np.concatenate([np.asarray(params[s.name], dtype=float).ravel() for s in system.param_specs])
    q = pack(system.forcing_specs, beam_forcing(geometry.num_nodes))
    return natural_frequencies(system, p, q, count=count)


def span_coordinate(geometry: WingGeometry) -> np.ndarray:
    """The stations' spanwise coordinate (m): ``geometry.span_coordinate``, else body y.

    Parameters
    ----------
    geometry : WingGeometry
        The wing's nodes and optional ``span_coordinate``.
    """
    if geometry.span_coordinate is not None:
        return np.asarray(geometry.span_coordinate, dtype=float)
    return np.asarray(geometry.node_positions, dtype=float)[:, 1]


def case_families(case, section: str = "box", panels: PanelLayout | None = None) -> tuple:
    """The KS families of a load case: its stress families, and with stiffened panels the panel
    modes (:func:`wingmdao.panels.layout.panel_families`).

    Parameters
    ----------
    case : LoadCase
        The load case.
    section : str
        Section kind.
    panels : PanelLayout or None
        The stiffened panels (adds their failure modes).
    """
    if section != "stiffened":
        return tuple(case.families)
    fams = panel_families(panels is not None and panels.laminate)
    return tuple(case.families) + tuple(f for f in fams if f not in case.families)
