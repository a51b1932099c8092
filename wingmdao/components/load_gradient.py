"""Spanwise gradient of the beam's internal force, for the skins' transverse running load.

The skin panels of the stiffened box (:class:`~wingmdao.components.panels.PanelFailure`) need
dF/ds, the rate at which the internal force changes along the span (the net load per length on
the box): it sets the chordwise running load of the skins between the spars
(:func:`wingmdao.stress.box_stress.panel_running_loads`, docs/panels.md).
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om


def _neighbours(n):
    """(lo, hi) node indices of the difference at each node: central inside, one-sided at the ends."""
    i = np.arange(n)
    return np.maximum(i - 1, 0), np.minimum(i + 1, n - 1)


def force_gradient(force, node_positions):
    """dF/ds at every node (N/m) of the nodal internal forces ``force`` (..., n, 3): the central
    difference (F_{i+1} - F_{i-1}) / |r_{i+1} - r_{i-1}| inside, one-sided at the two end nodes.
    On a beam whose nodal forces differ by the nodal loads, this is the net load per length
    averaged over the two bays beside the node.

    Parameters
    ----------
    force : array_like
        (..., n, 3) nodal internal forces (N).
    node_positions : array_like
        (n, 3) node positions (m).

    Returns
    -------
    numpy.ndarray or casadi.SX
        (..., n, 3) dF/ds (N/m).
    """
    r = np.asarray(node_positions, dtype=float)
    lo, hi = _neighbours(r.shape[0])
    dist = np.linalg.norm(r[hi] - r[lo], axis=1)
    f = np.asarray(force, dtype=float)
    return (f[..., hi, :] - f[..., lo, :]) / dist[:, None]


class InternalForceGradient(om.ExplicitComponent):
    """``F_csn`` (nt, n, 3) N and ``node_positions`` (n, 3) m -> ``dF_csn_ds`` (nt, n, 3) N/m,
    :func:`force_gradient` (the station frames' rotation between neighbouring nodes is
    neglected: the components are differenced as they are). Exact analytic sparse partials."""

    def initialize(self):
        self.options.declare("num_times", types=int, lower=1, desc="number of time steps")
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes")

    def setup(self):
        nt, n = self.options["num_times"], self.options["num_nodes"]
        self.add_input("F_csn", val=0.0, shape=(nt, n, 3), units="N",
                       desc="internal force [F_c, F_s, F_n] on the inboard part, csn")
        self.add_input("node_positions", val=np.zeros((n, 3)), units="m", desc="beam node positions, root first")
        self.add_output("dF_csn_ds", val=0.0, shape=(nt, n, 3), units="N/m",
                        desc="spanwise derivative of F_csn (net load per length on the box)")
        lo, hi = _neighbours(n)
        out = np.arange(nt * n * 3).reshape(nt, n, 3)
        t, i, k = np.meshgrid(np.arange(nt), np.arange(n), np.arange(3), indexing="ij")
        col_hi = (t * n + hi[i]) * 3 + k
        col_lo = (t * n + lo[i]) * 3 + k
        self._f_rows = np.concatenate([out.ravel(), out.ravel()])
        self._f_cols = np.concatenate([col_hi.ravel(), col_lo.ravel()])
        self.declare_partials("dF_csn_ds", "F_csn", rows=self._f_rows, cols=self._f_cols)
        # d out[t, i, k] / d r[hi_i, m] and r[lo_i, m]: (nt, n, 3, 3) each
        rows = np.broadcast_to(out[..., None], (nt, n, 3, 3))
        m = np.arange(3)
        c_hi = np.broadcast_to(3 * hi[None, :, None, None] + m, (nt, n, 3, 3))
        c_lo = np.broadcast_to(3 * lo[None, :, None, None] + m, (nt, n, 3, 3))
        self.declare_partials("dF_csn_ds", "node_positions", rows=np.concatenate([rows.ravel(), rows.ravel()]),
                              cols=np.concatenate([c_hi.ravel(), c_lo.ravel()]))

    def _geometry(self, inputs):
        r = np.asarray(inputs["node_positions"])
        lo, hi = _neighbours(r.shape[0])
        dr = r[hi] - r[lo]
        dist = np.sqrt(np.sum(dr * dr, axis=1))       # complex-step safe (no abs)
        if np.any(~np.isfinite(dist) | (dist.real <= 0.0)):
            i = int(np.flatnonzero(~(dist.real > 0.0))[0])
            raise ValueError(f"{self.msginfo}: node_positions: nodes {lo[i]} and {hi[i]} coincide; "
                             "the beam nodes must be distinct")
        return lo, hi, dr, dist

    def compute(self, inputs, outputs):
        lo, hi, _, dist = self._geometry(inputs)
        f = inputs["F_csn"]
        outputs["dF_csn_ds"] = (f[:, hi, :] - f[:, lo, :]) / dist[None, :, None]

    def compute_partials(self, inputs, partials):
        nt = self.options["num_times"]
        lo, hi, dr, dist = self._geometry(inputs)
        inv = np.broadcast_to((1.0 / dist)[None, :, None], (nt, dist.size, 3)).ravel()
        partials["dF_csn_ds", "F_csn"] = np.concatenate([inv, -inv])
        f = inputs["F_csn"]
        df = f[:, hi, :] - f[:, lo, :]                                   # (nt, n, 3)
        # d (df_k / d) / d r_hi,m = -df_k dr_m / d^3; r_lo: the opposite sign
        d_hi = -df[..., None] * (dr / dist[:, None] ** 3)[None, :, None, :]
        partials["dF_csn_ds", "node_positions"] = np.concatenate([d_hi.ravel(), -d_hi.ravel()])
