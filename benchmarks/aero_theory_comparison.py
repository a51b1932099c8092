"""Figures and numbers of docs/aerodynamics-3d.md: the vortex lattice checked, and strip theory,
lifting line and vortex lattice compared on the Goland wing and PEGASUS.

    PYTHONPATH=. python benchmarks/aero_theory_comparison.py [--skip-pegasus]
    PYTHONPATH=. python benchmarks/aero_theory_comparison.py --table [--skip-pegasus]

(``GUST_JSON_DIR=DIR`` reuses ``DIR/gust_THEORY.json`` of earlier ``wingmdao gust`` runs.)

``--table`` prints only the table of strip theory, lifting line, vortex lattice and doublet
lattice on Goland, HALE and PEGASUS (flutter speed, clamped 1-cos gust root-bending peak,
clamped turbulence A-bar of the root bending, PEGASUS sized mass): Goland and HALE in this
process (:mod:`wingmdao.loads.theory_comparison`, a few minutes, the flutter sweeps dominating),
PEGASUS from the JSON of ``wingmdao flutter|gust|turbulence|size pegasus --aero-theory THEORY``
(about 25 minutes for the four sizings and four flutter sweeps; ``TABLE_JSON_DIR=DIR`` keeps and
reuses them).

Writes docs/figures/vlm_lift_slope.png, docs/figures/goland_gust_theories.png,
docs/figures/goland_flutter_theories.png, docs/figures/pegasus_gust_theories.png and prints the tables of the docs. Several minutes on an
idle machine: three Goland flutter sweeps (``wingmdao flutter goland --aero-theory ...``) and three
PEGASUS gusts (``wingmdao gust pegasus --aero-theory ...``, ~30-40 s each) dominate.
"""

import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from wingmdao.aero import aero_parameters, cached_aeroelastic_system, station_gust_history, three_dimensional_parameters
from wingmdao.aero.modal_loads import station_load_history, station_load_model
from wingmdao.aero.rfa import fit
from wingmdao.aero.rfa_system import modal_rfa_system
from wingmdao.aero.vlm import build_lattice, flat_wing, solve_circulation, station_influence
from wingmdao.beam.static import beam_forcing
from wingmdao.cases import goland
from wingmdao.cli.flutter import analyse, analyse_dlm
from wingmdao.loads.theory_comparison import CONDITIONS, clamped_gust_root_moment, clamped_turbulence_a_bar, clamped_wing
from wingmdao.plots import save_figure
from wingmdao.stability.cases import flutter_problem
from wingmdao.stability.modal import case_forces, jig_modes
from wingmdao.stability.pk import ModalStructure
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import layout, pack

FIG = os.path.join(os.path.dirname(__file__), "..", "docs", "figures")
THEORIES = ("strip", "lifting-line", "vlm")
LABEL = {"strip": "strip theory (2 pi / beta)", "lifting-line": "lifting-line slopes", "vlm": "vortex lattice"}


def helmbold(aspect, sweep_half_chord=0.0, mach=0.0):
    """DATCOM Eq. 4.1.3.2-a, kappa = 1 (per rad)."""
    return 2 * np.pi * aspect / (2 + np.sqrt(aspect ** 2 * (1 - mach ** 2 + np.tan(sweep_half_chord) ** 2) + 4))


def elliptic_wing(aspect, n=31):
    c0 = 8.0 / (np.pi * aspect)
    r, c, ref = flat_wing(1.0, lambda y: c0 * np.sqrt(np.clip(1 - y ** 2, 0, None)) + 1e-6, n_stations=n)
    return r, c, ref, np.pi * c0 / 2


