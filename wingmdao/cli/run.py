"""``wingmdao run wing-box``: response of the App. D.1 'wing-like' box on the sizing model
(``--model beam``, default) or on the independent 3-D solid model (``--model solid``).

The box data and model builders live in :mod:`wingmdao.cases.wing_box` (Tables D.1, D.2, E.2).
Body axes (x aft, y outboard, z up), SI units, aluminium (E = 70 GPa, nu = 0.33,
rho = 2700 kg/m^3, sigma_y = 276 MPa), root clamped at CS1, loads at the CS4 section centre.
The analysis runs on the OpenMDAO chain users size with (``WingSizing`` with one
``LoadCase``: box section -> nonlinear beam (static or BDF2 time march) -> internal loads ->
stress -> KS), with the four wall thicknesses per node as design variables; ``--check-totals``
compares the adjoint totals of the KS outputs with central finite differences.
"""

from __future__ import annotations

import numpy as np

import wingmdao.cli._openmdao  # noqa: F401  (first: OpenMDAO without the matplotlib of its report plugins)
from wingmdao.cases import wing_box as case
from wingmdao.cases.wing_box.problem import analysis_problem, totals_max_rel_error
from wingmdao.cases.wing_box import HEIGHTS, geometry_data, station_rotations, station_summary
from wingmdao.cli import write_json
from wingmdao.groups.load_case import STRESS_FAMILIES
from wingmdao.limits import estimate_bytes
import openmdao.api as om
from wingmdao.verification.wingbox_solid import solve_wingbox


#: --load-steps and --elements (sum of the three segments) upper bounds
MAX_LOAD_STEPS = 1000
MAX_ELEMENTS = 600


def check_wing_box_args(args):
    """Check the wing-box flags (``--t-spar``, ``--t-skin``, ``--gravity``, ``--tip-load``,
    ``--tip-moment``) before any solve.

    Parameters
    ----------
    args : argparse.Namespace
        The command's arguments (:func:`add_wing_box_arguments`); thicknesses in m.

    Raises
    ------
    ValueError
        Naming the flag, the value and the allowed range.
    """
    g = geometry_data(args.geometry)
    limits = {"t_spar": 0.5 * min(g["widths"]), "t_skin": 0.5 * min(HEIGHTS)}
    for name, high in limits.items():
        v = getattr(args, name)
        if not (np.isfinite(v) and 0 < v < high):
            raise ValueError(f"--{name.replace('_', '-')} = {v} m; allowed range (0, {high:g}) m "
                             f"(two walls must fit in the {args.geometry} box)")
    if args.gravity is not None and not (np.isfinite(args.gravity) and args.gravity >= 0):
        raise ValueError(f"--gravity = {args.gravity} m/s^2; allowed range [0, inf) m/s^2")
    for name in ("tip_load", "tip_moment"):
        if not np.all(np.isfinite(getattr(args, name))):
            raise ValueError(f"--{name.replace('_', '-')} must be finite")
    if not 1 <= args.load_steps <= MAX_LOAD_STEPS:
        raise ValueError(f"--load-steps = {args.load_steps}; allowed range [1, {MAX_LOAD_STEPS}] (each step is a "
                         f"Newton solve of the whole beam: {args.load_steps} steps cost ~{args.load_steps} x one solve)")
    if min(args.elements) < 1 or sum(args.elements) > MAX_ELEMENTS:
        nodes = sum(args.elements) + 1
        steps = int(args.t_final / args.dt) + 1 if args.dynamic and args.dt > 0 else 1

        raise ValueError(f"--elements = {list(args.elements)}; each must be >= 1 and their sum <= {MAX_ELEMENTS} "
                         f"({nodes} nodes: ~{estimate_bytes(nodes, [steps]) / 1e9:.1f} GB by wingmdao.limits' "
                         "memory model)")
    if getattr(args, "model", "beam") == "solid":
        bad = [flag for flag, on in (("--dynamic", args.dynamic), ("--check-totals", args.check_totals),
                                      ("--gravity", args.gravity is not None)) if on]
        if bad:
            raise ValueError(f"--model solid is a static tip-load analysis; it does not take {', '.join(bad)}")
        for name, low, high in (("mesh_size", 0.02, 1.0), ("span_size", 0.05, 3.0)):
            v = getattr(args, name)
            if not (np.isfinite(v) and low <= v <= high):
                raise ValueError(f"--{name.replace('_', '-')} = {v} m; allowed range [{low}, {high}] m")


