"""Lumped masses, free flight and symmetry conditions of joined beams (wingmdao.beam.joints).

References coded here:

* cantilever with a tip mass M (offset e along the span, d chordwise) under gravity, Euler-Bernoulli
  and Saint-Venant torsion: w = P L^3/3EI + P e L^2/2EI, twist = P d L/GJ (P = M g);
* its first bending frequency: the frequency equation of the Euler-Bernoulli cantilever with a
  tip mass (tip conditions EI w'' = 0, EI w''' = -M omega^2 w):
  1 + cos(bL) cosh(bL) + (M / mL) bL (cos(bL) sinh(bL) - sin(bL) cosh(bL)) = 0,
  omega = (bL)^2 sqrt(EI / (m L^4)); and Rayleigh's estimate omega^2 = 3 EI / (L^3 (M + 33/140 m L));
* its first torsion frequency with a tip rotary inertia J (tip condition GJ theta' = J omega^2 theta):
  g tan(g) = rho_Ip L / J, omega = (g / L) sqrt(GJ / rho_Ip);
* rigid-body modes of a free structure: 3 for a symmetric half aircraft (surge, plunge, pitch),
  6 for the full aircraft; linear momentum of a free structure with no external force is
  conserved (the BDF2 rates are linear in the states, so the sum of the equilibrium rows holds it
  exactly), and under gravity alone it grows as (total mass) g t.
"""

import casadi as ca
import numpy as np
import pytest
import scipy.optimize as sopt

from wingmdao.beam.joints import (FUSELAGE_AXES, Beam, JoinedBeamModel, Joint, LumpedMass, MonitoringStation,
                                  Symmetry, build_joined_system, monitoring_loads)
from wingmdao.beam.modes import natural_frequencies
from wingmdao.beam.residual import build_beam_system
from wingmdao.beam.rotations import body_to_csn
from wingmdao.beam.static import beam_parameters, straight_beam
from wingmdao.cases import pegasus, pegasus_stick
from wingmdao.cases.planform import LB
from wingmdao.stability.eigen import eigenmodes
from wingmdao.timemarch.adjoint import LinearizedHistory
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import layout, pack

ROT = np.diag([1e-9, 1e-3, 1e-9])   # small rotary inertia per length (kg m), csn
SECTION = dict(EI_cc=2.0e6, GJ=1.5e6, EI_nn=1.8e7, EA=1e11, mass_per_length=20.0, inertia_per_length=ROT)
N, L = 21, 10.0


def _cantilever(masses, **section):
    r0, th0 = straight_beam(N, L)
    return JoinedBeamModel([Beam("wing", N)], [], {"wing": beam_parameters(r0, th0, **{**SECTION, **section})},
                           masses=masses)


def _frequencies(model):
    modes = eigenmodes(model.system, model.p, model.forcing(), model.system.jig_state(model.p), static=False,
                       method="dense")
    w = modes.frequency
    return np.sort(w[w > 1e-3])


# ----------------------------------------------------------------------------- lumped masses
def test_tip_mass_with_offsets_under_gravity_against_closed_form():
    """A massless cantilever with a 20 kg tip mass 0.5 m beyond the tip and 0.3 m aft: the weight
    bends it (P L^3/3EI + P e L^2/2EI) and twists it (P d L/GJ)."""
    M, e, d, g = 20.0, 0.5, 0.3, 9.81
    model = _cantilever([LumpedMass("wing", -1, M, offset=(d, e, 0.0), inertia=np.diag([1.0, 2.0, 3.0]))],
                        mass_per_length=1e-9)
    tip = model.solve(gravity=[0.0, 0.0, -g])["wing"]
    P, EI, GJ = M * g, SECTION["EI_cc"], SECTION["GJ"]
    assert tip["r"][-1, 2] == pytest.approx(-(P * L**3 / (3 * EI) + P * e * L**2 / (2 * EI)), rel=1e-3)
    assert tip["theta"][-1, 1] == pytest.approx(P * d * L / GJ, rel=1e-3)
    # the clamp carries the weight and its moment (equilibrium of the whole, exact)
    root = model.solve(gravity=[0.0, 0.0, -g])
    np.testing.assert_allclose(root["wing"]["F"][0], [0.0, 0.0, -P], atol=1e-8)


