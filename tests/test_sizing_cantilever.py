"""End-to-end sizing of the Sec. 4.7.1 cantilever: robustness to the initial guess (Fig. 4.40,
Table 4.24) and static versus dynamic sizing under a suddenly applied load (Table 4.25)."""

import numpy as np
import pytest

from wingmdao.cases import cantilever
from wingmdao.sizing import size_case

pytestmark = pytest.mark.slow


def _size(**kw):
    setup = cantilever.build(**kw)
    setup.options.disp = False
    prob, res = size_case(setup)
    return setup, prob, res


def _check_optimum(setup, res):
    assert res["success"], res.get("message")
    ks = [v for d in res["ks"].values() for v in d.values()]
    assert max(ks) <= 1e-6  # enabled constraints satisfied
    assert max(ks) > -1e-3  # and at least one active
    for name in ("width", "height"):
        lo, hi = cantilever.BOUNDS[name]
        vals = np.asarray(res[name])
        assert np.all(vals >= lo - 1e-9) and np.all(vals <= hi + 1e-9)


@pytest.fixture(scope="module")
def static_runs():
    return {g: _size(load="static", guess=g) for g in ("a", "b", "c")}


def test_three_initial_guesses_reach_the_same_optimum(static_runs):
    masses = []
    for setup, _, res in static_runs.values():
        _check_optimum(setup, res)
        masses.append(res["mass_kg"])
    assert max(masses) - min(masses) < 1e-4 * min(masses)


def test_dynamic_optimum_under_a_suddenly_applied_load_is_heavier(static_runs):
    setup, _, res = _size(load="step", guess="b", t_final=0.6, dt=0.01)
    _check_optimum(setup, res)
    static_mass = static_runs["b"][2]["mass_kg"]
    assert res["mass_kg"] > 1.05 * static_mass
