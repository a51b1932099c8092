"""Giavotto/BECAS cross-section analysis on Q9 meshes (dissertation Sec. 4.2, App. C).

Displacement u = Z(x2, x3) r(x1) + N(x2, x3) w(x1); strain eps = Z_s psi + B w + S w' with
psi = [eps1, gamma12, gamma13, kappa1, kappa2, kappa3] the sectional strains (Voigt strain order
[11, 22, 33, 23, 13, 12]). See docs/cross-section-fe.md for the derivation of the two solves.
"""

from __future__ import annotations

import multiprocessing as mp
import os
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse.csgraph import reverse_cuthill_mckee

from .mesh import SectionMesh

_GP1 = np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
_GW1 = np.array([5.0, 8.0, 5.0]) / 9.0


def _q9_shape():
    """Shape functions and local derivatives at the 3x3 Gauss points: N (9g, 9), dN/dxi, dN/deta."""
    def lag(x):
        return np.array([0.5 * x * (x - 1), 1 - x * x, 0.5 * x * (x + 1)])

    def dlag(x):
        return np.array([x - 0.5, -2 * x, x + 0.5])
    N, Nx, Ny, W = [], [], [], []
    for b, eta in enumerate(_GP1):
        for a, xi in enumerate(_GP1):
            N.append(np.outer(lag(eta), lag(xi)).ravel())
            Nx.append(np.outer(lag(eta), dlag(xi)).ravel())
            Ny.append(np.outer(dlag(eta), lag(xi)).ravel())
            W.append(_GW1[a] * _GW1[b])
    return np.array(N), np.array(Nx), np.array(Ny), np.array(W)


_N, _NXI, _NETA, _W = _q9_shape()


@dataclass
class Section:
    """Result of a cross-section analysis (SI; 6x6 order F1, F2, F3, M1, M2, M3 about the section origin).

    Parameters
    ----------
    mesh : SectionMesh
        The analysed mesh.
    stiffness : numpy.ndarray
        (6, 6) Timoshenko stiffness about the section origin.
    compliance : numpy.ndarray
        (6, 6) inverse of ``stiffness``.
    mass : numpy.ndarray
        (6, 6) mass matrix per length about the origin.
    shear_center, tension_center, mass_center : numpy.ndarray
        (2,) [x2, x3] of each centre (m).
    area : float
        Section area (m^2).
    X : numpy.ndarray
        (3 nn, 6) warping per unit sectional force.
    dX : numpy.ndarray
        (3 nn, 6) its x1 derivative.
    Y : numpy.ndarray
        (6, 6) sectional strains per unit force.
    """

    mesh: SectionMesh
    stiffness: np.ndarray
    compliance: np.ndarray
    mass: np.ndarray
    shear_center: np.ndarray
    tension_center: np.ndarray
    mass_center: np.ndarray
    area: float
    X: np.ndarray        # warping per unit sectional force (3 nn, 6)
    dX: np.ndarray       # its x1 derivative X T (3 nn, 6)
    Y: np.ndarray        # sectional strains per unit force (6, 6)


def _geometry(mesh):
    xe = mesh.nodes[mesh.elements]                       # (ne, 9, 2)
    pts = np.einsum("gk,ekd->egd", _N, xe)               # Gauss point coords (ne, 9g, 2)
    J11 = np.einsum("gk,ek->eg", _NXI, xe[..., 0]); J12 = np.einsum("gk,ek->eg", _NXI, xe[..., 1])
    J21 = np.einsum("gk,ek->eg", _NETA, xe[..., 0]); J22 = np.einsum("gk,ek->eg", _NETA, xe[..., 1])
    det = J11 * J22 - J12 * J21
    if np.any(det == 0) or np.any(np.sign(det) != np.sign(det[:, :1])):
        bad = int(np.nonzero(np.any(det == 0, axis=1) | np.any(np.sign(det) != np.sign(det[:, :1]), axis=1))[0][0])
        raise ValueError(f"mesh element {bad} is degenerate or folded (Jacobian changes sign)")
    dN2 = (J22[..., None] * _NXI - J12[..., None] * _NETA) / det[..., None]   # d/dx2 (ne, g, 9)
    dN3 = (-J21[..., None] * _NXI + J11[..., None] * _NETA) / det[..., None]  # d/dx3
    wdet = _W * np.abs(det)
    return pts, dN2, dN3, wdet


