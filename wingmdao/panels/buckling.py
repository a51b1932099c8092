"""Plate, column and crippling formulas for stiffened panels: one function per formula.

Plain arithmetic only (``select``, ``sqrt`` from :mod:`wingmdao.section.box`): every function
evaluates on floats, numpy arrays and CasADi ``SX`` symbols, and has no Python ``if`` on values.

Conventions. x along the stiffeners (plate length ``a``, the rib pitch), y across (plate width
``b``). Running loads N (N/m); in the ratios compression is negative. Bending stiffnesses
D11, D22, D12, D66 (N m) of a specially orthotropic plate (D16 = D26 = 0; with D16, D26 != 0
these formulas are unconservative, Kassapoglou Sec. 6.3).

Coefficient conventions. Plate buckling coefficients here are the ``k`` of
sigma_cr = k pi^2 E / (12 (1 - nu^2)) (t/b)^2 (Timoshenko & Gere); Bruhn's charts use ``K`` in
sigma_cr = K E (t/b)^2, so K = k pi^2 / (12 (1 - nu^2)) (:func:`bruhn_K`), e.g. k = 4 is
K = 3.62 for nu = 0.3.

Sources:

* Timoshenko & Gere, *Theory of Elastic Stability*, 2nd ed., McGraw-Hill 1961, Sec. 9.2
  (compression, Eq. 9-8 and Fig. 9-4), Sec. 9.7 (shear, Table 9-7 and the fit
  k_s = 5.35 + 4 (b/a)^2).
* Bruhn, *Analysis and Design of Flight Vehicle Structures*, Jacobs 1973, Ch. C5 (plate
  buckling and combined loads) and Ch. C7 (columns: the Johnson-Euler parabola; crippling:
  Needham's method). Section and equation numbers of Bruhn are given where checked; otherwise
  the chapter.
* Kassapoglou, *Design and Analysis of Composite Structures*, 2nd ed., Wiley 2013, Sec. 6.2
  (compression, Eq. 6.7), Sec. 6.5 (long plates under shear), Ch. 8 (crippling).
* Niu, *Airframe Stress Analysis and Sizing*, 2nd ed., Conmilit 1999, Ch. 10 (columns) and
  Ch. 11 (local buckling and crippling).
"""

from __future__ import annotations

import math

from wingmdao.section.box import select, sqrt

#: Added (dimensionless, ratio^2) under the square root of the interaction ratio so that its
#: derivative stays finite at zero load: it raises R by at most 5e-7 (at zero load).
RATIO_TINY = 1e-12

#: Added ((N/m)^2) under sqrt(N_xy^2 + NXY_TINY), the smooth ``|N_xy|``: at most 1e-3 N/m.
NXY_TINY = 1e-6

#: Largest number of half-waves m tried by :func:`plate_compression_ss` (see there).
M_MAX = 20


def _min(x, y):
    return select(x < y, x, y)


def _max(x, y):
    return select(x > y, x, y)


def bruhn_K(k, nu):
    """Bruhn's K = k pi^2 / (12 (1 - nu^2)) of a Timoshenko k (sigma_cr = K E (t/b)^2).

    Parameters
    ----------
    k : float or array_like
        Timoshenko's plate buckling coefficient (-).
    nu : float
        Poisson's ratio (-).

    Returns
    -------
    float or array_like
        Bruhn's coefficient K (-).
    """
    return k * math.pi**2 / (12.0 * (1.0 - nu * nu))


# --------------------------------------------------------------------------- compression
def plate_compression_long(D11, D22, D12, D66, b):
    """N_x,cr (N/m) of a long simply supported specially orthotropic plate in compression.

    N_cr = 2 pi^2 / b^2 (sqrt(D11 D22) + D12 + 2 D66) (Kassapoglou 2nd ed. Sec. 6.2, the minimum
    over a/b of Eq. 6.7; Jones 2nd ed. Sec. 5.5). Valid for a/b -> inf, in practice
    a/b >= 3 (D11/D22)^(1/4) within a few %. Isotropic: k = 4.

    Parameters
    ----------
    D11, D22, D12, D66 : float, array_like or casadi.SX
        Bending stiffnesses of the plate (N m).
    b : float, array_like or casadi.SX
        Plate width across the load (m).

    Returns
    -------
    float, array_like or casadi.SX
        Critical running load N_x,cr (N/m, positive).
    """
    return 2.0 * math.pi**2 / b**2 * (sqrt(D11 * D22) + D12 + 2.0 * D66)


