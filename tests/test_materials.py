"""Materials: built-in values, derived moduli, validation."""

import math

import pytest

from wingmdao.materials import ALUMINIUM, MATERIALS, Material, get_material


def test_dissertation_aluminium():
    assert ALUMINIUM.E == 70e9 and ALUMINIUM.rho == 2700.0 and ALUMINIUM.sigma_y == 276e6
    assert ALUMINIUM.nu == 0.33
    assert ALUMINIUM.G == pytest.approx(70e9 / 2.66, rel=1e-12)  # 26.3 GPa by hand


def test_nu_from_g():
    m = Material("x", E=200e9, rho=7800.0, sigma_y=250e6, G=80e9)
    assert m.nu == pytest.approx(0.25, rel=1e-12)
    assert m.G == 80e9


def test_builtins_plausible():
    for m in MATERIALS.values():
        assert 1e3 < m.rho < 1e4 and 1e8 < m.sigma_y < 2e9 and 5e10 < m.E < 3e11
        assert m.G == pytest.approx(m.E / (2 * (1 + m.nu)))


@pytest.mark.parametrize("name,expected", [("aluminium", "aluminium"), ("Aluminum", "aluminium"),
                                           ("AL7075-T6", "al7075-t6"), ("ti-6al-4v", "ti-6al-4v"),
                                           ("Steel-4130", "steel-4130"), ("al2024-t3", "al2024-t3")])
def test_get_material(name, expected):
    assert get_material(name).name == expected


def test_unknown_material_lists_valid():
    with pytest.raises(ValueError, match="unknown material 'unobtainium'.*aluminium.*al7075-t6"):
        get_material("unobtainium")


@pytest.mark.parametrize("kwargs,match", [
    (dict(E=-1.0, rho=1.0, sigma_y=1.0), r"E \(Young's modulus\) = -1.0 Pa; allowed range \(0, inf\) Pa"),
    (dict(E=1e9, rho=math.nan, sigma_y=1.0), r"rho \(density\) = nan"),
    (dict(E=1e9, rho=1.0, sigma_y=0.0), r"sigma_y"),
    (dict(E=1e9, rho=1.0, sigma_y=1.0, nu=0.5), r"nu = 0.5; allowed range \(-1, 0.5\)"),
    (dict(E=1e9, rho=1.0, sigma_y=1.0, nu=-1.0), r"allowed range \(-1, 0.5\)"),
    (dict(E=1e9, rho=1.0, sigma_y=1.0, G=0.2e9), r"nu in \(-1, 0.5\)"),
    (dict(E=1e9, rho=1.0, sigma_y=1.0, G=-1.0), r"G \(shear modulus\)"),
    (dict(E=1e9, rho=1.0, sigma_y=1.0, G=0.4e9, nu=0.3), r"only one of G and nu"),
])
def test_bad_material(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Material("bad", **kwargs)
