"""``wingmdao verify pegasus``: the PEGASUS wing (App. D.2) at n g (1 g by default) on the beam and
on a CalculiX shell or solid model with or without ribs (Sec. 4.3.1 Test 2, Sec. 4.2.5).

Model: the 20 box sections of :func:`wingmdao.cases.planform.wing_geometry` (centres, outer
width and height per station; station 0 is the centre box at the symmetry plane, clamped), wall
thicknesses of a ``wingmdao size pegasus`` result (``--design``) or the sized-like 4/4/5/4 mm
of ``wingmdao.verification.section_models.compare_1g``; ribs (shells / solid slabs) at the
case's rib stations 1..19, every ``--ribs`` m, or none. Loads, the same on both models: the
Schrenk lift and its torsion about the beam axis (``maneuver_line_loads``, centre of pressure
at 25 % chord) and the self weight of the beam's mass per length, lumped at the FE's span lines
(:mod:`wingmdao.fe.wing_loads`), and the engine weights at their stations, all entering through
distributing couplings; the beam takes the same line loads, gravity on its mass and the
engines as its non-structural mass. Modes: the engines as point masses spread on their
station rings.
"""

from __future__ import annotations
import argparse

import numpy as np

from wingmdao.cli.parsers.verify import GUST_PEAK, MANEUVERS
from wingmdao.cli._verify_fe import (build_fe_model, check_fe_args, design_walls, fe_material,
                                     percent_difference, von_mises_table)
from wingmdao.beam.modes import natural_frequencies
from wingmdao.beam.residual import forcing_specs
from wingmdao.beam.rotations import body_to_csn
from wingmdao.cases import pegasus as case
from wingmdao.cases.pegasus_verification import (DEFAULT_WALLS, beam_params, default_walls,  # noqa: F401
                                                  engine_stations as _engine_stations, fe_loads, gust_fe_loads,
                                                  gust_peak_loads)  # (also this module's names)
from wingmdao.cases.planform import G0
from wingmdao.cases.wing_box import station_rotations
from wingmdao.cli._verify_buckling import verify_pegasus_buckling
from wingmdao.fe.box_model import add_point_masses, solve_modes, solve_static
from wingmdao.fe.calculix import find_ccx
from wingmdao.fe.wing_loads import lumping_lengths
from wingmdao.timemarch.system import pack
import openmdao.api as om
from wingmdao.beam.static import BeamModel, beam_forcing
from wingmdao.cases.pegasus_verification import pegasus_setup as setup


def pegasus_walls(path):
    if path:
        return design_walls(path, "pegasus", count=20, how="a 'wingmdao size pegasus' result")

    return default_walls(20)


def pegasus_ribs(args, y, span) -> list:
    """Rib positions (m): the rib stations 1..19 (default), every ``--ribs`` m, or none."""
    if args.no_ribs:
        return []
    if args.ribs is not None:
        return [float(v) for v in np.arange(args.ribs, span + 1e-9, args.ribs)]
    return [float(v) for v in y[1:]]


def pegasus_setup(design, load_factor):
    """:func:`wingmdao.cases.pegasus_verification.pegasus_setup` with the walls of ``--design``."""
    return setup(pegasus_walls(design), load_factor, fe_material())


