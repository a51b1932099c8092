"""Beam vs CalculiX shell on the App. D.1 box: the tables of docs/verification-calculix.md.

Run: ``PYTHONPATH=. python benchmarks/calculix_comparison.py`` (about 1-2 min; needs ccx)."""

import sys

import numpy as np

from wingmdao.cli.verify import verify_args, verify_wing_box

LOADS = {"Fz = 1e5 N": ((0, 0, 1e5), (0, 0, 0)), "Fx = 1e5 N": ((1e5, 0, 0), (0, 0, 0)),
         "My = 1e5 N m": ((0, 0, 0), (0, 1e5, 0))}
GEOMS = ("prismatic", "taper", "sweep", "dihedral", "combined")


def row(res, torque):
    if torque:
        b = np.array(res["station_rotation_beam"])[1:, 1]
        f = np.array(res["station_rotation_fe"])[1:, 1]
    else:
        b = np.array(res["displacement_beam"])[1:]
        f = np.array(res["displacement_fe"])[1:]
    return b, f, 100 * (b - f) / f


def main():
    out = sys.stdout
    out.write("| geometry | load | quantity | CS2 beam | CS2 shell | CS3 beam | CS3 shell | CS4 beam | CS4 shell "
              "| diff CS2 (%) | diff CS3 (%) | diff CS4 (%) |\n|" + "---|" * 12 + "\n")
    for g in GEOMS:
        for name, (F, M) in LOADS.items():
            res = verify_wing_box(verify_args(g, F, M))
            tq = name.startswith("My")
            b, f, d = row(res, tq)
            vals = " | ".join(f"{x:.5e} | {y:.5e}" for x, y in zip(b, f))
            out.write(f"| {g} | {name} | {'theta_y (rad)' if tq else '|u| (m)'} | {vals} | "
                      + " | ".join(f"{x:+.2f}" for x in d) + " |\n")
            out.flush()
    out.write("\nMesh convergence (prismatic):\n\n| load | chord x height elements, span size (m) | elements "
              "| CS4 shell | change vs finest (%) |\n|---|---|---|---|---|\n")
    meshes = [(4, 1, 1.0), (8, 2, 0.5), (16, 4, 0.25), (24, 6, 0.125)]
    for name in ("Fz = 1e5 N", "My = 1e5 N m"):
        F, M = LOADS[name]
        tq = name.startswith("My")
        vals = []
        for nc, nh, s in meshes:
            res = verify_wing_box(verify_args("prismatic", F, M, chord_elements=nc, height_elements=nh, span_size=s))
            v = np.array(res["station_rotation_fe"])[-1, 1] if tq else res["displacement_fe"][-1]
            vals.append((nc, nh, s, res["mesh"]["num_elements"], v))
        for nc, nh, s, ne, v in vals:
            out.write(f"| {name} | {nc} x {nh}, {s} | {ne} | {v:.6e} | {100 * (v / vals[-1][-1] - 1):+.3f} |\n")
        out.flush()
    out.write("\nRibs (prismatic; 0.1 m ribs; first 4 frequencies, Hz, and CS4 response):\n\n| ribs | f1..f4 shell "
              "| f1..f4 beam | CS4 |u| Fz (m) | CS4 theta_y My (rad) |\n|---|---|---|---|---|\n")
    for ribs in (None, 2.5, 1.0):
        r1 = verify_wing_box(verify_args("prismatic", (0, 0, 1e5), ribs=ribs, modes=4))
        r2 = verify_wing_box(verify_args("prismatic", (0, 0, 0), (0, 1e5, 0), ribs=ribs))
        out.write(f"| {'tip rib only' if ribs is None else f'every {ribs} m'} | "
                  f"{', '.join(f'{x:.3f}' for x in r1['frequencies_fe_hz'])} | "
                  f"{', '.join(f'{x:.3f}' for x in r1['frequencies_beam_hz'])} | {r1['displacement_fe'][-1]:.5e} | "
                  f"{r2['station_rotation_fe'][-1][1]:.5e} |\n")
        out.flush()


if __name__ == "__main__":
    main()
