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

from dataclasses import dataclass, replace

import numpy as np

from wingmdao.cases import (CaseOptions, CaseSetup, add_option_arguments, case_options, check_step_count, option,
                            resolve_aero_theory)
from wingmdao.cases.planform import FT, G0, LB, Planform, wing_geometry
from wingmdao.aero.controls import control_spec, maneuver_commands, read_alleviation
from wingmdao.aero.pitch import check_pitch_inputs, elevator_effectiveness
from wingmdao.aero.strip import station_gust_history
from wingmdao.beam.residual import StrainRateDamping
from wingmdao.groups.load_case import LoadCase, parse_families as _parse
from wingmdao.loads.atmosphere import altitude_ft_to_m, density, mach_to_tas, speed_of_sound
from wingmdao.loads.files import read_load_history
from wingmdao.loads.gust import design_gust_velocity_eas, gust_line_loads
from wingmdao.loads.gust_set import FlightPoint, GustSet, log_spaced_gradients_ft, parse_signs, read_gust_set
from wingmdao.loads.maneuver import maneuver_line_loads
from wingmdao.materials import ALUMINIUM
from wingmdao.panels.layout import PanelLayout, STIFFENER_VARS, smeared_stringer
from wingmdao.section.box import WALL_NAMES, beam_params_from_section, box_properties, validate_box
from wingmdao.aero.coupled import CoupledAero
from wingmdao.aero.modal_design import cosine_gust
from wingmdao.aero.modal_free import free_cosine_gust
from wingmdao.aero.system import three_dimensional_parameters
from wingmdao.design import SECTION_KINDS, WALL_VARS, SizingOptions, design_beam_params, initial_design, initial_frequencies
from wingmdao.names import CASE_HELP
from wingmdao.aero.system import aero_parameters
from wingmdao.loads.rolling import (CONDITIONS as ROLL_CONDITIONS, check_rolling_inputs, condition_commands,
                                    rolling_speeds)

NAME = "pegasus"
HELP = CASE_HELP[NAME]

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
LOAD_SETS = ("maneuver", "gust", "all")
AERO_MODELS = ("strip", "coupled")
#: quasi-steady lift of --aero coupled (--aero-theory; wingmdao.aero.coupled.AERO_THEORY_CHOICES)
AERO_THEORIES = ("strip", "lifting-line", "vlm", "dlm")
#: the coupled gust's root: clamped (wind-tunnel wing) or the aircraft free in plunge
PLUNGE_MODES = ("clamped", "free")
#: the coupled gust's pitch: fixed or free with a horizontal tail (wingmdao.aero.pitch; needs free plunge)
PITCH_MODES = ("fixed", "free")
#: the aircraft data free pitch needs (no defaults: the case has no tail, CG or pitch inertia)
PITCH_REQUIRED = ("pitch_inertia", "cg_x", "tail_arm", "tail_area", "tail_lift_slope")
GUST_SIGNS = ("up", "down", "both")
#: wall models: unstiffened plates (strength only) or stiffened skins with buckling and ribs
PANEL_MODELS = ("unstiffened", "stiffened")
#: how the stiffened walls are sized (wingmdao.panel_sizing.PANEL_SIZINGS; kept here, the
#: case modules do not import the sizing)
PANEL_SIZINGS = ("full", "two-level")
#: --help group of the stiffened-panel options (pegasus and the cases built on it)
PANEL_GROUP = "stiffened panels (docs/panels.md)"
#: --help groups of the free-pitch and gust-set options
PITCH_GROUP = "free pitch (--pitch free; SI, body axes: x aft, z up from the symmetry-plane origin)"
ROLL_GROUP = "rolling conditions (--rolling; SI, body axes)"
#: the march of each sized rolling condition (s)
ROLL_CASE_T_FINAL = 2.0
GUST_SET_GROUP = "25.341(a) gust set (every gust is a load case with its own KS; see docs/gust-envelope.md)"
#: the panel options' fields (:func:`panel_options`)
PANEL_FIELDS = ("panels", "stiffener_pitch", "rib_pitch")


def panel_options() -> dict:
    """The stiffened-panel option fields of pegasus and the cases built on it.

    Returns
    -------
    dict
        ``{name: dataclasses.Field}`` of ``panels`` (wall model), ``stiffener_pitch`` (m) and
        ``rib_pitch`` (m; None: the case's ribs), new fields for each options dataclass.
    """
    return {
        "panels": option("unstiffened", "wall model: unstiffened plates sized for strength (von Mises) or "
                                        "stiffened: blade stiffeners on both skins with skin, panel, stiffener and "
                                        "spar-web buckling (safety factor 1.5 on the loads), ribs at the case's rib "
                                        "stations and the sizing rules", choices=PANEL_MODELS, group=PANEL_GROUP),
        "stiffener_pitch": option(0.15, "stiffener spacing on both skins (m)", metavar="M", group=PANEL_GROUP),
        "rib_pitch": option(None, "rib spacing (m) from the root rib to the tip rib, rounded to equal bays (default "
                                  "unset: the case's ribs, one at each station)", metavar="M", group=PANEL_GROUP),
    }


