"""The 14 CFR 25.349(a) rolling conditions on the antisymmetric aeroelastic half wing (docs/maneuvers.md, "Rolling conditions").

The regulation (:data:`REGULATION`): at V_A a sudden deflection of the aileron to the stop; at V_C
the deflection that gives a roll rate not less than that of V_A; at V_D the deflection that gives one
third of it; each in combination with an airplane load factor of zero and of two-thirds of the
positive maneuvering load factor used in design, the wing's torsional flexibility included.

Method. The airplane is :func:`wingmdao.aero.system.build_aeroelastic_system` with ``roll=True``
(:mod:`wingmdao.aero.roll`: the right half wing on a fuselage free to roll, the left mirrored
antisymmetrically) and the ailerons of a surfaces file as control surfaces (their actuators in the
residual). The command is a step at t = 0+ (the actuator shapes the deflection). The roll rate of
V_A is the steady roll (:func:`~wingmdao.aero.roll.steady_roll`) with every aileron at its stop
(``max_deflection_deg``, trailing edge down on the right wing); at V_C and V_D the deflection, the
same fraction k of the stops on every aileron, is found by the secant method on the steady roll
rate of the elastic wing (so the torsional flexibility is in the deflection, as 25.349(a) asks).
Each condition is marched from the level, unrolled state (the march carries the maximum angular
acceleration at the start and tends to the steady roll). The antisymmetric loads are increments:
the left wing carries the negatives of the right wing's. The symmetric loads at n = 0 and
n = 2/3 n_lim are the free-plunge trimmed static maneuver at the same speed (gravity n g0, lift
n W, :func:`symmetric_root_loads`); the combined design root loads are ``M_sym +- max_t |dM(t)|``
(the wing whose increment adds and the one whose increment subtracts; bending and torque
enveloped separately). ``aero_theory`` "strip" (per station) or "vlm" (the lattice with an
antisymmetric image for the rolling wing, a symmetric one for the symmetric maneuver).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wingmdao.aero.plunge import body_mass, half_wing_mass
from wingmdao.aero.roll import check_roll_inputs, steady_roll
from wingmdao.aero.system import cached_aeroelastic_system, three_dimensional_parameters
from wingmdao.loads.atmosphere import G0, density, speed_of_sound
from wingmdao.timemarch.bdf import march, solve_static, state_rates
from wingmdao.timemarch.system import layout, pack


#: the aerodynamic theories of the rolling conditions (the lifting line's slopes are those of the
#: symmetric loading)
ROLL_AERO_THEORIES = ("strip", "vlm")

#: 14 CFR 25.349 (introductory text and paragraph (a)), as written
REGULATION = (
    "§ 25.349 Rolling conditions. The airplane must be designed for loads resulting from the rolling conditions "
    "specified in paragraphs (a) and (b) of this section. Unbalanced aerodynamic moments about the center of "
    "gravity must be reacted in a rational or conservative manner, considering the principal masses furnishing "
    "the reacting inertia forces.\n"
    "(a) Maneuvering. The following conditions, speeds, and aileron deflections (except as the deflections may "
    "be limited by pilot effort) must be considered in combination with an airplane load factor of zero and of "
    "two-thirds of the positive maneuvering factor used in design. In determining the required aileron "
    "deflections, the torsional flexibility of the wing must be considered in accordance with § 25.301(b):\n"
    "(1) Conditions corresponding to steady rolling velocities must be investigated. In addition, conditions "
    "corresponding to maximum angular acceleration must be investigated for airplanes with engines or other "
    "weight concentrations outboard of the fuselage. For the angular acceleration conditions, zero rolling "
    "velocity may be assumed in the absence of a rational time history investigation of the maneuver.\n"
    "(2) At VA, a sudden deflection of the aileron to the stop is assumed.\n"
    "(3) At VC, the aileron deflection must be that required to produce a rate of roll not less than that "
    "obtained in paragraph (a)(2) of this section.\n"
    "(4) At VD, the aileron deflection must be that required to produce a rate of roll not less than one-third "
    "of that in paragraph (a)(2) of this section."
)

#: the conditions: name -> (paragraph, fraction of the V_A steady roll rate; None: ailerons at the stops)
CONDITIONS = {"VA": ("25.349(a)(2)", None), "VC": ("25.349(a)(3)", 1.0), "VD": ("25.349(a)(4)", 1.0 / 3.0)}


def check_rolling_inputs(alleviation, roll_inertia, maneuvering_speed_eas, aero_theory) -> None:
    """The inputs every 25.349(a) rolling run needs (``maneuver --rolling`` and ``size --rolling``),
    checked before any model is built: a one-line ValueError naming the flag, its value and the
    allowed range.

    Parameters
    ----------
    alleviation : str or None
        The control-surface file naming the ailerons (``--alleviation``).
    roll_inertia : float or None
        I_xx,body of the aircraft outside both wing halves (kg m^2, ``--roll-inertia``).
    maneuvering_speed_eas : float or None
        V_A (m/s EAS, ``--maneuvering-speed-eas``).
    aero_theory : str
        The aerodynamic theory (``--aero-theory``), one of :data:`ROLL_AERO_THEORIES`.
    """
    if aero_theory not in ROLL_AERO_THEORIES:
        raise ValueError(f"--aero-theory {aero_theory}: --rolling allows {', '.join(ROLL_AERO_THEORIES)} (the "
                         "lifting line's slopes are those of the symmetric loading)")
    if alleviation is None:
        raise ValueError("--rolling needs --alleviation FILE.yaml naming the ailerons (the case has no control "
                         "surfaces; e.g. docs/examples/pegasus_ailerons.yaml)")
    if roll_inertia is None:
        raise ValueError("--rolling needs --roll-inertia (I_xx,body, kg m^2; the case has none)")
    if not (np.isfinite(roll_inertia) and roll_inertia > 0):
        raise ValueError(f"--roll-inertia = {roll_inertia} kg*m**2; allowed range (0, inf) kg*m**2")
    if maneuvering_speed_eas is None:
        raise ValueError("--rolling needs --maneuvering-speed-eas (V_A, m/s EAS; the case has none)")
    if not (np.isfinite(maneuvering_speed_eas) and maneuvering_speed_eas > 0):
        raise ValueError(f"--maneuvering-speed-eas = {maneuvering_speed_eas} m/s; allowed range (0, inf) m/s")


def rolling_speeds(maneuvering_speed_eas, cruise_speed_eas, dive_speed_eas, altitude_m) -> dict:
    """``{"VA", "VC", "VD"}`` -> (EAS, TAS m/s, Mach) of the rolling conditions flown at ``altitude_m``;
    ValueError unless 0 < V_A <= V_C (14 CFR 25.335(c)).

    Parameters
    ----------
    maneuvering_speed_eas : float
        V_A (m/s EAS).
    cruise_speed_eas : float
        V_C (m/s EAS).
    dive_speed_eas : float
        V_D (m/s EAS).
    altitude_m : float
        Altitude (m).

    Returns
    -------
    dict
        The speeds.
    """
    va = float(maneuvering_speed_eas)
    if not (np.isfinite(va) and 0 < va <= cruise_speed_eas):
        raise ValueError(f"--maneuvering-speed-eas = {va} m/s; allowed range (0, V_C = {cruise_speed_eas:.2f}] m/s EAS "
                         "(14 CFR 25.335(c): V_A <= V_C)")
    root_sigma = float(np.sqrt(density(altitude_m) / density(0.0)))
    a = float(speed_of_sound(altitude_m))
    eas = {"VA": va, "VC": float(cruise_speed_eas), "VD": float(dive_speed_eas)}
    return {k: (v, v / root_sigma, v / root_sigma / a) for k, v in eas.items()}


@dataclass
class RollHistory:
    """One rolling condition's march (SI, rad; the right half wing).

    Parameters
    ----------
    time : numpy.ndarray
        (n_t,) s.
    aileron : numpy.ndarray
        (n_t, n_s) actuator deflections (rad, trailing edge down +).
    roll_rate, roll_angle, roll_acceleration : numpy.ndarray
        (n_t,) p (rad/s), phi (rad), dp/dt (rad/s^2); + right wing up (about +x, x aft).
    root_bending, root_torque : numpy.ndarray
        (n_t,) root moments M_x, M_y (N m, body axes) of the right half wing.
    command_fraction : float
        k: the command is k times each aileron's stop.
    steady_roll_rate : float
        Steady p (rad/s) at that command.
    """

    time: np.ndarray
    aileron: np.ndarray
    roll_rate: np.ndarray
    roll_angle: np.ndarray
    roll_acceleration: np.ndarray
    root_bending: np.ndarray
    root_torque: np.ndarray
    command_fraction: float
    steady_roll_rate: float


def _theory(aero_theory, beam_params, aero_params, controls=None, antisymmetric=False):
    """The aerodynamic parameters of ``aero_theory`` (checked) on top of the strip's."""
    if aero_theory not in ROLL_AERO_THEORIES:
        raise ValueError(f"aero_theory = {aero_theory!r}; allowed for the rolling conditions: "
                         f"{', '.join(ROLL_AERO_THEORIES)}")
    return {**aero_params, **three_dimensional_parameters(aero_theory, beam_params["node_positions"],
                                                          aero_params["chord"], aero_params["ref_point"],
                                                          aero_params["mach"], controls, antisymmetric)}


