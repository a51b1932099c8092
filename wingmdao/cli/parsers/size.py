"""Parser of ``wingmdao size CASE`` and ``wingmdao n2 CASE`` (run: :mod:`wingmdao.cli.size`).

``wingmdao size --help`` lists the cases from :data:`wingmdao.names.CASE_HELP`; the options of a
case come from its options dataclass (its module's ``OPTIONS``, the one table of its options), so
the parser of a named case imports that case's module.
"""

from __future__ import annotations

import dataclasses
import importlib

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import (add_aero_theory_argument, add_deprecated_alias, add_json_argument, add_output_arguments,
                               add_overwrite_argument)
from wingmdao.names import CASE_HELP, CASE_MODULES

#: ``wingmdao size aerostruct-crm`` (:mod:`wingmdao.cli._aerostruct`)
AEROSTRUCT_NAME = "aerostruct-crm"
AEROSTRUCT_HELP = ("uCRM multipoint aerostructural fuel burn (OpenAeroStruct VLM + the wingmdao beam, "
                   "cruise and 2.5 g maneuver), beside OpenAeroStruct's own beam; needs openaerostruct")


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


def case_named(argv, command: str) -> str | None:
    """The case a command line names after ``command``: the first argument after it that is not an option.

    Parameters
    ----------
    argv : sequence of str
        The arguments after the program name.
    command : str
        ``size`` or ``n2``.

    Returns
    -------
    str or None
        The case's name, None without one (or without ``command``).
    """
    argv = list(argv)
    if command not in argv:
        return None
    return next((a for a in argv[argv.index(command) + 1:] if not a.startswith("-")), None)


def _case_module(name: str):
    """The module of a shipped case, None when it does not import (:func:`wingmdao.cases.available_cases`)."""
    try:
        return importlib.import_module(CASE_MODULES[name])
    except ModuleNotFoundError as exc:
        if exc.name != CASE_MODULES[name]:
            raise
        return None


def _add_case(sub, name: str, mod, *, is_sizing: bool) -> None:
    """The parser of ``size NAME`` / ``n2 NAME``: the case's options (from its options dataclass) and the common flags."""
    cases = importlib.import_module("wingmdao.cases")  # add_option_arguments: with the case module, loaded anyway
    cp = sub.add_parser(name, help=mod.HELP, description=mod.HELP)
    # generated from the options dataclass, the one table of the case's options
    cases.add_option_arguments(cp, mod.OPTIONS, deprecated_alias=add_deprecated_alias)
    shared = {f.name: f for f in dataclasses.fields(mod.OPTIONS) if f.metadata.get("shared")}
    if "aero_theory" in shared:  # the flag's one spelling (wingmdao.cli._args), the case's default
        theory = shared["aero_theory"]
        add_aero_theory_argument(cp, default=theory.default, dlm=(
            ", or dlm (the coupled gust on the doublet lattice in the modal basis of the initial design's "
            "clamped jig, the design's mass and stiffness projected on it, over the trimmed 1 g state on the "
            "vortex-lattice beam; the maneuvers use the vortex lattice)")
            if "dlm" in theory.metadata.get("choices", ()) else False)
    _add_common(cp, is_sizing=is_sizing)
    cp.set_defaults(func="wingmdao.cli.size:run_size" if is_sizing else "wingmdao.cli.size:run_n2", case_module=mod)


def register(subparsers, argv=None):
    """Add ``size`` and ``n2``, each with a sub-parser per case.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line: only the case it names gets its options (its module imported); the
        others list their help line. None: every case's options.
    """
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
        named = None if argv is None else case_named(argv, cmd)
        for name in CASE_MODULES:
            mod = _case_module(name) if argv is None or name == named else False
            if mod is None:  # its module is not installed: not a choice
                continue
            if mod is False:
                sub.add_parser(name, help=CASE_HELP[name], add_help=False)
            else:
                _add_case(sub, name, mod, is_sizing=is_sizing)
        if is_sizing:  # OpenAeroStruct's uCRM fuel burn: a problem of its own, not a WingSizing case
            add_aerostruct_parser(sub)
        p.set_defaults(func=lambda a, p=p: (p.print_help(), 0)[1])


def add_aerostruct_parser(subparsers):
    """Add ``size aerostruct-crm`` (run: :func:`wingmdao.cli._aerostruct.run`).

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The cases of ``wingmdao size``.
    """
    p = subparsers.add_parser(
        AEROSTRUCT_NAME, help=AEROSTRUCT_HELP,
        description=AEROSTRUCT_HELP + ". Minimises the Breguet fuel burn over twist, spar and skin thickness "
        "(SLSQP) with CL = 0.5 at cruise, L = W and the stress KS <= 0 at the maneuver. Each "
        "optimisation records to SQLite in --out (aerostruct_crm.sql, aerostruct_crm_oas_beam.sql); "
        "read them back with 'wingmdao report'. See docs/embedding.md.")
    p.add_argument("--out", metavar="DIR", default="results", help="folder for the recordings")

    add_json_argument(p, overwrite=False)
    add_overwrite_argument(p, help="replace an earlier run's outputs (recordings, JSON) instead of refusing")
    p.add_argument("--analysis-only", action="store_true",
                   help="one coupled analysis of the initial design per beam, no optimisation")
    p.add_argument("--maxiter", type=int, default=40, metavar="N", help="maximum SLSQP iterations")
    p.add_argument("--tol", type=float, default=1e-6, metavar="TOL", help="SLSQP tolerance")
    p.add_argument("--num-y", type=int, default=15, metavar="N",
                   help="spanwise mesh points of the full wing (OpenAeroStruct's num_y: odd, >= 9); the beam has "
                        "(N + 1) / 2 nodes")
    p.add_argument("--no-oas-beam", action="store_true",
                   help="skip the same problem with OpenAeroStruct's own spatial beam (no 'oas_beam' in the JSON)")
    p.add_argument("--quiet", action="store_true", help="no per-evaluation progress lines")
    p.set_defaults(func="wingmdao.cli._aerostruct:run")
