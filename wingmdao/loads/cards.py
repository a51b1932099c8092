"""Stress-office cards of the critical cases: Nastran FORCE/MOMENT and CalculiX ``*CLOAD`` at the beam nodes.

For each critical case of the screening (:attr:`wingmdao.loads.database.LoadsDatabase.max_case`
and ``min_case``, per station and component) the database holds the wing's internal loads at the
instant of the extreme (a *snapshot*, csn frame of each station). They become nodal loads in the
basic (body) frame that reproduce them: with the internal loads of station k, F_k and M_k (body
axes, the resultant of everything outboard of the cut just inboard of node k, moments about node
k), the loads applied at node k are

    P_k = F_k - F_(k+1),      Q_k = M_k - M_(k+1) - (r_(k+1) - r_k) x F_(k+1),      F_n = M_n = 0,

so that the loads at nodes k..n-1 have the resultant (F_k, M_k) about node k, for every k
(:func:`station_resultants`). The csn loads are rotated to body axes with the jig frames and the
lever arms are the jig node positions: the cards load an undeformed (linear) stress model. The
root node's loads are those between the root station and station 1; in a model clamped at the
root node they go into the reaction.

Formats:

* Nastran bulk data (small field: 8-character fields): ``FORCE SID G CID F N1 N2 N3`` and
  ``MOMENT`` likewise, CID 0 (basic), F the magnitude and N the unit direction (MSC Nastran
  Quick Reference Guide, FORCE and MOMENT bulk data entries); one load set (SID) per distinct
  critical snapshot, a ``$`` comment naming the case, station, component and extreme;
* CalculiX input (free format): one ``*STEP`` / ``*STATIC`` / ``*CLOAD, OP=NEW`` per load set, DOFs
  1-3 forces and 4-6 moments (CalculiX CrunchiX User's Manual, ``*CLOAD``), to include after the
  model definition.

Beam node k is GRID / node ``first_id + k`` (default 1: numbered from the root).
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass

import numpy as np

from wingmdao.beam.rotations import body_to_csn
from wingmdao.loads.matrix import COMPONENTS, PRIMARY

_REAL = re.compile(r"^([+-]?(?:\d+\.?\d*|\.\d+))(?:[eEdD]?([+-]\d+))?$")


@dataclass(frozen=True)
class LoadSet:
    """One card load set: ``sid``, the case (``case_index``, ``case_name``), the (station,
    component, extreme) triples it is critical for, and the snapshot (n, 6) csn loads.

    Parameters
    ----------
    sid : int
        Load set id.
    case_index : int
        Case index in the database.
    case_name : str
        Case name.
    critical_for : tuple
        (station, component, extreme) triples the set is critical for.
    snapshot : numpy.ndarray
        (n, 6) csn internal loads (N, N m).
    """

    sid: int
    case_index: int
    case_name: str
    critical_for: tuple
    snapshot: np.ndarray


def csn_to_body(loads_csn, node_euler_angles) -> np.ndarray:
    """(n, 6) csn loads -> (n, 6) body-axes loads with the jig frames T of every node (body = T^T csn).

    Parameters
    ----------
    loads_csn : array_like
        (n, 6) csn loads (N, N m).
    node_euler_angles : array_like
        (n, 3) jig Euler angles of the nodes' csn frames (rad).

    Returns
    -------
    numpy.ndarray
        (n, 6) body-axes loads (N, N m).
    """
    L = np.asarray(loads_csn, dtype=float)
    T = np.stack([body_to_csn(np.asarray(a, dtype=float)) for a in np.asarray(node_euler_angles, dtype=float)])
    return np.concatenate([np.einsum("kji,kj->ki", T, L[:, :3]), np.einsum("kji,kj->ki", T, L[:, 3:])], axis=1)


def body_to_csn_loads(loads_body, node_euler_angles) -> np.ndarray:
    """The inverse of :func:`csn_to_body`.

    Parameters
    ----------
    loads_body : array_like
        (n, 6) body-axes loads (N, N m).
    node_euler_angles : array_like
        (n, 3) jig Euler angles of the nodes' csn frames (rad).

    Returns
    -------
    numpy.ndarray
        (n, 6) csn loads (N, N m).
    """
    L = np.asarray(loads_body, dtype=float)
    T = np.stack([body_to_csn(np.asarray(a, dtype=float)) for a in np.asarray(node_euler_angles, dtype=float)])
    return np.concatenate([np.einsum("kij,kj->ki", T, L[:, :3]), np.einsum("kij,kj->ki", T, L[:, 3:])], axis=1)


def nodal_loads(loads_csn, node_positions, node_euler_angles):
    """Nodal forces and moments (n, 3) each, body axes, whose resultants reproduce the station loads (module doc).

    Parameters
    ----------
    loads_csn : array_like
        (n, 6) csn internal loads of the stations (N, N m).
    node_positions : array_like
        (n, 3) jig node positions, body axes (m).
    node_euler_angles : array_like
        (n, 3) jig Euler angles of the nodes' csn frames (rad).

    Returns
    -------
    tuple
        Forces (n, 3) (N) and moments (n, 3) (N m), body axes.
    """
    L = csn_to_body(loads_csn, node_euler_angles)
    r = np.asarray(node_positions, dtype=float)
    F, M = L[:, :3], L[:, 3:]
    F1 = np.vstack([F[1:], np.zeros(3)])
    M1 = np.vstack([M[1:], np.zeros(3)])
    arm = np.vstack([r[1:] - r[:-1], np.zeros(3)])
    return F - F1, M - M1 - np.cross(arm, F1)


def station_resultants(forces, moments, node_positions) -> np.ndarray:
    """(n, 6) body-axes resultant of the nodal loads at nodes k..n-1 about node k, for every k.

    Parameters
    ----------
    forces : array_like
        (n, 3) nodal forces, body axes (N).
    moments : array_like
        (n, 3) nodal moments, body axes (N m).
    node_positions : array_like
        (n, 3) jig node positions, body axes (m).

    Returns
    -------
    numpy.ndarray
        (n, 6) resultants (N, N m).
    """
    P, Q, r = (np.asarray(a, dtype=float) for a in (forces, moments, node_positions))
    out = np.zeros((r.shape[0], 6))
    for k in range(r.shape[0]):
        out[k, :3] = P[k:].sum(axis=0)
        out[k, 3:] = Q[k:].sum(axis=0) + np.cross(r[k:] - r[k], P[k:]).sum(axis=0)
    return out


def critical_load_sets(db, components=PRIMARY, first_sid: int = 1) -> list:
    """One :class:`LoadSet` per distinct snapshot among the critical cases of ``components``
    (default vertical shear, bending, torsion) at every station, max and min; ordered by first use.

    Parameters
    ----------
    db : LoadsDatabase
        The loads database.
    components : sequence of str, optional
        csn components screened.
    first_sid : int, optional
        Id of the first load set.

    Returns
    -------
    list of LoadSet
        The load sets.
    """
    bad = [c for c in components if c not in COMPONENTS]
    if bad:
        raise ValueError(f"components {bad}; allowed {list(COMPONENTS)}")
    found = {}
    n = db.envelope_max.shape[0]
    for i in range(n):
        for comp in components:
            j = COMPONENTS.index(comp)
            for extreme, case, rows in (("max", db.max_case, db.max_snapshot), ("min", db.min_case, db.min_snapshot)):
                c = int(case[i, j])
                k = int(rows[c, i, j])
                found.setdefault(k, (c, []))[1].append((i, comp, extreme))
    names = [s.decode() for s in db.cases["name"]]
    return [LoadSet(first_sid + m, c, names[c], tuple(crit), db.snapshots[k])
            for m, (k, (c, crit)) in enumerate(found.items())]


def nastran_real(x: float) -> str:
    """The most precise Nastran real of at most 8 characters (``1.2346+5``, ``-.707107``, ``0.``).

    Parameters
    ----------
    x : float
        The number.

    Returns
    -------
    str
        The field text.
    """
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"card value {x}: not finite")
    if x == 0.0:
        return "0."
    cands = []
    for p in range(8):
        s = f"{x:.{p}f}"
        s = s if "." in s else s + "."
        s = s.replace("0.", ".", 1) if s.startswith(("0.", "-0.")) and abs(x) < 1 else s
        cands.append(s)
    for p in range(7):
        mant, exp = f"{x:.{p}e}".split("e")
        mant = mant if "." in mant else mant + "."
        cands.append(f"{mant}{'+' if int(exp) >= 0 else '-'}{abs(int(exp))}")
    ok = [s for s in cands if len(s) <= 8 and _REAL.match(s) and parse_nastran_real(s) != 0.0]
    if not ok:
        raise ValueError(f"card value {x:g}: no 8-character Nastran real")
    return min(ok, key=lambda s: (abs(parse_nastran_real(s) - x), len(s)))


def parse_nastran_real(text: str) -> float:
    """A Nastran real field (``1.2346+5``, ``1.2E-3``, ``-.5``, ``3.``) as a float.

    Parameters
    ----------
    text : str
        The field text.

    Returns
    -------
    float
        The value.
    """
    m = _REAL.match(text.strip())
    if not m:
        raise ValueError(f"{text!r} is not a Nastran real")
    return float(m.group(1)) * 10.0 ** int(m.group(2) or 0)


def _field(value) -> str:
    s = value if isinstance(value, str) else str(value)
    if len(s) > 8:
        raise ValueError(f"{s!r} does not fit an 8-character field")
    return f"{s:>8}"


def _describe(ls: LoadSet, limit=6) -> str:
    crit = ", ".join(f"station {i} {c} {e}" for i, c, e in ls.critical_for[:limit])
    more = f" and {len(ls.critical_for) - limit} more" if len(ls.critical_for) > limit else ""
    return f"case {ls.case_name}: critical for {crit}{more}"


def _vector_card(name, sid, grid, v):
    mag = float(np.linalg.norm(v))
    if mag == 0.0:
        return None
    u = np.asarray(v, dtype=float) / mag
    return (f"{name:<8}" + _field(sid) + _field(grid) + _field(0) + _field(nastran_real(mag))
            + "".join(_field(nastran_real(c)) for c in u))


def nastran_cards(load_sets, node_positions, node_euler_angles, first_id: int = 1) -> str:
    """FORCE and MOMENT bulk data of every load set (small field, basic frame).

    Parameters
    ----------
    load_sets : sequence of LoadSet
        The load sets.
    node_positions : array_like
        (n, 3) jig node positions, body axes (m).
    node_euler_angles : array_like
        (n, 3) jig Euler angles of the nodes' csn frames (rad).
    first_id : int, optional
        Node id of the first beam node.

    Returns
    -------
    str
        The bulk data.
    """
    lines = ["$ wingmdao loads: nodal loads of the critical cases (N, N m, basic frame); beam node k is GRID "
             f"{first_id} + k from the root"]
    for ls in load_sets:
        P, Q = nodal_loads(ls.snapshot, node_positions, node_euler_angles)
        lines.append(f"$ SID {ls.sid}: " + _describe(ls))
        for k in range(P.shape[0]):
            for card in (_vector_card("FORCE", ls.sid, first_id + k, P[k]),
                         _vector_card("MOMENT", ls.sid, first_id + k, Q[k])):
                if card:
                    lines.append(card)
    return "\n".join(lines) + "\n"


def calculix_cards(load_sets, node_positions, node_euler_angles, first_id: int = 1) -> str:
    """One static step per load set with its ``*CLOAD`` (DOFs 1-3 forces, 4-6 moments).

    Parameters
    ----------
    load_sets : sequence of LoadSet
        The load sets.
    node_positions : array_like
        (n, 3) jig node positions, body axes (m).
    node_euler_angles : array_like
        (n, 3) jig Euler angles of the nodes' csn frames (rad).
    first_id : int, optional
        Node id of the first beam node.

    Returns
    -------
    str
        The steps.
    """
    lines = ["** wingmdao loads: nodal loads of the critical cases (N, N m, global frame); beam node k is node "
             f"{first_id} + k from the root; include after the model definition"]
    for ls in load_sets:
        P, Q = nodal_loads(ls.snapshot, node_positions, node_euler_angles)
        lines += [f"** load set {ls.sid}: " + _describe(ls), "*STEP", "*STATIC", "*CLOAD, OP=NEW"]
        for k in range(P.shape[0]):
            for dof, value in enumerate(np.concatenate([P[k], Q[k]]), start=1):
                if value != 0.0:
                    lines.append(f"{first_id + k}, {dof}, {value:.12e}")
        lines.append("*END STEP")
    return "\n".join(lines) + "\n"


def _write_atomic(text, path):
    tmp = os.path.join(os.path.dirname(os.path.abspath(path)), f".{os.path.basename(path)}.tmp")
    with open(tmp, "w", encoding="utf-8") as fh:
        fh.write(text)
    os.replace(tmp, path)
    return path


def write_cards(db, nastran_path: str, calculix_path: str, components=PRIMARY) -> list:
    """Write both card files of the critical cases of ``db`` (atomically); returns the load sets.

    Parameters
    ----------
    db : LoadsDatabase
        The loads database.
    nastran_path : str
        Nastran bulk-data file to write.
    calculix_path : str
        CalculiX steps file to write.
    components : sequence of str, optional
        csn components screened.

    Returns
    -------
    list of LoadSet
        The load sets written.
    """
    sets = critical_load_sets(db, components)
    _write_atomic(nastran_cards(sets, db.node_positions, db.node_euler_angles), nastran_path)
    _write_atomic(calculix_cards(sets, db.node_positions, db.node_euler_angles), calculix_path)
    return sets


def read_nastran_loads(text: str, num_nodes: int, first_id: int = 1) -> dict:
    """{SID: (forces (n, 3), moments (n, 3))} from FORCE/MOMENT small-field cards (other lines ignored).

    Parameters
    ----------
    text : str
        Bulk-data text.
    num_nodes : int
        Number of beam nodes.
    first_id : int, optional
        Node id of the first beam node.

    Returns
    -------
    dict
        SID -> (forces (n, 3), moments (n, 3)).
    """
    out = {}
    for line in text.splitlines():
        name = line[:8].strip()
        if name not in ("FORCE", "MOMENT"):
            continue
        f = [line[8 * i:8 * (i + 1)] for i in range(1, 8)]
        sid, grid, cid = int(f[0]), int(f[1]), int(f[2])
        if cid != 0:
            raise ValueError(f"{name} card with CID {cid}: only the basic frame (0) is read")
        vec = parse_nastran_real(f[3]) * np.array([parse_nastran_real(s) for s in f[4:7]])
        P, Q = out.setdefault(sid, (np.zeros((num_nodes, 3)), np.zeros((num_nodes, 3))))
        (P if name == "FORCE" else Q)[grid - first_id] += vec
    return out


def read_calculix_cloads(text: str, num_nodes: int, first_id: int = 1) -> list:
    """[(forces (n, 3), moments (n, 3))] of every ``*CLOAD`` block, in order.

    Parameters
    ----------
    text : str
        CalculiX input text.
    num_nodes : int
        Number of beam nodes.
    first_id : int, optional
        Node id of the first beam node.

    Returns
    -------
    list of tuple
        (forces (n, 3), moments (n, 3)) per ``*CLOAD`` block.
    """
    out, current = [], None
    for line in text.splitlines():
        s = line.strip()
        if s.upper().startswith("*CLOAD"):
            current = (np.zeros((num_nodes, 3)), np.zeros((num_nodes, 3)))
            out.append(current)
        elif s.startswith("*"):
            current = None
        elif current is not None and s:
            node, dof, value = (t.strip() for t in s.split(","))
            d = int(dof)
            (current[0] if d <= 3 else current[1])[int(node) - first_id, (d - 1) % 3] += float(value)
    return out
