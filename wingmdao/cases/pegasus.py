"""PEGASUS wing (App. D.2, Tables D.3-D.4) sized for 2.5 g / -1.0 g maneuvers and a 25.341 gust.

Geometry: Table D.3 planform (586.33 ft^2, span 80.59 ft, taper 0.986) with spars at 18 % and
75 % chord, stations 0-19 (0 = symmetry plane, a copy of the root rib section, i.e. the centre
wingbox; 1 = root rib at 8 % semi-span; 19 = tip rib at 99.5 %). Stations 0 and 1 share their
design variables, giving the 4 x 19 = 76 design variables of Table 5.1 (minimum gauge 1 mm).

Airfoil (an assumption, documented in docs/cases.md): PEGASUS derives from the ATR 42 class,
whose wing uses NACA 43-series sections about 18 % thick at the root and 13 % at the tip; we
use NACA 43018 -> 43013 and derive box width/height per station with Eq. 4.11-4.12.
Engines (assumptions): per wing a hybrid-electric engine of 600 kg at 35 % semi-span and a
wing-tip electric motor of 150 kg, as point masses (smeared over the adjacent elements).
Loads: maneuvers by Schrenk lift with the centre of pressure at 25 % chord and inertia
relief from the beam's own mass (gravity + frame acceleration (n - 1) g); the gust of
Table 5.3 (25000 ft, Mach 0.5, U_ref 30 ft/s, H 350 ft, 5 s) by strip theory on top of 1 g
level flight, rigid-body plunge neglected (conservative).
"""

from __future__ import annotations

import numpy as np

from wingmdao.cases import CaseSetup
from wingmdao.cases.planform import FT, G0, LB, Planform, wing_geometry

NAME = "pegasus"
HELP = "PEGASUS wing (App. D.2): 76 thickness variables, 2.5 g / -1.0 g maneuvers and/or a 25.341 gust"

PLANFORM = Planform(area_ft2=586.3328, span_ft=80.58962, taper=0.986, le_sweep_deg=0.0,
                    front_spar=0.18, rear_spar=0.75, root_rib=0.08, tip_rib=0.995, num_ribs=19,
                    airfoil_root="43018", airfoil_tip="43013")
TOGW_LB = 41005.0
ENGINES = ((600.0, 0.35 * PLANFORM.semi_span), (150.0, PLANFORM.tip_rib * PLANFORM.semi_span))
MANEUVER_ALTITUDE_FT, MANEUVER_MACH = 20000.0, 0.5
#: 25.341(a)(6) inputs (assumed, ATR 42-600 class: MTOW 18 600 kg, MLW 18 300 kg, MZFW 16 700 kg,
#: ceiling 25 000 ft); F_g = 1 at and above Z_mo, so Table 5.3's 25 000 ft gust is unchanged.
GUST_SET_DEFAULTS = {"z_mo_ft": 25000.0, "mlw_over_mtow": 18300.0 / 18600.0, "mzfw_over_mtow": 16700.0 / 18600.0}
GUST = {"altitude_ft": 25000.0, "mach": 0.5, "u_ref_fps": 30.0, "gradient_ft": 350.0, "t_final": 5.0}
MIN_GAUGE = 1e-3  # m (Table 5.1)


