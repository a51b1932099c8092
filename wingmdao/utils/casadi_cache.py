"""Compiled CasADi functions: C code generation + gcc, cached on disk, compiled in the background.

CasADi's virtual machine evaluates the beam's big SX functions (residual, Newton matrix,
Jacobian history) 4-20x slower than the same expressions compiled to C (docs/time-marching.md,
"Compiled functions"). Compiling the largest ones takes tens of seconds at -O1, so:

* the shared library is cached, keyed by a SHA-256 of the function's serialized form, the CasADi
  version and the compiler flags, in ``$WINGMDAO_CACHE`` (default ``~/.cache/wingmdao/casadi``);
  a cache hit costs a hash and a ``dlopen``;
* :class:`JitFunction` starts compiling only once a function has been evaluated often
  (``threshold`` evaluations: long marches and optimizations, not short analyses), in a
  background thread running gcc in a subprocess, and switches to the compiled code when it is
  ready; until then (and whenever gcc is missing or fails, with one warning) the interpreted
  function is used. Results are identical to round-off (same expression graph).
* ``WINGMDAO_JIT=0`` disables all of it.

Libraries are written to a temporary name and renamed atomically, so concurrent processes can
share the cache. Next to each library, a manifest ``NAME.so.sha256`` (written before the library
is moved into place) holds its size and SHA-256; before every ``dlopen`` the library's size and
hash are checked against it, so a truncated or corrupt file (full disk, killed copy) is rebuilt
instead of crashing the process with SIGBUS. Only libraries owned by the current user, in a folder
owned by the user and not writable by group or others, are loaded (a shared library runs with the
user's rights); otherwise the cache is not used, with one warning. gcc runs detached: a compile still running when the program ends finishes on
its own (in well under a minute) and the next run finds the library.
"""

from __future__ import annotations

import hashlib
import os
import shlex
import stat
import sys
import shutil
import signal
import subprocess
import tempfile
import threading
import warnings
from pathlib import Path

import casadi as ca
import numpy as np

ENV_CACHE = "WINGMDAO_CACHE"
ENV_JIT = "WINGMDAO_JIT"
#: Compiler flags: -O1 is 10-20x faster than the CasADi VM on the beam functions; -O2/-O3 compile
#: much longer for little more.
DEFAULT_FLAGS = ("-O1",)

_warned = False


class CompileError(RuntimeError):
    """Code generation or compilation of a CasADi function failed."""


class UnsafeCache(CompileError):
    """The cache folder or a library in it is not owned by the user or writable by others."""


def jit_enabled() -> bool:
    """False when the environment variable ``WINGMDAO_JIT`` is 0/false/no/off."""
    return os.environ.get(ENV_JIT, "1").strip().lower() not in ("0", "false", "no", "off")


def cache_dir() -> Path:
    """Folder of the compiled libraries (``$WINGMDAO_CACHE`` or ``~/.cache/wingmdao/casadi``)."""
    env = os.environ.get(ENV_CACHE)
    return Path(env).expanduser() if env else Path.home() / ".cache" / "wingmdao" / "casadi"


def compiler() -> str | None:
    """Path of the C compiler (``$CC`` or gcc), or None."""
    return shutil.which(os.environ.get("CC", "gcc"))


def function_key(fun: ca.Function, flags=DEFAULT_FLAGS) -> str:
    """SHA-256 over the serialized function, the CasADi version and the flags."""
    h = hashlib.sha256()
    h.update(fun.serialize().encode())
    h.update(ca.__version__.encode())
    h.update(" ".join(flags).encode())
    return h.hexdigest()[:32]


def library_path(fun: ca.Function, flags=DEFAULT_FLAGS, key: str | None = None) -> Path:
    return cache_dir() / f"{fun.name()}_{key or function_key(fun, flags)}.so"


def manifest_path(path: Path) -> Path:
    """The manifest (``size sha256``) of library ``path``."""
    return path.with_name(path.name + ".sha256")


