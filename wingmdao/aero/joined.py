"""Unsteady strip aerodynamics on the lifting beams of a joined stick model, with trim of the free aircraft.

:func:`build_joined_aeroelastic_system` adds to the joined beams of :mod:`wingmdao.beam.joints`
(a :class:`~wingmdao.beam.joints.JoinedBeamSystem`, so the BDF march, the static solve, the
discrete adjoint and the flutter linearization run on it unchanged):

* on every node of every **lifting beam** (the wing, the horizontal tail; beams in body axes)
  the strip-section model of the lone wing (:func:`wingmdao.aero.system.node_aero`,
  :func:`wingmdao.aero.strip.section_model`): quasi-steady angle from the node's own motion,
  Wagner and Kuessner lag states (4 per node), apparent mass, follower lift and moment added to
  the node's distributed loads. Each station has its own gust velocity (forcing
  ``<beam>_gust_velocity``, its penetration delay x / V included, as
  :func:`~wingmdao.aero.strip.station_gust_history` gives it);
* **swept strips** (``normal_flow=True``): each strip's aerodynamics on the velocity component
  normal to its lifting beam's jig axis, V_n = V cos(Lambda), sin(Lambda) = s_x the body-x
  component of the node's jig span axis (simple sweep theory, the independence principle of
  R. T. Jones, "Wing plan-forms for high-speed flight", NACA Report 863, 1947; the strip theory
  of sections normal to the elastic axis of J. G. Barmby, H. J. Cunningham, I. E. Garrick,
  "Study of effects of sweep on the flutter of cantilever wings", NACA Report 1014, 1951, without
  its spanwise-flow terms): the dynamic pressure 1/2 rho V_n^2 of the circulatory lift and the
  cm0 moment, the Wagner and Kuessner time constants b / (B V_n), and the aircraft's angle
  (alpha_trim, tail incidence and downwash) as the normal section's angle alpha / cos(Lambda)
  (the normal velocity V alpha over V_n). The angles from the node's motion and gust are
  already the normal section's (v_n / v_c, v_c = V cos(Lambda) for a jig section). Steady lift
  per beam length 1/2 rho V^2 c_n a alpha cos(Lambda) (c_n the chord normal to the beam; per
  unit span the lift slope a cos(Lambda) on the streamwise chord). Default False: the full
  airspeed, the angle alpha (unswept beams are the same either way);
* the **downwash at the tail**: the tail's stations lose ``deps/dalpha e``, e the wing root's
  angle ``alpha_w = alpha_trim + (alpha_root - alpha_root,jig) + w_g,root / V`` (alpha_root =
  v_n / v_c of the root section's relative air velocity) lagged by the time the air takes from
  the wing root to the tail root, ``((x_t - x_w) / V) de/dt + e = alpha_w`` (as the free pitch of
  :mod:`wingmdao.aero.pitch`);
* **trim** of the free aircraft (trim unknowns in the residual, as the lone wing's trim): the
  aircraft angle of attack alpha_trim (added to every lifting station's angle; with
  ``trim_rotation`` a pitch of the aircraft, each station seeing :func:`trim_angle`), the tail
  incidence i_t (added to the tail's stations) and a thrust T along body x at the first support
  node. A tailless aircraft (``tail=None``) trims in pitch by an **elevon** instead
  (``elevon``: trailing-edge flaps on given stations, deflected by the same unknown; the strip's
  Theodorsen flap terms, :func:`wingmdao.aero.controls.flap_terms`). With the forcing ``trim_active`` = 1 their three rows hold the three ``supports``
  (body-axes displacements of nodes at the jig; a statically determinate support of the half
  aircraft's surge, plunge and pitch, as :func:`~wingmdao.beam.joints.solve_inertia_relief`'s):
  the free structure is then in equilibrium only if lift, thrust, weight and the inertia of the
  (optional) ``frame_acceleration`` balance, i.e. lift = n W and zero pitching moment about the
  CG, with no support reaction. With ``trim_active`` = 0 the rows are ``d/dt = 0``: the trim
  values are held and the aircraft is free. Set ``trim_active`` = 1 at t = 0 only: the march
  starts from the trimmed state.

State layout: the joined structure's (``system.n_struct`` unknowns), then the lag states of the
lifting beams (node-major, beam by beam, ``system.lag_index[beam]`` (n, 4)), then the downwash lag
(with a tail), then alpha_trim, tail_incidence, thrust (``system.trim_index``).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from wingmdao.aero.controls import theodorsen_flap_functions
from wingmdao.aero.strip import AERO_STATE_NAMES, N_AERO_STATES
from wingmdao.aero.system import check_aero_parameters, node_aero
from wingmdao.beam.joints import Beam, build_extended_joined_system
from wingmdao.beam.residual import NODE_PARAMS, STATE_BLOCKS
from wingmdao.beam.rotations import body_to_csn
from wingmdao.timemarch.system import VarSpec, layout
from wingmdao.utils.casadi_cache import definition_key

#: Per-station aerodynamic parameters of a lifting beam (``<beam>_<name>``, one value per node).
SECTION_PARAMS = ("chord", "ref_point", "lift_slope", "alpha_zero_lift", "cm0")
#: Trim unknowns, in state order (after the downwash lag).
TRIM_STATE_NAMES = ("alpha_trim", "tail_incidence", "thrust")
_XYZ = "xyz"
_GENERATING_MODULES = ("wingmdao.aero.joined", "wingmdao.aero.system", "wingmdao.aero.strip",
                       "wingmdao.beam.joints", "wingmdao.beam.residual", "wingmdao.beam.rotations",
                       "wingmdao.timemarch.system")


@dataclass(frozen=True)
class _Aero:
    """The extension of the joined residual (:func:`wingmdao.beam.joints.build_extended_joined_system`)."""

    beams: tuple
    lifting: tuple
    wing: str
    tail: str | None
    supports: tuple
    euler_sequence: str
    trim_rotation: bool = False
    elevon: tuple = ()           # ((beam, node, share), ...) stations with the elevon
    elevon_hinge: float = 0.75   # its hinge line, fraction of the chord
    normal_flow: bool = False    # swept strips on the velocity normal to the beam (module docstring)

    @property
    def counts(self):
        return {b.name: b.num_nodes for b in self.beams if b.name in self.lifting}

    @property
    def n_lag(self):
        return N_AERO_STATES * sum(self.counts.values())

    @property
    def n_states(self):
        return self.n_lag + (1 if self.tail else 0) + len(TRIM_STATE_NAMES)

    @property
    def param_specs(self):
        specs = []
        for name, n in self.counts.items():
            specs += [VarSpec(f"{name}_chord", (n,), "m", f"{name}: section chord at each node"),
                      VarSpec(f"{name}_ref_point", (n,), None, f"{name}: beam axis, fraction of chord aft of the "
                              "leading edge"),
                      VarSpec(f"{name}_lift_slope", (n,), "1/rad", f"{name}: incompressible section lift slope"),
                      VarSpec(f"{name}_alpha_zero_lift", (n,), "rad", f"{name}: section zero-lift angle"),
                      VarSpec(f"{name}_cm0", (n,), None, f"{name}: section moment coefficient about the quarter "
                              "chord (nose up +)")]
        specs += [VarSpec("airspeed", (), "m/s", "true airspeed V (free stream toward +x)"),
                  VarSpec("density", (), "kg/m**3", "air density"),
                  VarSpec("mach", (), None, "Mach number (Prandtl-Glauert factor on the lift slopes)")]
        if self.tail:
            specs.append(VarSpec("downwash_gradient", (), None, "downwash gradient deps/dalpha at the tail"))
        return specs

    @property
    def forcing_specs(self):
        specs = [VarSpec(f"{name}_gust_velocity", (n,), "m/s", f"{name}: gust velocity (body +z) at each station, "
                         "its penetration delay included") for name, n in self.counts.items()]
        return specs + [
            VarSpec("frame_velocity", (3,), "m/s", "velocity of the body axes relative to the trimmed flight"),
            VarSpec("frame_velocity_rate", (3,), "m/s**2", "rate of frame_velocity (apparent mass)"),
            VarSpec("trim_active", (), None, "1: solve the trim unknowns holding the supports; 0: hold the trim")]

    def definition(self, base):
        args = (base, self.lifting, self.wing, self.tail, self.supports, self.euler_sequence)
        if self.trim_rotation:      # the definitions without it as before
            args = args + ("trim_rotation",)
        if self.elevon:
            args = args + (("elevon", self.elevon, self.elevon_hinge),)
        if self.normal_flow:
            args = args + ("normal_flow",)
        return definition_key("wingmdao.aero.joined.build_joined_aeroelastic_system", args, _GENERATING_MODULES)

    def describe(self, k):
        if k < self.n_lag:
            i = 0
            for name, n in self.counts.items():
                if k < i + N_AERO_STATES * n:
                    node, j = divmod(k - i, N_AERO_STATES)
                    return f"beam {name}: node {node}, lag state {AERO_STATE_NAMES[j]}"
                i += N_AERO_STATES * n
        k -= self.n_lag
        if self.tail:
            if k == 0:
                return "downwash lag at the tail"
            k -= 1
        name = "elevon" if TRIM_STATE_NAMES[k] == "tail_incidence" and self.elevon else TRIM_STATE_NAMES[k]
        return f"trim: {name} (support {self.supports[k]} while trimming)"

    def flap(self, name, i, incidence, incidence_rate):
        """The elevon's ``flap`` argument of :func:`~wingmdao.aero.system.node_aero` at station
        ``i`` of beam ``name`` (None: no elevon there)."""
        share = {(b, n): w for b, n, w in self.elevon}.get((name, i))
        if share is None:
            return None
        return (theodorsen_flap_functions(self.elevon_hinge), share * incidence, share * incidence_rate, 0.0)

    def apply(self, nodes, x, xdot, p, q, play, qlay, n_struct):
        """Add the section loads to the lifting beams' nodes and return the extension's rows."""
        seq = self.euler_sequence
        i_lag = n_struct
        i_dw = n_struct + self.n_lag
        i_trim = i_dw + (1 if self.tail else 0)
        alpha_trim, incidence, thrust = (x[i_trim + k] for k in range(3))
        V, rho, mach = p[play["airspeed"]], p[play["density"]], p[play["mach"]]
        vf, dvf = q[qlay["frame_velocity"]], q[qlay["frame_velocity_rate"]]
        omega, domega = q[qlay["frame_angular_velocity"]], q[qlay["frame_angular_acceleration"]]
        frame = (vf, dvf, omega, domega)
        on = q[qlay["trim_active"]]
        st = STATE_BLOCKS
        rows = []
        wing_root = nodes[self.wing]
        root_angle = self._root_angle(wing_root["x"][0], wing_root["p"][0], vf, omega, V, seq)
        if self.tail:
            gust_root = q[qlay[f"{self.wing}_gust_velocity"]][0]
            alpha_w = alpha_trim + root_angle + gust_root / V
            x_w = wing_root["p"][0][NODE_PARAMS["r0"]][0]
            x_t = nodes[self.tail]["p"][0][NODE_PARAMS["r0"]][0]
            e = x[i_dw]
            downwash_row = ((x_t - x_w) / V) * xdot[i_dw] + e - alpha_w
        k = i_lag
        for name, n in self.counts.items():
            nd = nodes[name]
            gust = q[qlay[f"{name}_gust_velocity"]]
            for i in range(n):
                shift = trim_angle(alpha_trim, nd["x"][i][st["theta"]], seq) if self.trim_rotation else alpha_trim
                if name == self.tail:
                    shift = shift + incidence - p[play["downwash_gradient"]] * e
                speed = None
                if self.normal_flow:
                    cos_sweep = sweep_cosine(nd["p"][i][NODE_PARAMS["theta0"]], seq)
                    shift, speed = shift / cos_sweep, V * cos_sweep
                pa = ca.vertcat(*[p[play[f"{name}_{s}"]][i] for s in SECTION_PARAMS[:3]],
                                p[play[f"{name}_alpha_zero_lift"]][i] - shift, p[play[f"{name}_cm0"]][i], gust[i])
                xa = ca.vertcat(nd["x"][i], x[k:k + N_AERO_STATES])
                xda = ca.vertcat(nd["xdot"][i], xdot[k:k + N_AERO_STATES])
                f, m, res, _lift, _moment, _ = node_aero(xa, xda, pa, None, frame, V, rho, mach, seq,
                                                         self.flap(name, i, incidence, xdot[i_trim + 1]),
                                                         section_speed=speed)
                nd["q"][i] = nd["q"][i] + ca.vertcat(f, m, ca.SX.zeros(6))
                rows.append(res)
                k += N_AERO_STATES
        if self.tail:
            rows.append(downwash_row)
        # thrust along body x at the first support's node (its beam's axes)
        b0, n0 = self.supports[0][0], self.supports[0][1]
        R0 = nodes[b0]["R"]
        nodes[b0]["q"][n0] = nodes[b0]["q"][n0] + ca.vertcat(ca.SX.zeros(6), R0 @ ca.vertcat(thrust, 0, 0),
                                                             ca.SX.zeros(3))
        for j, (bname, node, comp) in enumerate(self.supports):
            nd = nodes[bname]
            direction = np.asarray(nd["R"]) @ np.eye(3)[_XYZ.index(comp)]
            held = ca.dot(ca.DM(direction), nd["x"][node][st["r"]] - nd["p"][node][NODE_PARAMS["r0"]])
            rows.append(on * held + (1.0 - on) * xdot[i_trim + j])
        return ca.vertcat(*rows)

    @staticmethod
    def _root_angle(xn, pn, vf, omega, V, seq):
        """v_n / v_c of the wing root section's relative air velocity minus its jig value (rad)."""
        st = STATE_BLOCKS
        free = ca.vertcat(V, 0, 0)
        T = body_to_csn(xn[st["theta"]], seq)
        rel = T @ (free - vf - ca.cross(omega, xn[st["r"]]) - xn[st["u"]])
        rel0 = body_to_csn(pn[NODE_PARAMS["theta0"]], seq) @ free
        return rel[2] / rel[0] - rel0[2] / rel0[0]


