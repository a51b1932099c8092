"""Common-subexpression elimination (CasADi ``cse``) before the C generation of the Newton functions.

    PYTHONPATH=. python benchmarks/bench_casadi_cse.py                      # all three systems, cse off and on
    PYTHONPATH=. python benchmarks/bench_casadi_cse.py --systems vlm --cse on --mem-limit-gb 8

For the Newton function (residual and Newton matrix dR/dx + alpha dR/dxdot, ``system._newton``)
of three systems: ``strip``, the PEGASUS lone wing with strip theory (20 nodes, free plunge and
trim: the coupled system of ``wingmdao size pegasus --aero coupled --plunge free --aero-theory strip``);
``vlm``, the same with the vortex-lattice loads (``--aero-theory vlm``, the default); ``stick``, the
PEGASUS stick model of the half aircraft (``wingmdao.cases.pegasus_stick.aeroelastic_system``,
1094 unknowns). With ``cse`` off and on (:func:`wingmdao.utils.casadi_cache.codegen_function`) it
prints: the CasADi instruction count, the time of the elimination (CPU), the size of the
generated C (:func:`~wingmdao.utils.casadi_cache.generate_source`), gcc's compile (the project's
command ``gcc -shared -fPIC -O1`` at ``nice -n 10``, one compile at a time, time limit
``--timeout``, 900 s as in ``compile_library``; user+sys CPU, wall, peak memory from
``/usr/bin/time``; ``--mem-limit-gb`` caps its address space), one interpreted call and one compiled call (CPU,
best of ``--calls`` batches of about 20 ms, the cse modes interleaved). Last column: the largest difference between the
outputs with and without cse on a random state, relative to the largest output (must be below
1e-12).
"""

from __future__ import annotations

import argparse
import os
import shutil
import signal
import subprocess
import tempfile
import time
from pathlib import Path

import casadi as ca
import numpy as np

from wingmdao.utils import casadi_cache as cc
from wingmdao.utils.casadi_cache import FastCall


def _system(name):
    if name == "stick":
        from wingmdao.cases import pegasus_stick

        return pegasus_stick.aeroelastic_system(pegasus_stick.build())
    from wingmdao.aero.system import build_aeroelastic_system

    return build_aeroelastic_system(20, plunge=True, trim=True, aero_theory=name)