def file_digest(path: Path) -> tuple[int, str]:
    """``(size in bytes, SHA-256 hex)`` of ``path``."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return os.path.getsize(path), h.hexdigest()


def check_safe(path: Path) -> None:
    """Raise :class:`UnsafeCache` unless ``path`` (file or folder) is owned by the current user and
    not writable by group or others (POSIX; no check where there are no user ids)."""
    if not hasattr(os, "getuid"):  # pragma: no cover - Windows
        return
    st = os.stat(path)
    if st.st_uid != os.getuid():
        raise UnsafeCache(f"{path} is owned by user id {st.st_uid}, not by you ({os.getuid()})")
    if st.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
        raise UnsafeCache(f"{path} is writable by group or others (mode {stat.filemode(st.st_mode)})")


def verify(path: Path) -> None:
    """Check library ``path`` before it is loaded: folder, library and manifest safe
    (:func:`check_safe`), size and SHA-256 equal to the manifest written at compile time.
    Raises :class:`UnsafeCache` or :class:`CompileError`."""
    man = manifest_path(path)
    for p in (path.parent, path):
        check_safe(p)
    if not man.exists():
        raise CompileError(f"{path}: no manifest {man.name} (an old or foreign library)")
    check_safe(man)
    try:
        size, digest = man.read_text().split()
        size = int(size)
    except ValueError as exc:
        raise CompileError(f"{man}: unreadable manifest") from exc
    if os.path.getsize(path) != size:
        raise CompileError(f"{path}: {os.path.getsize(path)} bytes, compiled as {size} (truncated or corrupt)")
    if file_digest(path)[1] != digest:
        raise CompileError(f"{path}: SHA-256 differs from the one recorded at compile time")


def load(fun: ca.Function, path: Path) -> ca.Function:
    """The compiled library at ``path`` (verified with :func:`verify`) as a CasADi Function with
    ``fun``'s signature."""
    verify(path)
    ext = ca.external(fun.name(), str(path))
    if ext.n_in() != fun.n_in() or ext.n_out() != fun.n_out():
        raise CompileError(f"{path}: signature differs from {fun.name()}")
    for i in range(fun.n_in()):
        if ext.sparsity_in(i) != fun.sparsity_in(i):
            raise CompileError(f"{path}: input {i} sparsity differs from {fun.name()}")
    for i in range(fun.n_out()):
        if ext.sparsity_out(i) != fun.sparsity_out(i):
            raise CompileError(f"{path}: output {i} sparsity differs from {fun.name()}")
    return ext


