"""Solid (C3D20R) model of a box wingbox for CalculiX: the wall cross-section of every streamwise
section meshed with a structured grid (``through`` elements through each wall thickness,
``chord_elements`` across the skins between the spars, ``height_elements`` along the spars
between the skins; the corner blocks belong to both), lofted linearly between the sections and
extruded along the span with 20-node quadratic hexahedra (reduced integration). Here the wall
thicknesses are those of the streamwise cut (the walls are prisms cut by the planes y = const).

Same loads and boundary conditions as the shell model (:mod:`wingmdao.fe.box_model`): root cross-
section clamped (three translations per node), ribs as solid slabs of the rib thickness filling
the box (one at the tip carries the tip load), loads as distributing-coupling nodal forces over
the wall nodes of a station cross-section. Station weights: the consistent nodal areas of the
8-node faces (corner -A/12, mid-side A/3 per face; they integrate quadratics exactly), so the
section average is the wall-area average and the coupling is statically exact.
"""

from __future__ import annotations

import numpy as np

from wingmdao.fe.box_model import WALLS, ShellBox, span_lines, BoxSections
from wingmdao.fe.calculix import Deck

#: C3D20R corners in (z index, x index) offsets: xi along z, eta along x, zeta along y (right-handed).
_CORNERS = ((0, 0), (2, 0), (2, 2), (0, 2))
_MIDS = ((1, 0), (2, 1), (1, 2), (0, 1))


def _breaks(lo, t_lo, t_hi, hi, through, inner):
    """Wall-grid coordinates (quadratic: with mid-points) from ``lo`` to ``hi``: ``through``
    elements in the walls of thickness t_lo, t_hi at either end, ``inner`` between."""
    e = np.concatenate([np.linspace(lo, lo + t_lo, through + 1),
                        np.linspace(lo + t_lo, hi - t_hi, inner + 1)[1:],
                        np.linspace(hi - t_hi, hi, through + 1)[1:]])
    q = np.empty(2 * len(e) - 1)
    q[0::2], q[1::2] = e, 0.5 * (e[:-1] + e[1:])
    return q


def cell_wall(i, k, m, nc, nh):
    """Wall index of grid cell (i along x, k along z): 0 upper skin, 1 lower skin, 2 front spar,
    3 rear spar, -1 the hollow interior.

    Parameters
    ----------
    i : int
        Cell index along x.
    k : int
        Cell index along z.
    m : int
        Cells through a wall's thickness.
    nc : int
        Interior cells across the chord.
    nh : int
        Interior cells up the height.

    Returns
    -------
    int
        Wall index, or -1 for the interior.
    """
    if k < m:
        return 1
    if k >= m + nh:
        return 0
    if i < m:
        return 2
    if i >= m + nc:
        return 3
    return -1


def _sample_cells(m, nc, nh):
    """Grid cells (i, k) of each of :data:`wingmdao.fe.stress_points.POINTS`."""
    lower, upper = range(m), range(m + nh, 2 * m + nh)
    front, rear = range(m), range(m + nc, 2 * m + nc)

    def centre(start, count):
        h = count // 2
        return [start + h - 1, start + h] if count % 2 == 0 else [start + h]

    cols = lambda ii, ks: [(i, k) for i in ii for k in ks]
    return [cols([m], lower), cols(front, [m]), cols([m + nc - 1], lower), cols(rear, [m]),
            cols([m + nc - 1], upper), cols(rear, [m + nh - 1]), cols([m], upper), cols(front, [m + nh - 1]),
            cols(centre(m, nc), upper), cols(centre(m, nc), lower), cols(front, centre(m, nh)),
            cols(rear, centre(m, nh))]


