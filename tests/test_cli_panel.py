"""``wingmdao panel`` command line."""

import json
import math
import re

import pytest

from wingmdao.cli import main

BASE = ["panel", "--t-skin", "0.004", "--width", "0.15", "--length", "0.6"]
LAM = ["--material", "stw-cfrp", "--ply-fractions", "0.4441", "0.222", "0.222", "0.1119"]
STIFF = ["--stiffener-height", "0.04", "--stiffener-thickness", "0.003"]
CRIT = ("skin_compression", "skin_shear", "panel_compression", "panel_shear", "stiffener_column",
        "stiffener_crippling")


def test_laminate_tee_json_stdout(capsys):
    assert main(BASE + LAM + STIFF + ["--stiffener", "tee", "--nx", "-5e5", "--nxy", "1e5", "--json", "-"]) == 0
    out = capsys.readouterr().out
    data = json.loads(out)  # only JSON on stdout
    assert set(data["material"]) >= {"E11_pa", "E22_pa", "G12_pa", "nu12", "ply_fractions"}
    assert set(data["D"]) == {"D11", "D22", "D12", "D66"}
    assert set(data["critical_running_loads_n_per_m"]) == set(CRIT)
    assert all(data["critical_running_loads_n_per_m"][k] > 0 for k in CRIT)
    ratios = data["failure_ratios"]
    assert set(ratios) == {*CRIT, "material", "skin_compression_shear", "panel_compression_shear"}
    assert data["critical_mode"] == max(ratios, key=ratios.get)


def test_metal_bare_skin_to_file(tmp_path):
    path = tmp_path / "p.json"
    assert main(BASE + ["--material", "aluminium", "--nx", "-1e4", "--json", str(path)]) == 0
    data = json.loads(path.read_text())
    assert data["material"]["E_pa"] == 70e9 and data["material"]["nu"] == 0.33
    d = 70e9 * 0.004**3 / (12 * (1 - 0.33**2))
    assert data["D"]["D11"] == pytest.approx(d, rel=1e-12)
    crit = data["critical_running_loads_n_per_m"]
    assert crit["skin_compression"] == pytest.approx(4 * math.pi**2 * d / 0.15**2, rel=1e-12)  # a/b = 4
    for k in ("panel_compression", "panel_shear", "stiffener_column", "stiffener_crippling"):
        assert crit[k] is None and data["failure_ratios"][k] is None
    assert data["failure_ratios"]["panel_compression_shear"] is None


@pytest.mark.parametrize("extra,match", [
    (["--material", "aluminium", "--t-skin", "0"], r"--t-skin = 0.0 m; allowed range \(0, inf\)"),
    (["--material", "aluminium", "--skin-thickness", "-0.1"], r"--t-skin = -0.1 m; allowed range \(0, inf\)"),
    (["--material", "aluminium", "--width", "nan"], r"--width = nan m; allowed range \(0, inf\)"),
    (["--material", "aluminium", "--length", "-1"], r"--length = -1.0 m; allowed range \(0, inf\)"),
    (["--material", "aluminium", "--stiffener-height", "0.04"], r"--stiffener-height needs --stiffener-thickness"),
    (["--material", "aluminium", "--stiffener-thickness", "0.003"], r"--stiffener-thickness needs --stiffener-height"),
    (["--material", "aluminium", *STIFF[:2], "--stiffener-thickness", "-0.003"],
     r"--stiffener-thickness = -0.003 m; allowed range"),
    (["--material", "aluminium", "--stiffener-height", "inf", "--stiffener-thickness", "0.003"],
     r"--stiffener-height = inf m; allowed range"),
    (["--material", "stw-cfrp"], r"needs --ply-fractions"),
    (["--material", "stw-cfrp", "--ply-fractions", "0.5", "0.5", "0.5", "-0.5"],
     r"--ply-fractions = 0.5 0.5 0.5 -0.5: -0.5 is outside the allowed range \[0, 1\]"),
    (["--material", "stw-cfrp", "--ply-fractions", "0.3", "0.3", "0.3", "0.3"],
     r"--ply-fractions = .*sum to 1.2; allowed sum 1"),
    (["--material", "stw-cfrp", "--ply-fractions", "0.5", "0.5"], r"--ply-fractions = 0.5 0.5: 2 values; expected 4"),
    (["--material", "al7075-t6", "--ply-fractions", "0.25", "0.25", "0.25", "0.25"],
     r"--ply-fractions = .* given for the metal 'al7075-t6'"),
    (["--material", "wood"], r"--material = 'wood': unknown; valid: metals aluminium"),
])
def test_bad_input_exit_2(extra, match, capsys):
    assert main(BASE + extra) == 2
    captured = capsys.readouterr()
    err = captured.err
    assert captured.out == ""
    assert err.startswith("wingmdao panel: error:") and len(err.strip().splitlines()) == 1, err
    assert re.search(match, err), err


def test_help_shows_defaults(capsys):
    with pytest.raises(SystemExit):
        main(["panel", "--help"])
    text = capsys.readouterr().out
    assert "(default: blade)" in text and "(default: -)" in text and "N/m" in text


def test_t_skin_required(capsys):
    assert main(["panel", "--material", "aluminium", "--width", "0.1", "--length", "0.5"]) == 2
    assert "--t-skin (skin thickness, m) is required" in capsys.readouterr().err
