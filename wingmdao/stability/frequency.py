"""Frequency response of a linearised residual system to a travelling vertical gust (docs/turbulence.md).

About a static state x0 (the trimmed 1 g level flight of a coupled case), the residual
R(x, xdot, p, q) = 0 linearises, with the gust velocities w (one per aerodynamic station, the
forcing ``gust_velocity``) as input, to

    E dx' + A dx + G w = 0,      A = dR/dx,  E = dR/dxdot,  G = dR/dw            (1)

(A and E are the pencil of the flutter analysis, :func:`wingmdao.stability.eigen.linearize`, here
from the system's own ``jac_state``, the functions its Newton solves already evaluate: a one-off
analysis does not form the flutter pencil's separate CasADi function, 6 s for the 20-node PEGASUS
system; G is the system's forcing Jacobian ``jac_inputs``). A unit harmonic gust of angular frequency omega
meets station i, at body x_i (its leading edge), (x_i - x_ref) / V after the most forward one,

    w_i(t) = Re[ exp(i omega t) exp(-i omega (x_i - x_ref) / V) ],                     (2)

so the steady harmonic state is Re[X(omega) exp(i omega t)] with

    (i omega E + A) X = -G w(omega),   w_i(omega) = exp(-i omega (x_i - x_ref) / V)     (3)

solved per frequency with a sparse complex LU (SuperLU). An output y = Cx dx + Cv dx' + D w
(internal loads, load factor, tip deflection: :func:`aeroelastic_outputs`) has the transfer
function H_y(omega) = (Cx + i omega Cv) X(omega) + D w(omega), in output units per m/s of gust.

Stresses: the box stresses of :mod:`wingmdao.stress.box_stress` (corner axial stress, flange-centre
shear) are linear in the section's internal loads for a given section, so their response is
``S H_loads`` exactly, with S the stress-per-unit-load matrix of each station
(:func:`stress_matrix`); the von Mises stress is not linear and has no transfer function.

Frequency grid (:func:`frequency_grid`): geometric from ``f_min`` to ``f_max`` plus, about every
lightly damped mode lambda = sigma + i omega_d of the pencil within the range, points spaced on
the scale of its half-power bandwidth |sigma|, where |H|^2 peaks. Integrals over the grid
(:func:`spectral_integral`) are trapezoidal, with the quadrature error estimated by Richardson
extrapolation against the same rule on every other point, (I_h - I_2h) / 3, and the part beyond
``f_max`` estimated from the power-law decay of the integrand over the last grid interval.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.beam.residual import STATE_BLOCKS
from wingmdao.beam.rotations import body_to_csn
from wingmdao.stability import pencil_lu
from wingmdao.stress.box_stress import box_stresses
from wingmdao.timemarch.system import layout

#: names of the six internal loads of a station in its csn frame (c chordwise aft, s along the beam
#: outboard, n normal up): forces F_c, F_s, F_n (N) and moments M_c, M_s, M_n (N m)
LOAD_NAMES = ("chordwise_shear", "axial_force", "vertical_shear", "bending_moment", "torsion",
              "chordwise_bending")
#: output units of the transfer functions per m/s of gust
LOAD_UNITS = ("N", "N", "N", "N m", "N m", "N m")
#: the linear box stresses (Pa) per station: 4 corner axial stresses then 4 flange-centre shears
STRESS_NAMES = ("sigma_corner", "tau_cent")


def check_frequencies(omega, name="frequencies") -> np.ndarray:
    """A validated 1-D grid of angular frequencies (rad/s): non-empty, finite, > 0, strictly increasing.

    Parameters
    ----------
    omega : array_like
        Angular frequencies (rad/s).
    name : str, optional
        Name used in the error.

    Returns
    -------
    numpy.ndarray
        The checked grid.
    """
    w = np.asarray(omega, dtype=float).ravel()
    if w.size == 0:
        raise ValueError(f"{name}: the frequency grid is empty; give at least 3 frequencies > 0 rad/s")
    bad = ~np.isfinite(w) | (w <= 0.0)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{name}[{i}] = {w[i]} rad/s; allowed range (0, inf) rad/s (finite)")
    if np.any(np.diff(w) <= 0.0):
        i = int(np.flatnonzero(np.diff(w) <= 0.0)[0])
        raise ValueError(f"{name} must increase strictly; {name}[{i}] = {w[i]}, {name}[{i + 1}] = {w[i + 1]} rad/s")
    return w


@dataclass
class OutputMap:
    """A linear output ``y = y0 + Cx dx + Cv dx' + D w`` (k outputs): ``y0`` its value at the
    linearisation state, ``Cx``/``Cv`` (k, n_state) and ``D`` (k, n_station) sparse.

    Parameters
    ----------
    y0 : numpy.ndarray
        (k,) output at the linearisation state.
    Cx, Cv : scipy.sparse.csr_matrix
        (k, n_state) maps of the state and its rate.
    D : scipy.sparse.csr_matrix
        (k, n_station) map of the gust velocities.
    units : str, optional
        Output units.
    """

    y0: np.ndarray
    Cx: sp.csr_matrix
    Cv: sp.csr_matrix
    D: sp.csr_matrix
    units: str = ""


@dataclass
class LinearGustModel:
    """The linearisation (1) about ``x0``: ``A``, ``E`` (n, n), ``G`` (n, n_station) sparse, the
    stations' penetration positions ``x_stations`` (m, body x), ``airspeed`` (m/s TAS) and the
    linear outputs ``outputs`` {name: :class:`OutputMap`}.

    Parameters
    ----------
    A, E : scipy.sparse.csc_matrix
        (n, n) dR/dx and dR/dxdot.
    G : scipy.sparse.csc_matrix
        (n, n_station) dR/dw of the stations' gust velocities.
    x_stations : numpy.ndarray
        (n_station,) penetration positions, body x (m).
    airspeed : float
        True airspeed (m/s).
    x0 : numpy.ndarray
        The linearisation state.
    outputs : dict, optional
        Name -> :class:`OutputMap`.
    """

    A: sp.csc_matrix
    E: sp.csc_matrix
    G: sp.csc_matrix
    x_stations: np.ndarray
    airspeed: float
    x0: np.ndarray
    outputs: dict = field(default_factory=dict)

    def gust_vector(self, omega) -> np.ndarray:
        """(n_freq, n_station) complex: exp(-i omega (x_i - x_ref) / V), x_ref the most forward station.

        Parameters
        ----------
        omega : array_like
            Angular frequencies (rad/s).

        Returns
        -------
        numpy.ndarray
            (n_freq, n_station) complex phase factors.
        """
        w = np.atleast_1d(np.asarray(omega, dtype=float))
        lag = (self.x_stations - np.min(self.x_stations)) / self.airspeed
        return np.exp(-1j * w[:, None] * lag[None, :])


def linear_gust_model(system, p, q, x0, *, x_stations, airspeed, outputs=None, gust_input=None) -> LinearGustModel:
    """Linearise ``system`` about the static state ``x0`` (forcing ``q``, whose ``trim_active``, if
    any, must be 0: the trim angle held) with the gust velocities of the stations as input.

    ``x_stations`` (n_station,) m: where each station meets the gust (body x); ``airspeed`` m/s TAS;
    ``outputs`` {name: :class:`OutputMap`}; ``gust_input`` G = dR/dw (n_state, n_station), by
    default the columns of the system's forcing ``gust_velocity`` in ``jac_inputs``. A free-pitch
    system (forcing ``tail_gust_velocity``, :mod:`wingmdao.aero.pitch`) gets one more station, the
    horizontal tail at its parameter ``tail_x``, appended to the wing's ``x_stations`` with its
    column of G. ValueError for bad input.

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    p, q : numpy.ndarray
        Packed parameters and forcing (``trim_active`` 0).
    x0 : numpy.ndarray
        Static state.
    x_stations : array_like
        (n_station,) penetration positions, body x (m).
    airspeed : float
        True airspeed (m/s).
    outputs : dict or None, optional
        Name -> :class:`OutputMap`.
    gust_input : scipy.sparse.spmatrix or None, optional
        G = dR/dw; None for the system's ``gust_velocity`` columns.

    Returns
    -------
    LinearGustModel
        The model.
    """
    ql = layout(system.forcing_specs)
    if gust_input is None and "gust_velocity" not in ql:
        raise ValueError(f"system {getattr(system, 'name', system)!r} has no gust_velocity forcing; pass gust_input")
    if "trim_active" in ql and float(np.ravel(q)[ql["trim_active"]][0]) != 0.0:
        raise ValueError("q: trim_active must be 0 in the linearisation (the trim angle held: the 1 g state is "
                         "solved with trim_active = 1, its response with 0)")
    xs = np.asarray(x_stations, dtype=float).ravel()
    x0 = np.asarray(x0, dtype=float).ravel()
    if gust_input is None:
        _, dq = system.jac_inputs(x0, np.zeros_like(x0), np.asarray(p, float).ravel(), np.asarray(q, float).ravel())
        cols = gust_columns(ql)
        gust_input = sp.csc_matrix(dq)[:, cols]
        if "tail_gust_velocity" in ql:
            xs = np.r_[xs, _tail_x(system, p)]
    G = sp.csc_matrix(gust_input)
    if G.shape[0] != system.n_state or xs.size != G.shape[1] or not np.all(np.isfinite(xs)):
        raise ValueError(f"x_stations: need {G.shape[1]} finite positions (m), got {xs.size}")
    if not (np.isfinite(airspeed) and airspeed > 0):
        raise ValueError(f"airspeed = {airspeed} m/s; allowed range (0, inf) m/s")
    A, E = system.jac_state(x0, np.zeros_like(x0), np.asarray(p, float).ravel(), np.asarray(q, float).ravel())
    A, E = sp.csc_matrix(A), sp.csc_matrix(E)
    A.eliminate_zeros()
    E.eliminate_zeros()
    return LinearGustModel(sp.csc_matrix(A), sp.csc_matrix(E), G, xs, float(airspeed), x0, dict(outputs or {}))


def gust_columns(ql) -> np.ndarray:
    """Forcing indices of the gust inputs: ``gust_velocity`` (one per wing station), then
    ``tail_gust_velocity`` of a free-pitch system.

    Parameters
    ----------
    ql : dict
        Forcing name -> slice of the packed forcing (:func:`wingmdao.timemarch.system.layout`).

    Returns
    -------
    numpy.ndarray
        Forcing indices.
    """
    cols = np.arange(ql["gust_velocity"].start, ql["gust_velocity"].stop)
    if "tail_gust_velocity" in ql:
        cols = np.r_[cols, ql["tail_gust_velocity"].start]
    return cols


def _tail_x(system, p) -> float:
    """Body x (m) of the horizontal tail's aerodynamic centre of a free-pitch system."""
    return float(np.ravel(p)[layout(system.param_specs)["tail_x"]][0])


