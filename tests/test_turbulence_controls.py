"""The control law in the continuous-turbulence frequency response (docs/controls.md, "The law in
continuous turbulence"): the actuators and the law are states of the residual, so its linearisation
carries them. Checked against the loop closed by hand on the open-loop transfer functions, against
the BDF2 march under a harmonic gust, and the turbulence constraint's partials with respect to the
gains against central differences; the command-line refusals."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from wingmdao.aero import aero_parameters, cached_aeroelastic_system
from wingmdao.aero.controls import ControlLaw, ControlSurface, control_spec
from wingmdao.beam.static import beam_parameters, straight_beam
from wingmdao.loads.atmosphere import G0
from wingmdao.loads.turbulence_analysis import control_outputs, gust_model_from_parameters
from wingmdao.stability.frequency import OutputMap, ShiftedFactors, frequency_response
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import layout

G = 9.81
N, V, SPAN, MASS = 4, 40.0, 8.0, 300.0
X_LE = straight_beam(N, SPAN)[0][:, 0] - 0.35 + np.array([0.0, 0.3, 0.6, 0.9])
SURFACES = (ControlSurface("aileron", hinge=0.75, nodes=(2, 3), actuator_order=2, frequency_hz=15.0, damping=0.7),)
#: a first-order filter (corner 8 rad/s) on the load factor, and feedthrough of the root bending:
#: all four matrices non-zero
LAW = ControlLaw(("load_factor", "root_bending"), A=[[-8.0]], B=[[8.0, 0.0]], C=[[-0.3]], D=[[0.0, -0.5]])


def _wing(law=LAW, plunge=True):
    """The flexible 4-node wing (free in plunge) with an aileron on its outer third and ``law``:
    ``(system, parameter values)``."""
    r0, th0 = straight_beam(N, SPAN)
    bp = beam_parameters(r0, th0, EI_cc=2e5, GJ=1e5, EI_nn=1e7, EA=1e9, mass_per_length=5.0)
    ap = aero_parameters(N, chord=1.0, ref_point=0.35, airspeed=V, density=1.0)
    s = cached_aeroelastic_system(N, plunge=plunge, trim=True, controls=control_spec(SURFACES, r0[:, 1], law))
    values = {**bp, **ap, "trim_lift": MASS * G, **law.matrices()}
    if plunge:
        values["body_mass"] = MASS - 2 * 5.0 * SPAN
    return s, values


def _zero_gains(law):
    return ControlLaw(law.outputs, law.A, law.B, np.zeros_like(law.C), np.zeros_like(law.D))


def test_closed_loop_response_equals_the_loop_closed_on_open_loop_transfer_functions():
    """The residual with the law as states against block-diagram algebra: the open-loop model (the
    same states, gains zero) gives the responses X_w to the gust and X_u to the surface command (the
    forcing ``surface_command``); with the measurements y = [dw_p/dt / g0, M_x,root / 1e6] and the
    controller K(i w) = C (i w - A)^-1 B + D the loop closes as u = (1 - K Y_u)^-1 K Y_w, and every
    output is Z_w + Z_u u. Equal within 1e-8 of the largest value over 0.1 to 15 Hz; the law changes
    the root bending response by more than 10 % somewhere (the check can fail)."""
    s, values = _wing()
    gm = gust_model_from_parameters(s, values, x_stations=X_LE, gravity=G)
    s0, v0 = _wing(_zero_gains(LAW))
    assert s0 is s  # the same residual; only the gains differ
    open_ = gust_model_from_parameters(s, v0, x_stations=X_LE, gravity=G)
    w = 2 * np.pi * np.geomspace(0.1, 15.0, 41)
    closed = frequency_response(gm.model, w).outputs
    opened = frequency_response(open_.model, w, keep_states=True)
    ql = layout(s.forcing_specs)
    _, dq = s.jac_inputs(open_.model.x0, np.zeros(s.n_state), open_.p, _lin(s, open_.q_static))
    Gu = sp.csc_matrix(dq)[:, ql["surface_command"]].toarray().ravel()
    fac = ShiftedFactors(open_.model.A, open_.model.E)
    i_p, i_m = s.layout.body["plunge"], s.layout.beam[0, 9]
    for k, om in enumerate(w):
        Xw = opened.states[k]
        Xu = fac.factor(1j * om).solve(-Gu)
        meas = lambda X: np.array([1j * om * X[i_p] / G0, X[i_m] / 1e6])  # the residual's units
        K = LAW.C @ np.linalg.solve(1j * om * np.eye(1) - LAW.A, LAW.B) + LAW.D  # (1, 2)
        u = (K @ meas(Xw)) / (1.0 - K @ meas(Xu))
        for name, m in open_.model.outputs.items():
            zw = opened.outputs[name][k]
            zu = m.Cx @ Xu + 1j * om * (m.Cv @ Xu)
            want = zw + zu * u[0]
            got = closed[name][k]
            assert np.max(np.abs(got - want)) <= 1e-8 * max(np.max(np.abs(want)), 1e-30), (name, om, got, want)
    rb_open, rb_closed = np.abs(opened.outputs["root_bending_moment"][:, 0]), np.abs(closed["root_bending_moment"][:, 0])
    assert np.max(np.abs(rb_closed / rb_open - 1)) > 0.1


def _lin(s, q_static):
    q = np.array(q_static, dtype=float)
    q[layout(s.forcing_specs)["trim_active"]] = 0.0
    return q


def test_closed_loop_frequency_response_equals_time_march_amplitude():
    """The BDF2 march of the same residual with the law, under a harmonic gust of 0.01 m/s at 2 Hz
    reaching each station with its delay (dt = 2 ms, 3.2 s from the trimmed 1 g state, a 0.2 s ramp):
    the steady amplitude and phase of the root bending moment, tip deflection, load factor (the
    march's own lift integral) and aileron deflection within 1e-3 of the linear response with
    i omega replaced by the BDF2 symbol (3 - 4/z + 1/z^2) / (2 dt) and within 5e-3 of the frequency
    response. The transient's slow modes (aerodynamic lags, plunge, the law's filter) are fitted with
    the harmonic."""
    from wingmdao.stability.eigen import eigenmodes

    s, values = _wing()
    gm = gust_model_from_parameters(s, values, x_stations=X_LE, gravity=G)
    model = gm.model
    ql = layout(s.forcing_specs)
    q0 = _lin(s, gm.q_static)
    om, U, dt = 2 * np.pi * 2.0, 0.01, 2e-3
    t = np.arange(int(3.2 / dt) + 1) * dt
    Q = np.tile(q0, (t.size, 1))
    Q[0] = gm.q_static
    lag = (model.x_stations - model.x_stations.min()) / V
    Q[:, ql["gust_velocity"]] = U * np.minimum(t / 0.2, 1.0)[:, None] * np.sin(om * (t[:, None] - lag[None, :]))
    h = march(s, t, gm.p, Q)
    beam = s.layout.beam_states(h.states)
    i_d = s.control_index["aileron_deflection"]
    series = {"root_bending_moment": beam[:, 0, 9], "tip_deflection": beam[:, -1, 2],
              "load_factor": s.total_lift_history(h.states, dt, gm.p, Q) / (MASS * G),
              "surface_deflection": h.states[:, i_d]}
    last = t >= 2.0
    lam = eigenmodes(s, gm.p, q0, model.x0, static=False).eigenvalues
    slow = lam[(lam.real < -0.1) & (lam.real > -15) & (np.abs(lam.imag) < 15)]
    tl = t[last] - t[last][0]
    basis = [np.sin(om * t[last]), np.cos(om * t[last]), np.ones(last.sum())]
    for r in slow[slow.imag >= 0]:
        basis += ([np.exp(r.real * tl)] if abs(r.imag) < 1e-9 else
                  [np.exp(r.real * tl) * np.cos(r.imag * tl), np.exp(r.real * tl) * np.sin(r.imag * tl)])
    basis = np.column_stack(basis)
    z = np.exp(1j * om * dt)
    s_h = (3 - 4 / z + 1 / z ** 2) / (2 * dt)
    wv = model.gust_vector([om])[0]
    X = np.linalg.solve((model.A + s_h * model.E).toarray(), -(model.G @ wv))
    H = frequency_response(model, [om]).outputs
    for name, y in series.items():
        coef, *_ = np.linalg.lstsq(basis, y[last], rcond=None)
        marched = (coef[0] + 1j * coef[1]) / U
        m = model.outputs[name]
        discrete = complex((m.Cx @ X + s_h * (m.Cv @ X) + m.D @ wv)[0])
        expected = complex(H[name][0, 0])
        print(f"{name}: march {marched:.6g}, BDF2 symbol {discrete:.6g}, H {expected:.6g}: "
              f"{abs(marched - discrete) / abs(discrete):.2e}, {abs(marched - expected) / abs(expected):.2e}")
        assert abs(marched - discrete) <= 1e-3 * abs(discrete), (name, marched, discrete)
        assert abs(marched - expected) <= 5e-3 * abs(expected), (name, marched, expected)
    assert abs(series["surface_deflection"][last]).max() > 0.0


def test_control_outputs_are_the_surface_states():
    """control_outputs: deflection and rate rows select the actuator states; none without surfaces."""
    s, values = _wing()
    x0 = np.arange(s.n_state, dtype=float)
    out = control_outputs(s, x0)
    for key, state in (("surface_deflection", "deflection"), ("surface_rate", "rate")):
        m = out[key]
        assert isinstance(m, OutputMap) and m.Cx.shape == (1, s.n_state)
        i = s.control_index[f"aileron_{state}"]
        assert m.Cx[0, i] == 1.0 and m.Cx.nnz == 1 and m.y0[0] == x0[i]
    assert control_outputs(cached_aeroelastic_system(N, plunge=True, trim=True), np.zeros(10)) == {}


def test_turbulence_stress_ks_partials_wrt_the_gains():
    """TurbulenceStressKS with the aileron and the law: its exact partials with respect to every
    entry of controller_A ... controller_D and a wall against central differences of the component's
    output (steps 1e-5 of each gain's scale), within 1e-5 of the largest; the law moves the KS."""
    import openmdao.api as om

    from wingmdao.beam.residual import StrainRateDamping
    from wingmdao.components.turbulence import TurbulenceStressKS
    from wingmdao.section.box import WALL_NAMES

    r0, _ = straight_beam(N, SPAN)
    s, values = _wing()

    def problem(law):
        prob = om.Problem()
        comp = TurbulenceStressKS(num_nodes=N, plunge=True, airspeed=V, x_stations=X_LE, width=np.full(N, 0.5),
                                  height=np.full(N, 0.12), u_sigma=10.0, sigma_allow=1e8, f_max=10.0, n_base=31,
                                  damping=StrainRateDamping.from_damping_ratio(0.02, 2.0), gravity=G,
                                  controls=control_spec(SURFACES, r0[:, 1], law), control_law=law)
        prob.model.add_subsystem("turb", comp, promotes=["*"])
        prob.setup()
        prob.final_setup()
        inputs = {nm for nm, _ in comp.list_inputs(out_stream=None)}
        for name, v in values.items():
            if name in inputs and not name.startswith("controller_"):
                prob.set_val(name, v)
        for k, w in enumerate(WALL_NAMES):
            prob.set_val(w, np.array([0.003, 0.0025, 0.004, 0.0035])[k] * np.linspace(1, 0.6, N))
        prob.run_model()
        return prob

    prob = problem(LAW)
    ks = float(prob.get_val("turbulence_ks")[0])
    ks0 = float(problem(_zero_gains(LAW)).get_val("turbulence_ks")[0])
    assert abs(ks - ks0) > 1e-3 * abs(ks0), (ks, ks0)
    names = ["controller_A", "controller_B", "controller_C", "controller_D", "t_upper_skin"]
    J = prob.compute_totals("turbulence_ks", names)
    for name in names:
        base = prob.get_val(name).copy()
        fd = np.zeros(base.size)
        for k in range(base.size):
            h = 1e-5 * max(abs(base.flat[k]), 1.0) if name.startswith("controller") else 1e-8
            vals = []
            for sign in (1, -1):
                v = base.copy()
                v.flat[k] += sign * h
                prob.set_val(name, v)
                prob.run_model()
                vals.append(float(prob.get_val("turbulence_ks")[0]))
            fd[k] = (vals[0] - vals[1]) / (2 * h)
        prob.set_val(name, base)
        got = J["turbulence_ks", name].ravel()
        print(name, got, fd)
        assert np.max(np.abs(got - fd)) <= 1e-5 * np.max(np.abs(fd)) + 1e-12, (name, got, fd)


def test_cli_turbulence_alleviation_refusals(capsys, tmp_path):
    """One-line errors before any solve: --alleviation with --aero strip, a load-factor law on the
    clamped wing (the vortex lattice and the doublet lattice), a missing file, a surface outside the span."""
    from wingmdao.cli import main

    law = tmp_path / "lf.yaml"
    law.write_text("surfaces:\n  - {name: a, span: [0.7, 1.0], hinge: 0.75}\nlaw: {outputs: [load_factor], gain: [-0.2]}\n")
    wide = tmp_path / "wide.yaml"
    wide.write_text("surfaces:\n  - {name: a, span: [0.7, 1.3], hinge: 0.75}\n")
    for argv, text in ((["--aero", "strip", "--clamped", "--alleviation", str(law)], "needs --aero coupled"),
                       (["--clamped", "--aero-theory", "dlm", "--alleviation", str(law)],
                        "output load_factor needs free plunge"),
                       (["--clamped", "--alleviation", str(law)], "output load_factor needs free plunge"),
                       (["--alleviation", str(tmp_path / "none.yaml")], "cannot read the file"),
                       (["--alleviation", str(wide)], "outside the semi-span")):
        assert main(["turbulence", "pegasus", "--no-plots", "--json", str(tmp_path / "t.json")] + argv) == 2
        err = capsys.readouterr().err
        assert text in err and "--alleviation" in err, (argv, err)
        assert not (tmp_path / "t.json").exists()


@pytest.mark.slow
def test_cli_turbulence_pegasus_alleviation(tmp_path):
    """`wingmdao turbulence pegasus --clamped --alleviation FILE` with a filtered root-bending law:
    the JSON's A-bar without the law equals the command without --alleviation, the law lowers the
    root bending A-bar, the surface's design deflection is U_sigma times its A-bar."""
    from wingmdao.cli import main

    law = tmp_path / "rb.yaml"
    law.write_text("surfaces:\n  - {name: aileron, span: [0.7, 1.0], hinge: 0.75, actuator: {order: 2, frequency_hz: "
                   "8.0, damping: 0.7}}\nlaw:\n  outputs: [root_bending]\n  state_space: {A: [[-6.0]], B: [[6.0]], "
                   "C: [[-0.5]], D: [[0.0]]}\n")
    common = ["turbulence", "pegasus", "--clamped", "--aero-theory", "strip", "--damping-ratio", "0.02",
              "--f-max-hz", "20", "--no-plots"]
    assert main(common + ["--alleviation", str(law), "--json", str(tmp_path / "a.json")]) == 0
    assert main(common + ["--json", str(tmp_path / "b.json")]) == 0
    a, b = (json.loads((tmp_path / f"{k}.json").read_text()) for k in "ab")
    al = a["alleviation"]
    for key in ("root_bending_moment", "load_factor", "tip_deflection"):
        assert al["a_bar_without_law"][key] == pytest.approx(b["a_bar"][key], rel=1e-9)
        assert al["a_bar_with_law"][key] == a["a_bar"][key]
    assert a["a_bar"]["root_bending_moment"] < 0.8 * b["a_bar"]["root_bending_moment"]
    srf = a["control_surfaces"]["aileron"]
    assert srf["design_deflection_deg"] == pytest.approx(a["u_sigma_m_s"] * srf["a_bar_deflection_deg_per_m_s"])
    assert srf["a_bar_deflection_deg_per_m_s"] > 0 and srf["max_deflection_deg"] == 20.0


RB_LAW = ("surfaces:\n  - {name: aileron, span: [0.7, 1.0], hinge: 0.75, actuator: {order: 2, frequency_hz: 8.0, "
          "damping: 0.7}}\nlaw:\n  outputs: [root_bending]\n  state_space: {A: [[-6.0]], B: [[6.0]], C: [[-0.5]], "
          "D: [[0.0]]}\n")


def test_sizing_problem_has_the_turbulence_constraint():
    """build_problem with the turbulence options (the file's law, fixed gains): turbulence_ks is a
    constraint of the driver beside the maneuvers' KS, and the law's gains are inputs of the component."""
    from wingmdao import sizing
    from wingmdao.cases import pegasus
    from wingmdao.loads.turbulence_analysis import sizing_turbulence_options

    setup = pegasus.build()
    example = Path(__file__).resolve().parents[1] / "docs" / "examples" / "pegasus_turbulence_alleviation.yaml"
    turb = sizing_turbulence_options(pegasus, setup, alleviation=str(example))
    prob, _ = sizing.build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=True,
                                   section=setup.section, turbulence=turb)
    prob.final_setup()
    assert set(prob.model.get_constraints()) == {"turbulence_ks", "cases.maneuver_pos.ks_vm", "cases.maneuver_neg.ks_vm"}
    assert prob.get_val("turbulence.controller_C")[0, 0] == -0.5


