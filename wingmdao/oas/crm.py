"""uCRM multipoint aerostructural fuel-burn problem with the wingmdao beam or OpenAeroStruct's own.

Used by ``wingmdao size aerostruct-crm``, ``cases/run_aerostruct_crm.py``, the tests and
``benchmarks/bench_aerostruct.py``. Based on OpenAeroStruct's wingbox multipoint example
(openaerostruct/docs/wingbox_mpt_opt_example.py, after Chauhan and Martins, "Low-fidelity
aerostructural optimization of aircraft wings with a simplified wingbox model using
OpenAeroStruct", EngOpt 2018): uCRM-based mesh from the OpenAeroStruct package, cruise point
and 2.5 g maneuver (:data:`CRM_POINTS`), Breguet fuel burn objective, twist and spar/skin
thickness design variables, CL = 0.5 at cruise, L = W at the maneuver, stress constraint at the
maneuver. Simplifications (both beams alike, see docs/embedding.md): rectangular wingbox
between 10 % and 60 % chord at t/c 0.12, no structural weight relief, fuel weight or engine
mass in the structural loads.

The stress measure is our KS of the box von Mises constraints (Eq. 4.26, 4.44 of
``wingmdao.DISSERTATION``) with our beam, and OpenAeroStruct's KS failure with its beam; both
are computed at every point, constrained (<= 0) at the maneuver; yield 420 MPa / safety factor
1.5 in both.
"""

from __future__ import annotations

import time

import numpy as np
import openmdao.api as om

from wingmdao.components.beam_loads import BeamInternalLoads
from wingmdao.components.ks import KSAggregate
from wingmdao.components.stress import BoxStress
from wingmdao.groups.wing import stress_points
from wingmdao.materials import Material
from wingmdao.oas.problems import aerostruct_problem, rect_wingbox_surface
from wingmdao.optimize import SolverIterationCounter, ProgressPrinter
from wingmdao.section.box import WALL_NAMES

#: Flight points of the problem (OpenAeroStruct's wingbox multipoint example):
#: name, Mach number, speed of sound (m/s), density (kg/m^3), dynamic viscosity (Pa s), load factor.
CRM_POINTS = (
    ("cruise", 0.85, 295.07, 0.348, 1.43e-5, 1.0),
    ("maneuver", 0.64, 340.294, 1.225, 1.81206e-5, 2.5),
)
#: Aircraft mass without the wing structure and the mission fuel, kg (OpenAeroStruct's example:
#: 128 t plus 15 t reserve fuel).
W0_KG = 128000.0 + 15000.0
#: Initial design (control points root-to-tip order of OpenAeroStruct's B-splines: tip first).
TWIST_CP_DEG = (4.0, 5.0, 8.0, 9.0)
SPAR_CP_M = (0.004, 0.005, 0.008, 0.01)
SKIN_CP_M = (0.005, 0.01, 0.015, 0.025)
#: Design variable bounds and scalers (as OpenAeroStruct's example).
DESIGN_VARS = {"wing.twist_cp": (-15.0, 15.0, 0.1), "wing.spar_thickness_cp": (0.003, 0.1, 1e2),
               "wing.skin_thickness_cp": (0.003, 0.1, 1e2)}
CL_CRUISE = 0.5
#: Coupled adjoint (LinearBlockGS, Aitken) tolerances: relative only. An absolute tolerance
#: (OpenAeroStruct's examples: 1e-10) stops the adjoint of a small-norm function (the stress KS:
#: its seed into the beam states is ~1e-8) before it converges: 4e-4 relative errors in the KS
#: totals on the uCRM, with either beam.
LIN_ATOL, LIN_RTOL, LIN_MAXITER = 1e-30, 1e-12, 200
BEAMS = ("wingmdao", "oas")
#: Stress measure of each beam (JSON ``stress_measure``).
STRESS_MEASURE = {"wingmdao": "wingmdao KS of the box-wall von Mises constraints (<= 0 holds)",
                  "oas": "OpenAeroStruct wingbox KS failure (<= 0 holds)"}


