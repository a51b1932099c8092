"""Local stiffener smearing by stiffness matching (dissertation Sec. 4.1, Eq. 4.1-4.10).

A built-up plate (width ``b`` along x2 = c, thickness ``t`` along x3 = n, centred on the origin)
carries blade stiffeners of any size and position. Its equivalent plate is the bare plate whose
stiffener footprints (the plate cells under each stiffener) get their own orthotropic material
with the 9 parameters of Eq. 4.4. The parameters are found by matching the classical 4x4
stiffness of the two sections (Methods 1-3) with SLSQP and exact CasADi gradients: the FE
section analysis (wingmdao.section.fe, Giavotto/BECAS) is rebuilt symbolically in CasADi MX,
with the element matrices linear in the parameters and the two warping solves done by a sparse
LU (``ca.solve(..., 'csparse')``), whose derivative CasADi forms exactly.

4x4 order (the dissertation's, Sec. 4.1.4): [axial, torsion, in-plane bending (about n, load case 2),
out-of-plane bending (about c, load case 3)] = FE components [F1, M1, M3, M2] about the section origin,
shear forces condensed out (inverse of the matching 4x4 block of the 6x6 FE compliance).
See docs/stiffener-smearing.md.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np
import scipy.optimize as so

from wingmdao.section.fe.analysis import analyse_section, assemble, assemble_rect, element_operators
from wingmdao.section.fe.materials import isotropic
from wingmdao.section.fe.mesh import SectionMesh, q9_from_grid, refine_edges
from wingmdao.beam.static import BeamModel, beam_parameters, straight_beam
from wingmdao.section.fe import beam_properties_csn

#: names of the 9 orthotropic parameters of Eq. 4.4 (VABS strain order 11, 12, 13, 22, 23, 33)
PARAM_NAMES = ("c11", "c14", "c16", "c22", "c33", "c44", "c46", "c55", "c66")
# (row, col) of each parameter in this package's Voigt order [11, 22, 33, 23, 13, 12]
_PARAM_POS = ((0, 0), (0, 1), (0, 2), (5, 5), (4, 4), (1, 1), (1, 2), (3, 3), (2, 2))
#: Table 4.3 (Method 2) and Table 4.4 (Method 3) bounds, order PARAM_NAMES
BOUNDS_METHOD2 = (np.array([1, 0, 0, 0.1, 0.1, 1, 0.5, 0.1, 1.0]), np.array([10, 1, 1, 1, 1, 1000, 1, 1, 1000.0]))
BOUNDS_METHOD3 = (np.array([1, 0, 0, -10, -10, 1, 0.5, 0.1, 1.0]), np.array([10, 1, 1, 1, 1, 1000, 1, 1, 1000.0]))
_ORDER4 = [0, 3, 5, 4]          # FE [F1, M1, M3, M2] -> [axial, torsion, in-plane, out-of-plane]

ALUMINIUM = isotropic(70e9, 0.33, 2700.0, "aluminium")


@dataclass(frozen=True)
class Stiffener:
    """Blade stiffener: centre ``position`` (x2, m), ``width`` (x2, m), ``height`` (x3, m) standing on
    the ``side`` ('upper' or 'lower') face of the plate (Fig. 4.4: a_i, w_i, h_i).

    Parameters
    ----------
    position : float
        Stiffener centre along the plate width x2 (m).
    width : float
        Stiffener width along x2 (m).
    height : float
        Stiffener height along x3 (m).
    side : {"upper", "lower"}, optional
        Face of the plate the stiffener stands on.
    """

    position: float
    width: float
    height: float
    side: str = "upper"


#: Sec. 4.1.3 specimens 1-4 (Tables 4.5-4.7): plate 0.17 m x 0.01 m, length 0.75 m
PLATE_WIDTH, PLATE_THICKNESS, PLATE_LENGTH = 0.17, 0.01, 0.75
SPECIMENS = {
    1: (),
    2: (Stiffener(0.01, 0.01, 0.01, "upper"),),
    3: (Stiffener(0.01, 0.01, 0.03, "upper"),),
    4: (Stiffener(0.01, 0.012, 0.0075, "upper"), Stiffener(-0.035, 0.0075, 0.0125, "lower")),
}
#: Table 4.8 tip loads (N) along [axial, in-plane, out-of-plane]
LOAD_CASES = {1: np.array([1e6, 0.0, 0.0]), 2: np.array([0.0, 5e4, 0.0]), 3: np.array([0.0, 0.0, 2e2])}


def _check_geometry(width, thickness, stiffeners):
    for name, v in (("plate width", width), ("plate thickness", thickness)):
        if not np.isfinite(v) or v <= 0:
            raise ValueError(f"{name} must be > 0 m, got {v}")
    spans = []
    for k, st in enumerate(stiffeners):
        if st.side not in ("upper", "lower"):
            raise ValueError(f"stiffener {k}: side must be 'upper' or 'lower', got {st.side!r}")
        for name in ("width", "height"):
            v = getattr(st, name)
            if not np.isfinite(v) or v <= 0:
                raise ValueError(f"stiffener {k}: {name} must be > 0 m, got {v}")
        x0, x1 = st.position - st.width / 2, st.position + st.width / 2
        if x0 < -width / 2 or x1 > width / 2:
            raise ValueError(f"stiffener {k}: position {st.position} m +- width/2 must lie within the plate "
                             f"[{-width / 2}, {width / 2}] m")
        for j, (a, b) in enumerate(spans):
            if x0 < b and a < x1:
                raise ValueError(f"stiffener {k}: footprint overlaps stiffener {j}")
        spans.append((x0, x1))


def _edges(breaks, mesh_size):
    out = [breaks[0]]
    for a, b in zip(breaks[:-1], breaks[1:]):
        n = max(1, int(np.ceil((b - a) / mesh_size - 1e-9)))
        out += list(np.linspace(a, b, n + 1)[1:])
    return np.array(out)


def stiffened_plate_mesh(stiffeners=(), width=PLATE_WIDTH, thickness=PLATE_THICKNESS, material=ALUMINIUM,
                         equivalent=False, region_Q=None, mesh_size=0.0025, n_thick=2) -> SectionMesh:
    """Q9 mesh of a plate with blade stiffeners (a union of rectangles on a structured grid).

    ``equivalent=True`` gives the equivalent plate: no stiffeners, the footprint of stiffener k is
    region k + 1 with stiffness ``region_Q[k]`` (6x6, Pa; default the plate material).
    Region 0 is the plate; in the built-up mesh region k + 1 is stiffener k.

    Parameters
    ----------
    stiffeners : sequence of Stiffener, optional
        The blade stiffeners.
    width : float, optional
        Plate width (m).
    thickness : float, optional
        Plate thickness (m).
    material : section.fe.materials.Material, optional
        Plate and stiffener material.
    equivalent : bool, optional
        Build the equivalent plate (stiffener footprints as regions) instead of the built-up one.
    region_Q : sequence of array_like or None, optional
        (6, 6) stiffness of each stiffener region of the equivalent plate (Pa); None for the plate
        material.
    mesh_size : float, optional
        Target element size (m).
    n_thick : int, optional
        Elements through the plate thickness.

    Returns
    -------
    SectionMesh
        The Q9 mesh.
    """
    stiffeners = tuple(stiffeners)
    _check_geometry(width, thickness, stiffeners)
    if not np.isfinite(mesh_size) or mesh_size <= 0:
        raise ValueError(f"mesh_size must be > 0 m, got {mesh_size}")
    xb = sorted({-width / 2, width / 2, *[s.position + d * s.width / 2 for s in stiffeners for d in (-1, 1)]})
    xe = _edges(xb, mesh_size)
    yplate = list(np.linspace(-thickness / 2, thickness / 2, n_thick + 1))
    hu = sorted({s.height for s in stiffeners if s.side == "upper"}) if not equivalent else []
    hl = sorted({s.height for s in stiffeners if s.side == "lower"}) if not equivalent else []
    yb = sorted({*yplate, *[thickness / 2 + h for h in hu], *[-thickness / 2 - h for h in hl]})
    ye = _edges(yb, mesh_size)
    xm, ym = 0.5 * (xe[1:] + xe[:-1]), 0.5 * (ye[1:] + ye[:-1])
    XM, YM = np.meshgrid(xm, ym, indexing="ij")
    in_plate = np.abs(YM) < thickness / 2
    region = np.zeros(XM.shape, int)
    mask = in_plate.copy()
    for k, s in enumerate(stiffeners):
        in_x = np.abs(XM - s.position) < s.width / 2
        if equivalent:
            region[in_x & in_plate] = k + 1
        else:
            lo, hi = (thickness / 2, thickness / 2 + s.height) if s.side == "upper" else (-thickness / 2 - s.height,
                                                                                     -thickness / 2)
            cell = in_x & (YM > lo) & (YM < hi)
            region[cell] = k + 1
            mask |= cell
    Qs = [material.C] + [material.C if region_Q is None else np.asarray(region_Q[k]) for k in range(len(stiffeners))]
    Q = np.array(Qs)[region]
    rho = np.full(XM.shape, material.rho)
    X, Y = np.meshgrid(refine_edges(xe), refine_edges(ye), indexing="ij")
    names = ["plate"] + [f"stiffener {k}" for k in range(len(stiffeners))]
    return q9_from_grid(X, Y, mask, Q, rho, region, names)


def classical_stiffness(section) -> np.ndarray:
    """Classical 4x4 stiffness of Eq. 4.2 [axial, torsion, in-plane, out-of-plane bending] about the
    section origin, shear forces condensed out (inverse of the 4x4 block of the FE compliance).

    Parameters
    ----------
    section : Section
        An analysed FE section (:func:`~wingmdao.section.fe.analysis.analyse_section`).

    Returns
    -------
    numpy.ndarray
        (4, 4) classical stiffness [axial, torsion, in-plane, out-of-plane bending] (N, N m^2).
    """
    F = section.compliance
    return np.linalg.inv(F[np.ix_(_ORDER4, _ORDER4)])


def material_matrix(params, E=ALUMINIUM.E_ref) -> np.ndarray:
    """6x6 stiffness (Pa, Voigt [11, 22, 33, 23, 13, 12]) from the 9 parameters of Eq. 4.4 times E.

    Parameters
    ----------
    params : array_like
        The 9 parameters of Eq. 4.4, over E (-).
    E : float, optional
        Reference modulus (Pa).

    Returns
    -------
    numpy.ndarray
        (6, 6) stiffness (Pa).
    """
    p = np.asarray(params, float)
    if p.shape != (9,) or not np.all(np.isfinite(p)):
        raise ValueError(f"params must be 9 finite values {PARAM_NAMES}, got shape {p.shape}")
    C = np.zeros((6, 6))
    for v, (i, j) in zip(p, _PARAM_POS):
        C[i, j] = C[j, i] = E * v
    return C


def initial_guess(stiffener: Stiffener, thickness=PLATE_THICKNESS, nu=0.33) -> np.ndarray:
    """Method 1, the analytic guess of Eq. 4.5-4.8 for one stiffener region (parameters over E).

    k_A = built-up area over equivalent area of the region = (t + h) / t (Eq. 4.7);
    E1 = E2 = E3 = k_A E (4.6); G12 = G13 = E1 / (2 (1 + nu)), G23 = E / (2 (1 + nu)) (4.8).

    Parameters
    ----------
    stiffener : Stiffener
        The stiffener of the region.
    thickness : float, optional
        Plate thickness (m).
    nu : float, optional
        Poisson's ratio (-).

    Returns
    -------
    numpy.ndarray
        (9,) parameters over E (-).
    """
    kA = (thickness + stiffener.height) / thickness
    E1 = kA
    S = np.zeros((6, 6))
    S[0, 0] = S[1, 1] = S[2, 2] = 1 / E1
    S[0, 1] = S[1, 0] = S[0, 2] = S[2, 0] = S[1, 2] = S[2, 1] = -nu / E1
    S[5, 5] = S[4, 4] = 2 * (1 + nu) / E1
    S[3, 3] = 2 * (1 + nu) / 1.0
    C = np.linalg.inv(S)
    return np.array([C[i, j] for i, j in _PARAM_POS])


def _matrices(mesh, Q):
    """Assembled E, C, M (sparse) and R, L, A (dense) of the FE analysis for element stiffnesses Q."""
    B, S, Z, wdet, _ = element_operators(mesh)
    nn = mesh.nodes.shape[0]
    n = 3 * nn
    dofs = (3 * mesh.elements[:, :, None] + np.arange(3)).reshape(-1, 27)
    ne, ng = wdet.shape
    wQ = Q[:, None] * wdet[:, :, None, None]
    QB = (wQ @ B).reshape(ne, ng * 6, 27)
    QZ = (wQ @ Z).reshape(ne, ng * 6, 6)
    QS = (wQ @ S).reshape(ne, ng * 6, 27)
    Bt = B.reshape(ne, ng * 6, 27).transpose(0, 2, 1)
    St = S.reshape(ne, ng * 6, 27).transpose(0, 2, 1)
    return (assemble(mesh, Bt @ QB, dofs, n), assemble(mesh, St @ QB, dofs, n), assemble(mesh, St @ QS, dofs, n),
            assemble_rect(Bt @ QZ, dofs, n, 6).toarray(), assemble_rect(St @ QZ, dofs, n, 6).toarray(),
            (Z.reshape(ne, ng * 6, 6).transpose(0, 2, 1) @ QZ).sum(axis=0))


def _dm(m):
    c = m.tocoo()
    return ca.DM.triplet(c.row.tolist(), c.col.tolist(), c.data.tolist(), m.shape[0], m.shape[1])


class EquivalentPlate:
    """Equivalent plate with one 9-parameter orthotropic material per stiffener region.

    ``stiffness(p)`` and ``jacobian(p)`` give the classical 4x4 stiffness (Eq. 4.2) and its exact
    derivative with respect to the parameters p (n_region x 9, over E), from a CasADi MX model of
    the FE section analysis (element matrices linear in p, sparse LU warping solves).

    Parameters
    ----------
    stiffeners : sequence of Stiffener
        The blade stiffeners.
    width : float, optional
        Plate width (m).
    thickness : float, optional
        Plate thickness (m).
    material : section.fe.materials.Material, optional
        Plate and stiffener material.
    mesh_size : float, optional
        Target element size (m).
    n_thick : int, optional
        Elements through the plate thickness.
    """

    def __init__(self, stiffeners, width=PLATE_WIDTH, thickness=PLATE_THICKNESS, material=ALUMINIUM,
                 mesh_size=0.0025, n_thick=2):
        self.stiffeners = tuple(stiffeners)
        self.E, self.material = material.E_ref, material
        self.mesh = stiffened_plate_mesh(self.stiffeners, width, thickness, material, True, None, mesh_size, n_thick)
        self.n_region = len(self.stiffeners)
        self.p = ca.MX.sym("p", 9 * self.n_region)
        mesh = self.mesh
        Q0 = mesh.Q.copy()
        Q0[mesh.region > 0] = 0.0
        terms = [(None, _matrices(mesh, Q0))]
        for r in range(self.n_region):
            for k, (i, j) in enumerate(_PARAM_POS):
                U = np.zeros((6, 6)); U[i, j] = U[j, i] = self.E
                Qk = np.zeros_like(mesh.Q); Qk[mesh.region == r + 1] = U
                terms.append((self.p[9 * r + k], _matrices(mesh, Qk)))
        mats = []
        for m in range(6):
            acc = 0
            for coef, mm in terms:
                val = _dm(mm[m]) if m < 3 else ca.DM(mm[m])
                acc = acc + (val if coef is None else coef * val)
            mats.append(acc)
        Em, Cm, Mm, Rm, Lm, Am = mats
        nn = mesh.nodes.shape[0]; n = 3 * nn
        x2, x3 = mesh.nodes[:, 0], mesh.nodes[:, 1]
        D = np.zeros((nn, 3, 6))
        D[:, 0, 0] = 1; D[:, 1, 1] = 1; D[:, 2, 2] = 1
        D[:, 1, 3] = -x3; D[:, 2, 3] = x2; D[:, 0, 4] = x3; D[:, 0, 5] = -x2
        D = ca.DM(D.reshape(n, 6) * np.sqrt(np.abs(terms[0][1][0].diagonal()).mean() + self.E))
        K = ca.blockcat([[Em, Rm, D], [Rm.T, Am, ca.DM(6, 6)], [D.T, ca.DM(6, 6), ca.DM(6, 6)]])
        T = np.zeros((6, 6)); T[4, 2] = 1.0; T[5, 1] = -1.0
        T = ca.DM(T)
        rhs0 = np.zeros((n + 12, 6)); rhs0[n:n + 6] = np.eye(6)
        s0 = ca.solve(K, ca.DM(rhs0), "csparse")
        X0, Y0 = s0[:n, :], s0[n:n + 6, :]
        X0T, Y0T = ca.mtimes(X0, T), ca.mtimes(Y0, T)
        r1 = -(ca.mtimes(Cm.T, X0T) - ca.mtimes(Cm, X0T)) + ca.mtimes(Lm, Y0T)
        rhs1 = ca.vertcat(r1, -ca.mtimes(Lm.T, X0T), ca.DM(6, 6))
        s1 = ca.solve(K, rhs1, "csparse")
        X, Y = X0 + s1[:n, :], Y0 + s1[n:n + 6, :]
        dX = ca.mtimes(X, T)
        cross = ca.mtimes(X.T, ca.mtimes(Cm.T, dX)) + ca.mtimes([X.T, Rm, Y]) + ca.mtimes([dX.T, Lm, Y])
        F = ca.mtimes(X.T, ca.mtimes(Em, X)) + ca.mtimes(dX.T, ca.mtimes(Mm, dX)) + ca.mtimes([Y.T, Am, Y]) \
            + cross + cross.T
        F = 0.5 * (F + F.T)
        F4 = F[_ORDER4, _ORDER4]
        S4 = ca.inv(F4)
        s4 = ca.reshape(S4, 16, 1)
        self._f = ca.Function("stiffness4", [self.p], [S4])
        self._J = ca.Function("stiffness4_jac", [self.p], [s4, ca.jacobian(s4, self.p)])

    def _p(self, params):
        p = np.asarray(params, float).reshape(-1)
        if p.size != 9 * self.n_region or not np.all(np.isfinite(p)):
            raise ValueError(f"params must be {self.n_region} x 9 finite values {PARAM_NAMES}")
        return p

    def stiffness(self, params) -> np.ndarray:
        """Classical 4x4 stiffness of the equivalent plate for parameters (n_region, 9).

        Parameters
        ----------
        params : array_like
            (n_region, 9) region parameters over E (-).

        Returns
        -------
        numpy.ndarray
            (4, 4) classical stiffness.
        """
        p = self._p(params)
        try:
            S = np.array(self._f(p))
        except RuntimeError:
            S = np.full((4, 4), np.nan)
        return self._finite(S, params)

    def _finite(self, S, params):
        if not np.all(np.isfinite(S)):
            raise ValueError("equivalent plate: the warping system is singular for parameters "
                             f"{np.asarray(params).reshape(-1, 9).round(4).tolist()} ({PARAM_NAMES}, over E); "
                             "use a material with a non-singular stiffness")
        return S

    def jacobian(self, params):
        """(4x4 stiffness, d S / d p) with dS/dp shaped (4, 4, 9 n_region).

        Parameters
        ----------
        params : array_like
            (n_region, 9) region parameters over E (-).

        Returns
        -------
        tuple
            (4, 4) stiffness and its (4, 4, 9 n_region) derivative.
        """
        p = self._p(params)
        try:
            s, J = self._J(p)
        except RuntimeError:
            s, J = np.full(16, np.nan), np.full((16, p.size), np.nan)
        S = self._finite(np.array(s).reshape(4, 4, order="F"), params)
        return S, np.array(J).reshape(4, 4, -1, order="F")

    def section_mesh(self, params) -> SectionMesh:
        """The equivalent plate mesh with the region materials of ``params`` (for analyse_section).

        Parameters
        ----------
        params : array_like
            (n_region, 9) region parameters over E (-).

        Returns
        -------
        SectionMesh
            The equivalent plate's mesh.
        """
        p = self._p(params).reshape(self.n_region, 9)
        mesh = self.mesh
        Q = mesh.Q.copy()
        for r in range(self.n_region):
            Q[mesh.region == r + 1] = material_matrix(p[r], self.E)
        return SectionMesh(mesh.nodes, mesh.elements, Q, mesh.rho, mesh.region, mesh.region_names)


def builtup_stiffness(stiffeners, **kw) -> tuple[np.ndarray, object]:
    """Classical 4x4 stiffness and FE section of the built-up plate.

    Parameters
    ----------
    stiffeners : sequence of Stiffener
        The blade stiffeners.
    **kw
        Passed to :func:`stiffened_plate_mesh` (``width``, ``thickness``, ``material``, mesh sizes).

    Returns
    -------
    tuple
        (4, 4) classical stiffness and the analysed FE section.
    """
    sec = analyse_section(stiffened_plate_mesh(stiffeners, **kw))
    return classical_stiffness(sec), sec


@dataclass
class MatchResult:
    """Outcome of one stiffness-matching method.

    Parameters
    ----------
    method : int
        Matching method (1, 2 or 3).
    params : numpy.ndarray
        (n_region, 9) matched parameters over E (-).
    stiffness : numpy.ndarray
        (4, 4) classical stiffness of the matched equivalent plate.
    target : numpy.ndarray
        (4, 4) classical stiffness of the built-up plate.
    objective : float
        Final objective of the method.
    success : bool
        Whether the optimizer converged.
    message : str
        The optimizer's message.
    """

    method: int
    params: np.ndarray           # (n_region, 9), over E
    stiffness: np.ndarray        # equivalent 4x4
    target: np.ndarray           # built-up 4x4
    objective: float
    success: bool
    message: str


def _objective(method, target):
    if method == 2:                                  # Eq. 4.9, squared relative S44 error
        def f(S, dS):
            e = (S[3, 3] - target[3, 3]) / target[3, 3]
            return e * e, 2 * e * dS[3, 3] / target[3, 3]
        return f
    idx = np.ix_([1, 3], [1, 3])                     # Eq. 4.10, squared relative Frobenius norm
    ref = np.sum(target[idx] ** 2)

    def f(S, dS):
        d = S[idx] - target[idx]
        return np.sum(d * d) / ref, 2 * np.einsum("ij,ijk->k", d, dS[1:4:2][:, [1, 3]]) / ref
    return f


def match_stiffness(stiffeners, method, equivalent: EquivalentPlate | None = None, target=None, maxiter=200,
                    bounds=None, **kw) -> MatchResult:
    """Stiffness matching of Sec. 4.1.2: Method 1 (analytic guess, Eq. 4.5-4.8), Method 2 (S44,
    Eq. 4.9, Table 4.3 bounds) or Method 3 (Frobenius norm of [S22 S24; S42 S44], Eq. 4.10,
    Table 4.4 bounds), by SLSQP with exact CasADi gradients from the analytic guess clipped to the bounds.
    ``bounds=(lb, ub)`` (9 values each, over E) replaces the table's bounds.

    Parameters
    ----------
    stiffeners : sequence of Stiffener
        The blade stiffeners.
    method : {1, 2, 3}
        Matching method of Sec. 4.1.2.
    equivalent : EquivalentPlate or None, optional
        A built equivalent plate to reuse; None builds one.
    target : numpy.ndarray or None, optional
        (4, 4) target stiffness; None computes the built-up plate's.
    maxiter : int, optional
        SLSQP iteration limit.
    bounds : tuple or None, optional
        ``(lb, ub)``, 9 values each over E; None for the method's table.
    **kw
        Passed to the plate meshes (``width``, ``thickness``, ``material``, mesh sizes).

    Returns
    -------
    MatchResult
        The outcome.
    """
    if method not in (1, 2, 3):
        raise ValueError(f"method must be 1, 2 or 3, got {method}")
    stiffeners = tuple(stiffeners)
    if not stiffeners:
        raise ValueError("stiffeners: need at least one stiffener to smear")
    eq = equivalent or EquivalentPlate(stiffeners, **kw)
    if target is None:
        target, _ = builtup_stiffness(stiffeners)
    p0 = np.array([initial_guess(s) for s in stiffeners])
    if method == 1:
        S = eq.stiffness(p0)
        return MatchResult(1, p0, S, target, float(abs(S[2, 2] / target[2, 2] - 1)), True, "analytic")
    lb, ub = bounds if bounds is not None else (BOUNDS_METHOD2 if method == 2 else BOUNDS_METHOD3)
    lb, ub = np.asarray(lb, float), np.asarray(ub, float)
    if lb.shape != (9,) or ub.shape != (9,) or np.any(~(lb <= ub)):
        raise ValueError(f"bounds must be two arrays of 9 values {PARAM_NAMES} with lb <= ub (over E)")
    lb, ub = np.tile(lb, len(stiffeners)), np.tile(ub, len(stiffeners))
    x0 = np.clip(p0.ravel(), lb, ub)
    f = _objective(method, target)
    cache = {}

    def fun(x):
        key = x.tobytes()
        if key not in cache:
            cache.clear()
            cache[key] = f(*eq.jacobian(x))
        return cache[key]
    res = so.minimize(lambda x: fun(x)[0], x0, jac=lambda x: fun(x)[1], method="SLSQP",
                      bounds=list(zip(lb, ub)), options=dict(maxiter=maxiter, ftol=1e-16))
    p = res.x.reshape(len(stiffeners), 9)
    return MatchResult(method, p, eq.stiffness(p), target, float(res.fun), bool(res.success), str(res.message))


def beam_tip_displacements(section, length=PLATE_LENGTH, n_nodes=11, load_steps=2) -> dict:
    """Tip displacement (m) of a cantilever (wingmdao.beam, along body y) with this FE section,
    for each Table 4.8 load case: {case: [axial, in-plane (c = body x), out-of-plane (n = body z)]}.

    Parameters
    ----------
    section : Section
        An analysed FE section.
    length : float, optional
        Cantilever length (m).
    n_nodes : int, optional
        Beam nodes.
    load_steps : int, optional
        Newton load steps of the static solve.

    Returns
    -------
    dict
        Load case -> [axial, in-plane, out-of-plane] tip displacement (m).
    """
    bp = beam_properties_csn(section)
    K = bp["stiffness_csn"]
    comp = bp["compliance_csn"]
    r0, th0 = straight_beam(n_nodes, length)
    model = BeamModel(beam_parameters(r0, th0, EI_cc=K[0, 0], GJ=K[1, 1], EI_nn=K[2, 2], EI_cn=K[0, 2],
                                      EA=1 / comp[1], GK_c=1 / comp[0], GK_n=1 / comp[2],
                                      tension_axis=bp["tension_center_cn"], shear_center=bp["shear_center_cn"]))
    out = {}
    for case, (fa, fi, fo) in LOAD_CASES.items():
        P = np.zeros((n_nodes, 3)); P[-1] = [fi, fa, fo]            # body (x, y, z) = (c, s, n)
        st = model.solve(point_force=P, load_steps=load_steps)
        d = st["r"][-1] - r0[-1]
        out[case] = np.array([d[1], d[0], d[2]])
    return out
