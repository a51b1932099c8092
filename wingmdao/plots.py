"""PNG plots a loads/stress engineer expects from a sizing run.

Thickness of each wall along the span (several runs overlaid, as Fig. 5.5-5.6 compare static
and gust sizing), the stress-constraint time history at the critical station, the load time
history at a few stations, and the optimizer's iteration history. matplotlib is an optional
dependency (``pip install wingmdao[plot]``); every function raises a clear ImportError without it.
"""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile

import numpy as np

from wingmdao.cli._io import default_file_mode
from wingmdao.utils.mpi_env import is_output_rank

WALLS = ("upper_skin", "lower_skin", "front_spar", "rear_spar")


def pyplot_agg():
    """matplotlib's pyplot on the Agg backend (files only, no display).

    Returns
    -------
    module
        ``matplotlib.pyplot``.

    Raises
    ------
    ImportError
        When matplotlib is not installed (:func:`optional_pyplot` warns instead).
    """
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the install
        raise ImportError("plots need matplotlib: pip install 'wingmdao[plot]'") from exc
    return plt


def optional_pyplot():
    """matplotlib's pyplot on the Agg backend, or None (with one line on standard error) when
    matplotlib is not installed: the commands' plots are optional, their results are not."""
    try:
        return pyplot_agg()
    except ImportError as exc:
        print(f"wingmdao: warning: no plots ({exc})", file=sys.stderr)
        return None


def save_figure(fig, path: str, dpi: int = 120, **layout) -> str:
    """Lay out (``tight_layout(**layout)``) and write ``fig`` to ``path`` atomically, then close it.

    A temporary file in the same folder (same extension, so matplotlib picks the format), flushed
    and fsynced, then ``os.replace``: an interrupted or failed write leaves the earlier file (or
    none), never a truncated image. Returns ``path``.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    path : str
        PNG (or other format by extension) to write.
    dpi : int, optional
        Resolution (dots per inch).
    **layout
        Passed to ``fig.tight_layout``.

    Returns
    -------
    str
        ``path``.
    """
    plt = pyplot_agg()
    if not is_output_rank():  # under mpirun only rank 0 writes
        plt.close(fig)
        return path
    fig.tight_layout(**layout)
    folder = os.path.dirname(os.path.abspath(path))
    ext = os.path.splitext(path)[1] or ".png"
    fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(path)}.", suffix=ext, dir=folder)
    try:
        with os.fdopen(fd, "wb") as fh:
            fig.savefig(fh, dpi=dpi, format=ext[1:])
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, default_file_mode())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    finally:
        plt.close(fig)
    return path


