"""The 14 CFR 25.331(c)(2) checked pitch maneuver (wingmdao.loads.checked_pitch) and the elevator of
the free-pitch model (wingmdao.aero.pitch; docs/maneuvers.md).

References: the regulation's control history (14 CFR 25.331(c)(2)(i), Amdt. 25-141, 2014); the
short-period approximation (Nelson, Flight Stability and Automatic Control, 2nd ed., 1998, Sec. 4.4;
Etkin & Reid, Dynamics of Flight, 3rd ed., 1996, Sec. 6.3) for the frequency and, written here
as its own two-state model with the elevator and the actuator and integrated by scipy, for the
load-factor response of a very stiff, small-chord wing (reduced frequency < 0.03: the Wagner lag
is negligible).
"""

import numpy as np
import pytest
import scipy.signal as sig

from wingmdao.aero import aero_parameters, cached_aeroelastic_system
from wingmdao.aero.pitch import elevator_effectiveness, pitch_parameters, short_period_closed_form
from wingmdao.beam.static import beam_parameters, straight_beam
from wingmdao.loads.checked_pitch import (checked_pitch, control_history, march_maneuver, maneuver_duration,
                                          minimum_frequency, short_period_mode)
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import layout, pack

G = 9.81
# the light aircraft of tests/test_pitch.py: long, very stiff, small-chord strip wing (S = 5 m^2)
N, SEMI, C, V, RHO, REF = 5, 25.0, 0.1, 60.0, 1.2, 0.25
MASS, IYY, TAIL_ARM, TAIL_SLOPE, TAIL_AREA, DOWNWASH, CG_X = 510.0, 600.0, 4.0, 4.0, 1.2, 0.3, 0.05
TAU_E, T_ACT = 0.5, 0.05


def _aircraft(elevator=True):
    r0, th0 = straight_beam(N, SEMI)
    bp = beam_parameters(r0, th0, EI_cc=1e12, GJ=1e12, EI_nn=1e13, EA=1e14, mass_per_length=0.1)
    ap = aero_parameters(N, chord=C, ref_point=REF, airspeed=V, density=RHO)
    s = cached_aeroelastic_system(N, plunge=True, trim=True, pitch=True, elevator=elevator)
    par = {**bp, **ap, "trim_lift": MASS * G}
    par.update(pitch_parameters(aircraft_mass=MASS, cg=(CG_X, 0.0), aircraft_pitch_inertia=IYY, tail_arm=TAIL_ARM,
                                tail_area=TAIL_AREA, tail_lift_slope=TAIL_SLOPE, downwash_gradient=DOWNWASH,
                                mass_per_length=bp["mass_per_length"], node_positions=r0))
    if elevator:
        par.update(elevator_effectiveness=TAU_E, elevator_time_constant=T_ACT)
    return s, pack(s.param_specs, par)


def test_no_elevator_is_unchanged_and_zero_command_changes_nothing():
    """The system without an elevator has no elevator state, parameter or forcing; with one and a
    zero command, the march is the same as without, state by state (to round-off)."""
    s0, p0 = _aircraft(elevator=False)
    s1, p1 = _aircraft(elevator=True)
    assert "elevator_deflection" not in s0.body_index and "elevator_command" not in layout(s0.forcing_specs)
    assert s1.n_state == s0.n_state + 1
    t = np.arange(41) * 0.01
    Q = []
    for s in (s0, s1):
        q = np.zeros((t.size, s.n_forcing))
        ql = layout(s.forcing_specs)
        q[:, ql["gravity"].start + 2] = -G
        q[0, ql["trim_active"]] = 1.0
        q[:, ql["tail_gust_velocity"]] = 0.5 * np.sin(10 * t)[:, None]  # something to respond to
        Q.append(q)
    h0 = march(s0, t, p0, Q[0], modified_newton=True)
    h1 = march(s1, t, p1, Q[1], modified_newton=True)
    keep = np.delete(np.arange(s1.n_state), s1.body_index["elevator_deflection"])
    np.testing.assert_allclose(h1.states[:, keep], h0.states, rtol=1e-10, atol=1e-10)
    assert np.all(h1.states[:, s1.body_index["elevator_deflection"]] == 0.0)


