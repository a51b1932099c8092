"""``wingmdao maneuver CASE --checked-pitch``: the 14 CFR 25.331(c)(2) checked pitch maneuver;
``wingmdao maneuver CASE --rolling``: the 14 CFR 25.349(a) rolling conditions.

The case's wing (its initial design or ``--design``) on the coupled aeroelastic beam, the airplane
free in plunge and pitch with a horizontal tail and an elevator (:mod:`wingmdao.aero.pitch`; the
tail, CG and pitch inertia are required flags: the case has none), trimmed in level 1 g flight at
the case's gust flight point (or ``--altitude-ft``, ``--mach``). The elevator command is
delta_1 sin(omega t) over [0, 3 pi / (2 omega)] (nose up: trailing edge up first; ``--nose-down``),
omega the short-period frequency of the linearized model but not less than pi V / (2 V_A),
delta_1 found so that the peak load factor reaches the 25.337 limit (nose up) or 0 g (nose down)
(:func:`wingmdao.loads.checked_pitch.checked_pitch`; docs/maneuvers.md).

JSON keys: time, elevator_deg (the actuator's deflection), elevator_command_deg, load_factor,
target_load_factor, peak_load_factor, pitch_rate_deg_s, root_bending_moment (N m, M_x at the
symmetry plane, 1 g included), peak_root_bending_moment (N m, over the instants 25.331(c)(2)(v)
asks for), omega_rad_s, short_period_frequency_rad_s, minimum_frequency_rad_s, delta_1_deg, t_max_s,
hold_s and target_reached (25.331(c)(2)(iii) with --max-elevator-deg), iterations (delta_1_deg,
hold_s, peak_load_factor per march) and the inputs.

--rolling: the antisymmetric half wing on a fuselage free to roll (:mod:`wingmdao.aero.roll`) with
the ailerons of ``--alleviation FILE`` (surfaces only: they fly open loop), the fuselage's roll
inertia ``--roll-inertia`` (I_xx,body, required: the case has none), V_A from
``--maneuvering-speed-eas`` and the case's V_C, V_D (:func:`wingmdao.cases.pegasus.flight_point`),
flown as equivalent airspeeds at ``--altitude-ft`` (default the case's cruise altitude)
(:mod:`wingmdao.loads.rolling`; docs/maneuvers.md, "Rolling conditions"). JSON keys: time, and per
condition (``conditions``: VA, VC, VD) aileron_deg, roll_rate_deg_s, roll_angle_deg,
roll_acceleration_deg_s2, steady_roll_rate_deg_s, steady_pb_2V, command_fraction, aileron_command_deg,
root_bending_moment, root_torque (N m increments of the right wing), their peaks, the symmetric root
loads at n = 0 and 2/3 n_lim and the combined design loads; the inputs.
"""

from __future__ import annotations

import sys
import time as _time

import numpy as np

from wingmdao.plots import optional_pyplot, save_figure

from wingmdao.cli._io import write_json, read_design
from wingmdao.aero.pitch import elevator_effectiveness, pitch_parameters
from wingmdao.cases import available_cases, case_beam_parameters
from wingmdao.cases.pegasus import GUST
from wingmdao.cases.planform import FT, G0, LB, wing_geometry
from wingmdao.cli.gust import check_outputs
from wingmdao.cli.parsers.maneuver import ROLL_T_FINAL
from wingmdao.loads.atmosphere import altitude_ft_to_m, density, mach_to_tas
from wingmdao.loads.maneuver import limit_load_factors
from wingmdao.aero.gust_response import wing_lift_slope
from wingmdao.aero.system import aero_parameters
from wingmdao.loads.checked_pitch import checked_pitch, maneuver_model
from wingmdao.aero.controls import control_spec, limit_report, read_alleviation
from wingmdao.aero.roll import half_wing_roll_inertia
from wingmdao.cases.pegasus import CRUISE_ALTITUDE_FT, rolling_flight_speeds_eas
from wingmdao.loads.rolling import (CONDITIONS, check_rolling_inputs, condition_commands, combined_loads, march_roll,
                                    rolling_speeds, symmetric_root_loads)

#: the pitch data the maneuver needs (flags)
REQUIRED_PITCH = ("pitch_inertia", "cg_x", "tail_arm", "tail_area", "tail_lift_slope")


