"""Continuous turbulence (14 CFR 25.341(b)): frequency response and A-bar against independent references.

* the frequency response against the BDF2 time march of the same residual under a harmonic gust;
* A-bar of the load factor of a rigid aircraft in plunge (Wagner in R. T. Jones' form, NACA Rep.
  681, 1940; Kuessner in the Sears-Sparks form, J. Aero. Sci. 9, 1941; apparent mass of
  Theodorsen, NACA Rep. 496, 1935) against an adaptive quadrature (scipy.integrate.quad) of the
  closed-form transfer function written out here;
* the von Karman spectrum of 25.341(b)(2) integrates to sigma^2;
* U_sigma, F_g and the V_C/V_D interpolation against values computed by hand at three altitudes;
* correlation coefficients of loads that are multiples of each other; bad input.
"""

import numpy as np
import pytest
from scipy.integrate import quad

from wingmdao.aero import aero_parameters, cached_aeroelastic_system
from wingmdao.beam.static import beam_forcing, beam_parameters, straight_beam
from wingmdao.loads import turbulence as tb
from wingmdao.stability.eigen import eigenmodes
from wingmdao.stability.frequency import (aeroelastic_outputs, check_frequencies, frequency_grid, frequency_response,
                                          state_output,
                                          linear_gust_model, spectral_integral, stress_matrix, stress_response)
from wingmdao.timemarch.bdf import march, solve_static
from wingmdao.timemarch.system import layout, pack

FT = 0.3048


def _trimmed_wing(n=4, V=40.0, rho=1.0, c=1.0, span=8.0, g=9.81, mass=300.0):
    """A flexible straight wing free in plunge, trimmed at 1 g under gravity."""
    r0, th0 = straight_beam(n, span)
    bp = beam_parameters(r0, th0, EI_cc=2e5, GJ=1e5, EI_nn=1e7, EA=1e9, mass_per_length=5.0)
    ap = aero_parameters(n, chord=c, ref_point=0.35, airspeed=V, density=rho)
    s = cached_aeroelastic_system(n, plunge=True, trim=True)
    W = mass * g
    p = pack(s.param_specs, {**bp, **ap, "body_mass": mass - 2 * 5.0 * span, "trim_lift": W})
    qd = beam_forcing(n, gravity=[0, 0, -g])
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3),
              trim_active=1.0)
    q_trim = pack(s.forcing_specs, qd)
    qd["trim_active"] = 0.0
    return s, p, q_trim, pack(s.forcing_specs, qd), r0, W


def _march_against_response(model, series, t, last, om, U, dt, decays):
    """(marched, discrete, expected) per output of ``series`` (histories at ``t`` under the harmonic
    gust U sin(om (t - lag))): the amplitude and phase fitted over ``t[last]`` (harmonic + constant +
    the transient's modes, ``decays`` complex rates), the linear response with i omega replaced by
    the BDF2 symbol (3 - 4/z + 1/z^2) / (2 dt), z = exp(i om dt), and the frequency response |H|.
    U sin(om t) = Re(-i U e^{i om t}) gives y = U (Re H sin + Im H cos)."""
    H = frequency_response(model, [om]).outputs
    tl = t[last] - t[last][0]
    basis = [np.sin(om * t[last]), np.cos(om * t[last]), np.ones(last.sum())]
    for r in decays:
        basis += ([np.exp(r.real * tl)] if abs(r.imag) < 1e-9 else
                  [np.exp(r.real * tl) * np.cos(r.imag * tl), np.exp(r.real * tl) * np.sin(r.imag * tl)])
    basis = np.column_stack(basis)
    z = np.exp(1j * om * dt)
    s_h = (3 - 4 / z + 1 / z ** 2) / (2 * dt)
    w_vec = model.gust_vector([om])[0]
    X = np.linalg.solve((model.A + s_h * model.E).toarray(), -(model.G @ w_vec))
    out = {}
    for name, y in series.items():
        coef, *_ = np.linalg.lstsq(basis, y[last], rcond=None)
        m = model.outputs[name]
        out[name] = ((coef[0] + 1j * coef[1]) / U, complex((m.Cx @ X + s_h * (m.Cv @ X) + m.D @ w_vec)[0]),
                     complex(H[name][0, 0]))
    return out


def test_frequency_response_equals_time_march_amplitude():
    """A harmonic gust sin(omega (t - x_i / V)) of 0.01 m/s at 3 Hz marched by BDF2 (dt = 2 ms, 1.6 s)
    from the trimmed 1 g state: the steady-state amplitude and phase of the root bending moment,
    tip deflection and load factor (the march's own lift integral) equal the frequency response
    within the time-step error (3e-3 at omega dt = 0.038), and equal to 4e-4 (1e-3 asserted) the
    linear response with i omega replaced by the BDF2 symbol (3 - 4/z + 1/z^2) / (2 dt),
    z = exp(i omega dt): the difference is the time step's. The transient of the slow real modes
    (Wagner lags, plunge) is fitted with the harmonic."""
    s, p, q_trim, q0, r0, W = _trimmed_wing()
    x0, _ = solve_static(s, p, q_trim)
    x_le = r0[:, 0] - 0.35 * 1.0 + np.array([0.0, 0.3, 0.6, 0.9])  # stations meet the gust at different times
    model = linear_gust_model(s, p, q0, x0, x_stations=x_le, airspeed=40.0,
                              outputs=aeroelastic_outputs(s, p, q0, x0, weight=W))
    om, U = 2 * np.pi * 3.0, 0.01
    dt = 2e-3
    t = np.arange(int(1.6 / dt) + 1) * dt
    ql = layout(s.forcing_specs)
    Q = np.tile(q0, (t.size, 1))
    Q[0] = q_trim
    lag = (x_le - x_le.min()) / 40.0
    ramp = np.minimum(t / 0.2, 1.0)[:, None]  # smooth start, steady after 0.2 s
    Q[:, ql["gust_velocity"]] = U * ramp * np.sin(om * (t[:, None] - lag[None, :]))
    h = march(s, t, p, Q)
    beam = s.layout.beam_states(h.states)
    series = {"root_bending_moment": beam[:, 0, 9], "tip_deflection": beam[:, -1, 2],
              "load_factor": s.total_lift_history(h.states, dt, p, Q) / W}
    last = t >= 1.2  # transients (slowest aerodynamic lag ~0.3 s) gone
    # the transient: the slow real modes (Wagner lags V beta_1 / b = 3.6 /s, plunge) decay as e^(lambda t)
    lam = eigenmodes(s, p, q0, x0, static=False).eigenvalues
    slow = np.unique(np.round(lam.real[(np.abs(lam.imag) < 1e-9) & (lam.real < -0.1) & (lam.real > -12)], 2))
    for name, (marched, discrete, expected) in _march_against_response(model, series, t, last, om, U, dt,
                                                                       slow.astype(complex)).items():
        assert abs(marched - discrete) <= 1e-3 * abs(discrete), (name, marched, discrete)
        assert abs(marched - expected) <= 5e-3 * abs(expected), (name, marched, expected)


def _plunge_reference(omega, *, V, rho, c, span, mass, a=2 * np.pi, g=9.81):
    """Closed-form load-factor transfer function (per m/s of gust) of a rigid wing free in plunge:
    M i w W = 2 s [q c a (C_J(k) (-W / V) + S(k) w_g / V) - pi rho b^2 i w W], dn = i w W / g."""
    b, q = c / 2, 0.5 * rho * V ** 2
    ik = 1j * omega * b / V
    C = 1 - 0.165 * ik / (ik + 0.0455) - 0.335 * ik / (ik + 0.3)
    S = 1 - 0.5 * ik / (ik + 0.13) - 0.5 * ik / (ik + 1.0)
    iw = 1j * omega
    W = 2 * span * q * c * a * S / V / (mass * iw + 2 * span * q * c * a * C / V + 2 * span * np.pi * rho * b ** 2 * iw)
    return iw * W / g


def _von_karman(omega, V, L=2500 * FT):
    """25.341(b)(2) with sigma = 1, converted to (m/s)^2 per rad/s: Phi(omega / V) / V."""
    x = 1.339 * L * omega / V
    return L / np.pi * (1 + 8 / 3 * x ** 2) / (1 + x ** 2) ** (11 / 6) / V


