"""Parser of ``wingmdao section`` (run: :mod:`wingmdao.cli.section`)."""

from __future__ import annotations

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import add_json_argument


THICKNESS_OPTIONS = (("t_upper", "t_upper_skin", "upper skin"), ("t_lower", "t_lower_skin", "lower skin"),
                      ("t_front", "t_front_spar", "front spar web"), ("t_rear", "t_rear_spar", "rear spar web"))


def register(subparsers, argv=None):
    """Add ``wingmdao section`` to the ``wingmdao`` sub-parsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line (unused: the command's options do not depend on it).
    """
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
    for opt, _, what in THICKNESS_OPTIONS:
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
    p.set_defaults(func="wingmdao.cli.section:run")
