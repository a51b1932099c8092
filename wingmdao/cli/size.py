"""``wingmdao size CASE``: minimum-mass sizing of a shipped case; ``wingmdao n2 CASE``: its N2 diagram."""

from __future__ import annotations

import dataclasses
import importlib
import importlib.util
import os
import sys
import time

import numpy as np

import wingmdao.cli._openmdao  # noqa: F401  (first: OpenMDAO without the matplotlib of its report plugins)
import openmdao.api as om

from wingmdao import sizing
from wingmdao.cases import (add_option_arguments, available_cases, options_from_namespace, pegasus_stick,
                            resolve_aero_theory)
from wingmdao.cli import COMMANDS
from wingmdao.cli._aerostruct import add_parser
from wingmdao.cli._args import add_aero_theory_argument, add_deprecated_alias, add_output_arguments
from wingmdao.cli._io import EXIT_INTERRUPTED, check_output_dir, check_output_file, refuse_existing, say, warn, write_json
from wingmdao.envelope import (check_stations, format_critical_table, output_paths, stick_set_envelope,
                               write_envelope_outputs)
from wingmdao.limits import check_memory
from wingmdao.loads.iteration import load_iteration
from wingmdao.loads.matrix import read_matrix
from wingmdao.loads.turbulence_analysis import sizing_turbulence_options
from wingmdao.panel_sizing import size_two_level
from wingmdao.panels.layout import STIFFENER_VARS
from wingmdao.parallel import assign_cases, launched_ranks, world_comm
from wingmdao.report import best_design, read_history
from wingmdao.results import write_case_plots
from wingmdao.stability.cases import FLUTTER_CASES, flutter_search, sizing_flutter_options
from wingmdao.utils.memory import return_freed_memory, return_large_blocks_on_free

#: --presize upper bound (passes)
MAX_PRESIZE = 20
#: --flutter-margin range (x V_D): below 1 the constraint asks less than flutter-free up to V_D
FLUTTER_MARGIN = (1.0, 2.0)


def _add_common(p, *, is_sizing: bool):
    add_output_arguments(p, what="the recording and plots" if is_sizing else "the N2 diagram (CASE_n2.html)",
                         plots=is_sizing, json=is_sizing)
    if is_sizing:
        p.add_argument("--optimizer", default="SLSQP", choices=["SLSQP", "SNOPT", "IPOPT"],
                       help="optimizer (SNOPT needs pyoptsparse; IPOPT runs through pyoptsparse, else "
                            "through cyipopt: pip install wingmdao[ipopt]; SLSQP runs through SciPy "
                            "when pyoptsparse does not import)")
        p.add_argument("--maxiter", type=int, default=None, metavar="N", help="maximum optimizer iterations (default unset: the case's choice)")
        p.add_argument("--presize", type=int, default=None, metavar="N",
                       help="fully stressed design passes before the optimizer (box sections; 0 = off; "
                            "default unset: the case's choice, 4 for pegasus and crm)")
        p.add_argument("--analysis-only", action="store_true",
                       help="analyse the initial design without optimizing")
        p.add_argument("--potato-stations", metavar="I", type=int, nargs="+", default=None,
                       help="station indices of the bending-torsion potato plots (default: root, mid, 3/4 span)")
        p.add_argument("--quiet", action="store_true", help="no per-evaluation progress lines")
        p.add_argument("--flutter-margin", metavar="F", type=float, default=None,
                       help="add the constraint flutter speed >= F V_D (14 CFR 25.629: 1.15) as a damping "
                            "constraint at speeds up to F V_D (cases with aerodynamic data: pegasus; docs/flutter.md)")
        p.add_argument("--turbulence", action="store_true",
                       help="add the 14 CFR 25.341(b) continuous-turbulence constraint: KS of the corner design stresses "
                            "1 g +/- U_sigma A-bar <= yield at V_C, root clamped, the vortex lattice with --aero coupled --aero-theory "
                            "vlm|dlm (else strip theory), structural damping --damping-ratio "
                            "when > 0, else 0.02 (cases with aerodynamic data: pegasus; docs/turbulence.md); with --alleviation "
                            "the file's surfaces and law (no load-factor law) in it, with --size-gains the gust case's "
                            "sized gains and turbulence_actuator_ks <= 1 (KS of U_sigma A-bar of each surface's "
                            "deflection and rate over its limits; reported with fixed gains) (docs/controls.md)")
        p.add_argument("--matrix", metavar="FILE.yaml", default=None,
                       help="size against the critical cases of a loads matrix (docs/loads-matrix.md), re-check "
                            "the whole matrix at the optimum, repeat while the critical set changes (load "
                            "iteration; cases with a loads-matrix model: pegasus; one process, no plots or recording)")
        p.add_argument("--model", choices=("wing", "stick"), default="wing",
                       help="wing (the lone wing, default) or stick (pegasus: the wing's walls sized for the trimmed "
                            "maneuvers and/or the gust, or the --gust-set, of --loads on the free half aircraft's "
                            "stick model, wing, fuselage, fin and tail with strip aerodynamics on wing and tail; "
                            "docs/stick-model.md)")
        p.add_argument("--size-beams", metavar="BEAMS", default=None,
                       help="with --model stick: comma list of the beams whose sections are sized, from wing, tail, "
                            "fuselage (the wing always is): the horizontal tail's box walls and the fuselage's tube "
                            "wall become design variables with von Mises KS constraints at their stations in every "
                            "case and their mass in the objective (docs/stick-model.md)")
        p.add_argument("--no-flutter-search", action="store_true",
                       help="do not search the flutter speed of the result (flutter_speed_m_s, cases with "
                            "aerodynamic data)")


