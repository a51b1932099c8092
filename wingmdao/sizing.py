"""Build, run and summarise a minimum-mass sizing problem (Sec. 4.7.2, 5.1, 5.2).

Design variables: the four wall thicknesses at every station with minimum-gauge lower
bounds (Table 5.1); constraints: the KS aggregate of every enabled stress family of every
load case <= 0; objective: structural mass.
"""

from __future__ import annotations

import os
import time as _time

import numpy as np
import openmdao.api as om
from openmdao.utils.mpi import FakeComm, MPI

from wingmdao.beam.geometry import WingGeometry
# the sizing's design (wingmdao.design): its names, also offered here
from wingmdao.design import (BOX_KINDS, OBJECTIVE_SCALE, RHO_KS_MIN, SECTION_KINDS, WALL_VARS,  # noqa: F401
                             SizingOptions, _stringers, case_families, design_beam_params, initial_design,
                             initial_frequencies, span_coordinate, station_design)
from wingmdao.groups.wing import WingSizing, set_case_loads
from wingmdao.panel_results import mass_breakdown, panel_summary, rib_summary
from wingmdao.panels.layout import PanelLayout, rib_weights
from wingmdao.optimize import ProgressPrinter, add_recorder, make_driver
from wingmdao.section.box import box_area
from wingmdao.components.flutter import paused_flutter
from wingmdao.components.mass import beam_mass
from wingmdao.components.turbulence import TurbulenceStressKS
from wingmdao.groups.load_case import LoadCase, StickCase
from wingmdao.groups.stick import StickSizing, set_sized_beams, set_stick_case
from wingmdao.limits import check_memory
from wingmdao.loads.turbulence_analysis import gust_model_from_parameters, turbulence_analysis
from wingmdao.stability.frequency import stress_matrices
from wingmdao.materials import Material
from wingmdao.timemarch.system import pack
from wingmdao.utils.memory import return_freed_memory
from wingmdao.aero.coupled import load_case_response
from wingmdao.aero.system import cached_aeroelastic_system, control_param_specs
from wingmdao.loads.maneuver_trim import elevator_trim
from wingmdao.cases.planform import G0, LB
from wingmdao.parallel import assign_cases, distributed_wing_sizing, set_shared_geometry, world_comm
from wingmdao.report import best_design, read_history


def check_problem_inputs(geometry, load_cases, material, options, section="box") -> None:
    """ValueError naming the argument for inputs :func:`build_problem` cannot use (before setup).

    Parameters
    ----------
    geometry : WingGeometry
        The wing's nodes, sections and station map.
    load_cases : list of LoadCase
        The load cases to size for.
    material : wingmdao.materials.Material
        The wall material.
    options : SizingOptions
        Bounds, start and driver settings.
    section : str
        Section kind, a key of ``wingmdao.design.SECTION_KINDS`` (``"box"``, ``"solid"``,
        ``"stiffened"``, ...).

    Raises
    ------
    ValueError
        Naming the argument, its value and the allowed range.
    """
    if section not in SECTION_KINDS:
        raise ValueError(f"section = {section!r}; allowed: {', '.join(SECTION_KINDS)}")
    if not isinstance(material, Material):
        raise ValueError(f"material must be a wingmdao.materials.Material (e.g. get_material('aluminium')), "
                         f"got {type(material).__name__} {material!r}")
    if isinstance(load_cases, LoadCase):
        raise ValueError("load_cases must be a list of LoadCase, got a single LoadCase (wrap it in [ ])")
    cases = list(load_cases)
    if not cases:
        raise ValueError("load_cases is empty; give at least one LoadCase")
    bad = [type(c).__name__ for c in cases if not isinstance(c, LoadCase)]
    if bad:
        raise ValueError(f"load_cases must hold LoadCase objects, got {', '.join(bad)}")
    names = [c.name for c in cases]
    if len(set(names)) != len(names):
        raise ValueError(f"load_cases: names must be unique, got {names}")
    _check_options(options, SECTION_KINDS[section]["design_vars"])
    _check_geometry(geometry, section)
    _check_initial(options, SECTION_KINDS[section]["design_vars"], geometry)


def _check_initial(options, design_vars, geometry) -> None:
    """ValueError for an initial design that names no design variable or does not fit its size."""
    smap = geometry.station_map
    n_dv = geometry.num_nodes if smap is None else int(np.max(smap)) + 1
    for w, v in (options.initial or {}).items():
        if w not in design_vars:
            raise ValueError(f"options.initial[{w!r}]: not a design variable; allowed: {', '.join(design_vars)}")
        size = np.asarray(v, dtype=float).size
        if size not in (1, n_dv):
            raise ValueError(f"options.initial[{w!r}]: {size} values; needs 1 or {n_dv} (one per design station), m")


def _number(value) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def _check_options(options, design_vars) -> None:
    """ValueError naming the SizingOptions field that is not usable (type, range, bounds)."""
    if not isinstance(options, SizingOptions):
        raise ValueError(f"options must be a SizingOptions, got {type(options).__name__}")
    rho = options.rho_ks
    if not (_number(rho) and np.isfinite(rho) and rho >= RHO_KS_MIN):
        raise ValueError(f"options.rho_ks = {rho!r}; allowed range [{RHO_KS_MIN:g}, inf) (a number)")
    if isinstance(options.maxiter, bool) or not isinstance(options.maxiter, (int, np.integer)) or options.maxiter < 1:
        raise ValueError(f"options.maxiter = {options.maxiter!r}; allowed range >= 1 (an integer)")
    if not (_number(options.tol) and np.isfinite(options.tol) and options.tol > 0):
        raise ValueError(f"options.tol = {options.tol!r}; allowed range (0, inf) (a number)")
    if options.mass_scale is not None and not (_number(options.mass_scale) and np.isfinite(options.mass_scale)
                                               and options.mass_scale > 0):
        raise ValueError(f"options.mass_scale = {options.mass_scale!r} kg; allowed range (0, inf) kg, or None")
    for what in ("lower", "upper", "initial"):
        for w, v in (getattr(options, what) or {}).items():
            if isinstance(v, str) or not np.all(np.isfinite(np.asarray(v, dtype=float))):
                raise ValueError(f"options.{what}[{w!r}] = {v!r}; must be finite numbers (m)")
    for what in ("lower", "upper"):
        missing = [w for w in design_vars if w not in (getattr(options, what) or {})]
        if missing:
            raise ValueError(f"options.{what}: no bound for {', '.join(missing)}; give one per design "
                             f"variable ({', '.join(design_vars)}), m")
    for w in design_vars:
        lo, up = np.asarray(options.lower[w], dtype=float), np.asarray(options.upper[w], dtype=float)
        if np.any(lo <= 0) or np.any(lo > up):
            raise ValueError(f"options.lower[{w!r}] = {options.lower[w]!r} m, options.upper[{w!r}] = "
                             f"{options.upper[w]!r} m; need 0 < lower <= upper")


