"""PEGASUS as a stick model of the symmetric half aircraft, free in surge, plunge and pitch.

Beams (:mod:`wingmdao.beam.joints`), body axes x aft, y right, z up, origin at the wing root's
leading edge on the plane of symmetry:

* **wing**: the PEGASUS wingbox of :mod:`wingmdao.cases.pegasus` (App. D.2, Tables D.3-D.4; its
  20-node mesh, NACA 43-series box, aluminium walls; 10 mm walls unless a sizing's thicknesses are
  given), without the engines' smeared mass: the engines are lumped masses here;
* **fuselage**: a beam along x (:data:`~wingmdao.beam.joints.FUSELAGE_AXES`) from the nose to the
  tail cone, joined to the wing's root node (station 0, on the plane of symmetry);
* **fin**: a vertical beam from the fuselage node under it to the horizontal tail (a T-tail, as
  on the ATR 42 class PEGASUS derives from);
* **horizontal tail**: a beam along y from the fin's tip.

Joints are rigid. Symmetry conditions (:class:`~wingmdao.beam.joints.Symmetry`) hold every
fuselage and fin node on the plane of symmetry (no lateral displacement, roll or yaw): the half
aircraft has 3 rigid-body modes. Members lying on that plane carry half the aircraft's stiffness
and mass; the wing and horizontal tail are one side's.

Data. The wing and its engines are the case's (:mod:`wingmdao.cases.pegasus`: TOGW 41 005 lb
from Table D.3; per wing a 600 kg hybrid-electric engine at 35 % semi-span and a 150 kg tip motor,
assumptions of that case). The rest are **assumptions** of this model (no fuselage or tail data
are published for PEGASUS), sized on the ATR 42 class (length 22.67 m, fuselage diameter 2.57 m,
horizontal tail span 7.31 m and area 11.73 m^2, T-tail):

* engines' mass centres 1.5 m ahead of and 0.5 m below the wing's beam axis (the 600 kg engine;
  a cylinder of radius 0.4 m and length 2.5 m for its rotary inertia) and 0.5 m ahead (the tip
  motor, a point mass): :data:`ENGINE_OFFSETS`;
* fuselage: x from -9.0 m to 13.5 m at the wing root's height; an aluminium circular shell of
  radius 1.3 m with a smeared (skin and stringers) thickness of 3 mm: EI = E pi R^3 t, GJ =
  G 2 pi R^3 t, EA = E 2 pi R t; structure 2600 kg uniformly along its length; the rest of the
  TOGW (payload, systems, fuel or batteries, furnishings, landing gear) as lumped masses spread
  evenly over the fuselage nodes from x = -7 m to 8 m (:data:`FUSELAGE`);
* fin: from the fuselage node at x = 12 m, 4.0 m high, straight; EI lateral 8e6, fore-aft 6e7,
  GJ 6e6 N m^2, EA 2e9 N, 35 kg/m (:data:`FIN`);
* horizontal tail: semi-span 3.655 m from the fin tip; EI flap 2e6, chordwise 2e7, GJ 2.5e6
  N m^2, EA 1e9 N, 20 kg/m (:data:`TAIL`).

:func:`natural_frequencies` gives the elastic frequencies of the free half aircraft about the
jig (``PYTHONPATH=. python benchmarks/pegasus_stick_modes.py``; docs/stick-model.md).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import casadi as ca
import numpy as np

from wingmdao.aero.joined import build_joined_aeroelastic_system, lift_total, pack_aero_forcing, pack_aero_parameters
from wingmdao.aero.strip import station_gust_history
from wingmdao.beam.joints import (FUSELAGE_AXES, Beam, JoinedBeamModel, Joint, LumpedMass, MonitoringStation,
                                  Symmetry, monitoring_loads)
from wingmdao.beam.rotations import body_to_csn, euler_from_axis
from wingmdao.beam.static import beam_parameters
from wingmdao.cases import pegasus
from wingmdao.cases.planform import FT, G0, LB, wing_geometry
from wingmdao.groups.load_case import SizedBeam, StickCase
from wingmdao.loads.atmosphere import altitude_ft_to_m, density, mach_to_tas, speed_of_sound
from wingmdao.loads.gust import design_gust_velocity_eas
from wingmdao.loads.maneuver import maneuver_line_loads
from wingmdao.materials import ALUMINIUM
from wingmdao.section.box import WALL_NAMES, beam_params_from_section, box_properties, validate_box
from wingmdao.stability.cases import sizing_flutter_options
from wingmdao.stability.eigen import eigenmodes
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import layout

#: Engines' mass centres from their wing nodes (m, body axes) and rotary inertias (kg m^2, about
#: their centres): the 600 kg engine as a cylinder of radius 0.4 m and length 2.5 m along x.
ENGINE_OFFSETS = ((-1.5, 0.0, -0.5), (-0.5, 0.0, 0.0))
ENGINE_INERTIA = (np.diag([0.5 * 600.0 * 0.4**2, 600.0 * (3 * 0.4**2 + 2.5**2) / 12,
                           600.0 * (3 * 0.4**2 + 2.5**2) / 12]), None)
#: Fuselage (full aircraft; the half model carries half): x range (m), shell radius (m), smeared
#: wall thickness (m), structural mass (kg), the x range of the lumped payload and systems (m).
FUSELAGE = {"x_nose": -9.0, "x_end": 13.5, "radius": 1.3, "thickness": 3e-3, "structure_mass": 2600.0,
            "payload_x": (-7.0, 8.0), "spacing": 1.5}
#: Fin (full aircraft): root x (m) on the fuselage, height (m), section (SI), nodes.
FIN = {"x": 12.0, "height": 4.0, "EI_lateral": 8e6, "EI_fore_aft": 6e7, "GJ": 6e6, "EA": 2e9,
       "mass_per_length": 35.0, "num_nodes": 5}
#: Horizontal tail (one side): semi-span (m), section (SI), nodes.
TAIL = {"semi_span": 3.655, "EI_cc": 2e6, "EI_nn": 2e7, "GJ": 2.5e6, "EA": 1e9, "mass_per_length": 20.0,
        "num_nodes": 8}
#: Horizontal tail's sections (assumption): the ATR 42 class tail's mean chord (area 11.73 m^2 over
#: span 7.31 m), beam axis at the quarter chord, thin-airfoil lift slope.
TAIL_SECTION = {"chord": 11.73 / 7.31, "ref_point": 0.25, "lift_slope": 2.0 * np.pi}
#: The horizontal tail as a box (``--size-beams tail``; assumption): a single-cell aluminium box of
#: 40 % of the tail's chord centred on its beam axis (the quarter chord: spars at 5 % and 45 %
#: chord), 10 % of the chord high (a 12 % thick section), equal walls of ``initial`` m at the
#: start (EI flap 1.97e6, chordwise 1.74e7, GJ 2.2e6 N m^2: the :data:`TAIL` data); the rest of
#: the tail's 20 kg/m (leading and trailing edges, ribs, elevator) is nonstructural.
TAIL_BOX = {"width": 0.4 * 11.73 / 7.31, "height": 0.1 * 11.73 / 7.31, "initial": 3.3e-3}
#: The fuselage as a thin circular tube (``--size-beams fuselage``): the :data:`FUSELAGE` shell
#: (radius 1.3 m, smeared wall 3 mm at the start); the rest of its 2600 kg of structure
#: (frames, floor, doors, windows) is nonstructural; the half model's beam carries half.
FUSELAGE_TUBE = {"initial": FUSELAGE["thickness"], "upper": 0.02}
#: The beams ``--size-beams`` can size besides the wing.
SIZABLE_BEAMS = ("tail", "fuselage")
#: Small rotary inertia per length (kg m, csn) of the fuselage, fin and tail sections.
_ROTARY = np.diag([1e-3, 1e-3, 1e-3])


@dataclass
class StickAircraft:
    """The half aircraft: its :class:`~wingmdao.beam.joints.JoinedBeamModel` (``model``), the mass
    (kg, half aircraft), centre of gravity (m, body axes) and pitch inertia about it (kg m^2, half
    aircraft) of the jig, and the beams' node positions in body axes (``nodes``).

    Parameters
    ----------
    model : wingmdao.beam.joints.JoinedBeamModel
        The joined beams of the half aircraft.
    mass : float
        Mass of the jig (kg, half aircraft).
    cg : numpy.ndarray
        Centre of gravity of the jig (m, body axes), shape (3,).
    pitch_inertia : float
        Pitch inertia about the centre of gravity (kg m^2, half aircraft).
    nodes : dict
        ``{beam name: (n, 3) node positions}`` (m, body axes).
    wing_chord : numpy.ndarray
        The wing's chord per node (m).
    wing_axis_fraction : numpy.ndarray
        The wing's beam axis per node as a fraction of the chord from the leading edge.
    """

    model: JoinedBeamModel
    mass: float
    cg: np.ndarray
    pitch_inertia: float
    nodes: dict
    wing_chord: np.ndarray
    wing_axis_fraction: np.ndarray


def _wing_params(num_nodes, thickness):
    """The PEGASUS wing's beam parameters without the engines' smeared mass."""
    n = int(num_nodes)
    geo, chord, frac = wing_geometry(pegasus.flutter_planform(n), ())
    t = pegasus.initial_thickness(n) if thickness is None else thickness
    walls = []
    for w in WALL_NAMES:
        v = t.get(w, t.get(w[2:]))
        if v is None:
            raise ValueError(f"thickness: missing wall {w!r}; needs {list(WALL_NAMES)} (m)")
        v = np.asarray(v, dtype=float).ravel()
        if v.size != n:
            raise ValueError(f"thickness {w!r}: {v.size} stations, the {n}-node PEGASUS wing needs {n}")
        walls.append(v)
    validate_box(geo.width, geo.height, *walls, source="thickness")
    props = box_properties(geo.width, geo.height, *walls, ALUMINIUM, None, geo.nonstructural_mass_per_length)
    return beam_params_from_section(props, geo.node_positions, geo.node_euler_angles), geo, chord, frac


def _fuselage_x(x_wing):
    """Fuselage node x: about ``spacing`` apart, with nodes at the wing root and the fin."""
    f = FUSELAGE
    cuts = [f["x_nose"], x_wing, FIN["x"], f["x_end"]]
    xs = [np.array([cuts[0]])]
    for a, b in zip(cuts[:-1], cuts[1:]):
        k = max(1, int(round((b - a) / f["spacing"])))
        xs.append(np.linspace(a, b, k + 1)[1:])
    return np.concatenate(xs)


def _beam_mass(params):
    """Mass (kg) of a beam: its elements' mean mass per length times their lengths."""
    r0 = np.asarray(params["node_positions"], dtype=float)
    mu = np.asarray(params["mass_per_length"], dtype=float)
    return float(np.sum(0.5 * (mu[:-1] + mu[1:]) * np.linalg.norm(np.diff(r0, axis=0), axis=1)))