def register(subparsers):
    cases = available_cases()
    for cmd, is_sizing in (("size", True), ("n2", False)):
        p = subparsers.add_parser(
            cmd,
            help=COMMANDS[cmd].help,
            description=(
                "Minimum-mass sizing of the wall thicknesses of a shipped case. Every run records to "
                "SQLite in --out; read it back with 'wingmdao report'." if is_sizing else
                "Set up a case's sizing model and write its N2 diagram to --out/CASE_n2.html."),
        )
        sub = p.add_subparsers(dest="case", metavar="CASE")
        for name, mod in cases.items():
            cp = sub.add_parser(name, help=mod.HELP, description=mod.HELP)
            # generated from the options dataclass, the one table of the case's options
            add_option_arguments(cp, mod.OPTIONS, deprecated_alias=add_deprecated_alias)
            shared = {f.name: f for f in dataclasses.fields(mod.OPTIONS) if f.metadata.get("shared")}
            if "aero_theory" in shared:  # the flag's one spelling (wingmdao.cli._args), the case's default
                theory = shared["aero_theory"]
                add_aero_theory_argument(cp, default=theory.default, dlm=(
                    ", or dlm (the coupled gust on the doublet lattice in the modal basis of the initial design's "
                    "clamped jig, the design's mass and stiffness projected on it, over the trimmed 1 g state on the "
                    "vortex-lattice beam; the maneuvers use the vortex lattice)")
                    if "dlm" in theory.metadata.get("choices", ()) else False)
            _add_common(cp, is_sizing=is_sizing)
            cp.set_defaults(func=run_size if is_sizing else run_n2, case_module=mod)
        if is_sizing:  # OpenAeroStruct's uCRM fuel burn: a problem of its own, not a WingSizing case
            add_parser(sub)
        p.set_defaults(func=lambda a, p=p: (p.print_help(), 0)[1])


def run_stem(args) -> str:
    """File stem of a run's outputs in --out: the case name, plus the load set for cases that have
    one (``pegasus_all``, ``pegasus_maneuver``), so runs of different load sets never clobber."""
    stem = args.case_module.NAME.replace("-", "_")
    loads = getattr(args, "loads", None)
    return f"{stem}_{loads}" if loads else stem


def _plot_paths(stem, setup):
    paths = [f"{stem}_thickness.png"] + ([f"{stem}_panels.png"] if setup.panels is not None else [])
    for case in setup.load_cases:
        if getattr(case, "time", None) is not None:
            paths += [f"{stem}_{case.name}_stress.png", f"{stem}_{case.name}_loads.png"]
    return paths


def run_size(args) -> int:
    # OpenMDAO is imported with this module (wingmdao.cli._openmdao), before the run has any data:
    # it keeps the traceback of its failed optional ``import jax`` as module globals
    # (``openmdao.func_api``, ``openmdao.components.explicit_func_comp``, ``implicit_func_comp``), and a
    # traceback keeps every frame that was on the stack at the import alive: imported from inside
    # ``_size``, it would hold the sizing problem (~300 MB) until the process ends.
    return_large_blocks_on_free()  # the resident set follows the memory in use, design point after design point
    return _size(args)


