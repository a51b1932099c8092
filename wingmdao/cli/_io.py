"""Shared input/output discipline of the ``wingmdao`` commands.

Every command should use these helpers so the command-line contract holds everywhere:

- :func:`write_json` / :func:`write_text_atomic`: results are written to a temporary file in the
  destination folder and renamed over the target (``os.replace``), so a full disk, a crash or
  Ctrl-C never leaves a truncated or emptied result. ``path == "-"`` writes to the real
  standard output.
- :func:`check_output_file` / :func:`check_output_dir`: called *before* a run starts, they raise
  :class:`ValueError` (shown by :func:`wingmdao.cli.main` as one line, exit code 2) for a
  missing parent folder, a read-only folder, a path that is a folder, two outputs on one path,
  or an existing file without ``--overwrite``.
- :func:`stdout_to_stderr`: while a command runs with ``--json -``, :func:`wingmdao.cli.main`
  sends everything printed to ``sys.stdout`` (progress, notes, summaries, optimizer messages)
  to ``sys.stderr``; only :func:`write_json` reaches the real standard output.
- :func:`say`: human text of a command (always standard error when JSON goes to standard
  output, else standard output).
- :data:`EXIT_INTERRUPTED` (130, the shell's 128 + SIGINT) is the exit code of a command
  stopped by Ctrl-C after it saved what it had.
"""

from __future__ import annotations

import contextlib
import json
import os
import sys
import tempfile

import numpy as np

from wingmdao.utils.mpi_env import is_output_rank
from wingmdao.names import WALL_NAMES as WALL_VARS

EXIT_INTERRUPTED = 130
EXIT_FAILED = 1
EXIT_USAGE = 2

_real_stdout = None  # the process's standard output while stdout_to_stderr() is active


def jsonable(obj):
    """``obj`` with NumPy arrays and scalars turned into lists and Python numbers (NaN/inf kept)."""
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


def json_stdout():
    """The stream that JSON for ``--json -`` goes to (the real standard output)."""
    return _real_stdout if _real_stdout is not None else sys.stdout


def write_text_atomic(text: str, path: str) -> None:
    """Write ``text`` to ``path`` atomically: a temporary file in the same folder, flushed and
    fsynced, then ``os.replace`` (the target is either the old file or the complete new one)."""
    if not is_output_rank():  # under mpirun only rank 0 writes
        return
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(path)}.", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, default_file_mode())  # mkstemp makes 0600; a result file gets the usual mode
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


class ResultWriteError(Exception):
    """A result could not be written (full disk, I/O error); the message says where it still is.
    :func:`wingmdao.cli.main` shows it as one line, exit code 1."""


def write_json(data: dict, path: str) -> None:
    """Write ``data`` as JSON to ``path`` atomically (``-`` means the real standard output).

    When the file cannot be written (``OSError``: a full disk, an I/O error) the earlier file stays
    whole, the JSON text goes to standard error so the result is not lost, and
    :class:`ResultWriteError` says so (and names the recording when ``data`` has one)."""
    if not is_output_rank():  # under mpirun only rank 0 writes
        return
    text = json.dumps(jsonable(data), indent=2) + "\n"
    if path == "-":
        out = json_stdout()
        out.write(text)
        out.flush()
        return
    try:
        write_text_atomic(text, path)
    except OSError as exc:
        sys.stderr.write(text)
        sys.stderr.flush()
        where = "the JSON text is on standard error above"
        if isinstance(data, dict) and data.get("recording"):
            where += f"; the run is also in the recording {data['recording']}"
        raise ResultWriteError(f"cannot write --json {path!r} ({exc.strerror or exc}); {where}") from None


def read_json_object(path: str, option: str) -> dict:
    """The JSON object (a dict) in file ``path`` given by ``option`` (e.g. ``"--design"``); ValueError
    naming the option and file when it is missing, a folder, unreadable, not standard JSON (NaN and
    Infinity are refused) or not an object."""
    def _refuse(token):
        raise ValueError(f"{option} {path!r}: {token} is not standard JSON; give finite numbers")

    if os.path.isdir(path):
        raise ValueError(f"{option} {path!r} is a folder; give a JSON file")
    try:
        with open(path, encoding="utf-8") as fh:
            data = json.load(fh, parse_constant=_refuse)
    except FileNotFoundError:
        raise ValueError(f"{option} {path!r}: no such file") from None
    except OSError as exc:
        raise ValueError(f"{option} {path!r}: cannot read it ({exc.strerror or exc})") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"{option} {path!r}: not a JSON file ({exc})") from None
    if not isinstance(data, dict):
        raise ValueError(f"{option} {path!r}: a JSON {type(data).__name__}; a JSON object (a result of "
                         "'wingmdao size') is needed")
    return data


