"""Static-pivot sparse LU (``wingmdao.timemarch.static_lu``, C kernel ``lu_kernel.c``) and its
use in the adjoint sweeps.

References are independent: SciPy's SuperLU/spsolve on the same matrices, and the SuperLU
sweeps of ``LinearizedHistory``. The suite runs with ``WINGMDAO_JIT=0`` (tests/conftest.py),
where the static LU falls back to SuperLU; the fixture ``kernel_on`` (tests/conftest.py) compiles the kernel into a
temporary cache and turns it on for these tests.
"""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.timemarch.adjoint import LinearizedHistory
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.examples import nonlinear_chain_system
from wingmdao.timemarch import adjoint as adjoint_module
from wingmdao.timemarch import lu_orders, static_lu
from wingmdao.timemarch.static_lu import StaticPivotLU, for_pattern, symbolic_lu
from wingmdao.utils import c_library
from wingmdao.utils import casadi_cache as cc

needs_gcc = pytest.mark.skipif(cc.compiler() is None, reason="needs gcc")


def _family(n=30, m=6, seed=0):
    """Banded nonsymmetric matrices with one pattern and a row order that needs pivoting."""
    rng = np.random.default_rng(seed)
    base = sp.random(n, n, density=0.12, random_state=rng) + sp.diags(rng.uniform(-1, 1, n - 1), 1)
    base = base + sp.diags(rng.uniform(-1, 1, n - 1), -1) + sp.diags(np.full(n, 0.05))
    base = sp.csc_matrix(base)
    base.sort_indices()
    return base, _perturbed(base, m, rng)


def _perturbed(a, m, rng):
    """``m`` matrices of ``a``'s pattern, each value scaled by 1 + 5 % noise."""
    return [sp.csc_matrix((a.data * (1.0 + 0.05 * rng.standard_normal(a.nnz)), a.indices, a.indptr), shape=a.shape)
            for _ in range(m)]


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


@needs_gcc
@pytest.mark.parametrize("seed, n, density", [(3, 40, 0.08), (5, 120, 0.03), (7, 7, 0.5)])
def test_compiled_symbolic_structure_equals_the_python_reference(kernel_on, seed, n, density):
    rng = np.random.default_rng(seed)
    a = sp.csc_matrix(sp.random(n, n, density=density, random_state=rng) + sp.eye(n))
    a.sort_indices()
    l_struct, u_struct = symbolic_lu(n, a.indices, a.indptr)
    # unsorted rows within columns (the C routine must not rely on their order)
    rows = a.indices.copy()
    for j in range(n):
        seg = slice(a.indptr[j], a.indptr[j + 1])
        rows[seg] = rng.permutation(rows[seg])
    lp, li, up, ui = static_lu.symbolic_lu_compiled(static_lu.kernel(), n, rows, a.indptr)
    for j in range(n):
        assert li[lp[j]:lp[j + 1]].tolist() == l_struct[j].tolist()
        assert ui[up[j]:up[j + 1]].tolist() == u_struct[j].tolist()


@needs_gcc
def test_factorization_work_of_a_dense_matrix_is_the_closed_form(kernel_on):
    """Dense n x n, diagonally dominant (no row exchange): sum_k (n - 1 - k)^2 = (n-1) n (2n-1) / 6
    multiply-adds, in any column order."""
    n = 8
    a = sp.csc_matrix(np.random.default_rng(1).uniform(0.1, 1.0, (n, n)) + n * np.eye(n))
    a.sort_indices()
    expected = (n - 1) * n * (2 * n - 1) // 6
    assert static_lu.factorization_work(n, a.indices, a.indptr, a.data) == expected
    assert static_lu.factorization_work(n, a.indices, a.indptr, a.data, np.arange(n)[::-1]) == expected


def _arrowhead_blocks(n_block, block, hub, seed):
    """Block-diagonal CSC matrix: in every block unknown ``hub`` couples to all the others, which
    couple only to themselves (diagonally dominant: no row exchange)."""
    rng = np.random.default_rng(seed)
    b = np.eye(block) * 2.0 * block
    b[hub, :] = b[:, hub] = rng.uniform(0.5, 1.0, block)
    b[hub, hub] = 2.0 * block
    a = sp.csc_matrix(sp.block_diag([b] * n_block))
    a.eliminate_zeros()
    a.sort_indices()
    return a.shape[0], a.indices, a.indptr, a.data


