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
class DampingConstraint:
    """Value and gradient of the aggregated damping constraint, with what it aggregated."""

    value: float                     # KS_rho(g), <= 0 when satisfied
    gradient: np.ndarray             # d value / d p (packed parameters, summed over the speeds)
    speeds: np.ndarray               # m/s
    eigenvalues: list                # per speed: the aggregated eigenvalues (complex array)
    damping_ratio: np.ndarray        # every aggregated mode's zeta, speed by speed


MEASURES = ("sigma", "ratio")


def damping_constraint(system, params_at, speeds, *, aero_mask, beam_mask, rho_ks=100.0, margin=0.0,
                       measure="sigma", min_frequency=1e-3, neutral_fraction=1e-2, static=True, gradient=True,
                       **eig_options) -> DampingConstraint:
    """KS over speeds and modes of ``sigma + margin`` (1/s) or ``margin - zeta`` (``measure``;
    module docstring) and its exact gradient with respect to the packed parameters ``p``
    (``params_at(V) -> (p, q)``; the gradient sums the speeds' contributions: meaningful for the
    entries common to every speed, e.g. the beam's).

    The modes at each speed: every oscillatory eigenvalue of the eigen window (|Im| >
    ``min_frequency`` rad/s) whose eigenvector's aerodynamic-state part (``aero_mask``: 1 on those
    states) is above ``neutral_fraction`` of its displacement / rotation part (``beam_mask``); the
    in-plane bending modes, which strip theory barely loads (Re lambda ~ 1e-7 1/s for every design;
    PEGASUS: ratio 5e-5 - 4e-4, loaded modes 0.19 - 0.53), are left out. No tracking between speeds
    (a coarse set of speeds is too far apart for MAC tracking near a coalescence).
    """
    from wingmdao.stability.eigen import check_speeds, eigenmodes, linearize

    if measure not in MEASURES:
        raise ValueError(f"measure = {measure!r}; allowed: {', '.join(MEASURES)}")
    v = check_speeds(speeds)
    mask = np.asarray(aero_mask, dtype=float).ravel()
    bmask = np.asarray(beam_mask, dtype=float).ravel()
    lams, zetas, gs, dgs, x = [], [], [], [], None
    for V in v:
        p, q = params_at(float(V))
        m = eigenmodes(system, p, q, x, static=static, **eig_options)
        x = m.x0
        share = np.linalg.norm(m.vectors * mask[:, None], axis=0) / np.linalg.norm(m.vectors * bmask[:, None], axis=0)
        keep = np.flatnonzero((m.frequency > min_frequency) & (share > neutral_fraction))
        if keep.size == 0:
            raise ValueError(f"no aerodynamically loaded oscillatory mode at {V} m/s in the eigen window")
        A, B = linearize(system, p, q, m.x0)
        row_l = []
        for j in keep:
            vec, uvec, lj = left_right_vectors(A, B, m.eigenvalues[j])
            z = -lj.real / abs(lj)
            row_l.append(lj)
            zetas.append(z)
            gs.append(lj.real + margin if measure == "sigma" else margin - z)
            if gradient:
                dl = eigenvalue_gradient(system, p, q, m.x0, lj, vec, uvec, A=A, B=B, static=static)
                dgs.append(dl.real if measure == "sigma" else -damping_ratio_gradient(lj, dl)[1])
        lams.append(np.array(row_l))
    value, w = ks_aggregate(np.array(gs), rho_ks)
    grad = (w @ np.array(dgs)) if gradient else None
    return DampingConstraint(float(value), grad, v, lams, np.array(zetas))
