"""Strip aerodynamics on the lifting beams of a free stick aircraft, and its trim (wingmdao.aero.joined).

Reference: the rigid plunge/pitch model of the lone wing (wingmdao.aero.pitch: the same strip
wing on a rigid body with a quasi-steady tail, Etkin & Reid, Dynamics of Flight, 3rd ed., 1996,
Sec. 2.4) built from the same mass properties; a stiff stick aircraft must reproduce its gust
load-factor history. The stick model's tail is a strip beam of small chord (0.05 m: Wagner and
Kuessner lags of about 1 ms, the quasi-steady limit) so that the two tails are the same surface.
"""

import re

import numpy as np
import pytest

from wingmdao.aero import aero_parameters, cached_aeroelastic_system, station_gust_history
from wingmdao.aero.joined import build_joined_aeroelastic_system, lift_total, pack_aero_forcing, pack_aero_parameters
from wingmdao.beam.joints import FUSELAGE_AXES, Beam, Joint, LumpedMass, Symmetry
from wingmdao.beam.rotations import euler_from_axis
from wingmdao.beam.static import beam_forcing, beam_parameters, straight_beam
from wingmdao.timemarch import lu_orders, static_lu
from wingmdao.timemarch.adjoint import LinearizedHistory
from wingmdao.timemarch.bdf import march, solve_static
from wingmdao.timemarch.system import layout, pack

G = 9.81
V, RHO = 60.0, 1.2
N_WING, SEMI, CHORD, REF = 5, 8.0, 1.0, 0.35
N_TAIL, TAIL_SEMI, TAIL_CHORD = 4, 12.0, 0.05
X_FUS = np.array([-4.0, -2.0, 0.0, 2.0, 4.0, 6.0])
I_WING, I_TAIL = 2, 5
# half aircraft's body masses on the fuselage nodes (kg)
BODY = np.array([60.0, 90.0, 120.0, 80.0, 40.0, 20.0])
STIFF = dict(EI_cc=1e11, GJ=1e11, EI_nn=1e12, EA=1e13)
DOWNWASH = 0.3
SUPPORTS = (("fuselage", 0, "x"), ("fuselage", 0, "z"), ("fuselage", -1, "z"))
ROT = np.diag([1e-4, 1e-4, 1e-4])


def _wing_params(section=None):
    r0, th0 = straight_beam(N_WING, SEMI)
    return beam_parameters(r0, th0, mass_per_length=15.0, inertia_per_length=ROT, **(section or STIFF))


def _stick(wing_section=None):
    fus_r = np.column_stack([X_FUS, 0 * X_FUS, 0 * X_FUS])
    fus = beam_parameters((np.array(FUSELAGE_AXES) @ fus_r.T).T, np.tile(euler_from_axis((0.0, 1.0, 0.0)),
                          (X_FUS.size, 1)), mass_per_length=1e-3, inertia_per_length=ROT, **STIFF)
    yt = np.linspace(0.0, TAIL_SEMI, N_TAIL)
    tail = beam_parameters(np.column_stack([np.full(N_TAIL, X_FUS[I_TAIL]), yt, 0 * yt]),
                           np.tile(euler_from_axis((0.0, 1.0, 0.0)), (N_TAIL, 1)), mass_per_length=1e-3,
                           inertia_per_length=ROT, **STIFF)
    beams = [Beam("fuselage", X_FUS.size, root="free", axes=FUSELAGE_AXES), Beam("wing", N_WING, root="free"),
             Beam("tail", N_TAIL, root="free")]
    joints = [Joint("fuselage", I_WING, "wing", 0), Joint("fuselage", I_TAIL, "tail", 0)]
    masses = [LumpedMass("fuselage", i, m) for i, m in enumerate(BODY)]
    symmetry = [Symmetry("fuselage", i) for i in range(X_FUS.size)]
    s = build_joined_aeroelastic_system(beams, joints, supports=SUPPORTS, masses=masses, symmetry=symmetry)
    p = pack_aero_parameters(s, {"fuselage": fus, "wing": _wing_params(wing_section), "tail": tail},
                             {"wing": {"chord": CHORD, "ref_point": REF}, "tail": {"chord": TAIL_CHORD, "ref_point": 0.25}},
                             airspeed=V, density=RHO, downwash_gradient=DOWNWASH)
    return s, p


