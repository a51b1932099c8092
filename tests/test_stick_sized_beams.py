"""The stick sizing's optional tail and fuselage sections (``size --model stick --size-beams``):
the thin tube's section and stress components (check_partials; the bending stress against
sigma = M c / I), the sized beams at their assumed data, the exact totals of every KS and the
total mass with respect to wing, tail and fuselage walls (reverse against central differences and
forward mode), and a sized fuselage whose bending stress at the wing joint is the allowable,
checked from the monitoring station's bending moment by M c / I."""

from dataclasses import replace

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.beam.joints import MonitoringStation, monitoring_loads
from wingmdao.cases import pegasus, pegasus_stick
from wingmdao.cases.planform import wing_geometry
from wingmdao.components.tube import TubeSection, TubeStress
from wingmdao.groups.load_case import SizedBeam
from wingmdao.groups.stick import StickCase, StickSizing, set_sized_beams, set_stick_case
from wingmdao.materials import ALUMINIUM
from wingmdao.sizing import build_stick_problem, presize_and_size, set_geometry
from wingmdao.timemarch.system import layout

N = 5
WALLS = ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")


def test_tube_components_partials_and_bending_stress():
    """TubeSection and TubeStress: declared partials against central differences; the stress at the
    top and bottom of the tube under a vertical bending moment and an axial force is N/A -+ M R / I
    (A = 2 pi R t, I = pi R^3 t of the whole tube; the beam carries half)."""
    R, f = 1.3, 0.5
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("sec", TubeSection(num_stations=3, material=ALUMINIUM, radius=R, fraction=f))
    prob.model.add_subsystem("st", TubeStress(num_times=2, num_stations=3, material=ALUMINIUM, radius=R, fraction=f))
    prob.setup()
    rng = np.random.default_rng(5)
    t = np.array([1.5e-3, 3e-3, 4.5e-3])
    prob.set_val("sec.t_wall", t)
    prob.set_val("sec.nonstructural_mass_per_length", [10.0, 20.0, 30.0])
    prob.set_val("st.t_wall", t)
    prob.set_val("st.F_csn", rng.normal(size=(2, 3, 3)) * 1e4)
    prob.set_val("st.M_csn", rng.normal(size=(2, 3, 3)) * 1e5)
    prob.run_model()
    data = prob.check_partials(method="fd", form="central", step=1e-8, out_stream=None)
    assert_check_partials(data, atol=1e-4, rtol=1e-6)
    E = ALUMINIUM.E
    np.testing.assert_allclose(prob.get_val("sec.stiffness_csn")[:, 0, 0], f * E * np.pi * R**3 * t, rtol=1e-12)
    np.testing.assert_allclose(prob.get_val("sec.mass_per_length"),
                               f * ALUMINIUM.rho * 2 * np.pi * R * t + [10.0, 20.0, 30.0], rtol=1e-12)
    # pure vertical bending and axial force, the beam's half share
    M_half, N_half = 4.0e5, 2.0e4
    prob.set_val("st.F_csn", np.tile([0.0, N_half, 0.0], (2, 3, 1)))
    prob.set_val("st.M_csn", np.tile([M_half, 0.0, 0.0], (2, 3, 1)))
    prob.run_model()
    sig = (prob.get_val("st.g_vm")[0] + 1.0) * ALUMINIUM.sigma_y          # (stations, 8 points), von Mises
    axial, bending = N_half / f / (2 * np.pi * R * t), M_half / f * R / (np.pi * R**3 * t)
    np.testing.assert_allclose(sig[:, 2], np.abs(axial - bending), rtol=1e-9)   # top (n = +R): compressed
    np.testing.assert_allclose(sig[:, 6], axial + bending, rtol=1e-9)           # bottom


@pytest.fixture(scope="module")
def gust_case():
    ac = pegasus_stick.build(N)
    s = pegasus_stick.aeroelastic_system(ac)
    fp = pegasus.flight_point()
    V = fp["cruise_speed"]
    t = np.linspace(0.0, 0.3, 16)
    p = pegasus_stick.aero_parameters(ac, s, airspeed=V, density=fp["density"], mach=0.5)
    Q = pegasus_stick.gust_forcing(ac, s, t, airspeed=V, u_ds_tas=15.0, gradient=20.0, gust_start=0.02)
    return StickCase("gust", s, t, p, Q)


