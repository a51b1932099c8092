"""BDF time marching and static solves of a :class:`~wingmdao.timemarch.system.ResidualSystem`.

Discrete equations (Sec. 3.5.2, Eq. 3.4-3.7; derivation in ``docs/time-marching.md``):

* step 0: static equilibrium ``R(x_0, 0, p, q_0) = 0`` (``initial="static"``) or a given
  state ``x_0 - x_init = 0`` (``initial="state"``);
* step 1: BDF1, ``xdot_1 = (x_1 - x_0) / dt``;
* steps n >= 2: BDF2, ``xdot_n = (3 x_n - 4 x_{n-1} + x_{n-2}) / (2 dt)`` (Eq. 3.5);
* each step: Newton on ``R(x_n, xdot(x_n), p, q_n) = 0`` with the matrix
  ``dR/dx + alpha_0/dt dR/dxdot`` (Eq. 3.7), sparse LU.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from math import isfinite

import numpy as np
from openmdao.core.analysis_error import AnalysisError
from wingmdao.timemarch.newton import DENSE_MAX, NewtonInfo, factor, newton_solve
from wingmdao.timemarch import fast_step as fs
from wingmdao.timemarch.fast_step import FastStepper

#: ``WINGMDAO_COMPILED_STEPS=0`` makes ``march(fast=None)`` use the Python Newton iterations
#: (SuperLU) even when the system's functions are compiled (benchmarks, debugging).
ENV_COMPILED_STEPS = "WINGMDAO_COMPILED_STEPS"

BDF1 = (1.0, -1.0, 0.0)
BDF2 = (1.5, -2.0, 0.5)


def bdf_coefficients(step: int) -> tuple[float, float, float]:
    """``(alpha_0, alpha_1, alpha_2)`` of step ``step`` (times 1/dt give Eq. 3.5); step 0 has none.

    Parameters
    ----------
    step : int
        Time step index (0 is the initial state, 1 uses BDF1, 2 and later BDF2).

    Returns
    -------
    tuple of float
        ``(alpha_0, alpha_1, alpha_2)``: ``(1, -1, 0)`` at step 1, ``(1.5, -2, 0.5)`` after,
        zeros at step 0.
    """
    if step <= 0:
        return (0.0, 0.0, 0.0)
    return BDF1 if step == 1 else BDF2


def time_step(time) -> float:
    """Validate a uniform time grid starting at 0 and return its step (s).

    A single entry ``[0.0]`` is a static solve and returns ``0.0``.

    Parameters
    ----------
    time : array_like, shape (n_time,)
        Time grid (s): finite, starting at 0, increasing and uniform to 1e-9 of the step.

    Returns
    -------
    float
        The uniform step (s); ``0.0`` for the single entry ``[0.0]``.

    Raises
    ------
    ValueError
        When the grid is empty, not 1-D, not finite, does not start at 0, is not increasing or
        is not uniform.
    """
    t = np.asarray(time, dtype=float)
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"time must be a non-empty 1-D array, got shape {t.shape}")
    if not np.all(np.isfinite(t)):
        bad = int(np.flatnonzero(~np.isfinite(t))[0])
        raise ValueError(f"time[{bad}] is not finite")
    if t[0] != 0.0:
        raise ValueError(f"time[0] must be 0 s, got {float(t[0])!r} s")
    if t.size == 1:
        return 0.0
    steps = np.diff(t)
    if np.any(steps <= 0.0):
        bad = int(np.flatnonzero(steps <= 0.0)[0])
        raise ValueError(f"time must be increasing: time[{bad + 1}] = {t[bad + 1]} s <= "
                         f"time[{bad}] = {t[bad]} s")
    dt = (t[-1] - t[0]) / (t.size - 1)
    dev = np.abs(steps - dt)
    if np.max(dev) > 1e-9 * dt + 1e-12 * abs(t[-1]):
        bad = int(np.argmax(dev))
        raise ValueError(f"time must be uniform: step {bad + 1} is {steps[bad]:.12g} s, the mean "
                         f"step is {dt:.12g} s (allowed deviation {1e-9 * dt:.1e} s)")
    return float(dt)


def state_rates(states, dt) -> np.ndarray:
    """BDF time derivatives of a state history (n_time, n_state); zero at step 0 (Eq. 3.5).

    Parameters
    ----------
    states : array_like, shape (n_time, n_state)
        State history on a uniform grid.
    dt : float
        Time step (s).

    Returns
    -------
    ndarray, shape (n_time, n_state)
        BDF1 rate at step 1, BDF2 rates from step 2 on, zeros at step 0.
    """
    X = np.asarray(states, dtype=float)
    xdot = np.zeros_like(X)
    if X.shape[0] > 1:
        xdot[1] = (X[1] - X[0]) / dt
    if X.shape[0] > 2:
        xdot[2:] = (1.5 * X[2:] - 2.0 * X[1:-1] + 0.5 * X[:-2]) / dt
    return xdot


@dataclass
class TimeHistory:
    """Result of :func:`march`: states and rates (n_time, n_state), Newton work per step.

    Parameters
    ----------
    time : ndarray, shape (n_time,)
        Time grid (s).
    states : ndarray, shape (n_time, n_state)
        State at each time.
    rates : ndarray, shape (n_time, n_state)
        BDF state rates (:func:`state_rates`).
    iterations : ndarray of int, shape (n_time,)
        Newton iterations of each step.
    factorizations : int
        LU factorizations of the march.
    info : dict
        Extra information (``"compiled_steps"``: whether the compiled stepper marched).
    """

    time: np.ndarray
    states: np.ndarray
    rates: np.ndarray
    iterations: np.ndarray
    factorizations: int = 0
    info: dict = field(default_factory=dict)


# ----------------------------------------------------------------------------- statics
def solve_static(system, p, q, x0=None, *, load_steps=1, scaled=None, max_halvings=6,
                 atol=0.0, rtol=1e-12, xtol=1e-12, max_iter=30, label="static solve"):
    """Static equilibrium ``R(x, 0, p, q) = 0`` with optional load stepping.

    Parameters
    ----------
    system : ResidualSystem
        The system to solve.
    p : ndarray, shape (n_param,)
        Time-invariant parameters (packed, see ``pack``).
    q : ndarray, shape (n_forcing,)
        Forcing (packed).
    x0 : ndarray, shape (n_state,), optional
        Initial guess; default ``system.initial_guess(p, q)``.
    load_steps : int
        Solve at ``q * k / load_steps``, k = 1..load_steps, each from the previous solution
        (continuation). A load step that fails is bisected up to ``max_halvings`` times.
    scaled : list of str, optional
        Forcing blocks that are stepped (default: all); the others are applied in full from the
        first step.
    max_halvings : int
        Bisections of a failed load step.
    atol, rtol, xtol, max_iter
        Newton tolerances (see :func:`newton_solve`); the default ``atol=0`` converges on the
        Newton step (residuals mix units).
    label : str
        Name of the solve in error messages.

    Returns
    -------
    x : ndarray, shape (n_state,)
        The equilibrium state.
    info : NewtonInfo
        With the total number of Newton iterations.

    Raises
    ------
    AnalysisError
        Naming the load fraction, residual norm and worst equation.
    """
    if int(load_steps) < 1:
        raise ValueError(f"load_steps must be >= 1, got {load_steps}")
    p = np.asarray(p, dtype=float).reshape(system.n_param)
    q = np.asarray(q, dtype=float).reshape(system.n_forcing)
    mask = _scale_mask(system, scaled)
    x = system.initial_guess(p, q) if x0 is None else np.array(x0, dtype=float).reshape(system.n_state)
    zero = np.zeros(system.n_state)
    total_it = 0

    def solve_at(frac, x_start):
        qk = np.where(mask, q * frac, q)
        # dR/dx from the (compiled once warm) Newton-matrix function with alpha = 0: the same
        # matrix as jac_state's first block, without building dR/dxdot (about 15x cheaper)
        return newton_solve(lambda z: system.residual(z, zero, p, qk),
                            lambda z: system.residual_and_newton_matrix(z, zero, p, qk, 0.0)[1], x_start,
                            atol=atol, rtol=rtol, xtol=xtol, max_iter=max_iter,
                            label=f"{label} at load fraction {frac:.4g}",
                            describe=system.describe_equation)

    done, step = 0.0, 1.0 / int(load_steps)
    halvings, info = 0, NewtonInfo(0, 0.0, True)
    while done < 1.0 - 1e-14:
        frac = min(1.0, done + step)
        try:
            x_new, info = solve_at(frac, x)
        except AnalysisError:
            if halvings >= max_halvings:
                raise
            halvings += 1
            step *= 0.5
            continue
        total_it += info.iterations
        x, done = x_new, frac
    return x, NewtonInfo(total_it, info.residual_norm, True)


def _scale_mask(system, scaled):
    if scaled is None:
        return np.ones(system.n_forcing, dtype=bool)
    names = [s.name for s in system.forcing_specs]
    mask = np.zeros(system.n_forcing, dtype=bool)
    start = 0
    unknown = set(scaled) - set(names)
    if unknown:
        raise ValueError(f"scaled: unknown forcing {sorted(unknown)}; forcing blocks are {names}")
    for s in system.forcing_specs:
        if s.name in scaled:
            mask[start:start + s.size] = True
        start += s.size
    return mask


# ----------------------------------------------------------------------------- marching
#: A Newton iteration whose residual stops decreasing once it is this far below the step's first
#: (predictor) residual has reached its round-off floor and is accepted. The states mix units, so
#: a step test alone can miss the floor: the 10-node aeroelastic beam stalls at a residual of
#: 5.4e-13 (6.5e-13 of its predictor residual) with 2.8e-8 N steps of a root axial force (EA =
#: 1e9 N turns round-off strains of 1e-16 into such forces), above 1000 xtol (1 + max|x|) = 1.1e-8.
#: A residual 1e10 below the predictor's is far below the BDF2 truncation error of the step.
FLOOR_RATIO = 1e-10


class _StepResidual:
    """``R(x, alpha x + hist, p, q)`` of one BDF step.

    Systems with a buffered evaluator (:meth:`CasadiResidualSystem.residual_call`) keep ``p`` and
    ``q`` in its input buffers and form ``xdot`` in place: no per-iteration copies or temporaries
    (the 20-node beam's compiled residual costs 3.6 us, the generic call 7 us). The returned
    array is the evaluator's output buffer, overwritten by the next call.
    """

    def __init__(self, system, p):
        self.system, self.p = system, p
        get = getattr(system, "residual_call", None)
        self.call = get() if get is not None else None
        self.fast = None
        self.hist = self.alpha = self.q = None

    def set_step(self, hist, alpha, q):
        self.hist, self.alpha, self.q = hist, alpha, q
        if self.fast is not None:
            self.fast.inp[3][:] = q

    def __call__(self, x):
        if self.call is None:
            return self.system.residual(x, self.alpha * x + self.hist, self.p, self.q)
        fast = self.call.refresh()
        if fast is not self.fast:      # first call, or the compiled function was swapped in
            fast.inp[2][:] = self.p
            fast.inp[3][:] = self.q
            self.fast = fast
        self.call.jit.count()
        inp = fast.inp
        inp[0][:] = x
        np.multiply(x, self.alpha, out=inp[1])
        inp[1] += self.hist
        fast.eval()
        return fast.out[0]


class _StepSolver:
    """Newton iterations of one BDF step, optionally reusing an LU (modified Newton)."""

    def __init__(self, system, p, *, atol, xtol, max_iter, modified, contraction):
        self.system, self.p = system, p
        self.atol, self.xtol, self.max_iter = atol, xtol, max_iter
        self.modified, self.contraction = modified, contraction
        self.lu, self.lu_alpha, self.factorizations = None, None, 0
        self.residual = _StepResidual(system, p)
        self._abs = np.empty(system.n_state)     # |r| and |dx| without temporaries

    def _factor(self, jac, label):
        try:
            self.lu = factor(jac)
        except RuntimeError as exc:
            raise AnalysisError(f"{label()}: singular Newton matrix ({exc})") from exc
        self.factorizations += 1

    def solve(self, x, hist, alpha, q, label):
        """Solve R(x, alpha x + hist, p, q) = 0 from ``x`` (updated in place and returned);
        ``alpha`` already divided by dt; ``label()`` names the step in error messages."""
        system, p, residual, absbuf = self.system, self.p, self.residual, self._abs
        if absbuf.size == 0:
            return x, 0
        atol, xtol, max_iter, modified = self.atol, self.xtol, self.max_iter, self.modified
        residual.set_step(hist, alpha, q)
        reuse = modified and self.lu is not None and self.lu_alpha == alpha
        prev_step, prev_norm, x_max = None, np.inf, 0.0
        for it in range(1, max_iter + 1):
            r = residual(x)
            norm = float(np.abs(r, out=absbuf).max())
            if not isfinite(norm):
                self._fail(label, it, r, "residual is not finite")
            if norm <= atol:
                return x, it - 1
            if it == 1:
                first_norm = norm
            # round-off floor: the residual stopped decreasing after a step that was already
            # within 1000 xtol, or once it is FLOOR_RATIO below the step's first residual (stiff,
            # mixed-unit systems jitter there instead of converging); x_max is max|x| of the
            # current iterate (computed after the last update)
            if (prev_step is not None and norm >= 0.5 * prev_norm
                    and (prev_step <= 1e3 * xtol * (1.0 + x_max) or norm <= FLOOR_RATIO * first_norm)):
                return x, it - 1
            prev_norm = norm
            if not reuse:  # new Newton matrix at the current iterate (Eq. 3.7)
                r, jac = system.residual_and_newton_matrix(x, alpha * x + hist, p, q, alpha)
                self._factor(jac, label)
                self.lu_alpha = alpha
            dx = self.lu.solve(r)
            step = float(np.abs(dx, out=absbuf).max())
            if not isfinite(step):
                self._fail(label, it, r, "Newton step is not finite")
            x -= dx
            x_max = float(np.abs(x, out=absbuf).max())
            tol = xtol * (1.0 + x_max)
            if step <= tol:
                return x, it
            if prev_step is not None and step < prev_step:
                # error estimate of the contracting iteration (Hairer & Wanner, IV.8):
                # |x - x*| <= theta / (1 - theta) |dx|, theta = |dx_k| / |dx_k-1|
                theta = step / prev_step
                if theta / (1.0 - theta) * step <= tol:
                    return x, it
            if modified:
                # keep the LU while the iteration contracts well, refactor otherwise
                reuse = prev_step is None or step <= self.contraction * prev_step
            prev_step = step
        r = residual(x)
        self._fail(label, max_iter, r, f"no convergence in {max_iter} iterations")

    def _fail(self, label, it, r, why):
        finite = np.where(np.isfinite(r), np.abs(r), np.inf)
        worst = int(np.argmax(finite))
        norm = float(np.max(finite)) if r.size else 0.0
        raise AnalysisError(f"{label()}: {why} (iteration {it}, max |residual| = {norm:.3e}, "
                               f"worst: {self.system.describe_equation(worst)})")


class _CompiledStepSolver(_StepSolver):
    """:class:`_StepSolver` whose iterations run in compiled code (:mod:`.fast_step`): same
    tests and error messages; its own sparse LU instead of SuperLU (results equal to round-off)."""

    def __init__(self, stepper, system, p, **opts):
        super().__init__(system, p, **opts)
        self.stepper = stepper

    def solve(self, x, hist, alpha, q, label):
        x = np.ascontiguousarray(x, dtype=float)
        status, it = self.stepper.solve(x, hist, alpha, np.ascontiguousarray(q, dtype=float))
        if status == fs.OK:
            return x, it
        self._raise(status, label)

    def march(self, X, Q, dt, iters, first, end, label):
        """Steps ``first .. end - 1`` of :func:`march` in one compiled call (predictor, history
        and Newton iterations); ``label(n)`` names step n in error messages."""
        status, step = self.stepper.march(X, Q, dt, iters, first, end)
        if status != fs.OK:
            self._raise(status, lambda: label(step))

    def _raise(self, status, label):
        fail_it, r = int(self.stepper.s.fail_iteration), self.stepper.r.copy()
        if status == fs.SINGULAR:
            raise AnalysisError(f"{label()}: singular Newton matrix (Factor is exactly singular)")
        why = {fs.RES_NONFINITE: "residual is not finite", fs.STEP_NONFINITE: "Newton step is not finite",
               fs.NO_CONVERGENCE: f"no convergence in {self.max_iter} iterations"}.get(
                   status, f"compiled function failed (status {status})")
        self._fail(label, fail_it, r, why)


def _step_solver(system, p, fast, **opts):
    """The compiled step solver when ``fast`` allows it and the system's functions are compiled
    (``fast=None``: for systems above ``DENSE_MAX`` states), else the Python one."""
    if fast is None and os.environ.get(ENV_COMPILED_STEPS, "1").strip().lower() in ("0", "false", "no", "off"):
        fast = False
    if fast is False or (fast is None and system.n_state <= DENSE_MAX):
        return _StepSolver(system, p, **opts)
    stepper = FastStepper.create(system, p, atol=opts["atol"], xtol=opts["xtol"], max_iter=opts["max_iter"],
                                 modified=opts["modified"], contraction=opts["contraction"])
    if stepper is None:
        if fast:
            raise ValueError("fast=True: the system's residual and Newton functions are not compiled "
                             "libraries (compile them with system.compile(); WINGMDAO_JIT must not be 0)")
        return _StepSolver(system, p, **opts)
    return _CompiledStepSolver(stepper, system, p, **opts)


def march(system, time, p, forcing, *, initial="static", x_init=None, x_guess=None,
          modified_newton=False, contraction=0.3, atol=0.0, xtol=1e-12, max_iter=25,
          static_options=None, callback=None, fast=None) -> TimeHistory:
    """Time-march ``R(x, xdot, p, q(t)) = 0`` with BDF1 then BDF2 (Eq. 3.4-3.7, Alg. 1).

    Parameters
    ----------
    system : ResidualSystem
        The system to march.
    time : ndarray, shape (n_time,)
        Uniform grid, ``time[0] = 0`` (s).
    p : ndarray, shape (n_param,)
        Parameters (packed).
    forcing : ndarray, shape (n_time, n_forcing)
        Forcing at every instant (packed per row).
    initial : {"static", "state"}
        Step 0: static equilibrium under q_0, or ``x_init``.
    x_init : ndarray, shape (n_state,), optional
        Initial state (``initial="state"``).
    x_guess : ndarray, shape (n_state,), optional
        Starting guess of the static solve (default ``system.initial_guess``).
    modified_newton : bool
        Reuse the LU across iterations and steps while the step contracts by ``contraction`` or
        better.
    contraction : float
        Modified Newton keeps its LU while each Newton step is at most ``contraction`` times the
        previous one.
    atol, xtol, max_iter
        Per-step convergence: ``max|R| <= atol``, or Newton step ``<= xtol (1 + max|x|)``. The
        default ``atol = 0`` always takes at least one Newton step: an absolute residual test is
        unreliable when residuals mix units (forces, curvatures).
    static_options : dict, optional
        Keyword arguments of :func:`solve_static` for step 0.
    callback : callable, optional
        ``callback(step, t, x)``, called after each converged step.
    fast : bool or None
        The Newton iterations in compiled code (:mod:`wingmdao.timemarch.fast_step`) when the
        system's residual and Newton functions are compiled. None: when available, for systems
        above ``newton.DENSE_MAX`` states, unless ``WINGMDAO_COMPILED_STEPS=0``; False: never
        (the Python path, SuperLU); True: required (ValueError when not available).

    Returns
    -------
    TimeHistory
        States and rates (n_time, n_state) and the Newton work per step.

    Raises
    ------
    AnalysisError
        Naming the step, time, residual and worst equation.
    """
    t = np.asarray(time, dtype=float)
    dt = time_step(t)
    n_time = t.size
    p = np.asarray(p, dtype=float).reshape(system.n_param)
    Q = np.asarray(forcing, dtype=float).reshape(n_time, system.n_forcing)
    X = np.zeros((n_time, system.n_state))
    iters = np.zeros(n_time, dtype=int)
    if initial not in ("static", "state"):
        raise ValueError(f'initial must be "static" or "state", got {initial!r}')
    if n_time > 1:
        system.count_march_steps(n_time - 1)
    solver = _step_solver(system, p, fast, atol=atol, xtol=xtol, max_iter=max_iter,
                          modified=modified_newton, contraction=contraction)
    if initial == "static":
        opts = dict(static_options or {})
        X[0], info = solve_static(system, p, Q[0], x_guess, label="step 0 (t = 0 s, static)", **opts)
        iters[0] = info.iterations
    else:
        if x_init is None:
            raise ValueError('initial="state" needs x_init')
        X[0] = np.asarray(x_init, dtype=float).reshape(system.n_state)
    if callback:
        callback(0, t[0], X[0])
    if isinstance(solver, _CompiledStepSolver) and n_time > 1:
        Qc = np.ascontiguousarray(Q)
        it64 = iters if iters.dtype == np.int64 else np.zeros(n_time, dtype=np.int64)
        chunks = [(n, n + 1) for n in range(1, n_time)] if callback else [(1, n_time)]
        for first, end in chunks:
            solver.march(X, Qc, dt, it64, first, end, lambda n: f"step {n} (t = {t[n]:.6g} s)")
            if callback:
                callback(first, t[first], X[first])
        iters[:] = it64
        return TimeHistory(t, X, state_rates(X, dt), iters, solver.stepper.factorizations,
                           info={"compiled_steps": True})
    for n in range(1, n_time):
        a0, a1, a2 = bdf_coefficients(n)
        hist = (a1 * X[n - 1] + (a2 * X[n - 2] if n >= 2 else 0.0)) / dt
        if n == 1:
            x_pred = X[0].copy()
        elif n == 2:
            x_pred = 2.0 * X[1] - X[0]
        else:
            x_pred = 3.0 * X[n - 1] - 3.0 * X[n - 2] + X[n - 3]
        X[n], iters[n] = solver.solve(x_pred, hist, a0 / dt, Q[n],
                                      lambda n=n: f"step {n} (t = {t[n]:.6g} s)")
        if callback:
            callback(n, t[n], X[n])
    return TimeHistory(t, X, state_rates(X, dt), iters, solver.factorizations,
                       info={"compiled_steps": False})
