"""Static nonlinear solve of the 21-node prismatic wing box (``wingmdao run wing-box``), solver alone.

    python benchmarks/bench_static.py [--loads 1e5 1e7 3e7] [--repeat 20] [--interpreted]

Prints best and median process time of :func:`wingmdao.timemarch.bdf.solve_static` from the jig
(cold) and from the converged state (warm) beside the goal of issue 15 (7 ms, the time of
SHARPy's compiled static beam solver on the same model, measured 6.6-9.8 ms).
"""

from __future__ import annotations

import argparse
import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

GOAL_MS, SHARPY_MS = 7.0, (6.6, 9.8)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    ap.add_argument("--loads", type=float, nargs="+", default=[1e5, 1e7, 3e7],
                    help="vertical tip loads (N)")
    ap.add_argument("--repeat", type=int, default=20, help="solves per figure")
    ap.add_argument("--interpreted", action="store_true", help="do not compile the CasADi functions")
    args = ap.parse_args(argv)

    from wingmdao.beam.residual import forcing_specs, param_specs
    from wingmdao.beam.static import beam_forcing, cached_beam_system
    from wingmdao.cases.wing_box.verification import wing_box_beam
    from wingmdao.timemarch.bdf import solve_static
    from wingmdao.timemarch.system import pack

    params, stations = wing_box_beam("prismatic")
    n = params["node_positions"].shape[0]
    system = cached_beam_system(n)
    if not args.interpreted:
        system.compile()
    p = pack(param_specs(n), params)
    print(f"21-node prismatic wing box: {system.n_state} states, "
          f"{'compiled' if not args.interpreted else 'interpreted'}, load average {os.getloadavg()[0]:.2f}")
    print(f"{'tip load N':>12s} {'start':>6s} {'Newton it':>10s} {'best ms':>9s} {'median ms':>10s} "
          f"{'goal ms':>8s} {'SHARPy ms':>10s}")
    for load in args.loads:
        tip = np.zeros((n, 3))
        tip[-1, 2] = load
        q = pack(forcing_specs(n), beam_forcing(n, point_force=tip))
        x_conv, info = solve_static(system, p, q)
        for start, x0 in (("cold", None), ("warm", x_conv)):
            times = []
            for _ in range(args.repeat):
                t0 = time.process_time()
                _, info = solve_static(system, p, q, x0)
                times.append(1e3 * (time.process_time() - t0))
            it = info.iterations
            print(f"{load:12.3g} {start:>6s} {str(it):>10s} {min(times):9.2f} {np.median(times):10.2f} "
                  f"{GOAL_MS:8.1f} {SHARPY_MS[0]:4.1f}-{SHARPY_MS[1]:.1f}")


if __name__ == "__main__":
    main()
