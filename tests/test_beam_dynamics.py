"""Beam time history: partials, first bending frequency, free fall back to the jig, adjoint of a KS."""

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

pytest.importorskip("wingmdao.beam.residual")

from wingmdao.components.beam import BeamDynamics, BeamStatic  # noqa: E402
from wingmdao.components.ks import KSAggregate  # noqa: E402

G = 9.81


def uniform_cantilever(n, length=10.0, EI=2.0e6, GJ=1.5e6, EA=1.0e9, GK=1.0e9, mu=20.0, i_rot=1e-4,
                       rng=None):
    """Inputs of a straight uniform cantilever along +y (body = csn at the jig)."""
    y = np.linspace(0.0, length, n)
    vals = {
        "node_positions": np.column_stack([np.zeros(n), y, np.zeros(n)]),
        "node_euler_angles": np.zeros((n, 3)),
        "stiffness_csn": np.tile(np.diag([EI, GJ, 5.0 * EI]), (n, 1, 1)),
        "compliance_csn": np.tile([1.0 / GK, 1.0 / EA, 1.0 / GK], (n, 1)),
        "tension_axis": np.zeros((n, 2)),
        "shear_center": np.zeros((n, 2)),
        "mass_per_length": np.full(n, mu),
        "mass_center": np.zeros((n, 2)),
        "inertia_per_length": np.tile(np.diag([i_rot, 2 * i_rot, i_rot]), (n, 1, 1)),
    }
    if rng is not None:  # asymmetric, non-trivial values for derivative checks
        vals["stiffness_csn"] = vals["stiffness_csn"] * rng.uniform(0.8, 1.2, (n, 1, 1))
        vals["stiffness_csn"][:, 0, 2] = vals["stiffness_csn"][:, 2, 0] = 0.1 * EI
        vals["mass_per_length"] = mu * rng.uniform(0.8, 1.2, n)
        vals["tension_axis"] = rng.uniform(-0.02, 0.02, (n, 2))
        vals["shear_center"] = rng.uniform(-0.02, 0.02, (n, 2))
        vals["mass_center"] = rng.uniform(-0.05, 0.05, (n, 2))
    return vals


def _problem(comp, values, mode="rev", extra=None):
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("beam", comp, promotes=["*"])
    if extra:
        extra(prob.model)
    prob.setup(mode=mode)
    for k, v in values.items():
        prob.set_val(k, v)
    return prob


def test_check_partials_small_beam():
    n, nt = 4, 5
    rng = np.random.default_rng(11)
    t = np.linspace(0.0, 0.04, nt)
    vals = uniform_cantilever(n, length=2.0, EI=5e4, GJ=4e4, EA=1e7, GK=1e7, mu=3.0, i_rot=0.01, rng=rng)
    pf = np.zeros((nt, n, 3))
    pf[:, -1] = np.outer(1.0 + 5 * t, [200.0, 50.0, 3000.0])
    vals.update(point_force=pf, gravity=np.tile([0.0, 0.0, -G], (nt, 1)),
                force_per_length=rng.normal(scale=100.0, size=(nt, n, 3)),
                frame_angular_velocity=np.tile([0.1, -0.05, 0.02], (nt, 1)))
    prob = _problem(BeamDynamics(num_nodes=n, time=t), vals)
    prob.run_model()
    x = prob.get_val("states")
    assert np.all(np.isfinite(x)) and np.max(np.abs(x[:, -1, 2])) > 1e-3
    prob.set_val("states", x + rng.normal(scale=1e-3, size=x.shape) * (1.0 + np.abs(x)))
    data = prob.check_partials(method="fd", form="central", step=1e-6, out_stream=None)
    assert_check_partials(data, atol=1e-5, rtol=1e-6)


