"""The one homes of shared concepts: unit constants, the KS formula, the once-per-process warning,
objects derived from a system, and the beam-parameter dict from section properties."""

import warnings

import numpy as np
import pytest

from wingmdao import units
from wingmdao.section.box import beam_params_from_rows, beam_params_from_section
from wingmdao.timemarch.system import ResidualSystem, derived
from wingmdao.utils.ks import ks_aggregate, ks_gradient, ks_value
from wingmdao.utils.warn_once import WarnOnce


def test_units_are_the_exact_definitions():
    """NIST SP 811 (2008), App. B: 1 lbf = 4.448 221 615 260 5 N, 1 slug = 14.593 90 kg,
    1 ft = 0.3048 m, 1 lb = 0.453 592 37 kg, g_n = 9.806 65 m/s^2, 1 knot = 1852/3600 m/s."""
    assert units.LBF == pytest.approx(4.4482216152605, rel=1e-15)
    assert units.SLUG == pytest.approx(14.59390, rel=1e-6)
    assert (units.FT, units.LB, units.G0) == (0.3048, 0.45359237, 9.80665)
    assert units.KNOT == pytest.approx(0.514444, rel=1e-6)


def test_ks_closed_form_and_one_exponential():
    """N equal entries: KS = g + ln(N) / rho, weights 1 / N; ks_aggregate = (ks_value, ks_gradient)."""
    g = np.full((3, 4), -0.25)
    val, w = ks_aggregate(g, 50.0)
    assert val == pytest.approx(-0.25 + np.log(12.0) / 50.0, rel=1e-15)
    np.testing.assert_allclose(w, np.full(12, 1.0 / 12.0), rtol=1e-15)
    rng = np.random.default_rng(0)
    g = rng.standard_normal(20) * 30.0
    val, w = ks_aggregate(g, 100.0)
    assert val == ks_value(g, 100.0) and np.array_equal(w, ks_gradient(g, 100.0))
    assert g.max() <= val <= g.max() + np.log(20) / 100.0


def test_warn_once_warns_once_until_reset():
    once = WarnOnce("fallback used ({})")
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        once("a")
        once("b")
        assert [str(w.message) for w in got] == ["fallback used (a)"]
        once.reset()
        once("c")
        assert [str(w.message) for w in got][-1] == "fallback used (c)" and len(got) == 2
        assert all(w.category is RuntimeWarning for w in got)


def test_derived_is_built_once_per_system_and_kept_on_it():
    class System:
        pass

    built = []

    def build(s):
        built.append(s)
        return object()

    a, b = System(), System()
    assert derived(a, "x", build) is derived(a, "x", build)
    assert derived(b, "x", build) is not derived(a, "x", build)
    assert built == [a, b] and "x" in a._derived


def test_beam_params_from_section_of_rows_and_of_one_section():
    """The per-node dict from rows equals the one-section dicts stacked."""
    rng = np.random.default_rng(1)
    rows = [{"stiffness_csn": rng.standard_normal((3, 3)), "compliance_csn": rng.standard_normal(3),
             "c_ea": rng.random(), "n_ea": rng.random(), "c_sc": rng.random(), "n_sc": rng.random(),
             "c_cg": rng.random(), "n_cg": rng.random(), "mass_per_length": rng.random(),
             "inertia_per_length": rng.standard_normal((3, 3))} for _ in range(4)]
    pos, ang = rng.standard_normal((4, 3)), rng.standard_normal((4, 3))
    full = beam_params_from_rows(rows, pos, ang)
    one = [beam_params_from_section(r) for r in rows]
    assert np.array_equal(full["node_positions"], pos) and np.array_equal(full["node_euler_angles"], ang)
    for k, _v in one[0].items():
        assert np.array_equal(full[k], np.array([o[k] for o in one])), k
    assert full["tension_axis"].shape == (4, 2) and full["inertia_per_length"].shape == (4, 3, 3)
    assert np.array_equal(full["shear_center"][2], [rows[2]["c_sc"], rows[2]["n_sc"]])


def test_a_system_pickles_without_its_derived_objects():
    """An OpenMDAO recorder pickles the components' options, which hold the system: the derived
    objects (compiled functions, which do not pickle) stay out and are rebuilt on demand."""
    import pickle
    import threading

    system = _Tiny()
    lock = derived(system, "unpicklable", lambda s: threading.Lock())
    copy = pickle.loads(pickle.dumps(system))
    assert "_derived" not in vars(copy) and derived(system, "unpicklable", None) is lock


class _Tiny(ResidualSystem):
    n_state, state_shape, param_specs, forcing_specs = 1, (1,), [], []


def test_a_shared_c_header_is_inserted_and_keys_the_library(tmp_path):
    """``#include "file"`` of a package file is inserted into the compiled source and its bytes
    key the library (an edit of ``timemarch/lu_triangular.h`` recompiles both LU kernels); the
    real and complex kernels both include that one header."""
    from wingmdao.stability import pencil_lu
    from wingmdao.timemarch import static_lu
    from wingmdao.utils import c_library

    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "h.h").write_text("static int twice(int x) { return 2 * x; }\n")
    src = tmp_path / "k.c"
    src.write_text('#include <math.h>\n#include "sub/h.h"\nint f(int x) { return twice(x); }\n')
    text = c_library.expanded_source(src).decode()
    assert "return 2 * x" in text and "#include <math.h>" in text and '#include "sub/h.h"' not in text
    key = c_library.library_key(src)
    (tmp_path / "sub" / "h.h").write_text("static int twice(int x) { return x + x; }\n")
    assert c_library.library_key(src) != key
    for kernel in (static_lu.SOURCE, pencil_lu.SOURCE):
        assert "static void LU_SOLVE(" in c_library.expanded_source(kernel).decode()
