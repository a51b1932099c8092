"""The BDF step's round-off floor (wingmdao.timemarch.bdf.FLOOR_RATIO): a stiff, mixed-unit system
whose Newton iteration stalls at a residual of ~5e-13 is accepted, not reported as diverged."""

import re
from pathlib import Path

import numpy as np
import openmdao.api as om
import pytest

from wingmdao.aero import aero_parameters
from wingmdao.beam.static import beam_parameters, straight_beam
from wingmdao.timemarch import bdf


def _gust_problem(n=10, n_time=50, dt=0.002):
    """The coupled clamped model of benchmarks/bench_aero.py (``AeroelasticBeamDynamics``,
    static start), 10 nodes."""
    from wingmdao.components.aeroelastic import AeroelasticBeamDynamics

    r0, th0 = straight_beam(n, 10.0)
    vals = beam_parameters(r0, th0, EI_cc=2e6, GJ=1.6e6, EI_nn=1e7, EA=1e9, mass_per_length=20.0,
                           inertia_per_length=np.diag([0.1, 0.2, 0.1]))
    vals.update(aero_parameters(n, chord=1.0, ref_point=0.4, airspeed=60.0, density=1.2))
    t = np.arange(n_time) * dt
    gust = 5.0 * np.sin(np.pi * np.clip(t / 0.2, 0.0, 1.0)) ** 2
    vals["gust_velocity"] = np.repeat(gust[:, None], n, axis=1)
    prob = om.Problem(reports=False)
    comp = prob.model.add_subsystem("beam", AeroelasticBeamDynamics(num_nodes=n, time=t), promotes=["*"])
    prob.setup()
    for k, v in vals.items():
        prob.set_val(k, v)
    return prob, comp


@pytest.mark.slow
def test_stalled_residual_far_below_the_predictor_residual_is_accepted(monkeypatch):
    """Compiled functions (the stall is a round-off accident of the compiled code; interpreted,
    the same steps converge). Without the ratio test step 4 stalls ('no convergence in 25
    iterations' at a residual of 5.4e-13 with this machine's gcc); with it, the Python and the
    compiled steps march and agree to round-off."""
    monkeypatch.setenv("WINGMDAO_JIT", "1")
    prob, comp = _gust_problem()
    if set(comp.build_system().compile(wait=True).values()) != {"compiled"}:
        pytest.skip("needs gcc")
    monkeypatch.setenv("WINGMDAO_COMPILED_STEPS", "0")
    monkeypatch.setattr(bdf, "FLOOR_RATIO", 0.0)
    try:
        prob.run_model()
    except om.AnalysisError as exc:
        assert "no convergence in 25 iterations" in str(exc)
    else:
        pytest.skip("this compiler's round-off does not stall the step: nothing to show")
    monkeypatch.setattr(bdf, "FLOOR_RATIO", 1e-10)
    states = {}
    for compiled_steps in ("0", "1"):
        monkeypatch.setenv("WINGMDAO_COMPILED_STEPS", compiled_steps)
        prob.run_model()
        h = comp.last_history
        assert h.info.get("compiled_steps", False) == (compiled_steps == "1")
        x = np.array(prob.get_val("states"))
        assert np.all(np.isfinite(x)) and h.iterations.max() < 25
        states[compiled_steps] = x
    scale = np.abs(states["0"]).max()
    np.testing.assert_allclose(states["1"], states["0"], rtol=0, atol=1e-10 * scale)


def test_the_compiled_step_uses_the_same_ratio():
    src = (Path(bdf.__file__).with_name("bdf_step.c")).read_text()
    found = re.findall(r"norm <= ([0-9.eE+-]+) \* first_norm", src)
    assert found and all(float(v) == bdf.FLOOR_RATIO for v in found)