def sweep_cosine(theta0, euler_sequence="surface"):
    """cos(Lambda) of a strip's sweep: sqrt(1 - s_x^2), s_x the body-x (free-stream) component of
    the span axis s of its jig frame (Euler angles ``theta0``), the ratio of the velocity normal
    to the beam to the airspeed (module docstring, ``normal_flow``). 1 for a beam normal to the
    free stream, whatever its dihedral.

    Parameters
    ----------
    theta0 : casadi.SX or array_like
        (3,) Euler angles of the node's jig frame in body axes (rad).
    euler_sequence : str, optional
        The Euler sequence of ``theta0`` (:func:`wingmdao.beam.rotations.body_to_csn`).

    Returns
    -------
    casadi.SX
        cos(Lambda) (-).
    """
    s_x = body_to_csn(theta0, euler_sequence)[1, 0]
    return ca.sqrt(1.0 - s_x * s_x)


def trim_angle(alpha_trim, theta, euler_sequence="surface"):
    """The angle of attack a section sees when the aircraft is pitched by ``alpha_trim`` (rad) about
    body y: ``atan(tan(alpha_trim) s_y)``, s_y the body-y component of the section's span axis s
    (its deformed frame, Euler angles ``theta``). A section rolled by phi (a wing's dihedral, or
    its slope when it bends) sees ``atan(tan(alpha) cos(phi))``: the free stream
    ``V (cos alpha, 0, sin alpha)`` in body axes has ``V sin(alpha) cos(phi)`` along the section
    normal and ``V cos(alpha)`` along the chord.

    Parameters
    ----------
    alpha_trim : casadi.SX or float
        The aircraft's trim angle of attack (rad).
    theta : casadi.SX or array_like
        (3,) Euler angles of the section's deformed frame (rad).
    euler_sequence : str, optional
        The Euler sequence of ``theta`` (:func:`wingmdao.beam.rotations.body_to_csn`).

    Returns
    -------
    casadi.SX
        The section's angle of attack (rad).
    """
    s_y = body_to_csn(theta, euler_sequence)[1, 1]
    return ca.atan(ca.tan(alpha_trim) * s_y)


