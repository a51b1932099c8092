"""The load iteration: size against the critical cases of a loads matrix, re-check the whole matrix,
repeat while the critical set changes (``wingmdao size CASE --matrix FILE.yaml``; docs/loads-matrix.md).

Loop (the industry's loads / stress iteration):

1. run the whole matrix on the current design (:func:`wingmdao.loads.database.run_matrix`) and
   screen it: the critical cases of the vertical shear, bending moment and torsion at every
   station, max and min;
2. the cases critical now that were not sized against before are *added*; without additions after
   the first pass the design holds for every case of the matrix and the loop stops;
3. size (:func:`wingmdao.sizing.size_case`) against the frozen loads of every case added so far:
   each critical snapshot (the wing's loads at the instant of the extreme, at the current design)
   becomes a static load case of nodal forces and moments (:func:`wingmdao.loads.cards.nodal_loads`:
   on the clamped, statically determinate half wing they give back the snapshot's shear forces
   exactly and its moments up to the deflection's change of the lever arms, under 1 % on PEGASUS
   in ``tests/test_load_iteration.py``);
4. back to 1 with the sized walls.

The loads of the dynamic cases depend on the design (stiffness and mass move the gust and
turbulence response), which is why the matrix is re-checked at every optimum; the sizing itself
sees frozen loads (no derivative of the loads with respect to the walls), as in a stress office.
"""

from __future__ import annotations

import copy
import sys

import numpy as np

from wingmdao.groups.load_case import LoadCase
from wingmdao.loads.cards import nodal_loads
from wingmdao.loads.database import run_matrix
from wingmdao.loads.matrix import COMPONENTS, PRIMARY, build_wing_model
from wingmdao.section.box import WALL_NAMES

#: most matrix passes (each one re-checks the whole matrix and sizes once)
MAX_LOOPS = 4


def critical_triples(db, components=PRIMARY) -> dict:
    """{case index: [(station, component, extreme), ...]} of the screening's critical cases.

    Parameters
    ----------
    db : LoadsDatabase
        The loads database.
    components : sequence of str, optional
        csn load components screened.

    Returns
    -------
    dict
        Case index -> [(station, component, extreme), ...].
    """
    out = {}
    for i in range(db.envelope_max.shape[0]):
        for comp in components:
            j = COMPONENTS.index(comp)
            out.setdefault(int(db.max_case[i, j]), []).append((i, comp, "max"))
            out.setdefault(int(db.min_case[i, j]), []).append((i, comp, "min"))
    return out


def frozen_load_cases(db, triples: dict, families=("vm",)) -> list:
    """One static :class:`~wingmdao.groups.load_case.LoadCase` per distinct snapshot of the
    ``triples`` {case index: [(station, component, extreme)]}: nodal forces and moments, no gravity
    (the snapshot's loads already hold the wing's inertia).

    Parameters
    ----------
    db : LoadsDatabase
        The loads database.
    triples : dict
        Case index -> [(station, component, extreme), ...] (:func:`critical_triples`).
    families : sequence of str, optional
        Stress constraint families of the cases.

    Returns
    -------
    list of LoadCase
        One static case per distinct snapshot.
    """
    out, seen = [], set()
    names = db.case_names
    for c in sorted(triples):
        for i, comp, extreme in triples[c]:
            snap = db.snapshot(c, i, comp, extreme)
            key = snap.tobytes()
            if key in seen:
                continue
            seen.add(key)
            P, Q = nodal_loads(snap, db.node_positions, db.node_euler_angles)
            out.append(LoadCase(f"m{len(out)}_{names[c]}"[:80].replace("+", "p").replace("-", "m").replace(".", "_"),
                                np.zeros(1), {"point_force": P[None], "point_moment": Q[None]}, tuple(families),
                                f"frozen loads of {names[c]} (critical for station {i} {comp} {extreme})"))
    return out


def check_meshes(setup, matrix, module) -> None:
    """The matrix's beam must be the sizing's: same node count and positions.

    Parameters
    ----------
    setup : object
        The sizing set-up of the case.
    matrix : LoadsMatrix
        The loads matrix.
    module : module
        The case module (``wingmdao.cases.<name>``).
    """
    n = setup.geometry.num_nodes
    if matrix.num_nodes != n:
        raise ValueError(f"--matrix: model.num_nodes = {matrix.num_nodes}; sizing against the matrix needs the "
                         f"{n} nodes of the {module.NAME} sizing mesh")
    model = build_wing_model(module, matrix)
    if not np.allclose(model.node_positions, setup.geometry.node_positions, rtol=0, atol=1e-9):
        raise ValueError(f"--matrix: the matrix's beam nodes differ from the {module.NAME} sizing mesh")
    if setup.section != "box":
        raise ValueError(f"--matrix needs box sections (the four walls), got section {setup.section!r}")


def load_iteration(module, matrix, setup, *, size, max_loops=MAX_LOOPS, progress=sys.stderr) -> dict:
    """Run the loop of the module docstring; ``size(setup) -> (problem, result)`` sizes a setup
    (:func:`wingmdao.sizing.size_case`). Returns the last sizing result with ``load_iteration``:
    per pass the cases re-checked, critical and added; the totals sized / re-checked / added; and
    whether the critical set stopped changing (``converged``) within ``max_loops`` passes.

    Parameters
    ----------
    module : module
        The case module (``wingmdao.cases.<name>``).
    matrix : LoadsMatrix
        The loads matrix.
    setup : object
        The sizing set-up of the case.
    size : callable
        ``size(setup) -> (problem, result)``.
    max_loops : int, optional
        Most passes of the loop.
    progress : file-like or None, optional
        Stream for progress lines.

    Returns
    -------
    dict
        The last sizing result with its ``load_iteration`` record.
    """
    check_meshes(setup, matrix, module)
    thickness, sized, passes, result = None, {}, [], None
    families = tuple(setup.load_cases[0].families) if setup.load_cases else ("vm",)
    converged = False
    for k in range(1, max_loops + 1):
        db = run_matrix(module, matrix, case=module.NAME, thickness=thickness, progress=progress)
        if db.status != "complete":
            raise KeyboardInterrupt
        crit = critical_triples(db)
        added = sorted(set(crit) - set(sized))
        passes.append({"pass": k, "rechecked": len(db.cases), "critical": len(crit), "added": len(added),
                       "added_cases": [db.case_names[c] for c in added],
                       "max_root_bending_n_m": float(db.envelope_max[0, 3])})
        print(f"load iteration pass {k}: {len(db.cases)} cases re-checked, {len(crit)} critical, {len(added)} added",
              file=progress)
        if k > 1 and not added:
            converged = True
            break
        if k == max_loops:
            break  # the last pass re-checks only
        for c in crit:
            sized.setdefault(c, set()).update(crit[c])
        trial = copy.copy(setup)
        trial.load_cases = frozen_load_cases(db, {c: sorted(t) for c, t in sized.items()}, families)
        trial.options = copy.copy(setup.options)
        _, result = size(trial)
        thickness = {w[2:]: np.asarray(result["thickness"][w[2:]], dtype=float) for w in WALL_NAMES}
        print(f"  sized against {len(sized)} cases ({len(trial.load_cases)} frozen load sets): "
              f"{result['mass_kg']:.1f} kg", file=progress)
    result = dict(result or {})
    result["load_iteration"] = {
        "passes": passes, "sized": len(sized), "rechecked": int(sum(p["rechecked"] for p in passes)),
        "added": int(sum(p["added"] for p in passes[1:])), "converged": converged,
        "sized_cases": sorted(db.case_names[c] for c in sized) if sized else []}
    return result
