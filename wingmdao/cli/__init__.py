"""Command-line entry ``wingmdao``.

Each subcommand lives in its own module of this package and exposes
``register(subparsers)``, which adds a parser whose ``func`` attribute is called with the
parsed arguments and returns an exit code. Modules are discovered automatically, so a
discipline adds its command without touching this file.
"""

from __future__ import annotations

import argparse
import importlib
import os
import pkgutil
import re
import sys
import warnings

from wingmdao.utils.threads import single_blas_thread_default

single_blas_thread_default()    # one BLAS thread unless the user chose: before NumPy loads (cli._io imports it)

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


def _subcommand_modules():
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if not info.name.startswith("_"):
            yield importlib.import_module(f"{__name__}.{info.name}")


def build_parser() -> argparse.ArgumentParser:
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
    for module in _subcommand_modules():
        module.register(sub)
    return parser


def _show_warning(message, category, filename, lineno, file=None, line=None):
    """A library or framework warning (``warnings.warn``) as the one warning line of every command,
    ``wingmdao: warning: MESSAGE``, instead of Python's two lines with the source file."""
    text = " ".join(str(message).split())
    text = text[len("wingmdao: "):] if text.startswith("wingmdao: ") else text
    warn(text if category is UserWarning else f"{text} ({category.__name__})")


def main(argv=None) -> int:
    parser = build_parser()
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
        with stdout_to_stderr(getattr(args, "json", None) == "-"):
            return int(args.func(args) or 0)
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
    except Exception as exc:
        import openmdao.api as om

        if isinstance(exc, om.AnalysisError):  # a solve failed: say so, no traceback
            print(f"wingmdao {args.command}: error: the analysis failed: {exc}", file=sys.stderr)
            return EXIT_FAILED
        raise


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
