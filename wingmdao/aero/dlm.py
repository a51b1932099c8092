"""Doublet-lattice unsteady aerodynamics of a wing planform in the modal basis of the jig beam
(no OpenMDAO).

Lattice. The panels are those of :mod:`wingmdao.aero.vlm` (the mean surface through the jig beam
nodes, ``n_chordwise`` x ``n_spanwise`` panels per beam element), the left half its explicit
mirror image. Each panel carries a doublet line on its quarter chord; the normalwash is
enforced at its three-quarter-chord point of mid-span. The aerodynamic influence coefficients
(AIC) ``A = A_0 + A(k)``, ``w / V = A dcp``: the steady part ``A_0`` is PanelAero's vortex
lattice (DLR, BSD-3, the optional ``aero3d`` extra); the oscillatory increment ``A(k)`` the
doublet-lattice kernel of Albano & Rodden ("A doublet-lattice method for calculating lift
distributions on oscillating surfaces in subsonic flows", AIAA J. 7(2), 1969, 279-285) with
Rodden, Taylor & McIntosh's quartic approximation of the incremental kernel ("Further refinement
of the subsonic doublet-lattice method", J. Aircraft 35(5), 1998, 720-727), evaluated for all
reduced frequencies at once by :func:`wingmdao.aero.dlm_kernel.oscillatory_aic` (PanelAero's
``DLM.calc_Ajj`` formulas, equal to it to round-off: tests/test_dlm_kernel.py). The left half's
panels only send: a symmetric motion's pressure jumps on the right half are
``dcp = -(A_RR + A_RL)^-1 w``, the rows of the right half's receiving points (the mirror image's
equations are the same by symmetry); PanelAero's ``xz_symmetry`` option is not used.

Reduced frequency ``k = omega b_ref / V`` (``b_ref`` the reference semi-chord, m); PanelAero's
kernel takes ``omega / V = k / b_ref`` (1/m).

Transfer (rigid chordwise links). At a panel's mid-span the beam's hat functions interpolate each
mode's nodal displacement ``u`` and rotation ``phi`` (the same hat functions as the vortex
lattice's station transfer); a point ``p`` of the panel moves rigidly with that beam section:
``u + phi x (p - r)``, ``r`` the beam axis there (heave and pitch about the elastic axis, plus
the roll and in-plane terms a dihedral or sweep brings). Its normal component at the
control point is ``h_j``, the streamwise slope of the normal displacement gives the panel's
incidence ``alpha_j = -(phi x e_x) . n_j``, and the normalwash of a harmonic motion is
``w_j / V = alpha_j - i (k / b_ref) h_j`` (positive: a nose-up incidence). The panel's normal
force ``q A_j dcp_j`` acts on its doublet line (quarter chord); its virtual work on each mode's
normal displacement there gives the generalized force. So

    Q(ik) = T^T Q_jj(k) D(k),     D(k) = D_alpha - i (k / b_ref) D_h,

``T`` (panels, modes) the panel areas times the modes' normal displacement at the force points
(m^2 per unit modal amplitude). The modal equations of motion are
``M q'' + C q' + K q = (rho V^2 / 2) Q(ik) q``.

Gust. A vertical gust ``w_g e^(i omega (t - (x - x_0) / V))`` reaches panel j's control point
with the delay ``(x_j - x_0) / V``; its normalwash per unit ``w_g / V`` is
``n_z,j exp(-i (k / b_ref) (x_j - x_0))``, and ``Q_g(ik) = T^T Q_jj(k) w_g`` (modes, ) per unit
``w_g / V``.

Control surfaces (flap modes). A trailing-edge surface hinged at ``h`` x the local chord over the
beam nodes ``nodes`` is the set of panels of the elements between its first and last node whose
leading edge lies at or aft of the hinge (the hinge on a chordwise panel edge,
:func:`wingmdao.aero.vlm.chord_fractions`; the panels of :func:`wingmdao.aero.vlm.flap_influence`).
A deflection delta (trailing edge down positive) rotates them about the hinge line: incidence
``+delta`` and normal displacement ``-(x - x_h) delta`` (``x_h`` the hinge line's x at the panel's
mid-span), so the normalwash of a harmonic deflection is ``(1 - i (k / b_ref) (x_j - x_h)) delta``
on those panels, like a structural mode's. Its pressures give the generalized forces on the modes
(``flap``), the station loads (``flap_station_loads``); the hinge moment (N m per unit q,
trailing edge down positive) of every column (modes, flaps, gust) is the virtual work of the
panel forces on the flap's rotation, ``-sum A_j dcp_j (x_f,j - x_h)`` over its panels (force
point x_f at the quarter chord of the panel) (``hinge``).

Station loads. The same pressure jumps, summed outboard of each beam node, give the aerodynamic
part of the internal force and moment there (:func:`station_summation`, ``station_loads`` of
:class:`GeneralizedForces`); :mod:`wingmdao.aero.modal_loads` adds the inertia.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from wingmdao.aero.dlm_kernel import oscillatory_aic
from wingmdao.aero.vlm import Lattice, build_lattice, check_planform, chord_fractions

#: default lattice density of the doublet lattice: chordwise panels, spanwise strips per beam element
DLM_CHORDWISE = 4
DLM_SPANWISE = 2
#: chordwise panels of a lattice with control surfaces (flap modes): a 25 % chord flap gets 4 panels;
#: its lift and hinge moment converge as 1 / n_chordwise (tests/test_dlm_flaps.py: 16 panels, lift
#: 2.8 % and hinge moment 5.8 % off Glauert's on an aspect-ratio-40 wing, 32 panels half that)
DLM_FLAP_CHORDWISE = 16
#: default reduced frequencies (k = omega b_ref / V) of the tabulated generalized forces
REDUCED_FREQUENCIES = (0.0, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0, 1.5)
_CACHE: dict = {}
_CACHE_SIZE = 8
#: pressure operators of planforms (:func:`pressure_operators`), the most recent few
_OPERATORS: dict = {}
_OPERATORS_SIZE = 4
_MIRROR = np.array([1.0, -1.0, 1.0])

__all__ = ["DLM_CHORDWISE", "DLM_SPANWISE", "DLM_FLAP_CHORDWISE", "REDUCED_FREQUENCIES", "GeneralizedForces", "ModalTransfer",
           "check_reduced_frequencies", "check_dlm_mach", "check_panels", "aerogrid", "steady_aic", "panel_pressure",
           "pressure_operators", "modal_transfer", "flap_panels", "flap_transfer",
           "generalized_forces", "interpolate", "station_summation"]


def _panelaero_dlm():
    try:
        from panelaero import DLM, VLM
    except ImportError as exc:  # pragma: no cover - the extra is installed in the test environment
        raise ImportError("--aero-theory dlm needs PanelAero: pip install 'wingmdao[aero3d]'") from exc
    return DLM, VLM


def check_reduced_frequencies(k) -> np.ndarray:
    """Validated reduced frequencies: a non-empty, finite, strictly increasing set of k >= 0.

    Parameters
    ----------
    k : float or array_like
        Reduced frequencies ``omega b_ref / V``.

    Returns
    -------
    ndarray
        The frequencies as a 1-D float array.
    """
    k = np.atleast_1d(np.asarray(k, dtype=float))
    if k.ndim != 1 or k.size == 0:
        raise ValueError("reduced_frequencies must be a non-empty 1-D set of k = omega b_ref / V >= 0, got none")
    if not np.all(np.isfinite(k)) or np.any(k < 0.0):
        raise ValueError(f"reduced_frequencies must be finite and >= 0, got {k.tolist()}")
    if np.any(np.diff(k) <= 0.0):
        raise ValueError(f"reduced_frequencies must be strictly increasing (sorted, no repeats), got {k.tolist()}")
    return k


def check_dlm_mach(mach) -> float:
    """The Mach number of the (subsonic) doublet lattice; ValueError outside [0, 1).

    Parameters
    ----------
    mach : float
        Mach number.

    Returns
    -------
    float
        The Mach number.
    """
    m = float(mach)
    if not (np.isfinite(m) and 0.0 <= m < 1.0):
        raise ValueError(f"mach must be in [0, 1) (the subsonic doublet-lattice kernel), got {mach}")
    return m


def check_panels(lat: Lattice) -> None:
    """ValueError naming the first panel of zero (or negative) area.

    Parameters
    ----------
    lat : Lattice
        The lattice.
    """
    area = lat.panel_chord * lat.span
    bad = np.flatnonzero(~(np.isfinite(area) & (area > 0.0)))
    if bad.size:
        raise ValueError(f"panel {bad[0]} (strip {lat.strip[bad[0]]}) has zero area ({area[bad[0]]} m^2): "
                         "chords must be > 0 and the nodes' y must increase from root to tip")


def aerogrid(lat: Lattice) -> dict:
    """PanelAero's aerogrid of both halves: the right half's panels (ours) then their mirror
    images, each doublet line from its lower-y end ``P1`` to its upper-y end ``P3``.

    Parameters
    ----------
    lat : Lattice
        The lattice of the right half.

    Returns
    -------
    dict
        ``offset_j``, ``offset_l``, ``offset_P1``, ``offset_P3``, ``N`` (2m, 3), ``A``, ``l``
        (2m,) and ``n`` (2m), as PanelAero expects.
    """
    area = lat.panel_chord * lat.span
    mid = 0.5 * (lat.bound_a + lat.bound_b)
    return {"offset_j": np.vstack([lat.control, lat.control * _MIRROR]),
            "offset_l": np.vstack([mid, mid * _MIRROR]),
            "offset_P1": np.vstack([lat.bound_a, lat.bound_b * _MIRROR]),
            "offset_P3": np.vstack([lat.bound_b, lat.bound_a * _MIRROR]),
            "N": np.vstack([lat.normal, lat.normal * _MIRROR]),
            "A": np.concatenate([area, area]), "l": np.concatenate([lat.panel_chord, lat.panel_chord]),
            "n": 2 * lat.span.size}


def steady_aic(lat: Lattice) -> np.ndarray:
    """PanelAero's steady (vortex-lattice) AIC ``A`` (2m, 2m) of both halves: ``w / V = A dcp``.

    Parameters
    ----------
    lat : Lattice
        The lattice of the right half.

    Returns
    -------
    ndarray, shape (2m, 2m)
        The steady AIC.
    """
    _, VLM = _panelaero_dlm()
    A, _ = VLM.calc_Ajj(aerogrid=aerogrid(lat), Ma=lat.mach)
    return A


def _symmetric_aic(lat: Lattice, k_over_b, method: str, steady=None) -> np.ndarray:
    """(nk, m, m) complex: the AIC of the right half's panels under a symmetric pressure jump
    (the left half the mirror image), ``A_RR + A_RL`` of the whole wing's ``A = A_0 + A(k)``, at
    each ``omega / V`` of ``k_over_b`` (1/m). ``method="quartic"``: the oscillatory part from
    :func:`wingmdao.aero.dlm_kernel.oscillatory_aic` (all k in one call, right-half rows only);
    ``"parabolic"``: PanelAero's ``DLM.calc_Ajj`` per k."""
    kb = np.atleast_1d(np.asarray(k_over_b, dtype=float))
    m = lat.span.size
    grid = aerogrid(lat)
    A0 = steady_aic(lat) if steady is None else steady
    if method == "quartic":
        inc = oscillatory_aic(grid["offset_j"], grid["offset_P1"], grid["offset_P3"], grid["l"], lat.mach, kb,
                              rows=np.arange(m))
    else:
        DLM, _ = _panelaero_dlm()
        inc = np.zeros((kb.size, m, 2 * m), dtype=complex)
        for i, k in enumerate(kb):
            if k > 0.0:
                with np.errstate(all="ignore"):
                    inc[i] = DLM.calc_Ajj(aerogrid=aerogrid(lat), Ma=lat.mach, k=float(k), method=method)[:m]
    A = A0[None, :m, :] + inc
    return A[:, :, :m] + A[:, :, m:]


