"""Doublet-lattice speed against issue 30's goals, in process (CPU) time (the machine may be shared).

1. Influence matrices of the 20-station PEGASUS wing: the doublet-lattice generalized forces and
   panel station loads of 6 jig modes at the 12 default reduced frequencies
   (``wingmdao.aero.dlm.generalized_forces``: lattice, steady AIC, one unsteady AIC per k), the
   first call and a repeated call (cached by planform, modes, Mach and k set). Goal: < 2 s, cached.
2. The coupled gust step in the sizing model: ``wingmdao.sizing.build_problem`` of the PEGASUS
   Table 5.3 gust, clamped, ``--aero coupled`` with ``--aero-theory strip`` (the aeroelastic beam,
   Wagner/Kuessner lags) and ``dlm`` (the trimmed 1 g static beam + the modal doublet-lattice march
   and its station loads), 20 nodes: ``run_model`` + ``compute_totals`` of the KS with respect to the
   four wall thicknesses, per time step. Goal: dlm <= 3x strip.
3. PEGASUS doublet-lattice flutter search (``wingmdao.stability.modal.dlm_flutter``, 4 modes, the
   default sweep, p-k and state space), the work of ``wingmdao flutter pegasus --aero-theory dlm``
   without the strip sweep beside it. Goal: < 10 s.

    PYTHONPATH=. python benchmarks/bench_dlm.py
"""

from __future__ import annotations

import time

import numpy as np


def _cpu(fn):
    t0 = time.process_time()
    out = fn()
    return time.process_time() - t0, out


def influence_matrices():
    from wingmdao.aero.dlm import generalized_forces
    from wingmdao.stability.cases import flutter_problem
    from wingmdao.stability.modal import jig_modes

    problem = flutter_problem("pegasus", num_nodes=20)
    modes = jig_modes(problem, 6)
    n = problem.num_nodes

    def build():
        return generalized_forces(problem.beam["node_positions"], np.broadcast_to(problem.aero["chord"], (n,)),
                                  np.broadcast_to(problem.aero["ref_point"], (n,)), modes.displacement,
                                  modes.rotation, mach=0.5)

    first, gaf = _cpu(build)
    again, _ = _cpu(build)
    print(f"influence matrices, 20 stations, {gaf.k.size} k, 6 modes: {first:.2f} s first, {again * 1e3:.2f} ms "
          f"cached (goal < 2 s, cached)")


def coupled_step():
    from wingmdao.cases import pegasus
    from wingmdao.sizing import WALL_VARS, build_problem

    per_step = {}
    for theory in ("strip", "dlm"):
        setup = pegasus.build(pegasus.PegasusOptions(loads="gust", aero="coupled", aero_theory=theory))
        setup.options.disp = False
        prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options)
        case = setup.load_cases[0]
        run, _ = _cpu(prob.run_model)
        ks = [k for k in prob.model.get_constraints() if k.startswith(f"cases.{case.name}")]
        grad, _ = _cpu(lambda: prob.compute_totals(of=ks, wrt=list(WALL_VARS)))
        nt = case.num_times
        per_step[theory] = (run + grad) / nt
        print(f"coupled gust, --aero-theory {theory}: {nt} steps, march {run:.2f} s, adjoint {grad:.2f} s, "
              f"{per_step[theory] * 1e3:.2f} ms per step")
    print(f"dlm / strip per step: {per_step['dlm'] / per_step['strip']:.2f} (goal <= 3)")


def flutter():
    from wingmdao.stability.cases import flutter_problem
    from wingmdao.stability.modal import dlm_flutter

    cpu, res = _cpu(lambda: dlm_flutter(flutter_problem("pegasus", num_nodes=20), n_modes=4))
    speed = res.pk.flutter_speed
    print(f"PEGASUS doublet-lattice flutter search: {cpu:.2f} s (goal < 10 s); flutter speed "
          f"{'none in the sweep' if speed is None else f'{speed:.1f} m/s'}; "
          + ", ".join(f"{k} {v:.2f} s" for k, v in res.timings.items()))


def main():
    influence_matrices()
    coupled_step()
    flutter()


if __name__ == "__main__":
    main()
