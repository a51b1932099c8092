"""14 CFR 25.341(a) discrete "1 - cos" gust and its strip-theory load history on the beam.

Dissertation Sec. 5.2.1, Eq. 5.1-5.2:

    U(s) = U_ds/2 (1 - cos(pi s / H)),  0 <= s <= 2H  (0 outside)          (5.1)
    U_ds = U_ref F_g (H / 350 ft)^(1/6)                                     (5.2)

with U_ref from the 25.341(a)(5) altitude table and F_g the flight-profile alleviation
factor of 25.341(a)(6). The regulation is written in feet and ft/s EAS: functions whose
argument names end in ``_ft`` take feet; everything returned is SI (m, m/s) unless the
name says otherwise. The incremental lift per unit span of a chordwise strip is

    dL' = q c C_l_alpha U / V = 1/2 rho V c C_l_alpha U        (quasi-steady)

optionally lagged by Kussner's function (Sears' approximation) through a Duhamel integral.
See ``docs/loads.md``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from wingmdao.loads.atmosphere import FT, RHO0, density, speed_of_sound
from wingmdao.loads.files import LoadHistory, validate_load_history
from wingmdao.loads.maneuver import LineLoads, check_strip_geometry, strip_line_loads

#: 25.341(a)(5)(i): reference gust velocity (ft/s EAS) vs altitude (ft), linear in between
U_REF_TABLE_FT = ((0.0, 56.0), (15000.0, 44.0), (60000.0, 20.86))
ALTITUDE_RANGE_FT = (0.0, 60000.0)
GRADIENT_RANGE_FT = (30.0, 350.0)
_RANGE_TOL = 1e-9  # relative, for values converted between feet and metres

# Sears' approximation of Kussner's function: psi(s) = 1 - A1 exp(-B1 s) - A2 exp(-B2 s)
_KUSSNER_A = (0.5, 0.5)
_KUSSNER_B = (0.13, 1.0)


# ============================================================================ 25.341 numbers
def check_range(name, value, lo, hi, unit, lo_open=False):
    """``value`` as a float, checked to lie in ``[lo, hi]`` (``(lo, hi]`` with ``lo_open``), with a
    relative tolerance at the bounds.

    Parameters
    ----------
    name : str
        The flag or input named in the error (e.g. ``"--altitude-ft"``).
    value : float
        The value, in ``unit``.
    lo, hi : float
        The allowed range, in ``unit``.
    unit : str
        The unit named in the error.
    lo_open : bool
        Whether ``lo`` itself is excluded.

    Returns
    -------
    float
        ``value``.

    Raises
    ------
    ValueError
        Naming ``name``, the value and the allowed range, for a value outside it or not finite.
    """
    v = float(value)
    tol = _RANGE_TOL * max(abs(lo), abs(hi), 1.0)
    ok_lo = v > lo if lo_open else v >= lo - tol
    if not (np.isfinite(v) and ok_lo and v <= hi + tol):
        bracket = "(" if lo_open else "["
        raise ValueError(f"{name} = {value} {unit}; allowed range {bracket}{lo:g}, {hi:g}] {unit}")
    return v


def reference_gust_velocity_eas(altitude_ft: float, at_vd: bool = False) -> float:
    """U_ref (m/s EAS), 25.341(a)(5): 56 ft/s at sea level, 44 at 15 000 ft, 20.86 at 60 000 ft.

    Linear in altitude between the table points; half of it at V_D (``at_vd``).

    Parameters
    ----------
    altitude_ft : float
        Altitude (ft).
    at_vd : bool, optional
        Halve it, the value at V_D.

    Returns
    -------
    float
        U_ref (m/s EAS).
    """
    h = check_range("altitude_ft", altitude_ft, *ALTITUDE_RANGE_FT, "ft")
    alt, u = zip(*U_REF_TABLE_FT)
    u_ref_fps = float(np.interp(h, alt, u))
    return (0.5 if at_vd else 1.0) * u_ref_fps * FT


def flight_profile_alleviation_factor(
    altitude_ft: float, z_mo_ft: float, mlw_over_mtow: float, mzfw_over_mtow: float
) -> float:
    """F_g, 25.341(a)(6): sea-level value (F_gz + F_gm)/2, rising linearly to 1.0 at Z_mo.

    F_gz = 1 - Z_mo / 250 000 ft, F_gm = sqrt(R2 tan(pi R1 / 4)), R1 = MLW/MTOW,
    R2 = MZFW/MTOW; F_g = 1 at and above Z_mo.

    Parameters
    ----------
    altitude_ft : float
        Altitude (ft).
    z_mo_ft : float
        Maximum operating altitude Z_mo (ft).
    mlw_over_mtow : float
        R1 = maximum landing weight / maximum take-off weight (-).
    mzfw_over_mtow : float
        R2 = maximum zero-fuel weight / maximum take-off weight (-).

    Returns
    -------
    float
        F_g (-).
    """
    h = check_range("altitude_ft", altitude_ft, *ALTITUDE_RANGE_FT, "ft")
    z_mo = check_range("z_mo_ft", z_mo_ft, 0.0, ALTITUDE_RANGE_FT[1], "ft", lo_open=True)
    r1 = check_range("mlw_over_mtow (R1)", mlw_over_mtow, 0.0, 1.0, "", lo_open=True)
    r2 = check_range("mzfw_over_mtow (R2)", mzfw_over_mtow, 0.0, 1.0, "", lo_open=True)
    f_gz = 1.0 - z_mo / 250000.0
    f_gm = np.sqrt(r2 * np.tan(np.pi * r1 / 4.0))
    f_sea_level = 0.5 * (f_gz + f_gm)
    if h >= z_mo:
        return 1.0
    return float(f_sea_level + (1.0 - f_sea_level) * h / z_mo)


def design_gust_velocity_eas(
    gust_gradient_ft: float, altitude_ft: float, alleviation_factor: float, at_vd: bool = False
) -> float:
    """U_ds = U_ref F_g (H / 350 ft)^(1/6) (m/s EAS), Eq. 5.2 / 25.341(a)(4).

    Parameters
    ----------
    gust_gradient_ft : float
        Gust gradient H (ft).
    altitude_ft : float
        Altitude (ft).
    alleviation_factor : float
        Flight profile alleviation factor F_g (-).
    at_vd : bool, optional
        Use half the reference velocity (at V_D).

    Returns
    -------
    float
        U_ds (m/s EAS).
    """
    h_grad = check_range("gust_gradient_ft (H)", gust_gradient_ft, *GRADIENT_RANGE_FT, "ft")
    f_g = check_range("alleviation_factor (F_g)", alleviation_factor, 0.0, 1.0, "", lo_open=True)
    return reference_gust_velocity_eas(altitude_ft, at_vd) * f_g * (h_grad / 350.0) ** (1.0 / 6.0)


class DesignGust(NamedTuple):
    """One 25.341(a) design gust; SI plus the regulation's ft and ft/s for reports.

    Parameters
    ----------
    gust_gradient_m : float
        Gust gradient H (m).
    u_ref_eas : float
        Reference gust velocity (m/s EAS).
    alleviation_factor : float
        Flight profile alleviation factor F_g (-).
    u_ds_eas : float
        Design gust velocity (m/s EAS).
    gust_gradient_ft : float
        Gust gradient H (ft).
    u_ref_eas_fps, u_ds_eas_fps : float
        The two velocities in ft/s EAS.
    """

    gust_gradient_m: float
    u_ref_eas: float  # m/s
    alleviation_factor: float
    u_ds_eas: float  # m/s
    gust_gradient_ft: float
    u_ref_eas_fps: float
    u_ds_eas_fps: float


def design_gust(
    altitude_ft: float,
    gust_gradient_ft: float,
    z_mo_ft: float,
    mlw_over_mtow: float,
    mzfw_over_mtow: float,
    at_vd: bool = False,
) -> DesignGust:
    """Everything 25.341(a) fixes for one (altitude, H) pair, from the regulation's inputs.

    Parameters
    ----------
    altitude_ft : float
        Altitude (ft).
    gust_gradient_ft : float
        Gust gradient H (ft).
    z_mo_ft : float
        Maximum operating altitude (ft).
    mlw_over_mtow : float
        Maximum landing over maximum take-off weight (-).
    mzfw_over_mtow : float
        Maximum zero-fuel over maximum take-off weight (-).
    at_vd : bool, optional
        The gust at V_D (half the reference velocity).

    Returns
    -------
    DesignGust
        The gust.
    """
    f_g = flight_profile_alleviation_factor(altitude_ft, z_mo_ft, mlw_over_mtow, mzfw_over_mtow)
    u_ref = reference_gust_velocity_eas(altitude_ft, at_vd)
    u_ds = design_gust_velocity_eas(gust_gradient_ft, altitude_ft, f_g, at_vd)
    return DesignGust(
        gust_gradient_ft * FT, u_ref, f_g, u_ds, float(gust_gradient_ft), u_ref / FT, u_ds / FT
    )


def gust_gradients_ft(count: int = 10) -> np.ndarray:
    """``count`` gust gradients H (ft) evenly spread over 30-350 ft, both ends included.

    25.341(a)(3) asks for "a sufficient number" in this range to find the critical one.

    Parameters
    ----------
    count : int, optional
        Number of gradients (>= 1).

    Returns
    -------
    numpy.ndarray
        Gust gradients H (ft).
    """
    if int(count) < 2:
        raise ValueError(f"count = {count}; allowed range [2, inf) (both 30 ft and 350 ft are included)")
    return np.linspace(*GRADIENT_RANGE_FT, int(count))


def one_minus_cosine(distance_m, gust_gradient_m: float, u_ds: float):
    """U(s) = U_ds/2 (1 - cos(pi s/H)) for 0 <= s <= 2H, else 0 (Eq. 5.1); s, H in m.

    Parameters
    ----------
    distance_m : float or array_like
        Distance s into the gust (m).
    gust_gradient_m : float
        Gust gradient H (m).
    u_ds : float
        Design gust velocity (m/s).

    Returns
    -------
    float or numpy.ndarray
        Gust velocity U(s) (m/s).
    """
    s = np.asarray(distance_m, dtype=float)
    h = float(gust_gradient_m)
    if not h > 0.0:
        raise ValueError(f"gust_gradient_m = {gust_gradient_m}; allowed range (0, inf) m")
    inside = (s >= 0.0) & (s <= 2.0 * h)
    return np.where(inside, 0.5 * u_ds * (1.0 - np.cos(np.pi * np.clip(s, 0.0, 2.0 * h) / h)), 0.0)


# ============================================================================ Kussner lag
def kussner_sears(semichords):
    """Kussner function, Sears' approximation: psi(s) = 1 - 0.5 e^(-0.13 s) - 0.5 e^(-s).

    ``s`` = distance the leading edge has penetrated into a sharp-edged gust, in semichords
    (0 before entry).

    Parameters
    ----------
    semichords : float or array_like
        Penetration distance s (semichords).

    Returns
    -------
    float or numpy.ndarray
        psi(s) (-).
    """
    s = np.maximum(np.asarray(semichords, dtype=float), 0.0)
    (a1, a2), (b1, b2) = _KUSSNER_A, _KUSSNER_B
    return 1.0 - a1 * np.exp(-b1 * s) - a2 * np.exp(-b2 * s)


def kussner_lagged_velocity(semichords, gust_velocity):
    """Effective (lagged) gust velocity by the Duhamel integral with Kussner's function.

        w_eff(s) = w(s_0) psi(s - s_0) + int_{s_0}^{s} dw/ds'(s') psi(s - s') ds'

    discretised exactly for w piecewise linear between the samples. With
    psi = 1 - sum_i a_i exp(-b_i s) this is

        w_eff(s_k) = w_0 psi(s_k - s_0) + (w_k - w_0) - sum_i a_i X_i(s_k),
        X_i(s_k) = exp(-b_i ds_k) X_i(s_(k-1)) + (dw_k/ds_k) (1 - exp(-b_i ds_k)) / b_i,

    a recursion that costs O(n) (no n x n Duhamel matrix). ``semichords`` (n,) or (n, m),
    strictly increasing down the first axis; ``gust_velocity`` (n,) or (n, m) (columns are
    independent strips). Exact for a gust that is piecewise linear between samples, e.g. a
    sharp-edged gust already present at s_0.

    Parameters
    ----------
    semichords : array_like
        (n,) or (n, m) distance travelled (semichords), strictly increasing down the first axis.
    gust_velocity : array_like
        (n,) or (n, m) gust velocity at those distances (m/s).

    Returns
    -------
    numpy.ndarray
        Lagged velocity, shaped as ``gust_velocity`` (m/s).
    """
    s = np.asarray(semichords, dtype=float)
    w = np.asarray(gust_velocity, dtype=float)
    squeeze = w.ndim == 1
    w2 = w.reshape(w.shape[0], -1)
    s2 = s.reshape(s.shape[0], -1)
    if s2.shape[0] != w2.shape[0] or s2.shape[1] not in (1, w2.shape[1]):
        raise ValueError(f"semichords {s.shape} and gust_velocity {w.shape}: incompatible shapes")
    ds = np.diff(s2, axis=0)
    if np.any(~(ds > 0.0)):
        raise ValueError("semichords: must increase strictly along the first axis")
    slope = np.diff(w2, axis=0) / ds
    out = w2[0][None, :] * kussner_sears(s2 - s2[0])
    out = out + (w2 - w2[0][None, :])
    for a_i, b_i in zip(_KUSSNER_A, _KUSSNER_B):
        decay = np.exp(-b_i * ds)
        gain = slope * (-np.expm1(-b_i * ds)) / b_i
        x = np.zeros(w2.shape[1])
        for k in range(ds.shape[0]):
            x = decay[k] * x + gain[k]
            out[k + 1] -= a_i * x
    return out[:, 0] if squeeze else out


# ============================================================================ strip loads
def lift_curve_slope(
    section_cl_alpha: float = 2.0 * np.pi,
    aspect_ratio: float | None = None,
    sweep_half_chord_rad: float = 0.0,
    mach: float = 0.0,
) -> float:
    """Lift-curve slope per radian used for every strip.

    Without ``aspect_ratio``: the section value, Prandtl-Glauert corrected, c_l_a / beta
    with beta = sqrt(1 - M^2). With it, the finite-wing correction of Helmbold / DATCOM:
    C_L_a = 2 pi A / (2 + sqrt(A^2 beta^2 / kappa^2 (1 + tan^2 Lambda_c/2 / beta^2) + 4)),
    kappa = c_l_a / (2 pi).

    Parameters
    ----------
    section_cl_alpha : float, optional
        Section lift-curve slope (1/rad).
    aspect_ratio : float or None, optional
        Wing aspect ratio; None for the section value.
    sweep_half_chord_rad : float, optional
        Half-chord sweep angle (rad).
    mach : float, optional
        Mach number (-).

    Returns
    -------
    float
        Lift-curve slope (1/rad).
    """
    check_range("mach", mach, 0.0, 0.85, "")
    check_range("section_cl_alpha", section_cl_alpha, 0.0, 4.0 * np.pi, "1/rad", lo_open=True)
    beta = np.sqrt(1.0 - mach**2)
    if aspect_ratio is None:
        return float(section_cl_alpha / beta)
    a = check_range("aspect_ratio", aspect_ratio, 0.0, 1.0e3, "", lo_open=True)
    kappa = section_cl_alpha / (2.0 * np.pi)
    tan2 = np.tan(sweep_half_chord_rad) ** 2
    return float(2.0 * np.pi * a / (2.0 + np.sqrt(a**2 * beta**2 / kappa**2 * (1.0 + tan2 / beta**2) + 4.0)))


def _check_time(time):
    t = np.asarray(time, dtype=float)
    zeros = np.zeros((t.size, 1, 3))
    validate_load_history(t, zeros, zeros, source="time")
    if t.size < 2:
        raise ValueError("time: need at least 2 samples")
    return t


def gust_line_loads(
    node_positions,
    chord,
    beam_axis_fraction,
    time,
    *,
    gust_gradient_m: float,
    u_ds_eas: float,
    airspeed_tas: float,
    altitude_m: float,
    cl_alpha: float = 2.0 * np.pi,
    aspect_ratio: float | None = None,
    sweep_half_chord_rad: float = 0.0,
    prandtl_glauert: bool = False,
    cp_fraction: float = 0.25,
    kussner: bool = False,
    gust_start_time: float = 0.0,
    penetration_delay: bool = True,
    direction: int = 1,
    steady: LineLoads | None = None,
    steady_load_factor: float = 1.0,
    fuselage_half_width: float = 0.0,
    fuselage_carries_lift: bool = True,
) -> LoadHistory:
    """Load time history of a 1 - cos gust on the beam by strip theory (Sec. 5.2.1).

    Each node carries a chordwise strip (chord ``chord[i]``, beam axis at
    ``beam_axis_fraction[i]`` of the chord). The gust front reaches the most forward leading
    edge at ``gust_start_time`` and a point at body x a further (x - x_front)/V later
    (``penetration_delay``). Quasi-steady, the strip sees the gust at its centre of pressure
    (``cp_fraction``): dL' = 1/2 rho V c C_l_a U_TAS, C_l_a = ``cl_alpha`` (per rad) or, with
    ``aspect_ratio`` and/or ``prandtl_glauert``, :func:`lift_curve_slope` of it at the flight
    Mach number (finite-wing / compressibility corrections); with ``kussner`` the gust seen at the
    leading edge is lagged by Kussner's function (Duhamel sum in semichords 2 V t / c).
    ``u_ds_eas`` (m/s EAS, >= 0) is converted to true airspeed at ``altitude_m``;
    ``direction`` +1 (up) or -1 (down). With ``steady`` (the 1-g level-flight line loads,
    e.g. from :func:`~wingmdao.loads.maneuver.maneuver_line_loads` at n = 1), the result is
    ``steady_load_factor`` x steady + gust increment; otherwise the increment only. Loads
    are per unit beam length, body axes; aerodynamic only (inertia relief is the beam's).
    Returns a :class:`~wingmdao.loads.files.LoadHistory` shaped (n_time, n_node, 3).

    Parameters
    ----------
    node_positions : array_like
        (n, 3) beam node positions, body axes (m).
    chord : array_like
        (n,) strip chords (m).
    beam_axis_fraction : array_like
        (n,) beam axis position as a fraction of the chord (-).
    time : array_like
        (n_time,) output times (s).
    gust_gradient_m : float
        Gust gradient H (m).
    u_ds_eas : float
        Design gust velocity (m/s EAS, >= 0).
    airspeed_tas : float
        True airspeed (m/s).
    altitude_m : float
        Altitude (m).
    cl_alpha : float, optional
        Section lift-curve slope (1/rad).
    aspect_ratio : float or None, optional
        Wing aspect ratio for the finite-wing correction; None for none.
    sweep_half_chord_rad : float, optional
        Half-chord sweep (rad).
    prandtl_glauert : bool, optional
        Apply the compressibility correction at the flight Mach number.
    cp_fraction : float, optional
        Centre of pressure as a fraction of the chord (-).
    kussner : bool, optional
        Lag the gust by Kussner's function.
    gust_start_time : float, optional
        Time the gust front reaches the most forward leading edge (s).
    penetration_delay : bool, optional
        Delay each strip by its distance aft of the front over V.
    direction : {1, -1}, optional
        Gust up (+1) or down (-1).
    steady : LineLoads or None, optional
        1 g level-flight line loads to add; None for the increment only.
    steady_load_factor : float, optional
        Factor on ``steady`` (-).
    fuselage_half_width : float, optional
        Fuselage half-width (m).
    fuselage_carries_lift : bool, optional
        Whether the strips with y below ``fuselage_half_width`` carry gust lift.

    Returns
    -------
    LoadHistory
        Loads per unit beam length, (n_time, n_node, 3), body axes.
    """
    r, c, xb = check_strip_geometry(node_positions, chord, beam_axis_fraction, cp_fraction)
    t = _check_time(time)
    h_lo, h_hi = (g * FT for g in GRADIENT_RANGE_FT)
    check_range("gust_gradient_m (H)", gust_gradient_m, h_lo, h_hi, "m")
    check_range("u_ds_eas", u_ds_eas, 0.0, 60.0, "m/s")
    check_range("airspeed_tas", airspeed_tas, 0.0, 400.0, "m/s", lo_open=True)
    check_range("cl_alpha", cl_alpha, 0.0, 4.0 * np.pi, "1/rad", lo_open=True)
    if direction not in (1, -1):
        raise ValueError(f"direction = {direction}; allowed +1 (up gust) or -1 (down gust)")
    if not np.isfinite(gust_start_time):
        raise ValueError(f"gust_start_time = {gust_start_time} s must be finite")
    rho = float(density(altitude_m))
    v = float(airspeed_tas)
    if aspect_ratio is not None or prandtl_glauert:
        mach = v / float(speed_of_sound(altitude_m)) if prandtl_glauert else 0.0
        cl_alpha = lift_curve_slope(cl_alpha, aspect_ratio, sweep_half_chord_rad, mach)
    u_ds_tas = u_ds_eas * np.sqrt(RHO0 / rho)

    x_axis = r[:, 0]
    x_le = x_axis - xb * c
    x_cp = x_le + cp_fraction * c
    x_front = np.min(x_le)
    entry_point = x_le if kussner else x_cp
    delay = (entry_point - x_front) / v if penetration_delay else np.zeros_like(x_le)
    distance = v * (t[:, None] - gust_start_time - delay[None, :])  # (n_t, n_node), m
    w = direction * one_minus_cosine(distance, gust_gradient_m, u_ds_tas)
    if kussner:
        w = kussner_lagged_velocity(2.0 * v * t[:, None] / c[None, :], w)
    lift = 0.5 * rho * v * c[None, :] * cl_alpha * w  # (n_t, n_node) N/m of span
    if not fuselage_carries_lift:
        lift[:, r[:, 1] < fuselage_half_width] = 0.0

    force, moment = strip_line_loads(r, c, xb, lift, cp_fraction)
    if steady is not None:
        if not (np.isfinite(steady_load_factor) and steady_load_factor > 0.0):
            raise ValueError(
                f"steady_load_factor = {steady_load_factor}; allowed range (0, inf) "
                "(the gust is applied from level flight, 25.341(a)(2): 1.0)"
            )
        f0 = np.asarray(steady.force_per_length, dtype=float)
        m0 = np.asarray(steady.moment_per_length, dtype=float)
        if f0.shape != (c.size, 3) or m0.shape != (c.size, 3):
            raise ValueError(f"steady: force/moment shapes {f0.shape}, {m0.shape}; expected ({c.size}, 3)")
        force += steady_load_factor * f0[None]
        moment += steady_load_factor * m0[None]
    return LoadHistory(t, force, moment)
