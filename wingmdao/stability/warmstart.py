"""Warm start of the flutter-damping constraint between an optimizer's evaluations.

:class:`WarmStart` owns the history of :func:`wingmdao.stability.sensitivity.damping_constraint`
(the tracked modes of every speed, the cold windows' discs, the counters) and refines it on each
new design (:meth:`WarmStart.modes_at`); the rules are in its docstring and in docs/flutter.md.
The refinement of one mode is :func:`wingmdao.stability.modes.refine_pair`; a mode far below the
KS maximum may stand at its two-sided Rayleigh-Ritz estimate (:func:`_ritz`, lazy refinement).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.linalg import lapack
from scipy.optimize import linear_sum_assignment

from wingmdao.stability.eigen import linearize, static_state
from wingmdao.stability.modes import Selection, SpeedModes, cold_speed, loaded_fraction, refine_pair
from wingmdao.stability.pencil_lu import ShiftedPencil
from wingmdao.timemarch.system import derived, layout

#: a warm-started mode whose KS exponent rho (g - g_max) is below -this (weight < 4e-18) of the
#: previous evaluation's g_max (minus the same again as a guard) may leave the set without a cold window
NEGLIGIBLE_KS = 80.0


class WarmStart:
    """History of :func:`~wingmdao.stability.sensitivity.damping_constraint` between evaluations
    (warm start; docs/flutter.md).

    After a cold evaluation (the full sparse eigen window at every speed) it keeps, per speed,
    **every oscillatory mode of the window** (eigenvalue, right and left vectors), loaded or not:
    an unloaded in-plane mode (Re lambda ~ 0) becomes loaded when it nears the torsion mode, and
    a history of the aggregated modes only missed it (PEGASUS sizing: warm KS -0.961, cold
    -0.003). The next evaluation refines all of them on the new design's full pencil
    (:func:`~wingmdao.stability.modes.refine_pair`, from the previous evaluation's vectors) and aggregates those now loaded,
    unless a rule asks for the full window again:

    * no history, or the speeds / options changed;
    * ``refresh`` evaluations since the last window of every speed (a full or a single-speed
      window; a speed whose own window is that old, while others had one since, gets a
      single-speed window instead: the window of each speed is at most ``refresh`` old);
    * optional: some parameter block moved by more than ``max_step`` of its largest entry from
      the last cold design (default off: SLSQP steps of the sizing move the stiffnesses by
      30-90 % and the refinement checks alone kept the value equal to the cold one);
    * a refinement is not trusted: not converged, its beam-weighted MAC with the previous
      vector below ``min_mac``, the mode turned real, two modes refined to the same eigenvalue,
      or it left the cold window's disc ``|lambda - sigma| < r`` (the cold set would drop it).
      Since every oscillatory mode of the window is refined, a refinement that lands on another
      mode lands on one of these (a tracked mode: duplicate; a real root; outside the disc).

    ``lazy`` (default): a mode is refined only when it may matter: its two-sided Rayleigh-Ritz
    estimate on the history's vectors (:func:`_ritz`, no LU) is not trusted, or may be loaded
    and within ``LAZY_KS / rho`` of g_max at the upper end of its (empirical) error bound; a
    second check against the exact g_max of the refined modes refines any skipped mode in reach.
    At the speeds after the first, a second estimate on this design's modes at the previous speed
    (refined or estimated just before; the in-plane modes barely change with the speed) replaces the
    history one per mode when it is trusted with a smaller bound (:func:`_best_ritz`).

    The history is the tracked set of the stored evaluation (the last ``keep``, since the last
    full or single-speed window) nearest the new design (:meth:`distance`): SLSQP's line searches
    jump back near earlier designs.

    The first evaluation (no history) makes one window, at the lowest speed; each later speed
    tracks the previous speed's set (every oscillatory mode refined on its pencil, MAC with that
    set, the first window's disc: the window radius is set by the aerodynamic lag roots and barely
    changes with the speed, PEGASUS 120.2-122.9 1/s) and gets its own window only when that fails.
    A failed speed is retried from this design's modes at the nearest speed that worked, then, if
    the step was too large for its history (a design moved ~8x, as a presizing pass does), by
    tracking this design's window set at the nearest speed that has one, and only then redone with
    the full window, so the value is always that of a converged set (PEGASUS maneuver sizing: one
    window in all, eight before). Not detected: an oscillatory mode entering the window between
    two cold evaluations from outside the disc or from two real roots (its KS weight is
    ~exp(-rho (g_max - g)); the next cold evaluation picks it up).

    Parameters
    ----------
    refresh : int, optional
        Evaluations after which a speed's eigen window is recomputed.
    max_step : float or None, optional
        Largest relative parameter change from the last cold design before a cold evaluation; None for no limit.
    min_mac : float, optional
        Smallest beam-weighted MAC of a trusted refinement (-).
    tol : float, optional
        Convergence tolerance of the refinements.
    keep : int, optional
        Stored evaluations the history is chosen from.
    lazy : bool, optional
        Refine a mode only when it may matter (above).
    """

    def __init__(self, *, refresh=100, max_step=None, min_mac=0.5, tol=1e-12, keep=6, lazy=True):
        if int(refresh) < 1:
            raise ValueError(f"WarmStart refresh = {refresh}; allowed: an integer >= 1 (evaluations)")
        if not ((max_step is None or 0.0 < float(max_step)) and 0.0 <= float(min_mac) <= 1.0):
            raise ValueError(f"WarmStart: max_step = {max_step} (> 0 or None), min_mac = {min_mac} [0, 1] "
                             "out of range")
        self.refresh, self.min_mac = int(refresh), float(min_mac)
        self.max_step = None if max_step is None else float(max_step)
        self.tol = float(tol)
        self.keep = max(1, int(keep))
        self.lazy = bool(lazy)
        self.reset()

    def reset(self):
        """Forget the history: the next evaluation is cold."""
        self.key = None              # (speeds, options) of the history
        self.cold_p = None           # per speed: p of the last cold evaluation
        self.cold_window = None      # per speed: (radius, sigma) of the cold window's disc
        self.tracked = None          # per speed: SpeedModes of every oscillatory window mode, last evaluation
        self.modes = None            # per speed: SpeedModes of the aggregated modes, last evaluation
        self.history = []            # (p at the first speed, tracked, modes) of the last ``keep`` evaluations
        self.since_cold = 0          # evaluations since the last full cold evaluation
        self.window_age = None       # per speed: evaluations since its last window (full or single-speed)
        self.n_cold = 0
        self.n_warm = 0
        self.n_speed_retry = 0       # single speeds retried from the design's modes at another speed
        self.n_speed_cold = 0        # single speeds redone with the full window in a warm evaluation
        self.n_speed_track = 0       # single speeds tracked from this design's window set at another speed
        self.n_windows = 0           # sparse eigen windows computed (full and single-speed)
        self.dropped = 0             # negligible modes dropped (turned real / left the window)
        self.n_refined = 0           # mode refinements (refine_pair from the history)
        self.n_skipped = 0           # modes left at their Ritz estimate (lazy refinement)
        self.n_lazy_redo = 0         # speeds refined again: a skipped mode came within reach of g_max
        self.reasons = []            # why each cold evaluation or cold speed was made

    @staticmethod
    def distance(system, p, ph):
        """Largest relative change of a parameter block between ``ph`` and ``p`` (max-norm over
        the block / its largest entry in ``ph``).

        Parameters
        ----------
        system : ResidualSystem
            The residual system.
        p : numpy.ndarray
            Packed parameters of the new design.
        ph : numpy.ndarray
            Packed parameters of a stored design.

        Returns
        -------
        float
            The largest relative change (-).
        """
        starts = _block_starts(system)
        if starts.size == 0:
            return 0.0
        scale = np.maximum.reduceat(np.abs(ph), starts)
        diff = np.maximum.reduceat(np.abs(np.asarray(p) - ph), starts)
        ok = scale > 0.0
        return float(np.max(diff[ok] / scale[ok], initial=0.0))

    def step_too_large(self, system, p_list):
        """True when ``max_step`` is set and some parameter block moved by more than ``max_step``
        of its largest entry (max-norm, relative) from the last cold design, at some speed.

        Parameters
        ----------
        system : ResidualSystem
            The residual system.
        p_list : sequence of numpy.ndarray
            Packed parameters at each speed.

        Returns
        -------
        bool
            Whether the step is too large.
        """
        if self.max_step is None:
            return False
        for p, pc in zip(p_list, self.cold_p):
            for sl in layout(system.param_specs).values():
                scale = float(np.max(np.abs(pc[sl]), initial=0.0))
                if np.max(np.abs(p[sl] - pc[sl]), initial=0.0) > self.max_step * scale + 1e-9:  # 1e-9: round-off of zero blocks (SI)
                    return True
        return False

    def modes_at(self, system, pq, speeds, sel: Selection, key) -> tuple[list, bool]:
        """``(tracked, cold)``: every oscillatory mode of the eigen window at each speed for the
        parameters ``pq`` (per speed ``(p, q)``), refined from the history when the rules allow
        (``cold`` False), else from a new window (``cold`` True; ``key``: the speeds and options,
        a change of which asks for a window).

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
        key : object
            The speeds and options; a change asks for a new window.

        Returns
        -------
        tuple
            (tracked modes per speed, cold).
        """
        reason = self.cold_reason(system, key, [p for p, _ in pq])
        if reason is None:
            return self._warm(system, pq, speeds, sel), False
        self.reasons.append(reason)
        return self._cold(system, pq, speeds, sel, key, track=reason == "no history"), True

    def remember(self, pq, tracked, modes):
        """Store an evaluation's tracked and aggregated modes (the next evaluation's history).

        Parameters
        ----------
        pq : sequence of tuple
            (p, q) per speed.
        tracked : list of SpeedModes
            Every oscillatory mode per speed.
        modes : list of SpeedModes
            The aggregated modes per speed.
        """
        self.tracked, self.modes = tracked, modes
        self.history = (self.history + [(pq[0][0], tracked, modes)])[-self.keep:]

    def cold_reason(self, system, key, p_list):
        """Why the next evaluation needs a full window at every speed, or None (a warm one).

        Parameters
        ----------
        system : ResidualSystem
            The residual system.
        key : object
            The speeds and options.
        p_list : sequence of numpy.ndarray
            Packed parameters at each speed.

        Returns
        -------
        str or None
            The reason, or None for a warm evaluation.
        """
        if self.tracked is None or self.key != key:
            return "no history"
        if min(self.window_age) + 1 >= self.refresh:   # every speed's window is stale
            return f"refresh after {self.refresh} evaluations"
        if self.step_too_large(system, p_list):
            return f"design step > {self.max_step:g} relative"
        return None

    def _cold(self, system, pq, speeds, sel, key, *, track):
        """A cold evaluation; ``track`` (the first evaluation): one window, at the lowest speed;
        each later speed tracks the previous speed's set (every oscillatory mode refined on its
        pencil, MAC with that set, the first window's disc), and gets a window of its own only when
        that fails (a refresh or a step rule always gives every speed its window)."""
        tracked, windows, x = [], [], None
        for k, ((p, q), V) in enumerate(zip(pq, speeds)):
            sm = None
            if track and k > 0:
                sm = self._track_over_speed(system, p, q, tracked[k - 1], V, windows[k - 1], sel, lambda lam: False)
                if isinstance(sm, str):
                    self.reasons.append(sm)
                    sm = None
                else:
                    windows.append(windows[k - 1])
            if sm is None:
                sm, win = cold_speed(system, p, q, x, V, sel)
                windows.append((float(np.max(np.abs(win - sel.sigma))), sel.sigma))
                self.n_windows += 1
            x = sm.x0
            tracked.append(sm)
        self.key, self.cold_p, self.cold_window = key, [p for p, _ in pq], windows
        self.history = []
        self.since_cold, self.n_cold = 0, self.n_cold + 1
        self.window_age = [0] * len(pq)
        return tracked

    def _warm(self, system, pq, speeds, sel):
        """A warm evaluation: the history's modes refined at every speed (a speed whose refinement
        is not trusted retried, then tracked over the speed, then given its own window)."""
        if len(self.history) > 1:   # the stored design nearest this one (line searches jump back)
            self.tracked, self.modes = min(self.history, key=lambda h: self.distance(system, pq[0][0], h[0]))[1:]
        g_prev = np.concatenate([sel.g(sm.eigenvalues) for sm in self.modes])
        cut = float(np.max(g_prev)) - NEGLIGIBLE_KS / sel.rho_ks

        def negligible(lam):
            return float(sel.g(np.atleast_1d(lam))[0]) < cut

        # a speed whose last window is `refresh` evaluations old gets a new one (the others stay warm)
        stale = {k for k in range(len(pq)) if self.window_age[k] + 1 >= self.refresh}
        pre = self._estimates(system, pq, stale, sel)
        low = self._lower_bound(pre, sel)
        skips = [self._skip_set(rz, low, sel) for _, _, _, rz in pre]
        tracked = []
        for k, (p, q) in enumerate(pq):
            if k in stale:
                tracked.append(self._window_at(system, pq, speeds, k, sel,
                                               f"refresh of {speeds[k]:.1f} m/s after {self.refresh} evaluations"))
                continue
            xk, Ak, Bk, rz = pre[k]
            near = tracked[k - 1] if k > 0 else None
            if rz is not None and isinstance(near, SpeedModes) and near.eigenvalues.size:
                # second estimate on this design's modes at the previous speed (the lightly loaded
                # in-plane modes barely change with the speed); per mode the better trusted one
                rz = _best_ritz(rz, _ritz(Ak, Bk, self.tracked[k], self.cold_window[k], sel, self.min_mac,
                                          basis=(near.right, near.left)))
                pre[k] = (xk, Ak, Bk, rz)
                skips[k] = self._skip_set(rz, low, sel)
            tracked.append(self._refine_speed(system, p, q, self.tracked[k], self.cold_window[k], sel, negligible,
                                              x=xk, A=Ak, B=Bk, skip=skips[k], ritz=rz))
        # speeds whose set this evaluation descends from a window of *this* design
        self._retry_failed(system, pq, speeds, sel, negligible, tracked, pre, skips, fresh=set(stale))
        self._check_skipped(system, pq, speeds, sel, negligible, tracked, pre, skips)
        self.since_cold += 1
        self.window_age = [a + 1 for a in self.window_age]
        self.n_warm += 1
        return tracked

    def _window_at(self, system, pq, speeds, k, sel, why):
        """The full window at speed ``k`` only (the cold path's value there)."""
        self.reasons.append(why)
        self.n_speed_cold += 1
        p, q = pq[k]
        sm, win = cold_speed(system, p, q, self.tracked[k].x0, speeds[k], sel)
        self.n_windows += 1
        self.cold_window[k] = (float(np.max(np.abs(win - sel.sigma))), sel.sigma)
        self.cold_p[k] = p
        self.window_age[k] = -1   # 0 after this evaluation
        self.history = []   # older designs' sets may lack a mode this window found
        return sm

    def _estimates(self, system, pq, stale, sel):
        """Per speed ``(x, A, B, ritz)``: the static state and pencil of the new design and the
        Ritz estimates of the history's modes on it (None unless ``lazy``; all None at a stale speed)."""
        pre = []
        for k, (p, q) in enumerate(pq):
            if k in stale:
                pre.append((None, None, None, None))
                continue
            prev = self.tracked[k]
            xk = static_state(system, p, q, prev.x0, **(sel.static_options or {})) if sel.static else prev.x0
            Ak, Bk = linearize(system, p, q, xk)
            rz = (_ritz(Ak, Bk, prev, self.cold_window[k], sel, self.min_mac)
                  if self.lazy and prev.eigenvalues.size else None)
            pre.append((xk, Ak, Bk, rz))
        return pre

    def _lower_bound(self, pre, sel):
        """A lower bound of g_max from the trusted estimates of clearly loaded modes (-inf unless ``lazy``)."""
        low = -np.inf
        if self.lazy:
            for _, _, _, rz in pre:
                if rz is not None:
                    sure = rz.trusted & (rz.loaded >= 10.0 * sel.neutral_fraction)
                    if np.any(sure):
                        low = max(low, float(np.max(sel.g_upper(rz.lam[sure], -rz.error[sure]))))
        return low

    def _skip_set(self, rz, low, sel):
        """The modes left at their estimate: trusted, and unloaded or, at the upper end of their
        bound, ``LAZY_KS / rho`` below the lower bound ``low`` of g_max."""
        if rz is None or not self.lazy:
            return set()
        weak = sel.g_upper(rz.lam, rz.error) < low - LAZY_KS / sel.rho_ks
        return set(np.flatnonzero(rz.trusted & (rz.unloaded | weak)).tolist())

    def _retry_failed(self, system, pq, speeds, sel, negligible, tracked, pre, skips, fresh):
        """Replace each failed speed of ``tracked`` (a string: why) by a retry from this design's
        modes at the nearest speed that worked, else (a step too large for the history, ~8x) by
        tracking this design's window set at the nearest speed in ``fresh`` (mode tracking over the
        speed, as the flutter sweep does; MAC with that set's vectors), else by its own window."""
        good = [k for k, sm in enumerate(tracked) if not isinstance(sm, str)]
        for k, (p, q) in enumerate(pq):
            if not isinstance(tracked[k], str):
                continue
            self.reasons.append(tracked[k])
            sm = tracked[k]
            skips[k] = set()
            x, A, B = pre[k][:3]
            if good:   # retry from this design's modes at the nearest speed that worked
                near = tracked[min(good, key=lambda i: abs(i - k))]
                sm = self._refine_speed(system, p, q, self.tracked[k], self.cold_window[k], sel, negligible,
                                        other=near, x=x, A=A, B=B)
                self.n_speed_retry += 1
            if isinstance(sm, str) and fresh:
                j = min(fresh, key=lambda i: abs(i - k))
                self.reasons.append(f"{speeds[k]:.1f} m/s from this design's window set at {speeds[j]:.1f} m/s")
                sm = self._track_over_speed(system, p, q, tracked[j], speeds[k], self.cold_window[k], sel, negligible,
                                            x=x, A=A, B=B)
                if not isinstance(sm, str):
                    self.window_age[k] = self.window_age[j]
                    fresh.add(k)
            if isinstance(sm, str):
                sm = self._window_at(system, pq, speeds, k, sel, sm)
                fresh.add(k)
            tracked[k] = sm
            good.append(k)   # later failed speeds retry from this one (a big step fails them all)

    def _check_skipped(self, system, pq, speeds, sel, negligible, tracked, pre, skips):
        """Lazy refinement, second check: every skipped, possibly loaded mode must lie
        ``LAZY_KS / rho`` below the exact g_max of the refined loaded modes (else refine it too
        and check again)."""
        for _ in range(len(pq) * 8):
            if not any(skips):
                break
            g_max = -np.inf
            for sm in tracked:
                ref = (sm.error == 0.0) & (loaded_fraction(sm.right, sel.aero_mask, sel.beam_mask)
                                           > sel.neutral_fraction)
                if np.any(ref):
                    g_max = max(g_max, float(np.max(sel.g(sm.eigenvalues[ref]))))
            redo = False
            for k, sm in enumerate(tracked):
                if not skips[k]:
                    continue
                rz = pre[k][3]
                bad = {j for j in skips[k] if not rz.unloaded[j]
                       and float(sel.g_upper(rz.lam[j], rz.error[j])[0]) >= g_max - LAZY_KS / sel.rho_ks}
                if not bad:
                    continue
                redo = True
                self.n_lazy_redo += 1
                skips[k] -= bad
                p, q = pq[k]
                sm = self._refine_speed(system, p, q, self.tracked[k], self.cold_window[k], sel, negligible,
                                        x=pre[k][0], A=pre[k][1], B=pre[k][2], skip=skips[k], ritz=rz)
                if isinstance(sm, str):
                    skips[k] = set()
                    sm = self._window_at(system, pq, speeds, k, sel, sm)
                tracked[k] = sm
            if not redo:
                break

    def _refine_speed(self, system, p, q, prev, window, sel, negligible, other=None, x=None, A=None, B=None, skip=(),
                      ritz=None):
        """Every tracked mode refined at one speed, or a string saying why the refinement is not trusted.
        ``negligible(lam)``: True when the mode's KS weight is below round-off; such a mode that turns
        real or leaves the window is dropped (the cold set drops it too) instead of failing.
        ``other``: this design's refined modes at another speed; a mode whose refinement from its
        history fails is retried from the mode of ``other`` with the largest MAC with its history
        (the modes change less with the speed than between SLSQP designs).
        ``skip``: indices of history modes not refined: their :class:`_Ritz` estimates (``ritz``) stand
        in (lazy refinement); a refined mode landing within a skipped
        estimate's bound fails the speed. ``x, A, B``: the static state and pencil, if already made."""
        if x is None:
            x = static_state(system, p, q, prev.x0, **(sel.static_options or {})) if sel.static else prev.x0
        if A is None:
            A, B = linearize(system, p, q, x)
        radius, sigma = window
        w = np.sqrt(sel.beam_mask)
        lams, vs, us, errs = [], [], [], []
        skip = set(int(j) for j in skip)
        for j in sorted(skip):
            lams.append(complex(ritz.lam[j]))
            vs.append(ritz.right[:, j])
            us.append(ritz.left[:, j])
            errs.append(float(ritz.error[j]))
            self.n_skipped += 1
        for j in range(prev.eigenvalues.size):
            if j in skip:
                continue
            self.n_refined += 1
            starts = [(prev.eigenvalues[j], prev.right[:, j], prev.left[:, j])]
            if ritz is not None and ritz.trusted[j]:   # the Ritz pair first: it follows the modes' mixing
                starts.insert(0, (ritz.lam[j], ritz.right[:, j], ritz.left[:, j]))
            if other is not None and other.eigenvalues.size:
                i = int(np.argmax([_beam_mac(prev.right[:, j], other.right[:, k], w) for k in range(other.eigenvalues.size)]))
                starts.append((other.eigenvalues[i], other.right[:, i], other.left[:, i]))
            for lam0, v0, u0 in starts:
                v, u, lam, ok = refine_pair(A, B, lam0, v0, u0, tol=self.tol)
                if lam.imag < 0.0:   # landed on the conjugate: A, B are real, (conj v, conj u) belong to conj lambda
                    v, u, lam = v.conj(), u.conj(), lam.conjugate()
                mac = _beam_mac(prev.right[:, j], v, w) if ok else 0.0
                if ok and mac >= self.min_mac:
                    break
            if not ok:
                return f"refinement of {prev.eigenvalues[j]:.3f} not converged at {prev.speed:.1f} m/s"
            if mac < self.min_mac:
                return f"MAC {mac:.3f} < {self.min_mac} ({prev.eigenvalues[j]:.3f} -> {lam:.3f}) at {prev.speed:.1f} m/s"
            if abs(lam.imag) <= sel.min_frequency or abs(lam - sigma) > radius * (1.0 + 1e-6):
                if negligible(lam) and negligible(prev.eigenvalues[j]):
                    self.dropped += 1
                    continue
                what = "turned real" if abs(lam.imag) <= sel.min_frequency else "left the eigen window"
                return f"mode {prev.eigenvalues[j]:.3f} {what} ({lam:.3f}) at {prev.speed:.1f} m/s"
            if any(abs(lam - lk) <= 1e-6 * abs(lam) + ek for lk, ek in zip(lams, errs)):
                return f"two modes refined to {lam:.3f} at {prev.speed:.1f} m/s"
            lams.append(lam)
            vs.append(v)
            us.append(u)
            errs.append(0.0)
        n = system.n_state
        return SpeedModes(prev.speed, p, q, x, A, B, np.array(lams, dtype=complex),
                          np.array(vs).T.reshape(n, len(vs)), np.array(us).T.reshape(n, len(us)),
                          np.array(errs, dtype=float))

    def _track_over_speed(self, system, p, q, src, V, window, sel, negligible, x=None, A=None, B=None):
        """Every oscillatory mode of ``src`` (this design's set at another speed) refined at speed ``V``
        (:meth:`_refine_speed` with ``src`` as the history: mode tracking over the speed, as the flutter
        sweep does, MAC with ``src``'s vectors, inside ``window``), or a string saying why not."""
        sm = self._refine_speed(system, p, q, replace(src, speed=float(V)), window, sel, negligible, x=x, A=A, B=B)
        if not isinstance(sm, str):
            self.n_speed_track += 1
        return sm


def _block_starts(system) -> np.ndarray:
    """Start index of every non-empty parameter block of ``system`` (for ``np.maximum.reduceat``;
    made once per system: a system's parameter specs are fixed when it is built)."""
    return derived(system, "parameter_block_starts", _starts)


def _starts(system) -> np.ndarray:
    sizes = np.array([spec.size for spec in system.param_specs], dtype=np.intp)
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.intp)
    return starts[sizes > 0]