@needs_gcc
def test_joint_column_order_search_finds_the_no_fill_order_of_arrowhead_blocks(kernel_on):
    """Hub first fills its block: dense LU, (b-1) b (2b-1)/6 multiply-adds per block. Any order
    with the hub unknowns last has no fill: one multiply-add per spoke. Two matrices with hubs 0
    and 1: the joint search must reach b - 1 per block in both (b - 2 spokes plus the other hub)."""
    n_block, block = 5, 4
    mats = [_arrowhead_blocks(n_block, block, hub, seed) for hub, seed in ((0, 1), (1, 2))]
    dense = (block - 1) * block * (2 * block - 1) // 6
    assert static_lu.factorization_work(*mats[0]) == n_block * dense
    local, works = static_lu.search_joint_block_order(mats, block, passes=4)
    assert sorted(local.tolist()) == list(range(block))
    assert works == [n_block * (block - 1)] * 2
    assert set(local[-2:].tolist()) == {0, 1}
    single, work = static_lu.search_block_order(*mats[0], block, passes=4)
    assert work == n_block * (block - 1) and 0 in single[-2:]   # a hub second to last has one spoke left


@needs_gcc
def test_compiled_symbolic_reports_a_structural_zero_pivot(kernel_on):
    a = sp.csc_matrix(np.array([[0.0, 1.0], [1.0, 0.0]]))
    with pytest.raises(ValueError, match="column 0: zero pivot"):
        static_lu.symbolic_lu_compiled(static_lu.kernel(), 2, a.indices, a.indptr)


@needs_gcc
def test_solves_agree_with_scipy_for_every_matrix_of_the_family(kernel_on):
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


@needs_gcc
def test_a_pivot_that_vanishes_is_reported_by_the_backward_error(kernel_on):
    """The reference's pivot order does not pivot; at another step that pivot is zero."""
    a0 = sp.csc_matrix(np.array([[4.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 4.0]]))
    a1 = sp.csc_matrix((np.where(np.arange(a0.nnz) == 0, 0.0, a0.data), a0.indices, a0.indptr), shape=(3, 3))
    slu = StaticPivotLU(3, a0.indices, a0.indptr, a0.data)
    assert np.array_equal(slu.perm_r, [0, 1, 2])
    x, _, berr = slu.solve(slu.factor(a1.data), a1.data, np.ones(3))
    assert not berr <= 1e-12   # inf or NaN: the caller falls back
    assert slu.solve(slu.factor(a0.data), a0.data, np.ones(3))[2] < 1e-15


def _backward_error_reference(m, x, b):
    """Arioli, Demmel & Duff (SIAM J. Matrix Anal. Appl. 10(2), 1989, Sec. 3), coded here: the
    componentwise backward error of the rows whose scale (|M| |x| + |b|)_i exceeds 1000 n eps
    (||M_i||_inf ||x||_inf + |b_i|), the normwise measure |r_i| / ((|M| |x|)_i + ||M_i||_inf
    ||x||_inf) on the others."""
    m = sp.csr_matrix(m)
    r, ax = np.abs(b - m @ x), abs(m) @ np.abs(x)
    rown, xn = abs(m).max(axis=1).toarray().ravel(), np.max(np.abs(x))
    small = ax + np.abs(b) <= 1000 * m.shape[0] * np.finfo(float).eps * (rown * xn + np.abs(b))
    return float(np.max(np.where(small, r / (ax + rown * xn), r / (ax + np.abs(b)))))


