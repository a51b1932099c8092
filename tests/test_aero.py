"""Unsteady strip theory on the beam (wingmdao.aero) against independent references.

References: Wagner's function in R. T. Jones' form (NACA Rep. 681, 1940), Kuessner's in the
Sears-Sparks form (J. Aero. Sci. 9, 1941), Theodorsen's C(k) from Hankel functions (NACA Rep. 496,
1935), strip-theory spanload and the torsional-divergence closed form of a uniform clamped wing
(e.g. Bisplinghoff, Ashley & Halfman, "Aeroelasticity", 1955, Sec. 8-2; Wright & Cooper,
"Introduction to Aircraft Aeroelasticity and Loads", 2007, Ch. 8).
"""

import numpy as np
import pytest

from wingmdao.aero import (aero_parameters, cached_aeroelastic_system, kussner_sears_sparks, station_gust_history,
                           theodorsen_exact, theodorsen_jones, wagner_jones)
from wingmdao.beam.static import beam_forcing, beam_parameters, straight_beam
from wingmdao.timemarch.bdf import march, solve_static, state_rates
from wingmdao.timemarch.system import layout, pack

RHO, V = 1.2, 20.0


def _wing(n, span=4.0, chord=1.0, GJ=1e9, EI=1e9, mass=1e-3, **aero):
    r0, th0 = straight_beam(n, span)
    bp = beam_parameters(r0, th0, EI_cc=EI, GJ=GJ, EI_nn=10 * EI, EA=100 * EI, mass_per_length=mass)
    kw = dict(chord=chord, ref_point=0.25, airspeed=V, density=RHO)
    kw.update(aero)
    ap = aero_parameters(n, **kw)
    s = cached_aeroelastic_system(n)
    qd = beam_forcing(n)
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3))
    return s, pack(s.param_specs, {**bp, **ap}), pack(s.forcing_specs, qd), r0


def _lift_history(s, t, p, Q):
    h = march(s, t, p, Q)
    L, _ = s.section_load_history(h.states, state_rates(h.states, t[1] - t[0]), p, Q)
    return L, h.states


def test_bad_inputs_raise():
    for kw, name in ((dict(chord=0.0), "chord"), (dict(chord=-1.0), "chord"), (dict(airspeed=0.0), "airspeed"),
                     (dict(density=-1.0), "density"), (dict(ref_point=1.2), "ref_point"),
                     (dict(mach=1.0), "mach")):
        args = dict(chord=1.0, airspeed=10.0, density=1.2)
        args.update(kw)
        with pytest.raises(ValueError, match=name) as err:
            aero_parameters(3, **args)
        value = float(next(iter(kw.values())))
        assert f"got {value!r}" in str(err.value) and "np." not in str(err.value), str(err.value)


def test_wagner_step_in_angle_of_attack():
    """Plunge-velocity step w0 (AoA step w0/V) on a very stiff wing: lift/length follows phi(s).

    Discretization: the step falls between t0 and t1 (ds = 0.1 semichord per step), BDF2; tolerance
    0.3 % for s >= 1 (ours 0.03 %)."""
    s, p, q, _ = _wing(3)
    t = np.arange(401) * 0.0025
    Q = np.tile(q, (t.size, 1))
    Q[1:, layout(s.forcing_specs)["frame_velocity"].start + 2] = -1.0
    L, _ = _lift_history(s, t, p, Q)
    sv = V * t / 0.5  # backward differences: the forcing of step 1 acts over (t0, t1]
    ref = 0.5 * RHO * V ** 2 * 1.0 * 2 * np.pi * (1.0 / V) * wagner_jones(sv)
    m = sv >= 1.0
    np.testing.assert_allclose(L[m, 1], ref[m], rtol=3e-3)
    assert abs(L[-1, 1] / ref[-1] - 1) < 2e-3


