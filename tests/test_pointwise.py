"""The pointwise CasADi base: values and declared sparse partials on a toy function."""

import numpy as np
import pytest
import openmdao.api as om
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.components.pointwise import PointwiseCasadiComponent, Var


class Toy(PointwiseCasadiComponent):
    def pointwise_inputs(self):
        return [Var("a", (), "m"), Var("b", (2, 3), "m"), Var("c", (), "m", per_last_axis=True)]

    def pointwise_outputs(self):
        return [Var("area", (), "m**2"), Var("bt", (3, 2), "m")]

    def pointwise_expressions(self, sym):
        a, b = sym["a"], sym["b"]
        return {"area": a * b[0, 1] + b[1, 2] ** 2 * sym["c"], "bt": a * b.T}


def test_values_and_partials():
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("toy", Toy(grid_shape=(4, 2)), promotes=["*"])
    prob.setup(force_alloc_complex=False)
    rng = np.random.default_rng(0)
    a = rng.uniform(1, 2, (4, 2))
    b = rng.uniform(1, 2, (4, 2, 2, 3))
    c = rng.uniform(1, 2, 2)
    prob["a"], prob["b"], prob["c"] = a, b, c
    prob.run_model()
    np.testing.assert_allclose(prob["area"], a * b[..., 0, 1] + b[..., 1, 2] ** 2 * c[None, :], rtol=1e-14)
    np.testing.assert_allclose(prob["bt"], a[..., None, None] * np.swapaxes(b, -1, -2), rtol=1e-14)
    data = prob.check_partials(method="fd", form="central", out_stream=None)
    assert_check_partials(data, atol=1e-6, rtol=1e-6)


@pytest.mark.parametrize("chunk, cache", [(4096, 64e6), (3, 0.0)])
def test_matrix_free_products_equal_declared_partials(monkeypatch, chunk, cache):
    """matrix_free=True (Jacobian-vector products from the per-point nonzeros, evaluated in
    chunks of points, kept or re-evaluated): check_partials against central differences, and
    totals in fwd and rev equal the declared partials'."""
    from wingmdao.components import pointwise

    monkeypatch.setattr(pointwise, "POINT_CHUNK", chunk)
    monkeypatch.setattr(pointwise, "POINTWISE_JAC_CACHE_BYTES", cache)
    rng = np.random.default_rng(1)
    vals = {"a": rng.uniform(1, 2, (4, 2)), "b": rng.uniform(1, 2, (4, 2, 2, 3)), "c": rng.uniform(1, 2, 2)}
    totals = {}
    for mf in (False, True):
        for mode in ("fwd", "rev"):
            prob = om.Problem(reports=False)
            prob.model.add_subsystem("toy", Toy(grid_shape=(4, 2), matrix_free=mf), promotes=["*"])
            prob.setup(mode=mode)
            for k, v in vals.items():
                prob[k] = v
            prob.run_model()
            assert prob.model.toy.matrix_free is mf
            if mf:
                data = prob.check_partials(method="fd", form="central", out_stream=None)
                assert_check_partials(data, atol=1e-6, rtol=1e-6)
            totals[mf, mode] = prob.compute_totals(of=["area", "bt"], wrt=["a", "b", "c"])
    for key, ref in totals[False, "rev"].items():
        for variant in [(False, "fwd"), (True, "fwd"), (True, "rev")]:
            np.testing.assert_allclose(totals[variant][key], ref, rtol=1e-13, atol=1e-14, err_msg=str((key, variant)))


class SparseOut(PointwiseCasadiComponent):
    """An output with a structural zero (its CasADi sparsity is not dense) and a shared input."""

    def pointwise_inputs(self):
        return [Var("a", (), "m"), Var("c", (2,), "m", per_last_axis=True)]

    def pointwise_outputs(self):
        return [Var("s", (3,), "m**2")]

    def pointwise_expressions(self, sym):
        import casadi as ca

        e = ca.SX(3, 1)  # entry 1 stays a structural zero
        e[0] = sym["a"] * sym["c"][0]
        e[2] = sym["a"] ** 2 + sym["c"][1]
        return {"s": e}


@pytest.mark.parametrize("mf", [False, True])
def test_buffered_evaluation_sparse_output_and_repeated_calls(mf):
    """The buffered evaluation scatters structurally sparse outputs into dense arrays, repeats the
    per-station inputs over time, and gives fresh values at every call (buffers are reused)."""
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("sp", SparseOut(grid_shape=(3, 2), matrix_free=mf), promotes=["*"])
    prob.setup()
    rng = np.random.default_rng(2)
    for _ in range(2):
        a, c = rng.uniform(1, 2, (3, 2)), rng.uniform(1, 2, (2, 2))
        prob["a"], prob["c"] = a, c
        prob.run_model()
        want = np.stack([a * c[None, :, 0], np.zeros_like(a), a ** 2 + c[None, :, 1]], axis=-1)
        np.testing.assert_allclose(prob["s"], want, rtol=1e-14)
        data = prob.check_partials(method="fd", form="central", out_stream=None)
        assert_check_partials(data, atol=1e-6, rtol=1e-6)
