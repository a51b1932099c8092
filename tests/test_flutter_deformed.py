"""Flutter about a deformed static state (wingmdao.stability.deformed) of the HALE wing.

Reference: the nonlinear-flutter curves of M. J. Patil, D. H. Hodges, C. E. S. Cesnik, "Nonlinear
aeroelasticity and flight dynamics of high-altitude long-endurance aircraft", J. Aircraft 38(1),
2001 (flutter speed, frequency and static tip displacement at flutter vs root angle of attack,
with gravity; flutter speed vs tip displacement set by a tip load), digitised from its figures
(``wingmdao.cases.hale.PUBLISHED_DEFORMED``). The static deflection under gravity alone is checked
against the cantilever closed form w L^4 / (8 EI).
"""

import numpy as np
import pytest

from wingmdao.cases import hale
from wingmdao.cli import main
from wingmdao.stability.cases import flutter_problem
from wingmdao.stability.deformed import check_root_aoa, deformed_flutter, deformed_params_at, tip_deflection
from wingmdao.stability.eigen import static_state


@pytest.mark.parametrize("bad, match", [([], "empty"), ([12.0], "within"), ([1.0, np.nan], "finite")])
def test_bad_root_aoa(bad, match):
    with pytest.raises(ValueError, match=match):
        check_root_aoa(bad)


@pytest.mark.parametrize("argv, match", [
    (["--root-aoa-deg", "2"], "need --deformed"),
    (["--deformed", "--root-aoa-deg", "15"], "within"),
    (["--deformed", "--gravity", "-1"], "--gravity = -1.0 m/s"),
])
def test_cli_deformed_bad_input_before_solve(argv, match, capsys, monkeypatch):
    import wingmdao.cli.flutter as fl

    monkeypatch.setattr(fl, "analyse", lambda *a, **k: pytest.fail("solve started"))
    assert main(["flutter", "hale", *argv]) == 2
    assert match in capsys.readouterr().err


def test_static_tip_deflection_under_gravity_closed_form():
    prob = flutter_problem("hale", 11)
    g = 0.05   # small: linear range
    p, q = deformed_params_at(prob, 0.0, g)(1.0)   # 1 m/s: no lift at zero angle of attack
    x = static_state(prob.system, p, q)
    ref = -hale.MASS * g * hale.SEMI_SPAN**4 / (8 * hale.EI_FLAP)
    assert tip_deflection(prob.system, x) == pytest.approx(ref, rel=0.01)


@pytest.mark.slow
def test_hale_flutter_falls_with_tip_deflection_as_published():
    pub = hale.PUBLISHED_DEFORMED
    angles = [1.0, 2.0, 3.0]
    prob = flutter_problem("hale", 11)
    rows = deformed_flutter(prob, angles, np.arange(18.0, 31.01, 0.5))
    V = np.array([r.flutter_speed for r in rows])
    w = np.array([r.flutter_frequency for r in rows])
    tip = np.array([r.tip_deflection for r in rows])
    V_ref = np.interp(angles, pub["speed_vs_root_aoa"]["root_aoa_deg"], pub["speed_vs_root_aoa"]["flutter_speed_m_s"])
    w_ref = np.interp(angles, pub["frequency_vs_root_aoa"]["root_aoa_deg"],
                      pub["frequency_vs_root_aoa"]["flutter_frequency_rad_s"])
    tip_ref = np.interp(angles, pub["tip_vs_root_aoa"]["root_aoa_deg"], pub["tip_vs_root_aoa"]["tip_deflection_m"])
    # the trend: the wing bends up more and flutters lower as the root angle grows
    assert np.all(np.diff(tip) > 0) and np.all(np.diff(V) < 0)
    # the magnitude: within 4 % (speed, frequency) and 10 % (tip deflection) of the published curves
    np.testing.assert_allclose(V, V_ref, rtol=0.04)
    np.testing.assert_allclose(w, w_ref, rtol=0.04)
    np.testing.assert_allclose(tip, tip_ref, rtol=0.10)
    # and the curve of flutter speed vs tip displacement (deflection set by a tip load)
    c = pub["speed_vs_tip_load_deflection"]
    np.testing.assert_allclose(V, np.interp(tip, c["tip_deflection_m"], c["flutter_speed_m_s"]), rtol=0.05)
    # a strong drop: from the undeformed 32.2 m/s to about two thirds at 1.6 m of tip deflection
    assert V[-1] / hale.PUBLISHED["flutter_speed_m_s"] == pytest.approx(V_ref[-1] / 32.15, rel=0.04)
