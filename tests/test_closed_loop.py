"""Closed-loop stability constraint (wingmdao.components.closed_loop): its sign against the
stability limit of the bending feedback that the march confirms (tests/test_controls_system.py),
exact partials, and the PEGASUS co-design constraint that rejects a destabilizing law."""

import os

import numpy as np
import openmdao.api as om
import pytest
import scipy.linalg as sla

from wingmdao.aero import aero_parameters, cached_aeroelastic_system
from wingmdao.aero.controls import ControlLaw, ControlSurface, control_spec
from wingmdao.beam.static import beam_forcing, beam_parameters, straight_beam
from wingmdao.components.closed_loop import ClosedLoopDamping, closed_loop_forcing, closed_loop_modes
from wingmdao.stability.eigen import linearize, static_state
from wingmdao.timemarch.system import layout, pack
from wingmdao.utils.ks import ks_aggregate

K_STAR = 163.0  # the bending feedback's stability limit of tests/test_controls_system.py (march-checked)


def _flexible_wing(n=5):
    r0, th0 = straight_beam(n, 4.0)
    bp = beam_parameters(r0, th0, EI_cc=5e4, GJ=2e4, EI_nn=5e5, EA=5e6, mass_per_length=5.0)
    ap = aero_parameters(n, chord=1.0, ref_point=0.4, airspeed=20.0, density=1.2)
    law = ControlLaw(("root_bending",), A=[], B=[], C=[], D=[[1.0]])
    spec = control_spec([ControlSurface("aileron", hinge=0.75, span=(0.5, 1.0), time_constant=0.02)], r0[:, 1], law)
    s = cached_aeroelastic_system(n, controls=spec)
    return s, lambda K: pack(s.param_specs, {**bp, **ap, **law.matrices(), "controller_D": np.array([[K]])})


def test_constraint_sign_at_the_stability_limit():
    """Below the limit every selected mode decays (KS < 0), above it the real branch the march
    shows growing at about 1.04 1/s (1.15 K*) makes the KS positive and equal to it."""
    s, params = _flexible_wing()
    x0 = static_state(s, params(0.0), closed_loop_forcing(s))
    for K, sign in ((0.0, -1), (0.7 * K_STAR, -1), (1.15 * K_STAR, 1), (1.3 * K_STAR, 1)):
        lam = closed_loop_modes(s, params(K), x0)[0]
        ks = ks_aggregate(lam.real, 100.0)[0]
        assert np.sign(ks) == sign, (K, ks)
    lam = closed_loop_modes(s, params(1.15 * K_STAR), x0)[0]
    assert ks_aggregate(lam.real, 100.0)[0] == pytest.approx(1.06, abs=0.03)


def _dense_selection(s, p, x0, max_frequency_hz=50.0):
    """The selected eigenvalues by SciPy's dense QZ solve of the whole pencil (the reference)."""
    A, B = linearize(s, p, closed_loop_forcing(s), x0)
    lam, vr = sla.eig(-A.toarray(), B.toarray())
    lay = s.layout
    beam = lay.beam[:, 0:6].ravel()
    other = np.concatenate([lay.aero.ravel(), np.asarray([lay.body[k] for k in s.control_index], dtype=int)])
    keep = np.isfinite(lam) & (np.abs(lam) < 1e6) & (np.abs(lam) > 1e-6) & (lam.imag >= 0.0)
    keep &= (np.abs(lam.imag) <= 2 * np.pi * max_frequency_hz)
    keep &= np.linalg.norm(vr[other], axis=0) > 1e-2 * np.linalg.norm(vr[beam], axis=0)
    return lam[keep]


def _assert_same_modes(s, p, x0, depth):
    """closed_loop_modes (eigenvalues of (A + sigma B)^-1 B, vectors by inverse iteration) selects
    the dense solve's eigenvalues to 1e-8 relative, each with vectors whose residual is round-off;
    with ``depth`` exactly those within ``depth`` of the largest real part."""
    ref = _dense_selection(s, p, x0)
    lam, v, u, A, B = closed_loop_modes(s, p, x0)
    assert lam.size == ref.size
    for x in lam:
        assert np.min(np.abs(ref - x)) <= 1e-8 * abs(x), x
    for y in ref:
        assert np.min(np.abs(lam - y)) <= 1e-8 * abs(y), y
    res = np.linalg.norm(A @ v + (B @ v) * lam, axis=0) / (abs(A).sum(axis=0).max() + np.abs(lam) * abs(B).sum(axis=0).max())
    resl = np.linalg.norm(A.T @ u.conj() + (B.T @ u.conj()) * lam, axis=0)
    assert res.max() < 1e-12 and resl.max() < 1e-8 * (abs(A).sum(axis=1).max() + np.abs(lam).max() * abs(B).sum(axis=1).max())
    near = closed_loop_modes(s, p, x0, depth=depth)[0]
    expect = ref[ref.real >= ref.real.max() - depth]
    assert near.size == expect.size, (near, expect)
    return ref


