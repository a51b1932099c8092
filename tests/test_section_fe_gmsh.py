"""Airfoil wingbox meshes from gmsh: the same section as the structured mesher, >= 5 elements through
every wall, positive element Jacobians, layups and the description-file / CLI choice of mesher."""

import json

import numpy as np
import pytest

from wingmdao.section.fe import airfoil_box_mesh, airfoil_box_mesh_gmsh, analyse_section, isotropic, orthotropic
from wingmdao.section.fe.airfoil import naca_surfaces
from wingmdao.section.fe.analysis import _N, _NETA, _NXI
from wingmdao.section.fe.gmsh_mesh import gmsh_available

pytestmark = pytest.mark.skipif(not gmsh_available(), reason="gmsh not installed")

AL = isotropic(71e9, 0.33, 2810.0)
WALLS = ("upper", "lower", "front", "rear")


def _walls(th=(0.004, 0.004, 0.006, 0.005), material=AL):
    return {k: {"thickness": t, "material": material} for k, t in zip(WALLS, th)}


def _pair(code="23015", walls=None, **kw):
    up, lo = naca_surfaces(code)
    args = (up, lo, 2.0, 0.18, 0.75, walls or _walls())
    return airfoil_box_mesh_gmsh(*args, **kw), airfoil_box_mesh(*args, **kw)


def test_same_section_as_the_structured_mesher():
    g, s = _pair(mesh_size=0.02, twist_deg=3.0)
    assert g.elements.shape == s.elements.shape
    sg, ss = analyse_section(g), analyse_section(s)
    scale = np.sqrt(np.outer(np.diag(ss.stiffness), np.diag(ss.stiffness)))
    np.testing.assert_allclose(sg.stiffness / scale, ss.stiffness / scale, atol=1e-4)   # measured <= 5e-5
    np.testing.assert_allclose(sg.mass[0, 0], ss.mass[0, 0], rtol=1e-5)
    np.testing.assert_allclose(sg.shear_center, ss.shear_center, atol=1e-4 * 2.0)


def test_layup_matches_the_structured_mesher():
    cfrp = orthotropic(140e9, 10e9, 10e9, 5e9, 5e9, 3.5e9, 0.3, 0.3, 0.5, 1600.0)
    lay = {"layup": [(cfrp, 0.001, 45.0), (cfrp, 0.002, 0.0), (cfrp, 0.001, -30.0)]}
    walls = {"upper": lay, "lower": lay, "front": {"thickness": 0.006, "material": AL},
             "rear": {"layup": [(cfrp, 0.003, 20.0), (cfrp, 0.002, 0.0)]}}
    g, s = _pair(walls=walls, mesh_size=0.02)
    Kg, Ks = analyse_section(g).stiffness, analyse_section(s).stiffness
    scale = np.sqrt(np.outer(np.diag(Ks), np.diag(Ks)))
    assert np.max(np.abs(Ks[0, 3]) / scale[0, 3]) > 1e-3        # extension-torsion coupling present
    np.testing.assert_allclose(Kg / scale, Ks / scale, atol=2e-4)


def _elements_across(mesh, region, x=None, z=None):
    """Elements of ``region`` crossed by the vertical line x (or horizontal line z)."""
    xe = mesh.nodes[mesh.elements]
    k = mesh.region_names.index(region)
    sel = mesh.region == k
    lo, hi = xe.min(axis=1), xe.max(axis=1)
    if x is not None:
        hit = (lo[:, 0] < x) & (hi[:, 0] > x)
    else:
        hit = (lo[:, 1] < z) & (hi[:, 1] > z)
    return int(np.sum(sel & hit))


@pytest.mark.parametrize("n_thick", [5, 7])
def test_at_least_n_thick_elements_through_every_wall(n_thick):
    g, _ = _pair(mesh_size=0.03, n_thick=n_thick)
    assert _elements_across(g, "upper", x=0.9) >= n_thick
    assert _elements_across(g, "lower", x=0.9) >= n_thick
    assert _elements_across(g, "front", z=0.05) >= n_thick
    assert _elements_across(g, "rear", z=0.0) >= n_thick


