"""Figures of docs/controls.md (control surfaces, actuators and load alleviation).

``python benchmarks/controls_figures.py`` writes

* docs/figures/controls_flap_theory.png - dCl/dbeta, dCm_c/4/dbeta and the hinge-moment
  coefficients against the hinge position: Theodorsen's flap functions (wingmdao.aero.controls)
  against Glauert's closed forms and a direct integration of the thin-airfoil load over the flap;
* docs/figures/controls_harmonic_flap.png - the marched residual's flap lift per radian at several
  reduced frequencies against Theodorsen's closed form with the model's C(k) (Jones) and the exact C(k);
* docs/figures/controls_stability_limit.png - the closed-loop eigenvalue of the root-bending
  feedback of tests/test_controls_system.py against the gain, with the marched growth/decay rates;
* docs/figures/controls_pegasus_gust.png - PEGASUS 1-cos gust without and with the law of
  docs/examples/pegasus_alleviation.yaml (runs ``wingmdao gust pegasus --alleviation ...``);
* docs/figures/controls_vlm_flap.png (``vlm``) - the flap as deflected vortex-lattice panels: the
  errors of the 2-D limit against the chordwise panels, and a part-span flap's spanload against
  the lifting line (the references of tests/test_vlm_flaps.py);
* docs/figures/controls_dlm_flap.png (``dlm``) - the flap as a flap mode of the doublet lattice: the
  mid-span strip's flap lift and hinge moment errors against the chordwise panels (Glauert at k = 0,
  Theodorsen with C(k) at k = 0.4; the references of tests/test_dlm_flaps.py), and the PEGASUS gust
  with the law of docs/examples/pegasus_alleviation.yaml on the doublet lattice and the vortex
  lattice (runs ``wingmdao gust pegasus --aero-theory dlm|vlm --alleviation ...``);
* ``mla`` (printed only) - the PEGASUS scheduled aileron's rigid-wing root-bending change with the
  lattice's flap panels, the equivalent angle through the lattice, and strips.

About 2 minutes on one core.
"""

import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests"))
import test_controls as TC  # noqa: E402
import test_controls_system as TS  # noqa: E402
import test_dlm_flaps as TD  # noqa: E402
import test_vlm_flaps as TV  # noqa: E402

from wingmdao.aero import theodorsen_exact, theodorsen_jones  # noqa: E402
from wingmdao.aero.controls import (ControlSurface, flap_harmonic_loads, flap_lift_effectiveness,  # noqa: E402
                                    hinge_moment_coefficients, theodorsen_flap_functions)
from wingmdao.aero.vlm import flap_influence, flat_wing  # noqa: E402
from wingmdao.plots import save_figure  # noqa: E402
from wingmdao.timemarch.bdf import march, state_rates  # noqa: E402
from wingmdao.timemarch.system import layout  # noqa: E402

FIG = os.path.join(HERE, "..", "docs", "figures")


def flap_theory(plt):
    hinge = np.linspace(0.5, 0.95, 46)
    th = np.arccos(1 - 2 * hinge)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    axes[0].plot(hinge, [flap_lift_effectiveness(h) for h in hinge], label="dCl/dbeta (2 T10)")
    axes[0].plot(hinge[::5], 2 * (np.pi - th[::5] + np.sin(th[::5])), "ko", mfc="none", label="Glauert")
    axes[0].plot(hinge, [-theodorsen_flap_functions(h)[15] / 2 for h in hinge], label="dCm_c/4/dbeta (-T15/2)")
    axes[0].plot(hinge[::5], -0.5 * np.sin(th[::5]) * (1 - np.cos(th[::5])), "ks", mfc="none",
                 label="Glauert -sin(th)(1-cos th)/2")
    axes[0].set_xlabel("hinge (fraction of chord)")
    axes[0].set_ylabel("per rad")
    axes[0].legend(fontsize=8)
    ch = np.array([hinge_moment_coefficients(h) for h in hinge])
    ref = np.array([(TC._thin_airfoil_hinge_coefficient(h, 1.0, 0.0), TC._thin_airfoil_hinge_coefficient(h, 0.0, 1.0))
                    for h in hinge[::5]])
    axes[1].plot(hinge, ch[:, 0], label="C_h,alpha (-T12/2)")
    axes[1].plot(hinge, ch[:, 1], label="C_h,beta (-(T18+T10 T12)/(2 pi))")
    axes[1].plot(hinge[::5], ref[:, 0], "ko", mfc="none", label="thin-airfoil load integrated")
    axes[1].plot(hinge[::5], ref[:, 1], "ks", mfc="none")
    axes[1].set_xlabel("hinge (fraction of chord)")
    axes[1].set_ylabel("hinge moment / (q c^2) per rad")
    axes[1].legend(fontsize=8)
    for ax in axes:
        ax.grid(True)
    print("max |C_h - thin airfoil|:", float(np.max(np.abs(ch[::5] - ref))))
    save_figure(fig, os.path.join(FIG, "controls_flap_theory.png"))


