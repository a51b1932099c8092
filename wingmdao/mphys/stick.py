"""MPhys builder of the stick model of a free aircraft (``StickBuilder``; needs ``mphys``).

The structural solver is the whole aircraft's joined beams (:mod:`wingmdao.beam.joints`: wing,
fuselage, fin, tail, lumped masses, symmetry conditions of a half aircraft) in static equilibrium
with **inertia relief** (:class:`~wingmdao.components.inertia_relief.InertiaRelief`): the free
aircraft's body axes accelerate (surge, plunge, pitch of the half aircraft: outputs ``frame_ax``
m/s^2, ``frame_az`` m/s^2, ``frame_alpha_y`` rad/s^2) so that the loads, the weight (``gravity``)
and the inertial loads balance, its rigid-body position held by statically determinate supports
that carry nothing. The MPhys interface is the wing's, as :class:`~wingmdao.mphys.builder.WingmdaoBuilder`:
the structural nodes are the wing's beam nodes (``x_struct0``, n*3, body axes), the loads
``f_aero_struct`` (n*6: force N and moment N*m per wing node, body axes) are the wing's point
loads, ``u_struct`` (n*6) the wing nodes' displacement relative to the supports and small rotation
vector, ``dv_struct`` (4*n, m) the wing's wall thicknesses; pre-coupling ``struct_mass`` (kg, the
wing's walls), post-coupling ``ks_<family>`` of the wing's box stresses. The rest of the aircraft
(fuselage, fin, tail sections, lumped masses) is fixed at the model's values, an input of the
coupling group under the joined system's names (``fuselage_stiffness_csn``, ``lumped_mass``, ...).

:func:`pegasus_stick_builder` builds it for the PEGASUS half aircraft of
:mod:`wingmdao.cases.pegasus_stick`. docs/embedding.md, "Stick model".
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om

from wingmdao.beam.joints import HALF_AIRCRAFT_ACCELERATIONS
from wingmdao.cases import pegasus, pegasus_stick
from wingmdao.cases.planform import wing_geometry
from wingmdao.materials import ALUMINIUM
from wingmdao.section.box import WALL_NAMES
from wingmdao.components.inertia_relief import InertiaRelief, acceleration_output
from wingmdao.components.state_slice import BeamStateSlice
from wingmdao.mphys.builder import (SECTION_TO_BEAM, STATES, BeamDisplacements, PostCoupling, PreCoupling,
                                    StructInputs, WingmdaoBuilder, _BuilderGroup, _tagged)

#: the joined state of the whole aircraft (coupling output)
STICK_STATES = "stick_states"
#: the wing's beam inputs of the joined system (``<wing>_<name>``) the coupling group takes from the wing
WING_INPUTS = ("node_positions", "node_euler_angles", *SECTION_TO_BEAM, "point_force", "point_moment")


class StickCoupling(_BuilderGroup):
    """The coupling subsystem: f_aero_struct -> wing point loads -> inertia relief of the whole
    aircraft -> the wing's states -> u_struct."""

    def setup(self):
        b = self.options["builder"]
        n, s, wing = b.num_nodes, b.system, b.wing
        self.add_subsystem("inputs", StructInputs(num_nodes=n), promotes=["*"])
        ivc = self.add_subsystem("jig", om.IndepVarComp(), promotes=["*"])
        ivc.add_output("node_euler_angles", val=b.node_euler_angles, units="rad", desc="jig Euler angles of the wing")
        coupled = {f"{wing}_{k}" for k in SECTION_TO_BEAM}
        cls = _tagged(_tagged(InertiaRelief, coupled | {STICK_STATES}, "mphys_coupling"),
                      {acceleration_output(a) for a in b.accelerations}, "mphys_result")
        relief = cls(system=s, supports=b.supports, accelerations=b.accelerations, param_values=b.param_values,
                     forcing_values=b.forcing_values, state_name=STICK_STATES, **b.newton_options)
        self.add_subsystem("relief", relief, promotes_inputs=[(f"{wing}_{k}", k) for k in WING_INPUTS],
                           promotes_outputs=["*"])
        columns = int(s.offsets[wing]) + np.arange(18 * n)
        self.add_subsystem("wing_states", _tagged(BeamStateSlice, {STATES}, "mphys_coupling")(
            num_times=None, num_nodes=n, state_shape=(s.n_state,), columns=columns, input_name=STICK_STATES,
            output_name=STATES), promotes=["*"])
        self.add_subsystem("disp", BeamDisplacements(node_euler_angles=b.node_euler_angles), promotes=["*"])


