"""Running-load allowables of a stiffened wall from its equivalent thickness alone: the outer
level of the two-level stiffened sizing (docs/panels.md, "Two-level sizing").

A stiffened skin of equivalent thickness t (skin plus smeared stiffener area per width) between
ribs L apart, designed at its minimum weight, carries a compressive running load N up to the
smallest of three allowables, each a closed form of t:

* Farrar's efficiency (Farrar, "The design of compression structures for minimum weight",
  J. R. Aeronaut. Soc. 53, 1949, pp. 1041-1052; tabulated in Niu, *Airframe Stress Analysis
  and Sizing*, 2nd ed., Hong Kong Conmilit 1999, Ch. 14, and Bruhn, *Analysis and Design of
  Flight Vehicle Structures*, Jacobs 1973, Ch. C7): the optimum panel works at
  sigma = F sqrt(N E / L), so N <= F^2 E t^2 / L; F = 0.81 for blade stiffeners, 0.91 for
  Z-stiffeners (:data:`FARRAR_EFFICIENCY`). Elastic, the stiffener pitch free;
* the skin between stiffeners at the given pitch b, a long simply supported plate
  (:func:`wingmdao.panels.buckling.plate_compression_long` of the isotropic skin,
  :func:`wingmdao.panels.laminate.isotropic_abd`: k = 4, Timoshenko & Gere, *Theory of Elastic
  Stability*, 2nd ed., 1961, Sec. 9.2): the skin of thickness phi t works at the panel's stress,
  N <= N_x,cr(phi t) t / (phi t) = 4 pi^2 E (phi t)^2 t / (12 (1 - nu^2) b^2), phi the skin's
  share of the area (:data:`SKIN_SHARE`): the fixed pitch's limit at low loads, where Farrar's
  optimum pitch would be smaller than b;
* the material: N <= sigma_c t, sigma_c the compressive yield (the crippling and Johnson
  cut-off of the detailed model never exceed it).

The three are combined as R_c = N sqrt(sum_i (1 / N_i)^2) (1 = failure), then with the skin's
shear buckling, :func:`wingmdao.panels.buckling.plate_shear_ss` of the skin phi t, b x L
(isotropic: N_xy,cr = k_s pi^2 E (phi t)^3 / (12 (1 - nu^2) b^2), k_s = 5.34 + 4 (b/L)^2 for
L >= b, the fit 5.35 + 4 (b/L)^2 of Timoshenko & Gere Sec. 9.7 through the long plate's 5.34), through the interaction R_c + R_s^2 = 1 of the detailed model
(:func:`wingmdao.panels.buckling.interaction_ratio`). Every ratio is homogeneous of degree 1 in
the loads, so a safety factor scales it exactly. Check: against the detailed model's own
minimum-weight panel (``tests/test_panel_two_level.py``). Metallic walls only.
"""

from __future__ import annotations

from wingmdao.panels import buckling as bk
from wingmdao.panels.laminate import isotropic_abd
from wingmdao.section.box import sqrt

#: Farrar's efficiency factor F of the minimum-weight stiffened panel, sigma = F sqrt(N E / L)
#: (Farrar 1949; Niu 1999 Ch. 14; Bruhn Ch. C7)
FARRAR_EFFICIENCY = {"blade": 0.81, "z": 0.91}

#: skin thickness over equivalent thickness of the skin-buckling and skin-shear allowables
#: (the detailed model's minimum-weight PEGASUS panels at 0.15 m pitch: 0.91 at low loads, where
#: this allowable governs; docs/panels.md)
SKIN_SHARE = 0.9


def _skin_d(material, t, skin_share):
    """D11, D22, D12, D66 (N m) of the isotropic skin of thickness phi t."""
    d = isotropic_abd(material.E, material.nu, skin_share * t)
    return d["D11"], d["D22"], d["D12"], d["D66"]


