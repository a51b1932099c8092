"""``wingmdao turbulence CASE``: 14 CFR 25.341(b) continuous-turbulence loads of a case's wing.

Analysis only (docs/turbulence.md): the case's wing (initial design or the thicknesses of a sizing
result, ``--design``) is linearised about its 1 g level-flight state (:mod:`wingmdao.loads.turbulence_analysis`:
``--aero coupled``, the aeroelastic beam trimmed, free in plunge or clamped; ``--aero strip``,
quasi-steady strip loads on the clamped structural beam); its frequency response to a unit
vertical gust with each station's penetration phase (:mod:`wingmdao.stability.frequency`) and the
von Karman spectrum give A-bar of every output; U_sigma = U_sigma_ref F_g, interpolated between
V_C and V_D (:mod:`wingmdao.loads.turbulence`), gives the design loads P_1g +/- U_sigma A-bar.

JSON keys: case, aero, plunge, design, altitude_ft, altitude_m, mach, damping_ratio, airspeed_tas_m_s, density_kg_m3,
u_sigma_ref_m_s, f_g, speed_factor, u_sigma_m_s, frequency_hz, psd (root_bending_moment,
load_factor), transfer_function_magnitude, a_bar and a_bar_error (root_bending_moment,
load_factor, tip_deflection; per station chordwise_shear, axial_force, vertical_shear,
bending_moment, torsion, chordwise_bending, csn frame; ``stress`` (n, 8): the 4 corner axial
stresses then the 4 flange-centre shears of each box station, Pa), design_loads (one_g, up, down of each),
correlation (bending_torsion per station, correlated_loads, root_ellipse), load_units,
quadrature, model, span_m, wall_s; with ``--alleviation FILE.yaml`` (control surfaces, actuators and a
law as states of the linearised residual, docs/controls.md) also control_surfaces (per surface A-bar of
deflection and rate, U_sigma A-bar against the limits) and alleviation (file, law, a_bar_without_law,
a_bar_with_law of root_bending_moment, load_factor, tip_deflection). ``--aero-theory dlm`` (with ``--clamped``): the doublet lattice
in the jig beam's modal basis with Roger's lag states, linearised as its residual system
(:mod:`wingmdao.stability.modal_turbulence`); its JSON holds a_bar and a_bar_error of
root_bending_moment, root_torsion, load_factor, tip_deflection and per station bending_moment and
torsion (body axes, force summation), the PSDs and transfer magnitudes, ``dlm`` (the model's
figures) and loads_include_1g false: no 1 g state, so no design_loads, correlation or stress.
"""

from __future__ import annotations

import os
import sys
import time as _time

import numpy as np

from wingmdao.plots import optional_pyplot

from wingmdao.aero.controls import control_spec, read_alleviation
from wingmdao.aero.dlm import DLM_CHORDWISE, DLM_FLAP_CHORDWISE
from wingmdao.cases import available_cases, case_beam_parameters, resolve_aero_theory
from wingmdao.cases.planform import G0, LB, wing_geometry
from wingmdao.cli._io import check_output_dir, check_output_file, read_design, refuse_existing, write_json
from wingmdao.loads.atmosphere import altitude_ft_to_m, density, mach_to_tas
from wingmdao.loads.turbulence import continuous_turbulence_intensity
from wingmdao.plots import save_figure
from wingmdao.stability.frequency import stress_matrices
from wingmdao.stability.modal_turbulence import dlm_turbulence_analysis
from wingmdao.aero.modal_free import free_modal_dlm_wing
from wingmdao.aero.system import aero_parameters, three_dimensional_parameters
from wingmdao.loads.turbulence_analysis import coupled_gust_model, strip_gust_model, turbulence_analysis
from wingmdao.design import SECTION_KINDS, WALL_VARS, initial_design, station_design
from wingmdao.stability.modal import modal_dlm_wing

#: --grid-points bounds (the geometric part of the frequency grid)
GRID_POINTS = (11, 5001)
#: --f-max-hz upper bound (Hz)
MAX_F_MAX_HZ = 1000.0


