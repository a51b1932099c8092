"""Several App. A beams joined at nodes, as one CasADi residual system (a stick model's structure).

Each beam keeps its own nodes, sections and stations and its 18 unknowns and 18 equations per
node (:mod:`wingmdao.beam.residual`), in its own axes (a constant rotation R of the body axes, e.g.
:data:`FUSELAGE_AXES` for a beam along body x; identity by default). A beam's root (node 0) is
clamped or free; its tip is free.
A joint connects node ``i`` of beam A with node ``j`` of beam B (coincident in the jig) and adds
12 unknowns and 12 equations (derivation: docs/stick-model.md):

* unknowns: the force and moment the joint exerts on beam A's node (``f_A``, ``m_A``) and on beam
  B's node (``f_B``, ``m_B``), body axes; each enters its beam as a point load at the node;
* equations: transfer of force and moment across the massless joint, ``f_A + f_B = 0`` and
  ``m_A + m_B = 0``; equal positions ``R_B^T r_B - R_A^T r_A = 0``; and the orientation condition
  on the relative rotation ``C = Lambda_A^T Lambda_B`` of the two node frames measured from the jig
  (``Lambda = R^T T(theta)^T T(theta_0) R``, body components), through its axial vector
  ``w = axial(C - C^T) / 2``:

  - rigid joint: ``w = 0`` (3 rows);
  - hinge about the unit axis ``a`` (body axes of the jig, carried by beam A): ``b_1 . w = 0`` and
    ``b_2 . w = 0`` with ``b_1, b_2`` normal to ``a``, and the hinge law
    ``(Lambda_A a) . m_B + k phi = 0``, ``phi = atan2(a . w, (tr C - 1) / 2)`` the hinge angle and
    ``k`` the rotational spring stiffness (``joint_rotational_stiffness``; a free hinge has no
    spring: ``(Lambda_A a) . m_B = 0``).

Lumped masses (:class:`LumpedMass`: mass, offset, rotary inertia on a node) add their weight and
d'Alembert loads to their nodes' point loads (:func:`lumped_mass_loads`). A free aircraft has no
clamped beam; its rigid-body motion is carried by the beams' states. Symmetry conditions
(:class:`Symmetry`) on nodes of the plane of symmetry make a half aircraft (3 unknowns and 3
equations each: lateral displacement, roll and yaw held). :func:`solve_inertia_relief` gives the
equilibrium of a free structure in uniformly accelerated motion, :func:`monitoring_loads` the
internal loads at monitoring stations.

State layout: the beams' node-major blocks in the order given (``offsets``), then 12 unknowns per
joint, then 3 per symmetry condition (``symmetry_offset``). Parameters and forcing: every beam's
blocks of :func:`wingmdao.beam.residual.param_specs` and
:func:`~wingmdao.beam.residual.forcing_specs` named ``<beam>_<block>``, then the joints' spring
stiffnesses and the lumped masses' values; gravity and the motion of the body axes are shared by
all beams.
"""

from __future__ import annotations

import functools
import math
import re
import time
import warnings
from dataclasses import dataclass

import casadi as ca
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.beam.residual import (N_STATE_PER_NODE, STATE_BLOCKS, StrainRateDamping, NODE_PARAMS, NODE_FORCING,
                                    element_function, nodal_acceleration, nodal_function, node_forcing,
                                    node_params,
                                    describe_equation as beam_equation, forcing_specs as beam_forcing_specs,
                                    jig_state as beam_jig_state, param_specs as beam_param_specs)
from wingmdao.beam.rotations import body_to_csn
from wingmdao.beam.static import beam_forcing, check_beam_parameters
from wingmdao.timemarch import lu_orders
from wingmdao.timemarch.bdf import solve_static
from wingmdao.timemarch.system import CasadiResidualSystem, VarSpec, layout, pack
from wingmdao.utils.casadi_cache import definition_key

#: Unknowns (and equations) per joint.
N_JOINT = 12
#: Joint unknowns: load of the joint on beam A's node, then on beam B's node (body axes).
JOINT_BLOCKS = {"force_a": slice(0, 3), "moment_a": slice(3, 6), "force_b": slice(6, 9),
                "moment_b": slice(9, 12)}
ROOT_CONDITIONS = ("clamped", "free")
JOINT_KINDS = ("rigid", "hinge")
#: Largest distance (m) between the jig positions of the two nodes of a joint.
POSITION_TOLERANCE = 1e-6
#: Scale of a free root's rows ``F_0 = 0``, ``M_0 = 0``. A power of two changes no rounding; it makes
#: partial pivoting take these rows for their own unknowns (unscaled, the tie with element 0's
#: equilibrium rows gave pivots whose static reuse failed the backward-error check of the tangent
#: sweep at every step of a march, docs/stick-model.md).
FREE_ROOT_ROW_SCALE = 2.0
#: Shared forcing blocks (one body frame for every beam).
_SHARED_FORCING = ("gravity", "frame_acceleration", "frame_angular_velocity", "frame_angular_acceleration")
_BEAM_FORCING = ("force_per_length", "moment_per_length", "point_force", "point_moment")
_GENERATING_MODULES = ("wingmdao.beam.joints", "wingmdao.beam.residual", "wingmdao.beam.rotations",
                       "wingmdao.timemarch.system")
_XYZ = "xyz"


#: Axes of a beam along the body x axis (a fuselage; the surface Euler sequence is singular there):
#: the beam's own y (its axis direction) is body x (aft), its x is body -y, its z is body z.
FUSELAGE_AXES = ((0.0, -1.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0))