def rolling_model(beam_params, aero_params, controls, *, roll_inertia, aero_theory="strip"):
    """(system, packed parameters) of the antisymmetric half wing with the ailerons ``controls``
    (:class:`~wingmdao.aero.controls.ControlSpec`, no law) and the fuselage roll inertia I_xx,body
    (kg m^2, > 0; each half carries I_xx,body / 2).

    Parameters
    ----------
    beam_params : dict
        Beam parameters.
    aero_params : dict
        Strip aerodynamic parameters.
    controls : ControlSpec
        The ailerons (no control law).
    roll_inertia : float
        I_xx,body: roll inertia of the aircraft outside both wing halves (kg m^2).
    aero_theory : {"strip", "vlm"}, optional
        Strips, or the vortex lattice with its antisymmetric image.

    Returns
    -------
    tuple
        (system, packed parameters).
    """
    check_roll_inputs(roll_inertia=roll_inertia)
    if controls.outputs:
        raise ValueError("rolling_model: the ailerons fly open loop; the control spec has a law")
    aero = _theory(aero_theory, beam_params, aero_params, controls, antisymmetric=True)
    n = np.asarray(aero_params["chord"]).size
    system = cached_aeroelastic_system(n, roll=True, controls=controls, aero_theory=aero_theory)
    values = {**beam_params, **aero, "body_roll_inertia": 0.5 * float(roll_inertia)}
    return system, pack(system.param_specs, values)


