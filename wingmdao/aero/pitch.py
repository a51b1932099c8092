"""Free pitch of the aircraft: rigid-body pitch states, horizontal tail, body pitch inertia (docs/aeroelasticity.md).

With ``pitch=True`` :func:`wingmdao.aero.system.build_aeroelastic_system` frees the aircraft in
plunge *and* pitch. Body axes (x aft, y outboard right, z up) are those of the aircraft, origin O
at the symmetry plane; the rigid-body states are the upward velocity w_p of O (the plunge state),
the pitch-attitude increment theta_p and the pitch rate q (nose up = + about y), optionally the
lagged downwash angle e, and the tail incidence i_t (a trim unknown). The "body" is the aircraft
outside both wing halves (fuselage, tail, payload): mass m_b, first moments s = m_b (x_b, z_b)
about O and pitch inertia I_O about O's y axis. With the two half-wings' root force F and moment
M (what the wing exerts on the body at the root node r_0, docs/conventions.md) and the tail lift
L_t acting at x_t (Newton-Euler of a rigid body about the accelerating point O, small angles):

    m_b (dw_p/dt - g_z) - s_x dq/dt - s_z q^2       = 2 F_z + L_t
    I_O dq/dt - s_x dw_p/dt                          = s_z g_x - s_x g_z + 2 (z_0 F_x - x_0 F_z + M_y) - x_t L_t
    dtheta_p/dt = q

Tail (quasi-steady; Etkin & Reid, *Dynamics of Flight*, 3rd ed., 1996, Sec. 2.4; Nelson,
*Flight Stability and Automatic Control*, 2nd ed., 1998, Sec. 2.4): ``L_t = 1/2 rho V^2 S_t a_t
alpha_t`` with

    alpha_t = alpha_trim + theta_p - w_p/V + q x_t / V + w_g,t / V - deps/dalpha e + i_t
    e = alpha_w = alpha_trim + theta_p - w_p/V + w_g,root / V        (no lag), or
    (x_t / V) de/dt + e = alpha_w                                     (tail_lag: first-order lag)

With an elevator (``elevator=True`` of the build) the tail angle gains ``tau_e delta``: the tail
lift increment ``L_t,delta = 1/2 rho V^2 S_t a_t tau_e delta`` (Etkin & Reid 1996, Sec. 2.4, the
elevator effectiveness tau_e = a_e / a_t; delta in rad, trailing edge down +, a nose-down
moment), and delta is the state of a first-order actuator driven by the forcing ``elevator_command``:

    t_a d(delta)/dt + delta = delta_cmd        (t_a = ``elevator_time_constant``, s)

:func:`elevator_effectiveness` gives tau_e of a plain flap from thin-airfoil theory.

(w_g,t the gust at the tail, w_g,root the gust at the root station). The pitch attitude adds to
every wing station's angle (as alpha_trim does) and (0, q, 0), (0, dq/dt, 0) add to the frame's
angular velocity and acceleration of the beam (its inertia) and of the aerodynamics (Omega x r,
section pitch rate). Small angles: gravity stays fixed in body axes and the airspeed is constant
(no surge/phugoid), the short-period assumptions of the references.

The user gives the whole aircraft (mass M, CG (x_cg, z_cg) from O, pitch inertia I_yy about the
CG); :func:`body_pitch_properties` removes both half-wings (their mass lumped at the nodes with
the trapezoid weights of :func:`wingmdao.aero.plunge.half_wing_mass`; the sections' rotary
inertia and mass-centre offsets are not removed, a small error for a thin wing):

    m_b = M - 2 m_h,  s = M (x_cg, z_cg) - 2 sum_i m_i (x_i, z_i),
    I_O = I_yy + M (x_cg^2 + z_cg^2) - 2 sum_i m_i (x_i^2 + z_i^2).
"""

from __future__ import annotations

import numpy as np

from wingmdao.timemarch.system import VarSpec
import casadi as ca
from wingmdao.aero.plunge import body_mass, trapezoid_node_weights

#: rigid-body states after the plunge velocity (pitch attitude, pitch rate, [lagged downwash]) and the
#: tail-incidence trim unknown; system.body_index maps them to their state indices
PITCH_STATE_NAMES = ("pitch_angle", "pitch_rate")
LAG_STATE_NAME = "downwash_lag"
INCIDENCE_STATE_NAME = "tail_incidence"
#: the elevator actuator's state (before the tail incidence, with ``elevator=True``)
ELEVATOR_STATE_NAME = "elevator_deflection"


