"""Independent verification models (not part of the sizing path).

* :mod:`wingmdao.verification.solid3d` - a small linear-elastic 3-D solid FE solver
  (27-node hexahedra on structured meshes, rigid-body-consistent face loads, rigid/rib tip
  couplings, section averages over cuts);
* :mod:`wingmdao.verification.wingbox_solid` - the 'wing-like' box beam of App. D.1 as a 3-D
  solid (``box_sections``, ``solve_wingbox``), an independent linear Timoshenko frame
  (``linear_beam_solution``) and the beam/solid comparison (``compare_with_beam``,
  ``comparison_markdown``, ``app_a_beam_solver``).

See docs/verification-solid3d.md.
"""