def vlm_figure(plt):
    aspects = np.array([4 / np.pi, 2, 3, 4, 6, 8, 10, 15, 20])
    vlm = [station_influence(*elliptic_wing(a)[:3]).lift_slope(elliptic_wing(a)[3]) for a in aspects]
    print("elliptic wings: A, VLM, DATCOM (Helmbold), lifting line 2 pi A / (A + 2)")
    for a, v in zip(aspects, vlm):
        print(f"  {a:6.3f}  {v:.4f}  {helmbold(a):.4f}  {2 * np.pi * a / (a + 2):.4f}")
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    aa = np.linspace(1, 20, 200)
    ax[0].plot(aa, helmbold(aa), "k-", label="DATCOM (Helmbold)")
    ax[0].plot(aa, 2 * np.pi * aa / (aa + 2), "k--", label="lifting line, 2 pi A / (A + 2)")
    ax[0].plot(aspects, vlm, "o", label="vortex lattice (wingmdao.aero.vlm)")
    ax[0].plot([4 / np.pi], [1.790], "r*", ms=12, label="circular wing, exact (Kinner 1937)")
    ax[0].set_xlabel("aspect ratio A")
    ax[0].set_ylabel("CL_alpha (1/rad)")
    ax[0].set_title("flat elliptic wings, M = 0")
    ax[0].legend(fontsize=8)
    ax[0].grid(True)
    r, c, ref, _ = elliptic_wing(6.0)
    lat = build_lattice(r, c, ref)
    gamma = np.bincount(lat.strip, solve_circulation(lat, np.ones(lat.span.size)))
    eta = lat.strip_y
    ax[1].plot(eta, gamma / gamma[0], "o", ms=3, label="vortex lattice, A = 6")
    ee = np.linspace(0, 1, 200)
    ax[1].plot(ee, np.sqrt(1 - ee ** 2), "k-", label="elliptic")
    ax[1].set_xlabel("eta = y / s")
    ax[1].set_ylabel("circulation / root circulation")
    ax[1].set_title("spanload of the elliptic wing")
    ax[1].legend(fontsize=8)
    ax[1].grid(True)
    save_figure(fig, os.path.join(FIG, "vlm_lift_slope.png"), dpi=100)


def goland_gust(theory, V=100.0, gradient=30.48, u_gust=10.0, dt=0.004, t_final=1.2):
    """Root bending moment history (N m) of the clamped Goland wing in a 1-cos gust of gradient H
    (m) and amplitude u_gust (m/s TAS) at V (m/s), sea level, no gravity, zero angle of attack."""
    n = 21
    bp = goland.beam_params(n)
    ad = goland.aero_data()
    ap = aero_parameters(n, chord=ad["chord"], ref_point=ad["ref_point"], airspeed=V, density=ad["density"])
    r0 = bp["node_positions"]
    if theory != "strip":
        ap.update(three_dimensional_parameters(theory, r0, ap["chord"], ap["ref_point"], 0.0))
    s = cached_aeroelastic_system(n, aero_theory="vlm" if theory == "vlm" else "strip")
    p = pack(s.param_specs, {**bp, **ap})
    qd = beam_forcing(n)
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3))
    t = np.arange(0.0, t_final + 0.5 * dt, dt)
    Q = np.tile(pack(s.forcing_specs, qd), (t.size, 1))

    def profile(tau):
        d = V * (np.asarray(tau) - 0.05)
        return np.where((d >= 0) & (d <= 2 * gradient), 0.5 * u_gust * (1 - np.cos(np.pi * d / gradient)), 0.0)

    x_le = r0[:, 0] - ap["ref_point"] * ap["chord"]
    Q[:, layout(s.forcing_specs)["gust_velocity"]] = station_gust_history(t, x_le, V, profile)
    h = march(s, t, p, Q)
    return t, s.layout.beam_states(h.states)[:, 0, 9]


def goland_gust_dlm(V=100.0, gradient=30.48, u_gust=10.0, dt=0.004, t_final=1.2, n_modes=6):
    """Root bending moment history (N m) of the same gust with the doublet lattice: the modal wing
    with Roger's lag states (wingmdao.aero.rfa_system, 21 nodes, ``n_modes`` modes), marched by
    BDF2, the root moment by force summation (wingmdao.aero.modal_loads); also returns the
    mode-displacement sum ``sum_i q_i M_root,i`` for comparison."""
    prob = flutter_problem("goland", num_nodes=21)
    modes = jig_modes(prob, n_modes)
    structure = ModalStructure.from_modes(modes)
    gaf = case_forces(prob, modes, 0.0)
    rfa = fit(gaf)
    s = modal_rfa_system(structure, rfa)
    t = np.arange(0.0, t_final + 0.5 * dt, dt)
    d = V * (t - 0.05)
    on = (d >= 0) & (d <= 2 * gradient)
    a = np.pi * V / gradient
    F = np.zeros((t.size, s.n_forcing))
    F[on, 0] = 0.5 * u_gust * (1 - np.cos(a * (t[on] - 0.05)))
    F[on, 1] = 0.5 * u_gust * a * np.sin(a * (t[on] - 0.05))
    F[on, 2] = 0.5 * u_gust * a ** 2 * np.cos(a * (t[on] - 0.05))
    X = march(s, t, pack(s.param_specs, {"airspeed": V, "density": goland.DENSITY}), F).states
    loads, _ = station_load_history(station_load_model(gaf, rfa, modes), structure, rfa, X, F, V, goland.DENSITY)
    return t, loads[:, 0, 3], X[:, :n_modes] @ modes.moment[:, 0, 0]


