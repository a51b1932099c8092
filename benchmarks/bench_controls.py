"""Cost of the coupled march with control surfaces and a law (docs/controls.md, Speed).

``OMP_NUM_THREADS=1 python benchmarks/bench_controls.py``: runs ``wingmdao gust pegasus --alleviation
docs/examples/pegasus_alleviation.yaml`` with the BDF2 march timed (process time, best of 7 marches
of the same gust) without and with the surfaces and the law, and prints both and their ratio.
"""

import os
import sys
import tempfile
import time

from wingmdao.aero import gust_response
from wingmdao.cli import main as cli_main

EXAMPLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "docs", "examples", "pegasus_alleviation.yaml")


def main():
    march = gust_response.march
    times = []

    def timed(system, *args, **kw):
        best, out = None, None
        for _ in range(7):
            t0 = time.process_time()
            out = march(system, *args, **kw)
            dt = time.process_time() - t0
            best = dt if best is None else min(best, dt)
        times.append((system.n_state, best))
        return out

    gust_response.march = timed
    with tempfile.TemporaryDirectory() as tmp:
        cli_main(["gust", "pegasus", "--alleviation", EXAMPLE, "--no-plots", "--json", os.path.join(tmp, "g.json")])
    (n0, t0), (n1, t1) = times
    print(f"march without surfaces: {n0} states, {t0:.4f} s; with surfaces and law: {n1} states, {t1:.4f} s; "
          f"ratio {t1 / t0:.2f}", file=sys.stderr)


if __name__ == "__main__":
    main()