def pitch_param_specs() -> list[VarSpec]:
    """Parameters of the free-pitch rows (appended after ``body_mass``)."""
    return [
        VarSpec("body_first_moment", (2,), "kg*m", "m_b (x_b, z_b): first moment of the body (aircraft outside both "
                "wing halves) about the body-axes origin"),
        VarSpec("body_pitch_inertia", (), "kg*m**2", "pitch inertia of the body about the body-axes origin (y axis)"),
        VarSpec("tail_x", (), "m", "x of the horizontal tail's aerodynamic centre aft of the body-axes origin"),
        VarSpec("tail_area", (), "m**2", "horizontal tail area S_t"),
        VarSpec("tail_lift_slope", (), "1/rad", "horizontal tail lift-curve slope a_t (compressibility included)"),
        VarSpec("downwash_gradient", (), None, "downwash gradient deps/dalpha at the tail"),
    ]


def pitch_forcing_specs() -> list[VarSpec]:
    """Forcing of the free-pitch rows at one instant."""
    return [VarSpec("tail_gust_velocity", (), "m/s", "gust velocity (body +z) at the tail, its penetration delay included")]


def elevator_param_specs() -> list[VarSpec]:
    """Parameters of the elevator (``elevator=True``; appended after the pitch parameters)."""
    return [
        VarSpec("elevator_effectiveness", (), None, "elevator effectiveness tau_e = d alpha_t / d delta (tail angle "
                "per elevator angle)"),
        VarSpec("elevator_time_constant", (), "s", "time constant t_a of the first-order elevator actuator"),
    ]


def elevator_forcing_specs() -> list[VarSpec]:
    """Forcing of the elevator at one instant."""
    return [VarSpec("elevator_command", (), "rad", "elevator command delta_cmd (trailing edge down +)")]


def elevator_effectiveness(chord_ratio) -> float:
    """Thin-airfoil elevator effectiveness tau_e = (dC_l/d delta) / (dC_l/d alpha) of a plain flap of
    chord ratio E = c_e / c (0 < E < 1): ``1 - (theta_h - sin theta_h) / pi``, cos theta_h = 2 E - 1
    (the flapped thin aerofoil: dC_l/d delta = 2 (pi - theta_h + sin theta_h); Glauert, *The
    Elements of Aerofoil and Airscrew Theory*, 2nd ed., Cambridge University Press, 1947; E = 0.3
    gives 0.66). Measured effectiveness is lower (the empirical flap-effectiveness charts of Nelson,
    *Flight Stability and Automatic Control*, 2nd ed., 1998, Ch. 2, give about 0.5 at E = 0.3).

    Parameters
    ----------
    chord_ratio : float
        Elevator chord over tail chord E, in (0, 1).

    Returns
    -------
    float
        tau_e.
    """
    e = float(chord_ratio)
    if not (np.isfinite(e) and 0.0 < e < 1.0):
        raise ValueError(f"elevator chord ratio = {e}; allowed range (0, 1)")
    th = np.arccos(2.0 * e - 1.0)
    return float(1.0 - (th - np.sin(th)) / np.pi)


def check_pitch_inputs(**values) -> None:
    """ValueError (input, value, allowed range, SI) for bad free-pitch inputs; checks those given.

    Parameters
    ----------
    **values
        Inputs by name: ``aircraft_pitch_inertia``, ``body_pitch_inertia`` (kg m^2),
        ``tail_area`` (m^2), ``tail_lift_slope`` (1/rad), ``downwash_gradient``, ``tail_arm``,
        ``tail_x`` (m), ``elevator_effectiveness``, ``elevator_time_constant`` (s).
    """
    rules = {"aircraft_pitch_inertia": ("kg*m**2", lambda v: v > 0, "(0, inf)"),
             "body_pitch_inertia": ("kg*m**2", lambda v: v > 0, "(0, inf)"),
             "tail_area": ("m**2", lambda v: v > 0, "(0, inf)"),
             "tail_lift_slope": ("1/rad", lambda v: v > 0, "(0, inf)"),
             "downwash_gradient": ("", lambda v: 0 <= v < 1, "[0, 1)"),
             "tail_arm": ("m", lambda v: v > 0, "(0, inf) (tail aft of the CG)"),
             "tail_x": ("m", lambda v: v > 0, "(0, inf) (tail aft of the body-axes origin)"),
             "elevator_effectiveness": ("", lambda v: 0 < v <= 1, "(0, 1]"),
             "elevator_time_constant": ("s", lambda v: v > 0, "(0, inf)")}
    for name, v in values.items():
        units, ok, rng = rules[name]
        val = float(np.real(v))
        if not (np.isfinite(val) and ok(val)):
            raise ValueError(f"{name} = {val} {units}; allowed range {rng} {units}".rstrip())


