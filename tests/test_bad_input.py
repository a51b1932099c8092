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
    (["pegasus", "--loads", "gust", "--t-final", "1e7", "--dt", "0.01"], "time steps; at most 100000"),
    (["pegasus", "--load-history", "x.npz"], "does not apply to --loads maneuver"),
    (["pegasus", "--load-factor", "nan"], "--load-factor must be > 0"),
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
