"""The 1 - cos gust response of a wing's beam, analysis only (``wingmdao gust``; docs/aeroelasticity.md).

* :func:`coupled_gust_response` - the aeroelastic beam (unsteady strip theory on the deforming
  wing, :func:`~wingmdao.aero.system.cached_aeroelastic_system`) marched from the trimmed 1 g state,
  root clamped or free in plunge, optionally free in pitch with a horizontal tail;
* :func:`strip_gust_response` - the sizing's precomputed rigid-wing strip-theory loads
  (:func:`wingmdao.loads.gust.gust_line_loads` on the Schrenk 1 g spanload) on the clamped
  structural beam.

Both return a :class:`GustResponse`: the load factor history, the beam states and the strips' wing
lift slope. The flight point is a :class:`GustFlight`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from wingmdao.aero.controls import control_spec, limit_report
from wingmdao.aero.dlm import DLM_CHORDWISE, DLM_FLAP_CHORDWISE, DLM_SPANWISE, REDUCED_FREQUENCIES
from wingmdao.aero.modal_controls import control_terms, hinge_moment_history
from wingmdao.aero.modal_free import free_modal_dlm_wing
from wingmdao.aero.modal_loads import modal_accelerations, station_load_history
from wingmdao.aero.rfa import N_LAGS
from wingmdao.aero.strip import station_gust_history
from wingmdao.aero.system import cached_aeroelastic_system, three_dimensional_parameters
from wingmdao.beam.static import march_line_loads
from wingmdao.loads.atmosphere import G0
from wingmdao.loads.gust import gust_line_loads
from wingmdao.loads.maneuver import maneuver_line_loads
from wingmdao.timemarch.bdf import march, state_rates
from wingmdao.stability.modal import modal_dlm_wing
from wingmdao.timemarch.system import layout, pack


@dataclass(frozen=True)
class GustFlight:
    """Flight point and gust of a response (SI): true airspeed ``airspeed`` (m/s), ``density``
    (kg/m^3), ``mach``, ``altitude`` (m), gust gradient ``gradient`` H (m), design gust velocity
    ``u_ds_eas`` and ``u_ds_tas`` (m/s), aircraft ``weight`` (N), ``gust_start`` (s: the gust front
    reaches the most forward leading edge).

    Parameters
    ----------
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    mach : float
        Mach number.
    altitude : float
        Altitude (m).
    gradient : float
        Gust gradient H (m).
    u_ds_eas : float
        Design gust velocity, equivalent airspeed (m/s).
    u_ds_tas : float
        Design gust velocity, true airspeed (m/s).
    weight : float
        Aircraft weight (N).
    gust_start : float
        Time at which the gust front reaches the most forward leading edge (s).
    """

    airspeed: float
    density: float
    mach: float
    altitude: float
    gradient: float
    u_ds_eas: float
    u_ds_tas: float
    weight: float
    gust_start: float


@dataclass
class GustResponse:
    """``load_factor`` (n_time,): lift of both half-wings (with free pitch, plus the tail's) over W;
    ``states`` (n_time, n, 18): the beam states per node; ``wing_lift_slope`` (1/rad): 2 int c a dy / S
    of the strips; ``trim_alpha`` (rad, None for strip loads); ``pitch``: the pitch histories with
    free pitch (``pitch_angle_rad``, ``pitch_rate_rad_s``, ``tail_lift_n``, ``tail_incidence_rad``);
    ``controls``: with control surfaces, their ``deflection`` and ``rate`` (n_time, n_s) rad, rad/s,
    ``hinge_moment`` (n_time, n_s) N m and the :func:`~wingmdao.aero.controls.limit_report` ``limits``.
    The doublet lattice's modal response (:func:`dlm_gust_response`) has no beam states
    (``states`` None) but ``station_loads`` (n_time, n, 6): internal force (N) and moment (N m) at
    every node, body axes, increments on the jig (free: on the 1 g flight; its ``pitch`` holds
    ``tail_lift_n`` as an increment and no tail incidence); ``tip_displacement`` (n_time,) m, z,
    elastic; ``dlm``: the modal model's figures (modes, lag roots, fit errors).

    Parameters
    ----------
    load_factor : ndarray, shape (n_time,)
        Load factor.
    states : ndarray, shape (n_time, n, 18) or None
        Beam states per node.
    wing_lift_slope : float
        Wing lift slope (1/rad).
    trim_alpha : float, optional
        Trim angle of attack (rad).
    pitch : dict
        Pitch histories with free pitch.
    controls : dict
        Control-surface histories and limits.
    station_loads : ndarray, shape (n_time, n, 6), optional
        Internal loads of the modal response (N, N m).
    tip_displacement : ndarray, shape (n_time,), optional
        Tip z displacement of the modal response (m).
    dlm : dict
        Figures of the modal model.
    """

    load_factor: np.ndarray
    states: np.ndarray | None
    wing_lift_slope: float
    trim_alpha: float | None = None
    pitch: dict = field(default_factory=dict)
    controls: dict = field(default_factory=dict)
    station_loads: np.ndarray | None = None
    tip_displacement: np.ndarray | None = None
    dlm: dict = field(default_factory=dict)


def gust_profile(flight: GustFlight):
    """1 - cos gust velocity (m/s TAS, up) at the leading edge reached first, as a function of time.

    Parameters
    ----------
    flight : GustFlight
        Flight point and gust.

    Returns
    -------
    callable
        ``profile(t)``: gust velocity (m/s) at time ``t`` (s).
    """
    V, H, u_tas, start = flight.airspeed, flight.gradient, flight.u_ds_tas, flight.gust_start

    def profile(tau):
        d = V * (np.asarray(tau) - start)
        return np.where((d >= 0) & (d <= 2 * H), 0.5 * u_tas * (1 - np.cos(np.pi * d / H)), 0.0)

    return profile


def wing_lift_slope(section_slope, chord, node_positions, area) -> float:
    """Wing lift slope (1/rad) of strips of slope ``section_slope``: 2 int c a dy / S (trapezoid).

    Parameters
    ----------
    section_slope : float or array_like, shape (n,)
        Section lift slope a at the nodes (1/rad).
    chord : float or array_like, shape (n,)
        Chord at the nodes (m).
    node_positions : array_like, shape (n, 3)
        Beam node positions (m).
    area : float
        Wing reference area S, both halves (m^2).

    Returns
    -------
    float
        The wing lift slope (1/rad).
    """
    a = np.asarray(section_slope) * np.asarray(chord)
    ds = np.linalg.norm(np.diff(node_positions, axis=0), axis=1)
    return float(2 * np.sum(0.5 * (a[1:] + a[:-1]) * ds) / area)


def coupled_gust_response(time, beam_params, chord, axis_frac, aero_params, flight: GustFlight, *, area,
                          plunge=True, body_mass=None, pitch_params=None, tail_lag=False,
                          aero_theory="strip", surfaces=None, law=None) -> GustResponse:
    """March the aeroelastic beam through the gust from the trimmed 1 g state.

    ``beam_params`` and ``aero_params`` are the beam and strip parameters per node
    (:func:`wingmdao.design.design_beam_params`, :func:`wingmdao.aero.aero_parameters`), ``area`` the
    wing reference area (m^2); ``plunge``: free in plunge (``body_mass``, kg, the aircraft less the
    wings) or root clamped; ``pitch_params`` (:func:`wingmdao.aero.pitch.pitch_parameters`): also free
    in pitch, the load factor then (wing + tail lift) / W. The gust reaches each strip after its
    penetration delay from the most forward leading edge, and the tail's aerodynamic centre x_t / V
    after it. ``aero_theory``: ``"vlm"`` when ``aero_params`` carry the vortex lattice's influence
    (:func:`wingmdao.aero.three_dimensional_parameters`), else ``"strip"`` (strips, or lifting-line
    slopes in ``lift_slope``). ``surfaces`` (:class:`~wingmdao.aero.controls.ControlSurface`) and
    ``law`` (:class:`~wingmdao.aero.controls.ControlLaw`, optional): control surfaces and a feedback
    law in the march, acting on the increments from the trimmed state (docs/controls.md).

    Parameters
    ----------
    time : ndarray, shape (n_time,)
        Uniform time grid from 0 (s).
    beam_params : dict
        Beam parameters per node.
    chord : array_like, shape (n,)
        Streamwise chord (m).
    axis_frac : array_like, shape (n,)
        Beam axis as a fraction of the chord aft of the leading edge.
    aero_params : dict
        Aerodynamic parameters per node.
    flight : GustFlight
        Flight point and gust.
    area : float
        Wing reference area (m^2).
    plunge : bool
        Free in plunge (else root clamped).
    body_mass : float, optional
        Aircraft mass less the wings (kg), with ``plunge``.
    pitch_params : dict, optional
        Free-pitch parameters; None: no pitch freedom.
    tail_lag : bool
        Lag the downwash at the tail (with free pitch).
    aero_theory : str
        ``"strip"`` or ``"vlm"``.
    surfaces : sequence of ControlSurface, optional
        Control surfaces.
    law : ControlLaw, optional
        Feedback law of the surfaces.

    Returns
    -------
    GustResponse
        The response.
    """
    chord, axis_frac = np.asarray(chord, dtype=float), np.asarray(axis_frac, dtype=float)
    pitch = pitch_params is not None
    spec = control_spec(surfaces, beam_params["node_positions"][:, 1], law) if surfaces else None
    system = cached_aeroelastic_system(chord.size, plunge=plunge, trim=True, pitch=pitch, tail_lag=pitch and tail_lag,
                                       aero_theory=aero_theory, controls=spec)
    params = {**beam_params, **aero_params, "trim_lift": flight.weight, **(law.matrices() if law is not None else {})}
    if aero_theory == "vlm" and spec is not None:  # the surfaces as deflected panels of one lattice
        params.update(three_dimensional_parameters("vlm", beam_params["node_positions"], chord, axis_frac,
                                                   aero_params["mach"], controls=spec))
    if plunge:
        params["body_mass"] = body_mass
    if pitch:
        params.update(pitch_params)
    p = pack(system.param_specs, params)
    r0 = beam_params["node_positions"]
    x_le = r0[:, 0] - axis_frac * chord
    profile = gust_profile(flight)
    ql = layout(system.forcing_specs)
    Q = np.zeros((time.size, system.n_forcing))
    Q[:, ql["gust_velocity"]] = station_gust_history(time, x_le, flight.airspeed, profile)
    Q[:, ql["gravity"].start + 2] = -G0
    Q[0, ql["trim_active"]] = 1.0
    if pitch:
        Q[:, ql["tail_gust_velocity"].start] = profile(time - (params["tail_x"] - x_le.min()) / flight.airspeed)
    dt = float(time[1] - time[0])
    hist = march(system, time, p, Q, modified_newton=True)
    lift = system.total_lift_history(hist.states, dt, p, Q)
    out = {}
    if pitch:
        tail = system.tail_lift_history(hist.states, dt, p, Q)
        lift = lift + tail
        bi = system.body_index
        out = {"pitch_angle_rad": hist.states[:, bi["pitch_angle"]].tolist(),
               "pitch_rate_rad_s": hist.states[:, bi["pitch_rate"]].tolist(),
               "tail_lift_n": tail.tolist(), "tail_incidence_rad": float(hist.states[0, bi["tail_incidence"]])}
    if "lift_influence" in aero_params:  # the lattice's wing slope: lift of a unit angle at every station
        slope = wing_lift_slope(aero_params["lift_influence"].sum(axis=1), np.ones(chord.size), r0, area)
    else:
        slope = wing_lift_slope(aero_params["lift_slope"] / np.sqrt(1 - flight.mach ** 2), chord, r0, area)
    ctl = {}
    if spec is not None:
        ctl = system.control_histories(hist.states, dt, p, Q)
        ctl["limits"] = limit_report(time, ctl["deflection"], ctl["rate"], surfaces)
    return GustResponse(lift / flight.weight, system.layout.beam_states(hist.states), slope,
                        float(hist.states[0, system.trim_index]), out, ctl)


def strip_gust_response(time, beam_params, chord, axis_frac, flight: GustFlight, *, area, semi_span,
                        fuselage_half_width) -> GustResponse:
    """The sizing's precomputed gust loads (rigid-wing quasi-steady strip theory, slope 2 pi, on the
    Schrenk 1 g spanload; as ``wingmdao size CASE --aero strip``) on the structural beam, root
    clamped; the load factor is the applied lift of both half-wings over W.

    Parameters
    ----------
    time : ndarray, shape (n_time,)
        Uniform time grid from 0 (s).
    beam_params : dict
        Beam parameters per node.
    chord : array_like, shape (n,)
        Streamwise chord (m).
    axis_frac : array_like, shape (n,)
        Beam axis as a fraction of the chord aft of the leading edge.
    flight : GustFlight
        Flight point and gust.
    area : float
        Wing reference area (m^2).
    semi_span : float
        Semi-span (m), for the Schrenk spanload.
    fuselage_half_width : float
        Fuselage half width (m).

    Returns
    -------
    GustResponse
        The response.
    """
    r0, n = beam_params["node_positions"], np.asarray(chord).size
    steady = maneuver_line_loads(r0, chord, axis_frac, flight.weight, 1.0, semi_span=semi_span,
                                 fuselage_half_width=fuselage_half_width)
    loads = gust_line_loads(r0, chord, axis_frac, time, gust_gradient_m=flight.gradient, u_ds_eas=flight.u_ds_eas,
                            airspeed_tas=flight.airspeed, altitude_m=flight.altitude,
                            gust_start_time=flight.gust_start, steady=steady,
                            fuselage_half_width=fuselage_half_width)
    hist = march_line_loads(beam_params, time, loads.force_per_length, loads.moment_per_length, (0.0, 0.0, -G0))
    fz = loads.force_per_length[:, :, 2]
    ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
    n_load = 2 * np.sum(0.5 * (fz[:, 1:] + fz[:, :-1]) * ds, axis=1) / flight.weight
    return GustResponse(n_load, hist.states.reshape(time.size, n, 18), wing_lift_slope(2 * np.pi, chord, r0, area))


def alleviation_summary(without: GustResponse, with_law: GustResponse, surfaces, law) -> dict:
    """The load alleviation's effect (JSON-ready): peak root bending (total, 1 g included, and the
    increment over the trimmed value; N m; the doublet lattice's modal response: increments on the
    1 g flight both) and peak load-factor increment without and with the law,
    the surfaces' deflection, rate and hinge-moment histories with their peaks against the limits,
    and the law's matrices.

    Parameters
    ----------
    without : GustResponse
        Response without the law.
    with_law : GustResponse
        Response with the law (with control histories).
    surfaces : sequence of ControlSurface
        The control surfaces.
    law : ControlLaw or None
        The law.

    Returns
    -------
    dict
        The summary.
    """
    def bending(resp):   # the doublet lattice's modal response: increments (no beam states)
        return resp.states[:, 0, 9] if resp.states is not None else resp.station_loads[:, 0, 3]

    def peaks(resp):
        m = bending(resp)
        dm = m - m[0]
        dn = resp.load_factor - resp.load_factor[0]
        return float(m[np.argmax(np.abs(m))]), float(dm[np.argmax(np.abs(dm))]), float(np.max(np.abs(dn)))

    m0, dm0, dn0 = peaks(without)
    m1, dm1, dn1 = peaks(with_law)
    out_surfaces = {}
    hinge = with_law.controls["hinge_moment"]
    for k, s in enumerate(surfaces):
        rep = dict(with_law.controls["limits"][s.name])
        rep.update(hinge=s.hinge, span=None if s.span is None else list(s.span),
                   nodes=None if s.nodes is None else list(s.nodes), actuator_order=s.actuator_order,
                   hinge_moment_n_m=hinge[:, k].tolist(), peak_hinge_moment_n_m=float(hinge[np.argmax(np.abs(hinge[:, k])), k]))
        out_surfaces[s.name] = rep
    law_out = None if law is None else {"outputs": list(law.outputs), **{k: v.tolist() for k, v in law.matrices().items()}}
    return {"surfaces": out_surfaces, "law": law_out,
            "peak_root_bending_moment_without_law": m0, "peak_root_bending_moment_with_law": m1,
            "peak_incremental_root_bending_without_law": dm0, "peak_incremental_root_bending_with_law": dm1,
            "incremental_root_bending_reduction": float(1.0 - abs(dm1) / abs(dm0)) if dm0 else 0.0,
            "peak_incremental_load_factor_without_law": dn0, "peak_incremental_load_factor_with_law": dn1,
            "load_factor_without_law": without.load_factor.tolist(),
            "root_bending_moment_without_law": bending(without).tolist()}


def gust_velocity_derivatives(flight: GustFlight, time) -> np.ndarray:
    """(n_time, 3): the 1 - cos gust velocity (m/s TAS, up) at the leading edge reached first and
    its first two time derivatives (the forcing of :func:`wingmdao.aero.rfa_system.modal_rfa_system`).

    Parameters
    ----------
    flight : GustFlight
        Flight point and gust.
    time : array_like, shape (n_time,)
        Times (s).

    Returns
    -------
    ndarray, shape (n_time, 3)
        Velocity (m/s), its rate (m/s^2) and second rate (m/s^3).
    """
    V, H, u = flight.airspeed, flight.gradient, flight.u_ds_tas
    d = V * (np.asarray(time, dtype=float) - flight.gust_start)
    on = (d >= 0) & (d <= 2 * H)
    w = np.pi * V / H
    return np.column_stack([np.where(on, 0.5 * u * (1 - np.cos(np.pi * d / H)), 0.0),
                            np.where(on, 0.5 * u * w * np.sin(np.pi * d / H), 0.0),
                            np.where(on, 0.5 * u * w ** 2 * np.cos(np.pi * d / H), 0.0)])


def dlm_gust_response(time, beam_params, chord, axis_frac, flight: GustFlight, *, area, n_modes: int = 6,
                      n_lags: int = N_LAGS, reduced_frequencies=REDUCED_FREQUENCIES, n_chordwise=DLM_CHORDWISE,
                      n_spanwise=DLM_SPANWISE, plunge: bool = False, pitch_params=None, surfaces=None,
                      law=None) -> GustResponse:
    """The gust response of the doublet lattice in the modal basis of the jig beam.

    The lowest ``n_modes`` normal modes of the beam about the jig (undamped, root clamped), the
    doublet-lattice generalized forces and station loads at ``reduced_frequencies`` and the flight
    Mach number, Roger's approximation with ``n_lags`` lag roots, marched by BDF2 from rest on
    ``time``; the gust front reaches the foremost leading edge at ``flight.gust_start`` and each
    panel after its delay. ``plunge``: the aircraft (mass ``flight.weight / g``) free in plunge, the
    rigid-body plunge mode in the basis; ``pitch_params``
    (:func:`wingmdao.aero.pitch.pitch_parameters`): also free in pitch with the quasi-steady tail,
    the gust reaching the tail ``(x_t - x_gust) / V`` after the leading edge
    (:mod:`wingmdao.aero.modal_free`; the increments on the trimmed 1 g flight). The load factor is
    ``1 +`` the lift increment of both half-wings (and the tail) over W; station loads by force
    summation (:mod:`wingmdao.aero.modal_loads`). ``surfaces`` and ``law``: control surfaces as flap
    modes of the lattice with their actuators and feedback law (:mod:`wingmdao.aero.modal_controls`;
    with the default ``n_chordwise`` the lattice then has :data:`wingmdao.aero.dlm.DLM_FLAP_CHORDWISE`
    chordwise panels, the hinges on panel edges).

    Parameters
    ----------
    time : ndarray, shape (n_time,)
        Uniform time grid from 0 (s).
    beam_params : dict
        Beam parameters per node.
    chord : array_like, shape (n,)
        Streamwise chord (m).
    axis_frac : array_like, shape (n,)
        Beam axis as a fraction of the chord aft of the leading edge.
    flight : GustFlight
        Flight point and gust.
    area : float
        Wing reference area (m^2).
    n_modes : int
        Number of normal modes.
    n_lags : int
        Number of lag roots of Roger's approximation.
    reduced_frequencies : array_like
        Reduced frequencies of the generalized forces.
    n_chordwise : int
        Chordwise panels of the doublet lattice.
    n_spanwise : int
        Spanwise strips per beam element.
    plunge : bool, optional
        Free the aircraft in plunge (the plunge mode in the basis).
    pitch_params : dict or None, optional
        :func:`wingmdao.aero.pitch.pitch_parameters`: also free in pitch with the quasi-steady tail.
    surfaces : sequence of ControlSurface, optional
        Control surfaces.
    law : ControlLaw, optional
        Feedback law of the surfaces.

    Returns
    -------
    GustResponse
        The response (no beam states; with surfaces their histories in ``controls``).
    """
    if pitch_params is not None and not plunge:
        raise ValueError("free pitch needs free plunge (plunge=True)")
    spec = control_spec(surfaces, np.asarray(beam_params["node_positions"])[:, 1], law) if surfaces else None
    if spec is not None and n_chordwise == DLM_CHORDWISE:
        n_chordwise = DLM_FLAP_CHORDWISE
    if plunge:
        wing = free_modal_dlm_wing(beam_params, chord, axis_frac, flight.mach, aircraft_mass=flight.weight / G0,
                                   pitch_params=pitch_params, n_modes=n_modes, n_lags=n_lags,
                                   reduced_frequencies=reduced_frequencies, n_chordwise=n_chordwise,
                                   n_spanwise=n_spanwise, controls=spec)
    else:
        wing = modal_dlm_wing(beam_params, chord, axis_frac, flight.mach, n_modes=n_modes, n_lags=n_lags,
                              reduced_frequencies=reduced_frequencies, n_chordwise=n_chordwise, n_spanwise=n_spanwise,
                              controls=spec)
    modal, structure, rfa, gaf, modes = wing.system, wing.structure, wing.rfa, wing.gaf, wing.modes
    tail = getattr(wing, "tail", None)
    m, V, rho = modes.count, flight.airspeed, flight.density
    F = np.zeros((np.size(time), modal.n_forcing))
    F[:, :3] = gust_velocity_derivatives(flight, time)
    if tail is not None:
        profile = gust_profile(flight)
        x_le = np.asarray(beam_params["node_positions"])[:, 0] - np.asarray(axis_frac) * np.asarray(chord)
        F[:, 3 + m] = profile(time - (pitch_params["tail_x"] - gaf.x_gust) / V)
        F[:, 4 + m] = profile(time - (x_le[0] - gaf.x_gust) / V)
    p = pack(modal.param_specs, {"airspeed": V, "density": rho, **(law.matrices() if law is not None else {})})
    # from rest: the free modes' static problem is singular (a plunge displacement loads nothing)
    X = march(modal, time, p, F, initial="state", x_init=np.zeros(modal.n_state)).states
    Xd = state_rates(X, float(time[1] - time[0])) if spec is not None else None
    total, aero = station_load_history(wing.loads, structure, rfa, X, F, V, rho, tail, wing.controls, Xd)
    a_wing = 2.0 * float(np.real(gaf.station_loads[0, 0, 2, -1])) / area
    lift = 2.0 * aero[:, 0, 2]
    pitch = {}
    if tail is not None:
        qd = 0.5 * rho * V ** 2
        tail_lift = tail.lift(qd, V, X[:, :m].T, X[:, m:2 * m].T, F[:, 3 + m], F[:, 4 + m])
        lift = lift + tail_lift
        pitch = {"pitch_angle_rad": X[:, 1].tolist(), "pitch_rate_rad_s": X[:, m + 1].tolist(),
                 "tail_lift_n": tail_lift.tolist()}
    tip = (wing.tip_displacement(X) if plunge else X[:, :m] @ modes.displacement[:, -1, 2])
    ctl = {}
    if spec is not None:
        a = modal_accelerations(structure, rfa, X, F, V, rho, tail, wing.controls, Xd)
        d, r, _, _ = control_terms(wing.controls, rfa, X, Xd, m)
        ctl = {"deflection": d, "rate": r,
               "hinge_moment": hinge_moment_history(wing.controls, rfa, X, Xd, a, F, V, rho),
               "limits": limit_report(time, d, r, surfaces)}
    return GustResponse(1.0 + lift / flight.weight, None, a_wing, pitch=pitch, controls=ctl, station_loads=total,
                        tip_displacement=tip, dlm=wing.info())
