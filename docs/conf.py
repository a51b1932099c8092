"""Sphinx configuration of the wingmdao manual.

Build: ``python -m sphinx -W -b html docs OUT`` (``tests/test_docs_build.py`` runs exactly this,
warnings are errors). The pages are the Markdown files of ``docs/`` (MyST); the API reference is
generated from the package's docstrings (autosummary + autodoc, numpydoc sections) into
``docs/api/generated/`` at every build (not committed).
"""

import os
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
    "numpydoc",
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
# numpydoc lists class members in its own autosummary tables; autodoc's ``members`` already
# documents them, and the tables would link every inherited OpenMDAO method.
numpydoc_show_class_members = False
