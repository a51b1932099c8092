"""Stiffened-panel numerics: laminate stiffness, plate/column/crippling formulas, panel checks.

* :mod:`wingmdao.panels.laminate`: ply materials, smeared laminate A and D (ply fractions);
* :mod:`wingmdao.panels.buckling`: one function per buckling/crippling formula;
* :mod:`wingmdao.panels.stiffened`: skin with blade or T stiffeners, critical running loads and
  load-linear failure ratios; the ``wingmdao panel`` command uses :func:`panel_analysis`.

Every function taking dimensions or loads is plain arithmetic, so it evaluates on floats, numpy
arrays and CasADi ``SX`` symbols. See docs/panels.md.
"""
