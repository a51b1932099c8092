"""Control surfaces in the coupled residual (wingmdao.aero.system with controls): the harmonic
flap response of the marched residual against Theodorsen's flap loads with the finite-state C(k),
the default system unchanged."""

import math

import numpy as np
import pytest

from wingmdao.aero import aero_parameters, cached_aeroelastic_system, theodorsen_jones
from wingmdao.aero.controls import ControlLaw, ControlSurface, control_spec, flap_harmonic_loads
from wingmdao.beam.static import beam_forcing, beam_parameters, straight_beam
from wingmdao.stability.eigen import eigenmodes
from wingmdao.timemarch.bdf import march, state_rates
from wingmdao.timemarch.system import layout, pack

RHO, V = 1.2, 20.0


def _rigid_wing(n, surfaces, law=None, chord=1.0, extra=None, **kw):
    r0, th0 = straight_beam(n, 4.0)
    bp = beam_parameters(r0, th0, EI_cc=1e9, GJ=1e9, EI_nn=1e10, EA=1e11, mass_per_length=1e-3)
    ap = aero_parameters(n, chord=chord, ref_point=0.25, airspeed=V, density=RHO)
    spec = control_spec(surfaces, r0[:, 1], law)
    s = cached_aeroelastic_system(n, controls=spec, **kw)
    qd = beam_forcing(n)
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3),
              surface_command=np.zeros(spec.n_surfaces))
    extra = {"body_mass": 100.0, "trim_lift": 1000.0, "trim_active": 0.0} | (extra or {})
    values = {**bp, **ap, **({} if law is None else law.matrices()), **qd, **extra}
    return s, pack(s.param_specs, values), pack(s.forcing_specs, values)


def test_default_system_unchanged():
    base = cached_aeroelastic_system(3, plunge=True, trim=True)
    assert base.n_state == 22 * 3 + 2 and base.controls is None
    s, _, _ = _rigid_wing(3, [ControlSurface("aileron", hinge=0.75, nodes=(1, 2))], plunge=True, trim=True)
    assert s.n_state == base.n_state + 2
    assert s.layout.body["trim"] == s.n_state - 1 and s.layout.body["plunge"] == 66


@pytest.mark.parametrize("k", [0.1, 0.4])
def test_harmonic_flap_through_the_residual(k):
    """beta = Im(beta_0 e^{i w t}) through a fast actuator on a rigid, clamped wing: the marched section
    lift, moment and hinge moment against Theodorsen's flap loads with Jones' C(k), the model's
    lift-deficiency function (lift coded independently: L / (rho V^2 b) = -i k T4 + k^2 T1
    + 2 C (T10 + i k T11 / 2), NACA Rep. 496); BDF2 with 200 steps per period: 0.5 %."""
    hinge, b = 0.75, 0.5
    s, p, q = _rigid_wing(2, [ControlSurface("flap", hinge=hinge, nodes=(0, 1), actuator_order=2,
                                             frequency_hz=200.0, damping=0.7)])
    w = k * V / b
    periods = 5
    t = np.linspace(0.0, periods * 2 * np.pi / w, periods * 200 + 1)
    Q = np.tile(q, (t.size, 1))
    Q[:, layout(s.forcing_specs)["surface_command"]] = 0.02 * np.sin(w * t)[:, None]
    h = march(s, t, p, Q)
    Xd = state_rates(h.states, t[1] - t[0])
    L, M = s.section_load_history(h.states, Xd, p, Q)
    beta = h.states[:, s.control_index["flap_deflection"]]
    H = np.array([s.hinge_moments(h.states[i], Xd[i], p, Q[i])[0] for i in range(t.size)]) / 4.0
    m = t >= (periods - 2) * 2 * np.pi / w
    A = np.column_stack([np.sin(w * t[m]), np.cos(w * t[m]), np.ones(m.sum())])

    def phasor(y):
        c = np.linalg.lstsq(A, y[m], rcond=None)[0]
        return c[0] + 1j * c[1]

    beta0 = phasor(beta)
    th = math.acos(1 - 2 * hinge)
    sn, cs = math.sin(th), math.cos(th)
    T4, T1 = -(math.pi - th) - cs * sn, -sn * (2 + cs * cs) / 3 - cs * (math.pi - th)
    T10, T11 = sn + math.pi - th, (math.pi - th) * (1 + 2 * cs) + sn * (2 + cs)
    C = theodorsen_jones(k)
    lift_ref = RHO * V ** 2 * b * (-1j * k * T4 + k ** 2 * T1 + 2 * C * (T10 + 0.5j * k * T11)) * beta0
    _, m_mid, h_ref = flap_harmonic_loads(np.array([k]), hinge, theodorsen_jones)
    moment_ref = (RHO * V ** 2 * b ** 2 * m_mid[0] + lift_ref * 2 * b * (0.25 - 0.5)) * 1.0
    moment_ref = RHO * V ** 2 * b ** 2 * m_mid[0] * beta0 + lift_ref * 2 * b * (0.25 - 0.5)
    hinge_ref = RHO * V ** 2 * b ** 2 * h_ref[0] * beta0
    for ours, ref in ((phasor(L[:, 0]), lift_ref), (phasor(M[:, 0]), moment_ref), (phasor(H), hinge_ref)):
        assert abs(ours - ref) < 5e-3 * abs(ref), (k, ours, ref)


