"""The two-level stiffened sizing (wingmdao.panels.equivalent, EquivalentPanelFailure,
wingmdao.panel_sizing; docs/panels.md, "Two-level sizing")."""

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials
from scipy.optimize import minimize

from wingmdao.components.panels import EquivalentPanelFailure
from wingmdao.components.section import BoxSection
from wingmdao.materials import ALUMINIUM
from wingmdao.panel_sizing import adjacency, envelope_states
from wingmdao.panels.box_panels import SKIN_MODES, skin_panel_ratios
from wingmdao.panels.equivalent import (FARRAR_EFFICIENCY, SKIN_SHARE, equivalent_compression_allowables,
                                        equivalent_shear_allowable, equivalent_skin_ratio)
from wingmdao.panels.layout import smeared_stringer
from wingmdao.section.box import WALL_NAMES
from wingmdao.stress.box_stress import SECTION_PROPERTIES


def _minimum_weight_panel(n, length, starts):
    """The detailed model's lightest blade panel (skin t, blade h x ts, pitch p free; mm) carrying
    the compressive running load n (N/m) over ``length`` (m): SLSQP from several starts."""
    best = None
    for x0 in starts:
        def teq(x):
            return x[0] + smeared_stringer(x[1], x[2], x[3], "blade")[0]   # mm

        def cons(x):
            r = skin_panel_ratios(ALUMINIUM, x[0] * 1e-3, x[1] * 1e-3, x[2] * 1e-3, x[3] * 1e-3, length, -n, 0.0)
            return np.array([1.0 - r[m] for m in SKIN_MODES])

        res = minimize(teq, x0, method="SLSQP", bounds=[(0.1, 50), (2, 300), (0.1, 30), (10, 600)],
                       constraints=[{"type": "ineq", "fun": cons}], options={"maxiter": 500, "ftol": 1e-12})
        if res.success and cons(res.x).min() > -1e-6 and (best is None or res.fun < best.fun):
            best = res
    return best


@pytest.mark.parametrize("n_over_l, rel", [(1e5, 0.05), (2e5, 0.05), (5e4, 0.12)])
def test_farrar_efficiency_of_the_detailed_panel_model(n_over_l, rel):
    """Farrar's blade-stiffened efficiency F = 0.81 (sigma = F sqrt(N E / L); Farrar 1949, Niu
    Ch. 14) recovered from the detailed model's own minimum-weight panel (skin, stiffener and
    pitch free, every mode of SKIN_MODES at 1): within 5 % at N/L = 1e5 and 2e5 N/m^2 (0.84,
    0.80); the model's F drifts with the load (0.89 at 5e4, 0.77 at 3e5) because its stiffener
    column's Johnson cut-off, Needham's crippling, scales as sqrt(E F_cy), not elastically."""
    length = 0.62
    n = n_over_l * length
    starts = [(t, h, ts, 30.0) for t in (0.3, 1.0) for h in (15.0, 40.0) for ts in (0.5, 2.0)]
    best = _minimum_weight_panel(n, length, starts)
    assert best is not None
    sigma = n / (best.fun * 1e-3)
    f = sigma / np.sqrt(n * ALUMINIUM.E / length)
    assert f == pytest.approx(FARRAR_EFFICIENCY["blade"], rel=rel)


def test_equivalent_ratio_against_the_detailed_fixed_pitch_optimum():
    """At the 0.15 m pitch and the PEGASUS rules, the detailed model's minimum-weight panels
    (SLSQP over t, h, ts at six running loads from 20 kN/m to 4 MN/m) sit at an equivalent ratio
    of 0.9 to 1.25: the outer constraint is conservative up to 25 % in load at mid loads and
    no more than 10 % unconservative where the material caps the stress."""
    length, pitch = 0.62, 0.15

    def lightest(n):
        best = None
        for x0 in [(t, h, ts) for t in (1.5, 4.0, 12.0) for h in (20.0, 60.0) for ts in (1.5, 6.0)]:
            def cons(x):
                r = skin_panel_ratios(ALUMINIUM, x[0] * 1e-3, x[1] * 1e-3, x[2] * 1e-3, pitch, length, -n, 0.0)
                return np.array([1.0 - r[m] for m in SKIN_MODES] + [x[1] / x[2] - 5, 30 - x[1] / x[2],
                                                                     15 * x[0] - x[2]])
            res = minimize(lambda x: x[0] + smeared_stringer(x[1], x[2], pitch * 1e3, "blade")[0], x0, method="SLSQP",
                           bounds=[(1, 100), (15, 100), (1, 8)], constraints=[{"type": "ineq", "fun": cons}],
                           options={"maxiter": 500, "ftol": 1e-12})
            if res.success and cons(res.x).min() > -1e-6 and (best is None or res.fun < best.fun):
                best = res
        return best.fun * 1e-3

    ratios = [equivalent_skin_ratio(ALUMINIUM, lightest(n), length, pitch, -n, 0.0)
              for n in (2e4, 1e5, 5e5, 1e6, 2e6, 4e6)]
    assert 0.9 < min(ratios) and max(ratios) < 1.25


