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


def _design_chain(law, t, compliance=False, objective=False):
    """Projection -> controlled design march (design=True with the flap modes and the law) ->
    ModalStationLoads on the Goland wing with an aileron, at the reference design; with the fixed
    controlled wing's march and recovery for comparison."""
    import openmdao.api as om

    from wingmdao.aero.modal_design import DESIGN_INPUTS, modal_projection
    from wingmdao.aero.rfa_system import modal_rfa_system
    from wingmdao.components.modal_dlm import ModalProjectionComp, ModalStationLoads
    from wingmdao.components.time_history import TimeHistoryComponent
    from wingmdao.aero.system import control_param_specs

    wing, _ = _goland(law, tau=0.02)
    problem = flutter_problem("goland", num_nodes=11)
    beam = problem.beam
    P = modal_projection(beam, wing.modes)
    if compliance:  # Goland's beam is inextensible (zeros): a relative step needs a value
        beam = dict(beam, compliance_csn=np.full((11, 3), 2e-9))
    m, ns = wing.modes.count, wing.controls.n_surfaces
    w = 2 * np.pi / 0.2
    on = t <= 0.2
    gust = np.column_stack([np.where(on, 2.0 * (1 - np.cos(w * t)), 0.0), np.where(on, 2.0 * w * np.sin(w * t), 0.0),
                            np.where(on, 2.0 * w * w * np.cos(w * t), 0.0)])
    data = {"gust_velocity": gust[:, 0], "gust_velocity_rate": gust[:, 1], "gust_velocity_acceleration": gust[:, 2],
            "modal_force": np.zeros((t.size, m)), "surface_command": np.zeros((t.size, ns))}
    gains = [sp.name for sp in control_param_specs(wing.controls.spec)]
    p = om.Problem()
    ivc = p.model.add_subsystem("ivc", om.IndepVarComp(), promotes=["*"])
    for k, (shape, u) in DESIGN_INPUTS.items():
        ivc.add_output(k, np.asarray(beam[k], float).reshape((11,) + shape), units=u)
    ivc.add_output("airspeed", V, units="m/s")
    ivc.add_output("density", RHO, units="kg/m**3")
    for k, val in law.matrices().items():
        ivc.add_output(k, np.asarray(val, float), units="1/s" if k == "controller_A" else None)
    p.model.add_subsystem("proj", ModalProjectionComp(projection=P), promotes_inputs=list(DESIGN_INPUTS))
    system = modal_rfa_system(wing.structure, wing.rfa, design=True, controls=wing.controls)
    p.model.add_subsystem("march", TimeHistoryComponent(system=system, time=t, forcing_data=data, initial="static"),
                          promotes_inputs=["airspeed", "density", *gains])
    p.model.add_subsystem("loads", ModalStationLoads(wing=wing, node_euler_angles=np.asarray(beam["node_euler_angles"], float),
                                                     airspeed=V, density=RHO, gust=gust, time_step=float(t[1] - t[0])))
    for k in ("modal_mass", "modal_stiffness"):
        p.model.connect("proj." + k, "march." + k)
        p.model.connect("proj." + k, "loads." + k)
    p.model.connect("proj.modal_inertia", "loads.modal_inertia")
    p.model.connect("proj.modal_inertia", "march.root_inertia", src_indices=np.arange(3 * m, 4 * m),
                    flat_src_indices=True)
    p.model.connect("march.states", "loads.states")
    if objective:  # a scalar of the root bending history
        p.model.add_subsystem("obj", om.ExecComp("f = sum(M[:, 0, 0] ** 2) * 1e-8", M={"shape": (t.size, 11, 3), "units": "N*m"},
                                                  f={"units": "N**2*m**2"}))
        p.model.connect("loads.M_csn", "obj.M")
    p.setup(mode="rev")
    p.run_model()
    F = np.column_stack([gust, np.zeros((t.size, m + ns))])
    X = march(wing.system, t, pack(wing.system.param_specs, {"airspeed": V, "density": RHO, **law.matrices()}), F,
              initial="static").states
    return p, wing, beam, X, F


ROOT_LAW = ControlLaw(("root_bending",), A=[[-8.0]], B=[[8.0]], C=[[-0.5]], D=[[0.2]])