class StickBuilder(WingmdaoBuilder):
    """MPhys builder of a free aircraft's stick model (module docstring).

    Parameters
    ----------
    model : wingmdao.beam.joints.JoinedBeamModel
        The joined beams with their parameters (``model.system``, ``model.params``); the ``wing``
        beam must lie in body axes (no ``axes`` rotation).
    width, height : array_like
        (n,) box width and height of the wing, m.
    thickness : float or array_like
        Initial ``dv_struct``: scalar or (4, n) m, the wing's walls (upper skin, lower skin, front
        spar, rear spar).
    material : wingmdao.materials.Material
        The wing's wall material.
    supports : sequence of (str, int, str)
        Statically determinate supports ``(beam, node, "x" | "y" | "z")``, one per acceleration.
    accelerations : sequence of str, optional
        The body axes' unknown accelerations (default surge, plunge, pitch: ``("ax", "az", "alpha_y")``).
    gravity : array_like, optional
        (3,) m/s^2, body axes (default (0, 0, -9.80665)).
    wing : str, optional
        Name of the wing beam (default ``"wing"``).
    nonstructural_mass_per_length : array_like, optional
        (n,) kg/m of the wing's sections (engines and systems smeared; default 0).
    families, rho_ks
        As :class:`~wingmdao.mphys.builder.WingmdaoBuilder`.
    newton_options : dict, optional
        :class:`~wingmdao.components.inertia_relief.InertiaRelief` options (``rtol``, ``max_iter``).
    """

    def __init__(self, model, width, height, thickness, material, supports, accelerations=HALF_AIRCRAFT_ACCELERATIONS,
                 gravity=(0.0, 0.0, -9.80665), wing="wing", nonstructural_mass_per_length=0.0, families=("vm",),
                 rho_ks=100.0, newton_options=None):
        s = model.system
        names = [b.name for b in s.beams]
        if wing not in names:
            raise ValueError(f"StickBuilder: wing = {wing!r} is not a beam of the model; its beams: {names}")
        if not np.allclose(s.beam(wing).rotation, np.eye(3)):
            raise ValueError(f"StickBuilder: the wing beam {wing!r} must lie in body axes (no axes rotation)")
        prm = model.params[wing]
        super().__init__(np.asarray(prm["node_positions"], dtype=float), width, height, thickness, material,
                         node_euler_angles=np.asarray(prm["node_euler_angles"], dtype=float), families=families,
                         rho_ks=rho_ks, newton_options=newton_options)
        g = np.asarray(gravity, dtype=float)
        if g.shape != (3,) or not np.all(np.isfinite(g)):
            raise ValueError(f"StickBuilder: gravity = {gravity}; expected 3 finite components, m/s^2")
        if len(supports) != len(accelerations):
            raise ValueError(f"StickBuilder: {len(supports)} supports for {len(accelerations)} accelerations; a "
                             "statically determinate support has one per acceleration")
        self.nonstructural_mass_per_length = self._per_node_nonnegative(nonstructural_mass_per_length)
        self.model = model
        self.system = s
        self.wing = wing
        self.supports = tuple(tuple(x) for x in supports)
        self.accelerations = tuple(accelerations)
        self.gravity = g
        self.param_values = np.asarray(model.p, dtype=float)
        self.forcing_values = np.asarray(model.forcing(gravity=g), dtype=float)

    def _per_node_nonnegative(self, v):
        a = np.broadcast_to(np.asarray(v, dtype=float), (self.num_nodes,)).copy()
        if not np.all(np.isfinite(a) & (a >= 0)):
            raise ValueError(f"StickBuilder: nonstructural_mass_per_length = {a.min()} kg/m somewhere; allowed "
                             "range [0, inf) kg/m")
        return a

    def get_pre_coupling_subsystem(self, scenario_name=None):
        """dv_struct -> the wing's box sections (with its nonstructural mass) and ``struct_mass``."""
        return PreCoupling(builder=self)

    def get_coupling_group_subsystem(self, scenario_name=None):
        """f_aero_struct -> inertia relief of the whole aircraft -> u_struct (:class:`StickCoupling`)."""
        return StickCoupling(builder=self)

    def get_post_coupling_subsystem(self, scenario_name=None):
        """The wing's states -> box stresses -> ``ks_<family>``."""
        return PostCoupling(builder=self)


def pegasus_stick_builder(num_wing_nodes=20, thickness=None, **options):
    """:class:`StickBuilder` of the PEGASUS half aircraft (:func:`wingmdao.cases.pegasus_stick.build`):
    its wing's box, nonstructural mass and initial walls, supports :data:`~wingmdao.cases.pegasus_stick.SUPPORTS`.

    Parameters
    ----------
    num_wing_nodes : int, optional
        Wing nodes (default 20).
    thickness : dict, optional
        The wing's walls ``{wall: (n,) m}`` (keys ``t_upper_skin`` ... or ``upper_skin`` ...); default
        the case's initial walls. They set the initial ``dv_struct`` and the model's lumped payload
        (the aircraft's mass is half the TOGW).
    **options
        Further :class:`StickBuilder` options (``gravity``, ``families``, ``rho_ks``, ``newton_options``).

    Returns
    -------
    StickBuilder
        The builder (not yet initialized).
    """
    n = int(num_wing_nodes)
    aircraft = pegasus_stick.build(n, thickness=thickness)
    geo = wing_geometry(pegasus.flutter_planform(n), ())[0]
    t = pegasus.initial_thickness(n) if thickness is None else thickness
    walls = np.array([np.asarray(t.get(w, t.get(w[2:])), dtype=float).ravel() for w in WALL_NAMES])
    return StickBuilder(aircraft.model, geo.width, geo.height, walls, ALUMINIUM, pegasus_stick.SUPPORTS,
                        nonstructural_mass_per_length=geo.nonstructural_mass_per_length, **options)
