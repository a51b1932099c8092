"""Lumped masses, free flight and symmetry conditions of joined beams (wingmdao.beam.joints).

References coded here:

* cantilever with a tip mass M (offset e along the span, d chordwise) under gravity, Euler-Bernoulli
  and Saint-Venant torsion: w = P L^3/3EI + P e L^2/2EI, twist = P d L/GJ (P = M g);
* its first bending frequency: the frequency equation of the Euler-Bernoulli cantilever with a
  tip mass (tip conditions EI w'' = 0, EI w''' = -M omega^2 w):
  1 + cos(bL) cosh(bL) + (M / mL) bL (cos(bL) sinh(bL) - sin(bL) cosh(bL)) = 0,
  omega = (bL)^2 sqrt(EI / (m L^4)); and Rayleigh's estimate omega^2 = 3 EI / (L^3 (M + 33/140 m L));
* its first torsion frequency with a tip rotary inertia J (tip condition GJ theta' = J omega^2 theta):
  g tan(g) = rho_Ip L / J, omega = (g / L) sqrt(GJ / rho_Ip);
* rigid-body modes of a free structure: 3 for a symmetric half aircraft (surge, plunge, pitch),
  6 for the full aircraft; linear momentum of a free structure with no external force is
  conserved (the BDF2 rates are linear in the states, so the sum of the equilibrium rows holds it
  exactly), and under gravity alone it grows as (total mass) g t.
"""

import numpy as np
import pytest
import scipy.optimize as sopt

from wingmdao.beam.joints import (FUSELAGE_AXES, Beam, JoinedBeamModel, Joint, LumpedMass, Symmetry,
                                  build_joined_system)
from wingmdao.beam.static import beam_parameters, straight_beam
from wingmdao.stability.eigen import eigenmodes
from wingmdao.timemarch.adjoint import LinearizedHistory
from wingmdao.timemarch.bdf import march
from wingmdao.timemarch.system import layout

ROT = np.diag([1e-9, 1e-3, 1e-9])   # small rotary inertia per length (kg m), csn
SECTION = dict(EI_cc=2.0e6, GJ=1.5e6, EI_nn=1.8e7, EA=1e11, mass_per_length=20.0, inertia_per_length=ROT)
N, L = 21, 10.0


def _cantilever(masses, **section):
    r0, th0 = straight_beam(N, L)
    return JoinedBeamModel([Beam("wing", N)], [], {"wing": beam_parameters(r0, th0, **{**SECTION, **section})},
                           masses=masses)


def _frequencies(model):
    modes = eigenmodes(model.system, model.p, model.forcing(), model.system.jig_state(model.p), static=False,
                       method="dense")
    w = modes.frequency
    return np.sort(w[w > 1e-3])


# ----------------------------------------------------------------------------- lumped masses
def test_tip_mass_with_offsets_under_gravity_against_closed_form():
    """A massless cantilever with a 20 kg tip mass 0.5 m beyond the tip and 0.3 m aft: the weight
    bends it (P L^3/3EI + P e L^2/2EI) and twists it (P d L/GJ)."""
    M, e, d, g = 20.0, 0.5, 0.3, 9.81
    model = _cantilever([LumpedMass("wing", -1, M, offset=(d, e, 0.0), inertia=np.diag([1.0, 2.0, 3.0]))],
                        mass_per_length=1e-9)
    tip = model.solve(gravity=[0.0, 0.0, -g])["wing"]
    P, EI, GJ = M * g, SECTION["EI_cc"], SECTION["GJ"]
    assert tip["r"][-1, 2] == pytest.approx(-(P * L**3 / (3 * EI) + P * e * L**2 / (2 * EI)), rel=1e-3)
    assert tip["theta"][-1, 1] == pytest.approx(P * d * L / GJ, rel=1e-3)
    # the clamp carries the weight and its moment (equilibrium of the whole, exact)
    root = model.solve(gravity=[0.0, 0.0, -g])
    np.testing.assert_allclose(root["wing"]["F"][0], [0.0, 0.0, -P], atol=1e-8)


