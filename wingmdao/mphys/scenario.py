"""A ready aerostructural MPhys model: OpenAeroStruct's VLM (``openaerostruct.mphys.AeroBuilder``)
on a symmetric half-wing + the wingmdao nonlinear box beam + the rigid-link transfer.

``aerostructural_problem()`` returns a set-up ``om.Problem`` with one ``ScenarioAeroStructural``
named ``cruise`` (``stick_aerostructural_problem()``: the same with the PEGASUS stick model, the
whole free aircraft in inertia relief, as the structure); the coupling group uses MPhys' default solvers (NonlinearBlockGS and
LinearBlockGS with Aitken, 25 iterations, 1e-8 tolerances). Design inputs: ``dv_struct`` (m),
``aoa`` (deg); outputs ``cruise.ks_vm``, ``cruise.struct_mass`` (kg), ``cruise.wing.CL``.
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om

from wingmdao.cases import pegasus_stick
from wingmdao.materials import ALUMINIUM
from wingmdao.mphys.builder import BeamRigidLinkBuilder, WingmdaoBuilder
from wingmdao.mphys.stick import pegasus_stick_builder


def rect_wing_surface(num_y=9, span=10.0, root_chord=1.0):
    """OpenAeroStruct surface dict of a rectangular symmetric wing (aerodynamics only).

    Parameters
    ----------
    num_y : int, optional
        Spanwise mesh points of the full wing.
    span : float, optional
        Full span (m).
    root_chord : float, optional
        Chord (m).

    Returns
    -------
    dict
        The surface.
    """
    from openaerostruct.geometry.utils import generate_mesh

    mesh = generate_mesh({"num_y": num_y, "num_x": 2, "wing_type": "rect", "symmetry": True,
                          "span": span, "root_chord": root_chord})
    return {"name": "wing", "symmetry": True, "S_ref_type": "wetted", "mesh": mesh,
            "CL0": 0.0, "CD0": 0.015, "k_lam": 0.05, "t_over_c_cp": np.array([0.15]), "c_max_t": 0.303,
            "with_viscous": False, "with_wave": False, "twist_cp": np.zeros(2)}


def beam_nodes_from_oas_mesh(mesh, chord_fraction=0.35):
    """Beam nodes on the right wing, root first, at ``chord_fraction`` of the local chord of an
    OpenAeroStruct left half-wing mesh (nx, ny, 3) (y <= 0, tip first): the y-mirror image of
    its spanwise stations, reversed.

    Parameters
    ----------
    mesh : numpy.ndarray
        (nx, ny, 3) OpenAeroStruct left half-wing mesh (m).
    chord_fraction : float, optional
        Chord fraction of the beam axis (-).

    Returns
    -------
    numpy.ndarray
        (ny, 3) beam nodes (m).
    """
    le, te = mesh[0, ::-1], mesh[-1, ::-1]
    x = le + chord_fraction * (te - le)
    return x * np.array([1.0, -1.0, 1.0])


def aerostructural_problem(surface=None, width=0.4, height=0.12, thickness=0.003, material=None,
                           flow=None, aoa_deg=5.0, iprint=2):
    """The coupled VLM + beam problem (set up, not run). ``flow``: v (m/s), rho (kg/m^3),
    mach_number, reynolds_number (1/m).

    Parameters
    ----------
    surface : dict or None, optional
        OpenAeroStruct surface; None for :func:`rect_wing_surface`.
    width, height : float or array_like, optional
        Box dimensions (m).
    thickness : float or array_like, optional
        Initial wall thicknesses (m).
    material : Material or None, optional
        Isotropic material; None for aluminium.
    flow : dict or None, optional
        ``v`` (m/s), ``rho`` (kg/m^3), ``mach_number``, ``reynolds_number`` (1/m); missing keys 50 m/s,
        1.2 kg/m^3, 0.15 and 1e6 /m.
    aoa_deg : float, optional
        Angle of attack (deg).
    iprint : int, optional
        Solver print level.

    Returns
    -------
    openmdao.api.Problem
        The set-up problem.
    """
    surface = surface or rect_wing_surface()
    material = material or ALUMINIUM
    nodes = beam_nodes_from_oas_mesh(surface["mesh"])
    return _problem(surface, lambda: WingmdaoBuilder(nodes, width=width, height=height, thickness=thickness,
                                                     material=material), flow, aoa_deg, iprint)


def stick_wing_surface(aircraft):
    """OpenAeroStruct surface dict (aerodynamics only) of the wing of a stick aircraft.

    Parameters
    ----------
    aircraft : wingmdao.cases.pegasus_stick.StickAircraft
        The stick model: its wing's nodes (body axes, root first), chords and beam-axis fractions.

    Returns
    -------
    dict
        A symmetric left half-wing, one chordwise panel, its spanwise stations the wing's beam nodes
        (tip first, y mirrored), leading edge ``axis_fraction * chord`` ahead of the beam axis.
    """
    r = np.asarray(aircraft.nodes["wing"], dtype=float)
    c, f = np.asarray(aircraft.wing_chord, dtype=float), np.asarray(aircraft.wing_axis_fraction, dtype=float)
    le = r.copy()
    le[:, 0] -= f * c
    te = le.copy()
    te[:, 0] += c
    mirror = np.array([1.0, -1.0, 1.0])
    mesh = np.array([le[::-1] * mirror, te[::-1] * mirror])
    return {"name": "wing", "symmetry": True, "S_ref_type": "wetted", "mesh": mesh,
            "CL0": 0.0, "CD0": 0.015, "k_lam": 0.05, "t_over_c_cp": np.array([0.15]), "c_max_t": 0.303,
            "with_viscous": False, "with_wave": False, "twist_cp": np.zeros(2)}


def stick_aerostructural_problem(num_wing_nodes=8, flow=None, aoa_deg=3.0, iprint=2):
    """The coupled VLM + stick model problem of the PEGASUS half aircraft (set up, not run).

    The vortex lattice on its wing (:func:`stick_wing_surface`), the whole aircraft in inertia relief
    (:func:`wingmdao.mphys.stick.pegasus_stick_builder`), the rigid-link transfer.

    Parameters
    ----------
    num_wing_nodes : int, optional
        Wing nodes of the stick model (and spanwise stations of the lattice).
    flow : dict, optional
        ``v`` (m/s), ``rho`` (kg/m^3), ``mach_number``, ``reynolds_number`` (1/m); default 25 000 ft,
        M 0.5: v 154.8 m/s, rho 0.5489 kg/m^3.
    aoa_deg : float, optional
        Angle of attack (deg).
    iprint : int, optional
        Print level of the coupling solvers.

    Returns
    -------
    openmdao.api.Problem
        Set up in reverse mode; outputs as :func:`aerostructural_problem` plus ``cruise.frame_ax``,
        ``cruise.frame_az`` (m/s^2) and ``cruise.frame_alpha_y`` (rad/s^2).
    """
    surface = stick_wing_surface(pegasus_stick.build(num_wing_nodes))
    flow = {"v": 154.8, "rho": 0.5489, "mach_number": 0.5, "reynolds_number": 1e6, **(flow or {})}
    return _problem(surface, lambda: pegasus_stick_builder(num_wing_nodes), flow, aoa_deg, iprint)


def _problem(surface, make_struct, flow, aoa_deg, iprint):
    """One ``cruise`` ScenarioAeroStructural: OpenAeroStruct's VLM on ``surface`` (a symmetric left
    half-wing), the structural builder ``make_struct()``, the rigid-link transfer."""
    from mphys import MPhysVariables, Multipoint
    from mphys.scenarios import ScenarioAeroStructural
    from openaerostruct.mphys import AeroBuilder

    flow = {"v": 50.0, "rho": 1.2, "mach_number": 0.15, "reynolds_number": 1e6, **(flow or {})}
    units = {"v": "m/s", "rho": "kg/m**3", "mach_number": None, "reynolds_number": "1/m"}
    AERO = MPhysVariables.Aerodynamics

    class Top(Multipoint):
        def setup(self):
            aero = AeroBuilder([surface], options={"write_solution": False})
            aero.initialize(self.comm)
            struct = make_struct()
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
            self.mphys_add_scenario("cruise", ScenarioAeroStructural(
                aero_builder=aero, struct_builder=struct, ldxfer_builder=xfer))
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