def test_kussner_sharp_edged_gust():
    """Sharp-edged gust w0 entering at t1 (same at every station): lift follows psi(s), within 0.3 %
    for s >= 1 (ours 0.24 %)."""
    s, p, q, _ = _wing(3)
    t = np.arange(401) * 0.0025
    Q = np.tile(q, (t.size, 1))
    Q[1:, layout(s.forcing_specs)["gust_velocity"]] = 1.0
    L, _ = _lift_history(s, t, p, Q)
    sv = V * t / 0.5  # backward differences: the forcing of step 1 acts over (t0, t1]
    ref = 0.5 * RHO * V ** 2 * 2 * np.pi * (1.0 / V) * kussner_sears_sparks(sv)
    m = sv >= 1.0
    np.testing.assert_allclose(L[m, 1], ref[m], rtol=3e-3)


def test_gust_penetration_delay():
    g = station_gust_history(np.array([0.0, 0.1, 0.2]), [0.0, 2.0], 10.0, lambda tau: (tau >= 0) * 1.0)
    np.testing.assert_array_equal(g, [[1, 0], [1, 0], [1, 1]])


@pytest.mark.parametrize("k", [0.1, 0.3, 0.5])
def test_harmonic_plunge_vs_theodorsen(k):
    """Harmonic plunge hdot = W sin(w t): lift amplitude and phase vs Theodorsen
    L = pi rho b^2 hddot + 2 pi rho V b C(k) hdot. Against C(k) of Jones. approximation: 0.1 %, 1 mrad
    (ours <= 0.02 %); against the exact C(k): within the Jones error plus the time step (2 %, 0.025 rad)."""
    b, W = 0.5, 0.5
    w = k * V / b
    s, p, q, _ = _wing(2)
    periods = 6
    t = np.linspace(0.0, periods * 2 * np.pi / w, periods * 160 + 1)
    Q = np.tile(q, (t.size, 1))
    ql = layout(s.forcing_specs)
    Q[:, ql["frame_velocity"].start + 2] = -W * np.sin(w * t)
    Q[:, ql["frame_acceleration"].start + 2] = -W * w * np.cos(w * t)
    Q[:, ql["frame_velocity_rate"].start + 2] = -W * w * np.cos(w * t)
    L, _ = _lift_history(s, t, p, Q)
    m = t >= (periods - 2) * 2 * np.pi / w
    A = np.column_stack([np.sin(w * t[m]), np.cos(w * t[m]), np.ones(m.sum())])
    coef = np.linalg.lstsq(A, L[m, 0], rcond=None)[0]
    ours = coef[0] + 1j * coef[1]  # L = Im(ours e^{iwt}) with sin -> 1, cos -> i
    for C, rtol, atol_phase in ((theodorsen_jones(k), 1e-3, 1e-3), (theodorsen_exact(k), 2e-2, 2.5e-2)):
        ref = W * (np.pi * RHO * b ** 2 * 1j * w + 2 * np.pi * RHO * V * b * C)
        assert abs(abs(ours) / abs(ref) - 1) < rtol, (k, ours, ref)
        assert abs(np.angle(ours / ref)) < atol_phase, (k, ours, ref)


def test_static_spanload_rigid_tapered_wing_prandtl_glauert():
    """Quasi-steady rigid clamped wing, linear taper, M = 0.5: root shear and bending moment equal
    the strip-theory closed form (q a / sqrt(1 - M^2) alpha c(y) integrated)."""
    n, span, alpha, mach = 21, 4.0, 0.05, 0.5
    c = np.linspace(1.5, 0.5, n)
    s, p, q, r0 = _wing(n, span=span, chord=c, alpha_zero_lift=-alpha, mach=mach)
    x, _ = solve_static(s, p, q)
    X = x.reshape(n, 22)
    ql = 0.5 * RHO * V ** 2 * 2 * np.pi / np.sqrt(1 - mach ** 2) * alpha
    # c(y) = 1.5 - 0.25 y: int c dy = 1.5 s - s^2/8 ; int c y dy = 0.75 s^2 - s^3/12
    shear = ql * (1.5 * span - span ** 2 / 8)
    moment = ql * (0.75 * span ** 2 - span ** 3 / 12)
    np.testing.assert_allclose(X[0, 8], shear, rtol=1e-6)
    np.testing.assert_allclose(X[0, 9], moment, rtol=2e-3)  # M_x about +x = lift outboard * y


