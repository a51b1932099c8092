"""Control surfaces as flap modes of the doublet lattice (wingmdao.aero.dlm, ``surfaces``): the
flap's lift and hinge moment on the mid-span strip of a very long wing against Glauert's steady
thin-airfoil closed forms and Theodorsen's oscillating-flap functions with C(k), a part-span
aileron's spanload and hinge moment against the vortex lattice's deflected panels
(:func:`wingmdao.aero.vlm.flap_influence`, independent horseshoes), bad input. Skipped without the
``aero3d`` extra."""

import numpy as np
import pytest
from scipy.special import hankel2

from wingmdao.aero.controls import flap_harmonic_loads, flap_lift_effectiveness, hinge_moment_coefficients
from wingmdao.aero.dlm import flap_panels, flap_transfer, generalized_forces, panel_pressure
from wingmdao.aero.vlm import build_lattice, chord_fractions, flap_influence, flat_wing

pytest.importorskip("panelaero.DLM")

HINGE = 0.75
B = 0.5


def theodorsen(k):
    """C(k) = H1(k) / (H1(k) + i H0(k)) (Theodorsen, NACA Report 496, 1935)."""
    return hankel2(1, k) / (hankel2(1, k) + 1j * hankel2(0, k))


def _mid_strip(n_chordwise, ks):
    """Mid-span (root) strip of a rectangular wing of aspect ratio 40 (chord 1 m, both halves
    explicit), full-span flap hinged at 75 % chord: per unit span and q, (lift, hinge moment) of a
    unit incidence and of a unit flap deflection at each k (rows)."""
    y = np.concatenate([np.linspace(0.0, 2.0, 9), np.linspace(2.0, 20.0, 13)[1:]])
    r = np.stack([np.full(y.size, 0.25), y, np.zeros(y.size)], axis=-1)
    lat = build_lattice(r, np.ones(y.size), 0.25, n_chordwise=n_chordwise, n_spanwise=1,
                        fractions=chord_fractions(n_chordwise, [HINGE]))
    fl = flap_transfer(lat, [(tuple(range(y.size)), HINGE)])
    root = lat.strip == 0
    out = []
    for k in ks:
        kb = k / B
        dcp = panel_pressure(lat, kb, np.column_stack([np.ones(lat.span.size), fl.incidence[:, 0] - 1j * kb * fl.heave[:, 0]]))
        lift = (lat.panel_chord[root, None] * dcp[root]).sum(axis=0)
        hinge = ((fl.force[root, 0] / lat.span[root])[:, None] * dcp[root]).sum(axis=0)
        out.append(np.concatenate([lift, hinge]))
    return np.array(out)


@pytest.fixture(scope="module")
def strips():
    ks = (0.0, 0.1, 0.4)
    return {nc: _mid_strip(nc, ks) for nc in (16, 32)}


def test_steady_flap_is_glauert(strips):
    """k = 0: the flap's lift over the wing's lift slope is Glauert's effectiveness
    tau = T10 / pi (lifting line: a full-span flap loads the span like an incidence tau beta); the
    hinge moment is C_h,alpha alpha_e + C_h,beta with the strip's effective incidence
    alpha_e = (Cl - 2 T10) / (2 pi) (Glauert, The Elements of Aerofoil and Airscrew Theory, 1926,
    Ch. VII; Theodorsen's T10, T12, T18). Both converge as 1 / n_chordwise: the errors halve from
    16 to 32 panels, and the Richardson extrapolation of the two is within 0.5 % (lift) and 1 % (hinge)."""
    tau = flap_lift_effectiveness(HINGE) / (2 * np.pi)
    cha, chb = hinge_moment_coefficients(HINGE)
    err = {}
    for nc, v in strips.items():
        cla, clb, hb = v[0, 0].real, v[0, 1].real, v[0, 3].real
        assert abs(v[0, 2].real - cha * cla / (2 * np.pi)) < 0.02 * abs(cha)      # C_h,alpha of the incidence
        ref = cha * (clb - 2 * np.pi * tau) / (2 * np.pi) + chb
        err[nc] = (clb / cla / tau - 1.0, hb / ref - 1.0)
    for i in range(2):
        assert 0.4 < err[32][i] / err[16][i] < 0.6                                  # first order in 1 / n_chordwise
        assert abs(2 * err[32][i] - err[16][i]) < (0.005, 0.01)[i]
    assert abs(err[32][0]) < 0.02 and abs(err[32][1]) < 0.04


