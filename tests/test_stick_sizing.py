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
from wingmdao.sizing import set_geometry

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
