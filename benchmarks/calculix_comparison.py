"""Beam vs CalculiX shell and solid on the App. D.1 box: the tables of docs/verification-calculix.md.

Run: ``PYTHONPATH=. python benchmarks/calculix_comparison.py [PART ...]`` with PART among
shell, solid, stress, mesh, solid-mesh, ribs, rib-test1, pegasus (default: all; a few minutes; needs ccx).
"""

import sys

import numpy as np

from wingmdao.cli.verify import verify_args, verify_wing_box

LOADS = {"Fz = 1e5 N": ((0, 0, 1e5), (0, 0, 0)), "Fx = 1e5 N": ((1e5, 0, 0), (0, 0, 0)),
         "My = 1e5 N m": ((0, 0, 0), (0, 1e5, 0))}
GEOMS = ("prismatic", "taper", "sweep", "dihedral", "combined")
out = sys.stdout


def _args(g, F, M, fidelity="shell", **kw):
    a = verify_args(g, F, M, **{k: v for k, v in kw.items() if k != "through_elements"})
    a.fidelity = fidelity
    a.through_elements = kw.get("through_elements", 2)
    return a


def row(res, torque):
    if torque:
        b = np.array(res["station_rotation_beam"])[1:, 1]
        f = np.array(res["station_rotation_fe"])[1:, 1]
    else:
        b = np.array(res["displacement_beam"])[1:]
        f = np.array(res["displacement_fe"])[1:]
    return b, f, 100 * (b - f) / f


def table(fidelity):
    out.write(f"| geometry | load | quantity | CS2 beam | CS2 {fidelity} | CS3 beam | CS3 {fidelity} | CS4 beam | "
              f"CS4 {fidelity} | diff CS2 (%) | diff CS3 (%) | diff CS4 (%) |\n|" + "---|" * 12 + "\n")
    for g in GEOMS:
        for name, (F, M) in LOADS.items():
            res = verify_wing_box(_args(g, F, M, fidelity))
            tq = name.startswith("My")
            b, f, d = row(res, tq)
            vals = " | ".join(f"{x:.5e} | {y:.5e}" for x, y in zip(b, f))
            out.write(f"| {g} | {name} | {'theta_y (rad)' if tq else '|u| (m)'} | {vals} | "
                      + " | ".join(f"{x:+.2f}" for x in d) + " |\n")
            out.flush()


STRESS_POINTS = ("front-upper skin", "front-upper spar", "upper skin centre", "front spar centre", "rear spar centre")


def stress_table(fidelity="shell"):
    """von Mises beam vs FE (%) at the rows nearest y = 1.5, 5 and 8.5 m, and the largest
    |difference| in per cent of the row maximum over 1 m < y < 9 m."""
    out.write(f"\nvon Mises, beam vs {fidelity} (100 (beam - FE) / FE at y = 1.5 / 5 / 8.5 m; last column: "
              "max |beam - FE| / row max FE over 1 < y < 9 m, %):\n\n| geometry | load | "
              + " | ".join(STRESS_POINTS) + " | max of row max (%) |\n|" + "---|" * (3 + len(STRESS_POINTS)) + "\n")
    for g in GEOMS:
        for name, (F, M) in LOADS.items():
            vm = verify_wing_box(_args(g, F, M, fidelity))["von_mises"]
            y = np.array(vm["y"])
            rows = [int(np.argmin(abs(y - v))) for v in (1.5, 5.0, 8.5)]
            d = np.array(vm["difference_percent"])
            cells = [" / ".join(f"{d[r, vm['points'].index(p)]:+.1f}" for r in rows) for p in STRESS_POINTS]
            inner = (y > 1.0) & (y < 9.0)
            mx = np.abs(np.array(vm["difference_percent_of_row_max"])[inner]).max()
            out.write(f"| {g} | {name} | " + " | ".join(cells) + f" | {mx:.1f} |\n")
            out.flush()


