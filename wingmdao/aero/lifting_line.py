"""Finite-span (tip-loss) correction: a section lift-slope distribution from Prandtl's lifting line.

Strip theory gives every section its 2-D slope and so over-predicts the tip loads. Solving
Prandtl's lifting-line equation for the planform at a uniform angle of attack gives the local lift
coefficient per radian c_l(y) / alpha; used as the strips' ``lift_slope``, the quasi-steady limit
of the strip model reproduces the lifting-line spanload of an untwisted wing (for twist and
camber it is an approximation, the induced angle being taken proportional to the local angle).

Monoplane equation (Glauert, "The elements of aerofoil and airscrew theory", 1926; Anderson,
"Fundamentals of Aerodynamics", Sec. 5.3), symmetric loading, y = s cos(theta), b = 2 s:

    alpha = sum_{n odd} A_n sin(n theta) (4 b / (a0 c(theta)) + n / sin(theta)),
    c_l(theta) = 4 b / c(theta) sum A_n sin(n theta),

solved by collocation at theta_j = j pi / (2 N), j = 1..N, with N odd terms.
"""

from __future__ import annotations

import numpy as np


def lifting_line_lift_slope(y, chord, semi_span, *, section_slope=2 * np.pi, n_terms=40):
    """Local lift slope c_l / alpha (1/rad) at spanwise positions ``y`` (0 <= y < semi_span).

    ``chord``: callable c(y) (m) or a pair ``(y_nodes, c_nodes)`` interpolated linearly;
    ``section_slope``: the 2-D slope a0 (1/rad, incompressible). Returns ``(slope at y, CL_alpha)``
    with CL_alpha the wing's lift-curve slope (1/rad) on the reference area int c dy of both halves.

    Parameters
    ----------
    y : array_like
        Spanwise positions (m), in [0, semi_span).
    chord : callable or tuple
        ``c(y)`` (m), or ``(y_nodes, c_nodes)`` interpolated linearly; > 0 inside the span.
    semi_span : float
        Semi-span s (m), > 0.
    section_slope : float
        Section lift slope a0 (1/rad), > 0.
    n_terms : int
        Number of odd Fourier terms (and collocation points).

    Returns
    -------
    slope : ndarray
        Local lift slope at ``y`` (1/rad).
    cl_alpha : float
        Wing lift-curve slope (1/rad).
    """
    s = float(semi_span)
    if not s > 0:
        raise ValueError(f"semi_span must be > 0 m, got {semi_span}")
    if not section_slope > 0:
        raise ValueError(f"section_slope must be > 0 1/rad, got {section_slope}")
    if callable(chord):
        cfun = chord
    else:
        yc, cc = (np.asarray(v, dtype=float) for v in chord)
        cfun = lambda yy: np.interp(yy, yc, cc)  # noqa: E731
    y = np.asarray(y, dtype=float)
    if np.any((y < 0) | (y >= s)):
        raise ValueError(f"y must be in [0, semi_span) = [0, {s}) m")
    b = 2 * s
    n = 2 * np.arange(n_terms) + 1
    th = np.arange(1, n_terms + 1) * np.pi / (2 * n_terms)
    c_th = np.asarray(cfun(s * np.cos(th)), dtype=float)
    if np.any(c_th <= 0):
        raise ValueError("chord must be > 0 m at the collocation points (|y| < semi_span)")
    sin_nt = np.sin(np.outer(th, n))
    M = sin_nt * (4 * b / (section_slope * c_th)[:, None] + n[None, :] / np.sin(th)[:, None])
    A = np.linalg.solve(M, np.ones(n_terms))
    th_y = np.arccos(y / s)
    c_y = np.asarray(cfun(y), dtype=float)
    cl = 4 * b / c_y * (np.sin(np.outer(th_y, n)) @ A)
    # CL = pi AR A_1 with AR = b^2 / S
    tt = np.linspace(0, np.pi / 2, 2001)
    area = 2 * np.trapezoid(np.asarray(cfun(s * np.cos(tt)), dtype=float) * s * np.sin(tt), tt)
    cl_alpha = np.pi * b ** 2 / area * A[0]
    return cl, float(cl_alpha)
