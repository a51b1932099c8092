"""Static-pivot complex LU of shifted pencils (``wingmdao.stability.pencil_lu``, C kernel
``pencil_lu.c``) and its use in the flutter refinement (``sensitivity.refine_pair``,
``left_right_vectors``).

References are independent: SciPy's ``spsolve`` (SuperLU) on the same complex matrices and the
SuperLU path of ``refine_pair`` (the kernel turned off). The suite runs with ``WINGMDAO_JIT=0``
(tests/conftest.py), where the kernel is off; the fixture ``kernel_on`` (tests/conftest.py) compiles it into a
temporary cache and turns it on for these tests.
"""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.stability import pencil_lu
from wingmdao.stability import sensitivity as se
from wingmdao.timemarch import static_lu
from wingmdao.utils import casadi_cache as cc

needs_gcc = pytest.mark.skipif(cc.compiler() is None, reason="needs gcc")


def _random_pencil(n=60, seed=0):
    """Real sparse A (with a random diagonal) and B (singular: a third of its rows empty, like the
    kinematic rows of the beam) on different patterns."""
    rng = np.random.default_rng(seed)
    A = sp.random(n, n, density=0.08, random_state=rng) + sp.diags(rng.uniform(-2.0, 2.0, n))
    B = sp.random(n, n, density=0.06, random_state=rng)
    B = sp.diags((np.arange(n) % 3 != 0).astype(float)) @ B
    return sp.csc_matrix(A), sp.csc_matrix(B)


def _rel(x, y):
    return np.linalg.norm(x - y) / np.linalg.norm(y)


def _pivoted(A, B, s):
    pen = pencil_lu.pencil(A, B)
    M = sp.csc_matrix(A + s * B, dtype=complex)
    pen.repivot(spla.splu(M, permc_spec="NATURAL").perm_r)
    return pen


@needs_gcc
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_kernel_solves_match_spsolve_on_random_complex_pencils(kernel_on, seed):
    A, B = _random_pencil(seed=seed)
    rng = np.random.default_rng(10 + seed)
    b = rng.standard_normal(A.shape[0]) + 1j * rng.standard_normal(A.shape[0])
    pen = _pivoted(A, B, 0.7 + 3.0j)
    # the pivot order of s = 0.7 + 3i, reused at other shifts (static pivoting)
    for s in (0.7 + 3.0j, 0.7 + 3.1j, 1.5j, -0.4 + 2.0j):
        M = sp.csc_matrix(A + s * B, dtype=complex)
        lu = pen.factor(s)
        assert lu is not None and pen.growth <= pencil_lu.GROWTH_MAX
        x, e = pen.solve(lu, b)
        xh, eh = pen.solve(lu, b, "H")
        assert e < pencil_lu.BACKWARD_TOL and eh < pencil_lu.BACKWARD_TOL
        assert _rel(x, spla.spsolve(M, b)) < 1e-12
        assert _rel(xh, spla.spsolve(sp.csc_matrix(M.conj().T), b)) < 1e-12


@needs_gcc
def test_kernel_matches_superlu_on_a_flutter_pencil(kernel_on):
    """The PEGASUS pencil (8 nodes) at 150 m/s: solves near an eigenvalue (A + lambda B nearly
    singular, where SuperLU's own componentwise backward error is large: the normwise one is the
    check) and away from it, with M and M^H."""
    from wingmdao.stability.cases import flutter_problem
    from wingmdao.stability.eigen import eigenmodes, linearize

    prob = flutter_problem("pegasus", 8)
    p, q = prob.params_at(150.0)
    m = eigenmodes(prob.system, p, q, static=True, **prob.eig_options)
    A, B = linearize(prob.system, p, q, m.x0)
    lam = m.eigenvalues[m.frequency > 1e-3]
    pen = _pivoted(A, B, lam[0])
    b = np.random.default_rng(3).standard_normal(A.shape[0]) + 0j
    for s in (120j, 60j + 3.0):
        M = sp.csc_matrix(A + s * B, dtype=complex)
        lu = pen.factor(s)
        x, _ = pen.solve(lu, b)
        xh, _ = pen.solve(lu, b, "H")
        assert _rel(x, spla.spsolve(M, b)) < 1e-10
        assert _rel(xh, spla.spsolve(sp.csc_matrix(M.conj().T), b)) < 1e-10
    for lj in lam:    # nearly singular: the normwise backward error is at round-off
        s = lj * (1 + 1e-10) + 1e-10
        lu = pen.factor(s)
        for trans in ("N", "H"):
            x, e = pen.solve(lu, b, trans)
            M = sp.csc_matrix(A + s * B, dtype=complex)
            M = M if trans == "N" else sp.csc_matrix(M.conj().T)
            r = b - M @ x
            assert np.max(np.abs(r)) / (abs(M) @ np.abs(x)).max() < 1e-14 and e < 1e-14
    # refine_pair and left_right_vectors: kernel against the SuperLU path
    for lj in lam:
        v0, u0, l0 = se.left_right_vectors(A, B, lj)
        start = (lj * (1 + 1e-3), v0 + 1e-3 * np.roll(v0, 1), u0)
        v, u, lk, ok = se.refine_pair(A, B, *start)
        with pytest.MonkeyPatch.context() as mp:
            mp.setenv(static_lu.ENV_KERNEL, "0")
            pencil_lu._LAST[:] = [None, None, None]
            assert pencil_lu.pencil(A, B) is None
            vr, ur, lr, okr = se.refine_pair(A, B, *start)
            vr0, ur0, lr0 = se.left_right_vectors(A, B, lj)
        pencil_lu._LAST[:] = [None, None, None]
        assert ok and okr
        assert abs(lk - lr) <= 1e-13 * abs(lr) and abs(l0 - lr0) <= 1e-13 * abs(lr0)
        for a, r in ((v, vr), (u, ur), (v0, vr0), (u0, ur0)):
            ph = np.vdot(a, r)
            assert np.linalg.norm(a * ph / abs(ph) - r) < 1e-9


