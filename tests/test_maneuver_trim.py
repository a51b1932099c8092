"""Elevator trim of the static maneuvers (wingmdao.loads.maneuver_trim, docs/controls.md): against the
rigid aircraft's closed form of trim, two equations (lift, moment about the CG) in two unknowns
(angle of attack, elevator) with the stabiliser at its 1 g setting."""

from __future__ import annotations

import numpy as np
import pytest

from wingmdao.aero import aero_parameters, cached_aeroelastic_system
from wingmdao.aero.pitch import pitch_parameters
from wingmdao.beam.static import beam_parameters, straight_beam
from wingmdao.loads.maneuver_trim import elevator_trim
from wingmdao.timemarch.system import pack

G = 9.81


def _aircraft(stiff=1.0, n=5, span=8.0, c=1.0, ref=0.35, V=40.0, rho=1.0, mass=300.0, cg=(0.05, 0.0), tail_arm=4.0,
              tail_area=2.0, a_t=4.0, deps=0.3):
    r0, th0 = straight_beam(n, span)
    bp = beam_parameters(r0, th0, EI_cc=2e5 * stiff, GJ=1e5 * stiff, EI_nn=1e7 * stiff, EA=1e9, mass_per_length=5.0)
    ap = aero_parameters(n, chord=c, ref_point=ref, airspeed=V, density=rho)
    s = cached_aeroelastic_system(n, plunge=True, trim=True, pitch=True)
    par = {**bp, **ap, "trim_lift": mass * G}
    par.update(pitch_parameters(aircraft_mass=mass, cg=cg, aircraft_pitch_inertia=400.0, tail_arm=tail_arm,
                                tail_area=tail_area, tail_lift_slope=a_t, downwash_gradient=deps,
                                mass_per_length=bp["mass_per_length"], node_positions=r0))
    return s, pack(s.param_specs, par), dict(c=c, ref=ref, V=V, rho=rho, W=mass * G, cg=cg[0],
                                              x_t=cg[0] + tail_arm, S=2 * span * c, S_t=tail_area, a_t=a_t, deps=deps)


def _closed_form(n, tau, k):
    """Rigid aircraft: L_w + L_t = n W, (x_ac - x_cg) L_w + (x_t - x_cg) L_t = 0 (moments about the CG),
    L_w = q S 2 pi alpha (strips, the wing's aerodynamic centre at the quarter chord, x_ac = -(ref - 1/4) c),
    L_t = q S_t a_t (alpha (1 - deps) + i_t + tau delta), i_t from the 1 g trim at delta = 0."""
    q = 0.5 * k["rho"] * k["V"] ** 2
    x_ac = -(k["ref"] - 0.25) * k["c"]

    def trim(n_g):
        L_w = n_g * k["W"] * (k["x_t"] - k["cg"]) / (k["x_t"] - x_ac)
        L_t = n_g * k["W"] - L_w
        alpha = L_w / (q * k["S"] * 2 * np.pi)
        return alpha, L_t, L_t / (q * k["S_t"] * k["a_t"]) - alpha * (1 - k["deps"])  # (alpha, L_t, i_t + tau delta)

    a1, _, it1 = trim(1.0)
    an, ltn, itn = trim(n)
    return an, ltn, it1, (itn - it1) / tau


@pytest.mark.parametrize("n_load", [2.5, -1.0])
def test_elevator_trim_against_the_rigid_closed_form(n_load):
    """A stiff straight wing (stiffness x 1e4) with the tail 4 m aft of the CG: angle of attack, tail lift,
    1 g stabiliser setting and elevator within 1e-4 (relative; 1e-7 rad absolute) of the closed form;
    the flexible wing (stiffness x 1) differs from it (its elastic twist and bending change the wing lift
    distribution, the check can fail) by more than 1e-3 in the elevator."""
    tau = 0.66
    s, p, k = _aircraft(stiff=1e4)
    t = elevator_trim(s, p, n_load, elevator_effectiveness=tau, weight=k["W"], gravity=G)
    alpha, lift_t, it1, delta = _closed_form(n_load, tau, k)
    for got, want in ((t.alpha, alpha), (t.tail_lift, lift_t), (t.tail_incidence_1g, it1), (t.elevator, delta)):
        assert got == pytest.approx(want, rel=1e-4, abs=1e-7), (got, want)
    assert abs(delta) > np.radians(0.1)  # a real elevator angle
    assert t.wing_lift + t.tail_lift == pytest.approx(n_load * k["W"], rel=1e-12)
    s, p, k = _aircraft(stiff=1.0)
    flex = elevator_trim(s, p, n_load, elevator_effectiveness=tau, weight=k["W"], gravity=G)
    assert abs(flex.elevator - delta) > 1e-3 * abs(delta), (flex.elevator, delta)