def test_a_bar_rigid_plunge_against_closed_form_quadrature():
    """A-bar of the load factor of a very stiff wing free in plunge (mass parameter mu = 20) against
    quad of the closed form: within 2e-4 relative, and within the stated quadrature error + 1e-4."""
    n, V, rho, c, span, g = 2, 20.0, 1.2, 1.0, 4.0, 9.81
    r0, th0 = straight_beam(n, span)
    bp = beam_parameters(r0, th0, EI_cc=1e10, GJ=1e10, EI_nn=1e11, EA=1e12, mass_per_length=1e-3)
    ap = aero_parameters(n, chord=c, ref_point=0.25, airspeed=V, density=rho)
    s = cached_aeroelastic_system(n, plunge=True)
    mu = 20.0
    M = mu * rho * c * 2 * np.pi * (2 * span * c) / 2  # mu = 2 (W/S) / (rho c a g)
    p = pack(s.param_specs, {**bp, **ap, "body_mass": M})
    qd = beam_forcing(n)
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3))
    q = pack(s.forcing_specs, qd)
    x0 = s.initial_guess(p, q)
    out = aeroelastic_outputs(s, p, q, x0, weight=(M + 2 * 1e-3 * span) * g)
    model = linear_gust_model(s, p, q, x0, x_stations=np.zeros(n), airspeed=V, outputs=out)
    modes = eigenmodes(s, p, q, x0, static=False)
    w = frequency_grid(modes.eigenvalues, f_min=1e-4, f_max=200.0, n_base=401)
    ab = tb.a_bar(w, frequency_response(model, w).outputs["load_factor"], V)
    ref2, _ = quad(lambda om: abs(_plunge_reference(om, V=V, rho=rho, c=c, span=span, mass=M + 2e-3 * span)) ** 2
                   * _von_karman(om, V), 0, np.inf, limit=400, epsabs=0, epsrel=1e-10)
    ref = np.sqrt(ref2)
    got, err = float(ab.value[0]), float(ab.error[0])
    assert abs(got - ref) <= 2e-4 * ref, (got, ref)
    assert abs(got - ref) <= err + 1e-4 * ref
    # the closed form itself, against the grid's transfer function at a few frequencies
    fr = frequency_response(model, [0.5, 5.0, 50.0]).outputs["load_factor"][:, 0]
    np.testing.assert_allclose(fr, _plunge_reference(np.array([0.5, 5.0, 50.0]), V=V, rho=rho, c=c, span=span,
                                                                   mass=M + 2 * 1e-3 * span),
                               rtol=1e-5)


def test_von_karman_integrates_to_sigma_squared():
    """int_0^inf Phi d omega = sigma^2 for the one-sided spectrum of 25.341(b)(2), to the rounding of
    its constant 1.339: int_0^inf (1 + 8/3 x^2) / (1 + x^2)^(11/6) dx = 4.2065463 (Beta functions,
    B(1/2, 4/3)/2 + 4/3 B(3/2, 1/3)), so the integral is 4.2065463 / (1.339 pi) sigma^2 = 0.999989 sigma^2."""
    for V in (50.0, 250.0):
        # in u = ln(omega): the omega^(-5/3) tail beyond e^40 rad/s is below 1e-11
        val, _ = quad(lambda u, V=V: tb.von_karman_psd(np.exp(u), V, sigma=3.0) * np.exp(u), -30, 40, limit=400,
                      epsrel=1e-11)
        assert abs(val / 9.0 - 0.999989) < 1e-6


def test_u_sigma_f_g_and_speed_interpolation_hand_values():
    """Z_mo = 41,000 ft, MLW/MTOW = 0.85, MZFW/MTOW = 0.75, by hand:
    F_gz = 1 - 41000/250000 = 0.836; F_gm = sqrt(0.75 tan(0.85 pi / 4)) = 0.768929;
    F_g(0) = (0.836 + 0.768929) / 2 = 0.802465, F_g(h) = F_g(0) + (1 - F_g(0)) h / 41000;
    U_sigma_ref: 90 ft/s (0 ft), 90 - 11 x 12000/24000 = 84.5 ft/s (12,000 ft), 79 ft/s (30,000 ft)."""
    hand = {0.0: (90.0, 0.802465), 12000.0: (84.5, 0.860280), 30000.0: (79.0, 0.947003)}
    for h, (u_ref_fps, f_g) in hand.items():
        pt = tb.continuous_turbulence_intensity(h, z_mo_ft=41000.0, mlw_over_mtow=0.85, mzfw_over_mtow=0.75)
        assert pt.u_sigma_ref == pytest.approx(u_ref_fps * FT, rel=1e-12)
        assert pt.f_g == pytest.approx(f_g, abs=1e-6)
        assert pt.u_sigma == pytest.approx(u_ref_fps * FT * f_g, rel=1e-6)
        # V_C = 150, V_D = 200 (m/s EAS): full at V_C and below, 3/4 at 175, 1/2 at V_D
        for speed, factor in ((120.0, 1.0), (150.0, 1.0), (175.0, 0.75), (200.0, 0.5)):
            pv = tb.continuous_turbulence_intensity(h, z_mo_ft=41000.0, mlw_over_mtow=0.85, mzfw_over_mtow=0.75,
                                                    speed=speed, v_c=150.0, v_d=200.0)
            assert pv.u_sigma == pytest.approx(factor * u_ref_fps * FT * f_g, rel=1e-6)
            assert pv.speed_factor == pytest.approx(factor, rel=1e-12)


def test_correlation_of_proportional_loads_and_ellipse():
    w = frequency_grid((), f_min=0.01, f_max=10.0, n_base=101)
    H = (1.0 + 0.3j * w) / (1.0 + 0.2j * w - 0.05 * w ** 2)
    assert tb.correlation(w, H, 2.5 * H, 100.0) == pytest.approx(1.0, abs=1e-12)
    assert tb.correlation(w, H, -0.1 * H, 100.0) == pytest.approx(-1.0, abs=1e-12)
    ab = tb.a_bar(w, np.column_stack([H, -3 * H]), 100.0).value
    assert ab[1] == pytest.approx(3 * ab[0], rel=1e-12)
    pts = tb.correlated_loads((10.0, 5.0), 2.0, (1.0, 3.0), -1.0)
    np.testing.assert_allclose(pts[0], [12.0, -1.0])
    ell = tb.equal_probability_ellipse((10.0, 5.0), 2.0, (1.0, 3.0), 0.5, n_points=2001)
    assert ell[:, 0].max() == pytest.approx(12.0, rel=1e-6)
    assert ell[:, 1].max() == pytest.approx(11.0, rel=1e-6)
    up, down = tb.design_loads([1.0, -2.0], 10.0, [0.5, 0.1])
    np.testing.assert_allclose(up, [6.0, -1.0])
    np.testing.assert_allclose(down, [-4.0, -3.0])


def test_quadrature_error_estimate_and_stresses_linear():
    """The Richardson estimate is of the size of the true error of a known integral
    (int_0^inf 1/(1 + w^2)^2 dw = pi/4), and the stress response is S times the load response."""
    w = frequency_grid([-0.05 + 1.0j], f_min=1e-3, f_max=50.0, n_base=61)
    f = 1 / (1 + w ** 2) ** 2
    res = spectral_integral(w, f)
    assert abs(res.value - np.pi / 4) < 3 * res.quadrature_error + 1e-3
    S = stress_matrix(0.5, 0.2, 0.004, 0.003, 0.006, 0.005)
    from wingmdao.stress.box_stress import box_stresses

    load = np.array([3e3, -2e4, 5e4, 2e5, -3e4, 1e5])
    ref = box_stresses(load[:3], load[3:], 0.5, 0.2, 0.004, 0.003, 0.006, 0.005)
    np.testing.assert_allclose(S @ load, np.r_[ref["sigma_corner"], ref["tau_cent"]], rtol=1e-12)
    H = np.random.default_rng(0).standard_normal((3, 12)) + 1j
    out = stress_response(H, np.stack([S, 2 * S]))
    np.testing.assert_allclose(out[:, 1], 2 * (H[:, 6:] @ S.T))


@pytest.mark.parametrize("grid, match", [([], "empty"), ([0.0, 1.0, 2.0], r"\[0\] = 0.0"),
                                         ([1.0, -2.0, 3.0], r"\[1\] = -2.0"), ([1.0, 1.0, 2.0], "increase")])
def test_bad_frequency_grid(grid, match):
    with pytest.raises(ValueError, match=match):
        check_frequencies(grid)
    with pytest.raises(ValueError, match=match):
        tb.a_bar(grid, np.ones(len(grid)), 100.0)


@pytest.mark.parametrize("alt", [-100.0, 60001.0, np.nan])
def test_altitude_outside_table(alt):
    with pytest.raises(ValueError, match="altitude_ft"):
        tb.reference_turbulence_intensity(alt)


