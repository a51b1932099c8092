"""Su's blended-wing-body flying wing (wingmdao.cases.bwb) beside the UM/NAST results for the same
aircraft (AeroBeams.jl test/referenceData/BWB): trim (centreline angle of attack, elevon) and the
two modes that coalesce in the body-freedom flutter against airspeed, then the flutter speed and
frequency with the default model (independence-principle strips, structural damping of the
reference), with streamwise strips, without structural damping, and on three meshes.

    PYTHONPATH=. python benchmarks/bwb_flutter.py [--quick]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from wingmdao.cases import bwb

SPEEDS = (30.0, 40.0, 60.0, 90.0, 110.0, 120.0, 130.0, 140.0)


def _ref(key, v):
    return bwb.REFERENCE[key][bwb.REFERENCE["airspeed_m_s"].index(v)]


def trim_table(aircraft):
    print("| V (m/s) | root AoA (deg) | UM/NAST | elevon (deg) | UM/NAST | mode 2 (Hz) | UM/NAST "
          "| mode 4 (Hz) / Re (1/s) | UM/NAST |")
    print("|---|---|---|---|---|---|---|---|---|")
    x = None
    for v in SPEEDS:
        t = bwb.trim(aircraft, v, x0=x)
        x = t["x"]
        lam = bwb.modes(aircraft, v, x).eigenvalues
        band = lam[(np.abs(lam.imag) > 2 * np.pi * 2.5) & (np.abs(lam.imag) < 2 * np.pi * 10.0)]
        band = band[np.argsort(np.abs(band.imag))]
        # mode 4: the one nearest 7.87 Hz with the smaller |Re|; mode 2: the most damped other one
        # in the band (the short period, rising through 2.5 Hz above 80 m/s, is less damped)
        k4 = int(np.argmin(np.abs(band.imag / (2 * np.pi) - 7.87) + 10 * (np.abs(band.real) > 5)))
        m4 = band[k4]
        rest = np.delete(band, k4)
        m2 = rest[int(np.argmin(rest.real))]
        print(f"| {v:.0f} | {t['root_aoa_deg']:.3f} | {_ref('trim_root_aoa_deg', v):.3f} | {t['elevon_deg']:.3f} "
              f"| {_ref('trim_elevon_deg', v):.3f} | {abs(m2.imag) / (2 * np.pi):.3f} | "
              f"{_ref('coalescing_mode_hz', v):.3f} | {abs(m4.imag) / (2 * np.pi):.3f} / {m4.real:+.3f} | "
              f"{_ref('flutter_mode_hz', v):.3f} / {_ref('flutter_mode_real', v):+.3f} |")


def flutter_row(label, aircraft, speeds):
    t0 = time.process_time()
    f = bwb.flutter(aircraft, speeds)
    ref_v, ref_w = bwb.REFERENCE["flutter_speed_m_s"], bwb.REFERENCE["flutter_frequency_rad_s"]
    print(f"| {label} | {f['speed']:.2f} | {100 * (f['speed'] / ref_v - 1):+.1f} % | {f['frequency']:.2f} | "
          f"{100 * (f['frequency'] / ref_w - 1):+.1f} % | {time.process_time() - t0:.1f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the default model only")
    args = ap.parse_args()
    aircraft = bwb.build()
    print(f"half aircraft: {aircraft.mass:.2f} kg, {aircraft.system.n_state} unknowns\n")
    trim_table(aircraft)
    print("\n| model | flutter speed (m/s) | vs 137.7 | frequency (rad/s) | vs 47.5 | CPU (s) |")
    print("|---|---|---|---|---|---|")
    coarse = (120.0, 130.0, 140.0)
    flutter_row("default (7 + 17 nodes)", aircraft, coarse)
    if args.quick:
        return
    flutter_row("4 + 9 nodes", bwb.build(num_body_nodes=4, num_wing_nodes=9), coarse)
    flutter_row("13 + 33 nodes", bwb.build(num_body_nodes=13, num_wing_nodes=33), coarse)
    flutter_row("streamwise strips", bwb.build(sweep="streamwise"), (100.0, 110.0, 120.0))
    flutter_row("no structural damping", bwb.build(damping_time=0.0), np.arange(60.0, 141.0, 10.0))


if __name__ == "__main__":
    main()
