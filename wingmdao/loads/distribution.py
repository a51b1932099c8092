"""Spanwise lift distributions for the half wing: Schrenk, elliptic, or a user shape.

All distributions are lift per unit *span* l(y) (N/m) at given stations y (m, body axis y,
y = 0 at the symmetry plane), scaled so that the trapezoid-rule integral over the stations
equals the half-wing lift exactly (the loads are applied on a beam that interpolates them
linearly between nodes). :func:`per_beam_length` converts to load per unit length of the
beam axis. See ``docs/loads.md``.
"""

from __future__ import annotations

import numpy as np


def trapezoid(values: np.ndarray, coords: np.ndarray) -> float:
    """Trapezoid-rule integral of nodal values over nodal coordinates.

    Parameters
    ----------
    values : numpy.ndarray
        Nodal values.
    coords : numpy.ndarray
        Nodal coordinates.

    Returns
    -------
    float
        The integral.
    """
    values, coords = np.asarray(values, float), np.asarray(coords, float)
    return float(np.sum(0.5 * (values[1:] + values[:-1]) * np.diff(coords)))


def _check_stations(y, chord, semi_span):
    y = np.asarray(y, dtype=float)
    chord = np.asarray(chord, dtype=float)
    if y.ndim != 1 or y.size < 2:
        raise ValueError(f"y: need a 1-D array of at least 2 stations, got shape {y.shape}")
    if chord.shape != y.shape:
        raise ValueError(f"chord: shape {chord.shape} must match y {y.shape}")
    for name, arr, lo in (("y", y, 0.0), ("chord", chord, 0.0)):
        bad = np.flatnonzero(~np.isfinite(arr) | (arr < lo))
        if bad.size:
            i = bad[0]
            raise ValueError(f"{name}[{i}] = {arr[i]} m at station {i}; allowed range [0, inf) m")
    bad = np.flatnonzero(np.diff(y) <= 0.0)
    if bad.size:
        i = bad[0] + 1
        raise ValueError(
            f"y[{i}] = {y[i]} m at station {i} is not greater than y[{i - 1}] = {y[i - 1]} m; "
            "stations must run outboard with strictly increasing y"
        )
    s = float(y[-1]) if semi_span is None else float(semi_span)
    if not (np.isfinite(s) and s >= y[-1] and s > 0.0):
        raise ValueError(f"semi_span = {s} m; allowed range [y[-1] = {y[-1]}, inf) m")
    return y, chord, s


def elliptic_shape(y, semi_span: float) -> np.ndarray:
    """sqrt(1 - (y/b2)^2), the elliptic loading shape (b2 = semi-span).

    Parameters
    ----------
    y : array_like
        Span coordinates (m).
    semi_span : float
        Semi-span b2 (m).

    Returns
    -------
    numpy.ndarray
        Shape values (-).
    """
    eta = np.clip(np.asarray(y, float) / semi_span, 0.0, 1.0)
    return np.sqrt(1.0 - eta**2)


