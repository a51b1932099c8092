"""``wingmdao gust CASE``: gust response of a case's wing with the coupled aeroelastic beam.

Analysis only (docs/aeroelasticity.md): the case's wing (its box sections for the initial design
or the thicknesses of a sizing result, ``--design``) becomes an
:class:`~wingmdao.aero.system.AeroelasticBeamSystem` (unsteady strip theory on the deforming
beam, Jones-Wagner and Sears-Sparks-Kuessner lag states, apparent mass, Prandtl-Glauert); a
14 CFR 25.341 1-cos gust of gradient H (U_ds = U_ref (H/350 ft)^(1/6) EAS) crosses it with each
station's penetration delay, the aircraft free in plunge (``--plunge``, default) or clamped at the
symmetry plane (``--clamped``), and with ``--pitch free`` also in pitch with a horizontal tail
(:mod:`wingmdao.aero.pitch`; the aircraft's pitch inertia, CG and tail are required flags, the
load factor then (wing + tail lift) / W). The march starts from the trimmed, deformed 1 g level-flight state
(aircraft angle of attack solved so that the lift of both half-wings equals W, gravity on; the
``trim`` option of :func:`~wingmdao.aero.system.build_aeroelastic_system`), the gust an increment
on it; the load factor is the lift integrated over both half-wings over W. ``--aero strip``
instead applies the sizing's precomputed rigid-wing strip-theory gust loads (on the Schrenk 1 g
spanload) to the structural beam, root clamped; the JSON keys are the same (trim_alpha_rad null).

JSON keys: time, load_factor, peak_incremental_load_factor, quasi_steady_incremental_load_factor
(dn = rho0 U_de V_e a / (2 W/S), a the model's wing lift slope: strips, lifting line or vortex lattice), trim_alpha_rad, wing_lift_slope_per_rad,
mass_parameter (mu = 2 (W/S) / (rho c a g)), mean_chord_m, wing_loading_pa, root_bending_moment
(N m, M_x at the symmetry plane), root_torsion (N m, M_y), peak_incremental_root_bending_moment (N m,
max |M_x(t) - M_x(0)|), station_y_m, station_bending_moment and station_torsion (N m, time x
node, body axes), loads_include_1g, tip_displacement (m, z), peak_up/peak_down_incremental_load_factor, with --pitch free
pitch_angle_rad, pitch_rate_rad_s, tail_lift_n, tail_incidence_rad, and the inputs. With
``--alleviation FILE.yaml`` (control surfaces, actuators and a feedback law, docs/controls.md) the
histories are those with the law, and ``alleviation`` holds the surfaces' deflection, rate and
hinge-moment histories, their peaks against the limits and the peak root bending and load factor
without and with the law (:func:`~wingmdao.aero.gust_response.alleviation_summary`).

``--model stick`` (pegasus): the same gust on the free half aircraft's stick model
(:func:`wingmdao.cases.pegasus_stick.gust_response`; docs/stick-model.md); the JSON holds time,
load_factor, the peak increments, trim_alpha_rad, tail_incidence_rad, trim_thrust_n,
downwash_gradient and ``monitoring_loads`` (per station: force and moment histories, body axes,
with their maxima and minima). ``--design`` gives the stick model's wing the walls of a sizing
result; ``--stiffness-scale`` multiplies every beam's section stiffness.
"""

from __future__ import annotations

import os
import sys
import time as _time

import numpy as np

from wingmdao.cases import resolve_aero_theory
from wingmdao.plots import optional_pyplot, save_figure
from wingmdao.cli.parsers.gust import DLM_MODES, MAX_U_REF_FPS
from wingmdao.cli._io import check_output_dir, check_output_file, read_design, refuse_existing, warn, write_json
from wingmdao.aero.controls import control_spec, read_alleviation
from wingmdao.aero.lifting_line import lifting_line_lift_slope
from wingmdao.aero.pitch import pitch_parameters
from wingmdao.aero.plunge import body_mass as plunge_body_mass, half_wing_mass
from wingmdao.cases import available_cases, case_beam_parameters, check_step_count
from wingmdao.cases.planform import FT, G0, LB, wing_geometry
from wingmdao.cases import pegasus
from wingmdao.loads.atmosphere import altitude_ft_to_m, density, mach_to_tas, speed_of_sound
from wingmdao.loads.gust_set import read_gust_set
from wingmdao.aero.gust_response import (GustFlight, alleviation_summary, coupled_gust_response,
                                         dlm_gust_response, strip_gust_response, wing_lift_slope)
from wingmdao.aero.system import aero_parameters, three_dimensional_parameters
from wingmdao.cases import pegasus_stick
from wingmdao.envelope import monitoring_potatoes, stick_set_envelope

#: --stiffness-scale range (a rigid wing is approached well before 1e6)
STIFFNESS_SCALE = (1e-3, 1e6)
#: --stiffness-scale range of --model stick (beyond it the trim's static solve or the march of the whole
#: aircraft fails: a very flexible wing does not trim, a very stiff aircraft's Newton matrix turns singular)
STICK_STIFFNESS_SCALE = (0.1, 100.0)
#: absolute residual tolerance of the stick model's trim (static) solve: a stiffened aircraft's
#: residual stalls at round-off before the Newton step is small
STICK_STATIC_ATOL = 1e-9


