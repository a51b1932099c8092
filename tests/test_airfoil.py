"""NACA airfoil generator against published section data."""

import numpy as np
import pytest

from wingmdao.cases.airfoil import camber, naca_coordinates, thickness


def test_max_thickness_of_a_4_digit_section_is_its_last_two_digits():
    x = np.linspace(0, 1, 20001)
    assert 2 * thickness(x, 0.12).max() == pytest.approx(0.12, rel=2e-3)
    assert x[np.argmax(thickness(x, 0.12))] == pytest.approx(0.30, abs=0.01)  # at 30 % chord


def test_naca_2412_max_camber_2_percent_at_40_percent():
    x = np.linspace(0, 1, 10001)
    yc, _ = camber("2412", x)
    assert yc.max() == pytest.approx(0.02, rel=1e-6)
    assert x[np.argmax(yc)] == pytest.approx(0.4, abs=1e-3)


def test_naca_23012_mean_line_peaks_at_15_percent():
    # 230: design C_l 0.3, maximum camber at 15 % chord, 1.8 % (Abbott & von Doenhoff)
    x = np.linspace(0, 1, 10001)
    yc, _ = camber("23012", x)
    assert x[np.argmax(yc)] == pytest.approx(0.15, abs=0.005)
    assert yc.max() == pytest.approx(0.0184, abs=3e-4)


def test_coordinates_closed_and_ordered():
    xy = naca_coordinates("43018", 101)
    assert xy.shape == (201, 2)
    np.testing.assert_allclose(xy[0], xy[-1], atol=1e-12)  # closed trailing edge
    np.testing.assert_allclose(xy[100], [0.0, 0.0], atol=1e-12)  # leading edge in the middle


def test_bad_designation():
    with pytest.raises(ValueError, match="must be digits"):
        naca_coordinates("64A010")
