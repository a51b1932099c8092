"""Airfoil outer mould lines: NACA 4- and 5-digit generators and Selig-format .dat files (unit chord)."""

from __future__ import annotations

import numpy as np


def _thickness(x, t):
    """NACA half-thickness (closed trailing edge coefficient -0.1036)."""
    return 5 * t * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x ** 2 + 0.2843 * x ** 3 - 0.1036 * x ** 4)


def _camber4(x, m, p):
    if m == 0:
        return np.zeros_like(x), np.zeros_like(x)
    yc = np.where(x < p, m / p ** 2 * (2 * p * x - x ** 2), m / (1 - p) ** 2 * (1 - 2 * p + 2 * p * x - x ** 2))
    dy = np.where(x < p, 2 * m / p ** 2 * (p - x), 2 * m / (1 - p) ** 2 * (p - x))
    return yc, dy


#: standard 5-digit mean lines (Abbott & von Doenhoff) for design lift coefficient 0.3 (L = 2):
#: maximum-camber digit P -> (r, k1); other L scale k1 by the design lift coefficient 0.15 L.
_FIVE = {1: (0.0580, 361.4), 2: (0.1260, 51.64), 3: (0.2025, 15.957), 4: (0.2900, 6.643), 5: (0.3910, 3.230)}


def _camber5(x, code3):
    """Mean line of the 5-digit series LPQ with Q = 0 (standard, non-reflexed)."""
    if code3[2] != "0" or int(code3[1]) not in _FIVE or code3[0] == "0":
        raise ValueError(f"NACA 5-digit camber line {code3} not supported; allowed: L P 0 with L = 1..9, P = 1..5")
    r, k1 = _FIVE[int(code3[1])]
    k1 *= 0.15 * int(code3[0]) / 0.3
    yc = np.where(x < r, k1 / 6 * (x ** 3 - 3 * r * x ** 2 + r ** 2 * (3 - r) * x), k1 * r ** 3 / 6 * (1 - x))
    dy = np.where(x < r, k1 / 6 * (3 * x ** 2 - 6 * r * x + r ** 2 * (3 - r)), -k1 * r ** 3 / 6 * np.ones_like(x))
    return yc, dy


def naca_surfaces(code: str):
    """Return functions upper(x), lower(x) giving z/c of the surfaces at chord fraction x (NACA 4/5 digit).

    Parameters
    ----------
    code : str
        NACA 4- or 5-digit designation, e.g. ``"2412"``.

    Returns
    -------
    tuple of callable
        ``upper(x)``, ``lower(x)``: z/c at chord fraction x.
    """
    code = str(code).strip().upper().replace("NACA", "").strip()
    if not code.isdigit() or len(code) not in (4, 5):
        raise ValueError(f"naca code must have 4 or 5 digits, got {code!r}")
    t = int(code[-2:]) / 100.0
    if len(code) == 4:
        camber = lambda x: _camber4(x, int(code[0]) / 100.0, int(code[1]) / 10.0)  # noqa: E731
    else:
        camber = lambda x: _camber5(x, code[:3])  # noqa: E731
    xs = 0.5 * (1 - np.cos(np.linspace(0, np.pi, 401)))
    yc, dy = camber(xs)
    th = np.arctan(dy)
    yt = _thickness(xs, t)
    xu, zu = xs - yt * np.sin(th), yc + yt * np.cos(th)
    xl, zl = xs + yt * np.sin(th), yc - yt * np.cos(th)
    return (lambda x: np.interp(x, xu, zu)), (lambda x: np.interp(x, xl, zl))


def selig_surfaces(path):
    """Upper/lower surface functions from a Selig .dat file (TE -> upper -> LE -> lower -> TE, unit chord).

    Parameters
    ----------
    path : str or path-like
        Selig-format ``.dat`` file (unit chord).

    Returns
    -------
    tuple of callable
        ``upper(x)``, ``lower(x)``: z/c at chord fraction x.
    """
    rows = []
    with open(path) as fh:
        for line in fh:
            parts = line.split()
            try:
                rows.append((float(parts[0]), float(parts[1])))
            except (ValueError, IndexError):
                continue
    xy = np.array(rows)
    if xy.shape[0] < 5:
        raise ValueError(f"coordinates file {path}: fewer than 5 coordinate rows")
    ile = int(np.argmin(xy[:, 0]))
    up, lo = xy[:ile + 1][::-1], xy[ile:]
    return (lambda x: np.interp(x, up[:, 0], up[:, 1])), (lambda x: np.interp(x, lo[:, 0], lo[:, 1]))
