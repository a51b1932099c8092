"""Vortex-lattice method of a wing planform: the steady aerodynamic influence of every beam
station's incidence on every station's lift and moment (no OpenMDAO).

Lattice. The half wing is the mean surface through the beam's jig nodes r_i (body axes: x aft,
y outboard, z up): at node i the streamwise chord c_i has its leading edge at
``x_i - ref_point_i c_i``; between nodes the leading and trailing edges are straight (taper,
sweep, dihedral follow the nodes). Each beam element is cut into ``n_spanwise`` equal spanwise
strips and every strip into ``n_chordwise`` equal chordwise panels. Each panel carries a
horseshoe vortex: its bound leg on the panel's quarter-chord line, its trailing legs streamwise
(+x) to infinity; flow tangency is enforced at the panel's three-quarter-chord point of mid-span
(Katz & Plotkin, "Low-Speed Aerodynamics", 2nd ed., Cambridge University Press, 2001,
Sec. 12.3; Bertin & Cummings, "Aerodynamics for Engineers", 5th ed., 2009, Sec. 7.4). The left
half is the explicit mirror image, its horseshoes added to the influence of every right-half panel
(symmetric loading), or subtracted (``antisymmetric=True``: the left half carries the negative
circulation, as in a rolling wing with ailerons deflected opposite, :mod:`wingmdao.aero.roll`).

Compressibility by the Prandtl-Glauert (Goethert) rule: the lattice is stretched in x by
1 / beta, beta = sqrt(1 - M^2), and solved incompressibly; the lift per span of the compressible
wing is rho V Gamma of the stretched wing (Katz & Plotkin Sec. 8.3;
:mod:`wingmdao.aero.weissinger` uses the same rule), its chordwise positions those of the real
wing.

Stations. The beam carries lift and moment per unit length at its nodes (trapezoidal between
nodes). The transfer is the virtual-work pair of the nodes' hat functions N_i(s): a panel's
incidence is sum_j N_j(s_k) alpha_j (the linear interpolation of the station incidences), and
node i's load per length is sum_k N_i(s_k) F_k / w_i with w_i = int N_i ds the node's
tributary beam length. So

    L = q A_L alpha,   M_qc = q A_M alpha

(q = rho V^2 / 2; L in N/m along the section normal; M_qc in N m/m nose up about each
station's quarter-chord point), with ``A_L`` (n, n) m and ``A_M`` (n, n) m^2 depending only on
the jig planform and the Mach number (:func:`station_influence`, cached). For strip theory
``A_L = diag(c_i a_i / beta)`` and ``A_M = 0``.

Control surfaces (:func:`flap_influence`). A trailing-edge surface is a set of panels aft of its
hinge line, the hinge on a chordwise panel edge (:func:`chord_fractions`); a deflection turns their
normals, so their boundary condition gets the normal-wash -V beta. Their columns on the same lattice
give the stations' lift and moment per radian of deflection and the hinge moments (docs/controls.md).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np

from wingmdao.aero.weissinger import segment_velocity, semi_infinite_velocity

#: default lattice density: chordwise panels, spanwise strips per beam element
N_CHORDWISE = 4
N_SPANWISE = 4
#: chordwise panels of a lattice whose flaps are panels (:func:`flap_influence`): the flap's lift and
#: hinge moments converge as 1 / n_chordwise (docs/aerodynamics-3d.md), 4 panels on a 25 % chord flap
FLAP_CHORDWISE = 16
_CACHE: dict = {}
_CACHE_SIZE = 32


@dataclass(frozen=True, eq=False)
class Lattice:
    """Panels of the right half wing (real, unstretched coordinates; m).

    ``bound_a``/``bound_b`` (m, 3): ends of each bound leg (inboard, outboard) on the panel's
    quarter chord; ``control`` (m, 3): the three-quarter-chord point of mid-span; ``normal``
    (m, 3): unit upward normal; ``span`` (m,): the bound leg's length in the y-z plane;
    ``x_quarter`` (m,): x of the local wing chord's quarter point at the panel's mid-span;
    ``hat`` (m, n): the nodes' hat functions at the panel's mid-span; ``tributary`` (n,): each
    node's tributary beam length int N_i ds (m); ``strip`` (m,): the spanwise strip index of each
    panel; ``strip_y``/``strip_chord`` (strips,): mid-span y and local chord of each strip;
    ``panel_chord`` (m,): each panel's streamwise chord at mid-span; ``mach``.
    Panel k = strip * n_chordwise + chordwise index.

    Parameters
    ----------
    bound_a : ndarray, shape (m, 3)
        Inboard end of each bound leg (m).
    bound_b : ndarray, shape (m, 3)
        Outboard end of each bound leg (m).
    control : ndarray, shape (m, 3)
        Control points (m).
    normal : ndarray, shape (m, 3)
        Unit upward normals.
    span : ndarray, shape (m,)
        Bound-leg length in the y-z plane (m).
    x_quarter : ndarray, shape (m,)
        x of the local quarter-chord point at mid-span (m).
    hat : ndarray, shape (m, n)
        Hat functions of the nodes at each panel's mid-span.
    tributary : ndarray, shape (n,)
        Tributary beam length of each node (m).
    strip : ndarray of int, shape (m,)
        Spanwise strip of each panel.
    strip_y : ndarray, shape (strips,)
        Mid-span y of each strip (m).
    strip_chord : ndarray, shape (strips,)
        Local chord of each strip (m).
    panel_chord : ndarray, shape (m,)
        Streamwise chord of each panel (m).
    mach : float
        Mach number.
    chord_start : ndarray, shape (m,), optional
        Leading edge of each panel as a fraction of the local chord.
    element : ndarray of int, shape (m,), optional
        Beam element (between nodes e and e + 1) of each panel.
    """

    bound_a: np.ndarray
    bound_b: np.ndarray
    control: np.ndarray
    normal: np.ndarray
    span: np.ndarray
    x_quarter: np.ndarray
    hat: np.ndarray
    tributary: np.ndarray
    strip: np.ndarray
    strip_y: np.ndarray
    strip_chord: np.ndarray
    panel_chord: np.ndarray
    mach: float
    chord_start: np.ndarray | None = None
    element: np.ndarray | None = None

    @property
    def beta(self) -> float:
        return float(np.sqrt(1.0 - self.mach ** 2))

    @property
    def area(self) -> float:
        """Planform area of both halves (m^2): the panels' streamwise chord times their y-z span."""
        return float(2.0 * np.sum(self.panel_chord * self.span))