def test_size_turbulence_alleviation_refusals(capsys, tmp_path):
    """`size --turbulence --alleviation`: a load-factor law (the constraint's wing is clamped) is a
    one-line error; with --size-gains, a gust set (several cases sizing their own gains, the constraint
    shares one case's) too."""
    from wingmdao.cli import main

    lf = tmp_path / "lf.yaml"
    lf.write_text("surfaces:\n  - {name: a, span: [0.7, 1.0], hinge: 0.75}\nlaw: {outputs: [load_factor], gain: [-0.2]}\n")
    rb = tmp_path / "rb.yaml"
    rb.write_text(RB_LAW)
    base = ["size", "pegasus", "--analysis-only", "--turbulence", "--no-plots", "--out", str(tmp_path)]
    assert main(base + ["--alleviation", str(lf)]) == 2
    err = capsys.readouterr().err
    assert "output load_factor needs a free aircraft" in err and str(lf) in err, err
    assert main(base + ["--loads", "gust", "--aero", "coupled", "--aero-theory", "strip", "--alleviation", str(rb),
                        "--size-gains", "--gust-gradients-ft", "100", "200", "--gust-sign", "up"]) == 2
    err = capsys.readouterr().err
    assert "--turbulence with --size-gains: 2 load cases size their own gains" in err, err