@dataclass
class FrequencyResponse:
    """Transfer functions on a grid: ``omega`` (rad/s), ``states`` (n_freq, n_state) complex (None
    unless kept) and ``outputs`` {name: (n_freq, k) complex, output units per m/s of gust}.

    Parameters
    ----------
    omega : numpy.ndarray
        Angular frequencies (rad/s).
    outputs : dict
        Name -> (n_freq, k) complex transfer functions (per m/s of gust).
    states : numpy.ndarray or None, optional
        (n_freq, n_state) complex state responses, when kept.
    """

    omega: np.ndarray
    outputs: dict
    states: np.ndarray | None = None

    @property
    def frequency_hz(self) -> np.ndarray:
        return self.omega / (2 * np.pi)


def frequency_response(model: LinearGustModel, omega, *, keep_states=False) -> FrequencyResponse:
    """Solve (3) at every ``omega`` (rad/s, > 0, increasing) and evaluate the outputs.

    Parameters
    ----------
    model : LinearGustModel
        The linear model.
    omega : array_like
        Angular frequencies (rad/s).
    keep_states : bool, optional
        Keep the state responses.

    Returns
    -------
    FrequencyResponse
        The transfer functions.
    """
    w = check_frequencies(omega)
    W = model.gust_vector(w)
    n = model.A.shape[0]
    X = np.empty((w.size, n), dtype=complex)
    factors = ShiftedFactors(model.A, model.E)
    for k, om in enumerate(w):
        X[k] = factors.factor(1j * om).solve(-(model.G @ W[k]))
    out = {}
    for name, m in model.outputs.items():
        y = (m.Cx @ X.T).T + (1j * w[:, None]) * (m.Cv @ X.T).T + (m.D @ W.T).T
        out[name] = np.asarray(y)
    return FrequencyResponse(w, out, X if keep_states else None)


