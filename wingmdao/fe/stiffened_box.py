"""Shell model of a stiffened wingbox for CalculiX linear buckling (``*BUCKLE``).

The box of :func:`wingmdao.fe.box_model.build_shell_box` (S8R on the skin and spar-web
mid-surfaces, ribs as shells in the rib planes sharing the ring nodes, root ring clamped) with
blade stiffeners on the inner faces of both skins:

* **Count and positions.** ``count`` blades per skin (default round(mean outer width / pitch)),
  the same along the span, at the design pitch p, centred on the box: chordwise offsets
  (k - (count - 1) / 2) p from the section centre. The interior skin bays are p wide; the two
  bays next to the spars take the rest of the width.
* **Webs.** Each blade is a spanwise strip of S8R shells in the plane x = const, from the skin
  mid-surface (sharing the skin's nodes on the stiffener line) inward to the skin's inner face
  plus the web height h (the panel model of :mod:`wingmdao.fe.panel_buckling` does the same: the
  part inside the skin half-thickness is counted twice). Height and thickness vary linearly
  between the stations (the design's per-station values interpolated at every mesh line; each
  element takes the mean thickness of its two ends).
* **Area per width.** The sizing smears the stiffeners over the outer box width w at
  a = h t_s / p per width, i.e. w / p blades, not an integer. The FE blades keep the design's h
  and p; their thickness is t_s w / (count p) (``thickness_scale``, about 1.06 for PEGASUS), so the
  stiffener area per width, mass, and axial and bending stiffness per width are the design's.
* **Ribs.** The stiffener webs pass through the rib planes; there u_x (out of the web's plane)
  of every web node equals u_x of its foot on the skin (``*EQUATION``), as a rib clip holds it.
* **Mesh.** ``bay_elements`` S8R across each interior skin bay (the edge bays in proportion),
  ``height_elements`` across each spar web, ``web_elements`` over the blade height, elements of
  at most ``span_element_size`` along the span with a mesh line on every station and rib.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from wingmdao.fe.box_model import BoxSections, ShellBox, build_shell_box, station_loads
from wingmdao.fe.calculix import buckle_step, mode_displacements, parse_dat, run_deck, static_step

SKINS = ("upper", "lower")


@dataclass
class StiffenedBox:
    """The built model: the shell box, the blade count and thickness scale, each node's part
    (``upper_skin``, ``lower_skin``, ``front_spar``, ``rear_spar``, ``upper_stiffeners``,
    ``lower_stiffeners``, ``ribs``) and the elements per part.

    Parameters
    ----------
    box : ShellBox
        The shell model.
    count : int
        Blade stiffeners per skin.
    pitch : float
        Stiffener pitch (m).
    thickness_scale : numpy.ndarray
        Per station, w / (count pitch) (-).
    node_part : dict, optional
        Node id -> part name.
    part_elements : dict, optional
        Part name -> element ids.
    num_webs : int, optional
        Number of stiffener web elements.
    num_ribs : int, optional
        Number of ribs.
    overlap_kg : float, optional
        Web mass inside the skins' half thickness, counted twice (kg).
    """

    box: ShellBox
    count: int
    pitch: float
    thickness_scale: np.ndarray            # per station: w / (count p)
    node_part: dict = field(default_factory=dict)
    part_elements: dict = field(default_factory=dict)
    num_webs: int = 0
    num_ribs: int = 0
    overlap_kg: float = 0.0                # web mass inside the skins' half thickness (counted twice)

    @property
    def deck(self):
        return self.box.deck

    @property
    def num_elements(self) -> int:
        return self.box.num_elements


def _linspace_tail(a, b, n):
    return list(np.linspace(a, b, n + 1)[1:])


def build_stiffened_box(sections: BoxSections, material, stiffeners: dict, pitch: float, *, count=None,
                        bay_elements=2, web_elements=1, height_elements=4, span_element_size=0.1, ribs_y=(),
                        rib_thickness=0.002) -> StiffenedBox:
    """Mesh the stiffened box (module docstring). ``stiffeners``: ``{"upper": (h, ts),
    "lower": (h, ts)}``, web height and thickness per section (m, (n,) each).

    Parameters
    ----------
    sections : BoxSections
        Streamwise sections of the box.
    material : Material
        Isotropic material.
    stiffeners : dict
        ``{"upper": (h, ts), "lower": (h, ts)}``, web height and thickness per section (m).
    pitch : float
        Stiffener pitch (m).
    count : int or None, optional
        Stiffeners per skin; None for the mean width over ``pitch``, rounded (at least 1).
    bay_elements : int, optional
        Elements across a skin bay.
    web_elements : int, optional
        Elements up a stiffener web.
    height_elements : int, optional
        Elements up a spar web.
    span_element_size : float, optional
        Largest element length along the span (m).
    ribs_y : sequence of float, optional
        Rib span coordinates (m).
    rib_thickness : float, optional
        Rib thickness (m).

    Returns
    -------
    StiffenedBox
        The model.
    """
    n_sec = len(sections.centres)
    dims = {}
    for s in SKINS:
        h, ts = (np.broadcast_to(np.asarray(v, float), (n_sec,)).copy() for v in stiffeners[s])
        if not np.all(np.isfinite(h) & (h > 0) & np.isfinite(ts) & (ts > 0)):
            raise ValueError(f"{s} stiffeners: heights and thicknesses must be positive (m), got {h}, {ts}")
        dims[s] = (h, ts)
    if not (math.isfinite(pitch) and pitch > 0):
        raise ValueError(f"stiffener pitch = {pitch} m; allowed range (0, inf)")
    for name, v in (("bay_elements", bay_elements), ("web_elements", web_elements),
                    ("height_elements", height_elements)):
        if int(v) < 1:
            raise ValueError(f"{name} = {v}; allowed >= 1")
    t = sections.thickness
    a_mid = sections.widths / 2 - (t["t_front_spar"] + t["t_rear_spar"]) / 4
    n = int(count) if count is not None else max(1, int(round(float(np.mean(sections.widths)) / pitch)))
    offsets = (np.arange(n) - (n - 1) / 2) * pitch
    edge = float(a_mid.min() - offsets[-1])
    if n < 1 or edge <= 0.05 * pitch:
        raise ValueError(f"{n} stiffeners at {pitch} m pitch do not fit in the box (mid-surface width "
                         f"{2 * a_mid.min():.4g} m); allowed: count <= {int(2 * a_mid.min() / pitch)}")
    ne = max(1, int(math.ceil(bay_elements * float(a_mid.max() - offsets[-1]) / pitch - 1e-9)))
    nc = 2 * ne + (n - 1) * int(bay_elements)

    def breaks(a):
        xs = [-a] + _linspace_tail(-a, offsets[0], ne)
        for k in range(n - 1):
            xs += _linspace_tail(offsets[k], offsets[k + 1], int(bay_elements))
        return np.array(xs + _linspace_tail(offsets[-1], a, ne))

    box = build_shell_box(sections, material, element="S8R", chord_elements=nc, height_elements=int(height_elements),
                          span_element_size=span_element_size, ribs_y=ribs_y, rib_thickness=rib_thickness,
                          skin_breaks=breaks)
    deck = box.deck
    q = 2
    Nc, Nh = q * nc, q * int(height_elements)
    parts = {}
    for ring in box.rings:      # ring order: lower skin, rear spar, upper skin, front spar
        for i, nd in enumerate(ring):
            parts[int(nd)] = ("lower_skin" if i < Nc else "rear_spar" if i < Nc + Nh
                              else "upper_skin" if i < 2 * Nc + Nh else "front_spar")
    # stiffener lines: break index jb = ne + k (n - 1 interior bays between the blades)
    jbs = [ne + k * int(bay_elements) for k in range(n)]
    ring_index = {"lower": [q * jb for jb in jbs], "upper": [Nc + Nh + (Nc - q * jb) for jb in jbs]}
    ys = box.span_y
    y_sec = sections.centres[:, 1]
    scale = sections.widths / (n * pitch)
    rib_lines = {int(np.argmin(np.abs(ys - yr))) for yr in ribs_y}
    Nk = q * int(web_elements)
    eqs = ["*EQUATION"]
    part_elements = {}
    nweb = 0
    overlap = 0.0
    for s in SKINS:
        h = np.interp(ys, y_sec, dims[s][0])
        ts = np.interp(ys, y_sec, dims[s][1] * scale)
        tskin = np.interp(ys, y_sec, t[f"t_{s}_skin"])
        inward = -1.0 if s == "upper" else 1.0
        elems = []
        for idx in ring_index[s]:
            grid = np.zeros((len(ys), Nk + 1), dtype=int)
            for j in range(len(ys)):
                foot = int(box.rings[j][idx])
                p0 = np.array(deck.nodes[foot])
                top = tskin[j] / 2 + h[j]
                grid[j, 0] = foot
                for k in range(1, Nk + 1):
                    if j % 2 and k % 2:
                        continue            # no centre node in S8R
                    nd = int(deck.add_nodes([p0 + np.array([0.0, 0.0, inward * top * k / Nk])])[0])
                    grid[j, k] = nd
                    parts[nd] = f"{s}_stiffeners"
                    if j in rib_lines:
                        eqs.append(f"2\n{nd}, 1, 1.0, {foot}, 1, -1.0")
            for j in range(0, len(ys) - 1, q):
                for k in range(0, Nk, q):
                    conn = [grid[j, k], grid[j + 2, k], grid[j + 2, k + 2], grid[j, k + 2],
                            grid[j + 1, k], grid[j + 2, k + 1], grid[j + 1, k + 2], grid[j, k + 1]]
                    name = f"ST{s[0].upper()}{len(elems) + 1}"
                    elems += deck.add_elements("S8R", name, [conn])
                    tw = 0.5 * (ts[j] + ts[j + 2])
                    deck.sections.append(f"*SHELL SECTION, ELSET={name}, MATERIAL=MAT\n{tw:.10g}")
                    if k == 0:   # the skin half thickness, at the foot of the web
                        overlap += tw * (ys[j + 2] - ys[j]) * 0.25 * (tskin[j] + tskin[j + 2]) * material.rho
            nweb += 1
        part_elements[f"{s}_stiffeners"] = elems
    if len(eqs) > 1:
        deck.model_extra.append("\n".join(eqs))
    for nd in deck.nodes:
        parts.setdefault(int(nd), "ribs")
    box.num_elements += sum(len(v) for v in part_elements.values())
    return StiffenedBox(box, n, float(pitch), scale, parts, part_elements, nweb, len(ribs_y), overlap)


def _section_thickness(deck) -> dict:
    out = {}
    for text in deck.sections:
        m = re.match(r"\*SHELL SECTION, ELSET=(\S+?), MATERIAL=\S+\n(\S+)", text)
        if m:
            out[m.group(1)] = float(m.group(2))
    return out


def shell_mass(deck, density: float) -> dict:
    """Mass (kg) of the deck's shell elements, area (of the corner-node quadrilateral, half the
    cross product of its diagonals) x section thickness x ``density``, by element set kind:
    ``walls`` (skins and spar webs), ``stiffeners``, ``ribs``, and ``total``.

    Parameters
    ----------
    deck : Deck
        The deck.
    density : float
        Material density (kg/m^3).

    Returns
    -------
    dict
        ``walls``, ``stiffeners``, ``ribs`` and ``total`` masses (kg).
    """
    thick = _section_thickness(deck)
    out = {"walls": 0.0, "stiffeners": 0.0, "ribs": 0.0}
    for etype, elset, block in deck.elements:
        if not etype.startswith("S") or elset not in thick:
            continue
        kind = "ribs" if elset.startswith("RIB") else "stiffeners" if elset.startswith("ST") else "walls"
        for conn in block.values():
            p = np.array([deck.nodes[c] for c in conn[:4]])
            area = 0.5 * np.linalg.norm(np.cross(p[2] - p[0], p[3] - p[1]))
            out[kind] += area * thick[elset] * density
    out["total"] = sum(out.values())
    return out


def solve_buckling(model: StiffenedBox, loads, modes: int = 5, keep_dir=None) -> dict:
    """``*BUCKLE`` of the station loads [(y, centre, F, M)] (entering through the rings'
    distributing couplings): the lowest positive factor (``factor``), all factors, and where the
    first positive mode peaks: the part and position of the node with the largest displacement
    magnitude (``peak_part``, ``peak_xyz``) and each part's largest displacement relative to it
    (``part_peaks``); ``positive_modes``: the same for every positive mode, lowest first.

    Parameters
    ----------
    model : StiffenedBox
        The built model.
    loads : sequence of tuple
        ``(y, centre, F, M)`` station loads (m, m, N, N m).
    modes : int, optional
        Buckling factors extracted.
    keep_dir : str, path-like or None, optional
        Folder to keep the CalculiX files in; None for a temporary one.

    Returns
    -------
    dict
        ``factor``, ``factors``, ``peak_part``, ``peak_xyz``, ``part_peaks``, ``positive_modes``.
    """
    if not (isinstance(modes, (int, np.integer)) and 1 <= modes <= 50):
        raise ValueError(f"buckling modes = {modes!r}; allowed: an integer in [1, 50]")
    deck = model.deck
    deck.nsets["ALLN"] = sorted(deck.nodes)
    run = run_deck(deck.text([buckle_step(modes, station_loads(model.box, loads), ["ALLN"])]), job="buckle",
                   keep_dir=keep_dir)
    factors = parse_dat(run["dat"])["buckling_factors"]
    positive = [(k, f) for k, f in enumerate(factors) if f > 0]
    if not positive:
        raise ValueError(f"no positive buckling factor among the {len(factors)} extracted ({factors.tolist()}); "
                         "ask for more modes")
    modes_out = []
    for k, f in sorted(positive, key=lambda kf: kf[1]):
        u = mode_displacements(run["dat"], k + 1, "ALLN")
        mags = {nd: float(np.linalg.norm(v)) for nd, v in u.items()}
        peak = max(mags, key=mags.get) if mags else None
        by_part: dict = {}
        for nd, m in mags.items():
            p = model.node_part.get(nd, "ribs")
            by_part[p] = max(by_part.get(p, 0.0), m)
        top = max(by_part.values()) if by_part else 1.0
        modes_out.append({"mode_number": k + 1, "factor": float(f), "peak_node": peak,
                          "peak_part": model.node_part.get(peak) if peak else None,
                          "peak_xyz": list(deck.nodes[peak]) if peak else None,
                          "part_peaks": {p: v / top for p, v in sorted(by_part.items())}})
    first = modes_out[0]
    return dict(first, factors=factors.tolist(), positive_modes=modes_out, time=run["time"])


def _element_index(deck) -> dict:
    """``{element id: (corner-node centroid (3,), element set)}`` of the deck's elements."""
    return {eid: (np.array([deck.nodes[c] for c in conn[:4]]).mean(axis=0), elset)
            for _, elset, block in deck.elements for eid, conn in block.items()}