def harmonic(plt):
    hinge, b = 0.75, 0.5
    s, p, q = TS._rigid_wing(2, [ControlSurface("flap", hinge=hinge, nodes=(0, 1), actuator_order=2,
                                                frequency_hz=200.0, damping=0.7)])
    ks = np.array([0.05, 0.1, 0.2, 0.4, 0.7, 1.0])
    ours = []
    for k in ks:
        w = k * TS.V / b
        t = np.linspace(0.0, 5 * 2 * np.pi / w, 5 * 200 + 1)
        Q = np.tile(q, (t.size, 1))
        Q[:, layout(s.forcing_specs)["surface_command"]] = 0.02 * np.sin(w * t)[:, None]
        h = march(s, t, p, Q)
        L, _ = s.section_load_history(h.states, state_rates(h.states, t[1] - t[0]), p, Q)
        m = t >= 3 * 2 * np.pi / w
        A = np.column_stack([np.sin(w * t[m]), np.cos(w * t[m]), np.ones(m.sum())])
        cl = np.linalg.lstsq(A, L[m, 0], rcond=None)[0]
        cb = np.linalg.lstsq(A, h.states[m, s.control_index["flap_deflection"]], rcond=None)[0]
        ours.append((cl[0] + 1j * cl[1]) / (cb[0] + 1j * cb[1]) / (TS.RHO * TS.V ** 2 * b))
    ours = np.array(ours)
    kk = np.linspace(0.02, 1.0, 100)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for C, style, name in ((theodorsen_jones, "-", "Theodorsen, Jones C(k)"), (theodorsen_exact, "--", "Theodorsen, exact C(k)")):
        ref = flap_harmonic_loads(kk, hinge, C)[0]
        axes[0].plot(kk, np.abs(ref), style, label=name)
        axes[1].plot(kk, np.degrees(np.angle(ref)), style, label=name)
    axes[0].plot(ks, np.abs(ours), "ko", label="marched residual")
    axes[1].plot(ks, np.degrees(np.angle(ours)), "ko", label="marched residual")
    axes[0].set_ylabel("|L| / (rho V^2 b beta)")
    axes[1].set_ylabel("phase (deg)")
    for ax in axes:
        ax.set_xlabel("reduced frequency k")
        ax.grid(True)
        ax.legend(fontsize=8)
    ref = flap_harmonic_loads(ks, hinge, theodorsen_jones)[0]
    print("harmonic flap lift, max |ours/ref - 1| (Jones C):", float(np.max(np.abs(ours / ref - 1))))
    save_figure(fig, os.path.join(FIG, "controls_harmonic_flap.png"))


def stability(plt):
    s, params, q = TS._flexible_wing(0.0)
    gains = np.linspace(0.0, 260.0, 27)
    lam = np.array([TS._slowest(s, params(K), q).real for K in gains])
    k_star = float(np.interp(0.0, lam, gains))
    t = np.arange(0, 601) * 0.01
    Q = np.tile(q, (t.size, 1))
    Q[(t > 0) & (t <= 0.05), layout(s.forcing_specs)["surface_command"]] = 0.01
    marched = []
    for K in (0.4 * k_star, 0.7 * k_star, 1.15 * k_star):
        h = march(s, t, params(K), Q)
        mlog = np.log(np.abs(h.states[:, 9]))
        marched.append((K, np.polyfit(t[t >= 3.0], mlog[t >= 3.0], 1)[0]))
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(gains, lam, label="eigenvalue (linearization)")
    ax.plot(*zip(*marched), "ko", mfc="none", label="march: growth rate of root bending")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.axvline(k_star, color="r", ls=":", label=f"K* = {k_star:.1f} rad/(MN m)")
    ax.set_xlabel("gain K (aileron rad per MN m of root bending)")
    ax.set_ylabel("real eigenvalue (1/s)")
    ax.grid(True)
    ax.legend(fontsize=8)
    print("stability limit K* =", k_star, "marched rates:", marched)
    save_figure(fig, os.path.join(FIG, "controls_stability_limit.png"))