@dataclass(frozen=True)
class PegasusOptions(CaseOptions):
    """Options of the PEGASUS case (units in the names); ``wingmdao size pegasus --help`` describes each."""

    CASE = NAME
    loads: str | None = option(None, "load cases: the 2.5 g and -1.0 g maneuvers, the gust of Table 5.3 (or the gust "
                                     "set), or all (default: maneuver, all with a gust set)", choices=LOAD_SETS)
    load_factor: float = option(2.5, "positive maneuver load factor (25.337 gives 2.57 at 41005 lb; the "
                                     "dissertation uses 2.5)", metavar="N")
    negative_load_factor: float = option(-1.0, "negative maneuver load factor", metavar="N")
    families: str = option("vm", "comma list of stress families constrained (vm, ss_tension, ss_compression, "
                                 "cent_pos, cent_neg; ss and cent: both signs)", metavar="FAMILIES")
    altitude_ft: float = option(GUST["altitude_ft"], "gust altitude (ft)", metavar="FT")
    mach: float = option(GUST["mach"], "gust flight Mach number", metavar="MACH")
    u_ref_fps: float = option(GUST["u_ref_fps"], "reference gust velocity (ft/s EAS) (Table 5.3: 30); 0 = the "
                                                 "25.341(a)(5) table value", metavar="FPS")
    gust_gradient_ft: float = option(GUST["gradient_ft"], "gust gradient H (ft), 30-350", metavar="FT")
    t_final: float = option(GUST["t_final"], "gust simulation time (s)", metavar="S")
    dt: float = option(0.02, "time step (s)", metavar="S")
    gust_start: float = option(0.2, "time the gust front reaches the wing (s)", metavar="S")
    aero: str = option("strip", "gust aerodynamics: strip (precomputed rigid-wing strip-theory loads) or coupled "
                                "(unsteady strip theory on the deforming beam, trimmed 1 g start, clamped root; "
                                "docs/aeroelasticity.md)", choices=AERO_MODELS)
    aero_theory: str | None = option(None, "quasi-steady lift of --aero coupled: strip, lifting-line or vlm (the "
                                           "--aero-theory flag shared by the commands; default vlm with --aero "
                                           "coupled)", choices=AERO_THEORIES, shared=True)
    plunge: str = option("clamped", "coupled gust (--aero coupled): clamped (root clamped, wind-tunnel wing, no "
                                    "alleviation; default) or free (the aircraft free in plunge, its mass the TOGW: "
                                    "gust alleviation by the aircraft's response; '--plunge' alone = free)",
                         choices=PLUNGE_MODES, nargs="?", const="free")
    pitch: str = option("fixed", "coupled gust with --plunge free: fixed (default) or free (the aircraft also free in "
                                 "pitch with a horizontal tail, docs/aeroelasticity.md; needs --pitch-inertia, --cg-x, "
                                 "--tail-arm, --tail-area, --tail-lift-slope; '--pitch' alone = free)",
                        choices=PITCH_MODES, nargs="?", const="free")
    pitch_inertia: float | None = option(None, "aircraft pitch inertia I_yy about its CG (kg m^2)", metavar="KG_M2",
                                         group=PITCH_GROUP)
    cg_x: float | None = option(None, "aircraft CG x (m aft of the body-axes origin)", metavar="M", group=PITCH_GROUP)
    cg_z: float = option(0.0, "aircraft CG z (m above the origin)", metavar="M", group=PITCH_GROUP)
    tail_arm: float | None = option(None, "CG to horizontal-tail aerodynamic centre (m, > 0)", metavar="M",
                                    group=PITCH_GROUP)
    tail_area: float | None = option(None, "horizontal tail area (m^2, > 0)", metavar="M2", group=PITCH_GROUP)
    tail_lift_slope: float | None = option(None, "horizontal tail lift slope a_t (1/rad, compressibility included)",
                                           metavar="PER_RAD", group=PITCH_GROUP)
    downwash_gradient: float | None = option(None, "deps/dalpha at the tail, [0, 1) (unset: 2 a_w / (pi AR), a_w the "
                                                   "strips' wing lift slope)", metavar="D", group=PITCH_GROUP)
    tail_lag: bool = option(False, "downwash lag: first-order lag of time constant x_t / V on the wing angle seen by "
                                   "the tail", group=PITCH_GROUP)
    elevator_chord_ratio: float = option(0.3, "with --pitch free, the coupled maneuvers trimmed by angle of attack and "
                                              "elevator: elevator chord / tail chord, (0, 1), its effectiveness from "
                                              "thin-airfoil theory (the elevator angle of the result)", metavar="E",
                                         group=PITCH_GROUP)
    alleviation: str | None = option(None, "coupled gust: control surfaces, actuators and a feedback law in the march; "
                                           "coupled maneuvers: the surfaces' maneuver_deg_per_g schedule "
                                           "(docs/controls.md)", metavar="FILE.yaml")
    size_gains: bool = option(False, "with --alleviation: the law's gain matrices C and D are design variables with "
                                     "the thicknesses (co-design of structure and load alleviation), with the "
                                     "constraints closed_loop_ks <= 0 and actuator_ks <= 1 (KS over the march of "
                                     "|deflection|/max_deflection_deg and |rate|/max_rate_deg_s per surface; with "
                                     "fixed gains actuator_ks is reported, not constrained)")
    closed_loop_margin: float = option(0.0, "with --size-gains: the decay rate every loaded closed-loop mode must reach, "
                                            "closed_loop_ks = KS(Re lambda + margin) <= 0, i.e. Re lambda <= -margin "
                                            "(1/s, >= 0; 0: stability only; a mode of frequency f gets damping "
                                            "ratio ~ margin / (2 pi f))", metavar="PER_S")
    rolling: bool = option(False, "add the 14 CFR 25.349(a) rolling conditions (V_A, V_C, V_D: the antisymmetric "
                                  "increments of a sudden aileron, the half wing free to roll, 2 s marches at --dt, "
                                  "each wing's combined with the strip loads' maneuver at 2/3 --load-factor; "
                                  "docs/maneuvers.md): the ailerons are the surfaces of --alleviation "
                                  "(its law is not in them); needs --roll-inertia and --maneuvering-speed-eas",
                           group=ROLL_GROUP)
    roll_inertia: float | None = option(None, "--rolling: roll inertia about the body x axis of the aircraft outside "
                                              "both wing halves, I_xx,body (kg m^2, > 0)", metavar="KG_M2",
                                        group=ROLL_GROUP)
    maneuvering_speed_eas: float | None = option(None, "--rolling: design maneuvering speed V_A (m/s EAS, (0, V_C])",
                                                 metavar="M_S", group=ROLL_GROUP)
    kussner: bool = option(False, "lag the gust lift by the Kussner function")
    damping_ratio: float = option(0.0, "structural damping ratio of the gust case's beam (Kelvin-Voigt strain-rate "
                                       "damping, Alg. 6) at --damping-frequency-hz; 0 = undamped; Nastran practice: "
                                       "0.02", metavar="ZETA")
    damping_frequency_hz: float | None = option(None, "frequency at which --damping-ratio holds (Hz); default unset: "
                                                      "the first mode of the initial design", metavar="HZ")
    gust_set: str | None = option(None, "gust set description (.json or .yaml): flight points x gradients x signs",
                                  metavar="FILE", group=GUST_SET_GROUP)
    gust_gradients_ft: tuple[float, ...] | None = option(
        None, "gust gradient distances (ft), 30-350, at the --altitude-ft/--mach flight point", metavar="H", nargs="+",
        group=GUST_SET_GROUP)
    gust_gradient_count: int | None = option(None, "N gradients log-spaced over 30-350 ft (instead of "
                                                   "--gust-gradients-ft)", metavar="N", group=GUST_SET_GROUP)
    gust_sign: str | None = option(None, "up and/or down gusts of the set (default: both with a set, up for the single "
                                         "gust)", choices=GUST_SIGNS, group=GUST_SET_GROUP)
    load_history: str | None = option(None, "gust case from a load time history file (.npz or .csv on the 20 beam "
                                            "nodes, format in docs/loads.md, e.g. exported from a Nastran SOL 146 "
                                            "run) instead of strip theory", metavar="FILE")
    panels: str = panel_options()["panels"]
    stiffener_pitch: float = panel_options()["stiffener_pitch"]  # m
    rib_pitch: float | None = panel_options()["rib_pitch"]  # m; None: the ribs at the case's rib stations
    panel_sizing: str = option("full", "how --panels stiffened is sized: full (every wall and stiffener variable in "
                                       "one optimization) or two-level (fully stressed walls of equivalent "
                                       "thickness with Farrar's minimum-weight panel, then each station's panels "
                                       "sized locally, checked on the full model; docs/panels.md)",
                               choices=PANEL_SIZINGS, group=PANEL_GROUP)


OPTIONS = PegasusOptions
#: the options only the gust cases use (a warning names those changed with --loads maneuver)
GUST_ONLY_OPTIONS = ("altitude_ft", "mach", "u_ref_fps", "gust_gradient_ft", "t_final", "dt", "gust_start",
                     "kussner", "damping_ratio", "damping_frequency_hz", "plunge", "pitch", "pitch_inertia", "cg_x",
                     "cg_z", "tail_arm", "tail_area", "tail_lift_slope", "downwash_gradient", "tail_lag", "alleviation",
                     "size_gains", "closed_loop_margin",
                     "gust_set", "gust_gradients_ft", "gust_gradient_count", "gust_sign")


def add_panel_arguments(p):
    """Add ``--panels``, ``--stiffener-pitch``, ``--rib-pitch`` from :func:`panel_options`.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The case's parser (the options go into the group :data:`PANEL_GROUP`).
    """
    add_option_arguments(p, PegasusOptions, names=PANEL_FIELDS)


def parse_families(text: str) -> tuple:
    """The ``--families`` list (:func:`wingmdao.groups.load_case.parse_families`).

    Parameters
    ----------
    text : str
        Comma-separated family names.

    Returns
    -------
    tuple of str
        The families.
    """
    return _parse(text)


def maneuver_case(name, n_load, geometry, chord, axis_frac, families, pf=PLANFORM, weight_lb=TOGW_LB):
    """Static symmetric maneuver at load factor ``n_load`` on the strip loads (the Schrenk spanload of n W), gravity and inertia relief (n - 1) g.

    Parameters
    ----------
    name : str
        Case name.
    n_load : float
        Load factor n (-).
    geometry : WingGeometry
        The wing geometry.
    chord : numpy.ndarray
        (n,) chords (m).
    axis_frac : numpy.ndarray
        (n,) beam axis as a fraction of the chord (-).
    families : tuple of str
        Stress constraint families.
    pf : Planform, optional
        The planform.
    weight_lb : float, optional
        Aircraft weight (lb).

    Returns
    -------
    LoadCase
        The load case.
    """
    loads = maneuver_line_loads(geometry.node_positions, chord, axis_frac, weight_lb * LB * G0, n_load,
                                semi_span=pf.semi_span, fuselage_half_width=pf.root_rib * pf.semi_span)
    forcing = {
        "force_per_length": loads.force_per_length[None],
        "moment_per_length": loads.moment_per_length[None],
        "gravity": np.array([[0.0, 0.0, -G0]]),
        "frame_acceleration": np.array([[0.0, 0.0, (n_load - 1.0) * G0]]),
    }
    return LoadCase(name, np.zeros(1), forcing, families, f"{n_load:+.2f} g symmetric maneuver")