def panel_pressure(lat: Lattice, k_over_b, normalwash, *, method: str = "quartic", steady=None) -> np.ndarray:
    """Pressure jumps dcp (m, c) on the right half of a symmetric normalwash ``w / V`` (m, c)
    (the left half the mirror image) at ``omega / V = k_over_b`` (1/m); ``k_over_b = 0``: the
    steady vortex lattice. ``steady``: :func:`steady_aic` of ``lat`` if already computed.

    Parameters
    ----------
    lat : Lattice
        The lattice of the right half.
    k_over_b : float
        ``omega / V`` (1/m), >= 0.
    normalwash : array_like, shape (m, c)
        Symmetric normalwash ``w / V`` of the right-half panels.
    method : str
        Kernel approximation: ``"quartic"`` (:func:`wingmdao.aero.dlm_kernel.oscillatory_aic`) or
        ``"parabolic"`` (PanelAero's).
    steady : ndarray, shape (2m, 2m), optional
        :func:`steady_aic` of ``lat``.

    Returns
    -------
    ndarray of complex, shape (m, c)
        The pressure jumps dcp.
    """
    A = _symmetric_aic(lat, [float(k_over_b)], method, steady)[0]
    # a symmetric normalwash on both halves; Q = -A^-1, so dcp = -A^-1 w
    return -np.linalg.solve(A, np.asarray(normalwash, dtype=complex))


