"""``wingmdao flutter CASE``: flutter and divergence of a benchmark wing (docs/flutter.md).

The case's beam (clamped root) with unsteady strip theory (:mod:`wingmdao.aero`) is linearised
about its static state at each speed of the sweep; the eigenvalues of (dR/dxdot, dR/dx)
(:mod:`wingmdao.stability`) give per-mode damping and frequency, tracked by MAC; the flutter and
divergence speeds are refined between sweep points.

JSON keys: case, num_nodes, density_kg_m3, flutter_speed_m_s, flutter_frequency_rad_s,
divergence_speed_m_s (null when none within the sweep), natural_frequencies_rad_s (in vacuo,
first six), speeds, damping (per tracked mode and speed, Re lambda 1/s), structural_damping
(``g = 2 Re / |Im|``), frequency_rad_s, published (the case's reference values), timings; for
PEGASUS also dive_speed_m_s (V_D) and design (the --design file, or "initial").
With ``--deformed``: ``deformed`` (gravity_m_s2 and, per root angle of attack, the flutter speed,
frequency and static tip deflection at flutter, the sweep's speeds and tip deflections,
:mod:`wingmdao.stability.deformed`), ``deformed_published`` and a flutter speed vs tip
deflection PNG.
With ``--aero-theory dlm`` the top-level flutter speed and frequency are the doublet lattice's
(p-k on its generalized forces, :mod:`wingmdao.stability.modal`), ``divergence_speed_m_s`` null;
``dlm`` holds the p-k and state-space sweeps and flutter points, the Roger fit (lag roots, fit
error), the Mach number, reduced frequencies, modal basis size and timings; ``strip`` the strip
theory sweep of the same speeds; the PNG draws both V-g / V-f side by side.
"""

from __future__ import annotations

import importlib
import sys
import time as _time

import numpy as np

import wingmdao.cli._openmdao  # noqa: F401  (first: OpenMDAO without the matplotlib of its report plugins)
from wingmdao.stability.cases import FLUTTER_CASES, DEFAULT_NODES, flutter_problem
from wingmdao.cli._io import read_design, warn, write_json
from wingmdao.beam.residual import forcing_specs
from wingmdao.cases.pegasus import flight_point
from wingmdao.cli.gust import check_outputs
from wingmdao.plots import save_figure
from wingmdao.stability import critical_speeds, eigenmodes, sweep
from wingmdao.stability.eigen import check_speeds
from wingmdao.timemarch.system import pack
from wingmdao.beam.static import BeamModel, beam_forcing
from wingmdao.stability.deformed import check_root_aoa, deformed_flutter
from wingmdao.stability.modal import dlm_flutter


#: --speeds N and --num-nodes upper bounds
MAX_SPEEDS = 1000
MAX_NODES = 200


def _states(num_nodes) -> int:
    """Size of the flutter eigenproblem: 22 states per node (462 for the 21-node Goland wing)."""
    return 22 * int(num_nodes)


def parse_speeds(values):
    """``(V0, V1, N)`` strings -> validated sweep; ValueError naming the input otherwise."""
    try:
        v0, v1, n = float(values[0]), float(values[1]), values[2]
        n = int(float(n)) if float(n) == int(float(n)) else None
    except (TypeError, ValueError):
        raise ValueError(f"--speeds = {' '.join(map(str, values))}; allowed V0 V1 N: two speeds (m/s) and an "
                         "integer N") from None
    if n is None or n < 2:
        raise ValueError(f"--speeds N = {values[2]}; allowed an integer in [2, {MAX_SPEEDS}]")
    if n > MAX_SPEEDS:
        raise ValueError(f"--speeds N = {values[2]}; allowed an integer in [2, {MAX_SPEEDS}] (one eigen-analysis "
                         f"per speed, ~1 s at 21 nodes, growing as nodes^3: {n} speeds ~{n / 60:.0f} min at 21 nodes)")
    if not (np.isfinite(v0) and np.isfinite(v1)) or v0 < 0.0:
        raise ValueError(f"--speeds V0 = {values[0]} m/s; allowed range [0, inf) m/s")
    if not v1 > v0:
        raise ValueError(f"--speeds V1 = {v1} m/s; allowed range (V0 = {v0}, inf) m/s (an increasing sweep)")
    return check_speeds(np.linspace(v0, v1, n))


def _value(x, unit) -> str:
    """A result value for human text: "none in the sweep" for a missing one (never a Python None)."""
    return "none in the sweep" if x is None else f"{x:.4g} {unit}"


