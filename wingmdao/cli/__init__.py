"""Command-line entry ``wingmdao``.

Each command has two modules of the same name: its parser, :mod:`wingmdao.cli.parsers`.NAME, whose
``register(subparsers, argv=None)`` adds the command's flags, defaults and help and imports argparse
and light modules only; and its run module, wingmdao.cli.NAME, which imports what it needs at its
top. The parser's ``func`` names the run function, ``"wingmdao.cli.NAME:FUNCTION"``, called with the
parsed arguments; it returns an exit code. :data:`COMMANDS` names each command's module and
one-line help: :func:`main` builds only the parser of the command it runs (or whose help it shows)
and imports the run module only once the command line has parsed, so ``wingmdao --help`` and
``wingmdao COMMAND --help`` start without OpenMDAO or CasADi
(``python benchmarks/bench_cli_startup.py``). A new command is a parser module, a run module and a
line of :data:`COMMANDS`.
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import sys
import warnings
from typing import NamedTuple

from wingmdao.utils.threads import single_blas_thread_default

single_blas_thread_default()    # one BLAS thread unless the user chose: before NumPy loads (cli._io imports it)

from openmdao.core.analysis_error import AnalysisError  # noqa: E402  (the class alone: no OpenMDAO start-up)

from wingmdao import __version__  # noqa: E402
from wingmdao.cli._io import EXIT_FAILED, EXIT_INTERRUPTED, EXIT_USAGE, jsonable as _jsonable  # noqa: E402,F401
from wingmdao.cli._io import ResultWriteError, check_json_option, stdout_to_stderr, warn  # noqa: E402
from wingmdao.utils.mpi_env import is_output_rank  # noqa: E402
from wingmdao.cli._io import write_json  # noqa: E402,F401  (write_json: public API)


class DefaultsHelpFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Adds ``(default: X)`` to every optional argument that takes a value (``(default: unset)``
    when it is None), unless its help already says what the default is (``default`` in the text,
    e.g. "default unset: the case's choice"); required arguments have none, and on/off flags are
    off unless given, so they get no ``(default: False)``."""

    def _get_help_string(self, action):
        text = action.help or ""
        if "default" in text.lower() or action.nargs == 0 or action.required:
            return text
        if action.default is None and (action.option_strings or action.nargs in ("?", "*")):
            return f"{text} (default: unset)"
        return super()._get_help_string(action)


class WingmdaoParser(argparse.ArgumentParser):
    """ArgumentParser that shows defaults in every help text and reads negative numbers in
    exponent notation (``--tip-load -1e6 0 1e7``) as values. Sub-parsers inherit the class."""

    _NEGATIVE = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-inf$|^-nan$", re.IGNORECASE)

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", DefaultsHelpFormatter)
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = self._NEGATIVE


class Command(NamedTuple):
    """A command of :data:`COMMANDS`.

    Parameters
    ----------
    module : str
        The module of this package that runs it; :mod:`wingmdao.cli.parsers` has its parser, of the same name.
    help : str
        Its one-line help (``wingmdao --help``).
    """
    module: str
    help: str


#: The commands, in the order of ``wingmdao --help``: the one home of each one-line help.
COMMANDS = {
    "cache": Command("cache", "show the compile cache (compiled functions, stored functions) and prune unused "
                              "entries"),
    "export": Command("export", "write a sized wing as a CalculiX / Abaqus / Nastran deck"),
    "flutter": Command("flutter", "flutter and divergence speeds, V-g / V-f sweep of a benchmark wing"),
    "gust": Command("gust", "gust response (load factor, root loads, tip deflection), coupled aeroelastic or "
                            "strip loads"),
    "loads": Command("loads", "loads matrix: altitudes x speeds x mass cases, screened; loads database and "
                              "stress cards"),
    "maneuver": Command("maneuver", "dynamic maneuvers: the 14 CFR 25.331(c)(2) checked pitch maneuver (free "
                                    "pitch, elevator) and the 25.349(a) rolling conditions (free roll, ailerons)"),
    "panel": Command("panel", "critical running loads and failure ratios of a stiffened skin panel or spar web "
                              "(JSON)"),
    "report": Command("report", "print the iteration history of a recorded sizing run and write plots"),
    "run": Command("run", "run a shipped analysis case (beam response, stresses) and write JSON"),
    "section": Command("section", "print box (App. F) or solid-rectangle section properties as JSON"),
    "section-fe": Command("section_fe", "6x6 stiffness and mass of an arbitrary cross-section (FE, "
                                        "Giavotto/BECAS) as JSON"),
    "size": Command("size", "size a wingbox case for its load cases (minimum mass, KS stress constraints)"),
    "n2": Command("size", "write the N2 diagram (HTML) of a case's OpenMDAO model"),
    "turbulence": Command("turbulence", "14 CFR 25.341(b) continuous turbulence: A-bar, design loads, "
                                        "correlations"),
    "verify": Command("verify", "cross-check the beam against a CalculiX shell or solid model"),
}


