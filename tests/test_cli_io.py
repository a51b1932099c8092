"""Data safety and the CLI contract (issue 11): atomic result files, output paths checked before the
run, no silent overwrite, Ctrl-C keeps a partial result, missing matplotlib keeps the result,
``--json -`` writes only JSON to standard output, negative numbers in exponent notation."""

import json
import os
import sys

import pytest

from wingmdao.cli import build_parser, main
from wingmdao.cli import _io

CANTILEVER = ["size", "cantilever", "--stations", "5", "--quiet"]


def test_write_json_is_atomic_old_file_survives_a_failed_write(tmp_path, monkeypatch):
    path = tmp_path / "r.json"
    _io.write_json({"a": 1}, str(path))
    assert json.loads(path.read_text()) == {"a": 1}

    def boom(*a):
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", boom)
    with pytest.raises(_io.ResultWriteError, match="disk full"):  # the text goes to standard error
        _io.write_json({"a": 2}, str(path))
    assert json.loads(path.read_text()) == {"a": 1}  # the earlier result is intact
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.json"]  # no temporary file left


@pytest.mark.parametrize("make, match", [
    (lambda d: str(d / "missing" / "r.json"), "does not exist"),
    (lambda d: str(d), "is a folder"),
    (lambda d: (d / "old.json").write_text("{}") and str(d / "old.json"), "--overwrite"),
])
def test_output_file_checks(tmp_path, make, match):
    with pytest.raises(ValueError, match=match):
        _io.check_output_file(make(tmp_path), "--json")


