"""Continuous-turbulence response of the modal doublet-lattice wing (no OpenMDAO; docs/turbulence.md).

The residual system of :func:`wingmdao.aero.rfa_system.modal_rfa_system` (modal amplitudes,
Roger lag states, gust lag states) is linear; its linearisation ``E dx' + A dx + G_0 w + G_1 w' +
G_2 w'' = 0`` (``A``, ``E`` from its ``jac_state`` as for the state-space flutter matrix, the
``G`` from ``jac_inputs`` on the gust velocity at ``x_gust`` and its two rates, the penetration
delays being inside the doublet lattice's gust column) gives at angular frequency omega

    (i omega E + A) X = -(G_0 + i omega G_1 - omega^2 G_2)                              (1)

per m/s of gust velocity, solved with the sparse shifted factors of
:mod:`wingmdao.stability.frequency`. The station loads (force summation,
:mod:`wingmdao.aero.modal_loads`) and the lift follow linearly from ``X``; A-bar is
:func:`wingmdao.loads.turbulence.a_bar` of their transfer functions with the von Karman spectrum.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from wingmdao.aero.modal_controls import control_terms, hinge_moment_history
from wingmdao.aero.modal_loads import StationLoadModel, _flap_sum
from wingmdao.aero.rfa import RogerApproximation
from wingmdao.loads.turbulence import ABar, a_bar
from wingmdao.stability.frequency import ShiftedFactors, check_frequencies, frequency_grid
from wingmdao.timemarch.system import layout, pack

__all__ = ["ModalGustResponse", "modal_gust_frequency_response", "modal_turbulence_a_bar", "dlm_turbulence_analysis"]


@dataclass
class ModalGustResponse:
    """Transfer functions per m/s of gust velocity on ``omega`` (rad/s): ``modal`` (n_freq, modes)
    amplitudes, ``station_loads`` (n_freq, n, 6) complex internal force (N) and moment (N m) by
    force summation, ``aero_station_loads`` (n_freq, n, 6) the panel forces' share.

    Parameters
    ----------
    omega : numpy.ndarray
        Angular frequencies (rad/s), shape (n_freq,).
    modal : numpy.ndarray
        Complex modal amplitudes per m/s of gust, shape (n_freq, modes).
    station_loads : numpy.ndarray
        Complex internal force (N) and moment (N m) per m/s of gust, shape (n_freq, n, 6).
    aero_station_loads : numpy.ndarray
        The panel forces' share, shape (n_freq, n, 6).
    controls : dict, optional
        With control surfaces: ``deflection`` and ``rate`` (n_freq, n_s) rad and rad/s and
        ``hinge_moment`` (n_freq, n_s) N m per m/s of gust.
    """

    omega: np.ndarray
    modal: np.ndarray
    station_loads: np.ndarray
    aero_station_loads: np.ndarray
    controls: dict = None


def modal_gust_frequency_response(system, structure, rfa: RogerApproximation, model: StationLoadModel, airspeed,
                                  density, omega, controls=None, law=None) -> ModalGustResponse:
    """Equation (1) of the module docstring for the modal residual ``system`` at ``airspeed`` (m/s)
    and ``density`` (kg/m^3) on ``omega`` (rad/s, > 0, increasing), and the station loads.

    Parameters
    ----------
    system : wingmdao.timemarch.system.ResidualSystem
        The modal residual system (:func:`wingmdao.aero.rfa_system.modal_rfa_system`).
    structure : wingmdao.stability.pk.ModalStructure
        Modal mass, stiffness and damping.
    rfa : wingmdao.aero.rfa.RogerApproximation
        The Roger approximation of the system.
    model : wingmdao.aero.modal_loads.StationLoadModel
        The station-load recovery.
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    omega : array_like
        Angular frequencies (rad/s, > 0, increasing).
    controls : wingmdao.aero.modal_controls.ModalControlModel or None
        The system's control surfaces (their flap loads and hinge moments); None: none.
    law : wingmdao.aero.controls.ControlLaw or None
        The law whose matrices the system's parameters take.

    Returns
    -------
    ModalGustResponse
        The transfer functions.
    """
    w = check_frequencies(omega)
    V, rho = float(airspeed), float(density)
    qd = 0.5 * rho * V ** 2
    b = float(rfa.b_ref)
    n, L = structure.mass.shape[0], rfa.n_lags
    p = pack(system.param_specs, {"airspeed": V, "density": rho, **(law.matrices() if law is not None else {})})
    x0 = np.zeros(system.n_state)
    f0 = np.zeros(system.n_forcing)
    A, E = (sp.csc_matrix(m) for m in system.jac_state(x0, x0, p, f0))
    _, dq = system.jac_inputs(x0, x0, p, f0)
    ql = layout(system.forcing_specs)
    G = [sp.csc_matrix(dq)[:, ql[name]].toarray().ravel()
         for name in ("gust_velocity", "gust_velocity_rate", "gust_velocity_acceleration")]
    factors = ShiftedFactors(A, E)
    X = np.empty((w.size, system.n_state), dtype=complex)
    for i, om in enumerate(w):
        X[i] = factors.factor(1j * om).solve(-(G[0] + 1j * om * G[1] - om ** 2 * G[2]))
    q, v = X[:, :n], X[:, n:2 * n]
    z = X[:, 2 * n:2 * n + L * n].reshape(-1, L, n)
    zg = X[:, 2 * n + L * n:2 * n + L * n + L]
    a = 1j * w[:, None] * v
    S, Sg = model.motion, model.gust
    g = np.ones(w.size) / V
    aero = qd * (np.einsum("scm,tm->tsc", S[0], q) + (b / V) * np.einsum("scm,tm->tsc", S[1], v)
                 + (b / V) ** 2 * np.einsum("scm,tm->tsc", S[2], a) + np.einsum("lscm,tlm->tsc", S[3:], z)
                 + np.einsum("sc,t->tsc", Sg[0], g) + (b / V) * np.einsum("sc,t->tsc", Sg[1], 1j * w * g)
                 + (b / V) ** 2 * np.einsum("sc,t->tsc", Sg[2], -w ** 2 * g) + np.einsum("lsc,tl->tsc", Sg[3:], zg))
    ctl = None
    if controls is not None:
        Xd = 1j * w[:, None] * X
        terms = control_terms(controls, rfa, X, Xd, n)
        aero = aero + qd * _flap_sum(controls.flap_loads, terms, b, V)
        F = np.zeros((w.size, 3), dtype=complex)
        F[:, 0], F[:, 1], F[:, 2] = 1.0, 1j * w, -w ** 2
        ctl = {"deflection": terms[0], "rate": terms[1],
               "hinge_moment": hinge_moment_history(controls, rfa, X, Xd, a, F, V, rho)}
    total = aero + np.einsum("scm,tm->tsc", model.inertia, a)
    return ModalGustResponse(w, q, total, aero, ctl)


def modal_turbulence_a_bar(system, structure, rfa: RogerApproximation, model: StationLoadModel, airspeed, density,
                           *, f_min=1e-3, f_max=20.0, n_base=161, controls=None,
                           law=None) -> tuple[ABar, ModalGustResponse]:
    """A-bar (N, N m per m/s) of the station loads (n, 6) on a grid refined about the modal
    system's lightly damped poles (:func:`wingmdao.stability.frequency.frequency_grid`), and the
    frequency response.

    Parameters
    ----------
    system : wingmdao.timemarch.system.ResidualSystem
        The modal residual system (:func:`wingmdao.aero.rfa_system.modal_rfa_system`).
    structure : wingmdao.stability.pk.ModalStructure
        Modal mass, stiffness and damping.
    rfa : wingmdao.aero.rfa.RogerApproximation
        The Roger approximation of the system.
    model : wingmdao.aero.modal_loads.StationLoadModel
        The station-load recovery.
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    f_min : float
        Lowest frequency of the grid (Hz).
    f_max : float
        Highest frequency of the grid (Hz).
    n_base : int
        Points of the geometric base grid.
    controls : wingmdao.aero.modal_controls.ModalControlModel or None
        The system's control surfaces; None: none.
    law : wingmdao.aero.controls.ControlLaw or None
        The law whose matrices the system's parameters take.

    Returns
    -------
    wingmdao.loads.turbulence.ABar
        A-bar of the station loads.
    ModalGustResponse
        The frequency response.
    """
    p = pack(system.param_specs, {"airspeed": float(airspeed), "density": float(density),
                                  **(law.matrices() if law is not None else {})})
    x0 = np.zeros(system.n_state)
    A, E = (m.toarray() for m in system.jac_state(x0, x0, p, np.zeros(system.n_forcing)))
    lam = sla.eigvals(-A, E)
    lam = lam[np.isfinite(lam) & (np.abs(lam) < 1e6)]
    omega = frequency_grid(lam, f_min=f_min, f_max=f_max, n_base=n_base)
    resp = modal_gust_frequency_response(system, structure, rfa, model, airspeed, density, omega, controls, law)
    return a_bar(omega, resp.station_loads, float(airspeed)), resp


def dlm_turbulence_analysis(wing, airspeed, density, weight, *, f_max=40.0, n_base=161, surfaces=None,
                            law=None, u_sigma=None) -> dict:
    """A-bar (per m/s of gust) of the modal doublet-lattice wing ``wing``
    (:class:`wingmdao.stability.modal.ModalDLMWing`, root clamped, or
    :class:`wingmdao.aero.modal_free.FreeModalDLMWing` free in plunge) as a JSON-ready dict:
    ``a_bar``/``a_bar_error`` of root_bending_moment (M_x, N m), root_torsion (M_y), load_factor
    (lift of both half-wings over ``weight`` N), tip_deflection (m, z), and per station
    bending_moment and torsion (body axes); ``frequency_hz``, ``psd`` and
    ``transfer_function_magnitude`` of the root bending and the load factor (tip deflection: the
    magnitude only, elastic, relative to the body axes when free); ``quadrature``; ``dlm`` the model's
    figures. No 1 g state (increments). A wing with control surfaces (``wing.controls``; ``surfaces``
    the :class:`~wingmdao.aero.controls.ControlSurface` list, ``law`` its law, ``u_sigma`` m/s the design
    intensity) adds ``control_surfaces``: per surface A-bar of the deflection, rate and hinge moment
    and their design values ``u_sigma`` A-bar against the limits.

    Parameters
    ----------
    wing : wingmdao.stability.modal.ModalDLMWing or wingmdao.aero.modal_free.FreeModalDLMWing
        The modal doublet-lattice wing.
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    weight : float
        Aircraft weight (N), the load factor's reference.
    f_max : float
        Highest frequency of the grid (Hz).
    n_base : int
        Points of the geometric base grid.
    surfaces : sequence of ControlSurface, optional
        The wing's control surfaces (in the order of ``wing.controls``).
    law : ControlLaw, optional
        Their law.
    u_sigma : float, optional
        Design turbulence intensity (m/s TAS), for the surfaces' design values.

    Returns
    -------
    dict
        The JSON-ready analysis.
    """
    rigid = getattr(wing, "rigid", 0)
    if getattr(wing, "tail", None) is not None:
        raise ValueError("the turbulence of the modal doublet-lattice wing is built free in plunge, not in pitch")
    ab, resp = modal_turbulence_a_bar(wing.system, wing.structure, wing.rfa, wing.loads, airspeed, density,
                                      f_max=f_max, n_base=n_base, controls=getattr(wing, "controls", None), law=law)
    w = resp.omega
    H = {"root_bending_moment": resp.station_loads[:, 0, 3], "root_torsion": resp.station_loads[:, 0, 4],
         "load_factor": 2.0 * resp.aero_station_loads[:, 0, 2] / float(weight),
         "tip_deflection": (resp.modal[:, rigid:] @ wing.elastic.displacement[:, -1, 2] if rigid
                            else resp.modal @ wing.modes.displacement[:, -1, 2])}
    out = {name: a_bar(w, h, float(airspeed)) for name, h in H.items()}
    a = {k: float(v.value) for k, v in out.items()}
    e = {k: float(v.error) for k, v in out.items()}
    a.update(bending_moment=ab.value[:, 3].tolist(), torsion=ab.value[:, 4].tolist())
    e.update(bending_moment=ab.error[:, 3].tolist(), torsion=ab.error[:, 4].tolist())
    rel = max(e[k] / a[k] for k in H if a[k] > 0)
    return {"model": "doublet lattice, modal (Roger lags), " + ("free in plunge" if rigid else "clamped"), "frequency_hz": (w / (2 * np.pi)).tolist(),
            "a_bar": a, "a_bar_error": e,
            "psd": {k: out[k].psd.tolist() for k in ("root_bending_moment", "load_factor")},
            "transfer_function_magnitude": {k: np.abs(H[k]).tolist() for k in ("root_bending_moment", "load_factor",
                                                                              "tip_deflection")},
            "quadrature": {"points": int(w.size), "f_max_hz": float(f_max), "max_relative_error_a_bar": float(rel)},
            "loads_include_1g": False, "dlm": wing.info(),
            **({"control_surfaces": _surface_report(surfaces, resp.controls, w, float(airspeed), u_sigma)}
               if resp.controls is not None and surfaces else {})}


def _surface_report(surfaces, ctl, w, V, u_sigma) -> dict:
    """Per surface: A-bar of deflection (deg per m/s), rate (deg/s per m/s) and hinge moment (N m per
    m/s), the design values u_sigma A-bar against the limits (reported, never clipped)."""
    out = {}
    for k, s in enumerate(surfaces):
        d, r = (float(np.degrees(a_bar(w, ctl[key][:, k], V).value)) for key in ("deflection", "rate"))
        h = float(a_bar(w, ctl["hinge_moment"][:, k], V).value)
        u = float(u_sigma) if u_sigma is not None else float("nan")
        out[s.name] = {"a_bar_deflection_deg_per_m_s": d, "a_bar_rate_deg_s_per_m_s": r,
                       "a_bar_hinge_moment_n_m_per_m_s": h,
                       "design_deflection_deg": u * d, "max_deflection_deg": float(s.max_deflection_deg),
                       "design_rate_deg_s": u * r, "max_rate_deg_s": float(s.max_rate_deg_s),
                       "design_hinge_moment_n_m": u * h,
                       "deflection_limit_exceeded": bool(u * d > s.max_deflection_deg),
                       "rate_limit_exceeded": bool(u * r > s.max_rate_deg_s)}
    return out
