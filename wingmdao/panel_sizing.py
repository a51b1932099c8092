"""Two-level sizing of a stiffened wingbox (``--panel-sizing two-level``; docs/panels.md,
"Two-level sizing").

* **Outer level**: the strength-only sizing's problem (the four walls per design station, the
  skins as equivalent thicknesses: skin plus stiffener area per width) with one more KS family
  per load case, ``equivalent_panels`` (:class:`~wingmdao.components.panels.EquivalentPanelFailure`:
  Farrar's minimum-weight stiffened panel on each skin's running loads, the detailed model's
  spar-web buckling), SLSQP after the fully stressed presize.
* **Inner level**: each design station's skin panels (skin thickness, stiffener height and
  thickness) sized locally for the envelope of that station's running loads over every time
  step of every load case, with the detailed checks of :func:`wingmdao.panels.box_panels.skin_panel_ratios`
  (skin, panel, stiffener column and crippling at the layout's safety factor), von Mises of the
  panel at yield and the sizing rules (5 <= h/ts <= 30, ts <= 15 t, the bounds): a small SLSQP
  per station and skin, minimum equivalent thickness, at fixed running loads (no time march).
  The adjacency rules (|dt| <= 2.5 mm, |dh| <= 10 mm) are then met by raising the thinner
  neighbour.
* **Check**: the recovered design in the full stiffened model (section ``"stiffened"``, the
  dynamic load cases, every panel family), one analysis; polish passes repeat the inner level
  (skins and, by bisection, the spar webs) with that model's running loads and analyse again,
  until every margin of safety is non-negative (a fixed point: the running loads move with the
  design, so the polish passes size to the allowable less a small reserve, ``POLISH_RESERVE``).
"""

from __future__ import annotations

import copy
import dataclasses
import time

import casadi as ca
import numpy as np
from scipy.optimize import minimize

from wingmdao.components.load_gradient import force_gradient
from wingmdao.panels.box_panels import SKIN_MODES, skin_panel_ratios, web_panel_ratio
from wingmdao.panels.layout import STIFFENER_VARS, smeared_stringer
from wingmdao.section.box import WALL_NAMES
from wingmdao.cases import pegasus as _pegasus
from wingmdao.components.flutter import paused_flutter
from wingmdao.sizing import build_problem, run_sizing, span_coordinate, station_values
from wingmdao.stress.box_stress import SECTION_PROPERTIES, panel_running_loads

#: how the stiffened walls are sized: all variables in one optimization, or the two levels
PANEL_SIZINGS = _pegasus.PANEL_SIZINGS
#: the sizing rules of the inner level (SizingRules): web aspect, stiffener over skin, adjacency (m)
ASPECT_RANGE = (5.0, 30.0)
STIFFENER_OVER_SKIN = 15.0
ADJACENT_THICKNESS = 2.5e-3
ADJACENT_HEIGHT = 10e-3


