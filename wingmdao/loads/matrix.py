"""The loads office's matrix: altitudes x speeds x mass cases, every load case, screened (docs/loads-matrix.md).

A loads engineer never runs one flight point. The matrix file (YAML, :func:`read_matrix`) names

* ``altitudes_ft``: the altitudes (ft, inside the 25.341 table, 0-60,000 ft);
* ``speeds``: ``V_C`` and/or ``V_D``, each as ``mach`` or ``eas_m_s`` / ``eas_kt`` (the same
  equivalent airspeed or Mach number at every altitude);
* ``mass_cases``: weight (``weight_lb`` or ``weight_kg``), CG (``cg_mac``, a fraction of the mean
  aerodynamic chord) and the wing fuel fraction (``fuel_fraction`` of ``aircraft.wing_fuel_kg``);

and :func:`expand` turns every (altitude, speed, mass case) point into load cases:

* discrete gusts, 25.341(a): every gradient H of ``gusts.gradients_ft`` (default ten, log-spaced
  30-350 ft), up and down; U_ds = U_ref F_g (H/350 ft)^(1/6), U_ref halved at V_D
  (:mod:`wingmdao.loads.gust`);
* continuous turbulence, 25.341(b): P_1g +/- U_sigma A-bar (:mod:`wingmdao.loads.turbulence`),
  U_sigma = U_sigma_ref F_g at V_C, half of it at V_D;
* the symmetric maneuvers, 25.337: ``maneuvers.load_factors`` (default n_max of the mass case's
  weight and -1.0).

Model (``model.aero``): ``strip`` (default) applies quasi-steady strip-theory loads to the clamped
structural beam, the loads of ``wingmdao size CASE --aero strip``; ``coupled`` uses the aeroelastic
beam of ``wingmdao gust`` (unsteady strip theory, Wagner and Kuessner lags, trimmed 1 g, root
clamped or, ``model.plunge: free``, free in plunge with the body mass L_w / g less both half
wings), its quasi-steady lift per ``model.aero_theory``: ``strip`` (default, the 2-D slope),
``lifting-line`` or ``vlm`` (the vortex lattice of the planform at each flight state's Mach number,
:func:`wingmdao.aero.system.three_dimensional_parameters`; the lags stay 2-D per station). The 1 g spanload is the Schrenk distribution of the wing's share of the weight,
L_w = n W / (1 + (x_cg - x_ac) c_mac / l_t) (the horizontal tail, arm ``aircraft.tail_arm_m`` from
the CG, balances the wing lift's moment about the CG; the wing's own pitching moment is
neglected), so a forward CG loads the wing more. Wing fuel is added to the beam's mass per
length, distributed along ``aircraft.fuel_span`` in proportion to the box's enclosed area w h (the
tank volume), on the beam axis (its rotary inertia is neglected). Gusts are marched in time
(BDF2); turbulence uses the frequency response of the same model linearised about its 1 g state
(:mod:`wingmdao.loads.turbulence_analysis`) with the structural damping ``model.damping_ratio``
(the quasi-steady strip gust lift carries no aerodynamic damping, so with ``strip`` the resonant
peaks are bounded by the structure alone and A-bar is conservative); maneuvers are static solves
of the Schrenk spanload of L_w at n with inertia relief n g, with either model.

Every case gives, at every beam station and for each of the six csn internal loads
(:data:`COMPONENTS`), its maximum and minimum (over time for gusts; P_1g +/- U_sigma A-bar for
turbulence) and the wing's loads at the instants of those extremes (the *snapshots*: for
turbulence the correlated loads rho_jk U_sigma A-bar_k about 1 g), from which
:mod:`wingmdao.loads.cards` writes the stress office's nodal loads. :func:`screen` finds per
station and component the critical case (max and min) and the envelopes. Cases run serially or
split over MPI ranks (:func:`evaluate_cases`, :func:`wingmdao.parallel.assign_cases`).
"""

from __future__ import annotations

import math
import os
import sys
import time as _time
from dataclasses import dataclass, field

import numpy as np

from wingmdao.aero.gust_response import GustFlight, coupled_gust_response
from wingmdao.aero.plunge import body_mass, half_wing_mass
from wingmdao.aero.system import AERO_THEORY_CHOICES, aero_parameters, three_dimensional_parameters
from wingmdao.beam.modes import natural_frequencies
from wingmdao.beam.residual import StrainRateDamping
from wingmdao.beam.static import beam_forcing, cached_beam_system, march_line_loads
from wingmdao.loads import turbulence as tb
from wingmdao.loads.atmosphere import FT, G0, KNOT as KT, LB, density, eas_to_tas, mach_to_tas, speed_of_sound
from wingmdao.loads.gust import (ALTITUDE_RANGE_FT, GRADIENT_RANGE_FT, design_gust_velocity_eas,
                                 flight_profile_alleviation_factor, gust_line_loads)
from wingmdao.loads.gust_set import log_spaced_gradients_ft
from wingmdao.loads.maneuver import limit_load_factors, maneuver_line_loads
from wingmdao.loads.turbulence_analysis import coupled_gust_model, strip_gust_model
from wingmdao.stability.frequency import LOAD_NAMES, LOAD_UNITS, frequency_grid, frequency_response, spectral_integral
from wingmdao.timemarch.bdf import solve_static
from wingmdao.timemarch.system import layout, pack
from wingmdao.cases.planform import wing_geometry
from wingmdao.parallel import assign_cases

#: the six internal loads of every station, csn frame (c chordwise, s along the beam, n normal)
COMPONENTS = LOAD_NAMES
COMPONENT_UNITS = LOAD_UNITS
#: the three a stress engineer screens first: vertical shear F_n, bending M_c, torsion M_s
PRIMARY = ("vertical_shear", "bending_moment", "torsion")
KINDS = ("gust", "turbulence", "maneuver")
SPEEDS = ("V_C", "V_D")


_TOP_KEYS = {"altitudes_ft": "list of altitudes (ft)", "speeds": "V_C and/or V_D: {mach: M} or {eas_m_s: V}",
             "mass_cases": "list of {name, weight_lb|weight_kg, cg_mac, fuel_fraction}",
             "aircraft": "{tail_arm_m, wing_fuel_kg, fuel_span, ac_mac}", "gusts": "{gradients_ft|gradient_count, signs}",
             "turbulence": "true or false", "maneuvers": "{load_factors}", "model": "{num_nodes, dt_s, ...}",
             "stations": "monitoring station indices"}