def build(num_wing_nodes: int = 20, thickness: dict | None = None) -> StickAircraft:
    """The free symmetric half PEGASUS stick model (module docstring): wing, fuselage, fin and
    horizontal tail, engines and payload as lumped masses, symmetry conditions on the plane of
    symmetry. ``thickness``: the wing's walls (m per node, as :func:`wingmdao.cases.pegasus.beam_params`).

    Parameters
    ----------
    num_wing_nodes : int
        Number of wing nodes.
    thickness : dict or None
        The wing's wall thicknesses (m per node, as :func:`wingmdao.cases.pegasus.beam_params`);
        None: :func:`wingmdao.cases.pegasus.initial_thickness`.

    Returns
    -------
    StickAircraft
        The half aircraft.
    """
    wing, geo, chord, frac = _wing_params(num_wing_nodes, thickness)
    r_wing = np.asarray(wing["node_positions"], dtype=float)
    x_wing = float(r_wing[0, 0])
    half = 0.5
    E, G = ALUMINIUM.E, ALUMINIUM.E / (2 * (1 + ALUMINIUM.nu))
    R, t = FUSELAGE["radius"], FUSELAGE["thickness"]
    xf = _fuselage_x(x_wing)
    fus_axes = np.array(FUSELAGE_AXES)
    fus = beam_parameters((fus_axes @ np.column_stack([xf, 0 * xf, 0 * xf]).T).T,
                          np.tile(euler_from_axis((0.0, 1.0, 0.0)), (xf.size, 1)),
                          EI_cc=half * E * np.pi * R**3 * t, EI_nn=half * E * np.pi * R**3 * t,
                          GJ=half * G * 2 * np.pi * R**3 * t, EA=half * E * 2 * np.pi * R * t,
                          mass_per_length=half * FUSELAGE["structure_mass"] / (xf[-1] - xf[0]),
                          inertia_per_length=_ROTARY)
    nfin = FIN["num_nodes"]
    zfin = np.linspace(0.0, FIN["height"], nfin)
    fin = beam_parameters(np.column_stack([np.full(nfin, FIN["x"]), 0 * zfin, zfin]),
                          np.tile(euler_from_axis((0.0, 0.0, 1.0)), (nfin, 1)),
                          EI_cc=half * FIN["EI_lateral"], EI_nn=half * FIN["EI_fore_aft"], GJ=half * FIN["GJ"],
                          EA=half * FIN["EA"], mass_per_length=half * FIN["mass_per_length"],
                          inertia_per_length=_ROTARY)
    nt = TAIL["num_nodes"]
    yt = np.linspace(0.0, TAIL["semi_span"], nt)
    tail = beam_parameters(np.column_stack([np.full(nt, FIN["x"]), yt, np.full(nt, FIN["height"])]),
                           np.tile(euler_from_axis((0.0, 1.0, 0.0)), (nt, 1)),
                           EI_cc=TAIL["EI_cc"], EI_nn=TAIL["EI_nn"], GJ=TAIL["GJ"], EA=TAIL["EA"],
                           mass_per_length=TAIL["mass_per_length"], inertia_per_length=_ROTARY)
    i_wing = int(np.argmin(np.abs(xf - x_wing)))
    i_fin = int(np.argmin(np.abs(xf - FIN["x"])))
    # engines on the wing nodes nearest their span stations (pegasus.ENGINES)
    y_nodes = geo.span_coordinate
    masses = [LumpedMass("wing", int(np.argmin(np.abs(y_nodes - y))), m, offset=d, inertia=J)
              for (m, y), d, J in zip(pegasus.ENGINES, ENGINE_OFFSETS, ENGINE_INERTIA)]
    # the rest of the half TOGW: payload and systems over the fuselage nodes in payload_x
    half_togw = half * pegasus.TOGW_LB * LB
    parts = {"wing": wing, "fuselage": fus, "fin": fin, "tail": tail}
    body = {"wing": wing["node_positions"], "fuselage": np.column_stack([xf, 0 * xf, 0 * xf]),
            "fin": fin["node_positions"], "tail": tail["node_positions"]}
    structure = sum(_beam_mass(parts[k]) for k in parts) + sum(lm.mass for lm in masses)
    payload = half_togw - structure
    if payload <= 0.0:
        raise ValueError(f"the structure and engines weigh {structure:.0f} kg, more than half the TOGW "
                         f"({half_togw:.0f} kg): thinner wing walls or lighter assumptions are needed")
    cabin = np.flatnonzero((xf >= FUSELAGE["payload_x"][0]) & (xf <= FUSELAGE["payload_x"][1]))
    masses += [LumpedMass("fuselage", int(i), payload / cabin.size) for i in cabin]
    beams = [Beam("fuselage", xf.size, root="free", axes=FUSELAGE_AXES), Beam("wing", r_wing.shape[0], root="free"),
             Beam("fin", nfin, root="free"), Beam("tail", nt, root="free")]
    joints = [Joint("fuselage", i_wing, "wing", 0), Joint("fuselage", i_fin, "fin", 0), Joint("fin", -1, "tail", 0)]
    # the fin's root is held through its rigid joint to the fuselage (a second condition there is redundant)
    symmetry = [Symmetry("fuselage", i) for i in range(xf.size)] + [Symmetry("fin", i) for i in range(1, nfin)]
    model = JoinedBeamModel(beams, joints, parts, masses=masses, symmetry=symmetry)
    axes = {b.name: b.rotation for b in beams}
    mass, cg, iyy = _mass_properties(parts, body, axes, masses)
    return StickAircraft(model=model, mass=mass, cg=cg, pitch_inertia=iyy, nodes=body, wing_chord=chord,
                         wing_axis_fraction=frac)