def _size(args) -> int:
    """``wingmdao size CASE`` once its modules are imported (:func:`run_size`)."""
    comm = world_comm()
    root = comm is None or comm.rank == 0
    if not root:  # under mpirun only rank 0 prints, records and writes files
        sys.stdout = open(os.devnull, "w")

    if args.maxiter is not None and args.maxiter < 1:
        raise ValueError(f"--maxiter = {args.maxiter}; allowed range >= 1 iteration "
                         "(use --analysis-only to analyse without optimizing)")
    if args.presize is not None and not 0 <= args.presize <= MAX_PRESIZE:
        raise ValueError(f"--presize = {args.presize}; allowed range [0, {MAX_PRESIZE}] passes (each pass is a full "
                         f"analysis of every load case: {args.presize} passes cost ~{args.presize} optimizer "
                         "iterations)")
    if args.flutter_margin is not None and not (np.isfinite(args.flutter_margin)
                                                and FLUTTER_MARGIN[0] <= args.flutter_margin <= FLUTTER_MARGIN[1]):
        raise ValueError(f"--flutter-margin = {args.flutter_margin}; allowed range [{FLUTTER_MARGIN[0]:g}, "
                         f"{FLUTTER_MARGIN[1]:g}] x V_D (14 CFR 25.629 asks for 1.15)")
    # every output is checked before the (possibly hour-long) run starts
    check_output_dir(args.out, "--out")
    stem = os.path.join(args.out, run_stem(args))
    recording = None if (args.analysis_only or not root) else stem + ".sql"
    if root:
        check_output_file(args.json, "--json", overwrite=args.overwrite, others={"recording": recording})
    if getattr(args, "model", "wing") == "stick":
        _check_stick_args(args, comm)
    else:
        size_beams(args)   # refused without --model stick
    case_options = options_from_namespace(args.case_module.OPTIONS, args)
    setup = args.case_module.build(case_options)
    if getattr(args, "model", "wing") == "stick":
        return _size_stick(args, setup, case_options, stem, recording, root=root, comm=comm)
    if args.flutter_margin is not None:
        if comm is not None and comm.size > 1:
            raise ValueError("--flutter-margin: the flutter constraint runs in one process (no mpirun)")
        setup.flutter = sizing_flutter_options(args.case_module.NAME, setup.geometry.num_nodes, args.flutter_margin)
        setup.notes.append(f"flutter constraint: KS of Re(lambda) <= 0 (rho 100 s) at {args.flutter_margin:g} V_D x "
                           f"(0.25, 0.5, 0.75, 1) = {', '.join(f'{v:.1f}' for v in setup.flutter['speeds'])} m/s")
    if getattr(args, "turbulence", False):
        _add_turbulence(args, setup, comm, case_options)
    if args.matrix is not None:
        return _run_load_iteration(args, setup, comm)
    plots = [] if args.no_plots else _plot_paths(stem, setup)
    if len(setup.load_cases) > 1:  # an envelope: its loads file and plots are outputs too
        check_stations(args.potato_stations, setup.geometry.num_nodes)
        plots += output_paths(stem, plots=not args.no_plots)
    elif args.potato_stations is not None:
        warn("--potato-stations ignored: potato plots are drawn for runs of several load cases")
    case_files = (args.case_module.output_files(stem, setup) if root and hasattr(args.case_module, "output_files")
                  else [])  # a case's own outputs (e.g. stw: lift and twist CSV files)
    if root:  # --json may not name any of the run's own outputs
        check_output_file(args.json, "--json", overwrite=args.overwrite,
                          others={"recording": recording, **{f"output {p}": p for p in plots + case_files}})
    refuse_existing([recording, *plots, *case_files], overwrite=args.overwrite,
                    what="recording, envelope, plots" + (" and case files" if case_files else ""))
    _driver_options(setup.options, args, recording)
    say(f"wingmdao size {args.case_module.NAME}: {len(setup.load_cases)} load case(s) "
        f"[{', '.join(c.name for c in setup.load_cases)}], {setup.geometry.num_nodes} stations")
    for note in setup.notes:
        if note.startswith("warning: "):  # e.g. options the chosen load set ignores
            warn(note[len("warning: "):])
        else:
            say(f"  note: {note}")
    if comm is not None:
        say(f"  MPI: {comm.size} ranks share the {len(setup.load_cases)} load cases (wingmdao.parallel)")
    optimize = not args.analysis_only

    mine = (setup.load_cases if comm is None else
            [setup.load_cases[i] for i in assign_cases(setup.load_cases, comm.size)[comm.rank]])
    check_memory(mine, setup.geometry.num_nodes)  # before any solve: this rank's marches must fit
    two_level = getattr(setup, "panel_sizing", "full") == "two-level"
    if two_level:
        _check_two_level(args, setup, comm)
        recording = None   # no driver to record: the outer level is fully stressed passes
    else:
        prob, desc = sizing.build_problem(setup.geometry, setup.load_cases, setup.material, setup.options,
                                          driver=optimize, section=setup.section, comm=comm or False,
                                          flutter=setup.flutter, panels=setup.panels, turbulence=setup.turbulence)

    interrupted = failed = False
    try:
        if two_level:

            prob, result = size_two_level(setup, progress=lambda line: say(f"  {line}"))
            desc = result["driver"]
        else:
            result = sizing.presize_and_size(prob, setup, desc, optimize=optimize)
    except KeyboardInterrupt:
        if two_level:   # no recording and no design yet to keep
            raise
        interrupted = True
        prob.cleanup()  # closes (and commits) the recording
        result = sizing.partial_result(prob, setup, desc, recording)
    except om.AnalysisError as exc:  # the beam failed (e.g. a load no design can carry): keep what we have
        if two_level:
            raise
        failed = True
        prob.cleanup()
        result = sizing.partial_result(prob, setup, desc, recording, interrupted=False)
        result["message"] = f"the analysis failed: {' '.join(str(exc).split())}"
        for key in ("ks", "max_ks", "active_constraints"):  # from the unconverged solve: meaningless
            result.pop(key, None)
    result["case"] = args.case_module.NAME
    gains = sizing.control_gains(prob, setup.load_cases) if comm is None and not failed else {}
    if gains:
        result["control_law"] = gains
    result["mpi_ranks"] = launched_ranks() if comm is not None else 1
    if recording:
        result["recording"] = recording
    # JSON on standard output is one document: written once, after the flutter search
    deferred = args.json == "-" and root and not (interrupted or failed)
    try:
        code, design = _finish(args, prob, setup, result, stem, recording, root=root, comm=comm,
                               interrupted=interrupted, failed=failed, write=not deferred)
    except KeyboardInterrupt:  # Ctrl-C after the optimizer finished: its result is kept
        if interrupted or failed or not root:
            raise
        prob.cleanup()
        return _interrupted_after_sizing(args, result, recording)
    except Exception:
        prob.cleanup()  # the recording is closed whatever failed (one SQLite file: no -wal/-shm left)
        if deferred:  # a failure in the outputs (e.g. the plots) must not lose the result
            write_json(result, args.json)
        raise
    if interrupted or failed or not root:
        return code
    # the flutter search needs only the design: it runs once the sizing problem is freed, so it
    # does not stack on the problem's vectors
    del prob, desc
    return_freed_memory()
    try:
        _add_flutter_result(result, args, setup, design)
    except KeyboardInterrupt:  # the sizing result is kept (written already unless on standard output)
        return _interrupted_after_sizing(args, result, recording)
    if args.json and (deferred or "flutter_speed_m_s" in result):
        write_json(result, args.json)
    return code


