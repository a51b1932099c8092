"""Symmetric maneuver loads: 14 CFR 25.337 limit load factors and spanwise line loads.

Only the *aerodynamic* part of the load is produced here. Inertia relief (the wing's own
weight and non-structural masses times the load factor) is applied by the beam's gravity /
acceleration terms, so it must not be added again. See ``docs/loads.md``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from wingmdao.loads.distribution import lift_per_span, span_per_beam_length, trapezoid, arc_length

N_POS_MIN, N_POS_MAX = 2.5, 3.8
N_NEG = -1.0


class LineLoads(NamedTuple):
    """Distributed loads at the beam nodes, per unit beam-axis length, body axes.

    Parameters
    ----------
    force_per_length : numpy.ndarray
        (n, 3) force per unit beam length (N/m).
    moment_per_length : numpy.ndarray
        (n, 3) moment per unit beam length (N m/m).
    lift_per_span : numpy.ndarray
        (n,) lift per unit span (N/m).
    """

    force_per_length: np.ndarray  # (n_node, 3) N/m
    moment_per_length: np.ndarray  # (n_node, 3) N m/m, about the beam axis at each node
    lift_per_span: np.ndarray  # (n_node,) N/m of span (before the dy/ds conversion)


def limit_load_factors(weight_lb) -> tuple[float, float]:
    """14 CFR 25.337(b)-(c): (positive, negative) limit maneuvering load factors.

    n_pos = 2.1 + 24000 / (W + 10000), W the design maximum takeoff weight in lb, not less
    than 2.5 and not more than 3.8; n_neg = -1.0 (up to V_C).

    Parameters
    ----------
    weight_lb : float
        Design maximum take-off weight (lb).

    Returns
    -------
    tuple of float
        (n_pos, n_neg) (-).
    """
    w = float(weight_lb)
    if not (np.isfinite(w) and w > 0.0):
        raise ValueError(f"weight_lb = {weight_lb}; allowed range (0, inf) lb")
    n_pos = 2.1 + 24000.0 / (w + 10000.0)
    return float(np.clip(n_pos, N_POS_MIN, N_POS_MAX)), N_NEG


def check_strip_geometry(node_positions, chord, beam_axis_fraction, cp_fraction):
    """Validate beam nodes and strip data; return arrays (positions (n,3), chord (n,), x_b (n,)).

    Parameters
    ----------
    node_positions : array_like
        (n, 3) beam node positions (m).
    chord : array_like
        (n,) strip chords (m).
    beam_axis_fraction : array_like
        (n,) beam axis as a fraction of the chord (-).
    cp_fraction : float
        Centre of pressure as a fraction of the chord (-).

    Returns
    -------
    tuple
        Positions (n, 3), chord (n,), beam-axis fraction (n,) as float arrays.
    """
    r = np.asarray(node_positions, dtype=float)
    if r.ndim != 2 or r.shape[1] != 3 or r.shape[0] < 2:
        raise ValueError(f"node_positions: shape {r.shape}; expected (n_node >= 2, 3) m")
    n = r.shape[0]
    if not np.all(np.isfinite(r)):
        raise ValueError("node_positions: non-finite value")
    c = np.broadcast_to(np.asarray(chord, dtype=float), (n,)).copy()
    xb = np.broadcast_to(np.asarray(beam_axis_fraction, dtype=float), (n,)).copy()
    bad = np.flatnonzero(~(c > 0.0) | ~np.isfinite(c))
    if bad.size:
        i = bad[0]
        raise ValueError(f"chord[{i}] = {c[i]} m at node {i}; allowed range (0, inf) m")
    bad = np.flatnonzero(~((xb >= 0.0) & (xb <= 1.0)))
    if bad.size:
        i = bad[0]
        raise ValueError(
            f"beam_axis_fraction[{i}] = {xb[i]} at node {i}; allowed range [0, 1] (fraction of chord)"
        )
    if not (0.0 <= cp_fraction <= 1.0):
        raise ValueError(f"cp_fraction = {cp_fraction}; allowed range [0, 1] (fraction of chord)")
    return r, c, xb


def strip_line_loads(node_positions, chord, beam_axis_fraction, lift_per_unit_span, cp_fraction=0.25):
    """Force and moment per unit beam length from a lift per unit span acting at ``cp_fraction``.

    Lift acts along +z (body axes) on a chordwise strip parallel to x; per unit beam length
    it is l dy/ds. Its point of action lies d = (cp_fraction - beam_axis_fraction) c aft of
    the beam axis, so the moment about the axis is r x f = (d, 0, 0) x (0, 0, f_z) =
    (0, -d f_z, 0): lift aft of the axis gives a nose-down (negative y) moment.
    ``lift_per_unit_span`` is (n_node,) or (..., n_node) (e.g. one row per time step);
    the results have one more trailing axis of length 3.

    Parameters
    ----------
    node_positions : array_like
        (n, 3) beam node positions (m).
    chord : array_like
        (n,) strip chords (m).
    beam_axis_fraction : array_like
        (n,) beam axis as a fraction of the chord (-).
    lift_per_unit_span : array_like
        (n,) or (..., n) lift per unit span (N/m).
    cp_fraction : float, optional
        Centre of pressure as a fraction of the chord (-).

    Returns
    -------
    tuple
        Force and moment per unit beam length (..., n, 3) (N/m, N m/m).
    """
    r, c, xb = check_strip_geometry(node_positions, chord, beam_axis_fraction, cp_fraction)
    lift = np.asarray(lift_per_unit_span, dtype=float)
    if lift.shape[-1:] != (r.shape[0],):
        raise ValueError(f"lift_per_unit_span: shape {lift.shape}; last axis must be n_node = {r.shape[0]}")
    fz = lift * span_per_beam_length(r)
    force = np.zeros(lift.shape + (3,))
    force[..., 2] = fz
    moment = np.zeros_like(force)
    moment[..., 1] = -(cp_fraction - xb) * c * fz
    return force, moment


def maneuver_line_loads(
    node_positions,
    chord,
    beam_axis_fraction,
    weight_N: float,
    load_factor: float,
    *,
    distribution="schrenk",
    cp_fraction: float = 0.25,
    wing_lift_fraction: float = 1.0,
    semi_span: float | None = None,
    fuselage_half_width: float = 0.0,
    fuselage_carries_lift: bool = True,
) -> LineLoads:
    """Aerodynamic line loads of a symmetric maneuver on the right half-wing beam.

    Half-wing lift L/2 = ``wing_lift_fraction`` n W / 2 (W in N) is spread spanwise by
    ``distribution`` (:func:`wingmdao.loads.distribution.lift_per_span`) at the nodes' y,
    converted to per unit beam length and rescaled so that the trapezoid integral along the
    beam equals L/2 exactly (a no-op for a straight beam), with the centre of pressure at
    ``cp_fraction`` of the chord giving the torsion about the beam axis (which lies at
    ``beam_axis_fraction`` of the chord). Inertia relief is *not* included: the beam's
    gravity terms apply it.

    Parameters
    ----------
    node_positions : array_like
        (n, 3) beam node positions (m).
    chord : array_like
        (n,) strip chords (m).
    beam_axis_fraction : array_like
        (n,) beam axis as a fraction of the chord (-).
    weight_N : float
        Aircraft weight W (N).
    load_factor : float
        Load factor n (-).
    distribution : {"schrenk", "elliptic"} or array_like, optional
        Spanwise lift shape (:func:`wingmdao.loads.distribution.lift_per_span`).
    cp_fraction : float, optional
        Centre of pressure as a fraction of the chord (-).
    wing_lift_fraction : float, optional
        Share of the lift carried by the wing (-).
    semi_span : float or None, optional
        Semi-span (m); None for the last node's y.
    fuselage_half_width : float, optional
        Fuselage half-width (m).
    fuselage_carries_lift : bool, optional
        Whether the stations inside the fuselage carry lift.

    Returns
    -------
    LineLoads
        The line loads.
    """
    if not (np.isfinite(weight_N) and weight_N > 0.0):
        raise ValueError(f"weight_N = {weight_N}; allowed range (0, inf) N")
    if not np.isfinite(load_factor):
        raise ValueError(f"load_factor = {load_factor}; must be a finite number")
    if not (0.0 < wing_lift_fraction <= 2.0):
        raise ValueError(f"wing_lift_fraction = {wing_lift_fraction}; allowed range (0, 2]")
    r, c, xb = check_strip_geometry(node_positions, chord, beam_axis_fraction, cp_fraction)
    half_lift = 0.5 * wing_lift_fraction * load_factor * weight_N
    lift = lift_per_span(
        r[:, 1], c, half_lift, distribution, semi_span=semi_span,
        fuselage_half_width=fuselage_half_width, fuselage_carries_lift=fuselage_carries_lift,
    )
    force, moment = strip_line_loads(r, c, xb, lift, cp_fraction)
    along_beam = trapezoid(force[:, 2], arc_length(r))
    if along_beam != 0.0:
        scale = half_lift / along_beam
        force *= scale
        moment *= scale
    return LineLoads(force, moment, lift)
