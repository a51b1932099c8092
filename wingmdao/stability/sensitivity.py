"""Eigenvalue derivatives of the linearised residual and the aggregated flutter-damping constraint.

Pencil. About a static state x0 (R(x0, 0, p, q) = 0), ``A = dR/dx`` and ``B = dR/dxdot``; an
eigenvalue lambda has right and left vectors ``(A + lambda B) v = 0`` and ``u^H (A + lambda B) = 0``.

Derivative (simple eigenvalue). Differentiating ``(A + lambda B) v = 0`` and multiplying by u^H:

    d lambda / dp = - u^H (dA/dp + lambda dB/dp) v / (u^H B v)

(e.g. R. B. Nelson, "Simplified calculation of eigenvector derivatives", AIAA J. 14(9), 1976; the
left-vector form of J. H. Wilkinson, *The algebraic eigenvalue problem*, 1965, Sec. 2.8). The
numerator is the p-gradient of the scalar ``s(x, p) = u^H (A(x, p) v + lambda B(x, p) v)`` with u,
v, lambda held fixed: ``A v`` and ``B v`` are directional derivatives of R (CasADi ``jtimes``) and
the gradient is reverse-mode AD of them, i.e. exact second derivatives of R, no differencing.
The static state moves with p: ``dx0/dp = -A^-1 dR/dp``, so the total numerator is
``ds/dp - (A^-T ds/dx)^T dR/dp`` (one extra solve with A^T per eigenvalue).

Constraint (see docs/flutter.md). At airspeeds V_1 < ... < V_K up to F V_D, per mode
either its damping ``sigma = Re lambda`` (1/s, ``measure="sigma"``, the default) or its damping
ratio ``zeta = -Re lambda / |lambda|`` (``measure="ratio"``); the constraint is

    KS_rho(g_kj) <= 0,  g = sigma + margin  or  g = margin - zeta,
    KS_rho(g) = g_max + ln(sum exp(rho (g - g_max))) / rho

(Kreisselmeier-Steinhauser; KS >= max g, so the aggregate is conservative by at most ln(N)/rho).
sigma is the default because the damping ratios of an undamped structure are all small at the
low speeds of the set (zeta ~ 1e-3 for a torsion mode at V_D / 4 on PEGASUS), below the KS
over-estimate ln(N)/rho, which made ``measure="ratio"`` infeasible for every design; sigma of
the same modes is ~0.2 1/s, far above ln(N)/rho = 0.03 1/s at rho = 100 s.
The modes at each speed are every oscillatory eigenvalue of the eigen window whose eigenvector
moves the aerodynamic states (strip theory does not load in-plane bending, whose Re lambda = 0
would make the KS infeasible for any design); they are not tracked between speeds: MAC tracking
over the coarse set of speeds swapped the PEGASUS flutter mode for a real root between 1.0 and
1.33 V_D, and the constraint missed a flutter that the sweep finds at 1.31 V_D.

Limits: the derivative is that of a simple eigenvalue. At a repeated eigenvalue (two modes
coalescing) it does not exist and u^H B v -> 0: the KS value stays continuous, its gradient
jumps. Real eigenvalues (divergence, or an overdamped bending mode) are not in the constraint;
a mode entering or leaving the eigen window changes the set (harmless when it is well damped:
its KS weight is ``~exp(-rho |g - g_max|)``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import casadi as ca
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.linalg import lapack
from scipy.optimize import linear_sum_assignment

from wingmdao.stability import pencil_lu
from wingmdao.stability.eigen import _signature, check_speeds, derived_definition, eigenmodes, linearize, static_state
from wingmdao.timemarch.system import layout
from wingmdao.utils import casadi_cache as cc

_FUNCTIONS: dict = {}


#: evaluations after which the gradient functions are compiled (cached on disk)
GRADIENT_JIT_THRESHOLD = 20


class _GradientFunctions:
    """CasADi functions of the eigenvalue derivative, built once per system and compiled to C after
    :data:`GRADIENT_JIT_THRESHOLD` evaluations (:class:`wingmdao.utils.casadi_cache.JitCall`):

    * ``pencil``: ``(x, xdot, p, q, vr, vi, ur, ui, lam_r, lam_i) -> (ds/dp, ds/dx)`` (each
      [real; imaginary] rows, dense) of ``s = u^H (dR/dx v + lambda dR/dxdot v)``;
    * ``vjp_p``: ``(x, xdot, p, q, W) -> W^T dR/dp`` for W (n, 2) (the static-state term with the
      real and imaginary parts of the adjoint ``A^-T ds/dx``), reverse-mode AD, no dR/dp matrix.

    With a warm compile cache the compiled libraries are loaded directly: their cache key is the
    definition (:func:`wingmdao.stability.eigen.derived_definition`) and the function names, and
    the library's signature check needs only the (dense) input and output shapes
    (:func:`_signature`), so the interpreted second-derivative functions (0.9 s of CasADi
    ``jacobian`` for the 20-node PEGASUS system) are built only when a library is missing, or on
    demand (:attr:`interpreted`).
    """

    def __init__(self, system):
        self.system = system
        f = system.residual_function
        n, npar, nq = system.n_state, system.n_param, system.n_forcing
        self.n, self.npar = n, npar
        self.names = (f"{f.name()}_pencil_gradient", f"{f.name()}_vjp_p")
        self.definition = derived_definition(system, "wingmdao.stability.sensitivity._GradientFunctions", __name__)
        vec = [(n, 1), (n, 1), (npar, 1), (nq, 1)]
        stubs = (_signature(self.names[0], vec + [(n, 1)] * 4 + [(1, 1)] * 2, [(2, npar), (2, n)]),
                 _signature(self.names[1], vec + [(n, 2)], [(2, npar)]))
        hits = ([cc.cached(st, key=cc.function_key(st, definition=self.definition)) for st in stubs]
                if cc.jit_enabled() else [None, None])
        self._built = None
        if all(h is not None for h in hits):
            self.pencil = cc.precompiled_call(hits[0], GRADIENT_JIT_THRESHOLD, definition=self.definition)
            self.vjp = cc.precompiled_call(hits[1], GRADIENT_JIT_THRESHOLD, definition=self.definition)
        else:
            pencil, vjp = self._build()
            self.pencil = cc.JitCall(pencil, GRADIENT_JIT_THRESHOLD, definition=self.definition)
            self.vjp = cc.JitCall(vjp, GRADIENT_JIT_THRESHOLD, definition=self.definition)

    def _build(self):
        """The interpreted functions (built once)."""
        if self._built is None:
            system = self.system
            f = system.residual_function
            n, npar, nq = system.n_state, system.n_param, system.n_forcing
            x, xd = ca.SX.sym("x", n), ca.SX.sym("xdot", n)
            p, q = ca.SX.sym("p", npar), ca.SX.sym("q", nq)
            vr, vi, ur, ui = (ca.SX.sym(k, n) for k in ("vr", "vi", "ur", "ui"))
            lr, li = ca.SX.sym("lr"), ca.SX.sym("li")
            R = f(x, xd, p, q)
            avr, avi = ca.jtimes(R, x, vr), ca.jtimes(R, x, vi)
            bvr, bvi = ca.jtimes(R, xd, vr), ca.jtimes(R, xd, vi)
            wr = avr + lr * bvr - li * bvi
            wi = avi + lr * bvi + li * bvr
            s = ca.vertcat(ca.dot(ur, wr) + ca.dot(ui, wi), ca.dot(ur, wi) - ca.dot(ui, wr))
            jp = ca.densify(ca.jacobian(s, p))
            jx = ca.densify(ca.jacobian(s, x))
            pencil = ca.Function(self.names[0], [x, xd, p, q, vr, vi, ur, ui, lr, li], [jp, jx])
            W = ca.SX.sym("W", n, 2)
            vjp = ca.densify(ca.jacobian(ca.mtimes(W.T, R), p))
            self._built = (pencil, ca.Function(self.names[1], [x, xd, p, q, W], [vjp]))
        return self._built

    @property
    def interpreted(self) -> ca.Function:
        """The interpreted ``pencil`` function (built on first use)."""
        return self._build()[0]

    @property
    def vjp_interpreted(self) -> ca.Function:
        """The interpreted ``vjp_p`` function (built on first use)."""
        return self._build()[1]

    def ds(self, x, p, q, v, u, lam):
        """``(ds/dp, ds/dx)``, complex vectors."""
        jp, jx = self.pencil(x, np.zeros_like(x), p, q, v.real, v.imag, u.real, u.imag, lam.real, lam.imag)
        jp = jp.reshape((2, self.npar), order="F")
        jx = jx.reshape((2, self.n), order="F")
        return jp[0] + 1j * jp[1], jx[0] + 1j * jx[1]

    def static_term(self, x, p, q, w):
        """``w^T dR/dp`` (complex w: the real and imaginary parts in one evaluation)."""
        W = np.column_stack([w.real, w.imag])
        out = self.vjp(x, np.zeros_like(x), p, q, W.ravel(order="F"))[0].reshape((2, self.npar), order="F")
        return out[0] + 1j * out[1]


def gradient_functions(system) -> _GradientFunctions:
    """The :class:`_GradientFunctions` of ``system`` (built once per system)."""
    key = id(system)
    if key in _FUNCTIONS and _FUNCTIONS[key][0] is system:
        return _FUNCTIONS[key][1]
    fun = _GradientFunctions(system)
    _FUNCTIONS[key] = (system, fun)
    return fun


def pencil_gradient_function(system) -> ca.Function:
    """CasADi function ``(x, xdot, p, q, vr, vi, ur, ui, lam_r, lam_i) -> (ds/dp, ds/dx)`` (each as
    [real; imaginary] rows) of ``s = u^H (dR/dx v + lambda dR/dxdot v)``; built once per system."""
    return gradient_functions(system).interpreted


def _lu(M):
    """Sparse LU of a pencil matrix (natural column order: the node-by-node beam ordering has
    the fill of COLAMD's and factors ~2x faster, 0.9 ms for the 440-state PEGASUS pencil)."""
    return spla.splu(sp.csc_matrix(M), permc_spec="NATURAL")


def left_right_vectors(A, B, lam, *, iterations=3, rel_shift=1e-10):
    """Right and left eigenvectors ``(v, u)`` (unit 2-norm) of ``(A + lambda B) v = 0`` and the
    Rayleigh-quotient eigenvalue ``-u^H A v / u^H B v``, by inverse iteration with the shift
    ``lambda (1 + rel_shift)`` (``lambda`` from an eigen-solver)."""
    A, B = sp.csc_matrix(A), sp.csc_matrix(B)
    n = A.shape[0]
    s = complex(lam) * (1.0 + rel_shift) + rel_shift
    rng = np.random.default_rng(0)
    v = rng.standard_normal(n) + 1j * rng.standard_normal(n)
    u = v.copy()
    pen = pencil_lu.pencil(A, B)
    if pen is not None and pen.has_pivots:   # the static-pivot kernel (pencil_lu.c); tol < 0: all steps
        v0 = v / np.linalg.norm(v)
        step = pen.iterate(s, v0, v0, B @ v0, lam, lam, iterations, -1.0)
        if step is not None:
            return step[0], step[1], step[3]
    lu = _lu(sp.csc_matrix(A + s * B, dtype=complex))
    if pen is not None:
        pen.repivot(lu.perm_r)
    BH = B.conj().T
    for _ in range(int(iterations)):
        v = lu.solve(np.asarray(B @ v))
        v /= np.linalg.norm(v)
        u = lu.solve(np.asarray(BH @ u), trans="H")
        u /= np.linalg.norm(u)
    lam_rq = -np.vdot(u, A @ v) / np.vdot(u, B @ v)
    return v, u, complex(lam_rq)


def eigenvalue_gradient(system, p, q, x0, lam, v, u, *, A=None, B=None, static=True) -> np.ndarray:
    """d lambda / d p (complex, one entry per packed parameter) of a simple eigenvalue with right /
    left vectors v, u at the state x0; ``static``: x0 is the static solution and moves with p."""
    x0 = np.asarray(x0, dtype=float).ravel()
    p = np.asarray(p, dtype=float).ravel()
    q = np.asarray(q, dtype=float).ravel()
    xd = np.zeros_like(x0)
    if A is None or B is None:
        A, B = system.jac_state(x0, xd, p, q)
        A, B = sp.csc_matrix(A), sp.csc_matrix(B)
    fun = gradient_functions(system)
    ds, gx = fun.ds(x0, p, q, v, u, lam)
    if static:
        lu = _lu(A)
        w = lu.solve(gx.real, trans="T") + 1j * lu.solve(gx.imag, trans="T")
        ds = ds - fun.static_term(x0, p, q, w)
    return -ds / np.vdot(u, B @ v)


def damping_ratio_gradient(lam, dlam):
    """``zeta = -Re lambda / |lambda|`` and its gradient from ``dlam`` (d lambda / dp)."""
    s, w = lam.real, lam.imag
    r = abs(lam)
    dr = (s * dlam.real + w * dlam.imag) / r
    return -s / r, -(dlam.real * r - s * dr) / r**2


def ks_aggregate(g, rho):
    """KS_rho(g) and d KS / d g (Kreisselmeier-Steinhauser, max-shifted)."""
    g = np.asarray(g, dtype=float).ravel()
    m = float(np.max(g))
    e = np.exp(rho * (g - m))
    return m + np.log(np.sum(e)) / rho, e / np.sum(e)


@dataclass
class SpeedModes:
    """The aggregated modes at one speed: what the gradient needs and what a warm start refines."""

    speed: float                     # m/s
    p: np.ndarray                    # packed parameters at this speed
    q: np.ndarray                    # packed forcing
    x0: np.ndarray                   # static state linearised about
    A: sp.csc_matrix                 # dR/dx at x0
    B: sp.csc_matrix                 # dR/dxdot at x0
    eigenvalues: np.ndarray          # complex (k,), two-sided Rayleigh quotients
    right: np.ndarray                # (n, k) right vectors, unit 2-norm
    left: np.ndarray                 # (n, k) left vectors, unit 2-norm
    error: np.ndarray = None         # (k,) 1/s: 0 refined; > 0 a lazy estimate (Ritz value, its error bound)


@dataclass
class DampingConstraint:
    """Value and gradient of the aggregated damping constraint, with what it aggregated."""

    value: float                     # KS_rho(g), <= 0 when satisfied
    gradient: np.ndarray             # d value / d p (packed parameters, summed over the speeds)
    speeds: np.ndarray               # m/s
    eigenvalues: list                # per speed: the aggregated eigenvalues (complex array)
    damping_ratio: np.ndarray        # every aggregated mode's zeta, speed by speed
    modes: list = None               # per speed: SpeedModes (vectors and pencil, for the gradient)
    weights: np.ndarray = None       # dKS/dg of every aggregated mode, speed by speed
    measure: str = "sigma"
    cold: bool = True                # True: full eigen window; False: warm-started refinement
    errors: list = None              # per speed: error estimate of each aggregated eigenvalue (1/s);
                                     # 0: refined; > 0: a lazy Ritz estimate of a mode of negligible KS weight


MEASURES = ("sigma", "ratio")


def refine_pair(A, B, lam0, v0, u0, *, tol=1e-12, iterations=6, shifts=3, rel_shift=1e-10, quotient_start=True):
    """Right / left vectors and the two-sided Rayleigh quotient of the eigenvalue of
    ``(A + lambda B) v = 0`` nearest ``lam0``, by inverse iteration from ``v0, u0`` (the
    previous design's vectors): one sparse LU of ``A + s B`` per shift s (first ``lam0``, then the
    current quotient; at most ``shifts``), the left vector from the transposed solve with the same
    LU. Converged when two quotients agree to ``tol`` relative. Returns ``(v, u, lam, converged)``.
    ``quotient_start``: the first shift is the two-sided quotient of ``v0, u0`` on the new pencil
    instead of ``lam0`` (it follows the mode's own change: the PEGASUS torsion and in-plane modes,
    1-3 rad/s apart, cross between SLSQP designs, and a shift at the old eigenvalue landed on the
    other one).
    With the compiled kernel (:mod:`wingmdao.stability.pencil_lu`) each shift's factorization and
    steps run in C with a static pivot order (checked; a shift it refuses runs here with SuperLU).
    (Two-sided Rayleigh-quotient iteration: B. N. Parlett, "The Rayleigh quotient iteration and
    some generalizations for nonnormal matrices", Math. Comp. 28(127), 1974.)"""
    v, u = np.asarray(v0, complex), np.asarray(u0, complex)
    v, u = v / np.linalg.norm(v), u / np.linalg.norm(u)
    Bv = B @ v
    lam_old, lam = complex(lam0), complex(lam0)
    if quotient_start:
        den = np.vdot(u, Bv)
        if abs(den) > 1e-12 * np.linalg.norm(Bv) * np.linalg.norm(u):
            lam_old = lam = complex(-np.vdot(u, A @ v) / den)

    def change(a, b):  # phase-aligned change of a unit vector
        ph = np.vdot(b, a)
        return np.linalg.norm(a - b * (ph / abs(ph) if ph != 0 else 1.0))

    pen = pencil_lu.pencil(A, B)
    for _ in range(int(shifts)):
        s = lam * (1.0 + rel_shift) + rel_shift
        step = pen.iterate(s, v, u, Bv, lam, lam_old, iterations, tol) if pen is not None and pen.has_pivots else None
        if step is not None:      # the static-pivot kernel (pencil_lu.c): the same steps in C
            v, u, Bv, lam, lam_old, ok = step
            if ok:
                return v, u, lam, True
            continue
        lu = _lu(sp.csc_matrix(A + s * B, dtype=complex))
        if pen is not None:       # no pivot order yet, or it failed this shift: take SuperLU's
            pen.repivot(lu.perm_r)
        BH = B.conj().T
        for _ in range(int(iterations)):
            v_new = lu.solve(np.asarray(Bv))
            v_new /= np.linalg.norm(v_new)
            u_new = lu.solve(np.asarray(BH @ u), trans="H")
            u_new /= np.linalg.norm(u_new)
            dv = max(change(v_new, v), change(u_new, u))
            v, u = v_new, u_new
            Bv = B @ v        # the quotient's and the next step's
            lam = complex(-np.vdot(u, A @ v) / np.vdot(u, Bv))
            # converged: the quotient to tol and the vectors (the gradient needs them; the
            # quotient is second order in their errors) to sqrt(tol)
            if abs(lam - lam_old) <= tol * abs(lam) and dv <= np.sqrt(tol):
                return v, u, lam, True
            lam_old = lam
    return v, u, lam, False


class WarmStart:
    """History of :func:`damping_constraint` between evaluations (warm start; docs/flutter.md).

    After a cold evaluation (the full sparse eigen window at every speed) it keeps, per speed,
    **every oscillatory mode of the window** (eigenvalue, right and left vectors), loaded or not:
    an unloaded in-plane mode (Re lambda ~ 0) becomes loaded when it nears the torsion mode, and
    a history of the aggregated modes only missed it (PEGASUS sizing: warm KS -0.961, cold
    -0.003). The next evaluation refines all of them on the new design's full pencil
    (:func:`refine_pair`, from the previous evaluation's vectors) and aggregates those now loaded,
    unless a rule asks for the full window again:

    * no history, or the speeds / options changed;
    * ``refresh`` evaluations since the last window of every speed (a full or a single-speed
      window; a speed whose own window is that old, while others had one since, gets a
      single-speed window instead: the window of each speed is at most ``refresh`` old);
    * optional: some parameter block moved by more than ``max_step`` of its largest entry from
      the last cold design (default off: SLSQP steps of the sizing move the stiffnesses by
      30-90 % and the refinement checks alone kept the value equal to the cold one);
    * a refinement is not trusted: not converged, its beam-weighted MAC with the previous
      vector below ``min_mac``, the mode turned real, two modes refined to the same eigenvalue,
      or it left the cold window's disc ``|lambda - sigma| < r`` (the cold set would drop it).
      Since every oscillatory mode of the window is refined, a refinement that lands on another
      mode lands on one of these (a tracked mode: duplicate; a real root; outside the disc).

    ``lazy`` (default): a mode is refined only when it may matter: its two-sided Rayleigh-Ritz
    estimate on the history's vectors (:func:`_ritz`, no LU) is not trusted, or may be loaded
    and within ``LAZY_KS / rho`` of g_max at the upper end of its (empirical) error bound; a
    second check against the exact g_max of the refined modes refines any skipped mode in reach.
    At the speeds after the first, a second estimate on this design's modes at the previous speed
    (refined or estimated just before; the in-plane modes barely change with the speed) replaces the
    history one per mode when it is trusted with a smaller bound (:func:`_best_ritz`).

    The history is the tracked set of the stored evaluation (the last ``keep``, since the last
    full or single-speed window) nearest the new design (:meth:`distance`): SLSQP's line searches
    jump back near earlier designs.

    The first evaluation (no history) makes one window, at the lowest speed; each later speed
    tracks the previous speed's set (every oscillatory mode refined on its pencil, MAC with that
    set, the first window's disc: the window radius is set by the aerodynamic lag roots and barely
    changes with the speed, PEGASUS 120.2-122.9 1/s) and gets its own window only when that fails.
    A failed speed is retried from this design's modes at the nearest speed that worked, then, if
    the step was too large for its history (a design moved ~8x, as a presizing pass does), by
    tracking this design's window set at the nearest speed that has one, and only then redone with
    the full window, so the value is always that of a converged set (PEGASUS maneuver sizing: one
    window in all, eight before). Not detected: an oscillatory mode entering the window between
    two cold evaluations from outside the disc or from two real roots (its KS weight is
    ~exp(-rho (g_max - g)); the next cold evaluation picks it up).
    """

    def __init__(self, *, refresh=100, max_step=None, min_mac=0.5, tol=1e-12, keep=6, lazy=True):
        if int(refresh) < 1:
            raise ValueError(f"WarmStart refresh = {refresh}; allowed: an integer >= 1 (evaluations)")
        if not ((max_step is None or 0.0 < float(max_step)) and 0.0 <= float(min_mac) <= 1.0):
            raise ValueError(f"WarmStart: max_step = {max_step} (> 0 or None), min_mac = {min_mac} [0, 1] "
                             "out of range")
        self.refresh, self.min_mac = int(refresh), float(min_mac)
        self.max_step = None if max_step is None else float(max_step)
        self.tol = float(tol)
        self.keep = max(1, int(keep))
        self.lazy = bool(lazy)
        self.reset()

    def reset(self):
        """Forget the history: the next evaluation is cold."""
        self.key = None              # (speeds, options) of the history
        self.cold_p = None           # per speed: p of the last cold evaluation
        self.cold_window = None      # per speed: (radius, sigma) of the cold window's disc
        self.tracked = None          # per speed: SpeedModes of every oscillatory window mode, last evaluation
        self.modes = None            # per speed: SpeedModes of the aggregated modes, last evaluation
        self.history = []            # (p at the first speed, tracked, modes) of the last ``keep`` evaluations
        self.since_cold = 0          # evaluations since the last full cold evaluation
        self.window_age = None       # per speed: evaluations since its last window (full or single-speed)
        self.n_cold = 0
        self.n_warm = 0
        self.n_speed_retry = 0       # single speeds retried from the design's modes at another speed
        self.n_speed_cold = 0        # single speeds redone with the full window in a warm evaluation
        self.n_speed_track = 0       # single speeds tracked from this design's window set at another speed
        self.n_windows = 0           # sparse eigen windows computed (full and single-speed)
        self.dropped = 0             # negligible modes dropped (turned real / left the window)
        self.n_refined = 0           # mode refinements (refine_pair from the history)
        self.n_skipped = 0           # modes left at their Ritz estimate (lazy refinement)
        self.n_lazy_redo = 0         # speeds refined again: a skipped mode came within reach of g_max
        self.reasons = []            # why each cold evaluation or cold speed was made

    @staticmethod
    def distance(system, p, ph):
        """Largest relative change of a parameter block between ``ph`` and ``p`` (max-norm over
        the block / its largest entry in ``ph``)."""
        starts = _block_starts(system)
        if starts.size == 0:
            return 0.0
        scale = np.maximum.reduceat(np.abs(ph), starts)
        diff = np.maximum.reduceat(np.abs(np.asarray(p) - ph), starts)
        ok = scale > 0.0
        return float(np.max(diff[ok] / scale[ok], initial=0.0))

    def step_too_large(self, system, p_list):
        """True when ``max_step`` is set and some parameter block moved by more than ``max_step``
        of its largest entry (max-norm, relative) from the last cold design, at some speed."""
        if self.max_step is None:
            return False
        for p, pc in zip(p_list, self.cold_p):
            for sl in layout(system.param_specs).values():
                scale = float(np.max(np.abs(pc[sl]), initial=0.0))
                if np.max(np.abs(p[sl] - pc[sl]), initial=0.0) > self.max_step * scale + 1e-9:  # 1e-9: round-off of zero blocks (SI)
                    return True
        return False


_STARTS: dict = {}


def _block_starts(system) -> np.ndarray:
    """Start index of every non-empty parameter block of ``system`` (for ``np.maximum.reduceat``;
    cached per system: a system's parameter specs are fixed when it is built)."""
    hit = _STARTS.get(id(system))
    if hit is not None and hit[0] is system:
        return hit[1]
    sizes = np.array([spec.size for spec in system.param_specs], dtype=np.intp)
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.intp)
    starts = starts[sizes > 0]
    _STARTS[id(system)] = (system, starts)
    return starts


