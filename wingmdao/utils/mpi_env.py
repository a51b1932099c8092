"""How many ranks the MPI launcher started, from its environment (no mpi4py or OpenMDAO import)."""

from __future__ import annotations

import os

#: Environment variables in which OpenMPI, MPICH/Hydra and PMIx launchers give the world size.
SIZE_VARS = ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE", "MPI_LOCALNRANKS")


def _first_int(names, floor: int) -> int:
    """The first of the environment variables ``names`` that holds an integer (at least ``floor``);
    ``floor`` when none does."""
    for var in names:
        try:
            return max(floor, int(os.environ[var]))
        except (KeyError, ValueError):
            continue
    return floor


def launched_ranks() -> int:
    """Number of ranks the MPI launcher reports in the environment (1 when not under mpirun)."""
    return _first_int(SIZE_VARS, 1)


#: Environment variables in which OpenMPI, MPICH/Hydra and PMIx launchers give this process's rank.
RANK_VARS = ("OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK")


def launched_rank() -> int:
    """This process's rank as the MPI launcher reports it in the environment (0 when not under mpirun)."""
    return _first_int(RANK_VARS, 0)


def is_output_rank() -> bool:
    """True in a serial run and on rank 0 under mpirun: the one process that prints and writes files."""
    return launched_ranks() <= 1 or launched_rank() == 0
