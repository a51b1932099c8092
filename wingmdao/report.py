"""Read a sizing run's SQLite recording: iteration history, final design, plots."""

from __future__ import annotations

import os

import numpy as np
import openmdao.api as om

from wingmdao.plots import WALLS, plot_iteration_history, plot_thickness


def constraint_margin(value, meta: dict) -> np.ndarray:
    """Signed distance of a constraint value to its bounds (unscaled): ``value - upper``,
    ``lower - value``, ``|value - equals|``; <= 0 where satisfied (equality: 0 only when met).
    A KS constraint ``ks <= 0`` keeps its own value; without bounds the value itself.

    Parameters
    ----------
    value : array_like
        Constraint value (unscaled).
    meta : dict
        OpenMDAO constraint metadata (``upper``, ``lower``, ``equals``, ``name``).

    Returns
    -------
    numpy.ndarray
        Margin; <= 0 where satisfied.
    """
    v = np.asarray(value, dtype=float).ravel()
    terms = []
    if meta.get("equals") is not None:
        terms.append(np.abs(v - np.asarray(meta["equals"], dtype=float).ravel()))
    for key, sign in (("upper", 1.0), ("lower", -1.0)):
        b = meta.get(key)
        if b is not None and np.all(np.abs(np.asarray(b, dtype=float)) < 1e29):   # OpenMDAO's "no bound" is +-1e30
            terms.append(sign * (v - np.asarray(b, dtype=float).ravel()))
    return np.max(terms, axis=0) if terms else v


def read_history(path: str) -> dict:
    """Objective, worst constraint margin (:func:`constraint_margin`, <= 0 when every constraint
    holds) and design variables of every recorded driver iteration.

    Parameters
    ----------
    path : str
        SQLite recording of a sizing.

    Returns
    -------
    dict
        ``iterations``, and per iteration ``objective``, ``max_constraint``, ``design_vars`` and
        ``failed``; ``final_constraints`` of the last one.
    """
    if not os.path.exists(path):
        raise ValueError(f"recording {path!r} does not exist")
    if os.path.isdir(path):
        raise ValueError(f"recording {path!r} is a folder, not an SQLite recording")
    try:
        reader = om.CaseReader(path)
        cases = reader.list_cases("driver", recurse=False, out_stream=None)
    except Exception as exc:  # not SQLite, or SQLite without OpenMDAO's tables
        raise ValueError(f"{path!r} is not an OpenMDAO recording of a sizing run ({exc})") from exc
    if not cases:
        raise ValueError(f"recording {path!r} holds no driver iterations")
    meta = reader.problem_metadata.get("variables", {})
    objective, worst, desvars, failed = [], [], [], []
    final = {}
    for cid in cases:
        case = reader.get_case(cid)
        # an evaluation whose analysis failed (wingmdao.optimize.BackoffSLSQPDriver records it with
        # success = 0): its outputs are not a solution, so objective and constraint are NaN
        failed.append(not case.success)
        obj = case.get_objectives()
        objective.append(float(np.ravel(next(iter(obj.values())))[0]) if obj and case.success else np.nan)
        cons = case.get_constraints()
        worst.append(max((float(np.max(constraint_margin(v, meta.get(k, {})))) for k, v in cons.items()),
                         default=np.nan) if case.success else np.nan)
        desvars.append({k: np.array(v) for k, v in case.get_design_vars().items()})
        if case.success:
            final = {k: float(np.max(v)) for k, v in cons.items()}
    return {"iterations": len(cases), "objective": np.array(objective),
            "max_constraint": np.array(worst), "design_vars": desvars, "failed": np.array(failed, dtype=bool),
            "final_constraints": final}


def format_margins(hist: dict) -> str:
    """The KS constraints of the last successful iteration with their margins of safety.

    Every stress and panel family is ``g = factor * ratio - 1`` (ratio 1 = failure), so its
    margin of safety is 1 / (g + 1) - 1; KS lies above the largest ratio it aggregates, so this
    margin is a lower bound of the design's. The flutter constraint (a decay rate) and the linear
    sizing rules are listed with their values only.

    Parameters
    ----------
    hist : dict
        Recorded history (:func:`read_history`).

    Returns
    -------
    str
        The table.
    """
    lines = [f"{'constraint':58s} {'value':>12s} {'margin of safety':>17s}"]
    for name, g in sorted(hist.get("final_constraints", {}).items()):
        if name.startswith("rules."):
            continue
        ratio_family = ".ks_" in name or name.startswith("ks_")
        ms = f"{round(1.0 / (g + 1.0) - 1.0, 3) + 0.0:+17.3f}" if ratio_family and g > -1.0 else f"{'':>17s}"
        lines.append(f"{name:58s} {g:+12.4e} {ms}")
    return "\n".join(lines)


