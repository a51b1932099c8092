"""Von Mises stress at the box corners and mid-flanges along the span: the CalculiX shell model
against the beam's stress recovery (:mod:`wingmdao.stress.box_stress`, Sec. 4.4.2).

Sample points (``POINTS``), per span row of shell elements: at each corner (front-lower,
rear-lower, rear-upper, front-upper, the order of ``wingmdao.section.box.CORNERS``) the skin
element and the spar element that meet there, then the centres of the upper skin, lower skin,
front spar and rear spar (the two elements either side of the centre when the wall has an even
number). FE value: von Mises of the mean stress tensor over the elements' integration points
(ccx expands S8R into C3D20R; the mean over the thickness is the membrane stress, the wall
bending cancels). Beam value at the same point (c, n) of the beam-normal section: the axial
stress of :func:`wingmdao.stress.box_stress.axial_stress` with the Bredt torsion shear q / t of the
wall (:func:`~wingmdao.stress.box_stress.torsion_shear_flow`), plus at the mid-flanges the
transverse shear V Q / (I t) of :func:`~wingmdao.stress.box_stress.box_stresses` (``tau_cent``);
sigma_vm = sqrt(sigma^2 + 3 tau^2) (Eq. 4.21). Internal loads by statics of the jig geometry:
the loads outboard of the row, moved to the row's section centre, in the row's csn axes.
"""

from __future__ import annotations

import numpy as np

from wingmdao.section.box import WALL_NAMES as WALLS
from wingmdao.stress.box_stress import axial_stress, box_stresses, section_quantities, torsion_shear_flow

#: Sample points; the wall index (0 upper skin, 1 lower skin, 2 front spar, 3 rear spar) of each.
POINTS = ("front-lower skin", "front-lower spar", "rear-lower skin", "rear-lower spar",
          "rear-upper skin", "rear-upper spar", "front-upper skin", "front-upper spar",
          "upper skin centre", "lower skin centre", "front spar centre", "rear spar centre")
POINT_WALL = (1, 2, 1, 3, 0, 3, 0, 2, 0, 1, 2, 3)


def _centre_elements(start, count):
    half = count // 2
    return [start + half - 1, start + half] if count % 2 == 0 else [start + half]


def ring_sample_indices(nc: int, nh: int) -> list:
    """Element indices around a ring (lower skin front->rear, rear spar up, upper skin
    rear->front, front spar down) of each of ``POINTS``.

    Parameters
    ----------
    nc : int
        Elements across each skin.
    nh : int
        Elements up each spar web.

    Returns
    -------
    list
        Element index around the ring of each stress point.
    """
    corners = [[0], [2 * nc + 2 * nh - 1], [nc - 1], [nc], [nc + nh], [nc + nh - 1],
               [2 * nc + nh - 1], [2 * nc + nh]]
    centres = [_centre_elements(nc + nh, nc), _centre_elements(0, nc), _centre_elements(2 * nc + nh, nh),
               _centre_elements(nc, nh)]
    return corners + centres


def sample_elements(model) -> list:
    """Per span row of ``model`` (:class:`wingmdao.fe.box_model.ShellBox`): the element ids of
    each of ``POINTS`` (the model's own ``samples`` when it has them: the solid).

    Parameters
    ----------
    model : ShellBox
        The built model.

    Returns
    -------
    list
        Per span row, the element ids of each of ``POINTS``.
    """
    if model.samples is not None:
        return model.samples
    idx = ring_sample_indices(*model.counts)
    return [[[row[k] for k in ks] for ks in idx] for row in model.wall_elements]


def element_centroid(deck, eids) -> np.ndarray:
    """Mean node position of the elements ``eids``.

    Parameters
    ----------
    deck : Deck
        The CalculiX deck.
    eids : sequence of int
        Element ids.

    Returns
    -------
    numpy.ndarray
        (3,) mean of the elements' node coordinates (m).
    """
    return np.mean([deck.nodes[n] for e in eids for n in _connectivity(deck, e)], axis=0)


def _connectivity(deck, eid):
    for _, _, block in deck.elements:
        if eid in block:
            return block[eid]
    raise KeyError(f"element {eid} not in the deck")


def von_mises(s) -> float:
    """Von Mises stress (Pa) of a stress vector (sxx, syy, szz, sxy, sxz, syz).

    Parameters
    ----------
    s : array_like
        (6,) stress vector (sxx, syy, szz, sxy, sxz, syz) (Pa).

    Returns
    -------
    float
        Von Mises stress (Pa).
    """
    sx, sy, sz, txy, txz, tyz = s
    return float(np.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2)
                         + 3.0 * (txy ** 2 + txz ** 2 + tyz ** 2)))