def test_output_file_equal_to_recording(tmp_path):
    rec = str(tmp_path / "c.sql")
    with pytest.raises(ValueError, match="same file as the recording"):
        _io.check_output_file(rec, "--json", others={"recording": rec})


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes to read-only folders")
def test_read_only_folder_is_refused_before_the_run(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        with pytest.raises(ValueError, match="not writable"):
            _io.check_output_file(str(ro / "r.json"), "--json")
        with pytest.raises(ValueError, match="not writable"):
            _io.check_output_dir(str(ro / "sub"), "--out")
        assert main([*CANTILEVER, "--out", str(ro / "sub"), "--no-plots"]) == 2
    finally:
        ro.chmod(0o755)


def test_out_that_is_a_file_fails_at_once(tmp_path, capsys):
    f = tmp_path / "file"
    f.write_text("x")
    assert main([*CANTILEVER, "--out", str(f)]) == 2
    assert "is a file, not a folder" in capsys.readouterr().err


def test_json_equal_to_recording_fails_at_once(tmp_path, capsys):
    rc = main([*CANTILEVER, "--out", str(tmp_path), "--json", str(tmp_path / "cantilever.sql")])
    assert rc == 2 and "same file as the recording" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


def test_second_run_refuses_to_overwrite_without_flag(tmp_path, capsys):
    args = [*CANTILEVER, "--out", str(tmp_path), "--no-plots", "--json", str(tmp_path / "c.json")]
    assert main(args) == 0
    before = (tmp_path / "cantilever.sql").stat().st_mtime_ns
    capsys.readouterr()
    assert main(args) == 2
    assert "--overwrite" in capsys.readouterr().err
    assert (tmp_path / "cantilever.sql").stat().st_mtime_ns == before
    assert main([*args, "--overwrite"]) == 0


def test_load_sets_get_their_own_outputs():
    from wingmdao.cli.size import run_stem

    parser = build_parser()
    stems = {run_stem(parser.parse_args(["size", "pegasus", "--loads", x])) for x in ("all", "maneuver")}
    assert stems == {"pegasus_all", "pegasus_maneuver"}


def test_json_stdout_is_only_json(tmp_path, capsys):
    assert main([*CANTILEVER[:-1], "--out", str(tmp_path), "--no-plots", "--json", "-"]) == 0
    cap = capsys.readouterr()
    res = json.loads(cap.out)  # nothing but the JSON on standard output
    assert res["success"] and "eval" in cap.err and "mass" in cap.err


@pytest.mark.parametrize("argv", [
    ["section", "--width", "3", "--height", "0.5", "--t-upper", "0.1", "--t-lower", "0.1",
     "--t-front", "0.2", "--t-rear", "0.2", "--json", "-"],
    ["section-fe", "--rectangle", "1", "0.5", "--material", "7e10", "0.3", "2700", "--json", "-"],
    ["run", "wing-box", "--geometry", "prismatic", "--tip-load", "0", "0", "1e5", "--json", "-"],
])
def test_json_stdout_is_only_json_on_every_command(argv, capsys):
    assert main(argv) == 0
    json.loads(capsys.readouterr().out)


def test_ctrl_c_during_size_keeps_a_partial_result(tmp_path, monkeypatch, capsys):
    from wingmdao.optimize import ProgressPrinter

    calls = {"n": 0}
    original = ProgressPrinter.record_iteration_driver

    def interrupt_at_third(self, *a, **k):
        original(self, *a, **k)
        calls["n"] += 1
        if calls["n"] == 3:
            raise KeyboardInterrupt

    monkeypatch.setattr(ProgressPrinter, "record_iteration_driver", interrupt_at_third)
    out = tmp_path / "c.json"
    rc = main([*CANTILEVER[:-1], "--out", str(tmp_path), "--json", str(out)])
    assert rc == 130
    res = json.loads(out.read_text())
    assert res["success"] is False and res["interrupted"] is True
    assert res["mass_kg"] > 0 and len(res["width"]) == 5
    assert res["best_design"]["iteration"] >= 0
    from wingmdao.report import read_history

    assert read_history(res["recording"])["iterations"] >= 2  # the recording is closed and readable


def test_missing_matplotlib_keeps_the_result(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    out = tmp_path / "p.json"
    assert main(["size", "pegasus", "--analysis-only", "--out", str(tmp_path), "--json", str(out)]) == 0
    assert json.loads(out.read_text())["mass_kg"] > 0
    err = capsys.readouterr().err
    assert err.count("plots skipped") == 1


def test_negative_numbers_in_exponent_notation_are_values():
    args = build_parser().parse_args(["run", "wing-box", "--geometry", "prismatic", "--tip-load", "-1e6", "0", "1e7"])
    assert list(args.tip_load) == [-1e6, 0.0, 1e7]


def test_help_shows_defaults(capsys):
    with pytest.raises(SystemExit):
        main(["size", "pegasus", "--help"])
    out = capsys.readouterr().out
    assert "default:" in out.split("\n  --loads", 1)[1].split("\n  --", 1)[0]  # stated in words: maneuver, ...
    assert "(default: 2.5)" in out  # --load-factor


def test_material_means_the_same_on_section_and_section_fe(capsys):
    """--material NAME names a built-in material on both commands (section-fe also takes E NU RHO)."""
    from wingmdao.materials import get_material

    al = get_material("aluminium")
    assert main(["section-fe", "--rectangle", "0.1", "0.05", "--material", "aluminium", "--json", "-"]) == 0
    by_name = json.loads(capsys.readouterr().out)
    assert main(["section-fe", "--rectangle", "0.1", "0.05", "--material", str(al.E), str(al.nu), str(al.rho),
                 "--json", "-"]) == 0
    assert json.loads(capsys.readouterr().out)["stiffness_6x6"] == by_name["stiffness_6x6"]
    assert main(["section-fe", "--rectangle", "0.1", "0.05", "--material", "1", "2"]) == 2
    assert "built-in name or three numbers" in capsys.readouterr().err


def test_atomic_result_files_get_the_usual_mode_not_mkstemps_0600(tmp_path):
    """A result written atomically (temporary file + rename) is readable like any file the user
    writes: 0666 less the umask, not the 0600 of the temporary file."""
    import os
    import stat

    from wingmdao.cli._io import write_json

    old = os.umask(0o022)
    try:
        path = tmp_path / "r.json"
        write_json({"a": 1}, str(path))
        assert stat.S_IMODE(path.stat().st_mode) == 0o644
    finally:
        os.umask(old)
