"""Stiffness-matched box (Sec. 4.2.4) on a PEGASUS-like NACA 23015 wingbox, and the section-fe CLI."""

import json

import numpy as np
import pytest

from wingmdao.section.fe import (airfoil_box_mesh, analyse_section, beam_properties_csn, box_stiffness, isotropic,
                                 match_box)
from wingmdao.section.fe.airfoil import naca_surfaces

AL = isotropic(71e9, 0.33, 2810.0)


def test_box_stiffness_closed_form_square_tube():
    # outer 1.01 m square, walls 0.01 m: I = (1.01^4 - 0.99^4) / 12; midline square 1 m: J = 4 A^2 / (4 / t)
    EIc, EIn, GJ = box_stiffness(1.01, 1.01, 0.01, 0.01, 0.01, 0.01, 1.0, 1.0)
    assert EIc == pytest.approx((1.01**4 - 0.99**4) / 12, rel=1e-12)
    assert EIn == pytest.approx(EIc, rel=1e-12)
    assert GJ == pytest.approx(4 * 1.0 / (4 / 0.01), rel=1e-12)


@pytest.mark.parametrize("th", [(0.004, 0.004, 0.006, 0.005), (0.003, 0.005, 0.008, 0.004)])
def test_pegasus_box_match_to_1e3(th):
    up, lo = naca_surfaces("23015")
    walls = {k: {"thickness": t, "material": AL} for k, t in zip(("upper", "lower", "front", "rear"), th)}
    sec = analyse_section(airfoil_box_mesh(up, lo, 2.0, 0.18, 0.75, walls))
    K = beam_properties_csn(sec)["stiffness_csn"]
    r = match_box(K[0, 0], K[1, 1], th, AL.E_ref, AL.G_ref, 1.1, 0.2, bounds=((0.1, 2.0), (0.02, 1.0)))
    EIc, _, GJ = box_stiffness(r["width"], r["height"], *th, AL.E_ref, AL.G_ref)
    assert EIc == pytest.approx(K[0, 0], rel=1e-3)
    assert GJ == pytest.approx(K[1, 1], rel=1e-3)
    assert 0.9 < r["width"] < 1.3 and 0.15 < r["height"] < 0.32      # near the real box (1.14 m x ~0.25 m)


def test_match_box_rejects_bad_target():
    with pytest.raises(ValueError, match="EI_cc"):
        match_box(-1.0, 1.0, (0.01,) * 4, 1.0, 1.0, 1.0, 1.0)


def test_cli_rectangle_and_file(tmp_path, capsys):
    from wingmdao.cli import main
    out = tmp_path / "r.json"
    rc = main(["section-fe", "--rectangle", "0.1", "0.05", "--material", "70e9", "0.3", "2700", "--json", str(out)])
    assert rc in (0, None)
    d = json.loads(out.read_text())
    assert np.array(d["stiffness_6x6"])[0, 0] == pytest.approx(70e9 * 0.005, rel=1e-10)
    assert d["area"] == pytest.approx(0.005)
    f = tmp_path / "c.json"
    f.write_text(json.dumps({"materials": {"al": {"type": "isotropic", "E": 70e9, "nu": 0.3, "rho": 2700}},
                             "section": {"shape": "airfoil", "naca": "2412", "chord": 1.0, "front_spar": 0.2,
                                         "rear_spar": 0.7, "mesh_size": 0.04,
                                         "walls": {k: {"thickness": 0.003, "material": "al"}
                                                   for k in ("upper", "lower", "front", "rear")}}}))
    out2 = tmp_path / "o.json"
    assert main(["section-fe", str(f), "--json", str(out2)]) in (0, None)
    d = json.loads(out2.read_text())
    assert {"width", "height"} <= set(d["box_match"])
    for k in ("mass_6x6", "shear_center", "tension_center", "mass_center"):
        assert k in d


def _naca_walls(t=0.003):
    return {k: {"thickness": t, "material": AL} for k in ("upper", "lower", "front", "rear")}


