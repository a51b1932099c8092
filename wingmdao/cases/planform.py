"""Trapezoidal wing planform -> beam mesh and box dimensions per rib station (Eq. 4.11-4.12).

Stations follow App. D.2: station 0 at the symmetry plane (the centre wingbox, a copy of
the root rib's section), stations 1..N at the ribs from the root rib to the tip rib, equally
spaced between their normalised span positions. The beam axis joins the box centres. Box
width (Eq. 4.11) is the mean of the upper and lower skin lengths between the spars; box
height (Eq. 4.12) the mean of ten heights between the spars, from the airfoil coordinates.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wingmdao.beam.geometry import WingGeometry, polyline_beam
from wingmdao.loads.atmosphere import FT, G0, LB  # noqa: F401  (G0: public here too)
from wingmdao.section.fe.airfoil import naca_surfaces


@dataclass(frozen=True)
class Planform:
    """A trapezoidal wing planform with its spars, ribs and airfoils.

    Parameters
    ----------
    area_ft2 : float
        Reference area of both wings (ft^2).
    span_ft : float
        Span tip to tip (ft).
    taper : float
        Tip over centre-line chord, (0, 1].
    le_sweep_deg : float
        Leading-edge sweep (deg).
    front_spar, rear_spar : float
        Spar positions (fractions of chord), 0 < front < rear < 1.
    root_rib, tip_rib : float
        Span positions of the root and tip ribs (fractions of the semi-span).
    num_ribs : int
        Ribs, stations 1..num_ribs (station 0: the symmetry plane).
    airfoil_root, airfoil_tip : str
        NACA 4-digit designations at the root and tip ribs.
    dihedral_deg : float, optional
        Dihedral (deg).

    Raises
    ------
    ValueError
        Spar, rib or taper values outside their ranges.
    """

    area_ft2: float
    span_ft: float
    taper: float
    le_sweep_deg: float
    front_spar: float  # fraction of chord
    rear_spar: float
    root_rib: float  # fraction of semi-span
    tip_rib: float
    num_ribs: int  # stations 1..num_ribs
    airfoil_root: str  # NACA designation
    airfoil_tip: str
    dihedral_deg: float = 0.0

    def __post_init__(self):
        if not (0.0 < self.front_spar < self.rear_spar < 1.0):
            raise ValueError(f"spar positions must satisfy 0 < front ({self.front_spar}) < rear ({self.rear_spar}) < 1")
        if not (0.0 <= self.root_rib < self.tip_rib <= 1.0):
            raise ValueError("rib span positions must satisfy 0 <= root < tip <= 1")
        if not (0.0 < self.taper <= 1.0):
            raise ValueError(f"taper ratio {self.taper} outside (0, 1]")

    @property
    def semi_span(self) -> float:
        return 0.5 * self.span_ft * FT

    @property
    def root_chord(self) -> float:
        """Centre-line chord of the trapezoid, m: S = b c_r (1 + taper) / 2."""
        return 2.0 * self.area_ft2 * FT**2 / (self.span_ft * FT * (1.0 + self.taper))

    def chord(self, y):
        """Streamwise chord.

        Parameters
        ----------
        y : float or array_like
            Span coordinate (m).

        Returns
        -------
        float or ndarray
            Chord (m).
        """
        return self.root_chord * (1.0 - (1.0 - self.taper) * np.asarray(y) / self.semi_span)

    def leading_edge_x(self, y):
        """Leading-edge x (aft) of the swept planform.

        Parameters
        ----------
        y : float or array_like
            Span coordinate (m).

        Returns
        -------
        float or ndarray
            x (m) from the centre-line leading edge.
        """
        return np.tan(np.radians(self.le_sweep_deg)) * np.asarray(y)

    def station_y(self) -> np.ndarray:
        """Span coordinates of the stations.

        Returns
        -------
        ndarray
            (num_ribs + 1,) y (m): 0 (the symmetry plane) and the ribs.
        """
        ribs = np.linspace(self.root_rib, self.tip_rib, self.num_ribs) * self.semi_span
        return np.concatenate([[0.0], ribs])


def box_dimensions(designation: str, chord: float, front: float, rear: float):
    """Box width (Eq. 4.11) and height (Eq. 4.12) between the spars of an airfoil.

    Parameters
    ----------
    designation : str
        NACA 4-digit designation.
    chord : float
        Chord (m).
    front, rear : float
        Spar positions (fractions of chord).

    Returns
    -------
    width : float
        Mean of the upper and lower skin lengths between the spars (m).
    height : float
        Mean of ten heights between the spars (m).
    """
    upper, lower = naca_surfaces(designation)
    xs = np.linspace(front, rear, 10)
    height = chord * float(np.mean(upper(xs) - lower(xs)))
    xf = np.linspace(front, rear, 200)
    w_up = chord * float(np.sum(np.hypot(np.diff(xf), np.diff(upper(xf)))))
    w_lo = chord * float(np.sum(np.hypot(np.diff(xf), np.diff(lower(xf)))))
    return 0.5 * (w_up + w_lo), height


def interpolate_designation(root: str, tip: str, fraction: float) -> str:
    """NACA designation with the thickness (last two digits) interpolated root -> tip.

    Parameters
    ----------
    root, tip : str
        NACA 4-digit designations.
    fraction : float
        0 at the root, 1 at the tip.

    Returns
    -------
    str
        The interpolated designation.
    """
    t = round((1 - fraction) * int(root[-2:]) + fraction * int(tip[-2:]))
    return root[:-2] + f"{t:02d}"


def wing_geometry(pf: Planform, point_masses=()):
    """Beam mesh (box centres), box width/height, chord and beam-axis chord fraction per station.

    Parameters
    ----------
    pf : Planform
        The planform.
    point_masses : sequence of (float, float), optional
        (mass kg, y m) pairs smeared as non-structural mass over the element lengths next to
        the nearest station (their integral equals the mass).

    Returns
    -------
    geometry : wingmdao.beam.geometry.WingGeometry
        Beam mesh at the box centres (m), box width and height (m).
    chord : ndarray
        (n,) chord (m).
    beam_axis_fraction : ndarray
        (n,) chord fraction of the beam axis.
    """
    y = pf.station_y()
    y_sec = np.where(y < pf.root_rib * pf.semi_span, pf.root_rib * pf.semi_span, y)  # centre box = root rib
    chord = pf.chord(y_sec)
    frac = (y_sec - y_sec[0]) / (y_sec[-1] - y_sec[0])
    dims = [box_dimensions(interpolate_designation(pf.airfoil_root, pf.airfoil_tip, f), c,
                           pf.front_spar, pf.rear_spar) for f, c in zip(frac, chord)]
    width = np.array([d[0] for d in dims])
    height = np.array([d[1] for d in dims])
    axis_frac = np.full(y.size, 0.5 * (pf.front_spar + pf.rear_spar))
    x = pf.leading_edge_x(y_sec) + axis_frac * chord
    x[0] = x[1]  # the centre wingbox is a prismatic continuation of the root rib section
    z = np.tan(np.radians(pf.dihedral_deg)) * y
    pos = np.column_stack([x, y, z])
    beam = polyline_beam(pos, np.ones(y.size - 1, dtype=int))  # jig Euler angles per node
    angles = beam.node_euler_angles
    seg = np.diff(pos, axis=0)
    nsm = np.zeros(y.size)
    ds = np.linalg.norm(seg, axis=1)
    trib = np.zeros(y.size)
    trib[:-1] += 0.5 * ds
    trib[1:] += 0.5 * ds
    for mass, y_m in point_masses:
        k = int(np.argmin(np.abs(y - y_m)))
        nsm[k] += mass / trib[k]
    station_map = np.concatenate([[0], np.arange(y.size - 1)])  # centre box repeats the root rib
    geo = WingGeometry(node_positions=pos, node_euler_angles=angles, width=width, height=height,
                       nonstructural_mass_per_length=nsm, span_coordinate=y, station_map=station_map)
    return geo, chord, axis_frac
