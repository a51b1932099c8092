"""Properties of a rectangular box section (App. F), written once for numpy and CasADi.

Every function uses plain arithmetic only, so it evaluates on floats, numpy arrays
(vectorised over stations) and CasADi ``SX``/``MX`` symbols (the OpenMDAO components get
exact derivatives from CasADi's AD). See docs/section.md for the derivations.

Geometry (Fig. F.1b, Eq. F.2-F.5, F.11-F.24). Coordinates (c, n) are measured from the box's
geometric centre, c chordwise aft along the width ``w``, n up along the height ``h``. The
skins span the full width; the spars sit between the skins (web height h - t_upper - t_lower):

* upper skin: w x t_upper_skin, centre (0, (h - t_upper)/2)                        (F.2, F.11)
* front spar ("left"): t_front x h_web, centre ((t_front - w)/2, (t_lower - t_upper)/2) (F.3, F.16)
* lower skin: w x t_lower_skin, centre (0, (t_lower - h)/2)                        (F.4, F.19)
* rear spar ("right"): t_rear x h_web, centre ((w - t_rear)/2, (t_lower - t_upper)/2)  (F.5, F.24)

The thin-walled quantities (torsion constant, shear centre) use the wall midlines: a
rectangle of width b = w - (t_front + t_rear)/2 and height d = h - (t_upper + t_lower)/2.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from wingmdao.names import WALL_NAMES

#: Outer corners as (c, n) signs: front-lower, rear-lower, rear-upper, front-upper.
CORNERS = ((-1, -1), (1, -1), (1, 1), (-1, 1))


def is_symbolic(*xs) -> bool:
    """Whether any of ``xs`` is a CasADi expression (``SX`` or ``MX``) rather than a number or array.

    Parameters
    ----------
    *xs : object
        The values to test.

    Returns
    -------
    bool
    """
    return any(isinstance(x, (ca.SX, ca.MX)) for x in xs)


def select(condition, if_true, if_false):
    """Elementwise ``if_true if condition else if_false`` for numpy and CasADi.

    Parameters
    ----------
    condition : bool, array_like or casadi.SX
        Condition, elementwise.
    if_true, if_false : float, array_like or casadi.SX
        Values taken where the condition holds and where it does not.

    Returns
    -------
    float, array_like or casadi.SX
        The selected values.
    """
    if is_symbolic(condition, if_true, if_false):
        return ca.if_else(condition, if_true, if_false)
    return np.where(condition, if_true, if_false)


def tanh(x):
    """Elementwise tanh for numpy and CasADi.

    Parameters
    ----------
    x : float, array_like or casadi.SX
        Argument.

    Returns
    -------
    float, array_like or casadi.SX
        tanh(x).
    """
    return ca.tanh(x) if is_symbolic(x) else np.tanh(x)


def sqrt(x):
    """Elementwise square root for numpy and CasADi.

    Parameters
    ----------
    x : float, array_like or casadi.SX
        Argument (>= 0).

    Returns
    -------
    float, array_like or casadi.SX
        sqrt(x).
    """
    return ca.sqrt(x) if is_symbolic(x) else np.sqrt(x)


# --------------------------------------------------------------------------- walls
def box_walls(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, stringers=None, weights=None):
    """The four wall rectangles (Eq. F.2-F.24): list of (area, c, n, i_own_nn, i_own_cc).

    ``i_own_nn`` = integral of (n - n_wall)^2 over the wall (its own vertical-bending second
    moment, e.g. w t^3/12 for a skin, Eq. F.9); ``i_own_cc`` = integral of (c - c_wall)^2
    (e.g. w^3 t/12, Eq. F.10). Order: upper skin, front spar, lower skin, rear spar (F: 1-4).
    With ``stringers`` (:func:`stringer_layers`) the two smeared stiffener layers of the skins
    follow (upper, lower). ``weights`` = (upper, lower, front, rear) factors on each wall's area
    and own moments (a stiffener layer takes its skin's): the modulus- or density-weighted section
    of walls of other materials (the transformed section; positions unchanged, so exact).

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Outer width and height of the box (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float, array_like or casadi.SX
        Wall thicknesses (m).
    stringers : tuple or None, optional
        Smeared skin stiffeners ``((a_u, d_u, i_u), (a_l, d_l, i_l))`` of :func:`stringer_layers`;
        None for none.
    weights : sequence of 4 or None, optional
        Factors (upper, lower, front, rear) on each wall's area and own moments (-); None for 1.

    Returns
    -------
    list of tuple
        ``(area, c, n, i_own_nn, i_own_cc)`` per wall and stiffener layer (m^2, m, m, m^4, m^4).
    """
    h_web = h - t_upper_skin - t_lower_skin
    n_web = 0.5 * (t_lower_skin - t_upper_skin)
    walls = [
        (w * t_upper_skin, 0.0 * w, 0.5 * (h - t_upper_skin), w * t_upper_skin**3 / 12.0, w**3 * t_upper_skin / 12.0),
        (t_front_spar * h_web, 0.5 * (t_front_spar - w), n_web, t_front_spar * h_web**3 / 12.0,
         t_front_spar**3 * h_web / 12.0),
        (w * t_lower_skin, 0.0 * w, 0.5 * (t_lower_skin - h), w * t_lower_skin**3 / 12.0, w**3 * t_lower_skin / 12.0),
        (t_rear_spar * h_web, 0.5 * (w - t_rear_spar), n_web, t_rear_spar * h_web**3 / 12.0,
         t_rear_spar**3 * h_web / 12.0),
    ]
    if stringers is not None:
        walls += stringer_layers(w, h, t_upper_skin, t_lower_skin, stringers)
    if weights is not None:
        # walls are ordered upper skin, front spar, lower skin, rear spar, then the stiffener layers
        f = [weights[0], weights[2], weights[1], weights[3], weights[0], weights[1]][: len(walls)]
        walls = [(a * k, c, n, inn * k, icc * k) for (a, c, n, inn, icc), k in zip(walls, f)]
    return walls


def stringer_layers(w, h, t_upper_skin, t_lower_skin, stringers):
    """The skins' stiffeners smeared into two layers across the box width (Sec. 4.1's smearing,
    closed form): ``stringers = ((a_u, d_u, i_u), (a_l, d_l, i_l))`` gives, per skin, the
    stiffener area per unit width a (m), the depth d of the stiffeners' centroid below the skin's
    inner face (m) and their own second moment per unit width about that centroid i (m^3).
    Each layer is (area, c, n, i_own_nn, i_own_cc) as in :func:`box_walls`: area w a at
    n = +-(h/2 - t - d), own moments w i and w^3 a / 12. The layers carry axial stress and
    bending only; shear flows stay in the skins and webs (torsion constant, shear areas and
    shear centre of the bare box; docs/panels.md).

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Outer width and height of the box (m).
    t_upper_skin, t_lower_skin : float, array_like or casadi.SX
        Skin thicknesses (m).
    stringers : tuple
        ``((a_u, d_u, i_u), (a_l, d_l, i_l))`` (m, m, m^3).

    Returns
    -------
    list of tuple
        The upper and lower layer as ``(area, c, n, i_own_nn, i_own_cc)``.
    """
    (a_u, d_u, i_u), (a_l, d_l, i_l) = stringers
    return [(w * a_u, 0.0 * w, 0.5 * h - t_upper_skin - d_u, w * i_u, w**3 * a_u / 12.0),
            (w * a_l, 0.0 * w, t_lower_skin + d_l - 0.5 * h, w * i_l, w**3 * a_l / 12.0)]


def box_area(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, stringers=None, weights=None):
    """Material area A (Eq. F.1-F.5), m^2.

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Outer width and height of the box (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float, array_like or casadi.SX
        Wall thicknesses (m).
    stringers : tuple or None, optional
        Smeared skin stiffeners ``((a_u, d_u, i_u), (a_l, d_l, i_l))`` of :func:`stringer_layers`;
        None for none.
    weights : sequence of 4 or None, optional
        Factors (upper, lower, front, rear) on each wall's area and own moments (-); None for 1.

    Returns
    -------
    float, array_like or casadi.SX
        Area (m^2).
    """
    return sum(a for a, *_ in box_walls(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, stringers,
                                        weights))


def box_centroid(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, stringers=None, weights=None):
    """Modulus-weighted centroid (c_ea, n_ea) from the box centre (Eq. F.25-F.26), m.

    One material, so E cancels and this is the area centroid; it is also the mass centre
    (Eq. F.34-F.35) and the tension axis.

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Outer width and height of the box (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float, array_like or casadi.SX
        Wall thicknesses (m).
    stringers : tuple or None, optional
        Smeared skin stiffeners ``((a_u, d_u, i_u), (a_l, d_l, i_l))`` of :func:`stringer_layers`;
        None for none.
    weights : sequence of 4 or None, optional
        Factors (upper, lower, front, rear) on each wall's area and own moments (-); None for 1.

    Returns
    -------
    tuple
        (c_ea, n_ea) (m).
    """
    walls = box_walls(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, stringers, weights)
    area = sum(a for a, *_ in walls)
    return sum(a * c for a, c, *_ in walls) / area, sum(a * n for a, _, n, *_ in walls) / area


def box_inertia(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, stringers=None, weights=None):
    """(Ixx, Izz, Ixz) about the centroid (Eq. F.6-F.8 corrected), m^4.

    Ixx = int (n - n_ea)^2 dA (vertical bending), Izz = int (c - c_ea)^2 dA (chordwise
    bending), Ixz = +int (c - c_ea)(n - n_ea) dA (the standard product of area, positive when
    area sits in the (+c, +n) and (-c, -n) quadrants). The scanned F.6-F.8 multiply the
    parallel-axis term by the total area A_i; here each wall's own area is used (parallel-axis
    theorem), and F.8's leading minus (the tensor form) is moved to EI_cn = -E Ixz.

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Outer width and height of the box (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float, array_like or casadi.SX
        Wall thicknesses (m).
    stringers : tuple or None, optional
        Smeared skin stiffeners ``((a_u, d_u, i_u), (a_l, d_l, i_l))`` of :func:`stringer_layers`;
        None for none.
    weights : sequence of 4 or None, optional
        Factors (upper, lower, front, rear) on each wall's area and own moments (-); None for 1.

    Returns
    -------
    tuple
        (Ixx, Izz, Ixz) (m^4).
    """
    walls = box_walls(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, stringers, weights)
    area = sum(a for a, *_ in walls)
    c0 = sum(a * c for a, c, *_ in walls) / area
    n0 = sum(a * n for a, _, n, *_ in walls) / area
    i_xx = sum(inn + a * (n - n0) ** 2 for a, c, n, inn, icc in walls)
    i_zz = sum(icc + a * (c - c0) ** 2 for a, c, n, inn, icc in walls)
    i_xz = sum(a * (c - c0) * (n - n0) for a, c, n, inn, icc in walls)
    return i_xx, i_zz, i_xz


# --------------------------------------------------------------------------- midline (thin-walled)
def box_midline(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar):
    """Wall midline rectangle: (c_front, c_rear, n_lower, n_upper), m from the box centre.

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Outer width and height of the box (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float, array_like or casadi.SX
        Wall thicknesses (m).

    Returns
    -------
    tuple
        (c_front, c_rear, n_lower, n_upper) (m).
    """
    return (0.5 * (t_front_spar - w), 0.5 * (w - t_rear_spar),
            0.5 * (t_lower_skin - h), 0.5 * (h - t_upper_skin))


def box_enclosed_area(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar):
    """A_m, area enclosed by the wall midlines: (w - (t_f + t_r)/2)(h - (t_u + t_l)/2), m^2.

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Outer width and height of the box (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float, array_like or casadi.SX
        Wall thicknesses (m).

    Returns
    -------
    float, array_like or casadi.SX
        Enclosed midline area A_m (m^2).
    """
    return (w - 0.5 * (t_front_spar + t_rear_spar)) * (h - 0.5 * (t_upper_skin + t_lower_skin))


def box_torsion_constant(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, shear_weights=None):
    """Bredt-Batho torsion constant J = 4 A_m^2 / (closed integral of ds/t), m^4.

    Generalises Eq. F.29, which is this formula with the thickness pairs replaced by their
    arithmetic means (docs/section.md). ``shear_weights`` (upper, lower, front, rear): walls of
    other shear moduli, G_wall / G in the loop integral (the transformed section, exact).

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Outer width and height of the box (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float, array_like or casadi.SX
        Wall thicknesses (m).
    shear_weights : sequence of 4 or None, optional
        G_wall / G factors (upper, lower, front, rear) (-); None for 1.

    Returns
    -------
    float, array_like or casadi.SX
        Torsion constant J (m^4).
    """
    g_u, g_l, g_f, g_r = (1.0, 1.0, 1.0, 1.0) if shear_weights is None else shear_weights
    b = w - 0.5 * (t_front_spar + t_rear_spar)
    d = h - 0.5 * (t_upper_skin + t_lower_skin)
    loop = b / (t_upper_skin * g_u) + b / (t_lower_skin * g_l) + d / (t_front_spar * g_f) + d / (t_rear_spar * g_r)
    return 4.0 * (b * d) ** 2 / loop


def _midline_segments(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar):
    """Closed midline loop as (start point, end point, thickness), circulating in the
    positive-torsion sense (upper skin aft, rear spar down, lower skin forward, front spar up)."""
    cf, cr, nl, nu = box_midline(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar)
    return [((cf, nu), (cr, nu), t_upper_skin), ((cr, nu), (cr, nl), t_rear_spar),
            ((cr, nl), (cf, nl), t_lower_skin), ((cf, nl), (cf, nu), t_front_spar)]


def _closed_flow_resultant(segments, c_m, n_m, alpha, beta):
    """Resultant (F_c, F_n, M_s about the box centre) of the closed-cell shear flow caused by
    an axial stress gradient d(sigma)/ds_span = alpha (c - c_m) + beta (n - n_m) (no twist).

    Wall equilibrium dq/ds = -t d(sigma)/ds_span makes q quadratic along each straight wall,
    so Simpson's rule integrates q and q/t exactly. The constant closing flow q0 follows from
    zero twist (closed integral of q/t ds = 0).
    """
    q = 0.0
    flows = []  # (q_start, q_mid, q_end, length, thickness, dc, dn, lever)
    for (c0, n0), (c1, n1), t in segments:
        dc, dn = c1 - c0, n1 - n0
        length = sqrt(dc**2 + dn**2)

        def g(frac):
            return alpha * (c0 + frac * dc - c_m) + beta * (n0 + frac * dn - n_m)

        q_mid = q - t * 0.5 * length * g(0.25)
        q_end = q - t * length * g(0.5)
        lever = (n0 * dc - c0 * dn) / length  # (r x unit tangent)_s, constant on the wall
        flows.append((q, q_mid, q_end, length, t, dc, dn, lever))
        q = q_end
    twist = sum(L / (6.0 * t) * (qa + 4.0 * qm + qb) for qa, qm, qb, L, t, *_ in flows)
    q0 = -twist / sum(L / t for _, _, _, L, t, *_ in flows)
    f_c = f_n = m_s = 0.0
    for qa, qm, qb, L, _t, dc, dn, lever in flows:
        integral = L / 6.0 * (qa + 4.0 * qm + qb) + q0 * L
        f_c = f_c + integral * dc / L
        f_n = f_n + integral * dn / L
        m_s = m_s + integral * lever
    return f_c, f_n, m_s


def box_shear_centre(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar):
    """Shear centre (c_sc, n_sc) of the closed thin-walled box, m from the box centre.

    Thin-walled midline model: the shear flows of two independent axial-stress gradients
    (along c and along n, about the midline centroid) are closed by zero twist; the
    combinations giving a unit vertical and a unit chordwise shear locate the lines of
    action, c_sc = -M_s(V_n = 1) and n_sc = M_s(V_c = 1). Symmetric walls give the centre;
    a thicker spar pulls the shear centre toward itself (docs/section.md).

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Outer width and height of the box (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float, array_like or casadi.SX
        Wall thicknesses (m).

    Returns
    -------
    tuple
        (c_sc, n_sc) (m).
    """
    segs = _midline_segments(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar)
    weights = [(t * sqrt((c1 - c0) ** 2 + (n1 - n0) ** 2), 0.5 * (c0 + c1), 0.5 * (n0 + n1))
               for (c0, n0), (c1, n1), t in segs]
    a_mid = sum(a for a, _, _ in weights)
    c_m = sum(a * c for a, c, _ in weights) / a_mid
    n_m = sum(a * n for a, _, n in weights) / a_mid
    fc1, fn1, m1 = _closed_flow_resultant(segs, c_m, n_m, 1.0, 0.0)
    fc2, fn2, m2 = _closed_flow_resultant(segs, c_m, n_m, 0.0, 1.0)
    det = fc1 * fn2 - fc2 * fn1
    m_unit_vn = (-fc2 * m1 + fc1 * m2) / det
    m_unit_vc = (fn2 * m1 - fn1 * m2) / det
    return -m_unit_vn, m_unit_vc


def box_first_moments(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, stringers=None, weights=None):
    """(Qx, Qz): first moments of area for the V Q / (I t) shear (Eq. F.32-F.33 corrected), m^3.

    Qx: area above the horizontal centroidal axis n = n_ea about that axis (vertical shear):
        w t_u (h/2 - t_u/2 - n_ea) + (t_f + t_r)(h/2 - t_u - n_ea)^2 / 2.
    Qz: area forward of the vertical centroidal axis c = c_ea about that axis (chordwise shear):
        t_f h_web (w/2 + c_ea - t_f/2) + (t_u + t_l)(w/2 + c_ea)^2 / 2, h_web = h - t_u - t_l

    (skins span the full width, Eq. F.2/F.4; the scan's F.33 uses h and t_left instead).
    Valid while the centroidal axes cross the webs and skins, i.e. for any practical box.
    With ``stringers`` (:func:`stringer_layers`) the upper layer adds w a_u (n_u - n_ea) to Qx
    (it lies above the axis) and both layers add (a_u + a_l)(w/2 + c_ea)^2 / 2 to Qz.

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Outer width and height of the box (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float, array_like or casadi.SX
        Wall thicknesses (m).
    stringers : tuple or None, optional
        Smeared skin stiffeners ``((a_u, d_u, i_u), (a_l, d_l, i_l))`` of :func:`stringer_layers`;
        None for none.
    weights : sequence of 4 or None, optional
        Factors (upper, lower, front, rear) on each wall's area and own moments (-); None for 1.

    Returns
    -------
    tuple
        (Qx, Qz) (m^3).
    """
    c0, n0 = box_centroid(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, stringers, weights)
    f_u, f_l, f_f, f_r = (1.0, 1.0, 1.0, 1.0) if weights is None else weights
    h_web = h - t_upper_skin - t_lower_skin
    q_x = (w * t_upper_skin * f_u * (0.5 * h - 0.5 * t_upper_skin - n0)
           + 0.5 * (t_front_spar * f_f + t_rear_spar * f_r) * (0.5 * h - t_upper_skin - n0) ** 2)
    q_z = (t_front_spar * f_f * h_web * (0.5 * w + c0 - 0.5 * t_front_spar)
           + 0.5 * (t_upper_skin * f_u + t_lower_skin * f_l) * (0.5 * w + c0) ** 2)
    if stringers is not None:
        (a_u, _, _), (a_l, _, _) = stringers
        upper = stringer_layers(w, h, t_upper_skin, t_lower_skin, stringers)[0]
        q_x = q_x + f_u * upper[0] * (upper[2] - n0)
        q_z = q_z + 0.5 * (a_u * f_u + a_l * f_l) * (0.5 * w + c0) ** 2
    return q_x, q_z


def box_shear_areas(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, shear_weights=None):
    """(K_c, K_n): shear areas of Eq. A.7, m^2. Chordwise shear is carried by the skins,
    K_c = w (t_u + t_l); vertical shear by the spar webs, K_n = (h - t_u - t_l)(t_f + t_r);
    ``shear_weights`` (upper, lower, front, rear) weight each wall by G_wall / G.

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Outer width and height of the box (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float, array_like or casadi.SX
        Wall thicknesses (m).
    shear_weights : sequence of 4 or None, optional
        G_wall / G factors (upper, lower, front, rear) (-); None for 1.

    Returns
    -------
    tuple
        (K_c, K_n) (m^2).
    """
    g_u, g_l, g_f, g_r = (1.0, 1.0, 1.0, 1.0) if shear_weights is None else shear_weights
    return (w * (t_upper_skin * g_u + t_lower_skin * g_l),
            (h - t_upper_skin - t_lower_skin) * (t_front_spar * g_f + t_rear_spar * g_r))


# --------------------------------------------------------------------------- beam data
def _matrix(rows, symbolic):
    if symbolic:
        return ca.vertcat(*[ca.horzcat(*r) for r in rows])
    rows = [[np.asarray(x, dtype=float) for x in r] for r in rows]
    shape = np.broadcast_shapes(*[x.shape for r in rows for x in r])
    return np.stack([np.stack([np.broadcast_to(x, shape) for x in r], axis=-1) for r in rows], axis=-2)


def _rotate(rot, mat, symbolic):
    """R M R^T (Eq. F.31)."""
    if symbolic:
        return ca.mtimes(rot, ca.mtimes(mat, rot.T))
    return np.einsum("...ij,...jk,...lk->...il", rot, mat, rot)


def _rotate_offset(rot, c, n, symbolic):
    """csn components (c, n) of R [c, 0, n] (an offset in the section plane)."""
    if symbolic:
        v = ca.mtimes(rot, ca.vertcat(c, 0.0, n))
        return v[0], v[2]
    rot = np.asarray(rot, dtype=float)
    return rot[..., 0, 0] * c + rot[..., 0, 2] * n, rot[..., 2, 0] * c + rot[..., 2, 2] * n


def beam_data(props: dict, material, section_to_csn=None, nonstructural_mass_per_length=0.0) -> dict:
    """Add the beam inputs of App. A to ``props`` (A, Ixx, Izz, Ixz, J, K_c, K_n and offsets).

    * ``stiffness_csn`` (Eq. A.6 via F.30-F.31): R [[E Ixx, 0, -E Ixz], [0, G J, 0],
      [-E Ixz, 0, E Izz]] R^T, ordering (c, s, n), about the centroid. The sign of the
      coupling follows from eps = eps0 + kappa_n c - kappa_c n with M_c = -int n sigma dA,
      M_n = int c sigma dA (docs/section.md).
    * ``compliance_csn`` (diagonal of Eq. A.7): [1/(G K_c), 1/(E A), 1/(G K_n)].
    * ``mass_per_length`` = rho A + nonstructural mass (taken at the mass centre, no rotary inertia).
    * ``inertia_per_length`` (tensor form, about the mass centre): R [[rho Ixx, 0, -rho Ixz],
      [0, rho (Ixx + Izz), 0], [-rho Ixz, 0, rho Izz]] R^T.
    * offsets (c_ea, n_ea), (c_sc, n_sc), (c_cg, n_cg) rotated by R into csn.

    Parameters
    ----------
    props : dict
        Section properties (``A``, ``Ixx``, ``Izz``, ``Ixz``, ``J``, ``K_c``, ``K_n`` and the
        offsets), as :func:`box_properties` builds them.
    material : Material
        Isotropic material of the section.
    section_to_csn : array_like or None, optional
        (3, 3) rotation R from the section's own axes to the csn frame; None when they coincide.
    nonstructural_mass_per_length : float, optional
        Mass per length added at the mass centre (kg/m).

    Returns
    -------
    dict
        ``props`` with the beam inputs added.
    """
    E, G, rho = material.E, material.G, material.rho
    i_xx, i_zz, i_xz = props["Ixx"], props["Izz"], props["Ixz"]
    symbolic = is_symbolic(i_xx, i_zz, i_xz, section_to_csn, nonstructural_mass_per_length)
    zero = 0.0 * i_xx
    out = dict(props)
    out["EA"] = E * props["A"]
    out["GJ"] = G * props["J"]
    out["EIxx"] = E * i_xx
    out["EIzz"] = E * i_zz
    stiff = _matrix([[E * i_xx, zero, -E * i_xz], [zero, G * props["J"], zero], [-E * i_xz, zero, E * i_zz]],
                    symbolic)
    inertia = _matrix([[rho * i_xx, zero, -rho * i_xz], [zero, rho * (i_xx + i_zz), zero],
                       [-rho * i_xz, zero, rho * i_zz]], symbolic)
    if section_to_csn is not None:
        stiff = _rotate(section_to_csn, stiff, symbolic)
        inertia = _rotate(section_to_csn, inertia, symbolic)
        for c_key, n_key in (("c_ea", "n_ea"), ("c_sc", "n_sc"), ("c_cg", "n_cg")):
            out[c_key], out[n_key] = _rotate_offset(section_to_csn, props[c_key], props[n_key], symbolic)
    out["stiffness_csn"] = stiff
    k_c, k_n = props["K_c"], props["K_n"]
    comp = [1.0 / (G * k_c), 1.0 / (E * props["A"]), 1.0 / (G * k_n)]
    out["compliance_csn"] = ca.vertcat(*comp) if symbolic else np.stack(np.broadcast_arrays(*comp), axis=-1)
    out["mass_per_length"] = rho * props["A"] + nonstructural_mass_per_length
    out["inertia_per_length"] = inertia
    return out


def box_properties(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, material,
                   section_to_csn=None, nonstructural_mass_per_length=0.0, stringers=None, weights=None,
                   shear_weights=None) -> dict:
    """All box section outputs (names as in ``BoxSection``) for one material.

    ``stringers``: the skins' smeared stiffeners (:func:`stringer_layers`); they add to the area,
    centroid, bending moments of area, first moments and mass; torsion constant, shear areas and
    shear centre are those of the bare box (the stiffeners carry no shear flow). ``weights``:
    factors on the walls' areas (:func:`box_walls`) for area, centroid, bending and first moments;
    ``shear_weights``: G_wall / G factors for the torsion constant and shear areas.

    Parameters
    ----------
    w, h : float, array_like or casadi.SX
        Outer width and height of the box (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float, array_like or casadi.SX
        Wall thicknesses (m).
    material : Material
        Reference material of the section.
    section_to_csn : array_like or None, optional
        (3, 3) rotation R from the section's own axes to the csn frame; None when they coincide.
    nonstructural_mass_per_length : float, optional
        Mass per length added at the mass centre (kg/m).
    stringers : tuple or None, optional
        Smeared skin stiffeners ``((a_u, d_u, i_u), (a_l, d_l, i_l))`` of :func:`stringer_layers`;
        None for none.
    weights : sequence of 4 or None, optional
        Factors (upper, lower, front, rear) on each wall's area and own moments (-); None for 1.
    shear_weights : sequence of 4 or None, optional
        G_wall / G factors (upper, lower, front, rear) (-); None for 1.

    Returns
    -------
    dict
        Section outputs keyed as ``BoxSection``'s.
    """
    args = (w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar)
    c_ea, n_ea = box_centroid(*args, stringers, weights)
    c_sc, n_sc = box_shear_centre(*args)
    i_xx, i_zz, i_xz = box_inertia(*args, stringers, weights)
    q_x, q_z = box_first_moments(*args, stringers, weights)
    k_c, k_n = box_shear_areas(*args, shear_weights)
    props = {"A": box_area(*args, stringers, weights), "Ixx": i_xx, "Izz": i_zz, "Ixz": i_xz, "J": box_torsion_constant(*args, shear_weights),
             "c_ea": c_ea, "n_ea": n_ea, "c_sc": c_sc, "n_sc": n_sc, "c_cg": c_ea, "n_cg": n_ea,
             "Qx": q_x, "Qz": q_z, "K_c": k_c, "K_n": k_n}
    return beam_data(props, material, section_to_csn, nonstructural_mass_per_length)


#: the section properties a beam needs (:func:`beam_params_from_section`)
SECTION_BEAM_KEYS = ("stiffness_csn", "compliance_csn", "c_ea", "n_ea", "c_sc", "n_sc", "mass_per_length",
                     "c_cg", "n_cg", "inertia_per_length")


def beam_params_from_section(props: dict, node_positions=None, node_euler_angles=None) -> dict:
    """Beam parameters (``param_specs`` names of :mod:`wingmdao.beam.residual`) from section
    properties: the one place where the parameter dict is built from a section.

    Parameters
    ----------
    props : dict
        :data:`SECTION_BEAM_KEYS` of one section (scalars, 3x3) or per node (arrays with a leading
        node axis), e.g. ``box_properties`` of per-station walls.
    node_positions, node_euler_angles : array_like, optional
        (n, 3) each; left out of the result when None (the section part only).

    Returns
    -------
    dict
        ``stiffness_csn``, ``compliance_csn``, ``tension_axis`` (c_ea, n_ea), ``shear_center``
        (c_sc, n_sc), ``mass_per_length``, ``mass_center`` (c_cg, n_cg), ``inertia_per_length``
        (3 x 3 per node), float arrays; ``node_positions``, ``node_euler_angles`` first when given.
    """
    f = {k: np.asarray(props[k], dtype=float) for k in SECTION_BEAM_KEYS}
    out = {} if node_positions is None else {"node_positions": np.asarray(node_positions, dtype=float),
                                             "node_euler_angles": np.asarray(node_euler_angles, dtype=float)}
    out.update({
        "stiffness_csn": f["stiffness_csn"],
        "compliance_csn": f["compliance_csn"],
        "tension_axis": np.stack([f["c_ea"], f["n_ea"]], axis=-1),
        "shear_center": np.stack([f["c_sc"], f["n_sc"]], axis=-1),
        "mass_per_length": f["mass_per_length"],
        "mass_center": np.stack([f["c_cg"], f["n_cg"]], axis=-1),
        "inertia_per_length": f["inertia_per_length"].reshape(f["mass_per_length"].shape + (3, 3)),
    })
    return out


def beam_params_from_rows(rows, node_positions, node_euler_angles) -> dict:
    """Beam parameters (``param_specs`` names) from per-node section rows of ``box_properties`` /
    ``solid_properties`` (:func:`beam_params_from_section` of the rows stacked).

    Parameters
    ----------
    rows : sequence of dict
        Per-node section outputs of :func:`box_properties` or ``solid_properties``.
    node_positions : array_like
        (n, 3) node positions (m).
    node_euler_angles : array_like
        (n, 3) node Euler angles (rad).

    Returns
    -------
    dict
        Beam parameters by ``param_specs`` name.
    """
    stacked = {k: np.array([r[k] for r in rows], dtype=float) for k in SECTION_BEAM_KEYS}
    return beam_params_from_section(stacked, node_positions, node_euler_angles)


# --------------------------------------------------------------------------- validation
def _station_error(name, values, bad, low, high, source, where=None):
    i = int(bad[0])
    at = f" at station {i}" if where is None else where
    return ValueError(f"{source}{name} = {float(values[i]):.6g} m{at}; allowed range "
                      f"({low[i] if np.ndim(low) else low:.6g}, {high[i] if np.ndim(high) else high:.6g}) m")


def validate_box(width, height, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, source="",
                 labels=None) -> None:
    """Raise ``ValueError`` naming the input, the station and the allowed range (m).

    All dimensions must be positive and finite; t_upper + t_lower < height (a web remains);
    t_front + t_rear < width. ``labels`` maps an input name (``width``, ``t_upper_skin``, ...) to
    the name the user gave it (a command-line flag such as ``--t-skin``); two walls with the same
    label (one flag for both skins) are checked as 2 t < height. The allowed range is never empty:
    when the other wall alone is too thick, the message names the sum instead.

    Parameters
    ----------
    width, height : float or array_like
        Outer box dimensions (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float or array_like
        Wall thicknesses (m).
    source : str, optional
        Input and station named in the error.
    labels : dict or None, optional
        Input name -> the name the user gave it (e.g. ``--t-skin``).
    """
    label = (lambda k: (labels or {}).get(k, k))
    vals = {name: np.atleast_1d(np.asarray(v, dtype=float)) for name, v in
            zip(("width", "height") + WALL_NAMES, (width, height, t_upper_skin, t_lower_skin, t_front_spar,
                                                   t_rear_spar))}
    n = max(v.size for v in vals.values())
    for name, v in vals.items():
        bad = np.flatnonzero(~(np.isfinite(v) & (v > 0.0)))
        if bad.size:
            raise _station_error(label(name), v, bad, 0.0, np.inf, source, None if n > 1 else "")
    vals = {k: np.broadcast_to(v, (n,)) for k, v in vals.items()}
    for pair, total in ((("t_upper_skin", "t_lower_skin"), "height"), (("t_front_spar", "t_rear_spar"), "width")):
        a, b = pair
        for this, other in ((a, b), (b, a)):
            high = vals[total] - vals[other]
            bad = np.flatnonzero(vals[this] >= high)
            if bad.size:
                i = int(bad[0])
                at = f" at station {i}" if n > 1 else ""
                walls = "skins" if "skin" in a else "spar webs"
                if label(a) == label(b):
                    raise ValueError(f"{source}{label(this)} = {vals[this][i]:.6g} m{at}: the two {walls} must be "
                                     f"thinner together than {label(total)} = {vals[total][i]:.6g} m; allowed range "
                                     f"(0, {vals[total][i] / 2:.6g}) m")
                if high[i] <= 0.0:  # the other wall alone fills the box: no range for this one
                    raise ValueError(f"{source}{label(a)} + {label(b)} = {vals[a][i]:.6g} + {vals[b][i]:.6g} m{at}; "
                                     f"the two {walls} must be thinner together than {label(total)} = "
                                     f"{vals[total][i]:.6g} m")
                raise ValueError(f"{source}{label(this)} = {vals[this][i]:.6g} m{at}: {label(a)} + {label(b)} must be "
                                 f"less than {label(total)} = {vals[total][i]:.6g} m; allowed range "
                                 f"(0, {high[i]:.6g}) m")
