"""Compiled CasADi functions with an on-disk cache: same numbers, cache hits, clean fallbacks."""

import subprocess

import casadi as ca
import numpy as np
import pytest

from wingmdao.utils import casadi_cache as cc

pytestmark = pytest.mark.skipif(cc.compiler() is None, reason="needs gcc")


@pytest.fixture
def jit_env(tmp_path, monkeypatch):
    monkeypatch.setenv(cc.ENV_JIT, "1")
    monkeypatch.setenv(cc.ENV_CACHE, str(tmp_path / "cache"))
    monkeypatch.setattr(cc._warn_once, "issued", False)
    return tmp_path / "cache"


def _function(name="f"):
    x, y = ca.SX.sym("x", 4), ca.SX.sym("y", 2)
    out = ca.vertcat(ca.sin(x[0]) * y[0] + x[1] ** 3, ca.exp(x[2] - y[1]) / (1 + x[3] ** 2), ca.sumsqr(x))
    return ca.Function(name, [x, y], [out, ca.jacobian(out, x)])


def _eval(f, x, y):
    return [np.array(o.full()) for o in f(x, y)]


def test_compiled_equals_interpreted_and_is_cached(jit_env):
    f = _function()
    g = cc.compiled(f)
    assert g is not f and g.class_name() == "External"
    rng = np.random.default_rng(1)
    for _ in range(5):
        x, y = rng.normal(size=4), rng.normal(size=2)
        for a, b in zip(_eval(f, x, y), _eval(g, x, y)):
            np.testing.assert_allclose(b, a, rtol=1e-13, atol=1e-15)
    libs = list(jit_env.glob("f_*.so"))
    assert len(libs) == 1


def test_cache_hit_does_not_call_the_compiler(jit_env, monkeypatch):
    f = _function()
    cc.compiled(f)

    def no_gcc(*args, **kwargs):
        raise AssertionError("gcc called on a cache hit")

    monkeypatch.setattr(subprocess, "Popen", no_gcc)
    g = cc.compiled(_function())          # a new, identical function: same key
    assert g.class_name() == "External"


def test_different_function_different_key(jit_env):
    x = ca.SX.sym("x")
    f1, f2 = ca.Function("h", [x], [x ** 2]), ca.Function("h", [x], [x ** 3])
    assert cc.function_key(f1) != cc.function_key(f2)


def test_corrupt_library_is_rebuilt(jit_env):
    f = _function()
    path = cc.library_path(f)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(b"not a shared library")
    assert cc.cached(f) is None
    g = cc.compiled(f)
    assert g.class_name() == "External"
    np.testing.assert_allclose(_eval(g, np.ones(4), np.ones(2))[0], _eval(f, np.ones(4), np.ones(2))[0], rtol=1e-13)


def test_missing_compiler_falls_back_with_one_warning(jit_env, monkeypatch):
    monkeypatch.setattr(cc, "compiler", lambda: None)
    f = _function()
    with pytest.warns(RuntimeWarning, match="interpreted"):
        assert cc.compiled(f) is f


def test_disabled_by_environment(jit_env, monkeypatch):
    monkeypatch.setenv(cc.ENV_JIT, "0")
    f = _function()
    assert cc.compiled(f) is f
    jf = cc.JitFunction(f, threshold=0)
    jf.count()
    assert jf.state == "disabled" and jf.current is f


def test_jit_function_switches_after_threshold(jit_env):
    f = _function()
    jf = cc.JitFunction(f, threshold=3)
    jf.count(2)
    assert jf.state == "interpreted" and not jf.poll()
    jf.count(1)
    jf.start(wait=True)
    assert jf.poll() and jf.state == "compiled" and jf.current.class_name() == "External"


def test_warm_cache_serves_from_the_first_evaluation(jit_env):
    """A library already in the cache is used from the first evaluation, not after the threshold;
    a cold cache waits for the threshold."""
    f = _function()
    cold = cc.JitFunction(f, threshold=10**9)
    cold.count()
    assert cold.state == "interpreted" and not cold.poll()
    cc.compiled(f)                                   # another run compiled it meanwhile
    warm = cc.JitFunction(_function(), threshold=10**9)
    warm.count()
    assert warm.poll() and warm.state == "compiled" and warm.current.class_name() == "External"


