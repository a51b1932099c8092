"""``wingmdao run wing-box`` command."""

import json

import numpy as np
import pytest

from wingmdao.cli import main


def test_run_wing_box_prismatic(tmp_path, capsys):
    out = tmp_path / "r.json"
    assert main(["run", "wing-box", "--geometry", "prismatic", "--tip-load", "0", "0", "1e5",
                 "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert data["stations"] == ["CS1", "CS2", "CS3", "CS4"]
    assert len(data["displacement"]) == 4 and data["displacement"][0] == pytest.approx(0.0, abs=1e-15)
    # hand value: P L^3/(3 E I) + P L/(G A_web), I = 0.0254 m^4, A_web = 0.12 m^2
    expected = 1e5 * 1000 / (3 * 70e9 * 0.0254) + 1e5 * 10 / (70e9 / 2.66 * 0.12)
    assert data["tip_displacement"][2] == pytest.approx(expected, rel=5e-3)
    assert data["displacement"][3] == pytest.approx(np.linalg.norm(data["tip_displacement"]))
    assert len(data["tip_rotation"]) == 3 and data["tip_rotation"][0] > 0


def test_run_wing_box_gravity_stdout(capsys):
    assert main(["run", "wing-box", "--geometry", "combined", "--gravity", "--json", "-"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["tip_displacement"][2] < 0  # sags under self weight
    assert np.all(np.diff(data["displacement"]) > 0)


def test_run_wing_box_bad_input(capsys):
    assert main(["run", "wing-box", "--geometry", "sweep", "--t-skin", "-0.1"]) == 2
    err = capsys.readouterr().err
    assert "--t-skin" in err and "allowed range" in err
    with pytest.raises(SystemExit):
        main(["run", "wing-box", "--geometry", "delta"])
