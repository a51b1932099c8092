"""Doublet-lattice speed against issue 30's goals, in process (CPU) time (the machine may be shared).

1. Influence matrices of the 20-station PEGASUS wing: the doublet-lattice generalized forces and
   panel station loads of 6 jig modes at the 12 default reduced frequencies
   (``wingmdao.aero.dlm.generalized_forces``: lattice, steady AIC, the oscillatory AIC of every k in
   one call of ``wingmdao.aero.dlm_kernel.oscillatory_aic``, one inverse per k), the first call and
   a repeated call (cached by planform, modes, Mach and k set). Goal: < 2 s, cached.
2. The coupled gust step in the sizing model: ``wingmdao.sizing.build_problem`` of the PEGASUS
   Table 5.3 gust, clamped, ``--aero coupled`` with ``--aero-theory strip`` (the aeroelastic beam,
   Wagner/Kuessner lags) and ``dlm`` (the trimmed 1 g static beam + the modal doublet-lattice march
   and its station loads), 20 nodes: ``run_model`` + ``compute_totals`` of the KS with respect to the
   four wall thicknesses, per time step. Goal: dlm <= 3x strip.
3. PEGASUS doublet-lattice flutter search (``wingmdao.stability.modal.dlm_flutter``, 4 modes, the
   default sweep, p-k and state space), the work of ``wingmdao flutter pegasus --aero-theory dlm``
   without the strip sweep beside it. Goal: < 10 s.

    PYTHONPATH=. python benchmarks/bench_dlm.py [--panelaero]

``--panelaero`` instead: the pressure operators of the same wing's lattice (Mach 0.5, the 12 k)
from ``wingmdao.aero.dlm_kernel`` (the right half's rows, all k in one call) and from PanelAero's
whole wing (``VLM.calc_Ajj`` + ``DLM.calc_Ajj(method="quartic")`` per k, 304 x 304, inverted),
their CPU times (kernel and inverses apart) and their largest difference.

One BLAS thread unless the environment sets a count (as the ``wingmdao`` command,
``wingmdao.utils.threads``): OpenBLAS's spinning threads on this shared 2-core machine cost a
multiple of the small inverses' work (the 12 inverses of the 152-panel AIC: 0.02 s with one
thread, 0.03-0.6 s of process time with two).
"""

from __future__ import annotations

import time

from wingmdao.utils.threads import single_blas_thread_default

single_blas_thread_default()    # before NumPy loads

import numpy as np  # noqa: E402


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
          + "parts (wall clock): " + ", ".join(f"{k} {v:.2f} s" for k, v in res.timings.items()))


def panelaero_check():
    from panelaero import DLM, VLM

    from wingmdao.aero import dlm
    from wingmdao.aero.dlm_kernel import oscillatory_aic
    from wingmdao.aero.vlm import build_lattice
    from wingmdao.stability.cases import flutter_problem

    problem = flutter_problem("pegasus", num_nodes=20)
    n = problem.num_nodes
    chord = np.broadcast_to(problem.aero["chord"], (n,))
    lat = build_lattice(problem.beam["node_positions"], chord, np.broadcast_to(problem.aero["ref_point"], (n,)),
                        mach=0.5, n_chordwise=dlm.DLM_CHORDWISE, n_spanwise=dlm.DLM_SPANWISE)
    kb = np.asarray(dlm.REDUCED_FREQUENCIES) / (0.5 * chord[0])
    m = lat.span.size
    grid = dlm.aerogrid(lat)
    kernel, _ = _cpu(lambda: oscillatory_aic(grid["offset_j"], grid["offset_P1"], grid["offset_P3"], grid["l"],
                                             lat.mach, kb, rows=np.arange(m)))
    ours, D = _cpu(lambda: dlm.pressure_operators(lat, kb))

    def whole_wing():
        A0, _ = VLM.calc_Ajj(aerogrid=dlm.aerogrid(lat), Ma=lat.mach)
        out = []
        for k in kb:
            A = A0.astype(complex)
            if k > 0.0:
                with np.errstate(all="ignore"):
                    A = A + DLM.calc_Ajj(aerogrid=dlm.aerogrid(lat), Ma=lat.mach, k=float(k), method="quartic")
            inv = np.linalg.inv(A)[:m]
            out.append(-(inv[:, :m] + inv[:, m:]))
        return np.array(out)

    theirs, ref = _cpu(whole_wing)
    err = np.abs(D - ref).max() / np.abs(ref).max()
    print(f"pressure operators, {m} panels per half, {kb.size} k: dlm_kernel {ours:.2f} s (kernel {kernel:.2f} s, "
          f"inverses and steady AIC {ours - kernel:.2f} s), PanelAero's whole wing {theirs:.2f} s; largest "
          f"difference {err:.1e} of the largest entry")


def main():
    import sys

    if "--panelaero" in sys.argv[1:]:
        panelaero_check()
        return
    influence_matrices()
    coupled_step()
    flutter()


if __name__ == "__main__":
    main()