def add_arguments(p):
    p.add_argument("--loads", choices=["maneuver", "gust", "all"], default=None,
                   help="load cases: the 2.5 g and -1.0 g maneuvers, the gust of Table 5.3 (or the gust set), "
                        "or all (default: maneuver, all with a gust set)")
    p.add_argument("--load-factor", type=float, default=2.5,
                   help="positive maneuver load factor (25.337 gives 2.57 at 41005 lb; the dissertation uses 2.5)")
    p.add_argument("--negative-load-factor", type=float, default=-1.0, help="negative maneuver load factor")
    p.add_argument("--families", default="vm",
                   help="comma list of stress families constrained (vm, ss_tension, ss_compression, cent_pos, cent_neg)")
    p.add_argument("--altitude-ft", type=float, default=GUST["altitude_ft"], help="gust altitude [ft]")
    p.add_argument("--mach", type=float, default=GUST["mach"], help="gust flight Mach number")
    p.add_argument("--u-ref-fps", type=float, default=GUST["u_ref_fps"],
                   help="reference gust velocity [ft/s EAS] (Table 5.3: 30); 0 = the 25.341(a)(5) table value")
    p.add_argument("--gust-gradient-ft", type=float, default=GUST["gradient_ft"], help="gust gradient H [ft], 30-350")
    p.add_argument("--t-final", type=float, default=GUST["t_final"], help="gust simulation time [s]")
    p.add_argument("--dt", type=float, default=0.02, help="time step [s]")
    p.add_argument("--gust-start", type=float, default=0.2, help="time the gust front reaches the wing [s]")
    p.add_argument("--aero", choices=["strip", "coupled"], default="strip",
                   help="gust aerodynamics: strip (precomputed rigid-wing strip-theory loads) or coupled (unsteady "
                        "strip theory on the deforming beam, trimmed 1 g start, clamped root; docs/aeroelasticity.md)")
    p.add_argument("--plunge", choices=["clamped", "free"], nargs="?", const="free", default="clamped",
                   help="coupled gust (--aero coupled): clamped (root clamped, wind-tunnel wing, no alleviation; "
                        "default) or free (the aircraft free in plunge, its mass the TOGW: gust alleviation by "
                        "the aircraft's response; '--plunge' alone = free)")
    p.add_argument("--kussner", action="store_true", help="lag the gust lift by the Kussner function")
    p.add_argument("--damping-ratio", type=float, default=0.0,
                   help="structural damping ratio of the gust case's beam (Kelvin-Voigt strain-rate damping, "
                        "Alg. 6) at --damping-frequency-hz; 0 = undamped; Nastran practice: 0.02")
    p.add_argument("--damping-frequency-hz", type=float, default=None,
                   help="frequency at which --damping-ratio holds [Hz]; unset (%(default)s): the first mode "
                        "of the initial design")
    g = p.add_argument_group("25.341(a) gust set (every gust is a load case with its own KS; see docs/gust-envelope.md)")
    g.add_argument("--gust-set", metavar="FILE", default=None,
                   help="gust set description (.json or .yaml): flight points x gradients x signs")
    g.add_argument("--gust-gradients-ft", metavar="H", type=float, nargs="+", default=None,
                   help="gust gradient distances [ft], 30-350, at the --altitude-ft/--mach flight point")
    g.add_argument("--gust-gradient-count", metavar="N", type=int, default=None,
                   help="N gradients log-spaced over 30-350 ft (instead of --gust-gradients-ft)")
    g.add_argument("--gust-sign", choices=["up", "down", "both"], default=None,
                   help="up and/or down gusts of the set (default: both with a set, up for the single gust)")
    p.add_argument("--load-history", metavar="FILE", default=None,
                   help="gust case from a load time history file (.npz or .csv on the 20 beam nodes, "
                        "format in docs/loads.md, e.g. exported from a Nastran SOL 146 run) instead of strip theory")


def parse_families(text: str) -> tuple:
    from wingmdao.groups.load_case import STRESS_FAMILIES

    fams = tuple(f.strip() for f in text.split(",") if f.strip())
    bad = [f for f in fams if f not in STRESS_FAMILIES]
    if bad or not fams:
        raise ValueError(f"--families: unknown {bad or 'empty'}; valid: {', '.join(STRESS_FAMILIES)}")
    return fams


def maneuver_case(name, n_load, geometry, chord, axis_frac, families, pf=PLANFORM, weight_lb=TOGW_LB):
    from wingmdao.groups.load_case import LoadCase
    from wingmdao.loads.maneuver import maneuver_line_loads

    loads = maneuver_line_loads(geometry.node_positions, chord, axis_frac, weight_lb * LB * G0, n_load,
                                semi_span=pf.semi_span, fuselage_half_width=pf.root_rib * pf.semi_span)
    forcing = {
        "force_per_length": loads.force_per_length[None],
        "moment_per_length": loads.moment_per_length[None],
        "gravity": np.array([[0.0, 0.0, -G0]]),
        "frame_acceleration": np.array([[0.0, 0.0, (n_load - 1.0) * G0]]),
    }
    return LoadCase(name, np.zeros(1), forcing, families, f"{n_load:+.2f} g symmetric maneuver")


