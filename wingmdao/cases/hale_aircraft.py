"""The Patil-Hodges-Cesnik HALE aircraft as a free symmetric half stick model, trimmed in level flight.

Data: M. J. Patil, D. H. Hodges, C. E. S. Cesnik, "Nonlinear aeroelasticity and flight dynamics
of high-altitude long-endurance aircraft", J. Aircraft 38(1), 2001, Sec. "Aircraft" and Table 1,
as the aircraft model of AeroBeams.jl states it (github.com/luizpancini/AeroBeams.jl,
``create_conventional_HALE``; data only, no code taken):

* **wing**: the HALE wing of :mod:`wingmdao.cases.hale` (32 m span, chord 1 m, beam axis and
  mass centre at 50 % chord, EI flap 2e4, EI lag 4e6, GJ 1e4 N m^2, 0.75 kg/m, 0.1 kg m), straight
  and untwisted, flat-plate sections (lift slope 2 pi, no camber);
* **payload**: 50 kg with rotary inertia 200 kg m^2 about each axis at the wing's root;
* **tail boom**: 10 m from the wing's root straight aft, rigid, 0.08 kg/m;
* **horizontal tail**: 5 m span, chord 0.5 m, beam axis at 50 % chord, at the boom's end; rigid,
  0.08 kg/m; flat plate;
* **vertical tail**: 2.5 m high at the boom's end, rigid, 0.08 kg/m; it lifts nothing in
  symmetric flight and enters as a lumped mass at its mid-height;
* flight at 20 km: air density 0.0889 kg/m^3; thrust at the wing's root along body x.

The model (body axes x aft along the flight path, y right, z up; origin at the wing root's beam
axis): beams ``wing`` (free root), ``boom`` (along body x, :data:`~wingmdao.beam.joints.FUSELAGE_AXES`,
free root) and ``tail`` (one side's horizontal tail), rigid joints wing root - boom node 0 and
boom end - tail root, symmetry conditions on every boom node. Members on the plane of symmetry
(boom, payload, vertical tail) carry half their mass. "Rigid" members are beams of stiffness
:data:`RIGID_STIFFNESS`. Trim (:mod:`wingmdao.aero.joined`, ``trim_rotation=True``): angle of
attack, tail incidence (the paper's elevator; a flat-plate tail's incidence and flap deflection
both only shift its lift) and thrust, with lift = W and zero pitching moment, the aircraft
pitched by alpha_trim so that a station bent to a slope phi sees ``atan(tan(alpha) cos(phi))``.
No downwash at the tail (strip theory, as in the paper).

Flight-path loads (:func:`trim`, ``flight_path_loads=True``, the default): the joined system's
trim keeps the air along body x and adds alpha_trim to every station's angle, so its lift (along
each section's normal) and the weight (along -z) are normal to the body's x axis. The aircraft
of the paper flies pitched by alpha: in body axes the air comes along ``(cos a, 0, sin a)``, each
station's lift is normal to it (tilted forward by a) and the weight is ``g (sin a, 0, -cos a)``.
On a wing whose tip is bent 8 m up, that forward tilt of the net load (lift minus the wing's
weight) twists the wing nose down about its root far more than the lift's 0.25 m offset ahead of
the beam axis twists it nose up; without it the elastic trim angle comes out 28 to 57 % below
the paper's. :func:`trim` adds both as loads of the joined system: the gravity vector and, on
every lifting station, the dead force ``L (l - n)`` per length (L its lift along its normal n, l
the unit vector normal to the air and the section's span axis), updated from the solved state
until alpha_trim is stationary (a fixed point; the converged state is the follower solution).

Published aircraft-level results used here (:data:`PUBLISHED_TRIM`): the trimmed angle of attack
against airspeed of the rigid and of the elastic aircraft, digitised from the paper's figure in
AeroBeams.jl (test/referenceData/conventionalHALE/trimAoAVsAirspeedRigid.txt and
trimAoAVsAirspeedElastic.txt), and the deflected wing at 25 m/s (trimDispAtU25.txt).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import openmdao.api as om

from wingmdao.aero.joined import build_joined_aeroelastic_system, lift_total, pack_aero_forcing, pack_aero_parameters
from wingmdao.beam.joints import FUSELAGE_AXES, Beam, Joint, LumpedMass, Symmetry
from wingmdao.beam.residual import STATE_BLOCKS
from wingmdao.beam.rotations import body_to_csn, euler_from_axis
from wingmdao.beam.static import beam_parameters
from wingmdao.cases import hale
from wingmdao.cases.planform import G0
from wingmdao.timemarch.bdf import solve_static
from wingmdao.timemarch.system import layout

#: Payload (full aircraft): mass (kg) and rotary inertia about each axis (kg m^2), at the wing root.
PAYLOAD_MASS = 50.0
PAYLOAD_INERTIA = 200.0
#: Tail boom: length (m), mass per length (kg/m).
BOOM_LENGTH = 10.0
BOOM_MASS = 0.08
#: Horizontal tail: span (m, both sides), chord (m), beam axis (fraction of chord), mass (kg/m).
TAIL_SPAN = 5.0
TAIL_CHORD = 0.5
TAIL_AXIS = 0.5
TAIL_MASS = 0.08
#: Vertical tail: height (m), mass per length (kg/m).
FIN_HEIGHT = 2.5
FIN_MASS = 0.08
#: Bending and torsion stiffness (N m^2) of the members the paper takes as rigid, and their EA (N).
RIGID_STIFFNESS = 1.0e8
RIGID_EA = 1.0e10
#: Wing stiffness factor of the "rigid" aircraft (its bending, torsion and lag stiffness times this).
RIGID_FACTOR = 1.0e4
#: Trim supports (surge and plunge of the wing root, plunge of the boom's end).
SUPPORTS = (("boom", 0, "x"), ("boom", 0, "z"), ("boom", -1, "z"))
#: Flight-path loads fixed point (:func:`trim`): tolerance on alpha_trim (rad) and most updates.
FLIGHT_PATH_TOL = 1e-9
FLIGHT_PATH_ITERATIONS = 80

#: Published trim (Patil, Hodges & Cesnik 2001, figure of the trimmed angle of attack vs airspeed;
#: digitised in AeroBeams.jl test/referenceData/conventionalHALE; digitising error ~1 %).
PUBLISHED_TRIM = {
    "source": "Patil, Hodges & Cesnik, J. Aircraft 38(1), 2001 (figure; digitised in AeroBeams.jl "
              "test/referenceData/conventionalHALE)",
    "rigid": {"airspeed_m_s": [20.105, 20.398, 20.655, 21.016, 21.394, 21.823, 22.356, 22.872, 23.422, 24.007,
                               24.592, 25.263, 25.986, 26.640, 27.467, 28.156, 28.965, 29.723, 30.550, 31.342,
                               32.032, 32.479],
              "alpha_deg": [11.390, 11.095, 10.816, 10.451, 10.069, 9.6515, 9.1820, 8.7300, 8.3127, 7.8954,
                            7.5476, 7.1303, 6.7826, 6.4174, 6.0523, 5.7741, 5.4437, 5.1829, 4.8874, 4.6613,
                            4.4701, 4.3136]},
    "elastic": {"airspeed_m_s": [20.096, 20.437, 20.821, 21.221, 21.724, 22.080, 22.583, 23.058, 23.576, 24.155,
                                 24.733, 25.342, 25.936, 26.426, 27.138, 27.792, 28.490, 29.040, 29.783, 30.348,
                                 30.987, 31.671, 32.415],
                "alpha_deg": [14.802, 14.307, 13.736, 13.076, 12.340, 11.845, 11.215, 10.644, 10.059, 9.4586,
                              8.9332, 8.4229, 7.9726, 7.5673, 7.1020, 6.7118, 6.3215, 5.9913, 5.6611, 5.4209,
                              5.1808, 4.9256, 4.7005]},
    # the trimmed elastic wing at 25 m/s: spanwise (m, from the root) and vertical (m) positions
    "deflected_wing_25_m_s": {
        "span_m": [0.12764, 0.72707, 1.4842, 2.2890, 3.1413, 3.7728, 4.5785, 5.4158, 6.2060, 6.9805, 7.7079,
                   8.3406, 9.0047, 9.7007, 10.333, 10.919, 11.488, 12.026, 12.643, 13.134, 13.593],
        "vertical_m": [0.068294, 0.14601, 0.23919, 0.41127, 0.63064, 0.85049, 1.2280, 1.6369, 2.0934, 2.5500,
                       3.0698, 3.5424, 4.0150, 4.5507, 5.0391, 5.5434, 5.9846, 6.4732, 6.9617, 7.4030, 7.7812]},
}


@dataclass
class HaleAircraft:
    """The free half aircraft.

    Parameters
    ----------
    system : JoinedBeamSystem
        Its aeroelastic residual system (trim with ``trim_rotation``).
    params : dict
        The beams' parameter dicts by beam name (SI).
    mass : float
        Mass of the half aircraft (kg).
    stiffness_factor : float
        The wing's bending and torsion stiffness factor.
    """

    system: object
    params: dict
    mass: float
    stiffness_factor: float

    def with_wing_stiffness(self, stiffness_factor: float) -> HaleAircraft:
        """The same aircraft (same system, no rebuild) with the wing's bending and torsion
        stiffness times ``stiffness_factor``.

        Parameters
        ----------
        stiffness_factor : float
            Stiffness factor (> 0; :data:`RIGID_FACTOR`: the rigid aircraft).

        Returns
        -------
        HaleAircraft
            The aircraft with the new wing parameters.
        """
        n = self.system.beam("wing").num_nodes
        params = dict(self.params, wing=hale.beam_params(n, stiffness_factor))
        return replace(self, params=params, stiffness_factor=float(stiffness_factor))


def _rotary(factor):
    """Rotary inertia per length (kg m, csn) of the boom and tails: a tenth of the wing's."""
    i_flap = hale.INERTIA * hale.EI_FLAP / hale.EI_LAG
    return factor * np.diag([i_flap, hale.INERTIA, hale.INERTIA - i_flap]) / 10.0


