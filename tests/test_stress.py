"""Box stress recovery (Sec. 4.4.2): hand calculations, signs, constraints, partials."""

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.components.stress import BoxStress
from wingmdao.materials import ALUMINIUM

SY = ALUMINIUM.sigma_y
WALLS = ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")
# symmetric box w = 1 m, h = 0.5 m, all walls 10 mm: hand values
SYM = dict(width=1.0, height=0.5, **{k: 0.01 for k in WALLS})
IXX = (1.0 * 0.5**3 - 0.98 * 0.48**3) / 12  # 1.38498667e-3 m^4
IZZ = (0.5 * 1.0**3 - 0.48 * 0.98**3) / 12
AREA = 0.5 - 0.98 * 0.48  # 0.0296 m^2
AM = 0.99 * 0.49  # midline enclosed area


def run(force, moment, geom=SYM, families=None, nt=1):
    n = 1
    prob = om.Problem(reports=False)
    kw = {} if families is None else {"families": families}
    prob.model.add_subsystem("s", BoxStress(num_times=nt, num_stations=n, material=ALUMINIUM, **kw), promotes=["*"])
    prob.setup()
    for k, v in geom.items():
        prob.set_val(k, v)
    prob.set_val("F_csn", np.reshape(force, (nt, n, 3)))
    prob.set_val("M_csn", np.reshape(moment, (nt, n, 3)))
    prob.run_model()
    return {k: prob.get_val(k)[0, 0] for k in ("sigma_corner", "sigma_vm", "tau_cent")}, prob


def test_pure_vertical_bending():
    s, p = run([0, 0, 0], [2e5, 0, 0])  # M_c > 0: tip load up on a right wing
    hand = 2e5 * 0.25 / IXX  # 36.1 MPa
    assert s["sigma_corner"] == pytest.approx([hand, hand, -hand, -hand], rel=1e-12)  # upper in compression
    assert p.get_val("g_ss_compression")[0, 0, 2] == pytest.approx(hand / SY - 1, rel=1e-12)
    assert p.get_val("g_ss_tension")[0, 0, 0] == pytest.approx(hand / SY - 1, rel=1e-12)
    # mid-corner: midline n = +-0.245, no shear -> von Mises = |sigma|
    assert s["sigma_vm"] == pytest.approx([2e5 * 0.245 / IXX] * 8, rel=1e-9)
    assert s["tau_cent"] == pytest.approx([0, 0, 0, 0], abs=1e-6)


def test_pure_chordwise_bending():
    s, _ = run([0, 0, 0], [0, 0, 3e5])
    hand = 3e5 * 0.5 / IZZ
    assert s["sigma_corner"] == pytest.approx([-hand, hand, hand, -hand], rel=1e-12)  # rear (c > 0) in tension


def test_pure_axial():
    s, p = run([0, 4e5, 0], [0, 0, 0])
    assert s["sigma_corner"] == pytest.approx([4e5 / AREA] * 4, rel=1e-12)
    assert s["sigma_vm"] == pytest.approx([4e5 / AREA] * 8, rel=1e-9)
    assert p.get_val("g_vm")[0, 0] == pytest.approx(4e5 / AREA / SY - 1, rel=1e-9)


def test_axial_through_offset_centroid_is_uniform():
    geom = dict(width=0.8, height=0.3, t_upper_skin=0.02, t_lower_skin=0.006, t_front_spar=0.004, t_rear_spar=0.012)
    wi, hi = 0.8 - 0.016, 0.3 - 0.026
    ci, ni = 0.5 * (0.004 - 0.012), 0.5 * (0.006 - 0.02)
    area = 0.8 * 0.3 - wi * hi
    c0, n0 = -wi * hi * ci / area, -wi * hi * ni / area  # outer rectangle minus hole
    fs = 1e5
    s, _ = run([0, fs, 0], [-n0 * fs, 0, c0 * fs], geom)  # moment of F_s applied at the centroid
    assert s["sigma_corner"] == pytest.approx([fs / area] * 4, rel=1e-10)


