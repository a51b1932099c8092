"""Linear buckling (CalculiX ``*BUCKLE``) of a flat, simply supported, blade- or T-stiffened panel.

Model (docs/verification-calculix.md, "Stiffened-panel buckling (CalculiX)"):

* Frame: x along the stiffeners (0 <= x <= a), y across (0 <= y <= W), z normal to the skin; the
  skin mid-plane is z = 0, the stiffeners stand on the +z side.
* Skin and stiffener webs: S8R shells on a structured mesh sharing nodes. With ``n`` stiffeners
  the panel width is W = n p (pitch p = W / n), stiffener k at the centre of its bay,
  y_k = (k + 1/2) p, so the inner skin spans between stiffeners are p wide and the two edge
  strips p/2. A web's shell runs from the skin mid-plane z = 0 to z_top = t/2 + h (+ t_s with a
  flange): its top is where the smeared model puts it (web from the skin face to h above it);
  the part inside the skin half-thickness (t/2 x t_s per web) is counted twice.
* T stiffeners: the flange (width b_f, thickness t_s) is added to the skin thickness over its
  footprint ``|y - y_k| < b_f/2`` (skin elements there have t + t_s, symmetric about the skin
  mid-plane: no offset); the web then starts at the flange's top face.
* Material: isotropic (E, nu).
* Supports: u_z = 0 on all four skin edges (simple support, rotations free); in-plane only
  u_x at (0, 0) and u_y at (0, 0) and (a, 0) (the rigid-body motions; the applied loads are in
  equilibrium, so these reactions are zero). Web ends (x = 0 and x = a) are held out of their
  plane as ribs would: u_y of every web end node equals u_y of its skin junction node
  (``*EQUATION``), which keeps the skin's in-plane motion (Poisson expansion, shear) free.
* Loads: N_x (N/m of panel width, compression negative) on the edges x = 0 and x = a, spread
  over the skin and the webs in proportion to their axial stiffness, so that the pre-buckling
  strain is uniform: eps = N_x W / (E A), A = the skin (with flanges) plus the webs' shell
  area; a line of thickness t_i carries E t_i eps per length. N_xy (shear flow, N/m) on the
  four skin edges (+y on x = a, -y on x = 0, +x on y = W, -x on y = 0). Both as consistent
  nodal forces of the quadratic edges, L q (1, 4, 1) / 6.
* Output: the lowest positive buckling factor of the ``*BUCKLE`` step (critical loads = factor x
  applied loads), and whether its mode is local (the stiffener lines stay nearly straight) or
  global.
"""

from __future__ import annotations

import math
import numbers
import os

import numpy as np

from wingmdao.fe.calculix import Deck, buckle_step, mode_displacements, parse_dat, quadratic_edge_forces, run_deck

#: elements per shortest half wave by default (mesh_size = min(a, p) / DEFAULT_DIVISIONS)
DEFAULT_DIVISIONS = 8
#: a mode is "global" when the stiffener junction lines deflect more than this fraction of the
#: largest skin deflection
GLOBAL_MODE_RATIO = 0.2


def _positive(name, value, unit, upper=None):
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value) or value <= 0:
        raise ValueError(f"{name} = {value!r} {unit}; allowed range (0, {upper if upper is not None else 'inf'}) {unit}")
    if upper is not None and value >= upper:
        raise ValueError(f"{name} = {value!r} {unit}; allowed range (0, {upper:.6g}) {unit}")
    return float(value)


def _finite(name, value, unit):
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
        raise ValueError(f"{name} = {value!r} {unit}; allowed: a finite number")
    return float(value)


def _divisions(length, size):
    return max(1, int(math.ceil(length / size - 1e-9)))


