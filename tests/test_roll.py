"""Free roll of the antisymmetric half wing (wingmdao.aero.roll; docs/maneuvers.md, "Rolling conditions").

Independent references, integrated by hand here (docs/maneuvers.md derives them):

* steady roll of a rigid rectangular strip wing, p = V delta c_l,delta int_ail y dy / (a int_0^s y^2 dy)
  with Glauert's thin-aerofoil flap effectiveness c_l,delta = 2 (pi - theta_h + sin theta_h),
  cos theta_h = 1 - 2 x_h/c (Glauert, *The Elements of Aerofoil and Airscrew Theory*, 2nd ed., 1947);
* the roll time constant tau = I_x / L_p of the rigid wing (one degree of freedom);
* the aileron reversal of a uniform wing flexible in torsion only, in steady roll, full-span aileron:
  (sec x - 1) / x^2 = c_m,delta / (2 (e c_l,delta + c_m,delta)), x^2 = q e c^2 a l^2 / GJ;
* the roll damping of the elliptic wing from Prandtl's lifting line, C_l,p = -(pi/4) A / (A + 4)
  (a_0 = 2 pi; the antisymmetric loading's Glauert series has the one term A_2), the limit of the
  antisymmetric vortex lattice at large aspect ratio.
"""

from pathlib import Path

import numpy as np
import pytest
import scipy.optimize as sopt

from wingmdao.aero import (aero_parameters, build_aeroelastic_system, cached_aeroelastic_system,
                           three_dimensional_parameters)
from wingmdao.aero.controls import ControlSurface, control_spec
from wingmdao.aero.roll import check_roll_inputs, half_wing_roll_inertia, steady_roll
from wingmdao.aero.vlm import flat_wing, station_influence
from wingmdao.beam.static import beam_forcing, beam_parameters, straight_beam
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import layout, pack

N, SEMI, RHO = 21, 10.0, 1.2
HINGE = 0.75
DELTA = float(np.radians(5.0))


def _glauert(hinge):
    """(c_l,delta, c_m,c/4,delta) of a plain flap on a thin aerofoil (per rad)."""
    th = np.arccos(1.0 - 2.0 * hinge)
    return 2.0 * (np.pi - th + np.sin(th)), -0.5 * np.sin(th) * (1.0 - np.cos(th))


def _wing(*, chord, V, span=(0.6, 1.0), GJ=1e12, ref=0.25, mu=1.0, inertia=3000.0, delta=DELTA, theory="strip"):
    r0, th0 = straight_beam(N, SEMI)
    bp = beam_parameters(r0, th0, EI_cc=1e12, GJ=GJ, EI_nn=1e13, EA=1e14, mass_per_length=mu)
    spec = control_spec([ControlSurface("aileron", hinge=HINGE, span=span, time_constant=0.02)], r0[:, 1])
    s = cached_aeroelastic_system(N, roll=True, controls=spec, aero_theory=theory)
    values = {**bp, **aero_parameters(N, chord=chord, ref_point=ref, airspeed=V, density=RHO),
              "body_roll_inertia": inertia}
    if theory == "vlm":
        values.update(three_dimensional_parameters("vlm", r0, chord, ref, 0.0, spec, antisymmetric=True))
    qd = beam_forcing(N, gravity=[0.0, 0.0, 0.0])
    qd.update(gust_velocity=np.zeros(N), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3),
              surface_command=[delta], roll_start=0.0)
    return s, values, pack(s.param_specs, values), pack(s.forcing_specs, qd), r0, bp