def roll_forcing(system, command, n_time=1):
    """(n_time, n_forcing) forcing of a rolling system: gravity zero, the surfaces' ``command`` (n_s,)
    rad from t > 0 (zero at t = 0, the level unrolled state), ``roll_start`` 1 at t = 0.

    Parameters
    ----------
    system : AeroelasticBeamSystem
        Built with ``roll=True`` and controls.
    command : array_like
        (n_s,) aileron commands (rad).
    n_time : int, optional
        Instants.

    Returns
    -------
    numpy.ndarray
        The forcing.
    """
    ql = layout(system.forcing_specs)
    Q = np.zeros((int(n_time), system.n_forcing))
    Q[:, ql["surface_command"]] = np.asarray(command, dtype=float)
    if n_time > 1:
        Q[0, ql["surface_command"]] = 0.0
        Q[0, ql["roll_start"]] = 1.0
    return Q


def steady_roll_rate(system, p, command, x0=None):
    """(steady roll rate rad/s, steady state) of the elastic wing at aileron ``command`` (n_s,) rad.

    Parameters
    ----------
    system : AeroelasticBeamSystem
        Built with ``roll=True`` and controls.
    p : numpy.ndarray
        Packed parameters.
    command : array_like
        (n_s,) aileron commands (rad).
    x0 : numpy.ndarray, optional
        Newton's start.

    Returns
    -------
    tuple
        (p_ss, state).
    """
    x = steady_roll(system, p, roll_forcing(system, command)[0], x0)
    return float(x[system.body_index["roll_rate"]]), x


