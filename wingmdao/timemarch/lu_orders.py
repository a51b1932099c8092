"""Within-node column orders of the adjoint's static-pivot LU (``P A Q = L U``), one table per model.

The adjoint factors the Newton matrix of every time step (:mod:`wingmdao.timemarch.static_lu`).
Node-major columns keep the matrix banded; the order of a node's unknowns inside the band sets
the fill and so the multiply-adds of each factorization (``static_lu.factorization_work``). The
orders below come from a greedy search over node-local permutations (pairwise swaps, first
improvement; ``benchmarks/lu_column_order.py --search``) that minimises the summed relative work
over several Newton matrices at once: the 20-node straight beam of ``benchmarks/bench_aero.py``
under a 1-cos gust (clamped, and free in plunge with trim) and the PEGASUS wing under its
Table 5.3 gust (swept, with dihedral: every structural entry of the pattern is nonzero). An
order found on the straight beam alone halved the work there but left the PEGASUS coupled
matrix at 149 386 multiply-adds; the joint order gives 76 787.

This module is deliberately not one of the modules whose source keys the compiled CasADi
libraries (``_GENERATING_MODULES`` of :mod:`wingmdao.beam.residual` and
:mod:`wingmdao.aero.system`): a column order changes no generated function, so retuning it must
not force a recompilation.
"""

from __future__ import annotations

import numpy as np

from wingmdao.timemarch.static_lu import block_column_order

#: Order of a beam node's 18 unknowns (state indices of ``STATE_BLOCKS``: r, theta, F, M, u,
#: omega). Work per factorization, natural -> this order: straight beam (lift) 11 244 -> 8 277,
#: straight beam (lift and moment) 39 993 -> 30 329, PEGASUS 45 772 -> 38 699.
BEAM_NODE_ORDER = (10, 0, 11, 9, 15, 2, 17, 7, 8, 16, 6, 1, 4, 13, 14, 12, 3, 5)

#: Order of an aeroelastic node's 22 unknowns (the 18 beam states, then the 4 lag states); body
#: states (plunge, pitch, trim unknowns) stay last. Work per factorization, natural -> this order:
#: straight beam clamped 124 448 -> 59 681, straight beam free plunge + trim 155 459 -> 79 469,
#: PEGASUS clamped with trim 182 051 -> 76 787, PEGASUS free plunge + trim 199 997 -> 87 777.
AEROELASTIC_NODE_ORDER = (11, 10, 9, 15, 5, 8, 1, 7, 16, 6, 19, 20, 18, 0, 21, 2, 12, 13, 14, 3, 4, 17)


def beam_lu_column_order(num_nodes: int) -> np.ndarray:
    """Column order of the static LU of the ``num_nodes``-node beam (:data:`BEAM_NODE_ORDER`).

    Parameters
    ----------
    num_nodes : int
        Number of beam nodes (18 unknowns each).

    Returns
    -------
    numpy.ndarray
        (18 num_nodes,) int64 column order.
    """
    return block_column_order(BEAM_NODE_ORDER, len(BEAM_NODE_ORDER), len(BEAM_NODE_ORDER) * int(num_nodes))


def aeroelastic_lu_column_order(n_state: int) -> np.ndarray:
    """Column order of the static LU of an aeroelastic system of ``n_state`` unknowns
    (:data:`AEROELASTIC_NODE_ORDER` per node, body states last).

    Parameters
    ----------
    n_state : int
        Number of unknowns of the system (22 per node, then the body states).

    Returns
    -------
    numpy.ndarray
        (n_state,) int64 column order.
    """
    return block_column_order(AEROELASTIC_NODE_ORDER, len(AEROELASTIC_NODE_ORDER), int(n_state))


#: The adjoint's order of an aeroelastic node's 18 beam unknowns after all lag states (the beam
#: entries of :data:`AEROELASTIC_NODE_ORDER` in their order; a greedy search of this part, lag
#: states first, found orders within 0.3 % of it: ``benchmarks/lu_column_order.py --search``).
AEROELASTIC_BEAM_ORDER = tuple(k for k in AEROELASTIC_NODE_ORDER if k < 18)


