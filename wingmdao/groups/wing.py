"""Groups that wire the discipline chain: section -> beam -> internal loads -> stress -> KS.

``WingStructure`` analyses one load case; ``WingSizing`` shares the thickness design
variables and section properties among any number of static and dynamic load cases and
adds the mass objective. Promoted names follow the chain so the N2 diagram reads like it::

    design  (t_upper_skin, ..., width, height, node_positions, node_euler_angles)
    section (BoxSection: stiffness_csn, compliance_csn, offsets, mass_per_length, ...)
    mass    (StructuralMass: mass)
    cases.<case>: forcing inputs (force_per_length, ..., promoted) -> beam (states)
                  -> internal_loads -> stress -> ks   (ks_<family>)

Loads are inputs: ``cases.<case>.force_per_length`` etc. are set by
:func:`set_case_loads` (``wingmdao.sizing.build_problem`` does it) or connected from any
upstream component, e.g. an aerodynamic solver; ``cases`` promotes only the inputs shared by
every case.

Every group uses ``LinearRunOnce`` (OpenMDAO's default): the beam solves its own linear
systems (forward and adjoint sweeps over the time history); a ``DirectSolver`` above it
would assemble the whole history matrix and bypass that.
"""

from __future__ import annotations

import importlib.util
import numbers
from dataclasses import replace

import numpy as np
import openmdao.api as om

from wingmdao.beam.residual import forcing_specs
from wingmdao.groups.load_case import FORCING_SHAPES, LoadCase
from wingmdao.groups.single_subsystem import SingleSubsystemRunOnce
from wingmdao.design import BOX_KINDS, SECTION_KINDS
from wingmdao.materials import Material
from wingmdao.panels.layout import STIFFENER_VARS, PanelLayout
from wingmdao.section.box import WALL_NAMES
from wingmdao.stress.box_stress import SECTION_PROPERTIES
from wingmdao.aero.modal_design import DESIGN_INPUTS
from wingmdao.aero.rfa_system import control_state_offset, modal_rfa_system
from wingmdao.components.beam import BeamDynamics
from wingmdao.components.modal_dlm import ModalLoadSum, ModalProjectionComp, ModalStationLoads
from wingmdao.components.time_history import TimeHistoryComponent
from wingmdao.components.beam_loads import BeamInternalLoads
from wingmdao.components.actuator_limits import ActuatorLimitKS
from wingmdao.components.closed_loop import ClosedLoopDamping
from wingmdao.components.modal_closed_loop import ModalClosedLoopDamping, loaded_modes
from wingmdao.components.flutter import FlutterDamping
from wingmdao.components.turbulence import TurbulenceStressKS
from wingmdao.components.ks import KSAggregate
from wingmdao.components.load_combination import SymmetricLoadCombination
from wingmdao.components.load_gradient import InternalForceGradient
from wingmdao.components.mass import StructuralMass
from wingmdao.components.station_map import StationMap
from wingmdao.aero.coupled import AERO_FORCING_META, AERO_FORCING_SHAPES, case_has_forcing
from wingmdao.aero.system import (aero_param_specs, cached_aeroelastic_system, control_param_specs, flap_param_specs,
                                  vlm_param_specs)
from wingmdao.beam.static import cached_beam_system
from wingmdao.components.aeroelastic import AeroelasticBeamDynamics, PitchBodyProperties, PlungeBodyMass
from wingmdao.components.panels import EquivalentPanelFailure, PanelFailure, RibMass, SizingRules, StiffenedBoxSection
from wingmdao.components.section import BoxSection, SolidRectSection
from wingmdao.components.solid_stress import SolidRectStress
from wingmdao.components.state_slice import BeamStateSlice
from wingmdao.components.stress import BoxStress

#: the control-law gains a sizing can make design variables (docs/controls.md): the filter dynamics A, B stay fixed
SIZED_GAINS = ("controller_C", "controller_D")

#: Inputs the beam takes from the section, with the section output that feeds it.
SECTION_TO_BEAM = ("stiffness_csn", "compliance_csn", "mass_per_length", "inertia_per_length")
WALLS = WALL_NAMES

def _section_classes(kind):
    if kind == "box":
        return BoxSection, BoxStress
    if kind == "stiffened":
        return StiffenedBoxSection, BoxStress
    if kind == "solid":
        return SolidRectSection, SolidRectStress
    raise ValueError(f"section must be one of {', '.join(SECTION_KINDS)}, got {kind!r}")


#: Beam offset inputs and the section outputs (c, n) that form them.
SECTION_OFFSETS = {"tension_axis": ("c_ea", "n_ea"), "shear_center": ("c_sc", "n_sc"),
                   "mass_center": ("c_cg", "n_cg")}


def add_section_offsets(group: om.Group, num_nodes: int, *, source: str = "", mux=None, **promotes):
    """Add an ``offsets`` MuxComp to ``group`` that stacks the section's (c, n) centres into the
    beam's (n, 2) ``tension_axis``, ``shear_center``, ``mass_center`` inputs (SECTION_OFFSETS).
    ``source``: prefix of the section outputs (e.g. ``"section."``; empty when promoted);
    ``mux``: a MuxComp instance to use (e.g. a tagged subclass); ``promotes``: add_subsystem's.

    Parameters
    ----------
    group : openmdao.api.Group
        The group to add to.
    num_nodes : int
        Beam nodes.
    source : str, optional
        Prefix of the section outputs.
    mux : openmdao.api.MuxComp or None, optional
        MuxComp instance to use.
    **promotes
        Passed to ``add_subsystem``.
    """
    mux = group.add_subsystem("offsets", mux if mux is not None else om.MuxComp(vec_size=2), **promotes)
    for out, (c, n) in SECTION_OFFSETS.items():
        mux.add_var(out, shape=(num_nodes,), axis=1, units="m")
        group.connect(f"{source}{c}", f"offsets.{out}_0")
        group.connect(f"{source}{n}", f"offsets.{out}_1")
    return mux