def maneuver_surfaces(opts, geometry):
    """The control surfaces of ``--alleviation`` that carry a maneuver schedule (``maneuver_deg_per_g``,
    docs/controls.md), or None: with them the trimmed maneuvers hold the surfaces at the scheduled
    deflection (maneuver load alleviation) while the angle of attack trims the lift.

    Parameters
    ----------
    opts : PegasusOptions
        The case options.
    geometry : WingGeometry
        The wing geometry.

    Returns
    -------
    tuple of ControlSurface or None
        The scheduled surfaces.
    """
    if not getattr(opts, "alleviation", None) or opts.aero != "coupled":
        return None
    surfaces, _ = read_alleviation(opts.alleviation)
    if not any(s.maneuver_deg_per_g for s in surfaces):
        return None
    try:
        control_spec(surfaces, geometry.node_positions[:, 1])
    except ValueError as exc:
        raise ValueError(f"--alleviation {opts.alleviation}: {exc}") from None
    return surfaces


def coupled_maneuver_case(name, n_load, opts, geometry, chord, axis_frac, families, weight_lb=TOGW_LB,
                          surfaces=None):
    """Trimmed static aeroelastic maneuver (``--aero coupled``): the aircraft angle of attack solved
    so that both half-wings lift n W on the deforming wing (strip theory, quasi-steady), at the
    --altitude-ft / --mach flight point, inertia relief (n - 1) g as in :func:`maneuver_case`.
    ``surfaces`` (:class:`~wingmdao.aero.controls.ControlSurface`, None: none) are held at their
    maneuver schedule ``maneuver_deg_per_g (n - 1)`` (:func:`~wingmdao.aero.controls.maneuver_commands`).

    Parameters
    ----------
    name : str
        Case name.
    n_load : float
        Load factor n (-).
    opts : PegasusOptions
        The case options.
    geometry : WingGeometry
        The wing geometry.
    chord : numpy.ndarray
        (n,) chords (m).
    axis_frac : numpy.ndarray
        (n,) beam axis as a fraction of the chord (-).
    families : tuple of str
        Stress constraint families.
    weight_lb : float, optional
        Aircraft weight (lb).
    surfaces : sequence of ControlSurface or None, optional
        Surfaces held at their maneuver schedule.

    Returns
    -------
    LoadCase
        The load case.
    """
    alt = float(altitude_ft_to_m(opts.altitude_ft))
    forcing = {"gravity": np.array([[0.0, 0.0, -G0]]),
               "frame_acceleration": np.array([[0.0, 0.0, (n_load - 1.0) * G0]]),
               "trim_active": np.ones(1)}
    pitch, what = {}, ""
    if getattr(opts, "pitch", "fixed") == "free":  # trimmed with the tail: lift n W, zero pitching moment
        # the body's weight too is n g (its moment about the origin): gravity n g0 in place of the frame's
        # (n - 1) g0, the same loads on the beam
        forcing = {"gravity": np.array([[0.0, 0.0, -n_load * G0]]), "trim_active": np.ones(1),
                   "tail_gust_velocity": np.zeros(1)}
        pitch = dict(plunge=True, aircraft_mass=weight_lb * LB,
                     **pitch_aero_options(opts, geometry, chord, axis_frac, float(opts.mach)), )
        pitch["tail_lag"] = False  # static: the lagged downwash equals the wing's angle
        pitch["elevator_effectiveness"] = elevator_effectiveness(opts.elevator_chord_ratio)
        what = ", trimmed with the tail (angle of attack and elevator)"
    controls = {}
    if surfaces:
        controls = dict(controls=control_spec(surfaces, geometry.node_positions[:, 1]))
        forcing["surface_command"] = maneuver_commands(surfaces, n_load)[None, :]
        what += ", " + ", ".join(f"{s.name} {np.degrees(u):+.2f} deg"
                                for s, u in zip(surfaces, forcing["surface_command"][0]))
    aero = CoupledAero(chord=np.asarray(chord, dtype=float), ref_point=np.asarray(axis_frac, dtype=float),
                       airspeed=float(mach_to_tas(opts.mach, alt)), density=float(density(alt)), mach=float(opts.mach),
                       trim=True, trim_lift=n_load * weight_lb * LB * G0, aero_theory=_steady_theory(opts.aero_theory),
                       node_positions=np.asarray(geometry.node_positions, dtype=float), **controls, **pitch)
    return LoadCase(name, np.zeros(1), forcing, families, f"{n_load:+.2f} g trimmed aeroelastic maneuver{what}",
                    aero=aero)


def _steady_theory(theory: str) -> str:
    """The quasi-steady theory of the beam's static states: the doublet lattice's k = 0 limit is the VLM."""
    return "vlm" if theory == "dlm" else theory


def modal_dlm_gust(geometry, chord, axis_frac, time, *, u_tas, airspeed, density, mach, gust_start, gradient_m,
                   aircraft_mass=None, controls=None):
    """:class:`wingmdao.aero.modal_design.ModalGust` of a 1 - cos gust on the modal doublet-lattice
    wing (:func:`wingmdao.aero.modal_design.cosine_gust`): basis the clamped jig modes of the
    sizing's initial design (every wall 10 mm, :func:`beam_params`), the design's mass and
    stiffness projected on it in the sizing; with ``aircraft_mass`` (kg) free in plunge, the plunge
    mode first (:func:`wingmdao.aero.modal_free.free_cosine_gust`).

    Parameters
    ----------
    geometry : WingGeometry
        The wing geometry.
    chord : numpy.ndarray
        (n,) chords (m).
    axis_frac : numpy.ndarray
        (n,) beam axis as a fraction of the chord (-).
    time : numpy.ndarray
        (nt,) time grid (s).
    u_tas : float
        Design gust velocity (m/s TAS).
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    mach : float
        Mach number (-).
    gust_start : float
        Time the gust front reaches the wing (s).
    gradient_m : float
        Gust gradient H (m).
    aircraft_mass : float or None, optional
        Aircraft mass (kg) of a free-plunge gust; None: root clamped.
    controls : ControlSpec or None, optional
        Control surfaces (flap modes of the lattice) and law; None: none.

    Returns
    -------
    ModalGust
        The gust.
    """
    params = beam_params(geometry.num_nodes)
    if not np.allclose(params["node_positions"], geometry.node_positions):
        raise ValueError("--aero-theory dlm: the sized wing's nodes differ from the PEGASUS beam's (beam_params)")
    kw = dict(u_tas=u_tas, airspeed=airspeed, density=density, mach=mach, gust_start=gust_start, gradient_m=gradient_m,
              controls=controls)
    if aircraft_mass is not None:
        return free_cosine_gust(params, chord, axis_frac, time, aircraft_mass=aircraft_mass, **kw)
    return cosine_gust(params, chord, axis_frac, time, **kw)


def gust_case(opts, geometry, chord, axis_frac, families, pf=PLANFORM, weight_lb=TOGW_LB):
    """The ``--loads gust`` case: the Table 5.3 (or ``--u-ref-fps``) 1 - cos gust at the ``--altitude-ft``/``--mach`` point, or a ``--load-history`` file; flight inputs checked first.

    Parameters
    ----------
    opts : PegasusOptions
        The case options.
    geometry : WingGeometry
        The wing geometry.
    chord : numpy.ndarray
        (n,) chords (m).
    axis_frac : numpy.ndarray
        (n,) beam axis as a fraction of the chord (-).
    families : tuple of str
        Stress constraint families.
    pf : Planform, optional
        The planform.
    weight_lb : float, optional
        Aircraft weight (lb).

    Returns
    -------
    LoadCase
        The load case.
    """
    if not 0.0 <= opts.altitude_ft <= 60000.0:
        raise ValueError(f"--altitude-ft = {opts.altitude_ft} ft; allowed range [0, 60000] ft (the 25.341 table)")
    if not 30.0 <= opts.gust_gradient_ft <= 350.0:
        raise ValueError(f"--gust-gradient-ft = {opts.gust_gradient_ft} ft; allowed range [30, 350] ft "
                         "(14 CFR 25.341(a)(3))")
    if not (0.0 < opts.mach < 1.0):
        raise ValueError(f"--mach = {opts.mach}; allowed range (0, 1)")
    if opts.load_history:
        return file_case(opts.load_history, geometry, families)
    _check_time_grid(opts, geometry.num_nodes)
    alt = altitude_ft_to_m(opts.altitude_ft)
    if opts.u_ref_fps > 0:
        u_ds = opts.u_ref_fps * FT * (opts.gust_gradient_ft / 350.0) ** (1.0 / 6.0)
    else:
        u_ds = design_gust_velocity_eas(opts.gust_gradient_ft, opts.altitude_ft, 1.0)
    direction = -1 if opts.gust_sign == "down" else 1
    return gust_history_case("gust", opts, geometry, chord, axis_frac, families, gradient_ft=opts.gust_gradient_ft,
                             u_ds_eas=u_ds, airspeed_tas=float(mach_to_tas(opts.mach, alt)), altitude_m=float(alt),
                             direction=direction, weight_lb=weight_lb, pf=pf,
                             description=f"1-cos gust U_ds = {u_ds / FT:.1f} ft/s EAS, H = {opts.gust_gradient_ft:g} ft"
                                         + (" (down)" if direction < 0 else ""))


