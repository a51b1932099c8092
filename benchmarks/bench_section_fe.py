"""Timing of the cross-section FE on a PEGASUS-like wingbox (NACA 23015, c = 2 m, spars 18 %/75 %).

Goals: one section of ~2000 elements <= 0.5 s; 20 stations <= 5 s (dissertation: 8.9 s VABS + 3.4 s meshing).
Run: python benchmarks/bench_section_fe.py
"""

import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")   # BLAS threads only contend on small dense products
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np

from wingmdao.section.fe import airfoil_box_mesh, analyse_section, beam_properties_csn, isotropic, match_box
from wingmdao.section.fe.airfoil import naca_surfaces

AL = isotropic(71e9, 0.33, 2810.0)
UP, LO = naca_surfaces("23015")


def station(th, mesh_size):
    walls = {k: {"thickness": t, "material": AL} for k, t in zip(("upper", "lower", "front", "rear"), th)}
    t0 = time.perf_counter()
    mesh = airfoil_box_mesh(UP, LO, 2.0, 0.18, 0.75, walls, mesh_size=mesh_size)
    t1 = time.perf_counter()
    sec = analyse_section(mesh)
    K = beam_properties_csn(sec)["stiffness_csn"]
    match_box(K[0, 0], K[1, 1], th, AL.E_ref, AL.G_ref, 1.1, 0.2, bounds=((0.1, 2.0), (0.02, 1.0)))
    t2 = time.perf_counter()
    return mesh.elements.shape[0], t1 - t0, t2 - t1, sec.stiffness


def main():
    th = (0.004, 0.004, 0.006, 0.005)
    print("mesh convergence (6x6 K44 torsion and K55 bending about the leading edge) and time per section:")
    print(f"{'mesh_size m':>12} {'elements':>9} {'mesh s':>8} {'solve s':>8} {'K44 at LE':>14} {'K55 at LE':>14}")
    for ms in (0.05, 0.03, 0.0105, 0.006):
        ne, tm, ts, K = station(th, ms)
        print(f"{ms:12.4f} {ne:9d} {tm:8.3f} {ts:8.3f} {K[3, 3]:14.6e} {K[4, 4]:14.6e}")
    best = min(sum(station(th, 0.0075)[1:3]) for _ in range(3))
    ne = station(th, 0.0075)[0]
    print(f"one section, {ne} elements: {best:.3f} s best of 3 (goal <= 0.5 s); load average {os.getloadavg()[0]:.1f}")
    t0 = time.perf_counter()
    for k in range(20):
        f = 1.0 - 0.03 * k
        station(tuple(np.array(th) * f), 0.03)
    print(f"20 stations (mesh_size 0.03 m, ~530 elements): {time.perf_counter() - t0:.2f} s (goal <= 5 s)")
    t0 = time.perf_counter()
    for k in range(20):
        station(tuple(np.array(th) * (1.0 - 0.03 * k)), 0.0075)
    print(f"20 stations (mesh_size 0.0075 m, ~1800 elements): {time.perf_counter() - t0:.2f} s")


if __name__ == "__main__":
    main()