class ShiftedFactors:
    """Factorizations of ``A + s E`` for complex shifts s: the static-pivot complex LU of
    :mod:`wingmdao.stability.pencil_lu` (pattern analysis once, numeric factorization per shift in
    C, every solve checked by its backward error), SuperLU (natural column order, partial
    pivoting) for the first shift, without the compiled kernel and for any shift whose static
    pivots fail. ``factor(s)`` returns an object with ``solve(rhs)`` and ``solve_transposed(rhs)``
    ((A + s E)^T x = rhs, for adjoints).

    Parameters
    ----------
    A, E : scipy.sparse.spmatrix
        Real sparse matrices of the pencil.
    """

    def __init__(self, A, E):
        self.A, self.E = sp.csc_matrix(A), sp.csc_matrix(E)
        self.pen = pencil_lu.pencil(self.A, self.E)

    def factor(self, s):
        """The factors of ``A + s E`` (the kernel's when its pivots hold, else SuperLU's).

        Parameters
        ----------
        s : complex
            The shift.

        Returns
        -------
        object
            Factors with ``solve(rhs)`` and ``solve_transposed(rhs)``.
        """
        lu = self.pen.factor(s) if self.pen is not None else None
        return _PencilFactor(self, s, lu)

    def superlu(self, s):
        """SuperLU of ``A + s E`` in natural column order; its row order becomes the kernel's pivots.

        Parameters
        ----------
        s : complex
            The shift.

        Returns
        -------
        scipy.sparse.linalg.SuperLU
            The factorization.
        """
        lu = spla.splu(sp.csc_matrix(self.A + s * self.E, dtype=complex), permc_spec="NATURAL")
        if self.pen is not None:
            self.pen.repivot(lu.perm_r)
        return lu


