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

    import wingmdao.report as report

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
