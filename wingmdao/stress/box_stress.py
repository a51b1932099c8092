"""Box-section stress recovery (Sec. 4.4.2, Eq. 4.19-4.28), for numpy and CasADi.

Loads: the internal force F = [F_c, F_s, F_n] (N) and moment M = [M_c, M_s, M_n] (N m)
that the outboard part exerts on the inboard part (docs/conventions.md), in the station's csn
frame, about the box's geometric centre (the beam reference axis). With a ``section_to_csn``
rotation R they are first brought to the section axes (R^T F, R^T M).

Points (docs/stress.md):

* ``corner`` (4): outer corners (c, n) = (+-w/2, +-h/2) in the order front-lower,
  rear-lower, rear-upper, front-upper (``wingmdao.section.box.CORNERS``).
* ``vm`` (8): the wall-midline corners, same corner order; at each corner first the skin,
  then the spar that meets there (each wall has its own torsional shear).
* ``cent`` (4): flange centres of the upper skin, lower skin, front spar, rear spar.
"""

from __future__ import annotations

import casadi as ca

from wingmdao.section.box import (CORNERS, is_symbolic, box_area, box_centroid, box_enclosed_area,
                                  box_first_moments, box_inertia, box_midline, box_shear_centre, sqrt)

#: Constraint families (docs/conventions.md) and their number of points per station.
FAMILIES = {"vm": 8, "ss_tension": 4, "ss_compression": 4, "cent_pos": 4, "cent_neg": 4}

#: Added under the von Mises square root (Pa^2) so that its derivative stays finite at zero
#: stress; it changes sigma_vm by at most 1 Pa (at zero stress), 5e-9 Pa at 100 MPa.
VM_TINY = 1.0


def _to_section(rot, vec):
    """R^T v for a 3-vector (list of three scalars / arrays, or an SX column)."""
    if rot is None:
        return [vec[0], vec[1], vec[2]]
    if is_symbolic(rot, vec):
        v = ca.mtimes(rot.T, vec)
        return [v[0], v[1], v[2]]
    return [sum(rot[..., j, i] * vec[j] for j in range(3)) for i in range(3)]


#: Section properties the stress recovery takes from the section component (BoxSection outputs of
#: the same names, App. F) when they are given instead of recomputed at every time and station.
SECTION_PROPERTIES = ("A", "c_ea", "n_ea", "Ixx", "Izz", "Ixz", "c_sc", "n_sc", "Qx", "Qz")


def section_quantities(geometry, given=None) -> dict:
    """Section quantities the stress recovery needs (``given``: those of SECTION_PROPERTIES
    already computed by the section component; only the enclosed midline area is added).

    Parameters
    ----------
    geometry : tuple
        ``(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar)`` of the box (m).
    given : dict or None, optional
        SECTION_PROPERTIES already computed for this station; None recomputes them.

    Returns
    -------
    dict
        ``A`` (m^2), ``c_ea``, ``n_ea``, ``c_sc``, ``n_sc`` (m), ``Ixx``, ``Izz``, ``Ixz`` (m^4),
        ``Qx``, ``Qz`` (m^3) and ``A_m`` (m^2).
    """
    if given is not None:
        return {**{k: given[k] for k in SECTION_PROPERTIES}, "A_m": box_enclosed_area(*geometry)}
    c0, n0 = box_centroid(*geometry)
    i_xx, i_zz, i_xz = box_inertia(*geometry)
    c_sc, n_sc = box_shear_centre(*geometry)
    q_x, q_z = box_first_moments(*geometry)
    return {"A": box_area(*geometry), "c_ea": c0, "n_ea": n0, "Ixx": i_xx, "Izz": i_zz, "Ixz": i_xz,
            "c_sc": c_sc, "n_sc": n_sc, "Qx": q_x, "Qz": q_z, "A_m": box_enclosed_area(*geometry)}