def build(num_wing_nodes: int = 17, num_boom_nodes: int = 6, num_tail_nodes: int = 4,
          stiffness_factor: float = 1.0) -> HaleAircraft:
    """The free symmetric half aircraft (module docstring).

    Parameters
    ----------
    num_wing_nodes, num_boom_nodes, num_tail_nodes : int
        Nodes of the half wing (>= 3), the boom (>= 2) and the half horizontal tail (>= 2).
    stiffness_factor : float
        Multiplies the wing's bending and torsion stiffness (> 0; :data:`RIGID_FACTOR` for the
        rigid aircraft).

    Returns
    -------
    HaleAircraft
    """
    if not (np.isfinite(stiffness_factor) and stiffness_factor > 0.0):
        raise ValueError(f"stiffness_factor = {stiffness_factor}; must be a finite number > 0")
    for name, n, low in (("num_wing_nodes", num_wing_nodes, 3), ("num_boom_nodes", num_boom_nodes, 2),
                         ("num_tail_nodes", num_tail_nodes, 2)):
        if int(n) != n or n < low:
            raise ValueError(f"{name} = {n}; must be an integer >= {low}")
    nw, nb, nt = int(num_wing_nodes), int(num_boom_nodes), int(num_tail_nodes)
    wing = hale.beam_params(nw, stiffness_factor)
    xb = np.linspace(0.0, BOOM_LENGTH, nb)
    boom_body = np.column_stack([xb, 0 * xb, 0 * xb])
    half = 0.5        # the boom lies on the plane of symmetry: the half model carries half of it
    boom = beam_parameters((np.array(FUSELAGE_AXES) @ boom_body.T).T, np.tile(euler_from_axis((0.0, 1.0, 0.0)), (nb, 1)),
                           EI_cc=half * RIGID_STIFFNESS, EI_nn=half * RIGID_STIFFNESS, GJ=half * RIGID_STIFFNESS,
                           EA=half * RIGID_EA, mass_per_length=half * BOOM_MASS, inertia_per_length=_rotary(half))
    yt = np.linspace(0.0, 0.5 * TAIL_SPAN, nt)
    tail = beam_parameters(np.column_stack([np.full(nt, BOOM_LENGTH), yt, 0 * yt]),
                           np.tile(euler_from_axis((0.0, 1.0, 0.0)), (nt, 1)),
                           EI_cc=RIGID_STIFFNESS, EI_nn=RIGID_STIFFNESS, GJ=RIGID_STIFFNESS, EA=RIGID_EA,
                           mass_per_length=TAIL_MASS, inertia_per_length=_rotary(1.0))
    fin_mass = half * FIN_MASS * FIN_HEIGHT
    i_fin = fin_mass * FIN_HEIGHT ** 2 / 12.0
    masses = (LumpedMass("wing", 0, half * PAYLOAD_MASS, inertia=np.eye(3) * half * PAYLOAD_INERTIA),
              LumpedMass("boom", -1, fin_mass, offset=(0.0, 0.0, 0.5 * FIN_HEIGHT),
                         inertia=np.diag([i_fin, i_fin, 0.0])))
    beams = [Beam("wing", nw, root="free"), Beam("boom", nb, root="free", axes=FUSELAGE_AXES),
             Beam("tail", nt, root="free")]
    joints = [Joint("boom", 0, "wing", 0), Joint("boom", -1, "tail", 0)]
    symmetry = [Symmetry("boom", i) for i in range(nb)]
    system = build_joined_aeroelastic_system(beams, joints, lifting=("wing", "tail"), wing="wing", tail="tail",
                                             supports=SUPPORTS, masses=masses, symmetry=symmetry,
                                             trim_rotation=True)
    params = {"wing": wing, "boom": boom, "tail": tail}
    mass = (hale.MASS * hale.SEMI_SPAN + half * PAYLOAD_MASS + half * BOOM_MASS * BOOM_LENGTH
            + TAIL_MASS * 0.5 * TAIL_SPAN + fin_mass)
    return HaleAircraft(system=system, params=params, mass=float(mass), stiffness_factor=float(stiffness_factor))


