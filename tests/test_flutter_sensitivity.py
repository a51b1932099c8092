"""Eigenvalue derivatives of the aeroelastic pencil and the flutter-damping constraint against
central finite differences of independently recomputed eigenvalues (FlutterDamping check_partials:
tests/test_flutter_damping_partials.py, a module of its own for pytest-xdist --dist loadscope);
check_totals of a small PEGASUS sizing group with the flutter constraint; bad input."""

import numpy as np
import pytest

from wingmdao.stability import eigenmodes, linearize
from wingmdao.stability.cases import flutter_problem, sizing_flutter_options
from wingmdao.stability.sensitivity import (damping_constraint, eigenvalue_gradient, ks_aggregate,
                                            left_right_vectors)
from wingmdao.timemarch.system import layout

DENSE = {"method": "dense"}
#: the 24 smallest |lambda| of the dense solve: lag roots and the lowest bending / torsion modes
DENSE_FEW = {"method": "dense", "count": 24}


def _goland(n=5, alpha=0.0):
    """Goland wing at 5 nodes; ``alpha`` (rad) gives a deformed static state (lift on)."""
    prob = flutter_problem("goland", n)

    def params_at(V):
        p, q = prob.params_at(V)
        if alpha:
            lay = layout(prob.system.param_specs)
            p = p.copy()
            p[lay["alpha_zero_lift"]] = -alpha
        return p, q
    return prob, params_at


def _nearest(prob, p, q, x0, lam, static=True):
    m = eigenmodes(prob.system, p, q, x0, static=static, **DENSE)
    return m.eigenvalues[np.argmin(np.abs(m.eigenvalues - lam))]


@pytest.mark.parametrize("alpha", [0.0, 0.05])
def test_eigenvalue_derivative_matches_central_differences(alpha):
    prob, params_at = _goland(5, alpha)
    p, q = params_at(120.0)
    m = eigenmodes(prob.system, p, q, **DENSE)
    if alpha:  # the static state is deformed: the tip deflects
        assert abs(m.x0.reshape(5, 22)[-1, 2]) > 1e-3
    osc = np.flatnonzero(m.frequency > 1.0)
    A, B = linearize(prob.system, p, q, m.x0)
    lay = layout(prob.system.param_specs)
    entries = [("stiffness_csn", 9 * 2 + 4), ("mass_per_length", 3), ("mass_center", 6), ("airspeed", 0),
               ("inertia_per_length", 9 * 3 + 4)]
    for j in osc[np.argsort(m.frequency[osc])][:2]:   # bending and torsion branches
        v, u, lam = left_right_vectors(A, B, m.eigenvalues[j])
        assert abs(lam - m.eigenvalues[j]) < 1e-8 * abs(lam)
        grad = eigenvalue_gradient(prob.system, p, q, m.x0, lam, v, u, A=A, B=B)
        frozen = eigenvalue_gradient(prob.system, p, q, m.x0, lam, v, u, A=A, B=B, static=False)
        for name, k in entries:
            i = lay[name].start + k
            h = 1e-3 * max(abs(p[i]), 1e-2)
            pp, pm = p.copy(), p.copy()
            pp[i] += h
            pm[i] -= h
            fd = (_nearest(prob, pp, q, m.x0, lam) - _nearest(prob, pm, q, m.x0, lam)) / (2 * h)
            assert abs(grad[i] - fd) <= 2e-3 * abs(fd) + 1e-9 * abs(lam) / h, (name, grad[i], fd)
        if alpha:  # the static-state term is what makes the airspeed derivative right when deformed
            i = lay["airspeed"].start
            assert abs(frozen[i] - grad[i]) > 1e-3 * abs(grad[i])


