"""``FlutterDamping``: the aggregated flutter-damping constraint of the aeroelastic beam.

Inputs: the beam parameters of the sizing chain (``node_positions``, ``node_euler_angles``,
``stiffness_csn``, ``compliance_csn``, ``tension_axis``, ``shear_center``, ``mass_per_length``,
``mass_center``, ``inertia_per_length``, names and units of :func:`wingmdao.beam.residual.param_specs`).
Output ``flutter_ks`` = KS over the speeds and the aerodynamically loaded oscillatory modes of
(Re lambda + margin) in 1/s
(``measure="sigma"``) or of (margin - damping ratio) (``measure="ratio"``); <= 0: every such
mode is damped at every speed of the set. From
:func:`wingmdao.stability.sensitivity.damping_constraint` on the clamped beam with unsteady strip
theory linearised about its static state at each speed (docs/flutter.md). Partials: exact,
from the eigenvalue derivatives (left/right vectors, CasADi second derivatives of the residual),
declared dense (one row). Cost: the value is computed in ``compute`` and the gradient, from
the stored eigenvectors, only in ``compute_partials``; between evaluations the modes are warm
started (:class:`wingmdao.stability.sensitivity.WarmStart`: every oscillatory mode of the last
window refined on the new design's full pencil from the previous design's vectors; a speed whose
refinement is not trusted is redone with the full eigen window), ``warm_start=False`` for a cold
window every time.
"""

from __future__ import annotations

import contextlib
import numbers

import numpy as np
import openmdao.api as om

from wingmdao.beam.residual import param_specs as beam_param_specs
from wingmdao.aero.joined import pack_aero_forcing
from wingmdao.aero.system import cached_aeroelastic_system
from wingmdao.stability.cases import FlutterProblem
from wingmdao.stability.eigen import check_speeds
from wingmdao.stability.sensitivity import constraint_gradient, damping_constraint, WarmStart
from wingmdao.timemarch.system import ResidualSystem, layout


