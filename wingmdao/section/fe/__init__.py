"""Cross-section finite-element analysis (Giavotto/BECAS formulation, dissertation Sec. 4.2, App. C).

Public API::

    from wingmdao.section.fe import (isotropic, orthotropic, anisotropic, ply_stiffness,
        rectangle_mesh, box_mesh, channel_mesh, tube_mesh, airfoil_box_mesh, airfoil_box_mesh_gmsh,
        analyse_section, recover_stresses, beam_properties_csn, match_box, box_stiffness)
"""

from .materials import isotropic, orthotropic, anisotropic, ply_stiffness
from .mesh import SectionMesh, rectangle_mesh, box_mesh, channel_mesh, tube_mesh, airfoil_box_mesh
from .gmsh_mesh import airfoil_box_mesh_gmsh
from .analysis import Section, analyse_section, analyse_sections, recover_stresses, beam_properties_csn
from .box_match import box_stiffness, match_box

__all__ = ["isotropic", "orthotropic", "anisotropic", "ply_stiffness", "SectionMesh", "rectangle_mesh",
           "box_mesh", "channel_mesh", "tube_mesh", "airfoil_box_mesh", "airfoil_box_mesh_gmsh", "Section", "analyse_section", "analyse_sections",
           "recover_stresses", "beam_properties_csn", "box_stiffness", "match_box"]
