"""The failure ratios of a wingbox wall's panel, as the stiffened sizing uses them.

A skin panel is the skin between two ribs (length = rib pitch) with its stiffeners at the
layout's pitch; a spar web is an unstiffened plate as wide as the web height between the skins.
Both go through :func:`wingmdao.panels.stiffened.panel_failure_ratios` (docs/panels.md), with
running loads from :func:`wingmdao.stress.box_stress.panel_running_loads`.
"""

from __future__ import annotations

from functools import cache

from wingmdao.panels import buckling as bk
from wingmdao.panels.stiffened import (PanelMaterial, panel_critical_loads, panel_failure_ratios, panel_material,
                                       skin_width_from_pitch, smeared_properties)

#: the skin panel's modes the sizing constrains (material strength is the box's von Mises family)
SKIN_MODES = ("skin_buckling", "panel_buckling", "stiffener_column", "stiffener_crippling")


@cache
def _panel_material(material):
    """A PanelMaterial as it is, an isotropic Material wrapped."""
    return material if isinstance(material, PanelMaterial) else panel_material(material)


def skin_panel_ratios(material, t, h, ts, pitch, length, nx, nxy, shape="blade", flange_ratio=1.0, ny=None) -> dict:
    """{mode: ratio} of :data:`SKIN_MODES` for a stiffened skin: thickness ``t``, stiffeners
    ``h`` x ``ts`` at ``pitch``, panel ``length`` (m), running loads ``nx``, ``nxy`` (N/m,
    compression negative). Each ratio is load-linear, 1 = failure at these loads.

    ``ny``: the skin's chordwise running load (N/m, compression negative; the stiffeners carry
    none of it). With it, ``skin_buckling`` is the skin between stiffeners under N_x, N_y and
    N_xy (:func:`~wingmdao.panels.buckling.biaxial_interaction_ratio`), N_y,cr the same b x a
    bay loaded on its long edges (:func:`transverse_skin_critical_load`), and ``panel_buckling``
    the stiffened panel between ribs under the same three loads, N_y,cr of
    :func:`transverse_panel_critical_load`.

    Parameters
    ----------
    material : str, Material, PlyMaterial or PanelMaterial
        Panel material (a name or material as :func:`~wingmdao.panels.stiffened.panel_material` takes).
    t : float, array_like or casadi.SX
        Skin thickness (m).
    h : float, array_like or casadi.SX
        Stiffener web height (m).
    ts : float, array_like or casadi.SX
        Stiffener thickness (m).
    pitch : float
        Stiffener pitch (m).
    length : float, array_like or casadi.SX
        Panel length between ribs (m).
    nx : float, array_like or casadi.SX
        Running load along the stiffeners (N/m, compression negative).
    nxy : float, array_like or casadi.SX
        Shear flow (N/m).
    shape : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-; ignored for blades).
    ny : float, array_like, casadi.SX or None, optional
        Skin running load across the stiffeners (N/m, compression negative); None for none.

    Returns
    -------
    dict
        Strength ratio (-) of each mode of :data:`SKIN_MODES`.
    """
    pm = _panel_material(material)
    b = skin_width_from_pitch(pitch, h, shape, flange_ratio)
    crit = panel_critical_loads(pm, t, b, length, h, ts, shape, flange_ratio)
    r = panel_failure_ratios(pm, t, b, length, h, ts, nx, nxy, shape, flange_ratio, critical=crit)
    if ny is not None:
        r["skin_buckling"] = bk.biaxial_interaction_ratio(nx, ny, nxy, crit["skin_compression"],
                                                          transverse_skin_critical_load(pm, t, b, length),
                                                          crit["skin_shear"])
        r["panel_buckling"] = bk.biaxial_interaction_ratio(
            nx, ny, nxy, crit["panel_compression"],
            transverse_panel_critical_load(pm, t, b, length, h, ts, shape, flange_ratio), crit["panel_shear"])
    return {mode: r[mode] for mode in SKIN_MODES}