def test_rigid_steady_roll_rate_closed_form():
    """Rigid rectangular wing, aileron on nodes 12..20 (y = 6 .. 10 m): the node-valued flap lift is
    interpolated linearly along the elements, so the strips' aileron starts halfway between nodes 11 and
    12 (y_1 = 5.75 m); p b/(2V) within 0.2 % of the closed form (measured 0.03 %). The aileron's own
    start at node 12 (y_1 = 6 m) is 4.6 % off: the test can fail."""
    V, C, d = 50.0, 0.1, np.radians(5.0)
    s, _, p, q, r0, _ = _wing(chord=C, V=V, delta=d)
    x = steady_roll(s, p, q)
    rate = x[s.body_index["roll_rate"]]
    cld, _ = _glauert(HINGE)
    a = 2.0 * np.pi
    y1 = 0.5 * (r0[11, 1] + r0[12, 1])
    # C_l,delta / C_l,p per half wing: int_y1^s c c_l,delta y dy / (int_0^s c a y^2 dy / s) (pb/2V per rad)
    pb2v = d * cld * (SEMI ** 2 - y1 ** 2) / 2.0 / (a * SEMI ** 3 / 3.0) * SEMI
    assert rate * SEMI / V == pytest.approx(pb2v, rel=2e-3)
    assert rate * SEMI / V != pytest.approx(d * cld * (SEMI ** 2 - 36.0) / 2.0 / (a * SEMI ** 3 / 3.0) * SEMI,
                                            rel=2e-2)
    # the sign: trailing edge down on the right wing lifts it: p > 0 (right wing up, +x aft)
    assert rate > 0


def test_roll_time_constant_rigid_wing():
    """Sudden aileron (20 ms actuator) on the rigid wing: past the actuator and Wagner transients
    ln(1 - p/p_ss) is a line of slope -1/tau, tau = (I_body/2 + I_wing + I_am) / L_p with
    L_p = rho V c a s^3 / 6 (one half, strip theory), I_wing = int mu y^2 dy, I_am = int pi rho b^2 y^2 dy
    (the strips' apparent mass). Within 1.5 % (measured 0.9 %: Wagner's lag raises the circulatory
    damping at the decay rate, phi(s = -1/tau) = 1.009 of Jones' approximation)."""
    V, C, I_half = 50.0, 0.1, 3000.0
    s, _, p, q, r0, bp = _wing(chord=C, V=V, inertia=I_half)
    pss = steady_roll(s, p, q)[s.body_index["roll_rate"]]
    dt = 0.005
    t = np.arange(401) * dt
    Q = np.tile(q, (t.size, 1))
    ql = layout(s.forcing_specs)
    Q[0, ql["surface_command"]] = 0.0
    Q[0, ql["roll_start"]] = 1.0
    rate = march(s, t, p, Q, modified_newton=True).states[:, s.body_index["roll_rate"]]
    m = (t > 0.3) & (t < 1.5)
    tau = -1.0 / np.polyfit(t[m], np.log(1.0 - rate[m] / pss), 1)[0]
    i_wing = 1.0 * SEMI ** 3 / 3.0
    i_am = np.pi * RHO * (C / 2) ** 2 * SEMI ** 3 / 3.0
    lp = RHO * V * C * 2 * np.pi * SEMI ** 3 / 6.0
    assert tau == pytest.approx((I_half + i_wing + i_am) / lp, rel=0.015)
    assert half_wing_roll_inertia(bp["mass_per_length"], r0) == pytest.approx(i_wing, rel=2e-3)
    assert rate[-1] == pytest.approx(pss * (1.0 - np.exp(-t[-1] / tau)), rel=2e-3)  # the march tends to p_ss


def _reversal_closed_form(GJ, chord, e, hinge):
    """q_R (Pa) of the uniform torsion-only wing in steady roll with a full-span aileron."""
    cld, cmd = _glauert(hinge)
    rhs = cmd / (2.0 * (e * cld + cmd))
    x = sopt.brentq(lambda x: (1.0 / np.cos(x) - 1.0) / x ** 2 - rhs, 1e-3, np.pi / 2 - 1e-6)
    return x ** 2 * GJ / (e * chord ** 2 * 2 * np.pi * SEMI ** 2)


def _effectiveness_closed_form(qd, GJ, chord, e, hinge):
    """(p/delta) / (p/delta)_rigid of the same wing at dynamic pressure qd (Pa)."""
    cld, cmd = _glauert(hinge)
    a = 2 * np.pi
    lam = np.sqrt(qd * e * chord ** 2 * a / GJ)
    x = lam * SEMI
    ak = cld + cmd / e
    s1 = (np.sin(x) - x * np.cos(x)) / lam ** 2
    bracket = (cld - ak) * SEMI ** 2 / 2 + ak * (1 / np.cos(x) - 1) / lam ** 2
    return bracket * lam * np.cos(x) / (a * s1) / (3 * cld / (2 * a * SEMI))