def lift_per_span(
    y,
    chord,
    half_wing_lift: float,
    distribution="schrenk",
    *,
    semi_span: float | None = None,
    fuselage_half_width: float = 0.0,
    fuselage_carries_lift: bool = True,
) -> np.ndarray:
    """Lift per unit span l(y) (N/m) at the stations, trapezoid integral = ``half_wing_lift`` (N).

    ``distribution``: ``"schrenk"`` (mean of the planform-chord shape c(y) and the elliptic
    shape, each carrying the full lift: Schrenk's approximation), ``"elliptic"``
    (4 L / (pi b2) sqrt(1 - (y/b2)^2) in the continuous limit) or an array of n non-negative
    shape values. ``semi_span`` b2 defaults to the last station y. With
    ``fuselage_carries_lift=False`` stations with y < ``fuselage_half_width`` get no lift and
    the exposed wing carries all of ``half_wing_lift``.

    Parameters
    ----------
    y : array_like
        (n,) station span coordinates (m).
    chord : array_like
        (n,) chords (m).
    half_wing_lift : float
        Lift of the half wing (N).
    distribution : {"schrenk", "elliptic"} or array_like, optional
        Spanwise shape.
    semi_span : float or None, optional
        Semi-span (m); None for the last station.
    fuselage_half_width : float, optional
        Fuselage half-width (m).
    fuselage_carries_lift : bool, optional
        Whether the stations inside the fuselage carry lift.

    Returns
    -------
    numpy.ndarray
        (n,) lift per span (N/m).
    """
    y, chord, b2 = _check_stations(y, chord, semi_span)
    if not np.isfinite(half_wing_lift):
        raise ValueError(f"half_wing_lift = {half_wing_lift} N must be finite")
    if not (np.isfinite(fuselage_half_width) and 0.0 <= fuselage_half_width < y[-1]):
        raise ValueError(
            f"fuselage_half_width = {fuselage_half_width} m; allowed range [0, {y[-1]}) m"
        )
    lifting = np.ones_like(y)
    if not fuselage_carries_lift:
        lifting[y < fuselage_half_width] = 0.0

    def unit(shape, name):
        shape = shape * lifting
        area = trapezoid(shape, y)
        if not area > 0.0:
            raise ValueError(f"{name}: the lift shape integrates to {area} over the lifting stations")
        return shape / area

    if isinstance(distribution, str):
        kind = distribution.lower()
        if kind == "elliptic":
            shape = unit(elliptic_shape(y, b2), "elliptic")
        elif kind == "schrenk":
            shape = 0.5 * (unit(chord, "chord") + unit(elliptic_shape(y, b2), "elliptic"))
        else:
            raise ValueError(
                f"distribution = '{distribution}'; allowed 'schrenk', 'elliptic' or an array of shape {y.shape}"
            )
    else:
        user = np.asarray(distribution, dtype=float)
        if user.shape != y.shape:
            raise ValueError(f"distribution: user array shape {user.shape} must match y {y.shape}")
        bad = np.flatnonzero(~np.isfinite(user) | (user < 0.0))
        if bad.size:
            i = bad[0]
            raise ValueError(f"distribution[{i}] = {user[i]} at station {i}; allowed range [0, inf)")
        shape = unit(user, "distribution")
    return half_wing_lift * shape


def span_per_beam_length(node_positions) -> np.ndarray:
    """dy/ds at each node: spanwise length per unit beam-axis length (tributary average).

    At node i, (y_{i+1} - y_{i-1}) / (s_{i+1} - s_{i-1}) over the adjacent elements (one
    element at the ends); cos(sweep) cos(dihedral) for a straight beam.

    Parameters
    ----------
    node_positions : array_like
        (n, 3) beam node positions (m).

    Returns
    -------
    numpy.ndarray
        (n,) dy/ds (-).
    """
    r = np.asarray(node_positions, dtype=float)
    if r.ndim != 2 or r.shape[1] != 3 or r.shape[0] < 2:
        raise ValueError(f"node_positions: shape {r.shape}; expected (n_node >= 2, 3) m")
    ds = np.linalg.norm(np.diff(r, axis=0), axis=1)
    bad = np.flatnonzero(~(ds > 0.0))
    if bad.size:
        i = bad[0]
        raise ValueError(f"node_positions[{i}] and node_positions[{i + 1}] coincide; element length must be > 0 m")
    dy = np.diff(r[:, 1])
    num = np.zeros(r.shape[0])
    den = np.zeros(r.shape[0])
    num[:-1] += dy
    num[1:] += dy
    den[:-1] += ds
    den[1:] += ds
    return num / den


def arc_length(node_positions) -> np.ndarray:
    """Cumulative beam-axis length s at each node (m), s = 0 at the root.

    Parameters
    ----------
    node_positions : array_like
        (n, 3) beam node positions (m).

    Returns
    -------
    numpy.ndarray
        (n,) arc length s (m).
    """
    r = np.asarray(node_positions, dtype=float)
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(r, axis=0), axis=1))])