def best_design(hist: dict, tol: float = 1e-6) -> dict | None:
    """The recorded iteration with the lowest objective among the feasible ones (every constraint
    margin <= ``tol``), else among all whose analysis did not fail: iteration, objective, max
    constraint, feasible, design variables; None when every recorded analysis failed.

    Parameters
    ----------
    hist : dict
        Recorded history (:func:`read_history`).
    tol : float, optional
        Largest constraint margin counted as feasible.

    Returns
    -------
    dict or None
        The iteration's record, or None.
    """
    feasible = np.flatnonzero(np.nan_to_num(hist["max_constraint"], nan=np.inf) <= tol)
    failed = hist.get("failed", np.zeros(hist["iterations"], dtype=bool))
    pool = feasible if feasible.size else np.flatnonzero(~failed)  # never a failed analysis
    if not pool.size:
        return None
    k = int(pool[np.nanargmin(hist["objective"][pool])])
    return {"iteration": k, "objective": float(hist["objective"][k]),
            "max_constraint": float(hist["max_constraint"][k]), "feasible": bool(feasible.size),
            "design_vars": {n: np.asarray(v).tolist() for n, v in hist["design_vars"][k].items()}}


def format_history(hist: dict) -> str:
    """The iteration table of a recorded history: objective and worst constraint margin, failed analyses marked.

    Parameters
    ----------
    hist : dict
        Recorded history (:func:`read_history`).

    Returns
    -------
    str
        One line per iteration.
    """
    lines = [f"{'iter':>5} {'objective':>14} {'max constraint':>15}"]
    failed = hist.get("failed", np.zeros(len(hist["objective"]), dtype=bool))
    for i, (f, g, bad) in enumerate(zip(hist["objective"], hist["max_constraint"], failed)):
        lines.append(f"{i:5d} {'analysis failed (SLSQP backed off)':>30}" if bad else f"{i:5d} {f:14.6g} {g:15.4e}")
    return "\n".join(lines)


def final_thickness(hist: dict) -> dict | None:
    """``{wall: (n,) m}`` of the last recorded iteration, or None when the design variables are not walls.

    Parameters
    ----------
    hist : dict
        Recorded history (:func:`read_history`).

    Returns
    -------
    dict or None
        Wall -> (n,) thickness (m), or None.
    """
    final = hist["design_vars"][-1]
    thick = {}
    for wall in WALLS:
        match = [k for k in final if k.endswith(f"t_{wall}")]
        if match:
            thick[wall] = final[match[0]]
    return thick if len(thick) == len(WALLS) else None


def write_comparison_plot(histories: dict, path: str) -> str:
    """Final thicknesses of several recorded runs on one figure (Fig. 5.5-5.6: static vs gust sizing).

    ``histories`` maps a label to :func:`read_history` output; all runs must size walls of the
    same number of design stations.

    Parameters
    ----------
    histories : dict
        Label -> recorded history.
    path : str
        PNG to write.

    Returns
    -------
    str
        ``path``.
    """
    runs = {}
    for label, hist in histories.items():
        thick = final_thickness(hist)
        if thick is None:
            raise ValueError(f"recording {label!r}: design variables are not the four wall thicknesses")
        runs[label] = thick
    sizes = {len(t["upper_skin"]) for t in runs.values()}
    if len(sizes) != 1:
        raise ValueError(f"recordings have different numbers of design stations: {sorted(sizes)}")
    n = sizes.pop()
    return plot_thickness(np.arange(n), runs, path, title="Final thickness per design station (index)")


def write_report_plots(hist: dict, out_dir: str) -> list[str]:
    """Iteration history PNG (and final thickness PNG when the design variables are wall thicknesses).

    Parameters
    ----------
    hist : dict
        Recorded history (:func:`read_history`).
    out_dir : str
        Folder for the PNG files.

    Returns
    -------
    list of str
        The files written.
    """
    os.makedirs(out_dir, exist_ok=True)
    paths = [plot_iteration_history(hist["objective"], hist["max_constraint"],
                                    os.path.join(out_dir, "iterations.png"))]
    thick = final_thickness(hist)
    if thick is not None:
        n = len(thick["upper_skin"])
        paths.append(plot_thickness(np.arange(n), {"final": thick},
                                    os.path.join(out_dir, "thickness_final.png"),
                                    title="Final thickness per station (index)"))
    return paths
