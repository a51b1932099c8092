"""Simple Transonic Wing (STW) of the MDO Aeroelastic Benchmark: beam geometry and planform data.

Data: :mod:`wingmdao.cases.stw_data` (each value with its source file in the benchmark
repository ``MDOBenchmarks/MDOAeroelasticBenchmark``). This module turns them into

* :func:`rib_y`: the 23 rib planes (streamwise, constant y), nominal ends 0 and 14 m;
* :func:`beam_geometry`: the beam of the wingbox, a :class:`wingmdao.sizing.WingGeometry`
  with nodes on the mid-box line (halfway between the spars in the streamwise section), a node
  at every rib and more nodes, if asked, inside the rib bays; box width and height per node;
* :func:`aero_reference`: chord, leading edge, quarter-chord line and its sweep per station,
  and the reference area, MAC and aspect ratio, for a strip or lifting-line model.

Assumptions (docs/cases.md, section "stw"): the beam axis lies in the chord plane (z = 0, the
wing has no dihedral); box height from the RAE 2822 thickness at the two spars (mean of the two
spar heights, or the project's Eq. 4.12 mean of ten heights); the default cut is normal to the
beam axis (chordwise dimensions x cos Lambda, as the wing-box case does). The benchmark's
supports (symmetry at y = 0, x and z held at the side of body) are not modelled: the beam is
clamped at y = 0 (docs/cases.md).

The sizing case ``wingmdao size stw`` (:func:`build`, :class:`StwOptions`): Case 1, the two
trimmed aeroelastic maneuvers of :mod:`wingmdao.cases.stw_loads`, stiffened panels (tee
stiffeners at 0.15 m, the 23 ribs, safety factor 1.5), the benchmark's minimum gauges as
bounds; the wall material from :func:`stw_material`. After a run :func:`write_outputs` writes
the lift and twist distributions of both maneuvers as CSV files beside the JSON.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wingmdao.cases import CaseOptions, CaseSetup, case_options, option
from wingmdao.cases import stw_data as D
from wingmdao.cases import stw_loads
from wingmdao.cases.planform import G0
from wingmdao.design import WALL_VARS, SizingOptions
from wingmdao.groups.load_case import parse_families
from wingmdao.materials import Material
from wingmdao.panels.laminate import STW_SKIN_FRACTIONS, STW_SPAR_FRACTIONS, laminate_moduli
from wingmdao.panels.layout import PanelLayout, STIFFENER_VARS
from wingmdao.panels.stiffened import panel_material
from wingmdao.names import CASE_HELP

NAME = "stw"
HELP = CASE_HELP[NAME]

from wingmdao.cases.stw_geometry import (  # noqa: F401, E402  (the case's geometry, re-exported)
    CUTS, HEIGHT_RULES, chord, leading_edge_x, spar_x, rib_y, airfoil_surfaces,
    thickness_to_chord, StwBeam, node_y, beam_geometry, AeroReference,
    quarter_chord_sweep_deg, aero_reference)

LOAD_SETS = ("maneuver",)
#: maneuver load cases: (name, benchmark flight condition)
MANEUVERS = (("pullup", D.PULL_UP), ("pushdown", D.PUSH_DOWN))
#: rib web thickness (m), not sized (an assumption: the benchmark sizes its ribs as panels)
RIB_THICKNESS = 2e-3
#: wall thickness bounds and start (m): the benchmark's minimum gauge 0.6 mm, start at its baseline panel
WALL_BOUNDS = (D.SIZING_RULES.min_skin_thickness, 0.03, D.BASELINE_PANEL.panel_thickness)
#: stiffener (lower, upper, start), m: web height >= the flange width 25.4 mm (flange = height),
#: <= the pitch (flange width <= pitch); thickness >= 0.6 mm; start at the baseline panel
STIFFENER_BOUNDS = {"h": (max(D.SIZING_RULES.min_stiffener_height, D.SIZING_RULES.min_flange_width),
                          D.STIFFENER_PITCH, D.BASELINE_PANEL.stiffener_height),
                    "t": (D.SIZING_RULES.min_stiffener_thickness, 0.01, D.BASELINE_PANEL.stiffener_thickness)}


def stw_laminates():
    """The benchmark's laminates (``stw_data``; ply ``stw-cfrp``) as panel materials: (skins and
    stiffeners, spar webs and ribs)."""
    return panel_material("stw-cfrp", STW_SKIN_FRACTIONS), panel_material("stw-cfrp", STW_SPAR_FRACTIONS)


def stw_material():
    """The sizing's reference material: isotropic with the skin laminate's membrane modulus Ex and
    the ply density (nu = 0.3 sets the reference G; every wall is weighted by its own laminate's
    Ex, G_xy and density against it, the transformed section of ``PanelLayout.wall_factors``).
    Strength is the laminates' Tsai-Wu first-ply failure (the panels' ``laminate_strength``
    family), so this material's sigma_y enters no constraint."""
    skin, _ = stw_laminates()
    ex = laminate_moduli(skin.base, skin.fractions)["Ex"]
    return Material("stw-cfrp (skin laminate Ex)", E=ex, rho=skin.base.rho, sigma_y=skin.compression_strength, nu=0.3)


