"""One 14 CFR 25.341(b) continuous-turbulence analysis of PEGASUS (coupled, free plunge), timed by part.

    OMP_NUM_THREADS=1 PYTHONPATH=. python benchmarks/bench_turbulence.py [--repeat 5] [--clamped] [--gradient]

Parts (process time, best of ``--repeat`` after one warm-up run that builds and caches the
aeroelastic system): the trimmed 1 g static solve and linearisation with the output maps
(``coupled_gust_model`` less its eigenvalues, timed alone), the pencil's eigenvalues (dense QZ,
no vectors, for the frequency grid), and the frequency response with A-bar, design loads and correlations
(``turbulence_analysis``, ~210 frequencies); with ``--gradient`` the KS of the corner design
stresses (:func:`wingmdao.stability.frequency_adjoint.turbulence_stress_ks`, initial-design walls)
with and without its gradient. Goal of issue #28: the analysis with its gradient under 2 s on
this 2-core machine.

Figures (process time, OMP_NUM_THREADS=1, best of 3, free plunge): static solve + linearisation +
outputs 0.02 s, eigenvalues 0.11 s, frequency response and A-bar (307 frequencies to 40 Hz)
0.13 s; the whole analysis 0.26 s; the stress KS (245 frequencies to 20 Hz) 0.10 s, with its
gradient 0.86 s: analysis and gradient 1.12 s.
"""

from __future__ import annotations

import argparse
import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def _pegasus():
    """Beam and aerodynamic parameters of the PEGASUS initial design at its V_C point (Mach 0.5, 20,000 ft)."""
    from wingmdao.aero import aero_parameters
    from wingmdao.cases import pegasus
    from wingmdao.cases.planform import G0, LB, wing_geometry
    from wingmdao.loads.atmosphere import altitude_ft_to_m, density, mach_to_tas
    from wingmdao.sizing import SECTION_KINDS, design_beam_params, initial_design

    setup = pegasus.build()
    design = initial_design(setup.options, SECTION_KINDS[setup.section]["design_vars"])
    bp = design_beam_params(setup.geometry, setup.material, design, setup.section)
    _, chord, axis = wing_geometry(pegasus.PLANFORM, pegasus.ENGINES)
    alt = float(altitude_ft_to_m(pegasus.CRUISE_ALTITUDE_FT))
    V = float(mach_to_tas(pegasus.CRUISE_MACH, alt))
    ap = aero_parameters(chord.size, chord=chord, ref_point=axis, airspeed=V, density=float(density(alt)),
                         mach=pegasus.CRUISE_MACH)
    return bp, ap, chord, axis, pegasus.TOGW_LB * LB * G0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5, help="timed runs (after one warm-up)")
    ap.add_argument("--clamped", action="store_true", help="root clamped instead of free plunge")
    ap.add_argument("--gradient", action="store_true",
                    help="also time the corner-stress KS and its gradient (wingmdao.stability.frequency_adjoint)")
    args = ap.parse_args(argv)

    from wingmdao.loads.turbulence_analysis import coupled_gust_model, turbulence_analysis
    from wingmdao.stability.frequency import pencil_eigenvalues

    bp, aero, chord, axis, weight = _pegasus()
    coupled_gust_model(bp, aero, chord=chord, axis_fraction=axis, weight=weight, plunge=not args.clamped)  # warm-up
    rows = []
    for _ in range(args.repeat):
        t0 = time.process_time()
        gm = coupled_gust_model(bp, aero, chord=chord, axis_fraction=axis, weight=weight, plunge=not args.clamped)
        t1 = time.process_time()
        pencil_eigenvalues(gm.model)  # timed alone: the part of the model's time spent on them
        t2 = time.process_time()
        res = turbulence_analysis(gm, 24.23)
        t3 = time.process_time()
        rows.append((t1 - t0 - (t2 - t1), t2 - t1, t3 - t2, (t1 - t0) + (t3 - t2)))
    best = [min(r[k] for r in rows) for k in range(4)]
    print(f"PEGASUS turbulence ({'clamped' if args.clamped else 'free plunge'}), best of {args.repeat} (process s):")
    print(f"  static solve + linearisation + outputs {best[0]:.3f}")
    print(f"  pencil eigenvalues (frequency grid)    {best[1]:.3f}")
    print(f"  frequency response, A-bar, loads       {best[2]:.3f}  ({res['quadrature']['points']} frequencies)")
    print(f"  whole analysis                         {best[3]:.3f}  (goal with gradient: 2 s)")
    if args.gradient:
        _gradient(gm, args.repeat)
    print(f"  A-bar load factor {res['a_bar']['load_factor']:.5f} per m/s, "
          f"root bending {res['a_bar']['root_bending_moment']:.1f} N m per m/s")


def _gradient(gm, repeat):
    """Time the KS of the corner design stresses (initial-design walls) with and without its gradient."""
    import numpy as np

    from wingmdao.cases import pegasus
    from wingmdao.sizing import SECTION_KINDS, WALL_VARS, initial_design, station_design
    from wingmdao.stability.frequency import frequency_grid
    from wingmdao.stability.frequency_adjoint import StressMap, turbulence_stress_ks

    setup = pegasus.build()
    geo = setup.geometry
    dv = station_design(geo, initial_design(setup.options, SECTION_KINDS[setup.section]["design_vars"]), WALL_VARS)
    walls = np.column_stack([dv[w] for w in WALL_VARS])
    t0 = time.process_time()
    stress = StressMap(gm.system.layout.beam, geo.width, geo.height, geo.section_to_csn, n_state=gm.system.n_state)
    t1 = time.process_time()
    grid = frequency_grid(gm.eigenvalues)
    best = {False: np.inf, True: np.inf}
    for _ in range(repeat):
        for grad in (False, True):
            a = time.process_time()
            res = turbulence_stress_ks(gm.system, gm.p, gm.q_static, gm.model, stress, walls, grid, u_sigma=24.23,
                                       sigma_allow=300e6, gradient=grad)
            best[grad] = min(best[grad], time.process_time() - a)
    print(f"  stress map build (once per process)    {t1 - t0:.3f}")
    print(f"  corner-stress KS, value only           {best[False]:.3f}  (KS {res.value:.4f}, {grid.size} frequencies)")
    print(f"  corner-stress KS with its gradient     {best[True]:.3f}")


if __name__ == "__main__":
    main()