def _check_geometry(geometry, section) -> None:
    """ValueError naming the WingGeometry field whose shape or values do not fit ``num_nodes``."""
    if not isinstance(geometry, WingGeometry):
        raise ValueError(f"geometry must be a wingmdao.sizing.WingGeometry, got {type(geometry).__name__}")
    n = geometry.num_nodes
    if n < 2:
        raise ValueError(f"geometry.node_positions: {n} node(s); a beam needs at least 2")
    shapes = {"node_positions": (n, 3), "node_euler_angles": (n, 3), "section_to_csn": (n, 3, 3),
              "nonstructural_mass_per_length": (n,), "span_coordinate": (n,)}
    if section in BOX_KINDS:
        shapes.update(width=(n,), height=(n,))
    for name, shape in shapes.items():
        value = getattr(geometry, name)
        if value is None and name not in ("node_positions", "node_euler_angles", "width", "height"):
            continue
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"geometry.{name}: not an array of numbers ({type(value).__name__})") from None
        if arr.shape != shape:
            raise ValueError(f"geometry.{name}: shape {arr.shape}; needs {shape} ({n} beam nodes)")
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"geometry.{name}: not finite at flat index {int(np.flatnonzero(~np.isfinite(arr))[0])}")
    if section in BOX_KINDS and (np.any(np.asarray(geometry.width) <= 0) or np.any(np.asarray(geometry.height) <= 0)):
        raise ValueError("geometry.width and geometry.height: box dimensions must be > 0 m at every node")
    if geometry.nonstructural_mass_per_length is not None and np.any(np.asarray(geometry.nonstructural_mass_per_length) < 0):
        raise ValueError("geometry.nonstructural_mass_per_length: allowed range [0, inf) kg/m")
    if geometry.station_map is not None:
        smap = np.asarray(geometry.station_map)
        if smap.shape != (n,) or not np.issubdtype(smap.dtype, np.integer):
            raise ValueError(f"geometry.station_map: shape {smap.shape} dtype {smap.dtype}; needs ({n},) integers "
                             "(one design index per beam node)")
        if smap.min() < 0 or set(np.unique(smap)) != set(range(int(smap.max()) + 1)):
            raise ValueError(f"geometry.station_map = {smap.tolist()}; indices must cover 0..k without gaps")


def build_problem(geometry: WingGeometry, load_cases, material, options: SizingOptions,
                  *, driver=True, parallel=None, section="box", comm=False,
                  flutter: dict | None = None, panels: PanelLayout | None = None,
                  turbulence: dict | None = None, equivalent_panels: PanelLayout | None = None
                  ) -> tuple[om.Problem, str]:
    """Set up the sizing problem; returns ``(problem, driver description)``.

    ``section`` is ``"box"`` (design variables: the four wall thicknesses) or ``"solid"``
    (design variables: width and height of a solid rectangle, Sec. 4.7.1). ``comm``: an MPI
    communicator with more than one rank spreads the load cases over its ranks
    (:mod:`wingmdao.parallel`); False/None: all cases in this process. ``flutter``: options of
    :class:`~wingmdao.components.flutter.FlutterDamping` (e.g. from
    :func:`wingmdao.stability.cases.sizing_flutter_options`): adds the constraint flutter_ks <= 0.
    ``turbulence``: options of :class:`~wingmdao.components.turbulence.TurbulenceStressKS` (e.g. from
    :func:`wingmdao.loads.turbulence_analysis.sizing_turbulence_options`): adds turbulence_ks <= 0.
    ``panels``: the stiffened panels and ribs (section ``"stiffened"``, and only there): adds the
    stiffener design variables, the panel failure constraints, the ribs' mass and the sizing rules
    (linear constraints; docs/panels.md).

    Parameters
    ----------
    geometry : WingGeometry
        The wing's nodes, sections and station map.
    load_cases : list of LoadCase
        The load cases to size for.
    material : wingmdao.materials.Material
        The wall material.
    options : SizingOptions
        Bounds, start, driver and scaling settings.
    driver : bool
        Add the optimizer, design variables, objective and constraints; False builds the model only.
    parallel : bool or None
        Passed to :class:`~wingmdao.groups.wing.WingSizing`: run the load cases in a parallel group.
    section : str
        ``"box"``, ``"solid"`` or ``"stiffened"`` (see above).
    comm : MPI communicator or bool or None
        With more than one rank, spreads the load cases over its ranks; False/None: one process.
    flutter : dict or None
        Options of :class:`~wingmdao.components.flutter.FlutterDamping`; None: no flutter constraint.
    panels : PanelLayout or None
        The stiffened panels and ribs (section ``"stiffened"`` only).
    turbulence : dict or None
        Options of :class:`~wingmdao.components.turbulence.TurbulenceStressKS`; None: no
        turbulence constraint.
    equivalent_panels : PanelLayout or None
        Section ``"box"`` only: the walls are stiffened panels' equivalent thicknesses, every case
        gets the outer constraint of the two-level sizing (``ks_equivalent_panels``,
        :class:`~wingmdao.components.panels.EquivalentPanelFailure`; :mod:`wingmdao.panel_sizing`).
    """
    check_problem_inputs(geometry, load_cases, material, options, section)
    if (section == "stiffened") != (panels is not None):
        raise ValueError(f"section = {section!r} with panels = {panels!r}: a PanelLayout goes with section "
                         "'stiffened' and only with it")
    if equivalent_panels is not None and section != "box":
        raise ValueError(f"section = {section!r} with equivalent_panels: the equivalent walls are a box's")
    n = geometry.num_nodes
    design_vars = SECTION_KINDS[section]["design_vars"]
    load_cases = list(load_cases)
    distributed = comm is not None and comm is not False and comm.size > 1
    if flutter is not None and (distributed or section not in BOX_KINDS):
        raise ValueError("the flutter constraint needs box sections in one process (no MPI distribution)")
    if turbulence is not None and (distributed or section != "box"):
        raise ValueError("the turbulence constraint needs box sections in one process (no MPI distribution)")
    if distributed and control_gain_design_vars(load_cases):
        raise ValueError("--size-gains: the control-law gains are sized in one process (no MPI distribution)")
    gain_vars = control_gain_design_vars(load_cases)
    if turbulence is not None and turbulence.get("control_law") is not None and gain_vars:
        turbulence, gain_vars = shared_turbulence_gains(load_cases, turbulence, gain_vars)
    mass_ref = (options.mass_scale or OBJECTIVE_SCALE * initial_mass(geometry, material, options, section, panels)) \
        if driver else 1.0
    # the load cases' forcing histories are fixed data of the beams, not OpenMDAO variables (issue 15)
    wing_kwargs = dict(rho_ks=options.rho_ks, add_constraints=driver, add_objective=driver, mass_ref=mass_ref,
                       forcing_as_data=True)
    if panels is not None:
        if distributed:
            raise ValueError("stiffened panels (section 'stiffened') run in one process (no MPI distribution)")
        wing_kwargs.update(panels=panels, rib_weights=rib_weights(span_coordinate(geometry), panels.rib_positions))
    if equivalent_panels is not None:
        if distributed:
            raise ValueError("the two-level sizing's outer level runs in one process (no MPI distribution)")
        wing_kwargs.update(equivalent_panels=equivalent_panels)
    if distributed:
        wing, _ = distributed_wing_sizing(geometry, load_cases, material, options, section, comm,
                                          build_problem=build_problem, **wing_kwargs)
    else:
        wing = WingSizing(num_nodes=n, load_cases=load_cases, material=material, parallel=parallel,
                          section=section, station_map=geometry.station_map, flutter=flutter,
                          turbulence=turbulence, **wing_kwargs)
    # the wing group is the model itself, not a subsystem of it: one group level less, so one
    # LinearRunOnce copy of all the d_outputs less (27 MB at 20 nodes x 4001 steps, issue 15)
    prob = om.Problem(model=wing, comm=None if distributed else _serial_comm(), reports=False)
    desc = "none (analysis only)"
    if driver:
        desc = _add_driver(prob, options, design_vars)
        for name, bounds in gain_vars.items():
            prob.model.add_design_var(name, **bounds)
        for path in closed_loop_constraints(load_cases):   # the sized law keeps the loop stable
            prob.model.add_constraint(path, upper=0.0, ref=1.0)
        for path in actuator_limit_outputs(load_cases, sized_only=True):  # ... and its surfaces within limits
            prob.model.add_constraint(path, upper=1.0, ref=1.0)
        if panels is not None:
            add_sizing_rules(prob.model, options, panels, design_vars,
                             n if geometry.station_map is None else int(np.max(geometry.station_map)) + 1)
    prob.setup(mode="rev")
    if distributed:  # the main problem holds only section and mass: set the geometry it has
        set_shared_geometry(prob, geometry, section)
    else:
        set_geometry(prob, geometry, section, panels)
        if equivalent_panels is not None:
            prob.set_val("panel_length", equivalent_panels.panel_lengths(span_coordinate(geometry)), units="m")
        for case in load_cases:
            set_case_loads(prob, case, n, f"cases.{case.name}")
    n_dv = n if geometry.station_map is None else int(np.max(geometry.station_map)) + 1
    for w in design_vars:
        prob.set_val(w, np.broadcast_to(options.initial.get(w, options.upper[w]), (n_dv,)))
    return prob, desc