#: a warm-started mode whose KS exponent rho (g - g_max) is below -this (weight < 4e-18) of the
#: previous evaluation's g_max (minus the same again as a guard) may leave the set without a cold window
NEGLIGIBLE_KS = 80.0


def _measure(lam, measure, margin):
    lam = np.asarray(lam, dtype=complex)
    return lam.real + margin if measure == "sigma" else margin + lam.real / np.abs(lam)


def _loaded(vectors, mask, bmask):
    """Loaded fraction of each column: |aerodynamic part| / |beam part| (``mask``, ``bmask``
    weights; only their nonzero rows are read)."""
    ia, ib = np.flatnonzero(mask), np.flatnonzero(bmask)
    return (np.linalg.norm(vectors[ia] * mask[ia, None], axis=0)
            / np.linalg.norm(vectors[ib] * bmask[ib, None], axis=0))


def _subset(sm, keep):
    return SpeedModes(sm.speed, sm.p, sm.q, sm.x0, sm.A, sm.B, sm.eigenvalues[keep], sm.right[:, keep],
                      sm.left[:, keep], None if sm.error is None else sm.error[keep])


def _aggregated(sm, V, mask, bmask, neutral_fraction):
    keep = np.flatnonzero(_loaded(sm.right, mask, bmask) > neutral_fraction)
    if keep.size == 0:
        raise ValueError(f"no aerodynamically loaded oscillatory mode at {V} m/s in the eigen window")
    return _subset(sm, keep)


