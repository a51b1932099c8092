"""``wingmdao section-fe``: finite-element cross-section analysis of a section description file."""

from __future__ import annotations
from wingmdao.cli import write_json
from wingmdao.materials import get_material
from wingmdao.section.fe.io import analyse_description, load_description


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
