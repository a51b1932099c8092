"""run_problem: the PEGASUS wing (App. D.2) sized for the 2.5 g / -1.0 g maneuvers and the
Table 5.3 gust, as ``wingmdao size pegasus --loads all`` does. Results in ./results/.

    python cases/run_pegasus.py [maneuver|gust|all|compare]

``compare`` sizes for the maneuvers alone and for the gust alone and overlays the two thickness
distributions (results/pegasus_static_vs_gust_thickness.png, as Fig. 5.5-5.6).
"""

import json
import os
import sys

from wingmdao.cases import pegasus
from wingmdao.plots import WALLS, plot_thickness
from wingmdao.results import span_coordinate, write_case_plots
from wingmdao.sizing import size_case, station_values

SUMMARY_KEYS = ("success", "mass_kg", "ks", "iterations", "wall_s", "driver")


def size(loads):
    setup = pegasus.build(loads=loads)
    setup.options.recording = f"results/pegasus_{loads}.sql"
    prob, result = size_case(setup)
    result["plots"] = write_case_plots(prob, setup, f"results/pegasus_{loads}")
    result["thickness_m"] = {w: station_values(prob, f"t_{w}") for w in WALLS}
    return setup, result


def main(mode):
    os.makedirs("results", exist_ok=True)
    if mode != "compare":
        _, result = size(mode)
        print(json.dumps({k: result[k] for k in SUMMARY_KEYS}, indent=2))
        return
    runs = {}
    for loads in ("maneuver", "gust"):
        setup, result = size(loads)
        runs[f"{loads} sizing ({result['mass_kg']:.1f} kg)"] = result["thickness_m"]
        print(loads, json.dumps({k: result[k] for k in SUMMARY_KEYS}))
    path = plot_thickness(span_coordinate(setup.geometry), runs, "results/pegasus_static_vs_gust_thickness.png",
                          title="PEGASUS: maneuver (static) against gust sizing")
    print(f"wrote {path}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "all")
