"""Timing of the cross-section FE on the PEGASUS wingbox stations (App. D.2).

Goals: one section of ~2000 elements <= 0.5 s; all 20 PEGASUS stations <= 5 s, meshing included
(dissertation: 8.9 s of VABS runs plus 3.4 s of meshing).
Run: python benchmarks/bench_section_fe.py [--mesh-size 0.0075]
"""

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")   # BLAS threads only contend on small dense products
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import time  # noqa: E402
from functools import partial  # noqa: E402

import numpy as np  # noqa: E402

from wingmdao.cases.pegasus import PLANFORM  # noqa: E402
from wingmdao.cases.planform import interpolate_designation  # noqa: E402
from wingmdao.section.fe import (airfoil_box_mesh, airfoil_box_mesh_gmsh, analyse_section,  # noqa: E402
                                 analyse_sections, beam_properties_csn, isotropic)
from wingmdao.section.fe.airfoil import naca_surfaces  # noqa: E402

AL = isotropic(71e9, 0.33, 2810.0)
THICKNESS = (0.004, 0.004, 0.006, 0.005)   # upper, lower skin, front, rear spar (m)


def stations(pf=PLANFORM):
    """(designation, chord) of the 20 PEGASUS stations (station 0 = the root-rib section)."""
    y = pf.station_y()
    y_sec = np.where(y < pf.root_rib * pf.semi_span, pf.root_rib * pf.semi_span, y)
    frac = (y_sec - y_sec[0]) / (y_sec[-1] - y_sec[0])
    return [(interpolate_designation(pf.airfoil_root, pf.airfoil_tip, f), float(c))
            for f, c in zip(frac, pf.chord(y_sec))]


def mesher_job(mesher, designation, chord, mesh_size, scale=1.0):
    up, lo = naca_surfaces(designation)
    walls = {k: {"thickness": t * scale, "material": AL} for k, t in zip(("upper", "lower", "front", "rear"), THICKNESS)}
    build = airfoil_box_mesh_gmsh if mesher == "gmsh" else airfoil_box_mesh
    return partial(build, up, lo, chord, PLANFORM.front_spar, PLANFORM.rear_spar, walls, mesh_size=mesh_size)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh-size", type=float, default=0.0075, help="element size along the walls (m)")
    args = ap.parse_args()
    st = stations()
    root = st[1]
    print(f"PEGASUS root station: NACA {root[0]}, chord {root[1]:.3f} m; walls {THICKNESS} m")
    print("mesh convergence at the root station (gmsh mesher), torsion K44 and bending K55 about the LE:")
    print(f"{'mesh_size m':>12} {'elements':>9} {'mesh s':>8} {'solve s':>8} {'K44':>14} {'K55':>14}")
    for ms in (0.05, 0.03, 0.015, 0.0075, 0.005):
        t0 = time.perf_counter()
        mesh = mesher_job("gmsh", *root, ms)()
        t1 = time.perf_counter()
        K = analyse_section(mesh).stiffness
        t2 = time.perf_counter()
        print(f"{ms:12.4f} {mesh.elements.shape[0]:9d} {t1 - t0:8.3f} {t2 - t1:8.3f} {K[3, 3]:14.6e} {K[4, 4]:14.6e}")
    print("\nmesher comparison at the root station (6x6 diagonal, relative difference gmsh vs structured):")
    secs = {m: analyse_section(mesher_job(m, *root, args.mesh_size)()) for m in ("gmsh", "structured")}
    d = np.abs(np.diag(secs["gmsh"].stiffness) / np.diag(secs["structured"].stiffness) - 1.0)
    print("  " + "  ".join(f"{x:.1e}" for x in d))
    for mesher in ("gmsh", "structured"):
        job = mesher_job(mesher, *root, args.mesh_size)
        best = min(_timed(lambda: beam_properties_csn(analyse_section(job()))) for _ in range(3))
        ne = job().elements.shape[0]
        print(f"one section, {mesher} mesher, {ne} elements, mesh + analysis: {best:.3f} s (goal <= 0.5 s)")
    for mesher in ("gmsh", "structured"):
        jobs = [mesher_job(mesher, d, c, args.mesh_size) for d, c in st]
        t_mesh = _timed(lambda: [j() for j in jobs])
        t_serial = _timed(lambda: [analyse_section(j()) for j in jobs])
        t_par = _timed(lambda: analyse_sections(jobs))
        ne = [j().elements.shape[0] for j in jobs]
        print(f"20 stations, {mesher} mesher ({min(ne)}-{max(ne)} elements): meshing {t_mesh:.2f} s; "
              f"mesh + analysis serial {t_serial:.2f} s, on {os.cpu_count()} processes {t_par:.2f} s "
              f"(goal <= 5 s; dissertation 8.9 s VABS + 3.4 s meshing)")


def _timed(fun):
    t0 = time.perf_counter()
    fun()
    return time.perf_counter() - t0


if __name__ == "__main__":
    main()
