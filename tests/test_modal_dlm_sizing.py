"""The modal doublet-lattice gust of a changing design (wingmdao.aero.modal_design,
wingmdao.components.modal_dlm): the projection on the fixed basis against the eigen-solution at the
reference design and the Rayleigh-Ritz bound at another design, the components' partials, the
design march against the module recovery, and the adjoint totals of the PEGASUS gust KS with
``--aero-theory dlm`` against central differences."""

import numpy as np
import openmdao.api as om
import pytest

from wingmdao.aero.modal_design import DESIGN_INPUTS, modal_projection
from wingmdao.aero.modal_loads import station_load_history
from wingmdao.aero.rfa_system import modal_rfa_system
from wingmdao.beam.rotations import body_to_csn
from wingmdao.components.modal_dlm import ModalLoadSum, ModalProjectionComp, ModalStationLoads
from wingmdao.components.time_history import TimeHistoryComponent
from wingmdao.stability.cases import flutter_problem
from wingmdao.stability.modal import jig_modes, modal_dlm_wing
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import pack

K_SET = np.array([0.0, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0, 1.5])
V, RHO = 120.0, 1.225


@pytest.fixture(scope="module")
def goland():
    pytest.importorskip("panelaero.DLM")
    problem = flutter_problem("goland", num_nodes=11)
    wing = modal_dlm_wing(problem.beam, problem.aero["chord"], problem.aero["ref_point"], 0.0, n_modes=4,
                          reduced_frequencies=K_SET)
    return problem, wing, modal_projection(problem.beam, wing.modes)


def test_projection_at_the_reference_design_is_the_eigen_solution(goland):
    """On its own modes the design's modal mass is the identity, its stiffness diag(omega^2) and
    its inertia loads -R_i / omega_i^2 (the modes' internal loads from the eigenvectors)."""
    problem, wing, P = goland
    M, K, inertia = P.evaluate(problem.beam)
    np.testing.assert_allclose(M, np.eye(4), atol=1e-8)
    np.testing.assert_allclose(K, np.diag(wing.modes.frequencies ** 2), rtol=1e-7, atol=1e-6 * K.max())
    R = np.concatenate([wing.modes.force, wing.modes.moment], axis=2)
    ref = -np.transpose(R / wing.modes.frequencies[:, None, None] ** 2, (1, 2, 0))
    np.testing.assert_allclose(inertia, ref, atol=1e-8 * np.abs(ref).max())


def test_projection_of_another_design_is_a_rayleigh_ritz_bound(goland):
    """Stiffer and heavier walls (bending stiffness x1.5, torsion x1.2, mass x1.1, offsets moved):
    the projected model's frequencies are upper bounds of the new design's own (Rayleigh-Ritz) and
    the first two within 3 %; the projected frequencies differ from the reference's (the test sees
    the design)."""
    problem, wing, P = goland
    beam = dict(problem.beam)
    E = np.array(beam["stiffness_csn"], dtype=float)
    E[:, 0, 0] *= 1.5
    E[:, 2, 2] *= 1.5
    E[:, 1, 1] *= 1.2
    beam["stiffness_csn"] = E
    beam["mass_per_length"] = 1.1 * np.asarray(beam["mass_per_length"], dtype=float)
    beam["mass_center"] = np.asarray(beam["mass_center"], dtype=float) * 0.8
    M, K, _ = P.evaluate(beam)
    projected = np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real))
    exact = jig_modes(type("P", (), {"num_nodes": 11, "beam": beam})(), 4).frequencies
    assert np.all(projected >= exact * (1 - 1e-9))
    np.testing.assert_allclose(projected[:2], exact[:2], rtol=0.03)
    assert np.abs(projected / wing.modes.frequencies - 1).max() > 0.05