_REQUIRED = ("altitudes_ft", "speeds", "mass_cases", "aircraft")
_SPEED_KEYS = {"mach", "eas_m_s", "eas_kt"}
_MASS_KEYS = {"name", "weight_lb", "weight_kg", "cg_mac", "fuel_fraction"}
_AIRCRAFT_KEYS = {"tail_arm_m", "wing_fuel_kg", "fuel_span", "ac_mac"}
_GUST_KEYS = {"gradients_ft", "gradient_count", "signs"}
_MANEUVER_KEYS = {"load_factors"}
_MODEL_DEFAULTS = {"aero": "strip", "aero_theory": "strip", "plunge": "clamped", "num_nodes": 20, "dt_s": 0.02, "gust_start_s": 0.2, "settle_s": 1.0, "damping_ratio": 0.02,
                   "damping_frequency_hz": None, "f_max_hz": 40.0, "grid_points": 161}
_MAX_CASES = 100000


@dataclass(frozen=True)
class Speed:
    """A matrix speed: ``label`` V_C or V_D, given as ``mach`` or as ``eas_m_s`` (one of them).

    Parameters
    ----------
    label : {"V_C", "V_D"}
        Speed name.
    mach : float or None, optional
        Mach number (-).
    eas_m_s : float or None, optional
        Equivalent airspeed (m/s).
    """

    label: str
    mach: float | None = None
    eas_m_s: float | None = None

    def tas(self, altitude_m: float) -> float:
        """True airspeed (m/s) at ``altitude_m``.

        Parameters
        ----------
        altitude_m : float
            Altitude (m).

        Returns
        -------
        float
            True airspeed (m/s).
        """
        if self.mach is not None:
            return float(mach_to_tas(self.mach, altitude_m))
        return float(eas_to_tas(self.eas_m_s, altitude_m))


@dataclass(frozen=True)
class MassCase:
    """A mass case: ``weight_n`` (N), CG ``cg_mac`` (fraction of the MAC), wing ``fuel_fraction``.

    Parameters
    ----------
    name : str
        Mass case name.
    weight_n : float
        Aircraft weight (N).
    cg_mac : float
        CG position, fraction of the mean aerodynamic chord (-).
    fuel_fraction : float
        Wing fuel over its capacity (-).
    """

    name: str
    weight_n: float
    cg_mac: float
    fuel_fraction: float

    @property
    def weight_lb(self) -> float:
        return self.weight_n / (LB * G0)


