"""``wingmdao size CASE --matrix FILE.yaml`` (wingmdao.loads.iteration): frozen critical loads give
back the snapshot's internal loads on the beam, and the load iteration sizes, re-checks and stops."""

import json

import numpy as np
import pytest

from wingmdao.cases import pegasus
from wingmdao.cli import main
from wingmdao.loads import iteration as it
from wingmdao.loads import matrix as lm

pytest.importorskip("yaml")
pytest.importorskip("h5py")

MATRIX = """\
altitudes_ft: [20000]
speeds:
  V_C: {mach: 0.5}
mass_cases:
  - {name: mtow, weight_lb: 41005, cg_mac: 0.25, fuel_fraction: 0.5}
aircraft: {tail_arm_m: 12.0, wing_fuel_kg: 1900}
gusts: {gradients_ft: [350], signs: [up]}
turbulence: false
maneuvers: {load_factors: [2.5, -1.0]}
model: {num_nodes: 20, dt_s: 0.05, settle_s: 0.3}
"""


def test_frozen_load_case_gives_back_the_snapshot(tmp_path):
    """The static beam under a frozen load set (nodal forces and moments) carries the snapshot's
    internal loads: the half wing is a statically determinate cantilever (up to its deflection)."""
    from wingmdao.beam.static import cached_beam_system
    from wingmdao.loads.cards import csn_to_body
    from wingmdao.loads.database import run_matrix
    from wingmdao.timemarch.bdf import solve_static
    from wingmdao.timemarch.system import layout, pack

    path = tmp_path / "m.yaml"
    path.write_text(MATRIX.replace("num_nodes: 20", "num_nodes: 6"))
    matrix = lm.read_matrix(str(path))
    db = run_matrix(pegasus, matrix, case="pegasus", progress=open("/dev/null", "w"))
    crit = it.critical_triples(db)
    cases = it.frozen_load_cases(db, crit)
    assert cases and all(c.time.size == 1 for c in cases)
    system = cached_beam_system(6)
    ql = layout(system.forcing_specs)
    p = pack(system.param_specs, pegasus.beam_params(6))
    c0 = sorted(crit)[0]
    snap = db.snapshot(c0, *crit[c0][0])
    case = next(c for c in cases if c.description.startswith(f"frozen loads of {db.case_names[c0]}"))
    q = np.zeros(system.n_forcing)
    q[ql["point_force"]] = case.forcing["point_force"][0].ravel()
    q[ql["point_moment"]] = case.forcing["point_moment"][0].ravel()
    x, _ = solve_static(system, p, q)
    X = x.reshape(6, 18)
    got = np.concatenate([X[:, 6:9], X[:, 9:12]], axis=1)  # body axes
    want = csn_to_body(snap, db.node_euler_angles)  # the cards' frames: the jig's
    # forces exactly (equilibrium of dead loads); moments up to the deflected lever arms (the
    # snapshot was computed on the deformed wing, the nodal loads use the jig's arms): < 1 %
    fs, ms = np.abs(want[:, :3]).max(), np.abs(want[:, 3:]).max()
    assert np.all(np.abs(got[:, :3] - want[:, :3]) <= 1e-9 * fs)
    assert np.all(np.abs(got[:, 3:] - want[:, 3:]) <= 1e-2 * ms)


@pytest.mark.slow
def test_size_matrix_load_iteration(tmp_path, capsys):
    path = tmp_path / "m.yaml"
    path.write_text(MATRIX)
    js = tmp_path / "r.json"
    argv = ["size", "pegasus", "--loads", "maneuver", "--matrix", str(path), "--maxiter", "6", "--presize", "1",
            "--quiet", "--out", str(tmp_path), "--json", str(js)]
    assert main(argv) == 0
    res = json.loads(js.read_text())
    li = res["load_iteration"]
    assert li["passes"][0]["rechecked"] == 3 and li["sized"] >= 1 and li["rechecked"] == 3 * len(li["passes"])
    assert li["added"] == sum(p["added"] for p in li["passes"][1:])
    assert li["converged"] == (li["passes"][-1]["added"] == 0 and len(li["passes"]) > 1)
    assert res["mass_kg"] > 0 and len(res["thickness"]["upper_skin"]) == 20
    assert "load iteration pass 1" in capsys.readouterr().err


def test_size_matrix_bad_mesh_is_refused_before_any_solve(tmp_path, capsys):
    path = tmp_path / "m.yaml"
    path.write_text(MATRIX.replace("num_nodes: 20", "num_nodes: 6"))
    assert main(["size", "pegasus", "--matrix", str(path), "--out", str(tmp_path), "--json", "-"]) == 2
    err = capsys.readouterr().err
    assert "model.num_nodes = 6; sizing against the matrix needs the 20 nodes" in err
    assert main(["size", "pegasus", "--matrix", str(path), "--analysis-only", "--json", "-"]) == 2
    assert "--matrix sizes against the matrix" in capsys.readouterr().err
