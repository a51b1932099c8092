"""Mesh convergence and timing of the wing-like box solid model (docs/verification-solid3d.md).

    python benchmarks/bench_solid3d.py [--sizes 0.5 0.35 0.25 0.18] [--geometries ...]

For each geometry and load (vertical tip force 1e5 N; tip torque M_y = 1e5 N m) prints the
CS2/CS3 section-average vertical displacement (force) or twist rotation (torque) per mesh size,
their change relative to the finest mesh (%), DOFs and wall time.
"""

import argparse

import numpy as np

from wingmdao.verification.wingbox_solid import geometry_names, solve_wingbox

LOADS = {"force": dict(tip_force=(0.0, 0.0, 1e5), tip_moment=(0.0, 0.0, 0.0)),
         "torque": dict(tip_force=(0.0, 0.0, 0.0), tip_moment=(0.0, 1e5, 0.0))}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", type=float, nargs="+", default=[0.5, 0.35, 0.25, 0.18])
    ap.add_argument("--geometries", nargs="+", default=geometry_names())
    ap.add_argument("--tip-load", default="diaphragm")
    args = ap.parse_args()
    print("| geometry | load | mesh_size (m) | DOFs | time (s) | CS2 | CS3 | CS2 change (%) | CS3 change (%) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for geo in args.geometries:
        for load, kw in LOADS.items():
            rows = []
            for h in args.sizes:
                r = solve_wingbox(geo, mesh_size=h, tip_load=args.tip_load, **kw)
                q = r["displacement"][:2, 2] if load == "force" else r["rotation"][:2, 1]
                rows.append((h, r["num_dof"], r["solve_time"], q))
            ref = rows[-1][3]
            for h, ndof, t, q in rows:
                ch = 100 * (q / ref - 1)
                print(f"| {geo} | {load} | {h} | {ndof} | {t:.1f} | {q[0]:.6e} | {q[1]:.6e} | "
                      f"{ch[0]:+.3f} | {ch[1]:+.3f} |", flush=True)


if __name__ == "__main__":
    main()