def running_load_states(prob, setup, stiffened: bool) -> dict:
    """The skins' running loads at every time step of every load case of a run sizing problem:
    ``{"upper": (nx, nxy, ny, node), "lower": ...}``, each a flat array over the cases, time
    steps, nodes and the skin's front and rear points (N/m, compression negative; ``node`` the
    beam node of each state). The walls' running loads of
    :func:`wingmdao.stress.box_stress.panel_running_loads` with the problem's section properties;
    the skins' area per width is the wall (equivalent thickness, outer level) or the skin plus
    its smeared stiffeners (``stiffened``).

    Parameters
    ----------
    prob : openmdao.api.Problem
        A run sizing problem (section ``"box"`` or ``"stiffened"``).
    setup : wingmdao.cases.CaseSetup
        Its case (geometry, load cases, panels).
    stiffened : bool
        Whether the problem's section is the stiffened one.

    Returns
    -------
    dict
        Per skin (``upper``, ``lower``) and spar web (``front``, ``rear``; ny zero), the tuple
        (nx, nxy, ny, node) of flat arrays.
    """
    geo = setup.geometry
    n = geo.num_nodes
    walls = [np.asarray(station_values(prob, w)).ravel() for w in WALL_NAMES]
    axial = [walls[0], walls[1]]
    if stiffened:
        p = setup.panels
        for k, s in enumerate(("upper", "lower")):
            h, ts = (np.asarray(station_values(prob, f"{q}_{s}_stiffener")).ravel() for q in ("h", "t"))
            axial[k] = walls[k] + smeared_stringer(h, ts, p.stiffener_pitch, p.shape, p.flange_ratio)[0]
    sec = {k: np.asarray(prob.get_val(k)).ravel() for k in SECTION_PROPERTIES}
    out = {s: [[], [], [], []] for s in ("upper", "lower", "front", "rear")}
    for case in setup.load_cases:
        f = np.asarray(prob.get_val(f"cases.{case.name}.{case.loads_path}.F_csn"))
        m = np.asarray(prob.get_val(f"cases.{case.name}.{case.loads_path}.M_csn"))
        df = force_gradient(f, geo.node_positions)
        loads = panel_running_loads([f[..., i] for i in range(3)], [m[..., i] for i in range(3)], geo.width,
                                    geo.height, *walls, tuple(axial), sec,
                                    force_gradient=[df[..., i] for i in range(3)])
        node = np.broadcast_to(np.arange(n), f.shape[:-1])
        for k in range(4):
            s = out["upper" if k < 2 else "lower"]
            for j, key in enumerate(("nx_skin", "nxy_skin", "ny_skin")):
                s[j].append(np.broadcast_to(loads[key][k], f.shape[:-1]).ravel())
            s[3].append(node.ravel())
        for k, web in enumerate(("front", "rear")):
            for j, key in enumerate(("nx_web", "nxy_web")):
                out[web][j].append(np.broadcast_to(loads[key][k], f.shape[:-1]).ravel())
            out[web][2].append(np.zeros(node.size))
            out[web][3].append(node.ravel())
    return {s: tuple(np.concatenate(v) for v in lists) for s, lists in out.items()}


def envelope_states(nx, nxy, ny) -> np.ndarray:
    """Indices of the load states no other state exceeds in every load a panel check grows with:
    the non-dominated states of (max(-N_x, 0), |N_xy|, max(-N_y, 0)) (the buckling modes) and of
    (|N_x|, |N_xy|) (von Mises). Every ratio of the panel checks is non-decreasing in these, so the
    envelope's largest ratio is the largest of all the states'.

    Parameters
    ----------
    nx, nxy, ny : numpy.ndarray
        Running loads of the states (N/m, compression negative).

    Returns
    -------
    numpy.ndarray
        Indices of the envelope's states.
    """
    keep = np.zeros(len(nx), dtype=bool)
    for cols in ((np.maximum(-nx, 0.0), np.abs(nxy), np.maximum(-ny, 0.0)), (np.abs(nx), np.abs(nxy))):
        y = np.column_stack(cols)
        # states strictly below one of a few large ones (the largest in each load and in their
        # scaled sum) are covered: dropped before the pairwise test
        scaled = y / np.maximum(y.max(axis=0), 1e-30)
        probe = y[np.unique(np.concatenate([np.argsort(-scaled[:, c])[:8] for c in range(y.shape[1])]
                                           + [np.argsort(-scaled.sum(axis=1))[:16]]))]
        below = np.any(np.all(probe[None, :, :] > y[:, None, :], axis=2), axis=1)
        x = np.flatnonzero(~below)
        x = x[np.unique(y[x], axis=0, return_index=True)[1]]   # one of equal states
        y = y[x]
        covered = np.zeros(len(x), dtype=bool)
        for lo in range(0, len(x), 256):   # pairwise in blocks: j covers i when y_j >= y_i, y_j != y_i
            blk = y[lo:lo + 256]
            ge = np.all(y[None, :, :] >= blk[:, None, :], axis=2)
            gt = np.any(y[None, :, :] > blk[:, None, :], axis=2)
            covered[lo:lo + 256] = np.any(ge & gt, axis=1)
        keep[x[~covered]] = True
    return np.flatnonzero(keep)


