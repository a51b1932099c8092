"""``ClosedLoopDamping``: the closed-loop stability constraint of a gust case with a feedback law.

The coupled gust case's residual (:func:`wingmdao.aero.system.build_aeroelastic_system` with
control surfaces and a law, docs/controls.md) linearised about the trimmed 1 g state, the first
instant of the march, with the trim released (``trim_active`` = 0: the angle of attack and the
measurement references held): ``(A + lambda B) v = 0`` with ``A = dR/dx``, ``B = dR/dxdot``.
Output ``closed_loop_ks`` = KS over the selected eigenvalues of ``Re lambda + margin`` (1/s);
<= 0: every selected mode decays at least at ``margin``. Selected: the finite eigenvalues with
``|lambda|`` above ``neutral`` (the held states' exact zeros are left out) and frequencies up to
``max_frequency_hz`` (the control bandwidth: the beam's axial and in-plane modes of thousands of
rad/s, which no air damps, are left out) whose eigenvector
loads the air (the aerodynamic lag states' part above ``neutral_fraction`` of the beam's
displacement and rotation part; the in-plane bending modes, which strip theory barely damps,
are left out, as in :class:`~wingmdao.components.flutter.FlutterDamping`) or moves the surfaces
and the controller (their states above the same fraction).

Inputs: every parameter of the system (the beam's, the aerodynamic ones, the body's and the law's
matrices ``controller_A`` ... ``controller_D``, so the gains) and ``trimmed_state`` (the march's
first state, connected from the time history: the trimmed state moves with the design through
the march's own adjoint). Partials: exact, from the simple eigenvalues' left and right vectors,
``d lambda = -u^H (dA + lambda dB) v / (u^H B v)`` with the second derivatives of the residual
(:func:`wingmdao.stability.sensitivity.gradient_functions`), for every mode whose KS weight
exceeds 1e-13; declared dense (one row).

Eigen-solve (:func:`closed_loop_modes`): every finite eigenvalue from the dense standard
eigenvalues, without vectors, of ``(A + sigma B)^-1 B`` on the columns where B is not zero (one
sparse LU, :class:`~wingmdao.stability.pencil_lu.ShiftedPencil`), so the selection sees the whole
spectrum; the vectors only of the band's candidates, by two-sided inverse iteration
(:func:`~wingmdao.stability.modes.refine_pair`), and in the component only of those within
``40 / rho_ks`` (1/s) of the least damped selected mode (the others weigh under exp(-40) in the
KS, against the 1e-13 of the partials). A refinement that does not converge to its own eigenvalue
sends the evaluation to the dense QZ solve with vectors. On the PEGASUS co-design's 446-state
pencil: 0.035-0.045 s against the QZ solve's 0.27-0.36 s.
"""

from __future__ import annotations

import numbers

import numpy as np
import openmdao.api as om
import scipy.linalg as sla

from wingmdao.aero.system import AeroelasticBeamSystem
from wingmdao.loads.atmosphere import G0
from wingmdao.stability.eigen import linearize
from wingmdao.stability.modes import refine_pair
from wingmdao.stability.pencil_lu import ShiftedPencil
from wingmdao.stability.sensitivity import gradient_functions
from wingmdao.timemarch.system import layout
from wingmdao.utils.ks import ks_aggregate


def closed_loop_forcing(system) -> np.ndarray:
    """The packed forcing of the linearisation: gravity, no gust, no command, trim released.

    Parameters
    ----------
    system : ResidualSystem
        The closed-loop gust-case system.

    Returns
    -------
    numpy.ndarray
        The packed forcing.
    """
    q = np.zeros(system.n_forcing)
    lay = layout(system.forcing_specs)
    if "gravity" in lay:
        q[lay["gravity"]] = [0.0, 0.0, -G0]
    return q


#: Real shifts of the eigenvalue solve, tried in turn: the first whose ``A + sigma B`` is well conditioned.
SHIFTS = (1.0, 7.3, -2.9)


def _pencil_eigenvalues(pen, max_abs):
    """Every finite eigenvalue of ``(A + lambda B) v = 0`` (``|lambda|`` below ``max_abs``): the
    dense standard eigenvalues ``mu`` of ``C = (A + sigma B)^-1 B`` (``lambda = sigma - 1/mu``),
    reduced to the columns where B is not zero (C's other columns are zero: their eigenvalues are
    the infinite ones), without vectors. None when no shift of :data:`SHIFTS` gives a well
    conditioned ``A + sigma B``."""
    B = pen.B
    cols = np.flatnonzero(np.asarray(abs(B).sum(axis=0)).ravel())
    if cols.size == 0:
        return np.zeros(0, complex)
    Bc = B[:, cols].toarray()
    for sigma in SHIFTS:
        C = pen.factor(sigma).solve(Bc).real[cols]   # a real matrix factored in complex: exact zeros
        if not np.all(np.isfinite(C)) or np.max(np.abs(C)) * abs(sigma) > 1e10:
            continue
        mu = np.linalg.eigvals(C)
        mu = mu[np.abs(mu) * max_abs > 1.0]
        return sigma - 1.0 / mu
    return None


