"""The command line of ``wingmdao size CASE`` is generated from the case's options dataclass.

Each case's ``OPTIONS`` fields carry their command-line metadata (:func:`wingmdao.cases.option`)
and :func:`wingmdao.cases.add_option_arguments` builds the flags. These tests check the generated
parser against the dataclass, independently of how it was built: one flag per field, values
that round-trip through the parser into the dataclass, choices refused by the parser, every
default shown in ``--help``, and the deprecated spellings still accepted with one warning.
"""

from __future__ import annotations

import argparse
import dataclasses
import typing

import pytest

from wingmdao.cases import (CaseOptions, _type_parts, add_option_arguments, available_cases, option, option_flag,
                            options_from_namespace)
from wingmdao.cli import DefaultsHelpFormatter, WingmdaoParser, build_parser
from wingmdao.cli._args import METAVARS, add_deprecated_alias

CASES = available_cases()
#: the cases whose command line is generated (every shipped case)
GENERATED = list(CASES)


def _parser(module):
    parser = WingmdaoParser(prog=f"wingmdao size {module.NAME}")
    add_option_arguments(parser, module.OPTIONS, deprecated_alias=add_deprecated_alias)
    return parser


def _own(module):
    """The fields whose flag the case's parser makes (not the ``shared`` ones the command adds)."""
    return [f for f in dataclasses.fields(module.OPTIONS) if not f.metadata.get("shared")]


def _size_parser(name):
    sub = build_parser()._subparsers._group_actions[0].choices["size"]
    return sub._subparsers._group_actions[0].choices[name]


def _visible(parser):
    return [a for a in parser._actions if a.option_strings and a.help != argparse.SUPPRESS
            and a.dest != "help"]


def _other_value(f, hint):
    """A valid value of field ``f`` different from its default, and its command-line words."""
    kind, item, _ = _type_parts(hint)
    choices = f.metadata.get("choices")
    if kind is bool:
        return (not f.default), ([] if f.default else [option_flag(f)])
    if choices is not None:
        value = next((c for c in reversed(list(choices)) if c != f.default), f.default)  # one choice: itself
        return value, [option_flag(f), str(value)]
    if kind is tuple:
        n = f.metadata["nargs"] if isinstance(f.metadata["nargs"], int) else 2
        value = tuple(item(k + 2) for k in range(n))
        return value, [option_flag(f), *map(str, value)]
    if kind is str:
        return "vm,ss", [option_flag(f), "vm,ss"]
    value = kind(3) if f.default is None else kind(f.default + 7 if kind is int else f.default * 1.5 + 0.25)
    return value, [option_flag(f), repr(value) if kind is float else str(value)]


def test_every_case_command_line_is_generated():
    assert {"cantilever", "wing-box", "pegasus", "crm", "stw"} <= set(GENERATED)
    assert not any(hasattr(mod, "add_arguments") for mod in CASES.values())


@pytest.mark.parametrize("name", GENERATED)
def test_one_flag_per_field(name):
    module = CASES[name]
    fields = dataclasses.fields(module.OPTIONS)
    assert all("help" in f.metadata for f in fields), "every field carries its command-line metadata"
    actions = _visible(_parser(module))
    assert sorted(a.dest for a in actions) == sorted(f.name for f in _own(module))
    assert all(len(a.option_strings) == 1 for a in actions)
    # the real command has every field's flag once, the shared ones too (plus the sizing options
    # common to every case), each storing into the field
    dests = {}
    for a in _visible(_size_parser(name)):
        for flag in a.option_strings:
            dests.setdefault(flag, []).append(a.dest)
    for f in fields:
        assert dests.get(option_flag(f)) == [f.name], (name, f.name)


@pytest.mark.parametrize("name", GENERATED)
def test_values_round_trip_through_the_parser(name):
    module = CASES[name]
    parser = _parser(module)
    assert options_from_namespace(module.OPTIONS, parser.parse_args([])) == module.OPTIONS()
    hints = typing.get_type_hints(module.OPTIONS)
    for f in _own(module):
        value, words = _other_value(f, hints[f.name])
        opts = options_from_namespace(module.OPTIONS, parser.parse_args(words))
        assert getattr(opts, f.name) == value, (name, f.name, words)
        assert type(getattr(opts, f.name)) is type(value), (name, f.name)
        assert opts == dataclasses.replace(module.OPTIONS(), **{f.name: value})