def test_elevator_effectiveness_thin_airfoil_and_bad_input():
    """Glauert's tau_e = 1 - (theta - sin theta) / pi, cos theta = 2 E - 1, at a closed value:
    E = 0.5 gives theta = pi / 2 and tau_e = 1 - (pi / 2 - 1) / pi = 0.5 + 1 / pi; E = 0.3 gives 0.6607."""
    assert elevator_effectiveness(0.5) == pytest.approx(0.5 + 1 / np.pi, rel=1e-14)
    assert elevator_effectiveness(0.3) == pytest.approx(0.6607, abs=1e-4)
    with pytest.raises(ValueError, match=r"elevator chord ratio = 1.2; allowed range \(0, 1\)"):
        elevator_effectiveness(1.2)


def test_control_history_has_the_regulation_form():
    """25.331(c)(2)(i): delta_1 sin(omega t) on [0, 3 pi / (2 omega)]: zero at the start, +-delta_1 at
    pi / (2 omega) and 3 pi / (2 omega) (the reverse direction), zero at pi / omega; nose up starts
    trailing edge up (negative). (iii) holds delta_1 for Delta t."""
    w, d1 = 2.0, 0.1
    tm = maneuver_duration(w)
    assert tm == pytest.approx(3 * np.pi / (2 * w))
    t = np.array([0.0, np.pi / (2 * w), np.pi / w, tm])
    np.testing.assert_allclose(control_history(t, d1, w, "nose-up"), [0, -d1, 0, d1], atol=1e-15)
    np.testing.assert_allclose(control_history(t, d1, w, "nose-down"), [0, d1, 0, -d1], atol=1e-15)
    tt = np.linspace(0, tm, 7)
    np.testing.assert_allclose(control_history(tt, d1, w, "nose-down"), d1 * np.sin(w * tt), atol=1e-15)
    dt = 0.7  # (iii): held at delta_1 from t_1 to t_1 + dt, then the rest of the sine
    th = np.array([0.5 * np.pi / w, 0.5 * np.pi / w + dt / 2, 0.5 * np.pi / w + dt, np.pi / w + dt,
                   maneuver_duration(w, dt)])
    np.testing.assert_allclose(control_history(th, d1, w, "nose-down", hold=dt), [d1, d1, d1, 0, -d1], atol=1e-15)
    assert minimum_frequency(200.0, 100.0) == pytest.approx(np.pi)
    with pytest.raises(ValueError, match=r"maneuvering_speed_eas = -1.0 m/s; allowed range \(0, inf\)"):
        minimum_frequency(100.0, -1.0)


def test_short_period_frequency_matches_closed_form():
    """The linearization's short-period mode (picked by its pitch attitude, with the elevator's
    actuator in the model) against the closed form: |lambda| within 1 % (measured 0.4 %; reduced
    frequency 0.006)."""
    s, p = _aircraft()
    lam, _ = short_period_mode(s, p, gravity=G)
    ref = short_period_closed_form(mass=MASS, pitch_inertia=IYY, airspeed=V, density=RHO, wing_area=2 * SEMI * C,
                                   wing_lift_slope=2 * np.pi, tail_area=TAIL_AREA, tail_lift_slope=TAIL_SLOPE,
                                   tail_arm=TAIL_ARM, downwash_gradient=DOWNWASH, wing_ac_arm=CG_X)
    assert abs(lam) == pytest.approx(abs(ref[0]), rel=0.01)
    assert lam.real < 0