@pytest.mark.parametrize("ratio", [0.5, 2.0])
def test_tip_mass_first_bending_and_torsion_frequencies(ratio):
    """First bending frequency of a cantilever with a tip mass M = ratio m L against the exact
    frequency equation (and Rayleigh's estimate), first torsion frequency with a tip rotary
    inertia J against g tan g = rho_Ip L / J."""
    mL = SECTION["mass_per_length"] * L
    J, rho_ip = 1e-2, ROT[1, 1]
    model = _cantilever([LumpedMass("wing", -1, ratio * mL, inertia=np.diag([1e-9, J, 1e-9]))])
    w = _frequencies(model)
    eq = lambda b: (1 + np.cos(b) * np.cosh(b)                               # noqa: E731
                    + ratio * b * (np.cos(b) * np.sinh(b) - np.sin(b) * np.cosh(b)))
    bL = sopt.brentq(eq, 0.3, 1.8751)
    exact = bL**2 * np.sqrt(SECTION["EI_cc"] / (SECTION["mass_per_length"] * L**4))
    rayleigh = np.sqrt(3 * SECTION["EI_cc"] / (L**3 * (ratio * mL + 33 / 140 * mL)))
    assert w[0] == pytest.approx(exact, rel=1e-3)
    assert w[0] == pytest.approx(rayleigh, rel=3e-3)
    gam = sopt.brentq(lambda x: x * np.tan(x) - rho_ip * L / J, 1e-6, np.pi / 2 - 1e-9)
    torsion = gam / L * np.sqrt(SECTION["GJ"] / rho_ip)
    assert np.min(np.abs(w / torsion - 1)) < 3e-4


def test_adjoint_gradient_with_respect_to_lumped_mass_values_against_central_differences():
    """A 16-step march of a 6-node cantilever with an offset tip mass under gravity and a step tip
    load: d(sum of tip z^2)/d(mass, offset, inertia) by the discrete adjoint and the tangent sweep
    against central differences."""
    r0, th0 = straight_beam(6, 4.0)
    model = JoinedBeamModel([Beam("wing", 6)], [], {"wing": beam_parameters(r0, th0, **SECTION)},
                            masses=[LumpedMass("wing", -1, 80.0, offset=(0.4, 0.2, -0.1),
                                               inertia=[[3.0, 0.2, 0.0], [0.2, 5.0, 0.0], [0.0, 0.0, 6.0]])])
    s, t = model.system, np.linspace(0.0, 0.12, 16)
    pf = np.zeros((6, 3))
    pf[-1] = [0.0, 0.0, 4e3]
    Q = np.tile(model.forcing({"wing": {"point_force": pf}}, gravity=[0.0, 0.0, -9.81]), (t.size, 1))
    Q[0] = model.forcing(gravity=[0.0, 0.0, -9.81])
    i = s.node_index("wing", -1) + 2

    def f_of(states):
        d = states[:, i] - states[0, i]
        dfdx = np.zeros_like(states)
        dfdx[:, i] = 2 * d
        dfdx[0, i] -= np.sum(2 * d)
        return float(np.sum(d**2)), dfdx

    run = lambda pp: march(s, t, pp, Q, atol=1e-12, static_options={"rtol": 1e-14})  # noqa: E731
    h = run(model.p)
    f, dfdx = f_of(h.states)
    lin = LinearizedHistory(s, t, h.states, model.p, Q, lu="static")
    grad = lin.gradient(dfdx)[0]
    lay = layout(s.param_specs)
    picks = {"mass": lay["lumped_mass"].start, "offset x": lay["lumped_mass_offset"].start,
             "offset z": lay["lumped_mass_offset"].start + 2, "inertia xx": lay["lumped_mass_inertia"].start}
    for name, j in picks.items():
        step = 1e-3 * abs(model.p[j])
        e = np.zeros_like(model.p)
        e[j] = step
        fd = (f_of(run(model.p + e).states)[0] - f_of(run(model.p - e).states)[0]) / (2 * step)
        assert grad[j] == pytest.approx(fd, rel=1e-5, abs=1e-9 * abs(f)), name
    direction = np.zeros_like(model.p)
    direction[list(picks.values())] = 1.0
    assert np.sum(dfdx * lin.tangent(dp=direction)) == pytest.approx(grad @ direction, rel=1e-9)


