"""``wingmdao verify panel``: the smeared panel model against CalculiX linear buckling
(docs/panels.md, "Model against CalculiX"). References are closed forms written out here
(Timoshenko & Gere, Theory of Elastic Stability, 2nd ed., Ch. 9); the solver tests are skipped
without ``ccx``, the input checks run without it."""

import json
import math
import shutil

import pytest

from wingmdao.cli import main

needs_ccx = pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX ccx not installed")

E, NU, T = 70e9, 0.33, 0.002                 # the built-in 'aluminium', 2 mm skin
D = E * T**3 / (12 * (1 - NU**2))            # plate bending stiffness (N m)
PLATE = ["--material", "aluminium", "--t-skin", "0.002", "--width", "0.15", "--length", "0.45"]
BLADES = ["--material", "aluminium", "--t-skin", "0.002", "--width", "0.15", "--length", "0.6",
          "--stiffener-height", "0.04", "--stiffener-thickness", "0.003"]
SMALL = ["--material", "aluminium", "--t-skin", "0.002", "--width", "0.15", "--length", "0.6",
         "--stiffener-height", "0.015", "--stiffener-thickness", "0.0015"]


def _run(argv, capsys):
    assert main(["verify", "panel", *argv, "--json", "-"]) == 0
    return json.loads(capsys.readouterr().out)


@needs_ccx
def test_unstiffened_plate_compression_k4(capsys, tmp_path):
    """150 x 450 mm plate (a/b = 3) in compression: N_cr = 4 pi^2 D / b^2 = 91.9 kN/m; model
    (exact k = 4) and CalculiX (-0.9 %) within 2 % of each other and of the closed form."""
    r = _run([*PLATE, "--nx", "-1000", "--keep-deck", str(tmp_path / "deck")], capsys)
    ref = 4 * math.pi**2 * D / 0.15**2 / 1000.0              # the factor on 1 kN/m
    assert r["model_buckling_factor"] == pytest.approx(ref, rel=1e-6)
    assert r["fe_buckling_factor"] == pytest.approx(ref, rel=0.02)
    assert r["model_buckling_factor"] == pytest.approx(r["fe_buckling_factor"], rel=0.02)
    assert r["difference_percent"] == pytest.approx(
        100 * (r["model_buckling_factor"] / r["fe_buckling_factor"] - 1), rel=1e-9)
    assert r["model_mode"] == "plate" and r["fe_mode"] == "plate"
    assert r["fe"]["panel_width_m"] == 0.15 and r["fe"]["n_stiffeners"] == 0
    assert (tmp_path / "deck" / "panel.inp").exists()
    assert r["critical_running_loads_n_per_m"]["skin_compression"] == pytest.approx(ref * 1000, rel=1e-6)


@needs_ccx
def test_unstiffened_plate_shear(capsys):
    """Same plate in shear: k_s = 5.35 + 4 (b/a)^2 (T&G Sec. 9.7, a 1-2 % fit): 132.8 kN/m; model
    and CalculiX (+0.6 %) within 3 %."""
    r = _run([*PLATE, "--nxy", "1000"], capsys)
    ref = (5.35 + 4 * (0.15 / 0.45) ** 2) * math.pi**2 * D / 0.15**2 / 1000.0
    assert r["model_buckling_factor"] == pytest.approx(ref, rel=0.01)
    assert r["fe_buckling_factor"] == pytest.approx(ref, rel=0.03)
    assert r["model_buckling_factor"] == pytest.approx(r["fe_buckling_factor"], rel=0.03)


@needs_ccx
def test_blade_panel_model_conservative_local(capsys):
    """3 blades 40 x 3 mm, pitch 0.15 m, a = 0.6 m, compression. The model's skin bay is simply
    supported (k = 4 at a/b = 4: sigma = 45.9 MPa, N_x = sigma t_eq, t_eq = t + h t_s / p); the
    FE's 3 mm webs restrain the 2 mm skin's rotation, CalculiX buckles at ~1.43 x that (model/FE
    0.70). Both local; the model conservative and within 45 %."""
    r = _run([*BLADES, "--nx", "-1000"], capsys)
    t_eq = T + 0.04 * 0.003 / 0.15
    ref = 4 * math.pi**2 * D / 0.15**2 * t_eq / T / 1000.0
    assert r["model_buckling_factor"] == pytest.approx(ref, rel=1e-6)
    ratio = r["model_buckling_factor"] / r["fe_buckling_factor"]
    print(f"blade panel: model {r['model_buckling_factor']:.1f}, FE {r['fe_buckling_factor']:.1f}, "
          f"model/FE {ratio:.3f}")
    assert 0.55 <= ratio <= 1.0
    assert ratio == pytest.approx(0.70, abs=0.03)
    assert r["model_mode"] == "local" and r["model_buckling_ratio"] == "skin_compression_shear"
    assert r["fe_mode"] == "local"
    assert r["fe"]["panel_width_m"] == pytest.approx(0.45) and r["fe"]["n_stiffeners"] == 3