def pitch_parameters(*, aircraft_mass, cg, aircraft_pitch_inertia, tail_arm, tail_area, tail_lift_slope,
                     downwash_gradient, mass_per_length, node_positions) -> dict:
    """Validated parameter dict of the free-pitch rows (``body_mass`` included) from the whole
    aircraft: mass (kg), CG (x, z) m from the body-axes origin, pitch inertia about the CG (kg m^2),
    tail arm CG -> tail aerodynamic centre (m), tail area (m^2), tail lift slope (1/rad), deps/dalpha.

    Parameters
    ----------
    aircraft_mass : float
        Aircraft mass (kg).
    cg : array_like, shape (2,)
        CG ``(x, z)`` from the body-axes origin (m).
    aircraft_pitch_inertia : float
        Aircraft pitch inertia about the CG (kg m^2).
    tail_arm : float
        Distance from the CG aft to the tail aerodynamic centre (m), > 0.
    tail_area : float
        Horizontal tail area (m^2), > 0.
    tail_lift_slope : float
        Tail lift-curve slope (1/rad), > 0.
    downwash_gradient : float
        deps/dalpha at the tail, in [0, 1).
    mass_per_length : array_like, shape (n,)
        Mass per length of the half-wing beam (kg/m).
    node_positions : array_like, shape (n, 3)
        Node positions of the half-wing beam (m).

    Returns
    -------
    dict
        ``body_mass``, ``body_first_moment``, ``body_pitch_inertia``, ``tail_x``, ``tail_area``,
        ``tail_lift_slope``, ``downwash_gradient``.
    """
    check_pitch_inputs(tail_arm=tail_arm, tail_area=tail_area, tail_lift_slope=tail_lift_slope,
                       downwash_gradient=downwash_gradient)
    mb, s, i_o = body_pitch_properties(aircraft_mass, np.asarray(cg, dtype=float), aircraft_pitch_inertia,
                                       mass_per_length, node_positions)
    return {"body_mass": float(mb), "body_first_moment": s, "body_pitch_inertia": float(i_o),
            "tail_x": float(cg[0] + tail_arm), "tail_area": float(tail_area), "tail_lift_slope": float(tail_lift_slope),
            "downwash_gradient": float(downwash_gradient)}


def half_wing_pitch_moments(mass_per_length, node_positions):
    """(m_h, (S_x, S_z), I_O) of one half-wing: mass, first moments and pitch inertia about the
    body-axes origin's y axis, mass lumped at the nodes with trapezoid weights (complex-step safe).

    Parameters
    ----------
    mass_per_length : array_like, shape (n,)
        Mass per length at the nodes (kg/m).
    node_positions : array_like, shape (n, 3)
        Node positions (m), body axes.

    Returns
    -------
    m_h : float
        Half-wing mass (kg).
    first_moment : ndarray, shape (2,)
        ``(S_x, S_z)`` (kg m).
    inertia : float
        Pitch inertia about the origin (kg m^2).
    """
    mu, r = np.asarray(mass_per_length), np.asarray(node_positions)
    m = trapezoid_node_weights(r) * mu
    x, z = r[:, 0], r[:, 2]
    return np.sum(m), np.array([np.sum(m * x), np.sum(m * z)]), np.sum(m * (x * x + z * z))