def _rigid_short_period_response(time, command):
    """Incremental load factor of the rigid airplane (alpha at the CG, q; first-order actuator):

        m V (d alpha/dt - q) = -dL,  I dq/dt = q_d S a_w x_w alpha - q_d S_t a_t l_t alpha_t,
        dL = q_d (S a_w alpha + S_t a_t alpha_t),  alpha_t = (1 - deps/dalpha) alpha + q l_t / V + tau_e delta,
        t_a d delta/dt + delta = delta_cmd,  dn = dL / (m g)."""
    qd, S = 0.5 * RHO * V ** 2, 2 * SEMI * C
    aw, at = S * 2 * np.pi * qd, TAIL_AREA * TAIL_SLOPE * qd
    # alpha_t = ka alpha + kq q + kd delta
    ka, kq, kd = 1 - DOWNWASH, TAIL_ARM / V, TAU_E
    A = np.array([[-(aw + at * ka) / (MASS * V), 1 - at * kq / (MASS * V), -at * kd / (MASS * V)],
                  [(aw * CG_X - at * ka * TAIL_ARM) / IYY, -at * kq * TAIL_ARM / IYY, -at * kd * TAIL_ARM / IYY],
                  [0.0, 0.0, -1 / T_ACT]])
    B = np.array([[0.0], [0.0], [1 / T_ACT]])
    Cm = np.array([[(aw + at * ka) / (MASS * G), at * kq / (MASS * G), at * kd / (MASS * G)]])
    _, y, _ = sig.lsim((A, B, Cm, np.zeros((1, 1))), command, time)
    return y


def test_load_factor_response_matches_rigid_short_period_model():
    """The march's load-factor increment to the checked-pitch command against the rigid two-state
    short-period model with the same elevator and actuator: within 3 % of the peak over the whole
    history (measured 1.6 %: the model takes the angle of attack at the CG and the tail arm from
    it, the march at the body-axes origin 0.05 m ahead, and has no wing pitch damping or Wagner
    lag)."""
    s, p = _aircraft()
    w = 5.0
    t = np.linspace(0.0, maneuver_duration(w), 301)
    cmd = control_history(t, np.radians(5.0), w, "nose-up")
    _, n, _ = march_maneuver(s, p, t, cmd, gravity=G, weight=MASS * G)
    ref = _rigid_short_period_response(t, cmd)
    assert np.max(np.abs(ref)) > 0.3
    assert np.max(np.abs((n - 1) - ref)) < 0.03 * np.max(np.abs(ref))


@pytest.mark.parametrize("direction, v_a", [("nose-up", 50.0), ("nose-down", 50.0), ("nose-up", 10.0)])
def test_checked_pitch_reaches_target(direction, v_a):
    """Peak load factor within 1 % of the target (2.5 nose up; 0 g nose down: within 0.01 g), the
    command of the regulation's form with omega = max(short period, pi V / (2 V_A)), the march
    over [0, t_max]; V_A = 10 m/s makes the regulation's lower limit (9.4 rad/s) the frequency."""
    s, p = _aircraft()
    r = checked_pitch(s, p, weight=MASS * G, airspeed_eas=V, maneuvering_speed_eas=v_a, limit_load_factor=2.5,
                      direction=direction, gravity=G)
    target = 2.5 if direction == "nose-up" else 0.0
    assert r.target_load_factor == target
    assert abs(r.peak_load_factor - target) <= 0.01 * max(abs(target), 1.0)
    assert r.omega == pytest.approx(max(abs(r.short_period_eigenvalue), np.pi * V / (2 * v_a)), rel=1e-14)
    assert (r.omega == r.omega_min) == (v_a == 10.0)
    assert r.time[0] == 0 and r.time[-1] == pytest.approx(3 * np.pi / (2 * r.omega), rel=1e-14)
    sign = -1.0 if direction == "nose-up" else 1.0
    np.testing.assert_allclose(r.elevator_command, sign * r.delta_1 * np.sin(r.omega * r.time), atol=1e-15)
    assert r.elevator_command[0] == 0 and abs(r.elevator_command[-1]) == pytest.approx(r.delta_1, rel=1e-12)
    assert r.elevator[0] == 0 and np.max(np.abs(r.elevator)) <= r.delta_1  # the actuator lags, never overshoots
    assert r.load_factor[0] == pytest.approx(1.0, abs=1e-9)


