"""Modal flutter with tabulated generalized aerodynamic forces: the p-k method on the exact
(doublet-lattice) matrices in the frequency domain, and the state-space eigenvalues of the
structure with Roger's rational-function approximation (no OpenMDAO).

Modal equations (modes of the jig beam, :func:`wingmdao.beam.modes.normal_modes`):
``M q'' + C q' + K q = (rho V^2 / 2) Q(p) q``, ``p = s b_ref / V``.

**p-k** (Hassig, "An approximate true damping solution of the flutter equation by determinant
iteration", J. Aircraft 8(11), 1971, 885-889): for each mode and speed, iterate
``det[M s^2 + (C - q b_ref / V Q_I(k) / k) s + K - q Q_R(k)] = 0`` with ``k = Im(s) b_ref / V``
until the k of the eigenvalue followed is the k the matrices were taken at; ``Q(k)`` is the cubic
spline of the tabulated matrices (:func:`wingmdao.aero.dlm.interpolate`); a k above the
tabulated range uses the last one (``k_clamped``: the mode is far from flutter there, at low
speed). Exact at zero damping, so the flutter speed is the doublet lattice's.

**State space**: Roger's approximation (:mod:`wingmdao.aero.rfa`) turns ``Q(p)`` into
``A_0 + A_1 p + A_2 p^2 + sum_l A_(l+2) z_l`` with lag states ``z_l' = q' - gamma_l V / b_ref z_l``;
the states ``(q, q', z_1 .. z_L)`` give one real matrix per speed (:func:`state_matrix`) whose
eigenvalues are the aeroelastic roots. Both methods report ``g = 2 Re(s) / Im(s)`` per structural
mode; flutter is the lowest speed at which a mode's ``Re(s)`` crosses zero upwards (to ``g >``
:data:`G_TOL`), refined by Brent's method.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.optimize as sopt

from wingmdao.aero.dlm import GeneralizedForces, interpolate
from wingmdao.aero.rfa import RogerApproximation

#: smallest k at which Q_I / k is evaluated (its limit at k -> 0)
_K_SMALL = 1e-4
#: damping g above which a crossing counts as flutter (a mode the air does not load, e.g. the
#: edgewise bending of a flat wing, keeps g = 0 to round-off and must not be reported)
G_TOL = 1e-6


@dataclass(frozen=True)
class ModalStructure:
    """Structural modal matrices (count, count): ``mass`` (kg m^2 per modal units), ``stiffness``,
    ``damping``.

    Parameters
    ----------
    mass : numpy.ndarray
        (count, count) modal mass.
    stiffness : numpy.ndarray
        (count, count) modal stiffness.
    damping : numpy.ndarray
        (count, count) modal damping.
    """

    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray

    @classmethod
    def from_modes(cls, modes, damping_ratio: float = 0.0) -> ModalStructure:
        """From :class:`wingmdao.beam.modes.NormalModes` with a modal damping ratio (fraction of critical).

        Parameters
        ----------
        modes : NormalModes
            Normal modes of the structure.
        damping_ratio : float, optional
            Modal damping ratio (fraction of critical).

        Returns
        -------
        ModalStructure
            The modal matrices.
        """
        m = np.asarray(modes.mass, dtype=float)
        k = np.asarray(modes.stiffness, dtype=float)
        c = 2.0 * float(damping_ratio) * np.diag(np.sqrt(np.diag(k) * np.diag(m)))
        return cls(mass=m, stiffness=k, damping=c)

    @property
    def frequencies(self) -> np.ndarray:
        """Undamped natural frequencies (rad/s) of the modal matrices."""
        return np.sqrt(np.sort(sla.eigvalsh(self.stiffness, self.mass)))


@dataclass
class FlutterResult:
    """A modal flutter sweep: ``speeds`` (nV,) m/s; ``damping`` (nV, modes) g = 2 Re(s) / Im(s);
    ``frequency`` (nV, modes) rad/s; ``flutter_speed`` m/s and ``flutter_frequency`` rad/s (None
    without a crossing in the sweep), ``flutter_mode`` (index of the structural mode followed),
    ``method`` ("p-k" | "state-space"), ``k_clamped`` (nV, modes) bool (p-k only).

    Parameters
    ----------
    speeds : numpy.ndarray
        (nV,) airspeeds (m/s).
    damping : numpy.ndarray
        (nV, modes) g = 2 Re(s) / Im(s) (-).
    frequency : numpy.ndarray
        (nV, modes) frequencies (rad/s).
    flutter_speed : float or None
        Flutter speed (m/s).
    flutter_frequency : float or None
        Flutter frequency (rad/s).
    flutter_mode : int or None
        Index of the structural mode that flutters.
    method : {"p-k", "state-space"}
        The method.
    k_clamped : numpy.ndarray or None, optional
        (nV, modes) whether k was clamped to the tabulated range (p-k only).
    """

    speeds: np.ndarray
    damping: np.ndarray
    frequency: np.ndarray
    flutter_speed: float | None
    flutter_frequency: float | None
    flutter_mode: int | None
    method: str
    k_clamped: np.ndarray | None = None


def _first_order(M, C, K):
    n = M.shape[0]
    Minv = np.linalg.inv(M)
    return np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])


def _nearest(values, target):
    values = values[values.imag > 0.0]
    return values[np.argmin(np.abs(values - target))]


def pk_root(structure: ModalStructure, gaf: GeneralizedForces, density, speed, start, *, tol=1e-9, max_iter=60):
    """The p-k eigenvalue ``s`` (1/s) followed from ``start`` at ``speed`` (module docstring) and
    whether its k was clamped to the tabulated range.

    Parameters
    ----------
    structure : ModalStructure
        Modal mass, stiffness and damping.
    gaf : GeneralizedForces
        Tabulated generalized aerodynamic forces.
    density : float
        Air density (kg/m^3).
    speed : float
        Airspeed (m/s).
    start : complex
        Starting eigenvalue (1/s).
    tol : float, optional
        Tolerance on the change of the reduced frequency k between iterations (-).
    max_iter : int, optional
        Iteration limit.

    Returns
    -------
    tuple
        (s, k clamped).
    """
    V, q = float(speed), 0.5 * float(density) * float(speed) ** 2
    b = gaf.b_ref
    kmax = float(gaf.k[-1])
    s = complex(start)
    clamped = False
    for _ in range(max_iter):
        k = abs(s.imag) * b / V
        clamped = k > kmax
        kk = min(max(k, _K_SMALL), kmax)
        Q, _ = interpolate(gaf, kk)
        K = structure.stiffness - q * Q.real
        C = structure.damping - q * (b / V) * Q.imag / kk
        s_new = _nearest(np.linalg.eigvals(_first_order(structure.mass, C, K)), s)
        if abs(s_new.imag - s.imag) * b / V < tol and abs(s_new - s) < 1e-6 * abs(s) + 1e-12:
            return s_new, clamped
        s = s_new
    return s, clamped


def state_matrix(structure: ModalStructure, rfa: RogerApproximation, density, speed) -> np.ndarray:
    """The real state matrix of ``(q, q', z_1 .. z_L)`` at ``speed`` (module docstring).

    Parameters
    ----------
    structure : ModalStructure
        Modal mass, stiffness and damping.
    rfa : RogerApproximation
        Roger's rational approximation of the forces.
    density : float
        Air density (kg/m^3).
    speed : float
        Airspeed (m/s).

    Returns
    -------
    numpy.ndarray
        The real state matrix.
    """
    V = float(speed)
    rho = float(density)
    b = rfa.b_ref
    qd = 0.5 * rho * V ** 2
    n = structure.mass.shape[0]
    L = rfa.n_lags
    Mb = structure.mass - 0.5 * rho * b ** 2 * rfa.A[2]
    Cb = structure.damping - 0.5 * rho * V * b * rfa.A[1]
    Kb = structure.stiffness - qd * rfa.A[0]
    Minv = np.linalg.inv(Mb)
    A = np.zeros((2 * n + L * n, 2 * n + L * n))
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n, :n] = -Minv @ Kb
    A[n:2 * n, n:2 * n] = -Minv @ Cb
    for l in range(L):
        cols = slice(2 * n + l * n, 2 * n + (l + 1) * n)
        A[n:2 * n, cols] = qd * Minv @ rfa.A[3 + l]
        A[cols, n:2 * n] = np.eye(n)
        A[cols, cols] = -rfa.lags[l] * V / b * np.eye(n)
    return A


def state_space_root(structure, rfa, density, speed, start):
    """The state-space eigenvalue nearest ``start`` at ``speed``.

    Parameters
    ----------
    structure : ModalStructure
        Modal mass, stiffness and damping.
    rfa : RogerApproximation
        Roger's rational approximation of the forces.
    density : float
        Air density (kg/m^3).
    speed : float
        Airspeed (m/s).
    start : complex
        Eigenvalue to be nearest to (1/s).

    Returns
    -------
    complex
        The eigenvalue (1/s).
    """
    return _nearest(np.linalg.eigvals(state_matrix(structure, rfa, density, speed)), complex(start))


def _sweep(root, structure, speeds, method):
    omega0 = np.sqrt(np.diag(structure.stiffness) / np.diag(structure.mass))
    nV, nm = len(speeds), omega0.size
    roots = np.zeros((nV, nm), dtype=complex)
    clamped = np.zeros((nV, nm), dtype=bool)
    prev = 1j * omega0
    for i, V in enumerate(speeds):
        for j in range(nm):
            roots[i, j], clamped[i, j] = root(V, prev[j])
        prev = roots[i]
    g = 2.0 * roots.real / np.abs(roots.imag)
    flutter = None
    for i in range(1, nV):
        up = np.flatnonzero((g[i - 1] < 0.0) & (g[i] > G_TOL))
        if up.size:
            j = int(up[np.argmin(roots[i, up].real)])
            lo, hi = float(speeds[i - 1]), float(speeds[i])
            start_lo, start_hi = roots[i - 1, j], roots[i, j]

            def sigma(V, j=j, lo=lo, hi=hi, a=start_lo, b=start_hi):
                t = (V - lo) / (hi - lo)
                return root(V, a + t * (b - a))[0].real

            Vf = sopt.brentq(sigma, lo, hi, xtol=1e-6 * hi)
            t = (Vf - lo) / (hi - lo)
            sf = root(Vf, start_lo + t * (start_hi - start_lo))[0]
            flutter = (Vf, abs(sf.imag), j)
            break
    return FlutterResult(speeds=np.asarray(speeds, dtype=float), damping=g, frequency=np.abs(roots.imag),
                         flutter_speed=None if flutter is None else float(flutter[0]),
                         flutter_frequency=None if flutter is None else float(flutter[1]),
                         flutter_mode=None if flutter is None else int(flutter[2]), method=method,
                         k_clamped=clamped if method == "p-k" else None)


def pk_flutter(structure: ModalStructure, gaf: GeneralizedForces, density, speeds) -> FlutterResult:
    """p-k sweep over ``speeds`` (m/s, increasing) at ``density`` (kg/m^3), the flutter crossing refined.

    Parameters
    ----------
    structure : ModalStructure
        Modal mass, stiffness and damping.
    gaf : GeneralizedForces
        Tabulated generalized aerodynamic forces.
    density : float
        Air density (kg/m^3).
    speeds : array_like
        Increasing airspeeds (m/s).

    Returns
    -------
    FlutterResult
        The sweep.
    """
    speeds = _check_speeds(speeds, density)
    return _sweep(lambda V, s: pk_root(structure, gaf, density, V, s), structure, speeds, "p-k")


def state_space_flutter(structure: ModalStructure, rfa: RogerApproximation, density, speeds) -> FlutterResult:
    """State-space sweep (Roger lag states) over ``speeds`` (m/s), the flutter crossing refined.

    Parameters
    ----------
    structure : ModalStructure
        Modal mass, stiffness and damping.
    rfa : RogerApproximation
        Roger's rational approximation of the forces.
    density : float
        Air density (kg/m^3).
    speeds : array_like
        Increasing airspeeds (m/s).

    Returns
    -------
    FlutterResult
        The sweep.
    """
    speeds = _check_speeds(speeds, density)
    return _sweep(lambda V, s: (state_space_root(structure, rfa, density, V, s), False), structure, speeds,
                  "state-space")


def _check_speeds(speeds, density):
    v = np.atleast_1d(np.asarray(speeds, dtype=float))
    if v.size < 2 or not np.all(np.isfinite(v)) or np.any(v <= 0.0) or np.any(np.diff(v) <= 0.0):
        raise ValueError(f"speeds must be at least two increasing airspeeds > 0 m/s, got {v.tolist()}")
    if not (np.isfinite(density) and float(density) > 0.0):
        raise ValueError(f"density must be > 0 kg/m^3, got {density}")
    return v
