"""Static-pivot sparse LU (``wingmdao.timemarch.static_lu``) and its use in the adjoint sweeps.

References are independent: SciPy's SuperLU/spsolve on the same matrices, and the SuperLU
sweeps of ``LinearizedHistory``. (The suite runs the CasADi functions interpreted; compiled
and interpreted results agree to round-off, tests/test_casadi_cache.py.)
"""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.timemarch.adjoint import LinearizedHistory
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.examples import nonlinear_chain_system
from wingmdao.timemarch.static_lu import StaticPivotLU, for_pattern, symbolic_lu


def _family(n=30, m=6, seed=0):
    """Banded nonsymmetric matrices with one pattern and a row order that needs pivoting."""
    rng = np.random.default_rng(seed)
    base = sp.random(n, n, density=0.12, random_state=rng) + sp.diags(rng.uniform(-1, 1, n - 1), 1)
    base = base + sp.diags(rng.uniform(-1, 1, n - 1), -1) + sp.diags(np.full(n, 0.05))
    base = sp.csc_matrix(base)
    base.sort_indices()
    mats = []
    for _ in range(m):
        vals = base.data * (1.0 + 0.05 * rng.standard_normal(base.nnz))
        mats.append(sp.csc_matrix((vals, base.indices, base.indptr), shape=(n, n)))
    return base, mats


def test_symbolic_structure_matches_a_dense_lu_without_pivoting():
    rng = np.random.default_rng(2)
    a = sp.random(12, 12, density=0.25, random_state=rng) + sp.eye(12) * 3.0
    a = sp.csc_matrix(a)
    a.sort_indices()
    l_struct, u_struct = symbolic_lu(12, a.indices, a.indptr)
    # dense Doolittle LU without pivoting on generic values: its nonzeros lie inside the structure
    d = a.toarray()
    for k in range(12):
        d[k + 1:, k] /= d[k, k]
        d[k + 1:, k + 1:] -= np.outer(d[k + 1:, k], d[k, k + 1:])
    for j in range(12):
        assert set(np.flatnonzero(np.abs(d[j + 1:, j]) > 1e-14) + j + 1) <= set(l_struct[j])
        assert set(np.flatnonzero(np.abs(d[:j, j]) > 1e-14)) <= set(u_struct[j])


def test_solves_agree_with_scipy_for_every_matrix_of_the_family():
    base, mats = _family()
    slu = StaticPivotLU(base.shape[0], base.indices, base.indptr, mats[0].data)
    factors = slu.factor_many(np.array([m.data for m in mats]))
    rng = np.random.default_rng(4)
    for m, f in zip(mats, factors):
        b = rng.standard_normal(m.shape[0])
        for trans, mat in (("N", m), ("T", m.T.tocsc())):
            x, res, berr = slu.solve(f, m.data, b, trans)
            np.testing.assert_allclose(x, spla.spsolve(mat, b), rtol=1e-8, atol=1e-10)
            np.testing.assert_allclose(res, b - mat @ x, atol=1e-12)
            assert berr == pytest.approx(slu.backward_error(m.data, x, b, trans), rel=1e-6, abs=1e-18)
            assert berr < 1e-10
    np.testing.assert_allclose(slu.factor(mats[2].data), factors[2])


def test_a_pivot_that_vanishes_is_reported_by_the_backward_error():
    """The reference's pivot order does not pivot; at another step that pivot is zero."""
    a0 = sp.csc_matrix(np.array([[4.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 4.0]]))
    a1 = sp.csc_matrix((np.where(np.arange(a0.nnz) == 0, 0.0, a0.data), a0.indices, a0.indptr), shape=(3, 3))
    slu = StaticPivotLU(3, a0.indices, a0.indptr, a0.data)
    assert np.array_equal(slu.perm_r, [0, 1, 2])
    x, _, berr = slu.solve(slu.factor(a1.data), a1.data, np.ones(3))
    assert not berr <= 1e-12   # inf or NaN: the caller falls back


