"""Parser of ``wingmdao report`` (run: :mod:`wingmdao.cli.report`)."""

from __future__ import annotations

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import add_deprecated_alias, add_overwrite_argument


def register(subparsers, argv=None):
    """Add ``wingmdao report`` to the ``wingmdao`` sub-parsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line (unused: the command's options do not depend on it).
    """
    p = subparsers.add_parser(
        "report",
        help=COMMANDS["report"].help,
        description="Read the SQLite recording of a sizing run (written by 'wingmdao size'), "
        "print objective and worst KS constraint per driver iteration, and write PNG plots. "
        "With several recordings, also overlay their final thicknesses in thickness_comparison.png "
        "(e.g. maneuver-only against gust sizing, as Fig. 5.5-5.6 of the dissertation).",
    )
    p.add_argument("recording", metavar="FILE.sql", nargs="+", help="SQLite recording(s) of sizing runs")

    p.add_argument("--out", metavar="DIR", default=None,
                   help="folder for the PNG plots (default unset: FILE_plots next to the first recording)")
    add_deprecated_alias(p, "--plots", "--out", dest="out", metavar="DIR")
    add_overwrite_argument(p, help="replace plots an earlier report (or run) left in the --out folder instead of refusing")
    p.add_argument("--potato-stations", metavar="I", type=int, nargs="+", default=None,
                   help="station indices of the potato plots of an envelope run (default: root, mid, 3/4 span)")
    p.set_defaults(func="wingmdao.cli.report:run")
