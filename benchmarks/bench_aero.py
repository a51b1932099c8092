"""Coupled aeroelastic march and adjoint beside the structural-only ones, per time step (issue 13
speed goal: a coupled step at most 1.5x a structural step), 20 nodes x 500 steps.

Four OpenMDAO problems of the same beam (BeamDynamics under the rigid-strip lift; BeamDynamics
under the rigid-strip lift and its pitching moment about the beam axis, a bending-torsion
response like the coupled one; AeroelasticBeamDynamics clamped; AeroelasticBeamDynamics free in
plunge from the trimmed 1 g state), each followed by a KS of the root moments (selected by
``bench_beam.WeightedStates``, constant partials declared: an ``ExecComp`` complex-stepped every
entry of the history in each linearization); the same 1-cos gust. Timed: the forward march (run_model) and the discrete adjoint (compute_totals of the KS
w.r.t. stiffness_csn and mass_per_length), best of ``--repeat`` (3), divided by the number of steps; ratios to
the first (the goal's reference) and to the second. ``--breakdown`` adds, per step, the parts
of one adjoint linearization: Jacobian-history evaluation, the blocks of the Newton matrices
(``LinearizedHistory`` set-up less the evaluation) and one SuperLU factorization, with the
Newton-matrix and L+U nonzeros. CasADi functions compiled first (gcc; cached), or
``--interpreted`` (WINGMDAO_JIT=0).

    python benchmarks/bench_aero.py [--nodes 20] [--steps 500] [--interpreted] [--breakdown]
    python benchmarks/bench_aero.py --pegasus [--rounds 5]

``--pegasus``: the same ratios inside the PEGASUS gust model itself (``wingmdao.sizing.build_problem``
of the Table 5.3 gust, 20 nodes, 251 steps; strip-theory loads, coupled clamped with trim, coupled
free plunge + trim): process time of the beam component alone (its ``solve_nonlinear`` for the
march; ``linearize`` + ``solve_linear`` + ``apply_linear`` for the adjoint, read from a cProfile of
``run_model`` + ``compute_totals`` of the case's KS w.r.t. the four wall thicknesses), the three
models in interleaved rounds, best round per model. A swept wing with dihedral fills every
structural entry of the Newton matrix, which the straight beam's does not.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
import openmdao.api as om

from wingmdao.aero import aero_parameters
from wingmdao.beam.static import beam_parameters, straight_beam
from wingmdao.components.aeroelastic import AeroelasticBeamDynamics
from wingmdao.components.beam import BeamDynamics
from wingmdao.components.ks import KSAggregate

from bench_beam import WeightedStates  # g = w * states, constant partials declared (no complex step)

V, RHO, CHORD, U_GUST, G = 60.0, 1.2, 1.0, 5.0, 9.81


def _inputs(n, nt, dt):
    r0, th0 = straight_beam(n, 10.0)
    bp = beam_parameters(r0, th0, EI_cc=2e6, GJ=1.6e6, EI_nn=1e7, EA=1e9, mass_per_length=20.0,
                         inertia_per_length=np.diag([0.1, 0.2, 0.1]))
    t = np.arange(nt) * dt
    gust = U_GUST * np.sin(np.pi * np.clip(t / 0.2, 0.0, 1.0)) ** 2
    return t, bp, gust


def build(kind, n, nt, dt, compile_first=False):
    """Problem ``kind`` in structural | coupled | plunge, run once; returns (problem, number of states)."""
    t, bp, gust = _inputs(n, nt, dt)
    prob = om.Problem(reports=False)
    vals = dict(bp)
    if kind.startswith("structural"):
        comp = BeamDynamics(num_nodes=n, time=t)
        flp = np.zeros((nt, n, 3))
        lift = 0.5 * RHO * V ** 2 * CHORD * 2 * np.pi * gust / V
        flp[:, :, 2] = lift[:, None]
        vals["force_per_length"] = flp
        if kind == "structural_torsion":  # lift at the quarter chord, beam axis at 0.4 chord: nose up
            mlp = np.zeros((nt, n, 3))
            mlp[:, :, 1] = (lift * (0.4 - 0.25) * CHORD)[:, None]
            vals["moment_per_length"] = mlp
    else:
        free = kind == "plunge"
        comp = AeroelasticBeamDynamics(num_nodes=n, time=t, plunge=free, trim=free)
        vals.update(aero_parameters(n, chord=CHORD, ref_point=0.4, airspeed=V, density=RHO))
        vals["gust_velocity"] = np.repeat(gust[:, None], n, axis=1)
        if free:
            vals.update(body_mass=2000.0, trim_lift=(2000.0 + 2 * 200.0) * G,
                        gravity=np.tile([0.0, 0.0, -G], (nt, 1)), trim_active=(t == 0).astype(float))
    prob.model.add_subsystem("beam", comp, promotes=["*"])
    system = comp.build_system()
    shape = (nt,) + tuple(system.state_shape)
    w = np.zeros(shape)
    root_m = system.layout.beam[0, 9:12] if hasattr(system, "layout") else np.arange(9, 12)
    w.reshape(nt, -1)[:, root_m] = 1e-5  # node 0 (root) moments, N m normalised
    prob.model.add_subsystem("pick", WeightedStates(weights=w), promotes=["*"])
    prob.model.add_subsystem("ks", KSAggregate(families={"root": shape}, rho_ks=50.0))
    prob.model.connect("g", "ks.g_root")
    if compile_first:  # compiled CasADi functions for every model (not only those in the cache)
        comp.build_system().compile(wait=True)
    prob.setup(mode="rev")
    for k, v in vals.items():
        prob.set_val(k, v)
    prob.run_model()
    return prob, int(np.prod(shape[1:]))


def breakdown(prob, nt, dt):
    """Per step (ms): evaluation of the state Jacobians dR/dx, dR/dxdot (what the linearization
    evaluates; dR/dp, dR/dq wait for their first use), the rest of the linearization (rates,
    pattern, Newton-matrix blocks), one SuperLU factorization (best of 3 each); nonzeros of A_n
    and of its L + U (natural order)."""
    import scipy.sparse.linalg as spla

    from wingmdao.timemarch.adjoint import LinearizedHistory
    from wingmdao.timemarch.newton import PERMC_SPEC
    from wingmdao.timemarch.system import pack

    system = prob.model.beam.build_system()
    X = np.asarray(prob.get_val("states")).reshape(nt, -1)
    p = pack(system.param_specs, {s.name: prob.get_val(s.name) for s in system.param_specs})
    Q = np.concatenate([np.asarray(prob.get_val(s.name)).reshape(nt, -1) for s in system.forcing_specs], axis=1)
    t = np.arange(nt) * dt
    Xd = np.zeros_like(X)
    t_jac = timed(lambda: system.state_jacobian_history(X, Xd, p, Q))
    t_lin = timed(lambda: LinearizedHistory(system, t, X, p, Q))
    lin = LinearizedHistory(system, t, X, p, Q)
    A = lin.newton_matrix(nt // 2)
    t_lu = timed(lambda: [spla.splu(A, permc_spec=PERMC_SPEC) for _ in range(50)]) / 50
    lu = spla.splu(A, permc_spec=PERMC_SPEC)
    return t_jac / nt * 1e3, max(t_lin - t_jac, 0.0) / nt * 1e3, t_lu * 1e3, A.nnz, lu.L.nnz + lu.U.nnz


CLOCK = time.perf_counter


def timed(fun, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t0 = CLOCK()
        fun()
        best = min(best, CLOCK() - t0)
    return best


def pegasus_rounds(rounds=5, repeat=3):
    """Per-step process time (ms) of the beam component's march and adjoint in the PEGASUS gust
    model (see the module docstring), ``{model: (steps, march, adjoint)}``, best of ``rounds``
    interleaved rounds of ``repeat`` evaluations each."""
    import cProfile
    import pstats

    from wingmdao.cases import pegasus
    from wingmdao.components.time_history import TimeHistoryComponent
    from wingmdao.sizing import WALL_VARS, build_problem

    probs = {}
    for label, aero, plunge in (("PEGASUS, strip-theory loads", "strip", "clamped"),
                                ("PEGASUS, coupled clamped + trim", "coupled", "clamped"),
                                ("PEGASUS, coupled free plunge + trim", "coupled", "free")):
        setup = pegasus.build(loads="gust", aero=aero, plunge=plunge)
        prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
        for comp in prob.model.system_iter(recurse=True, typ=TimeHistoryComponent):
            comp.build_system().compile(wait=True)
        of = [f"cases.{case.name}.ks_{fam}" for case in setup.load_cases for fam in case.families]
        prob.run_model()
        prob.compute_totals(of=of, wrt=list(WALL_VARS))
        probs[label] = (prob, of, setup.load_cases[0].num_times)
    best = {k: [np.inf, np.inf] for k in probs}
    for _ in range(rounds):
        for label, (prob, of, nt) in probs.items():
            prof = cProfile.Profile(timer=time.process_time)
            prof.enable()
            for _ in range(repeat):
                prob.run_model()
                prob.compute_totals(of=of, wrt=list(WALL_VARS))
            prof.disable()
            stats = pstats.Stats(prof).stats

            def cum(method):
                return sum(v[3] for k, v in stats.items()
                           if k[0].endswith("components/time_history.py") and k[2] == method) / repeat

            march = cum("solve_nonlinear")
            adjoint = cum("linearize") + cum("solve_linear") + cum("apply_linear")
            best[label] = [min(best[label][0], march / nt * 1e3), min(best[label][1], adjoint / nt * 1e3)]
    return {k: (probs[k][2], *v) for k, v in best.items()}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nodes", type=int, default=20, help="beam nodes (default %(default)s)")
    ap.add_argument("--steps", type=int, default=500, help="time steps (default %(default)s)")
    ap.add_argument("--dt", type=float, default=2e-3, help="time step, s (default %(default)s)")
    ap.add_argument("--interpreted", action="store_true", help="interpreted CasADi functions (no compilation)")
    ap.add_argument("--breakdown", action="store_true", help="also time the parts of one adjoint linearization")
    ap.add_argument("--repeat", type=int, default=3,
                    help="timings per figure, the best kept (default %(default)s; more on a noisy machine)")
    ap.add_argument("--process-time", action="store_true",
                    help="process (CPU) time instead of wall time: steadier on a shared machine")
    ap.add_argument("--pegasus", action="store_true",
                    help="per-step ratios inside the PEGASUS gust model (strip / coupled clamped / free plunge)")
    ap.add_argument("--rounds", type=int, default=5, help="interleaved rounds of --pegasus (default %(default)s)")
    args = ap.parse_args(argv)
    if args.pegasus:
        rows = pegasus_rounds(args.rounds)
        base = next(iter(rows.values()))
        print(f"PEGASUS gust model, beam component only, process time per step, best of {args.rounds} interleaved "
              f"rounds; load average {os.getloadavg()[0]:.1f}; goal: coupled <= 1.5 x strip")
        print(f"{'model':36s} {'steps':>6s} {'march ms/step':>14s} {'x strip':>8s} {'adjoint ms/step':>16s} {'x strip':>8s}")
        for label, (nt, f, a) in rows.items():
            print(f"{label:36s} {nt:6d} {f:14.3f} {f / base[1]:8.2f} {a:16.3f} {a / base[2]:8.2f}")
        return
    global CLOCK
    CLOCK = time.process_time if args.process_time else time.perf_counter
    if args.interpreted:
        os.environ["WINGMDAO_JIT"] = "0"
    n, nt = args.nodes, args.steps
    wrt = ["stiffness_csn", "mass_per_length"]
    rows, parts = {}, {}
    for kind in ("structural", "structural_torsion", "coupled", "plunge"):
        prob, n_state = build(kind, n, nt, args.dt, compile_first=not args.interpreted)
        prob.compute_totals(of=["ks.ks_root"], wrt=wrt)  # first gradient: factor storage, warm-up
        t_fwd = timed(prob.run_model, args.repeat)
        t_adj = timed(lambda: prob.compute_totals(of=["ks.ks_root"], wrt=wrt), args.repeat)
        rows[kind] = (n_state, t_fwd / nt * 1e3, t_adj / nt * 1e3)
        if args.breakdown:
            parts[kind] = breakdown(prob, nt, args.dt)
    base, b3d = rows["structural"], rows["structural_torsion"]
    print(f"{n} nodes x {nt} steps, dt = {args.dt} s, {'interpreted' if args.interpreted else 'compiled'}; per step, "
          f"best of {args.repeat}, {'process' if args.process_time else 'wall'} time (shared machine: indicative); "
          "goal: coupled <= 1.5 x structural (lift only)")
    print(f"{'model':30s} {'states':>7s} {'march ms/step':>14s} {'x struct':>9s} {'x torsion':>9s} "
          f"{'adjoint ms/step':>16s} {'x struct':>9s} {'x torsion':>9s}")
    labels = {"structural": "structural, lift", "structural_torsion": "structural, lift + moment",
              "coupled": "coupled, clamped", "plunge": "coupled, free plunge+trim"}
    for kind, (ns, f, a) in rows.items():
        print(f"{labels[kind]:30s} {ns:7d} {f:14.3f} {f / base[1]:9.2f} {f / b3d[1]:9.2f} {a:16.3f} "
              f"{a / base[2]:9.2f} {a / b3d[2]:9.2f}")
    if parts:
        print(f"\nadjoint linearization per step [ms]: {'model':30s} {'jacobians':>10s} {'blocks':>8s} "
              f"{'SuperLU':>8s} {'nnz A':>7s} {'nnz L+U':>8s}")
        for kind, (tj, tb, tl, nz, nlu) in parts.items():
            print(f"{'':37s}{labels[kind]:30s} {tj:10.3f} {tb:8.3f} {tl:8.3f} {nz:7d} {nlu:8d}")


if __name__ == "__main__":
    main()
