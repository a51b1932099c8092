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

from dataclasses import dataclass

import casadi as ca
import numpy as np
import scipy.sparse as sp

from wingmdao.stability.eigen import check_speeds, derived_definition
from wingmdao.stability.modes import (MEASURES, Selection, SpeedModes, aggregated, cold_set, left_right_vectors,
                                      refine_pair)
from wingmdao.stability.pencil_lu import superlu
from wingmdao.stability.warmstart import WarmStart
from wingmdao.timemarch.system import derived
from wingmdao.utils import casadi_cache as cc
from wingmdao.utils.ks import ks_aggregate

__all__ = ["DampingConstraint", "SpeedModes", "WarmStart", "constraint_gradient", "damping_constraint",
           "damping_ratio_gradient", "eigenvalue_gradient", "gradient_functions", "ks_aggregate",
           "left_right_vectors", "pencil_gradient_function", "refine_pair"]

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
    (:func:`~wingmdao.utils.casadi_cache.signature_stub`), so the interpreted second-derivative functions (0.9 s of CasADi
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
        stubs = (cc.signature_stub(self.names[0], vec + [(n, 1)] * 4 + [(1, 1)] * 2, [(2, npar), (2, n)]),
                 cc.signature_stub(self.names[1], vec + [(n, 2)], [(2, npar)]))
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
    """The :class:`_GradientFunctions` of ``system`` (built once per system).

    Parameters
    ----------
    system : ResidualSystem
        The residual system.

    Returns
    -------
    _GradientFunctions
        The functions.
    """
    return derived(system, "eigenvalue_gradient_functions", _GradientFunctions)


def pencil_gradient_function(system) -> ca.Function:
    """CasADi function ``(x, xdot, p, q, vr, vi, ur, ui, lam_r, lam_i) -> (ds/dp, ds/dx)`` (each as
    [real; imaginary] rows) of ``s = u^H (dR/dx v + lambda dR/dxdot v)``; built once per system.

    Parameters
    ----------
    system : ResidualSystem
        The residual system.

    Returns
    -------
    casadi.Function
        The function.
    """
    return gradient_functions(system).interpreted


def eigenvalue_gradient(system, p, q, x0, lam, v, u, *, A=None, B=None, static=True) -> np.ndarray:
    """d lambda / d p (complex, one entry per packed parameter) of a simple eigenvalue with right /
    left vectors v, u at the state x0; ``static``: x0 is the static solution and moves with p.

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    p, q : numpy.ndarray
        Packed parameters and forcing.
    x0 : numpy.ndarray
        State linearised about.
    lam : complex
        The eigenvalue (1/s).
    v, u : numpy.ndarray
        Right and left eigenvectors.
    A, B : scipy.sparse.csc_matrix or None, optional
        dR/dx and dR/dxdot at ``x0``; None linearises.
    static : bool, optional
        ``x0`` is the static solution and moves with ``p``.

    Returns
    -------
    numpy.ndarray
        d lambda / d p (complex).
    """
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
        lu = superlu(A)
        w = lu.solve(gx.real, trans="T") + 1j * lu.solve(gx.imag, trans="T")
        ds = ds - fun.static_term(x0, p, q, w)
    return -ds / np.vdot(u, B @ v)


def damping_ratio_gradient(lam, dlam):
    """``zeta = -Re lambda / |lambda|`` and its gradient from ``dlam`` (d lambda / dp).

    Parameters
    ----------
    lam : complex or array_like
        Eigenvalue(s) (1/s).
    dlam : numpy.ndarray
        d lambda / d p.

    Returns
    -------
    tuple
        (zeta, d zeta / d p).
    """
    s, w = lam.real, lam.imag
    r = abs(lam)
    dr = (s * dlam.real + w * dlam.imag) / r
    return -s / r, -(dlam.real * r - s * dr) / r**2


@dataclass
class DampingConstraint:
    """Value and gradient of the aggregated damping constraint, with what it aggregated.

    Parameters
    ----------
    value : float
        KS of g, <= 0 when satisfied.
    gradient : numpy.ndarray
        d value / d p (packed parameters, summed over the speeds).
    speeds : numpy.ndarray
        Airspeeds (m/s).
    eigenvalues : list
        Per speed, the aggregated eigenvalues (1/s).
    damping_ratio : numpy.ndarray
        Damping ratio zeta of every aggregated mode, speed by speed (-).
    modes : list or None, optional
        Per speed, the :class:`~wingmdao.stability.modes.SpeedModes` (for the gradient).
    weights : numpy.ndarray or None, optional
        dKS/dg of every aggregated mode, speed by speed.
    measure : {"sigma", "ratio"}, optional
        The measure aggregated.
    cold : bool, optional
        True for a full eigen window, False for a warm-started refinement.
    errors : list or None, optional
        Per speed, the error estimate of each aggregated eigenvalue (1/s; 0 when refined).
    """

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

    ``warm_start``: a :class:`~wingmdao.stability.warmstart.WarmStart` carried between calls (e.g.
    by an optimizer's evaluations): the previous evaluation's modes are refined instead of a new
    eigen window when its rules allow (same value to round-off; see its docstring).

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    params_at : callable
        ``params_at(V) -> (p, q)``.
    speeds : array_like
        Airspeeds (m/s).
    aero_mask : numpy.ndarray
        1 on the aerodynamic states.
    beam_mask : numpy.ndarray
        Weights of the beam's displacements and rotations.
    rho_ks : float, optional
        KS aggregation parameter.
    margin : float, optional
        Margin added to the measure.
    measure : {"sigma", "ratio"}, optional
        Aggregate Re(lambda) + margin (1/s) or margin - zeta.
    min_frequency : float, optional
        Oscillatory above this ``|Im|`` (rad/s).
    neutral_fraction : float, optional
        Loaded above this fraction of aerodynamic to beam part (-).
    static : bool, optional
        Linearise about the static solution.
    gradient : bool, optional
        Compute the gradient now.
    warm_start : WarmStart or None, optional
        History carried between calls.
    **eig_options
        Passed to :func:`~wingmdao.stability.eigen.eigenmodes`.

    Returns
    -------
    DampingConstraint
        Value, gradient and the aggregated modes.
    """
    if measure not in MEASURES:
        raise ValueError(f"measure = {measure!r}; allowed: {', '.join(MEASURES)}")
    v = check_speeds(speeds)
    sel = Selection(np.asarray(aero_mask, dtype=float).ravel(), np.asarray(beam_mask, dtype=float).ravel(),
                    min_frequency, neutral_fraction, static, measure, margin, rho_ks, eig_options)
    pq = [params_at(float(V)) for V in v]
    ws = warm_start
    if ws is None:
        tracked, cold = cold_set(system, pq, v, sel), True
    else:
        key = (tuple(v), rho_ks, margin, measure, min_frequency, neutral_fraction, static,
               repr(sorted(eig_options.items())))
        tracked, cold = ws.modes_at(system, pq, v, sel, key)
    modes = [aggregated(sm, V, sel.aero_mask, sel.beam_mask, neutral_fraction) for sm, V in zip(tracked, v)]
    if ws is not None:
        ws.remember(pq, tracked, modes)
    lams = [sm.eigenvalues for sm in modes]
    lam_all = np.concatenate(lams)
    zetas = -lam_all.real / np.abs(lam_all)
    gs = sel.g(lam_all)
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
    times their eigenvalue derivative (1e-13: below round-off of the gradient; 0 keeps all).

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    res : DampingConstraint
        A result of :func:`damping_constraint`.
    static : bool, optional
        The modes were linearised about the static solution.
    min_weight : float, optional
        KS weight at or below which a mode is skipped.

    Returns
    -------
    numpy.ndarray
        d KS / d p.
    """
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
        lu = superlu(sm.A) if static else None
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
