"""``ModalClosedLoopDamping``: the closed-loop stability constraint of the modal doublet-lattice gust.

The design's controlled modal residual (:func:`wingmdao.aero.rfa_system.modal_rfa_system` with
``design=True`` and ``controls``: modal amplitudes and rates, Roger's lag states, the gust's lag
states, the actuator and controller states and the flap lag states) is linear in its states; its
linearization about rest (no gust, no command) is the pencil ``(A + lambda B) v = 0`` with
``A = dR/dx``, ``B = dR/dxdot``. Output ``closed_loop_ks`` = KS over the selected eigenvalues of
``Re lambda + margin`` (1/s); <= 0: every selected mode decays at least at ``margin``. Selected as
in :class:`~wingmdao.components.closed_loop.ClosedLoopDamping`: the finite eigenvalues with
``|lambda|`` above ``neutral`` (the free plunge's rigid-body zero is left out), frequencies up to
``max_frequency_hz``, and an eigenvector that loads the air or moves the surfaces and the law
(the aerodynamic, flap lag and control states' part above ``neutral_fraction`` of the modal
amplitudes' and rates'; a mode the lattice does not load, e.g. an in-plane one, is left out).

Inputs: every parameter of the system: ``airspeed``, ``density``, the design's ``modal_mass``,
``modal_stiffness`` and ``root_inertia`` (the law's measured root bending's inertia row) and the
law's matrices ``controller_A`` ... ``controller_D`` (so the gains). Partials: exact, from the
simple eigenvalues' left and right vectors, ``d lambda = -u^H (dA + lambda dB) v / (u^H B v)``
with the second derivatives of the residual (:func:`wingmdao.stability.sensitivity.gradient_functions`),
for every mode whose KS weight exceeds 1e-13; declared dense (one row). The system has a few
dozen states: a dense QZ solve.
"""

from __future__ import annotations

import numbers

import numpy as np
import openmdao.api as om
import scipy.linalg as sla

from wingmdao.aero.rfa_system import control_state_offset
from wingmdao.stability.eigen import linearize
from wingmdao.stability.sensitivity import gradient_functions
from wingmdao.timemarch.system import CasadiResidualSystem, layout
from wingmdao.utils.ks import ks_aggregate


def loaded_modes(rfa, fraction=1e-2) -> np.ndarray:
    """(modes,) bool: the modes the lattice loads, those whose rows and columns of Roger's
    coefficients (every term) exceed ``fraction`` of the largest mode's (the in-plane modes of a flat
    lattice are not loaded).

    Parameters
    ----------
    rfa : wingmdao.aero.rfa.RogerApproximation
        The modal approximation.
    fraction : float
        Least norm of a mode's rows and columns relative to the largest.

    Returns
    -------
    numpy.ndarray
        The mask.
    """
    A = np.asarray(rfa.A, dtype=float)
    size = np.sqrt(np.sum(A ** 2, axis=(0, 1)) + np.sum(A ** 2, axis=(0, 2)))
    return size > fraction * size.max()


def modal_closed_loop_modes(system, p, loaded, n_lags, *, neutral=1e-6, neutral_fraction=1e-2, max_frequency_hz=50.0):
    """``(lam, v, u, A, B)``: the selected eigenvalues (module docstring) of the controlled modal
    system at packed parameters ``p`` about rest, their right and left vectors and the pencil.

    Parameters
    ----------
    system : CasadiResidualSystem
        :func:`wingmdao.aero.rfa_system.modal_rfa_system` with ``controls``.
    p : numpy.ndarray
        Packed parameters.
    loaded : numpy.ndarray
        (modes,) bool, the modes the air loads (:func:`loaded_modes`); the first ``2 modes`` states
        are the amplitudes and rates.
    n_lags : int
        Number of lag roots (the control states follow the modal and gust lag states).
    neutral : float
        Eigenvalues with ``|lambda|`` below this (1/s) are left out.
    neutral_fraction : float
        Least part of the loaded modes' amplitudes and rates, or of the actuator, controller and flap
        lag states, relative to all amplitudes and rates in a selected mode.
    max_frequency_hz : float
        Highest frequency |Im lambda| / (2 pi) of a selected mode (Hz).

    Returns
    -------
    tuple
        ``lam`` (k,) complex (1/s, the upper half plane), ``v``, ``u`` (n, k), ``A``, ``B`` (sparse).
    """
    x0 = np.zeros(system.n_state)
    A, B = linearize(system, p, np.zeros(system.n_forcing), x0)
    lam, vl, vr = sla.eig(-A.toarray(), B.toarray(), left=True, right=True)
    keep = np.isfinite(lam) & (np.abs(lam) < 1e6) & (np.abs(lam) > neutral) & (lam.imag >= 0.0)
    keep &= np.abs(lam.imag) <= 2.0 * np.pi * max_frequency_hz
    loaded = np.asarray(loaded, dtype=bool)
    m = loaded.size
    vb = np.linalg.norm(vr[:2 * m], axis=0)
    va = np.linalg.norm(vr[:2 * m][np.r_[loaded, loaded]], axis=0)
    vc = np.linalg.norm(vr[control_state_offset(m, n_lags):], axis=0)   # actuator, controller, flap lags
    keep &= (va > neutral_fraction * vb) | (vc > neutral_fraction * vb)
    return lam[keep], vr[:, keep], vl[:, keep], A, B