def _check_closed_loop_margin(opts):
    """Refuse a ``--closed-loop-margin`` that is not finite and >= 0, or given without ``--size-gains``.

    Parameters
    ----------
    opts : PegasusOptions
        The case options.
    """
    margin = opts.closed_loop_margin
    if not (np.isfinite(margin) and margin >= 0.0):
        raise ValueError(f"--closed-loop-margin = {margin} 1/s; allowed range [0, inf) 1/s "
                         "(the decay rate -Re lambda every closed-loop mode must reach)")
    if margin > 0.0 and not opts.size_gains:
        raise ValueError(f"--closed-loop-margin = {margin} 1/s applies with --size-gains (the constraint "
                         "closed_loop_ks of the sized law); add --size-gains or drop the margin")


def _check_time_grid(opts, num_nodes):
    """Time grid, reference gust velocity and gust start of the dynamic cases, before any solve."""
    if not (np.isfinite(opts.t_final) and opts.t_final > 0 and 0 < opts.dt <= opts.t_final / 10):
        raise ValueError(f"--t-final ({opts.t_final} s) and --dt ({opts.dt} s): need finite 0 < 10 dt <= t_final")

    check_step_count(opts.t_final, opts.dt, num_nodes)
    if not (np.isfinite(opts.u_ref_fps) and opts.u_ref_fps >= 0):
        raise ValueError(f"--u-ref-fps = {opts.u_ref_fps} ft/s; allowed range [0, inf) ft/s "
                         "(0 = the 25.341(a)(5) table value)")
    if not (np.isfinite(opts.gust_start) and 0.0 <= opts.gust_start < opts.t_final):
        raise ValueError(f"--gust-start = {opts.gust_start} s; allowed range [0, --t-final = {opts.t_final}) s")


def gust_history_case(name, opts, geometry, chord, axis_frac, families, *, gradient_ft, u_ds_eas, airspeed_tas,
                      altitude_m, direction, weight_lb, pf, description):
    """One strip-theory 1 - cos gust load case on top of 1 g level flight at ``weight_lb``.

    Parameters
    ----------
    name : str
        Case name.
    opts : PegasusOptions
        The case options.
    geometry : WingGeometry
        The wing geometry.
    chord : numpy.ndarray
        (n,) chords (m).
    axis_frac : numpy.ndarray
        (n,) beam axis as a fraction of the chord (-).
    families : tuple of str
        Stress constraint families.
    gradient_ft : float
        Gust gradient H (ft).
    u_ds_eas : float
        Design gust velocity (m/s EAS).
    airspeed_tas : float
        True airspeed (m/s).
    altitude_m : float
        Altitude (m).
    direction : {1, -1}
        Gust up or down.
    weight_lb : float
        Aircraft weight (lb).
    pf : Planform
        The planform.
    description : str
        Case description.

    Returns
    -------
    LoadCase
        The load case.
    """
    time = np.arange(0.0, opts.t_final + 0.5 * opts.dt, opts.dt)
    if opts.aero == "coupled":
        return coupled_gust_case(name, opts, geometry, chord, axis_frac, families, time, gradient_ft=gradient_ft,
                                 u_ds_eas=u_ds_eas, airspeed_tas=airspeed_tas, altitude_m=altitude_m,
                                 direction=direction, weight_lb=weight_lb, description=description, pf=pf)
    steady = maneuver_line_loads(geometry.node_positions, chord, axis_frac, weight_lb * LB * G0, 1.0,
                                 semi_span=pf.semi_span, fuselage_half_width=pf.root_rib * pf.semi_span)
    hist = gust_line_loads(geometry.node_positions, chord, axis_frac, time,
                           gust_gradient_m=gradient_ft * FT, u_ds_eas=u_ds_eas,
                           airspeed_tas=airspeed_tas, altitude_m=altitude_m,
                           kussner=opts.kussner, gust_start_time=opts.gust_start, steady=steady,
                           direction=direction, fuselage_half_width=pf.root_rib * pf.semi_span)
    forcing = {"force_per_length": hist.force_per_length, "moment_per_length": hist.moment_per_length,
               "gravity": np.array([0.0, 0.0, -G0])}
    return LoadCase(name, time, forcing, families, description)


def gust_set_of(opts):
    """The 25.341(a) gust set the options ask for, or None for the single gust of Table 5.3.

    ``--gust-set FILE`` (defaults: :data:`GUST_SET_DEFAULTS`), or ``--gust-gradients-ft`` /
    ``--gust-gradient-count`` at the ``--altitude-ft``, ``--mach`` flight point (U_ref from
    ``--u-ref-fps``, 0 = the 25.341(a)(5) table) with ``--gust-sign`` (default both).

    Parameters
    ----------
    opts : PegasusOptions
        The case options.

    Returns
    -------
    GustSet or None
        The set.
    """
    path = opts.gust_set
    grads = opts.gust_gradients_ft
    count = opts.gust_gradient_count
    sign = opts.gust_sign
    if sum(x is not None for x in (path, grads, count)) > 1:
        raise ValueError("give one of --gust-set, --gust-gradients-ft and --gust-gradient-count")
    if path is not None:
        gset = read_gust_set(path, defaults=GUST_SET_DEFAULTS)
        if sign is not None:
            gset = replace(gset, signs=parse_signs(sign))
        return gset
    if grads is None and count is None:
        return None
    if grads is not None and len(grads) == 0:
        raise ValueError("--gust-gradients-ft: empty; give at least one gradient distance in [30, 350] ft")
    fp = FlightPoint(altitude_ft=float(opts.altitude_ft), mach=float(opts.mach),
                     u_ref_fps=float(opts.u_ref_fps) if opts.u_ref_fps > 0 else None)
    h = grads if grads is not None else log_spaced_gradients_ft(count)
    return GustSet((fp,), h, parse_signs(sign or "both"), **GUST_SET_DEFAULTS)


def pitch_aero_options(opts, geometry, chord, axis_frac, mach, pf=PLANFORM) -> dict:
    """The free-pitch fields of :class:`~wingmdao.aero.coupled.CoupledAero` from ``--pitch free``'s
    options: CG, pitch inertia, tail arm, area and slope, ``tail_lag``, and deps/dalpha (given, or
    2 a_w / (pi AR), Etkin & Reid 1996 / Nelson 1998, a_w the wing slope of the --aero-theory).

    Parameters
    ----------
    opts : PegasusOptions
        The case options (``--pitch free`` checked).
    geometry : BeamGeometry
        The wing's beam geometry (``node_positions``).
    chord, axis_frac : array_like
        (n,) chord (m) and beam axis (fraction of the chord) per node.
    mach : float
        Mach number of the flight point.
    pf : Planform
        The planform (area, semi-span).

    Returns
    -------
    dict
        Keyword arguments of CoupledAero.
    """
    deps = opts.downwash_gradient
    if deps is None:  # Etkin & Reid (1996) / Nelson (1998): deps/dalpha = 2 a_w / (pi AR)
        area = pf.area_ft2 * FT ** 2  # a_w: the wing slope of the --aero-theory, 2 int c a dy / S (as wingmdao gust)
        theory = three_dimensional_parameters(opts.aero_theory, geometry.node_positions, chord, axis_frac, mach)
        if "lift_influence" in theory:  # the lattice: lift per unit span of a unit angle at every station
            a_c = theory["lift_influence"].sum(axis=1)
        else:  # strips (2 pi) or the lifting line's slopes, with Prandtl-Glauert
            a_c = (theory.get("lift_slope", 2 * np.pi) / np.sqrt(1 - mach ** 2)) * np.asarray(chord, dtype=float)
        ds = np.linalg.norm(np.diff(geometry.node_positions, axis=0), axis=1)
        a_w = 2 * np.sum(0.5 * (a_c[1:] + a_c[:-1]) * ds) / area
        deps = 2 * a_w / (np.pi * (2 * pf.semi_span) ** 2 / area)
    return dict(pitch=True, tail_lag=bool(opts.tail_lag), aircraft_cg=(float(opts.cg_x), float(opts.cg_z)),
                aircraft_pitch_inertia=float(opts.pitch_inertia), tail_arm=float(opts.tail_arm),
                tail_area=float(opts.tail_area), tail_lift_slope=float(opts.tail_lift_slope),
                downwash_gradient=float(deps))