def test_modes_equal_dense_solve_across_the_stability_limit():
    """The sparse-LU eigen-solve against the dense QZ solve for gains from none to beyond the limit,
    two of them 1 % either side of it."""
    s, params = _flexible_wing()
    x0 = static_state(s, params(0.0), closed_loop_forcing(s))
    tops = []
    for K in (0.0, 0.5 * K_STAR, 0.99 * K_STAR, 1.01 * K_STAR, 1.3 * K_STAR):
        tops.append(_assert_same_modes(s, params(K), x0, 0.4).real.max())
    assert tops[0] < 0.0 and tops[-1] > 0.0, tops


def test_dense_fallback_gives_the_same_selection(monkeypatch):
    """Without a usable shift the evaluation takes the dense QZ solve with vectors: the same modes."""
    import wingmdao.components.closed_loop as cl

    s, params = _flexible_wing()
    x0 = static_state(s, params(0.0), closed_loop_forcing(s))
    fast = np.sort_complex(closed_loop_modes(s, params(0.99 * K_STAR), x0)[0])
    monkeypatch.setattr(cl, "SHIFTS", ())
    dense = np.sort_complex(closed_loop_modes(s, params(0.99 * K_STAR), x0)[0])
    assert dense.size == fast.size and np.allclose(dense, fast, rtol=1e-8, atol=0.0)


def test_check_partials_free_plunge_trimmed():
    """Free plunge, trimmed, load-factor and root-bending feedback through a filter: partials
    with respect to every parameter (gains, stiffness, body mass) and the trimmed state."""
    n = 3
    r0, th0 = straight_beam(n, 2.0)
    bp = beam_parameters(r0, th0, EI_cc=5e4, GJ=2e4, EI_nn=5e5, EA=5e6, mass_per_length=5.0)
    ap = aero_parameters(n, chord=1.0, ref_point=0.4, airspeed=20.0, density=1.2, mach=0.3, alpha_zero_lift=-0.02)
    law = ControlLaw(("load_factor", "root_bending"), A=[[-6.0]], B=[[6.0, 0.0]], C=[[-0.3]], D=[[0.0, 20.0]])
    spec = control_spec([ControlSurface("aileron", hinge=0.75, nodes=(1, 2), actuator_order=2, frequency_hz=8.0)],
                        r0[:, 1], law)
    s = cached_aeroelastic_system(n, plunge=True, trim=True, controls=spec)
    values = {**bp, **ap, **law.matrices(), "body_mass": 200.0, "trim_lift": 200.0 * 9.81 + 2 * 5.0 * 2.0 * 9.81}
    qd = beam_forcing(n)
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3),
              surface_command=np.zeros(1), trim_active=1.0, gravity=np.array([0.0, 0.0, -9.81]))
    x0 = static_state(s, pack(s.param_specs, values), pack(s.forcing_specs, qd))
    prob = om.Problem()
    prob.model.add_subsystem("cl", ClosedLoopDamping(system=s, rho_ks=20.0), promotes=["*"])
    prob.setup(force_alloc_complex=False)
    for sp in s.param_specs:
        prob.set_val(sp.name, np.asarray(values[sp.name]).reshape(sp.shape or (1,)))
    prob.set_val("trimmed_state", x0)
    prob.run_model()
    assert prob.get_val("closed_loop_ks")[0] < 0.0
    names = [sp.name for sp in s.param_specs] + ["trimmed_state"]
    J = prob.compute_totals(of=["closed_loop_ks"], wrt=names, return_format="flat_dict")
    p0 = pack(s.param_specs, values)
    lay = layout(s.param_specs)

    def ks(p, x):
        return ks_aggregate(closed_loop_modes(s, p, x)[0].real, 20.0)[0]

    # central differences, each entry stepped by 1e-4 of its size (zeros: 1e-4 of its input's largest
    # entry, 1e-5 for the state's angles): the derivative times the step, so entries of every unit compare
    worst, big = 0.0, 0.0
    for nm in names:
        base = x0 if nm == "trimmed_state" else p0[lay[nm]]
        ref = max(np.abs(base).max(), 1e-3)
        jac = np.asarray(J[("closed_loop_ks", nm)]).ravel()
        for j in range(base.size):
            h = 1e-4 * abs(base[j]) if base[j] != 0.0 else (1e-5 if nm == "trimmed_state" else 1e-4 * ref)
            plus, minus = base.copy(), base.copy()
            plus[j] += h
            minus[j] -= h
            if nm == "trimmed_state":
                fd = (ks(p0, plus) - ks(p0, minus)) / (2 * h)
            else:
                pp, pm = p0.copy(), p0.copy()
                pp[lay[nm]], pm[lay[nm]] = plus, minus
                fd = (ks(pp, x0) - ks(pm, x0)) / (2 * h)
            worst = max(worst, abs(jac[j] - fd) * h)
            big = max(big, abs(fd) * h)
    assert big > 0 and worst <= 1e-3 * big, (worst, big)