@needs_gcc
def test_backward_error_measures_round_off_rows_normwise(kernel_on):
    """A solution component that is zero in exact arithmetic and round-off in the computed one
    (the mirror components of a symmetric half model's adjoint) has a componentwise backward
    error of 1 in its row when that row has one entry; the kernel measures such rows normwise
    (Arioli, Demmel & Duff), the others componentwise, as the reference coded here."""
    base, mats = _family()
    slu = StaticPivotLU(base.shape[0], base.indices, base.indptr, mats[0].data)
    rng = np.random.default_rng(11)
    m = mats[1]
    for trans, mat in (("N", m), ("T", m.T.tocsc())):
        x = spla.spsolve(mat, rng.standard_normal(m.shape[0]))
        b = mat @ x + 1e-14 * rng.standard_normal(m.shape[0])     # every row componentwise
        ref = _backward_error_reference(mat, x, b)
        assert slu.backward_error(m.data, x, b, trans) == pytest.approx(ref, rel=1e-12)
        cw = np.max(np.abs(b - mat @ x) / (abs(mat) @ np.abs(x) + np.abs(b)))
        assert ref == pytest.approx(cw, rel=1e-12)
    # a block-diagonal matrix: x[-1] is zero in exact arithmetic (b[-1] = 0, one entry in its row)
    a = sp.csc_matrix(sp.block_diag([m, sp.identity(1)]))
    a.sort_indices()
    big = StaticPivotLU(a.shape[0], a.indices, a.indptr, a.data)
    x = np.r_[spla.spsolve(m, rng.standard_normal(m.shape[0])), 1e-20]
    b = np.r_[m @ x[:-1], 0.0]
    berr = big.backward_error(a.data, x, b)
    assert np.max(np.abs(b - a @ x) / (abs(a) @ np.abs(x) + np.abs(b))) == 1.0     # componentwise
    assert berr == pytest.approx(_backward_error_reference(a, x, b), rel=1e-12)
    assert berr < 1e-14
    assert big.backward_error(a.data, np.r_[x[:-1], 1e-3], b) > 1e-4            # not round-off


def _chain_history(n_time=60):
    sysm = nonlinear_chain_system(25)     # 50 states: above the dense limit
    rng = np.random.default_rng(1)
    p = np.r_[1.3, 0.4, 0.8, rng.uniform(2.0, 4.0, 25)]
    t = np.linspace(0.0, 0.6, n_time)
    Q = np.outer(1.0 + np.sin(7 * t), rng.uniform(0.5, 1.5, 25))
    h = march(sysm, t, p, Q)
    return sysm, t, h.states, p, Q


@needs_gcc
@pytest.mark.parametrize("initial", ["static", "state"])
def test_static_sweeps_equal_the_superlu_sweeps(initial, kernel_on):
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
    # the sweeps factored with the C kernel's batched (lane) factorization, not SuperLU
    assert lin.static_stats["factored"] >= t.size - 2