@dataclass(frozen=True)
class LoadsMatrix:
    """A checked matrix file (:func:`read_matrix`); lengths SI unless the name says ft.

    Parameters
    ----------
    altitudes_ft : tuple
        Altitudes (ft).
    speeds : tuple of Speed
        Speeds.
    mass_cases : tuple of MassCase
        Mass cases.
    tail_arm_m : float
        Tail arm l_t (m).
    wing_fuel_kg : float, optional
        Wing fuel capacity of the aircraft (kg).
    fuel_span : tuple, optional
        Fuel tank span range, fractions of the semi-span (-).
    ac_mac : float, optional
        Aerodynamic centre, fraction of the MAC (-).
    gradients_ft : tuple, optional
        Gust gradients H (ft).
    signs : tuple, optional
        Gust directions (+1 up, -1 down).
    turbulence : bool, optional
        Include 25.341(b) continuous turbulence.
    load_factors : tuple or None, optional
        Maneuver load factors; None for the 25.337 limits.
    model : dict, optional
        Loads model settings (aero, plunge, mesh, time step, damping, frequency grid).
    stations : tuple or None, optional
        Monitoring stations; None for root, mid-span and 3/4 span.
    source : str, optional
        Text of the matrix file.
    """

    altitudes_ft: tuple
    speeds: tuple
    mass_cases: tuple
    tail_arm_m: float
    wing_fuel_kg: float = 0.0
    fuel_span: tuple = (0.0, 0.7)
    ac_mac: float = 0.25
    gradients_ft: tuple = tuple(float(h) for h in log_spaced_gradients_ft(10))
    signs: tuple = (1, -1)
    turbulence: bool = True
    load_factors: tuple | None = None
    model: dict = field(default_factory=lambda: dict(_MODEL_DEFAULTS))
    stations: tuple | None = None
    source: str = ""

    @property
    def num_nodes(self) -> int:
        return int(self.model["num_nodes"])

    def monitoring_stations(self) -> list:
        """The stations reported in the command's JSON: the given ones, else root, mid-span and 3/4 span."""
        n = self.num_nodes
        return list(self.stations) if self.stations is not None else sorted({0, n // 2, (3 * n) // 4})


@dataclass(frozen=True)
class MatrixCase:
    """One load case of the matrix; ``gradient_ft``, ``sign`` for gusts, ``load_factor`` for maneuvers.

    Parameters
    ----------
    index : int
        Position in the case table.
    name : str
        Case name.
    kind : {"gust", "turbulence", "maneuver"}
        Load case kind.
    altitude_ft : float
        Altitude (ft).
    speed : str
        Speed label.
    mass : str
        Mass case name.
    gradient_ft : float, optional
        Gust gradient H (ft; NaN when not a gust).
    sign : int, optional
        Gust direction (+1, -1; 0 when not a gust).
    load_factor : float, optional
        Maneuver load factor (NaN when not a maneuver).
    num_times : int, optional
        Time steps of the case.
    """

    index: int
    name: str
    kind: str
    altitude_ft: float
    speed: str
    mass: str
    gradient_ft: float = float("nan")
    sign: int = 0
    load_factor: float = float("nan")
    num_times: int = 1  # a cost estimate for the split over MPI ranks (time steps or frequencies)


# ----------------------------------------------------------------------------------------- the file
def _where(path):
    return f"--matrix {path!r}: " if path else "matrix: "


def _number(value, what, lo=-math.inf, hi=math.inf, lo_open=False, hi_open=False, unit=""):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"{what} = {value!r}; allowed a finite number")
    v = float(value)
    ok = (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi)
    if not ok:
        u = f" {unit}" if unit else ""
        raise ValueError(f"{what} = {value!r}{u}; allowed range {'(' if lo_open else '['}{lo:g}, {hi:g}"
                         f"{')' if hi_open or math.isinf(hi) else ']'}{u}")
    return v


def _mapping(value, what, keys, required=()):
    if not isinstance(value, dict):
        raise ValueError(f"{what} must be a mapping with keys {sorted(keys)}, got {value!r}")
    unknown = sorted(set(value) - set(keys))
    if unknown:
        raise ValueError(f"{what}: unknown key {unknown[0]!r}; allowed {sorted(keys)}")
    missing = [k for k in required if k not in value]
    if missing:
        raise ValueError(f"{what}: missing key {missing[0]!r}")
    return value


def _list(value, what):
    if not isinstance(value, list) or not value:
        raise ValueError(f"{what} must be a non-empty list, got {value!r}")
    return value


def _speeds(d):
    _mapping(d, "speeds", SPEEDS)
    if not d:
        raise ValueError(f"speeds: empty; give V_C and/or V_D ({sorted(_SPEED_KEYS)})")
    out = []
    for label in SPEEDS:
        if label not in d:
            continue
        s = _mapping(d[label], f"speeds.{label}", _SPEED_KEYS)
        if len(s) != 1:
            raise ValueError(f"speeds.{label}: give exactly one of {sorted(_SPEED_KEYS)}, got {sorted(s)}")
        (key, value), = s.items()
        if key == "mach":
            out.append(Speed(label, mach=_number(value, f"speeds.{label}.mach", 0.0, 0.85, lo_open=True, hi_open=True)))
        else:
            hi = 400.0 if key == "eas_m_s" else 400.0 / KT
            v = _number(value, f"speeds.{label}.{key}", 0.0, hi, lo_open=True)
            out.append(Speed(label, eas_m_s=v * (KT if key == "eas_kt" else 1.0)))
    return tuple(out)


def _mass_cases(items):
    out, names = [], set()
    for i, m in enumerate(_list(items, "mass_cases")):
        what = f"mass_cases[{i}]"
        _mapping(m, what, _MASS_KEYS, required=("name", "cg_mac"))
        name = m["name"]
        if not (isinstance(name, str) and name.isidentifier()):
            raise ValueError(f"{what}.name = {name!r}; allowed a name of letters, digits and _ (used in case names)")
        if name in names:
            raise ValueError(f"{what}.name = {name!r}: repeated; every mass case needs its own name")
        names.add(name)
        if ("weight_lb" in m) == ("weight_kg" in m):
            raise ValueError(f"{what} ({name}): give exactly one of weight_lb and weight_kg")
        if "weight_lb" in m:
            w = _number(m["weight_lb"], f"{what}.weight_lb", 0.0, lo_open=True, unit="lb") * LB * G0
        else:
            w = _number(m["weight_kg"], f"{what}.weight_kg", 0.0, lo_open=True, unit="kg") * G0
        cg = m["cg_mac"]
        if isinstance(cg, (int, float)) and not isinstance(cg, bool) and math.isfinite(cg) and not 0.0 <= cg <= 1.0:
            raise ValueError(f"{what}.cg_mac = {cg!r}: the CG is outside the chord; allowed range [0, 1] "
                             "(a fraction of the mean aerodynamic chord from its leading edge)")
        cg = _number(cg, f"{what}.cg_mac", 0.0, 1.0)
        fuel = _number(m.get("fuel_fraction", 0.0), f"{what}.fuel_fraction", 0.0, 1.0)
        out.append(MassCase(name, w, cg, fuel))
    return tuple(out)


def _altitudes(items):
    lo, hi = ALTITUDE_RANGE_FT
    out = []
    for i, h in enumerate(_list(items, "altitudes_ft")):
        if isinstance(h, (int, float)) and not isinstance(h, bool) and math.isfinite(h) and not lo <= h <= hi:
            raise ValueError(f"altitudes_ft[{i}] = {h!r} ft: outside the atmosphere and 25.341 tables; allowed range "
                             f"[{lo:g}, {hi:g}] ft")
        out.append(_number(h, f"altitudes_ft[{i}]", lo, hi, unit="ft"))
    if len(set(out)) != len(out):
        raise ValueError(f"altitudes_ft: repeated values in {out}")
    return tuple(out)


def _gusts(d):
    _mapping(d, "gusts", _GUST_KEYS)
    if "gradients_ft" in d and "gradient_count" in d:
        raise ValueError("gusts: give gradients_ft or gradient_count, not both")
    if "gradients_ft" in d:
        lo, hi = GRADIENT_RANGE_FT
        grads = tuple(_number(h, f"gusts.gradients_ft[{i}]", lo, hi, unit="ft")
                      for i, h in enumerate(_list(d["gradients_ft"], "gusts.gradients_ft")))
        if len(set(grads)) != len(grads):
            raise ValueError(f"gusts.gradients_ft: repeated values in {list(grads)}")
    elif "gradient_count" in d:
        c = d["gradient_count"]
        if isinstance(c, bool) or not isinstance(c, int) or not 0 <= c <= 1000:
            raise ValueError(f"gusts.gradient_count = {c!r}; allowed an integer in [0, 1000] (0: no discrete gusts)")
        grads = tuple(float(h) for h in log_spaced_gradients_ft(c)) if c else ()
    else:
        grads = LoadsMatrix.gradients_ft
    signs = d.get("signs", ["up", "down"])
    table = {"up": 1, "down": -1}
    if not isinstance(signs, list) or not signs or any(s not in table for s in signs) or len(set(signs)) != len(signs):
        raise ValueError(f"gusts.signs = {signs!r}; allowed a list of 'up' and/or 'down'")
    return grads, tuple(table[s] for s in signs)


def _model(d):
    _mapping(d, "model", _MODEL_DEFAULTS)
    m = {**_MODEL_DEFAULTS, **d}
    if m["aero"] not in ("strip", "coupled"):
        raise ValueError(f"model.aero = {m['aero']!r}; allowed 'strip' or 'coupled'")
    if m["aero_theory"] not in AERO_THEORY_CHOICES:
        raise ValueError(f"model.aero_theory = {m['aero_theory']!r}; allowed {', '.join(map(repr, AERO_THEORY_CHOICES))}")
    if m["aero_theory"] != "strip" and m["aero"] != "coupled":
        raise ValueError(f"model.aero_theory = {m['aero_theory']!r} needs model.aero = 'coupled' (the strip loads "
                         "are 2-D strips on the rigid wing)")
    if m["plunge"] not in ("clamped", "free"):
        raise ValueError(f"model.plunge = {m['plunge']!r}; allowed 'clamped' or 'free'")
    if m["plunge"] == "free" and m["aero"] != "coupled":
        raise ValueError("model.plunge = 'free' needs model.aero = 'coupled' (the strip loads act on a clamped wing)")
    n = m["num_nodes"]
    if isinstance(n, bool) or not isinstance(n, int) or not 3 <= n <= 200:
        raise ValueError(f"model.num_nodes = {n!r}; allowed an integer in [3, 200]")
    _number(m["dt_s"], "model.dt_s", 0.0, 0.5, lo_open=True, unit="s")
    _number(m["gust_start_s"], "model.gust_start_s", 0.0, 10.0, unit="s")
    _number(m["settle_s"], "model.settle_s", 0.0, 60.0, unit="s")
    _number(m["damping_ratio"], "model.damping_ratio", 0.0, 1.0, lo_open=True, hi_open=True)
    if m["damping_frequency_hz"] is not None:
        _number(m["damping_frequency_hz"], "model.damping_frequency_hz", 0.0, lo_open=True, unit="Hz")
    _number(m["f_max_hz"], "model.f_max_hz", 0.1, 1000.0, unit="Hz")
    g = m["grid_points"]
    if isinstance(g, bool) or not isinstance(g, int) or not 11 <= g <= 5001:
        raise ValueError(f"model.grid_points = {g!r}; allowed an integer in [11, 5001]")
    return m


def matrix_from_dict(d, path: str | None = None) -> LoadsMatrix:
    """A :class:`LoadsMatrix` from the parsed file; ValueError (one line, naming the file and key) on bad input.

    Parameters
    ----------
    d : dict
        The parsed matrix file.
    path : str or None, optional
        File named in errors.

    Returns
    -------
    LoadsMatrix
        The checked matrix.
    """
    try:
        if not isinstance(d, dict):
            raise ValueError(f"the file must be a mapping with keys {sorted(_TOP_KEYS)}, got {type(d).__name__}")
        _mapping(d, "top level", _TOP_KEYS, required=_REQUIRED)
        alts, speeds, masses = _altitudes(d["altitudes_ft"]), _speeds(d["speeds"]), _mass_cases(d["mass_cases"])
        ac = _mapping(d["aircraft"], "aircraft", _AIRCRAFT_KEYS, required=("tail_arm_m",))
        tail = _number(ac["tail_arm_m"], "aircraft.tail_arm_m", 0.0, lo_open=True, unit="m")
        fuel = _number(ac.get("wing_fuel_kg", 0.0), "aircraft.wing_fuel_kg", 0.0, unit="kg")
        span = ac.get("fuel_span", [0.0, 0.7])
        if not (isinstance(span, list) and len(span) == 2):
            raise ValueError(f"aircraft.fuel_span = {span!r}; allowed [start, end], fractions of the semi-span")
        span = tuple(_number(s, f"aircraft.fuel_span[{i}]", 0.0, 1.0) for i, s in enumerate(span))
        if not span[0] < span[1]:
            raise ValueError(f"aircraft.fuel_span = {list(span)}; need start < end (fractions of the semi-span)")
        ac_mac = _number(ac.get("ac_mac", 0.25), "aircraft.ac_mac", 0.0, 1.0)
        grads, signs = _gusts(d.get("gusts", {}))
        turb = d.get("turbulence", True)
        if not isinstance(turb, bool):
            raise ValueError(f"turbulence = {turb!r}; allowed true or false")
        man = _mapping(d.get("maneuvers", {}), "maneuvers", _MANEUVER_KEYS)
        nz = None
        if "load_factors" in man:
            lf = man["load_factors"]
            if not isinstance(lf, list):
                raise ValueError(f"maneuvers.load_factors = {lf!r}; allowed a list (empty: no maneuvers)")
            nz = tuple(_number(v, f"maneuvers.load_factors[{i}]", -4.0, 6.0) for i, v in enumerate(lf))
        model = _model(d.get("model", {}))
        stations = d.get("stations")
        if stations is not None:
            n = model["num_nodes"]
            if not isinstance(stations, list) or not stations or any(
                    isinstance(s, bool) or not isinstance(s, int) or not 0 <= s < n for s in stations):
                raise ValueError(f"stations = {stations!r}; allowed a list of station indices in [0, {n - 1}] "
                                 f"(model.num_nodes = {n})")
            stations = tuple(stations)
        m = LoadsMatrix(alts, speeds, masses, tail, fuel, span, ac_mac, grads, signs, turb, nz, model, stations)
        count = len(expand(m))
        if count == 0:
            raise ValueError("no load cases: give gusts, turbulence or maneuvers")
        if count > _MAX_CASES:
            raise ValueError(f"{count} load cases; allowed at most {_MAX_CASES}")
        return m
    except ValueError as exc:
        raise ValueError(f"{_where(path)}{exc}") from None


def read_matrix(path: str) -> LoadsMatrix:
    """Read and check a matrix file (YAML, PyYAML imported lazily); the file's text is kept in ``source``.

    Parameters
    ----------
    path : str
        YAML matrix file.

    Returns
    -------
    LoadsMatrix
        The checked matrix.
    """
    if not os.path.isfile(path):
        raise ValueError(f"--matrix {path!r} does not exist or is not a file")
    try:
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"--matrix {path!r}: cannot read it ({getattr(exc, 'strerror', None) or exc})") from None
    try:
        import yaml
    except ImportError as exc:  # pragma: no cover - depends on the install
        raise ImportError("matrix files are YAML: pip install pyyaml") from exc
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise ValueError(f"--matrix {path!r}: not valid YAML ({' '.join(str(exc).split())})") from None
    m = matrix_from_dict(data, path)
    return LoadsMatrix(**{**m.__dict__, "source": text})


