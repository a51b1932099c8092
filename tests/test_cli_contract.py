"""The command-line contract on every (sub)command (issue 11, docs/cli.md): help shows defaults, the
shared flags are spelled and defaulted the same everywhere, ``--json -`` writes only JSON to standard
output, negative numbers in exponent notation are values, plots are written atomically."""

import argparse
import json
import os
import shutil

import pytest

from wingmdao.cli import DefaultsHelpFormatter, build_parser, main


def _leaves(parser=None, path=()):
    """(command path, parser) of every parser that runs something (has ``func``)."""
    parser = parser or build_parser()
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if parser.get_default("func") is not None and not subs:
        yield path, parser
    for sub in subs:
        for name, child in sub.choices.items():
            yield from _leaves(child, (*path, name))


LEAVES = dict(_leaves())


def _options(parser):
    return {s: a for a in parser._actions for s in a.option_strings}


def _visible(parser):
    return {s for s, a in _options(parser).items() if a.help != argparse.SUPPRESS}


def test_every_command_is_walked():
    names = {p[0] for p in LEAVES}
    assert {"section", "section-fe", "run", "verify", "export", "size", "n2", "gust", "flutter", "report"} <= names
    assert ("size", "pegasus") in LEAVES and ("n2", "wing-box") in LEAVES


@pytest.mark.parametrize("path", sorted(LEAVES), ids=" ".join)
def test_help_shows_the_default_of_every_option(path):
    parser = LEAVES[path]
    assert issubclass(parser.formatter_class, DefaultsHelpFormatter)
    fmt = parser.formatter_class(prog="wingmdao")
    for action in parser._actions:
        if action.help == argparse.SUPPRESS or action.nargs == 0 or not action.option_strings or action.required:
            continue
        text = fmt._get_help_string(action)
        assert "default" in text.lower(), f"{' '.join(path)} {action.option_strings[0]}: {text!r}"
    parser.format_help()  # renders (no bad % in a help text)


#: the one spelling of each shared concept: flag -> (action attributes every command shares)
SHARED = {
    "--json": {"default": "-", "metavar": "PATH"},
    "--out": {"metavar": "DIR"},
    "--overwrite": {"nargs": 0, "default": False},
    "--no-plots": {"nargs": 0, "default": False},
    "--families": {"metavar": "FAMILIES"},
    "--t-skin": {"metavar": "M", "type": float},
    "--t-spar": {"metavar": "M", "type": float},
}
#: other spellings of those concepts, which no command may show (old ones are hidden aliases)
FORBIDDEN = {"--constraints", "--plots", "--output", "--outdir", "--out-dir", "--output-dir", "--json-out",
             "--no-plot", "--force", "--thickness-skin", "--skin-thickness", "--spar-thickness"}


@pytest.mark.parametrize("path", sorted(LEAVES), ids=" ".join)
def test_shared_flags_are_spelled_and_defaulted_the_same(path):
    parser = LEAVES[path]
    opts = _options(parser)
    assert not (_visible(parser) & FORBIDDEN), sorted(_visible(parser) & FORBIDDEN)
    for flag, attrs in SHARED.items():
        if flag in opts:
            for key, want in attrs.items():
                assert getattr(opts[flag], key) == want, f"{' '.join(path)} {flag}.{key}"
    if "--out" in opts and path[0] not in ("report", "verify"):  # (report: next to the recording; verify: no plot)
        assert opts["--out"].default == "results"
    if path[0] in ("size", "n2") and path[1] not in ("cantilever", "aerostruct-crm"):  # a choice of families
        assert "--families" in opts  # (the cantilever constrains its two fixed ones; the uCRM OAS's KS)
    if any(f in opts for f in ("--t-skin", "--t-spar", "--t-upper")):  # one wall-thickness family
        assert {"--t-skin", "--t-spar"} <= set(opts)
    if "--material" in opts:
        assert "built-in" in opts["--material"].help
    if path[0] in ("size", "gust", "flutter"):  # commands that write files into --out
        assert {"--out", "--overwrite", "--json"} <= set(opts)
        if path != ("size", "aerostruct-crm"):  # (it writes recordings only, no plots)
            assert "--no-plots" in opts


def test_old_spellings_still_work_with_one_warning(capsys):
    parser = build_parser()
    assert parser.parse_args(["size", "wing-box", "--constraints", "vm,ss"]).constraints == "vm,ss"
    assert parser.parse_args(["size", "wing-box", "--families", "vm,cent"]).constraints == "vm,cent"
    assert parser.parse_args(["report", "r.sql", "--plots", "d"]).out == "d"
    err = capsys.readouterr().err.splitlines()
    assert err == ["wingmdao: warning: --constraints is deprecated; use --families (same meaning)",
                   "wingmdao: warning: --plots is deprecated; use --out (same meaning)"]


