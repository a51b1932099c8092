"""KS aggregation (Eq. 4.44, 4.53-4.55): bounds, exact equal-value case, partials, no overflow."""

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.components.ks import KSAggregate, ks_value


def _problem(families, rho_ks, values):
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("ks", KSAggregate(families=families, rho_ks=rho_ks), promotes=["*"])
    prob.setup()
    for name, g in values.items():
        prob[f"g_{name}"] = g
    prob.run_model()
    return prob


@pytest.mark.parametrize("rho_ks", [5.0, 50.0, 1000.0])
def test_bounds_max_to_max_plus_lnN_over_rho(rho_ks):
    rng = np.random.default_rng(1)
    g = rng.uniform(-2.0, 0.3, (7, 5, 4))
    prob = _problem({"vm": g.shape}, rho_ks, {"vm": g})
    ks = prob["ks_vm"].item()
    assert g.max() <= ks <= g.max() + np.log(g.size) / rho_ks + 1e-15


@pytest.mark.parametrize("rho_ks", [1.0, 50.0, 1000.0])
def test_identical_values_give_max_plus_lnN_over_rho(rho_ks):
    g = np.full((3, 4, 4), 0.37)
    prob = _problem({"vm": g.shape}, rho_ks, {"vm": g})
    assert prob["ks_vm"].item() == pytest.approx(0.37 + np.log(48) / rho_ks, rel=1e-14, abs=1e-15)


def test_large_magnitude_and_large_rho_no_overflow():
    # without the max shift exp(1000 * 1e4) overflows
    g = np.array([1.0e4, 1.0e4 - 1e-3, -1.0e4, 9.0e3])
    assert ks_value(g, 1000.0) == pytest.approx(1.0e4 + np.log(1 + np.exp(-1.0)) / 1000.0, rel=1e-15)


def test_two_families_independent_and_partials():
    rng = np.random.default_rng(7)
    g_vm = rng.uniform(-1.5, 0.5, (6, 5, 4))
    g_ss = rng.uniform(-3.0, 1.0, (6, 5, 4))
    prob = _problem({"vm": g_vm.shape, "ss_tension": g_ss.shape}, 50.0, {"vm": g_vm, "ss_tension": g_ss})
    assert prob["ks_vm"].item() == pytest.approx(
        g_vm.max() + np.log(np.exp(50.0 * (g_vm - g_vm.max())).sum()) / 50.0, rel=1e-13
    )
    data = prob.check_partials(method="fd", form="central", step=1e-7, out_stream=None)
    assert_check_partials(data, atol=1e-7, rtol=1e-6)
    # cross partials are not declared: ks_vm does not depend on g_ss_tension
    assert ("ks_vm", "g_ss_tension") not in data["ks"]


@pytest.mark.parametrize("rho_ks, offset, spread, step", [(1000.0, 0.2, 0.004, 1e-8), (20.0, 1.0e3, 0.2, 1e-6)])
def test_partials_large_rho_and_large_values(rho_ks, offset, spread, step):
    rng = np.random.default_rng(3)
    # several entries close to the max so that more than one weight is non-negligible
    g = offset + rng.uniform(-spread, 0.0, (9, 3))
    prob = _problem({"cent_pos": g.shape}, rho_ks, {"cent_pos": g})
    data = prob.check_partials(method="fd", form="central", step=step, out_stream=None)
    assert_check_partials(data, atol=1e-6, rtol=1e-6)
    assert np.isfinite(prob["ks_cent_pos"]).all()


def test_gradient_sums_to_one_and_picks_max_for_large_rho():
    rng = np.random.default_rng(5)
    g = rng.uniform(-1, 1, 40)
    prob = _problem({"vm": (40,)}, 1000.0, {"vm": g})
    J = prob.compute_totals(of=["ks_vm"], wrt=["g_vm"])["ks_vm", "g_vm"].ravel()
    assert J.sum() == pytest.approx(1.0, rel=1e-12)
    assert np.argmax(J) == np.argmax(g)


def test_bad_input_raises_with_index():
    g = np.zeros((2, 3))
    g[1, 2] = np.nan
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("ks", KSAggregate(families={"vm": (2, 3)}), promotes=["*"])
    prob.setup()
    prob["g_vm"] = g
    with pytest.raises(Exception, match=r"g_vm.*\(1, 2\)"):
        prob.run_model()