def run(args):
    t_wall = _time.perf_counter()
    plunge = args.plunge or ("free" if args.aero == "coupled" else "clamped")
    if args.aero == "strip" and plunge == "free":
        raise ValueError("--plunge free needs --aero coupled (the strip-theory gust loads are precomputed on a "
                         "clamped wing); use --aero strip --clamped or --aero coupled --plunge free")
    if args.lifting_line and args.aero_theory == "dlm":
        raise ValueError("--lifting-line and --aero-theory dlm are two aerodynamic theories; give one")
    if args.lifting_line:
        warn("--lifting-line is deprecated; use --aero-theory lifting-line (same meaning)")
        args.aero_theory = "lifting-line"
    if args.aero_theory is None and args.model == "stick":  # the stick model's wing and tail are strips
        args.aero_theory = "strip"
    if args.aero == "strip" and args.aero_theory not in (None, "strip"):
        raise ValueError(f"--aero-theory {args.aero_theory} applies to --aero coupled (the precomputed --aero strip "
                         "loads use 2 pi)")
    args.aero_theory = resolve_aero_theory(args.aero_theory, args.aero)
    _check_dlm_args(args, plunge)
    args.plunge = plunge == "free"
    args.pitch = args.pitch == "free"
    _check_stick_args(args)
    gust_set = _read_stick_gust_set(args)
    _check_pitch_args(args)
    module = available_cases()[args.case]
    swept = getattr(module, "COUPLED_THEORIES", None)  # a swept case: only the lattice follows its sweep
    if args.aero == "coupled" and swept is not None and args.aero_theory not in swept:
        raise ValueError(f"--aero-theory {args.aero_theory}: not available for the {args.case} case with --aero coupled "
                         f"(its sweep: the strips take the streamwise chord with no sweep correction); allowed: "
                         + ", ".join(swept))
    base = __import__("wingmdao.cases.pegasus", fromlist=["GUST"])
    gust = dict(base.GUST)
    H_ft = gust["gradient_ft"] if args.gradient_ft is None else args.gradient_ft
    if not 30.0 <= H_ft <= 350.0:
        raise ValueError(f"--gust-gradient-ft = {H_ft} ft; allowed range [30, 350] ft (14 CFR 25.341(a)(3))")
    if not (np.isfinite(args.stiffness_scale) and STIFFNESS_SCALE[0] <= args.stiffness_scale <= STIFFNESS_SCALE[1]):
        raise ValueError(f"--stiffness-scale = {args.stiffness_scale}; allowed range [{STIFFNESS_SCALE[0]:g}, "
                         f"{STIFFNESS_SCALE[1]:g}] (beyond it the beam's Newton solve loses its digits)")
    lo, hi = STICK_STIFFNESS_SCALE
    if args.model == "stick" and not lo <= args.stiffness_scale <= hi:
        raise ValueError(f"--stiffness-scale = {args.stiffness_scale}; allowed range [{lo:g}, {hi:g}] with --model "
                         "stick (beyond it the whole aircraft's trim or march does not converge)")
    alt_ft = gust["altitude_ft"] if args.altitude_ft is None else args.altitude_ft
    if not 0.0 <= alt_ft <= 60000.0:
        raise ValueError(f"--altitude-ft = {alt_ft} ft; allowed range [0, 60000] ft (the 25.341 table)")
    mach = gust["mach"] if args.mach is None else args.mach
    if not 0.0 < mach < 1.0:
        raise ValueError(f"--mach = {mach}; allowed range (0, 1)")
    top = getattr(module, "MAX_COUPLED_MACH", None)
    if args.aero == "coupled" and top is not None and mach > top:
        raise ValueError(f"--mach = {mach}; allowed range (0, {top:g}] for the {args.case} case with --aero coupled "
                         "(above it the swept wing's flow is transonic: Prandtl-Glauert does not hold)")
    u_ref = gust["u_ref_fps"] if args.u_ref_fps is None else args.u_ref_fps
    if not (np.isfinite(u_ref) and 0 < u_ref <= MAX_U_REF_FPS):
        raise ValueError(f"--u-ref-fps = {u_ref} ft/s; allowed range (0, {MAX_U_REF_FPS:g}] ft/s EAS "
                         "(14 CFR 25.341(a)(5): 56 ft/s at sea level)")
    t_final = gust["t_final"] if args.t_final is None else args.t_final
    case_options = module.OPTIONS()  # the case's time grid and gust start, as on 'wingmdao size'
    args.dt = getattr(case_options, "dt", base.PegasusOptions.dt) if args.dt is None else args.dt
    args.gust_start = (getattr(case_options, "gust_start", base.PegasusOptions.gust_start) if args.gust_start is None
                       else args.gust_start)

    check_step_count(t_final, args.dt, 20)  # finite, > 0, at most MAX_TIME_STEPS (with the memory estimate)
    if not args.dt <= t_final / 10:
        raise ValueError(f"--t-final ({t_final} s) and --dt ({args.dt} s): need 0 < 10 dt <= t_final")
    if not (np.isfinite(args.gust_start) and 0.0 <= args.gust_start < t_final):
        raise ValueError(f"--gust-start = {args.gust_start} s; allowed range [0, --t-final = {t_final}) s")
    surfaces, law = _check_alleviation(args)
    plot_path = check_outputs(args, f"{args.case}_gust.png")

    pf = module.PLANFORM
    weight = module.TOGW_LB * LB * G0
    walls = read_design(args.design, None, case=args.case, command="gust") if args.design else None
    setup, bp = case_beam_parameters(module, walls, source=f"--design {args.design}")
    bp["stiffness_csn"] = bp["stiffness_csn"] * args.stiffness_scale
    bp["compliance_csn"] = bp["compliance_csn"] / args.stiffness_scale
    _, chord, axis_frac = wing_geometry(pf, getattr(module, "ENGINES", ()))
    n = setup.geometry.num_nodes
    alt = float(altitude_ft_to_m(alt_ft))
    rho, rho0 = float(density(alt)), float(density(0.0))
    V = float(mach_to_tas(mach, alt))
    slope = 2 * np.pi
    if args.aero_theory == "lifting-line":
        y_nodes = np.abs(bp["node_positions"][:, 1])
        slope, _ = lifting_line_lift_slope(y_nodes, pf.chord, pf.semi_span)
    ap = aero_parameters(n, chord=chord, ref_point=axis_frac, lift_slope=slope, airspeed=V, density=rho,
                         mach=mach)
    if args.aero_theory in ("vlm", "dlm"):  # dlm: the lattice is its k = 0 limit (the downwash gradient's slope)
        ap.update(three_dimensional_parameters("vlm", bp["node_positions"], chord, axis_frac, mach))
    r0 = bp["node_positions"]
    if surfaces:
        _check_surfaces_on_beam(args, surfaces, law, r0)
    body_mass = plunge_body_mass(weight / G0, half_wing_mass(bp["mass_per_length"], r0)[0])
    if args.pitch:
        a_w = (wing_lift_slope(ap["lift_influence"].sum(axis=1), np.ones(n), r0, _area(args)) if "lift_influence" in ap
               else wing_lift_slope(ap["lift_slope"] / np.sqrt(1 - mach ** 2), chord, r0, _area(args)))
        if args.downwash_gradient is None:  # Etkin & Reid (1996) / Nelson (1998): deps/dalpha = 2 a_w / (pi AR)
            args.downwash_gradient = 2 * a_w / (np.pi * (2 * pf.semi_span) ** 2 / (pf.area_ft2 * FT ** 2))
        args.pitch_params = pitch_parameters(
            aircraft_mass=weight / G0, cg=(args.cg_x, args.cg_z), aircraft_pitch_inertia=args.pitch_inertia,
            tail_arm=args.tail_arm, tail_area=args.tail_area, tail_lift_slope=args.tail_lift_slope,
            downwash_gradient=args.downwash_gradient, mass_per_length=bp["mass_per_length"], node_positions=r0)
    H = H_ft * FT
    u_eas = u_ref * FT * (H_ft / 350.0) ** (1.0 / 6.0)
    u_tas = u_eas * np.sqrt(rho0 / rho)
    t = np.arange(0.0, t_final + 0.5 * args.dt, args.dt)
    point = (f"--gust-set {args.gust_set} ({len(gust_set.gusts())} gusts)" if gust_set is not None else
             f"V = {V:.1f} m/s TAS, rho = {rho:.4f} kg/m^3, U_ds = {u_eas:.2f} m/s EAS, H = {H_ft:g} ft")
    print(f"wingmdao gust {args.case}: {n} nodes, {t.size} steps, {point}, --aero {args.aero}, "
          f"{'free plunge' if args.plunge else 'clamped'}{' + free pitch' if args.pitch else ''}", file=sys.stderr)
    flight = GustFlight(airspeed=V, density=rho, mach=mach, altitude=alt, gradient=H, u_ds_eas=u_eas, u_ds_tas=u_tas,
                        weight=weight, gust_start=args.gust_start)
    wing_area = pf.area_ft2 * FT ** 2
    if args.model == "stick":
        if gust_set is not None:
            return _run_stick_set(args, t, gust_set, walls, n, t_wall=t_wall, plot_path=plot_path)
        return _run_stick(args, t, flight, walls, n, H_ft=H_ft, alt_ft=alt_ft, t_wall=t_wall, plot_path=plot_path)
    pitch_out, alleviation = {}, {}
    if args.aero_theory == "dlm":
        def dlm_response(**controls):
            return dlm_gust_response(t, bp, chord, axis_frac, flight, area=wing_area, n_modes=args.modes,
                                     plunge=args.plunge, pitch_params=args.pitch_params if args.pitch else None,
                                     **controls)

        if surfaces:  # without the law on the same lattice (the hinges on panel edges), the surfaces held at 0
            without = dlm_response(surfaces=surfaces, law=None)
            resp = dlm_response(surfaces=surfaces, law=law)
            alleviation = {"alleviation": {"file": args.alleviation,
                                           **alleviation_summary(without, resp, surfaces, law)}}
        else:
            resp = dlm_response()
    elif args.aero == "coupled":
        def response(**controls):
            return coupled_gust_response(t, bp, chord, axis_frac, ap, flight, area=wing_area, plunge=args.plunge,
                                         body_mass=body_mass, pitch_params=args.pitch_params if args.pitch else None,
                                         tail_lag=args.tail_lag,
                                         aero_theory="vlm" if args.aero_theory == "vlm" else "strip", **controls)

        resp = response()
        if surfaces:
            controlled = response(surfaces=surfaces, law=law)
            alleviation = {"alleviation": {"file": args.alleviation,
                                           **alleviation_summary(resp, controlled, surfaces, law)}}
            resp = controlled
    else:
        resp = strip_gust_response(t, bp, chord, axis_frac, flight, area=wing_area, semi_span=pf.semi_span,
                                   fuselage_half_width=pf.root_rib * pf.semi_span)
    if args.pitch:
        pitch_out = {**resp.pitch, "pitch_inertia_kg_m2": args.pitch_inertia, "cg_m": [args.cg_x, args.cg_z],
                     "tail_arm_m": args.tail_arm, "tail_area_m2": args.tail_area,
                     "tail_lift_slope_per_rad": args.tail_lift_slope,
                     "downwash_gradient": float(args.downwash_gradient), "tail_lag": bool(args.tail_lag)}
    n_load, X, a_wing, trim_alpha = resp.load_factor, resp.states, resp.wing_lift_slope, resp.trim_alpha
    if resp.station_loads is None:  # total, 1 g included (X: the 18 beam states per node)
        bending, torsion, tip = X[:, :, 9], X[:, :, 10], X[:, -1, 2] - r0[-1, 2]
    else:  # the doublet lattice's gust increments on the jig
        bending, torsion, tip = resp.station_loads[:, :, 3], resp.station_loads[:, :, 4], resp.tip_displacement
    area = pf.area_ft2 * FT ** 2
    wing_loading = weight / area
    span = 2 * pf.semi_span
    mean_chord = area / span
    dn = n_load - n_load[0]
    V_e = V * np.sqrt(rho / rho0)
    dn_qs = rho0 * u_eas * V_e * a_wing / (2 * wing_loading)
    mu = 2 * wing_loading / (rho * mean_chord * a_wing * G0)
    res = {
        "case": args.case, "aero": args.aero, "plunge": bool(args.plunge), "pitch": bool(args.pitch), "gradient_ft": H_ft,
        "stiffness_scale": args.stiffness_scale, "lifting_line": args.aero_theory == "lifting-line",
        "aero_theory": args.aero_theory if args.aero == "coupled" else "strip",
        "modes": args.modes if args.aero_theory == "dlm" else None, "design": args.design, "altitude_ft": alt_ft, "mach": mach,
        "airspeed_tas_m_s": V, "density_kg_m3": rho, "u_ds_eas_m_s": u_eas,
        "time": t.tolist(),
        "load_factor": n_load.tolist(),
        "trim_alpha_rad": trim_alpha,
        "peak_incremental_load_factor": float(np.max(np.abs(dn))),
        "peak_up_incremental_load_factor": float(np.max(dn)),
        "peak_down_incremental_load_factor": float(np.min(dn)),
        "quasi_steady_incremental_load_factor": float(dn_qs),
        "wing_lift_slope_per_rad": a_wing,
        "mass_parameter": float(mu),
        "pratt_walker_factor": float(0.88 * mu / (5.3 + mu)),
        "mean_chord_m": float(mean_chord),
        "wing_loading_pa": float(wing_loading),
        "root_bending_moment": bending[:, 0].tolist(),
        "root_torsion": torsion[:, 0].tolist(),
        "peak_incremental_root_bending_moment": float(np.max(np.abs(bending[:, 0] - bending[0, 0]))),
        "loads_include_1g": resp.station_loads is None,
        "station_y_m": r0[:, 1].tolist(),
        "station_bending_moment": bending.tolist(),
        "station_torsion": torsion.tolist(),
        "tip_displacement": tip.tolist(),
        **({"dlm": resp.dlm} if resp.dlm else {}),
        **pitch_out,
        **alleviation,
        "wall_s": _time.perf_counter() - t_wall,
    }
    print(f"peak dn = {res['peak_incremental_load_factor']:.4f}, peak root bending increment = "
          f"{res['peak_incremental_root_bending_moment'] / 1e3:.1f} kN m, quasi-steady dn = {dn_qs:.4f}, mu = {mu:.2f}, "
          f"K_g = {res['pratt_walker_factor']:.3f}, {res['wall_s']:.1f} s", file=sys.stderr)
    if alleviation:
        a = alleviation["alleviation"]
        print(f"alleviation: peak root bending increment {a['peak_incremental_root_bending_without_law'] / 1e3:.1f} -> "
              f"{a['peak_incremental_root_bending_with_law'] / 1e3:.1f} kN m "
              f"({100 * a['incremental_root_bending_reduction']:.1f} % less); "
              + ", ".join(f"{nm}: peak {v['peak_deflection_deg']:.2f} deg (limit {v['max_deflection_deg']:g}), "
                          f"{v['peak_rate_deg_s']:.1f} deg/s (limit {v['max_rate_deg_s']:g})"
                          for nm, v in a["surfaces"].items()), file=sys.stderr)
    write_json(res, args.json)  # the result first: a plotting failure must never lose it
    if plot_path:
        _plots(res, plot_path[:-len(".png")])
    return 0