def closed_loop_constraints(load_cases) -> list:
    """``cases.<case>.closed_loop_ks`` of every load case whose law is sized (``gain_design``): the
    closed-loop stability constraint (:class:`~wingmdao.components.closed_loop.ClosedLoopDamping`),
    upper bound 0 (1/s).

    Parameters
    ----------
    load_cases : sequence of LoadCase
        The sizing's load cases.

    Returns
    -------
    list of str
        The constraint paths.
    """
    return [f"cases.{c.name}.closed_loop_ks" for c in load_cases
            if c.aero is not None and c.aero.gain_design and c.aero.control_law is not None]


def actuator_limit_outputs(load_cases, *, sized_only: bool = False) -> list:
    """``cases.<case>.actuator_ks`` of every coupled load case with control surfaces, a law and their
    limits (``CoupledAero.surface_limits``): the KS over the march of the surfaces' deflection and rate
    over their limits (:class:`~wingmdao.components.actuator_limits.ActuatorLimitKS`), <= 1. A
    constraint of the sizing where the case's gains are sized (``sized_only``); with fixed gains a check.

    Parameters
    ----------
    load_cases : sequence of LoadCase
        The sizing's load cases.
    sized_only : bool, optional
        Only the cases whose gains are design variables (``gain_design``).

    Returns
    -------
    list of str
        The output paths.
    """
    return [f"cases.{c.name}.actuator_ks" for c in load_cases
            if c.aero is not None and c.aero.control_law is not None and c.aero.controls is not None
            and getattr(c.aero, "surface_limits", None) is not None and (c.aero.gain_design or not sized_only)]


def _local_subsystem(prob, pathname: str):
    """The subsystem ``pathname`` of the problem's model if this rank holds it, else None."""
    return next((s for s in prob.model.system_iter(recurse=True) if s.pathname == pathname), None)


def actuator_peaks(prob, load_cases) -> dict:
    """``{case: {surface: {"peak_deflection_deg", "max_deflection_deg", "peak_rate_deg_s", "max_rate_deg_s"}}}``
    of the marched cases with :func:`actuator_limit_outputs`, from the problem's state histories.

    Parameters
    ----------
    prob : openmdao.api.Problem
        A run sizing problem.
    load_cases : sequence of LoadCase
        Its load cases.

    Returns
    -------
    dict
        Per case and surface the peaks and the limits.
    """
    out = {}
    for path in actuator_limit_outputs(load_cases):
        name = path.split(".")[1]
        case = next(c for c in load_cases if c.name == name)
        comp = _local_subsystem(prob, f"cases.{name}.actuator_limits")
        if comp is None:   # the case runs on another rank
            continue
        peak = np.max(np.abs(comp.ratios(prob.get_val(f"cases.{name}.actuator_limits.states"))), axis=0)
        lim = np.degrees(np.asarray(case.aero.surface_limits, dtype=float).reshape(-1, 2))
        ns = lim.shape[0]
        out[name] = {srf[0]: {"peak_deflection_deg": float(peak[k] * lim[k, 0]), "max_deflection_deg": float(lim[k, 0]),
                              "peak_rate_deg_s": float(peak[ns + k] * lim[k, 1]), "max_rate_deg_s": float(lim[k, 1])}
                     for k, srf in enumerate(case.aero.controls.surfaces)}
    return out


def turbulence_actuator(prob) -> dict | None:
    """Per control surface of the turbulence constraint (option ``surface_limits``), U_sigma A-bar of its
    deflection and rate over their limits at the last evaluation
    (:meth:`~wingmdao.components.turbulence.TurbulenceStressKS.actuator_ratios`); None without.

    Parameters
    ----------
    prob : openmdao.api.Problem
        A run sizing problem.

    Returns
    -------
    dict or None
        ``{surface: {"deflection": ratio, "rate": ratio}}``.
    """
    for comp in prob.model.system_iter(recurse=True, typ=TurbulenceStressKS):
        return comp.actuator_ratios()
    return None


def _add_driver(prob, options: SizingOptions, design_vars) -> str:
    """The sizing driver of ``options`` on ``prob`` with the walls ``design_vars`` (bounds, scaled by
    ``dv_ref`` or the upper bound), its recording and progress lines; returns its description."""
    prob.driver, desc = make_driver(options.optimizer, maxiter=options.maxiter, tol=options.tol, disp=options.disp)
    for w in design_vars:
        prob.model.add_design_var(w, lower=options.lower[w], upper=options.upper[w],
                                  ref=options.dv_ref.get(w, options.upper[w]) if options.dv_ref else options.upper[w])
    if options.recording:
        add_recorder(prob, options.recording)
    if options.progress:
        prob.driver.add_recorder(ProgressPrinter())
    return desc


