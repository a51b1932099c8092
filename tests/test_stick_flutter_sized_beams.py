"""The stick aircraft's flutter constraint with sized tail and fuselage sections (``size --model
stick --size-beams tail,fuselage --flutter-margin``): StickFlutterDamping's partials with respect to
the tail box's and the fuselage tube's beam parameters against central differences of the component
alone, and the total of ``flutter_ks`` along a tail wall and along the fuselage wall against central
differences of the whole sizing model (walls -> sections -> flutter eigenvalues)."""

import numpy as np
import openmdao.api as om
import pytest

from wingmdao.cases import pegasus, pegasus_stick
from wingmdao.cases.planform import wing_geometry
from wingmdao.components.flutter import StickFlutterDamping
from wingmdao.groups.stick import StickCase, StickSizing, set_sized_beams, set_stick_case
from wingmdao.materials import ALUMINIUM
from wingmdao.sizing import set_geometry
from wingmdao.timemarch.system import layout

N = 5
WALLS = ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")


@pytest.fixture(scope="module")
def model():
    """The stick sizing model (a short gust case, sized tail and fuselage, the flutter constraint at
    the two upper speeds of the 1.15 V_D set with a 16-mode window), its walls varied along the beams."""
    ac = pegasus_stick.build(N)
    s = pegasus_stick.aeroelastic_system(ac)
    fp = pegasus.flight_point()
    V = fp["cruise_speed"]
    t = np.linspace(0.0, 0.06, 4)
    p = pegasus_stick.aero_parameters(ac, s, airspeed=V, density=fp["density"], mach=0.5)
    Q = pegasus_stick.gust_forcing(ac, s, t, airspeed=V, u_ds_tas=15.0, gradient=20.0, gust_start=0.02)
    case = StickCase("gust", s, t, p, Q)
    sized = pegasus_stick.sized_beams(case, ["tail", "fuselage"])
    opts = pegasus_stick.flutter_options(case, 1.15)
    opts.update(speeds=opts["speeds"][2:], eig_options={"method": "sparse", "sigma": 60j, "count": 16, "ncv": 40})
    prob = om.Problem(StickSizing(num_nodes=N, material=ALUMINIUM, stick_cases=[case], parallel=False,
                                  stick_flutter=opts, sized_beams=sized), reports=False)
    prob.setup(mode="rev")
    set_geometry(prob, wing_geometry(pegasus.flutter_planform(N), ())[0])
    set_sized_beams(prob, sized)
    set_stick_case(prob, case, "cases.gust", sized)
    th = pegasus.initial_thickness(N)
    for k, w in enumerate(WALLS):
        prob.set_val(w, np.asarray(th.get(w, th.get(w[2:])), dtype=float) * (1.0 + 0.1 * k * np.linspace(-1, 1, N)))
    for b in sized:
        for k, v in enumerate(b.design_vars):
            prob.set_val(v, b.initial * (0.7 + 0.1 * k + 0.5 * np.linspace(0.0, 1.0, b.num_nodes) ** 2))
    prob.run_model()
    return prob, case, sized


def test_flutter_follows_the_sized_sections(model):
    """The flutter component takes the sized tail's and fuselage's section outputs (not the case's
    packed data, from which the varied walls move them), and its partials with respect to them
    match central differences of the component alone; a beam_inputs entry that is no other beam's
    parameter is refused at setup."""
    prob, case, sized = model
    comp = prob.model.stick_flutter
    lay, p = layout(case.system.param_specs), np.asarray(case.p)
    names = [k for b in sized for k in b.beam_inputs]
    assert set(names) >= {"tail_stiffness_csn", "tail_shear_center", "fuselage_compliance_csn"}
    for name in names:
        np.testing.assert_array_equal(comp.get_val(name), prob.get_val(name))
    for name in ("tail_stiffness_csn", "fuselage_mass_per_length"):
        given = p[lay[name]]
        assert np.linalg.norm(prob.get_val(name).ravel() - given) > 0.05 * np.linalg.norm(given)
    options = {k: comp.options[k] for k in comp.options if k in StickFlutterDamping().options}
    for bad in ("airspeed", "wing_stiffness_csn", "tail_chord_x"):
        wrong = om.Problem(reports=False)
        wrong.model.add_subsystem("f", StickFlutterDamping(**{**options, "beam_inputs": [bad]}))
        with pytest.raises(ValueError, match=f"beam_inputs entry '{bad}' is not a parameter of a beam other"):
            wrong.setup()
    alone = om.Problem(reports=False)
    alone.model.add_subsystem("f", StickFlutterDamping(**options), promotes=["*"])
    alone.setup(mode="rev")
    for name in (*comp.INPUTS, *names):
        alone.set_val(name, comp.get_val(name))
    alone.run_model()
    assert alone.get_val("flutter_ks")[0] == pytest.approx(prob.get_val("flutter_ks")[0], rel=1e-10)
    picks = (("tail_mass_per_length", (2,)), ("tail_stiffness_csn", (3, 0, 0)), ("tail_stiffness_csn", (1, 2, 2)),
             ("tail_shear_center", (4, 0)), ("fuselage_mass_per_length", (5,)),
             ("fuselage_stiffness_csn", (7, 0, 0)), ("fuselage_compliance_csn", (3, 1)))
    J = alone.compute_totals(["flutter_ks"], sorted({n for n, _ in picks}))
    sensitive = 0
    for name, index in picks:
        x0 = np.array(alone.get_val(name))
        scale = abs(x0[index]) or 1e-2   # a zero offset: 1 cm
        h = 1e-5 * scale
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
        sensitive += abs(cd) * scale > 1e-4 * abs(vals[0])
    assert sensitive >= 5


def test_flutter_totals_wrt_tail_and_fuselage_walls(model):
    """d flutter_ks / d(tail upper skin, fuselage wall), reverse mode through the sized sections,
    along a direction over the stations against central differences of the whole model."""
    prob, _, _ = model
    rng = np.random.default_rng(7)
    J = prob.compute_totals(["flutter_ks"], ["tail_t_upper_skin", "fuselage_t_wall"])
    f0 = prob.get_val("flutter_ks")[0]
    for name in ("tail_t_upper_skin", "fuselage_t_wall"):
        base = prob.get_val(name).copy()
        direction = rng.uniform(0.5, 1.0, base.size) * base
        slope = float(np.asarray(J["flutter_ks", name])[0] @ direction)
        h, vals = 1e-4, []
        for step in (h, -h):
            prob.set_val(name, base + step * direction)
            prob.run_model()
            vals.append(prob.get_val("flutter_ks")[0])
        prob.set_val(name, base)
        cd = (vals[0] - vals[1]) / (2 * h)
        assert abs(cd) > 1e-4 * abs(f0), name
        assert slope == pytest.approx(cd, rel=1e-4), name
    prob.run_model()
