"""Figures of lumped masses, free flight and the PEGASUS stick model (docs/stick-model.md).

Runs the cases of tests/test_stick_free.py and prints ours / reference / difference: a cantilever
with an offset tip mass under gravity (Euler-Bernoulli and Saint-Venant closed forms), its first
bending frequency (exact tip-mass frequency equation, Rayleigh) and torsion frequency with a tip
inertia, the rigid-body modes of the free half and full test aircraft, the drift of linear momentum
in a free march, inertia relief of a free-free beam and of the PEGASUS half aircraft; then the
PEGASUS half aircraft of :mod:`wingmdao.cases.pegasus_stick`: mass, centre of gravity, pitch
inertia, rigid-body modes and elastic frequencies (with each beam's share of the mode), beside the
clamped lone wing's, and its balanced 2.5 g maneuver with inertia relief: the loads at the
monitoring stations beside the lone wing's root loads. About 2.5 min (``--no-pegasus``: without the modes).
"""

import argparse
import os
import sys

import numpy as np
import scipy.optimize as sopt

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))
import test_stick_free as T  # noqa: E402

from wingmdao.beam.joints import LumpedMass  # noqa: E402
from wingmdao.beam.modes import natural_frequencies  # noqa: E402
from wingmdao.beam.residual import build_beam_system  # noqa: E402
from wingmdao.beam.static import BeamModel  # noqa: E402
from wingmdao.cases import pegasus, pegasus_stick  # noqa: E402
from wingmdao.cases.planform import G0, LB, wing_geometry  # noqa: E402
from wingmdao.loads.maneuver import maneuver_line_loads  # noqa: E402
from wingmdao.timemarch.adjoint import LinearizedHistory  # noqa: E402
from wingmdao.timemarch.bdf import march  # noqa: E402
from wingmdao.timemarch.system import pack  # noqa: E402


def _rel(a, b):
    return f"{100 * (a / b - 1):+.4f} %"


def tip_mass():
    M, e, d, g, L = 20.0, 0.5, 0.3, 9.81, T.L
    model = T._cantilever([LumpedMass("wing", -1, M, offset=(d, e, 0.0))], mass_per_length=1e-9)
    tip = model.solve(gravity=[0.0, 0.0, -g])["wing"]
    P, EI, GJ = M * g, T.SECTION["EI_cc"], T.SECTION["GJ"]
    w_ref = -(P * L**3 / (3 * EI) + P * e * L**2 / (2 * EI))
    print(f"tip mass 20 kg at (0.3, 0.5, 0) m, gravity, 20 elements: tip w {tip['r'][-1, 2]:.6e} m "
          f"({_rel(tip['r'][-1, 2], w_ref)} from PL^3/3EI + PeL^2/2EI), twist {tip['theta'][-1, 1]:.6e} rad "
          f"({_rel(tip['theta'][-1, 1], P * d * L / GJ)} from PdL/GJ)")
    mL = T.SECTION["mass_per_length"] * L
    for ratio in (0.5, 1.0, 2.0):
        J, rho_ip = 1e-2, T.ROT[1, 1]
        model = T._cantilever([LumpedMass("wing", -1, ratio * mL, inertia=np.diag([1e-9, J, 1e-9]))])
        w = T._frequencies(model)
        eq = lambda b: 1 + np.cos(b) * np.cosh(b) + ratio * b * (np.cos(b) * np.sinh(b) - np.sin(b) * np.cosh(b))  # noqa: E731
        bL = sopt.brentq(eq, 0.3, 1.8751)
        exact = bL**2 * np.sqrt(T.SECTION["EI_cc"] / (T.SECTION["mass_per_length"] * L**4))
        rayleigh = np.sqrt(3 * T.SECTION["EI_cc"] / (L**3 * (ratio * mL + 33 / 140 * mL)))
        gam = sopt.brentq(lambda x: x * np.tan(x) - rho_ip * L / J, 1e-6, np.pi / 2 - 1e-9)
        torsion = gam / L * np.sqrt(T.SECTION["GJ"] / rho_ip)
        wt = w[np.argmin(np.abs(w / torsion - 1))]
        print(f"  M/mL = {ratio}: bending {w[0]:.4f} rad/s, exact (beta L = {bL:.5f}) {exact:.4f} ({_rel(w[0], exact)}), "
              f"Rayleigh {rayleigh:.4f} ({_rel(w[0], rayleigh)}); torsion with J = 0.01 kg m^2 {wt:.2f}, "
              f"closed form {torsion:.2f} ({_rel(wt, torsion)})")