def _element_operators(mesh):
    """B (ne, g, 6, 27), S (ne, g, 6, 27), Z (ne, g, 6, 6), weights (ne, g)."""
    pts, dN2, dN3, wdet = _geometry(mesh)
    ne, ng = wdet.shape
    B = np.zeros((ne, ng, 6, 9, 3)); S = np.zeros((ne, ng, 6, 9, 3))
    B[:, :, 1, :, 1] = dN2                 # eps22 = d2 u2
    B[:, :, 2, :, 2] = dN3                 # eps33 = d3 u3
    B[:, :, 3, :, 1] = dN3; B[:, :, 3, :, 2] = dN2   # gamma23
    B[:, :, 4, :, 0] = dN3                 # gamma13 = d3 u1 (+ d1 u3 in S)
    B[:, :, 5, :, 0] = dN2                 # gamma12 = d2 u1 (+ d1 u2 in S)
    Nb = np.broadcast_to(_N, (ne, ng, 9))
    S[:, :, 0, :, 0] = Nb; S[:, :, 4, :, 2] = Nb; S[:, :, 5, :, 1] = Nb
    x2, x3 = pts[..., 0], pts[..., 1]
    Z = np.zeros((ne, ng, 6, 6))
    Z[..., 0, 0] = 1; Z[..., 0, 4] = x3; Z[..., 0, 5] = -x2
    Z[..., 4, 2] = 1; Z[..., 4, 3] = x2
    Z[..., 5, 1] = 1; Z[..., 5, 3] = -x3
    return B.reshape(ne, ng, 6, 27), S.reshape(ne, ng, 6, 27), Z, wdet, pts


def assemble(mesh, Ke, dofs, n):
    """Sparse (n, n) matrix from element matrices Ke (ne, 27, 27) on element dofs (ne, 27).

    Parameters
    ----------
    mesh : SectionMesh
        The mesh (not used by the assembly).
    Ke : numpy.ndarray
        (ne, 27, 27) element matrices.
    dofs : numpy.ndarray
        (ne, 27) global dof indices of each element.
    n : int
        Number of global dofs.

    Returns
    -------
    scipy.sparse.csr_matrix
        (n, n) assembled matrix.
    """
    return _assemble(mesh, Ke, dofs, n)


def assemble_rect(Ke, dofs, n, m):
    """Sparse (n, m) matrix from element blocks Ke (ne, 27, m) on element dofs (ne, 27).

    Parameters
    ----------
    Ke : numpy.ndarray
        (ne, 27, m) element blocks.
    dofs : numpy.ndarray
        (ne, 27) global dof indices of each element.
    n : int
        Number of global dofs (rows).
    m : int
        Number of columns.

    Returns
    -------
    scipy.sparse.csr_matrix
        (n, m) assembled matrix.
    """
    return _assemble_rect(Ke, dofs, n, m)


def element_operators(mesh):
    """Strain operators B, S (ne, g, 6, 27), rigid-section operator Z (ne, g, 6, 6), weights (ne, g)
    and Gauss points (ne, g, 2) of every element (Giavotto/BECAS form, docs/cross-section-fe.md).

    Parameters
    ----------
    mesh : SectionMesh
        The Q9 mesh.

    Returns
    -------
    tuple
        ``B``, ``S`` (ne, g, 6, 27), ``Z`` (ne, g, 6, 6), weights (ne, g), Gauss points (ne, g, 2).
    """
    return _element_operators(mesh)


