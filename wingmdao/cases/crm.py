"""CRM wing (App. D.3, Tables D.5-D.6) sized for 2.5 g and -1.0 g maneuvers.

Planform from Table D.5 as a single trapezoid (4444.38 ft^2, span 193.35 ft, taper 0.86031,
leading-edge sweep 37 deg), spars at 17 % and 68 % chord, ribs from 10 % to 99.5 % semi-span
at 32 in spacing (33 rib stations plus the centre-box station). The CRM's supercritical
sections are stood in for by NACA 4-digit sections of similar thickness (14 % root, 10 % tip:
an assumption, docs/cases.md); rib yaw (-10 deg) is not modelled (streamwise stations).
Engine (assumption): 9000 kg per wing at 35 % semi-span, as a point mass.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wingmdao.cases import CaseOptions, CaseSetup, case_options, option, resolve_aero_theory
from wingmdao.cases import pegasus as _pegasus
from wingmdao.cases.pegasus import AERO_MODELS
from wingmdao.cases.planform import Planform
from wingmdao.section.box import WALL_NAMES
from wingmdao.names import CASE_HELP

NAME = "crm"
HELP = CASE_HELP[NAME]

PLANFORM = Planform(area_ft2=4444.38127, span_ft=193.34768, taper=0.86031, le_sweep_deg=37.0,
                    front_spar=0.17, rear_spar=0.68, root_rib=0.10, tip_rib=0.995, num_ribs=33,
                    airfoil_root="2414", airfoil_tip="2410")
TOGW_LB = 650000.0
#: flight point of the trimmed maneuvers with --aero coupled (assumed: App. D.3 gives only the
#: M = 0.85 cruise): 10000 ft, M = 0.7, the Mach number normal to the 37 deg leading edge 0.56
COUPLED_FLIGHT_POINT = (10000.0, 0.7)
#: highest --mach of the coupled CRM: above it the 37 deg swept wing's flow turns transonic
#: (Prandtl-Glauert does not hold)
MAX_COUPLED_MACH = 0.75
ENGINES = ((9000.0, 0.35 * PLANFORM.semi_span),)


@dataclass(frozen=True)
class CrmOptions(CaseOptions):
    """Options of the CRM case; ``wingmdao size crm --help`` describes each."""

    CASE = NAME
    load_factor: float = option(2.5, "positive maneuver load factor", metavar="N")
    negative_load_factor: float = option(-1.0, "negative maneuver load factor", metavar="N")
    families: str = option("vm", "comma list of stress families constrained", metavar="FAMILIES")
    aero: str = option("strip", "maneuver loads: strip (Schrenk spanload) or coupled (trimmed static aeroelastic "
                                "maneuvers on the deforming swept wing with the vortex lattice, at --altitude-ft / "
                                "--mach)", choices=AERO_MODELS)
    aero_theory: str | None = option(None, "quasi-steady lift of --aero coupled (the --aero-theory flag shared by the "
                                           "commands; default vlm with --aero coupled)",
                                     choices=_pegasus.AERO_THEORIES, shared=True)
    altitude_ft: float = option(COUPLED_FLIGHT_POINT[0], "altitude of the coupled maneuvers (ft, 0-60000)", metavar="FT")
    mach: float = option(COUPLED_FLIGHT_POINT[1], f"Mach number of the coupled maneuvers, (0, {MAX_COUPLED_MACH:g}]",
                         metavar="MACH")
    panels: str = _pegasus.panel_options()["panels"]
    stiffener_pitch: float = _pegasus.panel_options()["stiffener_pitch"]  # m
    rib_pitch: float | None = _pegasus.panel_options()["rib_pitch"]  # m; None: the ribs at the case's rib stations


OPTIONS = CrmOptions


#: the quasi-steady theories of the coupled CRM: the vortex lattice only (its lattice follows the
#: sweep; the 2-D strips and Prandtl's lifting line take the streamwise chord with no sweep correction)
COUPLED_THEORIES = ("vlm",)


def check_coupled(opts: CrmOptions) -> str:
    """The theory of ``--aero coupled`` on the CRM (ValueError naming the flag and the allowed values
    for a theory without sweep or a transonic Mach number, before any solve).

    Parameters
    ----------
    opts : CrmOptions
        The case's options.

    Returns
    -------
    str
        The quasi-steady theory of the coupled maneuvers (``vlm``).
    """
    theory = resolve_aero_theory(opts.aero_theory, opts.aero)
    if theory not in COUPLED_THEORIES:
        raise ValueError(f"--aero-theory {theory}: not available for the crm case (37 deg sweep): the 2-D strips and "
                         "the lifting line take the streamwise chord with no sweep correction; allowed: "
                         + ", ".join(COUPLED_THEORIES))
    if not (np.isfinite(opts.mach) and 0.0 < opts.mach <= MAX_COUPLED_MACH):
        raise ValueError(f"--mach = {opts.mach}; allowed range (0, {MAX_COUPLED_MACH:g}] for the crm case's coupled "
                         "maneuvers (above it the swept wing's flow is transonic: Prandtl-Glauert does not hold)")
    if not (np.isfinite(opts.altitude_ft) and 0.0 <= opts.altitude_ft <= 60000.0):
        raise ValueError(f"--altitude-ft = {opts.altitude_ft} ft; allowed range [0, 60000] ft")
    return theory


def build(options: CrmOptions | None = None, **overrides) -> CaseSetup:
    """The CRM geometry, its two maneuvers, material and bounds.

    Parameters
    ----------
    options : CrmOptions, optional
        The case's options; None: the defaults.
    **overrides
        Options by field name, replacing those of ``options`` (``build(load_factor=2.0)``).

    Returns
    -------
    CaseSetup
        The CRM wing, its two maneuver load cases, material and sizing bounds.

    Raises
    ------
    ValueError
        A bad option, naming its flag, before any solve.
    """
    opts = case_options(CrmOptions, options, **overrides)
    coupled = {}
    if opts.aero == "coupled":
        coupled = dict(aero="coupled", aero_theory=check_coupled(opts), altitude_ft=opts.altitude_ft, mach=opts.mach)
    elif opts.aero_theory not in (None, "strip"):
        raise ValueError(f"--aero-theory {opts.aero_theory} applies to --aero coupled (the precomputed --aero strip "
                         "loads use the Schrenk spanload)")
    elif (opts.altitude_ft, opts.mach) != COUPLED_FLIGHT_POINT:
        raise ValueError("--altitude-ft and --mach set the flight point of --aero coupled; the --aero strip maneuvers "
                         "(Schrenk spanload) have none")
    maneuvers = _pegasus.PegasusOptions(loads="maneuver", load_factor=opts.load_factor,
                                        negative_load_factor=opts.negative_load_factor, families=opts.families,
                                        panels=opts.panels, stiffener_pitch=opts.stiffener_pitch,
                                        rib_pitch=opts.rib_pitch, **coupled)
    setup = _pegasus.build_wing(maneuvers, pf=PLANFORM, engines=ENGINES, weight_lb=TOGW_LB)
    setup.options.maxiter = 1000  # 136 variables and one aggregated constraint: SLSQP needs ~700 iterations
    for w in WALL_NAMES:
        setup.options.upper[w] = 0.1
        setup.options.initial[w] = 0.02
    setup.notes = ["airfoil NACA 2414 -> 2410 stand-in for the supercritical sections (assumed)",
                   "engine as a point mass: 9000 kg at 35 % semi-span (assumed)"] + [
        n for n in setup.notes if n.startswith(("stiffened panels", "warning"))]
    return setup
