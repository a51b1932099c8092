"""A skin with blade or T stiffeners between two ribs: smeared properties, critical running
loads and load-linear failure ratios; the unstiffened wall and the spar web through the same
functions (no ``h``, ``ts``).

Geometry (x along the stiffeners, z normal to the skin, from the skin mid-plane towards the
stiffeners). Skin thickness ``t``; ``b`` = skin width *between* stiffeners (between spars, or
the web height of a spar, when unstiffened); ``a`` = panel length = rib pitch. Stiffeners:

* ``"blade"``: a web ``h`` x ``ts`` standing on the skin; pitch p = b (the web's own footprint
  ts is neglected, as usual for blades);
* ``"tee"``: a web of height ``h`` and thickness ``ts`` on a flange of width
  w_f = ``flange_ratio`` h and thickness ts bonded to the skin; pitch p = b + w_f. Default
  ``flange_ratio`` = 1, the link w_stiff = h_stiff recommended by the MDO Aeroelastic Benchmark
  (docs/source/opt_problem.rst of github.com/MDOBenchmarks/MDOAeroelasticBenchmark).

Loads: running loads of the whole panel, N_x (N/m, compression negative) and N_xy (N/m).
The skin and the stiffeners share N_x at a common strain (same material in both, so a common
stress sigma = N_x / (area per width)); the skin alone carries N_xy. Every *critical running
load* below is expressed as the panel's N_x (or N_xy) at which that mode occurs, so each
ratio is applied / critical with the same N_x.

Materials: :class:`PanelMaterial` (:func:`panel_material`) wraps an isotropic
:class:`wingmdao.materials.Material` or a :class:`~wingmdao.panels.laminate.PlyMaterial` with
its ply fractions [0, +45, -45, 90] (the same laminate in skin and stiffeners, numeric
fractions). Dimensions and loads may be floats, numpy arrays or CasADi ``SX``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from wingmdao.materials import MATERIALS, Material, get_material
from wingmdao.panels import buckling as bk
from wingmdao.panels.laminate import (PLY_ANGLES, PLY_MATERIALS, PlyMaterial, check_ply_fractions, get_ply_material,
                                      isotropic_abd, laminate_moduli, q_matrix, smeared_abd)
from wingmdao.names import DEFAULT_FLANGE_RATIO, STIFFENERS
from wingmdao.section.box import select, sqrt


#: Added (Pa^2) under the von Mises square root: finite derivative at zero stress (as
#: wingmdao.stress.box_stress.VM_TINY).
VM_TINY = 1.0

#: Added (dimensionless) under the Tsai-Wu strength-ratio square root, for the same reason.
TW_TINY = 1e-12


def _max(x, y):
    return select(x > y, x, y)


def _min(x, y):
    return select(x < y, x, y)


# --------------------------------------------------------------------------- material
@dataclass(frozen=True)
class PanelMaterial:
    """A metal (``Material``) or a laminate (``PlyMaterial`` + 4 ply fractions) for panels.

    Parameters
    ----------
    base : Material or PlyMaterial
        The metal, or the ply of a laminate.
    fractions : tuple of 4 floats or None, optional
        Fractions of 0, +45, -45 and 90 deg plies (-), required for a ply material and refused for
        a metal.
    """

    base: Material | PlyMaterial
    fractions: tuple | None = None

    def __post_init__(self):
        if isinstance(self.base, PlyMaterial):
            if self.fractions is None:
                raise ValueError(f"laminate {self.base.name!r} needs --ply-fractions (fractions of 0, +45, -45 "
                                 "and 90 deg plies, each in [0, 1], summing to 1)")
            object.__setattr__(self, "fractions", check_ply_fractions(self.fractions))
        elif self.fractions is not None:
            raise ValueError(f"--ply-fractions = {' '.join(str(f) for f in self.fractions)} given for the metal "
                             f"{self.base.name!r}; ply fractions apply only to a ply material (valid: stw-cfrp)")

    @property
    def is_laminate(self) -> bool:
        return isinstance(self.base, PlyMaterial)

    @property
    def name(self) -> str:
        return self.base.name

    @property
    def E_x(self) -> float:
        """Membrane modulus along x (Pa): E of the metal, laminate Ex of the smeared laminate."""
        return laminate_moduli(self.base, self.fractions)["Ex"] if self.is_laminate else self.base.E

    def abd(self, thickness) -> dict:
        """A (N/m) and D (N m) of a plate of this material and ``thickness`` (m).

        Parameters
        ----------
        thickness : float, array_like or casadi.SX
            Plate thickness (m).

        Returns
        -------
        dict
            A (N/m) and D (N m) terms, the keys of :data:`~wingmdao.panels.laminate.ABD_KEYS`.
        """
        if self.is_laminate:
            return smeared_abd(self.base, self.fractions, thickness)
        return isotropic_abd(self.base.E, self.base.nu, thickness)

    @property
    def compression_strength(self) -> float:
        """Compressive strength (Pa) under uniaxial sigma_x: sigma_y of a metal (taken equal to the
        compressive yield); of a laminate the first-ply-failure stress of the Tsai-Wu criterion."""
        if not self.is_laminate:
            return self.base.sigma_y
        probe = 1e8  # Pa; large enough that TW_TINY is negligible (the ratio is load-linear)
        return float(probe / laminate_strength_ratio(self, -probe, 0.0))


def panel_material(material, ply_fractions=None) -> PanelMaterial:
    """:class:`PanelMaterial` from a name (metal of ``get_material`` or ply of ``get_ply_material``),
    a ``Material`` or a ``PlyMaterial``; a ply material needs ``ply_fractions``.

    Parameters
    ----------
    material : str, Material or PlyMaterial
        A material name (metal or ply, case-insensitive) or a material.
    ply_fractions : sequence of 4 floats or None, optional
        Fractions of 0, +45, -45 and 90 deg plies (-), for a ply material only.

    Returns
    -------
    PanelMaterial
        The panel material; ValueError naming ``--material`` or ``--ply-fractions`` for bad input.
    """
    if isinstance(material, str):
        key = material.strip().lower()
        try:
            material = get_ply_material(key)
        except ValueError:
            try:
                material = get_material(key)
            except ValueError:
                raise ValueError(f"--material = {material!r}: unknown; valid: metals {', '.join(MATERIALS)}; "
                                 f"ply materials {', '.join(PLY_MATERIALS)}") from None
    return PanelMaterial(material, None if ply_fractions is None else tuple(ply_fractions))


# --------------------------------------------------------------------------- strength
def _tsai_wu_ratio(ply: PlyMaterial, s1, s2, s12):
    """Tsai-Wu strength ratio R (1 = failure) of ply stresses (s1, s2, s12) (Pa), load-linear.

    Tsai & Wu, J. Composite Materials 5 (1971) 58-80; Kassapoglou 2nd ed. Ch. 4:
    F1 s1 + F2 s2 + F11 s1^2 + F22 s2^2 + F66 s12^2 + 2 F12 s1 s2 = 1 with F1 = 1/Xt - 1/Xc,
    F2 = 1/Yt - 1/Yc, F11 = 1/(Xt Xc), F22 = 1/(Yt Yc), F66 = 1/S12^2,
    F12 = -sqrt(F11 F22)/2. The load factor lambda with lambda s on the surface solves
    q lambda^2 + l lambda = 1 (q, l the quadratic and linear parts), so
    R = 1/lambda = (l + sqrt(l^2 + 4 q + TW_TINY)) / 2, homogeneous of degree 1 in the stresses.
    """
    f1 = 1.0 / ply.Xt - 1.0 / ply.Xc
    f2 = 1.0 / ply.Yt - 1.0 / ply.Yc
    f11, f22, f66 = 1.0 / (ply.Xt * ply.Xc), 1.0 / (ply.Yt * ply.Yc), 1.0 / ply.S12**2
    f12 = -0.5 * math.sqrt(f11 * f22)
    lin = f1 * s1 + f2 * s2
    quad = f11 * s1 * s1 + f22 * s2 * s2 + f66 * s12 * s12 + 2.0 * f12 * s1 * s2
    return 0.5 * (lin + sqrt(lin * lin + 4.0 * quad + TW_TINY))


def laminate_strength_ratio(pm: PanelMaterial, sigma_x, tau_xy):
    """Largest Tsai-Wu ratio over the 0, +45, -45, 90 plies of the smeared laminate under the
    average membrane stresses (sigma_x, 0, tau_xy) (Pa), a load-linear strength ratio.

    Laminate strains from the membrane compliance (A/t)^-1 (A16 = A26 = 0), rotated to each ply
    (strain transformation, Jones Sec. 2.6: eps1 = ex m^2 + ey n^2 + gxy m n, eps2 =
    ex n^2 + ey m^2 - gxy m n, g12 = 2 (ey - ex) m n + gxy (m^2 - n^2)), ply stresses Q eps.

    Parameters
    ----------
    pm : PanelMaterial
        A laminate panel material.
    sigma_x : float, array_like or casadi.SX
        Average membrane stress along x (Pa, compression negative).
    tau_xy : float, array_like or casadi.SX
        Average membrane shear stress (Pa).

    Returns
    -------
    float, array_like or casadi.SX
        Largest Tsai-Wu strength ratio over the four ply angles (-; 1 = first-ply failure).
    """
    ply = pm.base
    mod = laminate_moduli(ply, pm.fractions)
    ex = sigma_x / mod["Ex"]
    ey = -mod["nu_xy"] * ex
    gxy = tau_xy / mod["Gxy"]
    q = q_matrix(ply)
    ratio = None
    for ang in PLY_ANGLES:
        th = math.radians(ang)
        m, n = math.cos(th), math.sin(th)
        e1 = ex * m * m + ey * n * n + gxy * m * n
        e2 = ex * n * n + ey * m * m - gxy * m * n
        g12 = 2.0 * (ey - ex) * m * n + gxy * (m * m - n * n)
        s1 = q[0, 0] * e1 + q[0, 1] * e2
        s2 = q[0, 1] * e1 + q[1, 1] * e2
        s12 = q[2, 2] * g12
        r = _tsai_wu_ratio(ply, s1, s2, s12)
        ratio = r if ratio is None else _max(ratio, r)
    return ratio


# --------------------------------------------------------------------------- geometry
def _check_stiffener(stiffener):
    if stiffener not in STIFFENERS:
        raise ValueError(f"--stiffener = {stiffener!r}; valid: {', '.join(STIFFENERS)}")


def flange_width(h, stiffener: str = "blade", flange_ratio=DEFAULT_FLANGE_RATIO):
    """Flange width (m): flange_ratio h for a tee, 0 for a blade.

    Parameters
    ----------
    h : float, array_like or casadi.SX
        Stiffener web height (m).
    stiffener : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-).

    Returns
    -------
    float, array_like or casadi.SX
        Flange width (m).
    """
    _check_stiffener(stiffener)
    return flange_ratio * h if stiffener == "tee" else 0.0 * h


def stiffener_elements(h, ts, stiffener: str = "blade", flange_ratio=DEFAULT_FLANGE_RATIO):
    """The stiffener's flat elements: list of (width, thickness, z_centroid_above_skin_face,
    I_own about its centroid per element (m^4), edge) with z measured from the skin's face.

    Blade: the web (one edge free). Tee: the flange (w_f x ts, on the skin) and the web on top
    of it (h x ts); for crippling the flange counts as two one-edge-free halves of w_f/2.

    Parameters
    ----------
    h : float, array_like or casadi.SX
        Stiffener web height (m).
    ts : float, array_like or casadi.SX
        Stiffener thickness (m).
    stiffener : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-).

    Returns
    -------
    list of tuple
        ``(width, thickness, z, I_own, edge)`` per flat element (m, m, m, m^4, str).
    """
    _check_stiffener(stiffener)
    if stiffener == "blade":
        return [(h, ts, 0.5 * h, ts * h**3 / 12.0, "one_free")]
    wf = flange_ratio * h
    return [(wf, ts, 0.5 * ts, wf * ts**3 / 12.0, "flange"),
            (h, ts, ts + 0.5 * h, ts * h**3 / 12.0, "one_free")]


def stiffener_area(h, ts, stiffener: str = "blade", flange_ratio=DEFAULT_FLANGE_RATIO):
    """Stiffener cross-section area (m^2): h ts (blade), (h + flange_ratio h) ts (tee).

    Parameters
    ----------
    h : float, array_like or casadi.SX
        Stiffener web height (m).
    ts : float, array_like or casadi.SX
        Stiffener thickness (m).
    stiffener : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-).

    Returns
    -------
    float, array_like or casadi.SX
        Cross-section area (m^2).
    """
    return sum(w * th for w, th, *_ in stiffener_elements(h, ts, stiffener, flange_ratio))


def stiffener_pitch(b, h, stiffener: str = "blade", flange_ratio=DEFAULT_FLANGE_RATIO):
    """Pitch p (m) from the skin width between stiffeners: b + w_f (tee), b (blade).

    Parameters
    ----------
    b : float, array_like or casadi.SX
        Skin width between stiffeners (m).
    h : float, array_like or casadi.SX
        Stiffener web height (m).
    stiffener : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-).

    Returns
    -------
    float, array_like or casadi.SX
        Stiffener pitch (m).
    """
    return b + flange_width(h, stiffener, flange_ratio)


def skin_width_from_pitch(pitch, h, stiffener: str = "blade", flange_ratio=DEFAULT_FLANGE_RATIO):
    """Skin width between stiffeners b = p - w_f (tee) or p (blade), m.

    Parameters
    ----------
    pitch : float, array_like or casadi.SX
        Stiffener pitch (m).
    h : float, array_like or casadi.SX
        Stiffener web height (m).
    stiffener : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-).

    Returns
    -------
    float, array_like or casadi.SX
        Skin width between stiffeners (m).
    """
    return pitch - flange_width(h, stiffener, flange_ratio)


def smeared_properties(t, b, h, ts, stiffener: str = "blade", flange_ratio=DEFAULT_FLANGE_RATIO, E=1.0):
    """Smeared (per unit width) properties of the stiffened panel; same E in skin and stiffener.

    Returns ``pitch`` (m), ``area_per_width`` t_eq = t + A_st/p (m), ``z_na`` the neutral axis
    from the skin mid-plane (m, towards the stiffeners), ``EA_per_width`` = E t_eq (N/m),
    ``EI_per_width`` D_x = E [t^3/12 + t z_na^2 + (sum_i I_i + A_i (z_i - z_na)^2)/p] (N m,
    bending about the neutral axis in the x-z plane, the beam-column of unit width), and
    ``shear_thickness`` = t (the skin alone carries N_xy). For a laminate pass E = Ex of the
    smeared laminate (:func:`wingmdao.panels.laminate.laminate_moduli`); one E for skin and
    stiffener, so the neutral axis is the area centroid.

    Parameters
    ----------
    t : float, array_like or casadi.SX
        Skin thickness (m).
    b : float, array_like or casadi.SX
        Skin width between stiffeners (m).
    h : float, array_like or casadi.SX
        Stiffener web height (m).
    ts : float, array_like or casadi.SX
        Stiffener thickness (m).
    stiffener : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-).
    E : float, optional
        Membrane modulus of skin and stiffener (Pa; 1 gives the geometric properties).

    Returns
    -------
    dict
        ``pitch``, ``area_per_width``, ``z_na``, ``EA_per_width``, ``EI_per_width``,
        ``shear_thickness`` (units above).
    """
    p = stiffener_pitch(b, h, stiffener, flange_ratio)
    elements = stiffener_elements(h, ts, stiffener, flange_ratio)
    a_st = sum(w * th for w, th, *_ in elements)
    t_eq = t + a_st / p
    first = sum(w * th * (0.5 * t + z) for w, th, z, *_ in elements) / p
    z_na = first / t_eq
    i_pw = t**3 / 12.0 + t * z_na**2 + sum(i_own + w * th * (0.5 * t + z - z_na) ** 2
                                             for w, th, z, i_own, _ in elements) / p
    return {"pitch": p, "area_per_width": t_eq, "z_na": z_na, "EA_per_width": E * t_eq,
            "EI_per_width": E * i_pw, "shear_thickness": t + 0.0 * t_eq}


def stiffener_crippling_stress(pm: PanelMaterial, h, ts, stiffener: str = "blade",
                               flange_ratio=DEFAULT_FLANGE_RATIO):
    """Crippling stress of the stiffener (Pa): area-weighted mean of its elements
    (:func:`~wingmdao.panels.buckling.section_crippling`), every element one-edge-free (the
    web; the flange as two halves of w_f/2). Metal: Needham (:func:`crippling_metal`), laminate:
    CMH-17 (:func:`crippling_laminate`) with the laminate's Tsai-Wu compression strength.

    Parameters
    ----------
    pm : PanelMaterial
        Panel material.
    h : float, array_like or casadi.SX
        Stiffener web height (m).
    ts : float, array_like or casadi.SX
        Stiffener thickness (m).
    stiffener : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-).

    Returns
    -------
    float, array_like or casadi.SX
        Crippling stress (Pa).
    """
    stresses, areas = [], []
    for w, th, _, _, kind in stiffener_elements(h, ts, stiffener, flange_ratio):
        width = 0.5 * w if kind == "flange" else w
        if pm.is_laminate:
            f = bk.crippling_laminate(pm.compression_strength, width, th, "one_free")
        else:
            f = bk.crippling_metal(pm.base.E, pm.base.sigma_y, width, th, "one_free")
        stresses.append(f)
        areas.append(w * th)
    return bk.section_crippling(stresses, areas)


# --------------------------------------------------------------------------- critical loads
def panel_critical_loads(pm: PanelMaterial, t, b, a, h=None, ts=None, stiffener: str = "blade",
                         flange_ratio=DEFAULT_FLANGE_RATIO, panel_width=None, fixity=1.0,
                         m_max: int = bk.M_MAX) -> dict:
    """Critical running loads of the panel (magnitudes, N/m; None where a mode does not apply).

    * ``skin_compression``: the skin between stiffeners (b x a, simply supported,
      :func:`plate_compression_ss`) expressed as the panel N_x: N_cr,skin t_eq / t;
    * ``skin_shear``: the same plate in shear (:func:`plate_shear_ss`);
    * ``panel_compression``: global buckling of the stiffened panel between ribs. Without
      ``panel_width`` a wide column, N = pi^2 c D_x / a^2 (D_x the smeared bending stiffness
      per width; conservative for a panel wide compared with a, the edges at the spars
      ignored); with ``panel_width`` W the smeared orthotropic plate a x W,
      D11 = D_x, D22, D12, D66 of the skin (stiffener torsion and transverse stiffness ignored);
    * ``panel_shear``: the smeared plate in shear: with W, :func:`plate_shear_ss` (a x W);
      without, the infinitely wide strip of width a between the ribs (:func:`plate_shear_long`
      with the strip's long side along y);
    * ``stiffener_column``: the stiffener with the full skin width p (the skin is unbuckled as
      long as the skin ratio <= 1) as a column of length a and end fixity c = ``fixity``:
      Euler/Johnson (:func:`column_stress`) with the stiffener crippling stress as cut-off,
      times t_eq;
    * ``stiffener_crippling``: stiffener crippling stress times t_eq.

    Unstiffened wall or spar web (``h`` and ``ts`` None): only the two skin modes, b = the width
    between spars or the web height.

    Parameters
    ----------
    pm : PanelMaterial
        Panel material.
    t : float, array_like or casadi.SX
        Skin thickness (m).
    b : float, array_like or casadi.SX
        Skin width between stiffeners, or between spars / the web height when unstiffened (m).
    a : float, array_like or casadi.SX
        Panel length, the rib pitch (m).
    h, ts : float, array_like, casadi.SX or None, optional
        Stiffener web height and thickness (m); None for an unstiffened wall.
    stiffener : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-).
    panel_width : float or None, optional
        Width W of the stiffened panel between spars (m); None for the wide-column form.
    fixity : float, optional
        End-fixity coefficient c of the stiffener column (-).
    m_max : int, optional
        Largest number of half-waves tried in compression.

    Returns
    -------
    dict
        Critical running loads (N/m, magnitudes) by mode; None where a mode does not apply.
    """
    skin = pm.abd(t)
    d = (skin["D11"], skin["D22"], skin["D12"], skin["D66"])
    out = dict.fromkeys(("skin_compression", "skin_shear", "panel_compression", "panel_shear",
                         "stiffener_column", "stiffener_crippling"))
    n_skin_c = bk.plate_compression_ss(*d, a, b, m_max)
    out["skin_shear"] = bk.plate_shear_ss(*d, a, b)
    if h is None:
        out["skin_compression"] = n_skin_c
        return out
    E = pm.E_x
    sm = smeared_properties(t, b, h, ts, stiffener, flange_ratio, E)
    t_eq = sm["area_per_width"]
    out["skin_compression"] = n_skin_c * t_eq / t
    dx = sm["EI_per_width"]
    if panel_width is None:
        out["panel_compression"] = fixity * math.pi**2 * dx / a**2
        out["panel_shear"] = bk.plate_shear_long(d[1], dx, d[2], d[3], a)
    else:
        out["panel_compression"] = bk.plate_compression_ss(dx, d[1], d[2], d[3], a, panel_width, m_max)
        out["panel_shear"] = bk.plate_shear_ss(dx, d[1], d[2], d[3], a, panel_width)
    f_cc = stiffener_crippling_stress(pm, h, ts, stiffener, flange_ratio)
    rho = sqrt(dx / sm["EA_per_width"])
    out["stiffener_column"] = bk.column_stress(E, a / rho, f_cc, fixity) * t_eq
    out["stiffener_crippling"] = f_cc * t_eq
    return out


# --------------------------------------------------------------------------- ratios
def material_ratio(pm: PanelMaterial, t, t_eq, nx, nxy):
    """Load-linear strength ratio (1 = failure) under N_x (on t_eq) and N_xy (on the skin t).

    Metal: von Mises sqrt(sigma^2 + 3 tau^2 + VM_TINY) / sigma_y with sigma = N_x / t_eq and
    tau = N_xy / t (the skin; the stiffener has tau = 0 and the same sigma, so the skin governs).
    Laminate: the largest Tsai-Wu strength ratio over the four ply angles of the skin
    (sigma, tau) and of the stiffener (sigma, 0) (:func:`laminate_strength_ratio`).

    Parameters
    ----------
    pm : PanelMaterial
        Panel material.
    t : float, array_like or casadi.SX
        Skin thickness (m).
    t_eq : float, array_like or casadi.SX
        Smeared thickness of skin and stiffeners (m).
    nx : float, array_like or casadi.SX
        Running load along the stiffeners (N/m, compression negative).
    nxy : float, array_like or casadi.SX
        Shear flow (N/m).

    Returns
    -------
    float, array_like or casadi.SX
        Strength ratio (-; 1 = failure).
    """
    sigma = nx / t_eq
    tau = nxy / t
    if pm.is_laminate:
        return _max(laminate_strength_ratio(pm, sigma, tau), laminate_strength_ratio(pm, sigma, 0.0 * tau))
    return sqrt(sigma * sigma + 3.0 * tau * tau + VM_TINY) / pm.base.sigma_y


def panel_failure_ratios(pm: PanelMaterial, t, b, a, h, ts, nx, nxy, stiffener: str = "blade",
                         flange_ratio=DEFAULT_FLANGE_RATIO, panel_width=None, fixity=1.0,
                         critical: dict | None = None) -> dict:
    """Failure ratios (applied / allowable, 1 = failure), each homogeneous of degree 1 in the loads.

    ``material`` (:func:`material_ratio`); ``skin_compression`` = -N_x / N_cr (signed: negative
    in tension), ``skin_shear`` = ``|N_xy| / N_cr`` (smooth ``|.|``), ``skin_buckling`` the combined
    :func:`interaction_ratio`; the same three for the panel (``panel_*``, ``panel_buckling``);
    ``stiffener_column``, ``stiffener_crippling`` = -N_x / N_cr (compression only, negative in
    tension). Modes that do not apply (unstiffened: ``h`` None) are None. ``critical``: the
    :func:`panel_critical_loads` of the same panel, when already computed.

    Parameters
    ----------
    pm : PanelMaterial
        Panel material.
    t : float, array_like or casadi.SX
        Skin thickness (m).
    b : float, array_like or casadi.SX
        Skin width between stiffeners (m).
    a : float, array_like or casadi.SX
        Panel length, the rib pitch (m).
    h, ts : float, array_like, casadi.SX or None
        Stiffener web height and thickness (m); None for an unstiffened wall.
    nx : float, array_like or casadi.SX
        Running load along the stiffeners (N/m, compression negative).
    nxy : float, array_like or casadi.SX
        Shear flow (N/m).
    stiffener : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-).
    panel_width : float or None, optional
        Width of the stiffened panel between spars (m).
    fixity : float, optional
        End-fixity coefficient of the stiffener column (-).
    critical : dict or None, optional
        :func:`panel_critical_loads` of the same panel, when already computed.

    Returns
    -------
    dict
        Failure ratio (-) by mode; None where a mode does not apply.
    """
    crit = critical if critical is not None else panel_critical_loads(
        pm, t, b, a, h, ts, stiffener, flange_ratio, panel_width, fixity)
    t_eq = t if h is None else smeared_properties(t, b, h, ts, stiffener, flange_ratio)["area_per_width"]
    out = {"material": material_ratio(pm, t, t_eq, nx, nxy)}
    for part in ("skin", "panel"):
        nc, ns = crit[f"{part}_compression"], crit[f"{part}_shear"]
        if nc is None:
            out.update({f"{part}_compression": None, f"{part}_shear": None, f"{part}_buckling": None})
            continue
        out[f"{part}_compression"] = bk.compression_ratio(nx, nc)
        out[f"{part}_shear"] = bk.shear_ratio(nxy, ns)
        out[f"{part}_buckling"] = bk.interaction_ratio(nx, nxy, nc, ns)
    for mode in ("stiffener_column", "stiffener_crippling"):
        out[mode] = None if crit[mode] is None else bk.compression_ratio(nx, crit[mode])
    return out


# --------------------------------------------------------------------------- command result
CRITICAL_KEYS = ("skin_compression", "skin_shear", "panel_compression", "panel_shear", "stiffener_column",
                 "stiffener_crippling")
RATIO_KEYS = ("material", *CRITICAL_KEYS, "skin_compression_shear", "panel_compression_shear")


def _num(x):
    return None if x is None else float(np.asarray(x))


def panel_analysis(pm: PanelMaterial, t, b, a, h=None, ts=None, nx=0.0, nxy=0.0, stiffener: str = "blade",
                   flange_ratio=DEFAULT_FLANGE_RATIO, panel_width=None, fixity=1.0) -> dict:
    """The JSON-ready result of ``wingmdao panel`` (floats; see docs/panels.md for the keys).

    Parameters
    ----------
    pm : PanelMaterial
        Panel material.
    t : float
        Skin thickness (m).
    b : float
        Skin width between stiffeners (m).
    a : float
        Panel length, the rib pitch (m).
    h, ts : float or None, optional
        Stiffener web height and thickness (m); None for an unstiffened wall.
    nx : float, optional
        Running load along the stiffeners (N/m, compression negative).
    nxy : float, optional
        Shear flow (N/m).
    stiffener : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-).
    panel_width : float or None, optional
        Width of the stiffened panel between spars (m).
    fixity : float, optional
        End-fixity coefficient of the stiffener column (-).

    Returns
    -------
    dict
        Critical loads, failure ratios, smeared properties and mass per area, as floats.
    """
    if pm.is_laminate:
        ply = pm.base
        mat = {"name": ply.name, "E11_pa": ply.E11, "E22_pa": ply.E22, "G12_pa": ply.G12, "nu12": ply.nu12,
               "ply_fractions": list(pm.fractions), "Ex_pa": float(pm.E_x),
               "compression_strength_pa": pm.compression_strength}
    else:
        mat = {"name": pm.name, "E_pa": pm.base.E, "nu": pm.base.nu, "sigma_y_pa": pm.base.sigma_y}
    skin = pm.abd(t)
    crit = panel_critical_loads(pm, t, b, a, h, ts, stiffener, flange_ratio, panel_width, fixity)
    ratios = panel_failure_ratios(pm, t, b, a, h, ts, nx, nxy, stiffener, flange_ratio, panel_width, fixity,
                                  critical=crit)
    ratios["skin_compression_shear"] = ratios.pop("skin_buckling")
    ratios["panel_compression_shear"] = ratios.pop("panel_buckling")
    ratios = {k: _num(ratios[k]) for k in RATIO_KEYS}
    given = {k: v for k, v in ratios.items() if v is not None}
    out = {"material": mat,
           "inputs": {"skin_thickness_m": t, "width_m": b, "length_m": a, "stiffener_height_m": h,
                      "stiffener_thickness_m": ts, "stiffener": None if h is None else stiffener,
                      "flange_ratio": flange_ratio if (h is not None and stiffener == "tee") else None,
                      "nx_n_per_m": nx, "nxy_n_per_m": nxy},
           "D": {k: _num(skin[k]) for k in ("D11", "D22", "D12", "D66")},
           "critical_running_loads_n_per_m": {k: _num(crit[k]) for k in CRITICAL_KEYS},
           "failure_ratios": ratios,
           "critical_mode": max(given, key=given.get)}
    if h is not None:
        sm = smeared_properties(t, b, h, ts, stiffener, flange_ratio, pm.E_x)
        out["smeared"] = {"pitch_m": _num(sm["pitch"]), "area_per_width_m": _num(sm["area_per_width"]),
                          "neutral_axis_offset_m": _num(sm["z_na"]), "EI_per_width_n_m": _num(sm["EI_per_width"])}
    return out
