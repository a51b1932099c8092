"""Total derivatives of the full sizing problem (2.5 g, -1.0 g maneuvers + gust time history)
against central finite differences at a non-trivial initial design: the adjoint over the whole
time history, through section, beam, internal loads, stress and KS."""

import numpy as np
import pytest

from wingmdao.cases import pegasus
from wingmdao.sizing import WALL_VARS, build_problem


@pytest.fixture(scope="module")
def problem():
    args = pegasus.PegasusOptions(loads="all", t_final=0.4, dt=0.04, gust_start=0.0,
                                  families="vm,ss_tension,cent_pos")
    setup = pegasus.build(args)
    rng = np.random.default_rng(7)
    setup.options.initial = {w: rng.uniform(0.004, 0.012, 19) for w in WALL_VARS}
    setup.options.disp = False
    prob, _ = build_problem(setup.geometry, setup.load_cases, setup.material, setup.options)
    prob.run_model()
    return prob


def test_adjoint_totals_match_central_differences(problem):
    data = problem.check_totals(method="fd", form="central", step=1e-7, step_calc="rel_avg",
                                out_stream=None, compact_print=True)
    worst = 0.0
    for key, d in data.items():
        ref = np.abs(d["J_fd"]).max()
        err = np.abs(d["J_fwd"] - d["J_fd"]).max() / max(ref, 1e-12) if "J_fwd" in d else \
            np.abs(d["J_rev"] - d["J_fd"]).max() / max(ref, 1e-12)
        worst = max(worst, err)
    assert worst < 2e-5, worst
