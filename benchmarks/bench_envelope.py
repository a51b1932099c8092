"""Peak memory of a long history and the 25.341 envelope sizing, serial and under mpirun.

    python benchmarks/bench_envelope.py rss --steps 500 1000 [--nodes 20]   # peak RSS, 20-node PEGASUS gust
    python benchmarks/bench_envelope.py envelope [--ranks 2] [--dt 0.02] [--maxiter N]

``rss``: one sizing evaluation (forward march + adjoint totals of the KS) of a single PEGASUS gust
case with N time steps, each in a fresh process; prints the peak resident set size (ru_maxrss)
and the per-step slope, which :mod:`wingmdao.limits` uses for its memory check.
``envelope``: the 20-gust (10 log-spaced gradients x up/down) + 2-maneuver PEGASUS sizing, wall
time serial and with ``mpirun -n RANKS`` (needs mpirun; as root add --allow-run-as-root).
The machine's load average is printed with every figure: report them together.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _load():
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def rss_child(steps: int) -> None:
    import numpy as np

    from wingmdao.cases import pegasus
    from wingmdao.sizing import WALL_VARS, build_problem

    dt = 0.01
    setup = pegasus.build(loads="gust", t_final=steps * dt, dt=dt, gust_start=0.0)
    setup.options.disp = False
    os.environ["WINGMDAO_SKIP_MEMORY_CHECK"] = "1"
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options)
    t0 = time.perf_counter()
    prob.run_model()
    t1 = time.perf_counter()
    prob.compute_totals(of=["cases.gust.ks_vm"], wrt=list(WALL_VARS))
    t2 = time.perf_counter()
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(json.dumps({"steps": steps + 1, "nodes": setup.geometry.num_nodes, "peak_mb": peak / 1024.0,
                      "base_mb": before / 1024.0, "forward_s": t1 - t0, "gradient_s": t2 - t1,
                      "ks": float(np.asarray(prob.get_val("cases.gust.ks_vm"))[0])}))


def rss(args) -> None:
    rows = []
    print(f"{'steps':>6} {'nodes':>5} {'peak RSS MB':>12} {'before build MB':>15} {'forward s':>9} {'grad s':>7}  load avg")
    for n in args.steps:
        out = subprocess.run([sys.executable, __file__, "_rss_child", str(n)], capture_output=True, text=True,
                             env=dict(os.environ, PYTHONPATH=ROOT), check=True)
        r = json.loads(out.stdout.strip().splitlines()[-1])
        rows.append(r)
        print(f"{r['steps']:6d} {r['nodes']:5d} {r['peak_mb']:12.1f} {r['base_mb']:15.1f} {r['forward_s']:9.2f} "
              f"{r['gradient_s']:7.2f}  {_load()}", flush=True)
    if len(rows) >= 2:
        a, b = rows[0], rows[-1]
        slope = (b["peak_mb"] - a["peak_mb"]) / (b["steps"] - a["steps"])
        print(f"slope: {slope * 1024:.1f} kB per step at {a['nodes']} nodes "
              f"({slope * 1024 / a['nodes']:.2f} kB per node-step)")


def envelope(args) -> None:
    argv = ["-m", "wingmdao", "size", "pegasus", "--gust-gradient-count", "10", "--gust-sign", "both",
            "--dt", str(args.dt), "--no-plots", "--quiet"] + (["--maxiter", str(args.maxiter)] if args.maxiter else [])
    env = dict(os.environ, PYTHONPATH=ROOT)
    env.pop("OPENMDAO_USE_MPI", None)
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        runs = [("serial", [sys.executable])]
        mpirun = shutil.which("mpirun")
        if mpirun and args.ranks > 1:
            flags = ["--oversubscribe"] + (["--allow-run-as-root"] if os.geteuid() == 0 else [])
            runs.append((f"mpirun -n {args.ranks}", [mpirun, *flags, "-n", str(args.ranks), sys.executable]))
        for label, cmd in runs:
            js = os.path.join(tmp, "r.json")
            load0 = _load()
            t0 = time.perf_counter()
            subprocess.run([*cmd, *argv, "--out", tmp, "--json", js], env=env, check=False,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            wall = time.perf_counter() - t0
            r = json.load(open(js))
            results[label] = (wall, r)
            print(f"{label:14s} wall {wall:7.1f} s (sizing {r['wall_s']:6.1f} s)  mass {r['mass_kg']:.4f} kg  "
                  f"iterations {r['iterations']}  success {r['success']}  load avg before {load0}, after {_load()}",
                  flush=True)
    if len(results) == 2:
        (ws, rs), (wp, rp) = results.values()
        print(f"speed-up {ws / wp:.2f} (process wall), {rs['wall_s'] / rp['wall_s']:.2f} (sizing); "
              f"mass difference {abs(rs['mass_kg'] - rp['mass_kg']):.3e} kg")


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "_rss_child":
        return rss_child(int(sys.argv[2]))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("rss")
    r.add_argument("--steps", type=int, nargs="+", default=[500, 1000, 4000])
    e = sub.add_parser("envelope")
    e.add_argument("--ranks", type=int, default=2)
    e.add_argument("--dt", type=float, default=0.02)
    e.add_argument("--maxiter", type=int, default=None)
    args = ap.parse_args()
    rss(args) if args.cmd == "rss" else envelope(args)


if __name__ == "__main__":
    main()
