"""Derive and check the within-node column orders of the static-pivot LU (``lu_column_order``).

    python benchmarks/lu_column_order.py [--nodes 20] [--no-pegasus] [--search] [--passes 4]

The adjoint factors the Newton matrix of every time step (``wingmdao.timemarch.static_lu``,
``P A Q = L U``). Its work depends on the column order Q: node-major keeps the matrix banded,
and the order of the unknowns within a node sets the fill inside the band. For each model this
prints the multiply-adds of one factorization (``static_lu.factorization_work``, Newton matrix
of the middle step of a gust history) in the natural order and in the order stored in the
package (``wingmdao.timemarch.lu_orders``; the march's ``lu_column_order``) and in the adjoint's
order (``lu_orders.adjoint_lu_order``: for the aeroelastic models every lag state first with
diagonal pivots, then the beam part). Models: the straight 20-node beam of
``benchmarks/bench_aero.py`` (lift; lift and moment; coupled clamped; coupled free plunge +
trim) and, unless ``--no-pegasus``, the PEGASUS wing under its Table 5.3 gust (strip-theory
loads; coupled clamped, with trim; coupled free plunge + trim). With ``--search`` it runs
``static_lu.search_joint_block_order`` (greedy pairwise swaps of one node-local permutation,
minimising the summed work relative to the natural order over all beam models, then over all
aeroelastic models): the stored orders come from that search.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import bench_aero as B
from wingmdao.timemarch import lu_orders, static_lu
from wingmdao.timemarch.adjoint import LinearizedHistory
from wingmdao.timemarch.system import pack


def newton_matrix(kind, n, nt=200, dt=0.002):
    """(system, n_state, rows, indptr, values) of the Newton matrix at the middle step."""
    prob, _ = B.build(kind, n, nt, dt)
    system = prob.model.beam.build_system()
    X = np.asarray(prob.get_val("states")).reshape(nt, -1)
    p = pack(system.param_specs, {s.name: prob.get_val(s.name) for s in system.param_specs})
    Q = np.concatenate([np.asarray(prob.get_val(s.name)).reshape(nt, -1) for s in system.forcing_specs], axis=1)
    lin = LinearizedHistory(system, np.arange(nt) * dt, X, p, Q, lu="superlu")
    return (system,) + _middle(lin)


def _middle(lin):
    A = lin.newton_matrix(lin.n_time // 2).tocsc()
    A.sort_indices()
    return A.shape[0], A.indices, A.indptr, A.data


def pegasus_matrix(aero, plunge):
    """The same for the PEGASUS gust case (``--aero``, ``--plunge``) at its initial design (the
    beam component's own linearization, after one gradient)."""
    from wingmdao.cases import pegasus
    from wingmdao.components.time_history import TimeHistoryComponent
    from wingmdao.sizing import WALL_VARS, build_problem

    setup = pegasus.build(loads="gust", aero=aero, plunge=plunge)
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
    prob.run_model()
    prob.compute_totals(of=[f"cases.{case.name}.ks_{fam}" for case in setup.load_cases for fam in case.families],
                        wrt=list(WALL_VARS))
    beam = next(prob.model.system_iter(recurse=True, typ=TimeHistoryComponent))
    return (beam.build_system(),) + _middle(beam._lin)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nodes", type=int, default=20, help="beam nodes of the straight beam (default %(default)s)")
    ap.add_argument("--no-pegasus", action="store_true", help="leave out the PEGASUS matrices")
    ap.add_argument("--search", action="store_true", help="also search the joint orders (seconds to minutes)")
    ap.add_argument("--passes", type=int, default=4, help="search sweeps over the pairs (default %(default)s)")
    args = ap.parse_args(argv)
    models = [("structural", "straight beam, lift", lambda: newton_matrix("structural", args.nodes)),
              ("structural", "straight beam, lift + moment", lambda: newton_matrix("structural_torsion", args.nodes)),
              ("aero", "straight, coupled clamped", lambda: newton_matrix("coupled", args.nodes)),
              ("aero", "straight, free plunge + trim", lambda: newton_matrix("plunge", args.nodes))]
    if not args.no_pegasus:
        models += [("structural", "PEGASUS, strip loads", lambda: pegasus_matrix("strip", "clamped")),
                   ("aero", "PEGASUS, coupled clamped + trim", lambda: pegasus_matrix("coupled", "clamped")),
                   ("aero", "PEGASUS, free plunge + trim", lambda: pegasus_matrix("coupled", "free"))]
    print(f"{'model':34s} {'natural':>9s} {'stored':>9s} {'change':>7s} {'adjoint':>9s} {'change':>7s}")
    groups = {"structural": [], "aero": []}
    for family, label, make in models:
        system, n, rows, indptr, a = make()
        natural = static_lu.factorization_work(n, rows, indptr, a)
        order = system.lu_column_order()
        stored = static_lu.factorization_work(n, rows, indptr, a, order) if order is not None else natural
        adj_order, diagonal = lu_orders.adjoint_lu_order(system)
        adjoint = (static_lu.factorization_work(n, rows, indptr, a, adj_order, diagonal)
                   if adj_order is not None else natural)
        print(f"{label:34s} {natural:9d} {stored:9d} {100 * (stored / natural - 1):+6.0f}% {adjoint:9d} "
              f"{100 * (adjoint / natural - 1):+6.0f}%", flush=True)
        groups[family].append((label, (n, rows, indptr, a), natural))
    if args.search:
        for family, block, stored in (("structural", 18, lu_orders.BEAM_NODE_ORDER),
                                      ("aero", 22, lu_orders.AEROELASTIC_NODE_ORDER)):
            labels, mats, naturals = zip(*groups[family])
            t0 = time.perf_counter()
            best = None
            for start in (None, stored):
                local, works = static_lu.search_joint_block_order(list(mats), block, passes=args.passes, start=start)
                total = sum(w / w0 for w, w0 in zip(works, naturals))
                if best is None or total < best[2]:
                    best = (local, works, total)
            print(f"\n{family} models, joint search ({time.perf_counter() - t0:.0f} s): {best[0].tolist()}")
            for label, w in zip(labels, best[1]):
                print(f"  {label:32s} {w:9d}")


if __name__ == "__main__":
    main()
