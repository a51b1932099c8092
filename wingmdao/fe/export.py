"""Export a wing box to the decks stress engineers' tools read: CalculiX/Abaqus (``.inp``) and
Nastran bulk data (free-field), as a beam stick model or the shell model.

* Beam stick model: nodes at the section centres (``nodes_per_segment`` elements between
  sections), one element per interval with the box of the interval's mid-point. CalculiX /
  Abaqus: B32R with ``*BEAM SECTION, SECTION=BOX`` (a = width along the local 1-axis = body x,
  b = height, wall thicknesses t1..t4 = rear spar, lower skin, front spar, upper skin: the
  Abaqus BOX convention of walls at +1, +2, -1, -2 with local 2 = t x n1 = -z for a beam along
  +y); CalculiX gets E, G and nu = 0 (:func:`beam_material_ccx`, why: there), Abaqus the
  isotropic material (its beams are not expanded). Nastran: CBAR with PBAR (A, I1, I2, J of the box: thin-walled I about the centroid,
  Bredt J = 4 A_m^2 / sum(s/t)) and MAT1. Point masses: ``*MASS`` / CONM2. Root: all six DOFs
  fixed (``*BOUNDARY`` / SPC1 123456).
* Shell model: :func:`wingmdao.fe.box_model.build_shell_box` (S8R / CQUAD8 + PSHELL).

Abaqus and CalculiX share the input syntax used here (Abaqus Keywords Reference; CalculiX
CrunchiX User's Manual 2.20); the Nastran cards follow the MSC Nastran Quick Reference Guide
(GRID, CBAR, PBAR, CQUAD8, PSHELL, MAT1, CONM2, SPC1, FORCE, MOMENT, LOAD).
"""

from __future__ import annotations

import os

import numpy as np

from wingmdao.fe.box_model import BoxSections, WALLS, add_point_masses, build_shell_box, station_loads
from wingmdao.fe.calculix import Deck, static_step

FORMATS = ("calculix", "abaqus", "nastran")
FIDELITIES = ("beam", "shell")


def box_section_properties(w, h, t):
    """Area, I_x (vertical bending, about the horizontal centroidal axis), I_z and Bredt J (SI)
    of the thin-walled box on the wall mid-lines (w, h outer; t = {WALLS name: thickness}).

    Parameters
    ----------
    w, h : float or array_like
        Outer box width and height (m).
    t : dict
        Wall name -> thickness (m).

    Returns
    -------
    tuple
        Area (m^2), I_x, I_z and J (m^4).
    """
    tu, tl, tf, tr = (t[k] for k in WALLS)
    a = w - (tf + tr) / 2          # mid-line width
    b = h - (tu + tl) / 2          # mid-line height
    area = a * (tu + tl) + b * (tf + tr)
    zc = (a * tu * b / 2 - a * tl * b / 2) / area
    Ix = a * tu * (b / 2 - zc) ** 2 + a * tl * (b / 2 + zc) ** 2 + (tf + tr) * (b**3 / 12 + b * zc**2)
    xc = (b * tr * a / 2 - b * tf * a / 2) / area
    Iz = b * tr * (a / 2 - xc) ** 2 + b * tf * (a / 2 + xc) ** 2 + (tu + tl) * (a**3 / 12 + a * xc**2)
    J = 4 * (a * b) ** 2 / (a / tu + a / tl + b / tf + b / tr)
    return {"area": area, "Ix": Ix, "Iz": Iz, "J": J}