@needs_gcc
def test_static_sweep_falls_back_to_superlu_when_every_solve_fails(kernel_on, monkeypatch):
    sysm, t, X, p, Q = _chain_history(n_time=30)
    monkeypatch.setattr(adjoint_module, "STATIC_LU_TOL", -1.0)     # no backward error is accepted
    lin = LinearizedHistory(sysm, t, X, p, Q, lu="static")
    ref = LinearizedHistory(sysm, t, X, p, Q, lu="superlu")
    g = np.random.default_rng(2).standard_normal(X.shape)
    np.testing.assert_allclose(lin.solve_adjoint(g), ref.solve_adjoint(g), rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(lin.solve_tangent(g), ref.solve_tangent(g), rtol=1e-12, atol=1e-14)
    assert lin.lu_method == "static"
    # each sweep first takes the pivot order of MAX_REPIVOTS failing steps (which fail again),
    # then solves every failing step with SuperLU
    assert lin.static_stats["repivoted"] == 2 * adjoint_module.MAX_REPIVOTS
    assert lin.static_stats["fallback"] == 2 * (t.size - 1)
    assert lin.static_stats["refined"] == 2 * (t.size - 1) + lin.static_stats["repivoted"]


@needs_gcc
def test_a_bad_pivot_order_is_caught_per_step_and_the_sweeps_stay_exact(kernel_on, monkeypatch):
    """Static pivots chosen without pivoting (identity order) for a matrix family whose middle
    steps have a vanishing (1, 1) entry: the first of those steps in sweep order fails the
    backward-error check, the sweep takes that step's own pivot order and goes on with it; both
    sweeps equal the SuperLU sweeps. With re-pivoting off, the failing steps are solved by
    SuperLU."""
    sysm, t, X, p, Q = _chain_history(n_time=30)
    lin = LinearizedHistory(sysm, t, X, p, Q, lu="static")
    ref = LinearizedHistory(sysm, t, X, p, Q, lu="superlu")
    n = lin.n_state
    # the first diagonal entry of A_n scaled to ~0 at steps 10..14 (the same change for both)
    first = lin.m_indptr[0] + np.flatnonzero(lin.m_rows[lin.m_indptr[0]:lin.m_indptr[1]] == 0)[0]
    for h in (lin, ref):
        h.m_data[10:15, first] = 1e-300
        h._rep = np.arange(h.n_time)
        h._factors.clear()
    lin._static = StaticPivotLU(n, lin.m_rows, lin.m_indptr, perm_r=np.arange(n))
    g = np.random.default_rng(5).standard_normal(X.shape)
    a, b = lin.solve_adjoint(g), ref.solve_adjoint(g)
    np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-10 * np.max(np.abs(b)))
    assert lin.static_stats["fallback"] == 0
    assert 1 <= lin.static_stats["repivoted"] <= 2
    a, b = lin.solve_tangent(g), ref.solve_tangent(g)
    np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-10 * np.max(np.abs(b)))
    assert lin.static_stats["fallback"] == 0
    # without re-pivoting the failing steps go to SuperLU one by one
    monkeypatch.setattr(adjoint_module, "MAX_REPIVOTS", 0)
    lin._static = StaticPivotLU(n, lin.m_rows, lin.m_indptr, perm_r=np.arange(n))
    lin.static_stats.update(fallback=0, repivoted=0)
    a, b = lin.solve_adjoint(g), ref.solve_adjoint(g)
    np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-10 * np.max(np.abs(b)))
    assert 1 <= lin.static_stats["fallback"] <= 5
    assert lin.static_stats["repivoted"] == 0


def test_zero_entries_of_the_pattern_are_dropped_but_the_matrix_is_unchanged():
    sysm, t, X, p, Q = _chain_history(n_time=10)
    lin = LinearizedHistory(sysm, t, X, p, Q, lu="superlu")
    assert lin.m_rows.size <= lin.a_rows.size
    for n in (0, 1, 5):
        full = sp.csc_matrix((lin.a_data[n], lin.a_rows, lin.a_indptr), shape=(lin.n_state,) * 2)
        np.testing.assert_array_equal(lin.newton_matrix(n).toarray(), full.toarray())


@needs_gcc
def test_patterns_share_one_solver_per_pivot_order(kernel_on):
    base, mats = _family(n=20, m=2, seed=5)
    a = for_pattern(20, base.indices, base.indptr, mats[0].data)
    assert for_pattern(20, base.indices, base.indptr, mats[0].data.copy()) is a
    b = for_pattern(20, base.indices, base.indptr, mats[1].data)
    assert (b is a) == np.array_equal(b.perm_r, a.perm_r)


def test_lu_option_is_checked():
    sysm, t, X, p, Q = _chain_history(n_time=5)
    with pytest.raises(ValueError, match="lu must be"):
        LinearizedHistory(sysm, t, X, p, Q, lu="klu")


@needs_gcc
def test_beam_totals_with_the_static_lu_equal_the_superlu_totals(kernel_on):
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


# ---------------------------------------------------------------- the kernel's library
@needs_gcc
def test_a_kernel_library_that_does_not_load_is_rebuilt(tmp_path, monkeypatch):
    """A library whose manifest matches but that does not load (a foreign or damaged file, its
    manifest rewritten) is rebuilt, not left for the SuperLU fallback of every later run."""
    monkeypatch.setenv(cc.ENV_CACHE, str(tmp_path))
    monkeypatch.setattr(c_library, "_LOADED", {})
    path = c_library.compile_source(static_lu.SOURCE, "lu_kernel")
    path.write_bytes(b"not a shared library" * 100)
    size, digest = cc.file_digest(path)
    cc.manifest_path(path).write_text(f"{size} {digest}\n")
    cc.verify(path)                                  # the manifest matches the garbage
    lib = c_library.load(static_lu.SOURCE, "lu_kernel", force=True)
    assert lib is not None
    assert path.read_bytes()[:4] == b"\x7fELF"       # rebuilt
    cc.verify(path)


