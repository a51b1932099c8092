"""Envelope output on hand-built load histories: critical case per station, max/min envelopes over
cases and time, the convex hull of the potato plot, and the files (CSV, NPZ round trip, PNGs)."""

import json

import numpy as np
import pytest

from wingmdao import envelope as env


def _data():
    n = 3
    span = np.array([0.0, 1.0, 2.0])
    t = np.array([0.0, 0.1, 0.2])
    # case "a": static; case "b": 3 steps
    F_a = np.zeros((1, n, 3)); F_a[0, :, 2] = [10.0, 5.0, 0.0]
    M_a = np.zeros((1, n, 3)); M_a[0, :, 0] = [100.0, 20.0, 0.0]; M_a[0, :, 1] = [1.0, 1.0, 0.0]
    F_b = np.zeros((3, n, 3)); F_b[:, 0, 2] = [0.0, 12.0, -4.0]; F_b[:, 1, 2] = [0.0, 3.0, -1.0]
    M_b = np.zeros((3, n, 3)); M_b[:, 0, 0] = [0.0, 80.0, -50.0]; M_b[:, 1, 0] = [0.0, 30.0, -5.0]
    M_b[:, 0, 1] = [0.0, 4.0, -2.0]
    g_a = np.array([[0.0, -0.5, -1.0]])
    g_b = np.array([[-1.0, -1.0, -1.0], [-0.2, -0.1, -1.0], [-0.3, -0.4, -1.0]])
    return {"case_names": np.array(["a", "b"]), "span": span,
            "F__a": F_a, "M__a": M_a, "g__a": g_a, "t__a": np.zeros(1),
            "F__b": F_b, "M__b": M_b, "g__b": g_b, "t__b": t}


def test_critical_case_per_station():
    rows = env.critical_cases(_data())
    assert [r["case"] for r in rows] == ["a", "b", "a"]  # last station: tie at -1, first case kept
    assert rows[1]["g_max"] == pytest.approx(-0.1) and rows[1]["time_s"] == pytest.approx(0.1)


def test_envelopes():
    e = env.envelope(_data())
    assert np.allclose(e["shear"]["max"], [12.0, 5.0, 0.0]) and np.allclose(e["shear"]["min"], [-4.0, -1.0, 0.0])
    assert e["shear"]["max_case"][:2] == ["b", "a"]
    assert np.allclose(e["bending"]["max"], [100.0, 30.0, 0.0]) and np.allclose(e["bending"]["min"], [-50.0, -5.0, 0.0])
    assert np.allclose(e["torsion"]["max"], [4.0, 1.0, 0.0]) and e["torsion"]["min_case"][0] == "b"


def test_hull_of_square_with_interior_points():
    pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5], [0.2, 0.7]])
    hull = env._hull(pts)
    assert np.allclose(hull[0], hull[-1]) and len(hull) == 5
    assert {tuple(p) for p in hull[:-1]} == {(0, 0), (1, 0), (1, 1), (0, 1)}


def test_files_round_trip(tmp_path):
    pytest.importorskip("matplotlib")
    data = _data()
    path = env.save(data, str(tmp_path / "run_envelope.npz"))
    back = env.load(path)
    assert [str(s) for s in back["case_names"]] == ["a", "b"] and np.array_equal(back["M__b"], data["M__b"])
    paths = env.write_plots(back, str(tmp_path / "run"), stations=[0, 1])
    assert all((tmp_path / p.split("/")[-1]).exists() for p in paths) and len(paths) == 4
    assert (tmp_path / "run_critical_cases.csv").read_text().splitlines()[2].startswith("1,1,b,")
    with pytest.raises(ValueError, match="--potato-stations 7: station indices; allowed range"):
        env.write_plots(back, str(tmp_path / "run"), stations=[7])
    with pytest.raises(ValueError, match="does not exist"):
        env.load(str(tmp_path / "missing.npz"))


def test_turbulence_ellipse_on_the_potato_plots(tmp_path):
    """25.341(b) loads added to the envelope data: at a station the ellipse spans 1 g +/- U_sigma
    A-bar in each load, its correlated design points lie on it (AC 25.341-1 tangent points), the
    keys survive the NPZ round trip and the potato plot draws them."""
    pytest.importorskip("matplotlib")
    data = env.add_turbulence(_data(), {
        "u_sigma_m_s": 20.0, "bending_moment": {"one_g": [50.0, 10.0, 0.0], "a_bar": [2.0, 1.0, 0.0]},
        "torsion": {"one_g": [3.0, 1.0, 0.0], "a_bar": [0.5, 0.2, 0.0]}, "bending_torsion_correlation": [0.6, 0.3, 0.0]})
    back = env.load(env.save(data, str(tmp_path / "run_envelope.npz")))
    ellipse, design = env.turbulence_ellipse(back, 0)
    # (M_s, M_c): x = 3 +/- 20 * 0.5, y = 50 +/- 20 * 2
    assert ellipse[:, 0].max() == pytest.approx(13.0) and ellipse[:, 0].min() == pytest.approx(-7.0)
    assert ellipse[:, 1].max() == pytest.approx(90.0, rel=1e-3) and ellipse[:, 1].min() == pytest.approx(10.0, rel=1e-2)
    # on the ellipse: ((x - px)/ax)^2 - 2 rho (x - px)/ax (y - py)/ay + ((y - py)/ay)^2 = 1 - rho^2
    u, v, rho = (design[:, 0] - 3.0) / 10.0, (design[:, 1] - 50.0) / 40.0, 0.6
    np.testing.assert_allclose(u ** 2 - 2 * rho * u * v + v ** 2, 1 - rho ** 2, rtol=1e-12)
    assert env.turbulence_ellipse(_data(), 0) == (None, None)
    paths = env.write_plots(back, str(tmp_path / "run"), stations=[0, 1])
    assert any(p.endswith("_potato.png") for p in paths)


@pytest.mark.slow
def test_size_and_report_write_envelope_outputs(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    from wingmdao.cli import main

    out = tmp_path / "r"
    rc = main(["size", "pegasus", "--gust-gradients-ft", "60", "--t-final", "0.4", "--dt", "0.04",
               "--maxiter", "1", "--presize", "0", "--quiet", "--out", str(out), "--potato-stations", "1", "10"])
    assert rc in (0, 1)
    for name in ("critical_case.png", "envelope.png", "potato.png", "critical_cases.csv", "envelope.npz"):
        assert (out / f"pegasus_{name}").exists(), name
    cap = capsys.readouterr()
    assert "critical load case per station" in cap.err  # human text: standard error (JSON on stdout)
    assert "critical_cases" in json.loads(cap.out)
    assert main(["report", str(out / "pegasus.sql"), "--out", str(tmp_path / "rep")]) == 0
    assert (tmp_path / "rep" / "envelope_potato.png").exists()
