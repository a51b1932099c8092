"""Command-line entry ``wingmdao``.

Each subcommand lives in its own module of this package and exposes
``register(subparsers)``, which adds a parser whose ``func`` attribute is called with the
parsed arguments and returns an exit code. Modules are discovered automatically, so a
discipline adds its command without touching this file.
"""

from __future__ import annotations

import argparse
import importlib
import json
import pkgutil
import sys

import numpy as np

from wingmdao import __version__


def _subcommand_modules():
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if not info.name.startswith("_"):
            yield importlib.import_module(f"{__name__}.{info.name}")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
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


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


def write_json(data: dict, path: str) -> None:
    """Write ``data`` as JSON to ``path`` (``-`` means standard output)."""
    text = json.dumps(_jsonable(data), indent=2)
    if path == "-":
        sys.stdout.write(text + "\n")
    else:
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(text + "\n")


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        return int(args.func(args) or 0)
    except ValueError as exc:  # bad user input: one clear line, no traceback
        print(f"wingmdao {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
