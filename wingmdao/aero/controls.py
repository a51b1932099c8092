"""Control surfaces, actuators and linear feedback laws of the coupled aeroelastic model (docs/controls.md).

Flap aerodynamics. A trailing-edge surface of the section (chord c = 2 b) hinged at ``hinge`` x c
aft of the leading edge, deflection beta (trailing edge down positive, rad), is described by
Theodorsen's flap functions T1 ... T19 of the hinge position ``c_h = 2 hinge - 1`` (semichords aft
of midchord) and the reference axis ``a`` (semichords aft of midchord; 0 here, every moment is
formed about midchord and moved to the beam axis by the strip model): T. Theodorsen, "General
theory of aerodynamic instability and the mechanism of flutter", NACA Report 496, 1935, Table I
(T1 ... T14) and its flap forces; for brevity T15 = T4 + T10, T16 = T1 - T8 - (c_h - a) T4 + T11 / 2,
T17 = -2 T9 - T1 + (a - 1/2) T4, T18 = T5 - T4 T10, T19 = -T4 T11 / 2. In the strip model:

* circulatory: the flap adds ``T10 / pi beta + T11 b / (2 pi v_c) dbeta/dt`` to the three-quarter
  chord angle that drives the Wagner states (so the lift lags through the same C(k));
* non-circulatory lift (up) ``-rho b^2 (v_c T4 dbeta/dt + b T1 d2beta/dt2)``, moment about
  midchord (nose up) ``-rho v_c^2 b^2 T15 beta - rho v_c b^3 T16 dbeta/dt - 2 rho b^4 T13 d2beta/dt2``;
* hinge moment per length (trailing edge down positive, the sense of beta)
  ``H = rho b^3 T1 dw_mid/dt - rho v_c b^3 (T1 + T17) w_s - 2 rho b^4 T13 dw_s/dt
  + rho b^4 T3 / pi d2beta/dt2 - rho v_c b^3 T19 / pi dbeta/dt - rho v_c^2 b^2 T18 / pi beta
  - T12 b / (2 pi) L_c`` with ``w_mid`` the normal relative air velocity at midchord (the
  strip's; = dh/dt + V alpha of Theodorsen, h down), ``w_s`` the pitch rate and ``L_c`` the
  circulatory lift (the gust's circulatory lift is given the same chordwise distribution, an
  approximation).

Steady, these give Glauert's thin-airfoil flap results (Glauert, *The Elements of Aerofoil and
Airscrew Theory*, 1926, Ch. VII): dCl/dbeta = 2 T10 = 2 (pi - theta_f + sin theta_f) with
cos theta_f = 1 - 2 hinge, dCm_c/4/dbeta = -T15 / 2, and the hinge-moment coefficients
C_h,alpha = -T12 / 2, C_h,beta = -(T18 + T10 T12) / (2 pi) (on 1/2 rho V^2 c^2).

Actuators. Every surface has two states, its deflection beta and rate r: first order
(``time_constant`` tau) ``tau r + beta - u = 0``, ``dbeta/dt - r = 0``; second order
(``frequency_hz`` f, ``damping`` zeta, omega = 2 pi f) ``dr/dt + 2 zeta omega r + omega^2 (beta - u) = 0``,
``dbeta/dt - r = 0``. ``u`` is the command: the control law's output (rad). Deflection and rate
limits are reported against the histories (:func:`limit_report`), never clipped; a sizing whose gains
are design variables constrains them (:class:`wingmdao.components.actuator_limits.ActuatorLimitKS`).

Control law. A linear state-space controller from the measured outputs y (:data:`MEASUREMENTS`) to
the surface commands u: ``dx_c/dt = A_c x_c + B_c y``, ``u = C_c x_c + D_c y``; a PID law is the
state-space form with an integrator and a first-order filtered derivative (:func:`pid_state_space`).
The four matrices are parameters of the residual, so the gains are inputs of the time-history
component with exact partials and adjoint totals.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

#: measured outputs a control law can feed back (docs/controls.md):
#: ``load_factor`` - load-factor increment at the CG, dw_p/dt / g0 (needs free plunge);
#: ``root_bending`` - wing-root bending moment M_x (MN m, body axes);
#: ``tip_acceleration`` - vertical acceleration of the tip node in g (body z, plunge included);
#: ``pitch_rate`` - body pitch rate (rad/s, needs free pitch).
MEASUREMENTS = ("load_factor", "root_bending", "tip_acceleration", "pitch_rate")
#: the actuator's states per surface
ACTUATOR_STATE_NAMES = ("deflection", "rate")


def _finite(value, name, where):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{where}: {name} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise ValueError(f"{where}: {name} must be finite, got {value!r}")
    return v


@dataclass(frozen=True)
class ControlSurface:
    """A trailing-edge control surface of the half-wing and its actuator.

    ``name``; ``span`` (start, end) as fractions of the semi-span in [0, 1] (spanwise position of
    the beam nodes over the tip node's) or ``nodes`` (first, last) node indices (inclusive; one of
    the two); ``hinge`` the hinge line as a fraction of the chord aft of the leading edge, in
    (0, 1); ``actuator_order`` 1 (``time_constant`` s) or 2 (``frequency_hz``, ``damping``);
    ``max_deflection_deg`` and ``max_rate_deg_s`` the limits the histories are reported against;
    ``maneuver_deg_per_g`` the symmetric maneuver schedule (deg per g of load-factor increment,
    trailing edge down positive): in a trimmed maneuver at load factor n the surface is held at
    ``maneuver_deg_per_g (n - 1)`` while the angle of attack trims the lift (maneuver load
    alleviation, :func:`maneuver_commands`).

    Parameters
    ----------
    name : str
        Surface name.
    hinge : float
        Hinge line, fraction of the chord aft of the leading edge, in (0, 1).
    span : tuple or None, optional
        (start, end) fractions of the semi-span; give ``span`` or ``nodes``.
    nodes : tuple or None, optional
        (first, last) node indices, inclusive.
    actuator_order : {1, 2}, optional
        Actuator order.
    time_constant : float, optional
        First-order actuator time constant (s).
    frequency_hz : float, optional
        Second-order actuator natural frequency (Hz).
    damping : float, optional
        Second-order actuator damping ratio (-).
    max_deflection_deg : float, optional
        Deflection limit (deg).
    max_rate_deg_s : float, optional
        Rate limit (deg/s).
    maneuver_deg_per_g : float, optional
        Symmetric maneuver schedule (deg per g of load-factor increment, trailing edge down +).
    """

    name: str
    hinge: float
    span: tuple | None = None
    nodes: tuple | None = None
    actuator_order: int = 1
    time_constant: float = 0.05
    frequency_hz: float = 10.0
    damping: float = 0.7
    max_deflection_deg: float = 20.0
    max_rate_deg_s: float = 60.0
    maneuver_deg_per_g: float = 0.0

    def __post_init__(self):
        where = f"control surface {self.name!r}"
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"control surface name must be a non-empty string, got {self.name!r}")
        h = _finite(self.hinge, "hinge", where)
        if not 0.0 < h < 1.0:
            raise ValueError(f"{where}: hinge = {h} is outside the chord; allowed range (0, 1) "
                             "(fraction of the chord aft of the leading edge)")
        if (self.span is None) == (self.nodes is None):
            raise ValueError(f"{where}: give exactly one of span (fractions of the semi-span) or nodes (indices)")
        if self.span is not None:
            s = tuple(_finite(v, "span", where) for v in self.span)
            if len(s) != 2 or not (0.0 <= s[0] < s[1] <= 1.0):
                raise ValueError(f"{where}: span = {list(self.span)} is outside the semi-span; allowed "
                                 "0 <= start < end <= 1 (fractions of the semi-span)")
        if self.nodes is not None:
            k = tuple(self.nodes)
            if len(k) != 2 or not all(isinstance(v, (int, np.integer)) for v in k) or not 0 <= k[0] < k[1]:
                raise ValueError(f"{where}: nodes = {list(k)}; allowed two node indices 0 <= first < last")
        if self.actuator_order not in (1, 2):
            raise ValueError(f"{where}: actuator_order = {self.actuator_order!r}; allowed 1 or 2")
        for nm in ("time_constant", "frequency_hz", "damping", "max_deflection_deg", "max_rate_deg_s"):
            if _finite(getattr(self, nm), nm, where) <= 0.0:
                raise ValueError(f"{where}: {nm} = {getattr(self, nm)}; allowed range (0, inf)")
        sched = _finite(self.maneuver_deg_per_g, "maneuver_deg_per_g", where)
        if abs(sched) > 90.0:
            raise ValueError(f"{where}: maneuver_deg_per_g = {sched}; allowed range [-90, 90] deg per g")

    def node_indices(self, node_y) -> tuple:
        """The beam nodes (indices) the surface covers, for spanwise node positions ``node_y`` (m);
        ValueError when ``nodes`` lie outside the beam or a ``span`` holds fewer than two nodes.

        Parameters
        ----------
        node_y : array_like
            (n,) spanwise node positions (m).

        Returns
        -------
        tuple
            (first, last) node indices.
        """
        y = np.asarray(node_y, dtype=float).ravel()
        where = f"control surface {self.name!r}"
        if self.nodes is not None:
            if self.nodes[1] >= y.size:
                raise ValueError(f"{where}: nodes = {list(self.nodes)} outside the span; allowed indices 0 .. {y.size - 1}")
            return tuple(range(self.nodes[0], self.nodes[1] + 1))
        eta = (y - y[0]) / (y[-1] - y[0])
        tol = 1e-9
        idx = tuple(int(i) for i in np.flatnonzero((eta >= self.span[0] - tol) & (eta <= self.span[1] + tol)))
        if len(idx) < 2:
            raise ValueError(f"{where}: span = {list(self.span)} covers {len(idx)} beam node(s); a surface needs at "
                             "least two (widen the span or use more nodes)")
        return idx


def theodorsen_flap_functions(hinge: float, a: float = 0.0) -> dict:
    """Theodorsen's flap functions T1 ... T19 (NACA Rep. 496, 1935, Table I; T15 ... T19 grouped)
    for a hinge at ``hinge`` x chord aft of the leading edge and the axis ``a`` (semichords aft of
    midchord).

    Parameters
    ----------
    hinge : float
        Hinge line, fraction of the chord aft of the leading edge.
    a : float, optional
        Axis position, semichords aft of midchord.

    Returns
    -------
    dict
        ``T1`` ... ``T19``.
    """
    c = 2.0 * float(hinge) - 1.0
    s = math.sqrt(1.0 - c * c)
    ac = math.acos(c)
    T = {}
    T[1] = -s * (2.0 + c * c) / 3.0 + c * ac
    T[2] = c * (1.0 - c * c) - s * (1.0 + c * c) * ac + c * ac * ac
    T[3] = -(0.125 + c * c) * ac * ac + 0.25 * c * s * ac * (7.0 + 2.0 * c * c) - 0.125 * (1.0 - c * c) * (5.0 * c * c + 4.0)
    T[4] = -ac + c * s
    T[5] = -(1.0 - c * c) - ac * ac + 2.0 * c * s * ac
    T[6] = T[2]
    T[7] = -(0.125 + c * c) * ac + 0.125 * c * s * (7.0 + 2.0 * c * c)
    T[8] = -s * (2.0 * c * c + 1.0) / 3.0 + c * ac
    T[9] = 0.5 * (s ** 3 / 3.0 + a * T[4])
    T[10] = s + ac
    T[11] = ac * (1.0 - 2.0 * c) + s * (2.0 - c)
    T[12] = s * (2.0 + c) - ac * (2.0 * c + 1.0)
    T[13] = 0.5 * (-T[7] - (c - a) * T[1])
    T[14] = 1.0 / 16.0 + 0.5 * a * c
    T[15] = T[4] + T[10]
    T[16] = T[1] - T[8] - (c - a) * T[4] + 0.5 * T[11]
    T[17] = -2.0 * T[9] - T[1] + (a - 0.5) * T[4]
    T[18] = T[5] - T[4] * T[10]
    T[19] = -0.5 * T[4] * T[11]
    return T


def flap_lift_effectiveness(hinge: float) -> float:
    """dCl/dbeta (1/rad) of thin-airfoil theory, 2 T10.

    Parameters
    ----------
    hinge : float
        Hinge line, fraction of the chord.

    Returns
    -------
    float
        dCl/dbeta (1/rad).
    """
    return 2.0 * theodorsen_flap_functions(hinge)[10]


def hinge_moment_coefficients(hinge: float) -> tuple:
    """Steady thin-airfoil ``(C_h,alpha, C_h,beta)`` (1/rad; hinge moment over 1/2 rho V^2 c^2,
    trailing edge down positive) from Theodorsen's functions.

    Parameters
    ----------
    hinge : float
        Hinge line, fraction of the chord.

    Returns
    -------
    tuple
        (C_h,alpha, C_h,beta) (1/rad).
    """
    T = theodorsen_flap_functions(hinge)
    return -0.5 * T[12], -(T[18] + T[10] * T[12]) / (2.0 * math.pi)


def flap_terms(T: dict, b, v_c, rho, beta, dbeta, ddbeta):
    """The flap's additions to a strip (symbolic or numeric): ``(alpha_qs, lift_nc, moment_nc_mid)``,
    the three-quarter-chord angle (rad), the non-circulatory lift (N/m, up) and moment about
    midchord (N m/m, nose up) of deflection ``beta``, its rate and acceleration; ``T`` from
    :func:`theodorsen_flap_functions` with a = 0.

    Parameters
    ----------
    T : dict
        Theodorsen's flap functions (:func:`theodorsen_flap_functions`, a = 0).
    b : float or casadi.SX
        Semichord (m).
    v_c : float or casadi.SX
        Airspeed normal to the section (m/s).
    rho : float or casadi.SX
        Air density (kg/m^3).
    beta, dbeta, ddbeta : float or casadi.SX
        Flap deflection (rad), its rate (rad/s) and acceleration (rad/s^2).

    Returns
    -------
    tuple
        (alpha_qs (rad), lift_nc (N/m), moment_nc_mid (N m/m)).
    """
    alpha = T[10] / math.pi * beta + T[11] * b / (2.0 * math.pi * v_c) * dbeta
    lift = -rho * b ** 2 * (v_c * T[4] * dbeta + b * T[1] * ddbeta)
    moment = -rho * v_c ** 2 * b ** 2 * T[15] * beta - rho * v_c * b ** 3 * T[16] * dbeta - 2.0 * rho * b ** 4 * T[13] * ddbeta
    return alpha, lift, moment


def hinge_moment(T: dict, b, v_c, rho, beta, dbeta, ddbeta, dw_mid, w_s, dw_s, lift_circulatory):
    """Hinge moment per length (N m/m, trailing edge down positive) of the section's motion (the
    strip's ``dw_mid``, ``w_s``, ``dw_s``), the flap's and the circulatory lift; ``T`` with a = 0.

    Parameters
    ----------
    T : dict
        Theodorsen's flap functions (:func:`theodorsen_flap_functions`, a = 0).
    b : float or casadi.SX
        Semichord (m).
    v_c : float or casadi.SX
        Airspeed normal to the section (m/s).
    rho : float or casadi.SX
        Air density (kg/m^3).
    beta, dbeta, ddbeta : float or casadi.SX
        Flap deflection (rad), its rate (rad/s) and acceleration (rad/s^2).
    dw_mid : float or casadi.SX
        Rate of the normal relative air velocity at midchord, dw_mid/dt (m/s^2).
    w_s : float or casadi.SX
        Section pitch rate about the beam axis, w_s (rad/s).
    dw_s : float or casadi.SX
        Its rate (rad/s^2).
    lift_circulatory : float or casadi.SX
        Circulatory lift per length (N/m).

    Returns
    -------
    float or casadi.SX
        Hinge moment per length (N m/m).
    """
    return (rho * b ** 3 * T[1] * dw_mid - rho * v_c * b ** 3 * (T[1] + T[17]) * w_s - 2.0 * rho * b ** 4 * T[13] * dw_s
            + rho * b ** 4 * T[3] / math.pi * ddbeta - rho * v_c * b ** 3 * T[19] / math.pi * dbeta
            - rho * v_c ** 2 * b ** 2 * T[18] / math.pi * beta - T[12] * b / (2.0 * math.pi) * lift_circulatory)


def flap_harmonic_loads(k, hinge: float, C):
    """Lift, moment about midchord and hinge moment of a rigid section oscillating its flap,
    beta = e^{i omega t}, k = omega b / V, as coefficients: ``(L / (rho V^2 b), M / (rho V^2 b^2),
    H / (rho V^2 b^2))`` (complex, per radian); ``C`` the lift-deficiency function of k
    (:func:`wingmdao.aero.strip.theodorsen_exact`, or the finite-state model's
    :func:`~wingmdao.aero.strip.theodorsen_jones`).

    Parameters
    ----------
    k : float
        Reduced frequency omega b / V (-).
    hinge : float
        Hinge line, fraction of the chord.
    C : complex
        Lift-deficiency function at k.

    Returns
    -------
    tuple
        Complex lift, moment and hinge-moment coefficients per radian.
    """
    k = np.asarray(k, dtype=float)
    Ck = C(k)
    T = theodorsen_flap_functions(hinge)
    ik = 1j * k
    # with b = V = rho = 1: dbeta = i k beta, d2beta = -k^2 beta
    alpha, lift_nc, moment_nc = flap_terms(T, 1.0, 1.0, 1.0, 1.0, ik, ik * ik)
    lift_c = 2.0 * math.pi * Ck * alpha
    hinge_m = hinge_moment(T, 1.0, 1.0, 1.0, 1.0, ik, ik * ik, 0.0, 0.0, 0.0, lift_c)
    return lift_c + lift_nc, moment_nc + 0.5 * lift_c, hinge_m


def pid_state_space(kp, ki, kd, derivative_time_constant: float = 0.02):
    """(A, B, C, D) of ``u = kp y + ki int y dt + kd dy_f/dt`` for one output and one command, the
    derivative filtered by a first-order lag ``derivative_time_constant`` (s).

    Parameters
    ----------
    kp, ki, kd : float
        Proportional, integral and derivative gains.
    derivative_time_constant : float, optional
        Time constant of the derivative's filter (s).

    Returns
    -------
    tuple
        (A, B, C, D).
    """
    tf = float(derivative_time_constant)
    if not (math.isfinite(tf) and tf > 0):
        raise ValueError(f"derivative_time_constant = {derivative_time_constant}; allowed range (0, inf) s")
    A = np.array([[0.0, 0.0], [0.0, -1.0 / tf]])
    B = np.array([[1.0], [1.0 / tf]])
    C = np.array([[float(ki), -float(kd) / tf]])
    D = np.array([[float(kp) + float(kd) / tf]])
    return A, B, C, D


@dataclass(frozen=True, eq=False)
class ControlLaw:
    """A linear feedback law: measured ``outputs`` (names of :data:`MEASUREMENTS`), ``A`` (n_c, n_c),
    ``B`` (n_c, n_y), ``C`` (n_s, n_c), ``D`` (n_s, n_y) with n_s the number of surfaces (commands in
    the order of the surfaces). Checked on creation: sizes, finiteness, and the open-loop
    controller's stability (no eigenvalue of A with a positive real part).

    Parameters
    ----------
    outputs : tuple of str
        Measured outputs (:data:`MEASUREMENTS`).
    A : numpy.ndarray
        (n_c, n_c) controller dynamics.
    B : numpy.ndarray
        (n_c, n_y) input matrix.
    C : numpy.ndarray
        (n_s, n_c) output matrix.
    D : numpy.ndarray
        (n_s, n_y) feedthrough.
    n_surfaces : int, optional
        Number of surfaces commanded.
    """

    outputs: tuple
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    n_surfaces: int = field(default=1)

    def __post_init__(self):
        for nm in self.outputs:
            if nm not in MEASUREMENTS:
                raise ValueError(f"control law: output {nm!r} unknown; allowed: {', '.join(MEASUREMENTS)}")
        ny, ns = len(self.outputs), int(self.n_surfaces)
        if ny == 0:
            raise ValueError("control law: outputs is empty; give at least one of " + ", ".join(MEASUREMENTS))
        A = np.atleast_2d(np.asarray(self.A, dtype=float)) if np.size(self.A) else np.zeros((0, 0))
        nc = A.shape[0]
        want = {"A": (nc, nc), "B": (nc, ny), "C": (ns, nc), "D": (ns, ny)}
        for nm, shape in want.items():
            m = np.asarray(getattr(self, nm), dtype=float)
            m = m.reshape(shape) if m.size == math.prod(shape) and m.size else (np.zeros(shape) if not m.size else m)
            if m.shape != shape:
                raise ValueError(f"control law: {nm} has shape {np.shape(getattr(self, nm))}; allowed {shape} "
                                 f"({nc} controller states, {ny} outputs, {ns} surfaces)")
            if not np.all(np.isfinite(m)):
                raise ValueError(f"control law: {nm} has a non-finite entry")
            object.__setattr__(self, nm, m)
        if nc:
            eig = np.linalg.eigvals(self.A)
            worst = float(np.max(eig.real))
            if worst > 1e-9 * max(1.0, float(np.max(np.abs(eig)))):
                raise ValueError(f"control law: the open-loop controller is unstable (eigenvalue of A with real part "
                                 f"{worst:.4g} 1/s); allowed: all real parts <= 0")

    @property
    def n_states(self) -> int:
        return self.A.shape[0]

    def matrices(self) -> dict:
        """``{"controller_A": A, ...}``: the residual's parameter values."""
        return {"controller_A": self.A, "controller_B": self.B, "controller_C": self.C, "controller_D": self.D}


