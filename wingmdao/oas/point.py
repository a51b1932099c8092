"""OpenAeroStruct aerostructural point with the wingmdao beam as its structural solver.

``WingmdaoAerostructPoint`` is OpenAeroStruct's ``AerostructPoint`` composed again from
OpenAeroStruct's public components, with the per-surface coupled group solving the wingmdao
nonlinear box beam (:class:`~wingmdao.oas.coupling.OASBeamStates`) instead of the linear
spatial beam. Differences to connect: instead of
``coupled.<surface>.local_stiff_transformed`` connect ``coupled.<surface>.spar_thickness``,
``skin_thickness``, ``htop``, ``hbottom``, ``hfront``, ``hrear`` (from the same outputs of
``AerostructGeometry``): the box of each element is OpenAeroStruct's own (width hfront + hrear,
height htop + hbottom) when the surface has ``wingmdao_box = "oas"``, so both beams see nearly
the same section (htop and hbottom are OpenAeroStruct's KS-smoothed maxima, slightly above the
true box height: 2.3 % stiffer on the rectangular test wing). Default (``"surface"``): the box
from the surface dict (``box_geometry_from_surface``), exact for flat-topped "airfoils". Still
connect ``coupled.<surface>.nodes`` and ``coupled.<surface>.mesh`` (the displacement transfer
uses them). The beam's jig axis (nodes at ``fem_origin``) is fixed
when the point is set up; weight relief, fuel and point
masses are not applied to our beam (surfaces must have ``struct_weight_relief`` and
``distributed_fuel_weight`` False and no ``n_point_masses``).
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om

from wingmdao.oas.coupling import OASBeamStates


def box_geometry_from_surface(surface):
    """(fem_nodes (ny, 3), width (ny-1,), height (ny-1,)) in m from an OpenAeroStruct wingbox
    surface dict: nodes at ``fem_origin`` of the chord (OpenAeroStruct's rule), width = spar
    spacing, height = mean of the front and rear spar heights scaled to the element t/c.

    Parameters
    ----------
    surface : dict
        OpenAeroStruct wingbox surface.

    Returns
    -------
    tuple
        (fem_nodes, width, height).
    """
    mesh = np.real(np.asarray(surface["mesh"], dtype=complex))
    le, te = mesh[0], mesh[-1]
    w = float(surface.get("fem_origin", 0.35))
    nodes = (1.0 - w) * le + w * te
    chord_n = np.linalg.norm(te - le, axis=1)
    chord = 0.5 * (chord_n[1:] + chord_n[:-1])
    xu, yu = np.real(surface["data_x_upper"]), np.real(surface["data_y_upper"])
    yl = np.real(surface["data_y_lower"])
    width = (xu[-1] - xu[0]) * chord
    h0 = 0.5 * ((yu[0] - yl[0]) + (yu[-1] - yl[-1]))
    tc = np.asarray(surface.get("t_over_c", surface["original_wingbox_airfoil_t_over_c"]), dtype=float)
    if "t_over_c_cp" in surface and "t_over_c" not in surface:
        cp = np.real(surface["t_over_c_cp"])
        tc = np.interp(np.linspace(0, 1, chord.size), np.linspace(0, 1, cp.size), cp)
    height = h0 * tc / float(surface["original_wingbox_airfoil_t_over_c"]) * chord
    return nodes, width, np.broadcast_to(height, width.shape).copy()


#: OpenAeroStruct wingbox geometry outputs the beam's box is built from (connect them).
BOX_INPUTS = ("htop", "hbottom", "hfront", "hrear")


class WingmdaoCoupledAS(om.Group):
    """One surface of the coupled aerostructural loop: the wingmdao beam (``struct_states``,
    :class:`~wingmdao.oas.coupling.OASBeamStates`), OpenAeroStruct's displacement transfer
    (``def_mesh``) and VLM geometry (``aero_geom``); the same inputs and outputs as
    OpenAeroStruct's ``CoupledAS`` except ``spar_thickness``, ``skin_thickness`` (and the
    ``BOX_INPUTS`` with ``wingmdao_box = "oas"``) in place of ``local_stiff_transformed``."""

    def initialize(self):
        self.options.declare("surface", types=dict, desc="OpenAeroStruct wingbox surface dict with "
                             "'wingmdao_material' (wingmdao.materials.Material)")

    def setup(self):
        from openaerostruct.aerodynamics.geometry import VLMGeometry
        from openaerostruct.transfer.displacement_transfer_group import DisplacementTransferGroup


        surface = self.options["surface"]
        check_surface(surface)
        nodes, width, height = box_geometry_from_surface(surface)
        from_oas = surface.get("wingmdao_box", "surface") == "oas"
        self.add_subsystem("struct_states", OASBeamStates(
            fem_nodes=nodes, width=width, height=height, material=surface["wingmdao_material"],
            newton_options=surface.get("wingmdao_newton_options"), box_from_oas=from_oas),
            promotes_inputs=["loads", "spar_thickness", "skin_thickness", *(BOX_INPUTS if from_oas else ())],
            promotes_outputs=["disp"])
        self.add_subsystem("def_mesh", DisplacementTransferGroup(surface=surface),
                           promotes_inputs=["nodes", "mesh", "disp"], promotes_outputs=["def_mesh"])
        self.add_subsystem("aero_geom", VLMGeometry(surface=surface), promotes_inputs=["def_mesh"],
                           promotes_outputs=list(AERO_GEOM_OUTPUTS))
        self.linear_solver = om.LinearRunOnce()


#: outputs of OpenAeroStruct's VLMGeometry that the coupled surface group promotes.
AERO_GEOM_OUTPUTS = ("b_pts", "widths", "lengths_spanwise", "lengths", "chords", "normals", "S_ref")

#: ``coupled.<surface>.X`` -> ``<surface>_perf.Y`` (point level), as in OpenAeroStruct's AerostructPoint.
_TO_PERF = {"disp": "disp", "S_ref": "S_ref", "widths": "widths", "lengths": "lengths",
            "lengths_spanwise": "lengths_spanwise", "chords": "aero_funcs.chords"}
#: ``coupled.<surface>.X`` -> ``total_perf.<surface>_X``.
_TO_TOTAL = ("S_ref", "widths", "chords", "b_pts")
#: flight-condition inputs promoted by the performance group and by the total performance.
_PERF_INPUTS = ("rho", "v", "alpha", "beta", "re", "Mach_number")
_TOTAL_INPUTS = ("v", "rho", "empty_cg", "total_weight", "CT", "speed_of_sound", "R", "Mach_number", "W0",
                 "load_factor", "S_ref_total")
_TOTAL_OUTPUTS = ("L_equals_W", "fuelburn", "CL", "CD", "CM", "cg")


def check_surface(surface):
    """ValueError for a surface our beam cannot take (OpenAeroStruct options it does not model).

    Parameters
    ----------
    surface : dict
        OpenAeroStruct surface.
    """
    for key in ("struct_weight_relief", "distributed_fuel_weight"):
        if surface.get(key, False):
            raise ValueError(f"WingmdaoAerostructPoint: surface['{key}'] = True is not supported; set False")
    if "n_point_masses" in surface:
        raise ValueError("WingmdaoAerostructPoint: point masses (n_point_masses) are not supported")
    if "is_multi_section" in surface:
        raise ValueError("WingmdaoAerostructPoint: multi-section surfaces (is_multi_section) are not supported")
    if surface.get("fem_model_type", "").lower() != "wingbox":
        raise ValueError(f"WingmdaoAerostructPoint: surface['fem_model_type'] = {surface.get('fem_model_type')!r}; "
                         "the wingmdao beam needs 'wingbox'")
    if "wingmdao_material" not in surface:
        raise ValueError("WingmdaoAerostructPoint: surface['wingmdao_material'] (a wingmdao.materials.Material) "
                         "is missing")


class WingmdaoAerostructPoint(om.Group):
    """An aerostructural flight point with the wingmdao beam: the composition of OpenAeroStruct's
    ``AerostructPoint`` built from its public components (Jasa et al. 2018): ``coupled`` (per
    surface a :class:`WingmdaoCoupledAS` and a ``LoadTransfer``, one ``VLMStates``; NonlinearBlockGS
    with Aitken, DirectSolver), ``<surface>_perf`` (``CoupledPerformance``: CL, CD, stress
    failure) and ``total_perf`` (``TotalPerformance``: L = W, Breguet fuel burn, CM). Same
    variable names as ``AerostructPoint``, so OpenAeroStruct's problem scripts connect to it
    unchanged except for the structural inputs (module docstring)."""

    def initialize(self):
        self.options.declare("surfaces", types=list, desc="OpenAeroStruct wingbox surface dicts")
        self.options.declare("user_specified_Sref", types=bool, default=False,
                             desc="reference area S_ref_total given as an input (else the sum of the surfaces)")
        self.options.declare("internally_connect_fuelburn", types=bool, default=True,
                             desc="fuel burn of this point feeds its own L = W and CG")
        self.options.declare("compressible", types=bool, default=False,
                             desc="Prandtl-Glauert compressibility correction of the VLM")

    def setup(self):
        from openaerostruct.functionals.total_performance import TotalPerformance
        from openaerostruct.integration.aerostruct_groups import CoupledPerformance

        surfaces = self.options["surfaces"]
        for s in surfaces:
            check_surface(s)
        flight = ["v", "alpha", "beta", "rho"] + (["Mach_number"] if self.options["compressible"] else [])
        self.add_subsystem("coupled", self._coupled_group(surfaces, flight), promotes_inputs=flight)
        for s in surfaces:
            self.add_subsystem(f"{s['name']}_perf", CoupledPerformance(surface=s), promotes_inputs=list(_PERF_INPUTS))
        self.add_subsystem("total_perf", TotalPerformance(
            surfaces=surfaces, user_specified_Sref=self.options["user_specified_Sref"],
            internally_connect_fuelburn=self.options["internally_connect_fuelburn"]),
            promotes_inputs=list(_TOTAL_INPUTS), promotes_outputs=list(_TOTAL_OUTPUTS))
        for s in surfaces:
            self._connect_performance(s["name"])

    def _coupled_group(self, surfaces, flight):
        """The coupled loop: surfaces, one VLM solve, load transfers; OpenAeroStruct's solver settings."""
        from openaerostruct.aerodynamics.compressible_states import CompressibleVLMStates
        from openaerostruct.aerodynamics.states import VLMStates
        from openaerostruct.transfer.load_transfer import LoadTransfer

        g = om.Group()
        for s in surfaces:
            g.add_subsystem(s["name"], WingmdaoCoupledAS(surface=s))
        states = CompressibleVLMStates if self.options["compressible"] else VLMStates
        g.add_subsystem("aero_states", states(surfaces=surfaces), promotes_inputs=flight)
        for s in surfaces:
            name = s["name"]
            g.add_subsystem(f"{name}_loads", LoadTransfer(surface=s))
            g.connect(f"{name}_loads.loads", f"{name}.loads")
            g.connect(f"{name}.normals", f"aero_states.{name}_normals")
            g.connect(f"{name}.def_mesh", f"aero_states.{name}_def_mesh")
            g.connect(f"{name}.def_mesh", f"{name}_loads.def_mesh")
            g.connect(f"aero_states.{name}_sec_forces", f"{name}_loads.sec_forces")
        g.nonlinear_solver = om.NonlinearBlockGS(use_aitken=True, maxiter=100, atol=1e-7, rtol=1e-30, iprint=2,
                                                 err_on_non_converge=True)
        g.linear_solver = om.DirectSolver(assemble_jac=True)
        g.options["assembled_jac_type"] = "csc"
        return g

    def _connect_performance(self, name):
        forces = f"coupled.aero_states.{name}_sec_forces"
        self.connect(forces, f"{name}_perf.sec_forces")
        self.connect(forces, f"total_perf.{name}_sec_forces")
        for k in ("CL", "CD"):
            self.connect(f"{name}_perf.{k}", f"total_perf.{name}_{k}")
        for src, tgt in _TO_PERF.items():
            self.connect(f"coupled.{name}.{src}", f"{name}_perf.{tgt}")
        for k in _TO_TOTAL:
            self.connect(f"coupled.{name}.{k}", f"total_perf.{name}_{k}")


def wingmdao_aerostruct_point(**options):
    """``WingmdaoAerostructPoint(**options)`` (kept for scripts written against the factory).

    Parameters
    ----------
    **options
        Options of :class:`WingmdaoAerostructPoint`.

    Returns
    -------
    WingmdaoAerostructPoint
        The point group.
    """
    return WingmdaoAerostructPoint(**options)
