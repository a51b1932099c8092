"""Unsteady strip theory of one wing section with finite aerodynamic states (no OpenMDAO).

Per station (chord c = 2 b, reference point = beam axis at ``ref_point`` x c aft of the leading
edge), with the relative air velocity at the reference point resolved in the section's csn frame
(``v_c`` chordwise aft, ``v_n`` normal up; docs/conventions.md) and the section's pitch rate
``w_s`` (nose up positive, about +s):

* quasi-steady angle at the three-quarter chord (Theodorsen's downwash point)
  ``alpha_qs = (v_n + w_s c (3/4 - ref_point)) / v_c - alpha_zero_lift``;
* Wagner's indicial function in R. T. Jones' two-state form (Jones, "Operational treatment of
  the nonuniform-lift theory in airplane dynamics", NACA Rep. 681, 1940)
  ``phi(s) = 1 - 0.165 e^{-0.0455 s} - 0.335 e^{-0.3 s}``, s = V t / b, realised as two lag
  states ``lambda_k``: ``b / (beta_k V) dlambda_k/dt + lambda_k - alpha_qs = 0`` and
  ``alpha_eff = (1 - A_1 - A_2) alpha_qs + A_1 lambda_1 + A_2 lambda_2`` (A = 0.165, 0.335;
  beta = 0.0455, 0.3): a step in alpha_qs gives exactly alpha_eff = phi(s) alpha_step;
* Kuessner's gust function in the Sears-Sparks form (Sears & Sparks, "On the reaction of an
  elastic wing to vertical gusts", J. Aeronautical Sciences 9, 1941)
  ``psi(s) = 1 - 0.5 e^{-0.13 s} - 0.5 e^{-s}`` as two more states ``mu_k`` driven by the gust
  angle ``alpha_g = w_g,n / v_c`` of the gust velocity at the station (its penetration delay is
  in the forcing, :func:`station_gust_history`);
* circulatory lift ``L_c = 1/2 rho V^2 c a / sqrt(1 - M^2) (alpha_eff + alpha_g,eff)`` at the
  quarter chord (Prandtl-Glauert factor on the lift slope a);
* apparent-mass (non-circulatory) lift and moment of Theodorsen ("General theory of aerodynamic
  instability and the mechanism of flutter", NACA Rep. 496, 1935):
  ``L_nc = pi rho b^2 dw_mid/dt`` (w_mid the normal relative air velocity at midchord) acting at
  midchord, and the moment about midchord ``-pi rho b^3 v_c w_s / 2 - pi rho b^4 dw_s/dt / 8``;
* the section moment about the reference point, nose up:
  ``M = L_c c (ref - 1/4) + L_nc c (ref - 1/2) + 1/2 rho V^2 c^2 cm0 + (midchord terms)``.

For rigid harmonic motion these reduce exactly to Theodorsen's lift and moment with C(k) replaced
by Jones' rational approximation ``C_J(k) = 1 - A_1 i k/(i k + beta_1) - A_2 i k/(i k + beta_2)``
(:func:`theodorsen_jones`); against the exact C(k) its modulus differs by at most 1.4 % and its
phase by at most 0.023 rad for 0.05 <= k <= 0.5 (2.1 % in modulus at k = 1; tests/test_aero.py).
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
from scipy.special import hankel2

from wingmdao.aero.controls import flap_terms, hinge_moment

#: R. T. Jones' Wagner approximation (NACA Rep. 681): phi(s) = 1 - sum A_k exp(-beta_k s).
WAGNER_A = (0.165, 0.335)
WAGNER_B = (0.0455, 0.3)
#: Sears-Sparks Kuessner approximation: psi(s) = 1 - sum C_k exp(-delta_k s).
KUSSNER_A = (0.5, 0.5)
KUSSNER_B = (0.13, 1.0)
#: aerodynamic states per station: lambda_1, lambda_2 (Wagner), mu_1, mu_2 (Kuessner)
N_AERO_STATES = 4
AERO_STATE_NAMES = ("wagner lag 1", "wagner lag 2", "kussner lag 1", "kussner lag 2")


def wagner_jones(s):
    """Jones' two-term Wagner function phi(s), s in semichords travelled.

    Parameters
    ----------
    s : array_like
        Distance travelled in semichords.

    Returns
    -------
    ndarray
        phi(s).
    """
    s = np.asarray(s, dtype=float)
    return 1.0 - WAGNER_A[0] * np.exp(-WAGNER_B[0] * s) - WAGNER_A[1] * np.exp(-WAGNER_B[1] * s)


def kussner_sears_sparks(s):
    """Sears-Sparks two-term Kuessner function psi(s), s in semichords into the gust.

    Parameters
    ----------
    s : array_like
        Distance into the gust in semichords.

    Returns
    -------
    ndarray
        psi(s).
    """
    s = np.asarray(s, dtype=float)
    return 1.0 - KUSSNER_A[0] * np.exp(-KUSSNER_B[0] * s) - KUSSNER_A[1] * np.exp(-KUSSNER_B[1] * s)


def theodorsen_exact(k):
    """Theodorsen's C(k) = H1(k) / (H1(k) + i H0(k)) (Hankel functions of the second kind).

    Parameters
    ----------
    k : float or array_like
        Reduced frequency ``omega b / V``, > 0.

    Returns
    -------
    complex or ndarray of complex
        C(k).
    """
    h1, h0 = hankel2(1, k), hankel2(0, k)
    return h1 / (h1 + 1j * h0)


def theodorsen_jones(k):
    """C(k) of Jones' two-state Wagner approximation (the frequency response of the lag states).

    Parameters
    ----------
    k : float or array_like
        Reduced frequency ``omega b / V``.

    Returns
    -------
    complex or ndarray of complex
        The approximate C(k).
    """
    ik = 1j * np.asarray(k, dtype=float)
    return 1.0 - sum(a * ik / (ik + b) for a, b in zip(WAGNER_A, WAGNER_B))


def check_aero_inputs(*, chord=None, ref_point=None, airspeed=None, density=None, mach=None,
                      lift_slope=None) -> None:
    """ValueError naming the input, its value and the allowed range (SI) for bad section data.

    Parameters
    ----------
    chord : float or array_like, optional
        Chord (m), > 0.
    ref_point : float or array_like, optional
        Reference point as a fraction of the chord from the leading edge, in [0, 1].
    airspeed : float or array_like, optional
        Airspeed (m/s), > 0.
    density : float or array_like, optional
        Air density (kg/m^3), > 0.
    mach : float or array_like, optional
        Mach number, in [0, 1).
    lift_slope : float or array_like, optional
        Section lift slope (1/rad), > 0.
    """
    def _arr(v):
        return np.atleast_1d(np.asarray(v, dtype=float))

    checks = (("chord", chord, lambda a: a > 0.0, "> 0 m"),
              ("ref_point", ref_point, lambda a: (a >= 0.0) & (a <= 1.0), "in [0, 1] (fraction of chord from the leading edge)"),
              ("airspeed", airspeed, lambda a: a > 0.0, "> 0 m/s"),
              ("density", density, lambda a: a > 0.0, "> 0 kg/m**3"),
              ("mach", mach, lambda a: (a >= 0.0) & (a < 1.0), "in [0, 1) (subsonic Prandtl-Glauert)"),
              ("lift_slope", lift_slope, lambda a: a > 0.0, "> 0 1/rad"))
    for name, val, ok, allowed in checks:
        if val is None:
            continue
        a = _arr(val)
        good = np.isfinite(a) & ok(a)
        if not np.all(good):
            i = int(np.flatnonzero(~good)[0])
            where = f" at station {i}" if a.size > 1 else ""
            raise ValueError(f"{name} must be {allowed}; got {float(a[i])!r}{where}")


def section_model(rel_csn, w_s, dw_mid_dt, dw_s_dt, gust_n, aero_x, aero_xdot, chord, ref_point,
                  lift_slope, alpha_zero, cm0, airspeed, density, mach, flap=None, flap_lattice=False):
    """Symbolic (CasADi) section loads and lag-state residuals.

    ``rel_csn``: relative air velocity at the reference point in csn (without the gust);
    ``w_s``: pitch rate (nose up); ``dw_mid_dt``/``dw_s_dt``: rates of the midchord normal relative
    velocity and of the pitch rate (apparent mass); ``gust_n``: gust velocity normal to the section;
    ``aero_x``/``aero_xdot``: the 4 lag states and rates. Returns ``(lift, moment_ref, residual4,
    parts)`` with lift per length along +n and moment per length about +s at the reference point;
    ``parts`` also holds the lagged circulatory angle ``alpha_circulatory`` (alpha_eff +
    alpha_g,eff, to which the circulatory lift is proportional) and ``moment_noncirculatory`` (the
    moment without the circulatory lift's ``L_c c (ref - 1/4)``), from which a three-dimensional
    quasi-steady lift replaces the strip's (``aero_theory="vlm"``, :mod:`wingmdao.aero.system`).

    ``flap``: ``(T, beta, dbeta, ddbeta)`` of a trailing-edge control surface (Theodorsen's flap
    functions ``T`` with a = 0 and the deflection, its rate and acceleration,
    :mod:`wingmdao.aero.controls`): its angle adds to the three-quarter-chord angle that drives
    the Wagner states, its non-circulatory lift and moment to the section's, and ``parts`` holds
    the ``hinge_moment`` per length (trailing edge down positive). None: no surface.
    ``flap_lattice``: the flap is a set of deflected vortex-lattice panels (``aero_theory="vlm"``,
    :mod:`wingmdao.aero.system`), which carry its circulatory lift, its steady moment and the
    circulatory and steady parts of its hinge moment: its angle then stays out of the Wagner
    states (``parts["flap_input"]`` = beta + T11 b / (2 T10 v_c) dbeta, the input of the flap's own
    lag states), and the section keeps only the flap's rate and acceleration terms (non-circulatory
    lift, moment without the steady ``T15`` term, hinge moment without the ``T18`` and ``T12 L_c``
    terms).

    Parameters
    ----------
    rel_csn : casadi.SX, shape (3,)
        Relative air velocity at the reference point in csn (m/s), without the gust.
    w_s : casadi.SX
        Pitch rate, nose up (rad/s).
    dw_mid_dt : casadi.SX
        Rate of the midchord normal relative velocity (m/s^2).
    dw_s_dt : casadi.SX
        Rate of the pitch rate (rad/s^2).
    gust_n : casadi.SX
        Gust velocity normal to the section (m/s).
    aero_x : casadi.SX, shape (4,)
        Lag states (Wagner 1, 2, Kuessner 1, 2; rad).
    aero_xdot : casadi.SX, shape (4,)
        Their rates (rad/s).
    chord : casadi.SX or float
        Chord (m).
    ref_point : casadi.SX or float
        Reference point, fraction of the chord from the leading edge.
    lift_slope : casadi.SX or float
        Incompressible section lift slope (1/rad).
    alpha_zero : casadi.SX or float
        Zero-lift angle (rad).
    cm0 : casadi.SX or float
        Zero-lift moment coefficient about the quarter chord.
    airspeed : casadi.SX or float
        Airspeed V (m/s) of the dynamic pressure 1/2 rho V^2 and of the lags' time constants
        b / (B V); a swept strip on the normal velocity takes V cos(sweep) (:mod:`wingmdao.aero.joined`).
    density : casadi.SX or float
        Air density (kg/m^3).
    mach : casadi.SX or float
        Mach number.
    flap : tuple, optional
        ``(T, beta, dbeta, ddbeta)`` of a trailing-edge control surface; None: none.
    flap_lattice : bool, optional
        The flap's circulatory and steady loads come from a vortex lattice (above).

    Returns
    -------
    lift : casadi.SX
        Lift per length along +n (N/m).
    moment_ref : casadi.SX
        Moment per length about +s at the reference point (N m/m).
    residual : casadi.SX, shape (4,)
        Lag-state residuals.
    parts : dict
        Lift and angle components, as described above.
    """
    b = 0.5 * chord
    v_c = rel_csn[0]
    v_n = rel_csn[2]
    d34 = chord * (0.75 - ref_point)
    alpha_qs = (v_n + w_s * d34) / v_c - alpha_zero
    if flap is not None:
        alpha_f, lift_nc_f, moment_nc_f = flap_terms(flap[0], b, v_c, density, *flap[1:])
        if flap_lattice:  # the lattice carries the circulatory lift and the steady moment (T15 beta)
            moment_nc_f = flap_terms(flap[0], b, v_c, density, 0.0, *flap[2:])[2]
        else:
            alpha_qs = alpha_qs + alpha_f
    alpha_g = gust_n / v_c
    lam = [aero_x[0], aero_x[1]]
    mu = [aero_x[2], aero_x[3]]
    res = []
    for k in range(2):
        res.append(b / (WAGNER_B[k] * airspeed) * aero_xdot[k] + lam[k] - alpha_qs)
    for k in range(2):
        res.append(b / (KUSSNER_B[k] * airspeed) * aero_xdot[2 + k] + mu[k] - alpha_g)
    alpha_eff = ((1.0 - sum(WAGNER_A)) * alpha_qs + WAGNER_A[0] * lam[0] + WAGNER_A[1] * lam[1])
    alpha_geff = ((1.0 - sum(KUSSNER_A)) * alpha_g + KUSSNER_A[0] * mu[0] + KUSSNER_A[1] * mu[1])
    qdyn = 0.5 * density * airspeed ** 2
    a_pg = lift_slope / ca.sqrt(1.0 - mach ** 2)
    lift_c = qdyn * chord * a_pg * (alpha_eff + alpha_geff)
    lift_nc = math.pi * density * b ** 2 * dw_mid_dt
    moment = (lift_c * chord * (ref_point - 0.25) + lift_nc * chord * (ref_point - 0.5)
              + qdyn * chord ** 2 * cm0
              - math.pi * density * b ** 3 * v_c * w_s / 2.0 - math.pi * density * b ** 4 * dw_s_dt / 8.0)
    if flap is not None:
        lift_nc = lift_nc + lift_nc_f
        moment = moment + moment_nc_f + lift_nc_f * chord * (ref_point - 0.5)
    parts = {"lift_circulatory": lift_c, "lift_apparent_mass": lift_nc, "alpha_qs": alpha_qs,
             "alpha_gust": alpha_g, "alpha_circulatory": alpha_eff + alpha_geff,
             "moment_noncirculatory": moment - lift_c * chord * (ref_point - 0.25)}
    if flap is not None and flap_lattice:
        parts["hinge_moment"] = hinge_moment(flap[0], b, v_c, density, 0.0, *flap[2:], dw_mid_dt, w_s, dw_s_dt, 0.0)
        parts["flap_input"] = alpha_f * (math.pi / flap[0][10])
    elif flap is not None:
        parts["hinge_moment"] = hinge_moment(flap[0], b, v_c, density, *flap[1:], dw_mid_dt, w_s, dw_s_dt, lift_c)
    return lift_c + lift_nc, moment, ca.vertcat(*res), parts


def station_gust_history(time, x_stations, airspeed, profile, x_ref=None):
    """Gust velocity (n_time, n_station) at each station with its penetration delay.

    The gust front is at ``x_ref`` (default: the most forward station) at t = 0 and is carried
    aft with the air at ``airspeed``; a station at chordwise body position x meets the gust
    profile ``profile(tau)`` (upward m/s, tau the time since the front passed) at
    ``tau = t - (x - x_ref) / V``; ``profile`` must return 0 for tau < 0.

    Parameters
    ----------
    time : array_like, shape (n_time,)
        Times (s).
    x_stations : array_like, shape (n_station,)
        Chordwise body position x of each station (m).
    airspeed : float
        Airspeed (m/s), > 0.
    profile : callable
        ``profile(tau)`` gust velocity (m/s, up), 0 for tau < 0.
    x_ref : float, optional
        x of the gust front at t = 0 (m); default the most forward station.

    Returns
    -------
    ndarray, shape (n_time, n_station)
        Gust velocity (m/s).
    """
    check_aero_inputs(airspeed=airspeed)
    t = np.asarray(time, dtype=float)[:, None]
    x = np.asarray(x_stations, dtype=float)[None, :]
    x0 = np.min(x) if x_ref is None else float(x_ref)
    return np.asarray(profile(t - (x - x0) / float(airspeed)), dtype=float)