def fe_von_mises(stresses: dict, eids) -> float:
    """Von Mises of the mean integration-point stress of the elements ``eids`` (Pa).

    Parameters
    ----------
    stresses : dict
        Element id -> (k, 6) integration-point stresses (Pa).
    eids : sequence of int
        Element ids.

    Returns
    -------
    float
        Von Mises stress (Pa).
    """
    return von_mises(np.concatenate([stresses[e] for e in eids]).mean(axis=0))


def internal_loads(y, centre, loads):
    """Force and moment (body axes, N and N m) that the part outboard of span coordinate ``y``
    exerts, about ``centre``: sum over the loads [(y_k, centre_k, F_k, M_k)] with y_k > y.

    Parameters
    ----------
    y : float
        Span coordinate of the cut (m).
    centre : array_like
        (3,) point the moment is taken about (m).
    loads : sequence of tuple
        ``(y_k, centre_k, F_k, M_k)`` station loads (m, m, N, N m).

    Returns
    -------
    tuple
        Force (3,) (N) and moment (3,) (N m) in body axes.
    """
    F, M = np.zeros(3), np.zeros(3)
    for yk, ck, Fk, Mk in loads:
        if yk > y:
            Fk = np.asarray(Fk, float)
            F += Fk
            M += np.asarray(Mk, float) + np.cross(np.asarray(ck, float) - centre, Fk)
    return F, M


def beam_point_von_mises(force, moment, geometry, c, n, wall, centre_point) -> float:
    """Beam von Mises (Pa) at (c, n) of the section ``geometry`` = (w, h, t_upper_skin,
    t_lower_skin, t_front_spar, t_rear_spar) (beam-normal cut) under internal loads in csn axes;
    ``centre_point``: add the mid-flange transverse shear of ``box_stresses`` (index ``wall``).

    Parameters
    ----------
    force : array_like
        (3,) internal force in csn axes (N).
    moment : array_like
        (3,) internal moment in csn axes (N m).
    geometry : tuple
        ``(w, h, t_upper_skin, t_lower_skin, t_front_spar, t_rear_spar)`` (m).
    c, n : float
        Point in the section (m).
    wall : int
        Index of the wall in ``tau_cent`` of :func:`~wingmdao.stress.box_stress.box_stresses`.
    centre_point : bool
        Add the mid-flange transverse shear.

    Returns
    -------
    float
        Von Mises stress (Pa).
    """
    sec = section_quantities(geometry)
    sigma = axial_stress(c, n, force, moment, sec)
    if centre_point:
        tau = box_stresses(force, moment, *geometry)["tau_cent"][wall]
    else:
        tau = torsion_shear_flow(force, moment, sec) / geometry[2 + wall]
    return float(np.sqrt(sigma ** 2 + 3.0 * tau ** 2))


def compare_von_mises(model, sections, stresses: dict, loads, axes_at) -> dict:
    """Per span row: ``y`` (m), ``fe`` and ``beam`` (rows x POINTS, Pa). ``sections``:
    :class:`~wingmdao.fe.box_model.BoxSections` (streamwise widths/heights, normal-cut wall
    thicknesses); ``axes_at(y)``: the beam's csn axes T (rows c, s, n in body axes) at y.

    Parameters
    ----------
    model : ShellBox
        The built model.
    sections : BoxSections
        Streamwise sections of the box.
    stresses : dict
        Element id -> integration-point stresses (Pa).
    loads : sequence of tuple
        Station loads ``(y, centre, F, M)`` (m, m, N, N m).
    axes_at : callable
        ``axes_at(y)`` -> (3, 3) csn axes of the beam (rows c, s, n in body axes).

    Returns
    -------
    dict
        ``y`` (m), ``fe`` and ``beam`` (rows x POINTS, Pa).
    """
    ys, fe, beam = [], [], []
    for row in sample_elements(model):
        yc = float(np.mean([element_centroid(model.deck, eids)[1] for eids in row]))
        centre, w, h, t = sections.at(yc)
        T = np.asarray(axes_at(yc), float)
        s = T[1]
        geometry = (w * np.hypot(s[1], s[2]), h * np.hypot(s[0], s[1])) + tuple(t[k] for k in WALLS)
        F, M = internal_loads(yc, centre, loads)
        Fc, Mc = T @ F, T @ M
        ys.append(yc)
        fe.append([fe_von_mises(stresses, eids) for eids in row])
        b = []
        for k, eids in enumerate(row):
            d = element_centroid(model.deck, eids) - centre
            b.append(beam_point_von_mises(Fc, Mc, geometry, float(T[0] @ d), float(T[2] @ d), POINT_WALL[k], k >= 8))
        beam.append(b)
    return {"y": np.array(ys), "fe": np.array(fe), "beam": np.array(beam)}
