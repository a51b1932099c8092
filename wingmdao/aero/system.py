"""``AeroelasticBeamSystem``: the App. A beam with unsteady strip-theory loads on its deformed sections.

State per node (node-major, ``state_shape = (num_nodes, 22)``): the 18 beam states of
:mod:`wingmdao.beam.residual` (r, theta, F, M, u, omega) followed by the 4 aerodynamic lag states
of :mod:`wingmdao.aero.strip` (lambda_1, lambda_2 Wagner; mu_1, mu_2 Kuessner; rad). Residual rows
per node: the 18 beam rows of that node, then the 4 lag-state equations of that station.

Coupling. At node i, with T = T(theta_i) (body -> csn), the air velocity relative to the section
(body axes) is ``v_rel = (V, 0, 0) - frame_velocity - Omega x r_i - u_i`` (the free stream flows
aft, +x, relative to the wing; docs/conventions.md), its csn components ``T v_rel`` give the
quasi-steady angle, and the pitch rate is ``w_s = (T (omega_i + Omega))_s``. The gust
``gust_velocity_i`` (body +z, upward) enters through its section-normal component. The section
lift L (along the deformed section normal n) and moment M (about the deformed beam axis s) per
unit length are *follower* loads ``T^T (0, 0, L)`` and ``T^T (0, M, 0)`` added to the beam's
distributed ``force_per_length`` / ``moment_per_length`` of node i. The apparent-mass terms use
the exact time derivative of the midchord normal velocity and pitch rate (CasADi ``jtimes`` with
xdot, plus ``frame_velocity_rate`` / ``frame_angular_acceleration`` for the frame terms, the rates
of ``frame_velocity`` / ``frame_angular_velocity``). ``frame_acceleration`` acts on the beam's
inertia only, so a quasi-static maneuver's (n - 1) g relief adds no apparent mass.

Parameters: the beam's (:func:`wingmdao.beam.residual.param_specs`) then :func:`aero_param_specs`
(chord, ref_point, lift_slope, alpha_zero_lift, cm0 per node; airspeed, density, mach).
Forcing: the beam's (:func:`wingmdao.beam.residual.forcing_specs`) then ``gust_velocity`` (n,)
m/s, ``frame_velocity`` (3,) m/s and ``frame_velocity_rate`` (3,) m/s**2. Everything is differentiable (CasADi), so
:class:`~wingmdao.components.time_history.TimeHistoryComponent` marches it and its discrete
adjoint gives derivatives with respect to every parameter, airspeed and density included.
Free plunge, trim and free pitch add trailing states (w_p; pitch_angle, pitch_rate, [downwash_lag],
[elevator_deflection], tail_incidence; alpha_trim last), see :func:`build_aeroelastic_system` and :mod:`wingmdao.aero.pitch`.
"""

from __future__ import annotations

import time as _time
import zlib
from dataclasses import dataclass

import casadi as ca
import numpy as np

from wingmdao.aero.controls import actuator_residuals, theodorsen_flap_functions
from wingmdao.aero.lifting_line import lifting_line_lift_slope
from wingmdao.aero.strip import (AERO_STATE_NAMES, N_AERO_STATES, WAGNER_A, WAGNER_B, check_aero_inputs,
                                  section_model)
from wingmdao.aero.vlm import flap_influence, station_influence
from wingmdao.beam.residual import (N_STATE_PER_NODE, STATE_BLOCKS, NODE_FORCING as _Q_NODE, NODE_PARAMS as _P_NODE,
                                    element_function as _element_function, nodal_function as _nodal_function,
                                    node_forcing as _node_forcing, node_params as _node_params, describe_equation,
                                    forcing_specs as beam_forcing_specs, jig_state,
                                    param_specs as beam_param_specs, StrainRateDamping)
from wingmdao.beam.rotations import body_to_csn
from wingmdao.names import AERO_THEORY_CHOICES  # noqa: F401  (--aero-theory; its home)
from wingmdao.units import G0
from wingmdao.timemarch import lu_orders
from wingmdao.timemarch.system import CasadiResidualSystem, VarSpec, layout
from wingmdao.timemarch.bdf import state_rates
from wingmdao.utils import function_store
from wingmdao.utils.casadi_cache import definition_key
from wingmdao.aero.pitch import (ELEVATOR_STATE_NAME, INCIDENCE_STATE_NAME, LAG_STATE_NAME, PITCH_STATE_NAMES,
                                 body_residuals, elevator_forcing_specs, elevator_param_specs,
                                 pitch_forcing_specs, pitch_param_specs)
from wingmdao.aero.roll import ROLL_STATE_NAMES, roll_forcing_specs, roll_param_specs, roll_residuals

#: states per node of the aeroelastic system: 18 beam + 4 aerodynamic
N_AEROELASTIC_STATES = N_STATE_PER_NODE + N_AERO_STATES
#: names of the aerodynamic parameters (their validation is check_aero_parameters)
AERO_PARAMS = ("chord", "ref_point", "lift_slope", "alpha_zero_lift", "cm0", "airspeed", "density", "mach")
#: circulatory quasi-steady lift of the residual: per strip, or the vortex lattice's (build_aeroelastic_system)
AERO_THEORIES = ("strip", "vlm")


@dataclass(frozen=True, eq=False)
class StateLayout:
    """Where each state of the aeroelastic system sits in the flat state vector (flat indices).

    ``beam`` (n, 18): r, theta, F, M, u, omega of node i (:data:`wingmdao.beam.residual.STATE_BLOCKS`
    order); ``aero`` (n, 4): lambda_1, lambda_2, mu_1, mu_2 of station i; ``body``: the rigid-body
    states after the node blocks, ``{"plunge": index, "trim": index}`` for those present (bordered
    rows/columns, last so that the natural-order LU keeps the node-banded block fill-free);
    ``size`` the number of states. Residual rows use the same positions (a node's beam rows, then
    its lag equations; the body equations last).

    The node-major order interleaves each station's lag states with its node's beam states, so the
    Newton matrix is block-banded (block width 22: a node couples only to its neighbours).
    Measured alternatives (20 nodes, natural-order SuperLU, docs/aeroelasticity.md "Speed"): lag
    states before the beam's 13992 L+U nonzeros against 15253 at no measurable time gain; the best
    of all 5040 block orders of a node (F, r, M, lag, u, omega, theta) 11714, 17 % faster
    factorization but a beam-state order different from the structural beam's.

    Parameters
    ----------
    beam : ndarray of int, shape (n, 18)
        Flat indices of the beam states.
    aero : ndarray of int, shape (n, 4)
        Flat indices of the lag states.
    body : dict of str to int
        Flat index of each rigid-body state present.
    size : int
        Number of states.
    """

    beam: np.ndarray
    aero: np.ndarray
    body: dict
    size: int

    def beam_states(self, X):
        """The beam states (..., n, 18) of state vectors X (..., size) or (..., n, 22).

        Parameters
        ----------
        X : array_like, shape (..., size) or (..., n, 22)
            State vectors.

        Returns
        -------
        ndarray, shape (..., n, 18)
            The beam states.
        """
        X = np.asarray(X)
        if X.shape[-1] != self.size:
            X = X.reshape(X.shape[:-2] + (-1,))
        return X[..., self.beam]

    def aero_states(self, X):
        """The lag states (..., n, 4) of state vectors X (..., size) or (..., n, 22).

        Parameters
        ----------
        X : array_like, shape (..., size) or (..., n, 22)
            State vectors.

        Returns
        -------
        ndarray, shape (..., n, 4)
            The lag states.
        """
        X = np.asarray(X)
        if X.shape[-1] != self.size:
            X = X.reshape(X.shape[:-2] + (-1,))
        return X[..., self.aero]

    def mask(self, part: str) -> np.ndarray:
        """(size,) 1.0 on the ``beam`` or ``aero`` states, 0 elsewhere.

        Parameters
        ----------
        part : str
            ``"beam"`` or ``"aero"``.

        Returns
        -------
        ndarray, shape (size,)
            The mask.
        """
        w = np.zeros(self.size)
        w[getattr(self, part).ravel()] = 1.0
        return w


def state_layout(num_nodes: int, plunge: bool = False, trim: bool = False, pitch_states=(),
                 control_states=(), roll_states=()) -> StateLayout:
    """The :class:`StateLayout` of :func:`build_aeroelastic_system`: the one place that states
    the order (the build checks its symbols against it; the initial guess and every consumer
    index through it). A new body state goes here, in the order the build appends it: plunge,
    the free-pitch states ``pitch_states`` (:mod:`wingmdao.aero.pitch`), the free-roll states
    ``roll_states`` (:mod:`wingmdao.aero.roll`), the control states
    ``control_states`` (actuators, controller, measurement references; :mod:`wingmdao.aero.controls`),
    trim last.

    Parameters
    ----------
    num_nodes : int
        Number of nodes.
    plunge : bool
        Free plunge state present.
    trim : bool
        Trim state present.
    pitch_states : sequence of str
        Names of the free-pitch states, in order.
    control_states : sequence of str
        Names of the control states, in order.
    roll_states : sequence of str
        Names of the free-roll states, in order.

    Returns
    -------
    StateLayout
        The layout.
    """
    n = int(num_nodes)
    node = np.arange(n)[:, None] * N_AEROELASTIC_STATES
    body, k = {}, N_AEROELASTIC_STATES * n
    names = ((("plunge", plunge),) + tuple((nm, True) for nm in pitch_states)
             + tuple((nm, True) for nm in roll_states) + tuple((nm, True) for nm in control_states) + (("trim", trim),))
    for name, on in names:
        if on:
            body[name] = k
            k += 1
    return StateLayout(beam=node + np.arange(N_STATE_PER_NODE), aero=node + np.arange(N_STATE_PER_NODE,
                                                                                    N_AEROELASTIC_STATES),
                       body=body, size=k)


