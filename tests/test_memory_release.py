"""``sizing.release_derivative_storage`` (issue 27, item 8): after a sizing, the adjoint's stored
linearizations are dropped before the flutter search; outputs stay, and a later derivative
computation linearizes again to the same totals."""

import subprocess
import sys

import numpy as np

from wingmdao import sizing
from wingmdao.cases import cantilever
from wingmdao.utils.memory import return_freed_memory


def test_release_keeps_outputs_and_totals():
    setup = cantilever.build(load="step", stations=5, t_final=0.1, dt=0.01)
    prob, _ = sizing.build_problem(setup.geometry, setup.load_cases, setup.material, setup.options,
                                   driver=True, section=setup.section)
    prob.run_model()
    before = prob.compute_totals()
    outputs = prob.model._outputs.asarray().copy()
    stored = [s for s in prob.model.system_iter(recurse=True) if getattr(s, "_lin", None) is not None]
    assert stored  # the time history kept its linearization for reuse
    assert sizing.release_derivative_storage(prob) >= len(stored)
    assert all(s._lin is None for s in stored)
    assert np.array_equal(prob.model._outputs.asarray(), outputs)
    after = prob.compute_totals()
    for key, val in before.items():
        assert np.allclose(after[key], val, rtol=1e-12, atol=0), key
    prob.cleanup()


def test_return_freed_memory_is_safe_to_call():
    assert return_freed_memory() in (True, False)


def _one_case_totals():
    setup = cantilever.build(load="step", stations=5, t_final=0.1, dt=0.01)
    prob, _ = sizing.build_problem(setup.geometry, setup.load_cases, setup.material, setup.options,
                                   driver=True, section=setup.section)
    prob.run_model()
    totals = prob.compute_totals()
    solver = prob.model.cases.linear_solver
    prob.cleanup()
    return totals, solver


def test_one_case_group_solves_without_a_copy_of_its_vector(monkeypatch):
    """The ``cases`` group of a one-case model solves in reverse without LinearRunOnce's copy of its
    derivative vector (a whole history per case), to the same totals, bit for bit."""
    import openmdao.api as om

    import wingmdao.groups.wing as wing
    from wingmdao.groups.single_subsystem import SingleSubsystemRunOnce

    lean, solver = _one_case_totals()
    assert isinstance(solver, SingleSubsystemRunOnce) and solver._rhs_vec is None
    monkeypatch.setattr(wing, "SingleSubsystemRunOnce", om.LinearRunOnce)
    plain, solver = _one_case_totals()
    assert solver._rhs_vec is not None  # LinearRunOnce keeps the copy
    assert lean.keys() == plain.keys()
    for key, val in plain.items():
        assert np.array_equal(lean[key], val), key


def test_size_command_frees_its_problem():
    """OpenMDAO keeps the traceback of its failed optional jax import as module globals; imported
    first inside the sizing run, it kept the run's frames, and the problem (~300 MB on the PEGASUS
    gust), alive until the process ended. A fresh process: no Problem left after the command."""
    import os
    import subprocess
    import sys
    import tempfile

    code = ("import gc, sys\n"
            "from wingmdao.cli import main\n"
            "assert 'openmdao.api' not in sys.modules\n"  # (the dispatcher has AnalysisError's module only)
            "main(['size', 'cantilever', '--stations', '5', '--quiet', '--no-plots', '--out', sys.argv[1]])\n"
            "import openmdao.api as om\n"
            "gc.collect()\n"
            "print(sum(isinstance(o, om.Problem) for o in gc.get_objects()))\n")
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with tempfile.TemporaryDirectory() as out:
        proc = subprocess.run([sys.executable, "-c", code, out], capture_output=True, text=True,
                              env={**os.environ, "PYTHONPATH": root})
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.strip().splitlines()[-1] == "0"


def test_large_blocks_setting_leaves_the_users_choice(monkeypatch):
    from wingmdao.utils.memory import return_large_blocks_on_free

    monkeypatch.setenv("MALLOC_MMAP_THRESHOLD_", "1048576")
    assert return_large_blocks_on_free() is False
    monkeypatch.delenv("MALLOC_MMAP_THRESHOLD_")
    assert return_large_blocks_on_free() in (True, False)  # False without glibc


_LEAN_IMPORT = """
import sys
from wingmdao.utils.memory import import_openmdao_without_plot_plugins
assert import_openmdao_without_plot_plugins()
import openmdao.api as om
prob = om.Problem(reports=False)
prob.model.add_subsystem("c", om.ExecComp("y = (x - 3) ** 2"), promotes=["*"])
prob.model.add_design_var("x", lower=-10, upper=10)
prob.model.add_objective("y")
prob.driver = om.ScipyOptimizeDriver(optimizer="SLSQP", disp=False)
prob.setup()
prob.run_driver()
print("matplotlib" in sys.modules, round(float(prob.get_val("x")[0]), 6))
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
plt.figure()
print("matplotlib" in sys.modules, import_openmdao_without_plot_plugins())
"""


def test_openmdao_without_plot_plugins():
    """The command's OpenMDAO import loads no matplotlib (~30 MB): an optimization runs without it,
    and a plot drawn afterwards imports it as usual; a second call changes nothing."""
    out = subprocess.run([sys.executable, "-c", _LEAN_IMPORT], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "3.0", "True", "False"], out.stdout + out.stderr


def test_openmdao_lean_import_leaves_a_loaded_openmdao_alone():
    from wingmdao.utils.memory import import_openmdao_without_plot_plugins

    import openmdao.api  # noqa: F401  (this test process has it already)

    assert import_openmdao_without_plot_plugins() is False