# ------------------------------------------------------------------------------------ the expansion
def _case_name(h, speed, mass, tail):
    return f"h{h:g}_{speed}_{mass}_{tail}"


def expand(matrix: LoadsMatrix) -> list:
    """Every load case of the matrix, in a fixed order (altitude, speed, mass case, then gusts by
    gradient and sign, turbulence, maneuvers): the order of the database's case table.

    Parameters
    ----------
    matrix : LoadsMatrix
        The matrix.

    Returns
    -------
    list of MatrixCase
        Every load case.
    """
    out = []
    dt = float(matrix.model["dt_s"])
    for h in matrix.altitudes_ft:
        alt = h * FT
        for s in matrix.speeds:
            V = s.tas(alt)
            for m in matrix.mass_cases:
                def add(**kw):
                    out.append(MatrixCase(len(out), altitude_ft=h, speed=s.label, mass=m.name, **kw))

                for H in matrix.gradients_ft:
                    steps = int(math.ceil(gust_duration(matrix, H, V) / dt)) + 1
                    for sign in matrix.signs:
                        add(name=_case_name(h, s.label, m.name, f"gust_H{H:.4g}_{'up' if sign > 0 else 'down'}"),
                            kind="gust", gradient_ft=float(H), sign=sign, num_times=steps)
                if matrix.turbulence:
                    add(name=_case_name(h, s.label, m.name, "turbulence"), kind="turbulence",
                        num_times=int(matrix.model["grid_points"]))
                nz = matrix.load_factors if matrix.load_factors is not None else limit_load_factors(m.weight_lb)
                for n in nz:
                    add(name=_case_name(h, s.label, m.name, f"maneuver_{n:+.3g}g"), kind="maneuver",
                        load_factor=float(n))
    return out