class _PencilFactor:
    """One shift's factors (the C kernel's, or SuperLU's when they are missing or a solve fails)."""

    def __init__(self, owner: ShiftedFactors, s, lu):
        self.owner, self.s, self.lu, self.slu = owner, s, lu, None

    def _superlu(self):
        if self.slu is None:
            self.slu = self.owner.superlu(self.s)
        return self.slu

    def solve(self, rhs):
        if self.lu is not None:
            x, berr = self.owner.pen.solve(self.lu, rhs)
            if berr <= pencil_lu.BACKWARD_TOL:
                return x
        return self._superlu().solve(np.asarray(rhs, dtype=complex))

    def solve_transposed(self, rhs):
        """(A + s E)^T x = rhs: conj of the conjugate-transposed solve of conj(rhs)."""
        if self.lu is not None:
            x, berr = self.owner.pen.solve(self.lu, np.conj(rhs), trans="H")
            if berr <= pencil_lu.BACKWARD_TOL:
                return np.conj(x)
        return self._superlu().solve(np.asarray(rhs, dtype=complex), trans="T")


def pencil_eigenvalues(model: LinearGustModel) -> np.ndarray:
    """The finite eigenvalues lambda of ``lambda E v = -A v`` (dense QZ without vectors, ~0.5 s for
    the 441 states of the 20-node PEGASUS system on one core): where the response peaks.

    Parameters
    ----------
    model : LinearGustModel
        The linear model.

    Returns
    -------
    numpy.ndarray
        Finite eigenvalues (1/s).
    """
    lam = sla.eigvals(-model.A.toarray(), model.E.toarray())
    return lam[np.isfinite(lam) & (np.abs(lam) < 1e6)]


