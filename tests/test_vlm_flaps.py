"""Control surfaces as deflected panels of the vortex lattice (wingmdao.aero.vlm.flap_influence) and in
the coupled residual with aero_theory="vlm".

Checks, each against an independent result:

* 2-D limit (rectangular wing of aspect ratio 200, full-span flap, 32 chordwise panels): the centre
  station's dCl/ddelta against Glauert's thin-airfoil 2 (pi - theta_f + sin theta_f), its ratio to
  the lift slope against the flap effectiveness tau, and the hinge-moment coefficients C_h,alpha,
  C_h,beta against their thin-airfoil closed forms (coded here from Glauert's Fourier series, not
  from wingmdao.aero.controls);
* finite wing (aspect ratio 10): a full-span flap's CL_delta = tau CL_alpha (linear lifting theory),
  and part-span flaps' CL_delta against Prandtl's lifting line solved by Glauert's Fourier series
  (coded here);
* the residual: a steady deflection loads the stations with the lattice's flap columns; a harmonic
  flap on a high-aspect-ratio wing against Theodorsen's flap lift and hinge moment with the model's
  C(k); check_partials of the component and adjoint totals of a gust KS against central differences.
"""

import math

import numpy as np
import pytest

from wingmdao.aero import aero_parameters, cached_aeroelastic_system, theodorsen_jones
from wingmdao.aero.controls import ControlLaw, ControlSurface, control_spec
from wingmdao.aero.system import three_dimensional_parameters
from wingmdao.aero.vlm import build_lattice, chord_fractions, flap_influence, flat_wing
from wingmdao.beam.static import beam_forcing, beam_parameters, straight_beam
from wingmdao.timemarch.bdf import march, solve_static, state_rates
from wingmdao.timemarch.system import layout, pack

RHO, V = 1.2, 20.0


def _glauert(hinge):
    """Thin-airfoil flap (Glauert 1926, Ch. VII; Abbott & von Doenhoff Sec. 8.5): dCl/ddelta, and the
    hinge-moment coefficients on q c^2 (trailing edge down +) of the flat plate at alpha and of the
    flap, by direct integration of the thin-airfoil load over the flap (x from 0 to 1, x = (1 - cos
    theta) / 2). The flapped camber line's Fourier coefficients A0 = 1 - theta_f / pi,
    An = 2 sin(n theta_f) / (n pi) sum to sum An sin(n theta) = ln|sin((theta + theta_f)/2) /
    sin((theta - theta_f)/2)| / pi; the load is dCp = 4 (A0 cot(theta/2) + sum An sin(n theta))."""
    th_f = math.acos(1 - 2 * hinge)
    cl_d = 2 * (math.pi - th_f + math.sin(th_f))
    u = np.linspace(0.0, 1.0, 400001)[1:]
    th = th_f + (math.pi - th_f) * u ** 2  # clustered at the hinge's logarithmic singularity
    x = 0.5 * (1 - np.cos(th))
    cot_half = 1.0 / np.tan(0.5 * th)
    series = np.log(np.abs(np.sin(0.5 * (th + th_f)) / np.sin(0.5 * (th - th_f)))) / math.pi

    def hinge_of(dcp):
        f = -dcp * (x - hinge)
        return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(x)))

    ch_a = hinge_of(4 * cot_half)
    ch_b = hinge_of(4 * ((1 - th_f / math.pi) * cot_half + series))
    return cl_d, ch_a, ch_b


def test_chord_fractions_put_the_hinge_on_a_panel_edge():
    np.testing.assert_allclose(chord_fractions(4, [0.75]), [0, 0.25, 0.5, 0.75, 1])
    f = chord_fractions(4, [0.7])
    assert np.min(np.abs(f - 0.7)) < 1e-12 and f.size == 5  # three panels ahead, one aft (rounding)
    f = chord_fractions(16, [0.7, 0.8])
    assert all(np.min(np.abs(f - h)) < 1e-12 for h in (0.7, 0.8)) and np.all(np.diff(f) > 0)
    with pytest.raises(ValueError, match=r"hinge = 1.2 is outside the chord; allowed range \(0, 1\)"):
        chord_fractions(4, [1.2])
    r, c, ref = flat_wing(3.0, lambda y: np.ones_like(y), n_stations=5, spacing="uniform")
    with pytest.raises(ValueError, match=r"flap nodes \[1, 3\]: allowed at least two contiguous node indices"):
        flap_influence(r, c, ref, [((1, 3), 0.75)])
    with pytest.raises(ValueError, match="fractions must increase from 0 to 1"):
        build_lattice(r, c, ref, fractions=[0.0, 0.6, 0.5, 1.0])


