"""wingmdao: wingbox sizing for dynamic certification loads.

The method is that of *Structural analysis and optimization of aircraft wings through
dimensional reduction* (PhD dissertation, Georgia Institute of Technology, 2021):
box-beam section properties (App. F), the geometrically nonlinear Timoshenko beam of
App. A marched in time with BDF2 (Eq. 3.4-3.7) and its discrete adjoint (Eq. 3.9-3.11),
stress recovery (Sec. 4.4.2) and KS aggregation over space and time (Eq. 4.53-4.55).
Conventions (axes, signs, state order, names) are in ``docs/conventions.md``.
"""
import os

from wingmdao.utils.mpi_env import launched_ranks

__version__ = "0.1.0"

#: Citation of the method, attached to the components that implement its equations (``cite``).
DISSERTATION = ("Structural analysis and optimization of aircraft wings through dimensional reduction. "
                "PhD dissertation, Georgia Institute of Technology, 2021.")

def _mpi_environment():
    """Under ``mpirun -n P`` (P > 1) wingmdao distributes load cases itself (wingmdao.parallel) and
    runs each rank's OpenMDAO problem serially, which needs no PETSc: ``OPENMDAO_USE_MPI=0``
    unless the user set it. Must run before OpenMDAO is imported."""

    if launched_ranks() > 1:
        os.environ.setdefault("OPENMDAO_USE_MPI", "0")


_mpi_environment()