def test_sized_beams_start_at_the_assumed_data(gust_case):
    """At their initial walls the sized tail and fuselage have the stick model's mass per length (so
    the aircraft's mass is unchanged), the fuselage tube the assumed shell's EI, GJ, EA exactly, and
    the tail box a flap stiffness within 2 % of the assumed 2e6 N m^2; bad beam names are refused."""
    tail, fus = pegasus_stick.sized_beams(gust_case, ["tail", "fuselage"])
    prob = _sized_problem(gust_case, [tail, fus], "rev", vary=False)
    lay = layout(gust_case.system.param_specs)
    p = np.asarray(gust_case.p)
    for name in ("tail", "fuselage"):
        np.testing.assert_allclose(prob.get_val(f"{name}_mass_per_length"), p[lay[f"{name}_mass_per_length"]],
                                   rtol=1e-12)
    np.testing.assert_allclose(prob.get_val("fuselage_stiffness_csn").ravel(), p[lay["fuselage_stiffness_csn"]],
                               rtol=1e-12)
    np.testing.assert_allclose(prob.get_val("fuselage_compliance_csn").ravel(), p[lay["fuselage_compliance_csn"]],
                               rtol=1e-12)
    assert prob.get_val("tail_stiffness_csn")[:, 0, 0] == pytest.approx(pegasus_stick.TAIL["EI_cc"], rel=0.02)
    with pytest.raises(ValueError, match="--size-beams: fin; allowed: tail, fuselage"):
        pegasus_stick.sized_beams(gust_case, ["fin"])
    with pytest.raises(ValueError, match="kind = 'shell'"):
        SizedBeam("tail", "shell", np.zeros((3, 3)))


def _sized_problem(case, sized, mode, vary=True):
    prob = om.Problem(StickSizing(num_nodes=N, material=ALUMINIUM, stick_cases=[case], parallel=False,
                                  sized_beams=sized), reports=False)
    prob.setup(mode=mode)
    set_geometry(prob, wing_geometry(pegasus.flutter_planform(N), ())[0])
    set_sized_beams(prob, sized)
    set_stick_case(prob, case, f"cases.{case.name}", sized)
    th = pegasus.initial_thickness(N)
    for k, w in enumerate(WALLS):
        v = np.asarray(th.get(w, th.get(w[2:])), dtype=float)
        prob.set_val(w, v * (1.0 + 0.1 * k * np.linspace(-1.0, 1.0, N)))
    for b in sized if vary else ():   # walls that vary along the beam and from wall to wall
        for k, v in enumerate(b.design_vars):
            prob.set_val(v, b.initial * (0.7 + 0.1 * k + 0.5 * np.linspace(0.0, 1.0, b.num_nodes) ** 2))
    prob.run_model()
    return prob


