"""Parser of ``wingmdao flutter`` (run: :mod:`wingmdao.cli.flutter`)."""

from __future__ import annotations

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import add_aero_theory_argument, add_gravity_argument, add_output_arguments
from wingmdao.names import FLUTTER_CASES


def register(subparsers, argv=None):
    """Add ``wingmdao flutter`` to the ``wingmdao`` sub-parsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line (unused: the command's options do not depend on it).
    """
    p = subparsers.add_parser(
        "flutter", help=COMMANDS["flutter"].help,
        description="Linear stability of the aeroelastic beam (strip theory) over an airspeed sweep: flutter "
        "and divergence speeds, in vacuo frequencies, V-g / V-f plot (--aero-theory: the quasi-steady lift). SI output.")
    p.add_argument("case", metavar="CASE", help="case with aerodynamic data: " + ", ".join(FLUTTER_CASES))
    p.add_argument("--speeds", nargs=3, metavar=("V0", "V1", "N"), default=None,
                   help="sweep from V0 to V1 m/s with N >= 2 speeds (default: the case's)")
    p.add_argument("--num-nodes", type=int, default=None, metavar="N",
                   help="beam nodes, 3-200 (default: the case's; 21, pegasus 20 = its sizing mesh)")
    p.add_argument("--design", metavar="RESULT.json", default=None,
                   help="pegasus: analyse the wall thicknesses of a 'wingmdao size pegasus' JSON "
                        "(default: the sizing's initial design, 10 mm walls)")
    p.add_argument("--modes", type=int, default=4, metavar="N", help="number of modes tracked over the sweep (>= 1)")
    add_aero_theory_argument(p, default="strip", dlm=True)  # flutter: strip unless asked (docs/aerodynamics-3d.md)

    add_output_arguments(p, what="the V-g / V-f plot (flutter_CASE.png)")
    p.add_argument("--deformed", action="store_true",
                   help="also flutter about the static state at each --root-aoa-deg under gravity "
                        "(nonlinear flutter vs tip deflection; the sweep is --speeds or a fine default)")
    p.add_argument("--root-aoa-deg", type=float, nargs="+", metavar="A", default=None,
                   help="root angles of attack for --deformed, deg, |A| <= 10 (default: 1 2 3)")
    add_gravity_argument(p, help="gravity along -z for --deformed (m/s^2, >= 0; default unset: the case's, HALE "
                                 "9.807, Goland 0)")
    p.set_defaults(func="wingmdao.cli.flutter:run")