def test_check_partials_beam_static():
    """BeamStatic (no time axis): every declared partial of the stacked static residual."""
    n = 5
    rng = np.random.default_rng(12)
    vals = uniform_cantilever(n, length=2.0, EI=5e4, GJ=4e4, EA=1e7, GK=1e7, mu=3.0, i_rot=0.01, rng=rng)
    pf = np.zeros((n, 3))
    pf[-1] = [300.0, 80.0, 4000.0]
    pm = np.zeros((n, 3))
    pm[-1] = [100.0, 500.0, -50.0]
    vals.update(point_force=pf, point_moment=pm, gravity=np.array([0.0, 0.0, -G]),
                force_per_length=rng.normal(scale=100.0, size=(n, 3)))
    prob = _problem(BeamStatic(num_nodes=n), vals)
    prob.run_model()
    x = prob.get_val("states")
    assert x.shape == (n, 18) and abs(x[-1, 2]) > 1e-2       # a visibly deflected state
    prob.set_val("states", x + rng.normal(scale=1e-3, size=x.shape) * (1.0 + np.abs(x)))
    data = prob.check_partials(method="fd", form="central", step=1e-6, out_stream=None)
    assert_check_partials(data, atol=1e-5, rtol=1e-6)


def _tip_release(n, n_time, dt, EI, mu, L):
    t = np.arange(n_time) * dt
    vals = uniform_cantilever(n, length=L, EI=EI, mu=mu)
    pf = np.zeros((n_time, n, 3))
    pf[0, -1, 2] = 1e-3 * 3 * EI / L**2  # small static tip load, released at t > 0
    vals["point_force"] = pf
    prob = _problem(BeamDynamics(num_nodes=n, time=t, modified_newton=True), vals)
    prob.run_model()
    return t, prob.get_val("states")