def _cold_speed(system, p, q, x, V, mask, bmask, min_frequency, neutral_fraction, static, eig_options):
    """Every oscillatory mode of the full eigen window at one speed (refined right / left vectors)
    and the window's eigenvalues."""
    m = eigenmodes(system, p, q, x, static=static, **eig_options)
    osc = np.flatnonzero(m.frequency > min_frequency)
    A, B = linearize(system, p, q, m.x0)
    lams, vs, us = [], [], []
    for j in osc:
        vec, uvec, lj = left_right_vectors(A, B, m.eigenvalues[j])
        lams.append(lj)
        vs.append(vec)
        us.append(uvec)
    n = system.n_state
    sm = SpeedModes(float(V), p, q, m.x0, A, B, np.array(lams, dtype=complex),
                    np.array(vs).T.reshape(n, len(vs)), np.array(us).T.reshape(n, len(us)), np.zeros(len(lams)))
    return sm, m.eigenvalues


def _beam_mac(a, b, w):
    return abs(np.vdot(w * a, w * b)) ** 2 / (np.linalg.norm(w * a) ** 2 * np.linalg.norm(w * b) ** 2)


#: lazy refinement: a mode is left unrefined only when its KS exponent rho (g - g_max), with g at
#: the upper end of its error bound, is below -this (weight < 1.3e-14, below the gradient's
#: ``min_weight`` 1e-13; the value changes by < 1.3e-16 per skipped mode)
LAZY_KS = 32.0
#: lazy refinement: factor on the backward-error estimate of a Ritz value's error (:func:`_ritz`;
#: the largest ratio seen over a replayed PEGASUS sizing was 1.6)
LAZY_ERROR_FACTOR = 10.0