def _clean(x):
    if isinstance(x, dict):
        return {k: _clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_clean(v) for v in x]
    if isinstance(x, np.ndarray):
        return _clean(x.tolist())
    if isinstance(x, (float, np.floating)):
        return None if not np.isfinite(x) else float(x)
    if isinstance(x, np.integer):
        return int(x)
    return x


def analyse(case, speeds=None, num_nodes=None, n_modes=4, thickness=None, aero_theory="strip") -> dict:
    """Run the flutter analysis; returns the JSON dict (``thickness``: PEGASUS walls per node, m)."""
    if case not in FLUTTER_CASES:
        raise ValueError(f"case {case!r} has no aerodynamic (flutter) data; allowed: {list(FLUTTER_CASES)}")
    if int(n_modes) < 1:
        raise ValueError(f"--modes = {n_modes}; allowed range >= 1")
    if num_nodes is not None and int(num_nodes) < 3:
        raise ValueError(f"--num-nodes = {num_nodes}; allowed range [3, {MAX_NODES}]")
    t0 = _time.perf_counter()
    prob = flutter_problem(case, num_nodes, thickness, aero_theory=aero_theory)
    v = prob.speeds if speeds is None else np.asarray(speeds, dtype=float)
    # in vacuo: the structural beam alone
    beam = BeamModel(prob.beam)
    n = beam.num_nodes
    vac = eigenmodes(beam.system, beam.p, pack(forcing_specs(n), beam_forcing(n)), beam.jig().ravel())
    osc = np.flatnonzero(vac.frequency > 1e-6)
    natural = np.sort(vac.frequency[osc])[:6]
    t1 = _time.perf_counter()
    res = sweep(prob.system, prob.params_at, v, n_track=int(n_modes), weights=prob.beam_weights(),
                **prob.eig_options)
    t2 = _time.perf_counter()
    if res.tracked.shape[1] < int(n_modes):
        warn(f"--modes {n_modes}: the {case} model has {res.tracked.shape[1]} oscillatory modes at the first speed; "
             f"tracking {res.tracked.shape[1]}")
    crit = critical_speeds(res)
    t3 = _time.perf_counter()
    return _clean({
        "case": case, "num_nodes": prob.num_nodes, "aero_theory": aero_theory, "density_kg_m3": prob.aero["density"],
        **({"dive_speed_m_s": prob.dive_speed} if prob.dive_speed is not None else {}),
        "flutter_speed_m_s": crit["flutter_speed"], "flutter_frequency_rad_s": crit["flutter_frequency"],
        "divergence_speed_m_s": crit["divergence_speed"],
        "natural_frequencies_rad_s": natural,
        "speeds": res.speeds, "damping": res.damping.T, "structural_damping": res.structural_damping.T,
        "frequency_rad_s": res.frequency.T,
        "published": prob.published,
        "timings_s": {"setup_and_in_vacuo": t1 - t0, "sweep": t2 - t1, "per_speed": (t2 - t1) / v.size,
                      "refinement": t3 - t2},
    })


def _flutter_json(r) -> dict:
    """JSON of a :class:`wingmdao.stability.pk.FlutterResult` (per mode and speed)."""
    return {"flutter_speed_m_s": r.flutter_speed, "flutter_frequency_rad_s": r.flutter_frequency,
            "flutter_mode": r.flutter_mode, "speeds": r.speeds, "structural_damping": r.damping.T,
            "frequency_rad_s": r.frequency.T}


def analyse_dlm(case, speeds=None, num_nodes=None, n_modes=4, thickness=None) -> dict:
    """Doublet-lattice flutter (p-k and state space, :func:`wingmdao.stability.modal.dlm_flutter`)
    beside strip theory's sweep of the same speeds; returns the JSON dict."""
    strip = analyse(case, speeds, num_nodes, n_modes, thickness, "strip")
    v = np.asarray(strip["speeds"], dtype=float)
    v = v[v > 0.0]
    t0 = _time.perf_counter()
    prob = flutter_problem(case, num_nodes, thickness)
    r = dlm_flutter(prob, v, n_modes=max(int(n_modes), 2))
    total = _time.perf_counter() - t0
    result = dict(strip)
    result.update({
        "aero_theory": "dlm",
        "flutter_speed_m_s": r.pk.flutter_speed, "flutter_frequency_rad_s": r.pk.flutter_frequency,
        "divergence_speed_m_s": None,
        "strip": {k: strip[k] for k in ("flutter_speed_m_s", "flutter_frequency_rad_s", "divergence_speed_m_s",
                                         "speeds", "structural_damping", "frequency_rad_s")},
        "dlm": {"pk": _flutter_json(r.pk), "state_space": _flutter_json(r.state_space),
                "rfa": {"form": "Roger", "lag_roots": r.rfa.lags, "fit_error": r.rfa.error,
                        "gust_fit_error": r.rfa.gust_error},
                "mach": r.mach, "reduced_frequencies": r.gaf.k, "reference_semichord_m": r.gaf.b_ref,
                "n_modes": r.modes.count, "modal_frequencies_rad_s": r.modes.frequencies,
                "timings_s": {**r.timings, "total": total}},
    })
    return _clean(result)