# ----------------------------------------------------------------------------- free flight
FUSELAGE = dict(EI_cc=8.0e6, GJ=5.0e6, EI_nn=8.0e6, EA=1e9, mass_per_length=40.0, inertia_per_length=np.diag([1e-3] * 3))
SURFACE = dict(EI_cc=2.0e6, GJ=1.5e6, EI_nn=1.8e7, EA=1e9, mass_per_length=20.0, inertia_per_length=np.diag([1e-3] * 3))
ENGINE = dict(offset=(-1.0, 0.0, -0.5), inertia=np.diag([20.0, 30.0, 40.0]))


def _aircraft(full, engine=ENGINE, nf=9, nw=7, nt=4):
    """A free stick aircraft: fuselage 8 m along x (FUSELAGE_AXES), wing 6 m from the fuselage node at
    x = 2 m, tail 2 m from the fuselage's aft node, a 300 kg engine on each wing; the symmetric
    half (symmetry conditions on every fuselage node) or the full aircraft (left wing and tail)."""
    rf, thf = straight_beam(nf, 8.0)                 # the fuselage's own y is body x
    beams = [Beam("fuselage", nf, root="free", axes=FUSELAGE_AXES)]
    params = {"fuselage": beam_parameters(rf, thf, **FUSELAGE)}
    joints, masses = [], []
    for side, sign in (("right", 1.0), ("left", -1.0))[: 2 if full else 1]:
        rw, thw = straight_beam(nw, 6.0, (0.0, sign, 0.0))
        rt, tht = straight_beam(nt, 2.0, (0.0, sign, 0.0))
        beams += [Beam(f"{side}_wing", nw, root="free"), Beam(f"{side}_tail", nt, root="free")]
        params[f"{side}_wing"] = beam_parameters(rw + [2.0, 0.0, 0.0], thw, **SURFACE)
        params[f"{side}_tail"] = beam_parameters(rt + [8.0, 0.0, 0.0], tht, **SURFACE)
        joints += [Joint("fuselage", round(2.0 * (nf - 1) / 8.0), f"{side}_wing", 0),
                   Joint("fuselage", -1, f"{side}_tail", 0)]
        masses.append(LumpedMass(f"{side}_wing", 3, 300.0, **engine))
    symmetry = [] if full else [Symmetry("fuselage", i) for i in range(nf)]
    return JoinedBeamModel(beams, joints, params, masses=masses, symmetry=symmetry)


@pytest.mark.parametrize("full, rigid", [(False, 3), (True, 6)])
def test_free_aircraft_has_exactly_its_rigid_body_modes(full, rigid):
    """The free half aircraft has 3 zero-frequency modes (surge, plunge, pitch), the full one 6; each
    is a double zero eigenvalue of the first-order pencil. The next one is elastic."""
    model = _aircraft(full)
    modes = eigenmodes(model.system, model.p, model.forcing(), model.system.jig_state(model.p), static=False,
                       method="dense")
    lam = np.sort(np.abs(modes.eigenvalues))
    assert np.all(lam[:2 * rigid] < 1e-8)
    assert lam[2 * rigid] > 10.0


def _moving_state(model, seed=0):
    """The jig with a rigid velocity (3, 0, 2) m/s plus random nodal velocities and rates."""
    s = model.system
    x0 = s.jig_state(model.p)
    rng = np.random.default_rng(seed)
    for b in s.beams:
        i0 = s.offsets[b.name]
        blk = x0[i0:i0 + 18 * b.num_nodes].reshape(-1, 18)
        blk[:, 12:15] = 0.5 * rng.normal(size=(b.num_nodes, 3)) + b.rotation @ np.array([3.0, 0.0, 2.0])
        blk[:, 15:18] = 0.05 * rng.normal(size=(b.num_nodes, 3))
    return x0


