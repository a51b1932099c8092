"""STW (MDO Aeroelastic Benchmark) data and geometry against the benchmark's own stated values."""

import math

import numpy as np
import pytest

from wingmdao.cases import stw
from wingmdao.cases import stw_data as D
from wingmdao.sizing import _check_geometry


def test_planform_matches_the_stated_values():
    a = stw.aero_reference()
    assert a.area == pytest.approx(45.5, abs=1e-9)  # opt_problem.rst
    assert a.area == pytest.approx(D.PLANFORM_AREA)
    assert a.mac == pytest.approx(D.MAC, abs=0.005)  # 3.56 m stated, 3.5641 from the formula
    assert a.mac == pytest.approx(2 / 3 * (5 + 1.5 - 5 * 1.5 / 6.5), rel=1e-9)
    assert a.aspect_ratio == pytest.approx(2 * 14**2 / 45.5)
    assert D.ASPECT_RATIO == pytest.approx(8.6154, abs=1e-4)
    assert D.TAPER_RATIO == pytest.approx(0.3)
    assert stw.chord(0.0) == pytest.approx(5.0) and stw.chord(14.0) == pytest.approx(1.5)
    assert D.LE_SWEEP_DEG == pytest.approx(28.18, abs=0.01)  # atan(7.5 / 14), "28 deg"
    assert stw.quarter_chord_sweep_deg() == pytest.approx(math.degrees(math.atan(6.625 / 14)))
    assert D.DIHEDRAL_DEG == 0.0 and D.TWIST_DEG == (0.0, 0.0)


def test_airfoil_thickness():
    t = stw.thickness_to_chord(np.linspace(0, 1, 20001))
    assert t.max() == pytest.approx(D.THICKNESS_TO_CHORD, abs=1e-4)
    assert stw.thickness_to_chord(0.0) == pytest.approx(0.0) and stw.thickness_to_chord(1.0) == pytest.approx(0.0)


def test_ribs_and_layout():
    ribs = stw.rib_y()
    assert ribs.size == D.NUM_RIBS == 23
    assert np.all(np.diff(ribs) > 0) and ribs[0] >= 0 and ribs[-1] <= D.SEMI_SPAN
    assert np.count_nonzero(ribs <= D.SOB_Y + 1e-12) == 4 and D.SOB_Y in ribs
    assert np.allclose(np.diff(ribs[:4]), 0.5) and np.allclose(np.diff(ribs[3:]), 12.5 / 19)
    assert np.max(np.abs(ribs - np.array(D.RIB_Y_MESH))) <= D.MESH_END_OFFSET + 1e-12  # the FE mesh's ribs
    assert D.NUM_PANELS == 111
    assert sum(D.PLY_FRACTIONS_SKIN) == pytest.approx(1.0) and sum(D.PLY_FRACTIONS_SPAR_RIB) == pytest.approx(1.0)


def test_spars_follow_the_benchmark_mesh():
    xf, xr = stw.spar_x([0.0, D.SOB_Y, 14.0])
    assert xf[0] == pytest.approx(1.497321429) and xr[0] == pytest.approx(3.809821429)  # BDF $XSUPER, root rib
    assert xf[1] == xf[0] and xr[1] == xr[0]  # unswept centre box
    assert xf[2] == pytest.approx(7.5 + 0.15 * 1.5) and xr[2] == pytest.approx(7.5 + 0.65 * 1.5)
    b = stw.beam_geometry()
    fu, fl, ru, rl = D.ROOT_SPAR_CORNERS_Z_MESH
    assert b.front_spar_height[0] == pytest.approx(fu - fl, abs=1e-3)
    assert b.rear_spar_height[0] == pytest.approx(ru - rl, abs=1e-3)