@pytest.mark.slow
def test_sized_beams_totals(gust_case):
    """d(ks_vm, ks_tail_vm, ks_fuselage_vm, total_mass) / d(wing, tail and fuselage walls) of the
    16-step gust on the free half aircraft: reverse mode (the discrete adjoint of the march) against
    central differences of the whole model, and forward mode."""
    sized = pegasus_stick.sized_beams(gust_case, ["tail", "fuselage"])
    rev = _sized_problem(gust_case, sized, "rev")
    fwd = _sized_problem(gust_case, sized, "fwd")
    of = ["cases.gust.ks_vm", "cases.gust.ks_tail_vm", "cases.gust.ks_fuselage_vm", "total_mass"]
    wrt = ["t_upper_skin", "tail_t_upper_skin", "tail_t_rear_spar", "fuselage_t_wall"]
    J_rev, J_fwd = rev.compute_totals(of, wrt), fwd.compute_totals(of, wrt)
    picks = (("t_upper_skin", 1, 1e-6), ("tail_t_upper_skin", 1, 1e-7), ("tail_t_rear_spar", 2, 1e-7),
             ("fuselage_t_wall", 7, 1e-7), ("fuselage_t_wall", 11, 1e-7))
    checked = 0
    for name, idx, h in picks:
        v = rev.get_val(name).copy()
        vals = []
        for step in (h, -h):
            w = v.copy()
            w[idx] += step
            rev.set_val(name, w)
            rev.run_model()
            vals.append({k: rev.get_val(k)[0] for k in of})
        rev.set_val(name, v)
        for k in of:
            cd = (vals[0][k] - vals[1][k]) / (2 * h)
            scale = max(abs(J_rev[k, name]).max(), 1e-12)
            assert J_rev[k, name][0, idx] == pytest.approx(cd, rel=1e-5, abs=1e-6 * scale), (k, name, idx)
            assert J_fwd[k, name][0, idx] == pytest.approx(J_rev[k, name][0, idx], rel=1e-9, abs=1e-12 * scale), \
                (k, name, idx)
            checked += abs(cd) > 1e-6 * scale
    rev.run_model()
    assert checked >= 12          # most of them are not trivially zero
    # a beam's KS depends on its own walls most: the fuselage's on its wall at the wing joint
    assert abs(J_rev["cases.gust.ks_fuselage_vm", "fuselage_t_wall"][0, 7]) > 10 * abs(
        J_rev["cases.gust.ks_fuselage_vm", "tail_t_upper_skin"]).max()


@pytest.mark.slow
def test_sized_fuselage_bending_stress_is_the_allowable_at_the_wing_joint():
    """Size the fuselage tube alone (wing walls fixed at the case's start by bounds) for the trimmed
    2.5 g pull-up of the 5-node stick model, with a minimum gauge low enough for its stress
    constraint to be active. At the result, the fuselage's vertical bending moment at the cut ahead of
    the wing (beam.joints.monitoring_loads: the state, not the stress chain) gives by
    sigma = N / A + M c / I, A = 2 pi R t, I = pi R^3 t (the whole tube: the half model's loads
    doubled) the allowable sigma_y within the KS's margin, the wall at that station above the minimum
    gauge, and the result's fuselage mass that of the sized walls."""
    opts = pegasus.PegasusOptions(loads="maneuver")
    setup = replace(pegasus.build(opts), geometry=wing_geometry(pegasus.flutter_planform(N), ())[0])
    setup = pegasus_stick.sizing_setup(setup, opts)
    case = setup.load_cases[0]
    setup = replace(setup, load_cases=[case])
    fus = pegasus_stick.sized_beams(case, ["fuselage"], lower=5e-5)
    wall = 0.015   # the wing's walls held (thick: its own constraint inactive)
    options = replace(setup.options, lower={w: wall for w in WALLS}, upper={w: wall + 1e-9 for w in WALLS},
                      initial={w: wall for w in WALLS}, presize=2, maxiter=30, progress=False, recording=None,
                      disp=False)
    setup = replace(setup, options=options)
    prob, desc = build_stick_problem(setup.geometry, [case], setup.material, options, sized_beams=fus)
    result = presize_and_size(prob, setup, desc, sized_beams=fus)
    t = prob.get_val("fuselage_t_wall")
    ks = result["ks"]["maneuver_pos"]["fuselage_vm"]
    assert ks == pytest.approx(0.0, abs=2e-3)                            # the constraint is active
    s = case.system
    x = prob.get_val("cases.maneuver_pos.states")[0]
    i_wing = next(jt.node_a for jt in s.joints if jt.beam_b == "wing")
    loads = monitoring_loads(s, x, [MonitoringStation("fus", "fuselage", i_wing)])["fus"]
    R = pegasus_stick.FUSELAGE["radius"]
    M, N_ax = 2 * abs(loads["moment"][1]), 2 * loads["force"][0]          # body y bending, x axial; whole tube
    sigma = abs(N_ax) / (2 * np.pi * R * t[i_wing]) + M * R / (np.pi * R**3 * t[i_wing])
    n_points = 8 * len(t)
    assert 1.0 - np.log(n_points) / 100.0 - 2e-3 <= sigma / ALUMINIUM.sigma_y <= 1.0 + 2e-3
    assert t[i_wing] > 2 * fus[0].lower
    r0 = fus[0].node_positions
    area = 0.5 * 2 * np.pi * R * t
    a0, a1 = area[:-1], area[1:]            # StructuralMass's frustum rule per element
    mass = np.sum((a0 + a1 + np.sqrt(a0 * a1)) / 3 * np.linalg.norm(np.diff(r0, axis=0), axis=1)) * ALUMINIUM.rho
    assert result["beams"]["fuselage"]["mass_kg"] == pytest.approx(mass, rel=1e-9)
    assert result["total_mass_kg"] == pytest.approx(result["mass_kg"] + mass, rel=1e-12)


