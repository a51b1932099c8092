"""Stiffened PEGASUS sizing beside the strength-only one, and the rib-pitch study.

    python benchmarks/bench_panels.py [--loads maneuver|all] [--optimizer SLSQP|IPOPT]
    python benchmarks/bench_panels.py --rib-pitch 0.4 0.5 0.63 0.8 1.0 1.25
    python benchmarks/bench_panels.py --gradient [--loads maneuver|all] [--repeat 10]

The first form sizes PEGASUS with ``--panels unstiffened`` (walls sized for strength: von Mises)
and ``--panels stiffened`` (blade-stiffened skins, skin/panel/stiffener/web buckling at a
safety factor of 1.5, ribs) for the same load cases and prints mass, iterations, evaluations,
wall and CPU time, and the ratio of the stiffened to the strength-only CPU time (goal of the
stiffened-panel issue: at most 1.5 for the maneuver + gust sizing). The second sizes the
stiffened maneuver case at each rib pitch (m; the case's own ribs are 0.624 m apart) and prints
the mass by part: lighter ribs and longer panels against more ribs and shorter panels. The third
times one gradient of every nonlinear constraint and the mass (what each optimizer iteration
costs beside its analyses) at the starting design of both sizings: the median CPU time of
``--repeat`` gradients, after as many to warm the compiled kernels.
``cpu`` is this process's CPU time, the steadier figure when other jobs share the cores.
"""

from __future__ import annotations

import argparse
import statistics
import time

from wingmdao.cases import pegasus
from wingmdao.sizing import build_problem, size_case


def _size(optimizer="SLSQP", **options):
    setup = pegasus.build(**options)
    setup.options.disp = False
    setup.options.optimizer = optimizer
    w0, c0 = time.perf_counter(), time.process_time()
    _, res = size_case(setup, comm=False)
    return res, time.perf_counter() - w0, time.process_time() - c0


def compare(loads: str, optimizer: str) -> None:
    print(f"{'panels':12s} {'mass [kg]':>10s} {'success':>8s} {'iter':>5s} {'f-evals':>8s} {'g-evals':>8s} "
          f"{'wall [s]':>9s} {'cpu [s]':>8s}")
    cpu = {}
    for panels in ("unstiffened", "stiffened"):
        res, wall, cpu[panels] = _size(optimizer, loads=loads, panels=panels)
        print(f"{panels:12s} {res['mass_kg']:10.2f} {str(res['success']):>8s} {res['iterations']:5d} "
              f"{res['function_evaluations']:8d} {res['gradient_evaluations']:8d} {wall:9.1f} {cpu[panels]:8.1f}",
              flush=True)
    print(f"stiffened / strength-only CPU time: {cpu['stiffened'] / cpu['unstiffened']:.2f} (goal <= 1.5, "
          f"loads {loads}, optimizer {optimizer})")


def gradient_cost(loads: str, repeat: int) -> None:
    print(f"{'panels':12s} {'design vars':>11s} {'constraints':>11s} {'gradient cpu [s]':>16s}")
    cost = {}
    for panels in ("unstiffened", "stiffened"):
        setup = pegasus.build(loads=loads, panels=panels)
        setup.options.disp = False
        prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options,
                                section=setup.section, panels=setup.panels)
        prob.run_model()
        nonlinear = [k for k, m in prob.model.get_constraints().items() if not m["linear"]]
        times = []
        for k in range(2 * repeat):   # the first half warms the compiled kernels
            c0 = time.process_time()
            prob.compute_totals(of=nonlinear + ["mass"])
            if k >= repeat:
                times.append(time.process_time() - c0)
        cost[panels] = statistics.median(times)
        n_dv = sum(m["size"] for m in prob.model.get_design_vars().values())
        print(f"{panels:12s} {n_dv:11d} {len(nonlinear):11d} {cost[panels]:16.3f}", flush=True)
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
        compare(args.loads, args.optimizer)


if __name__ == "__main__":
    main()
