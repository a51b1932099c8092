"""The control surfaces' deflection and rate limits as constraints of the co-design (docs/controls.md,
"Actuator limits"): the gust march's ``actuator_ks`` (:class:`wingmdao.components.actuator_limits.ActuatorLimitKS`)
and the turbulence constraint's ``turbulence_actuator_ks`` (U_sigma A-bar of the deflection and rate
over the limits), their exact totals against central differences, their values against independent
computations, and a co-design whose optimum holds the deflection limit, checked by a separate
``wingmdao gust`` run on the sized wing."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import openmdao.api as om
import pytest

from wingmdao.aero import aero_parameters, cached_aeroelastic_system
from wingmdao.aero.controls import ControlLaw, ControlSurface, control_spec
from wingmdao.beam.residual import StrainRateDamping
from wingmdao.beam.static import beam_parameters, straight_beam
from wingmdao.components.actuator_limits import ActuatorLimitKS
from wingmdao.utils.ks import ks_value

EXAMPLE = "docs/examples/pegasus_alleviation.yaml"


def test_actuator_limit_ks_value_and_partials():
    """The KS lies between the largest |ratio| and that plus ln(4 n_t n_s)/rho (the ratios formed by
    hand from the state columns); check_partials against central differences."""
    rng = np.random.default_rng(3)
    nt, shape = 7, (5, 2)
    comp = ActuatorLimitKS(num_times=nt, state_shape=shape, deflection_index=np.array([3, 8]),
                           rate_index=np.array([4, 9]), max_deflection=np.radians([20.0, 15.0]),
                           max_rate=np.radians([60.0, 45.0]), rho_ks=30.0)
    prob = om.Problem()
    prob.model.add_subsystem("lim", comp, promotes=["*"])
    prob.setup(force_alloc_complex=True)
    states = rng.normal(scale=0.3, size=(nt,) + shape)
    prob.set_val("states", states)
    prob.run_model()
    flat = states.reshape(nt, -1)
    by_hand = np.column_stack([flat[:, 3] / np.radians(20.0), flat[:, 8] / np.radians(15.0),
                               flat[:, 4] / np.radians(60.0), flat[:, 9] / np.radians(45.0)])
    ks = float(prob.get_val("actuator_ks")[0])
    peak = np.max(np.abs(by_hand))
    assert peak <= ks <= peak + np.log(2 * by_hand.size) / 30.0
    assert ks == pytest.approx(ks_value(np.r_[by_hand.ravel(), -by_hand.ravel()], 30.0), rel=1e-12)
    data = prob.check_partials(method="fd", form="central", step=1e-7, out_stream=None)
    d = data["lim"]["actuator_ks", "states"]
    assert np.abs(d["J_fwd"] - d["J_fd"]).max() <= 1e-6 * np.abs(d["J_fd"]).max()
    with pytest.raises(ValueError, match="allowed range"):
        bad = om.Problem()
        bad.model.add_subsystem("lim", ActuatorLimitKS(num_times=2, state_shape=(4,), deflection_index=np.array([0]),
                                                       rate_index=np.array([1]), max_deflection=np.array([0.0]),
                                                       max_rate=np.array([1.0])))
        bad.setup()


def _pegasus_codesign(alleviation, size_gains=True, t_final=0.6):
    from wingmdao.cases import pegasus

    return pegasus.build(pegasus.PegasusOptions(loads="gust", aero="coupled", aero_theory="strip", plunge="free",
                                                t_final=t_final, dt=0.03, gust_start=0.0, alleviation=alleviation,
                                                size_gains=size_gains))


def test_gust_actuator_ks_totals_against_central_differences():
    """PEGASUS gust case (free plunge, strip theory, 0.6 s) with the example law in the sizing model at a
    non-trivial design (gains C = -0.6, D = -0.3 rad/g, a tapered upper skin): the totals of
    ``actuator_ks`` with respect to the gains and a wall by the march's adjoint against central
    differences within 1e-6 of the largest entry; with --size-gains it is a constraint (<= 1), with
    fixed gains an output only."""
    from wingmdao.sizing import actuator_limit_outputs, build_problem

    setup = _pegasus_codesign(EXAMPLE)
    assert actuator_limit_outputs(setup.load_cases, sized_only=True) == ["cases.gust.actuator_ks"]
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
    prob.set_val("cases.gust.controller_C", [[-0.6]])
    prob.set_val("cases.gust.controller_D", [[-0.3]])
    prob.set_val("t_upper_skin", np.linspace(0.012, 0.004, 19))
    prob.run_model()
    ks = float(prob.get_val("cases.gust.actuator_ks")[0])
    assert 0.3 < ks < 2.0, ks
    wrt = ["t_upper_skin", "cases.gust.controller_C", "cases.gust.controller_D"]
    data = prob.check_totals(of=["cases.gust.actuator_ks"], wrt=wrt, method="fd", form="central", step=1e-6,
                             step_calc="rel_avg", out_stream=None)
    for key, d in data.items():
        J = d["J_rev"] if "J_rev" in d else d["J_fwd"]
        assert np.abs(d["J_fd"]).max() > 1e-3, key
        assert np.abs(J - d["J_fd"]).max() <= 1e-6 * np.abs(d["J_fd"]).max(), key
    driven, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=True)
    driven.final_setup()
    cons = driven.model.get_constraints()
    assert cons["cases.gust.actuator_ks"]["upper"] == pytest.approx(1.0)
    fixed = _pegasus_codesign(EXAMPLE, size_gains=False)
    assert actuator_limit_outputs(fixed.load_cases) == ["cases.gust.actuator_ks"]
    assert actuator_limit_outputs(fixed.load_cases, sized_only=True) == []
    fixed_prob, _ = build_problem(fixed.geometry, fixed.load_cases, fixed.material, fixed.options, driver=True)
    fixed_prob.final_setup()
    assert "cases.gust.actuator_ks" not in fixed_prob.model.get_constraints()


N, V, SPAN, MASS, G = 4, 40.0, 8.0, 300.0, 9.81
X_LE = straight_beam(N, SPAN)[0][:, 0] - 0.35 + np.array([0.0, 0.3, 0.6, 0.9])
SURFACES = (ControlSurface("aileron", hinge=0.75, nodes=(2, 3), actuator_order=2, frequency_hz=15.0, damping=0.7,
                           max_deflection_deg=2.0, max_rate_deg_s=15.0),)
#: filtered root bending and tip acceleration feedthrough (a clamped wing): all four matrices non-zero
LAW = ControlLaw(("root_bending", "tip_acceleration"), A=[[-8.0]], B=[[8.0, 0.0]], C=[[-3.0]], D=[[0.0, -0.02]])
LIMITS = ((np.radians(2.0), np.radians(15.0)),)


def _turbulence_problem():
    from wingmdao.components.turbulence import TurbulenceStressKS
    from wingmdao.section.box import WALL_NAMES

    r0, th0 = straight_beam(N, SPAN)
    bp = beam_parameters(r0, th0, EI_cc=2e5, GJ=1e5, EI_nn=1e7, EA=1e9, mass_per_length=5.0)
    ap = aero_parameters(N, chord=1.0, ref_point=0.35, airspeed=V, density=1.0)
    values = {**bp, **ap, "trim_lift": MASS * G}
    prob = om.Problem()
    comp = TurbulenceStressKS(num_nodes=N, plunge=False, airspeed=V, airspeed_input=True, x_stations=X_LE, width=np.full(N, 0.5),
                              height=np.full(N, 0.12), u_sigma=10.0, sigma_allow=1e8, f_max=10.0, n_base=31,
                              damping=StrainRateDamping.from_damping_ratio(0.02, 2.0), gravity=G,
                              controls=control_spec(SURFACES, r0[:, 1], LAW), control_law=LAW, surface_limits=LIMITS)
    prob.model.add_subsystem("turb", comp, promotes=["*"])
    prob.setup()
    prob.final_setup()
    inputs = {nm for nm, _ in comp.list_inputs(out_stream=None)}
    for name, v in values.items():
        if name in inputs:
            prob.set_val(name, v)
    for k, w in enumerate(WALL_NAMES):
        prob.set_val(w, np.array([0.003, 0.0025, 0.004, 0.0035])[k] * np.linspace(1, 0.6, N))
    prob.run_model()
    return prob, comp


def test_turbulence_actuator_ks_value_and_totals():
    """The clamped 4-node wing with an aileron (second-order actuator, 15 Hz) and a law with all four
    matrices non-zero: U_sigma A-bar of the deflection and rate over their limits equal the A-bar of the
    surface outputs of the linear gust model (:func:`~wingmdao.loads.turbulence_analysis.control_outputs`,
    :func:`~wingmdao.stability.frequency.frequency_response`) integrated on the same grid (1e-8); the KS
    of both within ln 2 / rho of the larger; its totals with respect to the four gain matrices and the
    mass per length and the airspeed (aerodynamics, gust phases, spectrum) against central differences
    within 1e-5 of the largest entry."""
    from wingmdao.loads.turbulence import von_karman_psd
    from wingmdao.loads.turbulence_analysis import control_outputs
    from wingmdao.stability.frequency import frequency_response, linear_gust_model
    from wingmdao.stability.frequency_adjoint import quadrature_weights
    from wingmdao.timemarch.bdf import solve_static
    from wingmdao.timemarch.system import layout, pack

    prob, comp = _turbulence_problem()
    ratios = comp.actuator_ratios()["aileron"]
    # the A-bar of the surface outputs by the frequency response of the analysis path
    system = cached_aeroelastic_system(N, damping=comp.options["damping"], plunge=False, trim=True,
                                       controls=comp.options["controls"])
    values = {s.name: np.asarray(prob.get_val(s.name)).reshape(s.shape) for s in comp.specs}
    values["airspeed"] = V
    p = pack(system.param_specs, values)
    ql = layout(system.forcing_specs)
    q = np.zeros(system.n_forcing)
    q[ql["gravity"].start + 2] = -G
    q[ql["trim_active"]] = 1.0
    x0, _ = solve_static(system, p, q)
    q[ql["trim_active"]] = 0.0
    model = linear_gust_model(system, p, q, x0, x_stations=X_LE, airspeed=V)
    resp = frequency_response(dataclasses.replace(model, outputs=control_outputs(system, x0)), comp.grid)
    w = comp.grid
    weights = quadrature_weights(w) * von_karman_psd(w, V)
    for key, limit, name in (("surface_deflection", LIMITS[0][0], "deflection"),
                             ("surface_rate", LIMITS[0][1], "rate")):
        H = np.asarray(resp.outputs[key]).reshape(w.size, -1)[:, 0]
        a_bar = np.sqrt(weights @ np.abs(H) ** 2)
        assert ratios[name] == pytest.approx(10.0 * a_bar / limit, rel=1e-8), name
    ks = float(prob.get_val("turbulence_actuator_ks")[0])
    top = max(ratios.values())
    assert top <= ks <= top + np.log(2) / 50.0
    assert top > 0.5, ratios
    names = ["controller_A", "controller_B", "controller_C", "controller_D", "mass_per_length", "airspeed"]
    J = prob.compute_totals("turbulence_actuator_ks", names)
    for name in names:
        base = prob.get_val(name).copy()
        fd = np.zeros(base.size)
        for k in range(base.size):
            h = 1e-5 * max(abs(base.flat[k]), 1.0 if name.startswith("controller") else 0.0)
            vals = []
            for sign in (1, -1):
                v = base.copy()
                v.flat[k] += sign * h
                prob.set_val(name, v)
                prob.run_model()
                vals.append(float(prob.get_val("turbulence_actuator_ks")[0]))
            fd[k] = (vals[0] - vals[1]) / (2 * h)
        prob.set_val(name, base)
        got = J["turbulence_actuator_ks", name].ravel()
        assert np.max(np.abs(fd)) > 0, name
        assert np.max(np.abs(got - fd)) <= 1e-5 * np.max(np.abs(fd)), (name, got, fd)


def _law_file(tmp_path, name, max_deflection_deg, C=-0.25, D=0.0):
    text = open(EXAMPLE, encoding="utf-8").read()
    text = text.replace("max_deflection_deg: 20.0", f"max_deflection_deg: {max_deflection_deg}")
    text = text.replace("max_rate_deg_s: 60.0", "max_rate_deg_s: 1000.0")
    text = text.replace("C: [[-0.25]]", f"C: [[{C!r}]]").replace("D: [[0.0]]", f"D: [[{D!r}]]")
    path = tmp_path / name
    path.write_text(text)
    return path


def _peak_deflection(tmp_path, design, law, tag):
    """The aileron's peak deflection (deg) of ``wingmdao gust`` on the sized wing with the sized law."""
    from wingmdao.cli import main

    out = tmp_path / f"gust_{tag}.json"
    assert main(["gust", "pegasus", "--aero", "coupled", "--aero-theory", "strip", "--plunge", "free", "--design",
                 str(design), "--alleviation", str(law), "--t-final", "0.6", "--dt", "0.03", "--gust-start", "0",
                 "--no-plots", "--out", str(tmp_path / f"gust_{tag}"), "--json", str(out)]) == 0
    res = json.loads(out.read_text())
    return res["alleviation"]["surfaces"]["aileron"]["peak_deflection_deg"]