def mesh_study(fidelity, meshes):
    out.write(f"\nMesh convergence ({fidelity}, prismatic):\n\n| load | mesh | elements | CS2 | CS4 | CS4 change "
              "vs finest (%) | ccx (s) |\n|---|---|---|---|---|---|---|\n")
    for name in ("Fz = 1e5 N", "My = 1e5 N m"):
        F, M = LOADS[name]
        tq = name.startswith("My")
        vals = []
        for mesh in meshes:
            nc, nh, s = mesh[:3]
            kw = {"through_elements": mesh[3]} if len(mesh) > 3 else {}
            res = verify_wing_box(_args("prismatic", F, M, fidelity, chord_elements=nc, height_elements=nh,
                                        span_size=s, **kw))
            v = np.array(res["station_rotation_fe"])[:, 1] if tq else np.array(res["displacement_fe"])
            vals.append((mesh, res["mesh"]["num_elements"], v, res["fe_time_s"]))
        for mesh, ne, v, t in vals:
            label = f"{mesh[0]} x {mesh[1]}" + (f" x {mesh[3]} through" if len(mesh) > 3 else "") + f", {mesh[2]} m"
            out.write(f"| {name} | {label} | {ne} | {v[1]:.6e} | {v[-1]:.6e} | "
                      f"{100 * (v[-1] / vals[-1][2][-1] - 1):+.3f} | {t:.1f} |\n")
        out.flush()


def ribs():
    out.write("\nRibs (prismatic; 0.1 m ribs; first 4 frequencies, Hz, and CS4 response):\n\n| ribs | f1..f4 shell "
              "| f1..f4 beam | CS4 |u| Fz (m) | CS4 theta_y My (rad) |\n|---|---|---|---|---|\n")
    for r in (None, 2.5, 1.0):
        r1 = verify_wing_box(verify_args("prismatic", (0, 0, 1e5), ribs=r, modes=4))
        r2 = verify_wing_box(verify_args("prismatic", (0, 0, 0), (0, 1e5, 0), ribs=r))
        out.write(f"| {'tip rib only' if r is None else f'every {r} m'} | "
                  f"{', '.join(f'{x:.3f}' for x in r1['frequencies_fe_hz'])} | "
                  f"{', '.join(f'{x:.3f}' for x in r1['frequencies_beam_hz'])} | {r1['displacement_fe'][-1]:.5e} | "
                  f"{r2['station_rotation_fe'][-1][1]:.5e} |\n")
        out.flush()


def rib_test1(geometry="prismatic", modes=6):
    """Sec. 4.3.1 Test 1: one rib at CS2 (solid slab), thickness 0 (no rib) to 0.5 m; change of the
    first frequencies against the rib-less box (C3D20R, no tip rib)."""
    from wingmdao.cli.verify import fe_material, wing_box_sections
    from wingmdao.fe.box_model import solve_modes
    from wingmdao.fe.solid_box import build_solid_box

    sec = wing_box_sections(geometry, 0.2, 0.1)
    out.write(f"\nSec. 4.3.1 Test 1 ({geometry}, C3D20R, one rib at CS2; frequencies Hz and change vs no rib, %):"
              f"\n\n| rib thickness (m) | " + " | ".join(f"f{k + 1}" for k in range(modes)) + " |\n|"
              + "---|" * (modes + 1) + "\n")
    base = None
    for t in np.round(np.arange(0.0, 0.501, 0.05), 3):
        model = build_solid_box(sec, fe_material(), ribs_y=[3.0] if t > 0 else [], rib_thickness=float(t) or 0.1)
        f = solve_modes(model, modes)["frequencies_hz"]
        base = f if base is None else base
        out.write(f"| {t:.2f} | " + " | ".join(f"{x:.3f} ({100 * (x / b - 1):+.1f})" for x, b in zip(f, base)) + " |\n")
        out.flush()