@pytest.mark.parametrize("hinge", [0.75, 0.5])
def test_two_dimensional_limit_against_thin_airfoil_theory(hinge):
    """Aspect ratio 200, 32 chordwise panels: the centre station's dCl/ddelta within 2.5 % of Glauert's
    (found -1.9 % and -1.1 %; the error falls as 1 / n_chordwise), dCl/ddelta / dCl/dalpha within 1.5 %
    of tau; C_h,beta within 2.5 % and C_h,alpha (the lattice's at the section's 3-D lift slope) within
    2 % of the closed forms."""
    semi, n = 100.0, 11
    r, c, ref = flat_wing(semi, lambda y: np.ones_like(y), n_stations=n, spacing="uniform")
    st, fl = flap_influence(r, c, ref, [(tuple(range(n)), hinge)], n_chordwise=32, n_spanwise=2)
    cl_d, ch_a, ch_b = _glauert(hinge)
    centre_d, centre_a = fl.lift.sum(axis=1)[0], st.lift.sum(axis=1)[0]
    assert abs(centre_d / cl_d - 1) < 0.025
    assert abs((centre_d / centre_a) / (cl_d / (2 * math.pi)) - 1) < 0.015
    assert abs(fl.hinge_flap.sum() / semi / ch_b - 1) < 0.025
    assert abs(fl.hinge_station.sum() / semi * (2 * math.pi / centre_a) / ch_a - 1) < 0.02


def _lifting_line_cl(aspect, eta0, eta1, terms=199):
    """CL of a rectangular wing (chord 1, section slope 2 pi) with a unit angle on eta0 <= |y|/s <= eta1:
    Prandtl's lifting line by Glauert's Fourier series (odd terms, collocation)."""
    nn = np.arange(1, 2 * terms, 2)
    th = (np.arange(1, terms + 1) - 0.5) * (math.pi / 2) / terms
    mu = 2 * math.pi / (4 * aspect)
    eta = np.abs(np.cos(th))
    alpha = ((eta >= eta0 - 1e-12) & (eta <= eta1 + 1e-12)).astype(float)
    a = np.linalg.solve(np.sin(np.outer(th, nn)) * (np.sin(th)[:, None] + nn[None, :] * mu), mu * alpha * np.sin(th))
    return math.pi * aspect * a[0]


def test_finite_wing_full_and_part_span_flaps():
    """Aspect ratio 10, 16 chordwise panels. Full span: CL_delta = tau CL_alpha within 2 % (found
    -1.0 %). Part span (outboard 60-100 %, inboard 0-50 %, mid 30-70 % of the semi-span): CL_delta over
    the full-span flap's against the lifting line's CL of a unit angle on the flap's span over that
    of the whole span, within 1.5 % (found 0.2 to 1.0 %)."""
    aspect, n = 10.0, 21
    semi = aspect / 2
    r, c, ref = flat_wing(semi, lambda y: np.ones_like(y), n_stations=n, spacing="uniform")
    tau = _glauert(0.75)[0] / (2 * math.pi)

    def cl_delta(first, last):
        st, fl = flap_influence(r, c, ref, [(tuple(range(first, last + 1)), 0.75)], n_chordwise=16, n_spanwise=2)
        return 2 * st.tributary @ fl.lift.sum(axis=1) / aspect, st.lift_slope(aspect)

    full, cl_a = cl_delta(0, n - 1)
    assert abs(full / (tau * cl_a) - 1) < 0.02
    ll_full = _lifting_line_cl(aspect, 0.0, 1.0)
    for first, last in ((12, 20), (0, 10), (6, 14)):
        part, _ = cl_delta(first, last)
        ll = _lifting_line_cl(aspect, r[first, 1] / semi, r[last, 1] / semi) / ll_full
        assert abs((part / full) / ll - 1) < 0.015, (first, last, part / full, ll)


def _wing(n, span, surfaces, law=None, plunge=False, trim=False, stiff=True):
    r0, th0 = straight_beam(n, span)
    if stiff:
        bp = beam_parameters(r0, th0, EI_cc=1e9, GJ=1e9, EI_nn=1e10, EA=1e11, mass_per_length=1e-3)
    else:
        bp = beam_parameters(r0, th0, EI_cc=5e4, GJ=2e4, EI_nn=5e5, EA=5e6, mass_per_length=5.0)
    ap = aero_parameters(n, chord=1.0, ref_point=0.4, airspeed=V, density=RHO, mach=0.3,
                         alpha_zero_lift=0.0 if stiff else -0.02)
    spec = control_spec(surfaces, r0[:, 1], law)
    s = cached_aeroelastic_system(n, controls=spec, aero_theory="vlm", plunge=plunge, trim=trim)
    ap.update(three_dimensional_parameters("vlm", r0, ap["chord"], ap["ref_point"], ap["mach"], controls=spec))
    qd = beam_forcing(n)
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3),
              surface_command=np.zeros(spec.n_surfaces))
    values = {**bp, **ap, **qd, **({} if law is None else law.matrices())}
    return s, values, r0


