"""Every run-once group of the sizing models runs its subsystems after their sources: OpenMDAO's
``out_of_order`` configuration check finds nothing, and one analysis gives what a second gives.

A subsystem added before the component that feeds it gets, in a run-once group, the previous
evaluation's value (zero on the first), and the group's reverse sweep drops that path's
derivatives; the sizing then converges on lagged values and a single analysis of the result differs
from the sizing's own figures.
"""

import io
import logging

import numpy as np
import pytest

from wingmdao import sizing
from wingmdao.cases import pegasus, stw
from wingmdao.stability.cases import sizing_flutter_options

BUILDS = {
    "pegasus stiffened maneuvers": lambda: pegasus.build(loads="maneuver", panels="stiffened"),
    "pegasus box, maneuvers and gust": lambda: pegasus.build(loads="all", t_final=0.5, dt=0.05),
    "pegasus coupled gust, free plunge": lambda: pegasus.build(loads="gust", aero="coupled", plunge="free",
                                                               t_final=0.5, dt=0.05, gust_start=0.1),
    "stw laminate panels": lambda: stw.build(),
}


def _problem(name, flutter=False):
    setup = BUILDS[name]()
    if flutter:
        setup.flutter = sizing_flutter_options("pegasus", setup.geometry.num_nodes, 1.15)
    prob, _ = sizing.build_problem(setup.geometry, setup.load_cases, setup.material, setup.options, driver=False,
                                   section=setup.section, panels=setup.panels, flutter=setup.flutter)
    return setup, prob


def _out_of_order(prob) -> str:
    prob.final_setup()
    stream = io.StringIO()
    logger = logging.getLogger("wingmdao.test_model_order")
    logger.handlers, logger.propagate = [logging.StreamHandler(stream)], False
    logger.setLevel(logging.DEBUG)
    prob.check_config(checks=["out_of_order"], logger=logger)
    return "\n".join(line for line in stream.getvalue().splitlines() if "out-of-order" in line)


@pytest.mark.parametrize("name", list(BUILDS))
def test_no_subsystem_runs_before_its_sources(name):
    _, prob = _problem(name, flutter=name.startswith("pegasus box"))
    assert _out_of_order(prob) == ""


def test_the_order_check_can_fail():
    import openmdao.api as om

    prob = om.Problem(reports=False)
    prob.model.add_subsystem("b", om.ExecComp("z = 2 * y"))
    prob.model.add_subsystem("a", om.ExecComp("y = 3 * x"))
    prob.model.connect("a.y", "b.y")
    prob.setup()
    assert "executes out-of-order" in _out_of_order(prob)


def test_one_stiffened_analysis_equals_a_second():
    """The panels' chordwise running load (from dF/ds) is the current design's on the first run."""
    setup, prob = _problem("pegasus stiffened maneuvers")
    prob.run_model()
    first = {c.name: np.array(prob.get_val(f"cases.{c.name}.panels.g_panel_buckling")) for c in setup.load_cases}
    grad = np.array(prob.get_val("cases.maneuver_pos.panels.dF_csn_ds"))
    assert np.abs(grad).max() > 1e3  # N/m per m: the bending shear's spanwise change reached the panels
    prob.run_model()
    for name, g in first.items():
        # the second run's Newton solve starts from the first's state: equal to round-off
        assert np.allclose(g, prob.get_val(f"cases.{name}.panels.g_panel_buckling"), rtol=1e-9, atol=1e-12), name