def aero_param_specs(n: int) -> list[VarSpec]:
    """Aerodynamic parameters of an n-node aeroelastic beam (appended to the beam's).

    Parameters
    ----------
    n : int
        Number of nodes.

    Returns
    -------
    list of VarSpec
        The parameter blocks.
    """
    return [
        VarSpec("chord", (n,), "m", "section chord at each node"),
        VarSpec("ref_point", (n,), None, "beam-axis (reference point) position, fraction of chord aft of the leading edge"),
        VarSpec("lift_slope", (n,), "1/rad", "incompressible section lift-curve slope (2 pi: thin airfoil)"),
        VarSpec("alpha_zero_lift", (n,), "rad", "section zero-lift angle"),
        VarSpec("cm0", (n,), None, "section moment coefficient about the quarter chord (nose up +)"),
        VarSpec("airspeed", (), "m/s", "true airspeed V (free stream toward +x relative to the wing)"),
        VarSpec("density", (), "kg/m**3", "air density"),
        VarSpec("mach", (), None, "Mach number (Prandtl-Glauert factor on the lift slope)"),
    ]


def vlm_param_specs(n: int) -> list[VarSpec]:
    """The vortex-lattice influence parameters of ``aero_theory="vlm"`` (:mod:`wingmdao.aero.vlm`).

    Parameters
    ----------
    n : int
        Number of nodes.

    Returns
    -------
    list of VarSpec
        The parameter blocks.
    """
    return [
        VarSpec("lift_influence", (n, n), "m", "lift per length at station i per dynamic pressure and radian of "
                "circulatory angle at station j (vortex lattice, Prandtl-Glauert included)"),
        VarSpec("moment_influence", (n, n), "m**2", "moment per length about station i's quarter chord (nose up) per "
                "dynamic pressure and radian of circulatory angle at station j (vortex lattice)"),
    ]


def aero_forcing_specs(n: int) -> list[VarSpec]:
    """Aerodynamic forcing at one instant (appended to the beam's).

    Parameters
    ----------
    n : int
        Number of nodes.

    Returns
    -------
    list of VarSpec
        The forcing blocks.
    """
    return [
        VarSpec("gust_velocity", (n,), "m/s", "gust velocity (body +z, up) at each station, penetration delay included"),
        VarSpec("frame_velocity", (3,), "m/s", "velocity of the body-axes origin relative to the trimmed flight (e.g. plunge)"),
        VarSpec("frame_velocity_rate", (3,), "m/s**2", "rate of frame_velocity (apparent mass; the beam's inertia uses frame_acceleration)"),
    ]


def aero_parameters(n: int, *, chord, ref_point=0.4, lift_slope=2 * np.pi, alpha_zero_lift=0.0, cm0=0.0,
                    airspeed, density, mach=0.0) -> dict:
    """Dict of the aerodynamic parameters (scalars broadcast to every node), validated.

    Parameters
    ----------
    n : int
        Number of nodes.
    chord : float or array_like, shape (n,)
        Section chord (m).
    ref_point : float or array_like, shape (n,)
        Beam axis as a fraction of the chord aft of the leading edge.
    lift_slope : float or array_like, shape (n,)
        Incompressible section lift slope (1/rad).
    alpha_zero_lift : float or array_like, shape (n,)
        Section zero-lift angle (rad).
    cm0 : float or array_like, shape (n,)
        Section moment coefficient about the quarter chord.
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    mach : float
        Mach number.

    Returns
    -------
    dict
        The parameters of :func:`aero_param_specs`.
    """
    out = {}
    for name, v in (("chord", chord), ("ref_point", ref_point), ("lift_slope", lift_slope),
                    ("alpha_zero_lift", alpha_zero_lift), ("cm0", cm0)):
        out[name] = np.broadcast_to(np.asarray(v, dtype=float), (n,)).copy()
    out.update(airspeed=float(airspeed), density=float(density), mach=float(mach))
    check_aero_parameters(out)
    return out


def three_dimensional_parameters(aero_theory: str, node_positions, chord, ref_point, mach, controls=None,
                                 antisymmetric: bool = False) -> dict:
    """The aerodynamic parameters a theory of :data:`AERO_THEORY_CHOICES` sets on the strip model's:
    none for ``"strip"``; ``lift_slope`` (n,) 1/rad from Prandtl's lifting line of the planform
    (:func:`~wingmdao.aero.lifting_line.lifting_line_lift_slope`, zero at the tip node) for
    ``"lifting-line"``; ``lift_influence`` (n, n) m and ``moment_influence`` (n, n) m^2 from the
    vortex lattice at ``mach`` (:func:`~wingmdao.aero.vlm.station_influence`) for ``"vlm"``.
    ``node_positions`` (n, 3) m: the jig beam nodes; ``chord`` (n,) m; ``ref_point`` (n,).
    With ``controls`` and ``"vlm"`` the surfaces are deflected panels of the lattice: its chordwise
    panel edges hold every hinge (:func:`~wingmdao.aero.vlm.chord_fractions`) and the parameters of
    :func:`flap_param_specs` join (:func:`~wingmdao.aero.vlm.flap_influence`).

    Parameters
    ----------
    aero_theory : str
        A theory of :data:`AERO_THEORY_CHOICES`.
    node_positions : array_like, shape (n, 3)
        Jig beam nodes (m).
    chord : float or array_like, shape (n,)
        Chord (m).
    ref_point : float or array_like, shape (n,)
        Beam axis as a fraction of the chord aft of the leading edge.
    mach : float
        Mach number (vortex lattice).
    controls : ControlSpec, optional
        Control surfaces (their flap panels with ``"vlm"``).
    antisymmetric : bool, optional
        ``"vlm"``: the left half's loading the negative of the right's (the rolling half wing,
        ``build_aeroelastic_system(roll=True)``); the strips and the lifting line are per station.

    Returns
    -------
    dict
        The parameters, by name.
    """
    if aero_theory not in AERO_THEORY_CHOICES:
        raise ValueError(f"aero_theory = {aero_theory!r}; allowed: {', '.join(AERO_THEORY_CHOICES)}")
    if aero_theory == "strip":
        return {}
    r = np.asarray(node_positions, dtype=float).reshape(-1, 3)
    c = np.broadcast_to(np.asarray(chord, dtype=float), (r.shape[0],))
    if aero_theory == "lifting-line":
        y = r[:, 1]
        tip = float(y[-1])
        slope, _ = lifting_line_lift_slope(np.minimum(y, tip * (1 - 1e-12)), (y, c), tip)
        return {"lift_slope": np.maximum(slope, 1e-6)}  # the check wants > 0; zero at the tip node itself
    if controls is None:
        inf = station_influence(r, c, ref_point, mach=mach, antisymmetric=antisymmetric)
        return {"lift_influence": inf.lift, "moment_influence": inf.moment}
    inf, flap = flap_influence(r, c, ref_point, [(srf[1], srf[2]) for srf in controls.surfaces], mach=mach,
                               antisymmetric=antisymmetric)
    return {"lift_influence": inf.lift, "moment_influence": inf.moment, "flap_lift_influence": flap.lift,
            "flap_moment_influence": flap.moment, "hinge_station_influence": flap.hinge_station,
            "hinge_flap_influence": flap.hinge_flap}


def check_aero_parameters(values: dict) -> None:
    """ValueError (input, value, allowed range) for bad chord, ref_point, airspeed, density, mach.

    Parameters
    ----------
    values : dict
        Aerodynamic parameters by name (those present are checked).
    """
    check_aero_inputs(**{k: values[k] for k in ("chord", "ref_point", "airspeed", "density", "mach",
                                                 "lift_slope") if k in values})


