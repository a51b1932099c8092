"""``wingmdao cache``: what the compile cache holds, and removing what has not been used."""

from __future__ import annotations

import math
import sys

from wingmdao.cli._args import add_json_argument
from wingmdao.cli import COMMANDS, write_json
from wingmdao.utils.cache_admin import prune
from wingmdao.utils.casadi_cache import cache_dir

DEFAULT_UNUSED_DAYS = 30.0


def register(subparsers):
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
    p.set_defaults(func=run)


def _mb(n: int) -> str:
    return f"{n / 2 ** 20:.1f} MB"


def run(args) -> int:
    if not math.isfinite(args.unused_days) or args.unused_days < 0:
        raise ValueError(f"--unused-days = {args.unused_days}; allowed range [0, inf) days")
    summary = prune(cache_dir(), args.unused_days, dry_run=not args.prune)
    print(f"compile cache {summary['folder']}: {summary['entries']} entries "
          f"({summary['libraries']} compiled libraries, {summary['functions']} stored functions), "
          f"{_mb(summary['size_bytes'])}", file=sys.stderr)
    print(f"unused for more than {args.unused_days:g} days: {summary['unused_entries']} entries, "
          f"{_mb(summary['unused_bytes'])}", file=sys.stderr)
    if args.prune:
        print(f"removed {summary['removed_entries']} entries ({_mb(summary['removed_bytes'])}) and "
              f"{summary['removed_leftovers']} leftovers of interrupted compiles", file=sys.stderr)
    elif summary["unused_entries"]:
        print("(wingmdao cache --prune removes them)", file=sys.stderr)
    write_json(summary, args.json)
    return 0
