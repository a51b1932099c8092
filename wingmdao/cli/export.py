"""``wingmdao export wing-box``: write the (sized) wing box as a CalculiX, Abaqus or Nastran deck
(beam stick model or shell model), see :mod:`wingmdao.fe.export`."""

from __future__ import annotations

import numpy as np


def register(subparsers):
    p = subparsers.add_parser("export", help="write a sized wing as a CalculiX / Abaqus / Nastran deck",
                              description="Export a case as an FE deck (SI units: m, N, kg; body axes).")
    cases = p.add_subparsers(dest="case", metavar="CASE", required=True)
    wb = cases.add_parser("wing-box", help="App. D.1 box (Table E.2 walls, or --design)")
    from wingmdao.cli.run import add_wing_box_arguments

    add_wing_box_arguments(wb)
    wb.add_argument("--design", default=None, metavar="RESULT.json",
                    help="wall thicknesses from a 'wingmdao size wing-box --elements 1 1 1' result")
    wb.add_argument("--format", choices=("calculix", "nastran", "abaqus"), required=True, help="deck format")
    wb.add_argument("--fidelity", choices=("beam", "shell"), default="beam",
                    help="beam stick model or shell model of the walls")
    wb.add_argument("file", metavar="FILE", help="deck to write")
    wb.add_argument("--overwrite", action="store_true", help="replace an existing FILE instead of refusing")
    wb.set_defaults(func=run_export)


def run_export(args) -> int:
    import sys

    from wingmdao.cases import wing_box as case
    from wingmdao.cli.verify import _design_walls, wing_box_sections
    from wingmdao.fe.export import beam_deck, shell_deck, write_atomic
    from wingmdao.materials import ALUMINIUM

    from wingmdao.cli._io import check_output_file

    for name in ("tip_load", "tip_moment"):
        if not np.all(np.isfinite(getattr(args, name))):
            raise ValueError(f"--{name.replace('_', '-')} must be finite")
    check_output_file(args.file, "FILE", overwrite=args.overwrite)
    walls = _design_walls(args.design, case.NAME) if args.design else None
    sec = wing_box_sections(args.geometry, args.t_spar, args.t_skin, walls)
    build = beam_deck if args.fidelity == "beam" else shell_deck
    text = build(sec, ALUMINIUM, args.format, tip_force=args.tip_load, tip_moment=args.tip_moment)
    write_atomic(text, args.file)
    print(f"wingmdao export: wrote {args.fidelity} model ({args.format}) to {args.file}", file=sys.stderr)
    return 0
