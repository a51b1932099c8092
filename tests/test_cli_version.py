"""``wingmdao --version`` prints the package version, the one pyproject.toml declares."""

import re
import subprocess
import sys
from pathlib import Path

import wingmdao
from wingmdao.cli import main

ROOT = Path(__file__).resolve().parents[1]


def test_version_flag(capsys):
    try:
        main(["--version"])
    except SystemExit as exc:
        assert exc.code == 0
    assert capsys.readouterr().out.strip() == f"wingmdao {wingmdao.__version__}"


def test_version_matches_pyproject():
    declared = re.search(r'^version = "([^"]+)"', (ROOT / "pyproject.toml").read_text(), re.M).group(1)
    assert wingmdao.__version__ == declared


def test_version_from_the_module_entry_point():
    proc = subprocess.run([sys.executable, "-m", "wingmdao", "--version"], capture_output=True, text=True,
                          cwd=ROOT, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == f"wingmdao {wingmdao.__version__}"
