"""Beam-station internal loads of the modal doublet-lattice wing by force summation (no OpenMDAO).

The modal wing (:mod:`wingmdao.aero.rfa_system`) carries a few modal amplitudes; the loads
engineer wants the internal force and moment at each beam station (root bending, torsion). Two
recoveries exist:

* mode displacement: ``sum_i q_i R_i``, ``R_i`` each mode's internal loads
  (:class:`wingmdao.beam.modes.NormalModes`). It sees only the load distributions the retained
  modes can represent, so a gust's quasi-static load, spread over the span unlike any single mode,
  converges slowly with the number of modes;
* force summation (used here): the applied loads outboard of the station summed with their arms,
  aerodynamic plus inertia. The aerodynamic part is the panel pressures themselves
  (:func:`wingmdao.aero.dlm.station_summation`), exact for any number of modes in the static limit;
  only the inertia part depends on the modal truncation.

Aerodynamic part. The doublet-lattice station loads per unit modal amplitude ``S(ik)`` and per unit
gust angle ``S_g(ik)`` (``station_loads`` of :class:`wingmdao.aero.dlm.GeneralizedForces`) are
fitted in Roger's form with the lag roots of the modal approximation
(:func:`wingmdao.aero.rfa.fit_columns`), so the time history follows from the marched states with
no further states::

    L_aero = q_d [S_0 q + S_1 (b/V) v + S_2 (b/V)^2 v' + sum_l S_(l+2) z_l
                  + S_g0 g + S_g1 (b/V) g' + S_g2 (b/V)^2 g'' + sum_l S_g(l+2) zg_l]

Inertia part. The inertia load of a modal acceleration ``a_i`` is ``-M phi_i a_i``; since
``K phi_i = omega_i^2 M phi_i`` for the beam's own mass and stiffness, its internal loads are
``-R_i a_i / omega_i^2`` exactly (no separate mass lumping). Gravity is static and not part of
the response: the loads are increments on the clamped jig at rest (the 1 g state is not
included).

The modal accelerations ``v'`` come from the modal equations of motion at each step (not from
differencing the march).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wingmdao.aero.dlm import GeneralizedForces, interpolate
from wingmdao.aero.modal_controls import control_terms
from wingmdao.aero.rfa import RogerApproximation, fit_columns
from wingmdao.beam.modes import NormalModes

__all__ = ["StationLoadModel", "station_load_model", "modal_accelerations", "station_load_history",
           "harmonic_station_loads"]


@dataclass(frozen=True, eq=False)
class StationLoadModel:
    """Force-summation recovery of the station loads (module docstring).

    ``motion`` (3 + L, n, 6, modes): Roger coefficients of the aerodynamic station loads (force N,
    moment N m, body axes) per unit modal amplitude and dynamic pressure; ``gust`` (3 + L, n, 6):
    the same per unit ``w_g / V``; ``inertia`` (n, 6, modes): internal loads per unit modal
    acceleration; ``error``: the fit error of the station loads (as the approximation's ``error``).

    Parameters
    ----------
    motion : numpy.ndarray
        Roger coefficients of the aerodynamic station loads per unit modal amplitude and dynamic
        pressure, shape (3 + L, n, 6, modes).
    gust : numpy.ndarray
        The same per unit ``w_g / V``, shape (3 + L, n, 6).
    inertia : numpy.ndarray
        Internal loads per unit modal acceleration, shape (n, 6, modes).
    error : float
        Fit error of the station loads.
    """

    motion: np.ndarray
    gust: np.ndarray
    inertia: np.ndarray
    error: float


def _modal_inertia(modes: NormalModes) -> np.ndarray:
    """(n, 6, modes): ``-R_i / omega_i^2``, internal loads of a unit modal acceleration."""
    if modes.force is None or modes.moment is None:
        raise ValueError("the modes carry no internal loads (NormalModes.force/moment); use beam.modes.normal_modes")
    R = np.concatenate([modes.force, modes.moment], axis=2)              # (modes, n, 6)
    return -np.transpose(R / modes.frequencies[:, None, None] ** 2, (1, 2, 0))


def station_load_model(gaf: GeneralizedForces, rfa: RogerApproximation, modes: NormalModes) -> StationLoadModel:
    """:class:`StationLoadModel` of the doublet-lattice station loads of ``gaf`` fitted with the lag
    roots of ``rfa``, and the inertia of ``modes``.

    Parameters
    ----------
    gaf : wingmdao.aero.dlm.GeneralizedForces
        Tabulated generalized forces with their station loads.
    rfa : wingmdao.aero.rfa.RogerApproximation
        The approximation whose lag roots are used.
    modes : wingmdao.beam.modes.NormalModes
        The modes (their inertia loads).

    Returns
    -------
    StationLoadModel
        The station-load recovery.
    """
    if gaf.station_loads is None:
        raise ValueError("the generalized forces carry no station loads (wingmdao.aero.dlm.generalized_forces)")
    nm = gaf.Q.shape[1]
    coef, err = fit_columns(rfa, gaf.k, gaf.station_loads)
    return StationLoadModel(motion=coef[..., :nm], gust=coef[..., nm], inertia=_modal_inertia(modes), error=err)


def _split(X, n, L):
    q, v = X[:, :n], X[:, n:2 * n]
    z = X[:, 2 * n:2 * n + L * n].reshape(-1, L, n)
    zg = X[:, 2 * n + L * n:2 * n + L * n + L]
    return q, v, z, zg


def _flap_sum(coef, terms, b, V):
    """``sum`` of the Roger terms of the flap columns ``coef`` (3 + L, ..., n_s) over the control
    terms (:func:`wingmdao.aero.modal_controls.control_terms`), (nt, ...)."""
    d, r, dr, zf = terms
    return (np.einsum("...s,ts->t...", coef[0], d) + (b / V) * np.einsum("...s,ts->t...", coef[1], r)
            + (b / V) ** 2 * np.einsum("...s,ts->t...", coef[2], dr)
            + np.einsum("l...s,tls->t...", coef[3:], zf))


def modal_accelerations(structure, rfa: RogerApproximation, X, F, airspeed, density, tail=None,
                        controls=None, rates=None) -> np.ndarray:
    """Modal accelerations ``v'`` (nt, modes) of marched states ``X`` (nt, states) of
    :func:`wingmdao.aero.rfa_system.modal_rfa_system` under its forcing ``F`` (nt, 3 + modes
    [+ 2 with ``tail``, :class:`wingmdao.aero.modal_free.ModalTail`]), from the modal equations of
    motion.

    Parameters
    ----------
    structure : wingmdao.stability.pk.ModalStructure
        Modal mass, stiffness and damping.
    rfa : wingmdao.aero.rfa.RogerApproximation
        The Roger approximation of the system.
    X : numpy.ndarray
        Marched states, shape (nt, states).
    F : numpy.ndarray
        Forcing history, shape (nt, 3 + modes [+ 2]).
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    tail : wingmdao.aero.modal_free.ModalTail or None
        The free aircraft's horizontal tail; None: none.
    controls : wingmdao.aero.modal_controls.ModalControlModel or None
        Control surfaces of the system (their flap forces); None: none.
    rates : numpy.ndarray or None
        (nt, states) state rates (:func:`wingmdao.timemarch.bdf.state_rates`), with ``controls``
        (the surfaces' accelerations).

    Returns
    -------
    numpy.ndarray
        Modal accelerations, shape (nt, modes).
    """
    M, K, C = (np.asarray(a, dtype=float) for a in (structure.mass, structure.stiffness, structure.damping))
    n, L, b = M.shape[0], rfa.n_lags, float(rfa.b_ref)
    V, rho = float(airspeed), float(density)
    qd = 0.5 * rho * V ** 2
    q, v, z, zg = _split(np.asarray(X, dtype=float), n, L)
    F = np.asarray(F, dtype=float)
    g, g1, g2 = F[:, 0] / V, F[:, 1] / V, F[:, 2] / V
    A, G = rfa.A, rfa.gust
    rhs = (-(C - 0.5 * rho * V * b * A[1]) @ v.T - (K - qd * A[0]) @ q.T
           + qd * np.einsum("lij,tlj->it", A[3:], z)
           + qd * (np.outer(G[0], g) + np.outer(G[1], (b / V) * g1) + np.outer(G[2], (b / V) ** 2 * g2)
                   + G[3:].T @ zg.T)
           + F[:, 3:3 + n].T)
    if tail is not None:
        rhs = rhs + tail.force(qd, V, q.T, v.T, F[:, 3 + n], F[:, 4 + n])
    if controls is not None:
        rhs = rhs + qd * _flap_sum(controls.flap, control_terms(controls, rfa, X, rates, n), b, V).T
    return np.linalg.solve(M - 0.5 * rho * b ** 2 * A[2], rhs).T


def station_load_history(model: StationLoadModel, structure, rfa: RogerApproximation, X, F, airspeed,
                         density, tail=None, controls=None, rates=None) -> tuple[np.ndarray, np.ndarray]:
    """``(total, aerodynamic)`` station loads (nt, n, 6) of a march of
    :func:`wingmdao.aero.rfa_system.modal_rfa_system`: internal force (N) and moment (N m) at every
    beam node, body axes, by force summation (module docstring); ``aerodynamic`` is the panel
    forces' share alone (its root force z is the half-wing's lift). ``tail``: the free aircraft's
    tail in the modal equations (:func:`modal_accelerations`).

    Parameters
    ----------
    model : StationLoadModel
        The station-load recovery.
    structure : wingmdao.stability.pk.ModalStructure
        Modal mass, stiffness and damping.
    rfa : wingmdao.aero.rfa.RogerApproximation
        The Roger approximation of the system.
    X : numpy.ndarray
        Marched states, shape (nt, states).
    F : numpy.ndarray
        Forcing history, shape (nt, 3 + modes [+ 2]).
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    tail : wingmdao.aero.modal_free.ModalTail or None
        The free aircraft's horizontal tail; None: none.
    controls : wingmdao.aero.modal_controls.ModalControlModel or None
        Control surfaces of the system (their flap forces and station loads); None: none.
    rates : numpy.ndarray or None
        (nt, states) state rates, with ``controls``.

    Returns
    -------
    tuple of numpy.ndarray
        ``(total, aerodynamic)``, each shape (nt, n, 6).
    """
    n, L, b = structure.mass.shape[0], rfa.n_lags, float(rfa.b_ref)
    V = float(airspeed)
    qd = 0.5 * float(density) * V ** 2
    q, v, z, zg = _split(np.asarray(X, dtype=float), n, L)
    a = modal_accelerations(structure, rfa, X, F, airspeed, density, tail, controls, rates)
    F = np.asarray(F, dtype=float)
    g, g1, g2 = F[:, 0] / V, F[:, 1] / V, F[:, 2] / V
    S, Sg = model.motion, model.gust
    aero = (np.einsum("scm,tm->tsc", S[0], q) + (b / V) * np.einsum("scm,tm->tsc", S[1], v)
            + (b / V) ** 2 * np.einsum("scm,tm->tsc", S[2], a) + np.einsum("lscm,tlm->tsc", S[3:], z)
            + np.einsum("sc,t->tsc", Sg[0], g) + (b / V) * np.einsum("sc,t->tsc", Sg[1], g1)
            + (b / V) ** 2 * np.einsum("sc,t->tsc", Sg[2], g2) + np.einsum("lsc,tl->tsc", Sg[3:], zg))
    if controls is not None:
        aero = aero + _flap_sum(controls.flap_loads, control_terms(controls, rfa, X, rates, n), b, V)
    aero = qd * aero
    return aero + np.einsum("scm,tm->tsc", model.inertia, a), aero


def harmonic_station_loads(structure, gaf: GeneralizedForces, modes: NormalModes, airspeed, density, k):
    """Frequency response of the station loads (n, 6) complex (N, N m per m/s of gust velocity at
    ``x_gust``) to a harmonic gust at reduced frequency ``k``, with the exact tabulated
    doublet-lattice matrices (no rational approximation): the modal amplitudes from
    ``[-omega^2 M + i omega C + K - q_d Q(ik)] q = q_d Q_g(ik) / V``, then force summation.

    Parameters
    ----------
    structure : wingmdao.stability.pk.ModalStructure
        Modal mass, stiffness and damping.
    gaf : wingmdao.aero.dlm.GeneralizedForces
        Tabulated generalized forces with their station loads.
    modes : wingmdao.beam.modes.NormalModes
        The modes (their inertia loads).
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    k : float
        A tabulated reduced frequency.

    Returns
    -------
    numpy.ndarray
        Complex station loads, shape (n, 6).
    """
    V, rho = float(airspeed), float(density)
    qd = 0.5 * rho * V ** 2
    omega = float(k) * V / gaf.b_ref
    Q, G = interpolate(gaf, k)
    Z = -omega ** 2 * structure.mass + 1j * omega * structure.damping + structure.stiffness - qd * Q
    q = np.linalg.solve(Z, qd * G / V)
    idx = np.searchsorted(gaf.k, k)
    if idx >= gaf.k.size or not np.isclose(gaf.k[idx], k):
        raise ValueError(f"k = {k} is not a tabulated reduced frequency {gaf.k.tolist()}")
    L = gaf.station_loads[idx]                                          # (n, 6, modes + 1)
    aero = qd * (L[..., :-1] @ q + L[..., -1] / V)
    return aero + _modal_inertia(modes) @ (-omega ** 2 * q)