@needs_ccx
def test_small_stiffeners_global(capsys):
    """3 blades 15 x 1.5 mm: both find the global mode. The model's wide column
    N = pi^2 D_x / a^2 (26.0 kN/m) ignores the support of the panel's side edges and is 27 %
    below CalculiX (35.5 kN/m); the smeared orthotropic plate a x W with the same D_x
    (N = pi^2/a^2 [D_x + 2 D (a/W)^2 + D (a/W)^4], m = 1) gives 35.7 kN/m, within 2 % of
    CalculiX: the whole difference is the side-edge support, not the smeared stiffness."""
    r = _run([*SMALL, "--nx", "-1000"], capsys)
    t, h, ts, p, a, W = T, 0.015, 0.0015, 0.15, 0.6, 0.45
    area = t + h * ts / p                                     # per width
    z_na = (h * ts / p) * (t / 2 + h / 2) / area              # from the skin mid-plane
    dx = E * (t**3 / 12 + t * z_na**2 + (ts * h**3 / 12 + h * ts * (t / 2 + h / 2 - z_na) ** 2) / p)
    column = math.pi**2 * dx / a**2 / 1000.0
    plate = math.pi**2 / a**2 * (dx + 2 * D * (a / W) ** 2 + D * (a / W) ** 4) / 1000.0
    assert r["model_buckling_factor"] == pytest.approx(column, rel=1e-6)
    assert r["model_buckling_factor_finite_width"] == pytest.approx(plate, rel=1e-6)
    assert r["model_mode"] == "global" and r["fe_mode"] == "global"
    ratio = r["model_buckling_factor"] / r["fe_buckling_factor"]
    assert 0.65 <= ratio <= 1.0 and ratio == pytest.approx(0.733, abs=0.03)
    assert r["model_buckling_factor_finite_width"] == pytest.approx(r["fe_buckling_factor"], rel=0.02)


@pytest.mark.parametrize("argv, flag", [
    (["--material", "stw-cfrp", "--ply-fractions", "0.4441", "0.222", "0.222", "0.1119", "--t-skin", "0.004",
      "--width", "0.15", "--length", "0.6", "--nx", "-1000"], "--material"),
    ([*PLATE], "--nx"),
    ([*PLATE, "--nx", "1000"], "--nx"),
    ([*BLADES, "--nx", "-1000", "--stiffeners", "0"], "--stiffeners"),
    ([*PLATE, "--nx", "-1000", "--stiffeners", "2"], "--stiffeners"),
    ([*PLATE, "--nx", "-1000", "--mesh-size", "0.5"], "--mesh-size"),
    ([*PLATE, "--nx", "-1000", "--mesh-size", "-1"], "--mesh-size"),
])
def test_bad_input_names_the_flag(argv, flag, capsys):
    assert main(["verify", "panel", *argv, "--json", "-"]) == 2
    cap = capsys.readouterr()
    assert cap.out == ""
    err = cap.err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("wingmdao verify: error:") and flag in err[0]


def test_missing_ccx_one_line(capsys, monkeypatch):
    monkeypatch.setenv("WINGMDAO_CCX", "/nonexistent/ccx")
    monkeypatch.setenv("PATH", "/nonexistent")
    assert main(["verify", "panel", *PLATE, "--nx", "-1000", "--json", "-"]) == 2
    cap = capsys.readouterr()
    err = cap.err.strip().splitlines()
    assert cap.out == "" and len(err) == 1 and "ccx" in err[0]


@needs_ccx
def test_tee_panel_global(capsys):
    """3 tees 20 x 2 mm (flange 20 x 2 mm, pitch 0.17 m), a = 0.6 m, 25 mm mesh: global in both;
    the wide column is conservative (-7 %), the finite-width smeared plate within 2 % of CalculiX."""
    r = _run(["--material", "aluminium", "--t-skin", "0.002", "--width", "0.15", "--length", "0.6",
              "--stiffener-height", "0.02", "--stiffener-thickness", "0.002", "--stiffener", "tee",
              "--nx", "-1000", "--mesh-size", "0.025"], capsys)
    assert r["fe"]["pitch_m"] == pytest.approx(0.17) and r["fe"]["flange_width_m"] == pytest.approx(0.02)
    assert r["model_mode"] == "global" and r["fe_mode"] == "global"
    assert 0.85 <= r["model_buckling_factor"] / r["fe_buckling_factor"] <= 1.0
    assert r["model_buckling_factor_finite_width"] == pytest.approx(r["fe_buckling_factor"], rel=0.02)