def pressure_operators(lat: Lattice, k_over_b, *, method: str = "quartic", key: str | None = None) -> np.ndarray:
    """(nk, m, m) complex: the pressure jumps of the right half per unit symmetric normalwash at
    each ``omega / V`` of ``k_over_b`` (1/m), ``dcp = D_k w`` (:func:`panel_pressure`'s operator,
    one inverse of the symmetric unsteady AIC per k). ``key``: a hash of the planform, Mach number
    and lattice density; the operators are then cached by it (new mode shapes of the same
    planform, e.g. a design change in a flutter search, reuse them).

    Parameters
    ----------
    lat : Lattice
        The lattice of the right half.
    k_over_b : array_like, shape (nk,)
        ``omega / V`` values (1/m), >= 0.
    method : str
        Kernel approximation: ``"quartic"`` (:func:`wingmdao.aero.dlm_kernel.oscillatory_aic`) or
        ``"parabolic"`` (PanelAero's).
    key : str, optional
        Hash of the planform, Mach number and lattice density; None: not cached.

    Returns
    -------
    ndarray of complex, shape (nk, m, m)
        The operators D_k.
    """
    kb = np.asarray(k_over_b, dtype=float)
    full = None if key is None else key + hashlib.sha1(kb.tobytes() + method.encode()).hexdigest()
    if full is not None and full in _OPERATORS:
        return _OPERATORS[full]
    out = -np.linalg.inv(_symmetric_aic(lat, kb, method))
    if full is not None:
        if len(_OPERATORS) >= _OPERATORS_SIZE:
            _OPERATORS.pop(next(iter(_OPERATORS)))
        _OPERATORS[full] = out
    return out