@pytest.mark.slow
def test_static_aeroelastic_twist_vs_divergence_closed_form():
    """Uniform straight clamped wing, beam axis 0.15 c aft of the quarter chord, q = q_D / 2 with
    q_D = (pi/2)^2 GJ / (e c a s^2): tip twist alpha_r (1/cos(lam s) - 1) and lift effectiveness
    tan(lam s)/(lam s), lam^2 = q c a e / GJ. 41 nodes: 0.3 % (discretization)."""
    n, span, c, a, alpha = 41, 4.0, 1.0, 2 * np.pi, 0.02
    e = 0.15 * c
    q = 0.5 * RHO * V ** 2
    qD = 2 * q
    GJ = qD * e * c * a * span ** 2 / (np.pi / 2) ** 2
    s, p, qv, _ = _wing(n, span=span, chord=c, GJ=GJ, EI=1e3 * GJ, ref_point=0.4, alpha_zero_lift=-alpha)
    x, _ = solve_static(s, p, qv)
    X = x.reshape(n, 22)
    lam_s = np.sqrt(q * c * a * e / GJ) * span
    np.testing.assert_allclose(X[-1, 4], alpha * (1 / np.cos(lam_s) - 1), rtol=3e-3)
    rigid = q * c * a * alpha * span
    np.testing.assert_allclose(X[0, 8] / rigid, np.tan(lam_s) / lam_s, rtol=3e-3)


# ----------------------------------------------------------------------------- component
def _component_problem(n=3, n_time=6, dt=0.01, mode="rev", free=False):
    import openmdao.api as om

    from wingmdao.components.aeroelastic import AeroelasticBeamDynamics

    s, p, q, r0 = _wing(n, span=2.0, GJ=2e4, EI=5e4, mass=5.0, ref_point=0.4, alpha_zero_lift=-0.02, mach=0.3)
    t = np.arange(n_time) * dt
    prob = om.Problem()
    comp = AeroelasticBeamDynamics(num_nodes=n, time=t, matrix_free=False, plunge=free, trim=free)
    if free:
        s = cached_aeroelastic_system(n, plunge=True, trim=True)
    prob.model.add_subsystem("beam", comp, promotes=["*"])

    class RootMoment(om.ExplicitComponent):
        """y = sum_t M_x,root(t)^2 / n_time (a smooth aggregate of the root bending moment)."""

        def setup(self):
            self.add_input("states", shape=(n_time,) + s.state_shape)
            self.add_output("y", units="N**2*m**2", desc="mean square root bending moment")
            cols = np.arange(n_time) * s.n_state + 9
            self._cols = cols
            self.declare_partials("y", "states", rows=np.zeros(n_time, int), cols=cols)

        def compute(self, inputs, outputs):
            m = inputs["states"].reshape(n_time, -1)[:, 9]
            outputs["y"] = np.sum(m ** 2) / n_time

        def compute_partials(self, inputs, partials):
            partials["y", "states"] = 2 * inputs["states"].reshape(n_time, -1)[:, 9] / n_time

    prob.model.add_subsystem("agg", RootMoment(), promotes=["*"])
    prob.setup(mode=mode, force_alloc_complex=False)
    for spec, sl in zip(s.param_specs, layout(s.param_specs).values()):
        if spec.name in ("body_mass", "trim_lift"):
            continue
        prob.set_val(spec.name, p[sl].reshape(spec.shape or (1,)))
    if free:
        prob.set_val("body_mass", 200.0)
        prob.set_val("trim_lift", 200.0 * 9.81 + 2 * 5.0 * 2.0 * 9.81)
        prob.set_val("trim_active", (np.arange(n_time) == 0) * 1.0)
    # a 1-cos gust arriving along the span (a swept-free wing: same x, no delay)
    wg = 2.0 * 0.5 * (1 - np.cos(2 * np.pi * t / (n_time * dt)))
    prob.set_val("gust_velocity", np.tile(wg[:, None], (1, n)))
    prob.set_val("gravity", np.tile([0.0, 0.0, -9.81], (n_time, 1)))
    return prob