def _beam_mac(a, b, w):
    return abs(np.vdot(w * a, w * b)) ** 2 / (np.linalg.norm(w * a) ** 2 * np.linalg.norm(w * b) ** 2)


#: lazy refinement: a mode is left unrefined only when its KS exponent rho (g - g_max), with g at
#: the upper end of its error bound, is below -this (weight < 1.3e-14, below the gradient's
#: ``min_weight`` 1e-13; the value changes by < 1.3e-16 per skipped mode)
LAZY_KS = 32.0
#: lazy refinement: factor on the backward-error estimate of a Ritz value's error (:func:`_ritz`;
#: the largest ratio seen over a replayed PEGASUS sizing was 1.6)
LAZY_ERROR_FACTOR = 10.0


@dataclass
class _Ritz:
    """Two-sided Rayleigh-Ritz estimates of the tracked modes of one speed on a new pencil, one per
    history mode (same order): eigenvalue, unit right / left vectors, error bound (1/s, already
    times :data:`LAZY_ERROR_FACTOR`), beam-weighted MAC with the history vector, loaded fraction and
    whether the estimate may stand in for a refinement apart from its KS weight (``trusted``), and
    whether it is surely out of the aggregate (``unloaded``)."""

    lam: np.ndarray
    right: np.ndarray
    left: np.ndarray
    error: np.ndarray
    mac: np.ndarray
    loaded: np.ndarray
    trusted: np.ndarray
    unloaded: np.ndarray