def plot_thickness(span, runs: dict, path: str, title: str = "Wall thickness along the span"):
    """Thickness of the four walls versus span; ``runs`` maps a label to ``{wall: (n,) m}``.

    Parameters
    ----------
    span : array_like
        (n,) span coordinates (m).
    runs : dict
        Label -> {wall: (n,) thickness (m)}.
    path : str
        PNG to write.
    title : str, optional
        Figure title.

    Returns
    -------
    str
        ``path``.
    """
    plt = pyplot_agg()
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex=True)
    for ax, wall in zip(axes.ravel(), WALLS):
        for label, thick in runs.items():
            ax.plot(span, 1e3 * np.asarray(thick[wall]), marker="o", ms=3, label=label)
        ax.set_title(wall.replace("_", " "))
        ax.set_ylabel("thickness [mm]")
        ax.grid(True, alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("spanwise station y [m]")
    axes[0, 0].legend()
    fig.suptitle(title)
    return save_figure(fig, path)


def plot_time_history(time, series: dict, path: str, ylabel: str, title: str):
    """Curves over time; ``series`` maps a label to a (n_time,) array.

    Parameters
    ----------
    time : array_like
        (n_time,) times (s).
    series : dict
        Label -> (n_time,) values.
    path : str
        PNG to write.
    ylabel : str
        Y-axis label with units.
    title : str
        Figure title.

    Returns
    -------
    str
        ``path``.
    """
    plt = pyplot_agg()
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for label, y in series.items():
        ax.plot(time, y, label=label)
    ax.set_xlabel("time [s]")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend()
    return save_figure(fig, path)


def plot_iteration_history(objective, max_constraint, path: str):
    """Objective and worst constraint per driver iteration.

    Parameters
    ----------
    objective : array_like
        Objective per driver iteration.
    max_constraint : array_like
        Worst constraint margin per iteration.
    path : str
        PNG to write.

    Returns
    -------
    str
        ``path``.
    """
    plt = pyplot_agg()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    it = np.arange(len(objective))
    a1.plot(it, objective, marker="o", ms=3)
    a1.set_ylabel("mass [kg]")
    a1.grid(True, alpha=0.3)
    a2.plot(it, max_constraint, marker="o", ms=3, color="tab:red")
    a2.axhline(0.0, color="k", lw=0.8)
    a2.set_ylabel("max KS constraint [-]")
    a2.set_xlabel("driver iteration")
    a2.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_panels(span, panels: dict, path: str, title: str = "Stiffened panels along the span"):
    """The stiffened design along the span (``panels``: the result JSON's ``panels`` block):
    skin and equivalent thicknesses, stiffener heights and thicknesses, spar webs, and a map of
    the critical mode of every wall at every station with its margin of safety.

    Parameters
    ----------
    span : array_like
        (n,) span coordinates (m).
    panels : dict
        The result JSON's ``panels`` block.
    path : str
        PNG to write.
    title : str, optional
        Figure title.

    Returns
    -------
    str
        ``path``.
    """
    plt = pyplot_agg()
    span = np.asarray(span, dtype=float)
    fig, axes = plt.subplots(2, 2, figsize=(12, 8), sharex=True)
    ax = axes[0, 0]
    for wall, style in (("upper_skin", "-"), ("lower_skin", "--")):
        b = panels[wall]
        ax.plot(span, 1e3 * np.asarray(b["skin_thickness_m"]), style, marker="o", ms=3,
                label=f"{wall.replace('_', ' ')}: skin")
        ax.plot(span, 1e3 * np.asarray(b["equivalent_thickness_m"]), style, marker="s", ms=3,
                label=f"{wall.replace('_', ' ')}: skin + stiffeners (area per width)")
    ax.set_ylabel("thickness [mm]")
    ax.set_title("skins")
    ax.legend(fontsize=7)
    ax = axes[0, 1]
    for wall, style in (("upper_skin", "-"), ("lower_skin", "--")):
        b = panels[wall]
        ax.plot(span, 1e3 * np.asarray(b["stiffener_height_m"], dtype=float), style, marker="o", ms=3,
                label=f"{wall.replace('_', ' ')}: web height")
        ax.plot(span, 10e3 * np.asarray(b["stiffener_thickness_m"], dtype=float), style, marker="^", ms=3,
                label=f"{wall.replace('_', ' ')}: web thickness x 10")
    ax.set_ylabel("[mm]")
    ax.set_title("stiffeners")
    ax.legend(fontsize=7)
    ax = axes[1, 0]
    for wall in ("front_spar", "rear_spar"):
        ax.plot(span, 1e3 * np.asarray(panels[wall]["skin_thickness_m"]), marker="o", ms=3,
                label=wall.replace("_", " "))
    ax.set_ylabel("web thickness [mm]")
    ax.set_title("spar webs")
    ax.legend(fontsize=7)
    ax = axes[1, 1]
    modes = sorted({m for b in panels.values() for m in b["critical_mode"]})
    cmap = plt.get_cmap("tab10")
    for k, wall in enumerate(WALLS):
        b = panels[wall]
        for j, mode in enumerate(modes):
            pick = np.array([m == mode for m in b["critical_mode"]])
            if pick.any():
                ax.scatter(span[pick], np.full(pick.sum(), k), color=cmap(j % 10), s=60,
                           label=mode if k == 0 or mode not in [m for w in WALLS[:k] for m in panels[w]["critical_mode"]]
                           else None)
        for x, ms in zip(span, b["margin_of_safety"]):
            if ms < 10:
                ax.annotate(f"{ms:+.2f}", (x, k), textcoords="offset points", xytext=(0, 7), fontsize=5, ha="center")
    ax.set_yticks(range(len(WALLS)))
    ax.set_yticklabels([w.replace("_", " ") for w in WALLS])
    ax.set_ylim(-0.6, len(WALLS) - 0.3)
    ax.set_title("critical mode and margin of safety")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=3)
    for ax in axes[1]:
        ax.set_xlabel("spanwise station y [m]")
    for ax in axes.ravel():
        ax.grid(True, alpha=0.3)
    fig.suptitle(title)
    return save_figure(fig, path)
