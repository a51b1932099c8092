"""OpenAeroStruct aerostructural point with the wingmdao beam as its structural solver.

``WingmdaoAerostructPoint`` is OpenAeroStruct's ``AerostructPoint`` whose per-surface coupled
group solves the wingmdao nonlinear box beam (:class:`~wingmdao.oas.coupling.OASBeamStates`)
instead of the linear spatial beam. Differences to connect: instead of
``coupled.<surface>.local_stiff_transformed`` connect ``coupled.<surface>.spar_thickness``,
``skin_thickness``, ``htop``, ``hbottom``, ``hfront``, ``hrear`` (from the same outputs of
``AerostructGeometry``): the box of each element is OpenAeroStruct's own (width hfront + hrear,
height htop + hbottom) when the surface has ``wingmdao_box = "oas"``, so both beams see nearly
the same section (htop and hbottom are OpenAeroStruct's KS-smoothed maxima, slightly above the
true box height: 2.3 % stiffer on the rectangular test wing). Default (``"surface"``): the box
from the surface dict (``box_geometry_from_surface``), exact for flat-topped "airfoils". Still connect ``coupled.<surface>.nodes`` and ``coupled.<surface>.mesh``
(the displacement transfer uses them). The beam's jig axis (nodes at ``fem_origin``) is fixed
when the point is set up; weight relief, fuel and point
masses are not applied to our beam (surfaces must have ``struct_weight_relief`` and
``distributed_fuel_weight`` False and no ``n_point_masses``).
"""

from __future__ import annotations

import numpy as np


def box_geometry_from_surface(surface):
    """(fem_nodes (ny, 3), width (ny-1,), height (ny-1,)) in m from an OpenAeroStruct wingbox
    surface dict: nodes at ``fem_origin`` of the chord (OpenAeroStruct's rule), width = spar
    spacing, height = mean of the front and rear spar heights scaled to the element t/c."""
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


def _coupled_as_class():
    from openaerostruct.integration.aerostruct_groups import CoupledAS
    from openaerostruct.aerodynamics.geometry import VLMGeometry
    from openaerostruct.transfer.displacement_transfer_group import DisplacementTransferGroup

    from wingmdao.oas.coupling import OASBeamStates

    class WingmdaoCoupledAS(CoupledAS):
        """CoupledAS with the wingmdao beam in ``struct_states``."""

        def setup(self):
            surface = self.options["surface"]
            for key in ("struct_weight_relief", "distributed_fuel_weight"):
                if surface.get(key, False):
                    raise ValueError(f"WingmdaoAerostructPoint: surface['{key}'] = True is not supported; set False")
            if "n_point_masses" in surface:
                raise ValueError("WingmdaoAerostructPoint: point masses (n_point_masses) are not supported")
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
                               promotes_outputs=["b_pts", "widths", "lengths_spanwise", "lengths", "chords",
                                                 "normals", "S_ref"])

    return WingmdaoCoupledAS


def wingmdao_aerostruct_point(**options):
    """An ``AerostructPoint(**options)`` whose coupled surfaces use the wingmdao beam. Each surface
    dict needs ``wingmdao_material`` (a :class:`wingmdao.materials.Material`)."""
    from openaerostruct.integration.aerostruct_groups import AerostructPoint

    coupled_cls = _coupled_as_class()

    class WingmdaoAerostructPoint(AerostructPoint):
        def setup(self):
            super().setup()
            coupled = self._static_subsystems_allprocs.get("coupled") or self._subsystems_allprocs.get("coupled")
            coupled = coupled.system
            for s in self.options["surfaces"]:
                info = coupled._static_subsystems_allprocs.get(s["name"]) or coupled._subsystems_allprocs[s["name"]]
                info.system.__class__ = coupled_cls

    return WingmdaoAerostructPoint(**options)
