"""The aeroelastic beam with the vortex-lattice quasi-steady lift (aero_theory="vlm").

Checks: the diagonal influence of strip theory reproduces the strip residual (wiring); a rigid
rectangular wing's root shear and bending moment are the vortex lattice's spanload (whose lift
slope tests/test_vlm.py checks against Kinner's exact circular wing, DATCOM and the lifting line),
and the 3-D root shear lies below the strip theory's by the lattice's lift slope against 2 pi;
check_partials of the component; adjoint totals of a gust KS of the root bending moment against
central differences.
"""

import numpy as np
import pytest

from wingmdao.aero import aero_parameters, cached_aeroelastic_system
from wingmdao.aero.coupled import CoupledAero
from wingmdao.aero.vlm import station_influence
from wingmdao.beam.static import beam_forcing, beam_parameters, straight_beam
from wingmdao.timemarch.bdf import march, solve_static
from wingmdao.timemarch.system import layout, pack

RHO, V = 1.2, 20.0


def _wing(n, span=4.0, chord=1.0, GJ=1e9, EI=1e9, mass=1e-3, theory="vlm", influence=None, **aero):
    r0, th0 = straight_beam(n, span)
    bp = beam_parameters(r0, th0, EI_cc=EI, GJ=GJ, EI_nn=10 * EI, EA=100 * EI, mass_per_length=mass)
    kw = dict(chord=chord, ref_point=0.25, airspeed=V, density=RHO)
    kw.update(aero)
    ap = aero_parameters(n, **kw)
    s = cached_aeroelastic_system(n, aero_theory=theory)
    if theory == "vlm":
        if influence is None:
            inf = station_influence(r0, ap["chord"], ap["ref_point"], mach=ap["mach"])
            influence = (inf.lift, inf.moment)
        ap.update(lift_influence=influence[0], moment_influence=influence[1])
    qd = beam_forcing(n)
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3))
    return s, pack(s.param_specs, {**bp, **ap}), pack(s.forcing_specs, qd), r0


def test_diagonal_influence_reproduces_strip_theory():
    n, mach = 4, 0.4
    c = np.array([1.4, 1.2, 1.0, 0.8])
    diag = (np.diag(c * 2 * np.pi / np.sqrt(1 - mach ** 2)), np.zeros((n, n)))
    kw = dict(span=2.0, chord=c, GJ=3e4, EI=5e4, mass=5.0, ref_point=0.4, alpha_zero_lift=-0.02, mach=mach)
    sv, pv, qv, _ = _wing(n, influence=diag, **kw)
    ss, ps, qs, _ = _wing(n, theory="strip", **kw)
    t = np.arange(30) * 0.01
    wg = 3.0 * 0.5 * (1 - np.cos(2 * np.pi * t / 0.2)) * (t <= 0.2)
    Qv, Qs = np.tile(qv, (t.size, 1)), np.tile(qs, (t.size, 1))
    Qv[:, layout(sv.forcing_specs)["gust_velocity"]] = wg[:, None]
    Qs[:, layout(ss.forcing_specs)["gust_velocity"]] = wg[:, None]
    hv, hs = march(sv, t, pv, Qv), march(ss, t, ps, Qs)
    np.testing.assert_allclose(hv.states, hs.states, rtol=0, atol=1e-10 * np.max(np.abs(hs.states)))


def test_rigid_rectangular_wing_root_loads_are_the_lattice_spanload():
    n, span, alpha, mach = 11, 3.0, 0.04, 0.5
    s, p, q, r0 = _wing(n, span=span, chord=1.0, alpha_zero_lift=-alpha, mach=mach)
    x, _ = solve_static(s, p, q)
    X = s.layout.beam_states(x)
    qdyn = 0.5 * RHO * V ** 2
    inf = station_influence(r0, np.ones(n), np.full(n, 0.25), mach=mach)
    cl_a = inf.lift_slope(2 * span)
    # root shear of the half wing = q (S / 2) CL_alpha alpha
    np.testing.assert_allclose(X[0, 8], qdyn * span * cl_a * alpha, rtol=1e-6)
    # below strip theory by the 3-D lift slope (aspect ratio 6 at M 0.5: DATCOM 4.98 /rad, 0.69 of 2 pi / beta)
    strip = qdyn * span * 2 * np.pi / np.sqrt(1 - mach ** 2) * alpha
    assert 0.6 < X[0, 8] / strip < 0.7
    # root bending: the spanload's centroid lies inboard of strip theory's (tip loss)
    assert X[0, 9] / X[0, 8] < 0.5 * span


