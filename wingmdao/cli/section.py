"""``wingmdao section``: box or solid-rectangle section properties as JSON (SI units)."""

from __future__ import annotations

import numpy as np
from wingmdao.cli.parsers.section import THICKNESS_OPTIONS as _THICKNESS_OPTIONS
from wingmdao.cli import write_json
from wingmdao.materials import get_material
from wingmdao.section.box import box_properties, validate_box
from wingmdao.section.solid import solid_properties, validate_solid


#: allowed range of every length input (m): beyond it the second moments over- or underflow
LENGTH_RANGE = (1e-6, 1e3)

_FAMILY = {"t_upper": "t_skin", "t_lower": "t_skin", "t_front": "t_spar", "t_rear": "t_spar"}


def _wall_thicknesses(args) -> dict:
    """{wall: thickness or None}: a per-wall flag, else its family flag (--t-skin, --t-spar); giving
    both for one wall is an error (which one was meant?)."""
    out = {}
    for opt, name, _ in _THICKNESS_OPTIONS:
        own, family = getattr(args, opt), getattr(args, _FAMILY[opt], None)
        if own is not None and family is not None:
            raise ValueError(f"--{opt.replace('_', '-')} = {own} m and --{_FAMILY[opt].replace('_', '-')} = "
                             f"{family} m both set the {name[2:].replace('_', ' ')}; give one")
        out[name] = own if own is not None else family
    return out


def section_properties(args) -> dict:
    """Properties as a JSON-ready dict from the parsed arguments (raises ValueError on bad input)."""
    material = get_material(args.material)
    for flag in ("--width", "--height", "--t-skin", "--t-spar", *(f"--{o.replace('_', '-')}" for o, _, _ in
                                                                 _THICKNESS_OPTIONS)):
        v = getattr(args, flag[2:].replace("-", "_"), None)
        if v is not None and not (np.isfinite(v) and LENGTH_RANGE[0] <= v <= LENGTH_RANGE[1]):
            raise ValueError(f"{flag} = {v} m; allowed range [{LENGTH_RANGE[0]:g}, {LENGTH_RANGE[1]:g}] m")
    if not np.isfinite(args.nonstructural_mass) or args.nonstructural_mass < 0:
        raise ValueError(f"--nonstructural-mass = {args.nonstructural_mass} kg/m; allowed range [0, inf) kg/m")
    given = _wall_thicknesses(args)
    if args.solid:
        extra = [flag for flag in ("--t-skin", "--t-spar", *(f"--{o.replace('_', '-')}" for o, _, _ in
                                                             _THICKNESS_OPTIONS))
                 if getattr(args, flag[2:].replace("-", "_"), None) is not None]
        if extra:
            raise ValueError(f"--solid takes only --width and --height, not {', '.join(extra)}")
        validate_solid(args.width, args.height)
        props = solid_properties(args.width, args.height, material,
                                 nonstructural_mass_per_length=args.nonstructural_mass)
        inputs = {"width": args.width, "height": args.height}
    else:
        missing = [f"--{opt.replace('_', '-')}" for opt, name, _ in _THICKNESS_OPTIONS if given[name] is None]
        if missing:
            raise ValueError(f"a box section needs {', '.join(missing)} (m) (--t-skin sets both skins, "
                             "--t-spar both spar webs), or use --solid")
        labels = {"width": "--width", "height": "--height"}  # the flags the user gave, not the library's names
        labels.update({name: f"--{(opt if getattr(args, opt) is not None else _FAMILY[opt]).replace('_', '-')}"
                       for opt, name, _ in _THICKNESS_OPTIONS})
        validate_box(args.width, args.height, *given.values(), labels=labels)
        props = box_properties(args.width, args.height, *given.values(), material,
                               nonstructural_mass_per_length=args.nonstructural_mass)
        inputs = {"width": args.width, "height": args.height, **given}
    out = {"section": "solid" if args.solid else "box", "material": material.name, "units": "SI", "inputs": inputs}
    bad = [k for k, v in props.items() if not np.all(np.isfinite(v))]
    if bad:  # NaN/inf is not standard JSON: refuse the input rather than write it
        raise ValueError(f"the section {inputs} gives non-finite {', '.join(bad)}; give dimensions of a "
                         "real section (m)")
    out.update({k: np.asarray(v).tolist() for k, v in props.items()})
    return out


def run(args) -> int:
    write_json(section_properties(args), args.json)
    return 0
