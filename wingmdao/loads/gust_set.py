"""A 14 CFR 25.341(a) gust set: every gradient distance, up and down, at several flight points.

25.341(a)(3) asks for "a sufficient number of gust gradient distances in the range 30 feet to
350 feet" at every altitude, speed and weight that matters. A :class:`GustSet` is that product:

    gusts = flight points x gradient distances H x signs (up +1, down -1)

and each gust becomes one load case of the sizing problem with its own KS constraints. Per
flight point (altitude h, speed V_C or V_D, weight)::

    U_ref(h)  25.341(a)(5)(i): 56 ft/s EAS at sea level, 44 at 15 000 ft, 20.86 at 60 000 ft,
              linear in between; (a)(5)(ii): half of it at V_D
    F_g(h)    25.341(a)(6): (F_gz + F_gm)/2 at sea level, F_gz = 1 - Z_mo/250 000 ft,
              F_gm = sqrt(R2 tan(pi R1/4)), R1 = MLW/MTOW, R2 = MZFW/MTOW, linear to 1 at Z_mo
    U_ds      = U_ref F_g (H/350 ft)^(1/6)  25.341(a)(4) (Eq. 5.2 of the dissertation)

The numbers themselves come from :mod:`wingmdao.loads.gust` (one implementation of the
regulation); this module builds, checks and names the set. Source: 14 CFR 25.341(a),
Amendment 25-86 (1996); dissertation Sec. 5.2.1 ("Structural analysis and optimization of
aircraft wings through dimensional reduction", PhD dissertation, Georgia Institute of
Technology, 2021), which ran one gust and called the envelope "a combinatorial problem".

Description format (JSON or YAML, see ``docs/gust-envelope.md``)::

    {"gradients_ft": [30, 60, 120, 350]        # or "gradient_count": 10 (log-spaced 30-350 ft)
     "signs": "both",                          # "up", "down" or "both"
     "z_mo_ft": 25000, "mlw_over_mtow": 0.98, "mzfw_over_mtow": 0.90,
     "flight_points": [{"name": "vc25k", "altitude_ft": 25000, "mach": 0.5, "weight_lb": 41005},
                       {"name": "vd20k", "altitude_ft": 20000, "mach": 0.6, "speed": "VD"}]}
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field, replace

import numpy as np

from wingmdao.loads.gust import (
    ALTITUDE_RANGE_FT,
    GRADIENT_RANGE_FT,
    design_gust_velocity_eas,
    flight_profile_alleviation_factor,
    reference_gust_velocity_eas,
)
from wingmdao.loads.atmosphere import mach_to_tas
from wingmdao.units import FT

SIGNS = {"up": (1,), "down": (-1,), "both": (1, -1)}
_SIGN_NAME = {1: "up", -1: "down"}
_MAX_GUSTS = 1000


def log_spaced_gradients_ft(count: int) -> np.ndarray:
    """``count`` gust gradients H (ft) spaced logarithmically over 30-350 ft, both ends included.

    U_ds ~ H^(1/6) and the gust duration ~ H, so the response changes evenly in log H.

    Parameters
    ----------
    count : int
        Number of gradients (>= 1).

    Returns
    -------
    numpy.ndarray
        Gust gradients (ft).
    """
    if isinstance(count, bool) or int(count) != count or int(count) < 1:
        raise ValueError(f"gradient_count = {count}; allowed: an integer in [1, {_MAX_GUSTS}]")
    count = int(count)
    if count > _MAX_GUSTS:
        raise ValueError(f"gradient_count = {count}; allowed: an integer in [1, {_MAX_GUSTS}]")
    if count == 1:
        return np.array([GRADIENT_RANGE_FT[1]])
    return np.geomspace(*GRADIENT_RANGE_FT, count)


def _check_gradients(values) -> tuple:
    h = np.atleast_1d(np.asarray(values, dtype=float))
    if h.size == 0:
        raise ValueError("gradients_ft: empty; give at least one gust gradient distance in [30, 350] ft")
    lo, hi = GRADIENT_RANGE_FT
    for v in h:
        if not (np.isfinite(v) and lo - 1e-9 <= v <= hi + 1e-9):
            raise ValueError(f"gradients_ft: H = {v:g} ft; allowed range [{lo:g}, {hi:g}] ft "
                             f"(25.341(a)(3)), i.e. [{lo * FT:.3f}, {hi * FT:.3f}] m")
    if np.unique(np.round(h, 6)).size != h.size:
        raise ValueError(f"gradients_ft: repeated values in {h.tolist()}")
    return tuple(float(v) for v in np.clip(h, lo, hi))


@dataclass(frozen=True)
class FlightPoint:
    """Altitude, speed and weight of one gust condition.

    ``mach`` or ``v_tas_m_s`` gives the airspeed; ``speed`` is ``"VC"`` (U_ref from the table)
    or ``"VD"`` (half of it, 25.341(a)(5)(ii)); ``weight_lb`` the aircraft weight (None: the
    case's design weight) for the 1 g level-flight loads the gust starts from (25.341(a)(2)).
    ``u_ref_fps`` overrides the table (e.g. Table 5.3 of the dissertation: 30 ft/s).

    Parameters
    ----------
    altitude_ft : float
        Altitude (ft).
    mach : float or None, optional
        Mach number (-).
    v_tas_m_s : float or None, optional
        True airspeed (m/s).
    weight_lb : float or None, optional
        Aircraft weight (lb); None for the case's design weight.
    speed : {"VC", "VD"}, optional
        Speed of the point.
    name : str, optional
        Point name.
    u_ref_fps : float or None, optional
        Reference gust velocity overriding the table (ft/s EAS).
    """

    altitude_ft: float
    mach: float | None = None
    v_tas_m_s: float | None = None
    weight_lb: float | None = None
    speed: str = "VC"
    name: str = ""
    u_ref_fps: float | None = None

    def __post_init__(self):
        lo, hi = ALTITUDE_RANGE_FT
        h = self.altitude_ft
        if not (isinstance(h, (int, float)) and np.isfinite(h) and lo <= h <= hi):
            raise ValueError(f"flight point {self.name or '?'}: altitude_ft = {h}; allowed range "
                             f"[{lo:g}, {hi:g}] ft (the 25.341(a)(5) U_ref table), i.e. [0, {hi * FT:.0f}] m")
        if (self.mach is None) == (self.v_tas_m_s is None):
            raise ValueError(f"flight point {self.name or '?'}: give exactly one of mach "
                             f"(got {self.mach}) and v_tas_m_s (got {self.v_tas_m_s})")
        if self.mach is not None and not 0.0 < self.mach < 0.85:
            raise ValueError(f"flight point {self.name or '?'}: mach = {self.mach}; allowed range (0, 0.85)")
        if self.v_tas_m_s is not None and not 0.0 < self.v_tas_m_s <= 400.0:
            raise ValueError(f"flight point {self.name or '?'}: v_tas_m_s = {self.v_tas_m_s} m/s; "
                             "allowed range (0, 400] m/s")
        if self.weight_lb is not None and not (np.isfinite(self.weight_lb) and self.weight_lb > 0):
            raise ValueError(f"flight point {self.name or '?'}: weight_lb = {self.weight_lb} lb; "
                             "allowed range (0, inf) lb")
        if self.speed not in ("VC", "VD"):
            raise ValueError(f"flight point {self.name or '?'}: speed = {self.speed!r}; allowed 'VC' or 'VD'")
        if self.u_ref_fps is not None and not 0.0 < self.u_ref_fps <= 100.0:
            raise ValueError(f"flight point {self.name or '?'}: u_ref_fps = {self.u_ref_fps} ft/s; "
                             "allowed range (0, 100] ft/s")
        if self.name and not self.name.isidentifier():
            raise ValueError(f"flight point name {self.name!r} must be a Python identifier (used in case names)")

    @property
    def altitude_m(self) -> float:
        return float(self.altitude_ft * FT)

    def airspeed_tas(self) -> float:
        """True airspeed (m/s)."""
        if self.v_tas_m_s is not None:
            return float(self.v_tas_m_s)
        return float(mach_to_tas(self.mach, self.altitude_m))


@dataclass(frozen=True)
class Gust:
    """One design gust of the set (SI, plus the regulation's ft and ft/s).

    Parameters
    ----------
    name : str
        Case name.
    flight_point : FlightPoint
        The flight point.
    gradient_ft : float
        Gust gradient H (ft).
    sign : {1, -1}
        Up or down.
    u_ref_fps : float
        Reference gust velocity (ft/s EAS).
    alleviation_factor : float
        F_g (-).
    u_ds_eas : float
        Design gust velocity (m/s EAS).
    """

    name: str
    flight_point: FlightPoint
    gradient_ft: float
    sign: int  # +1 up, -1 down
    u_ref_fps: float  # ft/s EAS (after the V_D halving)
    alleviation_factor: float  # F_g
    u_ds_eas: float  # m/s EAS

    @property
    def gradient_m(self) -> float:
        return self.gradient_ft * FT

    @property
    def u_ds_fps(self) -> float:
        return self.u_ds_eas / FT

    def describe(self) -> str:
        """One line describing the gust: direction, H, U_ds, U_ref, F_g, altitude and speed.

        Returns
        -------
        str
            The description.
        """
        fp = self.flight_point
        spd = f"M {fp.mach:g}" if fp.mach is not None else f"V {fp.v_tas_m_s:g} m/s TAS"
        return (f"1-cos gust {_SIGN_NAME[self.sign]}, H = {self.gradient_ft:.1f} ft, U_ds = "
                f"{self.u_ds_fps:.2f} ft/s EAS (U_ref {self.u_ref_fps:.2f}, F_g {self.alleviation_factor:.4f}), "
                f"{fp.altitude_ft:g} ft, {spd} ({fp.speed})")


@dataclass(frozen=True)
class GustSet:
    """Flight points x gradients x signs; :meth:`gusts` lists them with U_ds per 25.341(a).

    Parameters
    ----------
    flight_points : tuple of FlightPoint
        The flight points.
    gradients_ft : tuple
        Gust gradients (ft).
    signs : tuple, optional
        Directions (+1 up, -1 down).
    z_mo_ft : float, optional
        Maximum operating altitude (ft).
    mlw_over_mtow : float, optional
        Maximum landing over maximum take-off weight (-).
    mzfw_over_mtow : float, optional
        Maximum zero-fuel over maximum take-off weight (-).
    name_prefix : str, optional
        Prefix of the case names.
    extra : dict, optional
        Case-specific keys of the description.
    """

    flight_points: tuple
    gradients_ft: tuple
    signs: tuple = (1, -1)
    z_mo_ft: float = 25000.0
    mlw_over_mtow: float = 1.0
    mzfw_over_mtow: float = 1.0
    name_prefix: str = "gust"
    extra: dict = field(default_factory=dict)

    def __post_init__(self):
        if not self.flight_points:
            raise ValueError("gust set: flight_points is empty; give at least one flight point")
        object.__setattr__(self, "gradients_ft", _check_gradients(self.gradients_ft))
        if not self.signs or any(s not in (1, -1) for s in self.signs):
            raise ValueError(f"gust set: signs = {self.signs}; allowed +1 (up) and/or -1 (down)")
        # F_g inputs checked once, with their names, before any gust is built
        flight_profile_alleviation_factor(0.0, self.z_mo_ft, self.mlw_over_mtow, self.mzfw_over_mtow)
        names = [fp.name for fp in self.flight_points]
        if len(self.flight_points) > 1 and (not all(names) or len(set(names)) != len(names)):
            fixed = tuple(fp if fp.name else _renamed(fp, f"fp{i}") for i, fp in enumerate(self.flight_points))
            names = [fp.name for fp in fixed]
            if len(set(names)) != len(names):
                raise ValueError(f"gust set: flight point names must be unique, got {names}")
            object.__setattr__(self, "flight_points", fixed)
        n = len(self.flight_points) * len(self.gradients_ft) * len(self.signs)
        if n > _MAX_GUSTS:
            raise ValueError(f"gust set: {n} gusts; allowed at most {_MAX_GUSTS}")

    def __len__(self) -> int:
        return len(self.flight_points) * len(self.gradients_ft) * len(self.signs)

    def gusts(self) -> list:
        """Every gust of the set (flight points x gradients x signs) with U_ds per 25.341(a).

        Returns
        -------
        list of Gust
            Every gust of the set.
        """
        out = []
        multi = len(self.flight_points) > 1
        for fp in self.flight_points:
            f_g = flight_profile_alleviation_factor(fp.altitude_ft, self.z_mo_ft, self.mlw_over_mtow,
                                                    self.mzfw_over_mtow)
            at_vd = fp.speed == "VD"
            if fp.u_ref_fps is not None:
                u_ref = (0.5 if at_vd else 1.0) * fp.u_ref_fps
            else:
                u_ref = reference_gust_velocity_eas(fp.altitude_ft, at_vd) / FT
            for h in self.gradients_ft:
                u_ds = u_ref * FT * f_g * (h / 350.0) ** (1.0 / 6.0)
                if fp.u_ref_fps is None:  # same number through the regulation's own function
                    u_ds = design_gust_velocity_eas(h, fp.altitude_ft, f_g, at_vd)
                for s in self.signs:
                    tag = f"{h:.0f}" if abs(h - round(h)) < 1e-9 else f"{h:.1f}".replace(".", "p")
                    parts = [self.name_prefix] + ([fp.name] if multi or fp.name else []) + [f"h{tag}", _SIGN_NAME[s]]
                    out.append(Gust("_".join(parts), fp, h, s, u_ref, f_g, u_ds))
        names = [g.name for g in out]
        if len(set(names)) != len(names):
            raise ValueError("gust set: two gusts got the same case name; use fewer or more distinct gradients")
        return out

    def table(self) -> str:
        """The set as a text table: case, altitude, H, sign, U_ref, F_g, U_ds.

        Returns
        -------
        str
            The table.
        """
        rows = [f"{'case':<28} {'alt ft':>7} {'H ft':>6} {'sign':>5} {'U_ref':>7} {'F_g':>7} {'U_ds ft/s':>9}"]
        for g in self.gusts():
            rows.append(f"{g.name:<28} {g.flight_point.altitude_ft:7.0f} {g.gradient_ft:6.1f} "
                        f"{_SIGN_NAME[g.sign]:>5} {g.u_ref_fps:7.2f} {g.alleviation_factor:7.4f} {g.u_ds_fps:9.3f}")
        return "\n".join(rows)


def _renamed(fp: FlightPoint, name: str) -> FlightPoint:
    return replace(fp, name=name)


def parse_signs(text) -> tuple:
    """The gust signs of a description's ``signs`` key.

    Parameters
    ----------
    text : str or sequence of int
        ``"up"``, ``"down"``, ``"both"`` or the signs.

    Returns
    -------
    tuple of int
        The signs.
    """
    if isinstance(text, str):
        if text not in SIGNS:
            raise ValueError(f"signs = {text!r}; allowed {', '.join(SIGNS)}")
        return SIGNS[text]
    vals = tuple(int(s) for s in text)
    return vals


_SET_KEYS = {"flight_points", "gradients_ft", "gradient_count", "signs", "z_mo_ft", "mlw_over_mtow",
             "mzfw_over_mtow", "name_prefix"}
_FP_KEYS = {"altitude_ft", "mach", "v_tas_m_s", "weight_lb", "speed", "name", "u_ref_fps"}


def gust_set_from_dict(d: dict, defaults: dict | None = None) -> GustSet:
    """A :class:`GustSet` from a description (keys in the module docstring); ``defaults`` fill missing keys.

    Parameters
    ----------
    d : dict
        The description.
    defaults : dict or None, optional
        Values for missing keys.

    Returns
    -------
    GustSet
        The set.
    """
    if not isinstance(d, dict):
        raise ValueError(f"gust set description must be a mapping, got {type(d).__name__}")
    d = {**(defaults or {}), **d}
    unknown = set(d) - _SET_KEYS
    if unknown:
        raise ValueError(f"gust set: unknown keys {sorted(unknown)}; allowed {sorted(_SET_KEYS)}")
    if "gradients_ft" in d and "gradient_count" in d:
        raise ValueError("gust set: give gradients_ft or gradient_count, not both")
    if "gradients_ft" in d:
        grads = d["gradients_ft"]
    elif "gradient_count" in d:
        grads = log_spaced_gradients_ft(d["gradient_count"])
    else:
        raise ValueError("gust set: needs gradients_ft (list, ft) or gradient_count (log-spaced 30-350 ft)")
    if not isinstance(d.get("flight_points", []), list):
        raise ValueError(f"gust set: flight_points = {d['flight_points']!r}; allowed a list of mappings "
                         "(altitude_ft and mach or v_tas_m_s each)")
    if "name_prefix" in d and not (isinstance(d["name_prefix"], str) and d["name_prefix"].isidentifier()):
        raise ValueError(f"gust set: name_prefix = {d['name_prefix']!r}; allowed a name (letters, digits, _) "
                         "used in the case names")
    for k in ("z_mo_ft", "mlw_over_mtow", "mzfw_over_mtow"):
        if k in d and (isinstance(d[k], bool) or not isinstance(d[k], (int, float)) or not math.isfinite(d[k])):
            raise ValueError(f"gust set: {k} = {d[k]!r}; allowed a finite number")
    fps = []
    for i, fp in enumerate(d.get("flight_points") or []):
        if not isinstance(fp, dict):
            raise ValueError(f"gust set: flight_points[{i}] must be a mapping")
        bad = set(fp) - _FP_KEYS
        if bad:
            raise ValueError(f"gust set: flight_points[{i}]: unknown keys {sorted(bad)}; allowed {sorted(_FP_KEYS)}")
        if "altitude_ft" not in fp:
            raise ValueError(f"gust set: flight_points[{i}] needs altitude_ft")
        for k, v in fp.items():
            numeric = k in ("altitude_ft", "mach", "v_tas_m_s", "weight_lb", "u_ref_fps")
            if numeric and v is not None and (isinstance(v, bool) or not isinstance(v, (int, float))
                                              or not math.isfinite(v)):
                raise ValueError(f"gust set: flight_points[{i}].{k} = {v!r}; allowed a finite number")
            if k in ("name", "speed") and not isinstance(v, str):
                raise ValueError(f"gust set: flight_points[{i}].{k} = {v!r}; allowed a string")
        fps.append(FlightPoint(**{k: (float(v) if k in ("altitude_ft", "mach", "v_tas_m_s", "weight_lb", "u_ref_fps")
                                      and v is not None else v) for k, v in fp.items()}))
    kwargs = {k: d[k] for k in ("z_mo_ft", "mlw_over_mtow", "mzfw_over_mtow", "name_prefix") if k in d}
    return GustSet(tuple(fps), grads, parse_signs(d.get("signs", "both")), **kwargs)


def read_gust_set(path: str, defaults: dict | None = None) -> GustSet:
    """Read a gust set description from ``.json`` or ``.yaml``/``.yml`` (PyYAML, imported lazily).

    Parameters
    ----------
    path : str
        JSON or YAML file.
    defaults : dict or None, optional
        Values for missing keys.

    Returns
    -------
    GustSet
        The set.
    """
    if not os.path.exists(path):
        raise ValueError(f"--gust-set {path!r} does not exist")
    if os.path.isdir(path):
        raise ValueError(f"--gust-set {path!r} is a folder; give a .json or .yaml file")
    ext = os.path.splitext(path)[1].lower()
    if ext not in (".json", ".yaml", ".yml"):
        raise ValueError(f"--gust-set {path!r}: extension {ext!r}; allowed .json, .yaml, .yml")
    try:
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"--gust-set {path!r}: cannot read it ({getattr(exc, 'strerror', None) or exc})") from None
    if ext == ".json":
        def _refuse(token):
            raise ValueError(f"{token} is not standard JSON; give finite numbers")

        try:
            data = json.loads(text, parse_constant=_refuse)
        except ValueError as exc:  # json.JSONDecodeError is one
            raise ValueError(f"--gust-set {path!r}: not valid JSON ({exc})") from None
    else:
        try:
            import yaml
        except ImportError as exc:  # pragma: no cover - depends on the install
            raise ImportError("YAML gust sets need PyYAML: pip install pyyaml (or write the set as JSON)") from exc
        try:
            data = yaml.safe_load(text)
        except yaml.YAMLError as exc:  # malformed, tab-indented, !!python/object tags (safe_load refuses them)
            what = " ".join(str(exc).split())
            hint = " (YAML indents with spaces, not tabs)" if "\t" in text else ""
            raise ValueError(f"--gust-set {path!r}: not a valid YAML gust set ({what}){hint}") from None
    try:
        return gust_set_from_dict(data, defaults)
    except ValueError as exc:
        raise ValueError(f"--gust-set {path!r}: {exc}") from None
