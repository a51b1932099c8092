"""A small linear-elastic 3-D solid finite-element solver (27-node hexahedra).

Used only to verify the beam (App. E.3: "3-D solid elements ... fixed boundary condition at one
end, tip loads at the other, average displacements over cross-sections"). Not part of the
sizing path and not an OpenMDAO component.

* Element: the triquadratic Lagrange hexahedron (hex27), isoparametric, full 3x3x3 Gauss
  integration. Local node ``a = i + 3 j + 9 k`` with ``i, j, k`` in {0, 1, 2} the positions
  -1, 0, +1 of the parametric coordinates (xi, eta, zeta).
* Meshes are structured: :func:`structured_hex27_mesh` takes a logical grid of node positions
  ``(n_span, n_c, n_n, 3)`` (a quadratic grid: odd counts) and a mask of active cells of the
  cross-section grid, so hollow sections (a box) are a mask away from solid ones.
* Isotropic Hooke's law, small strains. Stiffness assembled vectorised over elements with
  numpy, stored as scipy.sparse CSR, solved directly (``scipy.sparse.linalg.splu``).
* Surface loads: a resultant force and moment on a set of faces, spread as the
  rigid-body-consistent traction t(r) = F/A + omega x (r - r_c), with I_face omega = M
  (I_face the area "inertia tensor" of the faces about their centroid r_c): uniform for a
  force, linear for a moment; its resultant is exactly (F, M about r_c).
* Cuts: the area-weighted average displacement over faces, and the rigid rotation that fits
  the displacement field over the cut in the area-weighted least-squares sense.

All quantities SI (m, N, Pa).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

#: 3-point Gauss-Legendre rule on [-1, 1]
GAUSS_POINTS = np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
GAUSS_WEIGHTS = np.array([5.0, 8.0, 5.0]) / 9.0


# ----------------------------------------------------------------------------------------
# shape functions
# ----------------------------------------------------------------------------------------
def lagrange_quadratic(t):
    """1-D quadratic Lagrange functions at nodes -1, 0, 1 and their derivatives: (..., 3) each.

    Parameters
    ----------
    t : array_like
        Parametric coordinates in [-1, 1].

    Returns
    -------
    tuple
        Values (..., 3) and derivatives (..., 3).
    """
    t = np.asarray(t, dtype=float)[..., None]
    n = np.concatenate([0.5 * t * (t - 1.0), 1.0 - t * t, 0.5 * t * (t + 1.0)], axis=-1)
    dn = np.concatenate([t - 0.5, -2.0 * t, t + 0.5], axis=-1)
    return n, dn


def hex27_shape(xi, eta, zeta):
    """Hex27 shape functions N (..., 27) and parametric gradients dN (..., 27, 3).

    Parameters
    ----------
    xi, eta, zeta : array_like
        Parametric coordinates in [-1, 1].

    Returns
    -------
    tuple
        N (..., 27) and dN (..., 27, 3).
    """
    n1, d1 = lagrange_quadratic(xi)
    n2, d2 = lagrange_quadratic(eta)
    n3, d3 = lagrange_quadratic(zeta)
    # a = i + 3 j + 9 k  ->  outer product ordered (k, j, i)
    def outer(a, b, c):
        return np.einsum("...k,...j,...i->...kji", c, b, a).reshape(a.shape[:-1] + (27,))
    N = outer(n1, n2, n3)
    dN = np.stack([outer(d1, n2, n3), outer(n1, d2, n3), outer(n1, n2, d3)], axis=-1)
    return N, dN


def quad9_shape(xi, eta):
    """9-node quadrilateral shape functions (..., 9) and gradients (..., 9, 2); a = i + 3 k.

    Parameters
    ----------
    xi, eta : array_like
        Parametric coordinates in [-1, 1].

    Returns
    -------
    tuple
        N (..., 9) and dN (..., 9, 2).
    """
    n1, d1 = lagrange_quadratic(xi)
    n2, d2 = lagrange_quadratic(eta)
    N = np.einsum("...k,...i->...ki", n2, n1).reshape(n1.shape[:-1] + (9,))
    dN = np.stack([np.einsum("...k,...i->...ki", n2, d1).reshape(N.shape),
                   np.einsum("...k,...i->...ki", d2, n1).reshape(N.shape)], axis=-1)
    return N, dN


def _volume_rule():
    g = GAUSS_POINTS
    k, j, i = np.meshgrid(g, g, g, indexing="ij")
    w = np.einsum("k,j,i->kji", GAUSS_WEIGHTS, GAUSS_WEIGHTS, GAUSS_WEIGHTS).ravel()
    return np.stack([i.ravel(), j.ravel(), k.ravel()], axis=-1), w


def _surface_rule():
    g = GAUSS_POINTS
    k, i = np.meshgrid(g, g, indexing="ij")
    w = np.outer(GAUSS_WEIGHTS, GAUSS_WEIGHTS).ravel()
    return np.stack([i.ravel(), k.ravel()], axis=-1), w


# ----------------------------------------------------------------------------------------
# mesh
# ----------------------------------------------------------------------------------------
@dataclass
class HexMesh:
    """A hex27 mesh: ``nodes`` (n, 3) m, ``elements`` (n_el, 27) node indices (local a = i + 3j + 9k).

    ``grid_node`` (n_span, n_c, n_n) maps the logical grid of a structured mesh to node
    indices (-1 where no node), ``active`` (n_el_c, n_el_n) is the cross-section cell mask.

    Parameters
    ----------
    nodes : numpy.ndarray
        (n, 3) node positions (m).
    elements : numpy.ndarray
        (n_el, 27) node indices.
    grid_node : numpy.ndarray or None, optional
        (n_span, n_c, n_n) node index of each logical grid point (-1: none).
    active : numpy.ndarray or None, optional
        (n_el_c, n_el_n) bool mask of the cross-section cells with material.
    """

    nodes: np.ndarray
    elements: np.ndarray
    grid_node: np.ndarray | None = None
    active: np.ndarray | None = None

    @property
    def num_dof(self) -> int:
        return 3 * len(self.nodes)

    def slice_faces(self, span_index: int) -> np.ndarray:
        """The 9-node faces (n_f, 9) of the active cells on the span node-slice ``span_index`` (even).

        Face local node ``a = i + 3 k`` with i along the grid's c direction, k along n.

        Parameters
        ----------
        span_index : int
            Even span node-slice index.

        Returns
        -------
        numpy.ndarray
            (n_f, 9) face node indices.
        """
        if self.grid_node is None:
            raise ValueError("slice_faces needs a structured mesh (grid_node)")
        n_span = self.grid_node.shape[0]
        if span_index % 2 or not 0 <= span_index < n_span:
            raise ValueError(f"span_index must be an even node-slice index in [0, {n_span - 1}], "
                             f"got {span_index}")
        g = self.grid_node[span_index]
        faces = []
        for ec, en in zip(*np.nonzero(self.active)):
            block = g[2 * ec:2 * ec + 3, 2 * en:2 * en + 3]  # (i, k)
            faces.append(block.T.ravel())                     # a = i + 3 k
        return np.array(faces, dtype=int)

    def slice_nodes(self, span_index: int) -> np.ndarray:
        """All node indices on a span node-slice.

        Parameters
        ----------
        span_index : int
            Span node-slice index.

        Returns
        -------
        numpy.ndarray
            Node indices.
        """
        g = self.grid_node[span_index]
        return np.unique(g[g >= 0])


def structured_hex27_mesh(grid: np.ndarray, active: np.ndarray | None = None) -> HexMesh:
    """Hex27 mesh of a logical grid of node positions.

    grid: (n_span, n_c, n_n, 3) positions (m) of a quadratic grid (odd counts, 2 n_el + 1);
    element local axes xi, eta, zeta run along c, span, n (right-handed when c x span = n,
    as for the body axes x, y, z). active: (n_el_c, n_el_n) bool mask of the cross-section
    cells that carry material (default all), the same along the span.

    Parameters
    ----------
    grid : numpy.ndarray
        (n_span, n_c, n_n, 3) node positions of the quadratic grid (m).
    active : numpy.ndarray or None, optional
        (n_el_c, n_el_n) bool cell mask; None for all.

    Returns
    -------
    HexMesh
        The mesh.
    """
    grid = np.asarray(grid, dtype=float)
    if grid.ndim != 4 or grid.shape[-1] != 3:
        raise ValueError(f"grid must have shape (n_span, n_c, n_n, 3), got {grid.shape}")
    n_s, n_c, n_n, _ = grid.shape
    for name, n in (("n_span", n_s), ("n_c", n_c), ("n_n", n_n)):
        if n < 3 or n % 2 == 0:
            raise ValueError(f"grid {name} must be odd and >= 3 (quadratic grid), got {n}")
    e_s, e_c, e_n = (n_s - 1) // 2, (n_c - 1) // 2, (n_n - 1) // 2
    active = np.ones((e_c, e_n), bool) if active is None else np.asarray(active, bool)
    if active.shape != (e_c, e_n):
        raise ValueError(f"active must have shape {(e_c, e_n)}, got {active.shape}")
    # nodes used by active cells (per cross-section)
    used = np.zeros((n_c, n_n), bool)
    for ec, en in zip(*np.nonzero(active)):
        used[2 * ec:2 * ec + 3, 2 * en:2 * en + 3] = True
    per_slice = int(used.sum())
    local = -np.ones((n_c, n_n), int)
    local[used] = np.arange(per_slice)
    grid_node = -np.ones((n_s, n_c, n_n), int)
    grid_node[:, used] = np.arange(n_s)[:, None] * per_slice + local[used][None, :]
    nodes = grid[:, used, :].reshape(-1, 3)
    # elements: local a = i + 3 j + 9 k, i along c, j along span, k along n
    ii, jj, kk = np.meshgrid(np.arange(3), np.arange(3), np.arange(3), indexing="ij")
    order = np.argsort((ii + 3 * jj + 9 * kk).ravel())
    di, dj, dk = ii.ravel()[order], jj.ravel()[order], kk.ravel()[order]
    elements = []
    cells = np.argwhere(active)
    for es in range(e_s):
        s = 2 * es + dj
        c = 2 * cells[:, 0:1] + di
        n = 2 * cells[:, 1:2] + dk
        elements.append(grid_node[s[None, :], c, n])
    elements = np.concatenate(elements, axis=0)
    mesh = HexMesh(nodes, elements, grid_node, active)
    check_jacobians(mesh)
    return mesh


def check_jacobians(mesh: HexMesh) -> None:
    """Raise ValueError if any element has a non-positive Jacobian at a Gauss point.

    Parameters
    ----------
    mesh : HexMesh
        The hex27 mesh.
    """
    pts, _ = _volume_rule()
    _, dN = hex27_shape(pts[:, 0], pts[:, 1], pts[:, 2])
    X = mesh.nodes[mesh.elements]                      # (e, 27, 3)
    J = np.einsum("gak,eai->egik", dN, X)              # dx_i/dxi_k
    det = np.linalg.det(J)
    if np.any(det <= 0.0):
        e = int(np.argmin(det.min(axis=1)))
        raise ValueError(f"element {e} has a non-positive Jacobian (min det {det[e].min():.3e}); "
                         "grid must be right-handed (c x span = n) and not inverted")


# ----------------------------------------------------------------------------------------
# material and stiffness
# ----------------------------------------------------------------------------------------
def lame_parameters(E: float, nu: float) -> tuple[float, float]:
    """Lame's lambda and mu (Pa) of an isotropic material; validates E > 0, -1 < nu < 0.5.

    Parameters
    ----------
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio (-).

    Returns
    -------
    tuple of float
        (lambda, mu) (Pa).
    """
    if not (np.isfinite(E) and E > 0.0):
        raise ValueError(f"E must be finite and > 0 Pa, got {E}")
    if not (np.isfinite(nu) and -1.0 < nu < 0.5):
        raise ValueError(f"nu must be in (-1, 0.5), got {nu}")
    return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))


def _physical_gradients(mesh: HexMesh, elements: np.ndarray):
    """dN/dx (e, g, 27, 3) and det J * w (e, g) at the 27 Gauss points of ``elements``."""
    pts, w = _volume_rule()
    _, dN = hex27_shape(pts[:, 0], pts[:, 1], pts[:, 2])          # (g, 27, 3)
    X = mesh.nodes[elements]                                      # (e, 27, 3)
    J = np.einsum("gak,eai->egik", dN, X)                         # (e, g, 3, 3)
    det = np.linalg.det(J)
    Jinv = np.linalg.inv(J)                                       # dxi_k/dx_i
    G = np.einsum("gak,egki->egai", dN, Jinv)
    return G, det * w[None, :]


def element_stiffness(mesh: HexMesh, E: float, nu: float, elements: np.ndarray | None = None):
    """Element stiffness matrices (e, 81, 81), DOF order 3 a + i.

    K_aibj = sum_g w detJ [lambda G_ai G_bj + mu (G_aj G_bi + delta_ij G_ak G_bk)] with G = dN/dx.

    Parameters
    ----------
    mesh : HexMesh
        The hex27 mesh.
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio (-).
    elements : numpy.ndarray or None, optional
        Indices of the elements; None for all.

    Returns
    -------
    numpy.ndarray
        (e, 81, 81) stiffness matrices (N/m).
    """
    lam, mu = lame_parameters(E, nu)
    elements = mesh.elements if elements is None else elements
    G, wd = _physical_gradients(mesh, elements)
    Gw = (G * np.sqrt(wd)[:, :, None, None]).reshape(len(elements), 27, 81)  # (e, g, 3a+i)
    P = np.matmul(Gw.transpose(0, 2, 1), Gw).reshape(-1, 27, 3, 27, 3)    # P[a,i,b,j]
    S = P[:, :, 0, :, 0] + P[:, :, 1, :, 1] + P[:, :, 2, :, 2]
    K = lam * P + mu * P.transpose(0, 1, 4, 3, 2)
    for i in range(3):
        K[:, :, i, :, i] += mu * S
    return K.reshape(-1, 81, 81)


def element_dofs(elements: np.ndarray) -> np.ndarray:
    """Global DOF indices (e, 81) in the order 3 a + i.

    Parameters
    ----------
    elements : numpy.ndarray
        (e, 27) node indices.

    Returns
    -------
    numpy.ndarray
        (e, 81) DOF indices.
    """
    return (3 * elements[:, :, None] + np.arange(3)).reshape(len(elements), 81)


def assemble_stiffness(mesh: HexMesh, E: float, nu: float, chunk: int = 400) -> sp.csr_matrix:
    """Global stiffness (CSR, N/m), vectorised over chunks of elements.

    Parameters
    ----------
    mesh : HexMesh
        The hex27 mesh.
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio (-).
    chunk : int, optional
        Elements per vectorised chunk.

    Returns
    -------
    scipy.sparse.csr_matrix
        Global stiffness (N/m).
    """
    n = mesh.num_dof
    K = sp.csr_matrix((n, n))
    rows, cols, vals = [], [], []
    for start in range(0, len(mesh.elements), chunk):
        el = mesh.elements[start:start + chunk]
        ke = element_stiffness(mesh, E, nu, el)
        dofs = element_dofs(el)
        rows.append(np.repeat(dofs, 81, axis=1).ravel())
        cols.append(np.tile(dofs, (1, 81)).ravel())
        vals.append(ke.ravel())
        if sum(len(v) for v in vals) > 2e7:
            K = K + sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                  shape=(n, n)).tocsr()
            rows, cols, vals = [], [], []
    if vals:
        K = K + sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                              shape=(n, n)).tocsr()
    return K


def element_strains(mesh: HexMesh, u: np.ndarray) -> np.ndarray:
    """Engineering strains (e, 27 Gauss points, 6): xx, yy, zz, yz, xz, xy.

    Parameters
    ----------
    mesh : HexMesh
        The hex27 mesh.
    u : numpy.ndarray
        (num_dof,) nodal displacements (m).

    Returns
    -------
    numpy.ndarray
        (e, 27, 6) engineering strains (-).
    """
    G, _ = _physical_gradients(mesh, mesh.elements)
    grad = np.einsum("egaj,eai->egij", G, u.reshape(-1, 3)[mesh.elements])   # du_i/dx_j
    return np.stack([grad[..., 0, 0], grad[..., 1, 1], grad[..., 2, 2],
                     grad[..., 1, 2] + grad[..., 2, 1], grad[..., 0, 2] + grad[..., 2, 0],
                     grad[..., 0, 1] + grad[..., 1, 0]], axis=-1)


def stress_from_strain(strain: np.ndarray, E: float, nu: float) -> np.ndarray:
    """Cauchy stress (Voigt xx, yy, zz, yz, xz, xy; Pa) from engineering strain (Hooke's law).

    Parameters
    ----------
    strain : numpy.ndarray
        (..., 6) engineering strains (-).
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio (-).

    Returns
    -------
    numpy.ndarray
        (..., 6) stresses (Pa).
    """
    lam, mu = lame_parameters(E, nu)
    tr = strain[..., 0] + strain[..., 1] + strain[..., 2]
    s = np.empty_like(strain)
    s[..., :3] = lam * tr[..., None] + 2.0 * mu * strain[..., :3]
    s[..., 3:] = mu * strain[..., 3:]
    return s


# ----------------------------------------------------------------------------------------
# faces: loads and cuts
# ----------------------------------------------------------------------------------------
def _face_quadrature(mesh: HexMesh, faces: np.ndarray):
    """Gauss-point positions (f, g, 3), shape values (g, 9) and area weights (f, g) of 9-node faces."""
    pts, w = _surface_rule()
    N, dN = quad9_shape(pts[:, 0], pts[:, 1])                   # (g, 9), (g, 9, 2)
    X = mesh.nodes[faces]                                       # (f, 9, 3)
    r = np.einsum("ga,fai->fgi", N, X)
    t1 = np.einsum("ga,fai->fgi", dN[..., 0], X)
    t2 = np.einsum("ga,fai->fgi", dN[..., 1], X)
    dA = np.linalg.norm(np.cross(t1, t2), axis=-1) * w[None, :]
    return r, N, dA


def face_geometry(mesh: HexMesh, faces: np.ndarray) -> dict:
    """Area (m^2), centroid (3,) and area inertia tensor about the centroid (3, 3; m^4) of faces.

    ``I = integral(|rho|^2 1 - rho rho^T) dA`` with rho = r - centroid, so that
    integral(rho x (omega x rho)) dA = I omega.

    Parameters
    ----------
    mesh : HexMesh
        The hex27 mesh.
    faces : numpy.ndarray
        (n_f, 9) face node indices.

    Returns
    -------
    dict
        ``area`` (m^2), ``centroid`` (3,) (m), ``inertia`` (3, 3) (m^4).
    """
    r, _, dA = _face_quadrature(mesh, faces)
    area = dA.sum()
    centroid = np.einsum("fgi,fg->i", r, dA) / area
    rho = r - centroid
    I = (np.einsum("fgk,fgk,fg->", rho, rho, dA) * np.eye(3)
         - np.einsum("fgi,fgj,fg->ij", rho, rho, dA))
    return {"area": area, "centroid": centroid, "inertia": I}


def face_load_vector(mesh: HexMesh, faces: np.ndarray, force=(0.0, 0.0, 0.0),
                     moment=(0.0, 0.0, 0.0), ref_point=None) -> np.ndarray:
    """Consistent nodal forces (num_dof,) of a resultant force F (N) and moment M (N m) on faces.

    The moment is about ``ref_point`` (default: the faces' centroid r_c). Traction
    t(r) = F / A + omega x (r - r_c) with I omega = M_c, M_c = M + (ref_point - r_c) x F the
    moment about the centroid: uniform for a force, linear for a moment, and the rigid-body
    virtual work of t equals that of (F, M) exactly.

    Parameters
    ----------
    mesh : HexMesh
        The hex27 mesh.
    faces : numpy.ndarray
        (n_f, 9) face node indices.
    force : sequence of 3, optional
        Resultant force (N).
    moment : sequence of 3, optional
        Resultant moment about ``ref_point`` (N m).
    ref_point : array_like or None, optional
        Point the moment is taken about (m); None for the faces' centroid.

    Returns
    -------
    numpy.ndarray
        (num_dof,) nodal forces (N).
    """
    force, moment = np.asarray(force, float), np.asarray(moment, float)
    geo = face_geometry(mesh, faces)
    rc = geo["centroid"]
    ref = rc if ref_point is None else np.asarray(ref_point, float)
    m_c = moment + np.cross(ref - rc, force)
    I = geo["inertia"]
    # a planar cut has a singular in-plane block only if it is degenerate (a line)
    omega = np.linalg.solve(I, m_c)
    r, N, dA = _face_quadrature(mesh, faces)
    t = force / geo["area"] + np.cross(omega, r - rc)            # (f, g, 3)
    fe = np.einsum("ga,fgi,fg->fai", N, t, dA)                   # (f, 9, 3)
    f = np.zeros(mesh.num_dof)
    np.add.at(f, (3 * faces[:, :, None] + np.arange(3)).ravel(), fe.ravel())
    return f


def _cut_statistics(r: np.ndarray, ug: np.ndarray, dA: np.ndarray) -> dict:
    """Area, centroid, mean displacement and least-squares rotation from quadrature data."""
    area = dA.sum()
    centroid = np.einsum("fgi,fg->i", r, dA) / area
    rho = r - centroid
    inertia = (np.einsum("fgk,fgk,fg->", rho, rho, dA) * np.eye(3)
               - np.einsum("fgi,fgj,fg->ij", rho, rho, dA))
    mean = np.einsum("fgi,fg->i", ug, dA) / area
    rotation = np.linalg.solve(inertia, np.einsum("fgi,fg->i", np.cross(rho, ug), dA))
    return {"area": area, "centroid": centroid, "displacement": mean, "rotation": rotation}


def cut_average(mesh: HexMesh, faces: np.ndarray, u: np.ndarray) -> dict:
    """Area-weighted mean displacement (3,) and least-squares rigid rotation (3,) over a cut.

    rotation omega minimises ``integral |u - u_mean - omega x (r - r_c)|^2 dA``, i.e.
    I omega = integral (r - r_c) x u dA (small rotations, rad).

    Parameters
    ----------
    mesh : HexMesh
        The hex27 mesh.
    faces : numpy.ndarray
        (n_f, 9) face node indices of the cut.
    u : numpy.ndarray
        (num_dof,) nodal displacements (m).

    Returns
    -------
    dict
        Mean displacement (3,) (m) and rotation (3,) (rad).
    """
    r, N, dA = _face_quadrature(mesh, faces)
    ug = np.einsum("ga,fai->fgi", N, u.reshape(-1, 3)[faces])
    return _cut_statistics(r, ug, dA)


def _cut_row(mesh: HexMesh, y: float):
    """Elements of the span row containing the cut y = const (the outboard row at a node slice,
    the last row at the tip) and the parametric eta with y(eta) = y."""
    g = mesh.grid_node
    y_slices = np.array([mesh.nodes[g[k][g[k] >= 0][0], 1] for k in range(g.shape[0])])
    if not y_slices[0] <= y <= y_slices[-1]:
        raise ValueError(f"y must be in [{y_slices[0]}, {y_slices[-1]}] m, got {y}")
    row = min(int(np.searchsorted(y_slices[0::2], y, side="right")) - 1, (g.shape[0] - 1) // 2 - 1)
    y0, y2 = y_slices[2 * row], y_slices[2 * row + 2]
    n_cells = int(mesh.active.sum())
    return mesh.elements[row * n_cells:(row + 1) * n_cells], 2.0 * (y - y0) / (y2 - y0) - 1.0


def cut_average_at(mesh: HexMesh, y: float, u: np.ndarray) -> dict:
    """:func:`cut_average` over the cut y = const of a structured mesh whose node slices are
    planes y = const with midside slices halfway (as built by the wing-box mesher).

    The FE field is evaluated inside the elements of the span row containing y at the
    parametric eta with y(eta) = y, 3x3 Gauss points over each cell of the cut.

    Parameters
    ----------
    mesh : HexMesh
        The hex27 mesh.
    y : float
        Span coordinate of the cut (m).
    u : numpy.ndarray
        (num_dof,) nodal displacements (m).

    Returns
    -------
    dict
        Mean displacement (3,) (m) and rotation (3,) (rad).
    """
    elements, eta = _cut_row(mesh, y)
    pts, w = _surface_rule()
    N, dN = hex27_shape(pts[:, 0], np.full(len(pts), eta), pts[:, 1])      # (g, 27), (g, 27, 3)
    X = mesh.nodes[elements]
    r = np.einsum("ga,eai->egi", N, X)
    dA = np.linalg.norm(np.cross(np.einsum("ga,eai->egi", dN[..., 0], X),
                                 np.einsum("ga,eai->egi", dN[..., 2], X)), axis=-1) * w
    ug = np.einsum("ga,eai->egi", N, u.reshape(-1, 3)[elements])
    return _cut_statistics(r, ug, dA)


def von_mises(stress: np.ndarray) -> np.ndarray:
    """Von Mises stress (Pa) from Voigt stresses (..., 6): xx, yy, zz, yz, xz, xy.

    Parameters
    ----------
    stress : numpy.ndarray
        (..., 6) Voigt stresses (Pa).

    Returns
    -------
    numpy.ndarray
        (...) von Mises stress (Pa).
    """
    sx, sy, sz, tyz, txz, txy = np.moveaxis(stress, -1, 0)
    return np.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2)
                   + 3.0 * (tyz ** 2 + txz ** 2 + txy ** 2))


def cut_stress_at(mesh: HexMesh, y: float, u: np.ndarray, E: float, nu: float) -> dict:
    """Von Mises stress over the streamwise cut y = const (as :func:`cut_average_at`): the FE
    stress of the span row containing y (the outboard row at a node slice, the last row at the
    tip) at 3x3 Gauss points of each cell. Returns ``mean_von_mises`` (area average),
    ``max_von_mises`` (over the points; Pa) and ``area`` (m^2).

    Parameters
    ----------
    mesh : HexMesh
        The hex27 mesh.
    y : float
        Span coordinate of the cut (m).
    u : numpy.ndarray
        (num_dof,) nodal displacements (m).
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio (-).

    Returns
    -------
    dict
        ``mean_von_mises``, ``max_von_mises`` (Pa) and ``area`` (m^2).
    """
    elements, eta = _cut_row(mesh, y)
    pts, w = _surface_rule()
    _, dN = hex27_shape(pts[:, 0], np.full(len(pts), eta), pts[:, 1])      # (g, 27, 3)
    X = mesh.nodes[elements]
    J = np.einsum("gak,eai->egik", dN, X)                                  # dx_i/dxi_k
    G = np.einsum("gak,egki->egai", dN, np.linalg.inv(J))                  # dN_a/dx_i
    grad = np.einsum("egaj,eai->egij", G, u.reshape(-1, 3)[elements])      # du_i/dx_j
    strain = np.stack([grad[..., 0, 0], grad[..., 1, 1], grad[..., 2, 2],
                       grad[..., 1, 2] + grad[..., 2, 1], grad[..., 0, 2] + grad[..., 2, 0],
                       grad[..., 0, 1] + grad[..., 1, 0]], axis=-1)
    vm = von_mises(stress_from_strain(strain, E, nu))
    dA = np.linalg.norm(np.cross(J[..., 0], J[..., 2]), axis=-1) * w       # area of the cut cells
    return {"mean_von_mises": float(np.sum(vm * dA) / np.sum(dA)), "max_von_mises": float(vm.max()),
            "area": float(np.sum(dA))}


# ----------------------------------------------------------------------------------------
# solve
# ----------------------------------------------------------------------------------------
def solve_linear(K: sp.spmatrix, f: np.ndarray, fixed_dofs: np.ndarray,
                 fixed_values: np.ndarray | float = 0.0) -> np.ndarray:
    """Solve K u = f with u[fixed_dofs] = fixed_values (direct sparse LU); returns u (num_dof,).

    Parameters
    ----------
    K : scipy.sparse.spmatrix
        Stiffness (N/m).
    f : numpy.ndarray
        (num_dof,) load vector (N).
    fixed_dofs : numpy.ndarray
        Indices of the prescribed DOFs.
    fixed_values : numpy.ndarray or float, optional
        Their values (m).

    Returns
    -------
    numpy.ndarray
        (num_dof,) displacements (m).
    """
    n = K.shape[0]
    fixed_dofs = np.asarray(fixed_dofs, int)
    u = np.zeros(n)
    u[fixed_dofs] = fixed_values
    free = np.setdiff1d(np.arange(n), fixed_dofs)
    K = K.tocsr()
    rhs = f[free] - K[free][:, fixed_dofs] @ u[fixed_dofs]
    Kff = K[free][:, free].tocsc()
    lu = spla.splu(Kff, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
    u[free] = lu.solve(rhs)
    if not np.all(np.isfinite(u)):
        raise ValueError("solid FE solve produced non-finite displacements: the structure is "
                         "not restrained against rigid-body motion")
    return u


def rigid_face_transform(num_dof: int, nodes: np.ndarray, positions: np.ndarray,
                         ref_point) -> tuple[sp.csr_matrix, np.ndarray]:
    """Kinematic coupling of ``nodes`` to a rigid master at ``ref_point`` (6 DOFs U, Theta).

    Returns (T, keep): u = T v with v = [u of all DOFs not on ``nodes``; U (3); Theta (3)],
    u_node = U + Theta x (r_node - ref_point) (small rotations); ``keep`` lists the retained
    physical DOFs (the first columns of T, in order).

    Parameters
    ----------
    num_dof : int
        Number of DOFs of the mesh.
    nodes : numpy.ndarray
        Node indices coupled to the master.
    positions : numpy.ndarray
        (n, 3) positions of all nodes (m).
    ref_point : array_like
        (3,) master point (m).

    Returns
    -------
    tuple
        (T, keep): the transform and the retained physical DOFs.
    """
    nodes = np.asarray(nodes, int)
    slave = node_dofs(nodes)
    keep = np.setdiff1d(np.arange(num_dof), slave)
    n_keep = len(keep)
    rows, cols, vals = [keep], [np.arange(n_keep)], [np.ones(n_keep)]
    rho = positions[nodes] - np.asarray(ref_point, float)          # (m, 3)
    # Theta x rho = -[rho]x Theta: components
    skew = np.zeros((len(nodes), 3, 3))
    skew[:, 0, 1], skew[:, 0, 2] = rho[:, 2], -rho[:, 1]
    skew[:, 1, 0], skew[:, 1, 2] = -rho[:, 2], rho[:, 0]
    skew[:, 2, 0], skew[:, 2, 1] = rho[:, 1], -rho[:, 0]
    for i in range(3):
        rows.append(3 * nodes + i)
        cols.append(np.full(len(nodes), n_keep + i))
        vals.append(np.ones(len(nodes)))
        for j in range(3):
            rows.append(3 * nodes + i)
            cols.append(np.full(len(nodes), n_keep + 3 + j))
            vals.append(skew[:, i, j])
    T = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(num_dof, n_keep + 6))
    return T, keep


def diaphragm_transform(num_dof: int, nodes: np.ndarray, positions: np.ndarray, ref_point,
                        normal_axis: int = 1) -> tuple[sp.csr_matrix, np.ndarray]:
    """A rigid diaphragm (an end rib): ``nodes`` move rigidly in the plane normal to body axis
    ``normal_axis``, free out of plane (warping allowed).

    Master DOFs at ``ref_point``: the two in-plane translations (axis order) and the rotation
    about the normal. Returns (T, keep) with u = T v, v = [retained DOFs; 3 master DOFs]
    (translation along the first in-plane axis, along the second, rotation about the normal).

    Parameters
    ----------
    num_dof : int
        Number of DOFs of the mesh.
    nodes : numpy.ndarray
        Node indices of the diaphragm.
    positions : numpy.ndarray
        (n, 3) positions of all nodes (m).
    ref_point : array_like
        (3,) master point (m).
    normal_axis : int, optional
        Body axis normal to the diaphragm (0, 1 or 2).

    Returns
    -------
    tuple
        (T, keep): the transform and the retained physical DOFs.
    """
    a, b = [k for k in range(3) if k != normal_axis]
    nodes = np.asarray(nodes, int)
    slave = np.concatenate([3 * nodes + a, 3 * nodes + b])
    keep = np.setdiff1d(np.arange(num_dof), slave)
    n_keep, m = len(keep), len(nodes)
    rho = positions[nodes] - np.asarray(ref_point, float)
    # Theta e_normal x rho: components along a and b (right-handed a, normal, b cyclic order)
    e = np.zeros(3)
    e[normal_axis] = 1.0
    cross = np.cross(e, rho)                                    # (m, 3)
    rows = [keep, 3 * nodes + a, 3 * nodes + b, 3 * nodes + a, 3 * nodes + b]
    cols = [np.arange(n_keep), np.full(m, n_keep), np.full(m, n_keep + 1),
            np.full(m, n_keep + 2), np.full(m, n_keep + 2)]
    vals = [np.ones(n_keep), np.ones(m), np.ones(m), cross[:, a], cross[:, b]]
    T = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(num_dof, n_keep + 3))
    return T, keep


def node_dofs(nodes: np.ndarray) -> np.ndarray:
    """All three DOFs of the given nodes (flattened).

    Parameters
    ----------
    nodes : numpy.ndarray
        Node indices.

    Returns
    -------
    numpy.ndarray
        Their DOF indices.
    """
    return (3 * np.asarray(nodes)[:, None] + np.arange(3)).ravel()


def mesh_volume(mesh: HexMesh) -> float:
    """Volume of the mesh (m^3) by 3x3x3 Gauss quadrature (exact for trilinear maps).

    Parameters
    ----------
    mesh : HexMesh
        The hex27 mesh.

    Returns
    -------
    float
        Volume (m^3).
    """
    _, wd = _physical_gradients(mesh, mesh.elements)
    return float(wd.sum())
