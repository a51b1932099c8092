"""Sizing cases shipped with wingmdao (cantilever, wing-box, PEGASUS, CRM, STW).

Each case module defines

* ``NAME`` and ``HELP``;
* ``OPTIONS``: its options dataclass (a :class:`CaseOptions`): the one table of its options, each
  field with its type, default and command-line metadata (:func:`option`: help with units,
  metavar, choices, argument group, deprecated spellings), from which
  :func:`add_option_arguments` builds the command line of ``wingmdao size CASE``;
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
import inspect
import numbers
import os
import types
import typing
from dataclasses import dataclass, field

import numpy as np

from wingmdao.design import SECTION_KINDS, WALL_VARS, design_beam_params, initial_design
# CASE_MODULES: the shipped cases; DEFAULT_COUPLED_THEORY: --aero-theory unset with --aero coupled
from wingmdao.names import CASE_MODULES, DEFAULT_COUPLED_THEORY



@dataclass
class CaseSetup:
    """A built case: what :class:`wingmdao.sizing.WingSizing` needs to size it.

    Parameters
    ----------
    geometry : wingmdao.sizing.WingGeometry
        Beam nodes (m), orientations and section dimensions (m).
    load_cases : list of wingmdao.groups.load_case.LoadCase
        The load cases the design must carry.
    material : wingmdao.materials.Material
        Wall material (Pa, kg/m^3).
    options : wingmdao.design.SizingOptions
        Design-variable bounds and start (m), KS parameter, optimizer settings.
    section : str, optional
        ``"box"``, ``"stiffened"`` (with ``panels``) or ``"solid"``.
    notes : list of str, optional
        Assumptions printed with the run.
    flutter : dict, optional
        FlutterDamping options (:func:`wingmdao.stability.cases.sizing_flutter_options`).
    panels : wingmdao.panels.layout.PanelLayout, optional
        The stiffened-panel layout with section ``"stiffened"``.
    turbulence : dict, optional
        TurbulenceStressKS options
        (:func:`wingmdao.loads.turbulence_analysis.sizing_turbulence_options`).
    panel_sizing : str, optional
        ``"full"`` or ``"two-level"`` (:func:`wingmdao.panel_sizing.size_two_level`) for a stiffened case.
    """

    geometry: object
    load_cases: list
    material: object
    options: object
    section: str = "box"
    notes: list = field(default_factory=list)
    flutter: dict | None = None
    panels: object = None
    turbulence: dict | None = None
    panel_sizing: str = "full"


#: Most time steps of one march: states, their adjoint, residual Jacobian blocks and stresses are
#: stored per step (beyond this a run needs tens of GB and days).
MAX_TIME_STEPS = 100_000


def check_step_count(t_final: float, dt: float, num_nodes: int = 20) -> int:
    """Number of time steps of ``0..t_final`` by ``dt``, checked before anything is allocated.

    Parameters
    ----------
    t_final : float
        Simulated time (s), finite and > 0.
    dt : float
        Time step (s), finite and > 0.
    num_nodes : int, optional
        Beam nodes, for the memory estimate of the message (18 states per node, 8 bytes, ~6
        stored copies per step).

    Returns
    -------
    int
        ``int(t_final / dt) + 1``.

    Raises
    ------
    ValueError
        The values are not finite and positive, or the count exceeds :data:`MAX_TIME_STEPS`.
    """
    if not (np.isfinite(t_final) and np.isfinite(dt) and t_final > 0 and dt > 0):
        raise ValueError(f"--t-final = {t_final} s, --dt = {dt} s; both must be finite and > 0")
    steps = int(t_final / dt) + 1
    if steps > MAX_TIME_STEPS:
        gb = steps * num_nodes * 18 * 8 * 6 / 1e9
        raise ValueError(f"--t-final / --dt = {steps} time steps (~{gb:.1f} GB stored); at most "
                         f"{MAX_TIME_STEPS} steps")
    return steps


def available_cases() -> dict:
    """The shipped cases whose modules import.

    Returns
    -------
    dict
        ``{name: module}`` in the order of :data:`CASE_MODULES`.
    """
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

    def __init_subclass__(cls, **kwargs):
        """Append a numpydoc ``Parameters`` section, built from the fields' :func:`option` metadata
        (flag and help with units), to the subclass's docstring: the one table documents the API too.

        Parameters
        ----------
        **kwargs
            Passed on to ``object.__init_subclass__``.
        """
        super().__init_subclass__(**kwargs)
        lines = []
        for name, hint in cls.__dict__.get("__annotations__", {}).items():
            f = cls.__dict__.get(name)
            if isinstance(f, dataclasses.Field) and "help" in f.metadata:
                kind = hint if isinstance(hint, str) else getattr(hint, "__name__", str(hint))
                flag = f.metadata.get("flag") or "--" + name.replace("_", "-")
                lines += [f"{name} : {kind}, default {f.default!r}",
                          f"    ``{flag}``: {f.metadata['help']}."]
        if lines and "Parameters\n---" not in (cls.__doc__ or ""):
            cls.__doc__ = "\n".join([inspect.cleandoc(cls.__doc__ or ""), "", "Parameters", "----------", *lines])

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


def case_options(options_cls, options=None, **overrides):
    """An instance of an options dataclass with keyword overrides.

    Parameters
    ----------
    options_cls : type
        The :class:`CaseOptions` dataclass.
    options : CaseOptions, optional
        An instance of ``options_cls``; None: the defaults.
    **overrides
        Option values by field name, replacing those of ``options``.

    Returns
    -------
    CaseOptions
        The instance (type-checked on construction).

    Raises
    ------
    ValueError
        An unknown option name, or ``options`` of another type.
    """
    names = [f.name for f in dataclasses.fields(options_cls)]
    unknown = [k for k in overrides if k not in names]
    if unknown:
        raise ValueError(f"{options_cls.CASE} has no option {unknown[0]!r}; options: {', '.join(sorted(names))}")
    if options is None:
        return options_cls(**overrides)
    if not isinstance(options, options_cls):
        raise ValueError(f"{options_cls.CASE} options must be a {options_cls.__name__} (or keyword options), got "
                         f"{type(options).__name__}")
    return dataclasses.replace(options, **overrides) if overrides else options


def options_from_namespace(options_cls, namespace):
    """The options dataclass from a parsed command line (the CLI's one conversion).

    Parameters
    ----------
    options_cls : type
        The :class:`CaseOptions` dataclass.
    namespace : argparse.Namespace
        The parsed command line; its attributes named like the fields are taken (lists as tuples).

    Returns
    -------
    CaseOptions
        The options of the command line.
    """
    return options_cls(**{f.name: _plain(getattr(namespace, f.name)) for f in dataclasses.fields(options_cls)
                  if hasattr(namespace, f.name)})


def _plain(value):
    return tuple(value) if isinstance(value, list) else value


#: command-line metadata keys of :func:`option` (besides ``help``)
OPTION_KEYS = ("flag", "metavar", "choices", "nargs", "const", "group", "aliases", "shared")


def option(default, help: str, *, flag: str | None = None, metavar=None, choices=None, nargs=None,
           const=None, group: str | None = None, aliases: tuple = (), shared: bool = False):
    """A field of a case's options dataclass with its command-line metadata.

    Parameters
    ----------
    default : object
        The option's default (the dataclass default and the command line's).
    help : str
        The ``--help`` text, with the unit of a dimensional value (``(m)``, ``(s)``); the default
        is appended by the command's help formatter unless the text already states it.
    flag : str, optional
        The option string; default ``--`` and the field name with ``-`` for ``_``.
    metavar : str or tuple of str, optional
        The value's name in ``--help`` (its unit or kind: ``S``, ``M``, ``N``).
    choices : sequence, optional
        The allowed values, enforced by the parser and by :class:`CaseOptions`.
    nargs : int or str, optional
        Number of values of a tuple field (``3``, ``"+"``), or ``"?"`` with ``const``.
    const : object, optional
        The value of the flag given alone (with ``nargs="?"``).
    group : str, optional
        Title of the ``--help`` argument group the option is listed in.
    aliases : tuple of str, optional
        Older, deprecated spellings of the flag: accepted, with one warning line, storing into
        the same field.
    shared : bool, optional
        The flag is one several commands share, spelled once in :mod:`wingmdao.cli._args` (e.g.
        ``--aero-theory``): the command adds it and :func:`add_option_arguments` skips the field.

    Returns
    -------
    dataclasses.Field
        The field, its metadata the keys of :data:`OPTION_KEYS` that were given, and ``help``.
    """
    given = {"flag": flag, "metavar": metavar, "choices": choices, "nargs": nargs, "const": const,
             "group": group, "aliases": tuple(aliases) or None, "shared": shared or None}
    metadata = {"help": help, **{k: v for k, v in given.items() if v is not None}}
    return field(default=default, metadata=metadata)


def option_flag(f) -> str:
    """The option string of a field of an options dataclass.

    Parameters
    ----------
    f : dataclasses.Field
        A field of a :class:`CaseOptions` dataclass.

    Returns
    -------
    str
        Its ``flag`` metadata, or ``--`` and the field name with ``-`` for ``_``.
    """
    return f.metadata.get("flag") or "--" + f.name.replace("_", "-")


def option_argument(f, hint) -> tuple[str, dict]:
    """The ``add_argument`` flag and keywords of one field of an options dataclass.

    Parameters
    ----------
    f : dataclasses.Field
        A field made by :func:`option`.
    hint : type
        Its resolved annotation (``float``, ``int``, ``str``, ``bool``, ``tuple[float, ...]``,
        optionally ``| None``).

    Returns
    -------
    flag : str
        The option string (:func:`option_flag`).
    kwargs : dict
        The keywords of ``add_argument``: ``dest`` (the field name), ``default``, ``help``, and
        ``action="store_true"`` for a bool, else ``type`` (the element type of a tuple) and the
        ``metavar``, ``choices``, ``nargs``, ``const`` metadata.
    """
    md = f.metadata
    kind, item, _ = _type_parts(hint)
    kwargs = {"dest": f.name, "default": f.default, "help": md["help"]}
    if kind is bool:
        kwargs["action"] = "store_true"
    else:
        kwargs["type"] = item if kind is tuple else kind
        kwargs.update({k: (list(md[k]) if k == "choices" else md[k])
                       for k in ("metavar", "choices", "nargs", "const") if k in md})
    return option_flag(f), kwargs


def add_option_arguments(parser, cls, *, names=None, deprecated_alias=None) -> list:
    """Build the command-line options of an options dataclass from its fields (one table).

    Every field becomes one flag (:func:`option_argument`) storing into the field's name, in the
    field order, in the argument group its ``group`` metadata names (groups made once, in order
    of first use), except the ``shared`` ones the command adds itself; the parsed namespace converts back with :func:`options_from_namespace`.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The (sub)parser to add the options to.
    cls : type
        A :class:`CaseOptions` dataclass whose fields are all made by :func:`option`.
    names : collection of str, optional
        Only these fields (default: all).
    deprecated_alias : callable, optional
        ``deprecated_alias(parser, old, new, dest=..., **kwargs)`` adding an older spelling
        (:func:`wingmdao.cli._args.add_deprecated_alias`); None: the ``aliases`` are not accepted.

    Returns
    -------
    list of argparse.Action
        The actions of the fields' flags, in field order.

    Raises
    ------
    TypeError
        A field without command-line metadata (not made by :func:`option`).
    """
    hints = typing.get_type_hints(cls)
    groups, actions = {}, []
    for f in dataclasses.fields(cls):
        if (names is not None and f.name not in names) or f.metadata.get("shared"):
            continue
        if "help" not in f.metadata:
            raise TypeError(f"{cls.__name__}.{f.name} has no command-line metadata (make it with "
                            "wingmdao.cases.option)")
        flag, kwargs = option_argument(f, hints[f.name])
        target = parser
        title = f.metadata.get("group")
        if title is not None:
            if title not in groups:
                groups[title] = parser.add_argument_group(title)
            target = groups[title]
        actions.append(target.add_argument(flag, **kwargs))
        if deprecated_alias is not None:
            extra = {k: kwargs[k] for k in ("type", "nargs", "metavar", "choices", "const") if k in kwargs}
            for old in f.metadata.get("aliases", ()):
                deprecated_alias(parser, old, flag, dest=f.name, **extra)
    return actions


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




def case_beam_parameters(module, walls=None, *, source="walls"):
    """A shipped case's wing and its beam parameters for one design, without a model run.

    Parameters
    ----------
    module : module
        The case module (``module.build``; built with its maneuvers only when it has a ``loads``
        option).
    walls : dict, optional
        ``{wall: (n,) array}`` wall thicknesses (m) per beam node (the ``thickness`` of a sizing
        result, keys ``upper_skin``, ``lower_skin``, ``front_spar``, ``rear_spar``), mapped to the
        design stations; None: the case's initial design.
    source : str, optional
        What ``walls`` came from, named in the error (e.g. the command's ``--design FILE``).

    Returns
    -------
    setup : CaseSetup
        The built case.
    beam_params : dict
        The beam parameter dict of the sections the sizing model uses
        (:func:`wingmdao.design.design_beam_params`).

    Raises
    ------
    ValueError
        A wall without one value per beam node.
    """
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
    """A shipped case built from keyword options; no parser needed.

    Parameters
    ----------
    name : str
        The case name (a key of :data:`CASE_MODULES`).
    **options
        The case's options by field name (the command-line options with ``_`` for ``-``), e.g.
        ``build_case("pegasus", loads="all", load_factor=2.5)``.

    Returns
    -------
    CaseSetup
        Geometry, load cases, material and sizing options of the case.

    Raises
    ------
    ValueError
        An unknown case or a bad option.
    """
    cases = available_cases()
    if name not in cases:
        raise ValueError(f"unknown case {name!r}; available: {', '.join(cases)}")
    return cases[name].build(**options)
