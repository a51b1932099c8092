"""Maneuver loads: 25.337 load factors, Schrenk / elliptic distributions, line loads on a beam."""

import numpy as np
import pytest

from wingmdao.loads.distribution import lift_per_span, span_per_beam_length, trapezoid
from wingmdao.loads.maneuver import limit_load_factors, maneuver_line_loads


@pytest.mark.parametrize(
    "weight_lb, n_expected",
    [
        (41005.0, 2.1 + 24000.0 / 51005.0),  # PEGASUS TOGW: 2.570542, above the 2.5 floor
        (50000.0, 2.5),  # formula gives exactly 2.5
        (70000.0, 2.5),  # formula 2.4429 -> clipped up to 2.5
        (14000.0, 3.1),  # 2.1 + 24000/24000
        (4000.0, 3.8),  # formula 3.8143 -> clipped down to 3.8
    ],
)
def test_limit_load_factors(weight_lb, n_expected):
    n_pos, n_neg = limit_load_factors(weight_lb)
    assert n_pos == pytest.approx(n_expected, rel=1e-12)
    assert n_neg == -1.0


def test_limit_load_factor_pegasus_hand_value():
    assert limit_load_factors(41005.0)[0] == pytest.approx(2.570542, abs=1e-6)
    with pytest.raises(ValueError, match=r"weight_lb.*\(0, inf\) lb"):
        limit_load_factors(-10.0)


def test_elliptic_matches_closed_form_on_fine_mesh():
    b2, lift = 12.0, 1.0e5
    y = b2 * np.sin(np.linspace(0.0, np.pi / 2, 801))  # cosine spacing resolves the tip
    l = lift_per_span(y, np.full_like(y, 2.0), lift, "elliptic")
    exact = 4.0 * lift / (np.pi * b2) * np.sqrt(1.0 - (y / b2) ** 2)
    assert trapezoid(l, y) == pytest.approx(lift, rel=1e-13)
    np.testing.assert_allclose(l, exact, rtol=0, atol=2e-5 * exact[0])


def test_schrenk_rectangular_wing_closed_form_and_integral():
    # rectangular wing, c constant: l = L/2 (1/b2 + 4/(pi b2) sqrt(1 - eta^2))
    b2, lift = 10.0, 8.0e4
    y = b2 * np.sin(np.linspace(0.0, np.pi / 2, 801))
    l = lift_per_span(y, np.full_like(y, 1.7), lift)
    exact = 0.5 * lift * (1.0 / b2 + 4.0 / (np.pi * b2) * np.sqrt(1.0 - (y / b2) ** 2))
    np.testing.assert_allclose(l, exact, rtol=0, atol=2e-5 * exact[0])
    assert trapezoid(l, y) == pytest.approx(lift, rel=1e-13)


def test_schrenk_tapered_integral_and_fuselage_option():
    y = np.linspace(0.0, 12.0, 25)
    chord = 3.0 - 0.15 * y
    l = lift_per_span(y, chord, 5.0e4, "schrenk", fuselage_half_width=1.2, fuselage_carries_lift=False)
    assert np.all(l[y < 1.2] == 0.0) and np.all(l[y >= 1.2] > 0.0)
    assert trapezoid(l, y) == pytest.approx(5.0e4, rel=1e-13)
    l_user = lift_per_span(y, chord, 5.0e4, np.ones_like(y))
    np.testing.assert_allclose(l_user, 5.0e4 / 12.0, rtol=1e-13)


def test_distribution_bad_input():
    y = np.array([0.0, 1.0, 1.0, 3.0])
    with pytest.raises(ValueError, match=r"y\[2\].*station 2"):
        lift_per_span(y, np.ones(4), 1.0)
    with pytest.raises(ValueError, match=r"chord\[1\].*\[0, inf\) m"):
        lift_per_span(np.arange(4.0), np.array([1.0, -1.0, 1.0, 1.0]), 1.0)
    with pytest.raises(ValueError, match="distribution"):
        lift_per_span(np.arange(4.0), np.ones(4), 1.0, "triangular")


def _swept_beam(n=11, b2=12.0, sweep_deg=20.0):
    y = np.linspace(0.0, b2, n)
    return np.column_stack([y * np.tan(np.radians(sweep_deg)), y, 0.02 * y])


def test_maneuver_line_loads_equilibrium_and_torsion():
    r = _swept_beam()
    chord = np.linspace(3.0, 1.2, r.shape[0])
    weight_N = 18600.0 * 9.80665
    n = 2.5
    loads = maneuver_line_loads(r, chord, 0.45, weight_N, n, cp_fraction=0.25)
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(r, axis=0), axis=1))])
    # total vertical force on the half wing = n W / 2
    assert trapezoid(loads.force_per_length[:, 2], s) == pytest.approx(0.5 * n * weight_N, rel=1e-12)
    assert np.all(loads.force_per_length[:, :2] == 0.0)
    # lift at 25 % chord, axis at 45 %: offset -0.2 c (ahead), moment +0.2 c f_z about +y (nose up)
    np.testing.assert_allclose(
        loads.moment_per_length[:, 1], 0.2 * chord * loads.force_per_length[:, 2], rtol=1e-12
    )
    # per unit beam length = per unit span * dy/ds; dy/ds = cos(sweep) cos(dihedral) here
    dyds = span_per_beam_length(r)
    np.testing.assert_allclose(dyds, 1.0 / np.sqrt(1.0 + np.tan(np.radians(20.0)) ** 2 + 0.02**2), rtol=1e-12)
    np.testing.assert_allclose(loads.force_per_length[:, 2], loads.lift_per_span * dyds, rtol=1e-12)


def test_maneuver_bad_input():
    r = _swept_beam()
    with pytest.raises(ValueError, match=r"beam_axis_fraction\[3\].*node 3.*\[0, 1\]"):
        bad = np.full(r.shape[0], 0.4)
        bad[3] = 1.4
        maneuver_line_loads(r, 2.0, bad, 1e5, 2.5)
    with pytest.raises(ValueError, match="weight_N"):
        maneuver_line_loads(r, 2.0, 0.4, -1e5, 2.5)


def test_pegasus_elliptic_root_bending_moment_closed_form():
    # PEGASUS (App. D.2, Table D.3): TOGW 41 005 lb, span 80.58962 ft, 2.5 g (Sec. 5.1).
    # Elliptic loading: root bending moment of the half wing = (L/2) * 4 b2 / (3 pi).
    weight_N = 41005.0 * 0.45359237 * 9.80665
    b2 = 0.5 * 80.58962 * 0.3048
    y = b2 * np.sin(np.linspace(0.0, np.pi / 2, 2001))
    r = np.column_stack([np.zeros_like(y), y, np.zeros_like(y)])
    loads = maneuver_line_loads(r, np.full_like(y, 2.2), 0.465, weight_N, 2.5, distribution="elliptic")
    fz = loads.force_per_length[:, 2]
    root_moment = trapezoid(fz * y, y)
    half_lift = 0.5 * 2.5 * weight_N  # 18 599.6 kg * 9.80665 * 1.25 = 227 999 N
    assert half_lift == pytest.approx(227999.2, rel=1e-6)
    assert root_moment == pytest.approx(half_lift * 4.0 * b2 / (3.0 * np.pi), rel=1e-5)
