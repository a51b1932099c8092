"""Cost of the PEGASUS co-design (gains + thicknesses) against the coupled gust sizing (docs/controls.md, Speed).

``OMP_NUM_THREADS=1 nice -n 10 python benchmarks/bench_codesign.py [--json-dir DIR]`` runs, each in its
own process and with the same gust and options (``--loads gust --aero coupled --aero-theory strip
--plunge free --no-plots --no-flutter-search``):

* the coupled gust sizing (thicknesses only, no surfaces);
* the co-design, ``--alleviation docs/examples/pegasus_alleviation.yaml --size-gains`` (thicknesses,
  the law's C and D, the closed-loop and actuator-limit constraints);

and prints the CPU time of each (user + system of the child process: the machine may be shared, so
not the wall time), their ratio and the goal (ratio < 3), with each run's mass, iterations and
function/gradient evaluations. Each sizing runs ``--repeat`` times (default 2) and the least CPU time
counts: the first run of a model on a machine compiles its CasADi functions into the compile cache
(``wingmdao cache``), a one-off cost that is not the sizing's. ``--json-dir`` keeps the result JSON files.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
EXAMPLE = os.path.join(ROOT, "docs", "examples", "pegasus_alleviation.yaml")
COMMON = ["size", "pegasus", "--loads", "gust", "--aero", "coupled", "--aero-theory", "strip", "--plunge", "free",
          "--no-plots", "--no-flutter-search", "--quiet"]
GOAL = 3.0


def run(extra, json_path):
    """CPU seconds (user + system) of ``wingmdao COMMON extra --json json_path`` in a child process,
    and its result."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([ROOT, os.environ.get("PYTHONPATH", "")])}
    folder = os.path.splitext(json_path)[0]   # the run's recording
    subprocess.run([sys.executable, "-m", "wingmdao", *COMMON, *extra, "--out", folder, "--overwrite",
                    "--json", json_path], check=True, env=env, stdout=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    with open(json_path, encoding="utf-8") as fh:
        return cpu, json.load(fh)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json-dir", default=None, help="keep the result JSON files here")
    ap.add_argument("--repeat", type=int, default=2, help="runs of each sizing; the least CPU time counts")
    args = ap.parse_args()
    out = args.json_dir or tempfile.mkdtemp()
    os.makedirs(out, exist_ok=True)
    rows = []
    for label, extra, name in (("coupled gust sizing", [], "gust_sizing.json"),
                               ("co-design (gains + thicknesses)", ["--alleviation", EXAMPLE, "--size-gains"],
                                "codesign.json")):
        cpus = []
        for _ in range(max(1, args.repeat)):
            cpu, res = run(extra, os.path.join(out, name))
            cpus.append(cpu)
        cpu = min(cpus)
        rows.append(cpu)
        print(f"{label}: CPU {cpu:.1f} s (runs: {', '.join(f'{c:.1f}' for c in cpus)} s), mass {res['mass_kg']:.2f} kg, {res.get('iterations')} iterations, "
              f"{res.get('function_evaluations')} function / {res.get('gradient_evaluations')} gradient evaluations")
    ratio = rows[1] / rows[0]
    print(f"ratio {ratio:.2f} (goal: < {GOAL:g}) {'met' if ratio < GOAL else 'NOT met'}")


if __name__ == "__main__":
    main()
