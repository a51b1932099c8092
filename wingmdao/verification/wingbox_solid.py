"""3-D solid model of the 'wing-like' box beam of App. D.1 (Tables D.1, D.2, E.2).

Geometry (the issue's definition, body axes x aft, y outboard, z up, SI):

* Four cross-sections CS1..CS4, streamwise cuts parallel to the root section, at y = 0, 3, 7,
  10 m (d = 3, 4, 3 m, Table D.1). Each is a hollow rectangle: outer width w_i (chordwise, x),
  outer height h_i = 0.5 m (vertical, z), spars (front and rear walls) 0.2 m thick, skins
  (upper and lower walls) 0.1 m thick (Table E.2), all measured in the streamwise cut.
* Segment k (between CS k and CS k+1) has the leading-edge (front face) sweep lambda_k and
  the dihedral theta: the front face moves aft by d_k tan(lambda_k), so the section centre
  moves aft by d_k tan(lambda_k) - (w_k - w_{k+1}) / 2; each section is raised by
  d_k tan(theta). CS1's centre is the origin.
* Between two sections the solid is ruled (every wall face is a linear loft between the two
  sections), which a structured 27-node hexahedral mesh represents exactly.

The root face (CS1) is clamped; a tip force/moment acts on the CS4 face as the rigid-body-
consistent traction of :func:`wingmdao.verification.solid3d.face_load_vector` (moment about the
CS4 section centre). Output: section-average displacement and rotation at CS2, CS3, CS4.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from wingmdao.cases.wing_box.geometry import GEOMETRIES, HEIGHTS, T_SKIN, T_SPAR, geometry_data
from wingmdao.cases.wing_box.geometry import SPANS as SEGMENT_SPANS
from wingmdao.verification import solid3d
from wingmdao.beam.rotations import body_to_csn, euler_from_axis
from wingmdao.beam.static import BeamModel, beam_parameters
from wingmdao.materials import ALUMINIUM
from wingmdao.section.box import box_properties

#: Tables D.1, D.2, E.2 (spans, heights, wall thicknesses, the five geometries) come from
#: wingmdao.cases.wing_box.geometry, the one copy; the model below is independent of the beam's.

#: aluminium of the validation study (Pa, -)
E_ALUMINIUM = 70e9
NU_ALUMINIUM = 0.33

#: how the tip load enters the CS4 face (see solve_wingbox)
TIP_LOAD_MODES = ("traction", "diaphragm", "rigid")


@dataclass(frozen=True)
class BoxCrossSection:
    """One streamwise cross-section: centre (x, y, z) in m, outer width and height (m).

    Parameters
    ----------
    centre : tuple
        (x, y, z) of the section centre (m).
    width : float
        Outer width (m).
    height : float
        Outer height (m).
    """

    centre: tuple
    width: float
    height: float

    @property
    def y(self) -> float:
        return self.centre[1]


def geometry_names() -> list[str]:
    """The five geometries of Fig. D.2 / Table D.2.

    Returns
    -------
    list of str
        The geometry names.
    """
    return list(GEOMETRIES)


def box_sections(name: str) -> list[BoxCrossSection]:
    """CS1..CS4 of geometry ``name``: centres (m), widths and heights (m) (App. D.1, as above).

    Parameters
    ----------
    name : str
        Geometry name.

    Returns
    -------
    list of BoxCrossSection
        CS1 to CS4.
    """
    g = geometry_data(name)
    widths = g["widths"]
    tan_dihedral = np.tan(np.radians(g["dihedral_deg"]))
    x, y, z = 0.0, 0.0, 0.0
    sections = [BoxCrossSection((x, y, z), widths[0], HEIGHTS[0])]
    for k, d in enumerate(SEGMENT_SPANS):
        x += d * np.tan(np.radians(g["sweeps_deg"][k])) - 0.5 * (widths[k] - widths[k + 1])
        y += d
        z += d * tan_dihedral
        sections.append(BoxCrossSection((float(x), float(y), float(z)), widths[k + 1], HEIGHTS[k + 1]))
    return sections


def beam_axis_nodes(name: str, elements_per_segment=(6, 8, 6)) -> np.ndarray:
    """Beam-axis node positions (n, 3) m: straight lines through the section centres, CS1 first.

    Parameters
    ----------
    name : str
        Geometry name.
    elements_per_segment : tuple of int, optional
        Beam elements on each of the three segments.

    Returns
    -------
    numpy.ndarray
        (n, 3) node positions (m).
    """
    cs = np.array([s.centre for s in box_sections(name)])
    pts = [cs[:1]]
    for k, n in enumerate(elements_per_segment):
        t = np.linspace(0.0, 1.0, n + 1)[1:, None]
        pts.append(cs[k] + t * (cs[k + 1] - cs[k]))
    return np.concatenate(pts)


def section_lines(section: BoxCrossSection, t_spar: float, t_skin: float, divisions: dict):
    """Quadratic node lines of one section: x (n_c,) and z (n_n,) in m.

    c: front spar (``spar`` elements through its thickness), skin panel (``chord``), rear spar;
    n: lower skin (``skin`` elements), spar web (``web``), upper skin.

    Parameters
    ----------
    section : BoxCrossSection
        The section.
    t_spar : float
        Spar thickness (m).
    t_skin : float
        Skin thickness (m).
    divisions : dict
        Element counts (:func:`default_divisions`).

    Returns
    -------
    tuple
        x (n_c,) and z (n_n,) node lines (m).
    """
    xc, _, zc = section.centre
    w, h = section.width, section.height
    if not 0.0 < 2.0 * t_spar < w:
        raise ValueError(f"t_spar must be in (0, {w / 2:.4g}) m for width {w} m at y = {section.y} m, "
                         f"got {t_spar}")
    if not 0.0 < 2.0 * t_skin < h:
        raise ValueError(f"t_skin must be in (0, {h / 2:.4g}) m for height {h} m at y = {section.y} m, "
                         f"got {t_skin}")

    def lines(start, t_wall, inner, n_wall, n_inner):
        a = np.linspace(start, start + t_wall, 2 * n_wall + 1)
        b = np.linspace(start + t_wall, start + t_wall + inner, 2 * n_inner + 1)
        c = np.linspace(start + t_wall + inner, start + 2 * t_wall + inner, 2 * n_wall + 1)
        return np.concatenate([a, b[1:], c[1:]])

    x = lines(xc - 0.5 * w, t_spar, w - 2.0 * t_spar, divisions["spar"], divisions["chord"])
    z = lines(zc - 0.5 * h, t_skin, h - 2.0 * t_skin, divisions["skin"], divisions["web"])
    return x, z


def default_divisions(mesh_size: float = 0.15, t_spar: float = T_SPAR, t_skin: float = T_SKIN,
                      sections=None, span_size: float = 0.5, root_grading: float = 10.0) -> dict:
    """Element counts of the structured mesh; every count >= 1 (quadratic elements).

    Cross-section (shared by all segments, set by the root section): ``mesh_size`` (m) is the
    target largest edge: ``spar`` elements through a spar, ``skin`` through a skin, ``chord``
    across the skin panel between the spars, ``web`` up the spar web between the skins.
    Span: ``span_size`` (m) per segment; the root segment is graded towards the clamp (element
    lengths in geometric progression, last/first = ``root_grading``; its edge singularity
    otherwise dominates the error) with enough elements that its largest is <= span_size.
    The convergence study behind the defaults is in docs/verification-solid3d.md.

    Parameters
    ----------
    mesh_size : float, optional
        Largest cross-section edge (m).
    t_spar : float, optional
        Spar thickness (m).
    t_skin : float, optional
        Skin thickness (m).
    sections : sequence of BoxCrossSection or None, optional
        Sections of the geometry; None for a generic root section.
    span_size : float, optional
        Largest element length along the span (m).
    root_grading : float, optional
        Last over first element length of the root segment (-).

    Returns
    -------
    dict
        Element counts.
    """
    for label, v in (("mesh_size", mesh_size), ("span_size", span_size)):
        if not (np.isfinite(v) and v > 0.0):
            raise ValueError(f"{label} must be finite and > 0 m, got {v}")
    root = sections[0] if sections else BoxCrossSection((0.0, 0.0, 0.0), 3.0, 0.5)

    def count(length, size):
        return max(1, int(np.ceil(length / size - 1e-9)))

    n_root = count(SEGMENT_SPANS[0], span_size)
    while n_root < 1000:
        t = _span_parameters(n_root, root_grading)
        if SEGMENT_SPANS[0] * (t[-1] - t[-3]) <= span_size * (1.0 + 1e-9):
            break
        n_root += 1
    return {"span": (n_root,) + tuple(count(d, span_size) for d in SEGMENT_SPANS[1:]),
            "root_grading": root_grading,
            "spar": count(t_spar, mesh_size), "skin": count(t_skin, mesh_size),
            "chord": count(root.width - 2.0 * t_spar, mesh_size),
            "web": count(root.height - 2.0 * t_skin, mesh_size)}


def _span_parameters(n_el: int, grading: float) -> np.ndarray:
    """Node parameters in [0, 1] of n_el quadratic elements (2 n_el + 1 values, midside nodes at
    element midpoints), element lengths in geometric progression with last/first = ``grading``."""
    if n_el < 1:
        raise ValueError(f"span divisions must be >= 1 per segment, got {n_el}")
    q = grading ** (1.0 / max(n_el - 1, 1))
    lengths = q ** np.arange(n_el)
    ends = np.concatenate([[0.0], np.cumsum(lengths)]) / lengths.sum()
    t = np.empty(2 * n_el + 1)
    t[0::2] = ends
    t[1::2] = 0.5 * (ends[:-1] + ends[1:])
    return t


def box_mesh(sections, t_spar: float, t_skin: float, divisions: dict) -> tuple[solid3d.HexMesh, list]:
    """Structured hex27 mesh of the box between consecutive sections; returns (mesh, CS slice indices).

    Parameters
    ----------
    sections : sequence of BoxCrossSection
        The sections.
    t_spar : float
        Spar thickness (m).
    t_skin : float
        Skin thickness (m).
    divisions : dict
        Element counts.

    Returns
    -------
    tuple
        (HexMesh, span slice index of each section).
    """
    x_cs, z_cs = zip(*(section_lines(s, t_spar, t_skin, divisions) for s in sections))
    spans = divisions["span"]
    if len(spans) != len(sections) - 1:
        raise ValueError(f"divisions['span'] needs {len(sections) - 1} entries, got {len(spans)}")
    grading = float(divisions.get("root_grading", 1.0))
    if not (np.isfinite(grading) and grading >= 1.0):
        raise ValueError(f"divisions['root_grading'] must be >= 1 (last/first element length "
                         f"of the root segment), got {grading}")
    slices, cs_index = [], [0]
    for k, n_el in enumerate(spans):
        t = _span_parameters(n_el, grading if k == 0 else 1.0)
        if k:
            t = t[1:]
        for tk in t:
            y = (1.0 - tk) * sections[k].y + tk * sections[k + 1].y
            x = (1.0 - tk) * x_cs[k] + tk * x_cs[k + 1]
            z = (1.0 - tk) * z_cs[k] + tk * z_cs[k + 1]
            X, Z = np.meshgrid(x, z, indexing="ij")
            slices.append(np.stack([X, np.full_like(X, y), Z], axis=-1))
        cs_index.append(len(slices) - 1)
    grid = np.stack(slices)
    e_c, e_n = (grid.shape[1] - 1) // 2, (grid.shape[2] - 1) // 2
    ds, dk = divisions["spar"], divisions["skin"]
    active = np.ones((e_c, e_n), bool)
    active[ds:e_c - ds, dk:e_n - dk] = False          # the hollow interior
    return solid3d.structured_hex27_mesh(grid, active), cs_index


def _root_constraints(mesh: solid3d.HexMesh, root: str, centre) -> np.ndarray:
    """Constrained DOFs at CS1: 'clamped' (all) or 'free_warping' (in-plane DOFs; the axial DOF
    only on the section's symmetry lines x = x_c and z = z_c, where torsional warping vanishes)."""
    nodes = mesh.slice_nodes(0)
    if root == "clamped":
        return solid3d.node_dofs(nodes)
    if root != "free_warping":
        raise ValueError(f"root must be 'clamped' or 'free_warping', got {root!r}")
    r = mesh.nodes[nodes]
    on_axis = np.isclose(r[:, 0], centre[0], atol=1e-9) | np.isclose(r[:, 2], centre[2], atol=1e-9)
    return np.sort(np.concatenate([3 * nodes, 3 * nodes + 2, 3 * nodes[on_axis] + 1]))


def _tip_system(mesh, tip_nodes, tip_faces, centre, force, moment, tip_load):
    """(T, f): u = T v and the load vector on v for the tip-load mode (T None: v = u)."""
    if tip_load == "traction":
        return None, solid3d.face_load_vector(mesh, tip_faces, force, moment, ref_point=centre)
    if tip_load == "diaphragm":
        # the rib carries the in-plane forces and the torque; F_y, M_x, M_z go in as the
        # linear normal traction (the Navier distribution)
        f_normal = solid3d.face_load_vector(mesh, tip_faces, (0.0, force[1], 0.0),
                                            (moment[0], 0.0, moment[2]), ref_point=centre)
        T, _ = solid3d.diaphragm_transform(mesh.num_dof, tip_nodes, mesh.nodes, centre, 1)
        f = T.T @ f_normal
        f[-3:] += (force[0], force[2], moment[1])
        return T, f
    T, _ = solid3d.rigid_face_transform(mesh.num_dof, tip_nodes, mesh.nodes, centre)
    f = np.zeros(T.shape[1])
    f[-6:] = np.concatenate([force, moment])
    return T, f


def _check_load(label, v):
    v = np.asarray(v, float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{label} must be 3 finite body-axis components, got {v}")
    return v


def solve_wingbox(geometry_name: str, tip_force=(0.0, 0.0, 1.0e5), tip_moment=(0.0, 0.0, 0.0),
                  mesh_size: float = 0.15, *, span_size: float = 0.5, divisions: dict | None = None,
                  t_spar: float = T_SPAR, t_skin: float = T_SKIN,
                  E: float = E_ALUMINIUM, nu: float = NU_ALUMINIUM,
                  tip_load: str = "diaphragm", root: str = "clamped", cuts_y=()) -> dict:
    """Linear 3-D solid solution of a wing-like box beam, root (CS1) clamped, tip (CS4) loaded.

    tip_force (N) and tip_moment (N m, about the CS4 section centre) in body axes.
    ``tip_load``: 'diaphragm' (default) puts the in-plane force components and the torque
    M_y on a rigid tip rib (in-plane rigid, free to warp) and F_y, M_x, M_z on the face as the
    linear normal traction; 'traction' spreads everything as the rigid-body-consistent
    traction (uniform for a force, linear for a moment); 'rigid' ties the face to a rigid
    master node. ``root``: 'clamped' (default) or 'free_warping' (diagnostic, pure torque
    only). ``mesh_size``, ``span_size`` (m): see :func:`default_divisions` (or give
    ``divisions`` directly). ``cuts_y``: extra streamwise cuts (y in m, e.g. the beam's
    node stations), returned as ``cuts_displacement`` / ``cuts_rotation`` (n, 3).

    Returns a dict: ``stations`` ["CS2", "CS3", "CS4"], ``y`` (m), ``centre`` (3, 3) section
    centres (m), ``displacement`` (3, 3) section-average displacements (m), ``rotation``
    (3, 3) least-squares rigid rotations of the cuts (rad), ``mean_von_mises`` and
    ``max_von_mises`` (4,) over the cuts CS1..CS4 (Pa; :func:`solid3d.cut_stress_at`; CS1 is
    the clamp's stress singularity and CS4 the load introduction), ``root_reaction_force`` (N) and
    ``root_reaction_moment`` (N m, about the CS1 centre) exerted by the clamp, ``num_dof``,
    ``divisions``, ``solve_time`` (s).

    Parameters
    ----------
    geometry_name : str
        One of :func:`geometry_names`.
    tip_force : sequence of 3, optional
        Tip force, body axes (N).
    tip_moment : sequence of 3, optional
        Tip moment about the CS4 centre, body axes (N m).
    mesh_size : float, optional
        Largest cross-section edge (m).
    span_size : float, optional
        Largest element length along the span (m).
    divisions : dict or None, optional
        Element counts; None for :func:`default_divisions`.
    t_spar : float, optional
        Spar thickness (m).
    t_skin : float, optional
        Skin thickness (m).
    E : float, optional
        Young's modulus (Pa).
    nu : float, optional
        Poisson's ratio (-).
    tip_load : {"diaphragm", "traction", "rigid"}, optional
        How the tip load is introduced.
    root : {"clamped", "free_warping"}, optional
        Root condition.
    cuts_y : sequence of float, optional
        Extra span coordinates where section averages are wanted (m).

    Returns
    -------
    dict
        The solution (keys above).
    """
    t0 = time.perf_counter()
    tip_force, tip_moment = _check_load("tip_force (N)", tip_force), _check_load("tip_moment (N m)", tip_moment)
    if tip_load not in TIP_LOAD_MODES:
        raise ValueError(f"tip_load must be one of {TIP_LOAD_MODES}, got {tip_load!r}")
    if root == "free_warping" and (np.any(tip_force) or tip_moment[0] or tip_moment[2]):
        raise ValueError("root='free_warping' supports a pure tip torque (tip_moment y) only")
    sections = box_sections(geometry_name)
    div = (default_divisions(mesh_size, t_spar, t_skin, sections, span_size)
           if divisions is None else divisions)
    mesh, cs_index = box_mesh(sections, t_spar, t_skin, div)
    K = solid3d.assemble_stiffness(mesh, E, nu)
    fixed = _root_constraints(mesh, root, sections[0].centre)
    T, f = _tip_system(mesh, mesh.slice_nodes(cs_index[-1]), mesh.slice_faces(cs_index[-1]),
                       np.asarray(sections[-1].centre), tip_force, tip_moment, tip_load)
    if T is None:
        u = solid3d.solve_linear(K, f, fixed)
    else:
        # root DOFs are never tied to the tip master, so they keep their column in T
        col = np.asarray(T[fixed].argmax(axis=1)).ravel()
        u = T @ solid3d.solve_linear((T.T @ K @ T).tocsr(), f, col)
    cuts = [solid3d.cut_average(mesh, mesh.slice_faces(i), u) for i in cs_index[1:]]
    extra = [solid3d.cut_average_at(mesh, float(yc), u) for yc in np.atleast_1d(cuts_y)]
    stress = [solid3d.cut_stress_at(mesh, s.y, u, E, nu) for s in sections]
    # support reactions (no external load acts on the root DOFs): force and moment about CS1's centre
    reaction = (K @ u)[fixed]
    r_fixed = mesh.nodes[fixed // 3] - np.asarray(sections[0].centre)
    f_fixed = np.zeros((len(fixed), 3))
    f_fixed[np.arange(len(fixed)), fixed % 3] = reaction
    return {
        "cuts_y": np.atleast_1d(np.asarray(cuts_y, float)),
        "cuts_displacement": np.array([c["displacement"] for c in extra]).reshape(-1, 3),
        "cuts_rotation": np.array([c["rotation"] for c in extra]).reshape(-1, 3),
        "root_reaction_force": f_fixed.sum(axis=0),
        "root_reaction_moment": np.cross(r_fixed, f_fixed).sum(axis=0),
        "geometry": geometry_name,
        "stations": ["CS2", "CS3", "CS4"],
        "y": np.array([s.y for s in sections[1:]]),
        "centre": np.array([s.centre for s in sections[1:]]),
        "cut_centroid": np.array([c["centroid"] for c in cuts]),
        "displacement": np.array([c["displacement"] for c in cuts]),
        "rotation": np.array([c["rotation"] for c in cuts]),
        "mean_von_mises": np.array([c["mean_von_mises"] for c in stress]),
        "max_von_mises": np.array([c["max_von_mises"] for c in stress]),
        "tip_force": tip_force, "tip_moment": tip_moment, "tip_load": tip_load, "root": root,
        "num_dof": mesh.num_dof, "num_elements": len(mesh.elements), "divisions": div,
        "solve_time": time.perf_counter() - t0,
    }


# ----------------------------------------------------------------------------------------
# an independent linear Timoshenko frame along the beam axis (for the mismatch analysis)
# ----------------------------------------------------------------------------------------
def box_beam_properties(width, height, t_spar=T_SPAR, t_skin=T_SKIN, shear="webs"):
    """Linear-beam properties of a symmetric box cut (m, m^2, m^4): A, I_c (vertical bending,
    about the chordwise axis), I_n (chordwise bending), J (Bredt, wall midlines), and the shear
    areas K_n (vertical), K_c (chordwise).

    shear: 'webs' (K_n = spar webs between the skins, K_c = skins: the choice of
    wingmdao.section.box), 'flows' (thin-walled Jourawski shear flows in all walls, energy
    equivalent: K = I^2 / integral (Q/t)^2 t ds) or 'rigid' (Euler-Bernoulli).

    Parameters
    ----------
    width, height : float or array_like
        Outer box dimensions (m).
    t_spar : float, optional
        Spar thickness (m).
    t_skin : float, optional
        Skin thickness (m).
    shear : {"webs", "flows", "rigid"}, optional
        Shear-area model.

    Returns
    -------
    dict
        ``A``, ``I_c``, ``I_n``, ``J``, ``K_n``, ``K_c``.
    """
    w, h, ts, tk = width, height, t_spar, t_skin
    wi, hi = w - 2 * ts, h - 2 * tk
    b, d = w - ts, h - tk                           # midline rectangle
    props = {"A": w * h - wi * hi, "I_c": (w * h**3 - wi * hi**3) / 12,
             "I_n": (h * w**3 - hi * wi**3) / 12,
             "J": 4 * (b * d) ** 2 / (2 * b / tk + 2 * d / ts)}
    if shear == "webs":
        props["K_n"], props["K_c"] = 2 * ts * hi, 2 * tk * w
    elif shear == "flows":
        props["K_n"] = _flow_shear_area(props["I_c"], b, d, tk, ts)
        props["K_c"] = _flow_shear_area(props["I_n"], d, b, ts, tk)
    elif shear == "rigid":
        props["K_n"] = props["K_c"] = np.inf
    else:
        raise ValueError(f"shear must be 'webs', 'flows' or 'rigid', got {shear!r}")
    return props


def _flow_shear_area(I, b, d, t_flange, t_web, n=2001):
    """Energy-equivalent shear area of a symmetric thin-walled box for shear along d:
    flanges of length b (thickness t_flange) at +-d/2, webs of height d (t_web); q = V Q / I."""
    s = np.linspace(0.0, b / 2, n)
    q_f = t_flange * d / 2 * s
    z = np.linspace(0.0, d / 2, n)
    q_w = q_f[-1] + t_web * (d**2 / 4 - z**2) / 2
    energy = 4 * (np.trapezoid(q_f**2, s) / t_flange + np.trapezoid(q_w**2, z) / t_web)
    return I**2 / energy


def _timoshenko_element(L, EA, GJ, EI_y, EI_z, GA_y, GA_z):
    """12x12 local stiffness (u, v, w, rx, ry, rz at both ends), x the axis; bending in x-y uses
    EI_z and GA_y, in x-z uses EI_y and GA_z (exact for a uniform Timoshenko beam)."""
    k = np.zeros((12, 12))
    k[np.ix_([0, 6], [0, 6])] = EA / L * np.array([[1, -1], [-1, 1]])
    k[np.ix_([3, 9], [3, 9])] = GJ / L * np.array([[1, -1], [-1, 1]])
    for EI, GA, (v1, r1, v2, r2), sgn in ((EI_z, GA_y, (1, 5, 7, 11), 1.0), (EI_y, GA_z, (2, 4, 8, 10), -1.0)):
        phi = 12 * EI / (GA * L**2)
        c = EI / ((1 + phi) * L**3)
        m = c * np.array([[12, 6 * L * sgn, -12, 6 * L * sgn],
                          [6 * L * sgn, (4 + phi) * L**2, -6 * L * sgn, (2 - phi) * L**2],
                          [-12, -6 * L * sgn, 12, -6 * L * sgn],
                          [6 * L * sgn, (2 - phi) * L**2, -6 * L * sgn, (4 + phi) * L**2]])
        k[np.ix_([v1, r1, v2, r2], [v1, r1, v2, r2])] = m
    return k


def linear_beam_solution(geometry_name: str, tip_force=(0.0, 0.0, 1.0e5), tip_moment=(0.0, 0.0, 0.0),
                         *, elements_per_metre: int = 8, shear: str = "webs", section: str = "streamwise",
                         t_spar: float = T_SPAR, t_skin: float = T_SKIN,
                         E: float = E_ALUMINIUM, nu: float = NU_ALUMINIUM) -> dict:
    """Linear Timoshenko frame along the axis through the section centres (root clamped).

    An independent small-displacement reference for the beam of App. A (same axis and loads
    as :func:`solve_wingbox`): lets the solid/beam mismatch be split into shear compliance
    (``shear``), section definition (``section``: 'streamwise' uses the streamwise box cut
    as if it were normal to the axis; 'normal' uses the cut normal to the axis, widths times
    cos(sweep of the axis), heights times cos(dihedral)) and what no beam has (warping
    restraint, distortion). Returns ``displacement`` and ``rotation`` (3, 3) at CS2..CS4.

    Parameters
    ----------
    geometry_name : str
        One of :func:`geometry_names`.
    tip_force : sequence of 3, optional
        Tip force, body axes (N).
    tip_moment : sequence of 3, optional
        Tip moment about the CS4 centre, body axes (N m).
    elements_per_metre : int, optional
        Beam elements per metre of span.
    shear : {"webs", "flows", "rigid"}, optional
        Shear-area model.
    section : {"streamwise", "normal"}, optional
        Section cut used for the properties.
    t_spar : float, optional
        Spar thickness (m).
    t_skin : float, optional
        Skin thickness (m).
    E : float, optional
        Young's modulus (Pa).
    nu : float, optional
        Poisson's ratio (-).

    Returns
    -------
    dict
        ``displacement`` and ``rotation`` (3, 3) at CS2 to CS4.
    """
    tip_force, tip_moment = _check_load("tip_force (N)", tip_force), _check_load("tip_moment (N m)", tip_moment)
    if section not in ("streamwise", "normal"):
        raise ValueError(f"section must be 'streamwise' or 'normal', got {section!r}")
    G = E / (2 * (1 + nu))
    cs = box_sections(geometry_name)
    per_segment = [max(2, int(round(d * elements_per_metre))) for d in SEGMENT_SPANS]
    nodes = beam_axis_nodes(geometry_name, per_segment)
    cs_nodes = np.concatenate([[0], np.cumsum(per_segment)])
    n = len(nodes)
    K = np.zeros((6 * n, 6 * n))
    seg_of = np.repeat(np.arange(3), per_segment)
    frac = np.concatenate([(np.arange(m) + 0.5) / m for m in per_segment])
    for e in range(n - 1):
        k_seg, t = seg_of[e], frac[e]
        axis = nodes[e + 1] - nodes[e]
        L = np.linalg.norm(axis)
        s = axis / L
        c = np.array([1.0, 0.0, 0.0]) - s[0] * s
        c /= np.linalg.norm(c)
        nrm = np.cross(c, s)
        w = (1 - t) * cs[k_seg].width + t * cs[k_seg + 1].width
        h = (1 - t) * cs[k_seg].height + t * cs[k_seg + 1].height
        if section == "normal":
            cos_sweep = np.hypot(s[1], s[2])               # axis angle in the xy plane w.r.t. y
            cos_dih = np.hypot(s[0], s[1])
            p = box_beam_properties(w * cos_sweep, h * cos_dih, t_spar * cos_sweep, t_skin * cos_dih, shear)
        else:
            p = box_beam_properties(w, h, t_spar, t_skin, shear)
        # local x = s, y = n, z = c (right-handed: s x n = c)
        k = _timoshenko_element(L, E * p["A"], G * p["J"], E * p["I_n"], E * p["I_c"],
                                G * p["K_n"], G * p["K_c"])
        R = np.array([s, nrm, c])
        T = np.kron(np.eye(4), R)
        dofs = np.concatenate([np.arange(6 * e, 6 * e + 6), np.arange(6 * e + 6, 6 * e + 12)])
        K[np.ix_(dofs, dofs)] += T.T @ k @ T
    f = np.zeros(6 * n)
    f[-6:-3], f[-3:] = tip_force, tip_moment
    u = np.zeros(6 * n)
    u[6:] = np.linalg.solve(K[6:, 6:], f[6:])
    u = u.reshape(n, 6)
    return {"displacement": u[cs_nodes[1:], :3], "rotation": u[cs_nodes[1:], 3:],
            "nodes": nodes, "shear": shear, "section": section}


# ----------------------------------------------------------------------------------------
# beam vs solid comparison (App. E.3, Table E.3 style)
# ----------------------------------------------------------------------------------------
#: the comparison loads: a vertical tip force and a tip torque about y (linear regime)
COMPARISON_LOADS = {
    "tip force Fz = 1e5 N": {"tip_force": (0.0, 0.0, 1.0e5), "tip_moment": (0.0, 0.0, 0.0)},
    "tip torque My = 1e5 N m": {"tip_force": (0.0, 0.0, 0.0), "tip_moment": (0.0, 1.0e5, 0.0)},
}


def compare_with_beam(beam_solver, geometries=None, loads=None, mesh_size: float = 0.15,
                      stations=("CS2", "CS3"), solid_results: dict | None = None) -> list[dict]:
    """Beam-axis vs solid section-average results at CS2/CS3 for each geometry and load.

    beam_solver(geometry_name, tip_force, tip_moment) -> dict with ``displacement`` (3, 3):
    the beam-axis displacement (m, body axes) at CS2, CS3, CS4, and optionally ``rotation``
    (3, 3): the small-rotation vector (rad, body axes) there. Rows (dicts): geometry, load,
    station, quantity (``'|u|'`` displacement magnitude, ``'u_z'``, and ``'theta_y'`` under a torque when
    the beam gives rotations; displacements below 1e-9 m, zero by symmetry, are skipped),
    beam, solid, error_pct = 100 (beam - solid) / solid.
    ``solid_results`` caches solid solutions keyed (geometry, load name).

    Parameters
    ----------
    beam_solver : callable
        ``beam_solver(geometry_name, tip_force, tip_moment)`` -> dict (above).
    geometries : sequence of str or None, optional
        Geometry names; None for all.
    loads : dict or None, optional
        Load name -> (tip force, tip moment); None for ``COMPARISON_LOADS``.
    mesh_size : float, optional
        Solid mesh size (m).
    stations : sequence of str, optional
        Stations compared.
    solid_results : dict or None, optional
        Cache of solid solutions keyed (geometry, load name).

    Returns
    -------
    list of dict
        The comparison rows.
    """
    geometries = geometry_names() if geometries is None else list(geometries)
    loads = COMPARISON_LOADS if loads is None else loads
    cache = {} if solid_results is None else solid_results
    index = {"CS2": 0, "CS3": 1, "CS4": 2}
    rows = []
    for geo in geometries:
        for load_name, load in loads.items():
            key = (geo, load_name)
            if key not in cache:
                cache[key] = solve_wingbox(geo, mesh_size=mesh_size, **load)
            solid = cache[key]
            beam = beam_solver(geo, np.asarray(load["tip_force"], float), np.asarray(load["tip_moment"], float))
            u_beam = np.asarray(beam["displacement"], float)
            for st in stations:
                i = index[st]
                pairs = [("|u|", np.linalg.norm(u_beam[i]), np.linalg.norm(solid["displacement"][i])),
                         ("u_z", u_beam[i, 2], solid["displacement"][i, 2])]
                if "rotation" in beam and load["tip_moment"][1]:
                    pairs.append(("theta_y", np.asarray(beam["rotation"], float)[i, 1], solid["rotation"][i, 1]))
                for q, b, s in pairs:
                    if q != "theta_y" and abs(s) < 1e-9:    # zero by symmetry (round-off only)
                        continue
                    rows.append({"geometry": geo, "load": load_name, "station": st, "quantity": q,
                                 "beam": float(b), "solid": float(s),
                                 "error_pct": float(100.0 * (b - s) / s) if s else float("nan")})
    return rows


def comparison_markdown(rows: list[dict]) -> str:
    """A markdown table of :func:`compare_with_beam` rows.

    Parameters
    ----------
    rows : list of dict
        Rows of :func:`compare_with_beam`.

    Returns
    -------
    str
        The table.
    """
    lines = ["| geometry | load | station | quantity | beam | solid | error (%) |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['geometry']} | {r['load']} | {r['station']} | {r['quantity']} | "
                     f"{r['beam']:.5e} | {r['solid']:.5e} | {r['error_pct']:+.2f} |")
    return "\n".join(lines)


def app_a_beam_solver(geometry_name: str, tip_force, tip_moment, *, elements_per_metre: float = 3.0,
                      load_steps: int = 1) -> dict:
    """The App. A nonlinear beam (``wingmdao.beam``) on the box-beam axis, for :func:`compare_with_beam`.

    Nodes on the straight segments through the section centres (``elements_per_metre`` along
    y), jig frames from the segment directions (at CS2/CS3 the bisector of the two segments),
    section data from ``wingmdao.section.box.box_properties`` of the streamwise cut at each node
    (aluminium, identity ``section_to_csn``), tip force/moment (body axes) at the tip node.
    Returns ``displacement`` and small-rotation ``rotation`` (3, 3) at CS2, CS3, CS4 (body axes).

    Parameters
    ----------
    geometry_name : str
        One of :func:`geometry_names`.
    tip_force : sequence of 3
        Tip force, body axes (N).
    tip_moment : sequence of 3
        Tip moment, body axes (N m).
    elements_per_metre : float, optional
        Beam elements per metre of span.
    load_steps : int, optional
        Newton load steps.

    Returns
    -------
    dict
        ``displacement`` and ``rotation`` (3, 3) at CS2 to CS4.
    """
    per_segment = [max(2, int(round(d * elements_per_metre))) for d in SEGMENT_SPANS]
    nodes = beam_axis_nodes(geometry_name, per_segment)
    cs_nodes = np.concatenate([[0], np.cumsum(per_segment)])
    n = len(nodes)
    seg_dir = np.diff(nodes, axis=0)
    seg_dir /= np.linalg.norm(seg_dir, axis=1)[:, None]
    tangents = np.empty((n, 3))
    tangents[0], tangents[-1] = seg_dir[0], seg_dir[-1]
    tangents[1:-1] = seg_dir[:-1] + seg_dir[1:]
    angles = np.array([euler_from_axis(t) for t in tangents])
    cs = box_sections(geometry_name)
    y = nodes[:, 1]
    width = np.interp(y, [c.y for c in cs], [c.width for c in cs])
    height = np.interp(y, [c.y for c in cs], [c.height for c in cs])
    t_spar, t_skin = np.full(n, T_SPAR), np.full(n, T_SKIN)
    props = box_properties(width, height, t_skin, t_skin, t_spar, t_spar, ALUMINIUM)
    stiff, comp = np.asarray(props["stiffness_csn"]), np.asarray(props["compliance_csn"])
    params = beam_parameters(nodes, angles, EI_cc=stiff[:, 0, 0], GJ=stiff[:, 1, 1], EI_nn=stiff[:, 2, 2],
                             EA=1.0 / comp[:, 1], GK_c=1.0 / comp[:, 0], GK_n=1.0 / comp[:, 2],
                             EI_cn=stiff[:, 0, 2])
    point_force, point_moment = np.zeros((n, 3)), np.zeros((n, 3))
    point_force[-1], point_moment[-1] = tip_force, tip_moment
    out = BeamModel(params).solve(point_force=point_force, point_moment=point_moment, load_steps=load_steps)
    rotation = []
    for i in cs_nodes[1:]:
        Q = body_to_csn(out["theta"][i]).T @ body_to_csn(angles[i])   # jig frame -> deformed frame
        rotation.append(0.5 * np.array([Q[2, 1] - Q[1, 2], Q[0, 2] - Q[2, 0], Q[1, 0] - Q[0, 1]]))
    return {"displacement": out["r"][cs_nodes[1:]] - nodes[cs_nodes[1:]], "rotation": np.array(rotation),
            "num_nodes": n}