def test_residual_steady_flap_is_the_lattice_and_differs_from_strips():
    """A stiff wing (aspect ratio 6), the aileron on its outer half held at 3 deg: the stations' lift,
    moment and the hinge moment are q times the lattice's flap columns (wiring), and the lift at the
    inboard stations outside the aileron is not zero (the 3-D spread strip theory lacks)."""
    n, delta = 7, math.radians(3.0)
    s, values, r0 = _wing(n, 3.0, [ControlSurface("aileron", hinge=0.75, span=(0.5, 1.0))])
    values["surface_command"] = np.array([delta])
    p, q = pack(s.param_specs, values), pack(s.forcing_specs, values)
    x, _ = solve_static(s, p, q)
    L, M = s.section_loads(x, np.zeros_like(x), p, q)
    qd = 0.5 * RHO * V ** 2
    np.testing.assert_allclose(L, qd * values["flap_lift_influence"].sum(axis=1) * delta, rtol=1e-4)
    np.testing.assert_allclose(M, qd * values["flap_moment_influence"].sum(axis=1) * delta
                               + L * (0.4 - 0.25), rtol=1e-3, atol=1e-4 * np.max(np.abs(M)))
    H = s.hinge_moments(x, np.zeros_like(x), p, q)[0]
    np.testing.assert_allclose(H, qd * values["hinge_flap_influence"].sum() * delta, rtol=1e-4)
    assert L[0] > 0.05 * L.max()  # the root carries lift of the outboard flap


@pytest.mark.slow
@pytest.mark.parametrize("k", [0.1, 0.4])
def test_harmonic_flap_on_a_long_wing_against_theodorsen(k):
    """A rigid, clamped rectangular wing of aspect ratio 60 with a full-span flap driven harmonically
    (200 Hz actuator): the centre station's lift and the flap's hinge moment per span against
    Theodorsen's flap loads with Jones' C(k) (NACA Rep. 496), scaled by the lattice's steady flap
    lift and hinge moment over the thin-airfoil ones (its 3-D and chordwise-discretisation factors,
    the lags then being the model's); within 2 %."""
    from wingmdao.aero.controls import flap_harmonic_loads, theodorsen_flap_functions

    hinge, b, n = 0.75, 0.5, 7
    surfaces = [ControlSurface("flap", hinge=hinge, nodes=(0, n - 1), actuator_order=2, frequency_hz=200.0)]
    s, values, r0 = _wing(n, 30.0, surfaces)
    values["mach"] = 0.0
    spec = s.controls
    values.update(three_dimensional_parameters("vlm", r0, values["chord"], values["ref_point"], 0.0, controls=spec))
    p, q = pack(s.param_specs, values), pack(s.forcing_specs, values)
    w = k * V / b
    periods = 5
    t = np.linspace(0.0, periods * 2 * np.pi / w, periods * 200 + 1)
    Q = np.tile(q, (t.size, 1))
    Q[:, layout(s.forcing_specs)["surface_command"]] = 0.02 * np.sin(w * t)[:, None]
    h = march(s, t, p, Q)
    Xd = state_rates(h.states, t[1] - t[0])
    L, _ = s.section_load_history(h.states, Xd, p, Q)
    beta = h.states[:, s.control_index["flap_deflection"]]
    H = np.array([s.hinge_moments(h.states[i], Xd[i], p, Q[i])[0] for i in range(t.size)]) / 30.0
    m = t >= (periods - 2) * 2 * np.pi / w
    A = np.column_stack([np.sin(w * t[m]), np.cos(w * t[m]), np.ones(m.sum())])

    def phasor(y):
        c = np.linalg.lstsq(A, y[m], rcond=None)[0]
        return c[0] + 1j * c[1]

    beta0 = phasor(beta)
    T = theodorsen_flap_functions(hinge)
    qd = 0.5 * RHO * V ** 2
    k_lift = values["flap_lift_influence"].sum(axis=1)[0] / (2 * T[10])  # lattice / thin airfoil, steady
    C = theodorsen_jones(k)
    lift_c = RHO * V ** 2 * b * 2 * C * (T[10] + 0.5j * k * T[11]) * beta0
    lift_nc = RHO * V ** 2 * b * (-1j * k * T[4] + k ** 2 * T[1]) * beta0
    assert abs(phasor(L[:, 0]) - (k_lift * lift_c + lift_nc)) < 0.02 * abs(lift_c + lift_nc)
    # the hinge moment: Theodorsen's with its steady value replaced by the lattice's
    _, _, h_ref = flap_harmonic_loads(np.array([k]), hinge, theodorsen_jones)
    ch_b = -(T[18] + T[10] * T[12]) / (2 * math.pi)
    steady_lat = values["hinge_flap_influence"].sum() / 30.0 * qd
    ref = RHO * V ** 2 * b ** 2 * h_ref[0] * beta0 + (steady_lat - qd * ch_b) * beta0 * (
        (T[10] * T[12] * C * (1 + 0.5j * k * T[11] / T[10]) + T[18]) / (T[18] + T[10] * T[12]))
    assert abs(phasor(H) - ref) < 0.02 * abs(ref), (phasor(H), ref)