def _parameters(aircraft, airspeed):
    return pack_aero_parameters(aircraft.system, aircraft.params,
                                {"wing": {"chord": hale.CHORD, "ref_point": hale.ELASTIC_AXIS},
                                 "tail": {"chord": TAIL_CHORD, "ref_point": TAIL_AXIS}},
                                airspeed=airspeed, density=hale.DENSITY, mach=0.0, downwash_gradient=0.0)


def _node_frames(system, x, name):
    """(n, 3, 3) body-to-csn matrices of the deformed sections of beam ``name`` (rows c, s, n)."""
    th = STATE_BLOCKS["theta"]
    return np.array([body_to_csn(np.asarray(x[system.node_index(name, i) + th.start:system.node_index(name, i) + th.stop]))
                     for i in range(system.beam(name).num_nodes)])


def _air_lift(system, x, p, q, alpha):
    """Each lifting station's lift (N/m, along its normal in the model), its section frames and
    the unit vectors normal to the pitched air ``(cos a, 0, sin a)`` and to its span axis."""
    air = np.array([np.cos(alpha), 0.0, np.sin(alpha)])
    out = {}
    for name, (lift, _moment, _up) in system.section_loads(x, 0 * x, p, q).items():
        frames = _node_frames(system, x, name)
        normal_to_air = np.cross(air, frames[:, 1])
        normal_to_air /= np.linalg.norm(normal_to_air, axis=1)[:, None]
        normal_to_air *= np.sign(np.einsum("ij,ij->i", normal_to_air, frames[:, 2]))[:, None]
        out[name] = (lift, frames, normal_to_air)
    return out


