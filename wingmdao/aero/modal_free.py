"""The modal doublet-lattice wing of an aircraft free in plunge (and pitch): rigid-body modes in the
basis (no OpenMDAO).

The clamped modal wing (:func:`wingmdao.stability.modal.modal_dlm_wing`) moves in the clamped jig
beam's normal modes. Free, the half aircraft's motion is that of the body axes (rigid body) plus
the clamped modes relative to them (a Craig-Bampton basis with the root as the interface)::

    u(r) = w e_z + theta (e_y x r) + sum_i q_i phi_i(r)

``w`` the upward displacement of the body-axes origin O (the plunge), ``theta`` the nose-up
pitch attitude about O's y axis (body axes x aft, z up: a point at x moves ``-x theta`` up), the
same rigid body as :mod:`wingmdao.aero.plunge` and :mod:`wingmdao.aero.pitch`. The doublet
lattice sees each rigid mode like any other mode (its heave and incidence on every panel,
:func:`wingmdao.aero.dlm.modal_transfer`), so the generalized forces, the Roger fit and the
station-load coefficients of the augmented basis follow unchanged.

Structure of the half aircraft (per half, the generalized forces being the half-wing's):

* mass: the half-wing's generalized mass of the augmented basis (the beam residual's element
  inertia, :func:`wingmdao.beam.modes.generalized_mass`: rigid-rigid, rigid-elastic coupling and the
  clamped modes' identity) plus half the body's rigid-body mass, the aircraft outside both wing
  halves: ``m_b / 2`` in plunge; with pitch ``[[m_b, -s_x], [-s_x, I_O]] / 2``
  (:func:`wingmdao.aero.pitch.body_pitch_properties`: first moment ``s = m_b (x_b, z_b)`` and pitch
  inertia ``I_O`` about O);
* stiffness: zero for the rigid modes, ``diag(omega^2)`` for the clamped ones;
* station loads: force summation (:mod:`wingmdao.aero.modal_loads`), the inertia part of every
  basis mode, rigid ones included, from the element inertia outboard of each node
  (:func:`wingmdao.aero.modal_design.modal_projection`).

Horizontal tail (with pitch): quasi-steady, as the beam model's (:mod:`wingmdao.aero.pitch`, no
downwash lag), its lift increment ``L_t = q_d S_t a_t alpha_t``::

    alpha_t = theta - dw/dt / V + x_t dtheta/dt / V + w_g,t / V - deps/dalpha (theta - dw/dt / V + w_g,root / V)

acting at ``x_t``: the half aircraft's generalized force ``L_t / 2 (1, -x_t)`` on (w, theta).

The model is linear: its states are increments on the trimmed 1 g level flight (gravity, trim
angle, tail incidence and the 1 g deflection balance each other there and drop out of the
increments; small angles, constant airspeed, the short-period assumptions of the references).
The load factor is ``1 + (2 dL_wing + dL_t) / W``.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from wingmdao.aero.dlm import DLM_CHORDWISE, DLM_SPANWISE, REDUCED_FREQUENCIES, generalized_forces
from wingmdao.aero.modal_design import ModalGust, cosine_gust_history, modal_projection
from wingmdao.aero.modal_controls import modal_control_model
from wingmdao.aero.modal_loads import StationLoadModel
from wingmdao.aero.plunge import body_mass as plunge_body_mass, half_wing_mass
from wingmdao.aero.rfa import N_LAGS, fit, fit_columns
from wingmdao.aero.rfa_system import modal_rfa_system
from wingmdao.beam.modes import NormalModes, generalized_mass, normal_modes
from wingmdao.beam.static import beam_forcing, cached_beam_system
from wingmdao.stability.modal import N_MODES, ModalDLMWing
from wingmdao.stability.pk import ModalStructure
from wingmdao.timemarch.system import pack

__all__ = ["RIGID_NAMES", "rigid_body_modes", "ModalTail", "FreeModalDLMWing", "free_modal_dlm_wing",
           "free_cosine_gust"]

#: names of the rigid-body modes, in basis order (plunge first, then pitch)
RIGID_NAMES = ("plunge", "pitch")


def rigid_body_modes(node_positions, pitch: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Nodal displacement and rotation (count, n, 3) of the rigid-body modes of the beam's nodes.

    Parameters
    ----------
    node_positions : array_like, shape (n, 3)
        Jig node positions (m), body axes from the origin O (x aft, y right, z up).
    pitch : bool
        Also the pitch mode (a unit nose-up rotation about O's y axis).

    Returns
    -------
    displacement, rotation : ndarray, shape (1 or 2, n, 3)
        Plunge: ``(0, 0, 1)`` m everywhere, no rotation; pitch: rotation ``(0, 1, 0)`` rad and
        displacement ``e_y x r = (z, 0, -x)`` m.
    """
    r = np.asarray(node_positions, dtype=float)
    n = r.shape[0]
    d = np.zeros((2 if pitch else 1, n, 3))
    t = np.zeros_like(d)
    d[0, :, 2] = 1.0
    if pitch:
        t[1, :, 1] = 1.0
        d[1] = np.cross(np.array([0.0, 1.0, 0.0]), r)
    return d, t