def _assemble(mesh, Ke, dofs, n):
    rows = np.broadcast_to(dofs[:, :, None], Ke.shape).ravel()
    cols = np.broadcast_to(dofs[:, None, :], Ke.shape).ravel()
    return sp.csr_matrix((Ke.ravel(), (rows, cols)), shape=(n, n))


def _assemble_rect(Ke, dofs, n, m):
    rows = np.broadcast_to(dofs[:, :, None], Ke.shape).ravel()
    cols = np.broadcast_to(np.arange(m)[None, None, :], Ke.shape).ravel()
    return sp.csr_matrix((Ke.ravel(), (rows, cols)), shape=(n, m))


def analyse_section(mesh: SectionMesh) -> Section:
    """6x6 Timoshenko stiffness and mass, centres and warping fields of a meshed section.

    Parameters
    ----------
    mesh : SectionMesh
        The Q9 mesh.

    Returns
    -------
    Section
        Stiffness, mass, centres and warping fields.
    """
    B, S, Z, wdet, pts = _element_operators(mesh)
    Q = mesh.Q
    nn = mesh.nodes.shape[0]
    n = 3 * nn
    dofs = (3 * mesh.elements[:, :, None] + np.arange(3)).reshape(-1, 27)
    ne, ng = wdet.shape
    wQ = Q[:, None] * wdet[:, :, None, None]                          # weighted material (ne, g, 6, 6)
    QB = (wQ @ B).reshape(ne, ng * 6, 27)
    QS = (wQ @ S).reshape(ne, ng * 6, 27)
    QZ = (wQ @ Z).reshape(ne, ng * 6, 6)
    Bt = B.reshape(ne, ng * 6, 27).transpose(0, 2, 1)
    St = S.reshape(ne, ng * 6, 27).transpose(0, 2, 1)
    E = _assemble(mesh, Bt @ QB, dofs, n)
    C = _assemble(mesh, St @ QB, dofs, n)                              # int S^T Q B
    M = _assemble(mesh, St @ QS, dofs, n)
    R = _assemble_rect(Bt @ QZ, dofs, n, 6).toarray()
    L = _assemble_rect(St @ QZ, dofs, n, 6).toarray()
    A = (Z.reshape(ne, ng * 6, 6).transpose(0, 2, 1) @ QZ).sum(axis=0)
    # rigid-body warping constraints D^T w = 0 (nodal rigid motions)
    x2, x3 = mesh.nodes[:, 0], mesh.nodes[:, 1]
    D = np.zeros((nn, 3, 6))
    D[:, 0, 0] = 1; D[:, 1, 1] = 1; D[:, 2, 2] = 1
    D[:, 1, 3] = -x3; D[:, 2, 3] = x2; D[:, 0, 4] = x3; D[:, 0, 5] = -x2
    D = D.reshape(n, 6)
    scale = np.sqrt(np.abs(E.diagonal()).mean())
    Ds = sp.csr_matrix(D * scale)
    Rs = sp.csr_matrix(R)
    # bandwidth-reducing order of the warping dofs; the 12 dense border rows/columns stay last
    perm = reverse_cuthill_mckee(E.tocsr(), symmetric_mode=True)
    perm = np.concatenate([perm, np.arange(n, n + 12)])
    K = sp.bmat([[E, Rs, Ds], [Rs.T, sp.csr_matrix(A), None], [Ds.T, None, None]], format="csr")
    K = K[perm][:, perm].tocsc()
    lu_p = spla.splu(K, permc_spec="NATURAL", diag_pivot_thresh=0.0)
    inv_perm = np.argsort(perm)

    class _LU:
        @staticmethod
        def solve(b):
            return lu_p.solve(np.ascontiguousarray(b[perm]))[inv_perm]
    lu = _LU()
    T = np.zeros((6, 6)); T[4, 2] = 1.0; T[5, 1] = -1.0       # theta' = T theta (M2' = F3, M3' = -F2)
    rhs0 = np.zeros((n + 12, 6)); rhs0[n:n + 6] = np.eye(6)
    s0 = lu.solve(rhs0)
    X0, Y0 = s0[:n], s0[n:n + 6]
    X0T, Y0T = X0 @ T, Y0 @ T
    rhs1 = np.zeros((n + 12, 6))
    rhs1[:n] = -(C.T @ X0T - C @ X0T) + L @ Y0T
    rhs1[n:n + 6] = -L.T @ X0T
    s1 = lu.solve(rhs1)
    X, Y = X0 + s1[:n], Y0 + s1[n:n + 6]
    dX = X @ T
    cross = X.T @ (C.T @ dX) + X.T @ R @ Y + dX.T @ L @ Y
    F = X.T @ (E @ X) + dX.T @ (M @ dX) + Y.T @ A @ Y + cross + cross.T
    F = 0.5 * (F + F.T)
    Kst = np.linalg.inv(F)
    Kst = 0.5 * (Kst + Kst.T)
    mass, mc = _mass_matrix(mesh.rho, wdet, pts)
    area = float(wdet.sum())
    return Section(mesh, Kst, F, mass, _shear_center(F), _tension_center(F), mc, area, X, dX, Y)


