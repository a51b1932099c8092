"""Exact totals of the stick model's gust KS (wingmdao.groups.stick) with respect to the wing's walls
and a tail parameter: reverse mode (the discrete adjoint of the joined aeroelastic march), forward
mode and central differences of the whole model."""

import numpy as np
import openmdao.api as om
import pytest

from wingmdao.cases import pegasus, pegasus_stick
from wingmdao.cases.planform import wing_geometry
from wingmdao.groups.stick import StickCase, StickSizing, set_stick_case
from wingmdao.materials import ALUMINIUM
from wingmdao.sizing import closed_loop_constraints, set_geometry

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
    prob = om.Problem(StickSizing(num_nodes=N, material=ALUMINIUM, stick_cases=[case], parallel=False), reports=False)
    prob.setup(mode=mode)
    set_geometry(prob, wing_geometry(pegasus.flutter_planform(N), ())[0])
    set_stick_case(prob, case, "cases.gust")
    th = pegasus.initial_thickness(N)
    for w in ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar"):
        prob.set_val(w, th.get(w, th.get(w[2:])))
    prob.run_model()
    return prob


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
    (["size", "pegasus", "--model", "stick"], "--model stick does not take --loads maneuver (the default)"),
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
