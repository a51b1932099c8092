"""``wingmdao loads CASE --matrix FILE.yaml``: the loads office's matrix of flight points and mass cases.

Analysis only (docs/loads-matrix.md): every altitude x speed (V_C, V_D) x mass case (weight, CG,
fuel) of the matrix file runs its discrete gusts (every gradient, up and down), continuous
turbulence and maneuvers (:mod:`wingmdao.loads.matrix`), split over the ranks under
``mpirun -n P``; the internal loads of every station are screened for the critical case of each
load and written to a loads database (HDF5, :mod:`wingmdao.loads.database`) with the stress
office's cards of the critical cases (:mod:`wingmdao.loads.cards`). Ctrl-C keeps the cases done:
the database is written with status ``interrupted`` and the command exits with 130.

Files in ``--out``: ``CASE_loads.h5`` (the database), ``CASE_critical.bdf`` (Nastran FORCE/MOMENT)
and ``CASE_critical.inp`` (CalculiX ``*CLOAD``).

JSON keys: case, matrix, status (complete | interrupted), database, cards (nastran, calculix,
load_sets), case_count, evaluated_count, ranks, critical_cases (per monitoring station and load:
vertical_shear, bending_moment, torsion; the max and min with their case), wall_time_s.
"""

from __future__ import annotations

import importlib.util
import os
import sys
import time as _time

import wingmdao.cli._openmdao  # noqa: F401  (first: OpenMDAO without the matplotlib of its report plugins)
from wingmdao.cli._io import EXIT_INTERRUPTED, check_output_dir, check_output_file, read_design, refuse_existing, write_json
from wingmdao.cases import available_cases
from wingmdao.loads.cards import write_cards
from wingmdao.loads.database import run_matrix, write_database
from wingmdao.loads.matrix import critical_table, expand, read_matrix, screen
from wingmdao.parallel import is_root, world_comm


def output_paths(out: str, case: str) -> dict:
    """The command's files in folder ``out``."""
    return {"database": os.path.join(out, f"{case}_loads.h5"),
            "nastran": os.path.join(out, f"{case}_critical.bdf"),
            "calculix": os.path.join(out, f"{case}_critical.inp")}


def run(args):
    t0 = _time.perf_counter()
    missing = [m for m in ("h5py", "yaml") if importlib.util.find_spec(m) is None]
    if missing:
        raise ValueError(f"wingmdao loads needs {' and '.join(missing)} (the database, the matrix file): "
                         "pip install 'wingmdao[loads]'")
    module = available_cases()[args.case]
    matrix = read_matrix(args.matrix)
    thickness = None
    if args.design:
        thickness = read_design(args.design, matrix.num_nodes, case=args.case, command="loads")
    check_output_dir(args.out, "--out")
    paths = output_paths(args.out, args.case)
    refuse_existing(list(paths.values()), overwrite=args.overwrite, what="output")
    check_output_file(args.json, "--json", overwrite=args.overwrite, others=paths)
    comm = world_comm()
    cases = expand(matrix)
    ranks = 1 if comm is None else comm.size
    print(f"wingmdao loads {args.case}: {len(cases)} load cases ({len(matrix.altitudes_ft)} altitudes x "
          f"{len(matrix.speeds)} speeds x {len(matrix.mass_cases)} mass cases), {matrix.num_nodes} nodes, "
          f"{matrix.model['aero']} aero, {ranks} rank(s)", file=sys.stderr)
    db = run_matrix(module, matrix, case=args.case, comm=comm, thickness=thickness)
    done = int(db.cases["evaluated"].sum())
    sets = []
    if is_root():
        write_database(db, paths["database"])
        sets = write_cards(db, paths["nastran"], paths["calculix"])
    sc = screen(db.loads_max, db.loads_min, db.cases["evaluated"])
    res = {"case": args.case, "matrix": os.path.abspath(args.matrix), "status": db.status,
           "database": os.path.abspath(paths["database"]),
           "cards": {"nastran": os.path.abspath(paths["nastran"]), "calculix": os.path.abspath(paths["calculix"]),
                     "load_sets": len(sets)},
           "case_count": len(cases), "evaluated_count": done, "ranks": ranks,
           "critical_cases": critical_table(cases, sc, matrix.monitoring_stations(), db.node_positions[:, 1]),
           "wall_time_s": _time.perf_counter() - t0}
    print(f"{done} of {len(cases)} cases in {res['wall_time_s']:.1f} s ({db.status}); wrote {paths['database']}, "
          f"{len(sets)} critical load sets in {paths['nastran']} and {paths['calculix']}", file=sys.stderr)
    write_json(res, args.json)
    return EXIT_INTERRUPTED if db.status == "interrupted" else 0