@dataclass(frozen=True)
class ControlSpec:
    """What the residual needs of the surfaces and the law (hashable: it keys the built system).

    ``surfaces``: tuples ``(name, nodes, hinge, actuator_order, time_constant, frequency_hz,
    damping)``; ``outputs``: measured outputs; ``n_controller``: controller states.

    Parameters
    ----------
    surfaces : tuple
        ``(name, nodes, hinge, actuator_order, time_constant, frequency_hz, damping)`` per surface.
    outputs : tuple, optional
        Measured outputs.
    n_controller : int, optional
        Controller states.
    """

    surfaces: tuple
    outputs: tuple = ()
    n_controller: int = 0

    @property
    def n_surfaces(self) -> int:
        return len(self.surfaces)

    @property
    def n_states(self) -> int:
        return 2 * self.n_surfaces + self.n_controller

    def state_names(self) -> tuple:
        """Names of the control states in their order (after the rigid-body states, before trim)."""
        out = tuple(f"{s[0]}_{nm}" for s in self.surfaces for nm in ACTUATOR_STATE_NAMES)
        return out + tuple(f"controller_{k}" for k in range(self.n_controller))


def control_spec(surfaces, node_y, law: ControlLaw | None = None) -> ControlSpec:
    """The :class:`ControlSpec` of ``surfaces`` (:class:`ControlSurface`) on a beam with spanwise node
    positions ``node_y`` and an optional ``law``; ValueError for overlapping surfaces or a law whose
    command count differs from the surface count.

    Parameters
    ----------
    surfaces : sequence of ControlSurface
        The surfaces.
    node_y : array_like
        (n,) spanwise node positions (m).
    law : ControlLaw or None, optional
        The control law.

    Returns
    -------
    ControlSpec
        The specification.
    """
    surfaces = tuple(surfaces)
    if not surfaces:
        raise ValueError("control surfaces: none given")
    names = [s.name for s in surfaces]
    if len(set(names)) != len(names):
        raise ValueError(f"control surfaces: names must be unique, got {names}")
    rows, used = [], {}
    for s in surfaces:
        idx = s.node_indices(node_y)
        for i in idx:
            if i in used:
                raise ValueError(f"control surfaces {used[i]!r} and {s.name!r} overlap at node {i}")
            used[i] = s.name
        rows.append((s.name, idx, float(s.hinge), int(s.actuator_order), float(s.time_constant),
                     float(s.frequency_hz), float(s.damping)))
    if law is None:
        return ControlSpec(tuple(rows))
    if law.n_surfaces != len(surfaces):
        raise ValueError(f"control law: {law.n_surfaces} commands for {len(surfaces)} surfaces")
    return ControlSpec(tuple(rows), tuple(law.outputs), law.n_states)