def test_checked_pitch_bad_input_before_any_solve():
    s, p = _aircraft()
    with pytest.raises(ValueError, match=r"maneuvering_speed_eas = 0.0 m/s; allowed range \(0, inf\)"):
        checked_pitch(s, p, weight=MASS * G, airspeed_eas=V, maneuvering_speed_eas=0.0, limit_load_factor=2.5)
    with pytest.raises(ValueError, match=r"limit_load_factor = 0.5; allowed range \(1, inf\)"):
        checked_pitch(s, p, weight=MASS * G, airspeed_eas=V, maneuvering_speed_eas=50.0, limit_load_factor=0.5)
    s0, p0 = _aircraft(elevator=False)
    with pytest.raises(ValueError, match="needs a system with an elevator"):
        checked_pitch(s0, p0, weight=MASS * G, airspeed_eas=V, maneuvering_speed_eas=50.0, limit_load_factor=2.5)
    with pytest.raises(ValueError, match="elevator=True needs pitch=True"):
        cached_aeroelastic_system(N, plunge=True, trim=True, elevator=True)


def test_peak_root_bending_ks_totals_at_fixed_delta_1():
    """check_totals of a KS of the root bending moment over a short checked-pitch history at a fixed
    delta_1 (trimmed at t = 0, elevator command as forcing) through BoxSection and
    PitchBodyProperties: adjoint vs central FD w.r.t. the wall thicknesses and the elevator
    effectiveness, within 1e-6 of the largest entry (measured 1.8e-8, 1.6e-8, 4e-10)."""
    import openmdao.api as om

    from wingmdao.components.aeroelastic import AeroelasticBeamDynamics, PitchBodyProperties
    from wingmdao.components.section import BoxSection
    from wingmdao.materials import ALUMINIUM

    n, n_time, w = 3, 8, 6.0
    s = cached_aeroelastic_system(n, plunge=True, trim=True, pitch=True, elevator=True)
    r0, th0 = straight_beam(n, 4.0)
    t = np.linspace(0.0, maneuver_duration(w), n_time)
    prob = om.Problem(reports=False)
    model = prob.model
    model.add_subsystem("section", BoxSection(num_stations=n, material=ALUMINIUM), promotes=["*"])
    model.add_subsystem("body", PitchBodyProperties(num_nodes=n, trim_load_factor=1.0),
                        promotes_inputs=["mass_per_length"])
    model.add_subsystem("beam", AeroelasticBeamDynamics(num_nodes=n, time=t, matrix_free=False, system=s),
                        promotes_inputs=["stiffness_csn", "compliance_csn", "mass_per_length", "inertia_per_length",
                                         "elevator_effectiveness"])
    for k in ("body_mass", "body_first_moment", "body_pitch_inertia", "tail_x", "trim_lift"):
        model.connect(f"body.{k}", f"beam.{k}")
    model.connect("beam.node_positions", "body.node_positions")

    class KS(om.ExplicitComponent):
        def setup(self):
            self.add_input("states", shape=(n_time, s.n_state), units=None, desc="aeroelastic states")
            self.add_output("ks", units=None, desc="KS of the root bending moment / 1e3")
            self.declare_partials("ks", "states", rows=np.zeros(n_time, int), cols=np.arange(n_time) * s.n_state + 9)

        def _w(self, m):
            y = 10.0 * m[:, 9] / 1e3
            return y, np.exp(y - y.max())

        def compute(self, inputs, outputs):
            y, e = self._w(inputs["states"])
            outputs["ks"] = (y.max() + np.log(e.sum())) / 10.0

        def compute_partials(self, inputs, partials):
            _, e = self._w(inputs["states"])
            partials["ks", "states"] = e / e.sum() / 1e3

    model.add_subsystem("ks", KS())
    model.connect("beam.states", "ks.states")
    prob.setup(mode="rev")
    prob.set_val("width", np.full(n, 0.5))
    prob.set_val("height", np.full(n, 0.12))
    for wall in ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar"):
        prob.set_val(wall, np.full(n, 0.002))
    prob.set_val("beam.node_positions", r0)
    prob.set_val("beam.node_euler_angles", th0)
    for k in ("tension_axis", "shear_center", "mass_center"):
        prob.set_val(f"beam.{k}", np.zeros((n, 2)))
    for k, v in aero_parameters(n, chord=1.0, ref_point=0.4, airspeed=40.0, density=1.2).items():
        prob.set_val(f"beam.{k}", v)
    prob.set_val("body.aircraft_mass", 400.0)
    prob.set_val("body.aircraft_cg", [0.3, 0.0])
    prob.set_val("body.aircraft_pitch_inertia", 300.0)
    prob.set_val("body.tail_arm", 3.0)
    prob.set_val("beam.tail_area", 1.0)
    prob.set_val("beam.tail_lift_slope", 4.0)
    prob.set_val("beam.downwash_gradient", 0.3)
    prob.set_val("elevator_effectiveness", TAU_E)
    prob.set_val("beam.elevator_time_constant", T_ACT)
    prob.set_val("beam.gravity", np.tile([0.0, 0.0, -G], (n_time, 1)))
    trim = np.zeros(n_time)
    trim[0] = 1.0
    prob.set_val("beam.trim_active", trim)
    prob.set_val("beam.elevator_command", control_history(t, np.radians(8.0), w, "nose-up"))
    prob.run_model()
    X = prob.get_val("beam.states")
    assert np.max(np.abs(X[:, s.body_index["pitch_rate"]])) > 1e-3  # the elevator pitches the aircraft
    wrt = ["t_upper_skin", "t_front_spar", "elevator_effectiveness"]
    rev = prob.compute_totals(of=["ks.ks"], wrt=wrt)
    fd = prob.check_totals(of=["ks.ks"], wrt=wrt, method="fd", form="central", step=1e-6, step_calc="rel_avg",
                           out_stream=None)
    for name in wrt:
        ref = fd[("ks.ks", name)]["J_fd"]
        scale = np.max(np.abs(ref))
        assert scale > 0
        np.testing.assert_allclose(rev[("ks.ks", name)], ref, atol=1e-6 * scale, err_msg=name)


