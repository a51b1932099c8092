"""``wingmdao export wing-box|pegasus``: write the (sized) wing box as a CalculiX, Abaqus or Nastran deck
(beam stick model or shell model), see :mod:`wingmdao.fe.export`; ``export pegasus --format
nastran-aeroelastic``: the beam with its masses, lifting surface, splines and the SOL 144/145/146
cards, see :mod:`wingmdao.fe.nastran_aero`."""

from __future__ import annotations
import sys

import numpy as np
import wingmdao.cli._openmdao  # noqa: F401  (first: OpenMDAO without the matplotlib of its report plugins)
from wingmdao.cli.parsers.export import AEROELASTIC
from wingmdao.cli._io import check_output_file
from wingmdao.cases import pegasus as pegasus_case, wing_box as wing_box_case
from wingmdao.cases.planform import G0
from wingmdao.cli._verify_pegasus import pegasus_setup, pegasus_walls
from wingmdao.cli.verify import design_walls, wing_box_sections
from wingmdao.fe.export import beam_deck, shell_deck, write_atomic
from wingmdao.fe.wing_loads import lumped_line_loads, point_weights
from wingmdao.materials import ALUMINIUM
from wingmdao.cases.pegasus_verification import engine_stations, fe_loads, nastran_aeroelastic_deck

#: the flags only the aeroelastic deck reads, with their defaults
AEROELASTIC_ONLY = {"sol": 146, "modes": 10, "spanwise_boxes": 20, "chordwise_boxes": 8}


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
