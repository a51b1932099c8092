"""A beam (stick) model with its lifting surface as a Nastran aeroelastic bulk-data deck: structure,
masses, doublet-lattice panels, beam splines and the flutter / gust / trim cards of SOL 144, 145 and
146. DLR's Loads Kernel reads the same deck's GRID, CORD2R, SET1 and CAERO1 cards.

Fixed small-field format throughout: ten 8-character fields per line, the card name in field 1,
data in fields 2-9, a continuation marker ``+`` in field 10 of a continued line and in field 1 of
the line that continues it (:func:`card_lines`); reals always carry a decimal point and use
Nastran's short exponent form (``1.2345-5`` = 1.2345e-5) when that keeps more digits in 8
characters (:func:`nastran_real`). Units SI (m, kg, s, N); ``PARAM,WTMASS,1.0``.

The beam (``params``: the parameter dict of :mod:`wingmdao.beam.residual`, nodes root first):

* GRID per beam node (basic coordinates); SPC1 123456 at the root node.
* CBEAM per element with the orientation vector v = the element's n axis (so element y = n,
  z = c, x = s) and offsets WA = WB = the shear centre (OFFT GGG, basic axes); PBEAM with the
  section constants of the element's constitutive law: the residual averages the two nodes'
  compliances, (E_a^-1 + E_b^-1) / 2 for bending/torsion and the mean of 1/EA, 1/(G K) for
  stretching and shear, so the element's stiffness is the inverse of that mean. With MAT1's E and
  G: A = EA / E, I1 = EI_cc / E (bending in plane 1 about element z = c), I2 = EI_nn / E,
  I12 = -EI_cn / E (the beam's E_cn = -E int(c n) dA, Nastran's I12 = int(y z) dA), J = GJ / G,
  K1 = G K_n / (G A), K2 = G K_c / (G A); N1, N2 = the tension axis from the shear centre (y = n,
  z = c). MAT1 carries E and G (nu follows from them) and no density: all mass is in CONM2.
* CONM2 per node: half of each adjacent element's mass ds (mu_a + mu_b) / 2 at the element's
  mass-centre offset T^T (c_cg, 0, n_cg) from the node (T of the element's mean jig angles, as in
  the residual), combined per node into one mass at its centre of gravity with the elements'
  rotary inertia ds T^T i T / 2 and the parallel-axis terms of the halves. Total mass and centre
  of gravity equal the beam's (sum over elements of m_e (mid-point + offset)); the lumped model
  leaves out the spanwise rotary inertia m_e ds^2 / 12 of each element about its mid-point.

The aerodynamics (a half model, symmetric about the x-z plane):

* CAERO1 + PAERO1 per trapezoidal panel, NSPAN x NCHORD equal boxes; box ids EID, EID + 1, ...
  (chordwise first). SPLINE2 (beam spline) per panel, its axis the y axis of a CORD2R along the
  beam segment under the panel, rigidly attached in slope and twist (DTHX = DTHY = 0.0), on a
  SET1 of the segment's grids.
* AERO (SOL 145/146: velocity, reference chord, density), AEROS (SOL 144: REFC, REFB = full span,
  REFS = the half model's area); MKAERO1 (Mach numbers x reduced frequencies k = omega (c/2) / V).
* SOL 145: FLFACT (density ratio, Mach, velocities) and FLUTTER (PK); EIGRL for the modes.
* SOL 146: GUST (WG = 1 / V: a 1 m/s vertical gust) on RLOAD1 + TABLED1 (unit spectrum) + DAREA
  (zero load, the excitation's id), FREQ1, RANDPS on TABRND1: the one-sided von Karman PSD of
  14 CFR 25.341(b)(2) (L = 2,500 ft, sigma = 1 m/s) in (m/s)^2/Hz against Hz, log-log.
* SOL 144: AESTAT ANGLEA and TRIM at a fixed angle of attack (the restrained wing's loads per
  ``alpha``).

Card formats: MSC Nastran Quick Reference Guide (MSC Software), Bulk Data Entries GRID, CBEAM,
PBEAM, MAT1, CONM2, SPC1, CORD2R, SET1, CAERO1, PAERO1, SPLINE2, AERO, AEROS, MKAERO1, FLFACT,
FLUTTER, EIGRL, GUST, RLOAD1, TABLED1, DAREA, FREQ1, RANDPS, TABRND1, AESTAT, TRIM, PARAM, and
"The Nastran Small Field Format" (Bulk Data Entry format rules); the same cards in Altair
OptiStruct's reference (SPLINE2: "DTHX, DTHY rotational attachment flexibility"; CONM2: inertia
matrix [[I11, -I21, -I31], [-I21, I22, -I32], [-I31, -I32, I33]] about the centre of gravity;
PBEAM: the last two continuations K1, K2, ... and M1A ... N2B); MSC Nastran Aeroelastic Analysis
User's Guide (AEROS: REFB the full span, REFS the half model's area on a half-span model). Loads
Kernel's reader: DLR-AE/LoadsKernel, ``loadskernel/io_functions/read_bdf.py`` (fixed fields,
a continuation recognised by field 10 equal to the next line's field 1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from wingmdao.beam.rotations import body_to_csn

#: width of a small-field field (characters)
FIELD = 8
#: the solution sequences the deck's executive and case control can select
SOLUTIONS = (144, 145, 146)
#: ids of the deck's cards (structure 1.., aero boxes from AERO_ID, splines, sets, tables)
GRID_ID0, CONM2_ID0, CAERO_ID0, CAERO_STEP, SPLINE_ID0, CORD_ID0 = 1, 10001, 100001, 10000, 901, 901
PID_AERO, MID, SPC_ID, EIGRL_ID, FLUTTER_ID, GUST_ID, RLOAD_ID, TABLED_ID, DAREA_ID = 1, 1, 1, 10, 30, 50, 51, 52, 53
FREQ_ID, RANDOM_ID, TABRND_ID, TRIM_ID, AESTAT_ID = 40, 60, 61, 70, 71
FLFACT_DENSITY, FLFACT_MACH, FLFACT_VELOCITY = 31, 32, 33


# --------------------------------------------------------------------------- small-field format
def _nastran_exponent(text: str) -> str:
    """'1.2345e-05' -> '1.2345-5', '1e+10' -> '1.+10' (Nastran's short exponent form)."""
    mantissa, exponent = text.split("e")
    if "." not in mantissa:
        mantissa += "."
    return f"{mantissa}{int(exponent):+d}"


def _trim_fixed(text: str) -> str:
    """'0.500000' -> '.5', '-12.000' -> '-12.', '0.000' -> '0.'."""
    sign = "-" if text.startswith("-") else ""
    body = text.lstrip("-").rstrip("0")
    if body.startswith("0.") and body != "0.":
        body = body[1:]
    return sign + body


def nastran_real(value) -> str:
    """``value`` as a Nastran real in at most 8 characters, the representation with the smallest
    rounding error among the fixed-point and short-exponent forms ('1.2345-5', '123456.7', '-.5');
    always with a decimal point. ValueError for a value that is not finite.

    Parameters
    ----------
    value : float
        The number.

    Returns
    -------
    str
        The field text (at most 8 characters).
    """
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"a Nastran real must be finite, got {value!r}")
    if x == 0.0:
        return "0."
    candidates = []
    for digits in range(FIELD):
        text = f"{x:.{digits}f}"
        if float(text) != 0.0:
            candidates.append(_trim_fixed(text if "." in text else text + "."))
    for digits in range(FIELD - 1):
        text = f"{x:.{digits}e}"
        candidates.append(_nastran_exponent(text))
        mantissa, exponent = text.split("e")      # the same digits as .ddd x 10^(e+1): '.12345-9'
        sign = "-" if mantissa.startswith("-") else ""
        candidates.append(f"{sign}.{mantissa.lstrip('-').replace('.', '')}{int(exponent) + 1:+d}")
    fits = [c for c in candidates if len(c) <= FIELD and math.isfinite(parse_real(c))]
    if not fits:
        raise ValueError(f"{x!r} does not fit an 8-character Nastran real field")
    return min(fits, key=lambda c: (abs(parse_real(c) - x), len(c)))


