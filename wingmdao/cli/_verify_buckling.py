"""``wingmdao verify pegasus --buckling``: a stiffened PEGASUS design (``wingmdao size pegasus
--panels stiffened``) in CalculiX linear buckling under a sizing maneuver, against the sizing
model's smallest buckling load factor on the same load case.

FE model: :mod:`wingmdao.fe.stiffened_box` (skins, spar webs, blade stiffeners and ribs as S8R
shells, root ring clamped). Loads: the load case's forcing as the sizing beam takes it
(:func:`wingmdao.cases.pegasus.build` with ``loads="maneuver", panels="stiffened"``): the
aerodynamic force and moment per length, and gravity minus the frame acceleration on the sizing
beam's mass per length (structure with the smeared stiffeners, and the engines smeared as
non-structural mass), i.e. -n g m per length; lumped at the FE's span lines and entering through
distributing couplings (:mod:`wingmdao.fe.wing_loads`). The ribs' own weight is left out (as in
the sizing beam).

Model factor: the sizing problem analysed at the design; for each panel family f of the case the
unfactored ratio R = (g_f + 1) / safety factor at every station and point; the model's buckling
load factor is 1 / max R over the elastic buckling families (``skin_buckling``,
``panel_buckling``, ``web_buckling``); ``stiffener_column`` (Euler/Johnson) and
``stiffener_crippling`` (an inelastic allowable) are reported beside it.
"""

from __future__ import annotations

import json
import os

import numpy as np

from wingmdao.cases import pegasus
from wingmdao.cli._verify_fe import fe_material
from wingmdao.fe.box_model import BoxSections
from wingmdao.fe.calculix import find_ccx
from wingmdao.fe.stiffened_box import (build_stiffened_box, running_load_profile, shell_mass,
                                       skin_running_loads, solve_buckling)
from wingmdao.fe.wing_loads import lumped_line_loads
from wingmdao.panel_results import model_running_loads
from wingmdao.plots import save_figure
from wingmdao.sizing import build_problem

LOAD_CASES = ("maneuver_pos", "maneuver_neg")
ELASTIC = ("skin_buckling", "panel_buckling", "web_buckling")
OTHER = ("stiffener_column", "stiffener_crippling")
#: PanelFailure points per station: skins (upper front, upper rear, lower front, lower rear), webs (front, rear)
SKIN_POINTS = ("upper_skin", "upper_skin", "lower_skin", "lower_skin")
WEB_POINTS = ("front_spar", "rear_spar")


def read_stiffened_design(path) -> dict:
    """The design JSON of a stiffened PEGASUS sizing; ValueError naming ``--design`` otherwise."""
    if not path:
        raise ValueError("--buckling needs --design RESULT.json (a 'wingmdao size pegasus --panels stiffened' result)")
    if not os.path.exists(path):
        raise ValueError(f"--design {path!r}: no such file")
    try:
        with open(path, encoding="utf-8") as fh:
            data = json.load(fh)
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"--design {path!r}: not a JSON file ({exc})") from None
    if not isinstance(data, dict) or data.get("case") != "pegasus":
        raise ValueError(f"--design {path!r}: not a 'wingmdao size pegasus' result")
    panels = data.get("panels")
    skins = [panels.get(s, {}) if isinstance(panels, dict) else {} for s in ("upper_skin", "lower_skin")]
    if not isinstance(panels, dict) or any(None in s.get("stiffener_height_m", [None]) for s in skins):
        raise ValueError(f"--design {path!r}: not a stiffened design (no 'panels' block with stiffener "
                         "dimensions); --buckling needs a 'wingmdao size pegasus --panels stiffened' result")
    return data