def goland_comparison(plt):
    print("Goland wing, clamped, 1-cos gust H = 100 ft, 10 m/s, V = 100 m/s, sea level: root bending peak")
    fig, ax = plt.subplots(figsize=(7, 4))
    peaks = {}
    for th in THEORIES:
        t, m = goland_gust(th)
        peaks[th] = float(np.max(np.abs(m)))
        ax.plot(t, m / 1e3, label=LABEL[th])
    for th in THEORIES:
        print(f"  {th:13s} {peaks[th] / 1e3:8.2f} kN m  ({peaks[th] / peaks['vlm']:.3f} x vortex lattice)")
    t, m, m_modes = goland_gust_dlm()
    for name, mm in (("dlm", m), ("dlm (mode displacement)", m_modes)):
        peak = float(np.max(np.abs(mm)))
        print(f"  {name:13s} {peak / 1e3:8.2f} kN m  ({peak / peaks['vlm']:.3f} x vortex lattice)")
    ax.plot(t, m / 1e3, label="doublet lattice (modal, force summation)")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("root bending moment (kN m)")
    ax.set_title("Goland wing, 1-cos gust (H = 100 ft, 10 m/s, V = 100 m/s)")
    ax.grid(True)
    ax.legend()
    save_figure(fig, os.path.join(FIG, "goland_gust_theories.png"), dpi=100)
    print("Goland flutter (wingmdao flutter goland --aero-theory ...):")
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for k, th in enumerate(THEORIES):
        res = analyse("goland", aero_theory=th)
        print(f"  {th:13s} flutter {res['flutter_speed_m_s']:.1f} m/s at {res['flutter_frequency_rad_s']:.1f} rad/s, "
              f"divergence {res['divergence_speed_m_s']}")
        v = np.asarray(res["speeds"])
        for j, (g, w) in enumerate(zip(res["structural_damping"], res["frequency_rad_s"])):
            kw = dict(color=f"C{k}", label=LABEL[th] if j == 0 else None)
            ax[0].plot(v, np.asarray(g, dtype=float), **kw)
            ax[1].plot(v, np.asarray(w, dtype=float), **kw)
    ax[0].axhline(0.0, color="k", lw=0.8)
    ax[0].set_ylim(-0.3, 0.1)
    ax[0].set_ylabel("structural damping g")
    ax[1].set_ylabel("frequency (rad/s)")
    for a in ax:
        a.set_xlabel("airspeed (m/s)")
        a.grid(True)
    ax[0].legend(fontsize=8)
    ax[0].set_title("Goland wing, sea level: V-g")
    save_figure(fig, os.path.join(FIG, "goland_flutter_theories.png"), dpi=100)
    return peaks


def pegasus_maneuver(theory, load_factor=2.5):
    """Root bending moment and torsion (N m), trim angle (rad) of the trimmed static PEGASUS
    maneuver at ``load_factor`` on the initial design: the sizing's own coupled maneuver case
    (``wingmdao size pegasus --aero coupled --aero-theory THEORY``, case maneuver_pos)."""
    from wingmdao.cases import pegasus
    from wingmdao.sizing import SECTION_KINDS, design_beam_params, initial_design
    from wingmdao.timemarch.bdf import solve_static

    setup = pegasus.build(aero="coupled", aero_theory=theory, load_factor=load_factor)
    case = next(c for c in setup.load_cases if c.name == "maneuver_pos")
    n = setup.geometry.num_nodes
    bp = design_beam_params(setup.geometry, setup.material,
                            initial_design(setup.options, SECTION_KINDS[setup.section]["design_vars"]), setup.section)
    s = cached_aeroelastic_system(n, trim=True, aero_theory=case.aero.residual_theory)
    p = pack(s.param_specs, {**bp, **case.aero.parameters(n)})
    q = pack(s.forcing_specs, {sp.name: case.forcing_array(sp.name, n)[0] for sp in s.forcing_specs})
    x, _ = solve_static(s, p, q)
    X = s.layout.beam_states(x)
    return X[0, 9], X[0, 10], x[s.trim_index]