def test_section_wall_flags_t_skin_t_spar_match_the_four_walls(capsys):
    box = ["section", "--width", "3", "--height", "0.5"]
    assert main([*box, "--t-skin", "0.1", "--t-spar", "0.2"]) == 0
    by_family = json.loads(capsys.readouterr().out)
    assert main([*box, "--t-upper", "0.1", "--t-lower", "0.1", "--t-front", "0.2", "--t-rear", "0.2"]) == 0
    assert json.loads(capsys.readouterr().out) == by_family
    assert main([*box, "--t-skin", "0.1", "--t-upper", "0.2", "--t-spar", "0.2"]) == 2
    assert "both set the upper skin" in capsys.readouterr().err


HAS_CCX = shutil.which("ccx") is not None
#: fast inputs of every command that has --json (a new command with --json must be added here)
JSON_RUNS = {
    ("cache",): [],                   # a report only (no --prune): reads the user's cache, changes nothing
    ("section",): ["--width", "3", "--height", "0.5", "--t-skin", "0.1", "--t-spar", "0.2"],
    ("section-fe",): ["--rectangle", "1", "0.5", "--material", "aluminium"],
    ("panel",): ["--material", "aluminium", "--t-skin", "0.004", "--width", "0.15", "--length", "0.6",
                 "--stiffener-height", "0.04", "--stiffener-thickness", "0.003", "--nx", "-5e5"],
    ("run", "wing-box"): ["--geometry", "prismatic", "--tip-load", "0", "0", "-1e5"],
    ("verify", "wing-box"): ["--geometry", "prismatic", "--tip-load", "0", "0", "1e5", "--chord-elements", "2",
                             "--height-elements", "1", "--span-size", "2"],
    ("size", "cantilever"): ["--stations", "4", "--no-plots"],
    ("size", "wing-box"): ["--analysis-only", "--no-plots"],
    ("size", "pegasus"): ["--analysis-only", "--no-plots"],
    ("size", "crm"): ["--analysis-only", "--no-plots"],
    ("size", "stw"): ["--analysis-only", "--no-plots"],
    ("flutter",): ["goland", "--speeds", "100", "200", "3", "--num-nodes", "5", "--modes", "2", "--no-plots"],
    ("gust",): ["pegasus", "--t-final", "0.2", "--dt", "0.02", "--gust-start", "0.1", "--no-plots"],
    ("turbulence",): ["pegasus", "--grid-points", "11", "--no-plots"],
    ("maneuver",): ["pegasus", "--checked-pitch", "--maneuvering-speed-eas", "90", "--pitch-inertia", "345000",
                    "--cg-x", "0.67", "--tail-arm", "12", "--tail-area", "11.7", "--tail-lift-slope", "4",
                    "--steps", "20", "--no-plots"],
    ("loads",): ["pegasus", "--matrix", os.path.join(os.path.dirname(os.path.abspath(__file__)), "data",
                                                     "loads-matrix-tiny.yaml")],
    ("size", "aerostruct-crm"): ["--analysis-only", "--num-y", "9", "--no-oas-beam", "--quiet"],
    ("verify", "panel"): ["--material", "aluminium", "--t-skin", "0.002", "--width", "0.15", "--length", "0.45",
                          "--nx", "-1000", "--mesh-size", "0.075"],
    ("verify", "pegasus"): ["--no-ribs", "--chord-elements", "2", "--height-elements", "1", "--span-size", "2"],
}
SLOW_JSON = {("gust",), ("turbulence",), ("maneuver",), ("size", "pegasus"), ("size", "crm"), ("size", "aerostruct-crm"), ("verify", "pegasus")}


def test_every_command_with_json_has_a_fast_run():
    with_json = {p for p, parser in LEAVES.items() if "--json" in _options(parser)}
    assert with_json == set(JSON_RUNS)


@pytest.mark.parametrize("path", [pytest.param(p, marks=[pytest.mark.slow] if p in SLOW_JSON else [],
                                               id=" ".join(p)) for p in sorted(JSON_RUNS)])
def test_json_dash_writes_only_json_to_stdout(path, tmp_path, capsys):
    if path[0] == "verify" and not HAS_CCX:
        pytest.skip("CalculiX (ccx) not installed")
    argv = [*path, *JSON_RUNS[path]]
    if "--out" in _options(LEAVES[path]):
        argv += ["--out", str(tmp_path)]
    assert main([*argv, "--json", "-"]) == 0
    cap = capsys.readouterr()
    assert isinstance(json.loads(cap.out), dict)  # nothing but one JSON document on standard output
    if path in {("section",), ("section-fe",), ("run", "wing-box")}:  # the default is the same
        assert main(argv) == 0
        assert json.loads(capsys.readouterr().out) == json.loads(cap.out)