def test_damping_constraint_gradient_matches_central_differences():
    prob, params_at = _goland(5, 0.02)
    lay = layout(prob.system.param_specs)
    beam_keys = [s.name for s in prob.system.param_specs][:9]

    def params_with(beam):
        def at(V):
            p, q = params_at(V)
            p = p.copy()
            for k in beam_keys:
                p[lay[k]] = np.ravel(beam[k])
            return p, q
        return at

    speeds = [60.0, 110.0, 130.0]
    res = damping_constraint(prob.system, params_with(prob.beam), speeds, aero_mask=prob.aero_mask(),
                             beam_mask=prob.beam_weights(), rho_ks=20.0,
                             **DENSE_FEW)
    sig = np.concatenate(res.eigenvalues).real
    assert res.value > np.max(sig)  # KS >= max
    assert res.value < np.max(sig) + np.log(sig.size) / 20.0
    for name, k in (("stiffness_csn", 9 * 3 + 4), ("mass_center", 4), ("mass_per_length", 2)):
        h = 1e-3 * max(abs(np.ravel(prob.beam[name])[k]), 1e-2)
        vals = []
        for sgn in (1, -1):
            beam = {kk: np.array(vv, dtype=float) for kk, vv in prob.beam.items()}
            beam[name].reshape(-1)[k] += sgn * h
            vals.append(damping_constraint(prob.system, params_with(beam), speeds, aero_mask=prob.aero_mask(),
                                           beam_mask=prob.beam_weights(), rho_ks=20.0, gradient=False,
                                           **DENSE_FEW).value)
        fd = (vals[0] - vals[1]) / (2 * h)
        an = res.gradient[lay[name].start + k]
        assert an == pytest.approx(fd, rel=3e-3, abs=1e-9 / h), name


def test_ks_aggregate():
    g = np.array([-1.0, -0.5, -0.49])
    val, w = ks_aggregate(g, 50.0)
    assert -0.49 < val < -0.49 + np.log(3) / 50.0
    assert w.sum() == pytest.approx(1.0)
    assert w[2] > w[1] > w[0]


def _small_pegasus_sizing(n=6):
    from wingmdao.cases.pegasus import ENGINES, flutter_planform, maneuver_case
    from wingmdao.cases.planform import wing_geometry
    from wingmdao.materials import ALUMINIUM
    from wingmdao.sizing import SizingOptions, WALL_VARS, build_problem

    geo, chord, frac = wing_geometry(flutter_planform(n), ENGINES)
    geo.station_map = None
    case = maneuver_case("maneuver_pos", 2.5, geo, chord, frac, ("vm",))
    flutter = sizing_flutter_options("pegasus", n, 1.15)
    flutter.update(eig_options=DENSE_FEW)
    opts = SizingOptions(lower={w: 1e-3 for w in WALL_VARS}, upper={w: 0.05 for w in WALL_VARS},
                         initial={w: 0.004 for w in WALL_VARS})
    prob, _ = build_problem(geo, [case], ALUMINIUM, opts, driver=False, flutter=flutter)
    rng = np.random.default_rng(3)
    for w in WALL_VARS:
        prob.set_val(w, 0.003 + 0.002 * rng.random(n))
    return prob


@pytest.mark.slow
def test_small_pegasus_sizing_check_totals():
    from wingmdao.sizing import WALL_VARS

    prob = _small_pegasus_sizing(6)
    prob.run_model()
    assert prob.get_val("flutter_ks")[0] < 0.0  # the 10 mm class design does not flutter below 1.15 V_D
    data = prob.check_totals(of=["flutter_ks"], wrt=list(WALL_VARS), method="fd", form="central", step=1e-6,
                             out_stream=None)
    for key, d in data.items():
        J, fd = d.get("J_fwd", d.get("J_rev")), d["J_fd"]
        assert np.abs(fd).max() > 1e-3, key  # the thicknesses do move the damping
        assert np.abs(J - fd).max() <= 3e-3 * np.abs(fd).max() + 1e-8, (key, J, fd)



