"""KS of the 25.341(b) box stresses of a wing, and its exact gradient by the complex adjoint of the
frequency-response solves (docs/turbulence.md, "Gradient").

The constraint. At every box station i and corner point k the axial stress is linear in the
station's csn loads, s = S(t) L(x) (:func:`wingmdao.stability.frequency.stress_matrix`, t the four
wall thicknesses of the station). Its 1 g value s_1g = S L(x0) and its A-bar
A_k = sqrt(sum_j W_j |y_kj|^2), y_kj = (ds/dx) X_j, X_j = -(A + i omega_j E)^-1 G w_j, with the
weights W_j = (trapezoid weight, plus omega_0 at the first point) x Phi_1(omega_j) of the fixed
grid, give the design stresses s_1g +/- U_sigma A_k of 25.341(b)(1). Both signs of both are bounded
by the allowable: g = (+/- s_1g + U_sigma A) / sigma_allow - 1, aggregated by a KS function.

The gradient (exact for the discrete functional on the given grid). With abar_k = dKS/dA_k,
c_kj = abar_k W_j conj(y_kj) / A_k and sbar = dKS/ds_1g:

    dKS = sbar ds_1g + sum_j Re( c_j^T d(ds/dx) X_j ) - sum_j Re( lambda_j^T (dK_j X_j + dG w_j) ),
    K_j^T lambda_j = (ds/dx)^T c_j                                     (one adjoint solve per frequency)

The derivative terms are second derivatives of the residual and of the stress map contracted with
the solution and adjoint vectors (CasADi: a gradient of a ``jtimes``), split in real and imaginary
parts. The 1 g state x0 depends on the parameters through the static equations R(x0, 0, p, q_1g) = 0:
the total derivative adds -mu^T dR/dp with R_x^T mu = dKS/dx0 (one real adjoint solve).

Why the complex adjoint and not a Lyapunov form: the frequency-response solves already exist
(the analysis is made of them) and their adjoints cost one more solve per frequency with the same
factorization (transposed); a Lyapunov form needs a rational approximation of the von Karman
spectrum (more states, an approximated -5/3 tail) and dense O(n^3) Lyapunov solves and their
adjoints on the 441-state PEGASUS pencil.

The airspeed V enters the aerodynamics (the parameter ``airspeed`` of the system: the residual's
second derivatives above), the gust phases w_ij = exp(-i omega_j lag_i / V) and the von Karman
spectrum Phi(omega; V). Their derivatives: dw_ij / dV = w_ij i omega_j lag_i / V^2 (one more term
-Re(lambda_j^T G dw_j / dV) per frequency) and dW_j / dV = q_j dPhi_j / dV
(:func:`~wingmdao.loads.turbulence.von_karman_psd_airspeed_derivative`), giving
dA_k / dV = sum_j dW_j / dV |y_kj|^2 / (2 A_k): ``d_airspeed``, the total derivative at fixed Mach
number and density (``mach`` and ``density`` are parameters of their own).

Held fixed: the frequency grid (it follows the modes, a piecewise-constant function of the
design). With a ``spectrum`` of the caller's, its airspeed dependence is not differentiated.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.beam.residual import STATE_BLOCKS
from wingmdao.beam.rotations import body_to_csn
from wingmdao.loads.turbulence import von_karman_psd, von_karman_psd_airspeed_derivative
from wingmdao.stability.frequency import LinearGustModel, ShiftedFactors, gust_columns, check_frequencies
from wingmdao.stability.sensitivity import ks_aggregate
from wingmdao.stress.box_stress import box_stresses
from wingmdao.timemarch.system import layout

#: corner axial stresses per station (the rows of the stress map)
N_POINTS = 4


def quadrature_weights(omega) -> np.ndarray:
    """Trapezoid weights of ``omega`` plus omega_0 at the first point (the part below the grid):
    sum_j q_j f_j is the A-bar integral of :func:`wingmdao.stability.frequency.spectral_integral`
    without its tail estimate.

    Parameters
    ----------
    omega : array_like
        Angular frequencies (rad/s).

    Returns
    -------
    numpy.ndarray
        The weights (rad/s).
    """
    w = check_frequencies(omega)
    q = np.zeros(w.size)
    d = np.diff(w)
    q[:-1] += 0.5 * d
    q[1:] += 0.5 * d
    q[0] += w[0]
    return q


class StressMap:
    """The corner axial stresses s (4 n) of every box station as a CasADi function of the state x
    and the walls t (n, 4): s_i = S(t_i) [T(theta_i) F_i; T(theta_i) M_i] (:func:`box_stresses`),
    with its first and second derivatives.

    Parameters
    ----------
    beam_index : numpy.ndarray
        (n, 18) flat indices of each node's beam states.
    width, height : array_like
        (n,) outer box dimensions (m).
    section_to_csn : array_like or None, optional
        (n, 3, 3) rotations from the sections' own axes to csn; None when they coincide.
    n_state : int or None, optional
        Number of states; None for the largest beam index + 1.
    sequence : str, optional
        Euler angle sequence of the jig frames.
    """

    def __init__(self, beam_index, width, height, section_to_csn=None, n_state=None, sequence="surface"):
        beam = np.asarray(beam_index)
        n = beam.shape[0]
        N = int(n_state if n_state is not None else beam.max() + 1)
        x = ca.SX.sym("x", N)
        t = ca.SX.sym("t", n, 4)
        st = STATE_BLOCKS
        out = []
        for i in range(n):
            th = x[beam[i, st["theta"]].tolist()]
            T = body_to_csn(th, sequence)
            F = T @ x[beam[i, st["F"]].tolist()]
            M = T @ x[beam[i, st["M"]].tolist()]
            R = None if section_to_csn is None else ca.DM(np.asarray(section_to_csn)[i])
            s = box_stresses(F, M, float(width[i]), float(height[i]), t[i, 0], t[i, 1], t[i, 2], t[i, 3], R)
            out += list(s["sigma_corner"])
        s = ca.vertcat(*out)
        a, b = ca.SX.sym("a", s.shape[0]), ca.SX.sym("b", N)
        bil = ca.dot(a, ca.jtimes(s, x, b))
        tv = ca.vec(t)
        self.n, self.N = n, N
        self.value = ca.Function("stress", [x, tv], [s, ca.jacobian(s, x), ca.jacobian(s, tv)])
        self.second = ca.Function("stress_second", [x, tv, a, b], [ca.gradient(bil, x), ca.gradient(bil, tv)])

    def walls(self, t):
        """(n, 4) walls -> the column-major vector of the CasADi functions.

        Parameters
        ----------
        t : array_like
            (n, 4) wall thicknesses (m).

        Returns
        -------
        numpy.ndarray
            Column-major vector.
        """
        return np.asarray(t, dtype=float).reshape(self.n, 4).T.ravel()


_SECOND: dict = {}
_MAPPED: dict = {}


def _mapped(fun, count):
    """``fun.map(count)``, built once per function and count."""
    key = (id(fun), int(count))
    if key not in _MAPPED or _MAPPED[key][0] is not fun:
        _MAPPED[key] = (fun, fun.map(int(count)))
    return _MAPPED[key][1]


def _residual_second(system):
    """CasADi (x, p, q, a, bx, bxd, bq) -> gradients in x and p of a^T (R_x bx + R_xdot bxd + R_q bq)
    at xdot = 0 (built once per system)."""
    key = id(system)
    if key in _SECOND and _SECOND[key][0] is system:
        return _SECOND[key][1]
    N, P, Q = system.n_state, system.n_param, system.n_forcing
    x, xd, p, q = ca.MX.sym("x", N), ca.MX.sym("xd", N), ca.MX.sym("p", P), ca.MX.sym("q", Q)
    a, bx, bxd, bq = ca.MX.sym("a", N), ca.MX.sym("bx", N), ca.MX.sym("bxd", N), ca.MX.sym("bq", Q)
    R = system.residual_function(x, xd, p, q)
    jv = ca.jtimes(R, ca.vertcat(x, xd, q), ca.vertcat(bx, bxd, bq))
    s = ca.dot(a, jv)
    g = ca.Function("g", [x, xd, p, q, a, bx, bxd, bq], [ca.gradient(s, x), ca.gradient(s, p)])
    fun = ca.Function("residual_second", [x, p, q, a, bx, bxd, bq],
                      g(x, ca.MX.zeros(N), p, q, a, bx, bxd, bq))
    fun = fun.expand()  # SX: evaluated 1.6x faster than the MX graph (PEGASUS, 490 columns)
    _SECOND[key] = (system, fun)
    return fun


@dataclass
class TurbulenceStressKS:
    """``value`` (KS), ``g`` (the design-stress constraints: +s_1g then -s_1g), ``a_bar`` (Pa per m/s)
    and ``stress_1g`` (Pa) of the corner points; with the gradient ``d_p`` (n_param,), ``d_walls``
    (n, 4) and ``d_airspeed`` (the total derivative with respect to V: aerodynamics, gust phases and
    spectrum; None when the system has no ``airspeed`` parameter).

    Parameters
    ----------
    value : float
        The KS.
    g : numpy.ndarray
        Design-stress constraints.
    a_bar : numpy.ndarray
        A-bar of the corner stresses (Pa per m/s).
    stress_1g : numpy.ndarray
        1 g corner stresses (Pa).
    d_p : numpy.ndarray or None, optional
        d value / d p.
    d_walls : numpy.ndarray or None, optional
        (n, 4) d value / d walls.
    d_airspeed : float or None, optional
        d value / d V.
    state_value : float or None, optional
        With ``state_outputs``: the KS of their ratios U_sigma A-bar / limit.
    state_ratio : numpy.ndarray or None, optional
        The ratios U_sigma A-bar / limit of the ``state_outputs``.
    state_d_p : numpy.ndarray or None, optional
        d state_value / d p.
    state_d_airspeed : float or None, optional
        d state_value / d V.
    """

    value: float
    g: np.ndarray
    a_bar: np.ndarray
    stress_1g: np.ndarray
    d_p: np.ndarray | None = None
    d_walls: np.ndarray | None = None
    d_airspeed: float | None = None
    state_value: float | None = None
    state_ratio: np.ndarray | None = None
    state_d_p: np.ndarray | None = None
    state_d_airspeed: float | None = None


def turbulence_stress_ks(system, p, q_static, model: LinearGustModel, stress: StressMap, walls, omega, *,
                         u_sigma, sigma_allow, rho_ks=50.0, gradient=True, spectrum=None,
                         state_outputs=None) -> TurbulenceStressKS:
    """The KS of the 25.341(b) corner design stresses and (``gradient``) its total derivative with
    respect to the packed parameters ``p`` and the walls.

    ``model``: the linear gust model about the static state ``model.x0`` of ``R(x, 0, p, q_static) = 0``
    (built with :func:`~wingmdao.stability.frequency.linear_gust_model` and the system's own gust
    input, its forcing ``q`` the linearisation's; found here as ``q_static`` with ``trim_active``
    0); ``omega`` (rad/s) the fixed grid; ``spectrum(omega)`` the one-sided gust PSD of unit sigma
    per rad/s (default: von Karman at the model's airspeed).

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    p : numpy.ndarray
        Packed parameters.
    q_static : numpy.ndarray
        Packed forcing of the static state (``trim_active`` 0).
    model : LinearGustModel
        The linear gust model.
    stress : StressMap
        The corner stress map.
    walls : array_like
        (n, 4) wall thicknesses (m).
    omega : array_like
        Angular frequencies (rad/s). (fixed grid)
    u_sigma : float
        Design intensity U_sigma (m/s).
    sigma_allow : float
        Allowable stress (Pa).
    rho_ks : float, optional
        KS aggregation parameter.
    gradient : bool, optional
        Compute the gradient.
    spectrum : callable or None, optional
        ``spectrum(omega)``, the one-sided PSD of unit sigma per rad/s; None for von Karman.
    state_outputs : tuple or None, optional
        ``(index, limit)``: flat state indices (m,) and their limits (m,) in the states' units (e.g.
        the control surfaces' deflection and rate, rad and rad/s). Adds the KS (``rho_ks``) of the
        ratios U_sigma A-bar / limit (``state_value``, ``state_ratio``) and, with ``gradient``, its
        total derivative (``state_d_p``, ``state_d_airspeed``) by the same complex adjoint.

    Returns
    -------
    TurbulenceStressKS
        Value, constraints and gradient.
    """
    w = check_frequencies(omega)
    if not (np.isfinite(sigma_allow) and sigma_allow > 0):
        raise ValueError(f"sigma_allow = {sigma_allow} Pa; allowed range (0, inf) Pa")
    if not (np.isfinite(u_sigma) and u_sigma >= 0):
        raise ValueError(f"u_sigma = {u_sigma} m/s; allowed range [0, inf) m/s")
    p = np.asarray(p, float).ravel()
    x0 = model.x0
    tv = stress.walls(walls)
    s1g, Js, Jt = stress.value(x0, tv)
    s1g, Js, Jt = np.asarray(s1g).ravel(), sp.csr_matrix(Js), sp.csr_matrix(Jt)
    phi = (von_karman_psd(w, model.airspeed) if spectrum is None else np.asarray(spectrum(w))).ravel()
    W = quadrature_weights(w) * phi
    Wg = model.gust_vector(w)
    factors = ShiftedFactors(model.A, model.E)
    lus, X = [], np.empty((w.size, x0.size), dtype=complex)
    for j, om in enumerate(w):
        lu = factors.factor(1j * om)
        X[j] = lu.solve(-(model.G @ Wg[j]))
        lus.append(lu)
    Y = (Js @ X.T).T                                   # (n_freq, n_s) stress transfer functions
    a_bar = np.sqrt(W @ np.abs(Y) ** 2)
    g = np.concatenate([(s1g + u_sigma * a_bar) / sigma_allow - 1.0, (-s1g + u_sigma * a_bar) / sigma_allow - 1.0])
    ks, dks = ks_aggregate(g, rho_ks)
    out = TurbulenceStressKS(float(ks), g, a_bar, s1g)
    if state_outputs is not None:
        idx = np.asarray(state_outputs[0], dtype=int).ravel()
        scale = u_sigma / np.asarray(state_outputs[1], dtype=float).ravel()
        Ys = X[:, idx]                                    # (n_freq, m) state transfer functions
        a_s = np.sqrt(W @ np.abs(Ys) ** 2)
        out.state_ratio = scale * a_s
        ks_s, dks_s = ks_aggregate(out.state_ratio, rho_ks)
        out.state_value = float(ks_s)
    if not gradient:
        return out
    m = s1g.size
    sbar = (dks[:m] - dks[m:]) / sigma_allow
    abar = u_sigma * (dks[:m] + dks[m:]) / sigma_allow
    with np.errstate(divide="ignore", invalid="ignore"):
        coef = np.where(a_bar > 0, abar / a_bar, 0.0)
    C = W[:, None] * np.conj(Y) * coef[None, :]        # c_kj (n_freq, n_s)
    dx = Js.T @ sbar
    dt = Jt.T @ sbar
    dp = np.zeros(p.size)
    second_s = stress.second
    second_r = _residual_second(system)
    ql = layout(system.forcing_specs)
    gs = gust_columns(ql)  # the wing's stations, then a free-pitch system's tail
    q = _linearisation_forcing(system, q_static)
    # adjoint solves, then the second-derivative terms of all frequencies in one mapped call each
    # (real and imaginary parts as separate columns, signs +1 / -1: Re(a^T M b) = ar M br - ai M bi)
    lam = np.array([lus[j].solve_transposed(np.asarray(Js.T @ C[j], dtype=complex)) for j in range(w.size)])
    sign = np.r_[np.ones(w.size), -np.ones(w.size)]
    nf2 = 2 * w.size
    gx, gt = _mapped(second_s, nf2)(x0, tv, np.hstack([C.real.T, C.imag.T]), np.hstack([X.real.T, X.imag.T]))
    dx += np.asarray(gx) @ sign
    dt += np.asarray(gt) @ sign
    bq = np.zeros((q.size, nf2))
    bq[gs, :w.size], bq[gs, w.size:] = Wg.real.T, Wg.imag.T
    lams = [lam]
    if state_outputs is not None:  # the states' A-bar: their adjoint right-hand sides are selections
        with np.errstate(divide="ignore", invalid="ignore"):
            coef_s = np.where(a_s > 0, dks_s * scale / a_s, 0.0)
        Cs = W[:, None] * np.conj(Ys) * coef_s[None, :]
        rhs = np.zeros((w.size, x0.size), dtype=complex)
        for k, i in enumerate(idx):
            rhs[:, i] += Cs[:, k]
        lams.append(np.array([lus[j].solve_transposed(rhs[j]) for j in range(w.size)]))
    k_f = len(lams)   # the functionals share one mapped call of the residual's second derivatives
    xs = np.hstack([X.real.T, X.imag.T])
    xds = np.hstack([-(w * X.imag.T), w * X.real.T])
    rx, rp = _mapped(second_r, k_f * nf2)(x0, p, q, np.hstack([np.hstack([lm.real.T, lm.imag.T]) for lm in lams]),
                                          np.tile(xs, k_f), np.tile(xds, k_f), np.tile(bq, k_f))
    rx, rp = np.asarray(rx), np.asarray(rp)
    dx -= rx[:, :nf2] @ sign
    dp -= rp[:, :nf2] @ sign
    # the 1 g state: R(x0, 0, p, q_static) = 0
    Rx, _ = system.jac_state(x0, np.zeros_like(x0), p, q_static)
    Rp, _ = system.jac_inputs(x0, np.zeros_like(x0), p, q_static)
    RxT = spla.splu(sp.csc_matrix(Rx).T.tocsc())
    Rp = sp.csr_matrix(Rp)
    dp -= Rp.T @ RxT.solve(dx)
    out.d_p = dp
    out.d_walls = dt.reshape(4, stress.n).T
    if state_outputs is not None:
        dx_s = -(rx[:, nf2:] @ sign)
        out.state_d_p = -(rp[:, nf2:] @ sign) - Rp.T @ RxT.solve(dx_s)
    pl = layout(system.param_specs)
    if "airspeed" in pl:
        V = model.airspeed
        lag = (model.x_stations - np.min(model.x_stations)) / V
        dWg = Wg * (1j * w[:, None] * lag[None, :] / V)       # d w_ij / dV
        GdW = (model.G @ dWg.T).T
        dW = (quadrature_weights(w) * von_karman_psd_airspeed_derivative(w, V)) if spectrum is None else None

        def airspeed_total(lm, dpf, cf, Yf):
            phase = -np.sum(np.real(np.einsum("jn,jn->j", lm, GdW)))
            d_spec = 0.0 if dW is None else float(np.sum(cf * 0.5 * (dW @ np.abs(Yf) ** 2)))
            return float(dpf[pl["airspeed"]][0]) + phase + d_spec

        out.d_airspeed = airspeed_total(lam, dp, coef, Y)
        if state_outputs is not None:
            out.state_d_airspeed = airspeed_total(lams[1], out.state_d_p, coef_s, Ys)
    return out


def _linearisation_forcing(system, q_static):
    """``q_static`` with ``trim_active`` 0 (the linearisation holds the trim angle)."""
    q = np.array(q_static, dtype=float).ravel()
    ql = layout(system.forcing_specs)
    if "trim_active" in ql:
        q[ql["trim_active"]] = 0.0
    return q