def test_coupled_aero_builds_the_influence_and_refuses_bad_theory():
    n = 5
    r0, _ = straight_beam(n, 3.0)
    aero = CoupledAero(chord=1.0, airspeed=V, density=RHO, mach=0.3, aero_theory="vlm", node_positions=r0)
    par = aero.parameters(n)
    assert par["lift_influence"].shape == (n, n) and par["moment_influence"].shape == (n, n)
    ll = CoupledAero(chord=1.0, airspeed=V, density=RHO, aero_theory="lifting-line", node_positions=r0).parameters(n)
    assert np.all(ll["lift_slope"][:-1] < 2 * np.pi) and ll["lift_slope"][0] > 0.7 * 2 * np.pi
    with pytest.raises(ValueError, match="aero_theory = 'dlm'; allowed: strip, lifting-line, vlm"):
        CoupledAero(chord=1.0, airspeed=V, density=RHO, aero_theory="dlm", node_positions=r0).parameters(n)
    with pytest.raises(ValueError, match="needs node_positions"):
        CoupledAero(chord=1.0, airspeed=V, density=RHO, aero_theory="vlm").parameters(n)
    with pytest.raises(ValueError, match="aero_theory must be one of strip, vlm"):
        cached_aeroelastic_system(n, aero_theory="lifting-line")


# ----------------------------------------------------------------------------- component
def _problem(n=3, n_time=6, dt=0.01, mode="rev"):
    import openmdao.api as om

    from wingmdao.components.aeroelastic import AeroelasticBeamDynamics

    s, p, q, r0 = _wing(n, span=2.0, GJ=2e4, EI=5e4, mass=5.0, ref_point=0.4, alpha_zero_lift=-0.02, mach=0.3)
    t = np.arange(n_time) * dt
    prob = om.Problem()
    comp = AeroelasticBeamDynamics(num_nodes=n, time=t, matrix_free=False, aero_theory="vlm")
    prob.model.add_subsystem("beam", comp, promotes=["*"])
    rho_ks = 1e-3  # per (N m): the KS of the root bending moment history (a smooth maximum)

    class RootMomentKS(om.ExplicitComponent):
        """ks = max + ln(sum exp(rho (M_x,root(t) - max))) / rho (N m)."""

        def setup(self):
            self.add_input("states", shape=(n_time,) + s.state_shape, desc="state history")
            self.add_output("ks", units="N*m", desc="KS of the root bending moment history")
            self.declare_partials("ks", "states", rows=np.zeros(n_time, int), cols=np.arange(n_time) * s.n_state + 9)

        def _m(self, inputs):
            return inputs["states"].reshape(n_time, -1)[:, 9]

        def compute(self, inputs, outputs):
            m = self._m(inputs)
            outputs["ks"] = m.max() + np.log(np.sum(np.exp(rho_ks * (m - m.max())))) / rho_ks

        def compute_partials(self, inputs, partials):
            m = self._m(inputs)
            w = np.exp(rho_ks * (m - m.max()))
            partials["ks", "states"] = w / w.sum()

    prob.model.add_subsystem("agg", RootMomentKS(), promotes=["*"])
    prob.setup(mode=mode)
    for spec, sl in zip(s.param_specs, layout(s.param_specs).values()):
        prob.set_val(spec.name, p[sl].reshape(spec.shape or (1,)))
    wg = 2.0 * 0.5 * (1 - np.cos(2 * np.pi * t / (n_time * dt)))
    prob.set_val("gust_velocity", np.tile(wg[:, None], (1, n)))
    prob.set_val("gravity", np.tile([0.0, 0.0, -9.81], (n_time, 1)))
    return prob