def test_paused_flutter_evaluates_nothing_and_resumes():
    """The presizing passes run the model with the flutter constraint paused: no eigen-analysis,
    flutter_ks left as it was; afterwards (also after an error inside) it evaluates again."""
    from wingmdao.components.flutter import FlutterDamping, paused_flutter

    prob = _small_pegasus_sizing(4)
    comp = next(prob.model.system_iter(recurse=True, typ=FlutterDamping))
    with paused_flutter(prob) as comps:
        assert comps == [comp]
        prob.run_model()
        assert prob.get_val("flutter_ks")[0] == 0.0 and comp.last_result is None   # the initial value
    prob.run_model()
    assert np.isfinite(prob.get_val("flutter_ks")[0]) and comp.last_result is not None
    with pytest.raises(RuntimeError):
        with paused_flutter(prob):
            raise RuntimeError("interrupted")
    assert not comp.paused

def test_pegasus_flutter_problem_inputs():
    prob = flutter_problem("pegasus")
    assert prob.num_nodes == 20
    assert prob.dive_speed == pytest.approx(0.5 * 316.03 / 0.8, rel=1e-3)  # V_C / 0.8, 25.335(b)(1)
    assert prob.mach_at(prob.dive_speed) == pytest.approx(0.625)
    thin = flutter_problem("pegasus", 5, {w: np.full(5, 0.002) for w in
                                         ("upper_skin", "lower_skin", "front_spar", "rear_spar")})
    thick = flutter_problem("pegasus", 5)
    assert np.all(thin.beam["stiffness_csn"][:, 1, 1] < thick.beam["stiffness_csn"][:, 1, 1])
    with pytest.raises(ValueError, match="3 stations, the 5-node PEGASUS beam needs 5"):
        flutter_problem("pegasus", 5, {w: np.full(3, 0.002) for w in
                                       ("upper_skin", "lower_skin", "front_spar", "rear_spar")})
    with pytest.raises(ValueError, match="missing wall 't_rear_spar'"):
        flutter_problem("pegasus", 5, {w: np.full(5, 0.002) for w in ("upper_skin", "lower_skin", "front_spar")})
    with pytest.raises(ValueError, match="thickness applies to the sized PEGASUS wing only"):
        flutter_problem("goland", 5, {})


def test_flutter_margin_bad_input():
    with pytest.raises(ValueError, match="no aerodynamic data or dive speed"):
        sizing_flutter_options("crm", 20, 1.15)
    with pytest.raises(ValueError, match="no aerodynamic data or dive speed"):
        sizing_flutter_options("goland", 20, 1.15)
    with pytest.raises(ValueError, match=r"allowed range \(0, 3\]"):
        sizing_flutter_options("pegasus", 20, -1.0)
    with pytest.raises(ValueError, match="not subsonic"):
        sizing_flutter_options("pegasus", 20, 1.7)
    opts = sizing_flutter_options("pegasus", 20, 1.15)
    assert opts["speeds"][-1] == pytest.approx(1.15 * flutter_problem("pegasus").dive_speed)


def test_cli_flutter_margin_on_a_case_without_aero(tmp_path, capsys):
    from wingmdao.cli import main

    assert main(["size", "cantilever", "--flutter-margin", "1.15", "--out", str(tmp_path), "--no-plots"]) == 2
    assert "no aerodynamic data" in capsys.readouterr().err


#: wall thicknesses (mm) of the PEGASUS 2.5 g / -1 g strength optimum (`wingmdao size pegasus --loads maneuver`)
STRENGTH_OPTIMUM_MM = {
    "upper_skin": [10.10, 10.10, 7.50, 7.01, 6.14, 5.34, 4.57, 4.10, 3.37, 2.72, 2.14, 1.75, 1.27, 1.00, 1.00, 1.00,
                   1.00, 1.00, 1.00, 1.00],
    "lower_skin": [10.10, 10.10, 7.50, 7.02, 6.14, 5.34, 4.57, 4.10, 3.38, 2.73, 2.15, 1.77, 1.30, 1.00, 1.00, 1.00,
                   1.00, 1.00, 1.00, 1.00],
    "front_spar": [3.52, 3.52, 3.40, 3.55, 3.39, 3.14, 2.84, 2.67, 1.95, 1.67, 1.41, 1.27, 1.05, 1.00, 1.00, 1.00,
                   1.00, 1.00, 1.00, 1.00],
    "rear_spar": [1.00, 1.00, 1.00, 1.00, 1.00, 1.00, 1.00, 1.00, 1.39, 1.24, 1.08, 1.01, 1.00, 1.00, 1.00, 1.00,
                  1.00, 1.00, 1.00, 1.00],
}


