"""What a stress office reads of a stiffened sizing: panel dimensions, critical mode and margin
of safety per station and wall, and the mass by part (docs/panels.md)."""

from __future__ import annotations

import numpy as np

from wingmdao.stress.box_stress import SECTION_PROPERTIES, panel_running_loads
from wingmdao.panels.layout import (cover_kinks, panel_families, rib_crushing_ratio, rib_shear_ratio, rib_web_ratio,
                                   smeared_stringer)

#: the walls of the result JSON, with their panel points in PanelFailure (skin points 0-3: upper
#: front, upper rear, lower front, lower rear; web points 0-1: front, rear) and their von Mises
#: points in BoxStress (mid-corners: skin then spar at front-lower, rear-lower, rear-upper, front-upper)
WALL_POINTS = {
    "upper_skin": {"skin": (0, 1), "vm": (4, 6), "laminate": (0, 1)},
    "lower_skin": {"skin": (2, 3), "vm": (0, 2), "laminate": (2, 3)},
    "front_spar": {"web": (0,), "vm": (1, 7), "laminate": (4,)},
    "rear_spar": {"web": (1,), "vm": (3, 5), "laminate": (5,)},
}
SKIN_MODES = ("skin_buckling", "panel_buckling", "stiffener_column", "stiffener_crippling")


def _station_values(prob, name):
    try:
        return np.asarray(prob.get_val(f"{name}_station", units="m"))
    except KeyError:
        return np.asarray(prob.get_val(name, units="m"))


def worst_ratios(prob, load_cases, panels) -> dict:
    """{wall: {mode: (n,) largest factored failure ratio over every case and time step}}: for the
    panel modes safety_factor * R (= g + 1), for ``material`` sigma_vm / sigma_y (= g_vm + 1).

    Parameters
    ----------
    prob : openmdao.api.Problem
        A run stiffened sizing problem.
    load_cases : sequence of LoadCase
        The sizing's load cases.
    panels : PanelLayout
        The sizing's panel layout.

    Returns
    -------
    dict
        Wall -> mode -> (n,) largest factored ratio over the cases and steps (-).
    """
    out = {wall: {} for wall in WALL_POINTS}
    for case in load_cases:
        path = f"cases.{case.name}"
        g = {f: np.asarray(prob.get_val(f"{path}.panels.g_{f}")) for f in panel_families(panels.laminate)}
        vm = np.asarray(prob.get_val(f"{path}.stress.g_vm")) if "vm" in case.families else None
        lam = g.get("laminate_strength")
        for wall, pts in WALL_POINTS.items():
            modes = {}
            if "skin" in pts:
                for f in SKIN_MODES:
                    modes[f] = g[f][:, :, list(pts["skin"])].max(axis=(0, 2)) + 1.0
            else:
                modes["web_buckling"] = g["web_buckling"][:, :, list(pts["web"])].max(axis=(0, 2)) + 1.0
            if lam is not None:   # Tsai-Wu of the laminate (factored like the panel modes)
                modes["material"] = lam[:, :, list(pts["laminate"])].max(axis=(0, 2)) + 1.0
            elif vm is not None:
                modes["material"] = vm[:, :, list(pts["vm"])].max(axis=(0, 2)) + 1.0
            for f, r in modes.items():
                out[wall][f] = np.maximum(out[wall][f], r) if f in out[wall] else r
    return out


def panel_summary(prob, load_cases, panels) -> dict:
    """The ``panels`` block of the result JSON: per wall, lists along the stations of
    ``skin_thickness_m``, ``stiffener_height_m``, ``stiffener_thickness_m``, ``stiffener_pitch_m``
    (None on the unstiffened spar webs), ``equivalent_thickness_m`` (area per width),
    ``critical_mode`` and ``margin_of_safety`` = 1 / (largest factored ratio) - 1.

    Parameters
    ----------
    prob : openmdao.api.Problem
        A run stiffened sizing problem.
    load_cases : sequence of LoadCase
        The sizing's load cases.
    panels : PanelLayout
        The sizing's panel layout.

    Returns
    -------
    dict
        Wall -> JSON-ready lists along the stations.
    """
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


def mass_breakdown(prob, geometry, panels, rib_mass=None) -> dict:
    """``mass_breakdown_kg``: ``skins``, ``spars``, ``stiffeners``, ``ribs``; they sum to the
    structural mass. The box mass (frustum volumes of the total area, App. F.1) is split among
    skins, spars and stiffeners in proportion to the trapezoid-rule volumes of their areas;
    ``rib_mass`` (kg): the sized ribs' (default: the model's ``rib_mass``).

    Parameters
    ----------
    prob : openmdao.api.Problem
        A run stiffened sizing problem.
    geometry : WingGeometry
        The sizing's wing geometry.
    panels : PanelLayout
        The sizing's panel layout.
    rib_mass : float or None, optional
        Mass of the sized ribs (kg); None takes the model's ``rib_mass``.

    Returns
    -------
    dict
        ``skins``, ``spars``, ``stiffeners``, ``ribs`` masses (kg).
    """
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
    out["ribs"] = float(prob.get_val("rib_mass", units="kg")[0]) if rib_mass is None else float(rib_mass)
    return out


