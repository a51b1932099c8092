"""wingmdao.loads: certification loads on the beam mesh (SI inside; see docs/loads.md).

* :mod:`~wingmdao.loads.atmosphere`: ISA 0-20 km, EAS/TAS.
* :mod:`~wingmdao.loads.maneuver`: 14 CFR 25.337 load factors, maneuver line loads.
* :mod:`~wingmdao.loads.distribution`: Schrenk / elliptic / user spanwise lift.
* :mod:`~wingmdao.loads.gust`: 14 CFR 25.341(a) 1 - cos gust, strip theory, Kussner lag.
* :mod:`~wingmdao.loads.files`: :class:`LoadHistory`, NPZ and CSV load-history files.
"""

from wingmdao.loads.files import LoadHistory, read_load_history, write_load_history
from wingmdao.loads.gust import design_gust, gust_gradients_ft, gust_line_loads
from wingmdao.loads.maneuver import LineLoads, limit_load_factors, maneuver_line_loads

__all__ = [
    "LineLoads",
    "LoadHistory",
    "design_gust",
    "gust_gradients_ft",
    "gust_line_loads",
    "limit_load_factors",
    "maneuver_line_loads",
    "read_load_history",
    "write_load_history",
]
