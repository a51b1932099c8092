"""Finite-element cross-checks with external solvers (CalculiX), built from the beam's own
geometry, thickness and material objects (docs/verification-calculix.md)."""