@pytest.mark.parametrize("n", [23, 24, 60])
def test_beam_nodes_follow_the_sweep(n):
    b = stw.beam_geometry(n)
    pos = b.geometry.node_positions
    assert pos.shape == (n, 3) and b.geometry.num_nodes == n
    assert np.allclose(pos[b.rib_nodes, 1], b.rib_y)  # a node at every rib
    assert np.all(np.diff(pos[:, 1]) > 0) and pos[0, 1] == 0.0 and pos[-1, 1] == D.SEMI_SPAN
    out = pos[:, 1] >= D.SOB_Y
    x_mid = D.TIP_LE_OFFSET * pos[:, 1] / 14 + 0.4 * stw.chord(pos[:, 1])
    assert np.allclose(pos[out, 0], x_mid[out])
    assert np.allclose(pos[~out, 0], x_mid[np.flatnonzero(out)[0]])  # unswept centre box
    assert np.allclose(pos[:, 2], 0.0)
    sweep = math.degrees(math.atan(6.1 / 14))
    k_sob = int(np.flatnonzero(np.isclose(pos[:, 1], D.SOB_Y))[0])
    assert np.allclose(b.sweep_deg[k_sob + 1:], sweep) and np.allclose(b.sweep_deg[:k_sob], 0.0, atol=1e-12)
    assert np.allclose(b.geometry.node_euler_angles[k_sob + 1:, 2], -math.radians(sweep))
    assert np.allclose(b.geometry.node_euler_angles[:, :2], 0.0, atol=1e-12)
    _check_geometry(b.geometry, "box")


@pytest.mark.parametrize("cut,rule", [("normal", "spars"), ("streamwise", "spars"), ("normal", "mean10")])
def test_box_dimensions_positive_and_inside_the_airfoil(cut, rule):
    b = stw.beam_geometry(40, cut=cut, height_rule=rule)
    w, h = b.geometry.width, b.geometry.height
    assert np.all(w > 0) and np.all(h > 0)
    assert np.all(w <= 0.5 * b.chord + 1e-12) and np.all(w <= b.width_streamwise + 1e-12)
    assert np.all(h < D.THICKNESS_TO_CHORD * b.chord)
    if cut == "streamwise":
        assert np.allclose(w[b.y >= D.SOB_Y], 0.5 * b.chord[b.y >= D.SOB_Y])
    else:
        assert np.allclose(w, b.width_streamwise * np.cos(np.radians(b.sweep_deg)))
    if rule == "spars":
        assert np.allclose(h, 0.5 * (b.front_spar_height + b.rear_spar_height))
    assert np.allclose(b.geometry.nonstructural_mass_per_length, 0.0)


def test_case1_data():
    assert [c.load_factor for c in D.CASE1_CONDITIONS] == [2.5, -1.0]
    assert all(c.altitude == 0.0 and c.mach == 0.458 and c.mass == "LGM" for c in D.CASE1_CONDITIONS)
    assert 0.398 * 1.15 == pytest.approx(D.PULL_UP.mach, abs=5e-4)
    assert D.SAFETY_FACTOR == 1.5 and D.STIFFENER_PITCH == 0.15 and D.STIFFENER_TYPE == "T"
    assert D.landing_gross_mass(1000.0) == pytest.approx(41.5e3 + 2 * 10.147 * 1000.0**0.8162)
    assert D.equivalent_thickness(0.0065, 0.006 * 0.05 * 2, 0.15) == pytest.approx(0.0065 + 0.004)


@pytest.mark.parametrize("bad", [22, 0, -5, 23.0, True, "30"])
def test_bad_node_counts(bad):
    with pytest.raises(ValueError, match="num_nodes"):
        stw.beam_geometry(bad)


def test_bad_options_and_spans():
    with pytest.raises(ValueError, match="cut"):
        stw.beam_geometry(cut="oblique")
    with pytest.raises(ValueError, match="height_rule"):
        stw.beam_geometry(height_rule="max")
    with pytest.raises(ValueError, match="semi-span"):
        stw.aero_reference([0.0, 14.5])
    with pytest.raises(ValueError, match="finite"):
        stw.chord(np.nan)
    with pytest.raises(ValueError, match="wingbox_mass"):
        D.landing_gross_mass(-1.0)
