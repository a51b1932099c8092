"""Control surfaces on the modal doublet-lattice wing (wingmdao.aero.modal_controls, the controlled
modal residual of wingmdao.aero.rfa_system): an open-loop harmonic flap command marched by BDF2
against the frequency-domain response with the exact tabulated doublet-lattice matrices (no Roger
fit, no march); the adjoint totals of a gust functional with respect to the law's matrices against
central differences; the PEGASUS closed-loop gust of the docs' alleviation file against the vortex
lattice's deflected panels (another model and code path). Skipped without the ``aero3d`` extra."""

import json

import numpy as np
import pytest

from wingmdao.aero.controls import ControlLaw, ControlSurface, control_spec
from wingmdao.aero.modal_controls import control_terms, hinge_moment_history
from wingmdao.aero.modal_loads import _modal_inertia, modal_accelerations, station_load_history
from wingmdao.cli import main
from wingmdao.stability.cases import flutter_problem
from wingmdao.stability.modal import modal_dlm_wing
from wingmdao.timemarch.adjoint import LinearizedHistory
from wingmdao.timemarch.bdf import march, state_rates
from wingmdao.timemarch.system import layout, pack

pytest.importorskip("panelaero.DLM")

K_SET = np.array([0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0, 1.5])
RHO, V = 1.225, 100.0


def _goland(law=None, tau=1e-3, outputs=()):
    problem = flutter_problem("goland", num_nodes=11)
    y = problem.beam["node_positions"][:, 1]
    srf = [ControlSurface("flap", hinge=0.75, nodes=(6, 10), actuator_order=1, time_constant=tau)]
    wing = modal_dlm_wing(problem.beam, problem.aero["chord"], problem.aero["ref_point"], 0.0, n_modes=4,
                          reduced_frequencies=K_SET, n_chordwise=8, n_spanwise=1, controls=control_spec(srf, y, law))
    return wing, srf


@pytest.fixture(scope="module")
def goland_open():
    return _goland()


def test_harmonic_flap_command_equals_frequency_domain_dlm(goland_open):
    """An aileron (nodes 6-10 of the Goland wing, hinge 75 %, first-order actuator tau = 1 ms)
    commanded sin(omega t) at k = 0.3, 100 m/s, marched 3 s: the settled root bending, shear and
    hinge moment equal ``q = [-omega^2 M + K - q_d Q(ik)]^-1 q_d Q_f(ik) delta`` with the exact
    tabulated flap columns, station loads and hinge rows within 1 % (0.25 % found: the Roger fit and
    BDF2; delta = 1 / (1 + i omega tau))."""
    wing, _ = goland_open
    system, gaf, rfa, st = wing.system, wing.gaf, wing.rfa, wing.structure
    k = 0.3
    omega = k * V / gaf.b_ref
    t = np.linspace(0.0, 3.0, int(round(3.0 * omega / (2 * np.pi) * 100)) + 1)
    F = np.zeros((t.size, system.n_forcing))
    F[:, layout(system.forcing_specs)["surface_command"]] = np.sin(omega * t)[:, None]
    p = pack(system.param_specs, {"airspeed": V, "density": RHO})
    X = march(system, t, p, F, initial="state", x_init=np.zeros(system.n_state)).states
    Xd = state_rates(X, t[1] - t[0])
    total, _ = station_load_history(wing.loads, st, rfa, X, F, V, RHO, None, wing.controls, Xd)
    a = modal_accelerations(st, rfa, X, F, V, RHO, None, wing.controls, Xd)
    hinge = hinge_moment_history(wing.controls, rfa, X, Xd, a, F, V, RHO)[:, 0]
    delta = control_terms(wing.controls, rfa, X, Xd, wing.modes.count)[0][:, 0]
    # exact frequency domain
    qd = 0.5 * RHO * V ** 2
    i = int(np.flatnonzero(np.isclose(gaf.k, k))[0])
    d = 1.0 / (1.0 + 1j * omega * 1e-3)
    n = wing.modes.count
    Z = -omega ** 2 * st.mass + 1j * omega * st.damping + st.stiffness - qd * gaf.Q[i]
    q = np.linalg.solve(Z, qd * gaf.flap[i][:, 0] * d)
    loads = qd * (gaf.station_loads[i][..., :n] @ q + gaf.flap_station_loads[i][..., 0] * d) \
        + _modal_inertia(wing.modes) @ (-omega ** 2 * q)
    h = qd * (gaf.hinge[i, 0, :n] @ q + gaf.hinge[i, 0, n] * d)
    last = t > t[-1] - 2 * 2 * np.pi / omega
    basis = np.column_stack([np.sin(omega * t[last]), np.cos(omega * t[last])])

    def amp(sig):
        c, *_ = np.linalg.lstsq(basis, sig[last], rcond=None)
        return c[0] + 1j * c[1]

    assert abs(amp(delta) - d) < 1e-3
    for sig, ref in ((total[:, 0, 3], loads[0, 3]), (total[:, 0, 2], loads[0, 2]), (hinge, h)):
        assert abs(amp(sig) - ref) / abs(ref) < 0.01
    # the flap mode's own aerodynamics matter here: without the structure's response the root
    # bending differs (the test sees the coupling)
    assert abs(qd * gaf.flap_station_loads[i][0, 3, 0] * d - loads[0, 3]) / abs(loads[0, 3]) > 0.05