def build_joined_aeroelastic_system(beams, joints, *, lifting=("wing", "tail"), wing="wing", tail="tail",
                                    supports, masses=(), symmetry=(), euler_sequence="surface", damping=None,
                                    trim_rotation=False, elevon=None, elevon_hinge=0.75, normal_flow=False):
    """Joined beams (:func:`wingmdao.beam.joints.build_joined_system`) with unsteady strip
    aerodynamics on the ``lifting`` beams, the wing's downwash at the ``tail`` (None: no tail
    downwash and no tail incidence effect) and the trim unknowns of the free aircraft held by
    ``supports`` (three ``(beam, node, component)``, component ``"x"``, ``"y"`` or ``"z"`` of the
    body axes; the thrust acts at the first). Module docstring for the equations.
    ``trim_rotation``: alpha_trim pitches the aircraft about body y, so each station sees
    :func:`trim_angle` of its deformed span axis (a wing bent to a large dihedral sees less of
    it); False: alpha_trim is added to every station's angle (the small-deflection model).
    ``elevon`` (with ``tail=None``): ``{beam: node indices}`` of the lifting stations carrying a
    trailing-edge flap hinged at ``elevon_hinge`` x chord, or ``{beam: {node: share}}`` with the
    share (0, 1] of the deflection each station takes (0.5 at the node where the elevon ends
    makes the flapped span of the node-interpolated strips end there); the trim unknown
    ``tail_incidence`` is then its deflection (rad, trailing edge down +), trimmed in pitch as
    the tail incidence is. ``normal_flow``: each strip's aerodynamics on the velocity normal to
    its beam, V cos(sweep) (module docstring; not with ``trim_rotation``, whose
    :func:`trim_angle` is that of an unswept section).

    Returns the :class:`~wingmdao.beam.joints.JoinedBeamSystem` with ``lag_index`` ({beam: (n, 4)
    state indices}), ``downwash_index`` (or None), ``trim_index`` ({name: state index}),
    ``lifting`` and ``section_loads(x, xdot, p, q)`` ({beam: (lift (n,) N/m along the section
    normal, moment (n,) N about the beam axis, body-z force (n,) N/m)}).
    ValueError (before any build) for a lifting beam that is not a beam or not in body axes, a
    wing or tail not among the lifting beams, or supports that are not three valid triples.

    Parameters
    ----------
    beams : sequence of Beam
        The beams.
    joints : sequence of Joint
        The joints.
    lifting : sequence of str
        Names of the lifting beams (body axes).
    wing : str
        Name of the wing, a lifting beam.
    tail : str or None
        Name of the horizontal tail, another lifting beam; None: no tail downwash.
    supports : sequence of tuple
        Three ``(beam, node, component)``.
    masses : sequence of LumpedMass
        The lumped masses.
    symmetry : sequence of Symmetry
        The symmetry conditions.
    euler_sequence : str
        Euler-angle sequence.
    damping : StrainRateDamping, optional
        Strain-rate damping of the beams.
    trim_rotation : bool
        alpha_trim pitches the aircraft (see above).
    elevon : dict, optional
        ``{lifting beam: node indices}`` or ``{lifting beam: {node: share}}`` of the elevon
        stations (tailless aircraft only).
    elevon_hinge : float
        Hinge line of the elevon, fraction of the chord, in (0, 1).
    normal_flow : bool
        Swept strips on the velocity component normal to their beam (simple sweep theory).

    Returns
    -------
    JoinedBeamSystem
        The system, with the attributes above.
    """
    beams = tuple(beams)
    by_name = {b.name: b for b in beams if isinstance(b, Beam)}
    lifting = tuple(lifting)
    if not lifting or len(set(lifting)) != len(lifting):
        raise ValueError(f"lifting must name distinct beams, got {list(lifting)}")
    for name in lifting:
        if name not in by_name:
            raise ValueError(f"lifting beam {name!r} is not a beam; beams are {sorted(by_name)}")
        if by_name[name].axes is not None:
            raise ValueError(f"lifting beam {name!r}: its axes must be the body axes (axes=None), the strip "
                             f"sections' csn frame is measured from them; got axes={by_name[name].axes}")
    if wing not in lifting:
        raise ValueError(f"wing = {wing!r} must be one of the lifting beams {list(lifting)}")
    if tail is not None and (tail not in lifting or tail == wing):
        raise ValueError(f"tail = {tail!r} must be a lifting beam other than the wing {wing!r} "
                         f"(lifting beams {list(lifting)}), or None")
    if normal_flow and trim_rotation:
        raise ValueError("normal_flow=True with trim_rotation=True: not available (trim_angle is the angle of an "
                         "unswept section); use one of them")
    supports = tuple(tuple(s) for s in supports)
    if len(supports) != len(TRIM_STATE_NAMES):
        raise ValueError(f"supports: {len(supports)} given; trim needs 3 (surge, plunge, pitch of the half "
                         f"aircraft), e.g. (('fuselage', 0, 'x'), ('fuselage', 0, 'z'), ('fuselage', -1, 'z'))")
    for s in supports:
        if len(s) != 3 or s[0] not in by_name or s[2] not in _XYZ or not -by_name[s[0]].num_nodes <= int(s[1]) \
                < by_name[s[0]].num_nodes:
            raise ValueError(f"support {s}: must be (beam, node, 'x'|'y'|'z') with an existing beam and node")
    supports = tuple((s[0], int(s[1]) % by_name[s[0]].num_nodes, s[2]) for s in supports)
    lifting = tuple(b.name for b in beams if b.name in lifting)      # state order
    stations = ()
    if elevon:
        if tail is not None:
            raise ValueError(f"elevon: the tail {tail!r} trims in pitch; an elevon needs tail=None")
        if not (np.isfinite(elevon_hinge) and 0.0 < elevon_hinge < 1.0):
            raise ValueError(f"elevon_hinge = {elevon_hinge}; allowed range (0, 1) (fraction of the chord)")
        for name, nodes in elevon.items():
            if name not in lifting:
                raise ValueError(f"elevon beam {name!r} is not a lifting beam; lifting beams are {list(lifting)}")
            n = by_name[name].num_nodes
            shares = dict(nodes) if isinstance(nodes, dict) else {i: 1.0 for i in nodes}
            for i, w in shares.items():
                if int(i) != i or not -n <= int(i) < n:
                    raise ValueError(f"elevon node {i} of beam {name!r} does not exist: it has nodes 0..{n - 1}")
                if not (np.isfinite(w) and 0.0 < w <= 1.0):
                    raise ValueError(f"elevon share {w} at node {i} of beam {name!r}; allowed range (0, 1]")
                stations += ((name, int(i) % n, float(w)),)
        if len({st[:2] for st in stations}) != len(stations):
            raise ValueError(f"elevon: a station is given twice in {dict(elevon)}")
    ext = _Aero(beams, lifting, wing, tail, supports, euler_sequence, bool(trim_rotation), tuple(sorted(stations)),
                float(elevon_hinge), bool(normal_flow))
    system = build_extended_joined_system(beams, joints, euler_sequence=euler_sequence, damping=damping,
                                          masses=masses, symmetry=symmetry, extension=ext)
    k = system.n_struct
    system.lag_index = {}
    for name, n in ext.counts.items():
        system.lag_index[name] = k + np.arange(N_AERO_STATES * n).reshape(n, N_AERO_STATES)
        k += N_AERO_STATES * n
    system.downwash_index = k if tail else None
    k += 1 if tail else 0
    system.trim_index = {nm: k + j for j, nm in enumerate(TRIM_STATE_NAMES)}
    system.lifting = lifting
    system.aero = ext
    system._section_loads = _section_loads_function(system, ext)
    system.section_loads = lambda x, xdot, p, q: _unpack_loads(system, x, xdot, p, q)
    return system


