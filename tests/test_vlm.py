"""The vortex-lattice method of wingmdao.aero.vlm against independent results.

References:
* W. Kinner, "Die kreisfoermige Tragflaeche auf potentialtheoretischer Grundlage",
  Ingenieur-Archiv 8 (1937) 47-80; P. F. Jordan, "Exact solutions for lifting surfaces",
  AIAA Journal 11(8) (1973) 1123-1129: the lift-curve slope of the flat circular wing
  (aspect ratio 4/pi) from the exact lifting-surface solution, CL_alpha = 1.790 /rad.
* The Helmbold / DATCOM lift-curve slope (D. E. Hoak et al., "USAF Stability and Control
  DATCOM", 1978, Sec. 4.1.3.2, Eq. 4.1.3.2-a, kappa = 1):
  a = 2 pi A / (2 + sqrt(A^2 beta^2 (1 + tan^2 Lambda_c/2 / beta^2) + 4)); coded below.
* Prandtl's lifting line (L. Prandtl, "Tragfluegeltheorie", 1918; solved by
  wingmdao.aero.lifting_line with Glauert's series, a separate solver), the limit of
  lifting-surface theory at large aspect ratio.
* Weissinger's lifting line (wingmdao.aero.weissinger; NACA TM 1120, 1947), the one-chordwise-panel
  lattice with its own geometry and spacing.
* The elliptic planform's spanload is elliptic (lifting-line theory: Glauert, "The elements of
  aerofoil and airscrew theory", 1926, Ch. XI); for the flat lifting surface this holds away
  from the tip (the exact solutions depart near the tip, Jordan 1973).
"""

import numpy as np
import pytest

from wingmdao.aero.lifting_line import lifting_line_lift_slope
from wingmdao.aero.vlm import build_lattice, flat_wing, solve_circulation, station_influence
from wingmdao.aero.weissinger import weissinger_lift_slope


def helmbold(aspect, sweep_half_chord=0.0, mach=0.0):
    """DATCOM Eq. 4.1.3.2-a with kappa = 1 (per rad, compressible)."""
    beta2 = 1.0 - mach ** 2
    return 2 * np.pi * aspect / (2 + np.sqrt(aspect ** 2 * (beta2 + np.tan(sweep_half_chord) ** 2) + 4))


def elliptic(aspect, n=21, semi_span=1.0):
    c0 = 8 * semi_span / (np.pi * aspect)
    r, c, ref = flat_wing(semi_span, lambda y: c0 * np.sqrt(np.clip(1 - (y / semi_span) ** 2, 0, None)) + 1e-6,
                          n_stations=n)
    return r, c, ref, np.pi * semi_span * c0 / 2


def rectangular(aspect, n=21, sweep=0.0):
    s = aspect / 2
    r, c, ref = flat_wing(s, lambda y: np.ones_like(y), n_stations=n, sweep_quarter_deg=sweep)
    return r, c, ref, 2 * s


def slope(r, c, ref, area, **kw):
    return station_influence(r, c, ref, **kw).lift_slope(area)


def test_circular_wing_matches_kinners_exact_lift_slope():
    r, c, ref, area = elliptic(4 / np.pi, n=41)
    assert slope(r, c, ref, area) == pytest.approx(1.790, rel=0.01)


@pytest.mark.parametrize("aspect", [3.0, 6.0, 10.0])
def test_elliptic_wing_lift_slope_near_helmbold(aspect):
    # DATCOM states the formula for kappa = 1 is within a few percent of lifting-surface theory;
    # the exact circular wing (above) is 2.2 % below it, the vortex lattice converges 2-4 % below
    r, c, ref, area = elliptic(aspect)
    a = slope(r, c, ref, area)
    assert a == pytest.approx(helmbold(aspect), rel=0.04)
    assert a < helmbold(aspect)


def test_high_aspect_ratio_rectangular_wing_tends_to_the_lifting_line():
    for aspect, tol in ((20.0, 0.025), (40.0, 0.012)):
        r, c, ref, area = rectangular(aspect, n=31)
        _, a_ll = lifting_line_lift_slope([0.0], lambda y: np.ones_like(y), aspect / 2)
        assert slope(r, c, ref, area) == pytest.approx(a_ll, rel=tol)


@pytest.mark.parametrize("sweep", [30.0, 45.0])
def test_swept_wing_sweep_factor_matches_datcom(sweep):
    # rectangular A = 5 (the swept-wing example of Bertin & Cummings, "Aerodynamics for Engineers",
    # Sec. 7.4): the ratio swept / unswept against DATCOM's (the planform's edge effects cancel)
    r, c, ref, area = rectangular(5.0, sweep=sweep)
    r0, c0, ref0, _ = rectangular(5.0)
    ratio = slope(r, c, ref, area) / slope(r0, c0, ref0, area)
    assert ratio == pytest.approx(helmbold(5.0, np.radians(sweep)) / helmbold(5.0), rel=0.02)