def test_bad_speeds():
    with pytest.raises(ValueError, match="speed"):
        tb.turbulence_intensity(27.0, 0.9, 210.0, 150.0, 200.0)
    with pytest.raises(ValueError, match="V_C"):
        tb.turbulence_intensity(27.0, 0.9, 100.0, 200.0, 150.0)


def test_strip_model_static_limit_against_nonlinear_static_solve():
    """Strip model of a clamped beam: the response at omega -> 0 to a uniform gust equals the
    difference of two nonlinear static solves (1 g, and 1 g + the strip lift of a 0.01 m/s gust)."""
    from wingmdao.beam.static import cached_beam_system
    from wingmdao.loads.maneuver import maneuver_line_loads, strip_line_loads
    from wingmdao.loads.turbulence_analysis import strip_gust_model

    n, span, c, V, rho, W = 5, 10.0, 1.5, 100.0, 0.8, 5e4
    r0, th0 = straight_beam(n, span)
    bp = beam_parameters(r0, th0, EI_cc=5e6, GJ=2e6, EI_nn=5e7, EA=1e9, mass_per_length=20.0)
    chord, xb = np.full(n, c), np.full(n, 0.4)
    gm = strip_gust_model(bp, chord=chord, axis_fraction=xb, weight=W, airspeed=V, density=rho, semi_span=span)
    H = frequency_response(gm.model, [1e-6])
    s = cached_beam_system(n)
    ql = layout(s.forcing_specs)
    steady = maneuver_line_loads(r0, chord, xb, W, 1.0, semi_span=span)

    def static(w):
        f, m = strip_line_loads(r0, chord, xb, 0.5 * rho * V * chord * 2 * np.pi * w)
        q = np.zeros(s.n_forcing)
        q[ql["force_per_length"]] = (steady.force_per_length + f).ravel()
        q[ql["moment_per_length"]] = (steady.moment_per_length + m).ravel()
        q[ql["gravity"].start + 2] = -9.80665
        return solve_static(s, pack(s.param_specs, bp), q)[0].reshape(n, 18)

    x1, x0 = static(0.01), static(0.0)
    d_rbm = (x1[0, 9] - x0[0, 9]) / 0.01
    d_tip = (x1[-1, 2] - x0[-1, 2]) / 0.01
    assert abs(H.outputs["root_bending_moment"][0, 0] - d_rbm) < 1e-3 * abs(d_rbm)
    assert abs(H.outputs["tip_deflection"][0, 0] - d_tip) < 2e-3 * abs(d_tip)
    assert abs(H.outputs["root_bending_moment"][0, 0].imag) < 1e-6 * abs(d_rbm)


def test_cli_turbulence_bad_input(capsys, tmp_path):
    from wingmdao.cli import main

    for argv, flag in ((["--mach", "0.7"], "--mach"), (["--altitude-ft", "70000"], "--altitude-ft"),
                       (["--aero", "strip", "--plunge", "free"], "--plunge free"),
                       (["--f-max-hz", "0"], "--f-max-hz"), (["--grid-points", "2"], "--grid-points"),
                       (["--damping-ratio", "1"], "--damping-ratio"),
                       (["--damping-frequency-hz", "-1"], "--damping-frequency-hz")):
        assert main(["turbulence", "pegasus", "--no-plots", "--json", str(tmp_path / "t.json")] + argv) == 2
        assert flag in capsys.readouterr().err


@pytest.mark.slow
def test_cli_turbulence_pegasus_keys_and_consistency(tmp_path):
    """End to end (PEGASUS, coupled, free plunge): the JSON keys of the command, design loads
    P_1g +/- U_sigma A-bar, |rho| <= 1, and A-bar^2 = int PSD df of the written spectra within the
    stated quadrature error."""
    import json

    from wingmdao.cli import main

    out = tmp_path / "t.json"
    assert main(["turbulence", "pegasus", "--json", str(out), "--out", str(tmp_path)]) == 0
    r = json.loads(out.read_text())
    for key in ("altitude_m", "u_sigma_ref_m_s", "f_g", "u_sigma_m_s", "frequency_hz", "psd", "a_bar",
                "design_loads", "correlation", "quadrature"):
        assert key in r
    assert r["u_sigma_ref_m_s"] == pytest.approx((90 - 11 * 20000 / 24000) * FT)
    n = len(r["span_m"])
    for name in ("bending_moment", "torsion", "vertical_shear"):
        assert len(r["a_bar"][name]) == len(r["design_loads"][name]["up"]) == n
        np.testing.assert_allclose(np.subtract(r["design_loads"][name]["up"], r["design_loads"][name]["one_g"]),
                                   r["u_sigma_m_s"] * np.asarray(r["a_bar"][name]), rtol=1e-12)
    assert np.all(np.abs(r["correlation"]["bending_torsion"]) <= 1)
    f = np.asarray(r["frequency_hz"])
    for key in ("load_factor", "root_bending_moment"):
        integral = np.trapezoid(r["psd"][key], f)
        assert abs(np.sqrt(integral) / r["a_bar"][key] - 1) < 2 * r["quadrature"]["max_relative_error_a_bar"] + 1e-3
    for k in ("transfer", "psd", "envelope", "ellipse"):
        assert (tmp_path / f"pegasus_turbulence_{k}.png").exists()


def test_linear_model_uses_the_flutter_pencil():
    """The model's (A, E) are the flutter linearisation (stability.eigen.linearize) of the same state."""
    from wingmdao.stability.eigen import linearize

    s, p, q_trim, q0, r0, W = _trimmed_wing()
    x0, _ = solve_static(s, p, q_trim)
    model = linear_gust_model(s, p, q0, x0, x_stations=r0[:, 0], airspeed=40.0)
    A, E = linearize(s, p, q0, x0)
    assert abs(model.A - A).max() <= 1e-12 * abs(A).max()
    assert abs(model.E - E).max() <= 1e-12 * abs(E).max()


def test_turbulence_stress_ks_gradient_against_central_differences():
    """The complex-adjoint gradient of the KS of the 25.341(b) corner stresses (fixed grid) against
    central differences of the whole chain (trimmed static solve, linearisation, frequency response,
    A-bar, KS) w.r.t. stiffness, compliance, mass, body mass, chord, trim lift and the walls."""
    from wingmdao.stability.frequency import pencil_eigenvalues
    from wingmdao.stability.frequency_adjoint import StressMap, turbulence_stress_ks

    s, p, q_trim, q0, r0, W = _trimmed_wing()
    n = r0.shape[0]
    stress = StressMap(s.layout.beam, np.full(n, 0.5), np.full(n, 0.12), n_state=s.n_state)
    walls = np.tile([0.003, 0.0025, 0.004, 0.0035], (n, 1)) * np.linspace(1, 0.6, n)[:, None]
    x_le = r0[:, 0] - 0.35 + np.array([0.0, 0.3, 0.6, 0.9])
    grid = []

    def ks(p, walls, gradient=False):
        x0, _ = solve_static(s, p, q_trim)
        m = linear_gust_model(s, p, q0, x0, x_stations=x_le, airspeed=40.0)
        if not grid:
            grid.append(frequency_grid(pencil_eigenvalues(m), f_max=15.0, n_base=41, n_mode=8))
        return turbulence_stress_ks(s, p, q_trim, m, stress, walls, grid[0], u_sigma=10.0, sigma_allow=1e8,
                                    gradient=gradient)

    r = ks(p, walls, True)
    pl = layout(s.param_specs)
    for name, k in (("stiffness_csn", 0), ("stiffness_csn", 4), ("compliance_csn", 1), ("mass_per_length", 2),
                    ("body_mass", 0), ("chord", 1), ("trim_lift", 0)):
        i = pl[name].start + k
        # 1/EA = 1e-9 (its effect is small): a larger step against round-off
        h = (1e-1 if name == "compliance_csn" else 1e-6) * abs(p[i])
        pp, pm = p.copy(), p.copy()
        pp[i] += h
        pm[i] -= h
        fd = (ks(pp, walls).value - ks(pm, walls).value) / (2 * h)
        assert abs(r.d_p[i] - fd) <= (1e-4 if name == "compliance_csn" else 1e-5) * abs(fd), (name, k, r.d_p[i], fd)
    for i, j in ((0, 0), (1, 2), (3, 1)):
        h = 1e-7
        wp, wm = walls.copy(), walls.copy()
        wp[i, j] += h
        wm[i, j] -= h
        fd = (ks(p, wp).value - ks(p, wm).value) / (2 * h)
        assert abs(r.d_walls[i, j] - fd) <= 1e-5 * abs(r.d_walls).max(), (i, j, r.d_walls[i, j], fd)


