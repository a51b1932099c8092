"""Loads as promoted inputs (issue: embedding): an upstream component drives a case's forcing,
and the totals of KS with respect to that component's parameter match finite differences for a
static and a dynamic case; the tutorial's embedding snippets run as written."""

import re
from pathlib import Path

import numpy as np
import openmdao.api as om
import pytest

from wingmdao.groups.load_case import FORCING_SHAPES, LoadCase
from wingmdao.groups.wing import FORCING_META, WingSizing, WingStructure
from wingmdao.materials import ALUMINIUM

N = 6
SPAN = 8.0


class SpanLoad(om.ExplicitComponent):
    """force_per_length = lift_per_length * shape: a stand-in for an aerodynamic solver."""

    def initialize(self):
        self.options.declare("shape", types=np.ndarray, desc="(n_time, n, 3) load shape")

    def setup(self):
        shape = self.options["shape"]
        self.add_input("lift_per_length", val=1.0, units="N/m", desc="running lift at the root")
        self.add_output("force_per_length", shape=shape.shape, units="N/m", desc="distributed force")
        self.declare_partials("force_per_length", "lift_per_length", rows=np.arange(shape.size),
                              cols=np.zeros(shape.size, dtype=int), val=shape.ravel())

    def compute(self, inputs, outputs):
        outputs["force_per_length"] = inputs["lift_per_length"] * self.options["shape"]


def _shape(time):
    eta = np.linspace(0.0, 1.0, N)
    s = np.zeros((time.size, N, 3))
    s[:, :, 2] = np.sqrt(1.0 - 0.99 * eta ** 2)[None, :] * (1.0 - np.cos(np.pi * time / max(time[-1], 1e-9)))[:, None] \
        if time.size > 1 else np.sqrt(1.0 - 0.99 * eta ** 2)[None, :]
    return s


def _model():
    static = LoadCase("pullup", np.zeros(1), families=("vm", "ss_tension"))
    gust = LoadCase("gust", np.linspace(0.0, 0.12, 13), families=("vm",))
    prob = om.Problem(reports=False)
    model = prob.model
    for case in (static, gust):  # upstream of the wing, so they run first
        model.add_subsystem(f"aero_{case.name}", SpanLoad(shape=_shape(case.time)))
    model.add_subsystem("wing", WingSizing(num_nodes=N, load_cases=[static, gust], material=ALUMINIUM,
                                           parallel=False, add_constraints=True, add_objective=True,
                                           mass_ref=100.0), promotes=["*"])
    for case in (static, gust):
        model.connect(f"aero_{case.name}.force_per_length", f"cases.{case.name}.force_per_length")
    model.add_design_var("aero_pullup.lift_per_length")
    model.add_design_var("aero_gust.lift_per_length")
    model.add_design_var("t_upper_skin", lower=1e-3, upper=0.05)
    prob.setup(mode="rev")
    y = np.linspace(0.0, SPAN, N)
    prob.set_val("node_positions", np.column_stack([np.zeros(N), y, np.zeros(N)]))
    prob.set_val("width", np.linspace(0.8, 0.4, N))
    prob.set_val("height", np.linspace(0.25, 0.12, N))
    prob.set_val("section_to_csn", np.broadcast_to(np.eye(3), (N, 3, 3)))
    rng = np.random.default_rng(3)
    for w in ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar"):
        prob.set_val(w, rng.uniform(2e-3, 5e-3, N))
    prob.set_val("aero_pullup.lift_per_length", 3.0e4)
    prob.set_val("aero_gust.lift_per_length", 1.5e4)
    prob.run_model()
    return prob


@pytest.fixture(scope="module")
def prob():
    return _model()


def test_group_declares_constraints_and_objective(prob):
    cons = prob.model.get_constraints()
    assert {"cases.pullup.ks_vm", "cases.pullup.ks_ss_tension", "cases.gust.ks_vm"} <= set(cons)
    assert all(c["upper"] == 0.0 for c in cons.values())
    assert list(prob.model.get_objectives()) == ["mass"]


