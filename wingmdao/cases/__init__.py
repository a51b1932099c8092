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
    flutter: dict | None = None  # FlutterDamping options (wingmdao.stability.cases.sizing_flutter_options)


#: Most time steps of one march: states, their adjoint, residual Jacobian blocks and stresses are
#: stored per step (beyond this a run needs tens of GB and days).
MAX_TIME_STEPS = 100_000


def check_step_count(t_final: float, dt: float, num_nodes: int = 20) -> int:
    """Number of time steps of ``0..t_final`` by ``dt``; ValueError before anything is allocated when
    the values are not finite or the count exceeds :data:`MAX_TIME_STEPS` (with a memory estimate:
    18 states per node, 8 bytes, ~6 stored copies per step)."""
    import numpy as np

    if not (np.isfinite(t_final) and np.isfinite(dt) and t_final > 0 and dt > 0):
        raise ValueError(f"--t-final = {t_final} s, --dt = {dt} s; both must be finite and > 0")
    steps = int(t_final / dt) + 1
    if steps > MAX_TIME_STEPS:
        gb = steps * num_nodes * 18 * 8 * 6 / 1e9
        raise ValueError(f"--t-final / --dt = {steps} time steps (~{gb:.1f} GB stored); at most "
                         f"{MAX_TIME_STEPS} steps")
    return steps


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
    """The case's command-line defaults as a namespace, with ``overrides`` (for scripts).

    Each override is checked like the command line would: an unknown name, a value the option's
    type cannot read (``load_factor="abc"``), or a value outside the option's choices is a
    ValueError naming the option; strings are converted (``"2.5"`` -> 2.5)."""
    import argparse

    parser = argparse.ArgumentParser()
    module.add_arguments(parser)
    args = parser.parse_args([])
    actions = {a.dest: a for a in parser._actions}
    for key, value in overrides.items():
        if not hasattr(args, key):
            raise ValueError(f"{module.NAME} has no option {key!r}; options: "
                             f"{', '.join(sorted(k for k in actions if k != 'help'))}")
        action = actions.get(key)
        if action is not None and action.type is not None and value is not None and not hasattr(value, "ndim"):
            many = isinstance(value, (list, tuple))
            items = list(value) if many else [value]
            if action.type is int and any(isinstance(v, float) and not float(v).is_integer() for v in items):
                raise ValueError(f"{module.NAME} option {key} = {value!r}: must be an integer")
            try:
                conv = [action.type(v) if isinstance(v, str) or action.type in (int, float) else v
                        for v in items]
            except (TypeError, ValueError):
                raise ValueError(f"{module.NAME} option {key} = {value!r}: not a valid "
                                 f"{getattr(action.type, '__name__', 'value')}") from None
            value = type(value)(conv) if many else conv[0]
        if (action is not None and action.choices is not None and not isinstance(value, (list, tuple))
                and value not in action.choices):
            raise ValueError(f"{module.NAME} option {key} = {value!r}; allowed: "
                             f"{', '.join(map(str, action.choices))}")
        setattr(args, key, value)
    return args


def build_case(name: str, **options) -> CaseSetup:
    """A shipped case built from keyword options (the command-line options with ``_`` for ``-``),
    e.g. ``build_case("pegasus", loads="all", load_factor=2.5)``; no parser needed."""
    cases = available_cases()
    if name not in cases:
        raise ValueError(f"unknown case {name!r}; available: {', '.join(cases)}")
    module = cases[name]
    return module.build(case_arguments(module, **options))