@dataclass
class _Ritz:
    """Two-sided Rayleigh-Ritz estimates of the tracked modes of one speed on a new pencil, one per
    history mode (same order): eigenvalue, unit right / left vectors, error bound (1/s, already
    times :data:`LAZY_ERROR_FACTOR`), beam-weighted MAC with the history vector, loaded fraction and
    whether the estimate may stand in for a refinement apart from its KS weight (``trusted``), and
    whether it is surely out of the aggregate (``unloaded``)."""

    lam: np.ndarray
    right: np.ndarray
    left: np.ndarray
    error: np.ndarray
    mac: np.ndarray
    loaded: np.ndarray
    trusted: np.ndarray
    unloaded: np.ndarray


_LWORK: dict = {}


def _small_eig(a, b):
    """``(w, vl, vr)`` of the small complex pencil ``(a, b)`` (the k x k Ritz pencil, k ~ 5): the
    LAPACK ``zggev`` call of ``scipy.linalg.eig(a, b, left=True, right=True)`` with the same optimal
    workspace (queried once per size), so the same eigenvalues, without SciPy's per-call validation,
    workspace query and per-column normalisation (~0.2 ms of its ~0.26 ms). The vectors are **not
    normalised** (the caller normalises the Ritz vectors ``V y``, ``U z``)."""
    a = np.asfortranarray(a, dtype=complex)
    b = np.asfortranarray(b, dtype=complex)
    n = a.shape[0]
    lwork = _LWORK.get(n)
    if lwork is None:
        lwork = _LWORK[n] = int(lapack.zggev(a, b, lwork=-1)[-2][0].real)
    alpha, beta, vl, vr, _, info = lapack.zggev(a, b, 1, 1, lwork, 0, 0)
    if info != 0:
        raise np.linalg.LinAlgError(f"generalized eig algorithm (zggev) failed: info = {info}")
    w = np.empty_like(alpha)
    nz = beta != 0
    w[nz] = alpha[nz] / beta[nz]
    w[~nz & (alpha != 0)] = np.inf
    w[~nz & (alpha == 0)] = complex(np.nan, np.nan)
    return w, vl, vr


