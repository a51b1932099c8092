"""Loads-engineer output of an envelope sizing: critical case per station, load envelopes, potato plots.

From the internal loads of every load case (``cases.<name>.internal_loads.F_csn``/``M_csn``,
(n_time, n, 3) in the local csn frame: c chordwise, s along the beam, n normal) and the stress
constraints ``cases.<name>.stress.g_<family>`` (g = sigma/sigma_allow - 1):

* **critical case per station**: the case (and time) with the largest g over time steps, stress
  points and families at that station (a table, CSV, and a plot along the span);
* **envelope** along the span of the shear F_n, the bending moment M_c (about the chordwise
  axis, vertical bending) and the torsion M_s: maximum and minimum over all cases and time steps;
* **potato plots** (correlated loads): M_c against M_s at chosen stations, every time step of every
  case one point; the convex hull of all points is the envelope of simultaneous bending and
  torsion that the section must carry, its extreme corners the design points. How to read
  them: ``docs/gust-envelope.md``. A sizing with the 25.341(b) constraint adds, at each potato
  station, the continuous turbulence's equal-probability ellipse of (M_s, M_c) about its 1 g loads
  and its four correlated design points (:func:`add_turbulence`).

The loads are saved to ``<stem>_envelope.npz`` (written atomically) so that
``wingmdao report`` can redraw the plots from a finished run.
"""

from __future__ import annotations

import os

import numpy as np

from wingmdao.loads.turbulence import correlated_loads, equal_probability_ellipse
from wingmdao.design import case_families, span_coordinate
from wingmdao.plots import pyplot_agg, save_figure

QUANTITIES = {  # name: (array, component, label, scale to plot units, unit)
    "shear": ("F", 2, "shear F_n", 1e-3, "kN"),
    "bending": ("M", 0, "bending M_c", 1e-3, "kN m"),
    "torsion": ("M", 1, "torsion M_s", 1e-3, "kN m"),
}