def verify_pegasus(args) -> dict:
    buckling = getattr(args, "buckling", False)
    if getattr(args, "span_size", None) is None:
        args.span_size = 0.1 if buckling else 0.5
    if getattr(args, "height_elements", None) is None:
        args.height_elements = 4 if buckling else 2
    rib_given = getattr(args, "rib_thickness", None) is not None
    if not rib_given:
        args.rib_thickness = 0.002
    span = case.PLANFORM.semi_span
    check_fe_args(args, span)
    if buckling and not rib_given:
        args.rib_thickness = None       # the design's crushing-sized ribs (_verify_buckling.rib_thicknesses)
    if buckling:
        return verify_pegasus_buckling(args)
    name = getattr(args, "loads", "1g")
    if name in MANEUVERS:
        if args.load_factor != 1.0:
            raise ValueError(f"--loads {name} sets the load factor ({MANEUVERS[name]:g}); drop --load-factor")
        args.load_factor = MANEUVERS[name]
    gust = name == GUST_PEAK
    if gust and args.load_factor != 1.0:
        raise ValueError("--loads gust-peak sets its own loads (the gust's peak instant); drop --load-factor")
    geo, sec, line, params, structural, walls = pegasus_setup(args.design, args.load_factor)
    find_ccx()
    y = geo.span_coordinate
    ribs = pegasus_ribs(args, y, span)
    model = build_fe_model(args, sec, ribs)

    frame = np.array([0.0, 0.0, (args.load_factor - 1.0) * G0])
    force, moment = line.force_per_length, line.moment_per_length
    if gust:
        try:
            peak = gust_peak_loads(case, geo, params)
        except om.AnalysisError as exc:
            raise ValueError(f"the beam's gust march did not converge ({exc})") from exc
        # the beam: aerodynamic + inertial -m a* line loads (m with the engines), gravity on its mass
        force = peak["force_per_length"] - params["mass_per_length"][:, None] * peak["acceleration"]
        moment, frame = peak["moment_per_length"], np.zeros(3)
        loads = gust_fe_loads(case, geo, sec, model, peak, structural, G0)
    else:
        loads = fe_loads(case, geo, sec, model, line, structural, args.load_factor, G0)
    fe = solve_static(model, loads, y, nlgeom=args.nlgeom, stress=True)
    try:
        sol = BeamModel(params).solve(force_per_length=force, moment_per_length=moment,
                                      gravity=np.array([0.0, 0.0, -G0]), load_steps=args.load_steps,
                                      frame_acceleration=frame)
    except om.AnalysisError as exc:
        raise ValueError(f"the beam solve did not converge ({exc}); try more --load-steps") from exc
    disp_b = sol["r"] - geo.node_positions
    rot_b = station_rotations(sol["theta"], geo.node_euler_angles)
    d_b, d_f = np.linalg.norm(disp_b, axis=1), np.linalg.norm(fe["displacement"], axis=1)
    r_b, r_f = np.linalg.norm(rot_b, axis=1), np.linalg.norm(fe["rotation"], axis=1)
    T = np.array([_csn(t) for t in geo.node_euler_angles])
    res = {"case": "pegasus", "fidelity": args.fidelity, "loads": name, "load_factor": args.load_factor,
           "stations": [str(k) for k in range(y.size)], "station_y": y.tolist(),
           "ribs_y": [float(v) for v in ribs], "walls": {k: v.tolist() for k, v in walls.items()},
           "displacement_beam": d_b.tolist(), "displacement_fe": d_f.tolist(),
           "difference_percent": percent_difference(d_b, d_f, max(d_f.max(), span * r_f.max())),
           "rotation_beam": r_b.tolist(), "rotation_fe": r_f.tolist(),
           "rotation_difference_percent": percent_difference(r_b, r_f, max(r_f.max(), d_f.max() / span)),
           "station_displacement_beam": disp_b.tolist(), "station_displacement_fe": fe["displacement"].tolist(),
           "station_rotation_beam": rot_b.tolist(), "station_rotation_fe": fe["rotation"].tolist(),
           "tip_twist_deg": {"beam": float(np.degrees(rot_b[-1, 1])), "fe": float(np.degrees(fe["rotation"][-1, 1]))},
           "mesh": {"element": model.element, "num_elements": fe["num_elements"], "num_nodes": fe["num_nodes"],
                    "chord_elements": args.chord_elements, "height_elements": args.height_elements,
                    "span_size": args.span_size},
           "fe_time_s": fe["time"],
           "units": "SI (m, N, N*m, rad, Pa, Hz); body axes x aft, y outboard, z up"}
    if gust:
        dyn = peak["dynamic_displacement"]
        lumped = np.sum([F for _, _, F, _ in loads], axis=0)
        res["gust_peak"] = {
            "time_s": peak["time"], "criterion": "max |M_x| at the root (beam march)", "dt_s": peak["dt"],
            "gust_start_s": peak["gust_start"], "u_ds_eas_m_s": peak["u_ds_eas"], "gradient_ft": peak["gradient_ft"],
            "root_bending_moment_peak_n_m": float(peak["root_bending_moment"][peak["index"]]),
            "root_bending_moment_1g_n_m": float(peak["root_bending_moment"][0]),
            "fe_load_resultant_n": lumped.tolist(),
            "beam_aerodynamic_resultant_n": (lumping_lengths(y) @ peak["force_per_length"]).tolist(),
            "beam_inertial_resultant_n": (lumping_lengths(y) @ (-params["mass_per_length"][:, None]
                                                                * peak["acceleration"])).tolist(),
            "tip_displacement_dynamic": dyn[-1].tolist(),
            "tip_displacement_beam_static": disp_b[-1].tolist(),
            "static_vs_dynamic_tip_percent": float(100 * (np.linalg.norm(disp_b[-1]) - np.linalg.norm(dyn[-1]))
                                                   / np.linalg.norm(dyn[-1])),
            "applied": "per beam node: aerodynamic force/moment per length at t* (strip theory, 1 g Schrenk + "
                       "gust increment) and the inertial load -m a* (a* the BDF2 acceleration of the node at t*; "
                       "m structural + engines), gravity 1 g; FE: the same line loads lumped at its span lines "
                       "(structural mass), the engines as -m_e (a* + g) at their stations; rotary inertia and the "
                       "mass-centre offset of the inertia left out (both models)"}
    ys = y
    res["von_mises"] = von_mises_table(model, sec, fe["stresses"], loads,
                                       lambda v: T[int(np.clip(np.searchsorted(ys, v) - 1, 0, len(T) - 1))])
    if args.modes:
        add_point_masses(model, _engine_stations(case, geo))
        f_fe = solve_modes(model, args.modes)["frequencies_hz"]
        f_b = _beam_frequencies(params, args.modes)
        res["frequencies_fe_hz"], res["frequencies_beam_hz"] = f_fe.tolist(), f_b.tolist()
        k = min(len(f_b), len(f_fe))
        res["frequency_difference_percent"] = (100 * (f_b[:k] - f_fe[:k]) / f_fe[:k]).tolist()
    return res