def frequency_grid(eigenvalues=(), *, f_min=1e-3, f_max=20.0, n_base=161, n_mode=16, max_damping_ratio=0.5,
                   wing_ratio=1.5):
    """Angular frequencies (rad/s) refined about the pencil's modes; an odd count (for halving).

    Geometric from ``f_min`` to ``f_max`` (Hz) with ``n_base`` points, plus, about every mode
    lambda = sigma + i omega_d with f_min < omega_d / 2 pi < f_max, sigma < 0 and
    -sigma / |lambda| < ``max_damping_ratio``: ``n_mode`` points at omega_d + |sigma| tan(u), u
    uniform in (-1.45, 1.45) (8 half-bandwidths either side, densest at the peak), and on both
    sides points at offsets growing by ``wing_ratio`` from 8 |sigma| to the spacing of the
    geometric grid there, so that the Lorentzian flanks of a sharp peak are not bridged by one
    trapezoid.

    Parameters
    ----------
    eigenvalues : array_like, optional
        Eigenvalues of the pencil (1/s).
    f_min, f_max : float, optional
        Range of the geometric grid (Hz).
    n_base : int, optional
        Points of the geometric grid.
    n_mode : int, optional
        Points added about each mode.
    max_damping_ratio : float, optional
        Modes damped more than this get no refinement (-).
    wing_ratio : float, optional
        Growth of the flank offsets (-).

    Returns
    -------
    numpy.ndarray
        The grid (rad/s, odd count).
    """
    if not (np.isfinite(f_min) and np.isfinite(f_max) and 0 < f_min < f_max):
        raise ValueError(f"frequency range f_min = {f_min} Hz, f_max = {f_max} Hz; need 0 < f_min < f_max (finite)")
    if int(n_base) < 3:
        raise ValueError(f"n_base = {n_base}; allowed range [3, inf)")
    lo, hi = 2 * np.pi * f_min, 2 * np.pi * f_max
    pts = [np.geomspace(lo, hi, int(n_base))]
    step = (hi / lo) ** (1.0 / (int(n_base) - 1)) - 1.0  # relative spacing of the geometric grid
    for lam in np.atleast_1d(np.asarray(eigenvalues, dtype=complex)):
        wd, s = abs(lam.imag), lam.real
        if lo < wd < hi and s < 0 and -s / abs(lam) < max_damping_ratio and n_mode > 0:
            u = np.linspace(-1.45, 1.45, int(n_mode))
            pts.append(wd + abs(s) * np.tan(u))
            near, far = 8.0 * abs(s), step * wd
            if far > wing_ratio * near:
                offsets = np.geomspace(wing_ratio * near, far, int(np.ceil(np.log(far / near) / np.log(wing_ratio))))
                pts += [wd - offsets, wd + offsets]
    w = np.concatenate(pts)
    w = np.unique(w[(w >= lo) & (w <= hi)])
    keep = np.concatenate([[True], np.diff(w) > 1e-9 * w[1:]])
    w = w[keep]
    if w.size % 2 == 0:  # an odd count: the halved grid keeps both ends
        w = np.insert(w, w.size - 1, 0.5 * (w[-2] + w[-1]))
    return w


@dataclass
class SpectralIntegral:
    """``value`` = int_0^inf f(omega) d omega; ``quadrature_error`` the Richardson estimate
    |I_h - I_2h| / 3 of the trapezoid on the grid; ``tail`` the estimated part beyond the grid
    (included in ``value``); ``head`` the part below it (f at the first point times omega_0).

    Parameters
    ----------
    value : numpy.ndarray
        The integral.
    quadrature_error : numpy.ndarray
        Richardson estimate of the trapezoid's error.
    tail : numpy.ndarray
        Estimated part beyond the grid (in ``value``).
    head : numpy.ndarray
        Part below the grid (in ``value``).
    """

    value: np.ndarray
    quadrature_error: np.ndarray
    tail: np.ndarray
    head: np.ndarray


