"""NACA airfoil generator (wingmdao.section.fe.airfoil) against published section data."""

import numpy as np
import pytest

from wingmdao.section.fe.airfoil import _camber4, _camber5, _thickness, naca_surfaces


def test_max_thickness_of_a_4_digit_section_is_its_last_two_digits():
    x = np.linspace(0, 1, 20001)
    assert 2 * _thickness(x, 0.12).max() == pytest.approx(0.12, rel=2e-3)
    assert x[np.argmax(_thickness(x, 0.12))] == pytest.approx(0.30, abs=0.01)  # at 30 % chord


def test_naca_2412_max_camber_2_percent_at_40_percent():
    x = np.linspace(0, 1, 10001)
    yc, _ = _camber4(x, 0.02, 0.4)
    assert yc.max() == pytest.approx(0.02, rel=1e-6)
    assert x[np.argmax(yc)] == pytest.approx(0.4, abs=1e-3)


def test_naca_230_mean_line_peaks_at_15_percent():
    # 230: design C_l 0.3, maximum camber 1.8 % at 15 % chord (Abbott & von Doenhoff)
    x = np.linspace(0, 1, 10001)
    yc, _ = _camber5(x, "230")
    assert x[np.argmax(yc)] == pytest.approx(0.15, abs=0.005)
    assert yc.max() == pytest.approx(0.0184, abs=3e-4)


def test_430_mean_line_is_twice_the_230_one():
    # the 5-digit mean line scales with the design lift coefficient 0.15 L
    x = np.linspace(0, 1, 101)
    np.testing.assert_allclose(_camber5(x, "430")[0], 2 * _camber5(x, "230")[0], rtol=1e-12)


def test_surfaces_enclose_the_thickness():
    up, lo = naca_surfaces("43018")
    x = np.linspace(0.05, 0.95, 50)
    assert np.all(up(x) > lo(x))
    assert (up(x) - lo(x)).max() == pytest.approx(0.18, rel=0.02)


def test_bad_designation():
    with pytest.raises(ValueError, match="not supported"):
        naca_surfaces("23512")
