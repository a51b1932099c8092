"""Station loads of the modal doublet-lattice wing by force summation (wingmdao.aero.modal_loads):
the panel summation against the closed form of a uniform load, the BDF2 march's harmonic-gust
root bending and the linearization's transfer function against the frequency-domain doublet
lattice, the convergence with the number of modes against the mode-displacement sum, and the
turbulence command's refusals."""

import json

import numpy as np
import pytest

from wingmdao.aero.dlm import station_summation
from wingmdao.aero.modal_loads import harmonic_station_loads, station_load_history, station_load_model
from wingmdao.aero.rfa import fit
from wingmdao.aero.rfa_system import modal_rfa_system
from wingmdao.aero.vlm import build_lattice
from wingmdao.cli import main
from wingmdao.stability.cases import flutter_problem
from wingmdao.stability.modal import case_forces, jig_modes
from wingmdao.stability.modal_turbulence import modal_gust_frequency_response, modal_turbulence_a_bar
from wingmdao.stability.pk import ModalStructure
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import pack

K_SET = np.array([0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0, 1.5])
RHO = 1.225


def test_uniform_pressure_station_moments_are_the_cantilever_closed_form():
    """A uniform pressure p on a rectangular wing of chord c and semi-span L: at a station y the
    internal shear is p c (L - y) and the bending moment p c (L - y)^2 / 2 (statics of a
    cantilever under a uniform line load), both non-zero only outboard."""
    L, c, n = 6.0, 1.8, 9
    r = np.column_stack([np.zeros(n), np.linspace(0.0, L, n), np.zeros(n)])
    lat = build_lattice(r, np.full(n, c), np.full(n, 0.33), mach=0.0, n_chordwise=4, n_spanwise=3)
    S = station_summation(lat, r)
    loads = S @ np.ones(S.shape[2])
    y = r[:, 1]
    np.testing.assert_allclose(loads[:, 2], c * (L - y), rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(loads[:, 3], c * (L - y) ** 2 / 2, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(loads[:, [0, 1, 5]], 0.0, atol=1e-9)


@pytest.fixture(scope="module")
def goland():
    pytest.importorskip("panelaero.DLM")
    problem = flutter_problem("goland", num_nodes=11)
    modes = jig_modes(problem, 4)
    gaf = case_forces(problem, modes, 0.0, reduced_frequencies=K_SET)
    structure = ModalStructure.from_modes(modes)
    rfa = fit(gaf)
    return structure, modes, gaf, rfa, modal_rfa_system(structure, rfa)


def test_harmonic_gust_root_bending_equals_frequency_domain_dlm(goland):
    """A sinusoidal gust at k = 0.3, 120 m/s, marched 3 s by BDF2: the settled root bending moment
    and shear recovered by force summation from the Roger states equal the frequency-domain
    force summation with the exact doublet-lattice matrices and station loads within 2 % (1 % found)
    (the fit's share plus BDF2's)."""
    structure, modes, gaf, rfa, system = goland
    model = station_load_model(gaf, rfa, modes)
    assert model.error < 0.02
    V, k = 120.0, 0.3
    omega = k * V / gaf.b_ref
    t = np.linspace(0.0, 3.0, int(round(3.0 * omega / (2 * np.pi) * 100)) + 1)
    F = np.zeros((t.size, system.n_forcing))
    F[:, 0], F[:, 1], F[:, 2] = np.sin(omega * t), omega * np.cos(omega * t), -omega ** 2 * np.sin(omega * t)
    p = pack(system.param_specs, {"airspeed": V, "density": RHO})
    X = march(system, t, p, F, initial="static").states
    total, aero = station_load_history(model, structure, rfa, X, F, V, RHO)
    last = t > t[-1] - 2 * 2 * np.pi / omega
    basis = np.column_stack([np.sin(omega * t[last]), np.cos(omega * t[last])])
    exact = harmonic_station_loads(structure, gaf, modes, V, RHO, k)
    for comp in (3, 2):                                  # root M_x, root F_z
        coef, *_ = np.linalg.lstsq(basis, total[last, 0, comp], rcond=None)
        amp = coef[0] + 1j * coef[1]
        assert abs(amp - exact[0, comp]) / abs(exact[0, comp]) < 0.02
    # the inertia share is not negligible at this k (the test sees it)
    coef, *_ = np.linalg.lstsq(basis, aero[last, 0, 3], rcond=None)
    assert abs(coef[0] + 1j * coef[1] - exact[0, 3]) / abs(exact[0, 3]) > 0.05


def test_turbulence_transfer_function_of_the_linearization_equals_exact_dlm(goland):
    """The transfer function of the modal residual system's linearization (Roger lags), root bending
    and shear per m/s of gust at the tabulated k = 0.1, 0.3, 0.5 (120 m/s), equals the
    frequency-domain force summation with the exact doublet-lattice matrices within 2 %; A-bar of
    root bending is positive, finite, with a quadrature error estimate below 1 %."""
    structure, modes, gaf, rfa, system = goland
    model = station_load_model(gaf, rfa, modes)
    V = 120.0
    ks = np.array([0.1, 0.3, 0.5])
    resp = modal_gust_frequency_response(system, structure, rfa, model, V, RHO, ks * V / gaf.b_ref)
    for i, k in enumerate(ks):
        exact = harmonic_station_loads(structure, gaf, modes, V, RHO, k)
        for comp in (3, 2):
            assert abs(resp.station_loads[i, 0, comp] - exact[0, comp]) / abs(exact[0, comp]) < 0.02
    ab, _ = modal_turbulence_a_bar(system, structure, rfa, model, V, RHO)
    assert np.isfinite(ab.value[0, 3]) and ab.value[0, 3] > 0 and ab.error[0, 3] < 0.01 * ab.value[0, 3]


def test_turbulence_dlm_refusals_before_solve(capsys, monkeypatch):
    """turbulence --aero-theory dlm: --aero strip, structural damping and --modes out of range (or
    without dlm) are refused before any solve."""
    import wingmdao.cli.turbulence as command  # the names the command calls (imported at its top)

    monkeypatch.setattr(command, "modal_dlm_wing", lambda *a, **k: pytest.fail("solve started"))
    monkeypatch.setattr(command, "free_modal_dlm_wing", lambda *a, **k: pytest.fail("solve started"))
    for argv, msg in ((["--aero", "strip", "--aero-theory", "dlm"], "needs --aero coupled"),
                      (["--aero-theory", "dlm", "--damping-ratio", "0.02"], "is undamped"),
                      (["--aero-theory", "dlm", "--clamped", "--damping-ratio", "0.02"], "is undamped"),
                      (["--aero-theory", "dlm", "--clamped", "--modes", "30"], "--modes = 30; allowed range [2, 20]"),
                      (["--clamped", "--modes", "4"], "--modes = 4 applies to --aero-theory dlm only")):
        assert main(["turbulence", "pegasus", "--no-plots", *argv]) == 2
        assert msg in capsys.readouterr().err


def test_force_summation_converges_with_fewer_modes_than_mode_displacement():
    """Goland (11 nodes), a 1-cos gust (H = 30 m, 10 m/s, 100 m/s): the force-summation root bending
    peak with 2 modes is within 1 % of that with 6 modes, while the mode-displacement sum
    ``sum_i q_i M_i`` with 2 modes is more than 5 % below it (why the loads are summed)."""
    pytest.importorskip("panelaero.DLM")
    problem = flutter_problem("goland", num_nodes=11)
    V, H, u = 100.0, 30.0, 10.0
    t = np.arange(0.0, 1.0, 0.004)
    d = V * (t - 0.05)
    on = (d >= 0) & (d <= 2 * H)
    a = np.pi * V / H
    peaks = {}
    for n_modes in (2, 6):
        modes = jig_modes(problem, n_modes)
        gaf = case_forces(problem, modes, 0.0, reduced_frequencies=K_SET)
        structure = ModalStructure.from_modes(modes)
        rfa = fit(gaf)
        system = modal_rfa_system(structure, rfa)
        F = np.zeros((t.size, system.n_forcing))
        F[on, 0] = 0.5 * u * (1 - np.cos(a * d[on] / V))
        F[on, 1] = 0.5 * u * a * np.sin(a * d[on] / V)
        F[on, 2] = 0.5 * u * a ** 2 * np.cos(a * d[on] / V)
        X = march(system, t, pack(system.param_specs, {"airspeed": V, "density": RHO}), F, initial="static").states
        total, _ = station_load_history(station_load_model(gaf, rfa, modes), structure, rfa, X, F, V, RHO)
        peaks[n_modes] = (np.abs(total[:, 0, 3]).max(), np.abs(X[:, :n_modes] @ modes.moment[:, 0, 0]).max())
    assert peaks[2][0] == pytest.approx(peaks[6][0], rel=0.01)
    assert peaks[2][1] < 0.95 * peaks[6][0]


@pytest.mark.slow
def test_turbulence_pegasus_dlm_json(tmp_path):
    """turbulence pegasus --aero-theory dlm --clamped: A-bar of the root bending moment and of the
    load factor below strip theory's on the clamped beam by about the three-dimensional lift loss
    (lattice slope / 2-D slope 0.77 on PEGASUS: ratios within [0.6, 0.85]), quadrature error below
    1 %, the root entry of the station A-bars equal to the root's, no 1 g keys."""
    out = {}
    for theory in ("dlm", "strip"):
        path = tmp_path / f"{theory}.json"
        assert main(["turbulence", "pegasus", "--aero", "coupled", "--clamped", "--aero-theory", theory, "--no-plots",
                     "--json", str(path)]) == 0
        out[theory] = json.loads(path.read_text())
    d, s = out["dlm"]["a_bar"], out["strip"]["a_bar"]
    for key in ("root_bending_moment", "load_factor"):
        assert 0.6 < d[key] / s[key] < 0.85
    assert out["dlm"]["quadrature"]["max_relative_error_a_bar"] < 0.01
    assert d["bending_moment"][0] == pytest.approx(d["root_bending_moment"], rel=1e-12)
    assert out["dlm"]["loads_include_1g"] is False and "design_loads" not in out["dlm"]


@pytest.mark.slow
def test_turbulence_pegasus_dlm_free_plunge_against_vortex_lattice(tmp_path):
    """turbulence pegasus --aero-theory dlm free in plunge (the plunge mode in the modal basis) against
    the coupled beam with the vortex lattice free in plunge (another model and code path): A-bar of
    the load factor and of the root bending moment within 3 % (0.6 %, 0.5 % found); both well below
    the clamped doublet lattice's root bending (the plunge relieves it)."""
    out = {}
    for theory, extra in (("dlm", []), ("vlm", []), ("clamped", ["--clamped"])):
        path = tmp_path / f"{theory}.json"
        assert main(["turbulence", "pegasus", "--aero", "coupled", "--aero-theory", "vlm" if theory == "vlm" else "dlm",
                     *extra, "--no-plots", "--json", str(path)]) == 0
        out[theory] = json.loads(path.read_text())
    d, v, c = (out[k]["a_bar"] for k in ("dlm", "vlm", "clamped"))
    assert out["dlm"]["plunge"] and out["dlm"]["dlm"]["rigid_body_modes"] == ["plunge"]
    for key in ("load_factor", "root_bending_moment"):
        assert d[key] == pytest.approx(v[key], rel=0.03)
    assert d["root_bending_moment"] < 0.7 * c["root_bending_moment"]
