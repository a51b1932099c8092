"""``wingmdao gust pegasus --pitch free``: required pitch data, bad input, a short trimmed run."""

import json

import numpy as np
import pytest

from wingmdao.cli import main

PITCH = ["--aero", "coupled", "--plunge", "free", "--pitch", "free", "--pitch-inertia", "345000", "--cg-x", "0.67",
         "--tail-arm", "12", "--tail-area", "11.7", "--tail-lift-slope", "4"]


def test_pitch_needs_its_data_and_free_plunge(capsys):
    assert main(["gust", "pegasus", "--pitch", "free", "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert "--pitch free needs --pitch-inertia, --cg-x, --tail-arm, --tail-area, --tail-lift-slope" in err
    no_plunge = [a for a in PITCH if a not in ("--plunge", "free")] + ["--pitch", "free"]
    assert main(["gust", "pegasus", *no_plunge, "--clamped", "--no-plots"]) == 2
    assert "--pitch free needs --aero coupled and --plunge free" in capsys.readouterr().err
    assert main(["gust", "pegasus", "--tail-area", "5", "--no-plots"]) == 2
    assert "--tail-area applies to --pitch free only" in capsys.readouterr().err


@pytest.mark.parametrize("flag, value, name", [("--downwash-gradient", "1.0", "downwash_gradient"),
                                               ("--pitch-inertia", "-1", "aircraft_pitch_inertia"),
                                               ("--tail-arm", "-2", "tail_arm"), ("--tail-area", "0", "tail_area")])
def test_pitch_bad_values(capsys, flag, value, name):
    args = list(PITCH)
    if flag in args:
        args[args.index(flag) + 1] = value
    else:
        args += [flag, value]
    assert main(["gust", "pegasus", *args, "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert name in err and "allowed range" in err


@pytest.mark.slow
def test_pitch_free_short_run_keys_and_trim(tmp_path):
    """Trimmed 1 g start: wing + tail lift = W (load factor 1 at t = 0), pitch states zero; JSON keys."""
    out = tmp_path / "p.json"
    rc = main(["gust", "pegasus", *PITCH, "--tail-lag", "--t-final", "0.6", "--dt", "0.03", "--gust-start", "0.0",
               "--no-plots", "--json", str(out)])
    assert rc == 0
    res = json.loads(out.read_text())
    assert res["pitch"] is True and res["plunge"] is True and res["tail_lag"] is True
    np.testing.assert_allclose(res["load_factor"][0], 1.0, rtol=1e-9)
    assert abs(res["pitch_angle_rad"][0]) < 1e-12 and abs(res["pitch_rate_rad_s"][0]) < 1e-12
    assert len(res["tail_lift_n"]) == len(res["time"])
    # downwash default 2 a_w / (pi AR)
    ar = (80.58962 * 0.3048) ** 2 / (586.3328 * 0.3048 ** 2)
    np.testing.assert_allclose(res["downwash_gradient"], 2 * res["wing_lift_slope_per_rad"] / (np.pi * ar), rtol=1e-12)
    assert min(res["pitch_angle_rad"]) < -1e-4  # the upgust pitches the stable aircraft nose down