def _two_by_two():
    """M(s) = [[s, 1], [1, 0]]: partial pivoting at s = 2 keeps row 0 as the first pivot, which is
    zero at s = 0 and tiny (growth 1/s) near it."""
    A = sp.csc_matrix(np.array([[0.0, 1.0], [1.0, 0.0]]))
    B = sp.csc_matrix(np.array([[1.0, 0.0], [0.0, 0.0]]))
    return A, B


@needs_gcc
def test_bad_static_pivots_are_refused(kernel_on):
    A, B = _two_by_two()
    pen = _pivoted(A, B, 2.0)
    assert pen.factor(2.0) is not None
    assert pen.factor(0.0) is None                    # exactly zero pivot
    assert pen.factor(1e-9) is None and pen.growth > 1e8   # growth 1 / s
    v = np.array([1.0, 0.0], complex)
    assert pen.iterate(1e-9, v, v, B @ v, 0.0, 0.0, 3, 1e-12) is None
    # SuperLU's own order at s = 0 (rows swapped) is fine there
    pen.repivot(spla.splu(sp.csc_matrix(A + 0.0 * B, dtype=complex), permc_spec="NATURAL").perm_r)
    lu = pen.factor(0.0)
    assert lu is not None
    x, _ = pen.solve(lu, np.array([1.0, 2.0], complex))
    assert np.allclose(x, [2.0, 1.0], rtol=0, atol=1e-15)


@needs_gcc
@pytest.mark.parametrize("what", ["growth", "backward_error"])
def test_refine_pair_falls_back_to_superlu(kernel_on, monkeypatch, what):
    """Every kernel factorization refused (growth limit 0) or every checked solve (backward-error
    limit 0): refine_pair takes SuperLU for each shift and gives the SuperLU path's result."""
    A, B = _random_pencil(n=40, seed=4)
    lam = sla_eigs(A, B)
    v0 = np.random.default_rng(5).standard_normal(A.shape[0]) + 0j
    ref = se.refine_pair(A, B, lam * (1 + 1e-4), v0, v0.copy(), quotient_start=False)
    calls = []
    orig = pencil_lu.superlu
    monkeypatch.setattr(pencil_lu, "superlu", lambda M: calls.append(1) or orig(M))
    monkeypatch.setattr(pencil_lu, "GROWTH_MAX" if what == "growth" else "BACKWARD_TOL", 0.0)
    if what == "backward_error":     # the default argument was bound at definition
        monkeypatch.setattr(pencil_lu.Pencil.iterate, "__defaults__", (0.0, 1))
    pencil_lu._LAST[:] = [None, None, None]
    got = se.refine_pair(A, B, lam * (1 + 1e-4), v0, v0.copy(), quotient_start=False)
    assert calls                     # SuperLU was used
    assert got[3] and abs(got[2] - ref[2]) <= 1e-12 * abs(ref[2])
    with monkeypatch.context() as mp:
        mp.setenv(static_lu.ENV_KERNEL, "0")
        pencil_lu._LAST[:] = [None, None, None]
        pure = se.refine_pair(A, B, lam * (1 + 1e-4), v0, v0.copy(), quotient_start=False)
    pencil_lu._LAST[:] = [None, None, None]
    assert got[2] == pure[2] and np.array_equal(got[0], pure[0])   # exactly the SuperLU path


