"""Maneuver loads of the Simple Transonic Wing (Case 1): strip theory on the deforming beam, trimmed.

Method (docs/cases.md, section "stw", "Maneuver loads"): the trimmed static aeroelastic maneuver
of :class:`wingmdao.aero.coupled.CoupledAero` (quasi-steady strip theory on the deformed beam,
the aircraft angle of attack solved for the lift n LGM g), with

* each strip's effective lift slope from a Weissinger vortex-lattice solution of the swept,
  tapered planform at M 0.458 (:func:`wingmdao.aero.weissinger.weissinger_lift_slope`): a
  streamwise strip of chord c lifts l = q c a(y) alpha per unit span at a uniform angle alpha;
* the sweep handled in the beam frame. The coupled model resolves the free stream in each
  node's section frame (c normal to the beam axis in the chord plane, s along it, n up): for
  a beam swept Lambda_b, v_c = V cos Lambda_b and the section angle is v_n / v_c. A twist
  theta about s and a bending slope dw/ds tilt the section normal so that v_n / V = theta cos
  Lambda_b - (dw/ds) sin Lambda_b: the streamwise incidence change of a swept wing bending up
  (wash-out) is in the kinematics. The strip parameters are scaled so that the model's lift per
  unit beam length is l dy/ds: ``chord`` c cos Lambda_b (the quarter-chord-to-axis arm normal to
  the axis), ``lift_slope`` beta a(y) cos Lambda_o (beta undoes the model's own Prandtl-Glauert
  factor; a(y) already holds compressibility) with Lambda_o the sweep of the outboard beam, and
  the model's trim angle is alpha / cos Lambda_o. Outboard of the side of body (Lambda_b =
  Lambda_o) this is exact for the rigid and the elastic incidence; on the unswept centre box
  (Lambda_b = 0) the rigid lift is exact and the elastic incidence change is weighted by cos
  Lambda_o = 0.92 (there the clamped root leaves almost no deformation).
* camber of the RAE 2822 by thin-airfoil theory of its mean line: zero-lift angle and
  quarter-chord moment coefficient (:func:`camber_coefficients`).

Trim: both half-wings lift n LGM g; the beam carries its own weight and the frame acceleration
(n - 1) g (inertia relief of the wingbox mass, the only mass on the benchmark's structure).
LGM = 41 500 kg + 2 M_wing(M_wingbox) (stw_data.landing_gross_mass) with the wingbox mass of
the loads fixed before the sizing: by default that of the benchmark's baseline panel sizing
with the case material (:func:`baseline_wingbox_mass`), or a given value.
"""

from __future__ import annotations

import math

import numpy as np

from wingmdao.cases import stw_data as D, stw_geometry as stw
from wingmdao.aero.weissinger import weissinger_lift_slope
from wingmdao.beam.rotations import body_to_csn
from wingmdao.cases.planform import G0
from wingmdao.cases.stw_geometry import airfoil_surfaces
from wingmdao.groups.load_case import LoadCase
from wingmdao.loads.atmosphere import density, mach_to_tas
from wingmdao.timemarch.system import pack
from wingmdao.aero.coupled import CoupledAero
from wingmdao.aero.system import cached_aeroelastic_system

#: columns of the lift and twist CSV files (docs/cases.md)
CSV_COLUMNS = ("y_m", "eta", "lift_n_per_m", "cl", "twist_deg")


def beta(mach: float = D.PULL_UP.mach) -> float:
    """Prandtl-Glauert factor sqrt(1 - M^2).

    Parameters
    ----------
    mach : float, optional
        Mach number, < 1.

    Returns
    -------
    float
        beta (dimensionless).
    """
    return math.sqrt(1.0 - mach * mach)


def camber_coefficients(n: int = 2000) -> tuple[float, float]:
    """(alpha_zero_lift rad, cm about the quarter chord) of the RAE 2822 mean line by thin-airfoil
    theory: alpha_L0 = -1/pi int dz/dx (cos t - 1) dt, cm_c/4 = 1/2 int dz/dx (cos 2t - cos t) dt,
    x = (1 - cos t) / 2 (Abbott & von Doenhoff, Ch. 4).

    Parameters
    ----------
    n : int, optional
        Integration points.

    Returns
    -------
    alpha_zero_lift : float
        Zero-lift angle (rad).
    cm0 : float
        Pitching-moment coefficient about the quarter chord.
    """
    upper, lower = airfoil_surfaces()
    t = (np.arange(n) + 0.5) * np.pi / n
    dt = np.pi / n
    x = 0.5 * (1.0 - np.cos(t))
    h = 1e-5
    zc = lambda xx: 0.5 * (upper(xx) + lower(xx))  # noqa: E731
    dz = (zc(np.clip(x + h, 0, 1)) - zc(np.clip(x - h, 0, 1))) / (np.clip(x + h, 0, 1) - np.clip(x - h, 0, 1))
    a0 = -np.sum(dz * (np.cos(t) - 1.0)) * dt / np.pi
    cm = 0.5 * np.sum(dz * (np.cos(2 * t) - np.cos(t))) * dt
    return float(a0), float(cm)