def _flexible_wing(law_gain, n=5, tau=0.02):
    r0, th0 = straight_beam(n, 4.0)
    bp = beam_parameters(r0, th0, EI_cc=5e4, GJ=2e4, EI_nn=5e5, EA=5e6, mass_per_length=5.0)
    ap = aero_parameters(n, chord=1.0, ref_point=0.4, airspeed=V, density=RHO)
    law = ControlLaw(("root_bending",), A=[], B=[], C=[], D=[[1.0]])
    spec = control_spec([ControlSurface("aileron", hinge=0.75, span=(0.5, 1.0), time_constant=tau)], r0[:, 1], law)
    s = cached_aeroelastic_system(n, controls=spec)
    qd = beam_forcing(n)
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3),
              surface_command=np.zeros(1))

    def params(K):
        return pack(s.param_specs, {**bp, **ap, **law.matrices(), "controller_D": np.array([[K]])})

    return s, params, pack(s.forcing_specs, qd)


def _slowest(s, p, q):
    """The real closed-loop eigenvalue of largest real part (the branch the bending feedback drives
    through zero; the in-plane bending modes, undamped in strip theory, are left aside) from the
    linearization of the flutter analysis."""
    lam = eigenmodes(s, p, q, method="dense").eigenvalues
    lam = lam[np.abs(lam.imag) < 1e-9]
    return lam[np.argmax(lam.real)]


def test_closed_loop_stability_limit_eigenvalues_and_march():
    """Root bending fed back to an outboard aileron (u = K M_x,root, MN m): the gain K* where the
    linearization's eigenvalue crosses zero (bisection); below it the marched response to a
    command pulse decays, above it grows, each at the rate of that eigenvalue (5 %)."""
    s, params, q = _flexible_wing(0.0)
    lo, hi = 0.0, 1000.0
    assert _slowest(s, params(lo), q).real < 0 < _slowest(s, params(hi), q).real
    for _ in range(25):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _slowest(s, params(mid), q).real < 0 else (lo, mid)
    k_star = 0.5 * (lo + hi)
    t = np.arange(0, 601) * 0.01
    Q = np.tile(q, (t.size, 1))
    Q[(t > 0) & (t <= 0.05), layout(s.forcing_specs)["surface_command"]] = 0.01
    rates = {}
    for K in (0.7 * k_star, 1.15 * k_star):
        lam = _slowest(s, params(K), q)
        h = march(s, t, params(K), Q)
        m = np.abs(h.states[:, 9])  # root bending M_x
        late = t >= 3.0
        rates[K] = (np.polyfit(t[late], np.log(m[late]), 1)[0], lam.real)
        assert rates[K][0] == pytest.approx(lam.real, rel=0.05), (K, rates[K])
    r_stable, r_unstable = rates[0.7 * k_star][0], rates[1.15 * k_star][0]
    assert r_stable < 0 < r_unstable


def _gust_problem(free, n=3, n_time=8, dt=0.01):
    import openmdao.api as om

    from wingmdao.aero.controls import pid_state_space
    from wingmdao.components.aeroelastic import AeroelasticBeamDynamics

    r0, th0 = straight_beam(n, 2.0)
    bp = beam_parameters(r0, th0, EI_cc=5e4, GJ=2e4, EI_nn=5e5, EA=5e6, mass_per_length=5.0)
    ap = aero_parameters(n, chord=1.0, ref_point=0.4, airspeed=V, density=RHO, mach=0.3, alpha_zero_lift=-0.02)
    if free:
        law = ControlLaw(("load_factor",), A=[], B=[], C=[], D=[[-0.05]])
    else:
        law = ControlLaw(("root_bending",), *pid_state_space(-30.0, -10.0, -0.5, 0.05))
    spec = control_spec([ControlSurface("aileron", hinge=0.75, nodes=(1, 2), actuator_order=2, frequency_hz=8.0)],
                        r0[:, 1], law)
    s = cached_aeroelastic_system(n, plunge=free, trim=free, controls=spec)
    t = np.arange(n_time) * dt
    prob = om.Problem()
    prob.model.add_subsystem("beam", AeroelasticBeamDynamics(num_nodes=n, time=t, matrix_free=False, system=s),
                             promotes=["*"])

    class RootBendingKS(om.ExplicitComponent):
        """KS aggregate of the root bending moment history (kN m), rho = 5."""

        def setup(self):
            self.add_input("states", shape=(n_time,) + s.state_shape)
            self.add_output("ks", units="kN*m", desc="KS of the root bending moment")
            self.declare_partials("ks", "states", rows=np.zeros(n_time, int), cols=np.arange(n_time) * s.n_state + 9)

        def _m(self, inputs):
            return inputs["states"].reshape(n_time, -1)[:, 9] / 1e3

        def compute(self, inputs, outputs):
            m = self._m(inputs)
            outputs["ks"] = m.max() + np.log(np.sum(np.exp(5.0 * (m - m.max())))) / 5.0

        def compute_partials(self, inputs, partials):
            m = self._m(inputs)
            w = np.exp(5.0 * (m - m.max()))
            partials["ks", "states"] = w / w.sum() / 1e3

    prob.model.add_subsystem("agg", RootBendingKS(), promotes=["*"])
    prob.setup(mode="rev")
    values = {**bp, **ap, **law.matrices(), "body_mass": 200.0, "trim_lift": 200.0 * 9.81 + 2 * 5.0 * 2.0 * 9.81}
    for spec_ in s.param_specs:
        prob.set_val(spec_.name, np.asarray(values[spec_.name]).reshape(spec_.shape or (1,)))
    if free:
        prob.set_val("trim_active", (np.arange(n_time) == 0) * 1.0)
    wg = 2.0 * 0.5 * (1 - np.cos(2 * np.pi * t / (n_time * dt)))
    prob.set_val("gust_velocity", np.tile(wg[:, None], (1, n)))
    prob.set_val("gravity", np.tile([0.0, 0.0, -9.81], (n_time, 1)))
    return prob