def _check_args(args):
    """Every flag checked before any model is built (one-line ValueError naming the flag)."""
    if args.rolling and args.checked_pitch:
        raise ValueError("--rolling with --checked-pitch: one maneuver per run")
    if args.rolling:
        return _check_rolling_args(args)
    for flag in ("roll_inertia", "alleviation", "t_final", "aero_theory"):
        if getattr(args, flag) is not None:
            raise ValueError(f"--{flag.replace('_', '-')} is a --rolling flag")
    if not args.checked_pitch:
        raise ValueError("wingmdao maneuver needs a maneuver: --checked-pitch (14 CFR 25.331(c)(2)) or --rolling "
                         "(14 CFR 25.349(a))")
    missing = [f for f in REQUIRED_PITCH if getattr(args, f) is None]
    if missing:
        raise ValueError("--checked-pitch needs " + ", ".join("--" + f.replace("_", "-") for f in missing)
                         + " (the case has no published tail or pitch inertia)")
    for name in REQUIRED_PITCH + ("cg_z",):
        if not np.isfinite(getattr(args, name)):
            raise ValueError(f"--{name.replace('_', '-')} = {getattr(args, name)}; allowed a finite value")
    for name in ("pitch_inertia", "tail_arm", "tail_area", "tail_lift_slope"):
        if not getattr(args, name) > 0:
            raise ValueError(f"--{name.replace('_', '-')} = {getattr(args, name)}; allowed range (0, inf)")
    if args.downwash_gradient is not None and not 0.0 <= args.downwash_gradient < 1.0:
        raise ValueError(f"--downwash-gradient = {args.downwash_gradient}; allowed range [0, 1)")
    va = args.maneuvering_speed_eas
    if va is None:
        raise ValueError("--checked-pitch needs --maneuvering-speed-eas (V_A, m/s EAS; the case has none)")
    if not (np.isfinite(va) and va > 0):
        raise ValueError(f"--maneuvering-speed-eas = {va} m/s; allowed range (0, inf) m/s")
    if args.load_factor is not None and not (np.isfinite(args.load_factor) and args.load_factor > 1.0):
        raise ValueError(f"--load-factor = {args.load_factor}; allowed range (1, inf)")
    if args.max_elevator_deg is not None and not (np.isfinite(args.max_elevator_deg) and args.max_elevator_deg > 0):
        raise ValueError(f"--max-elevator-deg = {args.max_elevator_deg} deg; allowed range (0, inf) deg")
    if not (np.isfinite(args.elevator_chord_ratio) and 0.0 < args.elevator_chord_ratio < 1.0):
        raise ValueError(f"--elevator-chord-ratio = {args.elevator_chord_ratio}; allowed range (0, 1)")
    if not (np.isfinite(args.elevator_time_constant) and args.elevator_time_constant > 0):
        raise ValueError(f"--elevator-time-constant = {args.elevator_time_constant} s; allowed range (0, inf) s")
    if args.altitude_ft is not None and not 0.0 <= args.altitude_ft <= 60000.0:
        raise ValueError(f"--altitude-ft = {args.altitude_ft} ft; allowed range [0, 60000] ft")
    if args.mach is not None and not 0.0 < args.mach < 1.0:
        raise ValueError(f"--mach = {args.mach}; allowed range (0, 1)")
    if not 20 <= args.steps <= 100000:
        raise ValueError(f"--steps = {args.steps}; allowed range [20, 100000]")


