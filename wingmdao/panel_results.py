"""What a stress office reads of a stiffened sizing: panel dimensions, critical mode and margin
of safety per station and wall, and the mass by part (docs/panels.md)."""

from __future__ import annotations

import numpy as np

from wingmdao.panels.layout import PANEL_FAMILIES, smeared_stringer
from wingmdao.section.box import WALL_NAMES

#: the walls of the result JSON, with their panel points in PanelFailure (skin points 0-3: upper
#: front, upper rear, lower front, lower rear; web points 0-1: front, rear) and their von Mises
#: points in BoxStress (mid-corners: skin then spar at front-lower, rear-lower, rear-upper, front-upper)
WALL_POINTS = {
    "upper_skin": {"skin": (0, 1), "vm": (4, 6)},
    "lower_skin": {"skin": (2, 3), "vm": (0, 2)},
    "front_spar": {"web": (0,), "vm": (1, 7)},
    "rear_spar": {"web": (1,), "vm": (3, 5)},
}
SKIN_MODES = ("skin_buckling", "panel_buckling", "stiffener_column", "stiffener_crippling")


def _station_values(prob, name):
    try:
        return np.asarray(prob.get_val(f"{name}_station", units="m"))
    except KeyError:
        return np.asarray(prob.get_val(name, units="m"))


def worst_ratios(prob, load_cases, panels) -> dict:
    """{wall: {mode: (n,) largest factored failure ratio over every case and time step}}: for the
    panel modes safety_factor * R (= g + 1), for ``material`` sigma_vm / sigma_y (= g_vm + 1)."""
    out = {wall: {} for wall in WALL_POINTS}
    for case in load_cases:
        path = f"cases.{case.name}"
        g = {f: np.asarray(prob.get_val(f"{path}.panels.g_{f}")) for f in PANEL_FAMILIES}
        vm = np.asarray(prob.get_val(f"{path}.stress.g_vm")) if "vm" in case.families else None
        for wall, pts in WALL_POINTS.items():
            modes = {}
            if "skin" in pts:
                for f in SKIN_MODES:
                    modes[f] = g[f][:, :, list(pts["skin"])].max(axis=(0, 2)) + 1.0
            else:
                modes["web_buckling"] = g["web_buckling"][:, :, list(pts["web"])].max(axis=(0, 2)) + 1.0
            if vm is not None:
                modes["material"] = vm[:, :, list(pts["vm"])].max(axis=(0, 2)) + 1.0
            for f, r in modes.items():
                out[wall][f] = np.maximum(out[wall][f], r) if f in out[wall] else r
    return out


def panel_summary(prob, load_cases, panels) -> dict:
    """The ``panels`` block of the result JSON: per wall, lists along the stations of
    ``skin_thickness_m``, ``stiffener_height_m``, ``stiffener_thickness_m``, ``stiffener_pitch_m``
    (None on the unstiffened spar webs), ``equivalent_thickness_m`` (area per width),
    ``critical_mode`` and ``margin_of_safety`` = 1 / (largest factored ratio) - 1."""
    ratios = worst_ratios(prob, load_cases, panels)
    out = {}
    for wall in WALL_POINTS:
        t = _station_values(prob, f"t_{wall}")
        n = t.size
        block = {"skin_thickness_m": t.tolist()}
        if wall.endswith("skin"):
            side = wall.split("_")[0]
            h, ts = _station_values(prob, f"h_{side}_stiffener"), _station_values(prob, f"t_{side}_stiffener")
            a, _, _ = smeared_stringer(h, ts, panels.stiffener_pitch, panels.shape, panels.flange_ratio)
            block.update(stiffener_height_m=h.tolist(), stiffener_thickness_m=ts.tolist(),
                         stiffener_pitch_m=[panels.stiffener_pitch] * n, equivalent_thickness_m=(t + a).tolist())
        else:
            block.update(stiffener_height_m=[None] * n, stiffener_thickness_m=[None] * n,
                         stiffener_pitch_m=[None] * n, equivalent_thickness_m=t.tolist())
        modes = ratios[wall]
        names = list(modes)
        stack = np.array([modes[m] for m in names])
        worst = np.argmax(stack, axis=0)
        block["critical_mode"] = [names[k] for k in worst]
        block["margin_of_safety"] = (1.0 / stack.max(axis=0) - 1.0).tolist()
        block["factored_ratio"] = {m: modes[m].tolist() for m in names}
        out[wall] = block
    return out


def _trapezoid(area, node_positions):
    s = np.linalg.norm(np.diff(np.asarray(node_positions, dtype=float), axis=0), axis=1)
    return float(np.sum(0.5 * s * (area[:-1] + area[1:])))


def mass_breakdown(prob, geometry, panels) -> dict:
    """``mass_breakdown_kg``: ``skins``, ``spars``, ``stiffeners``, ``ribs``; they sum to the
    structural mass. The box mass (frustum volumes of the total area, App. F.1) is split among
    skins, spars and stiffeners in proportion to the trapezoid-rule volumes of their areas."""
    w = np.asarray(prob.get_val("width", units="m"))
    h = np.asarray(prob.get_val("height", units="m"))
    n = w.size
    t = {wall: np.broadcast_to(_per_node(prob, f"t_{wall}", geometry), (n,)) for wall in WALL_POINTS}
    a = [smeared_stringer(_per_node(prob, f"h_{s}_stiffener", geometry), _per_node(prob, f"t_{s}_stiffener", geometry),
                          panels.stiffener_pitch, panels.shape, panels.flange_ratio)[0] for s in ("upper", "lower")]
    parts = {"skins": w * (t["upper_skin"] + t["lower_skin"]),
             "spars": (h - t["upper_skin"] - t["lower_skin"]) * (t["front_spar"] + t["rear_spar"]),
             "stiffeners": w * (a[0] + a[1])}
    vols = {k: _trapezoid(v, geometry.node_positions) for k, v in parts.items()}
    box = float(prob.get_val("box_mass", units="kg")[0])
    total_vol = sum(vols.values())
    out = {k: box * v / total_vol for k, v in vols.items()}
    out["ribs"] = float(prob.get_val("rib_mass", units="kg")[0])
    return out


def _per_node(prob, name, geometry):
    v = np.asarray(prob.get_val(name, units="m"))
    smap = geometry.station_map
    return v if smap is None else v[np.asarray(smap)]