def node_aero(x, xdot, pa, qf, frame, V, rho, mach, sequence, flap=None, flap_lattice=False, section_speed=None):
    """Follower aerodynamic force and moment per length (body axes) and the 4 lag residuals of one
    node: the strip section (:func:`wingmdao.aero.strip.section_model`) on the node's motion.

    Parameters
    ----------
    x, xdot : casadi.SX
        The node's 18 beam states and 4 lag states (22,), and their rates (SI, rad).
    pa : casadi.SX
        The node's aerodynamic parameters ``(chord m, ref_point -, lift_slope 1/rad, alpha_zero rad,
        cm0 -, gust velocity m/s)``.
    qf : None
        Unused (the node's forcing enters through ``frame``).
    frame : tuple of casadi.SX
        ``(frame velocity m/s (3,), its rate m/s^2 (3,), frame angular velocity rad/s (3,), its rate
        rad/s^2 (3,))``, body axes.
    V, rho, mach : casadi.SX
        Airspeed (m/s), air density (kg/m^3) and Mach number (-).
    sequence : str
        Euler sequence of the beam rotations (``"surface"`` or ``"standard"``).
    flap : tuple, optional
        ``(T, beta, dbeta, ddbeta)`` of a control surface at the node (:func:`section_model`).
    flap_lattice : bool, optional
        The flap's circulatory and steady loads come from the vortex lattice (:func:`section_model`).
    section_speed : casadi.SX, optional
        The speed of the section's dynamic pressure and of its Wagner and Kuessner lags (m/s);
        None: ``V``. A swept strip on the velocity normal to its beam takes V cos(sweep)
        (:func:`wingmdao.aero.joined.build_joined_aeroelastic_system`, ``normal_flow``); the
        kinematics (free stream, angles) always use ``V``.

    Returns
    -------
    f, m : casadi.SX
        Aerodynamic force (N/m) and moment (N m/m) per length, body axes (3,).
    res : casadi.SX
        The 4 lag-state residuals.
    lift, moment : casadi.SX
        Section lift per length along +n (N/m) and moment per length about +s at the reference
        point (N m/m).
    extra : tuple
        For a three-dimensional quasi-steady lift: the section's normal and spanwise axes (body),
        its lagged circulatory angle (rad), apparent-mass lift (N/m), moment without the
        circulatory lift (N m/m), and with ``flap`` the hinge moment (N m/m), with ``flap_lattice``
        also the input of the flap's lag states (rad).
    """
    st = STATE_BLOCKS
    xb, xdb = x[:18], xdot[:18]
    _r, th, _u, _w = xb[st["r"]], xb[st["theta"]], xb[st["u"]], xb[st["omega"]]
    vf, acc0, rate, alpha0 = frame
    chord, ref, a, azl, cm0, wg = (pa[k] for k in range(6))
    T = body_to_csn(th, sequence)
    free = ca.vertcat(V, 0, 0)

    def kinematics(xb_, vf_, rate_):
        T_ = body_to_csn(xb_[st["theta"]], sequence)
        rel = T_ @ (free - vf_ - ca.cross(rate_, xb_[st["r"]]) - xb_[st["u"]])
        ws = (T_ @ (xb_[st["omega"]] + rate_))[1]
        return rel, ws

    rel, ws = kinematics(xb, vf, rate)
    w_mid = rel[2] + ws * chord * (0.5 - ref)
    z = ca.vertcat(xb, vf, rate)
    zdot = ca.vertcat(xdb, acc0, alpha0)
    dw_mid = ca.jtimes(w_mid, z, zdot)
    dws = ca.jtimes(ws, z, zdot)
    gust_n = (T @ ca.vertcat(0, 0, wg))[2]
    lift, moment, res, parts = section_model(rel, ws, dw_mid, dws, gust_n, x[18:], xdot[18:], chord, ref, a, azl,
                                             cm0, V if section_speed is None else section_speed, rho, mach, flap,
                                             flap_lattice)
    f = T.T @ ca.vertcat(0, 0, lift)
    m = T.T @ ca.vertcat(0, moment, 0)
    # for a three-dimensional quasi-steady lift (aero_theory "vlm"): the section's normal and
    # spanwise axes (body), its lagged circulatory angle and its loads without the circulatory lift
    extra = (T.T[:, 2], T.T[:, 1], parts["alpha_circulatory"], parts["lift_apparent_mass"],
             parts["moment_noncirculatory"]) + ((parts["hinge_moment"],) if flap is not None else ())
    if flap is not None and flap_lattice:
        extra = extra + (parts["flap_input"],)
    return f, m, res, lift, moment, extra


#: Modules whose code generates the aeroelastic system's CasADi functions (their source is part of
#: the compiled-library key, :func:`aeroelastic_definition`).
_GENERATING_MODULES = ("wingmdao.aero.system", "wingmdao.aero.strip", "wingmdao.aero.pitch", "wingmdao.aero.controls",
                       "wingmdao.aero.roll",
                       "wingmdao.aero.plunge", "wingmdao.beam.residual", "wingmdao.beam.rotations",
                       "wingmdao.timemarch.system")


def aeroelastic_definition(num_nodes: int, euler_sequence: str = "surface",
                           damping: StrainRateDamping | None = None, plunge: bool = False,
                           trim: bool = False, pitch: bool = False, tail_lag: bool = False,
                           aero_theory: str = "strip", elevator: bool = False, controls=None,
                           roll: bool = False) -> str:
    """What defines the functions of :func:`build_aeroelastic_system` (the key of their compiled
    libraries, :func:`wingmdao.utils.casadi_cache.definition_key`): its arguments, the source of
    the generating modules and the CasADi version. Keying on this instead of the serialized
    functions saves ~0.7 s per process (the serialization of the large coupled functions).

    Parameters
    ----------
    num_nodes : int
        Number of nodes (at least 2).
    euler_sequence : str
        Euler-angle sequence.
    damping : StrainRateDamping, optional
        Strain-rate damping of the beam.
    plunge : bool
        Free plunge.
    trim : bool
        Trim unknown alpha_trim.
    pitch : bool
        Free pitch with a horizontal tail.
    tail_lag : bool
        Downwash lag at the tail (with ``pitch``).
    aero_theory : str
        ``"strip"`` or ``"vlm"``.
    elevator : bool
        Elevator on the tail (with ``pitch``).
    controls : ControlSpec, optional
        Control surfaces and law; None: none.
    roll : bool
        The antisymmetric half wing on a fuselage free to roll.

    Returns
    -------
    str
        The definition key.
    """
    if damping is not None and damping.is_zero:
        damping = None
    args = (int(num_nodes), str(euler_sequence),
            None if damping is None else (damping.curvature, damping.strain),
            bool(plunge), bool(trim), bool(pitch), bool(tail_lag))
    if aero_theory != "strip":  # the strip system's arguments as before
        args = args + (str(aero_theory),)
    if elevator:
        args = args + ("elevator",)
    if controls is not None:
        args = args + (repr(controls),)
    if roll:
        args = args + ("roll",)
    return definition_key("wingmdao.aero.system.build_aeroelastic_system", args, _GENERATING_MODULES)