def _section_loads_function(system, ext):
    """CasADi function of the lift (N/m, along the section normal) and moment (N) of every lifting station."""
    x, xdot = ca.SX.sym("x", system.n_state), ca.SX.sym("xdot", system.n_state)
    p = ca.SX.sym("p", sum(v.size for v in system.param_specs))
    q = ca.SX.sym("q", sum(v.size for v in system.forcing_specs))
    play, qlay = layout(system.param_specs), layout(system.forcing_specs)
    seq = ext.euler_sequence
    V, rho, mach = p[play["airspeed"]], p[play["density"]], p[play["mach"]]
    frame = (q[qlay["frame_velocity"]], q[qlay["frame_velocity_rate"]], q[qlay["frame_angular_velocity"]],
             q[qlay["frame_angular_acceleration"]])
    i_trim = system.trim_index["alpha_trim"]
    out = []
    for name, n in ext.counts.items():
        i0 = system.offsets[name]
        for i in range(n):
            shift = x[i_trim]
            if ext.trim_rotation:
                shift = trim_angle(shift, x[i0 + 18 * i + STATE_BLOCKS["theta"].start:
                                            i0 + 18 * i + STATE_BLOCKS["theta"].stop], seq)
            if name == ext.tail:
                shift = shift + x[system.trim_index["tail_incidence"]] - \
                    p[play["downwash_gradient"]] * x[system.downwash_index]
            speed = None
            if ext.normal_flow:
                cos_sweep = sweep_cosine(p[play[f"{name}_node_euler_angles"]][3 * i:3 * i + 3], seq)
                shift, speed = shift / cos_sweep, V * cos_sweep
            pa = ca.vertcat(*[p[play[f"{name}_{s}"]][i] for s in SECTION_PARAMS[:3]],
                            p[play[f"{name}_alpha_zero_lift"]][i] - shift, p[play[f"{name}_cm0"]][i],
                            q[qlay[f"{name}_gust_velocity"]][i])
            lag = system.lag_index[name][i]
            xa = ca.vertcat(x[i0 + 18 * i: i0 + 18 * (i + 1)], x[int(lag[0]):int(lag[-1]) + 1])
            xda = ca.vertcat(xdot[i0 + 18 * i: i0 + 18 * (i + 1)], xdot[int(lag[0]):int(lag[-1]) + 1])
            i_inc = system.trim_index["tail_incidence"]
            f, _m, _res, lift, moment, _ = node_aero(xa, xda, pa, None, frame, V, rho, mach, seq,
                                                     ext.flap(name, i, x[i_inc], xdot[i_inc]), section_speed=speed)
            out += [lift, moment, f[2]]
    return ca.Function("joined_section_loads", [x, xdot, p, q], [ca.vertcat(*out)])