@pytest.mark.slow
def test_size_pegasus_turbulence_constraint_with_alleviation(tmp_path, capsys):
    """`size pegasus --analysis-only --turbulence --alleviation FILE` (root-bending law): the
    constraint's analysed loads equal `wingmdao turbulence --clamped --alleviation FILE` on the same
    design (the command's own model set-up), the law lowers turbulence_ks against the run without it,
    and no warning calls the file ignored."""
    from wingmdao.cli import main

    rb = tmp_path / "rb.yaml"
    rb.write_text(RB_LAW)
    runs = {}
    for key, extra in (("law", ["--alleviation", str(rb)]), ("plain", [])):
        out = tmp_path / f"{key}.json"
        assert main(["size", "pegasus", "--analysis-only", "--turbulence", "--no-plots", "--no-flutter-search",
                     "--out", str(tmp_path), "--json", str(out), "--overwrite"] + extra) == 0
        runs[key] = json.loads(out.read_text())
        if key == "law":
            text = "".join(capsys.readouterr())
            assert "control surfaces of" in text and "ignored" not in text, text
    assert runs["law"]["turbulence_ks"] < runs["plain"]["turbulence_ks"] - 0.1
    cmd = tmp_path / "t.json"
    assert main(["turbulence", "pegasus", "--clamped", "--aero-theory", "strip", "--damping-ratio", "0.02",
                 "--f-max-hz", "20", "--no-plots", "--alleviation", str(rb), "--json", str(cmd)]) == 0
    t = json.loads(cmd.read_text())
    tl = runs["law"]["turbulence_loads"]
    assert tl["a_bar_load_factor"] == pytest.approx(t["a_bar"]["load_factor"], rel=1e-6)
    np.testing.assert_allclose(tl["bending_moment"]["a_bar"], t["a_bar"]["bending_moment"], rtol=1e-6,
                               atol=1e-6 * max(t["a_bar"]["bending_moment"]))