def build_aeroelastic_system(num_nodes: int, *, euler_sequence: str = "surface",
                             damping: StrainRateDamping | None = None,
                             plunge: bool = False, trim: bool = False, pitch: bool = False,
                             tail_lag: bool = False, aero_theory: str = "strip",
                             elevator: bool = False, controls=None, roll: bool = False) -> AeroelasticBeamSystem:
    """The App. A beam of ``num_nodes`` nodes (root clamped) with unsteady strip theory.

    Returns an :class:`AeroelasticBeamSystem` (a :class:`CasadiResidualSystem`):
    ``state_shape = (num_nodes, 22)`` (18 beam + 4 lag states per node); ``param_specs`` = beam
    parameters + :func:`aero_param_specs`; ``forcing_specs`` = beam forcing +
    :func:`aero_forcing_specs`. ``system.section_loads(x, xdot, p, q)`` evaluates the lift and
    moment per length at every node.

    ``plunge=True`` frees the aircraft in plunge (the clamped, wind-tunnel root otherwise): one
    more state, the upward velocity w_p of the body axes (``state_shape = (22 num_nodes + 1,)``,
    the node-major (n, 22) block first), one more parameter ``body_mass`` (kg, the aircraft mass
    outside both wing halves), and the equation ``body_mass (dw_p/dt - g_z) = 2 F_root,z`` (the
    two half-wings' root shear, which holds their lift and their own inertia). The body velocity
    (0, 0, w_p) adds to ``frame_velocity`` in the aerodynamics and its rate to the beam's
    ``frame_acceleration``.

    ``trim=True`` adds the aircraft angle of attack alpha_trim (rad, added to every station's
    angle; the last state), the parameter ``trim_lift`` (N, the lift of both half-wings to trim
    to, n W) and the forcing ``trim_active`` (1: solve for alpha_trim so that the integrated lift
    of both halves equals ``trim_lift``; 0: hold it, d alpha_trim/dt = 0). Set ``trim_active`` = 1
    at t = 0 only and the march starts from the trimmed state, the gust an increment on it.

    ``pitch=True`` (needs ``plunge`` and ``trim``) also frees the aircraft in pitch with a
    horizontal tail (:mod:`wingmdao.aero.pitch`): states pitch_angle, pitch_rate, [downwash_lag
    with ``tail_lag``], tail_incidence after w_p (``system.body_index`` names their indices),
    parameters :func:`~wingmdao.aero.pitch.pitch_param_specs`, forcing ``tail_gust_velocity``;
    the trim then solves alpha_trim for "wing + tail lift = trim_lift" and tail_incidence for the
    static pitch-moment balance. ``elevator=True`` (needs ``pitch``) adds an elevator on the tail
    (:mod:`wingmdao.aero.pitch`): the state elevator_deflection (before tail_incidence), a
    first-order actuator driven by the forcing ``elevator_command``, and the parameters
    ``elevator_effectiveness``, ``elevator_time_constant``.

    ``aero_theory``: ``"strip"`` (each station's circulatory lift from its own angle, slope
    ``lift_slope / beta``) or ``"vlm"`` (:data:`AERO_THEORIES`): the circulatory quasi-steady lift
    and moment of every station from the lagged circulatory angles of all stations through the
    vortex-lattice influence matrices, the parameters ``lift_influence`` (n, n) m and
    ``moment_influence`` (n, n) m^2 (:func:`vlm_param_specs`, :mod:`wingmdao.aero.vlm`):
    ``L_c = q A_L alpha_c``, ``M_c = L_c c (ref - 1/4) + q A_M alpha_c`` with q = rho V^2 / 2 and
    alpha_c each station's Wagner/Kuessner-lagged angle (the strip's alpha_eff + alpha_g,eff).
    The lag states, the apparent mass and cm0 stay per station ("3-D quasi-steady + 2-D lag",
    the modified strip analysis of Yates, "Modified-strip-analysis method for predicting wing
    flutter at subsonic to hypersonic speeds", J. Aircraft 3(1), 1966, 25-29, with the spanwise
    loading from a lifting-surface solution instead of per-strip slopes). ``lift_slope`` and
    ``mach`` then do not enter the circulatory lift: the influence matrices hold the flat-plate
    sections and the Prandtl-Glauert factor of the Mach number they were built for.

    ``controls`` (:class:`~wingmdao.aero.controls.ControlSpec`, None: no surfaces) adds trailing-edge
    control surfaces, their actuators and an optional linear feedback law (docs/controls.md): per
    surface the states deflection and rate (rad, rad/s; the actuator rows of
    :func:`~wingmdao.aero.controls.actuator_residuals`), at each of its nodes the flap terms of
    :func:`~wingmdao.aero.strip.section_model`; the forcing ``surface_command`` (n_s,) rad (an
    open-loop command, added to the law's); with a law the controller states x_c, the parameters
    ``controller_A`` ... ``controller_D`` and, with ``trim``, one reference state per measured
    output (its trimmed value, held after t = 0) so that the law acts on the increments from the
    trimmed 1 g state; while ``trim_active`` the controller states are zero. The control states
    sit after the rigid-body states, before alpha_trim (:func:`state_layout`). With ``"vlm"`` the
    surfaces are deflected panels of the lattice (:func:`~wingmdao.aero.vlm.flap_influence`): per node
    of each surface two Wagner states lag its deflection (:func:`flap_lag_state_names`, input
    beta + T11 b / (2 T10 v_c) dbeta), the lattice's flap columns carry the circulatory lift of the
    lagged deflection, the steady quarter-chord moment of the deflection and the hinge moment
    (parameters :func:`flap_param_specs`); the section keeps the flap's non-circulatory terms.

    Parameters
    ----------
    num_nodes : int
        Number of nodes (at least 2).
    euler_sequence : str
        Euler-angle sequence.
    damping : StrainRateDamping, optional
        Strain-rate damping of the beam.
    plunge : bool
        Free plunge.
    trim : bool
        Trim unknown alpha_trim.
    pitch : bool
        Free pitch with a horizontal tail.
    tail_lag : bool
        Downwash lag at the tail (with ``pitch``).
    aero_theory : str
        ``"strip"`` or ``"vlm"``.
    elevator : bool
        Elevator on the tail (with ``pitch``).
    controls : ControlSpec, optional
        Control surfaces and law; None: none.
    roll : bool
        The antisymmetric half wing: its root on a fuselage free to roll (:mod:`wingmdao.aero.roll`;
        states roll_angle, roll_rate; parameter ``body_roll_inertia``; forcing ``roll_start``, 1 at
        t = 0: phi = 0 in the initial static state). Excludes ``plunge``,
        ``trim`` and ``pitch`` (the symmetric motions). With ``"vlm"`` the influence parameters
        must be those of the antisymmetric lattice (:func:`three_dimensional_parameters` with
        ``antisymmetric=True``).

    Returns
    -------
    AeroelasticBeamSystem
        The system.
    """
    if aero_theory not in AERO_THEORIES:
        raise ValueError(f"aero_theory must be one of {', '.join(AERO_THEORIES)}, got {aero_theory!r}")
    vlm = aero_theory == "vlm"
    n = int(num_nodes)
    if n < 2:
        raise ValueError(f"num_nodes must be >= 2, got {num_nodes}")
    if pitch and not (plunge and trim):
        raise ValueError(f"pitch=True needs plunge=True and trim=True (got plunge={plunge}, trim={trim}): free "
                         "pitch starts from the trimmed 1 g state (tail incidence solved for pitch balance)")
    if tail_lag and not pitch:
        raise ValueError("tail_lag=True needs pitch=True")
    if elevator and not pitch:
        raise ValueError("elevator=True needs pitch=True (the elevator is on the horizontal tail)")
    if roll and (plunge or trim or pitch):
        raise ValueError(f"roll=True is the antisymmetric half wing: it excludes plunge, trim and pitch (symmetric "
                         f"motions); got plunge={plunge}, trim={trim}, pitch={pitch}")
    ctl = controls
    if ctl is not None:
        _check_controls(ctl, n, plunge, pitch)
    t0 = _time.perf_counter()
    pspecs = beam_param_specs(n) + aero_param_specs(n) + (vlm_param_specs(n) if vlm else [])
    qspecs = beam_forcing_specs(n) + aero_forcing_specs(n)
    if plunge:
        pspecs.append(VarSpec("body_mass", (), "kg", "aircraft mass outside both wing halves (free plunge)"))
    n_body = 0
    if pitch:
        body_names = (PITCH_STATE_NAMES + ((LAG_STATE_NAME,) if tail_lag else ())
                      + ((ELEVATOR_STATE_NAME,) if elevator else ()) + (INCIDENCE_STATE_NAME,))
        n_body = len(body_names)
        pspecs += pitch_param_specs() + (elevator_param_specs() if elevator else [])
        qspecs += pitch_forcing_specs() + (elevator_forcing_specs() if elevator else [])
    roll_names = ROLL_STATE_NAMES if roll else ()
    if roll:
        pspecs += roll_param_specs()
        qspecs += roll_forcing_specs()
    ctl_names, lag_names = (), ()
    if ctl is not None:
        ctl_names = ctl.state_names() + (tuple(f"reference_{nm}" for nm in ctl.outputs) if trim else ())
        pspecs += control_param_specs(ctl)
        if vlm:  # the flaps are panels of the lattice: their lagged deflection per node (two Wagner states)
            lag_names = flap_lag_state_names(ctl)
            pspecs += flap_param_specs(n, ctl)
        qspecs.append(VarSpec("surface_command", (ctl.n_surfaces,), "rad",
                              "open-loop command of each control surface (added to the control law's)"))
    n_ctl_base = len(ctl_names)
    ctl_names = ctl_names + lag_names
    if trim:
        pspecs.append(VarSpec("trim_lift", (), "N", "lift of both half-wings to trim to (n W)"))
        qspecs.append(VarSpec("trim_active", (), None, "1: solve alpha_trim for trim_lift; 0: hold alpha_trim"))
    play, qlay = layout(pspecs), layout(qspecs)
    W = N_AEROELASTIC_STATES
    n_ctl = len(ctl_names)
    n_roll = len(roll_names)
    n_extra = int(bool(plunge)) + n_body + n_roll + n_ctl + int(bool(trim))
    i_trim = W * n + int(bool(plunge)) + n_body + n_roll + n_ctl
    i_ctl = W * n + int(bool(plunge)) + n_body + n_roll
    rolling = slice(W * n, W * n + n_roll)  # the roll states (empty without roll)
    body = slice(W * n + 1, W * n + 1 + n_body)  # the pitch states (empty without pitch)
    x = ca.SX.sym("x", W * n + n_extra)
    xdot = ca.SX.sym("xdot", W * n + n_extra)
    p = ca.SX.sym("p", sum(s.size for s in pspecs))
    q = ca.SX.sym("q", sum(s.size for s in qspecs))
    elem = _element_function(euler_sequence, damping)
    nodal = _nodal_function(euler_sequence)
    g = q[qlay["gravity"]]
    acc0, vf = q[qlay["frame_acceleration"]], q[qlay["frame_velocity"]]
    dvf = q[qlay["frame_velocity_rate"]]
    if plunge:
        e_z = ca.DM([0.0, 0.0, 1.0])
        acc0 = acc0 + e_z * xdot[W * n]
        vf = vf + e_z * x[W * n]
        dvf = dvf + e_z * xdot[W * n]
    frame = (acc0, q[qlay["frame_angular_velocity"]], q[qlay["frame_angular_acceleration"]])
    if pitch:  # the pitch rate and its rate add to the frame's angular velocity / acceleration (about +y)
        e_y = ca.DM([0.0, 1.0, 0.0])
        frame = (acc0, frame[1] + e_y * x[body][1], frame[2] + e_y * xdot[body][1])
    if roll:  # the roll rate and its rate add to the frame's angular velocity / acceleration (about +x)
        e_x = ca.DM([1.0, 0.0, 0.0])
        frame = (acc0, frame[1] + e_x * x[rolling][1], frame[2] + e_x * xdot[rolling][1])
    aero_frame = (vf, dvf) + frame[1:]
    V, rho, mach = p[play["airspeed"]], p[play["density"]], p[play["mach"]]

    # one symbolic node function for the aerodynamics, called per node
    xs_ = ca.SX.sym("xn", W)
    xds_ = ca.SX.sym("xdn", W)
    pa_ = ca.SX.sym("pa", 6)
    fr_ = [ca.SX.sym(nm, 3) for nm in ("vf", "A0", "Om", "al0")]
    sc_ = ca.SX.sym("s", 3)
    f_, m_, res_, L_, M_, ex_ = node_aero(xs_, xds_, pa_, None, fr_, sc_[0], sc_[1], sc_[2], euler_sequence)
    aero_fun = ca.Function("aero_node", [xs_, xds_, pa_, *fr_, sc_], [f_, m_, res_, L_, M_, *ex_])

    xs = [x[W * i: W * (i + 1)] for i in range(n)]
    xds = [xdot[W * i: W * (i + 1)] for i in range(n)]
    ps = [_node_params(p, play, i) for i in range(n)]
    scal = ca.vertcat(V, rho, mach)
    surface_at, flap_funs = {}, []
    if ctl is not None:  # one node function per surface (its hinge), with the deflection, rate, acceleration
        fl_ = ca.SX.sym("flap", 3)
        for k, srf in enumerate(ctl.surfaces):
            T_k = theodorsen_flap_functions(srf[2])
            out_k = node_aero(xs_, xds_, pa_, None, fr_, sc_[0], sc_[1], sc_[2], euler_sequence,
                               flap=(T_k, fl_[0], fl_[1], fl_[2]), flap_lattice=vlm)
            flap_funs.append(ca.Function(f"aero_node_{srf[0]}", [xs_, xds_, pa_, *fr_, sc_, fl_],
                                         [*out_k[:5], *out_k[5]]))
            surface_at.update({i: k for i in srf[1]})
    aero_out, qs = [], []
    for i in range(n):
        azl = p[play["alpha_zero_lift"]][i] - (x[i_trim] if trim else 0.0)
        if pitch:  # the pitch attitude adds to every station's angle
            azl = azl - x[body][0]
        pa = ca.vertcat(p[play["chord"]][i], p[play["ref_point"]][i], p[play["lift_slope"]][i], azl,
                        p[play["cm0"]][i], q[qlay["gust_velocity"]][i])
        if i in surface_at:
            k = surface_at[i]
            fl = ca.vertcat(x[i_ctl + 2 * k], x[i_ctl + 2 * k + 1], xdot[i_ctl + 2 * k + 1])
            f_a, m_a, res_a, L_a, M_a, *ex_a = flap_funs[k](xs[i], xds[i], pa, *aero_frame, scal, fl)
        else:
            f_a, m_a, res_a, L_a, M_a, *ex_a = aero_fun(xs[i], xds[i], pa, *aero_frame, scal)
        aero_out.append([res_a, L_a, M_a, f_a, m_a, ex_a])
    flap_rows, flap_state = [], None
    if vlm and ctl is not None:  # per flap column (surface node): its lagged and its actual deflection
        i_lag = i_ctl + n_ctl_base
        lagged, actual, col = [], [], 0
        for k, srf in enumerate(ctl.surfaces):
            for i in srf[1]:
                u_i = aero_out[i][5][6]
                l_i, dl_i = x[i_lag + 2 * col: i_lag + 2 * col + 2], xdot[i_lag + 2 * col: i_lag + 2 * col + 2]
                b_i = 0.5 * p[play["chord"]][i]
                flap_rows += [b_i / (WAGNER_B[m] * V) * dl_i[m] + l_i[m] - u_i for m in range(2)]
                lagged.append((1.0 - sum(WAGNER_A)) * u_i + WAGNER_A[0] * l_i[0] + WAGNER_A[1] * l_i[1])
                actual.append(x[i_ctl + 2 * k])
                col += 1
        flap_state = (ca.vertcat(*lagged), ca.vertcat(*actual))
    if vlm:
        hinge_lattice = _vlm_loads(aero_out, p, play, n, 0.5 * rho * V ** 2, ctl, flap_state)
    for i in range(n):
        f_a, m_a = aero_out[i][3], aero_out[i][4]
        qb = _node_forcing(q, qlay, i)
        qs.append(ca.vertcat(qb[_Q_NODE["f"]] + f_a, qb[_Q_NODE["m"]] + m_a, qb[_Q_NODE["P"]], qb[_Q_NODE["Q"]]))
    st = STATE_BLOCKS
    blocks = []
    for i in range(n):
        xb, xdb = xs[i][:18], xds[i][:18]
        if i < n - 1:
            blocks.append(elem(xb, xs[i + 1][:18], xdb, xds[i + 1][:18], ps[i], ps[i + 1], qs[i], qs[i + 1],
                               g, *frame))
        else:
            blocks.append(ca.vertcat(
                xs[0][st["r"]] - ps[0][_P_NODE["r0"]],
                xs[0][st["theta"]] - ps[0][_P_NODE["theta0"]],
                xb[st["F"]] - qs[i][_Q_NODE["P"]],
                xb[st["M"]] - qs[i][_Q_NODE["Q"]]))
        blocks.append(nodal(xb, xdb))
        blocks.append(aero_out[i][0])
    if plunge:
        mb = p[play["body_mass"]]
        r_plunge = mb * (xdot[W * n] - g[2]) - 2.0 * xs[0][st["F"]][2]
        if trim:  # while trimming the plunge velocity is zero (alpha_trim takes up the lift)
            on = q[qlay["trim_active"]]
            r_plunge = on * x[W * n] + (1.0 - on) * r_plunge
        if pitch:  # the rigid-body rows of wingmdao.aero.pitch replace the plunge row
            r_plunge, lift_tail = body_residuals(
                x[body], xdot[body], w_p=x[W * n], dw_p=xdot[W * n], F0=xs[0][st["F"]], M0=xs[0][st["M"]],
                r0=xs[0][st["r"]], alpha_trim=x[i_trim], gust_root=q[qlay["gust_velocity"]][0],
                gust_tail=q[qlay["tail_gust_velocity"]], V=V, rho=rho, g=g, body_mass=mb, tail_lag=tail_lag,
                on=q[qlay["trim_active"]], pars={k: p[play[k]] for k in ("body_first_moment", "body_pitch_inertia",
                                                 "tail_x", "tail_area", "tail_lift_slope", "downwash_gradient")},
                elevator=(p[play["elevator_effectiveness"]], p[play["elevator_time_constant"]],
                          q[qlay["elevator_command"]]) if elevator else None)
        blocks.append(r_plunge)
    if roll:
        blocks.append(roll_residuals(x[rolling], xdot[rolling], F0=xs[0][st["F"]], M0=xs[0][st["M"]],
                                     r0=xs[0][st["r"]], pars={"body_roll_inertia": p[play["body_roll_inertia"]]},
                                     start=q[qlay["roll_start"]]))
    if ctl is not None:
        measured = dict(load_factor=(xdot[W * n] / G0) if plunge else None,
                        root_bending=xs[0][st["M"]][0] / ROOT_BENDING_UNIT,
                        tip_acceleration=(xds[n - 1][st["u"]][2] + (xdot[W * n] if plunge else 0.0)) / G0,
                        pitch_rate=x[body][1] if pitch else None)
        i_base = i_ctl + n_ctl_base
        blocks.append(_control_residuals(ctl, x[i_ctl:i_base], xdot[i_ctl:i_base], p, play,
                                         q[qlay["surface_command"]], [measured[nm] for nm in ctl.outputs],
                                         q[qlay["trim_active"]] if trim else None))
        blocks += flap_rows
    if trim:
        r0 = [ps[i][_P_NODE["r0"]] for i in range(n)]
        total = 0
        for i in range(n - 1):
            total = total + ca.norm_2(r0[i + 1] - r0[i]) * 0.5 * (aero_out[i][1] + aero_out[i + 1][1])
        target = p[play["trim_lift"]]
        on = q[qlay["trim_active"]]
        scale = ca.fmax(ca.fabs(target), 1.0)
        if pitch:  # wing + tail lift = trim_lift
            total = total + 0.5 * lift_tail
        blocks.append(on * (2.0 * total - target) / scale + (1.0 - on) * xdot[i_trim])
    R = ca.vertcat(*blocks)
    definition = aeroelastic_definition(n, euler_sequence, damping, plunge, trim, pitch, tail_lag, aero_theory,
                                        elevator, ctl, roll)
    jacobians = stored_jacobians(f"aeroelastic_beam{n}", definition, R, (x, xdot, p, q))
    lifts = ca.vertcat(*[o[1] for o in aero_out])
    moments = ca.vertcat(*[o[2] for o in aero_out])
    system = AeroelasticBeamSystem(x, xdot, p, q, R, param_specs=pspecs, forcing_specs=qspecs,
                                   state_shape=(W * n + n_extra,) if n_extra else (n, W),
                                   name=f"aeroelastic_beam{n}" + ("_plunge" if plunge else "") + ("_trim" if trim else "")
                                   + ("_pitch" if pitch else "") + ("_lag" if tail_lag else "")
                                   + ("_elevator" if elevator else "") + ("_vlm" if vlm else "")
                                   + ("_ctl" if ctl is not None else "") + ("_roll" if roll else ""),
                                   describe=lambda k: describe_aeroelastic_equation(
                                       k, n, plunge, (body_names if pitch else ()) + roll_names, ctl_names),
                                   definition=definition, jacobians=jacobians,
                                   lu_column_order=lu_orders.aeroelastic_lu_column_order(W * n + n_extra))
    system.num_nodes = n
    system.plunge = bool(plunge)
    system.trim = bool(trim)
    system.pitch = bool(pitch)
    system.tail_lag = bool(tail_lag)
    system.elevator = bool(elevator)
    system.aero_theory = aero_theory
    system.roll = bool(roll)
    system.layout = state_layout(n, plunge, trim, body_names if pitch else (), ctl_names, roll_names)
    if system.layout.size != system.n_state or system.layout.body.get("trim", i_trim) != i_trim:
        raise RuntimeError("state_layout does not match the states of build_aeroelastic_system")
    system.trim_index = system.layout.body.get("trim")
    system.body_index = ({"plunge_velocity": system.layout.body["plunge"]} if plunge else {}) | (
        {nm: system.layout.body[nm] for nm in body_names} if pitch else {}) | {
        nm: system.layout.body[nm] for nm in roll_names}
    system.controls = ctl
    system.control_index = {nm: system.layout.body[nm] for nm in ctl_names}
    if ctl is not None:
        hinge = _surface_hinge_moments(ctl, aero_out, ps)
        if vlm:
            hinge = hinge + hinge_lattice
        system._hinge = ca.Function("hinge_moments", [x, xdot, p, q], [hinge])
    if pitch:
        system._tail_lift = ca.Function("tail_lift", [x, xdot, p, q], [lift_tail])
    system._loads = ca.Function("section_loads", [x, xdot, p, q], [lifts, moments])
    system.build_time = _time.perf_counter() - t0
    return system