def test_bad_rho_raises():
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("ks", KSAggregate(families={"vm": (2,)}, rho_ks=0.0))
    with pytest.raises(ValueError, match="rho_ks"):
        prob.setup()


def test_partials_at_a_changed_input_without_compute():
    """compute_partials reuses the exp terms of the last compute only at the same g: called with
    another g it returns the closed-form softmax of that g (the component's methods called
    directly, as OpenMDAO would after a transfer without a compute)."""
    rng = np.random.default_rng(3)
    g0, g1 = rng.uniform(-1.0, 0.5, 40), rng.uniform(-1.0, 0.5, 40)
    comp = _problem({"vm": (40,)}, 30.0, {"vm": g0}).model.ks
    for g in (g0, g1):
        comp.compute({"g_vm": g0}, {})
        partials = {}
        comp.compute_partials({"g_vm": g}, partials)
        w = np.exp(30.0 * (g - g.max()))
        np.testing.assert_allclose(partials["ks_vm", "g_vm"], w / w.sum(), rtol=1e-12)


@pytest.mark.parametrize("mode", ["fwd", "rev"])
def test_matrix_free_equals_declared_partials(mode):
    """matrix_free=True (products with the softmax weights, no declared rows/columns; the default
    above KS_MATRIX_FREE_ABOVE entries): check_partials, and totals equal to the declared ones."""
    import openmdao.api as om

    rng = np.random.default_rng(5)
    vals = {"vm": rng.uniform(-1.5, 0.5, (6, 5, 4)), "ss_tension": rng.uniform(-3.0, 1.0, (7, 3))}
    totals = {}
    for mf in (False, True):
        prob = om.Problem(reports=False)
        prob.model.add_subsystem("ks", KSAggregate(families={k: v.shape for k, v in vals.items()}, rho_ks=40.0,
                                                   matrix_free=mf), promotes=["*"])
        prob.setup(mode=mode)
        for k, v in vals.items():
            prob.set_val(f"g_{k}", v)
        prob.run_model()
        assert prob.model.ks.matrix_free is mf
        if mf:
            data = prob.check_partials(method="fd", form="central", step=1e-7, out_stream=None)
            assert_check_partials(data, atol=1e-7, rtol=1e-6)
        totals[mf] = prob.compute_totals(of=["ks_vm", "ks_ss_tension"], wrt=["g_vm", "g_ss_tension"])
    for key, ref in totals[False].items():
        np.testing.assert_allclose(totals[True][key], ref, rtol=1e-14, atol=1e-16, err_msg=str(key))


def test_g_by_conn_gives_the_same_ks_and_partials_and_checks_the_shape():
    """g_by_conn (g inputs shaped by the connected output, no default copy): same KS bitwise,
    check_partials passes; a connection of the wrong shape is rejected."""
    g = np.random.default_rng(3).normal(size=(5, 4, 2))
    ref = _problem({"vm": (5, 4, 2)}, 40.0, {"vm": g})

    def build(shape, matrix_free):
        prob = om.Problem(reports=False)
        prob.model.add_subsystem("ivc", om.IndepVarComp()).add_output("g", val=np.zeros(shape))
        prob.model.add_subsystem("ks", KSAggregate(families={"vm": (5, 4, 2)}, rho_ks=40.0, g_by_conn=True,
                                                   matrix_free=matrix_free))
        prob.model.connect("ivc.g", "ks.g_vm")
        prob.setup()
        return prob

    for matrix_free in (False, True):
        prob = build((5, 4, 2), matrix_free)
        prob.set_val("ivc.g", g)
        prob.run_model()
        assert prob.get_val("ks.ks_vm")[0] == ref.get_val("ks_vm")[0]
        assert_check_partials(prob.check_partials(method="fd", form="central", step=1e-7, out_stream=None,
                                                  includes=["ks"]), atol=1e-6, rtol=1e-6)
    for matrix_free in (False, True):
        prob = build((5, 4, 3), matrix_free)
        with pytest.raises(ValueError, match="connected with shape"):
            prob.final_setup()    # setup_partials checks the resolved shape
