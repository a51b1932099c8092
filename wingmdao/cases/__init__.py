"""Sizing cases shipped with wingmdao (cantilever, wing-box, PEGASUS, CRM, STW).

Each case module defines

* ``NAME`` and ``HELP``;
* ``OPTIONS``: its options dataclass (a :class:`CaseOptions`: fields, types and defaults);
* ``add_arguments(parser)``: its command-line options (units in the option names/help), whose
  defaults come from ``OPTIONS``;
* ``build(options=None, **keywords) -> CaseSetup``: the beam geometry, load cases, material and
  sizing options from an ``OPTIONS`` instance and/or keywords, validating them *before* any solve;
* optionally ``output_files(stem, setup)`` and ``write_outputs(prob, setup, stem, result)``: files
  of its own that ``wingmdao size`` writes beside the JSON after the run (checked, like the
  plots, before it; ``write_outputs`` may add keys to the result).

The command line converts its namespace once (:func:`options_from_namespace`); the scripts in
the repository's ``cases/`` folder call the same builders with keywords, without a parser.
"""

from __future__ import annotations

import dataclasses
import importlib
import numbers
import os
import types
import typing
from dataclasses import dataclass, field

import numpy as np

CASE_MODULES = {
    "cantilever": "wingmdao.cases.cantilever",
    "wing-box": "wingmdao.cases.wing_box",
    "pegasus": "wingmdao.cases.pegasus",
    "crm": "wingmdao.cases.crm",
    "stw": "wingmdao.cases.stw",
}


@dataclass
class CaseSetup:
    geometry: object  # wingmdao.sizing.WingGeometry
    load_cases: list
    material: object  # wingmdao.materials.Material
    options: object  # wingmdao.sizing.SizingOptions
    section: str = "box"  # "box", "stiffened" (with panels) or "solid"
    notes: list = field(default_factory=list)
    flutter: dict | None = None  # FlutterDamping options (wingmdao.stability.cases.sizing_flutter_options)
    panels: object = None  # wingmdao.panels.layout.PanelLayout with section "stiffened"
    turbulence: dict | None = None  # TurbulenceStressKS options (wingmdao.loads.turbulence_analysis.sizing_turbulence_options)


#: Most time steps of one march: states, their adjoint, residual Jacobian blocks and stresses are
#: stored per step (beyond this a run needs tens of GB and days).
MAX_TIME_STEPS = 100_000


def check_step_count(t_final: float, dt: float, num_nodes: int = 20) -> int:
    """Number of time steps of ``0..t_final`` by ``dt``; ValueError before anything is allocated when
    the values are not finite or the count exceeds :data:`MAX_TIME_STEPS` (with a memory estimate:
    18 states per node, 8 bytes, ~6 stored copies per step)."""
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


class CaseOptions:
    """Base of a case's options dataclass: every field is type-checked on construction.

    A subclass is a ``@dataclass(frozen=True)`` whose fields are the case's options (the
    command-line options with ``_`` for ``-``), annotated with their types (``float``, ``int``,
    ``str``, ``bool``, ``tuple[float, ...]``, ``... | None``); ``metadata={"choices": ...}`` on a
    field restricts its values. A wrong type (``load_factor="2.5"``) or a value outside the
    choices is a ValueError naming the case and the option; the value ranges are checked by the
    case's ``build``. ``CASE`` is the case name used in the messages.
    """

    CASE = "case"

    def __post_init__(self):
        hints = typing.get_type_hints(type(self))
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if isinstance(value, os.PathLike):  # a file option given as a pathlib.Path
                value = os.fspath(value)
                object.__setattr__(self, f.name, value)
            _check_option(self.CASE, f.name, value, hints[f.name], f.metadata.get("choices"))
            if isinstance(value, (list, np.ndarray)):
                object.__setattr__(self, f.name, tuple(value))  # the options stay immutable


def _type_parts(hint):
    """(base type, element type or None, optional) of an option annotation."""
    args = typing.get_args(hint)
    optional = False
    if typing.get_origin(hint) in (typing.Union, types.UnionType):
        optional = type(None) in args
        hint = next(a for a in args if a is not type(None))
        args = typing.get_args(hint)
    origin = typing.get_origin(hint) or hint
    return origin, (args[0] if origin is tuple and args else None), optional


def _is(value, kind) -> bool:
    if kind is float:
        return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))
    if kind is int:
        return isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_))
    if kind is bool:
        return isinstance(value, (bool, np.bool_))
    return isinstance(value, kind)


def _check_option(case, name, value, hint, choices) -> None:
    kind, item, optional = _type_parts(hint)
    what = {float: "a number", int: "an integer", bool: "True or False", str: "a string"}
    if value is None:
        if not optional:
            raise ValueError(f"{case} option {name} = None: must be {what.get(kind, kind.__name__)}")
        return
    if kind is tuple:
        ok = isinstance(value, (list, tuple, np.ndarray)) and all(_is(v, item) for v in value)
        if not ok:
            raise ValueError(f"{case} option {name} = {value!r}: must be a list of "
                             f"{what.get(item, item.__name__).split(' ', 1)[1]}s")
        return
    if not _is(value, kind):
        raise ValueError(f"{case} option {name} = {value!r} ({type(value).__name__}): must be "
                         f"{what.get(kind, kind.__name__)}")
    if choices is not None and value not in choices:
        raise ValueError(f"{case} option {name} = {value!r}; allowed: {', '.join(map(str, choices))}")