@dataclass(frozen=True, eq=False)
class ModalTail:
    """The quasi-steady horizontal tail of the free-pitch modal wing (module docstring).

    Parameters
    ----------
    angle, rate : ndarray, shape (m,)
        The tail angle's coefficients of the modal amplitudes and of the modal velocities over V.
    gust : ndarray, shape (2,)
        Its coefficients of ``(w_g,t, w_g,root) / V``.
    area_slope : float
        S_t a_t (m^2).
    direction : ndarray, shape (m,)
        Generalized force of a unit tail lift on the half aircraft, ``(1, -x_t) / 2`` on (plunge, pitch).
    """

    angle: np.ndarray
    rate: np.ndarray
    gust: np.ndarray
    area_slope: float
    direction: np.ndarray

    def lift(self, qd, V, q, v, w_t, w_r):
        """Tail lift increment (N) of the whole tail.

        Parameters
        ----------
        qd, V : float or casadi.SX
            Dynamic pressure (Pa) and airspeed (m/s).
        q, v : ndarray (m,) or (m, nt), or casadi.SX (m, 1)
            Modal amplitudes and velocities.
        w_t, w_r : float, ndarray (nt,) or casadi.SX
            Gust velocity (m/s) at the tail and at the wing root.

        Returns
        -------
        float, ndarray (nt,) or casadi.SX
            ``q_d S_t a_t alpha_t``.
        """
        if isinstance(q, (ca.SX, ca.MX)):
            alpha = ca.DM(self.angle).T @ q + ca.DM(self.rate).T @ v / V
        else:
            alpha = self.angle @ q + (self.rate @ v) / V
        return qd * self.area_slope * (alpha + (self.gust[0] * w_t + self.gust[1] * w_r) / V)

    def force(self, qd, V, q, v, w_t, w_r):
        """Generalized force of the tail on the half aircraft's modes.

        Parameters
        ----------
        qd, V, q, v, w_t, w_r
            As :meth:`lift`.

        Returns
        -------
        ndarray (m,) or (m, nt), or casadi.SX (m, 1)
            ``direction * lift``.
        """
        L = self.lift(qd, V, q, v, w_t, w_r)
        if isinstance(q, (ca.SX, ca.MX)):
            return ca.DM(self.direction) * L
        return np.multiply.outer(self.direction, L)


def _tail(pitch_params: dict, count: int) -> ModalTail:
    """:class:`ModalTail` of the basis (plunge 0, pitch 1, then ``count - 2`` clamped modes)."""
    de, x_t = float(pitch_params["downwash_gradient"]), float(pitch_params["tail_x"])
    angle, rate = np.zeros(count), np.zeros(count)
    angle[1] = 1.0 - de
    rate[0], rate[1] = -(1.0 - de), x_t
    direction = np.zeros(count)
    direction[0], direction[1] = 0.5, -0.5 * x_t
    return ModalTail(angle=angle, rate=rate, gust=np.array([1.0, -de]),
                     area_slope=float(pitch_params["tail_area"]) * float(pitch_params["tail_lift_slope"]),
                     direction=direction)


