"""Finite-element cross-checks with external solvers (CalculiX), built from the beam's own
geometry, thickness and material objects (docs/verification-calculix.md), and the decks other
tools read: CalculiX / Abaqus / Nastran structural decks (:mod:`wingmdao.fe.export`) and the
Nastran aeroelastic deck of a beam model (:mod:`wingmdao.fe.nastran_aero`, docs/nastran-export.md)."""
