"""The 'wing-like' box beam of App. D.1 / E.3 and its sizing studies (Sec. 4.7.2).

Tables transcribed by hand from the dissertation (SI):

* Table D.1: spanwise (y) distances between the cross-sections CS1..CS4: d = 3, 4, 3 m;
  heights h1..h4 = 0.5 m.
* Table D.2: widths w1..w4, leading-edge sweeps lambda_1..3 per segment and one dihedral.
* Table E.2: spar thickness 0.2 m, skin thickness 0.1 m (streamwise cut).

The sections are streamwise cuts parallel to the root. Segment k's sweep is that of the
leading edge (front face): from CS k to CS k+1 the box centre moves aft by
d_k tan(lambda_k) - (w_k - w_{k+1}) / 2 and up by d_k tan(dihedral). The beam axis joins the
section centres. Section properties are those of the beam-normal cut
(:func:`wingmdao.beam.geometry.streamwise_to_normal`), so ``section_to_csn`` is the identity
(docs/beam-theory.md, 'Streamwise and normal sections').

Two layers use these data:

* plain beam solves (:func:`wing_box_beam`, :func:`solve_wing_box`, :func:`comparison_solver`)
  for the solid-model comparison;
* the OpenMDAO chain section -> beam -> internal loads -> stress -> KS of
  :class:`wingmdao.groups.wing.WingSizing` with one tip-load case (:func:`wing_geometry`,
  :func:`tip_load_case`, :func:`analysis_problem`) for ``wingmdao run wing-box``, and the
  sizing studies 1-3 of Sec. 4.7.2 (``NAME``, ``add_arguments``, ``build``) for
  ``wingmdao size wing-box``.

Sizing (Eq. 4.57): the design variables are the four wall thicknesses of the *beam-normal*
section at every beam node (the default mesh of one element per segment puts the nodes at
CS1..CS4: 4 x 4 = 16 variables as in the dissertation; the beam's element properties blend the
two end sections). Study 2's loads are given in the dissertation's axes (beam along x, 'drag'
F_y, torsion M_x); in our body axes (beam along y, x aft) drag is +x and torsion is about +y.
"""

from __future__ import annotations

import numpy as np

from wingmdao.beam.geometry import polyline_beam, streamwise_to_normal, swept_dihedral_points
from wingmdao.cases import CaseSetup
from wingmdao.materials import ALUMINIUM

NAME = "wing-box"
HELP = "App. D.1 'wing-like' box beam, Sec. 4.7.2 studies 1-3 (tip loads, 16 thickness variables)"

SPANS = (3.0, 4.0, 3.0)                      # Table D.1, d1..d3 (m)
HEIGHTS = (0.5, 0.5, 0.5, 0.5)               # Table D.1, h1..h4 (m)
T_SPAR, T_SKIN = 0.2, 0.1                    # Table E.2 (m)
STATIONS = ("CS1", "CS2", "CS3", "CS4")
#: Table D.2: widths (m), leading-edge sweeps per segment (deg), dihedral (deg)
GEOMETRIES = {
    "prismatic": {"widths": (3.0, 3.0, 3.0, 3.0), "sweeps": (0.0, 0.0, 0.0), "dihedral": 0.0},
    "taper": {"widths": (3.0, 2.5, 2.0, 1.5), "sweeps": (0.0, 0.0, 0.0), "dihedral": 0.0},
    "sweep": {"widths": (3.0, 3.0, 3.0, 3.0), "sweeps": (10.0, 15.0, 20.0), "dihedral": 0.0},
    "dihedral": {"widths": (3.0, 3.0, 3.0, 3.0), "sweeps": (0.0, 0.0, 0.0), "dihedral": 5.0},
    "combined": {"widths": (3.0, 2.5, 2.0, 1.5), "sweeps": (10.0, 15.0, 20.0), "dihedral": 5.0},
}


def geometry_data(name: str) -> dict:
    if name not in GEOMETRIES:
        raise ValueError(f"geometry must be one of {list(GEOMETRIES)}, got {name!r}")
    return GEOMETRIES[name]