def _validate(length, width, skin_thickness, E, nu, n_stiffeners, stiffener_height, stiffener_thickness,
              flange_width, nx, nxy, mesh_size, n_modes):
    a = _positive("length", length, "m")
    W = _positive("width", width, "m")
    t = _positive("skin_thickness", skin_thickness, "m", upper=min(a, W) / 10)
    E = _positive("E", E, "Pa")
    if isinstance(nu, bool) or not isinstance(nu, numbers.Real) or not (-1.0 < nu < 0.5):
        raise ValueError(f"nu = {nu!r}; allowed range (-1, 0.5)")
    if isinstance(n_stiffeners, bool) or not isinstance(n_stiffeners, numbers.Integral) or n_stiffeners < 0:
        raise ValueError(f"n_stiffeners = {n_stiffeners!r}; allowed: an integer >= 0")
    n = int(n_stiffeners)
    h = ts = bf = None
    if n == 0:
        for name, v in (("stiffener_height", stiffener_height), ("stiffener_thickness", stiffener_thickness),
                        ("flange_width", flange_width)):
            if v is not None:
                raise ValueError(f"{name} = {v!r} given with n_stiffeners = 0; allowed: None without stiffeners")
    else:
        p = W / n
        if stiffener_height is None or stiffener_thickness is None:
            raise ValueError(f"stiffener_height and stiffener_thickness are required with n_stiffeners = {n} "
                             f"(got {stiffener_height!r}, {stiffener_thickness!r})")
        h = _positive("stiffener_height", stiffener_height, "m", upper=a)
        ts = _positive("stiffener_thickness", stiffener_thickness, "m", upper=min(h, p / 2))
        if flange_width is not None:
            bf = _positive("flange_width", flange_width, "m", upper=p)
            if bf <= ts:
                raise ValueError(f"flange_width = {flange_width!r} m; allowed range ({ts:.6g}, {p:.6g}) m "
                                 "(wider than the web, narrower than the pitch p = width / n_stiffeners)")
    nx = _finite("nx", nx, "N/m")
    nxy = _finite("nxy", nxy, "N/m")
    if nx >= 0.0 and nxy == 0.0:
        raise ValueError(f"nx = {nx!r} N/m with nxy = 0: nothing to buckle; allowed: nx < 0 (compression) "
                         "or nxy != 0")
    short = min(a, W / n if n else W)
    if mesh_size is None:
        size = short / DEFAULT_DIVISIONS
    else:
        size = _positive("mesh_size", mesh_size, "m", upper=short / 2 * (1 + 1e-9))   # half the span allowed
    if isinstance(n_modes, bool) or not isinstance(n_modes, numbers.Integral) or not (1 <= n_modes <= 50):
        raise ValueError(f"n_modes = {n_modes!r}; allowed: an integer in [1, 50]")
    return a, W, t, E, float(nu), n, h, ts, bf, nx, nxy, size, int(n_modes)


def _breaks(W, n, bf, size):
    """Element boundaries across the width (y), with every stiffener line and flange edge on one."""
    if n == 0:
        keys = [0.0, W]
    else:
        p = W / n
        keys = [0.0]
        for k in range(n):
            yk = (k + 0.5) * p
            keys += ([yk - bf / 2, yk, yk + bf / 2] if bf else [yk]) + [(k + 1) * p]
    out = [keys[0]]
    for y0, y1 in zip(keys[:-1], keys[1:]):
        out += list(np.linspace(y0, y1, _divisions(y1 - y0, size) + 1)[1:])
    return np.array(out)