def _mass_matrix(rho, wdet, pts):
    w = rho[:, None] * wdet
    m = w.sum()
    x2, x3 = pts[..., 0], pts[..., 1]
    m2, m3 = (w * x2).sum(), (w * x3).sum()
    I22, I33, I23 = (w * x3 ** 2).sum(), (w * x2 ** 2).sum(), (w * x2 * x3).sum()
    Mm = np.zeros((6, 6))
    Mm[0, 0] = Mm[1, 1] = Mm[2, 2] = m
    Mm[0, 4] = Mm[4, 0] = m3; Mm[0, 5] = Mm[5, 0] = -m2
    Mm[1, 3] = Mm[3, 1] = -m3; Mm[2, 3] = Mm[3, 2] = m2
    Mm[3, 3] = I22 + I33; Mm[4, 4] = I22; Mm[5, 5] = I33; Mm[4, 5] = Mm[5, 4] = -I23
    return Mm, (np.array([m2, m3]) / m if m > 0 else np.zeros(2))


def _shear_center(F):
    """Point (x2, x3) where a shear force causes no twist: x2 = -F43/F44, x3 = F42/F44 (1-based)."""
    return np.array([-F[3, 2] / F[3, 3], F[3, 1] / F[3, 3]])


def _tension_center(F):
    """Point (a2, a3) where an axial force causes no bending curvature (M2 = a3 F1, M3 = -a2 F1)."""
    Amat = np.array([[-F[4, 5], F[4, 4]], [-F[5, 5], F[5, 4]]])
    return np.linalg.solve(Amat, -np.array([F[4, 0], F[5, 0]]))


def recover_stresses(section: Section, forces6):
    """3-D stresses [s11, s22, s33, s23, s13, s12] (Pa) at every Gauss point, shape (ne, 9, 6),
    for sectional forces/moments [F1, F2, F3, M1, M2, M3] (N, N*m) about the section origin.

    Uses the central solution strains eps = Z Y theta + B X theta + S X T theta (App. C).

    Parameters
    ----------
    section : Section
        An analysed section.
    forces6 : array_like
        (6,) sectional forces and moments [F1, F2, F3, M1, M2, M3] (N, N m).

    Returns
    -------
    numpy.ndarray
        (ne, 9, 6) stresses (Pa).
    """
    theta = np.asarray(forces6, float)
    if theta.shape != (6,) or not np.all(np.isfinite(theta)):
        raise ValueError("forces6 must be 6 finite values [F1, F2, F3, M1, M2, M3] in N and N*m")
    mesh = section.mesh
    B, S, Z, _, _ = _element_operators(mesh)
    dofs = (3 * mesh.elements[:, :, None] + np.arange(3)).reshape(-1, 27)
    w, dw, psi = section.X @ theta, section.dX @ theta, section.Y @ theta
    eps = (np.einsum("egij,j->egi", Z, psi) + np.einsum("egij,ej->egi", B, w[dofs])
           + np.einsum("egij,ej->egi", S, dw[dofs]))
    return np.einsum("eij,egj->egi", mesh.Q, eps)


