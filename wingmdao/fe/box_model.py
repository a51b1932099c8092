"""Shell model of a box wingbox on the skin and spar mid-surfaces, for CalculiX.

The box is given by streamwise sections (planes y = const, parallel to the root, as in
App. D.1 of "Structural analysis and optimization of aircraft wings through dimensional
reduction", PhD dissertation, Georgia Institute of Technology, 2021): centre (x, y, z), outer
width (x) and height (z), and the four wall thicknesses normal to the walls (upper/lower skin,
front/rear spar), linearly interpolated between sections. The mid-surface rectangle of a section
has half-width w/2 - t_spar/2 and half-height h/2 - t_skin/2. Elements: S8R (default) or S4R
shells, one ``*SHELL SECTION`` per element with its mean wall thickness; optional ribs (shells in
the rib planes, sharing the ring nodes); root ring clamped (all six degrees of freedom); loads
at a station enter as the nodal forces of a distributing coupling of the station ring
(:func:`wingmdao.fe.calculix.distributing_forces`); point masses spread over a ring with the
same weights. Section-average displacement of a station: the weighted mean of its ring nodes'
displacements, the weights being wall thickness x tributary length (the wall-area average, the
definition of the solid reference in :mod:`wingmdao.verification.wingbox_solid`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from wingmdao.fe.calculix import Deck, distributing_forces, frequency_step, parse_dat, run_deck, static_step
from wingmdao.fe.stress_points import sample_elements
from wingmdao.section.box import WALL_NAMES

WALLS = WALL_NAMES


@dataclass
class BoxSections:
    """Streamwise sections of a box: centres (m, (n, 3)), widths and heights (m, (n,)) and wall
    thicknesses normal to the walls (m, {WALLS name: (n,)}).

    Parameters
    ----------
    centres : numpy.ndarray
        (n, 3) section centres in body axes (m).
    widths, heights : numpy.ndarray
        (n,) streamwise box width and height (m).
    thickness : dict
        Wall name -> (n,) wall thickness normal to the wall (m).
    """

    centres: np.ndarray
    widths: np.ndarray
    heights: np.ndarray
    thickness: dict

    def __post_init__(self):
        self.centres = np.asarray(self.centres, float)
        n = len(self.centres)
        self.widths = np.broadcast_to(np.asarray(self.widths, float), (n,)).copy()
        self.heights = np.broadcast_to(np.asarray(self.heights, float), (n,)).copy()
        self.thickness = {w: np.broadcast_to(np.asarray(self.thickness[w], float), (n,)).copy() for w in WALLS}
        if n < 2 or np.any(np.diff(self.centres[:, 1]) <= 0):
            raise ValueError("sections: at least two, with increasing span coordinate y (m)")
        for w in WALLS:
            t = self.thickness[w]
            if not np.all(np.isfinite(t) & (t > 0)):
                raise ValueError(f"{w} must be positive thicknesses in m, got {t.tolist()}")
        if np.any(self.thickness["t_front_spar"] / 2 + self.thickness["t_rear_spar"] / 2 >= self.widths) or \
                np.any(self.thickness["t_upper_skin"] / 2 + self.thickness["t_lower_skin"] / 2 >= self.heights):
            raise ValueError("wall thicknesses leave no mid-surface box (t_spar >= width or t_skin >= height)")

    @property
    def span(self) -> float:
        return float(self.centres[-1, 1] - self.centres[0, 1])

    def at(self, y):
        """Centre, width, height and thicknesses linearly interpolated at span coordinate y.

        Parameters
        ----------
        y : float
            Span coordinate (m).

        Returns
        -------
        tuple
            Centre (3,), width, height (m) and {wall: thickness} (m) at ``y``.
        """
        ys = self.centres[:, 1]
        c = np.array([np.interp(y, ys, self.centres[:, k]) for k in range(3)])
        return (c, float(np.interp(y, ys, self.widths)), float(np.interp(y, ys, self.heights)),
                {w: float(np.interp(y, ys, self.thickness[w])) for w in WALLS})


@dataclass
class ShellBox:
    """The built model: the deck, the station rings (node ids, weights) and span positions
    (also the solid model of :mod:`wingmdao.fe.solid_box`, whose rings are cross-sections).

    Parameters
    ----------
    deck : Deck
        The CalculiX deck.
    span_y : numpy.ndarray
        Span coordinates of the mesh lines (m).
    rings : list
        Per span line, the node ids of its ring.
    ring_weights : list
        Per span line, the nodes' weights (thickness times tributary length, m^2).
    num_elements : int
        Number of shell (or solid) elements.
    station_lines : dict, optional
        Label -> span line index of the stations.
    wall_elements : list, optional
        Per span row, the element ids around the ring.
    counts : tuple, optional
        (chord, height) elements of a ring.
    element : str, optional
        CalculiX element type.
    samples : list or None, optional
        Per span row, the element ids of each stress point (:data:`wingmdao.fe.stress_points.POINTS`).
    """

    deck: Deck
    span_y: np.ndarray
    rings: list                # per span line: node ids (P,)
    ring_weights: list         # per span line: thickness x tributary length (P,)
    num_elements: int
    station_lines: dict = field(default_factory=dict)   # label -> span line index
    wall_elements: list = field(default_factory=list)    # per span row: element ids around the ring
    counts: tuple = (8, 2)                                # chord x height elements
    element: str = "S8R"
    samples: list | None = None      # per span row: element ids of each stress point (stress_points.POINTS)

    def ring_points(self, j):
        """Coordinates of the nodes of the ring on span line ``j``.

        Parameters
        ----------
        j : int
            Span line index.

        Returns
        -------
        numpy.ndarray
            (P, 3) coordinates of the ring's nodes (m).
        """
        return np.array([self.deck.nodes[int(n)] for n in self.rings[j]])


def _perimeter(c, a, b, nc, nh, q, skin_x=None):
    """Mid-surface ring points (P, 3) at a section: lower skin front->rear, rear spar up, upper
    skin rear->front, front spar down; ``q`` = 2 for quadratic (mid-side) resolution. Also the
    wall index of each point's following segment (0 upper, 1 lower, 2 front, 3 rear).
    ``skin_x``: the skins' element boundaries (nc + 1 chordwise offsets from the centre, -a to
    a; default nc equal elements)."""
    pts, wall = [], []
    if skin_x is None:
        xs = np.linspace(-a, a, q * nc + 1)
    else:
        xb = np.asarray(skin_x, float)
        xs = xb if q == 1 else np.sort(np.concatenate([xb, 0.5 * (xb[:-1] + xb[1:])]))
    zs = np.linspace(-b, b, q * nh + 1)
    for x in xs[:-1]:
        pts.append((x, -b)); wall.append(1)
    for z in zs[:-1]:
        pts.append((a, z)); wall.append(3)
    for x in xs[::-1][:-1]:
        pts.append((x, b)); wall.append(0)
    for z in zs[::-1][:-1]:
        pts.append((-a, z)); wall.append(2)
    p = np.array(pts)
    out = np.column_stack([c[0] + p[:, 0], np.full(len(p), c[1]), c[2] + p[:, 1]])
    return out, np.array(wall)


def span_lines(sections: BoxSections, element_size: float, ribs_y=()) -> np.ndarray:
    """Span coordinates of the element boundaries: every section and rib plane, with elements
    no longer than ``element_size`` in between.

    Parameters
    ----------
    sections : BoxSections
        Streamwise sections of the box.
    element_size : float
        Largest element length along the span (m).
    ribs_y : sequence of float, optional
        Rib span coordinates (m).

    Returns
    -------
    numpy.ndarray
        Sorted span coordinates of the element boundaries (m).
    """
    ys = sorted(set(np.round(np.concatenate([sections.centres[:, 1], np.asarray(ribs_y, float)]), 9)))
    out = [ys[0]]
    for y0, y1 in zip(ys[:-1], ys[1:]):
        n = max(1, int(np.ceil((y1 - y0) / element_size - 1e-9)))
        out += list(np.linspace(y0, y1, n + 1)[1:])
    return np.array(out)


def build_shell_box(sections: BoxSections, material, *, element="S8R", chord_elements=8, height_elements=2,
                    span_element_size=0.5, ribs_y=(), rib_thickness=None, skin_breaks=None) -> ShellBox:
    """Mesh the box mid-surfaces (see module docstring); ``ribs_y``: rib span coordinates (m);
    ``rib_thickness``: one value (m) for every rib or one per rib of ``ribs_y`` (None: the
    thinnest wall of the rib station);
    ``skin_breaks``: ``f(a) -> (chord_elements + 1,)`` the skins' chordwise element boundaries
    (offsets from the section centre, -a to a) at a section of mid-surface half-width a
    (default: ``chord_elements`` equal elements).

    Parameters
    ----------
    sections : BoxSections
        Streamwise sections of the box.
    material : Material
        Isotropic material of the walls and ribs.
    element : {"S8R", "S4R"}, optional
        CalculiX shell element.
    chord_elements : int, optional
        Elements across each skin.
    height_elements : int, optional
        Elements up each spar web.
    span_element_size : float, optional
        Largest element length along the span (m).
    ribs_y : sequence of float, optional
        Rib span coordinates (m).
    rib_thickness : float, sequence of float or None, optional
        Rib thickness (m): one value, one per rib, or None for the thinnest wall of the rib station.
    skin_breaks : callable or None, optional
        ``f(a)`` -> the skins' chordwise element boundaries at mid-surface half-width a (m).

    Returns
    -------
    ShellBox
        The model.
    """
    if element not in ("S8R", "S4R"):
        raise ValueError(f"element must be 'S8R' or 'S4R', got {element!r}")
    q = 2 if element == "S8R" else 1
    y0, y1 = sections.centres[0, 1], sections.centres[-1, 1]
    for yr in ribs_y:
        if not (y0 <= yr <= y1 + 1e-9):
            raise ValueError(f"rib at y = {yr} m is outside the span [{y0}, {y1}] m")
    lines = span_lines(sections, span_element_size, ribs_y)
    # quadratic: mid-lines between element boundaries
    fine = lines if q == 1 else np.sort(np.concatenate([lines, 0.5 * (lines[:-1] + lines[1:])]))
    deck = Deck("wingmdao shell box")
    deck.material("MAT", material)
    rings, weights, walls_t, ring_walls = [], [], [], []
    for y in fine:
        c, w, h, t = sections.at(y)
        a = w / 2 - (t["t_front_spar"] + t["t_rear_spar"]) / 4
        b = h / 2 - (t["t_upper_skin"] + t["t_lower_skin"]) / 4
        xb = None
        if skin_breaks is not None:
            xb = np.asarray(skin_breaks(a), float)
            if xb.shape != (chord_elements + 1,) or abs(xb[0] + a) > 1e-9 or abs(xb[-1] - a) > 1e-9 \
                    or np.any(np.diff(xb) <= 0):
                raise ValueError(f"skin_breaks: {chord_elements + 1} increasing offsets from -a to a needed")
        pts, wall = _perimeter(c, a, b, chord_elements, height_elements, q, xb)
        ids = deck.add_nodes(pts)
        rings.append(ids)
        tw = np.array([t[WALLS[k]] for k in wall])
        walls_t.append(tw)
        ring_walls.append(wall)
        seg = np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1)   # segment i: point i -> i+1
        P = len(pts)
        wgt = np.zeros(P)
        if q == 1:
            for i in range(P):
                wgt[i] += 0.5 * seg[i] * tw[i]
                wgt[(i + 1) % P] += 0.5 * seg[i] * tw[i]
        else:   # Simpson weights on each quadratic edge (points 2k, 2k+1, 2k+2)
            for k in range(0, P, 2):
                L = seg[k] + seg[k + 1]
                tk = tw[k]
                wgt[k] += L * tk / 6
                wgt[k + 1] += 4 * L * tk / 6
                wgt[(k + 2) % P] += L * tk / 6
        weights.append(wgt)
    P = len(rings[0])
    nel = 0
    step = q
    rows = []
    for j in range(0, len(fine) - 1, step):
        rows.append([])
        for i in range(0, P, step):
            r0, r1 = rings[j], rings[j + step]
            if q == 1:
                conn = [r0[i], r0[(i + 1) % P], r1[(i + 1) % P], r1[i]]
            else:
                rm = rings[j + 1]
                conn = [r0[i], r0[(i + 2) % P], r1[(i + 2) % P], r1[i],
                        r0[(i + 1) % P], rm[(i + 2) % P], r1[(i + 1) % P], rm[i]]
            t = 0.5 * (walls_t[j][i] + walls_t[j + step][i])
            name = f"E{nel + 1}"
            rows[-1] += deck.add_elements(element, name, [conn])
            deck.sections.append(f"*SHELL SECTION, ELSET={name}, MATERIAL=MAT\n{t:.10g}")
            nel += 1
    # ribs: a structured shell grid in the rib plane sharing the ring nodes
    nc, nh = chord_elements, height_elements
    rib_t = np.broadcast_to(np.asarray(np.nan if rib_thickness is None else rib_thickness, float),
                            (len(ribs_y),)) if len(ribs_y) else np.zeros(0)
    for r_index, yr in enumerate(ribs_y):
        j = int(np.argmin(np.abs(fine - yr)))
        c, w, h, t = sections.at(fine[j])
        ring = rings[j]
        pts = np.array([deck.nodes[int(n)] for n in ring])
        za, zb = pts[:, 2].min(), pts[:, 2].max()
        Ni, Nk = q * nc, q * nh
        grid = np.zeros((Ni + 1, Nk + 1), dtype=int)
        for i in range(Ni + 1):
            for k in range(Nk + 1):
                if k == 0:
                    grid[i, k] = ring[i]
                elif i == Ni:
                    grid[i, k] = ring[Ni + k]
                elif k == Nk:
                    grid[i, k] = ring[Ni + Nk + (Ni - i)]
                elif i == 0:
                    grid[i, k] = ring[(2 * Ni + 2 * Nk - k) % P]
                elif q == 2 and i % 2 == 1 and k % 2 == 1:
                    grid[i, k] = 0      # no centre node in S8R
                else:
                    x = pts[i, 0]       # the lower skin's chordwise positions
                    z = za + (zb - za) * k / Nk
                    grid[i, k] = deck.add_nodes([(x, fine[j], z)])[0]
        tr = float(rib_t[r_index]) if rib_thickness is not None else min(t.values())
        conns = []
        for i in range(0, Ni, q):
            for k in range(0, Nk, q):
                if q == 1:
                    conns.append([grid[i, k], grid[i + 1, k], grid[i + 1, k + 1], grid[i, k + 1]])
                else:
                    conns.append([grid[i, k], grid[i + 2, k], grid[i + 2, k + 2], grid[i, k + 2],
                                  grid[i + 1, k], grid[i + 2, k + 1], grid[i + 1, k + 2], grid[i, k + 1]])
        name = f"RIB{len([s for s in deck.sections if 'RIB' in s]) + 1}"
        deck.add_elements(element, name, conns)
        deck.sections.append(f"*SHELL SECTION, ELSET={name}, MATERIAL=MAT\n{tr:.10g}")
        nel += len(conns)
    deck.nsets["ROOT"] = list(rings[0])
    deck.boundary.append(("ROOT", 1, 6))
    return ShellBox(deck, fine, rings, weights, nel, wall_elements=rows, counts=(nc, nh), element=element)


def line_index(model: ShellBox, y: float) -> int:
    """Index of the mesh line at span coordinate ``y``.

    Parameters
    ----------
    model : ShellBox
        The built shell (or solid) model.
    y : float
        Span coordinate (m).

    Returns
    -------
    int
        Index of the mesh line at ``y``; ValueError when none lies within 1e-6 m.
    """
    j = int(np.argmin(np.abs(model.span_y - y)))
    if abs(model.span_y[j] - y) > 1e-6:
        raise ValueError(f"no mesh line at y = {y} m")
    return j


def station_loads(model: ShellBox, loads) -> list:
    """``*CLOAD`` rows of [(y, centre (3,), force (3,), moment (3,))] via distributing couplings.

    Parameters
    ----------
    model : ShellBox
        The built shell (or solid) model.
    loads : sequence of tuple
        ``(y, centre (3,), force (3,), moment (3,))`` in body axes (m, m, N, N m).

    Returns
    -------
    list
        ``(node id, dof 1-3, force N)`` ``*CLOAD`` rows, one per loaded node and direction (loads at
        the same node summed); ValueError for a load off the mesh lines.
    """
    rows = []
    for y, centre, F, M in loads:
        j = line_index(model, y)
        f = distributing_forces(model.ring_points(j), model.ring_weights[j], centre, F, M)
        for n, fi in zip(model.rings[j], f):
            rows += [(int(n), d + 1, float(fi[d])) for d in range(3)]
    # merge duplicates
    acc: dict = {}
    for n, d, v in rows:
        acc[(n, d)] = acc.get((n, d), 0.0) + v
    return [(n, d, v) for (n, d), v in acc.items()]


def add_point_masses(model: ShellBox, masses) -> None:
    """Point masses [(y, mass kg)] spread over the station ring with the ring weights (``*MASS``).

    Parameters
    ----------
    model : ShellBox
        The built shell (or solid) model.
    masses : sequence of tuple
        ``(y, mass)`` pairs (m, kg).
    """
    for k, (y, m) in enumerate(masses):
        if not (np.isfinite(m) and m >= 0):
            raise ValueError(f"point mass at y = {y} m must be >= 0 kg, got {m}")
        j = line_index(model, y)
        w = model.ring_weights[j] / model.ring_weights[j].sum()
        for i, (n, wi) in enumerate(zip(model.rings[j], w)):
            name = f"PM{k + 1}_{i + 1}"
            model.deck.add_elements("MASS", name, [[n]])
            model.deck.model_extra.append(f"*MASS, ELSET={name}\n{m * wi:.10g}")


def section_average(model: ShellBox, displacements: dict, j: int) -> np.ndarray:
    """Weighted mean displacement of the ring on span line ``j`` (the ring weights).

    Parameters
    ----------
    model : ShellBox
        The built shell (or solid) model.
    displacements : dict
        Node id -> (3,) displacement (m).
    j : int
        Span line index.

    Returns
    -------
    numpy.ndarray
        (3,) weighted mean displacement of the ring (m).
    """
    w = model.ring_weights[j]
    u = np.array([displacements[int(n)] for n in model.rings[j]])
    return (w[:, None] * u).sum(0) / w.sum()


def section_rotation(model: ShellBox, displacements: dict, j: int) -> np.ndarray:
    """Section rotation vector (rad): the weighted least-squares rigid rotation of the ring,
    theta = J^-1 sum w_i r_i x (u_i - u_mean) (the distributing-coupling reference rotation).

    Parameters
    ----------
    model : ShellBox
        The built shell (or solid) model.
    displacements : dict
        Node id -> (3,) displacement (m).
    j : int
        Span line index.

    Returns
    -------
    numpy.ndarray
        (3,) rotation vector (rad).
    """
    w = model.ring_weights[j]
    p = model.ring_points(j)
    u = np.array([displacements[int(n)] for n in model.rings[j]])
    r = p - (w[:, None] * p).sum(0) / w.sum()
    du = u - (w[:, None] * u).sum(0) / w.sum()
    J = sum(wi * (ri @ ri * np.eye(3) - np.outer(ri, ri)) for wi, ri in zip(w, r))
    return np.linalg.pinv(J) @ (w[:, None] * np.cross(r, du)).sum(0)


def solve_static(model: ShellBox, loads, stations_y, nlgeom=False, increments=10, keep_dir=None,
                 stress=False) -> dict:
    """Static solve: section-average displacement (m, (k, 3)) and rotation (rad, (k, 3)) at the
    span coordinates ``stations_y``; with ``stress`` also the integration-point stresses of the
    corner and mid-flange elements (``stresses``, :mod:`wingmdao.fe.stress_points`).

    Parameters
    ----------
    model : ShellBox
        The built shell (or solid) model.
    loads : sequence of tuple
        ``(y, centre (3,), force (3,), moment (3,))`` station loads (m, m, N, N m).
    stations_y : sequence of float
        Span coordinates where results are wanted (m).
    nlgeom : bool, optional
        Geometrically nonlinear solve.
    increments : int, optional
        Load increments of a nonlinear solve.
    keep_dir : str, path-like or None, optional
        Folder to keep the CalculiX files in; None for a temporary one.
    stress : bool, optional
        Also return the stresses of the sample elements.

    Returns
    -------
    dict
        ``displacement`` (k, 3) (m), ``rotation`` (k, 3) (rad), the run ``time`` (s), the model
        size, and with ``stress`` the ``stresses``.
    """
    js = [line_index(model, y) for y in stations_y]
    model.deck.nsets["OUT"] = sorted({int(n) for j in js for n in model.rings[j]})
    elsets = ()
    if stress:
        model.deck.elsets["VMOUT"] = sorted({e for row in sample_elements(model) for eids in row for e in eids})
        elsets = ("VMOUT",)
    text = model.deck.text([static_step(station_loads(model, loads), ["OUT"], nlgeom=nlgeom,
                                        increments=increments, stress_elsets=elsets)])
    run = run_deck(text, keep_dir=keep_dir)
    dat = parse_dat(run["dat"])
    d = dat["displacements"]["OUT"]
    disp = np.array([section_average(model, d, j) for j in js])
    rot = np.array([section_rotation(model, d, j) for j in js])
    return {"displacement": disp, "rotation": rot, "time": run["time"], "num_nodes": len(model.deck.nodes),
            "num_elements": model.num_elements, "stresses": dat["stresses"]}


def solve_modes(model: ShellBox, modes: int, keep_dir=None) -> dict:
    """Lowest ``modes`` natural frequencies (Hz).

    Parameters
    ----------
    model : ShellBox
        The built shell (or solid) model.
    modes : int
        Number of modes.
    keep_dir : str, path-like or None, optional
        Folder to keep the CalculiX files in; None for a temporary one.

    Returns
    -------
    dict
        ``frequencies_hz`` (lowest ``modes``) and the run ``time`` (s).
    """
    if not (isinstance(modes, (int, np.integer)) and modes >= 1):
        raise ValueError(f"modes must be an integer >= 1, got {modes!r}")
    run = run_deck(model.deck.text([frequency_step(modes)]), keep_dir=keep_dir)
    return {"frequencies_hz": parse_dat(run["dat"])["frequencies_hz"][:modes], "time": run["time"]}