def _check_rolling_args(args):
    """The flags of --rolling, checked before any model is built; returns (surfaces, t_final)."""
    if args.nose_down or args.max_elevator_deg is not None or args.mach is not None:
        flag = "--nose-down" if args.nose_down else ("--max-elevator-deg" if args.mach is None else "--mach")
        raise ValueError(f"{flag} is a --checked-pitch flag; --rolling flies V_A, V_C and V_D")
    if args.aero_theory is None:
        args.aero_theory = "strip"
    check_rolling_inputs(args.alleviation, args.roll_inertia, args.maneuvering_speed_eas, args.aero_theory)
    if args.load_factor is not None and not (np.isfinite(args.load_factor) and args.load_factor > 1.0):
        raise ValueError(f"--load-factor = {args.load_factor}; allowed range (1, inf)")
    if args.altitude_ft is not None and not 0.0 <= args.altitude_ft <= 60000.0:
        raise ValueError(f"--altitude-ft = {args.altitude_ft} ft; allowed range [0, 60000] ft")
    t_final = ROLL_T_FINAL if args.t_final is None else args.t_final
    if not (np.isfinite(t_final) and t_final > 0):
        raise ValueError(f"--t-final = {t_final} s; allowed range (0, inf) s")
    if not 20 <= args.steps <= 100000:
        raise ValueError(f"--steps = {args.steps}; allowed range [20, 100000]")
    surfaces, law = read_alleviation(args.alleviation)
    if law is not None:
        raise ValueError(f"--alleviation {args.alleviation}: --rolling flies the ailerons open loop; remove 'law'")
    return surfaces, float(t_final)


def run(args):
    t_wall = _time.perf_counter()
    checked = _check_args(args)
    if args.rolling:
        return _run_rolling(args, *checked, t_wall)
    direction = "nose-down" if args.nose_down else "nose-up"
    plot_path = check_outputs(args, f"{args.case}_checked_pitch{'_nose_down' if args.nose_down else ''}.png")
    module = available_cases()[args.case]
    alt_ft = GUST["altitude_ft"] if args.altitude_ft is None else args.altitude_ft
    mach = GUST["mach"] if args.mach is None else args.mach
    alt = float(altitude_ft_to_m(alt_ft))
    rho, rho0 = float(density(alt)), float(density(0.0))
    V = float(mach_to_tas(mach, alt))
    v_eas = V * np.sqrt(rho / rho0)
    if v_eas < args.maneuvering_speed_eas:
        raise ValueError(f"--maneuvering-speed-eas = {args.maneuvering_speed_eas} m/s; allowed range (0, V = "
                         f"{v_eas:.2f}] m/s EAS: 25.331(c)(2) flies the checked maneuver between V_A and V_D")
    n_lim = limit_load_factors(module.TOGW_LB)[0] if args.load_factor is None else float(args.load_factor)
    weight = module.TOGW_LB * LB * G0
    pf = module.PLANFORM
    walls = read_design(args.design, None, case=args.case, command="maneuver") if args.design else None
    setup, bp = case_beam_parameters(module, walls, source=f"--design {args.design}")
    _, chord, axis_frac = wing_geometry(pf, getattr(module, "ENGINES", ()))
    n = setup.geometry.num_nodes
    r0 = bp["node_positions"]
    ap = aero_parameters(n, chord=chord, ref_point=axis_frac, lift_slope=2 * np.pi, airspeed=V, density=rho, mach=mach)
    area = pf.area_ft2 * FT ** 2
    if args.downwash_gradient is None:  # Etkin & Reid (1996) / Nelson (1998): deps/dalpha = 2 a_w / (pi AR)
        a_w = wing_lift_slope(ap["lift_slope"] / np.sqrt(1 - mach ** 2), chord, r0, area)
        args.downwash_gradient = 2 * a_w / (np.pi * (2 * pf.semi_span) ** 2 / area)
    pitch = pitch_parameters(aircraft_mass=weight / G0, cg=(args.cg_x, args.cg_z),
                             aircraft_pitch_inertia=args.pitch_inertia, tail_arm=args.tail_arm,
                             tail_area=args.tail_area, tail_lift_slope=args.tail_lift_slope,
                             downwash_gradient=args.downwash_gradient, mass_per_length=bp["mass_per_length"],
                             node_positions=r0)
    tau_e = elevator_effectiveness(args.elevator_chord_ratio)
    system, p = maneuver_model(bp, ap, pitch, weight=weight, elevator_effectiveness=tau_e,
                               elevator_time_constant=args.elevator_time_constant, tail_lag=args.tail_lag)
    print(f"wingmdao maneuver {args.case} --checked-pitch ({direction}): {n} nodes, V = {V:.1f} m/s TAS "
          f"({v_eas:.1f} m/s EAS), V_A = {args.maneuvering_speed_eas:g} m/s EAS, n_lim = {n_lim:.3f}, "
          f"tau_e = {tau_e:.3f}", file=sys.stderr)
    r = checked_pitch(system, p, weight=weight, airspeed_eas=v_eas, maneuvering_speed_eas=args.maneuvering_speed_eas,
                      limit_load_factor=n_lim, direction=direction, steps=args.steps, gravity=G0,
                      max_amplitude=None if args.max_elevator_deg is None else np.radians(args.max_elevator_deg))
    res = {
        "case": args.case, "maneuver": "checked-pitch", "direction": direction, "design": args.design,
        "altitude_ft": alt_ft, "mach": mach, "airspeed_tas_m_s": V, "airspeed_eas_m_s": v_eas,
        "density_kg_m3": rho, "maneuvering_speed_eas_m_s": args.maneuvering_speed_eas,
        "limit_load_factor": n_lim, "time": r.time.tolist(),
        "elevator_deg": np.degrees(r.elevator).tolist(),
        "elevator_command_deg": np.degrees(r.elevator_command).tolist(),
        "load_factor": r.load_factor.tolist(), "target_load_factor": r.target_load_factor,
        "peak_load_factor": r.peak_load_factor,
        "pitch_rate_deg_s": np.degrees(r.pitch_rate).tolist(),
        "root_bending_moment": r.root_bending_moment.tolist(),
        "peak_root_bending_moment": float(np.max(r.root_bending_moment[r.considered])),
        "min_root_bending_moment": float(np.min(r.root_bending_moment[r.considered])),
        "loads_considered_until_s": float(r.time[r.considered][-1]),
        "omega_rad_s": r.omega, "short_period_frequency_rad_s": r.omega_short_period,
        "short_period_eigenvalue": [r.short_period_eigenvalue.real, r.short_period_eigenvalue.imag],
        "minimum_frequency_rad_s": r.omega_min, "delta_1_deg": float(np.degrees(r.delta_1)), "t_max_s": r.t_max,
        "hold_s": r.hold, "target_reached": r.reached, "max_elevator_deg": args.max_elevator_deg,
        "iterations": [[float(np.degrees(d)), float(h), float(n_)] for d, h, n_ in r.iterations],
        "elevator_chord_ratio": args.elevator_chord_ratio, "elevator_effectiveness": tau_e,
        "elevator_time_constant_s": args.elevator_time_constant,
        "pitch_inertia_kg_m2": args.pitch_inertia, "cg_m": [args.cg_x, args.cg_z], "tail_arm_m": args.tail_arm,
        "tail_area_m2": args.tail_area, "tail_lift_slope_per_rad": args.tail_lift_slope,
        "downwash_gradient": float(args.downwash_gradient), "tail_lag": bool(args.tail_lag),
        "wall_s": _time.perf_counter() - t_wall,
    }
    print(f"omega = {r.omega:.4f} rad/s (short period {r.omega_short_period:.4f}, minimum {r.omega_min:.4f}), "
          f"delta_1 = {res['delta_1_deg']:.4f} deg, peak n = {r.peak_load_factor:.4f} (target "
          f"{r.target_load_factor:g}), peak root M_x = {res['peak_root_bending_moment'] / 1e3:.1f} kN m, "
          f"{len(r.iterations)} marches, {res['wall_s']:.1f} s", file=sys.stderr)
    write_json(res, args.json)  # the result first: a plotting failure must never lose it
    if plot_path:
        _plots(res, plot_path[:-len(".png")])
    return 0