def _check_args(args, module):
    """Every flag before any solve; returns (plunge_free, altitude_ft, mach, M_C, M_D)."""
    plunge = args.plunge or ("free" if args.aero == "coupled" else "clamped")
    if args.aero == "strip" and plunge == "free":
        raise ValueError("--plunge free needs --aero coupled (the strip-theory gust loads act on a clamped wing); "
                         "use --aero strip --clamped or --aero coupled --plunge free")
    alt = module.CRUISE_ALTITUDE_FT if args.altitude_ft is None else float(args.altitude_ft)
    if not (np.isfinite(alt) and 0.0 <= alt <= 60000.0):
        raise ValueError(f"--altitude-ft = {alt} ft; allowed range [0, 60000] ft (14 CFR 25.341(b)(3)(i))")
    m_c = module.CRUISE_MACH
    m_d = m_c / module.VC_OVER_VD
    mach = m_c if args.mach is None else float(args.mach)
    if not (np.isfinite(mach) and 0.0 < mach <= m_d):
        raise ValueError(f"--mach = {mach}; allowed range (0, {m_d:g}] (M_D of {args.case}: M_C / {module.VC_OVER_VD:g})")
    if not (np.isfinite(args.damping_ratio) and 0.0 <= args.damping_ratio < 1.0):
        raise ValueError(f"--damping-ratio = {args.damping_ratio}; allowed range [0, 1)")
    if args.damping_frequency_hz is not None and not (np.isfinite(args.damping_frequency_hz)
                                                      and args.damping_frequency_hz > 0):
        raise ValueError(f"--damping-frequency-hz = {args.damping_frequency_hz} Hz; allowed range (0, inf) Hz")
    if not (np.isfinite(args.f_max_hz) and 0.1 <= args.f_max_hz <= MAX_F_MAX_HZ):
        raise ValueError(f"--f-max-hz = {args.f_max_hz} Hz; allowed range [0.1, {MAX_F_MAX_HZ:g}] Hz")
    if not GRID_POINTS[0] <= args.grid_points <= GRID_POINTS[1]:
        raise ValueError(f"--grid-points = {args.grid_points}; allowed range [{GRID_POINTS[0]}, {GRID_POINTS[1]}]")
    _check_theory(args)
    _check_dlm(args, plunge)
    _check_alleviation(args, plunge)
    return plunge == "free", alt, mach, m_c, m_d


def _check_alleviation(args, plunge):
    """--alleviation: the file read and checked (keys, gains, spans, hinges) before any solve;
    ``args.surfaces``, ``args.law`` (empty and None without it)."""
    args.surfaces, args.law = (), None
    if getattr(args, "alleviation", None) is None:
        return
    if args.aero != "coupled":
        raise ValueError(f"--alleviation {args.alleviation} needs --aero coupled (the control surfaces are states of "
                         "the coupled aeroelastic model; the --aero strip loads have none)")
    surfaces, law = read_alleviation(args.alleviation)
    if law is not None:
        for out, ok, need in (("load_factor", plunge == "free", "free plunge (--plunge free)"),
                              ("pitch_rate", False, "free pitch, which wingmdao turbulence does not model")):
            if out in law.outputs and not ok:
                raise ValueError(f"--alleviation {args.alleviation}: output {out} needs {need}")
    args.surfaces, args.law = surfaces, law


def _check_theory(args):
    """--aero-theory: unset, the default of --aero (resolve_aero_theory); the 3-D theories need --aero coupled."""
    if args.aero == "strip" and args.aero_theory not in (None, "strip", "dlm"):  # dlm: _check_dlm
        raise ValueError(f"--aero-theory {args.aero_theory} applies to --aero coupled (the --aero strip gust loads "
                         "use 2 pi)")
    args.aero_theory = resolve_aero_theory(args.aero_theory, args.aero)


def _check_dlm(args, plunge):
    """--aero-theory dlm: the jig's modal doublet lattice, clamped or free in plunge, undamped; --modes
    applies to it only."""
    if args.aero_theory != "dlm":
        if args.modes is not None:
            raise ValueError(f"--modes = {args.modes} applies to --aero-theory dlm only")
        return
    if args.aero != "coupled":
        raise ValueError("--aero-theory dlm needs --aero coupled (the doublet lattice on the deforming wing)")
    if args.damping_ratio > 0:
        raise ValueError(f"--damping-ratio = {args.damping_ratio} applies to the beam models; --aero-theory dlm "
                         "is undamped (give 0)")
    args.modes = 6 if args.modes is None else args.modes
    if not 2 <= args.modes <= 20:
        raise ValueError(f"--modes = {args.modes}; allowed range [2, 20]")


def _stress_matrices(setup, args):
    """(n, 8, 6) box stress per unit csn load of every station of the design (initial, or the walls
    per node of --design), or None for a case whose sections are not plain boxes."""
    if setup.section != "box":
        return None
    geo = setup.geometry
    if args.design:
        walls = read_design(args.design, geo.num_nodes, case=args.case, command="turbulence")
        dv = {w: walls[w[2:]] for w in WALL_VARS}
    else:
        dv = station_design(geo, initial_design(setup.options, SECTION_KINDS[setup.section]["design_vars"]), WALL_VARS)
    return stress_matrices(geo.width, geo.height, np.column_stack([dv[w] for w in WALL_VARS]), geo.section_to_csn)