def _dense_modes(A, B):
    """Every eigenvalue and its left and right vectors (the dense QZ solve, the fallback)."""
    lam, vl, vr = sla.eig(-A.toarray(), B.toarray(), left=True, right=True)
    return lam, vr, vl


def closed_loop_modes(system, p, x0, *, neutral=1e-6, neutral_fraction=1e-2, max_frequency_hz=50.0, depth=None,
                      max_abs=1e6):
    """``(lam, v, u, A, B)``: the selected eigenvalues (module docstring) of the closed-loop system
    at packed parameters ``p`` about ``x0``, their right and left vectors and the pencil.

    Every finite eigenvalue comes from the dense standard eigenvalues (no vectors) of ``(A + sigma
    B)^-1 B`` (sparse LU, :func:`wingmdao.stability.pencil_lu.factor`): the selection sees the whole
    spectrum, none is missed. The vectors, which the selection's air/control test and the partials
    need, come only for the candidates in the band (``neutral < |lambda|``, ``Im lambda`` in ``[0,
    2 pi max_frequency_hz]``), in decreasing ``Re lambda``, by two-sided inverse iteration
    (:func:`wingmdao.stability.modes.refine_pair`, whose Rayleigh quotient is the returned
    eigenvalue); with ``depth`` it stops at the first candidate more than ``depth`` below the
    largest selected ``Re lambda`` (the KS weight of such a mode is below ``exp(-rho_ks depth)``).
    When a refinement does not converge to its own eigenvalue (relative 1e-6), the whole
    evaluation falls back to the dense QZ solve with vectors.

    Parameters
    ----------
    system : AeroelasticBeamSystem
        Built with ``controls``.
    p : numpy.ndarray
        Packed parameters.
    x0 : numpy.ndarray
        State to linearise about (the trimmed state).
    neutral : float
        Eigenvalues with ``|lambda|`` below this (1/s) are the held states' zeros and left out.
    neutral_fraction : float
        Least part of the aerodynamic or control states relative to the beam's in a selected mode.
    max_frequency_hz : float
        Highest frequency |Im lambda| / (2 pi) of a selected mode (Hz).
    depth : float or None
        Only the selected modes with ``Re lambda`` at most this (1/s) below the largest one
        (None: every selected mode).
    max_abs : float
        Eigenvalues with ``|lambda|`` above this (1/s) are the infinite ones.

    Returns
    -------
    tuple
        ``lam`` (k,) complex (1/s, the upper half plane), ``v``, ``u`` (n, k), ``A``, ``B`` (sparse).
    """
    q = closed_loop_forcing(system)
    A, B = linearize(system, p, q, x0)
    lay = system.layout
    beam = lay.beam[:, 0:6].ravel()
    other = np.concatenate([lay.aero.ravel(), np.asarray([lay.body[k] for k in system.control_index], dtype=int)])
    wmax = 2.0 * np.pi * max_frequency_hz

    def band(lam):
        return np.isfinite(lam) & (np.abs(lam) < max_abs) & (np.abs(lam) > neutral) & (lam.imag >= 0.0) \
            & (np.abs(lam.imag) <= wmax)

    def loaded(vr):
        return np.linalg.norm(vr[other], axis=0) > neutral_fraction * np.linalg.norm(vr[beam], axis=0)

    pen = ShiftedPencil(A, B)
    lam_all = _pencil_eigenvalues(pen, max_abs)
    if lam_all is not None:
        cand = lam_all[band(lam_all)]
        cand = cand[np.argsort(-cand.real, kind="stable")]
        rng = np.random.default_rng(0)
        n = A.shape[0]
        start = rng.standard_normal(n) + 1j * rng.standard_normal(n)
        lam_s, v_s, u_s, top, ok = [], [], [], None, True
        for lam0 in cand:
            if depth is not None and top is not None and lam0.real < top - depth:
                break
            v, u, lam, conv = refine_pair(A, B, lam0, start, start, quotient_start=False, pencil=pen)
            if not conv or abs(lam - lam0) > 1e-6 * max(1.0, abs(lam0)):
                ok = False
                break
            lam = complex(lam.real, 0.0) if lam0.imag == 0.0 else lam
            if loaded(v[:, None])[0]:
                lam_s.append(lam)
                v_s.append(v)
                u_s.append(u)
                top = lam.real if top is None else max(top, lam.real)
        if ok:
            lam_s = np.asarray(lam_s, complex)
            v_s = np.array(v_s, complex).T.reshape(n, -1)
            u_s = np.array(u_s, complex).T.reshape(n, -1)
            return lam_s, v_s, u_s, A, B
    lam, vr, vl = _dense_modes(A, B)
    keep = band(lam) & loaded(vr)
    lam, vr, vl = lam[keep], vr[:, keep], vl[:, keep]
    if depth is not None and lam.size:
        near = lam.real >= lam.real.max() - depth
        lam, vr, vl = lam[near], vr[:, near], vl[:, near]
    return lam, vr, vl, A, B