def build_stick_problem(geometry: WingGeometry, stick_cases, material, options: SizingOptions,
                        *, driver=True, flutter: dict | None = None, sized_beams=()) -> tuple[om.Problem, str]:
    """The sizing problem of the wing's walls with load cases on the stick model of the whole
    aircraft (:class:`~wingmdao.groups.stick.StickSizing`, ``stick_cases`` a list of
    :class:`~wingmdao.groups.stick.StickCase`); returns ``(problem, driver description)`` as
    :func:`build_problem` (box sections, one process). ``flutter``: options of
    :class:`~wingmdao.components.flutter.StickFlutterDamping` (e.g.
    :func:`wingmdao.cases.pegasus_stick.flutter_options`): adds the constraint flutter_ks <= 0.
    ``sized_beams``: other beams whose sections are sized too
    (:class:`~wingmdao.groups.load_case.SizedBeam`, e.g.
    :func:`wingmdao.cases.pegasus_stick.sized_beams`): their walls are design variables (their own
    bounds, scaled by their upper bound), their ``ks_<beam>_vm`` constraints of every case, and the
    objective is ``total_mass``.

    Parameters
    ----------
    geometry : WingGeometry
        The wing's nodes, sections and station map.
    stick_cases : list of StickCase
        The load cases on the aircraft's stick model.
    material : wingmdao.materials.Material
        The wall material.
    options : SizingOptions
        Bounds, start, driver and scaling settings.
    driver : bool
        Add the optimizer, design variables, objective and constraints; False builds the model only.
    flutter : dict or None
        Options of :class:`~wingmdao.components.flutter.StickFlutterDamping`; None: no flutter
        constraint.
    sized_beams : sequence of SizedBeam
        Beams other than the wing whose sections are sized.
    """
    cases = list(stick_cases)
    sized = list(sized_beams)
    if not cases or not all(isinstance(c, StickCase) for c in cases):
        raise ValueError("stick_cases must be a non-empty list of wingmdao.groups.stick.StickCase")
    _check_options(options, WALL_VARS)
    _check_geometry(geometry, "box")
    _check_initial(options, WALL_VARS, geometry)
    n = geometry.num_nodes
    mass_ref = (options.mass_scale or OBJECTIVE_SCALE * initial_mass(geometry, material, options, "box")) \
        if driver else 1.0
    wing = StickSizing(num_nodes=n, stick_cases=cases, material=material, parallel=False, rho_ks=options.rho_ks,
                       station_map=geometry.station_map, stick_flutter=flutter, sized_beams=sized,
                       add_constraints=driver, add_objective=driver, mass_ref=mass_ref)
    prob = om.Problem(model=wing, comm=_serial_comm(), reports=False)
    desc = "none (analysis only)"
    if driver:
        desc = _add_driver(prob, options, WALL_VARS)
        for b in sized:
            for name in b.design_vars:
                prob.model.add_design_var(name, lower=b.lower, upper=b.upper, ref=b.upper)
    prob.setup(mode="rev")
    set_geometry(prob, geometry, "box")
    set_sized_beams(prob, sized)
    for case in cases:
        set_stick_case(prob, case, f"cases.{case.name}", sized)
    n_dv = n if geometry.station_map is None else int(np.max(geometry.station_map)) + 1
    for w in WALL_VARS:
        prob.set_val(w, np.broadcast_to(options.initial.get(w, options.upper[w]), (n_dv,)))
    return prob, desc


def control_gain_design_vars(load_cases) -> dict:
    """``{"cases.NAME.controller_C"|"controller_D": {"lower", "upper", "ref"}}`` of the coupled cases
    whose control law is sized (``CoupledAero.gain_design``, docs/controls.md): the gains C and D
    (the filter dynamics A, B stay fixed), bounded by +-4 times the largest initial gain (1 when all
    are zero).

    Parameters
    ----------
    load_cases : list of LoadCase
        The load cases; only coupled cases with ``gain_design`` contribute.
    """
    out = {}
    for case in load_cases:
        aero = case.aero
        if aero is None or not getattr(aero, "gain_design", False) or aero.control_law is None:
            continue
        law = aero.control_law
        names = [s.name for s in control_param_specs(aero.controls) if s.name in ("controller_C", "controller_D")]
        size = max([float(np.max(np.abs(m))) for m in (law.C, law.D) if m.size] + [0.0])
        bound = 4.0 * size if size > 0 else 1.0
        for nm in names:
            out[f"cases.{case.name}.{nm}"] = {"lower": -bound, "upper": bound, "ref": bound}
    return out


def shared_turbulence_gains(load_cases, turbulence: dict, gain_vars: dict) -> tuple:
    """One law for the gust case whose gains are sized and the turbulence constraint: ``(turbulence
    options with gains_from_case, design variables)``, the gains' design variables moved to
    ``law_gains.<name>`` (an IndepVarComp of :class:`~wingmdao.groups.wing.WingSizing` feeding both).
    ValueError for more than one sized case or a law that differs from the constraint's.

    Parameters
    ----------
    load_cases : sequence of LoadCase
        The sizing's load cases.
    turbulence : dict
        Options of :class:`~wingmdao.components.turbulence.TurbulenceStressKS` with ``control_law``.
    gain_vars : dict
        :func:`control_gain_design_vars` of ``load_cases``.

    Returns
    -------
    tuple
        ``(turbulence options, design variables {name: bounds})``.
    """
    cases = sorted({name.split(".")[1] for name in gain_vars})
    if len(cases) != 1:
        raise ValueError(f"--turbulence with --size-gains: {len(cases)} load cases size their own gains "
                         f"({', '.join(cases)}); the turbulence constraint shares the gains of one (a single gust)")
    case = next(c for c in load_cases if c.name == cases[0])
    law, mine = case.aero.control_law, turbulence["control_law"]
    if tuple(law.outputs) != tuple(mine.outputs) or any(not np.array_equal(getattr(law, k), getattr(mine, k))
                                                         for k in "ABCD"):
        raise ValueError(f"--turbulence with --size-gains: the law of load case {case.name!r} differs from the "
                         "turbulence constraint's; give one alleviation file")
    moved = {f"law_gains.{name.split('.')[-1]}": bounds for name, bounds in gain_vars.items()}
    return {**turbulence, "gains_from_case": case.name}, moved


def control_gains(prob, load_cases) -> dict:
    """``{case: {"outputs": [...], "controller_A": ..., ...}}``: the control laws' matrices of the
    coupled cases with a law, as the problem holds them (sized or not).

    Parameters
    ----------
    prob : openmdao.api.Problem
        A set-up sizing problem.
    load_cases : list of LoadCase
        Its load cases; coupled cases with a control law are reported.
    """
    out = {}
    for case in load_cases:
        aero = case.aero
        if aero is None or getattr(aero, "control_law", None) is None:
            continue
        vals = {s.name: np.asarray(prob.get_val(f"cases.{case.name}.{s.name}")).tolist()
                for s in control_param_specs(aero.controls)}
        out[case.name] = {"outputs": list(aero.control_law.outputs), "sized": bool(aero.gain_design), **vals}
    return out


