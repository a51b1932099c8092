"""Checks of the hex27 solid solver against closed forms (wingmdao.verification.solid3d)."""

import numpy as np
import pytest

from wingmdao.verification import solid3d
from wingmdao.verification.wingbox_solid import solve_wingbox


def bar_mesh(length, width, height, n_span, n_width, n_height):
    """Solid rectangular bar along y, root face at y = 0, centred on the y axis."""
    y = np.linspace(0.0, length, 2 * n_span + 1)
    x = np.linspace(-width / 2, width / 2, 2 * n_width + 1)
    z = np.linspace(-height / 2, height / 2, 2 * n_height + 1)
    Y, X, Z = np.meshgrid(y, x, z, indexing="ij")
    return solid3d.structured_hex27_mesh(np.stack([X, Y, Z], axis=-1))


def cantilever_tip_deflection(nu, n_span=40, n_cross=4):
    L, b, h, E, P = 2.0, 0.1, 0.1, 70e9, 1000.0
    mesh = bar_mesh(L, b, h, n_span, n_cross, n_cross)
    K = solid3d.assemble_stiffness(mesh, E, nu)
    tip = mesh.slice_faces(2 * n_span)
    f = solid3d.face_load_vector(mesh, tip, force=(0.0, 0.0, P))
    u = solid3d.solve_linear(K, f, solid3d.node_dofs(mesh.slice_nodes(0)))
    cut = solid3d.cut_average(mesh, tip, u)
    # Euler-Bernoulli + Timoshenko shear with Cowper's rectangle coefficient
    G, I, A = E / (2 * (1 + nu)), b * h**3 / 12, b * h
    kappa = 10 * (1 + nu) / (12 + 11 * nu)
    closed = P * L**3 / (3 * E * I) + P * L / (kappa * G * A)
    return cut, closed, P * L**2 / (2 * E * I)


def test_cantilever_block_poisson_free_matches_timoshenko():
    """nu = 0: no clamp (Poisson) restraint, the solid must reproduce the closed form closely."""
    cut, closed, slope = cantilever_tip_deflection(0.0)
    assert cut["displacement"][2] == pytest.approx(closed, rel=1e-3)
    assert cut["rotation"][0] == pytest.approx(slope, rel=5e-3)   # tip slope, + about x
    assert abs(cut["displacement"][0]) < 1e-9 * closed


def test_cantilever_block_aluminium_within_one_percent():
    cut, closed, _ = cantilever_tip_deflection(0.33)
    assert cut["displacement"][2] == pytest.approx(closed, rel=1e-2)


def distorted_block(seed=3):
    rng = np.random.default_rng(seed)
    mesh = bar_mesh(1.0, 0.7, 0.5, 2, 2, 2)
    X = mesh.nodes
    interior = np.all((X > X.min(axis=0) + 1e-9) & (X < X.max(axis=0) - 1e-9), axis=1)
    mesh.nodes = X + np.where(interior[:, None], rng.uniform(-0.04, 0.04, X.shape), 0.0)
    solid3d.check_jacobians(mesh)
    return mesh, interior


def test_patch_test_uniform_strain_is_exact():
    """Linear displacement on the boundary of a distorted mesh: exact interior field and strain."""
    mesh, interior = distorted_block()
    B = np.array([[1.0, 2.0, -0.5], [0.3, -1.2, 0.8], [-0.7, 0.4, 1.5]]) * 1e-3
    exact = (mesh.nodes @ B.T + np.array([1e-3, -2e-3, 5e-4])).ravel()
    boundary = np.nonzero(~interior)[0]
    fixed = solid3d.node_dofs(boundary)
    K = solid3d.assemble_stiffness(mesh, 70e9, 0.33)
    u = solid3d.solve_linear(K, np.zeros(mesh.num_dof), fixed, exact[fixed])
    assert np.max(np.abs(u - exact)) < 1e-12
    strain = solid3d.element_strains(mesh, u)
    expected = [B[0, 0], B[1, 1], B[2, 2], B[1, 2] + B[2, 1], B[0, 2] + B[2, 0], B[0, 1] + B[1, 0]]
    assert np.max(np.abs(strain - expected)) < 1e-12


def test_rigid_body_motion_is_strain_free_and_cut_recovers_it():
    mesh, _ = distorted_block()
    K = solid3d.assemble_stiffness(mesh, 70e9, 0.33)
    a, w = np.array([0.1, -0.2, 0.3]), np.array([0.02, -0.01, 0.03])
    u = (a + np.cross(w, mesh.nodes)).ravel()
    assert np.max(np.abs(K @ u)) < 1e-12 * np.abs(K).max()
    cut = solid3d.cut_average(mesh, mesh.slice_faces(4), u)
    assert np.allclose(cut["displacement"], a + np.cross(w, cut["centroid"]), atol=1e-14)
    assert np.allclose(cut["rotation"], w, atol=1e-13)