def test_pure_torsion_bredt():
    geom = dict(width=1.0, height=0.5, t_upper_skin=0.01, t_lower_skin=0.005, t_front_spar=0.008,
                t_rear_spar=0.004)
    torque = 5e4
    s, _ = run([0, 0, 0], [0, torque, 0], geom)
    am = (1.0 - 0.006) * (0.5 - 0.0075)  # midline area by hand
    q = torque / (2 * am)
    assert s["tau_cent"] == pytest.approx([q / 0.01, q / 0.005, q / 0.008, q / 0.004], rel=1e-12)
    assert s["sigma_corner"] == pytest.approx([0] * 4, abs=1e-6)
    # corner order front-lower, rear-lower, rear-upper, front-upper; skin then spar
    walls = [0.005, 0.008, 0.005, 0.004, 0.01, 0.004, 0.01, 0.008]
    assert s["sigma_vm"] == pytest.approx([np.sqrt(3) * q / t for t in walls], rel=1e-9)


def test_pure_vertical_shear_vq_it():
    s, _ = run([0, 0, 1e5], [0, 0, 0])
    q_x = 1.0 * 0.01 * 0.245 + 2 * 0.01 * 0.24**2 / 2  # area above the neutral axis, by hand
    tau = 1e5 * q_x / (IXX * 0.02)
    assert s["tau_cent"] == pytest.approx([0, 0, tau, -tau], rel=1e-10, abs=1e-6)  # up in both spars


def test_pure_chordwise_shear_vq_it():
    s, _ = run([1e5, 0, 0], [0, 0, 0])
    q_z = 0.48 * 0.01 * 0.495 + 2 * 0.01 * 0.5**2 / 2
    tau = 1e5 * q_z / (IZZ * 0.02)
    assert s["tau_cent"] == pytest.approx([tau, -tau, 0, 0], rel=1e-10, abs=1e-6)  # aft in both skins


def test_von_mises_combination():
    s, _ = run([0, 0, 0], [1e5, 2e4, 0])
    sigma = 1e5 * 0.245 / IXX
    tau = 2e4 / (2 * AM * 0.01)
    assert s["sigma_vm"] == pytest.approx([np.sqrt(sigma**2 + 3 * tau**2)] * 8, rel=1e-9)


def test_unsymmetric_bending_by_strain_compatibility():
    geom = dict(width=0.5, height=0.3, t_upper_skin=0.03, t_lower_skin=0.01, t_front_spar=0.04, t_rear_spar=0.01)
    nx = nz = 1200
    c = (np.arange(nx) + 0.5) / nx * 0.5 - 0.25
    n = (np.arange(nz) + 0.5) / nz * 0.3 - 0.15
    cc, nn = np.meshgrid(c, n, indexing="ij")
    hole = (cc > -0.25 + 0.04) & (cc < 0.25 - 0.01) & (nn > -0.15 + 0.01) & (nn < 0.15 - 0.03)
    da = np.where(hole, 0.0, 0.5 * 0.3 / (nx * nz))
    basis = [np.ones_like(cc), -nn, cc]  # eps = eps0 - k_c n + k_n c about the box centre
    K = np.array([[np.sum(wt * b * da) for b in basis] for wt in basis])
    loads = np.array([2e4, 3e4, -1e4])  # [F_s, M_c, M_n] about the box centre
    eps = np.linalg.solve(K, loads)  # stresses (E eps) directly
    corners = [(-0.25, -0.15), (0.25, -0.15), (0.25, 0.15), (-0.25, 0.15)]
    ref = [eps[0] - eps[1] * nc + eps[2] * cc_ for cc_, nc in corners]
    s, _ = run([0, 2e4, 0], [3e4, 0, -1e4], geom)
    assert s["sigma_corner"] == pytest.approx(ref, rel=2e-3)