def collect(prob, load_cases, span, families=None) -> dict:
    """Internal loads and worst constraint value per station of every case from a run problem: every
    family the case's KS aggregates (``families``: {case name: families}, default the case's stress
    families; a stiffened box adds its panel modes, :func:`wingmdao.design.case_families`).

    Parameters
    ----------
    prob : openmdao.api.Problem
        A run sizing problem.
    load_cases : sequence of LoadCase
        Its load cases.
    span : array_like
        (n,) span coordinate of the stations (m).
    families : dict or None, optional
        Case name -> constraint families; None for the cases' own.

    Returns
    -------
    dict
        Per case the internal-load histories and the worst constraint per station.
    """
    names, data = [], {}
    for case in load_cases:
        p = f"cases.{case.name}"
        fams = case.families if families is None else families[case.name]
        g = np.max(np.stack([np.asarray(prob.get_val(f"{p}.{'stress' if f in case.families else 'panels'}.g_{f}"))
                             .max(axis=2) for f in fams]), axis=0)
        # a case combined with a symmetric one: both wings, symmetric + increment then - increment
        src = f"{p}.{getattr(case, 'loads_path', 'internal_loads')}"
        time = np.tile(np.asarray(case.time), getattr(case, "num_stress_times", len(case.time)) // len(case.time))
        data[f"F__{case.name}"] = np.asarray(prob.get_val(f"{src}.F_csn", units="N"))
        data[f"M__{case.name}"] = np.asarray(prob.get_val(f"{src}.M_csn", units="N*m"))
        data[f"g__{case.name}"] = g  # (nt, n)
        data[f"t__{case.name}"] = time
        names.append(case.name)
    data["case_names"] = np.array(names)
    data["span"] = np.asarray(span, dtype=float)
    return data


#: keys of the continuous-turbulence loads in the envelope data (:func:`add_turbulence`)
TURBULENCE_KEYS = ("turbulence_u_sigma", "turbulence_Mc_1g", "turbulence_Mc_abar", "turbulence_Ms_1g",
                   "turbulence_Ms_abar", "turbulence_rho")


def add_turbulence(data: dict, loads: dict) -> dict:
    """Add the 25.341(b) loads of :func:`wingmdao.sizing.turbulence_loads` (per station: 1 g and
    A-bar of M_c and M_s, their correlation; U_sigma) to the envelope ``data``; returns it.

    Parameters
    ----------
    data : dict
        Envelope data (:func:`collect`).
    loads : dict
        The ``turbulence_loads`` of the design.

    Returns
    -------
    dict
        ``data``.
    """
    data["turbulence_u_sigma"] = np.array(float(loads["u_sigma_m_s"]))
    data["turbulence_Mc_1g"] = np.asarray(loads["bending_moment"]["one_g"], dtype=float)
    data["turbulence_Mc_abar"] = np.asarray(loads["bending_moment"]["a_bar"], dtype=float)
    data["turbulence_Ms_1g"] = np.asarray(loads["torsion"]["one_g"], dtype=float)
    data["turbulence_Ms_abar"] = np.asarray(loads["torsion"]["a_bar"], dtype=float)
    data["turbulence_rho"] = np.asarray(loads["bending_torsion_correlation"], dtype=float)
    return data


def turbulence_ellipse(data: dict, station: int):
    """((n, 2) ellipse, (4, 2) correlated design points) of (M_s, M_c) in N m at ``station``, or
    (None, None) when the data hold no turbulence loads.

    Parameters
    ----------
    data : dict
        Envelope data (:func:`collect`).
    station : int
        Station index.

    Returns
    -------
    tuple
        Ellipse (n, 2) and design points (4, 2) (N m), or (None, None).
    """
    if "turbulence_rho" not in data:
        return None, None
    i = int(station)
    center = (data["turbulence_Ms_1g"][i], data["turbulence_Mc_1g"][i])
    a_bar = (data["turbulence_Ms_abar"][i], data["turbulence_Mc_abar"][i])
    u, rho = float(data["turbulence_u_sigma"]), float(data["turbulence_rho"][i])
    return equal_probability_ellipse(center, u, a_bar, rho), correlated_loads(center, u, a_bar, rho)


def save(data: dict, path: str) -> str:
    """Atomic NPZ write (temporary file in the same folder, then os.replace).

    Parameters
    ----------
    data : dict
        Envelope data (:func:`collect`).
    path : str
        NPZ file to write.

    Returns
    -------
    str
        ``path``.
    """
    tmp = path + ".tmp.npz"
    np.savez_compressed(tmp, **data)
    os.replace(tmp, path)
    return path


def load(path: str) -> dict:
    """Read envelope data written by :func:`save`; ValueError naming a missing file.

    Parameters
    ----------
    path : str
        NPZ file written by :func:`save`.

    Returns
    -------
    dict
        The envelope data.
    """
    if not os.path.exists(path):
        raise ValueError(f"envelope file {path!r} does not exist (written by 'wingmdao size')")
    with np.load(path, allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


def _names(data):
    return [str(n) for n in data["case_names"]]


def critical_cases(data: dict) -> list:
    """Per station: the case, time and value of the largest stress ratio g over all cases.

    Parameters
    ----------
    data : dict
        Envelope data (:func:`collect`).

    Returns
    -------
    list of dict
        Per station: ``station``, ``span_m``, ``case``, ``g_max``, ``time_s``.
    """
    names = _names(data)
    n = data["span"].size
    rows = []
    for i in range(n):
        best = (-np.inf, None, 0.0)
        for name in names:
            g = data[f"g__{name}"][:, i]
            k = int(np.argmax(g))
            if g[k] > best[0]:
                best = (float(g[k]), name, float(data[f"t__{name}"][k]))
        rows.append({"station": i, "span_m": float(data["span"][i]), "case": best[1], "g_max": best[0],
                     "time_s": best[2]})
    return rows


def envelope(data: dict) -> dict:
    """``{quantity: {"max", "min" (n,) SI, "max_case", "min_case" (n,) names}}`` over cases and time.

    Parameters
    ----------
    data : dict
        Envelope data (:func:`collect`).

    Returns
    -------
    dict
        Quantity -> maxima, minima and their cases.
    """
    names = _names(data)
    out = {}
    for q, (arr, comp, *_rest) in QUANTITIES.items():
        stack = [data[f"{arr}__{name}"][:, :, comp] for name in names]
        hi = np.array([s.max(axis=0) for s in stack])  # (n_case, n)
        lo = np.array([s.min(axis=0) for s in stack])
        out[q] = {"max": hi.max(axis=0), "min": lo.min(axis=0),
                  "max_case": [names[j] for j in hi.argmax(axis=0)],
                  "min_case": [names[j] for j in lo.argmin(axis=0)]}
    return out


def format_critical_table(rows) -> str:
    """The critical-case table as text: station, span, case, largest g and its time.

    Parameters
    ----------
    rows : list of dict
        Rows of :func:`critical_cases`.

    Returns
    -------
    str
        The table.
    """
    lines = [f"{'station':>7} {'y [m]':>7} {'critical case':<28} {'g max':>9} {'t [s]':>7}"]
    for r in rows:
        lines.append(f"{r['station']:7d} {r['span_m']:7.3f} {str(r['case']):<28} {r['g_max']:9.4f} {r['time_s']:7.3f}")
    return "\n".join(lines)


def _write_csv(rows, path):
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as fh:
        fh.write("station,span_m,critical_case,g_max,time_s\n")
        for r in rows:
            fh.write(f"{r['station']},{r['span_m']:.6g},{r['case']},{r['g_max']:.8g},{r['time_s']:.6g}\n")
    os.replace(tmp, path)
    return path


def _hull(points):
    """Convex hull (Andrew's monotone chain), counter-clockwise, closed."""
    pts = sorted(set(map(tuple, np.round(points, 12))))
    if len(pts) < 3:
        return np.array(pts + pts[:1])

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    hull = lower[:-1] + upper[:-1]
    return np.array(hull + hull[:1])


#: A second moment component whose range is below this fraction of the first's is round-off (e.g.
#: the yaw moment of a fuselage in symmetric flight): the potato pairs the moment with a force.
POTATO_NEGLIGIBLE = 1e-3


def monitoring_potatoes(loads: dict) -> dict:
    """Potato plots of monitoring stations (:func:`wingmdao.beam.joints.monitoring_loads` histories):
    for each ``{label: {"moment": (n_time, 3) N m, "force": (n_time, 3) N}}`` the correlated pair of
    the moment component with the largest range over the history and the moment component with the
    next largest (bending and torsion of a wing or tail root) or, when that one's range is below
    :data:`POTATO_NEGLIGIBLE` of the first's (a fuselage in symmetric flight), the force component
    with the largest range (bending and shear); ``components`` (their names, ``"M_x"``, ``"F_z"``,
    ... in body axes), ``values`` ((n_time, 2), N m or N) and ``hull``, the convex hull of the pairs
    ((k, 2), closed, counter-clockwise), as the wing stations' potato plots (:func:`write_plots`).

    Parameters
    ----------
    loads : dict
        Label -> ``{"moment": (n_time, 3), "force": (n_time, 3)}`` histories (N m, N).

    Returns
    -------
    dict
        Label -> ``components``, ``values`` and ``hull``.
    """
    out = {}
    for label, v in loads.items():
        m = np.asarray(v["moment"], dtype=float).reshape(-1, 3)
        f = np.asarray(v.get("force", np.zeros_like(m)), dtype=float).reshape(-1, 3)
        rm, rf = np.ptp(m, axis=0), np.ptp(f, axis=0)
        i, j = (int(k) for k in np.argsort(-rm)[:2])
        if rm[j] >= POTATO_NEGLIGIBLE * rm[i]:
            second, name = m[:, j], f"M_{'xyz'[j]}"
        else:
            k = int(np.argmax(rf))
            second, name = f[:, k], f"F_{'xyz'[k]}"
        values = np.column_stack([m[:, i], second])
        out[label] = {"components": [f"M_{'xyz'[i]}", name], "values": values, "hull": _hull(values)}
    return out


def default_stations(n: int) -> list:
    """The default potato-plot stations of a beam of ``n`` stations.

    Parameters
    ----------
    n : int
        Number of stations.

    Returns
    -------
    list of int
        Station 1 (next to the root), mid-span and 3/4 span.
    """
    return sorted({min(1, n - 1), n // 2, max(0, (3 * n) // 4)})


def check_stations(stations, n: int) -> list:
    """The potato-plot stations (``--potato-stations``) of a beam of ``n`` stations, checked before
    anything is solved or drawn; the default (root, mid, 3/4 span) for None.

    Parameters
    ----------
    stations : sequence of int or None
        Requested stations.
    n : int
        Number of stations.

    Returns
    -------
    list of int
        The checked stations.
    """
    if stations is None:
        return default_stations(n)
    bad = [i for i in stations if not 0 <= i <= n - 1]
    if bad:
        raise ValueError(f"--potato-stations {' '.join(str(i) for i in bad)}: station indices; allowed range "
                         f"[0, {n - 1}] ({n} stations)")
    return list(stations)


def output_paths(stem: str, plots: bool = True) -> list:
    """Files :func:`write_envelope_outputs` writes for ``stem``: the loads file and, with ``plots``,
    the critical-case CSV and the PNGs.

    Parameters
    ----------
    stem : str
        Path stem of the outputs.
    plots : bool, optional
        Include the plots and CSV.

    Returns
    -------
    list of str
        The files.
    """
    paths = [f"{stem}_envelope.npz"]
    if plots:
        paths += [f"{stem}_critical_cases.csv", f"{stem}_critical_case.png", f"{stem}_envelope.png",
                  f"{stem}_potato.png"]
    return paths


def write_plots(data: dict, stem: str, stations=None) -> list:
    """PNG plots (critical case, envelopes, potato plots) and the critical-case CSV next to ``stem``.

    Parameters
    ----------
    data : dict
        Envelope data (:func:`collect`).
    stem : str
        Path stem of the outputs.
    stations : sequence of int or None, optional
        Potato-plot stations; None for the default.

    Returns
    -------
    list of str
        The files written.
    """
    stations = check_stations(stations, data["span"].size)  # before anything is written
    plt = pyplot_agg()
    names = _names(data)
    span = data["span"]
    paths = []
    rows = critical_cases(data)
    paths.append(_write_csv(rows, f"{stem}_critical_cases.csv"))

    # critical case along the span
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True, gridspec_kw={"height_ratios": [1, 1.3]})
    a1.plot(span, [r["g_max"] for r in rows], marker="o", ms=3, color="k")
    a1.axhline(0.0, color="tab:red", lw=0.8)
    a1.set_ylabel("max g = sigma/sigma_allow - 1")
    a1.grid(True, alpha=0.3)
    idx = [names.index(r["case"]) for r in rows]
    a2.scatter(span, idx, c=idx, cmap="tab20", vmin=0, vmax=max(len(names) - 1, 1), s=30)
    a2.set_yticks(range(len(names)))
    a2.set_yticklabels(names, fontsize=7)
    a2.set_ylabel("critical load case")
    a2.set_xlabel("spanwise station y [m]")
    a2.grid(True, alpha=0.3)
    fig.suptitle("Critical load case per station")
    paths.append(save_figure(fig, f"{stem}_critical_case.png"))

    # envelopes
    env = envelope(data)
    fig, axes = plt.subplots(3, 1, figsize=(9, 9), sharex=True)
    for ax, (q, (arr, comp, label, scale, unit)) in zip(axes, QUANTITIES.items()):
        for name in names:
            x = data[f"{arr}__{name}"][:, :, comp] * scale
            ax.plot(span, x.max(axis=0), color="0.75", lw=0.6)
            ax.plot(span, x.min(axis=0), color="0.75", lw=0.6)
        ax.fill_between(span, env[q]["min"] * scale, env[q]["max"] * scale, color="tab:blue", alpha=0.25,
                        label="envelope (all cases, all time steps)")
        ax.plot(span, env[q]["max"] * scale, color="tab:blue")
        ax.plot(span, env[q]["min"] * scale, color="tab:blue")
        ax.set_ylabel(f"{label} [{unit}]")
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[-1].set_xlabel("spanwise station y [m]")
    fig.suptitle("Internal load envelope (grey: each case's max/min over time)")
    paths.append(save_figure(fig, f"{stem}_envelope.png"))

    # potato plots
    fig, axes = plt.subplots(1, len(stations), figsize=(5 * len(stations), 4.6), squeeze=False)
    cmap = plt.get_cmap("tab20")
    for ax, i in zip(axes[0], stations):
        allpts = []
        for j, name in enumerate(names):
            mt = data[f"M__{name}"][:, i, 1] * 1e-3
            mb = data[f"M__{name}"][:, i, 0] * 1e-3
            allpts.append(np.column_stack([mt, mb]))
            if mt.size == 1:
                ax.plot(mt, mb, "s", color=cmap(j % 20), ms=6, label=name)
            else:
                ax.plot(mt, mb, "-", color=cmap(j % 20), lw=0.8, label=name)
        hull = _hull(np.vstack(allpts))
        ax.plot(hull[:, 0], hull[:, 1], "k--", lw=1.0, label="convex hull")
        ellipse, design = turbulence_ellipse(data, i)
        if ellipse is not None:  # 25.341(b): 1 g +/- U_sigma A-bar, correlated
            ax.plot(ellipse[:, 0] * 1e-3, ellipse[:, 1] * 1e-3, "-", color="tab:purple", lw=1.4,
                    label="continuous turbulence (equal-probability ellipse)")
            ax.plot(design[:, 0] * 1e-3, design[:, 1] * 1e-3, "D", color="tab:purple", ms=5,
                    label="continuous turbulence: correlated design loads")
        ax.set_xlabel("torsion M_s [kN m]")
        ax.set_ylabel("bending M_c [kN m]")
        ax.set_title(f"station {i}, y = {span[i]:.2f} m")
        ax.grid(True, alpha=0.3)
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=7, loc="lower center", ncol=min(6, len(labels)))
    fig.suptitle("Correlated loads (potato plots): bending vs torsion, all cases and time steps")
    paths.append(save_figure(fig, f"{stem}_potato.png", rect=(0, 0.06 + 0.03 * (len(labels) // 6), 1, 1)))
    return paths


def write_envelope_outputs(prob, setup, stem: str, stations=None, plots: bool = True, turbulence=None) -> dict:
    """Collect, save ``<stem>_envelope.npz`` and (``plots``) write the PNGs; returns paths and the table.
    ``turbulence``: the 25.341(b) loads of the design (:func:`wingmdao.sizing.turbulence_loads`),
    drawn on the potato plots.

    Parameters
    ----------
    prob : openmdao.api.Problem
        A run sizing problem.
    setup : object
        The case's sizing set-up.
    stem : str
        Path stem of the outputs.
    stations : sequence of int or None, optional
        Potato-plot stations.
    plots : bool, optional
        Write the PNGs and CSV.
    turbulence : dict or None, optional
        The design's 25.341(b) loads.

    Returns
    -------
    dict
        Paths and the critical-case table.
    """
    families = {c.name: case_families(c, setup.section, setup.panels) for c in setup.load_cases}
    data = collect(prob, setup.load_cases, span_coordinate(setup.geometry), families)
    if turbulence is not None:
        add_turbulence(data, turbulence)
    out = {"envelope_file": save(data, f"{stem}_envelope.npz"), "critical_cases": critical_cases(data)}
    out["plots"] = write_plots(data, stem, stations) if plots else []
    return out


def stick_set_envelope(gusts) -> dict:
    """Envelopes of the monitoring stations over a set of stick gusts.

    Parameters
    ----------
    gusts : list of dict
        One entry per gust: ``name`` and ``monitoring_loads`` (``{label: {"force_n", "moment_n_m":
        (n_time, 3)}}``, as ``wingmdao gust --model stick`` writes them).

    Returns
    -------
    dict
        Per station: ``force_max_n``, ``force_min_n``, ``moment_max_n_m``, ``moment_min_n_m`` (3 each,
        over every instant of every gust), the gusts that give them (``force_max_gust``, ...), and the
        potato plot of the set (``potato_components``, ``potato_hull``: the convex hull of the pair over
        every gust, :func:`wingmdao.envelope.monitoring_potatoes` of the gusts' histories joined).
    """
    labels = list(gusts[0]["monitoring_loads"])
    joined = {lb: {"force": np.vstack([np.asarray(g["monitoring_loads"][lb]["force_n"]) for g in gusts]),
                   "moment": np.vstack([np.asarray(g["monitoring_loads"][lb]["moment_n_m"]) for g in gusts])}
              for lb in labels}
    potatoes = monitoring_potatoes(joined)
    owner = np.concatenate([np.full(len(g["monitoring_loads"][labels[0]]["force_n"]), k) for k, g in enumerate(gusts)])
    out = {}
    for lb in labels:
        entry = {}
        for key, unit in (("force", "n"), ("moment", "n_m")):
            a = joined[lb][key]
            entry[f"{key}_max_{unit}"] = a.max(axis=0).tolist()
            entry[f"{key}_min_{unit}"] = a.min(axis=0).tolist()
            entry[f"{key}_max_gust"] = [gusts[owner[i]]["name"] for i in a.argmax(axis=0)]
            entry[f"{key}_min_gust"] = [gusts[owner[i]]["name"] for i in a.argmin(axis=0)]
        entry["potato_components"] = potatoes[lb]["components"]
        entry["potato_hull"] = potatoes[lb]["hull"].tolist()
        out[lb] = entry
    return out