def build_solid_box(sections, material, *, chord_elements=8, height_elements=2, through=2,
                    span_element_size=0.5, ribs_y=(), rib_thickness=0.1, root="clamped") -> ShellBox:
    """Mesh the box walls with C3D20R (see module docstring). ``sections``: BoxSections with
    streamwise wall thicknesses; ``ribs_y``: rib positions (m; a rib at the tip lies inboard of
    it, elsewhere it is centred). ``root``: 'clamped' (all translations of the root section) or
    'free_warping' (in-plane translations; the axial one only on the section's symmetry lines,
    where the torsional warping of a doubly symmetric box vanishes: a pure-torque diagnostic).

    Parameters
    ----------
    sections : BoxSections
        Streamwise sections of the box. (streamwise wall thicknesses).
    material : Material
        Isotropic material.
    chord_elements : int, optional
        Elements across the skins' interior.
    height_elements : int, optional
        Elements up the webs' interior.
    through : int, optional
        Elements through each wall's thickness.
    span_element_size : float, optional
        Largest element length along the span (m).
    ribs_y : sequence of float, optional
        Rib span coordinates (m).
    rib_thickness : float, optional
        Rib thickness (m).
    root : {"clamped", "free_warping"}, optional
        Root boundary condition.

    Returns
    -------
    ShellBox
        The model (rings are cross-sections).
    """
    if root not in ("clamped", "free_warping"):
        raise ValueError(f"root must be 'clamped' or 'free_warping', got {root!r}")
    m, nc, nh = int(through), int(chord_elements), int(height_elements)
    if min(m, nc, nh) < 1:
        raise ValueError(f"through, chord and height elements must be >= 1, got {m}, {nc}, {nh}")
    y0, y1 = sections.centres[0, 1], sections.centres[-1, 1]
    slabs = []
    for yr in ribs_y:
        if not (y0 <= yr <= y1 + 1e-9):
            raise ValueError(f"rib at y = {yr} m is outside the span [{y0}, {y1}] m")
        a = min(max(yr - rib_thickness / 2, y0), y1 - rib_thickness)
        slabs.append((a, a + rib_thickness))
    lines = span_lines(sections, span_element_size, [v for s in slabs for v in s])
    fine = np.sort(np.concatenate([lines, 0.5 * (lines[:-1] + lines[1:])]))
    deck = Deck("wingmdao solid box")
    deck.material("MAT", material)
    grids = []
    for y in fine:
        c, w, h, t = sections.at(y)
        X = _breaks(-w / 2, t["t_front_spar"], t["t_rear_spar"], w / 2, m, nc)
        Z = _breaks(-h / 2, t["t_lower_skin"], t["t_upper_skin"], h / 2, m, nh)
        grids.append((c, X, Z))
    nodes: dict = {}

    def node(jj, ii, kk):
        key = (jj, ii, kk)
        if key not in nodes:
            c, X, Z = grids[jj]
            nodes[key] = int(deck.add_nodes([(c[0] + X[ii], fine[jj], c[2] + Z[kk])])[0])
        return nodes[key]

    NX, NZ = 2 * m + nc, 2 * m + nh
    conns, cells = [], []
    for j in range(len(lines) - 1):
        ymid = fine[2 * j + 1]
        rib = any(a - 1e-9 <= ymid <= b + 1e-9 for a, b in slabs)
        for i in range(NX):
            for k in range(NZ):
                if cell_wall(i, k, m, nc, nh) < 0 and not rib:
                    continue
                jj, ii, kk = 2 * j, 2 * i, 2 * k
                bot = [node(jj, ii + di, kk + dk) for dk, di in _CORNERS]
                top = [node(jj + 2, ii + di, kk + dk) for dk, di in _CORNERS]
                mb = [node(jj, ii + di, kk + dk) for dk, di in _MIDS]
                mt = [node(jj + 2, ii + di, kk + dk) for dk, di in _MIDS]
                vert = [node(jj + 1, ii + di, kk + dk) for dk, di in _CORNERS]
                conns.append(bot + top + mb + mt + vert)
                cells.append((i, k, j))
    ids = deck.add_elements("C3D20R", "BOX", conns)
    deck.sections.append("*SOLID SECTION, ELSET=BOX, MATERIAL=MAT")
    eid = dict(zip(cells, ids))
    rings, weights = [], []
    for jj in range(len(fine)):
        ring, wgt = _station_weights(jj, grids[jj], nodes, m, nc, nh) if jj % 2 == 0 else ([], [])
        rings.append(np.array(ring, dtype=int))
        weights.append(np.array(wgt))
    samples = [[[eid[(i, k, j)] for i, k in pt] for pt in _sample_cells(m, nc, nh)]
               for j in range(len(lines) - 1)]
    deck.nsets["ROOT"] = list(rings[0])
    if root == "clamped":
        deck.boundary.append(("ROOT", 1, 3))
    else:
        NXq, NZq = 2 * (2 * m + nc), 2 * (2 * m + nh)
        axis = [n for (jj, ii, kk), n in nodes.items() if jj == 0 and (ii == NXq // 2 or kk == NZq // 2)]
        deck.nsets["ROOTAXIS"] = sorted(axis)
        deck.boundary += [("ROOT", 1, 1), ("ROOT", 3, 3), ("ROOTAXIS", 2, 2)]
    box = ShellBox(deck, fine, rings, weights, len(conns), counts=(nc, nh), element="C3D20R")
    box.samples = samples
    return box


def _station_weights(jj, grid, nodes, m, nc, nh):
    """Wall nodes of the cross-section at quadratic span line ``jj`` and their consistent areas."""
    _, X, Z = grid
    acc: dict = {}
    for i in range(2 * m + nc):
        for k in range(2 * m + nh):
            if cell_wall(i, k, m, nc, nh) < 0:
                continue
            area = (X[2 * i + 2] - X[2 * i]) * (Z[2 * k + 2] - Z[2 * k])
            for (dk, di), f in [(c, -1 / 12) for c in _CORNERS] + [(c, 1 / 3) for c in _MIDS]:
                n = nodes[(jj, 2 * i + di, 2 * k + dk)]
                acc[n] = acc.get(n, 0.0) + f * area
    return list(acc), list(acc.values())


def streamwise_sections(sections, cos_sweep, cos_dihedral):
    """The BoxSections with streamwise wall thicknesses from beam-normal ones (spars / cos sweep,
    skins / cos dihedral, per section).

    Parameters
    ----------
    sections : BoxSections
        Streamwise sections of the box. (beam-normal wall thicknesses).
    cos_sweep : float or array_like
        Cosine of the sweep angle, per section.
    cos_dihedral : float or array_like
        Cosine of the dihedral angle, per section.

    Returns
    -------
    BoxSections
        The sections with streamwise thicknesses.
    """
    t = {w: sections.thickness[w] / (cos_sweep if "spar" in w else cos_dihedral) for w in WALLS}
    return BoxSections(sections.centres, sections.widths, sections.heights, t)