def test_turbulence_stress_ks_component_partials():
    """TurbulenceStressKS: its declared partials (through compute_totals) against central
    differences of the component's output."""
    import openmdao.api as om

    from wingmdao.components.turbulence import TurbulenceStressKS
    from wingmdao.section.box import WALL_NAMES

    s, p, q_trim, q0, r0, W = _trimmed_wing()
    n = r0.shape[0]
    prob = om.Problem()
    comp = TurbulenceStressKS(num_nodes=n, plunge=True, airspeed=40.0, x_stations=r0[:, 0] - 0.35,
                              width=np.full(n, 0.5), height=np.full(n, 0.12), u_sigma=10.0, sigma_allow=1e8,
                              f_max=15.0, n_base=41)
    prob.model.add_subsystem("turb", comp, promotes=["*"])
    prob.setup(force_alloc_complex=False)
    values = s.split_parameters(p)
    for spec in s.param_specs:
        if spec.name != "airspeed":
            prob.set_val(spec.name, values[spec.name])
    for k, w in enumerate(WALL_NAMES):
        prob.set_val(w, np.array([0.003, 0.0025, 0.004, 0.0035])[k] * np.linspace(1, 0.6, n))
    prob.run_model()
    J = prob.compute_totals("turbulence_ks", [nm for nm in ("stiffness_csn", "node_euler_angles", "body_mass",
                                                            "density", "t_upper_skin", "t_rear_spar")])
    # central differences through the component, a few entries (OpenMDAO's check_partials over all
    # ~300 inputs takes minutes; its relative steps are zero on the zero jig angles)
    for name, k, h in (("stiffness_csn", 0, 1.0), ("node_euler_angles", 4, 1e-6), ("body_mass", 0, 1e-3),
                       ("density", 0, 1e-7), ("t_upper_skin", 1, 1e-8), ("t_rear_spar", 0, 1e-8)):
        base = prob.get_val(name).copy()
        vals = []
        for sign in (1, -1):
            v = base.copy()
            v.flat[k] += sign * h
            prob.set_val(name, v)
            prob.run_model()
            vals.append(float(prob.get_val("turbulence_ks")[0]))
        prob.set_val(name, base)
        fd = (vals[0] - vals[1]) / (2 * h)
        got = J["turbulence_ks", name].ravel()[k]
        assert abs(got - fd) <= 1e-5 * abs(fd) + 1e-9, (name, k, got, fd)


@pytest.mark.parametrize("aero_theory", ["strip", "vlm"])
def test_turbulence_stress_ks_totals_wrt_thicknesses_through_the_section_chain(aero_theory):
    """d KS / d wall thicknesses through BoxSection (stiffness, mass, offsets) into the component:
    OpenMDAO check_totals (central differences) on a 4-node aluminium box wing, free in plunge, 2 %
    structural damping (undamped, the in-plane mode's peak moves across the held grid and the
    differences see its curvature); strip theory and the vortex lattice."""
    from wingmdao.aero.system import three_dimensional_parameters
    from wingmdao.beam.residual import StrainRateDamping
    import openmdao.api as om

    from wingmdao.components.section import BoxSection
    from wingmdao.components.turbulence import TurbulenceStressKS
    from wingmdao.groups.wing import add_section_offsets
    from wingmdao.materials import ALUMINIUM
    from wingmdao.section.box import WALL_NAMES

    s, p, q_trim, q0, r0, W = _trimmed_wing()
    n = r0.shape[0]
    width, height = np.full(n, 0.5), np.full(n, 0.12)
    prob = om.Problem()
    m = prob.model
    m.add_subsystem("section", BoxSection(num_stations=n, material=ALUMINIUM), promotes_inputs=["*"],
                    promotes_outputs=["*"])
    add_section_offsets(m, n, promotes_outputs=["*"])
    m.add_subsystem("turb", TurbulenceStressKS(num_nodes=n, plunge=True, airspeed=40.0, x_stations=r0[:, 0] - 0.35,
                                               width=width, height=height, u_sigma=10.0, sigma_allow=1e8,
                                               f_max=15.0, n_base=41, aero_theory=aero_theory,
                                               damping=StrainRateDamping.from_damping_ratio(0.02, 2.0)),
                    promotes_inputs=["*"])
    for w in WALL_NAMES:
        m.set_input_defaults(w, val=0.003 * np.linspace(1, 0.6, n), units="m")
    m.set_input_defaults("width", val=width, units="m")
    m.set_input_defaults("height", val=height, units="m")
    prob.setup()
    values = s.split_parameters(p)
    for name in ("node_positions", "node_euler_angles", "chord", "ref_point", "lift_slope", "alpha_zero_lift", "cm0",
                 "density", "mach", "trim_lift"):
        prob.set_val(name, values[name])
    if aero_theory == "vlm":
        for name, v in three_dimensional_parameters("vlm", r0, np.ones(n), np.full(n, 0.35), 0.0).items():
            prob.set_val(name, v)
    prob.set_val("body_mass", 200.0)
    prob.run_model()
    data = prob.check_totals(of=["turb.turbulence_ks"], wrt=list(WALL_NAMES), method="fd", form="central", step=1e-6,
                             out_stream=None)
    for key, d in data.items():
        exact, fd = np.asarray(d["J_fwd"] if "J_fwd" in d else d["J_rev"]), np.asarray(d["J_fd"])
        assert np.max(np.abs(exact - fd)) <= 1e-4 * np.max(np.abs(exact)), (key, exact, fd)


