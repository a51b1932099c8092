"""Kelvin-Voigt strain-rate damping of Alg. 6 (t_kappa, t_gamma).

Checks against closed forms, independent of the damping code: with the same time constant t on
every strain the damping is stiffness-proportional (C = t K), so every mode of circular frequency
w has lambda^2 + t w^2 lambda + w^2 = 0, i.e. Re(lambda) = -t |lambda|^2 / 2 exactly; and a
BDF2 free-vibration decay reproduces zeta = w t / 2.
"""

import numpy as np
import openmdao.api as om
import pytest
import scipy.linalg as sla
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.beam.residual import StrainRateDamping, forcing_specs, jig_state
from wingmdao.beam.static import BeamModel, beam_forcing, beam_parameters, cached_beam_system, straight_beam
from wingmdao.components.beam import BeamDynamics
from wingmdao.timemarch.system import pack

L, EI, MU = 10.0, 2.0e6, 20.0


def _model(n, damping, GK=None):
    r0, th0 = straight_beam(n, L)
    params = beam_parameters(r0, th0, EI_cc=EI, GJ=1.5e6, EI_nn=9 * EI, EA=1e9, GK_c=GK, GK_n=GK,
                             mass_per_length=MU, inertia_per_length=np.diag([1e-3, 0.4, 1e-3]))
    return BeamModel(params, damping=damping)


def _eigenvalues(model, count=12):
    n = model.num_nodes
    x = jig_state(model.params).ravel()
    q = pack(forcing_specs(n), beam_forcing(n))
    A, B = (m.toarray() for m in model.system.jac_state(x, np.zeros_like(x), model.p, q))
    lam = sla.eigvals(A, -B)
    lam = lam[np.isfinite(lam) & (lam.imag > 0)]
    return lam[np.argsort(np.abs(lam))][:count]


def test_uniform_time_constant_is_stiffness_proportional():
    t = 2e-3
    lam = _eigenvalues(_model(21, StrainRateDamping((t, t, t), (t, t, t)), GK=5e8))
    assert np.all(lam.real < 0)
    np.testing.assert_allclose(-lam.real / np.abs(lam) ** 2, t / 2, rtol=1e-6)


def test_bending_damping_ratio_matches_kelvin_voigt():
    """Curvature damping only: the first bending mode (pure bending strain) gets zeta = w t / 2."""
    t = 3e-3
    lam = _eigenvalues(_model(21, StrainRateDamping(curvature=(t, t, t))))
    w1 = 1.8751 ** 2 * np.sqrt(EI / (MU * L ** 4))
    first = lam[np.argmin(np.abs(np.abs(lam) - w1))]
    assert abs(first) == pytest.approx(w1, rel=5e-3)
    zeta = -first.real / abs(first)
    assert zeta == pytest.approx(abs(first) * t / 2, rel=1e-3)


def test_undamped_system_is_unchanged():
    assert cached_beam_system(5, "surface", StrainRateDamping()) is cached_beam_system(5, "surface")
    lam = _eigenvalues(_model(11, None), count=6)
    assert np.max(np.abs(lam.real)) < 1e-6 * np.max(np.abs(lam))


def test_free_vibration_decay_bdf2():
    """Logarithmic decrement of the BDF2 tip response after a released static load."""
    n = 11
    zeta_target = 0.03
    w1 = 1.8751 ** 2 * np.sqrt(EI / (MU * L ** 4))
    damping = StrainRateDamping.from_damping_ratio(zeta_target, w1 / (2 * np.pi))
    model = _model(n, damping)
    period = 2 * np.pi / w1
    time = np.arange(0.0, 4 * period, period / 200)
    force = np.zeros((time.size, n, 3))
    force[0, -1, 2] = 100.0                       # static tip load at t = 0, released after
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("beam", BeamDynamics(num_nodes=n, time=time, system=model.system), promotes=["*"])
    prob.setup()
    for k, v in model.params.items():
        prob.set_val(k, v)
    prob.set_val("point_force", force)
    prob.run_model()
    z = prob.get_val("states")[:, -1, 2]
    peaks = [k for k in range(1, time.size - 1) if z[k] > z[k - 1] and z[k] >= z[k + 1] and z[k] > 0]
    assert len(peaks) >= 3
    delta = np.log(z[peaks[0]] / z[peaks[2]]) / 2
    zeta = delta / np.sqrt(4 * np.pi ** 2 + delta ** 2)
    assert zeta == pytest.approx(zeta_target, rel=0.05)


def test_check_partials_with_damping():
    n, nt = 4, 4
    rng = np.random.default_rng(3)
    damping = StrainRateDamping((1e-3, 2e-3, 3e-3), (4e-4, 5e-4, 6e-4))
    r0, th0 = straight_beam(n, 2.0)
    params = beam_parameters(r0, th0, EI_cc=5e4, GJ=4e4, EI_nn=2e5, EA=1e7, GK_c=1e7, GK_n=1e7,
                             mass_per_length=3.0, inertia_per_length=np.diag([0.01, 0.02, 0.01]))
    system = cached_beam_system(n, "surface", damping)
    t = np.linspace(0.0, 0.03, nt)
    pf = np.zeros((nt, n, 3))
    pf[:, -1] = np.outer(1.0 + 20 * t, [200.0, 50.0, 3000.0])
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("beam", BeamDynamics(num_nodes=n, time=t, system=system), promotes=["*"])
    prob.setup()
    for k, v in params.items():
        prob.set_val(k, v)
    prob.set_val("point_force", pf)
    prob.set_val("frame_angular_velocity", np.tile([0.1, -0.05, 0.02], (nt, 1)))
    prob.run_model()
    x = prob.get_val("states")
    prob.set_val("states", x + rng.normal(scale=1e-3, size=x.shape) * (1.0 + np.abs(x)))
    data = prob.check_partials(method="fd", form="central", step=1e-6, out_stream=None)
    assert_check_partials(data, atol=1e-5, rtol=1e-6)


@pytest.mark.parametrize("bad", [dict(curvature=(-1.0, 0, 0)), dict(strain=(0, np.nan, 0)), dict(strain=(1.0, 2.0))])
def test_bad_damping_raises(bad):
    with pytest.raises(ValueError, match="StrainRateDamping"):
        StrainRateDamping(**bad)
    with pytest.raises(ValueError, match="zeta"):
        StrainRateDamping.from_damping_ratio(1.5, 1.0)


def test_natural_frequencies_closed_form():
    from wingmdao.beam.modes import natural_frequencies

    model = _model(41, None)
    f = natural_frequencies(model.system, model.p, pack(forcing_specs(41), beam_forcing(41)), count=3)
    f1 = 1.8751 ** 2 * np.sqrt(EI / (MU * L ** 4)) / (2 * np.pi)
    assert f[0] == pytest.approx(f1, rel=5e-3)
    assert np.all(np.diff(f) >= 0)
