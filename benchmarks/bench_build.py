"""Problem build + setup of the 21-node static wing-box case, and the compiled-cache key cost.

    OMP_NUM_THREADS=1 python benchmarks/bench_build.py [--repeat 3]

Figures (process time and wall time, s; best of ``--repeat`` fresh processes):

* ``build+setup``: ``wingmdao.cases.wing_box.problem.analysis_problem`` of the default ``wingmdao run
  wing-box`` mesh (6 + 8 + 6 elements, 21 nodes), static tip load, imports excluded; goal
  <= 0.2 s, OpenAeroStruct's structural problem on the same beam 0.065 s (issue #15);
* ``first run``: the ``run_model`` after it (a deferred beam system loads its compiled libraries,
  or builds its CasADi functions, here);
* ``beam build``: ``build_beam_system(21, defer=False)`` alone (the expression graphs);
* ``cache key``: the keys of the beam's residual, Newton and Jacobian-history functions: by
  definition (what the cache uses now) and by ``Function.serialize()`` (what it used before).
  A warm compiled cache must cost less than an interpreted 21-node gradient (~15 ms).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

GOAL, OAS = 0.2, 0.065

_CHILD = r"""
import json, time
import openmdao.api as om
import wingmdao.sizing, wingmdao.groups.wing, wingmdao.components.stress
# imports that OpenMDAO and the wing group make lazily during the first setup (mpi4py: ~0.08 s)
om.Problem(reports=False)
import wingmdao.components.beam, wingmdao.components.time_history, wingmdao.components.ks
import wingmdao.components.mass, wingmdao.components.beam_loads, wingmdao.components.station_map
from wingmdao.cases import wing_box as case
try:
    from wingmdao.cases.wing_box.problem import analysis_problem
except ImportError:     # code where the case package offered it
    analysis_problem = case.analysis_problem
from wingmdao.cases.wing_box.geometry import T_SKIN, T_SPAR
from wingmdao.groups.load_case import STRESS_FAMILIES
from wingmdao.beam import residual
from wingmdao.utils import casadi_cache as cc
try:
    from wingmdao.utils import function_store as fs
except ImportError:     # code before the persisted functions
    fs = None
out = {}
c, w = time.process_time(), time.perf_counter()
geometry, key, cs, cd = case.wing_geometry("combined", (6, 8, 6))
n = geometry.num_nodes
load = case.tip_load_case("run", n, (0.0, 0.0, 1e3), (0.0, 0.0, 0.0), STRESS_FAMILIES)
walls = {"t_upper_skin": T_SKIN * cd, "t_lower_skin": T_SKIN * cd, "t_front_spar": T_SPAR * cs,
         "t_rear_spar": T_SPAR * cs}
prob = analysis_problem(geometry, load, walls)
out["setup"] = (time.process_time() - c, time.perf_counter() - w, n)
out["store"] = dict(fs.stats) if fs else None
c, w = time.process_time(), time.perf_counter()
prob.run_model()
out["run"] = (time.process_time() - c, time.perf_counter() - w)
c, w = time.process_time(), time.perf_counter()
system = residual.build_beam_system(n, defer=False) if fs else residual.build_beam_system(n)
out["beam"] = (time.process_time() - c, time.perf_counter() - w)
funs = [system._fast_R.jit.interpreted, system._fast_newton.jit.interpreted, system._maps["J"].jit.interpreted]
c = time.process_time()
for f in funs:
    cc.function_key(f, definition=residual.beam_definition(n))
out["key_definition"] = time.process_time() - c
c = time.process_time()
for f in funs:
    cc.function_key(f)
out["key_serialize"] = time.process_time() - c
print(json.dumps(out))
"""


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="fresh processes (best of)")
    args = ap.parse_args(argv)
    env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "1"))
    runs = []
    for _ in range(args.repeat):
        res = subprocess.run([sys.executable, "-c", _CHILD], env=env, capture_output=True, text=True, check=True)
        runs.append(json.loads(res.stdout.strip().splitlines()[-1]))
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")

    def span(vals):
        return f"{min(vals):.3f} .. {max(vals):.3f}"

    n = runs[0]["setup"][2]
    print(f"load average {load:.2f}; {args.repeat} fresh processes; {n}-node static wing-box case")
    print(f"build+setup   process {span([r['setup'][0] for r in runs])} s, wall {span([r['setup'][1] for r in runs])} s"
          f"   (goal <= {GOAL} s; OpenAeroStruct {OAS} s)")
    print(f"first run     process {span([r['run'][0] for r in runs])} s, wall {span([r['run'][1] for r in runs])} s"
          "   (run_model after the setup: deferred beam functions are loaded or built here)")
    if runs[0]["store"] is not None:
        print(f"persisted functions (first process): {runs[0]['store']}")
    print(f"beam build    process {span([r['beam'][0] for r in runs])} s, wall {span([r['beam'][1] for r in runs])} s")
    print(f"cache key, 3 beam functions: by definition {span([r['key_definition'] for r in runs])} s, "
          f"by serialization {span([r['key_serialize'] for r in runs])} s")


if __name__ == "__main__":
    main()
