"""Internal loads of the beam in the local csn frames, for stress recovery.

At every time and node: ``F_csn = T(theta) F`` and ``M_csn = T(theta) M`` (Eq. A.1), with F, M
the body-axes resultants of the beam state (the outboard part acting on the inboard part,
docs/conventions.md). Components: force [F_c shear, F_s axial, F_n shear], moment [M_c bending,
M_s torsion, M_n bending]. The component is pointwise over the (n_time, n_node) grid, so its
partials are exact and block diagonal (CasADi AD via PointwiseCasadiComponent).
"""

from __future__ import annotations

import numpy as np

from wingmdao.beam.rotations import body_to_csn
from wingmdao.components.pointwise import PointwiseCasadiComponent, Var
from wingmdao import DISSERTATION


class BeamInternalLoads(PointwiseCasadiComponent):
    """``states`` (nt, n, 18) -> ``F_csn``, ``M_csn`` (nt, n, 3).

    Options: ``num_times``, ``num_nodes``, ``euler_sequence`` (default 'surface').
    """

    def initialize(self):
        super().initialize()
        self.cite = DISSERTATION  # OpenMDAO lists it in its citations report
        self.options.declare("num_times", types=int, lower=1, desc="number of time instants")
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes")
        self.options.declare("euler_sequence", default="surface", types=str, desc="Euler sequence of the beam")

    def point_grid(self):
        """Leading shape of every variable: (num_times, num_nodes).

        Returns
        -------
        tuple
            The grid shape.
        """
        return (self.options["num_times"], self.options["num_nodes"])

    def setup(self):
        super().setup()

    def expression_options(self):
        """The expressions depend on the Euler sequence (persisted, wingmdao.utils.function_store)."""
        return (self.options["euler_sequence"],)

    def pointwise_inputs(self):
        """The per-point inputs: the 18 beam states of a node at a time.

        Returns
        -------
        list of Var
            The inputs.
        """
        return [Var("states", (18,), None, "beam state r, theta, F, M, u, omega (body axes; SI)", 0.0)]

    def pointwise_outputs(self):
        """The per-point outputs: internal force and moment in the node's csn frame.

        Returns
        -------
        list of Var
            The outputs.
        """
        return [Var("F_csn", (3,), "N", "internal force [F_c, F_s axial, F_n] in the local csn frame"),
                Var("M_csn", (3,), "N*m", "internal moment [M_c, M_s torsion, M_n] in the local csn frame")]

    def pointwise_expressions(self, sym):
        """The outputs at one point as CasADi expressions: the states' F and M rotated into the jig csn frame.

        Parameters
        ----------
        sym : dict
            Input name -> SX symbol of the input's shape at one point.

        Returns
        -------
        dict
            Output name -> SX expression.
        """
        x = sym["states"]
        T = body_to_csn(x[3:6], self.options["euler_sequence"])
        return {"F_csn": T @ x[6:9], "M_csn": T @ x[9:12]}

    def check_inputs(self, inputs):
        """Raise ``ValueError`` naming the input, point and allowed range when a state is not finite.

        Parameters
        ----------
        inputs : dict-like
            The component's inputs.
        """
        x = np.asarray(inputs["states"])
        bad = ~np.isfinite(x)
        if np.any(bad):
            t, i, k = np.argwhere(bad)[0]
            raise ValueError(f"states must be finite; time index {t}, node {i}, state {k} is {x[t, i, k]}")
