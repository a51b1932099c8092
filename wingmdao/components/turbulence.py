"""``TurbulenceStressKS``: KS of the 14 CFR 25.341(b) corner design stresses of a wing, with exact partials.

The aeroelastic beam (:func:`wingmdao.aero.system.build_aeroelastic_system`, trim on, clamped or
free in plunge) is trimmed in 1 g level flight, linearised, and its frequency response to a unit
vertical gust with each station's penetration phase gives A-bar of the corner axial stresses of
every box station; the constraint is the KS of (+/- s_1g + U_sigma A-bar) / sigma_allow - 1
(:func:`wingmdao.stability.frequency_adjoint.turbulence_stress_ks`, docs/turbulence.md). Its
partials with respect to every beam and aerodynamic parameter and the four wall thicknesses come
from the complex adjoint of the frequency-response solves and the adjoint of the 1 g static solve:
declared dense (one output), never finite differences.

Control surfaces (option ``controls``): their actuators and the law are states of the residual, so
the linearisation carries them; the law's matrices ``controller_A`` ... ``controller_D`` are inputs
(defaults: option ``control_law``'s) with the same exact partials as any parameter (docs/controls.md).

Airspeed and aircraft mass: by default the true airspeed is the option ``airspeed`` and the
aircraft enters through ``trim_lift`` (N) and, free in plunge, ``body_mass`` (kg, outside both
wing halves). ``airspeed_input=True`` makes ``airspeed`` (m/s TAS) an input, its partial the total
derivative through the aerodynamics, the gust phases and the spectrum (at fixed Mach number and
density, inputs of their own); ``aircraft_mass_input=True`` replaces ``trim_lift`` and ``body_mass``
by ``aircraft_mass`` (kg): trim_lift = M g, body_mass = M - 2 m_half(mass_per_length,
node_positions) (:func:`wingmdao.aero.plunge.half_wing_mass`, chained into the partials of
``mass_per_length`` and ``node_positions``).

The frequency grid follows the pencil's modes at the first evaluation and is then held (option
``frequencies`` gives it outright): a grid that moved with the design would make the discrete
functional jump. A mode with almost no damping (strip theory leaves the in-plane bending modes
undamped) is a peak a fraction of a grid step wide that moves with the design: the functional is
then smooth but very nonlinear. Give the beam structural damping (option ``damping``).
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om

from wingmdao.aero.controls import ControlLaw, ControlSpec
from wingmdao.aero.plunge import half_wing_mass
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
        self.options.declare("airspeed", types=float, desc="true airspeed V (m/s): gust phases, spectrum, aerodynamics "
                             "(the input's default value with airspeed_input)")
        self.options.declare("airspeed_input", default=False, types=bool,
                             desc="airspeed (m/s TAS) an input, with its total derivative (aerodynamics, gust phases, "
                                  "spectrum at fixed Mach and density)")
        self.options.declare("aircraft_mass_input", default=False, types=bool,
                             desc="aircraft_mass (kg) an input in place of trim_lift (= M g) and body_mass "
                                  "(= M - 2 m_half)")
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
        self.options.declare("controls", default=None, allow_none=True, types=ControlSpec,
                             desc="control surfaces, actuators and law of the residual (wingmdao.aero.controls."
                                  "control_spec; None: none): the gains controller_A ... controller_D become inputs")
        self.options.declare("control_law", default=None, allow_none=True, types=ControlLaw,
                             desc="the law whose matrices are the default values of the gain inputs")
        self.options.declare("surface_limits", default=None, allow_none=True, types=tuple,
                             desc="per control surface (max_deflection rad, max_rate rad/s): adds the output "
                                  "turbulence_actuator_ks, the KS of U_sigma A-bar of each surface's deflection and "
                                  "rate over its limit (<= 1); None: none")
        self.options.declare("aero_theory", default="strip", values=("strip", "vlm"),
                             desc="quasi-steady lift of the aeroelastic beam: strips, or the vortex lattice (its "
                                  "influence matrices lift_influence and moment_influence then inputs, fixed data "
                                  "of the planform and Mach number)")
        self.options.declare("values", default=None, allow_none=True, types=dict,
                             desc="default values of inputs {name: value} (the aerodynamic parameters and "
                                  "trim_lift a sizing group does not connect)")

    def setup(self):
        n = self.options["num_nodes"]
        self.system = cached_aeroelastic_system(n, damping=self.options["damping"], plunge=self.options["plunge"],
                                                trim=True, controls=self.options["controls"],
                                                aero_theory=self.options["aero_theory"])
        derived = ("trim_lift", "body_mass") if self.options["aircraft_mass_input"] else ()
        self.specs = [s for s in self.system.param_specs if s.name != "airspeed" and s.name not in derived]
        law = self.options["control_law"]
        values = {**(law.matrices() if law is not None else {}), **(self.options["values"] or {})}
        for s in self.specs:
            self.add_input(s.name, val=values.get(s.name, 1.0), shape=s.shape or 1, units=s.units, desc=s.desc)
        self.extra = []
        if self.options["airspeed_input"]:
            self.add_input("airspeed", val=self.options["airspeed"], units="m/s",
                           desc="true airspeed V (aerodynamics, gust phases, von Karman spectrum)")
            self.extra.append("airspeed")
        if self.options["aircraft_mass_input"]:
            self.add_input("aircraft_mass", val=values.get("aircraft_mass", 1.0), units="kg",
                           desc="aircraft mass M: trim_lift = M g, body_mass = M - 2 m_half (free plunge)")
            self.extra.append("aircraft_mass")
        for w in WALL_NAMES:
            self.add_input(w, shape=n, units="m", desc=f"{w[2:].replace('_', ' ')} thickness at each station")
        self.add_output("turbulence_ks", units=None,
                        desc="KS of the 25.341(b) corner design-stress constraints (+/- s_1g + U_sigma A-bar)/sigma_allow - 1")
        limits = self.options["surface_limits"]
        self.state_outputs = None
        if limits is not None:
            ctl = self.options["controls"]
            lim = np.asarray(limits, dtype=float)
            if ctl is None or lim.shape != (ctl.n_surfaces, 2) or np.any(~np.isfinite(lim)) or np.any(lim <= 0):
                raise ValueError(f"TurbulenceStressKS: surface_limits {limits!r}; allowed one positive (max_deflection "
                                 "rad, max_rate rad/s) per surface of the option controls")
            names = [srf[0] for srf in ctl.surfaces]
            idx = [self.system.control_index[f"{nm}_deflection"] for nm in names]
            idx += [self.system.control_index[f"{nm}_rate"] for nm in names]
            self.state_outputs = (np.array(idx), np.r_[lim[:, 0], lim[:, 1]])
            self.add_output("turbulence_actuator_ks", units=None,
                            desc="KS of U_sigma A-bar / limit of every surface's deflection and rate (<= 1)")
        self.stress = StressMap(self.system.layout.beam, self.options["width"], self.options["height"],
                                self.options["section_to_csn"], n_state=self.system.n_state)
        self.grid = None if self.options["frequencies"] is None else np.asarray(self.options["frequencies"], float)
        self._cache = None
        self.declare_partials("turbulence_ks", [s.name for s in self.specs] + list(WALL_NAMES) + self.extra)
        if self.state_outputs is not None:  # the walls enter through the section parameters only
            self.declare_partials("turbulence_actuator_ks", [s.name for s in self.specs] + self.extra)

    def _evaluate(self, inputs, gradient):
        """The analysis at ``inputs`` (cached: compute_partials after compute at the same point
        adds the gradient's adjoint solves only)."""
        key = np.concatenate([np.asarray(inputs[k], float).ravel()
                              for k in [s.name for s in self.specs] + list(WALL_NAMES) + self.extra])
        if (self._cache is not None and np.array_equal(self._cache[0], key)
                and (self._cache[1].d_p is not None or not gradient)):
            return self._cache[1]
        system = self.system
        values = {s.name: np.asarray(inputs[s.name]).reshape(s.shape) for s in self.specs}
        V = float(inputs["airspeed"][0]) if self.options["airspeed_input"] else self.options["airspeed"]
        values["airspeed"] = V
        if self.options["aircraft_mass_input"]:
            M = float(inputs["aircraft_mass"][0])
            values["trim_lift"] = M * self.options["gravity"]
            if self.options["plunge"]:
                values["body_mass"] = M - 2.0 * half_wing_mass(values["mass_per_length"], values["node_positions"])[0]
        p = pack(system.param_specs, values)
        ql = layout(system.forcing_specs)
        q = np.zeros(system.n_forcing)
        q[ql["gravity"].start + 2] = -self.options["gravity"]
        q[ql["trim_active"]] = 1.0
        x0, _ = solve_static(system, p, q)
        q_lin = q.copy()
        q_lin[ql["trim_active"]] = 0.0
        model = linear_gust_model(system, p, q_lin, x0, x_stations=self.options["x_stations"],
                                  airspeed=V)
        if self.grid is None:
            self.grid = frequency_grid(pencil_eigenvalues(model), f_max=self.options["f_max"],
                                       n_base=self.options["n_base"])
        walls = np.column_stack([np.asarray(inputs[w], float) for w in WALL_NAMES])
        res = turbulence_stress_ks(system, p, q, model, self.stress, walls, self.grid,
                                   u_sigma=self.options["u_sigma"], sigma_allow=self.options["sigma_allow"],
                                   rho_ks=self.options["rho_ks"], gradient=gradient, state_outputs=self.state_outputs)
        self._cache = (key, res)
        return res

    def compute(self, inputs, outputs):
        res = self._evaluate(inputs, gradient=False)
        outputs["turbulence_ks"] = res.value
        if self.state_outputs is not None:
            outputs["turbulence_actuator_ks"] = res.state_value

    def actuator_ratios(self) -> dict | None:
        """``{surface: {"deflection": U_sigma A-bar / max_deflection, "rate": ...}}`` of the last
        evaluation; None without ``surface_limits`` or before one.

        Returns
        -------
        dict or None
            Per surface the two ratios.
        """
        if self.state_outputs is None or self._cache is None:
            return None
        r = self._cache[1].state_ratio
        names = [srf[0] for srf in self.options["controls"].surfaces]
        return {nm: {"deflection": float(r[k]), "rate": float(r[len(names) + k])} for k, nm in enumerate(names)}

    def compute_partials(self, inputs, partials):
        res = self._evaluate(inputs, gradient=True)
        if self.state_outputs is not None:
            self._chain_partials(partials, "turbulence_actuator_ks", res.state_d_p, res.state_d_airspeed, inputs)
        self._chain_partials(partials, "turbulence_ks", res.d_p, res.d_airspeed, inputs, walls=res.d_walls)

    def _chain_partials(self, partials, out, d_p, d_airspeed, inputs, walls=None):
        """The partials of output ``out`` from its packed gradient ``d_p`` (and ``d_airspeed``, the walls')."""
        pl = layout(self.system.param_specs)
        for s in self.specs:
            partials[out, s.name] = d_p[pl[s.name]].reshape(1, -1)
        if walls is not None:
            for k, w in enumerate(WALL_NAMES):
                partials[out, w] = walls[:, k].reshape(1, -1)
        if self.options["airspeed_input"]:
            partials[out, "airspeed"] = d_airspeed
        if self.options["aircraft_mass_input"]:
            d_lift = float(d_p[pl["trim_lift"]][0])
            d_mass = d_lift * self.options["gravity"]
            if self.options["plunge"]:
                d_body = float(d_p[pl["body_mass"]][0])
                _, dmu, dr = half_wing_mass(np.asarray(inputs["mass_per_length"]),
                                            np.asarray(inputs["node_positions"]).reshape(-1, 3))
                d_mass += d_body
                partials[out, "mass_per_length"] -= 2.0 * d_body * dmu.reshape(1, -1)
                partials[out, "node_positions"] -= 2.0 * d_body * dr.reshape(1, -1)
            partials[out, "aircraft_mass"] = d_mass
