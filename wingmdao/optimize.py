"""Optimizer selection and recording shared by every sizing case.

``pyoptsparse`` is not installable from the package registry on every machine, so the
driver falls back to SciPy's SLSQP through :class:`openmdao.api.ScipyOptimizeDriver` when
``pyoptsparse`` does not import, and IPOPT runs through ``cyipopt``
(:class:`wingmdao.drivers.ipopt.IpoptDriver`) when ``cyipopt`` imports. The choice is reported
in the results (``driver`` key).
Every run records to SQLite so no iteration is lost.

A design the analysis cannot solve (a beam whose Newton solve does not converge raises
``om.AnalysisError``) does not end a SciPy run: :class:`BackoffSLSQPDriver` answers SLSQP's line
search with a penalised objective so the step is shortened, records the failed evaluation, and
after ``max_failures`` consecutive failures stops with ``success = False`` at the last design
that was solved. pyOptSparse does the same natively (an AnalysisError becomes ``fail = 1``).
"""

from __future__ import annotations

import importlib.util
import sqlite3
import sys
import time

import numpy as np
import openmdao.api as om
from openmdao.recorders.case_recorder import CaseRecorder
from scipy.optimize import OptimizeResult

from wingmdao.drivers.failures import RecordsFailedAnalyses, one_line
from wingmdao.drivers.ipopt import IpoptDriver, cyipopt_available

PYOPTSPARSE_OPTIMIZERS = ("SNOPT", "IPOPT", "SLSQP")


#: IPOPT options :func:`make_driver` gives :class:`~wingmdao.drivers.ipopt.IpoptDriver` for sizing.
#: With IPOPT's defaults (6 quasi-Newton pairs, initial Hessian scaled by s'y/s's) the PEGASUS
#: maneuver sizing (76 thicknesses, 2 KS constraints, objective mass/ref ~ 0.035) wanders between
#: 280 and 580 kg for 200 iterations; a history as long as the design vector and a constant initial
#: Hessian 3 I bring it to the SLSQP mass (344.97 kg, KS <= 0) within 200 iterations.
IPOPT_SIZING_SETTINGS = {
    "limited_memory_max_history": 100,
    "limited_memory_initialization": "constant",
    "limited_memory_init_val": 3.0,
}


def pyoptsparse_available() -> bool:
    """True when ``pyoptsparse`` can be imported."""
    return importlib.util.find_spec("pyoptsparse") is not None


