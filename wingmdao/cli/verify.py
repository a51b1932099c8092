"""``wingmdao verify wing-box``: the beam against a CalculiX shell or solid model of the same box.

The shell model (:mod:`wingmdao.fe.box_model`, S8R on the wall mid-surfaces, streamwise
sections CS1..CS4 of App. D.1, wall thicknesses of the beam-normal cut as ``wingmdao run
wing-box`` uses them, root ring clamped, the tip load at the CS4 centre entering a CS4 rib
through a distributing coupling) or the solid model (:mod:`wingmdao.fe.solid_box`, C3D20R
walls, same loads and clamp) is written, run in ``ccx`` and read; von Mises at the box corners
and mid-flanges along the span (:mod:`wingmdao.fe.stress_points`); the beam is the project's
nonlinear beam on the same box (:func:`wingmdao.cases.wing_box.solve_wing_box`). JSON:
``stations``, ``displacement_beam``, ``displacement_fe`` (section-average displacement
magnitude per station, m), ``difference_percent``, and with ``--modes N``
``frequencies_beam_hz``, ``frequencies_fe_hz``, ``frequency_difference_percent``.
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

import wingmdao.cli._openmdao  # noqa: F401  (first: OpenMDAO without the matplotlib of its report plugins)
from wingmdao.cli.parsers.verify import LOAD_NAMES
from wingmdao.cli._verify_fe import build_fe_model, design_walls, fe_material  # noqa: F401
from wingmdao.cli._verify_fe import check_fe_args, percent_difference, von_mises_table  # noqa: F401
from wingmdao.cli._io import check_output_dir, check_output_file
from wingmdao.beam.geometry import polyline_beam
from wingmdao.beam.modes import natural_frequencies
from wingmdao.beam.residual import forcing_specs
from wingmdao.cases import wing_box as case
from wingmdao.cases.wing_box import STUDY_LOADS, wing_box_beam
from wingmdao.cli import write_json
from wingmdao.cli._verify_buckling import plot_buckling
from wingmdao.cli._verify_pegasus import verify_pegasus
from wingmdao.cli.run import check_wing_box_args
from wingmdao.fe.box_model import BoxSections, solve_modes, solve_static
from wingmdao.fe.calculix import CalculixNotFound, find_ccx
from wingmdao.plots import save_figure
from wingmdao.timemarch.system import pack
import openmdao.api as om
from wingmdao.beam.static import BeamModel, beam_forcing


def wing_box_sections(geometry, t_spar, t_skin, walls=None):
    """:class:`BoxSections` of CS1..CS4 with the beam-normal wall thicknesses of ``run wing-box``."""
    _, _, cos_sweep, cos_dih = case.wing_geometry(geometry, (1, 1, 1))
    g = case.geometry_data(geometry)
    if walls is None:
        walls = {"t_upper_skin": t_skin * cos_dih, "t_lower_skin": t_skin * cos_dih,
                 "t_front_spar": t_spar * cos_sweep, "t_rear_spar": t_spar * cos_sweep}
    return BoxSections(case.section_centres(geometry), g["widths"], case.HEIGHTS, walls)


#: --loads: named load cases at the CS4 centre (force N, moment N m, body axes). d1-*: the three
#: linear cases of the App. D.1 comparison (docs/verification-calculix.md); study1/study2: the
#: Sec. 4.7.2 sizing tip loads (``wingmdao.cases.wing_box.STUDY_LOADS``; study 3 has study 2's).
def named_loads():
    return {"d1-fz": ((0.0, 0.0, 1.0e5), (0.0, 0.0, 0.0)), "d1-fx": ((1.0e5, 0.0, 0.0), (0.0, 0.0, 0.0)),
            "d1-my": ((0.0, 0.0, 0.0), (0.0, 1.0e5, 0.0)),
            "study1": STUDY_LOADS[1], "study2": STUDY_LOADS[2]}


def _tip_loads(args):
    """(force, moment) of ``--loads`` (``tip``: ``--tip-load``/``--tip-moment``)."""
    name = getattr(args, "loads", "tip")
    if name == "tip":
        return tuple(args.tip_load), tuple(args.tip_moment)
    if name not in LOAD_NAMES:
        raise ValueError(f"--loads = {name!r}; allowed: {', '.join(LOAD_NAMES)}")
    if np.any(args.tip_load) or np.any(args.tip_moment):
        raise ValueError(f"--loads {name} is a named load case; drop --tip-load/--tip-moment")
    return named_loads()[name]


def _check_verify_args(args, span):
    for name, val in (("dynamic", False), ("check_totals", False), ("gravity", None), ("elements", (6, 8, 6)),
                      ("model", "beam"), ("load_steps", 1), ("nlgeom", False), ("loads", "tip"),
                      ("through_elements", 2), ("fidelity", "shell")):
        setattr(args, name, getattr(args, name, val))
    check_wing_box_args(args)
    check_fe_args(args, span)
    return _tip_loads(args)


def verify_wing_box(args) -> dict:
    span = float(sum(case.SPANS))
    force, moment = _check_verify_args(args, span)
    find_ccx()
    walls = design_walls(args.design, case.NAME) if args.design else None
    sec = wing_box_sections(args.geometry, args.t_spar, args.t_skin, walls)
    ribs = [] if args.ribs is None else list(np.arange(args.ribs, span + 1e-9, args.ribs))
    ribs = sorted(set(np.round(ribs + [span], 9)))
    model = build_fe_model(args, sec, ribs, *case.wing_geometry(args.geometry, (1, 1, 1))[2:])
    ys = sec.centres[:, 1]
    loads = [(span, sec.centres[-1], force, moment)]
    fe = solve_static(model, loads, ys, nlgeom=args.nlgeom, stress=True)

    try:
        beam = case.solve_wing_box(args.geometry, tip_force=force, tip_moment=moment, t_spar=args.t_spar,
                                   t_skin=args.t_skin, load_steps=args.load_steps, walls=walls)
    except om.AnalysisError as exc:    # the beam's Newton solve
        raise ValueError(f"the beam solve did not converge ({exc}); try more --load-steps") from exc
    d_beam = np.asarray(beam["displacement"])
    d_fe = np.linalg.norm(fe["displacement"], axis=1)
    r_beam = np.linalg.norm(beam["station_rotation"], axis=1)
    r_fe = np.linalg.norm(fe["rotation"], axis=1)
    res = {"case": case.NAME, "geometry": args.geometry, "fidelity": args.fidelity,
           "loads": {"name": args.loads, "tip_force": list(force), "tip_moment": list(moment),
                     "nlgeom": bool(args.nlgeom), "design": args.design},
           "stations": list(case.STATIONS), "station_y": ys.tolist(),
           "displacement_beam": d_beam.tolist(), "displacement_fe": d_fe.tolist(),
           "difference_percent": percent_difference(d_beam, d_fe, max(d_fe.max(), span * r_fe.max())),
           "rotation_beam": r_beam.tolist(), "rotation_fe": r_fe.tolist(),
           "rotation_difference_percent": percent_difference(r_beam, r_fe, max(r_fe.max(), d_fe.max() / span)),
           "station_displacement_beam": beam["station_displacement"],
           "station_displacement_fe": fe["displacement"].tolist(),
           "station_rotation_beam": beam["station_rotation"], "station_rotation_fe": fe["rotation"].tolist(),
           "ribs_y": ribs, "mesh": {"element": model.element, "num_elements": fe["num_elements"],
                                    "num_nodes": fe["num_nodes"], "chord_elements": args.chord_elements,
                                    "height_elements": args.height_elements, "span_size": args.span_size,
                                    "through_elements": args.through_elements if args.fidelity == "solid" else None},
           "fe_time_s": fe["time"],
           "units": "SI (m, N, N*m, rad, Pa, Hz); body axes x aft, y outboard, z up"}
    res["von_mises"] = von_mises_table(model, sec, fe["stresses"], loads, segment_axes(args.geometry))
    if args.modes:
        fm = solve_modes(model, args.modes)
        res["frequencies_fe_hz"] = fm["frequencies_hz"].tolist()
        fb = beam_frequencies(args.geometry, args.t_spar, args.t_skin, args.modes, walls=walls)
        res["frequencies_beam_hz"] = fb.tolist()
        k = min(len(fb), len(fm["frequencies_hz"]))
        res["frequency_difference_percent"] = (100 * (fb[:k] - fm["frequencies_hz"][:k])
                                               / fm["frequencies_hz"][:k]).tolist()
    if args.plot:
        _plot(res, args.plot)
        res["plot"] = args.plot
    return res


def segment_axes(geometry):
    """``axes_at(y)``: the beam's csn axes T (rows c, s, n, body axes) of the segment holding y."""
    centres = case.section_centres(geometry)
    T = polyline_beam(centres, (2,) * (len(centres) - 1)).csn_axes()[1::2]
    ys = centres[:, 1]
    return lambda y: T[int(np.clip(np.searchsorted(ys, y) - 1, 0, len(T) - 1))]


