"""Linear stability of a residual system R(x, xdot, p, q) = 0 about a static state.

Linearising R about a static solution x0 (R(x0, 0, p, q) = 0) gives ``B dx' + A dx = 0`` with
``A = dR/dx`` and ``B = dR/dxdot`` at (x0, 0). Solutions ``dx = v e^(lambda t)`` satisfy the
generalised eigenproblem ``lambda B v = -A v``. ``B`` is singular (the algebraic equations of the
system: strain-displacement, kinematics, the clamp), so the pencil has infinite eigenvalues, which
are discarded. This is the eigen-analysis ASWING performs about a deformed state (M. Drela,
"Integrated simulation model for preliminary aerodynamic, structural, and control-law design of
aircraft", AIAA 99-1394, 1999) and the one of M. J. Patil, D. H. Hodges, C. E. S. Cesnik,
"Nonlinear aeroelasticity and flight dynamics of high-altitude long-endurance aircraft",
J. Aircraft 38(1), 2001.

Per eigenvalue lambda = sigma + i omega: the *damping* sigma (1/s, < 0 stable), the frequency
``|omega|`` (rad/s) and the damping ratio ``g = 2 sigma / |omega|`` of the V-g plot (for a lightly damped
mode g is twice the fraction of critical damping, which is ``-sigma/|lambda|``).

Two solvers: dense QZ (``scipy.linalg.eig``) for small systems, and sparse shift-invert Arnoldi
(``scipy.sparse.linalg.eigs`` on ``(A + s B)^-1 B``, whose eigenvalues ``mu = 1 / (s - lambda)``
map infinite lambda to mu = 0) for large ones.

Mode tracking over a speed sweep pairs the modes at consecutive speeds by the modal assurance
criterion ``MAC = |v_i^H w_j|^2 / (|v_i|^2 |w_j|^2)`` (R. J. Allemang, "The modal assurance criterion
- twenty years of use and abuse", Sound and Vibration, 2003), with an optimal assignment.

Flutter: the lowest speed at which a tracked mode with non-zero frequency has its damping cross
zero, refined by Brent's method on that mode's damping. Divergence: the lowest speed at which a
real eigenvalue crosses zero, i.e. ``det A`` changes sign (``det(A + lambda B)`` at lambda = 0),
refined by bisection on that sign.
"""

from __future__ import annotations

import hashlib
import warnings
from dataclasses import dataclass, field

import casadi as ca
import numpy as np
import scipy.linalg as sla
import scipy.optimize as sopt
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.timemarch.system import derived
from wingmdao.utils import casadi_cache as cc
from wingmdao.utils.casadi_cache import JitCall, definition_key, signature_stub
from wingmdao.timemarch.bdf import solve_static

#: systems up to this many states use the dense QZ solver by default
DENSE_MAX_STATES = 800


def static_state(system, p, q, x0=None, **options) -> np.ndarray:
    """Static solution of ``R(x, 0, p, q) = 0`` (Newton with load stepping; om.AnalysisError if it fails).

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    p, q : numpy.ndarray
        Packed parameter and forcing vectors.
    x0 : numpy.ndarray or None, optional
        Starting guess; None for the system's initial guess.
    **options
        Passed to :func:`wingmdao.timemarch.bdf.solve_static` (load steps, tolerances).

    Returns
    -------
    numpy.ndarray
        The static state.
    """
    x, _ = solve_static(system, p, q, x0, **options)
    return x


#: evaluations of the pencil function after which it is compiled (a PEGASUS sizing with the flutter
#: constraint makes ~500, a 15-speed sweep 15-30; the compiled library is cached on disk)
PENCIL_JIT_THRESHOLD = 40


