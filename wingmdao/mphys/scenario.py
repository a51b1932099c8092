"""A ready aerostructural MPhys model: OpenAeroStruct's VLM (``openaerostruct.mphys.AeroBuilder``)
on a symmetric half-wing + the wingmdao nonlinear box beam + the rigid-link transfer.

``aerostructural_problem()`` returns a set-up ``om.Problem`` with one ``ScenarioAeroStructural``
named ``cruise``; the coupling group uses MPhys' default solvers (NonlinearBlockGS and
LinearBlockGS with Aitken, 25 iterations, 1e-8 tolerances). Design inputs: ``dv_struct`` (m),
``aoa`` (deg); outputs ``cruise.ks_vm``, ``cruise.struct_mass`` (kg), ``cruise.wing.CL``.
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om

from wingmdao.materials import ALUMINIUM
from wingmdao.mphys.builder import BeamRigidLinkBuilder, WingmdaoBuilder


def rect_wing_surface(num_y=9, span=10.0, root_chord=1.0):
    """OpenAeroStruct surface dict of a rectangular symmetric wing (aerodynamics only)."""
    from openaerostruct.geometry.utils import generate_mesh

    mesh = generate_mesh({"num_y": num_y, "num_x": 2, "wing_type": "rect", "symmetry": True,
                          "span": span, "root_chord": root_chord})
    return {"name": "wing", "symmetry": True, "S_ref_type": "wetted", "mesh": mesh,
            "CL0": 0.0, "CD0": 0.015, "k_lam": 0.05, "t_over_c_cp": np.array([0.15]), "c_max_t": 0.303,
            "with_viscous": False, "with_wave": False, "twist_cp": np.zeros(2)}


def beam_nodes_from_oas_mesh(mesh, chord_fraction=0.35):
    """Beam nodes on the right wing, root first, at ``chord_fraction`` of the local chord of an
    OpenAeroStruct left half-wing mesh (nx, ny, 3) (y <= 0, tip first): the y-mirror image of
    its spanwise stations, reversed."""
    le, te = mesh[0, ::-1], mesh[-1, ::-1]
    x = le + chord_fraction * (te - le)
    return x * np.array([1.0, -1.0, 1.0])


def aerostructural_problem(surface=None, width=0.4, height=0.12, thickness=0.003, material=None,
                           flow=None, aoa_deg=5.0, iprint=2):
    """The coupled VLM + beam problem (set up, not run). ``flow``: v (m/s), rho (kg/m^3),
    mach_number, reynolds_number (1/m)."""
    from mphys import MPhysVariables, Multipoint
    from mphys.scenarios import ScenarioAeroStructural
    from openaerostruct.mphys import AeroBuilder


    surface = surface or rect_wing_surface()
    material = material or ALUMINIUM
    flow = {"v": 50.0, "rho": 1.2, "mach_number": 0.15, "reynolds_number": 1e6, **(flow or {})}
    units = {"v": "m/s", "rho": "kg/m**3", "mach_number": None, "reynolds_number": "1/m"}
    nodes = beam_nodes_from_oas_mesh(surface["mesh"])
    AERO = MPhysVariables.Aerodynamics

    class Top(Multipoint):
        def setup(self):
            aero = AeroBuilder([surface], options={"write_solution": False})
            aero.initialize(self.comm)
            struct = WingmdaoBuilder(nodes, width=width, height=height, thickness=thickness, material=material)
            struct.initialize(self.comm)
            xfer = BeamRigidLinkBuilder(aero, struct, surface["mesh"].reshape(-1, 3), mirror_y=True)
            xfer.initialize(self.comm)
            dvs = self.add_subsystem("dvs", om.IndepVarComp(), promotes=["*"])
            dvs.add_output("dv_struct", struct.get_initial_dvs(), units="m", desc="wall thicknesses")
            dvs.add_output("aoa", aoa_deg, units="deg", desc="angle of attack")
            for k, v in flow.items():
                dvs.add_output(k, v, units=units[k], desc=k)
            dvs.add_output("cg", np.zeros(3), units="m", desc="moment reference point")
            self.add_subsystem("mesh_aero", aero.get_mesh_coordinate_subsystem())
            self.add_subsystem("mesh_struct", struct.get_mesh_coordinate_subsystem())
            sc = self.mphys_add_scenario("cruise", ScenarioAeroStructural(
                aero_builder=aero, struct_builder=struct, ldxfer_builder=xfer))
            del sc
            self.connect(f"mesh_aero.{AERO.Surface.Mesh.COORDINATES}", f"cruise.{AERO.Surface.COORDINATES_INITIAL}")
            self.connect(f"mesh_struct.{MPhysVariables.Structures.Mesh.COORDINATES}",
                         f"cruise.{MPhysVariables.Structures.COORDINATES}")
            self.connect("dv_struct", "cruise.dv_struct")
            self.connect("aoa", f"cruise.{AERO.FlowConditions.ANGLE_OF_ATTACK}")
            for k in (*flow, "cg"):
                self.connect(k, f"cruise.{k}")

        def configure(self):
            super().configure()
            self.cruise.coupling.nonlinear_solver.options["iprint"] = iprint
            self.cruise.coupling.linear_solver.options["iprint"] = iprint

    prob = om.Problem(Top(), reports=False)
    prob.setup(mode="rev")
    return prob