def body_pitch_properties(aircraft_mass, cg, aircraft_pitch_inertia, mass_per_length, node_positions):
    """Body (aircraft outside both half-wings) mass, first moment (2,) and pitch inertia about the
    origin from the whole aircraft's mass M (kg), CG (x, z) from the origin (m) and pitch inertia
    about the CG (kg m^2); ValueError unless the body's own inertia about its CG is > 0.

    Parameters
    ----------
    aircraft_mass : float
        Aircraft mass M (kg).
    cg : array_like, shape (2,)
        CG ``(x, z)`` from the origin (m).
    aircraft_pitch_inertia : float
        Pitch inertia about the CG (kg m^2), > 0.
    mass_per_length : array_like, shape (n,)
        Mass per length of the half-wing beam (kg/m).
    node_positions : array_like, shape (n, 3)
        Node positions of the half-wing beam (m).

    Returns
    -------
    body_mass : float
        m_b (kg).
    first_moment : ndarray, shape (2,)
        s (kg m).
    pitch_inertia : float
        I_O (kg m^2).
    """
    check_pitch_inputs(aircraft_pitch_inertia=aircraft_pitch_inertia)
    cg = np.asarray(cg)
    if cg.shape != (2,) or not np.all(np.isfinite(np.real(cg))):
        raise ValueError(f"cg = {np.real(cg)} m; allowed: two finite values (x, z) from the body-axes origin")
    m_h, s_h, i_h = half_wing_pitch_moments(mass_per_length, node_positions)
    mb = body_mass(aircraft_mass, m_h)
    s = aircraft_mass * cg - 2.0 * s_h
    i_o = aircraft_pitch_inertia + aircraft_mass * np.sum(cg * cg) - 2.0 * i_h
    own = i_o - np.sum(s * s) / mb
    if not np.real(own) > 0:
        raise ValueError(f"aircraft_pitch_inertia = {np.real(aircraft_pitch_inertia)} kg*m**2; allowed range "
                         f"({np.real(aircraft_pitch_inertia - own):.6g}, inf) kg*m**2: the body outside both wing "
                         "halves must keep a positive pitch inertia about its own CG")
    return mb, s, i_o


def body_residuals(x_b, xd_b, *, w_p, dw_p, F0, M0, r0, alpha_trim, gust_root, gust_tail, V, rho, g, pars, body_mass,
                   tail_lag, on, elevator=None):
    """CasADi rows of the rigid body (see the module docstring): (translation row replacing the
    plunge row, [theta row, q row, (lag row), (actuator row)], moment row of the tail-incidence
    trim unknown, L_t).

    ``x_b``/``xd_b``: (theta_p, q, [e], [delta], i_t) and their rates; ``on`` the trim switch (1:
    theta_p = q = w_p = 0 and i_t solves the static moment balance; 0: the dynamics, i_t held);
    ``elevator``: None (no elevator) or ``(tau_e, t_a, delta_cmd)``.

    Parameters
    ----------
    x_b : casadi.SX
        Rigid-body states (theta_p, q, [e], [delta], i_t) (rad, rad/s).
    xd_b : casadi.SX
        Their rates.
    w_p : casadi.SX
        Plunge velocity of the origin, up (m/s).
    dw_p : casadi.SX
        Its rate (m/s^2).
    F0 : casadi.SX, shape (3,)
        Root force of one half-wing on the body (N), body axes.
    M0 : casadi.SX, shape (3,)
        Root moment of one half-wing on the body (N m), body axes.
    r0 : casadi.SX or ndarray, shape (3,)
        Root node position (m).
    alpha_trim : casadi.SX
        Trim angle of attack (rad).
    gust_root : casadi.SX
        Gust velocity at the root station (m/s).
    gust_tail : casadi.SX
        Gust velocity at the tail (m/s).
    V : casadi.SX
        Airspeed (m/s).
    rho : casadi.SX
        Air density (kg/m^3).
    g : casadi.SX, shape (3,)
        Gravity (m/s^2), body axes.
    pars : dict
        The pitch parameters (:func:`pitch_param_specs`) as CasADi symbols.
    body_mass : casadi.SX
        m_b (kg).
    tail_lag : bool
        Whether the downwash lag state e is present.
    on : casadi.SX
        Trim switch (1: trim, 0: dynamics).
    elevator : tuple, optional
        ``(tau_e, t_a, delta_cmd)``; None: no elevator.

    Returns
    -------
    rows : casadi.SX
        The rows, in the order above.
    lift_t : casadi.SX
        Tail lift L_t (N).
    """
    theta, qr = x_b[0], x_b[1]
    it = x_b[-1]
    s_x, s_z = pars["body_first_moment"][0], pars["body_first_moment"][1]
    i_o, x_t = pars["body_pitch_inertia"], pars["tail_x"]
    alpha_w = alpha_trim + theta - w_p / V + gust_root / V
    e = x_b[2] if tail_lag else alpha_w
    alpha_t = (alpha_trim + theta - w_p / V + qr * x_t / V + gust_tail / V - pars["downwash_gradient"] * e + it)
    if elevator is not None:
        alpha_t = alpha_t + elevator[0] * x_b[-2]
    lift_t = 0.5 * rho * V * V * pars["tail_area"] * pars["tail_lift_slope"] * alpha_t
    trans = body_mass * (dw_p - g[2]) - s_x * xd_b[1] - s_z * qr * qr - 2.0 * F0[2] - lift_t
    moment = (i_o * xd_b[1] - s_x * dw_p - (s_z * g[0] - s_x * g[2])
              - 2.0 * (r0[2] * F0[0] - r0[0] * F0[2] + M0[1]) + x_t * lift_t)
    rows = [on * w_p + (1.0 - on) * trans,
            on * theta + (1.0 - on) * (xd_b[0] - qr),
            on * qr + (1.0 - on) * moment]
    if tail_lag:
        rows.append((x_t / V) * xd_b[2] + e - alpha_w)
    if elevator is not None:
        rows.append(elevator[1] * xd_b[-2] + x_b[-2] - elevator[2])
    rows.append(on * moment + (1.0 - on) * xd_b[-1])
    return ca.vertcat(*rows), lift_t


