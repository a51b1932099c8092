"""Sphinx configuration of the wingmdao manual.

Build: ``python -m sphinx -W -b html docs OUT`` (``tests/test_docs_build.py`` runs exactly this,
warnings are errors). The pages are the Markdown files of ``docs/`` (MyST); the API reference is
generated from the package's docstrings (autosummary + autodoc, numpydoc sections) into
``docs/api/generated/`` at every build (not committed).
"""

import fnmatch
import importlib.util
import os
import re
import shutil
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, ROOT)   # document the checkout being built, not another installed copy

import wingmdao  # noqa: E402

project = "wingmdao"
author = "wingmdao contributors"
copyright = "wingmdao contributors, Apache-2.0"
release = wingmdao.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "numpydoc",     # the reference renderer of the numpydoc format the package writes
    "sphinx.ext.mathjax",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "examples"]
templates_path = ["_templates"]
html_theme = "alabaster"

# MyST: $...$ and $$...$$ maths, ```{directive} fences, anchors for the headings of every page
# (cross-references such as [time-marching.md](time-marching.md#the-adjoint)).
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 4

# API reference
autosummary_generate = True
autodoc_default_options = {"members": True, "show-inheritance": True, "ignore-module-all": True}
autodoc_member_order = "bysource"
# The optional frameworks (extras ``mdo``, ``mpi``, ``ipopt``, ``plot``, ``mesh``) are stood in for
# by autodoc's mock modules when they are not installed, so the ``docs`` extra alone builds the
# manual; installed ones are imported as usual.
OPTIONAL = ("mphys", "openaerostruct", "mpi4py", "cyipopt", "matplotlib", "yaml", "meshio", "h5py", "panelaero")
autodoc_mock_imports = [name for name in OPTIONAL if importlib.util.find_spec(name) is None]
# numpydoc lists class members in its own autosummary tables; autodoc's ``members`` already
# documents them, and the tables would link every inherited OpenMDAO method.
numpydoc_show_class_members = False


def theory_pages_not_listed(index_text, pages):
    """The pages of ``docs/`` that no toctree entry of ``index.md`` names (entries may be glob
    patterns), in name order: the Theory section takes them, so a page added to ``docs/`` is in
    the manual (and the ``-W`` build passes) without touching the index. Name a page in another
    section's toctree to move it there."""
    entries = re.findall(r"^([\w./*?-]+)[ \t]*$", index_text, re.M)
    return sorted(p for p in pages if p != "index" and not any(fnmatch.fnmatch(p, e) for e in entries))


def index_with_unlisted_pages(index_text, pages):
    """``index.md`` with :func:`theory_pages_not_listed` appended to its Theory toctree."""
    extra = theory_pages_not_listed(index_text, pages)
    if not extra:
        return index_text
    return re.sub(r"(:caption: Theory\n.*?)(\n```)", lambda m: m.group(1) + "\n" + "\n".join(extra) + m.group(2),
                  index_text, count=1, flags=re.S)


def _append_unlisted_pages_to_theory(app, docname, source):
    if docname == "index":
        pages = [name[:-3] for name in os.listdir(app.srcdir) if name.endswith(".md")]
        source[0] = index_with_unlisted_pages(source[0], pages)


def _clear_generated_api_pages(app):
    """autosummary writes one page per module into ``api/generated`` at every build; clearing it
    first (before autosummary, hence the priority) keeps a renamed or removed module from leaving
    a stale page whose import fails."""
    shutil.rmtree(os.path.join(app.srcdir, "api", "generated"), ignore_errors=True)


def _reread_index_when_pages_change(app, env, added, changed, removed):
    """An incremental build re-reads the index when pages come or go (its Theory list depends on them)."""
    return ["index"] if added or removed else []


_LITERAL = re.compile(r"(``.*?``|`[^`]*`)")
_MAGNITUDE = re.compile(r"\|[^\s|`][^|`]*\|[^\s`),.;:]*")


def literal_magnitudes(line):
    """``line`` with every bare ``|x|`` (a magnitude or norm, outside backquotes) turned into an
    inline literal. Docstrings are written to be read as plain text, where ``|lambda|`` is a
    modulus; reStructuredText would read it as a substitution reference and fail the ``-W`` build.
    Line blocks (``| text``) and table rules are left alone."""
    if line.lstrip().startswith(("| ", "+-", "+=")):
        return line
    parts = _LITERAL.split(line)
    for i in range(0, len(parts), 2):
        parts[i] = _MAGNITUDE.sub(lambda m: "``" + m.group(0) + "``", parts[i])
    return "".join(parts)


def _docstring_magnitudes(app, what, name, obj, options, lines):
    lines[:] = [literal_magnitudes(line) for line in lines]


def setup(app):
    app.connect("builder-inited", _clear_generated_api_pages, priority=100)
    app.connect("source-read", _append_unlisted_pages_to_theory)
    app.connect("env-get-outdated", _reread_index_when_pages_change)
    app.connect("autodoc-process-docstring", _docstring_magnitudes)
