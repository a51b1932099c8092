"""The PEGASUS wing of the beam-against-CalculiX comparison (``wingmdao verify pegasus``,
``wingmdao export pegasus``; docs/verification-calculix.md): the box sections and beam parameters of
a design, the maneuver loads on the beam and lumped on the FE model's span lines, and the
equivalent static loads of the peak instant of the case's 25.341 gust."""

from __future__ import annotations

import numpy as np

from wingmdao.beam.static import march_line_loads
from wingmdao.cases import pegasus as case
from wingmdao.cases.planform import FT, G0, LB, wing_geometry
from wingmdao.fe.box_model import BoxSections
from wingmdao.fe.nastran_aero import FlightData, LiftingPanel, aeroelastic_deck
from wingmdao.fe.wing_loads import lumped_line_loads, point_weights
from wingmdao.loads.atmosphere import altitude_ft_to_m, density, mach_to_tas
from wingmdao.loads.gust import gust_line_loads
from wingmdao.loads.maneuver import maneuver_line_loads
from wingmdao.materials import ALUMINIUM
from wingmdao.section.box import WALL_NAMES, beam_data, box_properties

#: Sized-like walls (upper skin, lower skin, front spar, rear spar), m: section_models.compare_1g's.
DEFAULT_WALLS = (0.004, 0.004, 0.005, 0.004)


def default_walls(num_stations: int = 20) -> dict:
    """The walls of the comparison without a ``--design`` (:data:`DEFAULT_WALLS` at every station).

    Parameters
    ----------
    num_stations : int, optional
        Number of stations.

    Returns
    -------
    dict
        Wall name -> (num_stations,) thicknesses (m).
    """
    return {k: np.full(num_stations, v) for k, v in zip(WALL_NAMES, DEFAULT_WALLS)}


