"""The closed-loop damping constraint's total with respect to ``controller_C`` on PEGASUS (the
example alleviation file, short gust grid, as tests/test_closed_loop.py) against finite differences
(docs/controls.md, "Closed-loop stability constraint").

``PYTHONPATH=. python benchmarks/closed_loop_fd.py`` prints the adjoint total, central differences
at several steps (each evaluation warm-started from the previous one's states, then from the same
states), and least-squares polynomial fits of the constraint over C0 +- 6e-3 (13 points), with the
fit's rms residual (the evaluation's noise). About 15 minutes on one core.
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
    # every evaluation warm-started from the same states (the march's output reset to C0's solution)
    states = prob.get_val("cases.gust.states").copy()

    def reset_value(dc):
        prob.set_val("cases.gust.states", states)
        return value(dc)

    print(f"warm start reset: at C0 {reset_value(0.0):.10e}, again {reset_value(0.0):.10e}")
    for h in (2.5e-4, 1e-3, 2.5e-3):
        print(f"warm start reset, central difference, step {h:g}: {(reset_value(h) - reset_value(-h)) / (2 * h):.5e}")
    hs = np.linspace(-6e-3, 6e-3, 13)
    f = np.array([value(h) for h in hs])
    for deg in (2, 3):
        coef = np.polyfit(hs, f, deg)
        res = f - np.polyval(coef, hs)
        print(f"degree-{deg} fit over +-6e-3: slope {coef[-2]:.5e}, rms residual {np.sqrt(np.mean(res ** 2)):.2e} 1/s")


if __name__ == "__main__":
    main()