def test_component_check_partials():
    prob = _component_problem(n_time=4)
    prob.run_model()
    data = prob.check_partials(out_stream=None, method="fd", step=1e-6, form="central",
                               includes=["beam"])
    worst = 0.0
    for (of, wrt), d in data["beam"].items():
        fd = d["J_fd"]
        an = d["J_fwd"]
        scale = max(np.max(np.abs(fd)), 1e-8)
        worst = max(worst, np.max(np.abs(an - fd)) / scale)
        assert np.max(np.abs(an - fd)) <= 2e-5 * scale + 1e-6, (of, wrt)
    assert worst < 2e-5


@pytest.mark.parametrize("free", [False, True], ids=["clamped", "plunge+trim"])
def test_adjoint_totals_root_moment_vs_fd_and_forward(free):
    """d(mean square root moment over a 1-cos gust)/d(stiffness, airspeed, chord, density):
    reverse (adjoint) vs forward (tangent) vs central finite differences; clamped, and free in
    plunge from the trimmed 1 g state (gravity on)."""
    wrt = ["stiffness_csn", "airspeed", "chord", "density"] + (["body_mass"] if free else [])
    prob = _component_problem(mode="rev", free=free)
    prob.run_model()
    rev = prob.compute_totals(of=["y"], wrt=wrt)
    fd = prob.check_totals(of=["y"], wrt=wrt, method="fd", form="central", step=1e-4, out_stream=None)
    probf = _component_problem(mode="fwd", free=free)
    probf.run_model()
    fwd = probf.compute_totals(of=["y"], wrt=wrt)
    for w in wrt:
        key = ("y", w)
        ref = fd[key]["J_fd"]
        scale = np.max(np.abs(ref))
        assert scale > 0
        np.testing.assert_allclose(rev[key], ref, rtol=0, atol=2e-5 * scale)  # ours <= 7e-6 (stiffness), 1e-9 (others)
        np.testing.assert_allclose(fwd[key], rev[key], rtol=0, atol=1e-9 * scale)


@pytest.mark.slow
@pytest.mark.parametrize("mu", [10.0, 50.0])
def test_free_plunge_pratt_walker_alleviation(mu):
    """Free plunge, very stiff wing, 1-cos gust of gradient H = 12.5 c: peak incremental load
    factor / quasi-steady rho U V a / (2 W/S) = Pratt-Walker K_g = 0.88 mu / (5.3 + mu) within 5 %
    (Pratt & Walker, "A revised gust-load formula and a re-evaluation of V-G data taken on civil
    transport airplanes from 1933 to 1950", NACA Rep. 1206, 1954). Ours: +0.6 % (mu 10), +2.2 % (mu 50)."""
    n, span, c, a, g = 2, 4.0, 1.0, 2 * np.pi, 9.81
    r0, th0 = straight_beam(n, span)
    bp = beam_parameters(r0, th0, EI_cc=1e9, GJ=1e9, EI_nn=1e10, EA=1e11, mass_per_length=1e-3)
    ap = aero_parameters(n, chord=c, ref_point=0.25, airspeed=V, density=RHO)
    s = cached_aeroelastic_system(n, plunge=True)
    m = mu * RHO * c * a * g * (2 * span * c) / (2 * g)  # mu = 2 (W/S) / (rho c a g)
    wing_loading = m * g / (2 * span * c)
    p = pack(s.param_specs, {**bp, **ap, "body_mass": m})
    qd = beam_forcing(n)
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3))
    q = pack(s.forcing_specs, qd)
    U, T = 1.0, 2 * 12.5 * c / V
    t = np.arange(int(4 * T / 0.002) + 1) * 0.002
    Q = np.tile(q, (t.size, 1))
    Q[:, layout(s.forcing_specs)["gust_velocity"]] = np.where(t <= T, U / 2 * (1 - np.cos(2 * np.pi * t / T)),
                                                              0.0)[:, None]
    h = march(s, t, p, Q)
    dn = 2 * h.states[:, 8] / (m * g)
    ratio = dn.max() / (RHO * U * V * a / (2 * wing_loading))
    assert abs(ratio / (0.88 * mu / (5.3 + mu)) - 1) < 0.05


