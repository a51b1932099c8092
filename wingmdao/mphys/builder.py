"""MPhys builders for the static nonlinear beam (``WingmdaoBuilder``) and the rigid-link
load and displacement transfer (``BeamRigidLinkBuilder``).

Variable names follow ``mphys.MPhysVariables`` (MPhys 2.0): the structure reads
``x_struct0`` (n*3, m) and ``f_aero_struct`` (n*6: force N and moment N*m per node, body
axes) and returns ``u_struct`` (n*6: displacement m and small rotation vector rad per node,
body axes). Design variables ``dv_struct`` (4*n, m) are the wall thicknesses, wall-major:
``t_upper_skin``, ``t_lower_skin``, ``t_front_spar``, ``t_rear_spar`` (n each, root first).

* pre-coupling: ``dv_struct`` -> ``BoxSection`` (App. F) -> beam section inputs, and the
  structural mass ``struct_mass`` (kg);
* coupling: ``BeamStatic`` (geometrically nonlinear, App. A), solved by its own Newton
  iteration inside MPhys' NonlinearBlockGS, with its own tangent/adjoint solve inside
  LinearBlockGS;
* post-coupling: csn internal loads -> box stresses (Sec. 4.4.2) -> KS aggregate
  ``ks_<family>`` (Eq. 4.44).

The rotation output is the small-rotation vector of the beam frames, linearised about the
jig: ``theta_body = T(theta0)^T K(theta0) (theta - theta0)`` (Eq. A.1, A.3), which is what a
linear rigid-link transfer needs; the beam itself stays fully nonlinear.

Source: "Structural analysis and optimization of aircraft wings through dimensional
reduction", PhD dissertation, Georgia Institute of Technology, 2021 (App. A, App. F, Ch. 4).
MPhys: Yildirim et al., "MPhys: a modular multiphysics library for coupled simulation and
adjoint derivative computation", AIAA SciTech 2025 (the builder API).
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om
from mphys.core import Builder, MPhysVariables

from wingmdao.groups import wing as _wing
from wingmdao.mphys.transfer import RigidLinkDisplacementTransfer, RigidLinkLoadTransfer, rigid_links
from wingmdao.section.box import WALL_NAMES as WALLS
from wingmdao.beam.rotations import body_to_csn, euler_from_axis, rate_matrix
from wingmdao.components.beam import BeamStatic
from wingmdao.components.beam_loads import BeamInternalLoads
from wingmdao.components.ks import KSAggregate
from wingmdao.components.mass import StructuralMass
from wingmdao.components.section import BoxSection
from wingmdao.components.stress import BoxStress
from wingmdao.groups.wing import add_section_offsets, stress_points

#: beam inputs the pre-coupling passes to the coupling group (section properties and offsets)
SECTION_TO_BEAM = _wing.SECTION_TO_BEAM + tuple(_wing.SECTION_OFFSETS)
STATES = "wingmdao_states"
X_STRUCT0 = MPhysVariables.Structures.COORDINATES
U_STRUCT = MPhysVariables.Structures.DISPLACEMENTS
F_STRUCT = MPhysVariables.Structures.Loads.AERODYNAMIC


def _tagged(cls, names, tag):
    """Subclass of ``cls`` whose variables in ``names`` carry the MPhys ``tag`` (promotion)."""

    class Tagged(cls):
        def add_input(self, name, *args, **kwargs):
            if name in names:
                kwargs["tags"] = list(kwargs.get("tags") or []) + [tag]
            return super().add_input(name, *args, **kwargs)

        def add_output(self, name, *args, **kwargs):
            if name in names:
                kwargs["tags"] = list(kwargs.get("tags") or []) + [tag]
            return super().add_output(name, *args, **kwargs)

    Tagged.__name__ = cls.__name__
    return Tagged


def jig_euler_angles(node_positions: np.ndarray) -> np.ndarray:
    """Surface-sequence Euler angles of a beam axis through ``node_positions`` (n, 3), zero twist:
    the s axis along the polyline (node tangents averaged from the adjacent elements).

    Parameters
    ----------
    node_positions : numpy.ndarray
        (n, 3) beam node positions (m).

    Returns
    -------
    numpy.ndarray
        (n, 3) Euler angles (rad).
    """
    x = np.asarray(node_positions, dtype=float)
    t = np.gradient(x, axis=0)
    return np.array([euler_from_axis(ti) for ti in t])


def rotation_vector_map(node_euler_angles: np.ndarray) -> np.ndarray:
    """(n, 3, 3) A = T(theta0)^T K(theta0): Euler-angle increments -> small body-axes rotation vector.

    Parameters
    ----------
    node_euler_angles : numpy.ndarray
        (n, 3) jig Euler angles (rad).

    Returns
    -------
    numpy.ndarray
        (n, 3, 3) maps A.
    """
    return np.array([body_to_csn(t).T @ rate_matrix(t) for t in np.asarray(node_euler_angles, dtype=float)])


class StructInputs(om.ExplicitComponent):
    """Reshape ``x_struct0`` (n*3) -> ``node_positions`` (n, 3) and, with ``loads=True``,
    ``f_aero_struct`` (n*6) -> ``point_force``, ``point_moment`` (n, 3). Linear, constant partials."""

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes")
        self.options.declare("loads", default=True, types=bool, desc="also split the loads")

    def setup(self):
        n = self.options["num_nodes"]
        self.add_input(X_STRUCT0, shape_by_conn=True, units="m", tags=["mphys_coordinates"],
                       desc="jig beam node coordinates, n*3 (x, y, z per node, root first)")
        self.add_output("node_positions", shape=(n, 3), units="m", desc="jig beam-axis node positions")
        if self.options["loads"]:
            self.add_input(F_STRUCT, shape_by_conn=True, units=None, tags=["mphys_coupling"],
                           desc="nodal forces (N) and moments (N*m), n*6, body axes")
            self.add_output("point_force", shape=(n, 3), units="N", desc="aerodynamic point force per node")
            self.add_output("point_moment", shape=(n, 3), units="N*m", desc="aerodynamic point moment per node")

    def setup_partials(self):
        n = self.options["num_nodes"]
        for name, per, what in ((X_STRUCT0, 3, "3 coordinates per beam node"),
                                (F_STRUCT, 6, "3 forces and 3 moments per beam node")):
            meta = self.get_io_metadata(metadata_keys=["size", "shape"], return_rel_names=True)
            if name not in meta:
                continue
            size = meta[name]["size"]
            if size != per * n:
                raise ValueError(f"{self.pathname}: {name} has {size} entries, shape "
                                 f"{meta[name]['shape']}; expected {per * n} ({what}, "
                                 f"{n} beam nodes)")
        k = np.arange(3 * n)
        self.declare_partials("node_positions", X_STRUCT0, rows=k, cols=k, val=1.0)
        if self.options["loads"]:
            cols = (6 * np.arange(n)[:, None] + np.arange(3)[None, :]).ravel()
            self.declare_partials("point_force", F_STRUCT, rows=k, cols=cols, val=1.0)
            self.declare_partials("point_moment", F_STRUCT, rows=k, cols=cols + 3, val=1.0)

    def compute(self, inputs, outputs):
        n = self.options["num_nodes"]
        outputs["node_positions"] = np.asarray(inputs[X_STRUCT0]).reshape(n, 3)
        if self.options["loads"]:
            f = np.asarray(inputs[F_STRUCT]).reshape(n, 6)
            outputs["point_force"] = f[:, :3]
            outputs["point_moment"] = f[:, 3:]


class BeamDisplacements(om.ExplicitComponent):
    """Beam states -> ``u_struct`` (n*6): u = r - r0, rotation = A (theta - theta0). Linear."""

    def initialize(self):
        self.options.declare("node_euler_angles", types=(np.ndarray, list, tuple), desc="(n, 3) jig Euler angles, rad")

    def setup(self):
        th0 = np.asarray(self.options["node_euler_angles"], dtype=float)
        n = th0.shape[0]
        self._A = rotation_vector_map(th0)
        self.add_input(STATES, shape=(n, 18), units=None, tags=["mphys_coupling"],
                       desc="beam state r, theta, F, M, u, omega per node (SI)")
        self.add_input(X_STRUCT0, shape=3 * n, units="m", tags=["mphys_coordinates"],
                       desc="jig beam node coordinates")
        self.add_output(U_STRUCT, shape=6 * n, units=None, tags=["mphys_coupling"],
                        desc="node displacement (m) and small rotation vector (rad), body axes")
        node = np.arange(n)
        rows_u = (6 * node[:, None] + np.arange(3)).ravel()
        cols_u = (18 * node[:, None] + np.arange(3)).ravel()
        rows_t = np.repeat((6 * node[:, None] + 3 + np.arange(3)).ravel(), 3)
        cols_t = (18 * node[:, None, None] + 3 + np.arange(3)[None, None, :]
                  + 0 * np.arange(3)[None, :, None]).ravel()
        self.declare_partials(U_STRUCT, STATES, rows=np.concatenate([rows_u, rows_t]),
                              cols=np.concatenate([cols_u, cols_t]),
                              val=np.concatenate([np.ones(3 * n), self._A.ravel()]))
        self.declare_partials(U_STRUCT, X_STRUCT0, rows=rows_u, cols=np.arange(3 * n), val=-1.0)

    def compute(self, inputs, outputs):
        th0 = np.asarray(self.options["node_euler_angles"], dtype=float)
        n = th0.shape[0]
        x = np.asarray(inputs[STATES])
        u = np.zeros((n, 6), dtype=np.result_type(x, inputs[X_STRUCT0]))
        u[:, :3] = x[:, :3] - np.asarray(inputs[X_STRUCT0]).reshape(n, 3)
        u[:, 3:] = np.einsum("nij,nj->ni", self._A, x[:, 3:6] - th0)
        outputs[U_STRUCT] = u.ravel()


class DvSplit(om.ExplicitComponent):
    """``dv_struct`` (4*n) -> the four wall thicknesses (n each). Linear, constant partials."""

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes")
        self.options.declare("initial", types=(np.ndarray, list, tuple), desc="(4*n,) initial dv_struct, m")

    def setup(self):
        n = self.options["num_nodes"]
        self.add_input("dv_struct", val=np.asarray(self.options["initial"], dtype=float), units="m",
                       tags=["mphys_input"], desc="wall thicknesses: upper skin, lower skin, front spar, rear spar")
        for k, w in enumerate(WALLS):
            self.add_output(w, shape=n, units="m", desc=f"{w.replace('_', ' ')} thickness per node")
            self.declare_partials(w, "dv_struct", rows=np.arange(n), cols=k * n + np.arange(n), val=1.0)

    def compute(self, inputs, outputs):
        n = self.options["num_nodes"]
        dv = np.asarray(inputs["dv_struct"])
        bad = np.flatnonzero(~(dv > 0.0))
        if bad.size:
            i = int(bad[0])
            raise om.AnalysisError(f"{self.pathname}: dv_struct[{i}] ({WALLS[i // n]} at node {i % n}) = {dv[i]} m; "
                                   "allowed range (0, inf) m")
        for k, w in enumerate(WALLS):
            outputs[w] = dv[k * n:(k + 1) * n]


class _Geometry(om.IndepVarComp):
    def initialize(self):
        self.options.declare("width", types=(np.ndarray, list, tuple), desc="(n,) box width, m")
        self.options.declare("height", types=(np.ndarray, list, tuple), desc="(n,) box height, m")
        self.options.declare("nonstructural_mass_per_length", default=None, allow_none=True,
                             types=(np.ndarray, list, tuple), desc="(n,) nonstructural mass per length, kg/m")

    def setup(self):
        self.add_output("width", val=np.asarray(self.options["width"], float), units="m", desc="box width")
        self.add_output("height", val=np.asarray(self.options["height"], float), units="m", desc="box height")
        nsm = self.options["nonstructural_mass_per_length"]
        if nsm is not None:
            self.add_output("nonstructural_mass_per_length", val=np.asarray(nsm, float), units="kg/m",
                            desc="nonstructural mass per length at the section's mass centre")


class _BuilderGroup(om.Group):
    """A group built from a :class:`WingmdaoBuilder` (option ``builder``)."""

    def initialize(self):
        self.options.declare("builder", types=WingmdaoBuilder, recordable=False,
                             desc="the WingmdaoBuilder whose mesh, material and options this group uses")

    def add_design(self, b):
        """``dv_struct`` split into the four wall thicknesses, and the box width/height per node."""
        self.add_subsystem("dv", DvSplit(num_nodes=b.num_nodes, initial=b.get_initial_dvs()), promotes=["*"])
        self.add_subsystem("geometry", _Geometry(width=b.width, height=b.height,
                                                 nonstructural_mass_per_length=b.nonstructural_mass_per_length),
                           promotes=["*"])


class PreCoupling(_BuilderGroup):
    """dv_struct -> BoxSection -> beam section inputs (tagged for MPhys promotion), struct_mass."""

    def setup(self):
        b = self.options["builder"]
        n = b.num_nodes
        self.add_design(b)
        self.add_subsystem("xs", StructInputs(num_nodes=n, loads=False), promotes=["*"])
        cls = _tagged(BoxSection, set(SECTION_TO_BEAM), "mphys_coupling")
        self.add_subsystem("section", cls(num_stations=n, material=b.material), promotes=["*"])
        add_section_offsets(self, n, mux=_tagged(om.MuxComp, set(SECTION_TO_BEAM), "mphys_coupling")(vec_size=2),
                            promotes_outputs=["*"])
        self.add_subsystem("mass", _tagged(StructuralMass, {"mass"}, "mphys_result")(num_nodes=n, material=b.material),
                           promotes_inputs=["A", "node_positions"], promotes_outputs=[("mass", "struct_mass")])


class BeamCoupling(_BuilderGroup):
    """The coupling subsystem: f_aero_struct -> BeamStatic -> u_struct."""

    def setup(self):
        b = self.options["builder"]
        n = b.num_nodes
        self.add_subsystem("inputs", StructInputs(num_nodes=n), promotes=["*"])
        ivc = self.add_subsystem("jig", om.IndepVarComp(), promotes=["*"])
        ivc.add_output("node_euler_angles", val=b.node_euler_angles, units="rad", desc="jig Euler angles")
        beam = _tagged(BeamStatic, set(SECTION_TO_BEAM) | {STATES}, "mphys_coupling")(
            num_nodes=n, state_name=STATES, **b.newton_options)
        beam.recording_options["options_excludes"] = ["system"]
        self.add_subsystem("beam", beam, promotes_inputs=["node_positions", "node_euler_angles", "point_force",
                                                          "point_moment", *SECTION_TO_BEAM],
                           promotes_outputs=[STATES])
        self.add_subsystem("disp", BeamDisplacements(node_euler_angles=b.node_euler_angles), promotes=["*"])


class PostCoupling(_BuilderGroup):
    """States -> csn internal loads -> box stresses -> KS (``ks_<family>``)."""

    def setup(self):
        b = self.options["builder"]
        n = b.num_nodes
        self.add_design(b)
        il = self.add_subsystem("internal_loads",
                                _tagged(BeamInternalLoads, {"states"}, "mphys_coupling")(num_times=1, num_nodes=n))
        self.promotes("internal_loads", inputs=[("states", STATES)], src_indices=np.arange(18 * n).reshape(1, n, 18),
                      flat_src_indices=True, src_shape=(n, 18))
        del il
        self.add_subsystem("stress", BoxStress(num_times=1, num_stations=n, material=b.material,
                                               families=tuple(b.families), output_stresses=False),
                           promotes_inputs=["width", "height", *WALLS])
        self.connect("internal_loads.F_csn", "stress.F_csn")
        self.connect("internal_loads.M_csn", "stress.M_csn")
        shapes = {f: (1, n, k) for f, k in stress_points("box", b.families).items()}
        names = {f"ks_{f}" for f in b.families}
        self.add_subsystem("ks", _tagged(KSAggregate, names, "mphys_result")(families=shapes, rho_ks=b.rho_ks),
                           promotes_outputs=sorted(names))
        for f in b.families:
            self.connect(f"stress.g_{f}", f"ks.g_{f}")


class WingmdaoBuilder(Builder):
    """MPhys builder of the static nonlinear box beam (see the module docstring).

    Parameters: ``node_positions`` (n, 3) m, root first; ``width``, ``height`` (n,) m box
    dimensions; ``thickness`` (4, n) or scalar, m, the initial ``dv_struct``; ``material``
    (:class:`wingmdao.materials.Material`); ``node_euler_angles`` (n, 3) rad (default: along the
    polyline, no twist); ``families`` (stress constraint families, default ("vm",));
    ``rho_ks``; ``newton_options`` (BeamStatic options, e.g. ``{"static_options": {"load_steps": 2}}``).

    Parameters
    ----------
    node_positions : array_like
        (n, 3) beam node positions, root first (m).
    width, height : array_like
        (n,) box dimensions (m).
    thickness : float or array_like
        Initial wall thicknesses, scalar or (4, n) (m).
    material : Material
        Isotropic material.
    node_euler_angles : array_like or None, optional
        (n, 3) jig Euler angles (rad); None along the polyline, no twist.
    families : tuple of str, optional
        Stress constraint families.
    rho_ks : float, optional
        KS aggregation parameter.
    newton_options : dict or None, optional
        Options of the static beam solve.
    """

    def __init__(self, node_positions, width, height, thickness, material, node_euler_angles=None,
                 families=("vm",), rho_ks=100.0, newton_options=None):
        x = np.asarray(node_positions, dtype=float)
        if x.ndim != 2 or x.shape[1] != 3 or x.shape[0] < 2:
            raise ValueError(f"WingmdaoBuilder: node_positions has shape {x.shape}; expected (n, 3) with n >= 2")
        rigid_links(x, x[:1])   # coincident-node check
        n = x.shape[0]
        self.num_nodes = n
        self.node_positions = x
        self.width = self._per_node(width, "width")
        self.height = self._per_node(height, "height")
        t = np.broadcast_to(np.asarray(thickness, dtype=float), (4, n)) if np.ndim(thickness) in (0, 2) \
            else np.asarray(thickness, dtype=float)
        if t.shape != (4, n) or not np.all(t > 0):
            raise ValueError(f"WingmdaoBuilder: thickness must be positive, scalar or (4, {n}) m, "
                             f"got shape {np.shape(thickness)}")
        self.thickness = np.array(t)
        self.material = material
        th = jig_euler_angles(x) if node_euler_angles is None else np.asarray(node_euler_angles, dtype=float)
        if th.shape != (n, 3):
            raise ValueError(f"WingmdaoBuilder: node_euler_angles has shape {th.shape}; expected ({n}, 3)")
        self.node_euler_angles = th
        self.families = tuple(families)
        self.rho_ks = float(rho_ks)
        self.newton_options = dict(newton_options or {})
        self.nonstructural_mass_per_length = None   # the walls' mass only (StickBuilder sets the wing's)
        self.comm = None

    def _per_node(self, v, name):
        a = np.broadcast_to(np.asarray(v, dtype=float), (self.num_nodes,)).copy()
        if not np.all(a > 0):
            raise ValueError(f"WingmdaoBuilder: {name} = {a.min()} m somewhere; allowed range (0, inf) m")
        return a

    def initialize(self, comm):
        if comm is not None and comm.size > 1:
            raise ValueError(f"WingmdaoBuilder: the beam runs on one process, got a communicator of size {comm.size}")
        self.comm = comm

    def get_initial_dvs(self):
        """Initial ``dv_struct`` (4*n,), m, wall-major."""
        return self.thickness.ravel().copy()

    def get_mesh_coordinate_subsystem(self, scenario_name=None):
        ivc = om.IndepVarComp()
        ivc.add_output(MPhysVariables.Structures.Mesh.COORDINATES, val=self.node_positions.ravel(), units="m",
                       tags=["mphys_coordinates"], desc="jig beam node coordinates, n*3, root first")
        return ivc

    def get_pre_coupling_subsystem(self, scenario_name=None):
        return PreCoupling(builder=self)

    def get_coupling_group_subsystem(self, scenario_name=None):
        return BeamCoupling(builder=self)

    def get_post_coupling_subsystem(self, scenario_name=None):
        return PostCoupling(builder=self)

    def get_ndof(self):
        return 6

    def get_number_of_nodes(self):
        return self.num_nodes

    def get_tagged_indices(self, tags):
        """-1 (or [-1]) or 'all': every node; 'root'/'tip': the first/last; ints pass through."""
        if tags in (-1, [-1], "all", ["all"]):
            return list(range(self.num_nodes))
        out = []
        for t in tags:
            out.extend([0] if t == "root" else [self.num_nodes - 1] if t == "tip" else [int(t)])
        return out


class BeamRigidLinkBuilder(Builder):
    """Rigid-link load and displacement transfer between ``struct_builder`` (a
    :class:`WingmdaoBuilder`) and an aerodynamic builder whose surface nodes are ``x_aero0``
    ((m, 3) m, the jig surface). ``mirror_y=True``: the aerodynamic surface is the left half-wing
    (OpenAeroStruct symmetric surfaces, y <= 0) of the beam's right wing.

    Parameters
    ----------
    aero_builder : mphys.Builder
        The aerodynamic builder.
    struct_builder : WingmdaoBuilder
        The structural builder.
    x_aero0 : array_like
        (m, 3) jig aerodynamic surface nodes (m).
    mirror_y : bool, optional
        The aerodynamic surface is the left half-wing.
    """

    def __init__(self, aero_builder, struct_builder, x_aero0, mirror_y=False):
        self.aero_builder = aero_builder
        self.struct_builder = struct_builder
        self.x_aero0 = np.asarray(x_aero0, dtype=float).reshape(-1, 3)
        self.mirror_y = bool(mirror_y)

    def initialize(self, comm):
        self.comm = comm
        n_aero = self.aero_builder.get_number_of_nodes()
        if n_aero != self.x_aero0.shape[0]:
            raise ValueError(f"BeamRigidLinkBuilder: the aerodynamic builder has {n_aero} nodes but x_aero0 "
                             f"has {self.x_aero0.shape[0]}; they must match")
        if self.struct_builder.get_ndof() != 6:
            raise ValueError("BeamRigidLinkBuilder: the structural builder must have 6 dof per node "
                             f"(translations and rotations), got {self.struct_builder.get_ndof()}")
        xs = self.struct_builder.node_positions
        if xs.shape[0] != self.struct_builder.get_number_of_nodes():
            raise ValueError("BeamRigidLinkBuilder: structural node count and coordinates differ")
        xa = self.x_aero0 * (np.array([1.0, -1.0, 1.0]) if self.mirror_y else 1.0)
        self.links = rigid_links(xs, xa)

    def get_coupling_group_subsystem(self, scenario_name=None):
        kw = dict(links=self.links, num_struct_nodes=self.struct_builder.get_number_of_nodes(),
                  mirror_y=self.mirror_y)
        return RigidLinkDisplacementTransfer(**kw), RigidLinkLoadTransfer(**kw)

    def get_number_of_nodes(self):
        return self.x_aero0.shape[0]

    def get_ndof(self):
        return 3