def test_equivalent_ratio_is_load_linear():
    """The equivalent ratio doubles with the loads (a safety factor scales it exactly)."""
    for nx, nxy in ((-3e5, 4e4), (2e5, 6e4), (-1e6, 0.0)):
        r1 = equivalent_skin_ratio(ALUMINIUM, 5e-3, 0.6, 0.15, nx, nxy)
        r2 = equivalent_skin_ratio(ALUMINIUM, 5e-3, 0.6, 0.15, 2 * nx, 2 * nxy)
        assert r2 == pytest.approx(2 * r1, rel=1e-6)


@pytest.mark.parametrize("length", [0.3, 0.62, 1.5])
def test_equivalent_skin_allowables_timoshenko(length):
    """The skin terms against Timoshenko & Gere's isotropic plate (2nd ed., Secs. 9.2 and 9.7):
    compression k = 4 at the panel's stress, 4 pi^2 E (phi t)^2 t / (12 (1 - nu^2) b^2); shear
    k_s = 5.35 + 4 (b/L)^2 within 0.3 % (the long plate's 5.34 of the buckling module's fit)."""
    t, b = 4e-3, 0.15
    d = np.pi ** 2 * ALUMINIUM.E / (12.0 * (1.0 - ALUMINIUM.nu ** 2))
    n = equivalent_compression_allowables(ALUMINIUM, t, length, b)
    assert n["skin"] == pytest.approx(4.0 * d * (SKIN_SHARE * t) ** 2 * t / b ** 2, rel=1e-12)
    ks = 5.35 + 4.0 * (b / length) ** 2
    assert equivalent_shear_allowable(ALUMINIUM, t, length, b) == pytest.approx(
        ks * d * (SKIN_SHARE * t) ** 3 / b ** 2, rel=3e-3)


def test_equivalent_panel_failure_partials():
    """check_partials of EquivalentPanelFailure (per-point g, then its KS aggregate) on a
    non-trivial design (skins in compression and in tension, ratios 0.01 to 12), the section
    properties from BoxSection, against central differences."""
    nt, n = 3, 3
    for ks_rho in (None, 50.0):
        prob = om.Problem(reports=False)
        prob.model.add_subsystem("section", BoxSection(num_stations=n, material=ALUMINIUM), promotes_inputs=["*"])
        prob.model.add_subsystem("panels", EquivalentPanelFailure(num_times=nt, num_stations=n, material=ALUMINIUM,
                                                                  ks_rho=ks_rho),
                                 promotes_inputs=["width", "height", *WALL_NAMES, "panel_length", "F_csn", "M_csn"])
        for name in SECTION_PROPERTIES:
            prob.model.connect(f"section.{name}", f"panels.{name}")
        prob.setup(force_alloc_complex=True)
        rng = np.random.default_rng(7)
        prob.set_val("width", rng.uniform(0.6, 1.0, n))
        prob.set_val("height", rng.uniform(0.15, 0.3, n))
        for i, w in enumerate(WALL_NAMES):
            prob.set_val(w, rng.uniform(2e-3, 9e-3, n) * (1 + 0.3 * i))
        prob.set_val("nonstructural_mass_per_length", [5.0, 4.0, 3.0])
        prob.set_val("panel_length", rng.uniform(0.4, 0.8, n))
        prob.set_val("F_csn", rng.normal(0, 3e4, (nt, n, 3)))
        prob.set_val("M_csn", rng.normal(0, 1e5, (nt, n, 3)))
        prob.run_model()
        data = prob.check_partials(method="fd", form="central", step=1e-6, step_calc="rel", out_stream=None)
        if ks_rho is not None:   # aggregated: only ks_equivalent_panels carries partials (KSOfPointwise)
            data["panels"] = {k: v for k, v in data["panels"].items() if k[0] == "ks_equivalent_panels"}
            assert data["panels"]
        assert_check_partials(data, atol=1e-5, rtol=2e-4)


