"""Small residual systems for tests, examples and benchmarks.

* :func:`spring_mass_damper_system`: the spring-mass-damper of Sec. 4.6.1 (Eq. 4.29-4.31),
  parameters of Table 4.18 in :data:`SMD_TABLE_4_18`;
* :func:`spring_mass_damper_response`: its closed-form free response (for convergence tests);
* :func:`potential_energy_integral`: the functional of Eq. 4.33 and its partials;
* :func:`nonlinear_chain_system`: a chain of masses on nonlinear (cubic) springs, a larger
  test system of any size.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from wingmdao.timemarch.system import CasadiResidualSystem, VarSpec

#: Table 4.18: mass (kg), damping (N s/m), stiffness (N/m), and the time step (s). The
#: 8.666966 value of f in Table 4.19 corresponds to 10 s of free response from x = 1 m.
SMD_TABLE_4_18 = {"mass": 2.5, "damping": 0.2, "stiffness": 5.0, "dt": 1e-3, "t_final": 10.0}


def spring_mass_damper_system() -> CasadiResidualSystem:
    """SMD in first-order residual form (Eq. 4.30-4.31), states ``[x1, x2]`` = (position, velocity).

    ``R1 = m xdot2 + c x2 + k x1 - force``, ``R2 = x2 - xdot1``. Parameters ``mass``,
    ``damping``, ``stiffness``; forcing ``force`` (N, zero in Sec. 4.6.1).
    """
    x, xd = ca.SX.sym("x", 2), ca.SX.sym("xdot", 2)
    p, q = ca.SX.sym("p", 3), ca.SX.sym("q", 1)
    m, c, k = p[0], p[1], p[2]
    R = ca.vertcat(m * xd[1] + c * x[1] + k * x[0] - q[0], x[1] - xd[0])
    names = ["momentum balance m xdot2 + c x2 + k x1 = force", "kinematics x2 = xdot1"]
    return CasadiResidualSystem(
        x, xd, p, q, R,
        param_specs=[VarSpec("mass", (), "kg", "oscillator mass"),
                     VarSpec("damping", (), "N*s/m", "viscous damping constant"),
                     VarSpec("stiffness", (), "N/m", "spring stiffness")],
        forcing_specs=[VarSpec("force", (), "N", "external force on the mass")],
        name="smd", describe=lambda i: names[i],
    )


def spring_mass_damper_response(t, mass, damping, stiffness, x0=1.0, v0=0.0):
    """Closed-form free response ``(x(t), v(t))`` of an underdamped SMD.

    Parameters
    ----------
    t : array_like
        Times (s).
    mass : float
        Mass (kg).
    damping : float
        Viscous damping constant (N s/m); the damping ratio must be below 1.
    stiffness : float
        Spring stiffness (N/m).
    x0 : float
        Initial position (m).
    v0 : float
        Initial velocity (m/s).

    Returns
    -------
    x : ndarray
        Position (m) at ``t``.
    v : ndarray
        Velocity (m/s) at ``t``.
    """
    t = np.asarray(t, dtype=float)
    wn = np.sqrt(stiffness / mass)
    zeta = damping / (2.0 * np.sqrt(stiffness * mass))
    if zeta >= 1.0:
        raise ValueError(f"damping ratio {zeta:.3g} >= 1: only the underdamped response is implemented")
    wd = wn * np.sqrt(1.0 - zeta**2)
    a, b = x0, (v0 + zeta * wn * x0) / wd
    e = np.exp(-zeta * wn * t)
    x = e * (a * np.cos(wd * t) + b * np.sin(wd * t))
    v = -zeta * wn * x + e * (-a * wd * np.sin(wd * t) + b * wd * np.cos(wd * t))
    return x, v


def potential_energy_integral(states, dt, stiffness):
    """Eq. 4.33 (summed over i = 0..n as Eq. 3.8): ``f = sum_i dt k x1_i^2 / 2`` and its partials.

    Returns ``(f, df/dstates (n_time, 2), df/dstiffness)``. With Table 4.18 and x(0) = 1 m,
    f = 8.666966 (Table 4.19).

    Parameters
    ----------
    states : array_like, shape (n_time, 2)
        State history ``[x1, x2]`` (m, m/s).
    dt : float
        Time step (s).
    stiffness : float
        Spring stiffness (N/m).
    """
    X = np.asarray(states, dtype=float)
    x1 = X[:, 0]
    f = 0.5 * dt * stiffness * float(x1 @ x1)
    dfdx = np.zeros_like(X)
    dfdx[:, 0] = dt * stiffness * x1
    return f, dfdx, 0.5 * dt * float(x1 @ x1)


def nonlinear_chain_system(n_mass: int = 10) -> CasadiResidualSystem:
    """Chain of ``n_mass`` equal masses between a wall and cubic springs, damped.

    States per mass ``[u, v]`` (displacement, velocity); residuals
    ``m vdot + c v + k (1 + g u_rel^2) u_rel - ... - force = 0`` and ``v - udot = 0``.
    Parameters: ``mass`` (kg), ``damping`` (N s/m), ``stiffness`` (N/m, one per spring),
    ``hardening`` (1/m^2); forcing ``force`` (N, one per mass).

    Parameters
    ----------
    n_mass : int
        Number of masses.

    Returns
    -------
    CasadiResidualSystem
        The system, states of shape ``(n_mass, 2)``.
    """
    n = int(n_mass)
    x, xd = ca.SX.sym("x", 2 * n), ca.SX.sym("xdot", 2 * n)
    p, q = ca.SX.sym("p", 3 + n), ca.SX.sym("q", n)
    m, c, g = p[0], p[1], p[2]
    k = p[3:]
    u, v = x[0::2], x[1::2]
    ud, vd = xd[0::2], xd[1::2]
    stretch = ca.vertcat(u[0], u[1:] - u[:-1])
    tension = k * (stretch + g * stretch**3)
    res = []
    for i in range(n):
        outer = tension[i + 1] if i + 1 < n else 0.0
        res += [m * vd[i] + c * v[i] + tension[i] - outer - q[i], v[i] - ud[i]]
    names = [f"mass {i // 2}: {'momentum' if i % 2 == 0 else 'kinematics'}" for i in range(2 * n)]
    return CasadiResidualSystem(
        x, xd, p, q, ca.vertcat(*res),
        param_specs=[VarSpec("mass", (), "kg", "mass of each node"),
                     VarSpec("damping", (), "N*s/m", "damping of each node"),
                     VarSpec("hardening", (), "1/m**2", "cubic spring coefficient"),
                     VarSpec("stiffness", (n,), "N/m", "linear stiffness of each spring")],
        forcing_specs=[VarSpec("force", (n,), "N", "force on each mass")],
        state_shape=(n, 2), name=f"chain{n}", describe=lambda i: names[i],
    )