def plot_dlm(result, path):
    """Strip theory's V-g / V-f beside the doublet lattice's (p-k lines, state-space flutter point)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(11, 7), sharex=True, sharey="row")
    d = result["dlm"]
    panels = ((result["strip"], "strip theory (full beam, Wagner lags)", axes[:, 0]),
              (d["pk"], "doublet lattice, p-k (modal basis)", axes[:, 1]))
    for data, title, (ax1, ax2) in panels:
        v = np.asarray(data["speeds"], dtype=float)
        for j, (g, w) in enumerate(zip(data["structural_damping"], data["frequency_rad_s"])):
            g = np.array([np.nan if x is None else x for x in g], dtype=float)
            ax1.plot(v, g, "o-", ms=3, label=f"mode {j + 1}")
            ax2.plot(v, w, "o-", ms=3)
        vf = data["flutter_speed_m_s"]
        for ax in (ax1, ax2):
            if vf:
                ax.axvline(vf, color="r", ls="--", lw=0.8)
        ax1.axhline(0.0, color="k", lw=0.5)
        ax1.set_title(f"{title}: flutter {vf or float('nan'):.1f} m/s", fontsize=9)
        ax2.set_xlabel("airspeed (m/s)")
    vs = d["state_space"]["flutter_speed_m_s"]
    if vs:
        axes[0, 1].plot([vs], [0.0], "kx", ms=8, label=f"state space (Roger) {vs:.1f} m/s")
    axes[0, 0].set_ylabel("g = 2 Re / |Im|")
    axes[1, 0].set_ylabel("frequency (rad/s)")
    axes[0, 1].legend(fontsize=8)
    axes[0, 0].set_ylim(-0.6, 0.4)
    fig.suptitle(f"{result['case']}: V-g / V-f, strip theory and doublet lattice")
    fig.tight_layout()
    save_figure(fig, path, dpi=110)


DEFAULT_ROOT_AOA_DEG = (1.0, 2.0, 3.0)


def analyse_deformed(case, root_aoa_deg, speeds=None, num_nodes=21, n_modes=4, gravity=None) -> dict:
    """Flutter about the deformed state per root angle of attack; returns the JSON dict."""
    t0 = _time.perf_counter()
    prob = flutter_problem(case, int(num_nodes))
    if gravity is None:
        gravity = float(getattr(importlib.import_module(f"wingmdao.cases.{case}"), "GRAVITY", 0.0))
    rows = deformed_flutter(prob, root_aoa_deg, speeds, gravity=gravity, n_track=int(n_modes))
    out = {"gravity_m_s2": gravity, "cases": [{
        "root_aoa_deg": r.root_aoa_deg, "flutter_speed_m_s": r.flutter_speed,
        "flutter_frequency_rad_s": r.flutter_frequency, "tip_deflection_m": r.tip_deflection,
        "divergence_speed_m_s": r.divergence_speed, "static_failure_speed_m_s": r.static_failure_speed,
        "speeds": r.speeds, "tip_deflections_m": r.tip_deflections, "damping": r.damping.T,
        "frequency_rad_s": r.frequency.T} for r in rows],
        "time_s": _time.perf_counter() - t0}
    return _clean(out)


def plot_deformed(result, path):
    """Flutter speed and frequency vs static tip deflection at flutter (and the published curves)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [r for r in result["deformed"]["cases"] if r["flutter_speed_m_s"] is not None]
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    tip = [r["tip_deflection_m"] for r in rows]
    ax1.plot(tip, [r["flutter_speed_m_s"] for r in rows], "o-", label="wingmdao (root angle of attack)")
    ax2.plot(tip, [r["flutter_frequency_rad_s"] for r in rows], "o-")
    for r in rows:
        ax1.annotate(f"{r['root_aoa_deg']:g} deg", (r["tip_deflection_m"], r["flutter_speed_m_s"]), fontsize=7)
    pub = result.get("deformed_published")
    if pub:
        a = np.asarray(pub["speed_vs_root_aoa"]["root_aoa_deg"])
        t = np.interp(a, pub["tip_vs_root_aoa"]["root_aoa_deg"], pub["tip_vs_root_aoa"]["tip_deflection_m"])
        ax1.plot(t, pub["speed_vs_root_aoa"]["flutter_speed_m_s"], "k--", label="Patil et al. 2001 (root angle)")
        c = pub["speed_vs_tip_load_deflection"]
        ax1.plot(c["tip_deflection_m"], c["flutter_speed_m_s"], "k:", label="Patil et al. 2001 (tip load)")
        f = pub["frequency_vs_root_aoa"]
        ax2.plot(np.interp(f["root_aoa_deg"], pub["tip_vs_root_aoa"]["root_aoa_deg"],
                           pub["tip_vs_root_aoa"]["tip_deflection_m"]), f["flutter_frequency_rad_s"], "k--")
    ax1.set_ylabel("flutter speed (m/s)")
    ax1.legend(fontsize=8)
    ax2.set_ylabel("flutter frequency (rad/s)")
    ax2.set_xlabel("static tip deflection at flutter (m)")
    ax1.set_title(f"{result['case']}: flutter about the deformed state "
                  f"(g = {result['deformed']['gravity_m_s2']:g} m/s^2)")
    fig.tight_layout()
    _save_figure(fig, path)


