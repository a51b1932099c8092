"""Exact totals of the stick model's gust and maneuver KS (wingmdao.groups.stick) with respect to the
wing's walls and a tail parameter: reverse mode (the discrete adjoint of the joined aeroelastic march
or static solve), forward mode and central differences of the whole model; the trimmed maneuvers'
lift and wing root bending against free-body sums."""

from dataclasses import replace

import numpy as np
import openmdao.api as om
import pytest

from wingmdao.aero.joined import lift_total
from wingmdao.beam.joints import MonitoringStation, monitoring_loads
from wingmdao.cases import pegasus, pegasus_stick
from wingmdao.cases.planform import G0, wing_geometry
from wingmdao.components.flutter import StickFlutterDamping
from wingmdao.groups.stick import StickCase, StickSizing, set_stick_case
from wingmdao.materials import ALUMINIUM
from wingmdao.sizing import closed_loop_constraints, set_geometry
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import layout

N = 5
KS = "cases.gust.ks_vm"
TAIL = "gust.tail_mass_per_length"   # promoted out of "cases" (WingSizing proxy_cases)


@pytest.fixture(scope="module")
def case():
    ac = pegasus_stick.build(N)
    s = pegasus_stick.aeroelastic_system(ac)
    fp = pegasus.flight_point()
    V = fp["cruise_speed"]
    t = np.linspace(0.0, 0.3, 16)
    p = pegasus_stick.aero_parameters(ac, s, airspeed=V, density=fp["density"], mach=0.5)
    Q = pegasus_stick.gust_forcing(ac, s, t, airspeed=V, u_ds_tas=15.0, gradient=20.0, gust_start=0.02)
    return StickCase("gust", s, t, p, Q)


def _problem(case, mode):
    cases = case if isinstance(case, list) else [case]
    prob = om.Problem(StickSizing(num_nodes=N, material=ALUMINIUM, stick_cases=cases, parallel=False), reports=False)
    prob.setup(mode=mode)
    set_geometry(prob, wing_geometry(pegasus.flutter_planform(N), ())[0])
    for c in cases:
        set_stick_case(prob, c, f"cases.{c.name}")
    th = pegasus.initial_thickness(N)
    for k, w in enumerate(("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")):
        v = np.asarray(th.get(w, th.get(w[2:])), dtype=float)
        prob.set_val(w, v * (1.0 + 0.1 * k * np.linspace(-1.0, 1.0, N)))   # a design that varies along the span
    prob.run_model()
    return prob


def _stick_setup(loads, num_nodes=N, **extra):
    """The CLI's stick setup (pegasus_stick.sizing_setup) of ``--loads loads`` on a ``num_nodes`` wing."""
    opts = pegasus.PegasusOptions(loads=loads, **extra)
    setup = replace(pegasus.build(opts), geometry=wing_geometry(pegasus.flutter_planform(num_nodes), ())[0])
    return pegasus_stick.sizing_setup(setup, opts)


@pytest.fixture(scope="module")
def maneuvers():
    return _stick_setup("maneuver").load_cases


def _central_differences(prob, of, name, idx, h):
    v = prob.get_val(name).copy()
    vals = []
    for step in (h, -h):
        w = v.copy()
        w[idx] += step
        prob.set_val(name, w)
        prob.run_model()
        vals.append(prob.get_val(of).copy())
    prob.set_val(name, v)
    prob.run_model()
    return (vals[0] - vals[1]) / (2 * h)