def _check_alleviation(args):
    """``(surfaces, law)`` of --alleviation (empty without it), checked before any solve: the file's
    keys and values, the surfaces against the case's beam nodes, the law's outputs against the model."""
    if args.alleviation is None:
        return (), None
    if args.aero != "coupled":
        raise ValueError(f"--alleviation {args.alleviation} needs --aero coupled (control surfaces act in the march)")

    surfaces, law = read_alleviation(args.alleviation)
    outputs = () if law is None else law.outputs
    if "load_factor" in outputs and not args.plunge:
        raise ValueError(f"--alleviation {args.alleviation}: output load_factor needs free plunge (--plunge free)")
    if "pitch_rate" in outputs and not args.pitch:
        raise ValueError(f"--alleviation {args.alleviation}: output pitch_rate needs --pitch free")
    return surfaces, law


def _check_surfaces_on_beam(args, surfaces, law, node_positions):
    """The surfaces' spans against the case's beam nodes (before the march)."""
    try:
        control_spec(surfaces, np.asarray(node_positions)[:, 1], law)
    except ValueError as exc:
        raise ValueError(f"--alleviation {args.alleviation}: {exc}") from None


def check_outputs(args, plot_name):
    """Check ``--out``, ``--json`` and the plot path before the run.

    Parameters
    ----------
    args : argparse.Namespace
        The command's arguments (``out``, ``json``, ``no_plots``, ``overwrite``).
    plot_name : str
        The plot's file name in ``--out``.

    Returns
    -------
    str or None
        The plot path; None with ``--no-plots``.
    """

    plot = None
    if not args.no_plots:
        check_output_dir(args.out, "--out")
        plot = os.path.join(args.out, plot_name)
        refuse_existing([plot], overwrite=args.overwrite, what="plot")
    check_output_file(args.json, "--json", overwrite=args.overwrite, others={"plot": plot})
    return plot


