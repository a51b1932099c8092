"""Parser of ``wingmdao verify`` (run: :mod:`wingmdao.cli.verify`)."""

from __future__ import annotations

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import add_deprecated_alias, add_json_argument, add_overwrite_argument
from wingmdao.cli.parsers.panel import add_panel_arguments
from wingmdao.cli.parsers.run import add_wing_box_arguments


def register(subparsers, argv=None):
    """Add ``wingmdao verify`` to the ``wingmdao`` sub-parsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line (unused: the command's options do not depend on it).
    """
    p = subparsers.add_parser("verify", help=COMMANDS["verify"].help,
                              description="Beam vs CalculiX (ccx) shell or solid model of a shipped case. SI units, "
                              "body axes.")
    cases = p.add_subparsers(dest="case", metavar="CASE", required=True)
    wb = cases.add_parser("wing-box", help="App. D.1 box: beam vs CalculiX shell/solid under tip loads, modes")
    add_wing_box_arguments(wb)
    wb.add_argument("--loads", choices=LOAD_NAMES, default="tip",
                    help="load case at the CS4 centre: tip (--tip-load/--tip-moment, default); d1-fz, d1-fx, "
                    "d1-my (App. D.1 comparison: 1e5 N up, 1e5 N aft, 1e5 N m about y); study1 (Fz = 2e6 N), "
                    "study2 (Fx = 1e5 N, Fz = 2e6 N, My = 1e6 N m): the Sec. 4.7.2 sizing tip loads")
    add_fe_arguments(wb, rib_thickness=0.1, no_ribs_help="no ribs (only the CS4 load-introduction rib; default)",
                     design_help="wall thicknesses (beam-normal) from a 'wingmdao size wing-box --elements 1 1 1' "
                     "result (4 stations CS1..CS4), for the FE model and the beam (default: --t-spar/--t-skin)")
    wb.set_defaults(func="wingmdao.cli.verify:run_verify")
    register_pegasus(cases).set_defaults(func="wingmdao.cli.verify:run_verify")
    register_panel(cases)


LOAD_NAMES = ("tip", "d1-fz", "d1-fx", "d1-my", "study1", "study2")


def add_fe_arguments(p, *, rib_thickness, no_ribs_help, design_help, ribs_help="ribs every SPACING m of span",
                     rib_thickness_help="rib thickness (m)"):
    """The FE-model flags shared by the ``verify`` cases."""
    p.add_argument("--fidelity", choices=("shell", "solid"), default="shell",
                   help="FE model: shell (S8R on the wall mid-surfaces) or solid (C3D20R walls, "
                   "--through-elements through each wall thickness)")
    p.add_argument("--through-elements", type=int, default=2, metavar="N",
                   help="solid: elements through each wall thickness")
    p.add_argument("--nlgeom", action="store_true",
                   help="geometrically nonlinear FE solve (ccx NLGEOM, 10 increments); the beam is always nonlinear")
    p.add_argument("--load-steps", type=int, default=1, metavar="N",
                   help="load steps of the beam's static Newton solve")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--ribs", type=float, default=None, metavar="SPACING", help=ribs_help)
    g.add_argument("--no-ribs", action="store_true", help=no_ribs_help)
    p.add_argument("--rib-thickness", type=float, default=rib_thickness, metavar="M", help=rib_thickness_help)
    p.add_argument("--design", default=None, metavar="RESULT.json", help=design_help)
    p.add_argument("--modes", type=int, default=0, metavar="N", help="also compare the first N frequencies")
    p.add_argument("--chord-elements", type=int, default=8, metavar="N", help="elements across the skins")
    p.add_argument("--height-elements", type=int, default=2, metavar="N", help="elements across the spars")
    p.add_argument("--span-size", type=float, default=0.5, metavar="M",
                   help="element length along the span (m)")
    p.add_argument("--out", default=None, metavar="DIR",
                   help="folder for the beam-vs-FE displacement/rotation/stress plot (verify_CASE.png; "
                        "verify_pegasus_buckling.png with --buckling); default unset: no plot")
    p.set_defaults(plot=None)
    add_deprecated_alias(p, "--plot", "--out", dest="plot", metavar="PNG",
                         meaning="--out DIR writes DIR/verify_CASE.png")
    add_json_argument(p, overwrite=False)
    add_overwrite_argument(p, help="replace an earlier run's --json and plot files")