def pegasus(plt):
    example = os.path.join(HERE, "..", "docs", "examples", "pegasus_alleviation.yaml")
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "g.json")
        subprocess.run([sys.executable, "-m", "wingmdao", "gust", "pegasus", "--alleviation", example, "--no-plots",
                        "--json", out], check=True)
        with open(out) as fh:
            res = json.load(fh)
    a = res["alleviation"]
    s = a["surfaces"]["aileron"]
    t = np.asarray(res["time"])
    fig, axes = plt.subplots(4, 1, figsize=(7, 10), sharex=True)
    axes[0].plot(t, a["load_factor_without_law"], label="without law")
    axes[0].plot(t, res["load_factor"], label="with law")
    axes[0].set_ylabel("load factor")
    axes[1].plot(t, np.asarray(a["root_bending_moment_without_law"]) / 1e3, label="without law")
    axes[1].plot(t, np.asarray(res["root_bending_moment"]) / 1e3, label="with law")
    axes[1].set_ylabel("root bending (kN m)")
    axes[2].plot(t, s["deflection_deg"], label="deflection (deg)")
    axes[2].plot(t, s["rate_deg_s"], label="rate (deg/s)")
    for lim, style in ((s["max_deflection_deg"], ":"), (s["max_rate_deg_s"], "--")):
        axes[2].axhline(lim, color="k", ls=style, lw=0.7)
        axes[2].axhline(-lim, color="k", ls=style, lw=0.7)
    axes[2].set_ylabel("aileron")
    axes[3].plot(t, np.asarray(s["hinge_moment_n_m"]) / 1e3)
    axes[3].set_ylabel("hinge moment (kN m)")
    axes[3].set_xlabel("time (s)")
    for ax in axes:
        ax.grid(True)
    for ax in axes[:3]:
        ax.legend(fontsize=8)
    print("PEGASUS: peak root bending increment", a["peak_incremental_root_bending_without_law"],
          "->", a["peak_incremental_root_bending_with_law"], "peak dn", a["peak_incremental_load_factor_without_law"],
          "->", a["peak_incremental_load_factor_with_law"], "aileron peak", s["peak_deflection_deg"], "deg",
          s["peak_rate_deg_s"], "deg/s, hinge", s["peak_hinge_moment_n_m"], "N m")
    save_figure(fig, os.path.join(FIG, "controls_pegasus_gust.png"))


