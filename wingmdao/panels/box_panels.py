"""The failure ratios of a wingbox wall's panel, as the stiffened sizing uses them.

A skin panel is the skin between two ribs (length = rib pitch) with its stiffeners at the
layout's pitch; a spar web is an unstiffened plate as wide as the web height between the skins.
Both go through :func:`wingmdao.panels.stiffened.panel_failure_ratios` (docs/panels.md), with
running loads from :func:`wingmdao.stress.box_stress.panel_running_loads`.
"""

from __future__ import annotations

from functools import lru_cache

from wingmdao.panels.stiffened import PanelMaterial, panel_failure_ratios, panel_material, skin_width_from_pitch

#: the skin panel's modes the sizing constrains (material strength is the box's von Mises family)
SKIN_MODES = ("skin_buckling", "panel_buckling", "stiffener_column", "stiffener_crippling")


@lru_cache(maxsize=None)
def _panel_material(material):
    """A PanelMaterial as it is, an isotropic Material wrapped."""
    return material if isinstance(material, PanelMaterial) else panel_material(material)


def skin_panel_ratios(material, t, h, ts, pitch, length, nx, nxy, shape="blade", flange_ratio=1.0) -> dict:
    """{mode: ratio} of :data:`SKIN_MODES` for a stiffened skin: thickness ``t``, stiffeners
    ``h`` x ``ts`` at ``pitch``, panel ``length`` (m), running loads ``nx``, ``nxy`` (N/m,
    compression negative). Each ratio is load-linear, 1 = failure at these loads."""
    b = skin_width_from_pitch(pitch, h, shape, flange_ratio)
    r = panel_failure_ratios(_panel_material(material), t, b, length, h, ts, nx, nxy, shape, flange_ratio)
    return {mode: r[mode] for mode in SKIN_MODES}


def web_panel_ratio(material, t, b, length, nx, nxy):
    """Combined compression-shear buckling ratio of an unstiffened spar web of thickness ``t``
    and height ``b`` between ribs ``length`` apart (m) under ``nx``, ``nxy`` (N/m)."""
    r = panel_failure_ratios(_panel_material(material), t, b, length, None, None, nx, nxy)
    return r["skin_buckling"]
