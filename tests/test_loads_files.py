"""Load-history files: NPZ/CSV round trips and validation."""

import numpy as np
import pytest

from wingmdao.loads.files import (
    CSV_COLUMNS, LoadHistory, read_load_history, write_load_history,
)


def _history(n_t=5, n_n=4, seed=0):
    rng = np.random.default_rng(seed)
    time = np.concatenate([[0.0], np.cumsum(rng.uniform(0.01, 0.05, n_t - 1))])
    return LoadHistory(time, rng.normal(0, 1e3, (n_t, n_n, 3)), rng.normal(0, 1e2, (n_t, n_n, 3)))


@pytest.mark.parametrize("suffix", [".npz", ".csv"])
def test_round_trip_exact(tmp_path, suffix):
    h = _history()
    path = tmp_path / f"loads{suffix}"
    write_load_history(h, path)
    back = read_load_history(path)
    np.testing.assert_array_equal(back.time, h.time)
    np.testing.assert_array_equal(back.force_per_length, h.force_per_length)
    np.testing.assert_array_equal(back.moment_per_length, h.moment_per_length)


def test_csv_hand_written_rows_any_order_and_comments(tmp_path):
    text = "# exported from SOL 146\n" + ",".join(CSV_COLUMNS) + "\n" + "\n".join(
        [
            "0.1,1,0,0,12.5,0,-3,0",
            "0.0,0,0,0,10,0,-2,0",
            "0.1,0,0,0,11,0,-2.5,0",
            "0.0,1,0,0,9.5,0,-1,0",
        ]
    ) + "\n"
    path = tmp_path / "h.csv"
    path.write_text(text)
    h = read_load_history(path)
    np.testing.assert_array_equal(h.time, [0.0, 0.1])
    np.testing.assert_array_equal(h.force_per_length[:, :, 2], [[10, 9.5], [11, 12.5]])
    np.testing.assert_array_equal(h.moment_per_length[:, :, 1], [[-2, -1], [-2.5, -3]])


def test_validation_messages(tmp_path):
    h = _history()
    with pytest.raises(ValueError, match=r"time\[0\].*start at 0"):
        LoadHistory(h.time + 0.1, h.force_per_length, h.moment_per_length)
    t = h.time.copy()
    t[3] = t[2]
    with pytest.raises(ValueError, match=r"time\[3\].*increase strictly"):
        LoadHistory(t, h.force_per_length, h.moment_per_length)
    f = h.force_per_length.copy()
    f[2, 1, 0] = np.nan
    with pytest.raises(ValueError, match=r"force_per_length: non-finite value at index \(2, 1, 0\)"):
        LoadHistory(h.time, f, h.moment_per_length)
    with pytest.raises(ValueError, match=r"moment_per_length: shape"):
        LoadHistory(h.time, h.force_per_length, h.moment_per_length[:, :, :2])
    path = tmp_path / "bad.csv"
    path.write_text(",".join(CSV_COLUMNS) + "\n0,0,0,0,1,0,0,0\n0,1,0,0,1,0,0,0\n0.1,0,0,0,1,0,0,0\n")
    with pytest.raises(ValueError, match="every node"):
        read_load_history(path)
    path.write_text("t,node\n0,0\n")
    with pytest.raises(ValueError, match="header"):
        read_load_history(path)
    path.write_text(",".join(CSV_COLUMNS) + "\n0,0,0,0,nan,0,0,0\n")
    with pytest.raises(ValueError, match="non-finite"):
        read_load_history(path)
    with pytest.raises(ValueError, match=".npz or .csv"):
        read_load_history(tmp_path / "x.txt")
    np.savez(tmp_path / "m.npz", time=h.time)
    with pytest.raises(ValueError, match="missing"):
        read_load_history(tmp_path / "m.npz")


def test_resample_linear_and_as_forcing():
    time = np.array([0.0, 1.0, 3.0])
    f = np.zeros((3, 2, 3))
    f[:, 1, 2] = [0.0, 10.0, 30.0]  # linear in time: 10 N/m per s
    h = LoadHistory(time, f, -f)
    r = h.resample(np.linspace(0.0, 3.0, 7))
    np.testing.assert_allclose(r.force_per_length[:, 1, 2], 10.0 * np.linspace(0.0, 3.0, 7), rtol=1e-14)
    np.testing.assert_allclose(r.moment_per_length, -r.force_per_length)
    forcing = h.as_forcing()
    assert set(forcing) == {"force_per_length", "moment_per_length"}
    with pytest.raises(ValueError, match=r"new_time\[-1\] = 4.0 s; allowed range \[0, 3.0\] s"):
        h.resample([0.0, 4.0])
