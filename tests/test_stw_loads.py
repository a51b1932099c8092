"""STW Case 1 maneuver loads (wingmdao.cases.stw_loads) and the case ``wingmdao size stw``."""

import csv
import json
import math

import numpy as np
import pytest

from wingmdao.aero.weissinger import weissinger_lift_slope
from wingmdao.cases import stw, stw_loads
from wingmdao.cases import stw_data as D
from wingmdao.cases.planform import G0
from wingmdao.cli import main


def helmbold_diederich(aspect, mach, sweep_half_chord, kappa=1.0):
    """Lift-curve slope (1/rad) of the DATCOM / Helmbold-Diederich formula (USAF DATCOM 4.1.3.2):
    a = 2 pi A / (2 + sqrt(A^2 beta^2 / kappa^2 (1 + tan^2 Lambda_c/2 / beta^2) + 4))."""
    b2 = 1.0 - mach ** 2
    return 2 * math.pi * aspect / (2 + math.sqrt(aspect ** 2 * b2 / kappa ** 2
                                                 * (1 + math.tan(sweep_half_chord) ** 2 / b2) + 4))


@pytest.mark.parametrize("mach", [0.0, D.PULL_UP.mach])
def test_weissinger_lift_slope_of_the_stw_against_datcom(mach):
    _, cl_alpha, res = weissinger_lift_slope([0.0], stw.chord, stw.leading_edge_x, D.SEMI_SPAN, mach=mach)
    sweep_half = math.atan((D.TIP_LE_OFFSET + 0.5 * (D.TIP_CHORD - D.ROOT_CHORD)) / D.SEMI_SPAN)  # 22.3 deg
    ref = helmbold_diederich(D.ASPECT_RATIO, mach, sweep_half)
    assert cl_alpha == pytest.approx(ref, rel=0.03)  # 4.59 / 4.95 against 4.70 / 5.07
    assert res["area"] == pytest.approx(2 * D.PLANFORM_AREA, rel=1e-9)


@pytest.mark.parametrize("sweep_le_deg,aspect,taper", [(45.0, 6.0, 0.5), (0.0, 8.0, 0.4), (30.0, 10.0, 0.3)])
def test_weissinger_lift_slope_of_other_swept_wings(sweep_le_deg, aspect, taper):
    cr = 1.0
    s = aspect * cr * (1 + taper) / 4  # semi-span for the aspect ratio (2s)^2 / (s cr (1 + lambda))
    chord = lambda y: cr + (taper * cr - cr) * np.asarray(y) / s  # noqa: E731
    le = lambda y: math.tan(math.radians(sweep_le_deg)) * np.asarray(y)  # noqa: E731
    _, cl_alpha, _ = weissinger_lift_slope([0.0], chord, le, s)
    half = math.atan((s * math.tan(math.radians(sweep_le_deg)) + 0.5 * (taper - 1) * cr) / s)
    assert cl_alpha == pytest.approx(helmbold_diederich(aspect, 0.0, half), rel=0.04)


def test_weissinger_slope_vanishes_at_the_tip_and_checks_input():
    y = np.linspace(0.0, D.SEMI_SPAN, 15)
    a, _, _ = weissinger_lift_slope(y, stw.chord, stw.leading_edge_x, D.SEMI_SPAN)
    assert a[-1] == 0.0 and np.all(a[:-1] > 0)
    with pytest.raises(ValueError, match="mach"):
        weissinger_lift_slope(y, stw.chord, stw.leading_edge_x, D.SEMI_SPAN, mach=1.2)
    with pytest.raises(ValueError, match="y must be"):
        weissinger_lift_slope([15.0], stw.chord, stw.leading_edge_x, D.SEMI_SPAN)


def test_rigid_strip_loads_centre_of_pressure():
    """Rigid strip loads l = q c a(y) alpha: centre of pressure at 40-45 % of the semi-span (elliptic:
    4 / (3 pi) = 42.4 %; taper 0.3 and sweep move it slightly outboard), and the root bending moment
    of the half-wing lift at that arm."""
    y = np.linspace(0.0, D.SEMI_SPAN, 2001)
    a, cl_alpha = stw_loads.spanwise_lift_slope(y)
    lift = a * stw.chord(y)  # per unit q alpha
    half = np.trapezoid(lift, y)
    eta_cp = np.trapezoid(lift * y, y) / half / D.SEMI_SPAN
    assert 0.40 < eta_cp < 0.45
    assert 2 * half / (2 * D.PLANFORM_AREA) == pytest.approx(cl_alpha, rel=2e-3)  # the strips hold CL_alpha
    rbm = np.trapezoid(lift * y, y)
    assert rbm == pytest.approx(eta_cp * D.SEMI_SPAN * half)


def test_strip_parameters_reproduce_the_streamwise_lift_per_span():
    """chord c cos Lambda_b and slope beta a cos Lambda_o with the model's v_c = V cos Lambda_b and
    trim angle alpha / cos Lambda_o: lift per beam length = q c a alpha cos Lambda_b = l dy/ds."""
    beam = stw.beam_geometry(30)
    sp = stw_loads.strip_parameters(beam)
    lam_b, lam_o = np.radians(beam.sweep_deg), sp["sweep_out"]
    alpha = 0.05
    beta = stw_loads.beta()
    model = sp["chord"] * sp["lift_slope"] / beta * (alpha / math.cos(lam_o))  # q c_p a_p / beta * angle
    wanted = beam.chord * sp["strip_slope"] * alpha * np.cos(lam_b)
    assert np.allclose(model[:-1], wanted[:-1], rtol=1e-12)
    assert math.degrees(lam_o) == pytest.approx(math.degrees(math.atan(6.1 / 14)))
    a0, cm0 = stw_loads.camber_coefficients()
    assert -3.0 < math.degrees(a0) < -1.5 and -0.12 < cm0 < -0.04  # RAE 2822: aft-loaded, cambered


