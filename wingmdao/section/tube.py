"""Thin-walled circular tube: section properties and stress recovery (numpy and CasADi).

A fuselage shell idealised as a circular tube of radius R (to the wall's midline) and smeared wall
thickness t (skin and stringers), thin-walled (t << R):

    A = 2 pi R t,   I_cc = I_nn = pi R^3 t,   J = 2 pi R^3 t,
    EA = E A,   EI = E I,   GJ = G J,   shear stiffness GK = 1e6 EA (shear-rigid, as
    :func:`wingmdao.beam.static.beam_parameters`).

A member on the plane of symmetry of a half model carries the ``fraction`` (1/2) of the whole
tube's stiffness, area and mass, and the internal loads of that fraction: the stresses are those
of the whole tube under the loads divided by ``fraction``.

Stress recovery at ``TUBE_POINTS`` points of the wall's midline, (c, n) = R (cos phi, sin phi)
in the section's csn frame (c and n across, s along the axis), from the internal force
F = [F_c, F_s, F_n] and moment M = [M_c, M_s, M_n] about the tube's centre (the outboard part on
the inboard part, docs/conventions.md), with the sign convention of the box's and the solid's
(eps = eps0 + kappa_n c - kappa_c n):

    sigma = F_s / A - M_c n / I + M_n c / I,
    tau   = M_s / (2 pi R^2 t) - F_n cos(phi) / (pi R t),

tau along the direction s x r of a positive torque (the shear flow of the transverse force F_n of
a thin circular tube is F_n cos(phi) / (pi R): zero at the top and bottom, largest at the sides),
and the von Mises stress of plane stress sqrt(sigma^2 + 3 tau^2), the box's ``vm`` measure
(:func:`wingmdao.stress.box_stress.box_stresses`). The lateral shear F_c is left out: on a half
model's member held on the plane of symmetry at every node it is a round-off quantity of the
symmetry conditions (docs/stick-model.md, Sparsity and the LU order), and in symmetric flight it
is zero.
"""

from __future__ import annotations

import numpy as np

from wingmdao.section.box import sqrt
from wingmdao.stress.box_stress import VM_TINY

#: recovery points: angles phi (rad) from the c axis towards n
TUBE_POINTS = tuple(np.arange(8) * np.pi / 4)
#: shear stiffness over axial stiffness (shear-rigid, as beam_parameters' default)
SHEAR_RIGID = 1e6


def tube_properties(radius, thickness, material, fraction=1.0, nonstructural_mass_per_length=0.0) -> dict:
    """Beam data of a thin-walled circular tube (module docstring), numpy or CasADi.

    Parameters
    ----------
    radius : float
        Midline radius R (m).
    thickness : float, array_like or casadi.SX
        Wall thickness t (m).
    material : wingmdao.materials.Material
        Wall material (E, G, rho).
    fraction : float
        Share of the whole tube the beam carries (1/2 on a half model's plane of symmetry).
    nonstructural_mass_per_length : float, array_like or casadi.SX
        Nonstructural mass per length of the beam (kg/m, the beam's share).

    Returns
    -------
    dict
        ``A`` (m^2), ``EA`` (N), ``EI`` and ``GJ`` (N m^2), ``mass_per_length`` (kg/m), all the
        beam's share; ``stiffness_csn`` (3 x 3 diagonal, EI, GJ, EI) and ``compliance_csn``
        (1 / GK, 1 / EA, 1 / GK) as lists of entries (scalars or arrays).
    """
    R, t, f = float(radius), thickness, float(fraction)
    area = f * 2.0 * np.pi * R * t
    ea = material.E * area
    ei = material.E * f * np.pi * R**3 * t
    gj = material.G * f * 2.0 * np.pi * R**3 * t
    return {"A": area, "EA": ea, "EI": ei, "GJ": gj,
            "mass_per_length": material.rho * area + nonstructural_mass_per_length,
            "stiffness_csn": [[ei, 0.0, 0.0], [0.0, gj, 0.0], [0.0, 0.0, ei]],
            "compliance_csn": [1.0 / (SHEAR_RIGID * ea), 1.0 / ea, 1.0 / (SHEAR_RIGID * ea)]}


def tube_stresses(force, moment, radius, thickness, fraction=1.0) -> dict:
    """Axial, shear and von Mises stresses (Pa) at the :data:`TUBE_POINTS` of a thin tube
    (module docstring), numpy or CasADi.

    Parameters
    ----------
    force : sequence of 3
        Internal force [F_c, F_s, F_n] (N) of the beam (its share), csn.
    moment : sequence of 3
        Internal moment [M_c, M_s, M_n] (N m) about the tube's centre, csn.
    radius : float
        Midline radius R (m).
    thickness : float, array_like or casadi.SX
        Wall thickness t (m).
    fraction : float
        Share of the whole tube the beam carries; the loads are divided by it.

    Returns
    -------
    dict
        ``sigma``, ``tau`` and ``sigma_vm``: lists over the points (Pa).
    """
    R, t, f = float(radius), thickness, float(fraction)
    area, inertia = 2.0 * np.pi * R * t, np.pi * R**3 * t
    sigma, tau, vm = [], [], []
    for phi in TUBE_POINTS:
        c, n = R * np.cos(phi), R * np.sin(phi)
        s = (force[1] / area - moment[0] * n / inertia + moment[2] * c / inertia) / f
        q = (moment[1] / (2.0 * np.pi * R**2 * t) - force[2] * np.cos(phi) / (np.pi * R * t)) / f
        sigma.append(s)
        tau.append(q)
        vm.append(sqrt(s**2 + 3.0 * q**2 + VM_TINY))
    return {"sigma": sigma, "tau": tau, "sigma_vm": vm}


def validate_tube(radius, thickness, *, source: str = "") -> None:
    """ValueError naming the input, station and allowed range when the radius or a wall thickness is
    not finite and positive, or a wall is not thin (t >= R / 10).

    Parameters
    ----------
    radius : float
        Midline radius (m).
    thickness : array_like
        Wall thickness per station (m).
    source : str
        Prefix of the message (the caller's name).
    """
    R = float(radius)
    if not (np.isfinite(R) and R > 0):
        raise ValueError(f"{source}radius = {radius} m; allowed range (0, inf) m")
    t = np.atleast_1d(np.asarray(thickness, dtype=float))
    bad = np.flatnonzero(~(np.isfinite(t) & (t > 0) & (t < 0.1 * R)))
    if bad.size:
        k = int(bad[0])
        raise ValueError(f"{source}t_wall[{k}] = {t[k]} m at station {k}; allowed range (0, {0.1 * R:g}) m "
                         "(a thin wall, t < R / 10)")
