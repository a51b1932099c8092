"""Stress recovery of box sections (Sec. 4.4.2): plain functions for numpy and CasADi."""

from wingmdao.stress.box_stress import FAMILIES, box_stresses, stress_constraints

__all__ = ["FAMILIES", "box_stresses", "stress_constraints"]
