"""Where the stiffened panels of a wingbox sit and how their stiffeners are shaped.

A stiffened box (section kind ``"stiffened"``) has spanwise stiffeners on the inner faces of the
upper and lower skins, at a pitch per skin, and ribs at given stations; the spar webs are
unstiffened plates between the skins. Each station's panels are as long as the rib pitch there
(the distance between the ribs on either side of the station), so no equality constraint ties
the panel length to the rib positions.

Stiffener shapes (the web of height ``h`` and thickness ``ts`` standing normal to the skin):

* ``"blade"``: the web alone, bonded or riveted to the skin along its foot;
* ``"tee"``: the web standing on a flange of width ``flange_ratio * h`` and thickness ``ts``
  that lies on the skin (the flange width tied to the web height, as practitioners size them).

The stiffener's elements and the panel modes are those of :mod:`wingmdao.panels.stiffened`.

Every function here is plain arithmetic, so it evaluates on floats, numpy arrays and CasADi
symbols alike (the OpenMDAO components take their exact partials from CasADi).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from wingmdao.panels.laminate import laminate_moduli
from wingmdao.panels.stiffened import DEFAULT_FLANGE_RATIO, STIFFENERS, PanelMaterial, stiffener_elements

#: design variables of the stiffeners, per station (m): web height and thickness on each skin
STIFFENER_VARS = ("h_upper_stiffener", "t_upper_stiffener", "h_lower_stiffener", "t_lower_stiffener")
#: the skins that carry stiffeners, with their stiffener variables (height, thickness)
STIFFENED_SKINS = {"upper_skin": ("h_upper_stiffener", "t_upper_stiffener"),
                   "lower_skin": ("h_lower_stiffener", "t_lower_stiffener")}
STIFFENER_SHAPES = STIFFENERS
#: panel failure modes (constraint families of components.panels.PanelFailure) and their points
#: per station: the skins at their front and rear edges (4), the spar webs (2)
PANEL_FAMILIES = {"skin_buckling": 4, "panel_buckling": 4, "stiffener_column": 4, "stiffener_crippling": 4,
                  "web_buckling": 2}
#: the strength family of laminate walls (Tsai-Wu first-ply failure at the 4 skin and 2 web points;
#: metal walls keep the box's von Mises family instead)
LAMINATE_FAMILIES = {"laminate_strength": 6}


def panel_families(laminate: bool) -> dict:
    """The panel constraint families and their points per station (laminate walls add the
    laminate strength family).

    Parameters
    ----------
    laminate : bool
        Whether any wall is a laminate.

    Returns
    -------
    dict
        Family name -> number of constraint points per station.
    """
    return {**PANEL_FAMILIES, **(LAMINATE_FAMILIES if laminate else {})}


def stiffener_section(h, ts, shape: str = "blade", flange_ratio: float = DEFAULT_FLANGE_RATIO):
    """Area (m^2), centroid height above the skin's inner face (m) and own second moment of area
    about that centroid for bending out of the skin's plane (m^4) of one stiffener, from its flat
    elements (:func:`wingmdao.panels.stiffened.stiffener_elements`: the blade's web; the tee's
    flange on the skin and the web on top of it), by the parallel-axis theorem.

    Parameters
    ----------
    h : float, array_like or casadi.SX
        Stiffener web height (m).
    ts : float, array_like or casadi.SX
        Stiffener thickness (m).
    shape : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-).

    Returns
    -------
    tuple
        Area (m^2), centroid height above the skin's inner face (m), own second moment (m^4).
    """
    elements = stiffener_elements(h, ts, shape, flange_ratio)
    area = sum(w * t for w, t, *_ in elements)
    z = sum(w * t * zc for w, t, zc, *_ in elements) / area
    i_own = sum(i + w * t * (zc - z) ** 2 for w, t, zc, i, _ in elements)
    return area, z, i_own


def smeared_stringer(h, ts, pitch, shape: str = "blade", flange_ratio: float = DEFAULT_FLANGE_RATIO):
    """``(a, d, i)`` per unit skin width for :func:`wingmdao.section.box.stringer_layers`: the
    stiffener area per width (m), its centroid's depth below the skin's inner face (m) and its
    own second moment per width (m^3).

    Parameters
    ----------
    h : float, array_like or casadi.SX
        Stiffener web height (m).
    ts : float, array_like or casadi.SX
        Stiffener thickness (m).
    pitch : float
        Stiffener pitch (m).
    shape : {"blade", "tee"}, optional
        Stiffener shape.
    flange_ratio : float, optional
        Tee flange width over web height (-).

    Returns
    -------
    tuple
        Area per width (m), centroid depth below the skin's inner face (m), own second moment per
        width (m^3).
    """
    area, z, i_own = stiffener_section(h, ts, shape, flange_ratio)
    return area / pitch, z, i_own / pitch


def rib_pitch_at_stations(span_coordinate, rib_positions) -> np.ndarray:
    """Panel length (m) at each station: the distance between the nearest rib at or inboard of
    the station and the next rib outboard of it (the bay the station's panels sit in); a station
    on a rib takes the longer of its two bays. ``span_coordinate`` (n,) and ``rib_positions``
    (sorted, at least two) in m along the same spanwise coordinate.

    Parameters
    ----------
    span_coordinate : array_like
        (n,) station coordinates along the span (m).
    rib_positions : array_like
        Sorted rib coordinates along the same span coordinate (m), at least two.

    Returns
    -------
    numpy.ndarray
        (n,) panel length at each station (m).
    """
    y = np.asarray(span_coordinate, dtype=float)
    ribs = np.asarray(rib_positions, dtype=float)
    if ribs.ndim != 1 or ribs.size < 2 or not np.all(np.isfinite(ribs)):
        raise ValueError(f"rib positions: at least two finite values (m) needed, got {ribs.tolist()}")
    if np.any(np.diff(ribs) <= 0.0):
        raise ValueError(f"rib positions = {ribs.tolist()} m: must increase strictly (rib pitch > 0)")
    tol = 1e-9 * max(1.0, float(np.max(np.abs(ribs))))
    if y.min() < ribs[0] - tol or y.max() > ribs[-1] + tol:
        bad = y[(y < ribs[0] - tol) | (y > ribs[-1] + tol)][0]
        raise ValueError(f"station at {bad:.6g} m lies outside the ribs [{ribs[0]:.6g}, {ribs[-1]:.6g}] m; "
                         "every station needs a rib bay (ribs must span the stations)")
    bays = np.diff(ribs)
    out = np.empty(y.size)
    for k, yk in enumerate(y):
        on = np.flatnonzero(np.abs(ribs - yk) <= tol)
        if on.size:
            j = int(on[0])
            out[k] = max(bays[j - 1] if j > 0 else 0.0, bays[j] if j < bays.size else 0.0)
        else:
            j = int(np.searchsorted(ribs, yk) - 1)
            out[k] = bays[j]
    return out


def rib_weights(span_coordinate, rib_positions) -> np.ndarray:
    """(n,) ribs attributed to each station: a rib at a station counts 1 there; a rib between two
    stations is shared between them in proportion to its distance from each (linear
    interpolation of the box's width times height). Ribs at a negative span coordinate belong to
    the mirrored half-wing (they close the centre-box bay across the symmetry plane) and are not
    counted; ValueError for a rib outside the stations.

    Parameters
    ----------
    span_coordinate : array_like
        (n,) station coordinates along the span (m).
    rib_positions : array_like
        Rib coordinates along the same span coordinate (m).

    Returns
    -------
    numpy.ndarray
        (n,) number of ribs attributed to each station (-).
    """
    y = np.asarray(span_coordinate, dtype=float)
    out = np.zeros(y.size)
    tol = 1e-9 * max(1.0, float(np.max(np.abs(y))))
    for r in rib_positions:
        if r < 0.0:
            continue
        if r < y[0] - tol or r > y[-1] + tol:
            raise ValueError(f"rib at {r:.6g} m lies outside the stations [{y[0]:.6g}, {y[-1]:.6g}] m")
        j = int(np.clip(np.searchsorted(y, r) - 1, 0, y.size - 2))
        f = float(np.clip((r - y[j]) / (y[j + 1] - y[j]), 0.0, 1.0))
        out[j] += 1.0 - f
        out[j + 1] += f
    return out


@dataclass(frozen=True)
class PanelLayout:
    """The stiffened panels of a wingbox (section kind ``"stiffened"``).

    Parameters
    ----------
    rib_positions : sequence of float
        Spanwise rib coordinates (m, the case's span coordinate), sorted, spanning the stations.
    stiffener_pitch : float
        Stiffener spacing on both skins (m).
    shape : str
        Stiffener shape, ``"blade"`` or ``"tee"`` (module docstring).
    flange_ratio : float
        Tee flange width over web height (ignored for blades).
    safety_factor : float
        Factor on the loads for buckling and crippling (the failure ratio times it must stay
        <= 1); 1.5 is the ultimate factor of 14 CFR 25.303 when the loads are limit loads.
    rib_thickness : float
        Minimum rib web thickness (m): the ribs' mass in the optimization; the result sizes each
        rib for crushing from there.
    skin_material, spar_material : PanelMaterial or None
        Laminates (or metals) of the skins with their stiffeners and of the spar webs
        (:class:`wingmdao.panels.stiffened.PanelMaterial`); None: the sizing's isotropic material.
        The section then weights each wall by its membrane modulus, shear modulus and density
        relative to the sizing's material (the transformed section, :meth:`wall_factors`).
    """

    rib_positions: tuple
    stiffener_pitch: float = 0.15
    shape: str = "blade"
    flange_ratio: float = DEFAULT_FLANGE_RATIO
    safety_factor: float = 1.5
    rib_thickness: float = 0.002
    skin_material: PanelMaterial | None = None
    spar_material: PanelMaterial | None = None

    def __post_init__(self):
        object.__setattr__(self, "rib_positions", tuple(float(r) for r in self.rib_positions))
        for name in ("stiffener_pitch", "safety_factor", "rib_thickness"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0.0):
                raise ValueError(f"PanelLayout: {name} = {v}; allowed range (0, inf)")
        if self.shape not in STIFFENER_SHAPES:
            raise ValueError(f"PanelLayout: shape = {self.shape!r}; allowed: {', '.join(STIFFENER_SHAPES)}")
        if self.shape == "tee" and not (math.isfinite(self.flange_ratio) and self.flange_ratio > 0.0):
            raise ValueError(f"PanelLayout: flange_ratio = {self.flange_ratio} for tee stiffeners; "
                             "allowed range (0, inf)")

    @property
    def laminate(self) -> bool:
        """Whether any wall is a laminate (then the laminate strength family replaces von Mises)."""
        return any(m is not None and m.is_laminate for m in (self.skin_material, self.spar_material))

    def wall_factors(self, material) -> tuple:
        """(e, g, r) of the skins and of the spar webs against the isotropic ``material``: membrane
        modulus E_x / E, shear modulus G_xy / G and density rho_wall / rho (1 for a wall of the
        sizing's own material): six floats, skins first.

        Parameters
        ----------
        material : Material
            The sizing's isotropic material.

        Returns
        -------
        tuple of 6 floats
            (e, g, r) of the skins, then of the spar webs (-).
        """
        out = []
        for pm in (self.skin_material, self.spar_material):
            if pm is None:
                out += [1.0, 1.0, 1.0]
            elif pm.is_laminate:
                m = laminate_moduli(pm.base, pm.fractions)
                out += [m["Ex"] / material.E, m["Gxy"] / material.G, pm.base.rho / material.rho]
            else:
                out += [pm.base.E / material.E, pm.base.G / material.G, pm.base.rho / material.rho]
        return tuple(float(v) for v in out)

    def rib_material(self, material) -> tuple:
        """(E, nu, rho) of the ribs: the spar webs' material (a laminate by its membrane Ex and
        nu_xy: the crushing check treats the rib web as isotropic), else ``material``.

        Parameters
        ----------
        material : Material
            The sizing's isotropic material.

        Returns
        -------
        tuple of 3 floats
            E (Pa), nu (-) and rho (kg/m^3) of the ribs.
        """
        pm = self.spar_material
        if pm is None:
            return material.E, material.nu, material.rho
        if pm.is_laminate:
            m = laminate_moduli(pm.base, pm.fractions)
            return m["Ex"], m["nu_xy"], pm.base.rho
        return pm.base.E, pm.base.nu, pm.base.rho

    def panel_lengths(self, span_coordinate) -> np.ndarray:
        """Panel length (rib pitch) at each station, m (:func:`rib_pitch_at_stations`).

        Parameters
        ----------
        span_coordinate : array_like
            (n,) station coordinates along the span (m).

        Returns
        -------
        numpy.ndarray
            (n,) rib pitch at each station (m).
        """
        return rib_pitch_at_stations(span_coordinate, self.rib_positions)

    def max_stiffener_height(self) -> float:
        """Largest web height whose tee flange still fits in the pitch (flange width <= pitch), m;
        inf for blades."""
        return self.stiffener_pitch / self.flange_ratio if self.shape == "tee" else math.inf


def rib_crushing_ratio(E, nu, rib_thickness, rib_depth, rib_width, cover_load, curvature, rib_spacing, extra_load=0.0):
    """Crushing ratio of a rib web (1 = buckling of the web), load-linear in the square of the
    bending moment.

    The covers of a bent box follow its curvature kappa; a cover carrying the running load N
    (N/m, per unit chord) then presses on each rib with ``q = |N kappa| s`` per unit chord, s the
    rib spacing (the crushing or Brazier load: Niu, *Airframe Structural Design*, Ch. 9, rib
    crushing load; Brazier 1927). The compression cover pushes and the tension cover pulls
    toward the neutral axis, so the rib web between them is compressed at sigma = q / t_rib.
    Its elastic buckling stress, as a plate simply supported on all edges, loaded on its edges
    of length ``rib_width`` w over the depth h (Timoshenko & Gere, *Theory of Elastic Stability*,
    2nd ed., Sec. 9.2, m = 1): sigma_cr = pi^2 E t^2 / (12 (1 - nu^2) h^2) (1 + (h/w)^2)^2.
    Returns sigma / sigma_cr. Rib stiffeners and lightening holes are not modelled;
    ``extra_load`` (N/m per unit chord, default 0) adds a crushing load of other origin (the
    covers' kinks at the rib, :func:`wingmdao.panel_results.rib_summary`).

    Parameters
    ----------
    E : float
        Rib web Young's modulus (Pa).
    nu : float
        Rib web Poisson's ratio (-).
    rib_thickness : float or array_like
        Rib web thickness (m).
    rib_depth : float or array_like
        Rib depth, the box height (m).
    rib_width : float or array_like
        Rib width between the spars (m).
    cover_load : float or array_like
        Cover running load (N/m).
    curvature : float or array_like
        Bending curvature of the box (1/m).
    rib_spacing : float or array_like
        Rib pitch (m).
    extra_load : float or array_like, optional
        Crushing load of other origin (N/m per unit chord).

    Returns
    -------
    float or array_like
        Crushing ratio (-; 1 = web buckling).
    """
    q = np.abs(cover_load * curvature) * rib_spacing + np.abs(extra_load)
    sigma = q / rib_thickness
    sigma_cr = (np.pi**2 * E * rib_thickness**2 / (12.0 * (1.0 - nu**2) * rib_depth**2)
                * (1.0 + (rib_depth / rib_width) ** 2) ** 2)
    return sigma / sigma_cr


def rib_shear_ratio(E, nu, rib_thickness, rib_depth, rib_width, shear_force):
    """Shear buckling ratio of a rib web (1 = buckling): the shear ``shear_force`` V (N) that the
    rib delivers to a spar, over its depth h at tau = V / (h t_rib), against the web's elastic
    shear buckling stress as a plate simply supported on all edges (Timoshenko & Gere, *Theory
    of Elastic Stability*, 2nd ed., Sec. 9.7): tau_cr = k_s pi^2 E t^2 / (12 (1 - nu^2) s^2),
    k_s = 5.35 + 4 (s / l)^2, s and l the short and long sides of the depth x ``rib_width`` web.
    Scales as t_rib^-3.

    Parameters
    ----------
    E : float
        Rib web Young's modulus (Pa).
    nu : float
        Rib web Poisson's ratio (-).
    rib_thickness : float or array_like
        Rib web thickness (m).
    rib_depth : float or array_like
        Rib depth, the box height (m).
    rib_width : float or array_like
        Rib width between the spars (m).
    shear_force : float or array_like
        Shear the rib delivers to a spar (N).

    Returns
    -------
    float or array_like
        Shear buckling ratio (-; 1 = buckling).
    """
    short = np.minimum(rib_depth, rib_width)
    long_ = np.maximum(rib_depth, rib_width)
    tau = np.abs(shear_force) / (rib_depth * rib_thickness)
    tau_cr = ((5.35 + 4.0 * (short / long_) ** 2) * np.pi**2 * E * rib_thickness**2
              / (12.0 * (1.0 - nu**2) * short**2))
    return tau / tau_cr


def rib_web_ratio(crushing_ratio, shear_ratio):
    """Combined ratio of a rib web under crushing and shear: the load-linear R of the interaction
    R_c + R_s^2 = 1 (:func:`wingmdao.panels.buckling.interaction_ratio`),
    R = (R_c + sqrt(R_c^2 + 4 R_s^2)) / 2; with both ratios ~ t_rib^-3 so is R.

    Parameters
    ----------
    crushing_ratio : float or array_like
        Crushing ratio of :func:`rib_crushing_ratio` (-).
    shear_ratio : float or array_like
        Shear ratio of :func:`rib_shear_ratio` (-).

    Returns
    -------
    float or array_like
        Combined ratio (-; 1 = buckling).
    """
    return 0.5 * (crushing_ratio + np.sqrt(crushing_ratio**2 + 4.0 * shear_ratio**2))


def cover_kinks(span_coordinate, height, positions) -> np.ndarray:
    """Change of slope dh/ds (outboard minus inboard side, 1) of the box height at each position:
    the box is lofted linearly between the stations, so its covers kink at a station where the
    height's slope changes (zero between stations). At the first station the wing's other half
    mirrors the slope (inboard slope = -outboard slope). A cover at +-h/2 turns by half of it.

    Parameters
    ----------
    span_coordinate : array_like
        (n,) station coordinates along the span (m).
    height : array_like
        (n,) box height at the stations (m).
    positions : array_like
        Span coordinates where the kink is wanted (m).

    Returns
    -------
    numpy.ndarray
        Change of slope dh/ds at each position (-).
    """
    y = np.asarray(span_coordinate, dtype=float)
    h = np.asarray(height, dtype=float)
    slope = np.diff(h) / np.diff(y)
    inboard = np.concatenate([[-slope[0]], slope])
    outboard = np.concatenate([slope, [slope[-1]]])
    kink = outboard - inboard
    out = np.zeros(len(positions))
    for k, r in enumerate(positions):
        j = np.flatnonzero(np.abs(y - r) < 1e-6)
        out[k] = kink[j[0]] if j.size else 0.0
    return out
