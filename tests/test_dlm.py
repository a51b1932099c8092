"""wingmdao.aero.dlm: the doublet lattice (PanelAero's kernel, both halves explicit) checked against
the vortex lattice at k -> 0 and Theodorsen's function on a very high aspect-ratio wing; the
modal transfer and the generalized forces; bad input. Skipped without the ``aero3d`` extra."""

import numpy as np
import pytest
from scipy.special import hankel2

from wingmdao.aero.dlm import (check_dlm_mach, check_reduced_frequencies, generalized_forces, modal_transfer,
                               panel_pressure)
from wingmdao.aero.vlm import build_lattice, flat_wing, solve_circulation
from wingmdao.beam.modes import normal_modes
from wingmdao.beam.static import beam_forcing, cached_beam_system
from wingmdao.cases import goland
from wingmdao.timemarch.system import pack

pytest.importorskip("panelaero.DLM")


def theodorsen(k):
    """C(k) = H1(k) / (H1(k) + i H0(k)), Hankel functions of the second kind (Theodorsen, NACA
    Report 496, 1935, Eq. VI)."""
    return hankel2(1, k) / (hankel2(1, k) + 1j * hankel2(0, k))


def _swept_wing(mach):
    r, c, ref = flat_wing(6.0, lambda y: 2.0 - 0.12 * y, sweep_quarter_deg=25.0, n_stations=7, ref_point=0.4)
    return build_lattice(r, c, ref, mach=mach, n_chordwise=3, n_spanwise=2)


@pytest.mark.parametrize("mach", [0.0, 0.6])
def test_small_k_equals_vortex_lattice(mach):
    """At k -> 0 the doublet lattice's pressure jumps times the panel areas are the vortex
    lattice's normal forces 2 Gamma l / V (wingmdao.aero.vlm, an independent horseshoe lattice)."""
    lat = _swept_wing(mach)
    alpha = 0.01 * (1.0 + lat.hat @ np.linspace(0.0, 1.0, lat.hat.shape[1]))
    vlm = 2.0 * solve_circulation(lat, alpha) * lat.span
    area = lat.panel_chord * lat.span
    for kb in (0.0, 1e-4):
        dlm = panel_pressure(lat, kb, alpha[:, None])[:, 0] * area
        np.testing.assert_allclose(dlm.real, vlm, rtol=1e-4, atol=1e-5 * np.max(np.abs(vlm)))
        assert np.max(np.abs(dlm.imag)) < 1e-3 * np.max(np.abs(vlm))


def test_root_strip_of_very_long_wing_is_theodorsen():
    """Mid-span lift of a rectangular wing of aspect ratio 40 (both halves explicit) in plunge and
    in pitch about the quarter chord at k = 0.3 against Theodorsen's 2-D lift (circulatory with
    C(k) from the Hankel functions, plus apparent mass); Theodorsen, "General theory of
    aerodynamic instability and the mechanism of flutter", NACA Report 496, 1935, Eq. (XVIII)
    with a = -1/2. Per unit dynamic pressure, chord c = 2b = 1 m, heave h up, pitch alpha nose-up:
    plunge L/q = 2 pi b^2 kb^2 - 4 pi b C(k) i kb, pitch L/q = 2 pi b^2 (i kb - b kb^2 / 2)
    + 4 pi b C(k) (1 + i b kb), kb = k / b."""
    b, k = 0.5, 0.3
    y = np.concatenate([np.linspace(0.0, 2.0, 9), np.linspace(2.0, 20.0, 13)[1:]])
    r = np.stack([np.full(y.size, 0.25), y, np.zeros(y.size)], axis=-1)
    lat = build_lattice(r, np.ones(y.size), 0.25, mach=0.0, n_chordwise=6, n_spanwise=1)
    kb = k / b
    x = lat.control[:, 0]
    wash = np.column_stack([-1j * kb * np.ones_like(x), 1.0 + 1j * kb * (x - 0.25)])
    dcp = panel_pressure(lat, kb, wash)
    root = lat.strip == 0
    lift = (lat.panel_chord[root, None] * dcp[root]).sum(axis=0)   # per unit span, per q
    C = theodorsen(k)
    plunge = 2 * np.pi * b**2 * kb**2 - 4 * np.pi * b * C * 1j * kb
    pitch = 2 * np.pi * b**2 * (1j * kb - 0.5 * b * kb**2) + 4 * np.pi * b * C * (1.0 + 1j * b * kb)
    ratio = lift / np.array([plunge, pitch])
    np.testing.assert_allclose(np.abs(ratio), 1.0, atol=0.02)
    np.testing.assert_allclose(np.angle(ratio), 0.0, atol=0.02)


