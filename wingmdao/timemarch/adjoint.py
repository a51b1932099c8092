"""Generic discrete tangent and adjoint of the BDF time march (Eq. 3.9-3.11).

Written once for any :class:`~wingmdao.timemarch.system.ResidualSystem`. The stacked
equations of a history are ``G_n(x_0..x_n, p, q_n) = 0``, n = 0..N (see ``bdf.py``). Their
Jacobian with respect to the stacked states is block lower-triangular with bandwidth 2::

    dG_n/dx_n     = A_n   = dR_n/dx + alpha_0(n)/dt dR_n/dxdot
    dG_n/dx_{n-k} = B_n,k =           alpha_k(n)/dt dR_n/dxdot      (k = 1, 2)

(step 0: ``A_0 = dR_0/dx`` for a static start, ``I`` for a given state; no B blocks). The
tangent sweep solves ``J dx = r`` forward in time; the adjoint sweep solves ``J^T lam = g``
backward in time with transposed factors (the Jacobian is not symmetric). The gradient of
a functional f(x(p, q), p, q) is then (OpenMDAO sign convention, ``lam = J^-T df/dx``)::

    df/dp   = partial f/partial p   - sum_n lam_n^T dR_n/dp
    df/dq_n = partial f/partial q_n - lam_n^T dR_n/dq_n

The dissertation's multiplier (Eq. 3.9-3.11) is ``lambda_n = -lam_n / delta_n``. The full
derivation is in ``docs/time-marching.md``.
"""

from __future__ import annotations

import numpy as np
from openmdao.core.analysis_error import AnalysisError
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.timemarch.bdf import bdf_coefficients, state_rates, time_step
from wingmdao.timemarch.newton import DENSE_MAX, PERMC_SPEC, factor
from wingmdao.timemarch import lu_orders, static_lu
from wingmdao.utils.digest import ArrayStamp
from wingmdao.utils.sparse import scatter_matrix


#: Accepted componentwise backward error of a refined static-pivot solve (one refinement gives
#: ~1e-16; SuperLU's unrefined solves reach 1e-11 to 2e-9 on the 20-node beam).
STATIC_LU_TOL = 1e-12

#: Pivot orders a sweep (of a checkpoint segment) may add (:meth:`LinearizedHistory._repivot`) before the steps whose
#: static-pivot solve fails go to SuperLU one by one.
MAX_REPIVOTS = 4


def block_bytes_per_step(system) -> float:
    """Bytes of Jacobian blocks a :class:`LinearizedHistory` keeps per time step with full storage:
    the nonzeros of dR/dx, dR/dxdot, dR/dp, dR/dq, the Newton matrix (at most those of dR/dx and
    dR/dxdot) and dR/dxdot once more (its used entries), float64.

    Parameters
    ----------
    system : ResidualSystem
        The system (its ``jacobian_patterns()``).

    Returns
    -------
    float
        Bytes per time step.
    """
    nnz = {k: v[0].size for k, v in system.jacobian_patterns().items()}
    return 8.0 * (2 * (nnz["x"] + nnz["xdot"]) + nnz["xdot"] + nnz["p"] + nnz["q"])