def coupled_maneuver_case(name, n_load, args, geometry, chord, axis_frac, families, weight_lb=TOGW_LB):
    """Trimmed static aeroelastic maneuver (``--aero coupled``): the aircraft angle of attack solved
    so that both half-wings lift n W on the deforming wing (strip theory, quasi-steady), at the
    --altitude-ft / --mach flight point, inertia relief (n - 1) g as in :func:`maneuver_case`."""
    from wingmdao.aero.coupled import CoupledAero
    from wingmdao.groups.load_case import LoadCase
    from wingmdao.loads.atmosphere import altitude_ft_to_m, density, mach_to_tas

    alt = float(altitude_ft_to_m(args.altitude_ft))
    forcing = {"gravity": np.array([[0.0, 0.0, -G0]]),
               "frame_acceleration": np.array([[0.0, 0.0, (n_load - 1.0) * G0]]),
               "trim_active": np.ones(1)}
    aero = CoupledAero(chord=np.asarray(chord, dtype=float), ref_point=np.asarray(axis_frac, dtype=float),
                       airspeed=float(mach_to_tas(args.mach, alt)), density=float(density(alt)), mach=float(args.mach),
                       trim=True, trim_lift=n_load * weight_lb * LB * G0)
    return LoadCase(name, np.zeros(1), forcing, families, f"{n_load:+.2f} g trimmed aeroelastic maneuver", aero=aero)


def gust_case(args, geometry, chord, axis_frac, families, pf=PLANFORM, weight_lb=TOGW_LB):
    from wingmdao.loads.atmosphere import altitude_ft_to_m, mach_to_tas
    from wingmdao.loads.gust import design_gust_velocity_eas

    if not 0.0 <= args.altitude_ft <= 60000.0:
        raise ValueError(f"--altitude-ft {args.altitude_ft} outside the 25.341 table range 0-60000 ft")
    if not 30.0 <= args.gust_gradient_ft <= 350.0:
        raise ValueError(f"--gust-gradient-ft {args.gust_gradient_ft} outside 30-350 ft (25.341(a)(3))")
    if not (0.0 < args.mach < 1.0):
        raise ValueError(f"--mach {args.mach} outside (0, 1)")
    if getattr(args, "load_history", None):
        return file_case(args.load_history, geometry, families)
    _check_time_grid(args, geometry.num_nodes)
    alt = altitude_ft_to_m(args.altitude_ft)
    if args.u_ref_fps > 0:
        u_ds = args.u_ref_fps * FT * (args.gust_gradient_ft / 350.0) ** (1.0 / 6.0)
    else:
        u_ds = design_gust_velocity_eas(args.gust_gradient_ft, args.altitude_ft, 1.0)
    direction = -1 if getattr(args, "gust_sign", None) == "down" else 1
    return gust_history_case("gust", args, geometry, chord, axis_frac, families, gradient_ft=args.gust_gradient_ft,
                             u_ds_eas=u_ds, airspeed_tas=float(mach_to_tas(args.mach, alt)), altitude_m=float(alt),
                             direction=direction, weight_lb=weight_lb, pf=pf,
                             description=f"1-cos gust U_ds = {u_ds / FT:.1f} ft/s EAS, H = {args.gust_gradient_ft:g} ft"
                                         + (" (down)" if direction < 0 else ""))


def _check_time_grid(args, num_nodes):
    """Time grid, reference gust velocity and gust start of the dynamic cases, before any solve."""
    if not (np.isfinite(args.t_final) and args.t_final > 0 and 0 < args.dt <= args.t_final / 10):
        raise ValueError(f"--t-final ({args.t_final} s) and --dt ({args.dt} s): need finite 0 < 10 dt <= t_final")
    from wingmdao.cases import check_step_count

    check_step_count(args.t_final, args.dt, num_nodes)
    if not (np.isfinite(args.u_ref_fps) and args.u_ref_fps >= 0):
        raise ValueError(f"--u-ref-fps = {args.u_ref_fps} ft/s; allowed range [0, inf) ft/s "
                         "(0 = the 25.341(a)(5) table value)")
    if not (np.isfinite(args.gust_start) and 0.0 <= args.gust_start < args.t_final):
        raise ValueError(f"--gust-start = {args.gust_start} s; allowed range [0, --t-final = {args.t_final}) s")


