"""Components of the stiffened wingbox: the smeared section, the panel failure ratios over the
time history, the linear sizing rules and the ribs' mass (docs/panels.md).

* :class:`StiffenedBoxSection`: the box of :class:`~wingmdao.components.section.BoxSection`
  with the skins' stiffeners smeared into it (area, centroid, bending, mass).
* :class:`PanelFailure`: per time step and station, the running loads of every wall and the
  failure ratios of the panel modes (skin buckling between stiffeners, panel buckling between
  ribs, stiffener column buckling and crippling, spar-web buckling), each ``SF * R - 1 <= 0``.
* :class:`SizingRules`: the practitioners' rules (stiffener web aspect, stiffener over skin
  thickness, adjacency of neighbouring stations), linear in the design variables.
* :class:`RibMass`: the ribs' mass from their web areas.
* :class:`EquivalentPanelFailure`: the two-level sizing's outer constraint, Farrar's
  minimum-weight panel on the walls' equivalent thicknesses.

Partials: CasADi AD for the pointwise components, constant analytic ones for the linear rules.
"""

from __future__ import annotations

import numbers

import casadi as ca
import numpy as np
import openmdao.api as om

from wingmdao.components.ks import KSOfPointwise
from wingmdao.components.pointwise import PointwiseCasadiComponent, Var
from wingmdao.components.stress import SECTION_DEFAULTS
from wingmdao.components.section import SECTION_OUTPUTS, BoxSection, CombinedJacobianMixin
from wingmdao.materials import Material
from wingmdao.panels.layout import STIFFENER_SHAPES, STIFFENER_VARS, panel_families, smeared_stringer
from wingmdao.panels.box_panels import SKIN_MODES, skin_panel_ratios, web_panel_ratio
from wingmdao.panels.equivalent import FARRAR_EFFICIENCY, SKIN_SHARE, equivalent_skin_ratio
from wingmdao.panels.stiffened import PanelMaterial, material_ratio
from wingmdao.section.box import WALL_NAMES, beam_data, box_properties, validate_box
from wingmdao.stress.box_stress import SECTION_PROPERTIES, panel_running_loads


def _stiffener_inputs(default_h=0.04, default_t=0.003):
    return [
        Var("h_upper_stiffener", (), "m", "upper-skin stiffener web height", default_h),
        Var("t_upper_stiffener", (), "m", "upper-skin stiffener web thickness", default_t),
        Var("h_lower_stiffener", (), "m", "lower-skin stiffener web height", default_h),
        Var("t_lower_stiffener", (), "m", "lower-skin stiffener web thickness", default_t),
    ]


UNIT_FACTORS = (1.0,) * 6


def _declare_stiffener_options(options):
    options.declare("stiffener_pitch", default=0.15, types=numbers.Real, lower=1e-6,
                    desc="stiffener spacing on both skins (m)")
    options.declare("shape", default="blade", values=STIFFENER_SHAPES, desc="stiffener shape (blade or tee)")
    options.declare("flange_ratio", default=1.0, types=numbers.Real, lower=0.0,
                    desc="tee flange width over web height (ignored for blades)")
    options.declare("wall_factors", default=UNIT_FACTORS, types=tuple,
                    desc="(e, g, r) of the skins, then of the spar webs: membrane modulus, shear modulus and "
                         "density over the material's (PanelLayout.wall_factors; 1 for a wall of that material)")


def stringers_of(sym, pitch, shape, flange_ratio):
    """The two smeared stiffener layers (:func:`wingmdao.section.box.stringer_layers`) of the
    stiffener variables in ``sym``.

    Parameters
    ----------
    sym : dict
        Input name -> value or SX, with ``h_<skin>_stiffener`` and ``t_<skin>_stiffener``.
    pitch : float
        Stiffener pitch (m).
    shape : {"blade", "tee"}
        Stiffener shape.
    flange_ratio : float
        Tee flange width over web height (-).

    Returns
    -------
    tuple
        The upper and lower ``(a, d, i)`` of :func:`wingmdao.panels.layout.smeared_stringer`.
    """
    return tuple(smeared_stringer(sym[f"h_{s}_stiffener"], sym[f"t_{s}_stiffener"], pitch, shape, flange_ratio)
                 for s in ("upper", "lower"))