def maneuver_commands(surfaces, load_factor: float) -> np.ndarray:
    """The surfaces' commands (rad) of the symmetric maneuver schedule at ``load_factor`` (g):
    ``maneuver_deg_per_g (n - 1)`` per surface, trailing edge down positive.

    Parameters
    ----------
    surfaces : sequence of ControlSurface
        The surfaces in the order of the commands.
    load_factor : float
        Maneuver load factor n (g).

    Returns
    -------
    numpy.ndarray
        (n_s,) deflection commands (rad).
    """
    return np.radians([float(s.maneuver_deg_per_g) * (float(load_factor) - 1.0) for s in surfaces])


def actuator_residuals(order, tau, freq_hz, zeta, beta, rate, dbeta, drate, command):
    """The two actuator rows of one surface (symbolic or numeric): ``dbeta/dt - r`` and the
    first-order ``tau r + beta - u`` or second-order ``dr/dt + 2 zeta omega r + omega^2 (beta - u)``
    (scaled by 1/omega^2).

    Parameters
    ----------
    order : {1, 2}
        Actuator order.
    tau : float
        First-order time constant (s).
    freq_hz : float
        Second-order natural frequency (Hz).
    zeta : float
        Second-order damping ratio (-).
    beta, rate : float or casadi.SX
        Deflection (rad) and rate state (rad/s).
    dbeta, drate : float or casadi.SX
        Their time derivatives.
    command : float or casadi.SX
        Commanded deflection (rad).

    Returns
    -------
    tuple
        The two residual rows.
    """
    if order == 1:
        return dbeta - rate, tau * rate + beta - command
    w = 2.0 * math.pi * freq_hz
    return dbeta - rate, (drate + 2.0 * zeta * w * rate) / (w * w) + beta - command