def _weight_half():
    fus_beam = 1e-3 * (X_FUS[-1] - X_FUS[0])
    return (BODY.sum() + 15.0 * SEMI + fus_beam + 1e-3 * TAIL_SEMI) * G


def _pitch_model():
    """The lone wing on the rigid body: the same wing, body = the stick's fuselage masses (both halves)."""
    bp = _wing_params()
    s = cached_aeroelastic_system(N_WING, plunge=True, trim=True, pitch=True, tail_lag=True)
    mass_body = 2 * BODY.sum()
    par = {**bp, **aero_parameters(N_WING, chord=CHORD, ref_point=REF, airspeed=V, density=RHO),
           "trim_lift": 2 * _weight_half(), "body_mass": mass_body,
           "body_first_moment": np.array([2 * BODY @ X_FUS, 0.0]), "body_pitch_inertia": 2 * BODY @ X_FUS**2,
           "tail_x": X_FUS[I_TAIL], "tail_area": 2 * TAIL_SEMI * TAIL_CHORD, "tail_lift_slope": 2 * np.pi,
           "downwash_gradient": DOWNWASH}
    return s, pack(s.param_specs, par)


def _gust(length=40.0, u=8.0):
    """1-cos gust profile (m/s up) of length ``length`` (m) and peak ``u`` (m/s) at V."""
    def profile(tau):
        return np.where((tau >= 0) & (tau <= length / V), 0.5 * u * (1 - np.cos(2 * np.pi * V * tau / length)), 0.0)
    return profile


def test_trimmed_stick_aircraft_lifts_its_weight_with_no_pitching_moment():
    """Trim at 1 g: the free half aircraft is in equilibrium with no support reaction (the state
    solves the free residual with trim held), lift = W, and the pitching moment of lift and weight
    about the CG vanishes (the supports' rows are satisfied without reaction unknowns)."""
    s, p = _stick()
    q1 = pack_aero_forcing(s, trim_active=1.0, gravity=[0, 0, -G])
    x, _ = solve_static(s, p, q1)
    q0 = pack_aero_forcing(s, trim_active=0.0, gravity=[0, 0, -G])
    assert np.max(np.abs(s.residual(x, 0 * x, p, q0))) < 1e-8 * _weight_half()
    lift = lift_total(s, x, 0 * x, p, q0)
    assert abs(lift / _weight_half() - 1.0) < 1e-3
    # pitching moment about the origin (the weights' too, so the CG's): lift at each strip's x plus
    # the sections' moments (about +y for both surfaces), M_y = -x L + m
    loads = s.section_loads(x, 0 * x, p, q0)
    lay = layout(s.param_specs)
    moment = 0.0
    masses_x = list(X_FUS) + [0.0]
    for name, (lift_i, m_i, _) in loads.items():
        r0 = p[lay[f"{name}_node_positions"]].reshape(-1, 3)
        ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
        w = np.zeros(len(lift_i))
        w[:-1] += 0.5 * ds
        w[1:] += 0.5 * ds
        moment += np.sum(w * (-r0[:, 0] * lift_i + m_i))
    weights = np.concatenate([BODY, [15.0 * SEMI]]) * G
    moment += np.sum(weights * np.asarray(masses_x))      # M_y = -x F_z of the weights (F_z = -m g)
    assert abs(moment) < 1e-3 * _weight_half() * 1.0        # N m: below 1 mm of CG shift
    # the trimmed angle of attack and tail incidence equal the rigid plunge/pitch model's
    sp, pp = _pitch_model()
    qd = beam_forcing(N_WING, gravity=[0, 0, -G])
    qd.update(gust_velocity=np.zeros(N_WING), frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3),
              trim_active=1.0, tail_gust_velocity=0.0)
    xp, _ = solve_static(sp, pp, pack(sp.forcing_specs, qd))
    assert abs(x[s.trim_index["alpha_trim"]] / xp[sp.trim_index] - 1) < 1e-3
    assert abs(x[s.trim_index["tail_incidence"]] / xp[sp.body_index["tail_incidence"]] - 1) < 1e-2