def _unpack_loads(system, x, xdot, p, q):
    v = np.asarray(system._section_loads(np.ravel(x), np.ravel(xdot), np.ravel(p), np.ravel(q))).ravel().reshape(-1, 3)
    out, k = {}, 0
    for name, n in system.aero.counts.items():
        out[name] = (v[k:k + n, 0].copy(), v[k:k + n, 1].copy(), v[k:k + n, 2].copy())
        k += n
    return out


def pack_aero_parameters(system, beam_params: dict, sections: dict, *, airspeed, density, mach=0.0,
                         downwash_gradient=0.0) -> np.ndarray:
    """Packed parameters: the structure's (:meth:`~wingmdao.beam.joints.JoinedBeamSystem.pack_parameters`
    of ``beam_params``) and the aerodynamics': ``sections`` ``{beam: {chord, ref_point, lift_slope,
    alpha_zero_lift, cm0}}`` (scalars broadcast; defaults ref_point 0.4, lift_slope 2 pi, 0, 0).

    Parameters
    ----------
    system : JoinedBeamSystem
        A system of :func:`build_joined_aeroelastic_system`.
    beam_params : dict
        ``{beam name: parameter dict}``.
    sections : dict
        ``{lifting beam: {chord (m), ref_point, lift_slope (1/rad), alpha_zero_lift (rad), cm0}}``.
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    mach : float
        Mach number.
    downwash_gradient : float
        deps/dalpha at the tail, in [0, 1) (with a tail).

    Returns
    -------
    ndarray
        The packed parameters.
    """
    base = system.pack_parameters(beam_params)
    lay = layout(system.param_specs)
    p = np.zeros(sum(s.size for s in system.param_specs))
    n_base = base.size
    p[:n_base] = base
    values = {}
    for name in system.lifting:
        if name not in sections:
            raise ValueError(f"sections: no aerodynamic data for the lifting beam {name!r}")
        n = system.beam(name).num_nodes
        d = {"ref_point": 0.4, "lift_slope": 2 * np.pi, "alpha_zero_lift": 0.0, "cm0": 0.0, **sections[name]}
        for s in SECTION_PARAMS:
            values[f"{name}_{s}"] = np.broadcast_to(np.asarray(d[s], dtype=float), (n,)).copy()
        check_aero_parameters({k: values[f"{name}_{k}"] for k in ("chord", "ref_point", "lift_slope")}
                              | {"airspeed": airspeed, "density": density, "mach": mach})
    values.update(airspeed=float(airspeed), density=float(density), mach=float(mach))
    if system.aero.tail:
        if not (np.isfinite(downwash_gradient) and 0.0 <= downwash_gradient < 1.0):
            raise ValueError(f"downwash_gradient = {downwash_gradient}; allowed range [0, 1)")
        values["downwash_gradient"] = float(downwash_gradient)
    for k, v in values.items():
        p[lay[k]] = np.asarray(v, dtype=float).ravel()
    return p


