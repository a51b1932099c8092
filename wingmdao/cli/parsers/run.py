"""Parser of ``wingmdao run`` (run: :mod:`wingmdao.cli.run`)."""

from __future__ import annotations

from wingmdao.cli import COMMANDS
from wingmdao.cli._args import add_gravity_argument, add_json_argument
from wingmdao.names import WING_BOX_GEOMETRIES as GEOMETRIES, WING_BOX_T_SKIN as T_SKIN, WING_BOX_T_SPAR as T_SPAR


def add_wing_box_arguments(parser, *, walls=True, loads=True):
    """The App. D.1 box flags shared by ``run``, ``verify`` and ``export wing-box``: ``--geometry``,
    the streamwise wall thicknesses ``--t-spar``/``--t-skin`` (m), ``--tip-load``/``--tip-moment``."""
    parser.add_argument("--geometry", choices=list(GEOMETRIES), required=True, help="Table D.2 geometry")
    if walls:
        parser.add_argument("--t-spar", type=float, default=T_SPAR, metavar="M", help="spar thickness in the streamwise cut (m)")
        parser.add_argument("--t-skin", type=float, default=T_SKIN, metavar="M", help="skin thickness in the streamwise cut (m)")
    if loads:
        parser.add_argument("--tip-load", type=float, nargs=3, default=(0.0, 0.0, 0.0), metavar=("FX", "FY", "FZ"),
                            help="tip force at the CS4 centre, body axes (N)")
        parser.add_argument("--tip-moment", type=float, nargs=3, default=(0.0, 0.0, 0.0), metavar=("MX", "MY", "MZ"),
                            help="tip moment, body axes (N*m)")


def register(subparsers, argv=None):
    """Add ``wingmdao run`` to the ``wingmdao`` sub-parsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``wingmdao`` sub-parsers.
    argv : sequence of str, optional
        The command line (unused: the command's options do not depend on it).
    """
    p = subparsers.add_parser("run", help=COMMANDS["run"].help,
                              description="Run an analysis case. SI units, body axes x aft, y outboard, z up.")
    cases = p.add_subparsers(dest="case", metavar="CASE", required=True)
    wb = cases.add_parser(
        "wing-box", help="App. D.1 'wing-like' box beam under tip loads / self weight, static or dynamic",
        description="Nonlinear Timoshenko-beam response of the App. D.1 box (root clamped at CS1, aluminium "
        "E = 70 GPa, nu = 0.33, rho = 2700 kg/m^3, sigma_y = 276 MPa) on the OpenMDAO sizing model. Output "
        "JSON: stations (CS1..CS4), displacement (magnitude of the beam-axis displacement at each station, m), "
        "tip_displacement [dx, dy, dz] (m), tip_rotation (rotation vector, rad, body axes), max_von_mises "
        "per station (Pa, max over the 8 mid-corner points and time), ks (KS values per stress family), "
        "mass_kg; with --dynamic also time (s) and tip_displacement_history (n_time x 3, m); with "
        "--check-totals also check_totals_max_rel_error. Dynamic runs: the load is applied suddenly at "
        "t > 0 to the beam at rest in its unloaded shape; values without _history are at the last instant.")
    add_wing_box_arguments(wb)
    add_gravity_argument(wb, help="add self weight under gravity G along -z (m/s^2; default unset: no self weight)")
    wb.add_argument("--dynamic", action="store_true",
                    help="BDF2 time march: tip load applied suddenly at t > 0 to the beam at rest")
    wb.add_argument("--t-final", type=float, default=1.0, metavar="S", help="dynamic: simulated time (s)")
    wb.add_argument("--dt", type=float, default=0.005, metavar="S", help="dynamic: time step (s)")
    wb.add_argument("--check-totals", action="store_true",
                    help="compare adjoint totals d(KS)/d(wall thicknesses) with central finite differences")
    wb.add_argument("--load-steps", type=int, default=1, metavar="N", help="load steps of the static Newton solve")
    wb.add_argument("--elements", type=int, nargs=3, default=(6, 8, 6), metavar=("N1", "N2", "N3"),
                    help="beam elements per segment CS1-CS2, CS2-CS3, CS3-CS4")
    wb.add_argument("--model", choices=("beam", "solid"), default="beam",
                    help="beam: the sizing model (default). solid: the independent linear 3-D solid (hex27) "
                    "model of the same box (wingmdao.verification.wingbox_solid; root face clamped, load on a "
                    "tip rib), with the same JSON keys: cut-average displacements and rotations of the "
                    "streamwise cuts CS1..CS4, and max_von_mises / mean_von_mises over each cut; static, "
                    "tip loads only")
    wb.add_argument("--mesh-size", type=float, default=0.15, metavar="M",
                    help="solid: cross-section element size (m, default 0.15: CS2/CS3 within 0.06 %% (force) and "
                    "0.2 %% (torque) of the finest mesh, docs/verification-solid3d.md)")
    wb.add_argument("--span-size", type=float, default=0.5, metavar="M", help="solid: element length along the span (m)")
    wb.add_argument("--tip-introduction", choices=("diaphragm", "traction", "rigid"), default="diaphragm",
                    help="solid: how the tip load enters: a rigid tip rib free to warp (default), the "
                    "rigid-body-consistent traction, or a fully rigid tip face")
    add_json_argument(wb)
    wb.set_defaults(func="wingmdao.cli.run:run_wing_box")