def test_face_load_resultant_is_exact():
    mesh = bar_mesh(1.0, 0.6, 0.3, 1, 3, 2)
    faces = mesh.slice_faces(2)
    F, M, ref = np.array([1.0, -2.0, 3.0]), np.array([0.5, 4.0, -1.5]), np.array([0.1, 1.0, -0.2])
    f = solid3d.face_load_vector(mesh, faces, F, M, ref_point=ref).reshape(-1, 3)
    assert np.allclose(f.sum(axis=0), F, atol=1e-12)
    assert np.allclose(np.cross(mesh.nodes - ref, f).sum(axis=0), M, atol=1e-12)


def test_mesh_volume_and_bad_input():
    mesh = bar_mesh(2.0, 0.3, 0.2, 2, 1, 1)
    assert solid3d.mesh_volume(mesh) == pytest.approx(2.0 * 0.3 * 0.2, rel=1e-13)
    with pytest.raises(ValueError, match="nu"):
        solid3d.lame_parameters(70e9, 0.5)
    with pytest.raises(ValueError, match="E must"):
        solid3d.lame_parameters(-1.0, 0.3)
    inverted = mesh.nodes.copy()
    inverted[:, 0] *= -1.0
    with pytest.raises(ValueError, match="Jacobian"):
        solid3d.check_jacobians(solid3d.HexMesh(inverted, mesh.elements))
    with pytest.raises(ValueError, match="odd"):
        solid3d.structured_hex27_mesh(np.zeros((4, 3, 3, 3)))


def thin_wall_shear_area(w, h, t_spar, t_skin):
    """Shear area I^2 / integral (Q/t)^2 t ds of the thin-walled box midline (Jourawski flows)."""
    b, hm = w - t_spar, h - t_skin
    I = (w * h**3 - (w - 2 * t_spar) * (h - 2 * t_skin) ** 3) / 12
    s = np.linspace(0.0, b / 2, 4001)                 # upper skin, from the centre line
    q_skin = t_skin * hm / 2 * s
    z = np.linspace(0.0, hm / 2, 4001)                # front spar, from mid-height
    q_web = q_skin[-1] + t_spar * (hm**2 / 4 - z**2) / 2
    energy = 4 * (np.trapezoid(q_skin**2, s) / t_skin + np.trapezoid(q_web**2, z) / t_spar)
    return I, I**2 / energy


def test_prismatic_box_tip_deflection_closed_form():
    """Box 3 x 0.5 m, spars 0.2, skins 0.1, L = 10 m, tip load 1e5 N (App. D.1 prismatic).

    delta = P L^3 / (3 E I) + P L / (G A_s): A_s from the thin-walled shear flows (the
    shear carried by skins and spars). The wide skins make the shear term 5 % of the total;
    near the clamp the shear warping is restrained, so the solid is a little stiffer.
    """
    E, nu, P, L = 70e9, 0.33, 1e5, 10.0
    G = E / (2 * (1 + nu))
    I, A_s = thin_wall_shear_area(3.0, 0.5, 0.2, 0.1)
    closed = P * L**3 / (3 * E * I) + P * L / (G * A_s)
    lower = P * L**3 / (3 * E * I) + P * L / (G * 2 * 0.2 * 0.5)   # shear in the spar webs only
    res = solve_wingbox("prismatic", tip_force=(0, 0, P), mesh_size=0.5, tip_load="traction")
    tip = res["displacement"][2, 2]
    assert tip == pytest.approx(closed, rel=0.03)
    assert lower < tip < closed


def test_cut_inside_elements_is_exact_for_rigid_motion_and_matches_node_slices():
    from wingmdao.verification import wingbox_solid as wb

    cs = wb.box_sections("combined")
    mesh, cs_index = wb.box_mesh(cs, 0.2, 0.1, wb.default_divisions(0.5, span_size=1.0))
    a, w = np.array([0.1, -0.2, 0.3]), np.array([0.02, -0.01, 0.03])
    u = (a + np.cross(w, mesh.nodes)).ravel()
    for y in (1.3, 5.55):
        cut = solid3d.cut_average_at(mesh, y, u)
        width = np.interp(y, [0, 3, 7, 10], [3.0, 2.5, 2.0, 1.5])
        assert cut["area"] == pytest.approx(0.5 * width - (width - 0.4) * 0.3, rel=1e-12)
        assert np.allclose(cut["rotation"], w, atol=1e-13)
        assert np.allclose(cut["displacement"], a + np.cross(w, cut["centroid"]), atol=1e-14)
    with pytest.raises(ValueError, match=r"y must be in \[0.0, 10.0\] m"):
        solid3d.cut_average_at(mesh, 10.5, u)
    # a deformation field: at a node slice the in-element cut equals the face cut
    res = wb.solve_wingbox("combined", mesh_size=0.5, span_size=1.0, cuts_y=[3.0, 7.0])
    assert np.allclose(res["cuts_displacement"], res["displacement"][:2], rtol=1e-10, atol=1e-15)
    assert np.allclose(res["cuts_rotation"], res["rotation"][:2], rtol=1e-10, atol=1e-15)