def axial_stress(c, n, force, moment, sec):
    """Axial stress sigma_ss at (c, n) (Eq. 4.19 generalised to the unsymmetric section), Pa.

    sigma = F_s / A + E (kappa_n (c - c_ea) - kappa_c (n - n_ea)) with the curvature
    kappa = E^{-1} M about the centroid: M_c' = M_c + n_ea F_s, M_n' = M_n - c_ea F_s, so::

        sigma = F_s/A + [(Ixz M_c' + Ixx M_n')(c - c_ea) - (Izz M_c' + Ixz M_n')(n - n_ea)]
                / (Ixx Izz - Ixz^2)

    With Ixz = 0 and the centroid at the centre this is Eq. 4.19 (M_c compresses n > 0).
    ``sec`` is :func:`section_quantities`.

    Parameters
    ----------
    c, n : float, array_like or casadi.SX
        Chordwise and normal coordinates of the point in the section frame (m).
    force : sequence of 3
        Internal force (F_c, F_s, F_n) in the section frame (N).
    moment : sequence of 3
        Internal moment (M_c, M_s, M_n) in the section frame (N m).
    sec : dict
        Section quantities of :func:`section_quantities`.

    Returns
    -------
    float, array_like or casadi.SX
        Axial stress (Pa, tension positive).
    """
    c0, n0 = sec["c_ea"], sec["n_ea"]
    i_xx, i_zz, i_xz = sec["Ixx"], sec["Izz"], sec["Ixz"]
    m_c = moment[0] + n0 * force[1]
    m_n = moment[2] - c0 * force[1]
    det = i_xx * i_zz - i_xz**2
    return (force[1] / sec["A"]
            + ((i_xz * m_c + i_xx * m_n) * (c - c0) - (i_zz * m_c + i_xz * m_n) * (n - n0)) / det)


def torsion_shear_flow(force, moment, sec):
    """Bredt shear flow q = T / (2 A_m) (Eq. 4.20 corrected), N/m, positive upper skin aft.

    T is the torque about the shear centre: T = M_s - (n_sc F_c - c_sc F_n), so that the
    transverse shear (through the shear centre) is handled by Eq. 4.22-4.23 alone.

    Parameters
    ----------
    force : sequence of 3
        Internal force (F_c, F_s, F_n) in the section frame (N).
    moment : sequence of 3
        Internal moment (M_c, M_s, M_n) in the section frame (N m).
    sec : dict
        Section quantities of :func:`section_quantities`.

    Returns
    -------
    float, array_like or casadi.SX
        Shear flow (N/m).
    """
    torque = moment[1] - (sec["n_sc"] * force[0] - sec["c_sc"] * force[2])
    return torque / (2.0 * sec["A_m"])


def box_stresses(force, moment, w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar,
                 section_to_csn=None, section=None) -> dict:
    """Stresses at the recovery points (Pa): ``sigma_corner`` (4), ``sigma_vm`` (8), ``tau_cent`` (4).

    * corner axial stress, Eq. 4.19 generalised (:func:`axial_stress`);
    * mid-corner von Mises sigma_vm = sqrt(sigma^2 + 3 tau^2 + VM_TINY) with sigma the axial
      stress at the midline corner and tau = q / t of the skin, then of the spar (Eq. 4.20-4.21
      corrected: plane stress with one normal and one shear component);
    * flange-centre shear, torsion + V Q / (I t) (Eq. 4.22-4.25), positive in the sense of a
      positive torque (upper skin aft, rear spar down, lower skin forward, front spar up):
      tau_c = F_c Qz / (Izz (t_u + t_l)), tau_n = F_n Qx / (Ixx (t_f + t_r)).

    ``section``: the SECTION_PROPERTIES of this station, when already computed (else recomputed).

    Parameters
    ----------
    force : sequence of 3
        Internal force at the station, in the csn frame (N).
    moment : sequence of 3
        Internal moment at the station (N m), in the same frame as ``force``.
    w, h : float, array_like or casadi.SX
        Box width and height, outer (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float, array_like or casadi.SX
        Wall thicknesses (m).
    section_to_csn : array_like or None, optional
        (3, 3) rotation R from the section's own axes to the csn frame (the loads are rotated
        by R^T); None when the two coincide.
    section : dict or None, optional
        SECTION_PROPERTIES of this station, when already computed.

    Returns
    -------
    dict
        ``sigma_corner`` (4), ``sigma_vm`` (8) and ``tau_cent`` (4) stresses (Pa).
    """
    geometry = (w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar)
    force = _to_section(section_to_csn, force)
    moment = _to_section(section_to_csn, moment)
    sec = section_quantities(geometry, section)
    sigma_corner = [axial_stress(sc * 0.5 * w, sn * 0.5 * h, force, moment, sec) for sc, sn in CORNERS]

    q_t = torsion_shear_flow(force, moment, sec)
    c_front, c_rear, n_lower, n_upper = box_midline(*geometry)
    sigma_vm = []
    for sc, sn in CORNERS:
        sigma = axial_stress(c_rear if sc > 0 else c_front, n_upper if sn > 0 else n_lower, force, moment, sec)
        for t_wall in (t_upper_skin if sn > 0 else t_lower_skin, t_rear_spar if sc > 0 else t_front_spar):
            sigma_vm.append(sqrt(sigma**2 + 3.0 * (q_t / t_wall) ** 2 + VM_TINY))

    tau_c = force[0] * sec["Qz"] / (sec["Izz"] * (t_upper_skin + t_lower_skin))
    tau_n = force[2] * sec["Qx"] / (sec["Ixx"] * (t_front_spar + t_rear_spar))
    tau_cent = [q_t / t_upper_skin + tau_c, q_t / t_lower_skin - tau_c,
                q_t / t_front_spar + tau_n, q_t / t_rear_spar - tau_n]
    return {"sigma_corner": sigma_corner, "sigma_vm": sigma_vm, "tau_cent": tau_cent}