def _serial_comm():
    """OpenMDAO's serial communicator when it runs without MPI (``openmdao.utils.mpi.MPI`` is None:
    not under mpirun), else None (the default). ``om.Problem()`` imports mpi4py whenever it is
    installed, ~1.2 s of a 20 s gust sizing here, although it then runs serially."""
    return FakeComm() if MPI is None else None


def initial_mass(geometry: WingGeometry, material, options: SizingOptions, section: str = "box",
                 panels: PanelLayout | None = None) -> float:
    """Structural mass of the initial design (kg), to scale the objective (:data:`OBJECTIVE_SCALE`).

    Computed directly (App. F.1 frustum volumes of the section areas, Eq. F.1-F.5 for the box,
    w h for the solid rectangle), without the non-structural mass, as the sizing model's
    section and mass components would for the initial design variables.

    Parameters
    ----------
    geometry : WingGeometry
        The wing's nodes, sections and station map.
    material : wingmdao.materials.Material
        The wall material (density).
    options : SizingOptions
        Its ``initial`` values (else upper bounds) are the initial design.
    section : str
        Section kind (``"box"``, ``"solid"``, ``"stiffened"``).
    panels : PanelLayout or None
        The stiffened panels and ribs (section ``"stiffened"``).
    """
    design_vars = SECTION_KINDS[section]["design_vars"]
    dv = station_design(geometry, initial_design(options, design_vars), design_vars)
    if section in BOX_KINDS:
        area = box_area(np.asarray(geometry.width, dtype=float), np.asarray(geometry.height, dtype=float),
                        *(dv[w] for w in WALL_VARS), stringers=_stringers(dv, panels))
    else:
        area = dv["width"] * dv["height"]
    return beam_mass(area, geometry.node_positions, material.rho)


#: adjacency limits of the sizing rules between neighbouring design stations (m): thicknesses
#: and stiffener heights
ADJACENCY_THICKNESS, ADJACENCY_HEIGHT = 2.5e-3, 10e-3


def add_sizing_rules(model, options: SizingOptions, panels: PanelLayout, design_vars, n_dv: int) -> None:
    """The stiffened panels' sizing rules as linear constraints (components.panels.SizingRules):
    web aspect 5 <= h/ts <= 30, ts <= 15 t_skin, and neighbouring stations within 2.5 mm
    (thicknesses) and 10 mm (stiffener heights).

    Parameters
    ----------
    model : openmdao.api.Group
        The problem's model the constraint component is added to.
    options : SizingOptions
        Bounds and scaling settings.
    panels : PanelLayout
        The stiffened panels.
    design_vars : sequence of str
        The design variable names.
    n_dv : int
        Number of design stations.
    """
    ref = options.upper.get("t_upper_skin", 0.01)
    for name in ("stiffener_aspect_min", "stiffener_aspect_max", "stiffener_over_skin"):
        model.add_constraint(f"rules.{name}", upper=0.0, linear=True, ref=ref)
    for name in design_vars if n_dv > 1 else ():
        limit = ADJACENCY_HEIGHT if name.startswith("h_") else ADJACENCY_THICKNESS
        model.add_constraint(f"rules.adjacency_{name}", lower=-limit, upper=limit, linear=True, ref=limit)


def set_geometry(prob: om.Problem, geometry: WingGeometry, section: str = "box",
                 panels: PanelLayout | None = None) -> None:
    """Set the wing's geometry inputs (node positions and angles, section sizes, panel lengths, section map) on a set-up problem.

    Parameters
    ----------
    prob : openmdao.api.Problem
        A set-up sizing problem.
    geometry : WingGeometry
        The wing's nodes, sections and station map.
    section : str
        Section kind; box kinds also set the box width and height (m).
    panels : PanelLayout or None
        The stiffened panels; sets the panel lengths (m).
    """
    n = geometry.num_nodes
    prob.set_val("node_positions", geometry.node_positions, units="m")
    prob.set_val("node_euler_angles", geometry.node_euler_angles, units="rad")
    if section in BOX_KINDS:
        prob.set_val("width", geometry.width, units="m")
        prob.set_val("height", geometry.height, units="m")
    if panels is not None:
        prob.set_val("panel_length", panels.panel_lengths(span_coordinate(geometry)), units="m")
    if geometry.section_to_csn is not None:
        prob.set_val("section_to_csn", geometry.section_to_csn)
    else:
        prob.set_val("section_to_csn", np.broadcast_to(np.eye(3), (n, 3, 3)))
    if geometry.nonstructural_mass_per_length is not None:
        prob.set_val("nonstructural_mass_per_length", geometry.nonstructural_mass_per_length, units="kg/m")


def run_sizing(prob: om.Problem, load_cases, driver_desc: str, *, optimize=True, section="box", panels=None,
               geometry=None, material=None) -> dict:
    """Run the driver (or the model) and return the JSON-ready summary.

    Parameters
    ----------
    prob : openmdao.api.Problem
        A set-up sizing problem with its geometry set.
    load_cases : list of LoadCase
        Its load cases.
    driver_desc : str
        The driver's description, copied into the summary.
    optimize : bool
        Run the driver; False runs the model once.
    section : str
        Section kind.
    panels : PanelLayout or None
        The stiffened panels (section ``"stiffened"``).
    geometry : WingGeometry or None
        The wing, for the panel and rib summaries.
    material : wingmdao.materials.Material or None
        The wall material, for the panel and rib summaries.
    """
    t0 = _time.perf_counter()
    if optimize:
        outcome = prob.run_driver()
        success = bool(outcome.success) if hasattr(outcome, "success") else not bool(outcome)
    else:
        prob.run_model()
        success = True
    wall = _time.perf_counter() - t0
    return summarize(prob, load_cases, driver_desc, success=success, wall_s=wall, section=section, panels=panels,
                     geometry=geometry, material=material)


def station_values(prob, name: str) -> np.ndarray:
    """Per-station values of design variable ``name`` (expanded when stations share variables).

    Parameters
    ----------
    prob : openmdao.api.Problem
        A sizing problem.
    name : str
        Design variable name.
    """
    try:
        return prob.get_val(f"{name}_station", units="m")
    except KeyError:
        return prob.get_val(name, units="m")