def _save_figure(fig, path):
    save_figure(fig, path, dpi=110)


def plot(result, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    v = np.asarray(result["speeds"])
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    for j, (g, w) in enumerate(zip(result["structural_damping"], result["frequency_rad_s"])):
        g = np.array([np.nan if x is None else x for x in g], dtype=float)
        ax1.plot(v, g, "o-", ms=3, label=f"mode {j + 1}")
        ax2.plot(v, w, "o-", ms=3)
    for ax in (ax1, ax2):
        if result["flutter_speed_m_s"]:
            ax.axvline(result["flutter_speed_m_s"], color="r", ls="--", lw=0.8)
        if result["divergence_speed_m_s"]:
            ax.axvline(result["divergence_speed_m_s"], color="k", ls=":", lw=0.8)
    ax1.axhline(0.0, color="k", lw=0.5)
    ax1.set_ylabel("g = 2 Re / |Im|")
    ax1.legend(fontsize=8)
    ax2.set_ylabel("frequency (rad/s)")
    ax2.set_xlabel("airspeed (m/s)")
    ax1.set_title(f"{result['case']}: V-g / V-f (flutter {result['flutter_speed_m_s'] or float('nan'):.1f} m/s)")
    fig.tight_layout()

    save_figure(fig, path, dpi=110)


def check_deformed_args(args):
    """Validated root angles of attack (deg) for ``--deformed`` (None without it); ValueError otherwise."""
    if not args.deformed:
        if args.root_aoa_deg is not None or args.gravity is not None:
            raise ValueError("--root-aoa-deg and --gravity need --deformed")
        return None
    if args.gravity is not None and not (np.isfinite(args.gravity) and args.gravity >= 0.0):
        raise ValueError(f"--gravity = {args.gravity} m/s^2; allowed range [0, inf) m/s^2")
    try:
        return check_root_aoa(DEFAULT_ROOT_AOA_DEG if args.root_aoa_deg is None else args.root_aoa_deg)
    except ValueError as e:
        raise ValueError(f"--root-aoa-deg: {e}") from None


def run(args) -> int:
    # all input checks before any solve
    if args.case not in FLUTTER_CASES:
        raise ValueError(f"case {args.case!r} has no aerodynamic (flutter) data; allowed: {list(FLUTTER_CASES)}")
    speeds = parse_speeds(args.speeds) if args.speeds is not None else None
    if args.num_nodes is not None and not 3 <= args.num_nodes <= MAX_NODES:
        m = _states(args.num_nodes)
        cost = (f"; {args.num_nodes} nodes: an eigenproblem of {m} states, ~{m ** 2 * 16 * 4 / 1e9:.1f} GB dense, "
                f"~{(args.num_nodes / 21) ** 3:.0f} s per speed (21 nodes: ~1 s)" if args.num_nodes > MAX_NODES else "")
        raise ValueError(f"--num-nodes = {args.num_nodes}; allowed range [3, {MAX_NODES}]{cost}")
    if args.modes < 1:
        raise ValueError(f"--modes = {args.modes}; allowed range >= 1")

    plot_path = check_outputs(args, f"flutter_{args.case}.png")
    deformed_plot = None
    angles = check_deformed_args(args)
    if args.deformed:
        if args.case == "pegasus":
            raise ValueError("--deformed: the deformed-state sweep is set up for goland and hale, not pegasus")
        deformed_plot = check_outputs(args, f"flutter_{args.case}_deformed.png")
    thickness = None
    if args.design is not None:
        if args.case != "pegasus":
            raise ValueError(f"--design applies to the sized pegasus wing, not to case {args.case!r}")

        thickness = read_design(args.design, args.num_nodes or DEFAULT_NODES["pegasus"])
    if args.case == "pegasus" and speeds is not None:
        a = flight_point()["speed_of_sound"]
        if speeds[-1] >= a:
            raise ValueError(f"--speeds V1 = {speeds[-1]} m/s: pegasus flutter is subsonic (Mach = V / a, "
                             f"a = {a:.1f} m/s at 20 000 ft); allowed range V1 < {a:.1f} m/s")
    if args.deformed and args.aero_theory != "strip":
        raise ValueError(f"--deformed: the deformed-state sweep uses strip theory; drop --aero-theory {args.aero_theory}")
    if args.aero_theory == "dlm":
        result = analyse_dlm(args.case, speeds, args.num_nodes, args.modes, thickness)
        d = result["dlm"]
        print(f"{args.case} doublet lattice: p-k flutter {_value(d['pk']['flutter_speed_m_s'], 'm/s')} at "
              f"{_value(d['pk']['flutter_frequency_rad_s'], 'rad/s')}, state space "
              f"{_value(d['state_space']['flutter_speed_m_s'], 'm/s')} (Roger fit error "
              f"{100 * d['rfa']['fit_error']:.2f} %); strip theory {_value(result['strip']['flutter_speed_m_s'], 'm/s')}"
              f"; dlm flutter search {d['timings_s']['total']:.1f} s", file=sys.stderr)
    else:
        result = analyse(args.case, speeds, args.num_nodes, args.modes, thickness, args.aero_theory)
    if args.case == "pegasus":
        result["design"] = args.design or "initial"
    if args.deformed:
        result["deformed"] = analyse_deformed(args.case, angles, speeds, args.num_nodes or DEFAULT_NODES[args.case],
                                              args.modes, args.gravity)
        result["deformed_published"] = getattr(importlib.import_module(f"wingmdao.cases.{args.case}"),
                                               "PUBLISHED_DEFORMED", None)
        for r in result["deformed"]["cases"]:
            print(f"{args.case} deformed, root angle {r['root_aoa_deg']:g} deg: flutter "
                  f"{_value(r['flutter_speed_m_s'], 'm/s')} at {_value(r['flutter_frequency_rad_s'], 'rad/s')}, "
                  f"tip deflection {_value(r['tip_deflection_m'], 'm')}", file=sys.stderr)
    msg = (f"{args.case}: flutter {_value(result['flutter_speed_m_s'], 'm/s')} at "
           f"{_value(result['flutter_frequency_rad_s'], 'rad/s')}, "
           f"divergence {_value(result['divergence_speed_m_s'], 'm/s')}; in vacuo "
           + ", ".join(f"{w:.2f}" for w in result["natural_frequencies_rad_s"]) + " rad/s")
    print(msg, file=sys.stderr)
    write_json(result, args.json)  # the result first: a plotting failure must never lose it
    if plot_path:
        try:
            (plot_dlm if args.aero_theory == "dlm" else plot)(result, plot_path)
        except ImportError:
            warn("plot skipped (plots need matplotlib: pip install 'wingmdao[plot]'); the JSON is written")
        else:
            print(f"wrote {plot_path}", file=sys.stderr)
            result["plot"] = plot_path
            if deformed_plot:
                plot_deformed(result, deformed_plot)
                result["plot_deformed"] = deformed_plot
                print(f"wrote {deformed_plot}", file=sys.stderr)
            if args.json != "-":
                write_json(result, args.json)
    return 0
