"""Stress-office cards (wingmdao.loads.cards): Nastran FORCE/MOMENT in 8-character fields and
CalculiX *CLOAD of the critical cases, parsed back, their resultants about every station against
the critical case's internal loads."""

import io

import numpy as np
import pytest

from wingmdao.cases import pegasus
from wingmdao.loads import cards as lc
from wingmdao.loads import database as ldb
from wingmdao.loads import matrix as lm

pytest.importorskip("yaml")

SMALL = {
    "altitudes_ft": [10000], "speeds": {"V_C": {"mach": 0.5}},
    "mass_cases": [{"name": "mtow", "weight_lb": 41005, "cg_mac": 0.2, "fuel_fraction": 0.5}],
    "aircraft": {"tail_arm_m": 12.0, "wing_fuel_kg": 3000},
    "gusts": {"gradients_ft": [80, 300]}, "turbulence": True, "maneuvers": {"load_factors": [2.5, -1.0]},
    "model": {"num_nodes": 5, "dt_s": 0.025, "settle_s": 0.4, "grid_points": 21},
}


@pytest.fixture(scope="module")
def db():
    matrix = lm.matrix_from_dict(SMALL)
    return ldb.run_matrix(pegasus, matrix, case="pegasus", progress=io.StringIO())


@pytest.mark.parametrize("x", [0.0, 1.0, -1.0, 0.7071067811865476, -0.123456789, 123456.789, -9876543.21,
                               1.5e-7, -2.5e12, 41005.0, 1e-30])
def test_nastran_real_fits_eight_characters_and_parses_back(x):
    s = lc.nastran_real(x)
    assert len(s) <= 8 and "." in s
    assert lc.parse_nastran_real(s) == pytest.approx(x, rel=5e-5 if abs(x) >= 1 else 2e-5, abs=1e-37)


def test_nastran_real_by_hand():
    assert lc.nastran_real(-0.5) == "-.5"
    assert lc.nastran_real(123456.789) == "123456.8"
    assert lc.nastran_real(-2.5e12) == "-2.5+12"
    assert lc.parse_nastran_real("1.2345+5") == pytest.approx(123450.0)
    assert lc.parse_nastran_real("1.2E-3") == pytest.approx(1.2e-3)
    with pytest.raises(ValueError, match="not a Nastran real"):
        lc.parse_nastran_real("1,5")


def test_nodal_loads_of_a_cantilever_by_hand():
    """A straight beam along y with one tip load P z: the station loads are F_z = P and the bending
    M_x = P (L - y_k); the nodal loads are P at the tip only, nothing else."""
    r = np.column_stack([np.zeros(4), np.linspace(0.0, 3.0, 4), np.zeros(4)])
    euler = np.zeros((4, 3))
    P = 1000.0
    body = np.zeros((4, 6))
    body[:, 2] = P
    body[:, 3] = P * (3.0 - r[:, 1])
    F, M = lc.nodal_loads(lc.body_to_csn_loads(body, euler), r, euler)
    np.testing.assert_allclose(F, [[0, 0, 0]] * 3 + [[0, 0, P]], atol=1e-9)
    np.testing.assert_allclose(M, np.zeros((4, 3)), atol=1e-9)


def test_cards_parse_back_to_the_critical_loads(db):
    n = db.node_positions.shape[0]
    sets = lc.critical_load_sets(db)
    assert len(sets) == len({(s.case_index, s.snapshot.tobytes()) for s in sets})
    covered = {t for s in sets for t in s.critical_for}
    assert covered == {(i, c, e) for i in range(n) for c in lm.PRIMARY for e in ("max", "min")}
    deck = lc.nastran_cards(sets, db.node_positions, db.node_euler_angles)
    for line in deck.splitlines():
        if not line.startswith("$"):
            assert len(line) <= 72 and line[:8].strip() in ("FORCE", "MOMENT")
            assert all(len(line[k:k + 8]) == 8 for k in range(0, len(line), 8))
    nas = lc.read_nastran_loads(deck, n)
    ccx = lc.read_calculix_cloads(lc.calculix_cards(sets, db.node_positions, db.node_euler_angles), n)
    assert sorted(nas) == [s.sid for s in sets] and len(ccx) == len(sets)
    for s, (P2, Q2) in zip(sets, ccx):
        for P, Q, rtol in ((*nas[s.sid], 1e-4), (P2, Q2, 1e-10)):
            body = lc.station_resultants(P, Q, db.node_positions)
            got = lc.body_to_csn_loads(body, db.node_euler_angles)
            # 8-character fields keep 5-6 digits of each nodal load: relative to the largest force / moment
            big = np.abs(s.snapshot).max(axis=0)
            scale = np.r_[np.full(3, big[:3].max()), np.full(3, big[3:].max())]
            assert np.all(np.abs(got - s.snapshot) <= rtol * scale), s.case_name
            for i, comp, extreme in s.critical_for:  # the critical value itself, at its station
                j = lm.COMPONENTS.index(comp)
                env = (db.envelope_max if extreme == "max" else db.envelope_min)[i, j]
                assert abs(got[i, j] - env) <= rtol * scale[j]


def test_write_cards_atomic(db, tmp_path):
    nas, ccx = str(tmp_path / "c.bdf"), str(tmp_path / "c.inp")
    sets = lc.write_cards(db, nas, ccx)
    assert sets and sorted(p.name for p in tmp_path.iterdir()) == ["c.bdf", "c.inp"]
    text = open(ccx).read()
    assert text.count("*STEP") == len(sets) == text.count("*CLOAD, OP=NEW")
    with pytest.raises(ValueError, match="components"):
        lc.critical_load_sets(db, components=("bending",))
