"""NACA 4- and 5-digit airfoil coordinates (Abbott & von Doenhoff, Theory of Wing Sections).

Used to size the analytic box of a wing station (Eq. 4.11-4.12). Returns Selig-ordered
coordinates (upper surface trailing edge -> leading edge -> lower surface trailing edge),
chord 1, closed trailing edge.
"""

from __future__ import annotations

import numpy as np

#: standard 5-digit mean lines for design lift coefficient 0.3 (L = 2): P -> (r, k1)
_FIVE_DIGIT = {1: (0.0580, 361.4), 2: (0.1260, 51.64), 3: (0.2025, 15.957), 4: (0.2900, 6.643),
               5: (0.3910, 3.230)}


def thickness(x, t):
    """Half thickness y_t(x) of the NACA 4-digit family (closed trailing edge), chord 1."""
    return 5.0 * t * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3 - 0.1036 * x**4)


def camber(designation: str, x):
    """Mean line y_c(x) and slope dy_c/dx."""
    d = designation.strip().upper().removeprefix("NACA").strip()
    if len(d) == 4:
        m, p = int(d[0]) / 100.0, int(d[1]) / 10.0
        if m == 0.0:
            return np.zeros_like(x), np.zeros_like(x)
        fore = x < p
        yc = np.where(fore, m / p**2 * (2 * p * x - x**2), m / (1 - p) ** 2 * (1 - 2 * p + 2 * p * x - x**2))
        dy = np.where(fore, 2 * m / p**2 * (p - x), 2 * m / (1 - p) ** 2 * (p - x))
        return yc, dy
    if len(d) == 5 and d[2] == "0" and int(d[1]) in _FIVE_DIGIT:
        r, k1 = _FIVE_DIGIT[int(d[1])]
        k1 *= (0.15 * int(d[0])) / 0.3  # the mean line scales with the design lift coefficient
        fore = x < r
        yc = np.where(fore, k1 / 6 * (x**3 - 3 * r * x**2 + r**2 * (3 - r) * x), k1 * r**3 / 6 * (1 - x))
        dy = np.where(fore, k1 / 6 * (3 * x**2 - 6 * r * x + r**2 * (3 - r)), -k1 * r**3 / 6)
        return yc, dy
    raise ValueError(f"NACA designation {designation!r}: expected 4 digits (MPXX) or 5 digits (LP0XX, P = 1..5)")


def naca_coordinates(designation: str, num_points: int = 101) -> np.ndarray:
    """(2 num_points - 1, 2) coordinates of a NACA 4/5-digit airfoil, chord 1, Selig order."""
    d = designation.strip().upper().removeprefix("NACA").strip()
    if not d.isdigit():
        raise ValueError(f"NACA designation {designation!r} must be digits")
    t = int(d[-2:]) / 100.0
    if not 0.0 < t < 0.5:
        raise ValueError(f"NACA designation {designation!r}: thickness {t} outside (0, 0.5)")
    beta = np.linspace(0.0, np.pi, int(num_points))
    x = 0.5 * (1.0 - np.cos(beta))  # cosine spacing
    yt = thickness(x, t)
    yc, dy = camber(d, x)
    th = np.arctan(dy)
    upper = np.column_stack([x - yt * np.sin(th), yc + yt * np.cos(th)])
    lower = np.column_stack([x + yt * np.sin(th), yc - yt * np.cos(th)])
    return np.vstack([upper[::-1], lower[1:]])
