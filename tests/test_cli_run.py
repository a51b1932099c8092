"""``wingmdao run wing-box``: static and dynamic responses, stresses and total derivatives."""

import json

import numpy as np
import pytest

from wingmdao.cli import main

P = 1.0e5  # N
E, G = 70e9, 70e9 / 2.66
I_BOX = 3 * 0.5**3 / 12 - 2.6 * 0.3**3 / 12  # 0.0254 m^4: 3 x 0.5 box, skins 0.1, webs 0.2 x 0.3
A_WEB = 2 * 0.2 * 0.3  # m^2


def _run(tmp_path, *extra):
    out = tmp_path / "r.json"
    assert main(["run", "wing-box", *extra, "--json", str(out)]) == 0
    return json.loads(out.read_text())


def _static_tip_deflection():
    """Hand value: P L^3/(3 E I) + P L/(G A_web), L = 10 m."""
    return P * 10.0**3 / (3 * E * I_BOX) + P * 10.0 / (G * A_WEB)


def test_run_wing_box_prismatic(tmp_path):
    data = _run(tmp_path, "--geometry", "prismatic", "--tip-load", "0", "0", str(P))
    assert data["stations"] == ["CS1", "CS2", "CS3", "CS4"]
    assert len(data["displacement"]) == 4 and data["displacement"][0] == pytest.approx(0.0, abs=1e-15)
    assert data["tip_displacement"][2] == pytest.approx(_static_tip_deflection(), rel=5e-3)
    assert data["displacement"][3] == pytest.approx(np.linalg.norm(data["tip_displacement"]))
    assert len(data["tip_rotation"]) == 3 and data["tip_rotation"][0] > 0
    # von Mises at the root mid-corners: sigma = M n / I with M = P L, n = h/2 - t_skin/2 = 0.2 m
    # (no torque, so no shear at the corners); CS2 and CS3 carry M = P * 7 m and P * 3 m. The
    # deflected frames see part of P as axial force, P sin(phi)/A ~ 400 Pa (phi ~ 3e-3 rad):
    # the geometric nonlinearity stays below 500 Pa.
    for station, arm in ((0, 10.0), (1, 7.0), (2, 3.0)):
        assert data["max_von_mises"][station] == pytest.approx(P * arm * 0.2 / I_BOX, abs=500.0)
    assert data["max_von_mises"][3] < 1e3  # free tip: no bending moment, P sin(phi) / A only
    assert data["mass_kg"] == pytest.approx(2700 * 10 * (2 * 3 * 0.1 + A_WEB), rel=1e-12)
    assert "time" not in data and "check_totals_max_rel_error" not in data


