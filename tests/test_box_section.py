"""Box section (App. F): geometry against independent closed forms and integrations."""

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.components.section import BoxSection
from wingmdao.materials import ALUMINIUM
from wingmdao.section.box import box_properties

E, G, RHO = ALUMINIUM.E, ALUMINIUM.G, ALUMINIUM.rho
WALLS = ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")
ASYM = dict(width=0.9, height=0.35, t_upper_skin=0.012, t_lower_skin=0.007, t_front_spar=0.004,
            t_rear_spar=0.015)


def run_box(n=1, rot=None, nsm=0.0, **geom):
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("box", BoxSection(num_stations=n, material=ALUMINIUM), promotes=["*"])
    prob.setup()
    for k, v in geom.items():
        prob.set_val(k, v)
    if rot is not None:
        prob.set_val("section_to_csn", rot)
    prob.set_val("nonstructural_mass_per_length", nsm)
    prob.run_model()
    return prob


def outer_minus_hole(width, height, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar):
    """Independent closed form: outer rectangle minus the inner hole, about the centroid."""
    wi, hi = width - t_front_spar - t_rear_spar, height - t_upper_skin - t_lower_skin
    ci, ni = 0.5 * (t_front_spar - t_rear_spar), 0.5 * (t_lower_skin - t_upper_skin)
    area = width * height - wi * hi
    c0, n0 = -wi * hi * ci / area, -wi * hi * ni / area
    ixx_o = width * height**3 / 12 - (wi * hi**3 / 12 + wi * hi * ni**2)
    izz_o = height * width**3 / 12 - (hi * wi**3 / 12 + wi * hi * ci**2)
    ixz_o = -wi * hi * ci * ni
    return dict(A=area, c_ea=c0, n_ea=n0, Ixx=ixx_o - area * n0**2, Izz=izz_o - area * c0**2,
                Ixz=ixz_o - area * c0 * n0)


def test_symmetric_box_hand_values():
    # w = 1, h = 0.5, all walls 10 mm: hollow-rectangle formulas worked by hand
    p = run_box(width=1.0, height=0.5, **{k: 0.01 for k in WALLS})
    assert p.get_val("A")[0] == pytest.approx(1.0 * 0.5 - 0.98 * 0.48, rel=1e-12)  # 0.0296 m^2
    assert p.get_val("Ixx")[0] == pytest.approx((1.0 * 0.5**3 - 0.98 * 0.48**3) / 12, rel=1e-12)
    assert p.get_val("Izz")[0] == pytest.approx((0.5 * 1.0**3 - 0.48 * 0.98**3) / 12, rel=1e-12)
    for k in ("Ixz", "c_ea", "n_ea", "c_sc", "n_sc", "c_cg", "n_cg"):
        assert abs(p.get_val(k)[0]) < 1e-14, k
    # Bredt by hand: b = 0.99, d = 0.49, J = 4 (b d)^2 / (2 b/t + 2 d/t)
    assert p.get_val("J")[0] == pytest.approx(4 * 0.4851**2 / 296.0, rel=1e-12)
    assert p.get_val("EA")[0] == pytest.approx(70e9 * 0.0296, rel=1e-12)
    # Qx: half the section above n = 0 about n = 0, by hand
    assert p.get_val("Qx")[0] == pytest.approx(1.0 * 0.01 * 0.245 + 2 * 0.01 * 0.24**2 / 2, rel=1e-12)
    assert p.get_val("Qz")[0] == pytest.approx(0.48 * 0.01 * 0.495 + 2 * 0.01 * 0.5**2 / 2, rel=1e-12)


def test_asymmetric_against_outer_minus_hole():
    p = run_box(**ASYM)
    ref = outer_minus_hole(**ASYM)
    for k, v in ref.items():
        assert p.get_val(k)[0] == pytest.approx(v, rel=1e-10, abs=1e-16), k
    assert p.get_val("c_cg")[0] == pytest.approx(ref["c_ea"], rel=1e-10)
    assert p.get_val("n_cg")[0] == pytest.approx(ref["n_ea"], rel=1e-10)
    assert abs(ref["Ixz"]) > 1e-6  # really unsymmetric


def test_asymmetric_spars_centroid_by_hand():
    # w = 1, h = 0.5, skins 10 mm, front spar 10 mm, rear spar 30 mm
    p = run_box(width=1.0, height=0.5, t_upper_skin=0.01, t_lower_skin=0.01, t_front_spar=0.01, t_rear_spar=0.03)
    a_skins, a_front, a_rear = 2 * 0.01, 0.01 * 0.48, 0.03 * 0.48
    c_ea = (a_front * -0.495 + a_rear * 0.485) / (a_skins + a_front + a_rear)  # = 0.1897... m
    assert p.get_val("c_ea")[0] == pytest.approx(c_ea, rel=1e-12)
    assert abs(p.get_val("n_ea")[0]) < 1e-14 and abs(p.get_val("Ixz")[0]) < 1e-14
    assert 0 < p.get_val("c_sc")[0] < 0.5  # towards the thicker rear spar