class LocalPanelSizer:
    """Minimum-weight skin panel (skin thickness t, stiffener height h and thickness ts) of a
    stiffened skin for given load states, with the detailed panel checks: ``safety_factor`` times
    every mode of :data:`~wingmdao.panels.box_panels.SKIN_MODES` <= ``limit``, von Mises of the panel
    (sigma = N_x / t_eq, tau = N_xy / t) <= ``limit`` sigma_y, the web aspect and stiffener-over-skin rules
    and the bounds. CasADi functions of the checks give SLSQP exact gradients.

    Parameters
    ----------
    material : wingmdao.materials.Material
        Metal of skin and stiffeners.
    layout : wingmdao.panels.layout.PanelLayout
        Stiffener pitch, shape, flange ratio and safety factor.
    bounds : dict
        ``{"t": (lo, up), "h": (lo, up), "ts": (lo, up)}`` (m).
    limit : float, optional
        The largest ratio allowed (-; 1 - the polish passes' reserve).
    """

    def __init__(self, material, layout, bounds, limit=1.0):
        self.material, self.layout, self.bounds, self.limit = material, layout, bounds, float(limit)
        x = ca.SX.sym("x", 3)
        s = ca.SX.sym("s", 4)   # nx, nxy, ny, panel length
        t, h, ts = x[0] * 1e-3, x[1] * 1e-3, x[2] * 1e-3   # the variables in mm
        p = layout
        r = skin_panel_ratios(material, t, h, ts, p.stiffener_pitch, s[3], s[0], s[1], p.shape, p.flange_ratio,
                              ny=s[2])
        teq = t + smeared_stringer(h, ts, p.stiffener_pitch, p.shape, p.flange_ratio)[0]
        sig, tau = s[0] / teq, s[1] / t
        vm = ca.sqrt(sig * sig + 3.0 * tau * tau + 1.0) / material.sigma_y
        g = ca.vertcat(*(p.safety_factor * r[m] for m in SKIN_MODES), vm)
        self._g = ca.Function("g", [x, s], [g, ca.jacobian(g, x)])
        self._f = ca.Function("f", [x], [teq * 1e3, ca.jacobian(teq * 1e3, x)])

    def ratios(self, x_m, states) -> np.ndarray:
        """The factored ratios (modes of SKIN_MODES, then von Mises) of a panel at each state.

        Parameters
        ----------
        x_m : sequence of 3
            t, h, ts (m).
        states : numpy.ndarray
            (k, 4) nx, nxy, ny (N/m), panel length (m).

        Returns
        -------
        numpy.ndarray
            (k, 5) ratios (-; 1 = the allowable).
        """
        x = np.asarray(x_m, dtype=float) * 1e3
        return np.array([np.asarray(self._g(x, st)[0]).ravel() for st in states])

    def size(self, states, starts, fallback=()) -> tuple:
        """The lightest feasible panel from the given starts (then from ``fallback`` if none is
        feasible); returns ``((t, h, ts) in m, t_eq in m)``.

        Parameters
        ----------
        states : numpy.ndarray
            (k, 4) load states: nx, nxy, ny (N/m), panel length (m).
        starts : sequence of sequence of 3
            Starting (t, h, ts) (m).
        fallback : sequence of sequence of 3, optional
            Further starts (m), tried when none of ``starts`` ends feasible.

        Returns
        -------
        tuple
            The panel (m) and its equivalent thickness (m).
        """
        k = len(states)
        gmap = self._g.map(k)
        st = np.asarray(states, dtype=float).T

        memo = {}

        def evaluate(x):   # values and Jacobian in one call, kept for the same x
            key = x.tobytes()
            if key not in memo:
                memo.clear()
                g, jac = gmap(np.repeat(x[:, None], k, axis=1), st)
                jac = np.asarray(jac).reshape(-1, k, 3).transpose(1, 0, 2).reshape(-1, 3)   # (5, 3k) -> (5k, 3)
                memo[key] = (self.limit - np.asarray(g).T.ravel(), -jac)
            return memo[key]

        def cons(x):
            return evaluate(x)[0]

        def cons_jac(x):
            return evaluate(x)[1]

        lo, hi = ASPECT_RANGE
        rules = [{"type": "ineq", "fun": lambda x: np.array([x[1] - lo * x[2], hi * x[2] - x[1],
                                                             STIFFENER_OVER_SKIN * x[0] - x[2]]),
                  "jac": lambda x: np.array([[0.0, 1.0, -lo], [0.0, -1.0, hi], [STIFFENER_OVER_SKIN, 0.0, -1.0]])}]
        b = self.bounds
        bnds = [tuple(1e3 * v for v in b[key]) for key in ("t", "h", "ts")]
        best = None
        for x0 in [*starts, None, *fallback]:
            if x0 is None:
                if best is not None:
                    break
                continue
            x0 = np.clip(np.asarray(x0, dtype=float) * 1e3, [v[0] for v in bnds], [v[1] for v in bnds])
            res = minimize(lambda x: float(self._f(x)[0]), x0, jac=lambda x: np.asarray(self._f(x)[1]).ravel(),
                           bounds=bnds, constraints=[{"type": "ineq", "fun": cons, "jac": cons_jac}] + rules,
                           method="SLSQP", options={"maxiter": 200, "ftol": 1e-9})
            feasible = min(cons(res.x).min(), rules[0]["fun"](res.x).min()) > -1e-6
            if feasible and (best is None or res.fun < best.fun):
                best = res
        if best is None:   # no start converged to a feasible panel: the upper bounds (the heaviest panel)
            x = np.array([v[1] for v in bnds])
            return tuple(x * 1e-3), float(self._f(x)[0]) * 1e-3
        return tuple(best.x * 1e-3), float(best.fun) * 1e-3


