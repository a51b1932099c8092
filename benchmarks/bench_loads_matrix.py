"""The loads matrix of issue #28: at least 200 load cases of PEGASUS, serial and under ``mpirun -n 2``.

    PYTHONPATH=. python benchmarks/bench_loads_matrix.py [--num-nodes 20] [--gradients 10] [--ranks 2] [--aero strip]

The matrix: 4 altitudes (0, 10 000, 20 000, 25 000 ft) x V_C, V_D (Mach 0.5, 0.625) x 3 mass
cases (MTOW forward and aft CG with full wing fuel, MZFW forward CG), each point with
``--gradients`` gust gradients up and down, continuous turbulence and the two 25.337 maneuvers:
4 x 2 x 3 x (2 x 10 + 1 + 2) = 552 cases. Runs ``wingmdao loads pegasus`` serially and with
``mpirun -n RANKS`` (subprocesses), checks that the two databases are the same
(:func:`wingmdao.loads.database.differences`) and prints the wall times, the speed-up and the cost
per case of each kind (``/run/case_wall_s`` of the serial database). Goal of issue #28: under
10 minutes serial and faster under ``mpirun -n 2``.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

MATRIX = """\
altitudes_ft: [0, 10000, 20000, 25000]
speeds:
  V_C: {{mach: 0.5}}
  V_D: {{mach: 0.625}}
mass_cases:
  - {{name: mtow_fwd, weight_lb: 41005, cg_mac: 0.15, fuel_fraction: 1.0}}
  - {{name: mtow_aft, weight_lb: 41005, cg_mac: 0.35, fuel_fraction: 1.0}}
  - {{name: mzfw_fwd, weight_lb: 36800, cg_mac: 0.15, fuel_fraction: 0.0}}
aircraft: {{tail_arm_m: 12.0, wing_fuel_kg: 1900}}
gusts: {{gradient_count: {gradients}, signs: [up, down]}}
turbulence: true
model: {{num_nodes: {nodes}, aero: {aero}}}
"""


def _run(argv, env):
    t0 = time.perf_counter()
    proc = subprocess.run(argv, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        sys.exit(f"{' '.join(argv)} failed:\n{proc.stderr[-3000:]}")
    return wall


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--num-nodes", type=int, default=20, metavar="N", help="beam nodes")
    ap.add_argument("--gradients", type=int, default=10, metavar="N", help="gust gradients per point")
    ap.add_argument("--ranks", type=int, default=2, metavar="N", help="MPI ranks (0: serial only)")
    ap.add_argument("--aero", choices=("strip", "coupled"), default="strip", help="the matrix's model.aero")
    args = ap.parse_args()
    from wingmdao.loads.database import differences, read_database

    tmp = tempfile.mkdtemp(prefix="bench_loads_matrix_")
    path = os.path.join(tmp, "matrix.yaml")
    with open(path, "w") as fh:
        fh.write(MATRIX.format(gradients=args.gradients, nodes=args.num_nodes, aero=args.aero))
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""), OMP_NUM_THREADS="1",
               OPENBLAS_NUM_THREADS="1")
    env.pop("OPENMDAO_USE_MPI", None)
    cmd = [sys.executable, "-m", "wingmdao", "loads", "pegasus", "--matrix", path]
    serial = _run([*cmd, "--out", os.path.join(tmp, "s"), "--json", os.path.join(tmp, "s.json")], env)
    res = json.load(open(os.path.join(tmp, "s.json")))
    db = read_database(res["database"])
    kinds = db.cases["kind"]
    wall = db.run["case_wall_s"]
    print(f"{res['case_count']} cases, {args.num_nodes} nodes, --aero {args.aero}: serial {serial:.1f} s wall "
          f"(command {res['wall_time_s']:.1f} s), {res['cards']['load_sets']} critical load sets")
    for k in ("gust", "turbulence", "maneuver"):
        sel = kinds == k.encode()
        print(f"  {k:10s} {int(sel.sum()):4d} cases, {np.mean(wall[sel]):.3f} s each, {np.sum(wall[sel]):.1f} s in all")
    if args.ranks > 1:
        mpirun = shutil.which("mpirun")
        if mpirun is None:
            sys.exit("no mpirun (pip install 'wingmdao[mpi]')")
        flags = ["--oversubscribe"] + (["--allow-run-as-root"] if os.geteuid() == 0 else [])
        par = _run([mpirun, *flags, "-n", str(args.ranks), *cmd, "--out", os.path.join(tmp, "p"), "--json",
                    os.path.join(tmp, "p.json")], env)
        other = read_database(json.load(open(os.path.join(tmp, "p.json")))["database"])
        diff = differences(db, other)
        print(f"mpirun -n {args.ranks}: {par:.1f} s wall, speed-up x{serial / par:.2f}; databases "
              f"{'identical' if not diff else 'differ in ' + ', '.join(diff)}")
        if diff:  # how much, and in which cases
            rel = np.nanmax(np.abs(db.loads_max - other.loads_max), axis=(1, 2)) / np.nanmax(np.abs(db.loads_max))
            worst = np.argsort(-np.nan_to_num(rel))[:5]
            print("  largest differences of loads/max relative to its largest value: "
                  + ", ".join(f"{db.case_names[i]} {rel[i]:.1e}" for i in worst)
                  + f"; {int(np.sum(rel > 0))} of {rel.size} cases differ")
    shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
