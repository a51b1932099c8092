"""14 CFR 25.341(b) continuous turbulence: von Karman spectrum, U_sigma, A-bar, design and correlated loads.

The regulation (14 CFR 25.341(b), as amended by Amdt. 25-141, 79 FR 73463, Dec. 11, 2014; the same
criteria as CS 25.341(b)), in its own words for the quantities computed here:

* (b)(1): "Limit loads must be determined ... P_L = P_L-1g ± U_sigma A-bar, where P_L = limit load;
  P_L-1g = steady 1g load for the condition; A-bar = ratio of root-mean-square incremental load for
  the condition to root-mean-square turbulence velocity; and U_sigma = limit turbulence intensity
  in true airspeed" (:func:`design_loads`);
* (b)(2): the von Karman power spectral density
  "Phi(Omega) = sigma^2 L / pi [1 + 8/3 (1.339 L Omega)^2] / [1 + (1.339 L Omega)^2]^(11/6)",
  "Phi = power-spectral density (ft/sec)^2/rad/ft; sigma = root-mean-square gust velocity, ft/sec;
  Omega = reduced frequency, radians per foot; L = 2,500 ft" (:func:`von_karman_psd`);
* (b)(3)(i): "At airplane speeds between V_B and V_C: U_sigma = U_sigma_ref F_g, where U_sigma_ref
  is the reference turbulence intensity that varies linearly with altitude from 90 ft/sec (TAS)
  at sea level to 79 ft/sec (TAS) at 24,000 feet and is then constant at 79 ft/sec (TAS) up to
  the altitude of 60,000 feet. F_g is the flight profile alleviation factor defined in paragraph
  (a)(6) of this section" (:func:`reference_turbulence_intensity`; F_g is
  :func:`wingmdao.loads.gust.flight_profile_alleviation_factor`, its one home);
* (b)(3)(ii): "At speed V_D: U_sigma is equal to 1/2 the values obtained under paragraph
  (b)(3)(i)"; (b)(3)(iii): "At speeds between V_C and V_D: U_sigma is equal to a value obtained by
  linear interpolation" (:func:`turbulence_intensity`); (b)(3)(iv): "both positive and negative
  incremental loads due to continuous turbulence must be considered" (the ± of the design loads).

FAA AC 25.341-1, "Dynamic Gust Loads" (2014), describes the frequency-domain analysis (the
transfer functions of the linear aeroelastic model to a unit harmonic gust with the penetration
phase of each lifting station, A-bar from the integral of |H|^2 times the von Karman spectrum) and
the *equiprobable* (correlated) loads: with rho_xy the correlation coefficient of two loads, the
load y that goes with the design value P_x-1g ± U_sigma A-bar_x of x is P_y-1g ± rho_xy U_sigma
A-bar_y, the tangent point of the equal-probability ellipse (:func:`correlation`,
:func:`equal_probability_ellipse`; Hoblit, "Gust Loads on Aircraft: Concepts and Applications",
AIAA Education Series, 1988, Ch. 11).

Units: the regulation's feet and ft/s at the edges (names ending ``_ft``, ``_fps``), SI inside
and in every result: spectra in (m/s)^2 per rad/s of angular frequency omega (one-sided,
int_0^inf Phi d omega = sigma^2), A-bar in output units per m/s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from wingmdao.loads.atmosphere import FT
from wingmdao.loads.gust import check_range, flight_profile_alleviation_factor
from wingmdao.stability.frequency import check_frequencies, spectral_integral

#: 25.341(b)(2): the scale of turbulence L (ft), and the von Karman constant 1.339
SCALE_OF_TURBULENCE_FT = 2500.0
VON_KARMAN_A = 1.339
#: 25.341(b)(3)(i): U_sigma_ref (ft/s TAS) vs altitude (ft), linear in between, constant above 24,000 ft
U_SIGMA_REF_TABLE_FT = ((0.0, 90.0), (24000.0, 79.0), (60000.0, 79.0))
ALTITUDE_RANGE_FT = (0.0, 60000.0)

#: rational approximation of the von Karman vertical spectrum (numerator, denominator: coefficients of
#: (T s)^0, (T s)^1, ... with T = L / V): MIL-HDBK-1797, "Flying Qualities of Piloted Aircraft" (1997),
#: the forming filter of the von Karman vertical gust (written there with 2 L_w = L of 25.341(b)(2); the
#: coefficients of the MathWorks Aerospace Blockset "Von Karman Wind Turbulence Model (Continuous)", which
#: cites it). tests/test_turbulence.py checks the fit against von_karman_psd
VON_KARMAN_FILTER = ((1.0, 2.7478, 0.3398), (1.0, 2.9958, 1.9754, 0.1539))

__all__ = ["von_karman_psd", "von_karman_psd_airspeed_derivative", "von_karman_filter", "synthesize_vertical_turbulence", "reference_turbulence_intensity", "turbulence_intensity", "TurbulenceIntensity",
           "continuous_turbulence_intensity", "a_bar", "correlation", "design_loads",
           "equal_probability_ellipse", "correlated_loads", "flight_profile_alleviation_factor"]


def von_karman_psd(omega, airspeed, sigma=1.0, scale_m=SCALE_OF_TURBULENCE_FT * FT):
    """One-sided von Karman vertical-gust PSD in (m/s)^2 / (rad/s) at angular frequencies ``omega``
    (rad/s) for true airspeed ``airspeed`` (m/s): Phi_omega(omega) = Phi(Omega) / V with Phi(Omega)
    of 25.341(b)(2) at Omega = omega / V (rad/m), sigma in m/s and L = ``scale_m`` (2,500 ft).

    Parameters
    ----------
    omega : float or array_like
        Angular frequencies (rad/s).
    airspeed : float
        True airspeed V (m/s).
    sigma : float, optional
        Gust intensity (m/s, root mean square).
    scale_m : float, optional
        Scale of turbulence L (m).

    Returns
    -------
    numpy.ndarray
        PSD ((m/s)^2 / (rad/s)).
    """
    if not (np.isfinite(airspeed) and airspeed > 0):
        raise ValueError(f"airspeed = {airspeed} m/s; allowed range (0, inf) m/s TAS")
    if not (np.isfinite(scale_m) and scale_m > 0):
        raise ValueError(f"scale_m = {scale_m} m; allowed range (0, inf) m (25.341(b)(2): 2,500 ft)")
    w = np.asarray(omega, dtype=float)
    if np.any(~np.isfinite(w) | (w < 0)):
        raise ValueError("omega: angular frequencies must be finite and >= 0 rad/s")
    x2 = (VON_KARMAN_A * scale_m * w / float(airspeed)) ** 2
    return sigma ** 2 * scale_m / np.pi * (1.0 + 8.0 / 3.0 * x2) / (1.0 + x2) ** (11.0 / 6.0) / float(airspeed)


def von_karman_psd_airspeed_derivative(omega, airspeed, sigma=1.0, scale_m=SCALE_OF_TURBULENCE_FT * FT):
    """d Phi_omega / d V of :func:`von_karman_psd` at fixed omega, sigma and L ((m/s)^2 / (rad/s) per m/s):
    with y = (1.339 L omega / V)^2 and g(y) = (1 + 8/3 y) / (1 + y)^(11/6),
    Phi_omega = sigma^2 L / (pi V) g(y), d Phi / d V = -Phi / V - sigma^2 L / (pi V) g'(y) 2 y / V.

    Parameters
    ----------
    omega : float or array_like
        Angular frequencies (rad/s).
    airspeed : float
        True airspeed V (m/s).
    sigma : float, optional
        Gust intensity (m/s, root mean square).
    scale_m : float, optional
        Scale of turbulence L (m).

    Returns
    -------
    numpy.ndarray
        d Phi / d V.
    """
    phi = von_karman_psd(omega, airspeed, sigma, scale_m)
    V = float(airspeed)
    y = (VON_KARMAN_A * scale_m * np.asarray(omega, dtype=float) / V) ** 2
    dg = 8.0 / 3.0 / (1.0 + y) ** (11.0 / 6.0) - 11.0 / 6.0 * (1.0 + 8.0 / 3.0 * y) / (1.0 + y) ** (17.0 / 6.0)
    return -phi / V - sigma ** 2 * scale_m / (np.pi * V) * dg * 2.0 * y / V


def von_karman_filter(airspeed, sigma=1.0, scale_m=SCALE_OF_TURBULENCE_FT * FT):
    """(num, den): polynomial coefficients in s (highest power first) of the rational forming filter
    H(s) = sigma sqrt(L / (pi V)) (1 + 2.7478 T s + 0.3398 (T s)^2) / (1 + 2.9958 T s + 1.9754 (T s)^2
    + 0.1539 (T s)^3), T = L / V (:data:`VON_KARMAN_FILTER`). |H(i omega)|^2 approximates the
    one-sided :func:`von_karman_psd` (per rad/s): within 1.5 % for omega T <= 2, 4.6 % for omega T <= 20,
    21 % low at omega T = 50 (its tail falls as omega^-2, the spectrum's as omega^-5/3); its variance is
    0.9623 sigma^2.

    Parameters
    ----------
    airspeed : float
        True airspeed V (m/s).
    sigma : float, optional
        Gust intensity (m/s, root mean square).
    scale_m : float, optional
        Scale of turbulence L (m).

    Returns
    -------
    tuple
        (num, den) polynomial coefficients.
    """
    if not (np.isfinite(airspeed) and airspeed > 0):
        raise ValueError(f"airspeed = {airspeed} m/s; allowed range (0, inf) m/s TAS")
    if not (np.isfinite(scale_m) and scale_m > 0):
        raise ValueError(f"scale_m = {scale_m} m; allowed range (0, inf) m (25.341(b)(2): 2,500 ft)")
    T = float(scale_m) / float(airspeed)
    gain = float(sigma) * np.sqrt(float(scale_m) / (np.pi * float(airspeed)))
    num, den = (np.array([c * T ** k for k, c in enumerate(poly)])[::-1] for poly in VON_KARMAN_FILTER)
    return gain * num, den


def controllable_canonical_form(num, den):
    """``(A, B, C)`` of the strictly proper transfer function ``num(s) / den(s)`` (coefficients in
    descending powers, ``len(num) < len(den)``) in controllable canonical form, the convention of
    ``scipy.signal.tf2ss``: A's first row ``-a_1 ... -a_n`` (den normalized to a leading 1) over
    an identity shift, ``B = e_1``, ``C`` the numerator padded to ``n`` coefficients.

    Parameters
    ----------
    num, den : sequence of float
        Numerator and denominator coefficients, descending powers.

    Returns
    -------
    tuple
        (A, B, C).
    """
    num = np.atleast_1d(np.asarray(num, dtype=float))
    den = np.atleast_1d(np.asarray(den, dtype=float))
    n = den.size - 1
    if n < 1 or num.size > n:
        raise ValueError(f"transfer function of numerator degree {num.size - 1} over denominator degree {n}: "
                         "allowed a strictly proper one (numerator degree < denominator degree >= 1)")
    a = den[1:] / den[0]
    A = np.zeros((n, n))
    A[0, :] = -a
    A[1:, :-1] = np.eye(n - 1)
    B = np.zeros((n, 1))
    B[0, 0] = 1.0
    C = np.zeros((1, n))
    C[0, n - num.size:] = num / den[0]
    return A, B, C


def synthesize_vertical_turbulence(n_steps, dt, airspeed, sigma=1.0, scale_m=SCALE_OF_TURBULENCE_FT * FT,
                                   rng=None) -> np.ndarray:
    """(n_steps,) vertical gust velocity (m/s) at t_k = k dt: a sample of the output of
    :func:`von_karman_filter` driven by continuous white noise of one-sided PSD 1 per rad/s (so that
    the output's one-sided PSD is |H(i omega)|^2), started in its stationary state.

    The filter's state-space form is sampled exactly (no integration error): x_{k+1} = F x_k + v_k,
    v_k normal with the covariance Q_d = int_0^dt e^(A u) q B B^T e^(A^T u) du (q = pi, the noise
    intensity of a unit one-sided PSD) from the matrix exponential of Van Loan, "Computing integrals
    involving the matrix exponential", IEEE Trans. Automatic Control 23(3), 1978, 395-404; x_0 from the
    stationary covariance P (A P + P A^T + q B B^T = 0). ``rng``: a numpy Generator (default seed 0).

    Parameters
    ----------
    n_steps : int
        Number of samples.
    dt : float
        Time step (s).
    airspeed : float
        True airspeed V (m/s).
    sigma : float, optional
        Gust intensity (m/s, root mean square).
    scale_m : float, optional
        Scale of turbulence L (m).
    rng : numpy.random.Generator or None, optional
        Random generator; None for ``numpy.random.default_rng(0)`` (a reproducible sample).

    Returns
    -------
    numpy.ndarray
        (n_steps,) gust velocity (m/s).
    """
    n = int(n_steps)
    if n < 1:
        raise ValueError(f"n_steps = {n_steps}; allowed range [1, inf)")
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"dt = {dt} s; allowed range (0, inf) s")
    rng = np.random.default_rng(0) if rng is None else rng
    A, B, C = controllable_canonical_form(*von_karman_filter(airspeed, sigma, scale_m))
    q = np.pi
    k = A.shape[0]
    van_loan = sla.expm(np.block([[-A, q * B @ B.T], [np.zeros((k, k)), A.T]]) * float(dt))
    F = van_loan[k:, k:].T
    Qd = F @ van_loan[:k, k:]
    P = sla.solve_continuous_lyapunov(A, -q * B @ B.T)
    x = np.linalg.cholesky(0.5 * (P + P.T)) @ rng.standard_normal(k)
    Lq = np.linalg.cholesky(0.5 * (Qd + Qd.T))
    noise = rng.standard_normal((n, k)) @ Lq.T
    out = np.empty(n)
    for i in range(n):
        out[i] = (C @ x)[0]
        x = F @ x + noise[i]
    return out


def reference_turbulence_intensity(altitude_ft: float) -> float:
    """U_sigma_ref (m/s TAS), 25.341(b)(3)(i): 90 ft/s at sea level, linear to 79 ft/s at 24,000 ft,
    79 ft/s up to 60,000 ft; ValueError outside 0-60,000 ft.

    Parameters
    ----------
    altitude_ft : float
        Altitude (ft).

    Returns
    -------
    float
        U_sigma_ref (m/s TAS).
    """
    h = check_range("altitude_ft", altitude_ft, *ALTITUDE_RANGE_FT, "ft")
    alt, u = zip(*U_SIGMA_REF_TABLE_FT)
    return float(np.interp(h, alt, u)) * FT


def turbulence_intensity(u_sigma_ref: float, f_g: float, speed: float, v_c: float, v_d: float) -> float:
    """U_sigma = U_sigma_ref F_g at speeds up to V_C, half of it at V_D, linear in between
    (25.341(b)(3)(i)-(iii)); ``speed``, ``v_c``, ``v_d`` in one unit (e.g. m/s EAS), 0 < V_C < V_D,
    speed in (0, V_D].

    Parameters
    ----------
    u_sigma_ref : float
        Reference intensity (m/s TAS).
    f_g : float
        Flight profile alleviation factor (-).
    speed : float
        Airspeed.
    v_c : float
        Design cruising speed, same unit.
    v_d : float
        Design dive speed, same unit.

    Returns
    -------
    float
        U_sigma (m/s TAS).
    """
    if not (np.isfinite(u_sigma_ref) and u_sigma_ref > 0):
        raise ValueError(f"u_sigma_ref = {u_sigma_ref} m/s; allowed range (0, inf) m/s")
    check_range("f_g (flight profile alleviation factor)", f_g, 0.0, 1.0, "", lo_open=True)
    if not (np.isfinite(v_c) and np.isfinite(v_d) and 0 < v_c < v_d):
        raise ValueError(f"V_C = {v_c}, V_D = {v_d}; need 0 < V_C < V_D (same units)")
    v = check_range("speed", speed, 0.0, v_d, "(the unit of V_C, V_D)", lo_open=True)
    frac = min(max((v - v_c) / (v_d - v_c), 0.0), 1.0)
    return float(u_sigma_ref * f_g * (1.0 - 0.5 * frac))


@dataclass(frozen=True)
class TurbulenceIntensity:
    """The 25.341(b)(3) intensity of one flight point: ``altitude_ft``, ``u_sigma_ref`` (m/s TAS),
    ``f_g``, ``speed_factor`` (1 up to V_C, 1/2 at V_D) and ``u_sigma`` (m/s TAS).

    Parameters
    ----------
    altitude_ft : float
        Altitude (ft).
    u_sigma_ref : float
        Reference intensity (m/s TAS).
    f_g : float
        Flight profile alleviation factor (-).
    speed_factor : float
        1 up to V_C, 1/2 at V_D (-).
    u_sigma : float
        Design intensity (m/s TAS).
    """

    altitude_ft: float
    u_sigma_ref: float
    f_g: float
    speed_factor: float
    u_sigma: float


def continuous_turbulence_intensity(altitude_ft, *, z_mo_ft, mlw_over_mtow, mzfw_over_mtow, speed=None, v_c=None,
                                    v_d=None) -> TurbulenceIntensity:
    """Everything 25.341(b)(3) fixes for one flight point (F_g of 25.341(a)(6) from Z_mo, MLW/MTOW,
    MZFW/MTOW); without ``speed`` the point is at or below V_C.

    Parameters
    ----------
    altitude_ft : float
        Altitude (ft).
    z_mo_ft : float
        Maximum operating altitude (ft).
    mlw_over_mtow : float
        Maximum landing over maximum take-off weight (-).
    mzfw_over_mtow : float
        Maximum zero-fuel over maximum take-off weight (-).
    speed, v_c, v_d : float or None, optional
        Airspeed, V_C and V_D in one unit; None for a point at or below V_C.

    Returns
    -------
    TurbulenceIntensity
        The intensity.
    """
    u_ref = reference_turbulence_intensity(altitude_ft)
    f_g = flight_profile_alleviation_factor(altitude_ft, z_mo_ft, mlw_over_mtow, mzfw_over_mtow)
    if speed is None:
        u = u_ref * f_g
    else:
        u = turbulence_intensity(u_ref, f_g, speed, v_c, v_d)
    return TurbulenceIntensity(float(altitude_ft), u_ref, f_g, u / (u_ref * f_g), u)


@dataclass
class ABar:
    """A-bar of outputs (output units per m/s): ``value``, its quadrature error estimate
    ``error`` (from the Richardson estimate of the integral of A-bar^2 and the spectral tail,
    |dI| / (2 A-bar)) and the ``psd`` (n_freq, ...) of the output per unit (m/s)^2 of sigma^2.

    Parameters
    ----------
    value : numpy.ndarray
        A-bar (output units per m/s).
    error : numpy.ndarray
        Quadrature error estimate of ``value``.
    psd : numpy.ndarray
        (n_freq, ...) output PSD per unit sigma^2.
    """

    value: np.ndarray
    error: np.ndarray
    psd: np.ndarray


def a_bar(omega, response, airspeed, scale_m=SCALE_OF_TURBULENCE_FT * FT) -> ABar:
    """A-bar = sqrt(int_0^inf |H(omega)|^2 Phi_1(omega) d omega) of transfer functions ``response``
    (n_freq, ...) complex, Phi_1 the von Karman PSD of unit sigma (:func:`von_karman_psd`), on the
    grid ``omega`` (rad/s; odd count, :func:`wingmdao.stability.frequency.frequency_grid`).

    Parameters
    ----------
    omega : numpy.ndarray
        Frequency grid (rad/s, odd count).
    response : numpy.ndarray
        (n_freq, ...) complex transfer functions (output per m/s of gust).
    airspeed : float
        True airspeed V (m/s).
    scale_m : float, optional
        Scale of turbulence L (m).

    Returns
    -------
    ABar
        A-bar, its error estimate and the PSD.
    """
    w = check_frequencies(omega)
    H = np.asarray(response)
    phi = von_karman_psd(w, airspeed, 1.0, scale_m).reshape((-1,) + (1,) * (H.ndim - 1))
    psd = np.abs(H) ** 2 * phi
    integral = spectral_integral(w, psd)
    value = np.sqrt(np.maximum(integral.value, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        err = np.where(value > 0, (integral.quadrature_error + np.abs(integral.tail)) / (2 * value), 0.0)
    return ABar(value, err, psd)


def correlation(omega, response_x, response_y, airspeed, scale_m=SCALE_OF_TURBULENCE_FT * FT):
    """Correlation coefficient rho_xy = int Re(H_x conj(H_y)) Phi_1 / (A-bar_x A-bar_y) of two outputs
    (elementwise over the trailing axes), in [-1, 1].

    Parameters
    ----------
    omega : numpy.ndarray
        Frequency grid (rad/s, odd count).
    response_x, response_y : numpy.ndarray
        (n_freq, ...) complex transfer functions of the two outputs.
    airspeed : float
        True airspeed V (m/s).
    scale_m : float, optional
        Scale of turbulence L (m).

    Returns
    -------
    numpy.ndarray
        rho_xy (-).
    """
    w = check_frequencies(omega)
    hx, hy = np.asarray(response_x), np.asarray(response_y)
    if hx.shape != hy.shape:
        raise ValueError(f"response_x {hx.shape} and response_y {hy.shape}: need the same shape")
    phi = von_karman_psd(w, airspeed, 1.0, scale_m).reshape((-1,) + (1,) * (hx.ndim - 1))
    cross = spectral_integral(w, np.real(hx * np.conj(hy)) * phi).value
    ax = np.sqrt(np.maximum(spectral_integral(w, np.abs(hx) ** 2 * phi).value, 0.0))
    ay = np.sqrt(np.maximum(spectral_integral(w, np.abs(hy) ** 2 * phi).value, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = np.where((ax > 0) & (ay > 0), cross / (ax * ay), 0.0)
    return np.clip(rho, -1.0, 1.0)


def design_loads(load_1g, u_sigma, a_bar_value):
    """(P_1g + U_sigma A-bar, P_1g - U_sigma A-bar) of 25.341(b)(1), elementwise.

    Parameters
    ----------
    load_1g : array_like
        1 g loads P_1g.
    u_sigma : float
        Design intensity U_sigma (m/s).
    a_bar_value : array_like
        A-bar of the loads (load units per m/s).

    Returns
    -------
    tuple
        (upper, lower) design loads.
    """
    if not (np.isfinite(u_sigma) and u_sigma >= 0):
        raise ValueError(f"u_sigma = {u_sigma} m/s; allowed range [0, inf) m/s TAS")
    p = np.asarray(load_1g, dtype=float)
    d = float(u_sigma) * np.asarray(a_bar_value, dtype=float)
    return p + d, p - d


def equal_probability_ellipse(load_1g, u_sigma, a_bar_xy, rho, n_points=73):
    """(n_points, 2) points of the equal-probability ellipse of two loads (x, y):
    x = P_x + U A_x cos t, y = P_y + U A_y (rho cos t + sqrt(1 - rho^2) sin t), t in [0, 2 pi].

    Parameters
    ----------
    load_1g : sequence of 2
        1 g values (P_x, P_y).
    u_sigma : float
        Design intensity (m/s).
    a_bar_xy : sequence of 2
        A-bar of x and y (per m/s).
    rho : float
        Correlation coefficient (-).
    n_points : int, optional
        Points on the ellipse.

    Returns
    -------
    numpy.ndarray
        (n_points, 2) points.
    """
    if not -1.0 <= float(rho) <= 1.0:
        raise ValueError(f"rho = {rho}; allowed range [-1, 1]")
    t = np.linspace(0.0, 2 * np.pi, int(n_points))
    px, py = np.asarray(load_1g, dtype=float)
    ax, ay = float(u_sigma) * np.asarray(a_bar_xy, dtype=float)
    x = px + ax * np.cos(t)
    y = py + ay * (rho * np.cos(t) + np.sqrt(max(0.0, 1.0 - rho ** 2)) * np.sin(t))
    return np.column_stack([x, y])


def correlated_loads(load_1g, u_sigma, a_bar_xy, rho) -> np.ndarray:
    """(4, 2) tangent points of the ellipse (AC 25.341-1 equiprobable loads): x at its design values
    P_x ± U A_x with y = P_y ± rho U A_y, then y at P_y ± U A_y with x = P_x ± rho U A_x.

    Parameters
    ----------
    load_1g : sequence of 2
        1 g values (P_x, P_y).
    u_sigma : float
        Design intensity (m/s).
    a_bar_xy : sequence of 2
        A-bar of x and y (per m/s).
    rho : float
        Correlation coefficient (-).

    Returns
    -------
    numpy.ndarray
        (4, 2) design points.
    """
    px, py = np.asarray(load_1g, dtype=float)
    ax, ay = float(u_sigma) * np.asarray(a_bar_xy, dtype=float)
    return np.array([[px + ax, py + rho * ay], [px - ax, py - rho * ay],
                     [px + rho * ax, py + ay], [px - rho * ax, py - ay]])
