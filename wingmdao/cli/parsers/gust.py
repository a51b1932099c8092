"""Parser of ``wingmdao gust`` (run: :mod:`wingmdao.cli.gust`)."""

from __future__ import annotations

import argparse

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import (add_aero_and_plunge_arguments, add_aero_theory_argument, add_deprecated_alias,
                               add_free_pitch_arguments, add_output_arguments)


CASES = ("pegasus", "crm")


#: --model: the lone wing or the stick model of the whole aircraft (pegasus)
MODELS = ("wing", "stick")


#: --u-ref-fps upper bound (ft/s EAS)
MAX_U_REF_FPS = 200.0


#: default number of jig beam modes of --aero-theory dlm
DLM_MODES = 6


def register(subparsers, argv=None):
    """Add ``wingmdao gust`` to the ``wingmdao`` sub-parsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line (unused: the command's options do not depend on it).
    """
    p = subparsers.add_parser(
        "gust", help=COMMANDS["gust"].help,
        description="1-cos gust response of a case's wing: on the aeroelastic beam (--aero coupled: unsteady strip "
        "theory on the deforming wing, free plunge or clamped, from the trimmed 1 g level flight) or with the "
        "sizing's precomputed strip-theory loads on the clamped beam (--aero strip). SI output.")
    p.add_argument("case", choices=CASES, metavar="CASE", help="case: " + ", ".join(CASES))
    add_aero_and_plunge_arguments(p, "the sizing's precomputed rigid-wing strip-theory gust loads on the structural "
                                     "beam, clamped root; as 'wingmdao size CASE --aero strip'")
    p.add_argument("--pitch", dest="pitch", nargs="?", const="free", choices=("free", "fixed"), default="fixed",
                   help="free (aircraft also free in pitch with a horizontal tail; needs --aero coupled, free plunge and "
                        "--pitch-inertia, --cg-x, --tail-arm, --tail-area, --tail-lift-slope; '--pitch' alone = free) "
                        "or fixed (default)")
    add_free_pitch_arguments(p, "--pitch free")
    p.add_argument("--gust-gradient-ft", dest="gradient_ft", type=float, default=None, metavar="FT",
                   help="gust gradient H (ft, 30-350; default: the case's, as on 'size')")
    add_deprecated_alias(p, "--gradient-ft", "--gust-gradient-ft", dest="gradient_ft", type=float, metavar="FT")
    p.add_argument("--stiffness-scale", type=float, default=1.0, metavar="S",
                   help="multiply all section stiffnesses by S (> 0; large S approaches a rigid wing; --model stick: "
                        "every beam's, S in [0.1, 100])")
    p.add_argument("--design", metavar="RESULT.json", default=None,
                   help="thicknesses from a sizing result (its 'thickness' per station); default: the initial design")
    p.add_argument("--altitude-ft", type=float, default=None, metavar="FT",
                   help="gust altitude (ft, 0-60000; default: the case's)")
    p.add_argument("--mach", type=float, default=None, metavar="MACH", help="gust flight Mach number (0-1; default: the case's)")
    p.add_argument("--u-ref-fps", type=float, default=None, metavar="FPS",
                   help=f"reference gust velocity (ft/s EAS, (0, {MAX_U_REF_FPS:g}]; default: the case's)")
    p.add_argument("--t-final", type=float, default=None, metavar="S", help="gust simulation time (s; default: the case's)")
    p.add_argument("--dt", type=float, default=None, metavar="S", help="time step (s; default: the case's, as on 'size')")
    p.add_argument("--gust-start", type=float, default=None, metavar="S",
                   help="time the gust front reaches the wing (s; default: the case's, as on 'size')")
    add_aero_theory_argument(p, dlm=", or dlm (doublet lattice of the planform in the jig beam's modal basis with "
                                    "Roger's lag states; free plunge and --pitch free add the rigid-body modes; loads "
                                    "are gust increments on the 1 g state, by force summation)")
    p.add_argument("--modes", type=int, default=None, metavar="N",
                   help=f"number of jig beam modes of --aero-theory dlm (2-20; default: {DLM_MODES})")
    p.add_argument("--model", choices=MODELS, default="wing",
                   help="wing (the case's wing on the plunge/pitch states, default) or stick (pegasus only: the free "
                        "half aircraft's stick model, wing, fuselage, fin and horizontal tail with strip aerodynamics "
                        "on wing and tail, trimmed in angle of attack and tail incidence; docs/stick-model.md; the JSON "
                        "adds the monitoring stations' loads) (default: %(default)s)")
    p.add_argument("--gust-set", metavar="FILE", default=None,
                   help="--model stick: a 25.341(a) gust set (.json or .yaml: flight points x gradients x signs, as "
                        "'wingmdao size pegasus --gust-set'; docs/gust-envelope.md): every gust marched, the "
                        "monitoring stations' envelopes and potato plots over the set")
    p.add_argument("--alleviation", metavar="FILE.yaml", default=None,
                   help="control surfaces, actuators and a feedback law in the march (docs/controls.md; needs --aero "
                        "coupled); the result adds the surface histories and the peak root bending without and with it")
    p.add_argument("--lifting-line", action="store_true", help=argparse.SUPPRESS)  # deprecated: --aero-theory lifting-line

    add_output_arguments(p, what="the PNG plot (CASE_gust.png)")
    p.set_defaults(func="wingmdao.cli.gust:run")