def free_aircraft():
    for full in (False, True):
        model = T._aircraft(full)
        modes = T.eigenmodes(model.system, model.p, model.forcing(), model.system.jig_state(model.p),
                             static=False, method="dense")
        lam = np.sort(np.abs(modes.eigenvalues))
        zero = int(np.sum(lam < 1e-8))
        print(f"{'full' if full else 'half'} test aircraft ({model.system.n_state} states): {zero} zero eigenvalues "
              f"({zero // 2} rigid-body modes), largest {lam[zero - 1]:.1e} 1/s; next {lam[zero]:.2f} rad/s")
        m2 = T._aircraft(full, engine=dict(inertia=T.ENGINE["inertia"]))
        t = np.arange(41) * 2e-3
        Q = np.tile(m2.forcing(), (t.size, 1))
        h = march(m2.system, t, m2.p, Q, initial="state", x_init=T._moving_state(m2), xtol=1e-14)
        P = np.array([m2.system.linear_momentum(x, m2.p) for x in h.states])
        free = [0, 1, 2] if full else [0, 2]
        drift = np.max(np.abs(P[:, free] - P[0, free])) / np.max(np.abs(P[0]))
        print(f"  40-step free march, no load: momentum {P[0].round(3)} kg m/s, largest change {drift:.1e} relative")


def inertia_relief():
    model, P, L = T._free_beam_along_x(), 100.0, 10.0
    mL = T.SECTION["mass_per_length"] * L
    up = np.array(T.FUSELAGE_AXES) @ [0.0, 0.0, P]
    pf = np.zeros((11, 3))
    pf[0] = up
    out = model.solve_inertia_relief({"aft": {"point_force": pf}}, supports=T.BEAM_SUPPORTS)
    w_ref = P * L**3 / (128 * T.SECTION["EI_cc"])
    print(f"inertia relief, free-free beam, P at midspan: az {out['accelerations']['az']:.15f} m/s^2 (P/mL {P / mL}), "
          f"centre {out['aft']['r'][0, 2]:.6e} m ({out['aft']['r'][0, 2] / w_ref - 1:+.1e} from P L^3/128 EI)")
    pf = np.zeros((11, 3))
    pf[5] = up
    acc = model.solve_inertia_relief({"aft": {"point_force": pf}}, supports=T.BEAM_SUPPORTS)["accelerations"]
    inertia = mL * L**2 * (1 - 1 / 20**2) / 12 + 1e-3 * L
    print(f"  P at 3/4 span: alpha_y {acc['alpha_y']:.6f} rad/s^2 ({acc['alpha_y'] / (-P * 2.5 / inertia) - 1:+.1e}), "
          f"centre az {acc['az'] - 5 * acc['alpha_y']:.6f} ({(acc['az'] - 5 * acc['alpha_y']) / (P / mL) - 1:+.1e})")
    ac = pegasus_stick.build(num_wing_nodes=12)
    pw, pt = np.zeros((12, 3)), np.zeros((8, 3))
    pw[1:, 2], pt[1:, 2] = 1000.0, -300.0
    a = ac.model.solve_inertia_relief({"wing": {"point_force": pw}, "tail": {"point_force": pt}},
                                      supports=[("fuselage", 0, "x"), ("fuselage", 0, "z"),
                                                ("fuselage", -1, "z")])["accelerations"]
    force = pw[:, 2].sum() + pt[:, 2].sum()
    moment = (-np.sum((ac.nodes["wing"][:, 0] - ac.cg[0]) * pw[:, 2])
              - np.sum((ac.nodes["tail"][:, 0] - ac.cg[0]) * pt[:, 2]))
    a_cg = a["az"] - a["alpha_y"] * ac.cg[0]
    print(f"  PEGASUS half aircraft (12-node wing): CG az {a_cg:.6f} m/s^2 ({a_cg / (force / ac.mass) - 1:+.1e} from F/m), "
          f"alpha_y {a['alpha_y']:.6f} rad/s^2 ({a['alpha_y'] / (moment / ac.pitch_inertia) - 1:+.1e} from M/I_yy), "
          f"CG ax / az {(a['ax'] + a['alpha_y'] * ac.cg[2]) / a_cg:+.1e}")