class ClosedLoopDamping(om.ExplicitComponent):
    """KS of ``Re lambda + margin`` of the closed-loop gust-case system (see module docs)."""

    def initialize(self):
        self.options.declare("system", types=AeroelasticBeamSystem, desc="AeroelasticBeamSystem with control surfaces and a law")
        self.options.declare("rho_ks", default=100.0, lower=1.0, types=numbers.Real,
                             desc="KS aggregation parameter (s)")
        self.options.declare("margin", default=0.0, types=float,
                             desc="required decay rate -Re(lambda) (1/s)")
        self.options.declare("max_frequency_hz", default=50.0, types=float, lower=0.0,
                             desc="highest frequency of a selected mode (Hz): the control bandwidth")

    def setup(self):
        system = self.options["system"]
        if getattr(system, "controls", None) is None or not system.controls.outputs:
            raise ValueError("ClosedLoopDamping needs a system built with control surfaces and a feedback law")
        self._specs = list(system.param_specs)
        for s in self._specs:
            # the defaults of the time history's parameter inputs (promoted to the same names)
            self.add_input(s.name, val=1.0, shape=s.shape or (1,), units=s.units, desc=s.desc or s.name)
        self.add_input("trimmed_state", val=0.0, shape=(system.n_state,),
                       desc="state of the trimmed 1 g flight (the march's first instant), the linearisation point")
        self.add_output("closed_loop_ks", val=0.0, units="1/s",
                        desc="KS over the loaded closed-loop modes of Re(lambda) + margin; <= 0: stable")
        self._cache = None

    def setup_partials(self):
        for s in self._specs:
            size = int(np.prod(s.shape))
            self.declare_partials("closed_loop_ks", s.name, rows=np.zeros(size, int), cols=np.arange(size))
        n = self.options["system"].n_state
        self.declare_partials("closed_loop_ks", "trimmed_state", rows=np.zeros(n, int), cols=np.arange(n))

    def _packed(self, inputs):
        system = self.options["system"]
        lay = layout(system.param_specs)
        p = np.zeros(system.n_param)
        for s in self._specs:
            p[lay[s.name]] = np.asarray(inputs[s.name], dtype=float).ravel()
        return p, np.asarray(inputs["trimmed_state"], dtype=float).ravel()

    def _evaluate(self, inputs):
        p, x0 = self._packed(inputs)
        key = np.concatenate([p, x0])
        if self._cache is None or not np.array_equal(self._cache[0], key):
            # modes more than 40 / rho_ks below the least damped one weigh under exp(-40) in the KS
            lam, v, u, A, B = closed_loop_modes(self.options["system"], p, x0,
                                                max_frequency_hz=self.options["max_frequency_hz"],
                                                depth=40.0 / self.options["rho_ks"])
            if lam.size == 0:
                raise om.AnalysisError(f"{self.pathname}: no loaded closed-loop mode found")
            value, w = ks_aggregate(lam.real + self.options["margin"], self.options["rho_ks"])
            self._cache = (key, value, w, lam, v, u, B, p, x0)
        return self._cache

    def compute(self, inputs, outputs):
        outputs["closed_loop_ks"] = self._evaluate(inputs)[1]

    @property
    def last_eigenvalues(self):
        """The selected eigenvalues (1/s) of the last evaluation, or None."""
        return None if self._cache is None else self._cache[3]

    def compute_partials(self, inputs, partials):
        system = self.options["system"]
        _, _, w, lam, v, u, B, p, x0 = self._evaluate(inputs)
        fun = gradient_functions(system)
        q = closed_loop_forcing(system)
        gp, gx = np.zeros(system.n_param), np.zeros(system.n_state)
        for k in np.flatnonzero(w > 1e-13):
            ds_p, ds_x = fun.ds(x0, p, q, v[:, k], u[:, k], lam[k])
            den = np.vdot(u[:, k], B @ v[:, k])
            gp += w[k] * (-ds_p / den).real
            gx += w[k] * (-ds_x / den).real
        lay = layout(system.param_specs)
        for s in self._specs:
            partials["closed_loop_ks", s.name] = gp[lay[s.name]]
        partials["closed_loop_ks", "trimmed_state"] = gx
