"""``wingmdao section-fe``: finite-element cross-section analysis of a section description file."""

from __future__ import annotations
from wingmdao.cli._args import add_json_argument
from wingmdao.cli import COMMANDS, write_json
from wingmdao.materials import get_material
from wingmdao.section.fe.io import analyse_description, load_description


def register(subparsers):
    p = subparsers.add_parser(
        "section-fe",
        help=COMMANDS["section-fe"].help,
        description="Read a YAML/JSON section description (materials, section shape: rectangle, tube, "
        "channel, box, airfoil) and print the 6x6 Timoshenko stiffness (F1 axial, F2, F3 shear, M1 torsion, "
        "M2, M3 bending), 6x6 mass, centres and, for airfoil wingboxes, the stiffness-matched box. SI units. "
        "See docs/cross-section-fe.md for the frame and origin.")
    p.add_argument("file", nargs="?", help="section description (.yaml, .yml or .json)")
    p.add_argument("--rectangle", nargs=2, type=float, metavar=("W", "H"),
                   help="solid rectangle width and height (m) instead of a file")
    p.add_argument("--material", nargs="+", metavar="NAME | E NU RHO",
                   help="material of --rectangle: a built-in name as in 'wingmdao section --material' "
                        "(e.g. aluminium; wingmdao.materials.MATERIALS) or isotropic E (Pa) NU RHO (kg/m^3)")
    p.add_argument("--mesher", choices=["gmsh", "structured"], default=None,
                   help="mesher of airfoil wingboxes (overrides the file's section.mesher; default gmsh, "
                        "or the built-in structured mesher when gmsh is missing or the section has stringers)")

    add_json_argument(p)
    p.set_defaults(func=run)


def run(args) -> int:
    if args.rectangle:
        if not args.material:
            raise ValueError("--rectangle needs --material E NU RHO")
        E, nu, rho = _material(args.material)
        desc = {"materials": {"m": {"type": "isotropic", "E": E, "nu": nu, "rho": rho}},
                "section": {"shape": "rectangle", "width": args.rectangle[0], "height": args.rectangle[1],
                            "material": "m"}}
    elif args.file:
        desc = load_description(args.file)
    else:
        raise ValueError("give a section description FILE or --rectangle W H --material E NU RHO")
    if args.mesher:
        desc.setdefault("section", {})["mesher"] = args.mesher
    write_json(analyse_description(desc), args.json)
    return 0


def _material(tokens):
    """``--material NAME`` (built-in, as ``wingmdao section``) or ``--material E NU RHO``."""
    if len(tokens) == 1:
        m = get_material(tokens[0])
        return m.E, m.nu, m.rho
    if len(tokens) != 3:
        raise ValueError(f"--material {' '.join(tokens)}: give a built-in name or three numbers E NU RHO")
    try:
        return tuple(float(t) for t in tokens)
    except ValueError:
        raise ValueError(f"--material {' '.join(tokens)}: E NU RHO must be numbers (Pa, -, kg/m^3)") from None