def parse_real(text: str) -> float:
    """A Nastran real field ('1.2-5', '-.5', '3.E+4', '2.5D-3') as a float.

    Parameters
    ----------
    text : str
        The field text.

    Returns
    -------
    float
        The value.
    """
    s = text.strip().upper().replace("D", "E")
    if "E" not in s:
        for k in range(len(s) - 1, 0, -1):
            if s[k] in "+-":
                s = s[:k] + "E" + s[k:]
                break
    return float(s)


def _field(value) -> str:
    if value is None:
        return ""
    if isinstance(value, (bool, np.bool_)):
        raise TypeError("a Nastran field is an integer, a real or a string, not a bool")
    if isinstance(value, (int, np.integer)):
        text = str(int(value))
    elif isinstance(value, (float, np.floating)):
        text = nastran_real(value)
    else:
        text = str(value)
    if len(text) > FIELD:
        raise ValueError(f"Nastran field {text!r} is longer than {FIELD} characters")
    return text


def card_lines(name: str, fields) -> list[str]:
    """Small-field lines of one card: ``name`` and its data fields (int, float, str or None for a
    blank field), 8 data fields per line, ``+`` continuation markers in field 10 and field 1.

    Parameters
    ----------
    name : str
        Card name.
    fields : sequence
        Data fields: int, float, str or None (blank).

    Returns
    -------
    list of str
        The card's lines.
    """
    texts = [_field(v) for v in fields]
    while texts and texts[-1] == "":
        texts.pop()
    chunks = [texts[i:i + 8] for i in range(0, max(len(texts), 1), 8)]
    lines = []
    for k, chunk in enumerate(chunks):
        head = f"{name:<8}" if k == 0 else "+" + " " * (FIELD - 1)
        body = "".join(f"{t:>8}" if _is_number(t) else f"{t:<8}" for t in chunk)
        if k < len(chunks) - 1:
            body = f"{body:<64}+"
        lines.append((head + body).rstrip())
    return lines