class _PencilFunction:
    """``(x, xdot, p, q) -> (dR/dx, dR/dxdot)`` as one CasADi function of both Jacobians' nonzeros,
    compiled to C after :data:`PENCIL_JIT_THRESHOLD` evaluations (:class:`wingmdao.utils.casadi_cache.JitCall`;
    the interpreted ``jac_state`` of the aeroelastic beam costs ~3 ms, the compiled one ~0.1 ms).

    With a warm compile cache the library is loaded without forming the two Jacobians (0.35 s for
    the 20-node PEGASUS system): the patterns are the system's own (``jacobian_patterns``: the
    same residual, so the same sparsity) and the library's key and signature check need only the
    dense input and output shapes (:func:`~wingmdao.utils.casadi_cache.signature_stub`)."""

    def __init__(self, system):
        f = system.residual_function
        n, npar, nq = system.n_state, system.n_param, system.n_forcing
        self.n = n
        self.definition = derived_definition(system, "wingmdao.stability.eigen._PencilFunction", __name__)
        self.name = f"{f.name()}_pencil"
        pats = system.jacobian_patterns() if hasattr(system, "jacobian_patterns") else None
        self.call = self._cached(pats, n, npar, nq) if pats is not None and cc.jit_enabled() else None
        if self.call is None:
            self._build(f, n, npar, nq)

    def _cached(self, pats, n, npar, nq):
        """The precompiled call from the cache and the patterns from ``pats``, or None (a miss)."""
        patterns = []
        for k in ("x", "xdot"):
            rows, cols, shape = pats[k]
            if tuple(shape) != (n, n):
                return None
            indptr = np.searchsorted(np.asarray(cols), np.arange(n + 1)).astype(np.int64)
            patterns.append((np.asarray(rows, dtype=np.int64), indptr))
        stub = signature_stub(self.name, [(n, 1), (n, 1), (npar, 1), (nq, 1)],
                          [(patterns[0][0].size, 1), (patterns[1][0].size, 1)])
        hit = cc.cached(stub, key=cc.function_key(stub, definition=self.definition))
        if hit is None:
            return None
        self.patterns = patterns
        return cc.precompiled_call(hit, PENCIL_JIT_THRESHOLD, definition=self.definition)

    def _build(self, f, n, npar, nq):
        x, xd = ca.SX.sym("x", n), ca.SX.sym("xdot", n)
        p, q = ca.SX.sym("p", npar), ca.SX.sym("q", nq)
        R = f(x, xd, p, q)
        ja, jb = ca.jacobian(R, x), ca.jacobian(R, xd)
        self.patterns = []
        for j in (ja, jb):
            colind, row = j.sparsity().get_ccs()
            self.patterns.append((np.asarray(row, dtype=np.int64), np.asarray(colind, dtype=np.int64)))
        fun = ca.Function(self.name, [x, xd, p, q], [ja.nz[:], jb.nz[:]])
        self.call = JitCall(fun, PENCIL_JIT_THRESHOLD, definition=self.definition)

    def __call__(self, x, p, q):
        a, b = self.call(x, np.zeros_like(x), p, q)
        (ra, ca_), (rb, cb) = self.patterns
        A = sp.csc_matrix((a, ra, ca_), shape=(self.n, self.n))
        B = sp.csc_matrix((b, rb, cb), shape=(self.n, self.n))
        return A, B


def derived_definition(system, builder: str, module: str) -> str:
    """Cache definition (:func:`wingmdao.utils.casadi_cache.definition_key`) of a function that
    ``builder`` (in ``module``) derives from ``system``'s residual: the system's own definition or,
    without one, the SHA-256 of its serialized residual function (16 ms for the 20-node PEGASUS
    system, against 0.55 s to serialize the derived second-derivative function for its key),
    with the source of ``module``.

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    builder : str
        Name of the derived function's builder.
    module : str
        Dotted name of the builder's module.

    Returns
    -------
    str
        The cache definition.
    """

    base = getattr(system, "definition", None)
    if base is None:
        base = hashlib.sha256(system.residual_function.serialize().encode()).hexdigest()
    return definition_key(builder, (str(base),), (module,))


def pencil_function(system):
    """The (compiled once evaluated often) pencil function of ``system``, or None for a system
    without a CasADi ``residual_function`` (those use ``jac_state``).

    Parameters
    ----------
    system : ResidualSystem
        The residual system.

    Returns
    -------
    casadi.Function or None
        The pencil function.
    """
    return derived(system, "pencil_function",
                   lambda s: _PencilFunction(s) if hasattr(s, "residual_function") else None)


