"""Structural mass of the beam: the sizing objective (dissertation App. F.1).

    f_m = sum_i m_i,   m_i = rho V_i,   V_i = s_i/3 (A_i + A_{i+1} + sqrt(A_i A_{i+1}))

V_i is the volume of a frustum between the end sections A_i, A_{i+1} a distance s_i apart:
exact for similar sections scaled linearly along the element (a tapered solid square or a
box whose every wall scales with the same factor). Non-structural mass per length mu
(fuel, systems, ribs, ...) is added by the trapezoid rule, sum_i s_i (mu_i + mu_{i+1}) / 2.
"""

from __future__ import annotations

import numbers

import numpy as np
import openmdao.api as om

from wingmdao import DISSERTATION
from wingmdao.errors import InputRangeError
from wingmdao.materials import Material


def element_lengths(node_positions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Element lengths ``s_i = |r_{i+1} - r_i|`` and unit vectors e_i along each element.

    Parameters
    ----------
    node_positions : numpy.ndarray
        (n, 3) node positions (m).

    Returns
    -------
    tuple
        Lengths (n - 1,) (m) and unit vectors (n - 1, 3).
    """
    d = np.diff(np.asarray(node_positions, dtype=float), axis=0)
    s = np.linalg.norm(d, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):  # zero lengths are rejected by callers
        return s, d / s[:, None]


def frustum_volumes(area: np.ndarray, length: np.ndarray) -> np.ndarray:
    """Element volumes V_i = s_i/3 (A_i + A_{i+1} + sqrt(A_i A_{i+1})) (App. F.1).

    Parameters
    ----------
    area : numpy.ndarray
        (n,) section areas (m^2).
    length : numpy.ndarray
        (n - 1,) element lengths (m).

    Returns
    -------
    numpy.ndarray
        (n - 1,) volumes (m^3).
    """
    a0, a1 = area[:-1], area[1:]
    return length / 3.0 * (a0 + a1 + np.sqrt(a0 * a1))


def beam_mass(area, node_positions, density, nonstructural_mass_per_length=0.0) -> float:
    """Structural mass rho sum_i V_i (App. F.1, frustum volumes) plus the trapezoid-rule
    non-structural mass sum_i s_i (mu_i + mu_{i+1}) / 2, kg; no input checks (see StructuralMass).

    Parameters
    ----------
    area : array_like
        (n,) section areas (m^2).
    node_positions : array_like
        (n, 3) node positions (m).
    density : float
        Material density (kg/m^3).
    nonstructural_mass_per_length : float or array_like, optional
        Non-structural mass per length (kg/m), scalar or (n,).

    Returns
    -------
    float
        Mass (kg).
    """
    area = np.asarray(area, dtype=float)
    s, _ = element_lengths(node_positions)
    mu = np.broadcast_to(np.asarray(nonstructural_mass_per_length, dtype=float), area.shape)
    return float(density * np.sum(frustum_volumes(area, s)) + np.sum(0.5 * s * (mu[:-1] + mu[1:])))


class StructuralMass(om.ExplicitComponent):
    """Beam structural mass (App. F.1 objective) plus non-structural mass per length.

    Inputs ``A`` (n,) m^2, ``node_positions`` (n, 3) m (undeformed beam axis, body axes),
    ``nonstructural_mass_per_length`` (n,) kg/m (default 0). Output ``mass`` (kg).
    Option ``density`` (kg/m^3) or ``material`` (a ``wingmdao.materials.Material``);
    ``material`` wins when given.
    """

    def initialize(self):
        self.cite = DISSERTATION  # OpenMDAO lists it in its citations report
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes")
        self.options.declare(
            "density", default=None, allow_none=True, types=numbers.Real, desc="material density (kg/m^3)"
        )
        self.options.declare(
            "material", default=None, allow_none=True, types=Material,
            desc="optional wingmdao.materials.Material (its rho, kg/m^3, overrides density)",
        )

    @property
    def density(self) -> float:
        mat = self.options["material"]
        if mat is None and self.options["density"] is None:
            raise ValueError("StructuralMass: give the option density (kg/m^3) or material")
        rho = float(mat.rho) if mat is not None else float(self.options["density"])
        if not (np.isfinite(rho) and rho > 0.0):
            raise ValueError(f"StructuralMass: density = {rho} kg/m^3; allowed range (0, inf)")
        return rho

    def setup(self):
        n = self.options["num_nodes"]
        _ = self.density  # validate early
        self.add_input("A", val=1e-3, shape=(n,), units="m**2", desc="section material area at each node")
        self.add_input(
            "node_positions", val=0.0, shape=(n, 3), units="m",
            desc="undeformed beam-axis node positions, body axes",
        )
        self.add_input(
            "nonstructural_mass_per_length", val=0.0, shape=(n,), units="kg/m",
            desc="non-structural mass per unit beam length at each node",
        )
        self.add_output("mass", val=0.0, units="kg", desc="structural + non-structural beam mass")
        self.declare_partials("mass", "A", rows=np.zeros(n, int), cols=np.arange(n))
        self.declare_partials("mass", "node_positions", rows=np.zeros(3 * n, int), cols=np.arange(3 * n))
        self.declare_partials(
            "mass", "nonstructural_mass_per_length", rows=np.zeros(n, int), cols=np.arange(n)
        )

    def _checked(self, inputs):
        area = np.asarray(inputs["A"], dtype=float)
        pos = np.asarray(inputs["node_positions"], dtype=float)
        mu = np.asarray(inputs["nonstructural_mass_per_length"], dtype=float)
        for name, arr in (("A", area), ("node_positions", pos), ("nonstructural_mass_per_length", mu)):
            bad = np.flatnonzero(~np.isfinite(arr.ravel()))
            if bad.size:
                raise InputRangeError(f"StructuralMass: {name} is not finite at flat index {bad[0]}")
        bad = np.flatnonzero(area <= 0.0)
        if bad.size:
            i = bad[0]
            raise InputRangeError(
                f"StructuralMass: A[{i}] = {area[i]:.6g} m^2 at node {i}; allowed range (0, inf) m^2"
            )
        bad = np.flatnonzero(mu < 0.0)
        if bad.size:
            i = bad[0]
            raise InputRangeError(
                f"StructuralMass: nonstructural_mass_per_length[{i}] = {mu[i]:.6g} kg/m at node {i}; "
                "allowed range [0, inf) kg/m"
            )
        s, e = element_lengths(pos)
        bad = np.flatnonzero(s <= 0.0)
        if bad.size:
            i = bad[0]
            raise InputRangeError(
                f"StructuralMass: node_positions[{i}] and node_positions[{i + 1}] coincide; "
                "element length must be in (0, inf) m"
            )
        return area, mu, s, e

    def compute(self, inputs, outputs):
        area, mu, _, _ = self._checked(inputs)
        outputs["mass"] = beam_mass(area, inputs["node_positions"], self.density, mu)

    def compute_partials(self, inputs, partials):
        area, mu, s, e = self._checked(inputs)
        rho = self.density
        a0, a1 = area[:-1], area[1:]
        root = np.sqrt(a0 * a1)
        # d/dA of each element's volume (A > 0 is enforced, so sqrt is differentiable)
        dA = np.zeros_like(area)
        dA[:-1] += s / 3.0 * (1.0 + 0.5 * root / a0)
        dA[1:] += s / 3.0 * (1.0 + 0.5 * root / a1)
        partials["mass", "A"] = rho * dA
        # mass per unit element length; ds_i/dr_{i+1} = e_i, ds_i/dr_i = -e_i
        per_length = rho * (a0 + a1 + root) / 3.0 + 0.5 * (mu[:-1] + mu[1:])
        dr = np.zeros((area.size, 3))
        dr[:-1] -= per_length[:, None] * e
        dr[1:] += per_length[:, None] * e
        partials["mass", "node_positions"] = dr.ravel()
        dmu = np.zeros_like(mu)
        dmu[:-1] += 0.5 * s
        dmu[1:] += 0.5 * s
        partials["mass", "nonstructural_mass_per_length"] = dmu
