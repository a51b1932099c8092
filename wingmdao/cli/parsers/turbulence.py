"""Parser of ``wingmdao turbulence`` (run: :mod:`wingmdao.cli.turbulence`)."""

from __future__ import annotations

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import add_aero_and_plunge_arguments, add_aero_theory_argument, add_output_arguments


CASES = ("pegasus",)


def register(subparsers, argv=None):
    """Add ``wingmdao turbulence`` to the ``wingmdao`` sub-parsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line (unused: the command's options do not depend on it).
    """
    p = subparsers.add_parser(
        "turbulence", help=COMMANDS["turbulence"].help,
        description="Continuous-turbulence loads of a case's wing: frequency response of the wing linearised about "
        "its 1 g level flight to a unit vertical gust (penetration phase per station), von Karman spectrum "
        "(L = 2,500 ft), A-bar, design loads P_1g +/- U_sigma A-bar and (bending, torsion) correlations. SI output.")
    p.add_argument("case", choices=CASES, metavar="CASE", help="case: " + ", ".join(CASES))
    add_aero_and_plunge_arguments(p, "quasi-steady strip-theory gust lift on the clamped structural beam")
    p.add_argument("--design", metavar="RESULT.json", default=None,
                   help="thicknesses from a sizing result (its 'thickness' per station); default: the initial design")
    p.add_argument("--altitude-ft", type=float, metavar="FT", default=None,
                   help="altitude (ft, 0-60000; default: the case's cruise altitude, 20000 ft for pegasus)")
    p.add_argument("--mach", type=float, metavar="MACH", default=None,
                   help="Mach number, in (0, M_D] (default: the case's M_C; U_sigma is halved at M_D, linear between)")
    p.add_argument("--damping-ratio", type=float, metavar="ZETA", default=0.0,
                   help="structural damping ratio of the beam (Kelvin-Voigt strain-rate damping) at "
                        "--damping-frequency-hz; 0 = undamped; Nastran practice: 0.02")
    p.add_argument("--damping-frequency-hz", type=float, metavar="HZ", default=None,
                   help="frequency at which --damping-ratio holds (Hz); unset: the first mode of the initial design")
    p.add_argument("--f-max-hz", type=float, default=40.0, metavar="HZ",
                   help="highest frequency of the grid (Hz); the spectrum beyond it enters as an estimated tail")
    p.add_argument("--grid-points", type=int, default=161, metavar="N",
                   help="points of the geometric part of the grid (modes add 16 each)")
    add_aero_theory_argument(p, dlm=", or dlm (doublet lattice of the planform in the jig beam's modal basis with "
                                    "Roger's lag states, clamped or free in plunge (the plunge mode in the basis); "
                                    "needs --aero coupled; A-bar only, no 1 g state)")
    p.add_argument("--alleviation", metavar="FILE.yaml", default=None,
                   help="control surfaces, actuators and a feedback law in the linearised model (docs/controls.md; "
                        "needs --aero coupled and --aero-theory strip|lifting-line|vlm); the JSON adds the A-bar "
                        "without the law and the surfaces' A-bar against their limits")
    p.add_argument("--modes", type=int, default=None, metavar="N",
                   help="number of jig beam modes of --aero-theory dlm (2-20; default: 6)")
    add_output_arguments(p, what="the PNG plots (CASE_turbulence_*.png)")
    p.set_defaults(func="wingmdao.cli.turbulence:run")
