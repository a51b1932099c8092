"""The stiffened box: smeared stiffener layers against the discrete stiffened section
(sectionproperties), the components' partials, the sizing rules, the ribs' mass and the rib pitch."""

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.components.panels import PanelFailure, RibMass, SizingRules, StiffenedBoxSection
from wingmdao.materials import ALUMINIUM
from wingmdao.panels.layout import (PANEL_FAMILIES, STIFFENER_VARS, PanelLayout, rib_pitch_at_stations, rib_weights,
                                    smeared_stringer)
from wingmdao.section.box import WALL_NAMES, box_properties
from wingmdao.stress.box_stress import SECTION_PROPERTIES

W, H, TU, TL, TF, TR = 0.9, 0.25, 0.006, 0.004, 0.005, 0.003
HS, TS, PITCH, N_STIFF = 0.04, 0.003, 0.15, 6   # W = N_STIFF * PITCH


def test_smeared_layers_equal_the_discrete_stiffened_box():
    """Area, centroid height and vertical bending of the smeared box equal those of the box with
    N_STIFF discrete blades per skin (sectionproperties geometry, independent of our formulas);
    the chordwise bending differs only by the stiffeners' discrete positions (a few %)."""
    geometry_mod = pytest.importorskip("sectionproperties.pre.geometry")
    from sectionproperties.analysis.section import Section
    from shapely.geometry import box as rect
    from shapely.ops import unary_union

    parts = [rect(-W / 2, H / 2 - TU, W / 2, H / 2), rect(-W / 2, -H / 2, W / 2, -H / 2 + TL),
             rect(-W / 2, -H / 2 + TL, -W / 2 + TF, H / 2 - TU), rect(W / 2 - TR, -H / 2 + TL, W / 2, H / 2 - TU)]
    for k in range(N_STIFF):
        c = -W / 2 + (k + 0.5) * PITCH
        parts.append(rect(c - TS / 2, H / 2 - TU - HS, c + TS / 2, H / 2 - TU))
        parts.append(rect(c - TS / 2, -H / 2 + TL, c + TS / 2, -H / 2 + TL + HS))
    geom = geometry_mod.Geometry(unary_union(parts))
    geom.create_mesh(mesh_sizes=[2e-5])
    sec = Section(geom)
    sec.calculate_geometric_properties()
    area = sec.get_area()
    cx, cy = sec.get_c()
    ixx, iyy, _ = sec.get_ic()
    layer = smeared_stringer(HS, TS, PITCH)
    props = box_properties(W, H, TU, TL, TF, TR, ALUMINIUM, stringers=(layer, layer))
    assert props["A"] == pytest.approx(area, rel=1e-9)
    assert props["n_ea"] == pytest.approx(cy, abs=1e-9)
    assert props["Ixx"] == pytest.approx(ixx, rel=1e-6)
    assert props["Izz"] == pytest.approx(iyy, rel=0.05)
    # the bare box keeps its torsion constant (stiffeners carry no shear flow)
    assert props["J"] == box_properties(W, H, TU, TL, TF, TR, ALUMINIUM)["J"]


def _design(prob, n, rng):
    prob.set_val("width", rng.uniform(0.6, 1.0, n))
    prob.set_val("height", rng.uniform(0.15, 0.3, n))
    for i, w in enumerate(WALL_NAMES):
        prob.set_val(w, rng.uniform(2e-3, 9e-3, n) * (1 + 0.3 * i))
    for name in STIFFENER_VARS:
        prob.set_val(name, rng.uniform(0.03, 0.06, n) if name.startswith("h_") else rng.uniform(2e-3, 4e-3, n))


@pytest.mark.parametrize("shape", ["blade", "tee"])
def test_stiffened_section_partials(shape):
    n = 3
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("section", StiffenedBoxSection(num_stations=n, material=ALUMINIUM, shape=shape,
                                                            flange_ratio=0.6), promotes=["*"])
    prob.setup(force_alloc_complex=True)
    _design(prob, n, np.random.default_rng(3))
    prob.set_val("nonstructural_mass_per_length", [5.0, 4.0, 3.0])   # a relative fd step needs a nonzero value
    prob.run_model()
    data = prob.check_partials(method="fd", form="central", step=1e-6, step_calc="rel", out_stream=None)
    assert_check_partials(data, atol=1e-6, rtol=1e-5)