@dataclass(frozen=True, eq=False)
class ModalTransfer:
    """Rigid-link transfer of the modes to the panels (right half; columns = modes).

    ``incidence`` (m, modes) rad: each panel's incidence per unit modal amplitude;
    ``heave`` (m, modes) m: the normal displacement of its control point; ``force`` (m, modes)
    m^2: its area times the normal displacement of its force point (quarter chord of the panel).

    Parameters
    ----------
    incidence : ndarray, shape (m, modes)
        Panel incidence per unit modal amplitude (rad).
    heave : ndarray, shape (m, modes)
        Normal displacement of each control point (m).
    force : ndarray, shape (m, modes)
        Panel area times the normal displacement of its force point (m^2).
    """

    incidence: np.ndarray
    heave: np.ndarray
    force: np.ndarray


def _section_motion(lat: Lattice, node_positions, displacement, rotation, points):
    """Normal displacement (m, modes) of ``points`` (m, 3) rigidly linked to the beam section at
    each panel's mid-span, and the panels' incidence (m, modes)."""
    r = lat.hat @ np.asarray(node_positions, dtype=float)             # beam axis at each panel (m, 3)
    u = np.einsum("pn,knc->pkc", lat.hat, displacement)              # (m, modes, 3)
    phi = np.einsum("pn,knc->pkc", lat.hat, rotation)
    arm = (points - r)[:, None, :]
    normal = np.einsum("pkc,pc->pk", u + np.cross(phi, arm), lat.normal)
    incidence = -np.einsum("pkc,pc->pk", np.cross(phi, np.array([1.0, 0.0, 0.0])), lat.normal)
    return normal, incidence


