"""Geometrically nonlinear Timoshenko beam (App. A, ASWING form) as a CasADi residual system.

Unknowns per node (docs/conventions.md), node-major: r (3), theta (3), F (3), M (3), u (3),
omega (3); all vectors in body axes except the Euler angles theta = (phi, twist, psi) of
:mod:`wingmdao.beam.rotations`. F_i, M_i are the resultants the outboard part exerts on the
inboard part across a cut just inboard of node i (so a tip point load P gives F_tip = P and a
point load at an interior node i enters the equilibrium of element i).

Equations, 18 per node (derivations in docs/beam-theory.md):

* element i (nodes i, i+1), rows 18 i .. 18 i + 11:
  force equilibrium (Eq. A.10), moment equilibrium about node i (Eq. A.11),
  moment-curvature (Eq. A.18-A.19) and strain-displacement (Eq. A.20), with the jig terms
  subtracted so that the unloaded jig shape is an exact solution; the constitutive averages
  use the resultants just outboard of node i (F_i - P_i, M_i - Q_i);
* last node, rows 18 (n-1) .. 18 (n-1) + 11: root clamp r_1 = r0_1, theta_1 = theta0_1, and
  tip conditions F_n = point_force_n, M_n = point_moment_n;
* every node, rows 18 i + 12 .. 18 i + 17: u - dr/dt = 0 and
  omega - T^T K(theta) dtheta/dt = 0.

Optional Kelvin-Voigt strain-rate damping (Alg. 6, lines 6-7, time constants t_kappa and t_gamma;
:class:`StrainRateDamping`) adds t_kappa * d(curvature)/dt to the moment-curvature rows and
t_gamma * d(strain)/dt to the strain-displacement rows.

Distributed loads are per unit *undeformed* length (multiplied by ds0).
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass

import casadi as ca
import numpy as np

from wingmdao.beam.rotations import body_to_csn, rate_matrix
from wingmdao.timemarch import lu_orders
from wingmdao.timemarch.system import HISTORY_PARTS, JIT_THRESHOLD, CasadiResidualSystem, VarSpec, layout
from wingmdao.utils import function_store
from wingmdao.utils.casadi_cache import cached, definition_key, function_key, jit_enabled, precompiled_call

#: Per-node state blocks (docs/conventions.md).
STATE_BLOCKS = {"r": slice(0, 3), "theta": slice(3, 6), "F": slice(6, 9), "M": slice(9, 12),
                "u": slice(12, 15), "omega": slice(15, 18)}
N_STATE_PER_NODE = 18

_ELEMENT_EQUATIONS = ("force equilibrium", "moment equilibrium", "moment-curvature",
                      "strain-displacement")
_NODAL_EQUATIONS = ("velocity u - dr/dt", "angular rate omega - Euler rates")
_BC_EQUATIONS = ("root position clamp", "root angle clamp", "tip force", "tip moment")
_BODY = "xyz"
_ANGLES = ("phi", "twist", "psi")


def param_specs(n: int) -> list[VarSpec]:
    """Time-invariant parameters p of an n-node beam (per node, root first).

    Parameters
    ----------
    n : int
        Number of nodes.

    Returns
    -------
    list of VarSpec
        The parameter blocks, in packing order.
    """
    return [
        VarSpec("node_positions", (n, 3), "m", "jig beam-axis node positions, body axes"),
        VarSpec("node_euler_angles", (n, 3), "rad", "jig Euler angles (phi, twist, psi) of the csn frames"),
        VarSpec("stiffness_csn", (n, 3, 3), "N*m**2", "moment/curvature stiffness E in csn (Eq. A.6)"),
        VarSpec("compliance_csn", (n, 3), "1/N", "1/(G K_c), 1/(E A), 1/(G K_n) (Eq. A.7)"),
        VarSpec("tension_axis", (n, 2), "m", "(c, n) of the tension axis from the beam axis"),
        VarSpec("shear_center", (n, 2), "m", "(c, n) of the shear centre from the beam axis"),
        VarSpec("mass_per_length", (n,), "kg/m", "mass per unit length"),
        VarSpec("mass_center", (n, 2), "m", "(c, n) of the mass centre from the beam axis"),
        VarSpec("inertia_per_length", (n, 3, 3), "kg*m", "rotary inertia per length about the mass centre, csn"),
    ]


def forcing_specs(n: int) -> list[VarSpec]:
    """Forcing q at one instant (body axes).

    Parameters
    ----------
    n : int
        Number of nodes.

    Returns
    -------
    list of VarSpec
        The forcing blocks, in packing order.
    """
    return [
        VarSpec("force_per_length", (n, 3), "N/m", "dead distributed force per undeformed length"),
        VarSpec("moment_per_length", (n, 3), "N*m/m", "dead distributed moment per undeformed length"),
        VarSpec("point_force", (n, 3), "N", "point force at each node"),
        VarSpec("point_moment", (n, 3), "N*m", "point moment at each node"),
        VarSpec("gravity", (3,), "m/s**2", "gravitational acceleration, body axes"),
        VarSpec("frame_acceleration", (3,), "m/s**2", "acceleration A0 of the body-axes origin"),
        VarSpec("frame_angular_velocity", (3,), "rad/s", "angular velocity Omega of the body axes"),
        VarSpec("frame_angular_acceleration", (3,), "rad/s**2", "angular acceleration alpha0 of the body axes"),
    ]


# --------------------------------------------------------------------------- helpers
def _node_block(vec, start, n, i, width):
    """Entries of node i of a C-ordered (n, width) block starting at ``start`` of ``vec``."""
    return vec[start + width * i: start + width * (i + 1)]


def _mat3(v9):
    """3x3 SX matrix from 9 C-ordered (row-major) entries."""
    return ca.vertcat(*[ca.horzcat(v9[3 * r], v9[3 * r + 1], v9[3 * r + 2]) for r in range(3)])


def offset_matrix(tension_axis, shear_center):
    """D of Eq. A.8 as derived: M' = M_csn - D F_csn, strain = S F_csn - D^T kappa.

    Bending (c, n) moments are taken about the tension axis (c_ta, n_ta), where the axial
    force acts; torsion about the shear centre (c_sc, n_sc), where the shear forces act.

    Parameters
    ----------
    tension_axis : casadi.SX or sequence
        ``(c, n)`` of the tension axis from the beam axis (m).
    shear_center : casadi.SX or sequence
        ``(c, n)`` of the shear centre from the beam axis (m).

    Returns
    -------
    casadi.SX, shape (3, 3)
        D.
    """
    c_ta, n_ta = tension_axis[0], tension_axis[1]
    c_sc, n_sc = shear_center[0], shear_center[1]
    return ca.vertcat(ca.horzcat(0, -n_ta, 0), ca.horzcat(n_sc, 0, -c_sc), ca.horzcat(0, c_ta, 0))


@dataclass
class _Sym:
    """Per-node symbolic state, state rate and forcing of one element function."""

    x: ca.SX
    xdot: ca.SX
    q: ca.SX


def _node_symbols():
    return _Sym(ca.SX.sym("x", 18), ca.SX.sym("xdot", 18), ca.SX.sym("q", 12))


#: Per-node parameter layout inside the element function (34 entries).
NODE_PARAMS = {"r0": slice(0, 3), "theta0": slice(3, 6), "E": slice(6, 15), "S": slice(15, 18),
               "ta": slice(18, 20), "sc": slice(20, 22), "mu": slice(22, 23), "cg": slice(23, 25),
               "i": slice(25, 34)}
#: Per-node forcing layout (12 entries): f, m, P, Q.
NODE_FORCING = {"f": slice(0, 3), "m": slice(3, 6), "P": slice(6, 9), "Q": slice(9, 12)}


def _avg(a, b, key, table):
    return 0.5 * (a[table[key]] + b[table[key]])


def nodal_acceleration(r, u, udot, frame):
    """a_i = A0 + du/dt + alpha0 x r + Omega x (Omega x r) + 2 Omega x u (Alg. 2, line 6).

    Parameters
    ----------
    r : casadi.SX, shape (3,)
        Node position (m), body axes.
    u : casadi.SX, shape (3,)
        Node velocity relative to the body axes (m/s).
    udot : casadi.SX, shape (3,)
        Its rate (m/s^2).
    frame : tuple of casadi.SX
        ``(A0, Omega, alpha0)``: acceleration of the body-axes origin (m/s^2), angular velocity
        (rad/s) and angular acceleration (rad/s^2) of the body axes.

    Returns
    -------
    casadi.SX, shape (3,)
        Absolute acceleration of the node in body axes (m/s^2).
    """
    acc0, rate, alpha0 = frame
    return acc0 + udot + ca.cross(alpha0, r) + ca.cross(rate, ca.cross(rate, r)) + 2 * ca.cross(rate, u)


@dataclass(frozen=True)
class StrainRateDamping:
    """Kelvin-Voigt strain-rate damping of Alg. 6 (lines 6-7): time constants in s.

    ``curvature`` = (t_kappa_c, t_kappa_s, t_kappa_n) multiply the rates of the bending (c, n)
    and twist (s) curvatures, ``strain`` = (t_gamma_c, t_gamma_s, t_gamma_n) those of the
    shear (c, n) and axial (s) strains, so M = E (kappa + t_kappa dkappa/dt) per component.
    A mode of circular frequency w governed by one of these strains gets the damping ratio
    zeta = w t / 2 (docs/beam-theory.md, "Strain-rate damping").

    Parameters
    ----------
    curvature : tuple of 3 float
        Time constants ``(t_kappa_c, t_kappa_s, t_kappa_n)`` (s), each finite and >= 0.
    strain : tuple of 3 float
        Time constants ``(t_gamma_c, t_gamma_s, t_gamma_n)`` (s), each finite and >= 0.
    """

    curvature: tuple = (0.0, 0.0, 0.0)
    strain: tuple = (0.0, 0.0, 0.0)

    def __post_init__(self):
        for name in ("curvature", "strain"):
            vals = tuple(float(v) for v in getattr(self, name))
            if len(vals) != 3 or not all(math.isfinite(v) and v >= 0.0 for v in vals):
                raise ValueError(f"StrainRateDamping.{name} must be 3 finite time constants >= 0 s, got {vals}")
            object.__setattr__(self, name, vals)

    @classmethod
    def from_damping_ratio(cls, zeta: float, frequency_hz: float) -> StrainRateDamping:
        """Time constant t = 2 zeta / w = zeta / (pi f) on every strain: damping ratio ``zeta`` at
        ``frequency_hz`` (e.g. the first bending mode), proportionally more above it.

        Parameters
        ----------
        zeta : float
            Damping ratio, in [0, 1).
        frequency_hz : float
            Reference frequency (Hz), > 0.

        Returns
        -------
        StrainRateDamping
            The same time constant on all six strains.
        """
        if not (math.isfinite(zeta) and 0.0 <= zeta < 1.0):
            raise ValueError(f"damping ratio zeta must be in [0, 1), got {zeta}")
        if not (math.isfinite(frequency_hz) and frequency_hz > 0.0):
            raise ValueError(f"reference frequency must be > 0 Hz, got {frequency_hz}")
        t = zeta / (math.pi * frequency_hz)
        return cls((t, t, t), (t, t, t))

    @property
    def is_zero(self) -> bool:
        return not any(self.curvature) and not any(self.strain)


def element_function(sequence, damping: StrainRateDamping | None = None):
    """The CasADi function of one element's 12 residuals (force, moment, moment-curvature,
    strain-displacement).

    Parameters
    ----------
    sequence : str
        Euler-angle sequence of the node rotations (``"surface"``, ...; :mod:`wingmdao.beam.rotations`).
    damping : StrainRateDamping, optional
        Kelvin-Voigt strain-rate damping (None: none).

    Returns
    -------
    casadi.Function
        ``beam_element(x_a, x_b, xdot_a, xdot_b, p_a, p_b, q_a, q_b, g, *frame) -> R (12)``: the
        states (18 each, :data:`STATE_BLOCKS`), parameters (34 each, :data:`NODE_PARAMS`; a node's
        from :func:`node_params`) and forcing (12 each, :data:`NODE_FORCING`; :func:`node_forcing`)
        of the element's two nodes, gravity and the body frame.
    """
    a, b = _node_symbols(), _node_symbols()
    pa = ca.SX.sym("pa", 34)
    pb = ca.SX.sym("pb", 34)
    g = ca.SX.sym("g", 3)
    frame = (ca.SX.sym("A0", 3), ca.SX.sym("Omega", 3), ca.SX.sym("alpha0", 3))
    xa, xb = a.x, b.x
    st = STATE_BLOCKS
    r_a, r_b = xa[st["r"]], xb[st["r"]]
    th_a, th_b = xa[st["theta"]], xb[st["theta"]]
    F_a, F_b = xa[st["F"]], xb[st["F"]]
    M_a, M_b = xa[st["M"]], xb[st["M"]]
    u_a, u_b = xa[st["u"]], xb[st["u"]]
    w_a, w_b = xa[st["omega"]], xb[st["omega"]]
    r0_a, r0_b = pa[NODE_PARAMS["r0"]], pb[NODE_PARAMS["r0"]]
    th0_a, th0_b = pa[NODE_PARAMS["theta0"]], pb[NODE_PARAMS["theta0"]]
    ds0 = ca.norm_2(r0_b - r0_a)

    # element averages (ASWING style)
    theta_m = 0.5 * (th_a + th_b)
    theta0_m = 0.5 * (th0_a + th0_b)
    T = body_to_csn(theta_m, sequence)
    T0 = body_to_csn(theta0_m, sequence)
    E_a, E_b = _mat3(pa[NODE_PARAMS["E"]]), _mat3(pb[NODE_PARAMS["E"]])
    S = ca.diag(_avg(pa, pb, "S", NODE_PARAMS))
    D = offset_matrix(_avg(pa, pb, "ta", NODE_PARAMS), _avg(pa, pb, "sc", NODE_PARAMS))
    mu = _avg(pa, pb, "mu", NODE_PARAMS)
    cg = _avg(pa, pb, "cg", NODE_PARAMS)
    i_csn = _mat3(_avg(pa, pb, "i", NODE_PARAMS))
    qa, qb = a.q, b.q
    # resultants just outboard of node a (the cut value F_a, M_a includes node a's point loads)
    F_m = 0.5 * (F_a - qa[NODE_FORCING["P"]] + F_b)
    M_m = 0.5 * (M_a - qa[NODE_FORCING["Q"]] + M_b)
    f_dead = _avg(qa, qb, "f", NODE_FORCING)
    m_dead = _avg(qa, qb, "m", NODE_FORCING)

    # inertial loads per undeformed length (Alg. 2-3)
    acc_a = nodal_acceleration(r_a, u_a, a.xdot[st["u"]], frame)
    acc_b = nodal_acceleration(r_b, u_b, b.xdot[st["u"]], frame)
    w_tot = frame[1] + 0.5 * (w_a + w_b)
    wdot_tot = frame[2] + 0.5 * (a.xdot[st["omega"]] + b.xdot[st["omega"]]) + ca.cross(frame[1], 0.5 * (w_a + w_b))
    d_cg = T.T @ ca.vertcat(cg[0], 0, cg[1])
    acc_cg = 0.5 * (acc_a + acc_b) + ca.cross(wdot_tot, d_cg) + ca.cross(w_tot, ca.cross(w_tot, d_cg))
    f_inertial = mu * (g - acc_cg)
    I_body = T.T @ i_csn @ T
    m_inertial = ca.cross(d_cg, f_inertial) - (I_body @ wdot_tot + ca.cross(w_tot, I_body @ w_tot))
    f_tot = f_dead + f_inertial
    m_tot = m_dead + m_inertial

    # equilibrium of the element between the cut inboard of node a and the cut inboard of node b
    dr = r_b - r_a
    P_a, Q_a = qa[NODE_FORCING["P"]], qa[NODE_FORCING["Q"]]
    R_force = F_b - F_a + f_tot * ds0 + P_a
    R_moment = M_b - M_a + m_tot * ds0 + Q_a + ca.cross(dr, F_b + 0.5 * ds0 * f_tot)

    # constitutive relations with offsets (Eq. A.18-A.20 as derived)
    F_csn, M_csn = T @ F_m, T @ M_m
    M_prime = M_csn - D @ F_csn
    kappa = 0.5 * (ca.solve(E_a, M_prime) + ca.solve(E_b, M_prime))  # (E_i^-1 + E_i+1^-1)/2 M' (Alg. 6)
    strain = S @ F_csn - D.T @ kappa
    R_curv = (rate_matrix(theta_m, sequence) @ (th_b - th_a)
              - rate_matrix(theta0_m, sequence) @ (th0_b - th0_a) - ds0 * kappa)
    e_s = ca.DM([0.0, 1.0, 0.0])
    R_strain = dr - (r0_b - r0_a) - ds0 * (T.T @ (e_s + strain) - T0.T @ e_s)
    if damping is not None and not damping.is_zero:
        # Alg. 6 line 6: t_kappa * d/dt of the curvature term K(theta_m) (theta_b - theta_a)
        th_ab = ca.vertcat(th_a, th_b)
        thdot_ab = ca.vertcat(a.xdot[st["theta"]], b.xdot[st["theta"]])
        curv_rate = ca.jtimes(rate_matrix(theta_m, sequence) @ (th_b - th_a), th_ab, thdot_ab)
        R_curv = R_curv + ca.DM(damping.curvature) * curv_rate
        # Alg. 6 line 7: t_gamma * d/dt(T dr) = T (du - omega_m x dr), damping applied in csn
        strain_rate = T @ (u_b - u_a - ca.cross(0.5 * (w_a + w_b), dr))
        R_strain = R_strain + T.T @ (ca.DM(damping.strain) * strain_rate)

    out = ca.vertcat(R_force, R_moment, R_curv, R_strain)
    return ca.Function("beam_element", [a.x, b.x, a.xdot, b.xdot, pa, pb, a.q, b.q, g, *frame], [out])


def nodal_function(sequence):
    """The CasADi function ``beam_nodal(x, xdot) -> R (6)`` of one node's kinematic residuals
    (velocity u - dr/dt, angular rate omega - Euler rates; ``sequence`` as :func:`element_function`).

    Parameters
    ----------
    sequence : str
        Euler-angle sequence (``"surface"``).

    Returns
    -------
    casadi.Function
        ``beam_nodal(x (18), xdot (18)) -> R (6)``.
    """
    x, xdot = ca.SX.sym("x", 18), ca.SX.sym("xdot", 18)
    st = STATE_BLOCKS
    T = body_to_csn(x[st["theta"]], sequence)
    K = rate_matrix(x[st["theta"]], sequence)
    out = ca.vertcat(x[st["u"]] - xdot[st["r"]], x[st["omega"]] - T.T @ (K @ xdot[st["theta"]]))
    return ca.Function("beam_nodal", [x, xdot], [out])


def node_params(p, lay, i):
    """The 34 parameters of node ``i`` in the layout of :data:`NODE_PARAMS`, from the packed
    parameters ``p`` (CasADi) with the slices ``lay`` of :func:`param_specs` (``layout``).

    Parameters
    ----------
    p : casadi.SX
        Packed parameters of the beam.
    lay : dict of str to slice
        Layout of :func:`param_specs` (:func:`~wingmdao.timemarch.system.layout`).
    i : int
        Node index.

    Returns
    -------
    casadi.SX, shape (34,)
        The node's parameters.
    """
    parts = []
    for name, width in (("node_positions", 3), ("node_euler_angles", 3), ("stiffness_csn", 9),
                        ("compliance_csn", 3), ("tension_axis", 2), ("shear_center", 2),
                        ("mass_per_length", 1), ("mass_center", 2), ("inertia_per_length", 9)):
        parts.append(_node_block(p, lay[name].start, None, i, width))
    return ca.vertcat(*parts)


def node_forcing(q, lay, i):
    """The 12 forcing entries of node ``i`` in the layout of :data:`NODE_FORCING`, from the packed
    forcing ``q`` (CasADi) with the slices ``lay`` of :func:`forcing_specs` (``layout``).

    Parameters
    ----------
    q : casadi.SX
        Packed forcing of the beam.
    lay : dict of str to slice
        Layout of :func:`forcing_specs`.
    i : int
        Node index.

    Returns
    -------
    casadi.SX, shape (12,)
        The node's forcing ``(f, m, P, Q)``.
    """
    return ca.vertcat(*[_node_block(q, lay[name].start, None, i, 3) for name in
                        ("force_per_length", "moment_per_length", "point_force", "point_moment")])


def describe_equation(index: int, num_nodes: int) -> str:
    """Name of residual ``index``, e.g. 'node 5, moment equilibrium z'.

    Parameters
    ----------
    index : int
        Residual index, in ``[0, 18 num_nodes)``.
    num_nodes : int
        Number of nodes of the beam.

    Returns
    -------
    str
        The name.
    """
    node, k = divmod(int(index), N_STATE_PER_NODE)
    if not 0 <= node < num_nodes:
        raise ValueError(f"equation index must be in [0, {N_STATE_PER_NODE * num_nodes}), got {index}")
    comp = k % 3
    if k >= 12:
        kind = _NODAL_EQUATIONS[(k - 12) // 3]
        return f"node {node}, {kind} {_BODY[comp]}"
    if node == num_nodes - 1:
        kind = _BC_EQUATIONS[k // 3]
        label = _ANGLES[comp] if kind == "root angle clamp" else _BODY[comp]
        where = "root node 0" if k < 6 else f"tip node {node}"
        return f"{where}, {kind} {label}"
    kind = _ELEMENT_EQUATIONS[k // 3]
    label = "csn"[comp] if kind == "moment-curvature" else _BODY[comp]
    return f"node {node} (element {node}-{node + 1}), {kind} {label}"


def jig_state(p_values, num_nodes: int | None = None) -> np.ndarray:
    """Unloaded jig state (n, 18): r = node_positions, theta = node_euler_angles, rest zero.

    ``p_values`` is a dict of parameter arrays or the packed parameter vector (then
    ``num_nodes`` is required).

    Parameters
    ----------
    p_values : dict or array_like
        Parameter dict (``node_positions``, ``node_euler_angles``) or packed parameter vector.
    num_nodes : int, optional
        Number of nodes; required with a packed vector.

    Returns
    -------
    ndarray, shape (n, 18)
        The jig state.
    """
    if isinstance(p_values, dict):
        r0 = np.asarray(p_values["node_positions"], dtype=float).reshape(-1, 3)
        th0 = np.asarray(p_values["node_euler_angles"], dtype=float).reshape(-1, 3)
    else:
        if num_nodes is None:
            raise ValueError("num_nodes is required with a packed parameter vector")
        lay = layout(param_specs(num_nodes))
        p = np.asarray(p_values, dtype=float)
        r0 = p[lay["node_positions"]].reshape(num_nodes, 3)
        th0 = p[lay["node_euler_angles"]].reshape(num_nodes, 3)
    x = np.zeros((r0.shape[0], N_STATE_PER_NODE))
    x[:, STATE_BLOCKS["r"]] = r0
    x[:, STATE_BLOCKS["theta"]] = th0
    return x


def unpack_state(x, num_nodes: int | None = None) -> dict:
    """Split a state (flat or (n, 18)) into ``{'r', 'theta', 'F', 'M', 'u', 'omega'}`` (n, 3) arrays.

    Parameters
    ----------
    x : array_like, shape (18 n,) or (n, 18)
        Beam state.
    num_nodes : int, optional
        Number of nodes; default inferred from the size.

    Returns
    -------
    dict of str to ndarray
        ``{'r', 'theta', 'F', 'M', 'u', 'omega'}``, each (n, 3) (copies).
    """
    x = np.asarray(x, dtype=float)
    x = x.reshape(-1, N_STATE_PER_NODE) if num_nodes is None else x.reshape(num_nodes, N_STATE_PER_NODE)
    return {k: x[:, s].copy() for k, s in STATE_BLOCKS.items()}


#: Modules whose code generates the beam's CasADi expressions and functions (their source is part
#: of the compiled-library key, :func:`beam_definition`).
_GENERATING_MODULES = ("wingmdao.beam.residual", "wingmdao.beam.rotations", "wingmdao.timemarch.system")


def beam_definition(num_nodes: int, euler_sequence: str = "surface",
                    damping: StrainRateDamping | None = None) -> str:
    """What defines the functions of :func:`build_beam_system` (the key of their compiled
    libraries, :func:`wingmdao.utils.casadi_cache.definition_key`): its arguments, the source of
    the generating modules and the CasADi version.

    Parameters
    ----------
    num_nodes : int
        Number of nodes.
    euler_sequence : str
        Euler-angle sequence.
    damping : StrainRateDamping, optional
        Strain-rate damping (zero damping counts as None).

    Returns
    -------
    str
        The definition key.
    """
    if damping is not None and damping.is_zero:
        damping = None
    args = (int(num_nodes), str(euler_sequence),
            None if damping is None else (damping.curvature, damping.strain))
    return definition_key("wingmdao.beam.residual.build_beam_system", args, _GENERATING_MODULES)


def build_beam_system(num_nodes: int, *, euler_sequence: str = "surface",
                      damping: StrainRateDamping | None = None, defer: bool = True) -> CasadiResidualSystem:
    """The App. A beam of ``num_nodes`` nodes (root first) as a :class:`CasadiResidualSystem`.

    ``state_shape = (num_nodes, 18)``; parameters and forcing as in :func:`param_specs` and
    :func:`forcing_specs`. The element equations are built once symbolically and called per
    element; Jacobians are exact and sparse. The initial guess is the jig state.
    ``damping``: optional :class:`StrainRateDamping` (none by default).

    ``defer``: once a beam of this definition (:func:`beam_definition`) has been built on this
    machine, its sparsity patterns come from :mod:`wingmdao.utils.function_store` and the CasADi
    functions are made at first use (:class:`DeferredBeamSystem`): from the compiled-library
    cache when all of them are there, else built as here. ``defer=False`` builds now.

    Parameters
    ----------
    num_nodes : int
        Number of nodes (at least 2).
    euler_sequence : str
        Euler-angle sequence (``"surface"``).
    damping : StrainRateDamping, optional
        Kelvin-Voigt strain-rate damping; None: none.
    defer : bool
        Return a :class:`DeferredBeamSystem` when the definition's data is stored.

    Returns
    -------
    CasadiResidualSystem
        The beam system (a :class:`DeferredBeamSystem` when deferred).
    """
    n = int(num_nodes)
    if n < 2:
        raise ValueError(f"num_nodes must be >= 2, got {num_nodes}")
    if not defer:
        return _build_beam_system(n, euler_sequence, damping)
    t_start = time.perf_counter()
    definition = beam_definition(n, euler_sequence, damping)
    built = {}

    def make():
        built["system"] = _build_beam_system(n, euler_sequence, damping)
        return _beam_data(built["system"])

    data = function_store.get(f"beam{n}", definition, make)
    if "system" in built:
        return built["system"]
    system = DeferredBeamSystem(data, functools.partial(_build_beam_system, n, euler_sequence, damping),
                                n, definition)
    system.build_time = time.perf_counter() - t_start
    return system


#: Functions of a beam system whose compiled libraries serve a deferred system: the residual and
#: Newton-matrix evaluators (attributes) and the history parts (keys ``H_*`` of ``_maps``: the four
#: Jacobians and the input vector-Jacobian product, ``CasadiResidualSystem._part_call``).
_COMPILED = ("_fast_R", "_fast_newton", *(f"H_{k}" for k in HISTORY_PARTS))
#: Of those, the ones a deferred system needs compiled before it runs without building: the march
#: and the adjoint (dR/dx, dR/dxdot, reverse-mode products). dR/dp and dR/dq are evaluated only
#: by the forward products and declared partials, so they reach the compile threshold in few runs
#: (a machine's cache may never hold them): attached when cached, else built when first used.
_REQUIRED = ("_fast_R", "_fast_newton", "H_x", "H_xdot", "H_vjp")


def _beam_data(system) -> dict:
    """What a :class:`DeferredBeamSystem` needs before its functions exist: Jacobian and Newton
    patterns, the solver and history functions' signatures and the built system's attribute names."""
    data = {"attributes": np.array(sorted(system.__dict__), dtype=str)}
    for k, (rows, cols, shape) in system.jacobian_patterns().items():
        data[f"pattern_{k}_rows"], data[f"pattern_{k}_cols"] = rows, cols
        data[f"pattern_{k}_shape"] = np.asarray(shape, dtype=np.int64)
    data["newton_rows"], data["newton_indptr"] = system._newton_pattern
    funs = {"_fast_R": system._fast_R, "_fast_newton": system._fast_newton,
            **{f"H_{k}": system._part_call(k) for k in HISTORY_PARTS}}
    for attr in _COMPILED:
        fun = funs[attr].jit.interpreted
        data[f"{attr}_name"] = fun.name()
        for i in range(fun.n_in()):
            data[f"{attr}_in{i}"] = fun.sparsity_in(i)
        for i in range(fun.n_out()):
            data[f"{attr}_out{i}"] = fun.sparsity_out(i)
        data[f"{attr}_n"] = np.array([fun.n_in(), fun.n_out()])
    return data


class _Signature:
    """Name and input/output sparsity of a CasADi function that has not been made (what
    :func:`wingmdao.utils.casadi_cache.cached` checks a compiled library against)."""

    def __init__(self, data, attr):
        self._name = str(data[f"{attr}_name"])
        n_in, n_out = (int(v) for v in data[f"{attr}_n"])
        self._in = [data[f"{attr}_in{i}"] for i in range(n_in)]
        self._out = [data[f"{attr}_out{i}"] for i in range(n_out)]

    def name(self):
        return self._name

    def n_in(self):
        return len(self._in)

    def n_out(self):
        return len(self._out)

    def sparsity_in(self, i):
        return self._in[i]

    def sparsity_out(self, i):
        return self._out[i]


class DeferredBeamSystem(CasadiResidualSystem):
    """A beam :class:`CasadiResidualSystem` whose CasADi functions are made at first use.

    Sizes, specs and the Jacobian patterns (what components declare at setup) come from the
    persisted data of an earlier build of the same definition (:func:`_beam_data`). At the first
    use of the residual, Newton or history evaluators, the compiled libraries of
    them (``_COMPILED``) are loaded from the compiled cache when those the march and the adjoint
    use (``_REQUIRED``) are there (a static analysis, a march and its gradient then never build
    the expression graphs; dR/dp or dR/dq without a library build them at first use); any other attribute of a built system (or a cache miss) builds
    the system (:func:`_build_beam_system`) and takes over its attributes. Evaluations are those
    of the built system: the same compiled libraries, or the same interpreted functions.

    Parameters
    ----------
    data : dict
        Persisted patterns and function signatures of an earlier build (:func:`_beam_data`).
    build : callable
        ``build()`` returns the full :class:`CasadiResidualSystem`.
    num_nodes : int
        Number of nodes.
    definition : str
        Definition key (:func:`beam_definition`).
    """

    def __init__(self, data, build, num_nodes, definition):
        n = int(num_nodes)
        self.n_state = 18 * n
        self.state_shape = (n, 18)
        self.param_specs = param_specs(n)
        self.forcing_specs = forcing_specs(n)
        self._describe = functools.partial(describe_equation, num_nodes=n)
        self._initial_guess = functools.partial(_jig_guess, num_nodes=n)
        self.definition = definition
        self.jit_threshold = JIT_THRESHOLD
        self._newton_pattern = (data["newton_rows"], data["newton_indptr"])
        self._newton_dense_index = None
        self._lu_column_order = lu_orders.beam_lu_column_order(n)
        self._deferred = (data, build, frozenset(str(a) for a in data["attributes"]))

    def jacobian_patterns(self):
        """The four Jacobian patterns, from the persisted data while the system is not built.

        Returns
        -------
        dict
            ``{"x"|"xdot"|"p"|"q": (rows, cols, shape)}``.
        """
        data = self._deferred[0] if self._deferred is not None else None
        if data is None:
            return super().jacobian_patterns()
        return {k: (data[f"pattern_{k}_rows"].copy(), data[f"pattern_{k}_cols"].copy(),
                    tuple(int(v) for v in data[f"pattern_{k}_shape"])) for k in ("x", "xdot", "p", "q")}

    def set_jit_threshold(self, evaluations: int) -> None:
        """Evaluations after which each function is compiled (passed on once the evaluators exist).

        Parameters
        ----------
        evaluations : int
            The threshold.
        """
        self.jit_threshold = int(evaluations)
        if "_fast_R" in self.__dict__:
            super().set_jit_threshold(evaluations)

    def residual_history(self, X, Xdot, p, Q):
        """Residuals at every instant, with the interpreted residual function.

        Parameters
        ----------
        X : ndarray, shape (n_time, n_state)
            States at every instant.
        Xdot : ndarray, shape (n_time, n_state)
            State rates at every instant.
        p : ndarray, shape (n_param,)
            Packed parameters.
        Q : ndarray, shape (n_time, n_forcing)
            Packed forcing at every instant.

        Returns
        -------
        ndarray, shape (n_time, n_state)
            The residuals.
        """
        return self._history("R", self._maps["R"].jit.interpreted, X, Xdot, p, Q)[0]

    @property
    def is_built(self) -> bool:
        """True once the CasADi expressions have been built (False: deferred or compiled only)."""
        return self._deferred is None

    def __getattr__(self, name):
        deferred = self.__dict__.get("_deferred")
        if deferred is None or name not in deferred[2]:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        if name in ("_fast_R", "_fast_newton", "_maps") and "_fast_R" not in self.__dict__ \
                and self._attach_compiled():
            return self.__dict__[name]
        self._materialize()
        return getattr(self, name)

    def _attach_compiled(self) -> bool:
        """Use the cached compiled libraries of the solver and history functions, if those of
        :data:`_REQUIRED` load (the others as far as they are cached; a missing one is made from
        the built system at its first use: :meth:`_part_call`)."""
        if not jit_enabled():
            return False
        data = self._deferred[0]
        ext = {}
        for attr in _COMPILED:
            sig = _Signature(data, attr)
            hit = cached(sig, key=function_key(sig, definition=self.definition))
            if hit is None and attr in _REQUIRED:
                return False
            if hit is not None:
                ext[attr] = hit
        calls = {attr: precompiled_call(f, self.jit_threshold, definition=self.definition)
                 for attr, f in ext.items()}
        self._fast_R, self._fast_newton = calls["_fast_R"], calls["_fast_newton"]
        self._maps = {"R": self._fast_R, **{a: c for a, c in calls.items() if a.startswith("H_")}}
        return True

    def _materialize(self) -> None:
        """Build the system and take over every attribute this object does not have yet."""
        data, build, _ = self._deferred
        full = build()
        patterns = self.jacobian_patterns()
        for k, (rows, cols, shape) in full.jacobian_patterns().items():
            if shape != patterns[k][2] or not (np.array_equal(rows, patterns[k][0])
                                               and np.array_equal(cols, patterns[k][1])):
                raise RuntimeError(f"{full._R.name()}: the built dR/d{k} pattern differs from the persisted one")
        for k, v in full.__dict__.items():
            if k not in ("_deferred", "_describe", "_initial_guess"):
                self.__dict__.setdefault(k, v)
        self._deferred = None
        if full.jit_threshold != self.jit_threshold:
            super().set_jit_threshold(self.jit_threshold)


def _jig_guess(p_val, q_val, num_nodes):
    return jig_state(p_val, num_nodes).ravel()


def _build_beam_system(n: int, euler_sequence: str, damping) -> CasadiResidualSystem:
    """Build the expressions and functions of :func:`build_beam_system` (no persisted data)."""
    t_start = time.perf_counter()
    pspecs, qspecs = param_specs(n), forcing_specs(n)
    play, qlay = layout(pspecs), layout(qspecs)
    x = ca.SX.sym("x", 18 * n)
    xdot = ca.SX.sym("xdot", 18 * n)
    p = ca.SX.sym("p", sum(s.size for s in pspecs))
    q = ca.SX.sym("q", sum(s.size for s in qspecs))
    elem = element_function(euler_sequence, damping)
    nodal = nodal_function(euler_sequence)
    g = q[qlay["gravity"]]
    frame = (q[qlay["frame_acceleration"]], q[qlay["frame_angular_velocity"]],
             q[qlay["frame_angular_acceleration"]])
    xs = [x[18 * i: 18 * (i + 1)] for i in range(n)]
    xds = [xdot[18 * i: 18 * (i + 1)] for i in range(n)]
    ps = [node_params(p, play, i) for i in range(n)]
    qs = [node_forcing(q, qlay, i) for i in range(n)]
    st = STATE_BLOCKS
    blocks = []
    for i in range(n):
        if i < n - 1:
            blocks.append(elem(xs[i], xs[i + 1], xds[i], xds[i + 1], ps[i], ps[i + 1], qs[i], qs[i + 1],
                               g, *frame))
        else:
            blocks.append(ca.vertcat(
                xs[0][st["r"]] - ps[0][NODE_PARAMS["r0"]],
                xs[0][st["theta"]] - ps[0][NODE_PARAMS["theta0"]],
                xs[i][st["F"]] - qs[i][NODE_FORCING["P"]],
                xs[i][st["M"]] - qs[i][NODE_FORCING["Q"]]))
        blocks.append(nodal(xs[i], xds[i]))
    R = ca.vertcat(*blocks)

    system = CasadiResidualSystem(x, xdot, p, q, R, param_specs=pspecs, forcing_specs=qspecs,
                                  state_shape=(n, 18), name=f"beam{n}",
                                  describe=functools.partial(describe_equation, num_nodes=n),
                                  initial_guess=functools.partial(_jig_guess, num_nodes=n),
                                  definition=beam_definition(n, euler_sequence, damping),
                                  lu_column_order=lu_orders.beam_lu_column_order(n))
    system.build_time = time.perf_counter() - t_start
    return system