def pegasus_gusts(directory):
    """``wingmdao gust pegasus --aero-theory THEORY --json DIR/gust_THEORY.json`` for each theory
    (skipped when the file exists); the results by theory."""
    out = {}
    for th in THEORIES:
        path = os.path.join(directory, f"gust_{th}.json")
        if not os.path.exists(path):
            subprocess.run([sys.executable, "-m", "wingmdao", "gust", "pegasus", "--aero-theory", th, "--no-plots",
                            "--json", path], check=True, stderr=subprocess.DEVNULL)
        with open(path) as f:
            out[th] = json.load(f)
    return out


def pegasus(plt, directory):
    print("PEGASUS trimmed 2.5 g maneuver, initial design (the sizing's coupled case maneuver_pos):")
    for th in THEORIES:
        m, t, a = pegasus_maneuver(th)
        print(f"  {th:13s} root bending {m / 1e3:8.1f} kN m, root torsion {t / 1e3:7.1f} kN m, trim {np.degrees(a):.3f} deg")
    out = pegasus_gusts(directory)
    fig, ax = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    print("PEGASUS gust (wingmdao gust pegasus: free plunge, trimmed 1 g, H = 350 ft):")
    for th in THEORIES:
        r = out[th]
        m = np.asarray(r["root_bending_moment"])
        dm = m - m[0]
        print(f"  {th:13s} wing slope {r['wing_lift_slope_per_rad']:.3f} /rad, trim {np.degrees(r['trim_alpha_rad']):.3f} deg, "
              f"1 g root moment {m[0] / 1e3:.1f} kN m, peak {np.max(np.abs(m)) / 1e3:.1f} kN m (increment "
              f"{np.max(np.abs(dm)) / 1e3:.1f}), peak dn {r['peak_incremental_load_factor']:.3f}")
        ax[0].plot(r["time"], r["load_factor"], label=LABEL[th])
        ax[1].plot(r["time"], m / 1e3, label=LABEL[th])
    ax[0].set_ylabel("load factor")
    ax[1].set_ylabel("root bending moment (kN m)")
    ax[1].set_xlabel("time (s)")
    for a in ax:
        a.grid(True)
    ax[0].legend()
    ax[0].set_title("PEGASUS, 1-cos gust H = 350 ft, free plunge, trimmed 1 g start")
    save_figure(fig, os.path.join(FIG, "pegasus_gust_theories.png"), dpi=100)


TABLE_THEORIES = ("strip", "lifting-line", "vlm", "dlm")
#: the PEGASUS commands of the table (JSON to DIR/NAME_THEORY.json); ``dlm`` differences noted
PEGASUS_COMMANDS = {
    "flutter": ["flutter", "pegasus", "--no-plots"],
    "gust": ["gust", "pegasus", "--clamped", "--no-plots"],
    "turbulence": ["turbulence", "pegasus", "--aero", "coupled", "--clamped", "--no-plots"],
    "size": ["size", "pegasus", "--aero", "coupled", "--loads", "all", "--no-plots"],
}


def wing_row(case, theory):
    """Flutter speed and frequency (sea-level Goland, 20 km HALE; the default sweep), the clamped
    1-cos gust's root-bending peak (N m) and A-bar of the root bending (N m per m/s) of ``case``."""
    if theory == "dlm":
        res = analyse_dlm(case)
        wing = clamped_wing(case)
    else:
        res = analyse(case, aero_theory=theory)
        wing = None
    _, m = clamped_gust_root_moment(case, theory, wing=wing)
    ab, _ = clamped_turbulence_a_bar(case, theory, wing=wing)
    return {"flutter": res["flutter_speed_m_s"], "frequency": res["flutter_frequency_rad_s"],
            "gust": float(np.max(np.abs(m))), "a_bar": ab}


