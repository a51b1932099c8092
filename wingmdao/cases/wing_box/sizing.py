"""Sizing studies 1-3 of Sec. 4.7.2 on the App. D.1 box (``wingmdao size wing-box``).

Sizing (Eq. 4.57): the design variables are the four wall thicknesses of the *beam-normal*
section at every beam node (the default mesh of one element per segment puts the nodes at
CS1..CS4: 4 x 4 = 16 variables as in the dissertation; the beam's element properties blend the
two end sections). Study 2's loads are given in the dissertation's axes (beam along x, 'drag'
F_y, torsion M_x); in our body axes (beam along y, x aft) drag is +x and torsion is about +y.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wingmdao.cases import CaseOptions, CaseSetup, case_options, option
from wingmdao.cases.wing_box.geometry import GEOMETRIES
from wingmdao.cases.wing_box.model import time_grid, tip_load_case, wing_geometry
from wingmdao.materials import ALUMINIUM
from wingmdao.groups.load_case import FAMILY_GROUPS, parse_families
from wingmdao.design import RHO_KS_MIN, SizingOptions

#: Eq. 4.57 bounds (m). The skins' upper bound of 1.5 m exceeds the 0.5 m box height of
#: Table D.1 (two skins must leave a web), so it is capped at SKIN_CAP (docs/cases.md).
SKIN_CAP = 0.2
BOUNDS = {"t_front_spar": (0.003, 0.25), "t_rear_spar": (0.003, 0.25),
          "t_upper_skin": (0.003, min(1.5, SKIN_CAP)), "t_lower_skin": (0.003, min(1.5, SKIN_CAP))}
#: Tip loads (body axes, N and N*m). Study 2: the dissertation's drag F_y -> +x, torsion M_x -> +y.
STUDY_LOADS = {1: ((0.0, 0.0, 2.0e6), (0.0, 0.0, 0.0)),
               2: ((1.0e5, 0.0, 2.0e6), (0.0, 1.0e6, 0.0)),
               3: ((1.0e5, 0.0, 2.0e6), (0.0, 1.0e6, 0.0))}
#: SLSQP iteration budget of these studies. The sudden study 3 (vm, 0.5 s / 0.01 s) needs 112-188
#: iterations, the count moving with the floating-point summation order (thread count, LU kernel
#: version): its KS follows a peak time that jumps between steps as the design changes, and SLSQP
#: crawls along it. The library default of 200 left no margin (CI stopped at 200 with KS 5e-5).
MAXITER = 400
#: --families shorthands and the stress families they enable (one table: wingmdao.groups.load_case)
CONSTRAINT_GROUPS = {"vm": ("vm",), **FAMILY_GROUPS}


@dataclass(frozen=True)
class WingBoxOptions(CaseOptions):
    """Options of the wing-box sizing studies (SI); ``wingmdao size wing-box --help`` describes each."""

    CASE = "wing-box"
    study: int = option(1, "Sec. 4.7.2 study: 1 static Fz = 2 MN (von Mises); 2 static Fx = 0.1 MN, Fz = 2 MN, "
                           "My = 1 MN m (body axes); 3 the study-2 loads applied suddenly (dynamic)",
                        choices=tuple(STUDY_LOADS))
    constraints: str | None = option(
        None, "comma list of stress families (vm, ss_tension, ss_compression, cent_pos, cent_neg; ss and cent: "
              "both signs); default: vm for study 1, vm,ss,cent for studies 2 and 3",
        flag="--families", metavar="FAMILIES", aliases=("--constraints",))
    geometry: str = option("combined", "Table D.2 geometry", choices=tuple(GEOMETRIES))
    elements: tuple[int, ...] = option((1, 1, 1), "beam elements per segment (design variables at every node; "
                                                  "1 1 1: CS1..CS4)", nargs=3, metavar=("N1", "N2", "N3"))
    t_final: float = option(5.0, "study 3: simulated time (s)", metavar="S")
    dt: float = option(0.01, "study 3: time step (s)", metavar="S")
    ramp_time: float = option(0.25, "study 3: raise the loads linearly over this time (s); 0 applies them suddenly "
                                    "at t > 0, which no design within the bounds of Eq. 4.57 survives with all "
                                    "constraints (docs/cases.md)", metavar="S")
    rho_ks: float = option(100.0, "KS aggregation parameter", metavar="RHO")


def parse_constraints(text) -> tuple:
    """Stress families of the ``--families`` list.

    Parameters
    ----------
    text : str
        Comma list of family names and the ss / cent shorthands (the one vocabulary of every case,
        :func:`wingmdao.groups.load_case.parse_families`).

    Returns
    -------
    tuple of str
        The stress families.
    """
    return parse_families(text)


def build(options: WingBoxOptions | None = None, **overrides) -> CaseSetup:
    """The study's geometry, tip-load case, material and Eq. 4.57 bounds.

    Parameters
    ----------
    options : WingBoxOptions, optional
        The case's options; None: the defaults.
    **overrides
        Options by field name, replacing those of ``options`` (``build(study=2, geometry="taper")``).

    Returns
    -------
    CaseSetup
        The box beam, the study's load case, material and sizing bounds.

    Raises
    ------
    ValueError
        A bad option, naming its flag, before any solve.
    """
    opts = case_options(WingBoxOptions, options, **overrides)
    default = "vm" if opts.study == 1 else "vm,ss,cent"
    families = parse_constraints(opts.constraints if opts.constraints else default)
    if len(opts.elements) != 3 or min(opts.elements) < 1:
        raise ValueError(f"--elements = {list(opts.elements)}; three counts, each >= 1 (elements per segment)")
    if not (np.isfinite(opts.rho_ks) and opts.rho_ks >= RHO_KS_MIN):
        raise ValueError(f"--rho-ks = {opts.rho_ks}; allowed range [{RHO_KS_MIN:g}, inf) (KS exceeds the "
                         "maximum stress ratio by up to ln(N)/rho_KS)")
    geometry, _, _, _ = wing_geometry(opts.geometry, tuple(opts.elements))
    force, moment = STUDY_LOADS[opts.study]
    time = time_grid(opts.t_final, opts.dt) if opts.study == 3 else None
    case = tip_load_case(f"study{opts.study}", geometry.num_nodes, force, moment, families, time=time,
                         ramp_time=opts.ramp_time if opts.study == 3 else 0.0)
    sizing = SizingOptions(lower={w: b[0] for w, b in BOUNDS.items()},
                           upper={w: b[1] for w, b in BOUNDS.items()}, rho_ks=float(opts.rho_ks),
                           maxiter=MAXITER)
    notes = [f"Eq. 4.57 skin upper bound 1.5 m capped at {SKIN_CAP} m (box height 0.5 m)",
             "thickness design variables per beam node, beam-normal cut"]
    if opts.study > 1:
        notes.append("dissertation drag F_y = 1e5 N -> +x, torsion M_x = 1e6 N m -> +y (beam along y)")
    return CaseSetup(geometry, [case], ALUMINIUM, sizing, notes=notes)