@dataclass(frozen=True)
class StwOptions(CaseOptions):
    """Options of the STW case (units in the names); ``wingmdao size stw --help`` describes each."""

    CASE = NAME
    loads: str = option("maneuver", "load cases: both Case 1 maneuvers (2.5 g pull-up, -1 g push-down at sea level, "
                                    "M 0.458), trimmed aeroelastic (strip theory with Weissinger lift slopes on the "
                                    "deforming beam)", choices=LOAD_SETS)
    num_nodes: int = option(D.NUM_RIBS, "beam nodes (>= 23: one at each rib, more spread over the rib bays)",
                            metavar="N")
    wingbox_mass: float | None = option(
        None, "wingbox mass of one wing (kg) for the landing gross mass of the loads (LGM = 41 500 kg + 2 x 10.147 "
              "M_wingbox^0.8162); default unset: the benchmark's baseline panel sizing on this beam (rerun with the "
              "sized mass to iterate)", metavar="KG")
    families: str = option("vm", "comma list of stress families constrained (vm, ss_tension, ss_compression, "
                                 "cent_pos, cent_neg); the panel modes are always constrained", metavar="FAMILIES")
    cut: str = option("normal", "box section cut: normal to the beam axis or streamwise", choices=CUTS)
    height_rule: str = option("spars", "box height: mean of the two spar heights or of ten heights between the "
                                       "spars", choices=HEIGHT_RULES)


OPTIONS = StwOptions


