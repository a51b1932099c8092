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
its KS weight is ~exp(-rho |g - g_max|)).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

_FUNCTIONS: dict = {}


def pencil_gradient_function(system) -> ca.Function:
    """CasADi function ``(x, xdot, p, q, vr, vi, ur, ui, lam_r, lam_i) -> (ds/dp, ds/dx)`` (each as
    [real; imaginary] rows) of ``s = u^H (dR/dx v + lambda dR/dxdot v)``; built once per system."""
    key = id(system)
    if key in _FUNCTIONS and _FUNCTIONS[key][0] is system:
        return _FUNCTIONS[key][1]
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
    jp = ca.jacobian(s, p)
    jx = ca.jacobian(s, x)
    fun = ca.Function("pencil_gradient", [x, xd, p, q, vr, vi, ur, ui, lr, li], [jp, jx])
    _FUNCTIONS[key] = (system, fun)
    return fun


def left_right_vectors(A, B, lam, *, iterations=3, rel_shift=1e-10):
    """Right and left eigenvectors ``(v, u)`` (unit 2-norm) of ``(A + lambda B) v = 0`` and the
    Rayleigh-quotient eigenvalue ``-u^H A v / u^H B v``, by inverse iteration with the shift
    ``lambda (1 + rel_shift)`` (``lambda`` from an eigen-solver)."""
    A, B = sp.csc_matrix(A), sp.csc_matrix(B)
    n = A.shape[0]
    s = complex(lam) * (1.0 + rel_shift) + rel_shift
    lu = spla.splu(sp.csc_matrix(A + s * B, dtype=complex))
    rng = np.random.default_rng(0)
    v = rng.standard_normal(n) + 1j * rng.standard_normal(n)
    u = v.copy()
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
    jp, jx = pencil_gradient_function(system)(x0, xd, p, q, v.real, v.imag, u.real, u.imag, lam.real, lam.imag)
    jp, jx = np.asarray(jp), np.asarray(jx)
    ds = jp[0] + 1j * jp[1]
    if static:
        gx = jx[0] + 1j * jx[1]
        lu = spla.splu(sp.csc_matrix(A))
        w = lu.solve(gx.real, trans="T") + 1j * lu.solve(gx.imag, trans="T")
        Rp = sp.csc_matrix(system.jac_inputs(x0, xd, p, q)[0])
        ds = ds - Rp.T @ w
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


MEASURES = ("sigma", "ratio")


def refine_pair(A, B, lam0, v0, u0, *, tol=1e-12, iterations=6, shifts=2, rel_shift=1e-10):
    """Right / left vectors and the two-sided Rayleigh quotient of the eigenvalue of
    ``(A + lambda B) v = 0`` nearest ``lam0``, by inverse iteration from ``v0, u0`` (the
    previous design's vectors): one sparse LU of ``A + s B`` per shift s (first ``lam0``, then the
    current quotient; at most ``shifts``), the left vector from the transposed solve with the same
    LU. Converged when two quotients agree to ``tol`` relative. Returns ``(v, u, lam, converged)``.
    (Two-sided Rayleigh-quotient iteration: B. N. Parlett, "The Rayleigh quotient iteration and
    some generalizations for nonnormal matrices", Math. Comp. 28(127), 1974.)"""
    BH = B.conj().T
    v, u = np.asarray(v0, complex), np.asarray(u0, complex)
    lam_old, lam = complex(lam0), complex(lam0)
    for _ in range(int(shifts)):
        s = lam * (1.0 + rel_shift) + rel_shift
        lu = spla.splu(sp.csc_matrix(A + s * B, dtype=complex))
        for _ in range(int(iterations)):
            v = lu.solve(np.asarray(B @ v))
            v /= np.linalg.norm(v)
            u = lu.solve(np.asarray(BH @ u), trans="H")
            u /= np.linalg.norm(u)
            lam = complex(-np.vdot(u, A @ v) / np.vdot(u, B @ v))
            if abs(lam - lam_old) <= tol * abs(lam):
                return v, u, lam, True
            lam_old = lam
    return v, u, lam, False