def test_panel_failure_partials_and_ratios_scale_with_load():
    nt, n = 2, 3
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("section", StiffenedBoxSection(num_stations=n, material=ALUMINIUM), promotes_inputs=["*"])
    prob.model.add_subsystem("panels", PanelFailure(num_times=nt, num_stations=n, material=ALUMINIUM,
                                                    safety_factor=1.0),
                             promotes_inputs=["width", "height", *WALL_NAMES, *STIFFENER_VARS, "panel_length",
                                              "F_csn", "M_csn", "dF_csn_ds"])
    for name in SECTION_PROPERTIES:
        prob.model.connect(f"section.{name}", f"panels.{name}")
    prob.setup(force_alloc_complex=True)
    rng = np.random.default_rng(5)
    _design(prob, n, rng)
    prob.set_val("nonstructural_mass_per_length", [5.0, 4.0, 3.0])   # a relative fd step needs a nonzero value
    prob.set_val("panel_length", rng.uniform(0.4, 0.8, n))
    F = rng.normal(0, 3e4, (nt, n, 3))
    M = rng.normal(0, 1e5, (nt, n, 3))
    dF = rng.normal(0, 2e4, (nt, n, 3))     # the skins' chordwise load: compression on some skins, tension on others
    prob.set_val("F_csn", F)
    prob.set_val("M_csn", M)
    prob.set_val("dF_csn_ds", dF)
    prob.run_model()
    data = prob.check_partials(method="fd", form="central", step=1e-6, step_calc="rel", out_stream=None)
    # central differences of O(1) ratios: truncation and round-off ~1e-6 on the small Ixz
    assert_check_partials(data, atol=1e-5, rtol=2e-4)
    g1 = {f: prob.get_val(f"panels.g_{f}").copy() for f in PANEL_FAMILIES}
    prob.set_val("F_csn", 2 * F)
    prob.set_val("M_csn", 2 * M)
    prob.set_val("dF_csn_ds", 2 * dF)
    prob.run_model()
    for f in PANEL_FAMILIES:   # R = g + 1 is homogeneous of degree 1 in the loads
        np.testing.assert_allclose(prob.get_val(f"panels.g_{f}") + 1.0, 2.0 * (g1[f] + 1.0), rtol=1e-6, atol=1e-6)


def test_panel_failure_ks_outputs_equal_ks_of_the_ratios():
    """PanelFailure with ks_rho: each ks_<family> equals KSAggregate of its g_<family>, and its
    total derivatives (from the aggregated per-point nonzeros) equal those of g_<family> through
    KSAggregate (per-point partials, checked against finite differences above) and central
    differences."""
    from wingmdao.components.ks import KSAggregate

    nt, n = 3, 3
    prob = om.Problem(reports=False)
    model = prob.model
    model.add_subsystem("section", StiffenedBoxSection(num_stations=n, material=ALUMINIUM), promotes_inputs=["*"])
    promoted = ["width", "height", *WALL_NAMES, *STIFFENER_VARS, "panel_length", "F_csn", "M_csn"]
    for name, kw in (("agg", {"ks_rho": 50.0}), ("plain", {})):
        model.add_subsystem(name, PanelFailure(num_times=nt, num_stations=n, material=ALUMINIUM, **kw),
                            promotes_inputs=promoted)
        for prop in SECTION_PROPERTIES:
            model.connect(f"section.{prop}", f"{name}.{prop}")
    model.add_subsystem("ks", KSAggregate(families={f: (nt, n, k) for f, k in PANEL_FAMILIES.items()}, rho_ks=50.0))
    for f in PANEL_FAMILIES:
        model.connect(f"plain.g_{f}", f"ks.g_{f}")
    prob.setup(force_alloc_complex=True)
    rng = np.random.default_rng(11)
    _design(prob, n, rng)
    prob.set_val("nonstructural_mass_per_length", [5.0, 4.0, 3.0])
    prob.set_val("panel_length", rng.uniform(0.4, 0.8, n))
    prob.set_val("F_csn", rng.normal(0, 3e4, (nt, n, 3)))
    prob.set_val("M_csn", rng.normal(0, 1e5, (nt, n, 3)))
    prob.run_model()
    wrt = ["t_upper_skin", "t_front_spar", "h_upper_stiffener", "t_lower_stiffener", "panel_length", "F_csn", "M_csn"]
    agg = prob.compute_totals(of=[f"agg.ks_{f}" for f in PANEL_FAMILIES], wrt=wrt)
    ref = prob.compute_totals(of=[f"ks.ks_{f}" for f in PANEL_FAMILIES], wrt=wrt)
    for f in PANEL_FAMILIES:
        assert prob.get_val(f"agg.ks_{f}")[0] == pytest.approx(prob.get_val(f"ks.ks_{f}")[0], rel=1e-12, abs=1e-14)
        for w in wrt:
            np.testing.assert_allclose(agg[f"agg.ks_{f}", w], ref[f"ks.ks_{f}", w], rtol=1e-10, atol=1e-14)
    data = prob.check_totals(of=[f"agg.ks_{f}" for f in PANEL_FAMILIES], wrt=wrt, method="fd", form="central",
                             step=1e-6, step_calc="rel_avg", out_stream=None)
    for _key, d in data.items():
        j = d["J_fwd"] if "J_fwd" in d else d["J_rev"]
        np.testing.assert_allclose(j, d["J_fd"], rtol=2e-4, atol=1e-5 * max(1.0, np.abs(d["J_fd"]).max()))


