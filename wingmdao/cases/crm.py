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

from wingmdao.cases import CaseOptions, CaseSetup, case_options, option
from wingmdao.cases import pegasus as _pegasus
from wingmdao.cases.pegasus import AERO_MODELS
from wingmdao.cases.planform import Planform
from wingmdao.section.box import WALL_NAMES

NAME = "crm"
HELP = "CRM wing (App. D.3): thickness sizing for the 2.5 g and -1.0 g maneuvers"

PLANFORM = Planform(area_ft2=4444.38127, span_ft=193.34768, taper=0.86031, le_sweep_deg=37.0,
                    front_spar=0.17, rear_spar=0.68, root_rib=0.10, tip_rib=0.995, num_ribs=33,
                    airfoil_root="2414", airfoil_tip="2410")
TOGW_LB = 650000.0
ENGINES = ((9000.0, 0.35 * PLANFORM.semi_span),)


@dataclass(frozen=True)
class CrmOptions(CaseOptions):
    """Options of the CRM case; ``wingmdao size crm --help`` describes each."""

    CASE = NAME
    load_factor: float = option(2.5, "positive maneuver load factor", metavar="N")
    negative_load_factor: float = option(-1.0, "negative maneuver load factor", metavar="N")
    families: str = option("vm", "comma list of stress families constrained", metavar="FAMILIES")
    aero: str = option("strip", "maneuver loads: strip (Schrenk spanload) or coupled (not available for crm: see "
                                "docs)", choices=AERO_MODELS)
    panels: str = _pegasus.panel_options()["panels"]
    stiffener_pitch: float = _pegasus.panel_options()["stiffener_pitch"]  # m
    rib_pitch: float | None = _pegasus.panel_options()["rib_pitch"]  # m; None: the ribs at the case's rib stations


OPTIONS = CrmOptions


#: Why ``--aero coupled`` is refused for the CRM (docs/aeroelasticity.md).
NO_COUPLED = ("--aero coupled is not available for the crm case: App. D.3 gives the CRM's structure but no "
              "maneuver flight point, and its only speed, the M = 0.85 cruise, is transonic (Prandtl-Glauert "
              "strip theory does not hold there); the 37 deg swept strips of wingmdao.aero also take the "
              "streamwise chord with no sweep correction. Use --aero strip (Schrenk maneuvers)")


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
    if opts.aero == "coupled":
        raise ValueError(NO_COUPLED)
    maneuvers = _pegasus.PegasusOptions(loads="maneuver", load_factor=opts.load_factor,
                                        negative_load_factor=opts.negative_load_factor, families=opts.families,
                                        panels=opts.panels, stiffener_pitch=opts.stiffener_pitch,
                                        rib_pitch=opts.rib_pitch)
    setup = _pegasus.build_wing(maneuvers, pf=PLANFORM, engines=ENGINES, weight_lb=TOGW_LB)
    setup.options.maxiter = 1000  # 136 variables and one aggregated constraint: SLSQP needs ~700 iterations
    for w in WALL_NAMES:
        setup.options.upper[w] = 0.1
        setup.options.initial[w] = 0.02
    setup.notes = ["airfoil NACA 2414 -> 2410 stand-in for the supercritical sections (assumed)",
                   "engine as a point mass: 9000 kg at 35 % semi-span (assumed)"] + [
        n for n in setup.notes if n.startswith(("stiffened panels", "warning"))]
    return setup