def stress_constraints(stresses: dict, sigma_y: float, families=tuple(FAMILIES)) -> dict:
    """Constraint values g = stress / sigma_y - 1 (Eq. 4.26-4.28), lists keyed by family.

    ``ss_tension``/``ss_compression`` are the + and - forms of Eq. 4.27, ``cent_pos``/
    ``cent_neg`` of Eq. 4.28. Shear is compared with sigma_y as in the dissertation.

    Parameters
    ----------
    stresses : dict
        Stresses of :func:`box_stresses` (Pa).
    sigma_y : float
        Yield stress of the material (Pa).
    families : sequence of str, optional
        Constraint families to form (keys of :data:`FAMILIES`).

    Returns
    -------
    dict
        Family -> list of constraint values g (-; g <= 0 is feasible).
    """
    check_families(families)
    out = {
        "vm": [s / sigma_y - 1.0 for s in stresses["sigma_vm"]],
        "ss_tension": [s / sigma_y - 1.0 for s in stresses["sigma_corner"]],
        "ss_compression": [-s / sigma_y - 1.0 for s in stresses["sigma_corner"]],
        "cent_pos": [s / sigma_y - 1.0 for s in stresses["tau_cent"]],
        "cent_neg": [-s / sigma_y - 1.0 for s in stresses["tau_cent"]],
    }
    return {f: out[f] for f in families}


def check_families(families) -> None:
    """Raise ``ValueError`` unless every name is one of ``FAMILIES``.

    Parameters
    ----------
    families : sequence of str
        Constraint family names.
    """
    bad = [f for f in families if f not in FAMILIES]
    if bad or not len(families):
        raise ValueError(f"unknown stress constraint families {bad or list(families)}; valid: {', '.join(FAMILIES)}")


#: the panel points of :func:`panel_running_loads`: each skin at its front and rear edge (the
#: midline corners), each spar web at mid-height
SKIN_PANEL_POINTS = ("upper_front", "upper_rear", "lower_front", "lower_rear")
WEB_PANEL_POINTS = ("front", "rear")


