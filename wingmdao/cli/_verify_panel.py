"""``wingmdao verify panel``: the smeared panel model of ``wingmdao panel`` against a CalculiX
linear buckling analysis (:func:`wingmdao.fe.panel_buckling.panel_buckling_factor`) of the same
panel.

FE panel: ``--stiffeners N`` stiffeners (default 3 with stiffener flags, 0 without) at the
model's pitch p (B for blades, B + flange width for tees), width W = N p, length A, simply
supported on its four skin edges; an unstiffened panel is the B x A plate. Isotropic metals only.

Model buckling factor: the load multiplier at which the first elastic buckling mode of the
model is reached, 1 / max(R) over the model's **elastic buckling** ratios, which are load-linear:

* ``skin_compression_shear``: the skin bay between stiffeners (simply supported plate,
  compression-shear interaction) -- the FE's ``local`` (``plate`` without stiffeners) mode;
* ``panel_compression_shear``: the smeared panel between ribs (wide column in compression,
  infinitely wide strip in shear) -- the FE's ``global`` mode.

With stiffeners ``model_buckling_factor_finite_width`` is the same with the model's smeared
orthotropic plate a x W (``panel_width`` = the FE width, simply supported on all four edges as
the FE panel) in place of the wide column: it isolates the side-edge support the wide column
ignores.

Left out: ``stiffener_crippling`` (an inelastic crippling allowable, no eigenvalue) and
``stiffener_column`` (its Euler branch is ``panel_compression`` itself -- the same wide column
with the full skin width -- and its Johnson branch is plasticity, which a linear eigenvalue
analysis does not see); ``material`` (strength).
"""

from __future__ import annotations

import math
import sys

from wingmdao.cli import write_json
from wingmdao.cli.panel import panel_result
from wingmdao.fe.calculix import CalculixNotFound, find_ccx
from wingmdao.fe.panel_buckling import build_panel, panel_buckling_factor
from wingmdao.panels.laminate import check_ply_fractions
from wingmdao.panels.stiffened import flange_width, panel_analysis, panel_material, stiffener_pitch

#: the model's elastic buckling ratios compared with the FE eigenvalue, and the FE mode each is
MODEL_BUCKLING_MODES = {"skin_compression_shear": "local", "panel_compression_shear": "global"}

#: the FE module's argument names and the command's flags (its ValueErrors name the argument)
_FE_FLAGS = {"mesh_size": "--mesh-size", "stiffener_thickness": "--stiffener-thickness",
             "stiffener_height": "--stiffener-height", "skin_thickness": "--t-skin", "width": "--width",
             "length": "--length", "flange_width": "--stiffener tee (flange width)", "nx": "--nx", "nxy": "--nxy"}


def _fe_error(exc: ValueError) -> ValueError:
    msg = str(exc)
    name = msg.split(" ", 1)[0]
    if name in _FE_FLAGS:
        msg = _FE_FLAGS[name] + msg[len(name):]
    return ValueError(f"FE panel: {msg}")