def build_panel(length, width, skin_thickness, E, nu, *, n_stiffeners=0, stiffener_height=None,
                stiffener_thickness=None, flange_width=None, nx=0.0, nxy=0.0, mesh_size=None, n_modes=6):
    """The panel's deck (see the module docstring) and its bookkeeping:
    ``{"text", "num_elements", "num_nodes", "skin_nodes", "junction_nodes"}``.

    Parameters
    ----------
    length : float
        Panel length along the stiffeners (m).
    width : float
        Panel width (m).
    skin_thickness : float
        Skin thickness (m).
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio (-).
    n_stiffeners : int, optional
        Number of stiffeners.
    stiffener_height : float or None, optional
        Web height above the skin face (m).
    stiffener_thickness : float or None, optional
        Stiffener thickness (m).
    flange_width : float or None, optional
        Tee flange width (m); None for blades.
    nx : float, optional
        Running load along the stiffeners (N/m, compression negative).
    nxy : float, optional
        Shear flow (N/m).
    mesh_size : float or None, optional
        Element size (m); None for min(length, pitch) / 8.
    n_modes : int, optional
        Buckling factors extracted.

    Returns
    -------
    dict
        ``text``, ``num_elements``, ``num_nodes``, ``skin_nodes``, ``junction_nodes``.
    """
    a, W, t, E, nu, n, h, ts, bf, nx, nxy, size, n_modes = _validate(
        length, width, skin_thickness, E, nu, n_stiffeners, stiffener_height, stiffener_thickness, flange_width,
        nx, nxy, mesh_size, n_modes)
    xs = np.linspace(0.0, a, 2 * _divisions(a, size) + 1)          # quadratic: corner, mid, corner ...
    yb = _breaks(W, n, bf, size)
    ys = np.sort(np.concatenate([yb, 0.5 * (yb[:-1] + yb[1:])]))
    Ni, Nj = len(xs) - 1, len(ys) - 1
    deck = Deck("wingmdao stiffened panel buckling")
    deck.isotropic("MAT", E, nu)
    skin = np.zeros((Ni + 1, Nj + 1), dtype=int)
    for i, x in enumerate(xs):
        for j, y in enumerate(ys):
            if not (i % 2 and j % 2):
                skin[i, j] = deck.add_nodes([(x, y, 0.0)])[0]

    def quads(g, I, J):
        return [[g[i, j], g[i + 2, j], g[i + 2, j + 2], g[i, j + 2], g[i + 1, j], g[i + 2, j + 1],
                 g[i + 1, j + 2], g[i, j + 1]] for i in range(0, I, 2) for j in range(0, J, 2)]

    # skin elements, thickened under the flanges
    p = W / n if n else W
    yk = [(k + 0.5) * p for k in range(n)]
    jk = [int(np.argmin(np.abs(ys - y))) for y in yk]
    ymid = 0.5 * (ys[0:-1:2] + ys[2::2])                               # element centres across
    t_strip = np.full(len(ymid), t)
    if bf:
        for y in yk:
            t_strip[np.abs(ymid - y) < bf / 2] = t + ts
    nel = 0
    groups = [(t, "SKIN")] + ([(t + ts, "FLANGE")] if bf else [])
    for thick, name in groups:
        conns = [[skin[i, 2 * c], skin[i + 2, 2 * c], skin[i + 2, 2 * c + 2], skin[i, 2 * c + 2],
                  skin[i + 1, 2 * c], skin[i + 2, 2 * c + 1], skin[i + 1, 2 * c + 2], skin[i, 2 * c + 1]]
                 for i in range(0, Ni, 2) for c in range(len(ymid)) if t_strip[c] == thick]
        deck.add_elements("S8R", name, conns)
        deck.sections.append(f"*SHELL SECTION, ELSET={name}, MATERIAL=MAT\n{thick:.10g}")
        nel += len(conns)

    # webs: a grid in the plane y = y_k from z = 0 (shared skin nodes) to z_top
    z_top = (t / 2 + h + (ts if bf else 0.0)) if n else 0.0
    webs = []
    if n:
        zs = np.linspace(0.0, z_top, 2 * _divisions(z_top, size) + 1)
        Nk = len(zs) - 1
        for y, j in zip(yk, jk):
            g = np.zeros((Ni + 1, Nk + 1), dtype=int)
            for i, x in enumerate(xs):
                for k, z in enumerate(zs):
                    if k == 0:
                        g[i, k] = skin[i, j]
                    elif not (i % 2 and k % 2):
                        g[i, k] = deck.add_nodes([(x, y, z)])[0]
            webs.append(g)
        conns = [q for g in webs for q in quads(g, Ni, Nk)]
        deck.add_elements("S8R", "WEB", conns)
        deck.sections.append(f"*SHELL SECTION, ELSET=WEB, MATERIAL=MAT\n{ts:.10g}")
        nel += len(conns)

    # supports
    edge = sorted({int(v) for v in np.concatenate([skin[0, :], skin[-1, :], skin[:, 0], skin[:, -1]]) if v})
    deck.nsets["EDGES"] = edge
    deck.boundary += [("EDGES", 3, 3), (int(skin[0, 0]), 1, 1), (int(skin[0, 0]), 2, 2), (int(skin[-1, 0]), 2, 2)]
    if webs:
        eqs = ["*EQUATION"]
        for g in webs:
            for i in (0, Ni):
                for k in range(1, g.shape[1]):
                    if g[i, k]:
                        eqs.append(f"2\n{g[i, k]}, 2, 1.0, {g[i, 0]}, 2, -1.0")
        deck.model_extra.append("\n".join(eqs))

    # loads: N_x at uniform strain over skin + webs, N_xy on the skin edges
    acc: dict = {}

    def add(nodes, dof, forces):
        for nd, f in zip(nodes, forces):
            if nd:
                acc[(int(nd), dof)] = acc.get((int(nd), dof), 0.0) + float(f)

    area = float(np.sum(t_strip * np.diff(yb))) + (n * ts * z_top if n else 0.0)
    eps = nx * W / (E * area)
    if nx != 0.0:
        f_skin = quadratic_edge_forces(ys, E * t_strip * eps)
        add(skin[-1, :], 1, f_skin)
        add(skin[0, :], 1, -f_skin)
        for g in webs:
            f_web = quadratic_edge_forces(zs, E * ts * eps)
            add(g[-1, :], 1, f_web)
            add(g[0, :], 1, -f_web)
    if nxy != 0.0:
        fy = quadratic_edge_forces(ys, nxy)
        add(skin[-1, :], 2, fy)
        add(skin[0, :], 2, -fy)
        fx = quadratic_edge_forces(xs, nxy)
        add(skin[:, -1], 1, fx)
        add(skin[:, 0], 1, -fx)
    cloads = [(nd, d, v) for (nd, d), v in sorted(acc.items())]

    # mode-shape output: the skin (incl. junction lines)
    deck.nsets["SKINOUT"] = sorted(int(v) for v in skin.ravel() if v)
    junction = sorted(int(skin[i, j]) for j in jk for i in range(Ni + 1))
    text = deck.text([buckle_step(n_modes, cloads, ["SKINOUT"])])
    return {"text": text, "num_elements": nel, "num_nodes": len(deck.nodes), "junction_nodes": junction,
            "n_modes": n_modes, "nx": nx, "nxy": nxy, "axial_strain": eps, "E": E}