class FlutterDamping(om.ExplicitComponent):
    """KS damping constraint of the aeroelastic beam over a set of airspeeds (see module docs)."""

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=3, desc="number of beam nodes (root first)")
        self.options.declare("aero", types=dict,
                             desc="strip aerodynamics: chord (n,) m, ref_point (n,) chord fraction, lift_slope "
                                  "1/rad, density kg/m**3, optional speed_of_sound m/s (Mach = V / a; else 0)")
        self.options.declare("speeds", types=(list, tuple, np.ndarray),
                             desc="airspeeds of the constraint (m/s TAS, increasing)")
        self.options.declare("rho_ks", default=100.0, lower=1.0, types=numbers.Real,
                             desc="KS aggregation parameter (s with measure sigma)")
        self.options.declare("measure", default="sigma", values=("sigma", "ratio"),
                             desc="sigma: g = Re(lambda) + margin (1/s); ratio: g = margin - damping ratio")
        self.options.declare("margin", default=0.0, types=float,
                             desc="required decay rate -Re(lambda) (1/s, sigma) or damping ratio (ratio)")
        self.options.declare("eig_options", default=None, allow_none=True, types=dict,
                             desc="options of wingmdao.stability.eigenmodes (method, sigma, count, ncv)")
        self.options.declare("warm_start", default=True, types=bool,
                             desc="refine the previous evaluation's modes instead of a new eigen window "
                                  "(WarmStart rules); False: full window every evaluation")
        self.options.declare("refresh", default=100, types=int, lower=1,
                             desc="warm start: full eigen window at least every this many evaluations")
        self.options.declare("max_step", default=None, allow_none=True, types=float, lower=1e-12,
                             desc="warm start: full eigen window when a parameter moved more than this "
                                  "(relative) from the last full-window design; None: off (SLSQP steps "
                                  "move the stiffnesses by 30-90 %; the refinement checks decide)")

    def setup(self):
        n = self.options["num_nodes"]
        self._speeds = check_speeds(self.options["speeds"])
        aero = self.options["aero"]
        missing = [k for k in ("chord", "ref_point", "lift_slope", "density") if k not in aero]
        if missing:
            raise ValueError(f"FlutterDamping: aero lacks {missing} (chord m, ref_point, lift_slope 1/rad, "
                             "density kg/m**3)")
        self._system = cached_aeroelastic_system(n)
        self._specs = beam_param_specs(n)
        for s in self._specs:
            self.add_input(s.name, val=0.0, shape=s.shape, units=s.units, desc=s.desc or s.name)
        units = "1/s" if self.options["measure"] == "sigma" else None
        self.add_output("flutter_ks", val=0.0, units=units,
                        desc="KS over speeds and aerodynamically loaded modes of the damping measure; <= 0: no flutter")
        self._cache = None
        self._warm = None
        self.paused = False   # True: compute() evaluates nothing: see paused_flutter()
        if self.options["warm_start"]:
            self._warm = WarmStart(refresh=self.options["refresh"], max_step=self.options["max_step"])

    def setup_partials(self):
        for s in self._specs:
            size = int(np.prod(s.shape))
            self.declare_partials("flutter_ks", s.name, rows=np.zeros(size, int), cols=np.arange(size))

    def _flutter_problem(self, inputs):
        beam = {s.name: np.asarray(inputs[s.name], dtype=float).reshape(s.shape) for s in self._specs}
        return FlutterProblem("sizing", self.options["num_nodes"], beam, dict(self.options["aero"]),
                              self._system, {}, dict(self.options["eig_options"] or {}))

    def _evaluate(self, inputs, gradient):
        key = np.concatenate([np.asarray(inputs[s.name], dtype=float).ravel() for s in self._specs])
        if self._cache is not None and np.array_equal(self._cache[0], key):
            res = self._cache[1]
        else:
            prob = self._flutter_problem(inputs)
            try:
                res = damping_constraint(self._system, prob.params_at, self._speeds, aero_mask=prob.aero_mask(),
                                         beam_mask=prob.beam_weights(),
                                         rho_ks=self.options["rho_ks"], margin=self.options["margin"],
                                         measure=self.options["measure"], gradient=False,
                                         warm_start=self._warm, **prob.eig_options)
            except (RuntimeError, ValueError, np.linalg.LinAlgError) as exc:
                if self._warm is not None:
                    self._warm.reset()
                raise om.AnalysisError(f"{self.pathname}: flutter eigen-analysis failed: {exc}") from exc
            self._cache = (key, res)
        if gradient and res.gradient is None:
            res.gradient = constraint_gradient(self._system, res)
        return res

    def compute(self, inputs, outputs):
        # the value only; the gradient from the stored vectors in compute_partials (line-search
        # evaluations of SLSQP never ask for it)
        if self.paused:   # not evaluated: flutter_ks keeps its last value (paused_flutter)
            return
        outputs["flutter_ks"] = self._evaluate(inputs, gradient=False).value

    def compute_partials(self, inputs, partials):
        res = self._evaluate(inputs, gradient=True)
        lay = layout(self._system.param_specs)
        for s in self._specs:
            partials["flutter_ks", s.name] = res.gradient[lay[s.name]]

    @property
    def last_result(self):
        """The :class:`~wingmdao.stability.sensitivity.DampingConstraint` of the last evaluation."""
        return None if self._cache is None else self._cache[1]

    @property
    def warm_start_state(self):
        """The :class:`~wingmdao.stability.sensitivity.WarmStart` (counts of cold / warm evaluations), or None."""
        return self._warm


#: The stick model's loaded-fraction threshold of the aggregated modes: PEGASUS's half aircraft (5- and
#: 20-node wings, 57-227 m/s) has its wing's in-plane bending at 1.2e-2 to 1.7e-2 (Re lambda ~ -4e-4 1/s,
#: which the KS would lift to ln(count) / rho > 0) and every other oscillatory mode, the short period
#: included, at 3.8e-2 or above (docs/stick-model.md, "Flutter constraint on the stick model").
STICK_NEUTRAL_FRACTION = 0.025


