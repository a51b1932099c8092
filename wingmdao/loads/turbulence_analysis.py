"""One 25.341(b) continuous-turbulence analysis of a wing: the linear gust model about the 1 g state,
its frequency response, A-bar, design loads and correlations (docs/turbulence.md).

Two aerodynamic models, as ``wingmdao gust``:

* ``coupled`` (:func:`coupled_gust_model`): the aeroelastic beam of :mod:`wingmdao.aero.system`
  (unsteady strip theory, Wagner and Kuessner lag states, apparent mass), clamped or free in
  plunge, trimmed in 1 g level flight (alpha_trim solved for lift = W under gravity, then held);
  the stations meet the gust at their leading edges;
* ``strip`` (:func:`strip_gust_model`): the structural beam, root clamped, under the Schrenk 1 g
  spanload, with the quasi-steady strip-theory gust lift 1/2 rho V c a w at each station's
  centre of pressure (:func:`wingmdao.loads.maneuver.strip_line_loads`) as its gust input, the
  loads of ``wingmdao size CASE --aero strip`` in the frequency domain.

:func:`turbulence_analysis` then evaluates the response on a grid refined at the modes of the
pencil and returns everything 25.341(b) asks for (:mod:`wingmdao.loads.turbulence`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from wingmdao.aero.controls import control_spec, read_alleviation
from wingmdao.aero.plunge import body_mass, half_wing_mass
from wingmdao.aero.system import aero_parameters, cached_aeroelastic_system, three_dimensional_parameters
from wingmdao.beam.residual import STATE_BLOCKS
from wingmdao.beam.static import cached_beam_system
from wingmdao.loads import turbulence as tb
from wingmdao.loads.atmosphere import G0, LB
from wingmdao.loads.maneuver import maneuver_line_loads, strip_line_loads
from wingmdao.stability.frequency import (LOAD_NAMES, LOAD_UNITS, OutputMap, aeroelastic_outputs, frequency_grid,
                                          frequency_response, gust_columns, internal_load_output, lift_weights,
                                          linear_gust_model,
                                          pencil_eigenvalues, state_output, stress_response)
from wingmdao.timemarch.bdf import solve_static
from wingmdao.timemarch.system import layout, pack


@dataclass
class GustModel:
    """A linear gust model (:class:`~wingmdao.stability.frequency.LinearGustModel`) with the
    eigenvalues of its pencil (for the frequency grid), a description, and the system, packed
    parameters and forcing of its static (1 g) solve (for the gradient,
    :mod:`wingmdao.stability.frequency_adjoint`).

    Parameters
    ----------
    model : wingmdao.stability.frequency.LinearGustModel
        The linearised model with its outputs.
    eigenvalues : numpy.ndarray
        Eigenvalues of its pencil (1/s), for the frequency grid.
    description : str
        Description for reports.
    system : wingmdao.timemarch.system.ResidualSystem or None
        The residual system of the static (1 g) solve.
    p : numpy.ndarray or None
        Its packed parameters.
    q_static : numpy.ndarray or None
        Its packed static forcing.
    """

    model: object
    eigenvalues: np.ndarray
    description: str
    system: object = None
    p: np.ndarray | None = None
    q_static: np.ndarray | None = None


def coupled_gust_model(beam_params: dict, aero_params: dict, *, chord, axis_fraction, weight, plunge=True,
                       gravity=G0, damping=None, aero_theory="strip", surfaces=None, law=None) -> GustModel:
    """The aeroelastic beam trimmed in 1 g level flight (lift of both halves = ``weight`` N under
    ``gravity`` m/s^2), clamped or free in ``plunge`` (body mass = weight / g0 - 2 m_half), linearised
    with alpha_trim held; stations meet the gust at their leading edges. ``damping``: the beam's
    structural damping (:class:`~wingmdao.beam.residual.StrainRateDamping`), None: undamped.
    ``aero_theory``: the residual's quasi-steady lift, ``"strip"`` or ``"vlm"`` (then ``aero_params``
    hold ``lift_influence`` and ``moment_influence``, :func:`wingmdao.aero.three_dimensional_parameters`).
    ``surfaces`` (:class:`~wingmdao.aero.controls.ControlSurface`, None: none) and ``law``
    (:class:`~wingmdao.aero.controls.ControlLaw`, None: the surfaces held at the trimmed command):
    the actuators and the law are states of the residual, so the linearisation carries them
    (docs/controls.md, "The law in continuous turbulence"); the outputs then include every
    surface's deflection and rate (:func:`control_outputs`).

    Parameters
    ----------
    beam_params : dict
        The beam's parameters (``node_positions`` (n, 3) m, section properties).
    aero_params : dict
        The aerodynamic parameters of the residual (sections, flight point).
    chord : array_like
        Chord per node (m), shape (n,).
    axis_fraction : array_like
        Beam axis per node as a fraction of the chord.
    weight : float
        Aircraft weight (N), the trimmed lift of both halves.
    plunge : bool
        Free in plunge; False: root clamped.
    gravity : float
        Gravitational acceleration (m/s^2).
    damping : wingmdao.beam.residual.StrainRateDamping or None
        Structural damping of the beam.
    aero_theory : str
        ``"strip"`` or ``"vlm"``.
    surfaces : sequence of wingmdao.aero.controls.ControlSurface or None
        Control surfaces; None: none.
    law : wingmdao.aero.controls.ControlLaw or None
        Control law; None: surfaces held at the trimmed command.

    Returns
    -------
    GustModel
        The linear gust model.
    """
    n = np.asarray(chord).size
    spec = None
    if surfaces:
        spec = control_spec(surfaces, np.asarray(beam_params["node_positions"])[:, 1], law)
    system = cached_aeroelastic_system(n, damping=damping, plunge=bool(plunge), trim=True, aero_theory=aero_theory,
                                       controls=spec)
    params = {**beam_params, **aero_params, "trim_lift": float(weight)}
    if aero_theory == "vlm" and spec is not None:  # the surfaces as deflected panels of one lattice
        params.update(three_dimensional_parameters("vlm", beam_params["node_positions"], chord, axis_fraction,
                                                   aero_params["mach"], controls=spec))
    if law is not None:
        params.update(law.matrices())
    r0 = np.asarray(beam_params["node_positions"])
    if plunge:
        params["body_mass"] = body_mass(weight / G0, half_wing_mass(beam_params["mass_per_length"], r0)[0])
    x_le = r0[:, 0] - np.asarray(axis_fraction) * np.asarray(chord)
    return gust_model_from_parameters(system, params, x_stations=x_le, gravity=gravity)


def gust_model_from_parameters(system, params: dict, *, x_stations, gravity=G0) -> GustModel:
    """The gust model of an aeroelastic ``system`` (trim on) from its parameter values ``params``
    (every parameter of ``system.param_specs``, ``airspeed`` and ``trim_lift`` included): trimmed in
    1 g level flight under ``gravity`` m/s^2, linearised with the trim angle held, the stations
    meeting the gust at ``x_stations`` (m, body x), the load factor over ``trim_lift``. The model of
    :func:`coupled_gust_model` and of a sizing's turbulence constraint
    (:class:`~wingmdao.components.turbulence.TurbulenceStressKS`, :func:`wingmdao.sizing.turbulence_loads`).

    Parameters
    ----------
    system : AeroelasticBeamSystem
        The residual system (:func:`wingmdao.aero.system.cached_aeroelastic_system` with ``trim=True``).
    params : dict
        Parameter values by name (SI).
    x_stations : array_like
        (n,) m: where each station meets the gust.
    gravity : float
        Gravitational acceleration (m/s^2).

    Returns
    -------
    GustModel
        The linear gust model with its pencil's eigenvalues.
    """
    p = pack(system.param_specs, params)
    ql = layout(system.forcing_specs)
    q_static = np.zeros(system.n_forcing)
    q_static[ql["gravity"].start + 2] = -gravity
    q_static[ql["trim_active"]] = 1.0
    x0, _ = solve_static(system, p, q_static)
    q = q_static.copy()
    q[ql["trim_active"]] = 0.0
    outputs = aeroelastic_outputs(system, p, q, x0, weight=float(np.ravel(params["trim_lift"])[0]))
    outputs.update(control_outputs(system, x0))
    model = linear_gust_model(system, p, q, x0, x_stations=np.asarray(x_stations, dtype=float),
                              airspeed=float(np.ravel(params["airspeed"])[0]), outputs=outputs)
    plunge = getattr(system, "plunge", False)
    ctl = getattr(system, "controls", None)
    law = "" if ctl is None else (f", {ctl.n_surfaces} control surface(s)"
                                  + (f" and a law on {', '.join(ctl.outputs)}" if ctl.outputs else " held"))
    return GustModel(model, pencil_eigenvalues(model),
                     f"coupled strip theory, {'free plunge' if plunge else 'clamped'}, trimmed 1 g{law}", system, p,
                     q_static)


def control_outputs(system, x0) -> dict:
    """The control surfaces' deflection and rate as outputs of the linear gust model (rad and rad/s per
    m/s of gust): ``{"surface_deflection": OutputMap, "surface_rate": OutputMap}``, one row per surface
    in the order of ``system.controls.surfaces``; empty for a system without surfaces.

    Parameters
    ----------
    system : AeroelasticBeamSystem
        The residual system (its ``controls`` and ``control_index``).
    x0 : array_like
        The linearisation state.

    Returns
    -------
    dict
        ``{name: OutputMap}`` (empty without surfaces).
    """
    ctl = getattr(system, "controls", None)
    if ctl is None:
        return {}
    x0 = np.asarray(x0, dtype=float).ravel()
    N = system.n_state
    m = gust_columns(layout(system.forcing_specs)).size
    out = {}
    for key, state in (("surface_deflection", "deflection"), ("surface_rate", "rate")):
        idx = [system.control_index[f"{srf[0]}_{state}"] for srf in ctl.surfaces]
        C = sp.csr_matrix((np.ones(len(idx)), (np.arange(len(idx)), idx)), shape=(len(idx), N))
        out[key] = OutputMap(x0[idx], C, sp.csr_matrix((len(idx), N)), sp.csr_matrix((len(idx), m)),
                             "rad" if state == "deflection" else "rad/s")
    return out


def strip_gust_model(beam_params: dict, *, chord, axis_fraction, weight, airspeed, density, semi_span,
                     fuselage_half_width=0.0, lift_slope=2 * np.pi, cp_fraction=0.25, gravity=G0,
                     damping=None) -> GustModel:
    """The clamped structural beam under the Schrenk 1 g spanload and gravity, linearised, with
    the quasi-steady strip gust lift 1/2 rho V c a w_i (N/m per m/s) at each centre of pressure
    as input; the load factor is the lift of both halves over ``weight``.

    Parameters
    ----------
    beam_params : dict
        The beam's parameters (``node_positions`` (n, 3) m, section properties).
    chord : array_like
        Chord per node (m), shape (n,).
    axis_fraction : array_like
        Beam axis per node as a fraction of the chord.
    weight : float
        Aircraft weight (N), the 1 g lift of both halves.
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    semi_span : float
        Semi-span of the Schrenk spanload (m).
    fuselage_half_width : float
        Fuselage half-width (m) of the Schrenk spanload.
    lift_slope : float
        Section lift slope (1/rad).
    cp_fraction : float
        Centre of pressure as a fraction of the chord.
    gravity : float
        Gravitational acceleration (m/s^2).
    damping : wingmdao.beam.residual.StrainRateDamping or None
        Structural damping of the beam.

    Returns
    -------
    GustModel
        The linear gust model.
    """
    r0 = np.asarray(beam_params["node_positions"], dtype=float)
    c, xb = np.asarray(chord, dtype=float), np.asarray(axis_fraction, dtype=float)
    n = c.size
    system = cached_beam_system(n, damping=damping)
    ql = layout(system.forcing_specs)
    steady = maneuver_line_loads(r0, c, xb, weight, 1.0, semi_span=semi_span, fuselage_half_width=fuselage_half_width)
    q = np.zeros(system.n_forcing)
    q[ql["force_per_length"]] = np.asarray(steady.force_per_length).ravel()
    q[ql["moment_per_length"]] = np.asarray(steady.moment_per_length).ravel()
    q[ql["gravity"].start + 2] = -gravity
    p = pack(system.param_specs, beam_params)
    x0, _ = solve_static(system, p, q)
    lift_per_gust = 0.5 * density * airspeed * c * lift_slope  # N/m per m/s, station i
    f, m = strip_line_loads(r0, c, xb, np.diag(lift_per_gust), cp_fraction)  # (station, node, 3)
    dq = sp.csc_matrix(system.jac_inputs(x0, np.zeros_like(x0), p, q)[1])
    cols = np.r_[np.arange(ql["force_per_length"].start, ql["force_per_length"].stop),
                 np.arange(ql["moment_per_length"].start, ql["moment_per_length"].stop)]
    dload_dw = np.concatenate([f.reshape(n, -1), m.reshape(n, -1)], axis=1).T  # (6 n, station)
    G = dq[:, cols] @ sp.csc_matrix(dload_dw)
    beam = np.arange(18 * n).reshape(n, 18)
    wts = lift_weights(r0, weight)
    N = system.n_state
    i_m, i_z = beam[0, STATE_BLOCKS["M"].start], beam[-1, STATE_BLOCKS["r"].start + 2]
    outputs = {
        "loads": internal_load_output(x0, beam, n),
        "root_bending_moment": state_output(i_m, x0[i_m], N, n),
        "load_factor": OutputMap(np.array([wts @ np.asarray(steady.force_per_length)[:, 2]]), sp.csr_matrix((1, N)),
                                 sp.csr_matrix((1, N)), sp.csr_matrix(wts * lift_per_gust)),
        "tip_deflection": state_output(i_z, x0[i_z] - r0[-1, 2], N, n),
    }
    x_cp = r0[:, 0] + (cp_fraction - xb) * c
    model = linear_gust_model(system, p, q, x0, x_stations=x_cp, airspeed=airspeed, outputs=outputs, gust_input=G)
    return GustModel(model, pencil_eigenvalues(model),
                     "quasi-steady strip theory on the clamped structural beam, Schrenk 1 g", system, p, q)


def _lists(a):
    return np.asarray(a).tolist()


def turbulence_analysis(gm: GustModel, u_sigma: float, *, f_min=1e-3, f_max=40.0, n_base=161, n_mode=16,
                        stress_matrices=None, surfaces=None) -> dict:
    """A-bar, PSDs, design loads (P_1g +/- U_sigma A-bar) and (bending, torsion) correlations of every
    station; a JSON-ready dict (SI; A-bar in output units per m/s; PSDs one-sided, per Hz, for a unit
    rms gust). ``stress_matrices`` (n, 8, 6): :func:`wingmdao.stability.frequency.stress_matrix` of
    every station, adds the linear box stresses (Pa). ``surfaces``: the
    :class:`~wingmdao.aero.controls.ControlSurface` of a model with control surfaces (the outputs of
    :func:`control_outputs`), adds ``control_surfaces``: per surface A-bar of the deflection and rate
    and U_sigma A-bar against the surface's limits.

    Parameters
    ----------
    gm : GustModel
        The linear gust model.
    u_sigma : float
        Design gust intensity U_sigma (m/s TAS, > 0).
    f_min : float
        Lowest frequency of the grid (Hz).
    f_max : float
        Highest frequency of the grid (Hz).
    n_base : int
        Points of the geometric base grid.
    n_mode : int
        Points added about each lightly damped mode
        (:func:`wingmdao.stability.frequency.frequency_grid`).
    stress_matrices : array_like or None
        Stress matrices of every station, shape (n, 8, 6).
    surfaces : sequence of wingmdao.aero.controls.ControlSurface or None
        The model's control surfaces.

    Returns
    -------
    dict
        The JSON-ready analysis.
    """
    if not (np.isfinite(u_sigma) and u_sigma > 0):
        raise ValueError(f"u_sigma = {u_sigma} m/s; allowed range (0, inf) m/s TAS")
    model = gm.model
    V = model.airspeed
    w = frequency_grid(gm.eigenvalues, f_min=f_min, f_max=f_max, n_base=n_base, n_mode=n_mode)
    fr = frequency_response(model, w)
    H = dict(fr.outputs)
    one_g = {k: m.y0 for k, m in model.outputs.items()}
    n = one_g["loads"].size // 6
    if stress_matrices is not None:
        S = np.asarray(stress_matrices)
        H["stress"] = stress_response(H["loads"], S).reshape(w.size, -1)
        one_g["stress"] = np.einsum("sij,sj->si", S, one_g["loads"].reshape(n, 6)).ravel()
    ab = {k: tb.a_bar(w, h, V) for k, h in H.items()}
    per_hz = 2 * np.pi  # Phi_f = 2 pi Phi_omega
    res = {"frequency_hz": _lists(w / (2 * np.pi)),
           "psd": {"root_bending_moment": _lists(per_hz * ab["root_bending_moment"].psd[:, 0]),
                   "load_factor": _lists(per_hz * ab["load_factor"].psd[:, 0]),
                   "units": "one-sided, output^2 per Hz per (m/s)^2 of gust variance"},
           "transfer_function_magnitude": {k: _lists(np.abs(H[k][:, 0])) for k in ("root_bending_moment",
                                                                                    "load_factor", "tip_deflection")}}
    a_bar, err, design = {}, {}, {}
    for k in ("root_bending_moment", "load_factor", "tip_deflection"):
        a_bar[k], err[k] = float(ab[k].value[0]), float(ab[k].error[0])
        up, down = tb.design_loads(one_g[k][0], u_sigma, a_bar[k])
        design[k] = {"one_g": float(one_g[k][0]), "up": float(up), "down": float(down)}
    loads_ab = ab["loads"].value.reshape(n, 6)
    loads_err = ab["loads"].error.reshape(n, 6)
    loads_1g = one_g["loads"].reshape(n, 6)
    for j, name in enumerate(LOAD_NAMES):
        a_bar[name], err[name] = _lists(loads_ab[:, j]), _lists(loads_err[:, j])
        up, down = tb.design_loads(loads_1g[:, j], u_sigma, loads_ab[:, j])
        design[name] = {"one_g": _lists(loads_1g[:, j]), "up": _lists(up), "down": _lists(down)}
    if stress_matrices is not None:
        sa = ab["stress"].value.reshape(n, 8)
        a_bar["stress"], err["stress"] = _lists(sa), _lists(ab["stress"].error.reshape(n, 8))
        up, down = tb.design_loads(one_g["stress"].reshape(n, 8), u_sigma, sa)
        design["stress"] = {"one_g": _lists(one_g["stress"].reshape(n, 8)), "up": _lists(up), "down": _lists(down)}
    HL = H["loads"].reshape(w.size, n, 6)
    jb, jt = LOAD_NAMES.index("bending_moment"), LOAD_NAMES.index("torsion")
    rho = tb.correlation(w, HL[:, :, jb], HL[:, :, jt], V)
    corr = [tb.correlated_loads((loads_1g[i, jb], loads_1g[i, jt]), u_sigma, (loads_ab[i, jb], loads_ab[i, jt]),
                                float(rho[i])) for i in range(n)]
    ellipse = tb.equal_probability_ellipse((loads_1g[0, jb], loads_1g[0, jt]), u_sigma,
                                           (loads_ab[0, jb], loads_ab[0, jt]), float(rho[0]))
    # relative to each output's largest A-bar along the span (near the tip the loads, and A-bar, vanish)
    rel = max(float(np.max(err[k]) / np.max(v)) for k, v in a_bar.items() if np.max(v) > 0)
    res.update({
        "a_bar": a_bar, "a_bar_error": err, "design_loads": design,
        "correlation": {"bending_torsion": _lists(rho),
                        "correlated_loads": [_lists(c) for c in corr],
                        "root_ellipse": _lists(ellipse)},
        "load_units": dict(zip(LOAD_NAMES, LOAD_UNITS)),
        "quadrature": {"points": int(w.size), "f_min_hz": float(f_min), "f_max_hz": float(f_max),
                       "max_relative_error_a_bar": float(rel),
                       "method": "trapezoid on a grid refined at the pencil's modes; error = Richardson "
                                 "(I_h - I_2h)/3 on every other point + the power-law tail beyond f_max"},
        "model": gm.description,
    })
    if surfaces and "surface_deflection" in ab:
        res["control_surfaces"] = _surface_report(surfaces, ab, u_sigma)
    return res


def _surface_report(surfaces, ab, u_sigma) -> dict:
    """Per surface: A-bar of deflection (deg per m/s) and rate (deg/s per m/s), their design values
    U_sigma A-bar against the surface's limits (reported, never clipped)."""
    out = {}
    for k, s in enumerate(surfaces):
        d, r = (float(np.degrees(ab[key].value[k])) for key in ("surface_deflection", "surface_rate"))
        out[s.name] = {"a_bar_deflection_deg_per_m_s": d, "a_bar_rate_deg_s_per_m_s": r,
                       "design_deflection_deg": u_sigma * d, "max_deflection_deg": float(s.max_deflection_deg),
                       "design_rate_deg_s": u_sigma * r, "max_rate_deg_s": float(s.max_rate_deg_s),
                       "deflection_limit_exceeded": bool(u_sigma * d > s.max_deflection_deg),
                       "rate_limit_exceeded": bool(u_sigma * r > s.max_rate_deg_s)}
    return out