def _check_two_level(args, setup, comm) -> None:
    """``--panel-sizing two-level``: ValueError for what its outer level does not carry."""
    if comm is not None and comm.size > 1:
        raise ValueError("--panel-sizing two-level runs in one process (no mpirun)")
    for flag, given in (("--flutter-margin", setup.flutter is not None),
                        ("--turbulence", setup.turbulence is not None), ("--analysis-only", args.analysis_only)):
        if given:
            raise ValueError(f"--panel-sizing two-level does not take {flag} (its outer level has strength and "
                             "buckling constraints only; use --panel-sizing full)")


def _check_stick_args(args, comm) -> None:
    """``--model stick``: ValueError for a case without a stick model or options it does not take."""
    if args.case_module.NAME != "pegasus":
        raise ValueError(f"--model stick: case {args.case_module.NAME!r} has no stick model; allowed: pegasus")
    for flag, given in (("--turbulence", getattr(args, "turbulence", False)), ("--matrix", args.matrix is not None),
                        ("--gust-gradients-ft", getattr(args, "gust_gradients_ft", None)),
                        ("--gust-gradient-count", getattr(args, "gust_gradient_count", None)),
                        ("--load-history", getattr(args, "load_history", None))):
        if given:
            raise ValueError(f"--model stick does not take {flag}; it sizes for the 25.337 maneuvers and the 1-cos "
                             "gusts of one --gust-gradient-ft or of a --gust-set (--loads maneuver, gust or all)")
    if comm is not None and comm.size > 1:
        raise ValueError("--model stick runs in one process (no mpirun)")
    size_beams(args)   # its errors before any solve