def _check_dlm_args(args, plunge):
    """--aero-theory dlm: the modal doublet lattice of the jig, clamped or with the rigid-body modes
    of free plunge (and pitch); --modes applies to it only."""
    if args.aero_theory != "dlm":
        if args.modes is not None:
            raise ValueError(f"--modes = {args.modes} applies to --aero-theory dlm only")
        return
    if args.aero != "coupled":
        raise ValueError("--aero-theory dlm needs --aero coupled (the doublet lattice on the deforming wing)")
    if args.pitch == "free" and getattr(args, "tail_lag", False):
        raise ValueError("--tail-lag: the doublet lattice's tail is quasi-steady (no downwash lag); "
                         "use --aero-theory strip|lifting-line|vlm with --tail-lag")
    args.modes = DLM_MODES if args.modes is None else args.modes
    if not 2 <= args.modes <= 20:
        raise ValueError(f"--modes = {args.modes}; allowed range [2, 20]")


def _check_stick_args(args):
    """--model stick: the PEGASUS stick model, coupled aerodynamics, free in plunge and pitch through its
    own structure; the lone wing's options that do not apply are refused."""
    if args.model != "stick":
        return
    if args.case != "pegasus":
        raise ValueError(f"--model stick: case {args.case!r} has no stick model; allowed: pegasus")
    refused = [(args.aero != "coupled", f"--aero {args.aero}"), (not args.plunge, "--clamped"),
               (args.pitch, "--pitch free (the stick model is free in pitch through its structure)"),
               (args.alleviation is not None, "--alleviation"),
               (args.aero_theory != "strip", f"--aero-theory {args.aero_theory}")]
    for bad, flag in refused:
        if bad:
            raise ValueError(f"--model stick does not take {flag}; allowed: --aero coupled, free plunge, strip "
                             "aerodynamics")


