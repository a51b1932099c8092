"""One command-line vocabulary (issue 27, item 4; docs/cli.md, "One spelling per concept"): every
flag of every command collected through argparse, one spelling and one metavar per concept, units
in the help, no Python ``None`` in human text, errors that name the flag with a range that is not
empty, one warning format, and only rank 0 printing and writing under MPI."""

import argparse
import json
import re
import warnings

import pytest

from wingmdao.cli import build_parser, main
from wingmdao.cli._args import METAVARS

from test_cli_contract import LEAVES, _options


def _all_flags():
    """{flag: [(command path, action)]} over every command (hidden deprecated aliases left out)."""
    flags = {}
    for path, parser in LEAVES.items():
        for flag, action in _options(parser).items():
            if action.help != argparse.SUPPRESS and flag not in ("-h", "--help"):
                flags.setdefault(flag, []).append((path, action))
    return flags


FLAGS = _all_flags()

#: the concepts that had two spellings, and the one kept (the old one a hidden, deprecated alias)
RENAMED = {"--gradient-ft": "--gust-gradient-ft", "--stations": "--num-nodes", "--plot": "--out",
           "--loads-case": "--loads", "--plots": "--out", "--constraints": "--families"}


def test_one_spelling_per_concept():
    visible = set(FLAGS)
    assert not visible & set(RENAMED), sorted(visible & set(RENAMED))
    # the mesh size: beam nodes are --num-nodes everywhere (--elements N1 N2 N3 is per-segment
    # elements of the wing box, --num-y OpenAeroStruct's own mesh)
    assert not {"--nodes", "--n-nodes", "--num-stations", "--stations"} & visible
    assert {"--gust-gradient-ft", "--num-nodes", "--gravity", "--modes"} <= visible


def test_old_spellings_are_hidden_aliases_with_one_warning(capsys):
    parser = build_parser()
    cases = [
        (["gust", "pegasus", "--gradient-ft", "100"], "gradient_ft", 100.0, "--gust-gradient-ft"),
        (["size", "cantilever", "--stations", "5"], "stations", 5, "--num-nodes"),
        (["verify", "wing-box", "--geometry", "prismatic", "--plot", "p.png"], "plot", "p.png", "--out"),
        (["verify", "pegasus", "--buckling", "--loads-case", "maneuver_neg"], "loads", "maneuver-neg", "--loads"),
    ]
    for argv, dest, value, new in cases:
        assert getattr(parser.parse_args(argv), dest) == value
        err = capsys.readouterr().err.splitlines()
        assert len(err) == 1 and err[0].startswith(f"wingmdao: warning: {argv[-2]} is deprecated; use {new} ("), err


def test_one_metavar_per_flag():
    """A flag shown by several commands shows the same metavar (its unit or kind of value)."""
    for flag, uses in FLAGS.items():
        metavars = {str(a.metavar).split(" | ")[0] for _, a in uses if a.nargs != 0 and not a.choices}
        assert len(metavars) <= 1, (flag, metavars, [" ".join(p) for p, _ in uses])
        if flag in METAVARS and metavars:
            assert metavars == {METAVARS[flag]}, (flag, metavars)
    assert not [f for f, uses in FLAGS.items() for _, a in uses
                if a.nargs != 0 and a.metavar is None and not a.choices and a.type in (int, float)], \
        "every numeric flag names its unit or kind of value in its metavar"


def test_gust_defaults_are_the_cases_as_on_size():
    """``gust`` and ``size pegasus`` share the gust's time grid and start (the case's defaults)."""
    from wingmdao.cases.pegasus import PegasusOptions

    size = _options(LEAVES["size", "pegasus"])
    gust = _options(LEAVES["gust",])
    for flag in ("--dt", "--gust-start", "--t-final", "--gust-gradient-ft", "--altitude-ft", "--mach", "--u-ref-fps"):
        assert gust[flag].metavar == size[flag].metavar, flag
        assert gust[flag].default is None and "the case's" in gust[flag].help, flag  # resolved to the case's
    assert size["--dt"].default == PegasusOptions.dt and size["--gust-start"].default == PegasusOptions.gust_start


def test_gravity_is_a_value_on_every_command():
    """``--gravity [G]`` (m/s^2; alone 9.81) on ``run wing-box`` and ``flutter``, never a bare switch."""
    parser = build_parser()
    for path, action in FLAGS["--gravity"]:
        assert action.nargs == "?" and action.const == 9.81 and action.metavar == "M_S2", path
        assert "m/s^2" in action.help
    assert parser.parse_args(["run", "wing-box", "--geometry", "prismatic", "--gravity"]).gravity == 9.81
    assert parser.parse_args(["run", "wing-box", "--geometry", "prismatic", "--gravity", "1.62"]).gravity == 1.62
    assert parser.parse_args(["run", "wing-box", "--geometry", "prismatic"]).gravity is None
    assert parser.parse_args(["flutter", "goland", "--deformed", "--gravity"]).gravity == 9.81


def test_units_in_help_are_in_parentheses():
    """Units are written "(s)", "(m)", "(ft)" in every help text, never "[s]"."""
    bad = [(" ".join(p), f) for f, uses in FLAGS.items() for p, a in uses
           if re.search(r"\[(s|m|ft|Hz|ft/s[^\]]*)\]", a.help or "")]
    assert not bad, bad


@pytest.mark.parametrize("path", sorted(LEAVES), ids=" ".join)
def test_no_python_none_in_help(path):
    assert not re.search(r"\bNone\b", LEAVES[path].format_help()), " ".join(path)