def test_connected_load_reaches_the_beam(prob):
    """Root bending moment from the beam equals the integral of the connected running load."""
    states = prob.get_val("cases.pullup.states")[0]  # (n, 18)
    fz = prob.get_val("cases.pullup.force_per_length")[0, :, 2]
    y = np.linspace(0.0, SPAN, N)
    # statics of the element equilibrium of App. A on the deformed nodes (dead load per undeformed
    # length = mean of its nodal values, at the element midpoint):
    # F_i = F_(i+1) + h f_avg, M_i = M_(i+1) + dr_i x (F_(i+1) + h f_avg / 2)
    h = np.diff(y)
    f_avg = 0.5 * (fz[:-1] + fz[1:])
    dr = np.diff(states[:, 0:3], axis=0)
    shear, moment = np.zeros(3), np.zeros(3)
    for i in reversed(range(N - 1)):
        f_el = np.array([0.0, 0.0, h[i] * f_avg[i]])
        moment += np.cross(dr[i], shear + 0.5 * f_el)
        shear += f_el
    np.testing.assert_allclose(states[0, 6:9], shear, rtol=1e-9, atol=1e-6)  # root F
    np.testing.assert_allclose(states[0, 9:12], moment, rtol=1e-9, atol=1e-3 * abs(moment).max())


def test_totals_wrt_upstream_load_match_fd(prob):
    data = prob.check_totals(of=["cases.pullup.ks_vm", "cases.gust.ks_vm"],
                             wrt=["aero_pullup.lift_per_length", "aero_gust.lift_per_length", "t_upper_skin"],
                             method="fd", form="central", step=1e-6, step_calc="rel_avg",
                             out_stream=None)
    checked = 0
    for (of, wrt), d in data.items():
        fd, rev = d["J_fd"], d["J_rev"]
        ref = np.abs(fd).max()
        if ref < 1e-14:
            assert np.abs(rev).max() < 1e-10, (of, wrt)
            continue
        checked += 1
        assert np.abs(rev - fd).max() <= 2e-5 * ref, (of, wrt, rev, fd)
    # each case's KS depends on its own load parameter and on the thickness
    assert checked >= 4


def test_forcing_names_are_one_table():
    assert list(FORCING_META) == list(FORCING_SHAPES)


def test_standalone_structure_with_loads_component():
    """WingStructure on its own with loads_component=True holds the case's arrays itself."""
    f = np.zeros((1, N, 3))
    f[0, -1, 2] = 2.0e3
    case = LoadCase("tip", np.zeros(1), {"point_force": f})
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("s", WingStructure(num_nodes=N, load_case=case, material=ALUMINIUM,
                                                loads_component=True))
    prob.setup()
    assert prob.get_val("s.loads.point_force")[0, -1, 2] == 2.0e3
    assert "s.point_force" not in prob.model.get_io_metadata(iotypes="input", return_rel_names=False)


def _tutorial_block(title):
    text = Path(__file__).resolve().parents[1].joinpath("docs", "tutorial.md").read_text(encoding="utf-8")
    section = text.split(f"## {title}", 1)[1]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_tutorial_embedding_snippet_runs():
    code = _tutorial_block("5. Embedding the group in your own model")
    scope = {}
    exec(compile(code, "docs/tutorial.md (Embedding)", "exec"), scope)
    assert scope["totals"][("cases.pullup.ks_vm", "lift.scale")].shape == (1, 1)


@pytest.mark.slow
def test_tutorial_groups_snippet_runs():
    code = _tutorial_block("4. The same sizing from Python")
    scope = {}
    exec(compile(code, "docs/tutorial.md (sizing from Python)", "exec"), scope)
    assert 300.0 < scope["result"]["mass_kg"] < 400.0


def test_components_cite_the_dissertation(prob):
    from wingmdao import DISSERTATION

    cited = {type(s).__name__ for s in prob.model.system_iter(recurse=True) if getattr(s, "cite", "") == DISSERTATION}
    assert {"BoxSection", "BeamDynamics", "BeamInternalLoads", "BoxStress", "KSAggregate", "StructuralMass"} <= cited


def test_project_names_no_file_outside_the_repository():
    root = Path(__file__).resolve().parents[1]
    offenders = []
    for path in [root / "README.md", *root.glob("docs/**/*.md"), *root.glob("wingmdao/**/*.py")]:
        text = path.read_text(encoding="utf-8")
        if "../shared" in text or "CONVENTIONS.md" in text or "dissertation.txt" in text:
            offenders.append(str(path.relative_to(root)))
    assert not offenders


def test_bad_design_inside_a_solve_is_an_analysis_error(prob):
    """A thickness outside its range met while computing: ValueError (clear message) and
    om.AnalysisError (a driver backs off)."""
    t = prob.get_val("t_upper_skin").copy()
    prob.set_val("t_upper_skin", -t)
    try:
        with pytest.raises(om.AnalysisError, match="t_upper_skin") as info:
            prob.run_model()
        assert isinstance(info.value, ValueError)
    finally:
        prob.set_val("t_upper_skin", t)
        prob.run_model()
