"""Warm-started flutter constraint (WarmStart): equals the cold full-window constraint to round-off
along a sequence of designs, falls back to the full window by its rules, and never tracks a
different mode."""

import numpy as np
import pytest

from wingmdao.stability.cases import flutter_problem
from wingmdao.stability.sensitivity import WarmStart, damping_constraint

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


def test_warm_equals_cold_along_a_sequence_and_fallback():
    ws = WarmStart(refresh=1000, max_step=0.1)
    scales = [1.0, 1.01, 0.995, 1.02, 1.03, 1.3]   # the last step (> 10 %) must fall back
    for s in scales:
        rw = _eval(s, ws)
        rc = _eval(s, None)
        assert rw.value == pytest.approx(rc.value, abs=1e-10)
        assert np.abs(rw.gradient - rc.gradient).max() <= 1e-5 * np.abs(rc.gradient).max()  # cold: QZ round-off
        for a, b in zip(rw.eigenvalues, rc.eigenvalues):
            assert np.sort_complex(a) == pytest.approx(np.sort_complex(b), rel=1e-10)
    assert ws.n_warm == 4 and ws.n_cold == 2, (ws.n_warm, ws.n_cold, ws.reasons)
    assert "design step" in ws.reasons[-1]


def test_refresh_rule_and_wrong_mode_detected():
    ws = WarmStart(refresh=2)
    _eval(1.0, ws)
    assert not _eval(1.001, ws).cold
    assert _eval(1.002, ws).cold and "refresh" in ws.reasons[-1]
    # a corrupted history (the modes swapped for other eigenvalues) must not give another value
    ws2 = WarmStart(refresh=1000)
    _eval(1.0, ws2)
    sm = ws2.modes[1]
    sm.eigenvalues, sm.right, sm.left = sm.eigenvalues[::-1], sm.right[:, ::-1], sm.left[:, ::-1]  # swapped
    rw = _eval(1.0, ws2)
    assert rw.cold and "drifted" in ws2.reasons[-1] and rw.value == pytest.approx(_eval(1.0, None).value, abs=1e-10)


def test_warm_start_bad_input():
    with pytest.raises(ValueError, match="refresh = 0"):
        WarmStart(refresh=0)
    with pytest.raises(ValueError, match="max_step"):
        WarmStart(max_step=-1.0)
