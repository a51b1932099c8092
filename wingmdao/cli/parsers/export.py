"""Parser of ``wingmdao export`` (run: :mod:`wingmdao.cli.export`)."""

from __future__ import annotations

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import add_overwrite_argument
from wingmdao.cli.parsers.run import add_wing_box_arguments


#: --format of the aeroelastic Nastran deck (wingmdao.fe.nastran_aero)
AEROELASTIC = "nastran-aeroelastic"


def register(subparsers, argv=None):
    """Add ``wingmdao export`` to the ``wingmdao`` sub-parsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line (unused: the command's options do not depend on it).
    """
    p = subparsers.add_parser("export", help=COMMANDS["export"].help,
                              description="Export a case as an FE deck (SI units: m, N, kg; body axes).")
    cases = p.add_subparsers(dest="case", metavar="CASE", required=True)
    wb = cases.add_parser("wing-box", help="App. D.1 box (Table E.2 walls, or --design)")

    add_wing_box_arguments(wb)
    wb.add_argument("--design", default=None, metavar="RESULT.json",
                    help="wall thicknesses from a 'wingmdao size wing-box --elements 1 1 1' result")
    wb.add_argument("--format", choices=("calculix", "nastran", "abaqus"), required=True, help="deck format")
    wb.add_argument("--fidelity", choices=("beam", "shell"), default="beam",
                    help="beam stick model or shell model of the walls")
    add_overwrite_argument(wb, help="replace an existing FILE instead of refusing")
    wb.add_argument("file", metavar="FILE", help="deck to write")
    wb.set_defaults(func="wingmdao.cli.export:run_export")
    pg = cases.add_parser("pegasus", help="PEGASUS wing at n g (4/4/5/4 mm walls, or --design)")
    pg.add_argument("--design", default=None, metavar="RESULT.json",
                    help="wall thicknesses from a 'wingmdao size pegasus' result (20 stations)")
    pg.add_argument("--format", choices=("calculix", "nastran", "abaqus", AEROELASTIC), required=True,
                    help="deck format; nastran-aeroelastic: the beam with its masses, doublet-lattice panels, "
                    "beam splines and the flutter / gust / trim cards (docs/nastran-export.md)")
    pg.add_argument("--fidelity", choices=("beam", "shell"), default="beam",
                    help="beam stick model (one element per station interval) or shell model of the walls "
                    "(nastran-aeroelastic: beam only)")
    aero = pg.add_argument_group("nastran-aeroelastic")
    aero.add_argument("--sol", type=int, choices=(144, 145, 146), default=None,
                      help="executive and case control: 144 static aeroelastic trim, 145 flutter (PK), "
                      "146 continuous-turbulence frequency response (default 146)")
    aero.add_argument("--modes", type=int, default=None, metavar="N",
                      help="modes of EIGRL and FLUTTER, 1..200 (default 10)")
    aero.add_argument("--spanwise-boxes", type=int, default=None, metavar="N",
                      help="CAERO1 boxes along the semi-span, shared by the centre-box and outer panels, 2..500 "
                      "(default 20)")
    aero.add_argument("--chordwise-boxes", type=int, default=None, metavar="N",
                      help="CAERO1 boxes along the chord, 1..500 (default 8)")
    pg.add_argument("--load-factor", type=float, default=1.0, metavar="N",
                    help="load factor of the symmetric maneuver (lift n W and n g weight as nodal loads)")
    pg.add_argument("--no-ribs", action="store_true", help="shell: no ribs (default: ribs at the 19 rib stations)")
    pg.add_argument("--rib-thickness", type=float, default=0.002, metavar="M", help="shell: rib thickness (m)")
    add_overwrite_argument(pg, help="replace an existing FILE instead of refusing")
    pg.add_argument("file", metavar="FILE", help="deck to write")
    pg.set_defaults(func="wingmdao.cli.export:run_export_pegasus")
