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

from wingmdao.aero.modal_loads import StationLoadModel
from wingmdao.aero.rfa import RogerApproximation
from wingmdao.loads.turbulence import ABar, a_bar
from wingmdao.stability.frequency import ShiftedFactors, check_frequencies, frequency_grid
from wingmdao.timemarch.system import layout, pack

__all__ = ["ModalGustResponse", "modal_gust_frequency_response", "modal_turbulence_a_bar"]


@dataclass
class ModalGustResponse:
    """Transfer functions per m/s of gust velocity on ``omega`` (rad/s): ``modal`` (n_freq, modes)
    amplitudes, ``station_loads`` (n_freq, n, 6) complex internal force (N) and moment (N m) by
    force summation, ``aero_station_loads`` (n_freq, n, 6) the panel forces' share."""

    omega: np.ndarray
    modal: np.ndarray
    station_loads: np.ndarray
    aero_station_loads: np.ndarray


def modal_gust_frequency_response(system, structure, rfa: RogerApproximation, model: StationLoadModel, airspeed,
                                  density, omega) -> ModalGustResponse:
    """Equation (1) of the module docstring for the modal residual ``system`` at ``airspeed`` (m/s)
    and ``density`` (kg/m^3) on ``omega`` (rad/s, > 0, increasing), and the station loads."""
    w = check_frequencies(omega)
    V, rho = float(airspeed), float(density)
    qd = 0.5 * rho * V ** 2
    b = float(rfa.b_ref)
    n, L = structure.mass.shape[0], rfa.n_lags
    p = pack(system.param_specs, {"airspeed": V, "density": rho})
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
    zg = X[:, 2 * n + L * n:]
    a = 1j * w[:, None] * v
    S, Sg = model.motion, model.gust
    g = np.ones(w.size) / V
    aero = qd * (np.einsum("scm,tm->tsc", S[0], q) + (b / V) * np.einsum("scm,tm->tsc", S[1], v)
                 + (b / V) ** 2 * np.einsum("scm,tm->tsc", S[2], a) + np.einsum("lscm,tlm->tsc", S[3:], z)
                 + np.einsum("sc,t->tsc", Sg[0], g) + (b / V) * np.einsum("sc,t->tsc", Sg[1], 1j * w * g)
                 + (b / V) ** 2 * np.einsum("sc,t->tsc", Sg[2], -w ** 2 * g) + np.einsum("lsc,tl->tsc", Sg[3:], zg))
    total = aero + np.einsum("scm,tm->tsc", model.inertia, a)
    return ModalGustResponse(w, q, total, aero)


def modal_turbulence_a_bar(system, structure, rfa: RogerApproximation, model: StationLoadModel, airspeed, density,
                           *, f_min=1e-3, f_max=20.0, n_base=161) -> tuple[ABar, ModalGustResponse]:
    """A-bar (N, N m per m/s) of the station loads (n, 6) on a grid refined about the modal
    system's lightly damped poles (:func:`wingmdao.stability.frequency.frequency_grid`), and the
    frequency response."""
    p = pack(system.param_specs, {"airspeed": float(airspeed), "density": float(density)})
    x0 = np.zeros(system.n_state)
    A, E = (m.toarray() for m in system.jac_state(x0, x0, p, np.zeros(system.n_forcing)))
    lam = sla.eigvals(-A, E)
    lam = lam[np.isfinite(lam) & (np.abs(lam) < 1e6)]
    omega = frequency_grid(lam, f_min=f_min, f_max=f_max, n_base=n_base)
    resp = modal_gust_frequency_response(system, structure, rfa, model, airspeed, density, omega)
    return a_bar(omega, resp.station_loads, float(airspeed)), resp
