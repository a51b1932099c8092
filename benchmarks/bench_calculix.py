"""CalculiX shell model of the App. D.1 box: build + solve + read time beside the beam's solve
time, as ratios (docs/verification-calculix.md, 'Speed').

    PYTHONPATH=. python benchmarks/bench_calculix.py [--repeat 3]

Beam: ``wingmdao.cases.wing_box.solve_wing_box`` (static, 6/8/6 elements; the first call's
setup is excluded by a warm-up). Shell: ``build_shell_box`` + ``solve_static`` (deck writing,
ccx, .dat reading), per mesh; ccx's own wall time is reported separately.
"""

import argparse
import time

import numpy as np

from wingmdao.cases.wing_box import solve_wing_box
from wingmdao.cli.verify import wing_box_sections
from wingmdao.fe.box_model import build_shell_box, solve_static
from wingmdao.materials import ALUMINIUM

MESHES = ((8, 2, 0.5), (16, 4, 0.25))


def best(fn, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--geometry", default="combined")
    args = ap.parse_args()
    F = (0.0, 0.0, 1e5)
    solve_wing_box(args.geometry, tip_force=F)              # warm-up (CasADi build / JIT load)
    t_beam, _ = best(lambda: solve_wing_box(args.geometry, tip_force=F), args.repeat)
    print(f"beam solve ({args.geometry}, static): {t_beam:.3f} s")
    print("| mesh (chord x height, span m) | elements | build + solve + read (s) | ccx (s) | ratio to beam |")
    print("|---|---|---|---|---|")
    sec = wing_box_sections(args.geometry, 0.2, 0.1)
    for nc, nh, s in MESHES:
        def run():
            m = build_shell_box(sec, ALUMINIUM, chord_elements=nc, height_elements=nh, span_element_size=s,
                                ribs_y=[10.0])
            return solve_static(m, [(10.0, sec.centres[-1], F, (0, 0, 0))], sec.centres[:, 1])
        t, out = best(run, args.repeat)
        print(f"| {nc} x {nh}, {s} | {out['num_elements']} | {t:.2f} | {out['time']:.2f} | {t / t_beam:.0f} |")


if __name__ == "__main__":
    main()
