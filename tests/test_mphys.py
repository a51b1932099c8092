"""MPhys builder, rigid-link transfer and the OpenAeroStruct VLM + beam aerostructural scenario."""

import numpy as np
import openmdao.api as om
import pytest

mphys = pytest.importorskip("mphys")
pytest.importorskip("openaerostruct")

from wingmdao.materials import ALUMINIUM  # noqa: E402
from wingmdao.mphys.builder import SECTION_TO_BEAM, BeamDisplacements, StructInputs, WingmdaoBuilder, jig_euler_angles  # noqa: E402
from wingmdao.mphys.transfer import (RigidLinkDisplacementTransfer, RigidLinkLoadTransfer,  # noqa: E402
                                     rigid_links)

RNG = np.random.default_rng(3)


def _transfer_problem(mirror, n=4, m=10):
    xs = np.column_stack([np.zeros(n), np.linspace(0, 3, n), np.zeros(n)])
    xa = np.column_stack([RNG.uniform(-0.5, 0.5, m), RNG.uniform(0, 3, m), RNG.uniform(-0.1, 0.1, m)])
    if mirror:
        xa[:, 1] *= -1
    links = rigid_links(xs, xa * ([1, -1, 1] if mirror else 1))
    p = om.Problem(reports=False)
    kw = dict(links=links, num_struct_nodes=n, mirror_y=mirror)
    p.model.add_subsystem("d", RigidLinkDisplacementTransfer(**kw), promotes_inputs=["x_aero0", "x_struct0"])
    p.model.add_subsystem("l", RigidLinkLoadTransfer(**kw), promotes_inputs=["x_aero0", "x_struct0"])
    p.setup(force_alloc_complex=True)
    p.set_val("x_aero0", xa.ravel())
    p.set_val("x_struct0", xs.ravel())
    p.set_val("d.u_struct", RNG.normal(size=6 * n) * 0.1)
    p.set_val("l.f_aero", RNG.normal(size=3 * m))
    p.run_model()
    return p, xs, xa, links


@pytest.mark.parametrize("mirror", [False, True])
def test_transfer_partials_and_virtual_work(mirror):
    p, xs, xa, links = _transfer_problem(mirror)
    data = p.check_partials(method="cs", out_stream=None)
    for comp, d in data.items():
        for key, v in d.items():
            assert np.abs(v["J_fwd"] - v["J_fd"]).max() <= 1e-10 * max(1.0, np.abs(v["J_fd"]).max()), (comp, key)
    # consistency: work of the aero forces on u_aero = work of the beam loads on u_struct
    fa, ua = p.get_val("l.f_aero"), p.get_val("d.u_aero")
    fs, us = p.get_val("l.f_aero_struct"), p.get_val("d.u_struct")
    assert fa @ ua == pytest.approx(fs @ us, rel=1e-12)


def test_rigid_rotation_moves_aero_points_rigidly():
    """A small rigid rotation theta of the beam about its node: u_a = theta x (x_a - x_b) exactly."""
    p, xs, xa, links = _transfer_problem(False)
    n = xs.shape[0]
    theta = np.array([0.01, -0.02, 0.005])
    u = np.zeros((n, 6))
    u[:, 3:] = theta
    u[:, :3] = np.cross(theta, xs - xs[0])       # rigid rotation about node 0
    p.set_val("d.u_struct", u.ravel())
    p.run_model()
    expect = np.cross(theta, xa - xs[0])
    assert np.allclose(p.get_val("d.u_aero").reshape(-1, 3), expect, atol=1e-14)


def test_coincident_nodes_rejected():
    xs = np.array([[0, 0, 0], [0, 1, 0], [0, 1, 0], [0, 2, 0.0]])
    with pytest.raises(ValueError, match="beam nodes 1 and 2 coincide"):
        rigid_links(xs, np.zeros((3, 3)))
    with pytest.raises(ValueError, match="coincide"):
        WingmdaoBuilder(xs, 0.4, 0.1, 0.003, ALUMINIUM)