@pytest.mark.parametrize("argv, msg", [
    (["size", "pegasus", "--model", "stick", "--size-beams", "tail,fin"],
     "--size-beams = 'tail,fin'; allowed: a comma list of wing, tail, fuselage, each once"),
    (["size", "pegasus", "--model", "stick", "--size-beams", "tail,tail"], "each once"),
    (["size", "pegasus", "--size-beams", "tail"], "--size-beams tail: needs --model stick"),
])
def test_size_beams_bad_input(argv, msg, capsys, tmp_path):
    """--size-beams: one-line errors before any solve."""
    from wingmdao.cli import main

    assert main(argv + ["--no-plots", "--out", str(tmp_path)]) == 2
    assert msg in capsys.readouterr().err


@pytest.mark.slow
def test_stick_sizing_gust_set_cases_and_envelope(tmp_path):
    """``size --model stick --gust-set``: one StickCase per gust of the set, its design velocity
    U_ref F_g (H / 350)^(1/6) (EAS, in TAS by sqrt(rho_0 / rho); F_g of 25.341(a)(6) computed here)
    at every lifting station; the monitoring
    envelope over the set, from the sizing model's states, equals the extremes of each gust marched on
    its own (cases.pegasus_stick.gust_response: the march without OpenMDAO)."""
    from wingmdao.envelope import stick_set_envelope
    from wingmdao.loads.atmosphere import altitude_ft_to_m, density, speed_of_sound

    path = tmp_path / "set.yaml"
    path.write_text("flight_points:\n  - {name: fp, altitude_ft: 20000, mach: 0.45, u_ref_fps: 30}\n"
                    "gradients_ft: [60, 200]\nsigns: up\n")
    opts = pegasus.PegasusOptions(loads="gust", gust_set=str(path), t_final=0.3, dt=0.02, gust_start=0.02)
    setup = replace(pegasus.build(opts), geometry=wing_geometry(pegasus.flutter_planform(N), ())[0])
    cases = pegasus_stick.sizing_setup(setup, opts).load_cases
    assert [c.name for c in cases] == ["gust_fp_h60_up", "gust_fp_h200_up"]
    alt = float(altitude_ft_to_m(20000.0))
    rho, V = float(density(alt)), 0.45 * float(speed_of_sound(alt))
    s = cases[0].system
    play = layout(s.param_specs)
    ac = pegasus_stick.build(N)
    # 14 CFR 25.341(a)(6): F_g from the set's MLW, MZFW and Z_mo, linear from sea level to Z_mo
    r1, r2 = 18300.0 / 18600.0, 16700.0 / 18600.0
    f_g0 = 0.5 * ((1 - 25000.0 / 250000.0) + np.sqrt(r2 * np.tan(np.pi * r1 / 4)))
    f_g = f_g0 + (1 - f_g0) * 20000.0 / 25000.0
    for c, h in zip(cases, (60.0, 200.0)):     # the same 1-cos history of the U_ds computed here
        u_tas = 30 * 0.3048 * f_g * (h / 350) ** (1 / 6) * np.sqrt(float(density(0.0)) / rho)
        Q = pegasus_stick.gust_forcing(ac, s, c.time, airspeed=V, u_ds_tas=u_tas, gradient=h * 0.3048, gust_start=0.02)
        np.testing.assert_allclose(c.forcing, Q, rtol=1e-9, atol=1e-12)
        assert np.asarray(c.p)[play["airspeed"]][0] == pytest.approx(V, rel=1e-9)
        assert np.asarray(c.p)[play["density"]][0] == pytest.approx(rho, rel=1e-9)
    prob = om.Problem(StickSizing(num_nodes=N, material=ALUMINIUM, stick_cases=cases, parallel=False), reports=False)
    prob.setup()
    set_geometry(prob, wing_geometry(pegasus.flutter_planform(N), ())[0])
    for c in cases:
        set_stick_case(prob, c, f"cases.{c.name}")
    th = pegasus.initial_thickness(N)
    for w in WALLS:
        prob.set_val(w, np.asarray(th.get(w, th.get(w[2:])), dtype=float))
    prob.run_model()
    env = stick_set_envelope([{"name": c.name, "monitoring_loads": pegasus_stick.case_monitoring_loads(
        c, prob.get_val(f"cases.{c.name}.states"))} for c in cases])
    alone = [pegasus_stick.gust_response(ac, c.time, airspeed=V, density=rho, mach=0.45,
                                         u_ds_tas=30 * 0.3048 * f_g * (h / 350) ** (1 / 6)
                                         * np.sqrt(float(density(0.0)) / rho),
                                         gradient=h * 0.3048, gust_start=0.02)
             for c, h in zip(cases, (60.0, 200.0))]
    root = np.array([r.loads["wing root"]["moment"][:, 0] for r in alone])
    assert env["wing root"]["moment_max_n_m"][0] == pytest.approx(root.max(), rel=1e-5)
    assert env["wing root"]["moment_max_gust"][0] == cases[int(np.argmax(root.max(axis=1)))].name
    assert env["wing root"]["moment_min_n_m"][0] == pytest.approx(root.min(), rel=1e-5, abs=1e-5 * root.max())