def compile_library(fun: ca.Function, flags=DEFAULT_FLAGS, key: str | None = None,
                    timeout: float = 900.0) -> Path:
    """Generate C for ``fun``, compile it into the cache and return the library path.

    gcc runs detached (own session, output to a log file) from a shell that also moves the
    library into place: a compile still running when Python exits finishes on its own and
    fills the cache for the next run.
    """
    cc = compiler()
    if cc is None:
        raise CompileError("no C compiler (gcc) on PATH")
    target = library_path(fun, flags, key)
    if target.exists():
        return target
    target.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    check_safe(target.parent)  # never compile into (and later load from) a folder others can write
    stem = f".{target.stem}.{os.getpid()}.{threading.get_ident()}"
    src, partial, log = (target.with_name(stem + ext) for ext in (".c", ".so", ".log"))
    with tempfile.TemporaryDirectory(prefix="wingmdao_jit_") as tmp:
        gen = ca.CodeGenerator(fun.name(), {"with_header": False})
        gen.add(fun)
        gen.generate(str(Path(tmp)) + os.sep)
        shutil.move(str(Path(tmp) / f"{fun.name()}.c"), src)
    # at low priority: compiles run in the background of an optimization and must not slow it
    nice = ["nice", "-n", "10"] if shutil.which("nice") else []
    compile_cmd = " ".join(shlex.quote(a) for a in [*nice, cc, "-shared", "-fPIC", *flags, str(src), "-o",
                                                    str(partial)])
    # the mv is atomic on one file system: readers see the whole library or none
    # the manifest (size and SHA-256 of the finished library) is in place before the library
    man, man_partial = manifest_path(target), target.with_name(stem + ".sha256")
    digest = ("import hashlib, os, sys; p = sys.argv[1]; open(sys.argv[2], 'w').write('%d %s\\n' % "
              "(os.path.getsize(p), hashlib.sha256(open(p, 'rb').read()).hexdigest()))")
    manifest_cmd = " ".join(shlex.quote(a) for a in [sys.executable, "-c", digest, str(partial), str(man_partial)])
    script = (f"{compile_cmd} && {manifest_cmd} && mv -f {shlex.quote(str(man_partial))} {shlex.quote(str(man))} "
              f"&& mv -f {shlex.quote(str(partial))} {shlex.quote(str(target))} "
              f"&& rm -f {shlex.quote(str(log))}; "   # the log is kept only when gcc failed
              f"status=$?; rm -f {shlex.quote(str(src))} {shlex.quote(str(partial))} "
              f"{shlex.quote(str(man_partial))}; exit $status")
    with open(log, "w") as log_file:
        proc = subprocess.Popen(["sh", "-c", script], stdin=subprocess.DEVNULL, stdout=log_file,
                                stderr=subprocess.STDOUT, start_new_session=True)
    try:
        proc.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        raise CompileError(f"compiling {fun.name()} took more than {timeout} s")
    err = log.read_text(errors="replace") if log.exists() else ""
    log.unlink(missing_ok=True)
    if proc.returncode != 0 or not target.exists():
        raise CompileError(f"gcc failed on {fun.name()}: {err.strip()[-300:]}")
    return target


def cached(fun: ca.Function, flags=DEFAULT_FLAGS, key: str | None = None) -> ca.Function | None:
    """The compiled version of ``fun`` if it is in the cache and loads, else None. A library that
    does not load (corrupt, foreign) is removed, so the next compile rebuilds it."""
    path = library_path(fun, flags, key)
    if not path.exists():
        return None
    try:
        return load(fun, path)
    except UnsafeCache as exc:  # not ours to delete: leave it, warn, run interpreted
        _warn_once(exc)
        return None
    except Exception:       # noqa: BLE001
        path.unlink(missing_ok=True)
        manifest_path(path).unlink(missing_ok=True)
        return None


def compiled(fun: ca.Function, flags=DEFAULT_FLAGS) -> ca.Function:
    """``fun`` compiled now (from the cache when present); ``fun`` itself if that fails."""
    if not jit_enabled():
        return fun
    try:
        key = function_key(fun, flags)
        hit = cached(fun, flags, key)
        return hit if hit is not None else load(fun, compile_library(fun, flags, key))
    except Exception as exc:    # noqa: BLE001 - any failure falls back to the interpreted function
        _warn_once(exc)
        return fun


def _warn_once(exc):
    global _warned
    if not _warned:
        _warned = True
        warnings.warn(f"wingmdao: CasADi compilation unavailable, using the interpreted functions ({exc})",
                      RuntimeWarning, stacklevel=3)