@pytest.mark.slow
def test_size_pegasus_turbulence_constraint_analysis(tmp_path):
    """`size pegasus --turbulence --analysis-only`: the result has turbulence_ks, equal to the
    component's value computed outside the sizing group on the same design."""
    import json

    from wingmdao.cli import main

    out = tmp_path / "s.json"
    assert main(["size", "pegasus", "--analysis-only", "--turbulence", "--no-plots", "--quiet", "--out", str(tmp_path),
                 "--json", str(out)]) == 0
    r = json.loads(out.read_text())
    import openmdao.api as om

    from wingmdao.cases import pegasus
    from wingmdao.components.turbulence import TurbulenceStressKS
    from wingmdao.loads.turbulence_analysis import sizing_turbulence_options
    from wingmdao.sizing import SECTION_KINDS, WALL_VARS, design_beam_params, initial_design, station_design

    setup = pegasus.build()
    geo = setup.geometry
    damping = pegasus.gust_damping(0.02, None, geo, setup.options)[0]
    design = initial_design(setup.options, SECTION_KINDS["box"]["design_vars"])
    bp = design_beam_params(geo, setup.material, design, "box")
    walls = station_design(geo, design, WALL_VARS)
    prob = om.Problem()
    prob.model.add_subsystem("t", TurbulenceStressKS(num_nodes=geo.num_nodes,
                                                     **sizing_turbulence_options(pegasus, setup, damping=damping)),
                             promotes=["*"])
    prob.setup()
    for name, v in {**bp, **walls}.items():
        if name in ("node_positions", "node_euler_angles", "stiffness_csn", "compliance_csn", "tension_axis",
                    "shear_center", "mass_per_length", "mass_center", "inertia_per_length", *WALL_VARS):
            prob.set_val(name, v)
    prob.run_model()
    assert r["turbulence_ks"] == pytest.approx(float(prob.get_val("turbulence_ks")[0]), rel=1e-8)
    # the envelope's 25.341(b) loads (potato-plot ellipses) of the constraint's model against the
    # `wingmdao turbulence` command on the same design (its own beam and aerodynamic set-up)
    tl = r["turbulence_loads"]
    cmd = tmp_path / "t.json"
    assert main(["turbulence", "pegasus", "--clamped", "--aero-theory", "strip", "--damping-ratio", "0.02",
                 "--f-max-hz", "20", "--no-plots", "--json", str(cmd)]) == 0  # the constraint's strip theory
    t = json.loads(cmd.read_text())
    assert tl["u_sigma_m_s"] == pytest.approx(t["u_sigma_m_s"], rel=1e-12)
    for key in ("bending_moment", "torsion"):
        np.testing.assert_allclose(tl[key]["a_bar"], t["a_bar"][key], rtol=1e-6, atol=1e-6 * max(t["a_bar"][key]))
        np.testing.assert_allclose(tl[key]["one_g"], t["design_loads"][key]["one_g"], rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(tl["bending_torsion_correlation"], t["correlation"]["bending_torsion"], atol=1e-6)
    # the pointwise corner ratios under the constraint's KS: max g <= KS <= max g + ln(count) / rho
    g_max = max(tl["stress_ratio"]) - 1.0
    assert g_max <= r["turbulence_ks"] <= g_max + np.log(2 * 4 * len(tl["stress_ratio"])) / 50.0


def test_size_turbulence_bad_case(capsys):
    from wingmdao.cli import main

    assert main(["size", "cantilever", "--analysis-only", "--turbulence", "--no-plots"]) == 2
    assert "--turbulence" in capsys.readouterr().err


def test_case_beam_parameters_public_helper(tmp_path, capsys):
    """wingmdao.cases.case_beam_parameters (used by `gust` and `turbulence`): the initial design's
    walls given per node reproduce its beam parameters; a design with the wrong number of stations
    is a one-line error naming --design, before any solve, in both commands."""
    import json

    from wingmdao.cases import case_beam_parameters, pegasus
    from wingmdao.cli import main
    from wingmdao.sizing import SECTION_KINDS, WALL_VARS, initial_design, station_design

    setup, bp = case_beam_parameters(pegasus)
    dv = station_design(setup.geometry, initial_design(setup.options, SECTION_KINDS["box"]["design_vars"]), WALL_VARS)
    _, bp2 = case_beam_parameters(pegasus, {w[2:]: dv[w] for w in WALL_VARS})
    for k in bp:
        np.testing.assert_array_equal(bp[k], bp2[k])
    bad = tmp_path / "d.json"
    bad.write_text(json.dumps({"case": "pegasus", "thickness": {w[2:]: [0.01, 0.01] for w in WALL_VARS}}))
    for cmd in ("turbulence", "gust"):
        assert main([cmd, "pegasus", "--design", str(bad), "--no-plots", "--json", str(tmp_path / f"{cmd}.json")]) == 2
        err = capsys.readouterr().err
        assert f"--design {bad}" in err and "has 2 stations" in err and len(err.strip().splitlines()) == 1, err


@pytest.mark.slow
def test_a_bar_against_time_march_under_synthesized_turbulence():
    """A-bar against a Monte Carlo time march: the trimmed flexible wing free in plunge (4 nodes,
    V = 40 m/s, stations meeting the gust 0, 1, 2, 3 steps apart) marched by BDF2 (dt = 0.02 s,
    600 s, 30,000 steps) under vertical turbulence of U_sigma = 0.5 m/s synthesized through the
    rational von Karman filter of MIL-HDBK-1797 (loads.turbulence.von_karman_filter, sampled exactly:
    synthesize_vertical_turbulence). The RMS of the incremental root bending moment and load factor
    (the lift linearised about the 1 g state, checked against the march's own lift integral) over
    the 590 s after a 10 s transient
    equals U_sigma A-bar of the frequency-domain analysis (loads.turbulence.a_bar, von Karman) within
    three standard deviations of the estimate (99.7 % for a normal estimator) plus the computed
    deterministic differences (the filter's fit of the spectrum, the BDF2 time step).

    The scale is L = 10 m (T = L / V = 0.25 s): the filter follows the von Karman spectrum within
    4.6 % for omega T <= 20, so over the wing's whole response band (at L = 2,500 ft its omega^-2 tail
    would leave A-bar of the load factor 20 % low). Statistical error: for a Gaussian output of
    one-sided PSD Phi_y (per rad/s) and a record of length T_r, Var(sigma_hat^2) = (2 / T_r) int R^2 d tau
    = 2 pi int_0^inf Phi_y^2 d omega / T_r (Isserlis; Bendat & Piersol, "Random Data", 4th ed., 2010,
    Ch. 8: the normalised error 1 / sqrt(B_s T_r) of a mean-square estimate), so the RMS has the
    relative standard deviation eps = 1 / sqrt(2 N), N = T_r sigma_y^4 / (pi int Phi_y^2 d omega) the
    number of independent samples, computed here from the filter-spectrum output PSD (1792 for the
    root bending moment, 2411 for the load factor: eps = 1.7 %, 1.4 %). The time step's effect
    (omega dt = 0.38 at 3 Hz) is computed, not bounded: the linear response with i omega replaced by
    the BDF2 symbol (3 - 4/z + 1/z^2) / (2 dt), z = exp(i omega dt), up to the Nyquist frequency."""
    from wingmdao.stability.frequency import ShiftedFactors, pencil_eigenvalues
    from wingmdao.timemarch.bdf import state_rates

    s, p, q_trim, q0, r0, W = _trimmed_wing()
    x0, _ = solve_static(s, p, q_trim)
    V, L, U, dt, t_record, t_skip = 40.0, 10.0, 0.5, 0.02, 600.0, 10.0
    delay = np.array([0, 1, 2, 3])  # steps: the stations meet the gust V dt = 0.4 m apart
    x_le = r0[:, 0] - 0.35 + V * dt * delay
    model = linear_gust_model(s, p, q0, x0, x_stations=x_le, airspeed=V,
                              outputs=aeroelastic_outputs(s, p, q0, x0, weight=W))
    n = int(round(t_record / dt)) + 1
    gust = tb.synthesize_vertical_turbulence(n + delay.max(), dt, V, U, L, rng=np.random.default_rng(1))
    ql = layout(s.forcing_specs)
    Q = np.tile(q0, (n, 1))
    Q[:, ql["gust_velocity"]] = gust[delay.max() + np.arange(n)[:, None] - delay[None, :]]
    Q[0] = q_trim  # step 0: the trimmed 1 g state, gust off
    t = np.arange(n) * dt
    h = march(s, t, p, Q, modified_newton=True)
    keep = t >= t_skip
    beam = s.layout.beam_states(h.states)
    i_m = s.layout.beam[0, 9]
    # the load factor: the lift of both halves linearised about the 1 g state (the model's output map,
    # applied to the march's states, rates and gusts), checked on 500 instants against the march's
    # own (nonlinear) lift integral: the section-lift function costs 0.3 ms an instant
    rates = state_rates(h.states, dt)
    lf = model.outputs["load_factor"]
    gq = Q[:, ql["gust_velocity"]]
    n_z = (lf.Cx @ (h.states - x0).T + lf.Cv @ rates.T + lf.D @ gq.T)[0]
    sub = np.flatnonzero(keep)[::59]
    lift, _ = s._loads.expand().map(sub.size)(h.states[sub].T, rates[sub].T, p, Q[sub].T)
    lift = np.asarray(lift).T
    ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
    own = 2.0 * np.sum(0.5 * (lift[:, 1:] + lift[:, :-1]) * ds, axis=1) / W - lf.y0[0]
    assert np.max(np.abs(own - n_z[sub])) <= 0.01 * np.sqrt(np.mean(n_z[keep] ** 2)), np.max(np.abs(own - n_z[sub]))
    marched = {"root_bending_moment": (beam[keep, 0, 9] - x0[i_m], t_record - t_skip),
               "load_factor": (n_z[keep], t_record - t_skip)}
    # the frequency-domain analysis, and the filter's and the time step's deterministic differences
    w = frequency_grid(pencil_eigenvalues(model), f_min=1e-4, f_max=200.0, n_base=401)
    H = frequency_response(model, w).outputs
    num, den = tb.von_karman_filter(V, 1.0, L)
    filt = np.abs(np.polyval(num, 1j * w) / np.polyval(den, 1j * w)) ** 2
    band = w < np.pi / dt
    z = np.exp(1j * w[band] * dt)
    bdf2 = (3 - 4 / z + 1 / z ** 2) / (2 * dt)  # the march's symbol of d/dt
    factors = ShiftedFactors(model.A, model.E)
    gv = model.gust_vector(w[band])
    Xb = np.array([factors.factor(sh).solve(-(model.G @ g)) for sh, g in zip(bdf2, gv)])
    for name, (y, length) in marched.items():
        a_vk = float(tb.a_bar(w, H[name][:, 0], V, scale_m=L).value)
        phi = np.abs(H[name][:, 0]) ** 2 * filt
        a_filter = np.sqrt(spectral_integral(w, phi).value)
        m = model.outputs[name]
        Hb = (m.Cx @ Xb.T + bdf2 * (m.Cv @ Xb.T) + m.D @ gv.T)[0]
        step_ratio = np.sqrt(np.trapezoid(np.abs(Hb) ** 2 * filt[band], w[band])
                             / np.trapezoid(phi[band], w[band]))
        a_march = a_filter * step_ratio  # what the march should give, but for the sampling error
        independent = length * a_filter ** 4 / (np.pi * spectral_integral(w, phi ** 2).value)
        eps = 1.0 / np.sqrt(2.0 * independent)
        rms = np.sqrt(np.mean(y ** 2)) / U
        print(f"{name}: RMS / U_sigma {rms:.5g}, A-bar {a_vk:.5g} (von Karman), {a_march:.5g} (filter, BDF2), "
              f"N = {independent:.0f}, eps = {eps:.4f}, deviation {(rms / a_march - 1) / eps:+.2f} eps")
        assert abs(rms - a_march) <= 3 * eps * a_march, (name, rms, a_march, eps)
        assert abs(rms - a_vk) <= 3 * eps * a_vk + abs(a_march - a_vk), (name, rms, a_vk, a_march, eps)


def test_rational_von_karman_filter_fit_and_synthesized_variance():
    """The MIL-HDBK-1797 forming filter against the 25.341(b)(2) spectrum: |H|^2 within 1.5 % of it for
    omega T <= 2 and 4.6 % for omega T <= 20 (T = L / V), its variance 0.9623 sigma^2 (quad); the
    exactly sampled synthesis has that variance within 3 standard deviations of the estimate
    (100,000 samples at dt = T / 25, N independent samples from the filter's spectrum as in the
    Monte Carlo test above); bad input is a one-line error."""
    V, L, sigma = 50.0, 25.0, 2.0
    T = L / V
    num, den = tb.von_karman_filter(V, sigma, L)
    for top, tol in ((2.0, 0.015), (20.0, 0.046)):
        w = np.geomspace(1e-3, top, 200) / T
        ratio = np.abs(np.polyval(num, 1j * w) / np.polyval(den, 1j * w)) ** 2 / tb.von_karman_psd(w, V, sigma, L)
        assert np.max(np.abs(ratio - 1)) <= tol, (top, ratio.min(), ratio.max())
    phi = lambda u: abs(np.polyval(num, 1j * np.exp(u)) / np.polyval(den, 1j * np.exp(u))) ** 2 * np.exp(u)
    var, _ = quad(phi, -30, 30, limit=400, epsrel=1e-10)
    assert var / sigma ** 2 == pytest.approx(0.9623, abs=1e-4)
    phi2, _ = quad(lambda u: phi(u) ** 2 / np.exp(u), -30, 30, limit=400, epsrel=1e-10)
    dt, n = T / 25, 100_000
    g = tb.synthesize_vertical_turbulence(n, dt, V, sigma, L, rng=np.random.default_rng(3))
    eps = np.sqrt(2 * np.pi * phi2 / (n * dt)) / var  # relative standard deviation of the variance estimate
    assert abs(np.mean(g ** 2) / var - 1) <= 3 * eps, (np.mean(g ** 2) / var, eps)
    with pytest.raises(ValueError, match="dt = -1"):
        tb.synthesize_vertical_turbulence(10, -1.0, V)
    with pytest.raises(ValueError, match="scale_m"):
        tb.von_karman_filter(V, scale_m=0.0)


def _stress_ks_problem(n_base=41, f_max=15.0, **options):
    """TurbulenceStressKS on the trimmed 4-node wing (free plunge, 2 % structural damping, stations
    meeting the gust 0.3 m apart), set to the wing's parameters; ``options`` of the component."""
    import openmdao.api as om

    from wingmdao.beam.residual import StrainRateDamping
    from wingmdao.components.turbulence import TurbulenceStressKS
    from wingmdao.section.box import WALL_NAMES

    s, p, q_trim, q0, r0, W = _trimmed_wing()
    n = r0.shape[0]
    prob = om.Problem()
    comp = TurbulenceStressKS(num_nodes=n, plunge=True, airspeed=40.0,
                              x_stations=r0[:, 0] - 0.35 + np.array([0.0, 0.3, 0.6, 0.9]), width=np.full(n, 0.5),
                              height=np.full(n, 0.12), u_sigma=10.0, sigma_allow=1e8, f_max=f_max, n_base=n_base,
                              damping=StrainRateDamping.from_damping_ratio(0.02, 2.0), gravity=9.81, **options)
    prob.model.add_subsystem("turb", comp, promotes=["*"])
    prob.setup()
    values = s.split_parameters(p)
    inputs = {nm for nm, _ in comp.list_inputs(out_stream=None)}
    for name, v in values.items():
        if name in inputs:
            prob.set_val(name, v)
    if "aircraft_mass" in inputs:
        prob.set_val("aircraft_mass", 300.0)  # as _trimmed_wing: trim_lift = 300 g, body_mass = 300 - 2 m_half
    for k, w in enumerate(WALL_NAMES):
        prob.set_val(w, np.array([0.003, 0.0025, 0.004, 0.0035])[k] * np.linspace(1, 0.6, n))
    prob.run_model()
    return prob, comp


def test_turbulence_stress_ks_airspeed_and_aircraft_mass_gradients():
    """d KS / d airspeed (aerodynamics, gust phases, von Karman spectrum; at fixed Mach and density)
    and d KS / d aircraft mass (trim lift M g, body mass M - 2 m_half) of TurbulenceStressKS with
    airspeed_input and aircraft_mass_input, against central differences of its output (within
    1e-6); with the masses as the default inputs the same KS as with body_mass and trim_lift set from
    M; and the airspeed derivative of the von Karman spectrum against central differences."""
    prob, comp = _stress_ks_problem(airspeed_input=True, aircraft_mass_input=True)
    J = prob.compute_totals("turbulence_ks", ["airspeed", "aircraft_mass"])
    for name, h in (("airspeed", 1e-4), ("aircraft_mass", 1e-3)):
        base = prob.get_val(name).copy()
        vals = []
        for sign in (1, -1):
            prob.set_val(name, base + sign * h)
            prob.run_model()
            vals.append(float(prob.get_val("turbulence_ks")[0]))
        prob.set_val(name, base)
        fd = (vals[0] - vals[1]) / (2 * h)
        got = float(J["turbulence_ks", name][0, 0])
        assert abs(got - fd) <= 1e-6 * abs(fd), (name, got, fd)
    prob.run_model()
    ks_mass = float(prob.get_val("turbulence_ks")[0])
    # the same aircraft through the default inputs (body_mass, trim_lift) of _trimmed_wing
    prob2, _ = _stress_ks_problem()
    assert float(prob2.get_val("turbulence_ks")[0]) == pytest.approx(ks_mass, rel=1e-10)
    w = np.geomspace(1e-3, 100.0, 50)
    d = tb.von_karman_psd_airspeed_derivative(w, 60.0, 2.0, 100.0)
    fd = (tb.von_karman_psd(w, 60.0 + 1e-4, 2.0, 100.0) - tb.von_karman_psd(w, 60.0 - 1e-4, 2.0, 100.0)) / 2e-4
    np.testing.assert_allclose(d, fd, rtol=1e-7, atol=1e-12 * np.max(np.abs(fd)))


@pytest.mark.slow
def test_turbulence_stress_ks_check_partials_every_input():
    """OpenMDAO check_partials of TurbulenceStressKS over every input (airspeed and aircraft mass
    inputs on; 176 scalars, central differences), each with a step its scale needs: relative to
    each element (1e-6, at least 1e-6 absolute for the zero jig angles and offsets; the walls
    without that floor), the stiffness
    relative to its mean (its zero couplings), the rotary inertia 1e-3 kg m absolute (all zero),
    the compliance 1e-12 absolute (its shear entries are 1e-15: a relative step is lost in the
    round-off of the static solve). Every subjacobian within 1e-6 of its norm, the compliance
    within 2e-5 (its entries move KS by less than 1e-11 per 1e-12 step: differences resolve them
    to about 5e-4 each); with the default inputs the body_mass and trim_lift partials likewise."""
    from wingmdao.section.box import WALL_NAMES

    prob, comp = _stress_ks_problem(n_base=31, f_max=10.0, airspeed_input=True, aircraft_mass_input=True)
    special = ("stiffness_csn", "compliance_csn", "inertia_per_length") + tuple(WALL_NAMES)
    comp.set_check_partial_options(wrt=[nm for nm, _ in comp.list_inputs(out_stream=None) if nm not in special],
                                   method="fd", form="central", step=1e-6, step_calc="rel_element", minimum_step=1e-6)
    comp.set_check_partial_options(wrt=list(WALL_NAMES), method="fd", form="central", step=1e-6,
                                   step_calc="rel_element")
    comp.set_check_partial_options(wrt="stiffness_csn", method="fd", form="central", step=1e-6, step_calc="rel_avg")
    comp.set_check_partial_options(wrt="compliance_csn", method="fd", form="central", step=1e-12, step_calc="abs")
    comp.set_check_partial_options(wrt="inertia_per_length", method="fd", form="central", step=1e-3, step_calc="abs")
    data = prob.check_partials(out_stream=None, compact_print=True)["turb"]
    assert len(data) == len(list(comp.list_inputs(out_stream=None)))
    for (_of, wrt), d in data.items():
        exact, fd = np.asarray(d["J_fwd"]), np.asarray(d["J_fd"])
        tol = 2e-5 if wrt == "compliance_csn" else 1e-6
        assert np.linalg.norm(exact - fd) <= tol * np.linalg.norm(exact) + 1e-14, (wrt, exact, fd)
    prob, comp = _stress_ks_problem(n_base=31, f_max=10.0)
    comp.set_check_partial_options(wrt=["body_mass", "trim_lift"], method="fd", form="central", step=1e-6,
                                   step_calc="rel_element")
    data = prob.check_partials(out_stream=None, compact_print=True, includes=["turb"])["turb"]
    for (_of, wrt), d in data.items():
        if wrt in ("body_mass", "trim_lift"):
            exact, fd = np.asarray(d["J_fwd"]), np.asarray(d["J_fd"])
            assert np.linalg.norm(exact - fd) <= 1e-6 * np.linalg.norm(exact), (wrt, exact, fd)


def test_free_pitch_frequency_response_equals_time_march_amplitude():
    """Plunge + pitch (wingmdao.aero.pitch: horizontal tail 4 m aft of the CG, downwash 0.3) of the
    flexible 4-node wing: the frequency response (the tail a gust station of its own at tail_x, the
    load factor (wing + tail lift) / W) against the BDF2 march of the same residual under a harmonic
    gust at 2 Hz reaching each wing station and the tail with its delay (dt = 2 ms, 3 s from the
    trimmed 1 g state): the steady amplitude and phase of the root bending moment, load factor
    (the march's own wing and tail lift), tip deflection and pitch rate within 1e-3 of the linear
    response with i omega replaced by the BDF2 symbol, and within 5e-3 of |H|."""
    from wingmdao.aero.pitch import pitch_parameters

    n, V, g, mass = 4, 40.0, 9.81, 300.0
    r0, th0 = straight_beam(n, 8.0)
    bp = beam_parameters(r0, th0, EI_cc=2e5, GJ=1e5, EI_nn=1e7, EA=1e9, mass_per_length=5.0)
    ap = aero_parameters(n, chord=1.0, ref_point=0.35, airspeed=V, density=1.0)
    s = cached_aeroelastic_system(n, plunge=True, trim=True, pitch=True)
    par = {**bp, **ap, "trim_lift": mass * g}
    par.update(pitch_parameters(aircraft_mass=mass, cg=(0.05, 0.0), aircraft_pitch_inertia=400.0, tail_arm=4.0,
                                tail_area=2.0, tail_lift_slope=4.0, downwash_gradient=0.3,
                                mass_per_length=bp["mass_per_length"], node_positions=r0))
    p = pack(s.param_specs, par)
    qd = beam_forcing(n, gravity=[0, 0, -g])
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3),
              trim_active=1.0, tail_gust_velocity=0.0)
    q_trim = pack(s.forcing_specs, qd)
    q0 = pack(s.forcing_specs, {**qd, "trim_active": 0.0})
    x0, _ = solve_static(s, p, q_trim)
    x_le = r0[:, 0] - 0.35 + np.array([0.0, 0.3, 0.6, 0.9])
    W = mass * g
    out = aeroelastic_outputs(s, p, q0, x0, weight=W)
    i_q = s.body_index["pitch_rate"]
    out["pitch_rate"] = state_output(i_q, 0.0, s.n_state, n + 1)
    model = linear_gust_model(s, p, q0, x0, x_stations=x_le, airspeed=V, outputs=out)
    x_t = par["tail_x"]
    assert model.x_stations.size == n + 1 and model.x_stations[-1] == x_t
    om, U, dt = 2 * np.pi * 2.0, 0.01, 2e-3
    t = np.arange(int(3.0 / dt) + 1) * dt
    ql = layout(s.forcing_specs)
    Q = np.tile(q0, (t.size, 1))
    Q[0] = q_trim
    lag = (model.x_stations - model.x_stations.min()) / V
    ramp = np.minimum(t / 0.2, 1.0)[:, None]
    gusts = U * ramp * np.sin(om * (t[:, None] - lag[None, :]))
    Q[:, ql["gust_velocity"]] = gusts[:, :n]
    Q[:, ql["tail_gust_velocity"].start] = gusts[:, n]
    h = march(s, t, p, Q)
    beam = s.layout.beam_states(h.states)
    lift = s.total_lift_history(h.states, dt, p, Q) + s.tail_lift_history(h.states, dt, p, Q)
    series = {"root_bending_moment": beam[:, 0, 9], "tip_deflection": beam[:, -1, 2], "load_factor": lift / W,
              "pitch_rate": h.states[:, i_q]}
    last = t >= 2.0
    lam = eigenmodes(s, p, q0, x0, static=False).eigenvalues
    slow = lam[(lam.real < -0.1) & (lam.real > -12) & (np.abs(lam.imag) < 15)]  # Wagner lags, short period
    for name, (marched, discrete, expected) in _march_against_response(model, series, t, last, om, U, dt,
                                                                       slow).items():
        assert abs(marched - discrete) <= 1e-3 * abs(discrete), (name, marched, discrete)
        assert abs(marched - expected) <= 5e-3 * abs(expected), (name, marched, expected)


