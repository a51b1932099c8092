"""Sizing cases shipped with wingmdao (cantilever, wing-box, PEGASUS, CRM).

Each case module defines

* ``NAME`` and ``HELP``;
* ``add_arguments(parser)``: its command-line options (units in the option names/help);
* ``build(args) -> CaseSetup``: the beam geometry, load cases, material and sizing options,
  validating the options *before* any solve.

The ``run_problem`` scripts in the repository's ``cases/`` folder call the same builders.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field

CASE_MODULES = {
    "cantilever": "wingmdao.cases.cantilever",
    "wing-box": "wingmdao.cases.wing_box",
    "pegasus": "wingmdao.cases.pegasus",
    "crm": "wingmdao.cases.crm",
}


@dataclass
class CaseSetup:
    geometry: object  # wingmdao.sizing.WingGeometry
    load_cases: list
    material: object  # wingmdao.materials.Material
    options: object  # wingmdao.sizing.SizingOptions
    section: str = "box"  # "box" or "solid"
    notes: list = field(default_factory=list)


def available_cases() -> dict:
    """{name: module} of the cases whose modules import."""
    out = {}
    for name, mod in CASE_MODULES.items():
        try:
            out[name] = importlib.import_module(mod)
        except ModuleNotFoundError as exc:
            if exc.name != mod:
                raise
    return out


def case_arguments(module, **overrides):
    """The case's command-line defaults as a namespace, with ``overrides`` (for scripts)."""
    import argparse

    parser = argparse.ArgumentParser()
    module.add_arguments(parser)
    args = parser.parse_args([])
    for key, value in overrides.items():
        if not hasattr(args, key):
            raise ValueError(f"{module.NAME} has no option {key!r}")
        setattr(args, key, value)
    return args