class JitFunction:
    """A CasADi function that switches itself to compiled C after ``threshold`` evaluations.

    ``current`` is the function to call; :meth:`count` records evaluations and, at the threshold,
    loads the cached library or starts a background compile; :meth:`poll` (cheap, call it
    between evaluations) returns True once when the compiled function has replaced ``current``.
    """

    def __init__(self, fun: ca.Function, threshold: int = 2000, flags=DEFAULT_FLAGS):
        self.interpreted = fun
        self.current = fun
        self.threshold = threshold
        self.flags = tuple(flags)
        self.evaluations = 0
        self.state = "interpreted"   # -> "compiling" -> "compiled" | "failed" | "disabled"
        self._ready = None
        self._thread = None
        self._key = None              # function_key, computed once (0.3 s for the largest)

    def key(self) -> str:
        if self._key is None:
            self._key = function_key(self.interpreted, self.flags)
        return self._key

    def count(self, n: int = 1) -> None:
        """Record ``n`` evaluations. At the first, a library already in the cache is loaded (a
        warm cache serves from the start); at ``threshold``, compilation starts."""
        first = self.evaluations == 0
        self.evaluations += n
        if self.state != "interpreted":
            return
        if first and jit_enabled():
            self._load_cached()
        if self.state == "interpreted" and self.evaluations >= self.threshold:
            self.start()

    def _load_cached(self) -> bool:
        hit = cached(self.interpreted, self.flags, self.key())
        if hit is None:
            return False
        self._ready, self.state = hit, "compiling"
        return True

    def start(self, wait: bool = False) -> None:
        """Load from the cache or compile (in the background unless ``wait``)."""
        if self.state not in ("interpreted", "compiling"):
            return
        if not jit_enabled() or compiler() is None:
            self.state = "disabled"
            return
        if self.state == "interpreted":
            if self._load_cached():
                return
            self.state = "compiling"
            self._thread = threading.Thread(target=self._compile, daemon=True,
                                            name=f"jit-{self.interpreted.name()}")
            self._thread.start()
        if wait and self._thread is not None:
            self._thread.join()

    def _compile(self):
        try:
            path = compile_library(self.interpreted, self.flags, self.key())
            self._ready = load(self.interpreted, path)
        except Exception as exc:    # noqa: BLE001
            _warn_once(exc)
            self.state = "failed"

    def poll(self) -> bool:
        if self._ready is not None:
            self.current, self._ready = self._ready, None
            self.state = "compiled"
            return True
        return False


class FastCall:
    """Evaluate a CasADi function through preallocated buffers (~0.2 us instead of ~40 us a call).

    ``inp``/``out`` are the buffers (flat nonzeros); ``eval()`` evaluates in place. With
    ``copy_outputs=False`` a call returns the output buffers themselves (overwritten next call).
    """

    def __init__(self, fun: ca.Function, copy_outputs=True):
        self.fun = fun
        self.copy_outputs = copy_outputs
        self.inp = [np.zeros(fun.nnz_in(i)) for i in range(fun.n_in())]
        self.out = [np.zeros(fun.nnz_out(i)) for i in range(fun.n_out())]
        self.buf, self.eval = fun.buffer()
        for i, a in enumerate(self.inp):
            self.buf.set_arg(i, memoryview(a))
        for i, a in enumerate(self.out):
            self.buf.set_res(i, memoryview(a))

    def __call__(self, *args):
        for dst, src in zip(self.inp, args):
            dst[:] = np.ravel(src)
        self.eval()
        return [o.copy() for o in self.out] if self.copy_outputs else self.out


class JitCall:
    """A :class:`FastCall` whose function turns into compiled C after ``threshold`` evaluations
    (:class:`JitFunction`). Call :meth:`refresh` before using ``fast`` directly."""

    def __init__(self, fun: ca.Function, threshold: int, copy_outputs=True):
        self.jit = JitFunction(fun, threshold)
        self.fast = FastCall(fun, copy_outputs)

    def refresh(self) -> FastCall:
        """The current evaluator (switched to the compiled function once that is ready)."""
        if self.jit.poll():
            self.fast = FastCall(self.jit.current, self.fast.copy_outputs)
        return self.fast

    def __call__(self, *args):
        fast = self.refresh()
        self.jit.count()
        return fast(*args)


def compile_calls(calls: dict, wait: bool = True) -> dict:
    """Compile (or load from the cache) every :class:`JitCall` of ``{name: call}`` now.

    All compiles start first, so gcc runs them in parallel; with ``wait`` this returns once they
    have finished and the calls use them. Returns ``{name: state}`` (see :class:`JitFunction`).
    """
    for call in calls.values():
        call.jit.start(wait=False)
    for call in calls.values():
        if wait:
            call.jit.start(wait=True)
        call.refresh()
    return {name: call.jit.state for name, call in calls.items()}