#: the beams --size-beams names (the wing is always sized)
SIZE_BEAMS = ("wing", "tail", "fuselage")


def size_beams(args) -> list:
    """The beams besides the wing of ``--size-beams`` (a comma list of :data:`SIZE_BEAMS`); ValueError
    naming the flag and its value for an unknown or repeated beam, or the flag without ``--model stick``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed ``size`` arguments.

    Returns
    -------
    list of str
        The beams to size besides the wing, in the order given.
    """
    value = getattr(args, "size_beams", None)
    if value is None:
        return []
    if getattr(args, "model", "wing") != "stick":
        raise ValueError(f"--size-beams {value}: needs --model stick (the lone wing has no tail or fuselage)")
    names = [v.strip() for v in str(value).split(",") if v.strip()]
    if not names or any(v not in SIZE_BEAMS for v in names) or len(set(names)) != len(names):
        raise ValueError(f"--size-beams = {value!r}; allowed: a comma list of {', '.join(SIZE_BEAMS)}, each once")
    return [v for v in names if v != "wing"]


def _size_stick(args, setup, case_options, stem, recording, *, root, comm) -> int:
    """``--model stick``: the wing's walls sized on the PEGASUS stick model's maneuvers and gust
    (with ``--flutter-margin``, the free aircraft's flutter constraint)
    (:func:`wingmdao.cases.pegasus_stick.sizing_setup`, :func:`wingmdao.sizing.build_stick_problem`);
    JSON and summary (no plots, envelope or flutter search)."""
    setup = pegasus_stick.sizing_setup(setup, case_options)
    refuse_existing([recording], overwrite=args.overwrite, what="recording")
    _driver_options(setup.options, args, recording)
    say(f"wingmdao size {args.case_module.NAME} --model stick: {setup.geometry.num_nodes} wing stations")
    for note in setup.notes:
        say(f"  note: {note}")
    optimize = not args.analysis_only
    flutter = None
    if args.flutter_margin is not None:   # the free aircraft's modes (pegasus_stick.flutter_options)
        flutter = pegasus_stick.flutter_options(setup.load_cases[0], args.flutter_margin)
        say(f"  note: flutter constraint of the free stick aircraft: KS of Re(lambda) <= 0 (rho 100 s) at "
            f"{args.flutter_margin:g} V_D x (0.25, 0.5, 0.75, 1) = {', '.join(f'{v:.1f}' for v in flutter['speeds'])} m/s")
    sized = pegasus_stick.sized_beams(setup.load_cases[0], size_beams(args))
    for b in sized:
        say(f"  note: {b.name} sized: {'box walls' if b.kind == 'box' else 'tube wall'} "
            f"{', '.join(b.design_vars)} in [{b.lower * 1e3:g}, {b.upper * 1e3:g}] mm from {b.initial * 1e3:g} mm; "
            f"KS of its von Mises stress in every case; objective: total_mass")
    prob, desc = sizing.build_stick_problem(setup.geometry, setup.load_cases, setup.material, setup.options,
                                            driver=optimize, flutter=flutter, sized_beams=sized)
    result = sizing.presize_and_size(prob, setup, desc, optimize=optimize, sized_beams=sized)
    result.update(case=args.case_module.NAME, model="stick", mpi_ranks=1)
    gusts = [c for c in setup.load_cases if c.num_times > 1]
    if len(gusts) > 1:   # a gust set: the monitoring stations' envelopes over its gusts at the result
        result["monitoring_envelope"] = stick_set_envelope([
            {"name": c.name, "monitoring_loads": pegasus_stick.case_monitoring_loads(
                c, prob.get_val(f"cases.{c.name}.states"))} for c in gusts])
        for label, env in result["monitoring_envelope"].items():
            say(f"  {label}: moment max {', '.join(f'{v / 1e3:.1f}' for v in env['moment_max_n_m'])} kN m "
                f"({', '.join(env['moment_max_gust'])})")
    for name, beam in result.get("beams", {}).items():
        say(f"  {name}: walls {beam['mass_kg']:.2f} kg" + (f" (total {result['total_mass_kg']:.2f} kg)"
                                                            if name == "wing" else ""))
    if recording:
        result["recording"] = recording
    if args.json and root:
        write_json(result, args.json)
    _print_summary(result)
    prob.cleanup()
    return 0 if result["success"] else 1


