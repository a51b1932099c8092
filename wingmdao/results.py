"""Plots of a finished sizing problem: thickness along the span, stress and load time histories."""

from __future__ import annotations

import numpy as np

from wingmdao.plots import plot_panels, plot_thickness, plot_time_history
from wingmdao.sizing import span_coordinate  # noqa: F401  (also this module's public name)
from wingmdao.sizing import station_values


def write_case_plots(prob, setup, stem: str, result: dict | None = None) -> list[str]:
    """PNG plots next to ``stem``: thickness, and for dynamic cases stress and load histories.

    Parameters
    ----------
    prob : openmdao.api.Problem
        The run sizing problem.
    setup : object
        The case's sizing set-up.
    stem : str
        Path stem of the PNG files.
    result : dict or None, optional
        The result JSON, for the panel plot.

    Returns
    -------
    list of str
        The files written.
    """
    span = span_coordinate(setup.geometry)
    paths = []
    if setup.section in ("box", "stiffened"):
        thick = {w: station_values(prob, f"t_{w}") for w in
                 ("upper_skin", "lower_skin", "front_spar", "rear_spar")}
        paths.append(plot_thickness(span, {"sized": thick}, f"{stem}_thickness.png"))
    if result is not None and "panels" in result:
        paths.append(plot_panels(span, result["panels"], f"{stem}_panels.png"))
    for case in setup.load_cases:
        if case.is_static:
            continue
        path = f"cases.{case.name}"
        fam = case.families[0]
        g = prob.get_val(f"{path}.stress.g_{fam}")  # (nt, n, k)
        worst_station = int(np.unravel_index(np.argmax(g), g.shape)[1])
        series = {f"g_{fam} point {k}": g[:, worst_station, k] for k in range(g.shape[2])}
        paths.append(plot_time_history(case.time, series, f"{stem}_{case.name}_stress.png",
                                       "stress constraint g = sigma/sigma_y - 1 [-]",
                                       f"{case.name}: critical station {worst_station} (y = {span[worst_station]:.2f} m)"))
        f = case.forcing_array("force_per_length", setup.geometry.num_nodes)
        picks = sorted({1, len(span) // 2, len(span) - 2})
        series = {f"y = {span[i]:.2f} m": f[:, i, 2] for i in picks}
        paths.append(plot_time_history(case.time, series, f"{stem}_{case.name}_loads.png",
                                       "vertical force per length [N/m]", f"{case.name}: load time history"))
    return paths