@pytest.mark.slow
def test_stick_maneuver_ks_totals(maneuvers):
    """The KS of the trimmed pull-up and push-over (static solves of the free half aircraft with the trim
    unknowns) with respect to the walls and the tail's mass: reverse against central differences and
    forward mode."""
    assert [c.name for c in maneuvers] == ["maneuver_pos", "maneuver_neg"]
    rev = _problem(maneuvers, "rev")
    fwd = _problem(maneuvers, "fwd")
    of = ["cases.maneuver_pos.ks_vm", "cases.maneuver_neg.ks_vm"]
    tails = ["maneuver_pos.tail_mass_per_length", "maneuver_neg.tail_mass_per_length"]   # each case's own
    wrt = ["t_upper_skin", "t_rear_spar", *tails]
    J_rev, J_fwd = rev.compute_totals(of, wrt), fwd.compute_totals(of, wrt)
    for name, idx, h in (("t_upper_skin", 3, 1e-7), ("t_rear_spar", 1, 1e-7), (tails[0], 2, 0.05), (tails[1], 4, 0.05)):
        for ks in of:
            if name in tails and name.split(".")[0] != ks.split(".")[1]:
                assert J_rev[ks, name][0, idx] == 0.0 and J_fwd[ks, name][0, idx] == 0.0
                continue
            cd = _central_differences(rev, ks, name, idx, h)[0]
            assert abs(cd) > 1e-9, (ks, name)                      # the derivative is not trivially zero
            assert J_rev[ks, name][0, idx] == pytest.approx(cd, rel=1e-5, abs=1e-10), (ks, name)
            assert J_fwd[ks, name][0, idx] == pytest.approx(J_rev[ks, name][0, idx], rel=1e-9, abs=1e-13), (ks, name)


def test_stick_maneuver_lift_and_root_bending_of_the_stiff_stick():
    """The 25.337 pull-up (2.5 g) and push-over (-1.0 g) of the sizing's stick cases, wing stiffness x 1e4:
    the trimmed lift (wing and tail strips) is n W with W summed here from the beams' masses per length
    and the lumped masses; the wing root rib's bending moment (monitoring_loads, the beam's M_1) is the
    free-body sum, over the wing outboard of the rib, of the strips' vertical lift minus n g times the
    elements' and engines' masses times their arms from the rib, within 1e-3."""
    cases = _stick_setup("maneuver", num_nodes=8).load_cases
    s = cases[0].system
    lay = layout(s.param_specs)
    p = np.array(cases[0].p, dtype=float)
    p[lay["wing_stiffness_csn"]] *= 1e4
    p[lay["wing_compliance_csn"]] *= 1e-4
    mass = float(p[lay["lumped_mass"]].sum())
    for b in s.beams:
        r0 = p[lay[f"{b.name}_node_positions"]].reshape(-1, 3)
        mu = p[lay[f"{b.name}_mass_per_length"]]
        mass += float(np.sum(0.5 * (mu[:-1] + mu[1:]) * np.linalg.norm(np.diff(r0, axis=0), axis=1)))
    r0 = p[lay["wing_node_positions"]].reshape(-1, 3)
    mu, y = p[lay["wing_mass_per_length"]], r0[:, 1]
    ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
    y_mid = 0.5 * (y[:-1] + y[1:])
    for case, n in zip(cases, (2.5, -1.0)):
        x = march(s, np.zeros(1), p, case.forcing, atol=1e-6).states[0]
        q = case.forcing[0]
        assert lift_total(s, x, 0 * x, p, q, vertical=True) / (n * G0 * mass) == pytest.approx(1.0, abs=1e-9)
        up = s.section_loads(x, 0 * x, p, q)["wing"][2]
        fz = 0.5 * (up[:-1] + up[1:]) * ds - n * G0 * 0.5 * (mu[:-1] + mu[1:]) * ds
        bending = float(np.sum(fz[1:] * (y_mid[1:] - y[1])))
        bending -= sum(n * G0 * lm.mass * (y[lm.node] + lm.offset[1] - y[1]) for lm in s.masses if lm.beam == "wing")
        root = monitoring_loads(s, x, [MonitoringStation("root", "wing", 1)])["root"]["moment"]
        assert abs(bending) > 1e5
        assert root[0] == pytest.approx(bending, rel=1e-3), n


