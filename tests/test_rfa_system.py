"""The modal wing with Roger's lag states as a residual system (wingmdao.aero.rfa_system), marched by
BDF2: its harmonic gust response against the frequency-domain doublet lattice, its linearization
against the state-space flutter matrix, and its adjoint derivatives against central differences."""

import numpy as np
import pytest

from wingmdao.aero.rfa import fit
from wingmdao.aero.rfa_system import modal_rfa_system
from wingmdao.stability.cases import flutter_problem
from wingmdao.stability.modal import case_forces, jig_modes
from wingmdao.stability.pk import ModalStructure, state_matrix
from wingmdao.timemarch.adjoint import LinearizedHistory
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import pack

pytest.importorskip("panelaero.DLM")

K_SET = np.array([0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0, 1.5])
RHO = 1.225


@pytest.fixture(scope="module")
def goland_rfa():
    problem = flutter_problem("goland", num_nodes=11)
    modes = jig_modes(problem, 4)
    gaf = case_forces(problem, modes, 0.0, reduced_frequencies=K_SET)
    structure = ModalStructure.from_modes(modes)
    rfa = fit(gaf)
    return structure, gaf, rfa, modal_rfa_system(structure, rfa)


def _harmonic_gust(system, t, omega, amplitude=1.0):
    F = np.zeros((t.size, system.n_forcing))
    F[:, 0] = amplitude * np.sin(omega * t)
    F[:, 1] = amplitude * omega * np.cos(omega * t)
    F[:, 2] = -amplitude * omega ** 2 * np.sin(omega * t)
    return F


def test_harmonic_gust_response_equals_frequency_domain_dlm(goland_rfa):
    """A sinusoidal gust at k = 0.3, 120 m/s (below flutter), marched 3 s by BDF2 (100 steps per
    period): the settled modal amplitudes equal the frequency-domain solution with the exact
    doublet-lattice matrices, [-omega^2 M + i omega C + K - q Q(ik)] q = q Q_g(ik) w_g / V, within
    2 % (the Roger fit's share, 1 %, plus BDF2's), and the frequency response of the approximation
    itself within 0.5 % (BDF2's share)."""
    structure, gaf, rfa, system = goland_rfa
    V, k = 120.0, 0.3
    omega = k * V / gaf.b_ref
    t = np.linspace(0.0, 3.0, int(round(3.0 * omega / (2 * np.pi) * 100)) + 1)
    p = pack(system.param_specs, {"airspeed": V, "density": RHO})
    X = march(system, t, p, _harmonic_gust(system, t, omega), initial="static").states
    n = structure.mass.shape[0]
    last = t > t[-1] - 2 * 2 * np.pi / omega
    coef, *_ = np.linalg.lstsq(np.column_stack([np.sin(omega * t[last]), np.cos(omega * t[last])]),
                               X[last, :n], rcond=None)
    q_time = coef[0] + 1j * coef[1]                       # w_g = Im(e^(i omega t)) -> q = Im(q_hat e^(i omega t))
    qd = 0.5 * RHO * V ** 2

    def response(Q, G):
        Z = -omega ** 2 * structure.mass + 1j * omega * structure.damping + structure.stiffness - qd * Q
        return np.linalg.solve(Z, qd * G / V)

    exact = response(*gaf.at(k))
    approx = response(*rfa(k))
    assert np.linalg.norm(q_time - exact) / np.linalg.norm(exact) < 0.02
    assert np.linalg.norm(q_time - approx) / np.linalg.norm(approx) < 0.005


def test_linearization_is_the_state_space_flutter_matrix(goland_rfa):
    structure, _, rfa, system = goland_rfa
    V = 150.0
    p = pack(system.param_specs, {"airspeed": V, "density": RHO})
    x = np.zeros(system.n_state)
    A, B = (m.toarray() for m in system.jac_state(x, x, p, np.zeros(system.n_forcing)))
    m = state_matrix(structure, rfa, RHO, V).shape[0]
    S = -np.linalg.solve(B, A)
    np.testing.assert_allclose(S[:m, :m], state_matrix(structure, rfa, RHO, V), rtol=1e-10,
                               atol=1e-10 * np.abs(S[:m, :m]).max())


def test_adjoint_derivatives_against_central_differences(goland_rfa):
    """f = int q_1^2 dt over a 1-cos gust (gradient 10 m, 5 m/s): df/dV and df/drho by the
    marcher's discrete adjoint against central differences of the march."""
    _, _, _, system = goland_rfa
    t = np.linspace(0.0, 0.4, 161)
    V = 120.0
    tg = 2 * 10.0 / V
    on = t <= tg
    F = np.zeros((t.size, system.n_forcing))
    F[on, 0] = 2.5 * (1 - np.cos(2 * np.pi * t[on] / tg))
    F[on, 1] = 2.5 * 2 * np.pi / tg * np.sin(2 * np.pi * t[on] / tg)
    F[on, 2] = 2.5 * (2 * np.pi / tg) ** 2 * np.cos(2 * np.pi * t[on] / tg)
    dt = t[1] - t[0]

    def f_of(p):
        X = march(system, t, p, F, initial="static").states
        return dt * np.sum(X[:, 0] ** 2), X

    p = pack(system.param_specs, {"airspeed": V, "density": RHO})
    f0, X = f_of(p)
    dfdx = np.zeros_like(X)
    dfdx[:, 0] = 2.0 * dt * X[:, 0]
    dfdp, _, _ = LinearizedHistory(system, t, X, p, F, initial="static").gradient(dfdx)
    for i, h in enumerate((1e-3, 1e-6)):
        e = np.zeros(2)
        e[i] = h
        fd = (f_of(p + e)[0] - f_of(p - e)[0]) / (2 * h)
        assert dfdp[i] == pytest.approx(fd, rel=1e-5)