def summarize(prob, load_cases, driver_desc, *, success=True, wall_s=0.0, section="box", panels=None,
              geometry=None, material=None) -> dict:
    """JSON-ready summary of a sizing problem's current design: mass, design variables per station, KS values, driver and time.

    Parameters
    ----------
    prob : openmdao.api.Problem
        A run sizing problem.
    load_cases : list of LoadCase
        Its load cases.
    driver_desc : str
        The driver's description.
    success : bool
        Whether the driver converged.
    wall_s : float
        Wall-clock time of the run (s).
    section : str
        Section kind.
    panels : PanelLayout or None
        The stiffened panels (section ``"stiffened"``).
    geometry : WingGeometry or None
        The wing, for the panel and rib summaries.
    material : wingmdao.materials.Material or None
        The wall material, for the panel and rib summaries.

    Returns
    -------
    dict
        The summary.
    """
    ks = {c.name: {f: float(prob.get_val(f"cases.{c.name}.ks_{f}")[0]) for f in case_families(c, section, panels)}
          for c in load_cases}
    out = {
        "success": bool(success),
        "mass_kg": float(prob.get_val("mass", units="kg")[0]),
        **({"thickness": {w[2:]: station_values(prob, w).tolist() for w in WALL_VARS}} if section in BOX_KINDS
           else {"width": station_values(prob, "width").tolist(),
                 "height": station_values(prob, "height").tolist()}),
        "ks": ks,
        "driver": driver_desc,
        "wall_s": float(wall_s),
    }
    stats = getattr(prob.driver, "result", None)
    scipy_res = getattr(prob.driver, "optimize_result", None)  # wingmdao.optimize.BackoffSLSQPDriver
    if scipy_res is not None and hasattr(scipy_res, "nit"):
        out["iterations"] = int(scipy_res.nit)
        out["message"] = str(scipy_res.message)
    else:
        out["iterations"] = int(getattr(stats, "iter_count", 0) or 0)
    failed = getattr(prob.driver, "failed_evaluations", None)
    if failed is not None:  # designs whose analysis failed; SLSQP backed off from them
        out["failed_evaluations"] = failed
    out["function_evaluations"] = int(getattr(stats, "model_evals", 0) or 0)
    out["gradient_evaluations"] = int(getattr(stats, "deriv_evals", 0) or 0)
    worst = max((v for d in ks.values() for v in d.values()), default=np.nan)
    out["active_constraints"] = [f"{c}.{f}" for c, d in ks.items() for f, v in d.items() if v > -1e-3]
    for path in closed_loop_constraints(load_cases):
        value = float(np.asarray(prob.get_val(path)).ravel()[0])
        out.setdefault("closed_loop_ks", {})[path.split(".")[1]] = value
        case = next(c for c in load_cases if c.name == path.split(".")[1])
        out.setdefault("closed_loop_margin", {})[case.name] = float(case.aero.closed_loop_margin)   # 1/s
        if value > -1e-3:
            out["active_constraints"].append(path)
    for name in ("flutter_ks", "turbulence_ks"):
        value = _constraint_value(prob, name)
        if value is not None:
            out[name] = value
            if value > -1e-3:
                out["active_constraints"].append(name)
    constrained = set(prob.model.get_constraints())
    for path in actuator_limit_outputs(load_cases):  # <= 1; constraints where the gains are sized
        if _local_subsystem(prob, path.rsplit(".", 1)[0] + ".actuator_limits") is None:
            continue   # the case runs on another rank
        value = float(np.asarray(prob.get_val(path)).ravel()[0])
        out.setdefault("actuator_ks", {})[path.split(".")[1]] = value
        if path in constrained and value > 1.0 - 1e-3:
            out["active_constraints"].append(path)
    if "actuator_ks" in out:
        out["actuator_peaks"] = actuator_peaks(prob, load_cases)
    value = _constraint_value(prob, "turbulence_actuator_ks")
    if value is not None:
        out["turbulence_actuator_ks"] = value
        out["turbulence_actuator"] = turbulence_actuator(prob)
        if "turbulence_actuator_ks" in constrained and value > 1.0 - 1e-3:
            out["active_constraints"].append("turbulence_actuator_ks")
    out["max_ks"] = float(worst)
    if panels is not None:
        out["panels"] = panel_summary(prob, load_cases, panels)
        out["ribs"] = rib_summary(prob, load_cases, panels, geometry, material)
        out["mass_breakdown_kg"] = mass_breakdown(prob, geometry, panels, rib_mass=out["ribs"]["mass_kg"])
        out["mass_kg"] = float(sum(out["mass_breakdown_kg"].values()))
    return out


def _constraint_value(prob, name):
    """The value of the model's constraint ``name`` (flutter_ks, turbulence_ks) when it has one, else None."""
    try:
        return float(prob.get_val(name)[0])
    except KeyError:
        return None


def presize_fully_stressed(prob, load_cases, geometry: WingGeometry, options: SizingOptions,
                           passes: int, *, progress: bool = False, sized_beams=()) -> dict:
    """Fully stressed design (FSD) passes that give the optimizer a near-feasible start.

    Per design station k, r_k = max over load cases, time steps, stations mapped to k and
    von Mises points of sigma_vm / sigma_allow (= g_vm + 1, Sec. 4.4.2); all four walls are
    scaled t_k <- clip(t_k r_k, bounds), the classical stress-ratio resize for sigma ~ 1/t.
    Why: SLSQP linearises sigma/sigma_allow - 1 (hyperbolic in t) and from an over-designed
    start steps deep into the infeasible region, then needs ~100 evaluations to climb back
    (PEGASUS: 95 -> 59 maneuver iterations, 99 -> 53 gust iterations, same optimum).
    Box sections and load cases with the ``vm`` family only. A flutter constraint is paused in
    these passes (:func:`~wingmdao.components.flutter.paused_flutter`: the optimizer never sees
    their designs). Returns the pass history.

    Parameters
    ----------
    prob : openmdao.api.Problem
        A set-up sizing problem with its geometry set; its design variables are updated.
    load_cases : list of LoadCase
        Its load cases (those with the ``vm`` family are used).
    geometry : WingGeometry
        The wing; its ``station_map`` maps nodes to design stations.
    options : SizingOptions
        The bounds the resized thicknesses are clipped to.
    passes : int
        Number of passes; 0 or less does nothing.
    progress : bool
        Print a line per pass.
    sized_beams : sequence of SizedBeam
        Other beams of a stick sizing whose walls are resized the same way, each by the ratio of
        its own stress (``cases.<case>.<beam>_stress.g_vm``) at its stations, within its bounds.
    """
    if passes <= 0:
        return {"passes": 0}
    cases = [c for c in load_cases if "vm" in c.families]
    if not cases:
        raise ValueError("presize: needs at least one load case with the 'vm' stress family")
    smap = np.arange(geometry.num_nodes) if geometry.station_map is None else np.asarray(geometry.station_map)
    t0 = _time.perf_counter()
    history = []
    for k in range(int(passes)):
        with paused_flutter(prob):   # strength only: no flutter eigen-analyses
            prob.run_model()
        ratio = np.zeros(int(smap.max()) + 1)
        for case in cases:
            g = np.asarray(prob.get_val(f"cases.{case.name}.stress.g_vm"))
            np.maximum.at(ratio, smap, (g + 1.0).reshape(-1, g.shape[-2], g.shape[-1]).max(axis=(0, 2)))
        for w in WALL_VARS:
            prob.set_val(w, np.clip(prob.get_val(w) * ratio, options.lower[w], options.upper[w]))
        for b in sized_beams:
            r = np.zeros(b.num_nodes)
            for case in cases:
                g = np.asarray(prob.get_val(f"cases.{case.name}.{b.name}_stress.g_vm"))
                r = np.maximum(r, (g + 1.0).max(axis=(0, 2)))
            for w in b.design_vars:
                prob.set_val(w, np.clip(prob.get_val(w) * r, b.lower, b.upper))
        history.append({"mass_kg": float(prob.get_val("mass", units="kg")[0]), "max_ratio": float(ratio.max())})
        if progress:
            print(f"  presize (fully stressed) pass {k + 1}/{passes}: mass {history[-1]['mass_kg']:.2f} kg "
                  f"(before resize), max sigma/sigma_allow {ratio.max():.4f}", flush=True)
    return {"passes": int(passes), "history": history, "wall_s": _time.perf_counter() - t0}


