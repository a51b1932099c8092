"""Derive and check the within-node column orders of the static-pivot LU (``lu_column_order``).

    python benchmarks/lu_column_order.py [--nodes 20] [--search] [--passes 4]

The adjoint factors the Newton matrix of every time step (``wingmdao.timemarch.static_lu``,
``P A Q = L U``). Its work depends on the column order Q: node-major keeps the matrix banded,
and the order of the unknowns within a node sets the fill inside the band. For each model of
``benchmarks/bench_aero.py`` (structural beam; coupled aeroelastic beam clamped; free plunge +
trim) this prints the multiply-adds of one factorization (``static_lu.factorization_work``, at
the middle step of a 1-cos gust history) in the natural order and in the order stored in the
package (``wingmdao.beam.residual.LU_NODE_ORDER``, ``wingmdao.aero.system.LU_NODE_ORDER``), and
with ``--search`` the order found by ``static_lu.search_block_order`` (greedy pairwise swaps of
the node-local permutation, first improvement): the stored orders come from that search at 20
nodes.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import bench_aero as B
from wingmdao.timemarch import static_lu
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
    A = lin.newton_matrix(nt // 2).tocsc()
    A.sort_indices()
    return system, A.shape[0], A.indices, A.indptr, A.data


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nodes", type=int, default=20, help="beam nodes (default 20)")
    ap.add_argument("--search", action="store_true", help="also search the order (seconds per model)")
    ap.add_argument("--passes", type=int, default=4, help="search sweeps over the pairs (default 4)")
    args = ap.parse_args(argv)
    print(f"{'model':28s} {'natural':>9s} {'stored':>9s} {'change':>7s}" + ("  searched (order)" if args.search else ""))
    for kind, label in (("structural", "structural beam"), ("coupled", "coupled, clamped"),
                        ("plunge", "coupled, free plunge + trim")):
        system, n, rows, indptr, a = newton_matrix(kind, args.nodes)
        block = int(system.state_shape[-1]) if len(system.state_shape) == 2 else 22
        natural = static_lu.factorization_work(n, rows, indptr, a)
        order = system.lu_column_order()
        stored = static_lu.factorization_work(n, rows, indptr, a, order) if order is not None else natural
        line = f"{label:28s} {natural:9d} {stored:9d} {100 * (stored / natural - 1):+6.0f}%"
        if args.search:
            t0 = time.perf_counter()
            local, work = static_lu.search_block_order(n, rows, indptr, a, block, passes=args.passes)
            line += f"  {work:9d} ({time.perf_counter() - t0:.1f} s) {local.tolist()}"
        print(line, flush=True)


if __name__ == "__main__":
    main()
