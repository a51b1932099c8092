"""Box, stiffness-matched box and detailed section ("VbS") beams of a wing: a 1 g comparison.

Sec. 4.2.5 compares three beam models of the PEGASUS wing against a shell model (tip
displacement errors 19.45 %, 1.29 % and 0.57 %): the rectangular box of Eq. 4.11-4.12, the box
corrected by stiffness matching (Eq. 4.14), and the beam on the detailed airfoil-wingbox
section. :func:`compare_1g` builds the three beams for a planform case (same wall thicknesses,
same loads: 1 g lift and self weight) and returns their tip displacements; the detailed
section is the reference here (there is no shell model in this repository).
"""

from __future__ import annotations

import numpy as np

from wingmdao.beam.static import BeamModel
from wingmdao.materials import ALUMINIUM
from wingmdao.section.box import beam_data, beam_params_from_section, box_properties
from wingmdao.cases import pegasus
from wingmdao.cases.planform import G0, LB, interpolate_designation, wing_geometry
from wingmdao.loads.maneuver import maneuver_line_loads
from wingmdao.section.fe import airfoil_box_mesh, analyse_section, beam_properties_csn, isotropic, match_box
from wingmdao.section.fe.airfoil import naca_surfaces

WALL_KEYS = ("upper", "lower", "front", "rear")


def _box_params(width, height, walls, material):
    return beam_params_from_section(beam_data(box_properties(width, height, *walls, material), material))


def _detailed_params(designation, chord, front, rear, walls, material):
    """VbS: the FE section's stiffness and mass, offsets measured from the box centre."""
    fe_mat = isotropic(material.E, material.nu, material.rho)
    up, lo = naca_surfaces(designation)
    spec = {k: {"thickness": t, "material": fe_mat} for k, t in zip(WALL_KEYS, walls)}
    props = beam_properties_csn(analyse_section(airfoil_box_mesh(up, lo, chord, front, rear, spec)))
    xs = np.linspace(front, rear, 10)
    ref = np.array([0.5 * (front + rear) * chord, chord * float(np.mean(0.5 * (up(xs) + lo(xs))))])
    shift = lambda key: tuple(np.asarray(props[key], dtype=float) - ref)  # noqa: E731
    return {"stiffness_csn": props["stiffness_csn"], "compliance_csn": props["compliance_csn"],
            "tension_axis": shift("tension_center_cn"), "shear_center": shift("shear_center_cn"),
            "mass_per_length": props["mass_per_length"], "mass_center": shift("mass_center_cn"),
            "inertia_per_length": props["inertia_csn"]}, props


def _stack(per_node):
    keys = per_node[0].keys()
    return {k: np.array([np.asarray(p[k], dtype=float) for p in per_node]) for k in keys}


def compare_1g(case_module=None, walls=(0.004, 0.004, 0.005, 0.004), material=ALUMINIUM):
    """Tip displacement (m, body axes) of the box, matched-box and detailed-section beams at 1 g.

    Returns ``{"box": ..., "matched_box": ..., "detailed": ..., "error_percent": {...},
    "matched_dimensions": [(w, h), ...]}``; errors are of ``|tip displacement|`` against the detailed
    section beam.

    Parameters
    ----------
    case_module : module or None, optional
        Case module; None for PEGASUS.
    walls : tuple of 4 floats, optional
        Wall thicknesses (upper, lower, front, rear) (m).
    material : Material, optional
        Isotropic material.

    Returns
    -------
    dict
        Tip displacements and errors (above).
    """
    mod = case_module or pegasus
    pf = mod.PLANFORM
    geo, chord, axis_frac = wing_geometry(pf)
    n = geo.num_nodes
    y = geo.span_coordinate
    y_sec = np.where(y < pf.root_rib * pf.semi_span, pf.root_rib * pf.semi_span, y)
    frac = (y_sec - y_sec[0]) / (y_sec[-1] - y_sec[0])
    models = {"box": [], "matched_box": [], "detailed": []}
    matched = []
    for k in range(n):
        code = interpolate_designation(pf.airfoil_root, pf.airfoil_tip, frac[k])
        models["box"].append(_box_params(geo.width[k], geo.height[k], walls, material))
        det, props = _detailed_params(code, chord[k], pf.front_spar, pf.rear_spar, walls, material)
        models["detailed"].append(det)
        K = props["stiffness_csn"]
        m = match_box(K[0, 0], K[1, 1], walls, material.E, material.G, geo.width[k], geo.height[k],
                      bounds=((0.3 * geo.width[k], 2 * geo.width[k]), (0.3 * geo.height[k], 2 * geo.height[k])))
        matched.append((m["width"], m["height"]))
        models["matched_box"].append(_box_params(m["width"], m["height"], walls, material))
    loads = maneuver_line_loads(geo.node_positions, chord, axis_frac, mod.TOGW_LB * LB * G0, 1.0,
                                semi_span=pf.semi_span, fuselage_half_width=pf.root_rib * pf.semi_span)
    out = {"matched_dimensions": matched}
    for name, per_node in models.items():
        params = dict(node_positions=geo.node_positions, node_euler_angles=geo.node_euler_angles,
                      **_stack(per_node))
        sol = BeamModel(params).solve(force_per_length=loads.force_per_length,
                                      moment_per_length=loads.moment_per_length,
                                      gravity=np.array([0.0, 0.0, -G0]))
        out[name] = sol["r"][-1] - geo.node_positions[-1]
    ref = np.linalg.norm(out["detailed"])
    out["error_percent"] = {k: 100.0 * (np.linalg.norm(out[k]) - ref) / ref for k in ("box", "matched_box")}
    return out