def _check_outputs(args):
    """Check --out, --json and the plot paths before the run; the plot stem (None: --no-plots)."""
    stem, plots = None, []
    if not args.no_plots:
        check_output_dir(args.out, "--out")
        stem = os.path.join(args.out, f"{args.case}_turbulence")
        plots = [f"{stem}_{k}.png" for k in PLOTS]
        refuse_existing(plots, overwrite=args.overwrite, what="plot")
    check_output_file(args.json, "--json", overwrite=args.overwrite, others={"plot": plots[0] if plots else None})
    return stem


def run(args):
    t_wall = _time.perf_counter()
    module = available_cases()[args.case]
    plunge, alt_ft, mach, m_c, m_d = _check_args(args, module)
    stem = _check_outputs(args)
    fg = module.GUST_SET_DEFAULTS
    point = continuous_turbulence_intensity(alt_ft, z_mo_ft=fg["z_mo_ft"], mlw_over_mtow=fg["mlw_over_mtow"],
                                            mzfw_over_mtow=fg["mzfw_over_mtow"], speed=mach, v_c=m_c, v_d=m_d)
    walls = read_design(args.design, None, case=args.case, command="turbulence") if args.design else None
    setup, bp = case_beam_parameters(module, walls, source=f"--design {args.design}")
    pf = module.PLANFORM
    _, chord, axis_frac = wing_geometry(pf, getattr(module, "ENGINES", ()))
    alt = float(altitude_ft_to_m(alt_ft))
    rho, V = float(density(alt)), float(mach_to_tas(mach, alt))
    weight = module.TOGW_LB * LB * G0
    print(f"wingmdao turbulence {args.case}: {chord.size} nodes, --aero {args.aero}, "
          f"{'free plunge' if plunge else 'clamped'}, V = {V:.1f} m/s TAS, U_sigma = {point.u_sigma:.2f} m/s TAS",
          file=sys.stderr)
    damping = None
    if args.damping_ratio > 0:
        damping, note = module.gust_damping(args.damping_ratio, args.damping_frequency_hz, setup.geometry, setup.options)
        print(note, file=sys.stderr)
    if args.aero_theory == "dlm":
        return _run_dlm(args, bp, chord, axis_frac, mach, V, rho, weight, point, stem, t_wall,
                        {"altitude_ft": alt_ft, "altitude_m": alt}, plunge)
    without = None
    if args.aero == "coupled":
        if args.surfaces:
            try:
                control_spec(args.surfaces, np.asarray(bp["node_positions"])[:, 1], args.law)
            except ValueError as exc:
                raise ValueError(f"--alleviation {args.alleviation}: {exc}") from None
        ap = aero_parameters(chord.size, chord=chord, ref_point=axis_frac, airspeed=V, density=rho, mach=mach)
        ap.update(three_dimensional_parameters(args.aero_theory, bp["node_positions"], chord, axis_frac, mach))
        kw = dict(chord=chord, axis_fraction=axis_frac, weight=weight, plunge=plunge, damping=damping,
                  aero_theory="vlm" if args.aero_theory == "vlm" else "strip")
        gm = coupled_gust_model(bp, ap, **kw, surfaces=args.surfaces or None, law=args.law)
        if args.surfaces:  # the same wing without surfaces: the law's effect
            without = coupled_gust_model(bp, ap, **kw)
    else:
        gm = strip_gust_model(bp, chord=chord, axis_fraction=axis_frac, weight=weight, airspeed=V, density=rho,
                              semi_span=pf.semi_span, fuselage_half_width=pf.root_rib * pf.semi_span, damping=damping)
    res = {"case": args.case, "aero": args.aero, "aero_theory": args.aero_theory, "plunge": plunge, "design": args.design, "altitude_ft": alt_ft,
           "altitude_m": alt, "mach": mach, "damping_ratio": args.damping_ratio, "airspeed_tas_m_s": V, "density_kg_m3": rho,
           "u_sigma_ref_m_s": point.u_sigma_ref, "f_g": point.f_g, "speed_factor": point.speed_factor,
           "u_sigma_m_s": point.u_sigma, "span_m": np.asarray(bp["node_positions"])[:, 1].tolist()}
    res.update(turbulence_analysis(gm, point.u_sigma, f_max=args.f_max_hz, n_base=args.grid_points,
                                   stress_matrices=_stress_matrices(setup, args), surfaces=args.surfaces))
    if without is not None:
        res["alleviation"] = _alleviation_summary(args, res, without, point.u_sigma)
    res["wall_s"] = _time.perf_counter() - t_wall
    ab = res["a_bar"]
    print(f"A-bar: load factor {ab['load_factor']:.4g} per m/s, root bending {ab['root_bending_moment']:.4g} N m per m/s; "
          f"design load factor {res['design_loads']['load_factor']['up']:.3f} / "
          f"{res['design_loads']['load_factor']['down']:.3f}; quadrature error <= "
          f"{100 * res['quadrature']['max_relative_error_a_bar']:.2g} % of A-bar; {res['wall_s']:.1f} s", file=sys.stderr)
    write_json(res, args.json)  # the result first: a plotting failure must never lose it
    if stem:
        _plots(res, stem)
    return 0