class WarmStart:
    """History of :func:`damping_constraint` between evaluations (warm start; docs/flutter.md).

    After a cold evaluation (the full sparse eigen window at every speed) it keeps, per speed, the
    aggregated modes (eigenvalue, right and left vectors) and the window. The next evaluation
    refines those modes by :func:`refine_pair` instead of a new window, unless a rule asks for the
    full window again:

    * no history, or the speeds / options changed;
    * ``refresh`` evaluations since the last cold one;
    * the design moved too far from the last cold one: some parameter block (e.g. the stiffness
      matrices) changed by more than ``max_step`` of its largest entry;
    * a refinement failed: not converged, its beam-weighted MAC with the previous vector below
      ``min_mac``, the mode turned real or unloaded, it moved more than ``max_drift`` of its
      distance to the nearest other eigenvalue of the cold window (it may have swapped with it),
      two refined modes became the same eigenvalue, or it left the cold window's disc
      ``|lambda - sigma| < r`` (the cold set would have dropped it).

    A cold evaluation after a failed refinement redoes the whole evaluation, so the value is
    always that of a converged set; the warm value equals the cold one to round-off when the
    sets agree. Not detected: an oscillatory mode from outside the window entering it between
    two cold evaluations (its KS weight is ~exp(-rho (g_max - g)); the next cold evaluation
    picks it up).
    """

    def __init__(self, *, refresh=20, max_step=0.1, min_mac=0.9, max_drift=0.25, tol=1e-12):
        if int(refresh) < 1:
            raise ValueError(f"WarmStart refresh = {refresh}; allowed: an integer >= 1 (evaluations)")
        if not (0.0 < float(max_step) and 0.0 < float(min_mac) <= 1.0 and 0.0 < float(max_drift) < 1.0):
            raise ValueError(f"WarmStart: max_step = {max_step} (> 0), min_mac = {min_mac} (0, 1], "
                             f"max_drift = {max_drift} (0, 1) out of range")
        self.refresh, self.max_step, self.min_mac = int(refresh), float(max_step), float(min_mac)
        self.max_drift, self.tol = float(max_drift), float(tol)
        self.reset()

    def reset(self):
        """Forget the history: the next evaluation is cold."""
        self.key = None              # (speeds, options) of the history
        self.cold_p = None           # per speed: p of the last cold evaluation
        self.cold_window = None      # per speed: (eigenvalues of the cold window, radius, sigma)
        self.cold_lams = None        # per speed: the aggregated eigenvalues of the last cold evaluation
        self.modes = None            # per speed: SpeedModes of the last evaluation
        self.since_cold = 0
        self.n_cold = 0
        self.n_warm = 0
        self.reasons = []            # why each cold evaluation was made

    def step_too_large(self, system, p_list):
        """True when some parameter block moved by more than ``max_step`` of its largest entry
        (max-norm, relative) from the last cold design, at some speed."""
        from wingmdao.timemarch.system import layout

        for p, pc in zip(p_list, self.cold_p):
            for sl in layout(system.param_specs).values():
                scale = float(np.max(np.abs(pc[sl]), initial=0.0))
                if np.max(np.abs(p[sl] - pc[sl]), initial=0.0) > self.max_step * scale + 1e-9:  # 1e-9: round-off of zero blocks (SI)
                    return True
        return False


def _loaded(vectors, mask, bmask):
    return np.linalg.norm(vectors * mask[:, None], axis=0) / np.linalg.norm(vectors * bmask[:, None], axis=0)


def _cold_speed(system, p, q, x, V, mask, bmask, min_frequency, neutral_fraction, static, eig_options):
    from wingmdao.stability.eigen import eigenmodes, linearize

    m = eigenmodes(system, p, q, x, static=static, **eig_options)
    share = _loaded(m.vectors, mask, bmask)
    keep = np.flatnonzero((m.frequency > min_frequency) & (share > neutral_fraction))
    if keep.size == 0:
        raise ValueError(f"no aerodynamically loaded oscillatory mode at {V} m/s in the eigen window")
    A, B = linearize(system, p, q, m.x0)
    lams, vs, us = [], [], []
    for j in keep:
        vec, uvec, lj = left_right_vectors(A, B, m.eigenvalues[j])
        lams.append(lj)
        vs.append(vec)
        us.append(uvec)
    sm = SpeedModes(float(V), p, q, m.x0, A, B, np.array(lams), np.array(vs).T, np.array(us).T)
    return sm, m.eigenvalues