def _pitch_plunge_reference(omega, *, V, rho, c, semi_span, mass, x_cg, i_yy, tail_x, tail_area, tail_slope,
                            downwash, tail_delay, a=2 * np.pi, g=9.81):
    """Closed-form load-factor transfer function (per m/s of gust) of a rigid aircraft free in plunge
    and pitch: a straight strip wing of chord c (quarter chord at the body-axes origin O) with
    Jones' Wagner C and the Sears-Sparks Kuessner S (as _plunge_reference), the circulatory lift at
    the quarter chord from the angle at the three-quarter chord, the apparent-mass lift
    pi rho b^2 (V q - d/dt (w_p - q x_mid)) at the midchord, and a quasi-steady tail (Etkin & Reid,
    1996, Sec. 2.4: alpha_t = theta - w_p / V + q x_t / V + w_gt / V - deps/dalpha (theta - w_p / V +
    w_g / V)), its gust delayed by ``tail_delay``. Rigid-body rows about O (x aft, z up):
    M dw_p/dt - S_x dq/dt = L_w + L_t,  I_O dq/dt - S_x dw_p/dt = -x_mid L_nc - x_t L_t."""
    b, q_d, span = c / 2, 0.5 * rho * V ** 2, 2 * semi_span
    s = 1j * np.asarray(omega, dtype=complex)
    ik = s * b / V
    C = 1 - 0.165 * ik / (ik + 0.0455) - 0.335 * ik / (ik + 0.3)
    S = 1 - 0.5 * ik / (ik + 0.13) - 0.5 * ik / (ik + 1.0)
    x34, xmid, S_x, I_O = c / 2, c / 4, mass * x_cg, i_yy + mass * x_cg ** 2
    k_nc, k_w, k_t = np.pi * rho * b ** 2 * span, q_d * span * c * a, q_d * tail_area * tail_slope
    wgt = np.exp(-s * tail_delay)
    # lifts = (coefficient of W_p, of Theta, gust part)
    nc = (-k_nc * s, k_nc * (V * s + s * s * xmid))
    wing = (-k_w * C / V + nc[0], k_w * C * (1 + s * x34 / V) + nc[1], k_w * S / V)
    tail = (k_t * (downwash - 1) / V, k_t * (1 + s * tail_x / V - downwash), k_t * (wgt - downwash) / V)
    a11, a12 = mass * s - wing[0] - tail[0], -S_x * s * s - wing[1] - tail[1]
    a21, a22 = -S_x * s + xmid * nc[0] + tail_x * tail[0], I_O * s * s + xmid * nc[1] + tail_x * tail[1]
    r1, r2 = wing[2] + tail[2], -tail_x * tail[2]
    det = a11 * a22 - a12 * a21
    Wp, Th = (r1 * a22 - a12 * r2) / det, (a11 * r2 - a21 * r1) / det
    return (wing[0] * Wp + wing[1] * Th + wing[2] + tail[0] * Wp + tail[1] * Th + tail[2]) / (mass * g)


