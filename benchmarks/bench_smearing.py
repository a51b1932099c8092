"""Stiffness matching of the Sec. 4.1.3 specimens 2-4 (Methods 1-3) and the Sec. 4.1.4 beam comparison.

Prints, per specimen and method, the equivalent/built-up ratio of the 4x4 diagonal and of the
cantilever tip displacement along each Table 4.8 load, and the run time.
Run: python benchmarks/bench_smearing.py [mesh_size_m]
"""

import sys
import time

import numpy as np

from wingmdao.section.fe import analyse_section
from wingmdao.section.smearing import (SPECIMENS, EquivalentPlate, beam_tip_displacements, builtup_stiffness,
                                       match_stiffness)


def main(mesh_size=0.005):
    print(f"mesh_size {mesh_size} m")
    print("spec meth  S11    S22    S33    S44  | d1     d2     d3   | objective  time_s  params (over E)")
    for spec in (2, 3, 4):
        st = SPECIMENS[spec]
        Sb, sec_b = builtup_stiffness(st, mesh_size=mesh_size)
        db = beam_tip_displacements(sec_b)
        eq = EquivalentPlate(st, mesh_size=mesh_size)
        print(f"  specimen {spec} built-up diag {np.diag(Sb)}, tip displacements (m) "
              f"{db[1][0]:.4e} {db[2][1]:.4e} {db[3][2]:.4e}")
        for method in (1, 2, 3):
            t0 = time.perf_counter()
            r = match_stiffness(st, method, eq, Sb)
            dt = time.perf_counter() - t0
            de = beam_tip_displacements(analyse_section(eq.section_mesh(r.params)))
            ratios = np.diag(r.stiffness) / np.diag(Sb)
            dr = [de[c][i] / db[c][i] for c, i in ((1, 0), (2, 1), (3, 2))]
            print(f"  {spec}   {method}   " + " ".join(f"{v:.4f}" for v in ratios) + " | "
                  + " ".join(f"{v:.4f}" for v in dr) + f" | {r.objective:.3e} {dt:6.1f}  "
                  + np.array2string(r.params, precision=3, max_line_width=400).replace("\n", " "))


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 0.005)
