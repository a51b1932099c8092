"""IPOPT through cyipopt as an OpenMDAO driver, without pyoptsparse.

:class:`IpoptDriver` hands IPOPT (A. Waechter, L. T. Biegler, "On the implementation of an
interior-point filter line-search algorithm for large-scale nonlinear programming", Math.
Program. 106, 2006) the problem as OpenMDAO scales it: design variables with their bounds,
one objective, inequality constraints (lower and/or upper bound), equality constraints and
linear constraints, all in driver scaling (``ref``/``ref0``/``scaler``/``adder``). Gradients
and the constraint Jacobian come from ``_compute_totals``; the Hessian of the Lagrangian is
IPOPT's limited-memory quasi-Newton approximation (``hessian_approximation =
limited-memory``), as no second derivatives exist in the model.

Jacobian structure handed to IPOPT: rows of linear constraints have the exact nonzeros of their
constant Jacobian (computed once, before IPOPT starts). Rows of nonlinear constraints are dense
over every design variable the constraint depends on according to OpenMDAO's relevance graph
(blocks of design variables it cannot depend on are left out); no entry is dropped because it
happened to be zero at the starting design.

``cyipopt`` is imported when the driver runs, never when this module is imported.
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om
from openmdao.core.driver import Driver, DriverResult, RecordingDebugging

from wingmdao.drivers.failures import RecordsFailedAnalyses, one_line

#: IPOPT return statuses counted as converged: Solve_Succeeded, Solved_To_Acceptable_Level
SUCCESS_STATUSES = (0, 1)

def cyipopt_available() -> bool:
    """True when ``cyipopt`` imports (package ``cyipopt-wheels`` or ``cyipopt``)."""
    try:
        import cyipopt  # noqa: F401
    except ImportError:
        return False
    return True

class IpoptResult(dict):
    """What the latest IPOPT run returned (attribute access, like ``scipy.optimize.OptimizeResult``):
    ``success``, ``status`` (IPOPT's return status), ``message`` (its text), ``nit`` (IPOPT
    iterations), ``x`` (scaled design vector), ``fun`` (scaled objective), ``nfev`` (model
    evaluations), ``njev`` (total-derivative evaluations), ``failed_evaluations``."""

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError as exc:
            raise AttributeError(name) from exc

class IpoptDriver(RecordsFailedAnalyses, Driver):
    """OpenMDAO driver running IPOPT through cyipopt.

    Options: ``max_iter``, ``tol``, ``print_level`` (IPOPT's own console output, 0 = none; it
    writes to the process's standard output directly), ``disp`` (one Python line per IPOPT
    iteration and a summary, through ``sys.stdout``). ``opt_settings``: a dict passed to IPOPT
    verbatim (``driver.opt_settings["mu_strategy"] = "adaptive"``); it overrides everything the
    driver sets, including ``hessian_approximation``.

    An ``om.AnalysisError`` raised by the model while IPOPT runs does not end the run: the
    evaluation is reported to IPOPT as failed (``cyipopt.CyIpoptEvaluationError``), and IPOPT
    shortens its step. The failed evaluation is recorded with ``success = 0`` and the error as
    ``msg`` and listed in :attr:`failed_evaluations`. A failure at the initial design is raised.

    After :meth:`run`: :attr:`fail`, :attr:`optimize_result` (:class:`IpoptResult`, with ``nit``
    and ``message``), ``result`` (OpenMDAO's :class:`~openmdao.core.driver.DriverResult`:
    ``iter_count``, ``model_evals``, ``deriv_evals``, ``exit_status`` = IPOPT's message); the model
    is left at IPOPT's final design.

    Parameters
    ----------
    **kwargs
        Driver options (``max_iter``, ``tol``, ``print_level``, ``disp``).
    """

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.supports["optimization"] = True
        self.supports["inequality_constraints"] = True
        self.supports["equality_constraints"] = True
        self.supports["two_sided_constraints"] = True
        self.supports["linear_constraints"] = True
        self.supports["gradients"] = True
        self.supports["multiple_objectives"] = False
        self.supports["active_set"] = False
        self.supports["integer_design_vars"] = False
        self.supports["distributed_design_vars"] = False
        self.supports["simultaneous_derivatives"] = False
        self.supports._read_only = True

        self.opt_settings = {}
        self.fail = False
        self.iter_count = 0
        self.optimize_result = None
        self.failed_evaluations = []
        self._failure = None
        self._reset_state()

    def _declare_options(self):
        self.options.declare("max_iter", default=200, types=int, lower=0, desc="IPOPT max_iter")
        self.options.declare("tol", default=1e-6, types=float, lower=0.0,
                             desc="IPOPT tol (relative convergence tolerance of the scaled problem)")
        self.options.declare("print_level", default=0, types=int, lower=0, upper=12,
                             desc="IPOPT print_level (its own output on the process's standard output)")
        self.options.declare("disp", default=True, types=bool,
                             desc="print one line per IPOPT iteration and a summary through sys.stdout")

    def _reset_state(self):
        self._x_model = None  # design vector the model was last evaluated at
        self._x_jac = None  # design vector of the cached Jacobian
        self._obj_val = None
        self._con_val = None
        self._grad = None
        self._jac_vals = None
        self._nit = 0
        self._exc_info = None

    # -- setup ----------------------------------------------------------------------------------
    def _setup_driver(self, problem):
        super()._setup_driver(problem)
        if len(self._objs) != 1:
            raise RuntimeError(f"{self.msginfo}: IpoptDriver needs exactly one objective, got {len(self._objs)}.")

    def _get_name(self):
        return "IpoptDriver"

    # -- OpenMDAO hooks -------------------------------------------------------------------------
    def run(self):
        """Run IPOPT; returns the failure flag (True: IPOPT did not converge)."""
        import cyipopt

        self.result.reset()
        self.iter_count = 0
        self.fail = False
        self.failed_evaluations = []
        self.optimize_result = None
        self._failure = None
        self._total_jac = None
        self._total_jac_linear = None
        self._reset_state()
        model = self._problem().model

        self._check_for_missing_objective()
        self._check_for_invalid_desvar_values()

        with RecordingDebugging(self._get_name(), self.iter_count, self):
            with model._relevance.nonlinear_active("iter"):
                self._run_solve_nonlinear()
            self.iter_count += 1
        if self._failure is not None:
            raise self._failure  # nothing to back off to

        self._dvlist = list(self._designvars)
        sizes = {n: m["size"] for n, m in self._designvars.items()}
        x0 = self._dv_array(self.get_design_var_values())
        n = x0.size
        if n == 0:
            raise RuntimeError("Problem has no design variables.")
        self._dv_slices, i = {}, 0
        for name in self._dvlist:
            self._dv_slices[name] = slice(i, i + sizes[name])
            i += sizes[name]

        dv_bounds = self._autoscaler.get_bounds_scaling("design_var")
        lb = np.concatenate([_bound(dv_bounds[d].lower, sizes[d], -np.inf) for d in self._dvlist])
        ub = np.concatenate([_bound(dv_bounds[d].upper, sizes[d], np.inf) for d in self._dvlist])
        lb, ub = np.minimum(lb, ub), np.maximum(lb, ub)  # a negative scaler swaps the scaled bounds

        # constraints: nonlinear first, then linear
        self._nlcons = [c for c, m in self._cons.items() if not m["linear"]]
        self._lincons = [c for c, m in self._cons.items() if m["linear"]]
        con_bounds = self._autoscaler.get_bounds_scaling("constraint")
        cl, cu, self._con_slices, r = [], [], {}, 0
        for name in self._nlcons + self._lincons:
            meta, size = self._cons[name], self._cons[name]["size"]
            b = con_bounds[name]
            if meta["equals"] is not None:
                lo = hi = _bound(b.equals, size, 0.0)
            else:
                lo, hi = _bound(b.lower, size, -np.inf), _bound(b.upper, size, np.inf)
                lo, hi = np.minimum(lo, hi), np.maximum(lo, hi)
            cl.append(lo)
            cu.append(hi)
            self._con_slices[name] = slice(r, r + size)
            r += size
        m = r
        self._n_nl = sum(self._cons[c]["size"] for c in self._nlcons)
        cl = np.concatenate(cl) if cl else np.zeros(0)
        cu = np.concatenate(cu) if cu else np.zeros(0)

        # linear constraints: Jacobian once
        self._lin_jac = None
        if self._lincons:
            self._lin_jac = np.atleast_2d(self._compute_totals(of=self._lincons, wrt=self._dvlist,
                                                               return_format="array"))
        self._of = list(self._objs) + self._nlcons
        self._store_values(x0)

        self._structure = self._jacobian_structure(n)
        rows, cols = self._structure

        nlp = cyipopt.Problem(n=int(n), m=int(m), problem_obj=_Callbacks(self, cyipopt), lb=lb, ub=ub,
                              cl=cl, cu=cu)
        settings = {"hessian_approximation": "limited-memory", "max_iter": self.options["max_iter"],
                    "tol": self.options["tol"], "print_level": self.options["print_level"], "sb": "yes"}
        settings.update(self.opt_settings)
        for key, value in settings.items():
            nlp.add_option(key, value)

        x, info = nlp.solve(x0)
        status = int(info["status"])
        message = info["status_msg"]
        if isinstance(message, bytes):
            message = message.decode()
        self.fail = status not in SUCCESS_STATUSES

        # leave the model (and the last recorded case) at IPOPT's final design
        x = np.asarray(x, dtype=float)
        if self._x_model is None or not np.array_equal(x, self._x_model) or self._failure is not None:
            self._evaluate(x)
        self.optimize_result = IpoptResult(
            success=not self.fail, status=status, message=message, nit=int(self._nit), x=x,
            fun=float(info["obj_val"]), nfev=int(self.result.model_evals), njev=int(self.result.deriv_evals),
            failed_evaluations=len(self.failed_evaluations))
        if self.options["disp"]:
            head = "Optimization Complete" if not self.fail else "Optimization FAILED."
            print(f"{head}\nIPOPT: {message} (status {status})\n"
                  f"    Iterations: {self._nit}\n    Function evaluations: {self.result.model_evals}\n"
                  f"    Gradient evaluations: {self.result.deriv_evals}\n" + "-" * 35, flush=True)
        return self.fail

    def _update_result(self, result):
        if self.optimize_result is not None:
            result.exit_status = self.optimize_result.message

    @DriverResult.track_stats(kind="model")
    def _run_solve_nonlinear(self):
        self._failure = None
        try:
            return self._problem().model.run_solve_nonlinear()
        except om.AnalysisError as exc:
            self._failure = exc

    # -- evaluations ----------------------------------------------------------------------------
    def _dv_array(self, values):
        return np.concatenate([np.ravel(values[name]) for name in self._designvars]).astype(float)

    def _evaluate(self, x):
        """Run the model at the scaled design vector ``x`` (recorded); True when it solved."""
        model = self._problem().model
        self._vectors["design_var"].set_data(np.array(x, dtype=float), driver_scaling=True)
        self._set_design_vars(driver_scaling=True)
        with RecordingDebugging(self._get_name(), self.iter_count, self):
            self.iter_count += 1
            with model._relevance.nonlinear_active("iter"):
                self._run_solve_nonlinear()
        self._x_model = np.array(x, dtype=float)
        self._x_jac = None
        if self._failure is not None:
            self.failed_evaluations.append({
                "evaluation": int(self.iter_count), "message": one_line(self._failure),
                "design_vars": {k: np.asarray(v).tolist()
                                for k, v in self.get_design_var_values(driver_scaling=False).items()}})
            return False
        self._store_values(x)
        return True

    def _store_values(self, x):
        self._x_model = np.array(x, dtype=float)
        self._obj_val = float(np.ravel(next(iter(self.get_objective_values().values())))[0])
        cons = self.get_constraint_values()
        order = self._nlcons + self._lincons
        self._con_val = np.concatenate([np.ravel(cons[c]) for c in order]) if order else np.zeros(0)

    def _at(self, x):
        """Make the model current at ``x``; raises ``CyIpoptEvaluationError`` if it failed there."""
        x = np.asarray(x, dtype=float)
        if self._x_model is None or not np.array_equal(x, self._x_model):
            self._evaluate(x)
        if self._failure is not None:
            raise self._cyipopt.CyIpoptEvaluationError(f"analysis failed: {one_line(self._failure)}")

    def _derivatives(self, x):
        self._at(x)
        if self._x_jac is not None and np.array_equal(self._x_jac, self._x_model):
            return
        jac = np.atleast_2d(self._compute_totals(of=self._of, wrt=self._dvlist, return_format="array"))
        self._grad = np.array(jac[0], dtype=float)
        full = jac[1:]
        if self._lin_jac is not None:
            full = np.vstack([full, self._lin_jac])
        rows, cols = self._structure
        self._jac_vals = np.asarray(full[rows, cols], dtype=float)
        self._x_jac = self._x_model.copy()

    def _jacobian_structure(self, n):
        """Row and column indices of the Jacobian entries handed to IPOPT (see the module doc)."""
        rows, cols = [], []
        model = self._problem().model
        relevance = model._relevance
        for name in self._nlcons:
            meta, sl = self._cons[name], self._con_slices[name]
            with relevance.seeds_active(rev_seeds=(meta["source"],)):
                dvs = [d for d in self._dvlist if relevance.is_relevant(self._designvars[d]["source"])]
            cidx = np.concatenate([np.arange(n)[self._dv_slices[d]] for d in dvs]) if dvs else np.zeros(0, int)
            r, c = np.meshgrid(np.arange(sl.start, sl.stop), cidx, indexing="ij")
            rows.append(r.ravel())
            cols.append(c.ravel())
        if self._lin_jac is not None:
            r, c = np.nonzero(self._lin_jac)
            rows.append(r + self._n_nl)
            cols.append(c)
        if not rows:
            return np.zeros(0, int), np.zeros(0, int)
        return np.concatenate(rows).astype(int), np.concatenate(cols).astype(int)

class _Callbacks:
    """The object cyipopt calls (objective, gradient, constraints, jacobian, jacobianstructure,
    intermediate)."""

    def __init__(self, driver: IpoptDriver, cyipopt):
        self._d = driver
        driver._cyipopt = cyipopt
        if not hasattr(cyipopt, "CyIpoptEvaluationError"):  # cyipopt < 1.3: make IPOPT back off with NaN
            raise ImportError("IpoptDriver needs cyipopt >= 1.3 (cyipopt.CyIpoptEvaluationError)")

    def objective(self, x):
        self._d._at(x)
        return self._d._obj_val

    def gradient(self, x):
        self._d._derivatives(x)
        return self._d._grad

    def constraints(self, x):
        self._d._at(x)
        return self._d._con_val

    def jacobian(self, x):
        self._d._derivatives(x)
        return self._d._jac_vals

    def jacobianstructure(self):
        return self._d._structure

    def intermediate(self, alg_mod, iter_count, obj_value, inf_pr, inf_du, mu, d_norm,
                     regularization_size, alpha_du, alpha_pr, ls_trials):
        d = self._d
        d._nit = int(iter_count)
        if d.options["disp"]:
            if iter_count == 0:
                print("  IPOPT  iter    objective     inf_pr    inf_du   lg(mu)  alpha_pr  ls", flush=True)
            mode = "r" if alg_mod == 1 else " "
            print(f"  IPOPT {iter_count:4d}{mode} {obj_value:+.6e} {inf_pr:9.2e} {inf_du:9.2e} "
                  f"{np.log10(max(mu, 1e-300)):6.1f} {alpha_pr:9.2e} {ls_trials:3d}", flush=True)
        return True

def _bound(arr, size, default):
    if arr is None:
        return np.full(size, default, dtype=float)
    return np.broadcast_to(np.asarray(arr, dtype=float), (size,)).copy()