def check_num_y(num_y):
    """ValueError unless ``num_y`` (spanwise mesh points of the full wing) is odd and >= 9.

    Parameters
    ----------
    num_y : int
        Spanwise mesh points of the full wing.
    """
    if not isinstance(num_y, (int, np.integer)) or num_y < 9 or num_y % 2 == 0:
        raise ValueError(f"--num-y = {num_y!r}; allowed: an odd number of spanwise mesh points >= 9 "
                         "(the half-wing then has >= 4 beam elements for the 4 B-spline control points)")


def crm_surface(num_y=15):
    """OpenAeroStruct wingbox surface dict of the uCRM wing, ``num_y`` spanwise points (full wing).

    Parameters
    ----------
    num_y : int, optional
        Spanwise mesh points of the full wing (odd, >= 9).

    Returns
    -------
    dict
        The surface.
    """
    from openaerostruct.meshing.mesh_generator import generate_mesh


    check_num_y(num_y)
    mat = Material("al-crm", E=73.1e9, rho=2.78e3, sigma_y=420e6 / 1.5, G=73.1e9 / 2 / 1.33)
    surf = rect_wingbox_surface(material=mat)
    mesh, _ = generate_mesh({"num_y": num_y, "num_x": 3, "wing_type": "uCRM_based", "symmetry": True,
                             "chord_cos_spacing": 0, "span_cos_spacing": 0, "num_twist_cp": 4})
    surf.update({"mesh": mesh, "twist_cp": np.array(TWIST_CP_DEG), "spar_thickness_cp": np.array(SPAR_CP_M),
                 "skin_thickness_cp": np.array(SKIN_CP_M), "yield": 420e6, "safety_factor": 1.5,
                 "with_viscous": True, "with_wave": True, "wing_weight_ratio": 1.25, "CD0": 0.0078,
                 "wingmdao_box": "oas"})   # the box of each element from OpenAeroStruct's wingbox geometry
    return surf


def add_stress_ks(model, point, num_nodes, material, rho_ks=100.0):
    """Our box stress KS at one point (Eq. 4.44), from the beam states inside the point's coupled
    group; returns the KS output's path (``<point>_ks.ks.ks_vm``).

    Parameters
    ----------
    model : openmdao.api.Group
        The problem's model.
    point : str
        Name of the aerostructural point.
    num_nodes : int
        Beam nodes.
    material : Material
        Wingbox material.
    rho_ks : float, optional
        KS aggregation parameter.

    Returns
    -------
    str
        Path of the KS output.
    """
    n = num_nodes
    g = model.add_subsystem(f"{point}_ks", om.Group())
    g.add_subsystem("internal_loads", BeamInternalLoads(num_times=1, num_nodes=n))
    g.add_subsystem("stress", BoxStress(num_times=1, num_stations=n, material=material, families=("vm",),
                                        output_stresses=False))
    families = {f: (1, n, k) for f, k in stress_points("box", ("vm",)).items()}
    g.add_subsystem("ks", KSAggregate(families=families, rho_ks=rho_ks))
    g.connect("internal_loads.F_csn", "stress.F_csn")
    g.connect("internal_loads.M_csn", "stress.M_csn")
    g.connect("stress.g_vm", "ks.g_vm")
    ss = f"{point}.coupled.wing.struct_states"
    model.connect(f"{ss}.wingmdao_states", f"{point}_ks.internal_loads.states",
                  src_indices=np.arange(18 * n).reshape(1, n, 18), flat_src_indices=True)
    for k in ("width", "height") + WALL_NAMES:
        model.connect(f"{ss}.{k}", f"{point}_ks.stress.{k}")
    return f"{point}_ks.ks.ks_vm"