def beam_params(geo, walls, material):
    """Beam parameters of the box per station (``box_properties``) with the engines' mass.

    Parameters
    ----------
    geo : WingGeometry
        The wing geometry.
    walls : dict
        Wall name -> (n,) thicknesses (m).
    material : Material
        Isotropic material.

    Returns
    -------
    tuple
        (beam parameters, structural mass per length (n,) kg/m).
    """

    rows = [beam_data(box_properties(geo.width[k], geo.height[k], *(walls[w][k] for w in
                                     ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")), material),
                      material) for k in range(geo.num_nodes)]
    stack = lambda key: np.array([np.asarray(r[key], float) for r in rows])   # noqa: E731
    structural = stack("mass_per_length")
    params = {"node_positions": geo.node_positions, "node_euler_angles": geo.node_euler_angles,
              "stiffness_csn": stack("stiffness_csn"), "compliance_csn": stack("compliance_csn"),
              "tension_axis": np.column_stack([stack("c_ea"), stack("n_ea")]),
              "shear_center": np.column_stack([stack("c_sc"), stack("n_sc")]),
              "mass_per_length": structural + geo.nonstructural_mass_per_length,
              "mass_center": np.column_stack([stack("c_cg"), stack("n_cg")]),
              "inertia_per_length": stack("inertia_per_length")}
    return params, structural


def engine_stations(case, geo):
    """Each engine's mass at the span coordinate of the station nearest to it.

    Parameters
    ----------
    case : module
        The PEGASUS case module (``ENGINES``, ``GUST``).
    geo : WingGeometry
        The wing geometry.

    Returns
    -------
    list of tuple
        ``(y, mass)`` of each engine at its nearest station (m, kg).
    """
    y = geo.span_coordinate
    return [(float(y[int(np.argmin(abs(y - ym)))]), m) for m, ym in case.ENGINES]


def fe_loads(case, geo, sec, model, line, structural, n_load, G0):
    """Station loads on the FE lines: lift and torsion, self weight, engine weights (n g).

    Parameters
    ----------
    case : module
        The PEGASUS case module (``ENGINES``, ``GUST``).
    geo : WingGeometry
        The wing geometry.
    sec : BoxSections
        Streamwise sections of the FE box.
    model : ShellBox
        The FE model.
    line : LineLoads
        Aerodynamic line loads at the beam nodes.
    structural : numpy.ndarray
        (n,) structural mass per length (kg/m).
    n_load : float
        Load factor (-).
    G0 : float
        Gravitational acceleration (m/s^2).

    Returns
    -------
    list of tuple
        ``(y, centre, F, M)`` station loads.
    """

    ys = model.span_y[::2]
    y = geo.span_coordinate
    weight = np.zeros((y.size, 3))
    weight[:, 2] = -n_load * G0 * structural
    loads = lumped_line_loads(sec, ys, y, line.force_per_length + weight, line.moment_per_length)
    return loads + point_weights(sec, engine_stations(case, geo), gravity=n_load * G0)


def gust_peak_loads(case, geo, params, *, dt=0.01, t_final=None, gust_start=0.1):
    """Equivalent static loads of the instant of peak root bending of the case's 14 CFR 25.341
    1-cos gust (``GUST``: altitude, Mach, U_ref, gradient H; U_ds = U_ref (H/350 ft)^(1/6) EAS),
    on the beam of ``params`` (the --design), root clamped: the sizing's ``--aero strip`` loads
    (:func:`wingmdao.loads.gust.gust_line_loads`, quasi-steady strip theory on the Schrenk 1 g
    spanload, penetration delay) marched with BDF2 (:func:`wingmdao.timemarch.bdf.march`).

    At the instant t* of the largest ``|M_x|`` at the root the loads are, per beam node: the
    aerodynamic force and moment per length of t*, and the inertial load -m a* per length, a* the
    BDF2 acceleration (rate of the velocity state u) of the node at t*, m the mass per length of
    the beam (structural plus the engines' non-structural mass); gravity (1 g, -z) acts as well.
    D'Alembert's principle makes the beam in static equilibrium under these loads the dynamic
    state at t*, up to the inertia left out: the rotary inertia and the mass-centre offset of
    the translational inertia (their size is the ``static_vs_dynamic`` difference reported).

    Parameters
    ----------
    case : module
        The PEGASUS case module (``ENGINES``, ``GUST``).
    geo : WingGeometry
        The wing geometry.
    params : dict
        Beam parameters of the design.
    dt : float, optional
        Time step (s).
    t_final : float or None, optional
        End of the march (s); None for the case's ``GUST["t_final"]``.
    gust_start : float, optional
        Time the gust front reaches the wing (s).

    Returns
    -------
    dict
        The peak's time, line loads and nodal accelerations.
    """

    pf, g = case.PLANFORM, case.GUST
    _, chord, axis_frac = wing_geometry(pf, case.ENGINES)
    alt = float(altitude_ft_to_m(g["altitude_ft"]))
    V = float(mach_to_tas(g["mach"], alt))
    H_ft = g["gradient_ft"]
    u_eas = g["u_ref_fps"] * FT * (H_ft / 350.0) ** (1.0 / 6.0)
    r0 = params["node_positions"]
    n = r0.shape[0]
    fus = pf.root_rib * pf.semi_span
    steady = maneuver_line_loads(r0, chord, axis_frac, case.TOGW_LB * LB * G0, 1.0, semi_span=pf.semi_span,
                                 fuselage_half_width=fus)
    t = np.arange(0.0, (t_final or g["t_final"]) + 0.5 * dt, dt)
    loads = gust_line_loads(r0, chord, axis_frac, t, gust_gradient_m=H_ft * FT, u_ds_eas=u_eas, airspeed_tas=V,
                            altitude_m=alt, gust_start_time=gust_start, steady=steady, fuselage_half_width=fus)
    hist = march_line_loads(params, t, loads.force_per_length, loads.moment_per_length, (0.0, 0.0, -G0))
    X = hist.states.reshape(t.size, n, 18)
    acc = hist.rates.reshape(t.size, n, 18)[:, :, 12:15]
    k = int(np.argmax(np.abs(X[:, 0, 9])))
    return {"time": float(t[k]), "index": k, "dt": dt, "gust_start": gust_start, "u_ds_eas": float(u_eas),
            "airspeed_tas": V, "gradient_ft": H_ft, "root_bending_moment": X[:, 0, 9],
            "force_per_length": loads.force_per_length[k], "moment_per_length": loads.moment_per_length[k],
            "acceleration": acc[k], "dynamic_displacement": X[k, :, :3] - r0, "dynamic_theta": X[k, :, 3:6]}


def gust_fe_loads(case, geo, sec, model, peak, structural, G0):
    """Station loads on the FE lines of the gust peak: aerodynamic line loads plus the inertia
    and weight of the structure -m_s (a* + g e_z) per length, and the engines' -m_e (a*(y_e) + g e_z)
    at their stations (a* of the node there).

    Parameters
    ----------
    case : module
        The PEGASUS case module (``ENGINES``, ``GUST``).
    geo : WingGeometry
        The wing geometry.
    sec : BoxSections
        Streamwise sections of the FE box.
    model : ShellBox
        The FE model.
    peak : dict
        Result of :func:`gust_peak_loads`.
    structural : numpy.ndarray
        (n,) structural mass per length (kg/m).
    G0 : float
        Gravitational acceleration (m/s^2).

    Returns
    -------
    list of tuple
        ``(y, centre, F, M)`` station loads.
    """

    y = geo.span_coordinate
    a_eff = peak["acceleration"] + np.array([0.0, 0.0, G0])
    line = peak["force_per_length"] - structural[:, None] * a_eff
    loads = lumped_line_loads(sec, model.span_y[::2], y, line, peak["moment_per_length"])
    for ye, m in engine_stations(case, geo):
        k = int(np.argmin(abs(y - ye)))
        loads.append((float(ye), sec.at(ye)[0], -m * a_eff[k], np.zeros(3)))
    return loads


def pegasus_setup(walls, load_factor, material=ALUMINIUM):
    """(geometry, BoxSections, line loads, beam params, structural mass per length, walls) of the
    PEGASUS wing with ``walls`` ({wall: thickness per station, m}) at load factor ``load_factor``.

    Parameters
    ----------
    walls : dict
        Wall name -> (n,) thicknesses (m).
    load_factor : float
        Load factor n (0 < |n| <= 10).
    material : Material, optional
        Isotropic material.

    Returns
    -------
    tuple
        (geometry, BoxSections, line loads, beam parameters, structural mass per length, walls).
    """
    if not (np.isfinite(load_factor) and 0 < abs(load_factor) <= 10):
        raise ValueError(f"--load-factor = {load_factor}; allowed range 0 < |n| <= 10")
    pf = case.PLANFORM
    geo, chord, axis_frac = wing_geometry(pf, case.ENGINES)
    sec = BoxSections(geo.node_positions, geo.width, geo.height, walls)
    line = maneuver_line_loads(geo.node_positions, chord, axis_frac, case.TOGW_LB * LB * G0, load_factor,
                               semi_span=pf.semi_span, fuselage_half_width=pf.root_rib * pf.semi_span)
    params, structural = beam_params(geo, walls, material)
    return geo, sec, line, params, structural, walls


def aeroelastic_model(walls, *, spanwise_boxes=20, chordwise_boxes=8, material=ALUMINIUM):
    """The PEGASUS wing of ``walls`` for :func:`wingmdao.fe.nastran_aero.aeroelastic_deck`:
    (beam params, lifting panels, flight data).

    Beam: :func:`pegasus_setup` (the 20 box sections, engines smeared as non-structural mass).
    Panels: the Table D.3 trapezoid from the symmetry plane to the semi-span, split at the root rib
    (station 1) so that each panel lies over one straight beam segment: stations 0-1 (the centre
    box) and 1-19; ``spanwise_boxes`` shared between them by span, ``chordwise_boxes`` each.
    Flight: SOL 146 at the case's gust point (``GUST``: 25,000 ft, Mach 0.5), SOL 145 at the
    flutter point (:func:`wingmdao.cases.pegasus.flight_point`: 20,000 ft, velocities 0.5-1.3
    V_D, Mach M_D), SOL 144 at the maneuver point (20,000 ft, Mach 0.5, alpha 1 deg); reference
    chord S / b.

    Parameters
    ----------
    walls : dict
        Wall name -> (n,) thicknesses (m).
    spanwise_boxes : int, optional
        Aerodynamic boxes along the span.
    chordwise_boxes : int, optional
        Aerodynamic boxes along the chord.
    material : Material, optional
        Isotropic material.

    Returns
    -------
    tuple
        (beam parameters, lifting panels, flight data).
    """
    for name, value, low in (("--spanwise-boxes", spanwise_boxes, 2), ("--chordwise-boxes", chordwise_boxes, 1)):
        if not (isinstance(value, (int, np.integer)) and low <= value <= 500):
            raise ValueError(f"{name} = {value}; allowed range {low}..500")
    geo, _, _, params, _, _ = pegasus_setup(walls, 1.0, material)
    pf = case.PLANFORM
    semi, y1 = pf.semi_span, float(geo.span_coordinate[1])
    dihedral = np.tan(np.radians(pf.dihedral_deg))
    n_in = min(max(1, int(round(spanwise_boxes * y1 / semi))), spanwise_boxes - 1)
    panels = []
    for (ya, yb), nspan, nodes in (((0.0, y1), n_in, (0, 1)),
                                   ((y1, semi), spanwise_boxes - n_in, tuple(range(1, geo.num_nodes)))):
        panels.append(LiftingPanel(root_le=(float(pf.leading_edge_x(ya)), ya, dihedral * ya),
                                   root_chord=float(pf.chord(ya)),
                                   tip_le=(float(pf.leading_edge_x(yb)), yb, dihedral * yb),
                                   tip_chord=float(pf.chord(yb)), nspan=nspan, nchord=chordwise_boxes, nodes=nodes))
    fp = case.flight_point()
    h_gust = float(altitude_ft_to_m(case.GUST["altitude_ft"]))
    h_man = float(altitude_ft_to_m(case.MANEUVER_ALTITUDE_FT))
    v_gust = float(mach_to_tas(case.GUST["mach"], h_gust))
    v_man = float(mach_to_tas(case.MANEUVER_MACH, h_man))
    area, span = pf.area_ft2 * FT**2, pf.span_ft * FT
    flight = FlightData(reference_chord=area / span, full_span=span, half_area=area / 2,
                        gust_mach=case.GUST["mach"], gust_velocity=v_gust, gust_density=float(density(h_gust)),
                        flutter_density=fp["density"], flutter_mach=fp["dive_speed"] / fp["speed_of_sound"],
                        flutter_velocities=tuple(np.linspace(0.5, 1.3, 17) * fp["dive_speed"]),
                        trim_mach=case.MANEUVER_MACH, trim_dynamic_pressure=0.5 * float(density(h_man)) * v_man**2)
    return params, panels, flight


def nastran_aeroelastic_deck(walls, *, sol=146, modes=10, spanwise_boxes=20, chordwise_boxes=8) -> str:
    """The Nastran aeroelastic deck (:mod:`wingmdao.fe.nastran_aero`) of the PEGASUS wing of
    ``walls`` (:func:`aeroelastic_model`), executive and case control of SOL ``sol``.

    Parameters
    ----------
    walls : dict
        Wall name -> (n,) thicknesses (m).
    sol : {144, 145, 146}, optional
        Solution sequence.
    modes : int, optional
        Modes of EIGRL.
    spanwise_boxes : int, optional
        Aerodynamic boxes along the span.
    chordwise_boxes : int, optional
        Aerodynamic boxes along the chord.

    Returns
    -------
    str
        The deck text.
    """
    params, panels, flight = aeroelastic_model(walls, spanwise_boxes=spanwise_boxes, chordwise_boxes=chordwise_boxes)
    return aeroelastic_deck(params, ALUMINIUM, panels, flight, sol=sol, modes=modes,
                            title="wingmdao PEGASUS wing, aeroelastic beam model")
