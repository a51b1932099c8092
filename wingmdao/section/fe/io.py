"""Section description files (YAML or JSON) -> mesh -> results dict (SI units)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np


from .airfoil import naca_surfaces, selig_surfaces
from .analysis import analyse_section, beam_properties_csn
from .box_match import match_box
from .materials import isotropic, orthotropic
from .gmsh_mesh import airfoil_box_mesh_gmsh
from .mesh import airfoil_box_mesh, box_mesh, channel_mesh, rectangle_mesh, tube_mesh
from wingmdao.section.fe.gmsh_mesh import gmsh_available

_ORTHO_KEYS = ("E1", "E2", "E3", "G12", "G13", "G23", "nu12", "nu13", "nu23", "rho")


def load_description(path):
    """Read a YAML or JSON section description file into a dict (ValueError naming the file when it
    is missing, unreadable, malformed or not a mapping).

    Parameters
    ----------
    path : str or path-like
        YAML or JSON section description file.

    Returns
    -------
    dict
        The description.
    """
    try:
        text = Path(path).read_text(encoding="utf-8-sig")  # a byte-order mark is tolerated
    except FileNotFoundError:
        raise ValueError(f"section description {path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"section description {path}: cannot be read ({exc})") from None
    if str(path).endswith(".json"):
        try:
            desc = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ValueError(f"section description {path}: malformed JSON ({exc})") from None
    else:
        try:
            import yaml
        except ImportError:
            raise ValueError(f"reading {path} needs pyyaml (pip install pyyaml), or give the description as .json") from None
        try:
            desc = yaml.safe_load(text)
        except yaml.YAMLError as exc:
            raise ValueError(f"section description {path}: malformed YAML ({' '.join(str(exc).split())})") from None
    if not isinstance(desc, dict):
        raise ValueError(f"section description {path}: must be a mapping with 'materials' and 'section', "
                         f"got {type(desc).__name__}{' (empty file)' if desc is None else ''}")
    return desc


#: Lengths a section description may give (m): below, the mesh is below round-off of the section;
#: above, not a wing section.
LENGTH_RANGE = (1e-6, 1e4)
#: Largest width/height ratio of a solid rectangle on its n x n mesh: 1e3 keeps J and EI within
#: 0.1 % of the thin-strip closed forms, 1e4 is 11 % off (measured, see docs/cross-section-fe.md).
MAX_RECTANGLE_ASPECT = 1e3


def _number(value, name, low=None, high=None, *, open_low=False):
    """``value`` as a finite float in [low, high] (``(low, high]`` with open_low), else ValueError
    naming ``name``, the value and the range."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {value!r}: not a number") from None
    lo_ok = low is None or (v > low if open_low else v >= low)
    if not (np.isfinite(v) and lo_ok and (high is None or v <= high)):
        rng = f"{'(' if open_low else '['}{low if low is not None else '-inf'}, {high if high is not None else 'inf'}]"
        raise ValueError(f"{name} = {value!r}; allowed range {rng}")
    return v


def _length(value, name):
    return _number(value, f"{name} (m)", *LENGTH_RANGE)


def build_materials(spec):
    """Named materials from {'name': {type: isotropic, E, nu, rho} | {type: orthotropic, E1, ...}}.

    Parameters
    ----------
    spec : dict or None
        Material name -> ``{type, E, nu, rho}`` (isotropic) or the nine orthotropic constants and
        ``rho``.

    Returns
    -------
    dict
        Name -> :class:`~wingmdao.section.fe.materials.Material`.
    """
    out = {}
    for name, m in (spec or {}).items():
        kind = m.get("type", "isotropic")
        try:
            if kind == "isotropic":
                out[name] = isotropic(float(m["E"]), float(m["nu"]), float(m["rho"]), name)
            elif kind == "orthotropic":
                out[name] = orthotropic(*(float(m[k]) for k in _ORTHO_KEYS), name=name)
            else:
                raise ValueError(f"material {name}: type must be 'isotropic' or 'orthotropic', got {kind!r}")
        except KeyError as exc:
            raise ValueError(f"material {name}: missing {exc.args[0]}") from None
    return out


