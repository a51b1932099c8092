"""Coupled aerostructural analysis and total derivatives: the wingmdao nonlinear beam vs
OpenAeroStruct's linear spatial beam in the same OpenAeroStruct AerostructPoint (same VLM mesh,
same wingbox, same solvers: NonlinearBlockGS + LinearBlockGS with Aitken).

    python benchmarks/bench_aerostruct.py           # rectangular wing, ny = 11
    python benchmarks/bench_aerostruct.py --crm     # uCRM, 2 points (wingmdao.oas.crm, wingmdao size aerostruct-crm)
    python benchmarks/bench_aerostruct.py --crm --repeat 1 --optimize 5   # + time per analysis / gradient in SLSQP

Prints the time of one coupled analysis (cold start from the jig) and one total-derivative
evaluation (adjoint, CL, fuelburn, failure w.r.t. twist, thicknesses, alpha), best of
``--repeat``, for both beams and the ratio ours/OAS. Goal (issue 12): ratio <= 2 in the coupled loop.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def _problem(beam, crm):
    if crm:
        from wingmdao.oas.crm import build_crm_problem, setup_crm_problem

        prob, stress = build_crm_problem(beam, num_y=15)
        setup_crm_problem(prob)
        of = ["AS_point_0.fuelburn", "AS_point_0.CL", stress["maneuver"]]
    else:
        from wingmdao.oas.problems import aerostruct_problem, rect_wingbox_surface

        prob = aerostruct_problem(rect_wingbox_surface(), beam=beam)
        of = ["AS_point_0.CL", "AS_point_0.fuelburn", "AS_point_0.wing_perf.failure"]
    wrt = ["wing.twist_cp", "wing.spar_thickness_cp", "wing.skin_thickness_cp", "alpha"]
    return prob, of, wrt


def bench(beam, crm, repeat):
    t_an, t_tot = [], []
    for _ in range(repeat):
        prob, of, wrt = _problem(beam, crm)
        prob.final_setup()
        t0 = time.perf_counter()
        prob.run_model()
        t_an.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        prob.compute_totals(of=of, wrt=wrt)
        t_tot.append(time.perf_counter() - t0)
    return min(t_an), min(t_tot)


def bench_optimization(beam, maxiter):
    """Mean time per analysis and per gradient inside ``maxiter`` SLSQP iterations of the uCRM problem
    (warm-started coupled solves; OpenMDAO's DriverResult model_time / deriv_time)."""
    from wingmdao.oas.crm import build_crm_problem, setup_crm_problem, solve_crm

    prob, _ = build_crm_problem(beam, num_y=15)
    counter = setup_crm_problem(prob)
    info = solve_crm(prob, counter, maxiter=maxiter)
    return info["time_per_analysis_s"], info["time_per_gradient_s"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--crm", action="store_true", help="the uCRM two-point problem")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--optimize", type=int, default=0, metavar="N",
                    help="with --crm: also N SLSQP iterations, mean time per analysis and per gradient")
    a = ap.parse_args(argv)
    res = {b: bench(b, a.crm, a.repeat) for b in ("oas", "wingmdao")}
    rows = ["coupled analysis (s)", "total derivatives (s)"]
    if a.crm and a.optimize > 0:
        for b in res:
            res[b] += bench_optimization(b, a.optimize)
        rows += ["SLSQP: per analysis (s)", "SLSQP: per gradient (s)"]
    print(f"{'':26s}{'OAS beam':>12s}{'wingmdao':>12s}{'ratio':>8s}")
    for i, label in enumerate(rows):
        o, w = res["oas"][i], res["wingmdao"][i]
        print(f"{label:26s}{o:12.3f}{w:12.3f}{w / o:8.2f}")
    return res


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()
