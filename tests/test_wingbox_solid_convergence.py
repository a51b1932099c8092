"""Mesh convergence of the 3-D solid wing-like box (wingmdao.verification.wingbox_solid) at CS2 and
CS3: a module of its own (ten solid solves, five on the default mesh) so pytest-xdist --dist
loadscope runs it beside tests/test_wingbox_solid.py instead of after it on the same worker."""

import pytest

from wingmdao.verification import wingbox_solid as wb


@pytest.mark.slow
@pytest.mark.parametrize("name", wb.geometry_names())
def test_solid_cs2_cs3_are_mesh_converged_well_below_one_percent(name):
    """The issue checks the box definition against the dissertation's 3-D FEM (Table E.3, withheld)
    with this solid model at the 1 % level, so the solid's own discretisation error at CS2 and CS3
    must be far below that. Coarse (0.25 m) against default (0.15 m) cross-section mesh, force and
    torque together (the torque large enough that twist, not the bending-induced streamwise
    rotation of the swept boxes, dominates theta_y): < 0.5 %; the default is within 0.06 % (force)
    and 0.21 % (torque) of a 0.08 m mesh (docs/verification-solid3d.md, section 4)."""
    load = dict(tip_force=(0.0, 0.0, 1e5), tip_moment=(0.0, 1e6, 0.0))
    coarse, default = (wb.solve_wingbox(name, mesh_size=h, **load) for h in (0.25, 0.15))
    for k in (0, 1):     # CS2, CS3
        assert coarse["displacement"][k, 2] == pytest.approx(default["displacement"][k, 2], rel=5e-3)
        assert coarse["rotation"][k, 1] == pytest.approx(default["rotation"][k, 1], rel=5e-3)
