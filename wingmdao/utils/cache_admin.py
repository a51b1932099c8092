"""What the compile cache holds, when each entry was last used, and removing the unused ones.

The cache folder (:func:`wingmdao.utils.casadi_cache.cache_dir`, ``$WINGMDAO_CACHE``) keeps
every compiled CasADi library (``NAME_KEY.so`` with its manifest ``NAME_KEY.so.sha256``), the
compiled C kernels of the march and the adjoint (same layout) and, in ``functions/``, the stored
section, stress and internal-load functions (``NAME_KEY.npz``). Keys follow what defines a
function (builder arguments and the generating sources), so every new version of wingmdao, and
every beam size, adds entries and none is ever replaced: the folder only grows.

An entry's *last use* is the modification time of its manifest (a library) or of its file (a
stored function): :func:`record_use` sets it whenever an entry is loaded. :func:`prune` removes
the entries unused for more than a given number of days, manifest first, so a process that
looks up an entry meanwhile finds it absent (and rebuilds it) rather than half-removed; a
library another process already has open stays valid (POSIX unlink). Leftovers of compiles that
were killed (hidden ``.NAME_KEY.PID...`` files and folders) older than a day go too.
"""

from __future__ import annotations

import os
import shutil
import time
from dataclasses import dataclass
from pathlib import Path

#: temporary files of an unfinished compile are removed once older than this (s)
STALE_PARTIAL_SECONDS = 86400.0


@dataclass(frozen=True)
class CacheEntry:
    """One cache entry: ``kind`` "library" (a compiled .so and its manifest) or "function"
    (a stored function .npz); ``name`` the function's name (without the key); ``files`` its
    files; ``size_bytes``; ``last_used`` (POSIX time, s).

    Parameters
    ----------
    kind : {"library", "function"}
        Entry kind.
    name : str
        Function name, without the key.
    files : tuple
        Its files.
    size_bytes : int
        Total size (bytes).
    last_used : float
        POSIX time of last use (s).
    """

    kind: str
    name: str
    files: tuple
    size_bytes: int
    last_used: float


def record_use(path) -> None:
    """Mark the entry of ``path`` (a library or a stored function) as used now: the manifest's
    (a library's) or the file's (a stored function's) modification time. Best effort: a
    read-only cache is used as it is.

    Parameters
    ----------
    path : str or pathlib.Path
        Library or stored function file.
    """
    path = Path(path)
    target = path.with_name(path.name + ".sha256") if path.suffix == ".so" else path
    try:
        os.utime(target)
    except OSError:
        pass


def _name_of(stem: str) -> str:
    """``NAME`` of ``NAME_KEY`` (the key is the last underscore-separated part)."""
    return stem.rsplit("_", 1)[0] if "_" in stem else stem


def entries(folder) -> list[CacheEntry]:
    """The entries of the cache ``folder`` (none when it does not exist).

    Parameters
    ----------
    folder : str or pathlib.Path
        Cache folder.

    Returns
    -------
    list of CacheEntry
        The entries.
    """
    folder = Path(folder)
    out = []
    if not folder.is_dir():
        return out
    for lib in sorted(folder.glob("*.so")):
        if lib.name.startswith(".") or not lib.is_file():  # a folder named *.so is no entry: left alone
            continue
        man = lib.with_name(lib.name + ".sha256")
        files = (lib, man) if man.exists() else (lib,)
        stamp = (man if man.exists() else lib).stat().st_mtime
        out.append(CacheEntry("library", _name_of(lib.stem), files, sum(f.stat().st_size for f in files), stamp))
    for man in sorted(folder.glob("*.so.sha256")):     # a manifest whose library is gone
        if not man.name.startswith(".") and man.is_file() and not man.with_name(man.name[:-len(".sha256")]).exists():
            out.append(CacheEntry("library", _name_of(man.name[:-len(".so.sha256")]), (man,), man.stat().st_size,
                                  man.stat().st_mtime))
    functions = folder / "functions"
    if functions.is_dir():
        for f in sorted(functions.glob("*.npz")):
            if not f.name.startswith(".") and f.is_file():
                st = f.stat()
                out.append(CacheEntry("function", _name_of(f.stem), (f,), st.st_size, st.st_mtime))
    return out


def partial_files(folder, *, older_than: float = STALE_PARTIAL_SECONDS, now: float | None = None) -> list[Path]:
    """Hidden leftovers of unfinished compiles or writes (``.NAME...`` files and folders) in
    ``folder`` and ``folder/functions`` not modified for ``older_than`` seconds.

    Parameters
    ----------
    folder : str or pathlib.Path
        Cache folder.
    older_than : float, optional
        Age (s) above which a leftover is stale.
    now : float or None, optional
        Current POSIX time (s); None for the clock.

    Returns
    -------
    list of pathlib.Path
        The leftovers.
    """
    now = time.time() if now is None else now
    found = []
    for d in (Path(folder), Path(folder) / "functions"):
        if d.is_dir():
            found += [p for p in sorted(d.glob(".*")) if now - p.stat().st_mtime > older_than]
    return found


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        path.unlink(missing_ok=True)


def prune(folder, unused_days: float, *, dry_run: bool = False, now: float | None = None) -> dict:
    """Remove (``dry_run``: only list) the entries of ``folder`` unused for more than
    ``unused_days`` days and the stale leftovers of :func:`partial_files`. Returns a summary:
    ``entries``, ``size_bytes`` (before), ``unused`` (entries, bytes), ``removed`` (entries,
    bytes, leftovers) and the names of the unused entries.

    Parameters
    ----------
    folder : str or pathlib.Path
        Cache folder.
    unused_days : float
        Age (days) above which an entry is removed.
    dry_run : bool, optional
        Only list what would be removed.
    now : float or None, optional
        Current POSIX time (s); None for the clock.

    Returns
    -------
    dict
        The summary.
    """
    if not (unused_days >= 0.0):
        raise ValueError(f"unused days = {unused_days}; allowed range [0, inf) days")
    now = time.time() if now is None else now
    found = entries(folder)
    unused = [e for e in found if now - e.last_used > unused_days * 86400.0]
    leftovers = partial_files(folder, now=now)
    if not dry_run:
        for e in unused:
            # manifest first: a concurrent lookup then sees no entry, never a library without its check
            for f in sorted(e.files, key=lambda p: not p.name.endswith(".sha256")):
                f.unlink(missing_ok=True)
        for p in leftovers:
            _remove(p)
    unused_bytes = sum(e.size_bytes for e in unused)
    return {
        "folder": str(Path(folder)),
        "unused_days": float(unused_days),
        "entries": len(found),
        "size_bytes": sum(e.size_bytes for e in found),
        "libraries": sum(e.kind == "library" for e in found),
        "functions": sum(e.kind == "function" for e in found),
        "unused_entries": len(unused),
        "unused_bytes": unused_bytes,
        "unused_names": sorted({e.name for e in unused}),
        "removed_entries": 0 if dry_run else len(unused),
        "removed_bytes": 0 if dry_run else unused_bytes,
        "removed_leftovers": 0 if dry_run else len(leftovers),
        "dry_run": bool(dry_run),
    }