_LWORK: dict = {}


def _small_eig(a, b):
    """``(w, vl, vr)`` of the small complex pencil ``(a, b)`` (the k x k Ritz pencil, k ~ 5): the
    LAPACK ``zggev`` call of ``scipy.linalg.eig(a, b, left=True, right=True)`` with the same optimal
    workspace (queried once per size), so the same eigenvalues, without SciPy's per-call validation,
    workspace query and per-column normalisation (~0.2 ms of its ~0.26 ms). The vectors are **not
    normalised** (the caller normalises the Ritz vectors ``V y``, ``U z``)."""
    a = np.asfortranarray(a, dtype=complex)
    b = np.asfortranarray(b, dtype=complex)
    n = a.shape[0]
    lwork = _LWORK.get(n)
    if lwork is None:
        lwork = _LWORK[n] = int(lapack.zggev(a, b, lwork=-1)[-2][0].real)
    alpha, beta, vl, vr, _, info = lapack.zggev(a, b, 1, 1, lwork, 0, 0)
    if info != 0:
        raise np.linalg.LinAlgError(f"generalized eig algorithm (zggev) failed: info = {info}")
    w = np.empty_like(alpha)
    nz = beta != 0
    w[nz] = alpha[nz] / beta[nz]
    w[~nz & (alpha != 0)] = np.inf
    w[~nz & (alpha == 0)] = complex(np.nan, np.nan)
    return w, vl, vr


