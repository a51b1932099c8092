"""wingmdao beam as OpenAeroStruct's structural solver: conventions, partials, and the linear-range
comparison with OpenAeroStruct's own spatial beam (wingbox model) on the same wing."""

import numpy as np
import openmdao.api as om
import pytest

pytest.importorskip("openaerostruct")

from wingmdao.materials import ALUMINIUM as MAT  # noqa: E402
from wingmdao.oas import BeamToOASDisp, OASBeamStates, OASThicknessToBox, OASToBeamLoads  # noqa: E402

RNG = np.random.default_rng(7)


def test_load_mirror_and_order():
    n = 4
    L = RNG.normal(size=(n, 6))
    p = om.Problem(reports=False)
    p.model.add_subsystem("c", OASToBeamLoads(num_nodes=n))
    p.setup()
    p.set_val("c.loads", L)
    p.run_model()
    # beam root (0) is OAS node n-1; force (x, -y, z); moment (-x, y, -z)
    assert np.allclose(p.get_val("c.point_force")[0], L[-1, :3] * [1, -1, 1])
    assert np.allclose(p.get_val("c.point_moment")[-1], L[0, 3:] * [-1, 1, -1])


def test_coupling_partials():
    n = 5
    x0 = np.column_stack([np.full(n, 0.7), np.linspace(0, 10, n), np.zeros(n)])
    from wingmdao.mphys.builder import jig_euler_angles

    p = om.Problem(reports=False)
    p.model.add_subsystem("l", OASToBeamLoads(num_nodes=n))
    p.model.add_subsystem("d", BeamToOASDisp(node_positions=x0, node_euler_angles=jig_euler_angles(x0)))
    p.model.add_subsystem("t", OASThicknessToBox(num_nodes=n))
    p.setup(force_alloc_complex=True)
    p.set_val("l.loads", RNG.normal(size=(n, 6)))
    p.set_val("d.wingmdao_states", RNG.normal(size=(n, 18)))
    p.set_val("t.spar_thickness", RNG.uniform(0.002, 0.01, n - 1))
    p.set_val("t.skin_thickness", RNG.uniform(0.002, 0.01, n - 1))
    p.run_model()
    for comp, d in p.check_partials(method="cs", out_stream=None).items():
        for key, v in d.items():
            assert np.abs(v["J_fwd"] - v["J_fd"]).max() <= 1e-12, (comp, key)


def test_right_wing_nodes_rejected():
    nodes = np.column_stack([np.zeros(3), np.linspace(0, 5, 3), np.zeros(3)])
    p = om.Problem(reports=False)
    p.model.add_subsystem("s", OASBeamStates(fem_nodes=nodes, width=np.ones(2), height=np.ones(2), material=MAT))
    with pytest.raises(ValueError, match="left half-wing"):
        p.setup()


def _rect_wingbox_surface(ny, span, chord, h_c, t):
    from openaerostruct.meshing.mesh_generator import generate_mesh

    mesh = generate_mesh({"num_y": 2 * ny - 1, "num_x": 2, "wing_type": "rect", "symmetry": True,
                          "span": span, "root_chord": chord})
    # a flat-topped "airfoil" between 10 % and 60 % chord: OpenAeroStruct's wingbox is then a rectangle
    return {"name": "wing", "symmetry": True, "fem_model_type": "wingbox", "mesh": mesh,
            "spar_thickness_cp": np.array([t, t]), "skin_thickness_cp": np.array([t, t]),
            "t_over_c_cp": np.array([h_c]), "original_wingbox_airfoil_t_over_c": h_c,
            "data_x_upper": np.array([0.1, 0.6]), "data_y_upper": np.array([h_c / 2, h_c / 2]),
            "data_x_lower": np.array([0.1, 0.6]), "data_y_lower": np.array([-h_c / 2, -h_c / 2]),
            "E": MAT.E, "G": MAT.G, "yield": MAT.sigma_y, "mrho": MAT.rho, "fem_origin": 0.35,
            "wing_weight_ratio": 1.0, "struct_weight_relief": False, "distributed_fuel_weight": False,
            "exact_failure_constraint": False, "strength_factor_for_upper_skin": 1.0,
            "twist_cp": np.zeros(2), "t_over_c": h_c}