def gust_history_case(name, args, geometry, chord, axis_frac, families, *, gradient_ft, u_ds_eas, airspeed_tas,
                      altitude_m, direction, weight_lb, pf, description):
    """One strip-theory 1 - cos gust load case on top of 1 g level flight at ``weight_lb``."""
    from wingmdao.groups.load_case import LoadCase
    from wingmdao.loads.gust import gust_line_loads
    from wingmdao.loads.maneuver import maneuver_line_loads

    time = np.arange(0.0, args.t_final + 0.5 * args.dt, args.dt)
    if getattr(args, "aero", "strip") == "coupled":
        return coupled_gust_case(name, args, geometry, chord, axis_frac, families, time, gradient_ft=gradient_ft,
                                 u_ds_eas=u_ds_eas, airspeed_tas=airspeed_tas, altitude_m=altitude_m,
                                 direction=direction, weight_lb=weight_lb, description=description)
    steady = maneuver_line_loads(geometry.node_positions, chord, axis_frac, weight_lb * LB * G0, 1.0,
                                 semi_span=pf.semi_span, fuselage_half_width=pf.root_rib * pf.semi_span)
    hist = gust_line_loads(geometry.node_positions, chord, axis_frac, time,
                           gust_gradient_m=gradient_ft * FT, u_ds_eas=u_ds_eas,
                           airspeed_tas=airspeed_tas, altitude_m=altitude_m,
                           kussner=args.kussner, gust_start_time=args.gust_start, steady=steady,
                           direction=direction, fuselage_half_width=pf.root_rib * pf.semi_span)
    forcing = {"force_per_length": hist.force_per_length, "moment_per_length": hist.moment_per_length,
               "gravity": np.array([0.0, 0.0, -G0])}
    return LoadCase(name, time, forcing, families, description)


def gust_set_of(args):
    """The 25.341(a) gust set the options ask for, or None for the single gust of Table 5.3.

    ``--gust-set FILE`` (defaults: :data:`GUST_SET_DEFAULTS`), or ``--gust-gradients-ft`` /
    ``--gust-gradient-count`` at the ``--altitude-ft``, ``--mach`` flight point (U_ref from
    ``--u-ref-fps``, 0 = the 25.341(a)(5) table) with ``--gust-sign`` (default both).
    """
    from wingmdao.loads.gust_set import FlightPoint, GustSet, log_spaced_gradients_ft, parse_signs, read_gust_set

    path = getattr(args, "gust_set", None)
    grads = getattr(args, "gust_gradients_ft", None)
    count = getattr(args, "gust_gradient_count", None)
    sign = getattr(args, "gust_sign", None)
    if sum(x is not None for x in (path, grads, count)) > 1:
        raise ValueError("give one of --gust-set, --gust-gradients-ft and --gust-gradient-count")
    if path is not None:
        gset = read_gust_set(path, defaults=GUST_SET_DEFAULTS)
        if sign is not None:
            from dataclasses import replace

            gset = replace(gset, signs=parse_signs(sign))
        return gset
    if grads is None and count is None:
        return None
    if grads is not None and len(grads) == 0:
        raise ValueError("--gust-gradients-ft: empty; give at least one gradient distance in [30, 350] ft")
    fp = FlightPoint(altitude_ft=float(args.altitude_ft), mach=float(args.mach),
                     u_ref_fps=float(args.u_ref_fps) if args.u_ref_fps > 0 else None)
    h = grads if grads is not None else log_spaced_gradients_ft(count)
    return GustSet((fp,), h, parse_signs(sign or "both"), **GUST_SET_DEFAULTS)