@pytest.mark.parametrize("full", [False, True])
def test_free_march_conserves_linear_momentum(full):
    """A 40-step march of the free aircraft with no external load, from a state with random nodal
    velocities: its linear momentum (every direction of the full aircraft; x and z of the half,
    whose symmetry conditions react along y) stays at its initial value to round-off. Under gravity
    alone it grows as (total mass) g t."""
    model = _aircraft(full, engine=dict(inertia=ENGINE["inertia"]))     # engines at their nodes
    s, t = model.system, np.arange(41) * 2e-3
    x0 = _moving_state(model)
    free = [0, 1, 2] if full else [0, 2]
    for g in (0.0, -9.81):
        Q = np.tile(model.forcing(gravity=[0.0, 0.0, g]), (t.size, 1))
        h = march(s, t, model.p, Q, initial="state", x_init=x0, xtol=1e-14)
        P = np.array([s.linear_momentum(x, model.p) for x in h.states])
        assert np.max(np.abs(h.states[-1] - x0)) > 0.1                  # it moved and deformed
        mass = 8.0 * 40.0 + (2 if full else 1) * (6.0 * 20.0 + 2.0 * 20.0 + 300.0)
        expected = P[0] + np.outer(t, [0.0, 0.0, mass * g])
        np.testing.assert_allclose(P[:, free], expected[:, free], rtol=0, atol=1e-11 * np.abs(P[0]).max())


def test_lumped_mass_and_symmetry_input_errors():
    beams = [Beam("fuselage", 5, root="free", axes=FUSELAGE_AXES), Beam("wing", 4, root="free")]
    joints = [Joint("fuselage", 2, "wing", 0)]
    with pytest.raises(ValueError, match=r"lumped mass on wing node 4: node 4 does not exist: beam 'wing' has nodes 0..3"):
        build_joined_system(beams, joints, masses=[LumpedMass("wing", 4, 10.0)])
    with pytest.raises(ValueError, match=r"lumped mass on tail node 0: beam 'tail' is not a beam"):
        build_joined_system(beams, joints, masses=[LumpedMass("tail", 0, 10.0)])
    with pytest.raises(ValueError, match=r"mass must be finite and > 0 kg, got -1"):
        LumpedMass("wing", 1, -1.0)
    with pytest.raises(ValueError, match=r"inertia must be a symmetric positive semi-definite"):
        LumpedMass("wing", 1, 1.0, inertia=np.diag([1.0, -1.0, 1.0]))
    with pytest.raises(ValueError, match=r"offset must be 3 finite components"):
        LumpedMass("wing", 1, 1.0, offset=(0.0, 1.0))
    with pytest.raises(ValueError, match=r"symmetry condition on fuselage node -1: this node has two symmetry"):
        build_joined_system(beams, joints, symmetry=[Symmetry("fuselage", 4), Symmetry("fuselage", -1)])
    with pytest.raises(ValueError, match=r"node 7 does not exist: beam 'fuselage' has nodes 0..4"):
        build_joined_system(beams, joints, symmetry=[Symmetry("fuselage", 7)])
    clamped = [Beam("fuselage", 5, axes=FUSELAGE_AXES), beams[1]]
    with pytest.raises(ValueError, match=r"symmetry conditions are for a free aircraft: beams \['fuselage'\]"):
        build_joined_system(clamped, joints, symmetry=[Symmetry("fuselage", 0)])
    # a symmetry node off the plane y = 0 is refused when the parameters are packed
    rf, thf = straight_beam(5, 4.0)
    rw, thw = straight_beam(4, 3.0)
    params = {"fuselage": beam_parameters(rf, thf, **FUSELAGE), "wing": beam_parameters(rw + [2.0, 0, 0], thw, **SURFACE)}
    with pytest.raises(ValueError, match=r"symmetry condition on wing node 1: the node is not on the plane of "
                                         r"symmetry: its jig position is y = 1 m"):
        JoinedBeamModel(beams, joints, params, symmetry=[Symmetry("wing", 1)])
    system = build_joined_system(beams, joints, symmetry=[Symmetry("fuselage", 2)])
    assert system.describe_equation(system.n_state - 2) == "symmetry condition on fuselage node 2, roll rotation x held"


