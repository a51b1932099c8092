"""Peak memory of a long history and the 25.341 envelope sizing, serial and under mpirun.

    python benchmarks/bench_envelope.py rss --steps 500 1000 [--memory lean full]   # peak RSS, 20-node PEGASUS gust
    python benchmarks/bench_envelope.py envelope [--ranks 2] [--dt 0.02] [--maxiter N]

``rss``: one sizing evaluation (forward march + adjoint totals of the KS) of a single PEGASUS gust
case with N time steps, each in a fresh process; prints the peak resident set size (ru_maxrss)
and the per-step slope, which :mod:`wingmdao.limits` uses for its memory check. ``--memory lean``
is the default model (checkpointed beam adjoint and matrix-free pointwise components above their
thresholds); ``full`` forces full storage and declared partials (the model before issue 15) and
the gradients of both are compared. Goal (issue 15): <= 500 MB at 20 nodes x 4000 steps.
``envelope``: the 20-gust (10 log-spaced gradients x up/down) + 2-maneuver PEGASUS sizing, wall
time and peak RSS (goal: 8 GB) serial and with ``mpirun -n RANKS`` (needs mpirun; as root add
--allow-run-as-root; ``--ranks 1``: serial only).
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


GOAL_MB = 500.0
ENVELOPE_GOAL_GB = 8.0


def rss_child(steps: int, memory: str = "lean") -> None:
    import numpy as np

    if memory == "full":      # full storage, declared partials
        from wingmdao.components import pointwise, time_history

        time_history.ADJOINT_MEMORY_MB = 1e12
        pointwise.POINTWISE_MATRIX_FREE_ABOVE = 1 << 62

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
    tot = prob.compute_totals(of=["cases.gust.ks_vm"], wrt=list(WALL_VARS))
    t2 = time.perf_counter()
    grad = np.concatenate([np.ravel(v) for _, v in sorted(tot.items())])
    np.save(os.path.join(tempfile.gettempdir(), f"bench_envelope_grad_{steps}_{memory}.npy"), grad)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(json.dumps({"steps": steps + 1, "memory": memory, "nodes": setup.geometry.num_nodes, "peak_mb": peak / 1024.0,
                      "base_mb": before / 1024.0, "forward_s": t1 - t0, "gradient_s": t2 - t1,
                      "ks": float(np.asarray(prob.get_val("cases.gust.ks_vm"))[0])}))


def rss(args) -> None:
    import numpy as np

    rows = []
    print(f"{'memory':>6} {'steps':>6} {'nodes':>5} {'peak RSS MB':>12} {'goal MB':>8} {'before build MB':>15} "
          f"{'forward s':>9} {'grad s':>7}  load avg")
    for n in args.steps:
        for memory in args.memory:
            out = subprocess.run([sys.executable, __file__, "_rss_child", str(n), memory], capture_output=True,
                                 text=True, env=dict(os.environ, PYTHONPATH=ROOT), check=True)
            r = json.loads(out.stdout.strip().splitlines()[-1])
            if memory == args.memory[0]:
                rows.append(r)
            goal = f"{GOAL_MB:8.0f}" if r["steps"] >= 4001 else f"{'':8s}"
            print(f"{memory:>6} {r['steps']:6d} {r['nodes']:5d} {r['peak_mb']:12.1f} {goal} {r['base_mb']:15.1f} "
                  f"{r['forward_s']:9.2f} {r['gradient_s']:7.2f}  {_load()}", flush=True)
        if len(args.memory) == 2:
            g = [np.load(os.path.join(tempfile.gettempdir(), f"bench_envelope_grad_{n}_{m}.npy")) for m in args.memory]
            print(f"       gradients {args.memory[0]} vs {args.memory[1]}: max relative difference "
                  f"{np.max(np.abs(g[0] - g[1])) / np.max(np.abs(g[1])):.1e}")
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
            proc = subprocess.Popen([*cmd, *argv, "--out", tmp, "--json", js], env=env,
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            _, _, usage = os.wait4(proc.pid, 0)     # peak RSS of this run (largest rank under mpirun)
            wall = time.perf_counter() - t0
            r = json.load(open(js))
            results[label] = (wall, r)
            print(f"{label:14s} wall {wall:7.1f} s (sizing {r['wall_s']:6.1f} s)  mass {r['mass_kg']:.4f} kg  "
                  f"iterations {r['iterations']}  success {r['success']}  peak RSS {usage.ru_maxrss / 1024**2:.2f} GB "
                  f"(goal {ENVELOPE_GOAL_GB:g} GB per process)  load avg before {load0}, after {_load()}", flush=True)
    if len(results) == 2:
        (ws, rs), (wp, rp) = results.values()
        print(f"speed-up {ws / wp:.2f} (process wall), {rs['wall_s'] / rp['wall_s']:.2f} (sizing); "
              f"mass difference {abs(rs['mass_kg'] - rp['mass_kg']):.3e} kg")


def main():
    if len(sys.argv) in (3, 4) and sys.argv[1] == "_rss_child":
        return rss_child(int(sys.argv[2]), *sys.argv[3:])
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("rss")
    r.add_argument("--steps", type=int, nargs="+", default=[500, 1000, 4000])
    r.add_argument("--memory", nargs="+", default=["lean"], choices=["lean", "full"],
                   help="lean: the default model; full: full adjoint storage and declared partials")
    e = sub.add_parser("envelope")
    e.add_argument("--ranks", type=int, default=2)
    e.add_argument("--dt", type=float, default=0.02)
    e.add_argument("--maxiter", type=int, default=None)
    args = ap.parse_args()
    rss(args) if args.cmd == "rss" else envelope(args)


if __name__ == "__main__":
    main()
