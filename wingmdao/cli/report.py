"""``wingmdao report FILE.sql``: iteration history of a recorded sizing run, and plots."""

from __future__ import annotations

import os


def register(subparsers):
    p = subparsers.add_parser(
        "report",
        help="print the iteration history of a recorded sizing run and write plots",
        description="Read the SQLite recording of a sizing run (written by 'wingmdao size'), "
        "print objective and worst KS constraint per driver iteration, and write PNG plots.",
    )
    p.add_argument("recording", metavar="FILE.sql", help="SQLite recording of a sizing run")
    p.add_argument("--plots", metavar="DIR", default=None,
                   help="folder for the PNG plots (default: FILE_plots next to the recording)")
    p.set_defaults(func=run)


def run(args) -> int:
    from wingmdao.report import format_history, read_history, write_report_plots

    hist = read_history(args.recording)
    print(format_history(hist))
    out = args.plots or os.path.splitext(args.recording)[0] + "_plots"
    for path in write_report_plots(hist, out):
        print(f"wrote {path}")
    return 0
