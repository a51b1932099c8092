"""Isotropic materials (SI: Pa, kg/m^3).

``Material(name, E, rho, sigma_y, G=None, nu=None)``: give at most one of the shear modulus
``G`` and Poisson's ratio ``nu``; the other follows from G = E / (2 (1 + nu)) (isotropic
elasticity). With neither, nu = 0.33 is assumed.

Built-in materials (``MATERIALS``, ``get_material``):

* ``aluminium``: the dissertation's aluminium (Table 4.23: E = 70 GPa, rho = 2700 kg/m^3,
  sigma_y = 276 MPa; nu = 0.33).
* ``al2024-t3``, ``al7075-t6``, ``ti-6al-4v``, ``steel-4130``: typical room-temperature
  handbook values (ASM Aerospace Specification Metals / MatWeb data sheets, which reproduce
  MIL-HDBK-5 / MMPDS typical values): Al 2024-T3 E = 73.1 GPa, nu = 0.33, rho = 2780 kg/m^3,
  tensile yield 345 MPa; Al 7075-T6 E = 71.7 GPa, nu = 0.33, rho = 2810 kg/m^3, yield 503 MPa;
  Ti-6Al-4V (annealed) E = 113.8 GPa, nu = 0.342, rho = 4430 kg/m^3, yield 880 MPa;
  AISI 4130 steel (normalised) E = 205 GPa, nu = 0.29, rho = 7850 kg/m^3, yield 435 MPa.
  These are typical values, not statistically based design allowables.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

DEFAULT_NU = 0.33


def check_positive(value, name: str, units: str, owner: str = "Material") -> None:
    """ValueError naming ``owner``, the property, its value and the allowed range unless ``value``
    is a finite real number > 0 (the material data classes' one check).

    Parameters
    ----------
    value : object
        The value to check.
    name : str
        Property name used in the message.
    units : str
        Units of the property, for the message.
    owner : str, optional
        The material or data class named in the message.
    """
    if not isinstance(value, numbers.Real) or isinstance(value, bool):
        raise ValueError(f"{owner}: {name} must be a number in {units}, got {value!r}")
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{owner}: {name} = {value} {units}; allowed range (0, inf) {units}")


@dataclass(frozen=True)
class Material:
    """Linear elastic isotropic material: E, G in Pa, rho in kg/m^3, sigma_y in Pa.

    Parameters
    ----------
    name : str
        Material name.
    E : float
        Young's modulus (Pa).
    rho : float
        Density (kg/m^3).
    sigma_y : float
        Yield stress (Pa).
    G : float or None, optional
        Shear modulus (Pa); give G or ``nu``, not both. None derives it, G = E / (2 (1 + nu)).
    nu : float or None, optional
        Poisson's ratio (-, in (-1, 0.5)); None derives it from ``G``, or takes
        :data:`DEFAULT_NU` when neither is given.
    """

    name: str
    E: float
    rho: float
    sigma_y: float
    G: float | None = None
    nu: float | None = None

    def __post_init__(self):
        check_positive(self.E, "E (Young's modulus)", "Pa")
        check_positive(self.rho, "rho (density)", "kg/m^3")
        check_positive(self.sigma_y, "sigma_y (yield stress)", "Pa")
        if self.G is not None and self.nu is not None:
            raise ValueError(f"Material {self.name!r}: give only one of G and nu (the other is derived "
                             "from G = E / (2 (1 + nu)))")
        if self.G is not None:
            check_positive(self.G, "G (shear modulus)", "Pa")
            object.__setattr__(self, "nu", self.E / (2.0 * self.G) - 1.0)
            if not (-1.0 < self.nu < 0.5):
                raise ValueError(f"Material {self.name!r}: G = {self.G} Pa gives nu = E/(2G) - 1 = {self.nu:.4g}; "
                                 f"allowed G range ({self.E / 3.0:.6g}, inf) Pa, i.e. nu in (-1, 0.5)")
        else:
            nu = DEFAULT_NU if self.nu is None else self.nu
            if not isinstance(nu, numbers.Real) or not (math.isfinite(nu) and -1.0 < nu < 0.5):
                raise ValueError(f"Material {self.name!r}: nu = {nu}; allowed range (-1, 0.5)")
            object.__setattr__(self, "nu", float(nu))
            object.__setattr__(self, "G", self.E / (2.0 * (1.0 + nu)))


ALUMINIUM = Material("aluminium", E=70e9, rho=2700.0, sigma_y=276e6, nu=0.33)
AL2024_T3 = Material("al2024-t3", E=73.1e9, rho=2780.0, sigma_y=345e6, nu=0.33)
AL7075_T6 = Material("al7075-t6", E=71.7e9, rho=2810.0, sigma_y=503e6, nu=0.33)
TI_6AL_4V = Material("ti-6al-4v", E=113.8e9, rho=4430.0, sigma_y=880e6, nu=0.342)
STEEL_4130 = Material("steel-4130", E=205e9, rho=7850.0, sigma_y=435e6, nu=0.29)

#: Built-in materials by canonical (lower-case) name.
MATERIALS = {m.name: m for m in (ALUMINIUM, AL2024_T3, AL7075_T6, TI_6AL_4V, STEEL_4130)}

_ALIASES = {"aluminum": "aluminium", "al": "aluminium", "2024-t3": "al2024-t3", "7075-t6": "al7075-t6",
            "ti6al4v": "ti-6al-4v", "4130": "steel-4130"}


def get_material(name: str) -> Material:
    """Built-in material by name (case-insensitive; 'aluminium' and 'aluminum' are the same).

    Parameters
    ----------
    name : str
        Material name, case-insensitive.

    Returns
    -------
    Material
        The material; ValueError listing the valid names for an unknown one.
    """
    key = str(name).strip().lower()
    key = _ALIASES.get(key, key)
    if key not in MATERIALS:
        raise ValueError(f"unknown material {name!r}; valid: {', '.join(MATERIALS)} (alias: aluminum)")
    return MATERIALS[key]
