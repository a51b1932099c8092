"""Spanwise lift slopes of a swept, tapered wing: Weissinger's lifting line (a one-chordwise-panel
vortex lattice).

The Prandtl lifting line of :mod:`wingmdao.aero.lifting_line` has no sweep. Here the half-wing
is cut into ``n_panels`` spanwise strips (cosine spacing, finer at the tip); each carries a
horseshoe vortex whose bound leg lies on the quarter-chord line and whose trailing legs run
streamwise (+x) to infinity; the flow tangency condition is enforced at the three-quarter-chord
point of each strip's mid-span (Weissinger, "The lift distribution of swept-back wings", NACA
TM 1120, 1947; Katz & Plotkin, "Low-Speed Aerodynamics", 2nd ed., Sec. 12.1). The left half is
the mirror image (symmetric loading).

Compressibility by the Prandtl-Glauert (Goethert) rule: the planform is stretched in x by
1/beta, beta = sqrt(1 - M^2), and solved incompressibly; the stretched section's c_l' (on its
chord c / beta) divided by beta is the compressible c_l = 2 Gamma / (V c) (Katz & Plotkin
Sec. 8.3; the same affine rule gives the beta terms of the DATCOM lift-slope formula).

Lift per span l = rho V Gamma (Kutta-Joukowski on the bound leg per unit y); the local lift
slope is c_l / alpha = 2 Gamma / (V c alpha). The section slope of the flat-plate vortex at
the quarter chord with tangency at three quarters is 2 pi (thin-airfoil theory).
"""

from __future__ import annotations

import numpy as np

FOUR_PI = 4.0 * np.pi