def test_wrong_load_shape_rejected_at_setup():
    p = om.Problem(reports=False)
    ivc = p.model.add_subsystem("ivc", om.IndepVarComp())
    ivc.add_output("f", np.zeros((5, 3)))
    ivc.add_output("x", np.zeros(15), units="m")
    p.model.add_subsystem("s", StructInputs(num_nodes=5))
    p.model.connect("ivc.f", "s.f_aero_struct")
    p.model.connect("ivc.x", "s.x_struct0")
    with pytest.raises(ValueError, match=r"f_aero_struct has 15 entries.*expected 30"):
        p.setup()
        p.final_setup()


def test_mismatched_node_counts_rejected():
    from openaerostruct.mphys import AeroBuilder

    from wingmdao.mphys.builder import BeamRigidLinkBuilder
    from wingmdao.mphys.scenario import beam_nodes_from_oas_mesh, rect_wing_surface

    surf = rect_wing_surface(num_y=7)
    aero = AeroBuilder([surf])
    aero.initialize(om.Problem(reports=False).comm)
    struct = WingmdaoBuilder(beam_nodes_from_oas_mesh(surf["mesh"]), 0.4, 0.1, 0.003, ALUMINIUM)
    xfer = BeamRigidLinkBuilder(aero, struct, surf["mesh"].reshape(-1, 3)[:-2], mirror_y=True)
    with pytest.raises(ValueError, match="aerodynamic builder has 8 nodes but x_aero0 has 6"):
        xfer.initialize(None)


def test_displacement_and_input_partials():
    n = 4
    x0 = np.column_stack([0.1 * np.arange(n), np.linspace(0, 3, n), 0.05 * np.arange(n)])
    th0 = jig_euler_angles(x0)
    p = om.Problem(reports=False)
    p.model.add_subsystem("u", BeamDisplacements(node_euler_angles=th0))
    p.model.add_subsystem("s", StructInputs(num_nodes=n))
    p.setup(force_alloc_complex=True)
    p.set_val("u.wingmdao_states", RNG.normal(size=(n, 18)))
    p.set_val("s.f_aero_struct", RNG.normal(size=6 * n))
    p.set_val("s.x_struct0", x0.ravel())
    p.run_model()
    for comp, d in p.check_partials(method="cs", out_stream=None).items():
        for key, v in d.items():
            assert np.abs(v["J_fwd"] - v["J_fd"]).max() <= 1e-12, (comp, key)


def test_rotation_map_is_the_body_rotation_vector():
    """For a beam along y the rotation-vector map is the identity; for a beam along x (psi = -90 deg
    would be singular, so take 45 deg sweep) it maps a pure twist increment to a rotation about the
    beam axis."""
    from wingmdao.mphys.builder import rotation_vector_map

    A = rotation_vector_map(np.zeros((1, 3)))[0]
    assert np.allclose(A, np.eye(3))
    t = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)     # swept 45 deg aft? tangent in body axes
    th = jig_euler_angles(np.array([[0, 0, 0], t]))
    A = rotation_vector_map(th)
    assert np.allclose(A[0] @ [0.0, 1.0, 0.0], t)   # twist increment -> rotation about the axis


