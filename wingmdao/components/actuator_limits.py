"""``ActuatorLimitKS``: the control surfaces' deflection and rate limits over a gust march, as one KS.

The actuator states of a surface are its deflection beta (rad) and rate r = dbeta/dt (rad/s)
(:func:`wingmdao.aero.controls.actuator_residuals`). Over every instant t and surface s the
constraint aggregates both signs of both ratios,

    actuator_ks = KS( +-beta_s(t) / beta_max,s,  +-r_s(t) / r_max,s ) <= 1,

with the one KS of :mod:`wingmdao.utils.ks` (max g <= KS <= max g + ln(4 n_t n_s) / rho, so the
constraint keeps the peaks below their limits). The ratio is smooth in the states (the two signs
replace |.|); the partials are the KS weights on the selected state columns (sparse, exact); the
totals through the state history come from the march's discrete adjoint (docs/controls.md).
"""

from __future__ import annotations

import numbers

import numpy as np
import openmdao.api as om

from wingmdao.utils.ks import ks_aggregate


class ActuatorLimitKS(om.ExplicitComponent):
    """Input ``states`` (n_time, \\*state_shape), the state history of a march with control surfaces;
    output ``actuator_ks``: KS over time and surfaces of +-deflection / max_deflection and +-rate /
    max_rate (dimensionless, <= 1 within the limits)."""

    def initialize(self):
        self.options.declare("num_times", types=int, lower=1, desc="number of time instants")
        self.options.declare("state_shape", types=tuple, desc="state shape of the system per instant")
        self.options.declare("deflection_index", types=np.ndarray,
                             desc="(n_s,) flat state index of each surface's deflection (rad)")
        self.options.declare("rate_index", types=np.ndarray,
                             desc="(n_s,) flat state index of each surface's deflection rate (rad/s)")
        self.options.declare("max_deflection", types=np.ndarray, desc="(n_s,) deflection limits (rad), > 0")
        self.options.declare("max_rate", types=np.ndarray, desc="(n_s,) rate limits (rad/s), > 0")
        self.options.declare("rho_ks", default=100.0, lower=0.0, types=numbers.Real,
                             desc="KS aggregation parameter (on the dimensionless ratios)")

    def setup(self):
        nt = self.options["num_times"]
        shape = tuple(self.options["state_shape"])
        size = int(np.prod(shape))
        di = np.asarray(self.options["deflection_index"], dtype=int).ravel()
        ri = np.asarray(self.options["rate_index"], dtype=int).ravel()
        lim_d = np.asarray(self.options["max_deflection"], dtype=float).ravel()
        lim_r = np.asarray(self.options["max_rate"], dtype=float).ravel()
        if not (di.size == ri.size == lim_d.size == lim_r.size and di.size > 0):
            raise ValueError("ActuatorLimitKS: deflection_index, rate_index, max_deflection and max_rate need one "
                             f"entry per surface; got {di.size}, {ri.size}, {lim_d.size}, {lim_r.size}")
        if np.any(~np.isfinite(np.r_[lim_d, lim_r])) or np.any(np.r_[lim_d, lim_r] <= 0.0):
            raise ValueError(f"ActuatorLimitKS: limits {lim_d.tolist()} rad, {lim_r.tolist()} rad/s; allowed range (0, inf)")
        cols = np.r_[di, ri]
        if cols.min() < 0 or cols.max() >= size:
            raise ValueError(f"ActuatorLimitKS: state indices {cols.tolist()} outside [0, {size})")
        self._cols, self._scale, self._nt, self._size = cols, 1.0 / np.r_[lim_d, lim_r], nt, size
        self.add_input("states", shape=(nt,) + shape, desc="state history (n_time first) with the actuator states")
        self.add_output("actuator_ks", val=0.0,
                        desc="KS over time and surfaces of +-deflection/max_deflection and +-rate/max_rate (<= 1)")
        self.declare_partials("actuator_ks", "states", rows=np.zeros(nt * cols.size, int),
                              cols=(np.arange(nt)[:, None] * size + cols[None, :]).ravel())

    def ratios(self, states) -> np.ndarray:
        """(n_time, 2 n_s) signed ratios: deflection / max_deflection per surface, then rate / max_rate.

        Parameters
        ----------
        states : array_like
            The state history (n_time, \\*state_shape).

        Returns
        -------
        numpy.ndarray
            The ratios (dimensionless).
        """
        flat = np.asarray(states, dtype=float).reshape(self._nt, self._size)
        return flat[:, self._cols] * self._scale[None, :]

    def compute(self, inputs, outputs):
        r = self.ratios(inputs["states"])
        outputs["actuator_ks"] = ks_aggregate(np.stack([r, -r]), self.options["rho_ks"])[0]

    def compute_partials(self, inputs, partials):
        r = self.ratios(inputs["states"])
        _, w = ks_aggregate(np.stack([r, -r]), self.options["rho_ks"])
        w = w.reshape(2, *r.shape)
        partials["actuator_ks", "states"] = ((w[0] - w[1]) * self._scale[None, :]).ravel()
