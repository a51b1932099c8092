"""The OpenMDAO problem of ``wingmdao run wing-box``: the chain of
:class:`wingmdao.groups.wing.WingSizing` with one tip-load case of :mod:`.model` and a von Mises
stress output, and the check of its adjoint totals against finite differences."""

from __future__ import annotations

import numpy as np
import openmdao.api as om

from wingmdao.components.stress import BoxStress
from wingmdao.design import WALL_VARS
from wingmdao.groups.wing import WingSizing, set_case_loads
from wingmdao.materials import ALUMINIUM
from wingmdao.sizing import set_geometry


def analysis_problem(geometry, load_case, walls: dict, material=ALUMINIUM, *, design_vars=False,
                     rho_ks=100.0, mode="rev", newton_options=None):
    """Set up (not run) the sizing model of one load case plus a von Mises output.

    The chain is :class:`WingSizing` (section, mass, beam, internal loads, stress, KS) with an
    extra :class:`BoxStress` (``output_stresses=True``) on the case's internal loads, whose
    ``vm_stress.sigma_vm`` (nt, n, 8) Pa are the mid-corner von Mises stresses. ``walls`` maps
    the four wall names to per-node thicknesses (m). With ``design_vars`` the thicknesses are
    design variables and the case's KS outputs constraints (for ``check_totals``); ``mode`` is
    OpenMDAO's derivative mode ("rev": one adjoint sweep per KS output, "fwd": one tangent
    sweep per thickness).

    Parameters
    ----------
    geometry : wingmdao.sizing.WingGeometry
        The box beam (:func:`wing_geometry`).
    load_case : wingmdao.groups.load_case.LoadCase
        The one load case.
    walls : dict
        ``{wall name: (n,) thickness (m)}`` of the four walls.
    material : wingmdao.materials.Material, optional
        Wall material.
    design_vars : bool, optional
        Thicknesses as design variables and KS outputs as constraints.
    rho_ks : float, optional
        KS aggregation parameter (of the stress ratios: dimensionless).
    mode : str, optional
        OpenMDAO derivative mode, ``"rev"`` or ``"fwd"``.
    newton_options : dict, optional
        Options of the beam's Newton solver.

    Returns
    -------
    openmdao.api.Problem
        The set-up problem.
    """
    n = geometry.num_nodes
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("wing", WingSizing(num_nodes=n, load_cases=[load_case], material=material,
                                                rho_ks=rho_ks, newton_options=newton_options,
                                                add_constraints=design_vars, add_objective=design_vars),
                             promotes=["*"])
    prob.model.add_subsystem("vm_stress", BoxStress(num_times=load_case.num_times, num_stations=n,
                                                    material=material, families=("vm",)),
                             promotes_inputs=["width", "height", *WALL_VARS])
    base = f"cases.{load_case.name}.internal_loads"
    prob.model.connect(f"{base}.F_csn", "vm_stress.F_csn")
    prob.model.connect(f"{base}.M_csn", "vm_stress.M_csn")
    for name in ("width", "height", *WALL_VARS):
        prob.model.set_input_defaults(name, val=np.ones(n), units="m")
    if design_vars:
        for w in WALL_VARS:
            prob.model.add_design_var(w)
    prob.setup(mode=mode)
    set_geometry(prob, geometry)
    set_case_loads(prob, load_case, n, f"cases.{load_case.name}")
    for w in WALL_VARS:
        prob.set_val(w, np.broadcast_to(walls[w], (n,)), units="m")
    return prob


def totals_max_rel_error(prob, load_case) -> float:
    """Largest relative difference between the adjoint totals of the KS outputs w.r.t. the wall
    thicknesses and OpenMDAO's central finite differences (relative to each block's max ``|J|``).

    Step 1e-4 relative to the mean thickness: the truncation error is ~1e-8 and the Newton
    round-off noise (~1e-14 in KS) stays below 1e-9 of the derivatives (1e-6 gives ~5e-6).

    Parameters
    ----------
    prob : openmdao.api.Problem
        A problem of :func:`analysis_problem` with ``design_vars=True``, run.
    load_case : wingmdao.groups.load_case.LoadCase
        Its load case (the KS outputs of its families).

    Returns
    -------
    float
        The largest relative error (dimensionless).
    """
    of = [f"cases.{load_case.name}.ks_{f}" for f in load_case.families]
    data = prob.check_totals(of=of, wrt=list(WALL_VARS), method="fd", form="central", step=1e-4,
                             step_calc="rel_avg", out_stream=None)
    worst = 0.0
    for d in data.values():
        j_ad = d["J_rev"] if "J_rev" in d else d["J_fwd"]
        ref = max(np.abs(d["J_fd"]).max(), 1e-12)
        worst = max(worst, float(np.abs(j_ad - d["J_fd"]).max() / ref))
    return worst