@needs_gcc
def test_kernel_library_is_cached_verified_and_rebuilt(tmp_path, monkeypatch):
    """One compile per source and flags; a second load (new process: cleared registry) calls no
    compiler; a corrupted library fails its manifest check and is rebuilt."""
    import subprocess

    monkeypatch.setenv(cc.ENV_CACHE, str(tmp_path))
    monkeypatch.setattr(c_library, "_LOADED", {})
    path = c_library.compile_source(static_lu.SOURCE, "lu_kernel")
    assert path.parent == tmp_path and cc.manifest_path(path).exists()
    cc.verify(path)
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []   # no leftovers

    def no_gcc(*args, **kwargs):
        raise AssertionError("gcc called on a cache hit")

    monkeypatch.setattr(subprocess, "run", no_gcc)
    assert c_library.compile_source(static_lu.SOURCE, "lu_kernel") == path
    monkeypatch.undo()
    monkeypatch.setenv(cc.ENV_CACHE, str(tmp_path))
    path.write_bytes(path.read_bytes()[:100])       # truncated
    with pytest.raises(cc.CompileError):
        cc.verify(path)
    assert c_library.compile_source(static_lu.SOURCE, "lu_kernel") == path
    cc.verify(path)


def test_without_the_kernel_the_static_lu_is_superlu_and_silent(monkeypatch, recwarn):
    """WINGMDAO_LU_KERNEL=0 (or WINGMDAO_JIT=0, no gcc): lu="static" runs SuperLU, no warning."""
    monkeypatch.setenv(static_lu.ENV_KERNEL, "0")
    sysm, t, X, p, Q = _chain_history(n_time=12)
    lin = LinearizedHistory(sysm, t, X, p, Q)          # the default lu="static"
    ref = LinearizedHistory(sysm, t, X, p, Q, lu="superlu")
    assert lin.lu_method == "superlu" and static_lu.kernel() is None
    g = np.random.default_rng(1).standard_normal(X.shape)
    np.testing.assert_array_equal(lin.solve_adjoint(g), ref.solve_adjoint(g))
    assert not [w for w in recwarn if "kernel" in str(w.message)]


@needs_gcc
def test_kernel_products_and_assembly_equal_numpy(kernel_on):
    """The kernel's Newton-matrix assembly and Jacobian-history products (used whenever it is
    compiled) equal the NumPy code they replace."""
    sysm, t, X, p, Q = _chain_history(n_time=20)
    lin = LinearizedHistory(sysm, t, X, p, Q)
    assert lin._lib is not None
    blk = lin._make_blocks(0, lin.n_time, lin.n_time)
    ref = np.zeros_like(blk.m_data)
    ref[:, lin._slot[lin._pos_x[lin._x_nz]]] = blk.jx[:, lin._x_nz]
    ref[:, lin._slot[lin._pos_d[lin._d_nz]]] += lin.coef[:, :1] * blk.jxd[:, lin._d_nz]
    np.testing.assert_array_equal(blk.m_data, ref)
    np.testing.assert_array_equal(blk.same[1:], np.all(ref[1:] == ref[:-1], axis=1))
    np.testing.assert_array_equal(static_lu.nonzero_columns(lin._lib, blk.jx), np.any(blk.jx != 0, axis=0))
    steady = np.repeat(ref[:1], 4, axis=0)                # identical rows are found
    assert static_lu.nonzero_columns(lin._lib, steady).sum() == np.count_nonzero(ref[0])
    rng = np.random.default_rng(3)
    lam = rng.standard_normal(X.shape)
    lib, lin._lib = lin._lib, None
    numpy_products = (lin.apply(lam), lin.apply_transpose(lam), lin.param_product(lam), lin.forcing_product(lam))
    lin._lib = lib
    kernel_products = (lin.apply(lam), lin.apply_transpose(lam), lin.param_product(lam), lin.forcing_product(lam))
    for a, b in zip(kernel_products, numpy_products):
        np.testing.assert_allclose(a, b, rtol=1e-13, atol=1e-13 * np.max(np.abs(b)))