def test_stiff_stick_aircraft_reproduces_the_rigid_plunge_pitch_gust_load_factor():
    """1-cos gust from the trimmed 1 g state: the load factor (lift / W) of the stiff stick aircraft
    against the lone wing's plunge/pitch model within 1 % of the peak increment at every step."""
    t = np.arange(0.0, 1.2 + 1e-9, 0.005)
    prof = _gust()
    s, p = _stick()
    lay = layout(s.param_specs)
    x_w = p[lay["wing_node_positions"]].reshape(-1, 3)[:, 0]
    x_t = p[lay["tail_node_positions"]].reshape(-1, 3)[:, 0]
    g_all = station_gust_history(t, np.concatenate([x_w, x_t]), V, prof, x_ref=0.0)
    Q = np.array([pack_aero_forcing(s, {"wing": g_all[k, :N_WING], "tail": g_all[k, N_WING:]},
                                    trim_active=1.0 if k == 0 else 0.0, gravity=[0, 0, -G]) for k in range(t.size)])
    hist = march(s, t, p, Q, atol=1e-7)
    n_stick = np.array([lift_total(s, hist.states[k], hist.rates[k], p, Q[k]) for k in range(t.size)]) / _weight_half()

    sp, pp = _pitch_model()
    qd = beam_forcing(N_WING, gravity=[0, 0, -G])
    gw = station_gust_history(t, np.concatenate([x_w, [x_t[0]]]), V, prof, x_ref=0.0)
    Qp = []
    for k in range(t.size):
        qd.update(gust_velocity=gw[k, :N_WING], frame_velocity=np.zeros(3), frame_velocity_rate=np.zeros(3),
                  trim_active=1.0 if k == 0 else 0.0, tail_gust_velocity=gw[k, -1])
        Qp.append(pack(sp.forcing_specs, qd))
    Qp = np.array(Qp)
    hp = march(sp, t, pp, Qp, atol=1e-7)
    r0 = _wing_params()["node_positions"]
    ds = np.linalg.norm(np.diff(r0, axis=0), axis=1)
    n_pitch = []
    for k in range(t.size):
        lift, _ = sp.section_loads(hp.states[k], hp.rates[k], pp, Qp[k])
        lift = np.asarray(lift).ravel()
        wing = np.sum(0.5 * (lift[:-1] + lift[1:]) * ds)
        n_pitch.append((2 * wing + float(sp.tail_lift(hp.states[k], hp.rates[k], pp, Qp[k]))) / (2 * _weight_half()))
    n_pitch = np.array(n_pitch)
    peak = np.max(np.abs(n_pitch - 1))
    assert peak > 0.3
    err = np.max(np.abs(n_stick - n_pitch)) / peak
    print(f"peak increment {peak:.4f}, largest difference {err:.4%} of it")
    assert err < 0.01


def test_bad_lifting_surfaces_and_supports_are_refused_before_the_build():
    beams = [Beam("fuselage", X_FUS.size, root="free", axes=FUSELAGE_AXES), Beam("wing", N_WING, root="free"),
             Beam("tail", N_TAIL, root="free")]
    joints = [Joint("fuselage", I_WING, "wing", 0), Joint("fuselage", I_TAIL, "tail", 0)]
    cases = [(dict(lifting=("wing", "fuselage")), "axes must be the body axes"),
             (dict(lifting=("wing", "fin")), "'fin' is not a beam"),
             (dict(tail="wing"), "tail = 'wing' must be a lifting beam other than the wing"),
             (dict(supports=SUPPORTS[:2]), "supports: 2 given; trim needs 3"),
             (dict(supports=(("fuselage", 9, "z"),) + SUPPORTS[1:]), "must be (beam, node, 'x'|'y'|'z')")]
    for kw, msg in cases:
        kw = {"supports": SUPPORTS, **kw}
        with pytest.raises(ValueError, match=re.escape(msg)):
            build_joined_aeroelastic_system(beams, joints, **kw)