def test_aileron_reversal_torsion_only_wing():
    """Uniform wing rigid in bending, GJ = 2e5 N m^2, elastic axis 5 % chord aft of the quarter
    chord, full-span 25 % aileron: the roll effectiveness falls with q (against the closed form within
    2 % of the rigid value at three speeds) and reverses at q_R of the closed form within 1 %."""
    GJ, C, e = 2.0e5, 1.0, 0.05
    qr = _reversal_closed_form(GJ, C, e, HINGE)
    v_r = np.sqrt(2 * qr / RHO)
    s, values, p0, q, r0, _ = _wing(chord=C, V=v_r, span=(0.0, 1.0), GJ=GJ, ref=0.25 + e, mu=10.0)
    al = layout(s.param_specs)["airspeed"]
    cld, _ = _glauert(HINGE)
    d = np.radians(5.0)

    def effectiveness(V):
        p = p0.copy()
        p[al] = V
        rate = steady_roll(s, p, q)[s.body_index["roll_rate"]]
        return rate / (V * d * 3 * cld / (2 * 2 * np.pi * SEMI))

    eff = [effectiveness(v) for v in (0.4 * v_r, 0.7 * v_r, 0.9 * v_r)]
    ref = [_effectiveness_closed_form(0.5 * RHO * v ** 2, GJ, C, e, HINGE) for v in (0.4 * v_r, 0.7 * v_r, 0.9 * v_r)]
    assert eff[0] > eff[1] > eff[2] > 0
    np.testing.assert_allclose(eff, ref, atol=0.02)
    v_model = sopt.brentq(effectiveness, 0.9 * v_r, 1.1 * v_r, xtol=1e-6)
    assert 0.5 * RHO * v_model ** 2 == pytest.approx(qr, rel=0.01)


@pytest.mark.parametrize("aspect, tol", [(20.0, 0.035), (40.0, 0.015)])
def test_antisymmetric_lattice_roll_damping_tends_to_lifting_line(aspect, tol):
    """Elliptic flat wing, the lattice with its antisymmetric image: C_l,p (both halves, on S b) from
    the station influence of the incidence -y/s (pb/2V = 1) against Prandtl's -(pi/4) A / (A + 4),
    below it by the lifting-surface effect that vanishes as 1/A (measured -2.8 % at A = 20, -1.1 %
    at 40; the symmetric lift slope is 0.4 % below Prandtl's at 40)."""
    s = 1.0
    c0 = 8 * s / (np.pi * aspect)
    r, c, ref = flat_wing(s, lambda y: c0 * np.sqrt(np.clip(1 - (y / s) ** 2, 0, None)) + 1e-6, n_stations=31)
    area = np.pi * s * c0 / 2
    y = r[:, 1]

    inf = station_influence(r, c, ref, antisymmetric=True)
    clp = 2 * np.sum(inf.tributary * (inf.lift @ (-y / s)) * y) / (area * 2 * s)
    ref_ll = -(np.pi / 4) * aspect / (aspect + 4)
    assert clp == pytest.approx(ref_ll, rel=tol)
    assert clp > ref_ll


def test_vlm_rigid_steady_roll_is_the_lattice_balance():
    """The rolling residual with the antisymmetric lattice (aileron as lattice panels): the steady roll
    rate of the rigid rectangular wing equals the lattice's moment balance
    p / V = w^T F_L delta / (w^T A_L y) (w the beam's consistent rolling-moment weights of the node
    loads, linear between nodes) within 0.5 %, and is below the strips' (tip loss)."""
    V, C = 50.0, 1.0
    s, values, p, q, r0, _ = _wing(chord=C, V=V, theory="vlm")
    rate = steady_roll(s, p, q)[s.body_index["roll_rate"]]
    y = r0[:, 1]
    h = np.diff(y)
    w = np.zeros(N)
    w[:-1] += h / 6 * (2 * y[:-1] + y[1:])
    w[1:] += h / 6 * (y[:-1] + 2 * y[1:])
    A = values["lift_influence"]
    F = values["flap_lift_influence"]
    ref = V * (w @ F @ np.full(F.shape[1], DELTA)) / (w @ A @ y)
    assert rate == pytest.approx(ref, rel=5e-3)
    _, _, p_strip, q_strip, _, _ = _wing(chord=C, V=V)
    assert rate < 0.97 * steady_roll(cached_aeroelastic_system(N, roll=True, controls=s.controls), p_strip,
                                     q_strip)[s.body_index["roll_rate"]]