def _interrupted_after_sizing(args, result, recording) -> int:
    """Ctrl-C after the optimizer finished (outputs, flutter search): the JSON of its result, marked
    ``interrupted``, with the recording's best design; exit code 130."""
    result["interrupted"] = True
    result["message"] = (f"{result.get('message', '')}; interrupted while writing the outputs "
                         "(plots, envelope, flutter search): the design is the optimizer's result").lstrip("; ")
    if recording and os.path.exists(recording):
        try:
            best = best_design(read_history(recording))
        except ValueError:
            best = None
        if best is not None:
            result["best_design"] = best
    if args.json:
        write_json(result, args.json)
    say(f"wingmdao size {args.case_module.NAME}: interrupted after the optimizer finished; its result in "
        f"{'the JSON on standard output' if args.json == '-' else args.json}"
        + (f", recording {recording}" if recording else ""))
    return EXIT_INTERRUPTED


def _driver_options(opts, args, recording) -> None:
    """The optimizer flags (--optimizer, --maxiter, --presize, --quiet) and the recording path on
    the case's sizing options."""
    opts.optimizer = args.optimizer
    if args.maxiter is not None:
        opts.maxiter = args.maxiter
    if args.presize is not None:
        opts.presize = args.presize
    opts.recording = recording
    opts.progress = not args.quiet


def _run_load_iteration(args, setup, comm) -> int:
    """--matrix: the load iteration of :mod:`wingmdao.loads.iteration`; JSON: the last sizing's result
    with ``load_iteration`` (passes; cases sized, re-checked, added; converged)."""
    module = args.case_module
    if not (hasattr(module, "beam_params") and hasattr(module, "GUST_SET_DEFAULTS")):
        raise ValueError(f"--matrix: case {module.NAME!r} has no loads-matrix model (cases with it: pegasus)")
    if comm is not None:
        raise ValueError("--matrix: the load iteration runs in one process (no mpirun); "
                         "'mpirun -n P wingmdao loads CASE --matrix FILE' runs a matrix over ranks")
    if args.analysis_only:
        raise ValueError("--matrix sizes against the matrix; without sizing use 'wingmdao loads CASE --matrix FILE'")
    matrix = read_matrix(args.matrix)
    _driver_options(setup.options, args, None)
    say(f"wingmdao size {module.NAME} --matrix {args.matrix}: load iteration over the matrix's critical cases")
    result = load_iteration(module, matrix, setup, size=lambda s: sizing.size_case(s, comm=False),
                            progress=sys.stderr)
    result["case"] = module.NAME
    result["matrix"] = os.path.abspath(args.matrix)
    it = result["load_iteration"]
    say(f"load iteration: {it['sized']} cases sized, {it['rechecked']} re-checked, {it['added']} added after the "
        f"first pass, {'converged' if it['converged'] else 'not converged'}; mass {result.get('mass_kg', float('nan')):.1f} kg")
    write_json(result, args.json)
    return 0