def beam_material_ccx(name, material) -> str:
    """``*MATERIAL`` of a CalculiX beam stick: E and G of ``material``, Poisson ratios 0
    (``*ELASTIC, TYPE=ENGINEERING CONSTANTS``).

    ccx expands B32R into C3D20R bricks; where adjacent elements have different sections (a
    tapered wing) it joins them through a knot, a rigid body of the expanded section at the
    shared node (CalculiX CrunchiX User's Manual 2.20, "Three-node 3D beam element (B32 and
    B32R)", "Knots"). The knot keeps the section from contracting laterally, so with nu = 0.33
    the walls' axial strain is restrained by Poisson coupling: the PEGASUS stick was 26 % too
    stiff (0.602 against the beam's 0.815 m at 1 g), a stick whose width varies by 1.5 % 27 %
    stiffer than the prismatic one; with nu = 0 the same sticks differ by 0.3 %. A beam's
    section carries no transverse normal stress (the beam theory has E and G only), so nu = 0
    with G = E / (2 (1 + nu)) of the material is the beam's constitutive law, not an
    approximation of it.

    Parameters
    ----------
    name : str
        Material name in the deck.
    material : Material
        Isotropic material.

    Returns
    -------
    str
        The ``*MATERIAL`` block.
    """
    E, G = material.E, material.E / (2 * (1 + material.nu))
    return (f"*MATERIAL, NAME={name}\n*ELASTIC, TYPE=ENGINEERING CONSTANTS\n"
            f"{E:.10g}, {E:.10g}, {E:.10g}, 0., 0., 0., {G:.10g}, {G:.10g}\n{G:.10g}, 0.\n"
            f"*DENSITY\n{material.rho:.10g}")


def _stick(sections: BoxSections, nodes_per_segment):
    pts, mids = [sections.centres[0]], []
    for k in range(len(sections.centres) - 1):
        y0, y1 = sections.centres[k, 1], sections.centres[k + 1, 1]
        for s in np.linspace(y0, y1, nodes_per_segment + 1)[1:]:
            pts.append(sections.at(s)[0])
        ys = np.linspace(y0, y1, nodes_per_segment + 1)
        mids += list(0.5 * (ys[:-1] + ys[1:]))
    return np.array(pts), np.array(mids)


def _node_loads(pts, tip_force, tip_moment, loads):
    """[(node index, force (3,), moment (3,))] of the stick nodes: the tip load, or the station
    loads [(y, centre, F, M)] (each at the stick node at its y, moved from its centre)."""
    if loads is None:
        return [(len(pts) - 1, np.asarray(tip_force, float), np.asarray(tip_moment, float))]
    out = []
    for y, c, F, M in loads:
        i = int(np.argmin(np.abs(pts[:, 1] - y)))
        if abs(pts[i, 1] - y) > 1e-6:
            raise ValueError(f"station load at y = {y} m is not at a stick node")
        F = np.asarray(F, float)
        out.append((i, F, np.asarray(M, float) + np.cross(np.asarray(c, float) - pts[i], F)))
    return out


