"""Beam geometry: straight, swept, dihedral and tapered multi-segment beams.

A beam is a polyline of *key points* (e.g. the section centres CS1..CS4 of the App. D.1 box)
refined into elements per segment. Jig Euler angles follow the surface sequence of
:mod:`wingmdao.beam.rotations` (s along the segment, c in the horizontal plane for zero
twist). At a kink the node takes the mean of the two segments' angles, so only the two
elements next to the kink carry frames tilted by a quarter of the kink angle (the jig is still
an exact solution: the residual subtracts the jig terms). Section dimensions are interpolated
linearly in arc length along each segment.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wingmdao.beam.rotations import body_to_csn, euler_from_axis


@dataclass
class BeamGeometry:
    """Nodes of a refined polyline beam.

    Attributes: ``node_positions`` (n, 3) m; ``node_euler_angles`` (n, 3) rad;
    ``arc_length`` (n,) m from the root; ``key_nodes`` (indices of the key points);
    ``segment`` (n-1,) segment index of every element.

    Parameters
    ----------
    node_positions : ndarray, shape (n, 3)
        Node positions (m), body axes.
    node_euler_angles : ndarray, shape (n, 3)
        Jig Euler angles ``(phi, vartheta, psi)`` of each node (rad).
    arc_length : ndarray, shape (n,)
        Arc length from the root (m).
    key_nodes : ndarray of int, shape (k,)
        Node index of each key point.
    segment : ndarray of int, shape (n - 1,)
        Segment index of every element.
    """

    node_positions: np.ndarray
    node_euler_angles: np.ndarray
    arc_length: np.ndarray
    key_nodes: np.ndarray
    segment: np.ndarray

    @property
    def num_nodes(self) -> int:
        return self.node_positions.shape[0]

    def interpolate(self, key_values) -> np.ndarray:
        """Per-node values linear in arc length between the key points (e.g. box width).

        Parameters
        ----------
        key_values : array_like, shape (k,) or (k, m)
            Values at the key points (one row per key point).

        Returns
        -------
        ndarray, shape (n,) or (n, m)
            Values at the nodes.
        """
        key_values = np.asarray(key_values, dtype=float)
        if key_values.shape[0] != self.key_nodes.size:
            raise ValueError(f"need one value per key point ({self.key_nodes.size}), got {key_values.shape[0]}")
        s_key = self.arc_length[self.key_nodes]
        if key_values.ndim == 1:
            return np.interp(self.arc_length, s_key, key_values)
        return np.column_stack([np.interp(self.arc_length, s_key, v) for v in key_values.T])

    def csn_axes(self) -> np.ndarray:
        """T(theta0) of every node, (n, 3, 3): rows are the c, s, n unit vectors in body axes."""
        return np.array([body_to_csn(t) for t in self.node_euler_angles])


def polyline_beam(key_points, elements_per_segment, twist=0.0) -> BeamGeometry:
    """Refine the polyline ``key_points`` (k, 3) into ``elements_per_segment`` (k-1 ints) elements.

    ``twist`` (scalar or per key point, rad) is interpolated and stored as the twist angle.

    Parameters
    ----------
    key_points : array_like, shape (k, 3)
        Key points (m), body axes, k >= 2, no two consecutive ones equal.
    elements_per_segment : int or array_like of int, shape (k - 1,)
        Elements of each segment (at least 1).
    twist : float or array_like, shape (k,)
        Twist angle at the key points (rad).

    Returns
    -------
    BeamGeometry
        The refined beam.
    """
    pts = np.asarray(key_points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 3 or pts.shape[0] < 2:
        raise ValueError(f"key_points must have shape (k >= 2, 3), got {pts.shape}")
    n_el = np.broadcast_to(np.asarray(elements_per_segment, dtype=int), (pts.shape[0] - 1,))
    for k, m in enumerate(n_el):
        if m < 1:
            raise ValueError(f"elements_per_segment[{k}] must be >= 1, got {m}")
    seg_len = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    for k in np.flatnonzero(seg_len <= 0.0):
        raise ValueError(f"key_points {k} and {k + 1} coincide (segment length must be > 0 m)")
    seg_angles = [euler_from_axis(pts[k + 1] - pts[k]) for k in range(pts.shape[0] - 1)]
    r, seg, key = [pts[0]], [], [0]
    for k, m in enumerate(n_el):
        for j in range(1, m + 1):
            r.append(pts[k] + (pts[k + 1] - pts[k]) * j / m)
            seg.append(k)
        key.append(len(r) - 1)
    r = np.array(r)
    seg = np.array(seg)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(r, axis=0), axis=1))])
    angles = np.zeros((r.shape[0], 3))
    for i in range(r.shape[0]):
        touching = [seg[i - 1]] if i > 0 else []
        touching += [seg[i]] if i < seg.size else []
        angles[i] = np.mean([seg_angles[k] for k in sorted(set(touching))], axis=0)
    key = np.array(key)
    tw = np.broadcast_to(np.asarray(twist, dtype=float), (pts.shape[0],))
    angles[:, 1] = np.interp(arc, arc[key], tw)
    return BeamGeometry(r, angles, arc, key, seg)


def straight_geometry(length, num_elements, direction=(0.0, 1.0, 0.0)) -> BeamGeometry:
    """A straight beam from the origin along ``direction``.

    Parameters
    ----------
    length : float
        Beam length (m).
    num_elements : int
        Number of elements.
    direction : array_like, shape (3,)
        Beam direction in body axes (normalized here).

    Returns
    -------
    BeamGeometry
        The beam, ``num_elements + 1`` nodes.
    """
    d = np.asarray(direction, dtype=float)
    return polyline_beam([np.zeros(3), float(length) * d / np.linalg.norm(d)], [num_elements])


def swept_dihedral_points(spans, sweeps_deg=0.0, dihedral_deg=0.0, offsets_x=None) -> np.ndarray:
    """Key points from spanwise (y) distances: x += d tan(sweep) (+ offset), z += d tan(dihedral).

    ``sweeps_deg``/``dihedral_deg`` per segment (positive sweep moves the point aft, +x);
    ``offsets_x`` an extra aft shift per segment (m), e.g. minus half the width reduction
    of a box whose leading edge carries the sweep.

    Parameters
    ----------
    spans : array_like, shape (k,)
        Spanwise (y) length of each segment (m).
    sweeps_deg : float or array_like, shape (k,)
        Sweep of each segment (deg).
    dihedral_deg : float or array_like, shape (k,)
        Dihedral of each segment (deg).
    offsets_x : array_like, shape (k,), optional
        Extra aft (x) shift of each segment's end point (m).

    Returns
    -------
    ndarray, shape (k + 1, 3)
        Key points (m), the first at the origin.
    """
    d = np.asarray(spans, dtype=float)
    sw = np.radians(np.broadcast_to(np.asarray(sweeps_deg, dtype=float), d.shape))
    dh = np.radians(np.broadcast_to(np.asarray(dihedral_deg, dtype=float), d.shape))
    extra = np.zeros_like(d) if offsets_x is None else np.asarray(offsets_x, dtype=float)
    steps = np.column_stack([d * np.tan(sw) + extra, d, d * np.tan(dh)])
    return np.vstack([np.zeros(3), np.cumsum(steps, axis=0)])


def streamwise_to_normal(width, height, t_spar, t_skin, axis):
    """Box dimensions of the beam-normal section from the streamwise (x-z) cut.

    The s axis ``axis`` (unit, body) makes the angle Lambda with the y-z plane (sweep,
    cos Lambda = hypot(s_y, s_z)) and Gamma with the x-y plane (dihedral, cos Gamma =
    hypot(s_x, s_y)). A chordwise dimension measured in the streamwise cut shrinks by
    cos Lambda in the normal cut, a vertical one by cos Gamma. Returns (w, h, t_spar, t_skin).

    Parameters
    ----------
    width : float or ndarray
        Box width in the streamwise cut (m).
    height : float or ndarray
        Box height in the streamwise cut (m).
    t_spar : float or ndarray
        Spar thickness in the streamwise cut (m).
    t_skin : float or ndarray
        Skin thickness in the streamwise cut (m).
    axis : array_like, shape (3,)
        Beam axis s in body axes (normalized here).

    Returns
    -------
    tuple
        ``(width, height, t_spar, t_skin)`` of the normal section (m).
    """
    s = np.asarray(axis, dtype=float)
    s = s / np.linalg.norm(s)
    cos_sweep, cos_dih = np.hypot(s[1], s[2]), np.hypot(s[0], s[1])
    return width * cos_sweep, height * cos_dih, t_spar * cos_sweep, t_skin * cos_dih


def streamwise_section_to_csn(node_euler_angles) -> np.ndarray:
    """Rotation R (n, 3, 3) from streamwise-section axes to csn, for ``E_csn = R E_sec R^T`` (Eq. F.31).

    A streamwise cut is parallel to the root (x-z) plane, so its axes (chordwise, normal,
    vertical) are the body axes (x, y, z) and R = T(theta0) of each node. This is the
    alternative to :func:`streamwise_to_normal` (docs/beam-theory.md, section 9).

    Parameters
    ----------
    node_euler_angles : array_like, shape (n, 3)
        Jig Euler angles of the nodes (rad).

    Returns
    -------
    ndarray, shape (n, 3, 3)
        R of each node.
    """
    angles = np.asarray(node_euler_angles, dtype=float).reshape(-1, 3)
    return np.array([body_to_csn(a) for a in angles])


@dataclass
class WingGeometry:
    """Beam mesh and box outer dimensions per node (SI).

    Parameters
    ----------
    node_positions : ndarray, shape (n, 3)
        Node positions (m), body axes.
    node_euler_angles : ndarray, shape (n, 3)
        Jig Euler angles of each node (rad).
    width : ndarray, shape (n,)
        Box outer width (m).
    height : ndarray, shape (n,)
        Box outer height (m).
    section_to_csn : ndarray, shape (n, 3, 3), optional
        Rotation from section axes to csn at each node (:func:`streamwise_section_to_csn`).
    station_map : ndarray of int, shape (n,), optional
        Design index of each station; None: one design per station.
    nonstructural_mass_per_length : ndarray, shape (n,), optional
        Non-structural mass per length (kg/m).
    span_coordinate : ndarray, shape (n,), optional
        Span coordinate for plots (m); default y.
    """

    node_positions: np.ndarray  # (n, 3) m, body axes
    node_euler_angles: np.ndarray  # (n, 3) rad
    width: np.ndarray  # (n,) m, box outer width
    height: np.ndarray  # (n,) m, box outer height
    section_to_csn: np.ndarray | None = None  # (n, 3, 3)
    station_map: np.ndarray | None = None  # (n,) design index per station (None: one per station)
    nonstructural_mass_per_length: np.ndarray | None = None  # (n,) kg/m
    span_coordinate: np.ndarray | None = None  # (n,) m, for plots (default: y)

    @property
    def num_nodes(self) -> int:
        return int(np.asarray(self.node_positions).shape[0])
