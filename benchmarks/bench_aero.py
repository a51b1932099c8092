"""Coupled aeroelastic march and adjoint beside the structural-only ones, per time step (issue 13
speed goal: a coupled step at most 1.5x a structural step), 20 nodes x 500 steps.

Three OpenMDAO problems of the same beam (BeamDynamics; AeroelasticBeamDynamics clamped;
AeroelasticBeamDynamics free in plunge from the trimmed 1 g state), each followed by a KS of the
root moments; the same 1-cos gust (the structural beam gets it as the precomputed rigid-strip
lift). Timed: the forward march (run_model) and the discrete adjoint (compute_totals of the KS
w.r.t. stiffness_csn and mass_per_length), best of 3, divided by the number of steps. CasADi
functions compiled first (gcc; cached), or ``--interpreted`` (WINGMDAO_JIT=0).

    python benchmarks/bench_aero.py [--nodes 20] [--steps 500] [--interpreted]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import openmdao.api as om

from wingmdao.aero import aero_parameters
from wingmdao.beam.static import beam_forcing, beam_parameters, straight_beam
from wingmdao.components.aeroelastic import AeroelasticBeamDynamics
from wingmdao.components.beam import BeamDynamics
from wingmdao.components.ks import KSAggregate

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
    if kind == "structural":
        comp = BeamDynamics(num_nodes=n, time=t)
        flp = np.zeros((nt, n, 3))
        flp[:, :, 2] = (0.5 * RHO * V ** 2 * CHORD * 2 * np.pi * gust / V)[:, None]
        vals["force_per_length"] = flp
    else:
        free = kind == "plunge"
        comp = AeroelasticBeamDynamics(num_nodes=n, time=t, plunge=free, trim=free)
        vals.update(aero_parameters(n, chord=CHORD, ref_point=0.4, airspeed=V, density=RHO))
        vals["gust_velocity"] = np.repeat(gust[:, None], n, axis=1)
        if free:
            vals.update(body_mass=2000.0, trim_lift=(2000.0 + 2 * 200.0) * G,
                        gravity=np.tile([0.0, 0.0, -G], (nt, 1)), trim_active=(t == 0).astype(float))
    prob.model.add_subsystem("beam", comp, promotes=["*"])
    shape = (nt,) + tuple(comp.build_system().state_shape)
    w = np.zeros(shape)
    w.reshape(nt, -1)[:, 9:12] = 1e-5  # node 0 (root) moments, N m normalised; node-major in every layout
    prob.model.add_subsystem("pick", om.ExecComp("g = w * states", w={"val": w, "shape": shape},
                                                 states={"shape": shape}, g={"shape": shape},
                                                 has_diag_partials=True), promotes=["*"])
    prob.model.add_subsystem("ks", KSAggregate(families={"root": shape}, rho_ks=50.0))
    prob.model.connect("g", "ks.g_root")
    if compile_first:  # compiled CasADi functions for every model (not only those in the cache)
        comp.build_system().compile(wait=True)
    prob.setup(mode="rev")
    for k, v in vals.items():
        prob.set_val(k, v)
    prob.run_model()
    return prob, int(np.prod(shape[1:]))


def timed(fun, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fun()
        best = min(best, time.perf_counter() - t0)
    return best


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nodes", type=int, default=20, help="beam nodes (default %(default)s)")
    ap.add_argument("--steps", type=int, default=500, help="time steps (default %(default)s)")
    ap.add_argument("--dt", type=float, default=2e-3, help="time step, s (default %(default)s)")
    ap.add_argument("--interpreted", action="store_true", help="interpreted CasADi functions (no compilation)")
    args = ap.parse_args(argv)
    if args.interpreted:
        import os

        os.environ["WINGMDAO_JIT"] = "0"
    n, nt = args.nodes, args.steps
    wrt = ["stiffness_csn", "mass_per_length"]
    rows = {}
    for kind in ("structural", "coupled", "plunge"):
        prob, n_state = build(kind, n, nt, args.dt, compile_first=not args.interpreted)
        prob.compute_totals(of=["ks.ks_root"], wrt=wrt)  # first gradient: factor storage, warm-up
        t_fwd = timed(prob.run_model)
        t_adj = timed(lambda: prob.compute_totals(of=["ks.ks_root"], wrt=wrt))
        rows[kind] = (n_state, t_fwd / nt * 1e3, t_adj / nt * 1e3)
    base = rows["structural"]
    print(f"{n} nodes x {nt} steps, dt = {args.dt} s, {'interpreted' if args.interpreted else 'compiled'}; per step, best of 3 (shared machine: indicative)")
    print(f"{'model':24s} {'states':>7s} {'march ms/step':>14s} {'x struct':>9s} {'adjoint ms/step':>16s} "
          f"{'x struct':>9s}")
    labels = {"structural": "structural (BeamDynamics)", "coupled": "coupled, clamped",
              "plunge": "coupled, free plunge+trim"}
    for kind, (ns, f, a) in rows.items():
        print(f"{labels[kind]:24s} {ns:7d} {f:14.3f} {f / base[1]:9.2f} {a:16.3f} {a / base[2]:9.2f}")


if __name__ == "__main__":
    main()
