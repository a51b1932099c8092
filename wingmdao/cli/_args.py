"""The command-line flags shared by several ``wingmdao`` commands, spelled once.

One spelling per concept (docs/cli.md, "One spelling per concept"):

- ``--json PATH``: the result as JSON; default ``-`` (standard output; human text then goes to
  standard error) on every command that has a result;
- ``--out DIR``: the folder of a command's files (recordings, plots, N2); default ``results``;
- ``--overwrite``: replace an earlier run's outputs instead of refusing;
- ``--no-plots``: do not write PNG plots;
- ``--families LIST``: the constrained stress families of a sizing case;
- ``--t-skin`` / ``--t-spar``: skin and spar-web thicknesses (m) of a box.

An older spelling stays accepted as a deprecated alias (:func:`add_deprecated_alias`) that prints
one warning line and stores into the same destination.
"""

from __future__ import annotations

import argparse

from wingmdao.cli._io import warn
from wingmdao.names import AERO_THEORY_CHOICES, DEFAULT_COUPLED_THEORY

JSON_HELP = ("write the result as JSON to PATH; - = standard output (progress and human text then go to "
             "standard error)")


def add_json_argument(parser, *, overwrite: bool = True) -> None:
    """``--json PATH`` with the one default of every command: ``-`` (standard output), and
    ``--overwrite`` (``overwrite``; commands with ``--out`` add it with their folder): an existing
    PATH is refused before the run unless it is given (:func:`wingmdao.cli.main`)."""
    parser.add_argument("--json", metavar="PATH", default="-", help=JSON_HELP)
    if overwrite:
        add_overwrite_argument(parser)


def add_overwrite_argument(parser, help="replace an earlier run's outputs instead of refusing") -> None:
    parser.add_argument("--overwrite", action="store_true", help=help)


def add_output_arguments(parser, *, what: str, plots: bool = True, json: bool = True) -> None:
    """``--out DIR`` (``what``: the files it holds), ``--overwrite``, ``--no-plots`` and ``--json``."""
    parser.add_argument("--out", metavar="DIR", default="results", help=f"folder for {what}")
    add_overwrite_argument(parser)
    if plots:
        parser.add_argument("--no-plots", action="store_true", help="do not write PNG plots")
    if json:
        add_json_argument(parser, overwrite=False)


class _DeprecatedAlias(argparse.Action):
    """Stores like the new flag and warns once per use that the old spelling is deprecated.

    ``meaning`` replaces "same meaning" in the warning when the new flag is used differently (e.g.
    ``--plot PNG`` against ``--out DIR``); ``convert`` maps the old value onto the new flag's
    (e.g. ``maneuver_pos`` to ``maneuver-pos``)."""

    def __init__(self, option_strings, dest, new=None, meaning="same meaning", convert=None, **kwargs):
        self.new = new
        self.meaning = meaning
        self.convert = convert
        super().__init__(option_strings, dest, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None):
        warn(f"{option_string} is deprecated; use {self.new} ({self.meaning})")
        if self.nargs == 0:
            values = self.const
        elif self.convert is not None:
            values = self.convert(values)
        setattr(namespace, self.dest, values)


def add_deprecated_alias(parser, old: str, new: str, *, dest: str, meaning: str = "same meaning",
                         convert=None, **kwargs) -> None:
    """Accept ``old`` as a hidden, deprecated spelling of ``new`` storing into ``dest``; using it
    prints one line ``wingmdao: warning: OLD is deprecated; use NEW (MEANING)``."""
    parser.add_argument(old, dest=dest, action=_DeprecatedAlias, new=new, meaning=meaning, convert=convert,
                        default=argparse.SUPPRESS, help=argparse.SUPPRESS, **kwargs)


#: the metavar (the unit or the kind of value) of every flag that more than one command or case has
METAVARS = {"--t-final": "S", "--dt": "S", "--gust-start": "S", "--ramp-time": "S", "--altitude-ft": "FT",
            "--gust-gradient-ft": "FT", "--u-ref-fps": "FPS", "--mach": "MACH", "--length": "M",
            "--load-factor": "N", "--negative-load-factor": "N", "--damping-ratio": "ZETA",
            "--damping-frequency-hz": "HZ", "--rho-ks": "RHO", "--maxiter": "N", "--num-nodes": "N", "--modes": "N"}

#: standard gravity (m/s^2) of ``--gravity`` given alone
STANDARD_GRAVITY = 9.81


