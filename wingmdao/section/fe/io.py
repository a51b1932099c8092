"""Section description files (YAML or JSON) -> mesh -> results dict (SI units)."""

from __future__ import annotations

import json
from pathlib import Path


from .airfoil import naca_surfaces, selig_surfaces
from .analysis import analyse_section, beam_properties_csn
from .box_match import match_box
from .materials import isotropic, orthotropic
from .gmsh_mesh import airfoil_box_mesh_gmsh
from .mesh import airfoil_box_mesh, box_mesh, channel_mesh, rectangle_mesh, tube_mesh

_ORTHO_KEYS = ("E1", "E2", "E3", "G12", "G13", "G23", "nu12", "nu13", "nu23", "rho")


def load_description(path):
    """Read a YAML or JSON section description file into a dict."""
    text = Path(path).read_text()
    if str(path).endswith(".json"):
        return json.loads(text)
    try:
        import yaml
    except ImportError:
        raise ValueError(f"reading {path} needs pyyaml (pip install pyyaml), or give the description as .json") from None
    return yaml.safe_load(text)


def build_materials(spec):
    """Named materials from {'name': {type: isotropic, E, nu, rho} | {type: orthotropic, E1, ...}}."""
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
    if "layup" in spec:
        return {"layup": [(mat(m), float(t), float(a)) for m, t, a in spec["layup"]]}
    return {"thickness": float(spec["thickness"]), "material": mat(spec["material"]),
            "angle_deg": float(spec.get("angle_deg", 0.0))}


def default_airfoil_mesher(stringers=()) -> str:
    """'gmsh' when it imports and there are no stringers (not supported by it), else 'structured'."""
    from .gmsh_mesh import gmsh_available

    return "gmsh" if gmsh_available() and not stringers else "structured"


def build_mesh(desc):
    """Mesh from a description dict; returns (mesh, context) where context carries airfoil box data."""
    mats = build_materials(desc.get("materials"))
    sec = desc.get("section")
    if not sec or "shape" not in sec:
        raise ValueError("description needs a 'section' with a 'shape'")
    shape, size = sec["shape"], sec.get("mesh_size", desc.get("mesh_size"))
    n_thick = int(sec.get("n_thick", 5))
    if n_thick < 5:
        raise ValueError(f"n_thick must be >= 5 elements through a wall, got {n_thick}")
    walls = {k: _wall(v, mats, k) for k, v in (sec.get("walls") or {}).items()}
    if shape == "rectangle":
        n = int(sec.get("n", 20))
        return rectangle_mesh(float(sec["width"]), float(sec["height"]), mats[sec["material"]], n, n), None
    if shape == "tube":
        return tube_mesh(float(sec["diameter"]), _wall(sec, mats, "tube"), n_thick), None
    if shape == "box":
        return box_mesh(float(sec["width"]), float(sec["height"]), walls, n_thick, size,
                        corners=sec.get("corners", "mitre")), None
    if shape == "channel":
        return channel_mesh(float(sec["width"]), float(sec["height"]), walls, n_thick, size), None
    if shape == "airfoil":
        if "naca" in sec:
            up, lo = naca_surfaces(str(sec["naca"]))
        elif "coordinates" in sec:
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
        mesh = build(up, lo, float(sec["chord"]), float(sec["front_spar"]), float(sec["rear_spar"]),
                     walls, float(sec.get("twist_deg", 0.0)), n_thick, size,
                     sec.get("skin_offset", "inward"), stringers, sec.get("corners", "mitre"))
        return mesh, {"walls": walls, "chord": float(sec["chord"]), "mesher": mesher,
                      "spars": (float(sec["front_spar"]), float(sec["rear_spar"]))}
    raise ValueError(f"section shape must be rectangle, tube, channel, box or airfoil, got {shape!r}")


def analyse_description(desc) -> dict:
    """Analyse a description dict; JSON-ready results (SI, section frame: origin and axes in the docs)."""
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