def plate_compression_m(D11, D22, D12, D66, a, b, m):
    """N_x,cr (N/m) for ``m`` half-waves along x of an a x b simply supported orthotropic plate.

    N_cr(m) = pi^2 / b^2 [D11 (m b/a)^2 + 2 (D12 + 2 D66) + D22 (a/(m b))^2]
    (Kassapoglou 2nd ed. Eq. 6.7 with one half-wave across; Timoshenko & Gere Eq. 9-8 for
    isotropic D, k = (m b/a + a/(m b))^2).

    Parameters
    ----------
    D11, D22, D12, D66 : float, array_like or casadi.SX
        Bending stiffnesses of the plate (N m).
    a : float, array_like or casadi.SX
        Plate length along the load (m).
    b : float, array_like or casadi.SX
        Plate width across the load (m).
    m : int
        Number of half-waves along x.

    Returns
    -------
    float, array_like or casadi.SX
        Critical running load of that mode (N/m, positive).
    """
    r = m * b / a
    return math.pi**2 / b**2 * (D11 * r**2 + 2.0 * (D12 + 2.0 * D66) + D22 / r**2)


def plate_compression_ss(D11, D22, D12, D66, a, b, m_max: int = M_MAX):
    """N_x,cr (N/m) of a simply supported a x b specially orthotropic plate in uniaxial compression.

    N_cr = min over m = 1..m_max of :func:`plate_compression_m` (nested ``select``). When the
    continuous optimum m* = (a/b)(D22/D11)^(1/4) exceeds ``m_max`` the plate is long and
    :func:`plate_compression_long` is returned instead (the two agree within
    (1/(2 m_max))^2-ish there). Loaded edges x = 0, a; all edges simply supported; isotropic
    special case k = min_m (m b/a + a/(m b))^2 (= 4 at integer a/b).

    Parameters
    ----------
    D11, D22, D12, D66 : float, array_like or casadi.SX
        Bending stiffnesses of the plate (N m).
    a : float, array_like or casadi.SX
        Plate length along the load (m).
    b : float, array_like or casadi.SX
        Plate width across the load (m).
    m_max : int, optional
        Largest number of half-waves tried (:data:`M_MAX`).

    Returns
    -------
    float, array_like or casadi.SX
        Critical running load N_x,cr (N/m, positive).
    """
    n_cr = plate_compression_m(D11, D22, D12, D66, a, b, 1)
    for m in range(2, m_max + 1):
        n_cr = _min(n_cr, plate_compression_m(D11, D22, D12, D66, a, b, m))
    m_star = a / b * (D22 / D11) ** 0.25
    return select(m_star > m_max, plate_compression_long(D11, D22, D12, D66, b), n_cr)


# --------------------------------------------------------------------------- shear
def plate_shear_long(D11, D22, D12, D66, b):
    """N_xy,cr (N/m) of a long simply supported specially orthotropic plate in shear.

    The long side is along x (the plate is a strip of width b in y, infinitely long in x).
    Kassapoglou 2nd ed. Sec. 6.5 (after Seydel and Lekhnitskii), with
    K = (D12 + 2 D66) / sqrt(D11 D22):

    * K <= 1: N_xy,cr = 4 / b^2 (D11 D22^3)^(1/4) (8.125 + 5.045 K);
    * K >= 1: N_xy,cr = 4 / b^2 sqrt(D22 (D12 + 2 D66)) (11.7 + 0.532/K + 0.938/K^2).

    The two branches meet at K = 1 (13.17 (D11 D22^3)^(1/4) 4/b^2). Isotropic (K = 1):
    k_s = 4 x 13.17 / pi^2 = 5.34 against the exact 5.35 (Timoshenko & Gere Sec. 9.7).
    The bending stiffness across the strip, D22, has the larger weight: a plate stiff across
    the strip buckles later than one stiff along it.

    Parameters
    ----------
    D11, D22, D12, D66 : float, array_like or casadi.SX
        Bending stiffnesses of the plate (N m).
    b : float, array_like or casadi.SX
        Width of the strip (m).

    Returns
    -------
    float, array_like or casadi.SX
        Critical shear flow N_xy,cr (N/m, positive).
    """
    h = D12 + 2.0 * D66
    K = h / sqrt(D11 * D22)
    low = 4.0 / b**2 * (D11 * D22**3) ** 0.25 * (8.125 + 5.045 * K)
    high = 4.0 / b**2 * sqrt(D22 * h) * (11.7 + 0.532 / K + 0.938 / K**2)
    return select(K <= 1.0, low, high)