@needs_gcc
def test_linear_system_shares_factors_and_matches_superlu(kernel_on):
    """Spring-mass-damper (linear, 2 states): the Newton matrices of the BDF2 steps are identical
    (the kernel's assembly flags them and factors once per run); the adjoint and tangent sweeps
    through the kernel equal SuperLU's (dense LAPACK at this size)."""
    from wingmdao.timemarch.examples import SMD_TABLE_4_18, spring_mass_damper_system

    sysm = spring_mass_damper_system()
    p = np.array([SMD_TABLE_4_18["mass"], SMD_TABLE_4_18["damping"], SMD_TABLE_4_18["stiffness"]])
    t = np.linspace(0.0, 1.0, 101)
    h = march(sysm, t, p, np.zeros((t.size, 1)), initial="state", x_init=[1.0, 0.0])
    lin = LinearizedHistory(sysm, t, h.states, p, np.zeros((t.size, 1)), initial="state")
    ref = LinearizedHistory(sysm, t, h.states, p, np.zeros((t.size, 1)), initial="state", lu="superlu")
    assert lin.lu_method == "static" and lin._full.same[3:].all() and not lin._full.same[1]
    g = np.random.default_rng(0).standard_normal(h.states.shape)
    for sweep in ("solve_adjoint", "solve_tangent"):
        np.testing.assert_allclose(getattr(lin, sweep)(g), getattr(ref, sweep)(g), rtol=1e-10, atol=1e-12)


@needs_gcc
def test_new_nonzeros_found_in_the_assembly_pass_grow_the_pattern(kernel_on):
    """With the kernel the pattern of earlier histories is checked during the assembly: a history
    with nonzeros outside it (spring 5 back after a history without it) gets the grown pattern,
    and its sweeps equal SuperLU's."""
    sysm, t, X, p, Q = _chain_history(n_time=10)
    spring_removed = p.copy()
    spring_removed[3 + 5] = 0.0
    fresh = type(sysm).__new__(type(sysm))
    fresh.__dict__.update({k: v for k, v in sysm.__dict__.items() if k != "_linearized_history_nonzeros"})
    small = LinearizedHistory(fresh, t, X, spring_removed, Q)
    grown = LinearizedHistory(fresh, t, X, p, Q)
    assert grown.m_rows.size == small.m_rows.size + 2
    ref = LinearizedHistory(sysm, t, X, p, Q, lu="superlu")
    np.testing.assert_array_equal(grown.m_rows, ref.m_rows)
    np.testing.assert_array_equal(grown.m_data, ref.m_data)
    again = LinearizedHistory(fresh, t, X, spring_removed, Q)       # the grown pattern stays
    assert again.m_rows.size == grown.m_rows.size
    g = np.random.default_rng(4).standard_normal(X.shape)
    np.testing.assert_allclose(grown.solve_adjoint(g), ref.solve_adjoint(g), rtol=1e-9, atol=1e-10)


@needs_gcc
def test_a_column_order_gives_the_same_solutions(kernel_on):
    """P A Q = L U with a random column order Q: solves (A and A^T) equal SciPy's."""
    base, mats = _family(n=40, seed=11)
    q = np.random.default_rng(5).permutation(40)
    slu = StaticPivotLU(40, base.indices, base.indptr, mats[0].data, col_order=q)
    assert np.array_equal(slu.col_order, q)
    rng = np.random.default_rng(6)
    for m, f in zip(mats, slu.factor_many(np.array([m.data for m in mats]))):
        b = rng.standard_normal(40)
        for trans, mat in (("N", m), ("T", m.T.tocsc())):
            x, _, berr = slu.solve(f, m.data, b, trans)
            if berr > 1e-12:       # static pivots: refine once, as the sweeps do
                x = x + slu.solve(f, m.data, b - mat @ x, trans)[0]
            np.testing.assert_allclose(x, spla.spsolve(mat, b), rtol=1e-8, atol=1e-10)
    with pytest.raises(ValueError, match="permutation of 0..39"):
        StaticPivotLU(40, base.indices, base.indptr, mats[0].data, col_order=np.zeros(40, int))


