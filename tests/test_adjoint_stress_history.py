"""The time-history adjoint through the whole chain, as issue #3 names it: KS of the stresses over a
200-step history with respect to every wall thickness of a 10-station beam.

Chain: thicknesses -> box section (App. F) -> nonlinear beam, BDF2 march (App. A, Eq. 3.4-3.7) ->
internal loads -> corner/mid-corner/flange stresses (Sec. 4.4.2) -> KS over space and time
(Eq. 4.53-4.55). References: central finite differences of the whole march (independent of every
derivative in the code) and forward mode (tangent sweeps, a different recurrence from the
adjoint's transposed one).
"""

import numpy as np
import pytest

from wingmdao.cases.wing_box import tip_load_case, wing_geometry
from wingmdao.cases.wing_box.problem import analysis_problem
from wingmdao.sizing import WALL_VARS

pytestmark = pytest.mark.filterwarnings("ignore::openmdao.utils.om_warnings.DerivativesWarning")  # fwd on purpose

FAMILIES = ("vm", "ss_tension", "cent_pos")
N_STEPS = 200


def _problem(mode):
    geometry, _, _, _ = wing_geometry("combined", (3, 3, 3))       # 10 stations, swept, tapered
    n = geometry.num_nodes
    time = np.linspace(0.0, 1.0, N_STEPS)
    # tip force and torque raised over 0.1 s, then held: the box rings about the static state
    case = tip_load_case("dyn", n, (2e4, 0.0, 3e5), (0.0, 1e5, 0.0), FAMILIES, time=time, ramp_time=0.1)
    rng = np.random.default_rng(5)                                   # non-uniform design
    walls = {w: rng.uniform(0.05, 0.15, n) for w in WALL_VARS}
    prob = analysis_problem(geometry, case, walls, design_vars=True, mode=mode)
    prob.run_model()
    return prob, walls


@pytest.fixture(scope="module")
def derivatives():
    of = [f"cases.dyn.ks_{f}" for f in FAMILIES]
    out = {}
    for mode in ("rev", "fwd"):
        prob, walls = _problem(mode)
        tot = prob.compute_totals(of=of, wrt=list(WALL_VARS))
        out[mode] = {k: np.asarray(v).ravel() for k, v in tot.items()}
    # central differences of the whole analysis, every thickness of every wall
    fd = {}
    for w in WALL_VARS:
        cols = {o: np.zeros(walls[w].size) for o in of}
        for i in range(walls[w].size):
            h = 1e-5 * walls[w][i]
            vals = []
            for sign in (1.0, -1.0):
                t = walls[w].copy()
                t[i] += sign * h
                prob.set_val(w, t, units="m")
                prob.run_model()
                vals.append({o: float(prob.get_val(o)[0]) for o in of})
            prob.set_val(w, walls[w], units="m")
            for o in of:
                cols[o][i] = (vals[0][o] - vals[1][o]) / (2 * h)
        for o in of:
            fd[o, w] = cols[o]
    out["fd"] = fd
    assert prob.get_val("cases.dyn.states").shape[0] == N_STEPS
    return out


@pytest.mark.slow
def test_adjoint_matches_central_differences_for_every_thickness(derivatives):
    """1e-5 relative: each entry against its block's largest, and entries above 1 % of it on
    their own."""
    for key, fd in derivatives["fd"].items():
        ad = derivatives["rev"][key]
        scale = np.abs(fd).max()
        assert scale > 0, key
        assert np.max(np.abs(ad - fd)) <= 1e-5 * scale, (key, np.max(np.abs(ad - fd)) / scale)
        big = np.abs(fd) > 1e-2 * scale
        np.testing.assert_allclose(ad[big], fd[big], rtol=1e-5, err_msg=str(key))


@pytest.mark.slow
def test_forward_and_reverse_mode_agree(derivatives):
    for key, rev in derivatives["rev"].items():
        fwd = derivatives["fwd"][key]
        assert np.max(np.abs(fwd - rev)) <= 1e-10 * np.max(np.abs(rev)), key


def test_memory_lean_chain_gives_the_same_totals(monkeypatch):
    """Checkpointed beam adjoint (Jacobians re-evaluated 30 steps at a time) and matrix-free
    pointwise internal loads and stresses (Jacobians re-evaluated in chunks of 500 points) and
    matrix-free KS: the KS totals equal the default (full storage, declared partials) ones to 1e-10."""
    from wingmdao.components import ks, pointwise, time_history

    of = [f"cases.dyn.ks_{f}" for f in FAMILIES]
    ref = _problem("rev")[0].compute_totals(of=of, wrt=list(WALL_VARS))
    monkeypatch.setattr(time_history, "MATRIX_FREE_ABOVE", 0)
    monkeypatch.setattr(time_history, "ADJOINT_MEMORY_MB", 10.7)   # 89 kB per step: segments of 15 steps
    monkeypatch.setattr(pointwise, "POINTWISE_MATRIX_FREE_ABOVE", 0)
    monkeypatch.setattr(pointwise, "POINTWISE_JAC_CACHE_BYTES", 0.0)
    monkeypatch.setattr(pointwise, "POINT_CHUNK", 500)
    monkeypatch.setattr(ks, "KS_MATRIX_FREE_ABOVE", 0)
    prob, _ = _problem("rev")
    beam = next(s for s in prob.model.system_iter(recurse=True) if isinstance(s, time_history.TimeHistoryComponent))
    assert beam.checkpoint_every is not None and beam.checkpoint_every < N_STEPS
    stress = [s for s in prob.model.system_iter(recurse=True) if isinstance(s, pointwise.PointwiseCasadiComponent)]
    assert stress and all(s.matrix_free for s in stress if s.num_points >= N_STEPS)
    assert all(s.matrix_free for s in prob.model.system_iter(recurse=True) if isinstance(s, ks.KSAggregate))
    lean = prob.compute_totals(of=of, wrt=list(WALL_VARS))
    for key, val in ref.items():
        np.testing.assert_allclose(lean[key], val, rtol=1e-10, atol=1e-10 * np.max(np.abs(val)), err_msg=str(key))
