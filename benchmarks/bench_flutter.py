"""Flutter benchmark: eigen-solve time per speed and the whole flutter search (Goland, HALE).

    PYTHONPATH=. python benchmarks/bench_flutter.py [goland|hale ...] [--num-nodes N]

Prints, per case: the aeroelastic system build, one eigen-analysis (static solve + linearisation +
sparse shift-invert + det sign) averaged over the sweep, the sweep, the refinement of the flutter
and divergence speeds, and the results against the published values.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from wingmdao.stability import critical_speeds, sweep
from wingmdao.stability.cases import FLUTTER_CASES, flutter_problem


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cases", nargs="*", default=list(FLUTTER_CASES))
    ap.add_argument("--num-nodes", type=int, default=21)
    ap.add_argument("--deformed", action="store_true", help="also time the HALE deformed sweep (root 2 deg)")
    args = ap.parse_args(argv)
    for name in args.cases:
        t0 = time.perf_counter()
        prob = flutter_problem(name, args.num_nodes)
        t1 = time.perf_counter()
        v = prob.speeds
        res = sweep(prob.system, prob.params_at, v, n_track=4, weights=prob.beam_weights(), **prob.eig_options)
        t2 = time.perf_counter()
        crit = critical_speeds(res)
        t3 = time.perf_counter()
        pub = prob.published
        print(f"{name} ({args.num_nodes} nodes, {prob.system.n_state} states, {v.size} speeds)")
        print(f"  build {t1 - t0:.2f} s; eigen-analysis per speed {(t2 - t1) / v.size:.3f} s; "
              f"sweep {t2 - t1:.2f} s; refinement {t3 - t2:.2f} s; whole search {t3 - t1:.2f} s")
        for key, ref in (("flutter_speed", "flutter_speed_m_s"), ("flutter_frequency", "flutter_frequency_rad_s"),
                         ("divergence_speed", "divergence_speed_m_s")):
            ours = crit[key]
            diff = "" if ours is None else f" ({100 * (ours / pub[ref] - 1):+.2f} %)"
            print(f"  {key}: {ours} vs published {pub[ref]}{diff}")
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
