"""Figures of the joined-beam verification (docs/stick-model.md, "Checks").

Runs the cases of tests/test_beam_joints.py and prints ours / reference / difference: the split
cantilever against the single beam and PL^3/3EI, the free-free beam of two joined beams
(beta L = 4.7300, 7.8532, 10.9956), the L-frame under tip loads (unit-load method) and its in-plane
frequencies (frequency equation), the T-frame and the fuselage (own axes) with a wing under tip
loads (unit-load method), the hinge with a spring and the free hinge (pinned-free
beta L = 3.9266), the adjoint of a march against central differences, and the work of one
factorization of the static-pivot LU in three column orders. ``--compiled`` compares the compiled
march with the Python march; ``--figure PATH`` draws the pattern of dR/dx of three joined beams
(matplotlib). About 1 min (2 more with ``--compiled``, compiler cache cold).
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))
import test_beam_joints as T  # noqa: E402

from wingmdao.beam.joints import FUSELAGE_AXES, Beam, Joint, JoinedBeamModel, build_joined_system  # noqa: E402
from wingmdao.beam.static import beam_parameters, straight_beam  # noqa: E402
from wingmdao.timemarch import lu_orders, static_lu  # noqa: E402
from wingmdao.timemarch.adjoint import LinearizedHistory  # noqa: E402
from wingmdao.timemarch.bdf import march  # noqa: E402
from wingmdao.timemarch.system import layout  # noqa: E402


def _rel(a, b):
    return f"{100 * (a / b - 1):+.4f} %"


def split_cantilever():
    n, k, L, P = 21, 8, 10.0, 2e2
    single, joined = T._split_cantilever(n, k, L, **T.SECTION)
    pf = np.zeros((n, 3))
    pf[-1, 2] = P
    ref = single.solve(point_force=pf)["r"][-1, 2]
    ours = joined.solve({"outer": {"point_force": pf[k:]}})["outer"]["r"][-1, 2]
    closed = P * L**3 / (3 * T.SECTION["EI_cc"])
    print(f"split cantilever (8 + 12 elements), tip {P:.0f} N: joined {ours:.9f} m | single {ref:.9f} m | "
          f"PL^3/3EI {closed:.9f} m ({_rel(ours, closed)})")
    wj = T._frequencies(joined.system, joined.p, joined.forcing(), x0=joined.system.jig_state(joined.p))
    ws = T._frequencies(single.system, single.p, np.zeros(single.system.n_forcing), x0=single.jig())
    flap = 1.8751**2 * np.sqrt(T.SECTION["EI_cc"] / (T.SECTION["mass_per_length"] * L**4))
    print(f"  first flap {wj[0]:.6f} rad/s | single {ws[0]:.6f} | Euler-Bernoulli {flap:.6f} ({_rel(wj[0], flap)}); "
          f"max difference joined/single over 6 modes {np.max(np.abs(wj[:6] / ws[:6] - 1)):.1e}")


def free_free():
    L = 10.0
    scale = np.sqrt(T.SECTION["EI_cc"] / (T.SECTION["mass_per_length"] * L**4))
    ref = np.array([4.7300, 7.8532, 10.9956]) ** 2 * scale
    w = {}
    for n1, n2 in ((9, 13), (17, 25)):
        zero, w[n1 + n2 - 2] = T._free_free_flap_frequencies(n1, n2, L)
    rich = (4 * w[40] - w[20]) / 3
    print(f"free-free, two joined beams: {zero} zero eigenvalues (6 rigid-body modes); flap modes, rad/s")
    for i in range(3):
        print(f"  mode {i + 1}: 20 el. {w[20][i]:.4f}, 40 el. {w[40][i]:.4f} ({_rel(w[40][i], ref[i])}), "
              f"Richardson {rich[i]:.4f} ({_rel(rich[i], ref[i])}) | closed form {ref[i]:.4f}")


def l_frame():
    model = T._l_frame()
    P = 10.0
    r_tip = model.params["arm"]["node_positions"][-1]
    pf = np.zeros((17, 3))
    pf[-1] = [0.0, 0.0, -P]
    d = model.solve({"arm": {"point_force": pf}})["arm"]["r"][-1] - r_tip
    c, a = T.COLUMN, T.ARM
    ref = P * T.LA**3 / (3 * a["EI_cc"]) + P * T.LA**2 * T.H / c["EI_cc"] + P * T.H / c["EA"]
    print(f"L-frame (12 + 16 elements), tip {P:.0f} N: in-plane -z {-d[2]:.6e} m | unit load {ref:.6e} m ({_rel(-d[2], ref)})")
    ref_y = P * T.LA * T.H**2 / (2 * c["EI_cc"])
    print(f"  sway of the column top carried to the tip, y {d[1]:.6e} m | {ref_y:.6e} m ({_rel(d[1], ref_y)})")
    pf[-1] = [P, 0.0, 0.0]
    d = model.solve({"arm": {"point_force": pf}})["arm"]["r"][-1] - r_tip
    ref = P * T.LA**3 / (3 * a["EI_nn"]) + P * T.LA**2 * T.H / c["GJ"] + P * T.H**3 / (3 * c["EI_nn"])
    print(f"  out-of-plane x {d[0]:.6e} m | unit load {ref:.6e} m ({_rel(d[0], ref)})")
    m1, m2 = 30.0, 20.0
    ref = T._l_frame_frequency_equation(c["EI_cc"], m1, a["EI_cc"], m2)
    col = dict(EI_cc=c["EI_cc"], EI_nn=10 * c["EI_cc"], GJ=5 * c["EI_cc"], EA=1e11, mass_per_length=m1,
               inertia_per_length=T.ROT)
    arm = dict(EI_cc=a["EI_cc"], EI_nn=10 * a["EI_cc"], GJ=5 * a["EI_cc"], EA=1e11, mass_per_length=m2,
               inertia_per_length=T.ROT)
    w = {}
    for n1, n2 in ((7, 9), (13, 17)):
        rc, thc = straight_beam(n1, T.H, (0.0, 0.0, 1.0))
        ra, tha = straight_beam(n2, T.LA, (0.0, 1.0, 0.0))
        frame = JoinedBeamModel([Beam("column", n1), Beam("arm", n2, root="free")], [Joint("column", -1, "arm", 0)],
                                {"column": beam_parameters(rc, thc, **col),
                                 "arm": beam_parameters(ra + [0.0, 0.0, T.H], tha, **arm)})
        w[n1 + n2 - 2] = T._frequencies(frame.system, frame.p, frame.forcing())[:2]
    rich = (4 * w[28] - w[14]) / 3
    for i in range(2):
        print(f"  in-plane mode {i + 1}: 14 el. {w[14][i]:.4f}, 28 el. {w[28][i]:.4f} ({_rel(w[28][i], ref[i])}), "
              f"Richardson {rich[i]:.4f} ({_rel(rich[i], ref[i])}) | frequency equation {ref[i]:.4f} rad/s")


def t_frame():
    LR, LL, PR, PL = 4.0, 2.5, -10.0, 8.0
    rc, thc = straight_beam(13, T.H, (0.0, 0.0, 1.0))
    rr, thr = straight_beam(17, LR, (0.0, 1.0, 0.0))
    rl, thl = straight_beam(11, LL, (0.0, -1.0, 0.0))
    left = dict(EI_cc=0.6e6, EI_nn=2e6, GJ=0.5e6, EA=1e10)
    model = JoinedBeamModel([Beam("column", 13), Beam("right", 17, root="free"), Beam("left", 11, root="free")],
                            [Joint("column", -1, "right", 0), Joint("left", 0, "column", -1)],
                            {"column": beam_parameters(rc, thc, **T.COLUMN),
                             "right": beam_parameters(rr + [0.0, 0.0, T.H], thr, **T.ARM),
                             "left": beam_parameters(rl + [0.0, 0.0, T.H], thl, **left)})
    out = model.solve({"right": {"point_force": np.outer(np.eye(17)[-1], [0.0, 0.0, PR])},
                       "left": {"point_force": np.outer(np.eye(11)[-1], [0.0, 0.0, PL])}})
    phi = (LR * PR - LL * PL) * T.H / T.COLUMN["EI_cc"]
    short = (PR + PL) * T.H / T.COLUMN["EA"]
    right = PR * LR**3 / (3 * T.ARM["EI_cc"]) + phi * LR + short
    lft = PL * LL**3 / (3 * left["EI_cc"]) - phi * LL + short
    dr, dl = out["right"]["r"][-1, 2] - T.H, out["left"]["r"][-1, 2] - T.H
    print(f"T-frame (12 + 16 + 10 elements, two joints on the column top), tips {PR:.0f} / {PL:+.0f} N: "
          f"right z {dr:.6e} m | {right:.6e} ({_rel(dr, right)}), left z {dl:.6e} m | {lft:.6e} ({_rel(dl, lft)})")


def fuselage():
    Lf, a, Lw, P = 6.0, 4.0, 5.0, 10.0
    fus = dict(EI_cc=4e6, EI_nn=7e6, GJ=3e6, EA=1e9, mass_per_length=50.0)
    wing = dict(EI_cc=1e6, EI_nn=5e6, GJ=1e6, EA=1e9, mass_per_length=20.0)
    R = np.array(FUSELAGE_AXES)
    rf, thf = straight_beam(13, Lf)
    rw, thw = straight_beam(21, Lw)
    model = JoinedBeamModel([Beam("fuselage", 13, axes=FUSELAGE_AXES), Beam("wing", 21, root="free")],
                            [Joint("fuselage", 8, "wing", 0)],
                            {"fuselage": beam_parameters(rf, thf, **fus),
                             "wing": beam_parameters(rw + R.T @ rf[8], thw, **wing)})
    res = []
    for load, axis, ref in (([0.0, 0.0, -P], 2, -P * (Lw**3 / (3 * wing["EI_cc"]) + a**3 / (3 * fus["EI_cc"])
                                                         + Lw**2 * a / fus["GJ"])),
                            ([P, 0.0, 0.0], 0, P * (Lw**3 / (3 * wing["EI_nn"]) + Lw**2 * a / fus["EI_nn"]
                                                    + a / fus["EA"]))):
        out = model.solve({"wing": {"point_force": np.outer(np.eye(21)[-1], load)}})
        d = (out["wing"]["r"][-1] - model.params["wing"]["node_positions"][-1])[axis]
        res.append(f"{'xyz'[axis]} {d:.6e} m | {ref:.6e} ({_rel(d, ref)})")
    print(f"fuselage along x (own axes, 12 el.) with a wing (20 el.) at x = {a} m, tip {P:.0f} N: " + "; ".join(res))


def hinges():
    k, M = 2.5e5, 6e4
    model = T._hinged_beam(k)
    pm = np.zeros((13, 3))
    pm[-1] = [M, 0.0, 0.0]
    phi = model.solve({"outboard": {"point_moment": pm}}, load_steps=4)["outboard"]["theta"][-1, 0]
    ref = M * (4.0 / 3e6 + 1.0 / k + 6.0 / 1e6)
    print(f"hinge k = {k:.3g} N m/rad, tip moment {M:.3g} N m: tip rotation {phi:.12f} rad | "
          f"M (L1/EI1 + 1/k + L2/EI2) {ref:.12f} ({phi / ref - 1:+.1e})")
    EI, mu, L2 = 1e6, 10.0, 6.0
    free = T._hinged_beam(None, n1=3, n2=31, L1=0.5, L2=L2, sec1=dict(EI_cc=1e10, GJ=1e10, EI_nn=1e10, EA=1e12),
                          sec2=dict(EI_cc=EI, GJ=1e6, EI_nn=1e8, EA=1e11), mass_per_length=mu,
                          inertia_per_length=T.ROT)
    modes = T.eigenmodes(free.system, free.p, free.forcing(), free.system.jig_state(free.p), static=False,
                         method="sparse", sigma=5.0, count=8)
    scale = np.sqrt(EI / (mu * L2**4))
    w = np.sort(modes.frequency)
    ref = 3.9266**2 * scale
    print(f"free hinge on a stiff stub (30 elements): {int(np.sum(w < 1e-3 * scale))} zero eigenvalues, first flap "
          f"{w[w > 1e-3 * scale][0]:.4f} rad/s | pinned-free {ref:.4f} ({_rel(w[w > 1e-3 * scale][0], ref)})")


def adjoint():
    system, t, p, Q = T._march_case()
    run = lambda pp: march(system, t, pp, Q, atol=1e-12, static_options={"rtol": 1e-14})  # noqa: E731
    h = run(p)
    f, dfdx = T._tip_functional(system, h.states)
    g = LinearizedHistory(system, t, h.states, p, Q).gradient(dfdx)[0]
    lay = layout(system.param_specs)
    print(f"adjoint of a {t.size}-step march ({system.n_state} states, hinged L-frame), f = {f:.6e} m^2:")
    for name, j in (("arm EI_cc, node 1", lay["arm_stiffness_csn"].start + 9),
                    ("column GJ, node 2", lay["column_stiffness_csn"].start + 9 * 2 + 4),
                    ("column mass per length, node 0", lay["column_mass_per_length"].start),
                    ("hinge spring stiffness", lay["joint_rotational_stiffness"].start)):
        e = np.zeros_like(p)
        e[j] = 1e-3 * abs(p[j])
        fd = (T._tip_functional(system, run(p + e).states)[0]
              - T._tip_functional(system, run(p - e).states)[0]) / (2 * e[j])
        print(f"  df/d({name}): adjoint {g[j]:+.9e} | central difference {fd:+.9e} ({g[j] / fd - 1:+.1e})")


def compiled():
    """The compiled march (wingmdao.timemarch.fast_step) against the Python march, and the adjoint's
    static-pivot LU statistics, on a 200-step march of the hinged L-frame (9 + 9 nodes)."""
    system, _, p, Q = T._march_case(n1=9, n2=9, n_time=200)
    t = np.linspace(0.0, 1.0, 200)
    slow = march(system, t, p, Q, fast=False)
    system.compile(wait=True)
    fast = march(system, t, p, Q, fast=True)
    lin = LinearizedHistory(system, t, fast.states, p, Q)
    lin.gradient(T._tip_functional(system, fast.states)[1])
    print(f"compiled march, {t.size} steps, {system.n_state} states: max |x_compiled - x_python| "
          f"{np.max(np.abs(fast.states - slow.states)):.1e} (max |x| {np.max(np.abs(slow.states)):.3g}); adjoint LU "
          f"{lin.lu_method}: {lin.static_stats}")


def lu_work():
    if static_lu.kernel() is None:
        print("LU work: the static-pivot LU kernel is off (WINGMDAO_JIT=0 or no gcc)")
        return
    model = T._l_frame(9, 9, column=dict(mass_per_length=30.0), arm=dict(mass_per_length=20.0))
    s = model.system
    pf = np.zeros((9, 3))
    pf[-1] = [100.0, 50.0, -300.0]
    x = model.solve({"arm": {"point_force": pf}}, gravity=[0.0, 0.0, -9.81])["x"]
    q = model.forcing({"arm": {"point_force": pf}}, gravity=[0.0, 0.0, -9.81])
    mat = s.residual_and_newton_matrix(x, np.zeros_like(x), model.p, q, 1500.0)[1].tocsc()
    mat.sort_indices()
    n = s.n_state
    orders = {"natural": None,
              "BEAM_NODE_ORDER, joints last": static_lu.block_column_order(lu_orders.BEAM_NODE_ORDER, 18, n),
              "joined_lu_column_order": s.lu_column_order()}
    work = {k: static_lu.factorization_work(n, mat.indices, mat.indptr, mat.data, o) for k, o in orders.items()}
    print(f"static-pivot LU of the L-frame Newton matrix (9 + 9 nodes, {n} states, {mat.nnz} structural nonzeros), "
          "multiply-adds per factorization: " + ", ".join(f"{k} {v}" for k, v in work.items()))


def figure(path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    beams = [Beam("fuselage", 9, axes=FUSELAGE_AXES), Beam("wing", 7, root="free"), Beam("tail", 5, root="free")]
    joints = [Joint("fuselage", 3, "wing", 0), Joint("fuselage", -1, "tail", 0)]
    s = build_joined_system(beams, joints)
    rows, cols, shape = s.jacobian_patterns()["x"]
    fig, ax = plt.subplots(figsize=(6, 6))
    ax.plot(cols, rows, "s", markersize=0.6, color="k")
    edges = [s.offsets[b.name] for b in beams] + [s.joint_offset, s.n_state]
    for e in edges[1:-1]:
        ax.axhline(e - 0.5, color="tab:red", lw=0.5)
        ax.axvline(e - 0.5, color="tab:red", lw=0.5)
    ax.set_xlim(-0.5, shape[1] - 0.5)
    ax.set_ylim(shape[0] - 0.5, -0.5)
    ax.set_xlabel("unknown")
    ax.set_ylabel("equation")
    ax.set_title("dR/dx of three joined beams (9, 7, 5 nodes; 2 rigid joints)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    print(f"wrote {path} ({rows.size} structural nonzeros of {shape[0]} x {shape[1]})")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figure", default=None, help="write the dR/dx pattern of three joined beams here (default: none)")
    parser.add_argument("--compiled", action="store_true",
                        help="also compile the L-frame's functions and compare the compiled march (default: off)")
    args = parser.parse_args()
    split_cantilever()
    free_free()
    l_frame()
    t_frame()
    fuselage()
    hinges()
    adjoint()
    lu_work()
    if args.compiled:
        compiled()
    if args.figure:
        figure(args.figure)


if __name__ == "__main__":
    main()