# ----------------------------------------------------------------------------- PEGASUS stick model
def test_pegasus_stick_half_aircraft_mass_and_rigid_body_modes():
    """The PEGASUS half aircraft weighs half the TOGW (Table D.3, 41 005 lb), has exactly 3 rigid-body
    modes, and its first elastic mode is the wing's first bending, above the clamped lone wing's
    (body freedom of the free aircraft)."""
    ac = pegasus_stick.build(num_wing_nodes=12)
    assert ac.mass == pytest.approx(0.5 * pegasus.TOGW_LB * LB, rel=1e-12)
    m = ac.model
    modes = eigenmodes(m.system, m.p, m.forcing(), m.system.jig_state(m.p), static=False, method="sparse",
                       sigma=1.0, count=12)
    lam = np.sort(np.abs(modes.eigenvalues))
    assert np.sum(lam < 1e-6) == 6
    lone = build_beam_system(12)
    clamped = natural_frequencies(lone, pack(lone.param_specs, pegasus.beam_params(12)), np.zeros(lone.n_forcing), count=1)
    assert 1.0 < lam[6] / (2 * np.pi * clamped[0]) < 1.1
    # the rigid fin root: a symmetry condition on both nodes of a rigid joint is refused
    s = m.system
    with pytest.raises(ValueError, match=r"joint fuselage node \d+ - fin node 0: both nodes of this rigid joint have "
                                         r"symmetry conditions"):
        build_joined_system(s.beams, s.joints, masses=s.masses, symmetry=list(s.symmetry) + [Symmetry("fin", 0)])


def test_adjoint_of_a_free_half_aircraft_march(kernel_on):
    """The discrete adjoint of a free half aircraft's march (symmetry reactions and lumped masses in
    the static-pivot LU's column order) against SuperLU and central differences: f = the wing tip's
    deflection from the wing root, squared and summed, under a step tip load. No step falls back
    to SuperLU (symmetry conditions on several nodes of one beam)."""
    model = _aircraft(False, nf=5, nw=4, nt=3)          # wing at fuselage node 1 (x = 2 m)
    s, t = model.system, np.linspace(0.0, 0.05, 11)
    pf = np.zeros((4, 3))
    pf[-1] = [0.0, 0.0, 2e3]
    Q = np.tile(model.forcing({"right_wing": {"point_force": pf}}), (t.size, 1))
    Q[0] = model.forcing()
    tip, root = s.node_index("right_wing", -1) + 2, s.node_index("right_wing", 0) + 2

    def f_of(states):
        d = (states[:, tip] - states[:, root]) - (states[0, tip] - states[0, root])
        dfdx = np.zeros_like(states)
        dfdx[:, tip], dfdx[:, root] = 2 * d, -2 * d
        dfdx[0, tip] -= np.sum(2 * d)
        dfdx[0, root] += np.sum(2 * d)
        return float(np.sum(d**2)), dfdx

    x0 = s.jig_state(model.p)
    run = lambda pp: march(s, t, pp, Q, initial="state", x_init=x0, xtol=1e-14)  # noqa: E731
    h = run(model.p)
    f, dfdx = f_of(h.states)
    assert f > 0.0
    lins = {lu: LinearizedHistory(s, t, h.states, model.p, Q, initial="state", lu=lu) for lu in ("static", "superlu")}
    grads = {lu: lin.gradient(dfdx)[0] for lu, lin in lins.items()}
    np.testing.assert_allclose(grads["static"], grads["superlu"], rtol=1e-8, atol=1e-12 * np.max(np.abs(grads["superlu"])))
    # symmetry conditions on all 5 fuselage nodes: every step solved by the static-pivot LU
    stats = lins["static"].static_stats
    assert lins["static"].lu_method == "static"
    assert stats["fallback"] == 0 and stats["factored"] >= t.size - 1, stats
    lay = layout(s.param_specs)
    picks = {"engine mass": lay["lumped_mass"].start, "engine offset x": lay["lumped_mass_offset"].start,
             "wing EI_cc node 1": lay["right_wing_stiffness_csn"].start + 9,
             "fuselage mass node 2": lay["fuselage_mass_per_length"].start + 2}
    for name, j in picks.items():
        step = 1e-3 * abs(model.p[j])
        e = np.zeros_like(model.p)
        e[j] = step
        fd = (f_of(run(model.p + e).states)[0] - f_of(run(model.p - e).states)[0]) / (2 * step)
        assert grads["static"][j] == pytest.approx(fd, rel=1e-5), name