def pegasus_modes(count=10):
    ac = pegasus_stick.build()
    print(f"PEGASUS stick, half aircraft ({ac.model.system.n_state} states): mass {ac.mass:.1f} kg, "
          f"CG ({ac.cg[0]:.3f}, {ac.cg[1]:.3f}, {ac.cg[2]:.3f}) m, I_yy about the CG {ac.pitch_inertia:.4g} kg m^2")
    fr = pegasus_stick.natural_frequencies(ac, count)
    print(f"  rigid-body modes: {fr['rigid']}; elastic modes (Hz, share of each beam in the displacement):")
    for f, sh in zip(fr["hz"], fr["shares"]):
        print(f"  {f:8.3f}  " + ", ".join(f"{k} {v:.2f}" for k, v in sh.items()))
    n = 20
    system = build_beam_system(n)
    lone = natural_frequencies(system, pack(system.param_specs, pegasus.beam_params(n)), np.zeros(system.n_forcing),
                               count=4)
    print("  lone wing, clamped, engines smeared (pegasus.beam_params): " + ", ".join(f"{f:.3f}" for f in lone) + " Hz")


def pegasus_maneuver(n_load=2.5):
    n = 20
    ac = pegasus_stick.build(n)
    out = pegasus_stick.balanced_maneuver(ac, n_load)
    a = out["accelerations"]
    print(f"PEGASUS stick, {n_load} g balanced maneuver (half aircraft): wing lift {out['wing_lift']:.0f} N, "
          f"tail load {out['tail_load']:+.0f} N; CG az {a['az'] - a['alpha_y'] * ac.cg[0]:.6f} m/s^2 "
          f"((n - 1) g = {(n_load - 1) * G0:.6f}), alpha_y {a['alpha_y']:+.2e} rad/s^2")
    print("  monitoring station: force (N), moment (N m), body axes")
    for k, v in out["loads"].items():
        print(f"  {k:44s} F ({v['force'][0]:.0f}, {v['force'][1]:.0f}, {v['force'][2]:.0f}) "
              f"M ({v['moment'][0]:.0f}, {v['moment'][1]:.0f}, {v['moment'][2]:.0f})")
    geo, chord, frac = wing_geometry(pegasus.flutter_planform(n), pegasus.ENGINES)
    pf = pegasus.PLANFORM
    ll = maneuver_line_loads(geo.node_positions, chord, frac, pegasus.TOGW_LB * LB * G0, n_load, semi_span=pf.semi_span,
                             fuselage_half_width=pf.root_rib * pf.semi_span)
    lone = BeamModel(pegasus.beam_params(n)).solve(force_per_length=ll.force_per_length,
                                                   moment_per_length=ll.moment_per_length, gravity=[0.0, 0.0, -G0],
                                                   frame_acceleration=[0.0, 0.0, (n_load - 1) * G0])
    stick = out["loads"]["wing root"]
    print(f"  lone wing (clamped, engines smeared, the size command's maneuver): root rib F_z {lone['F'][1, 2]:.0f} N, "
          f"M_x {lone['M'][1, 0]:.0f} N m; stick / lone: shear {stick['force'][2] / lone['F'][1, 2]:.4f}, "
          f"bending {stick['moment'][0] / lone['M'][1, 0]:.4f}")


def compiled():
    """The compiled march against the Python march on a free half aircraft (5 + 4 + 3 nodes, 100
    steps, step tip load and gravity), and the adjoint's static-pivot LU statistics."""
    model = T._aircraft(False, nf=5, nw=4, nt=3)
    s = model.system
    t = np.linspace(0.0, 0.5, 101)
    pf = np.zeros((4, 3))
    pf[-1] = [0.0, 0.0, 2e3]
    Q = np.tile(model.forcing({"right_wing": {"point_force": pf}}, gravity=[0.0, 0.0, -9.81]), (t.size, 1))
    x0 = s.jig_state(model.p)
    slow = march(s, t, model.p, Q, initial="state", x_init=x0, fast=False)
    s.compile(wait=True)
    fast = march(s, t, model.p, Q, initial="state", x_init=x0, fast=True)
    lin = LinearizedHistory(s, t, fast.states, model.p, Q, initial="state")
    lin.gradient(np.ones_like(fast.states))
    print(f"compiled march of the free half test aircraft, {t.size} steps, {s.n_state} states: "
          f"max |x_compiled - x_python| {np.max(np.abs(fast.states - slow.states)):.1e} "
          f"(max |x| {np.max(np.abs(slow.states)):.3g}); adjoint LU {lin.lu_method}: {lin.static_stats}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-pegasus", action="store_true", help="skip the PEGASUS stick model (default: run it)")
    parser.add_argument("--compiled", action="store_true",
                        help="also compile a free half aircraft's functions and compare the compiled march (default: off)")
    args = parser.parse_args()
    tip_mass()
    free_aircraft()
    inertia_relief()
    if not args.no_pegasus:
        pegasus_modes()
        pegasus_maneuver()
    if args.compiled:
        compiled()


if __name__ == "__main__":
    main()
