"""Beam time-march benchmark beside the dissertation's figures (Sec. 4.5-4.6).

    python benchmarks/bench_beam.py            # full: build, 20 x 500 forward + KS gradient, scaling
    python benchmarks/bench_beam.py --quick    # fewer scaling points
    python benchmarks/bench_beam.py --forward  # only the compiled forward march: compiled Newton
                                               # steps against the Python steps, interleaved
    python benchmarks/bench_beam.py --gradient # 20 x 500 forward and gradient rows only

Thesis: model build 47.5 s; forward march 20 nodes x 500 steps 3.12 s; ~3.9 s per KS gradient.
Goals on this machine: build <= 2 s, forward <= 0.5 s, gradient <= 0.7 forward solves with the
default LU (compiled), cost linear in nodes and steps.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
import openmdao.api as om

from wingmdao.components.ks import KSAggregate

THESIS = {"build": 47.5, "forward": 3.12, "gradient": 3.9}


def cantilever_inputs(n, nt, dt):
    """Uniform aluminium-like cantilever along +y, 10 m, with a gust-like tip and running load."""
    L, EI, mu = 10.0, 2.0e6, 20.0
    y = np.linspace(0.0, L, n)
    t = np.arange(nt) * dt
    gust = np.sin(np.pi * np.clip(t / 0.2, 0.0, 1.0)) ** 2
    flp = np.zeros((nt, n, 3))
    flp[:, :, 2] = 2e3 * gust[:, None] * (1.0 - (y / L) ** 2)[None, :]
    return t, {
        "node_positions": np.column_stack([np.zeros(n), y, np.zeros(n)]),
        "node_euler_angles": np.zeros((n, 3)),
        "stiffness_csn": np.tile(np.diag([EI, 0.8 * EI, 5 * EI]), (n, 1, 1)),
        "compliance_csn": np.tile([1e-9, 1e-9, 1e-9], (n, 1)),
        "tension_axis": np.zeros((n, 2)),
        "shear_center": np.zeros((n, 2)),
        "mass_per_length": np.full(n, mu),
        "mass_center": np.zeros((n, 2)),
        "inertia_per_length": np.tile(np.diag([0.1, 0.2, 0.1]), (n, 1, 1)),
        "force_per_length": flp,
        "gravity": np.tile([0.0, 0.0, -9.81], (nt, 1)),
    }


class WeightedStates(om.ExplicitComponent):
    """``g = w * states`` elementwise, with the constant partials declared once on the nonzero
    weights (the benchmark's selection of the root moments). It replaces an ``ExecComp`` with
    ``has_diag_partials``, which complex-stepped all 180 000 entries in every linearization (6-7 ms
    of a 70 ms gradient) and multiplied them in every reverse product; values and totals are the
    same (the zero weights add zeros)."""

    def initialize(self):
        self.options.declare("weights", types=np.ndarray, desc="weights w, shape (n_time,) + the state shape, 1/(N*m)")

    def setup(self):
        w = self.options["weights"]
        self.add_input("states", shape=w.shape, desc="beam state history (mixed units, as BeamDynamics)")
        self.add_output("g", shape=w.shape, desc="weighted states, nondimensional")
        nz = np.flatnonzero(w)
        self.declare_partials("g", "states", rows=nz, cols=nz, val=w.ravel()[nz])

    def compute(self, inputs, outputs):
        outputs["g"] = self.options["weights"] * inputs["states"]


def build_problem(n, nt, dt=2e-3, ks=True, jit=True, dv_force_entries=None, **beam_opts):
    """Beam + KS of the root moments; ``jit=False``: interpreted CasADi functions only;
    ``dv_force_entries``: that many entries of the load history as driver design variables."""
    from wingmdao.components.beam import BeamDynamics, beam_system

    t, vals = cantilever_inputs(n, nt, dt)
    prob = om.Problem(reports=False)
    model = prob.model
    if dv_force_entries:
        model.add_subsystem("dv", om.IndepVarComp("force_per_length", val=vals["force_per_length"], units="N/m"),
                            promotes=["*"])
    if jit:
        system = beam_system(n)
    else:
        from wingmdao.beam.residual import build_beam_system

        system = build_beam_system(n)
        system.set_jit_threshold(10 ** 15)
    model.add_subsystem("beam", BeamDynamics(num_nodes=n, time=t, system=system, **beam_opts), promotes=["*"])
    if ks:
        w = np.zeros((nt, n, 18))
        w[:, 0, 9:12] = 1e-5  # root moments (N m), normalised
        model.add_subsystem("pick", WeightedStates(weights=w), promotes=["*"])
        model.add_subsystem("ks", KSAggregate(families={"root": (nt, n, 18)}, rho_ks=50.0))
        model.connect("g", "ks.g_root")
        if dv_force_entries:
            model.add_design_var("force_per_length", indices=np.arange(dv_force_entries), flat_indices=True)
            model.add_objective("ks.ks_root")
    prob.setup(mode="rev")
    for k, v in vals.items():
        prob.set_val(k, v)
    prob.final_setup()
    return prob


def timed_both(fun, repeat=1):
    """Best wall and best process time (s) of ``repeat`` calls (process time is less affected
    by other jobs on a shared machine)."""
    wall = cpu = np.inf
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        fun()
        wall, cpu = min(wall, time.perf_counter() - t0), min(cpu, time.process_time() - c0)
    return wall, cpu


#: Forward-march goal of issue #15 (20 nodes x 500 steps, compiled functions, warm cache).
FORWARD_GOAL_COMPILED = 0.06
#: Gradient goal of issue #15: all KS gradients (one adjoint) in at most this many forward marches.
GRADIENT_GOAL = 0.7


def timed(fun, repeat=1):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fun()
        best = min(best, time.perf_counter() - t0)
    return best


def forward_only(opts, rounds=5):
    """20 x 500 forward march (``prob.run_model()``), compiled CasADi functions (warm cache):
    compiled Newton steps (``wingmdao.timemarch.fast_step``) and the Python steps
    (``WINGMDAO_COMPILED_STEPS=0``) in alternating rounds, best of 5 calls per round."""
    from wingmdao.components.beam import beam_system
    from wingmdao.timemarch.bdf import ENV_COMPILED_STEPS

    os.environ.pop("WINGMDAO_JIT", None)
    print("compile/load:", beam_system(20).compile(wait=True))
    prob = build_problem(20, 500, jit=True, ks=True, **opts)
    prob.run_model()
    res = {"compiled steps": [], "python steps": []}
    for _ in range(rounds):
        for tag, env in (("compiled steps", "1"), ("python steps", "0")):
            os.environ[ENV_COMPILED_STEPS] = env
            res[tag].append(timed_both(prob.run_model, repeat=5))
            h = prob.model.beam.last_history
            assert h.info.get("compiled_steps", False) == (env == "1")
    os.environ.pop(ENV_COMPILED_STEPS, None)
    print(f"20 nodes x 500 steps, forward march + KS (prob.run_model), {rounds} interleaved rounds, "
          f"best of 5 each; load average {os.getloadavg()[0]:.2f}")
    print(f"{'':18s}{'process time s':>22s}{'wall s':>22s}{'goal':>8s}")
    for tag, vals in res.items():
        w, c = np.array(vals).T
        print(f"{tag:18s}{c.min():10.4f} - {c.max():.4f}{w.min():12.4f} - {w.max():.4f}"
              f"{FORWARD_GOAL_COMPILED:8.2f}")
    h = prob.model.beam.last_history
    print(f"Newton iterations {int(h.iterations[1:].sum())}, factorizations {h.factorizations}")


def gradient_breakdown(prob, wrt, repeat=7):
    """Process time (best of ``repeat``) of the parts of one KS gradient of a compiled problem:
    the history functions over the 500 steps (dR/dx, dR/dxdot, the reverse-mode products
    lam^T dR/dp, lam^T dR/dq), the assembly of the Newton matrices, the adjoint sweep (static-pivot
    LU in C) and the rest (OpenMDAO: linearize/solve/apply of the other components, transfers,
    vector set-up; the time-history component's packing)."""
    from wingmdao.timemarch.adjoint import LinearizedHistory

    beam = prob.model.beam
    lin, system = beam._lin, beam.system
    X, Xd, p, Q = lin._X, lin._Xdot, lin._p, lin._Q
    lam = lin.solve_adjoint(np.random.default_rng(0).normal(size=X.shape))

    def best(fun):
        return timed_both(fun, repeat)[1]

    parts = {
        "dR/dx over the history": best(lambda: system._eval_history(system._part_call("x"), X, Xd, p, Q)),
        "dR/dxdot over the history": best(lambda: system._eval_history(system._part_call("xdot"), X, Xd, p, Q)),
        "lam^T dR/dp, lam^T dR/dq (reverse mode)": best(lambda: system.input_vjp_history(X, Xd, p, Q, lam)),
    }
    data = lin._raw(0, lin.n_time, state_only=True)
    parts["Newton-matrix assembly + pattern check"] = best(lambda: lin._make_blocks(0, lin.n_time, lin.n_time, data,
                                                                                      check=True))
    parts["adjoint sweep (C kernel)"] = best(lambda: lin.solve_adjoint(lam))
    t_lin = best(lambda: LinearizedHistory(system, beam._time, X, p, Q))
    total = best(lambda: prob.compute_totals(of=["ks.ks_root"], wrt=wrt))
    parts["rest (OpenMDAO, packing, rates, step-0 SuperLU, pivot order)"] = total - sum(parts.values())
    print(f"\nbreakdown of one gradient (process time, best of {repeat}; load average "
          f"{os.getloadavg()[0]:.2f}): total {total * 1e3:.1f} ms, LinearizedHistory set-up {t_lin * 1e3:.1f} ms")
    for k, v in parts.items():
        print(f"  {k:62s}{v * 1e3:8.1f} ms")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="fewer scaling points")
    ap.add_argument("--gradient", action="store_true",
                    help="only the 20 x 500 forward march and gradient rows (no Table 4.21, no scaling)")
    ap.add_argument("--full-newton", action="store_true",
                    help="refactor every Newton iteration (default: modified Newton)")
    ap.add_argument("--forward", action="store_true",
                    help="only the compiled forward march: compiled vs Python Newton steps, interleaved")
    args = ap.parse_args(argv)
    if args.forward:
        return forward_only({"modified_newton": not args.full_newton})
    from wingmdao.beam.residual import build_beam_system

    from wingmdao.components.beam import beam_system
    from wingmdao.utils.casadi_cache import cache_dir, jit_enabled

    opts = {"modified_newton": not args.full_newton}
    t_build = timed(lambda: build_beam_system(20))
    wrt = ["stiffness_csn", "mass_per_length"]
    rows = {}
    default_prob = None
    jit_wanted = jit_enabled()
    t_compile, states = 0.0, {}
    # default lu="static": the static-pivot LU of the C kernel (SuperLU when not compiled, e.g.
    # with WINGMDAO_JIT=0 as in the interpreted variant)
    variants = [("interpreted", False, "static"), ("compiled", True, "static"),
                ("compiled, lu='superlu'", True, "superlu")]
    for tag, jit, lu in variants:
        if jit and not jit_wanted:
            break
        if jit:
            os.environ.pop("WINGMDAO_JIT", None)
            if not states:
                t0 = time.perf_counter()
                states = beam_system(20).compile(wait=True)
                t_compile = time.perf_counter() - t0
        else:   # interpreted throughout (no background gcc while timing)
            os.environ["WINGMDAO_JIT"] = "0"
        prob = build_problem(20, 500, jit=jit, lu=lu, **opts)
        prob.run_model()
        t0 = time.perf_counter()
        prob.compute_totals(of=["ks.ks_root"], wrt=wrt)
        t_first = time.perf_counter() - t0
        t_fwd, c_fwd = timed_both(prob.run_model, repeat=5)
        h = prob.model.beam.last_history
        work = (int(h.iterations[1:].sum()), h.factorizations)
        t_grad, c_grad = timed_both(lambda: prob.compute_totals(of=["ks.ks_root"], wrt=wrt), repeat=5)
        lin = prob.model.beam._lin
        rows[tag] = (t_fwd, t_grad, t_first, lin.lu_method, dict(lin.static_stats), c_fwd, work, jit, c_grad)
        if jit and lu == "static":
            default_prob = prob
    if not jit_wanted:
        os.environ["WINGMDAO_JIT"] = "0"
    print("20 nodes x 500 steps (time in s)")
    print(f"{'':52s}{'this machine':>14s}{'thesis':>10s}{'goal':>10s}   (gradient goal: <= {GRADIENT_GOAL} "
          "forward marches with the default LU, compiled)")
    print(f"{'model build (symbolic)':52s}{t_build:14.3f}{THESIS['build']:10.2f}{2.0:10.2f}")
    for tag, (t_fwd, t_grad, t_first, lu, stats, c_fwd, work, jit, c_grad) in rows.items():
        goal = FORWARD_GOAL_COMPILED if jit else 0.5
        print(f"{'forward time march, ' + tag:52s}{t_fwd:14.3f}{THESIS['forward']:10.2f}{goal:10.2f}"
              f"   process time {c_fwd:.3f} s; {work[0]} Newton iterations ({work[0] / 499:.2f} per "
              f"step: residual + back-substitution each), {work[1]} factorizations")
        note = (f"; first gradient {t_first:.2f} s, steps refined {stats['refined']}, SuperLU fallbacks "
                f"{stats['fallback']}" if lu == "static" else "")
        goal = GRADIENT_GOAL * t_fwd
        print(f"{'all KS gradients (adjoint), ' + tag:52s}{t_grad:14.3f}{THESIS['gradient']:10.2f}{goal:10.2f}"
              f"   LU {lu}; gradient/forward {t_grad / t_fwd:.2f} wall, {c_grad / c_fwd:.2f} process time "
              f"(goal <= {GRADIENT_GOAL}){note}")
    if states:
        print(f"compile (gcc, once; cached in {cache_dir()}): {t_compile:.1f} s {states}")
        gradient_breakdown(default_prob, wrt)
    if args.gradient:
        return

    print("\ngradient time against the number of design variables (Table 4.21), 20 nodes x 500 steps;")
    print("design variables: entries of the load history; finite differences estimated as (k + 1) forward marches")
    print(f"{'k':>6s}{'adjoint s':>11s}{'FD s (est.)':>13s}   thesis: adjoint 0.32 -> 5.34 s, FD 6.6 -> 7917 s")
    for k in ([20, 100] if args.quick else [20, 100, 500, 1000]):
        p = build_problem(20, 500, dv_force_entries=k, **opts)
        p.run_model()
        tf = timed(p.run_model)
        tg = timed(lambda: p.compute_totals(), repeat=2)
        print(f"{k:6d}{tg:11.3f}{(k + 1) * tf:13.1f}")

    nodes = [10, 20, 40, 80] if args.quick else [10, 20, 40, 80, 160]
    steps = [100, 500, 1000] if args.quick else [100, 500, 1000, 2000, 4000]
    os.environ["WINGMDAO_JIT"] = "0"    # no background compiles of new sizes while timing
    print("\nscaling (interpreted CasADi functions throughout, so that sizes compare like with like)")
    print("scaling with nodes (500 steps): nodes, build s, forward s, forward s per node")
    for n in nodes:
        tb = timed(lambda: build_beam_system(n))
        p = build_problem(n, 500, ks=False, jit=False, **opts)
        tf = timed(p.run_model)
        print(f"{n:6d}{tb:10.3f}{tf:10.3f}{tf / n:12.5f}")
    print("\nscaling with steps (20 nodes): steps, forward s, forward ms per step")
    for nt in steps:
        p = build_problem(20, nt, ks=False, jit=False, **opts)
        tf = timed(p.run_model)
        print(f"{nt:6d}{tf:10.3f}{1e3 * tf / nt:12.4f}")


if __name__ == "__main__":
    main()
