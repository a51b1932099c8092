"""Run the App. D.1 'wing-like' box (the data and builders live in ``wingmdao.cases.wing_box``).

Usage: ``python cases/wing_box.py combined`` prints the static response to a 100 kN tip load;
``python cases/wing_box.py size 1`` sizes study 1 of Sec. 4.7.2 (``2``, ``3`` likewise).
The names of the package module are re-exported here for scripts that load this file by path.
"""

from __future__ import annotations

import sys

from wingmdao.cases.wing_box import *  # noqa: F401,F403  (re-export for path-loaded scripts)
from wingmdao.cases.wing_box import (GEOMETRIES, STATIONS, comparison_solver, geometry_data,  # noqa: F401
                                     section_centres, solve_wing_box, station_rotations, wing_box_beam)


def run_problem(study: int = 1, **overrides) -> dict:
    """Size one Sec. 4.7.2 study with the case defaults (plus ``overrides``); returns the summary."""
    from wingmdao.cases.wing_box import build
    from wingmdao.sizing import size_case

    setup = build(study=study, **overrides)
    _, result = size_case(setup)
    return result


if __name__ == "__main__":
    if len(sys.argv) > 2 and sys.argv[1] == "size":
        print(run_problem(int(sys.argv[2])))
    else:
        name = sys.argv[1] if len(sys.argv) > 1 else "combined"
        print(solve_wing_box(name, tip_force=(0.0, 0.0, 1.0e5)))