def test_held_command_when_the_amplitude_is_limited():
    """25.331(c)(2)(iii): with the largest available command 0.8 of the delta_1 the sine needs, the
    command is held at it for the Delta t that reaches the target (within 1 %), its form sin /
    hold / sin over t_max = 3 pi / (2 omega) + Delta t; a tiny limit does not reach it within the
    5 s the rule asks for at most, and says so (50 steps over the sine: a 5 s hold is 500 more)."""
    s, p = _aircraft()
    kw = dict(weight=MASS * G, airspeed_eas=V, maneuvering_speed_eas=50.0, limit_load_factor=2.5, gravity=G, steps=50)
    free = checked_pitch(s, p, **kw)
    r = checked_pitch(s, p, max_amplitude=0.8 * free.delta_1, **kw)
    assert r.reached and 0 < r.hold < 5.0
    assert r.delta_1 == pytest.approx(0.8 * free.delta_1, rel=1e-14)
    assert abs(r.peak_load_factor - 2.5) <= 0.01 * 2.5
    assert r.time[-1] == pytest.approx(maneuver_duration(r.omega, r.hold), rel=1e-12)
    np.testing.assert_allclose(r.elevator_command, control_history(r.time, r.delta_1, r.omega, hold=r.hold),
                               atol=1e-15)
    t1 = 0.5 * np.pi / r.omega
    held = (r.time >= t1) & (r.time <= t1 + r.hold)
    assert held.sum() > 2 and np.all(r.elevator_command[held] == pytest.approx(-r.delta_1, rel=1e-12))
    short = checked_pitch(s, p, max_amplitude=0.5 * free.delta_1, **kw)
    assert not short.reached and short.hold == 5.0 and short.peak_load_factor < 2.0
