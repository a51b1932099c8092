"""Stiffened PEGASUS sizing beside the strength-only one, and the rib-pitch study.

    python benchmarks/bench_panels.py [--loads maneuver|all] [--optimizer SLSQP|IPOPT]
                                      [--dv-ref upper|2upper|start] [--objective-factor F]
    python benchmarks/bench_panels.py --rib-pitch 0.4 0.5 0.63 0.8 1.0 1.25
    python benchmarks/bench_panels.py --gradient [--loads maneuver|all] [--repeat 10]
    python benchmarks/bench_panels.py --loads all --panel-sizing two-level [--outer fsd|slsqp] [--polish 8]

The first form sizes PEGASUS with ``--panels unstiffened`` (walls sized for strength: von Mises)
and ``--panels stiffened`` (blade-stiffened skins, skin/panel/stiffener/web buckling at a
safety factor of 1.5, ribs) for the same load cases and prints mass, iterations, evaluations,
wall and CPU time, and the ratio of the stiffened to the strength-only CPU time (goal of the
stiffened-panel issue: at most 1.5 for the maneuver + gust sizing); ``--dv-ref`` and
``--objective-factor`` rescale the stiffened sizing's variables and objective. The second sizes the
stiffened maneuver case at each rib pitch (m; the case's own ribs are 0.624 m apart) and prints
the mass by part: lighter ribs and longer panels against more ribs and shorter panels. The third
times one gradient of every nonlinear constraint and the mass (what each optimizer iteration
costs beside its analyses) at the starting design of both sizings: the median CPU time of
``--repeat`` gradients, after as many to warm the compiled kernels, the part of it spent in the
time march's reverse solves and products (``time march``: the adjoint sweeps through the gust
history and the static solves, ``sweeps`` of them per gradient, one per nonlinear constraint
and load case), and the median CPU time of one analysis (``run_model``).
``--panel-sizing two-level`` sizes the stiffened case in two levels
(:func:`wingmdao.panel_sizing.size_two_level`) beside the strength-only one (``full``, the
default, sizes all stiffened variables in one SLSQP) and prints the smallest margin of safety of
the recovered design in the full model.
``cpu`` is this process's CPU time, the steadier figure when other jobs share the cores.
"""

from __future__ import annotations

import argparse
import statistics
import time

from wingmdao.cases import pegasus
from wingmdao.components.time_history import TimeHistoryComponent
from wingmdao.panel_sizing import OUTER_SOLVERS, PANEL_SIZINGS, size_two_level
from wingmdao.sizing import OBJECTIVE_SCALE, build_problem, initial_mass, size_case


#: design-variable scaling of the stiffened sizing (``--dv-ref``): each variable's ref
DV_REFS = {"upper": lambda o, w: o.upper[w], "2upper": lambda o, w: 2.0 * o.upper[w],
           "start": lambda o, w: o.initial[w]}


def _size(optimizer="SLSQP", dv_ref="upper", objective_factor=1.0, **options):
    setup = pegasus.build(**options)
    setup.options.disp = False
    setup.options.optimizer = optimizer
    o = setup.options
    if dv_ref != "upper":
        o.dv_ref = {w: DV_REFS[dv_ref](o, w) for w in o.upper}
    if objective_factor != 1.0:
        o.mass_scale = objective_factor * OBJECTIVE_SCALE * initial_mass(setup.geometry, setup.material, o,
                                                                         setup.section, setup.panels)
    w0, c0 = time.perf_counter(), time.process_time()
    _, res = size_case(setup, comm=False)
    return res, time.perf_counter() - w0, time.process_time() - c0


def _size_two_level(outer, polish, **options):
    setup = pegasus.build(**options)
    setup.options.disp = False
    w0, c0 = time.perf_counter(), time.process_time()
    _, res = size_two_level(setup, outer_solver=outer, polish=polish)
    return res, time.perf_counter() - w0, time.process_time() - c0


def compare(loads: str, optimizer: str, dv_ref: str = "upper", objective_factor: float = 1.0,
            panel_sizing: str = "full", outer: str = "fsd", polish: int = 8) -> None:
    print(f"{'panels':12s} {'mass [kg]':>10s} {'success':>8s} {'iter':>5s} {'f-evals':>8s} {'g-evals':>8s} "
          f"{'wall [s]':>9s} {'cpu [s]':>8s}")
    cpu = {}
    for panels in ("unstiffened", "stiffened"):
        scaling = dict(dv_ref=dv_ref, objective_factor=objective_factor) if panels == "stiffened" else {}
        if panels == "stiffened" and panel_sizing == "two-level":
            res, wall, cpu[panels] = _size_two_level(outer, polish, loads=loads, panels=panels)
            tl = res["two_level"]
            print(f"two-level: outer {outer} {tl['outer']['mass_kg']:.2f} kg; passes "
                  + "; ".join(f"{p['mass_kg']:.2f} kg, smallest margin {p['margin_of_safety']:+.4f} "
                              f"({p['wall']} station {p['station']}, {p['mode']})" for p in tl["passes"])
                  + "; cpu " + ", ".join(f"{k} {v:.1f} s" for k, v in tl["cpu_s"].items()), flush=True)
        else:
            res, wall, cpu[panels] = _size(optimizer, loads=loads, panels=panels, **scaling)
        print(f"{panels:12s} {res['mass_kg']:10.2f} {str(res['success']):>8s} {res['iterations']:5d} "
              f"{res['function_evaluations']:8d} {res['gradient_evaluations']:8d} {wall:9.1f} {cpu[panels]:8.1f}",
              flush=True)
    print(f"stiffened ({panel_sizing}) / strength-only CPU time: {cpu['stiffened'] / cpu['unstiffened']:.2f} "
          f"(goal <= 1.5, loads {loads}, optimizer {optimizer})")