def checkpoint_interval(system, n_time: int, budget_bytes: float):
    """Segment length (steps) that keeps the Jacobian blocks within ``budget_bytes``, or None
    when the whole history fits (full storage).

    Parameters
    ----------
    system : ResidualSystem
        The system (its ``jacobian_patterns()``).
    n_time : int
        Number of time steps of the history.
    budget_bytes : float
        Memory allowed for the Jacobian blocks (bytes).

    Returns
    -------
    int or None
        Steps per segment (``checkpoint_every`` of :class:`LinearizedHistory`), or None.
    """
    per_step = block_bytes_per_step(system)
    if n_time * per_step <= budget_bytes:
        return None
    return int(max(1, min(n_time, budget_bytes // per_step)))


class _Blocks:
    """Jacobian nonzeros of the steps ``off .. off + len - 1`` of a history; the sweeps loop over
    the steps ``lo .. hi - 1`` (the adjoint sweep reads two steps past ``hi``)."""

    __slots__ = ("off", "lo", "hi", "jx", "jxd", "jp", "jq", "m_data", "factors", "same")

    def row(self, n):
        return n - self.off

    def xd(self, n, used):
        """The used nonzeros of dR/dxdot at step n."""
        return self.jxd[n - self.off, used]


class LinearizedHistory:
    """Per-step Jacobian blocks of a converged BDF history, with tangent and adjoint sweeps.

    Parameters
    ----------
    system : ResidualSystem
        The marched system.
    time : array_like
        (n_time,) uniform time grid (s).
    states : array_like
        (n_time, n_state) converged state history.
    p : array_like
        (n_param,) parameters.
    forcing : array_like
        (n_time, n_forcing) forcing history.
    initial : {"static", "state"}, optional
        How step 0 was defined: a static equilibrium, or a given initial state
        (``x_0 - x_init``).
    store_factors : bool or "auto", optional
        Keep the LU factors of every ``A_n`` (fast repeated sweeps) or refactor
        in each sweep (memory ~ one factor). ``"auto"`` keeps them when
        ``n_time * n_state <= auto_limit``: SuperLU reserves ~170 kB per factor of a 360-state
        beam-like system (8x its nonzeros), and touching that memory made a stored-factor sweep
        5x slower than refactoring (measured, see ``docs/time-marching.md``).
    auto_limit : int, optional
        The ``n_time * n_state`` bound of ``store_factors="auto"``.
    lu : {"static", "superlu"}, optional
        ``"static"`` (default) factors the steps n >= 1 with one pivot
        order (SuperLU's for the middle step) in the compiled C kernel of
        :mod:`wingmdao.timemarch.static_lu` (symbolic analysis once per pattern and pivot order,
        no code generation), one C call per sweep of a stretch of steps; each solve is checked by
        its backward error and refined; at a step whose solve still fails the sweep takes the
        pivot order of that step's matrix and goes on with it (at most :data:`MAX_REPIVOTS` per
        sweep), else that step is redone with SuperLU.
        Without the kernel (``WINGMDAO_JIT=0``, no gcc) it is SuperLU (``lu_method`` tells which
        is used). ``"superlu"``: SuperLU for every step (docs/time-marching.md, "The static-pivot
        LU").
    checkpoint_every : int, optional
        None (default) keeps the Jacobian nonzeros of every step (the arrays
        ``jx, jxd, m_data``; ``jp, jq`` only once something needs them: the gradient uses the
        system's reverse-mode products ``input_vjp_history`` instead when it has them, the
        forward products and declared partials evaluate them; ~170 kB per step of a 20-node
        beam with all of them, ~70 kB without dR/dp, dR/dq). An integer k keeps
        only the states (``states`` is the whole converged history, so every step is a
        checkpoint) and re-evaluates the Jacobians of k steps at a time in every sweep and
        product: memory ~ k steps of blocks, one extra Jacobian evaluation per step and sweep.
        The sweeps are the same operations on the same values, so the results agree with the
        full storage to round-off (only sums over time are grouped by segment). Segments evaluate
        dR/dx, dR/dxdot only; the adjoint sweep forms ``param_product`` and ``forcing_product``
        per segment by the system's reverse-mode products (dR/dp, dR/dq of a segment are evaluated
        only for the forward products, or when the system has no such products).
    copy_states : bool, optional
        Copy ``states``; False keeps the caller's array, which must then not change while this
        linearization is in use.
    keep_forcing_product : bool, optional
        False: the checkpointed adjoint sweep does not keep ``forcing_product(lam)`` for a later
        call (no derivatives with respect to the forcing are needed).

    Notes
    -----
    Identical consecutive ``A_n`` (linear systems) share one factorization. Entries of the
    Jacobian pattern that are zero at every step (of this and of every earlier history of the
    same system object) are dropped from ``A_n`` before factoring
    (CasADi patterns are structural: 64 % of the 20-node beam's entries are zero for an
    initially straight beam; SuperLU is 2.5x faster without them).
    """

    def __init__(self, system, time, states, p, forcing, *, initial="static",
                 store_factors="auto", auto_limit=100_000, lu="static", checkpoint_every=None,
                 copy_states=True, keep_forcing_product=True):
        t = np.asarray(time, dtype=float)
        self.dt = time_step(t)
        self.system = system
        self.initial = initial
        if initial not in ("static", "state"):
            raise ValueError(f'initial must be "static" or "state", got {initial!r}')
        if lu not in ("superlu", "static"):
            raise ValueError(f'lu must be "superlu" or "static", got {lu!r}')
        self.n_time, self.n_state = t.size, system.n_state
        # the linearization point: a copy of the states, or (copy_states=False) the caller's
        # array itself, which the caller must not change while this linearization is in use
        X = (np.array if copy_states else np.asarray)(states, dtype=float).reshape(self.n_time, self.n_state)
        self._X = self.states = X
        #: False: the checkpointed adjoint sweep does not keep ``forcing_product(lam)`` (n_time x
        #: n_forcing) for a later call (the caller needs no derivatives with respect to the forcing)
        self.keep_forcing_product = bool(keep_forcing_product)
        self._Q = self.forcing = np.array(forcing, dtype=float).reshape(self.n_time, system.n_forcing)
        self._p = np.array(p, dtype=float).reshape(system.n_param)
        self.patterns = system.jacobian_patterns()
        self._lib = static_lu.kernel()    # the compiled C kernel (assembly, products, static LU) or None
        # coefficients alpha_k(n)/dt; row 0 all zero
        self.coef = np.array([bdf_coefficients(n) for n in range(self.n_time)])
        if self.n_time > 1:
            self.coef /= self.dt
        if checkpoint_every is not None:
            k = int(checkpoint_every)
            if k < 1:
                raise ValueError(f"checkpoint_every must be an integer >= 1 (steps), got {checkpoint_every!r}")
            checkpoint_every = None if k >= self.n_time else k
        self.checkpoint_every = checkpoint_every
        self._full = self._Xdot = None
        self._jp = self._jq = None        # dR/dp, dR/dq of full storage (evaluated at first use)
        # full storage keeps the rates; checkpointed sweeps recompute them per segment
        self._Xdot = self._rates(0, self.n_time) if checkpoint_every is None else None
        full = None
        if checkpoint_every is None:
            data = self._raw(0, self.n_time, state_only=True)
            seen = self._seen_nonzeros(data)
            contiguous = data["x"].flags.c_contiguous and data["xdot"].flags.c_contiguous
            if self._lib is not None and seen is not None and contiguous:
                # the pattern of the earlier histories, checked in the assembly's pass over the
                # Jacobians (one pass over ~25 MB instead of two, 20-node beam x 500 steps)
                x_nz, d_nz = seen[0].copy(), seen[1].copy()
                self._build_newton_pattern(x_nz, d_nz)
                full = self._make_blocks(0, self.n_time, self.n_time, data, check=True)
                if full.factors is not None:        # new nonzeros: grow the pattern, assemble again
                    x_nz, d_nz = x_nz | full.factors[0], d_nz | full.factors[1]
                    full = None
            elif self._lib is not None:
                x_nz, d_nz = (static_lu.nonzero_columns(self._lib, data[k]) for k in ("x", "xdot"))
            else:
                x_nz, d_nz = np.any(data["x"] != 0.0, axis=0), np.any(data["xdot"] != 0.0, axis=0)
        else:
            x_nz, d_nz, same = self._scan()
        if full is None:
            self._build_newton_pattern(x_nz, d_nz)
        if checkpoint_every is None:
            self._full = full if full is not None else self._make_blocks(0, self.n_time, self.n_time, data)
            self.jx, self.jxd = data["x"], data["xdot"]
            self._jp, self._jq = data.get("p"), data.get("q")     # None: evaluated at first use
            self.m_data = self._full.m_data
            # steps with the same Newton matrix as the step before share one factorization
            same = self._full.same
            if same is None:
                same = np.zeros(self.n_time, dtype=bool)
                same[1:] = np.all(self.m_data[1:] == self.m_data[:-1], axis=1)
        self._store = store_factors
        self._auto_limit = int(auto_limit)
        self._factors = {}
        self._keep = None
        self._rep = np.maximum.accumulate(np.where(same, 0, np.arange(self.n_time)))
        self.lu_method = lu if self.n_time > 1 and self._lib is not None else "superlu"
        self._static = None           # the StaticPivotLU once made
        self._same = None             # uint8: A_n == A_{n-1} (the kernel's reuse of factors)
        #: kernel counts: refined steps, steps solved by SuperLU after a failed static-pivot solve,
        #: factored matrices, and pivot orders taken from a failing step (``_repivot``)
        self.static_stats = {"refined": 0, "fallback": 0, "factored": 0, "repivoted": 0}
        # (stamp of lam, sum_n dR_n/dp^T lam_n, dR_n/dq_n^T lam_n) of the last sweep (a stamp,
        # wingmdao.utils.digest: a digest, not a copy, of a long history's lam)
        self._adjoint_cache = None

    # ------------------------------------------------------------------ blocks
    def _rates(self, lo, hi):
        """BDF rates of the steps lo..hi-1 (Eq. 3.5, as ``state_rates`` of the whole history)."""
        if self._Xdot is not None:
            return self._Xdot[lo:hi]
        if self.n_time == 1:
            return np.zeros_like(self._X)
        a = max(lo - 2, 0)     # rows past the first two of a slice are BDF2 rates
        return state_rates(self._X[a:hi], self.dt)[lo - a:]

    def _raw(self, lo, hi, state_only=False):
        """The four Jacobians' nonzeros at the steps lo..hi-1 (step 0 of a given state: none);
        ``state_only``: dR/dx and dR/dxdot (``system.state_jacobian_history``; "p", "q" only if
        the system returns them anyway)."""
        args = (self._X[lo:hi], self._rates(lo, hi), self._p, self._Q[lo:hi])
        data = dict(self.system.state_jacobian_history(*args) if state_only else self.system.jacobian_history(*args))
        if self.initial == "state" and lo == 0:   # step 0 is x_0 - x_init: identity, no p or q
            for v in data.values():
                v[0] = 0.0
        return data

    def _input_jacobians(self):
        """dR/dp, dR/dq of every step (full storage), evaluated at first use: the gradient needs
        only their products with the adjoint (:meth:`param_product`, reverse mode), the forward
        products and declared partials need them."""
        if self._full is None:
            raise AttributeError("dR/dp, dR/dq of every step are kept with full storage only (checkpoint_every=None)")
        if self._jp is None:
            data = dict(self.system.input_jacobian_history(self._X, self._Xdot, self._p, self._Q))
            if self.initial == "state":
                for v in data.values():
                    v[0] = 0.0
            self._jp, self._jq = data["p"], data["q"]
            self._full.jp, self._full.jq = self._jp, self._jq
        return self._jp, self._jq

    @property
    def jp(self) -> np.ndarray:
        """Nonzeros of dR/dp at every step (n_time, nnz), full storage (evaluated at first use)."""
        return self._input_jacobians()[0]

    @property
    def jq(self) -> np.ndarray:
        """Nonzeros of dR/dq at every step (n_time, nnz), full storage (evaluated at first use)."""
        return self._input_jacobians()[1]

    def _block_inputs(self, blk):
        """``(jp, jq)`` of a block, evaluated at first use (a checkpoint segment's: its steps)."""
        if blk.jp is None:
            if blk is self._full:
                self._input_jacobians()
            else:
                lo, stop = blk.off, blk.off + blk.jx.shape[0]
                data = dict(self.system.input_jacobian_history(self._X[lo:stop], self._rates(lo, stop), self._p,
                                                               self._Q[lo:stop]))
                if self.initial == "state" and lo == 0:
                    for v in data.values():
                        v[0] = 0.0
                blk.jp, blk.jq = data["p"], data["q"]
        return blk.jp, blk.jq

    def _segment_vjp(self, blk, lam):
        """``(sum dR_n/dp^T lam_n, dR_n/dq_n^T lam_n)`` over the steps ``blk.lo .. blk.hi - 1`` by the
        system's reverse-mode products, or None when it has none (checkpointed sweeps)."""
        lo, hi = blk.lo, blk.hi
        L = lam[lo:hi]
        if self.initial == "state" and lo == 0:
            L = L.copy()
            L[0] = 0.0
        return self.system.input_vjp_history(self._X[lo:hi], self._rates(lo, hi), self._p, self._Q[lo:hi], L)

    def _scan(self):
        """Checkpointed mode: one pass over the history in segments for the entries that are
        nonzero at some step and the steps whose Newton matrix equals the step before's (same
        dR/dx, dR/dxdot and alpha_0)."""
        k, N = self.checkpoint_every, self.n_time
        x_nz = d_nz = None
        same = np.zeros(N, dtype=bool)
        prev = None
        for lo in range(0, N, k):
            d = self._raw(lo, min(lo + k, N), state_only=True)
            jx, jxd = d["x"], d["xdot"]
            if x_nz is None:
                x_nz, d_nz = np.zeros(jx.shape[1], dtype=bool), np.zeros(jxd.shape[1], dtype=bool)
            x_nz |= np.any(jx != 0.0, axis=0)
            d_nz |= np.any(jxd != 0.0, axis=0)
            px = np.vstack([prev[0], jx]) if prev is not None else jx
            pd = np.vstack([prev[1], jxd]) if prev is not None else jxd
            s = np.all(px[1:] == px[:-1], axis=1) & np.all(pd[1:] == pd[:-1], axis=1)
            first = lo if prev is not None else lo + 1
            same[first:lo + jx.shape[0]] = s
            prev = (jx[-1:], jxd[-1:])
        same[1:] &= self.coef[1:, 0] == self.coef[:-1, 0]
        same[0] = False
        return x_nz, d_nz, same

    def _seen_nonzeros(self, data):
        """``(x_nz, d_nz)`` of the earlier histories of this system when they fit ``data``."""
        seen = getattr(self.system, "_linearized_history_nonzeros", None)
        if seen is not None and seen[0].shape == data["x"].shape[1:] and seen[1].shape == data["xdot"].shape[1:]:
            return seen
        return None

    def _make_blocks(self, lo, hi, stop, data=None, check=False) -> _Blocks:
        """Blocks of the steps lo..stop-1 (sweeps over lo..hi-1). ``check`` (kernel only): look
        for nonzeros of dR/dx, dR/dxdot outside the pattern in the same pass; if any, the block's
        ``factors`` holds their flags ``(x, xdot)`` (the block is then to be remade)."""
        if data is None:
            data = self._raw(lo, stop, state_only=True)
        b = _Blocks()
        b.off, b.lo, b.hi = lo, lo, hi
        b.jx, b.jxd, b.jp, b.jq = data["x"], data["xdot"], data.get("p"), data.get("q")
        m = stop - lo
        b.m_data = np.empty((m, self.m_rows.size))
        lib = self._lib
        if lib is not None and b.jx.flags.c_contiguous and b.jxd.flags.c_contiguous:
            sx, dx, sd, dd = self._assembly
            c = np.ascontiguousarray(self.coef[lo:stop, 0])
            same = np.zeros(m, dtype=np.uint8)     # row t equals row t - 1 (as NumPy's ==)
            flags = []
            if check:
                flags = [np.ascontiguousarray(self._x_nz, dtype=np.uint8), np.ascontiguousarray(self._d_nz, dtype=np.uint8),
                         np.zeros(self._x_nz.size, dtype=np.uint8), np.zeros(self._d_nz.size, dtype=np.uint8)]
            found = lib.assemble_newton(m, b.jx.ctypes.data, b.jx.shape[1], sx.ctypes.data, dx.ctypes.data, sx.size,
                                        b.jxd.ctypes.data, b.jxd.shape[1], sd.ctypes.data, dd.ctypes.data, sd.size,
                                        c.ctypes.data, b.m_data.ctypes.data, b.m_data.shape[1], same.ctypes.data,
                                        *(f.ctypes.data for f in flags), *([None] * (4 - len(flags))))
            b.same = same.view(bool)
            if found:
                b.factors = (flags[2].view(bool), flags[3].view(bool))
                return b
        else:
            b.same = None
            slot, pos_x, pos_d = self._slot, self._pos_x, self._pos_d
            b.m_data[:] = 0.0
            b.m_data[:, slot[pos_x[self._x_nz]]] = b.jx[:, self._x_nz]
            b.m_data[:, slot[pos_d[self._d_nz]]] += self.coef[lo:stop, :1] * b.jxd[:, self._d_nz]
        if self.initial == "state" and lo == 0:
            b.m_data[0, self._slot[self._pos_i]] = 1.0
            if b.same is not None and m > 1:
                b.same[1] = np.array_equal(b.m_data[1], b.m_data[0])
        b.factors = None
        return b

    def _blocks(self, reverse=False):
        """The blocks of the whole history, one segment at a time (all at once with full storage);
        in reverse order for the adjoint sweep, each with the two steps after it."""
        if self._full is not None:
            yield self._full
            return
        k, N = self.checkpoint_every, self.n_time
        starts = range(0, N, k)
        for lo in (reversed(starts) if reverse else starts):
            hi = min(lo + k, N)
            yield self._make_blocks(lo, hi, min(hi + 2, N) if reverse else hi)

    def _block_at(self, n) -> _Blocks:
        if self._full is not None:
            return self._full
        return self._make_blocks(n, n + 1, n + 1)

    # ------------------------------------------------------------------ structure
    def _newton_pattern(self):
        """Union pattern of dR/dx, dR/dxdot and the diagonal (CSC order), with the slots of each
        Jacobian's nonzeros in it and the scatter matrices; cached on the system (fixed there)."""
        cached = getattr(self.system, "_linearized_history_pattern", None)
        if cached is not None:
            return cached
        n = self.n_state
        rx, cx, _ = self.patterns["x"]
        rd, cd, _ = self.patterns["xdot"]
        eye = np.arange(n)
        keys = np.unique(np.concatenate([cx * n + rx, cd * n + rd, eye * n + eye]))  # CSC order
        rows, cols = keys % n, keys // n
        pat = {
            "rows": rows, "cols": cols, "indptr": np.searchsorted(cols, np.arange(n + 1)),
            "pos_x": np.searchsorted(keys, cx * n + rx), "pos_d": np.searchsorted(keys, cd * n + rd),
            "pos_i": np.searchsorted(keys, eye * n + eye),
            "scatter_rows": {k: scatter_matrix(self.patterns[k][0], n) for k in self.patterns},
            "scatter_cols": {k: scatter_matrix(self.patterns[k][1], self.patterns[k][2][1]) for k in self.patterns},
        }
        try:
            self.system._linearized_history_pattern = pat
        except AttributeError:      # a system that takes no attributes: recompute next time
            pass
        return pat

    def _build_newton_pattern(self, x_nz, d_nz):
        """The pattern of ``A_n``: entries of dR/dx, dR/dxdot that are nonzero at some step."""
        n = self.n_state
        pat = self._newton_pattern()
        self.a_rows, self.a_cols, self.a_indptr = pat["rows"], pat["cols"], pat["indptr"]
        pos_x, pos_d, pos_i = pat["pos_x"], pat["pos_d"], pat["pos_i"]
        # ... or at some step of an earlier history of this system: the pattern only grows, so a
        # design change that makes an entry exactly zero (e.g. a symmetric section's couplings)
        # does not make a new pattern (a new static-pivot LU to generate and compile)
        seen = getattr(self.system, "_linearized_history_nonzeros", None)
        if seen is not None and seen[0].shape == x_nz.shape and seen[1].shape == d_nz.shape:
            x_nz |= seen[0]
            d_nz |= seen[1]
        try:
            self.system._linearized_history_nonzeros = (x_nz.copy(), d_nz.copy())
        except AttributeError:
            pass
        used = np.zeros(self.a_rows.size, dtype=bool)
        used[pos_x[x_nz]] = True
        used[pos_d[d_nz]] = True
        if self.initial == "state":
            used[pos_i] = True
        self._slot = np.cumsum(used) - 1            # position of a used union slot in m_data
        self._used = used
        self._x_nz, self._d_nz = x_nz, d_nz
        self._pos_x, self._pos_d, self._pos_i = pos_x, pos_d, pos_i
        self.m_rows = self.a_rows[used]
        self.m_cols = self.a_cols[used]
        self.m_indptr = np.searchsorted(self.m_cols, np.arange(n + 1))
        # dR/dxdot on its used entries, for the history products of the sweeps
        rd, cd, _ = self.patterns["xdot"]
        self._xd_rows, self._xd_cols = rd[d_nz], cd[d_nz]
        self._d_src = np.flatnonzero(d_nz)
        # the kernel's assembly of A_n: source columns of dR/dx, dR/dxdot and their slots in m_data
        i32 = np.int32
        self._assembly = tuple(np.ascontiguousarray(v, dtype=i32) for v in (
            np.flatnonzero(x_nz), self._slot[pos_x[x_nz]], self._d_src, self._slot[pos_d[d_nz]]))
        if "idx32" not in pat:              # the Jacobian patterns as the kernel's int32 (fixed per system)
            pat["idx32"] = {k: (np.ascontiguousarray(self.patterns[k][0], dtype=i32),
                                np.ascontiguousarray(self.patterns[k][1], dtype=i32)) for k in self.patterns}
        self._idx32 = pat["idx32"]
        self._scatter_rows = pat["scatter_rows"]
        self._scatter_cols = pat["scatter_cols"]
        self._a_data = None
        self._csc = None

    @property
    def a_data(self) -> np.ndarray:
        """Nonzeros of every ``A_n`` on the full union pattern ``a_rows, a_indptr`` (n_time, nnz);
        full storage only."""
        if self._full is None:
            raise ValueError("a_data needs the full storage (checkpoint_every=None)")
        if self._a_data is None:
            self._a_data = np.zeros((self.n_time, self.a_rows.size))
            self._a_data[:, self._used] = self.m_data
        return self._a_data

    def newton_matrix(self, n, blk=None) -> sp.csc_matrix:
        """``A_n = dR_n/dx + alpha_0(n)/dt dR_n/dxdot`` (Eq. 3.7) as CSC.

        Parameters
        ----------
        n : int
            Time step index.
        blk : object, optional
            The internal block of stored Jacobians holding step ``n``; None: looked up.

        Returns
        -------
        scipy.sparse.csc_matrix
            (n_state, n_state) Newton matrix ``A_n``.
        """
        blk = blk if blk is not None else self._block_at(n)
        return sp.csc_matrix((blk.m_data[blk.row(n)], self.m_rows, self.m_indptr),
                             shape=(self.n_state,) * 2)

    def _lu(self, n, blk=None):
        """SuperLU factors of ``A_n``, shared by a run of identical matrices (``_rep``)."""
        r = int(self._rep[n])
        lu = self._factors.get(r)
        if lu is None:
            try:
                lu = self._factor_step(n, blk)    # A_n equals A_r
            except RuntimeError as exc:
                raise AnalysisError(f"linearized step {n}: singular Newton matrix ({exc})") from exc
            self._factors[r] = lu
        return lu

    def _factor_step(self, n, blk=None):
        """SuperLU factors of ``A_n`` (natural column order, as ``newton.factor``) from one CSC
        matrix made once per history whose values are overwritten: building and checking a new
        CSC matrix (twice: ``newton_matrix`` and ``factor``'s copy) cost as much as SuperLU's
        factorization itself (0.75 against 0.27-0.45 ms per step, 20-node beam)."""
        if self.n_state <= DENSE_MAX:
            return factor(self.newton_matrix(n, blk))
        blk = blk if blk is not None else self._block_at(n)
        csc = self._csc
        if csc is None:
            csc = self._csc = sp.csc_matrix((np.zeros(self.m_rows.size), self.m_rows, self.m_indptr),
                                            shape=(self.n_state,) * 2)
            csc.has_canonical_format = True    # rows sorted and unique per column (CSC order)
        csc.data[:] = blk.m_data[blk.row(n)]
        return spla.splu(csc, permc_spec=PERMC_SPEC)     # SuperLU copies the values

    def _static_lu(self):
        """The :class:`~wingmdao.timemarch.static_lu.StaticPivotLU` of this history (pivot order of
        the middle step, column order and leading diagonal pivots of
        :func:`wingmdao.timemarch.lu_orders.adjoint_lu_order`) when ``lu_method == "static"``, else
        None (also when the reference step cannot be factored: then SuperLU from here on)."""
        if self._static is None and self.lu_method == "static":
            mid = self.n_time // 2
            slu = self._static_for(mid, self._block_at(mid))
            if slu is None:
                self.lu_method = "superlu"
                return None
            self._static = slu
        return self._static

    def _static_for(self, n, blk):
        """The :class:`~wingmdao.timemarch.static_lu.StaticPivotLU` with the pivot order of ``A_n``
        (column order and leading diagonal pivots of :func:`lu_orders.adjoint_lu_order`, partial
        pivoting throughout when that has a zero diagonal pivot), or None when ``A_n`` cannot be
        factored."""
        a_ref = blk.m_data[blk.row(n)]
        order, diagonal = lu_orders.adjoint_lu_order(self.system)
        slu = static_lu.for_pattern(self.n_state, self.m_rows, self.m_indptr, a_ref, order, diagonal)
        if slu is None and diagonal:
            slu = static_lu.for_pattern(self.n_state, self.m_rows, self.m_indptr, a_ref,
                                        lu_orders.system_lu_column_order(self.system))
        return slu

    def _repivot(self, n, blk, tried):
        """The static-pivot LU with the pivot order of the failing step ``n``'s own matrix, for the
        sweep to redo that step and go on with (the steps near ``n`` resemble it); None when ``n``
        was already tried in this sweep (``tried``, updated), after :data:`MAX_REPIVOTS` new orders
        or when ``A_n`` cannot be factored (the caller then solves step ``n`` with SuperLU).

        The pivots of one reference step fail where an entry that the deformation makes large at
        the reference vanishes at another step (the wing tip's axial force column of the PEGASUS
        stick model before the gust reaches it: a pivot of 3e-18 against 4e-4 mid-gust)."""
        if n in tried or len(tried) >= MAX_REPIVOTS:
            return None
        tried.add(n)
        slu = self._static_for(n, blk)
        if slu is not None:
            self.static_stats["repivoted"] += 1
        return slu

    def _sweep_data(self, slu, blk):
        """The kernel's view of the steps of ``blk`` (kept on the block: one per block)."""
        if blk.factors is None:
            if self._same is None:
                self._same = np.zeros(self.n_time, dtype=np.uint8)
                self._same[1:] = self._rep[1:] == self._rep[:-1]
            blk.factors = slu.sweep_data(self.n_time, blk.off, blk.m_data, blk.jxd, self._d_src, self._xd_rows,
                                         self._xd_cols, self.coef, self._same, STATIC_LU_TOL)
        return blk.factors

    def _solve_step(self, blk, n, b, trans="N"):
        """``A_n x = b`` (or ``A_n^T x = b``) with the step's SuperLU factors."""
        return self._lu(n, blk).solve(b, trans=trans)

    def _fallback(self, n, b, trans, blk):
        """SuperLU solve of a step whose static-pivot solve failed (after refinement)."""
        self.static_stats["fallback"] += 1
        x = self._lu(n, blk).solve(b, trans=trans)
        if not self._keep_factors(None):
            self._factors.pop(int(self._rep[n]), None)
        return x

    def _keep_factors(self, lu):
        """Whether factors are kept between sweeps (decided once)."""
        if self._keep is None:
            if self._store == "auto":
                self._keep = self.n_time * self.n_state <= self._auto_limit
            else:
                self._keep = bool(self._store)
        return self._keep

    def _release(self, n, current):
        """Free the factor of step ``n`` once the sweep has moved on to ``current``."""
        r = int(self._rep[n])
        lu = self._factors.get(r)
        if lu is not None and r != self._rep[current] and not self._keep_factors(lu):
            del self._factors[r]

    # ------------------------------------------------------------------ products
    def _rate_product(self, blk, n, vec):
        """``dR_n/dxdot @ vec``."""
        return np.bincount(self._xd_rows, blk.xd(n, self._d_src) * vec[self._xd_cols], minlength=self.n_state)

    def _rate_product_t(self, blk, n, vec):
        """``dR_n/dxdot^T @ vec``."""
        return np.bincount(self._xd_cols, blk.xd(n, self._d_src) * vec[self._xd_rows], minlength=self.n_state)

    def _hist_product(self, key, data, vec, transpose=False):
        """Per step ``M_n @ vec_n`` (or ``M_n^T @ vec_n``) of the Jacobian ``key``, rows of ``data``."""
        rows, cols, shape = self.patterns[key]
        if self._lib is not None and data.flags.c_contiguous:
            r32, c32 = self._idx32[key]
            out_idx, in_idx, width = (c32, r32, shape[1]) if transpose else (r32, c32, shape[0])
            return static_lu.hist_product(self._lib, data, out_idx, in_idx, vec, width)
        if transpose:
            return np.asarray((data * vec[:, rows]) @ self._scatter_cols[key])
        return np.asarray((data * vec[:, cols]) @ self._scatter_rows[key])

    def _per_block(self, key, vec, transpose=False, width=None):
        """``_hist_product`` of the Jacobian ``key`` with the rows of ``vec``, block by block."""
        out = np.zeros((self.n_time, self.n_state if width is None else width))
        attr = {"x": "jx", "xdot": "jxd", "p": "jp", "q": "jq"}[key]
        for blk in self._blocks():
            lo, hi = blk.lo, blk.hi
            if key in ("p", "q"):
                self._block_inputs(blk)
            out[lo:hi] = self._hist_product(key, getattr(blk, attr)[:hi - lo], vec[lo:hi], transpose)
        return out

    def apply(self, dx) -> np.ndarray:
        """``J dx`` for a state perturbation history (n_time, n_state).

        Parameters
        ----------
        dx : numpy.ndarray
            (n_time, n_state) state perturbation history.

        Returns
        -------
        numpy.ndarray
            (n_time, n_state) residual perturbation history.
        """
        dx = np.asarray(dx, dtype=float).reshape(self.n_time, self.n_state)
        rates = np.zeros_like(dx)
        for k in range(3):
            rates[k:] += self.coef[k:, k:k + 1] * dx[:self.n_time - k]
        out = np.zeros_like(dx)
        for blk in self._blocks():
            lo, hi = blk.lo, blk.hi
            out[lo:hi] = (self._hist_product("x", blk.jx[:hi - lo], dx[lo:hi])
                          + self._hist_product("xdot", blk.jxd[:hi - lo], rates[lo:hi]))
        if self.initial == "state":
            out[0] = dx[0]
        return out

    def apply_transpose(self, lam) -> np.ndarray:
        """``J^T lam`` for a residual-weight history (n_time, n_state).

        Parameters
        ----------
        lam : numpy.ndarray
            (n_time, n_state) residual-weight history.

        Returns
        -------
        numpy.ndarray
            (n_time, n_state) weights on the states.
        """
        lam = np.asarray(lam, dtype=float).reshape(self.n_time, self.n_state)
        out, w = np.zeros_like(lam), np.zeros_like(lam)
        for blk in self._blocks():
            lo, hi = blk.lo, blk.hi
            out[lo:hi] = self._hist_product("x", blk.jx[:hi - lo], lam[lo:hi], transpose=True)
            w[lo:hi] = self._hist_product("xdot", blk.jxd[:hi - lo], lam[lo:hi], transpose=True)
        for k in range(3):
            out[:self.n_time - k] += self.coef[k:, k:k + 1] * w[k:]
        if self.initial == "state":
            out[0] += lam[0]
        return out

    def param_apply(self, dp) -> np.ndarray:
        """``dR_n/dp @ dp`` for every step, (n_time, n_state).

        Parameters
        ----------
        dp : numpy.ndarray
            (n_param,) parameter direction.

        Returns
        -------
        numpy.ndarray
            (n_time, n_state) residual perturbation history.
        """
        dp = np.asarray(dp, dtype=float).reshape(1, -1)
        return self._per_block("p", np.broadcast_to(dp, (self.n_time, dp.size)))

    def _param_sum(self, blk, lam):
        """``sum_n dR_n/dp^T lam_n`` over the steps of ``blk``."""
        rows, cols, shape = self.patterns["p"]
        lo, hi = blk.lo, blk.hi
        self._block_inputs(blk)
        if self._lib is not None and blk.jp.flags.c_contiguous:
            r32, c32 = self._idx32["p"]
            return static_lu.hist_product(self._lib, blk.jp[:hi - lo], c32, r32, lam[lo:hi], shape[1], sum_time=True)
        per_nonzero = np.einsum("ij,ij->j", blk.jp[:hi - lo], lam[lo:hi, rows])   # sum over time first
        return np.bincount(cols, per_nonzero, minlength=shape[1])

    def _cached_products(self, lam):
        c = self._adjoint_cache
        if c is not None and c[0].matches(lam):
            return c
        return None

    def _vjp_products(self, lam):
        """``(lam, param_product, forcing_product)`` by the system's reverse-mode products
        (``input_vjp_history``: one evaluation per step, dR/dp and dR/dq never formed), kept for
        the other product with the same ``lam``; None with checkpoints, with dR/dp already
        evaluated (its stored products are cheaper) or when the system has no such products."""
        if self._full is None or self._jp is not None:
            return None
        L = lam
        if self.initial == "state":       # step 0 has no p or q (x_0 - x_init)
            L = lam.copy()
            L[0] = 0.0
        got = self.system.input_vjp_history(self._X, self._Xdot, self._p, self._Q, L)
        if got is None:
            return None
        self._adjoint_cache = (ArrayStamp(lam), np.asarray(got[0], dtype=float).reshape(self.system.n_param),
                               np.asarray(got[1], dtype=float).reshape(self.n_time, self.system.n_forcing))
        return self._adjoint_cache

    def param_product(self, lam) -> np.ndarray:
        """``sum_n dR_n/dp^T lam_n`` (n_param,) (the sum in Eq. 3.11).

        Parameters
        ----------
        lam : numpy.ndarray
            (n_time, n_state) residual-weight (adjoint) history.

        Returns
        -------
        numpy.ndarray
            (n_param,) the summed product.
        """
        lam = np.asarray(lam, dtype=float).reshape(self.n_time, self.n_state)
        c = self._cached_products(lam) or self._vjp_products(lam)
        if c is not None:
            return c[1].copy()
        return sum(self._param_sum(blk, lam) for blk in self._blocks())

    def forcing_apply(self, dq) -> np.ndarray:
        """``dR_n/dq_n @ dq_n`` for every step, (n_time, n_state).

        Parameters
        ----------
        dq : numpy.ndarray
            (n_time, n_forcing) forcing direction.

        Returns
        -------
        numpy.ndarray
            (n_time, n_state) residual perturbation history.
        """
        return self._per_block("q", np.asarray(dq, dtype=float).reshape(self.n_time, -1))

    def forcing_product(self, lam) -> np.ndarray:
        """``dR_n/dq_n^T lam_n`` for every step, (n_time, n_forcing).

        Parameters
        ----------
        lam : numpy.ndarray
            (n_time, n_state) residual-weight (adjoint) history.

        Returns
        -------
        numpy.ndarray
            (n_time, n_forcing) the product at every step.
        """
        lam = np.asarray(lam, dtype=float).reshape(self.n_time, self.n_state)
        c = self._cached_products(lam)
        if c is None or c[2] is None:      # None: the sweep did not keep it (keep_forcing_product)
            c = self._vjp_products(lam)
        if c is not None:
            return c[2].copy()
        return self._per_block("q", lam, transpose=True, width=self.system.n_forcing)

    # ------------------------------------------------------------------ sweeps
    def solve_tangent(self, rhs) -> np.ndarray:
        """Forward sweep: solve ``J dx = rhs``, ``dx_n = A_n^-1 (rhs_n - sum_k B_n,k dx_n-k)``.

        Parameters
        ----------
        rhs : numpy.ndarray
            (n_time, n_state) right-hand side history.

        Returns
        -------
        numpy.ndarray
            (n_time, n_state) the solution ``dx``.
        """
        rhs = np.ascontiguousarray(np.asarray(rhs, dtype=float).reshape(self.n_time, self.n_state))
        dx = np.zeros_like(rhs)
        st = self._static_lu()
        for blk in self._blocks():
            if st is not None:
                self._tangent_block_static(blk, rhs, dx, st)
                continue
            for n in range(blk.lo, blk.hi):
                b = rhs[n].copy()
                if n >= 1:
                    hist = self.coef[n, 1] * dx[n - 1] + (self.coef[n, 2] * dx[n - 2] if n >= 2 else 0.0)
                    b -= self._rate_product(blk, n, hist)
                dx[n] = self._solve_step(blk, n, b)
                if n >= 1:
                    self._release(n - 1, n)
        return dx

    def _tangent_block_static(self, blk, rhs, dx, slu):
        """The tangent sweep over the steps of ``blk``: step 0 with SuperLU, the others in the C
        kernel (right-hand side, factorization, checked and refined solve); a step whose solve
        still fails is redone with SuperLU from the kernel's right-hand side."""
        if blk.lo == 0:
            dx[0] = self._lu(0, blk).solve(rhs[0])
        data = self._sweep_data(slu, blk)
        n, last = max(blk.lo, 1), blk.hi - 1
        tried = set()
        while n <= last:
            stop, refined, factored = slu.tangent_sweep(data, n, last, rhs, dx)
            self.static_stats["refined"] += refined
            self.static_stats["factored"] += factored
            if stop > last:
                break
            new = self._repivot(stop, blk, tried)
            if new is not None:          # redo the step with the pivots of its own matrix
                slu, n = new, stop
                continue
            dx[stop] = self._fallback(stop, slu.rhs_buffer.copy(), "N", blk)
            n = stop + 1

    def _adjoint_rhs(self, blk, n, rhs, lam):
        """``rhs_n - B_n+1,1^T lam_n+1 - B_n+2,2^T lam_n+2``: the right-hand side of step n of the
        adjoint sweep, with ``B_m,k = alpha_k(m)/dt dR_m/dxdot`` (zero past the last step)."""
        b = rhs[n].copy()
        for k in (1, 2):
            if n + k < self.n_time:
                b -= self.coef[n + k, k] * self._rate_product_t(blk, n + k, lam[n + k])
        return b

    def solve_adjoint(self, rhs) -> np.ndarray:
        """Reverse sweep: solve ``J^T lam = rhs`` backward in time with transposed factors.

        ``lam_n = A_n^-T (rhs_n - B_n+1,1^T lam_n+1 - B_n+2,2^T lam_n+2)``; the BDF1 block of
        step 1 enters through ``alpha_1(1) = -1/dt`` and ``B_2,2`` of step 2. With checkpoints
        the products ``param_product(lam)`` and ``forcing_product(lam)`` are formed segment by
        segment in the same sweep and kept for the next call with this ``lam``.

        Parameters
        ----------
        rhs : numpy.ndarray
            (n_time, n_state) right-hand side history.

        Returns
        -------
        numpy.ndarray
            (n_time, n_state) the adjoint history ``lam``.
        """
        rhs = np.ascontiguousarray(np.asarray(rhs, dtype=float).reshape(self.n_time, self.n_state))
        st = self._static_lu()
        lam = np.zeros_like(rhs)
        lean = self._full is None
        dp = np.zeros(self.system.n_param)
        dq = np.zeros((self.n_time, self.system.n_forcing)) if lean and self.keep_forcing_product else None
        for blk in self._blocks(reverse=True):
            if st is not None:
                self._adjoint_block_static(blk, rhs, lam, st)
            else:
                for n in range(blk.hi - 1, blk.lo - 1, -1):
                    lam[n] = self._solve_step(blk, n, self._adjoint_rhs(blk, n, rhs, lam), trans="T")
                    if n + 1 < self.n_time:
                        self._release(n + 1, n)
            if lean:
                lo, hi = blk.lo, blk.hi
                got = self._segment_vjp(blk, lam) if blk.jp is None else None   # reverse mode: no dR/dp
                if got is not None:
                    dp += got[0]
                    if dq is not None:
                        dq[lo:hi] = got[1]
                else:
                    dp += self._param_sum(blk, lam)
                    if dq is not None:
                        dq[lo:hi] = self._hist_product("q", self._block_inputs(blk)[1][:hi - lo], lam[lo:hi],
                                                       transpose=True)
        self._adjoint_cache = (ArrayStamp(lam), dp, dq) if lean else None
        return lam

    def _adjoint_block_static(self, blk, rhs, lam, slu):
        """The adjoint sweep of :meth:`solve_adjoint` over the steps n >= 1 of ``blk`` in the C
        kernel: the right-hand side :meth:`_adjoint_rhs`, the factorization of ``A_n``, the
        transposed solve, its backward error and one refinement
        (``StaticPivotLU.adjoint_sweep``). A step whose solve still fails is redone with SuperLU
        from the kernel's right-hand side; step 0 uses SuperLU."""
        data = self._sweep_data(slu, blk)
        n, first = blk.hi - 1, max(blk.lo, 1)
        tried = set()
        while n >= first:
            stop, refined, factored = slu.adjoint_sweep(data, n, first, rhs, lam)
            self.static_stats["refined"] += refined
            self.static_stats["factored"] += factored
            if stop < first:
                break
            new = self._repivot(stop, blk, tried)
            if new is not None:          # redo the step with the pivots of its own matrix
                slu, n = new, stop
                continue
            lam[stop] = self._fallback(stop, slu.rhs_buffer.copy(), "T", blk)
            n = stop - 1
        if blk.lo == 0:
            lam[0] = self._lu(0, blk).solve(self._adjoint_rhs(blk, 0, rhs, lam), trans="T")

    # ------------------------------------------------------------------ gradients
    def rate_gradient_to_states(self, dfdxdot) -> np.ndarray:
        """Chain ``df/dxdot_n`` through the BDF formulas onto the states (Eq. 3.10 F-terms).

        Parameters
        ----------
        dfdxdot : numpy.ndarray
            (n_time, n_state) derivative of the functional with respect to the state rates.

        Returns
        -------
        numpy.ndarray
            (n_time, n_state) the same derivative with respect to the states.
        """
        h = np.asarray(dfdxdot, dtype=float).reshape(self.n_time, self.n_state)
        out = np.zeros_like(h)
        for k in range(3):
            out[:self.n_time - k] += self.coef[k:, k:k + 1] * h[k:]
        return out

    def gradient(self, dfdx, dfdp=None, dfdq=None, dfdxdot=None):
        """Total derivatives of a functional by one adjoint sweep (Eq. 3.10-3.11).

        ``dfdx`` (n_time, n_state), optional ``dfdxdot`` likewise, explicit ``dfdp`` (n_param,)
        and ``dfdq`` (n_time, n_forcing). Returns ``(df/dp, df/dq, lam)``; with a given
        initial state, ``df/dx_init = lam_0``.

        Parameters
        ----------
        dfdx : numpy.ndarray
            (n_time, n_state) derivative of the functional with respect to the states.
        dfdp : numpy.ndarray, optional
            (n_param,) explicit derivative with respect to the parameters.
        dfdq : numpy.ndarray, optional
            (n_time, n_forcing) explicit derivative with respect to the forcing.
        dfdxdot : numpy.ndarray, optional
            (n_time, n_state) derivative with respect to the state rates.

        Returns
        -------
        dfdp : numpy.ndarray
            (n_param,) total derivative with respect to the parameters.
        dfdq : numpy.ndarray
            (n_time, n_forcing) total derivative with respect to the forcing.
        lam : numpy.ndarray
            (n_time, n_state) the adjoint history.
        """
        g = np.asarray(dfdx, dtype=float).reshape(self.n_time, self.n_state).copy()
        if dfdxdot is not None:
            g += self.rate_gradient_to_states(dfdxdot)
        lam = self.solve_adjoint(g)
        dp = -self.param_product(lam)
        dq = -self.forcing_product(lam)
        if dfdp is not None:
            dp = dp + np.asarray(dfdp, dtype=float).reshape(dp.shape)
        if dfdq is not None:
            dq = dq + np.asarray(dfdq, dtype=float).reshape(dq.shape)
        return dp, dq, lam

    def tangent(self, dp=None, dq=None, dx_init=None) -> np.ndarray:
        """State-history sensitivity to a parameter/forcing/initial-state direction (forward mode).

        Parameters
        ----------
        dp : numpy.ndarray, optional
            (n_param,) parameter direction.
        dq : numpy.ndarray, optional
            (n_time, n_forcing) forcing direction.
        dx_init : numpy.ndarray, optional
            (n_state,) initial-state direction (``initial="state"``).

        Returns
        -------
        numpy.ndarray
            (n_time, n_state) state-history sensitivity.
        """
        rhs = np.zeros((self.n_time, self.n_state))
        if dp is not None:
            rhs -= self.param_apply(dp)
        if dq is not None:
            rhs -= self.forcing_apply(dq)
        if dx_init is not None:
            rhs[0] += np.asarray(dx_init, dtype=float).reshape(self.n_state)
        return self.solve_tangent(rhs)