def test_evaluations_are_tallied_by_the_path_they_ran(jit_env, monkeypatch):
    """``EVALUATIONS[name] = [interpreted, compiled]``: a cold function counts interpreted until its
    compiled library is swapped in; a warm one counts compiled from its first evaluation; with
    ``WINGMDAO_JIT=0`` every evaluation counts interpreted."""
    monkeypatch.setattr(cc, "EVALUATIONS", {})
    cold = cc.JitFunction(_function("tally"), threshold=3)
    cold.count(2)
    assert cc.EVALUATIONS["tally"] == [2, 0]
    cold.count(1)
    cold.start(wait=True)
    cold.count(4)            # the library is ready (switched at the next poll): compiled
    cold.poll()
    cold.count(5)
    assert cc.EVALUATIONS["tally"] == [3, 9]
    warm = cc.JitFunction(_function("tally"), threshold=10**9)
    warm.count(7)
    assert cc.EVALUATIONS["tally"] == [3, 16]
    monkeypatch.setenv(cc.ENV_JIT, "0")
    off = cc.JitFunction(_function("tally"), threshold=2)
    off.count(1)
    off.count(10)
    assert off.state == "disabled" and cc.EVALUATIONS["tally"] == [14, 16]


def test_a_corrupt_cached_library_is_recompiled_by_the_jit_function(jit_env):
    f = _function()
    path = cc.library_path(f)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(b"not a shared library")
    jf = cc.JitFunction(f, threshold=1)
    jf.count()
    jf.start(wait=True)
    assert jf.poll() and jf.current.class_name() == "External"


def test_beam_system_compiled_matches_interpreted(jit_env):
    from wingmdao.beam.residual import build_beam_system
    from wingmdao.beam.static import beam_forcing, beam_parameters, straight_beam
    from wingmdao.timemarch.system import pack

    n = 3
    interp, comp = build_beam_system(n), build_beam_system(n)
    states = comp.compile(wait=True)
    assert set(states.values()) == {"compiled"}
    r0, th0 = straight_beam(n, 2.0)
    p = pack(comp.param_specs, beam_parameters(r0, th0, EI_cc=5e4, GJ=4e4, EI_nn=2e5, EA=1e7, GK_c=1e7, GK_n=1e7,
                                                mass_per_length=3.0, inertia_per_length=np.diag([0.01, 0.02, 0.01])))
    rng = np.random.default_rng(2)
    X, Xd = rng.normal(size=(4, 18 * n)), rng.normal(size=(4, 18 * n))
    Q = np.tile(pack(comp.forcing_specs, beam_forcing(n, point_force=[1.0, 2.0, 3.0])), (4, 1))
    np.testing.assert_allclose(comp.residual_history(X, Xd, p, Q), interp.residual_history(X, Xd, p, Q),
                               rtol=1e-13, atol=1e-12)
    ja, jb = comp.jacobian_history(X, Xd, p, Q), interp.jacobian_history(X, Xd, p, Q)
    for k in ja:
        np.testing.assert_allclose(ja[k], jb[k], rtol=1e-13, atol=1e-12)
    ra, ma = comp.residual_and_newton_matrix(X[0], Xd[0], p, Q[0], 50.0)
    rb, mb = interp.residual_and_newton_matrix(X[0], Xd[0], p, Q[0], 50.0)
    np.testing.assert_allclose(ra, rb, rtol=1e-13, atol=1e-12)
    np.testing.assert_allclose(np.asarray(ma.todense() if hasattr(ma, "todense") else ma),
                               np.asarray(mb.todense() if hasattr(mb, "todense") else mb), rtol=1e-13, atol=1e-12)