@pytest.mark.slow
def test_codesign_gains_shared_by_the_gust_case_and_the_turbulence_constraint(tmp_path):
    """`--loads gust --aero coupled --alleviation FILE --size-gains --turbulence` (PEGASUS, clamped,
    strip theory, a 1 s gust): one set of gains (law_gains) feeds the gust case and the turbulence
    constraint; the totals of turbulence_ks, the gust's stress KS and its closed-loop constraint with
    respect to controller_C and controller_D against central differences (step 1e-4) within 1e-4 of
    each output's largest entry, every one non-zero."""
    from wingmdao import sizing
    from wingmdao.cases import pegasus
    from wingmdao.loads.turbulence_analysis import sizing_turbulence_options

    rb = tmp_path / "rb.yaml"
    rb.write_text(RB_LAW)
    setup = pegasus.build(loads="gust", aero="coupled", aero_theory="strip", alleviation=str(rb), size_gains=True,
                          t_final=1.0)
    damping = pegasus.gust_damping(0.02, None, setup.geometry, setup.options)[0]
    turb = sizing_turbulence_options(pegasus, setup, damping=damping, alleviation=str(rb))
    prob, _ = sizing.build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=True,
                                   section=setup.section, turbulence=turb)
    wrt = ["law_gains.controller_C", "law_gains.controller_D"]
    assert set(wrt) <= set(prob.model.get_design_vars())
    assert not any(k.startswith("cases.") for k in prob.model.get_design_vars())
    prob.run_model()
    assert {"turbulence_ks", "cases.gust.ks_vm", "cases.gust.closed_loop_ks"} <= set(prob.model.get_constraints())
    of = ["turbulence_ks", "cases.gust.ks_vm", "cases.gust.closed_loop_ks"]
    J = prob.compute_totals(of, wrt)
    for w in wrt:
        base = prob.get_val(w).copy()
        vals = []
        for sign in (1, -1):
            prob.set_val(w, base + sign * 1e-4)
            prob.run_model()
            vals.append({o: np.asarray(prob.get_val(o)).ravel().copy() for o in of})
        prob.set_val(w, base)
        for o in of:
            fd = (vals[0][o] - vals[1][o]) / 2e-4
            got = np.asarray(J[o, w]).ravel()
            assert np.max(np.abs(fd)) > 1e-3, (o, w, fd)
            assert np.max(np.abs(got - fd)) <= 1e-4 * np.max(np.abs(fd)), (o, w, got, fd)
    np.testing.assert_array_equal(prob.get_val("cases.gust.controller_D"), prob.get_val("turbulence.controller_D"))
