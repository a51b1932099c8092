"""Joined beams (wingmdao.beam.joints): rigid joints and hinges against single beams, Euler-Bernoulli
closed forms of cantilevers and frames, and the discrete adjoint against central differences.

References coded here: the cantilever PL^3/3EI and 1.8751^2 sqrt(EI/(mu L^4)); the free-free beam
beta L = 4.7300; the statically determinate L-frame by the unit-load method; the in-plane
frequency equation of the clamped L-frame (Euler-Bernoulli members, inextensible, solved as an
8 x 8 determinant of the members' exact harmonic solutions); the pinned-free beam beta L = 3.9266
(R. D. Blevins, Formulas for Natural Frequency and Mode Shape, Van Nostrand Reinhold, 1979,
Table 8-1, case "pinned-free").
"""

import numpy as np
import pytest
import scipy.optimize as sopt

from wingmdao.beam.joints import FUSELAGE_AXES, Beam, JoinedBeamModel, Joint, build_joined_system
from wingmdao.beam.residual import StrainRateDamping, build_beam_system
from wingmdao.beam.static import BeamModel, beam_parameters, straight_beam
from wingmdao.stability.eigen import eigenmodes
from wingmdao.timemarch import lu_orders, static_lu
from wingmdao.timemarch.adjoint import LinearizedHistory
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import layout, pack

ROT = np.diag([1e-9, 1e-3, 1e-9])   # small rotary inertia per length (kg m), csn


def _frequencies(system, p, q, x0=None):
    """Circular frequencies (rad/s, ascending) of the elastic modes about the jig (static=False)
    or the static state, from the flutter linearization (wingmdao.stability.eigen)."""
    modes = eigenmodes(system, p, q, x0, static=x0 is None, method="sparse", sigma=1.0, count=12)
    w = modes.frequency
    low = (w > 1e-3) & (w < 1e4)
    assert np.all(np.abs(modes.damping[low]) < 1e-5 * w[low])    # undamped (to the Arnoldi accuracy)
    return np.sort(w[low])


def _split_cantilever(n, k, L, **section):
    r0, th0 = straight_beam(n, L)
    single = BeamModel(beam_parameters(r0, th0, **section))
    joined = JoinedBeamModel([Beam("inner", k + 1), Beam("outer", n - k, root="free")],
                             [Joint("inner", -1, "outer", 0)],
                             {"inner": beam_parameters(r0[:k + 1], th0[:k + 1], **section),
                              "outer": beam_parameters(r0[k:], th0[k:], **section)})
    return single, joined


SECTION = dict(EI_cc=2.0e6, GJ=1.5e6, EI_nn=1.8e7, EA=1e11, mass_per_length=20.0, inertia_per_length=ROT)


def test_split_cantilever_equals_single_beam_static_and_modes():
    n, k, L = 21, 8, 10.0
    single, joined = _split_cantilever(n, k, L, **SECTION)
    for load in ([0.0, 0.0, 2e2], [0.0, 0.0, 1.5e4], [3e3, 1e3, 1e4]):    # small, large (25 % L), 3-D
        pf = np.zeros((n, 3))
        pf[-1] = load
        ref = single.solve(point_force=pf, load_steps=2)
        out = joined.solve({"outer": {"point_force": pf[k:]}}, load_steps=2)
        np.testing.assert_allclose(out["outer"]["r"], ref["r"][k:], rtol=0, atol=1e-10)
        np.testing.assert_allclose(out["inner"]["r"], ref["r"][:k + 1], rtol=0, atol=1e-10)
        np.testing.assert_allclose(out["inner"]["M"], ref["M"][:k + 1], rtol=0, atol=1e-6)
        # the joint carries the inner beam's tip resultant into the outer beam's root
        np.testing.assert_allclose(out["joints"]["force_a"][0], ref["F"][k], atol=1e-8)
        np.testing.assert_allclose(out["joints"]["moment_b"][0], -ref["M"][k], atol=1e-6)
    # small load against the closed form (O(h^2) discretisation, docs/beam-theory.md section 8)
    pf = np.zeros((n - k, 3))
    pf[-1, 2] = 2e2
    tip = joined.solve({"outer": {"point_force": pf}})["outer"]["r"][-1, 2]
    assert tip == pytest.approx(2e2 * L**3 / (3 * SECTION["EI_cc"]), rel=1e-3)
    # modes: the same spectrum as the single beam, first flap mode against Euler-Bernoulli
    q1 = joined.forcing()
    w_joined = _frequencies(joined.system, joined.p, q1, x0=joined.system.jig_state(joined.p))
    w_single = _frequencies(single.system, single.p, np.zeros(single.system.n_forcing), x0=single.jig())
    np.testing.assert_allclose(w_joined[:6], w_single[:6], rtol=1e-7)
    flap = 1.8751**2 * np.sqrt(SECTION["EI_cc"] / (SECTION["mass_per_length"] * L**4))
    assert w_joined[0] == pytest.approx(flap, rel=2e-3)


