"""Flutter about a deformed static state (nonlinear flutter of a very flexible wing).

At each airspeed of the sweep the static aeroelastic equilibrium ``R(x0, 0, p(V), q) = 0`` is
solved with the wing at a root angle of attack ``alpha_r`` and under gravity, so the wing bends
(up with lift, down with its weight) and the deformation grows with speed; the residual is
linearised about that deformed state and its eigenvalues give the flutter speed
(:mod:`wingmdao.stability.eigen`). The flutter speed of a very flexible wing falls with the
static tip deflection: bending moves the torsion mode toward the edgewise (lag) mode and couples
them through the curved shape (M. J. Patil, D. H. Hodges, C. E. S. Cesnik, "Nonlinear
aeroelasticity and flight dynamics of high-altitude long-endurance aircraft", J. Aircraft 38(1),
2001, Figs. of flutter speed vs root angle of attack and vs tip displacement).

The root angle of attack is applied as a rigid incidence of every section: the section
zero-lift angle becomes ``alpha_zero_lift - alpha_r`` (the way the aeroelastic system's trim
angle enters, :func:`wingmdao.aero.system.build_aeroelastic_system`); the beam is not rotated, so
gravity stays along body -z (an error of order alpha_r^2 / 2 in the weight components, 0.4 % at
5 deg).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field

import numpy as np
import openmdao.api as om

from wingmdao.stability.eigen import (StabilitySweep, check_speeds, critical_speeds, eigenmodes, static_state, track_modes)
from wingmdao.beam.residual import STATE_BLOCKS
from wingmdao.timemarch.system import layout

#: default speed sweeps (V0, V1, N) about the deformed state, m/s: finer than the undeformed ones
#: (the static deflection of the HALE wing changes quickly near flutter)
DEFORMED_SWEEPS = {"goland": (20.0, 300.0, 57), "hale": (18.0, 36.0, 37)}
#: root angles of attack accepted (deg): beyond ~10 deg attached-flow strip theory is meaningless
MAX_ROOT_AOA_DEG = 10.0


def check_root_aoa(values) -> np.ndarray:
    """Validated root angles of attack (deg): a non-empty list of finite values in [-10, 10] deg.

    Parameters
    ----------
    values : sequence of float
        Root angles of attack (deg).

    Returns
    -------
    numpy.ndarray
        The checked angles (deg).
    """
    a = np.atleast_1d(np.asarray(values, dtype=float)).ravel()
    if a.size == 0:
        raise ValueError("root angle of attack list is empty: give at least one angle (deg)")
    bad = ~np.isfinite(a) | (np.abs(a) > MAX_ROOT_AOA_DEG)
    if np.any(bad):
        raise ValueError(f"root angle of attack must be finite and within +-{MAX_ROOT_AOA_DEG} deg, "
                         f"got {a[bad][0]} deg")
    return a


def deformed_params_at(prob, alpha_root_deg: float, gravity: float):
    """``params_at(V)`` of ``prob`` (a :class:`~wingmdao.stability.cases.FlutterProblem`) with the
    root angle of attack ``alpha_root_deg`` (deg) and gravity ``gravity`` (m/s^2, along body -z).

    Parameters
    ----------
    prob : FlutterProblem
        The flutter problem.
    alpha_root_deg : float
        Root angle of attack (deg).
    gravity : float
        Gravitational acceleration along body -z (m/s^2).

    Returns
    -------
    callable
        ``params_at(V) -> (p, q)``.
    """
    play, qlay = layout(prob.system.param_specs), layout(prob.system.forcing_specs)
    alpha = np.deg2rad(float(alpha_root_deg))

    def params_at(V):
        p, q = prob.params_at(V)   # new arrays each call
        p[play["alpha_zero_lift"]] -= alpha
        q[qlay["gravity"]] = (0.0, 0.0, -float(gravity))
        return p, q

    return params_at


def tip_deflection(system, x) -> float:
    """Vertical (body z) displacement of the tip node from the jig, m (up +).

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    x : numpy.ndarray
        State.

    Returns
    -------
    float
        Tip deflection (m).
    """
    n = system.num_nodes
    W = system.state_shape[-1] if len(system.state_shape) == 2 else None
    xs = np.asarray(x, dtype=float).ravel()[: n * W].reshape(n, W)
    return float(xs[-1, STATE_BLOCKS["r"]][2] - xs[0, STATE_BLOCKS["r"]][2])


@dataclass
class DeformedFlutter:
    """Flutter about the deformed state at one root angle of attack.

    Parameters
    ----------
    root_aoa_deg : float
        Root angle of attack (deg).
    flutter_speed : float or None
        Flutter speed (m/s).
    flutter_frequency : float or None
        Flutter frequency (rad/s).
    tip_deflection : float or None
        Static tip deflection at flutter (m).
    divergence_speed : float or None
        Divergence speed (m/s).
    speeds : numpy.ndarray or None, optional
        Airspeeds of the sweep (m/s).
    tip_deflections : numpy.ndarray or None, optional
        Static tip deflection at each speed (m).
    damping : numpy.ndarray or None, optional
        Re(lambda) of the tracked modes (1/s).
    frequency : numpy.ndarray or None, optional
        Frequency of the tracked modes (rad/s).
    static_failure_speed : float or None, optional
        First speed without a static solution (m/s).
    """

    root_aoa_deg: float
    flutter_speed: float | None            # m/s
    flutter_frequency: float | None        # rad/s
    tip_deflection: float | None           # m, static tip displacement at the flutter speed
    divergence_speed: float | None         # m/s
    speeds: np.ndarray = field(repr=False, default=None)
    tip_deflections: np.ndarray = field(repr=False, default=None)   # m, static, per sweep speed
    damping: np.ndarray = field(repr=False, default=None)           # (n_speed, n_track) 1/s
    frequency: np.ndarray = field(repr=False, default=None)         # (n_speed, n_track) rad/s
    static_failure_speed: float | None = None   # m/s: no static solution found there (sweep stopped)


def _static_continued(system, params_at, V0, x0, V1, depth=4):
    """Static state at V1 continued from the state x0 at V0, halving the speed step on failure."""
    p, q = params_at(V1)
    try:
        return static_state(system, p, q, x0)
    except om.AnalysisError:
        if depth <= 0:
            raise
        mid = 0.5 * (V0 + V1)
        x_mid = _static_continued(system, params_at, V0, x0, mid, depth - 1)
        return _static_continued(system, params_at, mid, x_mid, V1, depth - 1)


def _tracked_unstable(tracked, min_frequency) -> bool:
    """A tracked mode of non-zero frequency with Re > round-off at the last speed (the test of
    :func:`critical_speeds`)."""
    lam = tracked[-1]
    eps = 1e-9 * np.abs(lam)
    return bool(np.any((lam.real > eps) & (np.abs(lam.imag) > min_frequency)))


def deformed_sweep(prob, params_at, speeds, *, n_track=4, load_steps=8, min_frequency=1e-3):
    """Eigen-analysis about the static state at each speed, continued in speed, stopping at the
    first speed where a tracked mode (the ``n_track`` lowest-frequency modes of the first speed,
    followed by MAC) is unstable (the flutter bracket) or where no static solution is found
    (``stopped_at``, m/s, else None). Untracked modes are ignored: about a lifting, bent state the
    in-plane (lag) mode, without drag or structural damping, can sit at Re ~ +1e-4 ``|lambda|``.
    Returns ``(StabilitySweep, stopped_at)``.

    Parameters
    ----------
    prob : FlutterProblem
        The flutter problem.
    params_at : callable
        ``params_at(V) -> (p, q)``.
    speeds : array_like
        Increasing airspeeds (m/s).
    n_track : int, optional
        Modes tracked.
    load_steps : int, optional
        Load steps of the first static solve.
    min_frequency : float, optional
        Oscillatory above this ``|Im|`` (rad/s).

    Returns
    -------
    tuple
        (StabilitySweep, stopped_at).
    """
    v = check_speeds(speeds)
    system, opts = prob.system, dict(prob.eig_options)
    p, q = params_at(float(v[0]))
    x = static_state(system, p, q, load_steps=int(load_steps))
    modes, stopped = [], None
    for k, V in enumerate(v):
        if k:
            try:
                x = _static_continued(system, params_at, float(v[k - 1]), x, float(V))
            except om.AnalysisError:
                stopped = float(V)
                break
        p, q = params_at(float(V))
        m = eigenmodes(system, p, q, x, static=False, **opts)
        modes.append(m)
        if k == 0:
            osc = np.flatnonzero(m.frequency > min_frequency)
            if osc.size == 0:
                raise ValueError(f"no oscillatory mode at the first speed {v[0]} m/s")
            initial = osc[np.argsort(m.frequency[osc])][: int(n_track)]
        tracked, idx = track_modes(modes, initial, prob.beam_weights())
        if k and _tracked_unstable(tracked, min_frequency):
            break
    if len(modes) < 2:
        raise om.AnalysisError(f"deformed flutter sweep: no static solution beyond {v[0]} m/s")
    vv = v[: len(modes)]
    res = StabilitySweep(vv, modes, tracked, idx, params_at, system,
                         dict(opts, static=True, weights=prob.beam_weights(), min_frequency=min_frequency))
    return res, stopped


def deformed_flutter(prob, root_aoa_deg, speeds=None, *, gravity=None, n_track=4, load_steps=8,
                     xtol=1e-4) -> list[DeformedFlutter]:
    """Flutter speed, frequency and static tip deflection at flutter for each root angle of attack.

    ``gravity`` (m/s^2) defaults to the case's ``GRAVITY``; the first speed's static state is
    reached by ``load_steps`` steps of the weight (large deflections), the others by continuation
    in speed (:func:`deformed_sweep`); the sweep should be fine (~0.5 m/s for the HALE wing) as the
    deflection changes quickly near flutter.

    Parameters
    ----------
    prob : FlutterProblem
        The flutter problem.
    root_aoa_deg : sequence of float
        Root angles of attack (deg).
    speeds : array_like or None, optional
        Sweep (m/s); None for the case's default.
    gravity : float or None, optional
        Gravitational acceleration (m/s^2); None for the case's.
    n_track : int, optional
        Modes tracked.
    load_steps : int, optional
        Load steps of the first static solve.
    xtol : float, optional
        Relative tolerance of the located flutter speed.

    Returns
    -------
    list of DeformedFlutter
        One per angle.
    """
    angles = check_root_aoa(root_aoa_deg)
    v = check_speeds(np.linspace(*DEFORMED_SWEEPS[prob.name]) if speeds is None else speeds)
    if gravity is None:
        gravity = float(getattr(importlib.import_module(f"wingmdao.cases.{prob.name}"), "GRAVITY", 0.0))
    if not np.isfinite(gravity) or gravity < 0.0:
        raise ValueError(f"gravity must be finite and >= 0 m/s^2, got {gravity}")
    out = []
    for a in angles:
        params_at = deformed_params_at(prob, a, gravity)
        res, stopped = deformed_sweep(prob, params_at, v, n_track=n_track, load_steps=load_steps)
        crit = critical_speeds(res, xtol=xtol)
        tips = np.array([tip_deflection(prob.system, m.x0) for m in res.modes])
        tip_f = None
        if crit["flutter_speed"] is not None:
            V_f = crit["flutter_speed"]
            s = int(np.clip(np.searchsorted(res.speeds, V_f), 1, res.speeds.size - 1))
            x_f = _static_continued(prob.system, params_at, float(res.speeds[s - 1]), res.modes[s - 1].x0, V_f)
            tip_f = tip_deflection(prob.system, x_f)
        out.append(DeformedFlutter(float(a), crit["flutter_speed"], crit["flutter_frequency"], tip_f,
                                   crit["divergence_speed"], res.speeds, tips, res.damping, res.frequency,
                                   stopped))
    return out