def _period(t, signal):
    s = signal - np.mean(signal[len(signal) // 4:])
    idx = np.flatnonzero((s[:-1] > 0) & (s[1:] <= 0))  # downward zero crossings
    tc = t[idx] - s[idx] * (t[idx + 1] - t[idx]) / (s[idx + 1] - s[idx])
    return np.mean(np.diff(tc))


def test_first_bending_frequency_of_uniform_cantilever():
    """Free vibration after release: f1 = 1.8751^2 sqrt(EI / (mu L^4)) / (2 pi) within 2 %."""
    EI, mu, L, n = 2.0e6, 20.0, 10.0, 21
    f1 = 1.8751**2 * np.sqrt(EI / (mu * L**4)) / (2 * np.pi)
    dt = 1.0 / f1 / 200
    t, x = _tip_release(n, 601, dt, EI, mu, L)
    tip_z = x[:, -1, 2]
    assert tip_z[0] == pytest.approx(1e-3 * L, rel=0.02)  # P L^3 / (3 EI) with P = 3e-3 EI / L^2
    f_sim = 1.0 / _period(t, tip_z)
    assert f_sim == pytest.approx(f1, rel=0.02)


def test_gravity_then_free_fall_returns_to_jig_shape():
    """App. E.2: from the jig, gravity on -> self-weight equilibrium; then free fall
    (gravity = frame acceleration = -g) -> back to the jig shape."""
    EI, mu, L, n = 2.0e6, 20.0, 10.0, 11
    f1 = 1.8751**2 * np.sqrt(EI / (mu * L**4)) / (2 * np.pi)
    dt = 1.0 / f1  # BDF2 with one step per period damps the vibration quickly
    nt, n_fall = 121, 60
    t = np.arange(nt) * dt
    vals = uniform_cantilever(n, length=L, EI=EI, mu=mu)
    vals["gravity"] = np.tile([0.0, 0.0, -G], (nt, 1))
    acc = np.zeros((nt, 3))
    acc[n_fall:, 2] = -G  # the frame falls with gravity from step 60
    vals["frame_acceleration"] = acc
    jig = np.zeros((n, 18))
    jig[:, 0:3] = vals["node_positions"]
    vals["initial_state"] = jig
    prob = _problem(BeamDynamics(num_nodes=n, time=t, initial="state"), vals)
    prob.run_model()
    x = prob.get_val("states")
    sag = mu * G * L**4 / (8 * EI)
    assert np.min(x[:n_fall, -1, 2]) < -1.03 * sag  # dynamic overshoot (damped by the large step)
    assert x[n_fall - 1, -1, 2] == pytest.approx(-sag, rel=0.01)  # settled at the self-weight sag
    np.testing.assert_allclose(x[-1, :, 0:3], vals["node_positions"], atol=1e-3 * sag)
    np.testing.assert_allclose(x[-1, :, 6:12], 0.0, atol=1e-3 * mu * G * L**2)


def test_beam_static_tip_load_matches_linear_theory():
    n, L, EI = 21, 10.0, 2.0e6  # 20 elements: discretisation error ~0.06 %
    vals = uniform_cantilever(n, length=L, EI=EI)
    pf = np.zeros((n, 3))
    pf[-1, 2] = 1e-4 * EI / L**2
    vals["point_force"] = pf
    prob = _problem(BeamStatic(num_nodes=n), vals)
    prob.run_model()
    x = prob.get_val("states")
    assert x.shape == (n, 18)
    assert x[-1, 2] == pytest.approx(pf[-1, 2] * L**3 / (3 * EI), rel=2e-3)
    np.testing.assert_allclose(x[0, 6:9], pf[-1], rtol=1e-6, atol=1e-9)  # root force = tip load


def _ks_problem(n, t, vals, mode):
    nt = t.size

    def extra(model):
        w = np.zeros((nt, n, 18))
        w[:, 0, 9:12] = 1.0 / 1e4  # root moments, normalised
        model.add_subsystem("pick", om.ExecComp("g = w * states", w={"val": w, "shape": w.shape},
                                                states={"shape": w.shape}, g={"shape": w.shape},
                                                has_diag_partials=True), promotes=["*"])
        model.add_subsystem("ks", KSAggregate(families={"root": (nt, n, 18)}, rho_ks=20.0))
        model.connect("g", "ks.g_root")

    return _problem(BeamDynamics(num_nodes=n, time=t), vals, mode=mode, extra=extra)


@pytest.mark.slow
def test_adjoint_of_ks_of_root_moments_wrt_section_stiffness():
    n, nt = 10, 200
    rng = np.random.default_rng(3)
    L = 10.0
    EI = 2.0e6
    t = np.linspace(0.0, 1.0, nt)
    vals = uniform_cantilever(n, length=L, EI=EI, rng=rng)
    pf = np.zeros((nt, n, 3))
    pf[:, -1, 2] = 2e3 * np.sin(2 * np.pi * 3 * t) ** 2
    pf[:, -1, 0] = 3e2 * t
    vals["point_force"] = pf
    vals["gravity"] = np.tile([0.0, 0.0, -G], (nt, 1))
    totals = {}
    for mode in ("fwd", "rev"):
        prob = _ks_problem(n, t, vals, mode)
        prob.run_model()
        totals[mode] = prob.compute_totals(of=["ks.ks_root"], wrt=["stiffness_csn"])["ks.ks_root", "stiffness_csn"]
    # fwd and rev agree to 1e-10 of the gradient's largest entry (round-off of the sweeps)
    assert np.max(np.abs(totals["fwd"] - totals["rev"])) <= 1e-10 * np.max(np.abs(totals["rev"]))
    grad = totals["rev"].reshape(n, 3, 3)
    prob = _ks_problem(n, t, vals, "rev")
    for (i, a, b) in [(1, 0, 0), (4, 0, 0), (8, 1, 1), (2, 2, 2), (3, 0, 2)]:
        h = 1e-5 * vals["stiffness_csn"][i, a, b]
        f = []
        for sign in (1, -1):
            k = vals["stiffness_csn"].copy()
            k[i, a, b] += sign * h
            prob.set_val("stiffness_csn", k)
            prob.run_model()
            f.append(prob.get_val("ks.ks_root")[0])
        fd = (f[0] - f[1]) / (2 * h)
        assert grad[i, a, b] == pytest.approx(fd, rel=1e-5, abs=1e-5 * np.max(np.abs(grad))), (i, a, b)