def inner_sizing(setup, states: dict, start: dict | None = None, reserve: float = 0.0) -> dict:
    """The inner level: each design station's skin panels for the envelope of its states
    (:func:`running_load_states`), then the adjacency rules by raising the thinner neighbour.

    Parameters
    ----------
    setup : wingmdao.cases.CaseSetup
        The stiffened case (geometry, material, panels, bounds in ``options``).
    states : dict
        Per skin the (nx, nxy, ny, node) arrays of :func:`running_load_states`.
    start : dict or None, optional
        ``{var: (n_dv,)}`` a previous design (m), tried first at each station.
    reserve : float, optional
        Every ratio is held at most ``1 - reserve`` (-).

    Returns
    -------
    dict
        ``{t_upper_skin, t_lower_skin, h_/t_<skin>_stiffener: (n_dv,)}`` (m) and ``equivalent``:
        ``{skin: (n_dv,)}`` equivalent thicknesses (m), ``states``: the envelope's state count.
    """
    geo, o, p = setup.geometry, setup.options, setup.panels
    n = geo.num_nodes
    smap = np.arange(n) if geo.station_map is None else np.asarray(geo.station_map)
    n_dv = int(smap.max()) + 1
    length = p.panel_lengths(span_coordinate(geo))
    design, equivalent, count = {}, {}, 0
    for skin in ("upper", "lower"):
        t_name, h_name, ts_name = f"t_{skin}_skin", f"h_{skin}_stiffener", f"t_{skin}_stiffener"
        sizer = LocalPanelSizer(setup.material, p, {"t": (o.lower[t_name], o.upper[t_name]),
                                                    "h": (o.lower[h_name], o.upper[h_name]),
                                                    "ts": (o.lower[ts_name], o.upper[ts_name])},
                                limit=1.0 - reserve)
        nx, nxy, ny, node = states[skin]
        x = np.zeros((n_dv, 3))
        teq = np.zeros(n_dv)
        for j in range(n_dv):
            sel = np.flatnonzero(smap[node] == j)
            keep = sel[envelope_states(nx[sel], nxy[sel], ny[sel])]
            count += keep.size
            st = np.column_stack([nx[keep], nxy[keep], ny[keep], length[node[keep]]])
            generic = [(3e-3, 0.04, 0.003), (6e-3, 0.07, 0.006), (15e-3, 0.08, 0.008)]
            if start is not None:   # a polish pass: from the previous design, the generic starts if it fails
                starts, fallback = [tuple(start[v][j] for v in (t_name, h_name, ts_name))], generic
            else:
                starts, fallback = generic + ([tuple(x[j - 1])] if j > 0 else []), ()
            xj, teq[j] = sizer.size(st, starts, fallback)
            x[j] = xj
        x = adjacency(x)
        design[t_name], design[h_name], design[ts_name] = x[:, 0], x[:, 1], x[:, 2]
        equivalent[skin] = x[:, 0] + smeared_stringer(x[:, 1], x[:, 2], p.stiffener_pitch, p.shape,
                                                      p.flange_ratio)[0]
    design["equivalent"] = equivalent
    design["states"] = int(count)
    return design