def _free_free_flap_frequencies(n1, n2, L=10.0):
    """Two free beams of ``n1`` and ``n2`` nodes joined end to end into one of length ``L``: (the
    number of zero eigenvalues, the three lowest flap (z) bending frequencies in rad/s; the in-plane
    ones, EI_nn, told apart by their mode shapes). Shared with benchmarks/joints_verification.py."""
    scale = np.sqrt(SECTION["EI_cc"] / (SECTION["mass_per_length"] * L**4))
    r0, th0 = straight_beam(n1 + n2 - 1, L)
    model = JoinedBeamModel([Beam("left", n1, root="free"), Beam("right", n2, root="free")],
                            [Joint("left", -1, "right", 0)],
                            {"left": beam_parameters(r0[:n1], th0[:n1], **SECTION),
                             "right": beam_parameters(r0[n1 - 1:], th0[n1 - 1:], **SECTION)})
    x0 = model.system.jig_state(model.p)
    modes = eigenmodes(model.system, model.p, model.forcing(), x0, static=False, method="sparse", sigma=5.0, count=20)
    freq = modes.frequency
    z = [model.system.node_index(b, i) + 2 for b, n in (("left", n1), ("right", n2)) for i in range(n)]
    x = [i - 2 for i in z]
    flap = (freq > 1e-6 * scale) & (np.linalg.norm(modes.vectors[z], axis=0) > np.linalg.norm(modes.vectors[x], axis=0))
    return int(np.sum(freq < 1e-6 * scale)), np.sort(freq[flap])[:3]


def test_free_free_beam_of_two_joined_beams():
    """Two free beams joined end to end: six rigid-body modes (each a double zero eigenvalue), then
    beta L = 4.7300, 7.8532, 10.9956 of the flap (z) bending modes (the in-plane ones, EI_nn, are told
    apart by their mode shapes); 20 and 40 elements, O(h^2) errors, Richardson-extrapolated."""
    L = 10.0
    scale = np.sqrt(SECTION["EI_cc"] / (SECTION["mass_per_length"] * L**4))
    ref = np.array([4.7300, 7.8532, 10.9956]) ** 2 * scale
    w = {}
    for n1, n2 in ((9, 13), (17, 25)):
        zero, w[n1 + n2 - 2] = _free_free_flap_frequencies(n1, n2, L)
        assert zero == 12
    np.testing.assert_allclose(w[40], ref, rtol=1.3e-2)
    # the third mode keeps an O(h^4) remainder (docs/stick-model.md, "Checks")
    assert np.all(np.abs((4 * w[40] - w[20]) / 3 / ref - 1) < [2e-4, 2e-4, 1e-3])


# ----------------------------------------------------------------------------- L-shaped frame
H, LA = 3.0, 4.0                                           # column height (z), arm length (y)
COLUMN = dict(EI_cc=2.0e6, EI_nn=5.0e6, GJ=1.5e6, EA=1e10)
ARM = dict(EI_cc=1.0e6, EI_nn=3.0e6, GJ=0.8e6, EA=1e10)


def _l_frame(n1=13, n2=17, hinge=None, **mass):
    rc, thc = straight_beam(n1, H, (0.0, 0.0, 1.0))
    ra, tha = straight_beam(n2, LA, (0.0, 1.0, 0.0))
    ra = ra + [0.0, 0.0, H]
    joint = Joint("column", -1, "arm", 0) if hinge is None else Joint("column", -1, "arm", 0, **hinge)
    return JoinedBeamModel([Beam("column", n1), Beam("arm", n2, root="free")], [joint],
                           {"column": beam_parameters(rc, thc, **COLUMN, **mass.get("column", {})),
                            "arm": beam_parameters(ra, tha, **ARM, **mass.get("arm", {}))})


