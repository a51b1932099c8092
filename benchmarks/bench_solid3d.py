"""Mesh convergence and timing of the wing-like box solid model (docs/verification-solid3d.md).

    python benchmarks/bench_solid3d.py [--sizes 0.35 0.25 0.15 0.1] [--span-sizes 0.5]
                                       [--geometries ...]

For each geometry and load (vertical tip force 1e5 N; tip torque M_y = 1e5 N m) prints the
CS2/CS3 section-average vertical displacement (force) or twist rotation (torque) per
cross-section mesh size and span element size, the change relative to the last (finest) run
(%), DOFs and wall time.
"""

import argparse
import itertools

from wingmdao.verification.wingbox_solid import geometry_names, solve_wingbox

LOADS = {"force": dict(tip_force=(0.0, 0.0, 1e5), tip_moment=(0.0, 0.0, 0.0)),
         "torque": dict(tip_force=(0.0, 0.0, 0.0), tip_moment=(0.0, 1e5, 0.0))}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", type=float, nargs="+", default=[0.35, 0.25, 0.15, 0.1])
    ap.add_argument("--span-sizes", type=float, nargs="+", default=[0.5])
    ap.add_argument("--geometries", nargs="+", default=geometry_names())
    ap.add_argument("--tip-load", default="diaphragm")
    args = ap.parse_args()
    print("| geometry | load | mesh_size (m) | span_size (m) | divisions (spar, skin, chord, web; span) "
          "| DOFs | time (s) | CS2 | CS3 | CS2 change (%) | CS3 change (%) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for geo in args.geometries:
        for load, kw in LOADS.items():
            rows = []
            for h, hs in itertools.product(args.sizes, args.span_sizes):
                r = solve_wingbox(geo, mesh_size=h, span_size=hs, tip_load=args.tip_load, **kw)
                q = r["displacement"][:2, 2] if load == "force" else r["rotation"][:2, 1]
                d = r["divisions"]
                div = f"{d['spar']}, {d['skin']}, {d['chord']}, {d['web']}; {d['span']}"
                rows.append((h, hs, div, r["num_dof"], r["solve_time"], q))
            ref = rows[-1][-1]
            for h, hs, div, ndof, t, q in rows:
                ch = 100 * (q / ref - 1)
                print(f"| {geo} | {load} | {h} | {hs} | {div} | {ndof} | {t:.1f} | {q[0]:.6e} | "
                      f"{q[1]:.6e} | {ch[0]:+.3f} | {ch[1]:+.3f} |", flush=True)


if __name__ == "__main__":
    main()
