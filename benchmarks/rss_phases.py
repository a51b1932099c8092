"""Resident memory of a ``wingmdao`` command phase by phase (docs/gust-envelope.md, "The whole command").

    OPENBLAS_NUM_THREADS=1 python benchmarks/rss_phases.py size pegasus --loads gust --t-final 20 --dt 0.005 --maxiter 1 \\
        --presize 0 --no-plots --json /tmp/x.json --overwrite --quiet

Runs the command in this process with a thread sampling the resident set (``/proc/self/statm``,
every 50 ms) and marks at the start and end of ``build_problem``, ``presize_and_size``,
``summarize``, ``release_derivative_storage`` and ``flutter_search``; prints the peak, the RSS at
each mark and the peak between marks; ``flutter_search`` runs after the sizing problem is freed.
Linux only (``/proc``). This script imports ``wingmdao.sizing`` before the command, which the
``wingmdao`` command does not (it sets one BLAS thread before NumPy loads): set
``OPENBLAS_NUM_THREADS=1`` for the command's figures. The whole command's peak is measured on the
command itself, ``/usr/bin/time -v wingmdao size ...`` (maximum resident set size).
"""

from __future__ import annotations

import resource
import sys
import threading
import time

from wingmdao.utils.memory import import_openmdao_without_plot_plugins

import_openmdao_without_plot_plugins()  # as `wingmdao size` does, before the modules below load OpenMDAO

import wingmdao.sizing as sizing  # noqa: E402
import wingmdao.stability.cases as stability_cases  # noqa: E402
from wingmdao.cli import main  # noqa: E402


def rss_mb() -> float:
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * resource.getpagesize() / 1e6


def run(argv) -> int:
    marks, samples, done = [], [], threading.Event()

    def sample():
        while not done.is_set():
            samples.append((time.perf_counter(), rss_mb()))
            time.sleep(0.05)

    def marked(module, name):
        f = getattr(module, name)

        def g(*a, **k):
            marks.append((time.perf_counter(), f"start {name}", rss_mb()))
            try:
                return f(*a, **k)
            finally:
                marks.append((time.perf_counter(), f"end {name}", rss_mb()))

        setattr(module, name, g)

    for module, name in ((sizing, "build_problem"), (sizing, "presize_and_size"), (sizing, "summarize"),
                         (sizing, "release_derivative_storage"), (stability_cases, "flutter_search")):
        marked(module, name)
    threading.Thread(target=sample, daemon=True).start()
    t0 = time.perf_counter()
    try:
        return main(argv)
    finally:
        done.set()
        out = sys.__stderr__
        peak = max(samples, key=lambda s: s[1])
        print(f"peak {peak[1]:.0f} MB at {peak[0] - t0:.1f} s (ru_maxrss "
              f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e3:.0f} MB)", file=out)
        for t, what, r in marks:
            print(f"{t - t0:8.1f} s {r:7.0f} MB  {what}", file=out)
        edges = [t0] + [m[0] for m in marks] + [time.perf_counter()]
        for a, b in zip(edges[:-1], edges[1:]):
            seg = [r for t, r in samples if a <= t <= b]
            if seg:
                print(f"  {a - t0:7.1f} .. {b - t0:7.1f} s: peak {max(seg):.0f} MB", file=out)


if __name__ == "__main__":
    sys.exit(run(sys.argv[1:]))