def _chain(goland, t):
    problem, wing, P = goland
    H, w0 = 20.0, 5.0
    om_ = np.pi * V / H
    on = t <= 2 * H / V
    gust = np.column_stack([np.where(on, w0 / 2 * (1 - np.cos(om_ * t)), 0.0), np.where(on, w0 / 2 * om_ * np.sin(om_ * t), 0.0),
                            np.where(on, w0 / 2 * om_ ** 2 * np.cos(om_ * t), 0.0)])
    m = wing.modes.count
    data = {"gust_velocity": gust[:, 0], "gust_velocity_rate": gust[:, 1], "gust_velocity_acceleration": gust[:, 2],
            "modal_force": np.zeros((t.size, m))}
    p = om.Problem()
    ivc = p.model.add_subsystem("ivc", om.IndepVarComp(), promotes=["*"])
    for k, (shape, u) in DESIGN_INPUTS.items():
        ivc.add_output(k, np.asarray(problem.beam[k], float).reshape((11,) + shape), units=u)
    ivc.add_output("airspeed", V, units="m/s")
    ivc.add_output("density", RHO, units="kg/m**3")
    p.model.add_subsystem("proj", ModalProjectionComp(projection=P), promotes_inputs=list(DESIGN_INPUTS))
    p.model.add_subsystem("march", TimeHistoryComponent(system=modal_rfa_system(wing.structure, wing.rfa, design=True),
                                                        time=t, forcing_data=data), promotes_inputs=["airspeed", "density"])
    p.model.add_subsystem("loads", ModalStationLoads(wing=wing, node_euler_angles=np.asarray(problem.beam["node_euler_angles"], float),
                                                     airspeed=V, density=RHO, gust=gust))
    for k in ("modal_mass", "modal_stiffness"):
        p.model.connect("proj." + k, "march." + k)
        p.model.connect("proj." + k, "loads." + k)
    p.model.connect("proj.modal_inertia", "loads.modal_inertia")
    p.model.connect("march.states", "loads.states")
    p.setup(mode="rev")
    p.run_model()
    return p, gust


def test_design_march_equals_the_modal_wing_and_its_recovery(goland):
    """At the reference design the march with the projected matrices as inputs equals the fixed
    modal wing's march, and the component's root loads the module recovery's (rotated to csn)."""
    problem, wing, _ = goland
    t = np.linspace(0.0, 0.4, 41)
    p, gust = _chain(goland, t)
    F = np.column_stack([gust, np.zeros((t.size, wing.modes.count))])
    X = march(wing.system, t, pack(wing.system.param_specs, {"airspeed": V, "density": RHO}), F, initial="static").states
    np.testing.assert_allclose(p.get_val("march.states"), X, atol=1e-9 * np.abs(X).max())
    total, _ = station_load_history(wing.loads, wing.structure, wing.rfa, X, F, V, RHO)
    T0 = np.asarray(body_to_csn(problem.beam["node_euler_angles"][0]), float)
    Mc = p.get_val("loads.M_csn")[:, 0]
    np.testing.assert_allclose(Mc, total[:, 0, 3:] @ T0.T, atol=1e-9 * np.abs(Mc).max())
    assert np.abs(Mc).max() > 1e4


def test_component_partials(goland):
    t = np.linspace(0.0, 0.1, 6)
    p, _ = _chain(goland, t)
    p.set_val("compliance_csn", np.full((11, 3), 2e-9))   # Goland's beam is inextensible (zeros): a relative step needs a value
    p.run_model()
    data = p.check_partials(out_stream=None, includes=["proj", "loads"], method="fd", form="central", step=1e-6,
                            step_calc="rel_avg")
    for comp, d in data.items():
        for (of, wrt), v in d.items():
            an = v.get("J_fwd", v.get("J_rev"))
            # below what a relative step sees: an output change under 1e-7 of the output's size
            seen = 1e-7 * np.abs(p.get_val(f"{comp}.{of}")).max() / np.abs(p.get_val(f"{comp}.{wrt}")).max()
            assert np.abs(an - v["J_fd"]).max() <= 1e-5 * np.abs(v["J_fd"]).max() + seen, (comp, of, wrt)
    s = om.Problem()
    s.model.add_subsystem("sum", ModalLoadSum(num_times=3, num_nodes=4))
    s.setup(force_alloc_complex=True)
    s.set_val("sum.static_F_csn", np.random.default_rng(1).normal(size=(1, 4, 3)))
    s.run_model()
    for d in s.check_partials(out_stream=None, method="cs")["sum"].values():
        np.testing.assert_allclose(d["J_fwd"], d["J_fd"], atol=1e-12)


@pytest.mark.slow
@pytest.mark.parametrize("plunge", ["clamped", "free"])
def test_adjoint_totals_of_the_pegasus_dlm_gust_ks_match_central_differences(plunge):
    """The sized PEGASUS gust with --aero-theory dlm (trimmed 1 g on the VLM beam + the gust on the
    modal doublet lattice of the design), clamped and free in plunge (the plunge mode in the basis,
    the body's design-dependent mass in the projection), at a non-trivial design: the reverse-mode
    totals of the KS and the mass with respect to the four wall thicknesses equal central
    differences; the gust increment is a sizeable part of the root bending (the modal path is tested)."""
    pytest.importorskip("panelaero.DLM")
    from wingmdao.cases import pegasus
    from wingmdao.sizing import WALL_VARS, build_problem

    args = pegasus.PegasusOptions(loads="gust", aero="coupled", aero_theory="dlm", t_final=0.4, dt=0.04,
                                  gust_start=0.0, families="vm", plunge=plunge)
    setup = pegasus.build(args)
    rng = np.random.default_rng(7)
    setup.options.initial = {w: rng.uniform(0.004, 0.012, 19) for w in WALL_VARS}
    setup.options.disp = False
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options)
    prob.run_model()
    case = prob.model.cases.gust
    dyn = np.abs(case.modal.loads.get_val("M_csn")[:, 0, 0]).max()
    static = np.abs(case.static.internal_loads.get_val("M_csn")[0, 0, 0])
    assert dyn > 0.1 * static
    data = prob.check_totals(method="fd", form="central", step=1e-7, step_calc="rel_avg", out_stream=None)
    for key, d in data.items():
        an = d.get("J_rev", d.get("J_fwd"))
        assert np.abs(an - d["J_fd"]).max() <= 1e-5 * np.abs(d["J_fd"]).max(), key


