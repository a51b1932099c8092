"""The loads database of a matrix run: every case's monitoring-station loads in one HDF5 file.

Why HDF5 (h5py) rather than Parquet: the loads are n-dimensional arrays (case x station x
component, snapshots x station x component) that HDF5 stores as they are, with units and
descriptions as attributes on each dataset, readable from Python, MATLAB, Fortran and C
(``h5dump`` prints it all); a Parquet file is a table and would flatten them into long columns
with the layout kept outside the file. The case table, which is a table, is a structured
(compound) dataset.

Layout (docs/loads-matrix.md; every dataset has ``units`` and ``description`` attributes)::

    /                      attrs: format, format_version, case, status (complete | interrupted),
                                  wingmdao_version, model, matrix_file (the YAML text),
                                  components, component_units
    /cases                 (n_case,) compound: the case table (index, name, kind, altitude_ft,
                           speed, mass, mach, airspeed_tas_m_s, airspeed_eas_m_s, weight_n, cg_mac,
                           fuel_fraction, gradient_ft, sign, load_factor, intensity_m_s, evaluated)
    /stations/node_positions, /stations/node_euler_angles   (n, 3) jig beam nodes (m, rad)
    /loads/max, /loads/min            (n_case, n, 6) extremes per case, station, csn component
    /loads/max_snapshot, /loads/min_snapshot   (n_case, n, 6) index into /snapshots (-1: not run)
    /snapshots/loads       (k, n, 6) the wing's loads at the instant of an extreme
    /snapshots/time_s      (k,) that instant (NaN for turbulence and maneuvers)
    /snapshots/case        (k,) its case index
    /screening/envelope_max, /screening/envelope_min   (n, 6)
    /screening/max_case, /screening/min_case           (n, 6) critical case index
    /run                   attrs: wall_time_s, ranks; /run/case_wall_s (n_case,)

The file is written to a temporary name in the same folder and renamed (atomic). ``/run`` holds
what differs between runs of the same matrix (timings, rank count); :func:`differences` ignores it.
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass, field, fields

import numpy as np

from wingmdao.loads.matrix import build_wing_model, evaluate_cases, expand
from wingmdao import __version__
from wingmdao.loads.matrix import COMPONENT_UNITS, COMPONENTS, flight_state, screen

FORMAT = "wingmdao loads database"
FORMAT_VERSION = 1
STATUSES = ("complete", "interrupted")

CASE_DTYPE = np.dtype([
    ("index", "<i8"), ("name", "S96"), ("kind", "S16"), ("altitude_ft", "<f8"), ("speed", "S8"), ("mass", "S48"),
    ("mach", "<f8"), ("airspeed_tas_m_s", "<f8"), ("airspeed_eas_m_s", "<f8"), ("weight_n", "<f8"),
    ("cg_mac", "<f8"), ("fuel_fraction", "<f8"), ("gradient_ft", "<f8"), ("sign", "<i8"), ("load_factor", "<f8"),
    ("intensity_m_s", "<f8"), ("evaluated", "?")])
CASE_FIELDS = {  # field: (units, description)
    "index": ("", "position in the table"), "name": ("", "case name"),
    "kind": ("", "gust (25.341(a)), turbulence (25.341(b)) or maneuver (25.337)"),
    "altitude_ft": ("ft", "altitude"), "speed": ("", "V_C or V_D"), "mass": ("", "mass case name"),
    "mach": ("", "Mach number"), "airspeed_tas_m_s": ("m/s", "true airspeed"),
    "airspeed_eas_m_s": ("m/s", "equivalent airspeed"), "weight_n": ("N", "aircraft weight"),
    "cg_mac": ("", "CG, fraction of the mean aerodynamic chord"), "fuel_fraction": ("", "wing fuel / capacity"),
    "gradient_ft": ("ft", "gust gradient H (NaN: not a gust)"), "sign": ("", "+1 up gust, -1 down, 0 not a gust"),
    "load_factor": ("", "maneuver load factor (NaN: not a maneuver)"),
    "intensity_m_s": ("m/s", "U_ds (EAS) of a gust, U_sigma (TAS) of turbulence, NaN for a maneuver"),
    "evaluated": ("", "false: not run (an interrupted run)")}

_DATASETS = {  # attribute: (path, units, description)
    "node_positions": ("stations/node_positions", "m", "jig beam node positions, body axes (x aft, y out, z up)"),
    "node_euler_angles": ("stations/node_euler_angles", "rad", "jig Euler angles of the csn frames (surface sequence)"),
    "loads_max": ("loads/max", "N, N m", "largest value of each internal load over the case (csn frame)"),
    "loads_min": ("loads/min", "N, N m", "smallest value of each internal load over the case (csn frame)"),
    "max_snapshot": ("loads/max_snapshot", "", "row of snapshots/loads at the instant of loads/max (-1: not run)"),
    "min_snapshot": ("loads/min_snapshot", "", "row of snapshots/loads at the instant of loads/min (-1: not run)"),
    "snapshots": ("snapshots/loads", "N, N m", "internal loads of every station at the instant of an extreme "
                                              "(turbulence: correlated loads about 1 g)"),
    "snapshot_time": ("snapshots/time_s", "s", "time of the snapshot (NaN: turbulence or maneuver)"),
    "snapshot_case": ("snapshots/case", "", "case index of the snapshot"),
    "envelope_max": ("screening/envelope_max", "N, N m", "largest value over all evaluated cases"),
    "envelope_min": ("screening/envelope_min", "N, N m", "smallest value over all evaluated cases"),
    "max_case": ("screening/max_case", "", "case index of envelope_max (the critical case)"),
    "min_case": ("screening/min_case", "", "case index of envelope_min (the critical case)"),
}


@dataclass
class LoadsDatabase:
    """A loads database in memory (the arrays of the module docstring's layout).

    Parameters
    ----------
    case : str
        Case name (e.g. ``"pegasus"``).
    status : {"complete", "interrupted"}
        Whether every case ran.
    model : str
        Description of the loads model.
    matrix_file : str
        Text of the matrix YAML file.
    cases : numpy.ndarray
        (n_case,) case table, :data:`CASE_DTYPE`.
    node_positions, node_euler_angles : numpy.ndarray
        (n, 3) jig beam nodes (m) and their Euler angles (rad).
    loads_max, loads_min : numpy.ndarray
        (n_case, n, 6) extremes per case, station and csn component (N, N m).
    max_snapshot, min_snapshot : numpy.ndarray
        (n_case, n, 6) rows of ``snapshots`` at those extremes (-1: not run).
    snapshots : numpy.ndarray
        (k, n, 6) the wing's loads at the instant of an extreme (N, N m).
    snapshot_time : numpy.ndarray
        (k,) time of each snapshot (s; NaN for turbulence and maneuvers).
    snapshot_case : numpy.ndarray
        (k,) case index of each snapshot.
    envelope_max, envelope_min : numpy.ndarray
        (n, 6) envelope over the evaluated cases (N, N m).
    max_case, min_case : numpy.ndarray
        (n, 6) critical case index of the envelope.
    run : dict, optional
        Run record (wall times, ranks).
    """

    case: str
    status: str
    model: str
    matrix_file: str
    cases: np.ndarray
    node_positions: np.ndarray
    node_euler_angles: np.ndarray
    loads_max: np.ndarray
    loads_min: np.ndarray
    max_snapshot: np.ndarray
    min_snapshot: np.ndarray
    snapshots: np.ndarray
    snapshot_time: np.ndarray
    snapshot_case: np.ndarray
    envelope_max: np.ndarray
    envelope_min: np.ndarray
    max_case: np.ndarray
    min_case: np.ndarray
    run: dict = field(default_factory=dict)  # wall_time_s, ranks, case_wall_s

    @property
    def case_names(self) -> list:
        return [n.decode() for n in self.cases["name"]]

    def snapshot(self, case_index: int, station: int, component: str, extreme: str) -> np.ndarray:
        """(n, 6) loads of the wing at the instant case ``case_index`` reaches its ``extreme``
        (``"max"``/``"min"``) of ``component`` at ``station``.

        Parameters
        ----------
        case_index : int
            Case index.
        station : int
            Station (node) index.
        component : str
            csn load component name.
        extreme : {"max", "min"}
            Which extreme.

        Returns
        -------
        numpy.ndarray
            (n, 6) loads (N, N m).
        """
        j = COMPONENTS.index(component)
        k = (self.max_snapshot if extreme == "max" else self.min_snapshot)[case_index, station, j]
        if k < 0:
            raise ValueError(f"case {case_index} was not evaluated")
        return self.snapshots[k]


def _case_row(module, matrix, case, result):
    speed = next(s for s in matrix.speeds if s.label == case.speed)
    mass = next(m for m in matrix.mass_cases if m.name == case.mass)
    fs = flight_state(module, case.altitude_ft, speed)
    return (case.index, case.name.encode(), case.kind.encode(), case.altitude_ft, case.speed.encode(),
            case.mass.encode(), fs.mach, fs.airspeed, fs.eas, mass.weight_n, mass.cg_mac, mass.fuel_fraction,
            case.gradient_ft, case.sign, case.load_factor, np.nan if result is None else result.intensity,
            result is not None)


def assemble(module, model, cases, results: dict, *, case: str, interrupted=False, wall_time_s=0.0,
             ranks=1) -> LoadsDatabase:
    """The database of a run: ``results`` {case index: CaseLoads} of the ``cases`` that ran
    (:func:`wingmdao.loads.matrix.evaluate_cases`), screened over those.

    Parameters
    ----------
    module : module
        The case module.
    model : WingModel
        The matrix's wing model.
    cases : sequence of MatrixCase
        The expanded cases.
    results : dict
        Case index -> CaseLoads of the cases that ran.
    case : str
        Case name.
    interrupted : bool, optional
        Whether the run was interrupted.
    wall_time_s : float, optional
        Wall time of the run (s).
    ranks : int, optional
        MPI ranks of the run.

    Returns
    -------
    LoadsDatabase
        The database.
    """
    matrix = model.matrix
    n, nc = model.num_nodes, len(cases)
    table = np.array([_case_row(module, matrix, c, results.get(c.index)) for c in cases], dtype=CASE_DTYPE)
    hi, lo = np.full((nc, n, 6), np.nan), np.full((nc, n, 6), np.nan)
    i_hi, i_lo = np.full((nc, n, 6), -1, np.int64), np.full((nc, n, 6), -1, np.int64)
    snaps, times, owner, wall = [], [], [], np.full(nc, np.nan)
    k = 0
    for c in cases:
        r = results.get(c.index)
        if r is None:
            continue
        hi[c.index], lo[c.index] = r.max, r.min
        i_hi[c.index], i_lo[c.index] = k + r.max_snapshot, k + r.min_snapshot
        snaps.append(r.snapshots)
        times.append(r.snapshot_time)
        owner.append(np.full(r.snapshots.shape[0], c.index, np.int64))
        wall[c.index] = r.wall_s
        k += r.snapshots.shape[0]
    sc = screen(hi, lo, table["evaluated"])
    desc = (f"{matrix.model['aero']} aero, {matrix.model['plunge']} root, {n} nodes, dt {matrix.model['dt_s']:g} s, "
            f"structural damping {matrix.model['damping_ratio']:g}")
    return LoadsDatabase(
        case=case, status="interrupted" if interrupted else "complete", model=desc, matrix_file=matrix.source,
        cases=table, node_positions=np.asarray(model.node_positions, float),
        node_euler_angles=np.asarray(model.node_euler_angles, float), loads_max=hi, loads_min=lo,
        max_snapshot=i_hi, min_snapshot=i_lo,
        snapshots=np.concatenate(snaps) if snaps else np.zeros((0, n, 6)),
        snapshot_time=np.concatenate(times) if times else np.zeros(0),
        snapshot_case=np.concatenate(owner) if owner else np.zeros(0, np.int64),
        envelope_max=sc.envelope_max, envelope_min=sc.envelope_min, max_case=sc.max_case, min_case=sc.min_case,
        run={"wall_time_s": float(wall_time_s), "ranks": int(ranks), "case_wall_s": wall})


def _h5py():
    try:
        import h5py
    except ImportError as exc:  # pragma: no cover - depends on the install
        raise ImportError("the loads database needs h5py: pip install 'wingmdao[loads]'") from exc
    return h5py


def write_database(db: LoadsDatabase, path: str) -> str:
    """Write ``db`` to ``path`` (HDF5) atomically: a temporary file in the same folder, then a rename.

    Parameters
    ----------
    db : LoadsDatabase
        The loads database.
    path : str
        HDF5 file to write.

    Returns
    -------
    str
        The path written.
    """
    h5py = _h5py()

    if db.status not in STATUSES:
        raise ValueError(f"status = {db.status!r}; allowed {STATUSES}")
    tmp = os.path.join(os.path.dirname(os.path.abspath(path)), f".{os.path.basename(path)}.tmp")
    try:
        with h5py.File(tmp, "w") as f:
            f.attrs.update({"format": FORMAT, "format_version": FORMAT_VERSION, "case": db.case, "status": db.status,
                            "wingmdao_version": __version__, "model": db.model, "matrix_file": db.matrix_file,
                            "components": list(COMPONENTS), "component_units": list(COMPONENT_UNITS),
                            "frame": "csn of each station: c chordwise, s along the beam, n normal"})
            d = f.create_dataset("cases", data=db.cases)
            d.attrs["description"] = "the load cases of the matrix, one row each"
            d.attrs["units"] = [CASE_FIELDS[k][0] for k in CASE_DTYPE.names]
            d.attrs["field_descriptions"] = [CASE_FIELDS[k][1] for k in CASE_DTYPE.names]
            for attr, (where, units, text) in _DATASETS.items():
                d = f.create_dataset(where, data=getattr(db, attr), compression="gzip", shuffle=True)
                d.attrs["units"] = units
                d.attrs["description"] = text
            run = f.create_group("run")
            run.attrs["wall_time_s"] = db.run.get("wall_time_s", 0.0)
            run.attrs["ranks"] = db.run.get("ranks", 1)
            run.attrs["description"] = "what differs between runs of the same matrix"
            d = run.create_dataset("case_wall_s", data=np.asarray(db.run.get("case_wall_s", np.zeros(len(db.cases)))))
            d.attrs["units"] = "s"
            d.attrs["description"] = "wall time of each case on its rank (NaN: not run)"
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    return path


def read_database(path: str) -> LoadsDatabase:
    """Read a database written by :func:`write_database`; ValueError for a file that is not one.

    Parameters
    ----------
    path : str
        HDF5 file written by :func:`write_database`.

    Returns
    -------
    LoadsDatabase
        The database.
    """
    h5py = _h5py()

    if not os.path.isfile(path):
        raise ValueError(f"loads database {path!r} does not exist")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise ValueError(f"loads database {path!r}: not an HDF5 file ({exc})") from None
    with f:
        if f.attrs.get("format") != FORMAT:
            raise ValueError(f"{path!r} is not a {FORMAT} (format attribute {f.attrs.get('format')!r})")
        if int(f.attrs["format_version"]) != FORMAT_VERSION:
            raise ValueError(f"{path!r}: format_version {f.attrs['format_version']}; this wingmdao reads "
                             f"{FORMAT_VERSION}")
        arrays = {attr: f[where][()] for attr, (where, _, _) in _DATASETS.items()}
        run = {"wall_time_s": float(f["run"].attrs["wall_time_s"]), "ranks": int(f["run"].attrs["ranks"]),
               "case_wall_s": f["run/case_wall_s"][()]}
        return LoadsDatabase(case=str(f.attrs["case"]), status=str(f.attrs["status"]), model=str(f.attrs["model"]),
                             matrix_file=str(f.attrs["matrix_file"]), cases=f["cases"][()], run=run, **arrays)


def differences(a: LoadsDatabase, b: LoadsDatabase, *, rtol=0.0, atol=0.0, run=False) -> list:
    """Names of the fields in which ``a`` and ``b`` differ (NaN equal to NaN; floats within
    ``rtol``/``atol``); ``run`` also compares the run record (timings, ranks).

    Parameters
    ----------
    a, b : LoadsDatabase
        The two databases.
    rtol, atol : float, optional
        Relative and absolute tolerances on floats.
    run : bool, optional
        Also compare the run record.

    Returns
    -------
    list of str
        Names of the differing fields.
    """
    out = []
    for f in fields(LoadsDatabase):
        if f.name == "run" and not run:
            continue
        x, y = getattr(a, f.name), getattr(b, f.name)
        if f.name == "cases":
            same = x.dtype == y.dtype and x.shape == y.shape and all(
                np.allclose(x[k], y[k], rtol=rtol, atol=atol, equal_nan=True) if x.dtype[k].kind == "f"
                else np.array_equal(x[k], y[k]) for k in x.dtype.names)
        elif f.name == "run":
            same = x.keys() == y.keys() and all(np.array_equal(x[k], y[k], equal_nan=True) for k in x)
        elif isinstance(x, np.ndarray):
            same = x.shape == y.shape and x.dtype.kind == y.dtype.kind and (
                np.allclose(x, y, rtol=rtol, atol=atol, equal_nan=True) if x.dtype.kind == "f" else np.array_equal(x, y))
        else:
            same = x == y
        if not same:
            out.append(f.name)
    return out


def run_matrix(module, matrix, *, case: str, comm=None, thickness=None, progress=None) -> LoadsDatabase:
    """Build the wing, expand the matrix, evaluate every case (split over ``comm``'s ranks when
    given) and screen it: the database (status ``interrupted`` after Ctrl-C, with the cases done).

    Parameters
    ----------
    module : module
        The case module.
    matrix : LoadsMatrix
        The loads matrix.
    case : str
        Case name.
    comm : mpi4py.MPI.Comm or None, optional
        Communicator to split the cases over; None for serial.
    thickness : dict or None, optional
        Wall name -> (n,) thicknesses (m); None for the case's initial design.
    progress : file-like or None, optional
        Stream for progress lines; None for standard error.

    Returns
    -------
    LoadsDatabase
        The database.
    """

    t0 = time.perf_counter()
    model = build_wing_model(module, matrix, thickness)
    cases = expand(matrix)
    results, interrupted = evaluate_cases(module, model, cases, comm=comm,
                                          progress=sys.stderr if progress is None else progress)
    if not results:
        raise KeyboardInterrupt  # nothing to keep
    return assemble(module, model, cases, results, case=case, interrupted=interrupted,
                    wall_time_s=time.perf_counter() - t0, ranks=1 if comm is None else comm.size)