def _read_stick_gust_set(args):
    """``--gust-set FILE`` of ``--model stick`` (None without it), read and checked before any solve: the
    lone wing's gust flags it replaces are refused, every flight point's Mach number is in (0, 1) and its
    weight the stick model's (half the TOGW)."""
    if args.gust_set is None:
        return None
    if args.model != "stick":
        raise ValueError(f"--gust-set {args.gust_set}: applies to --model stick (the lone wing's gust sets are "
                         "sized by 'wingmdao size CASE --gust-set FILE')")
    given = [f for f, v in (("--gust-gradient-ft", args.gradient_ft), ("--altitude-ft", args.altitude_ft),
                            ("--mach", args.mach), ("--u-ref-fps", args.u_ref_fps)) if v is not None]
    if given:
        raise ValueError(f"--gust-set {args.gust_set} gives the flight points, gradients and U_ref; drop {given[0]}")
    gset = read_gust_set(args.gust_set, defaults=pegasus.GUST_SET_DEFAULTS)
    pegasus_stick.check_gust_set(gset, args.gust_set)
    return gset


def _stick_aircraft(args, walls, num_nodes):
    """The PEGASUS stick model of ``--design`` walls (None: the initial ones) and ``--stiffness-scale``."""
    aircraft = pegasus_stick.build(num_nodes, thickness=walls)
    if args.stiffness_scale != 1.0:
        scale_stick_stiffness(aircraft, args.stiffness_scale)
    print(f"stick model: {aircraft.model.system.n_state} structural unknowns, half aircraft {aircraft.mass:.0f} kg",
          file=sys.stderr)
    return aircraft


