"""Flutter and divergence of the Goland and HALE wings (beam + Jones/Wagner strip theory).

References: published strip-theory values (Goland: Patil, Hodges & Cesnik, J. Aircraft 37(5),
2000 and Palacios & Epureanu, AIAA 2011-1917; HALE: Patil, Hodges & Cesnik, J. Aircraft 38(1),
2001) and the closed-form torsional divergence of a uniform straight wing,
q_D = (pi/2)^2 GJ / (e c a s^2) (e: elastic axis aft of the quarter chord).
"""

import numpy as np
import pytest

from wingmdao.stability import critical_speeds, sweep
from wingmdao.stability.cases import flutter_problem

pytestmark = pytest.mark.slow


def divergence_closed_form(mod):
    e = (mod.ELASTIC_AXIS - 0.25) * mod.CHORD
    q = (np.pi / 2) ** 2 * mod.GJ / (e * mod.CHORD * 2 * np.pi * mod.SEMI_SPAN**2)
    return np.sqrt(2 * q / mod.DENSITY)


@pytest.mark.parametrize("name, speeds, tol_v, tol_w", [
    ("goland", np.linspace(60.0, 280.0, 8), 0.01, 0.025),
    ("hale", np.linspace(10.0, 40.0, 7), 0.02, 0.03),
])
def test_flutter_and_divergence_vs_published(name, speeds, tol_v, tol_w):
    import importlib

    mod = importlib.import_module(f"wingmdao.cases.{name}")
    prob = flutter_problem(name, 21)
    res = sweep(prob.system, prob.params_at, speeds, n_track=4, weights=prob.beam_weights(),
                **prob.eig_options)
    crit = critical_speeds(res, xtol=1e-4)
    pub = mod.PUBLISHED
    assert crit["flutter_speed"] == pytest.approx(pub["flutter_speed_m_s"], rel=tol_v)
    assert crit["flutter_frequency"] == pytest.approx(pub["flutter_frequency_rad_s"], rel=tol_w)
    assert crit["divergence_speed"] == pytest.approx(pub["divergence_speed_m_s"], rel=0.01)
    # uniform straight wing: strip-theory divergence closed form
    assert crit["divergence_speed"] == pytest.approx(divergence_closed_form(mod), rel=2e-3)


def test_case_without_aero_data():
    with pytest.raises(ValueError, match="no aerodynamic"):
        flutter_problem("crm")