def gust_duration(matrix: LoadsMatrix, gradient_ft: float, airspeed: float) -> float:
    """Marched time of a gust (s): its start, its passage 2 H / V over the wing and ``model.settle_s``.

    Parameters
    ----------
    matrix : LoadsMatrix
        The matrix.
    gradient_ft : float
        Gust gradient H (ft).
    airspeed : float
        True airspeed (m/s).

    Returns
    -------
    float
        Marched time (s).
    """
    return float(matrix.model["gust_start_s"] + 2 * gradient_ft * FT / airspeed + matrix.model["settle_s"])


# ---------------------------------------------------------------------------------------- the model
@dataclass
class WingModel:
    """The wing of a case at the matrix's mesh: geometry, aerodynamic strips, one beam per mass case.

    Parameters
    ----------
    node_positions : array_like
        (n, 3) jig node positions, body axes (m).
    node_euler_angles : array_like
        (n, 3) jig Euler angles of the nodes' csn frames (rad).
    chord : numpy.ndarray
        (n,) strip chords (m).
    axis_fraction : numpy.ndarray
        (n,) beam axis as a fraction of the chord (-).
    semi_span : float
        Semi-span (m).
    fuselage_half_width : float
        Fuselage half-width (m).
    mac : float
        Mean aerodynamic chord (m).
    area : float
        Half-wing area (m^2).
    beams : dict
        Mass case name -> beam parameters.
    damping : StrainRateDamping or None
        Structural damping of the march.
    matrix : LoadsMatrix
        The matrix.
    """

    node_positions: np.ndarray
    node_euler_angles: np.ndarray
    chord: np.ndarray
    axis_fraction: np.ndarray
    semi_span: float
    fuselage_half_width: float
    mac: float
    area: float
    beams: dict  # mass case name -> beam parameter dict
    damping: StrainRateDamping | None
    matrix: LoadsMatrix

    @property
    def num_nodes(self) -> int:
        return self.chord.size


def mean_aerodynamic_chord(chord, node_positions) -> float:
    """c_mac = int c^2 dy / int c dy over the half wing (trapezoid on the nodes).

    Parameters
    ----------
    chord : array_like
        (n,) chords (m).
    node_positions : array_like
        (n, 3) jig node positions, body axes (m).

    Returns
    -------
    float
        c_mac (m).
    """
    y = np.abs(np.asarray(node_positions)[:, 1])
    c = np.asarray(chord, dtype=float)
    return float(np.trapezoid(c * c, y) / np.trapezoid(c, y))


def fuel_mass_per_length(width, height, node_positions, semi_span, fuel_span, half_wing_fuel_kg) -> np.ndarray:
    """Fuel mass per beam length (kg/m) of one half wing: proportional to the box's enclosed area
    w h between the ``fuel_span`` fractions of the semi-span, integrating (trapezoid) to ``half_wing_fuel_kg``.

    Parameters
    ----------
    width, height : array_like
        (n,) box width and height (m).
    node_positions : array_like
        (n, 3) jig node positions, body axes (m).
    semi_span : float
        Semi-span (m).
    fuel_span : tuple
        Tank span range, fractions of the semi-span (-).
    half_wing_fuel_kg : float
        Fuel of one half wing (kg).

    Returns
    -------
    numpy.ndarray
        (n,) fuel mass per beam length (kg/m).
    """
    eta = np.abs(np.asarray(node_positions)[:, 1]) / semi_span
    shape = np.asarray(width) * np.asarray(height) * ((eta >= fuel_span[0] - 1e-12) & (eta <= fuel_span[1] + 1e-12))
    if half_wing_fuel_kg == 0.0:
        return np.zeros_like(shape)
    unit = half_wing_mass(shape, node_positions)[0]
    if unit <= 0:
        raise ValueError(f"aircraft.fuel_span = {list(fuel_span)}: contains fewer than two beam nodes; widen it "
                         "or raise model.num_nodes")
    return shape * (half_wing_fuel_kg / unit)


def build_wing_model(module, matrix: LoadsMatrix, thickness: dict | None = None) -> WingModel:
    """The wing of case ``module`` (its ``flutter_planform``, ``ENGINES``, ``beam_params``) at
    ``matrix.num_nodes`` nodes; ``thickness`` {wall: (n,) m} (default the initial design).

    Parameters
    ----------
    module : module
        The case module.
    matrix : LoadsMatrix
        The matrix.
    thickness : dict or None, optional
        Wall name -> (n,) thicknesses (m); None for the initial design.

    Returns
    -------
    WingModel
        The wing.
    """
    n = matrix.num_nodes
    pf = module.flutter_planform(n)
    geo, chord, frac = wing_geometry(pf, module.ENGINES)
    base = module.beam_params(n, thickness)
    r0 = np.asarray(base["node_positions"], dtype=float)
    beams = {}
    for m in matrix.mass_cases:
        mu_f = fuel_mass_per_length(geo.width, geo.height, r0, pf.semi_span, matrix.fuel_span,
                                    0.5 * m.fuel_fraction * matrix.wing_fuel_kg)
        bp = {k: np.array(v, dtype=float) for k, v in base.items()}
        mu_s = bp["mass_per_length"]
        bp["mass_per_length"] = mu_s + mu_f
        bp["mass_center"] = bp["mass_center"] * (mu_s / (mu_s + mu_f))[:, None]  # fuel on the beam axis
        beams[m.name] = bp
    damping = None
    if matrix.turbulence:
        f1 = matrix.model["damping_frequency_hz"]
        if f1 is None:
            system = cached_beam_system(n)
            f1 = float(natural_frequencies(system, pack(system.param_specs, base),
                                           pack(system.forcing_specs, beam_forcing(n)), count=1)[0])
        damping = StrainRateDamping.from_damping_ratio(float(matrix.model["damping_ratio"]), f1)
    mac = mean_aerodynamic_chord(chord, r0)
    if matrix.tail_arm_m <= mac:
        raise ValueError(f"aircraft.tail_arm_m = {matrix.tail_arm_m:g} m; allowed range ({mac:.3f}, inf) m "
                         "(longer than the mean aerodynamic chord)")
    return WingModel(r0, np.asarray(base["node_euler_angles"], dtype=float), np.asarray(chord, dtype=float),
                     np.asarray(frac, dtype=float), float(pf.semi_span), float(pf.root_rib * pf.semi_span), mac,
                     float(pf.area_ft2 * FT ** 2), beams,
                     damping, matrix)