def test_adjoint_of_a_gust_on_the_trimmed_flexible_stick_aircraft():
    """Discrete adjoint of a 16-step gust march from the trimmed state (static trim step included)
    of the stick aircraft with a flexible wing: d(sum of squared wing-root bending increments)/d(wing
    mass, tail chord, deps/dalpha, airspeed) against central differences, and the tangent sweep."""
    s, p = _stick(dict(EI_cc=4e6, GJ=3e6, EI_nn=4e7, EA=1e9))
    t = np.linspace(0.0, 0.15, 16)
    lay = layout(s.param_specs)
    x_w = p[lay["wing_node_positions"]].reshape(-1, 3)[:, 0]
    x_t = p[lay["tail_node_positions"]].reshape(-1, 3)[:, 0]
    g = station_gust_history(t, np.concatenate([x_w, x_t]), V, _gust(length=10.0, u=5.0), x_ref=0.0)
    Q = np.array([pack_aero_forcing(s, {"wing": g[k, :N_WING], "tail": g[k, N_WING:]},
                                    trim_active=float(k == 0), gravity=[0, 0, -G]) for k in range(t.size)])
    i = s.node_index("wing", 1) + 9          # M_x at the wing's root rib

    def f_of(states):
        d = states[:, i] - states[0, i]
        dfdx = np.zeros_like(states)
        dfdx[:, i] = 2 * d
        dfdx[0, i] -= np.sum(2 * d)
        return float(np.sum(d**2)), dfdx

    run = lambda pp: march(s, t, pp, Q, atol=1e-9, static_options={"atol": 1e-9})  # noqa: E731
    h = run(p)
    f, dfdx = f_of(h.states)
    assert f > 0
    lin = LinearizedHistory(s, t, h.states, p, Q, lu="static")
    grad = lin.gradient(dfdx)[0]
    picks = {"wing mass": lay["wing_mass_per_length"].start + 2, "tail chord": lay["tail_chord"].start + 1,
             "downwash": lay["downwash_gradient"].start, "airspeed": lay["airspeed"].start}
    for name, j in picks.items():
        step = 1e-4 * abs(p[j])
        e = np.zeros_like(p)
        e[j] = step
        fd = (f_of(run(p + e).states)[0] - f_of(run(p - e).states)[0]) / (2 * step)
        print(f"{name}: adjoint {grad[j]:.6e}, central differences {fd:.6e}, {grad[j] / fd - 1:+.1e}")
        assert grad[j] == pytest.approx(fd, rel=2e-5, abs=1e-8 * f), name
    direction = np.zeros_like(p)
    direction[list(picks.values())] = 1.0
    assert np.sum(dfdx * lin.tangent(dp=direction)) == pytest.approx(grad @ direction, rel=1e-8)


def _gust_march(s, p, n_time=16):
    t = np.linspace(0.0, 0.01 * (n_time - 1), n_time)
    lay = layout(s.param_specs)
    x_w = p[lay["wing_node_positions"]].reshape(-1, 3)[:, 0]
    x_t = p[lay["tail_node_positions"]].reshape(-1, 3)[:, 0]
    g = station_gust_history(t, np.concatenate([x_w, x_t]), V, _gust(length=10.0, u=5.0), x_ref=0.0)
    Q = np.array([pack_aero_forcing(s, {"wing": g[k, :N_WING], "tail": g[k, N_WING:]},
                                    trim_active=float(k == 0), gravity=[0, 0, -G]) for k in range(t.size)])
    return t, Q, march(s, t, p, Q, atol=1e-9, static_options={"atol": 1e-9})


