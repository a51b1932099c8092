"""``wingmdao panel``: buckling, crippling and strength checks of one stiffened panel as JSON."""

from __future__ import annotations

import argparse
import math
from wingmdao.cli._args import add_json_argument
from wingmdao.cli import COMMANDS, write_json
from wingmdao.panels.laminate import check_ply_fractions
from wingmdao.panels.stiffened import DEFAULT_FLANGE_RATIO, STIFFENERS, panel_analysis, panel_material


def register(subparsers):
    p = subparsers.add_parser(
        "panel",
        help=COMMANDS["panel"].help,
        description="Skin (or spar web) with optional blade or T stiffeners between two ribs: plate "
        "buckling of the skin between stiffeners, global panel buckling, stiffener column and crippling, "
        "material strength; critical running loads (N/m) and load-linear failure ratios (1 = failure). "
        "x is along the stiffeners. SI units; running loads in N/m, compression negative. See docs/panels.md.",
    )
    add_panel_arguments(p)
    p.set_defaults(func=run)


def add_panel_arguments(p):
    """The flags of ``wingmdao panel`` (material, thicknesses, sizes, stiffener, loads, ``--json``),
    shared with ``wingmdao verify panel``."""
    p.add_argument("--material", required=True, metavar="NAME",
                   help="built-in metal (aluminium, al2024-t3, al7075-t6, ti-6al-4v, steel-4130) or ply material "
                        "(stw-cfrp, needs --ply-fractions)")
    p.add_argument("--ply-fractions", type=float, nargs="+", default=None, metavar="F",
                   help="F0 F45 FM45 F90: fractions of 0, +45, -45 and 90 deg plies (4 values in [0, 1], sum 1), laminates only "
                        "(default unset: a metal)")
    p.add_argument("--t-skin", type=float, default=None, metavar="M",
                   help="skin (or spar web) thickness t (m), the --t-skin of every command; required")
    p.add_argument("--t-spar", type=float, default=None, metavar="M",
                   help="instead of --t-skin: a spar web of this thickness (m); --width is then the web height")
    # the spelling --skin-thickness is accepted too (hidden: docs/cli.md, one spelling per concept)
    p.add_argument("--skin-thickness", dest="t_skin", type=float, default=argparse.SUPPRESS, help=argparse.SUPPRESS)
    p.add_argument("--width", type=float, required=True, metavar="M",
                   help="skin width b between stiffeners, or between spars (web height of a spar) when there "
                        "are no stiffeners (m)")
    p.add_argument("--length", type=float, required=True, metavar="M", help="panel length a = rib pitch (m)")
    p.add_argument("--stiffener-height", type=float, default=None, metavar="H",
                   help="stiffener web height h (m); with --stiffener-thickness (default unset: no stiffeners)")
    p.add_argument("--stiffener-thickness", type=float, default=None, metavar="TS",
                   help="stiffener web (and flange) thickness (m) (default unset: no stiffeners)")
    p.add_argument("--stiffener", choices=STIFFENERS, default="blade",
                   help=f"stiffener shape; tee: flange width = {DEFAULT_FLANGE_RATIO:g} x height, "
                        "flange thickness = web thickness")
    p.add_argument("--nx", type=float, default=0.0, metavar="NX",
                   help="running load along the stiffeners (N/m, compression negative)")
    p.add_argument("--nxy", type=float, default=0.0, metavar="NXY", help="shear running load (N/m)")

    add_json_argument(p)


def _positive(flag: str, value) -> float:
    if value is None or not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{flag} = {value} m; allowed range (0, inf) m")
    return float(value)


def panel_result(args) -> dict:
    """The JSON-ready result from the parsed arguments (all input checks before any computation)."""
    if (args.t_skin is None) == (args.t_spar is None):
        raise ValueError("--t-skin (skin thickness, m) is required, or --t-spar (spar web thickness, m), not both; "
                         "allowed range (0, inf) m")
    t = _positive("--t-skin", args.t_skin) if args.t_spar is None else _positive("--t-spar", args.t_spar)
    b = _positive("--width", args.width)
    a = _positive("--length", args.length)
    h_given, ts_given = args.stiffener_height is not None, args.stiffener_thickness is not None
    if h_given != ts_given:
        given, missing = ("--stiffener-height", "--stiffener-thickness") if h_given else \
            ("--stiffener-thickness", "--stiffener-height")
        raise ValueError(f"{given} needs {missing} too (give both for a stiffened panel, neither for a bare skin)")
    h = _positive("--stiffener-height", args.stiffener_height) if h_given else None
    ts = _positive("--stiffener-thickness", args.stiffener_thickness) if ts_given else None
    for flag, value in (("--nx", args.nx), ("--nxy", args.nxy)):
        if not math.isfinite(value):
            raise ValueError(f"{flag} = {value} N/m; allowed range (-inf, inf) N/m (finite)")
    fractions = None if args.ply_fractions is None else check_ply_fractions(args.ply_fractions)
    pm = panel_material(args.material, fractions)
    return panel_analysis(pm, t, b, a, h, ts, nx=args.nx, nxy=args.nxy, stiffener=args.stiffener)


def run(args) -> int:
    write_json(panel_result(args), args.json)
    return 0
