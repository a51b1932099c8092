"""FlutterDamping check_partials on a coupled Goland section (every stiffness / inertia entry
non-zero) against central differences; a module of its own so pytest-xdist --dist loadscope can
run it beside tests/test_flutter_sensitivity.py."""

import numpy as np
import openmdao.api as om
import pytest

from wingmdao.components.flutter import FlutterDamping
from wingmdao.stability.cases import flutter_problem

#: the 24 smallest |lambda| of the dense solve: lag roots and the lowest bending / torsion modes
DENSE_FEW = {"method": "dense", "count": 24}


def _flutter_comp_problem(n=4):
    """Goland wing with every stiffness / inertia entry non-zero (a coupled, non-trivial section)."""
    prob0 = flutter_problem("goland", n)
    rng = np.random.default_rng(7)
    beam = {k: np.array(v, dtype=float) for k, v in prob0.beam.items()}
    for key in ("stiffness_csn", "inertia_per_length"):
        scale = np.abs(beam[key]).max(axis=(1, 2), keepdims=True)
        c = 0.01 * scale * rng.random(beam[key].shape)
        beam[key] += 0.5 * (c + np.swapaxes(c, 1, 2))
    beam["tension_axis"] += 0.02 * rng.random(beam["tension_axis"].shape)
    beam["shear_center"] += 0.02 * rng.random(beam["shear_center"].shape)
    p = om.Problem(reports=False)
    p.model.add_subsystem("f", FlutterDamping(num_nodes=n, aero=prob0.aero, speeds=[100.0, 130.0],
                                              rho_ks=20.0, eig_options=DENSE_FEW), promotes=["*"])
    p.setup()
    for k, v in beam.items():
        p.set_val(k, v)
    return p


@pytest.mark.slow
def test_flutter_damping_check_partials():
    p = _flutter_comp_problem(3)
    p.run_model()
    comp = p.model.f
    # dense-QZ eigenvalues carry ~1e-10 |lambda| round-off: steps large enough to see the derivative;
    # relative steps on the (all non-zero) section data, absolute ones on positions, angles, offsets
    comp.set_check_partial_options(wrt=["stiffness_csn", "compliance_csn", "mass_per_length", "inertia_per_length"],
                                   method="fd", form="central", step=1e-3, step_calc="rel_element")
    comp.set_check_partial_options(wrt=["node_positions", "node_euler_angles", "tension_axis", "shear_center",
                                        "mass_center"], method="fd", form="central", step=1e-4, step_calc="abs")
    data = p.check_partials(compact_print=True, out_stream=None)
    for (_of, wrt), d in data["f"].items():
        J, fd = d["J_fwd"], d["J_fd"]
        scale = np.abs(fd).max()
        assert np.abs(J - fd).max() <= 2e-3 * scale + 1e-8, (wrt, np.abs(J - fd).max(), scale)