def _per_node(prob, name, geometry):
    v = np.asarray(prob.get_val(name, units="m"))
    smap = geometry.station_map
    return v if smap is None else v[np.asarray(smap)]


def rib_summary(prob, load_cases, panels, geometry, material) -> dict:
    """The ``ribs`` block of the result JSON, with the ribs sized for their web's buckling: per
    rib its position (m), its thickness (m: the layout's minimum, or thicker where the loads need
    it, safety_factor * ratio = 1), its largest combined ratio over every load case and time
    step at that thickness (``web_ratio``, :func:`wingmdao.panels.layout.rib_web_ratio` of the
    crushing and shear ratios, both given too, unfactored) and the margin of safety
    1 / (safety_factor ratio) - 1; ``mass_kg`` of the sized ribs. The walls' sizing does not
    depend on the ribs (the beam carries neither their stiffness nor their mass), so sizing them
    after the walls is exact for this model. Loads of a rib (docs/panels.md, "Ribs"):

    * crushing (:func:`~wingmdao.panels.layout.rib_crushing_ratio`): the covers' curvature load
      |N kappa| s, N = M_c (n_upper - n_ea) t_eq / Ixx on the upper cover, kappa = M_c / (E Ixx),
      s the mean of the two bays beside the rib, plus the larger of the two covers' kink loads;
    * kinks: where the box height's slope changes at the rib (:func:`~wingmdao.panels.layout.cover_kinks`)
      each cover turns by half that change and presses on the rib with N_cover x turn per unit
      chord (upper and lower: f_u = N_u dh'/2, f_l = -N_l dh'/2, upward positive);
    * shear (:func:`~wingmdao.panels.layout.rib_shear_ratio`): the rib delivers to each spar half
      of the kinks' net vertical load |f_u + f_l| w / 2 plus half the net load of its bays,
      |dF_n/ds| s / 2 (all of the air and inertia load of the bay taken through the rib).

    Parameters
    ----------
    prob : openmdao.api.Problem
        A run stiffened sizing problem.
    load_cases : sequence of LoadCase
        The sizing's load cases.
    panels : PanelLayout
        The sizing's panel layout.
    geometry : WingGeometry
        The sizing's wing geometry.
    material : Material
        The sizing's material.

    Returns
    -------
    dict
        The JSON-ready ``ribs`` block.
    """
    y = geometry.span_coordinate if geometry.span_coordinate is not None else geometry.node_positions[:, 1]
    y = np.asarray(y, dtype=float)
    ribs = np.array([r for r in panels.rib_positions if r >= 0.0])
    all_ribs = np.asarray(panels.rib_positions, dtype=float)
    gaps = np.diff(all_ribs)
    idx = np.searchsorted(all_ribs, ribs)
    spacing = np.array([0.5 * ((gaps[i - 1] if i > 0 else gaps[i]) + (gaps[i] if i < gaps.size else gaps[i - 1]))
                        for i in idx])
    height = np.asarray(prob.get_val("height", units="m"))
    w = np.interp(ribs, y, np.asarray(prob.get_val("width", units="m")))
    h = np.interp(ribs, y, height)
    kink = cover_kinks(y, height, ribs)
    t_eq, t_skin = [], []
    for side in ("upper", "lower"):
        t_s = np.interp(ribs, y, _per_node(prob, f"t_{side}_skin", geometry))
        a_s = smeared_stringer(_per_node(prob, f"h_{side}_stiffener", geometry),
                               _per_node(prob, f"t_{side}_stiffener", geometry),
                               panels.stiffener_pitch, panels.shape, panels.flange_ratio)[0]
        t_skin.append(t_s)
        t_eq.append(t_s + np.interp(ribs, y, a_s))
    i_xx = np.interp(ribs, y, np.asarray(prob.get_val("Ixx")))
    n_ea = np.interp(ribs, y, np.asarray(prob.get_val("n_ea")))
    lever_u = 0.5 * h - 0.5 * t_skin[0] - n_ea
    lever_l = -(0.5 * h - 0.5 * t_skin[1]) - n_ea
    e_skin = panels.wall_factors(material)[0]
    rib_E, rib_nu, rib_rho = panels.rib_material(material)
    t0 = panels.rib_thickness
    depth = h - 2 * t_skin[0]
    worst = {k: np.zeros(ribs.size) for k in ("web", "crushing", "shear")}
    for case in load_cases:
        m = np.asarray(prob.get_val(f"cases.{case.name}.{case.loads_path}.M_csn"))[..., 0]   # (nt, n) M_c
        m_rib = np.array([np.interp(ribs, y, row) for row in m.reshape(-1, y.size)])
        dfn = np.asarray(prob.get_val(f"cases.{case.name}.load_gradient.dF_csn_ds"))[..., 2]
        p_rib = np.array([np.interp(ribs, y, row) for row in dfn.reshape(-1, y.size)])
        n_u = -e_skin * m_rib * lever_u * t_eq[0] / i_xx          # cover running loads, tension positive
        n_l = -e_skin * m_rib * lever_l * t_eq[1] / i_xx
        f_u, f_l = n_u * 0.5 * kink, -n_l * 0.5 * kink
        kappa = m_rib / (material.E * i_xx)
        crush = rib_crushing_ratio(rib_E, rib_nu, t0, depth, w, n_u, kappa, spacing,
                                   extra_load=np.maximum(np.abs(f_u), np.abs(f_l)))
        shear = rib_shear_ratio(rib_E, rib_nu, t0, depth, w,
                                np.abs(f_u + f_l) * 0.5 * w + np.abs(p_rib) * 0.5 * spacing)
        web = rib_web_ratio(crush, shear)
        worst["web"] = np.maximum(worst["web"], web.max(axis=0))
        worst["crushing"] = np.maximum(worst["crushing"], crush.max(axis=0))
        worst["shear"] = np.maximum(worst["shear"], shear.max(axis=0))
    # every ratio scales with t_rib^-3 (stress ~ 1/t, critical stress ~ t^2): the thickness at
    # which safety_factor * ratio = 1, never below the layout's minimum rib thickness
    sized = np.maximum(t0, t0 * np.cbrt(panels.safety_factor * worst["web"]))
    scale = (t0 / sized) ** 3
    ratio = worst["web"] * scale
    mass = float(rib_rho * np.sum(sized * w * h))
    return {"positions_m": ribs.tolist(), "minimum_thickness_m": t0, "thickness_m": sized.tolist(),
            "web_ratio": ratio.tolist(), "crushing_ratio": (worst["crushing"] * scale).tolist(),
            "shear_ratio": (worst["shear"] * scale).tolist(), "cover_kink": kink.tolist(),
            "margin_of_safety": (1.0 / np.maximum(panels.safety_factor * ratio, 1e-300) - 1.0).tolist(),
            "mass_kg": mass}