# ----------------------------------------------------------------------------- inertia relief
def _free_beam_along_x(n1=11, n2=11, L=10.0):
    """A free-free uniform beam 10 m along body x (two beams, FUSELAGE_AXES) on the plane of
    symmetry (symmetry conditions on every node): free in surge, plunge and pitch."""
    r0, th0 = straight_beam(n1 + n2 - 1, L)
    sec = {**SECTION, "inertia_per_length": np.diag([1e-3] * 3)}
    return JoinedBeamModel([Beam("fore", n1, root="free", axes=FUSELAGE_AXES), Beam("aft", n2, root="free", axes=FUSELAGE_AXES)],
                           [Joint("fore", -1, "aft", 0)],
                           {"fore": beam_parameters(r0[:n1], th0[:n1], **sec), "aft": beam_parameters(r0[n1 - 1:], th0[n1 - 1:], **sec)},
                           symmetry=[Symmetry("fore", i) for i in range(n1)] + [Symmetry("aft", i) for i in range(1, n2)])


BEAM_SUPPORTS = [("fore", 0, "x"), ("fore", 0, "z"), ("aft", -1, "z")]


def test_inertia_relief_of_a_free_free_beam_against_closed_forms():
    """A free-free beam (m = 20 kg/m, L = 10 m, 20 elements) under a point force P: its plunge
    acceleration is P/(mL); under P at midspan each half is a cantilever from the centre under the
    inertial load P/L, so the centre rises P L^3/(128 EI) above the ends; under P at 3/4 span the
    pitch acceleration is -P (L/4) / I with the elements' I = m L^3 (1 - 1/N^2)/12 + i L."""
    model, P, L = _free_beam_along_x(), 100.0, 10.0
    mL = SECTION["mass_per_length"] * L
    up = np.array(FUSELAGE_AXES) @ [0.0, 0.0, P]          # +z in the fuselage's axes
    pf = np.zeros((11, 3))
    pf[0] = up
    out = model.solve_inertia_relief({"aft": {"point_force": pf}}, supports=BEAM_SUPPORTS)
    assert out["accelerations"]["az"] == pytest.approx(P / mL, rel=1e-10)
    assert abs(out["accelerations"]["alpha_y"]) < 1e-12
    assert out["aft"]["r"][0, 2] == pytest.approx(P * L**3 / (128 * SECTION["EI_cc"]), rel=1e-6)
    pf = np.zeros((11, 3))
    pf[5] = up
    acc = model.solve_inertia_relief({"aft": {"point_force": pf}}, supports=BEAM_SUPPORTS)["accelerations"]
    inertia = mL * L**2 * (1 - 1 / 20**2) / 12 + 1e-3 * L
    assert acc["alpha_y"] == pytest.approx(-P * 2.5 / inertia, rel=1e-8)
    assert acc["az"] - 5.0 * acc["alpha_y"] == pytest.approx(P / mL, rel=1e-8)     # the centre's acceleration


