"""Control surfaces, actuators and a feedback law on the modal doublet-lattice wing (no OpenMDAO).

The surfaces are flap modes of the doublet lattice (:mod:`wingmdao.aero.dlm`, ``surfaces``): their
generalized forces on the modes ``Q_f(ik)``, their hinge moments (rows of every mode, flap and the
gust) and their station loads are fitted in Roger's form with the lag roots of the modal
approximation (:func:`wingmdao.aero.rfa.fit_columns`). In the time domain each surface adds the
actuator states of :mod:`wingmdao.aero.controls` (deflection delta and rate r, first or second
order, :func:`~wingmdao.aero.controls.actuator_residuals`) and one flap lag state per lag root
``z_f,l' - r + gamma_l (V / b) z_f,l = 0``; the modal equations gain

    - q_d [F_0 delta + F_1 (b / V) r + F_2 (b / V)^2 r' + sum_l F_(l+2) z_f,l]

and the law (:class:`~wingmdao.aero.controls.ControlLaw`, the same actuator and controller rows
as the strip path's, :mod:`wingmdao.aero.system`) closes the loop on measured outputs of the modal model:

* ``root_bending``: the root's M_x by force summation (:mod:`wingmdao.aero.modal_loads`:
  aerodynamic part of the modes, gust and flaps, inertia of the modal accelerations), MN m;
* ``tip_acceleration``: the tip node's z acceleration of the basis (rigid modes included) in g;
* ``load_factor``: the plunge mode's acceleration in g (free plunge);
* ``pitch_rate``: the pitch mode's rate (free pitch).

Everything is an increment on the trimmed (or jig) state, as the modal model's states are; the law
acts on these increments. The hinge moments are outputs (no hinge-moment feedback into the
actuator); the flap's own inertia is not modelled.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wingmdao.aero.controls import ControlSpec
from wingmdao.aero.dlm import GeneralizedForces
from wingmdao.aero.rfa import RogerApproximation, fit_columns
from wingmdao.aero.rfa_system import control_state_offset

__all__ = ["ModalControlModel", "modal_control_model", "control_terms", "hinge_moment_history"]


@dataclass(frozen=True, eq=False)
class ModalControlModel:
    """Roger coefficients of the flap modes on the modal wing (module docstring).

    Parameters
    ----------
    spec : ControlSpec
        The surfaces, measured outputs and controller size.
    flap : numpy.ndarray
        (3 + L, modes, n_s) generalized forces on the modes per radian of each surface (m^2).
    hinge : numpy.ndarray
        (3 + L, n_s, modes + n_s + 1) hinge moments per unit q (m^3) of each mode, surface and ``w_g / V``.
    flap_loads : numpy.ndarray
        (3 + L, n, 6, n_s) aerodynamic station loads per unit q and radian of each surface.
    root_motion, root_gust, root_flap : numpy.ndarray
        Root M_x rows of the modes' (3 + L, modes), the gust's (3 + L,) and the surfaces' (3 + L, n_s)
        aerodynamic station loads per unit q.
    root_inertia : numpy.ndarray
        (modes,) root M_x per unit modal acceleration (N m).
    tip : numpy.ndarray
        (modes,) tip z displacement per unit modal amplitude (m).
    plunge, pitch : int or None
        Index of the plunge and pitch modes (None: clamped, no free pitch).
    errors : dict
        Fit errors of the flap forces, hinge moments and flap station loads.
    """

    spec: ControlSpec
    flap: np.ndarray
    hinge: np.ndarray
    flap_loads: np.ndarray
    root_motion: np.ndarray
    root_gust: np.ndarray
    root_flap: np.ndarray
    root_inertia: np.ndarray
    tip: np.ndarray
    plunge: int | None
    pitch: int | None
    errors: dict

    @property
    def n_surfaces(self) -> int:
        return self.spec.n_surfaces


def modal_control_model(spec: ControlSpec, gaf: GeneralizedForces, rfa: RogerApproximation, loads,
                        tip, *, plunge=None, pitch=None) -> ModalControlModel:
    """:class:`ModalControlModel` of the flap modes of ``gaf`` (built with ``surfaces`` in the order
    of ``spec``) fitted with the lag roots of ``rfa``; ``loads`` the modes' station-load model
    (:class:`wingmdao.aero.modal_loads.StationLoadModel`), ``tip`` (modes,) the tip z displacement
    per mode; ``plunge``/``pitch`` the indices of the free rigid modes. ValueError when a measured
    output needs a freedom the model does not have.

    Parameters
    ----------
    spec : ControlSpec
        Surfaces and law.
    gaf : GeneralizedForces
        Tabulated forces with flap columns.
    rfa : RogerApproximation
        The modal approximation (its lag roots).
    loads : wingmdao.aero.modal_loads.StationLoadModel
        Station-load model of the modes.
    tip : array_like
        (modes,) tip z displacement per unit modal amplitude (m).
    plunge : int or None
        Index of the plunge mode.
    pitch : int or None
        Index of the pitch mode.

    Returns
    -------
    ModalControlModel
        The model.
    """
    if gaf.flap is None or gaf.flap.shape[2] != spec.n_surfaces:
        raise ValueError("the generalized forces carry no flap columns for the surfaces "
                         "(wingmdao.aero.dlm.generalized_forces(surfaces=...))")
    needs = {"load_factor": ("plunge", plunge), "pitch_rate": ("pitch", pitch)}
    for nm in spec.outputs:
        if nm in needs and needs[nm][1] is None:
            raise ValueError(f"control law output {nm!r} needs free {needs[nm][0]} in the modal model")
    flap, e_f = fit_columns(rfa, gaf.k, gaf.flap)
    hinge, e_h = fit_columns(rfa, gaf.k, gaf.hinge)
    fl, e_l = fit_columns(rfa, gaf.k, gaf.flap_station_loads)
    return ModalControlModel(spec=spec, flap=flap, hinge=hinge, flap_loads=fl,
                             root_motion=loads.motion[:, 0, 3, :], root_gust=loads.gust[:, 0, 3],
                             root_flap=fl[:, 0, 3, :], root_inertia=loads.inertia[0, 3, :],
                             tip=np.asarray(tip, dtype=float), plunge=plunge, pitch=pitch,
                             errors={"flap_fit_error": e_f, "hinge_fit_error": e_h, "flap_load_fit_error": e_l})


def control_terms(model: ModalControlModel, rfa: RogerApproximation, X, Xd, n_modes: int) -> tuple:
    """``(delta, rate, rate', z_f)`` of marched states ``X`` and their rates ``Xd`` (nt, states) of
    the controlled modal system (:func:`wingmdao.aero.rfa_system.modal_rfa_system`): deflections,
    rates and accelerations (nt, n_s) and the flap lag states (nt, L, n_s).

    Parameters
    ----------
    model : ModalControlModel
        The control model.
    rfa : RogerApproximation
        The modal approximation.
    X : numpy.ndarray
        (nt, states) marched states.
    Xd : numpy.ndarray
        (nt, states) their time derivatives.
    n_modes : int
        Number of modes.

    Returns
    -------
    tuple
        ``(delta, rate, drate, zf)``.
    """
    ns, L = model.n_surfaces, rfa.n_lags
    i0 = control_state_offset(n_modes, L)
    X, Xd = np.asarray(X), np.asarray(Xd)
    delta = X[:, i0:i0 + 2 * ns:2]
    rate = X[:, i0 + 1:i0 + 2 * ns:2]
    drate = Xd[:, i0 + 1:i0 + 2 * ns:2]
    j0 = i0 + model.spec.n_states
    zf = X[:, j0:j0 + L * ns].reshape(-1, L, ns)
    return delta, rate, drate, zf


def hinge_moment_history(model: ModalControlModel, rfa: RogerApproximation, X, Xd, a, F, airspeed,
                         density) -> np.ndarray:
    """Hinge moments (nt, n_s) N m of each surface of one half-wing, trailing edge down positive,
    of a march of the controlled modal system: the Roger rows of the modes (with the modal
    accelerations ``a`` (nt, modes)), the surfaces and the gust (forcing ``F``).

    Parameters
    ----------
    model : ModalControlModel
        The control model.
    rfa : RogerApproximation
        The modal approximation.
    X, Xd : numpy.ndarray
        (nt, states) marched states and their rates.
    a : numpy.ndarray
        (nt, modes) modal accelerations.
    F : numpy.ndarray
        (nt, forcing) forcing history (gust velocity and its rates first).
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).

    Returns
    -------
    numpy.ndarray
        (nt, n_s) hinge moments (N m).
    """
    n, L, b = a.shape[1], rfa.n_lags, float(rfa.b_ref)
    V = float(airspeed)
    qd = 0.5 * float(density) * V ** 2
    X, F = np.asarray(X), np.asarray(F)
    q, v = X[:, :n], X[:, n:2 * n]
    z = X[:, 2 * n:2 * n + L * n].reshape(-1, L, n)
    zg = X[:, 2 * n + L * n:2 * n + L * n + L]
    d, r, dr, zf = control_terms(model, rfa, X, Xd, n)
    ns = d.shape[1]
    H = model.hinge
    Hm, Hf, Hg = H[..., :n], H[..., n:n + ns], H[..., n + ns]
    g, g1, g2 = F[:, 0] / V, F[:, 1] / V, F[:, 2] / V
    out = (q @ Hm[0].T + (b / V) * v @ Hm[1].T + (b / V) ** 2 * a @ Hm[2].T + np.einsum("lsm,tlm->ts", Hm[3:], z)
           + d @ Hf[0].T + (b / V) * r @ Hf[1].T + (b / V) ** 2 * dr @ Hf[2].T + np.einsum("lsj,tlj->ts", Hf[3:], zf)
           + np.outer(g, Hg[0]) + (b / V) * np.outer(g1, Hg[1]) + (b / V) ** 2 * np.outer(g2, Hg[2]) + zg @ Hg[3:])
    return qd * out
