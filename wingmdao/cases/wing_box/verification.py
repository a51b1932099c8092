"""Plain beam solves of the App. D.1 box for the comparison with the solid models (App. E.3).

Section properties are those of the beam-normal cut
(:func:`wingmdao.beam.geometry.streamwise_to_normal`), so ``section_to_csn`` is the identity
(docs/beam-theory.md, 'Streamwise and normal sections'); :func:`comparison_solver` is the
beam side of :func:`wingmdao.verification.wingbox_solid.compare_with_beam`.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from wingmdao.beam.geometry import polyline_beam, streamwise_section_to_csn, streamwise_to_normal
from wingmdao.cases.wing_box.geometry import HEIGHTS, STATIONS, T_SKIN, T_SPAR, geometry_data, section_centres
from wingmdao.materials import ALUMINIUM
from wingmdao.section.box import WALL_NAMES, beam_params_from_rows, box_properties
from wingmdao.beam.rotations import body_to_csn
from wingmdao.section.fe import analyse_section, beam_properties_csn, box_mesh, isotropic
from wingmdao.beam.static import BeamModel


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

    Parameters
    ----------
    name : str
        Table D.2 geometry.
    elements_per_segment : sequence of 3 int, optional
        Beam elements in each of the three segments.
    t_spar : float, optional
        Uniform spar-web thickness (m).
    t_skin : float, optional
        Uniform skin thickness (m).
    material : wingmdao.materials.Material, optional
        Wall material.
    section_mapping : str, optional
        ``"normal"``, ``"rotated"`` or ``"fe"`` (above).
    walls : dict, optional
        Wall thicknesses (m) per station (above); None: ``t_spar`` / ``t_skin``.

    Returns
    -------
    params : dict
        The beam parameters (SI).
    stations : ndarray
        Node index of each station CS1..CS4.
    """
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
    node_walls = None if walls is None else {k: geo.interpolate(walls[k]) for k in WALL_NAMES}
    for i in range(geo.num_nodes):
        if node_walls is not None:
            w, h = streamwise_to_normal(width[i], height[i], t_spar, t_skin, T[i, 1])[:2]
            rows.append(box_properties(w, h, *(node_walls[k][i] for k in WALL_NAMES), material))
        elif section_mapping == "fe":
            rows.append(_fe_box_row(*streamwise_to_normal(width[i], height[i], t_spar, t_skin, T[i, 1]), material))
        elif section_mapping == "normal":
            w, h, ts, tk = streamwise_to_normal(width[i], height[i], t_spar, t_skin, T[i, 1])
            rows.append(box_properties(w, h, tk, tk, ts, ts, material))
        else:
            rows.append(box_properties(width[i], height[i], t_skin, t_skin, t_spar, t_spar, material,
                                       section_to_csn=R[i]))
    params = beam_params_from_rows(rows, geo.node_positions, geo.node_euler_angles)
    return params, geo.key_nodes


_FE_ROWS: dict = {}


def _fe_box_row(w, h, t_spar, t_skin, material, mesh_size=0.05):
    """Beam data of a w x h box (spars t_spar, skins t_skin) from the section FE, in the
    ``box_properties`` row format (cached per distinct cut)."""
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
    """Static response of the box, root clamped at CS1.

    Parameters
    ----------
    name : str
        Table D.2 geometry.
    tip_force : sequence of 3 float, optional
        Tip force (N), body axes.
    tip_moment : sequence of 3 float, optional
        Tip moment (N m), body axes.
    gravity : bool, optional
        Add the self weight (9.81 m/s^2 along -z).
    t_spar : float, optional
        Uniform spar-web thickness (m).
    t_skin : float, optional
        Uniform skin thickness (m).
    elements_per_segment : sequence of 3 int, optional
        Beam elements in each of the three segments.
    load_steps : int, optional
        Load increments of the Newton solve.
    section_mapping : str, optional
        ``"normal"``, ``"rotated"`` or ``"fe"`` (:func:`wing_box_beam`).
    walls : dict, optional
        Wall thicknesses (m) per station (:func:`wing_box_beam`).

    Returns
    -------
    dict
        ``geometry`` and the station response (:func:`station_summary`: m and rad).
    """
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
    """JSON keys of the CS1..CS4 response.

    Parameters
    ----------
    disp : ndarray
        (4, 3) station displacements (m), body axes.
    rot : ndarray
        (4, 3) station rotation vectors (rad), body axes.

    Returns
    -------
    dict
        Displacement magnitudes and vectors, tip displacement, rotations and tip rotation.
    """
    return {
        "stations": list(STATIONS),
        "displacement": np.linalg.norm(disp, axis=1).tolist(),
        "station_displacement": disp.tolist(),
        "tip_displacement": disp[-1].tolist(),
        "station_rotation": rot.tolist(),
        "tip_rotation": rot[-1].tolist(),
    }


def station_rotations(theta, theta0) -> np.ndarray:
    """Rotation vectors taking the jig frames T(theta0) to T(theta): R = T^T T0.

    Parameters
    ----------
    theta : ndarray
        (k, 3) deformed Euler angles (rad).
    theta0 : ndarray
        (k, 3) jig Euler angles (rad).

    Returns
    -------
    ndarray
        (k, 3) rotation vectors (rad), body axes.
    """
    mats = [body_to_csn(t).T @ body_to_csn(t0) for t, t0 in zip(theta, theta0)]
    return Rotation.from_matrix(np.array(mats)).as_rotvec()


def comparison_solver(geometry_name, tip_force, tip_moment, section_mapping="normal") -> dict:
    """Adapter for ``wingmdao.verification.wingbox_solid.compare_with_beam``: beam-axis
    displacement (3, 3) and rotation vectors (3, 3) at CS2, CS3, CS4 (body axes, SI).
    Use ``functools.partial(comparison_solver, section_mapping="rotated")`` for the Eq. F.31 mapping.

    Parameters
    ----------
    geometry_name : str
        Table D.2 geometry.
    tip_force : sequence of 3 float
        Tip force (N), body axes.
    tip_moment : sequence of 3 float
        Tip moment (N m), body axes.
    section_mapping : str, optional
        ``"normal"``, ``"rotated"`` or ``"fe"`` (:func:`wing_box_beam`).

    Returns
    -------
    dict
        ``displacement`` (3, 3) m and ``rotation`` (3, 3) rad at CS2, CS3, CS4.
    """
    res = solve_wing_box(geometry_name, tip_force=tip_force, tip_moment=tip_moment,
                         section_mapping=section_mapping)
    return {"displacement": np.asarray(res["station_displacement"])[1:],
            "rotation": np.asarray(res["station_rotation"])[1:]}
