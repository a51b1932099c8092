"""International Standard Atmosphere (ISO 2533 / ICAO), troposphere and lower stratosphere.

Valid from 0 to 20 000 m geopotential altitude: a linear temperature lapse of -6.5 K/km up
to the tropopause at 11 000 m, isothermal (216.65 K) above. SI throughout; the only
non-SI entry point is :func:`altitude_ft_to_m`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from wingmdao.units import FT, G0, KNOT, LB  # noqa: F401 - the unit constants' home (re-exported)

R_AIR = 287.05287  # specific gas constant of dry air, J/(kg K)
GAMMA_AIR = 1.4
T0 = 288.15  # sea-level temperature, K
P0 = 101325.0  # sea-level pressure, Pa
RHO0 = P0 / (R_AIR * T0)  # sea-level density, 1.225 kg/m^3
LAPSE = 0.0065  # troposphere lapse rate, K/m
H_TROPOPAUSE = 11000.0  # m
T_TROPOPAUSE = T0 - LAPSE * H_TROPOPAUSE  # 216.65 K
P_TROPOPAUSE = P0 * (T_TROPOPAUSE / T0) ** (G0 / (R_AIR * LAPSE))  # 22632 Pa
H_MAX = 20000.0  # m, top of the modelled layers


class IsaState(NamedTuple):
    """ISA state at an altitude (the fields of :func:`isa`).

    Parameters
    ----------
    temperature : numpy.ndarray
        Temperature (K).
    pressure : numpy.ndarray
        Static pressure (Pa).
    density : numpy.ndarray
        Density (kg/m^3).
    speed_of_sound : numpy.ndarray
        Speed of sound (m/s).
    """

    temperature: np.ndarray  # K
    pressure: np.ndarray  # Pa
    density: np.ndarray  # kg/m^3
    speed_of_sound: np.ndarray  # m/s


def altitude_ft_to_m(altitude_ft):
    """Feet to metres (edge conversion).

    Parameters
    ----------
    altitude_ft : float or array_like
        Altitude (ft).

    Returns
    -------
    float or numpy.ndarray
        Altitude (m).
    """
    return np.asarray(altitude_ft, dtype=float) * FT


def _checked_altitude(altitude_m) -> np.ndarray:
    h = np.asarray(altitude_m, dtype=float)
    bad = ~np.isfinite(h) | (h < 0.0) | (h > H_MAX)
    if np.any(bad):
        idx = int(np.flatnonzero(bad.ravel())[0])
        raise ValueError(
            f"altitude_m = {h.ravel()[idx]} at index {idx}; ISA model valid in [0, {H_MAX:.0f}] m"
        )
    return h


def isa(altitude_m) -> IsaState:
    """ISA temperature, pressure, density and speed of sound at geopotential altitude (m).

    Parameters
    ----------
    altitude_m : float or array_like
        Geopotential altitude (m).

    Returns
    -------
    IsaState
        The state.
    """
    h = _checked_altitude(altitude_m)
    tropo = h <= H_TROPOPAUSE
    temperature = np.where(tropo, T0 - LAPSE * h, T_TROPOPAUSE)
    p_tropo = P0 * (np.minimum(temperature, T0) / T0) ** (G0 / (R_AIR * LAPSE))
    p_strato = P_TROPOPAUSE * np.exp(-G0 * (h - H_TROPOPAUSE) / (R_AIR * T_TROPOPAUSE))
    pressure = np.where(tropo, p_tropo, p_strato)
    density = pressure / (R_AIR * temperature)
    a = np.sqrt(GAMMA_AIR * R_AIR * temperature)
    return IsaState(temperature, pressure, density, a)


def density(altitude_m):
    """ISA density (kg/m^3).

    Parameters
    ----------
    altitude_m : float or array_like
        Geopotential altitude (m).

    Returns
    -------
    float or numpy.ndarray
        Density (kg/m^3).
    """
    return isa(altitude_m).density


def temperature(altitude_m):
    """ISA temperature (K).

    Parameters
    ----------
    altitude_m : float or array_like
        Geopotential altitude (m).

    Returns
    -------
    float or numpy.ndarray
        Temperature (K).
    """
    return isa(altitude_m).temperature


def pressure(altitude_m):
    """ISA static pressure (Pa).

    Parameters
    ----------
    altitude_m : float or array_like
        Geopotential altitude (m).

    Returns
    -------
    float or numpy.ndarray
        Static pressure (Pa).
    """
    return isa(altitude_m).pressure


def speed_of_sound(altitude_m):
    """ISA speed of sound (m/s).

    Parameters
    ----------
    altitude_m : float or array_like
        Geopotential altitude (m).

    Returns
    -------
    float or numpy.ndarray
        Speed of sound (m/s).
    """
    return isa(altitude_m).speed_of_sound


def eas_to_tas(v_eas, altitude_m):
    """True airspeed from equivalent airspeed: V_T = V_E sqrt(rho0 / rho) (same dynamic pressure).

    Parameters
    ----------
    v_eas : float or array_like
        Equivalent airspeed (m/s).
    altitude_m : float or array_like
        Geopotential altitude (m).

    Returns
    -------
    float or numpy.ndarray
        True airspeed (m/s).
    """
    return np.asarray(v_eas, dtype=float) * np.sqrt(RHO0 / density(altitude_m))


def tas_to_eas(v_tas, altitude_m):
    """Equivalent airspeed from true airspeed: V_E = V_T sqrt(rho / rho0).

    Parameters
    ----------
    v_tas : float or array_like
        True airspeed (m/s).
    altitude_m : float or array_like
        Geopotential altitude (m).

    Returns
    -------
    float or numpy.ndarray
        Equivalent airspeed (m/s).
    """
    return np.asarray(v_tas, dtype=float) * np.sqrt(density(altitude_m) / RHO0)


def mach_to_tas(mach, altitude_m):
    """True airspeed (m/s) for a Mach number at an ISA altitude.

    Parameters
    ----------
    mach : float or array_like
        Mach number (-).
    altitude_m : float or array_like
        Geopotential altitude (m).

    Returns
    -------
    float or numpy.ndarray
        True airspeed (m/s).
    """
    return np.asarray(mach, dtype=float) * speed_of_sound(altitude_m)