def _vlm_loads(aero_out, p, play, n, qdyn, ctl=None, flap=None):
    """Replace each station's circulatory lift by the vortex lattice's, in place (``aero_out[i]`` =
    [residual, lift, moment, force, moment vector, (normal, span axis, alpha_c, L_nc, M_nc, ...)]):
    ``L_c = q (A_L alpha_c + F_L beta_c)``, ``M = L_c c (ref - 1/4) + q (A_M alpha_c + F_M beta) + M_nc``
    with the flap columns' lagged deflections beta_c and actual deflections beta (``flap``, with
    ``ctl``). Returns the lattice's part of each surface's hinge moment (N m, (n_s,)), or None
    without surfaces: ``q (H_A alpha_c + H_F (r beta_c + (1 - r) beta))``, r the circulatory share
    T10 T12 / (T18 + T10 T12) of the thin-airfoil C_h,beta."""
    # the parameters are packed row-major (numpy); CasADi reshapes column-major
    A_L = ca.reshape(p[play["lift_influence"]], n, n).T
    A_M = ca.reshape(p[play["moment_influence"]], n, n).T
    alpha_c = ca.vertcat(*[o[5][2] for o in aero_out])
    lift_c = qdyn * (A_L @ alpha_c)
    moment_c = qdyn * (A_M @ alpha_c)
    hinge = None
    if ctl is not None and flap is not None:
        beta_c, beta = flap
        nf, ns = beta_c.shape[0], ctl.n_surfaces
        F_L = _matrix(p, play["flap_lift_influence"], n, nf)
        F_M = _matrix(p, play["flap_moment_influence"], n, nf)
        H_A = _matrix(p, play["hinge_station_influence"], ns, n)
        H_F = _matrix(p, play["hinge_flap_influence"], ns, nf)
        lift_c = lift_c + qdyn * (F_L @ beta_c)
        moment_c = moment_c + qdyn * (F_M @ beta)
        share = []
        for srf in ctl.surfaces:
            T = theodorsen_flap_functions(srf[2])
            share += [T[10] * T[12] / (T[18] + T[10] * T[12])] * len(srf[1])
        r = ca.DM(share)
        hinge = qdyn * (H_A @ alpha_c + H_F @ (r * beta_c + (1.0 - r) * beta))
    chord, ref = p[play["chord"]], p[play["ref_point"]]
    for i, o in enumerate(aero_out):
        nrm, span, _, lift_nc, moment_nc = o[5][:5]
        lift = lift_c[i] + lift_nc
        moment = lift_c[i] * chord[i] * (ref[i] - 0.25) + moment_c[i] + moment_nc
        o[1], o[2], o[3], o[4] = lift, moment, nrm * lift, span * moment
    return hinge