def _warm_speed(system, p, q, prev, window, cold_lams, warm, mask, bmask, min_frequency, neutral_fraction,
                static, static_options):
    """Refined modes at one speed, or a string saying why the refinement is not trusted."""
    from wingmdao.stability.eigen import linearize, static_state

    x = static_state(system, p, q, prev.x0, **(static_options or {})) if static else prev.x0
    A, B = linearize(system, p, q, x)
    win, radius, sigma = window
    lams, vs, us = [], [], []
    for j in range(prev.eigenvalues.size):
        v, u, lam, ok = refine_pair(A, B, prev.eigenvalues[j], prev.right[:, j], prev.left[:, j], tol=warm.tol)
        if not ok:
            return f"refinement not converged at {prev.speed:.1f} m/s"
        w = np.sqrt(bmask)
        mac = abs(np.vdot(w * prev.right[:, j], w * v)) ** 2 / (np.linalg.norm(w * prev.right[:, j]) ** 2
                                                                * np.linalg.norm(w * v) ** 2)
        if mac < warm.min_mac:
            return f"MAC {mac:.3f} < {warm.min_mac} at {prev.speed:.1f} m/s"
        if abs(lam.imag) <= min_frequency or _loaded(v[:, None], mask, bmask)[0] <= neutral_fraction:
            return f"mode {lam:.3f} turned real or unloaded at {prev.speed:.1f} m/s"
        lc = cold_lams[j]
        others = np.concatenate([win, win.conj()])
        others = others[np.abs(others - lc) > 1e-8 * abs(lc)]
        if abs(lam - lc) > warm.max_drift * float(np.min(np.abs(others - lc))):
            return f"mode {lc:.3f} drifted to {lam:.3f} at {prev.speed:.1f} m/s"
        if abs(lam - sigma) >= radius:
            return f"mode {lam:.3f} left the eigen window at {prev.speed:.1f} m/s"
        if any(abs(lam - lk) <= 1e-6 * abs(lam) for lk in lams):
            return f"two modes refined to {lam:.3f} at {prev.speed:.1f} m/s"
        lams.append(lam)
        vs.append(v)
        us.append(u)
    return SpeedModes(prev.speed, p, q, x, A, B, np.array(lams), np.array(vs).T, np.array(us).T)


