"""25.341(a) gust: regulation numbers by hand, 1 - cos shape, Kussner lag, strip loads on a beam."""

import numpy as np
import pytest
from scipy.integrate import quad

from wingmdao.loads import gust as g
from wingmdao.loads.atmosphere import density
from wingmdao.loads.maneuver import maneuver_line_loads


# ---------------------------------------------------------------- regulation numbers
@pytest.mark.parametrize(
    "alt_ft, u_fps", [(0.0, 56.0), (15000.0, 44.0), (60000.0, 20.86), (7500.0, 50.0), (20000.0, 41.428889)]
)
def test_reference_gust_velocity_table(alt_ft, u_fps):
    # 20 000 ft by hand: 44 - (44 - 20.86) * 5000 / 45000 = 41.428889 ft/s
    assert g.reference_gust_velocity_eas(alt_ft) == pytest.approx(u_fps * 0.3048, rel=1e-7)
    assert g.reference_gust_velocity_eas(alt_ft, at_vd=True) == pytest.approx(0.5 * u_fps * 0.3048, rel=1e-7)


def test_design_gust_at_20000_ft_by_hand():
    # Z_mo = 30 000 ft, R1 = MLW/MTOW = 0.88, R2 = MZFW/MTOW = 0.80, H = 350 ft, altitude 20 000 ft:
    # F_gz = 1 - 30000/250000 = 0.88;  tan(0.22 pi) = tan(39.6 deg) = 0.827272
    # F_gm = sqrt(0.80 * 0.827272) = 0.813522;  F_g(sea level) = (0.88 + 0.813522)/2 = 0.846761
    # F_g(20 000 ft) = 0.846761 + (1 - 0.846761) * 20000/30000 = 0.948920
    # U_ds = 41.428889 * 0.948920 * (350/350)^(1/6) = 39.3127 ft/s EAS; H = 100 ft: * (100/350)^(1/6) = 31.9047
    d = g.design_gust(20000.0, 350.0, 30000.0, 0.88, 0.80)
    assert d.alleviation_factor == pytest.approx(0.948920, abs=1e-6)
    assert d.u_ds_eas_fps == pytest.approx(39.3127, abs=1e-4)
    assert d.u_ds_eas == pytest.approx(39.3127 * 0.3048, abs=1e-4)
    assert d.gust_gradient_m == pytest.approx(106.68, rel=1e-12)
    d100 = g.design_gust(20000.0, 100.0, 30000.0, 0.88, 0.80)
    assert d100.u_ds_eas_fps == pytest.approx(31.9047, abs=1e-4)
    # F_g = 1 at and above Z_mo; sea level value at 0 ft
    assert g.flight_profile_alleviation_factor(35000.0, 30000.0, 0.88, 0.80) == 1.0
    assert g.flight_profile_alleviation_factor(0.0, 30000.0, 0.88, 0.80) == pytest.approx(0.846761, abs=1e-6)


def test_gust_gradients_span_30_to_350_ft():
    h = g.gust_gradients_ft(5)
    np.testing.assert_allclose(h, [30.0, 110.0, 190.0, 270.0, 350.0])


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: g.reference_gust_velocity_eas(65000.0), r"altitude_ft = 65000.0 ft; allowed range \[0, 60000\] ft"),
        (lambda: g.reference_gust_velocity_eas(-100.0), r"altitude_ft.*\[0, 60000\] ft"),
        (lambda: g.design_gust_velocity_eas(25.0, 10000.0, 0.9), r"gust_gradient_ft \(H\) = 25.0 ft; allowed range \[30, 350\] ft"),
        (lambda: g.design_gust_velocity_eas(400.0, 10000.0, 0.9), r"\[30, 350\] ft"),
        (lambda: g.flight_profile_alleviation_factor(1000.0, 30000.0, 1.2, 0.8), r"mlw_over_mtow \(R1\) = 1.2.*\(0, 1\]"),
        (lambda: g.flight_profile_alleviation_factor(1000.0, 30000.0, 0.9, 0.0), r"mzfw_over_mtow \(R2\) = 0.0.*\(0, 1\]"),
        (lambda: g.flight_profile_alleviation_factor(1000.0, 0.0, 0.9, 0.8), r"z_mo_ft"),
        (lambda: g.gust_gradients_ft(1), r"count"),
    ],
)
def test_validation_ranges(call, match):
    with pytest.raises(ValueError, match=match):
        call()


# ---------------------------------------------------------------- 1 - cos shape
def test_one_minus_cosine_shape():
    h, u_ds = 50.0, 12.0
    s = np.array([-1.0, 0.0, 25.0, 50.0, 75.0, 100.0, 101.0])
    u = g.one_minus_cosine(s, h, u_ds)
    np.testing.assert_allclose(u, [0.0, 0.0, 6.0, 12.0, 6.0, 0.0, 0.0], atol=1e-12)
    fine = np.linspace(0, 2 * h, 2001)
    assert np.argmax(g.one_minus_cosine(fine, h, u_ds)) == 1000