def modal_transfer(lat: Lattice, node_positions, displacement, rotation) -> ModalTransfer:
    """:class:`ModalTransfer` of modes given by nodal ``displacement`` and ``rotation``
    (modes, n, 3), body axes, on the beam through ``node_positions`` (n, 3).

    Parameters
    ----------
    lat : Lattice
        The lattice of the right half.
    node_positions : array_like, shape (n, 3)
        Jig beam nodes (m).
    displacement : array_like, shape (modes, n, 3)
        Nodal displacements of the modes (m), body axes.
    rotation : array_like, shape (modes, n, 3)
        Nodal rotations of the modes (rad), body axes.

    Returns
    -------
    ModalTransfer
        The transfer.
    """
    d = np.asarray(displacement, dtype=float)
    t = np.asarray(rotation, dtype=float)
    if d.ndim != 3 or d.shape != t.shape or d.shape[1:] != (lat.hat.shape[1], 3):
        raise ValueError(f"displacement and rotation must be (modes, {lat.hat.shape[1]}, 3), got {d.shape}, {t.shape}")
    heave, incidence = _section_motion(lat, node_positions, d, t, lat.control)
    force_point = 0.5 * (lat.bound_a + lat.bound_b)
    h_force, _ = _section_motion(lat, node_positions, d, t, force_point)
    return ModalTransfer(incidence=incidence, heave=heave, force=(lat.panel_chord * lat.span)[:, None] * h_force)


def flap_panels(lat: Lattice, surfaces) -> np.ndarray:
    """(m, n_s) bool: the panels of each trailing-edge surface (module docstring), those of the
    elements between its first and last node whose leading edge lies at or aft of its hinge;
    ValueError when a hinge is not on a chordwise panel edge of ``lat`` or a surface has no panel.

    Parameters
    ----------
    lat : Lattice
        The lattice of the right half (built with the hinges on panel edges).
    surfaces : sequence of tuple
        ``(nodes, hinge)`` per surface: node indices (contiguous) and hinge line (fraction of the chord).

    Returns
    -------
    ndarray of bool, shape (m, n_s)
        Panel membership.
    """
    out = []
    for nodes, h in surfaces:
        nodes, h = tuple(int(i) for i in nodes), float(h)
        if len(nodes) < 2 or nodes != tuple(range(nodes[0], nodes[0] + len(nodes))):
            raise ValueError(f"flap nodes {list(nodes)}: allowed at least two contiguous node indices")
        edges = np.unique(np.round(lat.chord_start, 12))
        if np.min(np.abs(edges - h)) > 1e-9:
            raise ValueError(f"hinge = {h} is not on a chordwise panel edge of the lattice "
                             f"(edges {edges.tolist()}); build it with wingmdao.aero.vlm.chord_fractions")
        on = (lat.element >= nodes[0]) & (lat.element < nodes[-1]) & (lat.chord_start >= h - 1e-9)
        if not np.any(on):
            raise ValueError(f"flap nodes {list(nodes)}, hinge {h}: no panel of the lattice lies on the surface")
        out.append(on)
    return np.array(out).T.reshape(lat.span.size, len(out))


def flap_transfer(lat: Lattice, surfaces) -> ModalTransfer:
    """:class:`ModalTransfer` of a unit deflection (rad, trailing edge down positive) of each
    trailing-edge surface (columns), its panels rotating about the hinge line (module docstring).

    Parameters
    ----------
    lat : Lattice
        The lattice of the right half (built with the hinges on panel edges).
    surfaces : sequence of tuple
        ``(nodes, hinge)`` per surface.

    Returns
    -------
    ModalTransfer
        Incidence (rad), control-point normal displacement (m) and force transfer (m^2) per radian.
    """
    on = flap_panels(lat, surfaces).astype(float)
    h = np.array([float(s[1]) for s in surfaces])
    chord = lat.strip_chord[lat.strip]
    x_hinge = (lat.x_quarter - 0.25 * chord)[:, None] + chord[:, None] * h[None, :]   # (m, n_s)
    x_force = 0.5 * (lat.bound_a[:, 0] + lat.bound_b[:, 0])
    area = lat.panel_chord * lat.span
    return ModalTransfer(incidence=on, heave=-on * (lat.control[:, 0][:, None] - x_hinge),
                         force=-on * area[:, None] * (x_force[:, None] - x_hinge))