def test_selig_file_matches_generator(tmp_path):
    up, lo = naca_surfaces("2412")
    x = 0.5 * (1 - np.cos(np.linspace(0, np.pi, 161)))
    rows = [(xi, up(xi)) for xi in x[::-1]] + [(xi, lo(xi)) for xi in x[1:]]
    f = tmp_path / "naca2412.dat"
    f.write_text("NACA 2412\n" + "\n".join(f"{a:.8f} {b:.8f}" for a, b in rows))
    from wingmdao.section.fe.airfoil import selig_surfaces
    su, sl = selig_surfaces(f)
    k1 = analyse_section(airfoil_box_mesh(up, lo, 1.0, 0.2, 0.7, _naca_walls(), mesh_size=0.04)).stiffness
    k2 = analyse_section(airfoil_box_mesh(su, sl, 1.0, 0.2, 0.7, _naca_walls(), mesh_size=0.04)).stiffness
    assert np.allclose(k1, k2, rtol=1e-4, atol=1e-6 * np.abs(k1).max())


def test_twist_rotates_the_section():
    """Twisting by 10 deg is a rigid rotation: EA, torsion (condensed GJ) and the trace of the bending
    block are invariant; the mass centre rotates about the origin."""
    up, lo = naca_surfaces("23015")
    s0 = analyse_section(airfoil_box_mesh(up, lo, 2.0, 0.18, 0.75, _naca_walls(), mesh_size=0.05))
    s1 = analyse_section(airfoil_box_mesh(up, lo, 2.0, 0.18, 0.75, _naca_walls(), twist_deg=10.0, mesh_size=0.05))
    b0, b1 = beam_properties_csn(s0)["stiffness_csn"], beam_properties_csn(s1)["stiffness_csn"]
    assert b1[1, 1] == pytest.approx(b0[1, 1], rel=1e-6)
    assert b1[0, 0] + b1[2, 2] == pytest.approx(b0[0, 0] + b0[2, 2], rel=1e-6)
    assert np.linalg.norm(s1.mass_center) == pytest.approx(np.linalg.norm(s0.mass_center), rel=1e-9)
    assert s1.mass_center[1] < s0.mass_center[1]          # nose-up about the leading edge lowers the aft box


def test_cli_bad_shape_is_a_clean_error(tmp_path, capsys):
    from wingmdao.cli import main
    f = tmp_path / "bad.json"
    f.write_text(json.dumps({"materials": {}, "section": {"shape": "hexagon"}}))
    assert main(["section-fe", str(f)]) == 2
    assert "shape" in capsys.readouterr().err


def test_stringers_add_their_area_and_stiffness():
    """Six 4 mm x 30 mm blade stringers: area grows by 6 b h (the stringer top follows the curved inner
    skin, 1e-4), EA = E A exactly (one isotropic material), EI_cc grows."""
    up, lo = naca_surfaces("23015")
    s0 = analyse_section(airfoil_box_mesh(up, lo, 2.0, 0.18, 0.75, _naca_walls(0.004), mesh_size=0.05))
    st = [{"surface": sf, "x": x, "width": 0.004, "height": 0.03, "material": AL}
          for sf in ("upper", "lower") for x in (0.3, 0.45, 0.6)]
    s1 = analyse_section(airfoil_box_mesh(up, lo, 2.0, 0.18, 0.75, _naca_walls(0.004), mesh_size=0.05, stringers=st))
    assert s1.area - s0.area == pytest.approx(6 * 0.004 * 0.03, rel=1e-4)
    assert s1.stiffness[0, 0] == pytest.approx(AL.E_ref * s1.area, rel=1e-10)
    assert s1.stiffness[4, 4] > 1.03 * s0.stiffness[4, 4]
    with pytest.raises(ValueError, match="stringer 0"):
        airfoil_box_mesh(up, lo, 2.0, 0.18, 0.75, _naca_walls(), stringers=[dict(st[0], x=0.1)])


def test_midline_skin_offset_adds_half_thickness_outward():
    """'midline' puts the OML on the skin midline: the box grows by about one skin thickness in depth,
    so EI_cc rises by roughly 2 t / h (3 %) for a 0.25 m deep box with 4 mm skins."""
    up, lo = naca_surfaces("23015")
    k_in = analyse_section(airfoil_box_mesh(up, lo, 2.0, 0.18, 0.75, _naca_walls(0.004), mesh_size=0.05)).stiffness
    k_mid = analyse_section(airfoil_box_mesh(up, lo, 2.0, 0.18, 0.75, _naca_walls(0.004), mesh_size=0.05,
                                             skin_offset="midline")).stiffness
    assert 1.02 < k_mid[4, 4] / k_in[4, 4] < 1.05