def short_period_closed_form(*, mass, pitch_inertia, airspeed, density, wing_area, wing_lift_slope, tail_area,
                             tail_lift_slope, tail_arm, downwash_gradient, wing_ac_arm=0.0, tail_lag=False):
    """Short-period eigenvalues (1/s, complex pair) of the rigid aircraft, Nelson (1998) Sec. 4.4 /
    Etkin & Reid (1996) Sec. 6.3: ``lambda^2 - (Z_w + M_q + u0 M_wdot) lambda + Z_w M_q - u0 M_w = 0``.

    Dimensional derivatives (per unit mass / inertia, w the normal velocity at the CG, down +
    in the references, which leaves the characteristic equation unchanged), q_d = rho V^2 / 2:
    Z_w = -q_d (S a_w + S_t a_t (1 - deps/dalpha)) / (m V) (lift only: no drag, no C_L0 term);
    M_w = q_d (S a_w x_w - S_t a_t (1 - deps/dalpha) l_t) / (I V), x_w the wing aerodynamic centre
    *ahead* of the CG (``wing_ac_arm``, m); M_q = -q_d S_t a_t l_t^2 / (I V) (tail only);
    M_wdot = -q_d S_t a_t deps/dalpha l_t^2 / (I V^2) with the downwash lag, else 0.

    Parameters
    ----------
    mass : float
        Aircraft mass (kg).
    pitch_inertia : float
        Pitch inertia about the CG (kg m^2).
    airspeed : float
        Airspeed (m/s).
    density : float
        Air density (kg/m^3).
    wing_area : float
        Wing area S (m^2).
    wing_lift_slope : float
        Wing lift-curve slope a_w (1/rad).
    tail_area : float
        Tail area S_t (m^2).
    tail_lift_slope : float
        Tail lift-curve slope a_t (1/rad).
    tail_arm : float
        CG to tail aerodynamic centre l_t (m).
    downwash_gradient : float
        deps/dalpha.
    wing_ac_arm : float
        Wing aerodynamic centre ahead of the CG x_w (m).
    tail_lag : bool
        Include M_wdot from the downwash lag.

    Returns
    -------
    ndarray of complex, shape (2,)
        The eigenvalues (1/s).
    """
    qd, m, I, V = 0.5 * density * airspeed ** 2, mass, pitch_inertia, airspeed
    at = tail_area * tail_lift_slope
    Zw = -qd * (wing_area * wing_lift_slope + at * (1 - downwash_gradient)) / (m * V)
    Mw = qd * (wing_area * wing_lift_slope * wing_ac_arm - at * (1 - downwash_gradient) * tail_arm) / (I * V)
    Mq = -qd * at * tail_arm ** 2 / (I * V)
    Mwd = -qd * at * downwash_gradient * tail_arm ** 2 / (I * V * V) if tail_lag else 0.0
    return np.roots([1.0, -(Zw + Mq + V * Mwd), Zw * Mq - V * Mw])