#: the arguments a command needs before any option can be parsed
REQUIRED = {"section": ["--width", "1", "--height", "1"],
            "panel": ["--material", "aluminium", "--t-skin", "1", "--width", "1", "--length", "1"], "run": ["--geometry", "prismatic"],
            "verify": ["--geometry", "prismatic"], "export": ["--geometry", "prismatic", "--format", "calculix", "f"],
            "gust": ["pegasus"], "turbulence": ["pegasus"], "maneuver": ["pegasus"], "loads": ["pegasus", "--matrix", "m.yaml"], "flutter": ["goland"], "report": ["r.sql"],
            ("verify", "pegasus"): [],
            ("verify", "panel"): ["--material", "aluminium", "--t-skin", "1", "--width", "1", "--length", "1"], ("export", "pegasus"): ["--format", "calculix", "f"]}


def _numeric_options(parser):
    for action in parser._actions:
        if action.option_strings and action.help != argparse.SUPPRESS and action.nargs != 0 and (
                action.type in (float, int) or action.dest == "speeds") and action.choices is None:
            yield action


@pytest.mark.parametrize("path", sorted(LEAVES), ids=" ".join)
def test_negative_numbers_in_exponent_notation_are_values(path):
    """Every numeric option of every command reads -1e6 (floats) / -3 (integers) as a value, also in
    lists (``--tip-load -1e6 0 1e7``); range checks come later, with a clear message."""
    parser = LEAVES[path]
    for action in _numeric_options(parser):
        n = action.nargs if isinstance(action.nargs, int) else 1 if action.nargs in (None, "?") else 2
        value = "-3" if action.type is int else "-1e6"
        values = [value] + ["-2.5E-3" if action.type is not int else "-4"] * (n - 1)
        args = parser.parse_args([*REQUIRED.get(path, REQUIRED.get(path[0], [])), action.option_strings[0], *values])
        got = getattr(args, action.dest)
        got = list(got) if isinstance(got, (list, tuple)) else [got]
        assert [float(v) for v in got] == [float(v) for v in values], f"{' '.join(path)} {action.option_strings[0]}"


def test_save_figure_is_atomic(tmp_path, monkeypatch):
    """A plot is written to a temporary file in the same folder and renamed: a failed write keeps
    the earlier PNG whole and leaves no temporary file."""
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from wingmdao.plots import save_figure

    path = tmp_path / "p.png"
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    save_figure(fig, str(path))
    first = path.read_bytes()
    assert first[:8] == b"\x89PNG\r\n\x1a\n"

    def boom(*a):
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", boom)
    fig, ax = plt.subplots()
    ax.plot([0, 1], [1, 0])
    with pytest.raises(OSError, match="disk full"):
        save_figure(fig, str(path))
    assert path.read_bytes() == first
    assert [p.name for p in tmp_path.iterdir()] == ["p.png"]
    assert not plt.get_fignums()  # the figure is closed either way


def test_command_plots_go_through_save_figure(tmp_path, monkeypatch, capsys):
    """flutter's V-g plot (as gust's, verify's, size's and report's) is written by save_figure."""
    pytest.importorskip("matplotlib")
    import wingmdao.cli.flutter as flutter_command
    import wingmdao.plots as plots

    written = []
    original = plots.save_figure

    def spy(fig, path, dpi=120):
        written.append(path)
        return original(fig, path, dpi)

    monkeypatch.setattr(flutter_command, "save_figure", spy)  # the command's wingmdao.plots.save_figure
    out = tmp_path / "r.json"
    assert main(["flutter", "goland", *JSON_RUNS[("flutter",)][1:-1], "--out", str(tmp_path),
                 "--json", str(out)]) == 0
    assert written == [str(tmp_path / "flutter_goland.png")]
    assert json.loads(out.read_text())["plot"] == written[0]


def test_export_refuses_an_existing_deck_without_overwrite(tmp_path, capsys):
    deck = tmp_path / "box.inp"
    deck.write_text("earlier deck\n")
    argv = ["export", "wing-box", "--geometry", "prismatic", "--format", "calculix", str(deck)]
    assert main(argv) == 2
    assert "--overwrite" in capsys.readouterr().err and deck.read_text() == "earlier deck\n"
    assert main([*argv, "--overwrite"]) == 0 and deck.read_text() != "earlier deck\n"