def case_options(cls, options=None, **overrides):
    """An instance of the options dataclass ``cls``: ``options`` (an instance, or None for the
    defaults) with ``overrides``; an unknown name or an object of another type is a ValueError."""
    names = [f.name for f in dataclasses.fields(cls)]
    unknown = [k for k in overrides if k not in names]
    if unknown:
        raise ValueError(f"{cls.CASE} has no option {unknown[0]!r}; options: {', '.join(sorted(names))}")
    if options is None:
        return cls(**overrides)
    if not isinstance(options, cls):
        raise ValueError(f"{cls.CASE} options must be a {cls.__name__} (or keyword options), got "
                         f"{type(options).__name__}")
    return dataclasses.replace(options, **overrides) if overrides else options


def options_from_namespace(cls, namespace):
    """The options dataclass ``cls`` from a parsed command line (the CLI's one conversion)."""
    return cls(**{f.name: _plain(getattr(namespace, f.name)) for f in dataclasses.fields(cls)
                  if hasattr(namespace, f.name)})


def _plain(value):
    return tuple(value) if isinstance(value, list) else value


#: the quasi-steady lift of the coupled loads (trim, maneuvers, gusts, turbulence) when --aero-theory
#: is unset: the vortex lattice of the planform (wingmdao.aero.vlm). The flutter constraint of sizing and
#: ``wingmdao flutter`` keep strip theory unless asked (the lattice with 2-D lags is not a flutter
#: model; docs/aerodynamics-3d.md).
DEFAULT_COUPLED_THEORY = "vlm"


def resolve_aero_theory(aero_theory, aero: str) -> str:
    """The aerodynamic theory of a run: ``aero_theory`` as given, or when unset (None) the default of
    ``aero`` (``--aero``): :data:`DEFAULT_COUPLED_THEORY` for ``"coupled"``, ``"strip"`` (the
    precomputed loads' 2 pi) for ``"strip"``.

    Parameters
    ----------
    aero_theory : str or None
        ``--aero-theory`` as given (``strip``, ``lifting-line``, ``vlm``, ``dlm``) or None.
    aero : str
        ``--aero``: ``"strip"`` or ``"coupled"``.

    Returns
    -------
    str
        The theory the run uses.
    """
    if aero_theory is not None:
        return aero_theory
    return DEFAULT_COUPLED_THEORY if aero == "coupled" else "strip"


def set_parser_defaults(parser, cls) -> None:
    """Take the defaults of a case's command-line options from its options dataclass (one table)."""
    parser.set_defaults(**{f.name: f.default for f in dataclasses.fields(cls)})


def case_beam_parameters(module, walls=None, *, source="walls"):
    """``(setup, beam_params)`` of a shipped case's wing for one design, without a model run: the
    case built (``module.build``; with its maneuvers only when it has a ``loads`` option) and the
    beam parameter dict of the sections the sizing model uses
    (:func:`wingmdao.sizing.design_beam_params`). ``walls``: ``{wall: (n,) m}`` per beam node (the
    ``thickness`` of a sizing result, e.g. :func:`wingmdao.cli._io.read_design`, keys ``upper_skin``,
    ``lower_skin``, ``front_spar``, ``rear_spar``), mapped to the design stations; None: the initial
    design. ValueError naming ``source`` (e.g. the command's ``--design FILE``) when a wall has not
    one value per node."""
    from wingmdao.sizing import SECTION_KINDS, WALL_VARS, design_beam_params, initial_design

    maneuvers = {"loads": "maneuver"} if "loads" in {f.name for f in dataclasses.fields(module.OPTIONS)} else {}
    setup = module.build(**maneuvers)  # the CRM case has its maneuvers only
    design = initial_design(setup.options, SECTION_KINDS[setup.section]["design_vars"])
    if walls is not None:
        smap, n = setup.geometry.station_map, setup.geometry.num_nodes
        for w in WALL_VARS:
            vals = np.asarray(walls[w[2:]], dtype=float).ravel()
            if vals.size != n:
                raise ValueError(f"{source}: thickness {w[2:]!r} has {vals.size} stations; the {n}-node beam of "
                                 f"case {module.NAME!r} needs {n}")
            if smap is not None:  # the first node of every design station
                first = [int(np.flatnonzero(np.asarray(smap) == k)[0]) for k in range(int(np.max(smap)) + 1)]
                vals = vals[first]
            design[w] = vals
    return setup, design_beam_params(setup.geometry, setup.material, design, setup.section)


def build_case(name: str, **options) -> CaseSetup:
    """A shipped case built from keyword options (the command-line options with ``_`` for ``-``),
    e.g. ``build_case("pegasus", loads="all", load_factor=2.5)``; no parser needed."""
    cases = available_cases()
    if name not in cases:
        raise ValueError(f"unknown case {name!r}; available: {', '.join(cases)}")
    return cases[name].build(**options)