def _ritz(A, B, prev, window, sel, min_mac, enrich=False, basis=None):
    """Petrov-Galerkin (two-sided Rayleigh-Ritz) projection of the new pencil ``(A, B)`` on the
    span of the history's right vectors V (trial) and left vectors U (test): the k x k pencil
    ``(U^H A V, U^H B V)``, solved dense; Ritz pairs ``x = V y``, ``w = U z``. Error estimate of
    the Ritz value: ``LAZY_ERROR_FACTOR * max(eta_r, eta_l) * |theta|`` with the relative
    backward errors ``eta_r = |(A + theta B) x| / (|A x| + |theta| |B x|)`` and ``eta_l`` likewise
    for ``w^H`` (Higham & Higham, "Structured backward error and condition of generalized
    eigenvalue problems", SIAM J. Matrix Anal. Appl. 20(2), 1998, for the backward error). This is
    an *empirical* bound, not a rigorous one: the rigorous first-order bound ``|w| |r| / |w^H B x|``
    was 1e4-1e11 1/s on PEGASUS (|u| |v| / |u^H B v| ~ 1e10, the states' mixed units); over a
    replayed sizing (3826 estimates) ``|theta - lambda| <= 1.6 max(eta_r, eta_l) |theta|``, so the
    factor 10 leaves a 6x margin (docs/flutter.md).
    An estimate is ``trusted`` when the mode is isolated (bound < half the distance to every other
    Ritz value), oscillatory, inside the cold window's disc with its bound, and its MAC with the
    history vector is at least ``min_mac`` (Ritz pairs matched to the history modes by an optimal
    assignment of the MAC). ``unloaded``: trusted, and the loaded fraction plus the vector's error
    estimate (bound / gap) below half ``neutral_fraction`` (the mode stays out of the aggregate).
    ``basis``: ``(V, U)`` to project on instead of the history's vectors (this design's modes at the
    previous speed, :meth:`WarmStart._warm`); the estimates are still matched to, and trusted by
    their MAC with, the history modes ``prev`` (a history mode left unmatched is not trusted). Over
    the replayed sizing these estimates' error was at most 0.026 max(eta_r, eta_l) |theta|."""
    mask, bmask, min_frequency, neutral_fraction = sel.aero_mask, sel.beam_mask, sel.min_frequency, sel.neutral_fraction
    V, U = (prev.right, prev.left) if basis is None else basis
    k = prev.right.shape[1]
    if enrich:
        # one block inverse-iteration step with one LU at the window's shift: the basis [V, (A + s B)^-1 B V]
        # (and the left one alike) holds the new modes far better than the old vectors alone
        lu = ShiftedPencil(A, B).factor(complex(window[1]))
        V2 = lu.solve(B @ V)
        U2 = lu.solve(B.conj().T @ U, trans="H")
        V = np.linalg.qr(np.column_stack([V, V2]))[0]
        U = np.linalg.qr(np.column_stack([U, U2]))[0]
    pencil = ShiftedPencil(A, B)      # the sparse products (in C with the kernel: SciPy's summation order)
    AV, BV = pencil.products(V)
    UH = U.conj().T
    th, zl, yr = _small_eig(-(UH @ AV), UH @ BV)
    X, W = V @ yr, U @ zl
    AX, BX = AV @ yr, BV @ yr
    # columns: (w^H A)^T, (w^H B)^T
    WA, WB = pencil.products(W.conj(), trans=True)
    with np.errstate(divide="ignore", invalid="ignore"):   # (a non-finite Ritz value: inf bound, below)
        # the eight column norms in one call
        Z = np.concatenate([X, W, AX + BX * th, AX, BX, WA + WB * th, WA, WB], axis=1).view(float)
        nx, nw, nrx, nax, nbx, nrw, naw, nbw = np.sqrt(np.einsum("ij,ij->j", Z, Z).reshape(-1, 2).sum(axis=1)
                                                       ).reshape(8, -1)
        eta_r = nrx / (nax + np.abs(th) * nbx)
        eta_l = nrw / (naw + np.abs(th) * nbw)
        err = LAZY_ERROR_FACTOR * np.maximum(eta_r, eta_l) * np.abs(th)
    err = np.where(np.isfinite(err) & np.isfinite(th), err, np.inf)
    X, W = X / nx, W / nw
    ib = np.flatnonzero(bmask)
    w = np.sqrt(bmask[ib])[:, None]
    wv, wx = prev.right[ib] * w, X[ib] * w   # (k, k or 2k) MAC: history vs Ritz (beam rows only)
    mac = np.abs(wv.conj().T @ wx) ** 2 / np.outer(np.sum(np.abs(wv) ** 2, axis=0), np.sum(np.abs(wx) ** 2, axis=0))
    rows, cols = linear_sum_assignment(-mac)
    order = np.zeros(k, dtype=int)
    order[rows] = cols
    matched = np.zeros(k, dtype=bool)    # a basis of fewer vectors than history modes leaves some unmatched
    matched[rows] = True
    th_all = th
    th, X, W, err = th[order], X[:, order], W[:, order], err[order]
    mac = np.where(matched, mac[np.arange(k), order], 0.0)
    radius, sigma = window
    with np.errstate(invalid="ignore"):   # a non-finite estimate: NaN gap, so not trusted (below)
        dist = np.abs(th_all[None, :] - th[:, None])     # every Ritz value but the mode's own
        dist[np.arange(k), order] = np.inf
        gap = np.min(dist, axis=1, initial=np.inf)
    trusted = ((err < 0.5 * gap) & (th.imag - err > min_frequency) & (np.abs(th - sigma) + err < radius)
               & (mac >= min_mac) & np.isfinite(th))
    loaded = loaded_fraction(X, mask, bmask)
    with np.errstate(divide="ignore", invalid="ignore"):
        unloaded = trusted & (loaded + err / gap < 0.5 * neutral_fraction)
    return _Ritz(th, X, W, err, mac, loaded, trusted, unloaded)


def _best_ritz(a: _Ritz, b: _Ritz) -> _Ritz:
    """Per history mode the estimate of ``a`` or ``b`` (two :func:`_ritz` projections on different
    bases, same history modes): ``b``'s where it is trusted and ``a``'s is not or has a larger bound."""
    use = b.trusted & (~a.trusted | (b.error < a.error))

    def pick(x, y):
        return np.where(use[None, :] if x.ndim == 2 else use, y, x)

    return _Ritz(*(pick(getattr(a, f), getattr(b, f)) for f in
                   ("lam", "right", "left", "error", "mac", "loaded", "trusted", "unloaded")))
