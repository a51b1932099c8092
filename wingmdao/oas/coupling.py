"""The wingmdao nonlinear beam as OpenAeroStruct's structural solver.

OpenAeroStruct (Jasa et al., "Open-source coupled aerostructural optimization using Python",
Structural and Multidisciplinary Optimization 57, 2018; Chauhan and Martins, "Low-fidelity
aerostructural optimization of aircraft wings with a simplified wingbox model using
OpenAeroStruct", EngOpt 2018) models a symmetric wing by its *left* half: FEM nodes (ny, 3)
from the tip (index 0, y = -b/2) to the root (index ny - 1, y = 0), x aft, z up; its structural
solver reads ``loads`` (ny, 6: Fx, Fy, Fz, Mx, My, Mz at the nodes, N and N*m) and returns
``disp`` (ny, 6: translations m and small rotations rad). wingmdao models the *right* wing,
root first, y outboard. The maps here are the reflection M = diag(1, -1, 1) plus the reversal
of the node order:

    node k of the beam  <->  node ny - 1 - k of OpenAeroStruct
    force, translation (polar vectors):  (a_x, a_y, a_z) -> (a_x, -a_y, a_z)
    moment, rotation (axial vectors, det M = -1):  (b_x, b_y, b_z) -> (-b_x, b_y, -b_z)

The beam's rotation output is the small body-axes rotation vector linearised about the jig,
``A(theta0) (theta - theta0)`` with ``A = T^T K`` (App. A, Eq. A.1, A.3 of "Structural analysis
and optimization of aircraft wings through dimensional reduction", PhD dissertation, Georgia
Institute of Technology, 2021).

Wingbox thicknesses: OpenAeroStruct's ``spar_thickness`` and ``skin_thickness`` are per element
(ny - 1); the box walls of wingmdao are per node: upper = lower skin = skin thickness, front =
rear spar = spar thickness, each node the mean of its adjacent elements (the end nodes take
their element's value).
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om
from wingmdao.materials import Material
from wingmdao.section.box import WALL_NAMES
from wingmdao.components.beam import BeamStatic
from wingmdao.components.section import BoxSection
from wingmdao.groups.wing import SECTION_OFFSETS, add_section_offsets

POLAR = np.array([1.0, -1.0, 1.0])
AXIAL = np.array([-1.0, 1.0, -1.0])


def oas_order(n: int) -> np.ndarray:
    """OpenAeroStruct node index of each beam node (root first): ny - 1 - k.

    Parameters
    ----------
    n : int
        Number of beam nodes.

    Returns
    -------
    numpy.ndarray
        (n,) OpenAeroStruct node indices.
    """
    return np.arange(n)[::-1].copy()


def element_to_node_matrix(n: int) -> np.ndarray:
    """(n, n-1) averaging matrix: node value = mean of its adjacent element values.

    Parameters
    ----------
    n : int
        Number of nodes.

    Returns
    -------
    numpy.ndarray
        (n, n - 1) averaging matrix.
    """
    W = np.zeros((n, n - 1))
    for k in range(n):
        adj = [e for e in (k - 1, k) if 0 <= e < n - 1]
        W[k, adj] = 1.0 / len(adj)
    return W


class OASToBeamLoads(om.ExplicitComponent):
    """OpenAeroStruct ``loads`` (ny, 6), left wing tip first -> ``point_force``, ``point_moment``
    (ny, 3), right wing root first. Linear (signed permutation), constant partials."""

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=2, desc="ny, number of FEM nodes")

    def setup(self):
        n = self.options["num_nodes"]
        self.add_input("loads", shape_by_conn=False, shape=(n, 6), units="N",
                       desc="OpenAeroStruct nodal forces (N) and moments (N*m), left half-wing, tip first")
        self.add_output("point_force", shape=(n, 3), units="N", desc="beam nodal forces, right wing, root first")
        self.add_output("point_moment", shape=(n, 3), units="N*m", desc="beam nodal moments, right wing, root first")
        src = oas_order(n)
        rows = np.arange(3 * n)
        cols = (6 * src[:, None] + np.arange(3)).ravel()
        self.declare_partials("point_force", "loads", rows=rows, cols=cols, val=np.tile(POLAR, n))
        self.declare_partials("point_moment", "loads", rows=rows, cols=cols + 3, val=np.tile(AXIAL, n))

    def compute(self, inputs, outputs):
        L = np.asarray(inputs["loads"])[oas_order(self.options["num_nodes"])]
        outputs["point_force"] = L[:, :3] * POLAR
        outputs["point_moment"] = L[:, 3:] * AXIAL


class BeamToOASDisp(om.ExplicitComponent):
    """Beam ``wingmdao_states`` (ny, 18) -> OpenAeroStruct ``disp`` (ny, 6), tip first, left wing:
    translations r - r0, rotations A(theta0)(theta - theta0), reflected and reversed. Linear."""

    def initialize(self):
        self.options.declare("node_positions", types=(np.ndarray, list, tuple), desc="(ny, 3) jig beam nodes, right wing root first, m")
        self.options.declare("node_euler_angles", types=(np.ndarray, list, tuple), desc="(ny, 3) jig Euler angles, rad")

    def setup(self):
        from wingmdao.mphys.builder import rotation_vector_map

        x0 = np.asarray(self.options["node_positions"], dtype=float)
        th0 = np.asarray(self.options["node_euler_angles"], dtype=float)
        n = x0.shape[0]
        self._A = rotation_vector_map(th0)
        self.add_input("wingmdao_states", shape=(n, 18), units=None,
                       desc="beam state r, theta, F, M, u, omega per node (SI)")
        self.add_output("disp", shape=(n, 6), units="m",
                        desc="OpenAeroStruct nodal displacements (m) and rotations (rad), tip first")
        src = oas_order(n)   # beam node feeding OAS node j is src[j]
        j = np.arange(n)
        rows_u = (6 * j[:, None] + np.arange(3)).ravel()
        cols_u = (18 * src[:, None] + np.arange(3)).ravel()
        rows_t = np.repeat((6 * j[:, None] + 3 + np.arange(3)).ravel(), 3)
        cols_t = np.broadcast_to(18 * src[:, None, None] + 3 + np.arange(3)[None, None, :], (n, 3, 3)).ravel()
        vals_t = (AXIAL[None, :, None] * self._A[src]).ravel()
        self.declare_partials("disp", "wingmdao_states", rows=np.concatenate([rows_u, rows_t]),
                              cols=np.concatenate([cols_u, cols_t]),
                              val=np.concatenate([np.tile(POLAR, n), vals_t]))

    def compute(self, inputs, outputs):
        x0 = np.asarray(self.options["node_positions"], dtype=float)
        th0 = np.asarray(self.options["node_euler_angles"], dtype=float)
        X = np.asarray(inputs["wingmdao_states"])
        src = oas_order(x0.shape[0])
        d = np.zeros((x0.shape[0], 6), dtype=X.dtype)
        d[:, :3] = (X[src, :3] - x0[src]) * POLAR
        d[:, 3:] = np.einsum("nij,nj->ni", self._A[src], X[src, 3:6] - th0[src]) * AXIAL
        outputs["disp"] = d


class OASThicknessToBox(om.ExplicitComponent):
    """``spar_thickness``, ``skin_thickness`` (ny - 1, OpenAeroStruct element order, tip first) ->
    ``t_upper_skin``, ``t_lower_skin``, ``t_front_spar``, ``t_rear_spar`` (ny, beam order). Linear."""

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=2, desc="ny, number of FEM nodes")

    def setup(self):
        n = self.options["num_nodes"]
        # OAS element e (tip first) is beam element n - 2 - e
        W = element_to_node_matrix(n)[:, ::-1]
        self._W = W
        rows, cols = np.nonzero(W)
        for name in ("spar_thickness", "skin_thickness"):
            self.add_input(name, val=0.01, shape=n - 1, units="m", desc=f"OpenAeroStruct {name} per element")
        for out, src in (("t_upper_skin", "skin_thickness"), ("t_lower_skin", "skin_thickness"),
                         ("t_front_spar", "spar_thickness"), ("t_rear_spar", "spar_thickness")):
            self.add_output(out, shape=n, units="m", desc=f"{out.replace('_', ' ')} per beam node")
            self.declare_partials(out, src, rows=rows, cols=cols, val=W[rows, cols])

    def compute(self, inputs, outputs):
        for name in ("spar_thickness", "skin_thickness"):
            t = np.asarray(inputs[name])
            bad = np.flatnonzero(~(t > 0.0))
            if bad.size:
                raise ValueError(f"{self.pathname}: {name}[{bad[0]}] = {t[bad[0]]} m; allowed range (0, inf) m")
        outputs["t_upper_skin"] = outputs["t_lower_skin"] = self._W @ inputs["skin_thickness"]
        outputs["t_front_spar"] = outputs["t_rear_spar"] = self._W @ inputs["spar_thickness"]


class OASBoxDims(om.ExplicitComponent):
    """OpenAeroStruct's wingbox distances from the element centroid (``htop``, ``hbottom``,
    ``hfront``, ``hrear``, ny - 1, tip first) -> box ``width`` = hfront + hrear and ``height`` =
    htop + hbottom per beam node (mean of adjacent elements). Linear, constant partials."""

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=2, desc="ny, number of FEM nodes")

    def setup(self):
        n = self.options["num_nodes"]
        self._W = W = element_to_node_matrix(n)[:, ::-1]
        rows, cols = np.nonzero(W)
        for name, _out in (("htop", "height"), ("hbottom", "height"), ("hfront", "width"), ("hrear", "width")):
            self.add_input(name, val=0.1, shape=n - 1, units="m",
                           desc=f"OpenAeroStruct wingbox {name} (centroid to wall) per element")
        for out, ins in (("width", ("hfront", "hrear")), ("height", ("htop", "hbottom"))):
            self.add_output(out, shape=n, units="m", desc=f"box {out} per beam node")
            for i in ins:
                self.declare_partials(out, i, rows=rows, cols=cols, val=W[rows, cols])

    def compute(self, inputs, outputs):
        outputs["width"] = self._W @ (inputs["hfront"] + inputs["hrear"])
        outputs["height"] = self._W @ (inputs["htop"] + inputs["hbottom"])


class OASBeamStates(om.Group):
    """Drop-in for OpenAeroStruct's ``struct_states``: ``loads`` (ny, 6) and ``spar_thickness``,
    ``skin_thickness`` (ny - 1) in, ``disp`` (ny, 6) out, through a box section (App. F) and the
    geometrically nonlinear static beam (App. A).

    Options: ``fem_nodes`` (ny, 3) the OpenAeroStruct FEM nodes (left half-wing, tip first, m);
    ``width``, ``height`` (ny - 1, element order) box dimensions in m (e.g. from OpenAeroStruct's
    wingbox geometry: (x_upper[-1] - x_upper[0]) c and the spar height); ``material``;
    ``newton_options`` (BeamStatic options).
    """

    def initialize(self):
        self.options.declare("fem_nodes", types=(np.ndarray, list, tuple), desc="(ny, 3) OpenAeroStruct FEM nodes, m")
        self.options.declare("width", types=(np.ndarray, list, tuple), desc="(ny - 1,) box width per OAS element, m")
        self.options.declare("height", types=(np.ndarray, list, tuple), desc="(ny - 1,) box height per OAS element, m")
        self.options.declare("material", types=Material, desc="wingmdao.materials.Material")
        self.options.declare("newton_options", default=None, allow_none=True, types=dict,
                             desc="BeamStatic options (Newton tolerances, load steps)")
        self.options.declare("box_from_oas", default=False, types=bool,
                             desc="box width and height from the inputs htop, hbottom, hfront, hrear "
                                  "(OpenAeroStruct's wingbox geometry) instead of the options")

    def setup(self):
        from wingmdao.mphys.builder import SECTION_TO_BEAM, STATES, jig_euler_angles

        fem = np.asarray(self.options["fem_nodes"], dtype=float)
        if fem.ndim != 2 or fem.shape[1] != 3 or fem.shape[0] < 2:
            raise ValueError(f"OASBeamStates: fem_nodes has shape {fem.shape}; expected (ny, 3), ny >= 2")
        n = fem.shape[0]
        if np.any(fem[:, 1] > 1e-12 * np.abs(fem[:, 1]).max()):
            raise ValueError("OASBeamStates: fem_nodes must be a left half-wing (y <= 0), got max y = "
                             f"{fem[:, 1].max()} m")
        x0 = (fem * POLAR)[oas_order(n)]
        th0 = jig_euler_angles(x0)
        W = element_to_node_matrix(n)[:, ::-1]
        geo = {}
        for k in ("width", "height"):
            if self.options["box_from_oas"]:
                geo[k] = np.ones(n)
                continue
            v = np.asarray(self.options[k], dtype=float).ravel()
            if v.shape != (n - 1,) or not np.all(v > 0):
                raise ValueError(f"OASBeamStates: {k} must be positive, shape ({n - 1},) m; got shape {v.shape}")
            geo[k] = W @ v
        ivc = self.add_subsystem("jig", om.IndepVarComp(), promotes=["*"])
        ivc.add_output("node_positions", x0, units="m", desc="jig beam nodes, right wing, root first")
        ivc.add_output("node_euler_angles", th0, units="rad", desc="jig Euler angles")
        if self.options["box_from_oas"]:
            self.add_subsystem("box", OASBoxDims(num_nodes=n), promotes=["*"])
        else:
            ivc.add_output("width", geo["width"], units="m", desc="box width per node")
            ivc.add_output("height", geo["height"], units="m", desc="box height per node")
        self.add_subsystem("thickness", OASThicknessToBox(num_nodes=n), promotes=["*"])
        self.add_subsystem("section", BoxSection(num_stations=n, material=self.options["material"]),
                           promotes_inputs=["width", "height", *WALL_NAMES])

        add_section_offsets(self, n, source="section.")
        for out in SECTION_OFFSETS:
            self.connect(f"offsets.{out}", f"beam.{out}")
        self.add_subsystem("to_beam", OASToBeamLoads(num_nodes=n), promotes_inputs=["loads"])
        beam = BeamStatic(num_nodes=n, state_name=STATES, **(self.options["newton_options"] or {}))
        beam.recording_options["options_excludes"] = ["system"]
        self.add_subsystem("beam", beam, promotes_inputs=["node_positions", "node_euler_angles"],
                           promotes_outputs=[STATES])
        for k in ("stiffness_csn", "compliance_csn", "mass_per_length", "inertia_per_length"):
            self.connect(f"section.{k}", f"beam.{k}")
        del SECTION_TO_BEAM
        self.connect("to_beam.point_force", "beam.point_force")
        self.connect("to_beam.point_moment", "beam.point_moment")
        self.add_subsystem("to_oas", BeamToOASDisp(node_positions=x0, node_euler_angles=th0),
                           promotes_inputs=[STATES], promotes_outputs=["disp"])
