"""Parser of ``wingmdao maneuver`` (run: :mod:`wingmdao.cli.maneuver`)."""

from __future__ import annotations

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import METAVARS, add_aero_theory_argument, add_free_pitch_arguments, add_output_arguments


CASES = ("pegasus",)


#: the elevator's chord ratio assumed by default (an assumption: typical of transport elevators)
ELEVATOR_CHORD_RATIO = 0.3


#: the elevator actuator's time constant assumed by default (s)
ELEVATOR_TIME_CONSTANT = 0.05


#: the march of each rolling condition (s) by default
ROLL_T_FINAL = 2.0


def register(subparsers, argv=None):
    """Add ``wingmdao maneuver`` to the ``wingmdao`` sub-parsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line (unused: the command's options do not depend on it).
    """
    p = subparsers.add_parser(
        "maneuver", help=COMMANDS["maneuver"].help,
        description="Dynamic maneuver of a case's airplane on the coupled aeroelastic beam, free in plunge and pitch "
        "with a horizontal tail and an elevator, from trimmed level flight. --checked-pitch: 14 CFR 25.331(c)(2), "
        "delta(t) = delta_1 sin(omega t) for 0 <= t <= 3 pi / (2 omega), delta_1 scaled so that the peak load factor "
        "reaches the 25.337 limit (nose up) or 0 g (--nose-down). --rolling: 14 CFR 25.349(a), the antisymmetric half "
        "wing on a fuselage free to roll, a sudden aileron deflection at V_A, V_C and V_D. SI output.")
    p.add_argument("case", choices=CASES, metavar="CASE", help="case: " + ", ".join(CASES))
    p.add_argument("--checked-pitch", action="store_true", help="the 14 CFR 25.331(c)(2) checked pitch maneuver")
    p.add_argument("--rolling", action="store_true",
                   help="the 14 CFR 25.349(a) rolling conditions (antisymmetric half wing free to roll; needs "
                        "--alleviation with the ailerons, --roll-inertia and --maneuvering-speed-eas)")
    p.add_argument("--roll-inertia", type=float, default=None, metavar="KG_M2",
                   help="--rolling: roll inertia about the body x axis of the aircraft outside both wing halves "
                        "(fuselage, tail, payload), I_xx,body (kg m^2, > 0; required: the case has none)")
    p.add_argument("--alleviation", metavar="FILE.yaml", default=None,
                   help="--rolling: the ailerons (the surfaces of a control-surface file, docs/controls.md; no law): "
                        "each deflected to its max_deflection_deg (the stop) at V_A, trailing edge down on the right "
                        "wing, mirrored on the left")
    add_aero_theory_argument(p)
    p.add_argument("--t-final", type=float, default=None, metavar=METAVARS["--t-final"],
                   help=f"--rolling: duration of each condition's march (s, > 0; default {ROLL_T_FINAL:g})")
    p.add_argument("--nose-down", action="store_true",
                   help="the nose-down checked maneuver (target 0 g) instead of the nose-up one (target: the 25.337 "
                        "positive limit load factor)")
    p.add_argument("--maneuvering-speed-eas", type=float, default=None, metavar="M_S",
                   help="design maneuvering speed V_A (m/s EAS, > 0, 14 CFR 25.335(c); required: the case has none); "
                        "omega >= pi V / (2 V_A)")
    p.add_argument("--load-factor", type=float, default=None, metavar=METAVARS["--load-factor"],
                   help="positive limit load factor, > 1 (default unset: 14 CFR 25.337(b) at the case's weight)")
    p.add_argument("--max-elevator-deg", type=float, default=None, metavar="DEG",
                   help="largest available elevator command (deg, > 0: control stops or pilot effort, 25.397(b)); "
                        "when the target needs more, the command of 25.331(c)(2)(iii) holds it for up to 5 s "
                        "(default unset: unlimited)")
    p.add_argument("--elevator-chord-ratio", type=float, default=ELEVATOR_CHORD_RATIO, metavar="E",
                   help="elevator chord / tail chord, (0, 1): the elevator effectiveness from thin-airfoil theory")
    p.add_argument("--elevator-time-constant", type=float, default=ELEVATOR_TIME_CONSTANT, metavar="S",
                   help="time constant of the first-order elevator actuator (s, > 0)")
    p.add_argument("--altitude-ft", type=float, default=None, metavar=METAVARS["--altitude-ft"],
                   help="flight altitude (ft, 0-60000; default: the case's gust altitude)")
    p.add_argument("--mach", type=float, default=None, metavar=METAVARS["--mach"],
                   help="entry Mach number V (0-1; default: the case's gust Mach number)")
    p.add_argument("--steps", type=int, default=200, metavar="N",
                   help="time steps over the maneuver [0, 3 pi / (2 omega)] (--rolling: [0, --t-final]), 20-100000")
    p.add_argument("--design", metavar="RESULT.json", default=None,
                   help="thicknesses from a sizing result (its 'thickness' per station); default: the initial design")
    add_free_pitch_arguments(p, "--checked-pitch")
    add_output_arguments(p, what="the PNG plot (CASE_checked_pitch.png; with --nose-down CASE_checked_pitch_nose_down.png; "
                         "with --rolling CASE_rolling.png)")
    p.set_defaults(func="wingmdao.cli.maneuver:run")