def coupled_gust_case(name, args, geometry, chord, axis_frac, families, time, *, gradient_ft, u_ds_eas,
                      airspeed_tas, altitude_m, direction, weight_lb, description):
    """The 1 - cos gust on the aeroelastic beam (``--aero coupled``): unsteady strip theory on the
    deforming wing (wingmdao.aero), root clamped or free plunge, the march starting from the trimmed 1 g state
    (aircraft angle of attack solved at t = 0 so that both half-wings lift W, gravity on), the gust
    velocity per station with its penetration delay from the most forward leading edge.
    ``--plunge free``: the aircraft (``weight_lb``) free in plunge, its mass the case input
    ``aircraft_mass``; clamped root otherwise."""
    from wingmdao.aero import station_gust_history
    from wingmdao.aero.coupled import CoupledAero
    from wingmdao.groups.load_case import LoadCase
    from wingmdao.loads.atmosphere import density, speed_of_sound

    rho, rho0 = float(density(altitude_m)), float(density(0.0))
    V = float(airspeed_tas)
    mach = V / float(speed_of_sound(altitude_m))  # the flight point's (a gust set may have several)
    H = gradient_ft * FT
    u_tas = direction * u_ds_eas * np.sqrt(rho0 / rho)
    x_le = geometry.node_positions[:, 0] - np.asarray(axis_frac) * np.asarray(chord)

    def profile(tau):
        d = V * (tau - args.gust_start)
        return np.where((d >= 0) & (d <= 2 * H), 0.5 * u_tas * (1 - np.cos(np.pi * d / H)), 0.0)

    trim = np.zeros(time.size)
    trim[0] = 1.0
    forcing = {"gravity": np.array([0.0, 0.0, -G0]), "gust_velocity": station_gust_history(time, x_le, V, profile),
               "trim_active": trim}
    free = getattr(args, "plunge", "clamped") == "free"
    aero = CoupledAero(chord=np.asarray(chord, dtype=float), ref_point=np.asarray(axis_frac, dtype=float),
                       airspeed=V, density=rho, mach=mach, trim=True, trim_lift=weight_lb * LB * G0,
                       plunge=free, aircraft_mass=weight_lb * LB)
    return LoadCase(name, time, forcing, families,
                    description + f" (coupled aeroelastic, {'free plunge' if free else 'clamped root'})", aero=aero)


def gust_set_cases(gset, args, geometry, chord, axis_frac, families, pf=PLANFORM, weight_lb=TOGW_LB):
    """One load case per gust of ``gset`` (strip theory on top of 1 g at the flight point's weight)."""
    if getattr(args, "load_history", None):
        raise ValueError("--load-history and a gust set exclude each other")
    _check_time_grid(args, geometry.num_nodes)
    cases = []
    for g in gset.gusts():
        fp = g.flight_point
        cases.append(gust_history_case(g.name, args, geometry, chord, axis_frac, families, gradient_ft=g.gradient_ft,
                                       u_ds_eas=g.u_ds_eas, airspeed_tas=fp.airspeed_tas(), altitude_m=fp.altitude_m,
                                       direction=g.sign, weight_lb=fp.weight_lb or weight_lb, pf=pf,
                                       description=g.describe()))
    return cases


def file_case(path, geometry, families):
    """Gust load case from a load-history file (time, force/moment per length on the beam nodes)."""
    from wingmdao.groups.load_case import LoadCase
    from wingmdao.loads.files import read_load_history

    hist = read_load_history(path)
    if hist.num_nodes != geometry.num_nodes:
        raise ValueError(f"--load-history {path}: {hist.num_nodes} nodes, the beam has {geometry.num_nodes}")
    forcing = dict(hist.as_forcing(), gravity=np.array([0.0, 0.0, -G0]))
    return LoadCase("gust", hist.time, forcing, families, f"load history from {path}")


