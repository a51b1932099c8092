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
    for _key, d in data.items():
        ref = np.abs(d["J_fd"]).max()
        err = np.abs(d["J_fwd"] - d["J_fd"]).max() / max(ref, 1e-12) if "J_fwd" in d else \
            np.abs(d["J_rev"] - d["J_fd"]).max() / max(ref, 1e-12)
        worst = max(worst, err)
    assert worst < 2e-5, worst


def test_serial_sizing_problem_does_not_import_mpi4py():
    """Outside mpirun the sizing problem gets OpenMDAO's serial communicator: om.Problem() would
    otherwise import mpi4py (~1 s) although it runs serially. Checked in a fresh interpreter."""
    import subprocess
    import sys

    code = ("import sys\n"
            "from wingmdao.cases import pegasus\n"
            "from wingmdao.sizing import build_problem\n"
            "s = pegasus.build(loads='maneuver')\n"
            "prob, _ = build_problem(s.geometry, s.load_cases, s.material, s.options)\n"
            "assert prob.comm.size == 1\n"
            "print('mpi4py.MPI' in sys.modules)\n")
    env = {k: v for k, v in __import__("os").environ.items() if not k.startswith(("OMPI_", "PMI_", "PMIX_"))}
    env.pop("OPENMDAO_USE_MPI", None)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=600)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == "False"


def test_set_case_loads_follows_where_the_beam_forcing_lives(problem):
    """build_problem makes the beam forcing data of the beams (forcing_as_data): set_case_loads
    then sets no beam forcing by default and refuses to on request; a model that promotes the
    forcing as inputs gets it set from the case's arrays."""
    from wingmdao.cases import wing_box
    from wingmdao.cases.wing_box.problem import analysis_problem
    from wingmdao.groups.wing import set_case_loads

    args = pegasus.PegasusOptions(loads="all", t_final=0.4, dt=0.04, gust_start=0.0)
    setup = pegasus.build(args)
    case = setup.load_cases[0]
    set_case_loads(problem, case, 19, f"cases.{case.name}")          # data: nothing to set, no error
    with pytest.raises(ValueError, match="forcing_as_data"):
        set_case_loads(problem, case, 19, f"cases.{case.name}", forcing=True)

    geometry, _, _, _ = wing_box.wing_geometry("combined", (1, 1, 1))      # forcing promoted as inputs
    n = geometry.num_nodes
    box_case = wing_box.tip_load_case("tip", n, (2e4, 0.0, 3e5), (0.0, 1e5, 0.0), ("vm",),
                                      time=np.linspace(0.0, 0.1, 5), ramp_time=0.05)
    walls = {w: np.full(n, 0.1) for w in WALL_VARS}
    box = analysis_problem(geometry, box_case, walls)              # calls set_case_loads
    np.testing.assert_array_equal(box.get_val("cases.tip.point_force", units="N"),
                                  box_case.forcing_array("point_force", n))
    assert np.abs(box.get_val("cases.tip.point_force")).max() > 1e4
