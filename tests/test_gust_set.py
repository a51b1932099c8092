"""25.341(a) gust sets: U_ds against hand-computed values (U_ref table, F_g, (H/350)^(1/6)), gradient
lists, signs, case names, bad input, and a down-gust that mirrors an up-gust on a symmetric section.

Hand values (14 CFR 25.341(a)(4)-(6), Z_mo = 25 000 ft, R1 = 0.9, R2 = 0.8):
F_gz = 1 - 25000/250000 = 0.9, F_gm = sqrt(0.8 tan(0.9 pi/4)) = 0.826598, F_g(0) = 0.863299;
  h = 0 ft, H = 350 ft, V_C:   U_ref 56,            F_g 0.863299, U_ds = 48.3447 ft/s
  h = 10 000 ft, H = 100 ft:   U_ref 48,            F_g 0.917979, U_ds = 48 x 0.917979 x 0.811577 = 35.7599
  h = 30 000 ft, H = 30 ft:    U_ref 36.2867 (44 - 23.14/3), F_g 1 (above Z_mo), U_ds = 24.0948;
                                at V_D half: 12.0474
"""

import json

import numpy as np
import pytest

from wingmdao.cases import pegasus
from wingmdao.loads.gust_set import FlightPoint, GustSet, gust_set_from_dict, log_spaced_gradients_ft, read_gust_set

FT = 0.3048
FG = {"z_mo_ft": 25000.0, "mlw_over_mtow": 0.9, "mzfw_over_mtow": 0.8}


@pytest.mark.parametrize("alt, h, speed, u_ref, f_g, u_ds", [
    (0.0, 350.0, "VC", 56.0, 0.863299, 48.3447),
    (10000.0, 100.0, "VC", 48.0, 0.917979, 35.7599),
    (30000.0, 30.0, "VC", 36.2867, 1.0, 24.0948),
    (30000.0, 30.0, "VD", 18.1433, 1.0, 12.0474),
])
def test_u_ds_hand_values(alt, h, speed, u_ref, f_g, u_ds):
    gset = GustSet((FlightPoint(alt, mach=0.5, speed=speed),), [h], (1,), **FG)
    (g,) = gset.gusts()
    assert g.u_ref_fps == pytest.approx(u_ref, rel=2e-5)
    assert g.alleviation_factor == pytest.approx(f_g, rel=2e-6)
    assert g.u_ds_fps == pytest.approx(u_ds, rel=2e-5)
    assert g.u_ds_eas == pytest.approx(u_ds * FT, rel=2e-5)


def test_gradients_signs_and_names():
    h = log_spaced_gradients_ft(4)
    assert h[0] == pytest.approx(30.0) and h[-1] == pytest.approx(350.0)
    assert np.allclose(np.diff(np.log(h)), np.log(350.0 / 30.0) / 3)
    gset = gust_set_from_dict({"gradients_ft": [30, 120, 350], "signs": "both",
                               "flight_points": [{"altitude_ft": 20000, "mach": 0.5},
                                                 {"name": "vd", "altitude_ft": 20000, "mach": 0.6, "speed": "VD"}],
                               **FG})
    gusts = gset.gusts()
    assert len(gusts) == len(gset) == 12
    assert [g.sign for g in gusts[:2]] == [1, -1]
    assert gusts[0].name == "gust_fp0_h30_up" and gusts[-1].name == "gust_vd_h350_down"
    # V_D flight point: half the V_C gust at the same altitude and gradient
    assert gusts[6].u_ds_eas == pytest.approx(0.5 * gusts[0].u_ds_eas, rel=1e-12)
    up = GustSet((FlightPoint(0.0, mach=0.3),), [30.0, 60.0], (1,), **FG)
    assert [g.name for g in up.gusts()] == ["gust_h30_up", "gust_h60_up"]


def test_json_and_yaml_files(tmp_path):
    desc = {"gradient_count": 3, "signs": "down", "flight_points": [{"altitude_ft": 25000, "mach": 0.5}]}
    pj = tmp_path / "set.json"
    pj.write_text(json.dumps(desc))
    py = tmp_path / "set.yaml"
    py.write_text("gradient_count: 3\nsigns: down\nflight_points:\n  - {altitude_ft: 25000, mach: 0.5}\n")
    a, b = read_gust_set(str(pj), FG), read_gust_set(str(py), FG)
    assert a == b and len(a) == 3 and a.signs == (-1,)