# ---------------------------------------------------------------- Kussner
def test_kussner_sears_values():
    assert g.kussner_sears(0.0) == 0.0
    assert g.kussner_sears(1e6) == pytest.approx(1.0)
    assert g.kussner_sears(2.0) == pytest.approx(1 - 0.5 * np.exp(-0.26) - 0.5 * np.exp(-2.0), rel=1e-15)


def test_duhamel_sharp_edged_gust_is_kussner_function():
    # gust present from the first sample: response is exactly w0 psi(s)
    s = np.linspace(0.0, 40.0, 201)
    w = np.full_like(s, 3.0)
    np.testing.assert_allclose(g.kussner_lagged_velocity(s, w), 3.0 * g.kussner_sears(s), rtol=0, atol=1e-13)


@pytest.mark.parametrize("n", [401, 1601])
def test_duhamel_step_between_samples_converges(n):
    # sharp edge at s = 5.03 (between samples): the sampled step is a one-sample ramp; error <= w0 psi'max ds
    s = np.linspace(0.0, 40.0, n)
    w = np.where(s >= 5.03, 2.0, 0.0)
    out = g.kussner_lagged_velocity(s, w)
    exact = 2.0 * g.kussner_sears(s - 5.03) * (s >= 5.03)
    ds = s[1] - s[0]
    assert np.max(np.abs(out - exact)) <= 2.0 * 0.565 * ds


def test_duhamel_one_minus_cosine_against_quadrature():
    # continuous Duhamel integral int_0^s w'(s') psi(s - s') ds' by adaptive quadrature
    hs, u = 20.0, 1.5  # gust gradient in semichords
    dw = lambda sp: 0.5 * u * np.pi / hs * np.sin(np.pi * sp / hs) if 0 <= sp <= 2 * hs else 0.0
    s = np.linspace(0.0, 80.0, 801)
    out = g.kussner_lagged_velocity(s, g.one_minus_cosine(s, hs, u))
    for k in (50, 200, 300, 400, 600):
        ref, _ = quad(lambda sp: dw(sp) * g.kussner_sears(s[k] - sp), 0.0, min(s[k], 2 * hs), limit=200)
        assert out[k] == pytest.approx(ref, abs=2e-5 * u)


# ---------------------------------------------------------------- lift-curve slope
def test_lift_curve_slope():
    assert g.lift_curve_slope() == pytest.approx(2 * np.pi)
    # Helmbold, A = 6, unswept, incompressible: 2 pi 6 / (2 + sqrt(40)) = 4.52866
    assert g.lift_curve_slope(aspect_ratio=6.0) == pytest.approx(4.52866, abs=1e-5)
    assert g.lift_curve_slope(aspect_ratio=1e3) == pytest.approx(2 * np.pi, rel=3e-3)
    assert g.lift_curve_slope(mach=0.6) == pytest.approx(2 * np.pi / 0.8, rel=1e-14)


# ---------------------------------------------------------------- strip loads on a beam
def _beam(n=9, b2=12.0, sweep_deg=15.0):
    y = np.linspace(0.0, b2, n)
    r = np.column_stack([y * np.tan(np.radians(sweep_deg)), y, np.zeros(n)])
    return r, np.linspace(2.8, 1.4, n), np.full(n, 0.45)


def test_gust_line_loads_peak_and_penetration_delay():
    r, chord, xb = _beam()
    v, alt = 150.0, 6000.0
    h = 60.0
    u_ds_eas = 12.0
    time = np.linspace(0.0, 1.5, 1501)
    hist = g.gust_line_loads(
        r, chord, xb, time, gust_gradient_m=h, u_ds_eas=u_ds_eas, airspeed_tas=v, altitude_m=alt,
        gust_start_time=0.1,
    )
    assert hist.force_per_length.shape == (1501, 9, 3) and hist.time[0] == 0.0
    rho = float(density(alt))
    u_tas = u_ds_eas * np.sqrt(1.225 / rho)
    dyds = np.cos(np.radians(15.0))
    # hand formula: peak lift per unit span = 1/2 rho V c 2 pi U_ds,TAS; per beam length * cos(sweep)
    peak = 0.5 * rho * v * chord * 2 * np.pi * u_tas * dyds
    np.testing.assert_allclose(hist.force_per_length[:, :, 2].max(axis=0), peak, rtol=1e-5)
    # quarter-chord of station i is reached (x_cp_i - x_front)/V after the front: peak at + H/V
    x_le = r[:, 0] - xb * chord
    x_cp = x_le + 0.25 * chord
    t_peak = 0.1 + (x_cp - x_le.min()) / v + h / v
    np.testing.assert_allclose(time[np.argmax(hist.force_per_length[:, :, 2], axis=0)], t_peak, atol=1.5e-3)
    # torsion: lift 0.2 c ahead of the axis: nose-up moment + 0.2 c f_z about y
    np.testing.assert_allclose(
        hist.moment_per_length[..., 1], 0.2 * chord * hist.force_per_length[..., 2], rtol=1e-12, atol=1e-9
    )
    assert np.all(hist.force_per_length[time < 0.1] == 0.0)