def _plots(res, stem):
    plt = optional_pyplot()
    if plt is None:
        return
    t = res["time"]
    fig, axes = plt.subplots(4, 1, figsize=(7, 9), sharex=True)
    axes[0].plot(t, res["elevator_command_deg"], "--", label="command")
    axes[0].plot(t, res["elevator_deg"], label="elevator (actuator)")
    axes[0].set_ylabel("elevator (deg, TE down +)")
    axes[0].legend()
    axes[1].plot(t, res["load_factor"])
    axes[1].axhline(res["target_load_factor"], color="k", lw=0.8, ls=":")
    axes[1].set_ylabel("load factor")
    axes[2].plot(t, res["pitch_rate_deg_s"])
    axes[2].set_ylabel("pitch rate (deg/s)")
    axes[3].plot(t, np.asarray(res["root_bending_moment"]) / 1e3)
    axes[3].set_ylabel("root bending M_x (kN m)")
    axes[3].set_xlabel("time (s)")
    axes[0].set_title(f"{res['case']} checked pitch, {res['direction']}: omega = {res['omega_rad_s']:.3f} rad/s, "
                      f"delta_1 = {res['delta_1_deg']:.2f} deg", fontsize=9)
    for ax in axes:
        ax.grid(True)

    save_figure(fig, stem + ".png", dpi=100)
    print(f"wrote {stem}.png", file=sys.stderr)