def test_adjoint_totals_wrt_gains_equal_central_differences():
    """A 1-cos gust on the Goland wing with a filtered tip-acceleration law (A, B, C, D) on a
    second-order actuator: d(sum of squared root bending measurements) / d(controller matrices) by
    the discrete adjoint of the BDF2 march (wingmdao.timemarch.adjoint) equal central differences
    of re-marched histories to 1e-5 relative."""
    law = ControlLaw(("tip_acceleration",), A=[[-8.0]], B=[[8.0]], C=[[-0.02]], D=[[0.004]])
    wing, _ = _goland(law)
    system = wing.system
    t = np.linspace(0.0, 0.4, 81)
    F = np.zeros((t.size, system.n_forcing))
    w = 2 * np.pi / 0.2
    on = t <= 0.2
    F[:, 0] = np.where(on, 2.0 * (1 - np.cos(w * t)), 0.0)
    F[:, 1] = np.where(on, 2.0 * w * np.sin(w * t), 0.0)
    F[:, 2] = np.where(on, 2.0 * w * w * np.cos(w * t), 0.0)
    tip = wing.modes.displacement[:, -1, 2]
    n = wing.modes.count

    def run(p):
        X = march(system, t, p, F, initial="state", x_init=np.zeros(system.n_state)).states
        return X, float(np.sum((X[:, :n] @ tip) ** 2)) * 1e4

    p0 = pack(system.param_specs, {"airspeed": V, "density": RHO, **law.matrices()})
    X, _ = run(p0)
    dfdx = np.zeros_like(X)
    dfdx[:, :n] = 2e4 * (X[:, :n] @ tip)[:, None] * tip[None, :]
    lin = LinearizedHistory(system, t, X, p0, F, initial="state")
    dp, _, _ = lin.gradient(dfdx)
    play = layout(system.param_specs)
    for nm in ("controller_A", "controller_B", "controller_C", "controller_D"):
        j = play[nm].start
        h = 1e-6 * max(1.0, abs(p0[j]))
        pp, pm = p0.copy(), p0.copy()
        pp[j] += h
        pm[j] -= h
        fd = (run(pp)[1] - run(pm)[1]) / (2 * h)
        assert abs(dp[j] - fd) <= 1e-5 * abs(fd) + 1e-12, nm
    assert abs(dp[play["controller_D"].start]) > 0


@pytest.mark.slow
def test_pegasus_closed_loop_gust_against_vortex_lattice(tmp_path):
    """PEGASUS, free plunge, the docs' alleviation file (outboard aileron, filtered load-factor law):
    the doublet lattice's flap modes in the modal basis against the coupled beam with the vortex
    lattice's deflected panels. Peak root-bending increment with the law within 5 % (1.2 % found),
    without it within 5 %, the reduction within 3 points, the aileron's peak deflection and rate within
    5 %, the peak hinge moment increment within 15 %; the JSON carries the strip/VLM path's keys."""
    out = {}
    for theory in ("dlm", "vlm"):
        path = tmp_path / f"{theory}.json"
        assert main(["gust", "pegasus", "--aero-theory", theory, "--alleviation",
                     "docs/examples/pegasus_alleviation.yaml", "--no-plots", "--json", str(path)]) == 0
        out[theory] = json.loads(path.read_text())["alleviation"]
    d, v = out["dlm"], out["vlm"]
    assert set(d) == set(v) and set(d["surfaces"]["aileron"]) == set(v["surfaces"]["aileron"])
    for key in ("peak_incremental_root_bending_with_law", "peak_incremental_root_bending_without_law"):
        assert abs(d[key] / v[key] - 1.0) < 0.05, key
    assert abs(d["incremental_root_bending_reduction"] - v["incremental_root_bending_reduction"]) < 0.03
    sd, sv = d["surfaces"]["aileron"], v["surfaces"]["aileron"]
    for key in ("peak_deflection_deg", "peak_rate_deg_s"):
        assert abs(sd[key] / sv[key] - 1.0) < 0.05, key
    hv = np.asarray(sv["hinge_moment_n_m"])
    hv = hv - hv[0]                                   # the vortex lattice's includes the trimmed 1 g hinge moment
    hd = np.asarray(sd["hinge_moment_n_m"])
    assert abs(np.max(np.abs(hd)) / np.max(np.abs(hv)) - 1.0) < 0.15