@dataclass(eq=False)
class FreeModalDLMWing(ModalDLMWing):
    """:class:`wingmdao.stability.modal.ModalDLMWing` of a free aircraft.

    Parameters
    ----------
    modes, structure, gaf, rfa, system, loads, controls
        As :class:`wingmdao.stability.modal.ModalDLMWing`, on the augmented basis (``rigid``
        rigid-body modes first, frequencies 0).
    rigid : int
        Number of rigid-body modes (1: plunge; 2: plunge and pitch).
    tail : ModalTail or None
        The horizontal tail (None without pitch).
    elastic : NormalModes
        The clamped jig modes alone.
    """

    rigid: int = 1
    tail: ModalTail | None = None
    elastic: NormalModes | None = None

    def info(self) -> dict:
        """The model's figures for a JSON result (the clamped modes' frequencies, the rigid modes' names)."""
        out = super().info()
        out.update(n_modes=self.elastic.count, frequencies_hz=(self.elastic.frequencies / (2 * np.pi)).tolist(),
                   rigid_body_modes=list(RIGID_NAMES[:self.rigid]))
        return out

    def tip_displacement(self, X) -> np.ndarray:
        """Elastic tip displacement z relative to the body axes.

        Parameters
        ----------
        X : ndarray, shape (nt, states)
            Marched states of :attr:`system`.

        Returns
        -------
        ndarray, shape (nt,)
            m, up.
        """
        q = np.asarray(X)[:, self.rigid:self.modes.count]
        return q @ self.elastic.displacement[:, -1, 2]


def free_modal_dlm_wing(beam_params, chord, axis_frac, mach, *, aircraft_mass, pitch_params=None,
                        n_modes: int = N_MODES, n_lags: int = N_LAGS, reduced_frequencies=REDUCED_FREQUENCIES,
                        n_chordwise=DLM_CHORDWISE, n_spanwise=DLM_SPANWISE, damping_ratio: float = 0.0,
                        controls=None) -> FreeModalDLMWing:
    """The modal doublet-lattice wing of the aircraft free in plunge (and pitch), module docstring.

    Parameters
    ----------
    beam_params : dict
        Beam parameters of the half-wing (:func:`wingmdao.beam.residual.param_specs`).
    chord, axis_frac : array_like
        Chord (m) and beam-axis chord fraction per node.
    mach : float
        Mach number of the doublet lattice.
    aircraft_mass : float
        Whole aircraft mass (kg); the body is what is outside both wing halves.
    pitch_params : dict, optional
        Free pitch with a horizontal tail: :func:`wingmdao.aero.pitch.pitch_parameters` (body mass,
        first moment and pitch inertia about O, tail position, area, slope, downwash gradient).
    n_modes : int
        Number of clamped jig modes (the rigid modes come on top).
    n_lags, reduced_frequencies, n_chordwise, n_spanwise
        As :func:`wingmdao.stability.modal.modal_dlm_wing`.
    damping_ratio : float
        Structural damping of the clamped modes (fraction of critical, [0, 1)); the rigid modes have none.
    controls : wingmdao.aero.controls.ControlSpec or None
        Control surfaces (flap modes of the lattice, :mod:`wingmdao.aero.modal_controls`) and law.

    Returns
    -------
    FreeModalDLMWing
        The augmented basis, structure, doublet-lattice forces, Roger fit, residual system (with the
        tail's forcing with pitch) and station-load model.
    """
    if not (np.isfinite(damping_ratio) and 0.0 <= damping_ratio < 1.0):
        raise ValueError(f"damping_ratio = {damping_ratio}; allowed range [0, 1) (fraction of critical)")
    r0 = np.asarray(beam_params["node_positions"], dtype=float)
    n = r0.shape[0]
    pitch = pitch_params is not None
    mb = (float(pitch_params["body_mass"]) if pitch
          else plunge_body_mass(float(aircraft_mass), half_wing_mass(beam_params["mass_per_length"], r0)[0]))
    system = cached_beam_system(n)
    elastic = normal_modes(system, beam_params, pack(system.param_specs, beam_params),
                           pack(system.forcing_specs, beam_forcing(n)), count=int(n_modes))
    dr, tr = rigid_body_modes(r0, pitch)
    nr = dr.shape[0]
    m = nr + elastic.count
    disp = np.concatenate([dr, elastic.displacement])
    rot = np.concatenate([tr, elastic.rotation])
    zeros = np.zeros((nr, n, 3))
    mass = generalized_mass(beam_params, disp, rot)
    body = np.zeros((m, m))
    body[0, 0] = 0.5 * mb
    if pitch:
        s_x = float(pitch_params["body_first_moment"][0])
        body[0, 1] = body[1, 0] = -0.5 * s_x
        body[1, 1] = 0.5 * float(pitch_params["body_pitch_inertia"])
    stiffness = np.zeros((m, m))
    stiffness[nr:, nr:] = elastic.stiffness
    modes = NormalModes(frequencies=np.concatenate([np.zeros(nr), elastic.frequencies]), displacement=disp,
                        rotation=rot, mass=mass + body, stiffness=stiffness,
                        force=np.concatenate([zeros, elastic.force]), moment=np.concatenate([zeros, elastic.moment]))
    gaf = generalized_forces(r0, np.broadcast_to(chord, (n,)), np.broadcast_to(axis_frac, (n,)), disp, rot,
                             mach=mach, reduced_frequencies=reduced_frequencies, n_chordwise=n_chordwise,
                             n_spanwise=n_spanwise,
                             surfaces=() if controls is None else [(s[1], s[2]) for s in controls.surfaces])
    rfa = fit(gaf, n_lags=n_lags, low_k_slope=True)
    damping = np.zeros((m, m))
    damping[nr:, nr:] = ModalStructure.from_modes(elastic, damping_ratio).damping
    structure = ModalStructure(mass=mass + body, stiffness=stiffness, damping=damping)
    coef, err = fit_columns(rfa, gaf.k, gaf.station_loads)
    inertia = modal_projection(beam_params, modes).evaluate(beam_params)[2]
    loads = StationLoadModel(motion=coef[..., :m], gust=coef[..., m], inertia=inertia, error=err)
    tail = _tail(pitch_params, m) if pitch else None
    ctl = None if controls is None else modal_control_model(controls, gaf, rfa, loads, disp[:, -1, 2], plunge=0,
                                                            pitch=1 if pitch else None)
    return FreeModalDLMWing(modes, structure, gaf, rfa, modal_rfa_system(structure, rfa, tail=tail, controls=ctl),
                            loads, ctl, rigid=nr, tail=tail, elastic=elastic)