def section_centres(name: str) -> np.ndarray:
    """Centres of CS1..CS4 (4, 3), body axes, CS1 at the origin."""
    g = geometry_data(name)
    w = np.asarray(g["widths"])
    return swept_dihedral_points(SPANS, g["sweeps"], g["dihedral"], offsets_x=-0.5 * (w[:-1] - w[1:]))


def wing_box_beam(name: str, elements_per_segment=(6, 8, 6), t_spar=T_SPAR, t_skin=T_SKIN,
                  material=ALUMINIUM, section_mapping="normal", walls=None) -> tuple[dict, np.ndarray]:
    """Beam parameters (``param_specs`` names) of the box and the node index of each station.

    ``walls``: the four beam-normal wall thicknesses per station CS1..CS4 ({'t_upper_skin', ...:
    (4,)} m, a ``wingmdao size wing-box --elements 1 1 1`` design), linear in arc length between
    the stations, instead of the uniform ``t_spar``/``t_skin`` (normal mapping only).

    ``section_mapping``: 'normal' (default) takes the box properties of the beam-normal cut;
    'rotated' those of the streamwise cut rotated into csn (Eq. F.31, docs/beam-theory.md 9);
    'fe' the section FE (Giavotto/BECAS, ``wingmdao.section.fe``) of the beam-normal cut: the
    dissertation's "VbS" beam on the detailed section (thick-wall torsion, FE shear stiffness).
    """
    from wingmdao.beam.geometry import streamwise_section_to_csn
    from wingmdao.section.box import box_properties

    if section_mapping not in ("normal", "rotated", "fe"):
        raise ValueError(f"section_mapping must be 'normal', 'rotated' or 'fe', got {section_mapping!r}")

    for label, v in (("t_spar", t_spar), ("t_skin", t_skin)):
        if not (np.isfinite(v) and v > 0.0):
            raise ValueError(f"{label} must be a positive thickness in m, got {v}")
    g = geometry_data(name)
    geo = polyline_beam(section_centres(name), elements_per_segment)
    width = geo.interpolate(g["widths"])
    height = geo.interpolate(HEIGHTS)
    if np.any(2 * t_spar >= width) or np.any(2 * t_skin >= height):
        raise ValueError(f"t_spar must be < width/2 = {width.min() / 2} m and t_skin < height/2 = "
                         f"{height.min() / 2} m")
    T = geo.csn_axes()
    rows = []
    R = streamwise_section_to_csn(geo.node_euler_angles)
    if walls is not None and section_mapping != "normal":
        raise ValueError(f"walls per station need section_mapping='normal', got {section_mapping!r}")
    node_walls = None if walls is None else {k: geo.interpolate(walls[k]) for k in
                                             ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")}
    for i in range(geo.num_nodes):
        if node_walls is not None:
            w, h = streamwise_to_normal(width[i], height[i], t_spar, t_skin, T[i, 1])[:2]
            rows.append(box_properties(w, h, *(node_walls[k][i] for k in
                                               ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")),
                                       material))
        elif section_mapping == "fe":
            rows.append(_fe_box_row(*streamwise_to_normal(width[i], height[i], t_spar, t_skin, T[i, 1]), material))
        elif section_mapping == "normal":
            w, h, ts, tk = streamwise_to_normal(width[i], height[i], t_spar, t_skin, T[i, 1])
            rows.append(box_properties(w, h, tk, tk, ts, ts, material))
        else:
            rows.append(box_properties(width[i], height[i], t_skin, t_skin, t_spar, t_spar, material,
                                       section_to_csn=R[i]))
    n = geo.num_nodes
    params = {
        "node_positions": geo.node_positions,
        "node_euler_angles": geo.node_euler_angles,
        "stiffness_csn": np.array([r["stiffness_csn"] for r in rows]),
        "compliance_csn": np.array([r["compliance_csn"] for r in rows]),
        "tension_axis": np.array([[r["c_ea"], r["n_ea"]] for r in rows]),
        "shear_center": np.array([[r["c_sc"], r["n_sc"]] for r in rows]),
        "mass_per_length": np.array([r["mass_per_length"] for r in rows]),
        "mass_center": np.array([[r["c_cg"], r["n_cg"]] for r in rows]),
        "inertia_per_length": np.array([r["inertia_per_length"] for r in rows]).reshape(n, 3, 3),
    }
    return params, geo.key_nodes


_FE_ROWS: dict = {}


def _fe_box_row(w, h, t_spar, t_skin, material, mesh_size=0.05):
    """Beam data of a w x h box (spars t_spar, skins t_skin) from the section FE, in the
    ``box_properties`` row format (cached per distinct cut)."""
    from wingmdao.section.fe import analyse_section, beam_properties_csn, box_mesh, isotropic

    key = tuple(round(float(v), 12) for v in (w, h, t_spar, t_skin)) + (material.name,)
    if key not in _FE_ROWS:
        mat = isotropic(material.E, material.nu, material.rho)
        walls = {"upper": {"thickness": t_skin, "material": mat}, "lower": {"thickness": t_skin, "material": mat},
                 "front": {"thickness": t_spar, "material": mat}, "rear": {"thickness": t_spar, "material": mat}}
        props = beam_properties_csn(analyse_section(box_mesh(w, h, walls, mesh_size=mesh_size, corners="skins")))
        (c_ea, n_ea), (c_sc, n_sc), (c_cg, n_cg) = (props["tension_center_cn"], props["shear_center_cn"],
                                                    props["mass_center_cn"])
        _FE_ROWS[key] = {"stiffness_csn": props["stiffness_csn"], "compliance_csn": props["compliance_csn"],
                         "c_ea": c_ea, "n_ea": n_ea, "c_sc": c_sc, "n_sc": n_sc, "c_cg": c_cg, "n_cg": n_cg,
                         "mass_per_length": props["mass_per_length"], "inertia_per_length": props["inertia_csn"]}
    return _FE_ROWS[key]


def solve_wing_box(name: str, tip_force=(0.0, 0.0, 0.0), tip_moment=(0.0, 0.0, 0.0), gravity=False,
                   t_spar=T_SPAR, t_skin=T_SKIN, elements_per_segment=(6, 8, 6), load_steps=1,
                   section_mapping="normal", walls=None) -> dict:
    """Static response (root clamped at CS1): station displacements, tip displacement/rotation
    (``walls``: per-station wall thicknesses, :func:`wing_box_beam`)."""
    from wingmdao.beam.static import BeamModel

    params, stations = wing_box_beam(name, elements_per_segment, t_spar, t_skin,
                                     section_mapping=section_mapping, walls=walls)
    model = BeamModel(params)
    n = model.num_nodes
    pf, pm = np.zeros((n, 3)), np.zeros((n, 3))
    pf[-1], pm[-1] = tip_force, tip_moment
    forcing = {"point_force": pf, "point_moment": pm}
    if gravity:
        forcing["gravity"] = [0.0, 0.0, -9.81]
    out = model.solve(load_steps=load_steps, **forcing)
    disp = out["r"][stations] - params["node_positions"][stations]
    rot = station_rotations(out["theta"][stations], params["node_euler_angles"][stations])
    return {"geometry": name, **station_summary(disp, rot)}


def station_summary(disp, rot) -> dict:
    """JSON keys of the CS1..CS4 response: displacement magnitudes, vectors and rotations."""
    return {
        "stations": list(STATIONS),
        "displacement": np.linalg.norm(disp, axis=1).tolist(),
        "station_displacement": disp.tolist(),
        "tip_displacement": disp[-1].tolist(),
        "station_rotation": rot.tolist(),
        "tip_rotation": rot[-1].tolist(),
    }


def station_rotations(theta, theta0) -> np.ndarray:
    """Rotation vectors (rad, body axes) taking the jig frames T(theta0) to T(theta): R = T^T T0."""
    from scipy.spatial.transform import Rotation

    from wingmdao.beam.rotations import body_to_csn

    mats = [body_to_csn(t).T @ body_to_csn(t0) for t, t0 in zip(theta, theta0)]
    return Rotation.from_matrix(np.array(mats)).as_rotvec()


def comparison_solver(geometry_name, tip_force, tip_moment, section_mapping="normal") -> dict:
    """Adapter for ``wingmdao.verification.wingbox_solid.compare_with_beam``: beam-axis
    displacement (3, 3) and rotation vectors (3, 3) at CS2, CS3, CS4 (body axes, SI).
    Use ``functools.partial(comparison_solver, section_mapping="rotated")`` for the Eq. F.31 mapping."""
    res = solve_wing_box(geometry_name, tip_force=tip_force, tip_moment=tip_moment,
                         section_mapping=section_mapping)
    return {"displacement": np.asarray(res["station_displacement"])[1:],
            "rotation": np.asarray(res["station_rotation"])[1:]}



# --------------------------------------------------------------------------- OpenMDAO model
#: Eq. 4.57 bounds (m). The skins' upper bound of 1.5 m exceeds the 0.5 m box height of
#: Table D.1 (two skins must leave a web), so it is capped at SKIN_CAP (docs/cases.md).
SKIN_CAP = 0.2
BOUNDS = {"t_front_spar": (0.003, 0.25), "t_rear_spar": (0.003, 0.25),
          "t_upper_skin": (0.003, min(1.5, SKIN_CAP)), "t_lower_skin": (0.003, min(1.5, SKIN_CAP))}
#: Tip loads (body axes, N and N*m). Study 2: the dissertation's drag F_y -> +x, torsion M_x -> +y.
STUDY_LOADS = {1: ((0.0, 0.0, 2.0e6), (0.0, 0.0, 0.0)),
               2: ((1.0e5, 0.0, 2.0e6), (0.0, 1.0e6, 0.0)),
               3: ((1.0e5, 0.0, 2.0e6), (0.0, 1.0e6, 0.0))}
#: --constraints names and the stress families they enable.
CONSTRAINT_GROUPS = {"vm": ("vm",), "ss": ("ss_tension", "ss_compression"), "cent": ("cent_pos", "cent_neg")}


def wing_geometry(name: str, elements_per_segment=(1, 1, 1)):
    """The box as a :class:`wingmdao.sizing.WingGeometry` (beam-normal width/height per node).

    Returns ``(geometry, key_nodes, cos_sweep, cos_dihedral)``: the node indices of CS1..CS4
    and, per node, the factors that take streamwise-cut chordwise/vertical dimensions to the
    normal cut (:func:`streamwise_to_normal`).
    """
    from wingmdao.sizing import WingGeometry

    g = geometry_data(name)
    geo = polyline_beam(section_centres(name), elements_per_segment)
    T = geo.csn_axes()
    s = T[:, 1]
    cos_sweep, cos_dih = np.hypot(s[:, 1], s[:, 2]), np.hypot(s[:, 0], s[:, 1])
    width = geo.interpolate(g["widths"]) * cos_sweep
    height = geo.interpolate(HEIGHTS) * cos_dih
    wg = WingGeometry(node_positions=geo.node_positions, node_euler_angles=geo.node_euler_angles,
                      width=width, height=height, span_coordinate=geo.node_positions[:, 1])
    return wg, geo.key_nodes, cos_sweep, cos_dih


def tip_load_case(name: str, num_nodes: int, tip_force, tip_moment, families, *, time=None,
                  gravity=False, ramp_time=0.0):
    """A :class:`LoadCase` with a tip force/moment (body axes) at the last node.

    ``time=None``: static. Otherwise the load is zero at ``time[0]`` (the static initial state
    is the unloaded jig) and applied suddenly for t > 0 (``ramp_time`` = 0), or raised
    linearly to its full value over ``ramp_time`` seconds, then held constant.
    """
    from wingmdao.groups.load_case import LoadCase

    if not (np.isfinite(ramp_time) and ramp_time >= 0):
        raise ValueError(f"ramp time = {ramp_time} s; allowed range [0, inf) s")
    t = np.zeros(1) if time is None else np.asarray(time, dtype=float)
    if t.size == 1:
        on = np.ones(1)
    elif ramp_time > 0:
        on = np.clip(t / ramp_time, 0.0, 1.0)
    else:
        on = (t > 0.0).astype(float)
    pf = np.zeros((t.size, num_nodes, 3))
    pm = np.zeros((t.size, num_nodes, 3))
    pf[:, -1] = np.outer(on, tip_force)
    pm[:, -1] = np.outer(on, tip_moment)
    forcing = {"point_force": pf, "point_moment": pm}
    if gravity:
        forcing["gravity"] = np.array([0.0, 0.0, -9.81])
    kind = ("static" if t.size == 1 else f"ramped over {ramp_time:g} s, {t[-1]:g} s" if ramp_time > 0
            else f"suddenly applied, {t[-1]:g} s")
    return LoadCase(name, t, forcing, tuple(families), f"tip load {list(tip_force)} N, "
                    f"{list(tip_moment)} N*m ({kind})")


def time_grid(t_final: float, dt: float) -> np.ndarray:
    """Uniform grid 0..t_final (s); ValueError unless 0 < dt <= t_final / 2."""
    if not (np.isfinite(t_final) and np.isfinite(dt) and t_final > 0 and 0 < dt <= t_final / 2):
        raise ValueError(f"--t-final ({t_final} s) and --dt ({dt} s): allowed 0 < dt <= t_final / 2")
    from wingmdao.cases import check_step_count

    check_step_count(t_final, dt)
    return np.arange(0.0, t_final + 0.5 * dt, dt)


def analysis_problem(geometry, load_case, walls: dict, material=ALUMINIUM, *, design_vars=False,
                     rho_ks=100.0, mode="rev", newton_options=None):
    """Set up (not run) the sizing model of one load case plus a von Mises output.

    The chain is :class:`WingSizing` (section, mass, beam, internal loads, stress, KS) with an
    extra :class:`BoxStress` (``output_stresses=True``) on the case's internal loads, whose
    ``vm_stress.sigma_vm`` (nt, n, 8) Pa are the mid-corner von Mises stresses. ``walls`` maps
    the four wall names to per-node thicknesses (m). With ``design_vars`` the thicknesses are
    design variables and the case's KS outputs constraints (for ``check_totals``); ``mode`` is
    OpenMDAO's derivative mode ("rev": one adjoint sweep per KS output, "fwd": one tangent
    sweep per thickness).
    """
    import openmdao.api as om

    from wingmdao.components.stress import BoxStress
    from wingmdao.groups.wing import WingSizing, set_case_loads
    from wingmdao.sizing import WALL_VARS, set_geometry

    n = geometry.num_nodes
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("wing", WingSizing(num_nodes=n, load_cases=[load_case], material=material,
                                                rho_ks=rho_ks, newton_options=newton_options,
                                                add_constraints=design_vars, add_objective=design_vars),
                             promotes=["*"])
    prob.model.add_subsystem("vm_stress", BoxStress(num_times=load_case.num_times, num_stations=n,
                                                    material=material, families=("vm",)),
                             promotes_inputs=["width", "height", *WALL_VARS])
    base = f"cases.{load_case.name}.internal_loads"
    prob.model.connect(f"{base}.F_csn", "vm_stress.F_csn")
    prob.model.connect(f"{base}.M_csn", "vm_stress.M_csn")
    for name in ("width", "height", *WALL_VARS):
        prob.model.set_input_defaults(name, val=np.ones(n), units="m")
    if design_vars:
        for w in WALL_VARS:
            prob.model.add_design_var(w)
    prob.setup(mode=mode)
    set_geometry(prob, geometry)
    set_case_loads(prob, load_case, n, f"cases.{load_case.name}")
    for w in WALL_VARS:
        prob.set_val(w, np.broadcast_to(walls[w], (n,)), units="m")
    return prob


def totals_max_rel_error(prob, load_case) -> float:
    """Largest relative difference between the adjoint totals of the KS outputs w.r.t. the wall
    thicknesses and OpenMDAO's central finite differences (relative to each block's max |J|).

    Step 1e-4 relative to the mean thickness: the truncation error is ~1e-8 and the Newton
    round-off noise (~1e-14 in KS) stays below 1e-9 of the derivatives (1e-6 gives ~5e-6)."""
    from wingmdao.sizing import WALL_VARS

    of = [f"cases.{load_case.name}.ks_{f}" for f in load_case.families]
    data = prob.check_totals(of=of, wrt=list(WALL_VARS), method="fd", form="central", step=1e-4,
                             step_calc="rel_avg", out_stream=None)
    worst = 0.0
    for d in data.values():
        j_ad = d["J_rev"] if "J_rev" in d else d["J_fwd"]
        ref = max(np.abs(d["J_fd"]).max(), 1e-12)
        worst = max(worst, float(np.abs(j_ad - d["J_fd"]).max() / ref))
    return worst


# --------------------------------------------------------------------------- sizing case
def add_arguments(p):
    p.add_argument("--study", type=int, choices=[1, 2, 3], default=1,
                   help="Sec. 4.7.2 study: 1 static Fz = 2 MN (von Mises); 2 static Fx = 0.1 MN, "
                        "Fz = 2 MN, My = 1 MN m (body axes); 3 the study-2 loads applied suddenly (dynamic)")
    p.add_argument("--constraints", default=None,
                   help="comma list of vm, ss (= ss_tension + ss_compression), cent (= cent_pos + "
                        "cent_neg); default: vm for study 1, vm,ss,cent for studies 2 and 3")
    p.add_argument("--geometry", choices=list(GEOMETRIES), default="combined", help="Table D.2 geometry")
    p.add_argument("--elements", type=int, nargs=3, default=(1, 1, 1), metavar=("N1", "N2", "N3"),
                   help="beam elements per segment (design variables at every node; 1 1 1: CS1..CS4)")
    p.add_argument("--t-final", type=float, default=5.0, help="study 3: simulated time [s]")
    p.add_argument("--dt", type=float, default=0.01, help="study 3: time step [s]")
    p.add_argument("--ramp-time", type=float, default=0.25,
                   help="study 3: raise the loads linearly over this time [s]; 0 applies them suddenly at t > 0, "
                        "which no design within the bounds of Eq. 4.57 survives with all constraints (docs/cases.md)")
    p.add_argument("--rho-ks", type=float, default=100.0, help="KS aggregation parameter")


def parse_constraints(text) -> tuple:
    """Stress families of a --constraints list (vm, ss, cent); ValueError listing the valid names."""
    names = [t.strip() for t in str(text).split(",") if t.strip()]
    bad = [t for t in names if t not in CONSTRAINT_GROUPS]
    if bad or not names:
        raise ValueError(f"--constraints: unknown {bad or 'empty list'}; valid: {', '.join(CONSTRAINT_GROUPS)}")
    fams = []
    for t in names:
        fams += [f for f in CONSTRAINT_GROUPS[t] if f not in fams]
    return tuple(fams)


def build(args) -> CaseSetup:
    from wingmdao.sizing import SizingOptions

    default = "vm" if args.study == 1 else "vm,ss,cent"
    families = parse_constraints(args.constraints if args.constraints else default)
    if min(args.elements) < 1:
        raise ValueError(f"--elements = {list(args.elements)}; each must be >= 1")
    from wingmdao.sizing import RHO_KS_MIN

    if args.study not in STUDY_LOADS:
        raise ValueError(f"--study = {args.study!r}; allowed: {', '.join(map(str, STUDY_LOADS))}")
    if not (np.isfinite(args.rho_ks) and args.rho_ks >= RHO_KS_MIN):
        raise ValueError(f"--rho-ks = {args.rho_ks}; allowed range [{RHO_KS_MIN:g}, inf) (KS exceeds the "
                         "maximum stress ratio by up to ln(N)/rho_KS)")
    geometry, _, _, _ = wing_geometry(args.geometry, tuple(args.elements))
    force, moment = STUDY_LOADS[args.study]
    time = time_grid(args.t_final, args.dt) if args.study == 3 else None
    case = tip_load_case(f"study{args.study}", geometry.num_nodes, force, moment, families, time=time,
                         ramp_time=args.ramp_time if args.study == 3 else 0.0)
    options = SizingOptions(lower={w: b[0] for w, b in BOUNDS.items()},
                            upper={w: b[1] for w, b in BOUNDS.items()}, rho_ks=float(args.rho_ks))
    notes = [f"Eq. 4.57 skin upper bound 1.5 m capped at {SKIN_CAP} m (box height 0.5 m)",
             "thickness design variables per beam node, beam-normal cut"]
    if args.study > 1:
        notes.append("dissertation drag F_y = 1e5 N -> +x, torsion M_x = 1e6 N m -> +y (beam along y)")
    return CaseSetup(geometry, [case], ALUMINIUM, options, notes=notes)
