"""Free roll of the aircraft: the antisymmetric half wing on a fuselage free to roll (docs/maneuvers.md, "Rolling conditions").

With ``roll=True`` :func:`wingmdao.aero.system.build_aeroelastic_system` models the antisymmetric
motion of the aircraft: the right half wing (body axes x aft, y outboard right, z up, origin O at
the symmetry plane) is clamped at its root to a fuselage that rolls about the body x axis, the left
half wing mirrors it antisymmetrically (its ailerons deflected opposite, its deformation and loads
the negatives of the right's, mirrored), so that the two halves' rolling moments about x add and
their vertical forces cancel: the body neither plunges nor pitches. The rigid-body states are the
roll angle phi and the roll rate p (positive about +x: the right wing goes up). The fuselage's roll
inertia about x, I_xx,body (the aircraft outside both wing halves), is shared by the two halves;
each carries ``body_roll_inertia`` = I_xx,body / 2, with the root moment of its half wing about
the x axis through O (F, M what the wing exerts on the body at the root node r_0, as in
:mod:`wingmdao.aero.pitch`):

    (I_xx,body / 2) dp/dt = M_x + y_0 F_z - z_0 F_y
    dphi/dt = p

(p, 0, 0) and (dp/dt, 0, 0) add to the frame's angular velocity and acceleration of the beam (its
inertia: the wings' own roll inertia is in the root loads) and of the aerodynamics (Omega x r
gives each strip the normal velocity p y, carried by its Wagner/Kuessner states). Gravity and the
1 g trim are left out: the antisymmetric loads are increments on the symmetric flight (the
superposition of 14 CFR 25.349(a)), so ``gravity`` is zero and the roll angle enters no load. One
degree of freedom: no sideslip or yaw (the rolling conditions' usual analysis; the yaw of a rolling
airplane changes the wing loads little).
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.aero.plunge import trapezoid_node_weights
from wingmdao.timemarch.system import VarSpec

#: the roll states (after the node blocks; system.body_index maps them to their state indices)
ROLL_STATE_NAMES = ("roll_angle", "roll_rate")


def roll_param_specs() -> list[VarSpec]:
    """Parameters of the free-roll rows.

    Returns
    -------
    list of VarSpec
        ``body_roll_inertia``.
    """
    return [VarSpec("body_roll_inertia", (), "kg*m**2", "roll inertia about the body x axis of the aircraft outside "
                    "both wing halves, per half wing: I_xx,body / 2")]


def roll_forcing_specs() -> list[VarSpec]:
    """Forcing of the free-roll rows at one instant.

    Returns
    -------
    list of VarSpec
        ``roll_start``.
    """
    return [VarSpec("roll_start", (), None, "1: the roll angle is zero (the initial static state at t = 0); "
                    "0: dphi/dt = p")]


def check_roll_inputs(**values) -> None:
    """ValueError (input, value, allowed range, SI) for bad free-roll inputs; checks those given.

    Parameters
    ----------
    **values
        Inputs by name: ``body_roll_inertia``, ``roll_inertia`` (kg m^2).
    """
    for name, v in values.items():
        val = float(np.real(v))
        if not (np.isfinite(val) and val > 0):
            raise ValueError(f"{name} = {val} kg*m**2; allowed range (0, inf) kg*m**2")


def roll_residuals(x_r, xd_r, *, F0, M0, r0, pars, start):
    """CasADi rows of the rolling body: ``dphi/dt - p`` (``phi`` while ``start`` = 1: the roll
    angle, which enters no load, is fixed in the initial static state) and the roll moment balance
    ``(I_xx,body / 2) dp/dt - (M_x + y_0 F_z - z_0 F_y)`` (module docstring).

    Parameters
    ----------
    x_r : casadi.SX
        Roll states (phi, p) (rad, rad/s).
    xd_r : casadi.SX
        Their rates.
    F0 : casadi.SX, shape (3,)
        Root force of the half wing on the body (N), body axes.
    M0 : casadi.SX, shape (3,)
        Root moment of the half wing on the body (N m), body axes.
    r0 : casadi.SX or ndarray, shape (3,)
        Root node position (m).
    pars : dict
        ``body_roll_inertia`` as a CasADi symbol.
    start : casadi.SX
        The forcing ``roll_start`` (1: phi = 0; 0: dphi/dt = p).

    Returns
    -------
    casadi.SX
        The two rows.
    """
    moment = M0[0] + r0[1] * F0[2] - r0[2] * F0[1]
    return ca.vertcat(start * x_r[0] + (1.0 - start) * (xd_r[0] - x_r[1]),
                      pars["body_roll_inertia"] * xd_r[1] - moment)


def half_wing_roll_inertia(mass_per_length, node_positions):
    """Roll inertia (kg m^2) of one half wing about the body x axis, mass lumped at the nodes with
    trapezoid weights (as :func:`wingmdao.aero.pitch.half_wing_pitch_moments`; the sections' own
    rotary inertia left out).

    Parameters
    ----------
    mass_per_length : array_like, shape (n,)
        Mass per length at the nodes (kg/m).
    node_positions : array_like, shape (n, 3)
        Node positions (m), body axes.

    Returns
    -------
    float
        sum_i m_i (y_i^2 + z_i^2) (kg m^2).
    """
    mu, r = np.asarray(mass_per_length, dtype=float), np.asarray(node_positions, dtype=float)
    return float(np.sum(trapezoid_node_weights(r) * mu * (r[:, 1] ** 2 + r[:, 2] ** 2)))


def steady_roll(system, p, q, x0=None, *, tol=1e-9, max_iterations=30):
    """The steady roll of a ``roll=True`` system: the state with every rate zero except
    dphi/dt = p (the roll rate constant, the wing's deformation and lag states steady), phi = 0.
    Newton's method on ``R(x, xdot(x)) = 0`` with ``xdot = e_phi x_p`` and the phi row replaced by
    phi = 0 (the roll angle enters no load).

    Parameters
    ----------
    system : AeroelasticBeamSystem
        Built with ``roll=True``.
    p : numpy.ndarray
        Packed parameters.
    q : numpy.ndarray
        Packed forcing (gravity zero; the surfaces' command).
    x0 : numpy.ndarray, optional
        Start (default: the system's initial guess).
    tol : float, optional
        Converged when the largest residual is below tol times the largest at the start (or 1e-8).
    max_iterations : int, optional
        Most Newton steps.

    Returns
    -------
    numpy.ndarray
        The steady state (n_state,).
    """
    if not getattr(system, "roll", False):
        raise ValueError("steady_roll needs a system built with roll=True")
    i_phi, i_p = system.body_index["roll_angle"], system.body_index["roll_rate"]
    x = np.array(system.initial_guess(p, q) if x0 is None else x0, dtype=float)
    x[i_phi] = 0.0

    def rates(x_):
        xd = np.zeros_like(x_)
        xd[i_phi] = x_[i_p]
        return xd

    def res(x_):
        r = np.asarray(system.residual(x_, rates(x_), p, q), dtype=float).ravel()
        r[i_phi] = x_[i_phi]
        return r

    r = res(x)
    scale = max(float(np.max(np.abs(r))), 1.0)
    for _ in range(max_iterations):
        if np.max(np.abs(r)) <= max(tol * scale, 1e-8):
            return x
        Jx, Jd = system.jac_state(x, rates(x), p, q)
        J = sp.lil_matrix(sp.csr_matrix(Jx) + sp.csr_matrix(Jd)[:, [i_phi]] @ sp.csr_matrix(
            ([1.0], ([0], [i_p])), shape=(1, x.size)))
        J[i_phi, :] = 0.0
        J[i_phi, i_phi] = 1.0
        x = x - spla.spsolve(J.tocsc(), r)
        r = res(x)
    raise RuntimeError(f"steady_roll: Newton did not converge in {max_iterations} steps (largest residual "
                       f"{np.max(np.abs(r)):.3g})")