@dataclass(frozen=True, eq=False)
class GeneralizedForces:
    """Generalized aerodynamic forces of the modes, per unit dynamic pressure.

    ``k`` (nk,) reduced frequencies (omega b_ref / V); ``Q`` (nk, modes, modes) complex: the
    force on mode i of a unit harmonic amplitude of mode j (m^2 per modal amplitude units);
    ``gust`` (nk, modes) complex: of a unit ``w_g / V`` with each panel's penetration delay;
    ``b_ref`` m, ``mach``, ``x_gust`` the x (m) at which the gust phase is zero;
    ``station_loads`` (nk, n, 6, modes + 1) complex: the internal force (N) and moment (N m) at
    each beam node (body axes) of the panel forces outboard of it (:func:`station_summation`),
    per unit dynamic pressure, of a unit amplitude of each mode (columns ``:modes``) and of a unit
    ``w_g / V`` (last column). With control surfaces (flap modes, module docstring) also ``flap``,
    ``hinge`` and ``flap_station_loads``.

    Parameters
    ----------
    k : ndarray, shape (nk,)
        Reduced frequencies.
    Q : ndarray of complex, shape (nk, modes, modes)
        Generalized forces of the modes per unit dynamic pressure.
    gust : ndarray of complex, shape (nk, modes)
        Generalized forces of a unit ``w_g / V``.
    b_ref : float
        Reference semi-chord (m).
    mach : float
        Mach number.
    x_gust : float
        x at which the gust phase is zero (m).
    station_loads : ndarray of complex, shape (nk, n, 6, modes + 1), optional
        Aerodynamic internal loads at the beam nodes.
    flap : ndarray of complex, shape (nk, modes, n_s), optional
        Generalized forces on the modes of a unit deflection (rad) of each control surface.
    hinge : ndarray of complex, shape (nk, n_s, modes + n_s + 1), optional
        Hinge moments (m^3 per unit q, trailing edge down positive) of a unit amplitude of each
        mode, a unit deflection of each surface and a unit ``w_g / V`` (last column).
    flap_station_loads : ndarray of complex, shape (nk, n, 6, n_s), optional
        Aerodynamic internal loads at the beam nodes of a unit deflection of each surface.
    """

    k: np.ndarray
    Q: np.ndarray
    gust: np.ndarray
    b_ref: float
    mach: float
    x_gust: float
    station_loads: np.ndarray = None
    flap: np.ndarray = None
    hinge: np.ndarray = None
    flap_station_loads: np.ndarray = None

    def at(self, k):
        """``(Q, gust)`` at reduced frequency ``k`` (:func:`interpolate`).

        Parameters
        ----------
        k : float
            Reduced frequency, inside the tabulated range.

        Returns
        -------
        Q : ndarray of complex, shape (modes, modes)
            Generalized forces of the modes.
        gust : ndarray of complex, shape (modes,)
            Generalized gust forces.
        """
        return interpolate(self, k)


def interpolate(gaf: GeneralizedForces, k):
    """``(Q (modes, modes), gust (modes,))`` at reduced frequency ``k`` by cubic splines of the real
    and imaginary parts over the tabulated k (linear with two points); ValueError outside them.

    Parameters
    ----------
    gaf : GeneralizedForces
        The tabulated forces.
    k : float
        Reduced frequency, inside the tabulated range.

    Returns
    -------
    Q : ndarray of complex, shape (modes, modes)
        Generalized forces of the modes.
    gust : ndarray of complex, shape (modes,)
        Generalized gust forces.
    """
    k = float(k)
    lo, hi = gaf.k[0], gaf.k[-1]
    if not (lo - 1e-12 <= k <= hi + 1e-12):
        raise ValueError(f"reduced frequency {k:.4g} outside the tabulated range [{lo:.4g}, {hi:.4g}]; "
                         "add reduced frequencies")
    if gaf.k.size == 1:
        return gaf.Q[0], gaf.gust[0]
    if gaf.k.size < 4:
        out = [np.apply_along_axis(lambda f: np.interp(k, gaf.k, f.real) + 1j * np.interp(k, gaf.k, f.imag), 0, a)
               for a in (gaf.Q, gaf.gust)]
        return out[0], out[1]
    splines = gaf.__dict__.get("_splines")
    if splines is None:                  # built once per table (a p-k search interpolates it often)
        splines = [(CubicSpline(gaf.k, a.real, axis=0), CubicSpline(gaf.k, a.imag, axis=0)) for a in (gaf.Q, gaf.gust)]
        object.__setattr__(gaf, "_splines", splines)
    out = [re(k) + 1j * im(k) for re, im in splines]
    return out[0], out[1]