def test_elliptic_spanload_is_elliptic_away_from_the_tip():
    r, c, ref, _ = elliptic(6.0, n=31)
    lat = build_lattice(r, c, ref)
    g = solve_circulation(lat, np.ones(lat.span.size))
    gamma = np.bincount(lat.strip, g)
    eta = lat.strip_y / r[-1, 1]
    shape = gamma / np.sqrt(1 - eta ** 2)
    assert np.ptp(shape[eta < 0.5]) / shape[0] < 0.01
    assert np.ptp(shape[eta < 0.7]) / shape[0] < 0.025


@pytest.mark.parametrize("mach", [0.5, 0.8])
def test_prandtl_glauert_scaling(mach):
    beta = np.sqrt(1 - mach ** 2)
    r, c, ref, area = rectangular(6.0, sweep=30.0)
    a_m = slope(r, c, ref, area, mach=mach)
    # Goethert: the compressible wing = the incompressible wing stretched by 1/beta in x, lift / beta
    rs, cs = r * np.array([1 / beta, 1, 1]), c / beta
    a_stretched = slope(rs, cs, ref, area / beta) / beta  # CL on the stretched area, back to S
    assert a_m == pytest.approx(a_stretched, rel=1e-9)
    # and against DATCOM's compressibility dependence (ratio to incompressible)
    lam_half = np.arctan(np.tan(np.radians(30.0)))  # constant chord: every chord line has the same sweep
    assert a_m / slope(r, c, ref, area) == pytest.approx(helmbold(6.0, lam_half, mach) / helmbold(6.0, lam_half),
                                                          rel=0.02)


def test_agrees_with_weissinger_on_a_swept_tapered_wing():
    s, c_root, taper, sweep_le = 10.0, 3.0, 0.4, np.radians(28.0)

    def chord(y):
        return c_root * (1 - (1 - taper) * np.asarray(y) / s)

    def x_le(y):
        return np.asarray(y) * np.tan(sweep_le)

    _, a_w, res = weissinger_lift_slope([0.0], chord, x_le, s, mach=0.5, n_panels=80)
    y = s * np.sin(0.5 * np.pi * np.arange(21) / 20)
    r = np.stack([x_le(y) + 0.4 * chord(y), y, 0 * y], axis=-1)
    area = 2 * np.sum(0.5 * (chord(y)[1:] + chord(y)[:-1]) * np.diff(y))
    one_panel = station_influence(r, chord(y), 0.4, mach=0.5, n_chordwise=1, n_spanwise=4)
    four = station_influence(r, chord(y), 0.4, mach=0.5)
    assert one_panel.lift_slope(area) == pytest.approx(a_w, rel=0.005)
    assert four.lift_slope(area) == pytest.approx(a_w, rel=0.02)


def test_strip_limit_and_moment_of_a_very_long_wing():
    # a wing of aspect ratio 200: at mid-span the row sums give the 2-D slope 2 pi / beta on the
    # quarter chord (thin-airfoil theory), no moment about it
    r, c, ref, _ = rectangular(200.0, n=41)
    inf = station_influence(r, c, ref, mach=0.6)
    mid = np.argmin(np.abs(r[:, 1] - 50.0))
    assert inf.lift[mid].sum() == pytest.approx(2 * np.pi / 0.8, rel=0.02)
    assert abs(inf.moment[mid].sum()) < 1e-3 * inf.lift[mid].sum()


def test_influence_is_cached_by_planform():
    r, c, ref, _ = rectangular(6.0)
    assert station_influence(r, c, ref) is station_influence(r.copy(), c.copy(), ref.copy())
    assert station_influence(r, c, ref) is not station_influence(r, 1.1 * c, ref)


@pytest.mark.parametrize("change, match", [
    (lambda r, c: (r, np.where(np.arange(c.size) == 3, 0.0, c), 0.0), "chord must be > 0 m"),
    (lambda r, c: (r, c, 1.0), r"mach must be in \[0, 1\)"),
    (lambda r, c: (r, c, 1.2), r"mach must be in \[0, 1\)"),
    (lambda r, c: (r[[0, 1, 2, 4, 3, 5, 6, 7, 8, 9, 10]], c, 0.0), "y must increase from root to tip"),
    (lambda r, c: (np.vstack([r[:1], r[:1], r[2:]]), c, 0.0), "y must increase from root to tip"),
    (lambda r, c: (r - np.array([0, 1.0, 0]), c, 0.0), "must lie at y >= 0"),
])
def test_bad_planform_is_refused(change, match):
    r, c, ref, _ = rectangular(6.0, n=11)
    r2, c2, mach = change(r, c)
    with pytest.raises(ValueError, match=match):
        station_influence(r2, c2, ref, mach=mach)
