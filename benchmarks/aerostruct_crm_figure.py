"""Figure of the uCRM fuel-burn optima (docs/embedding.md): skin thickness and twist along the span,
the wingmdao beam beside OpenAeroStruct's own, from the JSON of ``wingmdao size aerostruct-crm``.

    wingmdao size aerostruct-crm --json results/crm_as.json
    python benchmarks/aerostruct_crm_figure.py results/crm_as.json docs/figures/aerostruct_crm_optimum.png
"""

from __future__ import annotations

import argparse
import json

import numpy as np


def element_eta(num_y):
    """Spanwise position 2y/b of each OpenAeroStruct element midpoint (tip first)."""
    from wingmdao.oas.crm import crm_surface

    y = np.abs(crm_surface(num_y)["mesh"][0, :, 1])
    return 0.5 * (y[1:] + y[:-1]) / y.max()


def main(argv=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("json", help="JSON of wingmdao size aerostruct-crm (with oas_beam)")
    ap.add_argument("png", help="figure to write")
    a = ap.parse_args(argv)
    res = json.load(open(a.json))
    eta = element_eta(res["num_y"])
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 3.8))
    for r, label, style in ((res, "wingmdao beam + our KS", "o-"), (res["oas_beam"], "OpenAeroStruct beam + its KS", "s--")):
        ax1.plot(eta, 1e3 * np.array(r["skin_thickness_m"]), style, label=f"{label}: skin")
        ax1.plot(eta, 1e3 * np.array(r["spar_thickness_m"]), style, alpha=0.5, label=f"{label}: spar")
        cp = np.array(r["design"]["twist_cp_deg"])   # B-spline control points, tip first
        ax2.plot(np.linspace(1, 0, cp.size), cp, style, label=f"{label} ({r['fuelburn_kg']:.0f} kg fuel, "
                 f"{r['wing_mass_kg']:.0f} kg wing)")
    ax1.set(xlabel="2y/b", ylabel="thickness (mm)", title="wall thickness per element")
    ax2.set(xlabel="2y/b (control point)", ylabel="twist control point (deg)", title="twist")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(a.png, dpi=120)
    print(f"wrote {a.png}")


if __name__ == "__main__":
    main()
