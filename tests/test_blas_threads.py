"""The command line runs with one BLAS thread unless the user chose a count (wingmdao.utils.threads)."""

import os
import subprocess
import sys

from wingmdao.utils.threads import BLAS_THREAD_VARIABLES

PROBE = ("import os, wingmdao.cli, numpy; "
         f"print(','.join(os.environ.get(v, '-') for v in {BLAS_THREAD_VARIABLES!r}))")


def _cli_environment(**chosen):
    env = {k: v for k, v in os.environ.items() if k not in BLAS_THREAD_VARIABLES}
    env.update(chosen)
    return subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True, text=True,
                          check=True).stdout.strip().split(",")


def test_cli_asks_for_one_blas_thread():
    assert _cli_environment() == ["1"] * len(BLAS_THREAD_VARIABLES)


def test_cli_keeps_the_users_thread_count():
    got = _cli_environment(OPENBLAS_NUM_THREADS="3")
    assert got[BLAS_THREAD_VARIABLES.index("OPENBLAS_NUM_THREADS")] == "3"
    assert got[BLAS_THREAD_VARIABLES.index("OMP_NUM_THREADS")] == "-"
