"""The closed-loop damping constraint's total with respect to ``controller_C`` on PEGASUS (the
example alleviation file, short gust grid, as tests/test_closed_loop.py) against finite differences
(docs/controls.md, "Closed-loop stability constraint").

``PYTHONPATH=. python benchmarks/closed_loop_fd.py`` prints the adjoint total, central differences
at several steps, and least-squares polynomial fits of the constraint over C0 +- 6e-3 (13 points),
with the fit's rms residual (the evaluation's noise). About 10 minutes on one core.
"""

import os

import numpy as np

from wingmdao.cases import pegasus
from wingmdao.sizing import build_problem

EXAMPLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "docs", "examples", "pegasus_alleviation.yaml")


def main():
    setup = pegasus.build(pegasus.PegasusOptions(loads="gust", aero="coupled", aero_theory="strip", plunge="free",
                                                 t_final=0.3, dt=0.03, gust_start=0.0, alleviation=EXAMPLE,
                                                 size_gains=True))
    setup.options.disp = False
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
    prob.run_model()
    name, of = "cases.gust.controller_C", "cases.gust.closed_loop_ks"
    c0 = prob.get_val(name).copy()
    f0 = float(prob.get_val(of)[0])
    total = float(prob.compute_totals(of=[of], wrt=[name])[(of, name)][0, 0])
    print(f"closed_loop_ks {f0:.10e} 1/s, adjoint d/dC {total:.5e}")

    def value(dc):
        prob.set_val(name, c0 + dc)
        prob.run_model()
        return float(prob.get_val(of)[0])

    for h in (2.5e-4, 2.5e-3, 2.5e-2):
        fp, fm = value(h), value(-h)
        print(f"central difference, step {h:g}: {(fp - fm) / (2 * h):.5e} (values {fp:.10e}, {fm:.10e})")
    print(f"repeated evaluation at C0: {value(0.0):.10e} (first {f0:.10e})")
    hs = np.linspace(-6e-3, 6e-3, 13)
    f = np.array([value(h) for h in hs])
    for deg in (2, 3):
        coef = np.polyfit(hs, f, deg)
        res = f - np.polyval(coef, hs)
        print(f"degree-{deg} fit over +-6e-3: slope {coef[-2]:.5e}, rms residual {np.sqrt(np.mean(res ** 2)):.2e} 1/s")


if __name__ == "__main__":
    main()
