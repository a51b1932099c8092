"""``CoupledAero``: the aerodynamic description of a load case on the aeroelastic beam.

A load case that carries one (``LoadCase.aero``) is analysed by
:class:`~wingmdao.components.aeroelastic.AeroelasticBeamDynamics` (unsteady strip theory on the
deforming beam, docs/aeroelasticity.md) instead of the structural ``BeamDynamics``; its gust
velocity history per station goes through the case's forcing ``gust_velocity`` (n_time, n) m/s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wingmdao.aero.system import (AERO_THEORY_CHOICES, aero_parameters, cached_aeroelastic_system,  # noqa: F401 - AERO_THEORY_CHOICES: public here
                                  control_param_specs, three_dimensional_parameters)
from wingmdao.loads.atmosphere import G0
from wingmdao.timemarch.system import pack
from wingmdao.aero.pitch import check_pitch_inputs
from wingmdao.aero.roll import check_roll_inputs

#: Aerodynamic forcing of a coupled case, shapes per instant ("n" = number of nodes).
AERO_FORCING_SHAPES = {"gust_velocity": ("n",), "frame_velocity": (3,), "frame_velocity_rate": (3,),
                       "trim_active": (), "tail_gust_velocity": (), "roll_start": ()}
AERO_FORCING_META = {"gust_velocity": ("m/s", "gust velocity (body +z) at each station, penetration delay included"),
                     "frame_velocity": ("m/s", "velocity of the body-axes origin relative to the trimmed flight"),
                     "frame_velocity_rate": ("m/s**2", "rate of frame_velocity (apparent mass)"),
                     "trim_active": (None, "1: solve alpha_trim for trim_lift; 0: hold alpha_trim"),
                     "tail_gust_velocity": ("m/s", "gust velocity (body +z) at the tail, its penetration delay included"),
                     "roll_start": (None, "1: the roll angle is zero (the initial static state); 0: dphi/dt = p")}
#: forcing only a free-pitch case has (wingmdao.aero.pitch)
PITCH_FORCING = ("tail_gust_velocity",)
#: forcing only a free-roll case has (wingmdao.aero.roll)
ROLL_FORCING = ("roll_start",)


def case_has_forcing(aero, name: str) -> bool:
    """Whether the coupled case ``aero`` (:class:`CoupledAero`) has the aerodynamic forcing ``name``
    (:data:`AERO_FORCING_SHAPES`): ``trim_active`` with trim, ``tail_gust_velocity`` with free pitch,
    ``roll_start`` with free roll, the others always.

    Parameters
    ----------
    aero : CoupledAero
        The case's aerodynamics.
    name : str
        A forcing name.

    Returns
    -------
    bool
        Whether the case's residual has it.
    """
    return ((name != "trim_active" or bool(aero.trim)) and (name not in PITCH_FORCING or bool(aero.pitch))
            and (name not in ROLL_FORCING or bool(getattr(aero, "roll", False))))


@dataclass
class CoupledAero:
    """Per-station aerodynamic parameters (SI) of a coupled load case.

    ``chord`` (m), ``ref_point`` (beam axis, fraction of chord aft of the leading edge),
    ``lift_slope`` (1/rad), ``alpha_zero_lift`` (rad), ``cm0`` per node (scalars broadcast);
    ``airspeed`` (m/s TAS), ``density`` (kg/m**3), ``mach``; ``trim`` solves the aircraft angle
    of attack for ``trim_lift`` (N, both half-wings) wherever the forcing ``trim_active`` is 1.
    ``plunge`` frees the aircraft in plunge: the case then has the input ``aircraft_mass`` (kg,
    the whole aircraft, set from this field; connect an aircraft model to it), the model forms
    the plunge state's mass ``aircraft_mass - 2 m_half`` (:mod:`wingmdao.aero.plunge`) and, with
    ``trim``, ``trim_lift = n g0 aircraft_mass`` at the load factor n = trim_lift / (g0 aircraft_mass)
    of the values given here (:func:`trim_load_factor`). ``pitch`` (needs ``plunge`` and ``trim``)
    also frees the aircraft in pitch with a horizontal tail (:mod:`wingmdao.aero.pitch`): inputs
    ``aircraft_cg`` (x, z m from the body-axes origin), ``aircraft_pitch_inertia`` (kg m^2, about the
    CG), ``tail_arm`` (m), parameters ``tail_area`` (m^2), ``tail_lift_slope`` (1/rad),
    ``downwash_gradient``; ``tail_lag`` the first-order downwash lag. ``controls``
    (:class:`~wingmdao.aero.controls.ControlSpec`) and ``control_law``
    (:class:`~wingmdao.aero.controls.ControlLaw`): control surfaces and a feedback law in the
    residual (docs/controls.md); the law's matrices are then inputs of the case (``controller_D``,
    and ``controller_A`` ... ``controller_C`` when the law has states) and ``surface_command`` (n_time,
    n_s) rad a forcing. ``gain_design``: the law's ``controller_C`` and ``controller_D`` are design
    variables of the sizing (:func:`wingmdao.sizing.control_gain_design_vars`). ``surface_limits``:
    per surface ``(max_deflection, max_rate)`` (rad, rad/s): the case then has the output
    ``actuator_ks`` (:class:`~wingmdao.components.actuator_limits.ActuatorLimitKS`), a constraint
    (<= 1) of the sizing when the gains are sized (a case with a modal doublet-lattice gust: of the
    modal march's actuator states). ``elevator_effectiveness``
    (tau_e, with ``pitch``; 0: none): a trimmed static maneuver reports its elevator angle with the
    stabiliser at its 1 g setting (:func:`wingmdao.loads.maneuver_trim.elevator_trim`). ``roll``: the
    antisymmetric half wing on a fuselage free to roll (:mod:`wingmdao.aero.roll`; no plunge, trim or
    pitch), ``roll_inertia`` the fuselage's I_xx,body (kg m^2; the case's input ``body_roll_inertia`` is
    half of it), the forcing ``roll_start`` (1 at t = 0); with ``"vlm"`` the lattice's antisymmetric image.

    ``aero_theory`` (:data:`AERO_THEORY_CHOICES`): ``"strip"`` (each station's slope
    ``lift_slope``), ``"lifting-line"`` (``lift_slope`` replaced by the section slopes of
    Prandtl's lifting line of the planform, :mod:`wingmdao.aero.lifting_line`) or ``"vlm"`` (the
    circulatory quasi-steady lift of every station from the vortex lattice of the planform,
    :mod:`wingmdao.aero.vlm`; ``lift_slope`` unused). Both 3-D theories need
    ``node_positions`` (n, 3) m, the jig beam nodes (the planform is chord, ref_point and the nodes).

    Parameters
    ----------
    chord : float or array_like
        Chord per node (m).
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    ref_point : float or array_like, optional
        Beam axis, fraction of the chord aft of the leading edge.
    lift_slope : float or array_like, optional
        Section lift-curve slope (1/rad).
    alpha_zero_lift : float or array_like, optional
        Zero-lift angle (rad).
    cm0 : float or array_like, optional
        Zero-lift pitching moment coefficient (-).
    mach : float, optional
        Mach number (-).
    plunge : bool, optional
        Free the aircraft in plunge.
    trim : bool, optional
        Trim the angle of attack for ``trim_lift``.
    aircraft_mass : float, optional
        Aircraft mass (kg).
    trim_lift : float, optional
        Lift of both half-wings to trim to (N).
    pitch : bool, optional
        Free the aircraft in pitch with a horizontal tail.
    tail_lag : bool, optional
        Lag the wing's downwash at the tail.
    aircraft_cg : tuple, optional
        (x, z) of the CG from the body-axes origin (m).
    aircraft_pitch_inertia : float, optional
        Pitch inertia about the CG (kg m^2).
    tail_arm : float, optional
        Tail arm (m).
    tail_area : float, optional
        Tail area (m^2).
    tail_lift_slope : float, optional
        Tail lift-curve slope (1/rad).
    downwash_gradient : float, optional
        d epsilon / d alpha at the tail (-).
    aero_theory : {"strip", "lifting-line", "vlm"}, optional
        Quasi-steady lift theory.
    node_positions : array_like or None, optional
        (n, 3) jig beam nodes (m), for the 3-D theories.
    controls : ControlSpec or None, optional
        Control surfaces in the residual.
    control_law : ControlLaw or None, optional
        Feedback law in the residual.
    gain_design : bool, optional
        The law's ``controller_C`` and ``controller_D`` are design variables.
    surface_limits : tuple or None, optional
        Per surface ``(max_deflection, max_rate)`` (rad, rad/s); None: no actuator-limit output.
    closed_loop_margin : float, optional
        With ``gain_design``: the decay rate every loaded closed-loop mode must reach,
        ``Re lambda <= -closed_loop_margin`` (1/s, >= 0; the ``margin`` of the ``closed_loop_ks``
        constraint).
    elevator_effectiveness : float, optional
        tau_e of the elevator (-; 0: none).
    roll : bool, optional
        The antisymmetric half wing free to roll.
    roll_inertia : float, optional
        I_xx,body of the fuselage (kg m^2), with ``roll``.
    """

    chord: object
    airspeed: float
    density: float
    ref_point: object = 0.4
    lift_slope: object = 2 * np.pi
    alpha_zero_lift: object = 0.0
    cm0: object = 0.0
    mach: float = 0.0
    plunge: bool = False
    trim: bool = False
    aircraft_mass: float = 0.0
    trim_lift: float = 0.0
    pitch: bool = False
    tail_lag: bool = False
    aircraft_cg: tuple = (0.0, 0.0)
    aircraft_pitch_inertia: float = 0.0
    tail_arm: float = 0.0
    tail_area: float = 0.0
    tail_lift_slope: float = 0.0
    downwash_gradient: float = 0.0
    aero_theory: str = "strip"
    node_positions: object = None
    controls: object = None
    control_law: object = None
    gain_design: bool = False
    surface_limits: object = None
    closed_loop_margin: float = 0.0
    elevator_effectiveness: float = 0.0
    roll: bool = False
    roll_inertia: float = 0.0

    @property
    def residual_theory(self) -> str:
        """The residual's ``aero_theory`` (:data:`wingmdao.aero.system.AERO_THEORIES`): the lifting
        line only changes ``lift_slope`` of the strip residual."""
        return "vlm" if self.aero_theory == "vlm" else "strip"

    def trim_load_factor(self) -> float:
        """n = trim_lift / (g0 aircraft_mass): the trimmed load factor of a free-plunge case."""
        return float(self.trim_lift) / (G0 * float(self.aircraft_mass))

    def model_inputs(self) -> dict:
        """Inputs of the case that are not aerodynamic parameters: ``aircraft_mass`` (kg) with plunge."""
        out = {"aircraft_mass": float(self.aircraft_mass)} if self.plunge else {}
        if self.pitch:
            out.update(aircraft_cg=np.asarray(self.aircraft_cg, dtype=float),
                       aircraft_pitch_inertia=float(self.aircraft_pitch_inertia), tail_arm=float(self.tail_arm))
        return out

    def parameters(self, num_nodes: int) -> dict:
        """The aerodynamic input values (validated; ValueError naming a bad input).

        Parameters
        ----------
        num_nodes : int
            Beam nodes.

        Returns
        -------
        dict
            Parameter name -> value.
        """
        out = aero_parameters(num_nodes, chord=self.chord, ref_point=self.ref_point, lift_slope=self.lift_slope,
                              alpha_zero_lift=self.alpha_zero_lift, cm0=self.cm0, airspeed=self.airspeed,
                              density=self.density, mach=self.mach)
        out.update(self._three_dimensional(num_nodes, out))
        if self.plunge and not (np.isfinite(self.aircraft_mass) and self.aircraft_mass > 0):
            raise ValueError(f"CoupledAero: aircraft_mass = {self.aircraft_mass} kg with plunge=True; "
                             "allowed range (0, inf) kg")
        if self.trim:
            if not np.isfinite(self.trim_lift):
                raise ValueError(f"CoupledAero: trim_lift must be finite (N), got {self.trim_lift}")
            if not self.plunge:  # with plunge the model forms trim_lift from aircraft_mass
                out["trim_lift"] = float(self.trim_lift)
        if self.pitch:
            if not (self.plunge and self.trim):
                raise ValueError("CoupledAero: pitch=True needs plunge=True and trim=True")
            check_pitch_inputs(aircraft_pitch_inertia=self.aircraft_pitch_inertia, tail_arm=self.tail_arm,
                               tail_area=self.tail_area, tail_lift_slope=self.tail_lift_slope,
                               downwash_gradient=self.downwash_gradient)
            out.update(tail_area=float(self.tail_area), tail_lift_slope=float(self.tail_lift_slope),
                       downwash_gradient=float(self.downwash_gradient))
        if self.roll:
            if self.plunge or self.trim or self.pitch:
                raise ValueError("CoupledAero: roll=True is the antisymmetric half wing; it excludes plunge, trim "
                                 "and pitch")
            if self.aero_theory == "lifting-line":
                raise ValueError("CoupledAero: roll=True allows aero_theory strip or vlm (the lifting line's slopes "
                                 "are those of the symmetric loading)")
            check_roll_inputs(roll_inertia=self.roll_inertia)
            out["body_roll_inertia"] = 0.5 * float(self.roll_inertia)
        if self.controls is not None and self.control_law is not None:
            names = {s.name for s in control_param_specs(self.controls)}
            out.update({k: v for k, v in self.control_law.matrices().items() if k in names})
        return out


    def _three_dimensional(self, num_nodes: int, values: dict) -> dict:
        """The lifting line's ``lift_slope`` or the vortex lattice's influence matrices (empty for strip)."""
        if self.aero_theory != "strip" and self.node_positions is None:
            raise ValueError(f"CoupledAero: aero_theory = {self.aero_theory!r} needs node_positions (the jig beam nodes)")
        return three_dimensional_parameters(self.aero_theory, self.node_positions, values["chord"],
                                            values["ref_point"], values["mach"], controls=self.controls,
                                            antisymmetric=bool(self.roll))


def load_case_response(prob, case, num_nodes: int, weight: float, *, path: str | None = None) -> dict:
    """Load factor and root loads of an analysed load case of a sizing problem (``cases.<name>``,
    or ``path``). A case with a modal doublet-lattice gust (``LoadCase.modal_dlm``): its static
    first instant plus the modal increment (:func:`modal_dlm_response`).

    ``weight`` (N): the aircraft weight W. Returns ``time``, ``load_factor`` (lift of both
    half-wings / W: for a coupled case from its section lift, :meth:`total_lift_history`, zero for
    a rolling case whose halves' lifts cancel; for a
    strip case the z-sum of its applied line and point forces), ``root_bending_moment`` and
    ``root_torsion`` (N m, M_x and M_y at the root node, body axes), ``tip_displacement`` (m, z),
    and the peaks ``peak_load_factor``, ``peak_root_bending_moment`` (largest magnitudes).

    Parameters
    ----------
    prob : openmdao.api.Problem
        A run sizing problem.
    case : LoadCase
        The load case.
    num_nodes : int
        Beam nodes.
    weight : float
        Aircraft weight W (N).
    path : str or None, optional
        Path of the case's group; None for ``cases.<name>``.

    Returns
    -------
    dict
        Histories and peaks (above).
    """
    if case.modal_dlm is not None:
        return modal_dlm_response(prob, case, num_nodes, weight)
    n, path = int(num_nodes), path or f"cases.{case.name}"
    t = case.time

    def value(name):  # the beam input under its promoted name (case, model) or its own
        for full in (f"{path}.{name}", name, f"{path}.beam.{name}"):
            try:
                return np.asarray(prob.get_val(full))
            except KeyError:
                continue
        raise KeyError(f"beam input {name} of load case {case.name} not found")

    def forcing(name):  # an input, or the case's own array when the beam holds it as data (forcing_as_data)
        try:
            return value(name)
        except KeyError:
            return np.asarray(case.forcing_array(name, n))

    X = np.asarray(prob.get_val(f"{path}.states")).reshape(t.size, -1)
    r0 = value("node_positions").reshape(n, 3)
    ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
    if case.aero is not None:
        pitch = bool(case.aero.pitch)
        system = cached_aeroelastic_system(n, plunge=bool(case.aero.plunge), trim=bool(case.aero.trim), pitch=pitch,
                                           tail_lag=pitch and bool(case.aero.tail_lag),
                                           aero_theory=case.aero.residual_theory, controls=case.aero.controls,
                                           roll=bool(case.aero.roll))
        beam = system.layout.beam_states(X)
        p = pack(system.param_specs, {s.name: value(s.name) for s in system.param_specs})
        Q = np.concatenate([forcing(s.name).reshape(t.size, -1) for s in system.forcing_specs], axis=1)
        dt = float(t[1] - t[0]) if t.size > 1 else 1.0
        lift = system.total_lift_history(X, dt, p, Q)
        if case.aero.roll:  # antisymmetric: the two halves' lifts cancel
            lift = 0.0 * lift
        if pitch:  # the aircraft's load factor: wing + tail lift
            lift = lift + system.tail_lift_history(X, dt, p, Q)
    else:
        beam = X.reshape(t.size, n, 18)
        f = case.forcing_array("force_per_length", n)[:, :, 2]
        lift = 2.0 * (np.sum(0.5 * (f[:, 1:] + f[:, :-1]) * ds, axis=1)
                      + case.forcing_array("point_force", n)[:, :, 2].sum(axis=1))
    n_load = lift / float(weight)
    rbm = beam[:, 0, 9]
    return {"time": t.tolist(), "load_factor": n_load.tolist(), "root_bending_moment": rbm.tolist(),
            "root_torsion": beam[:, 0, 10].tolist(), "tip_displacement": (beam[:, -1, 2] - r0[-1, 2]).tolist(),
            "peak_load_factor": float(n_load[np.argmax(np.abs(n_load))]),
            "peak_root_bending_moment": float(rbm[np.argmax(np.abs(rbm))])}


def modal_dlm_response(prob, case, num_nodes: int, weight: float) -> dict:
    """:func:`load_case_response` of a case with a modal doublet-lattice gust: the static first
    instant's (``cases.<name>.static``) plus the increments: load factor from the panel lift
    (twice the half-wing's aerodynamic root shear, :meth:`ModalStationLoads.aerodynamic_loads`),
    root moments from the force-summation loads, tip deflection from the modal amplitudes.

    Parameters
    ----------
    prob : openmdao.api.Problem
        A run sizing problem.
    case : LoadCase
        A case with a modal doublet-lattice gust.
    num_nodes : int
        Beam nodes.
    weight : float
        Aircraft weight W (N).

    Returns
    -------
    dict
        Histories and peaks, as :func:`load_case_response`.
    """
    n, path = int(num_nodes), f"cases.{case.name}"
    static = load_case_response(prob, case.static_case(n), n, weight, path=f"{path}.static")
    comp = next(s for s in prob.model.system_iter(recurse=True) if s.pathname == f"{path}.modal.loads")
    X = np.asarray(prob.get_val(f"{path}.modal.march.states"))
    inputs = {k: np.asarray(prob.get_val(f"{path}.modal.loads.{k}")) for k in ("modal_mass", "modal_stiffness",
                                                                                "modal_inertia")}
    inputs["states"] = X
    total, aero = comp.body_loads(inputs)
    wing = case.modal_dlm.wing
    m = wing.modes.count
    tip = (wing.tip_displacement(X) if case.modal_dlm.plunge  # elastic, relative to the body axes
           else wing.modes.displacement[:, -1, 2] @ X[:, :m].T)
    n_load = static["load_factor"][0] + 2.0 * aero[:, 0, 2] / float(weight)
    rbm = static["root_bending_moment"][0] + total[:, 0, 3]
    return {"time": case.time.tolist(), "load_factor": n_load.tolist(), "root_bending_moment": rbm.tolist(),
            "root_torsion": (static["root_torsion"][0] + total[:, 0, 4]).tolist(),
            "tip_displacement": (static["tip_displacement"][0] + tip).tolist(),
            "peak_load_factor": float(n_load[np.argmax(np.abs(n_load))]),
            "peak_root_bending_moment": float(rbm[np.argmax(np.abs(rbm))])}
