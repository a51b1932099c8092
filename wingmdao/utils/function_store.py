"""Built CasADi functions and sparsity data persisted on disk, keyed by their definition.

Without a store, problem setup rebuilds the same symbolic expressions, Jacobians and sparsity
patterns in every process (0.5 s of a 0.7 s setup of the 21-node wing-box case,
docs/time-marching.md, "Build and setup time"). What a builder produces depends only on its *definition*
(:func:`wingmdao.utils.casadi_cache.definition_key`: builder name and arguments, SHA-256 of the
generating modules' source, CasADi version), so it is stored once under that key:

* ``get(name, key, build)`` returns the data of ``build()`` (a dict of numpy arrays, strings and
  CasADi Functions / Sparsity) from this process's memory, else from
  ``$WINGMDAO_CACHE/functions/NAME_KEY.npz``, else builds and stores it;
* files are written to a temporary name and renamed atomically; a header line carries the
  format, the key and the payload's size and SHA-256, checked before anything is deserialized.
  A truncated, corrupt, stale or foreign file is removed and rebuilt; files and the folder must be
  the user's and not writable by others (as for compiled libraries: a CasADi Function can name
  an external library) or the disk is not used, with one warning;
* CasADi objects are stored with their own ``serialize()``; a deserialized Function holds the
  same instruction list as the built one, so it evaluates bit-identically;
* ``WINGMDAO_FUNCTION_CACHE=0`` disables the disk (in-memory reuse stays).
"""

from __future__ import annotations

import hashlib
import importlib.util
import io
import os
import sys
import threading
from pathlib import Path

import casadi as ca
import numpy as np

from wingmdao.utils.cache_admin import record_use
from wingmdao.utils.casadi_cache import UnsafeCache, cache_dir, check_safe
from wingmdao.utils.warn_once import WarnOnce
import re

ENV_STORE = "WINGMDAO_FUNCTION_CACHE"
_MAGIC = "wingmdao-functions 1"

_MEMORY: dict = {}
#: counters of this process (tests, benchmarks): data served from memory / disk, built
stats = {"memory": 0, "disk": 0, "built": 0}


def store_enabled() -> bool:
    """False when ``WINGMDAO_FUNCTION_CACHE`` is 0/false/no/off."""
    return os.environ.get(ENV_STORE, "1").strip().lower() not in ("0", "false", "no", "off")


def store_dir() -> Path:
    """Folder of the stored functions (``functions`` in the compiled cache).

    Returns
    -------
    pathlib.Path
        The folder.
    """
    return cache_dir() / "functions"


def path_for(name: str, key: str) -> Path:
    """File of the stored functions of ``name`` for definition ``key``.

    Parameters
    ----------
    name : str
        Builder name.
    key : str
        Definition key.

    Returns
    -------
    pathlib.Path
        The file path.
    """
    return store_dir() / f"{name}_{key[:32]}.npz"


_CLOSURES: dict = {}
_FROM_IMPORT = re.compile(r"^\s*from\s+(wingmdao(?:\.\w+)*)\s+import\s+(\([^)]*\)|[\w \t,]+)", re.M)
_IMPORT = re.compile(r"^\s*import\s+(wingmdao(?:\.\w+)*)", re.M)


#: Infrastructure that generates no expressions, left out of :func:`module_closure` (the file
#: format is versioned by the header instead): editing it must not invalidate every definition.
_NOT_GENERATING = frozenset({__name__, "wingmdao.utils.casadi_cache"})


def module_closure(*modules: str) -> tuple:
    """``modules`` and every ``wingmdao`` module they import, transitively (read from their
    source text, imports inside functions included; ``ast`` took 0.2 s), except the caches
    themselves, sorted: the modules whose source defines what a builder in ``modules`` generates.

    Parameters
    ----------
    *modules : str
        Dotted module names.

    Returns
    -------
    tuple of str
        The sorted module names.
    """
    seen, todo = set(_NOT_GENERATING), [m for m in modules if m not in _NOT_GENERATING]
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        if name not in _CLOSURES:
            spec = importlib.util.find_spec(name)
            deps = set()
            if spec is not None and spec.origin and spec.origin.endswith(".py"):
                text = Path(spec.origin).read_text()
                for mod, names in _FROM_IMPORT.findall(text):
                    deps.add(mod)
                    # "from wingmdao.x import y" may import the module wingmdao.x.y
                    deps.update(f"{mod}.{n.split()[0]}" for n in names.strip("()").split(",") if n.split())
                deps.update(_IMPORT.findall(text))
            _CLOSURES[name] = sorted(d for d in deps if d == "wingmdao" or d.startswith("wingmdao.")
                                     and _is_module(d))
        todo.extend(_CLOSURES[name])
    return tuple(sorted(seen - _NOT_GENERATING))


def _is_module(name: str) -> bool:
    mod = sys.modules.get(name)
    if mod is not None:
        return getattr(mod, "__file__", None) is not None
    try:
        return importlib.util.find_spec(name) is not None
    except (ImportError, AttributeError, ValueError):   # e.g. a name imported from a module
        return False


