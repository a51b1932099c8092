"""The modal doublet-lattice wing of a changing design: a fixed modal basis with the design's mass
and stiffness projected on it (no OpenMDAO).

The modal wing (:mod:`wingmdao.aero.rfa_system`) is built on the normal modes of one beam. A
sizing changes the wall thicknesses, hence the beam's mass and stiffness, at every iteration.
Recomputing the modes would make the doublet-lattice forces, their rational approximation and the
station-load model all functions of the design (eigenvector derivatives through the whole chain).
Instead the basis ``Phi`` is fixed, the modes of a reference design (the initial one), and the
design's structure is projected on it (a Ritz reduction):

* the aerodynamic matrices (generalized forces, Roger coefficients, panel station loads) depend
  only on the planform and ``Phi``: fixed data;
* the modal mass ``M_ij(d) = sum_e ds_e [mu (u_i + phi_i x c) . (u_j + phi_j x c) + phi_i . I phi_j]``
  (:func:`wingmdao.beam.modes.generalized_mass`, the beam residual's element inertia);
* the modal stiffness ``K_ij(d) = sum_e ds_e eps_i^T C_e(d) eps_j``: the strain energy of the
  basis's element strains and curvatures ``eps_i = (gamma, kappa)`` (fixed kinematics, from the
  reference modes' internal loads and the reference compliance) with the design's element
  stiffness ``C_e = Cc_e^-1``, ``Cc = [[S + D^T E^-1 D, -D^T E^-1], [-E^-1 D, E^-1]]`` the
  compliance of the beam residual's constitutive law (strain ``S F - D^T kappa``, curvature
  ``E^-1 (M - D F)``, ``E^-1`` the average of the element's nodal inverses);
* the internal loads per unit modal acceleration by force summation of the design's element
  inertia loads outboard of each node (the beam residual's equilibrium recursion with the jig's
  arms), which replaces ``-R_i / omega_i^2`` of :mod:`wingmdao.aero.modal_loads`.

At the reference design these equal the modal model's ``diag(1)``, ``diag(omega^2)`` and
``-R_i / omega_i^2`` (checked by the tests); elsewhere the reduced model is exact for its basis,
and its derivatives with respect to the beam parameters are the exact derivatives of these
closed forms (CasADi). The approximation is the basis's: a design far from the reference wants a
new basis (rebuild the modal wing at the new design).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from wingmdao.beam.modes import NormalModes
from wingmdao.beam.residual import offset_matrix
from wingmdao.beam.rotations import body_to_csn
from wingmdao.stability.modal import N_MODES, modal_dlm_wing

__all__ = ["DESIGN_INPUTS", "ModalProjection", "modal_projection", "ModalGust", "cosine_gust", "cosine_gust_history"]

#: beam parameters the projection depends on, with their per-node shapes and units
DESIGN_INPUTS = {"stiffness_csn": ((3, 3), "N*m**2"), "compliance_csn": ((3,), "1/N"),
                 "tension_axis": ((2,), "m"), "shear_center": ((2,), "m"), "mass_per_length": ((), "kg/m"),
                 "mass_center": ((2,), "m"), "inertia_per_length": ((3, 3), "kg*m")}


@dataclass(frozen=True, eq=False)
class ModalProjection:
    """The projection of a design on a fixed basis: ``function`` a CasADi function of the beam
    parameters of :data:`DESIGN_INPUTS` (each flattened, C order, in that order) returning the
    modal mass (modes, modes), the modal stiffness (modes, modes) and the inertia station loads
    (n * 6, modes; N and N m per unit modal acceleration, body axes, beam-state convention) as
    flattened column vectors; ``jacobian`` its Jacobian function; ``n_nodes``, ``n_modes``.

    Parameters
    ----------
    function : casadi.Function
        Design parameters -> modal mass, stiffness and inertia station loads.
    jacobian : casadi.Function
        Its Jacobian.
    n_nodes : int
        Beam nodes.
    n_modes : int
        Modes of the basis.
    """

    function: ca.Function
    jacobian: ca.Function
    n_nodes: int
    n_modes: int

    def evaluate(self, params: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(mass, stiffness, inertia)`` of the beam parameter dict ``params`` (shapes as
        :func:`wingmdao.beam.residual.param_specs`): (m, m), (m, m), (n, 6, m).

        Parameters
        ----------
        params : dict
            Beam parameters.

        Returns
        -------
        tuple
            (mass, stiffness, inertia).
        """
        out = self.function(*[np.asarray(params[k], dtype=float).ravel() for k in DESIGN_INPUTS])
        n, m = self.n_nodes, self.n_modes
        return (np.asarray(out[0]).reshape(m, m), np.asarray(out[1]).reshape(m, m),
                np.asarray(out[2]).reshape(n, 6, m))


