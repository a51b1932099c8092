"""Cross-check against sectionproperties (independent FE code; test-only dependency:
``sectionproperties==3.10.2`` on PyPI). Isotropic sections: area, second moments, torsion constant, shear centre."""

import pytest

sp_lib = pytest.importorskip("sectionproperties.pre.library",
                             reason="sectionproperties not installed (pip install sectionproperties)")
from sectionproperties.analysis.section import Section as SPSection  # noqa: E402

from wingmdao.section.fe import analyse_section, beam_properties_csn, box_mesh, channel_mesh, isotropic  # noqa: E402

E, NU = 70e9, 0.3
AL = isotropic(E, NU, 2700.0)
G = AL.G_ref


def _sp(geom, size):
    geom.create_mesh(mesh_sizes=[size])
    s = SPSection(geom)
    s.calculate_geometric_properties()
    s.calculate_warping_properties()
    return s


def test_hollow_rectangle_vs_sectionproperties():
    d, b, t = 0.2, 0.5, 0.01                  # depth (x3), breadth (x2), wall
    ref = _sp(sp_lib.rectangular_hollow_section(d=d, b=b, t=t, r_out=0.0, n_r=1), 2e-5)
    walls = {k: {"thickness": t, "material": AL} for k in ("upper", "lower", "front", "rear")}
    s = analyse_section(box_mesh(b, d, walls, mesh_size=0.01))
    ixx, iyy, _ = ref.get_ic()
    assert s.area == pytest.approx(ref.get_area(), rel=1e-8)
    assert s.stiffness[4, 4] / E == pytest.approx(ixx, rel=1e-6)
    assert s.stiffness[5, 5] / E == pytest.approx(iyy, rel=1e-6)
    assert s.stiffness[3, 3] / G == pytest.approx(ref.get_j(), rel=2e-3)


def test_channel_shear_center_vs_sectionproperties():
    d, b, tf, tw = 0.2, 0.1, 0.004, 0.004
    ref = _sp(sp_lib.channel_section(d=d, b=b, t_f=tf, t_w=tw, r=0.0, n_r=1), 1e-5)
    x_se, _ = ref.get_sc()                    # origin at the web's outer face, flanges towards +x
    walls = {"upper": {"thickness": tf, "material": AL}, "lower": {"thickness": tf, "material": AL},
             "web": {"thickness": tw, "material": AL}}
    s = analyse_section(channel_mesh(b, d, walls))
    e_fe = s.shear_center[0] - b / 2          # ours: web outer face at +b/2, flanges towards -x2
    assert e_fe == pytest.approx(-x_se, rel=1e-3)         # measured 7e-5
    GJ = beam_properties_csn(s)["stiffness_csn"][1, 1]   # torsion with zero shear force (about the shear centre)
    assert GJ / G == pytest.approx(ref.get_j(), rel=5e-3)


def test_asymmetric_box_shear_center_vs_sectionproperties():
    """Box with a thick front web (6 mm) and thin rear web (2 mm), 3 mm skins: shear centre moves forward."""
    w, h, tf, tr, ts = 0.3, 0.1, 0.006, 0.002, 0.003
    outer = sp_lib.rectangular_section(d=h, b=w)
    inner = sp_lib.rectangular_section(d=h - 2 * ts, b=w - tf - tr).shift_section(x_offset=tf, y_offset=ts)
    ref = _sp(outer - inner, 2e-6)
    x_se, y_se = ref.get_sc()                        # origin at the outer lower-front corner
    walls = {"upper": {"thickness": ts, "material": AL}, "lower": {"thickness": ts, "material": AL},
             "front": {"thickness": tf, "material": AL}, "rear": {"thickness": tr, "material": AL}}
    s = analyse_section(box_mesh(w, h, walls, mesh_size=0.005))
    assert s.shear_center[0] + w / 2 == pytest.approx(x_se, rel=1e-4)     # measured 8e-6
    assert s.shear_center[1] + h / 2 == pytest.approx(y_se, rel=1e-3)
    assert x_se < w / 2                              # forward of the middle, towards the stiff web