def _aeroelastic_history(plunge, n=6, n_time=40):
    """A 1-cos gust history of the coupled aeroelastic beam (clamped, or free plunge + trim)."""
    from wingmdao.aero import aero_parameters, cached_aeroelastic_system
    from wingmdao.beam.static import beam_forcing, beam_parameters, straight_beam
    from wingmdao.timemarch.system import layout, pack

    r0, th0 = straight_beam(n, 6.0)
    bp = beam_parameters(r0, th0, EI_cc=2e5, GJ=1e5, EI_nn=2e6, EA=1e8, mass_per_length=5.0)
    ap = aero_parameters(n, chord=1.0, ref_point=0.4, airspeed=30.0, density=1.2)
    s = cached_aeroelastic_system(n, plunge=plunge, trim=plunge)
    vals = {**bp, **ap}
    qd = beam_forcing(n)
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3))
    t = np.arange(n_time) * 0.005
    if plunge:
        vals.update(body_mass=200.0, trim_lift=(200.0 + 2 * 30.0) * 9.81)
        qd.update(gravity=np.array([0.0, 0.0, -9.81]), trim_active=np.ones(1))
    p = pack(s.param_specs, vals)
    Q = np.tile(pack(s.forcing_specs, qd), (n_time, 1))
    ql = layout(s.forcing_specs)
    Q[:, ql["gust_velocity"]] = (1.0 - np.cos(2 * np.pi * t / t[-1]))[:, None]
    if plunge:
        Q[1:, ql["trim_active"]] = 0.0
    return s, t, march(s, t, p, Q).states, p, Q