def test_design_march_with_law_equals_the_fixed_wing_and_its_recovery():
    """At the reference design the controlled design march (the modal mass, stiffness and the law's
    root-bending inertia row as inputs from the projection) equals the fixed controlled wing's march,
    and the component's root loads (flap columns, flap acceleration from the BDF rates) equal the
    module recovery's (wingmdao.aero.modal_loads, rotated to csn); the flap moves (the law acts)."""
    from wingmdao.beam.rotations import body_to_csn

    t = np.linspace(0.0, 0.4, 41)
    p, wing, beam, X, F = _design_chain(ROOT_LAW, t)
    np.testing.assert_allclose(p.get_val("march.states"), X, atol=1e-8 * np.abs(X).max())
    Xd = state_rates(X, t[1] - t[0])
    total, _ = station_load_history(wing.loads, wing.structure, wing.rfa, X, F, V, RHO, None, wing.controls, Xd)
    T0 = np.asarray(body_to_csn(beam["node_euler_angles"][0]), float)
    Mc = p.get_val("loads.M_csn")[:, 0]
    np.testing.assert_allclose(Mc, total[:, 0, 3:] @ T0.T, atol=1e-8 * np.abs(Mc).max())
    d, _, _, _ = control_terms(wing.controls, wing.rfa, X, Xd, wing.modes.count)
    assert np.abs(d).max() > 1e-3


def test_controlled_station_loads_partials_and_totals_wrt_gains():
    """ModalStationLoads with flap columns: check_partials against central differences; the reverse
    totals of the root bending history's sum of squares with respect to the law's gains and the
    mass per length (through the projection, the design march and the law's inertia row) against
    central differences of the whole chain."""
    t = np.linspace(0.0, 0.2, 21)
    p, *_ = _design_chain(ROOT_LAW, t, compliance=True)
    data = p.check_partials(out_stream=None, includes=["loads"], method="fd", form="central", step=1e-6,
                            step_calc="rel_avg")
    for comp, d in data.items():
        for (of, wrt), v in d.items():
            an = v.get("J_fwd", v.get("J_rev"))
            seen = 1e-7 * np.abs(p.get_val(f"{comp}.{of}")).max() / np.abs(p.get_val(f"{comp}.{wrt}")).max()
            assert np.abs(an - v["J_fd"]).max() <= 1e-5 * np.abs(v["J_fd"]).max() + seen, (comp, of, wrt)
    p2, *_ = _design_chain(ROOT_LAW, t, objective=True)
    wrt = ["controller_C", "controller_D", "mass_per_length"]
    J = p2.compute_totals(of=["obj.f"], wrt=wrt, return_format="flat_dict")
    for nm in wrt:
        base = np.asarray(p2.get_val(nm), float).copy()
        j = base.size // 2
        h = 1e-5 * abs(base.flat[j])
        vals = []
        for s in (1, -1):
            v = base.copy()
            v.flat[j] += s * h
            p2.set_val(nm, v)
            p2.run_model()
            vals.append(float(p2.get_val("obj.f")[0]))
        p2.set_val(nm, base)
        fd = (vals[0] - vals[1]) / (2 * h)
        an = np.asarray(J[("obj.f", nm)]).ravel()[j]
        assert fd != 0 and abs(an - fd) <= 1e-4 * abs(fd), (nm, an, fd)