def model_running_loads(prob, case_name, panels, time_index=0) -> dict:
    """The sizing model's running loads (N/m, compression negative) of the skins at every
    station of a load case, as the panel modes take them
    (:func:`wingmdao.stress.box_stress.panel_running_loads`): per skin (``upper``, ``lower``)
    lists along the stations of ``n_span_front``, ``n_span_rear`` (skin plus smeared
    stiffeners), ``n_shear_front``, ``n_shear_rear`` (the edge shear flows) and ``n_chord``
    (mid-chord). ``prob``: a run stiffened sizing problem; ``time_index``: the step of the case.
    Walls of the sizing's own material (the transformed-section wall factors are not applied).

    Parameters
    ----------
    prob : openmdao.api.Problem
        A run stiffened sizing problem.
    case_name : str
        Name of the load case.
    panels : PanelLayout
        The sizing's panel layout.
    time_index : int, optional
        Time step of the case.

    Returns
    -------
    dict
        ``upper`` and ``lower`` -> running-load name -> list along the stations (N/m).
    """
    path = f"cases.{case_name}.panels."
    val = {}
    for name in ("F_csn", "M_csn", "dF_csn_ds"):
        val[name] = np.asarray(prob.get_val(path + name))[time_index]
    station = {}
    for name in ("width", "height", "t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar",
                 "h_upper_stiffener", "t_upper_stiffener", "h_lower_stiffener", "t_lower_stiffener",
                 *SECTION_PROPERTIES):
        station[name] = np.asarray(prob.get_val(path + name)).reshape(-1)
    n = val["F_csn"].shape[0]
    out = {s: {k: [] for k in ("n_span_front", "n_span_rear", "n_shear_front", "n_shear_rear", "n_chord")}
           for s in ("upper", "lower")}
    for i in range(n):
        st = {k: v[i] if v.size == n else v[0] for k, v in station.items()}
        walls = [st[k] for k in ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")]
        t_ax = [walls[k] + smeared_stringer(st[f"h_{s}_stiffener"], st[f"t_{s}_stiffener"], panels.stiffener_pitch,
                                            panels.shape, panels.flange_ratio)[0]
                for k, s in enumerate(("upper", "lower"))]
        loads = panel_running_loads(val["F_csn"][i], val["M_csn"][i], st["width"], st["height"], *walls, t_ax,
                                    {k: st[k] for k in SECTION_PROPERTIES}, force_gradient=val["dF_csn_ds"][i])
        for k, s in enumerate(("upper", "lower")):
            o = out[s]
            o["n_span_front"].append(float(loads["nx_skin"][2 * k]))
            o["n_span_rear"].append(float(loads["nx_skin"][2 * k + 1]))
            o["n_shear_front"].append(float(loads["nxy_skin"][2 * k]))
            o["n_shear_rear"].append(float(loads["nxy_skin"][2 * k + 1]))
            o["n_chord"].append(float(loads["ny_skin"][2 * k]))
    return out
