"""Material stiffness in Voigt order [11, 22, 33, 23, 13, 12] (engineering shear strains).

Section axes: x1 along the beam, x2 chordwise (c), x3 normal (n). A ply's material axes are
a1 = fibre, a2 = in-plane transverse, a3 = wall normal.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Material:
    """A material: 6x6 stiffness C in its own axes (Pa), density rho (kg/m^3), name.

    Parameters
    ----------
    C : numpy.ndarray
        (6, 6) stiffness in the material axes, Voigt [11, 22, 33, 23, 13, 12] (Pa).
    rho : float
        Density (kg/m^3).
    name : str, optional
        Material name.
    E_ref, G_ref : float, optional
        Reference moduli for normalised outputs (Pa).
    """

    C: np.ndarray
    rho: float
    name: str = ""
    E_ref: float = 0.0
    G_ref: float = 0.0


def _positive(name, value):
    value = float(value)
    if not np.isfinite(value) or value <= 0.0:
        raise ValueError(f"material {name} must be finite and > 0, got {value}")
    return value


def isotropic(E, nu, rho, name="") -> Material:
    """Isotropic material from Young's modulus E (Pa), Poisson ratio nu (-1 < nu < 0.5), density rho.

    Parameters
    ----------
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio (-1 < nu < 0.5).
    rho : float
        Density (kg/m^3).
    name : str, optional
        Material name.

    Returns
    -------
    Material
        The material.
    """
    E = _positive(f"{name} E (Pa)", E)
    _positive(f"{name} rho (kg/m^3)", rho)
    if not -1.0 < nu < 0.5:
        raise ValueError(f"material {name} nu must lie in (-1, 0.5), got {nu}")
    G = E / (2 * (1 + nu))
    return orthotropic(E, E, E, G, G, G, nu, nu, nu, rho, name, E_ref=E, G_ref=G)


def orthotropic(E1, E2, E3, G12, G13, G23, nu12, nu13, nu23, rho, name="", E_ref=None, G_ref=None) -> Material:
    """Orthotropic material (engineering constants in material axes, Pa) -> stiffness by inverting the compliance.

    Parameters
    ----------
    E1, E2, E3 : float
        Moduli along the material axes (Pa).
    G12, G13, G23 : float
        Shear moduli (Pa).
    nu12, nu13, nu23 : float
        Poisson's ratios (-).
    rho : float
        Density (kg/m^3).
    name : str, optional
        Material name.
    E_ref, G_ref : float or None, optional
        Reference moduli (Pa); None for E1 and G12.

    Returns
    -------
    Material
        The material.
    """
    for k, v in dict(E1=E1, E2=E2, E3=E3, G12=G12, G13=G13, G23=G23, rho=rho).items():
        _positive(f"{name} {k}", v)
    S = np.zeros((6, 6))
    S[0, 0], S[1, 1], S[2, 2] = 1 / E1, 1 / E2, 1 / E3
    S[0, 1] = S[1, 0] = -nu12 / E1
    S[0, 2] = S[2, 0] = -nu13 / E1
    S[1, 2] = S[2, 1] = -nu23 / E2
    S[3, 3], S[4, 4], S[5, 5] = 1 / G23, 1 / G13, 1 / G12
    if np.any(np.linalg.eigvalsh(S) <= 0):
        raise ValueError(f"material {name}: Poisson ratios give a compliance that is not positive definite")
    return Material(np.linalg.inv(S), float(rho), name, E1 if E_ref is None else E_ref,
                    G12 if G_ref is None else G_ref)


def anisotropic(C, rho, name="") -> Material:
    """General anisotropic material from its symmetric positive-definite 6x6 stiffness (Pa).

    Parameters
    ----------
    C : array_like
        (6, 6) symmetric positive-definite stiffness (Pa).
    rho : float
        Density (kg/m^3).
    name : str, optional
        Material name.

    Returns
    -------
    Material
        The material.
    """
    C = np.asarray(C, float)
    if C.shape != (6, 6) or not np.allclose(C, C.T, rtol=1e-10, atol=0) or np.any(np.linalg.eigvalsh(C) <= 0):
        raise ValueError(f"material {name}: C must be a symmetric positive-definite 6x6 matrix (Pa)")
    _positive(f"{name} rho (kg/m^3)", rho)
    return Material(C, float(rho), name, C[0, 0], C[5, 5])


def bond_matrix(R):
    """Voigt stress transformation for axes rotation R (rows: new axes in old coordinates), order [11,22,33,23,13,12].

    Parameters
    ----------
    R : array_like
        (3, 3) rotation, rows the new axes in old coordinates.

    Returns
    -------
    numpy.ndarray
        (6, 6) Voigt stress transformation.
    """
    R = np.asarray(R)
    idx = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]
    K = np.zeros(R.shape[:-2] + (6, 6))
    for I, (i, j) in enumerate(idx):
        for J, (k, l) in enumerate(idx):
            if J < 3:
                K[..., I, J] = R[..., i, k] * R[..., j, l]
            else:
                K[..., I, J] = R[..., i, k] * R[..., j, l] + R[..., i, l] * R[..., j, k]
    return K


def ply_stiffness(material: Material, angle_rad, wall_normal):
    """Stiffness of a ply in section axes (Voigt [11,22,33,23,13,12]).

    The fibre lies at ``angle_rad`` from the beam axis e1, rotated about the outward wall normal
    ``wall_normal`` (unit, in the x2-x3 plane, given as (n2, n3); arrays allowed, shape (..., 2)).

    Parameters
    ----------
    material : Material
        Ply material in its own axes.
    angle_rad : float or array_like
        Fibre angle from the beam axis (rad).
    wall_normal : array_like
        (..., 2) outward unit wall normal (n2, n3).

    Returns
    -------
    numpy.ndarray
        (..., 6, 6) stiffness in section axes (Pa).
    """
    nrm = np.asarray(wall_normal, float)
    ang = np.asarray(angle_rad, float)
    shape = np.broadcast_shapes(nrm.shape[:-1], ang.shape)
    nrm = np.broadcast_to(nrm, shape + (2,))
    ang = np.broadcast_to(ang, shape)
    e1 = np.zeros(shape + (3,)); e1[..., 0] = 1.0
    n3 = np.zeros(shape + (3,)); n3[..., 1:] = nrm
    t = np.cross(n3, e1)                                  # in-plane wall tangent = n x e1
    a1 = np.cos(ang)[..., None] * e1 + np.sin(ang)[..., None] * t
    a2 = np.cross(n3, a1)
    R = np.stack([a1, a2, n3], axis=-2)                   # rows: material axes in section coordinates
    # sigma_section = T^T-type: C_sec = Kb^T... use strain/stress Bond matrices for section <- material
    Ks = bond_matrix(np.swapaxes(R, -1, -2))              # stress transform material -> section
    return Ks @ material.C @ np.swapaxes(Ks, -1, -2)