#: the one warning of an unusable function store (the functions are built instead)
_warn_once = WarnOnce("wingmdao: persisted CasADi functions unavailable, building them ({})")


def encode(data: dict) -> bytes:
    """``data`` as npz bytes: arrays as they are, strings as 0-d unicode arrays, CasADi
    Functions and Sparsity as the bytes of their ``serialize()`` text (entry names marked
    ``|F`` / ``|S``).

    Parameters
    ----------
    data : dict
        Arrays, strings, CasADi Functions and Sparsity.

    Returns
    -------
    bytes
        The npz payload.
    """
    arrays = {}
    for k, v in data.items():
        if "|" in k:
            raise ValueError(f"entry name {k!r}: '|' is reserved")
        if isinstance(v, (ca.Function, ca.Sparsity)):
            tag = "F" if isinstance(v, ca.Function) else "S"
            arrays[f"{k}|{tag}"] = np.frombuffer(v.serialize().encode(), dtype=np.uint8)
        else:
            arrays[k] = np.asarray(v)
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def decode(payload: bytes) -> dict:
    """The data of an :func:`encode` payload.

    Parameters
    ----------
    payload : bytes
        Bytes of :func:`encode`.

    Returns
    -------
    dict
        The data.
    """
    out = {}
    with np.load(io.BytesIO(payload), allow_pickle=False) as z:
        for k in z.files:
            v = z[k]
            name, _, tag = k.partition("|")
            if tag == "F":
                v = ca.Function.deserialize(v.tobytes().decode())
            elif tag == "S":
                v = ca.Sparsity.deserialize(v.tobytes().decode())
            elif v.dtype.kind == "U" and v.ndim == 0:
                v = str(v)
            out[name] = v
    return out


def save(path: Path, key: str, data: dict) -> None:
    """Write ``data`` atomically: header ``MAGIC key size sha256`` then the payload.

    Parameters
    ----------
    path : pathlib.Path
        File to write.
    key : str
        Definition key.
    data : dict
        The data.
    """
    payload = encode(data)
    path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    check_safe(path.parent)
    header = f"{_MAGIC} {key} {len(payload)} {hashlib.sha256(payload).hexdigest()}\n".encode()
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
    try:
        with open(tmp, "wb") as fh:
            fh.write(header + payload)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def load(path: Path, key: str) -> dict:
    """The data in ``path``; ``ValueError`` unless its header names this format and ``key`` and
    the payload has the recorded size and SHA-256 (``UnsafeCache`` for foreign files).

    Parameters
    ----------
    path : pathlib.Path
        Stored file.
    key : str
        Definition key it must carry.

    Returns
    -------
    dict
        The data.
    """
    check_safe(path.parent)
    check_safe(path)
    raw = path.read_bytes()
    head, sep, payload = raw.partition(b"\n")
    parts = head.decode(errors="replace").split(" ")
    if not sep or len(parts) != 5 or " ".join(parts[:2]) != _MAGIC:
        raise ValueError(f"{path}: not a wingmdao function file")
    if parts[2] != key:
        raise ValueError(f"{path}: written for another definition")
    if int(parts[3]) != len(payload) or hashlib.sha256(payload).hexdigest() != parts[4]:
        raise ValueError(f"{path}: payload size or SHA-256 differs from its header (truncated or corrupt)")
    data = decode(payload)
    record_use(path)          # its last use, for `wingmdao cache --prune`
    return data


def get(name: str, key: str | None, build) -> dict:
    """``build()``'s data (a dict) for definition ``key``: from memory, disk (see the module
    docs) or built now and stored. ``key=None``: built every time, nothing stored.

    Parameters
    ----------
    name : str
        Builder name.
    key : str or None
        Definition key; None builds every time.
    build : callable
        ``build()`` -> dict.

    Returns
    -------
    dict
        The data.
    """
    if key is None:
        stats["built"] += 1
        return build()
    hit = _MEMORY.get((name, key))
    if hit is not None:
        stats["memory"] += 1
        return hit
    path = path_for(name, key) if store_enabled() else None
    data = None
    if path is not None and path.exists():
        try:
            data = load(path, key)
            stats["disk"] += 1
        except UnsafeCache as exc:      # not ours to delete: leave it, build in memory
            _warn_once(exc)
            path = None
        except Exception:               # noqa: BLE001 - corrupt, stale, foreign format: rebuild
            path.unlink(missing_ok=True)
    if data is None:
        data = build()
        stats["built"] += 1
        if path is not None:
            try:
                save(path, key, data)
            except Exception as exc:    # noqa: BLE001 - a read-only or full disk costs only time
                _warn_once(exc)
    for v in data.values():         # shared by every user of this definition: read-only
        if isinstance(v, np.ndarray):
            v.flags.writeable = False
    _MEMORY[(name, key)] = data
    return data


def clear_memory() -> None:
    """Forget what this process has loaded or built (tests)."""
    _MEMORY.clear()