def _chain_history(n_time=60):
    sysm = nonlinear_chain_system(25)     # 50 states: above the dense limit
    rng = np.random.default_rng(1)
    p = np.r_[1.3, 0.4, 0.8, rng.uniform(2.0, 4.0, 25)]
    t = np.linspace(0.0, 0.6, n_time)
    Q = np.outer(1.0 + np.sin(7 * t), rng.uniform(0.5, 1.5, 25))
    h = march(sysm, t, p, Q)
    return sysm, t, h.states, p, Q


@pytest.mark.parametrize("initial", ["static", "state"])
def test_static_sweeps_equal_the_superlu_sweeps(initial):
    sysm, t, X, p, Q = _chain_history()
    ref = LinearizedHistory(sysm, t, X, p, Q, initial=initial, lu="superlu")
    lin = LinearizedHistory(sysm, t, X, p, Q, initial=initial, lu="static")
    assert lin.lu_method == "static"
    rng = np.random.default_rng(8)
    g = rng.standard_normal(X.shape)
    for sweep in ("solve_adjoint", "solve_tangent"):
        a, b = getattr(lin, sweep)(g), getattr(ref, sweep)(g)
        np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-10 * np.max(np.abs(b)))
    # the static solution satisfies the stacked equations (independent of either solver)
    np.testing.assert_allclose(lin.apply_transpose(lin.solve_adjoint(g)), g, atol=1e-9)
    np.testing.assert_allclose(lin.apply(lin.solve_tangent(g)), g, atol=1e-9)
    assert lin.static_stats["fallback"] == 0