def test_inertia_relief_of_the_pegasus_half_aircraft_against_its_mass_properties():
    """Lift on the wing and a down-load on the tail of the free PEGASUS half aircraft: the CG's
    acceleration is F/m and the pitch acceleration M_cg/I_yy, with the mass, CG and pitch inertia
    summed from the model's data (cases.pegasus_stick._mass_properties), within the shift of the
    CG by the deformation."""
    ac = pegasus_stick.build(num_wing_nodes=12)
    pw, pt = np.zeros((12, 3)), np.zeros((8, 3))
    pw[1:, 2], pt[1:, 2] = 1000.0, -300.0
    out = ac.model.solve_inertia_relief({"wing": {"point_force": pw}, "tail": {"point_force": pt}},
                                        supports=[("fuselage", 0, "x"), ("fuselage", 0, "z"), ("fuselage", -1, "z")])
    a = out["accelerations"]
    force = pw[:, 2].sum() + pt[:, 2].sum()
    moment = -np.sum((ac.nodes["wing"][:, 0] - ac.cg[0]) * pw[:, 2]) - np.sum((ac.nodes["tail"][:, 0] - ac.cg[0]) * pt[:, 2])
    assert a["alpha_y"] == pytest.approx(moment / ac.pitch_inertia, rel=1e-3)
    assert a["az"] - a["alpha_y"] * ac.cg[0] == pytest.approx(force / ac.mass, rel=1e-4)
    assert abs(a["ax"] + a["alpha_y"] * ac.cg[2]) < 1e-3 * force / ac.mass


def test_inertia_relief_input_errors():
    model = _free_beam_along_x(5, 5)
    with pytest.raises(ValueError, match=r"2 supports for 3 accelerations"):
        model.solve_inertia_relief(supports=BEAM_SUPPORTS[:2])
    with pytest.raises(ValueError, match=r"accelerations must be distinct names of \['ax', 'ay', 'az', 'alpha_x'"):
        model.solve_inertia_relief(supports=BEAM_SUPPORTS, accelerations=("ax", "az", "pitch"))
    with pytest.raises(ValueError, match=r"component must be 'x', 'y' or 'z'"):
        model.solve_inertia_relief(supports=[("fore", 0, "x"), ("fore", 0, "z"), ("aft", -1, "pitch")])
    with pytest.raises(ValueError, match=r"do not hold the structure's rigid-body modes"):
        model.solve_inertia_relief(supports=[("fore", 0, "x"), ("fore", 0, "z"), ("fore", 0, "z")])


def test_monitoring_loads_at_the_wing_root_rib_balance_the_outboard_loads():
    """The PEGASUS half aircraft in inertia relief under gravity, wing lift and a tail down-load: the
    wing root rib's internal force and moment (monitoring_loads, the beam's F_1, M_1) equal the sum,
    over the wing outboard of the rib, of the external loads and the inertial loads of the elements
    and engines (-m (A_0 + alpha x r) with the deformed positions, the sections' and engines'
    -J alpha, the engines' offsets turned with their nodes), summed here from the model's data."""
    ac = pegasus_stick.build(num_wing_nodes=12)
    m, s = ac.model, ac.model.system
    pw, pt = np.zeros((12, 3)), np.zeros((8, 3))
    pw[1:, 2], pt[1:, 2] = 8000.0, -2000.0
    g = np.array([0.0, 0.0, -9.81])
    out = m.solve_inertia_relief({"wing": {"point_force": pw}, "tail": {"point_force": pt}}, gravity=g,
                                 supports=[("fuselage", 0, "x"), ("fuselage", 0, "z"), ("fuselage", -1, "z")])
    a = out["accelerations"]
    A0, alpha = np.array([a["ax"], 0.0, a["az"]]), np.array([0.0, a["alpha_y"], 0.0])
    wing, prm = out["wing"], m.params["wing"]
    r, th = wing["r"], wing["theta"]
    T = [np.array(body_to_csn(ca.DM(t), "surface")) for t in th]
    T0 = [np.array(body_to_csn(ca.DM(t), "surface")) for t in prm["node_euler_angles"]]
    origin, force, moment = r[1], np.zeros(3), np.zeros(3)
    for k in range(1, 12):                                   # external point loads on nodes 1..
        force += pw[k]
        moment += np.cross(r[k] - origin, pw[k])
    mu, ip = np.asarray(prm["mass_per_length"]), np.asarray(prm["inertia_per_length"])
    ds = np.linalg.norm(np.diff(np.asarray(prm["node_positions"]), axis=0), axis=1)
    for e in range(1, 11):                                   # elements outboard of the rib
        mid = 0.5 * (r[e] + r[e + 1])
        f = 0.5 * (mu[e] + mu[e + 1]) * ds[e] * (g - A0 - np.cross(alpha, mid))
        Tm = np.array(body_to_csn(ca.DM(0.5 * (th[e] + th[e + 1])), "surface"))
        J = Tm.T @ (0.5 * (ip[e] + ip[e + 1])) @ Tm * ds[e]
        force += f
        moment += np.cross(mid - origin, f) - J @ alpha
    for lm in s.masses:                                      # engines
        if lm.beam != "wing":
            continue
        lam = T[lm.node].T @ T0[lm.node]
        d, J = lam @ np.asarray(lm.offset), lam @ np.asarray(lm.inertia) @ lam.T
        f = lm.mass * (g - A0 - np.cross(alpha, r[lm.node] + d))
        force += f
        moment += np.cross(r[lm.node] + d - origin, f) - J @ alpha
    loads = monitoring_loads(s, out["x"], [MonitoringStation("wing root", "wing", 1)])["wing root"]
    np.testing.assert_allclose(loads["force"], force, rtol=0, atol=1e-9 * np.abs(force).max())
    np.testing.assert_allclose(loads["moment"], moment, rtol=0, atol=1e-9 * np.abs(moment).max())
    assert loads["moment_csn"][0] == pytest.approx(np.linalg.norm(moment[[0, 2]]), rel=0.05)    # root bending, csn
    with pytest.raises(ValueError, match=r"monitoring station 'root': node 0 of beam 'wing' must be in 1..11"):
        monitoring_loads(s, out["x"], [MonitoringStation("root", "wing", 0)])


