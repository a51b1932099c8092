"""Distributed beam loads on an FE box model: line loads and weights lumped at the FE's span lines.

A line load given per beam node (force and moment per unit length about the beam axis, body
axes) is interpolated linearly in span coordinate y and lumped with the trapezoid rule at the
element-boundary lines of the FE model (half of each adjacent interval), giving station loads
[(y, centre, F, M)] that enter the model through distributing couplings
(:func:`wingmdao.fe.box_model.station_loads`). Their resultant equals the trapezoid integral of
the interpolated line load on the FE lines (the beam's own quadrature on its nodes differs by
the interpolation error of the line load only).
"""

from __future__ import annotations

import numpy as np

from wingmdao.units import G0


def lumping_lengths(ys) -> np.ndarray:
    """Trapezoid weights (m) of the sorted span coordinates ``ys``.

    Parameters
    ----------
    ys : array_like
        Sorted span coordinates (m).

    Returns
    -------
    numpy.ndarray
        Trapezoid weights (m).
    """
    ys = np.asarray(ys, float)
    d = np.diff(ys)
    w = np.zeros(ys.size)
    w[:-1] += 0.5 * d
    w[1:] += 0.5 * d
    return w


def lumped_line_loads(sections, ys, y_nodes, force_per_length, moment_per_length=None) -> list:
    """Station loads [(y, centre (3,), F (3,), M (3,))] at ``ys`` (m) of the line loads given at
    ``y_nodes`` (force N/m (n, 3), moment N m/m (n, 3) about the beam axis, body axes).

    Parameters
    ----------
    sections : BoxSections
        Streamwise sections of the box.
    ys : array_like
        Span coordinates of the station loads (m).
    y_nodes : array_like
        (n,) span coordinates of the line loads (m).
    force_per_length : array_like
        (n, 3) force per length (N/m, body axes).
    moment_per_length : array_like or None, optional
        (n, 3) moment per length about the beam axis (N m/m); None for zero.

    Returns
    -------
    list
        ``(y, centre (3,), F (3,), M (3,))`` station loads.
    """
    f = np.asarray(force_per_length, float)
    m = np.zeros_like(f) if moment_per_length is None else np.asarray(moment_per_length, float)
    if f.shape != (len(y_nodes), 3) or m.shape != f.shape:
        raise ValueError(f"line loads must have shape ({len(y_nodes)}, 3), got {f.shape} and {m.shape}")
    out = []
    for y, L in zip(ys, lumping_lengths(ys)):
        F = np.array([np.interp(y, y_nodes, f[:, k]) for k in range(3)]) * L
        M = np.array([np.interp(y, y_nodes, m[:, k]) for k in range(3)]) * L
        out.append((float(y), sections.at(y)[0], F, M))
    return out


def point_weights(sections, masses, gravity=G0) -> list:
    """Station loads of point masses [(y, kg)] under gravity -z (N) at their section centres.

    Parameters
    ----------
    sections : BoxSections
        Streamwise sections of the box.
    masses : sequence of tuple
        ``(y, mass)`` pairs (m, kg).
    gravity : float, optional
        Gravitational acceleration (m/s^2).

    Returns
    -------
    list
        ``(y, centre (3,), F (3,), M (3,))`` station loads.
    """
    return [(float(y), sections.at(y)[0], np.array([0.0, 0.0, -m * gravity]), np.zeros(3)) for y, m in masses]
