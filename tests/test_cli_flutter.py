"""``wingmdao flutter``: bad input is rejected before any solve; the JSON of a short sweep."""

import json

import pytest

from wingmdao.cli import main
from wingmdao.cli.flutter import parse_speeds


@pytest.mark.parametrize("speeds, match", [
    (["100", "50", "5"], "increasing"),
    (["-10", "50", "5"], ">= 0"),
    (["10", "50", "1"], ">= 2"),
    (["10", "50", "0"], ">= 2"),
    (["a", "50", "3"], "numbers"),
])
def test_bad_sweep(speeds, match):
    with pytest.raises(ValueError, match=match):
        parse_speeds(speeds)


def test_bad_input_exit_code_before_solve(capsys, monkeypatch):
    import wingmdao.cli.flutter as fl

    monkeypatch.setattr(fl, "analyse", lambda *a, **k: pytest.fail("solve started"))
    assert main(["flutter", "goland", "--speeds", "100", "100", "4"]) == 2
    assert "--speeds V1 must be > V0" in capsys.readouterr().err
    assert main(["flutter", "pegasus"]) == 2
    assert "no aerodynamic" in capsys.readouterr().err


@pytest.mark.slow
def test_flutter_json_goland(tmp_path, capsys):
    out = tmp_path / "f.json"
    assert main(["flutter", "goland", "--speeds", "100", "280", "4", "--num-nodes", "11",
                 "--json", str(out), "--out", str(tmp_path)]) == 0
    d = json.loads(out.read_text())
    for key in ("flutter_speed_m_s", "flutter_frequency_rad_s", "divergence_speed_m_s",
                "natural_frequencies_rad_s", "speeds", "damping", "frequency_rad_s"):
        assert key in d
    assert len(d["natural_frequencies_rad_s"]) == 6
    assert d["flutter_speed_m_s"] == pytest.approx(137.2, rel=0.02)
    assert (tmp_path / "flutter_goland.png").exists()
