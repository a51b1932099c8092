"""Figures of the free-pitch verification (docs/aeroelasticity.md, "Free pitch").

Runs the checks of tests/test_pitch.py and prints ours / reference / difference: short-period
eigenvalues of the linearized plunge + pitch system against the classical two-degree-of-freedom
closed form (Nelson 1998 Sec. 4.4; Etkin & Reid 1996 Sec. 6.3), and the peak incremental gust load
factor free in pitch against plunge only (Rokhsaz & Kliment, J. Aircraft 56(2), 2019: pitch
freedom lowers it by up to ~10 % for a stable transport). About 30 s.
"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))
import test_pitch as T  # noqa: E402


def main():
    print("short period (1/s): ours | closed form | difference real, imag")
    for cg, dw, lag, iyy in ((0.0, 0.0, False, T.IYY), (0.05, 0.3, False, T.IYY), (-0.02, 0.4, False, T.IYY),
                             (0.05, 0.4, True, 3000.0), (0.05, 0.4, True, T.IYY)):
        s, p, qd, _ = T._aircraft(cg_x=cg, downwash=dw, tail_lag=lag, iyy=iyy)
        lam = T._short_period(s, p, qd)[0][0]
        ref = T._closed(cg, iyy=iyy, downwash=dw, tail_lag=lag)
        ref = ref[ref.imag > 0][0]
        print(f"  cg {cg:+.2f} m, deps/dalpha {dw}, lag {lag!s:5}, I_yy {iyy:6.0f}: {lam.real:.3f} +- {lam.imag:.3f}i | "
              f"{ref.real:.3f} +- {ref.imag:.3f}i | {100 * (lam.real / ref.real - 1):+.1f} %, "
              f"{100 * (lam.imag / ref.imag - 1):+.1f} %")
    dn0, _ = T._gust_peak(False)
    print(f"1-cos gust H = 30 m: plunge only peak dn {dn0:.5f}; free pitch / plunge only (reference: < 1, "
          "by up to ~10 %):")
    for label, kw in (("I_yy nominal", {}), ("I_yy x 1e4", {"iyy": T.IYY * 1e4}),
                      ("small tail, I_yy nominal", {"cg_x": -0.02, "tail_area": 0.05}),
                      ("small tail, I_yy x 1e4 (-> plunge only)", {"cg_x": -0.02, "tail_area": 0.05, "iyy": T.IYY * 1e4})):
        dn, th = T._gust_peak(True, **kw)
        print(f"  {label}: {dn / dn0:.4f} (max |theta_p| {th:.2e} rad)")


if __name__ == "__main__":
    main()
