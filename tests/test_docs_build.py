"""The manual (docs/, Sphinx with MyST and autodoc) builds with warnings as errors, and lists every
public module, every environment switch and every page."""

import importlib.util
import pkgutil
import re
import subprocess
import sys
from pathlib import Path

import pytest

import wingmdao

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
#: not in the API reference: the command-line modules parse arguments and print (docs/cli.md)
NOT_IN_API = {"cli", "__main__"}


@pytest.mark.slow
def test_sphinx_build_without_warnings(tmp_path):
    if importlib.util.find_spec("sphinx") is None or importlib.util.find_spec("myst_parser") is None \
            or importlib.util.find_spec("numpydoc") is None:
        pytest.skip("sphinx, myst-parser or numpydoc is not installed (pip install -e '.[docs]')")
    proc = subprocess.run([sys.executable, "-m", "sphinx", "-W", "-q", "-b", "html", "docs", str(tmp_path / "html")],
                          cwd=ROOT, capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr[-4000:]
    assert (tmp_path / "html" / "index.html").is_file()
    assert (tmp_path / "html" / "api" / "generated" / "wingmdao.timemarch.bdf.html").is_file()


def test_api_reference_lists_every_public_module():
    listed = set(re.findall(r"^\s+(wingmdao\.\w+)\s*$", (DOCS / "api" / "index.md").read_text(), re.M))
    public = {f"wingmdao.{m.name}" for m in pkgutil.iter_modules(wingmdao.__path__)
              if not m.name.startswith("_") and m.name not in NOT_IN_API}
    assert public - listed == set(), "add these to docs/api/index.md"
    assert listed - public == set(), "no such modules"


def test_every_environment_switch_is_documented():
    names = set()
    for path in (ROOT / "wingmdao").rglob("*.py"):
        names |= set(re.findall(r"WINGMDAO_[A-Z][A-Z_]*", path.read_text()))
    table = (DOCS / "environment.md").read_text()
    assert names, "no WINGMDAO_ switch found: the scan is broken"
    assert {n for n in names if f"`{n}`" not in table} == set(), "add these to docs/environment.md"


def test_new_pages_join_the_theory_section():
    """A page added to docs/ without touching index.md lands under Theory (docs/conf.py), so the
    -W build does not fail on "document isn't included in any toctree"; pages the index places
    elsewhere stay there."""
    spec = importlib.util.spec_from_file_location("wingmdao_docs_conf", DOCS / "conf.py")
    conf = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(conf)
    index = (DOCS / "index.md").read_text()
    pages = ["index", "tutorial", "verification-calculix", "performance", "aerodynamics-3d", "turbulence"]
    assert conf.theory_pages_not_listed(index, pages) == ["aerodynamics-3d", "turbulence"]
    text = conf.index_with_unlisted_pages(index, pages)
    theory = text.split(":caption: Theory", 1)[1].split("```", 1)[0].split()
    verification = text.split(":caption: Verification", 1)[1].split("```", 1)[0].split()
    assert theory[-2:] == ["aerodynamics-3d", "turbulence"] and "section" in theory
    assert "verification-*" in verification and "tutorial" not in theory