def test_envelope_keeps_every_non_dominated_state():
    """Every state outside the envelope is covered by an envelope state in all its loads."""
    rng = np.random.default_rng(3)
    nx, nxy, ny = rng.normal(0, 1e5, 300), rng.normal(0, 3e4, 300), rng.normal(0, 1e4, 300)
    keep = envelope_states(nx, nxy, ny)
    x = np.column_stack([np.maximum(-nx, 0), np.abs(nxy), np.maximum(-ny, 0)])
    for i in set(range(300)) - set(keep):
        assert np.any(np.all(x[keep] >= x[i], axis=1))


def test_adjacency_raises_the_thinner_neighbour():
    x = adjacency(np.array([[0.02, 0.08, 0.006], [0.003, 0.03, 0.001], [0.003, 0.03, 0.001]]))
    assert np.all(np.abs(np.diff(x[:, 0])) <= 2.5e-3 + 1e-12)
    assert np.all(np.abs(np.diff(x[:, 1])) <= 10e-3 + 1e-12)
    assert np.all(x[:, 1] / x[:, 2] <= 30 + 1e-9)
    assert x[0].tolist() == [0.02, 0.08, 0.006]


@pytest.mark.slow
def test_two_level_pegasus_maneuver_sizing():
    """The two-level sizing of the stiffened PEGASUS maneuvers: every detailed check of the
    recovered design on the full model within its allowable (every margin >= 0 after the polish
    passes), the upper skin heavier than the lower one inboard (compression at
    2.5 g), and a mass within 3 % of the full stiffened SLSQP sizing's (644.50 kg,
    docs/panels.md, a different optimizer on the same model)."""
    from wingmdao.cases import pegasus
    from wingmdao.panel_sizing import size_two_level

    setup = pegasus.build(loads="maneuver", panels="stiffened")
    setup.options.disp = False
    _, res = size_two_level(setup)
    worst = res["two_level"]["passes"][-1]["margin_of_safety"]
    assert worst >= 0.0
    assert res["mass_kg"] == pytest.approx(644.50, rel=0.03)
    assert sum(res["mass_breakdown_kg"].values()) == pytest.approx(res["mass_kg"], rel=1e-9)
    eq = {s: np.asarray(res["panels"][f"{s}_skin"]["equivalent_thickness_m"]) for s in ("upper", "lower")}
    assert np.all(eq["upper"][:5] > 1.3 * eq["lower"][:5])


@pytest.mark.parametrize("extra, message", [
    ([], "--panel-sizing two-level needs --panels stiffened"),
    (["--panels", "stiffened", "--flutter-margin", "1.15"], "does not take --flutter-margin"),
])
def test_cli_refuses_two_level_without_what_it_needs(tmp_path, capsys, extra, message):
    """A one-line error naming the flag before any solve."""
    from wingmdao.cli import main

    code = main(["size", "pegasus", "--loads", "maneuver", "--panel-sizing", "two-level", *extra, "--no-plots",
                 "--out", str(tmp_path), "--json", str(tmp_path / "r.json")])
    assert code == 2
    assert message in capsys.readouterr().err


def test_outer_level_totals_match_central_differences():
    """The outer level's problem (section box, the equivalent-panel family in every case, a short
    gust): totals of ks_equivalent_panels and ks_vm of a maneuver and the gust with respect to
    the 76 walls, reverse against central differences, at a random design."""
    from wingmdao.cases import pegasus
    from wingmdao.panel_sizing import outer_setup
    from wingmdao.sizing import WALL_VARS, build_problem

    args = pegasus.PegasusOptions(loads="all", t_final=0.4, dt=0.04, gust_start=0.0, panels="stiffened")
    setup = pegasus.build(args)
    outer = outer_setup(setup)
    rng = np.random.default_rng(11)
    outer.options.initial = {w: rng.uniform(0.004, 0.012, 19) for w in WALL_VARS}
    outer.options.disp = False
    prob, _ = build_problem(outer.geometry, outer.load_cases, outer.material, outer.options, section="box",
                            equivalent_panels=setup.panels)
    prob.run_model()
    of = [f"cases.{c}.ks_{f}" for c in ("maneuver_pos", "gust") for f in ("vm", "equivalent_panels")]
    data = prob.check_totals(of=of, wrt=list(WALL_VARS), method="fd", form="central", step=1e-7,
                             step_calc="rel_avg", out_stream=None)
    worst = 0.0
    for d in data.values():
        j = d["J_fwd"] if "J_fwd" in d else d["J_rev"]
        worst = max(worst, np.abs(j - d["J_fd"]).max() / max(np.abs(d["J_fd"]).max(), 1e-12))
    assert worst < 1e-4, worst