def test_a_bar_rigid_plunge_pitch_against_closed_form_quadrature():
    """A-bar of the load factor of a rigid aircraft free in plunge and pitch (a very stiff, 0.1 m chord
    strip wing of 50 m span, 510 kg, I_yy 600 kg m^2, CG 0.05 m aft, tail 4 m aft of the CG, 1.2 m^2,
    a_t 4, deps/dalpha 0.3, V = 60 m/s) against quad of _pitch_plunge_reference: within 1e-3
    (measured 3.8e-4), |H| within 3e-3 at five frequencies. Not in the closed form, hence the
    tolerance: the wing's apparent-mass pitching moment about its midchord (order b^3), the
    rotation of the 1 g lift and of gravity with the pitch attitude in the linearisation."""
    from wingmdao.aero.pitch import pitch_parameters
    from wingmdao.stability.frequency import pencil_eigenvalues

    n, semi, c, V, rho, ref = 5, 25.0, 0.1, 60.0, 1.2, 0.25
    mass, iyy, arm, slope, area, eps, x_cg, g = 510.0, 600.0, 4.0, 4.0, 1.2, 0.3, 0.05, 9.81
    r0, th0 = straight_beam(n, semi)
    bp = beam_parameters(r0, th0, EI_cc=1e12, GJ=1e12, EI_nn=1e13, EA=1e14, mass_per_length=0.1)
    ap = aero_parameters(n, chord=c, ref_point=ref, airspeed=V, density=rho)
    s = cached_aeroelastic_system(n, plunge=True, trim=True, pitch=True)
    par = {**bp, **ap, "trim_lift": mass * g}
    par.update(pitch_parameters(aircraft_mass=mass, cg=(x_cg, 0.0), aircraft_pitch_inertia=iyy, tail_arm=arm,
                                tail_area=area, tail_lift_slope=slope, downwash_gradient=eps,
                                mass_per_length=bp["mass_per_length"], node_positions=r0))
    p = pack(s.param_specs, par)
    qd = beam_forcing(n, gravity=[0, 0, -g])
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3),
              trim_active=1.0, tail_gust_velocity=0.0)
    x0, _ = solve_static(s, p, pack(s.forcing_specs, qd))
    q0 = pack(s.forcing_specs, {**qd, "trim_active": 0.0})
    x_le = r0[:, 0] - ref * c
    model = linear_gust_model(s, p, q0, x0, x_stations=x_le, airspeed=V,
                              outputs=aeroelastic_outputs(s, p, q0, x0, weight=mass * g))
    w = frequency_grid(pencil_eigenvalues(model), f_min=1e-4, f_max=400.0, n_base=601)
    ab = tb.a_bar(w, frequency_response(model, w).outputs["load_factor"][:, 0], V)
    kw = dict(V=V, rho=rho, c=c, semi_span=semi, mass=mass, x_cg=x_cg, i_yy=iyy, tail_x=par["tail_x"],
              tail_area=area, tail_slope=slope, downwash=eps, tail_delay=(par["tail_x"] - x_le[0]) / V)
    ref2, _ = quad(lambda u: abs(_pitch_plunge_reference(np.exp(u), **kw)) ** 2 * _von_karman(np.exp(u), V) * np.exp(u),
                   -12, 12, limit=800, epsrel=1e-10)
    got = float(ab.value)
    assert abs(got / np.sqrt(ref2) - 1) <= 1e-3, (got, np.sqrt(ref2))
    om = np.array([0.5, 3.0, 10.0, 50.0, 300.0])
    H = frequency_response(model, om).outputs["load_factor"][:, 0]
    np.testing.assert_allclose(H, _pitch_plunge_reference(om, **kw), rtol=3e-3)


