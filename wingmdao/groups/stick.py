"""OpenMDAO groups of the stick model of the whole aircraft (:mod:`wingmdao.beam.joints`,
:mod:`wingmdao.aero.joined`) for sizing the wing's walls.

:class:`StickStructure` is one load case of the stick model with the interface of
:class:`~wingmdao.groups.wing.WingStructure`: it takes the wing's beam and section inputs
(``node_positions``, ``stiffness_csn``, ..., ``width``, ``t_upper_skin``, ...) as promoted inputs,
marches the joined aeroelastic system with the BDF2
:class:`~wingmdao.components.time_history.TimeHistoryComponent`, takes the wing's 18 beam states
per node out of the joined state (:class:`~wingmdao.components.state_slice.BeamStateSlice`), and
forms the wing's internal loads, stresses and KS aggregates (``ks_<family>``) as the lone wing's.
The other beams, the lumped masses and the aerodynamic parameters are promoted inputs too,
under the joined system's names (``fuselage_stiffness_csn``, ``lumped_mass``, ``airspeed``, ...);
so is the forcing (``wing_gust_velocity``, ``tail_gust_velocity``, ``gravity``, ``trim_active``,
... at every instant): :func:`set_stick_case` sets them. :class:`StickSizing` is
:class:`~wingmdao.groups.wing.WingSizing` with these cases.
"""

from __future__ import annotations

import numbers

import numpy as np
import openmdao.api as om

from wingmdao.components.beam_loads import BeamInternalLoads
from wingmdao.components.flutter import StickFlutterDamping
from wingmdao.components.ks import KSAggregate
from wingmdao.components.mass import StructuralMass
from wingmdao.components.section import SECTION_OUTPUTS, BoxSection
from wingmdao.components.stress import BoxStress
from wingmdao.components.tube import TubeSection, TubeStress
from wingmdao.components.state_slice import BeamStateSlice
from wingmdao.components.time_history import TimeHistoryComponent
from wingmdao.groups.load_case import SIZED_SECTION_DATA, SizedBeam, StickCase
from wingmdao.groups.wing import (SECTION_KINDS, SECTION_OFFSETS, SECTION_TO_BEAM, WingSizing, _section_classes,
                                  stress_points)
from wingmdao.materials import Material
from wingmdao.section.box import WALL_NAMES
from wingmdao.timemarch.system import layout

#: The wing's beam parameters (lone-wing names) that the joined system calls ``<wing>_<name>``.
WING_BEAM_INPUTS = ("node_positions", "node_euler_angles", *SECTION_TO_BEAM, "tension_axis", "shear_center",
                    "mass_center")