def _stick_gust_result(r) -> dict:
    """The JSON keys of one stick gust response ``r`` (:class:`~wingmdao.cases.pegasus_stick.StickGust`):
    load factor and its peaks, trim, and the monitoring stations' histories, extremes and potato plots."""
    dn = r.load_factor - r.load_factor[0]
    potatoes = monitoring_potatoes(r.loads)
    loads = {}
    for label, v in r.loads.items():
        f, m = v["force"], v["moment"]
        pot = potatoes[label]
        loads[label] = {"force_n": f.tolist(), "moment_n_m": m.tolist(),
                        "force_max_n": f.max(axis=0).tolist(), "force_min_n": f.min(axis=0).tolist(),
                        "moment_max_n_m": m.max(axis=0).tolist(), "moment_min_n_m": m.min(axis=0).tolist(),
                        "potato_components": pot["components"], "potato_hull": pot["hull"].tolist()}
    return {"load_factor": r.load_factor.tolist(),
            "peak_incremental_load_factor": float(np.max(np.abs(dn))),
            "peak_up_incremental_load_factor": float(np.max(dn)),
            "peak_down_incremental_load_factor": float(np.min(dn)),
            "trim_alpha_rad": r.trim["alpha_trim"], "tail_incidence_rad": r.trim["tail_incidence"],
            "trim_thrust_n": r.trim["thrust"], "downwash_gradient": r.downwash_gradient,
            "monitoring_loads": loads}


_MONITORING_AXES = ("body axes (x aft, y right, z up), N and N m; the outboard part on the inboard part; "
                    "potato_hull: the convex hull of the potato_components pair (N m or N)")


def _run_stick(args, t, flight, walls, num_nodes, *, H_ft, alt_ft, t_wall, plot_path):
    """The gust on the PEGASUS stick model (:func:`wingmdao.cases.pegasus_stick.gust_response`): its wing
    of ``walls`` (``--design``, checked against the case's ``num_nodes``-node wing; None: the initial
    walls), every beam's section stiffness times ``--stiffness-scale``."""
    aircraft = _stick_aircraft(args, walls, num_nodes)
    r = pegasus_stick.gust_response(aircraft, t, airspeed=flight.airspeed, density=flight.density, mach=flight.mach,
                                    u_ds_tas=flight.u_ds_tas, gradient=flight.gradient, gust_start=flight.gust_start,
                                    static_options={"atol": STICK_STATIC_ATOL})
    res = {"case": args.case, "model": "stick", "aero": "coupled", "plunge": True, "pitch": True,
           "design": args.design, "stiffness_scale": args.stiffness_scale, "gradient_ft": H_ft,
           "altitude_ft": alt_ft, "mach": flight.mach, "airspeed_tas_m_s": flight.airspeed,
           "density_kg_m3": flight.density, "u_ds_eas_m_s": flight.u_ds_eas, "time": t.tolist(),
           **_stick_gust_result(r), "half_aircraft_mass_kg": aircraft.mass,
           "monitoring_loads_axes": _MONITORING_AXES, "wall_s": _time.perf_counter() - t_wall}
    print(f"peak dn = {res['peak_incremental_load_factor']:.4f}, alpha_trim = {np.degrees(r.trim['alpha_trim']):.3f} "
          f"deg, tail incidence = {np.degrees(r.trim['tail_incidence']):.3f} deg, {res['wall_s']:.1f} s",
          file=sys.stderr)
    write_json(res, args.json)
    if plot_path:
        _stick_plots(res, plot_path[:-len(".png")])
    return 0