def segment_velocity(p, a, b):
    """Velocity induced by straight vortex segments of unit circulation (Biot-Savart).

    Parameters
    ----------
    p : ndarray, shape (..., 3)
        Points where the velocity is evaluated (m).
    a, b : ndarray, shape (..., 3)
        Start and end of each segment (m), broadcast against ``p``.

    Returns
    -------
    ndarray, shape (..., 3)
        Induced velocity per unit circulation (1/m); zero on the segment's line.
    """
    r1, r2 = p - a, p - b
    cross = np.cross(r1, r2)
    c2 = np.sum(cross * cross, axis=-1)
    n1, n2 = np.linalg.norm(r1, axis=-1), np.linalg.norm(r2, axis=-1)
    r0 = b - a
    k = np.sum(r0 * (r1 / n1[..., None] - r2 / n2[..., None]), axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(c2 > 1e-14, k / (FOUR_PI * c2), 0.0)
    return cross * f[..., None]


def semi_infinite_velocity(p, a, direction):
    """Velocity induced by a semi-infinite vortex of unit circulation.

    Parameters
    ----------
    p : ndarray, shape (..., 3)
        Points where the velocity is evaluated (m).
    a : ndarray, shape (..., 3)
        Start of the vortex (m).
    direction : ndarray, shape (3,)
        Unit vector along which the vortex runs from ``a`` to infinity.

    Returns
    -------
    ndarray, shape (..., 3)
        Induced velocity per unit circulation (1/m); zero on the vortex's line.
    """
    r1 = p - a
    cross = np.cross(direction, r1)
    c2 = np.sum(cross * cross, axis=-1)
    n1 = np.linalg.norm(r1, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(c2 > 1e-14, (1.0 + np.sum(direction * r1, axis=-1) / n1) / (FOUR_PI * c2), 0.0)
    return cross * f[..., None]


def _horseshoes(points, ya, yb, xa, xb):
    """w (z-velocity) at ``points`` (m, 3) of unit horseshoes with bound legs (xa, ya) -> (xb, yb)
    (z = 0), trailing legs to +x infinity: incoming along -x to the first corner, out from the second."""
    n = ya.size
    P = points[:, None, :]
    A = np.stack([xa, ya, np.zeros(n)], axis=-1)[None]
    B = np.stack([xb, yb, np.zeros(n)], axis=-1)[None]
    ex = np.array([1.0, 0.0, 0.0])
    v = segment_velocity(P, A, B) + semi_infinite_velocity(P, B, ex) - semi_infinite_velocity(P, A, ex)
    return v[..., 2]


def weissinger_lift_slope(y, chord, leading_edge_x, semi_span, *, mach=0.0, n_panels=60):
    """Local lift slope c_l / alpha (1/rad) at spanwise positions ``y`` of a swept wing.

    ``chord`` and ``leading_edge_x``: callables of y (m; streamwise chord and x of the leading
    edge), defined on [0, semi_span]; ``mach``: free-stream Mach number (Prandtl-Glauert).
    Returns ``(slope at y, CL_alpha, result)``: the wing's lift-curve slope (1/rad) on the
    planform area of both halves and a dict with the strips' ``y``, ``cl_alpha`` and
    ``circulation`` (per unit V alpha). Between strip centres the slope is interpolated on
    Gamma / sqrt(1 - eta^2) (smooth to the tip), so it vanishes at the tip (y = semi_span).

    Parameters
    ----------
    y : array_like
        Spanwise positions (m), in [0, semi_span].
    chord : callable
        Streamwise chord c(y) (m), > 0 on the span.
    leading_edge_x : callable
        x of the leading edge at y (m).
    semi_span : float
        Semi-span (m), > 0.
    mach : float
        Free-stream Mach number, in [0, 1).
    n_panels : int
        Spanwise panels of the half wing (at least 4, cosine spacing).

    Returns
    -------
    slope : ndarray
        Local lift slope at ``y`` (1/rad).
    cl_alpha : float
        Wing lift-curve slope (1/rad).
    result : dict
        The strips' ``y`` (m), ``cl_alpha`` (1/rad) and ``circulation`` (per unit V alpha, m).
    """
    s = float(semi_span)
    if not (np.isfinite(s) and s > 0):
        raise ValueError(f"semi_span must be > 0 m, got {semi_span}")
    if not (np.isfinite(mach) and 0.0 <= mach < 1.0):
        raise ValueError(f"mach must be in [0, 1), got {mach}")
    if int(n_panels) < 4:
        raise ValueError(f"n_panels must be >= 4, got {n_panels}")
    y = np.atleast_1d(np.asarray(y, dtype=float))
    if np.any(~np.isfinite(y)) or np.any((y < 0) | (y > s)):
        raise ValueError(f"y must be in [0, semi_span] = [0, {s}] m")
    beta = np.sqrt(1.0 - mach ** 2)
    n = int(n_panels)
    edges = s * np.sin(0.5 * np.pi * np.arange(n + 1) / n)  # cosine spacing, fine at the tip
    ym = 0.5 * (edges[1:] + edges[:-1])
    c_e, c_m = np.asarray(chord(edges), float), np.asarray(chord(ym), float)
    if np.any(c_e <= 0) or np.any(~np.isfinite(c_e)):
        raise ValueError("chord must be finite and > 0 m over the span")
    xq = (np.asarray(leading_edge_x(edges), float) + 0.25 * c_e) / beta  # stretched quarter-chord line
    xc = (np.asarray(leading_edge_x(ym), float) + 0.75 * c_m) / beta  # stretched 3/4-chord points
    pts = np.stack([xc, ym, np.zeros(n)], axis=-1)
    # right half: bound legs from the inboard to the outboard edge; left half: mirror image
    w = (_horseshoes(pts, edges[:-1], edges[1:], xq[:-1], xq[1:])
         + _horseshoes(pts, -edges[1:], -edges[:-1], xq[1:], xq[:-1]))
    gamma = np.linalg.solve(w, -np.ones(n))  # w Gamma + V alpha = 0 with V alpha = 1
    # the stretched section's c_l' = 2 Gamma / (c / beta); compressible c_l = c_l' / beta = 2 Gamma / c
    cl_strip = 2.0 * gamma / c_m  # per radian, compressible
    dy = np.diff(edges)
    area = 2.0 * np.sum(c_m * dy)
    cl_alpha = 2.0 * np.sum(2.0 * gamma * dy) / area
    # interpolation: g = Gamma / sqrt(1 - eta^2) is smooth to the tip
    g = gamma / np.sqrt(1.0 - (ym / s) ** 2)
    gy = np.interp(y, ym, g) * np.sqrt(np.clip(1.0 - (y / s) ** 2, 0.0, None))
    slope = 2.0 * gy / np.asarray(chord(y), float)
    return slope, float(cl_alpha), {"y": ym, "cl_alpha": cl_strip, "circulation": gamma, "area": area}
