"""BoxStress with the section properties as inputs (from BoxSection) gives the stresses of the
self-contained recovery, and its partials, chained through BoxSection, are exact."""

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.components.section import BoxSection
from wingmdao.components.stress import BoxStress
from wingmdao.materials import ALUMINIUM
from wingmdao.stress.box_stress import FAMILIES, SECTION_PROPERTIES

NT, N = 3, 4
WALLS = ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")


def _problem(section_properties):
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("section", BoxSection(num_stations=N, material=ALUMINIUM), promotes_inputs=["*"])
    prob.model.add_subsystem("stress", BoxStress(num_times=NT, num_stations=N, material=ALUMINIUM,
                                                 families=tuple(FAMILIES), section_properties=section_properties),
                             promotes_inputs=["width", "height", *WALLS])
    if section_properties:
        for name in SECTION_PROPERTIES:
            prob.model.connect(f"section.{name}", f"stress.{name}")
    prob.setup(force_alloc_complex=True)
    rng = np.random.default_rng(11)
    prob.set_val("width", rng.uniform(0.6, 1.0, N))
    prob.set_val("height", rng.uniform(0.15, 0.3, N))
    for i, w in enumerate(WALLS):
        prob.set_val(w, rng.uniform(2e-3, 9e-3, N) * (1 + 0.3 * i))  # unsymmetric walls: offsets, Ixz
    prob.set_val("stress.F_csn", rng.normal(0, 5e4, (NT, N, 3)))
    prob.set_val("stress.M_csn", rng.normal(0, 2e5, (NT, N, 3)))
    prob.run_model()
    return prob


@pytest.fixture(scope="module")
def both():
    return _problem(False), _problem(True)


def test_same_stresses(both):
    ref, new = both
    for name in ("sigma_corner", "sigma_vm", "tau_cent", *(f"g_{f}" for f in FAMILIES)):
        np.testing.assert_allclose(new.get_val(f"stress.{name}"), ref.get_val(f"stress.{name}"), rtol=1e-12, atol=1e-9)


def test_partials(both):
    src = both[1]
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("s", BoxStress(num_times=NT, num_stations=N, material=ALUMINIUM, section_properties=True),
                             promotes=["*"])
    prob.setup()
    for name in ("width", "height", *WALLS):
        prob.set_val(name, src.get_val(name))
    for name in SECTION_PROPERTIES:
        prob.set_val(name, src.get_val(f"section.{name}"))
    for name in ("F_csn", "M_csn"):
        prob.set_val(name, src.get_val(f"stress.{name}"))
    prob.run_model()
    data = prob.check_partials(method="fd", form="central", step=1e-6, step_calc="rel", out_stream=None)
    assert_check_partials(data, atol=1e-6, rtol=1e-5)


def test_same_totals_through_the_section(both):
    ref, new = both
    of = [f"stress.g_{f}" for f in FAMILIES]
    t_ref = ref.compute_totals(of=of, wrt=list(WALLS))
    t_new = new.compute_totals(of=of, wrt=list(WALLS))
    for key, val in t_ref.items():
        np.testing.assert_allclose(t_new[key], val, rtol=1e-9, atol=1e-12 * np.abs(val).max())
