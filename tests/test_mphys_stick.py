"""The stick model in MPhys: the inertia-relief component, the stick builder's wing sections, and an
MPhys structural scenario of the PEGASUS half aircraft with check_totals."""

import numpy as np
import openmdao.api as om
import pytest

mphys = pytest.importorskip("mphys")

from mphys import MPhysVariables, Multipoint  # noqa: E402
from mphys.scenarios import ScenarioStructural  # noqa: E402

from wingmdao.cases import pegasus_stick  # noqa: E402
from wingmdao.cases.planform import G0  # noqa: E402
from wingmdao.components.inertia_relief import InertiaRelief  # noqa: E402
from wingmdao.mphys.builder import SECTION_TO_BEAM  # noqa: E402
from wingmdao.components.state_slice import BeamStateSlice  # noqa: E402
from wingmdao.mphys.stick import StickBuilder, pegasus_stick_builder  # noqa: E402

N = 5   # wing nodes of the small PEGASUS stick model


@pytest.fixture(scope="module")
def aircraft():
    return pegasus_stick.build(N)


def _wing_loads(n=N):
    f = np.zeros((n, 6))
    f[1:, 2] = 8000.0 / (n - 1)          # N up on the outer wing nodes
    f[1:, 0] = 150.0 / (n - 1)           # N aft (drag)
    f[1:, 4] = -400.0                    # N m nose down
    return f


def test_inertia_relief_partials_and_rigid_body_accelerations(aircraft):
    """check_partials (central differences), and the accelerations of the free half aircraft against
    its rigid-body dynamics from the model's own mass, CG and pitch inertia (sums over elements and
    lumped masses, StickAircraft): the CG accelerates by F/m + g and pitches by M_cg/I_yy (the
    deformation moves the CG a little: 1e-4 of the plunge acceleration, 2e-3 of the pitch's)."""
    s = aircraft.model.system
    g = np.array([0.0, 0.0, -G0])
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("ir", InertiaRelief(system=s, supports=pegasus_stick.SUPPORTS, param_values=aircraft.model.p,
                                                 forcing_values=aircraft.model.forcing(gravity=g)), promotes=["*"])
    prob.setup()
    f = _wing_loads()
    prob.set_val("wing_point_force", f[:, :3])
    prob.set_val("wing_point_moment", f[:, 3:])
    prob.run_model()
    ax, az, alpha = (float(prob.get_val(k)[0]) for k in ("frame_ax", "frame_az", "frame_alpha_y"))
    r = aircraft.nodes["wing"]
    F = f[:, :3].sum(axis=0)
    M = np.sum(np.cross(r - aircraft.cg, f[:, :3]) + f[:, 3:], axis=0)
    a_cg = np.array([ax, 0.0, az]) + np.cross([0.0, alpha, 0.0], aircraft.cg)
    assert a_cg[2] == pytest.approx(F[2] / aircraft.mass + g[2], rel=1e-4)
    assert a_cg[0] == pytest.approx(F[0] / aircraft.mass, abs=1e-4 * abs(a_cg[2]))
    assert alpha == pytest.approx(M[1] / aircraft.pitch_inertia, rel=2e-3)
    # central differences of residuals of size ~1e4 with step 1e-6: round-off ~1e-6 absolute (the
    # derivatives with respect to the wing's walls are checked through the totals of the scenario)
    data = prob.check_partials(method="fd", form="central", step=1e-6, out_stream=None)
    for _comp, d in data.items():
        for key, v in d.items():
            J, F_ = v["J_fwd"], v["J_fd"]
            scale = np.abs(F_).max()
            assert np.abs(J - F_).max() <= 1e-5 + 1e-6 * scale, (key, np.abs(J - F_).max(), scale)