def flap_lag_state_names(ctl) -> tuple:
    """Names of the flaps' lag states of ``aero_theory="vlm"``: two Wagner states per node of each
    surface, ``NAME_lag_NODE_1``, ``NAME_lag_NODE_2`` (after the other control states).

    Parameters
    ----------
    ctl : ControlSpec
        The surfaces.

    Returns
    -------
    tuple of str
        The names in order.
    """
    return tuple(f"{srf[0]}_lag_{i}_{m}" for srf in ctl.surfaces for i in srf[1] for m in (1, 2))


def flap_param_specs(n: int, ctl) -> list[VarSpec]:
    """The lattice's flap influence parameters of ``aero_theory="vlm"`` with control surfaces
    (:func:`wingmdao.aero.vlm.flap_influence`; one column per node of each surface, in order).

    Parameters
    ----------
    n : int
        Number of nodes.
    ctl : ControlSpec
        The surfaces.

    Returns
    -------
    list of VarSpec
        The parameter blocks.
    """
    nf = sum(len(srf[1]) for srf in ctl.surfaces)
    ns = ctl.n_surfaces
    return [
        VarSpec("flap_lift_influence", (n, nf), "m", "lift per length at station i per dynamic pressure and radian "
                "of lagged flap deflection at flap column j (deflected lattice panels aft of the hinge)"),
        VarSpec("flap_moment_influence", (n, nf), "m**2", "moment per length about station i's quarter chord (nose "
                "up) per dynamic pressure and radian of flap deflection at flap column j (vortex lattice)"),
        VarSpec("hinge_station_influence", (ns, n), "m**3", "hinge moment of surface s (trailing edge down +) per "
                "dynamic pressure and radian of circulatory angle at station j (vortex lattice)"),
        VarSpec("hinge_flap_influence", (ns, nf), "m**3", "hinge moment of surface s (trailing edge down +) per "
                "dynamic pressure and radian of flap deflection at flap column j (vortex lattice)"),
    ]


#: unit of the measured root bending moment fed to a control law (MN m: gains of order one)
ROOT_BENDING_UNIT = 1.0e6


def _check_controls(ctl, n, plunge, pitch) -> None:
    """ValueError for a control spec the system cannot carry (nodes beyond the beam, an output that
    needs free plunge or pitch)."""
    for srf in ctl.surfaces:
        if max(srf[1]) >= n or min(srf[1]) < 0:
            raise ValueError(f"control surface {srf[0]!r}: nodes {srf[1][0]}..{srf[1][-1]} outside the span; "
                             f"allowed node indices 0 .. {n - 1}")
    needs = {"load_factor": ("plunge", plunge), "pitch_rate": ("pitch", pitch)}
    for nm in ctl.outputs:
        if nm in needs and not needs[nm][1]:
            raise ValueError(f"control law output {nm!r} needs free {needs[nm][0]} ({needs[nm][0]}=True)")