def test_bad_inputs():
    with pytest.raises(ValueError, match=r"body_roll_inertia = 0.0 kg\*m\*\*2; allowed range \(0, inf\)"):
        check_roll_inputs(body_roll_inertia=0.0)
    with pytest.raises(ValueError, match="roll=True is the antisymmetric half wing: it excludes plunge"):
        build_aeroelastic_system(3, roll=True, plunge=True)
    with pytest.raises(ValueError, match="steady_roll needs a system built with roll=True"):
        steady_roll(cached_aeroelastic_system(3), None, None)


def _roll_problem(n=3, n_time=8, dt=0.01):
    import openmdao.api as om

    from wingmdao.components.aeroelastic import AeroelasticBeamDynamics

    r0, th0 = straight_beam(n, 2.0)
    bp = beam_parameters(r0, th0, EI_cc=5e4, GJ=2e4, EI_nn=5e5, EA=5e6, mass_per_length=5.0)
    ap = aero_parameters(n, chord=1.0, ref_point=0.4, airspeed=20.0, density=RHO, mach=0.3)
    spec = control_spec([ControlSurface("aileron", hinge=0.75, nodes=(1, 2), time_constant=0.02)], r0[:, 1])
    s = cached_aeroelastic_system(n, roll=True, controls=spec)
    t = np.arange(n_time) * dt
    prob = om.Problem()
    prob.model.add_subsystem("beam", AeroelasticBeamDynamics(num_nodes=n, time=t, matrix_free=False, system=s),
                             promotes=["*"])

    class RootBendingKS(om.ExplicitComponent):
        """KS aggregate of the rolling root bending moment history (kN m), rho = 5."""

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
    values = {**bp, **ap, "body_roll_inertia": 50.0}
    for spec_ in s.param_specs:
        prob.set_val(spec_.name, np.asarray(values[spec_.name]).reshape(spec_.shape or (1,)))
    prob.set_val("surface_command", np.where(t[:, None] > 0, np.radians(10.0), 0.0))
    prob.set_val("gravity", np.zeros((n_time, 3)))
    prob.set_val("roll_start", (t == 0) * 1.0)
    return prob


def test_rolling_root_bending_ks_adjoint_totals():
    """d KS(root bending of a sudden aileron roll) / d(stiffness, body_roll_inertia, airspeed): the
    discrete adjoint through the roll states against central differences (check_totals)."""
    prob = _roll_problem()
    prob.run_model()
    wrt = ["stiffness_csn", "body_roll_inertia", "airspeed"]
    rev = prob.compute_totals(of=["ks"], wrt=wrt)
    fd = prob.check_totals(of=["ks"], wrt=wrt[:1], method="fd", form="central", step=1.0, out_stream=None)
    fd.update(prob.check_totals(of=["ks"], wrt=wrt[1:], method="fd", form="central", step=1e-4, out_stream=None))
    for w in wrt:
        ref = fd[("ks", w)]["J_fd"]
        scale = np.max(np.abs(ref))
        assert scale > 0, w
        np.testing.assert_allclose(rev[("ks", w)], ref, rtol=0, atol=1e-4 * scale)


def test_component_check_partials_roll():
    """AeroelasticBeamDynamics of the rolling half wing: its CasADi partials (roll states and
    body_roll_inertia included) against central differences."""
    prob = _roll_problem(n_time=4)
    prob.run_model()
    data = prob.check_partials(out_stream=None, method="fd", step=1e-6, form="central", includes=["beam"])
    for (of, wrt), d in data["beam"].items():
        fd, an = d["J_fd"], d["J_fwd"]
        scale = max(np.max(np.abs(fd)), 1e-8)
        assert np.max(np.abs(an - fd)) <= 2e-5 * scale + 1e-6, (of, wrt)