def coupled_gust_case(name, opts, geometry, chord, axis_frac, families, time, *, gradient_ft, u_ds_eas,
                      airspeed_tas, altitude_m, direction, weight_lb, description, pf=PLANFORM):
    """The 1 - cos gust on the aeroelastic beam (``--aero coupled``): unsteady strip theory on the
    deforming wing (wingmdao.aero), root clamped or free plunge, the march starting from the trimmed 1 g state
    (aircraft angle of attack solved at t = 0 so that both half-wings lift W, gravity on), the gust
    velocity per station with its penetration delay from the most forward leading edge.
    ``--plunge free``: the aircraft (``weight_lb``) free in plunge, its mass the case input
    ``aircraft_mass``; clamped root otherwise. ``--pitch free`` (with free plunge): also free in pitch
    with a horizontal tail (wingmdao.aero.pitch), the gust reaching the tail x_t / V after the first
    leading edge, deps/dalpha by default 2 a_w / (pi AR).

    Parameters
    ----------
    name : str
        Case name.
    opts : PegasusOptions
        The case options.
    geometry : WingGeometry
        The wing geometry.
    chord : numpy.ndarray
        (n,) chords (m).
    axis_frac : numpy.ndarray
        (n,) beam axis as a fraction of the chord (-).
    families : tuple of str
        Stress constraint families.
    time : numpy.ndarray
        (nt,) time grid (s).
    gradient_ft : float
        Gust gradient H (ft).
    u_ds_eas : float
        Design gust velocity (m/s EAS).
    airspeed_tas : float
        True airspeed (m/s).
    altitude_m : float
        Altitude (m).
    direction : {1, -1}
        Gust up or down.
    weight_lb : float
        Aircraft weight (lb).
    description : str
        Case description.
    pf : Planform, optional
        The planform.

    Returns
    -------
    LoadCase
        The load case.
    """
    rho, rho0 = float(density(altitude_m)), float(density(0.0))
    V = float(airspeed_tas)
    mach = V / float(speed_of_sound(altitude_m))  # the flight point's (a gust set may have several)
    H = gradient_ft * FT
    u_tas = direction * u_ds_eas * np.sqrt(rho0 / rho)
    x_le = geometry.node_positions[:, 0] - np.asarray(axis_frac) * np.asarray(chord)

    def profile(tau):
        d = V * (tau - opts.gust_start)
        return np.where((d >= 0) & (d <= 2 * H), 0.5 * u_tas * (1 - np.cos(np.pi * d / H)), 0.0)

    trim = np.zeros(time.size)
    trim[0] = 1.0
    forcing = {"gravity": np.array([0.0, 0.0, -G0]), "gust_velocity": station_gust_history(time, x_le, V, profile),
               "trim_active": trim}
    free = opts.plunge == "free"
    pitch = {}
    if getattr(opts, "pitch", "fixed") == "free":  # the tail meets the gust x_t / V after the first leading edge
        x_t = opts.cg_x + opts.tail_arm
        forcing["tail_gust_velocity"] = profile(time - (x_t - x_le.min()) / V)
        pitch = pitch_aero_options(opts, geometry, chord, axis_frac, mach, pf)
    controls = {}
    if getattr(opts, "size_gains", False) and not getattr(opts, "alleviation", None):
        raise ValueError("--size-gains needs --alleviation FILE.yaml (the law whose gains are sized)")
    margin = float(getattr(opts, "closed_loop_margin", 0.0))
    if getattr(opts, "alleviation", None):  # control surfaces and a feedback law (docs/controls.md)
        surfaces, law = read_alleviation(opts.alleviation)
        if law is not None and "load_factor" in law.outputs and not free:
            raise ValueError(f"--alleviation {opts.alleviation}: output load_factor needs free plunge (--plunge free)")
        if law is not None and "pitch_rate" in law.outputs and not pitch:
            raise ValueError(f"--alleviation {opts.alleviation}: output pitch_rate needs --pitch free")
        try:
            spec = control_spec(surfaces, geometry.node_positions[:, 1], law)
        except ValueError as exc:
            raise ValueError(f"--alleviation {opts.alleviation}: {exc}") from None
        if getattr(opts, "size_gains", False) and law is None:
            raise ValueError(f"--size-gains: --alleviation {opts.alleviation} has no law (no gains to size)")
        limits = tuple((float(np.radians(s.max_deflection_deg)), float(np.radians(s.max_rate_deg_s))) for s in surfaces)
        controls = dict(controls=spec, control_law=law, gain_design=bool(getattr(opts, "size_gains", False)),
                        closed_loop_margin=margin, surface_limits=limits if law is not None else None)
    modal = None
    if opts.aero_theory == "dlm":  # the trimmed 1 g state on the VLM beam + the gust on the modal doublet lattice
        if pitch:
            raise ValueError("--aero-theory dlm: the sized gust is clamped or free in plunge (the modal basis has "
                             "no pitch mode in a sizing); drop --pitch free")
        modal = modal_dlm_gust(geometry, chord, axis_frac, time, u_tas=u_tas, airspeed=V, density=rho, mach=mach,
                               gust_start=opts.gust_start, gradient_m=H, aircraft_mass=weight_lb * LB if free else None,
                               controls=controls.get("controls"))
    aero = CoupledAero(chord=np.asarray(chord, dtype=float), ref_point=np.asarray(axis_frac, dtype=float),
                       airspeed=V, density=rho, mach=mach, trim=True, trim_lift=weight_lb * LB * G0,
                       plunge=free, aircraft_mass=weight_lb * LB, aero_theory=_steady_theory(opts.aero_theory),
                       node_positions=np.asarray(geometry.node_positions, dtype=float), **pitch, **controls)
    mode = ("free plunge + pitch" if pitch else "free plunge") if free else "clamped root"
    if modal is not None:
        mode += f"; trimmed 1 g on the VLM beam + the gust on the modal doublet lattice ({modal.wing.modes.count} modes)"
    return LoadCase(name, time, forcing, families, description + f" (coupled aeroelastic, {mode})", aero=aero,
                    modal_dlm=modal)


def gust_set_cases(gset, opts, geometry, chord, axis_frac, families, pf=PLANFORM, weight_lb=TOGW_LB):
    """One load case per gust of ``gset`` (strip theory on top of 1 g at the flight point's weight).

    Parameters
    ----------
    gset : GustSet
        The gust set.
    opts : PegasusOptions
        The case options.
    geometry : WingGeometry
        The wing geometry.
    chord : numpy.ndarray
        (n,) chords (m).
    axis_frac : numpy.ndarray
        (n,) beam axis as a fraction of the chord (-).
    families : tuple of str
        Stress constraint families.
    pf : Planform, optional
        The planform.
    weight_lb : float, optional
        Aircraft weight (lb).

    Returns
    -------
    list of LoadCase
        One case per gust.
    """
    if opts.load_history:
        raise ValueError("--load-history and a gust set exclude each other")
    _check_time_grid(opts, geometry.num_nodes)
    cases = []
    for g in gset.gusts():
        fp = g.flight_point
        cases.append(gust_history_case(g.name, opts, geometry, chord, axis_frac, families, gradient_ft=g.gradient_ft,
                                       u_ds_eas=g.u_ds_eas, airspeed_tas=fp.airspeed_tas(), altitude_m=fp.altitude_m,
                                       direction=g.sign, weight_lb=fp.weight_lb or weight_lb, pf=pf,
                                       description=g.describe()))
    return cases


def file_case(path, geometry, families):
    """Gust load case from a load-history file (time, force/moment per length on the beam nodes).

    Parameters
    ----------
    path : str
        Load-history file (.npz or .csv).
    geometry : WingGeometry
        The wing geometry.
    families : tuple of str
        Stress constraint families.

    Returns
    -------
    LoadCase
        The load case.
    """
    hist = read_load_history(path)
    if hist.num_nodes != geometry.num_nodes:
        raise ValueError(f"--load-history {path}: {hist.num_nodes} nodes, the beam has {geometry.num_nodes}")
    forcing = dict(hist.as_forcing(), gravity=np.array([0.0, 0.0, -G0]))
    return LoadCase("gust", hist.time, forcing, families, f"load history from {path}")


def build(options: PegasusOptions | None = None, **overrides) -> CaseSetup:
    """The PEGASUS geometry, load cases, material and Table 5.1 bounds from a :class:`PegasusOptions`
    and/or keyword options (``build(loads="all", load_factor=2.5)``).

    Parameters
    ----------
    options : PegasusOptions or None, optional
        The case options; None for the defaults.
    **overrides
        Option values by field name.

    Returns
    -------
    CaseSetup
        Geometry, load cases, material and bounds.
    """
    return build_wing(case_options(PegasusOptions, options, **overrides))