def command_named(argv) -> str | None:
    """The command a command line runs: its first argument that is not an option (the top-level
    options, ``--help`` and ``--version``, take no value), if it is one of :data:`COMMANDS`.

    Parameters
    ----------
    argv : sequence of str
        The arguments after the program name.

    Returns
    -------
    str or None
        The command's name, None without one.
    """
    name = next((a for a in argv if not a.startswith("-")), None)
    return name if name in COMMANDS else None


def build_parser(commands=None, argv=None) -> argparse.ArgumentParser:
    """The ``wingmdao`` parser.

    Parameters
    ----------
    commands : iterable of str, optional
        The commands whose parsers to build (importing their parser modules); the others get a
        parser with their help line only. None: every command.
    argv : sequence of str, optional
        The command line, for the commands whose cases bring their own options (``size CASE``):
        only the named case's are built. None: every case's.

    Returns
    -------
    argparse.ArgumentParser
        The parser.
    """
    parser = WingmdaoParser(
        prog="wingmdao",
        description=(
            "Size aircraft wingboxes for static maneuver and dynamic gust loads with a "
            "nonlinear Timoshenko beam and its time-history adjoint (OpenMDAO). "
            "SI units unless an option names another."
        ),
    )
    parser.add_argument("--version", action="version", version=f"wingmdao {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    modules = {COMMANDS[c].module for c in (COMMANDS if commands is None else commands)}
    for name, command in COMMANDS.items():
        if command.module not in modules:
            sub.add_parser(name, help=command.help, add_help=False)
        elif name == next(n for n, c in COMMANDS.items() if c.module == command.module):
            importlib.import_module(f"{__name__}.parsers.{command.module}").register(sub, argv)  # all of its commands
    return parser


def run_function(func):
    """The function that runs a parsed command: its run module imported now that the command line
    has parsed (argparse has exited on ``--help`` or a usage error before).

    Parameters
    ----------
    func : str or callable
        The parser's ``func``: ``"wingmdao.cli.MODULE:FUNCTION"``, or the function itself.

    Returns
    -------
    callable
        The function, called with the parsed arguments.
    """
    if not isinstance(func, str):
        return func
    module, _, name = func.partition(":")
    return getattr(importlib.import_module(module), name)


def _show_warning(message, category, filename, lineno, file=None, line=None):
    """A library or framework warning (``warnings.warn``) as the one warning line of every command,
    ``wingmdao: warning: MESSAGE``, instead of Python's two lines with the source file."""
    text = " ".join(str(message).split())
    text = text[len("wingmdao: "):] if text.startswith("wingmdao: ") else text
    warn(text if category is UserWarning else f"{text} ({category.__name__})")


def main(argv=None) -> int:
    """Run the command of a command line.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments after the program name (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit code.
    """
    argv = sys.argv[1:] if argv is None else list(argv)
    command = command_named(argv)
    parser = build_parser(() if command is None else (command,), argv)
    root = is_output_rank()
    saved = sys.stdout, sys.stderr, warnings.showwarning
    if not root:  # under mpirun only rank 0 prints (and writes: wingmdao.cli._io); tracebacks still show
        sys.stdout = sys.stderr = open(os.devnull, "w")
    warnings.showwarning = _show_warning
    try:
        return _main(parser, argv)
    finally:
        if not root:
            sys.stdout.close()
        sys.stdout, sys.stderr, warnings.showwarning = saved


def _main(parser, argv) -> int:
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        # every command's --json is checked before it starts (the command adds its own outputs)
        check_json_option(args)
        func = run_function(args.func)
        with stdout_to_stderr(getattr(args, "json", None) == "-"):
            return int(func(args) or 0)
    except ResultWriteError as exc:  # the result was computed but not written: where it still is
        print(f"wingmdao {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_FAILED
    except ValueError as exc:  # bad user input: one clear line, no traceback
        print(f"wingmdao {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except BrokenPipeError:  # e.g. `wingmdao report run.sql | head`: the reader left, not an error
        _silence_stdout()
        return 0
    except KeyboardInterrupt:
        print(f"wingmdao {args.command}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except AnalysisError as exc:  # a solve failed: say so, no traceback
        print(f"wingmdao {args.command}: error: the analysis failed: {exc}", file=sys.stderr)
        return EXIT_FAILED


def _silence_stdout():
    """Point standard output at /dev/null so the interpreter's final flush after a broken pipe
    does not print a second error (Python docs, 'Note on SIGPIPE')."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
