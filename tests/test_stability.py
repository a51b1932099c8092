"""Linear stability (wingmdao.stability) on small systems with independent closed forms.

The 2-DOF typical section with quasi-steady aerodynamics (D. H. Hodges, G. A. Pierce,
"Introduction to Structural Dynamics and Aeroelasticity", 2nd ed., Cambridge, 2011, Ch. 5):
    m h'' + S theta'' + k_h h = -L,   S h'' + I theta'' + k_t theta = e L,
    L = q c a (theta + h'/V)   (h down, e: elastic axis aft of the aerodynamic centre).
The reference flutter speed is the zero of the largest real part of the roots of the
characteristic quartic det(M s^2 + C s + K) = 0 (numpy polynomial algebra), the divergence
speed q_D = k_t / (e c a).
"""

import casadi as ca
import numpy as np
import pytest
import scipy.optimize as sopt

from wingmdao.stability import critical_speeds, eigenmodes, mac_matrix, sweep
from wingmdao.stability.eigen import check_speeds
from wingmdao.timemarch.examples import spring_mass_damper_system
from wingmdao.timemarch.system import CasadiResidualSystem, VarSpec

SEC = dict(m=10.0, S=0.5, I=0.625, k_h=250.0, k_t=1440.0 * 0.625 / 10.0 * 1.0, c=1.0, e=0.1, a=2 * np.pi,
           rho=1.225)
SEC["k_t"] = SEC["I"] * 12.0**2     # torsion 12 rad/s, plunge 5 rad/s


def typical_section_system():
    x, xd = ca.SX.sym("x", 4), ca.SX.sym("xd", 4)
    p, q = ca.SX.sym("p", 1), ca.SX.sym("q", 0)
    V = p[0]
    s = SEC
    h, th, hd, thd = x[0], x[1], x[2], x[3]
    L = 0.5 * s["rho"] * V**2 * s["c"] * s["a"] * (th + hd / V)
    R = ca.vertcat(s["m"] * xd[2] + s["S"] * xd[3] + s["k_h"] * h + L,
                   s["S"] * xd[2] + s["I"] * xd[3] + s["k_t"] * th - s["e"] * L,
                   hd - xd[0], thd - xd[1])
    return CasadiResidualSystem(x, xd, p, q, R, param_specs=[VarSpec("airspeed", (), "m/s", "airspeed")],
                                forcing_specs=[], name="typical_section")


def quartic_roots(V):
    s = SEC
    qca = 0.5 * s["rho"] * V**2 * s["c"] * s["a"]
    # polynomial entries of M s^2 + C s + K (highest power first)
    p11 = [s["m"], qca / V, s["k_h"]]
    p12 = [s["S"], 0.0, qca]
    p21 = [s["S"], -s["e"] * qca / V, 0.0]
    p22 = [s["I"], 0.0, s["k_t"] - s["e"] * qca]
    return np.roots(np.polysub(np.polymul(p11, p22), np.polymul(p12, p21)))


def reference_flutter_speed():
    g = lambda V: np.max(quartic_roots(V).real)
    Vs = np.linspace(1.0, 60.0, 600)
    vals = np.array([g(V) for V in Vs])
    i = np.flatnonzero((vals[:-1] < 0) & (vals[1:] >= 0))[0]
    Vf = sopt.brentq(g, Vs[i], Vs[i + 1], xtol=1e-10)
    r = quartic_roots(Vf)
    return Vf, np.abs(r[np.argmax(r.real)].imag)


def params_at(V):
    return np.array([V]), np.zeros(0)


def test_typical_section_eigenvalues_match_quartic_roots():
    system = typical_section_system()
    for V in (5.0, 20.0):
        m = eigenmodes(system, *params_at(V), static=True)
        ref = quartic_roots(V)
        ref = ref[ref.imag >= 0]
        assert m.eigenvalues.size == ref.size
        for lam in ref:
            assert np.min(np.abs(m.eigenvalues - lam)) < 1e-8 * abs(lam)


def test_typical_section_flutter_and_divergence():
    system = typical_section_system()
    Vf_ref, wf_ref = reference_flutter_speed()
    s = SEC
    VD_ref = np.sqrt(2 * s["k_t"] / (s["e"] * s["c"] * s["a"] * s["rho"]))
    res = sweep(system, params_at, np.linspace(1.0, 1.2 * max(Vf_ref, VD_ref), 30), n_track=2)
    crit = critical_speeds(res, xtol=1e-7)
    assert crit["flutter_speed"] == pytest.approx(Vf_ref, rel=1e-5)
    assert crit["flutter_frequency"] == pytest.approx(wf_ref, rel=1e-4)
    assert crit["divergence_speed"] == pytest.approx(VD_ref, rel=1e-5)
    # damping is negative below flutter for both tracked modes
    below = res.speeds < Vf_ref
    assert np.all(res.damping[below] < 0)


