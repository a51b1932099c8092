"""Doublet-lattice flutter of a case's wing in the modal basis of its jig beam (no OpenMDAO).

The chain: the beam's undamped normal modes about the jig (:func:`wingmdao.beam.modes.normal_modes`,
clamped root), the doublet-lattice generalized forces of those modes at a set of reduced
frequencies (:func:`wingmdao.aero.dlm.generalized_forces`), then two flutter solutions that must
agree: p-k on the exact tabulated matrices and the state-space eigenvalues with Roger's lag
states (:mod:`wingmdao.stability.pk`, :mod:`wingmdao.aero.rfa`).

Mach number: the doublet lattice is built at one Mach number. For a case with a speed of sound
the first solution uses the Mach number of the sweep's middle speed; if the p-k flutter speed's
Mach number differs from it by more than :data:`MACH_MATCH_TOL`, the matrices are rebuilt at that
Mach number and both flutter solutions repeated (one match-point iteration).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from wingmdao.aero.dlm import (DLM_CHORDWISE, DLM_SPANWISE, REDUCED_FREQUENCIES, GeneralizedForces,
                               generalized_forces)
from wingmdao.aero.modal_controls import modal_control_model
from wingmdao.aero.modal_loads import StationLoadModel, station_load_model
from wingmdao.aero.rfa import N_LAGS, RogerApproximation, fit
from wingmdao.aero.rfa_system import modal_rfa_system
from wingmdao.beam.modes import NormalModes, normal_modes
from wingmdao.beam.static import beam_forcing, cached_beam_system
from wingmdao.stability.pk import FlutterResult, ModalStructure, pk_flutter, state_space_flutter
from wingmdao.timemarch.system import pack

#: default number of beam modes in the modal basis
N_MODES = 6
#: default number of Roger lag roots of the state-space model
N_LAGS_FLUTTER = 6
#: Mach-number mismatch above which the doublet lattice is rebuilt at the flutter speed's Mach number
MACH_MATCH_TOL = 0.02


@dataclass
class DLMFlutter:
    """Doublet-lattice flutter of a case: ``pk`` and ``state_space`` the two
    :class:`wingmdao.stability.pk.FlutterResult`; ``modes``, ``structure``, ``gaf``, ``rfa`` the
    pieces; ``mach`` the Mach number of the matrices; ``timings`` (s) per step.

    Parameters
    ----------
    pk : wingmdao.stability.pk.FlutterResult
        The p-k flutter result.
    state_space : wingmdao.stability.pk.FlutterResult
        The state-space flutter result on the Roger approximation.
    modes : wingmdao.beam.modes.NormalModes
        The jig normal modes.
    structure : wingmdao.stability.pk.ModalStructure
        Modal mass, stiffness and damping.
    gaf : wingmdao.aero.dlm.GeneralizedForces
        The tabulated doublet-lattice generalized forces.
    rfa : wingmdao.aero.rfa.RogerApproximation
        Roger's approximation of ``gaf``.
    mach : float
        The Mach number of the generalized forces.
    timings : dict
        Time (s) per step (``modes``, ``dlm``, ``pk``, ``state_space``).
    """

    pk: FlutterResult
    state_space: FlutterResult
    modes: NormalModes
    structure: ModalStructure
    gaf: GeneralizedForces
    rfa: RogerApproximation
    mach: float
    timings: dict = field(default_factory=dict)


def jig_modes(problem, n_modes: int = N_MODES) -> NormalModes:
    """The lowest ``n_modes`` normal modes of the case's beam (clamped, no air) about the jig.

    Parameters
    ----------
    problem : wingmdao.stability.cases.FlutterProblem
        The case (its ``num_nodes`` and ``beam`` parameters).
    n_modes : int
        Number of modes.

    Returns
    -------
    wingmdao.beam.modes.NormalModes
        The modes.
    """
    n = problem.num_nodes
    system = cached_beam_system(n)
    p = pack(system.param_specs, problem.beam)
    q = pack(system.forcing_specs, beam_forcing(n))
    return normal_modes(system, problem.beam, p, q, count=int(n_modes))


def case_forces(problem, modes: NormalModes, mach: float, *, reduced_frequencies=REDUCED_FREQUENCIES,
                n_chordwise=DLM_CHORDWISE, n_spanwise=DLM_SPANWISE) -> GeneralizedForces:
    """Doublet-lattice generalized forces of ``modes`` on the case's planform at ``mach``.

    Parameters
    ----------
    problem : wingmdao.stability.cases.FlutterProblem
        The case (its beam and ``aero`` chord and reference point).
    modes : wingmdao.beam.modes.NormalModes
        The modes whose forces are computed.
    mach : float
        Mach number.
    reduced_frequencies : sequence of float
        Reduced frequencies k = omega b_ref / V of the table.
    n_chordwise : int
        Chordwise doublet-lattice panels.
    n_spanwise : int
        Spanwise doublet-lattice strips per beam element.

    Returns
    -------
    wingmdao.aero.dlm.GeneralizedForces
        The tabulated generalized forces.
    """
    n = problem.num_nodes
    return generalized_forces(problem.beam["node_positions"], np.broadcast_to(problem.aero["chord"], (n,)),
                              np.broadcast_to(problem.aero["ref_point"], (n,)), modes.displacement,
                              modes.rotation, mach=mach, reduced_frequencies=reduced_frequencies,
                              n_chordwise=n_chordwise, n_spanwise=n_spanwise)


def dlm_flutter(problem, speeds=None, *, n_modes: int = N_MODES, reduced_frequencies=REDUCED_FREQUENCIES,
                n_lags: int = N_LAGS_FLUTTER, damping_ratio: float = 0.0, n_chordwise=DLM_CHORDWISE,
                n_spanwise=DLM_SPANWISE) -> DLMFlutter:
    """p-k and state-space flutter of ``problem`` (:class:`wingmdao.stability.cases.FlutterProblem`)
    with the doublet lattice (module docstring). ``speeds`` (m/s) default the case's sweep;
    ``damping_ratio`` the structural modal damping (fraction of critical).

    Parameters
    ----------
    problem : wingmdao.stability.cases.FlutterProblem
        The case.
    speeds : array_like or None
        Airspeeds (m/s); None: the case's sweep.
    n_modes : int
        Number of jig normal modes.
    reduced_frequencies : sequence of float
        Reduced frequencies of the tabulated generalized forces.
    n_lags : int
        Number of lag roots of the Roger approximation.
    damping_ratio : float
        Structural modal damping (fraction of critical).
    n_chordwise : int
        Chordwise doublet-lattice panels.
    n_spanwise : int
        Spanwise doublet-lattice strips per beam element.

    Returns
    -------
    DLMFlutter
        Both flutter results and their pieces.
    """
    speeds = problem.speeds if speeds is None else np.asarray(speeds, dtype=float)
    density = float(problem.aero["density"])
    t = {}
    t0 = time.perf_counter()
    modes = jig_modes(problem, n_modes)
    structure = ModalStructure.from_modes(modes, damping_ratio)
    t["modes"] = time.perf_counter() - t0
    mach = problem.mach_at(0.5 * (speeds[0] + speeds[-1]))
    for _ in range(2):
        t0 = time.perf_counter()
        gaf = case_forces(problem, modes, mach, reduced_frequencies=reduced_frequencies,
                          n_chordwise=n_chordwise, n_spanwise=n_spanwise)
        t["dlm"] = t.get("dlm", 0.0) + time.perf_counter() - t0
        t0 = time.perf_counter()
        pk = pk_flutter(structure, gaf, density, speeds)
        t["pk"] = t.get("pk", 0.0) + time.perf_counter() - t0
        if pk.flutter_speed is None or abs(problem.mach_at(pk.flutter_speed) - mach) <= MACH_MATCH_TOL:
            break
        mach = problem.mach_at(pk.flutter_speed)
    t0 = time.perf_counter()
    rfa = fit(gaf, n_lags=n_lags)
    ss = state_space_flutter(structure, rfa, density, speeds)
    t["state_space"] = time.perf_counter() - t0
    return DLMFlutter(pk=pk, state_space=ss, modes=modes, structure=structure, gaf=gaf, rfa=rfa, mach=mach,
                      timings=t)


@dataclass
class ModalDLMWing:
    """The modal doublet-lattice wing of a beam: ``modes``, ``structure``, ``gaf``, ``rfa``, the
    residual ``system`` (:func:`wingmdao.aero.rfa_system.modal_rfa_system`) and the station-load
    recovery ``loads`` (:func:`wingmdao.aero.modal_loads.station_load_model`).

    Parameters
    ----------
    modes : wingmdao.beam.modes.NormalModes
        The jig normal modes (clamped).
    structure : wingmdao.stability.pk.ModalStructure
        Modal mass, stiffness and damping.
    gaf : wingmdao.aero.dlm.GeneralizedForces
        The tabulated doublet-lattice generalized forces.
    rfa : wingmdao.aero.rfa.RogerApproximation
        Roger's approximation of ``gaf``.
    system : wingmdao.timemarch.system.ResidualSystem
        The modal residual system (:func:`wingmdao.aero.rfa_system.modal_rfa_system`).
    loads : wingmdao.aero.modal_loads.StationLoadModel
        The station-load recovery.
    controls : wingmdao.aero.modal_controls.ModalControlModel or None
        Control surfaces as flap modes (in ``system``); None: none.
    """

    modes: NormalModes
    structure: ModalStructure
    gaf: GeneralizedForces
    rfa: RogerApproximation
    system: object
    loads: StationLoadModel
    controls: object = None

    def info(self) -> dict:
        """The model's figures for a JSON result."""
        out = {"n_modes": self.modes.count, "frequencies_hz": (self.modes.frequencies / (2 * np.pi)).tolist(),
               "lag_roots": self.rfa.lags.tolist(), "fit_error": self.rfa.error, "gust_fit_error": self.rfa.gust_error,
               "station_load_fit_error": self.loads.error, "reduced_frequencies": self.gaf.k.tolist(),
               "b_ref_m": self.gaf.b_ref, "mach": self.gaf.mach}
        if self.controls is not None:
            out.update(self.controls.errors)
        return out