def stress_points(kind, families) -> dict:
    """Constraint points per station of each stress family of section ``kind`` (no Problem built).

    Parameters
    ----------
    kind : str
        Section kind.
    families : sequence of str
        Stress families.

    Returns
    -------
    dict
        Family -> points per station.
    """
    return {fam: _section_classes(kind)[1].points_per_station(fam) for fam in families}


#: Units and description of each forcing input of a load case (the beam's forcing blocks,
#: wingmdao.beam.residual.forcing_specs; shapes per instant: FORCING_SHAPES).
FORCING_META = {s.name: (s.units, s.desc) for s in forcing_specs(1)}


def set_case_loads(prob: om.Problem, case: LoadCase, num_nodes: int, path: str = "", *,
                   forcing: bool | None = None) -> None:
    """Set the forcing inputs of ``case`` at ``path`` (the WingStructure's promoted prefix,
    e.g. ``"cases.gust"``) from its arrays; forcing it does not give is set to zero.
    ``forcing``: whether to set the beam forcing (FORCING_META); None (default) sets it when the
    case promotes it as inputs and skips it when it is data of the beam (WingStructure
    ``forcing_as_data``); a coupled case's aerodynamic forcing and parameters are always set.

    Parameters
    ----------
    prob : openmdao.api.Problem
        The set-up problem.
    case : LoadCase
        The load case.
    num_nodes : int
        Beam nodes.
    path : str, optional
        Promoted prefix of the case's WingStructure.
    forcing : bool or None, optional
        Set the beam forcing; None when the case promotes it as inputs.
    """
    prefix = f"{path}." if path else ""
    promoted = {meta["prom_name"] for meta in
                prob.model.get_io_metadata(iotypes="input", metadata_keys=[], get_remote=True).values()}
    beam_inputs = [prefix + name in promoted for name in FORCING_META]
    if forcing is None:
        forcing = all(beam_inputs)
    elif forcing and not all(beam_inputs):
        missing = [prefix + name for name, have in zip(FORCING_META, beam_inputs) if not have]
        raise ValueError(f"set_case_loads(forcing=True): {', '.join(missing)} are not inputs of the model "
                         f"(the case's forcing is data of its beam, forcing_as_data=True, or path {path!r} "
                         "is not a load case's prefix); use forcing=None")
    if case.modal_dlm is not None:  # the beam's part is the static first instant (LoadCase.static_case)
        case = case.static_case(num_nodes)
    for name, (units, _) in (FORCING_META.items() if forcing else ()):
        prob.set_val(prefix + name, case.forcing_array(name, num_nodes), units=units)
    if case.aero is not None:  # coupled case: its aerodynamic forcing and parameters
        for name, (units, _) in AERO_FORCING_META.items():
            if case_has_forcing(case.aero, name):
                prob.set_val(prefix + name, case.forcing_array(name, num_nodes), units=units)
        if case.aero.controls is not None:
            prob.set_val(prefix + "surface_command", case.forcing_array("surface_command", num_nodes), units="rad")
        for name, val in {**case.aero.parameters(num_nodes), **case.aero.model_inputs()}.items():
            prob.set_val(prefix + name, val)