def _flag_text(name, value) -> str:
    """``--flag value`` as typed (a switch alone, a list space-separated)."""
    flag = f"--{name.replace('_', '-')}"
    if isinstance(value, bool):
        return flag
    if isinstance(value, (tuple, list)):
        return f"{flag} {' '.join(f'{v:g}' for v in value)}"
    return f"{flag} {value:g}" if isinstance(value, float) else f"{flag} {value}"


def build_wing(opts: PegasusOptions, pf=PLANFORM, engines=ENGINES, weight_lb=TOGW_LB) -> CaseSetup:
    """:func:`build` for any trapezoidal wing ``pf`` with point masses ``engines`` ((kg, y m) pairs)
    at take-off weight ``weight_lb`` (the CRM case reuses it).

    Parameters
    ----------
    opts : PegasusOptions
        The case options.
    pf : Planform, optional
        The planform.
    engines : sequence of tuple, optional
        (mass kg, y m) of each engine.
    weight_lb : float, optional
        Aircraft weight (lb).

    Returns
    -------
    CaseSetup
        Geometry, load cases, material and bounds.
    """
    families = parse_families(opts.families)
    gset = gust_set_of(opts)
    loads = opts.loads or ("all" if gset is not None else "maneuver")
    if opts.load_history and loads == "maneuver":
        raise ValueError(f"--load-history {opts.load_history} replaces the gust case; it does not apply to "
                         "--loads maneuver (use --loads gust or all)")
    if not np.isfinite(opts.load_factor) or opts.load_factor <= 0:
        raise ValueError(f"--load-factor = {opts.load_factor}; allowed range (0, inf)")
    if not (np.isfinite(opts.negative_load_factor) and opts.negative_load_factor < 0):
        raise ValueError(f"--negative-load-factor = {opts.negative_load_factor}; allowed range (-inf, 0)")
    if opts.aero_theory not in (None, "strip") and opts.aero != "coupled":
        raise ValueError(f"--aero-theory {opts.aero_theory} applies to --aero coupled (the precomputed --aero strip "
                         "loads use 2 pi)")
    opts = replace(opts, aero_theory=resolve_aero_theory(opts.aero_theory, opts.aero))
    if opts.plunge == "free" and opts.aero != "coupled":
        raise ValueError(f"--plunge free needs --aero coupled (the strip-theory loads are precomputed on a "
                         f"clamped wing), got --aero {opts.aero}")
    if opts.pitch == "free":
        if opts.aero != "coupled" or opts.plunge != "free":
            raise ValueError("--pitch free needs --aero coupled and --plunge free (the aircraft free in plunge and "
                             f"pitch), got --aero {opts.aero} --plunge {opts.plunge}")
        missing = [f for f in PITCH_REQUIRED if getattr(opts, f) is None]
        if missing:
            raise ValueError("--pitch free needs " + ", ".join("--" + f.replace("_", "-") for f in missing)
                             + " (the case has no published tail or pitch inertia)")
        for f in ("cg_x", "cg_z"):
            if not np.isfinite(getattr(opts, f)):
                raise ValueError(f"--{f.replace('_', '-')} = {getattr(opts, f)} m; allowed a finite position (m)")

        if not (np.isfinite(opts.elevator_chord_ratio) and 0.0 < opts.elevator_chord_ratio < 1.0):
            raise ValueError(f"--elevator-chord-ratio = {opts.elevator_chord_ratio}; allowed range (0, 1)")
        check_pitch_inputs(aircraft_pitch_inertia=opts.pitch_inertia, tail_arm=opts.tail_arm, tail_area=opts.tail_area,
                           tail_lift_slope=opts.tail_lift_slope,
                           **({} if opts.downwash_gradient is None else {"downwash_gradient": opts.downwash_gradient}))
    zeta = opts.damping_ratio
    if not 0.0 <= zeta < 1.0:
        raise ValueError(f"--damping-ratio = {zeta}; allowed range [0, 1)")
    _check_closed_loop_margin(opts)
    geometry, chord, axis_frac = wing_geometry(pf, engines)
    sizing = SizingOptions(lower={w: MIN_GAUGE for w in WALL_VARS}, upper={w: 0.05 for w in WALL_VARS},
                           initial={w: 0.01 for w in WALL_VARS}, rho_ks=100.0, presize=4)
    notes = ["airfoil NACA 43018 -> 43013 (assumed, ATR 42 class)",
             "engines as point masses: 600 kg at 35 % semi-span, 150 kg at the tip (assumed)"]
    if loads == "maneuver":  # given or the default: the gust options do nothing
        default = PegasusOptions()
        # the trimmed maneuvers' flight point and maneuver schedule of the surfaces
        used = ("altitude_ft", "mach", "alleviation") if opts.aero == "coupled" else ()
        used += ("alleviation", "dt") if opts.rolling else ()
        if opts.pitch == "free":  # the maneuvers trimmed with the tail (elevator trim)
            used += ("plunge", "pitch", "pitch_inertia", "cg_x", "cg_z", "tail_arm", "tail_area", "tail_lift_slope",
                     "downwash_gradient", "elevator_chord_ratio")
        ignored = [_flag_text(k, getattr(opts, k)) for k in GUST_ONLY_OPTIONS
                   if k not in used and getattr(opts, k) != getattr(default, k)]
        if ignored:
            why = "gust options" if opts.loads else "the default without a gust set; gust options"
            notes.append(f"warning: ignored with --loads maneuver ({why}): {', '.join(ignored)}")
    elif gset is None and opts.gust_sign is not None:
        notes.append(f"warning: ignored without a gust set (--gust-set, --gust-gradients-ft or "
                     f"--gust-gradient-count): --gust-sign {opts.gust_sign}")
    cases = []
    if loads in ("gust", "all"):
        gusts = ([gust_case(opts, geometry, chord, axis_frac, families, pf, weight_lb)] if gset is None
                 else gust_set_cases(gset, opts, geometry, chord, axis_frac, families, pf, weight_lb))
        if gset is not None:
            notes.append(f"25.341(a) gust set: {len(gset)} gusts ({len(gset.flight_points)} flight point(s) x "
                         f"{len(gset.gradients_ft)} gradient(s) x {len(gset.signs)} sign(s))")
        if zeta > 0.0:
            damping, note = gust_damping(zeta, opts.damping_frequency_hz, geometry, sizing)
            for case in gusts:
                case.damping = damping
            notes.append(note)
        cases.extend(gusts)
    if loads in ("maneuver", "all"):
        if opts.aero == "coupled":
            mla = maneuver_surfaces(opts, geometry)
            cases.insert(0, coupled_maneuver_case("maneuver_pos", opts.load_factor, opts, geometry, chord, axis_frac,
                                                  families, weight_lb, surfaces=mla))
            cases.insert(1, coupled_maneuver_case("maneuver_neg", opts.negative_load_factor, opts, geometry, chord,
                                                  axis_frac, families, weight_lb, surfaces=mla))
        else:
            cases.insert(0, maneuver_case("maneuver_pos", opts.load_factor, geometry, chord, axis_frac, families, pf,
                                          weight_lb))
            cases.insert(1, maneuver_case("maneuver_neg", opts.negative_load_factor, geometry, chord, axis_frac,
                                          families, pf, weight_lb))
    if opts.rolling:
        if pf is not PLANFORM:
            raise ValueError("--rolling: the PEGASUS case only (its V_C and V_D)")
        cases.extend(rolling_cases(opts, geometry, chord, axis_frac, families, sizing, weight_lb=weight_lb))
        notes.append("25.349(a) rolling conditions, the increments of each wing with the strip loads' symmetric "
                     f"maneuver at 2/3 n = {2.0 * opts.load_factor / 3.0:.3f}: "
                     + ", ".join(c.description for c in cases[-3:]))
    else:
        given = [f for f in ("roll_inertia", "maneuvering_speed_eas") if getattr(opts, f) is not None]
        if given:
            raise ValueError(f"--{given[0].replace('_', '-')} is a --rolling option")
    setup = CaseSetup(geometry, cases, ALUMINIUM, sizing, notes=notes)
    if opts.panels == "stiffened":
        stiffen(setup, pf, opts.stiffener_pitch, opts.rib_pitch)
        setup.panel_sizing = opts.panel_sizing
    elif opts.panel_sizing != "full":
        raise ValueError(f"--panel-sizing {opts.panel_sizing} needs --panels stiffened (got --panels {opts.panels})")
    elif opts.rib_pitch is not None or opts.stiffener_pitch != PegasusOptions.stiffener_pitch:
        setup.notes.append("warning: ignored without --panels stiffened: "
                           + ", ".join(f for f, v in (("--rib-pitch", opts.rib_pitch is not None),
                                                       ("--stiffener-pitch", opts.stiffener_pitch
                                                        != PegasusOptions.stiffener_pitch)) if v))
    return setup


