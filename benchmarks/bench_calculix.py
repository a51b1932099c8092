"""CalculiX shell and solid models of the App. D.1 box and the PEGASUS shell with ribs: build +
solve + read time beside the beam's solve time, as ratios (docs/verification-calculix.md, 'Speed').

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
from wingmdao.fe.solid_box import build_solid_box
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
        print(f"| shell {nc} x {nh}, {s} | {out['num_elements']} | {t:.2f} | {out['time']:.2f} | {t / t_beam:.0f} |")

    def run_solid():
        m = build_solid_box(sec, ALUMINIUM, ribs_y=[10.0])      # default 8 x 2 x 2, 0.5 m
        return solve_static(m, [(10.0, sec.centres[-1], F, (0, 0, 0))], sec.centres[:, 1])
    t, out = best(run_solid, args.repeat)
    print(f"| solid 8 x 2 x 2, 0.5 | {out['num_elements']} | {t:.2f} | {out['time']:.2f} | {t / t_beam:.0f} |")
    pegasus(args.repeat)


def pegasus(repeat):
    """PEGASUS at 1 g: the beam solve vs the shell with ribs (``verify pegasus`` without stresses)."""
    from wingmdao.beam.static import BeamModel
    from wingmdao.cases import pegasus as case
    from wingmdao.cases.planform import G0
    from wingmdao.cli._verify_pegasus import fe_loads, pegasus_setup

    geo, sec, line, params, structural, _ = pegasus_setup(None, 1.0)
    forcing = dict(force_per_length=line.force_per_length, moment_per_length=line.moment_per_length,
                   gravity=np.array([0.0, 0.0, -G0]))
    BeamModel(params).solve(**forcing)
    t_beam, _ = best(lambda: BeamModel(params).solve(**forcing), repeat)
    y = geo.span_coordinate

    def run():
        m = build_shell_box(sec, ALUMINIUM, ribs_y=list(y[1:]), rib_thickness=0.002)
        return solve_static(m, fe_loads(case, geo, sec, m, line, structural, 1.0, G0), y)
    t, out = best(run, repeat)
    print(f"\nPEGASUS beam solve (1 g): {t_beam:.3f} s")
    print(f"| PEGASUS shell 8 x 2, 0.5, ribs 1-19 | {out['num_elements']} | {t:.2f} | {out['time']:.2f} | "
          f"{t / t_beam:.0f} |")


if __name__ == "__main__":
    main()