def _mass_properties(parts, body, axes, masses):
    """Mass, centre of gravity and pitch inertia about it of the jig (half aircraft), as the beam's
    elements discretise them: each element's mass at the mean of its nodes' mass centres, its
    sections' rotary inertia per length; the lumped masses at their offset centres with their own
    I_yy."""
    pts, ms, iyy_own = [], [], 0.0
    for k, prm in parts.items():
        R = np.asarray(axes[k], dtype=float)
        theta0 = np.asarray(prm["node_euler_angles"], dtype=float)
        T0 = [np.array(body_to_csn(ca.DM(th), "surface")) @ R for th in theta0]      # body -> csn
        c = np.asarray(prm["mass_center"], dtype=float)
        centre = np.asarray(body[k], dtype=float) + np.array([t.T @ [cc[0], 0.0, cc[1]] for t, cc in zip(T0, c)])
        i_yy = np.array([(t.T @ np.asarray(i) @ t)[1, 1] for t, i in zip(T0, prm["inertia_per_length"])])
        mu = np.asarray(prm["mass_per_length"], dtype=float)
        ds = np.linalg.norm(np.diff(np.asarray(body[k], dtype=float), axis=0), axis=1)
        ms.append(0.5 * (mu[:-1] + mu[1:]) * ds)
        pts.append(0.5 * (centre[:-1] + centre[1:]))
        iyy_own += float(np.sum(0.5 * (i_yy[:-1] + i_yy[1:]) * ds))
    for lm in masses:
        ms.append(np.array([lm.mass]))
        pts.append((np.asarray(body[lm.beam], dtype=float)[lm.node] + np.asarray(lm.offset))[None, :])
        iyy_own += lm.inertia[1][1]
    m, p = np.concatenate(ms), np.vstack(pts)
    mass = float(m.sum())
    cg = m @ p / mass
    d = p - cg
    return mass, cg, float(m @ (d[:, 0] ** 2 + d[:, 2] ** 2) + iyy_own)