def _is_number(text: str) -> bool:
    return bool(text) and (text[0].isdigit() or text[0] in "+-.")


# --------------------------------------------------------------------------- model data
@dataclass(frozen=True)
class LiftingPanel:
    """A trapezoidal CAERO1 panel: leading-edge points (basic, m) and chords (m) at its inboard and
    outboard edges, ``nspan`` x ``nchord`` equal boxes, splined to the beam nodes ``nodes``
    (indices, root = 0) whose segment lies under it.

    Parameters
    ----------
    root_le, tip_le : tuple
        Leading-edge points of the inboard and outboard edges, basic axes (m).
    root_chord, tip_chord : float
        Chords of the inboard and outboard edges (m).
    nspan, nchord : int
        Boxes along the span and the chord.
    nodes : tuple of int
        Beam node indices splined to the panel (root = 0).
    """

    root_le: tuple
    root_chord: float
    tip_le: tuple
    tip_chord: float
    nspan: int
    nchord: int
    nodes: tuple

    @property
    def area(self) -> float:
        """Planform (x-y projected) area, m^2."""
        return 0.5 * (self.root_chord + self.tip_chord) * abs(self.tip_le[1] - self.root_le[1])


@dataclass(frozen=True)
class FlightData:
    """The aeroelastic cards' flight data (SI, TAS). ``gust_*``: the SOL 146 point (AERO's velocity
    and density); ``flutter_*``: the SOL 145 sweep (density, Mach, velocities); ``trim_*``: the
    SOL 144 point; ``reference_chord``, ``full_span``, ``half_area``: AERO/AEROS references.

    Parameters
    ----------
    reference_chord : float
        AERO/AEROS reference chord (m).
    full_span : float
        AEROS reference span of the full wing (m).
    half_area : float
        AEROS reference area of the half wing (m^2).
    gust_mach, gust_velocity, gust_density : float
        SOL 146 point: Mach number (-), true airspeed (m/s), air density (kg/m^3).
    flutter_density, flutter_mach : float
        SOL 145 density (kg/m^3) and Mach number (-).
    flutter_velocities : tuple
        SOL 145 velocities (m/s).
    trim_mach, trim_dynamic_pressure : float
        SOL 144 Mach number (-) and dynamic pressure (Pa).
    trim_alpha_deg : float, optional
        SOL 144 angle of attack (deg).
    reduced_frequencies : tuple, optional
        MKAERO1 reduced frequencies (-).
    frequency_hz : tuple, optional
        FREQ1 (F1, DF, NDF) of the gust response: start (Hz), step (Hz), number of steps.
    turbulence_scale_m : float, optional
        Von Karman scale length L (m).
    psd_frequencies_hz : tuple, optional
        TABRND1 frequencies of the gust PSD (Hz).
    """

    reference_chord: float
    full_span: float
    half_area: float
    gust_mach: float
    gust_velocity: float
    gust_density: float
    flutter_density: float
    flutter_mach: float
    flutter_velocities: tuple
    trim_mach: float
    trim_dynamic_pressure: float
    trim_alpha_deg: float = 1.0
    reduced_frequencies: tuple = (0.001, 0.01, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0)
    frequency_hz: tuple = (0.05, 0.05, 399)       # FREQ1: F1, DF, NDF
    turbulence_scale_m: float = 2500.0 * 0.3048
    psd_frequencies_hz: tuple = field(default_factory=lambda: tuple(np.geomspace(1e-3, 100.0, 51)))


