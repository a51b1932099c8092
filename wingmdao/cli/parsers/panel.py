"""Parser of ``wingmdao panel`` (run: :mod:`wingmdao.cli.panel`)."""

from __future__ import annotations

import argparse

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import add_json_argument
from wingmdao.names import DEFAULT_FLANGE_RATIO, STIFFENERS


def register(subparsers, argv=None):
    """Add ``wingmdao panel`` to the ``wingmdao`` sub-parsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line (unused: the command's options do not depend on it).
    """
    p = subparsers.add_parser(
        "panel",
        help=COMMANDS["panel"].help,
        description="Skin (or spar web) with optional blade or T stiffeners between two ribs: plate "
        "buckling of the skin between stiffeners, global panel buckling, stiffener column and crippling, "
        "material strength; critical running loads (N/m) and load-linear failure ratios (1 = failure). "
        "x is along the stiffeners. SI units; running loads in N/m, compression negative. See docs/panels.md.",
    )
    add_panel_arguments(p)
    p.set_defaults(func="wingmdao.cli.panel:run")


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