def test_component_check_partials_vlm():
    prob = _problem(n_time=4)
    prob.run_model()
    data = prob.check_partials(out_stream=None, method="fd", step=1e-6, form="central", includes=["beam"])
    for (of, wrt), d in data["beam"].items():
        fd, an = d["J_fd"], d["J_fwd"]
        scale = max(np.max(np.abs(fd)), 1e-8)
        assert np.max(np.abs(an - fd)) <= 2e-5 * scale + 1e-6, (of, wrt)


def test_adjoint_totals_of_gust_ks_vs_central_differences():
    # steps ~1e-5 of each input's size (the KS is ~1e3 N m: smaller steps meet round-off)
    steps = {"stiffness_csn": 0.5, "airspeed": 2e-4, "density": 1e-5, "lift_influence": 1e-5}
    prob = _problem(mode="rev")
    prob.run_model()
    rev = prob.compute_totals(of=["ks"], wrt=list(steps))
    for w, h in steps.items():
        fd = prob.check_totals(of=["ks"], wrt=[w], method="fd", form="central", step=h, out_stream=None)
        ref = fd[("ks", w)]["J_fd"]
        scale = np.max(np.abs(ref))
        assert scale > 0, w
        np.testing.assert_allclose(rev[("ks", w)], ref, rtol=0, atol=1e-5 * scale, err_msg=w)


def test_aero_theory_choices_are_spelled_once():
    from wingmdao.aero.coupled import AERO_THEORY_CHOICES
    from wingmdao.cases.pegasus import AERO_THEORIES
    from wingmdao.cli._args import AERO_THEORY_CHOICES as CLI_CHOICES

    assert AERO_THEORY_CHOICES == CLI_CHOICES
    # the PEGASUS sizing adds the doublet lattice of its coupled gust (the modal basis, docs/aerodynamics-3d.md)
    assert AERO_THEORIES == AERO_THEORY_CHOICES + ("dlm",)


def test_aero_theory_needs_coupled_aero():
    from wingmdao.cases import pegasus

    with pytest.raises(ValueError, match="--aero-theory vlm applies to --aero coupled"):
        pegasus.build(aero="strip", aero_theory="vlm")


def test_coupled_default_is_the_lattice_and_flutter_stays_strip():
    """--aero coupled without --aero-theory: the vortex lattice on the case (size) and on gust and
    turbulence; --aero strip: the precomputed strip loads; the flutter command: strip theory."""
    import argparse

    from wingmdao.cases import DEFAULT_COUPLED_THEORY, pegasus, resolve_aero_theory
    from wingmdao.cli import build_parser

    assert DEFAULT_COUPLED_THEORY == "vlm"
    assert {c.aero.aero_theory for c in pegasus.build(aero="coupled").load_cases} == {"vlm"}
    assert {c.aero.aero_theory for c in pegasus.build(aero="coupled", aero_theory="strip").load_cases} == {"strip"}
    assert all(c.aero is None for c in pegasus.build(aero="strip").load_cases)
    assert resolve_aero_theory(None, "coupled") == "vlm" and resolve_aero_theory(None, "strip") == "strip"
    assert resolve_aero_theory("lifting-line", "coupled") == "lifting-line"
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices
    for cmd in ("gust", "turbulence"):
        assert sub[cmd].parse_args(["pegasus"]).aero_theory is None  # resolved with --aero
        assert sub[cmd].parse_args(["pegasus", "--aero-theory", "strip"]).aero_theory == "strip"
    assert sub["flutter"].parse_args(["goland"]).aero_theory == "strip"


@pytest.mark.parametrize("cmd", ["gust", "turbulence"])
def test_three_dimensional_theory_with_strip_loads_is_refused(cmd, capsys):
    from wingmdao.cli import main

    assert main([cmd, "pegasus", "--aero", "strip", "--aero-theory", "vlm", "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert "--aero-theory vlm applies to --aero coupled" in err and "Traceback" not in err