def size_case(setup, *, optimize: bool = True, parallel: bool | None = None, comm=None):
    """Build and run a :class:`wingmdao.cases.CaseSetup`; returns ``(problem, result dict)``.

    With ``setup.options.presize > 0`` (and a box section) fully stressed design passes
    (:func:`presize_fully_stressed`) set the optimizer's starting point; their time is in ``wall_s``.
    ``comm``: None = the MPI world when run under ``mpirun -n P > 1`` (cases spread over the
    ranks, :mod:`wingmdao.parallel`), else serial; False = serial.

    Parameters
    ----------
    setup : wingmdao.cases.CaseSetup
        The case's geometry, load cases, material, options and constraints.
    optimize : bool
        Run the optimizer; False analyses the initial design.
    parallel : bool or None
        Passed to :func:`build_problem`.
    comm : MPI communicator or bool or None
        See above.
    """
    if comm is None:
        comm = world_comm()
    mine = setup.load_cases
    if comm is not None and comm is not False and comm.size > 1:
        mine = [setup.load_cases[i] for i in assign_cases(setup.load_cases, comm.size)[comm.rank]]
    check_memory(mine, setup.geometry.num_nodes)  # before any solve
    prob, desc = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options,
                               driver=optimize, parallel=parallel, section=setup.section, comm=comm,
                               flutter=setup.flutter, panels=setup.panels, turbulence=setup.turbulence)
    return prob, presize_and_size(prob, setup, desc, optimize=optimize)


def presize_and_size(prob, setup, desc: str, *, optimize: bool = True, sized_beams=()) -> dict:
    """The fully stressed presizing passes of ``setup.options.presize`` (box sections, when
    optimizing; :func:`presize_fully_stressed`), then :func:`run_sizing`; the result dict has the
    passes' time in ``wall_s`` and their history in ``presize``.

    Parameters
    ----------
    prob : openmdao.api.Problem
        The set-up sizing problem of ``setup``.
    setup : wingmdao.cases.CaseSetup
        The case's geometry, load cases, material and options.
    desc : str
        The driver's description.
    optimize : bool
        Presize and run the optimizer; False runs the model once.
    sized_beams : sequence of SizedBeam
        Other beams of a stick sizing (:func:`build_stick_problem`): presized with the wing and
        summarised by :func:`sized_beam_summary`.
    """
    pre = {"passes": 0}
    if optimize and setup.options.presize > 0 and setup.section in BOX_KINDS:
        pre = presize_fully_stressed(prob, setup.load_cases, setup.geometry, setup.options,
                                     setup.options.presize, progress=setup.options.progress, sized_beams=sized_beams)
    result = run_sizing(prob, setup.load_cases, desc, optimize=optimize, section=setup.section, panels=setup.panels,
                        geometry=setup.geometry, material=setup.material)
    if sized_beams:
        sized_beam_summary(prob, setup.load_cases, sized_beams, result)
    if pre["passes"]:
        result["wall_s"] += pre["wall_s"]
        result["presize"] = pre
    return result


def sized_beam_summary(prob, load_cases, sized_beams, result: dict) -> dict:
    """Add the sized beams of a stick sizing to its summary ``result`` (:func:`summarize`):
    ``beams`` ({beam: ``mass_kg`` of its walls and its ``thickness`` per wall and station}, the
    wing's included), ``total_mass_kg``, each case's ``ks`` of ``<beam>_vm``, and these in
    ``active_constraints`` (within 1e-3 of 0) and ``max_ks``.

    Parameters
    ----------
    prob : openmdao.api.Problem
        The run problem of :func:`build_stick_problem`.
    load_cases : sequence of StickCase
        Its load cases.
    sized_beams : sequence of SizedBeam
        Its sized beams.
    result : dict
        The summary; updated in place.

    Returns
    -------
    dict
        ``result``.
    """
    beams = {"wing": {"mass_kg": result["mass_kg"]}}
    for b in sized_beams:
        beams[b.name] = {"mass_kg": float(prob.get_val(f"{b.name}_mass", units="kg")[0]),
                         "thickness": {w: prob.get_val(f"{b.name}_{w}", units="m").tolist() for w in b.walls}}
    result["beams"] = beams
    result["total_mass_kg"] = float(prob.get_val("total_mass", units="kg")[0])
    for c in load_cases:
        for b in sized_beams:
            value = float(prob.get_val(f"cases.{c.name}.ks_{b.name}_vm")[0])
            result["ks"].setdefault(c.name, {})[f"{b.name}_vm"] = value
            if value > -1e-3:
                result.setdefault("active_constraints", []).append(f"{c.name}.{b.name}_vm")
            result["max_ks"] = max(result.get("max_ks", value), value)
    return result


def release_derivative_storage(prob) -> int:
    """Drop what the last derivative computation stored for reuse at the same design point: the
    time histories' linearizations (Jacobian blocks of the adjoint,
    :class:`~wingmdao.timemarch.adjoint.LinearizedHistory`) and the pointwise components' cached
    Jacobian chunks, and hand the freed heap back to the operating system
    (:func:`wingmdao.utils.memory.return_freed_memory`). Results and outputs are untouched; a later
    derivative computation linearizes again. Called after a sizing, before the flutter search
    (``wingmdao size``), so its memory does not stack on the adjoint's. Returns the number of
    components released.

    Parameters
    ----------
    prob : openmdao.api.Problem
        A sizing problem after a derivative computation.
    """
    released = 0
    for system in prob.model.system_iter(recurse=True, include_self=False):
        if getattr(system, "_lin", None) is not None:
            system._lin = system._lin_inputs = None
            released += 1
        if getattr(system, "_jac_values", None) is not None:
            system._jac_point, system._jac_values = None, None
            released += 1
    return_freed_memory()
    return released