@dataclass(frozen=True, eq=False)
class StationInfluence:
    """Aerodynamic influence of the stations' incidences (per unit dynamic pressure).

    ``lift`` (n, n) m: lift per length at station i (N/m per Pa per rad) of a unit incidence at
    station j; ``moment`` (n, n) m^2: moment per length about station i's quarter chord (nose up);
    ``tributary`` (n,) m; ``lattice`` the :class:`Lattice`; ``circulation`` (panels, n): panel
    circulations per unit airspeed and unit incidence of each station (m).

    Parameters
    ----------
    lift : ndarray, shape (n, n)
        Lift influence (m).
    moment : ndarray, shape (n, n)
        Quarter-chord moment influence (m^2).
    tributary : ndarray, shape (n,)
        Tributary beam length of each station (m).
    lattice : Lattice
        The lattice.
    circulation : ndarray, shape (panels, n)
        Panel circulations per unit airspeed and unit station incidence (m).
    """

    lift: np.ndarray
    moment: np.ndarray
    tributary: np.ndarray
    lattice: Lattice
    circulation: np.ndarray

    def lift_slope(self, area) -> float:
        """The wing's lift-curve slope CL_alpha (1/rad) on ``area`` (m^2, both halves): 2 int L ds / (q S)
        of a unit incidence at every station (the beam's trapezoid).

        Parameters
        ----------
        area : float
            Reference area of both halves (m^2).

        Returns
        -------
        float
            CL_alpha (1/rad).
        """
        return float(2.0 * self.tributary @ (self.lift @ np.ones(self.lift.shape[1])) / float(area))