def pegasus(meshes=((4, 1, 1.0), (8, 2, 0.5), (16, 4, 0.25))):
    """PEGASUS at 1 g: beam vs shell with ribs at the 19 rib stations and without ribs (Test 2),
    tip displacement, tip twist, first frequencies; mesh convergence with ribs."""
    from wingmdao.cli._verify_pegasus import verify_pegasus, verify_pegasus_args

    out.write("\nPEGASUS 1 g (walls 4/4/5/4 mm, ribs 2 mm):\n\n| model | mesh | elements | tip |u| beam (m) | "
              "tip |u| FE (m) | diff (%) | tip twist beam (deg) | tip twist FE (deg) | f1..f4 FE (Hz) | "
              "f1..f4 beam (Hz) |\n|" + "---|" * 10 + "\n")
    for ribs in ("stations", None):
        for nc, nh, s in meshes:
            modes = 4 if (nc, nh, s) == (8, 2, 0.5) else 0
            r = verify_pegasus(verify_pegasus_args(ribs=ribs, chord_elements=nc, height_elements=nh, span_size=s,
                                                   modes=modes))
            fe = ", ".join(f"{x:.3f}" for x in r.get("frequencies_fe_hz", []))
            fb = ", ".join(f"{x:.3f}" for x in r.get("frequencies_beam_hz", []))
            out.write(f"| {'ribs at stations 1-19' if ribs else 'no ribs'} | {nc} x {nh}, {s} m | "
                      f"{r['mesh']['num_elements']} | {r['displacement_beam'][-1]:.5f} | {r['displacement_fe'][-1]:.5f} | "
                      f"{r['difference_percent'][-1]:+.2f} | {r['tip_twist_deg']['beam']:.3f} | "
                      f"{r['tip_twist_deg']['fe']:.3f} | {fe} | {fb} |\n")
            out.flush()


def pegasus_noribs_mesh(meshes=((4, 1, 1.0), (8, 2, 0.5), (12, 3, 0.25), (16, 4, 0.25), (24, 6, 0.125))):
    """Mesh refinement of the rib-less PEGASUS shell at 1 g: elements, tip |u|, tip twist, root
    von Mises (largest of the corner / mid-flange points of the first span row), wall time."""
    import time

    from wingmdao.cli._verify_pegasus import verify_pegasus, verify_pegasus_args

    out.write("\nPEGASUS 1 g, no ribs, shell mesh refinement:\n\n| mesh | elements | nodes | tip |u| FE (m) | "
              "tip twist FE (deg) | root von Mises FE (MPa) | wall (s) | ccx (s) |\n|" + "---|" * 8 + "\n")
    for nc, nh, s in meshes:
        t0 = time.perf_counter()
        r = verify_pegasus(verify_pegasus_args(ribs=None, chord_elements=nc, height_elements=nh, span_size=s))
        wall = time.perf_counter() - t0
        vm = max(r["von_mises"]["fe_pa"][0]) / 1e6
        out.write(f"| {nc} x {nh}, {s} m | {r['mesh']['num_elements']} | {r['mesh']['num_nodes']} | "
                  f"{r['displacement_fe'][-1]:.5f} | {r['tip_twist_deg']['fe']:.3f} | {vm:.2f} | {wall:.1f} | "
                  f"{r['fe_time_s']:.1f} |\n")
        out.flush()


PARTS = {"shell": lambda: table("shell"), "solid": lambda: table("solid"), "stress": stress_table,
         "mesh": lambda: mesh_study("shell", [(4, 1, 1.0), (8, 2, 0.5), (16, 4, 0.25), (24, 6, 0.125)]),
         "solid-mesh": lambda: mesh_study("solid", [(4, 1, 1.0, 1), (8, 2, 0.5, 2), (12, 3, 0.25, 2),
                                                    (16, 4, 0.25, 3)]),
         "ribs": ribs, "rib-test1": rib_test1, "pegasus": pegasus,
         "pegasus-noribs-mesh": pegasus_noribs_mesh}


def main(parts):
    bad = [p for p in parts if p not in PARTS]
    if bad:
        raise SystemExit(f"unknown part(s) {bad}; choose from {list(PARTS)}")
    for p in parts or PARTS:
        PARTS[p]()


if __name__ == "__main__":
    main(sys.argv[1:])