def aeroelastic_adjoint_lu_order(num_nodes: int, n_state: int):
    """``(col_order, diagonal)`` of the adjoint's static LU of an aeroelastic system of
    ``num_nodes`` nodes (22 unknowns each, then the body states) and ``n_state`` unknowns: the
    4 lag states of every station first, each pivoting on its own row (``diagonal`` =
    4 ``num_nodes``, :func:`wingmdao.timemarch.static_lu.pivot_order`), then the beam unknowns
    node by node in :data:`AEROELASTIC_BEAM_ORDER`, the body states last.

    The lag rows hold a diagonal block (``A_aa = alpha_0/dt I + B_aa``, each lag state's own
    decay) and couple to a few beam unknowns of their station, which the beam rows of the
    section's loads depend on already: eliminating the lag states first (a Schur complement
    ``A_bb - A_ba A_aa^-1 A_ab``) adds no fill, so the factorization is that of the beam part.
    Partial pivoting in this order picks beam rows for the lag columns and fills the matrix
    (about 2 million multiply-adds): the diagonal pivots are what make the order work. PEGASUS
    coupled clamped 76 725 -> 63 075 multiply-adds per factorization, free plunge + trim
    87 726 -> 71 797; straight beam 59 521 -> 48 905 and 79 442 -> 65 425.

    Parameters
    ----------
    num_nodes : int
        Number of nodes (22 unknowns each).
    n_state : int
        Number of unknowns of the system (the nodes' unknowns, then the body states).

    Returns
    -------
    col_order : numpy.ndarray
        (n_state,) int64 column order.
    diagonal : int
        Number of leading columns pivoting on their own rows (``4 num_nodes``).
    """
    n, n_state = int(num_nodes), int(n_state)
    w, nb = len(AEROELASTIC_NODE_ORDER), len(AEROELASTIC_BEAM_ORDER)
    node = np.arange(n)[:, None] * w
    lag = (node + np.arange(nb, w)).ravel()
    beam = (node + np.asarray(AEROELASTIC_BEAM_ORDER)).ravel()
    return np.concatenate([lag, beam, np.arange(w * n, n_state)]).astype(np.int64), lag.size


def adjoint_lu_order(system):
    """``(col_order, diagonal)`` of the adjoint's static LU of ``system``
    (:class:`~wingmdao.timemarch.adjoint.LinearizedHistory`): for an aeroelastic system (a ``layout`` with ``aero``
    lag states, :mod:`wingmdao.aero.system`) :func:`aeroelastic_adjoint_lu_order`; else its
    ``lu_column_order()`` with partial pivoting throughout (``diagonal`` 0).

    The compiled march keeps :func:`system_lu_column_order`: its LU pivots by partial pivoting at every
    refactorization, for which the lag-first order fills. This lookup lives here, outside the
    modules that key the compiled libraries, so changing the adjoint's order recompiles nothing.

    Parameters
    ----------
    system : ResidualSystem
        The system whose Newton matrices the adjoint factors.

    Returns
    -------
    col_order : numpy.ndarray or None
        Column order Q (None: natural).
    diagonal : int
        Number of leading columns pivoting on their own rows.
    """
    lay = getattr(system, "layout", None)
    aero = getattr(lay, "aero", None)
    if aero is not None and getattr(lay, "size", None) == system.n_state and np.size(aero):
        order, diagonal = aeroelastic_adjoint_lu_order(np.shape(aero)[0], system.n_state)
        if np.array_equal(order[:diagonal], np.ravel(aero)):    # the layout this order assumes
            return order, diagonal
    return system_lu_column_order(system), 0


def system_lu_column_order(system):
    """The column order of the LUs of ``system``'s Newton matrix (the compiled march's,
    :mod:`wingmdao.timemarch.fast_step`, and the adjoint's when :func:`adjoint_lu_order` has no
    table for it): :func:`joined_aero_lu_column_order` for a joined aeroelastic system (its
    ``lag_index``), else ``system.lu_column_order()`` (None: natural).

    Parameters
    ----------
    system : ResidualSystem
        The system whose Newton matrix is factored.

    Returns
    -------
    ndarray or None
        Column order Q of ``P A Q = L U`` (column k of ``A Q`` is column ``Q[k]`` of A), or None
        for the natural order.
    """
    lags = getattr(system, "lag_index", None)
    order = system.lu_column_order()
    if lags and order is not None and getattr(system, "offsets", None) is not None:
        return joined_aero_lu_column_order(order, system.offsets, lags)
    return order