def test_sparse_shift_invert_matches_dense():
    system = typical_section_system()
    d = eigenmodes(system, *params_at(10.0), method="dense")
    s = eigenmodes(system, *params_at(10.0), method="sparse", count=1, sigma=-0.5 + 4.0j)
    assert np.min(np.abs(d.eigenvalues - s.eigenvalues[0])) < 1e-8 * abs(s.eigenvalues[0])


def test_spring_mass_damper_eigenvalue_closed_form():
    system = spring_mass_damper_system()
    mass, c, k = 2.5, 0.2, 5.0
    m = eigenmodes(system, np.array([mass, c, k]), np.zeros(1))
    ref = -c / (2 * mass) + 1j * np.sqrt(k / mass - (c / (2 * mass)) ** 2)
    assert m.eigenvalues.size == 1
    assert m.eigenvalues[0] == pytest.approx(ref, rel=1e-12)
    assert m.structural_damping[0] == pytest.approx(2 * ref.real / ref.imag, rel=1e-12)
    with pytest.deprecated_call():
        assert m.damping_ratio[0] == m.structural_damping[0]


def test_mac_identity_and_orthogonal():
    V = np.eye(3)
    np.testing.assert_allclose(mac_matrix(V, V * (1 + 2j)), np.eye(3), atol=1e-15)


@pytest.mark.parametrize("bad, match", [([], "at least 2"), ([5.0], "at least 2"), ([-1.0, 2.0], ">= 0"),
                                        ([1.0, 3.0, 2.0], "strictly increasing"),
                                        ([1.0, np.nan], "finite")])
def test_bad_speeds(bad, match):
    with pytest.raises(ValueError, match=match):
        check_speeds(bad)


@pytest.mark.parametrize("factor", [0.97, 1.03])
def test_eigenvalue_matches_free_response_time_march(factor):
    """Just below / above flutter: the BDF2 free response started on the critical eigenvector
    decays / grows at the eigenvalue's rate and oscillates at its frequency (Prony fit of the
    sampled response: h[k+2] = 2 Re z h[k+1] - |z|^2 h[k], z = exp(lambda dt))."""
    from wingmdao.timemarch.bdf import march

    system = typical_section_system()
    Vf, _ = reference_flutter_speed()
    V = factor * Vf
    m = eigenmodes(system, *params_at(V))
    j = int(np.argmax(m.damping))
    lam, v = m.eigenvalues[j], m.vectors[:, j]
    dt = 2e-4
    t = np.arange(0.0, 4 * 2 * np.pi / abs(lam.imag), dt)
    x_init = 1e-3 * np.real(v) / np.max(np.abs(v))
    hist = march(system, t, np.array([V]), np.zeros((t.size, 0)), initial="state", x_init=x_init)
    h = hist.states[:, 1]
    A = np.column_stack([h[1:-1], h[:-2]])
    c1, c2 = np.linalg.lstsq(A, h[2:], rcond=None)[0]
    z = np.roots([1.0, -c1, -c2])
    lam_march = np.log(z[np.argmax(z.imag)]) / dt
    assert lam_march.imag == pytest.approx(lam.imag, rel=1e-3)
    assert lam_march.real == pytest.approx(lam.real, abs=2e-3 * abs(lam))
    assert np.sign(lam_march.real) == np.sign(lam.real) == (1 if factor > 1 else -1)


def test_det_sign_sparse_lu_matches_slogdet():
    import scipy.sparse as sp
    from wingmdao.stability.eigen import _det_sign

    rng = np.random.default_rng(0)
    for _ in range(5):
        M = rng.normal(size=(80, 80)) + 5 * np.eye(80)
        M[0] *= rng.choice([-1, 1])
        assert _det_sign(sp.csc_matrix(M)) == np.linalg.slogdet(M)[0]


def test_sparse_eigen_solve_is_reproducible():
    """ARPACK starts from a fixed vector: the same problem gives the same eigenpairs, bit for bit."""
    from wingmdao.stability import eigenmodes
    from wingmdao.stability.cases import flutter_problem

    prob = flutter_problem("goland", 6)
    p, q = prob.params_at(120.0)
    opts = {**prob.eig_options, "method": "sparse"}
    a, b = (eigenmodes(prob.system, p, q, **opts) for _ in range(2))
    assert np.array_equal(a.eigenvalues, b.eigenvalues) and np.array_equal(a.vectors, b.vectors)