def wing_lift(model: WingModel, mass: MassCase, load_factor: float = 1.0) -> float:
    """The wing's share of n W (N): n W / (1 + (x_cg - x_ac) c_mac / l_t), the tail balancing the moment.

    Parameters
    ----------
    model : WingModel
        The matrix's wing.
    mass : MassCase
        Its mass case.
    load_factor : float, optional
        Load factor n (-).

    Returns
    -------
    float
        Wing lift (N).
    """
    arm = (mass.cg_mac - model.matrix.ac_mac) * model.mac
    return float(load_factor * mass.weight_n / (1.0 + arm / model.matrix.tail_arm_m))


@dataclass(frozen=True)
class FlightState:
    """Flight condition of a point (SI): TAS, EAS, Mach, density, F_g, U_ref (EAS), U_sigma (TAS).

    Parameters
    ----------
    altitude_m : float
        Altitude (m).
    airspeed : float
        True airspeed (m/s).
    eas : float
        Equivalent airspeed (m/s).
    mach : float
        Mach number (-).
    density : float
        Air density (kg/m^3).
    f_g : float
        Flight profile alleviation factor (-).
    u_sigma : float
        Turbulence intensity U_sigma (m/s TAS).
    """

    altitude_m: float
    airspeed: float
    eas: float
    mach: float
    density: float
    f_g: float
    u_sigma: float


def flight_state(module, altitude_ft: float, speed: Speed) -> FlightState:
    """The flight condition of (altitude, speed) with the case's F_g inputs (``GUST_SET_DEFAULTS``).

    Parameters
    ----------
    module : module
        The case module.
    altitude_ft : float
        Altitude (ft).
    speed : Speed
        The speed.

    Returns
    -------
    FlightState
        The flight condition.
    """
    alt = altitude_ft * FT
    V = speed.tas(alt)
    rho = float(density(alt))
    fg = module.GUST_SET_DEFAULTS
    f_g = flight_profile_alleviation_factor(altitude_ft, fg["z_mo_ft"], fg["mlw_over_mtow"], fg["mzfw_over_mtow"])
    point = tb.continuous_turbulence_intensity(altitude_ft, z_mo_ft=fg["z_mo_ft"], mlw_over_mtow=fg["mlw_over_mtow"],
                                               mzfw_over_mtow=fg["mzfw_over_mtow"])
    u_sigma = point.u_sigma * (0.5 if speed.label == "V_D" else 1.0)  # 25.341(b)(3)(iii)
    return FlightState(alt, V, V * math.sqrt(rho / float(density(0.0))), V / float(speed_of_sound(alt)), rho, f_g,
                       u_sigma)


# ----------------------------------------------------------------------------------- one case's loads
@dataclass
class CaseLoads:
    """Loads of one case, csn frame of each station (N, N m): ``max``/``min`` (n, 6), the wing at the
    instants of the extremes ``snapshots`` (k, n, 6) with their ``snapshot_time`` (k,) s (NaN when
    not an instant: turbulence, maneuver), ``max_snapshot``/``min_snapshot`` (n, 6) indices into
    them, ``intensity`` (U_ds EAS or U_sigma TAS, m/s; NaN for maneuvers), ``wall_s``.

    Parameters
    ----------
    max, min : numpy.ndarray
        (n, 6) extremes over the case (N, N m).
    snapshots : numpy.ndarray
        (k, n, 6) the wing's loads at the extremes' instants (N, N m).
    snapshot_time : numpy.ndarray
        (k,) their times (s; NaN when not an instant).
    max_snapshot, min_snapshot : numpy.ndarray
        (n, 6) indices into ``snapshots``.
    intensity : float, optional
        U_ds (EAS) or U_sigma (TAS) (m/s; NaN for maneuvers).
    wall_s : float, optional
        Wall time of the case (s).
    """

    max: np.ndarray
    min: np.ndarray
    snapshots: np.ndarray
    snapshot_time: np.ndarray
    max_snapshot: np.ndarray
    min_snapshot: np.ndarray
    intensity: float = float("nan")
    wall_s: float = 0.0


def csn_loads(states) -> np.ndarray:
    """(…, n, 6) csn internal loads T(theta) F, T(theta) M of beam states (…, n, 18), T of
    :func:`wingmdao.beam.rotations.body_to_csn` (surface sequence) vectorised.

    Parameters
    ----------
    states : array_like
        (..., n, 18) beam states.

    Returns
    -------
    numpy.ndarray
        (..., n, 6) csn internal loads (N, N m).
    """
    X = np.asarray(states, dtype=float)
    phi, tw, psi = X[..., 3], X[..., 4], X[..., 5]
    one, zero = np.ones_like(phi), np.zeros_like(phi)

    def mat(rows):
        return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)

    c, s = np.cos(phi), np.sin(phi)
    rx = mat([[one, zero, zero], [zero, c, s], [zero, -s, c]])
    c, s = np.cos(tw), np.sin(tw)
    ry = mat([[c, zero, -s], [zero, one, zero], [s, zero, c]])
    c, s = np.cos(psi), np.sin(psi)
    rz = mat([[c, s, zero], [-s, c, zero], [zero, zero, one]])
    T = ry @ rz @ rx
    return np.concatenate([np.einsum("...ij,...j->...i", T, X[..., 6:9]),
                           np.einsum("...ij,...j->...i", T, X[..., 9:12])], axis=-1)


def _from_history(L, time):
    """CaseLoads of a load history L (nt, n, 6): extremes over time and the distinct instants."""
    i_max, i_min = L.argmax(axis=0), L.argmin(axis=0)
    steps = np.unique(np.concatenate([i_max.ravel(), i_min.ravel()]))
    where = np.searchsorted(steps, np.arange(L.shape[0]))
    return CaseLoads(L.max(axis=0), L.min(axis=0), L[steps], np.asarray(time, dtype=float)[steps],
                     where[i_max], where[i_min])


