"""Memory and time-step limits of time-history sizing, checked before any solve.

A dynamic load case stores, per time step, the states and the linearization the discrete
adjoint sweep needs (residual Jacobian blocks, parameter and forcing partials) plus the stress
history. Up to the adjoint budget (``time_history.ADJOINT_MEMORY_MB``, 200 MB: ~1060 steps of a
20-node beam at 188 kB of blocks per step) every block is kept; longer histories are checkpointed
(segments re-evaluated in every sweep), so a step costs about half as much beyond that point.
Measured with ``benchmarks/bench_envelope.py rss`` (one PEGASUS gust case, 20 nodes, forward
march + adjoint totals, peak RSS on a 2-core machine; docs/gust-envelope.md): 220 MB at 251
steps, 338 MB at 1001, 487-490 MB at 4001, i.e. 7.9 kB per node-step up to 1001 steps and
2.5 kB per node-step beyond. Each case also costs a fixed part (its CasADi functions, OpenMDAO
variables). :func:`estimate_bytes` uses a 220 MB base, 50 MB per case,
10 kB per node-step up to the full-storage limit and 5 kB per node-step beyond, above every
measurement.

:func:`check_memory` raises a ValueError with the estimate and the largest step count that fits
when the load cases of this process would exceed the memory it can have: MemAvailable of
/proc/meminfo (and the cgroup limit when lower) shared by the MPI ranks of this host, or
``WINGMDAO_MAX_MEMORY_MB``. ``WINGMDAO_SKIP_MEMORY_CHECK=1`` turns the check off.
:func:`march_progress` prints progress of long marches (``WINGMDAO_PROGRESS_STEPS``, default
2000 steps) to standard error.
"""

from __future__ import annotations

import os
import sys
import time

#: per node and time step of a history kept in full storage (states, OpenMDAO vectors, every
#: Jacobian block), and beyond the full-storage limit (checkpointed adjoint)
BYTES_PER_NODE_STEP = 10e3
BYTES_PER_NODE_STEP_CHECKPOINTED = 5e3
#: Jacobian blocks of the adjoint per node and step (188 kB per step of the 20-node beam): with
#: ``time_history.ADJOINT_MEMORY_MB`` they set the step count up to which every block is kept
BLOCK_BYTES_PER_NODE_STEP = 9.4e3
BASE_BYTES = 220e6
#: per load case, static ones included (its CasADi section/stress/internal-load functions, the
#: OpenMDAO variables that do not grow with the steps): 1-3 gust cases of 101 steps took ~70 MB each
#: over 14 design points, 20 MB of which the per-step term covers
PER_CASE_BYTES = 50e6
PROGRESS_STEPS = 2000

#: Default budget (MB) of the Jacobian blocks kept for the adjoint (``adjoint_memory="auto"``):
#: about 1060 steps of a 20-node beam (188 kB per step) or 650 of the coupled aeroelastic one
#: (288-308 kB per step), so 500-step gusts of both keep every block (checkpointing a history
#: evaluates its Jacobians twice: the coupled adjoint cost 1.8-2.3x a structural step with the
#: earlier 100 MB); longer histories are checkpointed in segments of an eighth of the budget.
ADJOINT_MEMORY_MB = 200.0