def linearize(system, p, q, x0) -> tuple[sp.csc_matrix, sp.csc_matrix]:
    """``(A, B) = (dR/dx, dR/dxdot)`` at ``(x0, xdot = 0)``, sparse CSC (CasADi systems: one
    compiled function of both Jacobians, :func:`pencil_function`; others ``jac_state``).

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    p, q : numpy.ndarray
        Packed parameter and forcing vectors.
    x0 : numpy.ndarray
        State to linearise about.

    Returns
    -------
    tuple of scipy.sparse.csc_matrix
        (A, B).
    """
    x0 = np.asarray(x0, dtype=float).reshape(system.n_state)
    p, q = np.asarray(p, float).ravel(), np.asarray(q, float).ravel()
    fun = pencil_function(system)
    if fun is not None:
        A, B = fun(x0, p, q)
    else:
        A, B = system.jac_state(x0, np.zeros_like(x0), p, q)
        A, B = sp.csc_matrix(A), sp.csc_matrix(B)
    A.eliminate_zeros()
    B.eliminate_zeros()
    return A, B


@dataclass
class Modes:
    """Finite eigenvalues (one of each complex-conjugate pair: Im >= 0) and right eigenvectors.

    Parameters
    ----------
    eigenvalues : numpy.ndarray
        Finite eigenvalues, Im >= 0 (1/s).
    vectors : numpy.ndarray
        (n_state, n_modes) right eigenvectors.
    x0 : numpy.ndarray or None, optional
        The state linearised about.
    det_sign : float, optional
        Sign of det(dR/dx) at ``x0`` (a sign change between speeds marks divergence).
    """

    eigenvalues: np.ndarray          # complex (k,)
    vectors: np.ndarray              # complex (n_state, k), unit 2-norm columns
    x0: np.ndarray | None = None     # the static state linearised about
    det_sign: float = 1.0            # sign of det(dR/dx) at x0 (divergence detection)

    @property
    def damping(self) -> np.ndarray:
        """Re(lambda), 1/s (negative: decaying)."""
        return self.eigenvalues.real

    @property
    def frequency(self) -> np.ndarray:
        """``|Im(lambda)|``, rad/s."""
        return np.abs(self.eigenvalues.imag)

    @property
    def structural_damping(self) -> np.ndarray:
        """``g = 2 Re / |Im|`` (NaN for real eigenvalues; :func:`structural_damping`)."""
        return structural_damping(self.eigenvalues)

    @property
    def damping_ratio(self) -> np.ndarray:
        """Deprecated name of :attr:`structural_damping` (g, positive when unstable)."""
        return _deprecated_damping_ratio(self.eigenvalues)


def structural_damping(eigenvalues) -> np.ndarray:
    """The V-g method's structural damping ``g = 2 Re(lambda) / |Im(lambda)|`` (NaN for real
    eigenvalues): positive when the mode is unstable, about -2 zeta for a lightly damped mode
    (``zeta = -Re lambda / |lambda|``, the damping ratio of
    :attr:`wingmdao.stability.sensitivity.DampingConstraint.damping_ratio` and
    :meth:`wingmdao.beam.residual.StrainRateDamping.from_damping_ratio`).

    Parameters
    ----------
    eigenvalues : array_like
        Complex eigenvalues (1/s).

    Returns
    -------
    numpy.ndarray
        g (-).
    """
    lam = np.asarray(eigenvalues)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(np.abs(lam.imag) > 0, 2.0 * lam.real / np.abs(lam.imag), np.nan)


def damping_ratio(eigenvalues) -> np.ndarray:
    """Deprecated name of :func:`structural_damping` (``g = 2 Re / |Im|``, not a damping ratio).

    Parameters
    ----------
    eigenvalues : array_like
        Complex eigenvalues (1/s).

    Returns
    -------
    numpy.ndarray
        g (-).
    """
    return _deprecated_damping_ratio(eigenvalues)


