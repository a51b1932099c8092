"""Small-vibration modes of the beam about a state (the jig by default).

The residual R(x, xdot) linearised at a static state x0 gives (A + lambda B) v = 0 with
A = dR/dx, B = dR/dxdot; the undamped natural frequencies are ``|Im lambda| / (2 pi)``. Used to set
structural damping at a reference frequency (:class:`~wingmdao.beam.residual.StrainRateDamping`)
and to report the first bending mode.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from wingmdao.beam.residual import N_STATE_PER_NODE, STATE_BLOCKS
from wingmdao.beam.rotations import body_to_csn


def natural_frequencies(system, p, q, x0=None, count: int = 6, max_abs: float = 1e6) -> np.ndarray:
    """Lowest ``count`` natural frequencies (Hz, ascending) of ``system`` linearised at ``x0``.

    ``p``, ``q``: packed parameter and forcing vectors; ``x0`` defaults to the system's initial
    guess (the jig shape for the beam). Dense generalised eigenproblem: fine for the beam sizes
    of sizing problems (18 n unknowns, n <= ~100). Eigenvalues with ``|lambda|`` of ``max_abs``
    (1/s) or more are the pencil's infinite ones (constraint rows: clamps, joints), computed as
    large finite numbers, and are dropped first, as :func:`wingmdao.stability.eigen.eigenmodes` does.

    Parameters
    ----------
    system : ResidualSystem
        The beam (or any) system.
    p : array_like, shape (n_param,)
        Packed parameters.
    q : array_like, shape (n_forcing,)
        Packed forcing.
    x0 : array_like, shape (n_state,), optional
        State to linearise about; default ``system.initial_guess(p, q)``.
    count : int
        Number of frequencies (at least 1).
    max_abs : float
        Eigenvalues of this magnitude (1/s) or more are dropped as infinite.

    Returns
    -------
    ndarray, shape (count,) or fewer
        The frequencies (Hz), ascending.
    """
    if count < 1:
        raise ValueError(f"count must be >= 1, got {count}")
    p = np.asarray(p, dtype=float)
    q = np.asarray(q, dtype=float)
    x = np.asarray(system.initial_guess(p, q) if x0 is None else x0, dtype=float).ravel()
    A, B = (m.toarray() for m in system.jac_state(x, np.zeros_like(x), p, q))
    lam = sla.eigvals(A, -B)
    lam = lam[np.isfinite(lam) & (np.abs(lam) < max_abs)]
    lam = lam[lam.imag > 1e-9 * np.max(np.abs(lam), initial=1.0)]
    if lam.size == 0:
        raise ValueError("no oscillatory modes: is mass_per_length zero?")
    freqs = np.sort(np.abs(lam)) / (2 * np.pi)
    return freqs[:count]


@dataclass(frozen=True)
class NormalModes:
    """Undamped normal modes of the beam about a state (the jig by default).

    ``frequencies`` (count,) rad/s ascending; ``displacement`` (count, n, 3) m and ``rotation``
    (count, n, 3) rad: each mode's nodal displacement and small rotation vector (body axes), real,
    scaled to a unit generalized mass (:func:`generalized_mass`); ``mass`` (count, count) the
    generalized mass matrix of the scaled modes (the identity up to the modes' discrete
    orthogonality), ``stiffness`` (count, count) ``diag(omega^2)`` in the same scaling;
    ``force``, ``moment`` (count, n, 3): each mode's internal resultants F, M at the nodes (body
    axes, N and N m per unit modal amplitude; the beam's states, so ``sum_i q_i M_i`` is the
    mode-displacement estimate of the internal moment).

    Parameters
    ----------
    frequencies : ndarray, shape (count,)
        Circular frequencies (rad/s), ascending.
    displacement : ndarray, shape (count, n, 3)
        Nodal displacement of each mode (m per unit modal amplitude), body axes.
    rotation : ndarray, shape (count, n, 3)
        Nodal small rotation of each mode (rad per unit modal amplitude), body axes.
    mass : ndarray, shape (count, count)
        Generalized mass matrix of the scaled modes.
    stiffness : ndarray, shape (count, count)
        ``diag(omega^2)``.
    force : ndarray, shape (count, n, 3), optional
        Internal force of each mode at the nodes (N per unit modal amplitude), body axes.
    moment : ndarray, shape (count, n, 3), optional
        Internal moment of each mode at the nodes (N m per unit modal amplitude), body axes.
    """

    frequencies: np.ndarray
    displacement: np.ndarray
    rotation: np.ndarray
    mass: np.ndarray
    stiffness: np.ndarray
    force: np.ndarray = None
    moment: np.ndarray = None

    @property
    def count(self) -> int:
        return int(self.frequencies.size)


def generalized_mass(params: dict, displacement, rotation) -> np.ndarray:
    """Generalized mass ``M_ij`` (kg m^2 per unit modal amplitudes) of mode shapes on the beam.

    The beam residual's inertia (:func:`wingmdao.beam.residual.element_function`): per element the
    mass per length ``mu``, the mass-centre offset ``d`` and the rotary inertia ``I`` (element
    averages) act at the element's mid-point with the average of its nodes' motion, so
    ``M_ij = sum_e ds_e [mu (u_i + phi_i x d) . (u_j + phi_j x d) + phi_i . I phi_j]`` with the
    mid-point displacement ``u`` and rotation ``phi`` of each mode. ``displacement``, ``rotation``:
    (count, n, 3) in body axes.

    Parameters
    ----------
    params : dict
        Beam parameters (``node_positions``, ``node_euler_angles``, ``mass_per_length``,
        ``mass_center``, ``inertia_per_length``), as :func:`wingmdao.beam.static.beam_parameters`.
    displacement : array_like, shape (count, n, 3)
        Nodal displacements of the modes, body axes.
    rotation : array_like, shape (count, n, 3)
        Nodal small rotations of the modes, body axes.

    Returns
    -------
    ndarray, shape (count, count)
        The generalized mass matrix.
    """
    u = np.asarray(displacement, dtype=float)
    phi = np.asarray(rotation, dtype=float)
    r0 = np.asarray(params["node_positions"], dtype=float)
    th0 = np.asarray(params["node_euler_angles"], dtype=float)
    mu = 0.5 * (params["mass_per_length"][1:] + params["mass_per_length"][:-1])
    cg = 0.5 * (params["mass_center"][1:] + params["mass_center"][:-1])
    i_csn = 0.5 * (params["inertia_per_length"][1:] + params["inertia_per_length"][:-1])
    ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
    um = 0.5 * (u[:, 1:] + u[:, :-1])
    pm = 0.5 * (phi[:, 1:] + phi[:, :-1])
    M = np.zeros((u.shape[0], u.shape[0]))
    for e in range(ds.size):
        T = np.asarray(body_to_csn(0.5 * (th0[e] + th0[e + 1])), dtype=float)
        d = T.T @ np.array([cg[e, 0], 0.0, cg[e, 1]])
        v = um[:, e] + np.cross(pm[:, e], d)
        Ib = T.T @ i_csn[e] @ T
        M += ds[e] * (mu[e] * v @ v.T + pm[:, e] @ Ib @ pm[:, e].T)
    return M


def normal_modes(system, params: dict, p, q, count: int = 6, x0=None, max_abs: float = 1e6) -> NormalModes:
    """The lowest ``count`` undamped normal modes of the beam ``system`` about ``x0`` (the jig).

    ``params``: the beam parameter dict packed in ``p`` (for the generalized mass). Dense pencil
    ``(A + lambda B) v = 0`` as :func:`natural_frequencies`; each eigenvector's ``r`` block is the
    displacement, its ``omega`` block over ``lambda`` the rotation; made real by the phase of its
    largest entry and scaled to a unit generalized mass.

    Parameters
    ----------
    system : ResidualSystem
        The beam system.
    params : dict
        The beam parameters packed in ``p``.
    p : array_like, shape (n_param,)
        Packed parameters.
    q : array_like, shape (n_forcing,)
        Packed forcing.
    count : int
        Number of modes (at least 1).
    x0 : array_like, shape (n_state,), optional
        State to linearise about; default ``system.initial_guess(p, q)`` (the jig).
    max_abs : float
        Eigenvalues of this magnitude (1/s) or more are dropped as infinite.

    Returns
    -------
    NormalModes
        The modes.
    """
    if count < 1:
        raise ValueError(f"count must be >= 1, got {count}")
    p = np.asarray(p, dtype=float)
    q = np.asarray(q, dtype=float)
    x = np.asarray(system.initial_guess(p, q) if x0 is None else x0, dtype=float).ravel()
    A, B = (m.toarray() for m in system.jac_state(x, np.zeros_like(x), p, q))
    lam, vec = sla.eig(A, -B)
    keep = np.isfinite(lam) & (np.abs(lam) < max_abs)
    lam, vec = lam[keep], vec[:, keep]
    keep = lam.imag > 1e-9 * np.max(np.abs(lam), initial=1.0)
    lam, vec = lam[keep], vec[:, keep]
    if lam.size < count:
        raise ValueError(f"only {lam.size} oscillatory modes, {count} requested")
    order = np.argsort(np.abs(lam))[:count]
    n = params["node_positions"].shape[0]
    blocks = vec[:, order].T.reshape(count, n, N_STATE_PER_NODE)
    disp = blocks[:, :, STATE_BLOCKS["r"]]
    rot = blocks[:, :, STATE_BLOCKS["omega"]] / lam[order][:, None, None]
    flat = np.concatenate([disp.reshape(count, -1), rot.reshape(count, -1)], axis=1)
    phase = np.exp(-1j * np.angle(flat[np.arange(count), np.argmax(np.abs(flat), axis=1)]))
    disp = (disp * phase[:, None, None]).real
    rot = (rot * phase[:, None, None]).real
    scale = 1.0 / np.sqrt(np.diag(generalized_mass(params, disp, rot)))
    disp *= scale[:, None, None]
    rot *= scale[:, None, None]
    res = {key: (blocks[:, :, STATE_BLOCKS[key]] * phase[:, None, None]).real * scale[:, None, None]
           for key in ("F", "M")}
    omega = np.abs(lam[order])
    return NormalModes(frequencies=omega, displacement=disp, rotation=rot,
                       mass=generalized_mass(params, disp, rot), stiffness=np.diag(omega ** 2),
                       force=res["F"], moment=res["M"])