def test_sizing_case_rolling_totals():
    """A PEGASUS rolling load case (sudden aileron at V_A, strips, 0.3 s) in the sizing model
    (``CoupledAero(roll=True)``): the stress KS totals w.r.t. a wall thickness and the fuselage's roll
    inertia (the case input ``body_roll_inertia``) by the adjoint against central differences."""
    from wingmdao.aero.controls import read_alleviation
    from wingmdao.aero.coupled import CoupledAero
    from wingmdao.cases import pegasus
    from wingmdao.cases.planform import wing_geometry
    from wingmdao.groups.load_case import LoadCase
    from wingmdao.sizing import build_problem

    setup = pegasus.build(pegasus.PegasusOptions(loads="maneuver"))
    setup.options.disp = False
    geo = setup.geometry
    _, chord, axis = wing_geometry(pegasus.PLANFORM, pegasus.ENGINES)
    surfaces, _ = read_alleviation(str(Path(__file__).resolve().parents[1] / "docs/examples/pegasus_ailerons.yaml"))
    spec = control_spec(surfaces, geo.node_positions[:, 1])
    time = np.arange(11) * 0.03
    start = (time == 0) * 1.0
    command = np.where(time[:, None] > 0, np.radians(20.0), 0.0)
    aero = CoupledAero(chord=np.asarray(chord, dtype=float), ref_point=np.asarray(axis, dtype=float), airspeed=123.3,
                       density=0.6527, mach=0.39, roll=True, roll_inertia=2.0e4, controls=spec)
    case = LoadCase("roll", time, {"gravity": np.zeros(3), "roll_start": start, "surface_command": command},
                    setup.load_cases[0].families, "rolling, V_A", aero=aero)
    prob, _ = build_problem(geo, [case], setup.material, setup.options, driver=False)
    prob.run_model()
    X = np.asarray(prob.get_val("cases.roll.states")).reshape(time.size, -1)
    s = cached_aeroelastic_system(geo.num_nodes, roll=True, controls=spec)
    assert np.all(np.diff(X[:, s.body_index["roll_rate"]][1:]) > 0)  # the wing starts to roll (right wing up)
    wrt = ["t_upper_skin", "cases.roll.body_roll_inertia"]
    data = prob.check_totals(of=["cases.roll.ks_vm"], wrt=wrt, method="fd", form="central", step=1e-6,
                             step_calc="rel_avg", out_stream=None)
    for key, d in data.items():
        J = d["J_fwd"] if "J_fwd" in d else d["J_rev"]
        assert np.abs(d["J_fd"]).max() > 0, key
        assert np.abs(J - d["J_fd"]).max() <= 1e-6 * np.abs(d["J_fd"]).max(), key
    with pytest.raises(ValueError, match="roll=True is the antisymmetric half wing; it excludes plunge"):
        CoupledAero(chord=1.0, airspeed=50.0, density=1.2, roll=True, roll_inertia=1.0, plunge=True,
                    aircraft_mass=1000.0).parameters(3)
    with pytest.raises(ValueError, match="roll_inertia = 0.0 kg"):
        CoupledAero(chord=1.0, airspeed=50.0, density=1.2, roll=True).parameters(3)