def _alleviation_summary(args, res, without, u_sigma) -> dict:
    """``alleviation`` of the JSON: the file, the law, A-bar of the root bending, load factor and tip
    deflection without the surfaces (the same wing and grid settings) and with the law, and the
    surfaces' A-bar against their limits (``control_surfaces``)."""
    plain = turbulence_analysis(without, u_sigma, f_max=args.f_max_hz, n_base=args.grid_points)
    keys = ("root_bending_moment", "load_factor", "tip_deflection")
    law = None if args.law is None else {"outputs": list(args.law.outputs),
                                         **{k: v.tolist() for k, v in args.law.matrices().items()}}
    out = {"file": args.alleviation, "law": law,
           "a_bar_without_law": {k: plain["a_bar"][k] for k in keys},
           "a_bar_with_law": {k: res["a_bar"][k] for k in keys},
           "control_surfaces": res.get("control_surfaces", {})}
    for k in keys:
        print(f"alleviation: A-bar {k} {plain['a_bar'][k]:.4g} -> {res['a_bar'][k]:.4g} "
              f"({100 * (res['a_bar'][k] / plain['a_bar'][k] - 1):+.1f} %)", file=sys.stderr)
    return out


def _dlm_alleviation_summary(args, res, plain) -> dict:
    """``alleviation`` of the doublet lattice's JSON: as :func:`_alleviation_summary`, ``plain`` the
    same lattice with the surfaces held at zero."""
    keys = ("root_bending_moment", "load_factor", "tip_deflection")
    law = None if args.law is None else {"outputs": list(args.law.outputs),
                                         **{k: v.tolist() for k, v in args.law.matrices().items()}}
    for k in keys:
        print(f"alleviation: A-bar {k} {plain['a_bar'][k]:.4g} -> {res['a_bar'][k]:.4g} "
              f"({100 * (res['a_bar'][k] / plain['a_bar'][k] - 1):+.1f} %)", file=sys.stderr)
    return {"file": args.alleviation, "law": law, "a_bar_without_law": {k: plain["a_bar"][k] for k in keys},
            "a_bar_with_law": {k: res["a_bar"][k] for k in keys}, "control_surfaces": res.get("control_surfaces", {})}


def _run_dlm(args, bp, chord, axis_frac, mach, V, rho, weight, point, stem, t_wall, alt, plunge):
    y = np.asarray(bp["node_positions"])[:, 1]
    specs = [None]
    if args.surfaces:  # the surfaces as flap modes of the lattice; without the law: the same lattice, surfaces at 0
        try:
            specs = [control_spec(args.surfaces, y, args.law), control_spec(args.surfaces, y, None)]
        except ValueError as exc:
            raise ValueError(f"--alleviation {args.alleviation}: {exc}") from None
    kw = dict(n_modes=args.modes, n_chordwise=DLM_FLAP_CHORDWISE if args.surfaces else DLM_CHORDWISE)
    wings = [free_modal_dlm_wing(bp, chord, axis_frac, mach, aircraft_mass=weight / G0, controls=c, **kw) if plunge
             else modal_dlm_wing(bp, chord, axis_frac, mach, controls=c, **kw) for c in specs]
    wing = wings[0]
    res = {"case": args.case, "aero": args.aero, "aero_theory": "dlm", "plunge": bool(plunge), "design": args.design,
           **alt,
           "mach": mach, "damping_ratio": 0.0, "airspeed_tas_m_s": V, "density_kg_m3": rho,
           "u_sigma_ref_m_s": point.u_sigma_ref, "f_g": point.f_g, "speed_factor": point.speed_factor,
           "u_sigma_m_s": point.u_sigma, "span_m": np.asarray(bp["node_positions"])[:, 1].tolist(),
           "modes": args.modes}
    res.update(dlm_turbulence_analysis(wing, V, rho, weight, f_max=args.f_max_hz, n_base=args.grid_points,
                                       surfaces=args.surfaces, law=args.law, u_sigma=point.u_sigma))
    if args.surfaces:
        plain = dlm_turbulence_analysis(wings[1], V, rho, weight, f_max=args.f_max_hz, n_base=args.grid_points)
        res["alleviation"] = _dlm_alleviation_summary(args, res, plain)
    res["wall_s"] = _time.perf_counter() - t_wall
    ab = res["a_bar"]
    print(f"A-bar (doublet lattice, {args.modes} modes): load factor {ab['load_factor']:.4g} per m/s, root bending "
          f"{ab['root_bending_moment']:.4g} N m per m/s; quadrature error <= "
          f"{100 * res['quadrature']['max_relative_error_a_bar']:.2g} % of A-bar; {res['wall_s']:.1f} s", file=sys.stderr)
    write_json(res, args.json)
    if stem:
        _plots(res, stem)
    return 0