def _wall(spec, mats, name):
    def mat(key):
        if key not in mats:
            raise ValueError(f"wall {name}: unknown material {key!r}; defined: {sorted(mats)}")
        return mats[key]
    if not isinstance(spec, dict):
        raise ValueError(f"wall {name}: must be a mapping (thickness, material or layup), got {spec!r}")
    if "layup" in spec:
        plies = []
        for k, ply in enumerate(spec["layup"] or []):
            if not (isinstance(ply, (list, tuple)) and len(ply) == 3):
                raise ValueError(f"wall {name} ply {k}: {ply!r}; each ply is [material, thickness (m), angle (deg)]")
            m, t, a = ply
            plies.append((mat(m), _length(t, f"wall {name} ply {k} thickness"),
                          _number(a, f"wall {name} ply {k} angle (deg)", -360.0, 360.0)))
        if not plies:
            raise ValueError(f"wall {name}: empty layup")
        return {"layup": plies}
    return {"thickness": _length(spec["thickness"], f"wall {name} thickness"), "material": mat(spec["material"]),
            "angle_deg": _number(spec.get("angle_deg", 0.0), f"wall {name} angle_deg", -360.0, 360.0)}


def default_airfoil_mesher(stringers=()) -> str:
    """'gmsh' when it imports and there are no stringers (not supported by it), else 'structured'.

    Parameters
    ----------
    stringers : sequence, optional
        The description's stringers.

    Returns
    -------
    str
        ``"gmsh"`` or ``"structured"``.
    """
    return "gmsh" if gmsh_available() and not stringers else "structured"


def build_mesh(desc):
    """Mesh from a description dict; returns (mesh, context) where context carries airfoil box data.
    A missing key or a value of the wrong type is a ValueError naming it.

    Parameters
    ----------
    desc : dict
        A section description.

    Returns
    -------
    tuple
        (SectionMesh, context dict with the airfoil box data).
    """
    if not isinstance(desc, dict):
        raise ValueError(f"section description must be a mapping with 'materials' and 'section', got {desc!r}")
    try:
        return _build_mesh(desc)
    except KeyError as exc:
        raise ValueError(f"section description: missing key {exc.args[0]!r}") from None
    except (TypeError, AttributeError) as exc:
        raise ValueError(f"section description: a value has the wrong type ({exc})") from None