def turbulence_loads(prob) -> dict | None:
    """The 25.341(b) loads of the analysed design of a sizing with the turbulence constraint, for the
    stress office and the potato plots: the constraint's own model (its inputs at the design, its
    airspeed, stations and structural damping; :class:`~wingmdao.components.turbulence.TurbulenceStressKS`)
    analysed by :func:`wingmdao.loads.turbulence_analysis.turbulence_analysis` on the constraint's
    frequency range. None without the constraint.

    Parameters
    ----------
    prob : openmdao.api.Problem
        A sizing problem of :func:`build_problem` after its run.

    Returns
    -------
    dict or None
        ``u_sigma_m_s`` (m/s TAS); per station of ``bending_moment`` (M_c) and ``torsion`` (M_s) in
        each station's csn frame, ``one_g`` (N m) and ``a_bar`` (N m per m/s); ``bending_torsion_correlation``
        (per station); ``a_bar_load_factor`` (1 per m/s); ``stress_ratio`` per station, the
        largest corner design stress |s_1g +/- U_sigma A-bar| over ``sigma_allow`` (the constraint's
        pointwise ratio, before its KS).
    """
    comps = list(prob.model.system_iter(recurse=True, typ=TurbulenceStressKS))
    if not comps:
        return None
    comp = comps[0]
    opts = comp.options
    values = {s.name: np.asarray(prob.get_val(f"{comp.pathname}.{s.name}")).reshape(s.shape) for s in comp.specs}
    values["airspeed"] = (float(prob.get_val(f"{comp.pathname}.airspeed")[0]) if opts["airspeed_input"]
                          else opts["airspeed"])
    if opts["aircraft_mass_input"]:
        raise ValueError("turbulence_loads: a constraint with aircraft_mass_input takes the mass from its input; "
                         "analyse it with wingmdao.loads.turbulence_analysis directly")
    gm = gust_model_from_parameters(comp.system, values, x_stations=opts["x_stations"], gravity=opts["gravity"])
    walls = np.column_stack([np.asarray(prob.get_val(f"{comp.pathname}.{w}"), dtype=float) for w in WALL_VARS])
    S = stress_matrices(opts["width"], opts["height"], walls, opts["section_to_csn"])
    res = turbulence_analysis(gm, opts["u_sigma"], f_max=opts["f_max"], n_base=opts["n_base"], stress_matrices=S)
    corner = slice(0, 4)  # the corner axial stresses the constraint bounds
    up = np.abs(np.asarray(res["design_loads"]["stress"]["up"])[:, corner])
    down = np.abs(np.asarray(res["design_loads"]["stress"]["down"])[:, corner])
    return {"u_sigma_m_s": float(opts["u_sigma"]),
            "stress_ratio": (np.maximum(up, down).max(axis=1) / opts["sigma_allow"]).tolist(),
            "bending_moment": {"one_g": res["design_loads"]["bending_moment"]["one_g"],
                               "a_bar": res["a_bar"]["bending_moment"]},
            "torsion": {"one_g": res["design_loads"]["torsion"]["one_g"], "a_bar": res["a_bar"]["torsion"]},
            "bending_torsion_correlation": res["correlation"]["bending_torsion"],
            "a_bar_load_factor": res["a_bar"]["load_factor"]}


def case_responses(prob, setup, togw_lb) -> dict:
    """Per load case of the analysed design: peak load factor (lift of both halves / TOGW weight)
    and peak root bending moment (N m), :func:`wingmdao.aero.coupled.load_case_response`.

    Parameters
    ----------
    prob : openmdao.api.Problem
        An analysed sizing problem.
    setup : wingmdao.cases.CaseSetup
        The case: its load cases and geometry.
    togw_lb : float
        Take-off gross weight (lb), the load factor's reference.
    """
    out = {}
    for case in setup.load_cases:
        r = load_case_response(prob, case, setup.geometry.num_nodes, togw_lb * LB * G0)
        out[case.name] = {"peak_load_factor": r["peak_load_factor"],
                          "peak_root_bending_moment_n_m": r["peak_root_bending_moment"]}
        if case.symmetric is not None:  # both wings: symmetric ± increment, root M_c
            mc = np.asarray(prob.get_val(f"cases.{case.name}.combined_loads.M_csn", units="N*m"))[:, 0, 0]
            out[case.name]["combined_root_bending_moment_max_min_n_m"] = [float(mc.max()), float(mc.min())]
        trim = maneuver_elevator_trim(prob, case, setup.geometry.num_nodes, togw_lb * LB * G0)
        if trim is not None:
            out[case.name]["elevator_trim"] = trim
    return out


def maneuver_elevator_trim(prob, case, num_nodes: int, weight: float) -> dict | None:
    """The elevator trim of an analysed static maneuver trimmed with the tail (a coupled case with
    ``pitch`` and ``elevator_effectiveness``, one instant): :func:`wingmdao.loads.maneuver_trim.elevator_trim`
    at the case's state and parameters (``as_dict``: angle of attack, the 1 g stabiliser setting,
    elevator angle, tail and wing lift); None for any other case.

    Parameters
    ----------
    prob : openmdao.api.Problem
        The sizing problem after its run.
    case : LoadCase
        The load case (``cases.<name>``).
    num_nodes : int
        Beam nodes.
    weight : float
        Aircraft weight W (N).

    Returns
    -------
    dict or None
        The trim, JSON-ready.
    """
    aero = case.aero
    if aero is None or not aero.pitch or not aero.elevator_effectiveness or case.time.size != 1:
        return None
    path = f"cases.{case.name}"
    system = cached_aeroelastic_system(int(num_nodes), plunge=True, trim=True, pitch=True,
                                       aero_theory=aero.residual_theory, controls=aero.controls)

    def value(name):  # the beam input under the case's promoted name or the beam's own
        try:
            return np.asarray(prob.get_val(f"{path}.{name}"))
        except KeyError:
            return np.asarray(prob.get_val(f"{path}.beam.{name}"))

    values = {s.name: value(s.name) for s in system.param_specs}
    p = pack(system.param_specs, values)
    x = np.asarray(prob.get_val(f"{path}.states")).ravel()
    n = float(np.ravel(values["trim_lift"])[0]) / weight
    return elevator_trim(system, p, n, elevator_effectiveness=aero.elevator_effectiveness, weight=weight,
                         state=x).as_dict()


def partial_result(prob, setup, desc, recording, interrupted=True) -> dict:
    """The result of a sizing stopped by Ctrl-C (or a failed analysis): the design at the last
    evaluation and, from the recording, ``best_design`` (the lowest objective with every KS
    constraint <= 0, :func:`wingmdao.report.best_design`); ``success`` false.

    Parameters
    ----------
    prob : openmdao.api.Problem
        The interrupted sizing problem.
    setup : wingmdao.cases.CaseSetup
        The case: its load cases, section, panels, geometry and material.
    desc : str
        The driver's description.
    recording : str or None
        Path of the driver's recording, searched for the best feasible design.
    interrupted : bool
        Copied to the result's ``interrupted`` flag.
    """

    try:
        result = summarize(prob, setup.load_cases, desc, success=False, section=setup.section,
                           panels=setup.panels, geometry=setup.geometry, material=setup.material)
    except Exception as exc:  # the interrupt may have come before the first evaluation finished
        result = {"success": False, "message": f"no evaluated design ({exc})"}
    result.update(success=False, interrupted=interrupted)
    if recording and os.path.exists(recording):
        try:
            hist = read_history(recording)
        except ValueError:
            return result
        best = best_design(hist)
        if best is not None:
            result["best_design"] = best
    return result