def plate_shear_ss(D11, D22, D12, D66, a, b):
    """N_xy,cr (N/m) of a simply supported a x b specially orthotropic plate in shear.

    Finite-length correction of :func:`plate_shear_long`, consistent with the isotropic fit
    k_s = 5.35 + 4 (b/a)^2 for a >= b (Timoshenko & Gere Sec. 9.7; Bruhn Ch. C5), which is
    within -4 %/+0 % of the exact k_s for a/b >= 1 (k_s exact 9.34 / 6.6 / 5.9 at a/b = 1 / 2 / 3).
    The affine substitution x' = x (D22/D11)^(1/4) makes the plate "isotropic-like" with
    effective aspect ratio r = (b/a)(D11/D22)^(1/4), so

    * r <= 1 (long side along x): N = N_long(b) + 4 pi^2 D11^(3/4) D22^(1/4) / a^2;
    * r > 1 (long side along y): the same with (a, D11) and (b, D22) swapped.

    Both are continuous at r = 1; the correction is exact in the isotropic limit, an
    approximation of the same accuracy for orthotropic plates with K = (D12 + 2 D66)/sqrt(D11 D22)
    near 1 (for K far from 1 it is an engineering estimate).

    Parameters
    ----------
    D11, D22, D12, D66 : float, array_like or casadi.SX
        Bending stiffnesses of the plate (N m).
    a : float, array_like or casadi.SX
        Plate length along x (m).
    b : float, array_like or casadi.SX
        Plate width along y (m).

    Returns
    -------
    float, array_like or casadi.SX
        Critical shear flow N_xy,cr (N/m, positive).
    """
    r = b / a * (D11 / D22) ** 0.25
    along_x = plate_shear_long(D11, D22, D12, D66, b) + 4.0 * math.pi**2 * D11**0.75 * D22**0.25 / a**2
    along_y = plate_shear_long(D22, D11, D12, D66, a) + 4.0 * math.pi**2 * D22**0.75 * D11**0.25 / b**2
    return select(r <= 1.0, along_x, along_y)


# --------------------------------------------------------------------------- interaction
def smooth_abs(x, tiny=NXY_TINY):
    """sqrt(x^2 + tiny): ``|x|`` with a finite derivative at 0 (off by at most sqrt(tiny)).

    Parameters
    ----------
    x : float, array_like or casadi.SX
        Value whose magnitude is taken.
    tiny : float, optional
        Added under the square root, in the square of x's unit (:data:`NXY_TINY`).

    Returns
    -------
    float, array_like or casadi.SX
        Smooth ``|x|``, in x's unit.
    """
    return sqrt(x * x + tiny)


def compression_ratio(nx, nx_cr):
    """R_c = -N_x / N_x,cr (signed: compression positive, tension negative).

    Parameters
    ----------
    nx : float, array_like or casadi.SX
        Running load N_x (N/m, compression negative).
    nx_cr : float, array_like or casadi.SX
        Critical compressive running load (N/m, positive).

    Returns
    -------
    float, array_like or casadi.SX
        Signed compression ratio R_c (-).
    """
    return -nx / nx_cr


def shear_ratio(nxy, nxy_cr):
    """``R_s = |N_xy| / N_xy,cr`` with the smooth ``|N_xy|`` of :func:`smooth_abs`.

    Parameters
    ----------
    nxy : float, array_like or casadi.SX
        Shear flow N_xy (N/m, either sign).
    nxy_cr : float, array_like or casadi.SX
        Critical shear flow (N/m, positive).

    Returns
    -------
    float, array_like or casadi.SX
        Shear ratio R_s (-).
    """
    return smooth_abs(nxy) / nxy_cr