def test_l_frame_tip_loads_against_unit_load_method():
    """Column along z clamped at its base, arm along y, rigid joint: tip load in-plane (-z) and
    out-of-plane (x). Unit-load method (shear-rigid): in-plane PL^3/3EI_arm + PL^2H/EI_col + PH/EA;
    out-of-plane PL^3/3EI_arm + PL^2H/GJ_col (column torsion) + PH^3/3EI_col."""
    model = _l_frame()
    P = 10.0
    pf = np.zeros((17, 3))
    pf[-1] = [0.0, 0.0, -P]
    out = model.solve({"arm": {"point_force": pf}})
    tip = out["arm"]["r"][-1] - model.params["arm"]["node_positions"][-1]
    ref = P * LA**3 / (3 * ARM["EI_cc"]) + P * LA**2 * H / COLUMN["EI_cc"] + P * H / COLUMN["EA"]
    assert -tip[2] == pytest.approx(ref, rel=1e-3)
    # the column top swings aft (y) by M H^2 / 2 EI with M = P L
    assert tip[1] == pytest.approx(P * LA * H**2 / (2 * COLUMN["EI_cc"]), rel=1e-3)
    np.testing.assert_allclose(out["column"]["F"][0], [0.0, 0.0, -P], atol=1e-9)       # root reaction
    np.testing.assert_allclose(out["column"]["M"][0], np.cross(out["arm"]["r"][-1], [0.0, 0.0, -P]), atol=1e-9)
    pf[-1] = [P, 0.0, 0.0]
    tip = model.solve({"arm": {"point_force": pf}})["arm"]["r"][-1] - model.params["arm"]["node_positions"][-1]
    ref = P * LA**3 / (3 * ARM["EI_nn"]) + P * LA**2 * H / COLUMN["GJ"] + P * H**3 / (3 * COLUMN["EI_nn"])
    assert tip[0] == pytest.approx(ref, rel=1e-3)


def test_t_frame_two_joints_on_one_node_against_unit_load_method():
    """Column along z (clamped) with a right arm (+y) and a left arm (-y) both joined to its top
    node; tip loads -z (right) and +z (left). The column carries the net moment M = L_R P_R - L_L P_L about
    x: its top turns by M H / EI_col, moving the arm tips by +-phi L; plus each arm's PL^3/3EI and
    the column's shortening."""
    LR, LL, PR, PL = 4.0, 2.5, -10.0, 8.0
    rc, thc = straight_beam(13, H, (0.0, 0.0, 1.0))
    rr, thr = straight_beam(17, LR, (0.0, 1.0, 0.0))
    rl, thl = straight_beam(11, LL, (0.0, -1.0, 0.0))
    left = dict(EI_cc=0.6e6, EI_nn=2e6, GJ=0.5e6, EA=1e10)
    model = JoinedBeamModel([Beam("column", 13), Beam("right", 17, root="free"), Beam("left", 11, root="free")],
                            [Joint("column", -1, "right", 0), Joint("left", 0, "column", -1)],
                            {"column": beam_parameters(rc, thc, **COLUMN),
                             "right": beam_parameters(rr + [0.0, 0.0, H], thr, **ARM),
                             "left": beam_parameters(rl + [0.0, 0.0, H], thl, **left)})
    loads = {"right": {"point_force": np.outer(np.eye(17)[-1], [0.0, 0.0, PR])},
             "left": {"point_force": np.outer(np.eye(11)[-1], [0.0, 0.0, PL])}}
    out = model.solve(loads)
    phi = (LR * PR - LL * PL) * H / COLUMN["EI_cc"]
    shortening = (PR + PL) * H / COLUMN["EA"]
    dz_right = out["right"]["r"][-1, 2] - H
    dz_left = out["left"]["r"][-1, 2] - H
    assert dz_right == pytest.approx(PR * LR**3 / (3 * ARM["EI_cc"]) + phi * LR + shortening, rel=1e-3)
    assert dz_left == pytest.approx(PL * LL**3 / (3 * left["EI_cc"]) - phi * LL + shortening, rel=1e-3)
    assert out["column"]["theta"][-1, 0] - np.pi / 2 == pytest.approx(phi, rel=1e-4)   # (nonlinear: 3e-6)
    np.testing.assert_allclose(out["column"]["F"][0], [0.0, 0.0, PR + PL], atol=1e-9)


