"""uCRM multipoint fuel-burn problem (wingmdao.oas.crm) and ``wingmdao size aerostruct-crm``:
total derivatives against finite differences, the command-line contract, and the JSON.
A coarse mesh (num_y 9: 5 beam nodes) keeps it fast."""

import json
import sys

import numpy as np
import pytest

pytest.importorskip("openaerostruct")

from wingmdao.cli import main  # noqa: E402

NUM_Y = "9"


@pytest.fixture(scope="module")
def crm():
    from wingmdao.oas.crm import build_crm_problem, setup_crm_problem

    prob, stress = build_crm_problem("wingmdao", int(NUM_Y))
    setup_crm_problem(prob)
    prob.run_model()
    return prob, stress


@pytest.mark.slow
def test_crm_totals_match_finite_differences(crm):
    """Adjoint totals of fuel burn, CL, our KS at both points and L = W at the maneuver with
    respect to twist, spar and skin thickness and maneuver alpha: central FD, 1e-4 relative on
    the non-trivial entries (max 9.4e-7 measured). Fails with the old absolute adjoint tolerance
    (1e-10: 2e-3 on the maneuver KS)."""
    prob, stress = crm
    of = ["AS_point_0.fuelburn", "AS_point_0.CL", stress["cruise"], stress["maneuver"], "AS_point_1.L_equals_W"]
    wrt = ["wing.twist_cp", "wing.spar_thickness_cp", "wing.skin_thickness_cp", "alpha"]
    data = prob.check_totals(of=of, wrt=wrt, method="fd", step=1e-6, form="central", out_stream=None)
    checked = 0
    for key, v in data.items():
        J, F = v["J_rev"], v["J_fd"]
        if not np.any(F):   # cruise outputs do not depend on the maneuver alpha
            assert np.all(J == 0.0), key
            continue
        nontrivial = np.abs(F) > 1e-6 * np.abs(F).max()
        assert np.all(np.abs(J - F)[nontrivial] <= 1e-4 * np.abs(F)[nontrivial]), key
        checked += 1
    assert checked == len(of) * len(wrt) - 3   # fuelburn, CL, KS at cruise: not w.r.t. alpha[1]


def _run(argv, capsys):
    rc = main(argv)
    out = capsys.readouterr()
    return rc, out.out, out.err


def test_cli_analysis_only_json_stdout(tmp_path, capsys):
    """--json -: only JSON on stdout; fuel burn, mass, KS per point, L = W for both beams; the two
    beams on the same geometry: the same wing mass, fuel burn within 1 % (89 412 vs 89 360 kg at
    num_y 15, docs/embedding.md); < 25 coupled iterations (issue 12)."""
    rc, out, err = _run(["size", "aerostruct-crm", "--analysis-only", "--num-y", NUM_Y, "--out", str(tmp_path),
                         "--json", "-"], capsys)
    assert rc == 0, err
    res = json.loads(out)
    for r in (res, res["oas_beam"]):
        assert r["success"] is True and r["iterations"] == 0
        assert set(r["ks"]) == {"cruise", "maneuver"} and all(v < 0 for v in r["ks"].values())
        assert r["fuelburn_kg"] > 0 and r["wing_mass_kg"] > 0 and r["tip_deflection_m"] > 0
        assert np.isfinite(r["L_equals_W"])
        assert 1 <= max(r["coupled_iterations"].values()) < 25
    assert res["beam"] == "wingmdao" and res["oas_beam"]["beam"] == "oas"
    assert res["wing_mass_kg"] == pytest.approx(res["oas_beam"]["wing_mass_kg"], rel=1e-12)
    assert res["fuelburn_kg"] == pytest.approx(res["oas_beam"]["fuelburn_kg"], rel=0.01)
    # tip deflection: +8 % at num_y 9 (4 elements: our node-averaged element boxes), +1.2 % at num_y 15
    assert res["tip_deflection_m"] == pytest.approx(res["oas_beam"]["tip_deflection_m"], rel=0.12)
    assert "wingmdao size aerostruct-crm" in err


