"""``wingmdao size aerostruct-crm``: OpenAeroStruct's uCRM multipoint fuel-burn problem with the
wingmdao beam, beside the same problem with OpenAeroStruct's own beam (:mod:`wingmdao.oas.crm`,
the same problem as ``python cases/run_aerostruct_crm.py``)."""

from __future__ import annotations

import os
import sys

import wingmdao.cli._openmdao  # noqa: F401  (first: OpenMDAO without the matplotlib of its report plugins)
from wingmdao.cli._io import EXIT_FAILED, EXIT_INTERRUPTED, check_output_dir, check_output_file, refuse_existing, say, write_json
from wingmdao.cli.parsers.size import AEROSTRUCT_NAME as NAME
import openmdao.api as om
from wingmdao.oas.crm import build_crm_problem, check_num_y, crm_summary, setup_crm_problem, solve_crm
from wingmdao.report import best_design, read_history

#: recording file stem of each beam's run in --out
STEMS = {"wingmdao": "aerostruct_crm", "oas": "aerostruct_crm_oas_beam"}


def _check_args(args):
    if args.maxiter < 1:
        raise ValueError(f"--maxiter = {args.maxiter}; allowed range >= 1 iteration "
                         "(use --analysis-only to analyse without optimizing)")
    if not args.tol > 0:
        raise ValueError(f"--tol = {args.tol}; allowed range > 0")
    check_num_y(args.num_y)


def openaerostruct_missing() -> str | None:
    """The one-line message when OpenAeroStruct does not import, else None."""
    try:
        import openaerostruct  # noqa: F401
    except ImportError as exc:
        return (f"size {NAME} needs OpenAeroStruct ({exc}); install it with: pip install 'wingmdao[mdo]' "
                "(or pip install openaerostruct)")
    return None


def run(args) -> int:
    _check_args(args)
    missing = openaerostruct_missing()
    if missing:
        print(f"wingmdao size: error: {missing}", file=sys.stderr)
        return EXIT_FAILED
    beams = ("wingmdao",) if args.no_oas_beam else ("wingmdao", "oas")
    check_output_dir(args.out, "--out")
    recordings = {b: None if args.analysis_only else os.path.join(args.out, STEMS[b] + ".sql") for b in beams}
    check_output_file(args.json, "--json", overwrite=args.overwrite,
                      others={f"recording ({b} beam)": r for b, r in recordings.items()})
    refuse_existing(list(recordings.values()), overwrite=args.overwrite, what="recordings")

    result = {"case": NAME, "num_y": args.num_y, "analysis_only": bool(args.analysis_only)}
    status, last = None, None
    for beam in beams:
        say(f"wingmdao size {NAME}: {'analysis' if args.analysis_only else 'SLSQP'} with the "
            f"{'wingmdao' if beam == 'wingmdao' else 'OpenAeroStruct'} beam, num_y {args.num_y}")
        last, status = _run_beam(beam, args, recordings[beam])
        if beam == "wingmdao":
            result.update(last)
        else:
            result["oas_beam"] = last
        if status:
            break
    result["success"] = bool(result["success"] and result.get("oas_beam", {}).get("success", True))
    if status:
        result.update(success=False, interrupted=status == "interrupted")
    if args.json:
        write_json(result, args.json)
    _print_summary(result)
    if status == "interrupted":
        say(f"wingmdao size {NAME}: interrupted; design so far in {args.json or 'the JSON (pass --json)'}")
        return EXIT_INTERRUPTED
    if status == "failed":
        print(f"wingmdao size: error: the analysis failed ({last['beam']} beam): {last['message']}"
              + (f" (partial result in {args.json})" if args.json else ""), file=sys.stderr)
        return EXIT_FAILED
    return 0 if result["success"] else 1


def _run_beam(beam, args, recording):
    """(result dict, None | "interrupted" | "failed") of one beam's run."""
    prob, stress = build_crm_problem(beam, args.num_y)
    counter = setup_crm_problem(prob)
    status = None
    try:
        info = solve_crm(prob, counter, analysis_only=args.analysis_only, maxiter=args.maxiter, tol=args.tol,
                         recording=recording, progress=not args.quiet)
    except KeyboardInterrupt:
        status, info = "interrupted", {"success": False, "message": "interrupted (Ctrl-C)"}
    except om.AnalysisError as exc:
        status, info = "failed", {"success": False, "message": " ".join(str(exc).split())}
    prob.cleanup()   # closes (and commits) the recording
    try:
        res = crm_summary(prob, stress, beam, counter)
    except Exception as exc:  # interrupted before the first evaluation finished
        res = {"beam": beam, "summary_error": f"no evaluated design ({exc})"}
    res.update(info)
    if recording:
        res["recording"] = recording
        if status:
            res["best_design"] = _best_recorded(recording)
    return res, status


def _best_recorded(recording):
    """Best feasible recorded iteration (:func:`wingmdao.report.best_design`), or None."""
    try:
        return best_design(read_history(recording), tol=1e-4)   # CL and L = W equalities to 1e-4
    except ValueError:   # no recording yet, or no iteration recorded
        return None


def _print_summary(res):
    for label, r in (("wingmdao beam", res), ("OpenAeroStruct beam", res.get("oas_beam"))):
        if not r or "fuelburn_kg" not in r:
            continue
        ks = ", ".join(f"{k} {v:+.3e}" for k, v in r["ks"].items())
        print(f"  {label}: fuel burn {r['fuelburn_kg']:.1f} kg, wing mass {r['wing_mass_kg']:.1f} kg, "
              f"tip deflection {r['tip_deflection_m']:.3f} m, L=W {r['L_equals_W']:+.2e}, KS {ks}")
        print(f"    success {r['success']} ({r['message']}), {r.get('iterations', 0)} iterations, "
              f"{r.get('wall_time_s', float('nan')):.1f} s")
        if r.get("recording"):
            print(f"    recording: {r['recording']}  (wingmdao report {r['recording']})")