def damping_constraint(system, params_at, speeds, *, aero_mask, beam_mask, rho_ks=100.0, margin=0.0,
                       measure="sigma", min_frequency=1e-3, neutral_fraction=1e-2, static=True, gradient=True,
                       warm_start: WarmStart | None = None, **eig_options) -> DampingConstraint:
    """KS over speeds and modes of ``sigma + margin`` (1/s) or ``margin - zeta`` (``measure``;
    module docstring) and its exact gradient with respect to the packed parameters ``p``
    (``params_at(V) -> (p, q)``; the gradient sums the speeds' contributions: meaningful for the
    entries common to every speed, e.g. the beam's). ``gradient=False``: the value only (the
    gradient later from the result: :func:`constraint_gradient`).

    The modes at each speed: every oscillatory eigenvalue of the eigen window (|Im| >
    ``min_frequency`` rad/s) whose eigenvector's aerodynamic-state part (``aero_mask``: 1 on those
    states) is above ``neutral_fraction`` of its displacement / rotation part (``beam_mask``); the
    in-plane bending modes, which strip theory barely loads (Re lambda ~ 1e-7 1/s for every design;
    PEGASUS: ratio 5e-5 - 4e-4, loaded modes 0.19 - 0.53), are left out. No tracking between speeds
    (a coarse set of speeds is too far apart for MAC tracking near a coalescence).

    ``warm_start``: a :class:`WarmStart` carried between calls (e.g. by an optimizer's
    evaluations): the previous evaluation's modes are refined instead of a new eigen window
    when its rules allow (same value to round-off; see :class:`WarmStart`).
    """
    from wingmdao.stability.eigen import check_speeds

    if measure not in MEASURES:
        raise ValueError(f"measure = {measure!r}; allowed: {', '.join(MEASURES)}")
    v = check_speeds(speeds)
    mask = np.asarray(aero_mask, dtype=float).ravel()
    bmask = np.asarray(beam_mask, dtype=float).ravel()
    pq = [params_at(float(V)) for V in v]
    modes, cold = None, True
    ws = warm_start
    key = (tuple(v), rho_ks, margin, measure, min_frequency, neutral_fraction, static, repr(sorted(eig_options.items())))
    if ws is not None:
        reason = None
        if ws.modes is None or ws.key != key:
            reason = "no history"
        elif ws.since_cold + 1 >= ws.refresh:
            reason = f"refresh after {ws.refresh} evaluations"
        elif ws.step_too_large(system, [p for p, _ in pq]):
            reason = f"design step > {ws.max_step:g} relative"
        else:
            modes = []
            for k, (p, q) in enumerate(pq):
                sm = _warm_speed(system, p, q, ws.modes[k], ws.cold_window[k], ws.cold_lams[k], ws, mask, bmask,
                                 min_frequency, neutral_fraction, static, eig_options.get("static_options"))
                if isinstance(sm, str):
                    reason, modes = sm, None
                    break
                modes.append(sm)
        if modes is not None:
            cold = False
            ws.since_cold += 1
            ws.n_warm += 1
        else:
            ws.reasons.append(reason)
    if modes is None:
        modes, windows, x = [], [], None
        sigma = complex(eig_options.get("sigma", 0.0))
        for (p, q), V in zip(pq, v):
            sm, win = _cold_speed(system, p, q, x, V, mask, bmask, min_frequency, neutral_fraction, static,
                                  eig_options)
            x = sm.x0
            modes.append(sm)
            windows.append((win, float(np.max(np.abs(win - sigma))), sigma))
        if ws is not None:
            ws.key, ws.cold_p, ws.cold_window = key, [p for p, _ in pq], windows
            ws.cold_lams = [sm.eigenvalues.copy() for sm in modes]
            ws.since_cold, ws.n_cold = 0, ws.n_cold + 1
    if ws is not None:
        ws.modes = modes
    lams = [sm.eigenvalues for sm in modes]
    lam_all = np.concatenate(lams)
    zetas = -lam_all.real / np.abs(lam_all)
    gs = lam_all.real + margin if measure == "sigma" else margin - zetas
    value, w = ks_aggregate(gs, rho_ks)
    res = DampingConstraint(float(value), None, v, lams, zetas, modes, w, measure, cold)
    if gradient:
        res.gradient = constraint_gradient(system, res, static=static)
    return res


def constraint_gradient(system, res: DampingConstraint, *, static=True, min_weight=0.0) -> np.ndarray:
    """d KS / d p of a :func:`damping_constraint` result from its stored modes: per speed one
    ``dR/dp``, one LU of ``A`` (the static-state term, one ``A^T`` solve per mode) and one CasADi
    second-derivative evaluation per mode (:func:`eigenvalue_gradient`). Modes whose KS weight is
    at most ``min_weight`` are skipped (0: none; their contribution is that weight times the
    eigenvalue derivative)."""
    fun = pencil_gradient_function(system)
    grad = np.zeros(system.n_param)
    k = 0
    for sm in res.modes:
        nk = sm.eigenvalues.size
        wk = res.weights[k:k + nk]
        k += nk
        use = np.flatnonzero(wk > min_weight)
        if use.size == 0:
            continue
        xd = np.zeros_like(sm.x0)
        lu = spla.splu(sp.csc_matrix(sm.A)) if static else None
        Rp = sp.csc_matrix(system.jac_inputs(sm.x0, xd, sm.p, sm.q)[0]) if static else None
        for j in use:
            lam, v, u = sm.eigenvalues[j], sm.right[:, j], sm.left[:, j]
            jp, jx = fun(sm.x0, xd, sm.p, sm.q, v.real, v.imag, u.real, u.imag, lam.real, lam.imag)
            jp, jx = np.asarray(jp), np.asarray(jx)
            ds = jp[0] + 1j * jp[1]
            if static:
                gx = jx[0] + 1j * jx[1]
                wv = lu.solve(gx.real, trans="T") + 1j * lu.solve(gx.imag, trans="T")
                ds = ds - Rp.T @ wv
            dl = -ds / np.vdot(u, sm.B @ v)
            dg = dl.real if res.measure == "sigma" else -damping_ratio_gradient(lam, dl)[1]
            grad += wk[j] * dg
    return grad