def interaction_ratio(nx, nxy, nx_cr, nxy_cr):
    """Load-linear compression-shear ratio R (1 = buckling) of a plate.

    Interaction curve R_c + R_s^2 = 1 (Bruhn Ch. C5, combined compression and shear,
    after Batdorf & Stein, NACA TN 1223, 1947, for long plates; Niu Ch. 11) with R_c = -N_x / N_x,cr (signed) and
    ``R_s = |N_xy| / N_xy,cr``. The load factor lambda at which lambda (N_x, N_xy) reaches the
    curve solves R_c/R + (R_s/R)^2 = 1 with R = 1/lambda:

        R = (R_c + sqrt(R_c^2 + 4 R_s^2 + RATIO_TINY)) / 2,

    which is homogeneous of degree 1 in the loads (doubling both doubles R), equals R_c in pure
    compression, R_s in pure shear, and falls below R_s under tension (R_c < 0) as the
    interaction curve extended to tension says. RATIO_TINY keeps it differentiable at zero load.

    Parameters
    ----------
    nx : float, array_like or casadi.SX
        Running load N_x (N/m, compression negative).
    nxy : float, array_like or casadi.SX
        Shear flow N_xy (N/m, either sign).
    nx_cr : float, array_like or casadi.SX
        Critical compressive running load (N/m, positive).
    nxy_cr : float, array_like or casadi.SX
        Critical shear flow (N/m, positive).

    Returns
    -------
    float, array_like or casadi.SX
        Strength ratio R (-; 1 = buckling), linear in the loads.
    """
    rc = compression_ratio(nx, nx_cr)
    rs2 = (nxy * nxy + NXY_TINY) / nxy_cr**2
    return 0.5 * (rc + sqrt(rc * rc + 4.0 * rs2 + RATIO_TINY))


def positive_part(x, tiny=RATIO_TINY):
    """(x + sqrt(x^2 + tiny)) / 2: max(x, 0) with a finite derivative at 0 (off by at most sqrt(tiny) / 2).

    Parameters
    ----------
    x : float, array_like or casadi.SX
        Value whose positive part is taken.
    tiny : float, optional
        Added under the square root, in the square of x's unit (:data:`RATIO_TINY`).

    Returns
    -------
    float, array_like or casadi.SX
        Smooth max(x, 0), in x's unit.
    """
    return 0.5 * (x + sqrt(x * x + tiny))


def biaxial_interaction_ratio(nx, ny, nxy, nx_cr, ny_cr, nxy_cr):
    """:func:`interaction_ratio` of a plate that also carries a transverse load ``ny`` (N/m,
    compression negative) with its own critical load ``ny_cr`` (the plate loaded on its long
    edges): R_c = max(-N_x / N_x,cr, 0) + max(-N_y / N_y,cr, 0), then
    R = (R_c + sqrt(R_c^2 + 4 R_s^2)) / 2.

    The straight-line interaction of the two compressions is conservative for a simply
    supported plate: its biaxial stability condition is, per mode (m, n) of half-waves, linear
    in (N_x, N_y), N_x / N_x(m, n) + N_y / N_y(m, n) = 1 (Timoshenko & Gere Sec. 9.3, plates compressed
    in two perpendicular directions),
    with N_x(m, n) >= N_x,cr and N_y(m, n) >= N_y,cr, so every mode's line lies outside the line
    through (N_x,cr, 0) and (0, N_y,cr). Tension in either direction is not credited (the
    smooth :func:`positive_part`): the same line extended into tension is unconservative. The
    transverse mode of an a x b bay (a along the stiffeners, b across) has one half-wave each
    way, N_x(1, 1) = N_y,cr (a / b)^2, so a spanwise tension raises it by only
    -N_x (b / a)^2, against -N_x N_y,cr / N_x,cr on the straight line: (b/a)^2 N_x,cr / N_y,cr
    = 0.21 of it for a 0.15 x 0.62 m isotropic bay (tests/test_panel_loads.py: with
    N_x = 10 kN/m tension and N_y = -5 kN/m on a 1.5 mm bay the straight line gives half the
    exact load factor's ratio, this form 1.13 times it). Homogeneous of degree 1 in the loads.

    Parameters
    ----------
    nx : float, array_like or casadi.SX
        Running load along the stiffeners N_x (N/m, compression negative).
    ny : float, array_like or casadi.SX
        Running load across the stiffeners N_y (N/m, compression negative).
    nxy : float, array_like or casadi.SX
        Shear flow N_xy (N/m, either sign).
    nx_cr : float, array_like or casadi.SX
        Critical compressive N_x (N/m, positive).
    ny_cr : float, array_like or casadi.SX
        Critical compressive N_y (N/m, positive).
    nxy_cr : float, array_like or casadi.SX
        Critical shear flow (N/m, positive).

    Returns
    -------
    float, array_like or casadi.SX
        Strength ratio R (-; 1 = buckling), linear in the loads.
    """
    rc = positive_part(compression_ratio(nx, nx_cr)) + positive_part(compression_ratio(ny, ny_cr))
    rs2 = (nxy * nxy + NXY_TINY) / nxy_cr**2
    return 0.5 * (rc + sqrt(rc * rc + 4.0 * rs2 + RATIO_TINY))


