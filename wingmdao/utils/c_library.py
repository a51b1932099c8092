"""Hand-written C sources of the package compiled once with gcc, cached and loaded with ctypes.

The sibling of :mod:`wingmdao.utils.casadi_cache` for plain C files (the static-pivot LU kernel
``wingmdao/timemarch/lu_kernel.c``, the compiled march ``wingmdao/timemarch/bdf_step.c``), with its cache folder and its safety rules: the library is
keyed by a SHA-256 of the source, the flags and the compiler; compiled from a source of one fixed
name (gcc writes the file name into the library, so concurrent compiles give identical bytes),
to a temporary name; its manifest (size and SHA-256, :func:`casadi_cache.verify`) is written
before the library is renamed into place atomically; a library that fails the check is rebuilt.
``WINGMDAO_JIT=0`` or a missing compiler: :func:`load` returns None (callers use their
pure-Python path, without a warning); a failing compiler warns once.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import re
import shutil
import subprocess
import threading
from pathlib import Path

from wingmdao.utils import casadi_cache as cc
from wingmdao.utils.cache_admin import record_use
from wingmdao.utils.warn_once import WarnOnce

#: Flags of the kernels: small sources, so -O3 costs little compile time; no FMA contraction, so the kernels
#: round like the NumPy code they replace.
C_FLAGS = ("-O3", "-ffp-contract=off")

_LOADED: dict = {}
#: the one warning of a kernel that does not compile or load (the callers' fallback is used)
_warn_once = WarnOnce("wingmdao: C kernel {} unavailable, using the fallback ({})")
_lock = threading.Lock()


#: a kernel's include of another file of the package (``#include "path"``, relative to the kernel)
_LOCAL_INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]*"([^"]+)"[ \t]*$', re.M)


def expanded_source(source: Path) -> bytes:
    """The C file ``source`` with each ``#include "path"`` (a file of the package, relative to
    ``source``; one level) replaced by that file's text: what is compiled and what keys the
    library, so a shared header such as ``timemarch/lu_triangular.h`` recompiles every kernel
    that includes it.

    Parameters
    ----------
    source : pathlib.Path
        Path of the C file.

    Returns
    -------
    bytes
        The source text with the local includes inserted.
    """
    source = Path(source)
    text = source.read_text()

    def insert(m):
        return f"/* {m.group(1)} */\n" + (source.parent / m.group(1)).read_text()

    return _LOCAL_INCLUDE.sub(insert, text).encode()


def library_key(source: Path, flags=C_FLAGS) -> str:
    """SHA-256 (32 hex digits) of the expanded source (:func:`expanded_source`), the flags and the
    compiler path.

    Parameters
    ----------
    source : pathlib.Path
        Path of the C file.
    flags : tuple of str, optional
        Compiler flags (default :data:`C_FLAGS`).

    Returns
    -------
    str
        The first 32 hex digits of the SHA-256.
    """
    h = hashlib.sha256(expanded_source(source))
    h.update(b"\0" + " ".join(flags).encode() + b"\0" + str(cc.compiler()).encode())
    return h.hexdigest()[:32]


def compile_source(source: Path, name: str, flags=C_FLAGS, timeout: float = 120.0) -> Path:
    """The cached shared library of the C file ``source`` (compiled now if absent or corrupt).

    Parameters
    ----------
    source : pathlib.Path
        Path of the C file.
    name : str
        Stem of the library's file name in the cache folder.
    flags : tuple of str, optional
        Compiler flags (default :data:`C_FLAGS`).
    timeout : float, optional
        Maximum compile time (s).

    Returns
    -------
    pathlib.Path
        Path of the verified shared library.

    Raises
    ------
    wingmdao.utils.casadi_cache.CompileError
        With no compiler, when gcc fails or exceeds ``timeout``.
    """
    gcc = cc.compiler()
    if gcc is None:
        raise cc.CompileError("no C compiler (gcc) on PATH")
    target = cc.cache_dir() / f"{name}_{library_key(source, flags)}.so"
    if target.exists():
        try:
            cc.verify(target)
            return target
        except cc.UnsafeCache:
            raise
        except cc.CompileError:          # truncated or foreign: rebuild
            target.unlink(missing_ok=True)
            cc.manifest_path(target).unlink(missing_ok=True)
    target.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    cc.check_safe(target.parent)
    stem = f".{target.stem}.{os.getpid()}.{threading.get_ident()}"
    partial, man_partial = target.with_name(stem + ".so"), target.with_name(stem + ".sha256")
    src_dir = target.with_name(stem + ".d")
    src_dir.mkdir(mode=0o700)
    try:
        (src_dir / f"{target.stem}.c").write_bytes(expanded_source(source))
        proc = subprocess.run([gcc, "-shared", "-fPIC", *flags, f"{target.stem}.c", "-o", str(partial.absolute()),
                               "-lm"], cwd=src_dir, stdin=subprocess.DEVNULL, capture_output=True,
                              text=True, timeout=timeout)
        if proc.returncode != 0 or not partial.exists():
            raise cc.CompileError(f"gcc failed on {source.name}: {(proc.stderr or proc.stdout).strip()[-300:]}")
        size, digest = cc.file_digest(partial)
        man_partial.write_text(f"{size} {digest}\n")
        os.replace(man_partial, cc.manifest_path(target))   # manifest first, then the library
        os.replace(partial, target)
    except subprocess.TimeoutExpired as exc:
        raise cc.CompileError(f"compiling {source.name} took more than {timeout} s") from exc
    finally:
        shutil.rmtree(src_dir, ignore_errors=True)
        partial.unlink(missing_ok=True)
        man_partial.unlink(missing_ok=True)
    return target


def open_compiled(source: Path, name: str, flags=C_FLAGS) -> tuple:
    """``ctypes.CDLL`` of the compiled ``source``: from the cache (verified against its manifest),
    else compiled into it. A cached library that verifies but does not load (a foreign or damaged
    file whose manifest was rewritten to match) is removed and rebuilt once, not left for the
    fallback of every later run.

    Parameters
    ----------
    source : pathlib.Path
        Path of the C file.
    name : str
        Stem of the library's file name in the cache folder.
    flags : tuple of str, optional
        Compiler flags (default :data:`C_FLAGS`).

    Returns
    -------
    tuple
        ``(ctypes.CDLL, pathlib.Path)``: the opened library and its path.

    Raises
    ------
    wingmdao.utils.casadi_cache.CompileError
        With no compiler, when gcc fails, or the cache is not safe.
    OSError
        When the rebuilt library does not load either.
    """
    path = compile_source(Path(source), name, flags)
    cc.verify(path)
    try:
        return ctypes.CDLL(str(path)), path
    except OSError:
        path.unlink(missing_ok=True)
        cc.manifest_path(path).unlink(missing_ok=True)
    path = compile_source(Path(source), name, flags)
    return ctypes.CDLL(str(path)), path


def load(source: Path, name: str, flags=C_FLAGS, force: bool = False):
    """``ctypes.CDLL`` of the compiled ``source`` (once per process and cache folder), or None
    when compilation is off (``WINGMDAO_JIT=0``, unless ``force``), there is no compiler, or it
    fails (one warning).

    Parameters
    ----------
    source : pathlib.Path
        Path of the C file.
    name : str
        Stem of the library's file name in the cache folder.
    flags : tuple of str, optional
        Compiler flags (default :data:`C_FLAGS`).
    force : bool, optional
        Compile even when ``WINGMDAO_JIT=0``.

    Returns
    -------
    ctypes.CDLL or None
        The loaded library, or None.
    """
    if not (force or cc.jit_enabled()) or cc.compiler() is None:
        return None
    key = (str(Path(source).resolve()), name, tuple(flags), str(cc.cache_dir()))
    with _lock:
        if key in _LOADED:
            return _LOADED[key]
        try:
            lib, path = open_compiled(source, name, flags)
            record_use(path)      # its last use, for `wingmdao cache --prune`
        except Exception as exc:    # noqa: BLE001 - any failure: the caller's fallback
            _warn_once(name, exc, stacklevel=3)
            lib = None
        _LOADED[key] = lib
        return lib