def vlm_flap(plt):
    """2-D limit (aspect ratio 200) against the chordwise panels; part-span spanload against the lifting line."""
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    semi, n = 100.0, 11
    r, c, ref = flat_wing(semi, lambda y: np.ones_like(y), n_stations=n, spacing="uniform")
    counts = (4, 8, 16, 32, 64)
    for hinge, mk in ((0.75, "o"), (0.5, "s")):
        cl_d, ch_a, ch_b = TV._glauert(hinge)
        rows = []
        for nc in counts:
            st, fl = flap_influence(r, c, ref, [(tuple(range(n)), hinge)], n_chordwise=nc, n_spanwise=2)
            a0 = st.lift.sum(axis=1)[0]
            rows.append((fl.lift.sum(axis=1)[0] / a0 / (cl_d / (2 * np.pi)) - 1, fl.hinge_flap.sum() / semi / ch_b - 1,
                         fl.hinge_station.sum() / semi * (2 * np.pi / a0) / ch_a - 1, fl.lift.sum(axis=1)[0] / cl_d - 1))
            print(f"hinge {hinge} n_chordwise {nc}: dCl/ddelta {rows[-1][3]:+.4f}, / dCl/dalpha vs tau {rows[-1][0]:+.4f},"
                  f" C_h,beta {rows[-1][1]:+.4f}, C_h,alpha {rows[-1][2]:+.4f}")
        rows = np.array(rows)
        for k, lab in enumerate(("tau", "C_h,beta", "C_h,alpha")):
            axes[0].semilogx(counts, 100 * rows[:, k], marker=mk, color=f"C{k}", label=f"{lab}, hinge {hinge}",
                             ls="-" if hinge == 0.75 else "--")
    axes[0].set_xticks(counts, [str(k) for k in counts])
    axes[0].minorticks_off()
    axes[0].set_xlabel("chordwise panels")
    axes[0].set_ylabel("lattice / thin airfoil - 1 (%)")
    axes[0].axhline(0, color="k", lw=0.5)
    axes[0].legend(fontsize=7)
    aspect, n = 10.0, 21
    semi = aspect / 2
    r, c, ref = flat_wing(semi, lambda y: np.ones_like(y), n_stations=n, spacing="uniform")
    st, fl = flap_influence(r, c, ref, [(tuple(range(12, 21)), 0.75)], n_chordwise=16, n_spanwise=2)
    lift = fl.lift.sum(axis=1)
    # lifting line (Glauert's series) of a unit angle on the flap's span, scaled by the lattice's CL ratio
    terms = 199
    nn = np.arange(1, 2 * terms, 2)
    th = (np.arange(1, terms + 1) - 0.5) * (np.pi / 2) / terms
    mu = 2 * np.pi / (4 * aspect)
    eta0 = r[12, 1] / semi
    A = np.linalg.solve(np.sin(np.outer(th, nn)) * (np.sin(th)[:, None] + nn[None, :] * mu),
                        mu * (np.abs(np.cos(th)) >= eta0 - 1e-12) * np.sin(th))
    tg = np.linspace(1e-3, np.pi / 2, 400)
    cl_c = 4 * aspect * np.sin(np.outer(tg, nn)) @ A  # local c cl per unit angle (Gamma = 2 b V sum An sin n th)
    cl_ll_total = np.pi * aspect * A[0]
    cl_vlm_total = 2 * st.tributary @ lift / aspect
    axes[1].plot(r[:, 1] / semi, lift / cl_vlm_total, "o-", label="vortex lattice, flap panels (per CL)")
    axes[1].plot(np.cos(tg), cl_c / cl_ll_total, "k--", label="lifting line, angle on the flap span (per CL)")
    axes[1].axvspan(eta0, 1.0, color="0.9")
    axes[1].set_xlabel("y / s (aileron shaded)")
    axes[1].set_ylabel("lift per span / (q CL) (m)")
    axes[1].legend(fontsize=8)
    for ax in axes:
        ax.grid(True)
    print(f"part span 60-100 %: CL_delta / CL_delta,full lattice {cl_vlm_total:.4f} (per rad, tau included)")
    save_figure(fig, os.path.join(FIG, "controls_vlm_flap.png"))