def command_for_roll_rate(system, p, stops, target, *, rtol=1e-6, max_iterations=20):
    """k such that the steady roll rate at ``k stops`` is ``target`` (rad/s), by the secant method
    from the linear estimate.

    Parameters
    ----------
    system : AeroelasticBeamSystem
        Built with ``roll=True`` and controls.
    p : numpy.ndarray
        Packed parameters.
    stops : array_like
        (n_s,) each aileron's stop (rad).
    target : float
        Steady roll rate (rad/s).
    rtol : float, optional
        Relative tolerance on the roll rate.
    max_iterations : int, optional
        Most steady solves.

    Returns
    -------
    tuple
        (k, steady roll rate rad/s).
    """
    stops = np.asarray(stops, dtype=float)
    k0, (r0, x) = 1.0, steady_roll_rate(system, p, stops)
    if r0 * target <= 0:
        raise ValueError(f"command_for_roll_rate: the ailerons roll the wing the other way at this speed (steady "
                         f"p = {r0:.6g} rad/s at the stops): beyond aileron reversal")
    k1 = target / r0
    for _ in range(max_iterations):
        r1, x = steady_roll_rate(system, p, k1 * stops, x)
        if abs(r1 - target) <= rtol * abs(target):
            return float(k1), r1
        k0, r0, k1 = k1, r1, k1 - (r1 - target) * (k1 - k0) / (r1 - r0)
    raise RuntimeError(f"command_for_roll_rate: no convergence in {max_iterations} steady solves (k = {k1:.6g})")


def condition_commands(beam_params, speeds, aero_params_at, controls, stops, *, roll_inertia,
                       aero_theory="strip") -> dict:
    """Each 25.349(a) condition's rolling model and aileron command: the stops at V_A, at V_C the
    fraction of them that gives the V_A steady roll rate, at V_D the fraction giving a third of it.

    Parameters
    ----------
    beam_params : dict
        The half wing's beam parameters.
    speeds : dict
        :func:`rolling_speeds`: per condition ``(v_eas, v_tas, mach)``.
    aero_params_at : callable
        ``aero_params_at(v_tas, mach)``: the aerodynamic parameters at that flight point.
    controls : ControlSpec
        The ailerons.
    stops : array_like
        Each surface's stop (rad).
    roll_inertia : float
        I_xx,body of the aircraft outside both wing halves (kg m^2).
    aero_theory : str
        One of :data:`ROLL_AERO_THEORIES`.

    Returns
    -------
    dict
        Per condition (:data:`CONDITIONS` order) ``(system, p, command_fraction, steady_roll_rate)``.
    """
    out, p_a = {}, None
    for name, (_, fraction) in CONDITIONS.items():
        _, v, mach = speeds[name]
        system, p = rolling_model(beam_params, aero_params_at(v, mach), controls, roll_inertia=roll_inertia,
                                  aero_theory=aero_theory)
        if fraction is None:
            k, rate = 1.0, steady_roll_rate(system, p, stops)[0]
            p_a = rate
        else:
            k, rate = command_for_roll_rate(system, p, stops, fraction * p_a)
        out[name] = (system, p, k, rate)
    return out


