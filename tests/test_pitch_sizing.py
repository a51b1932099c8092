"""Free pitch in the sizing model: ``wingmdao size pegasus --aero coupled --plunge free --pitch free``
(CoupledAero(pitch=True) -> WingSizing with PitchBodyProperties): the case's load factor equals the
gust command's for the same aircraft, adjoint totals of the gust KS vs central FD, bad input."""

import json

import numpy as np
import pytest

from wingmdao.cases import pegasus
from wingmdao.cases.planform import G0, LB
from wingmdao.sizing import build_problem

AIRCRAFT = dict(pitch="free", pitch_inertia=345000.0, cg_x=0.67, tail_arm=12.0, tail_area=11.7, tail_lift_slope=4.0)
FLAGS = ["--pitch", "free", "--pitch-inertia", "345000", "--cg-x", "0.67", "--tail-arm", "12", "--tail-area", "11.7",
         "--tail-lift-slope", "4"]


def _pegasus_pitch_gust(t_final, dt, **kw):
    setup = pegasus.build(loads="gust", aero="coupled", plunge="free", t_final=t_final, dt=dt, gust_start=0.0,
                          **{**AIRCRAFT, **kw})
    setup.options.disp = False
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
    prob.run_model()
    return prob, setup


def test_pitch_case_bad_input():
    with pytest.raises(ValueError, match="--pitch free needs --aero coupled and --plunge free"):
        pegasus.build(loads="gust", aero="coupled", plunge="clamped", **AIRCRAFT)
    with pytest.raises(ValueError, match="--pitch free needs --tail-area"):
        pegasus.build(loads="gust", aero="coupled", plunge="free", **{**AIRCRAFT, "tail_area": None})
    with pytest.raises(ValueError, match="downwash_gradient = 1.5"):
        pegasus.build(loads="gust", aero="coupled", plunge="free", **AIRCRAFT, downwash_gradient=1.5)


@pytest.mark.slow
def test_pegasus_pitch_case_matches_gust_command_and_totals(tmp_path):
    """Same aircraft and gust through the sizing model and through ``wingmdao gust``: load factors
    (wing + tail lift) / W equal to 1e-6; adjoint totals of the gust KS w.r.t. thicknesses and the
    pitch inertia vs central FD (relative 1e-5)."""
    from wingmdao.aero.coupled import load_case_response
    from wingmdao.cli import main

    prob, setup = _pegasus_pitch_gust(0.3, 0.03, tail_lag=True)
    case = setup.load_cases[0]
    assert case.aero.pitch and case.aero.tail_lag
    r = load_case_response(prob, case, 20, pegasus.TOGW_LB * LB * G0)
    np.testing.assert_allclose(r["load_factor"][0], 1.0, rtol=1e-8)
    out = tmp_path / "g.json"
    assert main(["gust", "pegasus", "--aero", "coupled", "--plunge", "free", *FLAGS, "--tail-lag", "--t-final", "0.3",
                 "--dt", "0.03", "--gust-start", "0", "--no-plots", "--json", str(out)]) == 0
    g = json.loads(out.read_text())
    assert g["pitch"] and g["tail_lag"] and g["gradient_ft"] == pegasus.GUST["gradient_ft"]
    np.testing.assert_allclose(r["load_factor"], g["load_factor"], rtol=1e-6, atol=1e-9)
    data = prob.check_totals(of=["cases.gust.ks_vm"], wrt=["t_upper_skin", "t_front_spar", "cases.gust.aircraft_pitch_inertia"],
                             method="fd", form="central", step=1e-7, step_calc="rel_avg", out_stream=None)
    for key, d in data.items():
        J = d["J_rev"] if "J_rev" in d else d["J_fwd"]
        assert np.abs(d["J_fd"]).max() > 0, key
        err = np.abs(J - d["J_fd"]).max() / np.abs(d["J_fd"]).max()
        assert err < 1e-5, (key, err)


def test_default_downwash_follows_the_aero_theory(tmp_path):
    """deps/dalpha = 2 a_w / (pi AR) takes a_w of the chosen --aero-theory: with the vortex lattice
    the sizing case's downwash equals the one ``wingmdao gust --aero-theory vlm`` reports (a second
    implementation, through the gust response), and it is below strip theory's by the ratio of the
    wing slopes (the 3-D lift loss: PEGASUS a_w 5.5 against 7.2 /rad)."""
    from wingmdao.cli import main

    deps = {}
    for theory in ("strip", "vlm"):
        setup = pegasus.build(loads="gust", aero="coupled", plunge="free", aero_theory=theory, **AIRCRAFT)
        deps[theory] = setup.load_cases[0].aero.downwash_gradient
    assert 0.65 < deps["vlm"] / deps["strip"] < 0.85
    out = tmp_path / "g.json"
    assert main(["gust", "pegasus", "--aero", "coupled", "--plunge", "free", *FLAGS, "--aero-theory", "vlm",
                 "--t-final", "0.2", "--dt", "0.02", "--gust-start", "0", "--no-plots", "--json", str(out)]) == 0
    g = json.loads(out.read_text())
    np.testing.assert_allclose(g["downwash_gradient"], deps["vlm"], rtol=1e-10)