def _gust_problem(n=4, n_time=8, dt=0.01):
    import openmdao.api as om

    from wingmdao.components.aeroelastic import AeroelasticBeamDynamics

    law = ControlLaw(("load_factor",), A=[[-6.0]], B=[[6.0]], C=[[-0.3]], D=[[-0.05]])
    surfaces = [ControlSurface("aileron", hinge=0.7, nodes=(2, 3), actuator_order=2, frequency_hz=8.0)]
    s, values, r0 = _wing(n, 3.0, surfaces, law, plunge=True, trim=True, stiff=False)
    t = np.arange(n_time) * dt
    prob = om.Problem()
    prob.model.add_subsystem("beam", AeroelasticBeamDynamics(num_nodes=n, time=t, matrix_free=False, system=s,
                                                             aero_theory="vlm"), promotes=["*"])

    class RootBendingKS(om.ExplicitComponent):
        """KS aggregate of the root bending moment history (kN m), rho = 5."""

        def setup(self):
            self.add_input("states", shape=(n_time,) + s.state_shape, desc="state history")
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
    values.update(body_mass=200.0, trim_lift=200.0 * 9.81 + 2 * 5.0 * 3.0 * 9.81)
    for spec_ in s.param_specs:
        prob.set_val(spec_.name, np.asarray(values[spec_.name]).reshape(spec_.shape or (1,)))
    prob.set_val("trim_active", (np.arange(n_time) == 0) * 1.0)
    wg = 2.0 * 0.5 * (1 - np.cos(2 * np.pi * t / (n_time * dt)))
    prob.set_val("gust_velocity", np.tile(wg[:, None], (1, n)))
    prob.set_val("gravity", np.tile([0.0, 0.0, -9.81], (n_time, 1)))
    return prob, s


def test_adjoint_totals_of_gust_ks_with_lattice_aileron():
    """Free plunge from trim, a filtered load-factor law on an aileron of the lattice: d KS(root
    bending) / d(gains, stiffness, airspeed, flap influence) by the discrete adjoint against central
    differences (1e-4 of the largest entry)."""
    prob, s = _gust_problem()
    prob.run_model()
    assert np.ptp(prob.get_val("states").reshape(8, -1)[:, s.control_index["aileron_deflection"]]) > 1e-4
    groups = ((["stiffness_csn"], 1.0), (["controller_C", "controller_D", "airspeed"], 1e-5),
              (["flap_lift_influence", "hinge_flap_influence"], 1e-5))
    for wrt, step in groups:
        rev = prob.compute_totals(of=["ks"], wrt=wrt)
        fd = prob.check_totals(of=["ks"], wrt=wrt, method="fd", form="central", step=step, out_stream=None)
        for w in wrt:
            ref = fd[("ks", w)]["J_fd"]
            scale = np.max(np.abs(ref))
            if w != "hinge_flap_influence":  # the hinge moment loads nothing: its total is zero
                assert scale > 0, w
            np.testing.assert_allclose(rev[("ks", w)], ref, rtol=0, atol=1e-4 * max(scale, 1e-12))


@pytest.mark.slow
def test_component_check_partials_with_lattice_aileron():
    """AeroelasticBeamDynamics with a lattice aileron and a law: the CasADi partials (flap influence,
    gains, airspeed) against central differences."""
    prob, _ = _gust_problem(n_time=4)
    prob.run_model()
    data = prob.check_partials(out_stream=None, method="fd", step=1e-6, form="central", includes=["beam"])
    for (of, wrt), d in data["beam"].items():
        fd, an = d["J_fd"], d["J_fwd"]
        scale = max(np.max(np.abs(fd)), 1e-8)
        assert np.max(np.abs(an - fd)) <= 2e-5 * scale + 1e-6, (of, wrt)