def _ritz(A, B, prev, window, mask, bmask, min_frequency, min_mac, neutral_fraction, enrich=False, basis=None):
    """Petrov-Galerkin (two-sided Rayleigh-Ritz) projection of the new pencil ``(A, B)`` on the
    span of the history's right vectors V (trial) and left vectors U (test): the k x k pencil
    ``(U^H A V, U^H B V)``, solved dense; Ritz pairs ``x = V y``, ``w = U z``. Error estimate of
    the Ritz value: ``LAZY_ERROR_FACTOR * max(eta_r, eta_l) * |theta|`` with the relative
    backward errors ``eta_r = |(A + theta B) x| / (|A x| + |theta| |B x|)`` and ``eta_l`` likewise
    for ``w^H`` (Higham & Higham, "Structured backward error and condition of generalized
    eigenvalue problems", SIAM J. Matrix Anal. Appl. 20(2), 1998, for the backward error). This is
    an *empirical* bound, not a rigorous one: the rigorous first-order bound ``|w| |r| / |w^H B x|``
    was 1e4-1e11 1/s on PEGASUS (|u| |v| / |u^H B v| ~ 1e10, the states' mixed units); over a
    replayed sizing (3826 estimates) ``|theta - lambda| <= 1.6 max(eta_r, eta_l) |theta|``, so the
    factor 10 leaves a 6x margin (docs/flutter.md).
    An estimate is ``trusted`` when the mode is isolated (bound < half the distance to every other
    Ritz value), oscillatory, inside the cold window's disc with its bound, and its MAC with the
    history vector is at least ``min_mac`` (Ritz pairs matched to the history modes by an optimal
    assignment of the MAC). ``unloaded``: trusted, and the loaded fraction plus the vector's error
    estimate (bound / gap) below half ``neutral_fraction`` (the mode stays out of the aggregate).
    ``basis``: ``(V, U)`` to project on instead of the history's vectors (this design's modes at the
    previous speed, :func:`damping_constraint`); the estimates are still matched to, and trusted by
    their MAC with, the history modes ``prev`` (a history mode left unmatched is not trusted). Over
    the replayed sizing these estimates' error was at most 0.026 max(eta_r, eta_l) |theta|."""
    V, U = (prev.right, prev.left) if basis is None else basis
    k = prev.right.shape[1]
    if enrich:
        # one block inverse-iteration step with one LU at the window's shift: the basis [V, (A + s B)^-1 B V]
        # (and the left one alike) holds the new modes far better than the old vectors alone
        lu = _lu(sp.csc_matrix(A + complex(window[1]) * B, dtype=complex))
        V2 = lu.solve(np.asarray(B @ V, dtype=complex))
        U2 = lu.solve(np.asarray(B.conj().T @ U, dtype=complex), trans="H")
        V = np.linalg.qr(np.column_stack([V, V2]))[0]
        U = np.linalg.qr(np.column_stack([U, U2]))[0]
    pen = pencil_lu.pencil(A, B)      # the sparse products in C (same summation order), else SciPy's
    AV, BV = pen.products(V) if pen is not None else (A @ V, B @ V)
    UH = U.conj().T
    th, zl, yr = _small_eig(-(UH @ AV), UH @ BV)
    X, W = V @ yr, U @ zl
    AX, BX = AV @ yr, BV @ yr
    # columns: (w^H A)^T, (w^H B)^T
    WA, WB = pen.products(W.conj(), trans=True) if pen is not None else (A.T @ W.conj(), B.T @ W.conj())
    with np.errstate(divide="ignore", invalid="ignore"):   # (a non-finite Ritz value: inf bound, below)
        # the eight column norms in one call
        Z = np.concatenate([X, W, AX + BX * th, AX, BX, WA + WB * th, WA, WB], axis=1).view(float)
        nx, nw, nrx, nax, nbx, nrw, naw, nbw = np.sqrt(np.einsum("ij,ij->j", Z, Z).reshape(-1, 2).sum(axis=1)
                                                       ).reshape(8, -1)
        eta_r = nrx / (nax + np.abs(th) * nbx)
        eta_l = nrw / (naw + np.abs(th) * nbw)
        err = LAZY_ERROR_FACTOR * np.maximum(eta_r, eta_l) * np.abs(th)
    err = np.where(np.isfinite(err) & np.isfinite(th), err, np.inf)
    X, W = X / nx, W / nw
    ib = np.flatnonzero(bmask)
    w = np.sqrt(bmask[ib])[:, None]
    wv, wx = prev.right[ib] * w, X[ib] * w   # (k, k or 2k) MAC: history vs Ritz (beam rows only)
    mac = np.abs(wv.conj().T @ wx) ** 2 / np.outer(np.sum(np.abs(wv) ** 2, axis=0), np.sum(np.abs(wx) ** 2, axis=0))
    rows, cols = linear_sum_assignment(-mac)
    order = np.zeros(k, dtype=int)
    order[rows] = cols
    matched = np.zeros(k, dtype=bool)    # a basis of fewer vectors than history modes leaves some unmatched
    matched[rows] = True
    th_all = th
    th, X, W, err = th[order], X[:, order], W[:, order], err[order]
    mac = np.where(matched, mac[np.arange(k), order], 0.0)
    radius, sigma = window
    with np.errstate(invalid="ignore"):   # a non-finite estimate: NaN gap, so not trusted (below)
        dist = np.abs(th_all[None, :] - th[:, None])     # every Ritz value but the mode's own
        dist[np.arange(k), order] = np.inf
        gap = np.min(dist, axis=1, initial=np.inf)
    trusted = ((err < 0.5 * gap) & (th.imag - err > min_frequency) & (np.abs(th - sigma) + err < radius)
               & (mac >= min_mac) & np.isfinite(th))
    loaded = _loaded(X, mask, bmask)
    with np.errstate(divide="ignore", invalid="ignore"):
        unloaded = trusted & (loaded + err / gap < 0.5 * neutral_fraction)
    return _Ritz(th, X, W, err, mac, loaded, trusted, unloaded)


