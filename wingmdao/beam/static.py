"""Convenience layer: fill the beam parameters/forcing from section data.

``beam_parameters`` builds the parameter dict of :func:`wingmdao.beam.residual.param_specs`
from uniform or per-node section data; ``beam_forcing`` the forcing dict; ``cached_beam_system``
builds a beam system once per size; ``march_line_loads`` marches a beam under histories of
distributed loads (:func:`wingmdao.timemarch.bdf.march`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from wingmdao.beam.residual import (StrainRateDamping, build_beam_system, forcing_specs, jig_state,
                                    param_specs, unpack_state)
from wingmdao.timemarch.system import layout, pack
from wingmdao.beam.rotations import euler_from_axis
from wingmdao.timemarch.bdf import march, solve_static
from wingmdao.units import G0

_SYSTEMS: dict = {}


def cached_beam_system(num_nodes: int, euler_sequence: str = "surface",
                       damping: StrainRateDamping | None = None):
    """:func:`build_beam_system`, built once per (num_nodes, sequence, damping).

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
    CasadiResidualSystem
        The beam system of :func:`~wingmdao.beam.residual.build_beam_system`.
    """
    if damping is not None and damping.is_zero:
        damping = None
    key = (int(num_nodes), euler_sequence, damping)
    if key not in _SYSTEMS:
        _SYSTEMS[key] = build_beam_system(key[0], euler_sequence=euler_sequence, damping=damping)
    return _SYSTEMS[key]


def _per_node(value, n, shape, name):
    arr = np.asarray(value, dtype=float)
    if arr.shape == tuple(shape):
        arr = np.broadcast_to(arr, (n, *shape)).copy()
    if arr.shape != (n, *shape):
        raise ValueError(f"{name} must have shape {tuple(shape)} or {(n, *shape)}, got {arr.shape}")
    return arr


def beam_parameters(node_positions, node_euler_angles, *, EI_cc, GJ, EI_nn, EA, GK_c=None, GK_n=None,
                    EI_cn=0.0, tension_axis=(0.0, 0.0), shear_center=(0.0, 0.0), mass_per_length=0.0,
                    mass_center=(0.0, 0.0), inertia_per_length=None) -> dict:
    """Parameter dict of an n-node beam from uniform (scalar / per-node) section data, SI units.

    ``GK_c``/``GK_n`` default to 1e6 EA (shear-rigid, Euler-Bernoulli limit);
    ``inertia_per_length`` defaults to zero (3x3 in csn, or per node (n, 3, 3)).
    Stiffnesses must be positive: a ``ValueError`` names the input and the node otherwise.

    Parameters
    ----------
    node_positions : array_like, shape (n, 3)
        Jig node positions (m), body axes.
    node_euler_angles : array_like, shape (3,) or (n, 3)
        Jig Euler angles (rad).
    EI_cc : float or array_like, shape (n,)
        Bending stiffness about c (N m^2).
    GJ : float or array_like, shape (n,)
        Torsional stiffness (N m^2).
    EI_nn : float or array_like, shape (n,)
        Bending stiffness about n (N m^2).
    EA : float or array_like, shape (n,)
        Axial stiffness (N).
    GK_c : float or array_like, shape (n,), optional
        Shear stiffness along c (N); default 1e6 EA.
    GK_n : float or array_like, shape (n,), optional
        Shear stiffness along n (N); default 1e6 EA.
    EI_cn : float or array_like, shape (n,)
        Bending cross stiffness (N m^2).
    tension_axis : array_like, shape (2,) or (n, 2)
        ``(c, n)`` of the tension axis from the beam axis (m).
    shear_center : array_like, shape (2,) or (n, 2)
        ``(c, n)`` of the shear centre from the beam axis (m).
    mass_per_length : float or array_like, shape (n,)
        Mass per unit length (kg/m).
    mass_center : array_like, shape (2,) or (n, 2)
        ``(c, n)`` of the mass centre from the beam axis (m).
    inertia_per_length : array_like, shape (3, 3) or (n, 3, 3), optional
        Rotary inertia per length about the mass centre, csn (kg m); default zero.

    Returns
    -------
    dict
        The parameters of :func:`~wingmdao.beam.residual.param_specs`.
    """
    r0 = np.array(node_positions, dtype=float)  # a copy: callers may edit the dict
    n = r0.shape[0]
    th0 = _per_node(node_euler_angles, n, (3,), "node_euler_angles")
    vals = {}
    for name, v in (("EI_cc", EI_cc), ("GJ", GJ), ("EI_nn", EI_nn), ("EA", EA)):
        vals[name] = np.broadcast_to(np.asarray(v, dtype=float), (n,)).copy()
    vals["GK_c"] = vals["EA"] * 1e6 if GK_c is None else np.broadcast_to(np.asarray(GK_c, float), (n,)).copy()
    vals["GK_n"] = vals["EA"] * 1e6 if GK_n is None else np.broadcast_to(np.asarray(GK_n, float), (n,)).copy()
    for name, arr in vals.items():
        bad = np.flatnonzero(~(arr > 0.0))
        if bad.size:
            raise ValueError(f"{name} must be > 0 (SI units) at every node; node {bad[0]} has {arr[bad[0]]}")
    ei_cn = np.broadcast_to(np.asarray(EI_cn, dtype=float), (n,))
    E = np.zeros((n, 3, 3))
    E[:, 0, 0], E[:, 1, 1], E[:, 2, 2] = vals["EI_cc"], vals["GJ"], vals["EI_nn"]
    E[:, 0, 2] = E[:, 2, 0] = ei_cn
    inertia = np.zeros((3, 3)) if inertia_per_length is None else inertia_per_length
    return {
        "node_positions": r0,
        "node_euler_angles": th0,
        "stiffness_csn": E,
        "compliance_csn": np.column_stack([1.0 / vals["GK_c"], 1.0 / vals["EA"], 1.0 / vals["GK_n"]]),
        "tension_axis": _per_node(tension_axis, n, (2,), "tension_axis"),
        "shear_center": _per_node(shear_center, n, (2,), "shear_center"),
        "mass_per_length": np.broadcast_to(np.asarray(mass_per_length, dtype=float), (n,)).copy(),
        "mass_center": _per_node(mass_center, n, (2,), "mass_center"),
        "inertia_per_length": _per_node(inertia, n, (3, 3), "inertia_per_length"),
    }


def beam_forcing(n: int, **values) -> dict:
    """Forcing dict of an n-node beam: zeros except the given blocks (see ``forcing_specs``).

    Parameters
    ----------
    n : int
        Number of nodes.
    **values
        Forcing blocks by name (broadcast to their shapes).

    Returns
    -------
    dict
        Every forcing block of :func:`~wingmdao.beam.residual.forcing_specs`.
    """
    out = {s.name: np.zeros(s.shape) for s in forcing_specs(n)}
    for name, v in values.items():
        if name not in out:
            raise ValueError(f"unknown forcing {name!r}; allowed: {sorted(out)}")
        out[name] = np.broadcast_to(np.asarray(v, dtype=float), out[name].shape).copy()
    return out


def check_beam_parameters(params: dict) -> None:
    """Raise a ``ValueError`` naming the input, the node and the allowed range for bad beam data.

    Checks: finite values; distinct consecutive nodes (element length > 0 m); symmetric
    positive-definite ``stiffness_csn`` (N*m**2); ``compliance_csn`` > 0 (1/N);
    ``mass_per_length`` >= 0 (kg/m); symmetric positive semi-definite ``inertia_per_length``.

    Parameters
    ----------
    params : dict
        Beam parameters (:func:`~wingmdao.beam.residual.param_specs`).
    """
    for name, arr in params.items():
        a = np.asarray(arr, dtype=float)
        bad = ~np.isfinite(a.reshape(a.shape[0], -1)).all(axis=1) if a.ndim else ~np.isfinite(a)
        if np.any(bad):
            raise ValueError(f"{name} must be finite; node {int(np.flatnonzero(bad)[0])} is not")
    r0 = np.asarray(params["node_positions"], dtype=float)
    ds0 = np.linalg.norm(np.diff(r0, axis=0), axis=1)
    for i in np.flatnonzero(ds0 <= 1e-9 * max(1.0, np.max(np.abs(r0)))):
        raise ValueError(f"node_positions: nodes {i} and {i + 1} coincide (element length must be > 0 m)")
    E = np.asarray(params["stiffness_csn"], dtype=float)
    for i, Ei in enumerate(E):
        if not np.allclose(Ei, Ei.T, rtol=1e-9, atol=0.0) or np.min(np.linalg.eigvalsh(Ei)) <= 0.0:
            raise ValueError(f"stiffness_csn at node {i} must be symmetric positive definite (N*m**2)")
    S = np.asarray(params["compliance_csn"], dtype=float)
    for i in np.flatnonzero(np.any(S <= 0.0, axis=1)):
        raise ValueError(f"compliance_csn at node {i} must be > 0 (1/N), got {S[i]}")
    mu = np.asarray(params["mass_per_length"], dtype=float)
    for i in np.flatnonzero(mu < 0.0):
        raise ValueError(f"mass_per_length at node {i} must be >= 0 kg/m, got {mu[i]}")
    inertia = np.asarray(params["inertia_per_length"], dtype=float)
    for i, Ii in enumerate(inertia):
        if not np.allclose(Ii, Ii.T, atol=1e-12) or np.min(np.linalg.eigvalsh(0.5 * (Ii + Ii.T))) < -1e-12:
            raise ValueError(f"inertia_per_length at node {i} must be symmetric positive semi-definite (kg*m)")


@dataclass
class BeamModel:
    """A beam's parameters with a cached residual system; ``solve(**forcing)`` gives statics.

    Parameters
    ----------
    params : dict
        Beam parameters (checked by :func:`check_beam_parameters`).
    euler_sequence : str
        Euler-angle sequence.
    damping : StrainRateDamping, optional
        Strain-rate damping.
    """

    params: dict
    euler_sequence: str = "surface"
    damping: StrainRateDamping | None = None
    system: object = field(init=False, repr=False)

    def __post_init__(self):
        check_beam_parameters(self.params)
        self.num_nodes = np.asarray(self.params["node_positions"]).shape[0]
        self.system = cached_beam_system(self.num_nodes, self.euler_sequence, self.damping)
        self.p = pack(param_specs(self.num_nodes), self.params)

    def jig(self) -> np.ndarray:
        """The unloaded jig state.

        Returns
        -------
        ndarray, shape (n, 18)
            The jig state (:func:`~wingmdao.beam.residual.jig_state`).
        """
        return jig_state(self.params)

    def solve(self, *, load_steps=1, x0=None, max_iter=30, **forcing) -> dict:
        """Static equilibrium under the given forcing blocks; returns :func:`unpack_state` plus 'x'.

        Parameters
        ----------
        load_steps : int
            Load steps of the continuation (:func:`~wingmdao.timemarch.bdf.solve_static`).
        x0 : array_like, shape (18 n,), optional
            Initial guess; default the jig.
        max_iter : int
            Most Newton iterations per load step.
        **forcing
            Forcing blocks by name (:func:`beam_forcing`).

        Returns
        -------
        dict
            ``{'r', 'theta', 'F', 'M', 'u', 'omega'}`` (n, 3), the flat state ``'x'`` and the Newton
            ``'iterations'``.
        """
        q = pack(forcing_specs(self.num_nodes), beam_forcing(self.num_nodes, **forcing))
        x, info = solve_static(self.system, self.p, q, x0, load_steps=load_steps, max_iter=max_iter)
        out = unpack_state(x, self.num_nodes)
        out["x"] = x
        out["iterations"] = info.iterations
        return out


def straight_beam(n, length, direction=(0.0, 1.0, 0.0)):
    """Node positions and jig angles of a straight beam from the origin along ``direction``.

    Parameters
    ----------
    n : int
        Number of nodes.
    length : float
        Beam length (m).
    direction : array_like, shape (3,)
        Beam direction in body axes (normalized here).

    Returns
    -------
    node_positions : ndarray, shape (n, 3)
        Node positions (m).
    node_euler_angles : ndarray, shape (n, 3)
        Jig Euler angles (rad).
    """
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    r0 = np.outer(np.linspace(0.0, length, n), d)
    return r0, np.tile(euler_from_axis(d), (n, 1))


def march_line_loads(params: dict, time, force_per_length, moment_per_length, gravity=(0.0, 0.0, -G0)):
    """BDF2 history (:func:`wingmdao.timemarch.bdf.march`, modified Newton) of the clamped beam of
    ``params`` under dead line loads ``force_per_length`` / ``moment_per_length`` (n_time, n, 3)
    N/m, N m/m, and constant ``gravity`` (m/s^2, body axes), starting from the static state of t[0].

    Parameters
    ----------
    params : dict
        Beam parameters.
    time : array_like, shape (n_time,)
        Uniform time grid from 0 (s).
    force_per_length : array_like, shape (n_time, n, 3)
        Distributed force (N/m), body axes.
    moment_per_length : array_like, shape (n_time, n, 3)
        Distributed moment (N m/m), body axes.
    gravity : array_like, shape (3,)
        Gravitational acceleration (m/s^2), body axes.

    Returns
    -------
    TimeHistory
        The march.
    """
    t = np.asarray(time, dtype=float)
    n = np.asarray(params["node_positions"]).shape[0]
    system = cached_beam_system(n)
    ql = layout(system.forcing_specs)
    Q = np.zeros((t.size, system.n_forcing))
    Q[:, ql["force_per_length"]] = np.asarray(force_per_length, dtype=float).reshape(t.size, -1)
    Q[:, ql["moment_per_length"]] = np.asarray(moment_per_length, dtype=float).reshape(t.size, -1)
    Q[:, ql["gravity"]] = np.asarray(gravity, dtype=float)
    return march(system, t, pack(system.param_specs, params), Q, modified_newton=True)