@pytest.mark.parametrize("row, k", [(1, 0.1), (2, 0.4)])
def test_oscillating_flap_is_theodorsen(strips, row, k):
    """k = 0.1 and 0.4: the mid-span strip's lift and hinge moment of an oscillating flap against
    Theodorsen's (NACA Report 496, 1935) with C(k) from the Hankel functions
    (:func:`wingmdao.aero.controls.flap_harmonic_loads`): 32 chordwise panels (8 on the flap) within
    1.5 % (lift) and 4 % (hinge moment, magnitude and phase), the Richardson extrapolation of 16
    and 32 panels within 1.5 % (the residual: the wing's finite aspect ratio)."""
    L, _, H = flap_harmonic_loads(k, HINGE, theodorsen)
    ref = np.array([2 * B * L, 2 * B * B * H])           # per unit q and span, c = 1 m
    r16 = strips[16][row, [1, 3]] / ref
    r32 = strips[32][row, [1, 3]] / ref
    assert abs(r32[0] - 1.0) < 0.015 and abs(r32[1] - 1.0) < 0.04
    np.testing.assert_allclose(2 * r32 - r16, 1.0, atol=0.015)


def test_part_span_aileron_is_the_vortex_lattice_flap():
    """k = 0: a part-span aileron (nodes 4 .. 7 of 9, hinge 70 %) on a tapered swept wing: its
    spanload at the beam stations and its hinge moment from the doublet lattice's flap mode equal the
    vortex lattice's deflected panels (wingmdao.aero.vlm.flap_influence, its own horseshoe solve)
    on the same panels, to 1e-3 of the largest."""
    r, c, ref = flat_wing(8.0, lambda y: 2.5 - 0.15 * y, sweep_quarter_deg=20.0, n_stations=9, ref_point=0.4,
                          spacing="uniform")
    nodes, hinge = tuple(range(4, 8)), 0.7
    inf, flap = flap_influence(r, c, ref, [(nodes, hinge)], n_chordwise=10, n_spanwise=2)
    lat = build_lattice(r, c, ref, n_chordwise=10, n_spanwise=2, fractions=chord_fractions(10, [hinge]))
    fl = flap_transfer(lat, [(nodes, hinge)])
    dcp = panel_pressure(lat, 0.0, fl.incidence).real[:, 0]
    force = dcp * lat.panel_chord * lat.span
    lift = (lat.hat / lat.tributary[None, :]).T @ force
    vlm = flap.lift.sum(axis=1)
    np.testing.assert_allclose(lift, vlm, atol=1e-3 * np.max(np.abs(vlm)))
    assert np.max(np.abs(vlm[:3])) > 0.01 * np.max(np.abs(vlm))        # the aileron loads the inboard wing too
    np.testing.assert_allclose(fl.force[:, 0] @ dcp, flap.hinge_flap.sum(), rtol=1e-3)
    # the flap mode's panels are the vortex lattice's
    assert flap_panels(lat, [(nodes, hinge)])[:, 0].sum() == 3 * 3 * 2


def test_generalized_forces_carry_the_flap_columns():
    """generalized_forces(surfaces=...): the flap columns equal the pressures of the flap mode on
    the same lattice (forces on a rigid heave mode = the flap's lift), the hinge row's flap entry
    equals the flap's own virtual work, and the modes' forces are those of a lattice built with the
    same hinge edges."""
    r, c, ref = flat_wing(5.0, lambda y: np.full_like(y, 1.5), n_stations=6, ref_point=0.4, spacing="uniform")
    n = r.shape[0]
    disp = np.zeros((1, n, 3))
    disp[0, :, 2] = 1.0
    rot = np.zeros((1, n, 3))
    gaf = generalized_forces(r, c, ref, disp, rot, reduced_frequencies=(0.0, 0.3), n_chordwise=8, n_spanwise=1,
                             surfaces=[((2, 3, 4), 0.75)])
    assert gaf.flap.shape == (2, 1, 1) and gaf.hinge.shape == (2, 1, 3) and gaf.flap_station_loads.shape == (2, n, 6, 1)
    lat = build_lattice(r, c, ref, n_chordwise=8, n_spanwise=1, fractions=chord_fractions(8, [0.75]))
    fl = flap_transfer(lat, [((2, 3, 4), 0.75)])
    kb = 0.3 / gaf.b_ref
    dcp = panel_pressure(lat, kb, fl.incidence - 1j * kb * fl.heave)[:, 0]
    area = lat.panel_chord * lat.span
    np.testing.assert_allclose(gaf.flap[1, 0, 0], area @ dcp, rtol=1e-10)
    np.testing.assert_allclose(gaf.hinge[1, 0, 1], fl.force[:, 0] @ dcp, rtol=1e-10)
    np.testing.assert_allclose(gaf.flap_station_loads[1, 0, 2, 0], area @ dcp, rtol=1e-10)


def test_bad_surfaces_refused():
    r, c, ref = flat_wing(5.0, lambda y: np.full_like(y, 1.5), n_stations=6, ref_point=0.4, spacing="uniform")
    lat = build_lattice(r, c, ref, n_chordwise=4, n_spanwise=1)
    with pytest.raises(ValueError, match="not on a chordwise panel edge"):
        flap_transfer(lat, [((1, 2), 0.7)])
    disp = np.zeros((1, 6, 3))
    with pytest.raises(ValueError, match="outside the beam"):
        generalized_forces(r, c, ref, disp, disp, surfaces=[((4, 5, 6), 0.7)])