def test_balanced_maneuver_of_the_pegasus_half_aircraft():
    """A 2.5 g maneuver of the free PEGASUS half aircraft balanced by wing lift and a tail load: the
    inertia-relief solution accelerates the CG by (n - 1) g, and the fuselage's shear and bending
    just ahead of the wing equal the inertial loads of the fuselage ahead of it (its elements and
    payload masses, -m (g + a(r))), summed here from the model's data."""
    ac = pegasus_stick.build(num_wing_nodes=12)
    n = 2.5
    out = pegasus_stick.balanced_maneuver(ac, n)
    a = out["accelerations"]
    assert out["wing_lift"] + out["tail_load"] == pytest.approx(n * ac.mass * 9.80665, rel=1e-12)
    assert a["az"] - a["alpha_y"] * ac.cg[0] == pytest.approx((n - 1) * 9.80665, rel=1e-5)
    assert abs(a["alpha_y"]) < 1e-2
    s, m = ac.model.system, ac.model
    i_wing = next(jt.node_a for jt in s.joints if jt.beam_b == "wing")
    fus = s.unpack(out["x"], body_axes=True)["fuselage"]
    prm = m.params["fuselage"]
    A0, alpha = np.array([a["ax"], 0.0, a["az"]]), np.array([0.0, a["alpha_y"], 0.0])
    g = np.array([0.0, 0.0, -9.80665])
    r = fus["r"]
    origin = r[i_wing]
    ds = np.linalg.norm(np.diff(np.asarray(prm["node_positions"]), axis=0), axis=1)
    mu = np.asarray(prm["mass_per_length"])
    force, moment = np.zeros(3), np.zeros(3)
    for e in range(i_wing):
        mid = 0.5 * (r[e] + r[e + 1])
        f = 0.5 * (mu[e] + mu[e + 1]) * ds[e] * (g - A0 - np.cross(alpha, mid))
        force, moment = force + f, moment + np.cross(mid - origin, f)
    for lm in s.masses:
        if lm.beam == "fuselage" and lm.node < i_wing:
            f = lm.mass * (g - A0 - np.cross(alpha, r[lm.node]))
            force, moment = force + f, moment + np.cross(r[lm.node] - origin, f)
    station = next(v for k, v in out["loads"].items() if "ahead of the wing" in k)
    # the cut's load on the forward part balances the forward part's loads
    np.testing.assert_allclose(station["force"], -force, rtol=0, atol=1e-8 * np.abs(force).max())
    np.testing.assert_allclose(station["moment"], -moment, rtol=0, atol=1e-8 * np.abs(moment).max())
    assert set(out["loads"]) >= {"wing root", "fin root", "tail root"}
