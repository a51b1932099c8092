"""Stiffness-matched rectangular box (dissertation Sec. 4.2.4, Eq. 4.13-4.14).

The analytic box is the sizing model's own (``wingmdao.section.box``, App. F), so a matched
width/height feeds ``BoxSection`` directly (outer dimensions).
"""

from __future__ import annotations

import casadi as ca
import numpy as np
from scipy.optimize import minimize

from wingmdao.section.box import box_inertia, box_torsion_constant


def box_stiffness(width, height, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, E, G):
    """[EI_cc, EI_nn, GJ] (N m^2) of the analytic box of ``wingmdao.section.box`` (App. F).

    ``width`` and ``height`` are the box's *outer* dimensions (m), as ``BoxSection`` takes them;
    EI about the centroid (exact rectangles, parallel axes), GJ by Bredt-Batho over the wall
    midlines. Works on floats or CasADi symbols.

    Parameters
    ----------
    width, height : float or casadi.SX
        Outer box dimensions (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float or casadi.SX
        Wall thicknesses (m).
    E : float
        Young's modulus (Pa).
    G : float
        Shear modulus (Pa).

    Returns
    -------
    list
        [EI_cc, EI_nn, GJ] (N m^2).
    """
    walls = (t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar)
    i_xx, i_zz, _ = box_inertia(width, height, *walls)
    return E * i_xx, E * i_zz, G * box_torsion_constant(width, height, *walls)


_OBJ = []


def _objective():
    """CasADi objective f(x=[w, h], p=[EI_cc, GJ, EI_cs, tu, tl, tf, tr, E, G]) and its exact gradient (built once)."""
    if not _OBJ:
        x = ca.SX.sym("x", 2)
        p = ca.SX.sym("p", 9)
        EIc, _, GJb = box_stiffness(x[0], x[1], p[3], p[4], p[5], p[6], p[7], p[8])
        r = ca.vertcat((EIc - p[0]) / p[0], (GJb - p[1]) / p[1], 2 ** 0.5 * p[2] / ca.sqrt(p[0] * p[1]))
        f = ca.sumsqr(r)
        _OBJ.append(ca.Function("box_match_objective", [x, p], [f, ca.gradient(f, x)]))
    return _OBJ[0]


def match_box(EI_cc, GJ, thicknesses, E, G, w0, h0, bounds=((1e-3, 100.0), (1e-3, 100.0)), EI_cs=0.0):
    """Width and height of the box whose [EI_cc, EI_cs; EI_cs, GJ] best match the targets (Eq. 4.13-4.14).

    Objective: squared Frobenius norm of the difference scaled by the target diagonal
    (D^-1/2 (K_box - K) D^-1/2); the box has EI_cs = 0. Exact gradient from CasADi AD.
    Returns dict(width, height, EI_cc, GJ, residual).

    Parameters
    ----------
    EI_cc : float
        Target chordwise-axis bending stiffness (N m^2).
    GJ : float
        Target torsional stiffness (N m^2).
    thicknesses : sequence of 4 floats
        Wall thicknesses (upper, lower, front, rear) of the box (m).
    E : float
        Young's modulus (Pa).
    G : float
        Shear modulus (Pa).
    w0, h0 : float
        Starting width and height (m).
    bounds : tuple, optional
        ((lower, upper) width, (lower, upper) height) (m).
    EI_cs : float, optional
        Target bending-torsion coupling (N m^2).

    Returns
    -------
    dict
        ``width``, ``height`` (m), ``EI_cc``, ``GJ`` (N m^2) and ``residual`` (-).
    """
    for name, v in (("EI_cc", EI_cc), ("GJ", GJ)):
        if not np.isfinite(v) or v <= 0:
            raise ValueError(f"target {name} must be > 0 N m^2, got {v}")
    fun = _objective()
    p = [EI_cc, GJ, EI_cs, *thicknesses, E, G]

    def obj(v):
        val, g = fun(v, p)
        return float(val), np.array(g).ravel()
    res = minimize(obj, np.array([w0, h0]), jac=True, method="L-BFGS-B", bounds=bounds,
                   options={"ftol": 1e-20, "gtol": 1e-14, "maxiter": 500})
    w, h = res.x
    EIc, _, GJb = box_stiffness(w, h, *thicknesses, E, G)
    return {"width": float(w), "height": float(h), "EI_cc": float(EIc), "GJ": float(GJb), "residual": float(res.fun)}
