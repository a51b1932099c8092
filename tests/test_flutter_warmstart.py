"""Warm-started flutter constraint (WarmStart): equals the cold full-window constraint to round-off
along sequences of designs (Goland; PEGASUS with SLSQP-sized steps of 30-50 % in the wall
thicknesses), falls back to the full window by its rules (per speed), and never aggregates a
different mode."""

import numpy as np
import pytest

from wingmdao.stability.cases import flutter_problem, sizing_flutter_options
from wingmdao.stability.sensitivity import WarmStart, constraint_gradient, damping_constraint

DENSE_FEW = {"method": "dense", "count": 40}  # the kept modes well inside the window
SPEEDS = [60.0, 110.0, 130.0]


def _eval(scale, ws):
    prob = flutter_problem("goland", 5)
    beam = {k: np.array(v, dtype=float) for k, v in prob.beam.items()}
    beam["stiffness_csn"] *= scale

    def at(V):
        from wingmdao.timemarch.system import layout
        p, q = prob.params_at(V)
        lay = layout(prob.system.param_specs)
        p = p.copy()
        p[lay["stiffness_csn"]] = beam["stiffness_csn"].ravel()
        return p, q
    return damping_constraint(prob.system, at, SPEEDS, aero_mask=prob.aero_mask(), beam_mask=prob.beam_weights(),
                              rho_ks=20.0, warm_start=ws, **DENSE_FEW)


def _same_eigenvalues(rw, rc):
    """Refined eigenvalues equal the cold ones to 1e-10; lazy estimates within their error bound."""
    for a, e, b in zip(rw.eigenvalues, rw.errors, rc.eigenvalues):
        assert a.size == b.size
        for lam, err in zip(a, e):
            d = np.min(np.abs(b - lam))
            assert d <= (1e-10 * abs(lam) if err == 0.0 else err), (lam, err, d)


def test_warm_equals_cold_along_a_sequence_and_fallback():
    ws = WarmStart(refresh=1000, max_step=0.1)
    scales = [1.0, 1.01, 0.995, 1.02, 1.03, 1.3]   # the last step (> 10 %) must fall back
    for s in scales:
        rw = _eval(s, ws)
        rc = _eval(s, None)
        assert rw.value == pytest.approx(rc.value, abs=1e-10)
        assert np.abs(rw.gradient - rc.gradient).max() <= 1e-5 * np.abs(rc.gradient).max()  # cold: QZ round-off
        _same_eigenvalues(rw, rc)
    assert ws.n_warm == 4 and ws.n_cold == 2, (ws.n_warm, ws.n_cold, ws.reasons)
    assert "design step" in ws.reasons[-1]


def test_warm_without_step_rule_follows_large_steps():
    ws = WarmStart(refresh=1000)            # no step rule (the default)
    for s in [1.0, 1.3, 0.8, 1.25, 0.9]:
        rw = _eval(s, ws)
        assert rw.value == pytest.approx(_eval(s, None).value, abs=1e-10)
    assert ws.n_cold == 1 and ws.n_warm == 4, ws.reasons


def test_refresh_rule_and_wrong_mode_detected():
    ws = WarmStart(refresh=2)
    _eval(1.0, ws)
    assert not _eval(1.001, ws).cold
    # the refresh counts per speed since its last (full or single-speed) window: every speed stale
    # -> a full cold evaluation; only some -> single-speed windows for those
    ws.window_age = [1, 1, 1]
    rw = _eval(1.002, ws)
    assert rw.cold and ws.reasons[-1] == "refresh after 2 evaluations" and ws.window_age == [0, 0, 0]
    ws.window_age = [1, 0, 0]
    n = ws.n_speed_cold
    rw = _eval(1.003, ws)
    assert not rw.cold and ws.n_speed_cold >= n + 1 and ws.window_age[0] == 0
    assert any(r.startswith("refresh of 60.0 m/s") for r in ws.reasons), ws.reasons
    assert rw.value == pytest.approx(_eval(1.003, None).value, abs=1e-10)
    # a corrupted history (one mode's vectors replaced by another's): the two refine to one
    # eigenvalue; that speed is redone with the full window and the value is the cold one
    ws2 = WarmStart(refresh=1000)
    _eval(1.0, ws2)
    sm = ws2.tracked[1]
    sm.right[:, 0], sm.left[:, 0], sm.eigenvalues[0] = sm.right[:, 1], sm.left[:, 1], sm.eigenvalues[1]
    rw = _eval(1.0, ws2)
    assert not rw.cold and ws2.n_speed_cold >= 1 and any("two modes" in r for r in ws2.reasons), ws2.reasons
    assert rw.value == pytest.approx(_eval(1.0, None).value, abs=1e-10)