@pytest.mark.parametrize("argv, message", [
    (["section", "--width", "1", "--height", "1", "--t-skin", "0.6", "--t-spar", "0.1"],
     "--t-skin = 0.6 m: the two skins must be thinner together than --height = 1 m; allowed range (0, 0.5) m"),
    (["section", "--width", "1", "--height", "1", "--t-upper", "0.6", "--t-lower", "0.5", "--t-spar", "0.1"],
     "--t-upper = 0.6 m: --t-upper + --t-lower must be less than --height = 1 m; allowed range (0, 0.5) m"),
    (["section", "--width", "1", "--height", "1", "--t-upper", "0.1", "--t-lower", "5", "--t-spar", "0.1"],
     "--t-upper + --t-lower = 0.1 + 5 m; the two skins must be thinner together than --height = 1 m"),
    (["flutter", "goland", "--modes", "0", "--no-plots"], "--modes = 0; allowed range >= 1"),
    (["flutter", "goland", "--speeds", "10", "5", "4", "--no-plots"], "--speeds V1 = 5.0 m/s; allowed range (V0 = 10.0"),
    (["gust", "pegasus", "--mach", "5", "--no-plots"], "--mach = 5.0; allowed range (0, 1)"),
    (["gust", "pegasus", "--altitude-ft", "-1", "--no-plots"], "--altitude-ft = -1.0 ft; allowed range [0, 60000] ft"),
    (["size", "cantilever", "--num-nodes", "2", "--analysis-only"], "--num-nodes = 2; allowed range >= 3"),
    (["size", "pegasus", "--damping-ratio", "-1", "--analysis-only"], "--damping-ratio = -1.0; allowed range [0, 1)"),
    (["size", "pegasus", "--closed-loop-margin", "-0.5", "--analysis-only"],
     "--closed-loop-margin = -0.5 1/s; allowed range [0, inf) 1/s"),
    (["run", "wing-box", "--geometry", "prismatic", "--gravity", "-1"], "--gravity = -1.0 m/s^2; allowed range [0, inf)"),
])
def test_errors_name_the_flag_with_a_range_that_is_not_empty(argv, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
    assert not re.search(r"\bt_(upper|lower)_skin|t_(front|rear)_spar\b", err)  # the flag, not the variable
    for low, high in re.findall(r"allowed range [(\[]([-\d.e+]+), ([-\d.e+]+)[)\]]", err):
        assert float(low) < float(high), err


def test_error_messages_use_one_form():
    """Flag errors read ``FLAG = VALUE; allowed ...``, not "must be ..., got ..." (source scan of
    the command-line modules and the cases that check flags)."""
    import pathlib

    import wingmdao

    root = pathlib.Path(wingmdao.__file__).parent
    files = [*root.glob("cli/*.py"), root / "cases/pegasus.py", root / "cases/cantilever.py"]
    bad = [f"{f.name}: {line.strip()}" for f in files for line in f.read_text().splitlines()
           if re.search(r"--[a-z-]+ must be .*got \{", line)]
    assert not bad, bad


def test_ignored_gust_options_warn_with_the_default_load_set(capsys, tmp_path):
    """``size pegasus --mach 5`` without ``--loads``: the load set is the maneuvers, --mach is
    ignored, and says so (it ran silently)."""
    from wingmdao.cases import pegasus

    setup = pegasus.build(mach=0.7)
    assert "warning: ignored with --loads maneuver (the default without a gust set; gust options): --mach 0.7" \
        in setup.notes
    coupled = pegasus.build(mach=0.6, aero="coupled")  # the trimmed maneuvers' flight point: used
    assert not any("--mach" in n for n in coupled.notes)


def test_library_warnings_are_one_line_in_the_warning_format(capsys, monkeypatch):
    """A ``warnings.warn`` during a command prints ``wingmdao: warning: ...`` on one line."""
    import wingmdao.cli.section as section

    real = section.section_properties

    def noisy(args):
        warnings.warn("wingmdao: C kernel x unavailable,\n  using the fallback", UserWarning, stacklevel=2)
        warnings.warn("something old", DeprecationWarning, stacklevel=2)
        return real(args)

    monkeypatch.setattr(section, "section_properties", noisy)
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        assert main(["section", "--width", "1", "--height", "0.5", "--t-skin", "0.01", "--t-spar", "0.01"]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err == ["wingmdao: warning: C kernel x unavailable, using the fallback",
                   "wingmdao: warning: something old (DeprecationWarning)"], err


def test_under_mpi_only_rank_0_prints_and_writes(tmp_path, capsys, monkeypatch):
    """Rank 1 of 2 (as mpirun's environment says) prints nothing and writes no file; rank 0 both."""
    argv = ["section", "--width", "1", "--height", "0.5", "--t-skin", "0.01", "--t-spar", "0.01",
            "--json", str(tmp_path / "s.json")]
    monkeypatch.setenv("OMPI_COMM_WORLD_SIZE", "2")
    monkeypatch.setenv("OMPI_COMM_WORLD_RANK", "1")
    assert main(argv) == 0
    assert main(["section", "--width", "-1", "--height", "0.5", "--solid"]) == 2  # the error: rank 0 says it
    out = capsys.readouterr()
    assert out.out == "" and out.err == "" and not (tmp_path / "s.json").exists()
    monkeypatch.setenv("OMPI_COMM_WORLD_RANK", "0")
    assert main(argv) == 0
    assert json.loads((tmp_path / "s.json").read_text())["section"] == "box"
    assert main(["section", "--width", "-1", "--height", "0.5", "--solid"]) == 2
    assert "--width" in capsys.readouterr().err
