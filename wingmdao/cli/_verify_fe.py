"""The FE-model flags, design files, models and comparisons shared by the ``verify`` cases
(:mod:`wingmdao.cli.verify`, :mod:`wingmdao.cli._verify_pegasus`)."""

from __future__ import annotations

import numpy as np

from wingmdao.cli._io import read_json_object
from wingmdao.fe.box_model import build_shell_box
from wingmdao.fe.solid_box import build_solid_box, streamwise_sections
from wingmdao.fe.stress_points import POINTS, compare_von_mises
from wingmdao.materials import ALUMINIUM


def design_walls(path, case, count=4, how="size with --elements 1 1 1"):
    """The wall thicknesses of a sizing result given as ``--design``.

    Parameters
    ----------
    path : str
        The result's JSON file (``wingmdao size CASE --json``).
    case : str
        The case the result must be of.
    count : int
        Stations per wall the result must have.
    how : str
        How to make such a result, named in the errors.

    Returns
    -------
    dict
        ``{wall: (count,) ndarray}`` in m, walls ``upper_skin``, ``lower_skin``, ``front_spar``,
        ``rear_spar``.

    Raises
    ------
    ValueError
        Naming ``--design`` and the file: another case, no ``thickness`` object, or a wall without
        ``count`` positive finite values.
    """
    data = read_json_object(path, "--design")
    if data.get("case") != case:
        raise ValueError(f"--design {path!r} is a result of case {data.get('case')!r}, not {case!r}")
    th = data.get("thickness")
    if not isinstance(th, dict):
        raise ValueError(f"--design {path!r}: no 'thickness' object (upper_skin, lower_skin, front_spar, "
                         f"rear_spar per station, m; {how})")
    walls = {}
    for w in ("upper_skin", "lower_skin", "front_spar", "rear_spar"):
        v = np.asarray(th.get(w, []), float)
        if v.shape != (count,) or not np.all(np.isfinite(v) & (v > 0)):
            raise ValueError(f"--design {path!r}: thickness.{w} must have {count} positive values in m "
                             f"({how}), got {v.tolist()}")
        walls["t_" + w] = v
    return walls


def check_fe_args(args, span):
    """The shared FE flags (ValueError naming the flag, its value and the allowed range)."""
    if args.ribs is not None and not (np.isfinite(args.ribs) and 0 < args.ribs <= span):
        raise ValueError(f"--ribs = {args.ribs} m; allowed range (0, {span:g}] m (the span)")
    if args.modes < 0 or args.modes > 50:
        raise ValueError(f"--modes = {args.modes}; allowed range [0, 50]")
    for name, low in (("chord_elements", 1), ("height_elements", 1), ("through_elements", 1)):
        if getattr(args, name) < low:
            raise ValueError(f"--{name.replace('_', '-')} = {getattr(args, name)}; allowed >= {low}")
    if not (np.isfinite(args.span_size) and 0.05 <= args.span_size <= 3.0):
        raise ValueError(f"--span-size = {args.span_size} m; allowed range [0.05, 3] m")
    if not (np.isfinite(args.rib_thickness) and 0 < args.rib_thickness <= 0.5):
        raise ValueError(f"--rib-thickness = {args.rib_thickness} m; allowed range (0, 0.5] m")
    if args.load_steps < 1:
        raise ValueError(f"--load-steps = {args.load_steps}; allowed range >= 1")


def percent_difference(beam, fe, scale) -> list:
    """100 (beam - fe) / fe per station; None where |fe| <= 1e-6 ``scale`` (the clamped root, or
    a displacement a pure torque does not produce)."""
    return [None if abs(f) <= 1e-6 * scale or scale == 0 else float(100 * (b - f) / f)
            for b, f in zip(np.asarray(beam, float), np.asarray(fe, float))]


def build_fe_model(args, sec, ribs, cos_sweep=1.0, cos_dih=1.0):
    """The FE model of ``--fidelity`` on the sections ``sec`` (beam-normal wall thicknesses; the
    solid takes the streamwise ones, thickness / cos per section)."""
    if args.fidelity == "solid":
        return build_solid_box(streamwise_sections(sec, cos_sweep, cos_dih), fe_material(),
                               chord_elements=args.chord_elements, height_elements=args.height_elements,
                               through=args.through_elements, span_element_size=args.span_size, ribs_y=ribs,
                               rib_thickness=args.rib_thickness)
    return build_shell_box(sec, fe_material(), chord_elements=args.chord_elements,
                           height_elements=args.height_elements, span_element_size=args.span_size,
                           ribs_y=ribs, rib_thickness=args.rib_thickness)


def von_mises_table(model, sections, stresses, loads, axes_at) -> dict:
    """JSON block: von Mises (Pa) at POINTS per span row, beam vs FE, differences in per cent of
    the FE value and of the row's largest FE value (a point near zero stress has a large
    relative difference and no weight)."""
    c = compare_von_mises(model, sections, stresses, loads, axes_at)
    fe, beam = c["fe"], c["beam"]
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(fe > 0, 100 * (beam - fe) / fe, 0.0)
        of_max = np.where(fe.max(1, keepdims=True) > 0, 100 * (beam - fe) / fe.max(1, keepdims=True), 0.0)
    return {"points": list(POINTS), "y": c["y"].tolist(), "fe_pa": fe.tolist(), "beam_pa": beam.tolist(),
            "difference_percent": rel.tolist(), "difference_percent_of_row_max": of_max.tolist(),
            "note": "FE: von Mises of the mean integration-point stress of the corner / mid-flange elements "
                    "(shell: S8R expanded by ccx to C3D20R; solid: the elements through the wall); beam: "
                    "Sec. 4.4.2 recovery at the same points, internal loads by statics of the jig"}


def fe_material():
    """The material of the verification models (beam and CalculiX).

    Returns
    -------
    Material
        :data:`wingmdao.materials.ALUMINIUM` (SI: Pa, kg/m^3).
    """
    return ALUMINIUM
