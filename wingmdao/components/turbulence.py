"""``TurbulenceStressKS``: KS of the 14 CFR 25.341(b) corner design stresses of a wing, with exact partials.

The aeroelastic beam (:func:`wingmdao.aero.system.build_aeroelastic_system`, trim on, clamped or
free in plunge) is trimmed in 1 g level flight, linearised, and its frequency response to a unit
vertical gust with each station's penetration phase gives A-bar of the corner axial stresses of
every box station; the constraint is the KS of (+/- s_1g + U_sigma A-bar) / sigma_allow - 1
(:func:`wingmdao.stability.frequency_adjoint.turbulence_stress_ks`, docs/turbulence.md). Its
partials with respect to every beam and aerodynamic parameter (airspeed excepted, see below) and
the four wall thicknesses come from the complex adjoint of the frequency-response solves and the
adjoint of the 1 g static solve: declared dense (one output), never finite differences.

The frequency grid follows the pencil's modes at the first evaluation and is then held (option
``frequencies`` gives it outright): a grid that moved with the design would make the discrete
functional jump. A mode with almost no damping (strip theory leaves the in-plane bending modes
undamped) is a peak a fraction of a grid step wide that moves with the design: the functional is
then smooth but very nonlinear. Give the beam structural damping (option ``damping``). The gust phases and the spectrum depend on the airspeed, which is an option
here (``airspeed`` is not an input).
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om

from wingmdao.aero.system import cached_aeroelastic_system
from wingmdao.beam.residual import StrainRateDamping
from wingmdao.loads.atmosphere import G0
from wingmdao.section.box import WALL_NAMES
from wingmdao.stability.frequency import frequency_grid, linear_gust_model, pencil_eigenvalues
from wingmdao.stability.frequency_adjoint import StressMap, turbulence_stress_ks
from wingmdao.timemarch.bdf import solve_static
from wingmdao.timemarch.system import layout, pack


class TurbulenceStressKS(om.ExplicitComponent):
    """Inputs: the aeroelastic system's parameters but ``airspeed`` (its VarSpecs: names, shapes,
    units), the walls ``t_upper_skin``, ``t_lower_skin``, ``t_front_spar``, ``t_rear_spar`` (n,) m.
    Output ``turbulence_ks``: the KS of the 25.341(b) corner design-stress constraints (<= 0)."""

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes (root first)")
        self.options.declare("plunge", default=True, types=bool, desc="aircraft free in plunge (input body_mass)")
        self.options.declare("airspeed", types=float, desc="true airspeed V (m/s): gust phases, spectrum, aerodynamics")
        self.options.declare("x_stations", types=np.ndarray, desc="(n,) m: body x where each station meets the gust (leading edge)")
        self.options.declare("width", types=np.ndarray, desc="(n,) m: box outer width of each station")
        self.options.declare("height", types=np.ndarray, desc="(n,) m: box outer height of each station")
        self.options.declare("section_to_csn", default=None, allow_none=True, types=np.ndarray,
                             desc="(n, 3, 3) rotation from the section axes to csn (None: identity)")
        self.options.declare("u_sigma", types=float, desc="limit turbulence intensity U_sigma (m/s TAS)")
        self.options.declare("sigma_allow", types=float, desc="allowable axial stress (Pa)")
        self.options.declare("rho_ks", default=50.0, types=float, desc="KS aggregation parameter")
        self.options.declare("gravity", default=G0, types=float, desc="gravitational acceleration (m/s**2)")
        self.options.declare("damping", default=None, allow_none=True, types=StrainRateDamping,
                             desc="structural damping of the beam (wingmdao.beam.residual.StrainRateDamping); None: "
                                  "undamped (a mode strip theory leaves undamped then makes the KS very nonlinear)")
        self.options.declare("frequencies", default=None, allow_none=True, types=np.ndarray,
                             desc="fixed grid (rad/s, odd count); None: refined at the modes of the first evaluation")
        self.options.declare("f_max", default=20.0, types=float, desc="highest frequency of the automatic grid (Hz)")
        self.options.declare("n_base", default=161, types=int, desc="geometric points of the automatic grid")
        self.options.declare("values", default=None, allow_none=True, types=dict,
                             desc="default values of inputs {name: value} (the aerodynamic parameters and "
                                  "trim_lift a sizing group does not connect)")

    def setup(self):
        n = self.options["num_nodes"]
        self.system = cached_aeroelastic_system(n, damping=self.options["damping"], plunge=self.options["plunge"],
                                                trim=True)
        self.specs = [s for s in self.system.param_specs if s.name != "airspeed"]
        values = self.options["values"] or {}
        for s in self.specs:
            self.add_input(s.name, val=values.get(s.name, 1.0), shape=s.shape or 1, units=s.units, desc=s.desc)
        for w in WALL_NAMES:
            self.add_input(w, shape=n, units="m", desc=f"{w[2:].replace('_', ' ')} thickness at each station")
        self.add_output("turbulence_ks", units=None,
                        desc="KS of the 25.341(b) corner design-stress constraints (+/- s_1g + U_sigma A-bar)/sigma_allow - 1")
        self.stress = StressMap(self.system.layout.beam, self.options["width"], self.options["height"],
                                self.options["section_to_csn"], n_state=self.system.n_state)
        self.grid = None if self.options["frequencies"] is None else np.asarray(self.options["frequencies"], float)
        self._cache = None
        self.declare_partials("turbulence_ks", [s.name for s in self.specs] + list(WALL_NAMES))

    def _evaluate(self, inputs, gradient):
        """The analysis at ``inputs`` (cached: compute_partials after compute at the same point
        adds the gradient's adjoint solves only)."""
        key = np.concatenate([np.asarray(inputs[k], float).ravel() for k in [s.name for s in self.specs] + list(WALL_NAMES)])
        if (self._cache is not None and np.array_equal(self._cache[0], key)
                and (self._cache[1].d_p is not None or not gradient)):
            return self._cache[1]
        system = self.system
        values = {s.name: np.asarray(inputs[s.name]).reshape(s.shape) for s in self.specs}
        values["airspeed"] = self.options["airspeed"]
        p = pack(system.param_specs, values)
        ql = layout(system.forcing_specs)
        q = np.zeros(system.n_forcing)
        q[ql["gravity"].start + 2] = -self.options["gravity"]
        q[ql["trim_active"]] = 1.0
        x0, _ = solve_static(system, p, q)
        q_lin = q.copy()
        q_lin[ql["trim_active"]] = 0.0
        model = linear_gust_model(system, p, q_lin, x0, x_stations=self.options["x_stations"],
                                  airspeed=self.options["airspeed"])
        if self.grid is None:
            self.grid = frequency_grid(pencil_eigenvalues(model), f_max=self.options["f_max"],
                                       n_base=self.options["n_base"])
        walls = np.column_stack([np.asarray(inputs[w], float) for w in WALL_NAMES])
        res = turbulence_stress_ks(system, p, q, model, self.stress, walls, self.grid,
                                   u_sigma=self.options["u_sigma"], sigma_allow=self.options["sigma_allow"],
                                   rho_ks=self.options["rho_ks"], gradient=gradient)
        self._cache = (key, res)
        return res

    def compute(self, inputs, outputs):
        outputs["turbulence_ks"] = self._evaluate(inputs, gradient=False).value

    def compute_partials(self, inputs, partials):
        res = self._evaluate(inputs, gradient=True)
        pl = layout(self.system.param_specs)
        for s in self.specs:
            partials["turbulence_ks", s.name] = res.d_p[pl[s.name]].reshape(1, -1)
        for k, w in enumerate(WALL_NAMES):
            partials["turbulence_ks", w] = res.d_walls[:, k].reshape(1, -1)