def test_sizing_rules_values_and_partials():
    n = 4
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("rules", SizingRules(num_stations=n, adjacency=("t_upper_skin", "h_lower_stiffener")),
                             promotes=["*"])
    prob.setup(force_alloc_complex=True)
    rng = np.random.default_rng(1)
    vals = {name: rng.uniform(1e-3, 5e-2, n) for name in WALL_NAMES + STIFFENER_VARS}
    for k, v in vals.items():
        prob.set_val(k, v)
    prob.run_model()
    np.testing.assert_allclose(prob.get_val("stiffener_aspect_min")[0], 5 * vals["t_upper_stiffener"] - vals["h_upper_stiffener"])
    np.testing.assert_allclose(prob.get_val("stiffener_aspect_max")[1], vals["h_lower_stiffener"] - 30 * vals["t_lower_stiffener"])
    np.testing.assert_allclose(prob.get_val("stiffener_over_skin")[1], vals["t_lower_stiffener"] - 15 * vals["t_lower_skin"])
    np.testing.assert_allclose(prob.get_val("adjacency_t_upper_skin"), np.diff(vals["t_upper_skin"]))
    assert_check_partials(prob.check_partials(method="cs", out_stream=None), atol=1e-12, rtol=1e-10)


def test_rib_mass_by_hand_and_partials():
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("ribs", RibMass(num_nodes=4, rib_weights=[0.0, 1.0, 1.5, 0.5],
                                                          rib_thickness=0.002, density=2700.0),
                             promotes=["*"])
    prob.setup(force_alloc_complex=True)
    prob.set_val("width", [1.0, 0.9, 0.8, 0.7])
    prob.set_val("height", [0.3, 0.28, 0.26, 0.24])
    prob.run_model()
    assert prob.get_val("rib_mass")[0] == pytest.approx(2700 * 0.002 * (0.9 * 0.28 + 1.5 * 0.8 * 0.26 + 0.5 * 0.7 * 0.24))
    assert_check_partials(prob.check_partials(method="cs", out_stream=None), atol=1e-12, rtol=1e-10)


def test_rib_weights_share_ribs_between_stations():
    y = [0.0, 1.0, 2.0, 3.0]
    np.testing.assert_allclose(rib_weights(y, [-1.0, 0.0, 1.0, 1.5, 2.75, 3.0]), [1.0, 1.5, 0.75, 1.75])
    with pytest.raises(ValueError, match="outside the stations"):
        rib_weights(y, [3.5])


def test_rib_pitch_at_stations():
    ribs = [-1.0, 1.0, 1.5, 2.5, 4.0]
    y = [0.0, 1.0, 1.2, 2.5, 3.0, 4.0]
    np.testing.assert_allclose(rib_pitch_at_stations(y, ribs), [2.0, 2.0, 0.5, 1.5, 1.5, 1.5])


@pytest.mark.parametrize("kwargs, match", [
    (dict(rib_positions=(0.0, 1.0), stiffener_pitch=0.0), "stiffener_pitch"),
    (dict(rib_positions=(0.0, 1.0), stiffener_pitch=-0.1), "stiffener_pitch"),
    (dict(rib_positions=(0.0, 1.0), shape="hat"), "shape"),
    (dict(rib_positions=(0.0, 1.0), rib_thickness=float("nan")), "rib_thickness"),
])
def test_panel_layout_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        PanelLayout(**kwargs)


@pytest.mark.parametrize("ribs, y, match", [
    ([0.0, 1.0, 1.0], [0.5], "increase strictly"),
    ([0.0, 1.0], [0.5, 1.5], "outside the ribs"),
    ([0.0], [0.0], "at least two"),
])
def test_rib_positions_bad_input(ribs, y, match):
    with pytest.raises(ValueError, match=match):
        rib_pitch_at_stations(y, ribs)