def test_gust_with_kussner_lags_and_reduces_peak_and_adds_steady():
    r, chord, xb = _beam()
    time = np.linspace(0.0, 1.0, 801)
    kw = dict(gust_gradient_m=9.144, u_ds_eas=15.0, airspeed_tas=160.0, altitude_m=5000.0)
    qs = g.gust_line_loads(r, chord, xb, time, **kw)
    ku = g.gust_line_loads(r, chord, xb, time, kussner=True, **kw)
    assert np.all(ku.force_per_length[..., 2].max(axis=0) < qs.force_per_length[..., 2].max(axis=0))
    steady = maneuver_line_loads(r, chord, xb, 1.8e5, 1.0)
    down = g.gust_line_loads(r, chord, xb, time, direction=-1, steady=steady, **kw)
    np.testing.assert_allclose(
        down.force_per_length, steady.force_per_length[None] - qs.force_per_length, rtol=1e-12, atol=1e-9
    )
    with pytest.raises(ValueError, match=r"steady_load_factor = -1.0; allowed range \(0, inf\)"):
        g.gust_line_loads(r, chord, xb, time, steady=steady, steady_load_factor=-1.0, **kw)
    with pytest.raises(ValueError, match=r"gust_gradient_m \(H\).*\[9.144, 106.68\] m"):
        g.gust_line_loads(r, chord, xb, time, **{**kw, "gust_gradient_m": 5.0})
    with pytest.raises(ValueError, match=r"time\[0\]"):
        g.gust_line_loads(r, chord, xb, time + 0.5, **kw)


def test_total_gust_lift_equals_eas_form_without_delay():
    # without penetration delay every strip peaks together; the half-wing lift increment is then
    # 1/2 rho0 V_E U_E a S_half (EAS form: rho V_T U_T = rho0 V_E U_E), S_half = int c dy
    r, chord, xb = _beam(n=9, b2=12.0, sweep_deg=15.0)
    alt, v_tas, u_e = 7000.0, 170.0, 10.0
    time = np.linspace(0.0, 1.0, 201)
    h = 0.5 * v_tas * 1.0  # H reached at t = 0.5 s
    hist = g.gust_line_loads(
        r, chord, xb, time, gust_gradient_m=h, u_ds_eas=u_e, airspeed_tas=v_tas, altitude_m=alt,
        penetration_delay=False,
    )
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(r, axis=0), axis=1))])
    fz = hist.force_per_length[100, :, 2]
    total = np.sum(0.5 * (fz[1:] + fz[:-1]) * np.diff(s))
    rho0 = 101325.0 / (287.05287 * 288.15)  # 1.2250 kg/m^3
    v_e = v_tas * np.sqrt(float(density(alt)) / rho0)
    s_half = 12.0 * (2.8 + 1.4) / 2.0
    assert total == pytest.approx(0.5 * rho0 * v_e * u_e * 2 * np.pi * s_half, rel=1e-12)


def test_duhamel_columns_with_own_semichord_grids():
    t = np.linspace(0.0, 2.0, 301)
    s = t[:, None] * np.array([[20.0, 35.0, 50.0]])
    w = np.sin(3.0 * t)[:, None] * np.array([[1.0, -2.0, 0.5]])
    both = g.kussner_lagged_velocity(s, w)
    for j in range(3):
        np.testing.assert_allclose(both[:, j], g.kussner_lagged_velocity(s[:, j], w[:, j]), rtol=1e-14, atol=1e-14)


def test_gust_fuselage_stations_carry_no_lift_when_asked():
    r, chord, xb = _beam()
    time = np.linspace(0.0, 0.6, 121)
    kw = dict(gust_gradient_m=30.0, u_ds_eas=10.0, airspeed_tas=150.0, altitude_m=3000.0)
    hist = g.gust_line_loads(r, chord, xb, time, fuselage_half_width=2.0, fuselage_carries_lift=False, **kw)
    inside = r[:, 1] < 2.0
    assert np.all(hist.force_per_length[:, inside] == 0.0)
    assert np.all(hist.force_per_length[:, ~inside, 2].max(axis=0) > 0.0)


def test_gust_finite_wing_correction_scales_lift():
    r, chord, xb = _beam()
    time = np.linspace(0.0, 0.8, 161)
    kw = dict(gust_gradient_m=40.0, u_ds_eas=10.0, airspeed_tas=150.0, altitude_m=3000.0)
    base = g.gust_line_loads(r, chord, xb, time, **kw)
    ar6 = g.gust_line_loads(r, chord, xb, time, aspect_ratio=6.0, **kw)
    # Helmbold A = 6: 4.52866 / 2 pi
    np.testing.assert_allclose(ar6.force_per_length, base.force_per_length * 4.528664 / (2 * np.pi), rtol=1e-6)