def test_static_sweep_falls_back_to_superlu_when_the_pivots_go_bad(monkeypatch):
    sysm, t, X, p, Q = _chain_history(n_time=30)
    lin = LinearizedHistory(sysm, t, X, p, Q, lu="static")
    slu, factors = lin._static_lu()
    lin._static = (slu, np.full_like(factors, np.nan))      # every static solve fails
    ref = LinearizedHistory(sysm, t, X, p, Q, lu="superlu")
    g = np.random.default_rng(2).standard_normal(X.shape)
    np.testing.assert_allclose(lin.solve_adjoint(g), ref.solve_adjoint(g), rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(lin.solve_tangent(g), ref.solve_tangent(g), rtol=1e-12, atol=1e-14)
    assert lin.static_stats["fallback"] == 2 * (t.size - 1)


def test_zero_entries_of_the_pattern_are_dropped_but_the_matrix_is_unchanged():
    sysm, t, X, p, Q = _chain_history(n_time=10)
    lin = LinearizedHistory(sysm, t, X, p, Q, lu="superlu")
    assert lin.m_rows.size <= lin.a_rows.size
    for n in (0, 1, 5):
        full = sp.csc_matrix((lin.a_data[n], lin.a_rows, lin.a_indptr), shape=(lin.n_state,) * 2)
        np.testing.assert_array_equal(lin.newton_matrix(n).toarray(), full.toarray())


def test_patterns_share_one_generated_solver():
    base, mats = _family(n=20, m=2, seed=5)
    a = for_pattern(20, base.indices, base.indptr, mats[0].data)
    assert for_pattern(20, base.indices, base.indptr, mats[1].data) is a


def test_lu_option_is_checked():
    sysm, t, X, p, Q = _chain_history(n_time=5)
    with pytest.raises(ValueError, match="lu must be"):
        LinearizedHistory(sysm, t, X, p, Q, lu="klu")


def test_beam_totals_with_the_static_lu_equal_the_superlu_totals():
    """BeamDynamics (10 nodes, 120 steps, gust-like tip load): the KS-of-root-moment gradient with
    respect to the section stiffness through the static-pivot LU equals the SuperLU one."""
    import openmdao.api as om

    from wingmdao.components.beam import BeamDynamics
    from wingmdao.components.ks import KSAggregate

    n, nt = 10, 120
    t = np.linspace(0.0, 0.6, nt)
    y = np.linspace(0.0, 8.0, n)
    rng = np.random.default_rng(3)
    vals = {
        "node_positions": np.column_stack([np.zeros(n), y, 0.05 * y]),
        "node_euler_angles": np.zeros((n, 3)),
        "stiffness_csn": np.tile(np.diag([2e6, 1.5e6, 1e7]), (n, 1, 1)) * rng.uniform(0.8, 1.2, (n, 1, 1)),
        "compliance_csn": np.tile([1e-9, 1e-9, 1e-9], (n, 1)),
        "mass_per_length": np.full(n, 20.0),
        "inertia_per_length": np.tile(np.diag([0.1, 0.2, 0.1]), (n, 1, 1)),
    }
    pf = np.zeros((nt, n, 3))
    pf[:, -1, 2] = 3e3 * np.sin(np.pi * np.clip(t / 0.3, 0.0, 1.0)) ** 2
    pf[:, -1, 0] = 400.0 * t
    vals["point_force"] = pf
    grads, stats = {}, {}
    for lu in ("superlu", "static"):
        prob = om.Problem(reports=False)
        prob.model.add_subsystem("beam", BeamDynamics(num_nodes=n, time=t, lu=lu), promotes=["*"])
        w = np.zeros((nt, n, 18))
        w[:, 0, 9:12] = 1e-4
        prob.model.add_subsystem("pick", om.ExecComp("g = w * states", w={"val": w, "shape": w.shape},
                                                     states={"shape": w.shape}, g={"shape": w.shape},
                                                     has_diag_partials=True), promotes=["*"])
        prob.model.add_subsystem("ks", KSAggregate(families={"root": (nt, n, 18)}, rho_ks=20.0))
        prob.model.connect("g", "ks.g_root")
        prob.setup(mode="rev")
        for k, v in vals.items():
            prob.set_val(k, v)
        prob.run_model()
        grads[lu] = prob.compute_totals(of=["ks.ks_root"], wrt=["stiffness_csn"])["ks.ks_root", "stiffness_csn"]
        lin = prob.model.beam._lin
        stats[lu] = (lin.lu_method, dict(lin.static_stats))
    assert stats["static"][0] == "static" and stats["superlu"][0] == "superlu"
    assert stats["static"][1]["fallback"] == 0
    scale = np.max(np.abs(grads["superlu"]))
    assert scale > 0
    np.testing.assert_allclose(grads["static"], grads["superlu"], rtol=0, atol=1e-10 * scale)


def test_nonzero_pattern_only_grows_across_histories():
    """An entry that is zero in one history but not in an earlier one of the same system stays in
    the pattern (no new pattern, so no new static-pivot LU, when a design change zeroes it): here
    the couplings of masses 4 and 5 through spring 5, zero once that spring is removed."""
    sysm, t, X, p, Q = _chain_history(n_time=10)
    spring_removed = p.copy()
    spring_removed[3 + 5] = 0.0
    first = LinearizedHistory(sysm, t, X, p, Q, lu="superlu")
    second = LinearizedHistory(sysm, t, X, spring_removed, Q, lu="superlu")
    assert np.array_equal(second.m_rows, first.m_rows) and np.array_equal(second.m_indptr, first.m_indptr)
    fresh = type(sysm).__new__(type(sysm))       # the same system without the memory of `first`
    fresh.__dict__.update({k: v for k, v in sysm.__dict__.items() if k != "_linearized_history_nonzeros"})
    alone = LinearizedHistory(fresh, t, X, spring_removed, Q, lu="superlu")
    assert alone.m_rows.size == first.m_rows.size - 2      # dR_4/du_5 and dR_5/du_4 dropped
    np.testing.assert_array_equal(second.newton_matrix(3).toarray(), alone.newton_matrix(3).toarray())