class _MarchTimer:
    """CPU time and count of the reverse solves (adjoint sweeps) and reverse products of every
    :class:`TimeHistoryComponent` of a problem: wraps each instance's ``solve_linear`` and
    ``apply_linear`` (the benchmark's problem only)."""

    def __init__(self, prob):
        self.cpu, self.sweeps = 0.0, 0
        for comp in prob.model.system_iter(recurse=True, typ=TimeHistoryComponent):
            for name in ("solve_linear", "apply_linear"):
                setattr(comp, name, self._timed(getattr(comp, name), name == "solve_linear"))

    def _timed(self, method, sweep):
        def timed(*args, **kwargs):
            c0 = time.process_time()
            try:
                return method(*args, **kwargs)
            finally:
                self.cpu += time.process_time() - c0
                self.sweeps += sweep
        return timed


def gradient_cost(loads: str, repeat: int) -> None:
    print(f"{'panels':12s} {'design vars':>11s} {'constraints':>11s} {'gradient cpu [s]':>16s} "
          f"{'time march [s]':>14s} {'sweeps':>6s} {'analysis cpu [s]':>16s}")
    cost = {}
    for panels in ("unstiffened", "stiffened"):
        setup = pegasus.build(loads=loads, panels=panels)
        setup.options.disp = False
        prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options,
                                section=setup.section, panels=setup.panels)
        prob.run_model()
        nonlinear = [k for k, m in prob.model.get_constraints().items() if not m["linear"]]
        march = _MarchTimer(prob)
        times, marches, analyses = [], [], []
        for k in range(2 * repeat):   # the first half warms the compiled kernels
            c0, m0, s0 = time.process_time(), march.cpu, march.sweeps
            prob.compute_totals(of=nonlinear + ["mass"])
            if k >= repeat:
                times.append(time.process_time() - c0)
                marches.append(march.cpu - m0)
            sweeps = march.sweeps - s0
            c0 = time.process_time()
            prob.run_model()
            if k >= repeat:
                analyses.append(time.process_time() - c0)
        cost[panels] = statistics.median(times)
        n_dv = sum(m["size"] for m in prob.model.get_design_vars().values())
        print(f"{panels:12s} {n_dv:11d} {len(nonlinear):11d} {cost[panels]:16.3f} {statistics.median(marches):14.3f} "
              f"{sweeps:6d} {statistics.median(analyses):16.3f}", flush=True)
    print(f"stiffened / strength-only gradient CPU: {cost['stiffened'] / cost['unstiffened']:.2f}")


def rib_study(pitches) -> None:
    print(f"{'rib pitch [m]':>13s} {'ribs':>5s} {'mass [kg]':>10s} {'skins':>8s} {'spars':>8s} {'stiffeners':>10s} "
          f"{'ribs [kg]':>9s} {'success':>8s}")
    for p in pitches:
        res, _, _ = _size(loads="maneuver", panels="stiffened", rib_pitch=float(p))
        b = res["mass_breakdown_kg"]
        print(f"{p:13.3f} {len(res['ribs']['positions_m']):5d} {res['mass_kg']:10.2f} {b['skins']:8.2f} "
              f"{b['spars']:8.2f} {b['stiffeners']:10.2f} {b['ribs']:9.2f} {str(res['success']):>8s}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--loads", choices=("maneuver", "all"), default="all",
                    help="load cases of the comparison (all: the two maneuvers and the 25.341(a) gust)")
    ap.add_argument("--optimizer", default="SLSQP", help="optimizer of both sizings")
    ap.add_argument("--dv-ref", choices=tuple(DV_REFS), default="upper",
                    help="scaling (ref) of the stiffened sizing's variables: their upper bounds (the default), "
                         "twice those, or their starting values")
    ap.add_argument("--objective-factor", type=float, default=1.0,
                    help="the stiffened sizing's objective ref times this (default 1: 10 x the initial mass)")
    ap.add_argument("--panel-sizing", choices=PANEL_SIZINGS, default="full",
                    help="the stiffened sizing: all variables in one SLSQP, or two levels (wingmdao.panel_sizing)")
    ap.add_argument("--outer", choices=OUTER_SOLVERS, default="fsd",
                    help="outer level of --panel-sizing two-level: fully stressed passes, or SLSQP after them")
    ap.add_argument("--polish", type=int, default=8,
                    help="at most this many inner passes of --panel-sizing two-level with the full model's running "
                         "loads (they stop once every margin of safety is non-negative)")
    ap.add_argument("--rib-pitch", type=float, nargs="+", metavar="M", default=None,
                    help="run the rib-pitch study at these pitches instead of the comparison")
    ap.add_argument("--gradient", action="store_true",
                    help="time one gradient of both sizings at their starting design instead")
    ap.add_argument("--repeat", type=int, default=10, help="gradients timed with --gradient (median)")
    args = ap.parse_args()
    if args.gradient:
        gradient_cost(args.loads, args.repeat)
    elif args.rib_pitch:
        rib_study(args.rib_pitch)
    else:
        if not (args.objective_factor > 0 and args.objective_factor < float("inf")):
            ap.error(f"--objective-factor = {args.objective_factor}; allowed range (0, inf)")
        if not 0 <= args.polish <= 10:
            ap.error(f"--polish = {args.polish}; allowed range [0, 10]")
        compare(args.loads, args.optimizer, args.dv_ref, args.objective_factor, args.panel_sizing, args.outer,
                args.polish)


if __name__ == "__main__":
    main()