def _deprecated_damping_ratio(eigenvalues) -> np.ndarray:
    warnings.warn("wingmdao.stability.eigen: 'damping_ratio' (g = 2 Re / |Im|) is deprecated; use "
                  "'structural_damping'", DeprecationWarning, stacklevel=3)
    return structural_damping(eigenvalues)


def _det_sign(A) -> float:
    """Sign of det(A) from an LU factorisation (0 if exactly singular)."""
    if A.shape[0] <= 60:
        sign, _ = np.linalg.slogdet(A.toarray())
        return float(sign)
    try:
        lu = spla.splu(sp.csc_matrix(A), permc_spec="NATURAL")
    except RuntimeError:
        return 0.0
    d = lu.U.diagonal()
    sign = np.prod(np.sign(d))
    # permutation parities
    for perm in (lu.perm_r, lu.perm_c):
        sign *= _perm_parity(perm)
    return float(sign)


def _perm_parity(perm) -> float:
    perm = np.array(perm)
    seen = np.zeros(perm.size, bool)
    parity = 1.0
    for i in range(perm.size):
        if not seen[i]:
            j, length = i, 0
            while not seen[j]:
                seen[j] = True
                j = perm[j]
                length += 1
            if length % 2 == 0:
                parity = -parity
    return parity


def eigenmodes(system, p, q, x0=None, *, static=True, count=None, sigma=0.0, method="auto",
               max_abs=1e6, static_options=None, ncv=None) -> Modes:
    """Finite eigenvalues of ``lambda B v = -A v`` about a static state, sorted by ``|lambda|``.

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    p, q : numpy.ndarray
        Packed parameter and forcing vectors.
    x0 : numpy.ndarray or None, optional
        State to linearise about, or the starting guess of the static solve (``static=True``).
    static : bool, optional
        Solve ``R(x, 0, p, q) = 0`` first (from ``x0`` or the system's initial guess).
    count : int or None, optional
        Dense: keep the ``count`` smallest ``|lambda|`` (all finite ones by default); sparse: the
        ``count`` eigenvalues nearest to ``sigma`` (12 by default).
    sigma : float or complex, optional
        Shift of the sparse solver (1/s): the eigenvalues nearest to it.
    method : {"auto", "dense", "sparse"}, optional
        Eigen solver ("auto": dense up to ``DENSE_MAX_STATES`` states).
    max_abs : float, optional
        Eigenvalues with ``|lambda|`` above this (1/s) are treated as infinite (spurious).
    static_options : dict or None, optional
        Options of the static solve (:func:`static_state`).
    ncv : int or None, optional
        Arnoldi basis size of the sparse solver (ARPACK default 2 count + 1).

    Returns
    -------
    Modes
        The finite eigenvalues and right eigenvectors.
    """
    p = np.asarray(p, dtype=float)
    q = np.asarray(q, dtype=float)
    if method not in ("auto", "dense", "sparse"):
        raise ValueError(f'method must be "auto", "dense" or "sparse", got {method!r}')
    if count is not None and int(count) < 1:
        raise ValueError(f"count must be >= 1, got {count}")
    if static:
        x = static_state(system, p, q, x0, **(static_options or {}))
    else:
        x = np.asarray(system.initial_guess(p, q) if x0 is None else x0, dtype=float).ravel()
    A, B = linearize(system, p, q, x)
    n = system.n_state
    if method == "auto":
        method = "dense" if n <= DENSE_MAX_STATES else "sparse"
    if method == "dense":
        lam, vec = sla.eig(-A.toarray(), B.toarray())
    else:
        k = min(int(count or 12), n - 2)
        sigma = complex(sigma) if np.iscomplexobj(sigma) else float(sigma)
        shifted = sp.csc_matrix(A + sigma * B, dtype=complex if np.iscomplex(sigma) else float)
        lu = spla.splu(shifted)
        Bc = B
        op = spla.LinearOperator((n, n), matvec=lambda v: lu.solve(np.asarray(Bc @ v)),
                                 dtype=complex if np.iscomplex(sigma) else float)
        # a fixed Arnoldi start vector: ARPACK's default is random, so eigenvector phases and the
        # last digits of the eigenvalues changed from run to run
        v0 = np.random.default_rng(0).standard_normal(n).astype(op.dtype)
        mu, vec = spla.eigs(op, k=k, which="LM", v0=v0,
                            ncv=None if ncv is None else min(n - 1, int(ncv)))
        with np.errstate(divide="ignore"):
            lam = sigma - 1.0 / mu
    keep = np.isfinite(lam) & (np.abs(lam) < max_abs)
    lam, vec = lam[keep], vec[:, keep]
    scale = max(1.0, float(np.max(np.abs(lam), initial=1.0)))
    upper = lam.imag >= -1e-9 * scale
    lam, vec = lam[upper], vec[:, upper]
    lam = np.where(np.abs(lam.imag) <= 1e-9 * scale, lam.real + 0j, lam)
    order = np.argsort(np.abs(lam))
    if count is not None and method == "dense":
        order = order[: int(count)]
    lam, vec = lam[order], vec[:, order]
    vec = vec / np.linalg.norm(vec, axis=0, keepdims=True)
    return Modes(lam, vec, x, _det_sign(A))