def verify_panel(args) -> dict:
    """The JSON result of ``verify panel`` (``wingmdao panel``'s keys plus the comparison)."""
    res = panel_result(args)                      # the panel command's checks and result
    fractions = None if args.ply_fractions is None else check_ply_fractions(args.ply_fractions)
    pm = panel_material(args.material, fractions)
    if pm.is_laminate:
        raise ValueError(f"--material {args.material}: a laminate; the CalculiX panel model is isotropic only "
                         "(allowed: a metal)")
    if args.nx == 0.0 and args.nxy == 0.0:
        raise ValueError("--nx = 0 and --nxy = 0: nothing to buckle; allowed: a nonzero --nx or --nxy (N/m)")
    if args.nx > 0.0 and args.nxy == 0.0:
        raise ValueError(f"--nx = {args.nx:g} N/m (tension) with --nxy = 0: nothing to buckle; allowed: "
                         "--nx < 0 (compression) or a nonzero --nxy")
    stiffened = args.stiffener_height is not None
    n = args.stiffeners
    if n is None:
        n = 3 if stiffened else 0
    if n < 0 or n > 50:
        raise ValueError(f"--stiffeners = {n}; allowed range [0, 50]")
    if n == 0 and stiffened:
        raise ValueError("--stiffeners = 0 with --stiffener-height/--stiffener-thickness; allowed: >= 1 for a "
                         "stiffened panel (or drop the stiffener flags)")
    if n > 0 and not stiffened:
        raise ValueError(f"--stiffeners = {n} without --stiffener-height/--stiffener-thickness; allowed: 0 for "
                         "an unstiffened panel")
    if args.mesh_size is not None and not (math.isfinite(args.mesh_size) and args.mesh_size > 0):
        raise ValueError(f"--mesh-size = {args.mesh_size} m; allowed range (0, inf) m")
    t = args.t_skin if args.t_spar is None else args.t_spar
    b, a = args.width, args.length
    h, ts = args.stiffener_height, args.stiffener_thickness
    bf = flange_width(h, args.stiffener) if stiffened and args.stiffener == "tee" else None
    pitch = stiffener_pitch(b, h, args.stiffener) if stiffened else b
    W = n * pitch if stiffened else b
    E, nu = pm.base.E, pm.base.nu
    fe_kw = dict(n_stiffeners=n, stiffener_height=h if stiffened else None,
                 stiffener_thickness=ts if stiffened else None, flange_width=bf, nx=args.nx, nxy=args.nxy,
                 mesh_size=args.mesh_size)
    try:
        build_panel(a, W, t, E, nu, **fe_kw)      # the FE module's input checks, before ccx
    except ValueError as exc:
        raise _fe_error(exc) from exc
    find_ccx()

    ratios = {k: res["failure_ratios"][k] for k in MODEL_BUCKLING_MODES if res["failure_ratios"][k] is not None}
    key = max(ratios, key=ratios.get)
    model_factor = 1.0 / ratios[key] if ratios[key] > 0 else None
    finite = None
    if stiffened:      # the model's smeared orthotropic plate a x W (panel_width): the FE's edge supports
        fr = panel_analysis(pm, t, b, a, h, ts, nx=args.nx, nxy=args.nxy, stiffener=args.stiffener,
                            panel_width=W)["failure_ratios"]
        finite = 1.0 / max(fr[k] for k in MODEL_BUCKLING_MODES)
    fe = panel_buckling_factor(a, W, t, E, nu, workdir=args.keep_deck, **fe_kw)
    lam = fe["fe_buckling_factor"]
    res.update({
        "model_buckling_factor": model_factor,
        "model_mode": "plate" if not stiffened else MODEL_BUCKLING_MODES[key],
        "model_buckling_ratio": key,
        "model_buckling_ratios": ratios,
        "model_buckling_factor_finite_width": finite,
        "fe_buckling_factor": lam,
        "fe_mode": fe["mode"],
        "difference_percent": None if model_factor is None else 100.0 * (model_factor - lam) / lam,
        "fe": {"element": "S8R", "n_stiffeners": n, "pitch_m": pitch, "panel_width_m": W, "length_m": a,
               "flange_width_m": bf, "mesh_size_m": args.mesh_size, "num_elements": fe["num_elements"],
               "num_nodes": fe["num_nodes"], "buckling_factors": fe["buckling_factors"],
               "nx_critical_n_per_m": fe["nx_critical"], "nxy_critical_n_per_m": fe["nxy_critical"],
               "junction_ratio": fe["junction_ratio"], "deck_path": fe["deck_path"], "time_s": fe["time"]},
        "note": "buckling factor = critical loads / applied (NX, NXY); model: 1 / max of the elastic buckling "
                "ratios skin_compression_shear and panel_compression_shear (stiffener crippling and the "
                "Johnson column are inelastic, not compared); FE: simply supported flat panel, linear "
                "*BUCKLE, isotropic. difference_percent = 100 (model - fe) / fe",
    })
    return res


def run_verify_panel(args) -> int:
    try:
        res = verify_panel(args)
    except CalculixNotFound as exc:
        print(f"wingmdao verify: {exc}", file=sys.stderr)
        return 2
    write_json(res, args.json)
    return 0