def test_constraint_sign_agrees_with_the_flutter_search():
    """The damping constraint up to 0.98 V_F is satisfied and up to 1.02 V_F violated, V_F from the
    independent sweep + Brent search (the MAC-tracked first version missed this flutter)."""
    from wingmdao.stability.cases import CONSTRAINT_SPEED_FRACTIONS, flutter_search

    t = {w: np.asarray(v) * 1e-3 for w, v in STRENGTH_OPTIMUM_MM.items()}
    found = flutter_search("pegasus", 20, t)
    v_f = found["flutter_speed"]
    assert 1.2 * found["dive_speed"] < v_f < 1.45 * found["dive_speed"]
    prob = flutter_problem("pegasus", 20, t)
    for factor, sign in ((0.98, -1.0), (1.02, 1.0)):
        res = damping_constraint(prob.system, prob.params_at, factor * v_f * np.asarray(CONSTRAINT_SPEED_FRACTIONS),
                                 aero_mask=prob.aero_mask(), beam_mask=prob.beam_weights(), gradient=False,
                                 **prob.eig_options)
        assert np.sign(res.value) == sign, (factor, res.value)


@pytest.mark.skipif(__import__("wingmdao.utils.casadi_cache", fromlist=["compiler"]).compiler() is None,
                    reason="needs gcc")
def test_gradient_functions_load_from_the_cache_without_building(monkeypatch, tmp_path):
    """A warm compile cache serves the compiled second-derivative functions by their signature
    stub: no interpreted function is built, and they give the interpreted ones' values."""
    from wingmdao.stability import sensitivity as sens
    from wingmdao.utils import casadi_cache as cc

    monkeypatch.setenv(cc.ENV_JIT, "1")
    monkeypatch.setenv(cc.ENV_CACHE, str(tmp_path))
    prob = flutter_problem("goland", 3)
    cold = sens._GradientFunctions(prob.system)            # cache miss: built, interpreted until compiled
    assert cold._built is not None and cold.pencil.jit.state == "interpreted"
    rng = np.random.default_rng(3)
    n, npar, nq = prob.system.n_state, prob.system.n_param, prob.system.n_forcing
    x, p, q = rng.standard_normal(n), rng.standard_normal(npar), rng.standard_normal(nq)
    v, u = rng.standard_normal(n) + 1j * rng.standard_normal(n), rng.standard_normal(n) + 1j * rng.standard_normal(n)
    ref_p, ref_x = cold.ds(x, p, q, v, u, 0.3 + 2.0j)      # interpreted
    ref = cold.static_term(x, p, q, v)
    assert cc.compile_calls({"pencil": cold.pencil, "vjp": cold.vjp}) == {"pencil": "compiled", "vjp": "compiled"}
    warm = sens._GradientFunctions(prob.system)
    assert warm._built is None and warm.pencil.jit.state == "compiled" and warm.vjp.jit.state == "compiled"
    got_p, got_x = warm.ds(x, p, q, v, u, 0.3 + 2.0j)
    np.testing.assert_allclose(got_p, ref_p, rtol=1e-12, atol=1e-12 * np.abs(ref_p).max())
    np.testing.assert_allclose(got_x, ref_x, rtol=1e-12, atol=1e-12 * np.abs(ref_x).max())
    np.testing.assert_allclose(warm.static_term(x, p, q, v), ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())
    assert warm._built is None
    assert warm.interpreted.name() == cold.interpreted.name()   # built on demand
