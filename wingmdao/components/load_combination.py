"""The two wings of an antisymmetric load case combined with a symmetric static one.

A rolling condition of 14 CFR 25.349(a) is marched on the antisymmetric half wing: its internal
loads are increments ``Δ(t)`` of the right wing; the left wing's are ``−Δ(t)`` (mirrored). In
combination with a symmetric flight state (the static loads ``S`` of 2/3 n_lim) the right wing
carries ``S + Δ(t)`` and the left ``S − Δ(t)``. The stress recovery is linear in the station
internal loads for a given design, so superposing the loads superposes the stresses
(docs/maneuvers.md, "Rolling conditions").
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om


class SymmetricLoadCombination(om.ExplicitComponent):
    """``F_csn``, ``M_csn`` (2 nt, n, 3): rows ``[0, nt)`` = ``symmetric_*`` (1, n, 3) + the
    increment ``increment_*`` (nt, n, 3) at every instant (the right wing), rows ``[nt, 2 nt)``
    = symmetric − increment (the left wing).

    Parameters
    ----------
    **kwargs : dict
        OpenMDAO options: ``num_times`` (instants of the increment), ``num_nodes`` (stations).
    """

    def initialize(self):
        self.options.declare("num_times", types=int, lower=1, desc="number of time instants of the increment")
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes")

    def setup(self):
        nt, n = self.options["num_times"], self.options["num_nodes"]
        size = nt * n * 3
        rows = np.arange(2 * size)
        sym_cols = np.tile(np.arange(n * 3), 2 * nt)
        inc_cols = np.tile(np.arange(size), 2)
        inc_val = np.concatenate([np.ones(size), -np.ones(size)])
        for k, units, what in (("F_csn", "N", "internal force"), ("M_csn", "N*m", "internal moment")):
            self.add_input(f"symmetric_{k}", shape=(1, n, 3), units=units, desc=f"symmetric static {what}, csn")
            self.add_input(f"increment_{k}", shape=(nt, n, 3), units=units,
                           desc=f"antisymmetric increment of the {what} (right wing), csn")
            self.add_output(k, shape=(2 * nt, n, 3), units=units,
                            desc=f"{what}, csn: symmetric + increment (right wing), then symmetric - increment (left)")
            self.declare_partials(k, f"symmetric_{k}", rows=rows, cols=sym_cols, val=1.0)
            self.declare_partials(k, f"increment_{k}", rows=rows, cols=inc_cols, val=inc_val)

    def compute(self, inputs, outputs):
        for k in ("F_csn", "M_csn"):
            s, d = inputs[f"symmetric_{k}"], inputs[f"increment_{k}"]
            outputs[k] = np.concatenate([s + d, s - d], axis=0)
