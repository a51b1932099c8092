"""``wingmdao run wing-box``: static nonlinear beam response of the App. D.1 'wing-like' box.

The box data live in ``cases/wing_box.py`` of the repository (Tables D.1, D.2, E.2). Body axes
(x aft, y outboard, z up), SI units, aluminium (E = 70 GPa, nu = 0.33, rho = 2700 kg/m^3), root
clamped at CS1, loads at the CS4 section centre. Later options (dynamic march, stresses, total-
derivative checks) are meant to be added as further arguments handled in :func:`run_wing_box`.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

GEOMETRIES = ("prismatic", "taper", "sweep", "dihedral", "combined")


def register(subparsers):
    p = subparsers.add_parser("run", help="run a shipped analysis case (static beam response) and write JSON",
                              description="Run an analysis case. SI units, body axes x aft, y outboard, z up.")
    cases = p.add_subparsers(dest="case", metavar="CASE", required=True)
    wb = cases.add_parser(
        "wing-box", help="App. D.1 'wing-like' box beam under tip loads / self weight",
        description="Static nonlinear Timoshenko-beam response of the App. D.1 box (root clamped at CS1, "
        "aluminium E = 70 GPa, nu = 0.33, rho = 2700 kg/m^3). Output JSON: stations (CS1..CS4), displacement "
        "(magnitude of the beam-axis displacement at each station, m), tip_displacement [dx, dy, dz] (m), "
        "tip_rotation (rotation vector, rad, body axes).")
    wb.add_argument("--geometry", choices=GEOMETRIES, required=True, help="Table D.2 geometry")
    wb.add_argument("--t-spar", type=float, default=0.2, metavar="M", help="spar thickness in the streamwise cut (m, default 0.2)")
    wb.add_argument("--t-skin", type=float, default=0.1, metavar="M", help="skin thickness in the streamwise cut (m, default 0.1)")
    wb.add_argument("--tip-load", type=float, nargs=3, default=(0.0, 0.0, 0.0), metavar=("FX", "FY", "FZ"),
                    help="tip force at the CS4 centre, body axes (N)")
    wb.add_argument("--tip-moment", type=float, nargs=3, default=(0.0, 0.0, 0.0), metavar=("MX", "MY", "MZ"),
                    help="tip moment, body axes (N*m)")
    wb.add_argument("--gravity", action="store_true", help="add self weight (g = 9.81 m/s^2 along -z)")
    wb.add_argument("--load-steps", type=int, default=1, metavar="N", help="load steps of the Newton solve (default 1)")
    wb.add_argument("--elements", type=int, nargs=3, default=(6, 8, 6), metavar=("N1", "N2", "N3"),
                    help="beam elements per segment CS1-CS2, CS2-CS3, CS3-CS4 (default 6 8 6)")
    wb.add_argument("--json", default="-", metavar="PATH", help="output file ('-' = standard output, the default)")
    wb.set_defaults(func=run_wing_box)


def load_wing_box_case():
    """Import ``cases/wing_box.py`` from the repository (ValueError if it is not there)."""
    path = Path(__file__).resolve().parents[2] / "cases" / "wing_box.py"
    if not path.is_file():
        raise ValueError(f"case file {path} not found (the wing-box case ships with the repository)")
    spec = importlib.util.spec_from_file_location("wingmdao_case_wing_box", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _check_args(args):
    for name in ("t_spar", "t_skin"):
        v = getattr(args, name)
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"--{name.replace('_', '-')} = {v} m; allowed range (0, inf) m")
    for name in ("tip_load", "tip_moment"):
        if not np.all(np.isfinite(getattr(args, name))):
            raise ValueError(f"--{name.replace('_', '-')} must be finite")
    if args.load_steps < 1:
        raise ValueError(f"--load-steps = {args.load_steps}; allowed range >= 1")
    if min(args.elements) < 1:
        raise ValueError(f"--elements = {list(args.elements)}; each must be >= 1")


def wing_box_result(args) -> dict:
    """The JSON-ready result of ``wingmdao run wing-box`` from the parsed arguments."""
    import openmdao.api as om

    _check_args(args)
    case = load_wing_box_case()
    try:
        res = case.solve_wing_box(args.geometry, tip_force=args.tip_load, tip_moment=args.tip_moment,
                                  gravity=args.gravity, t_spar=args.t_spar, t_skin=args.t_skin,
                                  elements_per_segment=tuple(args.elements), load_steps=args.load_steps)
    except om.AnalysisError as exc:
        raise ValueError(f"the static solve did not converge ({exc}); try more --load-steps") from exc
    res["inputs"] = {"t_spar": args.t_spar, "t_skin": args.t_skin, "tip_load": list(args.tip_load),
                     "tip_moment": list(args.tip_moment), "gravity": bool(args.gravity),
                     "units": "SI (m, N, N*m, rad); body axes x aft, y outboard, z up"}
    return res


def run_wing_box(args) -> int:
    from wingmdao.cli import write_json

    write_json(wing_box_result(args), args.json)
    return 0