def panel_running_loads(force, moment, w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar,
                        skin_axial_thickness, section, section_to_csn=None, web_axial_thickness=None,
                        force_gradient=None) -> dict:
    """Running loads (N/m) of the walls as panels: ``nx_skin``, ``nxy_skin``, ``ny_skin`` at
    :data:`SKIN_PANEL_POINTS` and ``nx_web``, ``nxy_web`` at :data:`WEB_PANEL_POINTS`.

    N_x = sigma t_axial: the axial stress (:func:`axial_stress`, compression negative) at the
    point times the wall's area per width (a skin's ``skin_axial_thickness`` = (upper, lower)
    skin plus smeared stiffener area per width; a web's own thickness, or
    ``web_axial_thickness`` = (front, rear)). For walls of another material than the section's
    reference (transformed section) both are scaled by the wall's modulus ratio, so that N_x is
    the wall's own running load. N_xy = tau t: the
    flange-centre shear of the wall (torsion plus transverse shear, :func:`box_stresses`) times
    its thickness (the webs' peak shear flow, at mid-height). A skin's N_xy at its front and
    rear edge is its shear flow there (:func:`skin_edge_shear_flows`: the flange-centre value
    plus the vertical shear's part, which grows linearly from mid-chord to the spars). A skin's
    chordwise N_y (``ny_skin``, the same at both points of a skin) is its mid-chord value
    (:func:`skin_transverse_running_loads`) from ``force_gradient`` = dF/ds (N/m, the csn
    components of the spanwise derivative of ``force``; None: zero). ``section`` is the
    station's SECTION_PROPERTIES (the stiffened section's, so the stiffeners share the bending).

    Parameters
    ----------
    force : sequence of 3
        Internal force at the station (N).
    moment : sequence of 3
        Internal moment at the station (N m).
    w, h : float, array_like or casadi.SX
        Box width and height, outer (m).
    t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar : float, array_like or casadi.SX
        Wall thicknesses (m).
    skin_axial_thickness : sequence of 2
        Area per width of the upper and lower skin with their smeared stiffeners (m).
    section : dict
        SECTION_PROPERTIES of the station.
    section_to_csn : array_like or None, optional
        (3, 3) rotation R from the section's own axes to the csn frame; None when they coincide.
    web_axial_thickness : sequence of 2 or None, optional
        Area per width of the front and rear spar webs (m); None for their thicknesses.
    force_gradient : sequence of 3 or None, optional
        Spanwise derivative of ``force`` (N/m); None for zero.

    Returns
    -------
    dict
        ``nx_skin``, ``nxy_skin``, ``ny_skin`` at :data:`SKIN_PANEL_POINTS` and ``nx_web``,
        ``nxy_web`` at :data:`WEB_PANEL_POINTS` (N/m, compression negative).
    """
    geometry = (w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar)
    stresses = box_stresses(force, moment, *geometry, section_to_csn=section_to_csn, section=section)
    force = _to_section(section_to_csn, force)
    moment = _to_section(section_to_csn, moment)
    sec = section_quantities(geometry, section)
    c_front, c_rear, n_lower, n_upper = box_midline(*geometry)
    tau = stresses["tau_cent"]
    t_axial = {"upper": skin_axial_thickness[0], "lower": skin_axial_thickness[1]}
    edge = skin_edge_shear_flows(force, sec, c_rear - c_front, n_upper, n_lower, tau[0] * t_upper_skin,
                                 tau[1] * t_lower_skin, skin_axial_thickness)
    if force_gradient is None:
        ny = [0.0, 0.0]
    else:
        ny = skin_transverse_running_loads(_to_section(section_to_csn, force_gradient), sec, c_rear - c_front,
                                           n_upper, n_lower, skin_axial_thickness)
    nx_skin, nxy_skin, ny_skin = [], [], []
    for k, (skin, n_skin) in enumerate((("upper", n_upper), ("lower", n_lower))):
        for j, c in enumerate((c_front, c_rear)):
            nx_skin.append(axial_stress(c, n_skin, force, moment, sec) * t_axial[skin])
            nxy_skin.append(edge[2 * k + j])
            ny_skin.append(ny[k])
    n_mid = 0.5 * (n_lower + n_upper)
    t_web = (t_front_spar, t_rear_spar) if web_axial_thickness is None else web_axial_thickness
    nx_web = [axial_stress(c, n_mid, force, moment, sec) * t for c, t in zip((c_front, c_rear), t_web)]
    nxy_web = [tau[2] * t_front_spar, tau[3] * t_rear_spar]
    return {"nx_skin": nx_skin, "nxy_skin": nxy_skin, "ny_skin": ny_skin, "nx_web": nx_web, "nxy_web": nxy_web}


