"""Load cases over MPI ranks (wingmdao.parallel): case assignment, the more-ranks-than-cases error, and
``mpirun -n 2 wingmdao size pegasus`` against the serial run (mass, KS, thicknesses to round-off)."""

import json
import subprocess
import sys

import numpy as np
import pytest

from wingmdao.groups.load_case import LoadCase
from wingmdao.parallel import assign_cases

SMALL_SET = ["size", "pegasus", "--loads", "all", "--gust-gradients-ft", "60", "350", "--gust-sign", "up",
             "--t-final", "0.6", "--dt", "0.05", "--maxiter", "4", "--presize", "1", "--no-plots", "--quiet"]


def test_assign_cases_longest_first_and_too_many_ranks():
    cases = [LoadCase("m1"), LoadCase("m2"), LoadCase("g1", np.linspace(0, 1, 101)), LoadCase("g2", np.linspace(0, 1, 51))]
    assert assign_cases(cases, 2) == [[2], [0, 1, 3]]  # g1 (101 steps) alone, the rest (53) together
    assert assign_cases(cases, 1) == [[0, 1, 2, 3]]
    assert sorted(i for r in assign_cases(cases, 4) for i in r) == [0, 1, 2, 3]
    with pytest.raises(ValueError, match="5 ranks but only 4 load case"):
        assign_cases(cases, 5)


@pytest.mark.slow
def test_mpirun_two_ranks_matches_serial(tmp_path, mpirun, mpi_env):
    ser = subprocess.run([sys.executable, "-m", "wingmdao", *SMALL_SET, "--out", str(tmp_path / "s"),
                          "--json", str(tmp_path / "s.json")], env=mpi_env, capture_output=True, text=True, timeout=600)
    assert ser.returncode in (0, 1), ser.stderr[-2000:]
    par = subprocess.run([*mpirun, "-n", "2", sys.executable, "-m", "wingmdao", *SMALL_SET, "--out", str(tmp_path / "p"),
                          "--json", str(tmp_path / "p.json")], env=mpi_env, capture_output=True, text=True, timeout=600)
    assert par.returncode in (0, 1), par.stderr[-2000:]
    a = json.loads((tmp_path / "s.json").read_text())
    b = json.loads((tmp_path / "p.json").read_text())
    assert b["mpi_ranks"] == 2 and a["mpi_ranks"] == 1
    # (a mismatch was seen once under heavy load, 0 vs 4 iterations: show both runs' ends if it recurs)
    assert a["iterations"] == b["iterations"], (f"serial: {a['iterations']} iterations, {a.get('message')}\n"
                                                f"{ser.stderr[-1500:]}\nmpirun: {b['iterations']} iterations, "
                                                f"{b.get('message')}\n{par.stderr[-1500:]}")
    assert b["mass_kg"] == pytest.approx(a["mass_kg"], rel=1e-10)
    for case, fams in a["ks"].items():
        for f, v in fams.items():
            assert b["ks"][case][f] == pytest.approx(v, rel=1e-9, abs=1e-12)
    for w, t in a["thickness"].items():
        assert np.allclose(b["thickness"][w], t, rtol=1e-9, atol=1e-15)
    assert [r["case"] for r in b["critical_cases"]] == [r["case"] for r in a["critical_cases"]]
    assert np.allclose([r["g_max"] for r in b["critical_cases"]], [r["g_max"] for r in a["critical_cases"]],
                       rtol=1e-9, atol=1e-12)  # the internal loads and stresses gathered from the ranks
    assert (tmp_path / "p" / "pegasus_all.sql").exists()  # rank 0 records (stem: case + load set)
    assert (tmp_path / "p" / "pegasus_all_envelope.npz").exists()
    assert par.stdout.count("wingmdao size pegasus:") == 1  # only rank 0 prints


@pytest.mark.slow
def test_mpirun_more_ranks_than_cases_is_an_error(tmp_path, mpirun, mpi_env):
    argv = ["size", "pegasus", "--loads", "gust", "--gust-gradients-ft", "60", "--gust-sign", "up",
            "--t-final", "0.3", "--dt", "0.03", "--maxiter", "1", "--no-plots", "--quiet", "--out", str(tmp_path)]
    run = subprocess.run([*mpirun, "-n", "2", sys.executable, "-m", "wingmdao", *argv], env=mpi_env,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode != 0
    assert "2 ranks but only 1 load case(s)" in run.stderr


class _OneRank:
    """The part of an mpi4py communicator CaseExchange uses, for one rank in this process."""

    size, rank = 1, 0

    def allgather(self, obj):
        return [obj]


@pytest.mark.slow
def test_case_proxy_partials_and_values_match_the_case():
    """The proxy KS component (values and dense partials from the sub-problem's adjoint) against
    finite differences and against the case evaluated in the ordinary serial model."""
    import openmdao.api as om

    from wingmdao.cases import pegasus
    from wingmdao.parallel import CaseExchange, CaseKS
    from wingmdao.sizing import WALL_VARS, build_problem

    setup = pegasus.build(loads="maneuver")
    rng = np.random.default_rng(3)
    x = {w: rng.uniform(0.004, 0.012, 19) for w in WALL_VARS}
    ex = CaseExchange(setup.geometry, setup.load_cases, setup.material, setup.options, "box", _OneRank(), WALL_VARS,
                      build_problem=build_problem)
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("ks", CaseKS(exchange=ex, case=setup.load_cases[0], dv_size=19), promotes=["*"])
    prob.setup(force_alloc_complex=False)
    for w in WALL_VARS:
        prob.set_val(w, x[w])
    prob.run_model()
    data = prob.check_partials(method="fd", form="central", step=1e-8, out_stream=None)
    for (of, wrt), d in data["ks"].items():
        ref = np.abs(d["J_fd"]).max()
        assert np.abs(d["J_fwd"] - d["J_fd"]).max() <= 1e-5 * max(ref, 1e-12), (of, wrt)
    serial, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
    for w in WALL_VARS:
        serial.set_val(w, x[w])
    serial.run_model()
    assert prob.get_val("ks_vm")[0] == serial.get_val("cases.maneuver_pos.ks_vm")[0]