def test_elevator_trim_refusals():
    s, p, k = _aircraft()
    for kw, text in (({"elevator_effectiveness": 0.0}, "elevator_effectiveness"),
                     ({"elevator_effectiveness": 0.6, "weight": -1.0}, "weight")):
        kw.setdefault("weight", k["W"])
        with pytest.raises(ValueError, match=text):
            elevator_trim(s, p, 2.5, **kw)
    with pytest.raises(ValueError, match="load_factor"):
        elevator_trim(s, p, 0.0, elevator_effectiveness=0.6, weight=k["W"])
    with pytest.raises(ValueError, match="free-pitch"):
        elevator_trim(cached_aeroelastic_system(5, plunge=True, trim=True), p, 2.5, elevator_effectiveness=0.6,
                      weight=k["W"])


PITCH = ["--aero", "coupled", "--aero-theory", "strip", "--plunge", "free", "--pitch", "free", "--pitch-inertia",
         "345000", "--cg-x", "0.67", "--tail-arm", "12", "--tail-area", "11.7", "--tail-lift-slope", "4"]


def test_size_elevator_chord_ratio_refused(capsys, tmp_path):
    from wingmdao.cli import main

    assert main(["size", "pegasus", "--analysis-only", "--no-plots", "--out", str(tmp_path), *PITCH,
                 "--elevator-chord-ratio", "1.2"]) == 2
    err = capsys.readouterr().err
    assert "--elevator-chord-ratio = 1.2; allowed range (0, 1)" in err, err


@pytest.mark.slow
def test_size_pegasus_maneuvers_trimmed_with_the_elevator(tmp_path, capsys):
    """`size pegasus --aero coupled --plunge free --pitch free ... --analysis-only` (maneuvers): each
    maneuver's elevator_trim in the result; wing + tail lift = n W; one 1 g stabiliser setting; trailing
    edge up at +2.5 g and down at -1 g (the elevator against the stiffened-wing closed form is
    test_elevator_trim_against_the_rigid_closed_form). No warning
    calls the pitch options ignored; the tail lift moves the root bending against the wing-alone trim."""
    import json

    from wingmdao.aero.pitch import elevator_effectiveness
    from wingmdao.cli import main

    out = tmp_path / "m.json"
    assert main(["size", "pegasus", "--analysis-only", "--no-plots", "--quiet", "--no-flutter-search",
                 "--out", str(tmp_path), "--json", str(out), *PITCH]) == 0
    err = capsys.readouterr().err
    assert "ignored" not in err, err
    r = json.loads(out.read_text())["load_case_response"]
    plain = tmp_path / "p.json"
    (tmp_path / "plain").mkdir()
    assert main(["size", "pegasus", "--analysis-only", "--no-plots", "--quiet", "--no-flutter-search",
                 "--out", str(tmp_path / "plain"), "--json", str(plain), *PITCH[:4]]) == 0
    p = json.loads(plain.read_text())["load_case_response"]
    from wingmdao.cases import pegasus

    W = pegasus.TOGW_LB * pegasus.LB * 9.80665
    for name, n_load in (("maneuver_pos", 2.5), ("maneuver_neg", -1.0)):
        t = r[name]["elevator_trim"]
        assert t["load_factor"] == pytest.approx(n_load, rel=1e-12)
        assert t["wing_lift_n"] + t["tail_lift_n"] == pytest.approx(n_load * W, rel=1e-12)
        assert "elevator_trim" not in p[name]
        # the tail's share of the lift changes the wing's: the root bending moves with it
        assert abs(r[name]["peak_root_bending_moment_n_m"] - p[name]["peak_root_bending_moment_n_m"]) > 1e3
    up, down = r["maneuver_pos"]["elevator_trim"], r["maneuver_neg"]["elevator_trim"]
    assert up["tail_incidence_1g_deg"] == pytest.approx(down["tail_incidence_1g_deg"], rel=1e-9)
    assert up["elevator_deg"] < 0 < down["elevator_deg"]  # trailing edge up to pull up
    assert elevator_effectiveness(0.3) == pytest.approx(0.661, abs=1e-3)
