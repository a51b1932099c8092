"""Unit conversions and standard gravity: the one home of these constants in the package.

Every module that converts feet, pounds, slugs or knots, or uses standard gravity, takes them
from here (SI throughout: each constant is the SI value of one unit).
"""

from __future__ import annotations

FT = 0.3048                      # m per international foot
KNOT = 1852.0 / 3600.0           # m/s per knot
LB = 0.45359237                  # kg per pound (mass)
G0 = 9.80665                     # standard gravity, m/s^2 (ISO 80000-3)
LBF = LB * G0                    # N per pound-force (4.4482216152605)
SLUG = LBF / FT                  # kg per slug (14.593902937...)
