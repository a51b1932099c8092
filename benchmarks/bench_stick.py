"""Stick model against the lone wing: march and gradient of the PEGASUS gust KS (issue 29, "Speed").

    WINGMDAO_JIT=0 PYTHONPATH=. python benchmarks/bench_stick.py --steps 500          # both interpreted
    PYTHONPATH=. python benchmarks/bench_stick.py --steps 500 --compile --aero-theory strip  # both compiled

Builds the sizing models of ``wingmdao size pegasus --model stick`` (the free half aircraft: wing,
fuselage, fin, horizontal tail; :func:`wingmdao.sizing.build_stick_problem`) and of the lone wing
(``--aero coupled --plunge free [--aero-theory T]``; :func:`wingmdao.sizing.build_problem`) on the
same time grid, and times one analysis (``run_model``: the BDF2 march, stresses, KS) and one
gradient (``compute_totals`` of the KS with respect to the four walls: the discrete adjoint).
Prints the cost per beam node of each model and their ratio beside the goal (<= 1.3), and the
path each model ran: "compiled" (the C march, every evaluated CasADi function a compiled library,
the adjoint's static-pivot C LU), "interpreted" (none of these: ``WINGMDAO_JIT=0``) or "mixed".
The ratio is printed only when both ran the same path (else exit status 1; ``--allow-mixed``
prints it anyway). With the JIT on, a function is compiled only when its library is in the
compiled cache or after ``JIT_THRESHOLD`` evaluations (in the background), so a first run is
mixed: ``--compile`` loads or compiles every function of both models before timing (gcc at
``nice -n 10``, 900 s limit per function). Also prints the adjoint's static-pivot LU statistics
(steps solved by SuperLU after a failed static-pivot solve; pivot orders taken from a failing
step). Each figure is the best of ``--repeat`` runs (CPU time of this process).
"""

from __future__ import annotations

import argparse
import time

GOAL = 1.3


def _options(steps, dt, aero_theory=None):
    from wingmdao.cases import pegasus

    return pegasus.PegasusOptions(loads="gust", aero="coupled", plunge="free", t_final=steps * dt, dt=dt,
                                  aero_theory=aero_theory)


def _used_functions(system):
    """``{name: JitFunction}`` of the system's CasADi evaluators that have been evaluated (residual,
    Newton matrix, Jacobian and history functions)."""
    calls = {"residual": system._fast_R, "newton": system._fast_newton}
    calls.update({k[2:] if k.startswith("H_") else k: c for k, c in getattr(system, "_maps", {}).items()
                  if c is not system._fast_R})
    return {name: c.jit for name, c in calls.items() if c.jit.evaluations > 0}


