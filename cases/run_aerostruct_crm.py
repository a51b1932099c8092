"""uCRM multipoint aerostructural fuel-burn problem with the wingmdao beam beside OpenAeroStruct's own.

Based on OpenAeroStruct's wingbox multipoint example (openaerostruct/docs/wingbox_mpt_opt_example.py,
after Chauhan and Martins, "Low-fidelity aerostructural optimization of aircraft wings with a
simplified wingbox model using OpenAeroStruct", EngOpt 2018): uCRM-based mesh from the
OpenAeroStruct package, cruise point (M 0.85, rho 0.348 kg/m^3) and 2.5 g maneuver (M 0.64,
rho 1.225 kg/m^3), Breguet fuel burn objective, twist and spar/skin thickness design variables,
CL = 0.5 at cruise, L = W at the maneuver, stress constraint at the maneuver. Simplifications
(both beams alike, see docs/embedding.md): rectangular wingbox between 10 % and 60 % chord at
t/c 0.12, no structural weight relief, fuel weight or engine mass in the structural loads.

The stress constraint is our KS of the box von Mises constraints (Eq. 4.26, 4.44 of
"Structural analysis and optimization of aircraft wings through dimensional reduction", PhD
dissertation, Georgia Institute of Technology, 2021) with our beam, and OpenAeroStruct's KS
failure with its beam; yield 420 MPa / safety factor 1.5 in both.

    python cases/run_aerostruct_crm.py --analysis-only --json -     # one coupled analysis, both beams
    python cases/run_aerostruct_crm.py --json result.json            # optimise with both beams
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time

import numpy as np


def crm_surface(num_y=15):
    from openaerostruct.meshing.mesh_generator import generate_mesh

    from wingmdao.materials import Material
    from wingmdao.oas.problems import rect_wingbox_surface

    mat = Material("al-crm", E=73.1e9, rho=2.78e3, sigma_y=420e6 / 1.5, G=73.1e9 / 2 / 1.33)
    surf = rect_wingbox_surface(material=mat)
    mesh, _ = generate_mesh({"num_y": num_y, "num_x": 3, "wing_type": "uCRM_based", "symmetry": True,
                             "chord_cos_spacing": 0, "span_cos_spacing": 0, "num_twist_cp": 4})
    surf.update({"mesh": mesh, "twist_cp": np.array([4.0, 5.0, 8.0, 9.0]),
                 "spar_thickness_cp": np.array([0.004, 0.005, 0.008, 0.01]),
                 "skin_thickness_cp": np.array([0.005, 0.01, 0.015, 0.025]),
                 "yield": 420e6, "safety_factor": 1.5, "with_viscous": True, "with_wave": True,
                 "wing_weight_ratio": 1.25, "CD0": 0.0078,
                 "wingmdao_box": "oas"})   # the box of each element from OpenAeroStruct's wingbox geometry
    return surf


def add_our_ks(prob_model, point, num_nodes, material, rho_ks=100.0):
    """Our box stress KS at one point, from the beam states inside the point's coupled group."""
    from wingmdao.components.beam_loads import BeamInternalLoads
    from wingmdao.components.ks import KSAggregate
    from wingmdao.components.stress import BoxStress
    from wingmdao.groups.wing import stress_points

    import openmdao.api as om

    g = prob_model.add_subsystem(f"{point}_ks", om.Group())
    g.add_subsystem("internal_loads", BeamInternalLoads(num_times=1, num_nodes=num_nodes))
    g.add_subsystem("stress", BoxStress(num_times=1, num_stations=num_nodes, material=material,
                                        families=("vm",), output_stresses=False))
    g.add_subsystem("ks", KSAggregate(families={f: (1, num_nodes, k) for f, k in stress_points("box", ("vm",)).items()}, rho_ks=rho_ks))
    g.connect("internal_loads.F_csn", "stress.F_csn")
    g.connect("internal_loads.M_csn", "stress.M_csn")
    g.connect("stress.g_vm", "ks.g_vm")
    ss = f"{point}.coupled.wing.struct_states"
    n = num_nodes
    prob_model.connect(f"{ss}.wingmdao_states", f"{point}_ks.internal_loads.states",
                       src_indices=np.arange(18 * n).reshape(1, n, 18), flat_src_indices=True)
    for k in ("width", "height", "t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar"):
        prob_model.connect(f"{ss}.{k}", f"{point}_ks.stress.{k}")
    return f"{point}_ks.ks.ks_vm"