class StiffenedBoxSection(BoxSection):
    """Box section (App. F) with the skins' stiffeners smeared in, at ``num_stations`` stations.

    Inputs (per station, m): ``width``, ``height``, the four wall thicknesses (skins and spar
    webs), ``h_upper_stiffener``, ``t_upper_stiffener``, ``h_lower_stiffener``,
    ``t_lower_stiffener``; ``section_to_csn``, ``nonstructural_mass_per_length`` as for
    :class:`~wingmdao.components.section.BoxSection`. Outputs: ``SECTION_OUTPUTS`` and
    ``stiffener_area`` (m^2, both skins' stiffeners, the box's width times their area per width).
    The stiffeners add to the area, the centroid, the bending stiffness and the mass; the
    torsion constant, shear areas and shear centre are the bare box's (the stiffeners carry no
    shear flow; docs/panels.md).
    """

    def initialize(self):
        super().initialize()
        _declare_stiffener_options(self.options)

    def expression_options(self):
        """What the expressions depend on beside the variables: material, stiffener pitch, shape, flange ratio and wall factors (the key of the persisted functions).

        Returns
        -------
        tuple
            The option values.
        """
        o = self.options
        return (o["material"], float(o["stiffener_pitch"]), o["shape"], float(o["flange_ratio"]),
                tuple(float(f) for f in o["wall_factors"]))

    def pointwise_inputs(self):
        """The per-point inputs: the box section's and the stiffener variables.

        Returns
        -------
        list of Var
            The inputs.
        """
        return super().pointwise_inputs() + _stiffener_inputs()

    def pointwise_outputs(self):
        """The per-point outputs: the box section's, the stiffener area and the density-weighted area.

        Returns
        -------
        list of Var
            The outputs.
        """
        return super().pointwise_outputs() + [
            Var("stiffener_area", (), "m**2", "area of both skins' stiffeners across the box width"),
            Var("mass_area", (), "m**2", "area weighted by each wall's density over the material's (the mass "
                                         "per length is rho mass_area; A itself is modulus weighted)")]

    def pointwise_expressions(self, sym):
        """The outputs at one point as CasADi expressions: the transformed section with the smeared stiffeners (:func:`transformed_section`).

        Parameters
        ----------
        sym : dict
            Input name -> SX symbol of the input's shape at one point.

        Returns
        -------
        dict
            Output name -> SX expression.
        """
        o = self.options
        stringers = stringers_of(sym, o["stiffener_pitch"], o["shape"], o["flange_ratio"])
        walls = [sym[k] for k in WALL_NAMES]
        e_s, g_s, r_s, e_w, g_w, r_w = (float(f) for f in o["wall_factors"])

        def props_of(weights=(1.0, 1.0), shear=(1.0, 1.0), scale=(1.0, 1.0), rotate=True):
            """The box with wall weights, shear weights or its walls' thicknesses and stiffener
            areas scaled, each by (skin, web) factors."""
            skin, web = scale
            return box_properties(sym["width"], sym["height"], walls[0] * skin, walls[1] * skin, walls[2] * web,
                                  walls[3] * web, o["material"], sym["section_to_csn"] if rotate else None,
                                  sym["nonstructural_mass_per_length"],
                                  stringers=tuple((a * skin, d, i * skin) for a, d, i in stringers),
                                  weights=(weights[0], weights[0], weights[1], weights[1]),
                                  shear_weights=(shear[0], shear[0], shear[1], shear[1]))

        if (e_s, g_s, r_s, e_w, g_w, r_w) == UNIT_FACTORS:   # one material: the plain stiffened box
            out = self._select_outputs(props_of())
            out["mass_area"] = out["A"]
        else:   # transformed section: stiffness by modulus, torsion and shear by G, mass by density
            props = transformed_section(props_of, (e_s, e_w), (g_s, g_w), (r_s, r_w), o["material"],
                                        sym["section_to_csn"], sym["nonstructural_mass_per_length"])
            out = self._select_outputs(props)
            out["mass_area"] = props["mass_area"]
        out["stiffener_area"] = sym["width"] * (stringers[0][0] + stringers[1][0])
        return out

    def check_inputs(self, inputs):
        """Raise ``ValueError`` naming the input, point and allowed range when a box dimension or a stiffener variable is invalid.

        Parameters
        ----------
        inputs : dict-like
            The component's inputs.
        """
        super().check_inputs(inputs)
        validate_stiffeners({k: inputs[k] for k in STIFFENER_VARS}, f"{self.pathname or 'StiffenedBoxSection'}: ")