def test_sizing_case_rolling_combined_with_symmetric():
    """25.349(a) at 2/3 n_lim in the sizing model: a rolling case with ``symmetric`` (the strip loads'
    static maneuver) has, at every instant, the stresses of the separately computed symmetric case
    plus (right wing) and minus (left wing) those of the rolling increments alone: the box stresses
    recovered from each case's own internal loads are linear in them and add. Its stress KS has
    exact totals (the march's adjoint for the increment, the static beam's for the symmetric part)."""
    import openmdao.api as om

    from wingmdao.aero.controls import read_alleviation
    from wingmdao.aero.coupled import CoupledAero
    from wingmdao.cases import pegasus
    from wingmdao.cases.planform import wing_geometry
    from wingmdao.components.stress import BoxStress
    from wingmdao.groups.load_case import LoadCase
    from wingmdao.sizing import build_problem

    setup = pegasus.build(pegasus.PegasusOptions(loads="maneuver"))
    setup.options.disp = False
    geo = setup.geometry
    n = geo.num_nodes
    _, chord, axis = wing_geometry(pegasus.PLANFORM, pegasus.ENGINES)
    surfaces, _ = read_alleviation(str(Path(__file__).resolve().parents[1] / "docs/examples/pegasus_ailerons.yaml"))
    spec = control_spec(surfaces, geo.node_positions[:, 1])
    time = np.arange(11) * 0.03
    forcing = {"gravity": np.zeros(3), "roll_start": (time == 0) * 1.0,
               "surface_command": np.where(time[:, None] > 0, np.radians(20.0), 0.0)}
    aero = CoupledAero(chord=np.asarray(chord, dtype=float), ref_point=np.asarray(axis, dtype=float), airspeed=123.3,
                       density=0.6527, mach=0.39, roll=True, roll_inertia=2.0e4, controls=spec)
    sym = pegasus.maneuver_case("sym", 2.5 * 2 / 3, geo, chord, axis, ("vm",))
    cases = [LoadCase("inc", time, forcing, ("vm",), aero=aero), sym,
             LoadCase("comb", time, forcing, ("vm",), aero=aero, symmetric=sym)]
    prob, _ = build_problem(geo, cases, setup.material, setup.options, driver=False)
    prob.run_model()
    F = {c: np.asarray(prob.get_val(f"cases.{c}.internal_loads.F_csn")) for c in ("inc", "sym")}
    M = {c: np.asarray(prob.get_val(f"cases.{c}.internal_loads.M_csn")) for c in ("inc", "sym")}
    # the box stresses of each state from its own loads, separately: [increment, symmetric, their sum]
    k = int(np.argmax(np.abs(M["inc"][:, 0, 0])))   # the instant of the largest root bending increment
    assert abs(M["inc"][k, 0, 0]) > 0.02 * abs(M["sym"][0, 0, 0]) > 0
    rows = lambda a, b: np.stack([a["inc"][k], b["sym"][0], a["inc"][k] + b["sym"][0], b["sym"][0] - a["inc"][k]])
    p2 = om.Problem()
    p2.model.add_subsystem("s", BoxStress(num_times=4, num_stations=n, material=setup.material, families=("vm",)),
                           promotes=["*"])
    p2.setup()
    p2.set_val("F_csn", rows(F, F))
    p2.set_val("M_csn", rows(M, M))
    for name in ("width", "height", "t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar"):
        p2.set_val(name, prob.get_val(f"cases.comb.stress.{name}"))
    p2.run_model()
    for out in ("sigma_corner", "tau_cent"):
        s_ = np.asarray(p2.get_val(out))
        scale = np.abs(s_).max()
        assert np.abs(s_[2] - (s_[0] + s_[1])).max() <= 1e-9 * scale, out     # linear in the loads: they add
        assert np.abs(s_[3] - (s_[1] - s_[0])).max() <= 1e-9 * scale, out
    g_sep = np.asarray(p2.get_val("g_vm"))
    g = np.asarray(prob.get_val("cases.comb.stress.g_vm"))
    assert g.shape[0] == 2 * time.size
    scale = np.abs(g_sep[1]).max()
    assert np.abs(g[k] - g_sep[2]).max() <= 1e-6 * scale            # right wing: symmetric + increment
    assert np.abs(g[time.size + k] - g_sep[3]).max() <= 1e-6 * scale   # left wing: symmetric - increment
    assert np.abs(g[k] - g_sep[1]).max() > 1e-3 * scale              # the increment matters at this instant
    assert prob.get_val("cases.comb.ks_vm")[0] > max(prob.get_val("cases.inc.ks_vm")[0], prob.get_val("cases.sym.ks_vm")[0])
    wrt = ["t_upper_skin", "cases.comb.body_roll_inertia"]
    data = prob.check_totals(of=["cases.comb.ks_vm"], wrt=wrt, method="fd", form="central", step=1e-6,
                             step_calc="rel_avg", out_stream=None)
    for key, d in data.items():
        J = d["J_fwd"] if "J_fwd" in d else d["J_rev"]
        assert np.abs(d["J_fd"]).max() > 0, key
        assert np.abs(J - d["J_fd"]).max() <= 1e-6 * np.abs(d["J_fd"]).max(), key
    with pytest.raises(ValueError, match="symmetric must be a static structural LoadCase"):
        LoadCase("bad", time, forcing, ("vm",), aero=aero, symmetric=cases[0])


