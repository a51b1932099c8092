"""The 'wing-like' box beam of App. D.1 / E.3 (Tables D.1, D.2, E.2), as beam data.

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

Usage: ``python cases/wing_box.py combined`` prints the static response to a 100 kN tip load.
"""

from __future__ import annotations

import sys

import numpy as np

from wingmdao.beam.geometry import polyline_beam, streamwise_to_normal, swept_dihedral_points
from wingmdao.materials import ALUMINIUM

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
                  material=ALUMINIUM, section_mapping="normal") -> tuple[dict, np.ndarray]:
    """Beam parameters (``param_specs`` names) of the box and the node index of each station.

    ``section_mapping``: 'normal' (default) takes the box properties of the beam-normal cut;
    'rotated' those of the streamwise cut rotated into csn (Eq. F.31, docs/beam-theory.md 9).
    """
    from wingmdao.beam.geometry import streamwise_section_to_csn
    from wingmdao.section.box import box_properties

    if section_mapping not in ("normal", "rotated"):
        raise ValueError(f"section_mapping must be 'normal' or 'rotated', got {section_mapping!r}")

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
    for i in range(geo.num_nodes):
        if section_mapping == "normal":
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


def solve_wing_box(name: str, tip_force=(0.0, 0.0, 0.0), tip_moment=(0.0, 0.0, 0.0), gravity=False,
                   t_spar=T_SPAR, t_skin=T_SKIN, elements_per_segment=(6, 8, 6), load_steps=1,
                   section_mapping="normal") -> dict:
    """Static response (root clamped at CS1): station displacements, tip displacement/rotation."""
    from wingmdao.beam.static import BeamModel

    params, stations = wing_box_beam(name, elements_per_segment, t_spar, t_skin,
                                     section_mapping=section_mapping)
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
    return {
        "geometry": name,
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


if __name__ == "__main__":
    name = sys.argv[1] if len(sys.argv) > 1 else "combined"
    print(solve_wing_box(name, tip_force=(0.0, 0.0, 1.0e5)))