class StickStructure(om.Group):
    """One stick-model load case: joined aeroelastic march -> wing internal loads -> stress -> KS
    (module docstring). Promoted outputs ``ks_<family>`` and ``states``."""

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=2, desc="number of wing nodes (root first)")
        self.options.declare("load_case", types=StickCase, recordable=False, desc="the stick-model load case")
        self.options.declare("material", types=Material, desc="wall material (E, G, rho, sigma_y)")
        self.options.declare("rho_ks", default=100.0, lower=0.0, types=numbers.Real, desc="KS aggregation parameter")
        self.options.declare("add_constraints", default=False, types=bool,
                             desc="add every ks_<family> as a constraint ks <= 0")
        self.options.declare("newton_options", default=None, allow_none=True, types=dict,
                             desc="extra TimeHistoryComponent options (atol, max_iter, ...)")
        self.options.declare("sized_beams", default=[], types=list, recordable=False,
                             desc="SizedBeam list: beams whose stresses are constrained (ks_<beam>_vm)")

    def setup(self):
        n = self.options["num_nodes"]
        case = self.options["load_case"]
        s, nt, wing = case.system, case.num_times, case.wing
        if s.beam(wing).num_nodes != n:
            raise ValueError(f"StickStructure: num_nodes = {n}, the stick model's wing {wing!r} has "
                             f"{s.beam(wing).num_nodes} nodes")
        wing_names = {f"{wing}_{k}": k for k in WING_BEAM_INPUTS}
        # modified Newton, as the lone wing's march (AeroelasticBeamDynamics): 12 LUs in the 500 steps of
        # benchmarks/bench_stick.py instead of one per iteration, the KS and its gradient equal to 1e-12
        beam = TimeHistoryComponent(system=s, time=np.asarray(case.time, dtype=float),
                                    **{"atol": 1e-6, "modified_newton": True, **(self.options["newton_options"] or {})})
        beam.recording_options["options_excludes"] = ["system", "forcing_data"]
        promotes = [(k, v) for k, v in wing_names.items()]
        promotes += [sp.name for sp in s.param_specs + s.forcing_specs if sp.name not in wing_names]
        self.add_subsystem("beam", beam, promotes_inputs=promotes, promotes_outputs=["states"])
        self.add_subsystem("wing_states", BeamStateSlice(num_times=nt, num_nodes=n, state_shape=(s.n_state,),
                                                         columns=s.offsets[wing] + np.arange(18 * n)),
                           promotes_inputs=["states"])
        self.add_subsystem("internal_loads", BeamInternalLoads(num_times=nt, num_nodes=n, inputs_by_conn=True))
        self.connect("wing_states.beam_states", "internal_loads.states")
        stress_cls = _section_classes("box")[1]
        self.add_subsystem("stress", stress_cls(num_times=nt, num_stations=n, material=self.options["material"],
                                                families=tuple(case.families), inputs_by_conn=True,
                                                output_stresses=False, section_properties=True),
                           promotes_inputs=[*SECTION_KINDS["box"]["stress_inputs"],
                                            *SECTION_KINDS["box"]["section_to_stress"]])
        self.connect("internal_loads.F_csn", "stress.F_csn")
        self.connect("internal_loads.M_csn", "stress.M_csn")
        points = stress_points("box", case.families)
        shapes = {fam: (nt, n, k) for fam, k in points.items()}
        for b in self.options["sized_beams"]:
            shapes[f"{b.name}_vm"] = self._add_sized_beam(b, s, nt)
        self.add_subsystem("ks", KSAggregate(families=shapes, rho_ks=self.options["rho_ks"], g_by_conn=True,
                                             add_constraints=self.options["add_constraints"]),
                           promotes_outputs=[f"ks_{f}" for f in shapes])
        for fam in case.families:
            self.connect(f"stress.g_{fam}", f"ks.g_{fam}")
        for b in self.options["sized_beams"]:
            self.connect(f"{b.name}_stress.g_vm", f"ks.g_{b.name}_vm")

    def _add_sized_beam(self, b, s, nt):
        """States, internal loads and ``vm`` stress of the sized beam ``b``; returns its g shape."""
        nb = s.beam(b.name).num_nodes
        if nb != b.num_nodes:
            raise ValueError(f"StickStructure: sized beam {b.name!r} has {b.num_nodes} nodes, the stick model's "
                             f"{nb}")
        self.add_subsystem(f"{b.name}_states", BeamStateSlice(num_times=nt, num_nodes=nb, state_shape=(s.n_state,),
                                                              columns=s.offsets[b.name] + np.arange(18 * nb)),
                           promotes_inputs=["states"])
        self.add_subsystem(f"{b.name}_internal_loads", BeamInternalLoads(num_times=nt, num_nodes=nb,
                                                                         inputs_by_conn=True))
        self.connect(f"{b.name}_states.beam_states", f"{b.name}_internal_loads.states")
        mat = self.options["material"]
        if b.kind == "box":
            stress = BoxStress(num_times=nt, num_stations=nb, material=mat, families=("vm",), inputs_by_conn=True,
                               output_stresses=False, section_properties=True)
            points = stress_points("box", ("vm",))["vm"]
        else:
            stress = TubeStress(num_times=nt, num_stations=nb, material=mat, radius=b.data["radius"],
                                fraction=b.data.get("fraction", 1.0), inputs_by_conn=True)
            points = TubeStress.points_per_station()
        self.add_subsystem(f"{b.name}_stress", stress,
                           promotes_inputs=[(k[len(b.name) + 1:], k) for k in b.stress_inputs])
        self.connect(f"{b.name}_internal_loads.F_csn", f"{b.name}_stress.F_csn")
        self.connect(f"{b.name}_internal_loads.M_csn", f"{b.name}_stress.M_csn")
        return (nt, nb, points)


