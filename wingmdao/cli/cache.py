"""``wingmdao cache``: what the compile cache holds, and removing what has not been used."""

from __future__ import annotations

import math
import sys

from wingmdao.cli import write_json
from wingmdao.utils.cache_admin import prune
from wingmdao.utils.casadi_cache import cache_dir


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