def test_symmetric_load_combination_partials():
    """SymmetricLoadCombination: symmetric ± increment, its sparse partials against central differences."""
    import openmdao.api as om

    from wingmdao.components.load_combination import SymmetricLoadCombination

    rng = np.random.default_rng(3)
    prob = om.Problem()
    prob.model.add_subsystem("c", SymmetricLoadCombination(num_times=4, num_nodes=3), promotes=["*"])
    prob.setup(force_alloc_complex=False)
    for k in ("F_csn", "M_csn"):
        prob.set_val(f"symmetric_{k}", rng.normal(size=(1, 3, 3)))
        prob.set_val(f"increment_{k}", rng.normal(size=(4, 3, 3)))
    prob.run_model()
    s, d = prob.get_val("symmetric_M_csn"), prob.get_val("increment_M_csn")
    assert np.allclose(prob.get_val("M_csn")[:4], s + d) and np.allclose(prob.get_val("M_csn")[4:], s - d)
    data = prob.check_partials(method="fd", form="central", out_stream=None)
    for key, d_ in data["c"].items():
        assert np.abs(d_["J_fwd"] - d_["J_fd"]).max() <= 1e-6, key


def test_size_pegasus_rolling_cases_and_bad_options():
    """``size pegasus --rolling``: the three 25.349(a) cases join the load set (V_C and V_D
    deflections from the steady roll of the initial design, below the stops), the outputs are named
    ``pegasus_..._rolling``, and the rolling options are refused without ``--rolling`` or with
    missing data."""
    import argparse

    from wingmdao.cases import pegasus
    from wingmdao.cli.size import run_stem

    ail = str(Path(__file__).resolve().parents[1] / "docs/examples/pegasus_ailerons.yaml")
    setup = pegasus.build(pegasus.PegasusOptions(rolling=True, alleviation=ail, roll_inertia=2e4,
                                                 maneuvering_speed_eas=90.0, dt=0.1))
    names = [c.name for c in setup.load_cases]
    assert names == ["maneuver_pos", "maneuver_neg", "rolling_va", "rolling_vc", "rolling_vd"]
    cmd = [c.forcing["surface_command"][-1, 0] for c in setup.load_cases[2:]]
    assert cmd[0] == pytest.approx(np.radians(20.0)) and 0 < cmd[2] < cmd[1] < cmd[0]
    assert all(c.aero.roll and c.time.size == 21 for c in setup.load_cases[2:])
    ns = argparse.Namespace(case_module=pegasus, loads="maneuver", rolling=True)
    assert run_stem(ns) == "pegasus_maneuver_rolling"
    for kw, msg in [({"roll_inertia": 2e4}, "--roll-inertia is a --rolling option"),
                    ({"rolling": True, "roll_inertia": 2e4, "maneuvering_speed_eas": 90.0},
                     "--rolling needs --alleviation FILE.yaml"),
                    ({"rolling": True, "alleviation": ail, "maneuvering_speed_eas": 90.0}, "--rolling needs --roll-inertia"),
                    ({"rolling": True, "alleviation": ail, "roll_inertia": 0.0, "maneuvering_speed_eas": 90.0},
                     r"--roll-inertia = 0.0 kg\*m\*\*2; allowed range \(0, inf\)"),
                    ({"rolling": True, "alleviation": ail, "roll_inertia": 2e4, "maneuvering_speed_eas": 200.0},
                     r"--maneuvering-speed-eas = 200.0 m/s; allowed range \(0, V_C = 115.34\]")]:
        with pytest.raises(ValueError, match=msg):
            pegasus.build(pegasus.PegasusOptions(**kw))