def joined_aero_lu_column_order(order, offsets, lag_index) -> np.ndarray:
    """``order`` (a joined system's :func:`joined_lu_column_order`, the extension's unknowns last)
    with the 4 lag states of every strip node moved right after that node's 18 beam columns
    (``offsets``: {beam: first state}; ``lag_index``: {beam: (n, 4) state indices}); the other
    extension unknowns (downwash lag, trim) stay last.

    A node's lag rows and columns couple only to that node's unknowns and to each other; at the end
    of the order the 112 lag columns of the PEGASUS stick model (wing 20, tail 8 nodes) join every
    strip node's rows into one trailing block: 2 592 202 multiply-adds per factorization of its
    Newton matrix (1094 unknowns) against 482 216 in this order
    (``static_lu.factorization_work``; COLAMD's order needs 447 937).

    Parameters
    ----------
    order : array_like of int
        The joined system's column order, a permutation of its unknowns.
    offsets : dict
        ``{beam: first state index}`` of every beam.
    lag_index : dict
        ``{beam: (n, 4) state indices}`` of the lag states of every lifting beam's nodes.

    Returns
    -------
    ndarray
        The column order (int64) with the lag states moved.
    """
    order = np.asarray(order, dtype=np.int64)
    width = len(BEAM_NODE_ORDER)
    last = BEAM_NODE_ORDER[-1]
    after = {}
    for beam, idx in lag_index.items():
        first = int(offsets[beam])
        for i, cols in enumerate(np.asarray(idx, dtype=np.int64).reshape(-1, np.shape(idx)[-1])):
            after[first + width * i + last] = cols
    moved = np.zeros(order.size, dtype=bool)
    for cols in after.values():
        moved[cols] = True
    parts = []
    for c in order[~moved[order]]:
        parts.append([c])
        if int(c) in after:
            parts.append(after[int(c)])
    out = np.concatenate(parts).astype(np.int64)
    if out.size != order.size:
        raise ValueError(f"lag states outside the order: {order.size} columns, {out.size} placed")
    return out


def joined_lu_column_order(node_counts, joint_nodes, support_nodes=()) -> np.ndarray:
    """Column order of the static LU of joined beams (:mod:`wingmdao.beam.joints`): the beams'
    node blocks in state order, each in :data:`BEAM_NODE_ORDER`, and the 12 unknowns of every joint
    right after the later of its two nodes (``joint_nodes``: ``(node_a, node_b)`` counted over all
    beams in state order; the joint unknowns follow the node blocks in the state, joint by joint),
    then the 3 reactions of every symmetry condition right after its node (``support_nodes``,
    counted as ``joint_nodes``; their unknowns follow the joints' in the state).

    Placed there, a joint's columns are eliminated next to the only two node blocks they couple,
    instead of at the end of the matrix where the rows of the first beams' joint nodes would fill
    the band of every node between them (docs/stick-model.md, "Sparsity and the LU order").

    Parameters
    ----------
    node_counts : sequence of int
        Number of nodes of each beam, in state order.
    joint_nodes : sequence of tuple of int
        ``(node_a, node_b)`` of every joint, nodes counted over all beams.
    support_nodes : sequence of int, optional
        Node of every symmetry condition, counted as ``joint_nodes``.

    Returns
    -------
    numpy.ndarray
        int64 column order of all the unknowns (nodes, joints, supports).
    """
    n_nodes = int(sum(int(n) for n in node_counts))
    width = len(BEAM_NODE_ORDER)
    after = [[] for _ in range(n_nodes)]
    for j, (a, b) in enumerate(joint_nodes):
        after[max(int(a), int(b))].append(np.arange(12) + 12 * j)
    first_support = 12 * len(joint_nodes)
    for k, a in enumerate(support_nodes):
        after[int(a)].append(first_support + 3 * k + np.arange(3))
    local = np.asarray(BEAM_NODE_ORDER, dtype=np.int64)
    first_joint = width * n_nodes
    parts = []
    for g in range(n_nodes):
        parts.append(local + width * g)
        parts += [first_joint + cols for cols in after[g]]
    return np.concatenate(parts).astype(np.int64)