def _speeds(args):
    """{condition: (EAS, TAS, Mach)} of V_A, V_C, V_D (m/s) at the rolling altitude, and the density."""
    alt_ft = CRUISE_ALTITUDE_FT if args.altitude_ft is None else args.altitude_ft
    alt = float(altitude_ft_to_m(alt_ft))
    vc, vd = rolling_flight_speeds_eas()
    return alt_ft, float(density(alt)), rolling_speeds(args.maneuvering_speed_eas, vc, vd, alt)


def _run_rolling(args, surfaces, t_final, t_wall):
    """wingmdao maneuver CASE --rolling (module docstring)."""
    plot_path = check_outputs(args, f"{args.case}_rolling.png")
    module = available_cases()[args.case]
    alt_ft, rho, speeds = _speeds(args)
    n_lim = limit_load_factors(module.TOGW_LB)[0] if args.load_factor is None else float(args.load_factor)
    weight = module.TOGW_LB * LB * G0
    walls = read_design(args.design, None, case=args.case, command="maneuver") if args.design else None
    _, bp = case_beam_parameters(module, walls, source=f"--design {args.design}")
    _, chord, axis_frac = wing_geometry(module.PLANFORM, getattr(module, "ENGINES", ()))
    r0 = bp["node_positions"]
    n = r0.shape[0]
    try:
        spec = control_spec(surfaces, r0[:, 1])
    except ValueError as exc:
        raise ValueError(f"--alleviation {args.alleviation}: {exc}") from None
    stops = np.radians([s.max_deflection_deg for s in surfaces])
    i_wing = half_wing_roll_inertia(bp["mass_per_length"], r0)
    print(f"wingmdao maneuver {args.case} --rolling: {n} nodes, {args.aero_theory}, {alt_ft:g} ft, V_A / V_C / V_D = "
          + " / ".join(f"{v[0]:.1f}" for v in speeds.values()) + f" m/s EAS, I_xx,body = {args.roll_inertia:g} kg m^2 "
          f"(+ 2 x {i_wing:.4g} of the wings), n_lim = {n_lim:.4f}", file=sys.stderr)
    time = np.linspace(0.0, t_final, args.steps + 1)
    conditions = {}
    def aero_at(v, mach):
        return aero_parameters(n, chord=chord, ref_point=axis_frac, lift_slope=2 * np.pi, airspeed=v, density=rho,
                               mach=mach)

    commands = condition_commands(bp, speeds, aero_at, spec, stops, roll_inertia=args.roll_inertia,
                                  aero_theory=args.aero_theory)
    for name, (paragraph, _) in CONDITIONS.items():
        v_eas, v, mach = speeds[name]
        ap = aero_at(v, mach)
        system, p, k, rate = commands[name]
        h = march_roll(system, p, time, k * stops, k, rate)
        dt = float(time[1] - time[0])
        limits = limit_report(time, h.aileron, np.gradient(h.aileron, dt, axis=0), surfaces)
        sym = {}
        for label, n_sym in (("n=0", 0.0), ("n=2/3 n_lim", 2.0 * n_lim / 3.0)):
            m_sym = symmetric_root_loads(bp, ap, load_factor=n_sym, weight=weight, aero_theory=args.aero_theory)
            sym[label] = {"load_factor": n_sym, "symmetric_root_bending_moment": m_sym[0],
                          "symmetric_root_torque": m_sym[1], **combined_loads(h, m_sym)}
        ib, it = int(np.argmax(np.abs(h.root_bending))), int(np.argmax(np.abs(h.root_torque)))
        ia = int(np.argmax(np.abs(h.roll_acceleration)))
        conditions[name] = {
            "paragraph": paragraph, "airspeed_eas_m_s": v_eas, "airspeed_tas_m_s": v, "mach": mach,
            "dynamic_pressure_pa": 0.5 * rho * v * v, "command_fraction": k,
            "aileron_command_deg": {s.name: float(np.degrees(k * stops[j])) for j, s in enumerate(surfaces)},
            "aileron_deg": {s.name: np.degrees(h.aileron[:, j]).tolist() for j, s in enumerate(surfaces)},
            "aileron_limits": {nm: {kk: vv for kk, vv in d.items() if not kk.endswith(("_deg", "_deg_s"))
                                    or kk.startswith(("peak", "max"))} for nm, d in limits.items()},
            "roll_rate_deg_s": np.degrees(h.roll_rate).tolist(), "roll_angle_deg": np.degrees(h.roll_angle).tolist(),
            "roll_acceleration_deg_s2": np.degrees(h.roll_acceleration).tolist(),
            "steady_roll_rate_deg_s": float(np.degrees(rate)), "steady_pb_2V": float(rate * r0[-1, 1] / v),
            "peak_roll_acceleration_deg_s2": float(np.degrees(h.roll_acceleration[ia])),
            "peak_roll_acceleration_time_s": float(time[ia]),
            "root_bending_moment": h.root_bending.tolist(), "root_torque": h.root_torque.tolist(),
            "peak_root_bending_moment": float(h.root_bending[ib]), "peak_root_bending_time_s": float(time[ib]),
            "peak_root_torque": float(h.root_torque[it]), "peak_root_torque_time_s": float(time[it]),
            "combined": sym,
        }
        print(f"{name} ({paragraph}): V = {v_eas:.1f} m/s EAS, aileron {np.degrees(k * stops[0]):.3f} deg, steady p = "
              f"{np.degrees(rate):.2f} deg/s (pb/2V = {rate * r0[-1, 1] / v:.4f}), peak root dM_x = "
              f"{h.root_bending[ib] / 1e3:.1f} kN m at {time[ib]:.2f} s, peak root dM_y = {h.root_torque[it] / 1e3:.1f} "
              f"kN m", file=sys.stderr)
    res = {"case": args.case, "maneuver": "rolling", "design": args.design, "altitude_ft": alt_ft,
           "density_kg_m3": rho, "limit_load_factor": n_lim, "roll_inertia_body_kg_m2": args.roll_inertia,
           "roll_inertia_half_wing_kg_m2": i_wing, "roll_inertia_aircraft_kg_m2": args.roll_inertia + 2 * i_wing,
           "alleviation": args.alleviation, "aero_theory": args.aero_theory, "t_final_s": t_final, "time": time.tolist(), "conditions": conditions,
           "wall_s": _time.perf_counter() - t_wall}
    write_json(res, args.json)  # the result first: a plotting failure must never lose it
    if plot_path:
        _roll_plots(res, plot_path[:-len(".png")])
    return 0