def _flight_path_forcing(system, q, x, p, alpha, load_factor, drag_coefficient=0.0):
    """The forcing ``q`` with the weight in the pitched body axes, the lift tilt loads of the
    state ``x`` (module docstring, flight-path loads) and the section drag (``drag_coefficient``,
    along the air's component in each section's plane)."""
    lay, play = layout(system.forcing_specs), layout(system.param_specs)
    p = np.asarray(p, dtype=float)
    q = np.array(q, dtype=float)
    q[lay["gravity"]] = G0 * float(load_factor) * np.array([np.sin(alpha), 0.0, -np.cos(alpha)])
    air = np.array([np.cos(alpha), 0.0, np.sin(alpha)])
    qdyn = 0.5 * p[play["density"]].item() * p[play["airspeed"]].item() ** 2
    for name, (lift, frames, normal_to_air) in _air_lift(system, x, p, q, alpha).items():
        in_plane = air[None, :] - (frames[:, 1] @ air)[:, None] * frames[:, 1]
        speed2 = np.einsum("ij,ij->i", in_plane, in_plane)
        drag = (qdyn * drag_coefficient * p[play[f"{name}_chord"]] * np.sqrt(speed2))[:, None] * in_plane
        q[lay[f"{name}_force_per_length"]] = (lift[:, None] * (normal_to_air - frames[:, 2]) + drag).ravel()
    return q


