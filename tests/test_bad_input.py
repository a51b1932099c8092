"""Bad input (issue 11): each fails before any solve with one line naming the input, its value and
the allowed range (exit code 2), never a traceback or a silent replacement."""

import os
import subprocess
import sys

import pytest

from wingmdao.cli import main

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@pytest.mark.parametrize("argv, message", [
    (["pegasus", "--loads", "gust", "--u-ref-fps", "-5"], "--u-ref-fps = -5.0 ft/s; allowed range [0, inf)"),
    (["pegasus", "--loads", "gust", "--u-ref-fps", "nan"], "--u-ref-fps = nan"),
    (["pegasus", "--maxiter", "0"], "--maxiter = 0; allowed range >= 1"),
    (["pegasus", "--loads", "gust", "--gust-start", "10"], "--gust-start = 10.0 s; allowed range [0, --t-final = 5.0)"),
    (["pegasus", "--loads", "gust", "--t-final", "inf"], "need finite"),
    (["pegasus", "--loads", "gust", "--t-final", "1e7", "--dt", "0.01"], "time steps (~"),
    (["pegasus", "--load-history", "x.npz"], "does not apply to --loads maneuver"),
    (["pegasus", "--load-factor", "nan"], "--load-factor = nan; allowed range (0, inf)"),
])
def test_size_options_fail_before_any_solve(argv, message, capsys, tmp_path):
    assert main(["size", *argv, "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not list(tmp_path.iterdir())  # nothing written


def test_n2_takes_no_json(capsys, tmp_path):
    with pytest.raises(SystemExit):
        main(["n2", "pegasus", "--out", str(tmp_path), "--json", "-"])
    assert "unrecognized arguments: --json" in capsys.readouterr().err


@pytest.mark.parametrize("content", [b"hello", b"", None])
def test_report_on_a_file_that_is_not_a_recording(tmp_path, capsys, content):
    path = tmp_path / "x.sql"
    if content is None:
        path.mkdir()
    else:
        path.write_bytes(content)
    assert main(["report", str(path)]) == 2
    err = capsys.readouterr().err
    assert "x.sql" in err and ("not an OpenMDAO recording" in err or "folder" in err)


def test_report_into_a_closed_pipe_is_quiet(tmp_path):
    assert main(["size", "cantilever", "--stations", "5", "--quiet", "--no-plots", "--out", str(tmp_path)]) == 0
    env = dict(os.environ, PYTHONPATH=ROOT)
    proc = subprocess.Popen([sys.executable, "-m", "wingmdao", "report", str(tmp_path / "cantilever.sql"),
                             "--plots", str(tmp_path / "plots")],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
    proc.stdout.close()  # like `| head` that has already exited
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 0
    assert "Traceback" not in err and "BrokenPipe" not in err


_MAT = "materials:\n  m: {type: isotropic, E: 7e10, nu: 0.3, rho: 2700}\n"
_WALLS = ("walls: {upper: %s, lower: {thickness: 0.01, material: m}, front: {thickness: 0.01, material: m}, "
          "rear: {thickness: 0.01, material: m}}")


@pytest.mark.parametrize("name, text, message", [
    ("empty.yaml", "", "empty file"),
    ("list.yaml", "[1, 2]", "must be a mapping"),
    ("bad.yaml", "a: [", "malformed YAML"),
    ("bad.json", "{", "malformed JSON"),
    ("nokey.yaml", _MAT + "section: {shape: rectangle, width: 1}\n", "missing key 'height'"),
    ("n0.yaml", _MAT + "section: {shape: rectangle, width: 1, height: 0.5, material: m, n: 0}\n",
     "section n (elements per side) = 0; allowed range [1, 2000]"),
    ("ms.yaml", _MAT + "section: {shape: rectangle, width: 1, height: 0.5, material: m, mesh_size: 0}\n",
     "mesh_size (m) = 0; allowed range"),
    ("nan.yaml", _MAT + "section: {shape: box, width: 1, height: 0.5, " + _WALLS % "{layup: [[m, 0.01, .nan]]}" + "}\n",
     "wall upper ply 0 angle (deg) = nan"),
    ("two.yaml", _MAT + "section: {shape: box, width: 1, height: 0.5, " + _WALLS % "{layup: [[m, 0.01]]}" + "}\n",
     "each ply is [material, thickness (m), angle (deg)]"),
    ("coord.yaml", _MAT + "section: {shape: airfoil, coordinates: nofile.dat, chord: 1, front_spar: 0.2, "
     "rear_spar: 0.7}\n", "file 'nofile.dat' does not exist"),
    ("huge.yaml", _MAT + "section: {shape: rectangle, width: 1.0e+30, height: 1.0e-30, material: m}\n",
     "allowed range [1e-06, 10000.0]"),
    ("strip.yaml", _MAT + "section: {shape: rectangle, width: 1, height: 1.0e-5, material: m}\n",
     "aspect ratio 1e+05 > 1000"),
])
def test_section_fe_files(tmp_path, capsys, name, text, message):
    pytest.importorskip("yaml")
    path = tmp_path / name
    path.write_text(text)
    assert main(["section-fe", str(path)]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_section_fe_missing_file(capsys):
    assert main(["section-fe", "no_such_section.yaml"]) == 2
    assert "no_such_section.yaml: no such file" in capsys.readouterr().err


def test_section_fe_file_with_byte_order_mark(tmp_path, capsys):
    path = tmp_path / "bom.json"
    path.write_bytes(b"\xef\xbb\xbf" + b'{"materials": {"m": {"type": "isotropic", "E": 7e10, "nu": 0.3, "rho": 2700}},'
                     b' "section": {"shape": "rectangle", "width": 1, "height": 0.5, "material": "m", "n": 4}}')
    assert main(["section-fe", str(path)]) == 0


def _history():
    import numpy as np

    from wingmdao.loads.files import LoadHistory

    return LoadHistory(np.arange(3) * 0.1, np.ones((3, 4, 3)), np.zeros((3, 4, 3)))


@pytest.mark.parametrize("name, make, message", [
    ("empty.npz", lambda p, full: p.write_bytes(b""), "not a readable .npz archive"),
    ("cut.npz", lambda p, full: p.write_bytes(full[: len(full) // 2]), "not a readable .npz archive"),
    ("missing.npz", lambda p, full: None, "no such file"),
    ("missing.csv", lambda p, full: None, "no such file"),
    ("garbage.csv", lambda p, full: p.write_bytes(b"\x00\xff\xfegarbage\x89"), "not a UTF-8 text CSV"),
])
def test_bad_load_history_files_name_the_file(tmp_path, name, make, message):
    from wingmdao.loads.files import read_load_history, write_load_history

    full_path = tmp_path / "full.npz"
    write_load_history(_history(), full_path)
    path = tmp_path / name
    make(path, full_path.read_bytes())
    with pytest.raises(ValueError, match=message) as info:
        read_load_history(path)
    assert name in str(info.value)


def test_csv_load_history_with_byte_order_mark_is_read(tmp_path):
    import numpy as np

    from wingmdao.loads.files import read_load_history, write_load_history

    path = tmp_path / "h.csv"
    write_load_history(_history(), path)
    path.write_bytes(b"\xef\xbb\xbf" + path.read_bytes())
    np.testing.assert_array_equal(read_load_history(path).force_per_length, _history().force_per_length)


def _fail_below_root_area(monkeypatch, limit):
    """Make every analysis whose root cross-section area is below ``limit`` (m^2) fail with an
    om.AnalysisError, as a beam Newton solve that does not converge would."""
    import openmdao.api as om

    from wingmdao.components.mass import StructuralMass

    compute = StructuralMass.compute

    def failing(self, inputs, outputs):
        if float(inputs["A"][0]) < limit:
            raise om.AnalysisError(f"no convergence (test: root area {float(inputs['A'][0]):.3g} m^2)")
        return compute(self, inputs, outputs)

    monkeypatch.setattr(StructuralMass, "compute", failing)


@pytest.mark.slow
def test_sizing_backs_off_from_failed_analyses_and_converges(tmp_path, capsys, monkeypatch):
    """Cantilever from the tapered guess b: SLSQP steps into designs whose analysis fails (root area
    < 0.2 m^2); the run backs off, records them, and reaches the optimum of the unconstrained run
    (3959.40 kg, root area 0.2 x 1.076 = 0.215 m^2, outside the failing region)."""
    import json

    _fail_below_root_area(monkeypatch, 0.2)
    out = tmp_path / "c.json"
    rc = main(["size", "cantilever", "--guess", "b", "--no-plots", "--out", str(tmp_path), "--json", str(out)])
    res = json.loads(out.read_text())
    err = capsys.readouterr()
    assert rc == 0 and res["success"] is True and "Traceback" not in err.err + err.out
    assert res["failed_evaluations"] and all("no convergence" in f["message"] for f in res["failed_evaluations"])
    assert "(backing off)" in err.out  # the progress line of a failed evaluation
    assert res["mass_kg"] == pytest.approx(3959.40, rel=1e-4)


def _fail_when_root_area_moves(monkeypatch):
    """Make every analysis fail (om.AnalysisError) whose root cross-section area differs from the
    first analysed design's: every step, however shortened, fails."""
    import openmdao.api as om

    from wingmdao.components.mass import StructuralMass

    compute, first = StructuralMass.compute, []

    def failing(self, inputs, outputs):
        a = float(inputs["A"][0])
        first.append(a) if not first else None
        if abs(a - first[0]) > 1e-12 * abs(first[0]):
            raise om.AnalysisError(f"no convergence (test: root area {a:.6g} m^2)")
        return compute(self, inputs, outputs)

    monkeypatch.setattr(StructuralMass, "compute", failing)


@pytest.mark.slow
def test_sizing_that_keeps_failing_stops_cleanly(tmp_path, capsys, monkeypatch):
    """Every step away from the starting design fails, however shortened: exit code 1 after 10
    consecutive failed analyses, the reason in the summary and in the JSON (success false), no
    traceback, and only JSON on standard output with --json -. (The region of failure does not
    depend on the optimizer's path, which changes with its scaling.)"""
    import json

    _fail_when_root_area_moves(monkeypatch)
    rc = main(["size", "cantilever", "--guess", "a", "--no-plots", "--quiet", "--out", str(tmp_path),
               "--json", "-"])
    cap = capsys.readouterr()
    res = json.loads(cap.out)
    assert rc == 1 and res["success"] is False and "Traceback" not in cap.err
    assert "10 consecutive failed analyses" in res["message"] and "no convergence" in res["message"]
    assert len(res["failed_evaluations"]) >= 10
    assert "message: stopped after 10 consecutive" in cap.err


@pytest.mark.parametrize("argv", [
    ["size", "cantilever", "--load", "step", "--t-final", "1e9", "--dt", "1e-3"],
    ["size", "cantilever", "--load", "step", "--t-final", "inf"],
    ["run", "wing-box", "--geometry", "prismatic", "--dynamic", "--t-final", "1e7", "--dt", "0.01"],
])
def test_huge_or_infinite_time_grids_are_refused_before_allocating(argv, capsys, tmp_path):
    if argv[0] == "size":
        argv = [*argv, "--out", str(tmp_path)]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert ("time steps (~" in err and "at most 100000 steps" in err) or "finite" in err


def test_gust_options_with_maneuver_loads_are_reported():
    from wingmdao.cases import build_case

    notes = build_case("pegasus", loads="maneuver", mach=0.6, kussner=True).notes
    assert any("ignored with --loads maneuver" in n and "--mach 0.6" in n and "--kussner" in n for n in notes)
    assert not any("ignored" in n for n in build_case("pegasus", loads="maneuver").notes)