@pytest.mark.parametrize("ratio", [0.5, 2.0])
def test_tip_mass_first_bending_and_torsion_frequencies(ratio):
    """First bending frequency of a cantilever with a tip mass M = ratio m L against the exact
    frequency equation (and Rayleigh's estimate), first torsion frequency with a tip rotary
    inertia J against g tan g = rho_Ip L / J."""
    mL = SECTION["mass_per_length"] * L
    J, rho_ip = 1e-2, ROT[1, 1]
    model = _cantilever([LumpedMass("wing", -1, ratio * mL, inertia=np.diag([1e-9, J, 1e-9]))])
    w = _frequencies(model)
    eq = lambda b: (1 + np.cos(b) * np.cosh(b)                               # noqa: E731
                    + ratio * b * (np.cos(b) * np.sinh(b) - np.sin(b) * np.cosh(b)))
    bL = sopt.brentq(eq, 0.3, 1.8751)
    exact = bL**2 * np.sqrt(SECTION["EI_cc"] / (SECTION["mass_per_length"] * L**4))
    rayleigh = np.sqrt(3 * SECTION["EI_cc"] / (L**3 * (ratio * mL + 33 / 140 * mL)))
    assert w[0] == pytest.approx(exact, rel=1e-3)
    assert w[0] == pytest.approx(rayleigh, rel=3e-3)
    gam = sopt.brentq(lambda x: x * np.tan(x) - rho_ip * L / J, 1e-6, np.pi / 2 - 1e-9)
    torsion = gam / L * np.sqrt(SECTION["GJ"] / rho_ip)
    assert np.min(np.abs(w / torsion - 1)) < 3e-4


def test_adjoint_gradient_with_respect_to_lumped_mass_values_against_central_differences():
    """A 16-step march of a 6-node cantilever with an offset tip mass under gravity and a step tip
    load: d(sum of tip z^2)/d(mass, offset, inertia) by the discrete adjoint and the tangent sweep
    against central differences."""
    r0, th0 = straight_beam(6, 4.0)
    model = JoinedBeamModel([Beam("wing", 6)], [], {"wing": beam_parameters(r0, th0, **SECTION)},
                            masses=[LumpedMass("wing", -1, 80.0, offset=(0.4, 0.2, -0.1),
                                               inertia=[[3.0, 0.2, 0.0], [0.2, 5.0, 0.0], [0.0, 0.0, 6.0]])])
    s, t = model.system, np.linspace(0.0, 0.12, 16)
    pf = np.zeros((6, 3))
    pf[-1] = [0.0, 0.0, 4e3]
    Q = np.tile(model.forcing({"wing": {"point_force": pf}}, gravity=[0.0, 0.0, -9.81]), (t.size, 1))
    Q[0] = model.forcing(gravity=[0.0, 0.0, -9.81])
    i = s.node_index("wing", -1) + 2

    def f_of(states):
        d = states[:, i] - states[0, i]
        dfdx = np.zeros_like(states)
        dfdx[:, i] = 2 * d
        dfdx[0, i] -= np.sum(2 * d)
        return float(np.sum(d**2)), dfdx

    run = lambda pp: march(s, t, pp, Q, atol=1e-12, static_options={"rtol": 1e-14})  # noqa: E731
    h = run(model.p)
    f, dfdx = f_of(h.states)
    lin = LinearizedHistory(s, t, h.states, model.p, Q, lu="static")
    grad = lin.gradient(dfdx)[0]
    lay = layout(s.param_specs)
    picks = {"mass": lay["lumped_mass"].start, "offset x": lay["lumped_mass_offset"].start,
             "offset z": lay["lumped_mass_offset"].start + 2, "inertia xx": lay["lumped_mass_inertia"].start}
    for name, j in picks.items():
        step = 1e-3 * abs(model.p[j])
        e = np.zeros_like(model.p)
        e[j] = step
        fd = (f_of(run(model.p + e).states)[0] - f_of(run(model.p - e).states)[0]) / (2 * step)
        assert grad[j] == pytest.approx(fd, rel=1e-5, abs=1e-9 * abs(f)), name
    direction = np.zeros_like(model.p)
    direction[list(picks.values())] = 1.0
    assert np.sum(dfdx * lin.tangent(dp=direction)) == pytest.approx(grad @ direction, rel=1e-9)