def beam_properties_csn(section: Section) -> dict:
    """Section stiffness and mass in the beam's csn form (c = x2, n = x3, s along the beam).

    The FE frame (x1, x2, x3) is right-handed with x2 = c, x3 = n, so x1 = c x n = -s: moment and
    curvature components along s are minus those along x1 (see docs/cross-section-fe.md).
    Returns stiffness_csn (3x3 moment/curvature, about the tension centre, shear condensed),
    compliance_csn [1/GK_c, 1/EA, 1/GK_n], tension/shear-centre and mass-centre offsets (c, n),
    mass_per_length and inertia_csn (3x3 per length about the mass centre).

    Parameters
    ----------
    section : Section
        An analysed section.

    Returns
    -------
    dict
        ``stiffness_csn``, ``compliance_csn``, centre offsets, ``mass_per_length``, ``inertia_csn``.
    """
    F = section.compliance
    idx = [0, 3, 4, 5]
    K4 = np.linalg.inv(F[np.ix_(idx, idx)])
    Kb = K4[1:, 1:] - np.outer(K4[1:, 0], K4[0, 1:]) / K4[0, 0]     # moments with zero axial force
    P = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # (c, s, n) <- (x1, x2, x3)
    K_csn = P @ Kb @ P.T
    a2, a3 = section.tension_center
    f = np.array([1.0, 0.0, 0.0, 0.0, a3, -a2])
    EA = 1.0 / (f @ F @ f)
    s2, s3 = section.shear_center
    fc = np.array([0.0, 1.0, 0.0, -s3, 0.0, 0.0]); fn = np.array([0.0, 0.0, 1.0, s2, 0.0, 0.0])
    Mm = section.mass
    m = Mm[0, 0]
    c, n = section.mass_center
    Icc = Mm[4, 4] - m * n * n; Inn = Mm[5, 5] - m * c * c; Icn = -(-Mm[4, 5] - m * c * n)
    inertia = np.array([[Icc, 0.0, Icn], [0.0, Icc + Inn, 0.0], [Icn, 0.0, Inn]])
    return {"stiffness_csn": K_csn, "compliance_csn": np.array([fc @ F @ fc, 1.0 / EA, fn @ F @ fn]),
            "tension_center_cn": section.tension_center.copy(), "shear_center_cn": section.shear_center.copy(),
            "mass_per_length": m, "mass_center_cn": section.mass_center.copy(), "inertia_csn": inertia}


_JOBS: list = []   # jobs of analyse_sections, inherited by forked workers (closures need not pickle)


def _run_job(k):
    job = _JOBS[k]
    return analyse_section(job() if callable(job) else job)


def analyse_sections(jobs, processes: int | None = None) -> list:
    """:func:`analyse_section` of many sections (e.g. all stations of a wing) on worker processes.

    ``jobs``: meshes, or zero-argument callables that build a mesh (then meshing runs in the
    workers too). ``processes``: default the CPU count; 1 = serial in this process. Workers are
    forked (they inherit the jobs, so closures such as airfoil surface functions are fine);
    where fork is unavailable the jobs run serially.

    Parameters
    ----------
    jobs : sequence
        Meshes, or zero-argument callables that build one.
    processes : int or None, optional
        Worker processes; None for the CPU count, 1 for serial.

    Returns
    -------
    list of Section
        One per job, in order.
    """
    global _JOBS
    jobs = list(jobs)
    n_proc = min(len(jobs), processes or os.cpu_count() or 1)
    if n_proc <= 1 or "fork" not in mp.get_all_start_methods():
        return [analyse_section(j() if callable(j) else j) for j in jobs]
    _JOBS = jobs
    try:
        with ProcessPoolExecutor(max_workers=n_proc, mp_context=mp.get_context("fork")) as pool:
            return list(pool.map(_run_job, range(len(jobs))))
    finally:
        _JOBS = []