def dlm_flap(plt):
    """Flap modes of the doublet lattice: convergence with the chordwise panels; PEGASUS gust with the law."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    counts = (4, 8, 16, 32)
    k = 0.4
    L, _, H = flap_harmonic_loads(k, TD.HINGE, theodorsen_exact)
    tau = flap_lift_effectiveness(TD.HINGE) / (2 * np.pi)
    cha, chb = hinge_moment_coefficients(TD.HINGE)
    rows = []
    for nc in counts:
        v = TD._mid_strip(nc, (0.0, k))
        cla, clb, hb = v[0, 0].real, v[0, 1].real, v[0, 3].real
        rows.append((clb / cla / tau - 1, hb / (cha * (clb - 2 * np.pi * tau) / (2 * np.pi) + chb) - 1,
                     abs(v[1, 1] / (2 * TD.B * L)) - 1, abs(v[1, 3] / (2 * TD.B ** 2 * H)) - 1))
        print(f"n_chordwise {nc}: steady lift {rows[-1][0]:+.4f}, hinge {rows[-1][1]:+.4f}; k = {k}: lift "
              f"{rows[-1][2]:+.4f}, hinge {rows[-1][3]:+.4f}")
    rows = 100 * np.array(rows)
    for j, (lab, st) in enumerate((("lift, k = 0 (Glauert)", "o-"), ("hinge moment, k = 0 (Glauert)", "s-"),
                                   (f"|lift|, k = {k} (Theodorsen)", "o--"), (f"|hinge moment|, k = {k} (Theodorsen)", "s--"))):
        axes[0].semilogx(counts, rows[:, j], st, color=f"C{j % 2}", label=lab)
    axes[0].set_xticks(counts, [str(c) for c in counts])
    axes[0].minorticks_off()
    axes[0].axhline(0, color="k", lw=0.5)
    axes[0].set_xlabel("chordwise panels (a quarter of them on the 25 % flap)")
    axes[0].set_ylabel("doublet lattice / thin airfoil - 1 (%)")
    axes[0].legend(fontsize=7)
    example = os.path.join(HERE, "..", "docs", "examples", "pegasus_alleviation.yaml")
    res = {}
    with tempfile.TemporaryDirectory() as tmp:
        for theory in ("dlm", "vlm"):
            out = os.path.join(tmp, f"{theory}.json")
            subprocess.run([sys.executable, "-m", "wingmdao", "gust", "pegasus", "--aero-theory", theory,
                            "--alleviation", example, "--no-plots", "--json", out], check=True)
            with open(out) as fh:
                res[theory] = json.load(fh)
    for j, (theory, lab) in enumerate((("dlm", "doublet lattice, flap modes"), ("vlm", "vortex lattice, flap panels"))):
        r = res[theory]
        t = np.asarray(r["time"])
        m = np.asarray(r["root_bending_moment"])
        m0 = np.asarray(r["alleviation"]["root_bending_moment_without_law"])
        axes[1].plot(t, (m - m[0]) / 1e3, color=f"C{j}", label=f"{lab}, with law")
        axes[1].plot(t, (m0 - m0[0]) / 1e3, "--", color=f"C{j}", label=f"{lab}, without law")
        a = r["alleviation"]
        print(f"{theory}: peak root bending increment {a['peak_incremental_root_bending_without_law'] / 1e3:.1f} -> "
              f"{a['peak_incremental_root_bending_with_law'] / 1e3:.1f} kN m, dn {a['peak_incremental_load_factor_without_law']:.3f}"
              f" -> {a['peak_incremental_load_factor_with_law']:.3f}, aileron {a['surfaces']['aileron']['peak_deflection_deg']:.2f} deg")
    axes[1].set_xlabel("time (s)")
    axes[1].set_ylabel("root bending increment (kN m)")
    axes[1].legend(fontsize=7)
    for ax in axes:
        ax.grid(True)
    save_figure(fig, os.path.join(FIG, "controls_dlm_flap.png"))


def mla_lattice(plt):
    """PEGASUS 2.5 g scheduled aileron (docs/examples/pegasus_mla.yaml): the rigid wing's root-bending
    change with the lattice's flap columns, with the flap as the equivalent angle T10/pi delta through
    the lattice's station influence, and with strips (the closed form of docs/controls.md)."""
    import math

    from wingmdao.aero.vlm import station_influence
    from wingmdao.cases import pegasus

    setup = pegasus.build(pegasus.PegasusOptions(aero="coupled", aero_theory="vlm",
                                                 alleviation=os.path.join(HERE, "..", "docs", "examples",
                                                                          "pegasus_mla.yaml")))
    a = next(c for c in setup.load_cases if c.name == "maneuver_pos").aero
    r0 = np.asarray(a.node_positions)
    n = r0.shape[0]
    c, ref = np.broadcast_to(a.chord, (n,)), np.broadcast_to(a.ref_point, (n,))
    nodes = a.controls.surfaces[0][1]
    qd, delta = 0.5 * a.density * a.airspeed ** 2, math.radians(-6.0 * 1.5)
    y, ds = r0[:, 1] - r0[0, 1], np.linalg.norm(np.diff(r0, axis=0), axis=1)

    def integ(f):
        return float(np.sum(0.5 * (f[1:] + f[:-1]) * ds))

    st, fl = flap_influence(r0, c, ref, [(nodes, 0.75)], mach=a.mach)
    tau = theodorsen_flap_functions(0.75)[10] / math.pi
    e = np.zeros(n)
    e[list(nodes)] = tau
    beta = math.sqrt(1 - a.mach ** 2)
    cases = (("lattice flap panels", fl.lift.sum(axis=1), st.lift.sum(axis=1)),
             ("equivalent angle through the lattice", station_influence(r0, c, ref, mach=a.mach).lift @ e,
              station_influence(r0, c, ref, mach=a.mach).lift.sum(axis=1)),
             ("strips", 2 * np.pi / beta * c * e, 2 * np.pi / beta * c))
    for name, lf, one in cases:
        dm = qd * delta * (integ(lf * y) - integ(lf) / integ(one) * integ(one * y))
        print(f"{name}: aileron lift {integ(lf):.2f} m^2 per rad, 2.5 g root bending change {dm / 1e3:.1f} kN m, "
              f"-1 g {-dm / 1e3 * 12 / 9:.1f} kN m")


def main():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    which = sys.argv[1:] or ["flap", "harmonic", "stability", "pegasus"]
    for name, fun in (("flap", flap_theory), ("harmonic", harmonic), ("stability", stability), ("pegasus", pegasus),
                      ("vlm", vlm_flap), ("dlm", dlm_flap), ("mla", mla_lattice)):
        if name in which:
            fun(plt)


if __name__ == "__main__":
    main()