def free_cosine_gust(params: dict, chord, axis_frac, time, *, aircraft_mass, u_tas, airspeed, density, mach,
                     gust_start, gradient_m, n_modes: int = N_MODES, controls=None) -> ModalGust:
    """:class:`wingmdao.aero.modal_design.ModalGust` of a 1 - cos gust on the modal doublet-lattice
    wing of the aircraft free in plunge (:func:`free_modal_dlm_wing` of the reference design), for a
    sizing: the projection adds half the body's design-dependent mass to the plunge mode.

    Parameters
    ----------
    params : dict
        Beam parameters of the reference design.
    chord, axis_frac : array_like
        Chord (m) and beam-axis chord fraction per node.
    time : array_like
        The case's time grid (s).
    aircraft_mass : float
        Whole aircraft mass (kg).
    u_tas, airspeed, density, mach : float
        Gust amplitude (m/s, true airspeed), airspeed (m/s), air density (kg/m^3), Mach number.
    gust_start, gradient_m : float
        Time (s) the gust reaches the foremost leading edge, gradient H (m).
    n_modes : int
        Number of clamped modes of the basis (the plunge mode comes on top).
    controls : wingmdao.aero.controls.ControlSpec or None
        Control surfaces (flap modes) and law; None: none.

    Returns
    -------
    ModalGust
        With ``plunge=True``.
    """
    wing = free_modal_dlm_wing(params, chord, axis_frac, mach, aircraft_mass=aircraft_mass, n_modes=n_modes,
                               controls=controls)
    return ModalGust(wing=wing, projection=modal_projection(params, wing.modes, aircraft_mass=aircraft_mass),
                     airspeed=float(airspeed), density=float(density),
                     gust=cosine_gust_history(time, u_tas, airspeed, gust_start, gradient_m),
                     node_euler_angles=np.asarray(params["node_euler_angles"]), plunge=True)
