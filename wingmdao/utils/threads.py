"""The BLAS thread count of the command line and the test suite.

wingmdao's dense linear algebra works on small matrices (ARPACK's Krylov bases in the flutter
search, the 6x6 section blocks, Jacobian blocks of a few hundred rows). OpenBLAS threads do not
speed such products up and, when two processes (MPI ranks, pytest-xdist workers) share a 2-core
machine, their spinning threads cost several times the work itself: the PEGASUS flutter search
takes about half the CPU time with one BLAS thread (``docs/performance.md``). The ``wingmdao``
command therefore asks for one BLAS thread unless the user chose a count. OpenBLAS reads the
variables when NumPy loads, so this must run before NumPy is imported.
"""

from __future__ import annotations

import os
import sys

#: the variables that set the thread count of OpenBLAS, MKL and OpenMP-threaded BLAS
BLAS_THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def single_blas_thread_default() -> bool:
    """Set every variable of :data:`BLAS_THREAD_VARIABLES` to ``1`` unless the user set any of them.

    Returns
    -------
    bool
        True when the variables were set; False when the user chose a count (any of them is set)
        or NumPy is already loaded (too late to take effect, so nothing is changed).
    """
    if "numpy" in sys.modules or any(name in os.environ for name in BLAS_THREAD_VARIABLES):
        return False
    for name in BLAS_THREAD_VARIABLES:
        os.environ[name] = "1"
    return True