def monitoring_stations(aircraft: StickAircraft) -> list:
    """The monitoring stations of the half aircraft (:class:`~wingmdao.beam.joints.MonitoringStation`):
    the wing's root rib (the cut inboard of wing node 1), the fuselage just ahead of and just aft of
    the wing joint, the fuselage ahead of the fin, the fin root and the horizontal tail root.

    Parameters
    ----------
    aircraft : StickAircraft
        The half aircraft (from :func:`build`).

    Returns
    -------
    list of wingmdao.beam.joints.MonitoringStation
        The stations.
    """
    return _stations(aircraft.model.system, aircraft.nodes["fuselage"][:, 0])


def _stations(s, x):
    """:func:`monitoring_stations` of the joined system ``s`` whose fuselage nodes are at body x = ``x``."""
    i_wing = next(jt.node_a for jt in s.joints if jt.beam_b == "wing")
    i_fin = next(jt.node_a for jt in s.joints if jt.beam_b == "fin")
    return [MonitoringStation("wing root", "wing", 1),
            MonitoringStation(f"fuselage x = {x[i_wing]:.2f} m (ahead of the wing)", "fuselage", i_wing),
            MonitoringStation(f"fuselage x = {x[i_wing + 1]:.2f} m (aft of the wing)", "fuselage", i_wing + 1),
            MonitoringStation(f"fuselage x = {x[i_fin]:.2f} m (ahead of the fin)", "fuselage", i_fin),
            MonitoringStation("fin root", "fin", 1),
            MonitoringStation("tail root", "tail", 1)]


#: Supports of the inertia-relief solves (statically determinate: nose x and z, tail cone z).
SUPPORTS = (("fuselage", 0, "x"), ("fuselage", 0, "z"), ("fuselage", -1, "z"))


def balanced_maneuver(aircraft: StickAircraft, load_factor: float) -> dict:
    """A symmetric maneuver of the free half aircraft balanced by its lift: the wing's lift of the
    PEGASUS case (:func:`wingmdao.loads.maneuver.maneuver_line_loads`: Schrenk spanwise, centre of
    pressure at 25 % chord) scaled to a fraction of n W, and a tail load evenly on the tail's nodes,
    so that they lift n W and have no moment about the jig CG; then the inertia-relief solution
    (:func:`wingmdao.beam.joints.solve_inertia_relief`) under them and gravity.

    Returns ``wing_lift`` and ``tail_load`` (N, half aircraft), ``accelerations`` (of the body axes;
    the CG's vertical acceleration is (n - 1) g and the pitch acceleration zero up to the CG's shift
    by the deformation), ``loads`` at :func:`monitoring_stations` and the state ``x``.

    Parameters
    ----------
    aircraft : StickAircraft
        The half aircraft (from :func:`build`).
    load_factor : float
        The maneuver's load factor n.
    """
    if not np.isfinite(load_factor):
        raise ValueError(f"load_factor = {load_factor}; must be a finite number")
    m = aircraft.model
    weight = aircraft.mass * G0
    r_w, r_t = aircraft.nodes["wing"], aircraft.nodes["tail"]
    unit = maneuver_line_loads(r_w, aircraft.wing_chord, aircraft.wing_axis_fraction, 2.0 * weight, 1.0,
                               semi_span=pegasus.PLANFORM.semi_span,
                               fuselage_half_width=pegasus.PLANFORM.root_rib * pegasus.PLANFORM.semi_span)
    f, mm = unit.force_per_length, unit.moment_per_length
    ds = np.linalg.norm(np.diff(r_w, axis=0), axis=1)
    fe = 0.5 * (f[:-1] + f[1:]) * ds[:, None]                  # the elements' resultants at their midpoints
    me = 0.5 * (mm[:-1] + mm[1:]) * ds[:, None] + np.cross(0.5 * (r_w[:-1] + r_w[1:]) - aircraft.cg, fe)
    nt = r_t.shape[0]
    tail_unit = np.zeros((nt, 3))
    tail_unit[1:, 2] = 1.0 / (nt - 1)
    tail_moment = np.sum(np.cross(r_t - aircraft.cg, tail_unit), axis=0)
    A = np.array([[fe[:, 2].sum(), 1.0], [me[:, 1].sum(), tail_moment[1]]])
    wing_scale, tail_load = np.linalg.solve(A, [load_factor * weight, 0.0])
    loads = {"wing": {"force_per_length": wing_scale * f, "moment_per_length": wing_scale * mm},
             "tail": {"point_force": tail_load * tail_unit}}
    out = m.solve_inertia_relief(loads, supports=SUPPORTS, gravity=[0.0, 0.0, -G0])
    return {"wing_lift": float(wing_scale * fe[:, 2].sum()), "tail_load": float(tail_load),
            "accelerations": out["accelerations"], "x": out["x"],
            "loads": monitoring_loads(m.system, out["x"], monitoring_stations(aircraft))}


