"""Solid rectangle (Sec. 4.7.1): A, I, J (Saint-Venant series) against published values."""

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.components.section import SolidRectSection
from wingmdao.materials import ALUMINIUM


def run_solid(width, height, n=None):
    width, height = np.atleast_1d(width), np.atleast_1d(height)
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("s", SolidRectSection(num_stations=n or width.size, material=ALUMINIUM),
                             promotes=["*"])
    prob.setup()
    prob.set_val("width", width)
    prob.set_val("height", height)
    prob.run_model()
    return prob


def test_area_and_inertia_by_hand():
    p = run_solid(0.2, 0.5)
    assert p.get_val("A")[0] == pytest.approx(0.1, rel=1e-14)
    assert p.get_val("Ixx")[0] == pytest.approx(0.2 * 0.125 / 12, rel=1e-14)  # w h^3 / 12
    assert p.get_val("Izz")[0] == pytest.approx(0.5 * 0.008 / 12, rel=1e-14)  # h w^3 / 12
    assert p.get_val("EIxx")[0] == pytest.approx(70e9 * 0.025 / 12, rel=1e-14)
    assert p.get_val("mass_per_length")[0] == pytest.approx(270.0, rel=1e-14)
    for k in ("Ixz", "c_ea", "n_ea", "c_sc", "n_sc", "c_cg", "n_cg"):
        assert p.get_val(k)[0] == 0.0
    assert p.get_val("Qx")[0] == pytest.approx(0.2 * 0.25 * 0.125, rel=1e-14)  # half area x lever


# beta = J / (a b^3), a >= b: Timoshenko & Goodier, Theory of Elasticity (3rd ed.), Sec. 109 table
@pytest.mark.parametrize("ratio,beta", [(1.0, 0.141), (1.5, 0.196), (2.0, 0.229), (3.0, 0.263),
                                        (5.0, 0.291), (10.0, 0.312)])
def test_torsion_constant_table(ratio, beta):
    for w, h in ((0.3, 0.3 * ratio), (0.3 * ratio, 0.3)):  # either side may be the longer
        p = run_solid(w, h)
        b = min(w, h)
        assert p.get_val("J")[0] / (max(w, h) * b**3) == pytest.approx(beta, abs=6e-4)


def test_square_and_thin_limits():
    assert run_solid(2.0, 2.0).get_val("J")[0] == pytest.approx(0.140577 * 16, rel=2e-6)
    # very thin strip: J -> a b^3 / 3 (1 - 0.630 b / a)
    p = run_solid(0.01, 1.0)
    assert p.get_val("J")[0] == pytest.approx(1.0 * 0.01**3 / 3 * (1 - 0.630 * 0.01), rel=1e-5)


def test_check_partials_random_including_square():
    rng = np.random.default_rng(7)
    w = np.array([0.3, *rng.uniform(0.2, 1.0, 3)])
    h = np.array([0.3, *rng.uniform(0.2, 1.0, 3)])
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("s", SolidRectSection(num_stations=4, material=ALUMINIUM), promotes=["*"])
    prob.setup()
    prob.set_val("width", w)
    prob.set_val("height", h)
    th = rng.uniform(-0.4, 0.4, 4)
    prob.set_val("section_to_csn", [[[np.cos(a), 0, -np.sin(a)], [0, 1, 0], [np.sin(a), 0, np.cos(a)]] for a in th])
    prob.set_val("nonstructural_mass_per_length", rng.uniform(0, 5, 4))
    prob.run_model()
    data = prob.check_partials(method="fd", form="central", step=1e-7, step_calc="rel", out_stream=None)
    assert_check_partials(data, atol=1e-6, rtol=1e-6)


@pytest.mark.parametrize("name", ["width", "height"])
def test_bad_input(name):
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("s", SolidRectSection(num_stations=2, material=ALUMINIUM), promotes=["*"])
    prob.setup()
    prob.set_val(name, [0.5, -1.0])
    with pytest.raises(ValueError, match=rf"{name} = -1 m at station 1; allowed range \(0, inf\) m"):
        prob.run_model()