# --------------------------------------------------------------------------- columns
def euler_column_load(E, I, L, c=1.0):
    """Euler buckling load P_cr = c pi^2 E I / L^2 (N); c = end fixity (1 pinned, 4 clamped).

    Bruhn Ch. C2 (Euler column with end fixity c); Niu Ch. 10. Elastic, straight, prismatic column.

    Parameters
    ----------
    E : float, array_like or casadi.SX
        Young's modulus (Pa).
    I : float, array_like or casadi.SX
        Second moment of area about the buckling axis (m^4).
    L : float, array_like or casadi.SX
        Column length (m).
    c : float, optional
        End-fixity coefficient (-; 1 pinned-pinned, 4 clamped-clamped).

    Returns
    -------
    float, array_like or casadi.SX
        Critical load P_cr (N).
    """
    return c * math.pi**2 * E * I / L**2


def euler_column_stress(E, slenderness, c=1.0):
    """Euler stress sigma_E = c pi^2 E / (L/rho)^2 (Pa), ``slenderness`` = L/rho.

    Parameters
    ----------
    E : float, array_like or casadi.SX
        Young's modulus (Pa).
    slenderness : float, array_like or casadi.SX
        Slenderness L/rho (-).
    c : float, optional
        End-fixity coefficient (-; 1 pinned-pinned, 4 clamped-clamped).

    Returns
    -------
    float, array_like or casadi.SX
        Euler stress (Pa).
    """
    return c * math.pi**2 * E / slenderness**2


def johnson_column_stress(E, slenderness, sigma_cc, c=1.0):
    """Johnson-Euler parabola sigma = sigma_cc (1 - sigma_cc (L/rho)^2 / (4 c pi^2 E)) (Pa).

    Bruhn Ch. C7 ("Johnson-Euler column curve") and Niu Ch. 10: the short-column
    curve with the crippling stress sigma_cc as its cut-off at L/rho = 0, tangent to the Euler
    hyperbola at the transition slenderness (L/rho)_t = pi sqrt(2 c E / sigma_cc), where both
    equal sigma_cc / 2.

    Parameters
    ----------
    E : float, array_like or casadi.SX
        Young's modulus (Pa).
    slenderness : float, array_like or casadi.SX
        Slenderness L/rho (-).
    sigma_cc : float, array_like or casadi.SX
        Crippling stress, the cut-off at zero slenderness (Pa).
    c : float, optional
        End-fixity coefficient (-).

    Returns
    -------
    float, array_like or casadi.SX
        Johnson column stress (Pa).
    """
    return sigma_cc * (1.0 - sigma_cc * slenderness**2 / (4.0 * c * math.pi**2 * E))


def column_stress(E, slenderness, sigma_cc, c=1.0):
    """Column failure stress (Pa): Johnson below the transition slenderness, Euler above.

    ``select(sigma_E > sigma_cc/2, Johnson, Euler)`` with sigma_E = :func:`euler_column_stress`
    and the crippling stress ``sigma_cc`` as the cut-off (sigma <= sigma_cc everywhere).

    Parameters
    ----------
    E : float, array_like or casadi.SX
        Young's modulus (Pa).
    slenderness : float, array_like or casadi.SX
        Slenderness L/rho (-).
    sigma_cc : float, array_like or casadi.SX
        Crippling stress (Pa).
    c : float, optional
        End-fixity coefficient (-).

    Returns
    -------
    float, array_like or casadi.SX
        Column failure stress (Pa).
    """
    sigma_e = euler_column_stress(E, slenderness, c)
    return select(sigma_e > 0.5 * sigma_cc, johnson_column_stress(E, slenderness, sigma_cc, c), sigma_e)