def test_thin_walled_limit():
    w, h = 1.2, 0.4
    errors = []
    for t in (1e-3, 1e-4):
        p = run_box(width=w, height=h, **{k: t for k in WALLS})
        thin_ixx = 2 * w * t * (h / 2) ** 2 + 2 * t * h**3 / 12
        thin_izz = 2 * h * t * (w / 2) ** 2 + 2 * t * w**3 / 12
        thin_j = 2 * t * w**2 * h**2 / (w + h)
        errors.append([abs(p.get_val("Ixx")[0] / thin_ixx - 1), abs(p.get_val("Izz")[0] / thin_izz - 1),
                       abs(p.get_val("J")[0] / thin_j - 1), abs(p.get_val("A")[0] / (2 * t * (w + h)) - 1)])
    errors = np.array(errors)
    assert np.all(errors[1] < 1e-3)
    assert np.all(errors[1] < 0.15 * errors[0] + 1e-12)  # first-order convergence in t


def test_j_hand_bredt_unequal_and_f29():
    # w = 0.8, h = 0.3, t_u = 8 mm, t_l = 4 mm, t_f = 6 mm, t_r = 2 mm
    geom = dict(width=0.8, height=0.3, t_upper_skin=0.008, t_lower_skin=0.004, t_front_spar=0.006,
                t_rear_spar=0.002)
    p = run_box(**geom)
    b, d = 0.8 - 0.004, 0.3 - 0.006  # 0.796, 0.294
    loop = b / 0.008 + b / 0.004 + d / 0.006 + d / 0.002  # 99.5 + 199 + 49 + 147 = 494.5
    assert loop == pytest.approx(494.5)
    assert p.get_val("J")[0] == pytest.approx(4 * (b * d) ** 2 / 494.5, rel=1e-12)
    f29 = 2 * (d * b) ** 2 / (b / 0.006 + d / 0.004)  # Eq. F.29 (arithmetic-mean pairs)
    assert f29 > p.get_val("J")[0]


def _numerical_shear_centre(geom, per_wall=4001):
    """Thin-walled shear flow by cumulative trapezoid integration of the classical
    unsymmetric-bending formula q_b = -(a int t c ds + b int t n ds), closed by zero twist."""
    w, h = geom["width"], geom["height"]
    tu, tl, tf, tr = (geom[k] for k in WALLS)
    cf, cr, nl, nu = -w / 2 + tf / 2, w / 2 - tr / 2, -h / 2 + tl / 2, h / 2 - tu / 2
    pts, ts = [], []
    for (c0, n0), (c1, n1), t in (((cf, nu), (cr, nu), tu), ((cr, nu), (cr, nl), tr),
                                  ((cr, nl), (cf, nl), tl), ((cf, nl), (cf, nu), tf)):
        s = np.linspace(0, 1, per_wall)[:-1]
        pts.append(np.column_stack([c0 + s * (c1 - c0), n0 + s * (n1 - n0)]))
        ts.append(np.full(s.size, t))
    pts, ts = np.vstack(pts + [pts[0][:1]]), np.concatenate(ts + [ts[0][:1]])
    ds = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    tm = ts[:-1]  # thickness of each small piece (constant per wall)
    mid = 0.5 * (pts[1:] + pts[:-1])
    area = np.sum(tm * ds)
    cm, nm = np.sum(tm * ds * mid[:, 0]) / area, np.sum(tm * ds * mid[:, 1]) / area
    x, y = mid[:, 0] - cm, mid[:, 1] - nm
    ixx, iyy, ixy = np.sum(tm * ds * y**2), np.sum(tm * ds * x**2), np.sum(tm * ds * x * y)
    det = ixx * iyy - ixy**2
    results = []
    for sx, sy in ((0.0, 1.0), (1.0, 0.0)):
        a = (sx * ixx - sy * ixy) / det
        b = (sy * iyy - sx * ixy) / det
        dq = -(a * tm * x + b * tm * y) * ds
        q_nodes = np.concatenate([[0.0], np.cumsum(dq)])
        q_piece = 0.5 * (q_nodes[1:] + q_nodes[:-1])
        q0 = -np.sum(q_piece * ds / tm) / np.sum(ds / tm)
        q = q_piece + q0
        tang = np.diff(pts, axis=0)
        force = np.sum(q[:, None] * tang, axis=0)
        moment = np.sum(q * (mid[:, 1] * tang[:, 0] - mid[:, 0] * tang[:, 1]))
        results.append((force, moment))
    (f_v, m_v), (f_c, m_c) = results
    return -m_v / f_v[1], m_c / f_c[0]