# --------------------------------------------------------------------------- beam cards
def element_frames(params) -> np.ndarray:
    """(n-1, 3, 3): T(theta0_m) of each element's mean jig angles, rows c, s, n in basic axes.

    Parameters
    ----------
    params : dict
        Beam parameters (``param_specs`` names of :mod:`wingmdao.beam.residual`).

    Returns
    -------
    numpy.ndarray
        (n - 1, 3, 3) element frames.
    """
    th = np.asarray(params["node_euler_angles"], float)
    return np.array([body_to_csn(0.5 * (th[i] + th[i + 1])) for i in range(th.shape[0] - 1)])


def written_moduli(material) -> tuple[float, float]:
    """E and G as MAT1 carries them (rounded to 8 characters): the section constants are divided
    by these, so that the deck's E I, G J and E A are the beam's to the constants' own rounding.

    Parameters
    ----------
    material : Material
        Isotropic material.

    Returns
    -------
    tuple
        (E, G) as written (Pa).
    """
    return parse_real(nastran_real(material.E)), parse_real(nastran_real(material.G))


def element_sections(params, material) -> list[dict]:
    """Per element the PBEAM constants (see the module docstring) and the offsets (basic).

    Parameters
    ----------
    params : dict
        Beam parameters (``param_specs`` names of :mod:`wingmdao.beam.residual`).
    material : Material
        Isotropic material whose E and G the MAT1 card carries.

    Returns
    -------
    list of dict
        Per element the PBEAM constants and offsets.
    """
    E, G = written_moduli(material)
    stiff = np.asarray(params["stiffness_csn"], float)
    comp = np.asarray(params["compliance_csn"], float)
    ta = np.asarray(params["tension_axis"], float)
    sc = np.asarray(params["shear_center"], float)
    out = []
    for i, T in enumerate(element_frames(params)):
        K = np.linalg.inv(0.5 * (np.linalg.inv(stiff[i]) + np.linalg.inv(stiff[i + 1])))
        if abs(K[0, 1]) + abs(K[1, 2]) > 1e-9 * np.max(np.abs(K)):
            raise ValueError(f"stiffness_csn of element {i}: bending-torsion coupling (E_cs, E_sn) has no PBEAM "
                             "field; the Nastran export takes uncoupled sections")
        c_s, c_e, c_n = 0.5 * (comp[i] + comp[i + 1])      # 1/(G K_c), 1/EA, 1/(G K_n)
        area = 1.0 / (c_e * E)
        sc_m, ta_m = 0.5 * (sc[i] + sc[i + 1]), 0.5 * (ta[i] + ta[i + 1])
        out.append({"A": area, "I1": K[0, 0] / E, "I2": K[2, 2] / E, "I12": -K[0, 2] / E, "J": K[1, 1] / G,
                    "K1": 1.0 / (c_n * G * area), "K2": 1.0 / (c_s * G * area),
                    "N1": ta_m[1] - sc_m[1], "N2": ta_m[0] - sc_m[0],
                    "offset": T.T @ np.array([sc_m[0], 0.0, sc_m[1]]), "v": T[2]})
    return out