def _plots(res, stem):
    """|H|, the PSDs, the design-load envelope along the span and the root (bending, torsion) ellipse."""
    plt = optional_pyplot()
    if plt is None:
        return
    f = np.asarray(res["frequency_hz"])
    label = {"root_bending_moment": "root bending (N m per m/s)", "load_factor": "load factor (1 per m/s)",
             "tip_deflection": "tip deflection (m per m/s)"}
    fig, axes = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    for ax, (k, text) in zip(axes, label.items()):
        ax.loglog(f, res["transfer_function_magnitude"][k])
        ax.set_ylabel(f"|H| {text}", fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
    axes[-1].set_xlabel("frequency (Hz)")
    axes[0].set_title(f"{res['case']}: frequency response to a unit vertical gust ({res['model']})", fontsize=9)
    _save(fig, f"{stem}_transfer.png")

    fig, axes = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    for ax, k, unit in zip(axes, ("root_bending_moment", "load_factor"), ("(N m)^2/Hz", "1/Hz")):
        ax.loglog(f, np.asarray(res["psd"][k]) * res["u_sigma_m_s"] ** 2)
        ax.set_ylabel(f"PSD {k.replace('_', ' ')} {unit}", fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
    axes[-1].set_xlabel("frequency (Hz)")
    axes[0].set_title(f"output PSDs at U_sigma = {res['u_sigma_m_s']:.2f} m/s (von Karman, L = 2,500 ft)", fontsize=9)
    _save(fig, f"{stem}_psd.png")
    if "design_loads" not in res:  # the doublet lattice's A-bar only (no 1 g state)
        return

    y = np.abs(res["span_m"])
    fig, axes = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    for ax, k, scale, unit in zip(axes, ("vertical_shear", "bending_moment", "torsion"), (1e-3, 1e-3, 1e-3),
                                  ("kN", "kN m", "kN m")):
        d = res["design_loads"][k]
        ax.plot(y, np.asarray(d["one_g"]) * scale, "k-", label="1 g")
        ax.fill_between(y, np.asarray(d["down"]) * scale, np.asarray(d["up"]) * scale, alpha=0.3,
                        label="1 g +/- U_sigma A-bar")
        ax.set_ylabel(f"{k.replace('_', ' ')} ({unit})", fontsize=8)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[-1].set_xlabel("span y (m)")
    axes[0].set_title("25.341(b) design-load envelope (csn frame of each station)", fontsize=9)
    _save(fig, f"{stem}_envelope.png")

    fig, ax = plt.subplots(figsize=(6, 5))
    e = np.asarray(res["correlation"]["root_ellipse"]) * 1e-3
    c = np.asarray(res["correlation"]["correlated_loads"][0]) * 1e-3
    ax.plot(e[:, 0], e[:, 1], "b-", label="equal-probability ellipse")
    ax.plot(c[:, 0], c[:, 1], "ro", label="correlated design loads")
    ax.set_xlabel("root bending moment M_c (kN m)")
    ax.set_ylabel("root torsion M_s (kN m)")
    ax.set_title(f"root: rho = {res['correlation']['bending_torsion'][0]:.3f}", fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    _save(fig, f"{stem}_ellipse.png")


def _save(fig, path):
    save_figure(fig, path, dpi=100)
    print(f"wrote {path}", file=sys.stderr)


#: the plots of the command (suffixes of CASE_turbulence_*.png)
PLOTS = ("transfer", "psd", "envelope", "ellipse")