def set_stick_case(prob: om.Problem, case: StickCase, path: str = "", sized_beams=()) -> None:
    """Set the inputs of the stick case at ``path`` (its promoted prefix, e.g. ``"cases.gust"``)
    other than the wing's and the sized beams' sections: the other beams', lumped masses' and
    aerodynamic parameters from ``case.p`` and the forcing history ``case.forcing``.

    Parameters
    ----------
    prob : openmdao.api.Problem
        A set-up problem holding the stick case.
    case : wingmdao.groups.load_case.StickCase
        The stick case.
    path : str
        Promoted prefix of the case's group.
    sized_beams : sequence of SizedBeam
        Beams whose section parameters come from their sized sections (not set here).
    """
    prefix = f"{path}." if path else ""
    s = case.system
    wing_names = {f"{case.wing}_{k}" for k in WING_BEAM_INPUTS}
    wing_names |= {k for b in sized_beams for k in b.beam_inputs}
    play, qlay = layout(s.param_specs), layout(s.forcing_specs)
    for sp in s.param_specs:
        if sp.name not in wing_names:
            prob.set_val(prefix + sp.name, np.asarray(case.p)[play[sp.name]].reshape(sp.shape or (1,)))
    Q = np.asarray(case.forcing, dtype=float)
    for sp in s.forcing_specs:
        prob.set_val(prefix + sp.name, Q[:, qlay[sp.name]].reshape((case.num_times,) + (tuple(sp.shape) or (1,))))