def test_lu_column_order_puts_each_lag_after_its_node_and_the_adjoint_needs_no_superlu(kernel_on):
    """The LU column order of the joined aeroelastic system (``lu_orders.system_lu_column_order``:
    the compiled march's and the adjoint's) is a permutation with every strip node's 4 lag states
    right after that node's 18 beam columns, the downwash and trim unknowns last; it factors the
    Newton matrix with fewer multiply-adds than the joined order with the lags last. With it the
    static-pivot adjoint of a gust march of the free half aircraft (symmetry conditions on all 6
    fuselage nodes) solves every step without SuperLU and equals the SuperLU adjoint."""
    s, p = _stick(dict(EI_cc=4e6, GJ=3e6, EI_nn=4e7, EA=1e9))
    order = lu_orders.system_lu_column_order(s)
    n = s.n_state
    assert np.array_equal(np.sort(order), np.arange(n))
    pos = np.argsort(order)
    last = lu_orders.BEAM_NODE_ORDER[-1]
    for beam, lags in s.lag_index.items():
        for i, cols in enumerate(lags):
            node_last = s.node_index(beam, i) + last
            assert np.array_equal(np.sort(pos[cols]), pos[node_last] + 1 + np.arange(4)), (beam, i)
    tail = [s.downwash_index, *s.trim_index.values()]
    assert np.array_equal(np.sort(pos[tail]), np.arange(n - len(tail), n))
    t, Q, h = _gust_march(s, p)
    lin = LinearizedHistory(s, t, h.states, p, Q, lu="static")
    a = lin.m_data[t.size // 2]
    work_new = static_lu.factorization_work(n, lin.m_rows, lin.m_indptr, a, order)
    work_old = static_lu.factorization_work(n, lin.m_rows, lin.m_indptr, a, s.lu_column_order())
    assert work_new < 0.8 * work_old, (work_new, work_old)
    i = s.node_index("wing", 1) + 9
    dfdx = np.zeros_like(h.states)
    dfdx[:, i] = 2 * (h.states[:, i] - h.states[0, i])
    grad = lin.gradient(dfdx)[0]
    ref = LinearizedHistory(s, t, h.states, p, Q, lu="superlu").gradient(dfdx)[0]
    # not compared: d/d(the fuselage's lateral shear compliance, its c component). With the lateral
    # displacement and yaw held at every fuselage node, that compliance alone sets the fuselage's
    # lateral shear (1e-19 m/N for these sections): the Newton matrix is singular to round-off
    # in that direction and any two solvers (SuperLU with two column orders as well) give
    # different values of this derivative
    sl = layout(s.param_specs)["fuselage_compliance_csn"]
    keep = np.ones(p.size, dtype=bool)
    keep[sl.start:sl.stop:3] = False
    np.testing.assert_allclose(grad[keep], ref[keep], rtol=1e-8, atol=1e-10 * np.max(np.abs(ref)))
    assert lin.lu_method == "static"
    assert lin.static_stats["fallback"] == 0, lin.static_stats
    assert np.array_equal(lin._static.col_order, order)


def test_trim_at_a_load_factor_lifts_n_times_the_weight():
    """A steady pull-up at n = 2.5: the body axes accelerate upward at (n - 1) g (the shared forcing
    ``frame_acceleration``); the trim then gives lift = n W (W from the model's masses) with no
    support reaction."""
    s, p = _stick()
    n = 2.5
    shared = dict(gravity=[0, 0, -G], frame_acceleration=[0, 0, (n - 1) * G])
    x, _ = solve_static(s, p, pack_aero_forcing(s, trim_active=1.0, **shared))
    q0 = pack_aero_forcing(s, trim_active=0.0, **shared)
    assert np.max(np.abs(s.residual(x, 0 * x, p, q0))) < 1e-8 * _weight_half()
    assert abs(lift_total(s, x, 0 * x, p, q0, vertical=True) / (n * _weight_half()) - 1.0) < 1e-4