def run_path(comp, history) -> tuple[str, str]:
    """Which path a march and gradient of ``comp`` (a ``TimeHistoryComponent``) ran.

    Parameters
    ----------
    comp : TimeHistoryComponent
        The march component after ``run_model`` and ``compute_totals``.
    history : TimeHistory
        Its last march.

    Returns
    -------
    tuple of str
        ``("compiled" | "interpreted" | "mixed", detail)``: compiled when the march ran in the C
        stepper, every evaluated CasADi function was a compiled library and the adjoint factored
        with the static-pivot C kernel; interpreted when none of these; the detail names them.
    """
    funs = _used_functions(comp.system)
    interpreted = sorted(n for n, j in funs.items() if j.state != "compiled")
    march_c = bool(history.info.get("compiled_steps"))
    lu = comp._lin.lu_method if comp._lin is not None else "none"
    parts = [march_c, lu == "static"] + [j.state == "compiled" for j in funs.values()]
    path = "compiled" if all(parts) else "interpreted" if not any(parts) else "mixed"
    detail = (f"march {'C' if march_c else 'Python'}, {len(funs) - len(interpreted)}/{len(funs)} functions "
              f"compiled" + (f" (interpreted: {', '.join(interpreted)})" if interpreted and path == "mixed" else "")
              + f", adjoint LU {lu}")
    return path, detail


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=500, help="time steps (default 500)")
    ap.add_argument("--dt", type=float, default=0.01, help="time step (s)")
    ap.add_argument("--repeat", type=int, default=2, help="runs per figure (best taken)")
    ap.add_argument("--compile", action="store_true",
                    help="compile (or load from the cache) every CasADi function of both models before timing")
    ap.add_argument("--aero-theory", choices=("vlm", "strip"), default=None,
                    help="the lone wing's quasi-steady lift (default: the command line's, vlm); the stick model "
                         "has strips")
    ap.add_argument("--allow-mixed", action="store_true",
                    help="print the ratio even when the two models ran different paths")
    args = ap.parse_args(argv)
    from wingmdao import sizing
    from wingmdao.cases import pegasus, pegasus_stick, resolve_aero_theory
    from wingmdao.section.box import WALL_NAMES
    from wingmdao.utils.casadi_cache import jit_enabled

    opts = _options(args.steps, args.dt)
    setup = pegasus.build(_options(args.steps, args.dt, args.aero_theory))
    theory = resolve_aero_theory(args.aero_theory, "coupled")
    t0 = time.perf_counter()
    stick = pegasus_stick.sizing_setup(setup if args.aero_theory is None else pegasus.build(opts), opts)
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
        if args.compile:
            t0 = time.perf_counter()
            states = comp.system.compile(wait=True)
            print(f"{label}: compiled in {time.perf_counter() - t0:.0f} s (wall): "
                  + ", ".join(f"{k} {v}" for k, v in states.items()), flush=True)
        march = grad = float("inf")
        paths = set()
        for _ in range(args.repeat):
            t0 = time.process_time()
            prob.run_model()
            march = min(march, time.process_time() - t0)
            t0 = time.process_time()
            prob.compute_totals([ks], list(WALL_NAMES))
            grad = min(grad, time.process_time() - t0)
            paths.add(run_path(comp, comp.last_history))
        path, detail = paths.pop() if len(paths) == 1 else ("mixed", "path changed between runs: " + "; ".join(
            sorted(d for _, d in paths)))
        stats = comp._lin.static_stats if comp._lin is not None else {}
        lu = f"fallback {stats.get('fallback', 0)}, repivoted {stats.get('repivoted', 0)}"
        rows.append((label, nodes, comp._n_state, march, grad, path, detail, lu))
        prob.cleanup()
    print(f"PEGASUS gust, {args.steps} steps of {args.dt} s; lone wing {theory}; WINGMDAO_JIT {'on' if jit_enabled() else 'off'}; "
          f"stick model built (CasADi) in {build_s:.1f} s; CPU time, best of {args.repeat}")
    print(f"{'model':12s} {'nodes':>5s} {'states':>6s} {'march s':>8s} {'grad s':>8s} {'(m+g)/node ms':>14s} "
          f"{'path':>11s}  detail; adjoint static LU")
    for label, nodes, n_state, march, grad, path, detail, lu in rows:
        print(f"{label:12s} {nodes:5d} {n_state:6d} {march:8.2f} {grad:8.2f} {1e3 * (march + grad) / nodes:14.1f} "
              f"{path:>11s}  {detail}; {lu}")
    per = [(r[3] + r[4]) / r[1] for r in rows]
    ratio = f"cost per node, stick / lone wing: {per[1] / per[0]:.2f} (goal <= {GOAL})"
    if rows[0][5] == rows[1][5] != "mixed":
        print(ratio + f", both {rows[0][5]}")
        return 0
    print(f"the two models did not both run compiled or both interpreted ({rows[0][5]} / {rows[1][5]}): "
          "the ratio is not like for like (run with WINGMDAO_JIT=0, or --compile)"
          + (f"; {ratio}" if args.allow_mixed else ""))
    return 1


if __name__ == "__main__":
    raise SystemExit(main())