def _element_strains(params: dict, modes: NormalModes, T: list) -> np.ndarray:
    """(elements, 6, modes): element strain and curvature ``(gamma, kappa)`` of each basis mode
    from its internal loads and the reference design's compliance."""
    E = np.asarray(params["stiffness_csn"], dtype=float)
    S = np.asarray(params["compliance_csn"], dtype=float)
    ta, sc = np.asarray(params["tension_axis"], dtype=float), np.asarray(params["shear_center"], dtype=float)
    out = np.zeros((len(T), 6, modes.count))
    for e, Te in enumerate(T):
        F = Te @ (0.5 * (modes.force[:, e] + modes.force[:, e + 1])).T            # (3, m) csn
        M = Te @ (0.5 * (modes.moment[:, e] + modes.moment[:, e + 1])).T
        D = np.asarray(ca.DM(offset_matrix(0.5 * (ta[e] + ta[e + 1]), 0.5 * (sc[e] + sc[e + 1]))))
        einv = 0.5 * (np.linalg.inv(E[e]) + np.linalg.inv(E[e + 1]))
        kappa = einv @ (M - D @ F)
        gamma = np.diag(0.5 * (S[e] + S[e + 1])) @ F - D.T @ kappa
        out[e] = np.vstack([gamma, kappa])
    return out