def lumped_masses(params) -> list[tuple]:
    """[(node index, mass kg, offset (3,) m basic, inertia about the CG (3, 3) kg m^2 basic)] per
    node with mass (see the module docstring).

    Parameters
    ----------
    params : dict
        Beam parameters (``param_specs`` names of :mod:`wingmdao.beam.residual`).

    Returns
    -------
    list of tuple
        ``(node index, mass, offset, inertia)`` per node with mass.
    """
    r = np.asarray(params["node_positions"], float)
    mu = np.asarray(params["mass_per_length"], float)
    cg = np.asarray(params["mass_center"], float)
    inertia = np.asarray(params["inertia_per_length"], float)
    halves = [[] for _ in range(r.shape[0])]
    for i, T in enumerate(element_frames(params)):
        ds = float(np.linalg.norm(r[i + 1] - r[i]))
        m = 0.5 * ds * 0.5 * (mu[i] + mu[i + 1])
        c_cg, n_cg = 0.5 * (cg[i] + cg[i + 1])
        d = T.T @ np.array([c_cg, 0.0, n_cg])
        J = 0.5 * ds * T.T @ (0.5 * (inertia[i] + inertia[i + 1])) @ T
        halves[i].append((m, d, J))
        halves[i + 1].append((m, d, J))
    out = []
    for k, parts in enumerate(halves):
        mass = sum(m for m, _, _ in parts)
        if mass <= 0.0:
            continue
        x = sum(m * d for m, d, _ in parts) / mass
        J = sum(Jh + m * (np.dot(d - x, d - x) * np.eye(3) - np.outer(d - x, d - x)) for m, d, Jh in parts)
        out.append((k, mass, x, J))
    return out


def beam_cards(params, material) -> list[str]:
    """GRID, MAT1, PBEAM, CBEAM, CONM2, SPC1 lines of the beam ``params``.

    Parameters
    ----------
    params : dict
        Beam parameters (``param_specs`` names of :mod:`wingmdao.beam.residual`).
    material : Material
        Isotropic material whose E and G the MAT1 card carries.

    Returns
    -------
    list of str
        The bulk-data lines.
    """
    r = np.asarray(params["node_positions"], float)
    lines = []
    for k, p in enumerate(r):
        lines += card_lines("GRID", [GRID_ID0 + k, None, *map(float, p)])
    lines += card_lines("MAT1", [MID, *written_moduli(material)])
    for i, s in enumerate(element_sections(params, material)):
        pid, w = i + 1, [float(v) for v in s["offset"]]
        a_props = [float(s[k]) for k in ("A", "I1", "I2", "I12", "J")] + [0.0]
        lines += card_lines("PBEAM", [pid, MID, *a_props,
                                      *[0.0] * 8,
                                      "YESA", 1.0, *a_props,
                                      float(s["K1"]), float(s["K2"]), None, None, None, None, None, None,
                                      0.0, 0.0, 0.0, 0.0, float(s["N1"]), float(s["N2"]), float(s["N1"]),
                                      float(s["N2"])])
        lines += card_lines("CBEAM", [i + 1, pid, GRID_ID0 + i, GRID_ID0 + i + 1, *map(float, s["v"]), "GGG",
                                      None, None, *w, *w])
    for j, (k, m, x, J) in enumerate(lumped_masses(params)):
        lines += card_lines("CONM2", [CONM2_ID0 + j, GRID_ID0 + k, 0, float(m), *map(float, x), None,
                                      float(J[0, 0]), float(-J[1, 0]), float(J[1, 1]), float(-J[2, 0]),
                                      float(-J[2, 1]), float(J[2, 2])])
    lines += card_lines("SPC1", [SPC_ID, 123456, GRID_ID0])
    return lines


# --------------------------------------------------------------------------- aero cards
def _spline_frame(r0, r1) -> tuple[np.ndarray, np.ndarray]:
    """CORD2R points B (on z) and C (in x-z) of a frame at r0 with y along r1 - r0, z up."""
    ey = (r1 - r0) / np.linalg.norm(r1 - r0)
    ez = np.array([0.0, 0.0, 1.0]) - ey[2] * ey
    ez /= np.linalg.norm(ez)
    ex = np.cross(ey, ez)
    return r0 + ez, r0 + ex