EXAMPLE = os.path.join(os.path.dirname(__file__), "..", "docs", "examples", "pegasus_alleviation.yaml")


@pytest.mark.slow
def test_pegasus_co_design_constraint(tmp_path):
    """--size-gains adds closed_loop_ks <= 0: negative for the file's filtered law, positive for
    the pure gain -0.2 rad/g whose 3.3 Hz wing mode grows in the march (docs/controls.md)."""
    from wingmdao.cases import pegasus
    from wingmdao.sizing import build_problem, closed_loop_constraints

    pure = tmp_path / "pure.yaml"
    pure.write_text(open(EXAMPLE).read().split("law:")[0] + "law:\n  outputs: [load_factor]\n  gain: [-0.2]\n")
    ks = {}
    for tag, path in (("filtered", EXAMPLE), ("pure", str(pure))):
        setup = pegasus.build(pegasus.PegasusOptions(loads="gust", aero="coupled", aero_theory="strip", plunge="free", t_final=0.3,
                                                     dt=0.03, gust_start=0.0, alleviation=path, size_gains=True))
        setup.options.disp = False
        assert closed_loop_constraints(setup.load_cases) == ["cases.gust.closed_loop_ks"]
        prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
        prob.run_model()
        ks[tag] = float(prob.get_val("cases.gust.closed_loop_ks")[0])
    assert ks["filtered"] < 0.0 < ks["pure"], ks


@pytest.mark.slow
def test_pegasus_modes_equal_dense_solve():
    """PEGASUS closed loop (the co-design's gust case, docs/examples/pegasus_alleviation.yaml) with
    the law's gains scaled by 0, 1 and 4: the sparse-LU selection equals the dense solve's."""
    from wingmdao.cases import pegasus
    from wingmdao.sizing import build_problem

    setup = pegasus.build(pegasus.PegasusOptions(loads="gust", aero="coupled", aero_theory="strip", plunge="free", t_final=0.3,
                                                 dt=0.03, gust_start=0.0, alleviation=EXAMPLE, size_gains=True))
    setup.options.disp = False
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
    prob.run_model()
    comp = prob.model._get_subsystem("cases.gust.closed_loop")
    s = comp.options["system"]
    p, x0 = comp._packed(comp._inputs)
    lay = layout(s.param_specs)
    for scale in (0.0, 1.0, 4.0):
        ps = p.copy()
        for nm in ("controller_C", "controller_D"):
            ps[lay[nm]] *= scale
        _assert_same_modes(s, ps, x0, 40.0 / 100.0)


@pytest.mark.slow
def test_pegasus_closed_loop_margin_shifts_the_constraint():
    """--closed-loop-margin m reaches ClosedLoopDamping: at the same design and gains the constraint
    is KS(Re lambda + m) = KS(Re lambda) + m (the KS of a shifted set is the shifted KS), so the two
    runs differ by exactly m; a negative margin, or a margin without --size-gains, is refused before
    any solve."""
    from wingmdao.cases import pegasus
    from wingmdao.sizing import build_problem

    ks = {}
    for margin in (0.0, 0.75):
        setup = pegasus.build(pegasus.PegasusOptions(loads="gust", aero="coupled", aero_theory="strip", plunge="free",
                                                     t_final=0.3, dt=0.03, gust_start=0.0, alleviation=EXAMPLE,
                                                     size_gains=True, closed_loop_margin=margin))
        setup.options.disp = False
        prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False)
        assert prob.model._get_subsystem("cases.gust.closed_loop").options["margin"] == margin
        prob.run_model()
        ks[margin] = float(prob.get_val("cases.gust.closed_loop_ks")[0])
    assert ks[0.75] - ks[0.0] == pytest.approx(0.75, abs=1e-9), ks
    with pytest.raises(ValueError, match=r"--closed-loop-margin = -0.1 1/s; allowed range \[0, inf\) 1/s"):
        pegasus.build(pegasus.PegasusOptions(loads="gust", aero="coupled", plunge="free", alleviation=EXAMPLE,
                                             size_gains=True, closed_loop_margin=-0.1))
    with pytest.raises(ValueError, match="--closed-loop-margin = 0.5 1/s applies with --size-gains"):
        pegasus.build(pegasus.PegasusOptions(loads="gust", aero="coupled", plunge="free", alleviation=EXAMPLE,
                                             closed_loop_margin=0.5))
