"""Eigenpairs of the linearised residual's pencil at one speed: refinement and selection.

The pieces shared by the flutter-damping constraint (:mod:`wingmdao.stability.sensitivity`) and its
warm start (:mod:`wingmdao.stability.warmstart`): the right / left vectors of an eigenvalue of
``(A + lambda B) v = 0`` by inverse iteration (:func:`left_right_vectors`, :func:`refine_pair`),
the modes of one speed (:class:`SpeedModes`), the constraint's measure of a mode and the
selection of the aerodynamically loaded modes, and the full eigen window at one speed
(:func:`cold_speed`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from wingmdao.stability.pencil_lu import ShiftedPencil
from wingmdao.stability.eigen import eigenmodes, linearize

MEASURES = ("sigma", "ratio")


def left_right_vectors(A, B, lam, *, iterations=3, rel_shift=1e-10):
    """Right and left eigenvectors ``(v, u)`` (unit 2-norm) of ``(A + lambda B) v = 0`` and the
    Rayleigh-quotient eigenvalue ``-u^H A v / u^H B v``, by inverse iteration with the shift
    ``lambda (1 + rel_shift)`` (``lambda`` from an eigen-solver).

    Parameters
    ----------
    A, B : scipy.sparse.csc_matrix
        dR/dx and dR/dxdot of the pencil.
    lam : complex
        Eigenvalue from an eigen-solver (1/s).
    iterations : int, optional
        Inverse iterations.
    rel_shift : float, optional
        Relative offset of the shift from ``lam``.

    Returns
    -------
    tuple
        (v, u, Rayleigh-quotient eigenvalue).
    """
    A, B = sp.csc_matrix(A), sp.csc_matrix(B)
    n = A.shape[0]
    s = complex(lam) * (1.0 + rel_shift) + rel_shift
    rng = np.random.default_rng(0)
    v = rng.standard_normal(n) + 1j * rng.standard_normal(n)
    v /= np.linalg.norm(v)
    step = ShiftedPencil(A, B).refine(s, v, v, B @ v, lam, lam, iterations, -1.0)   # tol < 0: all steps
    return step[0], step[1], step[3]


@dataclass
class SpeedModes:
    """The aggregated modes at one speed: what the gradient needs and what a warm start refines.

    Parameters
    ----------
    speed : float
        Airspeed (m/s).
    p, q : numpy.ndarray
        Packed parameters and forcing at this speed.
    x0 : numpy.ndarray
        Static state linearised about.
    A, B : scipy.sparse.csc_matrix
        dR/dx and dR/dxdot at ``x0``.
    eigenvalues : numpy.ndarray
        (k,) two-sided Rayleigh quotients (1/s).
    right, left : numpy.ndarray
        (n, k) right and left vectors, unit 2-norm.
    error : numpy.ndarray or None, optional
        (k,) error bound of each eigenvalue (1/s; 0 when refined, > 0 for a lazy estimate).
    """

    speed: float                     # m/s
    p: np.ndarray                    # packed parameters at this speed
    q: np.ndarray                    # packed forcing
    x0: np.ndarray                   # static state linearised about
    A: sp.csc_matrix                 # dR/dx at x0
    B: sp.csc_matrix                 # dR/dxdot at x0
    eigenvalues: np.ndarray          # complex (k,), two-sided Rayleigh quotients
    right: np.ndarray                # (n, k) right vectors, unit 2-norm
    left: np.ndarray                 # (n, k) left vectors, unit 2-norm
    error: np.ndarray = None         # (k,) 1/s: 0 refined; > 0 a lazy estimate (Ritz value, its error bound)


def refine_pair(A, B, lam0, v0, u0, *, tol=1e-12, iterations=6, shifts=3, rel_shift=1e-10, quotient_start=True,
                pencil=None):
    """Right / left vectors and the two-sided Rayleigh quotient of the eigenvalue of
    ``(A + lambda B) v = 0`` nearest ``lam0``, by inverse iteration from ``v0, u0`` (the
    previous design's vectors): one sparse LU of ``A + s B`` per shift s (first ``lam0``, then the
    current quotient; at most ``shifts``), the left vector from the transposed solve with the same
    LU. Converged when two quotients agree to ``tol`` relative. Returns ``(v, u, lam, converged)``.
    ``quotient_start``: the first shift is the two-sided quotient of ``v0, u0`` on the new pencil
    instead of ``lam0`` (it follows the mode's own change: the PEGASUS torsion and in-plane modes,
    1-3 rad/s apart, cross between SLSQP designs, and a shift at the old eigenvalue landed on the
    other one).
    Each shift's factorization and steps: :meth:`wingmdao.stability.pencil_lu.ShiftedPencil.refine`
    (in C with a static pivot order when the kernel is on; a shift it refuses runs with SuperLU).
    (Two-sided Rayleigh-quotient iteration: B. N. Parlett, "The Rayleigh quotient iteration and
    some generalizations for nonnormal matrices", Math. Comp. 28(127), 1974.)

    Parameters
    ----------
    A, B : scipy.sparse.csc_matrix
        dR/dx and dR/dxdot of the pencil.
    lam0 : complex
        Eigenvalue to start from (1/s).
    v0, u0 : numpy.ndarray
        Right and left vectors to start from.
    tol : float, optional
        Relative agreement of two quotients for convergence.
    iterations : int, optional
        Inverse iterations per shift.
    shifts : int, optional
        Most LU factorizations.
    rel_shift : float, optional
        Relative offset of each shift from its eigenvalue.
    quotient_start : bool, optional
        Start from the two-sided quotient of ``v0, u0`` instead of ``lam0``.
    pencil : ShiftedPencil or None, optional
        The pencil of ``(A, B)`` when the caller refines several modes of it (its analysis once).

    Returns
    -------
    tuple
        (v, u, lam, converged).
    """
    v, u = np.asarray(v0, complex), np.asarray(u0, complex)
    v, u = v / np.linalg.norm(v), u / np.linalg.norm(u)
    Bv = B @ v
    lam_old, lam = complex(lam0), complex(lam0)
    if quotient_start:
        den = np.vdot(u, Bv)
        if abs(den) > 1e-12 * np.linalg.norm(Bv) * np.linalg.norm(u):
            lam_old = lam = complex(-np.vdot(u, A @ v) / den)
    pencil = ShiftedPencil(A, B) if pencil is None else pencil
    for _ in range(int(shifts)):
        s = lam * (1.0 + rel_shift) + rel_shift
        v, u, Bv, lam, lam_old, ok = pencil.refine(s, v, u, Bv, lam, lam_old, iterations, tol)
        if ok:
            return v, u, lam, True
    return v, u, lam, False


@dataclass
class Selection:
    """The modes the damping constraint aggregates and its measure (the keyword arguments of
    :func:`wingmdao.stability.sensitivity.damping_constraint`).

    Parameters
    ----------
    aero_mask : numpy.ndarray
        1 on the aerodynamic states.
    beam_mask : numpy.ndarray
        Weights of the beam's displacements and rotations.
    min_frequency : float
        Oscillatory above this ``|Im|`` (rad/s).
    neutral_fraction : float
        Loaded above this fraction of aerodynamic to beam part (-).
    static : bool
        Linearise about the static solution.
    measure : {"sigma", "ratio"}
        The constraint's measure.
    margin : float
        Margin added to the measure.
    rho_ks : float
        KS aggregation parameter.
    eig_options : dict
        Options of :func:`~wingmdao.stability.eigen.eigenmodes` (``sigma`` the window's centre, ``static_options``).
    """

    aero_mask: np.ndarray            # 1 on the aerodynamic states
    beam_mask: np.ndarray            # weights of the beam's displacements and rotations
    min_frequency: float             # rad/s: oscillatory above
    neutral_fraction: float          # loaded above this fraction of aerodynamic to beam part
    static: bool                     # linearise about the static solution
    measure: str                     # "sigma" or "ratio"
    margin: float
    rho_ks: float
    eig_options: dict                # of eigenmodes (``sigma``: the window's centre; ``static_options``)

    @property
    def sigma(self) -> complex:
        """The eigen window's centre."""
        return complex(self.eig_options.get("sigma", 0.0))

    @property
    def static_options(self):
        """The static solve's options (None: defaults)."""
        return self.eig_options.get("static_options")

    def g(self, lam) -> np.ndarray:
        """The constraint's ``g`` of each eigenvalue (:func:`measure_values`).

        Parameters
        ----------
        lam : array_like
            Eigenvalues (1/s).

        Returns
        -------
        numpy.ndarray
            g of each.
        """
        return measure_values(lam, self.measure, self.margin)

    def g_upper(self, lam, err) -> np.ndarray:
        """``g`` at the upper end of an eigenvalue error bound ``err`` (1/s).

        Parameters
        ----------
        lam : array_like
            Eigenvalues (1/s).
        err : array_like
            Their error bounds (1/s).

        Returns
        -------
        numpy.ndarray
            g at the upper ends.
        """
        lam = np.atleast_1d(lam)
        dg = err if self.measure == "sigma" else 2.0 * err / np.maximum(np.abs(lam) - err, 1e-300)
        return self.g(lam) + dg


def measure_values(lam, measure, margin):
    """The constraint's ``g`` of each eigenvalue: ``sigma + margin`` or ``margin - zeta``.

    Parameters
    ----------
    lam : array_like
        Eigenvalues (1/s).
    measure : {"sigma", "ratio"}
        ``sigma``: Re(lambda) + margin; ``ratio``: margin + Re(lambda) / ``|lambda|``.
    margin : float
        The margin.

    Returns
    -------
    numpy.ndarray
        g of each eigenvalue.
    """
    lam = np.asarray(lam, dtype=complex)
    return lam.real + margin if measure == "sigma" else margin + lam.real / np.abs(lam)


def loaded_fraction(vectors, mask, bmask):
    """Loaded fraction of each column: ``|aerodynamic part| / |beam part|`` (``mask``, ``bmask``
    weights; only their nonzero rows are read).

    Parameters
    ----------
    vectors : numpy.ndarray
        (n, k) mode vectors.
    mask : numpy.ndarray
        (n,) weights of the aerodynamic states.
    bmask : numpy.ndarray
        (n,) weights of the beam states.

    Returns
    -------
    numpy.ndarray
        (k,) loaded fractions (-).
    """
    ia, ib = np.flatnonzero(mask), np.flatnonzero(bmask)
    return (np.linalg.norm(vectors[ia] * mask[ia, None], axis=0)
            / np.linalg.norm(vectors[ib] * bmask[ib, None], axis=0))


def subset(sm, keep):
    """The modes ``keep`` of ``sm``.

    Parameters
    ----------
    sm : SpeedModes
        Modes at one speed.
    keep : array_like
        Indices or bool mask of the modes kept.

    Returns
    -------
    SpeedModes
        The kept modes.
    """
    return SpeedModes(sm.speed, sm.p, sm.q, sm.x0, sm.A, sm.B, sm.eigenvalues[keep], sm.right[:, keep],
                      sm.left[:, keep], None if sm.error is None else sm.error[keep])


def aggregated(sm, V, mask, bmask, neutral_fraction):
    """The aerodynamically loaded modes of ``sm`` (loaded fraction above ``neutral_fraction``).

    Parameters
    ----------
    sm : SpeedModes
        Modes at one speed.
    V : numpy.ndarray
        (n, k) vectors the loaded fraction is measured on.
    mask : numpy.ndarray
        (n,) weights of the aerodynamic states.
    bmask : numpy.ndarray
        (n,) weights of the beam states.
    neutral_fraction : float
        Loaded above this fraction (-).

    Returns
    -------
    SpeedModes
        The loaded modes.
    """
    keep = np.flatnonzero(loaded_fraction(sm.right, mask, bmask) > neutral_fraction)
    if keep.size == 0:
        raise ValueError(f"no aerodynamically loaded oscillatory mode at {V} m/s in the eigen window")
    return subset(sm, keep)


def cold_speed(system, p, q, x, V, sel: Selection):
    """Every oscillatory mode of the full eigen window at one speed (refined right / left vectors)
    and the window's eigenvalues.

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    p, q : numpy.ndarray
        Packed parameters and forcing.
    x : numpy.ndarray or None
        Starting guess of the static solve.
    V : float
        Airspeed (m/s).
    sel : Selection
        The modes aggregated and the measure.

    Returns
    -------
    tuple
        (SpeedModes, eigenvalues of the window).
    """
    m = eigenmodes(system, p, q, x, static=sel.static, **sel.eig_options)
    osc = np.flatnonzero(m.frequency > sel.min_frequency)
    A, B = linearize(system, p, q, m.x0)
    lams, vs, us = [], [], []
    for j in osc:
        vec, uvec, lj = left_right_vectors(A, B, m.eigenvalues[j])
        lams.append(lj)
        vs.append(vec)
        us.append(uvec)
    n = system.n_state
    sm = SpeedModes(float(V), p, q, m.x0, A, B, np.array(lams, dtype=complex),
                    np.array(vs).T.reshape(n, len(vs)), np.array(us).T.reshape(n, len(us)), np.zeros(len(lams)))
    return sm, m.eigenvalues


def cold_set(system, pq, speeds, sel: Selection) -> list:
    """The full eigen window's oscillatory modes at every speed (``pq``: per speed ``(p, q)``;
    each speed's static solve starts from the previous speed's state).

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    pq : sequence of tuple
        (p, q) per speed.
    speeds : array_like
        Airspeeds (m/s).
    sel : Selection
        The modes aggregated and the measure.

    Returns
    -------
    list of SpeedModes
        One per speed.
    """
    tracked, x = [], None
    for (p, q), V in zip(pq, speeds):
        sm = cold_speed(system, p, q, x, V, sel)[0]
        x = sm.x0
        tracked.append(sm)
    return tracked
