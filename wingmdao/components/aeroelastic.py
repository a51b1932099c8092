"""``AeroelasticBeamDynamics``: BDF2 time history of the beam with unsteady strip-theory loads.

A :class:`~wingmdao.components.time_history.TimeHistoryComponent` over
:func:`wingmdao.aero.system.build_aeroelastic_system` (docs/aeroelasticity.md). Inputs are the
beam parameter blocks (as ``BeamDynamics``), the aerodynamic parameters ``chord``, ``ref_point``,
``lift_slope``, ``alpha_zero_lift``, ``cm0``, ``airspeed``, ``density``, ``mach``, the beam forcing
blocks and ``gust_velocity`` (n_time, n_node), ``frame_velocity`` (n_time, 3). Output ``states``
(n_time, n_node, 22): 18 beam states then 4 aerodynamic lag states per node, the free-plunge and
trim states after them (flat; read them through ``build_system().layout``,
:func:`wingmdao.aero.system.state_layout`). Derivatives with
respect to every input (chord, airspeed, density included) come from the generic discrete adjoint
(or the forward tangent sweep), the same code as the structural beam. With ``aero_theory="vlm"``
the inputs ``lift_influence`` (n, n) m and ``moment_influence`` (n, n) m^2 carry the vortex
lattice of the jig planform (:func:`wingmdao.aero.vlm.station_influence`; set them from
:meth:`wingmdao.aero.coupled.CoupledAero.parameters`); they are inputs with exact partials like
the others, but nothing chains them to chord or node_positions (the planform is fixed data of a
sizing).

Aerodynamic inputs are checked before any solve (ValueError naming the input, value and range).
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om

from wingmdao.aero.pitch import body_pitch_properties, check_pitch_inputs
from wingmdao.aero.plunge import body_mass, half_wing_mass, trapezoid_node_weights
from wingmdao.aero.system import AERO_THEORIES, AeroelasticBeamSystem, cached_aeroelastic_system, check_aero_parameters
from wingmdao.loads.atmosphere import G0
from wingmdao.components.time_history import TimeHistoryComponent
from wingmdao.errors import InputRangeError


class AeroelasticBeamDynamics(TimeHistoryComponent):
    """Aeroelastic beam time history (options as ``BeamDynamics``: ``num_nodes``, ``time``, ...)."""

    def initialize(self):
        super().initialize()
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes (root first)")
        self.options.declare("euler_sequence", default="surface", types=str,
                             desc="Euler-angle sequence of wingmdao.beam.residual")
        self.options.declare("system", default=None, allow_none=True, types=AeroelasticBeamSystem,
                             desc="a prebuilt aeroelastic system (None: built from num_nodes)")
        self.options.declare("plunge", default=False, types=bool,
                             desc="free plunge of the aircraft (input body_mass); clamped root otherwise")
        self.options.declare("trim", default=False, types=bool,
                             desc="trim state alpha_trim (input trim_lift, forcing trim_active)")
        self.options.declare("aero_theory", default="strip", values=AERO_THEORIES,
                             desc="circulatory quasi-steady lift: strip (per station) or vlm (vortex-lattice "
                                  "influence matrices, inputs lift_influence and moment_influence)")
        self.options.declare("modified_newton", default=True, types=bool,
                             desc="reuse LU factors across Newton iterations and steps")

    def build_system(self):
        """The ``system`` option when given, else the aeroelastic beam of ``num_nodes`` nodes (cached)."""
        system = self.options["system"] or cached_aeroelastic_system(
            self.options["num_nodes"], self.options["euler_sequence"], plunge=self.options["plunge"],
            trim=self.options["trim"], aero_theory=self.options["aero_theory"])
        if system.num_nodes != self.options["num_nodes"]:
            raise ValueError(f"system has {system.num_nodes} nodes but num_nodes = {self.options['num_nodes']}")
        return system

    def solve_nonlinear(self, inputs, outputs):
        # checked before the march (not in apply_nonlinear/linearize: finite-difference checks
        # may step mach = 0 to a tiny negative value, where the equations are still defined)
        check_aero_parameters({k: np.asarray(inputs[k]) for k in
                               ("chord", "ref_point", "airspeed", "density", "mach", "lift_slope")})
        super().solve_nonlinear(inputs, outputs)

    def initial_guess(self, p, q0):
        """Starting point of the static solve of step 0: the aeroelastic system's own initial guess.

        Parameters
        ----------
        p : numpy.ndarray
            Packed parameters.
        q0 : numpy.ndarray
            Packed forcing at t = 0.

        Returns
        -------
        numpy.ndarray
            The system's initial guess.
        """
        return self.system.initial_guess(p, q0)


class PlungeBodyMass(om.ExplicitComponent):
    """Mass of the free-plunge state: ``body_mass = aircraft_mass - 2 m_half`` (wingmdao.aero.plunge).

    Inputs ``aircraft_mass`` (kg, the whole aircraft; connect an aircraft model to it),
    ``mass_per_length`` (n,) kg/m and ``node_positions`` (n, 3) m of the beam. Output
    ``body_mass`` (kg); with the option ``trim_load_factor`` n also ``trim_lift = n g0
    aircraft_mass`` (N, the lift of both half-wings the trim solves for). Analytic partials.
    A body mass <= 0 raises InputRangeError.
    """

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes")
        self.options.declare("trim_load_factor", default=None, allow_none=True, types=(int, float),
                             desc="load factor n of the output trim_lift = n g0 aircraft_mass (None: no output)")

    def setup(self):
        n = self.options["num_nodes"]
        self.add_input("aircraft_mass", val=1.0, units="kg", desc="aircraft mass (both wing halves included)")
        self.add_input("mass_per_length", val=0.0, shape=(n,), units="kg/m", desc="beam mass per unit length")
        self.add_input("node_positions", val=0.0, shape=(n, 3), units="m", desc="undeformed beam nodes, body axes")
        self.add_output("body_mass", val=1.0, units="kg", desc="aircraft mass outside both wing halves")
        self.declare_partials("body_mass", "aircraft_mass", val=1.0)
        self.declare_partials("body_mass", "mass_per_length", rows=np.zeros(n, int), cols=np.arange(n))
        self.declare_partials("body_mass", "node_positions", rows=np.zeros(3 * n, int), cols=np.arange(3 * n))
        if self.options["trim_load_factor"] is not None:
            self.add_output("trim_lift", val=1.0, units="N", desc="lift of both half-wings to trim to, n g0 aircraft_mass")
            self.declare_partials("trim_lift", "aircraft_mass", val=float(self.options["trim_load_factor"]) * G0)

    def compute(self, inputs, outputs):
        m_half, _, _ = half_wing_mass(inputs["mass_per_length"], inputs["node_positions"])
        try:
            outputs["body_mass"] = body_mass(inputs["aircraft_mass"][0], m_half)
        except ValueError as exc:
            raise InputRangeError(str(exc)) from None
        if self.options["trim_load_factor"] is not None:
            outputs["trim_lift"] = float(self.options["trim_load_factor"]) * G0 * inputs["aircraft_mass"]

    def compute_partials(self, inputs, partials):
        _, dmu, dr = half_wing_mass(inputs["mass_per_length"], inputs["node_positions"])
        partials["body_mass", "mass_per_length"] = -2.0 * dmu
        partials["body_mass", "node_positions"] = -2.0 * dr.ravel()


class PitchBodyProperties(om.ExplicitComponent):
    """Body mass, first moment and pitch inertia of the free-pitch rows from the whole aircraft
    (:func:`body_pitch_properties`), and the tail position ``tail_x = x_cg + tail_arm``.

    Inputs ``aircraft_mass`` (kg), ``aircraft_cg`` (2,) m (x aft, z up from the body-axes origin),
    ``aircraft_pitch_inertia`` (kg m^2, about the CG), ``tail_arm`` (m, CG to the tail's
    aerodynamic centre), ``mass_per_length`` (n,) kg/m, ``node_positions`` (n, 3) m. Outputs
    ``body_mass``, ``body_first_moment``, ``body_pitch_inertia``, ``tail_x``; with the option
    ``trim_load_factor`` n also ``trim_lift = n g0 aircraft_mass`` (N). Partials: analytic in the
    aircraft inputs and mass_per_length, complex step (exact) in node_positions. Bad values raise
    InputRangeError (a ValueError) naming the input.
    """

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes")
        self.options.declare("trim_load_factor", default=None, allow_none=True, types=(int, float),
                             desc="load factor n of the output trim_lift = n g0 aircraft_mass (None: no output)")

    def setup(self):
        n = self.options["num_nodes"]
        self.add_input("aircraft_mass", val=1.0, units="kg", desc="aircraft mass (both wing halves included)")
        self.add_input("aircraft_cg", val=np.zeros(2), units="m", desc="aircraft CG (x aft, z up) from the body-axes origin")
        self.add_input("aircraft_pitch_inertia", val=1.0, units="kg*m**2", desc="aircraft pitch inertia about its CG")
        self.add_input("tail_arm", val=1.0, units="m", desc="CG to horizontal-tail aerodynamic centre, along x (aft +)")
        self.add_input("mass_per_length", val=0.0, shape=(n,), units="kg/m", desc="beam mass per unit length")
        self.add_input("node_positions", val=0.0, shape=(n, 3), units="m", desc="undeformed beam nodes, body axes")
        self.add_output("body_mass", val=1.0, units="kg", desc="aircraft mass outside both wing halves")
        self.add_output("body_first_moment", val=np.zeros(2), units="kg*m", desc="m_b (x_b, z_b) about the origin")
        self.add_output("body_pitch_inertia", val=1.0, units="kg*m**2", desc="body pitch inertia about the origin")
        self.add_output("tail_x", val=1.0, units="m", desc="x of the tail aerodynamic centre from the origin")
        self.declare_partials(["body_mass", "body_first_moment", "body_pitch_inertia"],
                              ["aircraft_mass", "mass_per_length", "node_positions"])
        self.declare_partials(["body_first_moment", "body_pitch_inertia"], "aircraft_cg")
        self.declare_partials("body_pitch_inertia", "aircraft_pitch_inertia", val=1.0)
        self.declare_partials("tail_x", "tail_arm", val=1.0)
        self.declare_partials("tail_x", "aircraft_cg", rows=[0], cols=[0], val=1.0)
        if self.options["trim_load_factor"] is not None:
            self.add_output("trim_lift", val=1.0, units="N", desc="lift of wing + tail to trim to, n g0 aircraft_mass")
            self.declare_partials("trim_lift", "aircraft_mass", val=float(self.options["trim_load_factor"]) * G0)

    def _values(self, inputs, r=None):
        return body_pitch_properties(inputs["aircraft_mass"][0], inputs["aircraft_cg"], inputs["aircraft_pitch_inertia"][0],
                                     inputs["mass_per_length"], inputs["node_positions"] if r is None else r)

    def compute(self, inputs, outputs):
        try:
            check_pitch_inputs(tail_arm=inputs["tail_arm"][0])
            outputs["body_mass"], outputs["body_first_moment"], outputs["body_pitch_inertia"] = self._values(inputs)
        except ValueError as exc:
            raise InputRangeError(str(exc)) from None
        outputs["tail_x"] = inputs["aircraft_cg"][0] + inputs["tail_arm"]
        if self.options["trim_load_factor"] is not None:
            outputs["trim_lift"] = float(self.options["trim_load_factor"]) * G0 * inputs["aircraft_mass"]

    def compute_partials(self, inputs, partials):
        M, cg = inputs["aircraft_mass"][0], inputs["aircraft_cg"]
        r = inputs["node_positions"]
        w = trapezoid_node_weights(r)
        x, z = r[:, 0], r[:, 2]
        partials["body_mass", "aircraft_mass"] = 1.0
        partials["body_first_moment", "aircraft_mass"] = cg
        partials["body_pitch_inertia", "aircraft_mass"] = np.sum(cg * cg)
        partials["body_first_moment", "aircraft_cg"] = M * np.eye(2)
        partials["body_pitch_inertia", "aircraft_cg"] = 2.0 * M * cg
        partials["body_mass", "mass_per_length"] = -2.0 * w
        partials["body_first_moment", "mass_per_length"] = -2.0 * np.vstack([w * x, w * z])
        partials["body_pitch_inertia", "mass_per_length"] = -2.0 * w * (x * x + z * z)
        h = 1e-30
        d = np.zeros((4, r.size))
        for k in range(r.size):
            rc = r.astype(complex).ravel()
            rc[k] += 1j * h
            mb, sb, io = self._values(inputs, rc.reshape(r.shape))
            d[:, k] = np.imag(np.concatenate([[mb], sb, [io]])) / h
        partials["body_mass", "node_positions"] = d[0]
        partials["body_first_moment", "node_positions"] = d[1:3]
        partials["body_pitch_inertia", "node_positions"] = d[3]
