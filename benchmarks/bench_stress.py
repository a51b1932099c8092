"""Stress recovery over a gust history: section properties recomputed at every (time, station)
point against taken from the section component once per station (BoxStress ``section_properties``).

    python benchmarks/bench_stress.py [--steps 251] [--stations 20] [--repeat 3]

Times one ``compute`` + ``compute_partials`` of BoxStress (vm, ss_tension, cent_pos families,
as in the PEGASUS gust case) both ways, interpreted CasADi (WINGMDAO_JIT=0) unless compiled
functions are in the cache.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import openmdao.api as om

from wingmdao.components.section import BoxSection
from wingmdao.components.stress import BoxStress
from wingmdao.materials import ALUMINIUM
from wingmdao.stress.box_stress import SECTION_PROPERTIES

WALLS = ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")


def _timed(nt, n, section_properties, repeat):
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("section", BoxSection(num_stations=n, material=ALUMINIUM), promotes_inputs=["*"])
    prob.model.add_subsystem("stress", BoxStress(num_times=nt, num_stations=n, material=ALUMINIUM, output_stresses=False,
                                                 families=("vm", "ss_tension", "cent_pos"),
                                                 section_properties=section_properties),
                             promotes_inputs=["width", "height", *WALLS])
    if section_properties:
        for name in SECTION_PROPERTIES:
            prob.model.connect(f"section.{name}", f"stress.{name}")
    prob.setup()
    rng = np.random.default_rng(0)
    prob.set_val("width", rng.uniform(0.6, 1.0, n))
    prob.set_val("height", rng.uniform(0.15, 0.3, n))
    for w in WALLS:
        prob.set_val(w, rng.uniform(2e-3, 9e-3, n))
    prob.set_val("stress.F_csn", rng.normal(0, 5e4, (nt, n, 3)))
    prob.set_val("stress.M_csn", rng.normal(0, 2e5, (nt, n, 3)))
    prob.run_model()
    comp = prob.model.stress
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        prob.run_model()
        prob.model.run_linearize()
        best = min(best, time.perf_counter() - t0)
    return best, comp


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=251, help="time steps (PEGASUS gust: 251)")
    ap.add_argument("--stations", type=int, default=20, help="beam stations")
    ap.add_argument("--repeat", type=int, default=3, help="repetitions (best is printed)")
    args = ap.parse_args()
    old, _ = _timed(args.steps, args.stations, False, args.repeat)
    new, _ = _timed(args.steps, args.stations, True, args.repeat)
    print(f"BoxStress + BoxSection, {args.steps} steps x {args.stations} stations, compute + partials (best of {args.repeat}):")
    print(f"  section properties recomputed per point : {old:8.3f} s")
    print(f"  section properties from BoxSection      : {new:8.3f} s   ({old / new:.2f}x faster)")


if __name__ == "__main__":
    main()