def test_linear_range_matches_oas_spatial_beam():
    """Same wing, same loads (roughly uniform lift, tip deflection 1.5 % of the semispan), same box:
    tip deflection and tip rotation within 1 %, root bending moment equal to the statics of the
    loads within 0.1 %. The remaining differences are ours: transverse shear (Timoshenko vs
    OpenAeroStruct's Euler-Bernoulli element, +0.2 % here) and geometric nonlinearity
    (foreshortening, a tip y-displacement OpenAeroStruct's linear beam does not have)."""
    from openaerostruct.structures.struct_groups import SpatialBeamAlone

    ny, span, chord, h_c = 11, 20.0, 2.0, 0.12
    surf = _rect_wingbox_surface(ny, span, chord, h_c, 0.004)
    P = np.zeros((ny, 6))
    P[:, 2] = 2000.0
    P[0, 2] = 1000.0
    p = om.Problem(reports=False)
    p.model.add_subsystem("oas", SpatialBeamAlone(surface=surf))
    p.setup()
    p.set_val("oas.loads", P)
    p.run_model()
    d_oas, nodes = p.get_val("oas.disp"), p.get_val("oas.nodes")

    q = om.Problem(reports=False)
    q.model.add_subsystem("ours", OASBeamStates(fem_nodes=nodes, width=np.full(ny - 1, 0.5 * chord),
                                                height=np.full(ny - 1, h_c * chord), material=MAT))
    q.setup()
    q.set_val("ours.loads", P)
    q.set_val("ours.spar_thickness", p.get_val("oas.spar_thickness"))
    q.set_val("ours.skin_thickness", p.get_val("oas.skin_thickness"))
    q.run_model()
    d = q.get_val("ours.disp")
    assert d[0, 2] == pytest.approx(d_oas[0, 2], rel=0.01)        # 0.3001 vs 0.2993 m: +0.28 %
    assert d[0, 3] == pytest.approx(d_oas[0, 3], rel=0.01)        # -0.03995 vs -0.03997 rad
    assert d[0, 2] > d_oas[0, 2]                                  # shear flexibility adds deflection
    root_moment = q.get_val("ours.wingmdao_states")[0, 9]
    statics = -np.sum(P[:, 2] * (nodes[:, 1] - nodes[-1, 1]))     # 100 kN m
    assert root_moment == pytest.approx(statics, rel=1e-3)


@pytest.fixture(scope="module")
def points():
    from wingmdao.oas.problems import aerostruct_problem, rect_wingbox_surface

    out = {}
    for beam in ("oas", "wingmdao"):
        p = aerostruct_problem(rect_wingbox_surface(), beam=beam)
        p.run_model()
        out[beam] = p
    return out


def test_aerostruct_point_with_our_beam_matches_oas_beam(points):
    """Coupled VLM + beam, tip deflection 2.4 % of the semispan: tip deflection within 1 % of
    OpenAeroStruct's beam (+0.17 %: shear and nonlinearity), CL within 0.5 %, < 25 iterations."""
    ours, oas = points["wingmdao"], points["oas"]
    assert ours.model.AS_point_0.coupled.nonlinear_solver._iter_count < 25
    d, d_oas = ours.get_val("AS_point_0.coupled.wing.disp"), oas.get_val("AS_point_0.coupled.wing.disp")
    assert d[0, 2] == pytest.approx(d_oas[0, 2], rel=0.01)
    assert d[0, 3] == pytest.approx(d_oas[0, 3], rel=0.01)
    assert ours.get_val("AS_point_0.CL")[0] == pytest.approx(oas.get_val("AS_point_0.CL")[0], rel=5e-3)


def test_point_wiring_matches_oas_aerostruct_point(points):
    """WingmdaoAerostructPoint (composed from OpenAeroStruct's public components) feeds every input
    outside the structural solver from the same source as OpenAeroStruct's own AerostructPoint."""
    def inputs(model):
        return {n for n, _ in model.list_inputs(out_stream=None) if ".struct_states." not in n}

    def source(model, name):
        s = model.get_source(name)
        if s.startswith("_auto_ivc."):
            return "auto_ivc"
        head, sep, _ = s.partition(".struct_states.")
        return head + sep + s.rsplit(".", 1)[1] if sep else s   # disp: the structural solver's output

    ours, oas = points["wingmdao"].model, points["oas"].model
    names = inputs(oas)
    assert names == inputs(ours)
    assert [n for n in names if source(ours, n) != source(oas, n)] == []