def add_gravity_argument(parser, *, default=None, help: str) -> None:
    """``--gravity [G]``: gravity along -z in m/s^2, alone ``STANDARD_GRAVITY``; the one spelling on
    ``run wing-box`` (self weight, default off) and ``flutter --deformed`` (default: the case's)."""
    parser.add_argument("--gravity", type=float, nargs="?", const=STANDARD_GRAVITY, default=default,
                        metavar="M_S2", help=f"{help}; '--gravity' alone = {STANDARD_GRAVITY:g} m/s^2")


def add_aero_and_plunge_arguments(parser, strip_help: str) -> None:
    """``--aero strip|coupled`` (``strip_help``: what the strip choice runs) and the exclusive pair
    ``--plunge [free|clamped]`` / ``--clamped``, one spelling on ``gust`` and ``turbulence``."""
    parser.add_argument("--aero", choices=("strip", "coupled"), default="coupled",
                        help="aerodynamics: coupled (unsteady strip theory on the deforming beam, default) or strip "
                             f"({strip_help})")
    g = parser.add_mutually_exclusive_group()
    g.add_argument("--plunge", dest="plunge", nargs="?", const="free", choices=("free", "clamped"), default=None,
                   help="free (aircraft free in plunge; default with --aero coupled; '--plunge' alone = free) or "
                        "clamped (root clamped; the only choice with --aero strip)")
    g.add_argument("--clamped", dest="plunge", action="store_const", const="clamped",
                   help="root clamped (wind-tunnel wing): the same as --plunge clamped")


def add_aero_theory_argument(parser, default: str | None = None, dlm: bool | str = False) -> None:
    """``--aero-theory strip|lifting-line|vlm``: the quasi-steady lift of the coupled aeroelastic
    model (:data:`wingmdao.aero.coupled.AERO_THEORY_CHOICES`, docs/aerodynamics-3d.md); with
    ``dlm`` also ``dlm``, the doublet lattice in the jig's modal basis (``wingmdao flutter``; a
    string: its help text on another command)."""
    dlm_help = (dlm if isinstance(dlm, str) else
                ", or dlm (doublet lattice of the planform in the jig beam's modal basis: p-k on its generalized "
                "forces and the state-space eigenvalues with Roger's lag states, beside strip theory's V-g)"
                if dlm else "")
    parser.add_argument("--aero-theory", choices=AERO_THEORY_CHOICES + (("dlm",) if dlm else ()), default=default,
                        help="quasi-steady lift of the coupled aerodynamics: strip (each station's 2-D slope "
                             "2 pi / beta), lifting-line (section slopes of Prandtl's lifting line of the planform) "
                             "or vlm (vortex lattice of the planform: every station's lift from every station's "
                             f"angle); the Wagner/Kuessner lags stay per station{dlm_help} (default: "
                             + (f"{DEFAULT_COUPLED_THEORY} with --aero coupled, strip with --aero strip; the flutter "
                                "command and constraint: strip" if default is None else "%(default)s") + ")")


def add_free_pitch_arguments(parser, switch: str) -> None:
    """The aircraft data of free pitch (:mod:`wingmdao.aero.pitch`), one spelling on ``gust --pitch
    free`` and ``maneuver --checked-pitch`` (``switch``: the flag that needs them; ``size pegasus``
    spells its case options alike): ``--pitch-inertia``, ``--cg-x``, ``--cg-z``, ``--tail-arm``, ``--tail-area``,
    ``--tail-lift-slope``, ``--downwash-gradient``, ``--tail-lag``."""
    t = parser.add_argument_group(f"free pitch ({switch}; SI, body axes: x aft, z up from the symmetry-plane origin)")
    t.add_argument("--pitch-inertia", type=float, default=None, metavar="KG_M2",
                   help="aircraft pitch inertia I_yy about its CG (kg m^2; required)")
    t.add_argument("--cg-x", type=float, default=None, metavar="M", help="aircraft CG x (m aft of the body-axes origin; required)")
    t.add_argument("--cg-z", type=float, default=0.0, metavar="M", help="aircraft CG z (m above the origin; default 0)")
    t.add_argument("--tail-arm", type=float, default=None, metavar="M",
                   help="CG to horizontal-tail aerodynamic centre (m, > 0; required)")
    t.add_argument("--tail-area", type=float, default=None, metavar="M2", help="horizontal tail area (m^2, > 0; required)")
    t.add_argument("--tail-lift-slope", type=float, default=None, metavar="PER_RAD",
                   help="horizontal tail lift slope a_t (1/rad, compressibility included; required)")
    t.add_argument("--downwash-gradient", type=float, default=None, metavar="D",
                   help="deps/dalpha at the tail, [0, 1) (default: 2 a_w / (pi AR), a_w the strips' wing lift slope)")
    t.add_argument("--tail-lag", action="store_true",
                   help="downwash lag: first-order lag of time constant x_t / V on the wing angle seen by the tail")