@dataclass(frozen=True)
class Beam:
    """One beam of a joined system: a ``name`` (a Python identifier, prefix of its parameter and
    forcing blocks), its ``num_nodes`` (>= 2, root first) and its ``root`` condition,
    ``"clamped"`` (r, theta held at the jig) or ``"free"`` (no force or moment at the root).

    ``axes``: the beam's own axes as a rotation matrix R (3 x 3, rows = the beam's x, y, z in body
    components; ``v_beam = R v_body``); None: the body axes. The beam's parameters, states and
    loads are in its own axes, so a beam along body x (a fuselage, :data:`FUSELAGE_AXES`) runs
    along its own y, away from the singular direction of the Euler sequence.

    Parameters
    ----------
    name : str
        Name of the beam (a Python identifier).
    num_nodes : int
        Number of nodes (at least 2), root first.
    root : str
        ``"clamped"`` or ``"free"``.
    axes : tuple, optional
        Rotation matrix (3 x 3) from body to the beam's own axes; None: the body axes.
    """

    name: str
    num_nodes: int
    root: str = "clamped"
    axes: tuple | None = None

    def __post_init__(self):
        if not (isinstance(self.name, str) and re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", self.name)):
            raise ValueError(f"beam name must be an identifier (letters, digits, _), got {self.name!r}")
        if int(self.num_nodes) != self.num_nodes or int(self.num_nodes) < 2:
            raise ValueError(f"beam {self.name!r}: num_nodes must be an integer >= 2, got {self.num_nodes!r}")
        object.__setattr__(self, "num_nodes", int(self.num_nodes))
        if self.root not in ROOT_CONDITIONS:
            raise ValueError(f"beam {self.name!r}: root must be one of {ROOT_CONDITIONS}, got {self.root!r}")
        if self.axes is not None:
            R = np.asarray(self.axes, dtype=float)
            if R.shape != (3, 3) or not np.all(np.isfinite(R)) or not np.allclose(R @ R.T, np.eye(3), atol=1e-9) \
                    or np.linalg.det(R) <= 0.0:
                raise ValueError(f"beam {self.name!r}: axes must be a 3 x 3 rotation matrix (orthonormal rows, "
                                 f"determinant +1), got {self.axes}")
            object.__setattr__(self, "axes", tuple(tuple(float(v) for v in row) for row in R))

    @property
    def rotation(self) -> np.ndarray:
        """R: body components -> the beam's own components (identity without ``axes``)."""
        return np.eye(3) if self.axes is None else np.array(self.axes, dtype=float)


@dataclass(frozen=True)
class Joint:
    """A joint between node ``node_a`` of beam ``beam_a`` and node ``node_b`` of beam ``beam_b``
    (node indices from the root, negative from the tip as in Python).

    ``kind``: ``"rigid"`` (equal position and orientation) or ``"hinge"`` (equal position, free
    rotation about ``axis``, a vector in body axes of the jig carried by beam A, against the
    rotational spring ``stiffness`` in N*m/rad; None: no spring).

    Parameters
    ----------
    beam_a : str
        Name of beam A.
    node_a : int
        Node of beam A (negative from the tip).
    beam_b : str
        Name of beam B.
    node_b : int
        Node of beam B (negative from the tip).
    kind : str
        ``"rigid"`` or ``"hinge"``.
    axis : tuple of 3 float, optional
        Hinge axis in body axes of the jig (hinges only).
    stiffness : float, optional
        Rotational spring stiffness of a hinge (N m/rad); None: no spring.
    """

    beam_a: str
    node_a: int
    beam_b: str
    node_b: int
    kind: str = "rigid"
    axis: tuple | None = None
    stiffness: float | None = None

    def __post_init__(self):
        if self.kind not in JOINT_KINDS:
            raise ValueError(f"{self.label}: kind must be one of {JOINT_KINDS}, got {self.kind!r}")
        for name in ("node_a", "node_b"):
            v = getattr(self, name)
            if isinstance(v, bool) or int(v) != v:
                raise ValueError(f"{self.label}: {name} must be an integer node index, got {v!r}")
            object.__setattr__(self, name, int(v))
        if self.kind == "rigid":
            if self.axis is not None or self.stiffness is not None:
                raise ValueError(f"{self.label}: a rigid joint takes no axis or stiffness "
                                 f"(got axis={self.axis}, stiffness={self.stiffness}); use kind='hinge'")
            return
        axis = np.asarray(self.axis if self.axis is not None else (), dtype=float).ravel()
        if axis.size != 3 or not np.all(np.isfinite(axis)) or np.linalg.norm(axis) <= 1e-12:
            raise ValueError(f"{self.label}: a hinge needs an axis of 3 finite components and non-zero "
                             f"length (body axes), got axis={self.axis}")
        object.__setattr__(self, "axis", tuple(float(v) for v in axis / np.linalg.norm(axis)))
        if self.stiffness is not None:
            k = float(self.stiffness)
            if not (math.isfinite(k) and k > 0.0):
                raise ValueError(f"{self.label}: stiffness must be a finite rotational spring stiffness "
                                 f"> 0 N*m/rad (or None for a free hinge), got {self.stiffness}")
            object.__setattr__(self, "stiffness", k)

    @property
    def label(self) -> str:
        return f"joint {self.beam_a} node {self.node_a} - {self.beam_b} node {self.node_b}"


@dataclass(frozen=True)
class LumpedMass:
    """A rigid mass (an engine, fuel, payload, systems) attached to node ``node`` of beam ``beam``
    (negative from the tip): ``mass`` (kg, > 0), its centre at ``offset`` from the node (m, body
    axes of the jig; it turns with the node) and its rotary ``inertia`` about that centre (kg*m^2,
    3 x 3 symmetric, positive semi-definite, body axes of the jig; None: a point mass).

    Its inertia and weight enter the node as a point force and moment (docs/stick-model.md,
    "Lumped masses"); its values are parameters of the system (``lumped_mass``,
    ``lumped_mass_offset``, ``lumped_mass_inertia``), so gradients reach them.

    Parameters
    ----------
    beam : str
        Name of the beam.
    node : int
        Node the mass is attached to (negative from the tip).
    mass : float
        Mass (kg), > 0.
    offset : tuple of 3 float
        Position of its centre from the node (m), body axes of the jig.
    inertia : tuple, optional
        Rotary inertia about its centre (kg m^2, 3 x 3, body axes of the jig); None: a point mass.
    """

    beam: str
    node: int
    mass: float
    offset: tuple = (0.0, 0.0, 0.0)
    inertia: tuple | None = None

    def __post_init__(self):
        if isinstance(self.node, bool) or int(self.node) != self.node:
            raise ValueError(f"{self.label}: node must be an integer node index, got {self.node!r}")
        object.__setattr__(self, "node", int(self.node))
        m = float(self.mass)
        if not (math.isfinite(m) and m > 0.0):
            raise ValueError(f"{self.label}: mass must be finite and > 0 kg, got {self.mass}")
        object.__setattr__(self, "mass", m)
        d = np.asarray(self.offset, dtype=float).ravel()
        if d.size != 3 or not np.all(np.isfinite(d)):
            raise ValueError(f"{self.label}: offset must be 3 finite components (m, body axes), got {self.offset}")
        object.__setattr__(self, "offset", tuple(float(v) for v in d))
        J = np.zeros((3, 3)) if self.inertia is None else np.asarray(self.inertia, dtype=float)
        if J.shape != (3, 3) or not np.all(np.isfinite(J)) or not np.allclose(J, J.T, atol=1e-12 * (1 + np.abs(J).max())) \
                or np.linalg.eigvalsh(0.5 * (J + J.T)).min() < -1e-12 * (1 + np.abs(J).max()):
            raise ValueError(f"{self.label}: inertia must be a symmetric positive semi-definite 3 x 3 matrix "
                             f"(kg*m^2, body axes), got {self.inertia}")
        object.__setattr__(self, "inertia", tuple(tuple(float(v) for v in row) for row in J))

    @property
    def label(self) -> str:
        return f"lumped mass on {self.beam} node {self.node}"


#: Names of the three motions a :class:`Symmetry` condition holds.
SYMMETRY_HELD = ("lateral displacement y", "roll rotation x", "yaw rotation z")


@dataclass(frozen=True)
class Symmetry:
    """Symmetry conditions at node ``node`` of beam ``beam``, a node on the aircraft's plane of
    symmetry (the body x-z plane, y = 0): a symmetric half aircraft. The node keeps y = 0 and turns
    only about y (lateral displacement, roll and yaw held; surge, plunge and pitch free). Three
    unknowns, the mirror half's force along y and moments about x and z on the node (body axes),
    and three equations (docs/stick-model.md, "Free flight").

    Parameters
    ----------
    beam : str
        Name of the beam.
    node : int
        Node on the plane of symmetry (negative from the tip).
    """

    beam: str
    node: int

    def __post_init__(self):
        if isinstance(self.node, bool) or int(self.node) != self.node:
            raise ValueError(f"{self.label}: node must be an integer node index, got {self.node!r}")
        object.__setattr__(self, "node", int(self.node))

    @property
    def label(self) -> str:
        return f"symmetry condition on {self.beam} node {self.node}"


#: Unknowns (and equations) per symmetry condition.
N_SYMMETRY = 3


def _check_node(label, by_name, name, node, which=""):
    if name not in by_name:
        raise ValueError(f"{label}: beam{which} {name!r} is not a beam; beams are {sorted(by_name)}")
    n = by_name[name].num_nodes
    if not -n <= node < n:
        raise ValueError(f"{label}: node{which} {node} does not exist: beam {name!r} has nodes "
                         f"0..{n - 1} (or -{n}..-1 from the tip)")
    return node % n


def _check_attachments(by_name, masses, symmetry, joints=()):
    """Resolve and check lumped masses and symmetry conditions (beams and nodes exist; one
    symmetry condition per node and per pair of rigidly joined nodes; none on a system with a
    clamped beam)."""
    out_m, out_s, seen = [], [], set()
    for lm in masses:
        if not isinstance(lm, LumpedMass):
            raise TypeError(f"masses must be LumpedMass objects, got {type(lm).__name__}")
        node = _check_node(lm.label, by_name, lm.beam, lm.node)
        out_m.append(LumpedMass(lm.beam, node, lm.mass, lm.offset, lm.inertia))
    for sy in symmetry:
        if not isinstance(sy, Symmetry):
            raise TypeError(f"symmetry must be Symmetry objects, got {type(sy).__name__}")
        node = _check_node(sy.label, by_name, sy.beam, sy.node)
        if (sy.beam, node) in seen:
            raise ValueError(f"{sy.label}: this node has two symmetry conditions")
        seen.add((sy.beam, node))
        out_s.append(Symmetry(sy.beam, node))
    held = {(sy.beam, sy.node) for sy in out_s}
    for jt in joints:
        if jt.kind == "rigid" and (jt.beam_a, jt.node_a) in held and (jt.beam_b, jt.node_b) in held:
            raise ValueError(f"{jt.label}: both nodes of this rigid joint have symmetry conditions; they move as "
                             f"one, so one condition holds both (the second is redundant: drop it)")
    clamped = [b.name for b in by_name.values() if b.root == "clamped"]
    if out_s and clamped:
        raise ValueError(f"symmetry conditions are for a free aircraft: beams {clamped} have a clamped root "
                         f"(give them root='free')")
    return out_m, out_s


def _check_layout(beams, joints, masses=(), symmetry=()):
    """Resolve negative node indices and check names, nodes, duplicates and connectivity; returns
    the beams, joints, lumped masses and symmetry conditions."""
    beams, joints = list(beams), list(joints)
    if not beams:
        raise ValueError("a joined system needs at least one beam")
    by_name = {}
    for b in beams:
        if not isinstance(b, Beam):
            raise TypeError(f"beams must be Beam objects, got {type(b).__name__}")
        if b.name in by_name:
            raise ValueError(f"beam name {b.name!r} is used twice")
        by_name[b.name] = b
    resolved, pairs = [], set()
    for jt in joints:
        if not isinstance(jt, Joint):
            raise TypeError(f"joints must be Joint objects, got {type(jt).__name__}")
        nodes = [_check_node(jt.label, by_name, getattr(jt, f"beam_{w}"), getattr(jt, f"node_{w}"), f"_{w}")
                 for w in ("a", "b")]
        if jt.beam_a == jt.beam_b:
            raise ValueError(f"{jt.label}: a joint connects two different beams")
        key = frozenset(((jt.beam_a, nodes[0]), (jt.beam_b, nodes[1])))
        if key in pairs:
            raise ValueError(f"{jt.label}: these two nodes are joined twice")
        pairs.add(key)
        resolved.append(Joint(jt.beam_a, nodes[0], jt.beam_b, nodes[1], jt.kind, jt.axis, jt.stiffness))
    # connectivity: every beam reachable from the first through joints
    if len(beams) > 1:
        reached, frontier = {beams[0].name}, [beams[0].name]
        while frontier:
            name = frontier.pop()
            for jt in resolved:
                for a, b in ((jt.beam_a, jt.beam_b), (jt.beam_b, jt.beam_a)):
                    if a == name and b not in reached:
                        reached.add(b)
                        frontier.append(b)
        missing = [b.name for b in beams if b.name not in reached]
        if missing:
            raise ValueError(f"beams {missing} are joined to no other beam (every beam must be connected "
                             f"to {beams[0].name!r} through joints)")
    masses, symmetry = _check_attachments(by_name, list(masses), list(symmetry), resolved)
    return beams, resolved, masses, symmetry


def param_specs(beams, joints, masses=()) -> list[VarSpec]:
    """Parameters of the joined system: every beam's blocks (``<beam>_<block>``), then
    ``joint_rotational_stiffness`` (one per joint; used by hinges with a spring), then the lumped
    masses' ``lumped_mass``, ``lumped_mass_offset`` and ``lumped_mass_inertia`` (body axes of the jig).

    Parameters
    ----------
    beams : sequence of Beam
        The beams.
    joints : sequence of Joint
        The joints.
    masses : sequence of LumpedMass
        The lumped masses.

    Returns
    -------
    list of VarSpec
        The parameter blocks, in packing order.
    """
    specs = []
    for b in beams:
        specs += [VarSpec(f"{b.name}_{s.name}", s.shape, s.units, f"{b.name}: {s.desc}")
                  for s in beam_param_specs(b.num_nodes)]
    specs.append(VarSpec("joint_rotational_stiffness", (len(joints),), "N*m/rad",
                         "rotational spring stiffness of each hinge (unused for rigid joints and free hinges)"))
    n_mass = len(masses)
    specs += [VarSpec("lumped_mass", (n_mass,), "kg", "mass of each lumped mass"),
              VarSpec("lumped_mass_offset", (n_mass, 3), "m",
                      "centre of each lumped mass from its node, body axes of the jig"),
              VarSpec("lumped_mass_inertia", (n_mass, 3, 3), "kg*m**2",
                      "rotary inertia of each lumped mass about its centre, body axes of the jig")]
    return specs


def forcing_specs(beams) -> list[VarSpec]:
    """Forcing of the joined system: every beam's loads (``<beam>_<block>``), then gravity and the
    motion of the body axes, shared by all beams.

    Parameters
    ----------
    beams : sequence of Beam
        The beams.

    Returns
    -------
    list of VarSpec
        The forcing blocks, in packing order.
    """
    specs = []
    for b in beams:
        specs += [VarSpec(f"{b.name}_{s.name}", s.shape, s.units, f"{b.name}: {s.desc}")
                  for s in beam_forcing_specs(b.num_nodes) if s.name in _BEAM_FORCING]
    specs += [s for s in beam_forcing_specs(2) if s.name in _SHARED_FORCING]
    return specs


def _axial(C):
    """Axial vector of (C - C^T) / 2: sin(angle) times the unit axis of the rotation C."""
    return 0.5 * ca.vertcat(C[2, 1] - C[1, 2], C[0, 2] - C[2, 0], C[1, 0] - C[0, 1])


def _normals(axis):
    """Two unit vectors normal to ``axis`` and to each other."""
    a = np.asarray(axis, dtype=float)
    helper = np.eye(3)[int(np.argmin(np.abs(a)))]
    b1 = np.cross(a, helper)
    b1 /= np.linalg.norm(b1)
    return b1, np.cross(a, b1)


def _node_rotation(theta, theta0, R, sequence):
    """Lambda = R^T T(theta)^T T(theta_0) R: the rotation from the jig to the deformed frame of a
    node, body components (``R``: body -> the beam's axes, DM)."""
    lam = body_to_csn(theta, sequence).T @ body_to_csn(theta0, sequence)
    return R.T @ lam @ R


def joint_equations(joint, node_a, node_b, loads, stiffness, sequence="surface"):
    """The 12 residuals of ``joint`` (module docstring): force and moment transfer, equal positions,
    orientation (rigid: 3 rows; hinge: 2 rows and the hinge law). ``node_a``, ``node_b``:
    ``(x, theta_0, R)`` of the two nodes: the 18 states and jig Euler angles in the beam's axes and
    the beam's rotation R (body -> beam axes); ``loads``: the 12 joint unknowns (body axes);
    ``stiffness``: the spring stiffness (hinges with a spring).

    Parameters
    ----------
    joint : Joint
        The joint.
    node_a : tuple
        ``(x, theta_0, R)`` of the node on beam A.
    node_b : tuple
        ``(x, theta_0, R)`` of the node on beam B.
    loads : casadi.SX, shape (12,)
        Joint unknowns: force and moment on A, force and moment on B (body axes).
    stiffness : casadi.SX
        Rotational spring stiffness (N m/rad), used by a hinge with a spring.
    sequence : str
        Euler-angle sequence.

    Returns
    -------
    casadi.SX, shape (12,)
        The residuals.
    """
    st, jb = STATE_BLOCKS, JOINT_BLOCKS
    (x_a, th0_a, R_a), (x_b, th0_b, R_b) = node_a, node_b
    lam_a = _node_rotation(x_a[st["theta"]], th0_a, R_a, sequence)
    lam_b = _node_rotation(x_b[st["theta"]], th0_b, R_b, sequence)
    C = lam_a.T @ lam_b
    w = _axial(C)
    if joint.kind == "rigid":
        orientation = w
    else:
        a = np.asarray(joint.axis, dtype=float)
        b1, b2 = _normals(a)
        hinge_angle = ca.atan2(ca.dot(ca.DM(a), w), 0.5 * (ca.trace(C) - 1.0))
        spring = 0.0 if joint.stiffness is None else stiffness * hinge_angle
        law = ca.dot(lam_a @ ca.DM(a), loads[jb["moment_b"]]) + spring
        orientation = ca.vertcat(ca.dot(ca.DM(b1), w), ca.dot(ca.DM(b2), w), law)
    return ca.vertcat(loads[jb["force_a"]] + loads[jb["force_b"]],
                      loads[jb["moment_a"]] + loads[jb["moment_b"]],
                      R_b.T @ x_b[st["r"]] - R_a.T @ x_a[st["r"]],
                      orientation)


def lumped_mass_loads(node, xdot, mass, offset, inertia, g, frame, sequence="surface"):
    """Point force and moment (the beam's axes) of a rigid lumped mass on a node: its weight and
    d'Alembert load, ``P = m (g - a_c)`` and ``Q = d x P - (J w_dot + w x J w)``.

    ``node``: ``(x, theta_0, R)`` as in :func:`joint_equations`, ``xdot`` the node's 18 rates;
    ``mass``, ``offset`` (3, body axes of the jig) and ``inertia`` (9, row-major, body axes of the
    jig); ``g`` and ``frame`` (A0, Omega, alpha0) in the beam's axes. The offset and the inertia
    turn with the node: ``d = Lambda R d_0``, ``J = Lambda R J_0 R^T Lambda^T`` with
    ``Lambda = T(theta)^T T(theta_0)`` (the beam's axes); ``a_c = a + w_dot x d + w x (w x d)``
    with the node's acceleration ``a`` (:func:`~wingmdao.beam.residual.nodal_acceleration`),
    ``w = Omega + omega`` and ``w_dot = alpha0 + omega_dot + Omega x omega``, as the beam's elements
    take them (docs/stick-model.md, "Lumped masses").

    Parameters
    ----------
    node : tuple
        ``(x, theta_0, R)`` of the node.
    xdot : casadi.SX, shape (18,)
        State rates of the node.
    mass : casadi.SX
        Mass (kg).
    offset : casadi.SX, shape (3,)
        Centre offset from the node (m), body axes of the jig.
    inertia : casadi.SX, shape (9,)
        Rotary inertia about the centre (kg m^2), row-major, body axes of the jig.
    g : casadi.SX, shape (3,)
        Gravity (m/s^2), the beam's axes.
    frame : tuple of casadi.SX
        ``(A0, Omega, alpha0)`` of the body axes (m/s^2, rad/s, rad/s^2), the beam's axes.
    sequence : str
        Euler-angle sequence.

    Returns
    -------
    force : casadi.SX, shape (3,)
        Point force P on the node (N), the beam's axes.
    moment : casadi.SX, shape (3,)
        Point moment Q on the node (N m), the beam's axes.
    """
    st = STATE_BLOCKS
    x, theta0, R = node
    lam = body_to_csn(x[st["theta"]], sequence).T @ body_to_csn(theta0, sequence)
    d = lam @ (R @ offset)
    J = lam @ R @ ca.reshape(inertia, 3, 3).T @ R.T @ lam.T     # row-major entries
    acc = nodal_acceleration(x[st["r"]], x[st["u"]], xdot[st["u"]], frame)
    w = frame[1] + x[st["omega"]]
    wdot = frame[2] + xdot[st["omega"]] + ca.cross(frame[1], x[st["omega"]])
    acc_c = acc + ca.cross(wdot, d) + ca.cross(w, ca.cross(w, d))
    force = mass * (g - acc_c)
    moment = ca.cross(d, force) - (J @ wdot + ca.cross(w, J @ w))
    return force, moment


def symmetry_equations(node, r0, reactions, sequence="surface"):
    """The 3 residuals of a :class:`Symmetry` condition and the node's point loads from its 3
    reactions. ``node``: ``(x, theta_0, R)``; ``r0`` the node's jig position (beam axes);
    ``reactions``: the mirror half's force along body y and moments about body x and z.

    Rows: the body-y displacement ``e_y . R^T (r - r_0) = 0`` and the roll and yaw parts of the
    node's rotation from the jig, ``w_x = 0``, ``w_z = 0`` with ``w = axial(Lambda - Lambda^T) / 2``
    (``Lambda = R^T T(theta)^T T(theta_0) R``, body components), as the joints' orientation rows.
    Loads on the node (beam axes): ``R (0, f_y, 0)`` and ``R (m_x, 0, m_z)``.

    Parameters
    ----------
    node : tuple
        ``(x, theta_0, R)`` of the node.
    r0 : casadi.SX or ndarray, shape (3,)
        Jig position of the node (m), the beam's axes.
    reactions : casadi.SX, shape (3,)
        Force along body y (N), moments about body x and z (N m).
    sequence : str
        Euler-angle sequence.

    Returns
    -------
    rows : casadi.SX, shape (3,)
        The residuals.
    force : casadi.SX, shape (3,)
        Point force on the node (N), the beam's axes.
    moment : casadi.SX, shape (3,)
        Point moment on the node (N m), the beam's axes.
    """
    st = STATE_BLOCKS
    x, theta0, R = node
    w = _axial(_node_rotation(x[st["theta"]], theta0, R, sequence))
    disp = R.T @ (x[st["r"]] - r0)
    rows = ca.vertcat(disp[1], w[0], w[2])
    force = R @ ca.vertcat(0.0, reactions[0], 0.0)
    moment = R @ ca.vertcat(reactions[1], 0.0, reactions[2])
    return rows, force, moment


class JoinedBeamSystem(CasadiResidualSystem):
    """The residual system of :func:`build_joined_system` with its layout and packing helpers.

    Attributes: ``beams``, ``joints``, ``masses``, ``symmetry`` (node indices resolved from the
    root), ``offsets`` (``{beam: first state index}``), ``joint_offset`` (first joint unknown),
    ``symmetry_offset`` (first symmetry reaction).

    Parameters
    ----------
    beams : sequence of Beam
        The beams.
    joints : sequence of Joint
        The joints (nodes resolved from the root).
    offsets : dict of str to int
        First state index of each beam.
    joint_offset : int
        First state index of the joint unknowns.
    *args
        Positional arguments of :class:`~wingmdao.timemarch.system.CasadiResidualSystem`.
    masses : sequence of LumpedMass
        The lumped masses.
    symmetry : sequence of Symmetry
        The symmetry conditions.
    **kwargs
        Keyword arguments of :class:`~wingmdao.timemarch.system.CasadiResidualSystem`.
    """

    def __init__(self, beams, joints, offsets, joint_offset, *args, masses=(), symmetry=(), **kwargs):
        self.beams, self.joints = tuple(beams), tuple(joints)
        self.masses, self.symmetry = tuple(masses), tuple(symmetry)
        self.offsets, self.joint_offset = dict(offsets), int(joint_offset)
        self.symmetry_offset = self.joint_offset + N_JOINT * len(self.joints)
        super().__init__(*args, **kwargs)

    def beam(self, name) -> Beam:
        """The :class:`Beam` named ``name`` (ValueError if there is none).

        Parameters
        ----------
        name : str
            Name of the beam.

        Returns
        -------
        Beam
            The beam.
        """
        for b in self.beams:
            if b.name == name:
                return b
        raise ValueError(f"no beam {name!r}; beams are {[b.name for b in self.beams]}")

    def node_index(self, name, node) -> int:
        """First state index of node ``node`` of beam ``name``.

        Parameters
        ----------
        name : str
            Name of the beam.
        node : int
            Node index (negative from the tip).

        Returns
        -------
        int
            Index of the node's first state.
        """
        b = self.beam(name)
        if not -b.num_nodes <= int(node) < b.num_nodes:
            raise ValueError(f"beam {name!r} has nodes 0..{b.num_nodes - 1}, got node {node}")
        return self.offsets[name] + N_STATE_PER_NODE * (int(node) % b.num_nodes)

    def unpack(self, x, body_axes: bool = False) -> dict:
        """``{beam: {'r', 'theta', 'F', 'M', 'u', 'omega'} (n, 3) arrays}`` in each beam's axes (with
        ``body_axes``: r, F, M, u, omega in body axes; theta stays the beam's Euler angles) and
        ``'joints'``: ``{'force_a', 'moment_a', 'force_b', 'moment_b'}`` (n_joint, 3) arrays, body axes;
        ``'symmetry'``: (n_symmetry, 3) reactions (force y, moment x, moment z, body axes).

        Parameters
        ----------
        x : array_like, shape (n_state,)
            State of the joined system.
        body_axes : bool
            Give r, F, M, u, omega in body axes instead of each beam's axes.

        Returns
        -------
        dict
            The blocks described above.
        """
        x = np.asarray(x, dtype=float).reshape(self.n_state)
        out = {}
        for b in self.beams:
            blk = x[self.offsets[b.name]: self.offsets[b.name] + N_STATE_PER_NODE * b.num_nodes]
            blk = blk.reshape(b.num_nodes, N_STATE_PER_NODE)
            out[b.name] = {k: blk[:, s].copy() for k, s in STATE_BLOCKS.items()}
            if body_axes and b.axes is not None:
                for k in ("r", "F", "M", "u", "omega"):
                    out[b.name][k] = out[b.name][k] @ b.rotation
        jl = x[self.joint_offset:self.symmetry_offset].reshape(len(self.joints), N_JOINT)
        out["joints"] = {k: jl[:, s].copy() for k, s in JOINT_BLOCKS.items()}
        out["symmetry"] = x[self.symmetry_offset:self.symmetry_offset + N_SYMMETRY * len(self.symmetry)].reshape(
            len(self.symmetry), N_SYMMETRY).copy()
        return out

    def linear_momentum(self, x, p) -> np.ndarray:
        """Linear momentum (kg*m/s, body axes, relative to the body axes) of a state: every element's
        ``mu ds (u_a + u_b) / 2`` (mass centres on the beam axis) and every lumped mass's ``m u`` (at
        its node; offsets are not counted). The discrete BDF march of a free structure with no
        external force conserves it exactly (docs/stick-model.md, "Free flight").

        Parameters
        ----------
        x : array_like, shape (n_state,)
            State.
        p : array_like, shape (n_param,)
            Packed parameters.

        Returns
        -------
        ndarray, shape (3,)
            The linear momentum (kg m/s).
        """
        parts = self.unpack(x, body_axes=True)
        lay = layout(self.param_specs)
        p = np.asarray(p, dtype=float)
        total = np.zeros(3)
        for b in self.beams:
            r0 = p[lay[f"{b.name}_node_positions"]].reshape(b.num_nodes, 3)
            mu = p[lay[f"{b.name}_mass_per_length"]]
            ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
            u = parts[b.name]["u"]
            total += np.sum((0.5 * (mu[:-1] + mu[1:]) * ds)[:, None] * 0.5 * (u[:-1] + u[1:]), axis=0)
        masses = p[lay["lumped_mass"]]
        for lm, m in zip(self.masses, masses):
            total += m * parts[lm.beam]["u"][lm.node]
        return total

    def pack_parameters(self, beam_params: dict) -> np.ndarray:
        """Packed parameters from ``{beam: parameter dict}`` (:func:`wingmdao.beam.static.beam_parameters`)
        and the joints' stiffnesses; checks every beam's data
        (:func:`~wingmdao.beam.static.check_beam_parameters`) and that the two nodes of every joint
        coincide in the jig (ValueError naming the joint and the distance).

        Parameters
        ----------
        beam_params : dict
            ``{beam name: parameter dict}`` for every beam.

        Returns
        -------
        ndarray
            Packed parameters of the structure.
        """
        unknown = set(beam_params) - {b.name for b in self.beams}
        if unknown:
            raise ValueError(f"parameters for unknown beams {sorted(unknown)}; beams are {[b.name for b in self.beams]}")
        values = {}
        for b in self.beams:
            if b.name not in beam_params:
                raise ValueError(f"no parameters for beam {b.name!r}")
            prm = beam_params[b.name]
            r0 = np.asarray(prm["node_positions"], dtype=float)
            if r0.shape != (b.num_nodes, 3):
                raise ValueError(f"beam {b.name!r}: node_positions must have shape {(b.num_nodes, 3)}, got {r0.shape}")
            check_beam_parameters(prm)
            for s in beam_param_specs(b.num_nodes):
                values[f"{b.name}_{s.name}"] = prm[s.name]
        for jt in self.joints:
            ra = self.beam(jt.beam_a).rotation.T @ np.asarray(beam_params[jt.beam_a]["node_positions"], float)[jt.node_a]
            rb = self.beam(jt.beam_b).rotation.T @ np.asarray(beam_params[jt.beam_b]["node_positions"], float)[jt.node_b]
            gap = float(np.linalg.norm(ra - rb))
            if gap > POSITION_TOLERANCE:
                raise ValueError(f"{jt.label}: the beams do not meet at the joint: the nodes are {gap:.6g} m "
                                 f"apart in the jig ({ra} and {rb}, body axes); a joint needs coincident nodes "
                                 f"(within {POSITION_TOLERANCE} m)")
        for sy in self.symmetry:
            r = self.beam(sy.beam).rotation.T @ np.asarray(beam_params[sy.beam]["node_positions"], float)[sy.node]
            if abs(r[1]) > POSITION_TOLERANCE:
                raise ValueError(f"{sy.label}: the node is not on the plane of symmetry: its jig position is "
                                 f"y = {r[1]:.6g} m (body axes); it must be 0 (within {POSITION_TOLERANCE} m)")
        values["joint_rotational_stiffness"] = [0.0 if jt.stiffness is None else jt.stiffness for jt in self.joints]
        values["lumped_mass"] = [lm.mass for lm in self.masses]
        values["lumped_mass_offset"] = np.reshape([lm.offset for lm in self.masses], (len(self.masses), 3))
        values["lumped_mass_inertia"] = np.reshape([lm.inertia for lm in self.masses], (len(self.masses), 3, 3))
        return pack([s for s in self.param_specs if s.name in values], values)   # the structure's (first) blocks

    def pack_forcing(self, beam_loads: dict | None = None, **shared) -> np.ndarray:
        """Packed forcing from ``{beam: {block: array}}`` (blocks of
        :func:`wingmdao.beam.static.beam_forcing`, zero if absent) and the shared blocks
        (``gravity``, ``frame_acceleration``, ...).

        Parameters
        ----------
        beam_loads : dict, optional
            ``{beam name: {block: array}}``.
        **shared
            Shared forcing blocks (``gravity``, ``frame_acceleration``, ...; zero if absent).

        Returns
        -------
        ndarray
            Packed forcing of the structure.
        """
        beam_loads = beam_loads or {}
        unknown = set(beam_loads) - {b.name for b in self.beams}
        if unknown:
            raise ValueError(f"loads for unknown beams {sorted(unknown)}; beams are {[b.name for b in self.beams]}")
        values = {}
        for b in self.beams:
            loads = dict(beam_loads.get(b.name, {}))
            bad = set(loads) - set(_BEAM_FORCING)
            if bad:
                raise ValueError(f"beam {b.name!r}: unknown loads {sorted(bad)}; allowed: {list(_BEAM_FORCING)}")
            full = beam_forcing(b.num_nodes, **loads)
            values.update({f"{b.name}_{k}": full[k] for k in _BEAM_FORCING})
        bad = set(shared) - set(_SHARED_FORCING)
        if bad:
            raise ValueError(f"unknown shared forcing {sorted(bad)}; allowed: {list(_SHARED_FORCING)}")
        values.update({k: np.asarray(shared.get(k, np.zeros(3)), dtype=float) for k in _SHARED_FORCING})
        return pack([s for s in self.forcing_specs if s.name in values], values)  # the structure's (first) blocks

    def jig_state(self, p) -> np.ndarray:
        """The unloaded jig state (every beam's jig, joint loads zero).

        Parameters
        ----------
        p : array_like, shape (n_param,)
            Packed parameters.

        Returns
        -------
        ndarray, shape (n_state,)
            The jig state.
        """
        return _jig_guess(self, p, None)


def _jig_guess(system, p, q=None):
    p = np.asarray(p, dtype=float)
    lay = layout(system.param_specs)
    x = np.zeros(system.n_state)
    for b in system.beams:
        prm = {k: p[lay[f"{b.name}_{k}"]] for k in ("node_positions", "node_euler_angles")}
        x[system.offsets[b.name]: system.offsets[b.name] + N_STATE_PER_NODE * b.num_nodes] = \
            beam_jig_state(prm).ravel()
    return x


def describe_joined_equation(index, beams, joints, offsets, joint_offset, symmetry=()) -> str:
    """Name of residual ``index`` of a joined system, e.g. 'beam wing: node 3 ..., moment equilibrium z'.

    Parameters
    ----------
    index : int
        Residual index.
    beams : sequence of Beam
        The beams.
    joints : sequence of Joint
        The joints.
    offsets : dict of str to int
        First state index of each beam.
    joint_offset : int
        First state index of the joint unknowns.
    symmetry : sequence of Symmetry
        The symmetry conditions.

    Returns
    -------
    str
        The name.
    """
    index = int(index)
    symmetry_offset = joint_offset + N_JOINT * len(joints)
    if index >= symmetry_offset:
        k, c = divmod(index - symmetry_offset, N_SYMMETRY)
        if k >= len(symmetry):
            raise ValueError(f"equation index must be in [0, {symmetry_offset + N_SYMMETRY * len(symmetry)}), "
                             f"got {index}")
        return f"{symmetry[k].label}, {SYMMETRY_HELD[c]} held"
    if index >= joint_offset:
        j, k = divmod(index - joint_offset, N_JOINT)
        jt = joints[j]
        names = ["force transfer", "moment transfer", "equal position"]
        if k < 9:
            kind = f"{names[k // 3]} {_XYZ[k % 3]}"
        elif jt.kind == "rigid":
            kind = f"equal orientation {_XYZ[k - 9]}"
        else:
            kind = ("hinge: no rotation normal to the axis", "hinge: no rotation normal to the axis",
                    "hinge spring law" if jt.stiffness is not None else "hinge: no moment about the axis")[k - 9]
        return f"{jt.label} ({jt.kind}), {kind}"
    for b in beams:
        start = offsets[b.name]
        if start <= index < start + N_STATE_PER_NODE * b.num_nodes:
            local = index - start
            node, k = divmod(local, N_STATE_PER_NODE)
            if b.root == "free" and node == b.num_nodes - 1 and k < 6:
                return f"beam {b.name}: root node 0, free root {'force' if k < 3 else 'moment'} {_XYZ[k % 3]}"
            return f"beam {b.name}: {beam_equation(local, b.num_nodes)}"
    raise ValueError(f"equation index must be >= 0, got {index}")


def joined_definition(beams, joints, euler_sequence="surface", damping=None, masses=(), symmetry=()) -> str:
    """What defines the functions of :func:`build_joined_system` (key of their compiled libraries):
    the lumped masses' nodes count, their values (parameters) do not.

    Parameters
    ----------
    beams : sequence of Beam
        The beams.
    joints : sequence of Joint
        The joints.
    euler_sequence : str
        Euler-angle sequence.
    damping : StrainRateDamping, optional
        Strain-rate damping (zero damping counts as None).
    masses : sequence of LumpedMass
        The lumped masses (their nodes enter the key).
    symmetry : sequence of Symmetry
        The symmetry conditions.

    Returns
    -------
    str
        The definition key.
    """
    if damping is not None and damping.is_zero:
        damping = None
    args = (tuple(beams), tuple(joints), str(euler_sequence),
            None if damping is None else (damping.curvature, damping.strain))
    if masses or symmetry:
        args += (tuple((lm.beam, lm.node) for lm in masses), tuple(symmetry))
    return definition_key("wingmdao.beam.joints.build_joined_system", args, _GENERATING_MODULES)


def build_joined_system(beams, joints, *, euler_sequence: str = "surface",
                        damping: StrainRateDamping | None = None, masses=(), symmetry=()) -> JoinedBeamSystem:
    """The beams ``beams`` (:class:`Beam`) joined by ``joints`` (:class:`Joint`) as one
    :class:`JoinedBeamSystem` (a :class:`~wingmdao.timemarch.system.CasadiResidualSystem`: the
    BDF march, the static solve, the discrete adjoint and the stability linearization run on it),
    with lumped masses on nodes (``masses``, :class:`LumpedMass`) and symmetry conditions of a
    free half aircraft (``symmetry``, :class:`Symmetry`; 3 unknowns each, after the joints').

    Raises ValueError for an unknown beam, a node that does not exist, two joints on one node
    pair, a beam connected to no other, two symmetry conditions on one node or one on a system
    with a clamped beam. The jig positions of the joined nodes and of the symmetry nodes are
    checked when the parameters are packed (:meth:`JoinedBeamSystem.pack_parameters`).

    Parameters
    ----------
    beams : sequence of Beam
        The beams.
    joints : sequence of Joint
        The joints.
    euler_sequence : str
        Euler-angle sequence.
    damping : StrainRateDamping, optional
        Strain-rate damping of every beam.
    masses : sequence of LumpedMass
        The lumped masses.
    symmetry : sequence of Symmetry
        The symmetry conditions.

    Returns
    -------
    JoinedBeamSystem
        The residual system.
    """
    return build_extended_joined_system(beams, joints, euler_sequence=euler_sequence, damping=damping,
                                        masses=masses, symmetry=symmetry)


def build_extended_joined_system(beams, joints, *, euler_sequence="surface", damping=None, masses=(), symmetry=(),
                                 extension=None) -> JoinedBeamSystem:
    """:func:`build_joined_system` with an optional ``extension`` of its residual (the
    aerodynamics of :mod:`wingmdao.aero.joined` use it).

    Parameters
    ----------
    beams, joints, euler_sequence, damping, masses, symmetry
        As for :func:`build_joined_system`.
    extension : object, optional
        An object with ``n_states`` (unknowns appended after the symmetry reactions),
        ``param_specs`` and ``forcing_specs`` (appended), ``definition(base)`` (the system's
        definition key from the structure's), ``describe(k)`` (name of its row k) and
        ``apply(nodes, x, xdot, p, q, play, qlay, n_struct)``, which may add loads to the nodes'
        forcing (``nodes[beam]["q"][i]``, beam axes, N and N m) before the residual is assembled
        and returns its residual rows (``n_states`` of them). None: the structure alone.

    Returns
    -------
    JoinedBeamSystem
        The joined system, with the extension's states, parameters and residual rows.
    """
    t_start = time.perf_counter()
    beams, joints, masses, symmetry = _check_layout(beams, joints, masses, symmetry)
    if damping is not None and damping.is_zero:
        damping = None
    pspecs, qspecs = param_specs(beams, joints, masses), forcing_specs(beams)
    if extension is not None:
        pspecs, qspecs = pspecs + list(extension.param_specs), qspecs + list(extension.forcing_specs)
    offsets, start = {}, 0
    for b in beams:
        offsets[b.name] = start
        start += N_STATE_PER_NODE * b.num_nodes
    joint_offset = start
    symmetry_offset = joint_offset + N_JOINT * len(joints)
    n_struct = symmetry_offset + N_SYMMETRY * len(symmetry)
    n_state = n_struct + (0 if extension is None else int(extension.n_states))
    x, xdot = ca.SX.sym("x", n_state), ca.SX.sym("xdot", n_state)
    p = ca.SX.sym("p", sum(s.size for s in pspecs))
    q = ca.SX.sym("q", sum(s.size for s in qspecs))
    play = layout(pspecs)
    nodes = {b.name: _beam_nodes(b, x, xdot, p, q, offsets[b.name], play, layout(qspecs)) for b in beams}
    for k, lm in enumerate(masses):          # lumped masses: point loads of their nodes
        nd = nodes[lm.beam]
        force, moment = lumped_mass_loads(
            (nd["x"][lm.node], nd["p"][lm.node][NODE_PARAMS["theta0"]], nd["R"]), nd["xdot"][lm.node],
            p[play["lumped_mass"]][k], p[play["lumped_mass_offset"]][3 * k:3 * k + 3],
            p[play["lumped_mass_inertia"]][9 * k:9 * k + 9], nd["g"], nd["frame"], euler_sequence)
        nd["q"][lm.node] = nd["q"][lm.node] + ca.vertcat(ca.SX.zeros(6), force, moment)
    symmetry_rows = []
    for k, sy in enumerate(symmetry):         # symmetry reactions: point loads of their nodes
        nd = nodes[sy.beam]
        rows, force, moment = symmetry_equations(
            (nd["x"][sy.node], nd["p"][sy.node][NODE_PARAMS["theta0"]], nd["R"]),
            nd["p"][sy.node][NODE_PARAMS["r0"]], x[symmetry_offset + 3 * k: symmetry_offset + 3 * k + 3],
            euler_sequence)
        nd["q"][sy.node] = nd["q"][sy.node] + ca.vertcat(ca.SX.zeros(6), force, moment)
        symmetry_rows.append(rows)
    extra_rows = None if extension is None else extension.apply(nodes, x, xdot, p, q, play, layout(qspecs), n_struct)
    loads = [x[joint_offset + N_JOINT * j: joint_offset + N_JOINT * (j + 1)] for j in range(len(joints))]
    for jt, jl in zip(joints, loads):         # the joint loads are point loads of their two nodes
        for name, node, f, m in ((jt.beam_a, jt.node_a, "force_a", "moment_a"),
                                 (jt.beam_b, jt.node_b, "force_b", "moment_b")):
            R = ca.DM(next(b for b in beams if b.name == name).rotation)
            nodes[name]["q"][node] = nodes[name]["q"][node] + ca.vertcat(
                ca.SX.zeros(6), R @ jl[JOINT_BLOCKS[f]], R @ jl[JOINT_BLOCKS[m]])
    elem = element_function(euler_sequence, damping)
    nodal = nodal_function(euler_sequence)
    blocks = [_beam_residual(b, nodes[b.name], elem, nodal) for b in beams]
    stiffness = p[layout(pspecs)["joint_rotational_stiffness"]]
    for j, (jt, jl) in enumerate(zip(joints, loads)):
        ends = [(nodes[name]["x"][node], nodes[name]["p"][node][NODE_PARAMS["theta0"]], nodes[name]["R"])
                for name, node in ((jt.beam_a, jt.node_a), (jt.beam_b, jt.node_b))]
        blocks.append(joint_equations(jt, ends[0], ends[1], jl, stiffness[j], euler_sequence))
    blocks += symmetry_rows
    describe = functools.partial(describe_joined_equation, beams=beams, joints=joints, offsets=offsets,
                                 joint_offset=joint_offset, symmetry=symmetry)
    definition = joined_definition(beams, joints, euler_sequence, damping, masses, symmetry)
    if extension is not None:
        blocks.append(extra_rows)
        describe = functools.partial(_describe_extended, base=describe, n_struct=n_struct, extension=extension)
        definition = extension.definition(definition)
    first = {b.name: offsets[b.name] // N_STATE_PER_NODE for b in beams}
    order = lu_orders.joined_lu_column_order([b.num_nodes for b in beams],
                                             [(first[jt.beam_a] + jt.node_a, first[jt.beam_b] + jt.node_b)
                                              for jt in joints],
                                             [first[sy.beam] + sy.node for sy in symmetry])
    order = np.concatenate([np.asarray(order, dtype=np.int64), np.arange(n_struct, n_state, dtype=np.int64)])
    system = JoinedBeamSystem(beams, joints, offsets, joint_offset, x, xdot, p, q, ca.vertcat(*blocks),
                              param_specs=pspecs, forcing_specs=qspecs, state_shape=(n_state,),
                              name=f"joined{len(beams)}b{len(joints)}j{n_state}", describe=describe,
                              definition=definition,
                              lu_column_order=order, masses=masses, symmetry=symmetry)
    system._initial_guess = functools.partial(_jig_guess, system)
    system.euler_sequence = euler_sequence
    system.n_struct = n_struct
    system.build_time = time.perf_counter() - t_start
    return system


def _describe_extended(index, base, n_struct, extension):
    return base(index) if index < n_struct else extension.describe(index - n_struct)


def _beam_nodes(beam, x, xdot, p, q, offset, play, qlay) -> dict:
    """Per-node symbols of one beam: states ``x``, rates ``xdot``, the 34 parameters ``p`` and 12
    loads ``q`` of the element function (loads in the beam's axes), the shared gravity and frame
    motion turned into the beam's axes (``g``, ``frame``) and its rotation ``R`` (DM)."""
    n = beam.num_nodes
    specs, fspecs = beam_param_specs(n), beam_forcing_specs(n)
    pb = ca.vertcat(*[p[play[f"{beam.name}_{s.name}"]] for s in specs])
    qb = ca.vertcat(*[q[qlay[f"{beam.name}_{s.name}"]] if s.name in _BEAM_FORCING else ca.SX.zeros(s.size)
                      for s in fspecs])
    R = ca.DM(beam.rotation)
    blay, flay = layout(specs), layout(fspecs)
    return {"x": [x[offset + 18 * i: offset + 18 * (i + 1)] for i in range(n)],
            "xdot": [xdot[offset + 18 * i: offset + 18 * (i + 1)] for i in range(n)],
            "p": [node_params(pb, blay, i) for i in range(n)],
            "q": [node_forcing(qb, flay, i) for i in range(n)],
            "g": R @ q[qlay["gravity"]],
            "frame": tuple(R @ q[qlay[k]] for k in ("frame_acceleration", "frame_angular_velocity",
                                                    "frame_angular_acceleration")),
            "R": R}


def _beam_residual(beam, nd, elem, nodal):
    """The 18 n residuals of one beam in the single beam's row order: element rows, the root and
    tip rows in the last node's block (clamped root: r, theta at the jig; free root: F = M = 0;
    tip: F, M = the tip's point loads, joint loads included), the two kinematic rows per node."""
    st, n = STATE_BLOCKS, beam.num_nodes
    X, Xd, P, Q = nd["x"], nd["xdot"], nd["p"], nd["q"]
    blocks = []
    for i in range(n):
        if i < n - 1:
            blocks.append(elem(X[i], X[i + 1], Xd[i], Xd[i + 1], P[i], P[i + 1], Q[i], Q[i + 1], nd["g"], *nd["frame"]))
        else:
            if beam.root == "clamped":
                root = ca.vertcat(X[0][st["r"]] - P[0][NODE_PARAMS["r0"]], X[0][st["theta"]] - P[0][NODE_PARAMS["theta0"]])
            else:
                root = FREE_ROOT_ROW_SCALE * ca.vertcat(X[0][st["F"]], X[0][st["M"]])
            blocks.append(ca.vertcat(root, X[i][st["F"]] - Q[i][NODE_FORCING["P"]], X[i][st["M"]] - Q[i][NODE_FORCING["Q"]]))
        blocks.append(nodal(X[i], Xd[i]))
    return ca.vertcat(*blocks)


#: Rigid-body accelerations of the body axes an inertia-relief solve may take as unknowns: the
#: components of ``frame_acceleration`` (m/s^2) and ``frame_angular_acceleration`` (rad/s^2).
FRAME_ACCELERATIONS = {"ax": ("frame_acceleration", 0), "ay": ("frame_acceleration", 1),
                       "az": ("frame_acceleration", 2), "alpha_x": ("frame_angular_acceleration", 0),
                       "alpha_y": ("frame_angular_acceleration", 1), "alpha_z": ("frame_angular_acceleration", 2)}
#: The accelerations and supports of a symmetric half aircraft (surge, plunge, pitch).
HALF_AIRCRAFT_ACCELERATIONS = ("ax", "az", "alpha_y")


def solve_inertia_relief(system, p, q, supports, accelerations=HALF_AIRCRAFT_ACCELERATIONS, *, x0=None,
                         rtol=1e-10, max_iter=30) -> tuple[np.ndarray, dict]:
    """Static equilibrium of a free structure in uniformly accelerated rigid-body motion (inertia
    relief): the body axes accelerate (the ``accelerations``, unknowns, keys of
    :data:`FRAME_ACCELERATIONS`) so that the external loads, weight and inertial loads balance,
    and the structure deforms in those axes; ``supports`` (``(beam, node, component)`` with
    component ``"x"``, ``"y"`` or ``"z"``: that body-axes displacement of the node held at the jig,
    one per acceleration) fix its rigid-body position without loading it (their reactions are zero
    at the balance: a statically determinate support, as Nastran's SUPORT).

    Newton on ``R(x, 0, p, q(a)) = 0`` with the support rows, from ``x0`` (default the jig). Returns
    the state and ``{name: acceleration}``. ValueError for supports that do not hold the
    structure's rigid-body modes (a singular matrix), a count that differs from the accelerations',
    unknown names, or no convergence.

    Parameters
    ----------
    system : JoinedBeamSystem
        The free structure.
    p : array_like, shape (n_param,)
        Packed parameters.
    q : array_like, shape (n_forcing,)
        Packed forcing (its accelerations are the starting values).
    supports : sequence of tuple
        ``(beam, node, component)``, one per acceleration.
    accelerations : sequence of str
        Names of the unknown accelerations (keys of :data:`FRAME_ACCELERATIONS`).
    x0 : array_like, shape (n_state,), optional
        Initial guess; default the jig.
    rtol : float
        Convergence tolerance on ``max|R|`` relative to its first value (at least 1).
    max_iter : int
        Most Newton iterations.

    Returns
    -------
    x : ndarray, shape (n_state,)
        The state.
    accelerations : dict of str to float
        The accelerations (m/s^2, rad/s^2).
    """
    bad = [a for a in accelerations if a not in FRAME_ACCELERATIONS]
    if bad or len(set(accelerations)) != len(accelerations):
        raise ValueError(f"accelerations must be distinct names of {list(FRAME_ACCELERATIONS)}, got {list(accelerations)}")
    if len(supports) != len(accelerations):
        raise ValueError(f"{len(supports)} supports for {len(accelerations)} accelerations: a statically determinate "
                         f"support has one per acceleration")
    qlay = layout(system.forcing_specs)
    q_cols = [qlay[FRAME_ACCELERATIONS[a][0]].start + FRAME_ACCELERATIONS[a][1] for a in accelerations]
    n = system.n_state
    rows, cols, vals = [], [], []
    for k, sup in enumerate(supports):
        name, node, comp = sup
        if comp not in _XYZ:
            raise ValueError(f"support {sup}: component must be 'x', 'y' or 'z' (body axes), got {comp!r}")
        i0 = system.node_index(name, node) + STATE_BLOCKS["r"].start
        direction = system.beam(name).rotation @ np.eye(3)[_XYZ.index(comp)]      # body direction, beam axes
        for c in range(3):
            if direction[c] != 0.0:
                rows.append(k)
                cols.append(i0 + c)
                vals.append(direction[c])
    C = sp.csr_matrix((vals, (rows, cols)), shape=(len(supports), n))
    p = np.asarray(p, dtype=float)
    q = np.asarray(q, dtype=float).copy()
    x = system.initial_guess(p, q) if x0 is None else np.asarray(x0, dtype=float).copy()
    c0 = C @ system.jig_state(p)
    xdot = np.zeros(n)
    scale = None
    for _ in range(max_iter):
        jx = system.jac_state(x, xdot, p, q)[0]
        jq = system.jac_inputs(x, xdot, p, q)[1][:, q_cols]
        K = sp.bmat([[jx, jq], [C, None]], format="csc")
        try:       # factored before the convergence test: bad supports are refused even without load
            with warnings.catch_warnings():
                warnings.simplefilter("error", spla.MatrixRankWarning)
                lu = spla.splu(K)
        except (RuntimeError, spla.MatrixRankWarning):
            raise ValueError(f"inertia relief: the supports {list(supports)} with the accelerations "
                             f"{list(accelerations)} do not hold the structure's rigid-body modes (singular "
                             f"matrix)") from None
        R = np.concatenate([system.residual(x, xdot, p, q), C @ x - c0])
        if scale is None:
            scale = max(np.max(np.abs(R)), 1.0)
        if np.max(np.abs(R)) <= rtol * scale:
            return x, {a: float(q[j]) for a, j in zip(accelerations, q_cols)}
        step = lu.solve(-R)
        if not np.all(np.isfinite(step)):
            raise ValueError(f"inertia relief: the supports {list(supports)} do not hold the structure's "
                             f"rigid-body modes (singular matrix)")
        x = x + step[:n]
        q[q_cols] += step[n:]
    raise ValueError(f"inertia relief: no convergence in {max_iter} Newton iterations (largest residual "
                     f"{np.max(np.abs(R)):.3g}); apply the loads in steps")


@dataclass(frozen=True)
class MonitoringStation:
    """A monitoring station: the cut just inboard of node ``node`` of beam ``beam`` (between nodes
    ``node - 1`` and ``node``; node >= 1, negative from the tip), named ``label`` (e.g. "wing root"
    at the root rib, "fuselage x = 5 m").

    Parameters
    ----------
    label : str
        Name of the station.
    beam : str
        Name of the beam.
    node : int
        Node just outboard of the cut (>= 1, negative from the tip).
    """

    label: str
    beam: str
    node: int


def monitoring_loads(system, x, stations) -> dict:
    """Internal loads at monitoring stations (:class:`MonitoringStation`) of a state ``x`` of a
    :class:`JoinedBeamSystem`: the resultants the outboard part of the beam (from the station to the
    tip, the node's own point loads included) exerts on the inboard part, ``F`` and ``M`` of the
    state (docs/beam-theory.md). Returns ``{label: {"force": (3,), "moment": (3,)}}`` in body axes and
    ``"force_csn"``, ``"moment_csn"`` in the node's deformed section frame (c: chordwise shear,
    s: axial force / torsion, n: normal shear / bending about n).

    Parameters
    ----------
    system : JoinedBeamSystem
        The system.
    x : array_like, shape (n_state,)
        State.
    stations : sequence of MonitoringStation
        The stations.

    Returns
    -------
    dict
        The loads of each station, by label (N, N m).
    """
    x = np.asarray(x, dtype=float).reshape(system.n_state)
    out = {}
    for st in stations:
        if not isinstance(st, MonitoringStation):
            raise TypeError(f"stations must be MonitoringStation objects, got {type(st).__name__}")
        b = system.beam(st.beam)
        node = int(st.node)
        if not -b.num_nodes < node < b.num_nodes or node % b.num_nodes == 0:
            raise ValueError(f"monitoring station {st.label!r}: node {node} of beam {st.beam!r} must be in "
                             f"1..{b.num_nodes - 1} (or -{b.num_nodes - 1}..-1): the cut inboard of node 0 is "
                             f"the root's boundary")
        i = system.node_index(st.beam, node)
        blk = x[i:i + N_STATE_PER_NODE]
        R = b.rotation
        T = np.array(body_to_csn(ca.DM(blk[STATE_BLOCKS["theta"]]), system.euler_sequence))    # beam axes -> csn
        F, M = blk[STATE_BLOCKS["F"]], blk[STATE_BLOCKS["M"]]
        out[st.label] = {"force": R.T @ F, "moment": R.T @ M, "force_csn": T @ F, "moment_csn": T @ M}
    return out


class JoinedBeamModel:
    """Joined beams with their parameters: ``solve(loads, **shared)`` gives statics.

    ``beam_params``: ``{beam: parameter dict}`` (:func:`wingmdao.beam.static.beam_parameters`);
    ``masses``, ``symmetry``: as :func:`build_joined_system`.

    Parameters
    ----------
    beams : sequence of Beam
        The beams.
    joints : sequence of Joint
        The joints.
    beam_params : dict
        ``{beam name: parameter dict}``.
    euler_sequence : str
        Euler-angle sequence.
    damping : StrainRateDamping, optional
        Strain-rate damping.
    masses : sequence of LumpedMass
        The lumped masses.
    symmetry : sequence of Symmetry
        The symmetry conditions.
    """

    def __init__(self, beams, joints, beam_params, *, euler_sequence="surface", damping=None, masses=(),
                 symmetry=()):
        self.system = build_joined_system(beams, joints, euler_sequence=euler_sequence, damping=damping,
                                          masses=masses, symmetry=symmetry)
        self.params = beam_params
        self.p = self.system.pack_parameters(beam_params)

    def forcing(self, loads=None, **shared) -> np.ndarray:
        """Packed forcing (:meth:`JoinedBeamSystem.pack_forcing`).

        Parameters
        ----------
        loads : dict, optional
            ``{beam name: {block: array}}``.
        **shared
            Shared forcing blocks.

        Returns
        -------
        ndarray
            The packed forcing.
        """
        return self.system.pack_forcing(loads, **shared)

    def solve(self, loads=None, *, load_steps=1, x0=None, max_iter=30, **shared) -> dict:
        """Static equilibrium under ``loads`` (``{beam: {block: array}}``) and the shared forcing;
        returns :meth:`JoinedBeamSystem.unpack` of the state plus ``'x'`` and ``'iterations'``.

        Parameters
        ----------
        loads : dict, optional
            ``{beam name: {block: array}}``.
        load_steps : int
            Load steps of the continuation.
        x0 : array_like, shape (n_state,), optional
            Initial guess; default the jig.
        max_iter : int
            Most Newton iterations per load step.
        **shared
            Shared forcing blocks (``gravity``, ...).

        Returns
        -------
        dict
            The unpacked state, ``'x'`` and ``'iterations'``.
        """
        q = self.forcing(loads, **shared)
        x, info = solve_static(self.system, self.p, q, x0, load_steps=load_steps, max_iter=max_iter)
        out = self.system.unpack(x)
        out["x"], out["iterations"] = x, info.iterations
        return out

    def solve_inertia_relief(self, loads=None, *, supports, accelerations=HALF_AIRCRAFT_ACCELERATIONS,
                             **shared) -> dict:
        """Equilibrium of the free structure under ``loads`` with inertia relief
        (:func:`solve_inertia_relief`); returns :meth:`JoinedBeamSystem.unpack` of the state plus
        ``'x'`` and ``'accelerations'`` ({name: value}, m/s^2 and rad/s^2).

        Parameters
        ----------
        loads : dict, optional
            ``{beam name: {block: array}}``.
        supports : sequence of tuple
            ``(beam, node, component)``, one per acceleration.
        accelerations : sequence of str
            Names of the unknown accelerations.
        **shared
            Shared forcing blocks.

        Returns
        -------
        dict
            The unpacked state, ``'x'`` and ``'accelerations'``.
        """
        q = self.forcing(loads, **shared)
        x, acc = solve_inertia_relief(self.system, self.p, q, supports, accelerations)
        out = self.system.unpack(x)
        out["x"], out["accelerations"] = x, acc
        return out