def build_crm_problem(beam="wingmdao", num_y=15):
    """(problem not yet set up, ``{point name: stress output path}``) with design variables,
    objective and constraints. Points ``AS_point_0`` (cruise) and ``AS_point_1`` (maneuver).

    Parameters
    ----------
    beam : {"wingmdao", "oas"}, optional
        Structural model: the wingmdao beam or OpenAeroStruct's own.
    num_y : int, optional
        Spanwise mesh points of the full wing.

    Returns
    -------
    tuple
        (problem, {point name: stress output path}).
    """
    if beam not in BEAMS:
        raise ValueError(f"beam = {beam!r}; allowed: {', '.join(BEAMS)}")
    surf = crm_surface(num_y)
    ny = surf["mesh"].shape[1]
    names = [p[0] for p in CRM_POINTS]

    def extra(model):
        if beam == "oas":
            return {name: f"AS_point_{i}.wing_perf.failure" for i, name in enumerate(names)}
        return {name: add_stress_ks(model, f"AS_point_{i}", ny, surf["wingmdao_material"])
                for i, name in enumerate(names)}

    mach, a, rho, mu, nz = (np.array([p[k] for p in CRM_POINTS]) for k in range(1, 6))
    v = mach * a
    prob, stress = aerostruct_problem(surf, beam=beam, mach=tuple(mach), v=tuple(v), rho=tuple(rho),
                                      re=tuple(rho * v / mu), load_factor=tuple(nz), alpha_deg=(0.0, 0.0),
                                      W0=W0_KG, extra=extra, setup=False)
    m = prob.model
    for name, (lo, hi, scaler) in DESIGN_VARS.items():
        m.add_design_var(name, lower=lo, upper=hi, scaler=scaler)
    m.add_design_var("alpha", indices=[1], lower=-15.0, upper=15.0)
    m.add_objective("AS_point_0.fuelburn", scaler=1e-5)
    m.add_constraint("AS_point_0.CL", equals=CL_CRUISE)
    m.add_constraint("AS_point_1.L_equals_W", equals=0.0)
    m.add_constraint(stress["maneuver"], upper=0.0)
    return prob, stress


def setup_crm_problem(prob, iprint=-1):
    """``prob.setup(mode="rev")`` and the coupled solvers of both points: OpenAeroStruct's
    NonlinearBlockGS (Aitken) and LinearBlockGS (Aitken, relative 1e-12: LIN_RTOL) for the adjoint. Returns the
    :class:`~wingmdao.optimize.SolverIterationCounter` of the two coupled solves (pass it to
    :func:`solve_crm` and :func:`crm_summary`).

    Parameters
    ----------
    prob : openmdao.api.Problem
        The problem of :func:`build_crm_problem`.
    iprint : int, optional
        Solver print level.

    Returns
    -------
    SolverIterationCounter
        The coupled solves' counter.
    """
    prob.setup(mode="rev")
    solvers = {}
    for i, point in enumerate(CRM_POINTS):
        cp = getattr(prob.model, f"AS_point_{i}").coupled
        cp.linear_solver = om.LinearBlockGS(iprint=-1, maxiter=LIN_MAXITER, use_aitken=True, atol=LIN_ATOL,
                                            rtol=LIN_RTOL)
        cp.nonlinear_solver.options["iprint"] = iprint
        solvers[point[0]] = cp.nonlinear_solver
    return SolverIterationCounter(solvers, unrecorded=1)   # NonlinearBlockGS


def solve_crm(prob, counter=None, *, analysis_only=False, maxiter=40, tol=1e-6, recording=None, progress=False):
    """One coupled analysis, or SLSQP (``maxiter`` iterations, tolerance ``tol``) recorded to SQLite
    ``recording``; returns ``{success, message, iterations (gradient evaluations), evaluations
    (model evaluations), wall_time_s, time_per_analysis_s, time_per_gradient_s}`` (the means of
    OpenMDAO's DriverResult ``model_time`` and ``deriv_time``).

    Parameters
    ----------
    prob : openmdao.api.Problem
        The set-up problem.
    counter : SolverIterationCounter or None, optional
        Counter of :func:`setup_crm_problem`.
    analysis_only : bool, optional
        Run one coupled analysis only.
    maxiter : int, optional
        SLSQP iteration limit.
    tol : float, optional
        SLSQP tolerance.
    recording : str or None, optional
        SQLite file to record the optimization in.
    progress : bool, optional
        Print a line per driver evaluation.

    Returns
    -------
    dict
        The run summary (above).
    """
    t0 = time.perf_counter()
    if analysis_only:
        prob.run_model()
        if counter is not None:
            counter.snapshot()
        return {"success": True, "message": "analysis only", "iterations": 0, "evaluations": 1,
                "wall_time_s": time.perf_counter() - t0}
    prob.driver = om.ScipyOptimizeDriver(optimizer="SLSQP", tol=tol, maxiter=maxiter, disp=False)
    if recording:
        prob.driver.add_recorder(om.SqliteRecorder(recording))
    if counter is not None:
        prob.driver.add_recorder(counter)
    if progress:
        prob.driver.add_recorder(ProgressPrinter(objective="fuelburn", units="kg"))
    prob.final_setup()
    res = prob.run_driver()   # om DriverResult: SLSQP major iterations = gradient evaluations
    message = "optimum found (SLSQP)" if res.success else (
        f"SLSQP stopped at the iteration limit (maxiter {maxiter})" if res.deriv_evals >= maxiter
        else "SLSQP failed (see its message above)")
    return {"success": bool(res.success), "message": message, "iterations": int(res.deriv_evals),
            "evaluations": int(res.model_evals), "wall_time_s": time.perf_counter() - t0,
            "time_per_analysis_s": res.model_time / max(res.model_evals, 1),
            "time_per_gradient_s": res.deriv_time / max(res.deriv_evals, 1)}