def test_pointwise_component_switches_to_compiled(jit_env, monkeypatch):
    """A pointwise component (BoxStress) gives the same outputs and partials once compiled."""
    import openmdao.api as om

    from wingmdao.components import pointwise
    from wingmdao.components.stress import BoxStress
    from wingmdao.materials import ALUMINIUM

    monkeypatch.setattr(pointwise, "POINT_JIT_THRESHOLD", 10 ** 9)   # compiled below, on demand
    n, nt = 3, 2
    rng = np.random.default_rng(4)
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("s", BoxStress(num_times=nt, num_stations=n, material=ALUMINIUM), promotes=["*"])
    prob.setup()
    prob.set_val("width", rng.uniform(0.6, 1.2, n))
    prob.set_val("height", rng.uniform(0.2, 0.4, n))
    for k in ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar"):
        prob.set_val(k, rng.uniform(0.003, 0.02, n))
    prob.set_val("F_csn", rng.normal(0, 1e5, (nt, n, 3)))
    prob.set_val("M_csn", rng.normal(0, 1e5, (nt, n, 3)))
    prob.run_model()
    comp = prob.model.s
    out0 = {k: np.array(v) for k, v in comp._outputs.items()}
    jac0 = comp._fjac(*comp._stacked_inputs(comp._inputs))
    for jit in (comp._jit_f, comp._jit_fjac):
        jit.jit.start(wait=True)
    prob.run_model()
    assert comp._jit_f.jit.state == "compiled" and comp._f.class_name() != "SXFunction"
    for k, v in comp._outputs.items():
        np.testing.assert_allclose(np.array(v), out0[k], rtol=1e-13, atol=1e-9)
    comp._fjac = comp._jit_fjac.update(comp._fjac)
    assert comp._jit_fjac.jit.state == "compiled"
    jac1 = comp._fjac(*comp._stacked_inputs(comp._inputs))
    for a, b in zip(jac1 if isinstance(jac1, (list, tuple)) else [jac1], jac0 if isinstance(jac0, (list, tuple)) else [jac0]):
        np.testing.assert_allclose(np.array(a), np.array(b), rtol=1e-13, atol=1e-9)


def test_compile_running_at_exit_finishes_and_fills_the_cache(jit_env):
    """A background compile still running when the program exits completes detached; the next run
    finds the library (and no temporary files are left)."""
    import sys
    import time

    script = (
        "import casadi as ca\n"
        "from wingmdao.utils.casadi_cache import JitFunction\n"
        "x = ca.SX.sym('x', 30)\n"
        "f = ca.Function('exit_case', [x], [ca.sumsqr(ca.sin(x)) * ca.exp(x[0])])\n"
        "JitFunction(f, threshold=0).start()\n"
        "import time; time.sleep(0.5)\n"
    )
    subprocess.run([sys.executable, "-c", script], check=True, timeout=120)
    for _ in range(240):
        libs = list(jit_env.glob("exit_case_*.so"))
        if libs:
            break
        time.sleep(0.25)
    assert len(libs) == 1
    time.sleep(0.5)
    assert not list(jit_env.glob(".*"))                   # sources, partial libraries, logs removed


def test_manifest_records_size_and_hash(jit_env):
    f = _function()
    cc.compiled(f)
    path = cc.library_path(f)
    size, digest = cc.manifest_path(path).read_text().split()
    assert (int(size), digest) == cc.file_digest(path)


def test_truncated_library_is_detected_before_dlopen(jit_env, monkeypatch):
    """A truncated library (full disk, killed copy) would SIGBUS inside dlopen: the size check
    against the manifest rejects it first, and it is rebuilt."""
    f = _function()
    cc.compiled(f)
    path = cc.library_path(f)
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])

    def no_dlopen(*a, **k):
        raise AssertionError("dlopen of a library that failed verification")

    with monkeypatch.context() as m:
        m.setattr(ca, "external", no_dlopen)
        assert cc.cached(f) is None
    assert not path.exists()
    assert cc.compiled(f).class_name() == "External"


def test_same_size_corruption_is_detected_by_the_hash(jit_env):
    f = _function()
    cc.compiled(f)
    path = cc.library_path(f)
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    path.write_bytes(bytes(data))
    with pytest.raises(cc.CompileError, match="SHA-256"):
        cc.verify(path)


def test_library_without_manifest_is_not_loaded(jit_env):
    f = _function()
    cc.compiled(f)
    path = cc.library_path(f)
    cc.manifest_path(path).unlink()
    assert cc.cached(f) is None and not path.exists()