def test_trim_static_lift_and_hold():
    """Trim (free plunge, gravity): alpha_trim makes the lift of both halves n W; rigid wing closed
    form alpha = n W / (q S a / sqrt(1 - M^2)); with trim_active = 0 after t = 0 the state holds."""
    n, span, c, g, mach = 5, 4.0, 1.0, 9.81, 0.3
    r0, th0 = straight_beam(n, span)
    bp = beam_parameters(r0, th0, EI_cc=1e9, GJ=1e9, EI_nn=1e10, EA=1e11, mass_per_length=2.0)
    ap = aero_parameters(n, chord=c, ref_point=0.25, airspeed=V, density=RHO, mach=mach)
    s = cached_aeroelastic_system(n, plunge=True, trim=True)
    m, n_load = 60.0, 1.5
    p = pack(s.param_specs, {**bp, **ap, "body_mass": m - 2 * 2.0 * span, "trim_lift": n_load * m * g})
    qd = beam_forcing(n, gravity=[0, 0, -g], frame_acceleration=[0, 0, (n_load - 1) * g])
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3), trim_active=1.0)
    q = pack(s.forcing_specs, qd)
    x, _ = solve_static(s, p, q)
    q_dyn = 0.5 * RHO * V ** 2
    alpha = n_load * m * g / (q_dyn * 2 * span * c * 2 * np.pi / np.sqrt(1 - mach ** 2))
    np.testing.assert_allclose(x[s.trim_index], alpha, rtol=1e-9)
    # 1 g level flight: trimmed at t = 0, alpha_trim held after; the state stays put
    p1 = pack(s.param_specs, {**bp, **ap, "body_mass": m - 2 * 2.0 * span, "trim_lift": m * g})
    qd["frame_acceleration"] = np.zeros(3)
    t = np.arange(21) * 0.01
    Q1 = np.tile(pack(s.forcing_specs, qd), (t.size, 1))
    Q1[1:, layout(s.forcing_specs)["trim_active"]] = 0.0
    h = march(s, t, p1, Q1)
    assert np.max(np.abs(h.states - h.states[0])) < 1e-6
    np.testing.assert_allclose(h.states[-1, s.trim_index], alpha / n_load, rtol=1e-9)


def test_lifting_line_slope_elliptic_and_quasi_steady_spanload():
    """Elliptic planform: the lifting-line slope is uniform, a0 / (1 + a0 / (pi AR)) (Prandtl); used
    as the strips' lift_slope, the rigid wing's quasi-steady root shear equals CL_alpha q S alpha / 2."""
    from wingmdao.aero.lifting_line import lifting_line_lift_slope

    s_span, c0, alpha, n = 5.0, 1.0, 0.02, 41
    cf = lambda y: c0 * np.sqrt(np.clip(1 - (y / s_span) ** 2, 0, None))  # noqa: E731
    y = np.linspace(0.0, 0.98 * s_span, n)
    slope, cl_alpha = lifting_line_lift_slope(y, cf, s_span)
    ref = 2 * np.pi / (1 + 2 * np.pi / (np.pi * 8 * s_span / (np.pi * c0)))
    np.testing.assert_allclose(slope, ref, rtol=1e-10)
    np.testing.assert_allclose(cl_alpha, ref, rtol=1e-10)
    s, p, q, r0 = _wing(n, span=0.98 * s_span, chord=cf(y), lift_slope=slope, alpha_zero_lift=-alpha)
    x, _ = solve_static(s, p, q)
    # closed form of the half-wing lift up to y_end: q alpha a int c dy (elliptic chord integral)
    ye = 0.98 * s_span
    int_c = c0 * 0.5 * (ye * np.sqrt(1 - (ye / s_span) ** 2) + s_span * np.arcsin(ye / s_span))
    np.testing.assert_allclose(x.reshape(n, 22)[0, 8], 0.5 * RHO * V ** 2 * alpha * ref * int_c, rtol=2e-3)
    with pytest.raises(ValueError, match="semi_span"):
        lifting_line_lift_slope(y, cf, 0.0)