@pytest.mark.slow
def test_sized_beams_maneuver_totals():
    """The trimmed 2.5 g pull-up (a static solve of the free half aircraft with its trim unknowns):
    d(ks_tail_vm, ks_fuselage_vm, ks_vm) / d(tail and fuselage walls) in reverse mode against central
    differences (relative 1e-5 for a beam's KS and its own walls; 1e-4 for the small cross terms
    through the aircraft's mass and trim, where the differences are at the solve's tolerance) and
    forward mode."""
    opts = pegasus.PegasusOptions(loads="maneuver")
    setup = replace(pegasus.build(opts), geometry=wing_geometry(pegasus.flutter_planform(N), ())[0])
    case = pegasus_stick.sizing_setup(setup, opts).load_cases[0]
    sized = pegasus_stick.sized_beams(case, ["tail", "fuselage"])
    rev, fwd = _sized_problem(case, sized, "rev"), _sized_problem(case, sized, "fwd")
    of = [f"cases.{case.name}.ks_{f}" for f in ("vm", "tail_vm", "fuselage_vm")]
    wrt = ["tail_t_upper_skin", "tail_t_front_spar", "fuselage_t_wall"]
    J_rev, J_fwd = rev.compute_totals(of, wrt), fwd.compute_totals(of, wrt)
    nonzero = 0
    for name, idx, h in (("tail_t_upper_skin", 1, 1e-6), ("tail_t_front_spar", 3, 1e-6), ("fuselage_t_wall", 7, 1e-6)):
        v = rev.get_val(name).copy()
        vals = []
        for step in (h, -h):
            w = v.copy()
            w[idx] += step
            rev.set_val(name, w)
            rev.run_model()
            vals.append({k: rev.get_val(k)[0] for k in of})
        rev.set_val(name, v)
        for k in of:
            cd = (vals[0][k] - vals[1][k]) / (2 * h)
            scale = max(abs(J_rev[k, name]).max(), 1e-12)
            own = k.endswith(f"ks_{name.split('_')[0]}_vm")   # a beam's KS and its own walls; else through the trim
            assert J_rev[k, name][0, idx] == pytest.approx(cd, rel=1e-5 if own else 1e-4, abs=1e-6 * scale), (k, name)
            assert J_fwd[k, name][0, idx] == pytest.approx(J_rev[k, name][0, idx], rel=1e-9, abs=1e-12 * scale), (k, name)
            nonzero += abs(cd) > 1e-6 * scale
    assert nonzero >= 6
