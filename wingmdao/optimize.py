"""Optimizer selection and recording shared by every sizing case.

``pyoptsparse`` is not installable from the package registry on every machine, so the
driver falls back to SciPy's SLSQP through :class:`openmdao.api.ScipyOptimizeDriver` when
``pyoptsparse`` does not import. The choice is reported in the results (``driver`` key).
Every run records to SQLite so no iteration is lost.
"""

from __future__ import annotations

import importlib.util

import openmdao.api as om

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
    opts["includes"] = ["*mass*", "*ks_*"]
    prob.driver.add_recorder(rec)
    return rec
