"""Corner axial stress of a solid rectangular section (Sec. 4.6.2, Eq. 4.40-4.42).

sigma = F_s / A - M_c n / I_cc + M_n c / I_nn at the four corners (c, n) = (+-w/2, +-h/2),
with I_cc = w h^3 / 12 (vertical bending, about the chordwise axis) and I_nn = h w^3 / 12.
The sign follows the beam's strain eps = eps0 + kappa_n c - kappa_c n (docs/section.md), so
a positive M_c (tip load up on a right wing) compresses the upper fibres. Eq. 4.40 is the
special case F_s = M_n = 0 at n = -h/2. Constraints (Eq. 4.42): g = +-sigma / sigma_y - 1.
"""

from __future__ import annotations

import numpy as np

from wingmdao.components.pointwise import PointwiseCasadiComponent, Var
from wingmdao import DISSERTATION
from wingmdao.components.stress import declare_stress_grid_options
import casadi as ca

#: corner order: (c, n) signs of (front-lower, rear-lower, rear-upper, front-upper)
CORNERS = ((-1, -1), (1, -1), (1, 1), (-1, 1))


class SolidRectStress(PointwiseCasadiComponent):
    """Corner axial stress constraints of solid rectangles over (n_time, n_station).

    Inputs ``F_csn``, ``M_csn`` (n_time, n_station, 3) in N, N*m; ``width``, ``height``
    (n_station,) m. Outputs ``g_ss_tension`` and ``g_ss_compression`` (n_time, n_station, 4).
    """

    @staticmethod
    def points_per_station(family: str) -> int:
        """Constraint points per station of stress family ``family`` (last axis of ``g_<family>``).

        Parameters
        ----------
        family : str
            Constraint family name.

        Returns
        -------
        int
            Points per station.
        """
        return 4

    def initialize(self):
        super().initialize()
        self.cite = DISSERTATION  # OpenMDAO lists it in its citations report
        declare_stress_grid_options(self.options)
        self.options.declare("families", default=("ss_tension", "ss_compression"), types=tuple,
                             desc="constraint families to output (ss_tension, ss_compression)")

    def point_grid(self):
        """Leading shape of every variable: (num_times, num_stations).

        Returns
        -------
        tuple
            The grid shape.
        """
        return (self.options["num_times"], self.options["num_stations"])

    def setup(self):
        bad = [f for f in self.options["families"] if f not in ("ss_tension", "ss_compression")]
        if bad:
            raise ValueError(f"SolidRectStress: unsupported families {bad}; valid: ss_tension, ss_compression")
        super().setup()

    def pointwise_inputs(self):
        """The per-point inputs: internal force and moment (csn) per time and station, section width and height per station.

        Returns
        -------
        list of Var
            The inputs.
        """
        return [
            Var("F_csn", (3,), "N", "internal force [F_c, F_s (axial), F_n] in the station csn frame", 0.0),
            Var("M_csn", (3,), "N*m", "internal moment [M_c, M_s (torsion), M_n] in the station csn frame", 0.0),
            Var("width", (), "m", "section width (chordwise)", per_last_axis=True),
            Var("height", (), "m", "section height (normal)", per_last_axis=True),
        ]

    def pointwise_outputs(self):
        """The per-point outputs: the corner constraints ``g_<family>``.

        Returns
        -------
        list of Var
            The outputs.
        """
        return [Var(f"g_{f}", (4,), None, f"{f} corner constraint sigma/sigma_y - 1 (Eq. 4.42)")
                for f in self.options["families"]]

    def pointwise_expressions(self, sym):
        """The outputs at one point as CasADi expressions: the corner stress constraints (Eq. 4.42).

        Parameters
        ----------
        sym : dict
            Input name -> SX symbol of the input's shape at one point.

        Returns
        -------
        dict
            Output name -> SX expression.
        """
        w, h = sym["width"], sym["height"]
        f, m = sym["F_csn"], sym["M_csn"]
        area, i_cc, i_nn = w * h, w * h**3 / 12.0, h * w**3 / 12.0
        sig = [f[1] / area - m[0] * (sn * h / 2) / i_cc + m[2] * (sc * w / 2) / i_nn for sc, sn in CORNERS]
        sig = ca.vertcat(*sig)
        sy = self.options["material"].sigma_y
        out = {"g_ss_tension": sig / sy - 1.0, "g_ss_compression": -sig / sy - 1.0}
        return {f"g_{k}": out[f"g_{k}"] for k in self.options["families"]}

    def check_inputs(self, inputs):
        """Raise ``ValueError`` naming the input, point and allowed range when a width or height is not finite and positive.

        Parameters
        ----------
        inputs : dict-like
            The component's inputs.
        """
        for name in ("width", "height"):
            v = np.asarray(inputs[name])
            bad = np.flatnonzero(~(np.isfinite(v) & (v > 0)))
            if bad.size:
                raise ValueError(f"SolidRectStress: {name}[{bad[0]}] = {v[bad[0]]} m at station {bad[0]}; "
                                 "allowed range (0, inf) m")