def skin_running_loads(model: StiffenedBox, loads, span_range=None, keep_dir=None) -> dict:
    """The linear static state of the buckling deck (the same station loads, a ``*STATIC`` step):
    the running loads (N/m, compression negative) of every skin element whose centroid lies in
    ``span_range`` = (y0, y1) (m; None: the whole span).

    Each S8R element's membrane stress is the mean of its integration-point stresses (CalculiX
    expands S8R into C3D20R with two points through the thickness, so the mean drops the
    bending part); times the element thickness it is the running load. The skins lie close to
    the global x-y plane (x aft, y outboard), so ``n_span`` = sigma_yy t, ``n_chord`` =
    sigma_xx t and ``n_shear`` = sigma_xy t (the skins' slope from the box taper, a few
    hundredths, is neglected). Returns per skin (``upper``, ``lower``) arrays ``x_m``, ``y_m``,
    ``thickness_m``, ``n_span``, ``n_chord``, ``n_shear`` ordered by span row then front to rear,
    and ``stiffener_sigma_span`` (Pa): the blades' mean axial stress per element (``x_m``,
    ``y_m`` beside it), for the skin-plus-stiffener load the panel model smears.

    Parameters
    ----------
    model : StiffenedBox
        The built model.
    loads : sequence of tuple
        ``(y, centre, F, M)`` station loads (m, m, N, N m).
    span_range : tuple or None, optional
        (y0, y1) span range (m); None for the whole span.
    keep_dir : str, path-like or None, optional
        Folder to keep the CalculiX files in; None for a temporary one.

    Returns
    -------
    dict
        ``upper`` and ``lower``: element arrays of position (m), thickness (m) and running loads
        (N/m), with the stiffeners' axial stress (Pa).
    """
    box = model.box
    nc, nh = box.counts
    thick = _section_thickness(model.deck)
    lo, hi = (-np.inf, np.inf) if span_range is None else (float(span_range[0]), float(span_range[1]))
    if not lo < hi:
        raise ValueError(f"span range = {span_range}; allowed: y0 < y1 (m)")
    index = _element_index(model.deck)
    picked = {"lower": [], "upper": []}
    for row in box.wall_elements:
        lower, upper = row[:nc], row[nc + nh:2 * nc + nh][::-1]      # both front to rear
        for skin, eids in (("lower", lower), ("upper", upper)):
            for e in eids:
                c, elset = index[e]
                if lo <= c[1] <= hi:
                    picked[skin].append((e, c, thick[elset]))
    stiff = []
    for s in SKINS:
        for e in model.part_elements.get(f"{s}_stiffeners", []):
            c, elset = index[e]
            if lo <= c[1] <= hi:
                stiff.append((s, e, c))
    eids = [e for v in picked.values() for e, _, _ in v] + [e for _, e, _ in stiff]
    if not eids:
        raise ValueError(f"span range = {span_range}: no skin element has its centroid there")
    deck = model.deck
    deck.elsets["NOUT"] = sorted(set(eids))
    run = run_deck(deck.text([static_step(station_loads(box, loads), [], stress_elsets=("NOUT",))]), job="static",
                   keep_dir=keep_dir)
    del deck.elsets["NOUT"]
    stress = parse_dat(run["dat"])["stresses"]
    out = {}
    for skin, rows in picked.items():
        m = np.array([stress[e].mean(axis=0) for e, _, _ in rows]).reshape(-1, 6)
        t = np.array([tk for _, _, tk in rows])
        xyz = np.array([c for _, c, _ in rows]).reshape(-1, 3)
        out[skin] = {"x_m": xyz[:, 0], "y_m": xyz[:, 1], "thickness_m": t, "n_span": m[:, 1] * t,
                     "n_chord": m[:, 0] * t, "n_shear": m[:, 3] * t}
        sel = [(c, stress[e].mean(axis=0)[1]) for s, e, c in stiff if s == skin]
        out[skin]["stiffener_x_m"] = np.array([c[0] for c, _ in sel])
        out[skin]["stiffener_y_m"] = np.array([c[1] for c, _ in sel])
        out[skin]["stiffener_sigma_span"] = np.array([v for _, v in sel])
    out["time"] = run["time"]
    return out