def test_positive_jacobians_and_curved_skins():
    g, _ = _pair(mesh_size=0.05)
    xe = g.nodes[g.elements]
    det = (np.einsum("gk,ek->eg", _NXI, xe[..., 0]) * np.einsum("gk,ek->eg", _NETA, xe[..., 1])
           - np.einsum("gk,ek->eg", _NXI, xe[..., 1]) * np.einsum("gk,ek->eg", _NETA, xe[..., 0]))
    assert np.all(det > 0)
    assert _N.shape == (9, 9)
    # mid-side nodes of the outer upper skin lie on the airfoil (not on chords between corners)
    up, _ = naca_surfaces("23015")
    top = g.nodes[np.argmax(g.nodes[:, 1])]
    assert top[1] == pytest.approx(2.0 * up(top[0] / 2.0), rel=1e-4)


def test_symmetric_section_has_no_bending_extension_coupling():
    g, _ = _pair(code="0012", walls=_walls((0.004, 0.004, 0.005, 0.005)), mesh_size=0.02)
    sec = analyse_section(g)
    K = sec.stiffness
    assert abs(K[0, 4]) / np.sqrt(K[0, 0] * K[4, 4]) < 1e-6      # x3 = 0 is a symmetry line
    assert abs(sec.tension_center[1]) < 1e-8 and abs(sec.mass_center[1]) < 1e-8


def test_stringers_are_refused():
    up, lo = naca_surfaces("23015")
    st = [{"surface": "upper", "x": 0.4, "width": 0.004, "height": 0.02, "material": AL}]
    with pytest.raises(ValueError, match="stringers"):
        airfoil_box_mesh_gmsh(up, lo, 2.0, 0.18, 0.75, _walls(), stringers=st)


def test_description_file_and_cli_choose_the_mesher(tmp_path, capsys, monkeypatch):
    from wingmdao.cli import main
    from wingmdao.section.fe import io

    desc = {"materials": {"al": {"type": "isotropic", "E": 71e9, "nu": 0.33, "rho": 2810}},
            "section": {"shape": "airfoil", "naca": "23015", "chord": 2.0, "front_spar": 0.18, "rear_spar": 0.75,
                        "mesh_size": 0.03,
                        "walls": {w: {"thickness": 0.004, "material": "al"} for w in WALLS}}}
    path = tmp_path / "s.json"
    path.write_text(json.dumps(desc))
    out = {}
    for mesher in ("gmsh", "structured"):
        assert main(["section-fe", str(path), "--mesher", mesher, "--json", str(tmp_path / f"{mesher}.json")]) == 0
        out[mesher] = json.loads((tmp_path / f"{mesher}.json").read_text())
        assert out[mesher]["mesher"] == mesher
    assert io.analyse_description(desc)["mesher"] == "gmsh"          # the default
    np.testing.assert_allclose(out["gmsh"]["stiffness_6x6"][3][3], out["structured"]["stiffness_6x6"][3][3], rtol=1e-4)
    monkeypatch.setattr("wingmdao.section.fe.io.gmsh_available", lambda: False)   # the name io looks up
    assert io.default_airfoil_mesher() == "structured"
    assert io.default_airfoil_mesher(stringers=[{}]) == "structured"
    desc["section"]["mesher"] = "delaunay"
    with pytest.raises(ValueError, match="mesher"):
        io.analyse_description(desc)


def test_analyse_sections_in_worker_processes_equals_serial():
    from functools import partial

    from wingmdao.section.fe import analyse_sections

    up, lo = naca_surfaces("23015")
    jobs = [partial(airfoil_box_mesh_gmsh, up, lo, c, 0.18, 0.75, _walls(), mesh_size=0.05) for c in (1.5, 2.0, 2.5)]
    par = analyse_sections(jobs, processes=2)
    ser = analyse_sections(jobs, processes=1)
    for a, b in zip(par, ser):
        np.testing.assert_array_equal(a.stiffness, b.stiffness)
    assert par[2].stiffness[4, 4] > par[0].stiffness[4, 4]           # bigger chord, stiffer