def sizing_turbulence_options(module, setup, *, damping=None, rho_ks=50.0, alleviation=None,
                              aero_theory="strip") -> dict:
    """Options of :class:`wingmdao.components.turbulence.TurbulenceStressKS` for the sizing of a case
    with aerodynamic data. ``module``: its case module (``aero_data(n)``, ``flight_point()``,
    ``CRUISE_ALTITUDE_FT``, ``GUST_SET_DEFAULTS``, ``TOGW_LB``); ``setup``: its CaseSetup. The V_C
    point (U_sigma of 25.341(b)(3) at the cruise altitude), root clamped (the aircraft mass outside
    the wing is not a sizing input), the stations meeting the gust at their leading edges, the box
    geometry of the setup, sigma_allow the material's yield stress. ``alleviation``: the path of an
    alleviation file (docs/controls.md; None: no surfaces): its surfaces, actuators and law enter the
    constraint's residual (options ``controls`` and ``control_law``); a law on ``load_factor`` or
    ``pitch_rate`` is refused (the constraint's wing is clamped). ``aero_theory``: the beam's
    quasi-steady lift, ``"strip"`` (the case's section slopes) or ``"vlm"`` (the vortex lattice of
    the planform at the V_C Mach number, :func:`wingmdao.aero.three_dimensional_parameters`).

    Parameters
    ----------
    module : module
        The case module (``aero_data``, ``flight_point``, ``CRUISE_ALTITUDE_FT``,
        ``GUST_SET_DEFAULTS``, ``TOGW_LB``).
    setup : wingmdao.cases.CaseSetup
        The case's geometry and material.
    damping : wingmdao.beam.residual.StrainRateDamping or None
        Structural damping of the beam.
    rho_ks : float
        KS aggregation parameter of the constraint.
    alleviation : str or None
        Path of an alleviation file; None: no control surfaces.
    aero_theory : str
        ``"strip"`` or ``"vlm"``.

    Returns
    -------
    dict
        The component's options.
    """
    if aero_theory not in ("strip", "vlm"):
        raise ValueError(f"aero_theory = {aero_theory!r}; allowed: 'strip', 'vlm'")
    geo = setup.geometry
    n = geo.num_nodes
    aero, fp = module.aero_data(n), module.flight_point()
    V = float(fp["cruise_speed"])
    fg = module.GUST_SET_DEFAULTS
    point = tb.continuous_turbulence_intensity(module.CRUISE_ALTITUDE_FT, z_mo_ft=fg["z_mo_ft"],
                                               mlw_over_mtow=fg["mlw_over_mtow"], mzfw_over_mtow=fg["mzfw_over_mtow"])
    values = aero_parameters(n, chord=aero["chord"], ref_point=aero["ref_point"], lift_slope=aero["lift_slope"],
                             airspeed=V, density=aero["density"], mach=V / aero["speed_of_sound"])
    values.pop("airspeed")
    values["trim_lift"] = module.TOGW_LB * LB * G0
    x_le = np.asarray(geo.node_positions)[:, 0] - np.asarray(aero["ref_point"]) * np.asarray(aero["chord"])
    controls = {}
    if alleviation is not None:
        surfaces, law = read_alleviation(alleviation)
        bad = [o for o in (law.outputs if law is not None else ()) if o in ("load_factor", "pitch_rate")]
        if bad:
            raise ValueError(f"--turbulence --alleviation {alleviation}: output {bad[0]} needs a free aircraft; the "
                             "turbulence constraint's wing is root clamped (allowed outputs: root_bending, "
                             "tip_acceleration)")
        try:
            spec = control_spec(surfaces, np.asarray(geo.node_positions)[:, 1], law)
        except ValueError as exc:
            raise ValueError(f"--alleviation {alleviation}: {exc}") from None
        controls = {"controls": spec, "control_law": law}
        if law is not None:  # U_sigma A-bar of the surfaces' deflection and rate over their limits
            controls["surface_limits"] = tuple((float(np.radians(s.max_deflection_deg)), float(np.radians(s.max_rate_deg_s)))
                                               for s in surfaces)
    if aero_theory == "vlm":
        values.update(three_dimensional_parameters("vlm", np.asarray(geo.node_positions, dtype=float),
                                                   np.broadcast_to(aero["chord"], (n,)),
                                                   np.broadcast_to(aero["ref_point"], (n,)),
                                                   V / aero["speed_of_sound"], controls=controls.get("controls")))
    return {"plunge": False, "airspeed": V, **controls, "x_stations": x_le, "aero_theory": aero_theory,
            "width": np.asarray(geo.width),
            "height": np.asarray(geo.height), "section_to_csn": geo.section_to_csn, "u_sigma": float(point.u_sigma),
            "sigma_allow": float(setup.material.sigma_y), "rho_ks": float(rho_ks), "damping": damping,
            "values": values}