def spectral_integral(omega, integrand) -> SpectralIntegral:
    """int_0^inf of ``integrand`` (n_freq, ...) sampled on ``omega`` (rad/s, odd count >= 3).

    Parameters
    ----------
    omega : array_like
        Angular frequencies (rad/s). (odd count >= 3)
    integrand : numpy.ndarray
        (n_freq, ...) samples.

    Returns
    -------
    SpectralIntegral
        The integral and its error estimates.
    """
    w = check_frequencies(omega)
    f = np.asarray(integrand)
    if f.shape[0] != w.size:
        raise ValueError(f"integrand: first axis {f.shape[0]} != {w.size} frequencies")
    if w.size < 3 or w.size % 2 == 0:
        raise ValueError(f"omega: need an odd number >= 3 of frequencies (the error estimate halves the grid), "
                         f"got {w.size}")
    fine = np.trapezoid(f, w, axis=0)
    coarse = np.trapezoid(f[::2], w[::2], axis=0)
    head = f[0] * w[0]
    # tail: |f| ~ c omega^-k over the last interval, int_w1^inf = f1 w1 / (k - 1) (k > 1); a slower
    # decay has no finite tail: f1 w1 is then kept as the (unreliable) estimate
    f0, f1 = np.abs(f[-2]), np.abs(f[-1])
    ratio = np.where((f0 > 0) & (f1 > 0), f0 / np.where(f1 > 0, f1, 1.0), 1.0)
    k = np.log(ratio) / np.log(w[-1] / w[-2])
    tail = np.where(k > 1.05, f[-1] * w[-1] / np.maximum(k - 1.0, 0.05), f[-1] * w[-1])
    return SpectralIntegral(fine + head + tail, np.abs(fine - coarse) / 3.0, tail, head)


# ------------------------------------------------------------------------------- outputs of the beam
_CSN_LOADS: dict = {}


def _csn_loads_function(sequence):
    """CasADi (theta, F, M) of one node (body) -> (csn loads (6), their Jacobian (6, 9))."""
    if sequence not in _CSN_LOADS:
        node = ca.SX.sym("node", 9)
        T = body_to_csn(node[0:3], sequence)
        loads = ca.vertcat(T @ node[3:6], T @ node[6:9])
        _CSN_LOADS[sequence] = ca.Function("csn_loads", [node], [loads, ca.jacobian(loads, node)])
    return _CSN_LOADS[sequence]


def _zero(rows, cols):
    return sp.csr_matrix((rows, cols))


def state_output(index, value, n_state, n_station) -> OutputMap:
    """The output ``value + dx[index]`` (one state).

    Parameters
    ----------
    index : int
        State index.
    value : float
        Output at the linearisation state.
    n_state : int
        Number of states.
    n_station : int
        Number of gust stations.

    Returns
    -------
    OutputMap
        The output.
    """
    C = sp.csr_matrix(([1.0], ([0], [int(index)])), shape=(1, n_state))
    return OutputMap(np.array([float(value)]), C, _zero(1, n_state), _zero(1, n_station))


def internal_load_output(x0, beam_index, n_station, sequence="surface") -> OutputMap:
    """The internal loads of every node in its csn frame, ``(n, 6)`` node-major in the order of
    :data:`LOAD_NAMES`: T(theta) F and T(theta) M of the beam states (body axes), linearised
    exactly (the rotation of the frame included). ``beam_index`` (n, 18): the flat indices of each
    node's beam states (``system.layout.beam``, or ``arange(18 n).reshape(n, 18)`` for the beam).

    Parameters
    ----------
    x0 : numpy.ndarray
        Linearisation state.
    beam_index : numpy.ndarray
        (n, 18) flat indices of each node's beam states.
    n_station : int
        Number of gust stations.
    sequence : str, optional
        Euler angle sequence of the jig frames.

    Returns
    -------
    OutputMap
        The (6 n) internal loads.
    """
    fun = _csn_loads_function(sequence)
    x0 = np.asarray(x0, float).ravel()
    beam = np.asarray(beam_index)
    st = STATE_BLOCKS
    y0, rows, cols, vals = [], [], [], []
    for i in range(beam.shape[0]):
        idx = np.concatenate([beam[i, st["theta"]], beam[i, st["F"]], beam[i, st["M"]]])
        val, jac = fun(x0[idx])
        y0.append(np.asarray(val).ravel())
        J = np.asarray(jac)
        r, c = np.nonzero(J)
        rows.append(6 * i + r)
        cols.append(idx[c])
        vals.append(J[r, c])
    n_state = x0.size
    C = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(6 * beam.shape[0], n_state))
    return OutputMap(np.concatenate(y0), C, _zero(C.shape[0], n_state), _zero(C.shape[0], n_station))


