"""Failure ratios of a wingbox wall's panel as the sizing uses them (interim isotropic forms)."""

from __future__ import annotations

import math

from wingmdao.panels.layout import stiffener_section
from wingmdao.section.box import sqrt

TINY = 1.0  # (N/m)^2 under square roots: finite derivatives at zero load


def _interaction(r_c, r_s):
    return 0.5 * (r_c + sqrt(r_c**2 + 4.0 * r_s**2 + 1e-12))


def skin_panel_ratios(material, t, h, ts, pitch, length, nx, nxy, shape="blade", flange_ratio=0.0):
    E, nu = material.E, material.nu
    D = E * t**3 / (12.0 * (1.0 - nu**2))
    nxy_abs = sqrt(nxy**2 + TINY)
    n_c = 4.0 * math.pi**2 * D / pitch**2
    n_s = (5.35 + 4.0 * (pitch / length) ** 2) * math.pi**2 * D / pitch**2
    skin = _interaction(-nx / n_c, nxy_abs / n_s)
    area, z, i_own = stiffener_section(h, ts, shape, flange_ratio)
    a_tot = area + pitch * t
    zc = area * (t / 2 + z) / a_tot
    i_tot = i_own + area * (t / 2 + z - zc) ** 2 + pitch * t**3 / 12 + pitch * t * zc**2
    n_panel = math.pi**2 * E * i_tot / (pitch * length**2)
    panel = _interaction(-nx / n_panel, nxy_abs / (4 * n_s))
    column = -nx / n_panel
    crip = -nx * pitch / a_tot / (0.9 * material.sigma_y)
    return {"skin_buckling": skin, "panel_buckling": panel, "stiffener_column": column, "stiffener_crippling": crip}


def web_panel_ratio(material, t, b, length, nx, nxy):
    E, nu = material.E, material.nu
    D = E * t**3 / (12.0 * (1.0 - nu**2))
    n_c = 4.0 * math.pi**2 * D / b**2
    n_s = (5.35 + 4.0 * (b / length) ** 2) * math.pi**2 * D / b**2
    return _interaction(-nx / n_c, sqrt(nxy**2 + TINY) / n_s)