def test_generalized_forces_rigid_modes():
    """Rigid heave and pitch 'modes' of a flat wing: the steady (k = 0) generalized force of unit
    pitch on heave is the wing's lift / q, the vortex lattice's panel forces summed; heave alone
    has no steady force; the gust column at k = 0 equals the pitch column (a uniform w_g / V is a
    uniform incidence), and its phase follows the penetration delay."""
    r, c, ref = flat_wing(5.0, lambda y: np.full_like(y, 1.5), n_stations=6, ref_point=0.4, spacing="uniform")
    n = r.shape[0]
    disp = np.zeros((2, n, 3))
    rot = np.zeros((2, n, 3))
    disp[0, :, 2] = 1.0      # heave, m
    rot[1, :, 1] = 1.0       # pitch nose-up about the beam axis, rad
    gaf = generalized_forces(r, c, ref, disp, rot, reduced_frequencies=[0.0, 0.2], n_chordwise=3, n_spanwise=2)
    lat = build_lattice(r, c, ref, n_chordwise=3, n_spanwise=2)
    lift = np.sum(2.0 * solve_circulation(lat, np.ones(lat.span.size)) * lat.span)
    np.testing.assert_allclose(gaf.Q[0, 0, 1].real, lift, rtol=1e-4)
    assert abs(gaf.Q[0, 0, 0]) < 1e-9 * lift
    np.testing.assert_allclose(gaf.gust[0], gaf.Q[0, :, 1], rtol=1e-9, atol=1e-9 * lift)
    # with the delay the gust lift lags: its phase at k = 0.2 is negative
    assert np.angle(gaf.gust[1][0]) < -0.05
    tr = modal_transfer(lat, r, disp, rot)
    np.testing.assert_allclose(tr.incidence[:, 1], 1.0)
    np.testing.assert_allclose(tr.heave[:, 1], -(lat.control[:, 0] - lat.hat @ r[:, 0]))


@pytest.mark.parametrize("k, message", [([], "non-empty"), ([0.1, 0.05], "increasing"), ([0.1, 0.1], "increasing"),
                                        ([-0.1, 0.2], ">= 0"), ([0.0, np.nan], "finite")])
def test_bad_reduced_frequencies(k, message):
    with pytest.raises(ValueError, match=message):
        check_reduced_frequencies(k)


@pytest.mark.parametrize("mach", [1.0, 1.2, -0.1, np.nan])
def test_bad_mach(mach):
    with pytest.raises(ValueError, match=r"mach must be in \[0, 1\)"):
        check_dlm_mach(mach)


def test_bad_planform_refused_before_solve():
    r, c, ref = flat_wing(5.0, lambda y: np.full_like(y, 1.5), n_stations=4, ref_point=0.4, spacing="uniform")
    modes = np.zeros((1, 4, 3))
    with pytest.raises(ValueError, match="chord must be > 0"):
        generalized_forces(r, np.array([1.5, 0.0, 1.5, 1.5]), ref, modes, modes)
    r2 = r.copy()
    r2[2, 1] = r2[1, 1]
    with pytest.raises(ValueError, match="zero area"):
        generalized_forces(r2, c, ref, modes, modes)
    with pytest.raises(ValueError, match="mach"):
        generalized_forces(r, c, ref, modes, modes, mach=1.0)
    with pytest.raises(ValueError, match="increasing"):
        generalized_forces(r, c, ref, modes, modes, reduced_frequencies=[0.3, 0.1])


def test_goland_normal_modes():
    """The beam's modes for the modal basis: Goland's first bending, torsion and second bending
    frequencies against the exact coupled bending-torsion solution (1 %); the scaled modes are
    mass-orthonormal under the residual's element inertia (wingmdao.beam.modes.generalized_mass)."""
    n = 21
    params = goland.beam_params(n)
    system = cached_beam_system(n)
    modes = normal_modes(system, params, pack(system.param_specs, params),
                         pack(system.forcing_specs, beam_forcing(n)), count=4)
    np.testing.assert_allclose(modes.frequencies[:3], goland.EXACT_FREQUENCIES_RAD_S, rtol=0.01)
    np.testing.assert_allclose(modes.mass, np.eye(4), atol=1e-6)


def test_mode_displacement_root_moment_of_a_uniform_load():
    """The modes' internal resultants (the beam's M states): the static modal response to a uniform
    load p on the Goland wing gives the root bending moment p L^2 / 2 (statics) by the
    mode-displacement sum within 4 % with 6 modes (the truncation of the higher bending modes)."""
    n = 21
    params = goland.beam_params(n)
    system = cached_beam_system(n)
    modes = normal_modes(system, params, pack(system.param_specs, params),
                         pack(system.forcing_specs, beam_forcing(n)), count=6)
    y = params["node_positions"][:, 1]
    w = np.zeros(n)
    w[:-1] += 0.5 * np.diff(y)
    w[1:] += 0.5 * np.diff(y)
    f = (1000.0 * w) @ modes.displacement[:, :, 2].T
    root = (f / modes.frequencies ** 2) @ modes.moment[:, 0, 0]
    assert root == pytest.approx(1000.0 * y[-1] ** 2 / 2, rel=0.04)


def test_interpolate_passes_through_the_table_and_is_cubic():
    """The splines of a table (built once per table, reused by later calls) return its entries at
    the tabulated k, and a cubic in k exactly (a not-a-knot cubic spline reproduces cubics)."""
    from wingmdao.aero.dlm import GeneralizedForces, interpolate

    k = np.array([0.0, 0.1, 0.25, 0.4, 0.7, 1.0])

    def cubic(x):
        return np.array([[1.0 + 2.0j * x - x ** 3, 0.5 * x ** 2], [x, 3.0 - 1.0j * x ** 3]])

    gaf = GeneralizedForces(k=k, Q=np.stack([cubic(x) for x in k]), gust=np.stack([cubic(x)[0] for x in k]),
                            b_ref=1.0, mach=0.0, x_gust=0.0)
    for x in (0.25, 0.33, 0.9, 0.33):
        Q, g = interpolate(gaf, x)
        np.testing.assert_allclose(Q, cubic(x), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(g, cubic(x)[0], rtol=1e-12, atol=1e-12)
    with pytest.raises(ValueError, match="outside the tabulated range"):
        interpolate(gaf, 1.2)