class ModalClosedLoopDamping(om.ExplicitComponent):
    """KS of ``Re lambda + margin`` of the controlled modal doublet-lattice system (module docs)."""

    def initialize(self):
        self.options.declare("system", types=CasadiResidualSystem, recordable=False,
                             desc="modal_rfa_system(design=True, controls=...) of the design")
        self.options.declare("loaded", types=np.ndarray, desc="(modes,) bool: the modes the air loads (loaded_modes)")
        self.options.declare("n_lags", types=int, lower=0, desc="number of Roger lag roots")
        self.options.declare("rho_ks", default=100.0, lower=1.0, types=numbers.Real,
                             desc="KS aggregation parameter (s)")
        self.options.declare("margin", default=0.0, types=float, desc="required decay rate -Re(lambda) (1/s)")
        self.options.declare("max_frequency_hz", default=50.0, types=float, lower=0.0,
                             desc="highest frequency of a selected mode (Hz): the control bandwidth")

    def setup(self):
        system = self.options["system"]
        self._specs = list(system.param_specs)
        names = {s.name for s in self._specs}
        if not {"modal_mass", "controller_D"} <= names:
            raise ValueError("ModalClosedLoopDamping needs modal_rfa_system(design=True) with control surfaces "
                             f"and a law; its parameters are {sorted(names)}")
        for s in self._specs:
            self.add_input(s.name, val=1.0, shape=s.shape or (1,), units=s.units, desc=s.desc or s.name)
        self.add_output("closed_loop_ks", val=0.0, units="1/s",
                        desc="KS over the loaded closed-loop modes of the modal system of Re(lambda) + margin; "
                             "<= 0: stable")
        self._cache = None

    def setup_partials(self):
        for s in self._specs:
            size = int(np.prod(s.shape))
            self.declare_partials("closed_loop_ks", s.name, rows=np.zeros(size, int), cols=np.arange(size))

    def _packed(self, inputs):
        system = self.options["system"]
        lay = layout(system.param_specs)
        p = np.zeros(system.n_param)
        for s in self._specs:
            p[lay[s.name]] = np.asarray(inputs[s.name], dtype=float).ravel()
        return p

    def _evaluate(self, inputs):
        p = self._packed(inputs)
        if self._cache is None or not np.array_equal(self._cache[0], p):
            lam, v, u, A, B = modal_closed_loop_modes(self.options["system"], p, self.options["loaded"], self.options["n_lags"],
                                                      max_frequency_hz=self.options["max_frequency_hz"])
            if lam.size == 0:
                raise om.AnalysisError(f"{self.pathname}: no loaded closed-loop mode found")
            value, w = ks_aggregate(lam.real + self.options["margin"], self.options["rho_ks"])
            self._cache = (p, value, w, lam, v, u, B)
        return self._cache

    def compute(self, inputs, outputs):
        outputs["closed_loop_ks"] = self._evaluate(inputs)[1]

    @property
    def last_eigenvalues(self):
        """The selected eigenvalues (1/s) of the last evaluation, or None."""
        return None if self._cache is None else self._cache[3]

    def compute_partials(self, inputs, partials):
        system = self.options["system"]
        p, _, w, lam, v, u, B = self._evaluate(inputs)
        fun = gradient_functions(system)
        x0, q = np.zeros(system.n_state), np.zeros(system.n_forcing)
        gp = np.zeros(system.n_param)
        for k in np.flatnonzero(w > 1e-13):
            ds_p, _ = fun.ds(x0, p, q, v[:, k], u[:, k], lam[k])
            gp += w[k] * (-ds_p / np.vdot(u[:, k], B @ v[:, k])).real
        lay = layout(system.param_specs)
        for s in self._specs:
            partials["closed_loop_ks", s.name] = gp[lay[s.name]]