def check_output_file(path: str | None, option: str, *, overwrite: bool = False,
                      others: dict | None = None) -> None:
    """Raise ValueError now if ``path`` (given by ``option``, e.g. ``"--json"``) cannot be written
    later: its parent folder is missing or not writable, it is a folder, it equals one of the
    ``others`` outputs (``{description: path}``), or it exists and ``overwrite`` is false.
    ``None`` and ``"-"`` (standard output) always pass."""
    if not is_output_rank():  # under mpirun rank 0 checks and writes the outputs
        return
    if path is None or path == "-":
        return
    full = os.path.abspath(path)
    if os.path.isdir(full):
        raise ValueError(f"{option} {path!r} is a folder; give a file path")
    parent = os.path.dirname(full)
    if not os.path.isdir(parent):
        raise ValueError(f"{option} {path!r}: folder {parent!r} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ValueError(f"{option} {path!r}: folder {parent!r} is not writable")
    for what, other in (others or {}).items():
        if other and other != "-" and os.path.abspath(other) == full:
            raise ValueError(f"{option} {path!r} is the same file as the {what}; choose another path")
    if os.path.exists(full) and not overwrite:
        raise ValueError(f"{option} {path!r} exists (an earlier run's output); pass --overwrite to "
                         "replace it or choose another path")


def check_json_option(args) -> None:
    """The check :func:`wingmdao.cli.main` makes of every command's ``--json`` before the command
    starts (:func:`check_output_file`, ``--overwrite`` if the command has it); a path inside a
    ``--out`` folder that does not exist yet is left to the command (it creates ``--out`` first)."""
    path = getattr(args, "json", None)
    if path is None or path == "-":
        return
    out = getattr(args, "out", None)
    parent = os.path.dirname(os.path.abspath(path))
    if out and parent == os.path.abspath(out) and not os.path.exists(parent):
        return
    check_output_file(path, "--json", overwrite=getattr(args, "overwrite", False))


def check_output_dir(path: str, option: str, *, create: bool = True) -> None:
    """Raise ValueError now if folder ``path`` (given by ``option``) is a file, is not writable, or
    cannot be created under its nearest existing ancestor; create it when ``create``."""
    if not is_output_rank():  # under mpirun rank 0 checks and writes the outputs
        return
    full = os.path.abspath(path)
    if os.path.exists(full) and not os.path.isdir(full):
        raise ValueError(f"{option} {path!r} is a file, not a folder")
    probe = full
    while not os.path.exists(probe):
        probe = os.path.dirname(probe)
    if not os.path.isdir(probe):
        raise ValueError(f"{option} {path!r}: {probe!r} is a file, not a folder")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise ValueError(f"{option} {path!r}: folder {probe!r} is not writable")
    if create:
        os.makedirs(full, exist_ok=True)


def refuse_existing(paths, *, overwrite: bool, what: str = "output") -> None:
    """Raise ValueError if any of ``paths`` exists and ``overwrite`` is false (an earlier run's
    recording or plots are never replaced silently)."""
    if not is_output_rank():  # under mpirun rank 0 checks and writes the outputs
        return
    if overwrite:
        return
    found = [p for p in paths if p and os.path.exists(p)]
    if found:
        raise ValueError(f"{', '.join(found)} exist(s) from an earlier run ({what}); pass --overwrite "
                         "to replace, or choose another --out folder")


@contextlib.contextmanager
def stdout_to_stderr(enabled: bool = True):
    """While active, ``print()`` to standard output goes to standard error; :func:`write_json`
    with ``-`` still writes to the real standard output."""
    global _real_stdout
    if not enabled or _real_stdout is not None:
        yield
        return
    _real_stdout = sys.stdout
    try:
        with contextlib.redirect_stdout(sys.stderr):
            yield
    finally:
        _real_stdout = None


def say(*parts, **kw) -> None:
    """Print human text of a command (to standard error while JSON goes to standard output)."""
    kw.setdefault("flush", True)
    print(*parts, **kw)


def warn(message: str) -> None:
    """One line ``wingmdao: warning: MESSAGE`` on standard error (rank 0 only under mpirun); the one
    warning format of every command (library warnings too, :func:`wingmdao.cli.main`)."""
    if not is_output_rank():
        return
    print(f"wingmdao: warning: {message}", file=sys.stderr, flush=True)


def default_file_mode() -> int:
    """The mode ``open(path, "w")`` would give a new file: 0666 less the process umask."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def read_design(path, num_nodes=None, case="pegasus", command="flutter") -> dict:
    """Wall thicknesses ``{wall: (n,) m}`` of a ``wingmdao size`` JSON of ``case``; ValueError naming the
    file and what is wrong (missing, not JSON, not a sizing result, another case, wrong number of
    stations, values not finite and > 0)."""
    data = read_json_object(path, "--design")
    thick = data.get("thickness")
    walls = [w[2:] for w in WALL_VARS]
    if not isinstance(thick, dict) or any(w not in thick for w in walls):
        raise ValueError(f"--design {path}: not a box sizing result of 'wingmdao size' (needs a 'thickness' "
                         f"object with {', '.join(walls)} per station, m)")
    if "panels" in data:
        raise ValueError(f"--design {path}: a stiffened sizing result (its stiffeners are part of the sections, "
                         "which this command does not read); its flutter speed is the result's flutter_speed_m_s")
    if data.get("case", case) != case:
        raise ValueError(f"--design {path}: a sizing result of case {data['case']!r}; {command} {case} --design "
                         f"takes {case} results")
    out = {}
    for w in walls:
        v = np.asarray(thick[w], dtype=float).ravel() if isinstance(thick[w], list) else np.zeros(0)
        if num_nodes is not None and v.size != int(num_nodes):
            raise ValueError(f"--design {path}: thickness {w!r} has {v.size} stations; the "
                             f"{num_nodes}-node {case.upper() if case == 'pegasus' else case} beam needs {num_nodes}")
        if not np.all(np.isfinite(v) & (v > 0)):
            raise ValueError(f"--design {path}: thickness {w!r} must hold finite values > 0 m")
        out[w] = v
    return out