def limit_report(time, deflection, rate, surfaces) -> dict:
    """Per surface: deflection and rate histories (deg, deg/s), their peaks and the limits, and
    whether a limit is exceeded (reported, never clipped).

    Parameters
    ----------
    time : array_like
        (n_t,) times (s).
    deflection : array_like
        (n_t, n_s) deflections (rad).
    rate : array_like
        (n_t, n_s) rates (rad/s).
    surfaces : sequence of ControlSurface
        The surfaces.

    Returns
    -------
    dict
        Surface name -> histories, peaks, limits and exceedance.
    """
    out = {}
    for k, s in enumerate(surfaces):
        d = np.degrees(np.asarray(deflection)[:, k])
        r = np.degrees(np.asarray(rate)[:, k])
        pd, pr = float(np.max(np.abs(d))), float(np.max(np.abs(r)))
        out[s.name] = {"deflection_deg": d.tolist(), "rate_deg_s": r.tolist(),
                       "peak_deflection_deg": pd, "max_deflection_deg": float(s.max_deflection_deg),
                       "peak_rate_deg_s": pr, "max_rate_deg_s": float(s.max_rate_deg_s),
                       "deflection_limit_exceeded": bool(pd > s.max_deflection_deg),
                       "rate_limit_exceeded": bool(pr > s.max_rate_deg_s)}
    return out