@pytest.mark.slow
def test_stick_gust_ks_totals(case):
    rev = _problem(case, "rev")
    wrt = ["t_upper_skin", "t_front_spar", TAIL]
    J_rev = rev.compute_totals([KS], wrt)
    J_fwd = _problem(case, "fwd").compute_totals([KS], wrt)
    assert np.isfinite(rev.get_val(KS)).all()
    for name, idx, h in (("t_upper_skin", 0, 1e-6), ("t_upper_skin", 3, 1e-6), ("t_front_spar", 1, 1e-6),
                         (TAIL, 2, 1e-3)):
        v = rev.get_val(name).copy()
        vals = []
        for step in (h, -h):
            w = v.copy()
            w[idx] += step
            rev.set_val(name, w)
            rev.run_model()
            vals.append(rev.get_val(KS)[0])
        rev.set_val(name, v)
        cd = (vals[0] - vals[1]) / (2 * h)
        assert abs(cd) > 1e-6 * max(1.0, abs(J_rev[KS, name]).max())   # the derivative is not trivially zero
        assert J_rev[KS, name][0, idx] == pytest.approx(cd, rel=1e-5, abs=1e-9)
        assert J_fwd[KS, name][0, idx] == pytest.approx(J_rev[KS, name][0, idx], rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("argv, msg", [
    (["size", "crm", "--model", "stick"], "--model stick: case 'crm' has no stick model; allowed: pegasus"),
    (["size", "pegasus", "--model", "stick", "--gust-gradients-ft", "100", "350"],
     "--model stick does not take --gust-gradients-ft"),
    (["size", "pegasus", "--model", "stick", "--loads", "gust", "--turbulence"], "--model stick does not take --turbulence"),
])
def test_size_stick_model_refuses_other_options(argv, msg, capsys, tmp_path):
    from wingmdao.cli import main

    assert main(argv + ["--no-plots", "--out", str(tmp_path)]) == 2
    assert msg in capsys.readouterr().err


def test_monitoring_potatoes_hull_of_an_ellipse():
    """The potato of an elliptical moment history: the two components of largest range, and a convex
    hull whose vertices are points of the history and that contains every point."""
    from wingmdao.envelope import monitoring_potatoes

    t = np.linspace(0.0, 2 * np.pi, 181)
    m = np.column_stack([1e3 * np.sin(t) + 5.0, 20.0 * np.cos(3 * t), 3e3 * np.cos(t)])
    pot = monitoring_potatoes({"root": {"moment": m}})["root"]
    assert pot["components"] == ["M_z", "M_x"]
    hull = pot["hull"]
    np.testing.assert_array_equal(hull[0], hull[-1])                 # closed
    pts = m[:, [2, 0]]
    for a, b in zip(hull[:-1], hull[1:]):                            # counter-clockwise: every point left of every edge
        cross = (b[0] - a[0]) * (pts[:, 1] - a[1]) - (b[1] - a[1]) * (pts[:, 0] - a[0])
        assert cross.min() > -1e-6 * 3e3 ** 2
    assert all(np.min(np.linalg.norm(pts - v, axis=1)) < 1e-9 for v in hull)
    assert np.ptp(hull[:, 0]) == pytest.approx(6e3, rel=1e-3) and np.ptp(hull[:, 1]) == pytest.approx(2e3, rel=1e-3)


def test_monitoring_potatoes_pair_a_lone_moment_with_its_shear():
    """A station with one moment component (the rest round-off) pairs it with the force of largest range."""
    from wingmdao.envelope import monitoring_potatoes

    t = np.linspace(0.0, 1.0, 51)
    m = np.column_stack([1e-12 * t, 4e5 * np.sin(3 * t), 1e-11 * t])
    f = np.column_stack([10.0 * t, 0.0 * t, -2e4 * np.sin(3 * t) ** 2])
    pot = monitoring_potatoes({"fuselage": {"moment": m, "force": f}})["fuselage"]
    assert pot["components"] == ["M_y", "F_z"]
    np.testing.assert_array_equal(pot["values"], np.column_stack([m[:, 1], f[:, 2]]))


def test_a_stick_case_has_no_closed_loop_constraint():
    """The stick model's load case (no ``aero`` of the lone wing's kind) has no closed-loop
    stability constraint: the sizing's summary asks every case (``sizing.closed_loop_constraints``)."""
    case = StickCase("gust", None, np.zeros(3), np.zeros(1), np.zeros((3, 1)))
    assert closed_loop_constraints([case]) == []


@pytest.mark.slow
def test_stick_flutter_ks_totals(maneuvers):
    """The stick aircraft's flutter-damping KS (components.flutter.StickFlutterDamping, two speeds of the
    1.15 V_D set, a 16-mode window) through the section chain: its reverse-mode total along a direction
    over every wall of every station against central differences of the whole model; the aggregated
    modes are damped, oscillatory and exclude the rigid-body zeros, and one of them is the first elastic
    mode of the structure in vacuum within 3 %."""
    opts = pegasus_stick.flutter_options(maneuvers[0], 1.15)
    opts.update(speeds=opts["speeds"][2:], eig_options={"method": "sparse", "sigma": 60j, "count": 16, "ncv": 40})
    prob = om.Problem(StickSizing(num_nodes=N, material=ALUMINIUM, stick_cases=maneuvers[:1], parallel=False,
                                  stick_flutter=opts), reports=False)
    prob.setup(mode="rev")
    set_geometry(prob, wing_geometry(pegasus.flutter_planform(N), ())[0])
    set_stick_case(prob, maneuvers[0], "cases.maneuver_pos")
    walls = ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")
    th = pegasus.initial_thickness(N)
    base = {w: np.asarray(th.get(w, th.get(w[2:])), dtype=float) * (1.0 + 0.1 * k * np.linspace(-1, 1, N))
            for k, w in enumerate(walls)}
    rng = np.random.default_rng(3)
    direction = {w: rng.uniform(-1.0, 1.0, N) * base[w] for w in walls}
    for w in walls:
        prob.set_val(w, base[w])
    prob.run_model()
    res = prob.model.stick_flutter.last_result
    _check_stick_flutter_partials(prob.model.stick_flutter)
    lam = np.concatenate(res.eigenvalues)
    assert np.all(lam.real < 0) and np.all(np.abs(lam.imag) > 1.0)
    assert prob.get_val("flutter_ks")[0] < 0
    # the first wing bending in the air near its frequency in vacuum (the structure alone, no aerodynamics;
    # pegasus_stick.natural_frequencies at the same walls)
    ac = pegasus_stick.build(N, {w: base[w] for w in walls})
    f_vac = pegasus_stick.natural_frequencies(ac, count=1)["hz"][0]
    f_air = np.abs(res.eigenvalues[0].imag) / (2 * np.pi)
    assert np.min(np.abs(f_air / f_vac - 1.0)) < 0.03
    J = prob.compute_totals(["flutter_ks"], list(walls))
    slope = sum(float(J["flutter_ks", w][0] @ direction[w]) for w in walls)
    h, vals = 1e-4, []
    for step in (h, -h):
        for w in walls:
            prob.set_val(w, base[w] + step * direction[w])
        prob.run_model()
        vals.append(prob.get_val("flutter_ks")[0])
    cd = (vals[0] - vals[1]) / (2 * h)
    assert abs(cd) > 1e-3 * abs(prob.get_val("flutter_ks")[0])
    assert slope == pytest.approx(cd, rel=1e-4)


def _check_stick_flutter_partials(comp):
    """StickFlutterDamping alone (its inputs at the model's values): its declared partials with respect
    to the wing's mass per length and stiffness at two stations, against central differences."""
    alone = om.Problem(reports=False)
    alone.model.add_subsystem("f", StickFlutterDamping(**{k: comp.options[k] for k in comp.options
                                                          if k in StickFlutterDamping().options}),
                              promotes=["*"])
    alone.setup(mode="rev")
    for name in comp.INPUTS:
        alone.set_val(name, comp.get_val(name))
    alone.run_model()
    J = alone.compute_totals(["flutter_ks"], ["mass_per_length", "stiffness_csn"])
    sensitive = 0
    for name, index in (("mass_per_length", (1,)), ("mass_per_length", (3,)), ("stiffness_csn", (2, 0, 0)),
                        ("stiffness_csn", (4, 2, 2))):
        x0 = np.array(alone.get_val(name))
        h = 1e-5 * abs(x0[index])
        vals = []
        for step in (h, -h):
            x = x0.copy()
            x[index] += step
            alone.set_val(name, x)
            alone.run_model()
            vals.append(alone.get_val("flutter_ks")[0])
        alone.set_val(name, x0)
        cd = (vals[0] - vals[1]) / (2 * h)
        exact = np.asarray(J["flutter_ks", name]).reshape(x0.shape)[index]
        assert exact == pytest.approx(cd, rel=1e-3, abs=1e-9 * abs(vals[0]) / h), (name, index)
        sensitive += abs(cd) * abs(x0[index]) > 1e-3 * abs(vals[0])   # elasticity above 1e-3
    assert sensitive >= 2