def _run_stick_set(args, t, gset, walls, num_nodes, *, t_wall, plot_path):
    """Every gust of ``--gust-set`` on the PEGASUS stick model, with the monitoring stations' envelopes
    and potato plots over the set (:func:`stick_set_envelope`)."""
    aircraft = _stick_aircraft(args, walls, num_nodes)
    rho0 = float(density(0.0))
    gusts = []
    for g in gset.gusts():
        fp = g.flight_point
        alt = fp.altitude_m
        rho, V = float(density(alt)), fp.airspeed_tas()
        mach = V / float(speed_of_sound(alt))
        print(f"{g.name}: {g.describe()}", file=sys.stderr)
        r = pegasus_stick.gust_response(aircraft, t, airspeed=V, density=rho, mach=mach,
                                        u_ds_tas=g.sign * g.u_ds_eas * np.sqrt(rho0 / rho), gradient=g.gradient_m,
                                        gust_start=args.gust_start, static_options={"atol": STICK_STATIC_ATOL})
        gusts.append({"name": g.name, "description": g.describe(), "altitude_ft": fp.altitude_ft, "mach": mach,
                      "airspeed_tas_m_s": V, "density_kg_m3": rho, "gradient_ft": g.gradient_ft, "sign": g.sign,
                      "u_ds_eas_m_s": g.u_ds_eas, **_stick_gust_result(r)})
    up = max(gusts, key=lambda x: x["peak_up_incremental_load_factor"])
    down = min(gusts, key=lambda x: x["peak_down_incremental_load_factor"])
    res = {"case": args.case, "model": "stick", "aero": "coupled", "plunge": True, "pitch": True,
           "gust_set": args.gust_set, "design": args.design, "stiffness_scale": args.stiffness_scale,
           "time": t.tolist(), "half_aircraft_mass_kg": aircraft.mass,
           "peak_up_incremental_load_factor": up["peak_up_incremental_load_factor"], "peak_up_gust": up["name"],
           "peak_down_incremental_load_factor": down["peak_down_incremental_load_factor"],
           "peak_down_gust": down["name"], "gusts": gusts, "monitoring_envelope": stick_set_envelope(gusts),
           "monitoring_loads_axes": _MONITORING_AXES, "wall_s": _time.perf_counter() - t_wall}
    print(f"{len(gusts)} gusts: peak dn up {res['peak_up_incremental_load_factor']:.4f} ({up['name']}), down "
          f"{res['peak_down_incremental_load_factor']:.4f} ({down['name']}), {res['wall_s']:.1f} s", file=sys.stderr)
    write_json(res, args.json)
    if plot_path:
        _stick_set_plots(res, plot_path[:-len(".png")])
    return 0


def scale_stick_stiffness(aircraft, scale):
    """Multiply the section stiffness of every beam of a stick ``aircraft``
    (:class:`~wingmdao.cases.pegasus_stick.StickAircraft`, changed in place) by ``scale``.

    Parameters
    ----------
    aircraft : StickAircraft
        The stick model; its ``model.params`` (``stiffness_csn``, ``compliance_csn`` of each beam) and
        packed ``model.p`` are replaced. Masses, node positions and the trim data stay.
    scale : float
        The factor (> 0; as ``--stiffness-scale``).
    """
    params = {k: {**v, "stiffness_csn": np.asarray(v["stiffness_csn"]) * scale,
                  "compliance_csn": np.asarray(v["compliance_csn"]) / scale}
              for k, v in aircraft.model.params.items()}
    aircraft.model.params = params
    aircraft.model.p = aircraft.model.system.pack_parameters(params)


def _stick_plots(res, stem):
    plt = optional_pyplot()
    if plt is None:
        return
    t = res["time"]
    stations = res["monitoring_loads"]
    fig = plt.figure(figsize=(3 * len(stations), 10))
    grid = fig.add_gridspec(3, len(stations))
    axes = [fig.add_subplot(grid[0, :])]
    axes.append(fig.add_subplot(grid[1, :], sharex=axes[0]))
    for k, (label, v) in enumerate(stations.items()):   # potato plots: the correlated pair and its hull
        ax = fig.add_subplot(grid[2, k])
        pair = [np.asarray(v["moment_n_m" if c[0] == "M" else "force_n"])[:, "xyz".index(c[-1])] / 1e3
                for c in v["potato_components"]]
        hull = np.asarray(v["potato_hull"]) / 1e3
        ax.plot(pair[0], pair[1], lw=0.8)
        ax.plot(hull[:, 0], hull[:, 1], "k--", lw=0.8)
        units = ["kN m" if c[0] == "M" else "kN" for c in v["potato_components"]]
        ax.set_xlabel(f"{v['potato_components'][0]} ({units[0]})", fontsize=7)
        ax.set_ylabel(f"{v['potato_components'][1]} ({units[1]})", fontsize=7)
        ax.set_title(label, fontsize=7)
        ax.tick_params(labelsize=6)
        ax.grid(True)
    axes[0].plot(t, res["load_factor"])
    axes[0].set_ylabel("load factor")
    for label, v in res["monitoring_loads"].items():
        m = np.asarray(v["moment_n_m"])
        axes[1].plot(t, m[:, int(np.argmax(np.abs(m).max(axis=0)))] / 1e3, label=label)
    axes[1].set_ylabel("largest moment component (kN m)")
    axes[1].legend(fontsize=7)
    axes[-1].set_xlabel("time (s)")
    for ax in axes:
        ax.grid(True)

    save_figure(fig, stem + ".png", dpi=100)
    print(f"wrote {stem}.png", file=sys.stderr)