@pytest.mark.parametrize("free", [False, True], ids=["clamped-pid-root-bending", "plunge-trim-load-factor"])
def test_adjoint_totals_wrt_gains(free):
    """d KS(root bending over a 1-cos gust) / d(controller matrices, stiffness): the discrete adjoint
    against central differences (check_totals)."""
    prob = _gust_problem(free)
    prob.run_model()
    wrt = ["controller_D", "stiffness_csn"] + ([] if free else ["controller_C", "controller_A", "controller_B"])
    rev = prob.compute_totals(of=["ks"], wrt=wrt)
    fd = prob.check_totals(of=["ks"], wrt=wrt[1:2], method="fd", form="central", step=1.0,
                           out_stream=None)
    fd.update(prob.check_totals(of=["ks"], wrt=wrt[:1] + wrt[2:], method="fd", form="central", step=1e-5,
                                out_stream=None))
    for w in wrt:
        ref = fd[("ks", w)]["J_fd"]
        scale = np.max(np.abs(ref))
        assert scale > 0, w
        np.testing.assert_allclose(rev[("ks", w)], ref, rtol=0, atol=1e-4 * scale)


@pytest.mark.slow
def test_component_check_partials_with_law():
    """AeroelasticBeamDynamics carrying surfaces and a PID law: its CasADi partials (the controller
    matrices included) against central differences."""
    prob = _gust_problem(False, n_time=4)
    prob.run_model()
    data = prob.check_partials(out_stream=None, method="fd", step=1e-6, form="central", includes=["beam"])
    for (of, wrt), d in data["beam"].items():
        fd, an = d["J_fd"], d["J_fwd"]
        scale = max(np.max(np.abs(fd)), 1e-8)
        assert np.max(np.abs(an - fd)) <= 2e-5 * scale + 1e-6, (of, wrt)


def test_sizing_case_with_alleviation_totals_and_gain_design_vars():
    """PEGASUS coupled gust case (free plunge, short grid) with the alleviation file of docs/controls.md
    in the sizing model: the gains are case inputs, KS totals w.r.t. gains and a thickness against
    central differences, and ``size_gains`` makes C and D design variables."""
    import os

    from wingmdao.cases import pegasus
    from wingmdao.sizing import build_problem, control_gain_design_vars

    example = os.path.join(os.path.dirname(__file__), "..", "docs", "examples", "pegasus_alleviation.yaml")
    args = pegasus.PegasusOptions(loads="gust", aero="coupled", plunge="free", t_final=0.3, dt=0.03, gust_start=0.0,
                                  alleviation=example, size_gains=True)
    setup = pegasus.build(args)
    setup.options.disp = False
    dvs = control_gain_design_vars(setup.load_cases)
    assert set(dvs) == {"cases.gust.controller_C", "cases.gust.controller_D"}
    assert dvs["cases.gust.controller_C"]["upper"] == pytest.approx(1.0)  # 4 x |C| = 4 x 0.25
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
    prob.run_model()
    wrt = ["t_upper_skin", "cases.gust.controller_C", "cases.gust.controller_B"]
    data = prob.check_totals(of=["cases.gust.ks_vm"], wrt=wrt, method="fd", form="central", step=1e-6,
                             step_calc="rel_avg", out_stream=None)
    for key, d in data.items():
        J = d["J_fwd"] if "J_fwd" in d else d["J_rev"]
        assert np.abs(d["J_fd"]).max() > 0, key
        assert np.abs(J - d["J_fd"]).max() <= 1e-6 * np.abs(d["J_fd"]).max(), key
    with pytest.raises(ValueError, match="--size-gains needs --alleviation"):
        pegasus.build(pegasus.PegasusOptions(loads="gust", aero="coupled", plunge="free", size_gains=True))