def equivalent_compression_allowables(material, t, length, pitch, efficiency=FARRAR_EFFICIENCY["blade"],
                                      skin_share=SKIN_SHARE) -> dict:
    """The compressive running-load allowables (N/m) of a stiffened wall of equivalent thickness
    ``t``: ``farrar`` F^2 E t^2 / L, ``skin`` the skin's long-plate buckling load at the panel's
    stress, 4 pi^2 E (phi t)^2 t / (12 (1 - nu^2) b^2), ``material`` sigma_y t (module docstring).

    Parameters
    ----------
    material : wingmdao.materials.Material
        The metal of skin and stiffeners.
    t : float, array_like or casadi.SX
        Equivalent thickness, skin plus stiffener area per width (m).
    length : float, array_like or casadi.SX
        Panel length between ribs (m).
    pitch : float
        Stiffener pitch (m).
    efficiency : float, optional
        Farrar's F (-).
    skin_share : float, optional
        Skin thickness over equivalent thickness, phi (-).

    Returns
    -------
    dict
        ``farrar``, ``skin``, ``material``: allowable compressive running loads (N/m).
    """
    return {"farrar": efficiency ** 2 * material.E * t * t / length,
            "skin": bk.plate_compression_long(*_skin_d(material, t, skin_share), pitch) / skin_share,
            "material": material.sigma_y * t}


def equivalent_shear_allowable(material, t, length, pitch, skin_share=SKIN_SHARE):
    """Shear buckling running load (N/m) of the skin between stiffeners, thickness phi t, width
    the pitch b, length L: :func:`wingmdao.panels.buckling.plate_shear_ss` of the isotropic
    skin, k_s pi^2 E (phi t)^3 / (12 (1 - nu^2) b^2) with k_s = 5.34 + 4 (b/L)^2 for L >= b
    (Timoshenko & Gere Sec. 9.7).

    Parameters
    ----------
    material : wingmdao.materials.Material
        The metal of the skin.
    t : float, array_like or casadi.SX
        Equivalent thickness (m).
    length : float, array_like or casadi.SX
        Panel length between ribs (m).
    pitch : float
        Stiffener pitch (m).
    skin_share : float, optional
        Skin thickness over equivalent thickness (-).

    Returns
    -------
    float, array_like or casadi.SX
        Critical shear flow (N/m).
    """
    return bk.plate_shear_ss(*_skin_d(material, t, skin_share), length, pitch)


def equivalent_skin_ratio(material, t, length, pitch, nx, nxy, efficiency=FARRAR_EFFICIENCY["blade"],
                          skin_share=SKIN_SHARE):
    """Failure ratio (1 = failure) of a stiffened skin of equivalent thickness ``t`` under the
    running loads ``nx`` (compression negative) and ``nxy``: R_c = max(-N_x, 0) sqrt(sum_i
    N_i^-2) over the allowables of :func:`equivalent_compression_allowables`, R_s = |N_xy| /
    :func:`equivalent_shear_allowable`, combined by R_c + R_s^2 = 1. Homogeneous of degree 1 in
    the loads.

    Parameters
    ----------
    material : wingmdao.materials.Material
        The metal of skin and stiffeners.
    t : float, array_like or casadi.SX
        Equivalent thickness (m).
    length : float, array_like or casadi.SX
        Panel length between ribs (m).
    pitch : float
        Stiffener pitch (m).
    nx : float, array_like or casadi.SX
        Spanwise running load (N/m, compression negative).
    nxy : float, array_like or casadi.SX
        Shear flow (N/m).
    efficiency : float, optional
        Farrar's F (-).
    skin_share : float, optional
        Skin thickness over equivalent thickness (-).

    Returns
    -------
    float, array_like or casadi.SX
        Combined ratio (-).
    """
    n = equivalent_compression_allowables(material, t, length, pitch, efficiency, skin_share)
    inv = sqrt(sum((1.0 / v) ** 2 for v in n.values()))
    rc = bk.positive_part(-nx, 1e-6) * inv   # tension is not credited (as the detailed skin modes)
    return bk.interaction_ratio(-rc, nxy, 1.0, equivalent_shear_allowable(material, t, length, pitch, skin_share))
