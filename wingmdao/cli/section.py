"""``wingmdao section``: box or solid-rectangle section properties as JSON (SI units)."""

from __future__ import annotations

import numpy as np
from wingmdao.cli._args import add_json_argument
from wingmdao.cli import COMMANDS, write_json
from wingmdao.materials import get_material
from wingmdao.section.box import box_properties, validate_box
from wingmdao.section.solid import solid_properties, validate_solid

_THICKNESS_OPTIONS = (("t_upper", "t_upper_skin", "upper skin"), ("t_lower", "t_lower_skin", "lower skin"),
                      ("t_front", "t_front_spar", "front spar web"), ("t_rear", "t_rear_spar", "rear spar web"))


def register(subparsers):
    p = subparsers.add_parser(
        "section",
        help=COMMANDS["section"].help,
        description="Section properties of a rectangular box (outer width x height, four wall "
        "thicknesses) or, with --solid, of a solid rectangle. All inputs and outputs in SI units: "
        "lengths in m, areas m^2, second moments m^4, stiffnesses N and N*m^2, mass per length kg/m. "
        "Offsets (c_ea, n_ea, c_sc, n_sc, c_cg, n_cg) are from the box centre, c aft, n up.",
    )
    p.add_argument("--width", type=float, required=True, metavar="M", help="outer width, chordwise (m)")
    p.add_argument("--height", type=float, required=True, metavar="M", help="outer height, normal (m)")
    p.add_argument("--t-skin", type=float, default=None, metavar="M",
                   help="thickness of both skins (m), as on run/verify/export wing-box; or --t-upper/--t-lower")
    p.add_argument("--t-spar", type=float, default=None, metavar="M",
                   help="thickness of both spar webs (m), as on run/verify/export wing-box; or --t-front/--t-rear")
    for opt, _, what in _THICKNESS_OPTIONS:
        p.add_argument(f"--{opt.replace('_', '-')}", dest=opt, type=float, default=None, metavar="M",
                       help=f"{what} thickness (m), when it differs from the other "
                            f"{'skin' if 'skin' in what else 'web'}; a box needs all four walls")
    p.add_argument("--solid", action="store_true", help="solid rectangle (only --width and --height)")
    p.add_argument("--material", default="aluminium", metavar="NAME",
                   help="built-in material name (default: aluminium, E = 70 GPa, rho = 2700 kg/m^3, "
                   "sigma_y = 276 MPa); see wingmdao.materials.MATERIALS")
    p.add_argument("--nonstructural-mass", type=float, default=0.0, metavar="KG_PER_M",
                   help="nonstructural mass per length added to mass_per_length (kg/m)")

    add_json_argument(p)
    p.set_defaults(func=run)


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