class WingStructure(om.Group):
    """One load case: beam (static or BDF2 time march) -> csn internal loads -> stress -> KS.

    Promoted inputs: the forcing of the case, ``force_per_length``, ``moment_per_length``,
    ``point_force``, ``point_moment`` ((n_time, n, 3) in N/m, N*m/m, N, N*m, body axes),
    ``gravity``, ``frame_acceleration`` ((n_time, 3) m/s**2), ``frame_angular_velocity``
    (rad/s), ``frame_angular_acceleration`` (rad/s**2): connect any component to them, or set
    them with :func:`set_case_loads` (``loads_component=True`` instead adds an ``loads``
    IndepVarComp holding the case's arrays, for stand-alone use); the beam parameters and
    section inputs (``node_positions``, ``stiffness_csn``, ..., ``width``, ``t_upper_skin``, ...).
    A coupled case (``LoadCase.aero``) also promotes the aerodynamic parameters and forcing
    (``chord``, ..., ``gust_velocity``, ...) and, in free plunge, ``aircraft_mass`` (kg), from
    which ``plunge_mass`` (PlungeBodyMass) forms the plunge state's mass (and the trim lift).
    Promoted outputs: ``ks_<family>`` per stress family of the case (``add_constraints=True``
    makes each an upper-bounded-by-0 constraint, like ``om.KSComp``), and ``states``.
    """

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes (root first)")
        self.options.declare("load_case", types=LoadCase, desc="time grid, stress families, damping (and loads)")
        self.options.declare("material", types=Material, desc="wall material (E, G, rho, sigma_y)")
        self.options.declare("rho_ks", default=100.0, lower=0.0, types=numbers.Real, desc="KS aggregation parameter")
        self.options.declare("section", default="box", values=tuple(SECTION_KINDS),
                             desc="section kind: box (wall thicknesses) or solid (width, height)")
        self.options.declare("newton_options", default=None, allow_none=True, types=dict,
                             desc="extra BeamDynamics options (atol, max_iter, static_options, modified_newton, ...)")
        self.options.declare("loads_component", default=False, types=bool,
                             desc="hold the load case's forcing arrays in a 'loads' IndepVarComp "
                                  "(False: promoted inputs, set or connected from outside)")
        self.options.declare("add_constraints", default=False, types=bool,
                             desc="add every ks_<family> as a constraint ks <= 0")
        self.options.declare("panels", default=None, allow_none=True, types=PanelLayout,
                             desc="stiffened panels (section 'stiffened'): pitch, shape, safety factor, ribs")
        self.options.declare("equivalent_panels", default=None, allow_none=True, types=PanelLayout,
                             desc="section 'box' with walls of stiffened panels' equivalent thicknesses: the "
                                  "two-level sizing's outer constraint (EquivalentPanelFailure, ks_equivalent_panels)")
        self.options.declare("forcing_as_data", default=False, types=bool,
                             desc="the case's beam forcing arrays (FORCING_META) as data of the beam "
                                  "(TimeHistoryComponent forcing_data), not promoted inputs: fixed loads "
                                  "without OpenMDAO variables (100 MB less at 20 nodes x 4001 steps)")

    def setup(self):
        kind = self.options["section"]
        stress_cls = _section_classes(kind)[1]

        n = self.options["num_nodes"]
        case = self.options["load_case"]
        nt = case.num_times

        as_data = self.options["forcing_as_data"]
        if as_data and self.options["loads_component"]:
            raise ValueError("WingStructure: forcing_as_data and loads_component exclude each other")
        if self.options["loads_component"]:
            loads = self.add_subsystem("loads", om.IndepVarComp())
            for name, (units, desc) in FORCING_META.items():
                loads.add_output(name, val=case.forcing_array(name, n), units=units, desc=desc)

        if case.modal_dlm is not None:
            self._add_modal_dlm(n, case)
        else:
            self._add_beam(n, case, as_data)
        self._loads = "internal_loads"
        if case.symmetric is not None:  # the two wings: symmetric ± the increments (25.349(a) at 2/3 n_lim)
            self._add_symmetric(n, case)
            nt = 2 * nt

        if case.families:   # laminate walls may leave the strength to the panels' Tsai-Wu family
            # the box stress takes the section properties from the section component (computed once
            # per station, not at every time step)
            stress_kwargs = {"output_stresses": False, "section_properties": True} if kind in BOX_KINDS else {}
            self.add_subsystem("stress", stress_cls(num_times=nt, num_stations=n,
                                                    material=self.options["material"],
                                                    families=tuple(case.families), inputs_by_conn=True,
                                                    **stress_kwargs),
                               promotes_inputs=[*SECTION_KINDS[kind]["stress_inputs"],
                                                *SECTION_KINDS[kind]["section_to_stress"]])
            self.connect(f"{self._loads}.F_csn", "stress.F_csn")
            self.connect(f"{self._loads}.M_csn", "stress.M_csn")

        points = stress_points(kind, case.families)
        if kind == "stiffened":   # the panel modes' KS in the panels component (KSOfPointwise)
            self._add_panel_failure(nt, n)
        if self.options["equivalent_panels"] is not None:
            self._add_equivalent_panels(nt, n)
        if not points:
            return
        shapes = {fam: (nt, n, k) for fam, k in points.items()}
        # the per-step inputs of loads, stress and KS are shaped by their connections: no default
        # value of their own (18 MB at 20 nodes x 4001 steps, docs/gust-envelope.md)
        self.add_subsystem("ks", KSAggregate(families=shapes, rho_ks=self.options["rho_ks"], g_by_conn=True,
                                             add_constraints=self.options["add_constraints"]),
                           promotes_outputs=[f"ks_{f}" for f in points])
        for fam in case.families:
            self.connect(f"stress.g_{fam}", f"ks.g_{fam}")

    def _add_symmetric(self, n, case):
        """The case's symmetric static loads (``symmetric``: a WingStructure of ``case.symmetric``, its
        forcing as data, no stress) superposed on the beam's antisymmetric increments with both signs
        (``combined_loads``: symmetric + increment, the right wing, then symmetric - increment, the
        left); the stress, panels and KS then run over the 2 nt instants of ``combined_loads``."""
        sym = replace(case.symmetric, families=())
        self.add_subsystem("symmetric", WingStructure(num_nodes=n, load_case=sym, material=self.options["material"],
                                                      section="box", newton_options=self.options["newton_options"],
                                                      forcing_as_data=True),
                           promotes_inputs=["node_positions", "node_euler_angles", *SECTION_TO_BEAM, "tension_axis",
                                            "shear_center", "mass_center"])
        self.add_subsystem("combined_loads", SymmetricLoadCombination(num_times=case.num_times, num_nodes=n))
        for k in ("F_csn", "M_csn"):
            self.connect(f"symmetric.internal_loads.{k}", f"combined_loads.symmetric_{k}")
            self.connect(f"internal_loads.{k}", f"combined_loads.increment_{k}")
        self._loads = "combined_loads"

    def _add_modal_dlm(self, n, case):
        """The case's static first instant on the beam (``static``: a WingStructure of
        :meth:`LoadCase.static_case`, e.g. the trimmed 1 g state) plus the gust increment of the
        modal doublet-lattice wing of the design (``modal``: projection on the fixed basis, BDF2
        march, force-summation loads), summed in ``internal_loads`` (F_csn, M_csn). With control
        surfaces the law's closed-loop constraint (``closed_loop_ks``, sized gains) and the surfaces'
        limits (``actuator_ks``) are the modal system's (:mod:`wingmdao.components.modal_closed_loop`,
        the modal march's actuator states); the 1 g beam has neither."""
        spec = case.modal_dlm
        nt = case.num_times
        wing = spec.wing
        ctl = wing.controls
        aero = case.aero
        sized = aero is not None and aero.gain_design and aero.control_law is not None and ctl is not None
        limits = None if ctl is None or aero is None else getattr(aero, "surface_limits", None)
        static = case.static_case(n)
        if aero is not None:  # the law's stability and the surfaces' limits are the modal system's
            static = replace(static, aero=replace(aero, gain_design=False, surface_limits=None))
        self.recording_options["options_excludes"] = ["load_case"]   # CasADi functions of the projection
        self.add_subsystem("static", WingStructure(num_nodes=n, load_case=static,
                                                   material=self.options["material"], section=self.options["section"],
                                                   newton_options=self.options["newton_options"],
                                                   forcing_as_data=self.options["forcing_as_data"]),
                           promotes_inputs=["*"])
        gains = [] if ctl is None else [sp.name for sp in control_param_specs(ctl.spec)]
        modal = self.add_subsystem("modal", om.Group(), promotes_inputs=list(DESIGN_INPUTS) + gains)
        flight = modal.add_subsystem("flight", om.IndepVarComp())
        flight.add_output("airspeed", spec.airspeed, units="m/s", desc="true airspeed of the gust")
        flight.add_output("density", spec.density, units="kg/m**3", desc="air density of the gust")
        modal.add_subsystem("projection", ModalProjectionComp(projection=spec.projection),
                            promotes_inputs=list(DESIGN_INPUTS))
        m = wing.modes.count
        gust = np.asarray(spec.gust, dtype=float)
        data = {"gust_velocity": gust[:, 0], "gust_velocity_rate": gust[:, 1],
                "gust_velocity_acceleration": gust[:, 2], "modal_force": np.zeros((nt, m))}
        if ctl is not None:  # the flap modes and the law in the modal residual; no open-loop command
            data["surface_command"] = np.zeros((nt, ctl.n_surfaces))
        system = modal_rfa_system(wing.structure, wing.rfa, design=True, controls=ctl)
        march = TimeHistoryComponent(system=system,
                                     time=case.time, forcing_data=data,
                                     initial="state" if spec.plunge else "static")  # free: from rest
        march.recording_options["options_excludes"] = ["system", "forcing_data"]
        modal.add_subsystem("march", march, promotes_inputs=gains)
        dt = float(case.time[1] - case.time[0]) if nt > 1 else 0.0
        modal.add_subsystem("loads", ModalStationLoads(wing=wing, node_euler_angles=np.asarray(spec.node_euler_angles, dtype=float),
                                                       airspeed=float(spec.airspeed), density=float(spec.density),
                                                       gust=gust, time_step=dt))
        if ctl is not None:  # the law's measured root bending: the design's inertia row (root M_x)
            modal.connect("projection.modal_inertia", "march.root_inertia", src_indices=np.arange(3 * m, 4 * m),
                          flat_src_indices=True)
        for k in ("airspeed", "density"):
            modal.connect(f"flight.{k}", f"march.{k}")
        for k in ("modal_mass", "modal_stiffness"):
            modal.connect(f"projection.{k}", f"march.{k}")
            modal.connect(f"projection.{k}", f"loads.{k}")
        modal.connect("projection.modal_inertia", "loads.modal_inertia")
        modal.connect("march.states", "loads.states")
        if sized:  # the sized law keeps the modal system stable (docs/controls.md)
            modal.add_subsystem("closed_loop", ModalClosedLoopDamping(
                system=system, loaded=loaded_modes(wing.rfa), n_lags=wing.rfa.n_lags,
                margin=float(aero.closed_loop_margin)), promotes_inputs=gains,
                                promotes_outputs=["closed_loop_ks"])
            for k in ("airspeed", "density"):
                modal.connect(f"flight.{k}", f"closed_loop.{k}")
            for k in ("modal_mass", "modal_stiffness"):
                modal.connect(f"projection.{k}", f"closed_loop.{k}")
            modal.connect("projection.modal_inertia", "closed_loop.root_inertia", src_indices=np.arange(3 * m, 4 * m),
                          flat_src_indices=True)
            self.promotes("modal", outputs=["closed_loop_ks"])
        if limits is not None:  # the surfaces' deflection and rate over their limits on the modal march
            base = control_state_offset(m, wing.rfa.n_lags)   # the first actuator state
            lim = np.asarray(limits, dtype=float).reshape(ctl.n_surfaces, 2)
            self.add_subsystem("actuator_limits", ActuatorLimitKS(
                num_times=nt, state_shape=tuple(system.state_shape),
                deflection_index=base + 2 * np.arange(ctl.n_surfaces), rate_index=base + 1 + 2 * np.arange(ctl.n_surfaces),
                max_deflection=lim[:, 0], max_rate=lim[:, 1], rho_ks=self.options["rho_ks"]),
                promotes_outputs=["actuator_ks"])
            self.connect("modal.march.states", "actuator_limits.states")
        self.add_subsystem("internal_loads", ModalLoadSum(num_times=nt, num_nodes=n))
        for k in ("F_csn", "M_csn"):
            self.connect(f"static.internal_loads.{k}", f"internal_loads.static_{k}")
            self.connect(f"modal.loads.{k}", f"internal_loads.dynamic_{k}")

    def _add_beam(self, n, case, as_data):
        """The case's beam (static or BDF2 march; the aeroelastic beam of a coupled case) and its
        internal loads (``internal_loads``: F_csn, M_csn)."""
        nt = case.num_times
        beam_kwargs = dict(num_nodes=n, time=case.time, **(self.options["newton_options"] or {}))
        aero = case.aero
        if aero is not None:
            # coupled case: the aeroelastic beam (unsteady strip theory) in place of BeamDynamics;
            # its aerodynamic parameters and forcing are promoted inputs of the case

            if case.damping is not None and not case.damping.is_zero:
                raise ValueError(f"load case {case.name}: structural damping is not available with aero")
            beam = AeroelasticBeamDynamics(num_nodes=n, time=case.time, plunge=bool(aero.plunge),
                                           trim=bool(aero.trim), aero_theory=aero.residual_theory)
            if aero.pitch or aero.roll or aero.controls is not None:  # free pitch or roll, control surfaces
                beam.options["system"] = cached_aeroelastic_system(n, plunge=bool(aero.plunge), trim=bool(aero.trim),
                                                                   pitch=bool(aero.pitch),
                                                                   tail_lag=bool(aero.pitch and aero.tail_lag),
                                                                   aero_theory=aero.residual_theory,
                                                                   controls=aero.controls, roll=bool(aero.roll))
            for k, v in (self.options["newton_options"] or {}).items():
                if k in beam.options:
                    beam.options[k] = v
            extra = [s.name for s in aero_param_specs(n)] + list(AERO_FORCING_SHAPES)
            extra = [e for e in extra if e not in AERO_FORCING_SHAPES or case_has_forcing(aero, e)]
            extra += ["tail_area", "tail_lift_slope", "downwash_gradient"] if aero.pitch else []
            extra += ["body_roll_inertia"] if aero.roll else []
            extra += ["trim_lift"] if aero.trim and not aero.plunge else []
            extra += [s.name for s in vlm_param_specs(n)] if aero.residual_theory == "vlm" else []
            if aero.residual_theory == "vlm" and aero.controls is not None:  # the flaps as lattice panels
                extra += [s.name for s in flap_param_specs(n, aero.controls)]
            if aero.controls is not None:  # the law's matrices (the gains) and the open-loop command
                extra += [s.name for s in control_param_specs(aero.controls)] + ["surface_command"]
            if aero.pitch:  # body mass, first moment, pitch inertia, tail position from the aircraft inputs
                self.add_subsystem("pitch_body", PitchBodyProperties(num_nodes=n, trim_load_factor=aero.trim_load_factor()),
                                   promotes_inputs=["aircraft_mass", "aircraft_cg", "aircraft_pitch_inertia", "tail_arm",
                                                    "mass_per_length", "node_positions"])
                for k in ("body_mass", "body_first_moment", "body_pitch_inertia", "tail_x", "trim_lift"):
                    self.connect(f"pitch_body.{k}", f"beam.{k}")
            elif aero.plunge:  # the plunge mass (and trim lift) from the promoted input aircraft_mass
                n_trim = aero.trim_load_factor() if aero.trim else None
                self.add_subsystem("plunge_mass", PlungeBodyMass(num_nodes=n, trim_load_factor=n_trim),
                                   promotes_inputs=["aircraft_mass", "mass_per_length", "node_positions"])
                self.connect("plunge_mass.body_mass", "beam.body_mass")
                if aero.trim:
                    self.connect("plunge_mass.trim_lift", "beam.trim_lift")
        else:
            if case.damping is not None and not case.damping.is_zero:
                beam_kwargs["system"] = cached_beam_system(n, beam_kwargs.get("euler_sequence", "surface"),
                                                           case.damping)
            beam = BeamDynamics(**beam_kwargs)
            extra = []
        beam.recording_options["options_excludes"] = ["system", "forcing_data"]  # CasADi object; large arrays
        if as_data:
            beam.options["forcing_data"] = {name: case.forcing_array(name, n) for name in FORCING_META}
        forcing = [] if self.options["loads_component"] or as_data else list(FORCING_SHAPES)
        self.add_subsystem("beam", beam, promotes_inputs=[
            "node_positions", "node_euler_angles", *SECTION_TO_BEAM,
            "tension_axis", "shear_center", "mass_center", *forcing, *extra], promotes_outputs=["states"])
        if self.options["loads_component"]:
            for name in FORCING_SHAPES:
                self.connect(f"loads.{name}", f"beam.{name}")

        if aero is not None and aero.controls is not None and aero.control_law is not None and aero.gain_design:
            # sized gains: the closed-loop stability constraint about the trimmed state (docs/controls.md)
            system = beam.options["system"]
            if aero.pitch:  # the body's parameters come from the aircraft's, as the beam's
                connected = {k: f"pitch_body.{k}" for k in ("body_mass", "body_first_moment", "body_pitch_inertia",
                                                            "tail_x", "trim_lift")}
            elif aero.plunge:
                connected = {"body_mass": "plunge_mass.body_mass"} | (
                    {"trim_lift": "plunge_mass.trim_lift"} if aero.trim else {})
            else:  # clamped: trim_lift is the case's promoted input, shared with the beam
                connected = {}
            names = [sp.name for sp in system.param_specs]
            self.add_subsystem("closed_loop", ClosedLoopDamping(system=system, margin=float(aero.closed_loop_margin)),
                               promotes_inputs=[nm for nm in names if nm not in connected],
                               promotes_outputs=["closed_loop_ks"])
            for nm, src in connected.items():
                if nm in names:
                    self.connect(src, f"closed_loop.{nm}")
            self.connect("states", "closed_loop.trimmed_state", src_indices=np.arange(system.n_state),
                         flat_src_indices=True)
        if aero is not None and aero.controls is not None and getattr(aero, "surface_limits", None) is not None:
            # the surfaces' deflection and rate over their limits, one KS over the march (docs/controls.md)
            system = beam.options["system"]
            names = [srf[0] for srf in aero.controls.surfaces]
            lim = np.asarray(aero.surface_limits, dtype=float).reshape(len(names), 2)
            self.add_subsystem("actuator_limits", ActuatorLimitKS(
                num_times=nt, state_shape=tuple(system.state_shape),
                deflection_index=np.array([system.control_index[f"{nm}_deflection"] for nm in names]),
                rate_index=np.array([system.control_index[f"{nm}_rate"] for nm in names]),
                max_deflection=lim[:, 0], max_rate=lim[:, 1], rho_ks=self.options["rho_ks"]),
                promotes_inputs=["states"], promotes_outputs=["actuator_ks"])
        if aero is not None:
            shape = tuple(beam.build_system().state_shape)
            self.add_subsystem("beam_states", BeamStateSlice(num_times=nt, num_nodes=n, state_shape=shape),
                               promotes_inputs=["states"])
            self.add_subsystem("internal_loads", BeamInternalLoads(num_times=nt, num_nodes=n, inputs_by_conn=True))
            self.connect("beam_states.beam_states", "internal_loads.states")
        else:
            self.add_subsystem("internal_loads", BeamInternalLoads(num_times=nt, num_nodes=n, inputs_by_conn=True),
                               promotes_inputs=["states"])


    def _add_equivalent_panels(self, nt, n):
        """The equivalent-thickness panel constraint of the two-level sizing (EquivalentPanelFailure,
        promoted ``ks_equivalent_panels``) on the box's walls."""
        layout = self.options["equivalent_panels"]
        if self.options["section"] != "box":
            raise ValueError("WingStructure: equivalent_panels goes with section 'box' (the walls' equivalent "
                             f"thicknesses), got section {self.options['section']!r}")
        comp = self.add_subsystem("equivalent_panels", EquivalentPanelFailure(
            num_times=nt, num_stations=n, material=self.options["material"], safety_factor=layout.safety_factor,
            stiffener_pitch=layout.stiffener_pitch, inputs_by_conn=True, ks_rho=self.options["rho_ks"],
            ks_constraints=self.options["add_constraints"]),
            promotes_inputs=["width", "height", *WALLS, "panel_length", *SECTION_PROPERTIES])
        self.promotes("equivalent_panels", outputs=[f"ks_{f}" for f in comp.families])
        self.connect(f"{self._loads}.F_csn", "equivalent_panels.F_csn")
        self.connect(f"{self._loads}.M_csn", "equivalent_panels.M_csn")

    def _add_panel_failure(self, nt, n) -> dict:
        """The panel failure ratios of the stiffened box (PanelFailure) with the KS aggregate of
        each family (promoted ``ks_<family>``); returns their families' points per station."""
        layout = self.options["panels"]
        if layout is None:
            raise ValueError("WingStructure: section 'stiffened' needs the panels option (a PanelLayout)")
        # the chordwise running load comes from dF/ds: its component runs before the panels'
        # (added after them, a run-once group would hand the panels the previous evaluation's
        # value, zero on the first, and the reverse sweep would drop that path's derivatives)
        self.add_subsystem("load_gradient", InternalForceGradient(num_times=nt, num_nodes=n),
                           promotes_inputs=["node_positions"])
        comp = self.add_subsystem("panels", PanelFailure(
            num_times=nt, num_stations=n, material=self.options["material"], safety_factor=layout.safety_factor,
            stiffener_pitch=layout.stiffener_pitch, shape=layout.shape, flange_ratio=layout.flange_ratio,
            wall_factors=layout.wall_factors(self.options["material"]), skin_material=layout.skin_material,
            spar_material=layout.spar_material, inputs_by_conn=True, ks_rho=self.options["rho_ks"],
            ks_constraints=self.options["add_constraints"]),
            promotes_inputs=["width", "height", *WALLS, *STIFFENER_VARS, "panel_length", *SECTION_PROPERTIES])
        self.promotes("panels", outputs=[f"ks_{f}" for f in comp.families])
        self.connect(f"{self._loads}.F_csn", "panels.F_csn")
        self.connect(f"{self._loads}.M_csn", "panels.M_csn")
        self.connect(f"{self._loads}.F_csn", "load_gradient.F_csn")
        self.connect("load_gradient.dF_csn_ds", "panels.dF_csn_ds")
        return dict(comp.families)