def _inputs(fun, seed=0):
    """A random point: states and rates ~ N(0, 0.1), parameters and forcing in (0.1, 0.5) (a Mach number below 1)."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(fun.n_in()):
        n = fun.nnz_in(i)
        out.append(rng.normal(scale=0.1, size=n) if i < 2 else rng.uniform(0.1, 0.5, size=n))
    return out


def _best_call(fun, args, calls):
    """CPU time of one call: best of ``calls`` batches of about 20 ms each, per call."""
    fc = FastCall(fun, copy_outputs=False)
    t0 = time.process_time()
    fc(*args)
    batch = max(1, int(0.02 / max(time.process_time() - t0, 1e-6)))
    best = np.inf
    for _ in range(calls):
        t0 = time.process_time()
        for _ in range(batch):
            fc(*args)
        best = min(best, (time.process_time() - t0) / batch)
    return best


def _compile(src, timeout, mem_limit_gb):
    """gcc of ``src`` as compile_library runs it; (status, user+sys s, wall s, peak MB, library)."""
    lib = src.with_suffix(".so")
    cmd = ["/usr/bin/time", "-f", "%U %S %e %M", "nice", "-n", "10", cc.compiler(), "-shared", "-fPIC",
           *cc.DEFAULT_FLAGS, src.name, "-o", lib.name]
    if mem_limit_gb:
        cmd = ["prlimit", f"--as={int(mem_limit_gb * 2**30)}", *cmd]
    proc = subprocess.Popen(cmd, cwd=src.parent, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        _, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)      # gcc and cc1 too, not only the time wrapper
        proc.communicate()
        return f"> {timeout:.0f} s wall", np.nan, np.nan, np.nan, None
    u, s, e, m = err.strip().splitlines()[-1].split()
    status = "ok" if proc.returncode == 0 and lib.exists() else f"failed ({proc.returncode})"
    return status, float(u) + float(s), float(e), int(m) / 1024, lib if status == "ok" else None


def measure(name, cse_modes, compile_, timeout, mem_limit_gb, calls):
    """Rows of the table for system ``name``.

    Parameters
    ----------
    name : str
        ``strip``, ``vlm`` or ``stick``.
    cse_modes : sequence of bool
        cse off and/or on.
    compile_ : bool
        Run gcc.
    timeout : float
        gcc time limit (s).
    mem_limit_gb : float or None
        gcc address-space limit (GB).
    calls : int
        Interpreted calls timed (best taken).

    Returns
    -------
    list of dict
        One row per mode.
    """
    t0 = time.process_time()
    fun = _system(name)._newton
    build = time.process_time() - t0
    args = _inputs(fun)
    ref = [o.copy() for o in FastCall(fun)(*args)]
    rows, funs = [], []
    tmp = Path(tempfile.mkdtemp(prefix="bench_cse_"))
    try:
        for cse in cse_modes:
            t0 = time.process_time()
            gen = cc.codegen_function(fun, cse)
            t_cse = time.process_time() - t0
            vals = FastCall(gen)(*args)
            assert all(np.isfinite(o).all() for o in ref), f"{name}: non-finite outputs at the random point"
            diff = max(np.max(np.abs(a - b)) / max(np.max(np.abs(a)), 1e-300) for a, b in zip(ref, vals))
            src = cc.generate_source(fun, tmp / f"{fun.name()}_{'cse' if cse else 'plain'}.c", cse)
            row = dict(system=name, cse="on" if cse else "off", build=build, instructions=gen.n_instructions(),
                       t_cse=t_cse if cse else 0.0, c_mb=src.stat().st_size / 1e6, diff=diff,
                       status="-", cpu=np.nan, wall=np.nan, peak_mb=np.nan, interp_ms=np.inf, compiled_ms=np.inf)
            ext = None
            if compile_:
                status, cpu, wall, peak, lib = _compile(src, timeout, mem_limit_gb)
                row.update(status=status, cpu=cpu, wall=wall, peak_mb=peak)
                if lib is not None:
                    ext = ca.external(fun.name(), str(lib))
            rows.append(row)
            funs.append((gen, ext))
        for _ in range(calls):      # the modes interleaved: both see the same machine load
            for row, (gen, ext) in zip(rows, funs):
                row["interp_ms"] = min(row["interp_ms"], _best_call(gen, args, 1) * 1e3)
                if ext is not None:
                    row["compiled_ms"] = min(row["compiled_ms"], _best_call(ext, args, 1) * 1e3)
        for row in rows:
            print_row(row)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return rows


HEADER = ("system", "cse", "instructions", "cse s", "C MB", "gcc", "gcc CPU s", "gcc wall s", "gcc peak MB",
          "interp. ms", "compiled ms", "rel. diff")


def print_row(r):
    """Print one row of the table (the header first)."""
    if not getattr(print_row, "done", False):
        print(" | ".join(HEADER))
        print_row.done = True
    print(f"{r['system']} | {r['cse']} | {r['instructions']} | {r['t_cse']:.1f} | {r['c_mb']:.1f} | {r['status']} | "
          f"{r['cpu']:.0f} | {r['wall']:.0f} | {r['peak_mb']:.0f} | {r['interp_ms']:.2f} | "
          f"{r['compiled_ms'] if np.isfinite(r['compiled_ms']) else np.nan:.3f} | "
          f"{r['diff']:.1e}", flush=True)


def main(argv=None):
    """Command line (see the module docstring)."""
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--systems", nargs="+", default=["strip", "stick", "vlm"], choices=["strip", "vlm", "stick"])
    ap.add_argument("--cse", choices=["both", "on", "off"], default="both")
    ap.add_argument("--no-compile", action="store_true", help="skip gcc")
    ap.add_argument("--timeout", type=float, default=900.0, help="gcc time limit (s), default 900")
    ap.add_argument("--mem-limit-gb", type=float, default=None, help="gcc address-space limit (GB)")
    ap.add_argument("--calls", type=int, default=10, help="timed batches per function (best taken)")
    args = ap.parse_args(argv)
    modes = {"both": (False, True), "on": (True,), "off": (False,)}[args.cse]
    rows = []
    for name in args.systems:
        rows += measure(name, modes, not args.no_compile, args.timeout, args.mem_limit_gb, args.calls)
    bad = [r for r in rows if not r["diff"] < 1e-12]
    if bad:
        raise SystemExit(f"outputs with and without cse differ: {[(r['system'], r['diff']) for r in bad]}")


if __name__ == "__main__":
    main()
