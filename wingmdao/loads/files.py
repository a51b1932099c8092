"""Load time histories on the beam mesh: container, validation, NPZ and CSV files.

Formats (see ``docs/loads.md``):

* NPZ: arrays ``time`` (n_time,) s, ``force_per_length`` (n_time, n_node, 3) N/m and
  ``moment_per_length`` (n_time, n_node, 3) N m/m, body axes, per unit beam-axis length.
* CSV, long format, one row per (time, node), header exactly::

      time_s,node,fx_N_per_m,fy_N_per_m,fz_N_per_m,mx_Nm_per_m,my_Nm_per_m,mz_Nm_per_m

  rows in any order; every time must list every node 0..n_node-1 once (as exported from
  a Nastran SOL 146 run by a post-processing script). Lines starting with ``#`` are comments.

Time must start at 0 and increase strictly; no value may be NaN or infinite.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
import zipfile
from pathlib import Path

import numpy as np

CSV_COLUMNS = (
    "time_s", "node",
    "fx_N_per_m", "fy_N_per_m", "fz_N_per_m",
    "mx_Nm_per_m", "my_Nm_per_m", "mz_Nm_per_m",
)
TIME_ZERO_TOL = 1e-12  # s


@dataclass
class LoadHistory:
    """Distributed loads on the beam nodes over time (body axes, per unit beam length).

    Parameters
    ----------
    time : numpy.ndarray
        (n_time,) times from 0, increasing (s).
    force_per_length : numpy.ndarray
        (n_time, n_node, 3) force per unit beam length (N/m).
    moment_per_length : numpy.ndarray
        (n_time, n_node, 3) moment per unit beam length (N m/m).
    """

    time: np.ndarray  # (n_time,) s, time[0] = 0
    force_per_length: np.ndarray  # (n_time, n_node, 3) N/m
    moment_per_length: np.ndarray  # (n_time, n_node, 3) N m/m

    def __post_init__(self):
        self.time = np.asarray(self.time, dtype=float)
        self.force_per_length = np.asarray(self.force_per_length, dtype=float)
        self.moment_per_length = np.asarray(self.moment_per_length, dtype=float)
        validate_load_history(self.time, self.force_per_length, self.moment_per_length)

    @property
    def num_times(self) -> int:
        return self.time.size

    @property
    def num_nodes(self) -> int:
        return self.force_per_length.shape[1]

    def resample(self, new_time) -> LoadHistory:
        """Linear interpolation onto another time grid inside [0, time[-1]] (e.g. the beam's).

        Parameters
        ----------
        new_time : array_like
            Times inside [0, time[-1]] (s).

        Returns
        -------
        LoadHistory
            The interpolated history.
        """
        t = np.asarray(new_time, dtype=float)
        zeros = np.zeros((t.size, 1, 3))
        validate_load_history(t, zeros, zeros, source="new_time")
        if t[-1] > self.time[-1] * (1.0 + 1e-12):
            raise ValueError(
                f"new_time[-1] = {t[-1]} s; allowed range [0, {self.time[-1]}] s (the recorded history)"
            )

        def interp(arr):
            flat = arr.reshape(self.num_times, -1)
            out = np.column_stack([np.interp(t, self.time, flat[:, j]) for j in range(flat.shape[1])])
            return out.reshape((t.size,) + arr.shape[1:])

        return LoadHistory(t, interp(self.force_per_length), interp(self.moment_per_length))

    def as_forcing(self) -> dict:
        """``{"force_per_length": ..., "moment_per_length": ...}`` for a beam load case."""
        return {"force_per_length": self.force_per_length.copy(), "moment_per_length": self.moment_per_length.copy()}


def validate_load_history(time, force_per_length, moment_per_length, source: str = "") -> None:
    """Raise ``ValueError`` on wrong shapes, non-finite values or a bad time axis.

    Parameters
    ----------
    time : array_like
        (n_time,) times (s).
    force_per_length : array_like
        (n_time, n_node, 3) forces per length (N/m).
    moment_per_length : array_like
        (n_time, n_node, 3) moments per length (N m/m).
    source : str, optional
        File or input named in the error.
    """
    where = f"{source}: " if source else ""
    if time.ndim != 1 or time.size < 1:
        raise ValueError(f"{where}time: shape {time.shape}; expected (n_time >= 1,) s")
    n_t = time.size
    for name, arr in (("force_per_length", force_per_length), ("moment_per_length", moment_per_length)):
        if arr.ndim != 3 or arr.shape[0] != n_t or arr.shape[2] != 3 or arr.shape[1] < 1:
            raise ValueError(f"{where}{name}: shape {arr.shape}; expected (n_time={n_t}, n_node, 3)")
    if force_per_length.shape != moment_per_length.shape:
        raise ValueError(
            f"{where}force_per_length {force_per_length.shape} and moment_per_length "
            f"{moment_per_length.shape} must have the same shape"
        )
    for name, arr in (("time", time), ("force_per_length", force_per_length), ("moment_per_length", moment_per_length)):
        bad = ~np.isfinite(arr)
        if np.any(bad):
            idx = tuple(int(i) for i in np.unravel_index(int(np.flatnonzero(bad)[0]), arr.shape))
            raise ValueError(f"{where}{name}: non-finite value at index {idx}")
    if abs(time[0]) > TIME_ZERO_TOL:
        raise ValueError(f"{where}time[0] = {time[0]} s; time histories must start at 0 s")
    bad = np.flatnonzero(np.diff(time) <= 0.0)
    if bad.size:
        i = int(bad[0]) + 1
        raise ValueError(
            f"{where}time[{i}] = {time[i]} s is not greater than time[{i - 1}] = {time[i - 1]} s; "
            "time must increase strictly"
        )


# --------------------------------------------------------------------------- NPZ
def write_npz(history: LoadHistory, path) -> None:
    """Write a :class:`LoadHistory` to an ``.npz`` file.

    Parameters
    ----------
    history : LoadHistory
        The load history.
    path : str or path-like
        File to write.
    """
    np.savez(
        path, time=history.time, force_per_length=history.force_per_length,
        moment_per_length=history.moment_per_length,
    )


def read_npz(path) -> LoadHistory:
    """Read and validate an ``.npz`` load history.

    Parameters
    ----------
    path : str or path-like
        File to read.

    Returns
    -------
    LoadHistory
        The validated history.
    """
    try:
        data = np.load(path, allow_pickle=False)
    except FileNotFoundError:
        raise ValueError(f"load history {path}: no such file") from None
    except (EOFError, OSError, ValueError, zipfile.BadZipFile) as exc:
        raise ValueError(f"load history {path}: not a readable .npz archive (empty or truncated?): {exc}") from None
    if not hasattr(data, "files"):
        raise ValueError(f"load history {path}: a single .npy array, not an .npz archive")
    with data:
        missing = [k for k in ("time", "force_per_length", "moment_per_length") if k not in data]
        if missing:
            raise ValueError(f"{path}: missing array(s) {missing}; expected time, force_per_length, moment_per_length")
        try:
            arrays = [np.asarray(data[k], dtype=float) for k in ("time", "force_per_length", "moment_per_length")]
        except (EOFError, OSError, ValueError, zipfile.BadZipFile) as exc:
            raise ValueError(f"load history {path}: an array cannot be read (truncated?): {exc}") from None
    validate_load_history(*arrays, source=str(path))
    return LoadHistory(*arrays)


# --------------------------------------------------------------------------- CSV
def write_csv(history: LoadHistory, path) -> None:
    """Write a :class:`LoadHistory` as long-format CSV (one row per time and node).

    Parameters
    ----------
    history : LoadHistory
        The load history.
    path : str or path-like
        File to write.
    """
    n_t, n_n = history.num_times, history.num_nodes
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(CSV_COLUMNS)
        for k in range(n_t):
            for i in range(n_n):
                f = history.force_per_length[k, i]
                m = history.moment_per_length[k, i]
                writer.writerow([repr(float(history.time[k])), i, *(repr(float(v)) for v in (*f, *m))])


def _parse_csv_rows(path):
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:  # a byte-order mark is tolerated
            lines = [ln for ln in fh if ln.strip() and not ln.lstrip().startswith("#")]
    except FileNotFoundError:
        raise ValueError(f"load history {path}: no such file") from None
    except UnicodeDecodeError as exc:
        raise ValueError(f"load history {path}: not a UTF-8 text CSV ({exc})") from None
    if not lines:
        raise ValueError(f"{path}: empty file; expected header {','.join(CSV_COLUMNS)}")
    reader = csv.reader(lines)
    header = [h.strip() for h in next(reader)]
    if tuple(header) != CSV_COLUMNS:
        raise ValueError(f"{path}: header {','.join(header)}; expected {','.join(CSV_COLUMNS)}")
    rows = []
    for line_no, row in enumerate(reader, start=2):
        if len(row) != len(CSV_COLUMNS):
            raise ValueError(f"{path}: data row {line_no} has {len(row)} fields; expected {len(CSV_COLUMNS)}")
        try:
            rows.append([float(v) for v in row])
        except ValueError:
            raise ValueError(f"{path}: data row {line_no} has a non-numeric field: {row}") from None
    if not rows:
        raise ValueError(f"{path}: no data rows")
    return np.array(rows)


def read_csv(path) -> LoadHistory:
    """Read and validate a long-format CSV load history.

    Parameters
    ----------
    path : str or path-like
        File to read.

    Returns
    -------
    LoadHistory
        The validated history.
    """
    data = _parse_csv_rows(path)
    times = np.unique(data[:, 0])
    nodes = data[:, 1]
    if np.any(nodes != np.round(nodes)) or np.any(nodes < 0):
        i = int(np.flatnonzero((nodes != np.round(nodes)) | (nodes < 0))[0])
        raise ValueError(f"{path}: node = {nodes[i]} in data row {i + 2}; nodes are integers 0..n_node-1")
    nodes = nodes.astype(int)
    n_node = int(nodes.max()) + 1
    n_t = times.size
    if data.shape[0] != n_t * n_node:
        raise ValueError(
            f"{path}: {data.shape[0]} data rows for {n_t} times x {n_node} nodes; "
            "every time must list every node 0..n_node-1 exactly once"
        )
    t_index = np.searchsorted(times, data[:, 0])
    seen = np.zeros((n_t, n_node), dtype=int)
    np.add.at(seen, (t_index, nodes), 1)
    if np.any(seen != 1):
        k, i = (int(v) for v in np.argwhere(seen != 1)[0])
        raise ValueError(
            f"{path}: time {times[k]} s, node {i} appears {seen[k, i]} times; expected exactly once"
        )
    force = np.empty((n_t, n_node, 3))
    moment = np.empty((n_t, n_node, 3))
    force[t_index, nodes] = data[:, 2:5]
    moment[t_index, nodes] = data[:, 5:8]
    validate_load_history(times, force, moment, source=str(path))
    return LoadHistory(times, force, moment)


# --------------------------------------------------------------------------- dispatch
def read_load_history(path) -> LoadHistory:
    """Read a load history from ``.npz`` or ``.csv`` (by file suffix).

    Parameters
    ----------
    path : str or path-like
        ``.npz`` or ``.csv`` file.

    Returns
    -------
    LoadHistory
        The validated history.
    """
    suffix = Path(path).suffix.lower()
    if suffix == ".npz":
        return read_npz(path)
    if suffix == ".csv":
        return read_csv(path)
    raise ValueError(f"{path}: unknown load-history file type '{suffix}'; allowed .npz or .csv")


def write_load_history(history: LoadHistory, path) -> None:
    """Write a load history to ``.npz`` or ``.csv`` (by file suffix).

    Parameters
    ----------
    history : LoadHistory
        The load history.
    path : str or path-like
        ``.npz`` or ``.csv`` file.
    """
    suffix = Path(path).suffix.lower()
    if suffix == ".npz":
        write_npz(history, path)
    elif suffix == ".csv":
        write_csv(history, path)
    else:
        raise ValueError(f"{path}: unknown load-history file type '{suffix}'; allowed .npz or .csv")