def pegasus_json(directory, name, theory):
    """``wingmdao NAME pegasus ... --aero-theory THEORY --json DIR/NAME_THEORY.json`` (skipped when the
    file exists); its result."""
    path = os.path.join(directory, f"{name}_{theory}.json")
    if not os.path.exists(path):
        out = ["--out", os.path.join(directory, f"{name}_{theory}"), "--overwrite"] if name == "size" else []
        subprocess.run([sys.executable, "-m", "wingmdao", *PEGASUS_COMMANDS[name], "--aero-theory", theory, *out,
                        "--json", path], check=True, stderr=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
    with open(path) as f:
        return json.load(f)


def pegasus_row(directory, theory):
    """PEGASUS, initial design: flutter (the default sweep 20-300 m/s; the doublet lattice's p-k),
    the clamped Table 5.3 gust's peak root-bending increment, the clamped turbulence A-bar of the
    root bending (M 0.5, 20 000 ft) and the coupled ``--loads all`` sizing's mass."""
    fl = pegasus_json(directory, "flutter", theory)
    gu = pegasus_json(directory, "gust", theory)
    tu = pegasus_json(directory, "turbulence", theory)
    sz = pegasus_json(directory, "size", theory)
    return {"flutter": fl["flutter_speed_m_s"], "frequency": fl["flutter_frequency_rad_s"],
            "gust": gu["peak_incremental_root_bending_moment"], "a_bar": tu["a_bar"]["root_bending_moment"],
            "mass": sz["mass_kg"] if sz.get("success") else None}


def _fmt(x, scale=1.0, digits=1):
    return "none in the sweep" if x is None else f"{x / scale:.{digits}f}"


def _ratio(x, ref):
    return "" if x is None or ref is None else f"{x / ref:.2f}"


def comparison_table(skip_pegasus=False):
    """Print the table of docs/aerodynamics-3d.md: every theory on Goland, HALE and PEGASUS."""
    rows = {}
    for case in ("goland", "hale"):
        for th in TABLE_THEORIES:
            rows[case, th] = wing_row(case, th)
            print(f"  {case} {th}: {rows[case, th]}", file=sys.stderr, flush=True)
    if not skip_pegasus:
        directory = os.environ.get("TABLE_JSON_DIR") or tempfile.mkdtemp(prefix="aero_table_")
        for th in TABLE_THEORIES:
            rows["pegasus", th] = pegasus_row(directory, th)
            print(f"  pegasus {th}: {rows['pegasus', th]}", file=sys.stderr, flush=True)
    for case, c in CONDITIONS.items():
        print(f"{case}: clamped, gust {c['u_gust']} m/s, H = {c['gradient_m']} m at {c['airspeed']} m/s, "
              f"{c['density']} kg/m^3; A-bar at the same speed and density")
    name = {"strip": "strip", "lifting-line": "lifting line", "vlm": "vortex lattice (2-D lags)",
            "dlm": "doublet lattice"}
    print("| wing | theory | flutter speed (m/s) | / DLM | flutter frequency (rad/s) | gust root-bending peak | "
          "/ DLM | A-bar of root bending | / DLM | sized mass (kg) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    unit = {"goland": (1e3, "kN m", "kN m per m/s", 1), "hale": (1.0, "N m", "N m per m/s", 2),
            "pegasus": (1e3, "kN m", "kN m per m/s", 1)}
    label = {"goland": "Goland", "hale": "HALE", "pegasus": "PEGASUS"}
    for case in ("goland", "hale", "pegasus"):
        if (case, "dlm") not in rows:
            continue
        ref = rows[case, "dlm"]
        sc, gu, au, dig = unit[case]
        for th in TABLE_THEORIES:
            r = rows[case, th]
            mass = (_fmt(r["mass"], digits=2) if r.get("mass") is not None else "did not converge") if "mass" in r \
                else "no sizing (beam data only)"
            flutter = _fmt(r["flutter"], digits=dig)
            if th in ("lifting-line", "vlm") and r["flutter"] is not None:
                flutter += " (a)"  # quasi-steady 3-D lift with 2-D lags: overshoots the doublet lattice
            print(f"| {label[case]} | {name[th]} | {flutter} | {_ratio(r['flutter'], ref['flutter'])} | "
                  f"{_fmt(r['frequency'], digits=dig)} | {r['gust'] / sc:.2f} {gu} | {r['gust'] / ref['gust']:.2f} | "
                  f"{r['a_bar'] / sc:.2f} {au} | {r['a_bar'] / ref['a_bar']:.2f} | {mass} |")
    print("(a) quasi-steady 3-D lift with 2-D (Wagner) lags: overshoots the doublet lattice's flutter speed")


def main():
    if "--table" in sys.argv:
        comparison_table("--skip-pegasus" in sys.argv)
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    vlm_figure(plt)
    goland_comparison(plt)
    if "--skip-pegasus" not in sys.argv:
        with tempfile.TemporaryDirectory() as tmp:
            pegasus(plt, os.environ.get("GUST_JSON_DIR", tmp))


if __name__ == "__main__":
    main()