def modal_projection(params: dict, modes: NormalModes, aircraft_mass=None) -> ModalProjection:
    """:class:`ModalProjection` on the basis ``modes`` (:func:`wingmdao.beam.modes.normal_modes`
    of the reference design ``params``, a beam parameter dict; its jig geometry
    ``node_positions`` and ``node_euler_angles`` stay fixed). ``aircraft_mass`` (kg): the basis's
    first mode is the free aircraft's plunge (:mod:`wingmdao.aero.modal_free`), and the modal mass
    adds half the body's mass to it, ``M / 2 - m_half(d)`` with the design's trapezoid half-wing
    mass, so that the plunge mode carries half the aircraft.

    Parameters
    ----------
    params : dict
        Beam parameters of the reference design.
    modes : NormalModes
        Normal modes of the reference design.
    aircraft_mass : float or None, optional
        Aircraft mass (kg): the basis's first mode is the free aircraft's plunge; None: clamped.

    Returns
    -------
    ModalProjection
        The projection.
    """
    if modes.force is None or modes.moment is None:
        raise ValueError("the modes carry no internal loads (NormalModes.force/moment); use beam.modes.normal_modes")
    r0 = np.asarray(params["node_positions"], dtype=float)
    th0 = np.asarray(params["node_euler_angles"], dtype=float)
    n, m = r0.shape[0], modes.count
    ne = n - 1
    T = [np.asarray(ca.DM(body_to_csn(0.5 * (th0[e] + th0[e + 1]))), dtype=float) for e in range(ne)]
    ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
    eps = _element_strains(params, modes, T)
    sym = {k: ca.SX.sym(k, n * int(np.prod(shape))) for k, (shape, _) in DESIGN_INPUTS.items()}
    u = np.asarray(modes.displacement, dtype=float)
    phi = np.asarray(modes.rotation, dtype=float)
    um = 0.5 * (u[:, 1:] + u[:, :-1])                               # (m, ne, 3)
    pm = 0.5 * (phi[:, 1:] + phi[:, :-1])

    def node(name, i, width):
        return sym[name][width * i:width * (i + 1)]

    def mat3(v):
        return ca.reshape(v, 3, 3).T                                  # C-ordered 9 entries

    Mr = ca.SX.zeros(m, m)
    Kr = ca.SX.zeros(m, m)
    f_el, m_el = [], []
    for e in range(ne):
        a, b = e, e + 1
        mu = 0.5 * (sym["mass_per_length"][a] + sym["mass_per_length"][b])
        cg = 0.5 * (node("mass_center", a, 2) + node("mass_center", b, 2))
        i_csn = 0.5 * (mat3(node("inertia_per_length", a, 9)) + mat3(node("inertia_per_length", b, 9)))
        Te = ca.DM(T[e])
        d = Te.T @ ca.vertcat(cg[0], 0, cg[1])                        # mass centre offset, body
        Ib = Te.T @ i_csn @ Te
        P = ca.DM(pm[:, e, :].T)                                      # (3, m)
        V = ca.DM(um[:, e, :].T) + ca.horzcat(*[ca.cross(P[:, i], d) for i in range(m)])
        Mr = Mr + ds[e] * (mu * V.T @ V + P.T @ Ib @ P)
        # element inertia load per unit modal acceleration (residual: f = mu (g - acc_cg), m = d x f - I wdot)
        f = -mu * ds[e] * V                                           # (3, m)
        mm = ca.horzcat(*[ca.cross(d, f[:, i]) for i in range(m)]) - ds[e] * Ib @ P
        f_el.append(f)
        m_el.append(mm)
        # stiffness: eps^T Cc^-1 eps
        Ea, Eb = mat3(node("stiffness_csn", a, 9)), mat3(node("stiffness_csn", b, 9))
        einv = 0.5 * (ca.inv(Ea) + ca.inv(Eb))
        Sd = ca.diag(0.5 * (node("compliance_csn", a, 3) + node("compliance_csn", b, 3)))
        D = offset_matrix(0.5 * (node("tension_axis", a, 2) + node("tension_axis", b, 2)),
                          0.5 * (node("shear_center", a, 2) + node("shear_center", b, 2)))
        Cc = ca.vertcat(ca.horzcat(Sd + D.T @ einv @ D, -D.T @ einv), ca.horzcat(-einv @ D, einv))
        ep = ca.DM(eps[e])
        Kr = Kr + ds[e] * ep.T @ ca.solve(Cc, ep)
    if aircraft_mass is not None:
        m_half = sum(ds[e] * 0.5 * (sym["mass_per_length"][e] + sym["mass_per_length"][e + 1]) for e in range(ne))
        body = ca.SX.zeros(m, m)
        body[0, 0] = 0.5 * float(aircraft_mass) - m_half
        Mr = Mr + body
    # force summation from the tip (free: zero loads), the residual's equilibrium recursion
    Fn, Mn = ca.SX.zeros(3, m), ca.SX.zeros(3, m)
    rows = [None] * n
    rows[n - 1] = ca.vertcat(Fn, Mn)
    for e in range(ne - 1, -1, -1):
        dr = ca.DM(r0[e + 1] - r0[e])
        Fa = Fn + f_el[e]
        Ma = Mn + m_el[e] + ca.horzcat(*[ca.cross(dr, Fn[:, i] + 0.5 * f_el[e][:, i]) for i in range(m)])
        Fn, Mn = Fa, Ma
        rows[e] = ca.vertcat(Fa, Ma)
    inertia = ca.vertcat(*[ca.reshape(rows[s][c, :], m, 1) for s in range(n) for c in range(6)])
    args = [sym[k] for k in DESIGN_INPUTS]
    outs = [ca.reshape(Mr.T, m * m, 1), ca.reshape(((Kr + Kr.T) / 2).T, m * m, 1), inertia]
    fun = ca.Function("modal_projection", args, outs, list(DESIGN_INPUTS), ["mass", "stiffness", "inertia"])
    jac = ca.Function("modal_projection_jac", args, [ca.jacobian(o, a) for o in outs for a in args])
    return ModalProjection(function=fun, jacobian=jac, n_nodes=n, n_modes=m)