def transformed_section(props_of, e, g, r, material, section_to_csn, nonstructural_mass_per_length) -> dict:
    """Section outputs of a box whose walls are of other materials than ``material`` (the
    transformed section): area, axial and bending stiffness, centroid and first moments with each
    wall weighted by its membrane modulus ratio ``e`` (skins, webs), mass, mass centre and rotary
    inertia weighted by the density ratios ``r`` (both exact: :func:`~wingmdao.section.box.box_walls`
    weights), torsion constant and shear areas with the shear modulus ratios ``g`` (exact); the
    shear centre of the walls with their thicknesses scaled by ``g`` (thin walls: a scaled wall's
    midline moves by (1 - g) t / 2, which is neglected). ``props_of(weights=, shear=, scale=,
    rotate=)`` is the box with wall weights, shear weights or thickness factors, each (skin, web).

    Parameters
    ----------
    props_of : callable
        ``props_of(weights, shear, scale, rotate)`` -> box section properties with those wall factors.
    e : tuple
        Membrane modulus ratios (skins, webs) (-).
    g : tuple
        Shear modulus ratios (skins, webs) (-).
    r : tuple
        Density ratios (skins, webs) (-).
    material : Material
        The reference material.
    section_to_csn : array_like or casadi.SX
        (3, 3) rotation from the section's own axes to csn.
    nonstructural_mass_per_length : float or casadi.SX
        Non-structural mass per length (kg/m).

    Returns
    -------
    dict
        Section outputs.
    """
    ax, ms = props_of(weights=e, rotate=False), props_of(weights=r)
    sh, sc = props_of(shear=g, rotate=False), props_of(scale=g, rotate=False)
    base = {k: ax[k] for k in ("A", "Ixx", "Izz", "Ixz", "c_ea", "n_ea", "Qx", "Qz")}
    base.update({k: sh[k] for k in ("J", "K_c", "K_n")})
    base.update({k: sc[k] for k in ("c_sc", "n_sc")})
    base.update(c_cg=ax["c_ea"], n_cg=ax["n_ea"])
    out = beam_data(base, material, section_to_csn, nonstructural_mass_per_length)
    for k in ("mass_per_length", "inertia_per_length", "c_cg", "n_cg"):
        out[k] = ms[k]
    out["mass_area"] = ms["A"]
    return out


def validate_stiffeners(values: dict, source: str = "") -> None:
    """Raise ``ValueError`` naming the variable, station and allowed range unless every stiffener
    height and thickness is positive and finite.

    Parameters
    ----------
    values : dict
        Stiffener variable name -> (n,) values (m).
    source : str, optional
        Component or input named in the error.
    """
    for name, v in values.items():
        v = np.atleast_1d(np.asarray(v, dtype=float))
        bad = np.flatnonzero(~(np.isfinite(v) & (v > 0.0)))
        if bad.size:
            i = int(bad[0])
            raise ValueError(f"{source}{name} = {v[i]:.6g} m at station {i}; allowed range (0, inf) m")