def build(options: StwOptions | None = None, **overrides) -> CaseSetup:
    """The STW Case 1 sizing: beam, both trimmed maneuvers, material and bounds.

    Parameters
    ----------
    options : StwOptions, optional
        The case's options; None: the defaults.
    **overrides
        Options by field name, replacing those of ``options`` (``build(num_nodes=40)``).

    Returns
    -------
    CaseSetup
        The stiffened wingbox beam, both maneuver load cases, material and sizing bounds.

    Raises
    ------
    ValueError
        A bad option, naming its flag, before any solve.
    """
    opts = case_options(StwOptions, options, **overrides)
    if isinstance(opts.num_nodes, int) and opts.num_nodes < D.NUM_RIBS:
        raise ValueError(f"--num-nodes = {opts.num_nodes}; allowed range >= {D.NUM_RIBS} (a node at each rib)")
    if opts.num_nodes > 200:
        raise ValueError(f"--num-nodes = {opts.num_nodes}; allowed range {D.NUM_RIBS}-200")
    if opts.wingbox_mass is not None and not (np.isfinite(opts.wingbox_mass) and opts.wingbox_mass > 0):
        raise ValueError(f"--wingbox-mass = {opts.wingbox_mass} kg; allowed range (0, inf) kg")
    families = ()   # laminate walls: strength by the panels' Tsai-Wu family, not a metal's stress families
    if opts.families != StwOptions.families:
        parse_families(opts.families)
        notes_families = [f"warning: --families {opts.families} ignored: the laminate walls' strength is the panels' "
                          "Tsai-Wu family (laminate_strength)"]
    else:
        notes_families = []
    beam = beam_geometry(opts.num_nodes, cut=opts.cut, height_rule=opts.height_rule)
    material = stw_material()
    if opts.wingbox_mass is None:
        box_mass = stw_loads.baseline_wingbox_mass(beam, material)
        where = f"the baseline panel sizing in {material.name}"
    else:
        box_mass, where = float(opts.wingbox_mass), "given"
    lgm = D.landing_gross_mass(box_mass)
    cases = [stw_loads.maneuver_case(name, cond, beam, lgm, families) for name, cond in MANEUVERS]
    lo, up, start = WALL_BOUNDS
    sizing = SizingOptions(lower={w: lo for w in WALL_VARS}, upper={w: up for w in WALL_VARS},
                           initial={w: start for w in WALL_VARS}, rho_ks=100.0, maxiter=400)
    for name in STIFFENER_VARS:
        lo, up, start = STIFFENER_BOUNDS[name[0]]
        sizing.lower[name], sizing.upper[name], sizing.initial[name] = lo, up, start
    skin_laminate, spar_laminate = stw_laminates()
    sp = stw_loads.strip_parameters(beam)
    notes = [f"loads: LGM {lgm:.0f} kg from a wingbox mass of {box_mass:.0f} kg per wing ({where})",
             f"aerodynamics: strip theory on the deforming beam, Weissinger lift slopes at M {D.PULL_UP.mach:g} "
             f"(CL_alpha {sp['CL_alpha']:.3f} /rad), RAE 2822 camber by thin-airfoil theory",
             "walls: the benchmark's laminates (ply stw-cfrp; skins and stiffeners [0/+45/-45/90] = "
             f"{'/'.join(f'{f:.4g}' for f in skin_laminate.fractions)}, spars "
             f"{'/'.join(f'{f:.4g}' for f in spar_laminate.fractions)}), smeared, stacking ignored; Tsai-Wu "
             f"first-ply failure at safety factor {D.SAFETY_FACTOR:g}",
             "root clamped at y = 0: the benchmark's side-of-body support (x, z held at y = 1.5 m) is not modelled",
             f"stiffened panels: tee stiffeners at {D.STIFFENER_PITCH * 1e3:.0f} mm, flange = web height, "
             f"{D.NUM_RIBS} ribs {RIB_THICKNESS * 1e3:.0f} mm thick (assumed), safety factor {D.SAFETY_FACTOR:g} "
             "on buckling"] + notes_families
    setup = CaseSetup(beam.geometry, cases, material, sizing, section="stiffened", notes=notes,
                      panels=PanelLayout(rib_positions=tuple(beam.rib_y), stiffener_pitch=D.STIFFENER_PITCH,
                                         shape="tee", flange_ratio=1.0, safety_factor=D.SAFETY_FACTOR,
                                         rib_thickness=RIB_THICKNESS, skin_material=skin_laminate,
                                         spar_material=spar_laminate))
    setup.stw = {"beam": beam, "wingbox_mass_kg": box_mass, "landing_gross_mass_kg": lgm, "wingbox_mass_source": where}
    return setup


def output_files(stem: str, setup) -> list:
    """The files :func:`write_outputs` writes (checked before the run).

    Parameters
    ----------
    stem : str
        Path stem of the run's outputs (``--out`` folder and case name).
    setup : CaseSetup
        The built case.

    Returns
    -------
    list of str
        One CSV path per maneuver.
    """
    return [f"{stem}_{case.name}_distribution.csv" for case in setup.load_cases]


def write_outputs(prob, setup, stem: str, result: dict) -> list:
    """Write the lift and twist distributions of both maneuvers at the final design.

    Parameters
    ----------
    prob : openmdao.api.Problem
        The sized problem.
    setup : CaseSetup
        The built case.
    stem : str
        Path stem of the run's outputs (:func:`output_files`).
    result : dict
        The run's result; ``result["maneuvers"]`` receives each maneuver's angle of attack, load
        factor, lift (N) and root bending moment (N m), and the loads' masses (kg).

    Returns
    -------
    list of str
        The CSV files written (columns ``stw_loads.CSV_COLUMNS``).
    """
    info = setup.stw
    beam = info["beam"]
    paths, summary = [], {}
    weight = info["landing_gross_mass_kg"] * G0
    for case, path in zip(setup.load_cases, output_files(stem, setup)):
        st = stw_loads.trimmed_state(prob, case, beam)
        paths.append(stw_loads.write_distribution_csv(path, st))
        summary[case.name] = {"alpha_deg": st["alpha_deg"], "load_factor": st["total_lift_n"] / weight,
                              "total_lift_n": st["total_lift_n"],
                              "root_bending_moment_n_m": st["root_bending_moment_n_m"],
                              "tip_twist_deg": float(st["twist_deg"][-1]), "distribution_file": path}
    result["maneuvers"] = summary
    result["loads_wingbox_mass_kg"] = info["wingbox_mass_kg"]
    result["loads_landing_gross_mass_kg"] = info["landing_gross_mass_kg"]
    if "mass_kg" in result:
        result["landing_gross_mass_of_result_kg"] = D.landing_gross_mass(float(result["mass_kg"]))
    result["distribution_files"] = paths
    return paths