class WingSizing(om.Group):
    """Shared thickness design variables, box sections and mass; one WingStructure per load case.

    Inputs to set (promoted): ``t_upper_skin``, ``t_lower_skin``, ``t_front_spar``,
    ``t_rear_spar``, ``width``, ``height`` (per node, m), ``node_positions`` (n, 3) m,
    ``node_euler_angles`` (n, 3) rad, ``section_to_csn`` (n, 3, 3),
    ``nonstructural_mass_per_length`` (n,) kg/m; per load case the forcing inputs
    ``cases.<case>.force_per_length`` ... (see :class:`WingStructure`; set them with
    :func:`set_case_loads` or connect them). Outputs: ``mass`` (kg) and
    ``cases.<case>.ks_<family>``; with the ``flutter`` option also ``flutter_ks`` (1/s, the
    flutter-damping constraint of :class:`~wingmdao.components.flutter.FlutterDamping` on the
    section chain's beam parameters). ``add_constraints`` / ``add_objective`` declare the KS
    constraints (<= 0, flutter_ks included) and the mass objective themselves.
    """

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes (root first)")
        self.options.declare("load_cases", types=list, desc="list of wingmdao.groups.load_case.LoadCase")
        self.options.declare("material", types=Material, desc="wall material (E, G, rho, sigma_y)")
        self.options.declare("rho_ks", default=100.0, lower=0.0, types=numbers.Real, desc="KS aggregation parameter")
        self.options.declare("parallel", default=None, allow_none=True, types=bool,
                             desc="load cases in an om.ParallelGroup (None: when mpi4py imports)")
        self.options.declare("section", default="box", values=tuple(SECTION_KINDS),
                             desc="section kind: box (wall thicknesses) or solid (width, height)")
        self.options.declare("station_map", default=None, allow_none=True, types=(np.ndarray, list, tuple),
                             desc="(n,) int: design-variable index of each station (None: one per station)")
        self.options.declare("newton_options", default=None, allow_none=True, types=dict,
                             desc="extra BeamDynamics options of every case")
        self.options.declare("add_constraints", default=False, types=bool,
                             desc="add every case's ks_<family> as a constraint ks <= 0")
        self.options.declare("add_objective", default=False, types=bool,
                             desc="add the structural mass as the objective")
        self.options.declare("mass_ref", default=1.0, lower=0.0, types=numbers.Real, desc="objective scaling reference (kg)")
        self.options.declare("turbulence", default=None, allow_none=True, types=dict,
                             desc="options of components.turbulence.TurbulenceStressKS: adds the 25.341(b) "
                                  "continuous-turbulence stress constraint turbulence_ks <= 0 (None: none)")
        self.options.declare("flutter", default=None, allow_none=True, types=dict,
                             desc="options of components.flutter.FlutterDamping (aero, speeds, ...): adds the "
                                  "flutter-damping constraint flutter_ks <= 0 (None: no flutter constraint)")
        self.options.declare("forcing_as_data", default=False, types=bool,
                             desc="every case's beam forcing as data of its beam (WingStructure "
                                  "forcing_as_data; set_case_loads then sets only the aerodynamic forcing)")
        self.options.declare("panels", default=None, allow_none=True, types=PanelLayout,
                             desc="stiffened panels and ribs (section 'stiffened'; wingmdao.panels.layout)")
        self.options.declare("equivalent_panels", default=None, allow_none=True, types=PanelLayout,
                             desc="section 'box' whose walls are stiffened panels' equivalent thicknesses: every "
                                  "case gets the two-level sizing's outer constraint (WingStructure)")
        self.options.declare("rib_weights", default=None, allow_none=True, types=(list, tuple, np.ndarray),
                             desc="(n,) ribs attributed to each station (section 'stiffened': the ribs' mass; "
                                  "wingmdao.panels.layout.rib_weights)")
        self.options.declare("proxy_cases", default=False, types=bool,
                             desc="a subclass adds the cases to cases_group itself (wingmdao.parallel); "
                                  "load_cases may then be empty")

    def setup(self):
        n = self.options["num_nodes"]
        kind = self.options["section"]
        section_cls = _section_classes(kind)[0]
        mat = self.options["material"]
        if not self.options["load_cases"] and not self.options["proxy_cases"]:
            raise ValueError("WingSizing: load_cases is empty; give at least one LoadCase")
        bad = [c for c in self.options["load_cases"] if not isinstance(c, LoadCase)]
        if bad:
            raise ValueError(f"WingSizing: load_cases must be LoadCase objects, got {type(bad[0]).__name__}")
        if any(c.modal_dlm is not None for c in self.options["load_cases"]):   # CasADi functions: not picklable
            self.recording_options["options_excludes"] = ["load_cases"]
        names = [c.name for c in self.options["load_cases"]]
        if len(set(names)) != len(names):
            raise ValueError(f"load case names must be unique, got {names}")

        design = SECTION_KINDS[kind]["design_vars"]
        if (self.options["turbulence"] or {}).get("gains_from_case") is not None:
            self._add_law_gains(self.options["turbulence"])
        alias = []
        if self.options["station_map"] is not None:
            self.add_subsystem("design_map", StationMap(station_map=self.options["station_map"], names=design),
                               promotes=["*"])
            alias = [(d, f"{d}_station") for d in design]
        layout = self.options["panels"]
        if (kind == "stiffened") != (layout is not None):
            raise ValueError("WingSizing: the panels option (a PanelLayout) goes with section 'stiffened' "
                             f"and only with it; section = {kind!r}, panels = {layout!r}")
        section_kwargs = {} if layout is None else dict(
            stiffener_pitch=layout.stiffener_pitch, shape=layout.shape, flange_ratio=layout.flange_ratio,
            wall_factors=layout.wall_factors(mat))
        self.add_subsystem("section", section_cls(num_stations=n, material=mat, **section_kwargs),
                           promotes_inputs=alias + ["*"], promotes_outputs=["*"])
        add_section_offsets(self, n, promotes_outputs=["*"])
        self.add_subsystem("mass_calc", StructuralMass(num_nodes=n, density=mat.rho),
                           promotes_inputs=[("A", "mass_area") if layout is not None else "A", "node_positions"],
                           promotes_outputs=[("mass", "box_mass") if layout is not None else "mass"])
        if layout is not None:
            self._add_panel_parts(n, layout, design, bool(alias))

        # inputs shared by several components get one default (units and shape)
        self.set_input_defaults("node_positions", val=np.zeros((n, 3)), units="m")
        if not self.options["proxy_cases"]:  # only the beams of the cases take the jig angles
            self.set_input_defaults("node_euler_angles", val=np.zeros((n, 3)), units="rad")
        n_dv = n if self.options["station_map"] is None else int(np.max(self.options["station_map"])) + 1
        per_station = SECTION_KINDS[kind]["stress_inputs"] + (STIFFENER_VARS if layout is not None else ())
        for name in per_station:
            shape = (n_dv,) if (name in design and alias) else (n,)
            self.set_input_defaults(name, val=np.ones(shape) * (0.01 if name in STIFFENER_VARS else 1.0), units="m")

        parallel = self.options["parallel"]
        if parallel is None:
            parallel = importlib.util.find_spec("mpi4py") is not None
        alias_map = dict(alias)
        case_inputs = [(v, alias_map[v]) if v in alias_map else v for v in per_station]
        equivalent = self.options["equivalent_panels"]
        case_inputs += ["panel_length"] if (layout is not None or equivalent is not None) else []
        if equivalent is not None:
            self.set_input_defaults("panel_length", val=np.full(n, 0.5), units="m")
        case_inputs += ["node_positions", "node_euler_angles", *SECTION_TO_BEAM,
                        "tension_axis", "shear_center", "mass_center", *SECTION_KINDS[kind]["section_to_stress"]]
        # only the shared inputs leave 'cases'; each case's forcing stays cases.<case>.<forcing>
        shared = sorted({v[1] if isinstance(v, tuple) else v for v in case_inputs})
        #: the group of the load cases (``cases``), for subclasses that add cases themselves
        self.cases_group = cases = self.add_subsystem("cases", om.ParallelGroup() if parallel else om.Group(),
                                                      promotes_inputs=["*"] if self.options["proxy_cases"] else shared)
        # one case in one process: its solve without a copy of its whole derivative vector
        cases.linear_solver = SingleSubsystemRunOnce()
        for case in self.options["load_cases"]:
            cases.add_subsystem(case.name, WingStructure(
                num_nodes=n, load_case=case, material=mat, rho_ks=self.options["rho_ks"],
                section=kind, newton_options=self.options["newton_options"], panels=layout, equivalent_panels=equivalent,
                add_constraints=self.options["add_constraints"], forcing_as_data=self.options["forcing_as_data"]),
                promotes_inputs=case_inputs)
        if self.options["flutter"] is not None:
            self._add_flutter(n)
        if self.options["turbulence"] is not None:
            self._add_turbulence(n, alias_map)
        if self.options["add_objective"]:
            self.add_objective("mass", ref=self.options["mass_ref"])

    def _add_panel_parts(self, n, layout, design, mapped):
        """Ribs' mass, total mass (box + ribs) and the linear sizing rules of the stiffened box."""
        ribs = self.options["rib_weights"] if self.options["rib_weights"] is not None else np.zeros(n)
        self.add_subsystem("rib_mass_calc", RibMass(num_nodes=n, rib_weights=np.asarray(ribs, dtype=float),
                                                    rib_thickness=layout.rib_thickness,
                                                    density=layout.rib_material(self.options["material"])[2]),
                           promotes_inputs=["width", "height"], promotes_outputs=["rib_mass"])
        total = om.AddSubtractComp()
        total.add_equation("mass", ["box_mass", "rib_mass"], units="kg",
                           desc="structural mass: box walls, stiffeners and ribs")
        self.add_subsystem("mass_total", total, promotes=["*"])
        n_dv = n if self.options["station_map"] is None else int(np.max(self.options["station_map"])) + 1
        self.add_subsystem("rules", SizingRules(num_stations=n_dv, adjacency=tuple(design)),
                           promotes_inputs=list(design))
        self.set_input_defaults("panel_length", val=np.full(n, 0.5), units="m")

    #: scaling reference of the flutter constraint (1/s: a decay rate)
    FLUTTER_REF = 0.1

    def _add_turbulence(self, n, alias_map):
        """The 25.341(b) corner design-stress constraint on the section chain's beam parameters and the
        walls of every station (docs/turbulence.md)."""
        walls = [(w, alias_map[w]) if w in alias_map else w for w in WALLS]
        opts = dict(self.options["turbulence"])
        case = opts.pop("gains_from_case", None)
        self.add_subsystem("turbulence", TurbulenceStressKS(num_nodes=n, **opts),
                           promotes_inputs=["node_positions", "node_euler_angles", *SECTION_TO_BEAM,
                                            *SECTION_OFFSETS, *walls],
                           promotes_outputs=["turbulence_ks"] + (["turbulence_actuator_ks"]
                                                                 if opts.get("surface_limits") is not None else []))
        if case is not None:  # one law: the sized gains (law_gains, before the cases) feed the constraint too
            for spec in control_param_specs(opts["controls"]):
                if spec.name in SIZED_GAINS:
                    self.connect(f"law_gains.{spec.name}", [f"cases.{case}.{spec.name}", f"turbulence.{spec.name}"])
        if self.options["add_constraints"]:
            self.add_constraint("turbulence_ks", upper=0.0)
            if case is not None and opts.get("surface_limits") is not None:  # the sized law within its limits
                self.add_constraint("turbulence_actuator_ks", upper=1.0, ref=1.0)

    def _add_law_gains(self, turbulence):
        """``law_gains``: the sized gains of the law the gust case and the turbulence constraint share
        (before both: the reverse sweep of the group's linear solver meets it after them)."""
        law = turbulence["control_law"]
        gains = self.add_subsystem("law_gains", om.IndepVarComp())
        for spec in control_param_specs(turbulence["controls"]):
            if spec.name in SIZED_GAINS:
                gains.add_output(spec.name, val=getattr(law, spec.name[-1]), desc=spec.desc)

    def _add_flutter(self, n):
        """The flutter-damping constraint on the section chain's beam parameters (docs/flutter.md)."""
        self.add_subsystem("flutter", FlutterDamping(num_nodes=n, **self.options["flutter"]),
                           promotes_inputs=["node_positions", "node_euler_angles", *SECTION_TO_BEAM,
                                            *SECTION_OFFSETS],
                           promotes_outputs=["flutter_ks"])
        if self.options["add_constraints"]:
            self.add_constraint("flutter_ks", upper=0.0, ref=self.FLUTTER_REF)