def sla_eigs(A, B):
    """An eigenvalue of the random pencil (dense QZ), the finite one nearest 1j."""
    import scipy.linalg as sla

    lam = sla.eigvals(-A.toarray(), B.toarray())
    lam = lam[np.isfinite(lam) & (np.abs(lam) < 1e6)]
    return complex(lam[np.argmin(np.abs(lam - 1j))])


@needs_gcc
def test_products_and_shared_structure(kernel_on):
    """``Pencil.products`` equals SciPy's sparse products bitwise (same summation order); a pencil
    whose pattern is a subset of an earlier one (a numerical zero dropped) reuses its structure."""
    A, B = _random_pencil(seed=6)
    X = np.random.default_rng(7).standard_normal((A.shape[0], 5)) * (1 + 0.5j)
    pen = pencil_lu.pencil(A, B)
    for trans, (ya, yb) in ((False, (A @ X, B @ X)), (True, (A.T @ X, B.T @ X))):
        ga, gb = pen.products(np.asfortranarray(X), trans=trans)
        assert np.array_equal(ga, ya) and np.array_equal(gb, yb)
    A2 = A.copy()
    A2.data[3] = 0.0
    A2.eliminate_zeros()
    pen2 = pencil_lu.pencil(A2, B)
    assert pen2.st is pen.st and pen2.a[pen.a != pen2.a].size == 1


@pytest.mark.skipif(cc.compiler() is None, reason="needs gcc")
def test_pencil_function_from_a_warm_cache_forms_no_jacobian(tmp_path, monkeypatch):
    """With its library cached, the pencil function loads it with the system's own patterns and
    forms no Jacobian; (A, B) equal those of the function built from the residual."""
    import casadi as ca

    from wingmdao.stability import eigen
    from wingmdao.stability.cases import flutter_problem

    monkeypatch.setenv(cc.ENV_JIT, "1")
    monkeypatch.setenv(cc.ENV_CACHE, str(tmp_path / "cache"))
    prob = flutter_problem("goland", 4)
    p, q = prob.params_at(120.0)
    x0 = np.random.default_rng(6).normal(size=prob.system.n_state) * 1e-3
    built = eigen._PencilFunction(prob.system)            # empty cache: built from the residual
    assert isinstance(built.call.jit.interpreted, ca.Function) and built.call.jit.state == "interpreted"
    built.call.jit.start(wait=True)
    built.call.refresh()
    A0, B0 = built(x0, p, q)
    formed = []
    real = ca.jacobian
    monkeypatch.setattr(ca, "jacobian", lambda *a: formed.append(1) or real(*a))
    warm = eigen._PencilFunction(prob.system)
    assert not formed and warm.call.jit.state == "compiled"
    A1, B1 = warm(x0, p, q)
    assert (A1 != A0).nnz == 0 and (B1 != B0).nnz == 0 and A0.nnz > 0 and B0.nnz > 0


@pytest.mark.parametrize("kernel", ["1", "0"])
def test_factor_solves_a_complex_matrix_with_m_its_transpose_and_adjoint(kernel_on, monkeypatch, kernel):
    """``pencil_lu.factor`` (the LU interface: kernel or SuperLU, the caller does not branch) of a
    complex sparse M solves M x = b, M^T x = b and M^H x = b as a dense solve does, for real and
    complex right-hand sides, one or several; with the kernel on, its second factorization (the
    first gives it SuperLU's pivot order) is the kernel's."""
    monkeypatch.setenv(static_lu.ENV_KERNEL, kernel)
    A, B = _random_pencil(n=30, seed=8)
    M = sp.csc_matrix(A + (0.4 + 1.3j) * B)
    rng = np.random.default_rng(9)
    Md = M.toarray()
    for attempt in range(2):
        lu = pencil_lu.factor(M)
        assert lu.compiled == (kernel == "1") or attempt == 0
        for b in (rng.standard_normal(30), rng.standard_normal(30) + 1j * rng.standard_normal(30),
                  rng.standard_normal((30, 3))):
            for trans, Mt in (("N", Md), ("T", Md.T), ("H", Md.conj().T)):
                x = lu.solve(b, trans)
                np.testing.assert_allclose(x, np.linalg.solve(Mt, b), rtol=1e-10, atol=1e-12)
    with pytest.raises(ValueError, match="trans"):
        lu.solve(b, "C")
    real = pencil_lu.factor(sp.csc_matrix(A))
    np.testing.assert_allclose(real.solve(b[:, 0], "T"), np.linalg.solve(A.toarray().T, b[:, 0]), rtol=1e-10)
