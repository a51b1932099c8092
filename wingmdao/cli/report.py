"""``wingmdao report FILE.sql [FILE2.sql ...]``: iteration history of recorded sizing runs, plots,
and with several recordings a thickness comparison (e.g. maneuver vs gust sizing, Fig. 5.5-5.6)."""

from __future__ import annotations

import glob
import os

import wingmdao.cli._openmdao  # noqa: F401  (first: OpenMDAO without the matplotlib of its report plugins)
from wingmdao.cli._io import check_output_dir, refuse_existing, warn
from wingmdao.envelope import check_stations, critical_cases, format_critical_table, load, write_plots
from wingmdao.report import format_history, format_margins, read_history, write_comparison_plot, write_report_plots


def planned_plots(out: str, subs: list[str], *, several: bool) -> list[str]:
    """Files the report would write: per recording its history and thickness plots and any
    envelope plots (``envelope*``), and the comparison plot of several recordings."""
    paths = []
    for sub in subs:
        paths += [os.path.join(sub, "iterations.png"), os.path.join(sub, "thickness_final.png")]
        paths += sorted(glob.glob(os.path.join(glob.escape(sub), "envelope_*")))
    if several:
        paths.append(os.path.join(out, "thickness_comparison.png"))
    return paths


def run(args) -> int:
    histories = {}
    for rec in args.recording:
        hist = read_history(rec)
        label = os.path.splitext(os.path.basename(rec))[0]
        histories[label if label not in histories else rec] = hist
        print(f"== {rec}: {hist['iterations']} driver iterations")
        print(format_history(hist))
        if hist.get("final_constraints"):
            print(f"-- constraints at the last evaluated design of {rec}")
            print(format_margins(hist))
    first = args.recording[0]
    out = args.out or os.path.splitext(first)[0] + "_plots"
    subs = [out if len(args.recording) == 1 else os.path.join(out, os.path.splitext(os.path.basename(rec))[0])
            for rec in args.recording]
    check_output_dir(out, "--out", create=False)
    refuse_existing(planned_plots(out, subs, several=len(histories) > 1), overwrite=args.overwrite,
                    what="plots")
    envelopes = {}  # envelope runs: loaded and their --potato-stations checked before any plot is drawn
    for rec in args.recording:
        env_file = os.path.splitext(rec)[0] + "_envelope.npz"
        if os.path.exists(env_file):
            envelopes[rec] = (env_file, load(env_file))
            check_stations(args.potato_stations, envelopes[rec][1]["span"].size)
    if args.potato_stations is not None and not envelopes:
        warn("--potato-stations ignored: none of the recordings has an envelope (*_envelope.npz)")
    for sub in dict.fromkeys(subs):
        check_output_dir(sub, "--out")
    for sub, hist in zip(subs, histories.values()):
        for path in write_report_plots(hist, sub):
            print(f"wrote {path}")
    for rec, (env_file, data) in envelopes.items():  # envelope runs: critical-case, envelope, potato plots
        print(f"== {env_file}: critical load case per station")
        print(format_critical_table(critical_cases(data)))
        sub = subs[args.recording.index(rec)]
        for path in write_plots(data, os.path.join(sub, "envelope"), args.potato_stations):
            print(f"wrote {path}")
    if len(histories) > 1:
        print(f"wrote {write_comparison_plot(histories, os.path.join(out, 'thickness_comparison.png'))}")
    return 0
