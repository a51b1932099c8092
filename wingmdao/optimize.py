"""Optimizer selection and recording shared by every sizing case.

``pyoptsparse`` is not installable from the package registry on every machine, so the
driver falls back to SciPy's SLSQP through :class:`openmdao.api.ScipyOptimizeDriver` when
``pyoptsparse`` does not import. The choice is reported in the results (``driver`` key).
Every run records to SQLite so no iteration is lost.
"""

from __future__ import annotations

import importlib.util

import sys
import time

import numpy as np
import openmdao.api as om
from openmdao.recorders.case_recorder import CaseRecorder

PYOPTSPARSE_OPTIMIZERS = ("SNOPT", "IPOPT", "SLSQP")


def pyoptsparse_available() -> bool:
    """True when ``pyoptsparse`` can be imported."""
    return importlib.util.find_spec("pyoptsparse") is not None


def make_driver(optimizer: str = "SLSQP", *, maxiter: int = 200, tol: float = 1e-6,
                prefer_pyoptsparse: bool = True, disp: bool = True):
    """Return ``(driver, description)`` for ``optimizer``.

    With pyoptsparse importable and ``prefer_pyoptsparse``, an ``om.pyOptSparseDriver``
    running ``optimizer`` (SNOPT, IPOPT or SLSQP); otherwise ``om.ScipyOptimizeDriver`` with
    SLSQP (the only gradient-based SciPy method that handles our inequality constraints and
    bounds well). Raises ``ValueError`` for an unknown optimizer name.
    """
    name = optimizer.upper()
    if name not in PYOPTSPARSE_OPTIMIZERS:
        raise ValueError(f"optimizer must be one of {', '.join(PYOPTSPARSE_OPTIMIZERS)}, got {optimizer!r}")
    if prefer_pyoptsparse and pyoptsparse_available():
        driver = om.pyOptSparseDriver(optimizer=name, print_results=disp)
        if name == "SNOPT":
            driver.opt_settings["Major iterations limit"] = maxiter
            driver.opt_settings["Major optimality tolerance"] = tol
        elif name == "IPOPT":
            driver.opt_settings["max_iter"] = maxiter
            driver.opt_settings["tol"] = tol
        else:
            driver.opt_settings["MAXIT"] = maxiter
            driver.opt_settings["ACC"] = tol
        return driver, f"pyOptSparseDriver/{name}"
    if name != "SLSQP":
        raise ValueError(f"optimizer {name} needs pyoptsparse, which does not import here; use SLSQP")
    driver = om.ScipyOptimizeDriver(optimizer="SLSQP", maxiter=maxiter, tol=tol, disp=disp)
    return driver, "ScipyOptimizeDriver/SLSQP"


def add_recorder(prob: om.Problem, path: str) -> om.SqliteRecorder:
    """Record design variables, objectives, constraints and derivatives of every driver iteration."""
    rec = om.SqliteRecorder(path)
    opts = prob.driver.recording_options
    opts["record_desvars"] = True
    opts["record_objectives"] = True
    opts["record_constraints"] = True
    opts["record_derivatives"] = True
    prob.driver.add_recorder(rec)
    return rec


class ProgressPrinter(CaseRecorder):
    """Prints one line per driver evaluation: objective, worst constraint, elapsed time.

    Long optimizations (a gust sizing takes minutes) then show their progress as they run.
    """

    def __init__(self, stream=None, objective="mass", units="kg"):
        super().__init__(record_viewer_data=False)

        self._stream = stream or sys.stdout
        self._t0 = time.perf_counter()
        self._clock = time.perf_counter
        self._objective, self._units = objective, units
        self._count = 0

    def startup(self, recording_requester, comm=None):
        super().startup(recording_requester, comm)
        self._t0 = self._clock()

    def record_iteration_driver(self, recording_requester, data, metadata):
        out = data.get("output") or data.get("out") or {}
        obj = next((v for k, v in out.items() if k.endswith(self._objective)), None)
        cons = [float(np.max(v)) for k, v in out.items() if ".ks_" in k or k.startswith("ks_")]
        self._count += 1
        obj_txt = f"{float(np.ravel(obj)[0]):12.4f} {self._units}" if obj is not None else ""
        con_txt = f"max KS {max(cons):+.3e}" if cons else ""
        print(f"  eval {self._count:4d}  {self._objective} {obj_txt}  {con_txt}  "
              f"{self._clock() - self._t0:7.1f} s", file=self._stream, flush=True)

    def record_iteration_system(self, recording_requester, data, metadata):  # pragma: no cover
        pass

    def record_iteration_solver(self, recording_requester, data, metadata):  # pragma: no cover
        pass

    def record_iteration_problem(self, recording_requester, data, metadata):  # pragma: no cover
        pass

    def record_derivatives_driver(self, recording_requester, data, metadata):  # pragma: no cover
        pass

    def record_metadata_system(self, system, run_number=None):  # pragma: no cover
        pass

    def record_metadata_solver(self, solver, run_number=None):  # pragma: no cover
        pass

    def record_viewer_data(self, model_viewer_data):  # pragma: no cover
        pass


class SolverIterationCounter(CaseRecorder):
    """Iterations of the last solve of each watched nonlinear solver, through OpenMDAO's public
    recording hooks: every solver iteration calls ``record_iteration_solver``; a driver
    evaluation (``record_iteration_driver``) or :meth:`snapshot` closes the solves counted so far
    into :attr:`last` (``{name: iterations}``).

    ``solvers``: ``{name: solver}`` (set up, before ``final_setup``); attach to a driver with
    ``driver.add_recorder(counter)`` so each evaluation is counted separately. ``unrecorded``:
    iterations per solve that the solver does not record (1 for ``NonlinearBlockGS``, whose first
    Gauss-Seidel pass runs unrecorded while it computes the initial norm, and counts).
    """

    def __init__(self, solvers: dict, unrecorded: int = 0):
        super().__init__(record_viewer_data=False)
        self._unrecorded = int(unrecorded)
        self._names = {id(s): name for name, s in solvers.items()}
        self._running = dict.fromkeys(solvers, 0)
        self.last = dict.fromkeys(solvers, 0)
        for solver in solvers.values():
            solver.recording_options["record_inputs"] = False
            solver.recording_options["record_outputs"] = False
            solver.add_recorder(self)

    def snapshot(self) -> dict:
        """Close the solves counted since the last snapshot (kept as they were if none ran)."""
        if any(self._running.values()):
            self.last = {k: n + self._unrecorded if n else 0 for k, n in self._running.items()}
            self._running = dict.fromkeys(self._running, 0)
        return self.last

    def record_iteration_solver(self, recording_requester, data, metadata):
        self._running[self._names[id(recording_requester)]] += 1

    def record_iteration_driver(self, recording_requester, data, metadata):
        self.snapshot()

    def record_iteration_system(self, recording_requester, data, metadata):  # pragma: no cover
        pass

    def record_iteration_problem(self, recording_requester, data, metadata):  # pragma: no cover
        pass

    def record_derivatives_driver(self, recording_requester, data, metadata):  # pragma: no cover
        pass

    def record_metadata_system(self, system, run_number=None):  # pragma: no cover
        pass

    def record_metadata_solver(self, solver, run_number=None):  # pragma: no cover
        pass

    def record_viewer_data(self, model_viewer_data):  # pragma: no cover
        pass