def web_sizing(setup, states: dict, walls: dict, reserve: float = 0.0) -> dict:
    """Spar webs resized locally: per design station the thinnest web (bisection, 40 halvings)
    whose factored compression-shear buckling (:func:`wingmdao.panels.box_panels.web_panel_ratio`)
    and von Mises ratio are at most 1 at every state, the web's axial stress and shear flow
    held (N_x scales with the thickness, N_xy does not), within the bounds and the adjacency
    rule.

    Parameters
    ----------
    setup : wingmdao.cases.CaseSetup
        The stiffened case.
    states : dict
        :func:`running_load_states` of the design ``walls``.
    walls : dict
        ``{wall: (n_dv,)}`` the design's four wall thicknesses (m).
    reserve : float, optional
        Every ratio is held at most ``1 - reserve`` (-).

    Returns
    -------
    dict
        ``{t_front_spar, t_rear_spar: (n_dv,)}`` (m).
    """
    geo, o, p, mat = setup.geometry, setup.options, setup.panels, setup.material
    n = geo.num_nodes
    smap = np.arange(n) if geo.station_map is None else np.asarray(geo.station_map)
    length = p.panel_lengths(span_coordinate(geo))
    out = {}
    for web in ("front", "rear"):
        name = f"t_{web}_spar"
        nx, nxy, _, node = states[web]
        t0 = walls[name][smap[node]]
        h_web = geo.height[node] - walls["t_upper_skin"][smap[node]] - walls["t_lower_skin"][smap[node]]

        def ratio(t):   # t per state (m)
            r = p.safety_factor * web_panel_ratio(mat, t, h_web, length[node], nx * t / t0, nxy)
            vm = np.sqrt((nx / t0) ** 2 + 3.0 * (nxy / t) ** 2) / mat.sigma_y
            return np.maximum(r, vm)

        lo = np.full(len(walls[name]), o.lower[name])
        hi = np.full(len(walls[name]), o.upper[name])
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            worst = np.zeros(len(mid))
            np.maximum.at(worst, smap[node], ratio(mid[smap[node]]))
            hi = np.where(worst <= 1.0 - reserve, mid, hi)
            lo = np.where(worst <= 1.0 - reserve, lo, mid)
        out[name] = adjacency(np.column_stack([hi, np.zeros_like(hi), np.zeros_like(hi)]))[:, 0]
    return out


