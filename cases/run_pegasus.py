"""run_problem: the PEGASUS wing (App. D.2) sized for the 2.5 g / -1.0 g maneuvers and the
Table 5.3 gust, as ``wingmdao size pegasus --loads all`` does. Results in ./results/.

    python cases/run_pegasus.py [maneuver|gust|all]
"""

import json
import os
import sys

from wingmdao.cases import case_arguments, pegasus
from wingmdao.results import write_case_plots
from wingmdao.sizing import size_case

loads = sys.argv[1] if len(sys.argv) > 1 else "all"
setup = pegasus.build(case_arguments(pegasus, loads=loads))
os.makedirs("results", exist_ok=True)
setup.options.recording = f"results/pegasus_{loads}.sql"

prob, result = size_case(setup)
result["plots"] = write_case_plots(prob, setup, f"results/pegasus_{loads}")
print(json.dumps({k: result[k] for k in ("success", "mass_kg", "ks", "iterations", "wall_s", "driver")}, indent=2))