def _vertical_lift(system, x, p, q, alpha, flight_path_loads):
    """Integrated aerodynamic force (N) normal to the flight path of the modelled half aircraft."""
    if not flight_path_loads:
        return lift_total(system, x, 0 * x, p, q, vertical=True)
    up = np.array([-np.sin(alpha), 0.0, np.cos(alpha)])
    play = layout(system.param_specs)
    total = 0.0
    for name, (lift, _frames, normal_to_air) in _air_lift(system, x, p, q, alpha).items():
        f = lift * (normal_to_air @ up)
        ds = np.linalg.norm(np.diff(np.asarray(p)[play[f"{name}_node_positions"]].reshape(-1, 3), axis=0), axis=1)
        total += float(np.sum(0.5 * (f[:-1] + f[1:]) * ds))
    return total


def trim(aircraft: HaleAircraft, airspeed: float, x0=None, load_steps: int = 8, load_factor: float = 1.0,
         flight_path_loads: bool = True, drag_coefficient: float = 0.0) -> dict:
    """Trimmed level flight of the free half aircraft at ``airspeed`` (m/s): lift = W, zero
    pitching moment, by angle of attack, tail incidence and thrust.

    Parameters
    ----------
    aircraft : HaleAircraft
    airspeed : float
        True airspeed, m/s (> 0).
    x0 : ndarray, optional
        Initial guess (a trimmed state at a nearby airspeed); without it gravity is applied in
        ``load_steps`` steps from the jig.
    load_steps : int
        Gravity steps from the jig (unused with ``x0``).
    load_factor : float
        Gravity times this (> 0; lift = ``load_factor`` W; a small value gives the linear limit).
    flight_path_loads : bool
        True: the weight and the lift in the pitched body axes (module docstring), iterated to
        the fixed point; False: lift along the section normals and weight along body -z.
    drag_coefficient : float
        Section drag coefficient of the wing and tail strips (>= 0; with ``flight_path_loads``;
        the paper's aircraft data as stated here have none), balanced by the thrust.

    Returns
    -------
    dict
        ``alpha_deg`` (trim angle of attack, deg), ``tail_incidence_deg`` (deg), ``thrust`` (N,
        half aircraft), ``lift_over_weight`` (lift normal to the flight path over ``load_factor``
        W), ``wing`` (deformed wing beam-axis positions, (n, 3) m, body axes), ``tip_deflection``
        (m, body z), ``updates`` (flight-path load updates) and the state ``x``.
    """
    if not (np.isfinite(airspeed) and airspeed > 0.0):
        raise ValueError(f"airspeed = {airspeed} m/s; must be a finite number > 0")
    if not (np.isfinite(load_factor) and load_factor > 0.0):
        raise ValueError(f"load_factor = {load_factor}; must be a finite number > 0")
    if not (np.isfinite(drag_coefficient) and drag_coefficient >= 0.0):
        raise ValueError(f"drag_coefficient = {drag_coefficient}; must be a finite number >= 0")
    if drag_coefficient and not flight_path_loads:
        raise ValueError(f"drag_coefficient = {drag_coefficient} needs flight_path_loads=True")
    s = aircraft.system
    p = _parameters(aircraft, airspeed)
    g = [0.0, 0.0, -G0 * float(load_factor)]
    q = pack_aero_forcing(s, trim_active=1.0, gravity=g)
    label = f"HALE trim at {airspeed} m/s"
    if x0 is None:
        x, _ = solve_static(s, p, q, load_steps=load_steps, scaled=["gravity"], max_halvings=8, atol=1e-9,
                            label=label)
    else:
        x = np.asarray(x0, dtype=float)
        if not flight_path_loads:
            x, _ = solve_static(s, p, q, x, atol=1e-9, label=label)
    ti = s.trim_index
    alpha = float(x[ti["alpha_trim"]])
    updates = 0
    step = np.inf
    while flight_path_loads and abs(step) >= FLIGHT_PATH_TOL:
        if updates == FLIGHT_PATH_ITERATIONS:
            raise om.AnalysisError(f"{label}: flight-path loads not converged after {FLIGHT_PATH_ITERATIONS} "
                                   f"updates (last alpha_trim step {step:.2e} rad)")
        q = _flight_path_forcing(s, q, x, p, alpha, load_factor, drag_coefficient)
        x, _ = solve_static(s, p, q, x, atol=1e-9, label=label)
        step, alpha = float(x[ti["alpha_trim"]]) - alpha, float(x[ti["alpha_trim"]])
        updates += 1
    if flight_path_loads:
        q = _flight_path_forcing(s, q, x, p, alpha, load_factor, drag_coefficient)
    lift = _vertical_lift(s, x, p, q, alpha, flight_path_loads) / float(load_factor)
    r = np.array([x[s.node_index("wing", i) + STATE_BLOCKS["r"].start:
                    s.node_index("wing", i) + STATE_BLOCKS["r"].stop] for i in range(s.beam("wing").num_nodes)])
    return {"alpha_deg": float(np.degrees(alpha)),
            "tail_incidence_deg": float(np.degrees(x[ti["tail_incidence"]])), "thrust": float(x[ti["thrust"]]),
            "lift_over_weight": float(lift / (aircraft.mass * G0)), "wing": r,
            "tip_deflection": float(r[-1, 2] - r[0, 2]), "updates": updates, "x": x}