def test_turbulence_transfer_with_law_equals_the_closed_loop_march():
    """The transfer function of the controlled modal system's linearization (root bending, the
    aileron's deflection and hinge moment per m/s of gust at k = 0.3, a root-bending law on a
    second-order actuator) equals the settled closed-loop BDF2 march of a sinusoidal gust within 1 %
    (another code path: the shifted sparse solve of wingmdao.stability.modal_turbulence)."""
    from wingmdao.stability.modal_turbulence import modal_gust_frequency_response

    law = ControlLaw(("root_bending",), A=np.zeros((0, 0)), B=[], C=[], D=[[-0.5]])
    problem = flutter_problem("goland", num_nodes=11)
    y = problem.beam["node_positions"][:, 1]
    srf = [ControlSurface("flap", hinge=0.75, nodes=(6, 10), actuator_order=2, frequency_hz=15.0, damping=0.7)]
    wing = modal_dlm_wing(problem.beam, problem.aero["chord"], problem.aero["ref_point"], 0.0, n_modes=4,
                          reduced_frequencies=K_SET, n_chordwise=8, n_spanwise=1, controls=control_spec(srf, y, law))
    system, rfa, st = wing.system, wing.rfa, wing.structure
    k = 0.3
    omega = k * V / wing.gaf.b_ref
    resp = modal_gust_frequency_response(system, st, rfa, wing.loads, V, RHO, [omega], wing.controls, law)
    t = np.linspace(0.0, 3.0, int(round(3.0 * omega / (2 * np.pi) * 100)) + 1)
    F = np.zeros((t.size, system.n_forcing))
    F[:, 0], F[:, 1], F[:, 2] = np.sin(omega * t), omega * np.cos(omega * t), -omega ** 2 * np.sin(omega * t)
    p = pack(system.param_specs, {"airspeed": V, "density": RHO, **law.matrices()})
    X = march(system, t, p, F, initial="state", x_init=np.zeros(system.n_state)).states
    Xd = state_rates(X, t[1] - t[0])
    total, _ = station_load_history(wing.loads, st, rfa, X, F, V, RHO, None, wing.controls, Xd)
    a = modal_accelerations(st, rfa, X, F, V, RHO, None, wing.controls, Xd)
    hinge = hinge_moment_history(wing.controls, rfa, X, Xd, a, F, V, RHO)[:, 0]
    delta = control_terms(wing.controls, rfa, X, Xd, wing.modes.count)[0][:, 0]
    last = t > t[-1] - 2 * 2 * np.pi / omega
    basis = np.column_stack([np.sin(omega * t[last]), np.cos(omega * t[last])])
    for sig, ref in ((total[:, 0, 3], resp.station_loads[0, 0, 3]), (delta, resp.controls["deflection"][0, 0]),
                     (hinge, resp.controls["hinge_moment"][0, 0])):
        c, *_ = np.linalg.lstsq(basis, sig[last], rcond=None)
        assert abs(c[0] + 1j * c[1] - ref) / abs(ref) < 0.01
    assert abs(resp.controls["deflection"][0, 0]) > 1e-4          # the law moves the aileron


@pytest.mark.slow
def test_pegasus_turbulence_with_law_against_vortex_lattice(tmp_path):
    """wingmdao turbulence pegasus, free plunge, the docs' alleviation file: A-bar of the root bending
    and the load factor with and without the law from the doublet lattice's flap modes within 6 % of
    the vortex lattice's deflected panels on the coupled beam (4.9 % found for the root bending with
    the law, below 1 % for the rest); the aileron's deflection A-bar within 5 % (0.9 % found)."""
    out = {}
    for theory in ("dlm", "vlm"):
        path = tmp_path / f"{theory}.json"
        assert main(["turbulence", "pegasus", "--aero-theory", theory, "--alleviation",
                     "docs/examples/pegasus_alleviation.yaml", "--no-plots", "--json", str(path)]) == 0
        out[theory] = json.loads(path.read_text())["alleviation"]
    for key in ("a_bar_with_law", "a_bar_without_law"):
        for q in ("root_bending_moment", "load_factor"):
            assert abs(out["dlm"][key][q] / out["vlm"][key][q] - 1.0) < 0.06, (key, q)
    d, v = (out[t]["control_surfaces"]["aileron"]["a_bar_deflection_deg_per_m_s"] for t in ("dlm", "vlm"))
    assert abs(d / v - 1.0) < 0.05


def test_size_dlm_alleviation_refused_before_solve(capsys, tmp_path, monkeypatch):
    """size --loads gust --aero-theory dlm --alleviation: one line naming the file and the way out
    (the sized modal gust carries no control surfaces), before any solve."""
    import wingmdao.cases.pegasus as pegasus

    monkeypatch.setattr(pegasus, "modal_dlm_gust", lambda *a, **k: pytest.fail("solve started"))
    assert main(["size", "pegasus", "--loads", "gust", "--plunge", "free", "--aero", "coupled", "--aero-theory", "dlm",
                 "--alleviation", "docs/examples/pegasus_alleviation.yaml", "--no-plots",
                 "--json", str(tmp_path / "s.json")]) == 2
    err = capsys.readouterr().err
    assert "--alleviation docs/examples/pegasus_alleviation.yaml with --aero-theory dlm" in err
    assert "--aero-theory vlm --alleviation" in err and not (tmp_path / "s.json").exists()