@pytest.mark.slow
def test_codesign_holds_the_deflection_limit(tmp_path):
    """PEGASUS co-design (0.6 s gust, free plunge, strip theory): without a deflection limit (90 deg) the
    sized law deflects the aileron beyond 4 deg; with the limit 4 deg the constraint is active and
    ``wingmdao gust`` on the sized wing with the sized gains (a separate march) finds the peak
    deflection between 90 % of the limit and 1 % above it."""
    from wingmdao.cli import main

    peaks, results = {}, {}
    for tag, limit in (("free", 90.0), ("limited", 4.0)):
        law = _law_file(tmp_path, f"{tag}.yaml", limit)
        out = tmp_path / f"size_{tag}.json"
        assert main(["size", "pegasus", "--loads", "gust", "--aero", "coupled", "--aero-theory", "strip", "--plunge",
                     "free", "--alleviation", str(law), "--size-gains", "--t-final", "0.6", "--dt", "0.03",
                     "--gust-start", "0", "--no-plots", "--no-flutter-search", "--quiet", "--out", str(tmp_path / tag),
                     "--json", str(out)]) == 0
        res = json.loads(out.read_text())
        results[tag] = res
        gains = res["control_law"]["gust"]
        sized = _law_file(tmp_path, f"{tag}_sized.yaml", limit, C=float(np.ravel(gains["controller_C"])[0]),
                          D=float(np.ravel(gains["controller_D"])[0]))
        peaks[tag] = _peak_deflection(tmp_path, out, sized, tag)
    assert peaks["free"] > 4.0 * 1.05, peaks
    assert "cases.gust.actuator_ks" in results["limited"]["active_constraints"], results["limited"]["actuator_ks"]
    assert peaks["limited"] <= 4.0 * 1.01, peaks
    assert peaks["limited"] >= 4.0 * 0.9, peaks
    sized_peak = results["limited"]["actuator_peaks"]["gust"]["aileron"]["peak_deflection_deg"]
    assert sized_peak == pytest.approx(peaks["limited"], rel=1e-3)
