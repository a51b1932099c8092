"""Solid rectangle corner stress: Eq. 4.40 by hand, combined loading, partials."""

import numpy as np
import openmdao.api as om
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.components.solid_stress import SolidRectStress


def _material():
    from wingmdao.materials import Material

    return Material("test", E=70e9, rho=2700.0, sigma_y=276e6, nu=0.33)


def _prob(nt=2, n=3):
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("s", SolidRectStress(num_times=nt, num_stations=n, material=_material()),
                             promotes=["*"])
    prob.setup()
    return prob


def test_pure_bending_matches_eq_4_40():
    prob = _prob(1, 1)
    w, h, m = 0.3, 0.8, 2.0e6
    prob["width"], prob["height"] = w, h
    prob["M_csn"] = np.array([m, 0.0, 0.0]).reshape(1, 1, 3)
    prob.run_model()
    sigma_max = 6 * m / (w * h**2)  # Eq. 4.40
    np.testing.assert_allclose(prob["g_ss_tension"].max(), sigma_max / 276e6 - 1, rtol=1e-12)
    np.testing.assert_allclose(prob["g_ss_compression"].max(), sigma_max / 276e6 - 1, rtol=1e-12)
    # positive M_c (tip load up) compresses the upper corners (indices 2, 3)
    assert prob["g_ss_compression"][0, 0, 2] > prob["g_ss_tension"][0, 0, 2]


def test_axial_plus_chordwise_bending_superpose():
    prob = _prob(1, 1)
    w, h, n_ax, mn = 0.5, 0.4, 1e5, 3e5
    prob["width"], prob["height"] = w, h
    prob["F_csn"] = np.array([0.0, n_ax, 0.0]).reshape(1, 1, 3)
    prob["M_csn"] = np.array([0.0, 0.0, mn]).reshape(1, 1, 3)
    prob.run_model()
    rear = n_ax / (w * h) + mn * (w / 2) / (h * w**3 / 12)  # rear corners (c = +w/2)
    np.testing.assert_allclose((prob["g_ss_tension"][0, 0, 1] + 1) * 276e6, rear, rtol=1e-12)


def test_partials():
    prob = _prob()
    rng = np.random.default_rng(3)
    prob["width"] = rng.uniform(0.2, 0.6, 3)
    prob["height"] = rng.uniform(0.4, 1.0, 3)
    prob["F_csn"] = rng.normal(size=(2, 3, 3)) * 1e5
    prob["M_csn"] = rng.normal(size=(2, 3, 3)) * 1e6
    prob.run_model()
    data = prob.check_partials(method="fd", form="central", step=1e-7, out_stream=None)
    assert_check_partials(data, atol=1e-5, rtol=1e-6)