@pytest.mark.slow
def test_pegasus_dlm_co_design_totals_match_central_differences():
    """The sized PEGASUS gust with --aero-theory dlm, free plunge, the docs' alleviation file and
    --size-gains (the flap modes and the law in the design's modal residual), at a random design
    (walls 4-12 mm): the reverse totals of the gust KS, the modal system's closed-loop constraint and
    the actuator KS with respect to wall thicknesses and the gains C and D equal central differences
    of re-run models to 1e-4 of the largest entry of each row (steps: 1e-4 of a thickness, 1e-4 rad
    per unit for a gain), and the gains move every row (the modal law is in the loads)."""
    from wingmdao.cases import pegasus
    from wingmdao.sizing import WALL_VARS, build_problem, closed_loop_constraints

    args = pegasus.PegasusOptions(loads="gust", aero="coupled", aero_theory="dlm", t_final=0.4, dt=0.04,
                                  gust_start=0.0, families="vm", plunge="free", size_gains=True,
                                  alleviation="docs/examples/pegasus_alleviation.yaml")
    setup = pegasus.build(args)
    rng = np.random.default_rng(7)
    setup.options.initial = {w: rng.uniform(0.004, 0.012, 19) for w in WALL_VARS}
    setup.options.disp = False
    assert closed_loop_constraints(setup.load_cases) == ["cases.gust.closed_loop_ks"]
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options)
    prob.set_val("cases.gust.controller_D", [[-0.1]])
    prob.run_model()
    assert np.abs(prob.get_val("cases.gust.modal.march.states")[:, -8]).max() > 1e-3   # the aileron moves
    assert prob.model._get_subsystem("cases.gust.modal.closed_loop") is not None   # the modal system's
    of = ["cases.gust.ks_vm", "cases.gust.closed_loop_ks", "cases.gust.actuator_ks"]
    wrt = {"t_lower_skin": (3, 12), "t_front_spar": (5,), "cases.gust.controller_C": (0,),
           "cases.gust.controller_D": (0,)}
    J = prob.compute_totals(of=of, wrt=list(wrt), return_format="flat_dict")
    # relative steps and tolerances per output (the modal system's constraint and the actuator KS
    # are smooth functions of the projection and the march, as the gust KS)
    steps = {o: (1e-4, 1e-4, 1e-4) for o in of}
    for o, (h_t, h_g, tol) in steps.items():
        fd = {}
        for nm, idx in wrt.items():
            base = np.asarray(prob.get_val(nm), float).copy()
            for j in idx:
                h = h_g if "controller" in nm else h_t * abs(base.flat[j])   # gains: absolute steps
                vals = []
                for sgn in (1, -1):
                    v = base.copy()
                    v.flat[j] += sgn * h
                    prob.set_val(nm, v)
                    prob.run_model()
                    vals.append(float(prob.get_val(o).ravel()[0]))
                prob.set_val(nm, base)
                fd[(nm, j)] = (vals[0] - vals[1]) / (2 * h)
        big = max(abs(v) for v in fd.values())
        for (nm, j), v in fd.items():
            an = np.asarray(J[(o, nm)]).ravel()[j]
            assert abs(an - v) <= tol * big, (o, nm, j, an, v)
        # the gains move every row: the modal law is in the loads, the pencil and the march
        assert abs(fd[("cases.gust.controller_D", 0)]) > 1e-3 * big


def test_modal_closed_loop_eigenvalues_and_partials():
    """ModalClosedLoopDamping on the Goland wing with an aileron and a filtered root-bending law:
    with zero gains its selected eigenvalues are the open-loop doublet-lattice state matrix's
    (wingmdao.stability.pk.state_matrix, the flutter command's) and the decoupled actuator,
    controller and lag roots, and every oscillatory root of the state matrix is selected; with the
    law on a perturbed design (modal mass and stiffness off the reference) check_partials holds."""
    import openmdao.api as om

    from wingmdao.aero.rfa_system import modal_rfa_system
    from wingmdao.components.modal_closed_loop import ModalClosedLoopDamping, loaded_modes
    from wingmdao.stability.pk import state_matrix

    zero = ControlLaw(("root_bending",), A=[[-8.0]], B=[[8.0]], C=[[0.0]], D=[[0.0]])
    wing, _ = _goland(zero, tau=0.02)
    s, rfa = wing.structure, wing.rfa
    m, L = s.mass.shape[0], rfa.n_lags
    system = modal_rfa_system(s, rfa, design=True, controls=wing.controls)

    def model(law, M, K):
        p = om.Problem()
        p.model.add_subsystem("c", ModalClosedLoopDamping(system=system, loaded=loaded_modes(rfa), n_lags=L),
                              promotes=["*"])
        p.setup(force_alloc_complex=False)
        vals = {"airspeed": V, "density": RHO, "modal_mass": M, "modal_stiffness": K,
                "root_inertia": wing.controls.root_inertia, **law.matrices()}
        for k, val in vals.items():
            p.set_val(k, np.asarray(val, float))
        p.run_model()
        return p

    p = model(zero, s.mass, s.stiffness)
    lam = p.model.c.last_eigenvalues
    ref = np.linalg.eigvals(state_matrix(s, rfa, RHO, V))
    b = float(rfa.b_ref)
    extra = np.r_[-1.0 / 0.02, -8.0, -np.asarray(rfa.lags) * V / b]
    for z in lam:   # each selected root: the state matrix's or a decoupled one
        d = min(np.abs(ref - z).min(), np.abs(extra - z).min())
        assert d <= 1e-7 * abs(z), (z, d)
    osc = ref[(ref.imag > 1.0) & (ref.imag <= 2 * np.pi * 50.0)]
    assert osc.size >= 3
    for z in osc:
        assert np.abs(lam - z).min() <= 1e-7 * abs(z), z
    assert p.get_val("closed_loop_ks")[0] >= lam.real.max()

    rng = np.random.default_rng(3)
    E = np.diag(1.0 + 0.1 * rng.uniform(-1, 1, m))
    p = model(ROOT_LAW, E @ s.mass @ E, s.stiffness * (1.0 + 0.05 * rng.uniform(-1, 1, (m, m))))
    assert not np.allclose(p.model.c.last_eigenvalues.real, lam.real[:p.model.c.last_eigenvalues.size])
    data = p.check_partials(out_stream=None, method="fd", form="central", step=1e-6, step_calc="rel_avg")
    scale = max(np.abs(d["J_fd"]).max() for d in data["c"].values())   # the row's largest entry
    for (_o, i), d in data["c"].items():
        an, fd = d["J_fwd"], d["J_fd"]
        assert np.abs(an - fd).max() <= 1e-5 * scale, (i, np.abs(an - fd).max(), scale)
        if i in ("modal_stiffness", "controller_D"):
            assert np.abs(fd).max() > 1e3 * np.abs(an - fd).max(), i   # the design and the gain move it


