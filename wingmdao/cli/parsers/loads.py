"""Parser of ``wingmdao loads`` (run: :mod:`wingmdao.cli.loads`)."""

from __future__ import annotations

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import add_output_arguments


CASES = ("pegasus",)


def register(subparsers, argv=None):
    """Add ``wingmdao loads`` to the ``wingmdao`` sub-parsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line (unused: the command's options do not depend on it).
    """
    p = subparsers.add_parser(
        "loads", help=COMMANDS["loads"].help,
        description="Run a loads matrix (altitudes x V_C/V_D x mass cases; every discrete gust, continuous "
        "turbulence and the maneuvers of each point), screen the internal loads of every station for the "
        "critical cases, write the loads database (HDF5) and the Nastran/CalculiX cards of the critical cases. "
        "Under 'mpirun -n P' the cases are split over the ranks. SI output.")
    p.add_argument("case", choices=CASES, metavar="CASE", help="case: " + ", ".join(CASES))
    p.add_argument("--matrix", metavar="FILE.yaml", required=True,
                   help="the matrix file (YAML; format in docs/loads-matrix.md)")
    p.add_argument("--design", metavar="RESULT.json", default=None,
                   help="thicknesses from a sizing result (its 'thickness' per station, as many stations as the "
                        "matrix's model.num_nodes); default: the initial design")
    add_output_arguments(p, what="the loads database (CASE_loads.h5) and the cards (CASE_critical.bdf, "
                                 "CASE_critical.inp)", plots=False)
    p.set_defaults(func="wingmdao.cli.loads:run")