def control_param_specs(ctl) -> list[VarSpec]:
    """The control law's parameters (the gains): ``controller_A`` ... ``controller_C`` when the law
    has states, ``controller_D`` (feedthrough) whenever it has outputs (row-major matrices).

    Parameters
    ----------
    ctl : ControlSpec
        The surfaces and law.

    Returns
    -------
    list of VarSpec
        The parameter blocks (empty without outputs).
    """
    ny, ns, nc = len(ctl.outputs), ctl.n_surfaces, ctl.n_controller
    if not ny:
        return []
    out = []
    if nc:
        out += [VarSpec("controller_A", (nc, nc), "1/s", "controller state matrix A_c (dx_c/dt = A_c x_c + B_c y)"),
                VarSpec("controller_B", (nc, ny), None, "controller input matrix B_c (measured outputs y)"),
                VarSpec("controller_C", (ns, nc), None, "controller output matrix C_c (surface commands, rad)")]
    out.append(VarSpec("controller_D", (ns, ny), None, "controller feedthrough D_c: surface command (rad) per "
                       "measured output (load factor and accelerations in g, root bending in MN m, pitch rate rad/s)"))
    return out


def _matrix(p, sl, rows, cols):
    """A row-major packed parameter block as a CasADi (rows, cols) matrix."""
    return ca.reshape(p[sl], cols, rows).T


def _control_residuals(ctl, xc, xcd, p, play, command, measured, on):
    """Actuator, controller and measurement-reference rows (:func:`build_aeroelastic_system`)."""
    ns, nc, ny = ctl.n_surfaces, ctl.n_controller, len(ctl.outputs)
    u = command
    rows = []
    if ny:
        y = ca.vertcat(*measured)
        ref, dref = xc[2 * ns + nc:], xcd[2 * ns + nc:]
        e = y - ref if on is not None else y
        u = u + _matrix(p, play["controller_D"], ns, ny) @ e
        if nc:
            z, dz = xc[2 * ns:2 * ns + nc], xcd[2 * ns:2 * ns + nc]
            u = u + _matrix(p, play["controller_C"], ns, nc) @ z
            r_c = dz - _matrix(p, play["controller_A"], nc, nc) @ z - _matrix(p, play["controller_B"], nc, ny) @ e
            rows_c = r_c if on is None else on * z + (1.0 - on) * r_c
        if on is not None:
            rows_ref = on * (ref - y) + (1.0 - on) * dref
    for k, srf in enumerate(ctl.surfaces):
        rows += actuator_residuals(srf[3], srf[4], srf[5], srf[6], xc[2 * k], xc[2 * k + 1], xcd[2 * k],
                                   xcd[2 * k + 1], u[k])
    if ny and nc:
        rows.append(rows_c)
    if ny and on is not None:
        rows.append(rows_ref)
    return ca.vertcat(*rows)


def _surface_hinge_moments(ctl, aero_out, ps):
    """Hinge moment (N m, trailing edge down positive) of each surface of one half-wing: the
    trapezoid of its nodes' hinge moments per length over the undeformed beam."""
    out = []
    for srf in ctl.surfaces:
        idx, total = srf[1], 0
        for i, j in zip(idx[:-1], idx[1:]):
            ds = ca.norm_2(ps[j][_P_NODE["r0"]] - ps[i][_P_NODE["r0"]])
            total = total + 0.5 * ds * (aero_out[i][5][5] + aero_out[j][5][5])
        out.append(total)
    return ca.vertcat(*out)


def stored_jacobians(name: str, definition: str, R, args) -> dict:
    """``{"x", "xdot", "p", "q"}`` -> ``ca.jacobian(R, a)`` for the symbols ``args = (x, xdot, p, q)``,
    stored by ``definition`` (:mod:`wingmdao.utils.function_store`, entry ``NAME_jacobians``).

    Forming them is most of a coupled system's build (3.8 s of 4.0 s, 20 nodes, free plunge and
    trim), and it was repeated in every process. They are stored once as one CasADi function of
    ``args`` (its serialization, zlib-compressed: 3.2 MB instead of 25 MB) and, in a later process,
    deserialized (0.56 s) and called on this build's symbols (0.13 s): the same expression graphs,
    so the same sparsity patterns, values and compiled libraries (keyed by definition).

    Parameters
    ----------
    name : str
        Name of the system (prefix of the store entry).
    definition : str
        Definition key of the system.
    R : casadi.SX
        Residual expression.
    args : tuple of casadi.SX
        The symbols ``(x, xdot, p, q)``.

    Returns
    -------
    dict
        The four Jacobian expressions.
    """
    keys = ("x", "xdot", "p", "q")
    built = {}

    def make():
        built.update({k: ca.jacobian(R, a) for k, a in zip(keys, args)})
        fun = ca.Function(f"{name}_jacobians", list(args), [built[k] for k in keys])
        return {"function": np.frombuffer(zlib.compress(fun.serialize().encode(), 1), dtype=np.uint8)}

    data = function_store.get(f"{name}_jacobians", definition, make)
    if built:
        return built
    fun = ca.Function.deserialize(zlib.decompress(data["function"].tobytes()).decode())
    if fun.n_in() != len(args) or any(fun.size_in(i) != a.shape for i, a in enumerate(args)):
        raise RuntimeError(f"{name}: the stored Jacobians do not fit this build's symbols")
    return dict(zip(keys, fun.call(list(args))))


def describe_aeroelastic_equation(index: int, num_nodes: int, plunge: bool = False, body_names=(),
                                  control_names=()) -> str:
    """Name of residual ``index`` of an aeroelastic system (convergence diagnostics).

    Parameters
    ----------
    index : int
        Residual index.
    num_nodes : int
        Number of nodes.
    plunge : bool
        Free plunge.
    body_names : sequence of str
        Names of the free-pitch states.
    control_names : sequence of str
        Names of the control states.

    Returns
    -------
    str
        The name.
    """
    k_ctl = int(index) - N_AEROELASTIC_STATES * num_nodes - int(bool(plunge)) - len(body_names)
    if 0 <= k_ctl < len(control_names):
        return f"control state {control_names[k_ctl]} (actuator, controller, measurement reference or flap lag)"
    if index == N_AEROELASTIC_STATES * num_nodes and plunge:
        if body_names:
            return "free plunge + pitch: body translation (wingmdao.aero.pitch), or w_p = 0 in trim"
        return "free plunge: body_mass (dw_p/dt - g_z) = 2 F_root,z"
    k_body = int(index) - N_AEROELASTIC_STATES * num_nodes - int(bool(plunge))
    if 0 <= k_body < len(body_names):
        return {"pitch_angle": "dtheta_p/dt = q (theta_p = 0 in trim)",
                "pitch_rate": "body pitch moment about the origin (q = 0 in trim)",
                "downwash_lag": "downwash lag (x_t/V) de/dt + e = alpha_w",
                "elevator_deflection": "elevator actuator t_a d(delta)/dt + delta = elevator_command",
                "tail_incidence": "static pitch-moment balance in trim (tail incidence), held otherwise",
                "roll_angle": "dphi/dt = p (free roll), phi = 0 while roll_start",
                "roll_rate": "body roll moment about x: (I_xx,body / 2) dp/dt = M_x + y_0 F_z - z_0 F_y"}[body_names[k_body]]
    if index >= N_AEROELASTIC_STATES * num_nodes and body_names:
        return "trim: integrated lift of both halves + tail lift = trim_lift (or alpha_trim held)"
    if index >= N_AEROELASTIC_STATES * num_nodes:
        return "trim: integrated lift of both halves = trim_lift (or alpha_trim held)"
    node, k = divmod(int(index), N_AEROELASTIC_STATES)
    if k < N_STATE_PER_NODE:
        return describe_equation(node * N_STATE_PER_NODE + k, num_nodes)
    return f"node {node}, aerodynamic {AERO_STATE_NAMES[k - N_STATE_PER_NODE]}"