def mac_matrix(V, W, weights=None) -> np.ndarray:
    """``MAC[i, j] = |v_i^H w_j|^2 / (|v_i|^2 |w_j|^2)``; ``weights`` scale the state entries first.

    Parameters
    ----------
    V : numpy.ndarray
        (n_state, m) vectors.
    W : numpy.ndarray
        (n_state, k) vectors.
    weights : array_like or None, optional
        (n_state,) weights on the state entries; None for 1.

    Returns
    -------
    numpy.ndarray
        (m, k) MAC values in [0, 1].
    """
    V = np.asarray(V)
    W = np.asarray(W)
    if weights is not None:
        w = np.asarray(weights, dtype=float)[:, None]
        V, W = V * w, W * w
    num = np.abs(V.conj().T @ W) ** 2
    den = np.outer(np.sum(np.abs(V) ** 2, axis=0), np.sum(np.abs(W) ** 2, axis=0))
    return num / np.where(den > 0, den, 1.0)


def track_modes(modes_list, initial, weights=None):
    """Follow the modes ``initial`` (indices into ``modes_list[0]``) through the list.

    Returns ``(eigenvalues (n_speed, n_track) complex, indices (n_speed, n_track))``: at each
    speed the modes are paired with the previous speed's by an optimal assignment maximising MAC
    (ties broken by eigenvalue proximity).

    Parameters
    ----------
    modes_list : sequence of Modes
        Modes at each speed.
    initial : sequence of int
        Indices of the tracked modes at the first speed.
    weights : array_like or None, optional
        State weights of the MAC.

    Returns
    -------
    tuple
        Eigenvalues (n_speed, n_track) and indices (n_speed, n_track).
    """
    initial = np.asarray(initial, dtype=int)
    n_s, n_t = len(modes_list), initial.size
    lam = np.full((n_s, n_t), np.nan + 0j)
    idx = np.zeros((n_s, n_t), dtype=int)
    idx[0] = initial
    lam[0] = modes_list[0].eigenvalues[initial]
    prev_vec = modes_list[0].vectors[:, initial]
    prev_lam = lam[0]
    for s in range(1, n_s):
        m = modes_list[s]
        mac = mac_matrix(prev_vec, m.vectors, weights)
        dist = np.abs(prev_lam[:, None] - m.eigenvalues[None, :])
        dist = dist / (1.0 + np.abs(prev_lam[:, None]))
        cost = -(mac - 0.1 * np.minimum(dist, 1.0))
        rows, cols = sopt.linear_sum_assignment(cost)
        idx[s, rows] = cols
        lam[s, rows] = m.eigenvalues[cols]
        prev_vec = m.vectors[:, idx[s]]
        prev_lam = lam[s]
    return lam, idx