def design_variables(data, geometry) -> dict:
    """{design variable: (n,) m per station} of the design JSON."""
    out = {}
    for w in ("upper_skin", "lower_skin", "front_spar", "rear_spar"):
        out[f"t_{w}"] = np.asarray(data["thickness"][w], float)
    for s in ("upper", "lower"):
        p = data["panels"][f"{s}_skin"]
        out[f"h_{s}_stiffener"] = np.asarray(p["stiffener_height_m"], float)
        out[f"t_{s}_stiffener"] = np.asarray(p["stiffener_thickness_m"], float)
    n = geometry.num_nodes
    for k, v in out.items():
        if v.shape != (n,) or not np.all(np.isfinite(v) & (v > 0)):
            raise ValueError(f"--design: {k} must hold {n} positive values (m), got {v.tolist()}")
    return out


def rib_thicknesses(data, ribs_y, minimum) -> list:
    """Each FE rib's thickness (m): the design's sized rib at that position (its ``ribs`` block,
    ``positions_m`` and ``thickness_m``, from :func:`wingmdao.panel_results.rib_summary`); a rib
    the block does not list (or a design without the block) takes the layout's ``minimum``."""
    ribs = data.get("ribs") if isinstance(data.get("ribs"), dict) else {}
    pos = np.asarray(ribs.get("positions_m", []), float)
    thick = np.asarray(ribs.get("thickness_m", []), float)
    if pos.shape != thick.shape or not np.all(np.isfinite(thick) & (thick > 0)):
        raise ValueError(f"--design: ribs.thickness_m must hold one positive value (m) per ribs.positions_m, "
                         f"got {thick.tolist()}")
    out = []
    for y in ribs_y:
        k = np.flatnonzero(np.abs(pos - y) < 1e-6)
        out.append(float(thick[k[0]]) if k.size else float(minimum))
    return out


def case_setup(data):
    """The stiffened maneuver setup of the design (its load factors and stiffener pitch)."""
    resp = data.get("load_case_response", {})
    kw = {}
    if "maneuver_pos" in resp:
        kw["load_factor"] = round(float(resp["maneuver_pos"]["peak_load_factor"]), 9)
    if "maneuver_neg" in resp:
        kw["negative_load_factor"] = round(float(resp["maneuver_neg"]["peak_load_factor"]), 9)
    pitch = data["panels"]["upper_skin"]["stiffener_pitch_m"][0]
    return pegasus.build(loads="maneuver", panels="stiffened", stiffener_pitch=float(pitch), **kw)


def running_loads(model, loads, mdl, args) -> dict:
    """``fe_running_loads`` (the deck's static state, per skin and span row:
    :func:`wingmdao.fe.stiffened_box.running_load_profile`) and ``model_running_loads`` (the
    sizing model's per station: :func:`wingmdao.panel_results.model_running_loads`)."""
    keep = os.path.join(args.keep_deck, "static") if args.keep_deck else None
    fe = skin_running_loads(model, loads, keep_dir=keep)
    return {"fe_running_loads": {f"{s}_skin": running_load_profile(fe[s]) for s in ("upper", "lower")},
            "model_running_loads": {f"{s}_skin": v for s, v in mdl["running_loads"].items()},
            "running_loads_note": "N/m, compression negative; span = along y, chord = along x, shear = in-plane; "
                                  "FE: mean of each S8R element's integration points times its thickness "
                                  "(skin only; the blades carry their own share); model: n_span of the skin with "
                                  "its smeared stiffeners at the front and rear edge, n_chord at mid-chord"}