class StickSizing(WingSizing):
    """:class:`~wingmdao.groups.wing.WingSizing` (wall design variables, box sections, mass) with
    stick-model load cases (:class:`StickStructure`, option ``stick_cases``) in ``cases`` and, with
    the option ``stick_flutter``, the flutter-damping constraint ``flutter_ks`` of the free stick
    aircraft (:class:`~wingmdao.components.flutter.StickFlutterDamping`; with ``sized_beams``, it
    takes their sections' beam parameters too)."""

    def initialize(self):
        super().initialize()
        self.options.declare("stick_cases", types=list, recordable=False, desc="list of StickCase")
        self.options.declare("stick_flutter", default=None, allow_none=True, types=dict, recordable=False,
                             desc="options of components.flutter.StickFlutterDamping (system, p, speeds, ...): adds "
                                  "the constraint flutter_ks <= 0 (None: none)")
        self.options.declare("sized_beams", default=[], types=list, recordable=False,
                             desc="SizedBeam list: beams other than the wing whose sections are sized (their walls "
                                  "<beam>_<wall> inputs, ks_<beam>_vm per case, <beam>_mass; objective total_mass)")
        self.options["proxy_cases"] = True
        self.options["load_cases"] = []

    def setup(self):
        sized = self.options["sized_beams"]
        for b in sized:   # before the cases, which take their beam parameters
            self._add_sized_section(b)
        objective = self.options["add_objective"]
        self.options["add_objective"] = objective and not sized   # with sized beams: total_mass (below)
        try:
            super().setup()
        finally:
            self.options["add_objective"] = objective
        n = self.options["num_nodes"]
        if self.options["section"] != "box":
            raise ValueError(f"StickSizing: box sections only, got section {self.options['section']!r}")
        names = [c.name for c in self.options["stick_cases"]]
        if not names or len(set(names)) != len(names):
            raise ValueError(f"StickSizing: stick_cases must have distinct names, got {names}")
        mapped = self.options["station_map"] is not None   # the cases take the walls per station
        shared = ["width", "height", *[(w, f"{w}_station") if mapped else w for w in WALL_NAMES], *WING_BEAM_INPUTS,
                  *SECTION_KINDS["box"]["section_to_stress"]]
        shared += [k for b in sized for k in (*b.beam_inputs, *b.stress_inputs)]
        for case in self.options["stick_cases"]:
            self.cases_group.add_subsystem(case.name, StickStructure(
                num_nodes=n, load_case=case, material=self.options["material"], rho_ks=self.options["rho_ks"],
                add_constraints=self.options["add_constraints"], newton_options=self.options["newton_options"],
                sized_beams=list(sized)),
                promotes_inputs=shared)
        if sized:
            total = om.AddSubtractComp()
            total.add_equation("total_mass", ["mass", *[f"{b.name}_mass" for b in sized]], units="kg",
                               desc="structural mass of the sized walls: wing, " + ", ".join(b.name for b in sized))
            self.add_subsystem("total_mass_calc", total, promotes=["*"])
            if objective:
                self.add_objective("total_mass", ref=self.options["mass_ref"])
        if self.options["stick_flutter"] is not None:
            # the sized beams' sections feed the flutter constraint as they feed the cases
            beam_inputs = [k for b in sized for k in b.beam_inputs]
            flutter = {**self.options["stick_flutter"], "beam_inputs": beam_inputs}
            self.add_subsystem("stick_flutter", StickFlutterDamping(**flutter),
                               promotes_inputs=[*SECTION_TO_BEAM, *SECTION_OFFSETS, *beam_inputs],
                               promotes_outputs=["flutter_ks"])
            if self.options["add_constraints"]:
                self.add_constraint("flutter_ks", upper=0.0, ref=self.FLUTTER_REF)

    def _add_sized_section(self, b):
        """The section of the sized beam ``b`` (its beam parameters ``<b>_stiffness_csn``, ... and
        stress properties, promoted) and its walls' mass ``<b>_mass``."""
        nb, mat, name = b.num_nodes, self.options["material"], b.name
        ins = [(k, f"{name}_{k}") for k in (*b.walls, *SIZED_SECTION_DATA[b.kind])]
        if b.kind == "box":
            section = BoxSection(num_stations=nb, material=mat)
            outs = [(k, f"{name}_{k}") for k, *_ in SECTION_OUTPUTS]
        else:
            section = TubeSection(num_stations=nb, material=mat, radius=b.data["radius"],
                                  fraction=b.data.get("fraction", 1.0))
            outs = [(k, f"{name}_{k}") for k in ("A", "stiffness_csn", "compliance_csn", "mass_per_length")]
        self.add_subsystem(f"{name}_section", section, promotes_inputs=ins, promotes_outputs=outs)
        if b.kind == "box":
            mux = self.add_subsystem(f"{name}_offsets", om.MuxComp(vec_size=2),
                                     promotes_outputs=[(k, f"{name}_{k}") for k in SECTION_OFFSETS])
            for out, (c, nn) in SECTION_OFFSETS.items():
                mux.add_var(out, shape=(nb,), axis=1, units="m")
                self.connect(f"{name}_{c}", f"{name}_offsets.{out}_0")
                self.connect(f"{name}_{nn}", f"{name}_offsets.{out}_1")
        self.add_subsystem(f"{name}_mass_calc", StructuralMass(num_nodes=nb, density=mat.rho),
                           promotes_inputs=[("A", f"{name}_A")], promotes_outputs=[("mass", f"{name}_mass")])
        # the walls and the box's dimensions are inputs of the section and of every case's stress
        for k in (*b.walls, *(("width", "height") if b.kind == "box" else ())):
            self.set_input_defaults(f"{name}_{k}", val=np.full(nb, float(b.initial) if k in b.walls else 1.0),
                                    units="m")


def set_sized_beams(prob: om.Problem, sized_beams) -> None:
    """Set the sized beams' section data (box width and height, nonstructural mass per length),
    their node positions (for their mass) and their walls at ``initial``.

    Parameters
    ----------
    prob : openmdao.api.Problem
        A set-up problem holding a :class:`StickSizing` with these ``sized_beams``.
    sized_beams : sequence of SizedBeam
        The sized beams.
    """
    for b in sized_beams:
        nb = b.num_nodes
        for k in SIZED_SECTION_DATA[b.kind]:
            prob.set_val(f"{b.name}_{k}", np.broadcast_to(np.asarray(b.data[k], dtype=float), (nb,)))
        prob.set_val(f"{b.name}_mass_calc.node_positions", np.asarray(b.node_positions, dtype=float))
        for v in b.design_vars:
            prob.set_val(v, np.full(nb, float(b.initial)))


__all__ = ["StickCase", "StickStructure", "StickSizing", "SizedBeam", "set_stick_case", "set_sized_beams",
           "WING_BEAM_INPUTS"]
