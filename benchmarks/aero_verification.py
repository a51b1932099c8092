"""Figures of the unsteady strip-theory verification (docs/aeroelasticity.md).

Runs the checks of tests/test_aero.py, prints ours / reference / difference and writes
docs/figures/aero_indicial.png (Wagner and Kuessner step responses). About 20 s.
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))
import test_aero as T  # noqa: E402

from wingmdao.aero import kussner_sears_sparks, theodorsen_exact, theodorsen_jones, wagner_jones  # noqa: E402
from wingmdao.timemarch.system import layout  # noqa: E402


def indicial(kind):
    s, p, q, _ = T._wing(3)
    t = np.arange(401) * 0.0025
    Q = np.tile(q, (t.size, 1))
    ql = layout(s.forcing_specs)
    if kind == "wagner":
        Q[1:, ql["frame_velocity"].start + 2] = -1.0
        f = wagner_jones
    else:
        Q[1:, ql["gust_velocity"]] = 1.0
        f = kussner_sears_sparks
    L, _ = T._lift_history(s, t, p, Q)
    sv = T.V * t / 0.5
    ref = 0.5 * T.RHO * T.V ** 2 * 2 * np.pi / T.V
    return sv, L[:, 1] / ref, f(sv)


def main():
    rows = []
    curves = {}
    for kind in ("wagner", "kussner"):
        sv, ours, ref = indicial(kind)
        curves[kind] = (sv, ours, ref)
        m = sv >= 1.0
        rows.append((f"{kind} L/(q c a w0/V), max |rel diff| for s >= 1", np.nan, np.nan,
                     np.max(np.abs(ours[m] / ref[m] - 1))))
    for k in (0.1, 0.3, 0.5):
        rows.append((f"Jones C(k) vs exact, |C|, k = {k}", abs(theodorsen_jones(k)), abs(theodorsen_exact(k)),
                     abs(theodorsen_jones(k)) / abs(theodorsen_exact(k)) - 1))
    for r in rows:
        print(f"{r[0]:60s} ours {r[1]:.5g} ref {r[2]:.5g} diff {r[3]:+.4%}")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(6, 4))
    for kind, (sv, ours, ref) in curves.items():
        ax.plot(sv, ref, "-", label=f"{kind}: closed form")
        ax.plot(sv[::8], ours[::8], "o", ms=3, label=f"{kind}: beam + lag states (BDF2)")
    ax.set_xlabel("s = V t / b (semichords)")
    ax.set_ylabel("lift / quasi-steady lift")
    ax.legend()
    ax.grid(True)
    out = os.path.join(os.path.dirname(__file__), "..", "docs", "figures")
    os.makedirs(out, exist_ok=True)
    tmp = os.path.join(out, "aero_indicial.tmp.png")
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, os.path.join(out, "aero_indicial.png"))


if __name__ == "__main__":
    main()
