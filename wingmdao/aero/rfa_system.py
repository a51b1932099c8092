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

Control surfaces (``controls``, :mod:`wingmdao.aero.modal_controls`): after the gust lag states the
actuator states (deflection, rate per surface), the controller states and one flap lag state per
surface and lag root; the parameters gain the law's matrices ``controller_A`` ... ``controller_D``
and the forcing an open-loop ``surface_command`` per surface (rad, added to the law's).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from wingmdao.aero.rfa import RogerApproximation
from wingmdao.aero.system import ROOT_BENDING_UNIT, _control_residuals, control_param_specs
from wingmdao.timemarch.system import CasadiResidualSystem, VarSpec, layout
from wingmdao.units import G0


def control_state_offset(n_modes: int, n_lags: int) -> int:
    """Index of the first control state in :func:`modal_rfa_system`'s state vector: after the modal
    amplitudes and rates (2 n), the aerodynamic lag states (L n) and the gust lag states (L); the
    actuator states (deflection and rate per surface), the controller states, then the flap lag
    states follow.

    Parameters
    ----------
    n_modes : int
        Number of modes n.
    n_lags : int
        Number of Roger lag roots L.

    Returns
    -------
    int
        The index.
    """
    return 2 * n_modes + n_lags * (n_modes + 1)


def param_specs(n_modes: int | None = None, controls: bool = False) -> list[VarSpec]:
    """Airspeed and density; with ``n_modes`` also the modal mass and stiffness (a design-dependent
    structure, :mod:`wingmdao.aero.modal_design`) and, with ``controls``, the root M_x per unit
    modal acceleration (the inertia row of the law's measured root bending).

    Parameters
    ----------
    n_modes : int or None
        Number of modes; None: airspeed and density only.
    controls : bool
        With ``n_modes``: add ``root_inertia`` (modes,) N m.

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
        if controls:
            specs.append(VarSpec("root_inertia", (n_modes,), None,
                                 "root M_x per unit modal acceleration (N m per modal unit acceleration)"))
    return specs


def forcing_specs(n_modes: int, tail: bool = False, n_surfaces: int = 0) -> list[VarSpec]:
    """Forcing of one instant: the gust at ``x_gust`` and its rates, the applied modal force; with
    ``tail`` (a free aircraft's horizontal tail, :mod:`wingmdao.aero.modal_free`) also the gust at
    the tail and at the wing root.

    Parameters
    ----------
    n_modes : int
        Number of modes.
    tail : bool
        Add the gust at the tail and at the wing root.
    n_surfaces : int
        Control surfaces: an open-loop command each.

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
    if n_surfaces:
        specs.append(VarSpec("surface_command", (n_surfaces,), "rad",
                             "open-loop command of each control surface (added to the control law's)"))
    return specs


def modal_rfa_system(structure, rfa: RogerApproximation, *, design: bool = False, tail=None,
                     controls=None) -> CasadiResidualSystem:
    """The residual system of the module docstring for ``structure``
    (:class:`wingmdao.stability.pk.ModalStructure`) and ``rfa``.

    ``design``: the modal mass and stiffness are parameters ``modal_mass`` and ``modal_stiffness``
    (after airspeed and density; ``structure`` gives only the damping and the size), so the
    marcher's adjoint gives their derivatives (:mod:`wingmdao.aero.modal_design`); with
    ``controls`` also ``root_inertia`` (modes,), the inertia row of the law's measured root
    bending (the design's ``modal_inertia[0, 3]``). ``tail``: the
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
    controls : wingmdao.aero.modal_controls.ModalControlModel or None
        Control surfaces, actuators and law (module docstring); None: none.

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
    ns = 0 if controls is None else controls.n_surfaces
    n_ctl = 0 if controls is None else controls.spec.n_states + L * ns
    base = control_state_offset(n, L)
    x = ca.SX.sym("x", base + n_ctl)
    xd = ca.SX.sym("xdot", x.numel())
    pspecs = (param_specs(n if design else None, controls is not None)
              + ([] if controls is None else control_param_specs(controls.spec)))
    p = ca.SX.sym("p", sum(int(np.prod(s.shape)) for s in pspecs))
    f = ca.SX.sym("q", 3 + n + (2 if tail is not None else 0) + ns)
    V, rho = p[0], p[1]
    qd = 0.5 * rho * V ** 2
    if design:   # C-ordered (n, n) blocks
        M = ca.reshape(p[2:2 + n * n], n, n).T
        K = ca.reshape(p[2 + n * n:2 + 2 * n * n], n, n).T
    else:
        M, K = ca.DM(M), ca.DM(K)
    q, v = x[:n], x[n:2 * n]
    z = [x[2 * n + l * n:2 * n + (l + 1) * n] for l in range(L)]
    zg = x[2 * n + L * n:base]
    qdot, vdot = xd[:n], xd[n:2 * n]
    g, g1, g2 = f[0] / V, f[1] / V, f[2] / V
    A = [ca.DM(a) for a in rfa.A]
    G = [ca.DM(a) for a in rfa.gust]
    lag_force = sum((A[3 + l] @ z[l] for l in range(L)), ca.SX.zeros(n))
    gust_force = G[0] * g + G[1] * (b / V) * g1 + G[2] * (b / V) ** 2 * g2
    for l in range(L):
        gust_force = gust_force + G[3 + l] * zg[l]
    flap_force = ca.SX.zeros(n)
    if controls is not None:
        nsc = controls.spec.n_states
        xc, xcd = x[base:base + nsc], xd[base:base + nsc]
        zf = [x[base + nsc + l * ns:base + nsc + (l + 1) * ns] for l in range(L)]
        delta, rate, drate = xc[0:2 * ns:2], xc[1:2 * ns:2], xcd[1:2 * ns:2]
        Fc = [ca.DM(a) for a in controls.flap]
        flap_force = Fc[0] @ delta + (b / V) * Fc[1] @ rate + (b / V) ** 2 * Fc[2] @ drate
        for l in range(L):
            flap_force = flap_force + Fc[3 + l] @ zf[l]
    R = [qdot - v,
         (M - 0.5 * rho * b ** 2 * A[2]) @ vdot + (ca.DM(C) - 0.5 * rho * V * b * A[1]) @ v
         + (K - qd * A[0]) @ q - qd * lag_force - qd * gust_force - qd * flap_force - f[3:3 + n]
         - (tail.force(qd, V, q, v, f[3 + n], f[4 + n]) if tail is not None else 0)]
    R += [xd[2 * n + l * n:2 * n + (l + 1) * n] - v + rfa.lags[l] * V / b * z[l] for l in range(L)]
    R += [xd[2 * n + L * n + l] - g1 + rfa.lags[l] * V / b * zg[l] for l in range(L)]
    names = (["modal kinematics q' - v"] * n + ["modal equation of motion"] * n
             + ["aerodynamic lag state"] * (L * n) + ["gust lag state"] * L)
    if controls is not None:
        R.append(_control_rows(controls, rfa, q, v, vdot, z, zg, g, g1, g2, delta, rate, drate, zf, V, qd, b,
                               xc, xcd, p, layout(pspecs), f[f.numel() - ns:]))
        R += [xd[base + nsc + l * ns:base + nsc + (l + 1) * ns] - rate + rfa.lags[l] * V / b * zf[l]
              for l in range(L)]
        names += ["control state (actuator or controller)"] * nsc + ["flap lag state"] * (L * ns)
    return CasadiResidualSystem(x, xd, p, f, ca.vertcat(*R), param_specs=pspecs,
                                forcing_specs=forcing_specs(n, tail is not None, ns), name="modal_rfa",
                                describe=lambda i: f"{names[i]} (row {i})",
                                initial_guess=lambda p_, q_: np.zeros(x.numel()))


def _control_rows(ctl, rfa, q, v, vdot, z, zg, g, g1, g2, delta, rate, drate, zf, V, qd, b, xc, xcd, p, play, command):
    """Actuator and controller rows of the modal wing: the strip path's rows
    (:mod:`wingmdao.aero.system`) fed the modal model's measured outputs
    (:mod:`wingmdao.aero.modal_controls`)."""
    L = rfa.n_lags
    Sm, Sg, Sf = ctl.root_motion, ctl.root_gust, ctl.root_flap
    dm = lambda row, vec: ca.dot(ca.DM(row), vec)   # noqa: E731
    root = (dm(Sm[0], q) + (b / V) * dm(Sm[1], v) + (b / V) ** 2 * dm(Sm[2], vdot)
            + sum((dm(Sm[3 + l], z[l]) for l in range(L)), 0)
            + Sg[0] * g + Sg[1] * (b / V) * g1 + Sg[2] * (b / V) ** 2 * g2 + sum((Sg[3 + l] * zg[l] for l in range(L)), 0)
            + dm(Sf[0], delta) + (b / V) * dm(Sf[1], rate) + (b / V) ** 2 * dm(Sf[2], drate)
            + sum((dm(Sf[3 + l], zf[l]) for l in range(L)), 0))
    root = qd * root + (ca.dot(p[play["root_inertia"]], vdot) if "root_inertia" in play
                        else dm(ctl.root_inertia, vdot))
    measured = dict(root_bending=root / ROOT_BENDING_UNIT, tip_acceleration=dm(ctl.tip, vdot) / G0,
                    load_factor=None if ctl.plunge is None else vdot[ctl.plunge] / G0,
                    pitch_rate=None if ctl.pitch is None else v[ctl.pitch])
    return _control_residuals(ctl.spec, xc, xcd, p, play, command, [measured[nm] for nm in ctl.spec.outputs], None)