def aero_cards(params, panels) -> list[str]:
    """CAERO1, PAERO1, CORD2R, SET1, SPLINE2 lines of the ``panels`` (LiftingPanel) on the beam.

    Parameters
    ----------
    params : dict
        Beam parameters (``param_specs`` names of :mod:`wingmdao.beam.residual`).
    panels : sequence of LiftingPanel
        The lifting panels.

    Returns
    -------
    list of str
        The bulk-data lines.
    """
    r = np.asarray(params["node_positions"], float)
    lines = card_lines("PAERO1", [PID_AERO])
    for j, p in enumerate(panels):
        eid = CAERO_ID0 + j * CAERO_STEP
        if p.nspan * p.nchord >= CAERO_STEP:
            raise ValueError(f"panel {j}: {p.nspan} x {p.nchord} boxes; at most {CAERO_STEP - 1} per panel")
        lines += card_lines("CAERO1", [eid, PID_AERO, None, int(p.nspan), int(p.nchord), None, None, 1,
                                       *map(float, p.root_le), float(p.root_chord),
                                       *map(float, p.tip_le), float(p.tip_chord)])
        nodes = list(p.nodes)
        b, c = _spline_frame(r[nodes[0]], r[nodes[-1]])
        lines += card_lines("CORD2R", [CORD_ID0 + j, 0, *map(float, r[nodes[0]]), *map(float, b), *map(float, c)])
        lines += card_lines("SET1", [SPLINE_ID0 + j, *[GRID_ID0 + k for k in nodes]])
        lines += card_lines("SPLINE2", [SPLINE_ID0 + j, eid, eid, eid + p.nspan * p.nchord - 1, SPLINE_ID0 + j,
                                        0.0, 1.0, CORD_ID0 + j, 0.0, 0.0])
    return lines


def von_karman_psd_hz(f_hz, airspeed, scale_m, sigma=1.0) -> np.ndarray:
    """One-sided von Karman vertical-gust PSD in (m/s)^2/Hz at ``f_hz`` (14 CFR 25.341(b)(2) with
    Omega = 2 pi f / V): sigma^2 (2 L / V) (1 + 8/3 (1.339 L Omega)^2) / (1 + (1.339 L Omega)^2)^(11/6).

    Parameters
    ----------
    f_hz : float or array_like
        Frequency (Hz).
    airspeed : float
        True airspeed V (m/s).
    scale_m : float
        Scale length L (m).
    sigma : float, optional
        Gust intensity (m/s, root mean square).

    Returns
    -------
    numpy.ndarray
        PSD ((m/s)^2/Hz).
    """
    x2 = (1.339 * scale_m * 2.0 * np.pi * np.asarray(f_hz, float) / airspeed) ** 2
    return sigma**2 * 2.0 * scale_m / airspeed * (1.0 + 8.0 / 3.0 * x2) / (1.0 + x2) ** (11.0 / 6.0)


def flight_cards(flight: FlightData, panels, modes: int) -> list[str]:
    """AERO, AEROS, MKAERO1, EIGRL, FLFACT, FLUTTER, GUST (+ RLOAD1, TABLED1, DAREA, FREQ1, RANDPS,
    TABRND1), AESTAT and TRIM lines.

    Parameters
    ----------
    flight : FlightData
        The flight data.
    panels : sequence of LiftingPanel
        The lifting panels.
    modes : int
        Modes of EIGRL.

    Returns
    -------
    list of str
        The bulk-data lines.
    """
    f = flight
    lines = card_lines("AERO", [0, float(f.gust_velocity), float(f.reference_chord), float(f.gust_density), 1])
    lines += card_lines("AEROS", [0, 0, float(f.reference_chord), float(f.full_span), float(f.half_area), 1])
    machs = sorted({round(float(f.gust_mach), 4), round(float(f.flutter_mach), 4), round(float(f.trim_mach), 4)})
    lines += card_lines("MKAERO1", [*machs, *[None] * (8 - len(machs)), *map(float, f.reduced_frequencies)])
    lines += card_lines("EIGRL", [EIGRL_ID, None, None, int(modes)])
    lines += card_lines("FLFACT", [FLFACT_DENSITY, float(f.flutter_density / f.gust_density)])
    lines += card_lines("FLFACT", [FLFACT_MACH, float(f.flutter_mach)])
    lines += card_lines("FLFACT", [FLFACT_VELOCITY, *map(float, f.flutter_velocities)])
    lines += card_lines("FLUTTER", [FLUTTER_ID, "PK", FLFACT_DENSITY, FLFACT_MACH, FLFACT_VELOCITY, "L", int(modes)])
    lines += card_lines("GUST", [GUST_ID, RLOAD_ID, float(1.0 / f.gust_velocity), 0.0, float(f.gust_velocity)])
    lines += card_lines("RLOAD1", [RLOAD_ID, DAREA_ID, None, None, TABLED_ID])
    f1, df, ndf = f.frequency_hz
    lines += card_lines("TABLED1", [TABLED_ID, None, None, None, None, None, None, None,
                                    0.0, 1.0, float(f1 + df * (ndf + 1)), 1.0, "ENDT"])
    lines += card_lines("DAREA", [DAREA_ID, GRID_ID0, 3, 0.0])
    lines += card_lines("FREQ1", [FREQ_ID, float(f1), float(df), int(ndf)])
    lines += card_lines("RANDPS", [RANDOM_ID, 1, 1, 1.0, 0.0, TABRND_ID])
    psd = von_karman_psd_hz(f.psd_frequencies_hz, f.gust_velocity, f.turbulence_scale_m)
    pairs = [float(v) for fp in zip(f.psd_frequencies_hz, psd) for v in fp]
    lines += card_lines("TABRND1", [TABRND_ID, "LOG", "LOG", None, None, None, None, None, *pairs, "ENDT"])
    lines += card_lines("AESTAT", [AESTAT_ID, "ANGLEA"])
    lines += card_lines("TRIM", [TRIM_ID, float(f.trim_mach), float(f.trim_dynamic_pressure), "ANGLEA",
                                 float(np.radians(f.trim_alpha_deg))])
    return lines