def test_families_option():
    _, p = run([0, 0, 0], [1e4, 0, 0], families=("vm", "cent_neg"))
    names = set(p.model.s._var_rel2meta)
    assert {"g_vm", "g_cent_neg"} <= names and "g_ss_tension" not in names
    assert p.get_val("g_vm").shape == (1, 1, 8) and p.get_val("g_cent_neg").shape == (1, 1, 4)
    with pytest.raises(ValueError, match="unknown stress constraint families.*'tresca'.*valid: vm, ss_tension"):
        run([0, 0, 0], [0, 0, 0], families=("vm", "tresca"))


def test_bad_inputs():
    with pytest.raises(ValueError, match=r"t_front_spar = 0.6 m.*allowed range \(0, 0.49\) m"):
        run([0, 0, 0], [0, 0, 0], dict(SYM, t_front_spar=0.6, t_rear_spar=0.51))
    with pytest.raises(ValueError, match=r"M_csn\[0, 0, 1\] = nan N\*m at time index 0, station 0"):
        run([0, 0, 0], [0, np.nan, 0])


def test_zero_load_derivatives_finite():
    _, p = run([0, 0, 0], [0, 0, 0])
    totals = p.compute_totals(of=["g_vm"], wrt=["M_csn", "t_upper_skin"], return_format="array")
    assert np.all(np.isfinite(totals))


@pytest.mark.parametrize("matrix_free", [False, True])
def test_check_partials_random_asymmetric(matrix_free):
    """Declared partials, and the matrix-free products long histories use (pointwise base)."""
    nt, n = 3, 4
    rng = np.random.default_rng(11)
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("s", BoxStress(num_times=nt, num_stations=n, material=ALUMINIUM, section_rotation=True,
                                            matrix_free=matrix_free), promotes=["*"])
    prob.setup()
    assert "combined" in prob.model.s._fjac.name()  # the CSE'd combined Jacobian is in use
    prob.set_val("width", rng.uniform(0.6, 1.2, n))
    prob.set_val("height", rng.uniform(0.2, 0.4, n))
    for k in WALLS:
        prob.set_val(k, rng.uniform(0.003, 0.02, n))
    prob.set_val("F_csn", rng.normal(0, 1e5, (nt, n, 3)))
    prob.set_val("M_csn", rng.normal(0, 1e5, (nt, n, 3)))
    th = rng.uniform(-0.4, 0.4, n)
    rot = np.array([[[np.cos(a), 0, -np.sin(a)], [0, 1, 0], [np.sin(a), 0, np.cos(a)]] for a in th])
    prob.set_val("section_to_csn", rot + rng.uniform(0.02, 0.05, (n, 3, 3)))
    prob.run_model()
    assert prob.model.s.matrix_free is matrix_free
    data = prob.check_partials(method="fd", form="central", step=1e-5, step_calc="rel", out_stream=None)
    assert_check_partials(data, atol=1e-6, rtol=1e-6)


def test_options_reduce_outputs_and_rotation_matches():
    rot90 = np.array([[0.0, 0, -1], [0, 1, 0], [1, 0, 0]])  # section c axis = csn n axis
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("s", BoxStress(num_times=1, num_stations=1, material=ALUMINIUM, families=("ss_tension",),
                                            output_stresses=False, section_rotation=True), promotes=["*"])
    prob.setup()
    for k, v in SYM.items():
        prob.set_val(k, v)
    assert "sigma_corner" not in prob.model.s._var_rel2meta
    prob.set_val("section_to_csn", rot90)
    prob.set_val("M_csn", [[[0.0, 0, 3e5]]])  # R^T M: M_c = +3e5 in the section axes
    prob.run_model()
    hand = 3e5 * 0.25 / IXX
    assert prob.get_val("g_ss_tension")[0, 0] == pytest.approx(np.array([hand, hand, -hand, -hand]) / SY - 1, rel=1e-12)