def _finish(args, prob, setup, result, stem, recording, *, root, comm, interrupted, failed, write=True):
    """The outputs after the solve that need the problem: responses, envelope, JSON (``write``),
    plots, summary. Returns the exit code and the design of the flutter search (None: no search)."""
    if comm is None and not (interrupted or failed) and hasattr(args.case_module, "TOGW_LB"):
        result["load_case_response"] = sizing.case_responses(prob, setup, args.case_module.TOGW_LB)
    plots_on = not args.no_plots and root and not (interrupted or failed)
    if plots_on:
        if importlib.util.find_spec("matplotlib") is None:
            warn("plots skipped (plots need matplotlib: pip install 'wingmdao[plot]'); "
                 "the JSON and the recording are written")
            plots_on = False
    design = None
    if root and not (interrupted or failed):
        sizing.release_derivative_storage(prob)  # the adjoint's blocks are not needed again
        design = _flutter_design(result, args, setup, prob)
    if root and hasattr(args.case_module, "write_outputs") and not (interrupted or failed):
        args.case_module.write_outputs(prob, setup, stem, result)   # a case's own files (e.g. stw's CSVs)
    if root and len(setup.load_cases) > 1 and not (interrupted or failed):
        # an envelope: critical case per station, envelopes, potato plots

        turbulence = sizing.turbulence_loads(prob)  # 25.341(b) ellipses on the potato plots (with --turbulence)
        env = write_envelope_outputs(prob, setup, stem, args.potato_stations, plots=plots_on, turbulence=turbulence)
        if turbulence is not None:
            result["turbulence_loads"] = turbulence
        result["envelope_file"] = env["envelope_file"]
        result["critical_cases"] = env["critical_cases"]
        result.setdefault("plots", []).extend(env["plots"])
        say("  critical load case per station:")
        say("\n".join("    " + line for line in format_critical_table(env["critical_cases"]).splitlines()))
    if args.json and root and write:  # the result first: a plotting failure must never lose it
        write_json(result, args.json)
    if plots_on:
        try:
            result["plots"] = write_case_plots(prob, setup, stem, result) + result.get("plots", [])
        except ImportError as exc:
            warn(f"plots skipped ({exc}); the JSON and the recording are written")
        else:
            if args.json and args.json != "-" and root and write:
                write_json(result, args.json)
    if not failed:
        _print_summary(result)
    prob.cleanup()
    if failed:
        raise om.AnalysisError(result["message"][len("the analysis failed: "):]
                               + (" (partial result in the JSON on standard output)" if args.json == "-" else
                                  f" (partial result in {args.json})" if args.json else ""))
    if interrupted:
        say(f"wingmdao size {args.case_module.NAME}: interrupted; best design so far in "
            f"{'the JSON on standard output' if args.json == '-' else args.json}"
            + (f", recording {recording}" if recording else ""))
        return EXIT_INTERRUPTED, None
    return (0 if result["success"] else 1), design


def _add_turbulence(args, setup, comm, case_options=None) -> None:
    """--turbulence: the TurbulenceStressKS options of the case (one process, box sections, a case
    with aerodynamic data), 2 % structural damping at the first mode when the case has none; the
    vortex lattice with ``--aero coupled --aero-theory vlm|dlm``, else strip theory."""
    if comm is not None and comm.size > 1:
        raise ValueError("--turbulence: the turbulence constraint runs in one process (no mpirun)")
    module = args.case_module
    if not all(hasattr(module, a) for a in ("aero_data", "flight_point", "GUST_SET_DEFAULTS", "CRUISE_ALTITUDE_FT")):
        raise ValueError(f"--turbulence: case {module.NAME!r} has no aerodynamic data (cases with it: pegasus)")
    if setup.section != "box":
        raise ValueError(f"--turbulence needs box sections (the linear corner stresses), got section {setup.section!r}")
    zeta = getattr(args, "damping_ratio", None) or 0.02  # said in the help and in the run's notes
    damping, note = module.gust_damping(zeta, getattr(args, "damping_frequency_hz", None), setup.geometry, setup.options)
    aero = getattr(case_options, "aero", "strip")
    theory = resolve_aero_theory(getattr(case_options, "aero_theory", None), aero) if aero == "coupled" else "strip"
    theory = "vlm" if theory in ("vlm", "dlm") else "strip"  # dlm: its k = 0 limit, the lattice with 2-D lags
    alleviation = getattr(args, "alleviation", None)
    setup.turbulence = sizing_turbulence_options(module, setup, damping=damping, alleviation=alleviation,
                                                 aero_theory=theory)
    if alleviation:  # the turbulence constraint uses the file even where the case's own loads ignore it
        setup.notes = _drop_ignored_flag(setup.notes, f"--alleviation {alleviation}")
    law = setup.turbulence.get("control_law")
    with_law = "" if not alleviation else (
        f", control surfaces of {alleviation}" + (f" with the law on {', '.join(law.outputs)}" if law else " held"))
    setup.notes.append(f"turbulence constraint: KS of (+/- s_1g + U_sigma A-bar)/sigma_y - 1 <= 0 at V_C, U_sigma = "
                       f"{setup.turbulence['u_sigma']:.2f} m/s TAS, root clamped, "
                       f"{'vortex lattice' if theory == 'vlm' else 'strip theory'}, {note}{with_law}")


def _drop_ignored_flag(notes, flag) -> list:
    """``notes`` with ``flag`` taken out of the case's "ignored" warnings (a warning left without flags
    is dropped)."""
    out = []
    for note in notes:
        if note.startswith("warning: ignored") and flag in note:
            head, _, flags = note.rpartition(": ")
            kept = [f for f in flags.split(", ") if f != flag]
            if not kept:
                continue
            note = f"{head}: {', '.join(kept)}"
        out.append(note)
    return out