def station_summation(lat: Lattice, node_positions) -> np.ndarray:
    """Internal loads (n, 6, m) at the beam nodes of unit pressure jumps on the panels, per unit
    dynamic pressure: at node s the force ``sum_j A_j n_j`` (N) and the moment
    ``sum_j (p_j - r_s) x A_j n_j`` (N m) of the panels outboard of it (those on the beam elements
    from node s outwards), ``p_j`` the panel's force point (mid-span of its doublet line), body
    axes. The sign is the beam's: the internal loads at a node are those the outboard wing's
    applied loads put on it (:class:`wingmdao.beam.modes.NormalModes`).

    Parameters
    ----------
    lat : Lattice
        The lattice of the right half.
    node_positions : array_like, shape (n, 3)
        Jig beam nodes (m).

    Returns
    -------
    ndarray, shape (n, 6, m)
        The summation operator (m^2 for forces, m^3 for moments, per unit dcp and dynamic pressure).
    """
    r = np.asarray(node_positions, dtype=float)
    force = (lat.panel_chord * lat.span)[:, None] * lat.normal                  # (m, 3) per unit dcp
    point = 0.5 * (lat.bound_a + lat.bound_b)
    element = np.argmax(lat.hat > 0.0, axis=1)                                  # first node of the panel's element
    outboard = (element[None, :] >= np.arange(r.shape[0])[:, None]).astype(float)   # (n, m)
    S = np.zeros((r.shape[0], 6, force.shape[0]))
    S[:, :3, :] = outboard[:, None, :] * force.T[None, :, :]
    arm = point[None, :, :] - r[:, None, :]                                     # (n, m, 3)
    S[:, 3:, :] = outboard[:, None, :] * np.cross(arm, force[None, :, :]).transpose(0, 2, 1)
    return S