def build(args, pf=PLANFORM, engines=ENGINES, weight_lb=TOGW_LB) -> CaseSetup:
    from wingmdao.materials import ALUMINIUM
    from wingmdao.sizing import WALL_VARS, SizingOptions

    families = parse_families(args.families)
    gset = gust_set_of(args)
    loads = args.loads or ("all" if gset is not None else "maneuver")
    if getattr(args, "load_history", None) and loads == "maneuver":
        raise ValueError(f"--load-history {args.load_history} replaces the gust case; it does not apply to "
                         "--loads maneuver (use --loads gust or all)")
    if not np.isfinite(args.load_factor) or args.load_factor <= 0:
        raise ValueError(f"--load-factor must be > 0, got {args.load_factor}")
    if args.negative_load_factor >= 0:
        raise ValueError(f"--negative-load-factor must be < 0, got {args.negative_load_factor}")
    if getattr(args, "plunge", "clamped") == "free" and getattr(args, "aero", "strip") != "coupled":
        raise ValueError(f"--plunge free needs --aero coupled (the strip-theory loads are precomputed on a "
                         f"clamped wing), got --aero {getattr(args, 'aero', 'strip')}")
    zeta = float(getattr(args, "damping_ratio", 0.0) or 0.0)
    if not 0.0 <= zeta < 1.0:
        raise ValueError(f"--damping-ratio must be in [0, 1), got {zeta}")
    geometry, chord, axis_frac = wing_geometry(pf, engines)
    options = SizingOptions(lower={w: MIN_GAUGE for w in WALL_VARS}, upper={w: 0.05 for w in WALL_VARS},
                            initial={w: 0.01 for w in WALL_VARS}, rho_ks=100.0, presize=4)
    notes = ["airfoil NACA 43018 -> 43013 (assumed, ATR 42 class)",
             "engines as point masses: 600 kg at 35 % semi-span, 150 kg at the tip (assumed)"]
    if args.loads == "maneuver":
        gust_only = {"altitude_ft": GUST["altitude_ft"], "mach": GUST["mach"], "u_ref_fps": GUST["u_ref_fps"],
                     "gust_gradient_ft": GUST["gradient_ft"], "t_final": GUST["t_final"], "dt": 0.02,
                     "gust_start": 0.2, "kussner": False, "damping_ratio": 0.0, "damping_frequency_hz": None}
        ignored = [f"--{k.replace('_', '-')} {getattr(args, k)}" for k, d in gust_only.items()
                   if hasattr(args, k) and getattr(args, k) != d]
        if ignored:
            notes.append(f"warning: ignored with --loads maneuver (gust options): {', '.join(ignored)}")
    cases = []
    if loads in ("gust", "all"):
        gusts = ([gust_case(args, geometry, chord, axis_frac, families, pf, weight_lb)] if gset is None
                 else gust_set_cases(gset, args, geometry, chord, axis_frac, families, pf, weight_lb))
        if gset is not None:
            notes.append(f"25.341(a) gust set: {len(gset)} gusts ({len(gset.flight_points)} flight point(s) x "
                         f"{len(gset.gradients_ft)} gradient(s) x {len(gset.signs)} sign(s))")
        if zeta > 0.0:
            damping, note = gust_damping(zeta, getattr(args, "damping_frequency_hz", None), geometry, options)
            for case in gusts:
                case.damping = damping
            notes.append(note)
        cases.extend(gusts)
    if loads in ("maneuver", "all"):
        if getattr(args, "aero", "strip") == "coupled":
            cases.insert(0, coupled_maneuver_case("maneuver_pos", args.load_factor, args, geometry, chord, axis_frac,
                                                  families, weight_lb))
            cases.insert(1, coupled_maneuver_case("maneuver_neg", args.negative_load_factor, args, geometry, chord,
                                                  axis_frac, families, weight_lb))
        else:
            cases.insert(0, maneuver_case("maneuver_pos", args.load_factor, geometry, chord, axis_frac, families, pf,
                                          weight_lb))
            cases.insert(1, maneuver_case("maneuver_neg", args.negative_load_factor, geometry, chord, axis_frac,
                                          families, pf, weight_lb))
    return CaseSetup(geometry, cases, ALUMINIUM, options, notes=notes)


def gust_damping(zeta, frequency_hz, geometry, options):
    """Strain-rate damping with ratio ``zeta`` at ``frequency_hz`` (default: the initial design's first mode)."""
    from wingmdao.beam.residual import StrainRateDamping
    from wingmdao.materials import ALUMINIUM
    from wingmdao.sizing import initial_frequencies

    if frequency_hz is None:
        frequency_hz = float(initial_frequencies(geometry, ALUMINIUM, options, count=1)[0])
        where = "first mode of the initial design"
    else:
        where = "given"
    if not frequency_hz > 0.0:
        raise ValueError(f"--damping-frequency-hz must be > 0 Hz, got {frequency_hz}")
    damping = StrainRateDamping.from_damping_ratio(zeta, frequency_hz)
    return damping, (f"structural damping {zeta:g} at {frequency_hz:.3f} Hz ({where}): "
                     f"strain-rate time constant {damping.curvature[0] * 1e3:.3f} ms")
