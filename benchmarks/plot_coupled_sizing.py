"""Thickness distributions of PEGASUS sizings with strip-theory and coupled loads side by side
(docs/aeroelasticity.md, docs/figures/aero_sizing_thickness.png).

    wingmdao size pegasus --loads all --aero strip --json strip.json
    wingmdao size pegasus --loads all --aero coupled --aero-theory strip --json coupled.json
    wingmdao size pegasus --loads all --aero coupled --aero-theory strip --plunge free --json free.json
    python benchmarks/plot_coupled_sizing.py strip.json coupled.json free.json -o docs/figures/aero_sizing_thickness.png
"""

from __future__ import annotations

import argparse
import json
import os

import numpy as np

LABELS = {0: "strip gust / Schrenk maneuvers", 1: "coupled, clamped root", 2: "coupled, free plunge"}
WALLS = ("upper_skin", "lower_skin", "front_spar", "rear_spar")


def _span(res):
    """Station span coordinates (m): from the envelope of a multi-case run, else the PEGASUS mesh."""
    if "critical_cases" in res:
        return np.array([c["span_m"] for c in res["critical_cases"]])
    from wingmdao.cases import pegasus
    from wingmdao.cases.planform import wing_geometry

    return wing_geometry(pegasus.PLANFORM, pegasus.ENGINES)[0].node_positions[:, 1]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", nargs="+", help="sizing result JSON files (wingmdao size --json)")
    ap.add_argument("--labels", nargs="+", default=None, help="legend label per result")
    ap.add_argument("--title", default=None, help="figure title")
    ap.add_argument("-o", "--output", default="aero_sizing_thickness.png", help="PNG to write")
    args = ap.parse_args(argv)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex=True)
    for k, path in enumerate(args.results):
        with open(path, encoding="utf-8") as fh:
            res = json.load(fh)
        y = _span(res)
        label = args.labels[k] if args.labels else LABELS.get(k, os.path.basename(path))
        for ax, w in zip(axes.ravel(), WALLS):
            ax.step(y, np.asarray(res["thickness"][w]) * 1e3, where="mid", linestyle=("-", "--", ":", "-.")[k % 4],
                    linewidth=2.0 if k == 0 else 1.5, label=f"{label}: {res['mass_kg']:.1f} kg")
    for ax, w in zip(axes.ravel(), WALLS):
        ax.set_title(w.replace("_", " "))
        ax.set_ylabel("thickness (mm)")
        ax.grid(True)
        ax.ticklabel_format(axis="y", useOffset=False)
    for ax in axes[1]:
        ax.set_xlabel("span y (m)")
    axes[0, 0].legend(fontsize=8)
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    tmp = args.output + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