def test_leading_mode_with_a_wrong_history_falls_back():
    """The leading mode's history replaced by random vectors: the refinement lands anywhere, the MAC
    with the history flags it, that speed is redone with the full window: the cold value."""
    ws = WarmStart(refresh=1000)
    r0 = _eval(1.0, ws)
    k = int(np.argmax([sm.eigenvalues.real.max() for sm in ws.modes]))   # the speed holding the leading mode
    sm = ws.tracked[k]
    j = int(np.argmax(sm.eigenvalues.real))
    rng = np.random.default_rng(3)
    sm.right[:, j] = rng.standard_normal(sm.right.shape[0]) + 1j * rng.standard_normal(sm.right.shape[0])
    sm.left[:, j] = rng.standard_normal(sm.right.shape[0])
    rw = _eval(1.0, ws)
    assert ws.n_speed_cold >= 1, ws.reasons
    assert rw.value == pytest.approx(r0.value, abs=1e-10)



PEG_NODES = 8


def _pegasus(scale, ws, top=None):
    th = {w: np.full(PEG_NODES, 0.004 * f) for w, f in zip(("upper_skin", "lower_skin", "front_spar", "rear_spar"),
                                                          scale)}
    prob = flutter_problem("pegasus", PEG_NODES, th)
    o = sizing_flutter_options("pegasus", PEG_NODES, 1.15)
    return damping_constraint(prob.system, prob.params_at, o["speeds"], aero_mask=prob.aero_mask(),
                              beam_mask=prob.beam_weights(), rho_ks=o["rho_ks"], warm_start=ws, gradient=False,
                              **prob.eig_options)


def test_pegasus_warm_equals_cold_along_large_steps():
    """PEGASUS-like sequence: skins and spars moved by 20-50 % between designs (the size of SLSQP's
    steps in the sizing) and back (line searches): warm value = cold value to 1e-10, gradient to
    1e-4 relative (conditioning of the leading mode)."""
    ws = WarmStart(refresh=1000)
    seq = [(1, 1, 1, 1), (1.5, 1.4, 0.7, 1.2), (1.0, 1.05, 1.0, 0.95), (0.6, 0.7, 1.4, 0.6), (1.1, 1.0, 0.9, 1.0),
           (1.3, 1.2, 0.6, 1.5)]
    for s in seq:
        rw = _pegasus(s, ws)
        rc = _pegasus(s, None)
        assert rw.value == pytest.approx(rc.value, abs=1e-10), (s, ws.reasons)
        gw = constraint_gradient(_sys(), rw)
        gc = constraint_gradient(_sys(), rc, min_weight=0.0)
        # gradient: the leading near-neutral mode has cond = |u||v| / |u^H B v| ~ 1e10, so its
        # vectors (and the derivative) are determined to ~1e-7 relative by either path
        assert np.abs(gw - gc).max() <= 1e-4 * np.abs(gc).max()
    assert ws.n_cold == 1 and ws.n_warm == len(seq) - 1, ws.reasons