def test_run_wing_box_gravity_stdout(capsys):
    assert main(["run", "wing-box", "--geometry", "combined", "--gravity", "--json", "-"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["tip_displacement"][2] < 0  # sags under self weight
    assert np.all(np.diff(data["displacement"]) > 0)
    assert data["max_von_mises"][0] > data["max_von_mises"][1] > data["max_von_mises"][2] > 0


def test_run_wing_box_dynamic_suddenly_applied_load(tmp_path):
    """Dynamic amplification of a suddenly applied tip load, undamped.

    Modally, u_tip(t) = sum_k u_k (1 - cos w_k t) with every u_k = phi_k(L)^2 / (m_k w_k^2) > 0
    and sum_k u_k the static deflection, so the peak ratio is at most 2; at t = pi / w1 (the first
    peak, ~0.09 s here) it is at least 2 u_1 / u_static - (small), and the first mode carries
    97 % of a cantilever's static tip deflection (Euler-Bernoulli: 0.9707), so >= 1.94. BDF2 at
    ~95 steps per half period damps it by < 1e-4. Measured 1.961."""
    data = _run(tmp_path, "--geometry", "prismatic", "--tip-load", "0", "0", str(P), "--dynamic",
                "--t-final", "0.2", "--dt", "0.002")
    t = np.asarray(data["time"])
    hist = np.asarray(data["tip_displacement_history"])
    assert t[0] == 0.0 and t.size == 101 and hist.shape == (101, 3)
    assert np.allclose(hist[0], 0.0, atol=1e-12)  # at rest in the jig at t = 0
    ratio = hist[:, 2].max() / _static_tip_deflection()
    assert 1.93 < ratio <= 2.0 + 5e-3, ratio   # + the beam's 0.5 % difference from the closed form
    assert data["tip_displacement"] == pytest.approx(hist[-1].tolist())
    # the peak root stress over time is amplified too; higher modes add more to the root moment
    # than to the tip deflection (each mode peaks at twice its static share, not all at once),
    # so the bound is looser: 2.24 measured
    assert 1.6 < data["max_von_mises"][0] / (P * 10.0 * 0.2 / I_BOX) < 3.0


def test_run_wing_box_check_totals(tmp_path):
    data = _run(tmp_path, "--geometry", "combined", "--tip-load", "1e4", "0", str(P),
                "--tip-moment", "0", "5e4", "0", "--elements", "1", "1", "1", "--dynamic",
                "--t-final", "0.04", "--dt", "0.01", "--check-totals")
    assert set(data["ks"]) == {"vm", "ss_tension", "ss_compression", "cent_pos", "cent_neg"}
    assert data["check_totals_max_rel_error"] < 1e-5


def test_run_wing_box_bad_input(capsys):
    assert main(["run", "wing-box", "--geometry", "sweep", "--t-skin", "-0.1"]) == 2
    err = capsys.readouterr().err
    assert "--t-skin" in err and "allowed range" in err
    assert main(["run", "wing-box", "--geometry", "taper", "--t-spar", "0.8"]) == 2
    assert "(0, 0.75) m" in capsys.readouterr().err
    assert main(["run", "wing-box", "--geometry", "prismatic", "--dynamic", "--t-final", "0.1",
                 "--dt", "0.2"]) == 2
    assert "--dt" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["run", "wing-box", "--geometry", "delta"])


def test_run_wing_box_solid_model(tmp_path):
    """``--model solid``: the 3-D solid's cut averages in the beam run's JSON keys."""
    from wingmdao.verification.wingbox_solid import solve_wingbox

    data = _run(tmp_path, "--geometry", "taper", "--model", "solid", "--tip-load", "0", "0", str(P),
                "--tip-moment", "0", str(P), "0", "--mesh-size", "0.5", "--span-size", "1.0")
    ref = solve_wingbox("taper", (0, 0, P), (0, P, 0), 0.5, span_size=1.0)
    assert data["model"] == "solid" and data["stations"] == ["CS1", "CS2", "CS3", "CS4"]
    assert data["displacement"][0] == 0.0
    np.testing.assert_allclose(data["station_displacement"][1:], ref["displacement"], rtol=1e-12)
    np.testing.assert_allclose(data["tip_rotation"], ref["rotation"][-1], rtol=1e-12)
    assert len(data["max_von_mises"]) == len(data["mean_von_mises"]) == 4
    assert all(m >= a > 0 for m, a in zip(data["max_von_mises"], data["mean_von_mises"]))
    # the clamp carries the tip load: R = -F, M = -(M_tip + r_tip x F)
    np.testing.assert_allclose(data["root_reaction_force"], [0, 0, -P], atol=1e-6 * P)
    assert data["mesh"]["num_dof"] > 0


def test_run_wing_box_solid_rejects_beam_only_options(capsys):
    assert main(["run", "wing-box", "--geometry", "prismatic", "--model", "solid", "--dynamic"]) == 2
    assert "--dynamic" in capsys.readouterr().err
    assert main(["run", "wing-box", "--geometry", "prismatic", "--model", "solid", "--mesh-size", "0"]) == 2
    assert "--mesh-size" in capsys.readouterr().err


@pytest.mark.parametrize("geometry", ["taper", "sweep", "dihedral"])
def test_run_wing_box_geometries_and_wall_thicknesses(tmp_path, geometry):
    """Non-default walls (spars 0.15 m, skins 0.06 m) on the tapered, swept and dihedral boxes
    against the independent linear Timoshenko frame of wingmdao.verification (its own stiffness
    assembly, beam-normal cut, web shear area): CS2..CS4 displacements within 0.5 % (measured
    0.02-0.17 %; the default walls would be 2-3x stiffer)."""
    from wingmdao.verification.wingbox_solid import linear_beam_solution

    force, moment = (2e4, 0.0, P), (0.0, 3e4, 0.0)
    data = _run(tmp_path, "--geometry", geometry, "--t-spar", "0.15", "--t-skin", "0.06",
                "--tip-load", *map(str, force), "--tip-moment", *map(str, moment))
    lin = linear_beam_solution(geometry, force, moment, shear="webs", section="normal",
                               t_spar=0.15, t_skin=0.06)
    np.testing.assert_allclose(data["displacement"][1:], np.linalg.norm(lin["displacement"], axis=1),
                               rtol=5e-3)
    np.testing.assert_allclose(data["tip_displacement"], lin["displacement"][-1],
                               atol=5e-3 * np.linalg.norm(lin["displacement"][-1]))