def skin_edge_shear_flows(force, sec, width_mid, n_upper, n_lower, q_upper_centre, q_lower_centre,
                          skin_axial_thickness) -> list:
    """Shear flow (N/m) of each skin at its front and rear edge (the midline corners), in the
    sign of :func:`box_stresses` (positive torque): [upper front, upper rear, lower front, lower
    rear].

    The vertical shear F_n (through the shear centre) gives a skin a shear flow that is zero at
    mid-chord (the box symmetric about its vertical centreline) and grows linearly towards the
    spars, dq/dc = F_n (n_skin - n_ea) t_ax / Ixx: the first moment of the skin's axial area
    per width t_ax (skin plus smeared stiffeners, :func:`panel_running_loads`) between mid-chord
    and the point (thin-walled beam theory: T. H. G. Megson, *Aircraft Structures for
    Engineering Students*, 4th ed., Butterworth-Heinemann 2007, Sec. 17.3, shear of closed
    sections). At the edges, half the midline width ``width_mid`` from mid-chord, it reaches
    +-Delta, Delta_upper = F_n (n_upper - n_ea) t_ax,u (width_mid / 2) / Ixx and
    Delta_lower = F_n (n_ea - n_lower) t_ax,l (width_mid / 2) / Ixx, with +Delta at the front
    edge of both skins (it continues the webs' upward flow of F_n > 0 around the cell) and
    -Delta at the rear. Added to the skin's flange-centre flow ``q_*_centre`` (torsion plus
    the chordwise shear's part, which is largest at mid-chord, so keeping its centre value is
    the larger of the two when they add). Ixz is neglected, as in :func:`box_stresses`.

    Parameters
    ----------
    force : sequence of 3
        Internal force in the csn frame (N).
    sec : dict
        Section quantities of :func:`section_quantities`.
    width_mid : float, array_like or casadi.SX
        Midline width between the spars (m).
    n_upper, n_lower : float, array_like or casadi.SX
        Normal coordinates of the upper and lower skin midlines (m).
    q_upper_centre, q_lower_centre : float, array_like or casadi.SX
        Shear flow of each skin at mid-chord (N/m).
    skin_axial_thickness : sequence of 2
        Area per width of the upper and lower skin with their smeared stiffeners (m).

    Returns
    -------
    list
        Shear flows [upper front, upper rear, lower front, lower rear] (N/m).
    """
    half = 0.5 * width_mid
    shear = force[2] / sec["Ixx"]
    d_upper = shear * (n_upper - sec["n_ea"]) * skin_axial_thickness[0] * half
    d_lower = shear * (sec["n_ea"] - n_lower) * skin_axial_thickness[1] * half
    return [q_upper_centre + d_upper, q_upper_centre - d_upper, q_lower_centre + d_lower, q_lower_centre - d_lower]


def skin_transverse_running_loads(force_gradient, sec, width_mid, n_upper, n_lower, skin_axial_thickness) -> list:
    """Chordwise running load N_y (N/m, compression negative) of the upper and lower skin at
    mid-chord, from the spanwise change of the vertical shear.

    In-plane equilibrium of the skin (s spanwise, c chordwise, no surface traction in its
    plane): dN_s/ds + dN_sc/dc = 0 and dN_sc/ds + dN_c/dc = 0, so d^2 N_c / dc^2 =
    d^2 N_s / ds^2 (S. P. Timoshenko and J. N. Goodier, *Theory of Elasticity*, 3rd ed.,
    McGraw-Hill 1970, Sec. 17, the plane-stress equilibrium equations). With N_s = t_ax sigma,
    sigma = -M_c (n_skin - n_ea) / Ixx and dM_c/ds = -F_n (:func:`axial_stress`, the internal
    loads of the outboard part), d^2 N_s / ds^2 = t_ax (n_skin - n_ea) (dF_n/ds) / Ixx, the
    same across the chord for the vertical shear (the section's spanwise change neglected).
    The spar webs, vertical, take no chordwise load from the skin (N_c = 0 at both spars,
    ``width_mid`` apart), so N_c is a parabola with its extreme at mid-chord:

        N_y = -(width_mid^2 / 8) t_ax (n_skin - n_ea) (dF_n/ds) / Ixx.

    Under upward net load (dF_n/ds < 0, the shear grows inboard) it compresses the lower skin
    and stretches the upper one; a download the reverse. Ribs, which the model leaves out of
    the skins' in-plane equilibrium, relieve it near themselves, so this is the value between
    ribs.

    Parameters
    ----------
    force_gradient : sequence of 3
        Spanwise derivative of the internal force in the csn frame (N/m).
    sec : dict
        Section quantities of :func:`section_quantities`.
    width_mid : float, array_like or casadi.SX
        Midline width between the spars (m).
    n_upper, n_lower : float, array_like or casadi.SX
        Normal coordinates of the upper and lower skin midlines (m).
    skin_axial_thickness : sequence of 2
        Area per width of the upper and lower skin with their smeared stiffeners (m).

    Returns
    -------
    list
        Chordwise running load of the upper and lower skin at mid-chord (N/m, compression negative).
    """
    k = -(width_mid**2 / 8.0) * force_gradient[2] / sec["Ixx"]
    return [k * skin_axial_thickness[0] * (n_upper - sec["n_ea"]), k * skin_axial_thickness[1] * (n_lower - sec["n_ea"])]