def _best_ritz(a: _Ritz, b: _Ritz) -> _Ritz:
    """Per history mode the estimate of ``a`` or ``b`` (two :func:`_ritz` projections on different
    bases, same history modes): ``b``'s where it is trusted and ``a``'s is not or has a larger bound."""
    use = b.trusted & (~a.trusted | (b.error < a.error))

    def pick(x, y):
        return np.where(use[None, :] if x.ndim == 2 else use, y, x)

    return _Ritz(*(pick(getattr(a, f), getattr(b, f)) for f in
                   ("lam", "right", "left", "error", "mac", "loaded", "trusted", "unloaded")))


def _warm_speed(system, p, q, prev, window, warm, bmask, min_frequency, static, static_options, negligible,
                other=None, x=None, A=None, B=None, skip=(), ritz=None):
    """Every tracked mode refined at one speed, or a string saying why the refinement is not trusted.
    ``negligible(lam)``: True when the mode's KS weight is below round-off; such a mode that turns
    real or leaves the window is dropped (the cold set drops it too) instead of failing.
    ``other``: this design's refined modes at another speed; a mode whose refinement from its
    history fails is retried from the mode of ``other`` with the largest MAC with its history
    (the modes change less with the speed than between SLSQP designs).
    ``skip``: indices of history modes not refined: their :class:`_Ritz` estimates (``ritz``) stand
    in (lazy refinement, :func:`damping_constraint`); a refined mode landing within a skipped
    estimate's bound fails the speed. ``x, A, B``: the static state and pencil, if already made."""
    if x is None:
        x = static_state(system, p, q, prev.x0, **(static_options or {})) if static else prev.x0
    if A is None:
        A, B = linearize(system, p, q, x)
    radius, sigma = window
    w = np.sqrt(bmask)
    lams, vs, us, errs = [], [], [], []
    skip = set(int(j) for j in skip)
    for j in sorted(skip):
        lams.append(complex(ritz.lam[j]))
        vs.append(ritz.right[:, j])
        us.append(ritz.left[:, j])
        errs.append(float(ritz.error[j]))
        warm.n_skipped += 1
    for j in range(prev.eigenvalues.size):
        if j in skip:
            continue
        warm.n_refined += 1
        starts = [(prev.eigenvalues[j], prev.right[:, j], prev.left[:, j])]
        if ritz is not None and ritz.trusted[j]:   # the Ritz pair first: it follows the modes' mixing
            starts.insert(0, (ritz.lam[j], ritz.right[:, j], ritz.left[:, j]))
        if other is not None and other.eigenvalues.size:
            i = int(np.argmax([_beam_mac(prev.right[:, j], other.right[:, k], w) for k in range(other.eigenvalues.size)]))
            starts.append((other.eigenvalues[i], other.right[:, i], other.left[:, i]))
        for lam0, v0, u0 in starts:
            v, u, lam, ok = refine_pair(A, B, lam0, v0, u0, tol=warm.tol)
            if lam.imag < 0.0:   # landed on the conjugate: A, B are real, (conj v, conj u) belong to conj lambda
                v, u, lam = v.conj(), u.conj(), lam.conjugate()
            mac = _beam_mac(prev.right[:, j], v, w) if ok else 0.0
            if ok and mac >= warm.min_mac:
                break
        if not ok:
            return f"refinement of {prev.eigenvalues[j]:.3f} not converged at {prev.speed:.1f} m/s"
        if mac < warm.min_mac:
            return f"MAC {mac:.3f} < {warm.min_mac} ({prev.eigenvalues[j]:.3f} -> {lam:.3f}) at {prev.speed:.1f} m/s"
        if abs(lam.imag) <= min_frequency or abs(lam - sigma) > radius * (1.0 + 1e-6):
            if negligible(lam) and negligible(prev.eigenvalues[j]):
                warm.dropped += 1
                continue
            what = "turned real" if abs(lam.imag) <= min_frequency else "left the eigen window"
            return f"mode {prev.eigenvalues[j]:.3f} {what} ({lam:.3f}) at {prev.speed:.1f} m/s"
        if any(abs(lam - lk) <= 1e-6 * abs(lam) + ek for lk, ek in zip(lams, errs)):
            return f"two modes refined to {lam:.3f} at {prev.speed:.1f} m/s"
        lams.append(lam)
        vs.append(v)
        us.append(u)
        errs.append(0.0)
    n = system.n_state
    return SpeedModes(prev.speed, p, q, x, A, B, np.array(lams, dtype=complex),
                      np.array(vs).T.reshape(n, len(vs)), np.array(us).T.reshape(n, len(us)),
                      np.array(errs, dtype=float))


def _track_over_speed(system, p, q, src, V, window, warm, bmask, min_frequency, static, static_options, negligible,
                      x=None, A=None, B=None):
    """Every oscillatory mode of ``src`` (this design's set at another speed) refined at speed ``V``
    (:func:`_warm_speed` with ``src`` as the history: mode tracking over the speed, as the flutter
    sweep does, MAC with ``src``'s vectors, inside ``window``), or a string saying why not."""
    sm = _warm_speed(system, p, q, replace(src, speed=float(V)), window, warm, bmask, min_frequency, static,
                     static_options, negligible, x=x, A=A, B=B)
    if not isinstance(sm, str):
        warm.n_speed_track += 1
    return sm