def crm_summary(prob, stress, beam, counter=None):
    """Results of the current design: fuel burn (kg), wing structural mass (kg), maneuver tip
    deflection (m), the stress measure per point, L = W and CL, coupled iterations per point (of
    the last evaluation, from ``counter``), the
    design and the element thicknesses (OpenAeroStruct's element order: tip to root, m).

    Parameters
    ----------
    prob : openmdao.api.Problem
        The solved problem.
    stress : dict
        Point name -> stress output path.
    beam : {"wingmdao", "oas"}
        Structural model.
    counter : SolverIterationCounter or None, optional
        Counter of the coupled solves.

    Returns
    -------
    dict
        The results.
    """
    val = lambda name: np.asarray(prob.get_val(name)).ravel()  # noqa: E731
    points = [p[0] for p in CRM_POINTS]
    return {
        "beam": beam,
        "fuelburn_kg": float(val("AS_point_0.fuelburn")[0]),
        "wing_mass_kg": float(val("wing.structural_mass")[0]),
        "tip_deflection_m": float(prob.get_val("AS_point_1.coupled.wing.disp")[0, 2]),
        "ks": {name: float(val(stress[name]).max()) for name in points},
        "stress_measure": STRESS_MEASURE[beam],
        "L_equals_W": float(val("AS_point_1.L_equals_W")[0]),
        "CL_cruise": float(val("AS_point_0.CL")[0]),
        "coupled_iterations": dict(counter.last) if counter is not None else None,
        "design": {"twist_cp_deg": val("wing.twist_cp").tolist(),
                   "spar_thickness_cp_m": val("wing.spar_thickness_cp").tolist(),
                   "skin_thickness_cp_m": val("wing.skin_thickness_cp").tolist(),
                   "alpha_maneuver_deg": float(val("alpha")[1])},
        "spar_thickness_m": val("wing.spar_thickness").tolist(),
        "skin_thickness_m": val("wing.skin_thickness").tolist(),
    }


def run_crm(beam="wingmdao", *, analysis_only=False, maxiter=40, tol=1e-6, num_y=15, recording=None,
            progress=False):
    """Build, set up, solve (:func:`solve_crm`) and summarise (:func:`crm_summary`) the problem.

    Parameters
    ----------
    beam : {"wingmdao", "oas"}, optional
        Structural model: the wingmdao beam or OpenAeroStruct's own.
    analysis_only : bool, optional
        Run one coupled analysis only.
    maxiter : int, optional
        SLSQP iteration limit.
    tol : float, optional
        SLSQP tolerance.
    num_y : int, optional
        Spanwise mesh points of the full wing.
    recording : str or None, optional
        SQLite file to record the optimization in.
    progress : bool, optional
        Print a line per driver evaluation.

    Returns
    -------
    dict
        Run results and summary.
    """
    prob, stress = build_crm_problem(beam, num_y)
    counter = setup_crm_problem(prob)
    info = solve_crm(prob, counter, analysis_only=analysis_only, maxiter=maxiter, tol=tol, recording=recording,
                     progress=progress)
    out = crm_summary(prob, stress, beam, counter)
    out.update(info)
    prob.cleanup()
    return out