def _mode_uz(dat_text, mode, nset="SKINOUT") -> dict:
    """u_z of each node of ``nset`` in buckling mode ``mode`` (1-based)."""
    return {n: u[2] for n, u in mode_displacements(dat_text, mode, nset).items()}


def panel_buckling_factor(length, width, skin_thickness, E, nu, *, n_stiffeners=0, stiffener_height=None,
                          stiffener_thickness=None, flange_width=None, nx=0.0, nxy=0.0, mesh_size=None,
                          n_modes=6, workdir=None) -> dict:
    """Lowest positive CalculiX buckling factor of the stiffened panel under (nx, nxy) (N/m).

    ``length`` a (m, along the stiffeners), ``width`` W (m, = n_stiffeners x pitch),
    ``skin_thickness`` t (m), ``E`` (Pa), ``nu``; ``n_stiffeners`` blade webs of
    ``stiffener_height`` h (m, above the skin face) and ``stiffener_thickness`` t_s (m), T
    stiffeners with ``flange_width`` b_f (m, flange thickness t_s); ``nx`` < 0 compression,
    ``nxy`` shear flow; ``mesh_size`` (m, default min(a, pitch) / 8); ``n_modes`` factors
    extracted; ``workdir``: keep the deck and results there (``panel.inp``, ``panel.dat``).

    Returns ``{"fe_buckling_factor", "buckling_factors" (all extracted, mode order), "n_modes",
    "num_elements", "num_nodes", "nx_critical", "nxy_critical", "axial_strain" (pre-buckling strain at the
    applied nx), "axial_stress_critical" (Pa, E x strain at buckling: the skin and web stress),
    "mode" ("local" / "global" /
    "plate"), "junction_ratio" (max |u_z| on the stiffener lines / max |u_z| of the skin in the
    first mode), "time", "deck_path" (None without workdir)}``. ValueError (argument, value,
    allowed range) before anything is written; CalculixNotFound without ``ccx``.

    Parameters
    ----------
    length : float
        Panel length along the stiffeners (m).
    width : float
        Panel width (m).
    skin_thickness : float
        Skin thickness (m).
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio (-).
    n_stiffeners : int, optional
        Number of stiffeners.
    stiffener_height : float or None, optional
        Web height above the skin face (m).
    stiffener_thickness : float or None, optional
        Stiffener thickness (m).
    flange_width : float or None, optional
        Tee flange width (m); None for blades.
    nx : float, optional
        Running load along the stiffeners (N/m, compression negative).
    nxy : float, optional
        Shear flow (N/m).
    mesh_size : float or None, optional
        Element size (m).
    n_modes : int, optional
        Buckling factors extracted.
    workdir : str, path-like or None, optional
        Folder to keep the deck and results in.

    Returns
    -------
    dict
        ``fe_buckling_factor``, ``buckling_factors`` and the model size.
    """
    model = build_panel(length, width, skin_thickness, E, nu, n_stiffeners=n_stiffeners,
                        stiffener_height=stiffener_height, stiffener_thickness=stiffener_thickness,
                        flange_width=flange_width, nx=nx, nxy=nxy, mesh_size=mesh_size, n_modes=n_modes)
    if workdir is not None:
        workdir = os.fspath(workdir)
    run = run_deck(model["text"], job="panel", keep_dir=workdir)
    factors = parse_dat(run["dat"])["buckling_factors"]
    positive = [(k, f) for k, f in enumerate(factors) if f > 0]
    if not positive:
        raise RuntimeError(f"no positive buckling factor among the {len(factors)} extracted "
                           f"({factors.tolist()}); increase n_modes")
    k0, lam = min(positive, key=lambda kf: kf[1])
    uz = _mode_uz(run["dat"], k0 + 1)
    ratio = None
    mode = "plate"
    if model["junction_nodes"] and uz:
        skin_max = max(abs(v) for v in uz.values())
        ratio = max(abs(uz.get(nd, 0.0)) for nd in model["junction_nodes"]) / skin_max
        mode = "global" if ratio > GLOBAL_MODE_RATIO else "local"
    return {"fe_buckling_factor": float(lam), "buckling_factors": factors.tolist(), "n_modes": model["n_modes"],
            "num_elements": model["num_elements"], "num_nodes": model["num_nodes"],
            "nx_critical": float(lam) * model["nx"], "nxy_critical": float(lam) * model["nxy"],
            "axial_strain": model["axial_strain"], "axial_stress_critical": float(lam) * model["E"] * model["axial_strain"],
            "mode": mode, "junction_ratio": ratio, "time": run["time"],
            "deck_path": os.path.join(workdir, "panel.inp") if workdir is not None else None}