def gust_loads(model: WingModel, case: MatrixCase, fs: FlightState, mass: MassCase) -> CaseLoads:
    """A 1 - cos gust from the 1 g level flight, marched on the clamped beam (strip-theory loads).

    Parameters
    ----------
    model : WingModel
        The matrix's wing.
    case : MatrixCase
        The load case.
    fs : FlightState
        Its flight condition.
    mass : MassCase
        Its mass case.

    Returns
    -------
    CaseLoads
        The case's loads.
    """
    mx = model.matrix
    dt = float(mx.model["dt_s"])
    t = dt * np.arange(int(math.ceil(gust_duration(mx, case.gradient_ft, fs.airspeed) / dt)) + 1)
    u_ds = design_gust_velocity_eas(case.gradient_ft, case.altitude_ft, fs.f_g, at_vd=case.speed == "V_D")
    r0, c, xb = model.node_positions, model.chord, model.axis_fraction
    if mx.model["aero"] == "coupled":
        return _coupled_gust_loads(model, case, fs, mass, t, u_ds)
    steady = maneuver_line_loads(r0, c, xb, wing_lift(model, mass), 1.0, semi_span=model.semi_span,
                                 fuselage_half_width=model.fuselage_half_width)
    loads = gust_line_loads(r0, c, xb, t, gust_gradient_m=case.gradient_ft * FT, u_ds_eas=u_ds,
                            airspeed_tas=fs.airspeed, altitude_m=fs.altitude_m, gust_start_time=float(mx.model["gust_start_s"]),
                            direction=case.sign, steady=steady, fuselage_half_width=model.fuselage_half_width)
    hist = march_line_loads(model.beams[mass.name], t, loads.force_per_length, loads.moment_per_length, (0.0, 0.0, -G0))
    out = _from_history(csn_loads(hist.states.reshape(t.size, model.num_nodes, 18)), t)
    out.intensity = float(u_ds)
    return out


def _coupled_gust_loads(model, case, fs, mass, t, u_ds):
    """The gust on the aeroelastic beam (:func:`wingmdao.aero.gust_response.coupled_gust_response`),
    from the trimmed 1 g state, clamped or free in plunge."""
    mx = model.matrix
    bp = model.beams[mass.name]
    lift = wing_lift(model, mass)
    u_tas = u_ds * math.sqrt(float(density(0.0)) / fs.density)
    flight = GustFlight(airspeed=fs.airspeed, density=fs.density, mach=fs.mach, altitude=fs.altitude_m,
                        gradient=case.gradient_ft * FT, u_ds_eas=case.sign * u_ds, u_ds_tas=case.sign * u_tas,
                        weight=lift, gust_start=float(mx.model["gust_start_s"]))
    free = mx.model["plunge"] == "free"
    resp = coupled_gust_response(t, bp, model.chord, model.axis_fraction, _aero(model, fs), flight, area=model.area,
                                 plunge=free, body_mass=_body_mass(model, mass) if free else None,
                                 aero_theory=_residual_theory(model))
    out = _from_history(csn_loads(resp.states), t)
    out.intensity = float(u_ds)
    return out


def _aero(model, fs):
    """The coupled beam's aerodynamic parameters at the flight state: the strips, with
    ``model.aero_theory``'s lifting-line slopes or vortex-lattice influence at the flight Mach number."""
    ap = aero_parameters(model.num_nodes, chord=model.chord, ref_point=model.axis_fraction, airspeed=fs.airspeed,
                         density=fs.density, mach=fs.mach)
    ap.update(three_dimensional_parameters(model.matrix.model["aero_theory"], model.node_positions, model.chord,
                                           model.axis_fraction, fs.mach))
    return ap


def _residual_theory(model):
    """The aeroelastic residual's lift form: ``"vlm"`` (influence matrices) or ``"strip"`` (per-station slopes)."""
    return "vlm" if model.matrix.model["aero_theory"] == "vlm" else "strip"


def _body_mass(model, mass):
    """The aircraft less both wings (kg): the wing's share of the weight over g, less two half wings."""
    bp = model.beams[mass.name]
    return body_mass(wing_lift(model, mass) / G0, half_wing_mass(bp["mass_per_length"], bp["node_positions"])[0])


def maneuver_loads(model: WingModel, case: MatrixCase, mass: MassCase) -> CaseLoads:
    """A steady symmetric maneuver at n: the Schrenk spanload of the wing's share of n W, inertia relief n g.

    Parameters
    ----------
    model : WingModel
        The matrix's wing.
    case : MatrixCase
        The load case.
    mass : MassCase
        Its mass case.

    Returns
    -------
    CaseLoads
        The case's loads.
    """
    n = model.num_nodes
    loads = maneuver_line_loads(model.node_positions, model.chord, model.axis_fraction,
                                wing_lift(model, mass), case.load_factor, semi_span=model.semi_span,
                                fuselage_half_width=model.fuselage_half_width)
    system = cached_beam_system(n)
    ql = layout(system.forcing_specs)
    q = np.zeros(system.n_forcing)
    q[ql["force_per_length"]] = np.asarray(loads.force_per_length).ravel()
    q[ql["moment_per_length"]] = np.asarray(loads.moment_per_length).ravel()
    q[ql["gravity"].start + 2] = -case.load_factor * G0  # gravity and the frame's (n - 1) g
    x, _ = solve_static(system, pack(system.param_specs, model.beams[mass.name]), q,
                        label=f"maneuver {case.name}")
    return _from_history(csn_loads(x.reshape(1, n, 18)), [np.nan])


def turbulence_loads(model: WingModel, case: MatrixCase, fs: FlightState, mass: MassCase) -> CaseLoads:
    """25.341(b): P_1g +/- U_sigma A-bar of every load; the snapshot of each extreme the correlated
    loads P_1g,k +/- U_sigma rho_jk A-bar_k (the point of the equal-probability ellipse where load
    j peaks), rho_jk A-bar_j A-bar_k = int Re(H_j conj H_k) Phi_1.

    Parameters
    ----------
    model : WingModel
        The matrix's wing.
    case : MatrixCase
        The load case.
    fs : FlightState
        Its flight condition.
    mass : MassCase
        Its mass case.

    Returns
    -------
    CaseLoads
        The case's loads.
    """
    mx = model.matrix
    if mx.model["aero"] == "coupled":
        gm = coupled_gust_model(model.beams[mass.name], _aero(model, fs), chord=model.chord,
                                axis_fraction=model.axis_fraction, weight=wing_lift(model, mass),
                                plunge=mx.model["plunge"] == "free", damping=model.damping,
                                aero_theory=_residual_theory(model))
    else:
        gm = strip_gust_model(model.beams[mass.name], chord=model.chord, axis_fraction=model.axis_fraction,
                              weight=wing_lift(model, mass), airspeed=fs.airspeed, density=fs.density,
                              semi_span=model.semi_span, fuselage_half_width=model.fuselage_half_width,
                              damping=model.damping)
    w = frequency_grid(gm.eigenvalues, f_max=float(mx.model["f_max_hz"]), n_base=int(mx.model["grid_points"]))
    H = frequency_response(gm.model, w).outputs["loads"]  # (nw, 6 n)
    p1g = gm.model.outputs["loads"].y0
    phi = tb.von_karman_psd(w, fs.airspeed, 1.0)[:, None]
    cross = np.stack([spectral_integral(w, np.real(H[:, [j]] * np.conj(H)) * phi).value for j in range(H.shape[1])])
    ab = np.sqrt(np.maximum(np.diag(cross), 0.0))
    n = model.num_nodes
    with np.errstate(divide="ignore", invalid="ignore"):
        corr = np.where(ab[:, None] > 0, cross / ab[:, None], 0.0)  # row j: rho_jk A-bar_k
    corr[np.diag_indices_from(corr)] = ab  # rho_jj = 1 exactly: each snapshot holds its own extreme
    us = fs.u_sigma
    snaps = np.concatenate([p1g + us * corr, p1g - us * corr]).reshape(2 * 6 * n, n, 6)
    idx = np.arange(6 * n).reshape(n, 6)
    return CaseLoads((p1g + us * ab).reshape(n, 6), (p1g - us * ab).reshape(n, 6), snaps,
                     np.full(2 * 6 * n, np.nan), idx, idx + 6 * n, intensity=float(us))