def test_fuselage_along_x_with_its_own_axes_and_a_wing_at_a_mid_node():
    """A fuselage along body x (its own axes FUSELAGE_AXES: the Euler sequence is singular along
    body x) clamped at the nose, a wing along y joined at the fuselage's node at x = a. Unit-load
    method: tip load -z bends the wing (EI_cc), bends the fuselage vertically (EI_cc in its axes)
    and twists it (GJ); tip load +x bends the wing in-plane (EI_nn), bends the fuselage laterally
    (EI_nn) and stretches it. Under gravity the root reaction is the total weight (body axes)."""
    Lf, a, Lw, P = 6.0, 4.0, 5.0, 10.0
    fus = dict(EI_cc=4e6, EI_nn=7e6, GJ=3e6, EA=1e9, mass_per_length=50.0)
    wing = dict(EI_cc=1e6, EI_nn=5e6, GJ=1e6, EA=1e9, mass_per_length=20.0)
    R = np.array(FUSELAGE_AXES)
    rf, thf = straight_beam(13, Lf)                      # along the fuselage's own y = body x
    rw, thw = straight_beam(21, Lw)
    model = JoinedBeamModel([Beam("fuselage", 13, axes=FUSELAGE_AXES), Beam("wing", 21, root="free")],
                            [Joint("fuselage", 8, "wing", 0)],
                            {"fuselage": beam_parameters(rf, thf, **fus),
                             "wing": beam_parameters(rw + R.T @ rf[8], thw, **wing)})
    for load, axis, ref in (([0.0, 0.0, -P], 2, -P * (Lw**3 / (3 * wing["EI_cc"]) + a**3 / (3 * fus["EI_cc"])
                                                         + Lw**2 * a / fus["GJ"])),
                            ([P, 0.0, 0.0], 0, P * (Lw**3 / (3 * wing["EI_nn"]) + Lw**2 * a / fus["EI_nn"]
                                                    + a / fus["EA"]))):
        out = model.solve({"wing": {"point_force": np.outer(np.eye(21)[-1], load)}}, load_steps=1)
        tip = out["wing"]["r"][-1] - model.params["wing"]["node_positions"][-1]
        assert tip[axis] == pytest.approx(ref, rel=1e-3)
    g = 9.81
    out = model.solve(gravity=[0.0, 0.0, -g])
    weight = g * (fus["mass_per_length"] * Lf + wing["mass_per_length"] * Lw)
    body = model.system.unpack(out["x"], body_axes=True)
    np.testing.assert_allclose(body["fuselage"]["F"][0], [0.0, 0.0, -weight], rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(out["fuselage"]["F"][0], R @ [0.0, 0.0, -weight], rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(body["fuselage"]["r"][8], body["wing"]["r"][0], atol=1e-12)


def _l_frame_frequency_equation(EI1, m1, EI2, m2, count=2):
    """Lowest in-plane circular frequencies of the clamped L-frame (column H, arm LA; Euler-
    Bernoulli, inextensible). Column lateral deflection v(z) (y), arm deflection w(y) (z); rotations
    about x: column -v', arm w'. Conditions: v = v' = 0 at the base; at the corner w = 0 (column
    inextensible), -v'(H) = w'(0), moments EI1 v'' + EI2 w'' = 0, shear and the arm's rigid axial
    inertia EI1 v''' + m2 LA omega^2 v = 0; free arm tip w'' = w''' = 0."""
    def basis(beta, s):
        c, sn, ch, sh = np.cos(beta * s), np.sin(beta * s), np.cosh(beta * s), np.sinh(beta * s)
        return np.array([[c, sn, ch, sh], [-beta * sn, beta * c, beta * sh, beta * ch],
                         [-beta**2 * c, -beta**2 * sn, beta**2 * ch, beta**2 * sh],
                         [beta**3 * sn, -beta**3 * c, beta**3 * sh, beta**3 * ch]])

    def det(w):
        b1, b2 = (m1 * w**2 / EI1) ** 0.25, (m2 * w**2 / EI2) ** 0.25
        c0, cH, a0, aL = basis(b1, 0.0), basis(b1, H), basis(b2, 0.0), basis(b2, LA)
        z = np.zeros(4)
        A = np.array([np.r_[c0[0], z], np.r_[c0[1], z], np.r_[z, a0[0]], np.r_[cH[1], a0[1]],
                      np.r_[EI1 * cH[2], EI2 * a0[2]], np.r_[EI1 * cH[3] + m2 * LA * w**2 * cH[0], z],
                      np.r_[z, aL[2]], np.r_[z, aL[3]]])
        return np.linalg.det(A / np.linalg.norm(A, axis=1, keepdims=True))

    grid = np.linspace(1.0, 200.0, 2000)
    d = np.array([det(w) for w in grid])
    roots = [sopt.brentq(det, grid[i], grid[i + 1], xtol=1e-12)
             for i in np.flatnonzero(np.sign(d[:-1]) != np.sign(d[1:]))]
    return np.array(roots[:count])


def test_l_frame_natural_frequencies_against_frequency_equation():
    """The two lowest in-plane modes of the clamped L-frame (out-of-plane bending and torsion made
    stiffer so that they come above): 6 + 8 and 12 + 16 elements, O(h^2) errors, Richardson-
    extrapolated."""
    m1, m2 = 30.0, 20.0
    ref = _l_frame_frequency_equation(COLUMN["EI_cc"], m1, ARM["EI_cc"], m2)
    assert ref == pytest.approx([27.7632, 68.9771], rel=1e-5)      # the equation's roots (docs/stick-model.md)
    col = dict(EI_cc=COLUMN["EI_cc"], EI_nn=10 * COLUMN["EI_cc"], GJ=5 * COLUMN["EI_cc"], EA=1e11,
               mass_per_length=m1, inertia_per_length=ROT)
    arm = dict(EI_cc=ARM["EI_cc"], EI_nn=10 * ARM["EI_cc"], GJ=5 * ARM["EI_cc"], EA=1e11,
               mass_per_length=m2, inertia_per_length=ROT)
    w = {}
    for n1, n2 in ((7, 9), (13, 17)):
        rc, thc = straight_beam(n1, H, (0.0, 0.0, 1.0))
        ra, tha = straight_beam(n2, LA, (0.0, 1.0, 0.0))
        model = JoinedBeamModel([Beam("column", n1), Beam("arm", n2, root="free")], [Joint("column", -1, "arm", 0)],
                                {"column": beam_parameters(rc, thc, **col),
                                 "arm": beam_parameters(ra + [0.0, 0.0, H], tha, **arm)})
        w[n1 + n2 - 2] = _frequencies(model.system, model.p, model.forcing())[:2]   # about the static state
    np.testing.assert_allclose(w[28], ref, rtol=3e-3)
    np.testing.assert_allclose((4 * w[28] - w[14]) / 3, ref, rtol=1e-4)


# ----------------------------------------------------------------------------- hinges
def _hinged_beam(k, axis=(1.0, 0.0, 0.0), n1=9, n2=13, L1=4.0, L2=6.0, sec1=None, sec2=None, **mass):
    r0, th0 = straight_beam(n1 + n2 - 1, L1 + L2)
    r0 = np.vstack([np.linspace([0, 0, 0], [0, L1, 0], n1), np.linspace([0, L1, 0], [0, L1 + L2, 0], n2)[1:]])
    sec1 = sec1 or dict(EI_cc=3e6, GJ=2e6, EI_nn=3e7, EA=1e10)
    sec2 = sec2 or dict(EI_cc=1e6, GJ=1e6, EI_nn=1e7, EA=1e10)
    return JoinedBeamModel([Beam("inboard", n1), Beam("outboard", n2, root="free")],
                           [Joint("inboard", -1, "outboard", 0, kind="hinge", axis=axis, stiffness=k)],
                           {"inboard": beam_parameters(r0[:n1], th0[:n1], **sec1, **mass),
                            "outboard": beam_parameters(r0[n1 - 1:], th0[n1 - 1:], **sec2, **mass)})


def test_hinge_spring_tip_rotation_is_spring_plus_beam_compliance():
    """Tip moment about the hinge axis x: phi_tip = M (L1/EI1 + 1/k + L2/EI2) exactly (constant
    bending moment, large rotation); a torque about the beam axis passes the hinge rigidly."""
    k = 2.5e5
    model = _hinged_beam(k)
    M = 6e4
    pm = np.zeros((13, 3))
    pm[-1] = [M, 0.0, 0.0]
    out = model.solve({"outboard": {"point_moment": pm}}, load_steps=4)
    ref = M * (4.0 / 3e6 + 1.0 / k + 6.0 / 1e6)
    assert ref > 0.3                                              # a large rotation (rad)
    assert out["outboard"]["theta"][-1, 0] == pytest.approx(ref, rel=1e-9)
    jump = out["outboard"]["theta"][0, 0] - out["inboard"]["theta"][-1, 0]
    assert jump == pytest.approx(M / k, rel=1e-9)
    pm[-1] = [0.0, 500.0, 0.0]
    twist = model.solve({"outboard": {"point_moment": pm}})["outboard"]["theta"][-1, 1]
    assert twist == pytest.approx(500.0 * (4.0 / 2e6 + 6.0 / 1e6), rel=1e-6)
    # a tip force: cantilever deflections plus the hinge rotation times the outboard length
    pf = np.zeros((13, 3))
    pf[-1, 2] = 100.0
    tip = model.solve({"outboard": {"point_force": pf}})["outboard"]["r"][-1, 2]
    # inboard tip deflection and rotation under shear P and moment P L2: P L1^3/3EI + P L2 L1^2/2EI
    # carried to the tip by the rotation P L1^2/2EI + P L2 L1/EI
    P, L1, L2, EI1, EI2 = 100.0, 4.0, 6.0, 3e6, 1e6
    ref = (P * L1**3 / (3 * EI1) + P * L2 * L1**2 / (2 * EI1) + (P * L1**2 / (2 * EI1) + P * L2 * L1 / EI1) * L2
           + P * L2**3 / (3 * EI2) + P * L2 * L2 / k)
    assert tip == pytest.approx(ref, rel=2e-3)



def test_torsion_hinge_about_the_beam_axis():
    """Hinge about the beam axis y with a spring: tip torque T twists T (L1/GJ1 + 1/k + L2/GJ2)
    (exact: constant torque); a bending moment about x passes the hinge rigidly."""
    k, T_tip = 4e5, 2e5
    model = _hinged_beam(k, axis=(0.0, 2.0, 0.0))          # any length: normalised
    pm = np.zeros((13, 3))
    pm[-1] = [0.0, T_tip, 0.0]
    out = model.solve({"outboard": {"point_moment": pm}}, load_steps=2)
    ref = T_tip * (4.0 / 2e6 + 1.0 / k + 6.0 / 1e6)
    assert ref > 0.5
    assert out["outboard"]["theta"][-1, 1] == pytest.approx(ref, rel=1e-9)
    pm[-1] = [300.0, 0.0, 0.0]
    phi = model.solve({"outboard": {"point_moment": pm}})["outboard"]["theta"][-1, 0]
    assert phi == pytest.approx(300.0 * (4.0 / 3e6 + 6.0 / 1e6), rel=1e-9)

def test_free_hinge_pinned_free_frequency():
    """A free hinge (no spring) on a stiff, light clamped stub: the outboard beam flaps as a
    pinned-free beam, beta L = 3.9266 (Blevins 1979, Table 8-1), after a zero-frequency hinge mode."""
    EI, mu, L2 = 1e6, 10.0, 6.0
    model = _hinged_beam(None, n1=3, n2=31, L1=0.5, L2=L2, sec1=dict(EI_cc=1e10, GJ=1e10, EI_nn=1e10, EA=1e12),
                         sec2=dict(EI_cc=EI, GJ=1e6, EI_nn=1e8, EA=1e11), mass_per_length=mu,
                         inertia_per_length=ROT)
    x0 = model.system.jig_state(model.p)
    modes = eigenmodes(model.system, model.p, model.forcing(), x0, static=False, method="sparse", sigma=5.0,
                       count=8)
    scale = np.sqrt(EI / (mu * L2**4))
    w = np.sort(modes.frequency)
    assert np.sum(w < 1e-3 * scale) >= 1                        # the rigid rotation about the hinge
    assert w[w > 1e-3 * scale][0] == pytest.approx(3.9266**2 * scale, rel=3e-3)


# ----------------------------------------------------------------------------- adjoint and LU order
def _march_case(p=None, n1=4, n2=4, n_time=16):
    model = _l_frame(n1, n2, hinge=dict(kind="hinge", axis=(1.0, 0.0, 0.0), stiffness=4e5),
                     column=dict(mass_per_length=30.0, inertia_per_length=ROT),
                     arm=dict(mass_per_length=20.0, inertia_per_length=ROT))
    system = model.system
    t = np.linspace(0.0, 0.15, n_time)
    pf = np.zeros((n2, 3))
    pf[-1] = [200.0, 0.0, -800.0]
    q_step = model.forcing({"arm": {"point_force": pf}}, gravity=[0.0, 0.0, -9.81])
    Q = np.tile(q_step, (n_time, 1))
    Q[0] = model.forcing(gravity=[0.0, 0.0, -9.81])
    return system, t, model.p if p is None else p, Q


def _tip_functional(system, states):
    """f = sum over time of the arm tip's (x, z) displacement squared from the jig."""
    i = system.node_index("arm", -1)
    d = states[:, i:i + 3] - states[0, i:i + 3]
    dfdx = np.zeros_like(states)
    dfdx[:, i], dfdx[:, i + 2] = 2 * d[:, 0], 2 * d[:, 2]
    dfdx[0, i] -= np.sum(2 * d[:, 0])
    dfdx[0, i + 2] -= np.sum(2 * d[:, 2])
    return float(np.sum(d[:, 0] ** 2 + d[:, 2] ** 2)), dfdx


def test_adjoint_of_joined_march_against_central_differences(kernel_on):
    system, t, p, Q = _march_case()
    run = lambda pp: march(system, t, pp, Q, atol=1e-12, static_options={"rtol": 1e-14})  # noqa: E731
    h = run(p)
    f, dfdx = _tip_functional(system, h.states)
    assert f > 0.0
    grads = {}
    for lu in ("static", "superlu"):
        lin = LinearizedHistory(system, t, h.states, p, Q, lu=lu)
        grads[lu] = lin.gradient(dfdx)[0]
        assert lin.lu_method == lu
    np.testing.assert_allclose(grads["static"], grads["superlu"], rtol=1e-8, atol=1e-12 * np.max(np.abs(grads["superlu"])))
    lay = layout(system.param_specs)
    picks = {"arm EI_cc node 1": lay["arm_stiffness_csn"].start + 9 * 1,
             "column GJ node 2": lay["column_stiffness_csn"].start + 9 * 2 + 4,
             "column mass node 0": lay["column_mass_per_length"].start,
             "hinge spring": lay["joint_rotational_stiffness"].start}
    for name, j in picks.items():
        step = 1e-3 * abs(p[j])     # (smaller steps meet the march's convergence noise)
        e = np.zeros_like(p)
        e[j] = step
        fd = (_tip_functional(system, run(p + e).states)[0] - _tip_functional(system, run(p - e).states)[0]) / (2 * step)
        assert grads["static"][j] == pytest.approx(fd, rel=1e-5), name
    # forward mode (the tangent sweep) agrees with reverse
    lin = LinearizedHistory(system, t, h.states, p, Q, lu="static")
    direction = np.zeros_like(p)
    direction[list(picks.values())] = 1e-3 * np.abs(p[list(picks.values())])
    dx = lin.tangent(dp=direction)
    assert np.sum(dfdx * dx) == pytest.approx(grads["static"] @ direction, rel=1e-9)


def test_joined_lu_order_lowers_factorization_work(kernel_on):
    """The joint unknowns placed next to their nodes (lu_orders.joined_lu_column_order) against
    the natural order and against the node blocks in BEAM_NODE_ORDER with the joints last."""
    model = _l_frame(9, 9, column=dict(mass_per_length=30.0), arm=dict(mass_per_length=20.0))
    system = model.system
    pf = np.zeros((9, 3))
    pf[-1] = [100.0, 50.0, -300.0]
    q = model.forcing({"arm": {"point_force": pf}}, gravity=[0.0, 0.0, -9.81])
    x = model.solve({"arm": {"point_force": pf}}, gravity=[0.0, 0.0, -9.81])["x"]
    _, matrix = system.residual_and_newton_matrix(x, np.zeros_like(x), model.p, q, 1500.0)
    matrix = matrix.tocsc()
    matrix.sort_indices()
    rows, indptr, data = matrix.indices, matrix.indptr, matrix.data
    n = system.n_state
    joined = system.lu_column_order()
    last = static_lu.block_column_order(lu_orders.BEAM_NODE_ORDER, 18, n)
    works = [static_lu.factorization_work(n, rows, indptr, data, order) for order in (None, last, joined)]
    assert works[2] < works[1] < works[0]


# ----------------------------------------------------------------------------- bad input
TWO = [Beam("wing", 5), Beam("tail", 4, root="free")]


@pytest.mark.parametrize("beams, joints, match", [
    (TWO, [Joint("wing", 5, "tail", 0)], r"node_a 5 does not exist: beam 'wing' has nodes 0\.\.4"),
    (TWO, [Joint("wing", -1, "tail", -5)], r"node_b -5 does not exist: beam 'tail' has nodes 0\.\.3"),
    (TWO, [Joint("wing", -1, "fin", 0)], r"beam_b 'fin' is not a beam"),
    (TWO, [Joint("wing", -1, "wing", 0)], r"connects two different beams"),
    (TWO, [Joint("wing", -1, "tail", 0), Joint("tail", 0, "wing", 4)], r"joined twice"),
    (TWO, [], r"beams \['tail'\] are joined to no other beam"),
    (TWO + [Beam("fin", 3, root="free")], [Joint("wing", -1, "tail", 0)], r"beams \['fin'\] are joined to no other"),
    ([Beam("wing", 5), Beam("wing", 4)], [], r"beam name 'wing' is used twice"),
])
def test_bad_layouts_are_refused_before_any_build(beams, joints, match):
    with pytest.raises(ValueError, match=match):
        build_joined_system(beams, joints)


@pytest.mark.parametrize("kwargs, match", [
    (dict(kind="hinge", axis=(1.0, 0.0, 0.0), stiffness=0.0), r"stiffness must be .* > 0 N\*m/rad .*got 0\.0"),
    (dict(kind="hinge", axis=(1.0, 0.0, 0.0), stiffness=-5.0), r"stiffness must be .* > 0 N\*m/rad .*got -5\.0"),
    (dict(kind="hinge", axis=(1.0, 0.0, 0.0), stiffness=float("nan")), r"stiffness must be"),
    (dict(kind="hinge", axis=(0.0, 0.0, 0.0)), r"axis of 3 finite components and non-zero length"),
    (dict(kind="hinge"), r"a hinge needs an axis"),
    (dict(kind="rigid", stiffness=1e4), r"a rigid joint takes no axis or stiffness"),
    (dict(kind="weld"), r"kind must be one of \('rigid', 'hinge'\), got 'weld'"),
])
def test_bad_joints_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Joint("wing", -1, "tail", 0, **kwargs)


@pytest.mark.parametrize("kwargs, match", [
    (dict(name="wing tip", num_nodes=3), r"beam name must be an identifier"),
    (dict(name="wing", num_nodes=1), r"beam 'wing': num_nodes must be an integer >= 2, got 1"),
    (dict(name="wing", num_nodes=3, root="pinned"), r"root must be one of \('clamped', 'free'\), got 'pinned'"),
    (dict(name="fuselage", num_nodes=3, axes=((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, -1.0))),
     r"beam 'fuselage': axes must be a 3 x 3 rotation matrix"),
    (dict(name="fuselage", num_nodes=3, axes=(1.0, 0.0, 0.0)), r"axes must be a 3 x 3 rotation matrix"),
])
def test_bad_beams_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Beam(**kwargs)


def test_beams_that_do_not_meet_at_the_joint_are_refused():
    system = build_joined_system([Beam("column", 3), Beam("arm", 3, root="free")], [Joint("column", -1, "arm", 0)])
    rc, thc = straight_beam(3, H, (0.0, 0.0, 1.0))
    ra, tha = straight_beam(3, LA, (0.0, 1.0, 0.0))
    params = {"column": beam_parameters(rc, thc, **COLUMN), "arm": beam_parameters(ra + [0.0, 0.0, H], tha, **ARM)}
    system.pack_parameters(params)
    params["arm"] = beam_parameters(ra + [0.0, 0.0, H + 0.01], tha, **ARM)
    with pytest.raises(ValueError, match=r"joint column node 2 - arm node 0: the beams do not meet at the joint: "
                                         r"the nodes are 0\.01 m apart"):
        system.pack_parameters(params)
    with pytest.raises(ValueError, match=r"no parameters for beam 'arm'"):
        system.pack_parameters({"column": params["column"]})
    with pytest.raises(ValueError, match=r"beam 'arm': unknown loads \['point_forces'\]"):
        system.pack_forcing({"arm": {"point_forces": np.zeros((3, 3))}})


def test_equation_names_of_a_joined_system():
    system = build_joined_system([Beam("wing", 3), Beam("tail", 3, root="free")],
                                 [Joint("wing", -1, "tail", 0, kind="hinge", axis=(1.0, 0.0, 0.0), stiffness=1e3)])
    assert system.describe_equation(18 + 3) == "beam wing: node 1 (element 1-2), moment equilibrium x"
    assert system.describe_equation(54 + 36 + 4) == "beam tail: root node 0, free root moment y"
    assert system.describe_equation(108 + 7) == "joint wing node 2 - tail node 0 (hinge), equal position y"
    assert system.describe_equation(108 + 11) == "joint wing node 2 - tail node 0 (hinge), hinge spring law"
    assert system.node_index("tail", -1) == 54 + 36


def test_strain_rate_damping_passes_to_every_beam():
    """With Kelvin-Voigt damping the split cantilever's complex eigenvalues are the single beam's."""
    damping = StrainRateDamping.from_damping_ratio(0.02, 1.8)
    n, k, L = 11, 4, 10.0
    r0, th0 = straight_beam(n, L)
    single = build_beam_system(n, damping=damping, defer=False)
    p1 = pack(single.param_specs, beam_parameters(r0, th0, **SECTION))
    joined = build_joined_system([Beam("inner", k + 1), Beam("outer", n - k, root="free")],
                                 [Joint("inner", -1, "outer", 0)], damping=damping)
    p2 = joined.pack_parameters({"inner": beam_parameters(r0[:k + 1], th0[:k + 1], **SECTION),
                                 "outer": beam_parameters(r0[k:], th0[k:], **SECTION)})
    lam = []
    for system, p, q in ((single, p1, np.zeros(single.n_forcing)), (joined, p2, joined.pack_forcing())):
        modes = eigenmodes(system, p, q, system.initial_guess(p, q), static=False, method="sparse", sigma=1.0, count=8)
        lam.append(modes.eigenvalues[np.argsort(np.abs(modes.eigenvalues))][:4])
    np.testing.assert_allclose(lam[1], lam[0], rtol=1e-7)
    zeta = -lam[0][0].real / abs(lam[0][0])
    assert 0.005 < zeta < 0.05          # damped


def test_natural_frequencies_of_a_joined_system_equal_the_single_beam():
    """``beam.modes.natural_frequencies`` on a joined system: the joint rows' spurious (infinite)
    eigenvalues are dropped before the oscillatory ones are picked, so the lowest frequencies are
    the single beam's and the first is Euler-Bernoulli's flap frequency."""
    from wingmdao.beam.modes import natural_frequencies

    n, k, L = 13, 5, 10.0
    single, joined = _split_cantilever(n, k, L, **SECTION)
    f_joined = natural_frequencies(joined.system, joined.p, joined.forcing(), joined.system.jig_state(joined.p), count=4)
    f_single = natural_frequencies(single.system, single.p, np.zeros(single.system.n_forcing), single.jig(), count=4)
    np.testing.assert_allclose(f_joined, f_single, rtol=1e-6)
    flap = 1.8751**2 * np.sqrt(SECTION["EI_cc"] / (SECTION["mass_per_length"] * L**4)) / (2 * np.pi)
    assert f_joined[0] == pytest.approx(flap, rel=5e-3)