def test_rib_crushing_ratio_limits():
    """A rib web much wider than deep buckles as a wide column: sigma_cr -> pi^2 E t^2 /
    (12 (1 - nu^2) h^2) (Euler, pinned, unit width); a square web has (1 + 1)^2 = 4 times that.
    The crushing stress is |N kappa| s / t (N the cover load, kappa the curvature, s the spacing)."""
    from wingmdao.panels.layout import rib_crushing_ratio

    E, nu, t, h = 70e9, 0.33, 2e-3, 0.3
    euler = np.pi**2 * E * t**2 / (12 * (1 - nu**2) * h**2)
    n_cover, kappa, s = 1e6, 1e-3, 0.5
    sigma = n_cover * kappa * s / t
    assert rib_crushing_ratio(E, nu, t, h, 1e3 * h, n_cover, kappa, s) == pytest.approx(sigma / euler, rel=1e-5)
    assert rib_crushing_ratio(E, nu, t, h, h, n_cover, kappa, s) == pytest.approx(sigma / (4 * euler), rel=1e-12)
    # the sign of the bending does not matter: both covers crush the rib
    assert rib_crushing_ratio(E, nu, t, h, h, -n_cover, kappa, s) == rib_crushing_ratio(E, nu, t, h, h, n_cover,
                                                                                         kappa, s)


def test_rib_shear_ratio_kinks_and_web_ratio():
    """Rib web in shear: tau = V / (h t) against k_s pi^2 E t^2 / (12 (1 - nu^2) h^2) with
    k_s = 5.35 + 4 (h/w)^2 (Timoshenko & Gere Sec. 9.7, coded here); the ratio scales with
    t^-3. The combined ratio solves R_c/R + (R_s/R)^2 = 1. Kinks: a height lofted linearly
    between stations turns where its slope changes, zero elsewhere and between stations."""
    from wingmdao.panels.layout import cover_kinks, rib_shear_ratio, rib_web_ratio

    E, nu, t, h, w, V = 70e9, 0.33, 3e-3, 0.3, 1.2, 2e4
    tau_cr = (5.35 + 4 * (h / w) ** 2) * np.pi**2 * E * t**2 / (12 * (1 - nu**2) * h**2)
    assert rib_shear_ratio(E, nu, t, h, w, V) == pytest.approx(V / (h * t) / tau_cr, rel=1e-12)
    assert rib_shear_ratio(E, nu, 2 * t, h, w, V) == pytest.approx(rib_shear_ratio(E, nu, t, h, w, V) / 8, rel=1e-12)
    rc, rs = 0.4, 0.7
    r = rib_web_ratio(rc, rs)
    assert rc / r + (rs / r) ** 2 == pytest.approx(1.0, rel=1e-12)
    y = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    hgt = np.array([0.3, 0.3, 0.28, 0.28, 0.27])
    np.testing.assert_allclose(cover_kinks(y, hgt, [0.0, 1.0, 2.0, 2.5, 3.0, 4.0]),
                               [0.0, -0.02, 0.02, 0.0, -0.01, 0.0], atol=1e-12)


def test_transformed_section_equals_a_box_of_the_wall_material():
    """Walls of titanium on an aluminium reference (transformed section) against the same box
    computed in titanium: stiffnesses, torsion, shear areas and mass exactly (weighted walls), the
    shear centre to the thin-wall approximation of the shear-scaled thicknesses."""
    from wingmdao.components.panels import transformed_section
    from wingmdao.materials import TI_6AL_4V
    from wingmdao.panels.stiffened import panel_material

    layer = smeared_stringer(HS, TS, PITCH)
    layout = PanelLayout((0.0, 1.0), skin_material=panel_material(TI_6AL_4V), spar_material=panel_material(TI_6AL_4V))
    e_s, g_s, r_s, e_w, g_w, r_w = layout.wall_factors(ALUMINIUM)
    assert e_s == pytest.approx(TI_6AL_4V.E / ALUMINIUM.E)

    def props_of(weights=(1.0, 1.0), shear=(1.0, 1.0), scale=(1.0, 1.0), rotate=True):
        skin, web = scale
        return box_properties(W, H, TU * skin, TL * skin, TF * web, TR * web, ALUMINIUM, None, 0.0,
                              stringers=tuple((a * skin, d, i * skin) for a, d, i in (layer, layer)),
                              weights=(weights[0], weights[0], weights[1], weights[1]),
                              shear_weights=(shear[0], shear[0], shear[1], shear[1]))

    got = transformed_section(props_of, (e_s, e_w), (g_s, g_w), (r_s, r_w), ALUMINIUM, None, 0.0)
    ref = box_properties(W, H, TU, TL, TF, TR, TI_6AL_4V, stringers=(layer, layer))
    for key in ("EA", "EIxx", "EIzz", "mass_per_length", "n_ea", "c_ea"):
        assert got[key] == pytest.approx(ref[key], rel=1e-12), key
    for key in ("Qx", "Qz"):   # modulus-weighted: Q / I (the shear flow) is the wall material's
        assert got[key] / got["Ixx"] == pytest.approx(ref[key] / ref["Ixx"], rel=1e-12), key
    for key in ("GJ", "compliance_csn"):
        np.testing.assert_allclose(got[key], ref[key], rtol=1e-12)
    assert got["n_sc"] == pytest.approx(ref["n_sc"], abs=1e-3)


