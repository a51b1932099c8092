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


AILERONS = "docs/examples/pegasus_ailerons.yaml"
ROLL = ["--rolling", "--maneuvering-speed-eas", "90", "--roll-inertia", "20000"]


@pytest.mark.parametrize("argv, message", [
    ([*ROLL, "--alleviation", AILERONS, "--checked-pitch"], "--rolling with --checked-pitch: one maneuver per run"),
    (ROLL, "--rolling needs --alleviation FILE.yaml naming the ailerons"),
    ([*ROLL[:-2], "--alleviation", AILERONS], "--rolling needs --roll-inertia"),
    ([*ROLL[:-1], "0", "--alleviation", AILERONS], "--roll-inertia = 0.0 kg*m**2; allowed range (0, inf) kg*m**2"),
    ([*ROLL[:-1], "-5", "--alleviation", AILERONS], "--roll-inertia = -5.0 kg*m**2; allowed range (0, inf)"),
    ([*ROLL, "--alleviation", "ALLEVIATION"], "--rolling flies the ailerons open loop; remove 'law'"),
    ([*ROLL, "--alleviation", "NOSURFACES"], ": surfaces must be a non-empty list"),
    (["--checked-pitch", "--maneuvering-speed-eas", "90", "--roll-inertia", "2e4", *AIRCRAFT],
     "--roll-inertia is a --rolling flag"),
    ([*ROLL, "--alleviation", AILERONS, "--t-final", "0"], "--t-final = 0.0 s; allowed range (0, inf) s"),
    ([*ROLL, "--alleviation", AILERONS, "--aero-theory", "lifting-line"],
     "--aero-theory lifting-line: --rolling allows strip, vlm"),
    (["--checked-pitch", "--maneuvering-speed-eas", "90", "--aero-theory", "vlm", *AIRCRAFT],
     "--aero-theory is a --rolling flag"),
    ([*ROLL[:2], "200", *ROLL[3:], "--alleviation", AILERONS],
     "--maneuvering-speed-eas = 200.0 m/s; allowed range (0, V_C = 115.34] m/s EAS"),
])
def test_rolling_bad_input_one_line(argv, message, capsys, tmp_path, monkeypatch):
    """--rolling: bad flags and files named in one line before any model is built."""
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    (tmp_path / "ALLEVIATION").write_text((root / "docs/examples/pegasus_alleviation.yaml").read_text())
    (tmp_path / "NOSURFACES").write_text("surfaces: []\n")
    argv = [str(root / a) if a == AILERONS else a for a in argv]
    monkeypatch.chdir(tmp_path)
    assert main(["maneuver", "pegasus", *argv, "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err


def test_pegasus_rolling_json(tmp_path):
    """PEGASUS rolling conditions (illustrative ailerons and fuselage inertia, docs/maneuvers.md): the
    JSON keys; V_C flies the V_A steady roll rate with less aileron, V_D a third of it; the roll angle is
    the time integral of the roll rate (trapezoid within 1 %); the combined loads are the symmetric loads
    plus and minus the largest antisymmetric increment."""
    from pathlib import Path

    out = tmp_path / "r.json"
    ail = str(Path(__file__).resolve().parents[1] / AILERONS)
    assert main(["maneuver", "pegasus", *ROLL, "--alleviation", ail, "--steps", "80", "--t-final", "1.6",
                 "--json", str(out), "--out", str(tmp_path)]) == 0
    r = json.loads(out.read_text())
    t = np.asarray(r["time"])
    c = r["conditions"]
    assert list(c) == ["VA", "VC", "VD"]
    assert c["VA"]["aileron_command_deg"]["aileron"] == 20.0
    assert c["VC"]["steady_roll_rate_deg_s"] == pytest.approx(c["VA"]["steady_roll_rate_deg_s"], rel=1e-5)
    assert c["VD"]["steady_roll_rate_deg_s"] == pytest.approx(c["VA"]["steady_roll_rate_deg_s"] / 3, rel=1e-5)
    assert 0 < c["VD"]["aileron_command_deg"]["aileron"] < c["VC"]["aileron_command_deg"]["aileron"] < 20.0
    for k, cond in c.items():
        rate, phi = np.asarray(cond["roll_rate_deg_s"]), np.asarray(cond["roll_angle_deg"])
        trap = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(t))])
        assert abs(phi[-1] - trap[-1]) < 0.01 * abs(trap[-1]), k
        assert cond["steady_pb_2V"] == pytest.approx(np.radians(cond["steady_roll_rate_deg_s"]) * 12.2204488
                                                     / cond["airspeed_tas_m_s"], rel=1e-6)
        comb = cond["combined"]["n=2/3 n_lim"]
        assert comb["load_factor"] == pytest.approx(2 * r["limit_load_factor"] / 3)
        peak = np.max(np.abs(cond["root_bending_moment"]))
        assert comb["root_bending_max"] - comb["symmetric_root_bending_moment"] == pytest.approx(peak)
        assert cond["combined"]["n=0"]["symmetric_root_bending_moment"] == pytest.approx(0.0, abs=1e-6)
    assert (tmp_path / "pegasus_rolling.png").exists()