def add_buckling_arguments(p):
    """The ``--buckling`` flags of ``wingmdao verify pegasus``.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The ``verify pegasus`` parser.
    """
    g = p.add_argument_group("buckling (--buckling: a stiffened design in CalculiX *BUCKLE)")
    g.add_argument("--buckling", action="store_true",
                   help="linear buckling of a stiffened --design (skins, blade stiffeners, spar webs, ribs as "
                   "shells) under a sizing maneuver, against the sizing model's buckling factor")
    p.set_defaults(loads_case=None)  # --buckling reads --loads maneuver-pos (default) or maneuver-neg
    add_deprecated_alias(p, "--loads-case", "--loads", dest="loads", convert=lambda v: v.replace("_", "-"),
                         metavar="CASE")
    g.add_argument("--buckling-modes", type=int, default=10, metavar="N", help="buckling factors extracted")
    g.add_argument("--bay-elements", type=int, default=2, metavar="N",
                   help="--buckling: S8R elements across each skin bay between stiffeners")
    g.add_argument("--web-elements", type=int, default=1, metavar="N",
                   help="--buckling: S8R elements over the stiffener height")
    g.add_argument("--stiffeners", type=int, default=None, metavar="N",
                   help="--buckling: blades per skin (default round(box width / pitch))")
    g.add_argument("--load-lines", choices=("ribs", "all"), default="ribs",
                   help="--buckling: the line loads lumped at the rib stations and entering through the rib rings "
                   "(default), or at every FE corner line")
    g.add_argument("--keep-deck", default=None, metavar="DIR", help="--buckling: keep buckle.inp and its results")
    g.add_argument("--running-loads", action="store_true",
                   help="--buckling: also solve the deck's linear static state (the buckling step's pre-buckling "
                   "loads) and report the skins' running loads per span row (fe_running_loads) beside the sizing "
                   "model's per station (model_running_loads)")


#: --loads: the load factor of each named case (the sizing maneuvers of ``wingmdao size pegasus``,
#: ``--load-factor`` / ``--negative-load-factor`` defaults); '1g' takes ``--load-factor``.
MANEUVERS = {"maneuver-pos": 2.5, "maneuver-neg": -1.0}


#: --loads gust-peak: the equivalent static loads of the peak instant of the case's 25.341 gust
GUST_PEAK = "gust-peak"


def register_pegasus(cases):
    """Add ``wingmdao verify pegasus``.

    Parameters
    ----------
    cases : argparse._SubParsersAction
        The cases of ``wingmdao verify``.

    Returns
    -------
    argparse.ArgumentParser
        Its parser.
    """
    p = cases.add_parser("pegasus", help="PEGASUS wing at n g: beam vs CalculiX shell/solid, with or without ribs")
    p.add_argument("--load-factor", type=float, default=1.0, metavar="N",
                   help="load factor n of the symmetric maneuver (lift n W, gravity 1 g plus (n-1) g frame "
                   "acceleration on the masses)")
    p.add_argument("--loads", choices=("1g", *MANEUVERS, GUST_PEAK), default="1g",
                   help="1g: the symmetric maneuver at --load-factor; maneuver-pos / maneuver-neg: the 2.5 g and "
                   "-1.0 g sizing maneuvers of 'wingmdao size pegasus'; gust-peak: the equivalent static loads "
                   "(aerodynamic + inertial -m a + weight) of the instant of peak root bending of the case's "
                   "25.341 gust marched on the beam of --design (strip theory, clamped root); with --buckling: "
                   "maneuver-pos (also for 1g) or maneuver-neg")
    add_fe_arguments(p, rib_thickness=0.002, no_ribs_help="no ribs at all (Sec. 4.3.1 Test 2's rib-less model)",
                     ribs_help="ribs every SPACING m instead of at the case's 19 rib stations",
                     rib_thickness_help="rib thickness (m; default 0.002, with --buckling each rib's thickness of "
                     "the design's 'ribs' block, sized for crushing and shear)",
                     design_help="wall thicknesses from a 'wingmdao size pegasus' result (20 stations) "
                     "(unset: 4/4/5/4 mm upper/lower skin, front/rear spar)")

    add_buckling_arguments(p)
    # unset: 0.5 m and 2 (static), 0.1 m and 4 (--buckling); ribs 2 mm (static), the design's sized ribs (--buckling)
    p.set_defaults(through_elements=2, span_size=None, height_elements=None, rib_thickness=None)
    return p


def register_panel(cases):
    """Add ``wingmdao verify panel`` (run: :func:`wingmdao.cli._verify_panel.run_verify_panel`).

    Parameters
    ----------
    cases : argparse._SubParsersAction
        The cases of ``wingmdao verify``.
    """
    p = cases.add_parser("panel", help="stiffened panel: smeared model vs CalculiX linear buckling (S8R)",
                         description="The panel of 'wingmdao panel' (same flags) against a CalculiX *BUCKLE "
                         "analysis of a flat simply supported panel with --stiffeners stiffeners at the model's "
                         "pitch: the model's buckling factor (1 / largest elastic buckling ratio) vs CalculiX's "
                         "first buckling factor. Isotropic metals only. See docs/panels.md.")
    add_panel_arguments(p)
    p.add_argument("--stiffeners", type=int, default=None, metavar="N",
                   help="stiffeners in the FE panel (width N x pitch; default 3 with stiffener flags, 0 without)")
    p.add_argument("--mesh-size", type=float, default=None, metavar="M",
                   help="FE element size (m) (default min(length, pitch) / 8)")
    p.add_argument("--keep-deck", default=None, metavar="DIR",
                   help="write the CalculiX deck (panel.inp) and results there (default: a temporary folder)")
    p.set_defaults(func="wingmdao.cli._verify_panel:run_verify_panel")