def spanwise_lift_slope(y, mach: float = D.PULL_UP.mach, n_panels: int = 60):
    """Effective strip lift slope a(y) (1/rad, compressible, per streamwise angle) at span
    positions ``y`` and the wing's CL_alpha, from the Weissinger solution of the STW planform.

    Parameters
    ----------
    y : array_like
        Span positions (m).
    mach : float, optional
        Mach number.
    n_panels : int, optional
        Spanwise panels of the Weissinger solution.

    Returns
    -------
    slope : ndarray
        a(y) (1/rad).
    cl_alpha : float
        Wing lift slope (1/rad).
    """
    slope, cl_alpha, _ = weissinger_lift_slope(y, stw.chord, stw.leading_edge_x, D.SEMI_SPAN, mach=mach,
                                               n_panels=n_panels)
    return slope, cl_alpha


def outboard_sweep(beam) -> float:
    """Sweep of the outboard beam (rad): the mid-box line outboard of the side of body.

    Parameters
    ----------
    beam : wingmdao.cases.stw_geometry.StwBeam
        The STW beam.

    Returns
    -------
    float
        Sweep (rad).
    """
    return float(np.radians(beam.sweep_deg[-1]))


def strip_parameters(beam, mach: float = D.PULL_UP.mach) -> dict:
    """CoupledAero section data per beam node (module docstring): chord, ref_point, lift_slope,
    alpha_zero_lift, cm0; and the unscaled ``strip_slope`` a(y), ``CL_alpha``, ``sweep_out``.

    Parameters
    ----------
    beam : wingmdao.cases.stw_geometry.StwBeam
        The STW beam.
    mach : float, optional
        Mach number.

    Returns
    -------
    dict
        The section data per node (m, rad, 1/rad).
    """
    lam_b = np.radians(beam.sweep_deg)
    lam_o = outboard_sweep(beam)
    a, cl_alpha = spanwise_lift_slope(beam.y, mach)
    a0, cm0 = camber_coefficients()
    slope = np.maximum(a * beta(mach) * math.cos(lam_o), 1e-6)  # > 0 at the tip (zero loading there)
    return {"chord": beam.chord * np.cos(lam_b), "ref_point": np.asarray(beam.axis_fraction, dtype=float),
            "lift_slope": slope, "alpha_zero_lift": np.full(beam.y.size, a0 / math.cos(lam_o)),
            "cm0": np.full(beam.y.size, cm0), "strip_slope": a, "CL_alpha": cl_alpha, "sweep_out": lam_o,
            "alpha_zero_lift_streamwise": a0}


def baseline_wingbox_mass(beam, material, panel=D.BASELINE_PANEL) -> float:
    """Wingbox mass of one wing (kg) of the benchmark's baseline panel sizing (required_results.rst:
    panels 6.5 mm, T stiffeners 50 mm x 6 mm at 0.15 m, flange = web height) on the beam's box:
    skins of t_panel + A_stiff / p_stiff, unstiffened spar webs of t_panel (the beam's spars
    carry no stiffeners), ribs left out; density of ``material``.

    Parameters
    ----------
    beam : wingmdao.cases.stw_geometry.StwBeam
        The STW beam (box width, height and node positions in m).
    material : wingmdao.materials.Material
        Material whose density (kg/m^3) is used.
    panel : stw_data.PanelSizing, optional
        The panel sizing (m).

    Returns
    -------
    float
        Wingbox mass of one wing (kg).
    """
    area_stiff = 2.0 * panel.stiffener_height * panel.stiffener_thickness  # web + flange (flange = height)
    t_eq = panel.panel_thickness + area_stiff / panel.stiffener_pitch
    per_length = material.rho * (2.0 * beam.geometry.width * t_eq + 2.0 * beam.geometry.height * panel.panel_thickness)
    ds = np.linalg.norm(np.diff(beam.geometry.node_positions, axis=0), axis=1)
    return float(np.sum(0.5 * (per_length[1:] + per_length[:-1]) * ds))