def evaluate_case(module, model: WingModel, case: MatrixCase) -> CaseLoads:
    """The loads of one matrix case.

    Parameters
    ----------
    module : module
        The case module.
    model : WingModel
        The matrix's wing.
    case : MatrixCase
        The load case.

    Returns
    -------
    CaseLoads
        The case's loads.
    """
    t0 = _time.perf_counter()
    mass = next(m for m in model.matrix.mass_cases if m.name == case.mass)
    if case.kind == "maneuver":
        out = maneuver_loads(model, case, mass)
    else:
        speed = next(s for s in model.matrix.speeds if s.label == case.speed)
        fs = flight_state(module, case.altitude_ft, speed)
        out = gust_loads(model, case, fs, mass) if case.kind == "gust" else turbulence_loads(model, case, fs, mass)
    out.wall_s = _time.perf_counter() - t0
    return out


def _progress(done, total, t0, stream):
    if stream is None:
        return
    el = _time.perf_counter() - t0
    eta = el / done * (total - done) if done else float("nan")
    print(f"  {done}/{total} cases, {el:.1f} s, about {eta:.0f} s to go", file=stream, flush=True)


def evaluate_cases(module, model: WingModel, cases, *, comm=None, progress=sys.stderr, every: int = 10):
    """Loads of every case: ``({index: CaseLoads}, interrupted)``. With ``comm`` (an MPI
    communicator) the cases are split over its ranks (:func:`wingmdao.parallel.assign_cases`) and
    gathered on every rank. Ctrl-C (KeyboardInterrupt) stops the loop and returns what is done
    with ``interrupted`` True (under MPI every rank receives the signal and reaches the gather).

    Parameters
    ----------
    module : module
        The case module.
    model : WingModel
        The matrix's wing.
    cases : sequence of MatrixCase
        The cases.
    comm : mpi4py.MPI.Comm or None, optional
        Communicator to split the cases over; None for serial.
    progress : file-like, optional
        Stream for progress lines.
    every : int, optional
        Cases between two progress lines.

    Returns
    -------
    tuple
        ({index: CaseLoads}, interrupted).
    """
    cases = list(cases)
    mine = cases if comm is None else [cases[i] for i in assign_cases(cases, comm.size)[comm.rank]]
    results, interrupted = {}, False
    t0 = _time.perf_counter()
    try:
        for k, case in enumerate(mine):
            results[case.index] = evaluate_case(module, model, case)
            if (k + 1) % every == 0 or k + 1 == len(mine):
                _progress(k + 1, len(mine), t0, progress)
    except KeyboardInterrupt:
        interrupted = True
    if comm is not None:
        parts = comm.allgather((results, interrupted))
        results = {k: v for part, _ in parts for k, v in part.items()}
        interrupted = any(flag for _, flag in parts)
    return results, interrupted


# ------------------------------------------------------------------------------------------ screening
@dataclass
class Screening:
    """Per station and component (n, 6): the envelopes ``envelope_max``/``envelope_min`` (N, N m)
    and the critical cases ``max_case``/``min_case`` (case indices).

    Parameters
    ----------
    envelope_max, envelope_min : numpy.ndarray
        (n, 6) envelopes (N, N m).
    max_case, min_case : numpy.ndarray
        (n, 6) critical case indices.
    """

    envelope_max: np.ndarray
    envelope_min: np.ndarray
    max_case: np.ndarray
    min_case: np.ndarray


def screen(loads_max, loads_min, evaluated=None) -> Screening:
    """The critical case (largest maximum, smallest minimum) of every station and component over
    the ``evaluated`` cases (bool (n_case,), default all) of ``loads_max``/``loads_min`` (n_case, n, 6).
    Ties go to the first case in the table.

    Parameters
    ----------
    loads_max, loads_min : numpy.ndarray
        (n_case, n, 6) extremes per case (N, N m).
    evaluated : array_like or None, optional
        (n_case,) bool, the cases that ran; None for all.

    Returns
    -------
    Screening
        Envelopes and critical cases.
    """
    hi, lo = np.asarray(loads_max, dtype=float), np.asarray(loads_min, dtype=float)
    ok = np.ones(hi.shape[0], bool) if evaluated is None else np.asarray(evaluated, bool)
    if not ok.any():
        raise ValueError("screening: no evaluated load case")
    hi = np.where(ok[:, None, None], hi, -np.inf)
    lo = np.where(ok[:, None, None], lo, np.inf)
    i_hi, i_lo = hi.argmax(axis=0), lo.argmin(axis=0)
    return Screening(np.take_along_axis(hi, i_hi[None], 0)[0], np.take_along_axis(lo, i_lo[None], 0)[0], i_hi, i_lo)


def critical_table(cases, screening: Screening, stations, span, components=PRIMARY) -> list:
    """JSON rows of the critical cases at the monitoring ``stations``: one row per station and component.

    Parameters
    ----------
    cases : sequence of MatrixCase
        The case table.
    screening : Screening
        The screening.
    stations : sequence of int
        Monitoring stations.
    span : array_like
        (n,) span coordinate of each station (m).
    components : sequence of str, optional
        csn components reported.

    Returns
    -------
    list of dict
        One row per station and component.
    """
    rows = []
    for i in stations:
        for comp in components:
            j = COMPONENTS.index(comp)
            rows.append({"station": int(i), "span_m": float(span[i]), "component": comp,
                         "unit": COMPONENT_UNITS[j],
                         "max": {"case": cases[int(screening.max_case[i, j])].name,
                                 "value": float(screening.envelope_max[i, j])},
                         "min": {"case": cases[int(screening.min_case[i, j])].name,
                                 "value": float(screening.envelope_min[i, j])}})
    return rows