def _flutter_design(result, args, setup, prob):
    """``dive_speed_m_s`` (and the constraint's margin and speeds) in the result of a case with
    aerodynamic data, and the design its flutter search analyses: the result's thicknesses, plus
    the stiffeners of a stiffened design. None when there is no search."""

    name = args.case_module.NAME
    if name not in FLUTTER_CASES or "thickness" not in result:
        return None
    result["dive_speed_m_s"] = float(importlib.import_module(f"wingmdao.cases.{name}").flight_point()["dive_speed"])
    if setup.flutter is not None:
        result["flutter_margin"] = float(args.flutter_margin)
        result["flutter_constraint_speeds_m_s"] = [float(v) for v in setup.flutter["speeds"]]
    if args.no_flutter_search:
        return None
    design = dict(result["thickness"])
    if setup.panels is not None:   # the stiffened design: its stiffeners are in the sections too
        design.update({k: sizing.station_values(prob, k) for k in STIFFENER_VARS})
    return design


def _add_flutter_result(result, args, setup, design) -> None:
    """The result's ``flutter_speed_m_s`` (a sweep and refinement at the design,
    :func:`wingmdao.stability.cases.flutter_search`) for cases with aerodynamic data; nothing when
    ``design`` is None (:func:`_flutter_design`)."""

    if design is None:
        return
    t0 = time.perf_counter()
    found = flutter_search(args.case_module.NAME, setup.geometry.num_nodes, design, panels=setup.panels)
    result["flutter_speed_m_s"] = found["flutter_speed"]
    result["flutter_frequency_rad_s"] = found["flutter_frequency"]
    result["divergence_speed_m_s"] = found["divergence_speed"]
    result["flutter_search_max_speed_m_s"] = found["sweep_max_speed"]
    result["flutter_search_s"] = time.perf_counter() - t0
    vf = found["flutter_speed"]
    say(f"  flutter of the result: {'none' if vf is None else f'{vf:.1f} m/s'} below "
        f"{found['sweep_max_speed']:.0f} m/s (V_D = {found['dive_speed']:.1f} m/s), "
        f"{result['flutter_search_s']:.1f} s")


def _print_summary(res):
    if "mass_kg" not in res:
        print(f"  success: {res['success']}   {res.get('message', '')}")
        return
    print(f"  driver: {res['driver']}")
    print(f"  success: {res['success']}   mass: {res['mass_kg']:.2f} kg   wall time: {res['wall_s']:.1f} s"
          + (f"   iterations: {res['iterations']}" if res.get("iterations") is not None else ""))
    if not res["success"] and res.get("message"):
        print(f"  message: {res['message']}")
    if res.get("failed_evaluations"):
        print(f"  failed analyses (SLSQP backed off): {len(res['failed_evaluations'])} "
              f"(evaluations {', '.join(str(f['evaluation']) for f in res['failed_evaluations'][:10])}"
              f"{', ...' if len(res['failed_evaluations']) > 10 else ''})")
    for case, fams in res["ks"].items():
        vals = ", ".join(f"{f} = {v:+.3e}" for f, v in fams.items())
        print(f"  KS {case}: {vals}")
    for case, r in res.get("load_case_response", {}).items():
        print(f"  {case}: peak load factor {r['peak_load_factor']:+.3f}, "
              f"peak root bending {r['peak_root_bending_moment_n_m'] / 1e3:.1f} kN m")
    if res.get("active_constraints"):
        print(f"  active: {', '.join(res['active_constraints'])}")
    for p in res.get("plots", []):
        print(f"  wrote {p}")
    if res.get("recording"):
        print(f"  recording: {res['recording']}  (wingmdao report {res['recording']})")


def run_n2(args) -> int:
    check_output_dir(args.out, "--out")
    path = os.path.join(args.out, f"{args.case_module.NAME.replace('-', '_')}_n2.html")
    refuse_existing([path], overwrite=args.overwrite, what="N2 diagram")
    setup = args.case_module.build(options_from_namespace(args.case_module.OPTIONS, args))
    prob, _ = sizing.build_problem(setup.geometry, setup.load_cases, setup.material, setup.options,
                                   driver=True, section=setup.section, panels=setup.panels)
    om.n2(prob, outfile=path, show_browser=False)
    say(f"wrote {path}")
    return 0
