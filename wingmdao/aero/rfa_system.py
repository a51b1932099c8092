"""The modal aeroelastic wing with Roger's lag states as a time-domain residual system (no OpenMDAO).

States ``x = (q, v, z_1 .. z_L, zg_1 .. zg_L)``: the modal amplitudes ``q`` of the jig beam's
modes (:func:`wingmdao.beam.modes.normal_modes`), their rates ``v``, the aerodynamic lag states
``z_l`` (one per mode and lag root) and the gust's lag states ``zg_l``. With Roger's
approximation (:mod:`wingmdao.aero.rfa`) of the doublet-lattice forces, ``Q(p) = A_0 + A_1 p +
A_2 p^2 + sum_l A_(l+2) p / (p + gamma_l)`` and the gust column ``G(p)`` of the same form, the
residual is::

    q' - v = 0
    (M - rho b^2 / 2 A_2) v' + (C - rho V b / 2 A_1) v + (K - q_d A_0) q - q_d sum_l A_(l+2) z_l
        - q_d [G_0 g + G_1 (b / V) g' + G_2 (b / V)^2 g'' + sum_l G_(l+2) zg_l] - f = 0
    z_l' - v + gamma_l (V / b) z_l = 0
    zg_l' - g' + gamma_l (V / b) zg_l = 0

``q_d = rho V^2 / 2``, ``b = b_ref``, ``g = w_g / V`` the gust angle (its rates from the forcing's
gust velocity rate and acceleration), ``f`` an applied modal force. Parameters: airspeed (m/s)
and density (kg/m^3), so the marcher's adjoint gives their derivatives; the modal and Roger
matrices are fixed data of the planform and jig. Marched by :func:`wingmdao.timemarch.bdf.march`
(BDF2) like every other residual system; its linearization at rest is the state matrix of
:func:`wingmdao.stability.pk.state_matrix` (plus the gust states).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from wingmdao.aero.rfa import RogerApproximation
from wingmdao.timemarch.system import CasadiResidualSystem, VarSpec


def param_specs(n_modes: int | None = None) -> list[VarSpec]:
    """Airspeed and density; with ``n_modes`` also the modal mass and stiffness (a design-dependent
    structure, :mod:`wingmdao.aero.modal_design`).

    Parameters
    ----------
    n_modes : int or None
        Number of modes; None: airspeed and density only.

    Returns
    -------
    list of VarSpec
        The parameter specifications.
    """
    specs = [VarSpec("airspeed", (), "m/s", "true airspeed"),
             VarSpec("density", (), "kg/m**3", "air density")]
    if n_modes is not None:
        specs += [VarSpec("modal_mass", (n_modes, n_modes), None, "modal mass matrix (kg m^2 per modal units squared)"),
                  VarSpec("modal_stiffness", (n_modes, n_modes), None,
                          "modal stiffness matrix (N m per modal units squared)")]
    return specs


def forcing_specs(n_modes: int, tail: bool = False) -> list[VarSpec]:
    """Forcing of one instant: the gust at ``x_gust`` and its rates, the applied modal force; with
    ``tail`` (a free aircraft's horizontal tail, :mod:`wingmdao.aero.modal_free`) also the gust at
    the tail and at the wing root.

    Parameters
    ----------
    n_modes : int
        Number of modes.
    tail : bool
        Add the gust at the tail and at the wing root.

    Returns
    -------
    list of VarSpec
        The forcing specifications.
    """
    specs = [VarSpec("gust_velocity", (), "m/s", "vertical gust velocity w_g at x_gust (up)"),
             VarSpec("gust_velocity_rate", (), "m/s**2", "dw_g/dt at x_gust"),
             VarSpec("gust_velocity_acceleration", (), "m/s**3", "d2w_g/dt2 at x_gust"),
             VarSpec("modal_force", (n_modes,), "N*m", "applied generalized force per mode (unit-mass modes)")]
    if tail:
        specs += [VarSpec("tail_gust_velocity", (), "m/s", "gust velocity at the tail's aerodynamic centre (up)"),
                  VarSpec("root_gust_velocity", (), "m/s", "gust velocity at the wing root (the downwash's angle)")]
    return specs


def modal_rfa_system(structure, rfa: RogerApproximation, *, design: bool = False, tail=None) -> CasadiResidualSystem:
    """The residual system of the module docstring for ``structure``
    (:class:`wingmdao.stability.pk.ModalStructure`) and ``rfa``.

    ``design``: the modal mass and stiffness are parameters ``modal_mass`` and ``modal_stiffness``
    (after airspeed and density; ``structure`` gives only the damping and the size), so the
    marcher's adjoint gives their derivatives (:mod:`wingmdao.aero.modal_design`). ``tail``: the
    quasi-steady horizontal tail of a free aircraft (:class:`wingmdao.aero.modal_free.ModalTail`),
    its generalized force ``tail.force(q_d, V, q, v, w_t, w_r)`` added to the modal equations and
    the gust at the tail and root as two more forcing entries.

    Parameters
    ----------
    structure : wingmdao.stability.pk.ModalStructure
        Modal mass, stiffness and damping.
    rfa : wingmdao.aero.rfa.RogerApproximation
        The Roger approximation.
    design : bool
        Modal mass and stiffness as parameters.
    tail : wingmdao.aero.modal_free.ModalTail or None
        The quasi-steady horizontal tail of a free aircraft; None: none.

    Returns
    -------
    CasadiResidualSystem
        The residual system.
    """
    M, K, C = (np.asarray(a, dtype=float) for a in (structure.mass, structure.stiffness, structure.damping))
    n = M.shape[0]
    L = rfa.n_lags
    if rfa.A.shape[1:] != (n, n):
        raise ValueError(f"the approximation has {rfa.A.shape[1]} modes, the structure {n}")
    b = float(rfa.b_ref)
    x = ca.SX.sym("x", 2 * n + L * n + L)
    xd = ca.SX.sym("xdot", x.numel())
    p = ca.SX.sym("p", 2 + (2 * n * n if design else 0))
    f = ca.SX.sym("q", 3 + n + (2 if tail is not None else 0))
    V, rho = p[0], p[1]
    qd = 0.5 * rho * V ** 2
    if design:   # C-ordered (n, n) blocks
        M = ca.reshape(p[2:2 + n * n], n, n).T
        K = ca.reshape(p[2 + n * n:], n, n).T
    else:
        M, K = ca.DM(M), ca.DM(K)
    q, v = x[:n], x[n:2 * n]
    z = [x[2 * n + l * n:2 * n + (l + 1) * n] for l in range(L)]
    zg = x[2 * n + L * n:]
    qdot, vdot = xd[:n], xd[n:2 * n]
    g, g1, g2 = f[0] / V, f[1] / V, f[2] / V
    A = [ca.DM(a) for a in rfa.A]
    G = [ca.DM(a) for a in rfa.gust]
    lag_force = sum((A[3 + l] @ z[l] for l in range(L)), ca.SX.zeros(n))
    gust_force = G[0] * g + G[1] * (b / V) * g1 + G[2] * (b / V) ** 2 * g2
    for l in range(L):
        gust_force = gust_force + G[3 + l] * zg[l]
    R = [qdot - v,
         (M - 0.5 * rho * b ** 2 * A[2]) @ vdot + (ca.DM(C) - 0.5 * rho * V * b * A[1]) @ v
         + (K - qd * A[0]) @ q - qd * lag_force - qd * gust_force - f[3:3 + n]
         - (tail.force(qd, V, q, v, f[3 + n], f[4 + n]) if tail is not None else 0)]
    R += [xd[2 * n + l * n:2 * n + (l + 1) * n] - v + rfa.lags[l] * V / b * z[l] for l in range(L)]
    R += [xd[2 * n + L * n + l] - g1 + rfa.lags[l] * V / b * zg[l] for l in range(L)]
    names = (["modal kinematics q' - v"] * n + ["modal equation of motion"] * n
             + ["aerodynamic lag state"] * (L * n) + ["gust lag state"] * L)
    return CasadiResidualSystem(x, xd, p, f, ca.vertcat(*R), param_specs=param_specs(n if design else None),
                                forcing_specs=forcing_specs(n, tail is not None), name="modal_rfa",
                                describe=lambda i: f"{names[i]} (row {i})",
                                initial_guess=lambda p_, q_: np.zeros(x.numel()))