def damping_constraint(system, params_at, speeds, *, aero_mask, beam_mask, rho_ks=100.0, margin=0.0,
                       measure="sigma", min_frequency=1e-3, neutral_fraction=1e-2, static=True, gradient=True,
                       warm_start: WarmStart | None = None, **eig_options) -> DampingConstraint:
    """KS over speeds and modes of ``sigma + margin`` (1/s) or ``margin - zeta`` (``measure``;
    module docstring) and its exact gradient with respect to the packed parameters ``p``
    (``params_at(V) -> (p, q)``; the gradient sums the speeds' contributions: meaningful for the
    entries common to every speed, e.g. the beam's). ``gradient=False``: the value only (the
    gradient later from the result: :func:`constraint_gradient`).

    The modes at each speed: every oscillatory eigenvalue of the eigen window (``|Im|`` >
    ``min_frequency`` rad/s) whose eigenvector's aerodynamic-state part (``aero_mask``: 1 on those
    states) is above ``neutral_fraction`` of its displacement / rotation part (``beam_mask``); the
    in-plane bending modes, which strip theory barely loads (Re lambda ~ 1e-7 1/s for every design;
    PEGASUS: ratio 5e-5 - 4e-4, loaded modes 0.19 - 0.53), are left out. No tracking between speeds
    (a coarse set of speeds is too far apart for MAC tracking near a coalescence).

    ``warm_start``: a :class:`WarmStart` carried between calls (e.g. by an optimizer's
    evaluations): the previous evaluation's modes are refined instead of a new eigen window
    when its rules allow (same value to round-off; see :class:`WarmStart`).
    """
    if measure not in MEASURES:
        raise ValueError(f"measure = {measure!r}; allowed: {', '.join(MEASURES)}")
    v = check_speeds(speeds)
    mask = np.asarray(aero_mask, dtype=float).ravel()
    bmask = np.asarray(beam_mask, dtype=float).ravel()
    pq = [params_at(float(V)) for V in v]
    tracked, cold = None, True
    ws = warm_start
    key = (tuple(v), rho_ks, margin, measure, min_frequency, neutral_fraction, static, repr(sorted(eig_options.items())))
    if ws is not None:
        reason = None
        if ws.tracked is None or ws.key != key:
            reason = "no history"
        elif min(ws.window_age) + 1 >= ws.refresh:   # every speed's window is stale
            reason = f"refresh after {ws.refresh} evaluations"
        elif ws.step_too_large(system, [p for p, _ in pq]):
            reason = f"design step > {ws.max_step:g} relative"
        else:
            if len(ws.history) > 1:   # the stored design nearest this one (line searches jump back)
                ws.tracked, ws.modes = min(ws.history, key=lambda h: ws.distance(system, pq[0][0], h[0]))[1:]
            tracked = []
            g_prev = np.concatenate([_measure(sm.eigenvalues, measure, margin) for sm in ws.modes])
            cut = float(np.max(g_prev)) - NEGLIGIBLE_KS / rho_ks

            def negligible(lam):
                return float(_measure(np.atleast_1d(lam), measure, margin)[0]) < cut

            sopt = eig_options.get("static_options")
            from wingmdao.stability.eigen import linearize, static_state

            def g_up(lam, err):   # the measure at the upper end of an eigenvalue error bound
                lam = np.atleast_1d(lam)
                dg = err if measure == "sigma" else 2.0 * err / np.maximum(np.abs(lam) - err, 1e-300)
                return _measure(lam, measure, margin) + dg

            def cold_at(k, why):
                # this speed only: the full window (the cold path's value there)
                ws.reasons.append(why)
                ws.n_speed_cold += 1
                p, q = pq[k]
                sm, win = _cold_speed(system, p, q, ws.tracked[k].x0, v[k], mask, bmask, min_frequency,
                                      neutral_fraction, static, eig_options)
                ws.n_windows += 1
                sigma = complex(eig_options.get("sigma", 0.0))
                ws.cold_window[k] = (float(np.max(np.abs(win - sigma))), sigma)
                ws.cold_p[k] = p
                ws.window_age[k] = -1   # 0 after this evaluation
                ws.history = []   # older designs' sets may lack a mode this window found
                return sm

            # a speed whose last window is `refresh` evaluations old gets a new one (the others stay warm)
            stale = {k for k in range(len(pq)) if ws.window_age[k] + 1 >= ws.refresh}
            pre, skips = [], []
            for k, (p, q) in enumerate(pq):
                if k in stale:
                    pre.append((None, None, None, None))
                    continue
                prev = ws.tracked[k]
                xk = static_state(system, p, q, prev.x0, **(sopt or {})) if static else prev.x0
                Ak, Bk = linearize(system, p, q, xk)
                rz = (_ritz(Ak, Bk, prev, ws.cold_window[k], mask, bmask, min_frequency, ws.min_mac, neutral_fraction)
                      if ws.lazy and prev.eigenvalues.size else None)
                pre.append((xk, Ak, Bk, rz))
            low = -np.inf
            if ws.lazy:
                # a lower bound of g_max from the trusted estimates of clearly loaded modes; a mode is
                # refined unless trusted and unloaded with its bound, or its g (upper end of its bound)
                # is LAZY_KS / rho below that lower bound
                low = -np.inf
                for _, _, _, rz in pre:
                    if rz is not None:
                        sure = rz.trusted & (rz.loaded >= 10.0 * neutral_fraction)
                        if np.any(sure):
                            low = max(low, float(np.max(g_up(rz.lam[sure], -rz.error[sure]))))

            def skip_set(rz):
                if rz is None or not ws.lazy:
                    return set()
                weak = g_up(rz.lam, rz.error) < low - LAZY_KS / rho_ks
                return set(np.flatnonzero(rz.trusted & (rz.unloaded | weak)).tolist())

            skips = [skip_set(rz) for _, _, _, rz in pre]
            for k, (p, q) in enumerate(pq):
                if k in stale:
                    tracked.append(cold_at(k, f"refresh of {v[k]:.1f} m/s after {ws.refresh} evaluations"))
                    continue
                xk, Ak, Bk, rz = pre[k]
                near = tracked[k - 1] if k > 0 else None
                if rz is not None and isinstance(near, SpeedModes) and near.eigenvalues.size:
                    # second estimate on this design's modes at the previous speed (the lightly loaded
                    # in-plane modes barely change with the speed); per mode the better trusted one
                    rz = _best_ritz(rz, _ritz(Ak, Bk, ws.tracked[k], ws.cold_window[k], mask, bmask, min_frequency,
                                              ws.min_mac, neutral_fraction, basis=(near.right, near.left)))
                    pre[k] = (xk, Ak, Bk, rz)
                    skips[k] = skip_set(rz)
                tracked.append(_warm_speed(system, p, q, ws.tracked[k], ws.cold_window[k], ws, bmask, min_frequency,
                                           static, sopt, negligible, x=xk, A=Ak, B=Bk, skip=skips[k], ritz=rz))
            good = [k for k, sm in enumerate(tracked) if not isinstance(sm, str)]
            # speeds whose set this evaluation descends from a window of *this* design (below)
            fresh = set(stale)

            for k, (p, q) in enumerate(pq):
                if not isinstance(tracked[k], str):
                    continue
                ws.reasons.append(tracked[k])
                sm = tracked[k]
                skips[k] = set()
                if good:   # retry from this design's modes at the nearest speed that worked
                    near = tracked[min(good, key=lambda i: abs(i - k))]
                    sm = _warm_speed(system, p, q, ws.tracked[k], ws.cold_window[k], ws, bmask, min_frequency,
                                     static, sopt, negligible, other=near, x=pre[k][0], A=pre[k][1], B=pre[k][2])
                    ws.n_speed_retry += 1
                if isinstance(sm, str) and fresh:
                    # a step too large for the history (~8x): track every oscillatory mode of this
                    # design's window set at the nearest such speed to this speed instead (mode tracking over
                    # the speed, as the flutter sweep does; MAC with that set's vectors)
                    j = min(fresh, key=lambda i: abs(i - k))
                    ws.reasons.append(f"{v[k]:.1f} m/s from this design's window set at {v[j]:.1f} m/s")
                    sm = _track_over_speed(system, p, q, tracked[j], v[k], ws.cold_window[k], ws, bmask,
                                           min_frequency, static, sopt, negligible, x=pre[k][0], A=pre[k][1],
                                           B=pre[k][2])
                    if not isinstance(sm, str):
                        ws.window_age[k] = ws.window_age[j]
                        fresh.add(k)
                if isinstance(sm, str):
                    sm = cold_at(k, sm)
                    fresh.add(k)
                tracked[k] = sm
                good.append(k)   # later failed speeds retry from this one (a big step fails them all)
            # lazy refinement, second check: every skipped, possibly loaded mode must lie LAZY_KS / rho
            # below the exact g_max of the refined loaded modes (else refine it too and check again)
            for _ in range(len(pq) * 8):
                if not any(skips):
                    break
                g_max = -np.inf
                for sm in tracked:
                    ref = (sm.error == 0.0) & (_loaded(sm.right, mask, bmask) > neutral_fraction)
                    if np.any(ref):
                        g_max = max(g_max, float(np.max(_measure(sm.eigenvalues[ref], measure, margin))))
                redo = False
                for k, sm in enumerate(tracked):
                    if not skips[k]:
                        continue
                    rz = pre[k][3]
                    bad = {j for j in skips[k] if not rz.unloaded[j]
                           and float(g_up(rz.lam[j], rz.error[j])[0]) >= g_max - LAZY_KS / rho_ks}
                    if not bad:
                        continue
                    redo = True
                    ws.n_lazy_redo += 1
                    skips[k] -= bad
                    p, q = pq[k]
                    sm = _warm_speed(system, p, q, ws.tracked[k], ws.cold_window[k], ws, bmask, min_frequency,
                                     static, sopt, negligible, x=pre[k][0], A=pre[k][1], B=pre[k][2],
                                     skip=skips[k], ritz=rz)
                    if isinstance(sm, str):
                        skips[k] = set()
                        sm = cold_at(k, sm)
                    tracked[k] = sm
                if not redo:
                    break
        if tracked is not None:
            cold = False
            ws.since_cold += 1
            ws.window_age = [a + 1 for a in ws.window_age]
            ws.n_warm += 1
        else:
            ws.reasons.append(reason)
    if tracked is None:
        tracked, windows, x = [], [], None
        sigma = complex(eig_options.get("sigma", 0.0))
        # the first evaluation of a warm start: one window, at the lowest speed; each later speed tracks
        # the previous speed's set (every oscillatory mode refined on its pencil, MAC with that set, the
        # first window's disc), and gets a window of its own only when that fails (a refresh or a step
        # rule always gives every speed its window)
        track = ws is not None and reason == "no history"
        for k, ((p, q), V) in enumerate(zip(pq, v)):
            sm = None
            if track and k > 0:
                sm = _track_over_speed(system, p, q, tracked[k - 1], V, windows[k - 1], ws, bmask, min_frequency,
                                       static, eig_options.get("static_options"), lambda lam: False)
                if isinstance(sm, str):
                    ws.reasons.append(sm)
                    sm = None
                else:
                    windows.append(windows[k - 1])
            if sm is None:
                sm, win = _cold_speed(system, p, q, x, V, mask, bmask, min_frequency, neutral_fraction, static,
                                      eig_options)
                windows.append((float(np.max(np.abs(win - sigma))), sigma))
                if ws is not None:
                    ws.n_windows += 1
            x = sm.x0
            tracked.append(sm)
        if ws is not None:
            ws.key, ws.cold_p, ws.cold_window = key, [p for p, _ in pq], windows
            ws.history = []
            ws.since_cold, ws.n_cold = 0, ws.n_cold + 1
            ws.window_age = [0] * len(pq)
    modes = [_aggregated(sm, V, mask, bmask, neutral_fraction) for sm, V in zip(tracked, v)]
    if ws is not None:
        ws.tracked, ws.modes = tracked, modes
        ws.history = (ws.history + [(pq[0][0], tracked, modes)])[-ws.keep:]
    lams = [sm.eigenvalues for sm in modes]
    lam_all = np.concatenate(lams)
    zetas = -lam_all.real / np.abs(lam_all)
    gs = _measure(lam_all, measure, margin)
    value, w = ks_aggregate(gs, rho_ks)
    errs = [np.zeros(sm.eigenvalues.size) if sm.error is None else sm.error for sm in modes]
    res = DampingConstraint(float(value), None, v, lams, zetas, modes, w, measure, cold, errs)
    if gradient:
        res.gradient = constraint_gradient(system, res, static=static)
    return res


