"""Solid rectangular cantilever of Sec. 4.7.1 (Table 4.23): width and height per station.

The dissertation does not state the beam length; we use 10 m (option ``--length``). The
beam lies along +y (docs/conventions.md), clamped at y = 0, with the tip load along +z. Load
cases: ``static`` (constant tip load 1 MN, static solve), ``sine`` (F_z = 1 MN sin(20 t),
the load of Fig. 4.41a) and ``step`` (the same constant load applied suddenly at t > 0 to
the beam at rest: the dynamic counterpart of ``static``, Table 4.25). Initial guesses
``a``, ``b``, ``c`` stand for Fig. 4.40 (uniform, tapered, infeasible at the lower bounds).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wingmdao.cases import CaseOptions, CaseSetup, case_options, check_step_count, option
from wingmdao.groups.load_case import LoadCase
from wingmdao.materials import Material
from wingmdao.beam.geometry import WingGeometry
from wingmdao.design import SizingOptions
from wingmdao.names import CASE_HELP

NAME = "cantilever"
HELP = CASE_HELP[NAME]

#: Table 4.23
E, SIGMA_Y, RHO = 70e9, 276e6, 2700.0
BOUNDS = {"height": (0.4, 5.0), "width": (0.2, 5.0)}
TIP_LOAD = 1.0e6  # N
LOAD_KINDS = ("static", "sine", "step")
GUESSES = ("a", "b", "c")  # Fig. 4.40


@dataclass(frozen=True)
class CantileverOptions(CaseOptions):
    """Options of the cantilever case (SI); ``wingmdao size cantilever --help`` describes each."""

    CASE = NAME
    load: str = option("static", "tip load history: constant static, 1 MN sin(20 t), or 1 MN applied suddenly",
                       choices=LOAD_KINDS)
    guess: str = option("b", "initial design (Fig. 4.40): a uniform, b tapered, c infeasible (lower bounds)",
                        choices=GUESSES)
    stations: int = option(10, "beam nodes (stations, >= 3)", flag="--num-nodes", metavar="N",
                           aliases=("--stations",))
    length: float = option(10.0, "beam length (m)", metavar="M")
    t_final: float = option(1.0, "simulated time for dynamic loads (s)", metavar="S")
    dt: float = option(0.01, "time step for dynamic loads (s)", metavar="S")


OPTIONS = CantileverOptions


def initial_guess(kind: str, n: int) -> dict:
    """The initial design of Fig. 4.40.

    Parameters
    ----------
    kind : str
        ``a`` uniform, ``b`` tapered, ``c`` infeasible (every value at its lower bound).
    n : int
        Beam nodes.

    Returns
    -------
    dict
        ``{"width": (n,) m, "height": (n,) m}``.
    """
    s = np.linspace(0.0, 1.0, n)
    if kind == "a":
        return {"width": np.full(n, 1.0), "height": np.full(n, 2.5)}
    if kind == "b":
        return {"width": 2.0 - 1.5 * s, "height": 4.0 - 3.0 * s}
    return {"width": np.full(n, BOUNDS["width"][0]), "height": np.full(n, BOUNDS["height"][0])}


def load_case(kind: str, n: int, t_final: float, dt: float):
    """The tip-load case of the cantilever (tip force :data:`TIP_LOAD` along +z).

    Parameters
    ----------
    kind : str
        ``static`` (static solve), ``sine`` (1 MN sin(20 t)) or ``step`` (1 MN for t > 0).
    n : int
        Beam nodes.
    t_final : float
        Simulated time of the dynamic kinds (s).
    dt : float
        Time step of the dynamic kinds (s).

    Returns
    -------
    wingmdao.groups.load_case.LoadCase
        The load case, constraining the ``ss_tension`` and ``ss_compression`` families.
    """
    if kind == "static":
        f = np.zeros((1, n, 3))
        f[0, -1, 2] = TIP_LOAD
        return LoadCase("static", np.zeros(1), {"point_force": f}, ("ss_tension", "ss_compression"))
    if not (t_final > 0 and 0 < dt <= t_final):
        raise ValueError(f"--t-final ({t_final} s) and --dt ({dt} s) must satisfy 0 < dt <= t_final")
    check_step_count(t_final, dt, n)
    time = np.arange(0.0, t_final + 0.5 * dt, dt)
    f = np.zeros((time.size, n, 3))
    f[:, -1, 2] = TIP_LOAD * (np.sin(20.0 * time) if kind == "sine" else (time > 0))
    return LoadCase(kind, time, {"point_force": f}, ("ss_tension", "ss_compression"))


def build(options: CantileverOptions | None = None, **overrides) -> CaseSetup:
    """Geometry, tip-load case, Table 4.23 material and bounds of the cantilever.

    Parameters
    ----------
    options : CantileverOptions, optional
        The case's options; None: the defaults.
    **overrides
        Options by field name, replacing those of ``options`` (``build(load="step", guess="a")``).

    Returns
    -------
    CaseSetup
        The solid-section beam, its load case, material and sizing bounds.

    Raises
    ------
    ValueError
        A bad option, naming its flag, before any solve.
    """
    opts = case_options(CantileverOptions, options, **overrides)
    n = opts.stations
    if n < 3:
        raise ValueError(f"--num-nodes = {n}; allowed range >= 3")
    if not (np.isfinite(opts.length) and opts.length > 0):
        raise ValueError(f"--length = {opts.length} m; allowed range (0, inf) m")
    y = np.linspace(0.0, opts.length, n)
    geometry = WingGeometry(node_positions=np.column_stack([np.zeros(n), y, np.zeros(n)]),
                            node_euler_angles=np.zeros((n, 3)), width=np.ones(n), height=np.ones(n))
    material = Material("cantilever aluminium (Table 4.23)", E=E, rho=RHO, sigma_y=SIGMA_Y, nu=0.33)
    sizing = SizingOptions(lower={k: v[0] for k, v in BOUNDS.items()},
                           upper={k: v[1] for k, v in BOUNDS.items()},
                           initial=initial_guess(opts.guess, n), rho_ks=50.0)
    case = load_case(opts.load, n, opts.t_final, opts.dt)
    return CaseSetup(geometry, [case], material, sizing, section="solid",
                     notes=[f"beam length {opts.length} m (not stated in the dissertation)"])
