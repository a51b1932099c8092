"""``wingmdao export wing-box|pegasus``: write the (sized) wing box as a CalculiX, Abaqus or Nastran deck
(beam stick model or shell model), see :mod:`wingmdao.fe.export`; ``export pegasus --format
nastran-aeroelastic``: the beam with its masses, lifting surface, splines and the SOL 144/145/146
cards, see :mod:`wingmdao.fe.nastran_aero`."""

from __future__ import annotations
import sys

import numpy as np
import wingmdao.cli._openmdao  # noqa: F401  (first: OpenMDAO without the matplotlib of its report plugins)
from wingmdao.cli import COMMANDS
from wingmdao.cli._io import check_output_file
from wingmdao.cases import pegasus as pegasus_case, wing_box as wing_box_case
from wingmdao.cases.planform import G0
from wingmdao.cli._verify_pegasus import pegasus_setup, pegasus_walls
from wingmdao.cli.run import add_wing_box_arguments
from wingmdao.cli.verify import design_walls, wing_box_sections
from wingmdao.fe.export import beam_deck, shell_deck, write_atomic
from wingmdao.fe.wing_loads import lumped_line_loads, point_weights
from wingmdao.materials import ALUMINIUM
from wingmdao.cases.pegasus_verification import engine_stations, fe_loads, nastran_aeroelastic_deck

#: --format of the aeroelastic Nastran deck (wingmdao.fe.nastran_aero)
AEROELASTIC = "nastran-aeroelastic"
#: the flags only the aeroelastic deck reads, with their defaults
AEROELASTIC_ONLY = {"sol": 146, "modes": 10, "spanwise_boxes": 20, "chordwise_boxes": 8}


def register(subparsers):
    p = subparsers.add_parser("export", help=COMMANDS["export"].help,
                              description="Export a case as an FE deck (SI units: m, N, kg; body axes).")
    cases = p.add_subparsers(dest="case", metavar="CASE", required=True)
    wb = cases.add_parser("wing-box", help="App. D.1 box (Table E.2 walls, or --design)")

    add_wing_box_arguments(wb)
    wb.add_argument("--design", default=None, metavar="RESULT.json",
                    help="wall thicknesses from a 'wingmdao size wing-box --elements 1 1 1' result")
    wb.add_argument("--format", choices=("calculix", "nastran", "abaqus"), required=True, help="deck format")
    wb.add_argument("--fidelity", choices=("beam", "shell"), default="beam",
                    help="beam stick model or shell model of the walls")
    wb.add_argument("--overwrite", action="store_true", help="replace an existing FILE instead of refusing")
    wb.add_argument("file", metavar="FILE", help="deck to write")
    wb.set_defaults(func=run_export)
    pg = cases.add_parser("pegasus", help="PEGASUS wing at n g (4/4/5/4 mm walls, or --design)")
    pg.add_argument("--design", default=None, metavar="RESULT.json",
                    help="wall thicknesses from a 'wingmdao size pegasus' result (20 stations)")
    pg.add_argument("--format", choices=("calculix", "nastran", "abaqus", AEROELASTIC), required=True,
                    help="deck format; nastran-aeroelastic: the beam with its masses, doublet-lattice panels, "
                    "beam splines and the flutter / gust / trim cards (docs/nastran-export.md)")
    pg.add_argument("--fidelity", choices=("beam", "shell"), default="beam",
                    help="beam stick model (one element per station interval) or shell model of the walls "
                    "(nastran-aeroelastic: beam only)")
    aero = pg.add_argument_group("nastran-aeroelastic")
    aero.add_argument("--sol", type=int, choices=(144, 145, 146), default=None,
                      help="executive and case control: 144 static aeroelastic trim, 145 flutter (PK), "
                      "146 continuous-turbulence frequency response (default 146)")
    aero.add_argument("--modes", type=int, default=None, metavar="N",
                      help="modes of EIGRL and FLUTTER, 1..200 (default 10)")
    aero.add_argument("--spanwise-boxes", type=int, default=None, metavar="N",
                      help="CAERO1 boxes along the semi-span, shared by the centre-box and outer panels, 2..500 "
                      "(default 20)")
    aero.add_argument("--chordwise-boxes", type=int, default=None, metavar="N",
                      help="CAERO1 boxes along the chord, 1..500 (default 8)")
    pg.add_argument("--load-factor", type=float, default=1.0, metavar="N",
                    help="load factor of the symmetric maneuver (lift n W and n g weight as nodal loads)")
    pg.add_argument("--no-ribs", action="store_true", help="shell: no ribs (default: ribs at the 19 rib stations)")
    pg.add_argument("--rib-thickness", type=float, default=0.002, metavar="M", help="shell: rib thickness (m)")
    pg.add_argument("--overwrite", action="store_true", help="replace an existing FILE instead of refusing")
    pg.add_argument("file", metavar="FILE", help="deck to write")
    pg.set_defaults(func=run_export_pegasus)