@needs_gcc
@pytest.mark.parametrize("plunge", [False, True])
def test_coupled_sweeps_with_the_stored_column_order_equal_superlu(plunge, kernel_on):
    """The aeroelastic system's LU orders (wingmdao.timemarch.lu_orders): the adjoint's (lag states
    first with diagonal pivots, then AEROELASTIC_BEAM_ORDER per node) is the one the sweeps use,
    whose results equal the SuperLU ones; the march's AEROELASTIC_NODE_ORDER saves at least a
    third of the factorization's multiply-adds against the natural order (half at 20 nodes,
    benchmarks/lu_column_order.py) and the adjoint's order no less."""
    s, t, X, p, Q = _aeroelastic_history(plunge)
    ref = LinearizedHistory(s, t, X, p, Q, lu="superlu")
    lin = LinearizedHistory(s, t, X, p, Q, lu="static")
    rng = np.random.default_rng(2)
    g = rng.standard_normal(X.shape)
    for sweep in ("solve_adjoint", "solve_tangent"):
        a, b = getattr(lin, sweep)(g), getattr(ref, sweep)(g)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-10 * np.max(np.abs(b)))
    assert lin.static_stats["fallback"] == 0
    slu = lin._static_lu()
    order, diagonal = lu_orders.adjoint_lu_order(s)
    assert diagonal == 4 * s.num_nodes
    assert slu is not None and np.array_equal(slu.col_order, order)
    a_mid = ref.newton_matrix(len(t) // 2).tocsc()
    a_mid.sort_indices()
    args = (s.n_state, a_mid.indices, a_mid.indptr, a_mid.data)
    natural = static_lu.factorization_work(*args)
    assert static_lu.factorization_work(*args, s.lu_column_order()) < 0.67 * natural
    # the adjoint's lag-first order with diagonal lag pivots: no more work than the march's order
    assert static_lu.factorization_work(*args, order, diagonal) <= static_lu.factorization_work(*args, s.lu_column_order())


def _leading_block_family(n=30, k=6, m=4, seed=3):
    """Matrices with one pattern whose rows/columns ``lead`` hold a diagonal block (like the lag
    states of the aeroelastic beam), small against a coupling of 5 in another row of each of
    those columns (partial pivoting would pick that row), the other rows needing pivoting."""
    base, _ = _family(n=n, m=1, seed=seed)
    rng = np.random.default_rng(seed + 1)
    lead = np.sort(rng.choice(n, size=k, replace=False))
    a = base.tolil()
    for i in lead:
        for j in lead:
            a[i, j] = 0.0
        a[i, i] = 1.0
        a[int(rng.choice(np.setdiff1d(np.arange(n), lead))), i] = 5.0
    a = sp.csc_matrix(a)
    a.eliminate_zeros()
    a.sort_indices()
    return lead, _perturbed(a, m, rng)


@needs_gcc
def test_leading_diagonal_pivots_are_the_schur_complement_pivoting(kernel_on):
    """``pivot_order(..., diagonal=k)``: the first k columns of Q pivot on their own rows and the
    other rows are SuperLU's partial pivoting of the explicitly formed Schur complement
    ``A_22 - A_21 A_11^-1 A_12`` (the independent reference); the solves with that pivot order
    equal SciPy's, and plain partial pivoting would have picked other rows."""
    n, k = 30, 6
    lead, mats = _leading_block_family(n, k)
    a = mats[0]
    assert all(a.nnz == m.nnz and np.array_equal(a.indices, m.indices) for m in mats)
    rest = np.setdiff1d(np.arange(n), lead)
    q = np.concatenate([lead, np.random.default_rng(7).permutation(rest)])
    perm = static_lu.pivot_order(n, a.indices, a.indptr, a.data, q, k)
    assert np.array_equal(perm[q[:k]], np.arange(k))
    d = a[lead][:, lead].diagonal()
    schur = (a[rest][:, rest] - a[rest][:, lead] @ sp.diags(1.0 / d) @ a[lead][:, rest]).tocsc()
    cols = np.searchsorted(rest, q[k:])
    ref = spla.splu(sp.csc_matrix(schur[:, cols]), permc_spec="NATURAL").perm_r
    np.testing.assert_array_equal(perm[rest], k + ref)
    plain = static_lu.pivot_order(n, a.indices, a.indptr, a.data, q)
    assert not np.array_equal(plain[q[:k]], np.arange(k))      # partial pivoting goes elsewhere
    slu = StaticPivotLU(n, a.indices, a.indptr, perm_r=perm, col_order=q)
    rng = np.random.default_rng(8)
    for m, f in zip(mats, slu.factor_many(np.array([m.data for m in mats]))):
        b = rng.standard_normal(n)
        for trans, mat in (("N", m), ("T", m.T.tocsc())):
            x, _, berr = slu.solve(f, m.data, b, trans)
            if berr > 1e-12:
                x = x + slu.solve(f, m.data, b - mat @ x, trans)[0]
            np.testing.assert_allclose(x, spla.spsolve(mat, b), rtol=1e-8, atol=1e-10)
    assert for_pattern(n, a.indices, a.indptr, a.data, q, k).perm_r.tolist() == perm.tolist()


def test_adjoint_lu_order_of_the_beam_and_of_the_aeroelastic_beam():
    """The structural beam keeps its ``lu_column_order`` with partial pivoting; the aeroelastic
    beam's adjoint order is a permutation with every lag state first (``layout.aero``), then the
    beam states node by node, the body states last."""
    from wingmdao.aero import cached_aeroelastic_system
    from wingmdao.components.beam import beam_system

    b = beam_system(4)
    order, diagonal = lu_orders.adjoint_lu_order(b)
    assert diagonal == 0 and np.array_equal(order, b.lu_column_order())
    s = cached_aeroelastic_system(4, plunge=True, trim=True)
    order, diagonal = lu_orders.adjoint_lu_order(s)
    assert diagonal == 16
    assert np.array_equal(np.sort(order), np.arange(s.n_state))
    np.testing.assert_array_equal(order[:16], s.layout.aero.ravel())
    np.testing.assert_array_equal(np.sort(order[16:88]), np.sort(s.layout.beam.ravel()))
    np.testing.assert_array_equal(order[88:], [s.layout.body["plunge"], s.layout.body["trim"]])
