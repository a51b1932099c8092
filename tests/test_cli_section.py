"""``wingmdao section`` command line."""

import json
import re
import shutil
import subprocess
import sys

import pytest

from wingmdao.cli import main

BOX = ["section", "--width", "1.0", "--height", "0.5", "--t-upper", "0.01", "--t-lower", "0.01",
       "--t-front", "0.01", "--t-rear", "0.01"]
KEYS = ("A", "Ixx", "Izz", "Ixz", "J", "EA", "GJ", "EIxx", "EIzz", "c_ea", "n_ea", "mass_per_length",
        "c_sc", "n_sc", "Qx", "Qz", "stiffness_csn", "compliance_csn", "inertia_per_length")


def test_box_to_file(tmp_path):
    out = tmp_path / "box.json"
    assert main(BOX + ["--json", str(out)]) == 0
    data = json.loads(out.read_text())
    for k in KEYS:
        assert k in data, k
    assert data["A"] == pytest.approx(0.5 - 0.98 * 0.48, rel=1e-12)  # hollow rectangle by hand
    assert data["Ixx"] == pytest.approx((0.5**3 - 0.98 * 0.48**3) / 12, rel=1e-12)
    assert data["mass_per_length"] == pytest.approx(2700 * 0.0296, rel=1e-12)
    assert data["material"] == "aluminium"


def test_solid_to_stdout(capsys):
    assert main(["section", "--solid", "--width", "0.2", "--height", "0.4", "--material", "Steel-4130",
                 "--json", "-"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["section"] == "solid" and data["material"] == "steel-4130"
    assert data["Ixx"] == pytest.approx(0.2 * 0.4**3 / 12, rel=1e-12)
    assert data["J"] == pytest.approx(0.229 * 0.4 * 0.2**3, rel=3e-3)  # beta(2) = 0.229
    assert data["EA"] == pytest.approx(205e9 * 0.08, rel=1e-12)


@pytest.mark.parametrize("argv,match", [
    (BOX[:-2], "needs --t-rear"),
    (["section", "--solid", "--width", "1", "--height", "1", "--t-upper", "0.1"], "--solid takes only"),
    (BOX[:9] + ["--t-front", "0.6", "--t-rear", "0.5"], r"--t-front = 0.6 m.*allowed range \(0, 0.5\) m"),
    (BOX + ["--material", "wood"], "unknown material 'wood'.*valid: aluminium"),
    (["section", "--solid", "--width", "nan", "--height", "1"], r"width = nan m; allowed range \[1e-06, 1000\] m"),
])
def test_bad_input_clean_error(argv, match, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("wingmdao section: error:") and len(err.strip().splitlines()) == 1
    assert re.search(match, err), err


def test_console_script_subprocess():
    exe = shutil.which("wingmdao")
    cmd = [exe] if exe else [sys.executable, "-m", "wingmdao"]
    res = subprocess.run(cmd + BOX, capture_output=True, text=True, timeout=60, check=False)
    assert res.returncode == 0, res.stderr
    data = json.loads(res.stdout)
    assert data["J"] == pytest.approx(4 * 0.4851**2 / 296.0, rel=1e-12)  # Bredt by hand
    assert "--t-upper M" in subprocess.run(cmd + ["section", "--help"], capture_output=True, text=True,
                                           timeout=60).stdout