def generalized_forces(node_positions, chord, ref_point, displacement, rotation, *, mach=0.0,
                       reduced_frequencies=REDUCED_FREQUENCIES, b_ref=None, x_gust=None,
                       n_chordwise=DLM_CHORDWISE, n_spanwise=DLM_SPANWISE, method="quartic",
                       surfaces=()) -> GeneralizedForces:
    """:class:`GeneralizedForces` of the doublet lattice of the planform (module docstring).

    ``node_positions`` (n, 3) m, ``chord`` (n,) m, ``ref_point`` (n,): the jig beam as for
    :func:`wingmdao.aero.vlm.station_influence`; ``displacement``, ``rotation`` (modes, n, 3): the
    mode shapes (:func:`wingmdao.beam.modes.normal_modes`); ``b_ref`` (m): reference semi-chord
    (default half the root chord); ``x_gust`` (m): where the gust phase is zero (default the
    foremost leading edge); ``surfaces``: trailing-edge control surfaces ``(nodes, hinge)`` as flap
    modes (module docstring; the chordwise panel edges then hold every hinge,
    :func:`wingmdao.aero.vlm.chord_fractions`). Cached by planform, modes, Mach and k set; the pressure operators by planform, Mach and k set
    alone (:func:`pressure_operators`: new modes of the same planform reuse them).
    Errors (ValueError, before any solve): Mach outside [0, 1), an empty or unsorted k set, a
    panel of zero area, a planform whose nodes do not move outboard.

    Parameters
    ----------
    node_positions : array_like, shape (n, 3)
        Jig beam nodes (m).
    chord : float or array_like, shape (n,)
        Streamwise chord (m).
    ref_point : float or array_like, shape (n,)
        Beam axis as a fraction of the chord aft of the leading edge.
    displacement : array_like, shape (modes, n, 3)
        Nodal displacements of the modes (m), body axes.
    rotation : array_like, shape (modes, n, 3)
        Nodal rotations of the modes (rad), body axes.
    mach : float
        Mach number, in [0, 1).
    reduced_frequencies : array_like
        Reduced frequencies ``omega b_ref / V``, increasing, >= 0.
    b_ref : float, optional
        Reference semi-chord (m); default half the root chord.
    x_gust : float, optional
        x where the gust phase is zero (m); default the foremost leading edge.
    n_chordwise : int
        Chordwise panels.
    n_spanwise : int
        Spanwise strips per beam element.
    method : str
        Kernel approximation: ``"quartic"`` (:func:`wingmdao.aero.dlm_kernel.oscillatory_aic`) or
        ``"parabolic"`` (PanelAero's).
    surfaces : sequence of tuple
        ``(nodes, hinge)`` per control surface (node indices, contiguous; hinge fraction of the chord).

    Returns
    -------
    GeneralizedForces
        The forces (shared by the cache: do not modify).
    """
    mach = check_dlm_mach(mach)
    k = check_reduced_frequencies(reduced_frequencies)
    r, c, ref, mach = check_planform(node_positions, chord, ref_point, mach)
    if method not in ("quartic", "parabolic"):
        raise ValueError(f'method must be "quartic" or "parabolic", got {method!r}')
    b = 0.5 * float(c[0]) if b_ref is None else float(b_ref)
    if not (np.isfinite(b) and b > 0.0):
        raise ValueError(f"b_ref must be > 0 m (reference semi-chord), got {b_ref}")
    d = np.asarray(displacement, dtype=float)
    t = np.asarray(rotation, dtype=float)
    srf = tuple((tuple(int(i) for i in nodes), float(h)) for nodes, h in surfaces)
    for nodes, _ in srf:
        if nodes and (nodes[0] < 0 or nodes[-1] >= r.shape[0]):
            raise ValueError(f"flap nodes {list(nodes)} outside the beam; allowed node indices 0 .. {r.shape[0] - 1}")
    fractions = chord_fractions(n_chordwise, [h for _, h in srf]) if srf else None
    key = hashlib.sha1(b"".join(np.ascontiguousarray(v).tobytes() for v in (r, c, ref, d, t, k))
                       + repr((mach, b, x_gust, int(n_chordwise), int(n_spanwise), method, srf)).encode()).hexdigest()
    if key in _CACHE:
        return _CACHE[key]
    lat = build_lattice(r, c, ref, mach=mach, n_chordwise=n_chordwise, n_spanwise=n_spanwise, fractions=fractions)
    check_panels(lat)
    tr = modal_transfer(lat, r, d, t)
    fl = flap_transfer(lat, srf) if srf else None
    nf = len(srf)
    x0 = float(np.min(r[:, 0] - ref * c)) if x_gust is None else float(x_gust)
    nm = d.shape[0]
    Q = np.zeros((k.size, nm, nm), dtype=complex)
    G = np.zeros((k.size, nm), dtype=complex)
    planform = hashlib.sha1(b"".join(np.ascontiguousarray(v).tobytes() for v in (r, c, ref))
                            + repr((mach, int(n_chordwise), int(n_spanwise),
                                    None if fractions is None else fractions.tolist())).encode()).hexdigest()
    D = pressure_operators(lat, k / b, method=method, key=planform)
    S = station_summation(lat, r)
    loads = np.zeros((k.size, r.shape[0], 6, nm + 1), dtype=complex)
    flap = np.zeros((k.size, nm, nf), dtype=complex)
    hinge = np.zeros((k.size, nf, nm + nf + 1), dtype=complex)
    flap_loads = np.zeros((k.size, r.shape[0], 6, nf), dtype=complex)
    for i, ki in enumerate(k):
        kb = ki / b
        cols = [tr.incidence - 1j * kb * tr.heave,
                (lat.normal[:, 2] * np.exp(-1j * kb * (lat.control[:, 0] - x0)))[:, None]]
        if nf:
            cols.append(fl.incidence - 1j * kb * fl.heave)
        dcp = D[i] @ np.concatenate(cols, axis=1)
        F = tr.force.T @ dcp
        Q[i], G[i] = F[:, :nm], F[:, nm]
        L = np.tensordot(S, dcp, axes=1)
        loads[i] = L[..., :nm + 1]
        if nf:
            flap[i] = F[:, nm + 1:]
            Hm = fl.force.T @ dcp                                   # modes, gust, flaps
            hinge[i] = np.concatenate([Hm[:, :nm], Hm[:, nm + 1:], Hm[:, nm:nm + 1]], axis=1)
            flap_loads[i] = L[..., nm + 1:]
    out = GeneralizedForces(k=k, Q=Q, gust=G, b_ref=b, mach=mach, x_gust=x0, station_loads=loads,
                            **({"flap": flap, "hinge": hinge, "flap_station_loads": flap_loads} if nf else {}))
    if len(_CACHE) >= _CACHE_SIZE:
        _CACHE.pop(next(iter(_CACHE)))
    _CACHE[key] = out
    return out
