"""Ply materials and the smeared (stacking-free) laminate stiffness of ply fractions.

Classical lamination theory (Jones, *Mechanics of Composite Materials*, 2nd ed., Taylor &
Francis 1999, Sec. 2.6 and 4.2-4.3): the ply reduced stiffness Q (Eq. 2.61), its rotation to
the laminate axes Qbar (Eq. 2.84), and A = sum Qbar_k t_k, D = sum Qbar_k (z_k^3 - z_{k-1}^3)/3
(Eq. 4.28). With the *smeared* laminate the plies of each angle are spread uniformly over the
thickness (many thin plies, stacking sequence ignored), so A = t sum_k f_k Qbar_k and
D = t^3/12 sum_k f_k Qbar_k, f_k the fraction of plies at angle k in [0, +45, -45, 90]. This
is the limit of [0/45/-45/90]_ns for large n and the usual preliminary-sizing model
(e.g. the ply-fraction parametrisation of the MDO Aeroelastic Benchmark's Simple Transonic
Wing). Equal +45 and -45 fractions give A16 = A26 = D16 = D26 = 0.

Conventions: x is the laminate 0 deg direction (along the stiffeners, spanwise), y across;
angles in degrees, positive from x towards y. SI units.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from wingmdao.materials import check_positive

#: Ply angles (deg) of the four ply fractions, in this order everywhere.
PLY_ANGLES = (0.0, 45.0, -45.0, 90.0)

ABD_KEYS = ("A11", "A22", "A12", "A66", "A16", "A26", "D11", "D22", "D12", "D66", "D16", "D26")

_QBAR_INDEX = {"11": (0, 0), "22": (1, 1), "12": (0, 1), "66": (2, 2), "16": (0, 2), "26": (1, 2)}


@dataclass(frozen=True)
class PlyMaterial:
    """Unidirectional ply: elastic constants (Pa), density (kg/m^3), strengths and thickness.

    ``E11``, ``E22``, ``G12`` (Pa), ``nu12`` (major Poisson's ratio), ``rho`` (kg/m^3);
    strengths as magnitudes (Pa): ``Xt``, ``Xc`` (fibre tension, compression), ``Yt``, ``Yc``
    (transverse), ``S12`` (in-plane shear); ``ply_thickness`` (m); optional allowable strains
    (magnitudes, dimensionless) ``eps1_t``, ``eps1_c``, ``eps2_t``, ``eps2_c``, ``gamma12``.
    Validity: 0 < nu12 and nu12^2 < E11/E22 (positive-definite ply stiffness).

    Parameters
    ----------
    name : str
        Material name (the key of :data:`PLY_MATERIALS`).
    E11, E22 : float
        Moduli along and across the fibres (Pa).
    G12 : float
        In-plane shear modulus (Pa).
    nu12 : float
        Major Poisson's ratio (-).
    rho : float
        Density (kg/m^3).
    Xt, Xc : float
        Fibre-direction tensile and compressive strengths, magnitudes (Pa).
    Yt, Yc : float
        Transverse tensile and compressive strengths, magnitudes (Pa).
    S12 : float
        In-plane shear strength (Pa).
    ply_thickness : float
        Cured ply thickness (m).
    eps1_t, eps1_c, eps2_t, eps2_c, gamma12 : float or None, optional
        Allowable strains, magnitudes (-); None where not given.
    """

    name: str
    E11: float
    E22: float
    G12: float
    nu12: float
    rho: float
    Xt: float
    Xc: float
    Yt: float
    Yc: float
    S12: float
    ply_thickness: float
    eps1_t: float | None = None
    eps1_c: float | None = None
    eps2_t: float | None = None
    eps2_c: float | None = None
    gamma12: float | None = None

    def __post_init__(self):
        for field, units in (("E11", "Pa"), ("E22", "Pa"), ("G12", "Pa"), ("rho", "kg/m^3"), ("Xt", "Pa"),
                             ("Xc", "Pa"), ("Yt", "Pa"), ("Yc", "Pa"), ("S12", "Pa"), ("ply_thickness", "m")):
            check_positive(getattr(self, field), f"{field} of {self.name!r}", units, "PlyMaterial")
        for field in ("eps1_t", "eps1_c", "eps2_t", "eps2_c", "gamma12"):
            if getattr(self, field) is not None:
                check_positive(getattr(self, field), f"{field} of {self.name!r}", "(strain)", "PlyMaterial")
        nu_max = math.sqrt(self.E11 / self.E22)
        if not (isinstance(self.nu12, numbers.Real) and math.isfinite(self.nu12) and 0.0 < self.nu12 < nu_max):
            raise ValueError(f"PlyMaterial: nu12 of {self.name!r} = {self.nu12!r}; allowed range "
                             f"(0, sqrt(E11/E22)) = (0, {nu_max:.4g})")

    @property
    def nu21(self) -> float:
        """Minor Poisson's ratio nu21 = nu12 E22 / E11 (reciprocity, Jones Eq. 2.67)."""
        return self.nu12 * self.E22 / self.E11


#: Ply of the Simple Transonic Wing (STW) of the MDO Aeroelastic Benchmark
#: (github.com/MDOBenchmarks/MDOAeroelasticBenchmark, docs/source/model.rst, table
#: "Composite ply properties", taken there from Brooks et al. 2020): E11 = 117.7 GPa,
#: E22 = 9.7 GPa, G12 = 4.8 GPa, nu12 = 0.35, rho = 1550 kg/m^3, T1 = 1648 MPa, C1 = 1034 MPa,
#: T2 = 64 MPa, C2 = 228 MPa, S12 = 71 MPa. The benchmark gives no ply thickness and no
#: allowable strains: the ply thickness 0.125 mm is *assumed* (a common prepreg ply; it only
#: matters for the number of plies, not for the smeared stiffness or the strength ratios), and
#: the strength checks use the strengths (Tsai-Wu), so no strain allowables are set.
STW_CFRP = PlyMaterial("stw-cfrp", E11=117.7e9, E22=9.7e9, G12=4.8e9, nu12=0.35, rho=1550.0,
                       Xt=1648e6, Xc=1034e6, Yt=64e6, Yc=228e6, S12=71e6, ply_thickness=0.125e-3)

#: Ply fractions [0, +45, -45, 90] of the STW skins and stiffeners, and of its spars and ribs
#: (docs/source/model.rst of the benchmark).
STW_SKIN_FRACTIONS = (0.4441, 0.222, 0.222, 0.1119)
STW_SPAR_FRACTIONS = (0.10, 0.35, 0.35, 0.20)

PLY_MATERIALS = {m.name: m for m in (STW_CFRP,)}


def get_ply_material(name: str) -> PlyMaterial:
    """Built-in ply material by (case-insensitive) name; see :data:`PLY_MATERIALS`.

    Parameters
    ----------
    name : str
        Ply material name, case-insensitive (e.g. ``"stw-cfrp"``).

    Returns
    -------
    PlyMaterial
        The material; ValueError listing the valid names for an unknown one.
    """
    key = str(name).strip().lower()
    if key not in PLY_MATERIALS:
        raise ValueError(f"unknown ply material {name!r}; valid: {', '.join(PLY_MATERIALS)}")
    return PLY_MATERIALS[key]


# --------------------------------------------------------------------------- ply stiffness
def q_matrix(ply: PlyMaterial) -> np.ndarray:
    """Ply reduced stiffness Q in the ply axes (1 fibre, 2 transverse), 3x3, Pa (Jones Eq. 2.61).

    Q11 = E11/(1 - nu12 nu21), Q22 = E22/(1 - nu12 nu21), Q12 = nu12 E22/(1 - nu12 nu21),
    Q66 = G12; engineering shear strain (gamma12). Plane stress.

    Parameters
    ----------
    ply : PlyMaterial
        The ply material.

    Returns
    -------
    numpy.ndarray
        (3, 3) reduced stiffness Q (Pa).
    """
    d = 1.0 - ply.nu12 * ply.nu21
    return np.array([[ply.E11 / d, ply.nu12 * ply.E22 / d, 0.0],
                     [ply.nu12 * ply.E22 / d, ply.E22 / d, 0.0],
                     [0.0, 0.0, ply.G12]])


def qbar(ply: PlyMaterial, angle_deg: float) -> np.ndarray:
    """Transformed reduced stiffness Qbar of a ply at ``angle_deg`` (deg), 3x3, Pa (numpy only).

    Jones Eq. 2.84: with m = cos(theta), n = sin(theta),
    Qbar11 = Q11 m^4 + 2(Q12 + 2Q66) m^2 n^2 + Q22 n^4,
    Qbar22 = Q11 n^4 + 2(Q12 + 2Q66) m^2 n^2 + Q22 m^4,
    Qbar12 = (Q11 + Q22 - 4Q66) m^2 n^2 + Q12 (m^4 + n^4),
    Qbar66 = (Q11 + Q22 - 2Q12 - 2Q66) m^2 n^2 + Q66 (m^4 + n^4),
    Qbar16 = (Q11 - Q12 - 2Q66) m^3 n + (Q12 - Q22 + 2Q66) m n^3,
    Qbar26 = (Q11 - Q12 - 2Q66) m n^3 + (Q12 - Q22 + 2Q66) m^3 n.

    Parameters
    ----------
    ply : PlyMaterial
        The ply material.
    angle_deg : float
        Ply angle from the laminate x axis (deg).

    Returns
    -------
    numpy.ndarray
        (3, 3) transformed reduced stiffness Qbar (Pa).
    """
    q = q_matrix(ply)
    q11, q22, q12, q66 = q[0, 0], q[1, 1], q[0, 1], q[2, 2]
    th = math.radians(angle_deg)
    m, n = math.cos(th), math.sin(th)
    m2n2 = m * m * n * n
    out = np.empty((3, 3))
    out[0, 0] = q11 * m**4 + 2.0 * (q12 + 2.0 * q66) * m2n2 + q22 * n**4
    out[1, 1] = q11 * n**4 + 2.0 * (q12 + 2.0 * q66) * m2n2 + q22 * m**4
    out[0, 1] = out[1, 0] = (q11 + q22 - 4.0 * q66) * m2n2 + q12 * (m**4 + n**4)
    out[2, 2] = (q11 + q22 - 2.0 * q12 - 2.0 * q66) * m2n2 + q66 * (m**4 + n**4)
    out[0, 2] = out[2, 0] = (q11 - q12 - 2.0 * q66) * m**3 * n + (q12 - q22 + 2.0 * q66) * m * n**3
    out[1, 2] = out[2, 1] = (q11 - q12 - 2.0 * q66) * m * n**3 + (q12 - q22 + 2.0 * q66) * m**3 * n
    return out


def _mixed_qbar(ply: PlyMaterial, fractions) -> dict:
    """sum_k f_k Qbar_k by component ('11', ...): linear in the fractions (works on SX)."""
    qbars = [qbar(ply, ang) for ang in PLY_ANGLES]
    f = [fractions[k] for k in range(4)]
    return {key: sum(float(qb[i, j]) * fk for qb, fk in zip(qbars, f)) for key, (i, j) in _QBAR_INDEX.items()}


def smeared_abd(ply: PlyMaterial, fractions, thickness) -> dict:
    """A (N/m) and D (N m) of the smeared laminate of ply ``fractions`` [0, +45, -45, 90].

    A = t sum_k f_k Qbar_k, D = t^3/12 sum_k f_k Qbar_k (module docstring; the large-n limit of
    [0/45/-45/90]_ns, Jones Eq. 4.28). B = 0 (symmetric). ``fractions`` (4 values) and
    ``thickness`` (m) may be CasADi symbols: the four Qbar are numbers combined linearly.
    Returns a dict with :data:`ABD_KEYS`.

    Parameters
    ----------
    ply : PlyMaterial
        The ply material.
    fractions : sequence of 4 floats or casadi.SX
        Fractions of 0, +45, -45 and 90 deg plies (-, summing to 1).
    thickness : float or casadi.SX
        Laminate thickness (m).

    Returns
    -------
    dict
        ``A11 A22 A12 A66 A16 A26`` (N/m) and ``D11 D22 D12 D66 D16 D26`` (N m), the keys of
        :data:`ABD_KEYS`.
    """
    mix = _mixed_qbar(ply, fractions)
    out = {f"A{k}": thickness * v for k, v in mix.items()}
    out.update({f"D{k}": thickness**3 / 12.0 * v for k, v in mix.items()})
    return out


def isotropic_abd(E, nu, thickness) -> dict:
    """A and D of an isotropic plate (same keys as :func:`smeared_abd`).

    A11 = A22 = E t/(1 - nu^2), A12 = nu A11, A66 = E t/(2(1 + nu)); D = A t^2/12, so
    D11 = D22 = E t^3/(12(1 - nu^2)) (Timoshenko & Gere, *Theory of Elastic Stability*, 2nd ed.,
    Eq. 9-3), D12 = nu D11, D66 = (1 - nu) D11 / 2, and D12 + 2 D66 = D11.

    Parameters
    ----------
    E : float or casadi.SX
        Young's modulus (Pa).
    nu : float
        Poisson's ratio (-).
    thickness : float or casadi.SX
        Plate thickness (m).

    Returns
    -------
    dict
        A (N/m) and D (N m) terms, the keys of :data:`ABD_KEYS`.
    """
    a11 = E * thickness / (1.0 - nu * nu)
    a66 = E * thickness / (2.0 * (1.0 + nu))
    t2 = thickness**2 / 12.0
    zero = 0.0 * thickness
    return {"A11": a11, "A22": a11, "A12": nu * a11, "A66": a66, "A16": zero, "A26": zero,
            "D11": a11 * t2, "D22": a11 * t2, "D12": nu * a11 * t2, "D66": a66 * t2, "D16": zero, "D26": zero}


def check_ply_fractions(fractions, source: str = "--ply-fractions") -> tuple:
    """The four ply fractions [0, +45, -45, 90] as floats, or a ValueError naming ``source``.

    Each must be finite and >= 0, and their sum within 1e-6 of 1.

    Parameters
    ----------
    fractions : sequence of 4 floats
        Fractions of 0, +45, -45 and 90 deg plies (-).
    source : str, optional
        The flag or file key named in the error message.

    Returns
    -------
    tuple of 4 floats
        The checked fractions.
    """
    try:
        values = tuple(float(f) for f in fractions)
    except (TypeError, ValueError):
        raise ValueError(f"{source} = {fractions!r}; expected 4 numbers (fractions of 0, +45, -45 and 90 deg "
                         "plies), each in [0, 1], summing to 1") from None
    shown = " ".join(f"{v:g}" for v in values)
    if len(values) != 4:
        raise ValueError(f"{source} = {shown}: {len(values)} values; expected 4 (fractions of 0, +45, -45 and "
                         "90 deg plies), each in [0, 1], summing to 1")
    bad = [v for v in values if not (math.isfinite(v) and 0.0 <= v <= 1.0)]
    if bad:
        raise ValueError(f"{source} = {shown}: {bad[0]:g} is outside the allowed range [0, 1]; the 4 fractions "
                         "must sum to 1")
    total = sum(values)
    if abs(total - 1.0) > 1e-6:
        raise ValueError(f"{source} = {shown}: the fractions sum to {total:.9g}; allowed sum 1 (within 1e-6)")
    return values


def laminate_moduli(ply: PlyMaterial, fractions) -> dict:
    """Membrane engineering constants of the smeared laminate: Ex, Ey, Gxy (Pa), nu_xy.

    From a = (A/t)^-1, the laminate membrane compliance (the "apparent" laminate engineering
    constants of e.g. Kassapoglou, *Design and Analysis of Composite Structures*, 2nd ed., Ch. 3):
    Ex = 1/a11, Ey = 1/a22, Gxy = 1/a66, nu_xy = -a12/a11. Written for A16 = A26
    = 0 (equal +45 and -45 fractions, as with the smeared laminate), where the inverse is in
    closed form (with unequal +-45 fractions A16, A26 are ignored here): Ex = (A11 A22 - A12^2)/(t A22), Ey = (A11 A22 - A12^2)/(t A11), Gxy = A66/t,
    nu_xy = A12/A22. Works on CasADi symbols.

    Parameters
    ----------
    ply : PlyMaterial
        The ply material.
    fractions : sequence of 4 floats or casadi.SX
        Fractions of 0, +45, -45 and 90 deg plies (-).

    Returns
    -------
    dict
        ``Ex``, ``Ey``, ``Gxy`` (Pa) and ``nu_xy`` (-).
    """
    q = _mixed_qbar(ply, fractions)
    det = q["11"] * q["22"] - q["12"] ** 2
    return {"Ex": det / q["22"], "Ey": det / q["11"], "Gxy": q["66"], "nu_xy": q["12"] / q["22"]}