def beam_deck(sections: BoxSections, material, fmt, *, tip_force=(0, 0, 0), tip_moment=(0, 0, 0),
              point_masses=(), nodes_per_segment=4, loads=None) -> str:
    """Stick-model deck text (see module docstring). ``point_masses``: [(node index, kg)];
    ``loads``: station loads [(y, centre, F, M)] at stick nodes instead of the tip load.

    Parameters
    ----------
    sections : BoxSections
        Streamwise sections of the box.
    material : Material
        Isotropic material.
    fmt : {"calculix", "abaqus", "nastran"}
        Deck format.
    tip_force : sequence of 3, optional
        Tip force in body axes (N).
    tip_moment : sequence of 3, optional
        Tip moment in body axes (N m).
    point_masses : sequence of tuple, optional
        ``(node index, mass)`` pairs (kg).
    nodes_per_segment : int, optional
        Beam nodes between two sections.
    loads : sequence of tuple or None, optional
        ``(y, centre, F, M)`` station loads instead of the tip load.

    Returns
    -------
    str
        The deck text.
    """
    pts, mids = _stick(sections, nodes_per_segment)
    n = len(pts)
    node_loads = _node_loads(pts, tip_force, tip_moment, loads)
    props = []
    for y in mids:
        _, w, h, t = sections.at(y)
        props.append((w, h, t, box_section_properties(w, h, t)))
    if fmt in ("calculix", "abaqus"):
        d = Deck("wingmdao beam stick model")
        if fmt == "calculix":
            d.materials.append(beam_material_ccx("MAT", material))
        else:
            d.material("MAT", material)
        # B32R: mid-side nodes at the element mid-points
        ids = d.add_nodes(pts)
        mid_ids = d.add_nodes([0.5 * (pts[i] + pts[i + 1]) for i in range(n - 1)])
        for i, (w, h, t, _) in enumerate(props):
            name = f"B{i + 1}"
            d.add_elements("B32R", name, [[ids[i], mid_ids[i], ids[i + 1]]])
            d.sections.append(f"*BEAM SECTION, ELSET={name}, MATERIAL=MAT, SECTION=BOX\n"
                              f"{w:.10g}, {h:.10g}, {t['t_rear_spar']:.10g}, {t['t_lower_skin']:.10g}, "
                              f"{t['t_front_spar']:.10g}, {t['t_upper_skin']:.10g}\n1., 0., 0.")
        for k, (i, m) in enumerate(point_masses):
            d.add_elements("MASS", f"PM{k + 1}", [[ids[i]]])
            d.model_extra.append(f"*MASS, ELSET=PM{k + 1}\n{m:.10g}")
        d.nsets["ROOT"] = [int(ids[0])]
        d.nsets["TIP"] = [int(ids[-1])]
        d.boundary.append(("ROOT", 1, 6))
        # loads at the clamped root node go straight into the support (ccx refuses moments there)
        rows = [(int(ids[i]), k + 1, float(v)) for i, F, M in node_loads if i > 0
                for k, v in enumerate(np.concatenate([F, M]))]
        return d.text([static_step(rows, ["TIP"])])
    if fmt != "nastran":
        raise ValueError(f"format must be one of {FORMATS}, got {fmt!r}")
    G = material.E / (2 * (1 + material.nu))
    out = ["$ wingmdao beam stick model (SI: m, N, kg, s)", "SOL 101", "CEND", "SUBCASE 1", "  SPC = 1",
           "  LOAD = 1", "  DISPLACEMENT = ALL", "BEGIN BULK"]
    out += [f"GRID,{i + 1},,{p[0]:.10g},{p[1]:.10g},{p[2]:.10g}" for i, p in enumerate(pts)]
    out.append(f"MAT1,1,{material.E:.10g},{G:.10g},{material.nu:.10g},{material.rho:.10g}")
    for i, (_, _, _, pr) in enumerate(props):
        # PBAR I1: about the element z axis (plane 1 = x-y with v = body x), I2 about y
        out.append(f"PBAR,{i + 1},1,{pr['area']:.10g},{pr['Iz']:.10g},{pr['Ix']:.10g},{pr['J']:.10g}")
        out.append(f"CBAR,{i + 1},{i + 1},{i + 1},{i + 2},1.,0.,0.")
    for k, (i, m) in enumerate(point_masses):
        out.append(f"CONM2,{1000 + k},{i + 1},,{m:.10g}")
    out.append("SPC1,1,123456,1")
    for i, F, M in node_loads:
        out.append(f"FORCE,1,{i + 1},,1.,{F[0]:.10g},{F[1]:.10g},{F[2]:.10g}")
        out.append(f"MOMENT,1,{i + 1},,1.,{M[0]:.10g},{M[1]:.10g},{M[2]:.10g}")
    out.append("ENDDATA")
    return "\n".join(out) + "\n"