def test_folder_writable_by_others_is_refused_with_a_warning(jit_env):
    f = _function()
    cc.compiled(f)
    jit_env.chmod(0o777)
    try:
        with pytest.raises(cc.UnsafeCache, match="writable by group or others"):
            cc.verify(cc.library_path(f))
        with pytest.warns(RuntimeWarning, match="writable by group or others"):
            assert cc.compiled(_function()) is not None
        assert cc.library_path(f).exists()  # not deleted: it may not be ours
    finally:
        jit_env.chmod(0o700)


def test_library_owned_by_another_user_is_refused(jit_env, monkeypatch):
    f = _function()
    cc.compiled(f)
    uid = cc.os.getuid()
    monkeypatch.setattr(cc.os, "getuid", lambda: uid + 1)
    with pytest.raises(cc.UnsafeCache, match="owned by user id"):
        cc.verify(cc.library_path(f))


# ---------------------------------------------------------------- keys by definition (issue #15)
def _no_serialize(monkeypatch):
    def boom(self, *args, **kwargs):
        raise AssertionError("Function.serialize() called although a definition key was given")

    monkeypatch.setattr(ca.Function, "serialize", boom)


def test_definition_key_changes_with_every_builder_argument():
    from wingmdao.beam.residual import StrainRateDamping, beam_definition

    base = beam_definition(21)
    assert beam_definition(21) == base                        # deterministic
    assert beam_definition(21, damping=StrainRateDamping()) == base   # zero damping builds the same system
    others = [beam_definition(22), beam_definition(21, euler_sequence="aswing"),
              beam_definition(21, damping=StrainRateDamping((1e-3, 0, 0), (0, 0, 0))),
              beam_definition(21, damping=StrainRateDamping((2e-3, 0, 0), (0, 0, 0)))]
    assert len({base, *others}) == 1 + len(others)


