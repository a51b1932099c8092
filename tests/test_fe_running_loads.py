"""The skins' running loads of the stiffened-box deck's static state
(:func:`wingmdao.fe.stiffened_box.skin_running_loads`, ``wingmdao verify pegasus --buckling
--running-loads``) against thin-walled beam theory, and the sizing model's running loads
(:func:`wingmdao.panel_results.model_running_loads`) against ``panel_running_loads`` by hand.
The CalculiX test is skipped when ``ccx`` is not installed."""

import shutil

import numpy as np
import pytest

from wingmdao.materials import Material

MAT = Material("al", E=70e9, rho=2700.0, sigma_y=276e6, nu=0.33)
SPAN, W, H, T, HS, TS, PITCH, F = 2.0, 0.6, 0.2, 0.002, 0.02, 0.002, 0.15, 10e3


@pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX ccx not installed")
def test_fe_running_loads_of_a_stiffened_box_in_bending():
    """A uniform box 2 m long (0.6 x 0.2 m, 2 mm walls, 4 blades 20 x 2 mm per skin at 0.15 m),
    clamped, 10 kN up at the tip rib. At mid-span (away from the clamp and the tip) the skins'
    spanwise load at mid-chord is M n t / I of the FE's own mid-surface section (skins at +-b,
    webs of height 2 b, blades from the skin mid-surface to the inner face plus h; I by hand
    here, Euler-Bernoulli), within 3 %; the lower skin's shear flow from the vertical shear
    runs antisymmetric about mid-chord (its chordwise resultant about zero) and its front half's
    resultant is (F / I) times the integral of the first moment Q(c) of the skin and blades
    between mid-chord and c (thin-walled closed section; Megson, Aircraft Structures, 4th ed.,
    2007, Sec. 17.3), within 3 %; no chordwise load without a distributed load (|N_c| < 3 % of
    N_span)."""
    from wingmdao.fe.box_model import BoxSections
    from wingmdao.fe.stiffened_box import build_stiffened_box, running_load_profile, skin_running_loads

    walls = {k: T for k in ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")}
    sec = BoxSections(centres=[(0, 0, 0), (0, SPAN, 0)], widths=W, heights=H, thickness=walls)
    stiff = {s: (HS, TS) for s in ("upper", "lower")}
    model = build_stiffened_box(sec, MAT, stiff, PITCH, count=4, span_element_size=0.1, ribs_y=[SPAN],
                                rib_thickness=0.01)
    loads = [(SPAN, np.array([0.0, SPAN, 0.0]), np.array([0.0, 0.0, F]), np.zeros(3))]   # at the tip section centre
    fe = skin_running_loads(model, loads, span_range=(0.9, 1.1))
    a, b = W / 2 - T / 2, H / 2 - T / 2                 # mid-surface half width and half height
    ts = TS * model.thickness_scale[0]                  # the FE blades' thickness (area per width kept)
    hb = T / 2 + HS                                     # blade from the skin mid-surface inward
    I_ = 2 * (2 * a * T * b**2) + 2 * (T * (2 * b) ** 3 / 12) \
        + 2 * 4 * (ts * hb**3 / 12 + ts * hb * (b - hb / 2) ** 2)
    for skin, sign in (("upper", -1.0), ("lower", 1.0)):
        rows = running_load_profile(fe[skin])
        assert len(rows) == 2                           # the two element rows about mid-span
        for row in rows:
            expected = sign * F * (SPAN - row["y_m"]) * b * T / I_
            assert row["n_span_mid"] == pytest.approx(expected, rel=0.03)
            assert abs(row["n_chord_mid"]) < 0.03 * abs(expected)
    y_mid = rows[0]
    low = fe["lower"]
    row = np.abs(low["y_m"] - y_mid["y_m"]) < 1e-6
    x, q = low["x_m"][row], low["n_shear"][row]
    order = np.argsort(x)
    x, q = x[order], q[order]
    edges = np.concatenate([[-a], 0.5 * (x[1:] + x[:-1]), [a]])
    dw = np.diff(edges)
    h_front = float(np.sum((q * dw)[x < 0]))
    h_total = float(np.sum(q * dw))
    # q(c) = F Q(c) / I, Q the first moment of the skin and the blades between mid-chord and c:
    # H_front = (F / I) [T b a^2 / 2 + sum over the front blades of A_k z_k (a - |c_k|)]
    offsets = (np.arange(4) - 1.5) * PITCH
    blades = sum(ts * hb * (b - hb / 2) * (a - abs(c)) for c in offsets if c < 0)
    expected_front = F * (T * b * a**2 / 2 + blades) / I_
    assert abs(h_front) == pytest.approx(expected_front, rel=0.03)
    assert abs(h_total) < 0.05 * expected_front


def test_model_running_loads_match_panel_running_loads():
    """``model_running_loads`` reads the panel component's inputs and returns, per station,
    what :func:`wingmdao.stress.box_stress.panel_running_loads` gives for them (skin plus blade
    area per width h t / p), on the stiffened PEGASUS maneuver analysis."""
    from wingmdao.cases import pegasus
    from wingmdao.panel_results import model_running_loads
    from wingmdao.sizing import build_problem
    from wingmdao.stress.box_stress import SECTION_PROPERTIES, panel_running_loads

    setup = pegasus.build(loads="maneuver", panels="stiffened")
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False,
                            section="stiffened", panels=setup.panels)
    prob.run_model()
    out = model_running_loads(prob, "maneuver_pos", setup.panels)
    path = "cases.maneuver_pos.panels."
    k = 10
    g = {n: np.asarray(prob.get_val(path + n)).reshape(-1) for n in (
        "width", "height", "t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar", "h_lower_stiffener",
        "t_lower_stiffener", "h_upper_stiffener", "t_upper_stiffener", *SECTION_PROPERTIES)}
    p = setup.panels.stiffener_pitch
    t_ax = [g["t_upper_skin"][k] + g["h_upper_stiffener"][k] * g["t_upper_stiffener"][k] / p,
            g["t_lower_skin"][k] + g["h_lower_stiffener"][k] * g["t_lower_stiffener"][k] / p]
    ref = panel_running_loads(np.asarray(prob.get_val(path + "F_csn"))[0, k],
                              np.asarray(prob.get_val(path + "M_csn"))[0, k], g["width"][k], g["height"][k],
                              *(g[w][k] for w in ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")),
                              t_ax, {n: g[n][k] for n in SECTION_PROPERTIES},
                              force_gradient=np.asarray(prob.get_val(path + "dF_csn_ds"))[0, k])
    assert setup.panels.shape == "blade"
    assert out["lower"]["n_span_front"][k] == pytest.approx(float(ref["nx_skin"][2]), rel=1e-12)
    assert out["lower"]["n_shear_rear"][k] == pytest.approx(float(ref["nxy_skin"][3]), rel=1e-12)
    assert out["upper"]["n_chord"][k] == pytest.approx(float(ref["ny_skin"][0]), rel=1e-12)
    assert out["lower"]["n_span_front"][k] > 0 > out["upper"]["n_span_front"][k]     # 2.5 g: lower in tension
