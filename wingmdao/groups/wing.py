"""Groups that wire the discipline chain: section -> beam -> internal loads -> stress -> KS.

``WingStructure`` analyses one load case; ``WingSizing`` shares the thickness design
variables and section properties among any number of static and dynamic load cases and
adds the mass objective. Promoted names follow the chain so the N2 diagram reads like it:

    design  (t_upper_skin, ..., width, height, node_positions, node_euler_angles)
    section (BoxSection: stiffness_csn, compliance_csn, offsets, mass_per_length, ...)
    mass    (StructuralMass: mass)
    cases.<case>.loads -> beam -> internal_loads -> stress -> ks   (ks_<family>)

Every group uses ``LinearRunOnce`` (OpenMDAO's default): the beam solves its own linear
systems (forward and adjoint sweeps over the time history); a ``DirectSolver`` above it
would assemble the whole history matrix and bypass that.
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om

from wingmdao.groups.load_case import FORCING_SHAPES, LoadCase

#: Inputs the beam takes from the section, with the section output that feeds it.
SECTION_TO_BEAM = ("stiffness_csn", "compliance_csn", "mass_per_length", "inertia_per_length")
WALLS = ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")

#: Section kinds: the per-station inputs of the stress component (also the design variables
#: of a sizing problem are the thicknesses for a box, width and height for a solid section).
SECTION_KINDS = {
    "box": {"stress_inputs": ("width", "height") + WALLS, "design_vars": WALLS},
    "solid": {"stress_inputs": ("width", "height"), "design_vars": ("width", "height")},
}


def _section_classes(kind):
    if kind == "box":
        from wingmdao.components.section import BoxSection
        from wingmdao.components.stress import BoxStress

        return BoxSection, BoxStress
    if kind == "solid":
        from wingmdao.components.section import SolidRectSection
        from wingmdao.components.solid_stress import SolidRectStress

        return SolidRectSection, SolidRectStress
    raise ValueError(f"section must be one of {', '.join(SECTION_KINDS)}, got {kind!r}")


def _stress_points(kind, families, num_times, num_nodes, material):
    """Shapes of each family's constraint array, read from a stand-alone stress component."""
    stress_cls = _section_classes(kind)[1]
    probe = om.Problem(reports=False)
    probe.model.add_subsystem("s", stress_cls(num_times=1, num_stations=1, material=material,
                                              families=tuple(families)))
    probe.setup()
    shapes = {}
    for fam in families:
        k = probe.model.s._var_rel2meta[f"g_{fam}"]["shape"][-1]
        shapes[fam] = (num_times, num_nodes, k)
    return shapes


class WingStructure(om.Group):
    """One load case: beam (static or BDF2 time march) -> csn internal loads -> stress -> KS."""

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=2)
        self.options.declare("load_case", types=LoadCase)
        self.options.declare("material", desc="wingmdao.materials.Material")
        self.options.declare("rho_ks", default=100.0, lower=0.0, desc="KS aggregation parameter")
        self.options.declare("section", default="box", values=tuple(SECTION_KINDS))
        self.options.declare("newton_options", default=None, allow_none=True, types=dict,
                             desc="extra BeamDynamics options (atol, max_iter, static_options, modified_newton, ...)")

    def setup(self):
        from wingmdao.components.beam import BeamDynamics
        from wingmdao.components.beam_loads import BeamInternalLoads
        from wingmdao.components.ks import KSAggregate

        kind = self.options["section"]
        stress_cls = _section_classes(kind)[1]

        n = self.options["num_nodes"]
        case = self.options["load_case"]
        nt = case.num_times

        loads = self.add_subsystem("loads", om.IndepVarComp())
        for name, (units, desc) in _FORCING_META.items():
            loads.add_output(name, val=case.forcing_array(name, n), units=units, desc=desc)

        beam_kwargs = dict(num_nodes=n, time=case.time, **(self.options["newton_options"] or {}))
        if case.damping is not None and not case.damping.is_zero:
            from wingmdao.beam.static import cached_beam_system

            beam_kwargs["system"] = cached_beam_system(n, beam_kwargs.get("euler_sequence", "surface"), case.damping)
        beam = BeamDynamics(**beam_kwargs)
        beam.recording_options["options_excludes"] = ["system"]  # a CasADi object: not picklable
        self.add_subsystem("beam", beam, promotes_inputs=[
            "node_positions", "node_euler_angles", *SECTION_TO_BEAM,
            "tension_axis", "shear_center", "mass_center"])
        for name in FORCING_SHAPES:
            self.connect(f"loads.{name}", f"beam.{name}")

        self.add_subsystem("internal_loads", BeamInternalLoads(num_times=nt, num_nodes=n))
        self.connect("beam.states", "internal_loads.states")

        stress_kwargs = {"output_stresses": False} if kind == "box" else {}
        self.add_subsystem("stress", stress_cls(num_times=nt, num_stations=n,
                                                material=self.options["material"],
                                                families=tuple(case.families), **stress_kwargs),
                           promotes_inputs=list(SECTION_KINDS[kind]["stress_inputs"]))
        self.connect("internal_loads.F_csn", "stress.F_csn")
        self.connect("internal_loads.M_csn", "stress.M_csn")

        shapes = _stress_points(kind, case.families, nt, n, self.options["material"])
        self.add_subsystem("ks", KSAggregate(families=shapes, rho_ks=self.options["rho_ks"]),
                           promotes_outputs=[f"ks_{f}" for f in case.families])
        for fam in case.families:
            self.connect(f"stress.g_{fam}", f"ks.g_{fam}")


