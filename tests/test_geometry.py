"""Beam geometry (multi-segment, swept, dihedral, tapered) and the App. D.1 wing-like box case."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from wingmdao.beam.geometry import polyline_beam, streamwise_to_normal, swept_dihedral_points
from wingmdao.beam.residual import forcing_specs, jig_state
from wingmdao.beam.static import BeamModel, beam_forcing
from wingmdao.timemarch.system import pack

_spec = importlib.util.spec_from_file_location("wing_box", Path(__file__).parents[1] / "cases" / "wing_box.py")
wing_box = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(wing_box)


def test_polyline_refinement_and_frames():
    pts = [[0, 0, 0], [1.0, 4.0, 0.0], [1.0, 8.0, 2.0]]
    geo = polyline_beam(pts, [4, 2])
    assert geo.num_nodes == 7
    np.testing.assert_array_equal(geo.key_nodes, [0, 4, 6])
    np.testing.assert_allclose(geo.node_positions[2], [0.5, 2.0, 0.0])
    np.testing.assert_allclose(geo.arc_length[-1], np.sqrt(17) + np.sqrt(20))
    T = geo.csn_axes()
    np.testing.assert_allclose(T[1, 1], np.array([1.0, 4.0, 0.0]) / np.sqrt(17), atol=1e-14)  # s along segment
    np.testing.assert_allclose(T[5, 1], np.array([0.0, 4.0, 2.0]) / np.sqrt(20), atol=1e-14)
    np.testing.assert_allclose(T[1, 2], [0, 0, 1], atol=1e-14)  # horizontal segment: n up
    # kink node: mean angles
    np.testing.assert_allclose(geo.node_euler_angles[4], 0.5 * (geo.node_euler_angles[3] + geo.node_euler_angles[5]))
    np.testing.assert_allclose(geo.interpolate([3.0, 2.0, 1.0])[[0, 2, 4, 5, 6]], [3.0, 2.5, 2.0, 1.5, 1.0])


def test_polyline_bad_input():
    with pytest.raises(ValueError, match="elements_per_segment\\[1\\]"):
        polyline_beam([[0, 0, 0], [0, 1, 0], [0, 2, 0]], [2, 0])
    with pytest.raises(ValueError, match="key_points 0 and 1 coincide"):
        polyline_beam([[0, 0, 0], [0, 0, 0]], [2])


def test_swept_dihedral_points_by_hand():
    pts = swept_dihedral_points([2.0, 3.0], sweeps_deg=[30.0, 0.0], dihedral_deg=10.0)
    np.testing.assert_allclose(pts[1], [2 * np.tan(np.radians(30)), 2.0, 2 * np.tan(np.radians(10))])
    np.testing.assert_allclose(pts[2], [2 * np.tan(np.radians(30)), 5.0, 5 * np.tan(np.radians(10))])


@pytest.mark.parametrize("name", list(wing_box.GEOMETRIES))
def test_wing_box_section_centres(name):
    """Hand values: front face moves aft by d tan(lambda), centre by that minus half the width loss."""
    c = wing_box.section_centres(name)
    g = wing_box.GEOMETRIES[name]
    np.testing.assert_allclose(c[:, 1], [0.0, 3.0, 7.0, 10.0])
    np.testing.assert_allclose(c[:, 2], np.array([0, 3, 7, 10]) * np.tan(np.radians(g["dihedral_deg"])), atol=1e-14)
    front = c[:, 0] - 0.5 * np.array(g["widths"])
    np.testing.assert_allclose(np.diff(front), np.array([3, 4, 3]) * np.tan(np.radians(g["sweeps_deg"])), atol=1e-14)
    if name == "combined":  # CS2: 3 tan 10 deg - 0.25 = 0.27898 m aft, 3 tan 5 deg = 0.26247 m up
        np.testing.assert_allclose(c[1], [0.278981, 3.0, 0.262465], atol=1e-6)


def test_streamwise_to_normal():
    s = np.array([np.sin(0.3), np.cos(0.3), 0.0])
    w, h, ts, tk = streamwise_to_normal(3.0, 0.5, 0.2, 0.1, s)
    assert (w, ts) == pytest.approx((3 * np.cos(0.3), 0.2 * np.cos(0.3)))
    assert (h, tk) == pytest.approx((0.5, 0.1))


@pytest.mark.parametrize("name", list(wing_box.GEOMETRIES))
def test_wing_box_jig_is_equilibrium(name):
    params, stations = wing_box.wing_box_beam(name)
    model = BeamModel(params)
    n = model.num_nodes
    x = jig_state(params).ravel()
    q = pack(forcing_specs(n), beam_forcing(n))
    assert np.max(np.abs(model.system.residual(x, 0 * x, model.p, q))) < 1e-9
    np.testing.assert_array_equal(stations, [0, 6, 14, 20])


def test_prismatic_wing_box_tip_load_closed_form():
    """Hollow rectangle 3 x 0.5 m, spars 0.2, skins 0.1: I = (3 0.5^3 - 2.6 0.3^3) / 12 = 0.0254 m^4;
    Timoshenko tip deflection P L^3 / (3 E I) + P L / (G A_web) with A_web = 2 * 0.2 * 0.3."""
    P, L, E = 1e5, 10.0, 70e9
    G = E / (2 * 1.33)
    out = wing_box.solve_wing_box("prismatic", tip_force=(0.0, 0.0, P))
    expected = P * L**3 / (3 * E * 0.0254) + P * L / (G * 0.12)
    assert out["tip_displacement"][2] == pytest.approx(expected, rel=5e-3)
    assert out["tip_rotation"][0] == pytest.approx(P * L**2 / (2 * E * 0.0254), rel=5e-3)
    assert out["displacement"][0] == pytest.approx(0.0, abs=1e-15)


def test_wing_box_bad_thickness():
    with pytest.raises(ValueError, match="t_skin < height/2 = 0.25 m"):
        wing_box.wing_box_beam("prismatic", t_skin=0.3)
    with pytest.raises(ValueError, match="geometry must be one of"):
        wing_box.section_centres("delta")


def test_streamwise_section_to_csn_rotates_stiffness():
    """Unswept, 5 deg dihedral: bending about x stays EI_cc; the s axis is tilted up by 5 deg."""
    from wingmdao.beam.geometry import streamwise_section_to_csn

    geo = polyline_beam(swept_dihedral_points([3.0], 0.0, 5.0), [2])
    R = streamwise_section_to_csn(geo.node_euler_angles)
    np.testing.assert_allclose(R[0] @ [0, np.cos(np.radians(5)), np.sin(np.radians(5))], [0, 1, 0], atol=1e-14)
    E_sec = np.diag([2.0, 1.0, 5.0])
    E_csn = R[1] @ E_sec @ R[1].T
    assert E_csn[0, 0] == pytest.approx(2.0)
    np.testing.assert_allclose(np.linalg.eigvalsh(E_csn), [1.0, 2.0, 5.0])


def test_wing_box_section_mappings_agree_without_sweep_or_dihedral():
    """Prismatic box: the normal cut is the streamwise cut, both mappings give the same beam."""
    a, _ = wing_box.wing_box_beam("prismatic")
    b, _ = wing_box.wing_box_beam("prismatic", section_mapping="rotated")
    np.testing.assert_allclose(a["stiffness_csn"], b["stiffness_csn"], rtol=1e-12, atol=1e-3)
    c, _ = wing_box.wing_box_beam("sweep", section_mapping="rotated")
    assert abs(c["stiffness_csn"][10, 0, 1]) > 0.0  # rotated streamwise tensor couples bending and torsion
    with pytest.raises(ValueError, match="section_mapping"):
        wing_box.wing_box_beam("sweep", section_mapping="skewed")