def _build_mesh(desc):
    if not isinstance(desc.get("materials") or {}, dict):
        raise ValueError("section description: 'materials' must be a mapping of name -> properties")
    mats = build_materials(desc.get("materials"))
    sec = desc.get("section")
    if not isinstance(sec, dict) or "shape" not in sec:
        raise ValueError("description needs a 'section' with a 'shape'")
    shape, size = sec["shape"], sec.get("mesh_size", desc.get("mesh_size"))
    if size is not None:
        size = _length(size, "mesh_size")
    n_thick = int(sec.get("n_thick", 5))
    if n_thick < 5:
        raise ValueError(f"n_thick must be >= 5 elements through a wall, got {n_thick}")
    walls = {k: _wall(v, mats, k) for k, v in (sec.get("walls") or {}).items()}
    if shape == "rectangle":
        n = int(_number(sec.get("n", 20), "section n (elements per side)", 1, 2000))
        w, h = _length(sec["width"], "width"), _length(sec["height"], "height")
        if max(w, h) / min(w, h) > MAX_RECTANGLE_ASPECT:
            raise ValueError(f"rectangle {w:g} x {h:g} m: aspect ratio {max(w, h) / min(w, h):.3g} > "
                             f"{MAX_RECTANGLE_ASPECT:g} (the n x n mesh loses the torsion and bending "
                             "stiffness); model a thin strip as a box or channel wall")
        if sec["material"] not in mats:
            raise ValueError(f"rectangle: unknown material {sec['material']!r}; defined: {sorted(mats)}")
        return rectangle_mesh(w, h, mats[sec["material"]], n, n), None
    if shape == "tube":
        return tube_mesh(_length(sec["diameter"], "diameter"), _wall(sec, mats, "tube"), n_thick), None
    if shape == "box":
        return box_mesh(_length(sec["width"], "width"), _length(sec["height"], "height"), walls, n_thick, size,
                        corners=sec.get("corners", "mitre")), None
    if shape == "channel":
        return channel_mesh(_length(sec["width"], "width"), _length(sec["height"], "height"), walls, n_thick, size), None
    if shape == "airfoil":
        if "naca" in sec:
            up, lo = naca_surfaces(str(sec["naca"]))
        elif "coordinates" in sec:
            if not Path(str(sec["coordinates"])).is_file():
                raise ValueError(f"section coordinates: file {sec['coordinates']!r} does not exist")
            up, lo = selig_surfaces(sec["coordinates"])
        else:
            raise ValueError("airfoil section needs 'naca' or 'coordinates'")
        stringers = []
        for k, st in enumerate(sec.get("stringers") or []):
            if st.get("material") not in mats:
                raise ValueError(f"stringer {k}: unknown material {st.get('material')!r}; defined: {sorted(mats)}")
            stringers.append({**st, "material": mats[st["material"]]})
        mesher = sec.get("mesher") or default_airfoil_mesher(stringers)
        if mesher not in ("gmsh", "structured"):
            raise ValueError(f"section.mesher must be 'gmsh' or 'structured', got {mesher!r}")
        build = airfoil_box_mesh_gmsh if mesher == "gmsh" else airfoil_box_mesh
        mesh = build(up, lo, _length(sec["chord"], "chord"), float(sec["front_spar"]), float(sec["rear_spar"]),
                     walls, float(sec.get("twist_deg", 0.0)), n_thick, size,
                     sec.get("skin_offset", "inward"), stringers, sec.get("corners", "mitre"))
        return mesh, {"walls": walls, "chord": float(sec["chord"]), "mesher": mesher,
                      "spars": (float(sec["front_spar"]), float(sec["rear_spar"]))}
    raise ValueError(f"section shape must be rectangle, tube, channel, box or airfoil, got {shape!r}")


def analyse_description(desc) -> dict:
    """Analyse a description dict; JSON-ready results (SI, section frame: origin and axes in the docs).

    Parameters
    ----------
    desc : dict
        A section description.

    Returns
    -------
    dict
        JSON-ready results (SI).
    """
    mesh, ctx = build_mesh(desc)
    sec = analyse_section(mesh)
    out = {"stiffness_6x6": sec.stiffness, "mass_6x6": sec.mass, "shear_center": sec.shear_center,
           "tension_center": sec.tension_center, "mass_center": sec.mass_center, "area": sec.area,
           "n_elements": int(mesh.elements.shape[0])}
    if ctx is not None:
        out["mesher"] = ctx["mesher"]
    vbs = beam_properties_csn(sec)
    out["beam_csn"] = vbs
    if ctx is not None:
        walls = ctx["walls"]
        th = [sum(_thick(walls[w])) for w in ("upper", "lower", "front", "rear")]
        m0 = _first_material(walls["upper"])
        K = vbs["stiffness_csn"]
        chord = ctx["chord"]
        w0 = (ctx["spars"][1] - ctx["spars"][0]) * chord
        out["box_match"] = match_box(K[0, 0], K[1, 1], th, m0.E_ref, m0.G_ref, w0, 0.1 * chord,
                                     bounds=((1e-3 * chord, chord), (1e-3 * chord, chord)), EI_cs=K[0, 1])
    return out


def _thick(wall):
    return [t for _, t, _ in wall["layup"]] if "layup" in wall else [wall["thickness"]]


def _first_material(wall):
    return wall["layup"][0][0] if "layup" in wall else wall["material"]