def beam_frequencies(geometry, t_spar, t_skin, count, walls=None):
    """Lowest natural frequencies (Hz) of the beam of ``run wing-box`` (jig state)."""
    params, _ = wing_box_beam(geometry, t_spar=t_spar, t_skin=t_skin, walls=walls)
    m = BeamModel(params)
    n = m.num_nodes
    return natural_frequencies(m.system, m.p, pack(forcing_specs(n), beam_forcing(n)), count=count)


def _plot(res, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, rx, bx) = plt.subplots(1, 3, figsize=(15, 4))
    label = f"CalculiX {res['fidelity']} ({res['mesh']['element']})"
    for axis, key, name in ((ax, "displacement", "section-average displacement (m)"),
                            (rx, "rotation", "section rotation magnitude (rad)")):
        axis.plot(res["station_y"], res[f"{key}_fe"], "o-", label=label)
        axis.plot(res["station_y"], res[f"{key}_beam"], "s--", label="beam")
        axis.set_xlabel("span y (m)")
        axis.set_ylabel(name)
        axis.legend()
        axis.grid(True)
    vm = res.get("von_mises")
    if vm:
        fe, beam = np.array(vm["fe_pa"]) / 1e6, np.array(vm["beam_pa"]) / 1e6
        for k, point in enumerate(vm["points"]):
            if point in ("front-upper skin", "front-upper spar", "upper skin centre", "front spar centre"):
                line, = bx.plot(vm["y"], fe[:, k], "-", label=f"{point} FE")
                bx.plot(vm["y"], beam[:, k], "--", color=line.get_color(), label=f"{point} beam")
        bx.set_xlabel("span y (m)")
        bx.set_ylabel("von Mises (MPa)")
        bx.legend(fontsize=7)
        bx.grid(True)

    save_figure(fig, path)