def test_joined_beam_states_partials():
    p = om.Problem(reports=False)
    p.model.add_subsystem("c", BeamStateSlice(num_times=None, num_nodes=3, state_shape=(100,),
                                              columns=20 + np.arange(54), input_name="stick_states",
                                              output_name="wingmdao_states"))
    p.setup(force_alloc_complex=True)
    p.set_val("c.stick_states", np.arange(100.0))
    p.run_model()
    np.testing.assert_array_equal(p.get_val("c.wingmdao_states").ravel(), np.arange(20.0, 74.0))
    for _comp, d in p.check_partials(method="cs", out_stream=None).items():
        for key, v in d.items():
            assert np.abs(v["J_fwd"] - v["J_fd"]).max() < 1e-14, key


def test_builder_wing_sections_equal_the_stick_models(aircraft):
    """The pre-coupling's box sections (CasADi BoxSection with the wing's nonstructural mass) at the
    initial walls equal the stick model's wing parameters (numpy box_properties,
    cases.pegasus_stick.build)."""
    b = pegasus_stick_builder(N)
    b.initialize(None)
    p = om.Problem(reports=False)
    p.model.add_subsystem("pre", b.get_pre_coupling_subsystem(), promotes=["*"])
    p.setup()
    p.set_val("x_struct0", b.node_positions.ravel())
    p.run_model()
    wing = aircraft.model.params["wing"]
    for k in SECTION_TO_BEAM:
        np.testing.assert_allclose(p.get_val(k), np.asarray(wing[k]).reshape(p.get_val(k).shape), rtol=1e-10,
                                   atol=1e-12 * np.abs(np.asarray(wing[k])).max(), err_msg=k)


def test_builder_bad_input(aircraft):
    m = aircraft.model
    with pytest.raises(ValueError, match="wing = 'main' is not a beam of the model"):
        StickBuilder(m, 0.4, 0.1, 0.003, None, pegasus_stick.SUPPORTS, wing="main")
    with pytest.raises(ValueError, match="2 supports for 3 accelerations"):
        StickBuilder(m, 0.4, 0.1, 0.003, None, pegasus_stick.SUPPORTS[:2])
    with pytest.raises(ValueError, match="must lie in body axes"):
        StickBuilder(m, 0.4, 0.1, 0.003, None, pegasus_stick.SUPPORTS, wing="fuselage")


@pytest.fixture(scope="module")
def scenario():
    class Top(Multipoint):
        def setup(self):
            b = pegasus_stick_builder(N)
            b.initialize(self.comm)
            dvs = self.add_subsystem("dvs", om.IndepVarComp(), promotes=["*"])
            dvs.add_output("dv_struct", b.get_initial_dvs(), units="m", desc="wing wall thicknesses")
            dvs.add_output("f_aero_struct", _wing_loads().ravel(), desc="wing nodal forces (N) and moments (N*m)")
            self.add_subsystem("mesh", b.get_mesh_coordinate_subsystem())
            self.mphys_add_scenario("cruise", ScenarioStructural(struct_builder=b))
            self.connect(f"mesh.{MPhysVariables.Structures.Mesh.COORDINATES}",
                         f"cruise.{MPhysVariables.Structures.COORDINATES}")
            self.connect("dv_struct", "cruise.dv_struct")
            self.connect("f_aero_struct", "cruise.f_aero_struct")

    prob = om.Problem(Top(), reports=False)
    prob.setup(mode="rev")
    prob.run_model()
    return prob


def test_stick_scenario_loads_and_displacements(scenario, aircraft):
    """The wing's loads reach the whole aircraft: plunge acceleration F/m + g at the CG, the wing
    bends up relative to the fuselage supports, its KS is that of a loaded wing."""
    f = _wing_loads()
    az = float(scenario.get_val("cruise.frame_az")[0]) + float(scenario.get_val("cruise.frame_alpha_y")[0]) * (
        -aircraft.cg[0])
    assert az == pytest.approx(f[:, 2].sum() / aircraft.mass - G0, rel=1e-4)
    u = scenario.get_val("cruise.u_struct").reshape(N, 6)
    assert u[-1, 2] > 0.01 and u[-1, 3] > 0.0          # tip up, rotation about x positive (bending up)
    # the wing root moves with the fuselage, which bends between its supports at the nose and the tail cone
    assert 0.0 < np.abs(u[0, :3]).max() < 0.05 * u[-1, 2]
    assert -1.0 < scenario.get_val("cruise.ks_vm")[0] < 0.0