def test_adjoint_totals_wrt_thicknesses_through_box_sections():
    """Box sections (wall thicknesses) -> aeroelastic beam over a 1-cos gust -> mean-square root
    moment: reverse totals w.r.t. the four wall thicknesses and airspeed vs central FD."""
    import openmdao.api as om

    from wingmdao.components.aeroelastic import AeroelasticBeamDynamics
    from wingmdao.components.section import BoxSection
    from wingmdao.materials import ALUMINIUM

    n, n_time, dt = 3, 6, 0.01
    cached_aeroelastic_system(n)
    r0, th0 = straight_beam(n, 4.0)
    t = np.arange(n_time) * dt
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("section", BoxSection(num_stations=n, material=ALUMINIUM), promotes=["*"])
    prob.model.add_subsystem("beam", AeroelasticBeamDynamics(num_nodes=n, time=t, matrix_free=False),
                             promotes_inputs=["stiffness_csn", "compliance_csn", "mass_per_length",
                                              "inertia_per_length", "airspeed"])

    class RootMoment(om.ExplicitComponent):
        def setup(self):
            self.add_input("states", shape=(n_time, n, 22))
            self.add_output("y", desc="mean square root bending moment / 1e6")
            self.declare_partials("y", "states", rows=np.zeros(n_time, int), cols=np.arange(n_time) * n * 22 + 9)

        def compute(self, inputs, outputs):
            outputs["y"] = np.sum(inputs["states"][:, 0, 9] ** 2) / 1e6

        def compute_partials(self, inputs, partials):
            partials["y", "states"] = 2 * inputs["states"][:, 0, 9] / 1e6

    prob.model.add_subsystem("agg", RootMoment())
    prob.model.connect("beam.states", "agg.states")
    prob.setup(mode="rev")
    prob.set_val("width", np.full(n, 0.5))
    prob.set_val("height", np.full(n, 0.12))
    for w in ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar"):
        prob.set_val(w, np.full(n, 0.002))
    prob.set_val("beam.node_positions", r0)
    prob.set_val("beam.node_euler_angles", th0)
    for k in ("tension_axis", "shear_center", "mass_center"):
        prob.set_val(f"beam.{k}", np.zeros((n, 2)))
    ap = aero_parameters(n, chord=1.0, ref_point=0.4, airspeed=40.0, density=1.2, alpha_zero_lift=-0.02)
    for k, v in ap.items():
        if k != "airspeed":
            prob.set_val(f"beam.{k}", v)
    prob.set_val("airspeed", 40.0)
    prob.set_val("beam.gust_velocity", np.tile((3.0 * (1 - np.cos(2 * np.pi * t / (n_time * dt))))[:, None], (1, n)))
    prob.run_model()
    wrt = ["t_upper_skin", "t_front_spar", "airspeed"]
    rev = prob.compute_totals(of=["agg.y"], wrt=wrt)
    fd = prob.check_totals(of=["agg.y"], wrt=wrt, method="fd", form="central", step=1e-7, out_stream=None)
    for w in wrt:
        ref = fd[("agg.y", w)]["J_fd"]
        scale = np.max(np.abs(ref))
        assert scale > 0
        np.testing.assert_allclose(rev[("agg.y", w)], ref, rtol=0, atol=1e-4 * scale)
