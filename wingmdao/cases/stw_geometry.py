"""Simple Transonic Wing (STW) of the MDO Aeroelastic Benchmark: planform, wingbox and beam
geometry (data: :mod:`wingmdao.cases.stw_data`; the case: :mod:`wingmdao.cases.stw`, which
re-exports these names)."""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np

from wingmdao.cases import stw_data as D
from wingmdao.beam.geometry import WingGeometry, polyline_beam

CUTS = ("normal", "streamwise")
HEIGHT_RULES = ("spars", "mean10")


# ------------------------------------------------------------------------------------------------
# Planform
# ------------------------------------------------------------------------------------------------
def _span_array(y, name="y") -> np.ndarray:
    arr = np.asarray(y, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite (m)")
    if np.any(arr < 0.0) or np.any(arr > D.SEMI_SPAN):
        raise ValueError(f"{name} must lie in [0, {D.SEMI_SPAN}] m (the nominal semi-span), got "
                         f"{float(arr.min()):g} .. {float(arr.max()):g} m")
    return arr


def chord(y) -> np.ndarray:
    """Streamwise chord: linear from 5 m at y = 0 to 1.5 m at the tip.

    Parameters
    ----------
    y : float or array_like
        Span position(s) (m), in [0, 14].

    Returns
    -------
    ndarray
        Chord (m).
    """
    y = _span_array(y)
    return D.ROOT_CHORD + (D.TIP_CHORD - D.ROOT_CHORD) * y / D.SEMI_SPAN


def leading_edge_x(y) -> np.ndarray:
    """x of the leading edge: straight, 7.5 m aft at the tip.

    Parameters
    ----------
    y : float or array_like
        Span position(s) (m), in [0, 14].

    Returns
    -------
    ndarray
        x (m aft of the root leading edge).
    """
    y = _span_array(y)
    return D.TIP_LE_OFFSET * y / D.SEMI_SPAN


def spar_x(y) -> tuple[np.ndarray, np.ndarray]:
    """x of the front and rear spars (m). Outboard of the side of body at 15 % and 65 % of the
    local chord; inboard the box is unswept: the spars keep their side-of-body x (wingGeometry.py).

    Parameters
    ----------
    y : float or array_like
        Span position(s) (m), in [0, 14].

    Returns
    -------
    front, rear : ndarray
        x of the front and rear spars (m aft of the root leading edge).
    """
    y = _span_array(y)
    ys = np.maximum(y, D.SOB_Y)
    le, c = leading_edge_x(ys), chord(ys)
    return le + D.FRONT_SPAR_FRACTION * c, le + D.REAR_SPAR_FRACTION * c


def rib_y() -> np.ndarray:
    """The 23 rib planes (m): 4 evenly spaced from the symmetry plane to the side of body (both
    included), 19 evenly spaced outboard of it, the last at the tip (model.rst). The benchmark's
    meshes put the end ribs 1 mm inside (``stw_data.RIB_Y_MESH``); here the nominal 0 and 14 m."""
    inner = np.linspace(0.0, D.SOB_Y, D.NUM_RIBS_CENTRE)
    outer = D.SOB_Y + (D.SEMI_SPAN - D.SOB_Y) * np.arange(1, D.NUM_RIBS_OUTER + 1) / D.NUM_RIBS_OUTER
    return np.concatenate([inner, outer])


# ------------------------------------------------------------------------------------------------
# Airfoil
# ------------------------------------------------------------------------------------------------
def airfoil_surfaces():
    """Functions upper(x), lower(x): z/c of the RAE 2822 surfaces at chord fraction x, linear
    interpolation of the benchmark's coordinates (upper: first point to the leading edge)."""
    xy = np.asarray(D.RAE2822_COORDINATES, dtype=float)
    ile = int(np.argmin(xy[:, 0]))
    up, lo = xy[: ile + 1][::-1], xy[ile:]
    return (lambda x: np.interp(x, up[:, 0], up[:, 1])), (lambda x: np.interp(x, lo[:, 0], lo[:, 1]))


def thickness_to_chord(x) -> np.ndarray:
    """RAE 2822 thickness (upper minus lower surface) over chord.

    Parameters
    ----------
    x : float or array_like
        Chord fraction(s), in [0, 1].

    Returns
    -------
    ndarray
        Thickness over chord (dimensionless).
    """
    x = np.asarray(x, dtype=float)
    if np.any(x < 0.0) or np.any(x > 1.0) or not np.all(np.isfinite(x)):
        raise ValueError("chord fractions must lie in [0, 1]")
    upper, lower = airfoil_surfaces()
    return upper(x) - lower(x)


# ------------------------------------------------------------------------------------------------
# Beam geometry
# ------------------------------------------------------------------------------------------------
@dataclass
class StwBeam:
    """The STW wingbox beam: the :class:`~wingmdao.sizing.WingGeometry` and the data behind it.

    Per node (n,): ``y`` span position (m), ``chord`` streamwise chord (m), ``axis_fraction``
    chord fraction of the beam axis in the streamwise section, ``front_spar_height`` and
    ``rear_spar_height`` (m, airfoil thickness at the spars), ``width_streamwise`` (m, spar to
    spar along x), ``sweep_deg`` (beam-axis sweep at the node; the mean of the two elements at
    the side-of-body kink). ``rib_y`` (23,) m and ``rib_nodes`` (23,) their node indices.

    Parameters
    ----------
    geometry : WingGeometry
        The beam's geometry.
    y : numpy.ndarray
        (n,) span positions (m).
    rib_y : numpy.ndarray
        (23,) rib positions (m).
    rib_nodes : numpy.ndarray
        (23,) node index of each rib.
    chord : numpy.ndarray
        (n,) streamwise chords (m).
    axis_fraction : numpy.ndarray
        (n,) beam axis as a chord fraction of the streamwise section (-).
    front_spar_height, rear_spar_height : numpy.ndarray
        (n,) airfoil thickness at the spars (m).
    width_streamwise : numpy.ndarray
        (n,) spar-to-spar width along x (m).
    sweep_deg : numpy.ndarray
        (n,) beam-axis sweep (deg).
    cut : {"normal", "streamwise"}
        Section cut of the box: normal to the beam axis or streamwise.
    height_rule : {"spars", "mean10"}
        How the box height is taken from the airfoil (:func:`beam_geometry`).
    """

    geometry: object  # wingmdao.sizing.WingGeometry
    y: np.ndarray
    rib_y: np.ndarray
    rib_nodes: np.ndarray
    chord: np.ndarray
    axis_fraction: np.ndarray
    front_spar_height: np.ndarray
    rear_spar_height: np.ndarray
    width_streamwise: np.ndarray
    sweep_deg: np.ndarray
    cut: str
    height_rule: str


def _elements_per_bay(num_nodes: int, bay_length: np.ndarray) -> np.ndarray:
    """Elements of every rib bay, >= 1 each, summing to num_nodes - 1, close to proportional to
    the bay lengths (largest remainders)."""
    total = num_nodes - 1
    target = total * bay_length / bay_length.sum()
    m = np.maximum(1, np.floor(target)).astype(int)
    while m.sum() < total:
        m[int(np.argmax(target - m))] += 1
    while m.sum() > total:
        k = np.flatnonzero(m > 1)
        m[k[int(np.argmin((target - m)[k]))]] -= 1
    return m


def node_y(num_nodes: int = D.NUM_RIBS) -> tuple[np.ndarray, np.ndarray]:
    """Span positions of the beam nodes, with a node on every rib.

    Parameters
    ----------
    num_nodes : int, optional
        Beam nodes, >= 23 (the ribs).

    Returns
    -------
    y : ndarray
        (num_nodes,) span positions (m).
    rib_nodes : ndarray
        Node index of each rib.

    Raises
    ------
    ValueError
        Fewer nodes than ribs or a non-integer count.
    """
    if isinstance(num_nodes, (bool, np.bool_)) or not isinstance(num_nodes, numbers.Integral):
        raise ValueError(f"stw num_nodes = {num_nodes!r}: must be an integer")
    if num_nodes < D.NUM_RIBS:
        raise ValueError(f"stw num_nodes = {num_nodes}: the beam needs a node at each of the "
                         f"{D.NUM_RIBS} ribs, so at least {D.NUM_RIBS} nodes")
    ribs = rib_y()
    per_bay = _elements_per_bay(int(num_nodes), np.diff(ribs))
    y = [ribs[0]]
    for k, m in enumerate(per_bay):
        y.extend(ribs[k] + (ribs[k + 1] - ribs[k]) * np.arange(1, m + 1) / m)
    y = np.array(y)
    y[-1] = ribs[-1]
    rib_nodes = np.concatenate([[0], np.cumsum(per_bay)])
    return y, rib_nodes


def beam_geometry(num_nodes: int = D.NUM_RIBS, *, cut: str = "normal", height_rule: str = "spars") -> StwBeam:
    """The wingbox beam with ``num_nodes`` nodes (>= 23: one per rib, more inside the bays).

    Nodes lie on the mid-box line, halfway between the spars in the streamwise section (x),
    in the chord plane (z = 0: no dihedral); outboard of the side of body the line is straight
    (sweep atan(6.1 / 14) = 23.5 deg), inboard it is unswept along y. Jig Euler angles from the
    polyline (``wingmdao.beam.geometry.polyline_beam``; the kink node takes the mean).

    ``cut``: ``"normal"`` (default) gives the box dimensions in the section normal to the beam
    axis, the streamwise spar-to-spar width times cos(sweep), the height unchanged (the
    convention of the wing-box case, docs/cases.md); ``"streamwise"`` the streamwise section.
    ``height_rule``: ``"spars"`` (default) the mean of the front and rear spar heights (airfoil
    thickness at the spars, the box taken as the rectangle of the spar-to-spar trapezoid);
    ``"mean10"`` the mean of ten heights between the spars (Eq. 4.12, as the PEGASUS and CRM
    cases). No non-structural mass: the benchmark has none.

    Parameters
    ----------
    num_nodes : int, optional
        Beam nodes, >= 23.
    cut : str, optional
        ``"normal"`` or ``"streamwise"`` (above).
    height_rule : str, optional
        ``"spars"`` or ``"mean10"`` (above).

    Returns
    -------
    StwBeam
        The beam geometry and the data behind it (m, deg).
    """
    if cut not in CUTS:
        raise ValueError(f"stw cut = {cut!r}; allowed: {', '.join(CUTS)}")
    if height_rule not in HEIGHT_RULES:
        raise ValueError(f"stw height_rule = {height_rule!r}; allowed: {', '.join(HEIGHT_RULES)}")
    y, rib_nodes = node_y(num_nodes)
    c = chord(y)
    le = leading_edge_x(y)
    xf, xr = spar_x(y)
    x_axis = 0.5 * (xf + xr)
    f_front, f_rear = (xf - le) / c, (xr - le) / c
    h_front = thickness_to_chord(f_front) * c
    h_rear = thickness_to_chord(f_rear) * c
    if height_rule == "spars":
        height = 0.5 * (h_front + h_rear)
    else:
        fr = np.linspace(0.0, 1.0, 10)[None, :]
        frac = f_front[:, None] + fr * (f_rear - f_front)[:, None]
        height = np.mean(thickness_to_chord(frac), axis=1) * c
    z = np.tan(np.radians(D.DIHEDRAL_DEG)) * y
    pos = np.column_stack([x_axis, y, z])
    beam = polyline_beam(pos, np.ones(y.size - 1, dtype=int))
    angles = beam.node_euler_angles
    sweep = -angles[:, 2]  # psi = atan2(-s_x, hypot(s_y, s_z)): minus the sweep
    width_s = xr - xf
    width = width_s * np.cos(sweep) if cut == "normal" else width_s.copy()
    geo = WingGeometry(node_positions=pos, node_euler_angles=angles, width=width, height=height,
                       nonstructural_mass_per_length=np.zeros(y.size), span_coordinate=y.copy())
    return StwBeam(geometry=geo, y=y, rib_y=rib_y(), rib_nodes=rib_nodes, chord=c,
                   axis_fraction=(x_axis - le) / c, front_spar_height=h_front, rear_spar_height=h_rear,
                   width_streamwise=width_s, sweep_deg=np.degrees(sweep), cut=cut, height_rule=height_rule)


# ------------------------------------------------------------------------------------------------
# Aerodynamic reference data
# ------------------------------------------------------------------------------------------------
@dataclass
class AeroReference:
    """Planform data per station and for the wing, for strip or lifting-line models.

    Per station (n,): ``y`` (m), ``chord`` (m, streamwise), ``leading_edge_x`` and
    ``quarter_chord_x`` (m aft of the root leading edge), ``quarter_chord_sweep_deg`` (local
    sweep of the quarter-chord line; constant: the planform is one trapezoid, the side-of-body
    break is in the wingbox only), ``twist_deg`` (zero: untwisted). Wing: ``semi_span`` (m),
    ``area`` (one wing, m^2), ``mac`` (m), ``aspect_ratio`` (2 b^2 / S), ``mach`` of the Case 1
    maneuvers.

    Parameters
    ----------
    y : numpy.ndarray
        (n,) span positions (m).
    chord : numpy.ndarray
        (n,) streamwise chords (m).
    leading_edge_x, quarter_chord_x : numpy.ndarray
        (n,) positions aft of the root leading edge (m).
    quarter_chord_sweep_deg : numpy.ndarray
        (n,) local quarter-chord sweep (deg).
    twist_deg : numpy.ndarray
        (n,) twist (deg).
    semi_span : float
        Semi-span (m).
    area : float
        Area of one wing (m^2).
    mac : float
        Mean aerodynamic chord (m).
    aspect_ratio : float
        2 b^2 / S (-).
    mach : float
        Mach number of the Case 1 maneuvers (-).
    """

    y: np.ndarray
    chord: np.ndarray
    leading_edge_x: np.ndarray
    quarter_chord_x: np.ndarray
    quarter_chord_sweep_deg: np.ndarray
    twist_deg: np.ndarray
    semi_span: float
    area: float
    mac: float
    aspect_ratio: float
    mach: float


def quarter_chord_sweep_deg() -> float:
    """Sweep of the quarter-chord line, deg (derived): atan((7.5 - 0.25 (5 - 1.5)) / 14) = 25.3 deg."""
    return float(np.degrees(np.arctan((D.TIP_LE_OFFSET + 0.25 * (D.TIP_CHORD - D.ROOT_CHORD)) / D.SEMI_SPAN)))


def aero_reference(y=None) -> AeroReference:
    """Planform data at span positions ``y`` (m, in [0, 14]; default: the 23 rib planes).

    Area and MAC are the integrals of the linear chord (S = int c dy, MAC = int c^2 dy / S); the
    benchmark states 45.5 m^2 and 3.56 m.

    Parameters
    ----------
    y : array_like, optional
        Span positions (m), in [0, 14]; None: the 23 rib planes.

    Returns
    -------
    AeroReference
        Per-station chord, leading edge, quarter-chord line (m, deg) and the wing's area (m^2),
        MAC (m) and aspect ratio.
    """
    y = rib_y() if y is None else _span_array(y)
    y = np.atleast_1d(y)
    c = chord(y)
    le = leading_edge_x(y)
    cr, ct, b = D.ROOT_CHORD, D.TIP_CHORD, D.SEMI_SPAN
    area = b * (cr + ct) / 2.0  # int c dy of the linear chord
    mac = b * (cr * cr + cr * ct + ct * ct) / 3.0 / area  # int c^2 dy / S
    return AeroReference(y=y, chord=c, leading_edge_x=le, quarter_chord_x=le + 0.25 * c,
                         quarter_chord_sweep_deg=np.full(y.size, quarter_chord_sweep_deg()),
                         twist_deg=np.zeros(y.size), semi_span=D.SEMI_SPAN, area=area, mac=mac,
                         aspect_ratio=2.0 * D.SEMI_SPAN**2 / area, mach=D.PULL_UP.mach)


# ------------------------------------------------------------------------------------------------
# The sizing case: wingmdao size stw
# ------------------------------------------------------------------------------------------------
#: load sets: both Case 1 maneuvers (the only one)