def test_cantilever_tip_load_matches_euler_bernoulli():
    """The coupling subsystem alone: a tip force on a straight box beam, tip deflection P L^3/(3EI)
    (Euler-Bernoulli; shear deflection P L/(G A_s) is < 0.1 % here) and u_struct rotation P L^2/(2EI)."""
    from wingmdao.section.box import box_properties

    n, L, P = 11, 5.0, 200.0
    nodes = np.column_stack([np.zeros(n), np.linspace(0, L, n), np.zeros(n)])
    b = WingmdaoBuilder(nodes, width=0.4, height=0.12, thickness=0.003, material=ALUMINIUM)
    p = om.Problem(reports=False)
    sec = list(SECTION_TO_BEAM)
    p.model.add_subsystem("pre", b.get_pre_coupling_subsystem(),
                          promotes=["dv_struct", "x_struct0", "struct_mass", *sec])
    p.model.add_subsystem("coupling", b.get_coupling_group_subsystem(),
                          promotes=["x_struct0", "f_aero_struct", "u_struct", "wingmdao_states", *sec])
    p.model.add_subsystem("post", b.get_post_coupling_subsystem(), promotes=["dv_struct", "wingmdao_states", "ks_vm"])
    p.setup()
    f = np.zeros((n, 6))
    f[-1, 2] = P
    p.set_val("f_aero_struct", f.ravel())
    p.set_val("x_struct0", nodes.ravel())
    p.run_model()
    u = p.get_val("u_struct").reshape(n, 6)
    EI = float(np.asarray(box_properties(0.4, 0.12, 0.003, 0.003, 0.003, 0.003, ALUMINIUM)["EIxx"]))
    assert u[-1, 2] == pytest.approx(P * L**3 / (3 * EI), rel=2e-3)
    assert u[-1, 3] == pytest.approx(P * L**2 / (2 * EI), rel=2e-3)
    assert p.get_val("struct_mass")[0] == pytest.approx(ALUMINIUM.rho * L * 2 * (0.4 * 0.003 + 0.114 * 0.003), rel=1e-2)


@pytest.fixture(scope="module")
def coupled():
    from wingmdao.mphys.scenario import aerostructural_problem

    prob = aerostructural_problem(iprint=-1)
    prob.run_model()
    return prob


def test_scenario_converges_and_balances(coupled):
    solver = coupled.model.cruise.coupling.nonlinear_solver
    assert solver._iter_count < 25
    fs = coupled.get_val("cruise.f_aero_struct").reshape(-1, 6)
    fa = coupled.get_val("cruise.f_aero").reshape(-1, 3)
    # the beam is the y-mirror image of OpenAeroStruct's left half-wing
    assert fs[:, :3].sum(axis=0) == pytest.approx(fa.sum(axis=0) * [1, -1, 1], rel=1e-12)
    u = coupled.get_val("cruise.u_struct").reshape(-1, 6)
    assert u[-1, 2] > 0.01      # the wing bends up under lift
    ua = coupled.get_val("cruise.u_aero").reshape(2, -1, 3)
    assert ua[:, 0, 2] == pytest.approx(u[-1, 2], rel=0.05)   # OAS tip (index 0) follows the beam tip


def test_scenario_totals(coupled):
    data = coupled.check_totals(of=["cruise.ks_vm", "cruise.struct_mass", "cruise.wing.CL"],
                                wrt=["dv_struct", "aoa"], method="fd", form="central", step=1e-6,
                                out_stream=None)
    for key, v in data.items():
        J, F = v["J_rev"] if "J_rev" in v else v["J_fwd"], v["J_fd"]
        scale = np.abs(F).max()
        if scale == 0.0:
            assert np.abs(J).max() == 0.0
            continue
        nontrivial = np.abs(F) > 1e-6 * scale
        assert np.all(np.abs(J - F)[nontrivial] <= 1e-4 * np.abs(F)[nontrivial]), key


def test_dv_split_partials_and_bad_thickness():
    from wingmdao.mphys.builder import DvSplit

    n = 3
    dv = RNG.uniform(1e-3, 1e-2, 4 * n)
    p = om.Problem(reports=False)
    p.model.add_subsystem("d", DvSplit(num_nodes=n, initial=dv))
    p.setup(force_alloc_complex=True)
    p.run_model()
    np.testing.assert_array_equal(p.get_val("d.t_front_spar"), dv[2 * n:3 * n])
    for comp, d in p.check_partials(method="cs", out_stream=None).items():
        for key, v in d.items():
            assert v["abs error"].forward < 1e-12, (comp, key)
    p.set_val("d.dv_struct", -dv)
    with pytest.raises(om.AnalysisError, match="dv_struct"):
        p.run_model()