#: keys of an alleviation file (docs/controls.md) and of its parts
ALLEVIATION_KEYS = ("surfaces", "law")
SURFACE_KEYS = ("name", "span", "nodes", "hinge", "actuator", "max_deflection_deg", "max_rate_deg_s",
                "maneuver_deg_per_g")
ACTUATOR_KEYS = ("order", "time_constant", "frequency_hz", "damping")
LAW_KEYS = ("outputs", "gain", "pid", "state_space")
PID_KEYS = ("kp", "ki", "kd", "derivative_time_constant")
STATE_SPACE_KEYS = ("A", "B", "C", "D")


def _keys(where, data, allowed, required=()):
    if not isinstance(data, dict):
        raise ValueError(f"{where}: expected a mapping with keys {', '.join(allowed)}; got {type(data).__name__}")
    unknown = [k for k in data if k not in allowed]
    if unknown:
        raise ValueError(f"{where}: unknown key {unknown[0]!r}; allowed: {', '.join(allowed)}")
    missing = [k for k in required if k not in data]
    if missing:
        raise ValueError(f"{where}: missing key {missing[0]!r}")


def alleviation_from_dict(data: dict, where: str = "alleviation") -> tuple:
    """``(surfaces, law)`` of an alleviation description (the parsed YAML of docs/controls.md);
    ValueError naming ``where`` and the offending key for missing or unknown keys, wrong gain sizes,
    an unstable open-loop controller, a surface outside the span or a hinge outside the chord.

    Parameters
    ----------
    data : dict
        The parsed alleviation description.
    where : str, optional
        File or key named in errors.

    Returns
    -------
    tuple
        (surfaces, law or None).
    """
    _keys(where, data, ALLEVIATION_KEYS, ("surfaces",))
    raw = data["surfaces"]
    if not isinstance(raw, list) or not raw:
        raise ValueError(f"{where}: surfaces must be a non-empty list")
    surfaces = []
    for k, s in enumerate(raw):
        w = f"{where}: surfaces[{k}]"
        _keys(w, s, SURFACE_KEYS, ("name", "hinge"))
        act = s.get("actuator", {"order": 1})
        _keys(f"{w}.actuator", act, ACTUATOR_KEYS, ("order",))
        kw = {nm: act[nm] for nm in ACTUATOR_KEYS[1:] if nm in act}
        kw.update({nm: s[nm] for nm in ("max_deflection_deg", "max_rate_deg_s", "maneuver_deg_per_g") if nm in s})
        try:
            surfaces.append(ControlSurface(
                str(s["name"]), hinge=s["hinge"], span=tuple(s["span"]) if "span" in s else None,
                nodes=tuple(s["nodes"]) if "nodes" in s else None, actuator_order=act["order"], **kw))
        except ValueError as exc:
            raise ValueError(f"{where}: {exc}") from None
    if "law" not in data or data["law"] is None:
        return tuple(surfaces), None
    law = data["law"]
    _keys(f"{where}: law", law, LAW_KEYS, ("outputs",))
    forms = [k for k in ("gain", "pid", "state_space") if k in law]
    if len(forms) != 1:
        raise ValueError(f"{where}: law needs exactly one of gain, pid, state_space; got {forms or 'none'}")
    outputs = law["outputs"]
    if isinstance(outputs, str):
        outputs = [outputs]
    ns = len(surfaces)
    try:
        if forms[0] == "gain":
            D = np.asarray(law["gain"], dtype=float)
            if D.ndim < 2:  # one gain per output, the same command to every surface
                D = np.tile(np.atleast_1d(D)[None, :], (ns, 1)) if D.size == len(outputs) else D
            return tuple(surfaces), ControlLaw(tuple(outputs), A=np.zeros((0, 0)), B=[], C=[], D=D, n_surfaces=ns)
        if forms[0] == "pid":
            pid = law["pid"]
            _keys(f"{where}: law.pid", pid, PID_KEYS)
            if len(outputs) != 1:
                raise ValueError(f"{where}: law.pid needs exactly one output, got {len(outputs)}")
            A, B, C, D = pid_state_space(pid.get("kp", 0.0), pid.get("ki", 0.0), pid.get("kd", 0.0),
                                         pid.get("derivative_time_constant", 0.02))
            return tuple(surfaces), ControlLaw(tuple(outputs), A, B, np.tile(C, (ns, 1)), np.tile(D, (ns, 1)),
                                               n_surfaces=ns)
        ss = law["state_space"]
        _keys(f"{where}: law.state_space", ss, STATE_SPACE_KEYS, STATE_SPACE_KEYS)
        A = np.asarray(ss["A"], dtype=float)
        return tuple(surfaces), ControlLaw(tuple(outputs), A if A.size else np.zeros((0, 0)), ss["B"], ss["C"],
                                           ss["D"], n_surfaces=ns)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{where}: {exc}") from None


def read_alleviation(path) -> tuple:
    """``(surfaces, law)`` of an alleviation YAML file (:func:`alleviation_from_dict`); errors name the file.

    Parameters
    ----------
    path : str or path-like
        Alleviation YAML file.

    Returns
    -------
    tuple
        (surfaces, law or None).
    """
    import yaml

    try:
        with open(path, encoding="utf-8") as fh:
            data = yaml.safe_load(fh)
    except OSError as exc:
        raise ValueError(f"--alleviation {path}: cannot read the file ({exc.strerror})") from None
    except yaml.YAMLError as exc:
        raise ValueError(f"--alleviation {path}: not valid YAML ({str(exc).splitlines()[0]})") from None
    return alleviation_from_dict(data, f"--alleviation {path}")