def full_storage_steps(num_nodes: int) -> int:
    """Steps up to which a history keeps every Jacobian block.

    Parameters
    ----------
    num_nodes : int
        Beam nodes.

    Returns
    -------
    int
        The adjoint budget of :mod:`wingmdao.components.time_history` over
        :data:`BLOCK_BYTES_PER_NODE_STEP` per node.
    """
    return int(ADJOINT_MEMORY_MB * 1e6 // (BLOCK_BYTES_PER_NODE_STEP * max(int(num_nodes), 1)))


def history_bytes(num_nodes: int, steps: int) -> float:
    """Memory of one dynamic case beyond its fixed part.

    Parameters
    ----------
    num_nodes : int
        Beam nodes.
    steps : int
        Time steps of the case.

    Returns
    -------
    float
        Bytes: the full-storage rate up to :func:`full_storage_steps`, the checkpointed rate beyond.
    """
    full = full_storage_steps(num_nodes)
    return num_nodes * (BYTES_PER_NODE_STEP * min(steps, full)
                        + BYTES_PER_NODE_STEP_CHECKPOINTED * max(steps - full, 0))


def estimate_bytes(num_nodes: int, steps) -> float:
    """Peak memory of one process holding load cases.

    Parameters
    ----------
    num_nodes : int
        Beam nodes.
    steps : sequence of int
        Time steps of each load case (1: a static case).

    Returns
    -------
    float
        Estimated peak memory (bytes).
    """
    steps = [int(s) for s in steps]
    return (BASE_BYTES + PER_CASE_BYTES * len(steps)
            + sum(history_bytes(num_nodes, s) for s in steps if s > 1))


def fitting_steps(num_nodes: int, num_cases: int, num_dynamic: int, available: float) -> int:
    """Largest step count per dynamic case whose :func:`estimate_bytes` fits the memory available.

    Parameters
    ----------
    num_nodes : int
        Beam nodes.
    num_cases : int
        Load cases of the process.
    num_dynamic : int
        Dynamic (time-marched) load cases among them.
    available : float
        Memory available (bytes).

    Returns
    -------
    int
        Time steps per dynamic case.
    """
    per_case = (available - BASE_BYTES - PER_CASE_BYTES * num_cases) / max(num_dynamic, 1)
    full = full_storage_steps(num_nodes)
    if per_case <= history_bytes(num_nodes, full):
        return int(per_case // (BYTES_PER_NODE_STEP * num_nodes))
    return full + int((per_case - history_bytes(num_nodes, full)) // (BYTES_PER_NODE_STEP_CHECKPOINTED * num_nodes))


def _meminfo_available() -> float | None:
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        return None
    return None


def _cgroup_limit() -> float | None:
    for path in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            text = open(path, encoding="ascii").read().strip()
        except OSError:
            continue
        if text.isdigit() and int(text) < 1 << 60:
            return float(text)
    return None


def available_bytes() -> float | None:
    """Memory this process may use (bytes), None when unknown."""
    env = os.environ.get("WINGMDAO_MAX_MEMORY_MB")
    if env:
        try:
            value = float(env)
        except ValueError:
            raise ValueError(f"WINGMDAO_MAX_MEMORY_MB = {env!r}; allowed: a number of MB > 0") from None
        if not value > 0:
            raise ValueError(f"WINGMDAO_MAX_MEMORY_MB = {env!r}; allowed: a number of MB > 0")
        return value * 1e6
    vals = [v for v in (_meminfo_available(), _cgroup_limit()) if v]
    if not vals:
        return None
    local = 1
    for var in ("OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS", "PMI_LOCAL_SIZE"):
        if os.environ.get(var, "").isdigit():
            local = max(1, int(os.environ[var]))
            break
    return min(vals) / local


def check_memory(load_cases, num_nodes: int, available: float | None = None) -> float:
    """Check, before any solve, that the load cases fit in memory.

    Parameters
    ----------
    load_cases : sequence of wingmdao.groups.load_case.LoadCase
        The process's load cases (their ``num_times``).
    num_nodes : int
        Beam nodes.
    available : float, optional
        Memory available (bytes); None: :func:`available_bytes`.

    Returns
    -------
    float
        The estimate (bytes).

    Raises
    ------
    ValueError
        The estimate exceeds the memory available.
    """
    steps = [int(c.num_times) for c in load_cases]
    need = estimate_bytes(num_nodes, steps)
    if os.environ.get("WINGMDAO_SKIP_MEMORY_CHECK") == "1":
        return need
    avail = available_bytes() if available is None else float(available)
    if avail is None or need <= avail:
        return need
    dynamic = [s for s in steps if s > 1]
    fit = fitting_steps(num_nodes, len(steps), len(dynamic), avail)
    hint = (f"the largest step count that fits is {fit} steps per dynamic case" if fit > 1 else
            "even one step per case does not fit")
    raise ValueError(
        f"time histories: {len(dynamic)} dynamic case(s) x up to {max(dynamic, default=0)} steps x {num_nodes} "
        f"nodes need an estimated {need / 1e6:.0f} MB ({BASE_BYTES / 1e6:.0f} MB + {PER_CASE_BYTES / 1e6:.0f} MB "
        f"per case + {BYTES_PER_NODE_STEP / 1e3:.0f} kB per node-step up to {full_storage_steps(num_nodes)} steps, "
        f"{BYTES_PER_NODE_STEP_CHECKPOINTED / 1e3:.0f} kB beyond), {avail / 1e6:.0f} MB available; {hint} "
        "(increase --dt, shorten --t-final, spread the cases over MPI ranks, or set WINGMDAO_MAX_MEMORY_MB)")


def march_progress(n_time: int, label: str = "march"):
    """A progress callback for long time marches.

    Parameters
    ----------
    n_time : int
        Time steps of the march.
    label : str, optional
        Name of the march in the progress lines.

    Returns
    -------
    callable or None
        ``callback(step, t, x)`` printing progress every 10 % for marches of
        ``WINGMDAO_PROGRESS_STEPS`` (default 2000) steps or more; None for shorter ones.
    """
    raw = os.environ.get("WINGMDAO_PROGRESS_STEPS", str(PROGRESS_STEPS))
    try:
        threshold = int(raw)
    except ValueError:
        raise ValueError(f"WINGMDAO_PROGRESS_STEPS = {raw!r}; allowed an integer number of time steps "
                         f"(default {PROGRESS_STEPS})") from None
    if n_time < max(threshold, 2):
        return None
    t0 = time.perf_counter()
    every = max(1, (n_time - 1) // 10)

    def callback(step, t, x):
        if step and (step % every == 0 or step == n_time - 1):
            el = time.perf_counter() - t0
            print(f"  {label}: step {step}/{n_time - 1} (t = {t:.4g} s), {el:.1f} s elapsed, "
                  f"~{el * (n_time - 1 - step) / step:.1f} s to go", file=sys.stderr, flush=True)

    return callback
