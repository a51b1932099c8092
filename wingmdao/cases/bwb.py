"""The blended-wing-body (BWB) flying wing of W. Su as a free symmetric half stick model: trim and
body-freedom flutter in free flight.

Data: W. Su, "Coupled nonlinear aeroelasticity and flight dynamics of fully flexible aircraft",
PhD thesis, University of Michigan, 2008, and W. Su, C. E. S. Cesnik, "Nonlinear aeroelasticity
of a very flexible blended-wing-body aircraft", J. Aircraft 47(5), 2010, 1539-1553, as the
aircraft model of AeroBeams.jl states them (github.com/luizpancini/AeroBeams.jl, ``create_BWB``
and test/examples/BWBflutter.jl; data only, no code taken). Per side of the aircraft:

* **body** (the centre section): a beam from the centreline to the body-wing junction, 0.889 m
  spanwise and 0.1285 m forward (0.898 m long, swept forward 8.23 deg); EA 1.69e8 N, GJ 2.25e6,
  EI flap 7.5e5, EI in-plane 3.5e7 N m^2; 50 kg/m, rotary inertia 0.7 (flap) and 22 (in-plane)
  kg m; streamwise chord 1.38557 m at the centreline to 0.54864 m at the junction, beam axis at
  64.38 % to 45.60 % of the chord (linear); a 40 kg point mass at the centreline 0.892 m ahead of
  the beam axis (the root leading edge);
* **wing**: from the junction 2.359 m spanwise and 1.362 m aft (2.724 m, swept back 30.0 deg);
  EA 1.55e8 N, GJ 1.1e4, EI flap 1.17e4, EI in-plane 1.3e5 N m^2; 6.2 kg/m, rotary inertia
  5e-4 (flap) and 4.62e-3 (in-plane) kg m; streamwise chord 0.54864 m, beam axis at 45.6 %; 2 kg
  point masses at the nine nodes of its eight equal elements (junction to tip);
* **elevon**: trailing-edge flap hinged at 75 % chord over the inner three quarters of the wing;
* **airfoil**: lift slope 2 pi, zero-lift angle 0, moment coefficient about the quarter chord
  +0.1 (nose up);
* flight at sea level (air density 1.225 kg/m^3, g = 9.80665 m/s^2), thrust at the body.

Model (body axes x aft, y right, z up; origin on the centreline at the body's beam axis): beams
``body`` and ``wing`` of the right half in body axes, a rigid joint at the junction, a symmetry
condition at the centreline node; the 40 kg mass carries half of the pair of AeroBeams' two
body masses (their lateral offsets, +-0.128 m, cancel in the pair and are left out). Strips on
both beams (:mod:`wingmdao.aero.joined`), sections normal to each beam: the chord there is the
streamwise chord times cos(sweep), the beam-axis fraction the same, lift slope 2 pi.
``sweep="normal"`` (the default): the strips on the velocity component normal to each beam,
V cos(sweep), dynamic pressure, Wagner and Kuessner lags and the aircraft's angle alike (simple
sweep theory, the joined system's ``normal_flow``); ``sweep="streamwise"``: on the full airspeed
and the aircraft's angle alpha, the lift per beam length ``q c_n 2 pi alpha``. Structural damping:
strain-rate damping of time constant :data:`DAMPING_TIME`, read off the reference's own modes. Trim (lift = W, zero pitching moment) by the angle of attack,
the elevon (the joined system's ``elevon``: Theodorsen's thin-airfoil flap, dCl/dbeta = 3.83,
where AeroBeams.jl tabulates 3.518) and thrust. No tail, no downwash.

The flutter linearization (:func:`wingmdao.stability.eigen.eigenmodes`) is taken about the trimmed
state with the trim values held (``trim_active`` = 0): the free aircraft's short period and
elastic modes. Reference results (:data:`REFERENCE`): the flutter speed and frequency and the
trim of the aircraft computed with UM/NAST (University of Michigan's Nonlinear Aeroelastic
Simulation Tool, 2024 version, not the version of Su's thesis) as tabulated in AeroBeams.jl
test/referenceData/BWB and quoted in its BWBflutter documentation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import openmdao.api as om

from wingmdao.aero.joined import build_joined_aeroelastic_system, pack_aero_forcing, pack_aero_parameters
from wingmdao.beam.joints import Beam, Joint, LumpedMass, Symmetry
from wingmdao.beam.residual import STATE_BLOCKS, StrainRateDamping
from wingmdao.beam.rotations import body_to_csn, euler_from_axis
from wingmdao.beam.static import beam_parameters
from wingmdao.stability.eigen import eigenmodes
from wingmdao.timemarch.bdf import solve_static

#: Key points of the half aircraft's beam axis in body axes (m): centreline, junction, wing tip.
CENTRE = (0.0, 0.0, 0.0)
JUNCTION = (-0.128524, 0.889, 0.0)
TIP = (1.233678, 3.248152, 0.0)
#: Body section (per side): EA (N), GJ, EI flap, EI in-plane (N m^2), mass (kg/m), rotary inertia
#: about the chordwise and the normal axis (kg m).
BODY = {"EA": 1.69e8, "GJ": 2.25e6, "EI_flap": 7.5e5, "EI_inplane": 3.5e7, "mass": 50.0,
        "i_flap": 0.7, "i_inplane": 22.0}
WING = {"EA": 1.55e8, "GJ": 1.1e4, "EI_flap": 1.17e4, "EI_inplane": 1.3e5, "mass": 6.2,
        "i_flap": 5e-4, "i_inplane": 4.62e-3}
#: Streamwise chords (m) and beam-axis positions (fraction of the chord) at the centreline and at
#: the junction (the wing's all along).
ROOT_CHORD, TIP_CHORD = 1.38557, 0.54864
ROOT_AXIS, TIP_AXIS = 0.6438, 0.4560
#: Point masses: at the centreline (kg, per side) and its offset ahead of the beam axis (m); on the
#: wing's nine equally spaced nodes (kg each).
BODY_POINT_MASS, BODY_POINT_OFFSET = 40.0, 0.891968
WING_POINT_MASS, WING_POINT_COUNT = 2.0, 9
#: Airfoil: lift slope (1/rad), moment coefficient about the quarter chord (nose up +).
LIFT_SLOPE = 2.0 * np.pi
CM0 = 0.1
#: Elevon: hinge (fraction of the chord) and the wing's span fraction it covers from the junction.
ELEVON_HINGE = 0.75
ELEVON_SPAN = 0.75
#: Sea level.
DENSITY = 1.225
GRAVITY = 9.80665
#: Trim supports: surge and plunge of the centreline node, plunge of the junction.
SUPPORTS = (("body", 0, "x"), ("body", 0, "z"), ("body", -1, "z"))
SWEEP_MODELS = ("streamwise", "normal")
#: Stiffness-proportional structural damping of the UM/NAST reference (s): its fourth and fifth
#: modes (7.89 and 13.84 Hz, nearly airspeed-independent) decay at 0.619 and 1.894 1/s at 35 to
#: 40 m/s, ``t w^2 / 2`` with t = 5.04e-4 and 5.01e-4 s.
DAMPING_TIME = 5.0e-4

#: Reference: UM/NAST (2024 version), free-flight flutter of the full aircraft at sea level, from
#: AeroBeams.jl test/referenceData/BWB (freqs.txt in Hz, damps.txt real parts in 1/s, trimAoA.txt
#: root angle of attack and trimDelta.txt elevon in deg, on 30:5:160 m/s) and its BWBflutter page
#: ("flutter speed and frequency predicted by UM/NAST are around 137.7 m/s and 47.5 rad/s";
#: AeroBeams.jl itself: 120.7 m/s, 47.4 rad/s).
REFERENCE = {
    "source": "UM/NAST (2024 version) results for Su's BWB, tabulated in AeroBeams.jl test/referenceData/BWB "
              "and quoted in its BWBflutter example",
    "flutter_speed_m_s": 137.7, "flutter_frequency_rad_s": 47.5,
    "aerobeams_flutter_speed_m_s": 120.7, "aerobeams_flutter_frequency_rad_s": 47.4,
    "airspeed_m_s": [30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0, 90.0, 95.0, 100.0,
                     105.0, 110.0, 115.0, 120.0, 125.0, 130.0, 135.0, 140.0, 145.0, 150.0, 155.0, 160.0],
    # the flutter mode (fourth row of freqs.txt / damps.txt): frequency (Hz) and real part (1/s)
    "flutter_mode_hz": [7.8932, 7.8918, 7.8910, 7.8904, 7.8899, 7.8895, 7.8892, 7.8888, 7.8884, 7.8879, 7.8873,
                        7.8864, 7.8852, 7.8834, 7.8810, 7.8774, 7.8722, 7.8644, 7.8521, 7.8315, 7.7926, 7.6923,
                        7.4489, 7.6447, 7.9878, 8.6142, 9.1760],
    "flutter_mode_real": [-0.62089, -0.61908, -0.61911, -0.61970, -0.62052, -0.62153, -0.62271, -0.62412, -0.62582,
                          -0.62784, -0.63031, -0.63336, -0.63719, -0.64211, -0.64846, -0.65692, -0.66851, -0.68503,
                          -0.70979, -0.74980, -0.82279, -0.98936, 0.86563, 2.8312, 4.0850, 5.8394, 9.8637],
    # the mode that coalesces with it (second row): frequency (Hz)
    "coalescing_mode_hz": [3.2562, 3.2824, 3.3119, 3.3454, 3.3833, 3.4265, 3.4758, 3.5323, 3.5980, 3.6750, 3.7664,
                           3.8757, 4.0066, 4.1627, 4.3469, 4.5626, 4.8135, 5.1046, 5.4429, 5.8385, 6.3087, 6.9032,
                           7.7060, 8.1212, 8.3919, 8.3062, 8.1739],
    "trim_root_aoa_deg": [15.674, 10.817, 7.7097, 5.5977, 4.0969, 2.9935, 2.1599, 1.5162, 1.0099, 0.60552, 0.27821,
                          0.01025, -0.21133, -0.39620, -0.55166, -0.68334, -0.79562, -0.89194, -0.97504, -1.0471,
                          -1.1100, -1.1650, -1.2134, -1.2563, -1.2943, -1.3281, -1.3585],
    "trim_elevon_deg": [-21.524, -13.720, -8.4713, -4.8428, -2.2603, -0.37469, 1.0320, 2.1005, 2.9246, 3.5687,
                        4.0783, 4.4861, 4.8164, 5.0872, 5.3124, 5.5026, 5.6662, 5.8097, 5.9384, 6.0563, 6.1669,
                        6.2728, 6.3763, 6.4792, 6.5829, 6.6886, 6.7972],
}


@dataclass
class BwbAircraft:
    """The free half aircraft.

    Parameters
    ----------
    system : JoinedBeamSystem
        Its aeroelastic residual system (elevon trim).
    params : dict
        The beams' parameter dicts by beam name (SI).
    sections : dict
        The strips' section data by beam name (:func:`~wingmdao.aero.joined.pack_aero_parameters`).
    mass : float
        Mass of the half aircraft (kg).
    sweep : str
        The strips' sweep model (:data:`SWEEP_MODELS`).
    """

    system: object
    params: dict
    sections: dict
    mass: float
    sweep: str


def _axis(a, b):
    d = np.asarray(b, float) - np.asarray(a, float)
    return d / np.linalg.norm(d), float(np.linalg.norm(d))


def sweep_angle(beam: str) -> float:
    """Sweep of a beam's axis (rad, aft +): ``"body"`` -8.23 deg, ``"wing"`` +30.0 deg.

    Parameters
    ----------
    beam : str
        ``"body"`` or ``"wing"``.

    Returns
    -------
    float
        The sweep angle (rad).
    """
    ends = {"body": (CENTRE, JUNCTION), "wing": (JUNCTION, TIP)}
    if beam not in ends:
        raise ValueError(f"beam = {beam!r}; allowed: {sorted(ends)}")
    d, _ = _axis(*ends[beam])
    return float(np.arctan2(d[0], d[1]))


def _inertia(section):
    """Rotary inertia per length in csn (kg m): about c (flap), s (torsion: the sum), n (in-plane)."""
    return np.diag([section["i_flap"], section["i_flap"] + section["i_inplane"], section["i_inplane"]])


def build(num_body_nodes: int = 7, num_wing_nodes: int = 17, sweep: str = "normal",
          damping_time: float = DAMPING_TIME, wing_stiffness_factor: float = 1.0) -> BwbAircraft:
    """The free symmetric half aircraft (module docstring).

    Parameters
    ----------
    num_body_nodes : int
        Nodes of the body beam (>= 2).
    num_wing_nodes : int
        Nodes of the wing beam: 8 k + 1 (k >= 1), so that the nine point masses sit on nodes.
    sweep : str
        ``"streamwise"`` or ``"normal"`` (module docstring).
    damping_time : float
        Time constant of the strain-rate (stiffness-proportional) structural damping of both
        beams (s, >= 0; 0: none): a mode of circular frequency w decays at ``damping_time w^2 / 2``.
    wing_stiffness_factor : float
        Multiplies the wing's bending and torsion stiffness (> 0).

    Returns
    -------
    BwbAircraft
    """
    if int(num_body_nodes) != num_body_nodes or num_body_nodes < 2:
        raise ValueError(f"num_body_nodes = {num_body_nodes}; must be an integer >= 2")
    if int(num_wing_nodes) != num_wing_nodes or num_wing_nodes < 9 or (num_wing_nodes - 1) % 8:
        raise ValueError(f"num_wing_nodes = {num_wing_nodes}; must be 8 k + 1 with k >= 1 (9, 17, 25, ...)")
    if sweep not in SWEEP_MODELS:
        raise ValueError(f"sweep = {sweep!r}; allowed: {list(SWEEP_MODELS)}")
    if not (np.isfinite(damping_time) and damping_time >= 0.0):
        raise ValueError(f"damping_time = {damping_time} s; must be a finite number >= 0")
    if not (np.isfinite(wing_stiffness_factor) and wing_stiffness_factor > 0.0):
        raise ValueError(f"wing_stiffness_factor = {wing_stiffness_factor}; must be a finite number > 0")
    nb, nw = int(num_body_nodes), int(num_wing_nodes)
    db, _ = _axis(CENTRE, JUNCTION)
    dw, _ = _axis(JUNCTION, TIP)
    rb = np.asarray(CENTRE) + np.linspace(0.0, 1.0, nb)[:, None] * (np.asarray(JUNCTION) - CENTRE)
    rw = np.asarray(JUNCTION) + np.linspace(0.0, 1.0, nw)[:, None] * (np.asarray(TIP) - JUNCTION)
    k = float(wing_stiffness_factor)
    body = beam_parameters(rb, euler_from_axis(db), EI_cc=BODY["EI_flap"], EI_nn=BODY["EI_inplane"], GJ=BODY["GJ"],
                           EA=BODY["EA"], mass_per_length=BODY["mass"], inertia_per_length=_inertia(BODY))
    wing = beam_parameters(rw, euler_from_axis(dw), EI_cc=k * WING["EI_flap"], EI_nn=k * WING["EI_inplane"],
                           GJ=k * WING["GJ"], EA=WING["EA"], mass_per_length=WING["mass"],
                           inertia_per_length=_inertia(WING))
    lam_b, lam_w = sweep_angle("body"), sweep_angle("wing")
    # the 40 kg mass: ahead of the centreline node along the body's chordwise axis (normal to the
    # body beam in the plane; its lateral component cancels with the mirror side's)
    masses = [LumpedMass("body", 0, BODY_POINT_MASS, offset=(-BODY_POINT_OFFSET * np.cos(lam_b), 0.0, 0.0))]
    step = (nw - 1) // (WING_POINT_COUNT - 1)
    masses += [LumpedMass("wing", i, WING_POINT_MASS) for i in range(0, nw, step)]
    beams = [Beam("body", nb, root="free"), Beam("wing", nw, root="free")]
    joints = [Joint("body", -1, "wing", 0)]
    t = float(damping_time)
    damping = StrainRateDamping(curvature=(t, t, t), strain=(t, t, t)) if t > 0.0 else None
    # the elevon's end on a node (8 k + 1 nodes): half its deflection there, so that the strips'
    # loads, interpolated between nodes, carry the flap over exactly ELEVON_SPAN of the wing
    end = round(ELEVON_SPAN * (nw - 1))
    elevon_nodes = {i: (0.5 if i == end else 1.0) for i in range(end + 1)}
    system = build_joined_aeroelastic_system(beams, joints, lifting=("body", "wing"), wing="body", tail=None,
                                             supports=SUPPORTS, masses=masses, symmetry=[Symmetry("body", 0)],
                                             elevon={"wing": elevon_nodes}, elevon_hinge=ELEVON_HINGE,
                                             damping=damping, normal_flow=sweep == "normal")
    sb = np.linspace(0.0, 1.0, nb)
    sections = {
        "body": {"chord": (ROOT_CHORD + (TIP_CHORD - ROOT_CHORD) * sb) * np.cos(lam_b),
                 "ref_point": ROOT_AXIS + (TIP_AXIS - ROOT_AXIS) * sb, "lift_slope": LIFT_SLOPE, "cm0": CM0},
        "wing": {"chord": np.full(nw, TIP_CHORD * np.cos(lam_w)), "ref_point": np.full(nw, TIP_AXIS),
                 "lift_slope": LIFT_SLOPE, "cm0": CM0}}
    mass = (BODY["mass"] * _axis(CENTRE, JUNCTION)[1] + WING["mass"] * _axis(JUNCTION, TIP)[1] + BODY_POINT_MASS
            + WING_POINT_MASS * WING_POINT_COUNT)
    return BwbAircraft(system=system, params={"body": body, "wing": wing}, sections=sections, mass=float(mass),
                       sweep=sweep)


def parameters(aircraft: BwbAircraft, airspeed: float) -> np.ndarray:
    """Packed parameters of the aircraft at ``airspeed`` (m/s, sea level, incompressible).

    Parameters
    ----------
    aircraft : BwbAircraft
        The aircraft (:func:`build`).
    airspeed : float
        True airspeed (m/s, > 0).

    Returns
    -------
    ndarray
        The packed parameters.
    """
    if not (np.isfinite(airspeed) and airspeed > 0.0):
        raise ValueError(f"airspeed = {airspeed} m/s; must be a finite number > 0")
    return pack_aero_parameters(aircraft.system, aircraft.params, aircraft.sections, airspeed=float(airspeed),
                                density=DENSITY, mach=0.0)


def trim(aircraft: BwbAircraft, airspeed: float, x0=None, load_steps: int = 4) -> dict:
    """Trimmed level flight at ``airspeed``: lift = W and zero pitching moment by angle of attack,
    elevon and thrust.

    Parameters
    ----------
    aircraft : BwbAircraft
        The aircraft (:func:`build`).
    airspeed : float
        True airspeed (m/s, > 0).
    x0 : ndarray, optional
        Initial guess (a trimmed state at a nearby airspeed); without it gravity is applied in
        ``load_steps`` steps from the jig.
    load_steps : int
        Gravity steps from the jig (unused with ``x0``).

    Returns
    -------
    dict
        ``alpha_deg`` (the aircraft's angle of attack), ``root_aoa_deg`` (that of the centreline
        section, deformation included), ``elevon_deg`` (trailing edge down +), ``thrust`` (N,
        half aircraft), ``tip_deflection`` (m, body z) and the state ``x``.
    """
    s = aircraft.system
    p = parameters(aircraft, airspeed)
    q = pack_aero_forcing(s, trim_active=1.0, gravity=[0.0, 0.0, -GRAVITY])
    label = f"BWB trim at {airspeed} m/s"
    if x0 is None:
        x, _ = solve_static(s, p, q, load_steps=load_steps, scaled=["gravity"], max_halvings=8, atol=1e-9,
                            label=label)
    else:
        x, _ = solve_static(s, p, q, np.asarray(x0, dtype=float), atol=1e-9, label=label)
    ti = s.trim_index
    th = STATE_BLOCKS["theta"]
    i0 = s.node_index("body", 0)
    alpha = float(x[ti["alpha_trim"]])
    # the centreline section's angle to the free stream, deformation included (from its jig angle)
    free = np.array([1.0, 0.0, 0.0])
    rel = body_to_csn(np.asarray(x[i0 + th.start:i0 + th.stop])) @ free
    rel0 = body_to_csn(euler_from_axis(_axis(CENTRE, JUNCTION)[0])) @ free
    twist = float(np.arctan2(rel[2], rel[0]) - np.arctan2(rel0[2], rel0[0]))
    iw = s.node_index("wing", s.beam("wing").num_nodes - 1)
    return {"alpha_deg": float(np.degrees(alpha)), "root_aoa_deg": float(np.degrees(alpha + twist)),
            "elevon_deg": float(np.degrees(x[ti["tail_incidence"]])), "thrust": float(x[ti["thrust"]]),
            "tip_deflection": float(x[iw + 2] - TIP[2]), "x": x}


def modes(aircraft: BwbAircraft, airspeed: float, x) -> object:
    """Eigenvalues of the free aircraft linearised about the trimmed state ``x`` with the trim
    values held (:func:`wingmdao.stability.eigen.eigenmodes`, dense).

    Parameters
    ----------
    aircraft : BwbAircraft
        The aircraft (:func:`build`).
    airspeed : float
        True airspeed (m/s).
    x : ndarray
        The trimmed state (:func:`trim`).

    Returns
    -------
    Modes
        Eigenvalues (Im >= 0) and right eigenvectors.
    """
    s = aircraft.system
    q = pack_aero_forcing(s, trim_active=0.0, gravity=[0.0, 0.0, -GRAVITY])
    return eigenmodes(s, parameters(aircraft, airspeed), q, x, static=False, method="dense")


def _unstable(m, min_frequency, max_frequency):
    lam = m.eigenvalues
    osc = lam[(np.abs(lam.imag) > min_frequency) & (np.abs(lam.imag) < max_frequency)]
    k = int(np.argmax(osc.real))
    return float(osc.real[k]), float(abs(osc.imag[k]))


def flutter(aircraft: BwbAircraft, speeds=None, *, min_frequency: float = 2.0 * np.pi,
            max_frequency: float = 100.0 * np.pi, xtol: float = 0.05) -> dict:
    """Flutter of the free aircraft: trimmed at each of ``speeds`` (m/s, continued from the
    previous one), the largest real part of its oscillatory eigenvalues between ``min_frequency``
    and ``max_frequency`` (rad/s; the defaults 1 and 50 Hz leave out the phugoid and the axial and
    shear modes of the nearly rigid body, kHz, which without structural damping come out with
    round-off real parts of either sign); the first sign change is refined by bisection (each
    point trimmed anew) to ``xtol`` m/s.

    Parameters
    ----------
    aircraft : BwbAircraft
        The aircraft (:func:`build`).
    speeds : array_like, optional
        Increasing airspeeds (m/s); default 60 to 180 m/s every 10.
    min_frequency, max_frequency : float
        Frequency band of the modes searched (rad/s).
    xtol : float
        Speed tolerance of the bisection (m/s).

    Returns
    -------
    dict
        ``speed`` (m/s; None if stable at every speed), ``frequency`` (rad/s), ``speeds``,
        ``real`` (largest real part, 1/s, at each) and ``frequencies`` (rad/s, of that mode).
    """
    speeds = np.asarray(np.arange(60.0, 181.0, 10.0) if speeds is None else speeds, dtype=float)
    if speeds.ndim != 1 or speeds.size < 2 or np.any(np.diff(speeds) <= 0) or speeds[0] <= 0:
        raise ValueError(f"speeds = {speeds}; must be at least two increasing airspeeds > 0 m/s")
    x = None
    reals, freqs, states = [], [], []
    for V in speeds:
        x = trim(aircraft, float(V), x0=x)["x"]
        r, f = _unstable(modes(aircraft, float(V), x), min_frequency, max_frequency)
        reals.append(r)
        freqs.append(f)
        states.append(x)
        if r > 0.0:
            break
    out = {"speeds": speeds[:len(reals)], "real": np.array(reals), "frequencies": np.array(freqs),
           "speed": None, "frequency": None}
    if reals[-1] <= 0.0:
        return out
    if len(reals) == 1:
        raise om.AnalysisError(f"BWB flutter: unstable already at the first speed {speeds[0]} m/s")
    lo, hi, x_lo = float(speeds[len(reals) - 2]), float(speeds[len(reals) - 1]), states[-2]
    r_lo, r_hi, f_lo, f_hi = reals[-2], reals[-1], freqs[-2], freqs[-1]
    while hi - lo > xtol:
        mid = 0.5 * (lo + hi)
        x_mid = trim(aircraft, mid, x0=x_lo)["x"]
        r, f = _unstable(modes(aircraft, mid, x_mid), min_frequency, max_frequency)
        if r > 0.0:
            hi, r_hi, f_hi = mid, r, f
        else:
            lo, r_lo, f_lo, x_lo = mid, r, f, x_mid
    w = -r_lo / (r_hi - r_lo)
    out["speed"] = lo + w * (hi - lo)
    out["frequency"] = f_lo + w * (f_hi - f_lo)
    return out


__all__ = ["build", "parameters", "trim", "modes", "flutter", "sweep_angle", "BwbAircraft", "REFERENCE",
           "SWEEP_MODELS", "SUPPORTS"]