def transverse_panel_critical_load(material, t, b, length, h, ts, shape="blade", flange_ratio=1.0):
    """N_y,cr (N/m) of the stiffened panel between two ribs ``length`` apart compressed across
    the stiffeners, the skin and stiffeners buckling together: the smeared orthotropic plate
    (D_x of the stiffened section along the stiffeners, the skin's D22, D12, D66) as an
    infinitely long strip of width ``length`` loaded along its length,
    2 pi^2 / length^2 (sqrt(D_x D22) + D12 + 2 D66) (:func:`~wingmdao.panels.buckling.plate_compression_long`,
    Kassapoglou Sec. 6.2; the long-plate limit is the lowest over the panel's chordwise extent,
    so the spars' support is not counted). The stiffeners raise it through D_x only: thin
    blades leave it below the skin bay's :func:`transverse_skin_critical_load`.

    Parameters
    ----------
    material : str, Material, PlyMaterial or PanelMaterial
        Panel material.
    t : float, array_like or casadi.SX
        Skin thickness (m).
    b : float, array_like or casadi.SX
        Skin width between stiffeners (m).
    length : float, array_like or casadi.SX
        Rib pitch (m).
    h : float, array_like or casadi.SX
        Stiffener web height (m).
    ts : float, array_like or casadi.SX
        Stiffener thickness (m).
    shape : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-).

    Returns
    -------
    float, array_like or casadi.SX
        Critical running load N_y,cr (N/m, positive).
    """
    pm = _panel_material(material)
    d = pm.abd(t)
    dx = smeared_properties(t, b, h, ts, shape, flange_ratio, pm.E_x)["EI_per_width"]
    return bk.plate_compression_long(dx, d["D22"], d["D12"], d["D66"], length)


def transverse_skin_critical_load(material, t, b, length):
    """N_y,cr (N/m) of the skin between stiffeners (``b`` wide, ``length`` between ribs, simply
    supported) compressed across the stiffeners, i.e. on its long edges:
    :func:`~wingmdao.panels.buckling.plate_compression_ss` with the axes swapped (load along
    y over the length b, loaded edges ``length`` long). Isotropic:
    k pi^2 D / b^2 with k = (1 + (b / length)^2)^2 (one half-wave; Timoshenko & Gere Sec. 9.2).

    Parameters
    ----------
    material : str, Material, PlyMaterial or PanelMaterial
        Panel material.
    t : float, array_like or casadi.SX
        Skin thickness (m).
    b : float, array_like or casadi.SX
        Skin width between stiffeners (m).
    length : float, array_like or casadi.SX
        Rib pitch (m).

    Returns
    -------
    float, array_like or casadi.SX
        Critical running load N_y,cr (N/m, positive).
    """
    d = _panel_material(material).abd(t)
    return bk.plate_compression_ss(d["D22"], d["D11"], d["D12"], d["D66"], b, length)


def web_panel_ratio(material, t, b, length, nx, nxy):
    """Combined compression-shear buckling ratio of an unstiffened spar web of thickness ``t``
    and height ``b`` between ribs ``length`` apart (m) under ``nx``, ``nxy`` (N/m).

    Parameters
    ----------
    material : str, Material, PlyMaterial or PanelMaterial
        Web material.
    t : float, array_like or casadi.SX
        Web thickness (m).
    b : float, array_like or casadi.SX
        Web height (m).
    length : float, array_like or casadi.SX
        Rib pitch (m).
    nx : float, array_like or casadi.SX
        Spanwise running load in the web (N/m, compression negative).
    nxy : float, array_like or casadi.SX
        Shear flow in the web (N/m).

    Returns
    -------
    float, array_like or casadi.SX
        Compression-shear buckling ratio (-; 1 = buckling).
    """
    r = panel_failure_ratios(_panel_material(material), t, b, length, None, None, nx, nxy)
    return r["skin_buckling"]
