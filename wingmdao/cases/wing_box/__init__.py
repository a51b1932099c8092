"""The 'wing-like' box beam of App. D.1 / E.3 and its sizing studies (Sec. 4.7.2).

* :mod:`.geometry`: Tables D.1, D.2, E.2 (``GEOMETRIES``, ``SPANS``, ``HEIGHTS``, ``T_SPAR``,
  ``T_SKIN``) and the section centres, defined once;
* :mod:`.verification`: plain beam solves (:func:`wing_box_beam`, :func:`solve_wing_box`,
  :func:`comparison_solver`) for the solid-model comparison;
* :mod:`.model`: the beam geometry and one tip-load case (:func:`wing_geometry`,
  :func:`tip_load_case`, :func:`time_grid`) of ``wingmdao run wing-box``;
* :mod:`.problem`: its OpenMDAO problem (``analysis_problem``, ``totals_max_rel_error``), imported
  from there (it loads OpenMDAO; the case's other modules do not);
* :mod:`.sizing`: the studies 1-3 of Sec. 4.7.2 (:class:`WingBoxOptions`, ``build``) for ``wingmdao size wing-box``.

The names below are re-exported, so ``from wingmdao.cases.wing_box import solve_wing_box`` works.
"""

from wingmdao.cases.wing_box.geometry import (GEOMETRIES, HEIGHTS, SPANS, STATIONS, T_SKIN, T_SPAR,
                                              geometry_data, section_centres)
from wingmdao.cases.wing_box.model import time_grid, tip_load_case, wing_geometry
from wingmdao.cases.wing_box.sizing import (BOUNDS, CONSTRAINT_GROUPS, SKIN_CAP, STUDY_LOADS, WingBoxOptions, build,
                                            parse_constraints)
from wingmdao.cases.wing_box.verification import (comparison_solver, solve_wing_box, station_rotations,
                                                  station_summary, wing_box_beam)
from wingmdao.names import CASE_HELP

NAME = "wing-box"
HELP = CASE_HELP[NAME]
OPTIONS = WingBoxOptions

__all__ = ["GEOMETRIES", "HEIGHTS", "SPANS", "STATIONS", "T_SKIN", "T_SPAR", "geometry_data", "section_centres",
           "time_grid", "tip_load_case", "wing_geometry",
           "BOUNDS", "CONSTRAINT_GROUPS", "SKIN_CAP", "STUDY_LOADS", "WingBoxOptions", "build",
           "parse_constraints", "comparison_solver", "solve_wing_box", "station_rotations", "station_summary",
           "wing_box_beam", "NAME", "HELP", "OPTIONS"]
