"""Geometrically nonlinear Timoshenko beam of App. A (ASWING form).

* :mod:`wingmdao.beam.rotations` - Euler-angle frames T(theta) and the rate/curvature matrix K;
* :mod:`wingmdao.beam.residual` - ``build_beam_system(num_nodes)``: the 18-unknowns-per-node
  CasADi residual system, ``jig_state``, ``unpack_state``;
* :mod:`wingmdao.beam.static` - ``beam_parameters``, ``beam_forcing``, ``BeamModel`` (statics);
* :mod:`wingmdao.beam.geometry` - straight, swept, dihedral, tapered multi-segment beams;
* :mod:`wingmdao.beam.joints` - several beams joined at nodes (rigid joints, hinges) as one
  residual system, with lumped masses, symmetry conditions of a free half aircraft, inertia
  relief and monitoring-station loads (docs/stick-model.md).

Derivations: docs/beam-theory.md.
"""
