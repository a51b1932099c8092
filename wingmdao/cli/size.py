"""``wingmdao size CASE``: minimum-mass sizing of a shipped case; ``wingmdao n2 CASE``: its N2 diagram."""

from __future__ import annotations

import argparse
import os


def _add_common(p, *, sizing: bool):
    p.add_argument("--json", metavar="PATH", default=None, help="write results as JSON (- = stdout)")
    p.add_argument("--out", metavar="DIR", default="results",
                   help="folder for the recording and plots")
    if sizing:
        p.add_argument("--optimizer", default="SLSQP", choices=["SLSQP", "SNOPT", "IPOPT"],
                       help="optimizer (SNOPT/IPOPT need pyoptsparse; default SLSQP, via SciPy "
                            "when pyoptsparse does not import)")
        p.add_argument("--maxiter", type=int, default=None, help="maximum optimizer iterations (unset (%(default)s): the case's choice)")
        p.add_argument("--presize", type=int, default=None, metavar="N",
                       help="fully stressed design passes before the optimizer (box sections; 0 = off; "
                            "unset (%(default)s): the case's choice, 4 for pegasus and crm)")
        p.add_argument("--analysis-only", action="store_true",
                       help="analyse the initial design without optimizing")
        p.add_argument("--no-plots", action="store_true", help="do not write PNG plots")
        p.add_argument("--potato-stations", metavar="I", type=int, nargs="+", default=None,
                       help="station indices of the bending-torsion potato plots (default: root, mid, 3/4 span)")
        p.add_argument("--quiet", action="store_true", help="no per-evaluation progress lines")


def register(subparsers):
    from wingmdao.cases import available_cases

    cases = available_cases()
    for cmd, sizing in (("size", True), ("n2", False)):
        p = subparsers.add_parser(
            cmd,
            help=("size a wingbox case for its load cases (minimum mass, KS stress constraints)"
                  if sizing else "write the N2 diagram (HTML) of a case's OpenMDAO model"),
            description=(
                "Minimum-mass sizing of the wall thicknesses of a shipped case. Every run records to "
                "SQLite in --out; read it back with 'wingmdao report'." if sizing else
                "Set up a case's sizing model and write its N2 diagram to --out/CASE_n2.html."),
        )
        sub = p.add_subparsers(dest="case", metavar="CASE")
        for name, mod in cases.items():
            cp = sub.add_parser(name, help=mod.HELP, description=mod.HELP,
                                formatter_class=argparse.ArgumentDefaultsHelpFormatter)
            mod.add_arguments(cp)
            _add_common(cp, sizing=sizing)
            cp.set_defaults(func=run_size if sizing else run_n2, case_module=mod)
        p.set_defaults(func=lambda a, p=p: (p.print_help(), 0)[1])


def run_size(args) -> int:
    import sys

    from wingmdao.cli import write_json
    from wingmdao.parallel import launched_ranks, world_comm
    from wingmdao.sizing import size_case

    comm = world_comm()
    root = comm is None or comm.rank == 0
    if not root:  # under mpirun only rank 0 prints, records and writes files
        sys.stdout = open(os.devnull, "w")
    setup = args.case_module.build(args)
    opts = setup.options
    os.makedirs(args.out, exist_ok=True)
    opts.optimizer = args.optimizer
    if args.maxiter:
        opts.maxiter = args.maxiter
    if args.presize is not None:
        if args.presize < 0:
            raise ValueError(f"--presize must be >= 0 passes, got {args.presize}")
        opts.presize = args.presize
    stem = os.path.join(args.out, args.case_module.NAME.replace("-", "_"))
    opts.recording = None if (args.analysis_only or not root) else stem + ".sql"
    opts.progress = not args.quiet
    print(f"wingmdao size {args.case_module.NAME}: {len(setup.load_cases)} load case(s) "
          f"[{', '.join(c.name for c in setup.load_cases)}], {setup.geometry.num_nodes} stations")
    for note in setup.notes:
        print(f"  note: {note}")
    if comm is not None:
        print(f"  MPI: {comm.size} ranks share the {len(setup.load_cases)} load cases (wingmdao.parallel)")
    prob, result = size_case(setup, optimize=not args.analysis_only, comm=comm or False)
    result["case"] = args.case_module.NAME
    result["mpi_ranks"] = launched_ranks() if comm is not None else 1
    if opts.recording:
        result["recording"] = opts.recording
    if not args.no_plots and root:
        from wingmdao.results import write_case_plots

        result["plots"] = write_case_plots(prob, setup, stem)
    if root and len(setup.load_cases) > 1:  # an envelope: critical case per station, envelopes, potato plots
        from wingmdao.envelope import format_critical_table, write_envelope_outputs

        env = write_envelope_outputs(prob, setup, stem, args.potato_stations, plots=not args.no_plots)
        result["envelope_file"] = env["envelope_file"]
        result["critical_cases"] = env["critical_cases"]
        result.setdefault("plots", []).extend(env["plots"])
        print("  critical load case per station:")
        print("\n".join("    " + line for line in format_critical_table(env["critical_cases"]).splitlines()))
    _print_summary(result)
    if args.json and root:
        write_json(result, args.json)
    prob.cleanup()
    return 0 if result["success"] else 1


def _print_summary(res):
    print(f"  driver: {res['driver']}")
    print(f"  success: {res['success']}   mass: {res['mass_kg']:.2f} kg   wall time: {res['wall_s']:.1f} s"
          f"   iterations: {res.get('iterations')}")
    for case, fams in res["ks"].items():
        vals = ", ".join(f"{f} = {v:+.3e}" for f, v in fams.items())
        print(f"  KS {case}: {vals}")
    if res.get("active_constraints"):
        print(f"  active: {', '.join(res['active_constraints'])}")
    for p in res.get("plots", []):
        print(f"  wrote {p}")
    if res.get("recording"):
        print(f"  recording: {res['recording']}  (wingmdao report {res['recording']})")


def run_n2(args) -> int:
    import openmdao.api as om

    from wingmdao.sizing import build_problem

    setup = args.case_module.build(args)
    os.makedirs(args.out, exist_ok=True)
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options,
                            driver=True, section=setup.section)
    path = os.path.join(args.out, f"{args.case_module.NAME.replace('-', '_')}_n2.html")
    om.n2(prob, outfile=path, show_browser=False)
    print(f"wrote {path}")
    return 0