#: stiffener bounds and start (m): web height and thickness (Niu, Airframe Structural Design,
#: Ch. 14: the web aspect rule 5 <= h/ts <= 30 within these)
STIFFENER_BOUNDS = {"h": (0.015, 0.10, 0.04), "t": (1e-3, 8e-3, 3e-3)}
RIB_THICKNESS = 2e-3  # m (assumed)


def rib_positions(pf=PLANFORM, rib_pitch: float | None = None) -> tuple:
    """Spanwise rib positions (m): a centreline rib (assumed: it closes the centre-box bay) and
    the planform's ribs at stations 1..num_ribs, or with ``rib_pitch`` equal bays of about that
    length from the root rib to the tip rib. A centre-box bay (centreline to root rib) longer
    than two rib pitches (the CRM's 2.95 m) is split into equal bays of about the pitch by
    intermediate ribs (assumed; :func:`centre_box_ribs`).

    Parameters
    ----------
    pf : Planform, optional
        The planform.
    rib_pitch : float or None, optional
        Rib pitch (m); None for the planform's ribs.

    Returns
    -------
    tuple of float
        Rib positions (m).
    """
    ribs = pf.station_y()
    if rib_pitch is None:
        return centre_box_ribs(tuple(float(r) for r in ribs), float(ribs[2] - ribs[1]))
    span = ribs[-1] - ribs[1]
    if not (np.isfinite(rib_pitch) and rib_pitch > 0):
        raise ValueError(f"--rib-pitch = {rib_pitch} m; allowed range (0, {span:.4g}] m")
    if rib_pitch > span:
        raise ValueError(f"--rib-pitch = {rib_pitch} m; allowed range (0, {span:.4g}] m (root to tip rib)")
    bays = max(1, int(round(span / rib_pitch)))
    return centre_box_ribs((0.0, *(float(r) for r in np.linspace(ribs[1], ribs[-1], bays + 1))), float(rib_pitch))


def centre_box_ribs(ribs: tuple, pitch: float) -> tuple:
    """``ribs`` with the centre-box bay (``ribs[0]`` to ``ribs[1]``) split into round(bay/pitch)
    equal bays when it is longer than two pitches; otherwise ``ribs`` unchanged. Without them the
    centre box's skin panels would be one bay long (2.95 m on the CRM) and their column buckling
    would size the whole inboard wing through the adjacency rules.

    Parameters
    ----------
    ribs : tuple of float
        Rib positions (m).
    pitch : float
        Rib pitch (m).

    Returns
    -------
    tuple of float
        Rib positions (m).
    """
    bay = ribs[1] - ribs[0]
    if bay <= 2.0 * pitch:
        return ribs
    bays = int(round(bay / pitch))
    return (*(float(r) for r in np.linspace(ribs[0], ribs[1], bays + 1)[:-1]), *ribs[1:])


def stiffen(setup, pf=PLANFORM, pitch: float = 0.15, rib_pitch: float | None = None):
    """Make ``setup`` a stiffened sizing (in place): section ``"stiffened"``, blade stiffeners at
    ``pitch`` on both skins, ribs at the planform's rib stations and a centreline rib (assumed:
    it closes the centre-box bay and is counted whole in the half-wing's mass), all
    :data:`RIB_THICKNESS` thick, safety factor 1.5 on buckling, the stiffener bounds of
    :data:`STIFFENER_BOUNDS`.

    Parameters
    ----------
    setup : CaseSetup
        The sizing set-up, changed in place.
    pf : Planform, optional
        The planform.
    pitch : float, optional
        Stiffener pitch (m).
    rib_pitch : float or None, optional
        Rib pitch (m); None for the planform's ribs.
    """
    if not (np.isfinite(pitch) and pitch > 0):
        raise ValueError(f"--stiffener-pitch = {pitch} m; allowed range (0, inf) m")
    ribs = rib_positions(pf, rib_pitch)
    setup.panels = PanelLayout(rib_positions=ribs, stiffener_pitch=float(pitch), shape="blade",
                               safety_factor=1.5, rib_thickness=RIB_THICKNESS)
    setup.section = "stiffened"
    setup.options.maxiter = max(setup.options.maxiter, 400)   # 8 variables per station: SLSQP needs ~260
    for name in STIFFENER_VARS:
        lo, up, start = STIFFENER_BOUNDS[name[0]]
        setup.options.lower[name], setup.options.upper[name], setup.options.initial[name] = lo, up, start
    setup.notes.append(f"stiffened panels: blade stiffeners at {pitch * 1e3:.0f} mm on both skins, {len(ribs)} ribs "
                       f"{RIB_THICKNESS * 1e3:.0f} mm thick (assumed), safety factor 1.5 on buckling")


def gust_damping(zeta, frequency_hz, geometry, options):
    """Strain-rate damping with ratio ``zeta`` at ``frequency_hz`` (default: the initial design's first mode).

    Parameters
    ----------
    zeta : float
        Damping ratio (-).
    frequency_hz : float or None
        Frequency where the ratio holds (Hz); None for the initial design's first mode.
    geometry : WingGeometry
        The wing geometry.
    options : SizingOptions
        The sizing options.

    Returns
    -------
    tuple
        (StrainRateDamping, description).
    """
    if frequency_hz is None:
        frequency_hz = float(initial_frequencies(geometry, ALUMINIUM, options, count=1)[0])
        where = "first mode of the initial design"
    else:
        where = "given"
    if not frequency_hz > 0.0:
        raise ValueError(f"--damping-frequency-hz = {frequency_hz} Hz; allowed range (0, inf) Hz")
    damping = StrainRateDamping.from_damping_ratio(zeta, frequency_hz)
    return damping, (f"structural damping {zeta:g} at {frequency_hz:.3f} Hz ({where}): "
                     f"strain-rate time constant {damping.curvature[0] * 1e3:.3f} ms")


# --------------------------------------------------------------------------- flutter data
#: Cruise point of Table D.3 (altitude 20 000 ft, Mach 0.5), taken as V_C / M_C.
CRUISE_ALTITUDE_FT, CRUISE_MACH = 20000.0, 0.5
#: 14 CFR 25.335(b)(1): V_D is chosen so that V_C / M_C is not greater than 0.8 V_D / M_D; the
#: smallest admissible V_D of that rule is V_C / 0.8 (an assumption: the dissertation gives no V_D).
VC_OVER_VD = 0.8
#: flutter analyses of this wing start from no published value (none exists)
PUBLISHED = {"source": "none published; V_D from 14 CFR 25.335(b)(1) with V_C = Mach 0.5 at 20 000 ft "
                       "(Table D.3)"}


def flight_point() -> dict:
    """Flutter flight point (SI): altitude (m), density (kg/m^3), speed of sound (m/s), V_C and V_D (TAS, m/s).

    V_C = M_C a(20 000 ft) with M_C = 0.5 (Table D.3); V_D = V_C / 0.8 (14 CFR 25.335(b)(1)), M_D = 0.625.
    14 CFR 25.629(b) asks for freedom from flutter up to 1.15 V_D (the --flutter-margin of sizing).
    """
    h = float(altitude_ft_to_m(CRUISE_ALTITUDE_FT))
    a = float(speed_of_sound(h))
    v_c = CRUISE_MACH * a
    return {"altitude_m": h, "density": float(density(h)), "speed_of_sound": a, "cruise_speed": v_c,
            "dive_speed": v_c / VC_OVER_VD}


def rolling_flight_speeds_eas() -> tuple:
    """(V_C, V_D) of the rolling conditions, m/s EAS: those of :func:`flight_point`.

    Returns
    -------
    tuple
        (V_C, V_D) (m/s EAS).
    """
    fp = flight_point()
    sigma = np.sqrt(fp["density"] / float(density(0.0)))
    return float(fp["cruise_speed"] * sigma), float(fp["dive_speed"] * sigma)


