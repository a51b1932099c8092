"""The 25.337 maneuvers and the flutter constraint of the PEGASUS stick model at the initial walls
(docs/stick-model.md, "Sizing on the stick model").

    PYTHONPATH=. python benchmarks/stick_maneuver.py [--nodes 20] [--no-flutter]

prints, for the pull-up (2.5 g) and push-over (-1.0 g) cases of ``size pegasus --model stick``
(:func:`wingmdao.cases.pegasus_stick.sizing_setup`, 25 000 ft, M 0.5): the trim (angle of attack,
tail incidence), the trimmed lift over n W (W: the beams' and lumped masses summed here), the wing
root rib's bending M_x (``monitoring_loads``) beside the free-body sum of the strips' vertical lift
and the inertial loads outboard of the rib (jig arms; exact for a rigid wing), the tail load; then
the flutter constraint of ``--flutter-margin 1.15`` (:func:`wingmdao.cases.pegasus_stick.flutter_options`,
:class:`wingmdao.components.flutter.StickFlutterDamping`): its value and the least damped
aggregated mode at each speed.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace

import numpy as np


def main(argv=None):
    from wingmdao.aero.joined import lift_total
    from wingmdao.beam.joints import MonitoringStation, monitoring_loads
    from wingmdao.cases import pegasus, pegasus_stick
    from wingmdao.cases.planform import G0, wing_geometry
    from wingmdao.timemarch.bdf import march
    from wingmdao.timemarch.system import layout

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nodes", type=int, default=20, help="wing nodes")
    ap.add_argument("--no-flutter", action="store_true", help="skip the flutter constraint")
    args = ap.parse_args(argv)
    t0 = time.process_time()
    opts = pegasus.PegasusOptions(loads="maneuver")
    setup = replace(pegasus.build(opts), geometry=wing_geometry(pegasus.flutter_planform(args.nodes), ())[0])
    cases = pegasus_stick.sizing_setup(setup, opts).load_cases
    s = cases[0].system
    lay = layout(s.param_specs)
    p = np.asarray(cases[0].p, dtype=float)
    mass = float(p[lay["lumped_mass"]].sum())
    for b in s.beams:
        r0 = p[lay[f"{b.name}_node_positions"]].reshape(-1, 3)
        mu = p[lay[f"{b.name}_mass_per_length"]]
        mass += float(np.sum(0.5 * (mu[:-1] + mu[1:]) * np.linalg.norm(np.diff(r0, axis=0), axis=1)))
    r0 = p[lay["wing_node_positions"]].reshape(-1, 3)
    mu, y = p[lay["wing_mass_per_length"]], r0[:, 1]
    ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
    y_mid = 0.5 * (y[:-1] + y[1:])
    print(f"PEGASUS stick model, {args.nodes}-node wing, initial walls: half aircraft {mass:.1f} kg")
    for case in cases:
        q = case.forcing[0]
        n = 1.0 + q[lay_f(s)["frame_acceleration"]][2] / G0
        x = march(s, np.zeros(1), p, case.forcing, atol=1e-6).states[0]
        loads = s.section_loads(x, 0 * x, p, q)
        up = loads["wing"][2]
        fz = 0.5 * (up[:-1] + up[1:]) * ds - n * G0 * 0.5 * (mu[:-1] + mu[1:]) * ds
        free_body = float(np.sum(fz[1:] * (y_mid[1:] - y[1])))
        free_body -= sum(n * G0 * lm.mass * (y[lm.node] + lm.offset[1] - y[1]) for lm in s.masses if lm.beam == "wing")
        root = monitoring_loads(s, x, [MonitoringStation("root", "wing", 1)])["root"]["moment"]
        rt = p[lay["tail_node_positions"]].reshape(-1, 3)
        ut = loads["tail"][2]
        tail = float(np.sum(0.5 * (ut[:-1] + ut[1:]) * np.linalg.norm(np.diff(rt, axis=0), axis=1)))
        trim = {k: float(x[i]) for k, i in s.trim_index.items()}
        print(f"  {case.name}: n = {n:+.2f}; alpha {np.degrees(trim['alpha_trim']):+.3f} deg, tail incidence "
              f"{np.degrees(trim['tail_incidence']):+.3f} deg; lift / (n W) - 1 = "
              f"{lift_total(s, x, 0 * x, p, q, vertical=True) / (n * G0 * mass) - 1:+.1e}; tail lift {tail:+.0f} N; "
              f"root rib M_x {root[0]:.0f} N m, free-body (jig arms) {free_body:.0f} N m ({root[0] / free_body - 1:+.2%})")
    print(f"  CPU {time.process_time() - t0:.1f} s")
    if args.no_flutter:
        return
    import openmdao.api as om

    from wingmdao.components.flutter import StickFlutterDamping

    fo = pegasus_stick.flutter_options(cases[0], 1.15)
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("flutter", StickFlutterDamping(**fo), promotes=["*"])
    prob.setup()
    t1 = time.process_time()
    prob.run_model()
    first = time.process_time() - t1
    ks = prob.get_val("flutter_ks")[0]
    res = prob.model.flutter.last_result
    t2 = time.process_time()
    prob.set_val("stiffness_csn", 1.01 * prob.get_val("stiffness_csn"))    # a second design: no cache
    prob.run_model()
    print(f"flutter constraint, 1.15 V_D: flutter_ks = {ks:+.4f} 1/s (CPU of the first evaluation {first:.1f} s, "
          f"one-time builds included; of a second, stiffness x 1.01, {time.process_time() - t2:.1f} s)")
    for V, lam in zip(res.speeds, res.eigenvalues):
        k = int(np.argmax(lam.real))
        print(f"  V = {V:6.1f} m/s: {lam.size} modes, least damped {lam[k].real:+.4f} 1/s at "
              f"{abs(lam[k].imag) / (2 * np.pi):.3f} Hz; lowest {min(abs(lam.imag)) / (2 * np.pi):.3f} Hz")


def lay_f(system):
    """The forcing layout of ``system``."""
    from wingmdao.timemarch.system import layout

    return layout(system.forcing_specs)


if __name__ == "__main__":
    main()
