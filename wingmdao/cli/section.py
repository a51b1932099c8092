"""``wingmdao section``: box or solid-rectangle section properties as JSON (SI units)."""

from __future__ import annotations

import numpy as np

_THICKNESS_OPTIONS = (("t_upper", "t_upper_skin", "upper skin"), ("t_lower", "t_lower_skin", "lower skin"),
                      ("t_front", "t_front_spar", "front spar web"), ("t_rear", "t_rear_spar", "rear spar web"))


def register(subparsers):
    p = subparsers.add_parser(
        "section",
        help="print box (App. F) or solid-rectangle section properties as JSON",
        description="Section properties of a rectangular box (outer width x height, four wall "
        "thicknesses) or, with --solid, of a solid rectangle. All inputs and outputs in SI units: "
        "lengths in m, areas m^2, second moments m^4, stiffnesses N and N*m^2, mass per length kg/m. "
        "Offsets (c_ea, n_ea, c_sc, n_sc, c_cg, n_cg) are from the box centre, c aft, n up.",
    )
    p.add_argument("--width", type=float, required=True, metavar="M", help="outer width, chordwise (m)")
    p.add_argument("--height", type=float, required=True, metavar="M", help="outer height, normal (m)")
    for opt, _, what in _THICKNESS_OPTIONS:
        p.add_argument(f"--{opt.replace('_', '-')}", dest=opt, type=float, default=None, metavar="M",
                       help=f"{what} thickness (m); required for a box, not allowed with --solid")
    p.add_argument("--solid", action="store_true", help="solid rectangle (only --width and --height)")
    p.add_argument("--material", default="aluminium",
                   help="built-in material name (default: aluminium, E = 70 GPa, rho = 2700 kg/m^3, "
                   "sigma_y = 276 MPa); see wingmdao.materials.MATERIALS")
    p.add_argument("--nonstructural-mass", type=float, default=0.0, metavar="KG_PER_M",
                   help="nonstructural mass per length added to mass_per_length (kg/m, default 0)")
    p.add_argument("--json", default="-", metavar="PATH", help="output file ('-' = standard output, the default)")
    p.set_defaults(func=run)


def section_properties(args) -> dict:
    """Properties as a JSON-ready dict from the parsed arguments (raises ValueError on bad input)."""
    from wingmdao.materials import get_material
    from wingmdao.section.box import box_properties, validate_box
    from wingmdao.section.solid import solid_properties, validate_solid

    material = get_material(args.material)
    if not np.isfinite(args.nonstructural_mass) or args.nonstructural_mass < 0:
        raise ValueError(f"--nonstructural-mass = {args.nonstructural_mass} kg/m; allowed range [0, inf) kg/m")
    given = {name: getattr(args, opt) for opt, name, _ in _THICKNESS_OPTIONS}
    if args.solid:
        extra = [f"--{opt.replace('_', '-')}" for opt, name, _ in _THICKNESS_OPTIONS if given[name] is not None]
        if extra:
            raise ValueError(f"--solid takes only --width and --height, not {', '.join(extra)}")
        validate_solid(args.width, args.height)
        props = solid_properties(args.width, args.height, material,
                                 nonstructural_mass_per_length=args.nonstructural_mass)
        inputs = {"width": args.width, "height": args.height}
    else:
        missing = [f"--{opt.replace('_', '-')}" for opt, name, _ in _THICKNESS_OPTIONS if given[name] is None]
        if missing:
            raise ValueError(f"a box section needs {', '.join(missing)} (m), or use --solid")
        validate_box(args.width, args.height, *given.values())
        props = box_properties(args.width, args.height, *given.values(), material,
                               nonstructural_mass_per_length=args.nonstructural_mass)
        inputs = {"width": args.width, "height": args.height, **given}
    out = {"section": "solid" if args.solid else "box", "material": material.name, "units": "SI", "inputs": inputs}
    out.update({k: np.asarray(v).tolist() for k, v in props.items()})
    return out


def run(args) -> int:
    from wingmdao.cli import write_json

    write_json(section_properties(args), args.json)
    return 0
