"""Clamped 1-cos gust and continuous turbulence of the benchmark wings per aerodynamic theory (no OpenMDAO).

The Goland and HALE wings (:mod:`wingmdao.cases.goland`, :mod:`wingmdao.cases.hale`) are beam and
aerodynamic data only, without an aircraft: the ``gust`` and ``turbulence`` commands do not take
them. Here each is clamped at the root, at zero angle of attack and without gravity, and flies one
flight point (:data:`CONDITIONS`, the same for every theory):

* ``strip``, ``lifting-line``, ``vlm``: the aeroelastic beam (:mod:`wingmdao.aero.system`) with the
  theory's quasi-steady lift and the strips' 2-D Wagner/Kuessner lags, each station meeting the
  gust at its leading edge; the 1-cos gust marched by BDF2
  (:func:`clamped_gust_root_moment`), the turbulence from the linearisation about the jig
  (:func:`wingmdao.loads.turbulence_analysis.coupled_gust_model`, clamped; its 1 g trim asks a lift
  of 1 N, which leaves the wing at its jig);
* ``dlm``: the doublet lattice in the jig beam's modal basis with Roger's lag states
  (:func:`wingmdao.stability.modal.modal_dlm_wing`: :mod:`wingmdao.aero.rfa_system`), the gust
  column with each panel's penetration delay; the gust marched by BDF2 with the root moment by
  force summation (:mod:`wingmdao.aero.modal_loads`), the turbulence from the residual system's
  linearisation (:mod:`wingmdao.stability.modal_turbulence`).

A-bar is the root bending moment's, per m/s of rms vertical gust, with the von Karman spectrum of
25.341(b) (L = 2,500 ft; :func:`wingmdao.loads.turbulence.a_bar`). Every load here is an increment
on the jig at rest, so the gust peak is also the peak increment. docs/aerodynamics-3d.md, "Four
theories on three wings".
"""

from __future__ import annotations

import numpy as np

from wingmdao.aero.modal_design import cosine_gust_history
from wingmdao.aero.modal_loads import station_load_history
from wingmdao.aero.strip import station_gust_history
from wingmdao.aero.system import aero_parameters, cached_aeroelastic_system, three_dimensional_parameters
from wingmdao.beam.static import beam_forcing
from wingmdao.loads.turbulence_analysis import coupled_gust_model, turbulence_analysis
from wingmdao.stability.cases import flutter_problem
from wingmdao.stability.modal import ModalDLMWing, modal_dlm_wing
from wingmdao.stability.modal_turbulence import modal_turbulence_a_bar
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import layout, pack

__all__ = ["THEORIES", "CONDITIONS", "beam_and_aero", "clamped_wing", "clamped_gust_root_moment", "clamped_turbulence_a_bar"]

#: the theories compared (``--aero-theory``)
THEORIES = ("strip", "lifting-line", "vlm", "dlm")
#: the benchmark wings' flight point, gust and time step: airspeed (m/s TAS), density (kg/m^3), 1-cos
#: gust amplitude u_gust (m/s TAS) and gradient H (m), gust_start (s, the gust front at the foremost
#: leading edge), time step dt and t_final (s). Goland: 73 % of its strip-theory flutter speed, sea
#: level, H = 100 ft. HALE: 62 % of its strip-theory flutter speed (32.21 m/s), 20 km (Patil, Hodges
#: & Cesnik's density), H = 10 chords, 1 m/s (2.9 deg; the geometrically exact beam's peak per m/s
#: changes by 0.02 % from 0.01 to 1 m/s)
CONDITIONS = {
    "goland": {"airspeed": 100.0, "density": 1.225, "u_gust": 10.0, "gradient_m": 30.48, "gust_start": 0.05,
               "dt": 0.004, "t_final": 1.2},
    "hale": {"airspeed": 20.0, "density": 0.0889, "u_gust": 1.0, "gradient_m": 10.0, "gust_start": 0.05,
             "dt": 0.005, "t_final": 4.0},
}