def check_planform(node_positions, chord, ref_point, mach) -> tuple:
    """Validated (r (n, 3), chord (n,), ref_point (n,), mach); ValueError naming the input, value and range.

    Parameters
    ----------
    node_positions : array_like, shape (n, 3)
        Jig beam nodes (m), y >= 0 and increasing.
    chord : float or array_like, shape (n,)
        Streamwise chord (m), > 0.
    ref_point : float or array_like, shape (n,)
        Beam axis as a fraction of the chord aft of the leading edge, in [0, 1].
    mach : float
        Mach number, in [0, 1).

    Returns
    -------
    tuple
        ``(r, chord, ref_point, mach)``.
    """
    r = np.asarray(node_positions, dtype=float)
    if r.ndim != 2 or r.shape[1] != 3 or r.shape[0] < 2:
        raise ValueError(f"node_positions must be (n >= 2, 3) m, got shape {r.shape}")
    n = r.shape[0]
    c = np.broadcast_to(np.asarray(chord, dtype=float), (n,)).copy()
    ref = np.broadcast_to(np.asarray(ref_point, dtype=float), (n,)).copy()
    if not np.all(np.isfinite(r)):
        raise ValueError("node_positions must be finite (m)")
    bad = np.flatnonzero(~(np.isfinite(c) & (c > 0)))
    if bad.size:
        raise ValueError(f"chord must be > 0 m (a panel of zero area otherwise); got {c[bad[0]]!r} at station {bad[0]}")
    bad = np.flatnonzero(~(np.isfinite(ref) & (ref >= 0) & (ref <= 1)))
    if bad.size:
        raise ValueError(f"ref_point must be in [0, 1] (fraction of chord); got {ref[bad[0]]!r} at station {bad[0]}")
    if not (np.isfinite(mach) and 0.0 <= float(mach) < 1.0):
        raise ValueError(f"mach must be in [0, 1) (subsonic Prandtl-Glauert vortex lattice), got {mach}")
    if np.any(r[:, 1] < 0.0):
        i = int(np.flatnonzero(r[:, 1] < 0)[0])
        raise ValueError(f"node_positions: y = {r[i, 1]} m at station {i}; the half wing must lie at y >= 0 "
                         "(its mirror image is the left half; panels would cross the symmetry plane)")
    dy = np.diff(r[:, 1])
    bad = np.flatnonzero(~(dy > 0.0))
    if bad.size:
        e = int(bad[0])
        raise ValueError(f"node_positions: y must increase from root to tip (the panels of element {e} would have "
                         f"zero area or cross their neighbours); got y = {r[e, 1]} m then {r[e + 1, 1]} m")
    return r, c, ref, float(mach)


def chord_fractions(n_chordwise=N_CHORDWISE, hinges=()) -> np.ndarray:
    """Chordwise panel edges (fractions of the local chord, 0 ... 1) with every hinge line on an edge.

    Without hinges (or when every hinge falls on an edge of the ``n_chordwise`` equal panels) the
    equal division. Otherwise the chord is cut at the hinges and each piece gets
    ``max(1, round(n_chordwise x its length))`` equal panels, so the count may differ from
    ``n_chordwise`` by the rounding (a hinge at 0.7 with 4 panels: three panels ahead of it, one
    aft).

    Parameters
    ----------
    n_chordwise : int
        Chordwise panels of the equal division (at least 1).
    hinges : sequence of float
        Hinge lines, fractions of the chord in (0, 1).

    Returns
    -------
    ndarray
        Increasing panel edges from 0 to 1.
    """
    nc = int(n_chordwise)
    if nc < 1:
        raise ValueError(f"n_chordwise must be >= 1, got {n_chordwise}")
    equal = np.arange(nc + 1) / nc
    cuts = sorted({float(h) for h in hinges})
    for h in cuts:
        if not 0.0 < h < 1.0:
            raise ValueError(f"hinge = {h} is outside the chord; allowed range (0, 1)")
    if all(np.min(np.abs(equal - h)) < 1e-9 for h in cuts):
        return equal
    bounds = np.array([0.0] + cuts + [1.0])
    edges = [0.0]
    for a, b in zip(bounds[:-1], bounds[1:]):
        k = max(1, int(round(nc * (b - a))))
        edges += list(a + (b - a) * np.arange(1, k + 1) / k)
    return np.array(edges)


