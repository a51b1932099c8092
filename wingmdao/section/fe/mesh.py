"""Structured 9-node quadrilateral (Q9) meshes of thin-walled and solid sections.

Each wall is split through its thickness into at least ``n_thick`` (default 5) elements; layer
interfaces of a layup fall on element edges. Meshes are mapped structured grids (blocks of a
logically rectangular grid with unused cells removed), so every element is a well-shaped quad.
Section coordinates: x2 chordwise (c, aft), x3 normal (n, up).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .materials import Material, ply_stiffness


@dataclass
class SectionMesh:
    """Q9 mesh: nodes (nn, 2) [x2, x3] in m, elements (ne, 9) node indices (tensor order 3*j + i),
    Q (ne, 6, 6) element stiffness in section axes (Pa), rho (ne,) kg/m^3, region (ne,) wall labels.

    Parameters
    ----------
    nodes : numpy.ndarray
        (nn, 2) node coordinates [x2, x3] (m).
    elements : numpy.ndarray
        (ne, 9) node indices, tensor order 3 j + i.
    Q : numpy.ndarray
        (ne, 6, 6) element stiffness in section axes (Pa).
    rho : numpy.ndarray
        (ne,) element density (kg/m^3).
    region : numpy.ndarray, optional
        (ne,) region label of each element.
    region_names : tuple, optional
        Name of each region label.
    """

    nodes: np.ndarray
    elements: np.ndarray
    Q: np.ndarray
    rho: np.ndarray
    region: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    region_names: tuple = ()


def _layers(wall, name, n_thick):
    """Normalise a wall spec into a list of (material, thickness, angle_rad), outer -> inner."""
    if "layup" in wall and wall["layup"] is not None:
        layers = [(m, float(t), np.radians(float(a))) for m, t, a in wall["layup"]]
    else:
        layers = [(wall["material"], float(wall["thickness"]), np.radians(float(wall.get("angle_deg", 0.0))))]
    for k, (m, t, _a) in enumerate(layers):
        if not isinstance(m, Material):
            raise ValueError(f"wall {name} layer {k}: material must be a Material, got {m!r}")
        if not np.isfinite(t) or t <= 0:
            raise ValueError(f"wall {name} layer {k}: thickness must be > 0 m, got {t}")
    return layers


def _split_layers(layers, n_thick):
    """Element counts per layer (>= 1 each, >= n_thick total, roughly proportional to thickness)."""
    total = sum(t for _, t, _ in layers)
    counts = [max(1, int(np.ceil(n_thick * t / total))) for _, t, _ in layers]
    return counts


def _wall_fractions(layers, n_thick):
    """Element edge positions through the wall as fractions 0 (outer) -> 1 (inner), and layer index per cell."""
    total = sum(t for _, t, _ in layers)
    counts = _split_layers(layers, n_thick)
    edges, layer_of_cell, s = [0.0], [], 0.0
    for k, ((_, t, _), c) in enumerate(zip(layers, counts)):
        edges.extend(list(s / total + (t / total) * np.arange(1, c + 1) / c))
        layer_of_cell.extend([k] * c)
        s += t
    return np.array(edges), np.array(layer_of_cell)


def q9_from_grid(X, Y, mask, cell_Q, cell_rho, cell_region, names, periodic_i=False) -> SectionMesh:
    """Q9 mesh from a node grid (2 ni + 1, 2 nj + 1) and a cell mask (ni, nj) with per-cell material.

    Parameters
    ----------
    X, Y : numpy.ndarray
        (2 ni + 1, 2 nj + 1) node coordinates x2, x3 (m); 2 ni rows when periodic in i.
    mask : numpy.ndarray
        (ni, nj) bool, the cells that are material.
    cell_Q : numpy.ndarray
        (ni, nj, 6, 6) stiffness of each cell (Pa).
    cell_rho : numpy.ndarray
        (ni, nj) density of each cell (kg/m^3).
    cell_region : numpy.ndarray
        (ni, nj) region label of each cell.
    names : sequence of str
        Region names.
    periodic_i : bool, optional
        Whether the grid closes on itself in i (a tube).

    Returns
    -------
    SectionMesh
        The mesh.
    """
    return _q9_from_grid(X, Y, mask, cell_Q, cell_rho, cell_region, names, periodic_i)


def refine_edges(edges):
    """Element edge coordinates (k + 1,) -> Q9 node lines (2 k + 1,) (midpoints inserted).

    Parameters
    ----------
    edges : array_like
        (k + 1,) element edge coordinates.

    Returns
    -------
    numpy.ndarray
        (2 k + 1,) node coordinates.
    """
    return _refine_edges(edges)


def _q9_from_grid(X, Y, mask, cell_Q, cell_rho, cell_region, names, periodic_i=False):
    """Build a Q9 mesh from a node grid (2*ni+1, 2*nj+1) (or 2*ni with periodic_i) and a cell mask (ni, nj)."""
    ni, nj = mask.shape
    NI = X.shape[0]
    idx = np.arange(X.size).reshape(X.shape)
    ii, jj = np.nonzero(mask)
    conn = np.empty((ii.size, 9), int)
    for b in range(3):
        for a in range(3):
            I = 2 * ii + a
            if periodic_i:
                I = I % NI
            conn[:, 3 * b + a] = idx[I, 2 * jj + b]
    used, inv = np.unique(conn, return_inverse=True)
    nodes = np.column_stack([X.ravel()[used], Y.ravel()[used]])
    return SectionMesh(nodes, inv.reshape(conn.shape), cell_Q[ii, jj], cell_rho[ii, jj],
                       cell_region[ii, jj], tuple(names))


def _refine_edges(edges):
    """Insert midpoints: element edges (k+1,) -> Q9 node lines (2k+1,)."""
    edges = np.asarray(edges, float)
    out = np.empty(2 * edges.size - 1)
    out[0::2] = edges
    out[1::2] = 0.5 * (edges[:-1] + edges[1:])
    return out


def span_divisions(length, mesh_size, minimum=2):
    """Number of elements along a length for a target element size.

    Parameters
    ----------
    length : float
        The length to divide (m).
    mesh_size : float
        The target element size (m).
    minimum : int
        The fewest elements.

    Returns
    -------
    int
        ``max(minimum, ceil(length / mesh_size))``.
    """
    return max(minimum, int(np.ceil(length / mesh_size)))


def rectangle_mesh(width, height, material, nx=20, ny=20):
    """Solid rectangle width (x2) x height (x3), centred on the origin, nx x ny Q9 elements.

    Parameters
    ----------
    width, height : float
        Rectangle sides along x2 and x3 (m).
    material : Material
        Material.
    nx, ny : int, optional
        Elements along x2 and x3.

    Returns
    -------
    SectionMesh
        The mesh.
    """
    _check_positive(width=width, height=height)
    xe = np.linspace(-width / 2, width / 2, nx + 1)
    ye = np.linspace(-height / 2, height / 2, ny + 1)
    X, Y = np.meshgrid(_refine_edges(xe), _refine_edges(ye), indexing="ij")
    mask = np.ones((nx, ny), bool)
    Q = np.broadcast_to(material.C, (nx, ny, 6, 6))
    return _q9_from_grid(X, Y, mask, Q, np.full((nx, ny), material.rho), np.zeros((nx, ny), int), ["solid"])


def _check_positive(**kw):
    for k, v in kw.items():
        if not np.isfinite(v) or v <= 0:
            raise ValueError(f"{k} must be > 0 m, got {v}")


def _ply_Q(layers, layer_idx, normal):
    m, _, ang = layers[layer_idx]
    return ply_stiffness(m, ang, normal), m.rho


def box_mesh(width, height, walls, n_thick=5, mesh_size=None, open_walls=(), corners="mitre"):
    """Rectangular box (outer width x height, centred on the origin) with walls 'upper', 'lower', 'front', 'rear'.

    Each wall: {'thickness': t, 'material': Material} or {'layup': [(Material, t, angle_deg), ...]} outer -> inner.
    Walls named in ``open_walls`` are left out (a channel is a box without its front wall).
    Corner squares belong to the skins (``corners='skins'``) or are split along their diagonal so that
    each layer wraps round the corner (``corners='mitre'``, staircase on the element grid).

    Parameters
    ----------
    width, height : float
        Outer box dimensions (m).
    walls : dict
        Wall name -> ``{'thickness': t, 'material': Material}`` or ``{'layup': [(Material, t,
        angle_deg), ...]}`` outer to inner.
    n_thick : int, optional
        Elements through each wall's thickness.
    mesh_size : float or None, optional
        Element size along the walls (m); None for four times the thinnest wall's element.
    open_walls : sequence of str, optional
        Walls left out.
    corners : {"mitre", "skins"}, optional
        Corner squares split along their diagonal, or owned by the skins.

    Returns
    -------
    SectionMesh
        The mesh.
    """
    if corners not in ("skins", "mitre"):
        raise ValueError(f"corners must be 'skins' or 'mitre', got {corners!r}")
    _check_positive(width=width, height=height)
    names = [w for w in ("upper", "lower", "front", "rear") if w not in open_walls]
    L = {w: _layers(walls[w], w, n_thick) for w in names}
    T = {w: sum(t for _, t, _ in L[w]) for w in names}
    tf, tr = T.get("front", 0.0), T.get("rear", 0.0)
    tu, tl = T.get("upper", 0.0), T.get("lower", 0.0)
    if tf + tr >= width:
        raise ValueError(f"front + rear wall thickness {tf + tr} m must be < width {width} m")
    if tu + tl >= height:
        raise ValueError(f"upper + lower wall thickness {tu + tl} m must be < height {height} m")
    h = mesh_size or min(T.values()) / n_thick * 4
    fr = {w: _wall_fractions(L[w], n_thick) for w in names}
    # x edges: front wall (outer at -w/2), interior, rear wall (outer at +w/2)
    x0, x1 = -width / 2, width / 2
    y0, y1 = -height / 2, height / 2
    xs, xc = [x0], []                      # xc: (kind, layer index) per x-cell
    if "front" in names:
        e, lay = fr["front"]; xs = list(x0 + e * tf); xc += [("front", k) for k in lay]
    n_mid = span_divisions(width - tf - tr, h)
    xs += list(np.linspace(x0 + tf, x1 - tr, n_mid + 1)[1:]); xc += [("mid", 0)] * n_mid
    if "rear" in names:
        e, lay = fr["rear"]; xs += list((x1 - e * tr)[::-1][1:]); xc += [("rear", k) for k in lay[::-1]]
    ys, yc = [y0], []
    if "lower" in names:
        e, lay = fr["lower"]; ys = list(y0 + e * tl); yc += [("lower", k) for k in lay]
    n_mid = span_divisions(height - tu - tl, h)
    ys += list(np.linspace(y0 + tl, y1 - tu, n_mid + 1)[1:]); yc += [("mid", 0)] * n_mid
    if "upper" in names:
        e, lay = fr["upper"]; ys += list((y1 - e * tu)[::-1][1:]); yc += [("upper", k) for k in lay[::-1]]
    X, Y = np.meshgrid(_refine_edges(xs), _refine_edges(ys), indexing="ij")
    ni, nj = len(xc), len(yc)
    mask = np.zeros((ni, nj), bool)
    Q = np.zeros((ni, nj, 6, 6)); rho = np.zeros((ni, nj)); reg = np.zeros((ni, nj), int)
    normals = {"upper": (0.0, 1.0), "lower": (0.0, -1.0), "front": (-1.0, 0.0), "rear": (1.0, 0.0)}
    cache = {}
    for i, (kx, lx) in enumerate(xc):
        for j, (ky, ly) in enumerate(yc):
            wall, lay = (ky, ly) if ky != "mid" else (kx, lx)
            if wall == "mid":
                continue
            if corners == "mitre" and ky != "mid" and kx != "mid":
                # relative depth from the outer faces: layers wrap around the corner along its diagonal
                xm, ym = 0.5 * (xs[i] + xs[i + 1]), 0.5 * (ys[j] + ys[j + 1])
                d_web = (xm - x0) / tf if kx == "front" else (x1 - xm) / tr
                d_skin = (ym - y0) / tl if ky == "lower" else (y1 - ym) / tu
                if d_web < d_skin:
                    wall, lay = kx, lx
            if (wall, lay) not in cache:
                cache[wall, lay] = _ply_Q(L[wall], lay, normals[wall])
            mask[i, j] = True
            Q[i, j], rho[i, j] = cache[wall, lay]
            reg[i, j] = names.index(wall)
    return _q9_from_grid(X, Y, mask, Q, rho, reg, names)


def channel_mesh(width, height, walls, n_thick=5, mesh_size=None):
    """Channel (C) section: walls 'upper', 'lower' flanges and 'web' (at x2 = +width/2, flanges open at -width/2).

    Parameters
    ----------
    width, height : float
        Outer dimensions (m).
    walls : dict
        ``upper``, ``lower`` and ``web`` -> ``{'thickness': t, 'material': Material}`` or ``{'layup': [(Material, t,
        angle_deg), ...]}`` outer to inner.
    n_thick : int, optional
        Elements through each wall's thickness.
    mesh_size : float or None, optional
        Element size along the walls (m).

    Returns
    -------
    SectionMesh
        The mesh.
    """
    w = dict(walls)
    w["rear"] = w.pop("web")
    return box_mesh(width, height, w, n_thick, mesh_size, open_walls=("front",))


def tube_mesh(diameter, wall, n_thick=5, n_around=None):
    """Circular tube of outer diameter, wall {'thickness', 'material'} or {'layup'} outer -> inner, centred on the origin.

    Parameters
    ----------
    diameter : float
        Outer diameter (m).
    wall : dict
        ``{'thickness', 'material'}`` or ``{'layup'}`` outer to inner.
    n_thick : int, optional
        Elements through the wall's thickness.
    n_around : int or None, optional
        Elements around the circumference; None for a default from the diameter.

    Returns
    -------
    SectionMesh
        The mesh.
    """
    _check_positive(diameter=diameter)
    L = _layers(wall, "tube", n_thick)
    t = sum(tt for _, tt, _ in L)
    if t >= diameter / 2:
        raise ValueError(f"tube thickness {t} m must be < radius {diameter / 2} m")
    e, lay = _wall_fractions(L, n_thick)
    r_edges = diameter / 2 - e * t                       # outer -> inner
    n_around = n_around or max(32, int(np.ceil(np.pi * diameter / (2 * t / n_thick))) // 2)
    th = np.linspace(0, 2 * np.pi, 2 * n_around + 1)[:-1]
    r = _refine_edges(r_edges)
    R, TH = np.meshgrid(r, th, indexing="ij")  # i: radial (not periodic), j: around -> swap for periodic i
    X = (R * np.cos(TH)).T; Y = (R * np.sin(TH)).T       # (2*n_around, 2*nr+1)
    nr = len(lay)
    mask = np.ones((n_around, nr), bool)
    thc = (np.arange(n_around) + 0.5) * 2 * np.pi / n_around
    Q = np.zeros((n_around, nr, 6, 6)); rho = np.zeros((n_around, nr))
    for j in range(nr):
        nrm = np.column_stack([np.cos(thc), np.sin(thc)])
        m, _, ang = L[lay[j]]
        Q[:, j] = ply_stiffness(m, ang, nrm); rho[:, j] = m.rho
    return _q9_from_grid(X, Y, mask, Q, rho, np.zeros((n_around, nr), int), ["tube"], periodic_i=True)


def airfoil_box_walls(walls, chord, front_spar, rear_spar, n_thick, skin_offset, corners):
    """Checked options and wall data of an airfoil wingbox (shared by the structured and gmsh meshers):
    wall names, layers per wall (outer -> inner), wall thicknesses and element-edge fractions.

    Parameters
    ----------
    walls : dict
        Wall name -> wall data, as for :func:`airfoil_box_mesh`.
    chord : float
        Chord (m).
    front_spar, rear_spar : float
        Spar web midlines (chord fractions).
    n_thick : int
        Elements through each wall's thickness.
    skin_offset : {"inward", "midline"}
        Skin placement about the mould line.
    corners : {"mitre", "skins"}
        Corner ownership.

    Returns
    -------
    tuple
        Wall names, layers per wall, wall thicknesses and element-edge fractions.
    """
    if corners not in ("skins", "mitre"):
        raise ValueError(f"corners must be 'skins' or 'mitre', got {corners!r}")
    if skin_offset not in ("inward", "midline"):
        raise ValueError(f"skin_offset must be 'inward' or 'midline', got {skin_offset!r}")
    _check_positive(chord=chord)
    if not 0.0 < front_spar < rear_spar < 1.0:
        raise ValueError(f"need 0 < front_spar < rear_spar < 1 (chord fractions), got {front_spar}, {rear_spar}")
    names = ["upper", "lower", "front", "rear"]
    L = {w: _layers(walls[w], w, n_thick) for w in names}
    T = {w: sum(t for _, t, _ in L[w]) for w in names}
    fr = {w: _wall_fractions(L[w], n_thick) for w in names}
    return names, L, T, fr


def airfoil_box_mesh(upper, lower, chord, front_spar, rear_spar, walls, twist_deg=0.0,
                     n_thick=5, mesh_size=None, skin_offset="inward", stringers=(), corners="mitre"):
    """Wingbox of an airfoil between spars (mapped Q9 grid); origin at the leading edge, x2 aft along the chord.

    ``upper``/``lower``: functions z/c(x/c) of the outer mould line. Spar web midlines at
    ``front_spar``/``rear_spar`` (chord fractions). Skins are offset inward from the OML by their
    thickness measured normal to the surface (``skin_offset='inward'``), or centred on it
    (``'midline'``: the OML points are the skin midline, offset both ways, as in Fig. 4.15a).
    ``twist_deg`` rotates the section nose-up about the origin. Walls as for :func:`box_mesh`.
    ``stringers``: blade stringers (Fig. 4.17), each {'surface': 'upper'|'lower', 'x': chord fraction
    of its centre, 'width', 'height' (m), 'material'} standing on the inner skin face; all stringers
    on one surface share one height. ``corners``: as for :func:`box_mesh` ('mitre' or 'skins').

    Parameters
    ----------
    upper, lower : callable
        z/c(x/c) of the upper and lower outer mould line.
    chord : float
        Chord (m).
    front_spar, rear_spar : float
        Spar web midlines (chord fractions).
    walls : dict
        Wall name -> ``{'thickness', 'material'}`` or ``{'layup'}``, as for :func:`box_mesh`.
    twist_deg : float, optional
        Nose-up rotation of the section about the origin (deg).
    n_thick : int, optional
        Elements through each wall's thickness.
    mesh_size : float or None, optional
        Element size along the walls (m); None for chord / 60.
    skin_offset : {"inward", "midline"}, optional
        Skins inside the mould line, or centred on it.
    stringers : sequence of dict, optional
        Blade stringers ``{'surface', 'x', 'width', 'height', 'material'}``.
    corners : {"mitre", "skins"}, optional
        Corner ownership, as for :func:`box_mesh`.

    Returns
    -------
    SectionMesh
        The mesh.
    """
    names, L, T, fr = airfoil_box_walls(walls, chord, front_spar, rear_spar, n_thick, skin_offset, corners)
    xf, xr = front_spar * chord, rear_spar * chord
    h = mesh_size or chord / 60
    xs, xc = [], []
    e, lay = fr["front"]; xs += list(xf - T["front"] / 2 + e * T["front"]); xc += [("front", k) for k in lay]
    a, b = xf + T["front"] / 2, xr - T["rear"] / 2
    if b <= a:
        raise ValueError("spar webs overlap: rear_spar - front_spar too small for the spar thicknesses")
    str_list = [dict(st) for st in stringers]
    str_h = {"upper": 0.0, "lower": 0.0}
    bps = [a, b]
    for k, st in enumerate(str_list):
        surf = st.get("surface")
        if surf not in ("upper", "lower"):
            raise ValueError(f"stringer {k}: surface must be 'upper' or 'lower', got {surf!r}")
        _check_positive(**{f"stringer {k} width": st["width"], f"stringer {k} height": st["height"]})
        x0, x1 = st["x"] * chord - st["width"] / 2, st["x"] * chord + st["width"] / 2
        if x0 <= a or x1 >= b:
            raise ValueError(f"stringer {k}: x = {st['x']} must place it between the spar webs "
                             f"({a / chord:.4f} < x +- width/2 / chord < {b / chord:.4f})")
        if str_h[surf] and abs(str_h[surf] - st["height"]) > 1e-12:
            raise ValueError(f"stringer {k}: all {surf} stringers must share one height, got {st['height']} m")
        str_h[surf] = float(st["height"])
        st["x0"], st["x1"] = x0, x1
        bps += [x0, x1]
    bps = np.unique(bps)
    for x0, x1 in zip(bps[:-1], bps[1:]):
        xm = 0.5 * (x0 + x1)
        on = {sf: next((k for k, st in enumerate(str_list) if st["surface"] == sf and st["x0"] < xm < st["x1"]), -1)
              for sf in ("upper", "lower")}
        n_iv = span_divisions(x1 - x0, h, 2 if max(on.values()) >= 0 else 1)
        xs += list(np.linspace(x0, x1, n_iv + 1)[1:]); xc += [("mid", (on["upper"], on["lower"]))] * n_iv
    e, lay = fr["rear"]; xs += list((xr + T["rear"] / 2 - e * T["rear"])[::-1][1:]); xc += [("rear", k) for k in lay[::-1]]
    xn = _refine_edges(xs)
    zu, zl = chord * upper(xn / chord), chord * lower(xn / chord)
    d = 1e-4
    su = chord * (upper(xn / chord + d) - upper(xn / chord - d)) / (2 * d * chord)
    sl = chord * (lower(xn / chord + d) - lower(xn / chord - d)) / (2 * d * chord)
    tu_v, tl_v = T["upper"] * np.sqrt(1 + su ** 2), T["lower"] * np.sqrt(1 + sl ** 2)   # vertical offsets
    if skin_offset == "midline":
        zu, zl = zu + tu_v / 2, zl - tl_v / 2
    inner_u, inner_l = zu - tu_v, zl + tl_v
    if np.any(inner_u <= inner_l):
        raise ValueError("upper + lower skin thickness exceeds the airfoil depth between the spars")
    eL, layL = fr["lower"]; eU, layU = fr["upper"]
    hmin = float(np.min(inner_u - inner_l)) - str_h["upper"] - str_h["lower"]
    if hmin <= 0:
        raise ValueError("stringers taller than the space between the skins")
    n_midz = span_divisions(hmin, h)
    n_s = {sf: (4 if str_h[sf] else 0) for sf in ("upper", "lower")}
    # vertical fractions per node column: lower skin, interior, upper skin
    cols = []
    for k in range(xn.size):
        z = list(zl[k] + eL * tl_v[k])
        z += list(inner_l[k] + str_h["lower"] * np.arange(1, n_s["lower"] + 1) / max(n_s["lower"], 1))
        z += list(np.linspace(inner_l[k] + str_h["lower"], inner_u[k] - str_h["upper"], n_midz + 1)[1:])
        z += list(inner_u[k] - str_h["upper"] * np.arange(n_s["upper"] - 1, -1, -1) / max(n_s["upper"], 1))[:n_s["upper"]]
        z += list((zu[k] - eU * tu_v[k])[::-1][1:])
        cols.append(_refine_edges(z))
    Zn = np.array(cols)
    Xn = np.broadcast_to(xn[:, None], Zn.shape).copy()
    yc = ([("lower", k) for k in layL] + [("slower", 0)] * n_s["lower"] + [("mid", 0)] * n_midz
          + [("supper", 0)] * n_s["upper"] + [("upper", k) for k in layU[::-1]])
    ni, nj = len(xc), len(yc)
    mask = np.zeros((ni, nj), bool)
    Q = np.zeros((ni, nj, 6, 6)); rho = np.zeros((ni, nj)); reg = np.zeros((ni, nj), int)
    xcell = xn[1::2]
    slope_u = np.interp(xcell, xn, su); slope_l = np.interp(xcell, xn, sl)
    tw = np.radians(twist_deg)
    rot = np.array([[np.cos(tw), np.sin(tw)], [-np.sin(tw), np.cos(tw)]])   # nose-up about the LE: aft points move down
    eF, eR = fr["front"][0], fr["rear"][0]
    nF, nLs = len(eF) - 1, len(eL) - 1

    def _web_depth(i):          # depth of x-cell i below the web's outer face, fraction of its thickness
        if i < nF:
            return 0.5 * (eF[i] + eF[i + 1])
        k = ni - 1 - i
        return 0.5 * (eR[k] + eR[k + 1])

    def _skin_depth(j):
        if j < nLs:
            return 0.5 * (eL[j] + eL[j + 1])
        k = nj - 1 - j
        return 0.5 * (eU[k] + eU[k + 1])

    cells = {}
    for i, (kx, lx) in enumerate(xc):
        for j, (ky, ly) in enumerate(yc):
            if ky in ("upper", "lower"):
                wall, lay = ky, ly
                if corners == "mitre" and kx in ("front", "rear") and _web_depth(i) < _skin_depth(j):
                    wall, lay = kx, lx
            elif kx != "mid":
                wall, lay = kx, lx
            elif ky == "supper" and lx[0] >= 0:
                wall, lay = "stringer", lx[0]
            elif ky == "slower" and lx[1] >= 0:
                wall, lay = "stringer", lx[1]
            else:
                continue
            cells.setdefault((wall, lay), []).append((i, j))
    for (wall, lay), ij in cells.items():
        ii, jj = np.array(ij).T
        if wall == "upper":
            nrm = np.column_stack([-slope_u[ii], np.ones(ii.size)]) / np.hypot(slope_u[ii], 1.0)[:, None]
        elif wall == "lower":
            nrm = np.column_stack([slope_l[ii], -np.ones(ii.size)]) / np.hypot(slope_l[ii], 1.0)[:, None]
        else:
            nrm = np.broadcast_to(np.array({"front": [-1.0, 0.0], "rear": [1.0, 0.0]}.get(wall, [0.0, 1.0])),
                                  (ii.size, 2))
        mask[ii, jj] = True
        if wall == "stringer":
            m, ang = str_list[lay]["material"], np.radians(float(str_list[lay].get("angle_deg", 0.0)))
        else:
            m, _, ang = L[wall][lay]
        Q[ii, jj] = ply_stiffness(m, ang, nrm @ rot.T)
        rho[ii, jj] = m.rho
        reg[ii, jj] = (names + ["stringer"]).index(wall)
    P = np.stack([Xn, Zn], axis=-1) @ rot.T
    return _q9_from_grid(P[..., 0], P[..., 1], mask, Q, rho, reg, names + ["stringer"])