def test_definition_key_includes_the_generating_source(tmp_path, monkeypatch):
    import importlib
    import os

    mod_file = tmp_path / "gen_mod_s7.py"
    mod_file.write_text("A = 1\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    mod = importlib.import_module("gen_mod_s7")
    k1 = cc.definition_key("builder", (3,), [mod])
    mod_file.write_text("A = 2  # edited\n")
    os.utime(mod_file, ns=(1, 10 ** 18))                     # a new mtime even on coarse clocks
    k2 = cc.definition_key("builder", (3,), [mod])
    assert k1 != k2
    assert cc.definition_key("builder", (4,), [mod]) != k2
    assert cc.definition_key("other", (3,), [mod]) != k2


def test_function_key_by_definition_does_not_serialize(monkeypatch):
    f = _function("g")
    by_def = cc.function_key(f, definition="d1")
    assert by_def != cc.function_key(f)
    _no_serialize(monkeypatch)
    assert cc.function_key(f, definition="d1") == by_def
    assert cc.function_key(f, definition="d2") != by_def
    assert cc.function_key(f, ("-O2",), definition="d1") != by_def
    x = ca.SX.sym("x", 4)
    other_name = ca.Function("h", [x], [x])
    assert cc.function_key(other_name, definition="d1") != by_def


def test_warm_beam_cache_is_served_without_serializing(jit_env, monkeypatch):
    """A second build of the same beam finds the compiled libraries by definition alone (no
    Function.serialize) and gives the same numbers as the interpreted functions."""
    from wingmdao.beam.residual import beam_definition, build_beam_system

    n = 3
    first = build_beam_system(n)
    assert first.definition == beam_definition(n)
    assert set(first.compile(wait=True).values()) == {"compiled"}
    _no_serialize(monkeypatch)
    monkeypatch.setattr(subprocess, "Popen", lambda *a, **k: (_ for _ in ()).throw(AssertionError("gcc")))
    warm = build_beam_system(n)
    assert set(warm.compile(wait=True).values()) == {"compiled"}
    cold = build_beam_system(n)
    cold.set_jit_threshold(10 ** 15)
    monkeypatch.setenv(cc.ENV_JIT, "0")
    rng = np.random.default_rng(3)
    x, xd = rng.normal(size=18 * n), rng.normal(size=18 * n)
    p, q = rng.normal(size=warm.n_param), rng.normal(size=warm.n_forcing)
    ra, ma = warm.residual_and_newton_matrix(x, xd, p, q, 7.0)
    rb, mb = cold.residual_and_newton_matrix(x, xd, p, q, 7.0)
    np.testing.assert_allclose(ra, rb, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(ma.toarray(), mb.toarray(), rtol=1e-13, atol=1e-13)


def test_newton_matrix_is_dx_plus_alpha_dxdot():
    """The Newton function reuses the dR/dx, dR/dxdot expressions: same numbers as the separate
    Jacobian functions (to round-off of one multiply-add)."""
    from wingmdao.beam.residual import build_beam_system

    s = build_beam_system(4)
    rng = np.random.default_rng(4)
    x, xd = rng.normal(size=s.n_state), rng.normal(size=s.n_state)
    p, q = rng.normal(size=s.n_param), rng.normal(size=s.n_forcing)
    r, m = s.residual_and_newton_matrix(x, xd, p, q, 3.5)
    jx, jxd = s.jac_state(x, xd, p, q)
    np.testing.assert_allclose(np.asarray(m.todense() if hasattr(m, "todense") else m),
                               (jx + 3.5 * jxd).toarray(), rtol=1e-15, atol=1e-12)
    np.testing.assert_array_equal(r, s.residual(x, xd, p, q))


def test_library_bytes_do_not_depend_on_the_compiling_process(jit_env, monkeypatch):
    """Two compiles of one function (other pid / thread: other temporary names) give the same
    bytes, so a reader between one compile's manifest and the other's library never sees a
    hash mismatch. The cache folder may be given as a relative path."""
    import hashlib
    import os

    monkeypatch.chdir(jit_env.parent)
    monkeypatch.setenv(cc.ENV_CACHE, "cache")
    f = _function("det")
    digests = []
    for pid in (1111, 2222):
        path = cc.library_path(f)
        for p in (path, cc.manifest_path(path)):
            p.unlink(missing_ok=True)
        monkeypatch.setattr(os, "getpid", lambda pid=pid: pid)
        assert cc.compile_library(f) == path
        digests.append(hashlib.sha256(path.read_bytes()).hexdigest())
        cc.verify(path)
    assert digests[0] == digests[1]
    assert sorted(p.name for p in path.parent.iterdir()) == sorted([path.name, cc.manifest_path(path).name])


def test_under_mpirun_no_compile_starts_mid_run_but_a_cached_library_loads(jit_env, monkeypatch):
    """Under ``mpirun -n 2`` a JitFunction never starts a compile at its threshold (a compile ends at
    a different evaluation on each rank, and the ranks' drivers would drift apart at round-off),
    but a library already cached is loaded at the first evaluation, as in a serial run."""
    monkeypatch.setenv("OMPI_COMM_WORLD_SIZE", "2")
    assert cc.under_mpi()
    jf = cc.JitFunction(_function("g_mpi"), threshold=3)
    jf.count(5)
    assert jf.state == "interpreted" and not jf.poll()      # no compile started
    assert not list(jit_env.glob("g_mpi_*.so"))
    monkeypatch.delenv("OMPI_COMM_WORLD_SIZE")
    cc.compiled(_function("g_mpi"))                          # a serial run put it in the cache
    monkeypatch.setenv("OMPI_COMM_WORLD_SIZE", "2")
    jf2 = cc.JitFunction(_function("g_mpi"), threshold=3)
    jf2.count(1)
    assert jf2.poll() and jf2.state == "compiled"
    monkeypatch.delenv("OMPI_COMM_WORLD_SIZE")
    jf3 = cc.JitFunction(_function("h_serial"), threshold=3)
    jf3.count(5)
    assert jf3.state == "compiling"                          # serial: the compile starts at the threshold
    jf3.start(wait=True)


def test_aeroelastic_definition_changes_with_every_builder_argument():
    from wingmdao.aero.system import aeroelastic_definition
    from wingmdao.beam.residual import StrainRateDamping, beam_definition

    base = aeroelastic_definition(20)
    assert aeroelastic_definition(20) == base
    assert aeroelastic_definition(20, damping=StrainRateDamping()) == base
    others = [aeroelastic_definition(21), aeroelastic_definition(20, euler_sequence="aswing"),
              aeroelastic_definition(20, damping=StrainRateDamping((1e-3, 0, 0), (0, 0, 0))),
              aeroelastic_definition(20, plunge=True), aeroelastic_definition(20, trim=True),
              aeroelastic_definition(20, plunge=True, trim=True, pitch=True),
              aeroelastic_definition(20, plunge=True, trim=True, pitch=True, tail_lag=True),
              beam_definition(20)]
    assert len({base, *others}) == 1 + len(others)


def test_a_march_counts_its_steps_towards_the_newton_compile(jit_env):
    """Modified Newton evaluates the Newton matrix a few times per march; the compiled march uses
    it at every step, so a march counts its steps and a system that is only marched gets
    compiled (the coupled aeroelastic beam stayed interpreted before)."""
    from wingmdao.timemarch.bdf import march
    from wingmdao.timemarch.examples import nonlinear_chain_system

    system = nonlinear_chain_system(3)
    system.set_jit_threshold(100)
    p = np.concatenate([[1.0, 0.1, 0.5], np.full(3, 10.0)])
    t = np.linspace(0.0, 1.0, 61)
    forcing = np.tile([0.0, 0.0, 1.0], (t.size, 1))
    march(system, t, p, forcing, modified_newton=True, fast=False)
    newton = system._fast_newton.jit
    assert newton.evaluations >= 60 and newton.state == "interpreted"
    march(system, t, p, forcing, modified_newton=True, fast=False)
    assert newton.state in ("compiling", "compiled")


def _relative_difference(a, b):
    return max(np.max(np.abs(np.ravel(u) - np.ravel(v))) / np.max(np.abs(u)) for u, v in zip(a, b))


def test_cse_generates_the_same_newton_function_with_fewer_instructions():
    """The copy generated after common-subexpression elimination gives the residual and Newton
    matrix of a coupled vortex-lattice wing (free plunge, trim) to 1e-12 at a random state, with
    fewer instructions; without cse, and for MX functions, the function itself is generated."""
    from wingmdao.aero.system import build_aeroelastic_system

    f = build_aeroelastic_system(4, plunge=True, trim=True, aero_theory="vlm")._newton
    g = cc.codegen_function(f, cse=True)
    assert g.name() == f.name() and g.n_instructions() < 0.95 * f.n_instructions()
    assert cc.codegen_function(f, cse=False) is f
    rng = np.random.default_rng(5)
    args = [rng.normal(scale=0.1, size=f.nnz_in(i)) if i < 2 else rng.uniform(0.1, 0.5, size=f.nnz_in(i))
            for i in range(f.n_in())]
    ref, out = [o.full() for o in f(*args)], [o.full() for o in g(*args)]
    assert all(np.isfinite(o).all() and np.abs(o).max() > 0 for o in ref)
    assert _relative_difference(ref, out) < 1e-12
    m = ca.MX.sym("m", 2)
    fm = ca.Function("fm", [m], [ca.sin(m) + ca.sin(m)])
    assert cc.codegen_function(fm, cse=True) is fm


def test_cse_is_part_of_the_cache_key(jit_env):
    """Libraries generated with and without cse have different keys (an old library is never
    served for the other option); both compile to the interpreted function's values."""
    f = _function("cse_key")
    assert cc.function_key(f) == cc.function_key(f, cse=cc.CSE)
    assert cc.function_key(f, cse=True) != cc.function_key(f, cse=False)
    assert cc.function_key(f, definition="d", cse=True) != cc.function_key(f, definition="d", cse=False)
    paths = [cc.compile_library(f, cse=cse) for cse in (False, True)]
    assert paths[0] != paths[1] and paths[int(cc.CSE)] == cc.library_path(f)
    x, y = np.array([0.3, -1.2, 0.7, 2.0]), np.array([0.4, -0.5])
    for path in paths:
        assert _relative_difference(_eval(f, x, y), _eval(cc.load(f, path), x, y)) < 1e-13