@pytest.mark.parametrize("wrt, step", [("dv_struct", 1e-6), ("f_aero_struct", 1e-2)])
def test_stick_scenario_totals(scenario, wrt, step):
    """Reverse mode (the inertia relief's transposed LU inside MPhys' coupling group) against central
    differences: the KS, the wing's mass, the plunge acceleration and the displacements with respect
    to the wing's walls (m) and loads (N, N m)."""
    data = scenario.check_totals(of=["cruise.ks_vm", "cruise.struct_mass", "cruise.frame_az", "cruise.u_struct"],
                                 wrt=[wrt], method="fd", form="central", step=step, out_stream=None)
    for key, v in data.items():
        J, F = v["J_rev"] if "J_rev" in v else v["J_fwd"], v["J_fd"]
        scale = np.abs(F).max()
        if scale == 0.0:
            assert np.abs(J).max() == 0.0, key
            continue
        nontrivial = np.abs(F) > 1e-3 * scale
        assert np.all(np.abs(J - F)[nontrivial] <= 1e-4 * np.abs(F)[nontrivial]), key
        assert np.abs(J - F).max() <= 1e-5 * scale, key


@pytest.fixture(scope="module")
def coupled_stick():
    pytest.importorskip("openaerostruct")
    from wingmdao.mphys.scenario import stick_aerostructural_problem

    prob = stick_aerostructural_problem(num_wing_nodes=8, iprint=-1)
    prob.run_model()
    return prob


def test_stick_aerostructural_scenario_balances(coupled_stick):
    """OpenAeroStruct's VLM on the PEGASUS wing coupled with the stick model: NLBGS converges, the beam
    takes the lattice's force (mirror image), and the whole aircraft accelerates as Newton's second
    law gives from the transferred lift and the model's mass and CG."""
    aircraft = pegasus_stick.build(8)
    assert coupled_stick.model.cruise.coupling.nonlinear_solver._iter_count < 25
    fs = coupled_stick.get_val("cruise.f_aero_struct").reshape(-1, 6)
    fa = coupled_stick.get_val("cruise.f_aero").reshape(-1, 3)
    assert fs[:, :3].sum(axis=0) == pytest.approx(fa.sum(axis=0) * [1, -1, 1], rel=1e-12)
    az = float(coupled_stick.get_val("cruise.frame_az")[0])
    alpha = float(coupled_stick.get_val("cruise.frame_alpha_y")[0])
    a_cg = np.array([0.0, 0.0, az]) + np.cross([0.0, alpha, 0.0], aircraft.cg)
    assert a_cg[2] == pytest.approx(fs[:, 2].sum() / aircraft.mass - G0, rel=1e-4)
    u = coupled_stick.get_val("cruise.u_struct").reshape(-1, 6)
    assert u[-1, 2] > 0.05                                       # the wing bends up under lift
    ua = coupled_stick.get_val("cruise.u_aero").reshape(2, -1, 3)
    assert ua[:, 0, 2] == pytest.approx(u[-1, 2], rel=0.05)     # OAS tip (index 0) follows the beam tip


def test_stick_aerostructural_totals(coupled_stick):
    data = coupled_stick.check_totals(of=["cruise.ks_vm", "cruise.frame_az", "cruise.wing.CL"],
                                      wrt=["dv_struct", "aoa"], method="fd", form="central", step=1e-6,
                                      out_stream=None)
    for key, v in data.items():
        J, F = v["J_rev"] if "J_rev" in v else v["J_fwd"], v["J_fd"]
        scale = np.abs(F).max()
        nontrivial = np.abs(F) > 1e-3 * scale
        assert scale > 0.0 and np.all(np.abs(J - F)[nontrivial] <= 1e-4 * np.abs(F)[nontrivial]), key