def test_build_validates_before_any_solve():
    for kw, flag in (({"num_nodes": 10}, "--num-nodes"), ({"wingbox_mass": -5.0}, "--wingbox-mass"),
                     ({"families": "xx"}, "--families")):
        with pytest.raises(ValueError, match=flag):
            stw.build(**kw)
    with pytest.raises(ValueError, match="loads"):
        stw.build(loads="gust")
    setup = stw.build()
    assert setup.section == "stiffened" and setup.panels.shape == "tee" and setup.panels.flange_ratio == 1.0
    assert setup.panels.stiffener_pitch == 0.15 and setup.panels.safety_factor == 1.5
    assert np.allclose(setup.panels.rib_positions, stw.rib_y())
    assert setup.options.lower["t_upper_skin"] == 0.6e-3 and setup.options.lower["t_upper_stiffener"] == 0.6e-3
    assert setup.options.lower["h_upper_stiffener"] == pytest.approx(25.4e-3)
    assert [c.name for c in setup.load_cases] == ["pullup", "pushdown"]
    lgm = setup.stw["landing_gross_mass_kg"]
    assert lgm == pytest.approx(D.landing_gross_mass(setup.stw["wingbox_mass_kg"]))
    for case, n in zip(setup.load_cases, (2.5, -1.0)):
        assert case.aero.trim and case.aero.trim_lift == pytest.approx(n * lgm * G0)
        assert case.forcing_array("frame_acceleration", 23)[0, 2] == pytest.approx((n - 1) * G0)
    assert stw.build(wingbox_mass=1000.0).stw["landing_gross_mass_kg"] == pytest.approx(
        D.landing_gross_mass(1000.0))


def test_size_stw_analysis_only_json_and_distributions(tmp_path, capsys):
    rc = main(["size", "stw", "--analysis-only", "--no-plots", "--out", str(tmp_path), "--json", "-"])
    assert rc == 0
    cap = capsys.readouterr()
    res = json.loads(cap.out)  # standard output holds the JSON and nothing else
    assert res["case"] == "stw"
    lgm = res["loads_landing_gross_mass_kg"]
    assert lgm == pytest.approx(D.landing_gross_mass(res["loads_wingbox_mass_kg"]))
    for name, n in (("pullup", 2.5), ("pushdown", -1.0)):
        m = res["maneuvers"][name]
        assert m["total_lift_n"] == pytest.approx(n * lgm * G0, rel=1e-3)  # trimmed: n LGM g within 0.1 %
        assert m["load_factor"] == pytest.approx(n, rel=1e-3)
        assert np.sign(m["root_bending_moment_n_m"]) == np.sign(n)
        path = m["distribution_file"]
        assert path == str(tmp_path / f"stw_maneuver_{name}_distribution.csv")
        with open(path, newline="") as fh:
            rows = list(csv.reader(fh))
        assert tuple(rows[0]) == stw_loads.CSV_COLUMNS
        data = np.array(rows[1:], dtype=float)
        assert data.shape == (D.NUM_RIBS, 5)  # one row per beam station (23 by default)
        y, eta, lift, cl, twist = data.T
        assert np.allclose(y, stw.beam_geometry().y) and np.allclose(eta, y / 14.0)
        assert 2 * np.trapezoid(lift, y) == pytest.approx(n * lgm * G0, rel=0.03)
        assert twist[0] == pytest.approx(0.0, abs=1e-9)  # clamped root
        assert np.sign(twist[-1]) == -np.sign(n)  # bending up washes the swept tip out
    pull, push = res["maneuvers"]["pullup"], res["maneuvers"]["pushdown"]
    # hand reference: alpha = n LGM g / (q 2 S CL_alpha) + alpha_0, before the elastic wash-out
    q = 0.5 * 1.225 * (D.PULL_UP.mach * 340.294) ** 2
    _, cla = stw_loads.spanwise_lift_slope([0.0])
    a0 = math.degrees(stw_loads.camber_coefficients()[0])
    rigid = [math.degrees(n * lgm * G0 / (q * 2 * D.PLANFORM_AREA * cla)) + a0 for n in (2.5, -1.0)]
    assert rigid[0] < pull["alpha_deg"] < rigid[0] + 4.0  # wash-out asks for more angle
    assert rigid[1] - 2.0 < push["alpha_deg"] < rigid[1] + 0.1


@pytest.mark.parametrize("argv,flag", [(["--num-nodes", "5"], "--num-nodes"),
                                       (["--wingbox-mass", "-3"], "--wingbox-mass"),
                                       (["--loads", "gust"], "--loads"),
                                       (["--families", "bogus"], "--families")])
def test_bad_input_exit_code_2(argv, flag, tmp_path, capsys):
    with pytest.raises(SystemExit) if flag == "--loads" else _nothing() as exc:
        rc = main(["size", "stw", "--analysis-only", "--no-plots", "--out", str(tmp_path), *argv])
    rc = exc.value.code if flag == "--loads" else rc
    assert rc == 2
    assert flag in capsys.readouterr().err


class _nothing:
    def __enter__(self):
        return self

    def __exit__(self, *a):
        return False
