"""``wingmdao gust CASE --alleviation FILE.yaml``: the file's checks (one-line errors before any
solve) and the PEGASUS example of docs/controls.md."""

import json
import os

import pytest

from wingmdao.aero.controls import alleviation_from_dict
from wingmdao.cli import main

EXAMPLE = os.path.join(os.path.dirname(__file__), "..", "docs", "examples", "pegasus_alleviation.yaml")
SURFACE = {"name": "aileron", "span": [0.7, 1.0], "hinge": 0.75, "actuator": {"order": 1, "time_constant": 0.05}}


@pytest.mark.parametrize("data, message", [
    ({"law": {}}, "missing key 'surfaces'"),
    ({"surfaces": [SURFACE], "controller": {}}, "unknown key 'controller'"),
    ({"surfaces": [{**SURFACE, "chord_ratio": 0.25}]}, r"surfaces\[0\]: unknown key 'chord_ratio'"),
    ({"surfaces": [{**SURFACE, "hinge": 1.1}]}, "hinge = 1.1 is outside the chord"),
    ({"surfaces": [{**SURFACE, "span": [0.7, 1.2]}]}, "is outside the semi-span"),
    ({"surfaces": [{**SURFACE, "actuator": {"time_constant": 0.05}}]}, r"actuator: missing key 'order'"),
    ({"surfaces": [SURFACE], "law": {"outputs": ["root_bending"], "gain": [[1.0, 2.0]]}},
     r"D has shape \(1, 2\); allowed \(1, 1\)"),
    ({"surfaces": [SURFACE], "law": {"outputs": ["root_bending"],
                                     "state_space": {"A": [[0.3]], "B": [[1.0]], "C": [[1.0]], "D": [[0.0]]}}},
     "open-loop controller is unstable"),
    ({"surfaces": [SURFACE], "law": {"outputs": ["root_bending"], "gain": [1.0], "pid": {"kp": 1.0}}},
     "exactly one of gain, pid, state_space"),
    ({"surfaces": [SURFACE], "law": {"outputs": ["wing_twist"], "gain": [1.0]}}, "output 'wing_twist' unknown"),
])
def test_alleviation_file_errors(data, message):
    with pytest.raises(ValueError, match=message):
        alleviation_from_dict(data, "--alleviation f.yaml")


def test_alleviation_forms():
    surfaces, law = alleviation_from_dict({"surfaces": [SURFACE, {**SURFACE, "name": "inboard", "span": [0.4, 0.6]}],
                                           "law": {"outputs": ["root_bending"], "pid": {"kp": -2.0, "ki": -1.0}}})
    assert len(surfaces) == 2 and law.n_states == 2 and law.D.shape == (2, 1)
    _, law = alleviation_from_dict({"surfaces": [SURFACE], "law": {"outputs": ["load_factor"], "gain": [-0.2]}})
    assert law.n_states == 0 and law.D.tolist() == [[-0.2]]


def test_cli_alleviation_errors_before_solve(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("surfaces:\n  - {name: aileron, span: [0.7, 1.0], hinge: 1.3}\n")
    assert main(["gust", "pegasus", "--alleviation", str(bad), "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert "hinge = 1.3 is outside the chord" in err and str(bad) in err and "Traceback" not in err
    assert main(["gust", "pegasus", "--alleviation", str(tmp_path / "missing.yaml"), "--no-plots"]) == 2
    assert "cannot read the file" in capsys.readouterr().err
    assert main(["gust", "pegasus", "--aero", "strip", "--clamped", "--alleviation", EXAMPLE, "--no-plots"]) == 2
    assert "needs --aero coupled" in capsys.readouterr().err
    assert main(["gust", "pegasus", "--clamped", "--alleviation", EXAMPLE, "--no-plots"]) == 2
    assert "load_factor needs free plunge" in capsys.readouterr().err


@pytest.mark.slow
def test_cli_alleviation_pegasus_example(tmp_path):
    """docs/controls.md's example as it stands: the law lowers the peak root-bending increment and
    the load factor, the result carries the surface histories and limits."""
    out = tmp_path / "g.json"
    assert main(["gust", "pegasus", "--aero-theory", "strip", "--alleviation", EXAMPLE, "--no-plots", "--json",
                 str(out)]) == 0
    res = json.loads(out.read_text())
    a = res["alleviation"]
    assert abs(a["peak_incremental_root_bending_with_law"]) < 0.6 * abs(a["peak_incremental_root_bending_without_law"])
    assert a["peak_incremental_load_factor_with_law"] < a["peak_incremental_load_factor_without_law"]
    s = a["surfaces"]["aileron"]
    assert len(s["deflection_deg"]) == len(res["time"]) == len(s["hinge_moment_n_m"])
    assert 0 < s["peak_deflection_deg"] <= s["max_deflection_deg"] and not s["rate_limit_exceeded"]
