"""Structural mass (App. F.1): prismatic and tapered closed forms, partials, bad input."""

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.components.mass import StructuralMass
from wingmdao.materials import Material


def _run(area, pos, mu=None, **opts):
    n = len(area)
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("m", StructuralMass(num_nodes=n, **opts), promotes=["*"])
    prob.setup()
    prob["A"] = area
    prob["node_positions"] = pos
    if mu is not None:
        prob["nonstructural_mass_per_length"] = mu
    prob.run_model()
    return prob


def _swept_line(n, length, sweep_deg=25.0, dihedral_deg=4.0):
    sw, dh = np.radians(sweep_deg), np.radians(dihedral_deg)
    direction = np.array([np.sin(sw) * np.cos(dh), np.cos(sw) * np.cos(dh), np.sin(dh)])
    return np.linspace(0.0, length, n)[:, None] * direction[None, :]


def test_prismatic_beam_rho_A_L():
    prob = _run(np.full(6, 0.012), _swept_line(6, 7.5), density=2780.0)
    assert prob["mass"].item() == pytest.approx(2780.0 * 0.012 * 7.5, rel=1e-14)


def test_tapered_solid_square_equals_pyramid_frustum():
    # solid square, side 0.30 m at the root tapering linearly to 0.12 m over 9 m
    a_root, a_tip, length = 0.30, 0.12, 9.0
    n = 5
    side = np.linspace(a_root, a_tip, n)
    prob = _run(side**2, _swept_line(n, length), density=1600.0)
    # frustum of a pyramid, V = h/3 (B1 + B2 + sqrt(B1 B2)), B = side^2
    v_exact = length / 3.0 * (a_root**2 + a_tip**2 + a_root * a_tip)
    assert prob["mass"].item() == pytest.approx(1600.0 * v_exact, rel=1e-13)
    # also equal to the integral of side(y)^2 over the length (independent closed form)
    integral = length * (a_root**2 + a_root * (a_tip - a_root) + (a_tip - a_root) ** 2 / 3.0)
    assert v_exact == pytest.approx(integral, rel=1e-14)


def test_nonstructural_mass_trapezoid_and_material_object():
    n = 4
    pos = _swept_line(n, 6.0)
    mu = np.linspace(30.0, 10.0, n)  # linear: trapezoid is exact
    steel = Material("steel", E=200e9, rho=7850.0, sigma_y=250e6)
    prob = _run(np.full(n, 1e-3), pos, mu, material=steel, density=1.0)
    assert prob["mass"].item() == pytest.approx(7850.0 * 1e-3 * 6.0 + 6.0 * (30.0 + 10.0) / 2, rel=1e-14)


def test_check_partials_random_asymmetric():
    rng = np.random.default_rng(11)
    n = 7
    area = rng.uniform(2e-3, 9e-3, n)
    pos = np.cumsum(rng.uniform(0.3, 1.2, (n, 3)) * np.array([0.4, 1.0, 0.1]), axis=0)
    mu = rng.uniform(5.0, 40.0, n)
    prob = _run(area, pos, mu, density=2780.0)
    data = prob.check_partials(method="fd", form="central", step=1e-7, out_stream=None)
    assert_check_partials(data, atol=1e-6, rtol=1e-6)


def test_negative_area_names_the_node():
    area = np.full(5, 1e-3)
    area[3] = -2e-4
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("m", StructuralMass(num_nodes=5, density=2780.0), promotes=["*"])
    prob.setup()
    prob["A"] = area
    prob["node_positions"] = _swept_line(5, 4.0)
    with pytest.raises(Exception, match=r"A\[3\].*node 3.*\(0, inf\) m\^2"):
        prob.run_model()


def test_coincident_nodes_and_missing_density_raise():
    pos = _swept_line(4, 3.0)
    pos[2] = pos[1]
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("m", StructuralMass(num_nodes=4, density=2780.0), promotes=["*"])
    prob.setup()
    prob["node_positions"] = pos
    with pytest.raises(Exception, match="coincide"):
        prob.run_model()
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("m", StructuralMass(num_nodes=4))
    with pytest.raises(ValueError, match="density"):
        prob.setup()


def test_initial_mass_closed_form_without_a_problem(monkeypatch):
    """initial_mass computes directly (no om.Problem). Cantilever guess b: w = 2 - 1.5 s, h = 4 - 3 s
    (similar sections, so the frustum is exact): V = 8 L int_0^1 (1 - 0.75 s)^2 ds = 35 m^3 for L = 10 m,
    m = 2700 kg/m^3 x 35 m^3 = 94 500 kg. Box: hollow 3 x 0.5 m prism, walls 0.02 m, length 10 m:
    A = 3 x 0.5 - 2.96 x 0.46 = 0.1384 m^2, m = 2700 x 1.384 = 3736.8 kg."""
    from wingmdao.cases import build_case
    from wingmdao.materials import ALUMINIUM
    from wingmdao.sizing import WALL_VARS, SizingOptions, WingGeometry, initial_mass

    def no_problem(*a, **k):
        raise AssertionError("initial_mass built an om.Problem")

    monkeypatch.setattr(om, "Problem", no_problem)
    s = build_case("cantilever", stations=7, guess="b")
    assert initial_mass(s.geometry, s.material, s.options, s.section) == pytest.approx(94500.0, rel=1e-12)
    n = 4
    geo = WingGeometry(node_positions=np.column_stack([np.zeros(n), np.linspace(0, 10, n), np.zeros(n)]),
                       node_euler_angles=np.zeros((n, 3)), width=np.full(n, 3.0), height=np.full(n, 0.5),
                       nonstructural_mass_per_length=np.full(n, 50.0))  # not part of the scaling mass
    opts = SizingOptions(initial={w: 0.02 for w in WALL_VARS})
    assert initial_mass(geo, ALUMINIUM, opts) == pytest.approx(ALUMINIUM.rho * 1.384, rel=1e-12)
