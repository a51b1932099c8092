"""Expand design variables to beam stations: value at station i = design value map[i].

PEGASUS (Table 5.1) has 20 beam stations but 19 design stations per wall: the centre
wingbox (station 0) repeats the root rib's section (station 1).
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om


class StationMap(om.ExplicitComponent):
    """``<name>_station[i] = <name>[station_map[i]]`` for each name (a linear, sparse map)."""

    def initialize(self):
        self.options.declare("station_map", types=(np.ndarray, list, tuple), desc="(n_station,) int: design index of each station")
        self.options.declare("names", types=tuple, desc="variable names to expand")
        self.options.declare("units", default="m", types=str, desc="units of the variables and their expansions")

    def setup(self):
        smap = np.asarray(self.options["station_map"], dtype=int)
        n_dv = int(smap.max()) + 1
        if smap.min() < 0 or set(range(n_dv)) - set(smap.tolist()):
            raise ValueError(f"station_map must use every design index 0..{n_dv - 1} and no negative ones")
        self._map = smap
        for name in self.options["names"]:
            self.add_input(name, val=1.0, shape=(n_dv,), units=self.options["units"], desc=f"{name} design values")
            self.add_output(f"{name}_station", val=1.0, shape=(smap.size,), units=self.options["units"],
                            desc=f"{name} at every beam station")
            self.declare_partials(f"{name}_station", name, rows=np.arange(smap.size), cols=smap,
                                  val=np.ones(smap.size))

    def compute(self, inputs, outputs):
        for name in self.options["names"]:
            outputs[f"{name}_station"] = inputs[name][self._map]