def lift_weights(node_positions, weight) -> np.ndarray:
    """(n,) load factor per unit section lift (N/m): 2 x the trapezoid weights of the undeformed
    beam over the weight ``weight`` (N); the lift of both half-wings is ``weights * weight @ lift``.

    Parameters
    ----------
    node_positions : array_like
        (n, 3) node positions (m).
    weight : float
        Aircraft weight (N).

    Returns
    -------
    numpy.ndarray
        (n,) weights (m/N).
    """
    if not (np.isfinite(weight) and weight > 0):
        raise ValueError(f"weight = {weight} N; allowed range (0, inf) N")
    r0 = np.asarray(node_positions, dtype=float)
    ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
    w = np.zeros(r0.shape[0])
    w[:-1] += 0.5 * ds
    w[1:] += 0.5 * ds
    return 2.0 * w / float(weight)


_LIFT_FUNCTIONS: dict = {}


def _lift_jacobians(system, tail=False):
    """CasADi (x, xdot, p, q) -> section lift (n), or the tail lift of a free-pitch system
    (``tail``), and its Jacobians in x, xdot, q (built once)."""
    key = (id(system), bool(tail))
    if key in _LIFT_FUNCTIONS and _LIFT_FUNCTIONS[key][0] is system:
        return _LIFT_FUNCTIONS[key][1]
    x, xd = ca.MX.sym("x", system.n_state), ca.MX.sym("xdot", system.n_state)
    p, q = ca.MX.sym("p", system.n_param), ca.MX.sym("q", system.n_forcing)
    lift = system._tail_lift(x, xd, p, q) if tail else system._loads(x, xd, p, q)[0]
    fun = ca.Function("lift_jacobians", [x, xd, p, q],
                      [lift, ca.jacobian(lift, x), ca.jacobian(lift, xd), ca.jacobian(lift, q)])
    _LIFT_FUNCTIONS[key] = (system, fun)
    return fun


def aeroelastic_outputs(system, p, q, x0, *, weight, sequence="surface") -> dict:
    """The outputs of an :class:`~wingmdao.aero.system.AeroelasticBeamSystem` about ``x0``:

    * ``loads`` (6 n): :func:`internal_load_output`;
    * ``root_bending_moment`` (1): M_x at the root node, body axes (N m; the key of ``wingmdao gust``);
    * ``load_factor`` (1): the lift of both half-wings (trapezoid of the section lift over the
      undeformed beam), plus the horizontal tail's lift of a free-pitch system, over ``weight`` (N);
      the apparent-mass lift enters through Cv;
    * ``tip_deflection`` (1): z of the tip node from its jig position (m).

    The gust stations are those of :func:`linear_gust_model`: the wing's, then the tail of a
    free-pitch system.

    Parameters
    ----------
    system : ResidualSystem
        The residual system.
    p, q : numpy.ndarray
        Packed parameters and forcing.
    x0 : numpy.ndarray
        Linearisation state.
    weight : float
        Aircraft weight (N).
    sequence : str, optional
        Euler angle sequence of the jig frames.

    Returns
    -------
    dict
        Name -> :class:`OutputMap`.
    """
    x0 = np.asarray(x0, float).ravel()
    p, q = np.asarray(p, float).ravel(), np.asarray(q, float).ravel()
    r0 = system.split_parameters(p)["node_positions"]
    wts = lift_weights(r0, weight)
    cols = gust_columns(layout(system.forcing_specs))
    lift, dlx, dlv, dlq = _lift_jacobians(system)(x0, np.zeros_like(x0), p, q)
    y0 = wts @ np.asarray(lift).ravel()
    Cx, Cv, D = (wts @ sp.csr_matrix(J) for J in (dlx, dlv, dlq))
    if getattr(system, "pitch", False):  # the tail lift: (wing + tail lift) / W, as the trim and wingmdao gust
        lt, dtx, dtv, dtq = _lift_jacobians(system, tail=True)(x0, np.zeros_like(x0), p, q)
        y0 = y0 + float(lt) / weight
        Cx, Cv, D = (a + sp.csr_matrix(J).toarray().ravel() / weight for a, J in ((Cx, dtx), (Cv, dtv), (D, dtq)))
    N, m = system.n_state, cols.size
    beam = system.layout.beam
    i_m, i_z = beam[0, STATE_BLOCKS["M"].start], beam[-1, STATE_BLOCKS["r"].start + 2]
    row = lambda a: sp.csr_matrix(np.asarray(a).reshape(1, -1))
    return {
        "loads": internal_load_output(x0, beam, m, sequence),
        "root_bending_moment": state_output(i_m, x0[i_m], N, m),
        "load_factor": OutputMap(np.array([y0]), row(Cx), row(Cv), row(np.asarray(D).ravel()[cols])),
        "tip_deflection": state_output(i_z, x0[i_z] - r0[-1, 2], N, m),
    }


