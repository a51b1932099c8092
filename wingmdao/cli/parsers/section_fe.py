"""Parser of ``wingmdao section-fe`` (run: :mod:`wingmdao.cli.section_fe`)."""

from __future__ import annotations

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import add_json_argument


def register(subparsers, argv=None):
    """Add ``wingmdao section-fe`` to the ``wingmdao`` sub-parsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line (unused: the command's options do not depend on it).
    """
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
    p.set_defaults(func="wingmdao.cli.section_fe:run")
