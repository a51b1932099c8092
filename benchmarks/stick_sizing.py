"""PEGASUS sizing on the stick model beside the lone wing's coupled sizing (issue 29, "Speed":
goal, the stick-model sizing within 3 times the wing-alone one).

    PYTHONPATH=. python benchmarks/stick_sizing.py --t-final 2.0 --dt 0.02 --maxiter 40 [--loads all]

runs, in this process, one after the other,

    wingmdao size pegasus --loads LOADS --aero coupled --plunge free [--aero-theory T]  (the lone wing, free in plunge)
    wingmdao size pegasus --model stick --loads LOADS                  (the free half aircraft)

with the same time grid and iteration limit (analysis-only with ``--analysis-only``), and prints
the mass, the optimizer's iterations and evaluations, the CPU time of each (``time.process_time``;
the stick model's CasADi build counted), the share of each run's CasADi evaluations that ran
compiled (``casadi_cache.EVALUATIONS``) and the ratio of the CPU times beside the goal. The ratio
is like for like only when both runs are interpreted (``WINGMDAO_JIT=0``) or both compiled from
the start (their libraries in the compiled cache: ``benchmarks/bench_stick.py --compile``);
otherwise it is printed with a warning and the exit status is 1.
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
    from wingmdao.utils import casadi_cache

    before = {k: list(v) for k, v in casadi_cache.EVALUATIONS.items()}
    t0 = time.process_time()
    code = main(argv)
    cpu = time.process_time() - t0
    runs = {k: [v[i] - before.get(k, [0, 0])[i] for i in (0, 1)] for k, v in casadi_cache.EVALUATIONS.items()}
    return code, cpu, {k: v for k, v in runs.items() if sum(v)}


def path(evaluations) -> tuple[str, str]:
    """``("compiled" | "interpreted" | "mixed", detail)`` of a run's CasADi evaluations.

    Parameters
    ----------
    evaluations : dict
        ``{function name: [interpreted, compiled]}`` evaluations of the run.

    Returns
    -------
    tuple of str
        The path and the share of evaluations that ran compiled (naming the interpreted functions).
    """
    interp = sum(v[0] for v in evaluations.values())
    total = interp + sum(v[1] for v in evaluations.values())
    kind = "interpreted" if interp == total else "compiled" if interp == 0 else "mixed"
    names = sorted(k for k, v in evaluations.items() if v[0])
    return kind, (f"{100 * (total - interp) / max(total, 1):.1f} % of {total} CasADi evaluations compiled"
                  + (f" (interpreted: {', '.join(names)})" if kind == "mixed" else ""))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--t-final", type=float, default=2.0, help="gust time grid end (s)")
    ap.add_argument("--dt", type=float, default=0.02, help="time step (s)")
    ap.add_argument("--maxiter", type=int, default=40, help="optimizer iteration limit of both sizings")
    ap.add_argument("--loads", default="gust", choices=("gust", "maneuver", "all"),
                    help="load set of both sizings (the 25.337 maneuvers, the 1-cos gust or both)")
    ap.add_argument("--aero-theory", choices=("vlm", "strip"), default=None,
                    help="the lone wing's --aero-theory (default: the command line's, vlm); the stick model has strips")
    ap.add_argument("--analysis-only", action="store_true", help="one analysis of each, no optimizer")
    args = ap.parse_args(argv)
    common = ["--loads", args.loads, "--t-final", str(args.t_final), "--dt", str(args.dt), "--maxiter", str(args.maxiter),
              "--quiet", "--no-plots", "--no-flutter-search"] + (["--analysis-only"] if args.analysis_only else [])
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        lone = ["--aero", "coupled", "--plunge", "free"] + (["--aero-theory", args.aero_theory] if args.aero_theory else [])
        for label, extra in ((f"lone wing (coupled {args.aero_theory or 'vlm'}, free plunge)", lone),
                             ("stick model", ["--model", "stick"])):
            out = os.path.join(tmp, label.split()[0] + ("" if args.aero_theory is None else "_" + args.aero_theory))
            os.makedirs(out)
            js = os.path.join(out, "result.json")
            code, cpu, evaluations = _run(["size", "pegasus", *extra, *common, "--out", out, "--json", js])
            with open(js) as f:
                res = json.load(f)
            rows.append((label, res, cpu, path(evaluations)))
            print(label, json.dumps({k: res.get(k) for k in ("mass_kg", "ks", "iterations", "success")}), flush=True)
    print(f"PEGASUS --loads {args.loads}, gust t = 0..{args.t_final} s by {args.dt} s, maxiter {args.maxiter}")
    print(f"{'model':34s} {'mass kg':>8s} {'iter':>5s} {'f-evals':>7s} {'g-evals':>7s} {'max KS':>10s} {'CPU s':>8s}")
    for label, res, cpu, (kind, detail) in rows:
        print(f"{label:34s} {res['mass_kg']:8.1f} {res['iterations']:5d} {res['function_evaluations']:7d} "
              f"{res['gradient_evaluations']:7d} {res['max_ks']:10.2e} {cpu:8.1f}  {kind}: {detail}")
    ratio = f"CPU time, stick / lone wing: {rows[1][2] / rows[0][2]:.2f} (goal <= {GOAL})"
    kinds = [r[3][0] for r in rows]
    if kinds[0] == kinds[1] != "mixed":
        print(f"{ratio}, both {kinds[0]}")
        return 0
    print(f"{ratio}; NOT like for like ({kinds[0]} / {kinds[1]}): run with WINGMDAO_JIT=0, or with both "
          "models' libraries in the compiled cache (benchmarks/bench_stick.py --compile)")
    return 1


if __name__ == "__main__":
    raise SystemExit(main())
