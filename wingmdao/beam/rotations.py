"""Euler-angle rotations of the beam's local csn frames (App. A, Eq. A.1 and A.3).

Angles are stored by the body axis they turn about: ``theta = (phi, vartheta, psi)`` =
(about x, twist about the beam axis s, about z). The *surface* sequence (ASWING's, used
for wings) applies phi about x first (dihedral / bending roll-up), then psi about the new
n axis (sweep / in-plane bending), then the twist vartheta about the new s axis:

    T(theta) = C_y(vartheta) C_z(psi) C_x(phi),   body components -> csn components.

``C_k(a)`` is the passive (frame) rotation by +a about axis k. The Euler-rate / curvature
matrix K (Eq. A.3, derived in docs/beam-theory.md) gives the frame's angular velocity in
csn components, ``omega_csn = K(theta) dtheta/dt``, and its curvature
``kappa_csn = K(theta) dtheta/ds``. det K = cos(psi): the sequence is singular only when
the beam axis points chordwise (``|psi|`` -> 90 deg); roll-up about x and twist are unlimited.

All functions work on numpy arrays and on CasADi SX/MX symbols.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

#: Supported Euler sequences.
SEQUENCES = ("surface",)


def _lib(a):
    return np if isinstance(a, (float, int, np.ndarray, np.generic)) else ca


def _mat(rows, like):
    if _lib(like) is np:
        return np.array(rows, dtype=float)
    return ca.vertcat(*[ca.horzcat(*r) for r in rows])


def rot_x(a):
    """Passive rotation by ``a`` about x (body -> rotated frame components).

    Parameters
    ----------
    a : float or casadi.SX or casadi.MX
        Angle (rad).

    Returns
    -------
    ndarray or casadi matrix, shape (3, 3)
        The rotation matrix.
    """
    m = _lib(a)
    c, s = m.cos(a), m.sin(a)
    return _mat([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]], a)


def rot_y(a):
    """Passive rotation by ``a`` about y.

    Parameters
    ----------
    a : float or casadi.SX or casadi.MX
        Angle (rad).

    Returns
    -------
    ndarray or casadi matrix, shape (3, 3)
        The rotation matrix.
    """
    m = _lib(a)
    c, s = m.cos(a), m.sin(a)
    return _mat([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]], a)


def rot_z(a):
    """Passive rotation by ``a`` about z.

    Parameters
    ----------
    a : float or casadi.SX or casadi.MX
        Angle (rad).

    Returns
    -------
    ndarray or casadi matrix, shape (3, 3)
        The rotation matrix.
    """
    m = _lib(a)
    c, s = m.cos(a), m.sin(a)
    return _mat([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]], a)


def _check_sequence(sequence):
    if sequence not in SEQUENCES:
        raise ValueError(f"euler_sequence must be one of {SEQUENCES}, got {sequence!r}")


def body_to_csn(theta, sequence="surface"):
    """T(theta) of Eq. A.1: maps body components (x, y, z) to local (c, s, n) components.

    Parameters
    ----------
    theta : sequence of 3 (float or casadi symbol)
        Euler angles ``(phi, vartheta, psi)`` (rad).
    sequence : str
        Euler sequence; only ``"surface"`` (:data:`SEQUENCES`).

    Returns
    -------
    ndarray or casadi matrix, shape (3, 3)
        T(theta).
    """
    _check_sequence(sequence)
    phi, twist, psi = theta[0], theta[1], theta[2]
    return rot_y(twist) @ rot_z(psi) @ rot_x(phi)


def rate_matrix(theta, sequence="surface"):
    """K(theta) of Eq. A.3: ``omega_csn = K dtheta/dt`` and ``kappa_csn = K dtheta/ds``.

    Columns: C_y C_z e_x (phi rate), e_y (twist rate), C_y e_z (psi rate).

    Parameters
    ----------
    theta : sequence of 3 (float or casadi symbol)
        Euler angles ``(phi, vartheta, psi)`` (rad).
    sequence : str
        Euler sequence; only ``"surface"`` (:data:`SEQUENCES`).

    Returns
    -------
    ndarray or casadi matrix, shape (3, 3)
        K(theta).
    """
    _check_sequence(sequence)
    twist, psi = theta[1], theta[2]
    m = _lib(twist)
    cv, sv, cp, sp = m.cos(twist), m.sin(twist), m.cos(psi), m.sin(psi)
    # C_y(vt) C_z(psi) e_x = C_y(vt) (cos psi, -sin psi, 0);  C_y(vt) e_z = (-sin vt, 0, cos vt)
    return _mat([[cv * cp, 0.0, -sv], [-sp, 1.0, 0.0], [sv * cp, 0.0, cv]], twist)


def euler_from_axis(tangent, twist=0.0):
    """Surface-sequence angles (phi, twist, psi) whose s axis is the unit vector ``tangent``.

    s = T^T e_s = (-sin psi, cos psi cos phi, cos psi sin phi), so
    phi = atan2(t_z, t_y) and psi = atan2(-t_x, hypot(t_y, t_z)).

    Parameters
    ----------
    tangent : array_like, shape (3,)
        Direction of the s axis in body axes (normalized here).
    twist : float
        Twist angle vartheta (rad), stored as given.

    Returns
    -------
    ndarray, shape (3,)
        ``(phi, vartheta, psi)`` (rad).
    """
    t = np.asarray(tangent, dtype=float)
    t = t / np.linalg.norm(t)
    return np.array([np.arctan2(t[2], t[1]), float(twist), np.arctan2(-t[0], np.hypot(t[1], t[2]))])