@pytest.mark.parametrize("desc, message", [
    ({"gradients_ft": [20.0]}, "H = 20 ft; allowed range [30, 350] ft"),
    ({"gradients_ft": [30.0, 400.0]}, "H = 400 ft"),
    ({"gradients_ft": []}, "empty"),
    ({"gradients_ft": [30.0], "flight_points": []}, "flight_points is empty"),
    ({"gradients_ft": [30.0], "flight_points": [{"altitude_ft": 65000, "mach": 0.5}]},
     "altitude_ft = 65000.0; allowed range [0, 60000] ft"),
    ({"gradients_ft": [30.0], "flight_points": [{"altitude_ft": 1000}]}, "exactly one of mach"),
    ({"gradients_ft": [30.0], "signs": "sideways"}, "allowed up, down, both"),
    ({"gradients_ft": [30.0], "z_mo_ft": -5.0}, "z_mo_ft"),
    ({"gradient_count": 0}, "gradient_count = 0"),
    ({"gradients_ft": [30.0], "bogus": 1}, "unknown keys"),
])
def test_bad_input(desc, message):
    d = {"flight_points": [{"altitude_ft": 1000, "mach": 0.4}], **FG, **desc}
    with pytest.raises(ValueError, match=message.replace("[", r"\[").replace("]", r"\]").replace("(", r"\(")
                       .replace(")", r"\)").replace(".", r"\.")):
        gust_set_from_dict(d)


def test_pegasus_cli_flags_make_one_case_per_gust():
    args = pegasus.PegasusOptions(gust_gradients_ft=[30.0, 350.0], gust_sign="both", t_final=0.5, dt=0.05)
    setup = pegasus.build(args)
    names = [c.name for c in setup.load_cases]
    assert names == ["maneuver_pos", "maneuver_neg", "gust_h30_up", "gust_h30_down", "gust_h350_up", "gust_h350_down"]
    up, down = setup.load_cases[2], setup.load_cases[3]
    steady = pegasus.build(loads="gust", gust_gradients_ft=[30.0], gust_sign="up",
                           t_final=0.5, dt=0.05).load_cases[0]
    # same 1 g level flight; the gust increments are opposite
    f0 = up.forcing["force_per_length"][0]
    assert np.allclose(down.forcing["force_per_length"][0], f0)
    assert np.allclose(up.forcing["force_per_length"] - f0, -(down.forcing["force_per_length"] - f0), atol=1e-9)
    assert np.allclose(steady.forcing["force_per_length"], up.forcing["force_per_length"])
    with pytest.raises(ValueError, match="gradients_ft: H = 400 ft"):
        pegasus.build(gust_gradients_ft=[400.0])
    with pytest.raises(ValueError, match="one of --gust-set"):
        pegasus.build(gust_gradients_ft=[30.0], gust_gradient_count=3)


def test_down_gust_mirrors_up_gust_on_symmetric_section():
    """Gust increment only (no 1 g, no gravity), equal skins: the z-reflection maps the up-gust
    response onto the down-gust one, so their von Mises KS agree to round-off (the stresses of
    the upper skin in one are those of the lower skin in the other)."""
    from wingmdao.groups.load_case import LoadCase
    from wingmdao.sizing import build_problem

    args = pegasus.PegasusOptions(loads="gust", gust_gradients_ft=[60.0], t_final=0.3, dt=0.03, gust_start=0.0)
    setup = pegasus.build(args)
    geom = setup.geometry
    assert np.allclose(geom.node_positions[:, 2], 0.0) and np.allclose(geom.node_euler_angles[:, 0], 0.0)
    cases = []
    for c in setup.load_cases:
        f = c.forcing["force_per_length"] - c.forcing["force_per_length"][:1]
        m = c.forcing["moment_per_length"] - c.forcing["moment_per_length"][:1]
        cases.append(LoadCase(c.name, c.time, {"force_per_length": f, "moment_per_length": m}, ("vm",)))
    prob, _ = build_problem(geom, cases, setup.material, setup.options, driver=False)
    prob.run_model()
    ks_up = float(prob.get_val("cases.gust_h60_up.ks_vm")[0])
    ks_down = float(prob.get_val("cases.gust_h60_down.ks_vm")[0])
    g_up = np.sort(np.asarray(prob.get_val("cases.gust_h60_up.stress.g_vm")).ravel())
    g_down = np.sort(np.asarray(prob.get_val("cases.gust_h60_down.stress.g_vm")).ravel())
    assert g_up.max() > -0.999  # the gust loads the box
    assert ks_down == pytest.approx(ks_up, rel=1e-9, abs=1e-12)
    assert np.allclose(g_up, g_down, rtol=1e-8, atol=1e-12)


def test_pegasus_gust_set_file_and_sign_override(tmp_path):
    path = tmp_path / "set.yaml"
    path.write_text("gradients_ft: [30, 350]\nflight_points:\n  - {name: a, altitude_ft: 10000, mach: 0.4}\n"
                    "  - {name: b, altitude_ft: 20000, mach: 0.5, speed: VD, weight_lb: 35000}\n")
    setup = pegasus.build(gust_set=str(path), gust_sign="down", loads="gust",
                          t_final=0.5, dt=0.05)
    assert [c.name for c in setup.load_cases] == ["gust_a_h30_down", "gust_a_h350_down",
                                                  "gust_b_h30_down", "gust_b_h350_down"]
    # the file's flight points use the (a)(5) table and the PEGASUS F_g inputs (F_g < 1 below Z_mo)
    assert "F_g 0.9" in setup.load_cases[0].description and "(VD)" in setup.load_cases[2].description
    with pytest.raises(ValueError, match="does not exist"):
        pegasus.build(gust_set=str(tmp_path / "none.json"))