def test_controllable_canonical_form_matches_scipy_tf2ss():
    """The state-space form of the von Karman filter (and of other strictly proper transfer
    functions) equals scipy.signal.tf2ss's; an improper one is refused."""
    import scipy.signal as ss

    from wingmdao.loads.turbulence import controllable_canonical_form, von_karman_filter

    for num, den in (von_karman_filter(100.0, 1.0, 762.0), ([2.0, 3.0], [4.0, 1.0, 5.0, 7.0]), ([5.0], [2.0, 1.0])):
        A, B, C = controllable_canonical_form(num, den)
        A2, B2, C2, D2 = ss.tf2ss(num, den)
        np.testing.assert_allclose(A, A2, rtol=1e-14)
        np.testing.assert_allclose(B, B2, rtol=1e-14)
        np.testing.assert_allclose(C, C2, rtol=1e-14)
        assert np.all(D2 == 0)
    with pytest.raises(ValueError, match="strictly proper"):
        controllable_canonical_form([1.0, 2.0], [1.0, 3.0])


def test_turbulence_stress_ks_vortex_lattice_partials():
    """TurbulenceStressKS with ``aero_theory="vlm"`` (the beam's quasi-steady lift from the vortex
    lattice's influence matrices, inputs): its declared partials (through compute_totals) against
    central differences of the component's output, a few entries, the influence included; and its
    KS differs from strip theory's on the same wing (the lattice's lower lift)."""
    import openmdao.api as om

    from wingmdao.aero.system import three_dimensional_parameters
    from wingmdao.components.turbulence import TurbulenceStressKS
    from wingmdao.section.box import WALL_NAMES

    s, p, q_trim, q0, r0, W = _trimmed_wing()
    n = r0.shape[0]
    values = s.split_parameters(p)
    values.update(three_dimensional_parameters("vlm", r0, np.ones(n), np.full(n, 0.35), 0.0))
    ks = {}
    for theory in ("vlm", "strip"):
        prob = om.Problem()
        comp = TurbulenceStressKS(num_nodes=n, plunge=True, airspeed=40.0, x_stations=r0[:, 0] - 0.35,
                                  width=np.full(n, 0.5), height=np.full(n, 0.12), u_sigma=10.0, sigma_allow=1e8,
                                  f_max=15.0, n_base=41, aero_theory=theory)
        prob.model.add_subsystem("turb", comp, promotes=["*"])
        prob.setup(force_alloc_complex=False)
        for spec in comp.specs:
            prob.set_val(spec.name, values[spec.name])
        for k, w in enumerate(WALL_NAMES):
            prob.set_val(w, np.array([0.003, 0.0025, 0.004, 0.0035])[k] * np.linspace(1, 0.6, n))
        prob.run_model()
        ks[theory] = float(prob.get_val("turbulence_ks")[0])
        if theory == "strip":
            continue
        names = ("stiffness_csn", "body_mass", "density", "t_upper_skin", "lift_influence")
        J = prob.compute_totals("turbulence_ks", list(names))
        for name, k, h in (("stiffness_csn", 0, 1.0), ("body_mass", 0, 1e-3), ("density", 0, 1e-7),
                           ("t_upper_skin", 1, 1e-6), ("lift_influence", 5, 1e-6)):
            base = prob.get_val(name).copy()
            vals = []
            for sign in (1, -1):
                v = base.copy()
                v.flat[k] += sign * h
                prob.set_val(name, v)
                prob.run_model()
                vals.append(float(prob.get_val("turbulence_ks")[0]))
            prob.set_val(name, base)
            fd = (vals[0] - vals[1]) / (2 * h)
            got = J["turbulence_ks", name].ravel()[k]
            assert abs(got - fd) <= 1e-5 * abs(fd) + 1e-9, (name, k, got, fd)
    assert abs(ks["vlm"] - ks["strip"]) > 1e-3 * abs(ks["strip"])


@pytest.mark.slow
def test_size_pegasus_turbulence_constraint_vortex_lattice(tmp_path):
    """`size pegasus --aero coupled --aero-theory vlm --turbulence --analysis-only`: the constraint's
    model is the vortex lattice on the beam; its 25.341(b) A-bar and 1 g loads equal those of the
    `wingmdao turbulence pegasus --clamped --aero-theory vlm` command on the same design (its own
    set-up, another code path) to 1e-6, and its root bending A-bar is below strip theory's
    (the lattice's lower lift slope)."""
    import json

    from wingmdao.cli import main

    out = tmp_path / "s.json"
    assert main(["size", "pegasus", "--aero", "coupled", "--aero-theory", "vlm", "--loads", "maneuver", "--analysis-only",
                 "--turbulence", "--no-plots", "--quiet", "--out", str(tmp_path), "--json", str(out)]) == 0
    tl = json.loads(out.read_text())["turbulence_loads"]
    t = {}
    for theory in ("vlm", "strip"):
        cmd = tmp_path / f"t_{theory}.json"
        assert main(["turbulence", "pegasus", "--clamped", "--aero-theory", theory, "--damping-ratio", "0.02",
                     "--f-max-hz", "20", "--no-plots", "--json", str(cmd)]) == 0
        t[theory] = json.loads(cmd.read_text())
    for key in ("bending_moment", "torsion"):
        np.testing.assert_allclose(tl[key]["a_bar"], t["vlm"]["a_bar"][key], rtol=1e-6,
                                   atol=1e-6 * max(t["vlm"]["a_bar"][key]))
        np.testing.assert_allclose(tl[key]["one_g"], t["vlm"]["design_loads"][key]["one_g"], rtol=1e-9, atol=1e-6)
    assert tl["bending_moment"]["a_bar"][0] < 0.8 * t["strip"]["a_bar"]["bending_moment"][0]