class SizingRules(om.ExplicitComponent):
    """The stiffened panels' sizing rules as linear functions of the design variables, each <= 0.

    Outputs (per design station unless noted), all in m:

    * ``stiffener_aspect_min`` = 5 ts - h, ``stiffener_aspect_max`` = h - 30 ts
      (web aspect 5 <= h/ts <= 30), per skin: shape (2, n);
    * ``stiffener_over_skin`` = ts - 15 t_skin per skin: shape (2, n);
    * ``adjacency_<var>`` = x_{i+1} - x_i for every design variable between neighbouring design
      stations: shape (n - 1,); the driver bounds it by +-2.5 mm (thicknesses) and +-10 mm
      (stiffener heights).

    Every partial is constant (declared once, with values); the driver may treat the rules as
    linear constraints.
    """

    ASPECT_MIN, ASPECT_MAX, STIFFENER_OVER_SKIN = 5.0, 30.0, 15.0

    def initialize(self):
        self.options.declare("num_stations", types=int, lower=1, desc="number of design stations")
        self.options.declare("adjacency", default=(), types=tuple,
                             desc="design variables whose neighbouring-station differences are output")

    def setup(self):
        n = self.options["num_stations"]
        for name in WALL_NAMES + STIFFENER_VARS:
            self.add_input(name, val=0.01, shape=(n,), units="m", desc=f"{name} per design station")
        self.add_output("stiffener_aspect_min", shape=(2, n), units="m", desc="5 ts - h <= 0 (upper, lower skin)")
        self.add_output("stiffener_aspect_max", shape=(2, n), units="m", desc="h - 30 ts <= 0 (upper, lower skin)")
        self.add_output("stiffener_over_skin", shape=(2, n), units="m", desc="ts - 15 t_skin <= 0 (upper, lower)")
        idx = np.arange(n)
        for k, side in enumerate(("upper", "lower")):
            rows = k * n + idx
            h, ts, skin = f"h_{side}_stiffener", f"t_{side}_stiffener", f"t_{side}_skin"
            self.declare_partials("stiffener_aspect_min", ts, rows=rows, cols=idx, val=self.ASPECT_MIN)
            self.declare_partials("stiffener_aspect_min", h, rows=rows, cols=idx, val=-1.0)
            self.declare_partials("stiffener_aspect_max", h, rows=rows, cols=idx, val=1.0)
            self.declare_partials("stiffener_aspect_max", ts, rows=rows, cols=idx, val=-self.ASPECT_MAX)
            self.declare_partials("stiffener_over_skin", ts, rows=rows, cols=idx, val=1.0)
            self.declare_partials("stiffener_over_skin", skin, rows=rows, cols=idx, val=-self.STIFFENER_OVER_SKIN)
        if n > 1:
            d = np.arange(n - 1)
            for name in self.options["adjacency"]:
                self.add_output(f"adjacency_{name}", shape=(n - 1,), units="m",
                                desc=f"{name} at station i + 1 minus station i")
                self.declare_partials(f"adjacency_{name}", name, rows=np.r_[d, d], cols=np.r_[d + 1, d],
                                      val=np.r_[np.ones(n - 1), -np.ones(n - 1)])

    def compute(self, inputs, outputs):
        for k, side in enumerate(("upper", "lower")):
            h, ts, skin = inputs[f"h_{side}_stiffener"], inputs[f"t_{side}_stiffener"], inputs[f"t_{side}_skin"]
            outputs["stiffener_aspect_min"][k] = self.ASPECT_MIN * ts - h
            outputs["stiffener_aspect_max"][k] = h - self.ASPECT_MAX * ts
            outputs["stiffener_over_skin"][k] = ts - self.STIFFENER_OVER_SKIN * skin
        if self.options["num_stations"] > 1:
            for name in self.options["adjacency"]:
                outputs[f"adjacency_{name}"] = np.diff(inputs[name])


class RibMass(om.ExplicitComponent):
    """Mass of the ribs: each rib a web of the box's outer width times height and the rib
    thickness, rho t_rib sum_k c_k w_k h_k (kg), with c_k the ribs attributed to station k
    (``rib_weights``: a rib between two stations is shared between them linearly,
    :func:`wingmdao.panels.layout.rib_weights`). Lightening holes, flanges and stiffeners of the
    rib are not modelled (docs/panels.md).

    Inputs ``width``, ``height`` (n,) m. Options: ``rib_weights`` (n,), ``rib_thickness`` (m),
    ``density`` (kg/m^3). Output ``rib_mass`` (kg).
    """

    def initialize(self):
        self.options.declare("num_nodes", types=int, lower=1, desc="number of beam stations")
        self.options.declare("rib_weights", types=(list, tuple, np.ndarray),
                             desc="(n,) number of ribs attributed to each station")
        self.options.declare("rib_thickness", types=numbers.Real, lower=0.0, desc="rib web thickness (m)")
        self.options.declare("density", types=numbers.Real, lower=0.0, desc="rib material density (kg/m^3)")

    def setup(self):
        n = self.options["num_nodes"]
        self.add_input("width", val=1.0, shape=(n,), units="m", desc="box outer width per station")
        self.add_input("height", val=0.3, shape=(n,), units="m", desc="box outer height per station")
        self.add_output("rib_mass", val=0.0, units="kg", desc="mass of all ribs")
        c = np.asarray(self.options["rib_weights"], dtype=float)
        if c.shape != (n,) or not np.all(np.isfinite(c) & (c >= 0.0)):
            raise ValueError(f"{self.msginfo}: rib_weights must be {n} finite values >= 0, got {c.tolist()}")
        self._count = c
        self._cols = np.flatnonzero(c)
        self.declare_partials("rib_mass", ["width", "height"], rows=np.zeros(self._cols.size, int), cols=self._cols)

    def compute(self, inputs, outputs):
        k = self.options["density"] * self.options["rib_thickness"]
        outputs["rib_mass"] = k * np.sum(self._count * inputs["width"] * inputs["height"])

    def compute_partials(self, inputs, partials):
        k = self.options["density"] * self.options["rib_thickness"]
        c = self._cols
        partials["rib_mass", "width"] = k * self._count[c] * inputs["height"][c]
        partials["rib_mass", "height"] = k * self._count[c] * inputs["width"][c]