def build_lattice(node_positions, chord, ref_point, *, mach=0.0, n_chordwise=N_CHORDWISE,
                  n_spanwise=N_SPANWISE, fractions=None) -> Lattice:
    """The :class:`Lattice` of the half wing through the beam nodes (module docstring).

    Parameters
    ----------
    node_positions : array_like, shape (n, 3)
        Jig beam nodes (m).
    chord : float or array_like, shape (n,)
        Streamwise chord (m).
    ref_point : float or array_like, shape (n,)
        Beam axis as a fraction of the chord aft of the leading edge.
    mach : float
        Mach number, in [0, 1).
    n_chordwise : int
        Chordwise panels (at least 1).
    n_spanwise : int
        Spanwise strips per beam element (at least 1).
    fractions : array_like, optional
        Chordwise panel edges, fractions of the local chord from 0 to 1 (:func:`chord_fractions`);
        None: ``n_chordwise`` equal panels.

    Returns
    -------
    Lattice
        The lattice.
    """
    r, c, ref, mach = check_planform(node_positions, chord, ref_point, mach)
    nc, ns = int(n_chordwise), int(n_spanwise)
    if nc < 1 or ns < 1:
        raise ValueError(f"n_chordwise and n_spanwise must be >= 1, got {n_chordwise}, {n_spanwise}")
    edges = np.arange(nc + 1) / nc if fractions is None else np.asarray(fractions, dtype=float)
    if edges.ndim != 1 or edges.size < 2 or edges[0] != 0.0 or edges[-1] != 1.0 or np.any(np.diff(edges) <= 0):
        raise ValueError(f"fractions must increase from 0 to 1 (chordwise panel edges), got {fractions!r}")
    nc = edges.size - 1
    n = r.shape[0]
    le = r.copy()
    le[:, 0] -= ref * c
    # spanwise edges: ns equal strips per element, parameter t in [0, 1] along each element
    te = np.linspace(0.0, 1.0, ns + 1)
    tm = 0.5 * (te[1:] + te[:-1])
    A, B, P, N, S, XQ, H, strip_y, strip_c = [], [], [], [], [], [], [], [], []
    frac, width = edges[:-1], np.diff(edges)  # panel leading edges and widths, fractions of the local chord
    elem = []
    for e in range(n - 1):
        le_e = le[e] + te[:, None] * (le[e + 1] - le[e])
        c_e = c[e] + te * (c[e + 1] - c[e])
        le_m = le[e] + tm[:, None] * (le[e + 1] - le[e])
        c_m = c[e] + tm * (c[e + 1] - c[e])
        span_vec = le[e + 1] - le[e]
        span_vec[0] = 0.0
        nrm = np.cross(np.array([1.0, 0.0, 0.0]), span_vec)
        nrm /= np.linalg.norm(nrm)
        for j in range(ns):
            hat = np.zeros(n)
            hat[e], hat[e + 1] = 1.0 - tm[j], tm[j]
            strip_y.append(le_m[j, 1])
            strip_c.append(c_m[j])
            for k in range(nc):
                xa = le_e[j] + np.array([(frac[k] + 0.25 * width[k]) * c_e[j], 0.0, 0.0])
                xb = le_e[j + 1] + np.array([(frac[k] + 0.25 * width[k]) * c_e[j + 1], 0.0, 0.0])
                A.append(xa)
                B.append(xb)
                P.append(le_m[j] + np.array([(frac[k] + 0.75 * width[k]) * c_m[j], 0.0, 0.0]))
                elem.append(e)
                N.append(nrm)
                S.append(np.hypot(xb[1] - xa[1], xb[2] - xa[2]))
                XQ.append(le_m[j, 0] + 0.25 * c_m[j])
                H.append(hat)
    ds = np.linalg.norm(np.diff(r, axis=0), axis=1)
    trib = np.zeros(n)
    trib[:-1] += 0.5 * ds
    trib[1:] += 0.5 * ds
    m = len(A)
    return Lattice(bound_a=np.array(A), bound_b=np.array(B), control=np.array(P), normal=np.array(N),
                   span=np.array(S), x_quarter=np.array(XQ), hat=np.array(H), tributary=trib,
                   strip=np.repeat(np.arange(m // nc), nc), strip_y=np.array(strip_y), strip_chord=np.array(strip_c),
                   panel_chord=np.repeat(np.array(strip_c), nc) * np.tile(width, m // nc), mach=mach,
                   chord_start=np.tile(frac, m // nc), element=np.array(elem, dtype=int))


def _mirror(p):
    return p * np.array([1.0, -1.0, 1.0])


def _horseshoe_velocity(points, a, b):
    """Velocity (m_p, m_v, 3) at ``points`` of unit horseshoes with bound legs a -> b, trailing to +x."""
    P = points[:, None, :]
    ex = np.array([1.0, 0.0, 0.0])
    return segment_velocity(P, a[None], b[None]) + semi_infinite_velocity(P, b[None], ex) - semi_infinite_velocity(P, a[None], ex)


def normalwash_matrix(lat: Lattice, antisymmetric: bool = False) -> np.ndarray:
    """(m, m) normal velocity at each control point of unit circulation on each horseshoe and its
    mirror image (the image's circulation negative with ``antisymmetric``), in the stretched
    (Prandtl-Glauert) lattice.

    Parameters
    ----------
    lat : Lattice
        The lattice.
    antisymmetric : bool, optional
        The mirror image carries the negative circulation.

    Returns
    -------
    ndarray, shape (m, m)
        The normalwash matrix (1/m).
    """
    s = np.array([1.0 / lat.beta, 1.0, 1.0])
    pts, a, b = lat.control * s, lat.bound_a * s, lat.bound_b * s
    image = -1.0 if antisymmetric else 1.0
    v = _horseshoe_velocity(pts, a, b) + image * _horseshoe_velocity(pts, _mirror(b), _mirror(a))
    return np.einsum("ijk,ik->ij", v, lat.normal)


def solve_circulation(lat: Lattice, panel_incidence, antisymmetric: bool = False) -> np.ndarray:
    """Panel circulations per unit airspeed (m) for panel incidences (m,) or (m, k) rad.

    Parameters
    ----------
    lat : Lattice
        The lattice.
    panel_incidence : array_like, shape (m,) or (m, k)
        Panel incidences (rad).
    antisymmetric : bool, optional
        Antisymmetric mirror image (:func:`normalwash_matrix`).

    Returns
    -------
    ndarray, shape (m,) or (m, k)
        Circulations per unit airspeed (m).
    """
    W = normalwash_matrix(lat, antisymmetric)
    return np.linalg.solve(W, -np.asarray(panel_incidence, dtype=float))


def station_influence(node_positions, chord, ref_point, *, mach=0.0, n_chordwise=N_CHORDWISE,
                      n_spanwise=N_SPANWISE, fractions=None, antisymmetric=False) -> StationInfluence:
    """:class:`StationInfluence` of the beam stations (module docstring), cached by planform and Mach.

    ``node_positions`` (n, 3) m: the jig beam nodes (root first, y >= 0 increasing);
    ``chord`` (n,) m streamwise; ``ref_point`` (n,): the beam axis as a fraction of the chord aft
    of the leading edge; ``mach`` in [0, 1). Bad input (a chord <= 0, nodes not moving outboard,
    a node at y < 0, Mach outside [0, 1)) raises ValueError naming it.

    Parameters
    ----------
    node_positions : array_like, shape (n, 3)
        Jig beam nodes (m).
    chord : float or array_like, shape (n,)
        Streamwise chord (m).
    ref_point : float or array_like, shape (n,)
        Beam axis as a fraction of the chord aft of the leading edge.
    mach : float
        Mach number, in [0, 1).
    n_chordwise : int
        Chordwise panels.
    n_spanwise : int
        Spanwise strips per beam element.
    fractions : array_like, optional
        Chordwise panel edges (:func:`chord_fractions`); None: ``n_chordwise`` equal panels.
    antisymmetric : bool, optional
        The left half's loading the negative of the right's (:func:`normalwash_matrix`).

    Returns
    -------
    StationInfluence
        The influence (shared by the cache: do not modify).
    """
    return _influences(node_positions, chord, ref_point, mach, n_chordwise, n_spanwise, fractions, (),
                       antisymmetric)[0]


@dataclass(frozen=True, eq=False)
class FlapInfluence:
    """Aerodynamic influence of trailing-edge flaps modelled as deflected lattice panels (per unit q).

    A surface covers the beam nodes ``nodes`` (contiguous) and is hinged at ``hinge`` x the local
    chord; its panels are those of the elements between its first and last node whose leading edge
    lies at or aft of the hinge (the hinge is a panel edge, :func:`chord_fractions`; a panel is a flap
    panel when its bound vortex lies aft of the hinge). A deflection
    beta_j at each of its nodes gives the flap panels the incidence ``sum_j N_j(s_k) beta_j``
    (trailing edge down +, the hat functions of the station incidences); a uniform deflection is
    beta on every flap panel. The columns are the surfaces' nodes in order (``columns``: (surface,
    node) per column).

    ``lift`` (n, n_f) m: lift per length at station i per q and radian at flap column j;
    ``moment`` (n, n_f) m^2: moment per length about station i's quarter chord (nose up);
    ``hinge_station`` (n_s, n) m^3: hinge moment of surface s (N m, trailing edge down +, one
    half wing) per q and radian of incidence at station j; ``hinge_flap`` (n_s, n_f) m^3: the same
    per radian at flap column j.

    Parameters
    ----------
    lift : ndarray, shape (n, n_f)
        Lift influence of the flap columns (m).
    moment : ndarray, shape (n, n_f)
        Quarter-chord moment influence of the flap columns (m^2).
    hinge_station : ndarray, shape (n_s, n)
        Hinge moment per station incidence (m^3).
    hinge_flap : ndarray, shape (n_s, n_f)
        Hinge moment per flap-column deflection (m^3).
    columns : tuple
        (surface index, node) of each flap column.
    """

    lift: np.ndarray
    moment: np.ndarray
    hinge_station: np.ndarray
    hinge_flap: np.ndarray
    columns: tuple


def flap_influence(node_positions, chord, ref_point, surfaces, *, mach=0.0, n_chordwise=FLAP_CHORDWISE,
                   n_spanwise=N_SPANWISE, antisymmetric=False) -> tuple:
    """The stations' and the flaps' influence on one lattice whose chordwise panel edges hold every
    hinge (:func:`chord_fractions`): ``(StationInfluence, FlapInfluence)``, cached.

    Parameters
    ----------
    node_positions : array_like, shape (n, 3)
        Jig beam nodes (m).
    chord : float or array_like, shape (n,)
        Streamwise chord (m).
    ref_point : float or array_like, shape (n,)
        Beam axis as a fraction of the chord aft of the leading edge.
    surfaces : sequence of tuple
        ``(nodes, hinge)`` per surface: its node indices (contiguous, at least two) and hinge
        line (fraction of the chord aft of the leading edge, in (0, 1)).
    mach : float
        Mach number, in [0, 1).
    n_chordwise : int
        Chordwise panels of the equal division (:data:`FLAP_CHORDWISE`).
    n_spanwise : int
        Spanwise strips per beam element.
    antisymmetric : bool, optional
        The left half's loading (and flaps) the negative of the right's (:func:`normalwash_matrix`).

    Returns
    -------
    tuple
        ``(StationInfluence, FlapInfluence)`` (shared by the cache: do not modify).
    """
    srf = tuple((tuple(int(i) for i in nodes), float(h)) for nodes, h in surfaces)
    n = np.asarray(node_positions, dtype=float).reshape(-1, 3).shape[0]
    for nodes, _ in srf:
        if len(nodes) < 2 or nodes != tuple(range(nodes[0], nodes[0] + len(nodes))) or nodes[0] < 0 or nodes[-1] >= n:
            raise ValueError(f"flap nodes {list(nodes)}: allowed at least two contiguous node indices in 0 .. {n - 1}")
    fractions = chord_fractions(n_chordwise, [h for _, h in srf])
    return _influences(node_positions, chord, ref_point, mach, n_chordwise, n_spanwise, fractions, srf,
                       antisymmetric)


def _influences(node_positions, chord, ref_point, mach, n_chordwise, n_spanwise, fractions, surfaces,
                antisymmetric=False):
    r, c, ref, mach = check_planform(node_positions, chord, ref_point, mach)
    fr = None if fractions is None else np.asarray(fractions, dtype=float)
    key = hashlib.sha1(b"".join(np.ascontiguousarray(v).tobytes() for v in (r, c, ref))
                       + repr((mach, int(n_chordwise), int(n_spanwise), None if fr is None else fr.tolist(),
                               surfaces) + (("antisymmetric",) if antisymmetric else ())).encode()).hexdigest()
    if key in _CACHE:
        return _CACHE[key]
    lat = build_lattice(r, c, ref, mach=mach, n_chordwise=n_chordwise, n_spanwise=n_spanwise, fractions=fr)
    m, n = lat.hat.shape
    # flap columns: incidence N_j(s_k) on the panels of surface s aft of its hinge
    cols, masks, E = [], [], []
    bound_frac = lat.chord_start + 0.25 * lat.panel_chord / lat.strip_chord[lat.strip]  # bound leg, fraction of chord
    for k, (nodes, h) in enumerate(surfaces):
        on = ((lat.element >= nodes[0]) & (lat.element < nodes[-1]) & (bound_frac >= h - 1e-9))
        masks.append(on)
        for j in nodes:
            cols.append((k, j))
            E.append(np.where(on, lat.hat[:, j], 0.0))
    rhs = np.concatenate([lat.hat, np.array(E).T.reshape(m, -1)], axis=1) if E else lat.hat
    gamma = solve_circulation(lat, rhs, antisymmetric)  # (m, n + n_f): unit incidence of each station, then each flap column
    force = 2.0 * gamma * lat.span[:, None]  # normal force per q of each panel (m^2): rho V Gamma l / q
    x_bound = 0.5 * (lat.bound_a[:, 0] + lat.bound_b[:, 0])
    moment = force * (lat.x_quarter - x_bound)[:, None]  # nose up about the local quarter chord (m^3)
    w = lat.hat / lat.tributary[None, :]
    lift_all, moment_all = w.T @ force, w.T @ moment
    out = StationInfluence(lift=lift_all[:, :n], moment=moment_all[:, :n], tributary=lat.tributary, lattice=lat,
                           circulation=gamma[:, :n])
    flap = None
    if surfaces:
        x_le = lat.x_quarter - 0.25 * lat.strip_chord[lat.strip]
        hinge_rows = []
        for on, (_, h) in zip(masks, surfaces):
            arm = x_bound - (x_le + h * lat.strip_chord[lat.strip])  # aft of the hinge line (m)
            hinge_rows.append(-(on * arm) @ force)  # an upward force aft of the hinge: trailing edge up
        H = np.array(hinge_rows)
        flap = FlapInfluence(lift=lift_all[:, n:], moment=moment_all[:, n:], hinge_station=H[:, :n],
                             hinge_flap=H[:, n:], columns=tuple(cols))
    result = (out, flap)
    if len(_CACHE) >= _CACHE_SIZE:
        _CACHE.pop(next(iter(_CACHE)))
    _CACHE[key] = result
    return result


def flat_wing(semi_span, chord_of_y, *, sweep_quarter_deg=0.0, n_stations=21, ref_point=0.25, spacing="cosine"):
    """Beam nodes, chords and reference points of a flat wing of chord ``chord_of_y(y)`` (m) whose
    quarter-chord line is swept by ``sweep_quarter_deg``; the stations cosine-spaced (finer at the
    tip) or ``"uniform"``. Returns ``(node_positions, chord, ref_point)``; for tests and examples.

    Parameters
    ----------
    semi_span : float
        Semi-span (m).
    chord_of_y : callable
        Chord c(y) (m).
    sweep_quarter_deg : float
        Sweep of the quarter-chord line (deg).
    n_stations : int
        Number of stations.
    ref_point : float
        Beam axis as a fraction of the chord aft of the leading edge.
    spacing : str
        ``"cosine"`` or ``"uniform"``.

    Returns
    -------
    node_positions : ndarray, shape (n_stations, 3)
        Beam nodes (m).
    chord : ndarray, shape (n_stations,)
        Chords (m).
    ref_point : ndarray, shape (n_stations,)
        Reference points.
    """
    s = float(semi_span)
    k = np.arange(n_stations)
    y = s * (np.sin(0.5 * np.pi * k / (n_stations - 1)) if spacing == "cosine" else k / (n_stations - 1))
    c = np.asarray(chord_of_y(y), dtype=float)
    x_qc = y * np.tan(np.radians(sweep_quarter_deg))
    x_ref = x_qc + (ref_point - 0.25) * c
    return np.stack([x_ref, y, np.zeros_like(y)], axis=-1), c, np.full(y.size, float(ref_point))
