"""Rigid-link load and displacement transfer between a beam and an aerodynamic surface mesh.

Every aerodynamic node ``a`` is attached by a rigid link to one beam node ``b(a)`` (the
nearest one in the jig geometry, fixed at setup). Linear rigid-link kinematics and the
consistent (transpose, virtual-work conserving) load transfer:

    u_a = u_b + theta_b x (x_a - x_b)
    F_b = sum_{a in b} f_a,      M_b = sum_{a in b} (x_a - x_b) x f_a

(Brown, "Displacement extrapolation for CFD+CSM aeroelastic analysis", AIAA 97-1090, 1997,
the rigid-link special case; the same transfer as a finite element RBE2/RBAR element). Unlike
MELD (Kiviaho and Kennedy, "Efficient and robust load and displacement transfer scheme using
weighted least squares", AIAA Journal 57(5), 2019), which reads only the translations of the
structural nodes, this transfer uses the beam's rotations (twist moves the leading and
trailing edges in opposite directions) and returns moments to the beam.

``mirror_y=True`` couples a beam modelled on the right wing (y outboard) with an aerodynamic
half-wing on the left (y negative, OpenAeroStruct's symmetric surfaces): the aerodynamic
coordinates, displacements and forces are reflected by M = diag(1, -1, 1) on the way in and
out, so f_a . u_a = (M f_a) . (M u_a) and the transfer stays consistent.

The aerodynamic variables are distributed (MPhys convention), the structural ones serial; the
components run on one process.
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om

_MIRROR = np.array([1.0, -1.0, 1.0])


def rigid_links(x_struct: np.ndarray, x_aero: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    """Index of the beam node each aerodynamic node is linked to (nearest, jig geometry).

    ``x_struct`` (n, 3), ``x_aero`` (m, 3) in m. Raises ValueError for coincident beam nodes
    (closer than ``tol`` times the largest node distance) or empty meshes.

    Parameters
    ----------
    x_struct : numpy.ndarray
        (n, 3) beam nodes (m).
    x_aero : numpy.ndarray
        (m, 3) aerodynamic nodes (m).
    tol : float, optional
        Relative distance below which two beam nodes coincide.

    Returns
    -------
    numpy.ndarray
        (m,) beam node index of each aerodynamic node.
    """
    xs = np.asarray(x_struct, dtype=float).reshape(-1, 3)
    xa = np.asarray(x_aero, dtype=float).reshape(-1, 3)
    if xs.shape[0] < 2:
        raise ValueError(f"rigid links: x_struct0 has {xs.shape[0]} beam nodes; at least 2 needed")
    if xa.shape[0] < 1:
        raise ValueError("rigid links: x_aero0 has no aerodynamic nodes; at least 1 needed")
    d = np.linalg.norm(xs[:, None, :] - xs[None, :, :], axis=2)
    scale = max(float(np.max(d)), 1e-300)
    d[np.diag_indices_from(d)] = np.inf
    i, j = np.unravel_index(int(np.argmin(d)), d.shape)
    if d[i, j] <= tol * scale:
        raise ValueError(f"rigid links: beam nodes {min(i, j)} and {max(i, j)} coincide at "
                         f"{xs[i].tolist()} m (distance {d[i, j]:.3g} m); beam nodes must be distinct")
    return np.argmin(np.linalg.norm(xa[:, None, :] - xs[None, :, :], axis=2), axis=1)


def _skew(v):
    """[v]x for (k, 3) vectors: (k, 3, 3)."""
    s = np.zeros(v.shape[:-1] + (3, 3))
    s[..., 0, 1], s[..., 0, 2] = -v[..., 2], v[..., 1]
    s[..., 1, 0], s[..., 1, 2] = v[..., 2], -v[..., 0]
    s[..., 2, 0], s[..., 2, 1] = -v[..., 1], v[..., 0]
    return s


class _LinkBase(om.ExplicitComponent):
    def initialize(self):
        self.options.declare("links", types=(np.ndarray, list, tuple), desc="(n_aero,) int: beam node of each aerodynamic node")
        self.options.declare("num_struct_nodes", types=int, lower=2, desc="number of beam nodes")
        self.options.declare("mirror_y", default=False, types=bool,
                             desc="aerodynamic mesh is the y-mirror image of the beam's wing")

    def _sizes(self):
        links = np.asarray(self.options["links"], dtype=int)
        n = self.options["num_struct_nodes"]
        if links.ndim != 1 or links.size < 1 or links.min() < 0 or links.max() >= n:
            raise ValueError(f"{self.pathname}: links must be (n_aero,) indices in [0, {n - 1}], "
                             f"got shape {links.shape}, range [{links.min()}, {links.max()}]")
        return links, links.size, n

    def _add_coords(self, m, n):
        self.add_input("x_aero0", shape=3 * m, distributed=True, units="m", tags=["mphys_coordinates"],
                       desc="jig aerodynamic surface node coordinates (x, y, z per node)")
        self.add_input("x_struct0", shape=3 * n, units="m", tags=["mphys_coordinates"],
                       desc="jig beam node coordinates (x, y, z per node, root first)")

    def _arms(self, inputs):
        links, m, n = self._sizes()
        xa = np.asarray(inputs["x_aero0"]).reshape(m, 3)
        if self.options["mirror_y"]:
            xa = xa * _MIRROR
        xs = np.asarray(inputs["x_struct0"]).reshape(n, 3)
        return xa - xs[links]   # (m, 3), in the beam's frame

    def _check_size(self, name, expected, what):
        size = self.get_io_metadata(metadata_keys=["size"], return_rel_names=True)[name]["size"]
        if size != expected:
            raise ValueError(f"{self.pathname}: {name} has {size} entries; expected {expected} ({what})")


class RigidLinkDisplacementTransfer(_LinkBase):
    """``u_struct`` (n*6: u, theta per beam node) -> ``u_aero`` (m*3), u_a = M(u_b + theta_b x r_a)."""

    def setup(self):
        links, m, n = self._sizes()
        self._add_coords(m, n)
        self.add_input("u_struct", shape=6 * n, units=None, tags=["mphys_coupling"],
                       desc="beam node displacements (m) and small rotation vectors (rad), body axes")
        self.add_output("u_aero", shape=3 * m, distributed=True, units="m", tags=["mphys_coupling"],
                        desc="aerodynamic node displacements")

    def setup_partials(self):
        links, m, n = self._sizes()
        rows = np.repeat(np.arange(3 * m).reshape(m, 3), 3, axis=1).reshape(m, 3, 3)  # (m, i, j)
        bcols = 6 * links[:, None, None]
        cols_u = np.broadcast_to(bcols + np.arange(3)[None, None, :], (m, 3, 3))
        cols_t = cols_u + 3
        self._rows = rows.ravel()
        self.declare_partials("u_aero", "u_struct", rows=np.concatenate([rows.ravel(), rows.ravel()]),
                              cols=np.concatenate([cols_u.ravel(), cols_t.ravel()]))
        cols_xa = np.broadcast_to(3 * np.arange(m)[:, None, None] + np.arange(3)[None, None, :], (m, 3, 3))
        cols_xs = np.broadcast_to(3 * links[:, None, None] + np.arange(3)[None, None, :], (m, 3, 3))
        self.declare_partials("u_aero", "x_aero0", rows=rows.ravel(), cols=cols_xa.ravel())
        self.declare_partials("u_aero", "x_struct0", rows=rows.ravel(), cols=cols_xs.ravel())

    def compute(self, inputs, outputs):
        links, m, n = self._sizes()
        us = np.asarray(inputs["u_struct"]).reshape(n, 6)
        ua = us[links, :3] + np.cross(us[links, 3:], self._arms(inputs))
        if self.options["mirror_y"]:
            ua = ua * _MIRROR
        outputs["u_aero"] = ua.ravel()

    def compute_partials(self, inputs, partials):
        links, m, n = self._sizes()
        us = np.asarray(inputs["u_struct"]).reshape(n, 6)
        mir = _MIRROR if self.options["mirror_y"] else np.ones(3)
        eye = np.broadcast_to(np.diag(mir), (m, 3, 3))
        # d(theta x r)/d theta = -[r]x ; d(theta x r)/dr = [theta]x
        d_theta = mir[None, :, None] * (-_skew(self._arms(inputs)))
        partials["u_aero", "u_struct"] = np.concatenate([eye.ravel(), d_theta.ravel()])
        skt = mir[None, :, None] * _skew(us[links, 3:])
        partials["u_aero", "x_aero0"] = (skt * mir[None, None, :]).ravel()
        partials["u_aero", "x_struct0"] = (-skt).ravel()


class RigidLinkLoadTransfer(_LinkBase):
    """``f_aero`` (m*3) -> ``f_aero_struct`` (n*6): F_b = sum M f_a, M_b = sum r_a x M f_a."""

    def setup(self):
        links, m, n = self._sizes()
        self._add_coords(m, n)
        self.add_input("f_aero", shape=3 * m, distributed=True, units="N", tags=["mphys_coupling"],
                       desc="aerodynamic node forces")
        self.add_output("f_aero_struct", shape=6 * n, units=None, tags=["mphys_coupling"],
                        desc="beam node forces (N) and moments (N*m) from the aerodynamic loads, body axes")

    def setup_partials(self):
        links, m, n = self._sizes()
        rows_f = 6 * links[:, None, None] + np.arange(3)[None, :, None]    # (m, i, 1)
        rows = np.broadcast_to(rows_f, (m, 3, 3))
        cols_fa = np.broadcast_to(3 * np.arange(m)[:, None, None] + np.arange(3)[None, None, :], (m, 3, 3))
        self.declare_partials("f_aero_struct", "f_aero", rows=np.concatenate([rows.ravel(), (rows + 3).ravel()]),
                              cols=np.concatenate([cols_fa.ravel(), cols_fa.ravel()]))
        self.declare_partials("f_aero_struct", "x_aero0", rows=(rows + 3).ravel(), cols=cols_fa.ravel())
        b = np.arange(n)[:, None, None]   # one 3x3 block per beam node (links summed)
        self.declare_partials("f_aero_struct", "x_struct0",
                              rows=np.broadcast_to(6 * b + 3 + np.arange(3)[None, :, None], (n, 3, 3)).ravel(),
                              cols=np.broadcast_to(3 * b + np.arange(3)[None, None, :], (n, 3, 3)).ravel())

    def compute(self, inputs, outputs):
        links, m, n = self._sizes()
        mir = _MIRROR if self.options["mirror_y"] else np.ones(3)
        fa = np.asarray(inputs["f_aero"]).reshape(m, 3) * mir
        out = np.zeros((n, 6), dtype=np.result_type(fa, inputs["x_struct0"]))
        np.add.at(out[:, :3], links, fa)
        np.add.at(out[:, 3:], links, np.cross(self._arms(inputs), fa))
        outputs["f_aero_struct"] = out.ravel()

    def compute_partials(self, inputs, partials):
        links, m, n = self._sizes()
        mir = _MIRROR if self.options["mirror_y"] else np.ones(3)
        fa = np.asarray(inputs["f_aero"]).reshape(m, 3) * mir
        eye = np.broadcast_to(np.diag(mir), (m, 3, 3))
        # d(r x f)/df = [r]x ; d(r x f)/dr = -[f]x
        partials["f_aero_struct", "f_aero"] = np.concatenate(
            [eye.ravel(), (_skew(self._arms(inputs)) * mir[None, None, :]).ravel()])
        skf = -_skew(fa)
        partials["f_aero_struct", "x_aero0"] = (skf * mir[None, None, :]).ravel()
        blocks = np.zeros((n, 3, 3), dtype=skf.dtype)
        np.add.at(blocks, links, -skf)
        partials["f_aero_struct", "x_struct0"] = blocks.ravel()
