"""CPU time of the closed-loop constraint's eigen-solve on PEGASUS (docs/controls.md, Speed).

``OMP_NUM_THREADS=1 nice -n 10 python benchmarks/bench_closed_loop_eigen.py`` builds the co-design's
gust case (``docs/examples/pegasus_alleviation.yaml``, short gust grid), evaluates it once, and times on
its 446-state pencil, with the law's gains scaled by 0, 1 and 4 (best of 5 each, process time):
:func:`wingmdao.components.closed_loop.closed_loop_modes` as the component calls it (``depth`` 40 /
rho_ks) and SciPy's dense QZ solve with left and right vectors that it replaces.
"""

from __future__ import annotations

import os
import time

import scipy.linalg as sla

from wingmdao.cases import pegasus
from wingmdao.components.closed_loop import closed_loop_forcing, closed_loop_modes
from wingmdao.sizing import build_problem
from wingmdao.stability.eigen import linearize
from wingmdao.timemarch.system import layout

EXAMPLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "docs", "examples", "pegasus_alleviation.yaml")


def best(fun, repeat=5):
    """Least process time of ``repeat`` calls of ``fun``."""
    times = []
    for _ in range(repeat):
        t0 = time.process_time()
        fun()
        times.append(time.process_time() - t0)
    return min(times)


def main():
    setup = pegasus.build(pegasus.PegasusOptions(loads="gust", aero="coupled", aero_theory="strip", plunge="free",
                                                 t_final=0.3, dt=0.03, gust_start=0.0, alleviation=EXAMPLE,
                                                 size_gains=True))
    setup.options.disp = False
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
    prob.run_model()
    comp = prob.model._get_subsystem("cases.gust.closed_loop")
    s = comp.options["system"]
    p, x0 = comp._packed(comp._inputs)
    lay = layout(s.param_specs)
    depth = 40.0 / comp.options["rho_ks"]
    for scale in (0.0, 1.0, 4.0):
        ps = p.copy()
        for nm in ("controller_C", "controller_D"):
            ps[lay[nm]] *= scale
        A, B = linearize(s, ps, closed_loop_forcing(s), x0)
        Ad, Bd = -A.toarray(), B.toarray()
        t_new = best(lambda: closed_loop_modes(s, ps, x0, depth=depth))
        t_qz = best(lambda: sla.eig(Ad, Bd, left=True, right=True))
        lam = closed_loop_modes(s, ps, x0, depth=depth)[0]
        print(f"gains x {scale:g}: {A.shape[0]} states, closed_loop_modes {t_new:.3f} s, "
              f"dense QZ with vectors {t_qz:.3f} s; {lam.size} modes within {depth:g} 1/s, "
              f"largest Re {lam.real.max():.3e} 1/s")


if __name__ == "__main__":
    main()