def rolling_cases(opts, geometry, chord, axis_frac, families, sizing, weight_lb=TOGW_LB) -> list:
    """The 14 CFR 25.349(a) rolling conditions as coupled load cases (``--rolling``):
    V_A (the ailerons of ``--alleviation`` at their stops), V_C (the V_A steady roll rate) and V_D (a
    third of it), each a sudden step marched for :data:`ROLL_CASE_T_FINAL` s at ``--dt`` on the
    antisymmetric half wing free to roll (:func:`wingmdao.loads.rolling.rolling_model`), flown at
    the cruise altitude. The deflections of V_C and V_D are those of the initial box design's
    elastic wing (they stay fixed while the sizing changes the wing). Each case is combined with
    two-thirds of the positive maneuvering load factor: its ``symmetric`` part is the strip loads'
    static maneuver (:func:`maneuver_case`) at 2/3 ``opts.load_factor``, superposed as symmetric ±
    increment (the right and the left wing).

    Parameters
    ----------
    opts : PegasusOptions
        The options (``alleviation``, ``roll_inertia``, ``maneuvering_speed_eas``, ``aero_theory``
        resolved, ``dt``, ``load_factor``).
    geometry : WingGeometry
        The wing.
    chord : array_like
        (n,) chord (m).
    axis_frac : array_like
        (n,) beam axis, chord fraction.
    families : tuple
        Stress families.
    sizing : SizingOptions
        The sizing options (their initial design).
    weight_lb : float, optional
        Aircraft weight (lb) of the symmetric maneuver.

    Returns
    -------
    list of LoadCase
        ``rolling_va``, ``rolling_vc``, ``rolling_vd``.
    """
    check_rolling_inputs(opts.alleviation, opts.roll_inertia, opts.maneuvering_speed_eas, opts.aero_theory)
    alt = float(altitude_ft_to_m(CRUISE_ALTITUDE_FT))
    speeds = rolling_speeds(opts.maneuvering_speed_eas, *rolling_flight_speeds_eas(), alt)
    n_time = check_step_count(ROLL_CASE_T_FINAL, opts.dt, geometry.num_nodes)
    surfaces, _ = read_alleviation(opts.alleviation)
    try:
        spec = control_spec(surfaces, geometry.node_positions[:, 1])
    except ValueError as exc:
        raise ValueError(f"--alleviation {opts.alleviation}: {exc}") from None
    bp = design_beam_params(geometry, ALUMINIUM, initial_design(sizing, SECTION_KINDS["box"]["design_vars"]), "box")
    stops = np.radians([s_.max_deflection_deg for s_ in surfaces])
    time = np.arange(n_time) * opts.dt
    start = (time == 0) * 1.0
    rho, n = float(density(alt)), geometry.num_nodes
    cases = []
    n_sym = 2.0 * opts.load_factor / 3.0
    symmetric = maneuver_case("rolling_symmetric", n_sym, geometry, chord, axis_frac, (), PLANFORM, weight_lb)
    def aero_at(v, mach):
        return aero_parameters(n, chord=chord, ref_point=axis_frac, lift_slope=2 * np.pi, airspeed=v, density=rho,
                               mach=mach)

    commands = condition_commands(bp, speeds, aero_at, spec, stops, roll_inertia=opts.roll_inertia,
                                  aero_theory=opts.aero_theory)
    for name, (paragraph, _) in ROLL_CONDITIONS.items():
        v_eas, v, mach = speeds[name]
        k = commands[name][2]
        command = np.where(time[:, None] > 0, k * stops[None, :], 0.0)
        aero = CoupledAero(chord=np.asarray(chord, dtype=float), ref_point=np.asarray(axis_frac, dtype=float),
                           airspeed=v, density=rho, mach=mach, roll=True, roll_inertia=float(opts.roll_inertia),
                           controls=spec, aero_theory=opts.aero_theory,
                           node_positions=np.asarray(geometry.node_positions, dtype=float))
        cases.append(LoadCase(f"rolling_{name.lower()}", time, {"gravity": np.zeros(3), "roll_start": start,
                                                                "surface_command": command}, families,
                              f"{paragraph} at {v_eas:.1f} m/s EAS, aileron {np.degrees(k * stops[0]):.2f} deg, "
                              f"with {n_sym:.3f} g", aero=aero, symmetric=symmetric))
    return cases


def flutter_planform(num_nodes: int = 20) -> Planform:
    """The PEGASUS planform with ``num_nodes - 1`` ribs (20 nodes: the sizing mesh).

    Parameters
    ----------
    num_nodes : int, optional
        Beam nodes.

    Returns
    -------
    Planform
        The planform.
    """
    if int(num_nodes) < 3:
        raise ValueError(f"num_nodes must be >= 3, got {num_nodes}")
    return replace(PLANFORM, num_ribs=int(num_nodes) - 1)


def initial_thickness(num_nodes: int = 20) -> dict:
    """The sizing's initial design: every wall 10 mm at every node (m).

    Parameters
    ----------
    num_nodes : int, optional
        Beam nodes.

    Returns
    -------
    dict
        Wall name -> (num_nodes,) thicknesses (m).
    """
    return {w: np.full(int(num_nodes), 0.01) for w in WALL_VARS}


def beam_params(num_nodes: int = 20, thickness: dict | None = None, panels=None) -> dict:
    """Beam parameter dict (``wingmdao.beam.residual.param_specs``) of the PEGASUS wing, SI.

    ``thickness``: ``{wall: (num_nodes,) m}`` per node, walls ``t_upper_skin, t_lower_skin,
    t_front_spar, t_rear_spar`` (keys without the ``t_`` prefix accepted, as a sizing JSON writes
    them); default :func:`initial_thickness`. Sections from :func:`wingmdao.section.box.box_properties`
    (aluminium, engines as smeared non-structural mass), the same as the sizing model's.
    ``panels`` (a :class:`~wingmdao.panels.layout.PanelLayout`): the design is stiffened and
    ``thickness`` also holds the stiffener variables ``h_upper_stiffener`` ... (m per node),
    smeared into the sections as the stiffened sizing does.

    Parameters
    ----------
    num_nodes : int, optional
        Beam nodes.
    thickness : dict or None, optional
        Wall name -> (num_nodes,) thicknesses (m); None for :func:`initial_thickness`.
    panels : PanelLayout or None, optional
        Panel layout of a stiffened design.

    Returns
    -------
    dict
        Beam parameters.
    """
    n = int(num_nodes)
    geo, _, _ = wing_geometry(flutter_planform(n), ENGINES)
    t = initial_thickness(n) if thickness is None else thickness
    walls = []
    for w in WALL_NAMES:
        v = t.get(w, t.get(w[2:])) if isinstance(t, dict) else None
        if v is None:
            raise ValueError(f"thickness: missing wall {w!r}; needs {list(WALL_NAMES)} (m)")
        v = np.asarray(v, dtype=float).ravel()
        if v.size != n:
            raise ValueError(f"thickness {w!r}: {v.size} stations, the {n}-node PEGASUS beam needs {n}")
        walls.append(v)
    validate_box(geo.width, geo.height, *walls, source="thickness")
    stringers = None
    if panels is not None:
        missing = [k for k in STIFFENER_VARS if k not in t]
        if missing:
            raise ValueError(f"thickness: a stiffened design needs {', '.join(missing)} (m per node)")
        st = {k: np.asarray(t[k], dtype=float).ravel() for k in STIFFENER_VARS}
        stringers = tuple(smeared_stringer(st[f"h_{s}_stiffener"], st[f"t_{s}_stiffener"], panels.stiffener_pitch,
                                           panels.shape, panels.flange_ratio) for s in ("upper", "lower"))
    pr = box_properties(geo.width, geo.height, *walls, ALUMINIUM, None, geo.nonstructural_mass_per_length,
                        stringers=stringers)
    return beam_params_from_section(pr, geo.node_positions, geo.node_euler_angles)


def aero_data(num_nodes: int = 20) -> dict:
    """Strip aerodynamics of the flutter problem: chord (m), beam-axis chord fraction, 2 pi lift slope,
    density and speed of sound of :func:`flight_point` (Mach = V / a at each speed), V_D (m/s).

    Parameters
    ----------
    num_nodes : int, optional
        Beam nodes.

    Returns
    -------
    dict
        Strip aerodynamic data.
    """
    _, chord, frac = wing_geometry(flutter_planform(num_nodes), ENGINES)
    fp = flight_point()
    return {"chord": chord, "ref_point": frac, "lift_slope": 2 * np.pi, "density": fp["density"],
            "speed_of_sound": fp["speed_of_sound"], "dive_speed": fp["dive_speed"]}