def shell_deck(sections: BoxSections, material, fmt, *, tip_force=(0, 0, 0), tip_moment=(0, 0, 0),
               ribs_y=(), rib_thickness=0.1, loads=None, point_masses=(), **mesh) -> str:
    """Shell-model deck text (S8R / CQUAD8), tip rib, tip load through a distributing coupling.
    ``loads``: a callable model -> station loads [(y, centre, F, M)] instead of the tip load (no
    tip rib added); ``point_masses``: [(y, kg)] spread on their rings.

    Parameters
    ----------
    sections : BoxSections
        Streamwise sections of the box.
    material : Material
        Isotropic material.
    fmt : {"calculix", "abaqus", "nastran"}
        Deck format.
    tip_force : sequence of 3, optional
        Tip force in body axes (N).
    tip_moment : sequence of 3, optional
        Tip moment in body axes (N m).
    ribs_y : sequence of float, optional
        Rib span coordinates (m).
    rib_thickness : float, optional
        Rib thickness (m).
    loads : callable or None, optional
        ``loads(model)`` -> station loads ``(y, centre, F, M)`` instead of the tip load.
    point_masses : sequence of tuple, optional
        ``(y, mass)`` pairs (m, kg).
    **mesh
        Passed to :func:`~wingmdao.fe.box_model.build_shell_box` (element, element counts and size).

    Returns
    -------
    str
        The deck text.
    """
    span_end = sections.centres[-1, 1]
    ribs = sorted(set(np.round(list(ribs_y) + ([span_end] if loads is None else []), 9)))
    model = build_shell_box(sections, material, ribs_y=ribs, rib_thickness=rib_thickness, **mesh)
    if point_masses:
        add_point_masses(model, point_masses)
    if loads is None:
        loads = station_loads(model, [(span_end, sections.centres[-1], tip_force, tip_moment)])
    else:
        loads = station_loads(model, loads(model))
    d = model.deck
    d.nsets["TIP"] = [int(v) for v in model.rings[-1]]
    if fmt in ("calculix", "abaqus"):
        return d.text([static_step(loads, ["TIP"])])
    if fmt != "nastran":
        raise ValueError(f"format must be one of {FORMATS}, got {fmt!r}")
    G = material.E / (2 * (1 + material.nu))
    out = ["$ wingmdao shell model (SI: m, N, kg, s)", "SOL 101", "CEND", "SUBCASE 1", "  SPC = 1", "  LOAD = 1",
           "  DISPLACEMENT = ALL", "BEGIN BULK"]
    out += [f"GRID,{i},,{c[0]:.10g},{c[1]:.10g},{c[2]:.10g}" for i, c in sorted(d.nodes.items())]
    out.append(f"MAT1,1,{material.E:.10g},{G:.10g},{material.nu:.10g},{material.rho:.10g}")
    thick = {}
    for s in d.sections:
        head, val = s.split("\n")
        thick[head.split("ELSET=")[1].split(",")[0]] = float(val)
    masses = {e.split("ELSET=")[1].split("\n")[0]: float(e.split("\n")[1]) for e in d.model_extra
              if e.startswith("*MASS")}
    pid = 0
    for etype, elset, block in d.elements:
        if etype == "MASS":
            out += [f"CONM2,{e},{conn[0]},,{masses[elset]:.10g}" for e, conn in block.items()]
            continue
        pid += 1
        out.append(f"PSHELL,{pid},1,{thick[elset]:.10g},1")
        card = "CQUAD8" if len(next(iter(block.values()))) == 8 else "CQUAD4"
        for e, conn in block.items():
            out.append(f"{card},{e},{pid}," + ",".join(map(str, conn)))
    out.append("SPC1,1,123456," + ",".join(map(str, d.nsets["ROOT"])))
    for _k, (node, dof, v) in enumerate(loads):
        vec = [0.0, 0.0, 0.0]
        vec[dof - 1] = v
        out.append(f"FORCE,1,{node},,1.,{vec[0]:.10g},{vec[1]:.10g},{vec[2]:.10g}")
    out.append("ENDDATA")
    return "\n".join(out) + "\n"


def write_atomic(text: str, path: str) -> None:
    """Write ``text`` to ``path`` through a temporary file in the same folder and an atomic rename.

    Parameters
    ----------
    text : str
        File contents (ASCII).
    path : str
        Destination file.
    """
    folder = os.path.dirname(os.path.abspath(path))
    tmp = os.path.join(folder, f".{os.path.basename(path)}.tmp")
    with open(tmp, "w", encoding="ascii") as fh:
        fh.write(text)
    os.replace(tmp, path)