def pack_aero_forcing(system, gust: dict | None = None, *, trim_active=0.0, frame_velocity=(0.0, 0.0, 0.0),
                      frame_velocity_rate=(0.0, 0.0, 0.0), **shared) -> np.ndarray:
    """Packed forcing at one instant: ``gust`` ``{beam: (n,) m/s}`` of the lifting beams (zero if
    absent), the trim switch and the shared structure forcing (``gravity``, ``frame_acceleration``, ...).

    Parameters
    ----------
    system : JoinedBeamSystem
        A system of :func:`build_joined_aeroelastic_system`.
    gust : dict, optional
        ``{lifting beam: (n,) gust velocity (m/s)}``.
    trim_active : float
        Trim switch (1: solve the trim unknowns; 0: hold them).
    frame_velocity : array_like, shape (3,)
        Velocity of the body axes relative to the trimmed flight (m/s).
    frame_velocity_rate : array_like, shape (3,)
        Its rate (m/s^2).
    **shared
        Shared structure forcing blocks.

    Returns
    -------
    ndarray
        The packed forcing.
    """
    base = system.pack_forcing(None, **shared)
    lay = layout(system.forcing_specs)
    q = np.zeros(sum(s.size for s in system.forcing_specs))
    q[:base.size] = base
    for name in system.lifting:
        g = np.zeros(system.beam(name).num_nodes) if not gust or name not in gust else np.asarray(gust[name], float)
        q[lay[f"{name}_gust_velocity"]] = g
    q[lay["frame_velocity"]] = frame_velocity
    q[lay["frame_velocity_rate"]] = frame_velocity_rate
    q[lay["trim_active"]] = float(trim_active)
    return q


