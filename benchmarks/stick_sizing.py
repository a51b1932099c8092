"""PEGASUS sizing on the stick model beside the lone wing's coupled sizing (issue 29, "Speed":
goal, the stick-model sizing within 3 times the wing-alone one).

    PYTHONPATH=. python benchmarks/stick_sizing.py --t-final 2.0 --dt 0.02 --maxiter 40 [--loads all]

runs, in this process, one after the other,

    wingmdao size pegasus --loads LOADS --aero coupled --plunge free   (the lone wing, free in plunge)
    wingmdao size pegasus --model stick --loads LOADS                  (the free half aircraft)

with the same time grid and iteration limit (analysis-only with ``--analysis-only``), and prints
the mass, the optimizer's iterations and evaluations, the CPU time of each (``time.process_time``;
the stick model's CasADi build counted) and the ratio of the CPU times beside the goal.
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time

GOAL = 3.0


def _run(argv):
    from wingmdao.cli import main

    t0 = time.process_time()
    code = main(argv)
    return code, time.process_time() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--t-final", type=float, default=2.0, help="gust time grid end (s)")
    ap.add_argument("--dt", type=float, default=0.02, help="time step (s)")
    ap.add_argument("--maxiter", type=int, default=40, help="optimizer iteration limit of both sizings")
    ap.add_argument("--loads", default="gust", choices=("gust", "maneuver", "all"),
                    help="load set of both sizings (the 25.337 maneuvers, the 1-cos gust or both)")
    ap.add_argument("--analysis-only", action="store_true", help="one analysis of each, no optimizer")
    args = ap.parse_args(argv)
    common = ["--loads", args.loads, "--t-final", str(args.t_final), "--dt", str(args.dt), "--maxiter", str(args.maxiter),
              "--quiet", "--no-plots", "--no-flutter-search"] + (["--analysis-only"] if args.analysis_only else [])
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, extra in (("lone wing (coupled, free plunge)", ["--aero", "coupled", "--plunge", "free"]),
                             ("stick model", ["--model", "stick"])):
            out = os.path.join(tmp, label.split()[0])
            os.makedirs(out)
            js = os.path.join(out, "result.json")
            code, cpu = _run(["size", "pegasus", *extra, *common, "--out", out, "--json", js])
            with open(js) as f:
                res = json.load(f)
            rows.append((label, res, cpu))
            print(label, json.dumps({k: res.get(k) for k in ("mass_kg", "ks", "iterations", "success")}), flush=True)
    print(f"PEGASUS --loads {args.loads}, gust t = 0..{args.t_final} s by {args.dt} s, maxiter {args.maxiter}")
    print(f"{'model':34s} {'mass kg':>8s} {'iter':>5s} {'f-evals':>7s} {'g-evals':>7s} {'max KS':>10s} {'CPU s':>8s}")
    for label, res, cpu in rows:
        print(f"{label:34s} {res['mass_kg']:8.1f} {res['iterations']:5d} {res['function_evaluations']:7d} "
              f"{res['gradient_evaluations']:7d} {res['max_ks']:10.2e} {cpu:8.1f}")
    print(f"CPU time, stick / lone wing: {rows[1][2] / rows[0][2]:.2f} (goal <= {GOAL})")


if __name__ == "__main__":
    main()