@pytest.mark.parametrize("geom", [
    dict(width=1.0, height=0.5, t_upper_skin=0.01, t_lower_skin=0.01, t_front_spar=0.01, t_rear_spar=0.03),
    ASYM,
    dict(width=0.6, height=0.4, t_upper_skin=0.003, t_lower_skin=0.02, t_front_spar=0.012, t_rear_spar=0.005),
])
def test_shear_centre_against_numerical_shear_flow(geom):
    p = run_box(**geom)
    c_ref, n_ref = _numerical_shear_centre(geom)
    assert p.get_val("c_sc")[0] == pytest.approx(c_ref, rel=1e-5, abs=1e-7)
    assert p.get_val("n_sc")[0] == pytest.approx(n_ref, rel=1e-5, abs=1e-7)


def test_shear_centre_moves_towards_thicker_spar():
    base = dict(width=1.0, height=0.4, t_upper_skin=0.01, t_lower_skin=0.01)
    front = run_box(**base, t_front_spar=0.02, t_rear_spar=0.005).get_val("c_sc")[0]
    rear = run_box(**base, t_front_spar=0.005, t_rear_spar=0.02).get_val("c_sc")[0]
    assert front < 0 < rear and front == pytest.approx(-rear, rel=1e-12)


def _grid_integrals(geom, nx=1200, nz=1200):
    """Midpoint-rule integrals over the box walls (pixel grid) about the box centre."""
    w, h = geom["width"], geom["height"]
    c = (np.arange(nx) + 0.5) / nx * w - w / 2
    n = (np.arange(nz) + 0.5) / nz * h - h / 2
    cc, nn = np.meshgrid(c, n, indexing="ij")
    hole = ((cc > -w / 2 + geom["t_front_spar"]) & (cc < w / 2 - geom["t_rear_spar"])
            & (nn > -h / 2 + geom["t_lower_skin"]) & (nn < h / 2 - geom["t_upper_skin"]))
    da = np.where(hole, 0.0, w * h / (nx * nz))
    return cc, nn, da


def test_stiffness_sign_by_strain_compatibility():
    """Pure M_c on an unsymmetric box: solve eps = eps0 + k_n c - k_c n from N = 0, M_c = 1 kN m,
    M_n = 0 by direct integration; the tilt k_n / k_c must match E^{-1} M of stiffness_csn."""
    geom = dict(width=0.5, height=0.3, t_upper_skin=0.03, t_lower_skin=0.01, t_front_spar=0.04,
                t_rear_spar=0.01)
    cc, nn, da = _grid_integrals(geom)
    # rows: N, M_c = -int n sigma, M_n = int c sigma; columns: eps0, k_c, k_n
    basis = [np.ones_like(cc), -nn, cc]
    weights = [np.ones_like(cc), -nn, cc]
    K = np.array([[E * np.sum(wt * b * da) for b in basis] for wt in weights])
    eps0, k_c, k_n = np.linalg.solve(K, [0.0, 1e3, 0.0])
    p = run_box(**geom)
    stiff = p.get_val("stiffness_csn")[0]
    k_model = np.linalg.solve(stiff[np.ix_([0, 2], [0, 2])], [1e3, 0.0])
    assert k_n / k_c == pytest.approx(k_model[1] / k_model[0], rel=2e-3)
    assert k_c == pytest.approx(k_model[0], rel=2e-3)
    assert abs(k_model[1] / k_model[0]) > 0.05  # a real tilt (sign checked above)
    assert stiff[0, 1] == stiff[1, 2] == 0.0
    assert stiff[1, 1] == pytest.approx(G * p.get_val("J")[0])


