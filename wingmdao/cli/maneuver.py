"""``wingmdao maneuver CASE --checked-pitch``: the 14 CFR 25.331(c)(2) checked pitch maneuver.

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
from wingmdao.loads.atmosphere import altitude_ft_to_m, density, mach_to_tas
from wingmdao.loads.maneuver import limit_load_factors
from wingmdao.aero.gust_response import wing_lift_slope
from wingmdao.aero.system import aero_parameters
from wingmdao.loads.checked_pitch import checked_pitch, maneuver_model

#: the pitch data the maneuver needs (flags)
REQUIRED_PITCH = ("pitch_inertia", "cg_x", "tail_arm", "tail_area", "tail_lift_slope")


def _check_args(args):
    """Every flag checked before any model is built (one-line ValueError naming the flag)."""
    if not args.checked_pitch:
        raise ValueError("wingmdao maneuver needs a maneuver: --checked-pitch (14 CFR 25.331(c)(2))")
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


def run(args):
    t_wall = _time.perf_counter()
    _check_args(args)
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