def _check(case, theory):
    if case not in CONDITIONS:
        raise ValueError(f"case = {case!r}; allowed: {', '.join(CONDITIONS)}")
    if theory not in THEORIES:
        raise ValueError(f"aero_theory = {theory!r}; allowed: {', '.join(THEORIES)}")


def _conditions(case, overrides) -> dict:
    c = dict(CONDITIONS[case])
    unknown = set(overrides) - set(c)
    if unknown:
        raise ValueError(f"unknown flight-point keys {sorted(unknown)}; allowed: {', '.join(c)}")
    c.update({k: float(v) for k, v in overrides.items()})
    for k in ("airspeed", "density", "gradient_m", "dt", "t_final"):
        if not (np.isfinite(c[k]) and c[k] > 0):
            raise ValueError(f"{k} = {c[k]}; allowed range (0, inf)")
    return c


def beam_and_aero(case: str, theory: str, num_nodes: int, airspeed: float, density: float) -> tuple:
    """The clamped wing's beam and the aeroelastic beam's aerodynamic parameters of ``theory`` at M 0.

    Parameters
    ----------
    case : str
        ``"goland"`` or ``"hale"``.
    theory : str
        One of :data:`THEORIES` (``dlm``: the strip parameters alone).
    num_nodes : int
        Beam nodes.
    airspeed, density : float
        Airspeed (m/s) and air density (kg/m^3).

    Returns
    -------
    tuple
        ``(beam_params, aero_params, chord, axis_fraction)``: the dicts of the residual's parameters,
        chord (m) and beam-axis chord fraction per node, (n,) each.
    """
    _check(case, theory)
    prob = flutter_problem(case, num_nodes)
    n = prob.num_nodes
    chord = np.broadcast_to(np.asarray(prob.aero["chord"], dtype=float), (n,)).copy()
    axis = np.broadcast_to(np.asarray(prob.aero["ref_point"], dtype=float), (n,)).copy()
    ap = aero_parameters(n, chord=chord, ref_point=axis, lift_slope=prob.aero["lift_slope"], airspeed=airspeed,
                         density=density, mach=0.0)
    if theory != "dlm":
        ap.update(three_dimensional_parameters(theory, prob.beam["node_positions"], chord, axis, 0.0))
    return prob.beam, ap, chord, axis


def clamped_wing(case: str, num_nodes: int = 21, n_modes: int = 6) -> ModalDLMWing:
    """The clamped modal doublet-lattice wing of ``case`` at M 0 (jig modes, Roger's lags).

    Parameters
    ----------
    case : str
        ``"goland"`` or ``"hale"``.
    num_nodes : int, optional
        Beam nodes.
    n_modes : int, optional
        Jig modes of the basis.

    Returns
    -------
    wingmdao.stability.modal.ModalDLMWing
        The modal wing.
    """
    _check(case, "dlm")
    beam, _, chord, axis = beam_and_aero(case, "dlm", num_nodes, 1.0, 1.0)
    return modal_dlm_wing(beam, chord, axis, 0.0, n_modes=n_modes)


