"""The loads matrix (wingmdao.loads.matrix) and its database (wingmdao.loads.database): the file's
checks, the expansion, the station loads against equilibrium, the screening against a brute-force
search, the database round trip, an interrupted run, and serial against ``mpirun -n 2``."""

import io
import os
import subprocess
import sys

import numpy as np
import pytest

from wingmdao.aero.plunge import half_wing_mass
from wingmdao.cases import pegasus
from wingmdao.loads import database as ldb
from wingmdao.loads import matrix as lm
from wingmdao.loads.atmosphere import G0, LB
from wingmdao.loads.maneuver import limit_load_factors, maneuver_line_loads

pytest.importorskip("yaml")
pytest.importorskip("h5py")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

TINY = """\
altitudes_ft: [0, 20000]
speeds:
  V_C: {mach: 0.5}
  V_D: {eas_kt: 260}
mass_cases:
  - {name: heavy_fwd, weight_lb: 41005, cg_mac: 0.15, fuel_fraction: 1.0}
  - {name: light_aft, weight_kg: 14000, cg_mac: 0.40, fuel_fraction: 0.1}
aircraft: {tail_arm_m: 12.0, wing_fuel_kg: 3000, fuel_span: [0.0, 0.7]}
gusts: {gradients_ft: [60, 350], signs: [up, down]}
turbulence: true
maneuvers: {load_factors: [2.5, -1.0]}
model: {num_nodes: 5, dt_s: 0.025, settle_s: 0.4, grid_points: 21}
stations: [0, 2]
"""