def test_a_step_too_large_for_every_speed_costs_one_window():
    """The first evaluation makes one window and tracks its modes over the speed. Then every speed's
    history made useless (random vectors, as after a fully stressed presizing pass in the PEGASUS
    sizing, which moves the stiffnesses ~8x): the first speed gets the full window and the others
    track that window's modes over the speed (MAC with them) instead of a window each; the value is
    the cold one and those speeds' window age restarts with the window they descend from."""
    ws = WarmStart(refresh=1000)
    r0 = _pegasus((1, 1, 1, 1), ws)
    n_speeds = len(r0.speeds)
    # the first evaluation: one window (lowest speed), the others tracked over the speed; the cold value
    assert r0.value == pytest.approx(_pegasus((1, 1, 1, 1), None).value, abs=1e-10), ws.reasons
    assert ws.n_windows == 1 and ws.n_speed_track == n_speeds - 1, ws.reasons
    rng = np.random.default_rng(5)
    for sm in ws.tracked:
        n, k = sm.right.shape
        sm.right[:] = rng.standard_normal((n, k)) + 1j * rng.standard_normal((n, k))
        sm.left[:] = rng.standard_normal((n, k))
    ws.history = ws.history[-1:]
    s = (1.1, 1.05, 0.9, 1.1)
    rw = _pegasus(s, ws)
    rc = _pegasus(s, None)
    assert rw.value == pytest.approx(rc.value, abs=1e-10), ws.reasons
    assert ws.n_windows == 2 and ws.n_speed_cold == 1 and ws.n_speed_track == 2 * (n_speeds - 1), ws.reasons
    assert ws.window_age == [0] * n_speeds
    assert any("from this design's window set at" in r for r in ws.reasons), ws.reasons


def _sys():
    return flutter_problem("pegasus", PEG_NODES).system


def test_warm_start_bad_input():
    with pytest.raises(ValueError, match="refresh = 0"):
        WarmStart(refresh=0)
    with pytest.raises(ValueError, match="max_step"):
        WarmStart(max_step=-1.0)
    with pytest.raises(ValueError, match="min_mac"):
        WarmStart(min_mac=1.5)


def test_lazy_refinement_skips_and_second_check_catches(monkeypatch):
    """Lazy refinement (modes far below the KS maximum left at their Ritz estimate): the value is
    the cold one, some modes are skipped; and when the first pass's lower bound of g_max is wrong
    (the leading mode's Ritz estimate made 2 1/s too high and every loaded estimate trusted, so
    modes that matter are skipped), the second check against the exact g_max refines them: still
    the cold value."""
    import wingmdao.stability.warmstart as S

    seq = [(1, 1, 1, 1), (1.05, 1.0, 0.97, 1.02), (1.5, 1.4, 0.7, 1.2)]
    ws = WarmStart(refresh=1000)
    for s in seq:
        assert _pegasus(s, ws).value == pytest.approx(_pegasus(s, None).value, abs=1e-10)
    assert ws.n_skipped > 0 and ws.n_lazy_redo == 0, (ws.n_skipped, ws.reasons)
    nolazy = WarmStart(refresh=1000, lazy=False)
    for s in seq:
        _pegasus(s, nolazy)
    assert nolazy.n_skipped == 0 and nolazy.n_refined > ws.n_refined

    orig = S._ritz

    def too_high(A, B, prev, *args, **kw):
        rz = orig(A, B, prev, *args, **kw)
        j = int(np.argmax(np.where(rz.loaded > 0.1, rz.lam.real, -np.inf)))
        rz.lam[j] += 2.0           # lower bound of g_max 2 1/s too high
        sure = rz.loaded > 0.1     # and every loaded estimate trusted with a tiny bound: skipped unless checked
        rz.error[sure], rz.trusted[sure] = 1e-9, True
        return rz

    ws2 = WarmStart(refresh=1000)
    _pegasus(seq[0], ws2)
    monkeypatch.setattr(S, "_ritz", too_high)
    for s in seq[1:]:
        assert _pegasus(s, ws2).value == pytest.approx(_pegasus(s, None).value, abs=1e-10)
    assert ws2.n_lazy_redo >= 1, ws2.reasons


