"""The CRM with coupled loads (``size crm --aero coupled``): the vortex lattice of the 37 deg swept
planform in the aeroelastic beam.

Checks: the case builds its trimmed maneuvers with the lattice at its flight point, and refuses
(before any solve, naming the flag) a theory without sweep, a transonic Mach number and flight-point
flags without ``--aero coupled``; a stiff CRM wing at a fixed angle of attack, solved statically by
the coupled model, carries the spanload of the steady vortex lattice solved directly on the panels
(:func:`wingmdao.aero.vlm.build_lattice`, :func:`~wingmdao.aero.vlm.solve_circulation`: no station
transfer, no beam): the shear (the integrated lift) at every station.
"""

import numpy as np
import pytest

from wingmdao.cases import crm


def test_coupled_crm_maneuvers_use_the_lattice_at_the_flight_point():
    setup = crm.build(aero="coupled")
    assert [c.name for c in setup.load_cases] == ["maneuver_pos", "maneuver_neg"]
    for case in setup.load_cases:
        assert case.aero.aero_theory == "vlm"
        assert case.aero.mach == crm.COUPLED_FLIGHT_POINT[1]
        assert case.aero.node_positions.shape == (setup.geometry.num_nodes, 3)
    assert crm.build(aero="coupled", aero_theory="vlm").load_cases[0].aero.aero_theory == "vlm"


@pytest.mark.parametrize("options, match", [
    (dict(aero="coupled", aero_theory="strip"), "--aero-theory strip: not available for the crm case"),
    (dict(aero="coupled", aero_theory="lifting-line"), "--aero-theory lifting-line: not available"),
    (dict(aero="coupled", mach=0.85), r"--mach = 0.85; allowed range \(0, 0.75\]"),
    (dict(aero="coupled", mach=0.0), r"--mach = 0.0; allowed range"),
    (dict(aero="coupled", altitude_ft=-10.0), r"--altitude-ft = -10.0 ft; allowed range \[0, 60000\]"),
    (dict(aero_theory="vlm"), "--aero-theory vlm applies to --aero coupled"),
    (dict(mach=0.5), "--altitude-ft and --mach set the flight point of --aero coupled"),
])
def test_coupled_crm_bad_input_is_refused(options, match):
    with pytest.raises(ValueError, match=match):
        crm.build(**options)


def test_cli_coupled_crm_refuses_a_transonic_mach(capsys):
    from wingmdao.cli import main

    assert main(["size", "crm", "--aero", "coupled", "--mach", "0.85", "--analysis-only"]) == 2
    err = capsys.readouterr().err
    assert "error: --mach = 0.85; allowed range (0, 0.75]" in err and "Traceback" not in err


@pytest.mark.parametrize("flags, match", [
    (["--aero-theory", "strip"], "--aero-theory strip: not available for the crm case"),
    (["--aero-theory", "dlm", "--clamped"], "--aero-theory dlm: not available for the crm case"),
    (["--mach", "0.8"], r"--mach = 0.8; allowed range \(0, 0.75\]"),
])
def test_cli_gust_crm_coupled_bad_input(flags, match, capsys):
    import re

    from wingmdao.cli import main

    assert main(["gust", "crm", "--aero", "coupled", "--no-plots", *flags]) == 2
    err = capsys.readouterr().err
    assert re.search(match, err) and "Traceback" not in err


@pytest.mark.slow
def test_stiff_crm_wing_carries_the_lattice_spanload():
    from wingmdao.aero import aero_parameters, cached_aeroelastic_system, three_dimensional_parameters
    from wingmdao.aero.vlm import build_lattice, solve_circulation
    from wingmdao.beam.static import beam_forcing
    from wingmdao.cases import case_beam_parameters
    from wingmdao.cases.planform import wing_geometry
    from wingmdao.timemarch.bdf import solve_static
    from wingmdao.timemarch.system import pack

    _, bp = case_beam_parameters(crm)
    bp = dict(bp, stiffness_csn=bp["stiffness_csn"] * 1e3, compliance_csn=bp["compliance_csn"] / 1e3,
              mass_per_length=bp["mass_per_length"] * 1e-6)  # rigid and weightless: the incidence stays alpha
    _, chord, frac = wing_geometry(crm.PLANFORM, crm.ENGINES)
    r0 = bp["node_positions"]
    n = r0.shape[0]
    alpha, rho, mach = 0.05, 0.9, crm.COUPLED_FLIGHT_POINT[1]
    V = 220.0
    ap = aero_parameters(n, chord=chord, ref_point=frac, airspeed=V, density=rho, mach=mach, alpha_zero_lift=-alpha)
    ap.update(three_dimensional_parameters("vlm", r0, chord, frac, mach))
    system = cached_aeroelastic_system(n, aero_theory="vlm")
    qd = beam_forcing(n)
    qd.update(gust_velocity=np.zeros(n), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3))
    x, _ = solve_static(system, pack(system.param_specs, {**bp, **ap}), pack(system.forcing_specs, qd))
    X = system.layout.beam_states(x)
    # the steady lattice directly: every panel at alpha, lift rho V^2 Gamma l per panel
    lat = build_lattice(r0, chord, frac, mach=mach)
    gamma = solve_circulation(lat, np.full(lat.control.shape[0], alpha))
    force = 0.5 * rho * V ** 2 * 2.0 * gamma * lat.span
    y = 0.5 * (lat.bound_a[:, 1] + lat.bound_b[:, 1])
    shear = np.array([force[y > r0[i, 1]].sum() for i in range(n)])
    inner = slice(0, n - 3)  # the last elements' loads are small; compared absolutely below
    np.testing.assert_allclose(X[inner, 8], shear[inner], rtol=1e-2)
    np.testing.assert_allclose(X[:, 8], shear, rtol=0, atol=3e-3 * shear[0])
    # the sweep matters: the swept lattice's root shear is below the unswept strips' 2 pi / beta
    strip = 0.5 * rho * V ** 2 * alpha * 2 * np.pi / np.sqrt(1 - mach ** 2) * np.trapezoid(chord, r0[:, 1])
    assert shear[0] < 0.75 * strip


@pytest.mark.slow
def test_cli_gust_crm_coupled_runs_with_the_lattice_slope(tmp_path):
    """``wingmdao gust crm --aero coupled --clamped`` (short): it runs from the trimmed 1 g state, and
    its wing lift slope is the lattice's CL_alpha summed directly over the panels at the gust Mach
    number (2 sum L / (q S) of a unit incidence on every panel)."""
    import json

    from wingmdao.aero.vlm import build_lattice, solve_circulation
    from wingmdao.cases.planform import FT, wing_geometry
    from wingmdao.cli import main

    out = tmp_path / "g.json"
    assert main(["gust", "crm", "--aero", "coupled", "--clamped", "--t-final", "0.3", "--dt", "0.03",
                 "--no-plots", "--json", str(out)]) == 0
    r = json.loads(out.read_text())
    assert r["aero_theory"] == "vlm"
    np.testing.assert_allclose(r["load_factor"][0], 1.0, rtol=1e-8)
    geo, chord, frac = wing_geometry(crm.PLANFORM, crm.ENGINES)
    lat = build_lattice(geo.node_positions, chord, frac, mach=r["mach"])
    gamma = solve_circulation(lat, np.ones(lat.control.shape[0]))
    cl_a = 2 * np.sum(2 * gamma * lat.span) / (crm.PLANFORM.area_ft2 * FT ** 2)
    assert r["wing_lift_slope_per_rad"] == pytest.approx(cl_a, rel=5e-3)