def _pair(v, components):
    """The potato pair's histories (kN m or kN) of one station's ``force_n``/``moment_n_m``."""
    return [np.asarray(v["moment_n_m" if c[0] == "M" else "force_n"])[:, "xyz".index(c[-1])] / 1e3 for c in components]


def _stick_set_plots(res, stem):
    plt = optional_pyplot()
    if plt is None:
        return
    t = res["time"]
    env = res["monitoring_envelope"]
    fig = plt.figure(figsize=(3 * len(env), 7))
    grid = fig.add_gridspec(2, len(env))
    ax0 = fig.add_subplot(grid[0, :])
    for g in res["gusts"]:
        ax0.plot(t, g["load_factor"], lw=0.8, label=g["name"])
    ax0.set_xlabel("time (s)")
    ax0.set_ylabel("load factor")
    ax0.legend(fontsize=6, ncol=2)
    ax0.grid(True)
    for k, (label, e) in enumerate(env.items()):   # potato plots over the set: every gust's pair and the hull
        ax = fig.add_subplot(grid[1, k])
        comps = e["potato_components"]
        for g in res["gusts"]:
            pair = _pair(g["monitoring_loads"][label], comps)
            ax.plot(pair[0], pair[1], lw=0.6)
        hull = np.asarray(e["potato_hull"]) / 1e3
        ax.plot(hull[:, 0], hull[:, 1], "k--", lw=0.8)
        units = ["kN m" if c[0] == "M" else "kN" for c in comps]
        ax.set_xlabel(f"{comps[0]} ({units[0]})", fontsize=7)
        ax.set_ylabel(f"{comps[1]} ({units[1]})", fontsize=7)
        ax.set_title(label, fontsize=7)
        ax.tick_params(labelsize=6)
        ax.grid(True)
    save_figure(fig, stem + ".png", dpi=100)
    print(f"wrote {stem}.png", file=sys.stderr)


def _check_pitch_args(args):
    """--pitch free needs --aero coupled, free plunge and the aircraft's pitch data (no PEGASUS defaults:
    its tail and pitch inertia are not published with the case, docs/aeroelasticity.md)."""
    if not args.pitch:
        given = [f for f in ("pitch_inertia", "cg_x", "tail_arm", "tail_area", "tail_lift_slope", "downwash_gradient")
                 if getattr(args, f) is not None] + (["tail_lag"] if args.tail_lag else [])
        if given:
            raise ValueError(f"--{given[0].replace('_', '-')} applies to --pitch free only")
        return
    if args.aero != "coupled" or not args.plunge:
        raise ValueError("--pitch free needs --aero coupled and --plunge free (the aircraft free in plunge and pitch)")
    missing = [f for f in ("pitch_inertia", "cg_x", "tail_arm", "tail_area", "tail_lift_slope") if getattr(args, f) is None]
    if missing:
        raise ValueError("--pitch free needs " + ", ".join("--" + f.replace("_", "-") for f in missing)
                         + " (the case has no published tail or pitch inertia)")
    for name in ("pitch_inertia", "cg_x", "cg_z", "tail_arm", "tail_area", "tail_lift_slope"):
        if not np.isfinite(getattr(args, name)):
            raise ValueError(f"--{name.replace('_', '-')} = {getattr(args, name)}; allowed a finite value")


def _area(args):
    return available_cases()[args.case].PLANFORM.area_ft2 * FT ** 2


def _plots(res, stem):
    plt = optional_pyplot()
    if plt is None:
        return
    t = res["time"]
    alleviation = res.get("alleviation")
    fig, axes = plt.subplots(4 if alleviation else 3, 1, figsize=(7, 10 if alleviation else 8), sharex=True)
    axes[0].plot(t, res["load_factor"], label="with law" if alleviation else None)
    axes[0].set_ylabel("load factor")
    if alleviation:  # the same gust without the law, and the surfaces' deflections
        axes[0].plot(t, alleviation["load_factor_without_law"], "--", label="without law")
        axes[0].legend()
        axes[1].plot(t, np.asarray(alleviation["root_bending_moment_without_law"]) / 1e3, "--",
                     label="bending M_x without law")
        for name, srf in alleviation["surfaces"].items():
            axes[3].plot(t, srf["deflection_deg"], label=f"{name} (limit {srf['max_deflection_deg']:g} deg)")
        axes[3].set_ylabel("deflection (deg)")
        axes[3].legend()
    axes[1].plot(t, np.asarray(res["root_bending_moment"]) / 1e3, label="bending M_x")
    axes[1].plot(t, np.asarray(res["root_torsion"]) / 1e3, label="torsion M_y")
    axes[1].set_ylabel("root moment (kN m)")
    axes[1].legend()
    axes[2].plot(t, res["tip_displacement"])
    axes[2].set_ylabel("tip deflection (m)")
    axes[-1].set_xlabel("time (s)")
    for ax in axes:
        ax.grid(True)

    save_figure(fig, stem + ".png", dpi=100)
    print(f"wrote {stem}.png", file=sys.stderr)