def maneuver_case(name, condition, beam, landing_mass, families, mach=None):
    """The trimmed aeroelastic maneuver ``condition`` (stw_data.PULL_UP / PUSH_DOWN) at the
    landing gross mass ``landing_mass`` (kg): a :class:`~wingmdao.groups.load_case.LoadCase` with a
    :class:`~wingmdao.aero.coupled.CoupledAero` (trim=True).

    Parameters
    ----------
    name : str
        Load case name.
    condition : stw_data.FlightCondition
        The maneuver's flight condition.
    beam : wingmdao.cases.stw_geometry.StwBeam
        The STW beam.
    landing_mass : float
        Landing gross mass (kg).
    families : sequence of str
        Stress families constrained.
    mach : float, optional
        Mach number of the aerodynamics; None: the condition's.

    Returns
    -------
    wingmdao.groups.load_case.LoadCase
        The trimmed maneuver case.
    """
    mach = condition.mach if mach is None else mach
    n = condition.load_factor
    alt = condition.altitude
    sp = strip_parameters(beam, mach)
    aero = CoupledAero(chord=sp["chord"], ref_point=sp["ref_point"], lift_slope=sp["lift_slope"],
                       alpha_zero_lift=sp["alpha_zero_lift"], cm0=sp["cm0"],
                       airspeed=float(mach_to_tas(mach, alt)), density=float(density(alt)), mach=float(mach),
                       trim=True, trim_lift=n * landing_mass * G0)
    forcing = {"gravity": np.array([[0.0, 0.0, -G0]]),
               "frame_acceleration": np.array([[0.0, 0.0, (n - 1.0) * G0]]),
               "trim_active": np.ones(1)}
    return LoadCase(name, np.zeros(1), forcing, families,
                    f"{n:+.2f} g trimmed aeroelastic maneuver, M {mach:g} at {alt:g} m, LGM {landing_mass:.0f} kg",
                    aero=aero)


def trimmed_state(prob, case, beam) -> dict:
    """The trimmed state of an analysed maneuver ``case`` of a sizing problem: per node ``y_m``,
    ``eta``, ``lift_n_per_m`` (lift per unit span, N/m), ``cl`` (on the streamwise chord, free-stream
    dynamic pressure), ``twist_deg`` (streamwise incidence change of the deformed section, deg:
    asin of the x component of the deformed section normal, i.e. theta cos Lambda - dw/ds sin
    Lambda for small rotations); and ``alpha_deg`` (aircraft angle of attack), ``total_lift_n``
    (both half-wings), ``root_bending_moment_n_m`` (beam state M_x at the root).

    Parameters
    ----------
    prob : openmdao.api.Problem
        The analysed sizing problem.
    case : wingmdao.groups.load_case.LoadCase
        The maneuver case (:func:`maneuver_case`).
    beam : wingmdao.cases.stw_geometry.StwBeam
        The STW beam.

    Returns
    -------
    dict
        The state, units above.
    """
    n = beam.geometry.num_nodes
    path = f"cases.{case.name}"

    def value(name):
        for full in (f"{path}.{name}", name, f"{path}.beam.{name}"):
            try:
                return np.asarray(prob.get_val(full))
            except KeyError:
                continue
        try:
            return np.asarray(case.forcing_array(name, n))
        except Exception as exc:  # noqa: BLE001
            raise KeyError(f"input {name} of load case {case.name} not found") from exc

    system = cached_aeroelastic_system(n, trim=True)
    X = np.asarray(prob.get_val(f"{path}.states")).reshape(-1)
    x = X[-system.n_state:]
    p = pack(system.param_specs, {s.name: value(s.name) for s in system.param_specs})
    q = np.concatenate([np.asarray(value(s.name)).reshape(-1)[-s.size:] for s in system.forcing_specs])
    lift_beam, _ = system.section_loads(x, np.zeros_like(x), p, q)
    beam_states = system.layout.beam_states(x).reshape(n, 18)
    theta = beam_states[:, 3:6]
    nx = np.array([body_to_csn(th)[2, 0] for th in theta])
    twist = np.degrees(np.arcsin(np.clip(nx, -1, 1)))
    cos_b = np.cos(np.radians(beam.sweep_deg))
    lift = lift_beam / cos_b  # per unit beam length -> per unit span
    aero = case.aero
    qdyn = 0.5 * aero.density * aero.airspeed ** 2
    r0 = beam.geometry.node_positions
    ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
    total = 2.0 * float(np.sum(0.5 * (lift_beam[1:] + lift_beam[:-1]) * ds))
    alpha_model = float(x[system.trim_index])
    return {"y_m": beam.y.copy(), "eta": beam.y / D.SEMI_SPAN, "lift_n_per_m": lift, "cl": lift / (qdyn * beam.chord),
            "twist_deg": twist, "alpha_deg": math.degrees(alpha_model * math.cos(outboard_sweep(beam))),
            "total_lift_n": total, "root_bending_moment_n_m": float(beam_states[0, 9])}


def write_distribution_csv(path: str, state: dict) -> str:
    """Write one maneuver's distributions (:data:`CSV_COLUMNS`, one row per beam station).

    Parameters
    ----------
    path : str
        CSV file to write.
    state : dict
        A :func:`trimmed_state`.

    Returns
    -------
    str
        ``path``.
    """
    rows = np.column_stack([np.asarray(state[c], dtype=float) for c in CSV_COLUMNS])
    np.savetxt(path, rows, delimiter=",", header=",".join(CSV_COLUMNS), comments="", fmt="%.9g")
    return path