@dataclass
class StabilitySweep:
    """Eigen-analysis over an increasing speed sweep with tracked modes.

    Parameters
    ----------
    speeds : numpy.ndarray
        (n_speed,) airspeeds (m/s).
    modes : list of Modes
        Modes at each speed.
    tracked : numpy.ndarray
        (n_speed, n_track) tracked eigenvalues (1/s).
    indices : numpy.ndarray
        (n_speed, n_track) indices of the tracked modes in ``modes``.
    params_at : callable or None, optional
        ``params_at(V) -> (p, q)`` of the sweep.
    system : ResidualSystem or None, optional
        The residual system.
    options : dict, optional
        Options of the sweep (eigen solver, static, weights, min_frequency).
    """

    speeds: np.ndarray
    modes: list
    tracked: np.ndarray              # (n_speed, n_track) complex eigenvalues
    indices: np.ndarray
    params_at: object = field(repr=False, default=None)
    system: object = field(repr=False, default=None)
    options: dict = field(default_factory=dict)

    @property
    def damping(self) -> np.ndarray:
        """Re(lambda) per speed and tracked mode, 1/s."""
        return self.tracked.real

    @property
    def frequency(self) -> np.ndarray:
        """``|Im(lambda)|`` per speed and tracked mode, rad/s."""
        return np.abs(self.tracked.imag)

    @property
    def structural_damping(self) -> np.ndarray:
        """``g = 2 Re / |Im|`` per speed and tracked mode (NaN for real eigenvalues; :func:`structural_damping`)."""
        return structural_damping(self.tracked)

    @property
    def damping_ratio(self) -> np.ndarray:
        """Deprecated name of :attr:`structural_damping` (g, positive when unstable)."""
        return _deprecated_damping_ratio(self.tracked)


def check_speeds(speeds) -> np.ndarray:
    """Validated sweep: a 1-D array of at least 2 finite, non-negative, strictly increasing speeds (m/s).

    Parameters
    ----------
    speeds : array_like
        Airspeeds (m/s).

    Returns
    -------
    numpy.ndarray
        The checked speeds.
    """
    v = np.asarray(speeds, dtype=float).ravel()
    if v.size < 2:
        raise ValueError(f"speeds must hold at least 2 airspeeds (m/s), got {v.size}")
    if not np.all(np.isfinite(v)) or np.any(v < 0.0):
        raise ValueError(f"speeds must be finite and >= 0 m/s, got min {np.min(v)}")
    if np.any(np.diff(v) <= 0.0):
        i = int(np.flatnonzero(np.diff(v) <= 0.0)[0])
        raise ValueError(f"speeds must be strictly increasing; speeds[{i}] = {v[i]} m/s, "
                         f"speeds[{i + 1}] = {v[i + 1]} m/s")
    return v


def sweep(system, params_at, speeds, *, n_track=6, min_frequency=1e-3, weights=None, x0=None,
          static=True, **eig_options) -> StabilitySweep:
    """Eigen-analysis at each speed; tracks the ``n_track`` lowest-frequency oscillatory modes of
    the first speed (``|Im| > min_frequency`` rad/s). ``params_at(V) -> (p, q)``.

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    params_at : callable
        ``params_at(V) -> (p, q)``.
    speeds : array_like
        Increasing airspeeds (m/s).
    n_track : int, optional
        Number of modes tracked.
    min_frequency : float, optional
        Smallest ``|Im|`` of a tracked mode (rad/s).
    weights : array_like or None, optional
        State weights of the MAC.
    x0 : numpy.ndarray or None, optional
        Starting guess of the first static solve.
    static : bool, optional
        Linearise about the static state at each speed.
    **eig_options
        Passed to :func:`eigenmodes`.

    Returns
    -------
    StabilitySweep
        The sweep.
    """
    v = check_speeds(speeds)
    modes, x = [], x0
    for V in v:
        p, q = params_at(float(V))
        m = eigenmodes(system, p, q, x, static=static, **eig_options)
        if static:
            x = m.x0  # continuation
        modes.append(m)
    m0 = modes[0]
    osc = np.flatnonzero(m0.frequency > min_frequency)
    if osc.size == 0:
        raise ValueError(f"no oscillatory mode at the first speed {v[0]} m/s (is the mass zero?)")
    initial = osc[np.argsort(m0.frequency[osc])][: int(n_track)]
    tracked, idx = track_modes(modes, initial, weights)
    opts = dict(eig_options, static=static, weights=weights, min_frequency=min_frequency)
    return StabilitySweep(v, modes, tracked, idx, params_at, system, opts)