def natural_frequencies(aircraft: StickAircraft, count: int = 8) -> dict:
    """The free half aircraft's modes about the jig (the flutter linearization,
    :func:`wingmdao.stability.eigen.eigenmodes`): ``rigid`` (the number of zero-frequency modes:
    3) and the lowest ``count`` elastic frequencies ``hz`` with the share of each beam in the mode's
    displacement (``shares``, {beam: fraction of the sum of squared nodal displacements}).

    Parameters
    ----------
    aircraft : StickAircraft
        The half aircraft (from :func:`build`).
    count : int
        Number of elastic frequencies.

    Returns
    -------
    dict
        ``rigid``, ``hz`` and ``shares`` as above.
    """
    m = aircraft.model
    s = m.system
    modes = eigenmodes(s, m.p, m.forcing(), s.jig_state(m.p), static=False, method="dense")
    lam = modes.eigenvalues
    zero = np.abs(lam) < 1e-6
    order = np.argsort(modes.frequency)
    elastic = [k for k in order if not zero[k] and modes.frequency[k] > 1e-3][:count]
    shares = []
    for k in elastic:
        v = modes.vectors[:, k]
        e = {b.name: float(np.sum(np.abs(v[[s.node_index(b.name, i) + c for i in range(b.num_nodes)
                                              for c in range(3)]]) ** 2)) for b in s.beams}
        tot = sum(e.values())
        shares.append({b: e[b] / tot for b in e})
    return {"rigid": int(np.sum(zero)) // 2, "hz": modes.frequency[elastic] / (2 * np.pi), "shares": shares}


@dataclass
class StickGust:
    """Gust response of the free half aircraft (:func:`gust_response`): ``time`` (s),
    ``load_factor`` (body-z aerodynamic force of wing and tail over W), ``trim`` (alpha_trim and tail_incidence in rad,
    thrust in N, half aircraft), ``loads`` ({station label: {"force", "moment"}: (n_time, 3) body
    axes, N and N m}) at :func:`monitoring_stations`, the downwash gradient used and the states.

    Parameters
    ----------
    time : numpy.ndarray
        Time steps (s), shape (n_time,).
    load_factor : numpy.ndarray
        Body-z aerodynamic force of wing and tail over W per time step.
    trim : dict
        ``alpha_trim`` and ``tail_incidence`` (rad), ``thrust`` (N, half aircraft).
    loads : dict
        ``{station label: {"force", "moment"}: (n_time, 3)}`` (body axes, N and N m).
    downwash_gradient : float
        The deps/dalpha used.
    states : numpy.ndarray
        The system's state history, shape (n_time, n_states).
    """

    time: np.ndarray
    load_factor: np.ndarray
    trim: dict
    loads: dict
    downwash_gradient: float
    states: np.ndarray


def downwash_gradient(mach: float) -> float:
    """deps/dalpha at the tail (assumption): ``2 a_w / (pi AR)`` (Etkin & Reid, *Dynamics of Flight*,
    3rd ed., 1996, Sec. 2.4; Nelson, *Flight Stability and Automatic Control*, 2nd ed., 1998,
    Sec. 2.4) with the strips' wing slope a_w = 2 pi / sqrt(1 - M^2) and the PEGASUS aspect ratio.

    Parameters
    ----------
    mach : float
        Flight Mach number (< 1).

    Returns
    -------
    float
        deps/dalpha at the tail.
    """
    pf = pegasus.PLANFORM
    aspect = (2 * pf.semi_span) ** 2 / (pf.area_ft2 * FT ** 2)
    return float(2 * (2 * np.pi / np.sqrt(1 - mach ** 2)) / (np.pi * aspect))


def aeroelastic_system(aircraft: StickAircraft):
    """The half aircraft's joined system with strip aerodynamics on the wing and the horizontal tail
    (:func:`wingmdao.aero.joined.build_joined_aeroelastic_system`, trim supports :data:`SUPPORTS`).

    Parameters
    ----------
    aircraft : StickAircraft
        The half aircraft (from :func:`build`).

    Returns
    -------
    wingmdao.timemarch.system.ResidualSystem
        The joined aeroelastic system.
    """
    s = aircraft.model.system
    return build_joined_aeroelastic_system(s.beams, s.joints, lifting=("wing", "tail"), supports=SUPPORTS,
                                           masses=s.masses, symmetry=s.symmetry, euler_sequence=s.euler_sequence)


def aero_parameters(aircraft: StickAircraft, system, *, airspeed, density, mach, downwash=None) -> np.ndarray:
    """Packed parameters of the aeroelastic ``system`` (:func:`aeroelastic_system`): the aircraft's
    beams, the wing's strip sections and :data:`TAIL_SECTION`, the flight point (m/s, kg/m^3) and
    the downwash gradient (default :func:`downwash_gradient`).

    Parameters
    ----------
    aircraft : StickAircraft
        The half aircraft (from :func:`build`).
    system : wingmdao.timemarch.system.ResidualSystem
        Its aeroelastic system (:func:`aeroelastic_system`).
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    mach : float
        Flight Mach number.
    downwash : float or None
        deps/dalpha at the tail; None: :func:`downwash_gradient`.

    Returns
    -------
    numpy.ndarray
        The packed parameter vector.
    """
    dw = downwash_gradient(mach) if downwash is None else float(downwash)
    return pack_aero_parameters(system, aircraft.model.params,
                                {"wing": {"chord": aircraft.wing_chord, "ref_point": aircraft.wing_axis_fraction},
                                 "tail": TAIL_SECTION},
                                airspeed=airspeed, density=density, mach=mach, downwash_gradient=dw)


def gust_forcing(aircraft: StickAircraft, system, time, *, airspeed, u_ds_tas, gradient, gust_start) -> np.ndarray:
    """Packed forcing history (n_time, n_forcing) of a 1-cos gust of gradient ``gradient`` (m) and
    design velocity ``u_ds_tas`` (m/s TAS) meeting the wing's leading station at ``gust_start`` (s),
    every lifting station x / V later; gravity; trim active at t = 0 only (:func:`gust_response`).

    Parameters
    ----------
    aircraft : StickAircraft
        The half aircraft (from :func:`build`).
    system : wingmdao.timemarch.system.ResidualSystem
        Its aeroelastic system (:func:`aeroelastic_system`).
    time : numpy.ndarray
        Time steps (s), shape (n_time,).
    airspeed : float
        True airspeed (m/s).
    u_ds_tas : float
        Gust design velocity (m/s TAS).
    gradient : float
        Gust gradient (m).
    gust_start : float
        Time the gust front meets the wing's leading station (s).

    Returns
    -------
    numpy.ndarray
        Forcing history, shape (n_time, n_forcing).
    """
    time = np.asarray(time, dtype=float)
    x_w, x_t = aircraft.nodes["wing"][:, 0], aircraft.nodes["tail"][:, 0]
    n_w = x_w.size
    length = 2.0 * gradient

    def profile(tau):
        inside = (tau >= 0.0) & (tau <= length / airspeed)
        return np.where(inside, 0.5 * u_ds_tas * (1.0 - np.cos(2.0 * np.pi * airspeed * tau / length)), 0.0)

    g = station_gust_history(time - gust_start, np.concatenate([x_w, x_t]), airspeed, profile)
    return np.array([pack_aero_forcing(system, {"wing": g[k, :n_w], "tail": g[k, n_w:]}, trim_active=float(k == 0),
                                       gravity=[0.0, 0.0, -G0]) for k in range(time.size)])


def maneuver_forcing(system, load_factor: float) -> np.ndarray:
    """Packed forcing (1, n_forcing) of the steady symmetric maneuver at load factor ``load_factor``
    of the free half aircraft (14 CFR 25.337 pull-up or push-over): gravity, the body axes
    accelerating upward at (n - 1) g (``frame_acceleration``) and the trim active, so that a
    static solve (a one-instant :class:`~wingmdao.groups.load_case.StickCase`) finds the angle of
    attack, tail incidence and thrust for which wing and tail lift n W with no pitching moment.

    Parameters
    ----------
    system : JoinedBeamSystem
        The aeroelastic system of :func:`aeroelastic_system`.
    load_factor : float
        n (finite, nonzero).

    Returns
    -------
    numpy.ndarray
        The forcing of the one instant, shape (1, n_forcing).
    """
    n = float(load_factor)
    if not np.isfinite(n) or n == 0.0:
        raise ValueError(f"load_factor = {load_factor}; must be a finite nonzero number (n of the maneuver)")
    return pack_aero_forcing(system, trim_active=1.0, gravity=[0.0, 0.0, -G0],
                             frame_acceleration=[0.0, 0.0, (n - 1.0) * G0])[None, :]


def gust_response(aircraft: StickAircraft, time, *, airspeed, density, mach, u_ds_tas, gradient, gust_start,
                  downwash=None, static_options=None) -> StickGust:
    """A 1-cos gust of gradient ``gradient`` (m) and design velocity ``u_ds_tas`` (m/s TAS) on the free
    half aircraft from its trimmed 1 g level flight (:mod:`wingmdao.aero.joined`: alpha_trim, tail
    incidence and thrust solved at t = 0, then held). The gust front reaches the wing's leading
    station at ``gust_start`` (s); every lifting station meets it x / V later. ``downwash``:
    deps/dalpha (default :func:`downwash_gradient`); ``static_options``: options of the trim's static
    solve (:func:`wingmdao.timemarch.bdf.march`, e.g. ``{"atol": 1e-9}``). The march is modified Newton
    (the Jacobian refactored only when the iterations stop contracting), as the sizing's.

    Parameters
    ----------
    aircraft : StickAircraft
        The half aircraft (from :func:`build`).
    time : numpy.ndarray
        Time steps (s), shape (n_time,).
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    mach : float
        Flight Mach number.
    u_ds_tas : float
        Gust design velocity (m/s TAS).
    gradient : float
        Gust gradient (m).
    gust_start : float
        Time the gust front meets the wing's leading station (s).
    downwash : float or None
        deps/dalpha at the tail; None: :func:`downwash_gradient`.
    static_options : dict or None
        Options of the trim's static solve.

    Returns
    -------
    StickGust
        The response.
    """
    time = np.asarray(time, dtype=float)
    s = aeroelastic_system(aircraft)
    dw = downwash_gradient(mach) if downwash is None else float(downwash)
    p = aero_parameters(aircraft, s, airspeed=airspeed, density=density, mach=mach, downwash=dw)
    Q = gust_forcing(aircraft, s, time, airspeed=airspeed, u_ds_tas=u_ds_tas, gradient=gradient, gust_start=gust_start)
    hist = march(s, time, p, Q, atol=1e-6, modified_newton=True, static_options=static_options)
    weight = aircraft.mass * G0
    n = np.array([lift_total(s, hist.states[k], hist.rates[k], p, Q[k], vertical=True) for k in range(time.size)]) / weight
    stations = monitoring_stations(aircraft)
    per_step = [monitoring_loads(s, x, stations) for x in hist.states]
    loads = {st.label: {k: np.array([ps[st.label][k] for ps in per_step]) for k in ("force", "moment")}
             for st in stations}
    x0 = hist.states[0]
    trim = {k: float(x0[i]) for k, i in s.trim_index.items()}
    return StickGust(time=time, load_factor=n, trim=trim, loads=loads, downwash_gradient=dw, states=hist.states)


def flutter_options(case: StickCase, factor: float, *, rho_ks: float = 100.0) -> dict:
    """Options of :class:`~wingmdao.components.flutter.StickFlutterDamping` for "flutter speed >=
    F V_D" of the free half aircraft of a stick ``case`` (its system and packed parameters; F =
    ``factor``): the damping constraint Re(lambda) <= 0 (KS, 1/s) at F V_D x (0.25, 0.5, 0.75, 1),
    the lone wing's speeds (:func:`wingmdao.stability.cases.sizing_flutter_options`: PEGASUS's
    V_D, density and speed of sound at 25 000 ft, its eigen window).

    Parameters
    ----------
    case : StickCase
        A load case of :func:`sizing_setup` (its ``system`` and ``p``).
    factor : float
        F, the flutter margin on V_D (14 CFR 25.629: 1.15).
    rho_ks : float
        KS aggregation parameter (s).

    Returns
    -------
    dict
        The component's options.
    """
    lone = sizing_flutter_options("pegasus", case.system.beam(case.wing).num_nodes, factor, rho_ks=rho_ks)
    p = np.array(case.p, dtype=float)
    p[layout(case.system.param_specs)["density"]] = lone["aero"]["density"]
    return {"system": case.system, "p": p, "speeds": lone["speeds"], "speed_of_sound": lone["aero"]["speed_of_sound"],
            "rho_ks": float(rho_ks), "eig_options": lone["eig_options"], "wing": case.wing}


def sized_beams(case: StickCase, names, *, lower: float = pegasus.MIN_GAUGE) -> list:
    """The beams ``names`` (of :data:`SIZABLE_BEAMS`) of the stick model of ``case`` as
    :class:`~wingmdao.groups.load_case.SizedBeam`: the horizontal tail as the box of
    :data:`TAIL_BOX`, the fuselage as the thin tube of :data:`FUSELAGE` (half of it in the half
    model), each with walls from ``lower`` to 0.05 m (tail) or 0.02 m (fuselage), starting at the
    assumed data's, and the nonstructural mass per length that keeps the beam's mass per length
    of :func:`build` at the start (so the lumped payload, and the aircraft's mass, are unchanged
    there).

    Parameters
    ----------
    case : StickCase
        A load case of :func:`sizing_setup` (its system and packed parameters).
    names : sequence of str
        Beams to size, from :data:`SIZABLE_BEAMS`.
    lower : float
        Minimum gauge of the walls (m).

    Returns
    -------
    list of SizedBeam
        The sized beams, in the order of ``names``.
    """
    bad = [b for b in names if b not in SIZABLE_BEAMS]
    if bad or len(set(names)) != len(names):
        raise ValueError(f"--size-beams: {', '.join(names)}; allowed: {', '.join(SIZABLE_BEAMS)} (each once; the "
                         "wing is always sized)")
    lay = layout(case.system.param_specs)
    p = np.asarray(case.p, dtype=float)
    out = []
    for name in names:
        r0 = p[lay[f"{name}_node_positions"]].reshape(-1, 3)
        mu = p[lay[f"{name}_mass_per_length"]]
        if name == "tail":
            w, h, t0 = TAIL_BOX["width"], TAIL_BOX["height"], TAIL_BOX["initial"]
            area = float(box_properties(w, h, t0, t0, t0, t0, ALUMINIUM, None, 0.0)["A"])
            out.append(SizedBeam(name, "box", r0, {"width": np.full(len(r0), w), "height": np.full(len(r0), h),
                                                   "nonstructural_mass_per_length": mu - ALUMINIUM.rho * area},
                                 initial=t0, lower=float(lower), upper=0.05))
        else:
            t0, R = FUSELAGE_TUBE["initial"], FUSELAGE["radius"]
            shell = 0.5 * ALUMINIUM.rho * 2 * np.pi * R * t0
            out.append(SizedBeam(name, "tube", r0, {"radius": R, "fraction": 0.5,
                                                    "nonstructural_mass_per_length": mu - shell},
                                 initial=t0, lower=float(lower), upper=FUSELAGE_TUBE["upper"]))
    return out


def check_gust_set(gset, source) -> None:
    """ValueError naming the flight point when a 25.341(a) gust set does not fit the stick model: a
    Mach number outside (0, 1), or a ``weight_lb`` other than the TOGW (the stick model's weight is
    its masses').

    Parameters
    ----------
    gset : wingmdao.loads.gust_set.GustSet
        The gust set.
    source : str
        The ``--gust-set`` file, for the messages.
    """
    for i, fp in enumerate(gset.flight_points):
        mach = fp.airspeed_tas() / float(speed_of_sound(fp.altitude_m))
        if not 0.0 < mach < 1.0:
            raise ValueError(f"--gust-set {source}: flight point {fp.name or i} has Mach {mach:.3g}; allowed "
                             "range (0, 1)")
        if fp.weight_lb is not None and not np.isclose(fp.weight_lb, pegasus.TOGW_LB, rtol=1e-9):
            raise ValueError(f"--gust-set {source}: flight point {fp.name or i} has weight_lb = "
                             f"{fp.weight_lb:g}; the stick model weighs the TOGW, {pegasus.TOGW_LB:g} lb (drop weight_lb)")


def stick_gust_set_cases(aircraft: StickAircraft, system, gset, opts, families=("vm",)) -> list:
    """One :class:`~wingmdao.groups.load_case.StickCase` per gust of the 25.341(a) gust set ``gset``
    (:class:`~wingmdao.loads.gust_set.GustSet`; ``--gust-set``): each flight point's airspeed,
    density and Mach number, the gust's U_ds (EAS, turned into TAS) and gradient, the time grid and
    gust start of ``opts``, marched from the trimmed 1 g state (:func:`gust_forcing`). ValueError
    naming the flight point for a Mach number outside (0, 1) or a ``weight_lb`` other than the TOGW
    (the stick model's weight is its masses').

    Parameters
    ----------
    aircraft : StickAircraft
        The half aircraft (from :func:`build`).
    system : wingmdao.timemarch.system.ResidualSystem
        Its aeroelastic system (:func:`aeroelastic_system`).
    gset : GustSet
        The gust set.
    opts : PegasusOptions
        The case's options (``t_final``, ``dt``, ``gust_start``, ``gust_set`` for the messages).
    families : tuple of str
        Stress families of every case's KS.

    Returns
    -------
    list of StickCase
        One case per gust, named as the set names its gusts.
    """
    rho0 = float(density(0.0))
    time = np.arange(0.0, opts.t_final + 0.5 * opts.dt, opts.dt)
    cases = []
    check_gust_set(gset, opts.gust_set)
    for g in gset.gusts():
        fp = g.flight_point
        rho, V = float(density(fp.altitude_m)), fp.airspeed_tas()
        mach = V / float(speed_of_sound(fp.altitude_m))
        p = aero_parameters(aircraft, system, airspeed=V, density=rho, mach=mach)
        Q = gust_forcing(aircraft, system, time, airspeed=V, u_ds_tas=g.sign * g.u_ds_eas * np.sqrt(rho0 / rho),
                         gradient=g.gradient_m, gust_start=opts.gust_start)
        cases.append(StickCase(g.name, system, time, p, Q, families=tuple(families)))
    return cases


def case_monitoring_loads(case: StickCase, states) -> dict:
    """The monitoring stations' loads (:func:`monitoring_stations`, :func:`~wingmdao.beam.joints.monitoring_loads`)
    over a stick case's state history ``states`` (n_time, n_state), e.g. a sizing's
    ``cases.<case>.states``: ``{label: {"force_n", "moment_n_m": (n_time, 3) body axes}}``.

    Parameters
    ----------
    case : StickCase
        A load case of :func:`sizing_setup` (its system and packed parameters).
    states : numpy.ndarray
        The case's state history, shape (n_time, n_state).

    Returns
    -------
    dict
        Per station label, the force (N) and moment (N m) histories.
    """
    s = case.system
    lay = layout(s.param_specs)
    r_own = np.asarray(case.p, dtype=float)[lay["fuselage_node_positions"]].reshape(-1, 3)
    body = (np.asarray(FUSELAGE_AXES, dtype=float).T @ r_own.T).T        # v_body = R^T v_beam
    stations = _stations(s, body[:, 0])
    per_step = [monitoring_loads(s, x, stations) for x in np.atleast_2d(np.asarray(states, dtype=float))]
    return {st.label: {"force_n": np.array([ps[st.label]["force"] for ps in per_step]),
                       "moment_n_m": np.array([ps[st.label]["moment"] for ps in per_step])} for st in stations}


#: ``--loads`` sets of the stick sizing (:func:`sizing_setup`)
STICK_LOAD_SETS = ("maneuver", "gust", "all")


def sizing_setup(setup, opts, families=("vm",)):
    """The PEGASUS sizing ``setup`` (:func:`wingmdao.cases.pegasus.build`) with its load cases on the
    stick model instead of the lone wing: a copy whose ``load_cases`` are
    :class:`~wingmdao.groups.load_case.StickCase` and whose ``geometry`` is the stick model's wing
    (its engines are lumped masses, not smeared). ``--loads maneuver``: the 14 CFR 25.337 pull-up
    (``--load-factor``, 2.5) and push-over (``--negative-load-factor``, -1.0), each a static solve of
    the free half aircraft trimmed at n (:func:`maneuver_forcing`) at the ``--altitude-ft`` /
    ``--mach`` flight point; ``--loads gust``: the single 1-cos gust (gradient, altitude, Mach, sign,
    time grid and gust start of ``opts``) marched from the trimmed 1 g state; ``--loads all``: the
    three. The lumped payload masses are those of the initial walls (:func:`build`): the aircraft's
    mass follows the wing's. ValueError for options the stick sizing does not take.

    Parameters
    ----------
    setup : CaseSetup
        The lone wing's setup of the same options.
    opts : PegasusOptions
        The case's options.
    families : tuple of str
        Stress families of every case's KS.

    Returns
    -------
    CaseSetup
        The copy with the stick cases (maneuvers first, then the gust).
    """
    loads = opts.loads or "maneuver"
    if loads not in STICK_LOAD_SETS or getattr(opts, "gust_gradients_ft", None) \
            or getattr(opts, "gust_gradient_count", None) or getattr(opts, "load_history", None):
        raise ValueError(f"--model stick: sizes for the 25.337 maneuvers and the 1-cos gusts of one "
                         f"--gust-gradient-ft or of a --gust-set (--loads {', '.join(STICK_LOAD_SETS)}); got --loads "
                         f"{opts.loads}")
    if setup.section != "box":
        raise ValueError(f"--model stick: box walls only, got section {setup.section!r}")
    n = setup.geometry.num_nodes
    alt = float(altitude_ft_to_m(opts.altitude_ft))
    rho = float(density(alt))
    V = float(mach_to_tas(opts.mach, alt))
    aircraft = build(n)
    s = aeroelastic_system(aircraft)
    p = aero_parameters(aircraft, s, airspeed=V, density=rho, mach=float(opts.mach))
    cases, what = [], []
    if loads in ("maneuver", "all"):
        for name, n_load in (("maneuver_pos", opts.load_factor), ("maneuver_neg", opts.negative_load_factor)):
            cases.append(StickCase(name, s, np.zeros(1), p, maneuver_forcing(s, n_load), families=tuple(families)))
        what.append(f"trimmed maneuvers n = {opts.load_factor:+g}, {opts.negative_load_factor:+g}")
    gset = pegasus.gust_set_of(opts) if loads in ("gust", "all") and getattr(opts, "gust_set", None) else None
    if gset is not None:
        cases += stick_gust_set_cases(aircraft, s, gset, opts, families)
        what.append(f"gust set {opts.gust_set} ({len(gset)} gusts)")
    elif loads in ("gust", "all"):
        u_ds = (opts.u_ref_fps * FT * (opts.gust_gradient_ft / 350.0) ** (1.0 / 6.0) if opts.u_ref_fps > 0
                else design_gust_velocity_eas(opts.gust_gradient_ft, opts.altitude_ft, 1.0))
        sign = -1.0 if opts.gust_sign == "down" else 1.0
        u_tas = sign * u_ds * np.sqrt(float(density(0.0)) / rho)
        time = np.arange(0.0, opts.t_final + 0.5 * opts.dt, opts.dt)
        Q = gust_forcing(aircraft, s, time, airspeed=V, u_ds_tas=u_tas, gradient=opts.gust_gradient_ft * FT,
                         gust_start=opts.gust_start)
        cases.append(StickCase("gust", s, time, p, Q, families=tuple(families)))
        what.append(f"1-cos gust U_ds = {u_ds / FT:.1f} ft/s EAS, H = {opts.gust_gradient_ft:g} ft")
    geo = wing_geometry(pegasus.flutter_planform(n), ())[0]
    notes = [k for k in setup.notes if not k.startswith("warning: ignored with --loads maneuver")]
    if loads == "maneuver":   # the stick model's maneuvers use the flight point
        default = pegasus.PegasusOptions()
        ignored = [pegasus._flag_text(k, getattr(opts, k)) for k in pegasus.GUST_ONLY_OPTIONS
                   if k not in ("altitude_ft", "mach") and getattr(opts, k) != getattr(default, k)]
        if ignored:
            notes.append(f"warning: ignored with --loads maneuver (gust options): {', '.join(ignored)}")
    notes += [f"stick model: free half aircraft ({s.n_state} unknowns), {'; '.join(what)}, "
                                 f"V = {V:.1f} m/s TAS; payload lumped masses of the initial design"]
    return replace(setup, load_cases=cases, geometry=geo, notes=notes, flutter=None, turbulence=None)