@dataclass(frozen=True, eq=False)
class ModalGust:
    """A gust on the modal doublet-lattice wing of a changing design (a load case's ``modal_dlm``,
    :class:`wingmdao.groups.load_case.LoadCase`): ``wing`` the
    :class:`wingmdao.stability.modal.ModalDLMWing` of the reference design (basis, approximation,
    station-load coefficients), ``projection`` its :class:`ModalProjection`, the flight condition
    ``airspeed`` (m/s) and ``density`` (kg/m^3), ``gust`` (nt, 3) the gust velocity (m/s), its rate
    (m/s^2) and acceleration (m/s^3) at ``x_gust`` on the case's time grid, ``node_euler_angles``
    (n, 3) rad the jig's (the csn frames of the loads); the wing's ``controls`` (flap modes and law,
    :mod:`wingmdao.aero.modal_controls`) go into the design's residual and loads; ``plunge``: the aircraft free in plunge (the
    basis's first mode, :func:`wingmdao.aero.modal_free.free_cosine_gust`; the march starts from rest).

    Parameters
    ----------
    wing : ModalDLMWing
        The modal doublet-lattice wing of the reference design.
    projection : ModalProjection
        Its projection.
    airspeed : float
        True airspeed (m/s).
    density : float
        Air density (kg/m^3).
    gust : numpy.ndarray
        (nt, 3) gust velocity (m/s), rate (m/s^2) and acceleration (m/s^3).
    node_euler_angles : numpy.ndarray
        (n, 3) jig Euler angles (rad).
    plunge : bool, optional
        The aircraft free in plunge (the basis's first mode).
    """

    wing: object
    projection: ModalProjection
    airspeed: float
    density: float
    gust: np.ndarray
    node_euler_angles: np.ndarray
    plunge: bool = False


def cosine_gust(params: dict, chord, axis_frac, time, *, u_tas, airspeed, density, mach, gust_start, gradient_m,
                n_modes: int = N_MODES, controls=None) -> ModalGust:
    """:class:`ModalGust` of a 1 - cos gust on the modal doublet-lattice wing of the beam ``params``
    (the reference design; clamped jig modes, :func:`wingmdao.stability.modal.modal_dlm_wing`).

    Parameters
    ----------
    params : dict
        Beam parameters of the reference design (:func:`wingmdao.beam.residual.param_specs`).
    chord, axis_frac : array_like
        Chord (m) and beam-axis chord fraction per node.
    time : array_like
        The case's time grid (s).
    u_tas, airspeed, density, mach : float
        Gust amplitude (m/s, true airspeed), airspeed (m/s), air density (kg/m^3), Mach number.
    gust_start, gradient_m : float
        Time (s) the gust reaches the foremost leading edge (the lattice's ``x_gust``), gradient H (m).
    n_modes : int
        Number of modes of the basis.
    controls : wingmdao.aero.controls.ControlSpec or None
        Control surfaces (flap modes) and law of the wing (``wing.controls``); None: none.

    Returns
    -------
    ModalGust
        ``w = u_tas / 2 (1 - cos(pi V (t - gust_start) / H))`` for ``0 <= V (t - gust_start) <= 2 H``
        with its analytic rate and acceleration.
    """
    wing = modal_dlm_wing(params, chord, axis_frac, mach, n_modes=n_modes, controls=controls)
    return ModalGust(wing=wing, projection=modal_projection(params, wing.modes), airspeed=float(airspeed),
                     density=float(density), gust=cosine_gust_history(time, u_tas, airspeed, gust_start, gradient_m),
                     node_euler_angles=np.asarray(params["node_euler_angles"]))


def cosine_gust_history(time, u_tas, airspeed, gust_start, gradient_m) -> np.ndarray:
    """The 1 - cos gust velocity at the lattice's ``x_gust`` and its two rates on ``time``.

    Parameters
    ----------
    time : array_like
        Time grid (s).
    u_tas, airspeed : float
        Gust amplitude and airspeed (m/s, true airspeed).
    gust_start, gradient_m : float
        Time (s) the gust reaches ``x_gust``, gradient H (m).

    Returns
    -------
    ndarray, shape (nt, 3)
        ``w`` (m/s), ``dw/dt`` (m/s^2), ``d2w/dt2`` (m/s^3).
    """
    V, H = float(airspeed), float(gradient_m)
    time = np.asarray(time, dtype=float)
    d = V * (time - gust_start)
    on = (d >= 0) & (d <= 2 * H)
    w = np.where(on, 0.5 * u_tas * (1 - np.cos(np.pi * d / H)), 0.0)
    rate = np.where(on, 0.5 * u_tas * (np.pi * V / H) * np.sin(np.pi * d / H), 0.0)
    acc = np.where(on, 0.5 * u_tas * (np.pi * V / H) ** 2 * np.cos(np.pi * d / H), 0.0)
    return np.column_stack([w, rate, acc])
