"""The stiffened skins' running loads beyond the flange-centre shear (docs/panels.md, "Running
loads of the walls"): the shear flow at the skins' edges, the chordwise running load from the
spanwise change of the vertical shear, the biaxial skin-bay check, and the spanwise force
gradient, each against a closed form written out here."""

import math

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.components.load_gradient import InternalForceGradient, force_gradient
from wingmdao.materials import ALUMINIUM
from wingmdao.panels import buckling as bk
from wingmdao.panels.box_panels import (skin_panel_ratios, transverse_panel_critical_load,
                                       transverse_skin_critical_load)
from wingmdao.stress.box_stress import axial_stress, panel_running_loads, section_quantities

# a doubly symmetric box: outer 1.2 x 0.3 m, skins 3 mm, spars 5 mm, no stiffeners
W, H, TS, TW = 1.2, 0.3, 0.003, 0.005
WM, HM = W - TW, H - TS        # midline width and height
GEOMETRY = (W, H, TS, TS, TW, TW)


def _ixx_thin_wall():
    """Ixx of the midline box (thin walls): two skins t w_m at +-h_m/2 and two webs t h_m^3 / 12."""
    return 2 * TS * WM * (HM / 2) ** 2 + 2 * TW * HM**3 / 12


def _loads(force, gradient=None, moment=(0.0, 0.0, 0.0)):
    sec = section_quantities(GEOMETRY)
    return panel_running_loads(list(force), list(moment), *GEOMETRY, (TS, TS), sec, force_gradient=gradient)


def test_skin_edge_shear_of_vertical_shear_closed_form():
    """Vertical shear F_n alone on the symmetric box: the skins' flow is zero at mid-chord and
    +-F_n t (h_m/2)(w_m/2) / Ixx at the spars (front +, rear -, both skins); the front web's
    flow at mid-height (the existing flange-centre recovery) is the skin's edge flow plus the
    web's own first moment, F_n t_w (h_m/2)^2 / 2 / Ixx."""
    fn = 1.0e5
    r = _loads((0.0, 0.0, fn))
    ixx = _ixx_thin_wall()
    delta = fn * TS * (HM / 2) * (WM / 2) / ixx
    np.testing.assert_allclose(r["nxy_skin"], [delta, -delta, delta, -delta], rtol=0.02)
    web_mid = delta + fn * TW * (HM / 2) ** 2 / 2 / ixx
    assert r["nxy_web"][0] == pytest.approx(web_mid, rel=0.02)
    assert r["nxy_web"][1] == pytest.approx(-web_mid, rel=0.02)
    # torsion alone: the Bredt flow T / (2 A_m), the same at both edges
    torque = 2.0e4
    t_only = _loads((0.0, 0.0, 0.0), moment=(0.0, torque, 0.0))
    np.testing.assert_allclose(t_only["nxy_skin"], [torque / (2 * WM * HM)] * 4, rtol=1e-9)
    # the edge values combine both: the front spar's side adds, the rear's subtracts
    both = _loads((0.0, 0.0, fn), moment=(0.0, torque, 0.0))
    np.testing.assert_allclose(both["nxy_skin"], np.add(r["nxy_skin"], t_only["nxy_skin"]), rtol=1e-12)


def test_skin_transverse_load_closed_form_and_sign():
    """N_y at mid-chord = -(w_m^2 / 8) t (n_skin - n_ea) (dF_n/ds) / Ixx: an upward net load
    (dF_n/ds < 0) compresses the lower skin and stretches the upper one by the same amount."""
    p = -1.5e4     # N/m: the shear falls outboard
    r = _loads((0.0, 0.0, 5e4), gradient=(0.0, 0.0, p))
    expected = (WM**2 / 8) * TS * (HM / 2) * abs(p) / _ixx_thin_wall()
    assert r["ny_skin"][2] == pytest.approx(-expected, rel=0.02) and r["ny_skin"][3] == r["ny_skin"][2]
    assert r["ny_skin"][0] == pytest.approx(expected, rel=0.02) and r["ny_skin"][1] == r["ny_skin"][0]
    assert _loads((0.0, 0.0, 5e4))["ny_skin"] == [0.0, 0.0, 0.0, 0.0]


