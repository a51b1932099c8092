"""Stick model against the lone wing: march and gradient of the PEGASUS gust KS (issue 29, "Speed").

    PYTHONPATH=. python benchmarks/bench_stick.py                # 500 steps
    PYTHONPATH=. python benchmarks/bench_stick.py --steps 100    # quicker

Builds the sizing models of ``wingmdao size pegasus --model stick`` (the free half aircraft: wing,
fuselage, fin, horizontal tail; :func:`wingmdao.sizing.build_stick_problem`) and of the lone wing
(``--aero coupled --plunge free``; :func:`wingmdao.sizing.build_problem`) on the same time grid,
and times one analysis (``run_model``: the BDF2 march, stresses, KS) and one gradient
(``compute_totals`` of the KS with respect to the four walls: the discrete adjoint). Prints
the cost per beam node of each model and their ratio beside the goal (<= 1.3), whether the
march ran compiled (``compiled_steps`` of its history; the CasADi libraries come from the
compiled cache, or are compiled in the background after ``JIT_THRESHOLD`` evaluations, so the
first runs of a new definition are interpreted) and the adjoint's static-pivot LU statistics
(steps solved by SuperLU after a failed static-pivot solve; pivot orders taken from a failing
step). Each figure is the best of ``--repeat`` runs (CPU time of this process).
"""

from __future__ import annotations

import argparse
import time

GOAL = 1.3


def _cpu(f, repeat):
    best = float("inf")
    for _ in range(repeat):
        t0 = time.process_time()
        f()
        best = min(best, time.process_time() - t0)
    return best


def _options(steps, dt):
    from wingmdao.cases import pegasus

    return pegasus.PegasusOptions(loads="gust", aero="coupled", plunge="free", t_final=steps * dt, dt=dt)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=500, help="time steps (default 500)")
    ap.add_argument("--dt", type=float, default=0.01, help="time step (s)")
    ap.add_argument("--repeat", type=int, default=2, help="runs per figure (best taken)")
    args = ap.parse_args(argv)
    from wingmdao import sizing
    from wingmdao.cases import pegasus, pegasus_stick
    from wingmdao.section.box import WALL_NAMES

    opts = _options(args.steps, args.dt)
    setup = pegasus.build(opts)
    t0 = time.perf_counter()
    stick = pegasus_stick.sizing_setup(setup, opts)
    build_s = time.perf_counter() - t0
    case = stick.load_cases[0]
    nodes_stick = sum(b.num_nodes for b in case.system.beams)
    rows = []
    for label, st, build, nodes in (
            ("lone wing", setup, lambda s: sizing.build_problem(s.geometry, s.load_cases, s.material, s.options,
                                                                driver=False, parallel=False)[0],
             setup.geometry.num_nodes),
            ("stick model", stick, lambda s: sizing.build_stick_problem(s.geometry, s.load_cases, s.material,
                                                                        s.options, driver=False)[0], nodes_stick)):
        prob = build(st)
        ks = f"cases.{st.load_cases[0].name}.ks_vm"
        comp = next(c for c in prob.model.system_iter(recurse=True) if hasattr(c, "_n_state"))
        march = _cpu(prob.run_model, args.repeat)
        grad = _cpu(lambda: prob.compute_totals([ks], list(WALL_NAMES)), args.repeat)
        compiled = bool(comp.last_history.info.get("compiled_steps"))
        stats = comp._lin.static_stats if comp._lin is not None else {}
        lu = f"{comp._lin.lu_method}, fallback {stats.get('fallback', 0)}, repivoted {stats.get('repivoted', 0)}"
        rows.append((label, nodes, comp._n_state, march, grad, compiled, lu))
        prob.cleanup()
    print(f"PEGASUS gust, {args.steps} steps of {args.dt} s; stick model built (CasADi) in {build_s:.1f} s")
    print(f"{'model':12s} {'nodes':>5s} {'states':>6s} {'march s':>8s} {'grad s':>8s} {'(m+g)/node ms':>14s} "
          f"{'compiled':>8s}  adjoint LU")
    for label, nodes, n_state, march, grad, compiled, lu in rows:
        print(f"{label:12s} {nodes:5d} {n_state:6d} {march:8.2f} {grad:8.2f} {1e3 * (march + grad) / nodes:14.1f} "
              f"{'yes' if compiled else 'no':>8s}  {lu}")
    per = [(r[3] + r[4]) / r[1] for r in rows]
    print(f"cost per node, stick / lone wing: {per[1] / per[0]:.2f} (goal <= {GOAL})")


if __name__ == "__main__":
    main()