def make_driver(optimizer: str = "SLSQP", *, maxiter: int = 200, tol: float = 1e-6,
                prefer_pyoptsparse: bool = True, disp: bool = True):
    """Return ``(driver, description)`` for ``optimizer``.

    With pyoptsparse importable and ``prefer_pyoptsparse``, an ``om.pyOptSparseDriver``
    running ``optimizer`` (SNOPT, IPOPT or SLSQP); otherwise, for IPOPT,
    :class:`wingmdao.drivers.ipopt.IpoptDriver` when ``cyipopt`` imports (the ``ipopt`` extra),
    and for SLSQP ``om.ScipyOptimizeDriver`` with SLSQP (the only gradient-based SciPy method
    that handles our inequality constraints and bounds well). Raises ``ValueError`` for an
    unknown optimizer name, or one that nothing installed here can run.

    Parameters
    ----------
    optimizer : {"SLSQP", "IPOPT", "SNOPT"}, optional
        Optimizer name.
    maxiter : int, optional
        Iteration limit.
    tol : float, optional
        Convergence tolerance.
    prefer_pyoptsparse : bool, optional
        Use pyOptSparse when it imports.
    disp : bool, optional
        Print the optimizer's summary.

    Returns
    -------
    tuple
        (driver, description).
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
    if name == "IPOPT":
        if cyipopt_available():
            driver = IpoptDriver(max_iter=maxiter, tol=tol, disp=disp)
            driver.opt_settings.update(IPOPT_SIZING_SETTINGS)
            return driver, "IpoptDriver/IPOPT (cyipopt)"
        raise ValueError("optimizer IPOPT needs pyoptsparse or cyipopt, and neither imports here; "
                         "install the ipopt extra (pip install wingmdao[ipopt]) or use SLSQP")
    if name != "SLSQP":
        raise ValueError(f"optimizer {name} needs pyoptsparse, which does not import here; use SLSQP")
    driver = BackoffSLSQPDriver(maxiter=maxiter, tol=tol, disp=disp)
    return driver, "ScipyOptimizeDriver/SLSQP"


class _StopBackoff(Exception):
    """Ends an SLSQP run from inside a callback (caught by :meth:`BackoffSLSQPDriver.run`)."""


class BackoffSLSQPDriver(RecordsFailedAnalyses, om.ScipyOptimizeDriver):
    """SciPy SLSQP that backs off from designs the analysis cannot solve.

    While SLSQP runs, an ``om.AnalysisError`` raised by the model is not re-raised (as
    ``om.ScipyOptimizeDriver`` does, ending the run): the objective is returned as the last
    solved value plus ``failure_penalty`` (times ``max(1, |f|)``) and the constraints as their last
    solved values. SLSQP's L1-merit line search (D. Kraft, "A software package for sequential
    quadratic programming", DFVLR-FB 88-28, 1988; SciPy's implementation: alpha <- max(h3 / (2 (h3 -
    h1)), 0.1) while the merit does not decrease, at most 10 times) then shortens the step tenfold per
    failure, back towards the accepted design. Each failure is recorded (the recorded case has
    ``success = 0`` and the error as ``msg``) and listed in :attr:`failed_evaluations`. After
    ``max_failures`` consecutive failures, or when SLSQP asks for derivatives at a design that
    was not solved, the run stops: :attr:`fail` is True, :attr:`stop_message` says why, and the
    model is left at (and the last recorded case is) the last solved design. A failure of the
    initial design is raised as before (there is nothing to back off to).

    Parameters
    ----------
    **kwargs
        Driver options (``om.ScipyOptimizeDriver``'s and ``failure_penalty``).
    """

    def __init__(self, **kwargs):
        super().__init__(optimizer="SLSQP", **kwargs)
        self.failed_evaluations = []
        self.stop_message = None
        self._failure = None  # AnalysisError of the latest model evaluation
        self._backing_off = False  # True inside SLSQP's callbacks
        self._good = None  # (x, f) of the latest solved evaluation
        self._good_cons = {}
        self._consecutive = 0
        self._gradients = 0

    def _declare_options(self):
        super()._declare_options()
        self.options.declare("max_failures", default=10, types=int, lower=1,
                             desc="consecutive failed analyses (om.AnalysisError) after which the run stops "
                                  "at the last solved design")
        self.options.declare("failure_penalty", default=1e6, types=float, lower=0.0,
                             desc="added to the last solved objective (times max(1, |f|)) at a design whose "
                                  "analysis failed, so that SLSQP's line search shortens the step")

    # -- OpenMDAO hooks -------------------------------------------------------------------------
    def run(self):
        """Run SLSQP with back-off; returns the failure flag (True: not converged or stopped)."""
        self.failed_evaluations, self.stop_message = [], None
        self._failure, self._good, self._good_cons = None, None, {}
        self._consecutive = self._gradients = 0
        try:
            fail = super().run()
        except _StopBackoff as stop:
            self.stop_message = str(stop)
            fail = self.fail = True
            print(f"Optimization FAILED.\n{self.stop_message}\n" + "-" * 35)
        if self._failure is not None and self._good is not None:
            self._objfunc(self._good[0])  # leave the model (and the last recorded case) at a solved design
        return fail

    @property
    def optimize_result(self):
        """``scipy.optimize.OptimizeResult`` of the latest run; when the back-off stopped it:
        ``success = False``, ``message`` = :attr:`stop_message`, ``nit`` = gradient evaluations."""
        if self.stop_message is None:
            return self._scipy_optimize_result  # documented attribute of om.ScipyOptimizeDriver
        x = None if self._good is None else self._good[0]
        return OptimizeResult(success=False, status=-1, message=self.stop_message, nit=self._gradients, x=x)

    def _run_solve_nonlinear(self):
        self._failure = None
        try:
            return super()._run_solve_nonlinear()
        except om.AnalysisError as exc:
            if not self._backing_off:
                raise
            self._failure = exc

    # -- SLSQP callbacks ------------------------------------------------------------------------
    def _objfunc(self, x_new):
        self._backing_off = True
        try:
            f = super()._objfunc(x_new)
        finally:
            self._backing_off = False
        if self._failure is None:
            self._good, self._consecutive = (np.array(x_new, dtype=float), f), 0
            return f
        self._consecutive += 1
        self.failed_evaluations.append({
            "evaluation": int(self.iter_count), "message": one_line(self._failure),
            "design_vars": {k: np.asarray(v).tolist()
                            for k, v in self.get_design_var_values(driver_scaling=False).items()}})
        if self._good is None:  # cannot happen after a solved initial run; be safe
            raise _StopBackoff(f"the analysis failed at the first SLSQP design: {one_line(self._failure)}")
        if self._consecutive >= self.options["max_failures"]:
            raise _StopBackoff(
                f"stopped after {self._consecutive} consecutive failed analyses (SLSQP shortened its step "
                f"{self._consecutive} times from the last solved design); last error: {one_line(self._failure)}")
        f_good = float(np.ravel(self._good[1])[0])
        return f_good + self.options["failure_penalty"] * max(1.0, abs(f_good))

    def _confunc(self, x_new, name, dbl, idx):
        key = (name, bool(dbl), int(idx))
        if self._failure is not None:
            return self._good_cons.get(key, 0.0)
        value = super()._confunc(x_new, name, dbl, idx)
        self._good_cons[key] = value
        return value

    def _gradfunc(self, x_new):
        if self._failure is not None:
            raise _StopBackoff(
                f"SLSQP accepted a design whose analysis failed after {self._consecutive} shortened steps "
                f"and asked for its derivatives; last error: {one_line(self._failure)}")
        self._gradients += 1
        return super()._gradfunc(x_new)


class WalSqliteRecorder(om.SqliteRecorder):
    """``om.SqliteRecorder`` whose database is written in SQLite's write-ahead-log mode.

    ``om.SqliteRecorder`` commits every record; in SQLite's default rollback-journal mode each
    commit syncs the journal and the database to disk (here 22 ms per commit on a busy disk,
    ~240 commits = 5 s of a 20 s PEGASUS gust sizing). With ``journal_mode=WAL`` and
    ``synchronous=NORMAL`` (https://www.sqlite.org/wal.html, https://www.sqlite.org/pragma.html
    #pragma_synchronous) a commit appends to the log without a sync (0.02 ms): every commit is
    still atomic and survives a crash of the process (the log is replayed when the file is next
    opened); only a power loss or OS crash may drop the latest commits, never corrupt the file.
    :meth:`shutdown` checkpoints the log into the database and switches it back to the default
    journal mode, so the closed recording is one ordinary SQLite file.
    """

    PRAGMAS = ("PRAGMA journal_mode=WAL", "PRAGMA synchronous=NORMAL")

    def startup(self, recording_requester, comm=None):
        super().startup(recording_requester, comm)
        for con in self._connections():
            for pragma in self.PRAGMAS:
                con.execute(pragma)

    def shutdown(self):
        for con in self._connections():
            try:  # checkpoints the log and removes the -wal file
                con.execute("PRAGMA journal_mode=DELETE")
            except sqlite3.Error:  # closed already, or another reader holds the file: it stays WAL (valid)
                pass
        super().shutdown()

    def _connections(self):
        return [c for c in dict.fromkeys((self.connection, self.metadata_connection)) if c is not None]


def add_recorder(prob: om.Problem, path: str) -> om.SqliteRecorder:
    """Record design variables, objectives, constraints and derivatives of every driver iteration
    (:class:`WalSqliteRecorder`: no disk sync per record).

    Parameters
    ----------
    prob : openmdao.api.Problem
        The problem, its driver already set.
    path : str
        SQLite file to record into.

    Returns
    -------
    WalSqliteRecorder
        The recorder.
    """
    rec = WalSqliteRecorder(path)
    opts = prob.driver.recording_options
    opts["record_desvars"] = True
    opts["record_objectives"] = True
    opts["record_constraints"] = True
    opts["record_derivatives"] = True
    prob.driver.add_recorder(rec)
    return rec


class _ListeningRecorder(CaseRecorder):
    """A CaseRecorder that stores nothing: every recording hook is a no-op; subclasses override
    the hooks they listen to (a driver's or a solver's iterations)."""

    def record_iteration_driver(self, recording_requester, data, metadata):  # pragma: no cover
        pass

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


class ProgressPrinter(_ListeningRecorder):
    """Prints one line per driver evaluation: objective, worst constraint, elapsed time.

    Long optimizations (a gust sizing takes minutes) then show their progress as they run.

    Parameters
    ----------
    stream : file-like or None, optional
        Output stream; None for standard output.
    objective : str, optional
        Objective name printed.
    units : str, optional
        Objective units printed.
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
        if not metadata.get("success", 1):  # BackoffSLSQPDriver: the analysis failed, SLSQP backs off
            print(f"  eval {self._count:4d}  {metadata.get('msg', 'analysis failed')} (backing off)  "
                  f"{self._clock() - self._t0:7.1f} s", file=self._stream, flush=True)
            return
        obj_txt = f"{float(np.ravel(obj)[0]):12.4f} {self._units}" if obj is not None else ""
        con_txt = f"max KS {max(cons):+.3e}" if cons else ""
        print(f"  eval {self._count:4d}  {self._objective} {obj_txt}  {con_txt}  "
              f"{self._clock() - self._t0:7.1f} s", file=self._stream, flush=True)


class SolverIterationCounter(_ListeningRecorder):
    """Iterations of the last solve of each watched nonlinear solver, through OpenMDAO's public
    recording hooks: every solver iteration calls ``record_iteration_solver``; a driver
    evaluation (``record_iteration_driver``) or :meth:`snapshot` closes the solves counted so far
    into :attr:`last` (``{name: iterations}``).

    ``solvers``: ``{name: solver}`` (set up, before ``final_setup``); attach to a driver with
    ``driver.add_recorder(counter)`` so each evaluation is counted separately. ``unrecorded``:
    iterations per solve that the solver does not record (1 for ``NonlinearBlockGS``, whose first
    Gauss-Seidel pass runs unrecorded while it computes the initial norm, and counts).

    Parameters
    ----------
    solvers : dict
        Name -> nonlinear solver to watch.
    unrecorded : int, optional
        Iterations per solve that the solver does not record.
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