def running_load_profile(skin_loads: dict) -> list:
    """Per span row of :func:`skin_running_loads` (one skin's arrays), the values a panel check
    reads: ``y_m``; ``n_span_front``, ``n_span_mid``, ``n_span_rear`` and ``n_span_min`` (the
    elements at the front and rear edges and nearest mid-chord, and the most compressive);
    ``n_chord_mid`` and ``n_chord_min``; ``n_shear_front``, ``n_shear_rear`` and
    ``n_shear_max_abs`` (N/m, compression negative).

    Parameters
    ----------
    skin_loads : dict
        One skin's arrays of :func:`skin_running_loads`.

    Returns
    -------
    list of dict
        Per span row, the running loads a panel check reads (N/m).
    """
    y = np.asarray(skin_loads["y_m"])
    rows = []
    for yy in np.unique(np.round(y, 6)):
        m = np.flatnonzero(np.abs(y - yy) < 1e-6)
        m = m[np.argsort(np.asarray(skin_loads["x_m"])[m])]
        ns, nc, nq = (np.asarray(skin_loads[k])[m] for k in ("n_span", "n_chord", "n_shear"))
        k = len(m) // 2
        mid = slice(k - 1, k + 1) if len(m) % 2 == 0 else slice(k, k + 1)
        rows.append({"y_m": float(yy), "n_span_front": float(ns[0]), "n_span_mid": float(ns[mid].mean()),
                     "n_span_rear": float(ns[-1]), "n_span_min": float(ns.min()),
                     "n_chord_mid": float(nc[mid].mean()), "n_chord_min": float(nc.min()),
                     "n_shear_front": float(nq[0]), "n_shear_rear": float(nq[-1]),
                     "n_shear_max_abs": float(np.abs(nq).max())})
    return rows