def test_point_results_unchanged_by_public_api_rewrite(points):
    """Regression against the earlier point (commit 8742f6e: OpenAeroStruct's AerostructPoint with
    its coupled surface's class swapped through private OpenMDAO attributes), rectangular wing."""
    p = points["wingmdao"]
    assert p.get_val("AS_point_0.fuelburn")[0] == pytest.approx(20773.715045945657, rel=1e-9)
    assert p.get_val("wing.structural_mass")[0] == pytest.approx(532.224, rel=1e-12)
    assert p.get_val("AS_point_0.coupled.wing.disp")[0, 2] == pytest.approx(0.4725006922618921, rel=1e-8)
    assert p.get_val("AS_point_0.CL")[0] == pytest.approx(0.3568561560838396, rel=1e-9)


@pytest.mark.parametrize("key, value", [("struct_weight_relief", True), ("distributed_fuel_weight", True),
                                        ("fem_model_type", "tube")])
def test_point_rejects_unsupported_surface(key, value):
    from wingmdao.oas.problems import aerostruct_problem, rect_wingbox_surface

    surf = rect_wingbox_surface(num_y=3)
    surf[key] = value
    with pytest.raises(ValueError, match=key):
        aerostruct_problem(surf, beam="wingmdao")


def test_aerostruct_point_totals(points):
    p = points["wingmdao"]
    data = p.check_totals(of=["AS_point_0.CL", "AS_point_0.fuelburn", "AS_point_0.wing_perf.failure"],
                          wrt=["wing.twist_cp", "wing.spar_thickness_cp", "wing.skin_thickness_cp", "alpha"],
                          method="fd", step=1e-6, form="central", out_stream=None)
    for key, v in data.items():
        J, F = v["J_rev"], v["J_fd"]
        nontrivial = np.abs(F) > 1e-6 * np.abs(F).max()
        assert np.all(np.abs(J - F)[nontrivial] <= 1e-4 * np.abs(F)[nontrivial]), key


@pytest.mark.slow
def test_crm_analysis_only_json(tmp_path):
    import json
    import runpy

    mod = runpy.run_path(str(__import__("pathlib").Path(__file__).parents[1] / "cases" / "run_aerostruct_crm.py"),
                         run_name="crm")
    out = tmp_path / "crm.json"
    mod["main"](["--analysis-only", "--json", str(out)])
    res = json.loads(out.read_text())
    for d in (res, res["oas_beam"]):
        for k in ("fuelburn_kg", "wing_mass_kg", "tip_deflection_m"):
            assert np.isfinite(d[k]) and d[k] > 0, k
        assert max(d["coupled_iterations"].values()) < 25
    assert res["wing_mass_kg"] == pytest.approx(res["oas_beam"]["wing_mass_kg"], rel=1e-12)  # same geometry
    assert res["fuelburn_kg"] == pytest.approx(res["oas_beam"]["fuelburn_kg"], rel=0.03)
    # unchanged by the public-API point (regression against commit 8742f6e's class-swapped point)
    assert res["fuelburn_kg"] == pytest.approx(89412.16368701155, rel=1e-9)
    assert res["wing_mass_kg"] == pytest.approx(25767.69436468528, rel=1e-12)
    assert res["tip_deflection_m"] == pytest.approx(1.4362992228870846, rel=1e-8)


def test_box_dims_partials_and_values():
    """OASBoxDims: width = hfront + hrear, height = htop + hbottom, element -> node averaging."""
    from wingmdao.oas.coupling import OASBoxDims

    n = 5
    p = om.Problem(reports=False)
    p.model.add_subsystem("b", OASBoxDims(num_nodes=n))
    p.setup(force_alloc_complex=True)
    h = {k: RNG.uniform(0.05, 0.3, n - 1) for k in ("htop", "hbottom", "hfront", "hrear")}
    for k, v in h.items():
        p.set_val(f"b.{k}", v)
    p.run_model()
    # OAS elements run tip first; node i (root first) averages its adjacent elements
    w_el = (h["hfront"] + h["hrear"])[::-1]
    ref = np.concatenate([[w_el[0]], 0.5 * (w_el[:-1] + w_el[1:]), [w_el[-1]]])
    np.testing.assert_allclose(p.get_val("b.width"), ref, rtol=1e-12)
    for comp, d in p.check_partials(method="cs", out_stream=None).items():
        for key, v in d.items():
            assert v["abs error"].forward < 1e-10, (comp, key)