def modal_dlm_wing(beam_params, chord, axis_frac, mach, *, n_modes: int = N_MODES, n_lags: int = N_LAGS,
                   reduced_frequencies=REDUCED_FREQUENCIES, n_chordwise=DLM_CHORDWISE,
                   n_spanwise=DLM_SPANWISE, damping_ratio: float = 0.0, controls=None) -> ModalDLMWing:
    """:class:`ModalDLMWing` of the beam ``beam_params`` (clamped, modes about the jig), planform
    ``chord`` and ``axis_frac`` per node, at ``mach``.

    Parameters
    ----------
    beam_params : dict
        The beam's parameters (``node_positions`` (n, 3) m, section properties).
    chord : float or array_like
        Chord per node (m).
    axis_frac : float or array_like
        Beam axis per node as a fraction of the chord.
    mach : float
        Mach number of the generalized forces.
    n_modes : int
        Number of normal modes.
    n_lags : int
        Number of lag roots of the Roger approximation.
    reduced_frequencies : sequence of float
        Reduced frequencies of the tabulated generalized forces.
    n_chordwise : int
        Chordwise doublet-lattice panels.
    n_spanwise : int
        Spanwise doublet-lattice strips per beam element.
    damping_ratio : float
        Structural modal damping (fraction of critical).
    controls : wingmdao.aero.controls.ControlSpec or None
        Control surfaces (flap modes of the lattice, :mod:`wingmdao.aero.modal_controls`) and law.

    Returns
    -------
    ModalDLMWing
        The modal wing.
    """
    r0 = np.asarray(beam_params["node_positions"], dtype=float)
    n = r0.shape[0]
    system = cached_beam_system(n)
    modes = normal_modes(system, beam_params, pack(system.param_specs, beam_params),
                         pack(system.forcing_specs, beam_forcing(n)), count=int(n_modes))
    gaf = generalized_forces(r0, np.broadcast_to(chord, (n,)), np.broadcast_to(axis_frac, (n,)), modes.displacement,
                             modes.rotation, mach=mach, reduced_frequencies=reduced_frequencies,
                             n_chordwise=n_chordwise, n_spanwise=n_spanwise,
                             surfaces=() if controls is None else [(s[1], s[2]) for s in controls.surfaces])
    rfa = fit(gaf, n_lags=n_lags)
    structure = ModalStructure.from_modes(modes, damping_ratio)
    loads = station_load_model(gaf, rfa, modes)
    ctl = None if controls is None else modal_control_model(controls, gaf, rfa, loads, modes.displacement[:, -1, 2])
    return ModalDLMWing(modes, structure, gaf, rfa, modal_rfa_system(structure, rfa, controls=ctl), loads, ctl)