def adjacency(x: np.ndarray) -> np.ndarray:
    """Panels (n_dv, 3) of t, h, ts (m) raised until neighbouring stations differ by at most
    :data:`ADJACENT_THICKNESS` in t and ts and :data:`ADJACENT_HEIGHT` in h (the thinner one
    raised, so no check gets worse except a blade's crippling through h/ts), ts then raised to
    keep h/ts <= 30.

    Parameters
    ----------
    x : numpy.ndarray
        (n_dv, 3) panels (m).

    Returns
    -------
    numpy.ndarray
        (n_dv, 3) panels meeting the rules (m).
    """
    x = np.array(x, dtype=float)
    step = np.array([ADJACENT_THICKNESS, ADJACENT_HEIGHT, ADJACENT_THICKNESS])
    for _ in range(2 * len(x)):
        before = x.copy()
        for j in range(len(x)):
            for k in (j - 1, j + 1):
                if 0 <= k < len(x):
                    x[j] = np.maximum(x[j], x[k] - step)
        x[:, 2] = np.maximum(x[:, 2], x[:, 1] / ASPECT_RANGE[1])
        if np.array_equal(x, before):
            break
    return x


#: exponent e of the fully stressed resize t <- t r^(1/e) of the equivalent-panel ratio r:
#: skins 1 (Farrar at a fixed stress: R ~ 1/t), webs 2 (shear buckling at a fixed shear flow: R ~ 1/t^3,
#: compression at a fixed stress: R ~ 1/t^2)
EQUIVALENT_EXPONENTS = {"t_upper_skin": 1.0, "t_lower_skin": 1.0, "t_front_spar": 2.0, "t_rear_spar": 2.0}
#: the points of g_equivalent_panels of each wall
EQUIVALENT_POINTS = {"t_upper_skin": (0, 1), "t_lower_skin": (2, 3), "t_front_spar": (4,), "t_rear_spar": (5,)}


def presize_equivalent(prob, setup, passes: int) -> dict:
    """Fully stressed passes of the outer level: per design station and wall,
    t <- clip(t max(r_vm, r_eq^(1/e)), bounds), r_vm the station's largest von Mises ratio
    (as :func:`wingmdao.sizing.presize_fully_stressed`), r_eq the wall's largest factored
    equivalent-panel ratio (g + 1 of ``g_equivalent_panels``) over the cases and time steps,
    e of :data:`EQUIVALENT_EXPONENTS`. Gives SLSQP a start near the buckling-aware optimum.

    Parameters
    ----------
    prob : openmdao.api.Problem
        The outer level's set-up problem; its walls are updated.
    setup : wingmdao.cases.CaseSetup
        The outer case (geometry, load cases, bounds).
    passes : int
        Number of passes.

    Returns
    -------
    dict
        ``passes`` and ``history`` (mass before each resize, kg; largest ratio).
    """
    geo, o = setup.geometry, setup.options
    smap = np.arange(geo.num_nodes) if geo.station_map is None else np.asarray(geo.station_map)
    n_dv = int(smap.max()) + 1
    history = []
    for _ in range(int(passes)):
        with paused_flutter(prob):
            prob.run_model()
        r_vm = np.zeros(n_dv)
        r_eq = {w: np.zeros(n_dv) for w in WALL_NAMES}
        for case in setup.load_cases:
            if "vm" in case.families:
                g = np.asarray(prob.get_val(f"cases.{case.name}.stress.g_vm"))
                np.maximum.at(r_vm, smap, (g + 1.0).reshape(-1, g.shape[-2], g.shape[-1]).max(axis=(0, 2)))
            g = np.asarray(prob.get_val(f"cases.{case.name}.equivalent_panels.g_equivalent_panels")) + 1.0
            g = g.reshape(-1, g.shape[-2], g.shape[-1])
            for w, pts in EQUIVALENT_POINTS.items():
                np.maximum.at(r_eq[w], smap, g[..., list(pts)].max(axis=(0, 2)))
        for w in WALL_NAMES:
            scale = np.sqrt(np.maximum(r_vm, np.maximum(r_eq[w], 1e-3) ** (1.0 / EQUIVALENT_EXPONENTS[w])))
            prob.set_val(w, np.clip(prob.get_val(w) * scale, o.lower[w], o.upper[w]))
        history.append({"mass_kg": float(prob.get_val("mass", units="kg")[0]),
                        "max_ratio": float(max(r_vm.max(), *(r.max() for r in r_eq.values())))})
    return {"passes": int(passes), "history": history}