class AeroelasticBeamSystem(CasadiResidualSystem):
    """Beam + unsteady strip theory residual system; build with :func:`build_aeroelastic_system`.

    Attributes: ``num_nodes``; ``state_shape = (num_nodes, 22)``; ``layout``, the
    :class:`StateLayout` (flat indices of the beam, lag and body states: use it rather than
    offsets); ``BEAM = slice(0, 18)`` and ``AERO = slice(18, 22)`` index a node's row of the
    (n, 22) state.

    Parameters
    ----------
    x : casadi.SX or casadi.MX
        State symbol (column vector).
    xdot : casadi.SX or casadi.MX
        State-rate symbol, same size as ``x``.
    p : casadi.SX or casadi.MX
        Parameter symbol.
    q : casadi.SX or casadi.MX
        Forcing symbol.
    R : casadi.SX or casadi.MX
        Residual expression, one equation per state.
    param_specs : sequence of VarSpec
        Blocks of ``p`` (their sizes must add up to its size).
    forcing_specs : sequence of VarSpec
        Blocks of ``q``.
    state_shape : tuple of int, optional
        How the flat state is shown to users; default ``(n_state,)``.
    name : str
        Name of the CasADi functions.
    describe : callable, optional
        ``describe(i) -> str`` names residual ``i``.
    initial_guess : callable, optional
        ``initial_guess(p, q)`` returns the start of a static solve; default zeros.
    definition : optional
        Key of the expressions' compiled libraries (:func:`aeroelastic_definition`); None keys them by serialization.
    lu_column_order : array_like of int, optional
        Column order of the adjoint's static LU; None: natural order.
    jacobians : dict, optional
        Symbolic Jacobians ``{"x", "xdot", "p", "q"}`` already formed; None forms them.
    """

    BEAM = slice(0, N_STATE_PER_NODE)
    AERO = slice(N_STATE_PER_NODE, N_AEROELASTIC_STATES)

    def initial_guess(self, p, q):
        """Jig beam state with zero aerodynamic states.

        Parameters
        ----------
        p : array_like, shape (n_param,)
            Packed parameters.
        q : array_like, shape (n_forcing,)
            Packed forcing (unused).

        Returns
        -------
        ndarray, shape (n_state,)
            The guess.
        """
        n = self.num_nodes
        play = layout(self.param_specs)
        bp = {s.name: np.asarray(p[play[s.name]]).reshape(s.shape) for s in beam_param_specs(n)}
        x = np.zeros(self.n_state)
        x[self.layout.beam] = jig_state(bp)
        return x

    def section_loads(self, x, xdot, p, q):
        """(lift, moment) per unit length at every node (N/m along the section normal, N*m/m nose up).

        Parameters
        ----------
        x : array_like, shape (n_state,)
            State.
        xdot : array_like, shape (n_state,)
            State rate.
        p : array_like, shape (n_param,)
            Packed parameters.
        q : array_like, shape (n_forcing,)
            Packed forcing.

        Returns
        -------
        lift : ndarray, shape (n,)
            Lift per length (N/m).
        moment : ndarray, shape (n,)
            Moment per length (N m/m).
        """
        L, M = self._loads(np.ravel(x), np.ravel(xdot), np.ravel(p), np.ravel(q))
        return np.asarray(L).ravel(), np.asarray(M).ravel()

    def section_load_history(self, X, Xdot, p, Q):
        """Lift and moment per length histories (n_time, n_node) for state/rate/forcing histories.

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            State history.
        Xdot : ndarray, shape (n_time, n_state)
            State-rate history.
        p : array_like, shape (n_param,)
            Packed parameters.
        Q : ndarray, shape (n_time, n_forcing)
            Forcing history.

        Returns
        -------
        lift : ndarray, shape (n_time, n)
            Lift per length (N/m).
        moment : ndarray, shape (n_time, n)
            Moment per length (N m/m).
        """
        out = [self.section_loads(X[i], Xdot[i], p, Q[i]) for i in range(X.shape[0])]
        return np.array([o[0] for o in out]), np.array([o[1] for o in out])

    def total_lift_history(self, X, dt, p, Q):
        """Lift of both half-wings (N) at every instant: 2 x the trapezoid of the section lift over
        the undeformed beam (states X (n_time, n_state), BDF rates at step ``dt``, forcing Q).

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            State history.
        dt : float
            Time step (s).
        p : array_like, shape (n_param,)
            Packed parameters.
        Q : ndarray, shape (n_time, n_forcing)
            Forcing history.

        Returns
        -------
        ndarray, shape (n_time,)
            The lift (N).
        """
        lift, _ = self.section_load_history(X, state_rates(X, dt), p, Q)
        r0 = self.split_parameters(p)["node_positions"]
        ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
        return 2.0 * np.sum(0.5 * (lift[:, 1:] + lift[:, :-1]) * ds, axis=1)

    def tail_lift(self, x, xdot, p, q) -> float:
        """Horizontal-tail lift (N, body +z) of a free-pitch system at one state, rate and forcing.

        Parameters
        ----------
        x : array_like, shape (n_state,)
            State.
        xdot : array_like, shape (n_state,)
            State rate.
        p : array_like, shape (n_param,)
            Packed parameters.
        q : array_like, shape (n_forcing,)
            Packed forcing.

        Returns
        -------
        float
            The tail lift (N).
        """
        if not getattr(self, "pitch", False):
            raise ValueError("tail_lift needs a system built with pitch=True")
        return float(self._tail_lift(np.ravel(x), np.ravel(xdot), np.ravel(p), np.ravel(q)))

    def tail_lift_history(self, X, dt, p, Q):
        """Horizontal-tail lift (N) at every instant of a free-pitch system (``pitch=True``).

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            State history.
        dt : float
            Time step (s).
        p : array_like, shape (n_param,)
            Packed parameters.
        Q : ndarray, shape (n_time, n_forcing)
            Forcing history.

        Returns
        -------
        ndarray, shape (n_time,)
            The tail lift (N).
        """
        if not getattr(self, "pitch", False):
            raise ValueError("tail_lift_history needs a system built with pitch=True")
        Xd = state_rates(X, dt)
        return np.array([self.tail_lift(X[i], Xd[i], p, Q[i]) for i in range(X.shape[0])])

    def hinge_moments(self, x, xdot, p, q) -> np.ndarray:
        """Hinge moment (N m, trailing edge down positive) of each control surface of one half-wing.

        Parameters
        ----------
        x : array_like, shape (n_state,)
            State.
        xdot : array_like, shape (n_state,)
            State rate.
        p : array_like, shape (n_param,)
            Packed parameters.
        q : array_like, shape (n_forcing,)
            Packed forcing.

        Returns
        -------
        ndarray, shape (n_s,)
            The hinge moments (N m).
        """
        if getattr(self, "controls", None) is None:
            raise ValueError("hinge_moments needs a system built with controls")
        return np.asarray(self._hinge(np.ravel(x), np.ravel(xdot), np.ravel(p), np.ravel(q))).ravel()

    def control_histories(self, X, dt, p, Q) -> dict:
        """``deflection`` and ``rate`` (n_time, n_s) rad, rad/s and ``hinge_moment`` (n_time, n_s) N m
        of the control surfaces for a state history X (BDF rates at step ``dt``) and forcing Q.

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            State history.
        dt : float
            Time step (s).
        p : array_like, shape (n_param,)
            Packed parameters.
        Q : ndarray, shape (n_time, n_forcing)
            Forcing history.

        Returns
        -------
        dict
            The histories.
        """
        if getattr(self, "controls", None) is None:
            raise ValueError("control_histories needs a system built with controls")
        X = np.asarray(X)
        Xd = state_rates(X, dt)
        names = [s[0] for s in self.controls.surfaces]
        defl = np.stack([X[:, self.control_index[f"{nm}_deflection"]] for nm in names], axis=1)
        rate = np.stack([X[:, self.control_index[f"{nm}_rate"]] for nm in names], axis=1)
        hinge = np.array([self.hinge_moments(X[i], Xd[i], p, Q[i]) for i in range(X.shape[0])])
        return {"deflection": defl, "rate": rate, "hinge_moment": hinge}

    def split_parameters(self, p):
        """``{name: array}`` of a packed parameter vector.

        Parameters
        ----------
        p : array_like, shape (n_param,)
            Packed parameters.

        Returns
        -------
        dict of str to ndarray
            Each block in its shape.
        """
        lay = layout(self.param_specs)
        return {s.name: np.asarray(p[lay[s.name]]).reshape(s.shape) for s in self.param_specs}


_SYSTEMS: dict = {}


def cached_aeroelastic_system(num_nodes: int, euler_sequence: str = "surface",
                              damping: StrainRateDamping | None = None,
                              plunge: bool = False, trim: bool = False, pitch: bool = False,
                              tail_lag: bool = False, aero_theory: str = "strip",
                              elevator: bool = False, controls=None, roll: bool = False) -> AeroelasticBeamSystem:
    """:func:`build_aeroelastic_system`, built once per (num_nodes, sequence, damping, plunge, trim, pitch,
    tail_lag, aero_theory, elevator, controls).

    Parameters
    ----------
    num_nodes : int
        Number of nodes (at least 2).
    euler_sequence : str
        Euler-angle sequence.
    damping : StrainRateDamping, optional
        Strain-rate damping of the beam.
    plunge : bool
        Free plunge.
    trim : bool
        Trim unknown alpha_trim.
    pitch : bool
        Free pitch with a horizontal tail.
    tail_lag : bool
        Downwash lag at the tail (with ``pitch``).
    aero_theory : str
        ``"strip"`` or ``"vlm"``.
    elevator : bool
        Elevator on the tail (with ``pitch``).
    controls : ControlSpec, optional
        Control surfaces and law; None: none.
    roll : bool
        The antisymmetric half wing on a fuselage free to roll.

    Returns
    -------
    AeroelasticBeamSystem
        The (shared) system.
    """
    if damping is not None and damping.is_zero:
        damping = None
    key = (int(num_nodes), euler_sequence, damping, bool(plunge), bool(trim), bool(pitch), bool(tail_lag),
           str(aero_theory), bool(elevator)) + ((controls,) if controls is not None else ()) + (
        ("roll",) if roll else ())
    if key not in _SYSTEMS:
        _SYSTEMS[key] = build_aeroelastic_system(key[0], euler_sequence=euler_sequence, damping=damping,
                                                 plunge=key[3], trim=key[4], pitch=key[5], tail_lag=key[6],
                                                 aero_theory=key[7], elevator=key[8], controls=controls,
                                                 roll=bool(roll))
    return _SYSTEMS[key]
