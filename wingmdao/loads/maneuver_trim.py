"""Elevator trim of a static symmetric maneuver of the aircraft with a horizontal tail (docs/controls.md,
"Elevator trim of the maneuvers").

The free-pitch aeroelastic system (:mod:`wingmdao.aero.pitch`, ``plunge=True, trim=True, pitch=True``)
trimmed with ``trim_active`` = 1 solves two unknowns, the aircraft angle of attack alpha (wing and
tail lift = ``trim_lift`` = n W) and the tail incidence i_t (zero pitching moment about the body-axes
origin, the body's weight n M g at its CG, the wing's root loads and the tail lift), on the deforming
wing. The static maneuver at load factor n is the state under gravity n g0 (the beam's and the body's
weight and inertia relief; a steady pull-up's pitch rate is left out, as in the maneuvers without a
tail).

The stabiliser is set by the 1 g trim: i_t = i_t(1). At n g the elevator takes up the rest. The tail
angle is ``alpha_t = alpha (1 - deps/dalpha) + i_t + tau_e delta`` (quasi-steady tail of
:func:`wingmdao.aero.pitch.body_residuals`), linear in i_t and delta with the same lift in both, so the
trim at n with the incidence held at i_t(1) is the trim at n with the incidence free, with

    delta(n) = (i_t(n) - i_t(1)) / tau_e                                    (1)

and every other state equal (alpha, the wing's deformation, the tail lift): the two equations
(lift, moment) in the two unknowns (alpha, delta). :func:`elevator_trim` solves both trims and
returns (1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wingmdao.loads.atmosphere import G0
from wingmdao.timemarch.bdf import solve_static
from wingmdao.timemarch.system import layout


@dataclass
class ElevatorTrim:
    """A trimmed static maneuver of :func:`elevator_trim` (SI, angles in rad).

    Parameters
    ----------
    load_factor : float
        n (g).
    alpha : float
        The aircraft angle of attack (rad).
    tail_incidence_1g : float
        The stabiliser setting of the 1 g trim (rad).
    elevator : float
        The elevator angle (1), rad, trailing edge down +.
    tail_lift : float
        Tail lift (N).
    wing_lift : float
        Lift of both half-wings (N).
    state : numpy.ndarray
        The maneuver's trimmed state (incidence free).
    """

    load_factor: float
    alpha: float
    tail_incidence_1g: float
    elevator: float
    tail_lift: float
    wing_lift: float
    state: np.ndarray

    def as_dict(self) -> dict:
        """JSON-ready values (degrees for the angles)."""
        return {"load_factor": self.load_factor, "alpha_deg": float(np.degrees(self.alpha)),
                "tail_incidence_1g_deg": float(np.degrees(self.tail_incidence_1g)),
                "elevator_deg": float(np.degrees(self.elevator)), "tail_lift_n": self.tail_lift,
                "wing_lift_n": self.wing_lift}


def maneuver_forcing(system, load_factor: float, gravity: float = G0) -> np.ndarray:
    """The forcing of the trimmed static maneuver at ``load_factor`` of a free-pitch ``system``: gravity
    ``-n g`` along body z, ``trim_active`` 1, everything else zero.

    Parameters
    ----------
    system : AeroelasticBeamSystem
        A system with ``trim`` and ``pitch``.
    load_factor : float
        n (g).
    gravity : float
        g (m/s^2).

    Returns
    -------
    numpy.ndarray
        The packed forcing (n_forcing,).
    """
    ql = layout(system.forcing_specs)
    q = np.zeros(system.n_forcing)
    q[ql["gravity"].start + 2] = -float(load_factor) * float(gravity)
    q[ql["trim_active"]] = 1.0
    return q


def elevator_trim(system, p, load_factor: float, *, elevator_effectiveness: float, weight: float,
                  gravity: float = G0, state=None) -> ElevatorTrim:
    """Trim the static maneuver at ``load_factor`` by angle of attack and elevator, the stabiliser at
    its 1 g setting (module docstring, (1)).

    Parameters
    ----------
    system : AeroelasticBeamSystem
        The free-pitch system (``plunge``, ``trim``, ``pitch``; an elevator, if any, commanded 0).
    p : array_like
        Packed parameters; ``trim_lift`` is replaced by n ``weight`` and ``weight``.
    load_factor : float
        n (g), finite and non-zero.
    elevator_effectiveness : float
        tau_e in (0, 1] (:func:`wingmdao.aero.pitch.elevator_effectiveness`).
    weight : float
        Aircraft weight W (N).
    gravity : float
        g (m/s^2).
    state : array_like, optional
        The maneuver's trimmed state if already solved (e.g. a sizing's), else solved here.

    Returns
    -------
    ElevatorTrim
        The trim at n.
    """
    if not getattr(system, "pitch", False) or not getattr(system, "trim", False):
        raise ValueError("elevator_trim needs a free-pitch system with trim (pitch=True, trim=True)")
    n = float(load_factor)
    if not (np.isfinite(n) and n != 0.0):
        raise ValueError(f"load_factor = {load_factor}; allowed a finite non-zero load factor (g)")
    tau = float(elevator_effectiveness)
    if not (np.isfinite(tau) and 0.0 < tau <= 1.0):
        raise ValueError(f"elevator_effectiveness = {elevator_effectiveness}; allowed range (0, 1]")
    if not (np.isfinite(weight) and weight > 0):
        raise ValueError(f"weight = {weight} N; allowed range (0, inf) N")
    pl = layout(system.param_specs)
    p = np.array(p, dtype=float).ravel()

    def solve(n_g, x=None):
        pp = p.copy()
        pp[pl["trim_lift"]] = n_g * weight
        q = maneuver_forcing(system, n_g, gravity)
        if x is None:
            x, _ = solve_static(system, pp, q)
        return np.asarray(x, dtype=float).ravel(), pp, q

    x1, _, _ = solve(1.0)
    xn, pn, qn = solve(n, state)
    i_t = system.body_index["tail_incidence"]
    zero = np.zeros_like(xn)
    lift_t = float(system._tail_lift(xn, zero, pn, qn))
    return ElevatorTrim(n, float(xn[system.trim_index]), float(x1[i_t]), float((xn[i_t] - x1[i_t]) / tau),
                        lift_t, n * float(weight) - lift_t, xn)