class StickFlutterDamping(om.ExplicitComponent):
    """KS damping constraint of the free stick aircraft (a joined aeroelastic system of
    :func:`wingmdao.aero.joined.build_joined_aeroelastic_system`) over a set of airspeeds, with
    respect to the wing beam's section inputs.

    The modes at each speed are those of the flutter linearization about the unloaded jig in
    zero-lift flight without gravity (every lifting beam's ``alpha_zero_lift`` and ``cm0`` set to
    zero, trim unknowns zero and held): that state is the equilibrium of every design, so the
    eigenvalue derivatives need no static term and are exact. Aggregated: the oscillatory modes
    whose aerodynamic part exceeds ``neutral_fraction`` of their beams' displacement and rotation
    part (:func:`wingmdao.stability.sensitivity.damping_constraint`; rigid-body modes and the trim
    states are zero eigenvalues, left out). Inputs: the wing's section quantities under the lone
    wing's names (``stiffness_csn``, ``compliance_csn``, ``mass_per_length``,
    ``inertia_per_length``, ``tension_axis``, ``shear_center``, ``mass_center``) and, with the
    option ``beam_inputs``, other beams' parameters under the joined system's names (a sized tail's
    or fuselage's ``tail_stiffness_csn``, ``fuselage_mass_per_length``, ...,
    :attr:`wingmdao.groups.load_case.SizedBeam.beam_inputs`); the geometry and the rest of the
    beams are the packed ``p``'s. Output ``flutter_ks`` (1/s), <= 0: every such mode damped.
    """

    #: the wing's parameter blocks that are inputs (lone-wing names)
    INPUTS = ("stiffness_csn", "compliance_csn", "mass_per_length", "inertia_per_length", "tension_axis",
              "shear_center", "mass_center")

    def initialize(self):
        self.options.declare("system", types=ResidualSystem, recordable=False,
                             desc="the joined aeroelastic system of the stick aircraft")
        self.options.declare("p", types=np.ndarray, recordable=False,
                             desc="packed parameters of the system (airspeed, Mach and the wing's inputs replaced)")
        self.options.declare("speeds", types=(list, tuple, np.ndarray), desc="airspeeds (m/s TAS, increasing)")
        self.options.declare("speed_of_sound", types=numbers.Real, desc="m/s: the Mach number V / a of each speed")
        self.options.declare("wing", default="wing", types=str, desc="name of the wing beam")
        self.options.declare("beam_inputs", default=(), types=(list, tuple), recordable=False,
                             desc="parameters of other beams (joined-system names, e.g. tail_stiffness_csn) "
                                  "that are inputs too")
        self.options.declare("rho_ks", default=100.0, lower=1.0, types=numbers.Real, desc="KS aggregation parameter (s)")
        self.options.declare("margin", default=0.0, types=float, desc="required decay rate -Re(lambda) (1/s)")
        self.options.declare("neutral_fraction", default=STICK_NEUTRAL_FRACTION, types=float, lower=0.0,
                             desc="aggregated modes: aerodynamic part above this fraction of the beam part")
        self.options.declare("eig_options", default=None, allow_none=True, types=dict,
                             desc="options of wingmdao.stability.eigenmodes (method, sigma, count, ncv)")

    def setup(self):
        s, wing = self.options["system"], self.options["wing"]
        self._speeds = check_speeds(self.options["speeds"])
        self._lay = layout(s.param_specs)
        specs = {sp.name: sp for sp in s.param_specs}
        p = np.array(self.options["p"], dtype=float)
        if p.size != sum(sp.size for sp in s.param_specs):
            raise ValueError(f"StickFlutterDamping: p has {p.size} entries, the system {sum(sp.size for sp in s.param_specs)}")
        for name in s.lifting:                           # zero-lift flight: the jig is the equilibrium
            p[self._lay[f"{name}_alpha_zero_lift"]] = 0.0
            p[self._lay[f"{name}_cm0"]] = 0.0
        self._p = p
        self._q = pack_aero_forcing(s)                   # no gravity, no gust, trim held
        # input name -> the joined system's parameter
        self._param_of = {k: f"{wing}_{k}" for k in self.INPUTS}
        others = [b.name for b in s.beams if b.name != wing]
        for name in self.options["beam_inputs"]:
            if (name not in specs or name in self._param_of
                    or not any(name.startswith(f"{b}_") for b in others)):
                raise ValueError(f"StickFlutterDamping: beam_inputs entry {name!r} is not a parameter of a beam "
                                 f"other than {wing!r} (allowed: parameters of {', '.join(others)}; each once)")
            self._param_of[name] = name
        for k, name in self._param_of.items():
            sp = specs[name]
            self.add_input(k, val=p[self._lay[name]].reshape(sp.shape), units=sp.units, desc=sp.desc or k)
        self.add_output("flutter_ks", val=0.0, units="1/s",
                        desc="KS over speeds and aerodynamically loaded modes of Re(lambda) + margin; <= 0: no flutter")
        self._aero_mask = np.zeros(s.n_state)
        for idx in s.lag_index.values():
            self._aero_mask[np.asarray(idx).ravel()] = 1.0
        if s.downwash_index is not None:
            self._aero_mask[s.downwash_index] = 1.0
        self._beam_mask = np.zeros(s.n_state)
        for b in s.beams:
            for i in range(b.num_nodes):
                k = s.node_index(b.name, i)
                self._beam_mask[k:k + 6] = 1.0           # r, theta
        self._cache = None
        self.paused = False   # True: compute() evaluates nothing (paused_flutter)

    def setup_partials(self):
        for k, name in self._param_of.items():
            sl = self._lay[name]
            size = sl.stop - sl.start
            self.declare_partials("flutter_ks", k, rows=np.zeros(size, int), cols=np.arange(size))

    def _params(self, inputs):
        p = self._p.copy()
        for k, name in self._param_of.items():
            p[self._lay[name]] = np.asarray(inputs[k], dtype=float).ravel()
        return p

    def _evaluate(self, inputs, gradient):
        s = self.options["system"]
        p = self._params(inputs)
        if self._cache is None or not np.array_equal(self._cache[0], p):
            a = float(self.options["speed_of_sound"])

            def params_at(V):
                pv = p.copy()
                pv[self._lay["airspeed"]] = V
                pv[self._lay["mach"]] = V / a
                return pv, self._q.copy()

            try:
                res = damping_constraint(s, params_at, self._speeds, aero_mask=self._aero_mask,
                                         beam_mask=self._beam_mask, rho_ks=self.options["rho_ks"],
                                         margin=self.options["margin"], measure="sigma", static=False,
                                         neutral_fraction=self.options["neutral_fraction"], gradient=False,
                                         **dict(self.options["eig_options"] or {}))
            except (RuntimeError, ValueError, np.linalg.LinAlgError) as exc:
                raise om.AnalysisError(f"{self.pathname}: flutter eigen-analysis failed: {exc}") from exc
            self._cache = (p, res)
        res = self._cache[1]
        if gradient and res.gradient is None:
            res.gradient = constraint_gradient(s, res, static=False)
        return res

    def compute(self, inputs, outputs):
        if self.paused:
            return
        outputs["flutter_ks"] = self._evaluate(inputs, gradient=False).value

    def compute_partials(self, inputs, partials):
        g = self._evaluate(inputs, gradient=True).gradient
        for k, name in self._param_of.items():
            partials["flutter_ks", k] = g[self._lay[name]]

    @property
    def last_result(self):
        """The :class:`~wingmdao.stability.sensitivity.DampingConstraint` of the last evaluation, or None."""
        return None if self._cache is None else self._cache[1]


@contextlib.contextmanager
def paused_flutter(problem):
    """Context in which every :class:`FlutterDamping` of ``problem`` evaluates nothing
    (``flutter_ks`` keeps its last value, stale until the next evaluation), e.g. for the
    strength-only fully stressed presizing passes, whose designs the optimizer never sees
    (PEGASUS: 4 evaluations, ~0.5 s, the first of them the cold one).

    Parameters
    ----------
    problem : openmdao.api.Problem
        The sizing problem.

    Returns
    -------
    contextlib.AbstractContextManager
        The context.
    """
    comps = [c for c in problem.model.system_iter(include_self=True, recurse=True)
             if isinstance(c, (FlutterDamping, StickFlutterDamping))]
    for c in comps:
        c.paused = True
    try:
        yield comps
    finally:
        for c in comps:
            c.paused = False