def _csn(theta):
    return body_to_csn(theta)


def _beam_frequencies(params, count):
    m = BeamModel(params)
    n = m.num_nodes
    return natural_frequencies(m.system, m.p, pack(forcing_specs(n), beam_forcing(n)), count=count)


def verify_pegasus_args(*, ribs="stations", fidelity="shell", modes=0, chord_elements=8, height_elements=2,
                        span_size=0.5, rib_thickness=None, load_factor=1.0, design=None, loads="1g",
                        buckling=False, loads_case="maneuver_pos", buckling_modes=5, bay_elements=2, web_elements=1,
                        stiffeners=None, keep_deck=None, load_lines="ribs"):
    """The parsed-argument namespace of ``verify pegasus`` (``ribs``: 'stations', None, or a spacing)."""
    return argparse.Namespace(case="pegasus", loads=loads, load_factor=load_factor, fidelity=fidelity, through_elements=2,
                              nlgeom=False, load_steps=1, ribs=None if ribs in ("stations", None) else ribs,
                              no_ribs=ribs is None, rib_thickness=rib_thickness, design=design, modes=modes,
                              chord_elements=chord_elements, height_elements=height_elements, span_size=span_size,
                              plot=None, json="-", overwrite=False, buckling=buckling, loads_case=loads_case,
                              buckling_modes=buckling_modes, bay_elements=bay_elements, web_elements=web_elements,
                              stiffeners=stiffeners, keep_deck=keep_deck, load_lines=load_lines)