def outer_setup(setup):
    """The outer level's case: ``setup`` with section ``"box"`` (the walls' equivalent
    thicknesses, the 4 wall variables per design station) and no panel layout.

    Parameters
    ----------
    setup : wingmdao.cases.CaseSetup
        The stiffened case.

    Returns
    -------
    wingmdao.cases.CaseSetup
        A copy for the outer level.
    """
    outer = copy.copy(setup)
    o = setup.options
    outer.options = dataclasses.replace(o, lower={w: o.lower[w] for w in WALL_NAMES},
                                        upper={w: o.upper[w] for w in WALL_NAMES},
                                        initial={w: v for w, v in o.initial.items() if w in WALL_NAMES})
    outer.section, outer.panels = "box", None
    return outer


#: the outer level's solvers: fully stressed passes only, or SLSQP after them
OUTER_SOLVERS = ("fsd", "slsqp")


#: The polish passes size every ratio to 1 - POLISH_RESERVE: the running loads of the next check
#: move with the design, and the reserve lets the fixed point end with non-negative margins.
POLISH_RESERVE = 2e-3


def size_two_level(setup, *, outer_solver: str = "fsd", fsd_passes: int = 12, polish: int = 8,
                   margin_tol: float = 0.0, progress=None) -> tuple:
    """Size a stiffened case in two levels (module docstring); returns ``(problem, result)``:
    the full stiffened model at the recovered design and its summary
    (:func:`wingmdao.sizing.summarize`: mass, panels with their margins, ribs, mass breakdown),
    with ``two_level``: the outer sizing's mass, iterations, evaluations and success, the inner
    level's envelope states, the masses after each pass, and the CPU time of each level.

    Parameters
    ----------
    setup : wingmdao.cases.CaseSetup
        A stiffened case (section ``"stiffened"``, metallic walls).
    outer_solver : {"fsd", "slsqp"}, optional
        The outer level: ``fsd_passes`` fully stressed passes (:func:`presize_equivalent`), or
        the case's presize passes then SLSQP on the 4 walls per station.
    fsd_passes : int, optional
        Fully stressed passes of ``outer_solver="fsd"``.
    polish : int, optional
        At most this many inner passes with the full model's running loads after the first
        check (0: none); they stop once the smallest margin of safety is at least ``-margin_tol``.
    margin_tol : float, optional
        The polish passes stop once the smallest margin of safety is at least ``-margin_tol`` (-;
        0: every margin non-negative). The polish passes size every ratio to ``1 - POLISH_RESERVE``.
    progress : callable or None, optional
        Called with a line of text after each step.

    Returns
    -------
    tuple
        The full problem and the result dict.
    """
    if setup.section != "stiffened" or setup.panels is None:
        raise ValueError(f"--panel-sizing two-level needs --panels stiffened (section {setup.section!r})")
    if setup.panels.laminate:
        raise ValueError("--panel-sizing two-level: metallic walls only (Farrar's efficiency of a metal panel)")
    if outer_solver not in OUTER_SOLVERS:
        raise ValueError(f"outer_solver = {outer_solver!r}; allowed: {', '.join(OUTER_SOLVERS)}")
    say = progress or (lambda line: None)
    cpu = {}
    w0 = time.perf_counter()
    c0 = time.process_time()
    outer = outer_setup(setup)
    slsqp = outer_solver == "slsqp"
    prob, desc = build_problem(outer.geometry, outer.load_cases, outer.material, outer.options, section="box",
                               flutter=outer.flutter, turbulence=outer.turbulence, equivalent_panels=setup.panels,
                               driver=slsqp)
    presize = presize_equivalent(prob, outer, outer.options.presize if slsqp else fsd_passes)
    res = run_sizing(prob, outer.load_cases, desc, optimize=slsqp, section="box", geometry=outer.geometry,
                     material=outer.material)
    res["presize"] = presize
    if not slsqp:
        res.update(iterations=int(fsd_passes), function_evaluations=int(fsd_passes) + 1, gradient_evaluations=0)
    cpu["outer"] = time.process_time() - c0
    say(f"outer level: {res['mass_kg']:.2f} kg (walls and stiffeners, no ribs), {res['iterations']} iterations, "
        f"success {res['success']}")
    c0 = time.process_time()
    design = inner_sizing(setup, running_load_states(prob, setup, stiffened=False))
    cpu["inner"] = time.process_time() - c0
    spars = {w: np.asarray(prob.get_val(w, units="m")).ravel() for w in ("t_front_spar", "t_rear_spar")}
    c0 = time.process_time()
    full, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False,
                            section="stiffened", flutter=setup.flutter, panels=setup.panels)
    passes, inner_before = [], cpu["inner"]
    for k in range(polish + 1):
        for w in (*WALL_NAMES, *STIFFENER_VARS):
            full.set_val(w, spars[w] if w in spars else design[w], units="m")
        result = run_sizing(full, setup.load_cases, f"two-level (outer {outer_solver}, inner per-station SLSQP)",
                            optimize=False, section="stiffened", panels=setup.panels, geometry=setup.geometry,
                            material=setup.material)
        worst = _worst_margin(result)
        passes.append({"mass_kg": result["mass_kg"], "envelope_states": design["states"], **worst})
        say(f"check {k}: {result['mass_kg']:.2f} kg, smallest margin {worst['margin_of_safety']:+.4f} "
            f"({worst['wall']} station {worst['station']}, {worst['mode']})")
        if k < polish and worst["margin_of_safety"] < -margin_tol:
            c1 = time.process_time()
            states = running_load_states(full, setup, stiffened=True)
            walls = {w: np.asarray(full.get_val(w, units="m")).ravel() for w in WALL_NAMES}
            design = inner_sizing(setup, states,
                                  start={v: design[v] for v in design if v not in ("equivalent", "states")},
                                  reserve=POLISH_RESERVE)
            spars = web_sizing(setup, states, walls, reserve=POLISH_RESERVE)
            cpu["inner"] += time.process_time() - c1
        else:
            break
    cpu["check"] = time.process_time() - c0 - (cpu["inner"] - inner_before)
    result["wall_s"] = time.perf_counter() - w0
    result["iterations"] = res["iterations"]
    result["function_evaluations"] = res.get("function_evaluations")
    result["gradient_evaluations"] = res.get("gradient_evaluations")
    result["success"] = bool(res["success"])
    result["two_level"] = {"outer": {k: res.get(k) for k in ("mass_kg", "iterations", "function_evaluations",
                                                             "gradient_evaluations", "success", "ks")},
                           "passes": passes, "cpu_s": cpu}
    return full, result


def _worst_margin(result) -> dict:
    """The smallest margin of safety of a stiffened summary's panels: wall, station, mode."""
    worst = {"margin_of_safety": np.inf, "wall": None, "station": None, "mode": None}
    for wall, d in result["panels"].items():
        for i, ms in enumerate(d["margin_of_safety"]):
            if ms is not None and ms < worst["margin_of_safety"]:
                worst = {"margin_of_safety": float(ms), "wall": wall, "station": i, "mode": d["critical_mode"][i]}
    return worst