def constraint_gradient(system, res: DampingConstraint, *, static=True, min_weight=1e-13) -> np.ndarray:
    """d KS / d p of a :func:`damping_constraint` result from its stored modes: per speed one LU
    of ``A`` (the static-state term, one ``A^T`` solve per mode), per mode one evaluation of the
    second-derivative function and one reverse-mode product ``w^T dR/dp``
    (:class:`_GradientFunctions`, compiled once evaluated often). Modes whose KS weight (the
    weights sum to 1) is at most ``min_weight`` are skipped: their contribution is that weight
    times their eigenvalue derivative (1e-13: below round-off of the gradient; 0 keeps all)."""
    fun = gradient_functions(system)
    grad = np.zeros(system.n_param)
    k = 0
    for sm in res.modes:
        nk = sm.eigenvalues.size
        wk = res.weights[k:k + nk]
        k += nk
        use = np.flatnonzero(wk > min_weight)
        if use.size == 0:
            continue
        lu = _lu(sm.A) if static else None
        for j in use:
            lam, v, u = sm.eigenvalues[j], sm.right[:, j], sm.left[:, j]
            ds, gx = fun.ds(sm.x0, sm.p, sm.q, v, u, lam)
            if static:
                wv = lu.solve(gx.real, trans="T") + 1j * lu.solve(gx.imag, trans="T")
                ds = ds - fun.static_term(sm.x0, sm.p, sm.q, wv)
            dl = -ds / np.vdot(u, sm.B @ v)
            dg = dl.real if res.measure == "sigma" else -damping_ratio_gradient(lam, dl)[1]
            grad += wk[j] * dg
    return grad