def _roll_plots(res, stem):
    plt = optional_pyplot()
    if plt is None:
        return
    t = res["time"]
    fig, axes = plt.subplots(4, 1, figsize=(7, 9), sharex=True)
    for name, c in res["conditions"].items():
        label = f"{name} ({c['airspeed_eas_m_s']:.0f} m/s EAS)"
        line, = axes[0].plot(t, next(iter(c["aileron_deg"].values())), label=label)
        axes[1].plot(t, c["roll_rate_deg_s"], color=line.get_color())
        axes[2].plot(t, np.asarray(c["root_bending_moment"]) / 1e3, color=line.get_color())
        axes[3].plot(t, np.asarray(c["root_torque"]) / 1e3, color=line.get_color())
    axes[0].set_ylabel("aileron (deg, TE down +)")
    axes[0].legend(fontsize=8)
    axes[1].set_ylabel("roll rate (deg/s)")
    axes[2].set_ylabel("root dM_x (kN m)")
    axes[3].set_ylabel("root dM_y (kN m)")
    axes[3].set_xlabel("time (s)")
    axes[0].set_title(f"{res['case']} rolling conditions 25.349(a), {res['aero_theory']}: right half wing "
                      "(antisymmetric increments)",
                      fontsize=9)
    for ax in axes:
        ax.grid(True)
    save_figure(fig, stem + ".png", dpi=100)
    print(f"wrote {stem}.png", file=sys.stderr)