def test_distance_is_the_largest_relative_block_change():
    """WarmStart.distance (vectorised over the parameter blocks) equals the block-by-block
    definition: max over blocks of max|p - ph| / max|ph|, blocks with max|ph| = 0 left out."""
    from wingmdao.timemarch.system import layout

    prob = flutter_problem("goland", 5)
    system = prob.system
    rng = np.random.default_rng(3)
    ph = rng.standard_normal(system.n_param)
    lay = layout(system.param_specs)
    first = next(sl for sl in lay.values() if sl.stop > sl.start)
    ph[first] = 0.0                      # a zero block: no scale, not counted
    for _ in range(5):
        p = ph + rng.standard_normal(system.n_param) * rng.uniform(0.01, 1.0)
        ref = 0.0
        for sl in lay.values():
            scale = float(np.max(np.abs(ph[sl]), initial=0.0))
            if scale > 0.0:
                ref = max(ref, float(np.max(np.abs(p[sl] - ph[sl]))) / scale)
        assert WarmStart.distance(system, p, ph) == ref
    assert WarmStart.distance(system, ph, ph) == 0.0


def test_small_eig_is_scipy_eig_without_the_wrapper():
    """``_small_eig`` (the Ritz pencil's QZ) gives SciPy's eigenvalues bitwise and its vectors up
    to the normalisation; a singular B gives an infinite eigenvalue, as SciPy's."""
    import scipy.linalg as sla

    from wingmdao.stability.warmstart import _small_eig

    rng = np.random.default_rng(11)
    for k in (1, 5, 6, 9):
        a = rng.standard_normal((k, k)) + 1j * rng.standard_normal((k, k))
        b = rng.standard_normal((k, k)) + 1j * rng.standard_normal((k, k))
        if k == 6:
            b[:, 0] = 0.0   # singular B: one infinite eigenvalue
        w, vl, vr = _small_eig(a, b)
        ws, vls, vrs = sla.eig(a, b, left=True, right=True)
        assert np.array_equal(w, ws)
        fin = np.isfinite(w)
        assert np.allclose(vr[:, fin] / np.linalg.norm(vr[:, fin], axis=0), vrs[:, fin], atol=1e-13)
        assert np.allclose(vl[:, fin] / np.linalg.norm(vl[:, fin], axis=0), vls[:, fin], atol=1e-13)
        for j in np.flatnonzero(fin):   # a v = w b v, u^H a = w u^H b
            v, u, tol = vr[:, j], vl[:, j].conj(), 1e-11 * (1 + abs(w[j]))
            assert np.linalg.norm(a @ v - w[j] * (b @ v)) <= tol * np.linalg.norm(v)
            assert np.linalg.norm(u @ a - w[j] * (u @ b)) <= tol * np.linalg.norm(u)
        assert (k == 6) == (not fin.all())


def test_params_at_packs_once_and_returns_fresh_arrays():
    """``FlutterProblem.params_at`` sets only the airspeed and Mach number on a design packed once:
    equal to the full packing at every speed, new arrays each call, bad speeds still refused."""
    from wingmdao.timemarch.system import layout

    prob = flutter_problem("pegasus", 5)
    lay = layout(prob.system.param_specs)
    for V in (40.0, 150.0, 240.0):
        p, q = prob.params_at(V)
        p_full, q_full, *_ = prob._pack_at(V)
        assert np.array_equal(p, p_full) and np.array_equal(q, q_full)
        assert p[lay["airspeed"]][0] == V and p[lay["mach"]][0] == pytest.approx(prob.mach_at(V))
        p[:] = np.nan
        q[:] = np.nan
    assert np.all(np.isfinite(prob.params_at(100.0)[0]))
    for bad in (0.0, -10.0, float("nan")):
        with pytest.raises(ValueError, match="airspeed"):
            prob.params_at(bad)
    with pytest.raises(ValueError, match="mach"):
        prob.params_at(1e4)   # supersonic