# ------------------------------------------------------------------------------------------ stress
def stress_matrix(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar, section_to_csn=None) -> np.ndarray:
    """(8, 6) stresses (Pa) per unit csn load of one box section: rows the 4 corner axial stresses
    then the 4 flange-centre shears of :func:`wingmdao.stress.box_stress.box_stresses`, columns the
    loads of :data:`LOAD_NAMES`. Both are linear in the loads (Eq. 4.19, 4.22-4.25), so a column is
    the stresses of a unit load (checked: a load of 2 gives twice the stresses).

    Parameters
    ----------
    w, h : float
        Outer box width and height (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float
        Wall thicknesses (m).
    section_to_csn : array_like or None, optional
        (3, 3) rotation from the section's own axes to csn; None when they coincide.

    Returns
    -------
    numpy.ndarray
        (8, 6) stresses per unit load (Pa per N or N m).
    """
    def stresses(load):
        s = box_stresses(load[:3], load[3:], w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar,
                         section_to_csn)
        return np.array([float(v) for v in s["sigma_corner"]] + [float(v) for v in s["tau_cent"]])

    S = np.zeros((8, 6))
    for j, unit in enumerate(np.eye(6)):
        S[:, j] = stresses(unit)
        if not np.allclose(stresses(2.0 * unit), 2.0 * S[:, j], rtol=1e-12, atol=1e-12 * np.max(np.abs(S[:, j]))):
            raise RuntimeError("box_stresses: the corner and flange-centre stresses are not linear in the loads")
    return S


def stress_matrices(width, height, walls, section_to_csn=None) -> np.ndarray:
    """(n, 8, 6) :func:`stress_matrix` of every box station.

    Parameters
    ----------
    width, height : array_like
        (n,) m: box outer width and height of each station.
    walls : array_like
        (n, 4) m: upper skin, lower skin, front spar and rear spar thickness of each station.
    section_to_csn : array_like, optional
        (n, 3, 3) rotation of each section to its csn frame; None: aligned.

    Returns
    -------
    ndarray
        (n, 8, 6) stresses (Pa) per unit csn load.
    """
    t = np.asarray(walls, dtype=float)
    return np.stack([stress_matrix(width[i], height[i], *t[i], None if section_to_csn is None else section_to_csn[i])
                     for i in range(t.shape[0])])


def stress_response(load_response, matrices) -> np.ndarray:
    """Stress transfer functions (n_freq, n, 8) from the csn load transfer functions (n_freq, 6 n)
    and the per-station :func:`stress_matrix` (n, 8, 6).

    Parameters
    ----------
    load_response : numpy.ndarray
        (n_freq, 6 n) csn load transfer functions.
    matrices : numpy.ndarray
        (n, 8, 6) stress matrices.

    Returns
    -------
    numpy.ndarray
        (n_freq, n, 8) stress transfer functions (Pa per m/s).
    """
    H = np.asarray(load_response)
    S = np.asarray(matrices)
    n = S.shape[0]
    if H.shape[-1] != 6 * n:
        raise ValueError(f"load_response: last axis {H.shape[-1]} != 6 x {n} stations")
    return np.einsum("sij,fsj->fsi", S, H.reshape(H.shape[0], n, 6))