@pytest.mark.parametrize("name", GENERATED)
def test_choices_are_enforced(name, capsys):
    module = CASES[name]
    parser = _parser(module)
    with_choices = [f for f in _own(module) if "choices" in f.metadata]
    assert with_choices, name
    for f in with_choices:
        with pytest.raises(SystemExit) as exc:
            parser.parse_args([option_flag(f), "9"])
        assert exc.value.code == 2
        assert "invalid choice" in capsys.readouterr().err
        with pytest.raises(ValueError, match=f.name):  # the dataclass refuses it too (library path)
            module.OPTIONS(**{f.name: "9"})


@pytest.mark.parametrize("name", GENERATED)
def test_help_shows_units_and_defaults(name):
    module = CASES[name]
    parser = _parser(module)
    formatter = DefaultsHelpFormatter(parser.prog)
    by_dest = {a.dest: a for a in _visible(parser)}
    for f in _own(module):
        action = by_dest[f.name]
        text = formatter._get_help_string(action)
        if action.nargs != 0:  # on/off switches are off unless given
            assert "default" in text.lower(), (name, f.name, text)
            if "%(default)s" in text:
                assert (text % {"default": f.default}).endswith(f"(default: {f.default})")
        flag = option_flag(f)
        if flag in METAVARS:  # one metavar (its unit or kind) per flag shared by commands
            assert action.metavar == METAVARS[flag], (name, flag)
    full = parser.format_help()
    assert "(default:" in full


@pytest.mark.parametrize("name", GENERATED)
def test_deprecated_aliases_warn_and_store(name, capsys):
    module = CASES[name]
    parser = _parser(module)
    hints = typing.get_type_hints(module.OPTIONS)
    aliased = [f for f in dataclasses.fields(module.OPTIONS) if f.metadata.get("aliases")]
    for f in aliased:
        value, words = _other_value(f, hints[f.name])
        for old in f.metadata["aliases"]:
            opts = options_from_namespace(module.OPTIONS, parser.parse_args([old, *words[1:]]))
            assert getattr(opts, f.name) == value
            err = capsys.readouterr().err
            assert err.strip() == f"wingmdao: warning: {old} is deprecated; use {option_flag(f)} (same meaning)"
            assert old not in parser.format_help()  # hidden


def test_renamed_options_keep_their_old_spelling():
    """``--stations`` (cantilever) and ``--constraints`` (wing-box) stay deprecated aliases."""
    assert "--stations" in CASES["cantilever"].OPTIONS.__dataclass_fields__["stations"].metadata["aliases"]
    assert "--constraints" in CASES["wing-box"].OPTIONS.__dataclass_fields__["constraints"].metadata["aliases"]


def test_a_field_without_metadata_is_refused():
    @dataclasses.dataclass(frozen=True)
    class Bare(CaseOptions):
        CASE = "bare"
        x: float = 1.0
        y: int = option(2, "count", metavar="N")

    with pytest.raises(TypeError, match="Bare.x"):
        add_option_arguments(WingmdaoParser(), Bare)
    parser = WingmdaoParser()
    add_option_arguments(parser, Bare, names=("y",))
    assert parser.parse_args(["--y", "4"]).y == 4


@pytest.mark.parametrize("name", GENERATED)
def test_shared_flags_round_trip_on_the_command(name):
    """Fields whose flag the commands share (``--aero-theory``) parse on ``wingmdao size CASE``
    with the case's default."""
    module = CASES[name]
    parser = _size_parser(name)
    hints = typing.get_type_hints(module.OPTIONS)
    assert options_from_namespace(module.OPTIONS, parser.parse_args([])) == module.OPTIONS()
    for f in dataclasses.fields(module.OPTIONS):
        if f.metadata.get("shared"):
            value, words = _other_value(f, hints[f.name])
            assert getattr(options_from_namespace(module.OPTIONS, parser.parse_args(words)), f.name) == value


def test_closed_loop_margin_flag_help_and_value():
    """``wingmdao size pegasus --closed-loop-margin`` (1/s): its help names the unit and the default
    0.0, and the value reaches the case options."""
    parser = _size_parser("pegasus")
    action = next(a for a in parser._actions if "--closed-loop-margin" in a.option_strings)
    text = DefaultsHelpFormatter(parser.prog)._get_help_string(action) % {"default": action.default}
    assert action.metavar == "PER_S" and "Re lambda <= -margin (1/s, >= 0;" in text, text
    assert text.endswith("(default: 0.0)"), text
    assert "--closed-loop-margin PER_S" in parser.format_help()
    args = parser.parse_args(["--closed-loop-margin", "0.4"])
    assert args.closed_loop_margin == 0.4
    assert parser.parse_args([]).closed_loop_margin == 0.0