def march_roll(system, p, time, command, command_fraction=1.0, steady_rate=float("nan")) -> RollHistory:
    """March a sudden aileron step ``command`` (n_s,) rad from the level unrolled state.

    Parameters
    ----------
    system : AeroelasticBeamSystem
        Built with ``roll=True`` and controls.
    p : numpy.ndarray
        Packed parameters.
    time : numpy.ndarray
        (n_t,) s, uniform.
    command : array_like
        (n_s,) aileron commands (rad).
    command_fraction : float, optional
        k, recorded.
    steady_rate : float, optional
        The steady roll rate at ``command`` (rad/s), recorded.

    Returns
    -------
    RollHistory
        The histories.
    """
    Q = roll_forcing(system, command, time.size)
    X = march(system, time, p, Q, modified_newton=True).states
    Xd = state_rates(X, float(time[1] - time[0]))
    bi = system.body_index
    names = [s[0] for s in system.controls.surfaces]
    defl = np.stack([X[:, system.control_index[f"{nm}_deflection"]] for nm in names], axis=1)
    root = system.layout.beam_states(X)[:, 0, :]
    return RollHistory(time=np.asarray(time), aileron=defl, roll_rate=X[:, bi["roll_rate"]].copy(),
                       roll_angle=X[:, bi["roll_angle"]].copy(), roll_acceleration=Xd[:, bi["roll_rate"]].copy(),
                       root_bending=root[:, 9].copy(), root_torque=root[:, 10].copy(),
                       command_fraction=float(command_fraction), steady_roll_rate=float(steady_rate))


def symmetric_root_loads(beam_params, aero_params, *, load_factor, weight, gravity=G0, aero_theory="strip"):
    """Root M_x, M_y (N m) of the right half wing in the trimmed static symmetric maneuver at
    ``load_factor`` (free plunge and trim: lift n W, gravity n g0 on the wing's mass).

    Parameters
    ----------
    beam_params : dict
        Beam parameters.
    aero_params : dict
        Strip aerodynamic parameters (the condition's speed).
    load_factor : float
        n (-).
    weight : float
        Airplane weight W (N).
    gravity : float, optional
        g0 (m/s^2).
    aero_theory : {"strip", "vlm"}, optional
        Strips, or the vortex lattice (symmetric image).

    Returns
    -------
    tuple
        (M_x, M_y) N m.
    """
    n = np.asarray(aero_params["chord"]).size
    aero = _theory(aero_theory, beam_params, aero_params)
    s = cached_aeroelastic_system(n, plunge=True, trim=True, aero_theory=aero_theory)
    m_h = half_wing_mass(beam_params["mass_per_length"], beam_params["node_positions"])[0]
    values = {**beam_params, **aero, "trim_lift": float(load_factor) * weight,
              "body_mass": body_mass(weight / gravity, m_h)}
    p = pack(s.param_specs, values)
    ql = layout(s.forcing_specs)
    q = np.zeros(s.n_forcing)
    q[ql["gravity"].start + 2] = -float(load_factor) * gravity
    q[ql["trim_active"]] = 1.0
    x, _ = solve_static(s, p, q)
    root = s.layout.beam_states(x[None, :])[0, 0]
    return float(root[9]), float(root[10])


def combined_loads(history: RollHistory, symmetric) -> dict:
    """The combined design root loads of one condition at one symmetric load factor: ``M_sym +- max_t |dM|``.

    Parameters
    ----------
    history : RollHistory
        The condition's march.
    symmetric : tuple
        (M_x, M_y) of the symmetric maneuver (N m).

    Returns
    -------
    dict
        ``root_bending_max``, ``root_bending_min``, ``root_torque_max``, ``root_torque_min`` (N m).
    """
    db = float(np.max(np.abs(history.root_bending)))
    dt = float(np.max(np.abs(history.root_torque)))
    return {"root_bending_max": symmetric[0] + db, "root_bending_min": symmetric[0] - db,
            "root_torque_max": symmetric[1] + dt, "root_torque_min": symmetric[1] - dt}