_FORCING_META = {
    "force_per_length": ("N/m", "distributed force per unit undeformed length, body axes"),
    "moment_per_length": ("N*m/m", "distributed moment per unit undeformed length, body axes"),
    "point_force": ("N", "point forces at the nodes, body axes"),
    "point_moment": ("N*m", "point moments at the nodes, body axes"),
    "gravity": ("m/s**2", "gravitational acceleration in body axes"),
    "frame_acceleration": ("m/s**2", "acceleration of the body frame origin"),
    "frame_angular_velocity": ("rad/s", "angular velocity of the body frame"),
    "frame_angular_acceleration": ("rad/s**2", "angular acceleration of the body frame"),
}


class WingSizing(om.Group):
    """Shared thickness design variables, box sections and mass; one WingStructure per load case.

    Options: ``num_nodes``; ``load_cases`` (list of :class:`LoadCase`); ``material``;
    ``rho_ks``; ``parallel`` (put the cases in an ``om.ParallelGroup`` to run them side by side
    under MPI; default: when mpi4py is installed, else a serial ``om.Group``).
    Inputs to set (promoted): ``t_upper_skin``, ``t_lower_skin``, ``t_front_spar``,
    ``t_rear_spar``, ``width``, ``height`` (per node, m), ``node_positions`` (n, 3) m,
    ``node_euler_angles`` (n, 3) rad, ``section_to_csn`` (n, 3, 3),
    ``nonstructural_mass_per_length`` (n,) kg/m. Outputs: ``mass`` (kg) and
    ``cases.<case>.ks_<family>``.
    """

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=2)
        self.options.declare("load_cases", types=list)
        self.options.declare("material", desc="wingmdao.materials.Material")
        self.options.declare("rho_ks", default=100.0, lower=0.0)
        self.options.declare("parallel", default=None, allow_none=True, types=bool,
                             desc="load cases in an om.ParallelGroup (None: when mpi4py imports)")
        self.options.declare("section", default="box", values=tuple(SECTION_KINDS))
        self.options.declare("station_map", default=None, allow_none=True,
                             desc="(n,) int: design-variable index of each station (None: one per station)")
        self.options.declare("newton_options", default=None, allow_none=True, types=dict)

    def setup(self):
        from wingmdao.components.mass import StructuralMass
        from wingmdao.components.station_map import StationMap

        n = self.options["num_nodes"]
        kind = self.options["section"]
        section_cls = _section_classes(kind)[0]
        mat = self.options["material"]
        names = [c.name for c in self.options["load_cases"]]
        if len(set(names)) != len(names):
            raise ValueError(f"load case names must be unique, got {names}")

        design = SECTION_KINDS[kind]["design_vars"]
        alias = []
        if self.options["station_map"] is not None:
            self.add_subsystem("design_map", StationMap(station_map=self.options["station_map"], names=design),
                               promotes=["*"])
            alias = [(d, f"{d}_station") for d in design]
        self.add_subsystem("section", section_cls(num_stations=n, material=mat),
                           promotes_inputs=alias + ["*"], promotes_outputs=["*"])
        mux = self.add_subsystem("offsets", om.MuxComp(vec_size=2), promotes_outputs=["*"])
        for out, (c, s) in {"tension_axis": ("c_ea", "n_ea"), "shear_center": ("c_sc", "n_sc"),
                            "mass_center": ("c_cg", "n_cg")}.items():
            mux.add_var(out, shape=(n,), axis=1, units="m")
            self.connect(c, f"offsets.{out}_0")
            self.connect(s, f"offsets.{out}_1")
        self.add_subsystem("mass_calc", StructuralMass(num_nodes=n, density=mat.rho),
                           promotes_inputs=["A", "node_positions"],
                           promotes_outputs=["mass"])

        # inputs shared by several components get one default (units and shape)
        self.set_input_defaults("node_positions", val=np.zeros((n, 3)), units="m")
        self.set_input_defaults("node_euler_angles", val=np.zeros((n, 3)), units="rad")
        n_dv = n if self.options["station_map"] is None else int(np.max(self.options["station_map"])) + 1
        for name in SECTION_KINDS[kind]["stress_inputs"]:
            shape = (n_dv,) if (name in design and alias) else (n,)
            self.set_input_defaults(name, val=np.ones(shape), units="m")

        parallel = self.options["parallel"]
        if parallel is None:
            import importlib.util

            parallel = importlib.util.find_spec("mpi4py") is not None
        cases = self.add_subsystem("cases", om.ParallelGroup() if parallel else om.Group(),
                                   promotes_inputs=["*"])
        alias_map = dict(alias)
        case_inputs = [(v, alias_map[v]) if v in alias_map else v for v in SECTION_KINDS[kind]["stress_inputs"]]
        case_inputs += ["node_positions", "node_euler_angles", *SECTION_TO_BEAM,
                        "tension_axis", "shear_center", "mass_center"]
        for case in self.options["load_cases"]:
            cases.add_subsystem(case.name, WingStructure(
                num_nodes=n, load_case=case, material=mat, rho_ks=self.options["rho_ks"],
                section=kind, newton_options=self.options["newton_options"]),
                promotes_inputs=case_inputs)
