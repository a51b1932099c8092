"""``wingmdao panel``: buckling, crippling and strength checks of one stiffened panel as JSON."""

from __future__ import annotations

import math
from wingmdao.cli import write_json
from wingmdao.panels.laminate import check_ply_fractions
from wingmdao.panels.stiffened import panel_analysis, panel_material


def _positive(flag: str, value) -> float:
    if value is None or not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{flag} = {value} m; allowed range (0, inf) m")
    return float(value)


def panel_result(args) -> dict:
    """The JSON-ready result from the parsed arguments (all input checks before any computation)."""
    if (args.t_skin is None) == (args.t_spar is None):
        raise ValueError("--t-skin (skin thickness, m) is required, or --t-spar (spar web thickness, m), not both; "
                         "allowed range (0, inf) m")
    t = _positive("--t-skin", args.t_skin) if args.t_spar is None else _positive("--t-spar", args.t_spar)
    b = _positive("--width", args.width)
    a = _positive("--length", args.length)
    h_given, ts_given = args.stiffener_height is not None, args.stiffener_thickness is not None
    if h_given != ts_given:
        given, missing = ("--stiffener-height", "--stiffener-thickness") if h_given else \
            ("--stiffener-thickness", "--stiffener-height")
        raise ValueError(f"{given} needs {missing} too (give both for a stiffened panel, neither for a bare skin)")
    h = _positive("--stiffener-height", args.stiffener_height) if h_given else None
    ts = _positive("--stiffener-thickness", args.stiffener_thickness) if ts_given else None
    for flag, value in (("--nx", args.nx), ("--nxy", args.nxy)):
        if not math.isfinite(value):
            raise ValueError(f"{flag} = {value} N/m; allowed range (-inf, inf) N/m (finite)")
    fractions = None if args.ply_fractions is None else check_ply_fractions(args.ply_fractions)
    pm = panel_material(args.material, fractions)
    return panel_analysis(pm, t, b, a, h, ts, nx=args.nx, nxy=args.nxy, stiffener=args.stiffener)


def run(args) -> int:
    write_json(panel_result(args), args.json)
    return 0