def critical_speeds(result: StabilitySweep, *, refine=True, xtol=1e-4):
    """Flutter and divergence speeds from a sweep (None when not reached within it).

    Returns a dict: ``flutter_speed``, ``flutter_frequency`` (rad/s), ``flutter_mode`` (tracked
    index), ``divergence_speed``. With ``refine`` the crossing is located to ``xtol`` (relative)
    by Brent's method on the damping of the crossing mode (flutter) and by bisection on the sign of
    det(dR/dx) (divergence).

    Parameters
    ----------
    result : StabilitySweep
        The sweep.
    refine : bool, optional
        Locate the crossings.
    xtol : float, optional
        Relative tolerance of the located speeds.

    Returns
    -------
    dict
        ``flutter_speed`` (m/s), ``flutter_frequency`` (rad/s), ``flutter_mode``, ``divergence_speed`` (m/s).
    """
    v = result.speeds
    opts = dict(result.options)
    weights = opts.pop("weights", None)
    min_f = opts.pop("min_frequency", 1e-3)
    out = {"flutter_speed": None, "flutter_frequency": None, "flutter_mode": None,
           "divergence_speed": None}

    # ---- flutter: first tracked oscillatory mode whose damping becomes >= 0 ----
    best = None
    for j in range(result.tracked.shape[1]):
        lam = result.tracked[:, j]
        for s in range(1, v.size):
            eps = 1e-9 * max(abs(lam[s]), abs(lam[s - 1]))   # neutral (no-aero) modes sit at +-round-off
            if (lam[s - 1].real < -eps and lam[s].real > eps and abs(lam[s].imag) > min_f
                    and abs(lam[s - 1].imag) > min_f):
                if best is None or v[s] < v[best[1]] or (s == best[1] and lam[s].real > best[2]):
                    best = (j, s, lam[s].real)
                break
    if best is not None:
        j, s, _ = best
        lo, hi = v[s - 1], v[s]
        ref_vec = result.modes[s - 1].vectors[:, result.indices[s - 1, j]]
        ref_lam = result.tracked[s - 1, j]
        lam_hi = result.tracked[s, j]
        V_f, om_f = hi, abs(lam_hi.imag)
        if refine:
            def mode_at(V):
                p, q = result.params_at(float(V))
                m = eigenmodes(result.system, p, q, result.modes[s - 1].x0, **opts)
                mac = mac_matrix(ref_vec[:, None], m.vectors, weights)[0]
                frac = (V - lo) / (hi - lo)
                guess = ref_lam + frac * (lam_hi - ref_lam)
                dist = np.abs(m.eigenvalues - guess) / (1.0 + abs(guess))
                return m.eigenvalues[int(np.argmax(mac - 0.1 * np.minimum(dist, 1.0)))]

            def f(V):
                if V == lo:
                    return ref_lam.real
                if V == hi:
                    return lam_hi.real
                return mode_at(V).real

            V_f = sopt.brentq(f, lo, hi, xtol=xtol * hi, rtol=1e-10)
            om_f = abs(mode_at(V_f).imag)
        out.update(flutter_speed=float(V_f), flutter_frequency=float(om_f), flutter_mode=int(j))

    # ---- divergence: sign change of det(dR/dx) ----
    signs = np.array([m.det_sign for m in result.modes])
    change = np.flatnonzero(signs[1:] != signs[0])
    if change.size:
        s = int(change[0]) + 1
        lo, hi = v[s - 1], v[s]
        if refine:
            s0 = signs[0]
            x_ref = result.modes[s - 1].x0
            while hi - lo > xtol * hi:
                mid = 0.5 * (lo + hi)
                p, q = result.params_at(float(mid))
                x = static_state(result.system, p, q, x_ref) if opts.get("static", True) else x_ref
                A, _ = linearize(result.system, p, q, x)
                if _det_sign(A) == s0:
                    lo = mid
                else:
                    hi = mid
        out["divergence_speed"] = float(0.5 * (lo + hi))
    return out
