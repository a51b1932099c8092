"""No result lost, no traceback, no silent wrong input (docs/cli.md): each test reproduces one
defect of the command line (it failed before the fix)."""

import errno
import json
import os

import pytest

from wingmdao.cli import main
from wingmdao.cli import _io

CANTILEVER = ["size", "cantilever", "--stations", "5", "--quiet"]
PEGASUS = ["size", "pegasus", "--analysis-only", "--quiet"]


def _err(capsys):
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return err


# --- no result lost ----------------------------------------------------------------------------

def test_ctrl_c_after_the_optimizer_keeps_its_result(tmp_path, monkeypatch, capsys):
    """Ctrl-C in the post-processing (flutter search, envelope, plots) used to lose the finished result."""
    import wingmdao.cli.size as size

    def interrupt(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(size, "_add_flutter_result", interrupt)
    out = tmp_path / "c.json"
    assert main([*CANTILEVER, "--out", str(tmp_path), "--no-plots", "--json", str(out)]) == 130
    res = json.loads(out.read_text())
    assert res["interrupted"] is True and res["success"] is True  # the optimizer had converged
    assert res["mass_kg"] > 0 and "best_design" in res and "interrupted while writing" in res["message"]
    from wingmdao.report import read_history

    assert read_history(res["recording"])["iterations"] >= 2


def test_sigint_after_optimization_complete_keeps_the_json(tmp_path):
    """A real SIGINT just after SLSQP prints "Optimization Complete": the command ends with a JSON
    (complete, exit 0, or marked interrupted, exit 130). (On the cantilever the signal lands before the
    post-processing; test_ctrl_c_after_the_optimizer_keeps_its_result reproduces the lost result.)"""
    import signal
    import subprocess
    import sys

    out = tmp_path / "c.json"
    env = {**os.environ, "PYTHONPATH": os.path.dirname(os.path.dirname(os.path.abspath(__file__)))}
    proc = subprocess.Popen([sys.executable, "-m", "wingmdao", *CANTILEVER, "--out", str(tmp_path), "--json",
                             str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    seen = ""
    for line in proc.stdout:
        seen += line
        if "Optimization Complete" in line:
            proc.send_signal(signal.SIGINT)
            break
    rest, err = proc.communicate(timeout=300)
    assert "Optimization Complete" in seen and "Traceback" not in err, err
    res = json.loads(out.read_text())
    assert res["mass_kg"] > 0
    assert proc.returncode == 0 or (proc.returncode == 130 and res["interrupted"] is True and "best_design" in res)


def test_potato_stations_checked_before_the_solve(tmp_path, monkeypatch, capsys):
    from wingmdao import sizing

    def no_solve(*a, **k):
        raise AssertionError("solved before checking --potato-stations")

    monkeypatch.setattr(sizing, "presize_and_size", no_solve)
    assert main([*PEGASUS, "--out", str(tmp_path), "--potato-stations", "100"]) == 2
    err = _err(capsys)
    assert "--potato-stations 100" in err and "[0, 19]" in err
    assert not list(tmp_path.iterdir())


@pytest.fixture
def fake_report(tmp_path, monkeypatch):
    """A recording (read_history stubbed) with an envelope of 20 stations; the plots written are listed."""
    import numpy as np

    import wingmdao.cli.report as report  # the names the command looks up

    rec = tmp_path / "pegasus.sql"
    rec.write_text("")
    np.savez(tmp_path / "pegasus_envelope.npz", span=np.linspace(0, 10, 20))
    written = []
    monkeypatch.setattr(report, "read_history", lambda path: {"iterations": 1})
    monkeypatch.setattr(report, "format_history", lambda hist: "")
    monkeypatch.setattr(report, "write_report_plots", lambda hist, sub: written.append(sub) or [])
    return rec, written


def test_report_potato_stations_checked_before_any_plot(fake_report, capsys):
    rec, written = fake_report
    assert main(["report", str(rec), "--potato-stations", "100"]) == 2
    err = _err(capsys)
    assert "--potato-stations 100" in err and "[0, 19]" in err
    assert written == [] and not os.path.exists(str(rec)[:-4] + "_plots")


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes to read-only folders")
def test_report_out_read_only(fake_report, tmp_path, capsys):
    rec, written = fake_report
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        assert main(["report", str(rec), "--out", str(ro / "plots")]) == 2
        assert "not writable" in _err(capsys) and written == []
    finally:
        ro.chmod(0o755)


def test_report_out_is_a_file(fake_report, tmp_path, capsys):
    rec, written = fake_report
    f = tmp_path / "file.png"
    f.write_text("x")
    assert main(["report", str(rec), "--out", str(f)]) == 2
    assert "is a file, not a folder" in _err(capsys) and written == []


@pytest.mark.parametrize("argv", [
    ["section", "--width", "3", "--height", "0.5", "--t-skin", "0.1", "--t-spar", "0.2"],
    ["section-fe", "--rectangle", "1", "0.5", "--material", "aluminium"],
    ["run", "wing-box", "--geometry", "prismatic", "--tip-load", "0", "0", "-1e5"],
    ["cache"],
], ids=lambda a: a[0])
def test_every_json_refuses_an_existing_file_without_overwrite(argv, tmp_path, capsys):
    out = tmp_path / "r.json"
    out.write_text("earlier\n")
    assert main([*argv, "--json", str(out)]) == 2
    assert "--overwrite" in _err(capsys) and out.read_text() == "earlier\n"
    assert main([*argv, "--json", str(tmp_path / "missing" / "r.json")]) == 2
    assert "does not exist" in _err(capsys)
    assert main([*argv, "--json", str(tmp_path)]) == 2
    assert "is a folder" in _err(capsys)
    if argv[0] != "cache":
        assert main([*argv, "--json", str(out), "--overwrite"]) == 0
        assert json.loads(out.read_text())


def test_analysis_only_rerun_does_not_replace_the_envelope_and_json_names_no_output(tmp_path, capsys):
    argv = [*PEGASUS, "--out", str(tmp_path), "--no-plots", "--json", str(tmp_path / "a.json")]
    assert main(argv) == 0
    npz = tmp_path / "pegasus_envelope.npz"
    before = npz.stat().st_mtime_ns
    capsys.readouterr()
    assert main([*PEGASUS, "--out", str(tmp_path), "--no-plots", "--json", str(tmp_path / "b.json")]) == 2
    assert "pegasus_envelope.npz" in _err(capsys) and npz.stat().st_mtime_ns == before
    assert main([*PEGASUS, "--out", str(tmp_path), "--json", str(tmp_path / "pegasus_potato.png"),
                 "--overwrite"]) == 2
    assert "same file as the output" in _err(capsys)
    assert main([*PEGASUS, "--out", str(tmp_path), "--json", str(npz), "--overwrite"]) == 2
    assert "same file as the output" in _err(capsys) and npz.stat().st_mtime_ns == before


def test_full_disk_says_where_the_result_is(tmp_path, monkeypatch, capsys):
    def full(*a, **k):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(_io, "write_text_atomic", full)
    out = tmp_path / "c.json"
    assert main([*CANTILEVER, "--out", str(tmp_path), "--no-plots", "--json", str(out)]) == 1
    err = _err(capsys)
    line = [x for x in err.splitlines() if x.startswith("wingmdao size: error:")]
    assert len(line) == 1 and "No space left on device" in line[0] and "standard error" in line[0]
    assert "cantilever.sql" in line[0]
    text = err[err.index("{"):err.rindex("}") + 1]
    assert json.loads(text)["mass_kg"] > 0  # the result itself is on standard error
    assert not out.exists()
    # the recording is one closed SQLite file: no write-ahead log or shared-memory file left beside it
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("cantilever.sql")) == ["cantilever.sql"]


# --- no traceback: one line naming the flag or file, the value and what is allowed, exit 2 ------

def _design(tmp_path, data, name="d.json"):
    path = tmp_path / name
    path.write_text(data if isinstance(data, str) else json.dumps(data))
    return str(path)


@pytest.mark.parametrize("data, match", [
    (None, "no such file"),
    ({"case": "pegasus", "thickness": {"upper_skin": [0.01] * 20}}, "not a box sizing result"),
    ({"case": "pegasus", "thickness": {w: "thin" for w in ("upper_skin", "lower_skin", "front_spar", "rear_spar")}},
     "has 0 stations"),
    ([1, 2], "a JSON list"),
    ("\"text\"", "a JSON str"),
    ({"case": "crm", "thickness": {w: [0.01] * 20 for w in ("upper_skin", "lower_skin", "front_spar", "rear_spar")}},
     "case 'crm'"),
])
def test_gust_design_bad_file(tmp_path, capsys, data, match):
    path = str(tmp_path / "missing.json") if data is None else _design(tmp_path, data)
    assert main(["gust", "pegasus", "--no-plots", "--design", path]) == 2
    err = _err(capsys)
    assert "--design" in err and match in err


@pytest.mark.parametrize("command", [["export", "pegasus", "--format", "calculix", "deck.inp"],
                                     ["verify", "pegasus", "--no-ribs"]], ids=lambda c: c[0])
@pytest.mark.parametrize("data", [[1, 2], "\"text\"", {"case": "pegasus", "thickness": [1]}])
def test_export_verify_pegasus_design_of_wrong_type(tmp_path, capsys, monkeypatch, command, data):
    monkeypatch.chdir(tmp_path)
    assert main([*command, "--design", _design(tmp_path, data)]) == 2
    err = _err(capsys)
    assert "--design" in err


@pytest.mark.parametrize("name, text, match", [
    ("g.json", "{\"gradients_ft\": [100,", "not valid JSON"),
    ("g.yaml", "gradients_ft: [100, 200\nflight_points: [", "not a valid YAML"),
    ("g.yaml", "gradients_ft:\n\t- 100\n", "not tabs"),
    ("g.yaml", "gradients_ft: !!python/object:os.system [ls]\n", "not a valid YAML"),
    ("g.yaml", "gradients_ft: [100]\nflight_points: 5\n", "flight_points = 5"),
    ("g.yaml", "gradients_ft: [100]\nname_prefix: null\n"
               "flight_points: [{altitude_ft: 20000, mach: 0.5}]\n", "name_prefix = None"),
    ("g.json", "{\"gradients_ft\": [100], \"flight_points\": [{\"altitude_ft\": NaN, \"mach\": 0.5}]}",
     "NaN is not standard JSON"),
    ("folder.yaml", None, "is a folder"),
])
def test_gust_set_bad_files(tmp_path, capsys, name, text, match):
    pytest.importorskip("yaml")
    path = tmp_path / name
    if text is None:
        path.mkdir()
    else:
        path.write_text(text)
    assert main(["size", "pegasus", "--analysis-only", "--out", str(tmp_path / "o"), "--gust-set", str(path)]) == 2
    err = _err(capsys)
    assert err.count("\n") == 1 and "--gust-set" in err and match in err, err


def test_gust_t_final_step_cap(capsys):
    assert main(["gust", "pegasus", "--no-plots", "--t-final", "1e6"]) == 2
    err = _err(capsys)
    assert "time steps" in err and "at most 100000" in err


def test_cache_prune_meets_a_folder_named_like_a_library(tmp_path, monkeypatch, capsys):
    from wingmdao.utils import casadi_cache as cc

    monkeypatch.setenv(cc.ENV_CACHE, str(tmp_path))
    (tmp_path / "odd.so").mkdir()
    (tmp_path / "odd.so" / "keep.txt").write_text("x")
    rc = main(["cache", "--prune", "--unused-days", "0", "--json", str(tmp_path / "c.json")])
    _err(capsys)
    assert rc == 0 and (tmp_path / "odd.so" / "keep.txt").exists()


@pytest.mark.parametrize("flags", [["--width", "1e300"], ["--width", "1e-300"], ["--t-skin", "nan"],
                                   ["--solid", "--width", "1e300"]])
def test_section_dimensions_out_of_range(flags, capsys):
    base = {"--width": "3", "--height": "0.5", "--t-skin": "0.1", "--t-spar": "0.2"}
    if "--solid" in flags:
        base = {"--width": "3", "--height": "0.5"}
    argv = ["section"]
    for k, v in base.items():
        argv += [k, flags[flags.index(k) + 1] if k in flags else v]
    argv += [f for f in flags if f == "--solid"]
    assert main(argv) == 2
    err = _err(capsys)
    assert "allowed range [1e-06, 1000] m" in err and "NaN" not in capsys.readouterr().out


# --- no silent wrong input -----------------------------------------------------------------------

@pytest.mark.parametrize("flags, match", [
    (["--gust-start", "nan"], "--gust-start = nan"), (["--gust-start", "-5"], "--gust-start = -5"),
    (["--gust-start", "1e9"], "--gust-start = 1000000000"), (["--gust-start", "inf"], "--gust-start = inf"),
    (["--u-ref-fps", "inf"], "--u-ref-fps = inf"), (["--stiffness-scale", "1e300"], "--stiffness-scale = 1e+300"),
])
def test_gust_inputs_checked_up_front(flags, match, capsys):
    assert main(["gust", "pegasus", "--no-plots", *flags]) == 2
    err = _err(capsys)
    assert match in err and "allowed range" in err


def test_flutter_modes_capped_with_a_warning(capsys):
    assert main(["flutter", "goland", "--speeds", "100", "200", "3", "--num-nodes", "3", "--modes", "500",
                 "--no-plots", "--json", "-"]) == 0
    err = _err(capsys)
    assert "wingmdao: warning: --modes 500: the goland model has" in err and "tracking" in err
    assert "None" not in err  # a speed not found in the sweep is said in words


def _stop_before_build(monkeypatch):
    from wingmdao import sizing

    def stop(*a, **k):
        raise ValueError("stopped before the model (test)")

    monkeypatch.setattr(sizing, "build_problem", stop)


@pytest.mark.parametrize("flags, warning", [
    (["--loads", "maneuver", "--gust-gradient-count", "3"],
     "wingmdao: warning: ignored with --loads maneuver (gust options): --gust-gradient-count 3"),
    (["--loads", "maneuver", "--tail-lag", "--gust-start", "0.5"],
     "wingmdao: warning: ignored with --loads maneuver (gust options): --gust-start 0.5, --tail-lag"),
    (["--loads", "gust", "--gust-sign", "down"], "wingmdao: warning: ignored without a gust set"),
    (["--gust-sign", "down"], "wingmdao: warning: ignored with --loads maneuver (the default without a gust set; gust "
                              "options): --gust-sign down"),
    (["--mach", "0.7"], "wingmdao: warning: ignored with --loads maneuver (the default without a gust set; gust "
                        "options): --mach 0.7"),
])
def test_ignored_flags_warn(flags, warning, tmp_path, monkeypatch, capsys):
    _stop_before_build(monkeypatch)
    assert main(["size", "pegasus", "--analysis-only", "--out", str(tmp_path), *flags]) == 2
    err = _err(capsys)
    assert warning in err and "None" not in err


def test_size_potato_stations_ignored_with_one_load_case(tmp_path, monkeypatch, capsys):
    _stop_before_build(monkeypatch)
    assert main([*CANTILEVER, "--out", str(tmp_path), "--potato-stations", "1"]) == 2
    assert "wingmdao: warning: --potato-stations ignored" in _err(capsys)


@pytest.mark.parametrize("argv, match", [
    (["size", "pegasus", "--pitch", "free", "--aero", "coupled", "--plunge", "free", "--pitch-inertia", "1e5",
      "--cg-x", "nan", "--tail-arm", "10", "--tail-area", "10", "--tail-lift-slope", "4"], "--cg-x = nan m"),
    (["size", "pegasus", "--flutter-margin", "0.5"], "--flutter-margin = 0.5; allowed range [1, 2]"),
    (["size", "pegasus", "--presize", "100"], "--presize = 100; allowed range [0, 20] passes"),
    (["run", "wing-box", "--geometry", "prismatic", "--elements", "1000", "1", "1"], "sum <= 600 (1003 nodes: ~"),
    (["run", "wing-box", "--geometry", "prismatic", "--load-steps", "100000"], "allowed range [1, 1000]"),
    (["flutter", "goland", "--speeds", "100", "200", "1000000", "--no-plots"], "[2, 1000]"),
    (["flutter", "goland", "--num-nodes", "5000", "--no-plots"], "[3, 200]; 5000 nodes: an eigenproblem of"),
])
def test_inputs_refused_up_front(argv, match, tmp_path, monkeypatch, capsys):
    _stop_before_build(monkeypatch)
    if argv[0] == "size":
        argv = [*argv, "--analysis-only", "--out", str(tmp_path)]
    assert main(argv) == 2
    err = _err(capsys)
    assert match in err and "stopped before the model" not in err