def lift_total(system, x, xdot, p, q, vertical: bool = False) -> float:
    """Integrated lift (N, trapezoid over each lifting beam's jig node positions) of the modelled
    half (or whole) aircraft: along the sections' normals, or with ``vertical`` its body-z
    component (the aerodynamic force that balances the weight).

    Parameters
    ----------
    system : JoinedBeamSystem
        A system of :func:`build_joined_aeroelastic_system`.
    x : array_like, shape (n_state,)
        State.
    xdot : array_like, shape (n_state,)
        State rate.
    p : array_like, shape (n_param,)
        Packed parameters.
    q : array_like, shape (n_forcing,)
        Packed forcing.
    vertical : bool
        Integrate the body-z component instead of the normal lift.

    Returns
    -------
    float
        The lift (N).
    """
    lay = layout(system.param_specs)
    p = np.asarray(p, dtype=float)
    total = 0.0
    for name, (normal, _, up) in system.section_loads(x, xdot, p, q).items():
        lift = up if vertical else normal
        r0 = p[lay[f"{name}_node_positions"]].reshape(-1, 3)
        ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
        total += float(np.sum(0.5 * (lift[:-1] + lift[1:]) * ds))
    return total


__all__ = ["build_joined_aeroelastic_system", "trim_angle", "sweep_cosine", "pack_aero_parameters", "pack_aero_forcing", "lift_total",
           "SECTION_PARAMS", "TRIM_STATE_NAMES"]