def model_buckling(setup, design, case_name) -> dict:
    """The sizing model at the design on ``case_name``: per family the smallest load factor
    1 / max R and where it is, the elastic-buckling minimum (``factor``), the mass (kg)."""
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False,
                            section="stiffened", panels=setup.panels)
    smap = np.asarray(setup.geometry.station_map) if setup.geometry.station_map is not None else None
    for k, v in design.items():
        if smap is not None:
            dv = np.zeros(int(smap.max()) + 1)
            dv[smap] = v
            v = dv
        prob.set_val(k, v, units="m")
    prob.run_model()
    sf = setup.panels.safety_factor
    families = {}
    walls = {w: np.zeros(setup.geometry.num_nodes) for w in ("upper_skin", "lower_skin", "front_spar", "rear_spar")}
    for f in ELASTIC + OTHER:
        g = np.asarray(prob.get_val(f"cases.{case_name}.panels.g_{f}"))[0]   # (stations, points)
        R = (g + 1.0) / sf
        if f in ELASTIC:
            for k, w in enumerate(WEB_POINTS if f == "web_buckling" else SKIN_POINTS):
                walls[w] = np.maximum(walls[w], R[:, k])
        st, pt = np.unravel_index(int(np.argmax(R)), R.shape)
        wall = (WEB_POINTS if f == "web_buckling" else SKIN_POINTS)[pt]
        families[f] = {"factor": float(1.0 / R.max()), "station": int(st), "wall": wall,
                       "span_y_m": float(setup.geometry.span_coordinate[st])}
    worst = min(ELASTIC, key=lambda f: families[f]["factor"])
    mass = float(prob.get_val("box_mass", units="kg")[0] + prob.get_val("rib_mass", units="kg")[0])
    loads = model_running_loads(prob, case_name, setup.panels)
    return {"running_loads": loads, "factor": families[worst]["factor"], "critical": dict(families[worst], mode=worst),
            "families": families, "safety_factor": sf, "mass_kg": mass,
            "by_station": {w: [float(1.0 / r) if r > 0 else None for r in v] for w, v in walls.items()}}


def fe_station_loads(setup, case_name, design, model_box, sections, at_ribs=True):
    """Station loads [(y, centre, F, M)] of the load case: trapezoid-lumped at the stations, where
    the ribs are (``at_ribs``: the sizing beam's own nodal loads, entering the box through the
    rib rings), or at every FE corner line (between the ribs too)."""
    case = next(c for c in setup.load_cases if c.name == case_name)
    fo = case.forcing
    mpl = pegasus.beam_params(setup.geometry.num_nodes, thickness=design, panels=setup.panels)["mass_per_length"]
    accel = np.asarray(fo["gravity"])[0] - np.asarray(fo.get("frame_acceleration", np.zeros((1, 3))))[0]
    force = np.asarray(fo["force_per_length"])[0] + mpl[:, None] * accel[None, :]
    moment = np.asarray(fo["moment_per_length"])[0]
    at = np.asarray(setup.geometry.span_coordinate) if at_ribs else model_box.span_y[::2]
    return lumped_line_loads(sections, at, setup.geometry.span_coordinate, force, moment), \
        {"load_factor": float(-accel[2] / 9.80665), "lift_n": float(np.trapezoid(
            np.asarray(fo["force_per_length"])[0][:, 2], setup.geometry.span_coordinate)),
         "description": case.description}


def check_buckling_args(args):
    """The flags that do not go with --buckling (ValueError naming them), before any solve."""
    loads = getattr(args, "loads", "1g")
    if getattr(args, "loads_case", None) is None:  # --loads of the command line: maneuver-pos (default) or -neg
        loads = "maneuver-pos" if loads == "1g" else loads
        if loads.replace("-", "_") not in LOAD_CASES:
            raise ValueError(f"--buckling --loads = {loads}; allowed: "
                             f"{', '.join(c.replace('_', '-') for c in LOAD_CASES)} (the sizing maneuvers)")
        args.loads_case = loads.replace("-", "_")
    elif args.loads_case not in LOAD_CASES or loads != "1g":
        raise ValueError(f"loads_case = {args.loads_case!r} with loads = {loads!r}; allowed loads_case: "
                         f"{', '.join(LOAD_CASES)} with loads '1g'")
    if getattr(args, "fidelity", "shell") != "shell":
        raise ValueError("--buckling is a shell model; drop --fidelity solid")
    if getattr(args, "load_factor", 1.0) != 1.0:
        raise ValueError("--buckling takes its loads from --loads maneuver-pos or maneuver-neg; drop --load-factor")
    if getattr(args, "modes", 0):
        raise ValueError("--buckling: drop --modes (use --buckling-modes)")
    if getattr(args, "nlgeom", False):
        raise ValueError("--buckling is a linear buckling analysis; drop --nlgeom")
    if getattr(args, "no_ribs", False) or getattr(args, "ribs", None) is not None:
        raise ValueError("--buckling puts ribs at the design's rib stations; drop --ribs / --no-ribs")
    for name, low in (("bay_elements", 1), ("web_elements", 1), ("buckling_modes", 1)):
        if getattr(args, name) < low:
            raise ValueError(f"--{name.replace('_', '-')} = {getattr(args, name)}; allowed >= {low}")
    if args.buckling_modes > 50:
        raise ValueError(f"--buckling-modes = {args.buckling_modes}; allowed range [1, 50]")
    if args.stiffeners is not None and args.stiffeners < 1:
        raise ValueError(f"--stiffeners = {args.stiffeners}; allowed >= 1")