def _write(tmp_path, text, name="m.yaml"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    path = _write(tmp_path_factory.mktemp("matrix"), TINY)
    matrix = lm.read_matrix(path)
    model = lm.build_wing_model(pegasus, matrix)
    cases = lm.expand(matrix)
    results, interrupted = lm.evaluate_cases(pegasus, model, cases, progress=io.StringIO())
    assert not interrupted
    db = ldb.assemble(pegasus, model, cases, results, case="pegasus")
    return {"path": path, "matrix": matrix, "model": model, "cases": cases, "results": results, "db": db}


def test_expansion_counts_and_names(tmp_path):
    m = lm.read_matrix(_write(tmp_path, TINY))
    cases = lm.expand(m)
    # 2 altitudes x 2 speeds x 2 mass cases x (2 gradients x 2 signs + turbulence + 2 maneuvers)
    assert len(cases) == 2 * 2 * 2 * (4 + 1 + 2)
    assert [c.index for c in cases] == list(range(len(cases)))
    assert len({c.name for c in cases}) == len(cases)
    kinds = [c.kind for c in cases]
    assert kinds.count("gust") == 32 and kinds.count("turbulence") == 8 and kinds.count("maneuver") == 16
    # without maneuvers.load_factors each mass case gets its 25.337 limits
    text = TINY.replace("maneuvers: {load_factors: [2.5, -1.0]}\n", "")
    cases = lm.expand(lm.read_matrix(_write(tmp_path, text, "d.yaml")))
    heavy = sorted({c.load_factor for c in cases if c.kind == "maneuver" and c.mass == "heavy_fwd"})
    assert heavy == sorted(limit_load_factors(41005.0))
    light = sorted({c.load_factor for c in cases if c.kind == "maneuver" and c.mass == "light_aft"})
    assert light == sorted(limit_load_factors(14000.0 / LB))


@pytest.mark.parametrize("old,new,message", [
    ("altitudes_ft: [0, 20000]\n", "", "missing key 'altitudes_ft'"),
    ("turbulence: true", "turbulance: true", "unknown key 'turbulance'"),
    ("[0, 20000]", "[0, 70000]", "altitudes_ft[1] = 70000 ft: outside the atmosphere"),
    ("cg_mac: 0.40", "cg_mac: 1.3", "cg_mac = 1.3: the CG is outside the chord; allowed range [0, 1]"),
    ("cg_mac: 0.15", "cg_mac: -0.1", "the CG is outside the chord"),
    ("weight_lb: 41005", "weight_lb: 0", "mass_cases[0].weight_lb = 0 lb; allowed range (0, inf)"),
    ("weight_kg: 14000", "weight_kg: -5", "weight_kg = -5 kg; allowed range (0, inf)"),
    ("V_D: {eas_kt: 260}", "V_B: {eas_kt: 260}", "speeds: unknown key 'V_B'"),
    ("V_C: {mach: 0.5}", "V_C: {mach: 0.5, eas_m_s: 100}", "speeds.V_C: give exactly one of"),
    ("fuel_fraction: 1.0", "fuel_fraction: 1.5", "fuel_fraction = 1.5; allowed range [0, 1]"),
    ("gradients_ft: [60, 350]", "gradients_ft: [20, 350]", "gusts.gradients_ft[0] = 20 ft; allowed range [30, 350]"),
    ("tail_arm_m: 12.0", "tail_span: 12.0", "aircraft: unknown key 'tail_span'"),
    ("num_nodes: 5", "num_nodes: 2", "model.num_nodes = 2; allowed an integer in [3, 200]"),
    ("stations: [0, 2]", "stations: [0, 9]", "stations = [0, 9]; allowed a list of station indices in [0, 4]"),
    ("name: light_aft", "name: heavy_fwd", "repeated"),
    ("num_nodes: 5,", "aero_theory: vlm, num_nodes: 5,", "model.aero_theory = 'vlm' needs model.aero = 'coupled'"),
    ("num_nodes: 5,", "aero: coupled, aero_theory: panel, num_nodes: 5,",
     "model.aero_theory = 'panel'; allowed 'strip', 'lifting-line', 'vlm'"),
])
def test_bad_matrix_file_one_line_error(tmp_path, old, new, message):
    assert old in TINY
    path = _write(tmp_path, TINY.replace(old, new))
    with pytest.raises(ValueError) as err:
        lm.read_matrix(path)
    text = str(err.value)
    assert message in text and path in text and "\n" not in text


def test_bad_matrix_file_not_yaml_or_missing(tmp_path):
    with pytest.raises(ValueError, match="does not exist"):
        lm.read_matrix(str(tmp_path / "none.yaml"))
    with pytest.raises(ValueError, match="not valid YAML"):
        lm.read_matrix(_write(tmp_path, "altitudes_ft: [0\n  speeds: {"))
    with pytest.raises(ValueError, match="must be a mapping"):
        lm.read_matrix(_write(tmp_path, "- 1\n- 2\n", "l.yaml"))


def test_tail_arm_shorter_than_the_chord_is_refused(tmp_path):
    m = lm.read_matrix(_write(tmp_path, TINY.replace("tail_arm_m: 12.0", "tail_arm_m: 1.0")))
    with pytest.raises(ValueError, match=r"aircraft.tail_arm_m = 1 m; allowed range \(2\.\d+, inf\) m"):
        lm.build_wing_model(pegasus, m)


def test_maneuver_root_shear_is_the_applied_lift_less_inertia(tiny):
    """Equilibrium of the clamped half wing: the root vertical shear of a maneuver equals the
    integral of the applied lift line load less n g times the half wing's mass (fuel included),
    and the wing's lift share follows the tail balance n W / (1 + (x_cg - x_ac) c_mac / l_t)."""
    model, matrix = tiny["model"], tiny["matrix"]
    j = lm.COMPONENTS.index("vertical_shear")
    checked = 0
    for c in tiny["cases"]:
        if c.kind != "maneuver":
            continue
        mass = next(m for m in matrix.mass_cases if m.name == c.mass)
        share = mass.weight_n / (1 + (mass.cg_mac - 0.25) * model.mac / 12.0)
        loads = maneuver_line_loads(model.node_positions, model.chord, model.axis_fraction, share, c.load_factor,
                                    semi_span=model.semi_span, fuselage_half_width=model.fuselage_half_width)
        r = model.node_positions
        ds = np.linalg.norm(np.diff(r, axis=0), axis=1)
        fz = loads.force_per_length[:, 2]
        lift = np.sum(0.5 * (fz[1:] + fz[:-1]) * ds)
        m_half = half_wing_mass(model.beams[c.mass]["mass_per_length"], r)[0]
        expected = lift - c.load_factor * G0 * m_half
        got = tiny["results"][c.index].max[0, j]
        assert got == pytest.approx(expected, rel=1e-6, abs=1e-6 * abs(lift)), c.name
        checked += 1
    assert checked == 16
    # the fuel: full tanks of the heavy case add 1500 kg per half wing over the structure's mass
    heavy = half_wing_mass(model.beams["heavy_fwd"]["mass_per_length"], r)[0]
    base = half_wing_mass(pegasus.beam_params(5)["mass_per_length"], r)[0]
    assert heavy - base == pytest.approx(1500.0, rel=1e-9)


def test_turbulence_is_one_g_plus_minus_u_sigma_a_bar(tiny):
    """25.341(b): the turbulence extremes straddle the 1 g loads, which equal the n = 1 maneuver's
    (the same Schrenk spanload and gravity, solved independently by the static solve)."""
    db = tiny["db"]
    table = db.cases
    for i in np.flatnonzero(table["kind"] == b"turbulence"):
        row = table[i]
        one_g = 0.5 * (db.loads_max[i] + db.loads_min[i])
        # the +2.5 g maneuver of the same point, scaled back to 1 g is not linear (inertia); compare
        # against a 1 g static solve instead
        case = lm.MatrixCase(0, "one_g", "maneuver", float(row["altitude_ft"]), row["speed"].decode(),
                             row["mass"].decode(), load_factor=1.0)
        ref = lm.evaluate_case(pegasus, tiny["model"], case).max
        scale = np.max(np.abs(ref), axis=0)
        assert np.all(np.abs(one_g - ref) <= 1e-6 * scale + 1e-9)
        assert np.all(db.loads_max[i] >= db.loads_min[i])


def _brute_force(cases, results):
    """Per station and component, the case of the largest max and smallest min: plain loops."""
    some = results[cases[0].index]
    n, k = some.max.shape
    best_hi = [[None] * k for _ in range(n)]
    best_lo = [[None] * k for _ in range(n)]
    for c in cases:
        r = results[c.index]
        for i in range(n):
            for j in range(k):
                if best_hi[i][j] is None or r.max[i, j] > best_hi[i][j][0]:
                    best_hi[i][j] = (r.max[i, j], c.index)
                if best_lo[i][j] is None or r.min[i, j] < best_lo[i][j][0]:
                    best_lo[i][j] = (r.min[i, j], c.index)
    return best_hi, best_lo


def test_screening_equals_brute_force(tiny):
    db, cases = tiny["db"], tiny["cases"]
    # the brute force evaluates every case again, one by one, outside evaluate_cases
    again = {c.index: lm.evaluate_case(pegasus, tiny["model"], c) for c in cases}
    hi, lo = _brute_force(cases, again)
    n = db.envelope_max.shape[0]
    for i in range(n):
        for j in range(6):
            assert db.envelope_max[i, j] == hi[i][j][0] and db.max_case[i, j] == hi[i][j][1], (i, j)
            assert db.envelope_min[i, j] == lo[i][j][0] and db.min_case[i, j] == lo[i][j][1], (i, j)
    # the snapshot of a critical case is the whole wing at that instant: it holds the critical value
    for i in range(n):
        for j in range(6):
            c = int(db.max_case[i, j])
            assert db.snapshot(c, i, lm.COMPONENTS[j], "max")[i, j] == db.envelope_max[i, j]
            c = int(db.min_case[i, j])
            assert db.snapshot(c, i, lm.COMPONENTS[j], "min")[i, j] == db.envelope_min[i, j]
    # the critical set mixes kinds (gusts and maneuvers both size some station), and the JSON table
    kinds = {db.cases["kind"][c] for c in np.concatenate([db.max_case.ravel(), db.min_case.ravel()])}
    assert len(kinds) >= 2
    rows = lm.critical_table(cases, lm.screen(db.loads_max, db.loads_min), [0, 2], db.node_positions[:, 1])
    assert len(rows) == 2 * 3 and rows[0]["max"]["case"] == cases[int(db.max_case[0, 0 + 2])].name


def test_gust_snapshot_is_the_history_at_its_instant(tiny):
    """The stored extremes of a gust equal those of an independent march of the same gust
    (wingmdao.aero.gust_response.strip_gust_response, up gusts), and each snapshot is the history at its time."""
    from wingmdao.aero.gust_response import GustFlight, strip_gust_response
    from wingmdao.loads.gust import design_gust_velocity_eas

    model, matrix = tiny["model"], tiny["matrix"]
    c = next(c for c in tiny["cases"] if c.kind == "gust" and c.sign > 0 and c.speed == "V_C" and c.altitude_ft > 0)
    speed = matrix.speeds[0]
    mass = next(m for m in matrix.mass_cases if m.name == c.mass)
    fs = lm.flight_state(pegasus, c.altitude_ft, speed)
    u = design_gust_velocity_eas(c.gradient_ft, c.altitude_ft, fs.f_g)
    dt = matrix.model["dt_s"]
    t = dt * np.arange(int(np.ceil(lm.gust_duration(matrix, c.gradient_ft, fs.airspeed) / dt)) + 1)
    flight = GustFlight(fs.airspeed, fs.density, fs.mach, fs.altitude_m, c.gradient_ft * 0.3048, u,
                        u * np.sqrt(1.225 / fs.density), lm.wing_lift(model, mass), matrix.model["gust_start_s"])
    resp = strip_gust_response(t, model.beams[c.mass], model.chord, model.axis_fraction, flight, area=model.area,
                               semi_span=model.semi_span, fuselage_half_width=model.fuselage_half_width)
    L = lm.csn_loads(resp.states)
    r = tiny["results"][c.index]
    scale = np.abs(L).max(axis=(0, 1))
    assert np.all(np.abs(L.max(axis=0) - r.max) <= 1e-9 * scale)
    assert np.all(np.abs(L.min(axis=0) - r.min) <= 1e-9 * scale)
    for k, time in enumerate(r.snapshot_time):
        step = int(round(time / dt))
        assert np.all(np.abs(L[step] - r.snapshots[k]) <= 1e-9 * scale)


def test_forward_cg_and_heavier_weight_load_the_wing_more(tiny):
    model, matrix = tiny["model"], tiny["matrix"]
    heavy, light = matrix.mass_cases
    share = lm.wing_lift(model, heavy)
    assert share == pytest.approx(41005 * LB * G0 / (1 - 0.1 * model.mac / 12.0), rel=1e-12)
    assert share > heavy.weight_n  # forward of the aerodynamic centre: tail download
    assert lm.wing_lift(model, light) < light.weight_n


def test_database_round_trip_identical_and_self_describing(tiny, tmp_path):
    import h5py

    db = tiny["db"]
    assert db.status == "complete" and db.cases["evaluated"].all()
    path = ldb.write_database(db, str(tmp_path / "loads.h5"))
    back = ldb.read_database(path)
    assert ldb.differences(db, back, run=True) == []
    assert back.matrix_file == TINY and back.case_names == [c.name for c in tiny["cases"]]
    assert not [p for p in os.listdir(tmp_path) if p.endswith(".tmp")]
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                assert "units" in obj.attrs and "description" in obj.attrs, name
        f.visititems(visit)
        assert f["cases"].dtype.names == ldb.CASE_DTYPE.names
        assert list(f.attrs["components"]) == list(lm.COMPONENTS)
    # a changed value is a difference
    back.loads_max[3, 1, 2] += 1.0
    assert ldb.differences(db, back) == ["loads_max"]
    with pytest.raises(ValueError, match="not an HDF5 file"):
        ldb.read_database(_write(tmp_path, "text", "x.h5"))


def test_interrupted_run_keeps_the_cases_done(tiny, monkeypatch):
    calls = {"n": 0}
    real = lm.evaluate_case

    def stop_after_five(module, model, case):
        calls["n"] += 1
        if calls["n"] > 5:
            raise KeyboardInterrupt
        return real(module, model, case)

    monkeypatch.setattr(lm, "evaluate_case", stop_after_five)
    db = ldb.run_matrix(pegasus, tiny["matrix"], case="pegasus", progress=io.StringIO())
    assert db.status == "interrupted"
    assert db.cases["evaluated"].tolist() == [True] * 5 + [False] * (len(tiny["cases"]) - 5)
    assert np.isnan(db.loads_max[5:]).all() and (db.max_snapshot[5:] == -1).all()
    assert db.max_case.max() < 5 and db.min_case.max() < 5
    np.testing.assert_array_equal(db.loads_max[:5], tiny["db"].loads_max[:5])


MPI_SCRIPT = """
import sys
from mpi4py import MPI
from wingmdao.cases import pegasus
from wingmdao.loads import database as ldb, matrix as lm
import io
comm = MPI.COMM_WORLD
db = ldb.run_matrix(pegasus, lm.read_matrix(sys.argv[1]), case="pegasus", comm=comm if comm.size > 1 else None,
                    progress=io.StringIO())
if comm.rank == 0:
    ldb.write_database(db, sys.argv[2])
"""


@pytest.mark.slow
def test_serial_and_mpirun_two_ranks_give_the_same_database(tmp_path, mpirun, mpi_env):
    small = TINY.replace("altitudes_ft: [0, 20000]", "altitudes_ft: [20000]").replace("turbulence: true",
                                                                                        "turbulence: false")
    path = _write(tmp_path, small)
    script = _write(tmp_path, MPI_SCRIPT, "run.py")
    ser = subprocess.run([sys.executable, script, path, str(tmp_path / "s.h5")], env=mpi_env, capture_output=True,
                         text=True, timeout=300, cwd=ROOT)
    assert ser.returncode == 0, ser.stderr[-2000:]
    par = subprocess.run([*mpirun, "-n", "2", sys.executable, script, path, str(tmp_path / "p.h5")], env=mpi_env,
                         capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert par.returncode == 0, par.stderr[-2000:]
    a, b = ldb.read_database(str(tmp_path / "s.h5")), ldb.read_database(str(tmp_path / "p.h5"))
    assert a.run["ranks"] == 1 and b.run["ranks"] == 2
    assert ldb.differences(a, b) == []


def test_coupled_vortex_lattice_gust_is_the_gust_commands_lattice(tmp_path):
    """``model: {aero: coupled, aero_theory: vlm}``: the matrix's up gust (V_C, 20 000 ft, heavy_fwd)
    is the vortex-lattice aeroelastic beam of ``wingmdao gust --aero-theory vlm``
    (wingmdao.aero.gust_response.coupled_gust_response with the lattice's influence matrices, checked
    against the lattice solved on its panels in tests/test_aero_vlm.py), root bending extremes to
    1e-9; the 2-D strips' (``aero_theory: strip``) peak root bending increment is more than 15 %
    above it (the lattice's lower lift slope, 5.5 against 7.2 /rad)."""
    from wingmdao.aero.gust_response import GustFlight, coupled_gust_response
    from wingmdao.aero.system import aero_parameters, three_dimensional_parameters
    from wingmdao.loads.gust import design_gust_velocity_eas

    text = TINY.replace("model: {", "model: {aero: coupled, aero_theory: vlm, ").replace("[60, 350]", "[350]")
    peaks = {}
    for theory in ("vlm", "strip"):
        matrix = lm.read_matrix(_write(tmp_path, text.replace("aero_theory: vlm", f"aero_theory: {theory}")))
        model = lm.build_wing_model(pegasus, matrix)
        c = next(c for c in lm.expand(matrix) if c.kind == "gust" and c.sign > 0 and c.speed == "V_C"
                 and c.altitude_ft > 0 and c.mass == "heavy_fwd")
        mass = next(m for m in matrix.mass_cases if m.name == c.mass)
        fs = lm.flight_state(pegasus, c.altitude_ft, matrix.speeds[0])
        r = lm.gust_loads(model, c, fs, mass)
        root = lm.COMPONENTS.index("bending_moment")
        peaks[theory] = r.max[0, root]
        if theory != "vlm":
            continue
        u = design_gust_velocity_eas(c.gradient_ft, c.altitude_ft, fs.f_g)
        dt = matrix.model["dt_s"]
        t = dt * np.arange(int(np.ceil(lm.gust_duration(matrix, c.gradient_ft, fs.airspeed) / dt)) + 1)
        flight = GustFlight(fs.airspeed, fs.density, fs.mach, fs.altitude_m, c.gradient_ft * 0.3048, u,
                            u * np.sqrt(1.225 / fs.density), lm.wing_lift(model, mass), matrix.model["gust_start_s"])
        ap = aero_parameters(model.num_nodes, chord=model.chord, ref_point=model.axis_fraction, airspeed=fs.airspeed,
                             density=fs.density, mach=fs.mach)
        ap.update(three_dimensional_parameters("vlm", model.node_positions, model.chord, model.axis_fraction,
                                               fs.mach))
        resp = coupled_gust_response(t, model.beams[c.mass], model.chord, model.axis_fraction, ap, flight,
                                     area=model.area, plunge=False, aero_theory="vlm")
        L = lm.csn_loads(resp.states)
        np.testing.assert_allclose(r.max[0], L.max(axis=0)[0], rtol=1e-6)
    assert peaks["strip"] > 1.15 * peaks["vlm"]