def clamped_gust_root_moment(case: str, theory: str, *, num_nodes: int = 21, n_modes: int = 6, wing=None,
                             **conditions) -> tuple[np.ndarray, np.ndarray]:
    """Root bending moment history of the clamped wing ``case`` in the 1-cos gust of
    :data:`CONDITIONS` (entries overridden by ``conditions``), theory ``theory``.

    Parameters
    ----------
    case : str
        ``"goland"`` or ``"hale"``.
    theory : str
        One of :data:`THEORIES`.
    num_nodes : int, optional
        Beam nodes.
    n_modes : int, optional
        Jig modes of the doublet lattice's basis.
    wing : wingmdao.stability.modal.ModalDLMWing or None, optional
        A prebuilt :func:`clamped_wing` (``dlm`` only); None builds it.
    **conditions
        Overrides of :data:`CONDITIONS` (airspeed, density, u_gust, gradient_m, gust_start, dt, t_final).

    Returns
    -------
    tuple of numpy.ndarray
        Time (s) and the root bending moment M_x (N m, body axes, positive tip up), each (nt,).
    """
    _check(case, theory)
    c = _conditions(case, conditions)
    V, rho = c["airspeed"], c["density"]
    t = np.arange(0.0, c["t_final"] + 0.5 * c["dt"], c["dt"])
    if theory == "dlm":
        w = clamped_wing(case, num_nodes, n_modes) if wing is None else wing
        s = w.system
        F = np.zeros((t.size, s.n_forcing))
        F[:, :3] = cosine_gust_history(t, c["u_gust"], V, c["gust_start"], c["gradient_m"])
        X = march(s, t, pack(s.param_specs, {"airspeed": V, "density": rho}), F).states
        loads, _ = station_load_history(w.loads, w.structure, w.rfa, X, F, V, rho)
        return t, loads[:, 0, 3]
    beam, ap, chord, axis = beam_and_aero(case, theory, num_nodes, V, rho)
    n = chord.size
    s = cached_aeroelastic_system(n, aero_theory="vlm" if theory == "vlm" else "strip")
    p = pack(s.param_specs, {**beam, **ap})
    qd = beam_forcing(n)
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3))
    Q = np.tile(pack(s.forcing_specs, qd), (t.size, 1))

    def profile(tau):
        d = V * (np.asarray(tau) - c["gust_start"])
        H = c["gradient_m"]
        return np.where((d >= 0) & (d <= 2 * H), 0.5 * c["u_gust"] * (1 - np.cos(np.pi * d / H)), 0.0)

    x_le = np.asarray(beam["node_positions"])[:, 0] - axis * chord
    Q[:, layout(s.forcing_specs)["gust_velocity"]] = station_gust_history(t, x_le, V, profile)
    h = march(s, t, p, Q)
    return t, s.layout.beam_states(h.states)[:, 0, 9]


def clamped_turbulence_a_bar(case: str, theory: str, *, num_nodes: int = 21, n_modes: int = 6, wing=None,
                             f_max: float = 40.0, n_base: int = 161, **conditions) -> tuple[float, float]:
    """A-bar of the root bending moment (N m per m/s of rms vertical gust) of the clamped wing
    ``case`` at the flight point of :data:`CONDITIONS` (airspeed and density, overridable), von
    Karman spectrum of 25.341(b), undamped structure.

    Parameters
    ----------
    case : str
        ``"goland"`` or ``"hale"``.
    theory : str
        One of :data:`THEORIES`.
    num_nodes : int, optional
        Beam nodes.
    n_modes : int, optional
        Jig modes of the doublet lattice's basis.
    wing : wingmdao.stability.modal.ModalDLMWing or None, optional
        A prebuilt :func:`clamped_wing` (``dlm`` only); None builds it.
    f_max : float, optional
        Highest frequency of the grid (Hz).
    n_base : int, optional
        Points of the geometric base grid.
    **conditions
        Overrides of :data:`CONDITIONS` (airspeed, density).

    Returns
    -------
    tuple of float
        A-bar (N m per m/s) and its quadrature error estimate.
    """
    _check(case, theory)
    c = _conditions(case, conditions)
    V, rho = c["airspeed"], c["density"]
    if theory == "dlm":
        w = clamped_wing(case, num_nodes, n_modes) if wing is None else wing
        ab, _ = modal_turbulence_a_bar(w.system, w.structure, w.rfa, w.loads, V, rho, f_max=f_max, n_base=n_base)
        return float(ab.value[0, 3]), float(ab.error[0, 3])
    beam, ap, chord, axis = beam_and_aero(case, theory, num_nodes, V, rho)
    gm = coupled_gust_model(beam, ap, chord=chord, axis_fraction=axis, weight=1.0, plunge=False, gravity=0.0,
                            aero_theory="vlm" if theory == "vlm" else "strip")
    res = turbulence_analysis(gm, 1.0, f_max=f_max, n_base=n_base)
    return float(res["a_bar"]["root_bending_moment"]), float(res["a_bar_error"]["root_bending_moment"])
