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


def trapezoid_node_weights(node_positions) -> np.ndarray:
    """Each node's share of the beam length (m) for lumping a per-length quantity at the nodes with
    the trapezoid rule: half of each adjacent element's length (complex-step safe).

    Parameters
    ----------
    node_positions : array_like, shape (n, 3)
        Node positions (m).

    Returns
    -------
    ndarray, shape (n,)
        The weights (m); ValueError unless every element length is > 0 m.
    """
    r = np.asarray(node_positions)
    s = np.sqrt(np.sum(np.diff(r, axis=0) ** 2, axis=1))
    if np.any(np.real(s) <= 0):
        raise ValueError("node_positions: element lengths must be > 0 m")
    w = np.zeros(r.shape[0], dtype=s.dtype)
    w[:-1] += 0.5 * s
    w[1:] += 0.5 * s
    return w


def half_wing_mass(mass_per_length, node_positions):
    """(m_half kg, d m_half / d mu (n,), d m_half / d node_positions (n, 3)) by the trapezoid rule
    (complex-step safe).

    Parameters
    ----------
    mass_per_length : array_like, shape (n,)
        Mass per length of the beam at the nodes (kg/m); may be complex (complex step).
    node_positions : array_like, shape (n, 3)
        Node positions (m); consecutive nodes distinct.

    Returns
    -------
    m_half : float
        Half-wing mass (kg).
    dm_dmu : ndarray, shape (n,)
        Its derivative with respect to the mass per length (m).
    dm_dr : ndarray, shape (n, 3)
        Its derivative with respect to the node positions (kg/m).
    """
    mu, r = np.asarray(mass_per_length), np.asarray(node_positions)
    d = np.diff(r, axis=0)
    s = np.sqrt(np.sum(d * d, axis=1))
    if np.any(np.real(s) <= 0):
        raise ValueError("node_positions: element lengths must be > 0 m")
    mbar = 0.5 * (mu[1:] + mu[:-1])
    dmu = trapezoid_node_weights(r)
    g = (mbar / s)[:, None] * d  # d (mbar s) / d r_{i+1}
    dr = np.zeros(r.shape, dtype=g.dtype)
    dr[1:] += g
    dr[:-1] -= g
    return np.sum(mbar * s), dmu, dr


def body_mass(aircraft_mass, half_mass):
    """Mass outside both wing halves, ``aircraft_mass - 2 half_mass`` (kg); ValueError unless > 0.

    Parameters
    ----------
    aircraft_mass : float
        Aircraft mass (kg).
    half_mass : float
        Mass of one wing half (kg).

    Returns
    -------
    float
        The body mass (kg), > 0.
    """
    m = aircraft_mass - 2.0 * half_mass
    if not (np.isfinite(np.real(aircraft_mass)) and np.real(m) > 0.0):
        raise ValueError(f"aircraft_mass = {np.real(aircraft_mass)} kg; allowed range (2 x half-wing mass = "
                         f"{2.0 * np.real(half_mass):.6g} kg, inf): the free-plunge body mass must be > 0")
    return m