def test_transverse_load_matches_the_skin_equilibrium_of_a_cantilever():
    """Independent check of N_y by the skin's own in-plane equilibrium: a prismatic box
    cantilever under a uniform upward load p (F_n(s) = p (L - s)); N_s(c, s) of the lower skin
    from the beam's bending stress; then N_sc by integrating dN_sc/dc = -dN_s/ds from the
    mid-chord (zero there by symmetry) and N_c by integrating dN_c/dc = -dN_sc/ds from the spar
    (zero there), all by finite differences on a grid; N_c at mid-chord against the formula."""
    L, p = 10.0, 2.0e4
    sec = section_quantities(GEOMETRY)
    s0, ds = 6.0, 1e-2
    cs = np.linspace(-WM / 2, WM / 2, 2001)

    def n_s(s):   # lower skin axial running load: sigma t, M_c = p (L - s)^2 / 2
        m = [p * (L - s) ** 2 / 2, 0.0, 0.0]
        return _axial(cs, m, sec) * TS

    def n_sc(s):  # from mid-chord, where it vanishes
        dns = (n_s(s + ds) - n_s(s - ds)) / (2 * ds)
        q = np.concatenate([[0.0], np.cumsum(0.5 * (dns[1:] + dns[:-1]) * np.diff(cs))])
        return -(q - np.interp(0.0, cs, q))

    dnsc = (n_sc(s0 + ds) - n_sc(s0 - ds)) / (2 * ds)
    nc = -np.concatenate([[0.0], np.cumsum(0.5 * (dnsc[1:] + dnsc[:-1]) * np.diff(cs))])
    fe_like = float(np.interp(0.0, cs, nc))
    formula = _loads((0.0, 0.0, p * (L - s0)), gradient=(0.0, 0.0, -p))["ny_skin"][2]
    assert fe_like < 0 and formula == pytest.approx(fe_like, rel=0.02)


def _axial(c, moment, sec):
    return axial_stress(c, -(H - TS) / 2, [0.0, 0.0, 0.0], moment, sec)


def test_biaxial_interaction_square_plate_exact_and_conservative_long_plate():
    """Square isotropic plate under equal biaxial compression: exact N = 2 pi^2 D / b^2
    (Timoshenko & Gere Sec. 9.3, m = n = 1), where the straight-line interaction is exact
    (R = 1). A 0.15 x 0.62 m bay: R times the exact biaxial load factor (the minimum over
    half-waves (m, n) of the Navier condition) is >= 1 (conservative) and below 1.3 (1.28 at
    N_x / N_y = 1)."""
    t, nu, E = 0.002, ALUMINIUM.nu, ALUMINIUM.E
    D = E * t**3 / (12 * (1 - nu**2))
    b = 0.2
    n_uni = 4 * math.pi**2 * D / b**2
    n = -2 * math.pi**2 * D / b**2
    assert bk.biaxial_interaction_ratio(n, n, 0.0, n_uni, n_uni, 1e9) == pytest.approx(1.0, abs=1e-6)
    a, b = 0.62, 0.15          # bay: length along x, width across
    nx_cr = bk.plate_compression_ss(D, D, nu * D, (1 - nu) * D / 2, a, b)
    ny_cr = bk.plate_compression_ss(D, D, nu * D, (1 - nu) * D / 2, b, a)
    for nx, ny in ((-4e4, -5e3), (-1e4, -1e4), (-2e3, -8e3)):
        lam = min(math.pi**2 * D * ((m / a) ** 2 + (k / b) ** 2) ** 2 / (-nx * (m / a) ** 2 - ny * (k / b) ** 2)
                  for m in range(1, 30) for k in range(1, 5))
        r = bk.biaxial_interaction_ratio(nx, ny, 0.0, nx_cr, ny_cr, 1e9)
        assert 1.0 <= r * lam < 1.3
    # transverse tension is not credited; no transverse load is the uniaxial interaction
    assert bk.biaxial_interaction_ratio(-1e4, 5e3, 3e3, nx_cr, ny_cr, 2e4) == pytest.approx(
        bk.interaction_ratio(-1e4, 3e3, nx_cr, 2e4), rel=1e-9)


def test_biaxial_interaction_does_not_credit_spanwise_tension_against_chordwise_compression():
    """A 0.15 x 0.62 m bay (1.5 mm aluminium) under chordwise compression N_y with spanwise
    tension N_x (the lower skin near the tip at +2.5 g): the exact load factor is the minimum
    over half-waves (m, n) of the Navier condition N_x (m/a)^2 + N_y (n/b)^2 =
    pi^2 D ((m/a)^2 + (n/b)^2)^2 (Timoshenko & Gere Sec. 9.3). The tension raises the transverse
    mode (1, 1) by only N_x (b/a)^2, so the interaction must stay conservative (R times the
    exact factor >= 1), which the straight line extended into tension (R_c = -N_x / N_x,cr +
    N_y / N_y,cr) is not; without tension it is N_y / N_y,cr."""
    t, nu, E = 0.0015, ALUMINIUM.nu, ALUMINIUM.E
    D = E * t**3 / (12 * (1 - nu**2))
    a, b = 0.62, 0.15
    nx_cr = bk.plate_compression_ss(D, D, nu * D, (1 - nu) * D / 2, a, b)
    ny_cr = bk.plate_compression_ss(D, D, nu * D, (1 - nu) * D / 2, b, a)
    for nx, ny in ((1e4, -5e3), (2e4, -5e3), (3e4, -8e3)):
        lam = min(math.pi**2 * D * ((m / a) ** 2 + (k / b) ** 2) ** 2 / (-nx * (m / a) ** 2 - ny * (k / b) ** 2)
                  for m in range(1, 30) for k in range(1, 5)
                  if -nx * (m / a) ** 2 - ny * (k / b) ** 2 > 0)
        r = float(bk.biaxial_interaction_ratio(nx, ny, 0.0, nx_cr, ny_cr, 1e9))
        assert r * lam >= 1.0
        assert r == pytest.approx(-ny / ny_cr, rel=1e-6)
        straight_line = -nx / nx_cr - ny / ny_cr
        assert straight_line * lam < 0.9            # what crediting the tension would give: unconservative


