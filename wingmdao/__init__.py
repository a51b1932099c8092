"""wingmdao: wingbox sizing for dynamic certification loads.

The method is that of the dissertation in ``shared/reference/dissertation.txt``:
box-beam section properties (App. F), the geometrically nonlinear Timoshenko beam of
App. A marched in time with BDF2 (Eq. 3.4-3.7) and its discrete adjoint (Eq. 3.9-3.11),
stress recovery (Sec. 4.4.2) and KS aggregation over space and time (Eq. 4.53-4.55).
Conventions (axes, signs, state order, names) are in ``docs/conventions.md``.
"""

__version__ = "0.1.0"