def test_modal_closed_loop_eigenvalues_equal_the_march_decay():
    """The filtered root-bending law on the Goland wing's aileron: started from the real part of a
    selected eigenvector of ModalClosedLoopDamping's pencil (the design system at the reference
    design), the fixed controlled wing's BDF2 march (wing.system, dt = 1e-4 s) keeps the mode's
    coordinate (the left vector's) at exp(lambda t): its decay rate and frequency over 0.3 s equal
    Re and Im lambda of the two least-damped oscillatory modes."""
    from wingmdao.aero.rfa_system import modal_rfa_system
    from wingmdao.components.modal_closed_loop import loaded_modes, modal_closed_loop_modes

    wing, _ = _goland(ROOT_LAW, tau=0.02)
    s, rfa, ctl = wing.structure, wing.rfa, wing.controls
    system = modal_rfa_system(s, rfa, design=True, controls=ctl)
    p = pack(system.param_specs, {"airspeed": V, "density": RHO, "modal_mass": s.mass, "modal_stiffness": s.stiffness,
                                  "root_inertia": ctl.root_inertia, **ROOT_LAW.matrices()})
    lam, v, u, A, B = modal_closed_loop_modes(system, p, loaded_modes(rfa), rfa.n_lags)
    osc = np.flatnonzero(lam.imag > 1.0)
    t = np.arange(0.0, 0.3 + 5e-5, 1e-4)
    pf = pack(wing.system.param_specs, {"airspeed": V, "density": RHO, **ROOT_LAW.matrices()})
    F = np.zeros((t.size, wing.system.n_forcing))
    for k in osc[np.argsort(-lam[osc].real)][:2]:
        x0 = (v[:, k] / v[np.argmax(np.abs(v[:2 * s.mass.shape[0], k])), k]).real
        X = march(wing.system, t, pf, F, initial="state", x_init=x0).states
        c = X @ (B.T @ u[:, k].conj()) / np.vdot(u[:, k], B @ v[:, k])   # the mode's coordinate, 1/2 exp(lambda t)
        i0, i1 = np.searchsorted(t, [0.1, 0.3])
        rate = np.log(abs(c[i1]) / abs(c[i0])) / (t[i1] - t[i0])
        freq = np.angle(c[i1] / c[i1 - 1]) / (t[i1] - t[i1 - 1])
        assert abs(rate - lam[k].real) <= 2e-3 * abs(lam[k].real), (lam[k], rate)
        assert abs(freq - lam[k].imag) <= 1e-3 * lam[k].imag, (lam[k], freq)


@pytest.mark.slow
def test_pegasus_dlm_closed_loop_margin_shifts_the_constraint():
    """--closed-loop-margin m reaches the modal system's ModalClosedLoopDamping (--aero-theory dlm
    --size-gains): at the same design and gains closed_loop_ks grows by exactly m (KS(x + m) =
    KS(x) + m)."""
    from wingmdao.cases import pegasus
    from wingmdao.sizing import build_problem

    ks = {}
    for margin in (0.0, 0.75):
        setup = pegasus.build(pegasus.PegasusOptions(
            loads="gust", aero="coupled", aero_theory="dlm", t_final=0.4, dt=0.04, gust_start=0.0, families="vm",
            plunge="free", size_gains=True, alleviation="docs/examples/pegasus_alleviation.yaml",
            closed_loop_margin=margin))
        setup.options.disp = False
        prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
        assert prob.model._get_subsystem("cases.gust.modal.closed_loop").options["margin"] == margin
        prob.run_model()
        ks[margin] = float(prob.get_val("cases.gust.closed_loop_ks")[0])
    assert ks[0.75] - ks[0.0] == pytest.approx(0.75, abs=1e-9), ks
