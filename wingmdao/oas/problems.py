"""Ready OpenAeroStruct aerostructural problems with either beam (used by tests, benchmarks, cases).

``aerostruct_problem(surface, beam="wingmdao" | "oas", ...)``: one ``AerostructGeometry`` and
``AerostructPoint``s at the given flight conditions (one per entry of ``mach``, ``v``, ``rho``,
``re``, ``load_factor``, ``alpha_deg``), connected as in OpenAeroStruct's wingbox examples, with
the structural solver either OpenAeroStruct's spatial beam or the wingmdao beam.
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om

from wingmdao.materials import ALUMINIUM
from wingmdao.oas.point import WingmdaoAerostructPoint


def rect_wingbox_surface(num_y=11, span=20.0, chord=2.0, t_over_c=0.12, spar=0.004, skin=0.004,
                         material=None):
    """Rectangular symmetric wing with a rectangular wingbox (10 % to 60 % chord).

    Parameters
    ----------
    num_y : int, optional
        Spanwise mesh points of the full wing.
    span : float, optional
        Full span (m).
    chord : float, optional
        Chord (m).
    t_over_c : float, optional
        Thickness-to-chord ratio (-).
    spar : float, optional
        Spar thickness (m).
    skin : float, optional
        Skin thickness (m).
    material : Material or None, optional
        Wingbox material; None for aluminium.

    Returns
    -------
    dict
        The surface.
    """
    from openaerostruct.meshing.mesh_generator import generate_mesh


    mat = material or ALUMINIUM
    mesh = generate_mesh({"num_y": 2 * num_y - 1, "num_x": 2, "wing_type": "rect", "symmetry": True,
                          "span": span, "root_chord": chord})
    h = t_over_c / 2
    return {"name": "wing", "symmetry": True, "S_ref_type": "projected", "mesh": mesh,
            "fem_model_type": "wingbox", "twist_cp": np.zeros(2),
            "spar_thickness_cp": np.array([spar, spar]), "skin_thickness_cp": np.array([skin, skin]),
            "t_over_c_cp": np.array([t_over_c]), "original_wingbox_airfoil_t_over_c": t_over_c,
            "data_x_upper": np.array([0.1, 0.6]), "data_y_upper": np.array([h, h]),
            "data_x_lower": np.array([0.1, 0.6]), "data_y_lower": np.array([-h, -h]),
            "CL0": 0.0, "CD0": 0.0078, "with_viscous": False, "with_wave": False, "k_lam": 0.05, "c_max_t": 0.38,
            "E": mat.E, "G": mat.G, "yield": mat.sigma_y, "safety_factor": 1.5, "mrho": mat.rho,
            "strength_factor_for_upper_skin": 1.0, "wing_weight_ratio": 1.0, "exact_failure_constraint": False,
            "struct_weight_relief": False, "distributed_fuel_weight": False, "fem_origin": 0.35,
            "wingmdao_material": mat}


def aerostruct_problem(surface, beam="wingmdao", mach=(0.3,), v=(100.0,), rho=(1.0,), re=(1e6,),
                       load_factor=(1.0,), alpha_deg=(4.0,), W0=20000.0, iprint=-1, extra=None, setup=True):
    """Set-up problem; points ``AS_point_<i>``; outputs per point ``CL``, ``fuelburn``, ``wing_perf.failure``,
    geometry ``wing.structural_mass``, displacements ``AS_point_<i>.coupled.wing.disp`` (ny, 6).
    ``extra(model)``: called before setup to add components (its return value is returned too,
    as ``(prob, extra_result)``); ``setup=False`` leaves the problem to set up (and skips the
    solver settings, see :func:`wingmdao.oas.crm.setup_crm_problem`).

    Parameters
    ----------
    surface : dict
        OpenAeroStruct surface.
    beam : {"wingmdao", "oas"}, optional
        Structural model: the wingmdao beam or OpenAeroStruct's own.
    mach, v, rho, re, load_factor, alpha_deg : tuple, optional
        Per point: Mach number (-), airspeed (m/s), density (kg/m^3), Reynolds number per length (1/m),
        load factor (-), angle of attack (deg).
    W0 : float, optional
        Aircraft weight without the wing structure and fuel (kg).
    iprint : int, optional
        Solver print level.
    extra : callable or None, optional
        ``extra(model)``, called before setup.
    setup : bool, optional
        Set the problem up.

    Returns
    -------
    openmdao.api.Problem or tuple
        The problem; (problem, extra's result) when ``extra`` is given or ``setup`` is False.
    """
    from openaerostruct.integration.aerostruct_groups import AerostructGeometry, AerostructPoint


    if beam not in ("wingmdao", "oas"):
        raise ValueError(f"beam must be 'wingmdao' or 'oas', got {beam!r}")
    npt = len(mach)
    prob = om.Problem(reports=False)
    ivc = prob.model.add_subsystem("prob_vars", om.IndepVarComp(), promotes=["*"])
    ivc.add_output("Mach_number", val=np.array(mach, float))
    ivc.add_output("v", val=np.array(v, float), units="m/s")
    ivc.add_output("re", val=np.array(re, float), units="1/m")
    ivc.add_output("rho", val=np.array(rho, float), units="kg/m**3")
    ivc.add_output("speed_of_sound", val=np.array(v, float) / np.array(mach, float), units="m/s")
    ivc.add_output("CT", val=0.53 / 3600, units="1/s")
    ivc.add_output("R", val=14.307e6, units="m")
    ivc.add_output("W0", val=W0, units="kg")
    ivc.add_output("load_factor", val=np.array(load_factor, float))
    ivc.add_output("alpha", val=np.array(alpha_deg, float), units="deg")
    ivc.add_output("empty_cg", val=np.zeros(3), units="m")
    ivc.add_output("fuel_mass", val=10000.0, units="kg")
    name = surface["name"]
    prob.model.add_subsystem(name, AerostructGeometry(surface=surface))
    for i in range(npt):
        pt = f"AS_point_{i}"
        point = (WingmdaoAerostructPoint if beam == "wingmdao" else AerostructPoint)(
            surfaces=[surface], internally_connect_fuelburn=False)
        prob.model.add_subsystem(pt, point)
        for k in ("v", "Mach_number", "re", "rho", "speed_of_sound", "load_factor", "alpha"):
            prob.model.connect(k, f"{pt}.{k}", src_indices=[i])
        for k in ("CT", "R", "W0", "empty_cg"):
            prob.model.connect(k, f"{pt}.{k}")
        prob.model.connect("fuel_mass", f"{pt}.total_perf.L_equals_W.fuelburn")
        prob.model.connect("fuel_mass", f"{pt}.total_perf.CG.fuelburn")
        c, perf = f"{pt}.coupled.{name}", f"{pt}.{name}_perf."
        if beam == "oas":
            prob.model.connect(f"{name}.local_stiff_transformed", f"{c}.local_stiff_transformed")
        else:
            prob.model.connect(f"{name}.spar_thickness", f"{c}.spar_thickness")
            prob.model.connect(f"{name}.skin_thickness", f"{c}.skin_thickness")
            for k in (("htop", "hbottom", "hfront", "hrear") if surface.get("wingmdao_box") == "oas" else ()):
                prob.model.connect(f"{name}.{k}", f"{c}.{k}")
        prob.model.connect(f"{name}.nodes", f"{c}.nodes")
        prob.model.connect(f"{name}.mesh", f"{c}.mesh")
        prob.model.connect(f"{name}.nodes", perf + "nodes")
        prob.model.connect(f"{name}.cg_location", f"{pt}.total_perf.{name}_cg_location")
        prob.model.connect(f"{name}.structural_mass", f"{pt}.total_perf.{name}_structural_mass")
        for k in ("Qz", "J", "A_enc", "htop", "hbottom", "hfront", "hrear", "spar_thickness", "t_over_c"):
            prob.model.connect(f"{name}.{k}", perf + k)
    extra_result = extra(prob.model) if extra is not None else None
    if not setup:
        return prob, extra_result
    prob.setup(mode="rev")
    for i in range(npt):
        cp = getattr(prob.model, f"AS_point_{i}").coupled
        cp.nonlinear_solver.options["iprint"] = iprint
        cp.linear_solver = om.LinearBlockGS(iprint=-1, maxiter=50, use_aitken=True, atol=1e-12, rtol=1e-12)
    return (prob, extra_result) if extra is not None else prob