# --------------------------------------------------------------------------- crippling
#: Needham's coefficients C_e (Bruhn Ch. C7, Needham's method; Needham, "The ultimate strength of
#: aluminum-alloy formed structural shapes in compression", J. Aeronaut. Sci. 21(4), 1954):
#: by the number of free edges of the element.
NEEDHAM_CE = {"two_free": 0.316, "one_free": 0.342, "none_free": 0.366}


def crippling_metal(E, sigma_cy, b, t, edge: str = "one_free"):
    """Crippling stress F_cc (Pa) of a metal element of width b and thickness t (Needham).

    F_cc = C_e sqrt(E sigma_cy) / (b/t)^0.75, capped at the compressive yield ``sigma_cy``
    (Bruhn Ch. C7, Needham's method), C_e = 0.342 for an element with one edge free
    (a flange or a blade standing on the skin), 0.366 with no edge free, 0.316 with two free
    (:data:`NEEDHAM_CE`). Needham gives C_e per angle unit with b' = (a + b)/2; here it is used
    per flat element with b' = b, the usual element-by-element (Gerard-style) reading, and the
    section's stress is the area-weighted mean (:func:`section_crippling`). Tests on aluminium
    alloys; for other metals use with care.

    Parameters
    ----------
    E : float, array_like or casadi.SX
        Young's modulus (Pa).
    sigma_cy : float, array_like or casadi.SX
        Compressive yield stress (Pa).
    b : float, array_like or casadi.SX
        Element width (m).
    t : float, array_like or casadi.SX
        Element thickness (m).
    edge : {"one_free", "none_free", "two_free"}, optional
        Free edges of the element (:data:`NEEDHAM_CE`).

    Returns
    -------
    float, array_like or casadi.SX
        Crippling stress F_cc (Pa).
    """
    f = NEEDHAM_CE[edge] * sqrt(E * sigma_cy) / (b / t) ** 0.75
    return _min(f, sigma_cy)


def crippling_laminate(F_cu, b, t, edge: str = "one_free"):
    """Crippling stress F_cc (Pa) of a laminate element, MIL-HDBK-17 (CMH-17) empirical fits.

    One edge free: F_cc / F_cu = 1.63 / (b/t)^0.717; no edge free: F_cc / F_cu = 11 / (b/t)^1.124;
    capped at 1 (F_cc <= F_cu, the laminate compression strength). MIL-HDBK-17-3F Vol. 3
    Sec. 5.7 (crippling); as used in Kassapoglou 2nd ed. Ch. 8 (Eqs. for one- and no-edge-free
    flanges). Fits to quasi-isotropic-ish carbon/epoxy tests, b/t roughly 5-40 (OEF) and
    10-60 (NEF).

    Parameters
    ----------
    F_cu : float, array_like or casadi.SX
        Laminate compression strength (Pa).
    b : float, array_like or casadi.SX
        Element width (m).
    t : float, array_like or casadi.SX
        Element thickness (m).
    edge : {"one_free", "none_free"}, optional
        Free edges of the element.

    Returns
    -------
    float, array_like or casadi.SX
        Crippling stress F_cc (Pa).
    """
    coef, expo = {"one_free": (1.63, 0.717), "none_free": (11.0, 1.124)}[edge]
    ratio = coef / (b / t) ** expo
    return F_cu * _min(ratio, 1.0)


def section_crippling(stresses, areas):
    """Area-weighted crippling stress of a section: sum F_i A_i / sum A_i (Pa).

    Bruhn Ch. C7 (Needham / Gerard element methods); Kassapoglou Ch. 8 for laminates.

    Parameters
    ----------
    stresses : sequence
        Crippling stress of each element (Pa).
    areas : sequence
        Area of each element (m^2).

    Returns
    -------
    float, array_like or casadi.SX
        Area-weighted crippling stress (Pa).
    """
    return sum(f * area for f, area in zip(stresses, areas)) / sum(areas)
