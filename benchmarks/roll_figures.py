"""Figures of docs/maneuvers.md, "Rolling conditions" (the free-roll checks of tests/test_roll.py).

``python benchmarks/roll_figures.py`` writes docs/figures/roll_checks.png:

* left: the rigid rectangular strip wing's roll rate after a sudden 5 deg aileron (20 ms actuator),
  marched, against the one-degree-of-freedom closed form p_ss (1 - (tau e^{-t/tau} - t_a e^{-t/t_a}) /
  (tau - t_a)) with p_ss and tau = I_x / L_p integrated by hand (tests/test_roll.py);
* right: the roll effectiveness (p/delta over its rigid value) of the uniform torsion-only wing
  against q / q_R, the steady roll of the residual against the closed form, and the reversal.

About 20 s on one core. The PEGASUS figure is the command's plot (docs/maneuvers.md).
"""

import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests"))
import test_roll as TR  # noqa: E402

from wingmdao.aero.roll import steady_roll  # noqa: E402
from wingmdao.plots import optional_pyplot, save_figure  # noqa: E402
from wingmdao.timemarch.bdf import march  # noqa: E402
from wingmdao.timemarch.system import layout  # noqa: E402


def step_response():
    V, C, I_half, ta = 50.0, 0.1, 3000.0, 0.02
    s, _, p, q, _, _ = TR._wing(chord=C, V=V, inertia=I_half)
    pss_model = steady_roll(s, p, q)[s.body_index["roll_rate"]]
    t = np.arange(301) * 0.005
    Q = np.tile(q, (t.size, 1))
    ql = layout(s.forcing_specs)
    Q[0, ql["surface_command"]] = 0.0
    Q[0, ql["roll_start"]] = 1.0
    rate = march(s, t, p, Q, modified_newton=True).states[:, s.body_index["roll_rate"]]
    cld, _ = TR._glauert(TR.HINGE)
    y1 = 5.75
    pss = V * TR.DELTA * cld * (TR.SEMI ** 2 - y1 ** 2) / 2 / (2 * np.pi * TR.SEMI ** 3 / 3)
    lp = TR.RHO * V * C * 2 * np.pi * TR.SEMI ** 3 / 6
    tau = (I_half + TR.SEMI ** 3 / 3 + np.pi * TR.RHO * (C / 2) ** 2 * TR.SEMI ** 3 / 3) / lp
    ref = pss * (1 - (tau * np.exp(-t / tau) - ta * np.exp(-t / ta)) / (tau - ta))
    print(f"step: p_ss model {pss_model:.6f} closed {pss:.6f} rad/s; tau closed {tau:.4f} s; "
          f"largest difference {np.max(np.abs(rate - ref)) / pss * 100:.2f} % of p_ss")
    return t, rate, ref


def reversal():
    GJ, C, e = 2.0e5, 1.0, 0.05
    qr = TR._reversal_closed_form(GJ, C, e, TR.HINGE)
    v_r = np.sqrt(2 * qr / TR.RHO)
    s, _, p0, q, _, _ = TR._wing(chord=C, V=v_r, span=(0.0, 1.0), GJ=GJ, ref=0.25 + e, mu=10.0)
    al = layout(s.param_specs)["airspeed"]
    cld, _ = TR._glauert(TR.HINGE)
    ratios = np.linspace(0.1, 1.3, 13)
    eff = []
    for r in ratios:
        v = v_r * np.sqrt(r)
        p = p0.copy()
        p[al] = v
        rate = steady_roll(s, p, q)[s.body_index["roll_rate"]]
        eff.append(rate / (v * TR.DELTA * 3 * cld / (2 * 2 * np.pi * TR.SEMI)))
    fine = np.linspace(0.02, 1.3, 200)
    ref = [TR._effectiveness_closed_form(r * qr, GJ, C, e, TR.HINGE) for r in fine]
    print(f"reversal: q_R closed form {qr:.1f} Pa (V_R = {v_r:.3f} m/s at rho = {TR.RHO})")
    return ratios, np.array(eff), fine, np.array(ref)


def main():
    plt = optional_pyplot()
    t, rate, ref = step_response()
    ratios, eff, fine, eff_ref = reversal()
    if plt is None:
        return
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    ax[0].plot(t, np.degrees(rate), label="residual (BDF2 march)")
    ax[0].plot(t, np.degrees(ref), "--", label="closed form, 1 DOF + actuator")
    ax[0].set_xlabel("time (s)")
    ax[0].set_ylabel("roll rate (deg/s)")
    ax[0].set_title("rigid strip wing, sudden 5 deg aileron", fontsize=9)
    ax[0].legend(fontsize=8)
    ax[1].plot(fine, eff_ref, label="closed form (torsion only)")
    ax[1].plot(ratios, eff, "o", label="residual, steady roll")
    ax[1].axhline(0.0, color="k", lw=0.8)
    ax[1].axvline(1.0, color="k", lw=0.8, ls=":")
    ax[1].set_xlabel("q / q_R")
    ax[1].set_ylabel("roll effectiveness (p/delta) / (p/delta)_rigid")
    ax[1].set_title("uniform wing, full-span aileron: aileron reversal", fontsize=9)
    ax[1].legend(fontsize=8)
    for a in ax:
        a.grid(True)
    path = os.path.join(HERE, "..", "docs", "figures", "roll_checks.png")
    save_figure(fig, path, dpi=100)
    print(f"wrote {os.path.normpath(path)}")


if __name__ == "__main__":
    main()