def wing_box_result(args) -> dict:
    """The JSON-ready result of ``wingmdao run wing-box`` from the parsed arguments."""

    check_wing_box_args(args)
    if getattr(args, "model", "beam") == "solid":
        return solid_result(args)
    geometry, key, cos_sweep, cos_dih = case.wing_geometry(args.geometry, tuple(args.elements))
    n = geometry.num_nodes
    time = case.time_grid(args.t_final, args.dt) if args.dynamic else None
    load = case.tip_load_case("run", n, args.tip_load, args.tip_moment, STRESS_FAMILIES, time=time,
                              gravity=args.gravity)
    walls = {"t_upper_skin": args.t_skin * cos_dih, "t_lower_skin": args.t_skin * cos_dih,
             "t_front_spar": args.t_spar * cos_sweep, "t_rear_spar": args.t_spar * cos_sweep}
    prob = analysis_problem(geometry, load, walls, design_vars=args.check_totals,
                                 newton_options={"static_options": {"load_steps": args.load_steps}})
    try:
        prob.run_model()
    except om.AnalysisError as exc:
        raise ValueError(f"the beam solve did not converge ({exc}); try more --load-steps or a smaller --dt") from exc
    res = _response(prob, geometry, key)
    if args.dynamic:
        res["time"] = load.time.tolist()
        res["tip_displacement_history"] = res.pop("_tip_history").tolist()
        res["peak_tip_displacement"] = float(np.max(np.linalg.norm(res["tip_displacement_history"], axis=1)))
    else:
        res.pop("_tip_history")
    if args.check_totals:
        res["check_totals_max_rel_error"] = totals_max_rel_error(prob, load)
    res["geometry"] = args.geometry
    res["model"] = "beam"
    res["inputs"] = {"t_spar": args.t_spar, "t_skin": args.t_skin, "tip_load": list(args.tip_load),
                     "tip_moment": list(args.tip_moment), "gravity": args.gravity is not None,
                     "gravity_m_s2": 0.0 if args.gravity is None else float(args.gravity),
                     "dynamic": bool(args.dynamic), "elements": list(args.elements),
                     "units": "SI (m, N, N*m, rad, Pa, s); body axes x aft, y outboard, z up"}
    prob.cleanup()
    return res


def solid_result(args) -> dict:
    """``wingmdao run wing-box --model solid``: the 3-D solid model's response in the JSON keys
    of the beam run (CS1 is the clamped root face: zero displacement)."""
    sol = solve_wingbox(args.geometry, args.tip_load, args.tip_moment, args.mesh_size,
                        span_size=args.span_size, t_spar=args.t_spar, t_skin=args.t_skin,
                        tip_load=args.tip_introduction)
    disp = np.vstack([np.zeros(3), sol["displacement"]])
    rot = np.vstack([np.zeros(3), sol["rotation"]])
    return {
        **station_summary(disp, rot),
        "max_von_mises": sol["max_von_mises"].tolist(),
        "mean_von_mises": sol["mean_von_mises"].tolist(),
        "root_reaction_force": sol["root_reaction_force"].tolist(),
        "root_reaction_moment": sol["root_reaction_moment"].tolist(),
        "geometry": args.geometry,
        "model": "solid",
        "mesh": {"num_dof": int(sol["num_dof"]), "num_elements": int(sol["num_elements"]),
                 "mesh_size": args.mesh_size, "span_size": args.span_size,
                 "tip_introduction": args.tip_introduction, "element": "hex27 (triquadratic), linear elastic"},
        "solve_time": float(sol["solve_time"]),
        "inputs": {"t_spar": args.t_spar, "t_skin": args.t_skin, "tip_load": list(args.tip_load),
                   "tip_moment": list(args.tip_moment),
                   "units": "SI (m, N, N*m, rad, Pa, s); body axes x aft, y outboard, z up"},
    }


def _response(prob, geometry, key) -> dict:
    """Station displacements/rotations (last instant), tip history, von Mises, KS and mass."""
    states = prob.get_val("cases.run.states")
    r0 = np.asarray(geometry.node_positions)
    disp = states[-1, key, 0:3] - r0[key]
    rot = station_rotations(states[-1, key, 3:6], np.asarray(geometry.node_euler_angles)[key])
    vm = prob.get_val("vm_stress.sigma_vm", units="Pa")
    fams = prob.model.wing.options["load_cases"][0].families
    return {
        **station_summary(disp, rot),
        "max_von_mises": vm[:, key].max(axis=(0, 2)).tolist(),
        "ks": {f: float(prob.get_val(f"cases.run.ks_{f}")[0]) for f in fams},
        "mass_kg": float(prob.get_val("mass", units="kg")[0]),
        "_tip_history": states[:, -1, 0:3] - r0[-1],
    }


def run_wing_box(args) -> int:
    write_json(wing_box_result(args), args.json)
    return 0