def trim_sweep(aircraft: HaleAircraft, airspeeds, start: float = 25.0, flight_path_loads: bool = True,
               drag_coefficient: float = 0.0) -> dict:
    """:func:`trim` at each of ``airspeeds`` (m/s): first at ``start`` from the jig (gravity
    steps), then outward from it, each airspeed from its neighbour's state nearer ``start``
    (continuation). An airspeed whose trim does not converge ends its side of the sweep.

    Parameters
    ----------
    aircraft : HaleAircraft
        The aircraft (:func:`build`).
    airspeeds : array_like
        Airspeeds (m/s).
    start : float, optional
        The airspeed trimmed first from the jig (m/s).
    flight_path_loads, drag_coefficient : optional
        Passed to :func:`trim`.

    Returns
    -------
    dict
        ``{airspeed: trim result}`` (:func:`trim`) of the converged airspeeds, and under
        ``"failed"`` ``{airspeed: message}`` of the first that did not converge on each side.
    """
    speeds = sorted(float(v) for v in airspeeds)
    out = {"failed": {}}
    opts = {"flight_path_loads": flight_path_loads, "drag_coefficient": drag_coefficient}
    x_start = trim(aircraft, float(start), **opts)["x"]
    for side in ([v for v in speeds if v >= start], [v for v in reversed(speeds) if v < start]):
        x = x_start
        for v in side:
            try:
                res = trim(aircraft, v, x0=x, **opts)
            except om.AnalysisError as exc:
                out["failed"][v] = str(exc).splitlines()[0]
                break
            out[v] = res
            x = res["x"]
    return out


__all__ = ["build", "trim", "trim_sweep", "HaleAircraft", "PUBLISHED_TRIM", "RIGID_FACTOR", "SUPPORTS"]
