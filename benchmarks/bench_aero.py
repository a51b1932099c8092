"""Coupled aeroelastic march beside the structural-only one (issue 13 speed goal: a coupled step
at most 1.5x a structural step), 20 nodes x 500 steps, interpreted CasADi functions (WINGMDAO_JIT=0)
or compiled (default when the cache has them).

    python benchmarks/bench_aero.py
"""

from __future__ import annotations

import time

import numpy as np

from wingmdao.aero import aero_parameters, cached_aeroelastic_system
from wingmdao.beam.static import beam_forcing, beam_parameters, cached_beam_system, straight_beam
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import layout, pack


def main(n=20, nt=500, dt=2e-3):
    r0, th0 = straight_beam(n, 10.0)
    bp = beam_parameters(r0, th0, EI_cc=2e6, GJ=1.6e6, EI_nn=1e7, EA=1e9, mass_per_length=20.0,
                         inertia_per_length=np.diag([0.1, 0.2, 0.1]))
    t = np.arange(nt) * dt
    gust = np.sin(np.pi * np.clip(t / 0.2, 0.0, 1.0)) ** 2
    # structural: the rigid-strip lift of the same gust as a precomputed load
    sb = cached_beam_system(n)
    qb = pack(sb.forcing_specs, beam_forcing(n))
    Qb = np.tile(qb, (nt, 1))
    q_dyn, V, c = 0.5 * 1.2 * 60.0 ** 2, 60.0, 1.0
    flp = np.zeros((nt, n, 3))
    flp[:, :, 2] = (q_dyn * c * 2 * np.pi * 5.0 * gust / V)[:, None]
    Qb[:, layout(sb.forcing_specs)["force_per_length"]] = flp.reshape(nt, -1)
    pb = pack(sb.param_specs, bp)
    sa = cached_aeroelastic_system(n)
    ap = aero_parameters(n, chord=c, ref_point=0.4, airspeed=V, density=1.2)
    pa = pack(sa.param_specs, {**bp, **ap})
    qd = beam_forcing(n)
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3))
    Qa = np.tile(pack(sa.forcing_specs, qd), (nt, 1))
    Qa[:, layout(sa.forcing_specs)["gust_velocity"]] = 5.0 * gust[:, None]
    out = {}
    for name, (s, p, Q) in {"structural": (sb, pb, Qb), "coupled": (sa, pa, Qa)}.items():
        march(s, t[:20], p, Q[:20], modified_newton=True)  # warm up
        t0 = time.perf_counter()
        h = march(s, t, p, Q, modified_newton=True)
        out[name] = time.perf_counter() - t0
        print(f"{name:10s} {n} nodes x {nt} steps: {out[name]:.3f} s ({s.n_state} states)")
    print(f"coupled / structural: {out['coupled'] / out['structural']:.2f}")


if __name__ == "__main__":
    main()
