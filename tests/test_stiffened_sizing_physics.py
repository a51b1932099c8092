"""The sized stiffened PEGASUS wing: compression sizes the upper skin, stiffened is heavier than
strength-only (two full maneuver sizings; a module of its own so pytest-xdist --dist loadscope can
run it beside tests/test_stiffened_sizing.py)."""

import numpy as np
import pytest

from wingmdao.cases import pegasus
from wingmdao.sizing import size_case


@pytest.mark.slow
def test_sized_stiffened_pegasus_physics():
    """Maneuver sizing: with buckling the upper (compression at 2.5 g) skin panels come out heavier
    than the lower ones inboard, the wing is heavier than the strength-only one, every constraint
    holds and the mass breakdown sums to the mass."""
    stiff = pegasus.build(loads="maneuver", panels="stiffened")
    stiff.options.disp = False
    _, res = size_case(stiff, comm=False)
    plain = pegasus.build(loads="maneuver")
    plain.options.disp = False
    _, ref = size_case(plain, comm=False)
    assert res["success"], res.get("message")
    assert res["max_ks"] <= 1e-3
    assert res["mass_kg"] > ref["mass_kg"]
    p = res["panels"]
    inboard = slice(1, 8)
    up = np.array(p["upper_skin"]["equivalent_thickness_m"])[inboard]
    lo = np.array(p["lower_skin"]["equivalent_thickness_m"])[inboard]
    assert np.all(up > lo)
    assert sum(res["mass_breakdown_kg"].values()) == pytest.approx(res["mass_kg"], rel=1e-9)
    for wall in ("upper_skin", "lower_skin", "front_spar", "rear_spar"):
        assert min(p[wall]["margin_of_safety"]) >= -0.01