def test_laminate_panel_failure_partials():
    """Laminate skins and webs (the MDO Aeroelastic Benchmark's ply and fractions): the panel
    component adds the Tsai-Wu family, and its partials are exact."""
    from wingmdao.panels.laminate import STW_SKIN_FRACTIONS, STW_SPAR_FRACTIONS
    from wingmdao.panels.stiffened import panel_material

    skin, spar = panel_material("stw-cfrp", STW_SKIN_FRACTIONS), panel_material("stw-cfrp", STW_SPAR_FRACTIONS)
    layout = PanelLayout((0.0, 1.0), shape="tee", skin_material=skin, spar_material=spar)
    nt, n = 2, 2
    prob = om.Problem(reports=False)
    kw = dict(shape="tee", wall_factors=layout.wall_factors(ALUMINIUM))
    prob.model.add_subsystem("section", StiffenedBoxSection(num_stations=n, material=ALUMINIUM, **kw),
                             promotes_inputs=["*"])
    prob.model.add_subsystem("panels", PanelFailure(num_times=nt, num_stations=n, material=ALUMINIUM,
                                                    skin_material=skin, spar_material=spar, **kw),
                             promotes_inputs=["width", "height", *WALL_NAMES, *STIFFENER_VARS, "panel_length",
                                              "F_csn", "M_csn"])
    for name in SECTION_PROPERTIES:
        prob.model.connect(f"section.{name}", f"panels.{name}")
    prob.setup()
    rng = np.random.default_rng(8)
    _design(prob, n, rng)
    prob.set_val("nonstructural_mass_per_length", [5.0, 4.0])
    prob.set_val("panel_length", [0.6, 0.7])
    prob.set_val("F_csn", rng.normal(0, 3e4, (nt, n, 3)))
    prob.set_val("M_csn", rng.normal(0, 1e5, (nt, n, 3)))
    prob.run_model()
    assert prob.get_val("panels.g_laminate_strength").shape == (nt, n, 6)
    assert prob.get_val("section.mass_area")[0] < prob.get_val("section.A")[0] * 2   # density 1550 vs 2700
    data = prob.check_partials(method="fd", form="central", step=1e-6, step_calc="rel", out_stream=None)
    assert_check_partials(data, atol=1e-3, rtol=2e-4)  # entries up to ~4e3 (d g / d Ixz): 1e-3 is 3e-7 of them


def test_centre_box_bay_split_at_the_rib_pitch():
    """The CRM's centre-box bay (centreline to the root rib at 10 % semi-span, 2.947 m) is split
    into round(2.947 / 0.824) = 4 equal bays; PEGASUS's (0.983 m, under two pitches of 0.624 m)
    is kept, and so is every rib outboard of the root rib."""
    from wingmdao.cases import crm, pegasus

    peg = pegasus.rib_positions(pegasus.PLANFORM)
    assert peg == tuple(float(y) for y in pegasus.PLANFORM.station_y())
    planform = crm.PLANFORM.station_y()
    ribs = np.asarray(pegasus.rib_positions(crm.PLANFORM))
    assert len(ribs) == len(planform) + 3
    np.testing.assert_allclose(np.diff(ribs[:5]), planform[1] / 4, rtol=1e-12)
    np.testing.assert_allclose(ribs[4:], planform[1:], rtol=1e-12)
    # with --rib-pitch: the centre box at that pitch too
    ribs = np.asarray(pegasus.rib_positions(crm.PLANFORM, rib_pitch=1.0))
    np.testing.assert_allclose(np.diff(ribs[:4]), planform[1] / 3, rtol=1e-12)