def test_transverse_skin_critical_load_isotropic():
    """A bay b wide, a long, compressed across (on its long edges): k = (1 + (b/a)^2)^2 on
    pi^2 D / b^2 (Timoshenko & Gere Sec. 9.2 with the plate's length b in the load direction)."""
    t, b, a = 0.0015, 0.15, 0.62
    D = ALUMINIUM.E * t**3 / (12 * (1 - ALUMINIUM.nu**2))
    expected = (1 + (b / a) ** 2) ** 2 * math.pi**2 * D / b**2
    assert transverse_skin_critical_load(ALUMINIUM, t, b, a) == pytest.approx(expected, rel=1e-9)
    r0 = skin_panel_ratios(ALUMINIUM, t, 0.03, 0.002, b, a, -1e4, 5e3)
    r1 = skin_panel_ratios(ALUMINIUM, t, 0.03, 0.002, b, a, -1e4, 5e3, ny=-0.5 * expected)
    assert r1["skin_buckling"] > r0["skin_buckling"] and r1["panel_buckling"] > r0["panel_buckling"]
    assert r1["stiffener_column"] == r0["stiffener_column"]


def test_transverse_panel_critical_load_closed_form():
    """Stiffened panel compressed across its blades: the long orthotropic strip of width a (the
    rib pitch), 2 pi^2 / a^2 (sqrt(D_x D) + D12 + 2 D66), isotropic skin D12 + 2 D66 = D, with
    D_x = E I per width of the skin and blade about their common neutral axis, by hand. Without
    stiffener bending stiffness (D_x -> D) it is the bare strip, k = 4 on pi^2 D / a^2."""
    t, b, a, h, ts = 0.0016, 0.15, 0.62, 0.017, 0.001
    E, nu = ALUMINIUM.E, ALUMINIUM.nu
    D = E * t**3 / (12 * (1 - nu**2))
    area = t * b + h * ts
    z_blade = t / 2 + h / 2
    z_na = h * ts * z_blade / area
    ei = E * (b * t**3 / 12 + b * t * z_na**2 + ts * h**3 / 12 + h * ts * (z_blade - z_na) ** 2) / b
    expected = 2 * math.pi**2 / a**2 * (math.sqrt(ei * D) + D)
    assert transverse_panel_critical_load(ALUMINIUM, t, b, a, h, ts) == pytest.approx(expected, rel=1e-9)
    assert transverse_panel_critical_load(ALUMINIUM, t, b, a, h, ts) < transverse_skin_critical_load(ALUMINIUM, t, b, a)


def test_force_gradient_closed_form_and_partials():
    """A force linear in the arc length has its slope as gradient at every node (a beam with
    dihedral: arc length, not y); check_partials of the component."""
    n, nt = 6, 2
    s = np.array([0.0, 0.7, 1.5, 2.0, 3.1, 4.0])
    r = np.stack([np.zeros(n), s * math.cos(0.1), s * math.sin(0.1)], axis=1)
    slope = np.array([3.0, -2.0e3, -1.5e4])
    f = np.array([[1.0, 2.0, 3.0] + slope * si for si in s]) * np.ones((nt, 1, 1))
    np.testing.assert_allclose(force_gradient(f, r), np.broadcast_to(slope, (nt, n, 3)), rtol=1e-12, atol=1e-9)
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("g", InternalForceGradient(num_times=nt, num_nodes=n), promotes=["*"])
    prob.setup(force_alloc_complex=True)
    rng = np.random.default_rng(3)
    prob.set_val("F_csn", rng.normal(0, 1e4, (nt, n, 3)))
    prob.set_val("node_positions", r + rng.normal(0, 0.01, r.shape))
    prob.run_model()
    np.testing.assert_allclose(prob.get_val("dF_csn_ds"), force_gradient(prob.get_val("F_csn"),
                                                                         prob.get_val("node_positions")))
    assert_check_partials(prob.check_partials(method="cs", out_stream=None), atol=1e-8, rtol=1e-8)
    prob.set_val("node_positions", np.zeros((n, 3)))
    with pytest.raises(ValueError, match="coincide"):
        prob.run_model()
