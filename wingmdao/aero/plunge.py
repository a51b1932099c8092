"""Free plunge of the aircraft: the mass the plunge state carries (docs/aeroelasticity.md).

The plunge row of :func:`wingmdao.aero.system.build_aeroelastic_system` is
``body_mass (dw_p/dt - g_z) = 2 F_root,z``: the root shear of the two half-wings already holds
their own inertia, so the plunge state carries the aircraft mass *outside* the wing halves,

    body_mass = aircraft_mass - 2 m_half,   m_half = sum_i s_i (mu_i + mu_{i+1}) / 2

with mu the beam's mass per length (structure + non-structural + smeared point masses) and
s_i the element lengths (trapezoid rule, as the wing mass of :mod:`wingmdao.components.mass`).
"""

from __future__ import annotations

import numpy as np


def half_wing_mass(mass_per_length, node_positions):
    """(m_half kg, d m_half / d mu (n,), d m_half / d node_positions (n, 3)) by the trapezoid rule."""
    mu = np.asarray(mass_per_length, dtype=float)
    r = np.asarray(node_positions, dtype=float)
    d = np.diff(r, axis=0)
    s = np.linalg.norm(d, axis=1)
    if np.any(s <= 0):
        raise ValueError("node_positions: element lengths must be > 0 m")
    mbar = 0.5 * (mu[1:] + mu[:-1])
    dmu = np.zeros(mu.size)
    dmu[:-1] += 0.5 * s
    dmu[1:] += 0.5 * s
    g = (mbar / s)[:, None] * d  # d (mbar s) / d r_{i+1}
    dr = np.zeros_like(r)
    dr[1:] += g
    dr[:-1] -= g
    return float(np.sum(mbar * s)), dmu, dr


def body_mass(aircraft_mass: float, half_mass: float) -> float:
    """Mass outside both wing halves, ``aircraft_mass - 2 half_mass`` (kg); ValueError unless > 0."""
    m = float(aircraft_mass) - 2.0 * float(half_mass)
    if not (np.isfinite(aircraft_mass) and m > 0.0):
        raise ValueError(f"aircraft_mass = {aircraft_mass} kg; allowed range (2 x half-wing mass = "
                         f"{2.0 * half_mass:.6g} kg, inf): the free-plunge body mass must be > 0")
    return m
