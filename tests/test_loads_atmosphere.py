"""ISA against published standard-atmosphere table values (ICAO Doc 7488 / US Std Atm 1976)."""

import numpy as np
import pytest

from wingmdao.loads import atmosphere as atm


@pytest.mark.parametrize(
    "h, T, p, rho, a",
    [
        (0.0, 288.15, 101325.0, 1.2250, 340.29),
        (5000.0, 255.65, 54019.9, 0.73612, 320.53),
        (11000.0, 216.65, 22632.1, 0.36392, 295.07),
        (15000.0, 216.65, 12044.6, 0.19367, 295.07),
        (20000.0, 216.65, 5474.89, 0.088035, 295.07),
    ],
)
def test_isa_table(h, T, p, rho, a):
    s = atm.isa(h)
    assert s.temperature == pytest.approx(T, rel=1e-6)
    assert s.pressure == pytest.approx(p, rel=2e-5)
    assert s.density == pytest.approx(rho, rel=2e-4)
    assert s.speed_of_sound == pytest.approx(a, rel=2e-5)


def test_20000_ft_and_25000_ft():
    # ISA tables (imperial): density ratio sigma = 0.5328 at 20 000 ft, 0.4481 at 25 000 ft
    assert atm.density(atm.altitude_ft_to_m(20000)) / 1.225 == pytest.approx(0.5328, abs=1e-4)
    assert atm.density(atm.altitude_ft_to_m(25000)) / 1.225 == pytest.approx(0.4481, abs=1e-4)


def test_eas_tas_round_trip_and_sea_level_identity():
    assert atm.eas_to_tas(100.0, 0.0) == pytest.approx(100.0, rel=1e-12)
    h = np.array([1000.0, 7000.0, 15000.0])
    v = np.array([120.0, 150.0, 180.0])
    np.testing.assert_allclose(atm.tas_to_eas(atm.eas_to_tas(v, h), h), v, rtol=1e-14)
    # at 11 km, sigma = 0.36392 / 1.225 = 0.29708: V_T = V_E / sqrt(sigma)
    assert atm.eas_to_tas(100.0, 11000.0) == pytest.approx(100.0 / np.sqrt(0.36392 / 1.225), rel=2e-4)


def test_array_and_out_of_range():
    assert atm.density(np.array([0.0, 11000.0])).shape == (2,)
    with pytest.raises(ValueError, match=r"altitude_m = 21000.*index 1.*\[0, 20000\] m"):
        atm.isa(np.array([0.0, 21000.0]))
    with pytest.raises(ValueError, match="altitude_m"):
        atm.isa(-5.0)