def test_section_to_csn_rotation_and_beam_data():
    theta = np.radians(90.0)
    rot = np.array([[np.cos(theta), 0, -np.sin(theta)], [0, 1, 0], [np.sin(theta), 0, np.cos(theta)]])
    p0 = run_box(**ASYM)
    p1 = run_box(rot=rot, nsm=3.5, **ASYM)
    e0, e1 = p0.get_val("stiffness_csn")[0], p1.get_val("stiffness_csn")[0]
    # a quarter turn about s swaps the bending stiffnesses and flips the coupling sign
    assert e1[0, 0] == pytest.approx(e0[2, 2]) and e1[2, 2] == pytest.approx(e0[0, 0])
    assert e1[0, 2] == pytest.approx(-e0[0, 2])
    assert p1.get_val("c_ea")[0] == pytest.approx(-p0.get_val("n_ea")[0])
    ref = outer_minus_hole(**ASYM)
    assert p1.get_val("mass_per_length")[0] == pytest.approx(RHO * ref["A"] + 3.5, rel=1e-12)
    inertia = p0.get_val("inertia_per_length")[0]
    assert inertia[1, 1] == pytest.approx(RHO * (ref["Ixx"] + ref["Izz"]), rel=1e-10)
    assert inertia[0, 2] == pytest.approx(-RHO * ref["Ixz"], rel=1e-10)
    comp = p0.get_val("compliance_csn")[0]
    w, h = ASYM["width"], ASYM["height"]
    k_c = w * (ASYM["t_upper_skin"] + ASYM["t_lower_skin"])
    k_n = (h - ASYM["t_upper_skin"] - ASYM["t_lower_skin"]) * (ASYM["t_front_spar"] + ASYM["t_rear_spar"])
    assert comp == pytest.approx([1 / (G * k_c), 1 / (E * ref["A"]), 1 / (G * k_n)], rel=1e-12)


def test_numpy_path_matches_component():
    p = run_box(**ASYM)
    props = box_properties(*(ASYM[k] for k in ("width", "height") + WALLS), ALUMINIUM)
    for k in ("A", "J", "c_sc", "n_sc", "Qx", "Qz"):
        assert p.get_val(k)[0] == pytest.approx(props[k], rel=1e-12), k


def test_check_partials_random_asymmetric():
    rng = np.random.default_rng(42)
    n = 4
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("box", BoxSection(num_stations=n, material=ALUMINIUM), promotes=["*"])
    prob.setup()
    prob.set_val("width", rng.uniform(0.6, 1.4, n))
    prob.set_val("height", rng.uniform(0.2, 0.45, n))
    for k in WALLS:
        prob.set_val(k, rng.uniform(0.002, 0.03, n))
    th = rng.uniform(-0.4, 0.4, n)
    rot = np.array([[[np.cos(a), 0, -np.sin(a)], [0, 1, 0], [np.sin(a), 0, np.cos(a)]] for a in th])
    prob.set_val("section_to_csn", rot + rng.normal(0, 0.05, (n, 3, 3)))
    prob.set_val("nonstructural_mass_per_length", rng.uniform(0, 10, n))
    prob.run_model()
    data = prob.check_partials(method="fd", form="central", step=1e-7, step_calc="rel", out_stream=None)
    assert_check_partials(data, atol=1e-6, rtol=1e-6)


@pytest.mark.parametrize("name,value,match", [
    ("width", np.array([1.0, -0.2, 1.0]), r"width = -0.2 m at station 1; allowed range \(0, inf\) m"),
    ("height", np.array([0.3, 0.3, np.nan]), r"height = nan m at station 2; allowed range \(0, inf\) m"),
    ("t_rear_spar", np.array([0.0, 0.01, 0.01]), r"t_rear_spar = 0 m at station 0"),
    ("t_upper_skin", np.array([0.01, 0.295, 0.01]),
     r"t_upper_skin = 0.295 m at station 1: t_upper_skin \+ t_lower_skin must be less than height = 0.3 m; "
     r"allowed range \(0, 0.29\) m"),
    ("t_front_spar", np.array([0.01, 0.01, 1.0]), r"t_front_spar = 1 m at station 2.*allowed range \(0, 0.99\) m"),
])
def test_bad_input(name, value, match):
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("box", BoxSection(num_stations=3, material=ALUMINIUM), promotes=["*"])
    prob.setup()
    prob.set_val("width", 1.0)
    prob.set_val("height", 0.3)
    for k in WALLS:
        prob.set_val(k, 0.01)
    prob.set_val(name, value)
    with pytest.raises(ValueError, match=match):
        prob.run_model()


def test_shear_centre_closed_form_equal_skins():
    """Equal skins t_s, spars t_f != t_r: closed form from a hand (symbolic) integration of the
    thin-walled flow, measured from the midline-rectangle centre (docs/section.md)."""
    w, h, ts, tf, tr = 1.1, 0.42, 0.006, 0.018, 0.005
    b, d = w - (tf + tr) / 2, h - ts
    c_mid = b * d * (tr - tf) * (2 * b * tf * tr + 12 * b * ts**2 + d * ts * (tf + tr)) / (
        2 * (6 * b * ts + d * (tf + tr)) * (2 * b * tf * tr + d * ts * (tf + tr)))
    p = run_box(width=w, height=h, t_upper_skin=ts, t_lower_skin=ts, t_front_spar=tf, t_rear_spar=tr)
    assert p.get_val("c_sc")[0] == pytest.approx(c_mid + (tf - tr) / 4, rel=1e-12)
    assert abs(p.get_val("n_sc")[0]) < 1e-15