def run_export(args) -> int:
    check_output_file(args.file, "FILE", overwrite=args.overwrite)
    for name in ("tip_load", "tip_moment"):
        if not np.all(np.isfinite(getattr(args, name))):
            raise ValueError(f"--{name.replace('_', '-')} must be finite")
    walls = design_walls(args.design, wing_box_case.NAME) if args.design else None
    sec = wing_box_sections(args.geometry, args.t_spar, args.t_skin, walls)
    build = beam_deck if args.fidelity == "beam" else shell_deck
    text = build(sec, ALUMINIUM, args.format, tip_force=args.tip_load, tip_moment=args.tip_moment)
    write_atomic(text, args.file)
    print(f"wingmdao export: wrote {args.fidelity} model ({args.format}) to {args.file}", file=sys.stderr)
    return 0


def pegasus_deck(design, fmt, fidelity, load_factor=1.0, ribs=True, rib_thickness=0.002) -> str:
    """Deck text of the PEGASUS wing (``verify pegasus``'s model and loads, :mod:`wingmdao.fe.export`)."""
    if not (np.isfinite(rib_thickness) and 0 < rib_thickness <= 0.5):
        raise ValueError(f"--rib-thickness = {rib_thickness} m; allowed range (0, 0.5] m")
    geo, sec, line, _, structural, _ = pegasus_setup(design, load_factor)
    y = geo.span_coordinate
    engines = engine_stations(pegasus_case, geo)
    if fidelity == "shell":
        return shell_deck(sec, ALUMINIUM, fmt, ribs_y=list(y[1:]) if ribs else [], rib_thickness=rib_thickness,
                          loads=lambda model: fe_loads(pegasus_case, geo, sec, model, line, structural, load_factor, G0),
                          point_masses=engines)
    weight = np.zeros((y.size, 3))
    weight[:, 2] = -load_factor * G0 * structural
    loads = lumped_line_loads(sec, y, y, line.force_per_length + weight, line.moment_per_length)
    loads += point_weights(sec, engines, gravity=load_factor * G0)
    per = 4      # 4 elements per station interval (ccx tip deflection: 0.81061 m with 1, 0.81035 m with 4)
    masses = [(per * int(np.argmin(abs(y - ye))), m) for ye, m in engines]
    return beam_deck(sec, ALUMINIUM, fmt, nodes_per_segment=per, loads=loads, point_masses=masses)


def run_export_pegasus(args) -> int:
    check_output_file(args.file, "FILE", overwrite=args.overwrite)
    if args.format == AEROELASTIC:
        return run_export_aeroelastic(args)
    for name in AEROELASTIC_ONLY:
        if getattr(args, name) is not None:
            raise ValueError(f"--{name.replace('_', '-')} is read by --format {AEROELASTIC} only; drop it "
                             f"with --format {args.format}")
    text = pegasus_deck(args.design, args.format, args.fidelity, args.load_factor, not args.no_ribs,
                        args.rib_thickness)
    write_atomic(text, args.file)
    print(f"wingmdao export: wrote pegasus {args.fidelity} model ({args.format}) to {args.file}", file=sys.stderr)
    return 0


def run_export_aeroelastic(args) -> int:
    """``export pegasus --format nastran-aeroelastic``: the deck of :mod:`wingmdao.fe.nastran_aero`."""
    if args.fidelity != "beam":
        raise ValueError(f"--fidelity {args.fidelity}: --format {AEROELASTIC} writes the beam model; "
                         "drop --fidelity or give --fidelity beam")
    if args.load_factor != 1.0:
        raise ValueError(f"--load-factor = {args.load_factor:g}: --format {AEROELASTIC} writes no static loads "
                         "(its SOL 144 trims the wing itself); drop --load-factor")
    opts = {name: default if getattr(args, name) is None else getattr(args, name)
            for name, default in AEROELASTIC_ONLY.items()}
    text = nastran_aeroelastic_deck(pegasus_walls(args.design), **opts)
    write_atomic(text, args.file)
    print(f"wingmdao export: wrote pegasus aeroelastic beam model (Nastran SOL {opts['sol']}) to {args.file}",
          file=sys.stderr)
    return 0