def build_model(data, setup, design, args, rib_t):
    """(StiffenedBox, BoxSections) of the design."""
    geo = setup.geometry
    walls = {k: design[k] for k in ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")}
    sec = BoxSections(geo.node_positions, geo.width, geo.height, walls)
    stiff = {s: (design[f"h_{s}_stiffener"], design[f"t_{s}_stiffener"]) for s in ("upper", "lower")}
    model = build_stiffened_box(sec, fe_material(), stiff, setup.panels.stiffener_pitch, count=args.stiffeners,
                                bay_elements=args.bay_elements, web_elements=args.web_elements,
                                height_elements=args.height_elements, span_element_size=args.span_size,
                                ribs_y=list(setup.panels.rib_positions), rib_thickness=rib_t)
    return model, sec


def verify_pegasus_buckling(args) -> dict:
    check_buckling_args(args)
    data = read_stiffened_design(args.design)
    setup = case_setup(data)
    design = design_variables(data, setup.geometry)
    find_ccx()
    ribs_y = list(setup.panels.rib_positions)
    rib_t = (rib_thicknesses(data, ribs_y, setup.panels.rib_thickness) if args.rib_thickness is None
             else [float(args.rib_thickness)] * len(ribs_y))
    model, sec = build_model(data, setup, design, args, rib_t)
    mass = shell_mass(model.deck, fe_material().rho)
    mdl = model_buckling(setup, design, args.loads_case)
    loads, info = fe_station_loads(setup, args.loads_case, design, model.box, sec,
                                   at_ribs=args.load_lines == "ribs")
    fe = solve_buckling(model, loads, modes=args.buckling_modes, keep_dir=args.keep_deck)
    running = running_loads(model, loads, mdl, args) if getattr(args, "running_loads", False) else None
    y = setup.geometry.span_coordinate

    def where(m):
        py = m["peak_xyz"][1]
        bay = int(np.clip(np.searchsorted(y, py, side="right") - 1, 0, y.size - 2))
        return {"wall": m["peak_part"], "span_y_m": py, "station": int(np.argmin(np.abs(y - py))),
                "bay": [bay, bay + 1], "xyz_m": m["peak_xyz"],
                "part_peaks_relative": {k: round(v, 4) for k, v in m["part_peaks"].items()}}

    modes = [dict(mode_number=m["mode_number"], factor=m["factor"], **where(m)) for m in fe["positive_modes"]]
    box_modes = [m for m in modes if m["wall"] != "ribs"]
    sf = mdl["safety_factor"]
    overlap = model.overlap_kg
    fe_mass = dict(mass, stiffeners_above_skin_face=mass["stiffeners"] - overlap, total=mass["total"] - overlap)
    return {
        "case": "pegasus", "analysis": "buckling", "design": args.design, "loads_case": args.loads_case,
        "loads": dict(info, entering_at=args.load_lines),
        "fe_buckling_factor": fe["factor"], "fe_buckling_factors": fe["factors"], "fe_mode_number": fe["mode_number"],
        "fe_mode_location": modes[0],
        "fe_modes": modes,
        "fe_first_box_mode": box_modes[0] if box_modes else None,
        "rib_thickness_m": {"fe": rib_t, "positions_m": ribs_y, "minimum": setup.panels.rib_thickness,
                            "from": "--rib-thickness" if args.rib_thickness is not None else "design"},
        "model_buckling_factor": mdl["factor"], "model_critical": mdl["critical"],
        "model_factors_by_mode": mdl["families"], "safety_factor": sf, "station_y": y.tolist(),
        "model_factor_by_station": mdl["by_station"],
        "fe_over_model": fe["factor"] / mdl["factor"], "fe_over_safety_factor": fe["factor"] / sf,
        "acceptance": {"fe_at_least_safety_factor": bool(fe["factor"] >= sf),
                       "fe_at_least_0p7_safety_factor": bool(fe["factor"] >= 0.7 * sf),
                       "note": "the panel model is conservative by ~25-30 % against FE (docs/panels.md, 'Model "
                               "against CalculiX'): the FE factor should be >= the safety factor; below it a mode "
                               "the model does not have (rib, spar-web with ribs, coupled) or the FE's load and "
                               "boundary idealisation is the suspect (docs/verification-calculix.md)"},
        "mass_kg": {"fe": fe_mass, "design": float(data["mass_kg"]), "model_recomputed": mdl["mass_kg"],
                    "design_breakdown": data.get("mass_breakdown_kg"),
                    "difference_percent": 100.0 * (fe_mass["total"] - float(data["mass_kg"])) / float(data["mass_kg"]),
                    "note": "FE: element area x thickness x density; the stiffener webs' part inside the skins' "
                            "half thickness (modelled twice) is taken off the total"},
        "mesh": {"element": "S8R", "num_elements": model.num_elements, "num_nodes": len(model.deck.nodes),
                 "stiffeners_per_skin": model.count, "stiffener_pitch_m": model.pitch,
                 "stiffener_thickness_scale": [float(model.thickness_scale.min()), float(model.thickness_scale.max())],
                 "num_stiffener_strips": model.num_webs, "num_ribs": model.num_ribs,
                 "bay_elements": args.bay_elements, "web_elements": args.web_elements,
                 "height_elements": args.height_elements, "span_size": args.span_size},
        "fe_time_s": fe["time"],
        **(running or {}),
        "units": "SI (m, N, kg); body axes x aft, y outboard, z up; buckling factors multiply the limit loads",
    }


def plot_buckling(res, path):
    """The model's buckling load factor per station and wall (elastic modes) with the CalculiX
    factors of the extracted modes at the span position of their peaks, marked by part."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 5))
    y = res["station_y"]
    for w, v in res["model_factor_by_station"].items():
        ax.plot(y, [np.nan if f is None else f for f in v], "-o", ms=3,
                label=f"model {w} (elastic modes: skin, panel, web)")
    markers = {"upper_skin": "^", "lower_skin": "v", "upper_stiffeners": "^", "lower_stiffeners": "v",
               "front_spar": "s", "rear_spar": "s", "ribs": "x"}
    seen = set()
    for m in res["fe_modes"]:
        lab = f"CalculiX mode: {m['wall']}" if m["wall"] not in seen else None
        seen.add(m["wall"])
        ax.plot([m["span_y_m"]], [m["factor"]], markers.get(m["wall"], "o"), color="k", ms=8, label=lab)
    ax.axhline(res["safety_factor"], color="r", ls="--", label=f"safety factor {res['safety_factor']:g}")
    ax.set_xlabel("span y (m)")
    ax.set_ylabel("buckling load factor on the limit loads")
    ax.set_ylim(0, max(4.0, 1.2 * res["fe_buckling_factor"]))
    ax.set_title(f"PEGASUS stiffened box, {res['loads_case']}")
    ax.legend(fontsize=7)
    ax.grid(True)
    save_figure(fig, path)
