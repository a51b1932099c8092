"""App. D.1 'wing-like' box: the geometry tables (Tables D.1, D.2, E.2), defined once.

Transcribed by hand from the dissertation (:data:`wingmdao.DISSERTATION`), SI:

* Table D.1: spanwise (y) distances between the cross-sections CS1..CS4: d = 3, 4, 3 m;
  heights h1..h4 = 0.5 m.
* Table D.2: widths w1..w4, leading-edge sweeps lambda_1..3 per segment and one dihedral.
* Table E.2: spar thickness 0.2 m, skin thickness 0.1 m (streamwise cut).

The sections are streamwise cuts parallel to the root. Segment k's sweep is that of the
leading edge (front face): from CS k to CS k+1 the box centre moves aft by
d_k tan(lambda_k) - (w_k - w_{k+1}) / 2 and up by d_k tan(dihedral). Used by the beam case
(this package) and by the independent solid model (:mod:`wingmdao.verification.wingbox_solid`).
"""

from __future__ import annotations

import numpy as np

from wingmdao.beam.geometry import swept_dihedral_points
from wingmdao.names import WING_BOX_GEOMETRIES as GEOMETRIES  # Table D.2: widths (m), sweeps, dihedral (deg)
from wingmdao.names import WING_BOX_T_SKIN as T_SKIN, WING_BOX_T_SPAR as T_SPAR  # noqa: F401  (Table E.2, m)

SPANS = (3.0, 4.0, 3.0)                      # Table D.1, d1..d3 (m)
HEIGHTS = (0.5, 0.5, 0.5, 0.5)               # Table D.1, h1..h4 (m)
STATIONS = ("CS1", "CS2", "CS3", "CS4")


def geometry_data(name: str) -> dict:
    """The Table D.2 row of a geometry.

    Parameters
    ----------
    name : str
        A key of ``GEOMETRIES``.

    Returns
    -------
    dict
        Its widths and heights (m), sweeps and dihedral (deg).

    Raises
    ------
    ValueError
        An unknown name (the message lists the names).
    """
    if name not in GEOMETRIES:
        raise ValueError(f"geometry must be one of {list(GEOMETRIES)}, got {name!r}")
    return GEOMETRIES[name]


def section_centres(name: str) -> np.ndarray:
    """Centres of the sections CS1..CS4, body axes, CS1 at the origin.

    Parameters
    ----------
    name : str
        A key of ``GEOMETRIES``.

    Returns
    -------
    ndarray
        (4, 3) centres (m).
    """
    g = geometry_data(name)
    w = np.asarray(g["widths"])
    return swept_dihedral_points(SPANS, g["sweeps_deg"], g["dihedral_deg"], offsets_x=-0.5 * (w[:-1] - w[1:]))