@pytest.mark.slow
def test_cli_optimisation_records_reports_and_refuses_overwrite(tmp_path, capsys):
    """Two SLSQP iterations with our beam only: the fuel burn drops, the recording reads back with
    `wingmdao report`, and a second run refuses to replace the recording and the JSON."""
    js = tmp_path / "crm.json"
    argv = ["size", "aerostruct-crm", "--num-y", NUM_Y, "--maxiter", "2", "--no-oas-beam", "--quiet",
            "--out", str(tmp_path), "--json", str(js)]
    rc, out, err = _run(argv, capsys)
    assert rc == 1   # the iteration limit: not converged
    res = json.loads(js.read_text())
    assert "oas_beam" not in res and res["success"] is False and "iteration limit" in res["message"]
    assert res["iterations"] >= 2 and res["evaluations"] >= 2
    assert res["fuelburn_kg"] < 89119.0   # the initial design at num_y 9: 89 119.6 kg
    rec = res["recording"]
    assert rec == str(tmp_path / "aerostruct_crm.sql")
    rc, out, err = _run(["report", rec, "--plots", str(tmp_path / "plots")], capsys)
    assert rc == 0 and "driver iterations" in out
    rc, out, err = _run(argv, capsys)   # refused before any solve
    assert rc == 2 and "--overwrite" in err


def test_cli_ctrl_c_writes_partial_json(tmp_path, capsys, monkeypatch):
    from wingmdao.optimize import SolverIterationCounter

    calls = {"n": 0}
    original = SolverIterationCounter.record_iteration_driver

    def interrupt_at_second(self, *a, **k):
        original(self, *a, **k)
        calls["n"] += 1
        if calls["n"] == 2:
            raise KeyboardInterrupt

    monkeypatch.setattr(SolverIterationCounter, "record_iteration_driver", interrupt_at_second)
    js = tmp_path / "crm.json"
    rc, out, err = _run(["size", "aerostruct-crm", "--num-y", NUM_Y, "--quiet", "--out", str(tmp_path),
                         "--json", str(js)], capsys)
    assert rc == 130
    res = json.loads(js.read_text())
    assert res["success"] is False and res["interrupted"] is True and "oas_beam" not in res
    assert res["fuelburn_kg"] > 0
    best = res["best_design"]
    assert best is not None and best["iteration"] >= 0 and "wing.twist_cp" in best["design_vars"]


@pytest.mark.parametrize("args, text", [(["--num-y", "8"], "--num-y = 8"), (["--maxiter", "0"], "--maxiter = 0"),
                                        (["--tol", "-1"], "--tol = -1")])
def test_cli_bad_input_is_one_line(args, text, tmp_path, capsys):
    rc, out, err = _run(["size", "aerostruct-crm", *args, "--out", str(tmp_path)], capsys)
    assert rc == 2 and text in err and "Traceback" not in err


def test_cli_without_openaerostruct_says_what_to_install(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "openaerostruct", None)
    rc, out, err = _run(["size", "aerostruct-crm", "--out", str(tmp_path)], capsys)
    assert rc == 1 and "pip install" in err and "openaerostruct" in err.lower()
    assert "Traceback" not in err


def test_cli_help_shows_defaults(capsys):
    with pytest.raises(SystemExit):
        main(["size", "aerostruct-crm", "--help"])
    out = " ".join(capsys.readouterr().out.split())  # help lines wrap at the terminal width
    assert "(default: 40)" in out and "(default: 15)" in out


def test_iteration_counter_matches_solver_iterations():
    """SolverIterationCounter (public recording hooks) counts the NonlinearBlockGS iterations as the
    solver's own counter does (its first pass runs unrecorded: unrecorded=1)."""
    from wingmdao.oas.crm import build_crm_problem, setup_crm_problem

    prob, _ = build_crm_problem("wingmdao", int(NUM_Y))
    counter = setup_crm_problem(prob)
    prob.run_model()
    counter.snapshot()
    for i, name in enumerate(("cruise", "maneuver")):
        solver = getattr(prob.model, f"AS_point_{i}").coupled.nonlinear_solver
        assert counter.last[name] == solver._iter_count > 1   # the solver's private counter, as ground truth
