"""``wingmdao maneuver CASE --checked-pitch`` (wingmdao/cli/maneuver.py; docs/maneuvers.md): bad input
named before any model is built, and the PEGASUS nose-up run's JSON (peak load factor at the
25.337 limit within 1 %)."""

import json

import numpy as np
import pytest

from wingmdao.cli import main

AIRCRAFT = ["--pitch-inertia", "345000", "--cg-x", "0.67", "--tail-arm", "12", "--tail-area", "11.7",
            "--tail-lift-slope", "4"]


@pytest.mark.parametrize("argv, message", [
    (["--checked-pitch", "--maneuvering-speed-eas", "90", *AIRCRAFT[:-2]],
     "--checked-pitch needs --tail-lift-slope (the case has no published tail or pitch inertia)"),
    (["--checked-pitch", *AIRCRAFT], "--checked-pitch needs --maneuvering-speed-eas"),
    (["--checked-pitch", "--maneuvering-speed-eas", "0", *AIRCRAFT],
     "--maneuvering-speed-eas = 0.0 m/s; allowed range (0, inf) m/s"),
    (["--checked-pitch", "--maneuvering-speed-eas", "-5", *AIRCRAFT],
     "--maneuvering-speed-eas = -5.0 m/s; allowed range (0, inf) m/s"),
    (["--checked-pitch", "--maneuvering-speed-eas", "200", *AIRCRAFT],
     "--maneuvering-speed-eas = 200.0 m/s; allowed range (0, V = 103.6"),
    (["--maneuvering-speed-eas", "90", *AIRCRAFT], "wingmdao maneuver needs a maneuver: --checked-pitch"),
    (["--checked-pitch", "--maneuvering-speed-eas", "90", "--elevator-chord-ratio", "1.5", *AIRCRAFT],
     "--elevator-chord-ratio = 1.5; allowed range (0, 1)"),
    (["--checked-pitch", "--maneuvering-speed-eas", "90", "--elevator-time-constant", "0", *AIRCRAFT],
     "--elevator-time-constant = 0.0 s; allowed range (0, inf) s"),
    (["--checked-pitch", "--maneuvering-speed-eas", "90", "--load-factor", "0.8", *AIRCRAFT],
     "--load-factor = 0.8; allowed range (1, inf)"),
])
def test_bad_input_one_line_before_any_solve(argv, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["maneuver", "pegasus", *argv, "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err


@pytest.mark.slow
def test_pegasus_nose_up_json(tmp_path):
    """The PEGASUS nose-up checked maneuver (illustrative tail and inertia of docs/aeroelasticity.md):
    the JSON keys, the peak load factor at the 25.337 limit (2.5705 at 41005 lb) within 1 %, the
    command delta_1 sin(omega t) over [0, 3 pi / (2 omega)] and omega >= pi V / (2 V_A)."""
    out = tmp_path / "r.json"
    assert main(["maneuver", "pegasus", "--checked-pitch", "--maneuvering-speed-eas", "90", *AIRCRAFT, "--steps",
                 "100", "--json", str(out), "--out", str(tmp_path)]) == 0
    r = json.loads(out.read_text())
    for k in ("time", "elevator_deg", "load_factor", "target_load_factor", "peak_load_factor", "pitch_rate_deg_s",
              "root_bending_moment", "omega_rad_s", "delta_1_deg"):
        assert k in r, k
    assert r["target_load_factor"] == pytest.approx(2.5705, abs=1e-4)
    assert abs(r["peak_load_factor"] / r["target_load_factor"] - 1) < 0.01
    t = np.asarray(r["time"])
    assert t[-1] == pytest.approx(1.5 * np.pi / r["omega_rad_s"], rel=1e-12)
    np.testing.assert_allclose(r["elevator_command_deg"], -r["delta_1_deg"] * np.sin(r["omega_rad_s"] * t),
                               atol=1e-12)
    assert r["omega_rad_s"] >= np.pi * r["airspeed_eas_m_s"] / (2 * 90.0)
    assert (tmp_path / "pegasus_checked_pitch.png").exists()
