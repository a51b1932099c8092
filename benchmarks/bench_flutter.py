"""Flutter benchmark: eigen-solve time per speed and the whole flutter search (Goland, HALE, PEGASUS),
and the cost of the PEGASUS flutter-margin constraint (value and exact gradient).

    PYTHONPATH=. python benchmarks/bench_flutter.py [goland|hale|pegasus ...] [--num-nodes N]
        [--design RESULT.json] [--margin F]
    PYTHONPATH=. python benchmarks/bench_flutter.py --record SEQ.pkl     # run the PEGASUS maneuver sizing
        with --flutter-margin F, recording every FlutterDamping input
    PYTHONPATH=. python benchmarks/bench_flutter.py --replay SEQ.pkl [--no-cold] [--no-lazy] [--refresh N]
        # warm (WarmStart) against cold at every recorded design: largest differences, CPU per evaluation
    PYTHONPATH=. python benchmarks/bench_flutter.py --sizing-cost ROUNDS [--margin F]
        # what the constraint adds to the PEGASUS maneuver sizing (goal of issue #14: at most 30 %)

Prints, per case: the aeroelastic system build, one eigen-analysis (static solve + linearisation +
sparse shift-invert + det sign) averaged over the sweep, the sweep, the refinement of the flutter
and divergence speeds, and the results against the published values (PEGASUS: against V_D).
For PEGASUS also the constraint: one cold evaluation of the KS damping constraint at its 4 speeds
and one of its gradient (left/right vectors and eigenvalue derivatives of every aggregated mode),
and the warm-started evaluation (value + gradient) along a sequence of designs with SLSQP-sized
steps, with its largest difference from the cold value.
BLAS threads are pinned to one (``OMP_NUM_THREADS=1``): on this shared 2-core machine threaded
BLAS in the small dense products made ARPACK 10-20x slower.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from wingmdao.stability import critical_speeds, sweep  # noqa: E402
from wingmdao.stability.cases import DEFAULT_NODES, FLUTTER_CASES, flutter_problem  # noqa: E402


WALLS = ("upper_skin", "lower_skin", "front_spar", "rear_spar")


def search(name, num_nodes, thickness):
    t0 = time.perf_counter()
    prob = flutter_problem(name, num_nodes or DEFAULT_NODES[name], thickness)
    t1 = time.perf_counter()
    v = prob.speeds
    res = sweep(prob.system, prob.params_at, v, n_track=4, weights=prob.beam_weights(), **prob.eig_options)
    t2 = time.perf_counter()
    crit = critical_speeds(res)
    t3 = time.perf_counter()
    pub = prob.published
    print(f"{name} ({prob.num_nodes} nodes, {prob.system.n_state} states, {v.size} speeds)")
    print(f"  build {t1 - t0:.2f} s; eigen-analysis per speed {(t2 - t1) / v.size:.3f} s; "
          f"sweep {t2 - t1:.2f} s; refinement {t3 - t2:.2f} s; whole search {t3 - t1:.2f} s")
    for key, ref in (("flutter_speed", "flutter_speed_m_s"), ("flutter_frequency", "flutter_frequency_rad_s"),
                     ("divergence_speed", "divergence_speed_m_s")):
        ours = crit[key]
        if ref in pub:
            diff = "" if ours is None else f" ({100 * (ours / pub[ref] - 1):+.2f} %)"
            print(f"  {key}: {ours} vs published {pub[ref]}{diff}")
        else:
            print(f"  {key}: {ours}" + (f" (V_D = {prob.dive_speed:.1f} m/s)" if prob.dive_speed else ""))
    return prob


def constraint_cost(prob, margin, thickness=None):
    from wingmdao.stability.cases import sizing_flutter_options
    from wingmdao.stability.sensitivity import damping_constraint

    o = sizing_flutter_options("pegasus", prob.num_nodes, margin)
    kw = dict(aero_mask=prob.aero_mask(), beam_mask=prob.beam_weights(), rho_ks=o["rho_ks"], margin=o["margin"], measure=o["measure"],
              **prob.eig_options)
    damping_constraint(prob.system, prob.params_at, o["speeds"], **kw)  # builds the CasADi gradient function
    t0 = time.perf_counter()
    val = damping_constraint(prob.system, prob.params_at, o["speeds"], gradient=False, **kw)
    t1 = time.perf_counter()
    damping_constraint(prob.system, prob.params_at, o["speeds"], **kw)
    t2 = time.perf_counter()
    print(f"  flutter constraint ({o['speeds'].size} speeds up to {margin:g} V_D = {o['speeds'][-1]:.1f} m/s, "
          f"{sum(len(e) for e in val.eigenvalues)} mode-speed points): value {val.value:+.4f} 1/s in {t1 - t0:.2f} s; "
          f"value + gradient {t2 - t1:.2f} s (cold: full eigen window)")
    warm_sequence(prob, o, kw, thickness)


def warm_sequence(prob, o, kw, thickness, n_designs=12, seed=0):
    """Warm-started constraint (WarmStart, the sizing's default) along designs whose four wall
    thicknesses jump by factors 0.6-1.5 per station (the size of SLSQP's steps in the sizing),
    every other design a return near the previous one (line searches); value + gradient per
    evaluation (process time) against the cold evaluation, and the largest |warm - cold| value."""
    from wingmdao.stability.cases import flutter_problem
    from wingmdao.stability.sensitivity import WarmStart, constraint_gradient, damping_constraint

    rng = np.random.default_rng(seed)
    from wingmdao.cases.pegasus import initial_thickness

    th0 = initial_thickness(prob.num_nodes) if thickness is None else thickness
    t0 = {w: np.asarray(th0.get(w, th0.get("t_" + w)), dtype=float) for w in WALLS}
    ws = WarmStart()
    designs, cur = [], t0
    for i in range(n_designs):
        f = rng.uniform(0.6, 1.5, (4, prob.num_nodes)) if i % 2 else rng.uniform(0.95, 1.05, (4, prob.num_nodes))
        cur = {w: np.clip(t0[w] * f[k], 1e-3, 0.02) for k, w in enumerate(WALLS)}
        designs.append(cur)
    tw = tc = 0.0
    worst = 0.0
    for th in designs:
        p = flutter_problem("pegasus", prob.num_nodes, th)
        t = time.process_time()
        rw = damping_constraint(p.system, p.params_at, o["speeds"], warm_start=ws, gradient=False, **kw)
        constraint_gradient(p.system, rw)
        tw += time.process_time() - t
        t = time.process_time()
        rc = damping_constraint(p.system, p.params_at, o["speeds"], **kw)
        tc += time.process_time() - t
        worst = max(worst, abs(rw.value - rc.value))
    n = len(designs)
    print(f"  warm start along {n} designs (steps x0.6-1.5): value + gradient {1e3 * tw / n:.1f} ms per evaluation "
          f"(cold {1e3 * tc / n:.0f} ms; goal of issue #14: ~20-25 ms); full windows {ws.n_cold}, single-speed "
          f"windows {ws.n_speed_cold}, retried speeds {ws.n_speed_retry}; max |warm - cold| {worst:.1e} 1/s")


def record(path, margin):
    """Run ``wingmdao size pegasus --loads maneuver --flutter-margin F`` and pickle every
    ``FlutterDamping`` input (beam parameters, whether the gradient was asked) to ``path``."""
    import pickle
    import tempfile

    from wingmdao.cli import main as cli
    from wingmdao.components import flutter as fl

    rec = []
    orig = fl.FlutterDamping._evaluate

    def evaluate(self, inputs, gradient):
        rec.append(({s.name: np.array(inputs[s.name]) for s in self._specs}, gradient))
        return orig(self, inputs, gradient)

    fl.FlutterDamping._evaluate = evaluate
    try:
        with tempfile.TemporaryDirectory() as out:
            cli(["size", "pegasus", "--loads", "maneuver", "--flutter-margin", str(margin), "--out", out,
                 "--no-flutter-search"])
    finally:
        fl.FlutterDamping._evaluate = orig
        tmp = path + ".tmp"
        with open(tmp, "wb") as fh:
            pickle.dump(rec, fh)
        os.replace(tmp, path)
    print(f"recorded {len(rec)} FlutterDamping evaluations to {path}")


def replay(path, margin, cold=True, lazy=True, num_nodes=20, refresh=10 ** 6):
    """Replay a :func:`record` sequence: the warm-started constraint (as the component runs it: the
    value at each new design, the gradient from the stored modes when asked) against the cold one
    at every design; prints the largest value and gradient differences, process time per warm
    evaluation (value + gradient when asked) and the warm start's counters."""
    import pickle

    from wingmdao.aero.system import cached_aeroelastic_system
    from wingmdao.stability.cases import FlutterProblem, sizing_flutter_options
    from wingmdao.stability.sensitivity import WarmStart, constraint_gradient, damping_constraint

    with open(path, "rb") as fh:
        rec = pickle.load(fh)
    o = sizing_flutter_options("pegasus", num_nodes, margin)
    system = cached_aeroelastic_system(num_nodes)
    ws = WarmStart(refresh=refresh, lazy=lazy)
    tw = tc = worst = worst_g = 0.0
    prev, rw, rc, n_grad = None, None, None, 0
    for beam, grad in rec:
        prob = FlutterProblem("sizing", num_nodes, beam, dict(o["aero"]), system, {}, dict(o["eig_options"]))
        kw = dict(aero_mask=prob.aero_mask(), beam_mask=prob.beam_weights(), rho_ks=o["rho_ks"],
                  margin=o["margin"], measure=o["measure"], **prob.eig_options)
        key = np.concatenate([np.ravel(v) for v in beam.values()])
        if prev is None or not np.array_equal(key, prev):
            prev = key
            t = time.process_time()
            rw = damping_constraint(system, prob.params_at, o["speeds"], gradient=False, warm_start=ws, **kw)
            tw += time.process_time() - t
            if cold:
                t = time.process_time()
                rc = damping_constraint(system, prob.params_at, o["speeds"], gradient=False, **kw)
                tc += time.process_time() - t
                worst = max(worst, abs(rw.value - rc.value))
        if grad and rw.gradient is None:
            t = time.process_time()
            rw.gradient = constraint_gradient(system, rw)
            tw += time.process_time() - t
            if cold:
                gc = constraint_gradient(system, rc, min_weight=0.0)
                worst_g = max(worst_g, float(np.abs(rw.gradient - gc).max() / np.abs(gc).max()))
                n_grad += 1
    n = ws.n_cold + ws.n_warm
    print(f"replay of {len(rec)} calls ({n} designs, {n_grad} gradients compared), lazy={lazy}: warm {tw:.2f} s CPU, "
          f"{1e3 * tw / n:.1f} ms per evaluation (goal of issue #14: ~20-25 ms)"
          + (f"; cold {tc:.1f} s; max |warm - cold| value {worst:.1e} 1/s, gradient {worst_g:.1e} relative" if cold else ""))
    print(f"  refresh {refresh}: eigen windows {ws.n_windows} (cold evaluations {ws.n_cold}, single-speed windows "
          f"{ws.n_speed_cold}), retried speeds {ws.n_speed_retry}, tracked from a same-design window {ws.n_speed_track}, "
          f"dropped {ws.dropped}; refinements {ws.n_refined}, lazy estimates {ws.n_skipped}, lazy re-checks "
          f"{ws.n_lazy_redo}")


_CHILD = """
import contextlib, io, json, os, sys, tempfile, time
t0 = time.process_time()
from wingmdao.cli import main as cli
from wingmdao.components import flutter as fl
spent = [0.0]
orig = fl.FlutterDamping._evaluate
def evaluate(self, inputs, gradient):
    t = time.process_time()
    try:
        return orig(self, inputs, gradient)
    finally:
        spent[0] += time.process_time() - t
fl.FlutterDamping._evaluate = evaluate
with tempfile.TemporaryDirectory() as out:
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        cli(["size", "pegasus", "--loads", "maneuver", "--no-plots", "--json", out + "/r.json", "--out", out]
            + sys.argv[1:])
    res = json.load(open(out + "/r.json"))
print(json.dumps({"cpu_s": time.process_time() - t0, "constraint_s": spent[0], "mass_kg": res["mass_kg"],
                  "iterations": res["iterations"]}))
"""


def sizing_cost(rounds, margin):
    """CPU (process time, the child's own) of ``wingmdao size pegasus --loads maneuver --no-plots``
    without and with ``--flutter-margin F``, one process each, the two alternating and the order
    swapped every round (a run right after a margin run is 1-2 s slower on this machine), and the
    constraint's own CPU (``FlutterDamping._evaluate``) in the margin runs: its ratio to the rest of
    the same process is what it adds to the command, free of drifts between processes (the
    aeroelastic build, paid by the no-margin run's flutter search, is in the margin run's set-up)."""
    import json
    import subprocess
    import sys

    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    runs = {"plain": [], "margin": []}
    for r in range(int(rounds)):
        for kind in (("plain", "margin") if r % 2 == 0 else ("margin", "plain")):
            argv = ["--flutter-margin", str(margin)] if kind == "margin" else []
            out = subprocess.run([sys.executable, "-c", _CHILD, *argv], env=env, capture_output=True, text=True,
                                 check=True).stdout
            res = json.loads(out.strip().splitlines()[-1])
            runs[kind].append(res)
            print(f"  round {r + 1} {kind:6s}: CPU {res['cpu_s']:.2f} s, constraint {res['constraint_s']:.2f} s, "
                  f"{res['mass_kg']:.3f} kg, {res['iterations']} iterations", file=sys.stderr)
    plain = np.array([x["cpu_s"] for x in runs["plain"]])
    marg = np.array([x["cpu_s"] for x in runs["margin"]])
    con = np.array([x["constraint_s"] for x in runs["margin"]])
    diff = marg - plain
    same = con / (marg - con)
    print(f"PEGASUS maneuver sizing, {rounds} pairs: no margin {plain.min():.2f}-{plain.max():.2f} s CPU (mean "
          f"{plain.mean():.2f}), --flutter-margin {margin:g} {marg.min():.2f}-{marg.max():.2f} s (mean {marg.mean():.2f})")
    print(f"  constraint's cost: pair by pair {100 * (diff / plain).min():+.0f} ... {100 * (diff / plain).max():+.0f} %, "
          f"mean {100 * diff.mean() / plain.mean():+.0f} %, median {100 * np.median(diff) / np.median(plain):+.0f} %; "
          f"its own CPU {con.min():.2f}-{con.max():.2f} s = {100 * same.min():.0f}-{100 * same.max():.0f} % of the rest "
          f"of its process (goal of issue #14: at most +30 %)")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cases", nargs="*", default=list(FLUTTER_CASES))
    ap.add_argument("--num-nodes", type=int, default=None)
    ap.add_argument("--design", default=None, help="PEGASUS: a 'wingmdao size pegasus' JSON")
    ap.add_argument("--margin", type=float, default=1.15, help="PEGASUS constraint factor F on V_D")
    ap.add_argument("--deformed", action="store_true", help="also time the HALE deformed sweep (root 2 deg)")
    ap.add_argument("--record", default=None, help="record the sizing's FlutterDamping inputs to this pickle")
    ap.add_argument("--replay", default=None, help="replay a --record pickle: warm vs cold at every design")
    ap.add_argument("--no-cold", action="store_true", help="--replay: time the warm start only")
    ap.add_argument("--no-lazy", action="store_true", help="--replay: refine every tracked mode")
    ap.add_argument("--refresh", type=int, default=10 ** 6,
                    help="--replay: WarmStart refresh (the sizing's is 100; default: off)")
    ap.add_argument("--sizing-cost", type=int, default=None, metavar="ROUNDS",
                    help="time ROUNDS pairs of PEGASUS maneuver sizings without / with --flutter-margin")
    args = ap.parse_args(argv)
    if args.sizing_cost:
        sizing_cost(args.sizing_cost, args.margin)
        return
    if args.record or args.replay:
        if args.record:
            record(args.record, args.margin)
        if args.replay:
            replay(args.replay, args.margin, cold=not args.no_cold, lazy=not args.no_lazy, refresh=args.refresh)
        return
    for name in args.cases:
        thickness = None
        if name == "pegasus" and args.design:
            from wingmdao.cli.flutter import read_design

            thickness = read_design(args.design, args.num_nodes or DEFAULT_NODES[name])
        prob = search(name, args.num_nodes, thickness)
        if name == "pegasus":
            constraint_cost(prob, args.margin, thickness)
        if name == "hale" and args.deformed:
            from wingmdao.stability.deformed import deformed_flutter

            t4 = time.perf_counter()
            rows = deformed_flutter(prob, [2.0])
            t5 = time.perf_counter()
            r = rows[0]
            print(f"  deformed (root 2 deg, g): {r.speeds.size} speeds in {t5 - t4:.2f} s "
                  f"({(t5 - t4) / r.speeds.size:.3f} s per speed): flutter {r.flutter_speed:.2f} m/s, "
                  f"tip {r.tip_deflection:.2f} m")


if __name__ == "__main__":
    main()
