"""Parser of ``wingmdao cache`` (run: :mod:`wingmdao.cli.cache`)."""

from __future__ import annotations

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import add_json_argument


DEFAULT_UNUSED_DAYS = 30.0


def register(subparsers, argv=None):
    """Add ``wingmdao cache`` to the ``wingmdao`` sub-parsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line (unused: the command's options do not depend on it).
    """
    p = subparsers.add_parser(
        "cache",
        help=COMMANDS["cache"].help,
        description="The compile cache ($WINGMDAO_CACHE, default ~/.cache/wingmdao/casadi) keeps every "
        "compiled CasADi function and C kernel and every stored section/stress/load function; each new "
        "wingmdao version and beam size adds entries, none is replaced. Without --prune this only reports "
        "(entries, size, those unused for --unused-days); with --prune it removes the unused ones (they are "
        "rebuilt if needed again) and the leftovers of interrupted compiles older than a day.",
    )
    p.add_argument("--unused-days", type=float, default=DEFAULT_UNUSED_DAYS, metavar="DAYS",
                   help="an entry not loaded for more than DAYS days counts as unused (0: every entry)")
    p.add_argument("--prune", action="store_true", help="remove the unused entries (default: only report)")

    add_json_argument(p)
    p.set_defaults(func="wingmdao.cli.cache:run")
