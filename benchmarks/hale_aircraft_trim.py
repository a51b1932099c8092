"""Trim of the free Patil-Hodges-Cesnik HALE aircraft (wingmdao.cases.hale_aircraft) beside the
published trimmed angle of attack (Patil, Hodges & Cesnik, J. Aircraft 38(1), 2001; digitised in
AeroBeams.jl test/referenceData/conventionalHALE), rigid and elastic with the flight-path loads
(lift normal to the pitched air, weight in the pitched body axes), the elastic aircraft also with
the loads normal to body x (``flight_path_loads=False``) and with a section drag coefficient of
0.01 (``drag_coefficient=0.01``, not in the paper's data as stated here), the deflected wing at
25 m/s, and the linear limit (1 % of the weight) against the closed-form wash-in of a uniform strip wing.

    PYTHONPATH=. python benchmarks/hale_aircraft_trim.py
"""

from __future__ import annotations

import time

import numpy as np

from wingmdao.cases import hale, hale_aircraft as ha

SPEEDS = (20.1, 22.0, 25.0, 28.0, 30.0, 32.0)


def published(kind, v):
    d = ha.PUBLISHED_TRIM[kind]
    return float(np.interp(v, d["airspeed_m_s"], d["alpha_deg"]))


def wash_in_ratio(v):
    """alpha_elastic / alpha_rigid of a uniform clamped strip wing (lift e ahead of the beam axis):
    lambda L / tan(lambda L), lambda L = (pi / 2) V / V_D, q_D = (pi / 2)^2 GJ / (e c a L^2)."""
    e = (hale.ELASTIC_AXIS - 0.25) * hale.CHORD
    q_d = (np.pi / 2) ** 2 * hale.GJ / (e * hale.CHORD * 2 * np.pi * hale.SEMI_SPAN ** 2)
    v_d = np.sqrt(2 * q_d / hale.DENSITY)
    lam = 0.5 * np.pi * v / v_d
    return lam / np.tan(lam), v_d


def main():
    t0 = time.perf_counter()
    aircraft = ha.build()
    rigid = aircraft.with_wing_stiffness(ha.RIGID_FACTOR)
    print(f"HALE aircraft (half): mass {aircraft.mass:.2f} kg, {aircraft.system.n_state} unknowns, "
          f"built in {time.perf_counter() - t0:.1f} s")
    print(f"published: {ha.PUBLISHED_TRIM['source']}")
    r_sweep = ha.trim_sweep(rigid, SPEEDS)
    e_sweep = ha.trim_sweep(aircraft, SPEEDS)
    w_sweep = ha.trim_sweep(aircraft, SPEEDS, flight_path_loads=False)
    d_sweep = ha.trim_sweep(aircraft, SPEEDS, drag_coefficient=0.01)
    print("\ntrimmed angle of attack (deg)")
    print(f"{'V m/s':>6} {'rigid':>8} {'publ.':>8} {'diff':>7}   {'elastic':>8} {'publ.':>8} {'diff':>7}   "
          f"{'body-x':>8} {'publ.':>8} {'diff':>7}   {'cd0 0.01':>8} {'publ.':>8} {'diff':>7}   {'tail inc. r/e':>14}")
    for v in SPEEDS:
        row = f"{v:6.1f}"
        for sweep, kind in ((r_sweep, "rigid"), (e_sweep, "elastic"), (w_sweep, "elastic"), (d_sweep, "elastic")):
            if v in sweep:
                a, pub = sweep[v]["alpha_deg"], published(kind, v)
                row += f" {a:8.3f} {pub:8.3f} {100 * (a / pub - 1):+6.1f}%  "
            else:
                row += f" {'--':>8} {published(kind, v):8.3f} {'':>7}  "
        inc = [f"{s[v]['tail_incidence_deg']:+.2f}" if v in s else "--" for s in (r_sweep, e_sweep)]
        print(row + f" {'/'.join(inc):>14}")
    for sweep, kind in ((r_sweep, "rigid"), (e_sweep, "elastic"), (w_sweep, "elastic, body-x loads"),
                        (d_sweep, "elastic, cd0 0.01")):
        for v, msg in sweep["failed"].items():
            print(f"{kind} {v} m/s: no trim ({msg})")
    if 25.0 in e_sweep:
        w = e_sweep[25.0]["wing"]
        pub = ha.PUBLISHED_TRIM["deflected_wing_25_m_s"]
        print("\nelastic wing at 25 m/s (beam axis, m): spanwise y, vertical z")
        print(f"  model tip: y = {w[-1, 1]:.2f}, z = {w[-1, 2]:.2f}; published last point: y = {pub['span_m'][-1]:.2f}, "
              f"z = {pub['vertical_m'][-1]:.2f}")
        z_at = np.interp(pub["span_m"], w[:, 1], w[:, 2])
        for y, zp, zm in list(zip(pub["span_m"], pub["vertical_m"], z_at))[::4]:
            print(f"  y = {y:6.2f}: model z = {zm:6.3f}, published z = {zp:6.3f}")
    print("\nlinear limit (1 % of the weight): alpha_elastic / alpha_rigid against the closed form")
    for v in (20.1, 25.0, 30.0):
        a_e = ha.trim(aircraft, v, load_factor=0.01)["alpha_deg"]
        a_r = ha.trim(rigid, v, load_factor=0.01)["alpha_deg"]
        ratio, v_d = wash_in_ratio(v)
        print(f"  V = {v:4.1f} m/s: model {a_e / a_r:.4f}, closed form {ratio:.4f} (V_D = {v_d:.2f} m/s; "
              f"published wing divergence {hale.PUBLISHED['divergence_speed_m_s']} m/s)")
    print(f"\ntotal {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