_PANEL_DESC = {
    "skin_buckling": "skin between stiffeners, compression-shear interaction (SF R - 1)",
    "panel_buckling": "stiffened panel between ribs, compression-shear interaction (SF R - 1)",
    "stiffener_column": "stiffener with its effective skin as a column between ribs (SF R - 1)",
    "stiffener_crippling": "stiffener crippling (SF R - 1)",
    "web_buckling": "spar web between the skins, compression-shear interaction (SF R - 1)",
    "laminate_strength": "Tsai-Wu first-ply failure of skin, stiffener and web laminates (SF R - 1)",
}


class PanelFailure(KSOfPointwise, CombinedJacobianMixin, PointwiseCasadiComponent):
    """Failure ratios of the stiffened box's panels on the grid (num_times, num_stations).

    Inputs: ``F_csn``, ``M_csn`` (nt, n, 3) N and N*m, ``dF_csn_ds`` (nt, n, 3) N/m (the
    spanwise derivative of F_csn, :class:`~wingmdao.components.load_gradient.InternalForceGradient`;
    it sets the skins' chordwise running load, zero when not connected); per station the box geometry (``width``,
    ``height``, the four wall thicknesses), the stiffener variables, ``panel_length`` (the rib
    pitch, m) and the section properties A, c_ea, n_ea, Ixx, Izz, Ixz, c_sc, n_sc, Qx, Qz of
    :class:`StiffenedBoxSection`. Outputs ``g_<family>`` for every family of
    :func:`~wingmdao.panels.layout.panel_families`: ``safety_factor * R - 1`` with R the load-linear failure ratio of the
    mode (1 = failure at these loads), at the skin points upper front, upper rear, lower front,
    lower rear and the web points front, rear (:func:`wingmdao.stress.box_stress.panel_running_loads`).
    With ``ks_rho`` (:class:`~wingmdao.components.ks.KSOfPointwise`) also ``ks_<family>``, the KS
    aggregate of each family over time, stations and points; only these then carry partials.
    """


    def initialize(self):
        super().initialize()
        self.options.declare("num_times", types=int, lower=1, desc="number of time steps")
        self.options.declare("num_stations", types=int, lower=1, desc="number of beam stations")
        self.options.declare("material", types=Material, desc="wall and stiffener material")
        self.options.declare("safety_factor", default=1.5, types=numbers.Real, lower=0.0,
                             desc="factor on the loads of every panel mode")
        self.options.declare("skin_material", default=None, allow_none=True, types=PanelMaterial,
                             desc="laminate or metal of the skins and stiffeners (None: material)")
        self.options.declare("spar_material", default=None, allow_none=True, types=PanelMaterial,
                             desc="laminate or metal of the spar webs (None: material)")
        _declare_stiffener_options(self.options)

    def point_grid(self):
        """Leading shape of every variable: (num_times, num_stations).

        Returns
        -------
        tuple
            The grid shape.
        """
        return (self.options["num_times"], self.options["num_stations"])

    def expression_options(self):
        """What the expressions depend on beside the variables: materials, safety factor, stiffener pitch, shape, flange ratio and wall factors (the key of the persisted functions).

        Returns
        -------
        tuple
            The option values.
        """
        o = self.options
        return (o["material"], float(o["safety_factor"]), float(o["stiffener_pitch"]), o["shape"],
                float(o["flange_ratio"]), tuple(float(f) for f in o["wall_factors"]), o["skin_material"],
                o["spar_material"])

    def _materials(self):
        o = self.options
        pm = [o["skin_material"], o["spar_material"]]
        return tuple(PanelMaterial(o["material"]) if m is None else m for m in pm)

    @property
    def families(self) -> dict:
        """This component's families and points per station."""
        return panel_families(any(m.is_laminate for m in self._materials()))

    def pointwise_inputs(self):
        """The per-point inputs: internal loads and their spanwise derivative per time and station, box, stiffener and panel-length data per station.

        Returns
        -------
        list of Var
            The inputs.
        """
        per = dict(per_last_axis=True)
        return [
            Var("F_csn", (3,), "N", "internal force [F_c, F_s (axial), F_n] on the inboard part, csn", 0.0),
            Var("M_csn", (3,), "N*m", "internal moment [M_c, M_s (torsion), M_n] about the box centre, csn", 0.0),
            Var("dF_csn_ds", (3,), "N/m", "spanwise derivative of F_csn (net load per length; sets the skins' "
                "chordwise running load)", 0.0),
            Var("width", (), "m", "box outer width (chordwise)", **per),
            Var("height", (), "m", "box outer height (normal)", 0.3, **per),
            Var("t_upper_skin", (), "m", "upper skin thickness", 0.01, **per),
            Var("t_lower_skin", (), "m", "lower skin thickness", 0.01, **per),
            Var("t_front_spar", (), "m", "front spar web thickness", 0.01, **per),
            Var("t_rear_spar", (), "m", "rear spar web thickness", 0.01, **per),
        ] + [Var(v.name, v.shape, v.units, v.desc, v.val, **per) for v in _stiffener_inputs()] + [
            Var("panel_length", (), "m", "panel length between ribs (rib pitch) at the station", 0.5, **per),
        ] + [Var(name, (), units, desc, SECTION_DEFAULTS.get(name, 0.0),
                 **per) for name, _, units, desc in SECTION_OUTPUTS if name in SECTION_PROPERTIES]

    def pointwise_outputs(self):
        """The per-point outputs: the constraints ``g_<family>`` of every panel family.

        Returns
        -------
        list of Var
            The outputs.
        """
        return [Var(f"g_{f}", (k,), None, _PANEL_DESC[f]) for f, k in self.families.items()]

    def pointwise_expressions(self, sym):
        """The outputs at one point as CasADi expressions: factored failure ratios minus one of every panel mode.

        Parameters
        ----------
        sym : dict
            Input name -> SX symbol of the input's shape at one point.

        Returns
        -------
        dict
            Output name -> SX expression.
        """
        o = self.options
        stringers = stringers_of(sym, o["stiffener_pitch"], o["shape"], o["flange_ratio"])
        walls = [sym[k] for k in WALL_NAMES]
        e_skin, e_web = float(o["wall_factors"][0]), float(o["wall_factors"][3])
        t_eq = (walls[0] + stringers[0][0], walls[1] + stringers[1][0])
        loads = panel_running_loads(sym["F_csn"], sym["M_csn"], sym["width"], sym["height"], *walls,
                                    (e_skin * t_eq[0], e_skin * t_eq[1]), {k: sym[k] for k in SECTION_PROPERTIES},
                                    web_axial_thickness=(e_web * walls[2], e_web * walls[3]),
                                    force_gradient=sym["dF_csn_ds"])
        sf = float(o["safety_factor"])
        skin_pm, web_pm = self._materials()
        laminate = "laminate_strength" in self.families
        out = {f: [] for f in self.families}
        for k, side in enumerate(("upper", "upper", "lower", "lower")):
            t, nx, nxy = sym[f"t_{side}_skin"], loads["nx_skin"][k], loads["nxy_skin"][k]
            r = skin_panel_ratios(skin_pm, t, sym[f"h_{side}_stiffener"], sym[f"t_{side}_stiffener"],
                                  o["stiffener_pitch"], sym["panel_length"], nx, nxy, o["shape"], o["flange_ratio"],
                                  ny=loads["ny_skin"][k])
            for f in SKIN_MODES:
                out[f].append(sf * r[f] - 1.0)
            if laminate:
                out["laminate_strength"].append(sf * material_ratio(skin_pm, t, t_eq[k // 2], nx, nxy) - 1.0)
        h_web = sym["height"] - walls[0] - walls[1]
        for k, t_web in enumerate((walls[2], walls[3])):
            nx, nxy = loads["nx_web"][k], loads["nxy_web"][k]
            out["web_buckling"].append(sf * web_panel_ratio(web_pm, t_web, h_web, sym["panel_length"], nx, nxy) - 1.0)
            if laminate:
                out["laminate_strength"].append(sf * material_ratio(web_pm, t_web, t_web, nx, nxy) - 1.0)
        return {f"g_{f}": ca.vertcat(*v) for f, v in out.items()}

    def check_inputs(self, inputs):
        """Raise ``ValueError`` naming the input, point and allowed range when a box dimension, a stiffener variable or a panel length is invalid.

        Parameters
        ----------
        inputs : dict-like
            The component's inputs.
        """
        source = f"{self.pathname or 'PanelFailure'}: "
        validate_box(inputs["width"], inputs["height"], *(inputs[k] for k in WALL_NAMES), source=source)
        validate_stiffeners({k: inputs[k] for k in STIFFENER_VARS}, source)
        length = np.asarray(inputs["panel_length"])
        bad = np.flatnonzero(~(np.isfinite(length) & (length > 0.0)))
        if bad.size:
            raise ValueError(f"{source}panel_length = {length[bad[0]]:.6g} m at station {bad[0]}; "
                             "allowed range (0, inf) m (the rib pitch)")


class EquivalentPanelFailure(KSOfPointwise, CombinedJacobianMixin, PointwiseCasadiComponent):
    """The outer level of the two-level stiffened sizing: failure ratios of a box whose walls are
    the stiffened walls' equivalent thicknesses (skin plus smeared stiffener area per width), on
    the grid (num_times, num_stations).

    Inputs as :class:`PanelFailure` without the stiffener variables and the load gradient:
    ``F_csn``, ``M_csn`` (nt, n, 3), per station ``width``, ``height``, the four wall thicknesses
    (the skins' equivalent ones), ``panel_length`` and the box section's properties. One output
    family ``g_equivalent_panels`` (6 per station): ``safety_factor * R - 1`` at the skin points
    upper front, upper rear, lower front, lower rear, R of
    :func:`wingmdao.panels.equivalent.equivalent_skin_ratio` (Farrar's minimum-weight panel, the
    skin at the pitch, the material; with the skin's shear), and at the web points front, rear,
    R the unstiffened web's compression-shear buckling of the detailed model
    (:func:`wingmdao.panels.box_panels.web_panel_ratio`). With ``ks_rho``: ``ks_equivalent_panels``.
    """

    #: the family and its points per station
    FAMILIES = {"equivalent_panels": 6}

    def initialize(self):
        super().initialize()
        self.options.declare("num_times", types=int, lower=1, desc="number of time steps")
        self.options.declare("num_stations", types=int, lower=1, desc="number of beam stations")
        self.options.declare("material", types=Material, desc="metal of walls and stiffeners")
        self.options.declare("safety_factor", default=1.5, types=numbers.Real, lower=0.0,
                             desc="factor on the loads of every panel mode")
        self.options.declare("stiffener_pitch", default=0.15, types=numbers.Real, lower=1e-6,
                             desc="stiffener spacing on both skins (m)")
        self.options.declare("efficiency", default=FARRAR_EFFICIENCY["blade"], types=numbers.Real, lower=0.0,
                             desc="Farrar's efficiency factor F of the minimum-weight panel (-)")
        self.options.declare("skin_share", default=SKIN_SHARE, types=numbers.Real, lower=0.0, upper=1.0,
                             desc="skin thickness over equivalent thickness in the skin modes (-)")

    def point_grid(self):
        """Leading shape of every variable: (num_times, num_stations).

        Returns
        -------
        tuple
            The grid shape.
        """
        return (self.options["num_times"], self.options["num_stations"])

    def expression_options(self):
        """What the expressions depend on beside the variables (the key of the persisted functions).

        Returns
        -------
        tuple
            The option values.
        """
        o = self.options
        return (o["material"], float(o["safety_factor"]), float(o["stiffener_pitch"]), float(o["efficiency"]),
                float(o["skin_share"]))

    @property
    def families(self) -> dict:
        """This component's family and points per station."""
        return dict(self.FAMILIES)

    def pointwise_inputs(self):
        """The per-point inputs: internal loads per time and station, box and panel-length data per station.

        Returns
        -------
        list of Var
            The inputs.
        """
        per = dict(per_last_axis=True)
        return [
            Var("F_csn", (3,), "N", "internal force [F_c, F_s (axial), F_n] on the inboard part, csn", 0.0),
            Var("M_csn", (3,), "N*m", "internal moment [M_c, M_s (torsion), M_n] about the box centre, csn", 0.0),
            Var("width", (), "m", "box outer width (chordwise)", **per),
            Var("height", (), "m", "box outer height (normal)", 0.3, **per),
            Var("t_upper_skin", (), "m", "upper skin equivalent thickness (skin and stiffeners)", 0.01, **per),
            Var("t_lower_skin", (), "m", "lower skin equivalent thickness (skin and stiffeners)", 0.01, **per),
            Var("t_front_spar", (), "m", "front spar web thickness", 0.01, **per),
            Var("t_rear_spar", (), "m", "rear spar web thickness", 0.01, **per),
            Var("panel_length", (), "m", "panel length between ribs (rib pitch) at the station", 0.5, **per),
        ] + [Var(name, (), units, desc, SECTION_DEFAULTS.get(name, 0.0),
                 **per) for name, _, units, desc in SECTION_OUTPUTS if name in SECTION_PROPERTIES]

    def pointwise_outputs(self):
        """The per-point output ``g_equivalent_panels``.

        Returns
        -------
        list of Var
            The outputs.
        """
        return [Var("g_equivalent_panels", (6,), None,
                    "equivalent stiffened skins (Farrar) and spar webs, compression-shear (SF R - 1)")]

    def pointwise_expressions(self, sym):
        """The outputs at one point as CasADi expressions: factored ratios minus one.

        Parameters
        ----------
        sym : dict
            Input name -> SX symbol of the input's shape at one point.

        Returns
        -------
        dict
            Output name -> SX expression.
        """
        o = self.options
        mat, sf, pitch = o["material"], float(o["safety_factor"]), float(o["stiffener_pitch"])
        walls = [sym[k] for k in WALL_NAMES]
        loads = panel_running_loads(sym["F_csn"], sym["M_csn"], sym["width"], sym["height"], *walls,
                                    (walls[0], walls[1]), {k: sym[k] for k in SECTION_PROPERTIES})
        g = []
        for k in range(4):
            r = equivalent_skin_ratio(mat, walls[k // 2], sym["panel_length"], pitch, loads["nx_skin"][k],
                                      loads["nxy_skin"][k], float(o["efficiency"]), float(o["skin_share"]))
            g.append(sf * r - 1.0)
        h_web = sym["height"] - walls[0] - walls[1]
        for k, t_web in enumerate((walls[2], walls[3])):
            r = web_panel_ratio(PanelMaterial(mat), t_web, h_web, sym["panel_length"], loads["nx_web"][k],
                                loads["nxy_web"][k])
            g.append(sf * r - 1.0)
        return {"g_equivalent_panels": ca.vertcat(*g)}

    def check_inputs(self, inputs):
        """Raise ``ValueError`` naming the input, point and allowed range when a box dimension or a panel length is invalid.

        Parameters
        ----------
        inputs : dict-like
            The component's inputs.
        """
        source = f"{self.pathname or 'EquivalentPanelFailure'}: "
        validate_box(inputs["width"], inputs["height"], *(inputs[k] for k in WALL_NAMES), source=source)
        length = np.asarray(inputs["panel_length"])
        bad = np.flatnonzero(~(np.isfinite(length) & (length > 0.0)))
        if bad.size:
            raise ValueError(f"{source}panel_length = {length[bad[0]]:.6g} m at station {bad[0]}; "
                             "allowed range (0, inf) m (the rib pitch)")