def run_verify(args) -> int:
    overwrite = getattr(args, "overwrite", False)
    if getattr(args, "out", None) is not None and args.plot is None:
        check_output_dir(args.out, "--out")
        name = "verify_pegasus_buckling.png" if getattr(args, "buckling", False) else f"verify_{args.case.replace('-', '_')}.png"
        args.plot = os.path.join(args.out, name)
    check_output_file(args.json, "--json", overwrite=overwrite, others={"plot": args.plot})
    check_output_file(args.plot, "--out" if getattr(args, "out", None) else "--plot", overwrite=overwrite)
    try:
        res = verify_pegasus(args) if args.case == "pegasus" else verify_wing_box(args)
        if args.case == "pegasus" and args.plot and res.get("analysis") == "buckling":
            plot_buckling(res, args.plot)
            res["plot"] = args.plot
        elif args.case == "pegasus" and args.plot:
            _plot(res, args.plot)
            res["plot"] = args.plot
    except CalculixNotFound as exc:
        print(f"wingmdao verify: {exc}", file=sys.stderr)
        return 2
    write_json(res, args.json)
    return 0


def verify_args(geometry, tip_load=(0.0, 0.0, 0.0), tip_moment=(0.0, 0.0, 0.0), *, ribs=None, modes=0,
                chord_elements=8, height_elements=2, span_size=0.5, rib_thickness=0.1, t_spar=0.2, t_skin=0.1):
    """The parsed-argument namespace of ``verify wing-box`` (for scripts and tests)."""
    return argparse.Namespace(geometry=geometry, tip_load=tuple(tip_load), tip_moment=tuple(tip_moment),
                              ribs=ribs, no_ribs=ribs is None, modes=modes, chord_elements=chord_elements,
                              height_elements=height_elements, span_size=span_size, rib_thickness=rib_thickness,
                              t_spar=t_spar, t_skin=t_skin, design=None, fidelity="shell", plot=None, json="-",
                              loads="tip", nlgeom=False, load_steps=1, through_elements=2, overwrite=False)