def test_pressure_operators_are_cached_by_planform_and_equal_the_direct_solve():
    """The generalized forces of new modes on the same planform reuse the pressure operators; the
    operator times a normalwash equals panel_pressure's direct solve."""
    pytest.importorskip("panelaero.DLM")
    from wingmdao.aero import dlm
    from wingmdao.aero.vlm import build_lattice

    n = 6
    r = np.column_stack([np.zeros(n), np.linspace(0.0, 5.0, n), np.zeros(n)])
    lat = build_lattice(r, np.full(n, 1.0), np.full(n, 0.3), mach=0.3, n_chordwise=3, n_spanwise=1)
    w = np.random.default_rng(3).normal(size=(lat.span.size, 2))
    D = dlm.pressure_operators(lat, [0.0, 0.4], key="unit-test-planform")
    for i, kb in enumerate((0.0, 0.4)):
        np.testing.assert_allclose(D[i] @ w, dlm.panel_pressure(lat, kb, w), rtol=1e-10, atol=1e-12)
    assert dlm.pressure_operators(lat, [0.0, 0.4], key="unit-test-planform") is D
    rot = np.zeros((1, n, 3))
    disp = np.zeros((1, n, 3))
    disp[0, :, 2] = np.linspace(0.0, 1.0, n)
    before = len(dlm._OPERATORS)
    a = dlm.generalized_forces(r, np.full(n, 1.0), np.full(n, 0.3), disp, rot, mach=0.3, reduced_frequencies=[0.0, 0.2])
    after_a = len(dlm._OPERATORS)
    assert after_a <= before + 1                        # this planform's operators (cached already by another test)
    b = dlm.generalized_forces(r, np.full(n, 1.0), np.full(n, 0.3), 2 * disp, rot, mach=0.3,
                               reduced_frequencies=[0.0, 0.2])
    assert len(dlm._OPERATORS) == after_a               # one planform, two mode sets: no new operators
    np.testing.assert_allclose(b.Q, 4 * a.Q, rtol=1e-12)


def test_dlm_sizing_refuses_free_pitch_before_any_solve():
    from wingmdao.cases import pegasus

    with pytest.raises(ValueError, match="dlm"):
        pegasus.build(pegasus.PegasusOptions(loads="gust", aero="coupled", aero_theory="dlm", plunge="free",
                                             pitch="free", pitch_inertia=3.45e5, cg_x=0.67, tail_arm=12.0,
                                             tail_area=11.7, tail_lift_slope=4.0))


def test_free_plunge_projection_carries_half_the_aircraft(goland):
    """The free-plunge projection (plunge mode first, ``aircraft_mass``): at the reference design it
    equals the free modal wing's mass matrix (wing + half the body) and stiffness; on a heavier wing
    the plunge entry stays M / 2 (the body is the aircraft less the wings) while the wing-plunge
    coupling grows with the wing's mass."""
    from wingmdao.aero.modal_free import free_modal_dlm_wing

    problem, _, _ = goland
    beam = problem.beam
    mass = 1500.0
    wing = free_modal_dlm_wing(beam, problem.aero["chord"], problem.aero["ref_point"], 0.0, aircraft_mass=mass,
                               n_modes=3, reduced_frequencies=K_SET)
    P = modal_projection(beam, wing.modes, aircraft_mass=mass)
    M, K, _ = P.evaluate(beam)
    np.testing.assert_allclose(M, wing.structure.mass, rtol=1e-10, atol=1e-10 * np.abs(M).max())
    np.testing.assert_allclose(K, wing.structure.stiffness, rtol=1e-7, atol=1e-6 * np.abs(K).max())
    heavy = dict(beam, mass_per_length=1.3 * np.asarray(beam["mass_per_length"], dtype=float))
    M2, _, _ = P.evaluate(heavy)
    assert M2[0, 0] == pytest.approx(mass / 2, rel=1e-12)
    np.testing.assert_allclose(M2[0, 1:], 1.3 * M[0, 1:], rtol=1e-10)
