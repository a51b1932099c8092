"""The 14 CFR 25.331(c)(2) checked pitch maneuver on the free-pitch aeroelastic model (docs/maneuvers.md).

The regulation (14 CFR 25.331(c)(2), as amended by Amdt. 25-141, 79 FR 73466, Dec. 11, 2014),
quoted in :data:`REGULATION`: the flight deck pitch control moves as delta(t) = delta_1 sin(omega t)
for 0 <= t <= t_max = 3 pi / (2 omega), omega the undamped natural frequency of the short-period
rigid mode but not less than pi V / (2 V_A); the amplitude is scaled so that the nose-up
maneuver reaches the 25.337 positive limit load factor and the nose-down one 0 g; loads beyond
t_max (and beyond the time n goes below 0 g nose up, above the limit nose down) need not be
considered (25.331(c)(2)(v)).

Method. The airplane is :func:`wingmdao.aero.system.build_aeroelastic_system` with free plunge,
trim, free pitch and an elevator (``elevator=True``): the elevator angle is a first-order actuator
state driven by the forcing ``elevator_command``, so the BDF2/Newton march, its adjoint and the
linearization carry it. The command is the pilot's control displacement through a linear gearing
(elevator angle per unit displacement), so delta(t) is given directly as the elevator command.

* omega: the linearization of the trimmed free-pitch model (:func:`wingmdao.stability.eigen.eigenmodes`
  about the trimmed state with the trim switched off), the complex mode whose eigenvector has the
  largest pitch attitude against the wing's elastic rotations (:func:`short_period_mode`);
  omega_n = |lambda|, bounded below by pi V / (2 V_A) (V and V_A both equivalent airspeeds);
* delta_1: the secant method on marches, so that the peak load-factor increment reaches the target
  one (n_lim - 1 nose up; -1, i.e. 0 g, nose down) within ``rtol`` of it;
* with a largest available command (``max_amplitude``: stops, pilot effort) below the delta_1
  found, the command of 25.331(c)(2)(iii) (the sine held at delta_1 for Delta t <= 5 s) with the
  Delta t that reaches the target (Brent's method);
* the march covers [0, t_max]; the elevator trailing edge down is positive, so the nose-up
  maneuver starts with a negative (trailing edge up) elevator.

The load factor is (wing + tail lift) / W, as in the free-pitch gust response.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.optimize as sopt

from wingmdao.aero.pitch import check_pitch_inputs
from wingmdao.aero.system import cached_aeroelastic_system
from wingmdao.loads.atmosphere import G0
from wingmdao.stability.eigen import eigenmodes
from wingmdao.timemarch.bdf import march, solve_static
from wingmdao.timemarch.system import layout, pack

#: 14 CFR 25.331(c)(2) (Amdt. 25-141, 2014), the paragraphs this module implements, as written
#: (the formula for the minimum omega, a graphic in the Federal Register, in words)
REGULATION = (
    "(2) Checked maneuver between VA and VD. Nose-up checked pitching maneuvers must be analyzed in which "
    "the positive limit load factor prescribed in § 25.337 is achieved. As a separate condition, nose-down "
    "checked pitching maneuvers must be analyzed in which a limit load factor of 0g is achieved. In defining "
    "the airplane loads, the flight deck pitch control motions described in paragraphs (c)(2)(i) through (iv) "
    "of this section must be used:\n"
    "(i) The airplane is assumed to be flying in steady level flight at any speed between VA and VD and the "
    "flight deck pitch control is moved in accordance with the following formula: δ(t) = δ1 sin(ωt) for "
    "0 ≤ t ≤ tmax Where— δ1 = the maximum available displacement of the flight deck pitch control in the "
    "initial direction, as limited by the control system stops, control surface stops, or by pilot effort in "
    "accordance with § 25.397(b); δ(t) = the displacement of the flight deck pitch control as a function of "
    "time. In the initial direction, δ(t) is limited to δ1. In the reverse direction, δ(t) may be truncated at "
    "the maximum available displacement of the flight deck pitch control as limited by the control system "
    "stops, control surface stops, or by pilot effort in accordance with 25.397(b); tmax = 3π/2ω; ω = the "
    "circular frequency (radians/second) of the control deflection taken equal to the undamped natural "
    "frequency of the short period rigid mode of the airplane, with active control system effects included "
    "where appropriate; but not less than: ω = πV/2VA radians per second; Where V = the speed of the airplane "
    "at entry to the maneuver. VA = the design maneuvering speed prescribed in § 25.335(c)."
)

#: the longest hold Delta t of 25.331(c)(2)(iii) (s: "need not exceed five seconds")
MAX_HOLD = 5.0
#: the first amplitude delta_1 of the secant iteration (rad, 1 deg)
FIRST_AMPLITUDE = float(np.radians(1.0))
#: the maneuver's directions: the sign of the initial elevator motion (trailing edge down +)
DIRECTIONS = {"nose-up": -1.0, "nose-down": 1.0}


@dataclass
class CheckedPitchResult:
    """One checked pitch maneuver (SI, radians).

    ``time`` (n_t,) s over [0, t_max]; ``elevator_command`` and ``elevator`` (the actuator's
    deflection) (n_t,) rad, trailing edge down +; ``load_factor`` (n_t,) (wing + tail lift) / W;
    ``pitch_rate`` (n_t,) rad/s nose up +; ``root_bending_moment`` (n_t,) N m (M_x at the
    symmetry plane, 1 g included); ``omega`` rad/s the control frequency, ``omega_short_period``
    rad/s the linearization's undamped short-period frequency, ``omega_min`` = pi V / (2 V_A);
    ``short_period_eigenvalue`` 1/s; ``delta_1`` rad (> 0, the amplitude of the command);
    ``direction`` "nose-up" or "nose-down"; ``target_load_factor``, ``peak_load_factor`` (max n
    nose up, min n nose down); ``t_max`` s; ``considered`` (n_t,) bool, the instants whose loads
    25.331(c)(2)(v) asks for; ``iterations`` the marches [(delta_1 rad, hold s, peak n), ...];
    ``states`` (n_t, n_state) the march's states; ``hold`` s, the Delta t of 25.331(c)(2)(iii)
    (0: the sine of (i)); ``reached``: the peak meets the target (False only when a 5 s hold at
    the largest available amplitude falls short).

    Parameters
    ----------
    time : numpy.ndarray
        (n_t,) times (s).
    elevator_command, elevator : numpy.ndarray
        (n_t,) command and actuator deflection (rad, trailing edge down +).
    load_factor : numpy.ndarray
        (n_t,) load factor (-).
    pitch_rate : numpy.ndarray
        (n_t,) pitch rate (rad/s, nose up +).
    root_bending_moment : numpy.ndarray
        (n_t,) root bending moment (N m).
    omega, omega_short_period, omega_min : float
        Control frequency, short-period frequency and the regulation's lower limit (rad/s).
    short_period_eigenvalue : complex
        Short-period eigenvalue (1/s).
    delta_1 : float
        Command amplitude (rad).
    direction : {"nose-up", "nose-down"}
        The maneuver.
    target_load_factor, peak_load_factor : float
        Target and peak load factor (-).
    t_max : float
        End of the maneuver (s).
    considered : numpy.ndarray
        (n_t,) bool, the instants whose loads 25.331(c)(2)(v) asks for.
    iterations : list
        The marches [(delta_1, hold, peak n), ...].
    states : numpy.ndarray
        (n_t, n_state) states of the march.
    hold : float, optional
        Delta t of 25.331(c)(2)(iii) (s).
    reached : bool, optional
        Whether the peak meets the target.
    """

    time: np.ndarray
    elevator_command: np.ndarray
    elevator: np.ndarray
    load_factor: np.ndarray
    pitch_rate: np.ndarray
    root_bending_moment: np.ndarray
    omega: float
    omega_short_period: float
    omega_min: float
    short_period_eigenvalue: complex
    delta_1: float
    direction: str
    target_load_factor: float
    peak_load_factor: float
    t_max: float
    considered: np.ndarray
    iterations: list
    states: np.ndarray
    hold: float = 0.0
    reached: bool = True


def check_maneuver_inputs(*, airspeed_eas, maneuvering_speed_eas, direction="nose-up", steps=200) -> None:
    """ValueError (input, value, allowed range) for bad maneuver inputs, before any solve.

    Parameters
    ----------
    airspeed_eas : float
        Entry speed (m/s EAS).
    maneuvering_speed_eas : float
        V_A (m/s EAS).
    direction : {"nose-up", "nose-down"}, optional
        The maneuver.
    steps : int, optional
        Time steps of the maneuver.
    """
    va = float(maneuvering_speed_eas)
    if not (np.isfinite(va) and va > 0):
        raise ValueError(f"maneuvering_speed_eas = {va} m/s; allowed range (0, inf) m/s (V_A, 14 CFR 25.335(c))")
    v = float(airspeed_eas)
    if not (np.isfinite(v) and v > 0):
        raise ValueError(f"airspeed_eas = {v} m/s; allowed range (0, inf) m/s")
    if direction not in DIRECTIONS:
        raise ValueError(f"direction = {direction!r}; allowed: {', '.join(DIRECTIONS)}")
    if not (int(steps) == steps and 20 <= steps <= 100000):
        raise ValueError(f"steps = {steps}; allowed range [20, 100000]")


def minimum_frequency(airspeed_eas, maneuvering_speed_eas) -> float:
    """The regulation's lower limit of omega, pi V / (2 V_A) (rad/s; both speeds EAS, m/s).

    Parameters
    ----------
    airspeed_eas : float
        Entry speed V (m/s EAS).
    maneuvering_speed_eas : float
        V_A (m/s EAS).

    Returns
    -------
    float
        omega_min (rad/s).
    """
    check_maneuver_inputs(airspeed_eas=airspeed_eas, maneuvering_speed_eas=maneuvering_speed_eas)
    return float(np.pi * airspeed_eas / (2.0 * maneuvering_speed_eas))


def control_history(time, delta_1, omega, direction="nose-up", hold=0.0) -> np.ndarray:
    """Elevator command (rad, trailing edge down +) of the checked maneuver at ``time`` (s).

    ``hold`` = 0: 25.331(c)(2)(i), s delta_1 sin(omega t) for 0 <= t <= 3 pi / (2 omega) (s = -1
    nose up); after t_max the command stays at its t_max value. ``hold`` = Delta t > 0: the form
    of 25.331(c)(2)(iii) for an airplane that does not reach the load factor with (i): sin up to
    t_1 = pi / (2 omega), held at s delta_1 until t_2 = t_1 + Delta t, then s delta_1 sin(omega
    (t + t_1 - t_2)) until t_max = t_2 + pi / omega.

    Parameters
    ----------
    time : array_like
        Times (s).
    delta_1 : float
        Amplitude (rad, > 0).
    omega : float
        Control frequency (rad/s).
    direction : {"nose-up", "nose-down"}, optional
        The maneuver.
    hold : float, optional
        Delta t of 25.331(c)(2)(iii) (s).

    Returns
    -------
    numpy.ndarray
        Elevator command (rad).
    """
    t = np.asarray(time, dtype=float)
    s = DIRECTIONS[direction]
    t1 = 0.5 * np.pi / omega
    t2 = t1 + float(hold)
    t_max = t2 + np.pi / omega
    tau = np.where(t <= t1, t, np.where(t <= t2, t1, t - (t2 - t1)))
    tau = np.minimum(tau, t_max - (t2 - t1))
    return s * float(delta_1) * np.sin(omega * tau)


def maneuver_duration(omega, hold=0.0) -> float:
    """t_max (s): 3 pi / (2 omega), plus the hold Delta t of 25.331(c)(2)(iii).

    Parameters
    ----------
    omega : float
        Control frequency (rad/s).
    hold : float, optional
        Delta t of 25.331(c)(2)(iii) (s).

    Returns
    -------
    float
        t_max (s).
    """
    return float(1.5 * np.pi / omega + hold)


def maneuver_model(beam_params, aero_params, pitch_params, *, weight, elevator_effectiveness,
                   elevator_time_constant, tail_lag=False):
    """(system, packed parameters) of the airplane free in plunge and pitch with an elevator:
    ``beam_params`` (:func:`wingmdao.design.design_beam_params`), ``aero_params``
    (:func:`wingmdao.aero.aero_parameters`), ``pitch_params`` (:func:`wingmdao.aero.pitch.pitch_parameters`),
    ``weight`` N (the trim lift), tau_e and the actuator's time constant (s) checked first.

    Parameters
    ----------
    beam_params : dict
        Beam parameters.
    aero_params : dict
        Strip aerodynamic parameters.
    pitch_params : dict
        Plunge-pitch and tail parameters.
    weight : float
        Trim lift (N).
    elevator_effectiveness : float
        tau_e (-).
    elevator_time_constant : float
        Actuator time constant (s).
    tail_lag : bool, optional
        Lag the wing's downwash at the tail.

    Returns
    -------
    tuple
        (system, packed parameters).
    """
    check_pitch_inputs(elevator_effectiveness=elevator_effectiveness, elevator_time_constant=elevator_time_constant)
    n = np.asarray(aero_params["chord"]).size
    system = cached_aeroelastic_system(n, plunge=True, trim=True, pitch=True, tail_lag=bool(tail_lag), elevator=True)
    params = {**beam_params, **aero_params, **pitch_params, "trim_lift": float(weight),
              "elevator_effectiveness": float(elevator_effectiveness),
              "elevator_time_constant": float(elevator_time_constant)}
    return system, pack(system.param_specs, params)


def _forcing(system, n_time, gravity):
    ql = layout(system.forcing_specs)
    Q = np.zeros((n_time, system.n_forcing))
    Q[:, ql["gravity"].start + 2] = -gravity
    Q[0, ql["trim_active"]] = 1.0
    return Q, ql


def short_period_mode(system, p, *, gravity=G0):
    """(eigenvalue 1/s, trimmed state) of the short-period mode of a free-pitch system.

    The system is trimmed (``trim_active`` = 1, :func:`~wingmdao.timemarch.bdf.solve_static`),
    linearized about that state with the trim off (:func:`~wingmdao.stability.eigen.eigenmodes`,
    ``static=False``), and of the oscillatory modes the one whose eigenvector has the largest
    pitch attitude |v_theta_p| against the largest elastic rotation of the wing's nodes is
    returned (the rigid-body pitch mode; its undamped natural frequency is |lambda|).

    Parameters
    ----------
    system : AeroelasticBeamSystem
        A free-pitch system.
    p : numpy.ndarray
        Its packed parameters.
    gravity : float, optional
        Gravitational acceleration (m/s^2).

    Returns
    -------
    tuple
        (eigenvalue (1/s), trimmed state).
    """
    if not getattr(system, "pitch", False):
        raise ValueError("short_period_mode needs a free-pitch system (build_aeroelastic_system(pitch=True))")
    Q, ql = _forcing(system, 1, gravity)
    q = Q[0]
    x0, _ = solve_static(system, p, q)
    q_free = q.copy()
    q_free[ql["trim_active"]] = 0.0
    modes = eigenmodes(system, p, q_free, x0, static=False)
    lam, vec = modes.eigenvalues, modes.vectors
    osc = np.abs(lam.imag) > 1e-6 * np.maximum(1.0, np.abs(lam))
    if not np.any(osc):
        raise RuntimeError("short_period_mode: the linearization has no oscillatory mode (no short period)")
    rot = system.layout.beam[:, 3:6].ravel()
    pitch = np.abs(vec[system.body_index["pitch_angle"]])
    share = pitch / (pitch + np.max(np.abs(vec[rot]), axis=0))
    k = int(np.argmax(np.where(osc, share, -1.0)))
    return complex(lam[k]), x0


def march_maneuver(system, p, time, command, *, gravity=G0, weight):
    """March the trimmed airplane through an elevator command history (rad, (n_t,)): (states,
    load factor (wing + tail lift) / W, root bending moment N m).

    Parameters
    ----------
    system : AeroelasticBeamSystem
        The airplane.
    p : numpy.ndarray
        Its packed parameters.
    time : numpy.ndarray
        (n_t,) times (s).
    command : numpy.ndarray
        (n_t,) elevator command (rad).
    gravity : float, optional
        Gravitational acceleration (m/s^2).
    weight : float
        Airplane weight (N).

    Returns
    -------
    tuple
        (states, load factor, root bending moment).
    """
    Q, ql = _forcing(system, time.size, gravity)
    Q[:, ql["elevator_command"]] = np.asarray(command, dtype=float)[:, None]
    hist = march(system, time, p, Q, modified_newton=True)
    dt = float(time[1] - time[0])
    lift = system.total_lift_history(hist.states, dt, p, Q) + system.tail_lift_history(hist.states, dt, p, Q)
    bending = system.layout.beam_states(hist.states)[:, 0, 9]
    return hist.states, lift / weight, bending


def _peak(n, direction):
    """The largest (nose up) or smallest (nose down) load factor of a history, the parabola through
    the extreme sample and its neighbours between samples (so that it varies smoothly with the
    amplitude and the hold, whose time grids differ)."""
    y = np.asarray(n, dtype=float) * (1.0 if direction == "nose-up" else -1.0)
    i = int(np.argmax(y))
    peak = y[i]
    if 0 < i < y.size - 1:
        curv = y[i - 1] - 2.0 * y[i] + y[i + 1]
        if curv < 0:
            peak = y[i] - 0.125 * (y[i - 1] - y[i + 1]) ** 2 / curv
    return float(peak) * (1.0 if direction == "nose-up" else -1.0)


def checked_pitch(system, p, *, weight, airspeed_eas, maneuvering_speed_eas, limit_load_factor,
                  direction="nose-up", max_amplitude=None, steps=200, rtol=0.002, delta_guess=FIRST_AMPLITUDE,
                  max_iterations=10, gravity=G0) -> CheckedPitchResult:
    """The 25.331(c)(2) checked pitch maneuver of a free-pitch airplane with an elevator.

    Parameters
    ----------
    system : AeroelasticBeamSystem
        Built with ``plunge``, ``trim``, ``pitch`` and ``elevator``.
    p : numpy.ndarray
        Its packed parameters (``trim_lift`` = ``weight``).
    weight : float
        The airplane's weight, the load factor's denominator (N).
    airspeed_eas, maneuvering_speed_eas : float
        The entry speed V and V_A of 25.335(c) (m/s EAS).
    limit_load_factor : float
        The 25.337 positive limit load factor: the nose-up target (the nose-down target is 0 g)
        and the end of the nose-down loads (25.331(c)(2)(v)).
    direction : {"nose-up", "nose-down"}, optional
        The maneuver.
    max_amplitude : float or None, optional
        The largest available elevator command (rad; stops, pilot effort), or None (unlimited).
        When the target needs more, delta_1 = ``max_amplitude`` and the history of
        25.331(c)(2)(iii) holds it for the Delta t (at most 5 s) that reaches the target.
    steps : int, optional
        Time steps over [0, 3 pi / (2 omega)] (a hold adds steps of the same size).
    rtol : float, optional
        The peak load-factor increment meets the target increment within rtol of it.
    delta_guess : float, optional
        The first amplitude of the secant iteration (rad).
    max_iterations : int, optional
        Most marches of the secant iteration.
    gravity : float, optional
        Gravitational acceleration (m/s^2).

    Returns
    -------
    CheckedPitchResult
        The histories and the peak against the target.
    """
    check_maneuver_inputs(airspeed_eas=airspeed_eas, maneuvering_speed_eas=maneuvering_speed_eas,
                          direction=direction, steps=steps)
    if not getattr(system, "elevator", False):
        raise ValueError("checked_pitch needs a system with an elevator (build_aeroelastic_system(elevator=True))")
    if not (np.isfinite(limit_load_factor) and limit_load_factor > 1.0):
        raise ValueError(f"limit_load_factor = {limit_load_factor}; allowed range (1, inf) (14 CFR 25.337(b))")
    if max_amplitude is not None and not (np.isfinite(max_amplitude) and max_amplitude > 0):
        raise ValueError(f"max_amplitude = {max_amplitude} rad; allowed range (0, inf) rad")
    target_load_factor = float(limit_load_factor) if direction == "nose-up" else 0.0
    target_inc = target_load_factor - 1.0
    lam, _ = short_period_mode(system, p, gravity=gravity)
    w_sp = abs(lam)
    w_min = minimum_frequency(airspeed_eas, maneuvering_speed_eas)
    omega = max(w_sp, w_min)
    dt = maneuver_duration(omega) / int(steps)

    def run(delta_1, hold=0.0):
        n_steps = max(int(steps), int(np.ceil(maneuver_duration(omega, hold) / dt - 1e-9)))
        time = np.linspace(0.0, maneuver_duration(omega, hold), n_steps + 1)
        cmd = control_history(time, delta_1, omega, direction, hold=hold)
        X, n, mb = march_maneuver(system, p, time, cmd, gravity=gravity, weight=weight)
        return time, cmd, X, n, mb

    def miss(out):
        return _peak(out[3], direction) - 1.0 - target_inc

    tol = rtol * abs(target_inc)
    history = []
    d1, out = _secant_amplitude(run, miss, float(delta_guess), target_inc, tol, int(max_iterations), history,
                                direction)
    hold, reached = 0.0, True
    if max_amplitude is not None and d1 > max_amplitude:
        d1 = float(max_amplitude)
        hold, out, reached = _hold_search(lambda h: run(d1, h), miss, tol, int(max_iterations), history, d1,
                                          direction, 0.5 * np.pi / omega)
    time, cmd, X, n, mb = out
    considered = _considered(n, direction, limit_load_factor)
    bi = system.body_index
    return CheckedPitchResult(time=time, elevator_command=cmd, elevator=X[:, bi["elevator_deflection"]].copy(),
                              load_factor=n, pitch_rate=X[:, bi["pitch_rate"]].copy(), root_bending_moment=mb,
                              omega=float(omega), omega_short_period=float(w_sp), omega_min=float(w_min),
                              short_period_eigenvalue=lam, delta_1=float(d1), direction=direction,
                              target_load_factor=float(target_load_factor), peak_load_factor=_peak(n, direction),
                              t_max=float(time[-1]), considered=considered, iterations=history, states=X,
                              hold=float(hold), reached=bool(reached))


def _secant_amplitude(run, miss, d0, target_inc, tol, max_iterations, history, direction):
    """delta_1 (rad) and its march by the secant method on the peak load-factor increment, from d0."""
    out0 = run(d0)
    f0 = miss(out0)
    history.append((d0, 0.0, _peak(out0[3], direction)))
    d1 = d0 * target_inc / (f0 + target_inc)
    for _ in range(max_iterations):
        out1 = run(d1)
        f1 = miss(out1)
        history.append((d1, 0.0, _peak(out1[3], direction)))
        if abs(f1) <= tol:
            return d1, out1
        d0, f0, d1 = d1, f1, d1 - f1 * (d1 - d0) / (f1 - f0)
    raise RuntimeError(f"checked_pitch: the secant iteration on delta_1 did not meet the tolerance {tol:.3g} in "
                       f"{max_iterations} marches (last delta_1 = {d1:.6g} rad, peak n = {history[-1][2]:.6g})")


class _Found(Exception):
    """Raised inside the root finder when a march meets the tolerance (carries the march)."""


def _hold_search(run_hold, miss, tol, max_iterations, history, d1, direction, first):
    """(Delta t, march, reached) of 25.331(c)(2)(iii) at delta_1 = d1: the hold whose peak
    load-factor increment meets the target. The bracket grows from ``first`` (s) by doubling up to
    MAX_HOLD; Brent's method on it. MAX_HOLD and reached = False when even that falls short (the
    rule's "need not exceed five seconds")."""
    runs = {}

    def f(h):
        if h not in runs:  # Brent evaluates the bracket's ends again
            runs[h] = run_hold(h)
            history.append((d1, float(h), _peak(runs[h][3], direction)))
        value = miss(runs[h])
        if abs(value) <= tol:
            raise _Found(h)
        return value

    try:
        lo, f_lo = 0.0, f(0.0)
        hi = min(float(first), MAX_HOLD)
        f_hi = f(hi)
        while np.sign(f_hi) == np.sign(f_lo) and hi < MAX_HOLD:
            lo, f_lo, hi = hi, f_hi, min(2.0 * hi, MAX_HOLD)
            f_hi = f(hi)
        if np.sign(f_hi) == np.sign(f_lo):
            return hi, runs[hi], False
        sopt.brentq(f, lo, hi, xtol=1e-9, maxiter=3 * max_iterations)
    except _Found as found:
        h = found.args[0]
        return float(h), runs[h], True
    raise RuntimeError(f"checked_pitch: the search for the hold Delta t did not meet the tolerance {tol:.3g} "
                       f"(last Delta t = {history[-1][1]:.6g} s, peak n = {history[-1][2]:.6g})")


def _considered(n, direction, limit):
    """25.331(c)(2)(v): the instants before n first goes below 0 g (nose up) or above the positive
    limit (nose down); t_max is the end of the march."""
    beyond = n < 0.0 if direction == "nose-up" else n > float(limit)
    idx = np.flatnonzero(beyond)
    out = np.ones(n.size, dtype=bool)
    if idx.size:
        out[idx[0]:] = False
    return out