def case_control(sol: int, title: str) -> list[str]:
    """Executive and case control of ``sol`` (144 trim, 145 flutter, 146 gust frequency response).

    Parameters
    ----------
    sol : {144, 145, 146}
        Solution sequence.
    title : str
        Title line.

    Returns
    -------
    list of str
        The executive and case control lines.
    """
    if sol not in SOLUTIONS:
        raise ValueError(f"--sol = {sol}; allowed: {', '.join(map(str, SOLUTIONS))}")
    head = [f"$ {title}", "$ units SI (m, kg, s, N); half model, symmetric about the x-z plane",
            f"SOL {sol}", "CEND", f"TITLE = {title}", "ECHO = NONE", f"SPC = {SPC_ID}", "DISPLACEMENT = ALL"]
    body = {144: [f"TRIM = {TRIM_ID}", "AEROF = ALL", "APRES = ALL", "FORCE = ALL"],
            145: [f"METHOD = {EIGRL_ID}", f"FMETHOD = {FLUTTER_ID}"],
            146: [f"METHOD = {EIGRL_ID}", f"FREQ = {FREQ_ID}", f"GUST = {GUST_ID}", f"DLOAD = {RLOAD_ID}",
                  f"RANDOM = {RANDOM_ID}", "FORCE(PSDF) = ALL"]}[sol]
    return head + ["SUBCASE 1", *[f"  {b}" for b in body], "BEGIN BULK"]


def aeroelastic_deck(params, material, panels, flight: FlightData, *, sol: int = 146, modes: int = 10,
                     title: str = "wingmdao aeroelastic beam model") -> str:
    """The deck text (see the module docstring): executive and case control of ``sol``, the beam
    ``params`` with ``material``'s E and G, the lifting ``panels`` and the ``flight`` cards.

    Parameters
    ----------
    params : dict
        Beam parameters (``param_specs`` names of :mod:`wingmdao.beam.residual`).
    material : Material
        Isotropic material whose E and G the MAT1 card carries.
    panels : sequence of LiftingPanel
        The lifting panels.
    flight : FlightData
        The flight data.
    sol : {144, 145, 146}, optional
        Solution sequence.
    modes : int, optional
        Modes of EIGRL.
    title : str, optional
        Title line.

    Returns
    -------
    str
        The deck text.
    """
    if not (isinstance(modes, (int, np.integer)) and 1 <= modes <= 200):
        raise ValueError(f"--modes = {modes}; allowed range 1..200")
    lines = case_control(sol, title)
    lines += card_lines("PARAM", ["WTMASS", 1.0]) + card_lines("PARAM", ["GRDPNT", 0])
    lines += beam_cards(params, material)
    lines += aero_cards(params, panels)
    lines += flight_cards(flight, panels, modes)
    return "\n".join(lines + ["ENDDATA"]) + "\n"