def build(beam, num_y=15):
    from wingmdao.oas.problems import aerostruct_problem

    surf = crm_surface(num_y)
    ny = surf["mesh"].shape[1]

    def extra(model):
        return add_our_ks(model, "AS_point_1", ny, surf["wingmdao_material"]) if beam == "wingmdao" else None

    prob, ks = aerostruct_problem(surf, beam=beam, mach=(0.85, 0.64), v=(0.85 * 295.07, 0.64 * 340.294),
                                  rho=(0.348, 1.225),
                                  re=(0.348 * 295.07 * 0.85 / 1.43e-5, 1.225 * 340.294 * 0.64 / 1.81206e-5),
                                  load_factor=(1.0, 2.5), alpha_deg=(0.0, 0.0), W0=128000.0 + 15000.0,
                                  extra=extra, setup=False)
    m = prob.model
    m.add_design_var("wing.twist_cp", lower=-15.0, upper=15.0, scaler=0.1)
    m.add_design_var("wing.spar_thickness_cp", lower=0.003, upper=0.1, scaler=1e2)
    m.add_design_var("wing.skin_thickness_cp", lower=0.003, upper=0.1, scaler=1e2)
    m.add_design_var("alpha", indices=[1], lower=-15.0, upper=15.0)
    m.add_objective("AS_point_0.fuelburn", scaler=1e-5)
    m.add_constraint("AS_point_0.CL", equals=0.5)
    m.add_constraint("AS_point_1.L_equals_W", equals=0.0)
    m.add_constraint(ks if ks else "AS_point_1.wing_perf.failure", upper=0.0)
    return prob, ks


def summary(prob, t, iters):
    d = prob.get_val("AS_point_1.coupled.wing.disp")
    return {"fuelburn_kg": float(prob.get_val("AS_point_0.fuelburn")[0]),
            "wing_mass_kg": float(prob.get_val("wing.structural_mass")[0]),
            "tip_deflection_m": float(d[0, 2]),
            "CL_cruise": float(prob.get_val("AS_point_0.CL")[0]),
            "coupled_iterations": [int(getattr(prob.model, f"AS_point_{i}").coupled.nonlinear_solver._iter_count)
                                   for i in range(2)],
            "optimizer_iterations": iters, "wall_time_s": t}


def run(beam, analysis_only, maxiter, tol=1e-6):
    import openmdao.api as om

    prob, ks = build(beam)
    prob.setup(mode="rev")
    for i in range(2):
        getattr(prob.model, f"AS_point_{i}").coupled.linear_solver = om.LinearBlockGS(
            iprint=-1, maxiter=50, use_aitken=True, atol=1e-10, rtol=1e-10)
        getattr(prob.model, f"AS_point_{i}").coupled.nonlinear_solver.options["iprint"] = -1
    t0 = time.perf_counter()
    iters = 0
    if analysis_only:
        prob.run_model()
    else:
        prob.driver = om.ScipyOptimizeDriver(optimizer="SLSQP", tol=tol, maxiter=maxiter, disp=False)
        prob.run_driver()
        iters = int(prob.driver.iter_count)
    out = summary(prob, time.perf_counter() - t0, iters)
    out["success"] = bool(getattr(prob.driver, "result", None) is None or prob.driver.result.success) \
        if not analysis_only else True
    out["stress_constraint"] = float(prob.get_val(ks if ks else "AS_point_1.wing_perf.failure").max())
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--analysis-only", action="store_true", help="one coupled analysis of the initial design")
    ap.add_argument("--json", metavar="FILE", help="write the results as JSON ('-' for stdout)")
    ap.add_argument("--maxiter", type=int, default=40, help="SLSQP iterations (optimisation)")
    ap.add_argument("--tol", type=float, default=1e-6, help="SLSQP tolerance")
    a = ap.parse_args(argv)
    res = run("wingmdao", a.analysis_only, a.maxiter, a.tol)
    res["oas_beam"] = run("oas", a.analysis_only, a.maxiter, a.tol)
    text = json.dumps(res, indent=2)
    print(text if a.json != "-" else "", file=sys.stderr)
    if a.json == "-":
        print(text)
    elif a.json:
        d = os.path.dirname(os.path.abspath(a.json))
        fd, tmp = tempfile.mkstemp(dir=d, suffix=".tmp")
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, a.json)
    return res


if __name__ == "__main__":
    main()
