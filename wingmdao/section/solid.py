"""Properties of a solid rectangular section (Sec. 4.7.1), for numpy and CasADi.

Width ``w`` (chordwise, c) and height ``h`` (normal, n) are the design variables; the
centroid, shear centre and mass centre are all at the geometric centre.
"""

from __future__ import annotations

import math

import numpy as np

from wingmdao.section.box import beam_data, select, tanh

#: Odd terms kept in the torsion series; the truncation error is below 1e-9 relative.
TORSION_SERIES_TERMS = 60

#: Timoshenko shear coefficient of a rectangle (5/6), used for both shear areas.
SHEAR_COEFFICIENT = 5.0 / 6.0


def _torsion_long_short(a, b):
    """Saint-Venant J of an a x b rectangle, series expanded along the side a (exact for any
    a, b; well conditioned for a >= b): J = a b^3/3 [1 - 192 b/(pi^5 a) sum_{k odd}
    tanh(k pi a / (2 b)) / k^5] (Timoshenko & Goodier, Theory of Elasticity, Sec. 109)."""
    series = 0.0
    for i in range(TORSION_SERIES_TERMS):
        k = 2 * i + 1
        series = series + tanh(k * math.pi * a / (2.0 * b)) / k**5
    return a * b**3 / 3.0 * (1.0 - 192.0 / math.pi**5 * b / a * series)


def solid_torsion_constant(w, h):
    """J = beta(h/w) w^3 h of a solid rectangle (w the shorter side), m^4; 0.1406 a^4 for a
    square. The series is always expanded along the longer side.

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Sides of the rectangle (m).

    Returns
    -------
    float, array_like or casadi.SX
        Torsion constant J (m^4).
    """
    return select(h >= w, _torsion_long_short(h, w), _torsion_long_short(w, h))


def solid_properties(w, h, material, section_to_csn=None, nonstructural_mass_per_length=0.0) -> dict:
    """All solid-rectangle section outputs (names as in ``SolidRectSection``).

    A = w h, Ixx = w h^3/12 (vertical bending), Izz = h w^3/12, Ixz = 0, J from the series,
    Qx = w h^2/8, Qz = h w^2/8 (half the section about the centroidal axis), shear areas
    K_c = K_n = 5/6 A.

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Width and height of the rectangle (m).
    material : Material
        Isotropic material.
    section_to_csn : array_like or None, optional
        (3, 3) rotation R from the section's own axes to the csn frame; None when they coincide.
    nonstructural_mass_per_length : float, optional
        Mass per length added to the section (kg/m).

    Returns
    -------
    dict
        Section outputs keyed as ``SolidRectSection``'s.
    """
    zero = 0.0 * w * h
    area = w * h
    props = {"A": area, "Ixx": w * h**3 / 12.0, "Izz": h * w**3 / 12.0, "Ixz": zero,
             "J": solid_torsion_constant(w, h),
             "c_ea": zero, "n_ea": zero, "c_sc": zero, "n_sc": zero, "c_cg": zero, "n_cg": zero,
             "Qx": w * h**2 / 8.0, "Qz": h * w**2 / 8.0,
             "K_c": SHEAR_COEFFICIENT * area, "K_n": SHEAR_COEFFICIENT * area}
    return beam_data(props, material, section_to_csn, nonstructural_mass_per_length)


def validate_solid(width, height, source="") -> None:
    """Raise ``ValueError`` naming the input and station unless width, height are finite and > 0 (m).

    Parameters
    ----------
    width, height : float or array_like
        Rectangle sides (m).
    source : str, optional
        Input and station named in the error.
    """
    for name, v in (("width", width), ("height", height)):
        v = np.atleast_1d(np.asarray(v, dtype=float))
        bad = np.flatnonzero(~(np.isfinite(v) & (v > 0.0)))
        if bad.size:
            i = int(bad[0])
            raise ValueError(f"{source}{name} = {v[i]:.6g} m at station {i}; allowed range (0, inf) m")
