"""Load-case validation (clear errors before any solve) and the station map's partials."""

import numpy as np
import openmdao.api as om
import pytest
from openmdao.utils.assert_utils import assert_check_partials

from wingmdao.components.station_map import StationMap
from wingmdao.groups.load_case import LoadCase


def test_load_case_rejects_bad_input():
    with pytest.raises(ValueError, match="unknown stress families"):
        LoadCase("gust", families=("vm", "buckling"))
    with pytest.raises(ValueError, match="start at 0"):
        LoadCase("gust", time=[0.1, 0.2])
    with pytest.raises(ValueError, match="strictly increasing"):
        LoadCase("gust", time=[0.0, 0.2, 0.1])
    with pytest.raises(ValueError, match="unknown forcing"):
        LoadCase("gust", forcing={"lift": np.zeros(3)})
    case = LoadCase("m", forcing={"point_force": np.zeros((4, 3))})
    with pytest.raises(ValueError, match="expected"):
        case.forcing_array("point_force", 5)


def test_load_case_broadcasts_constant_forcing():
    case = LoadCase("step", time=[0.0, 0.1, 0.2], forcing={"gravity": np.array([0, 0, -9.81])})
    g = case.forcing_array("gravity", 4)
    assert g.shape == (3, 3) and np.all(g[:, 2] == -9.81)
    assert case.forcing_array("point_force", 4).shape == (3, 4, 3)


def test_station_map_values_and_partials():
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("m", StationMap(station_map=[0, 0, 1, 2], names=("t_upper_skin",)),
                             promotes=["*"])
    prob.setup()
    prob["t_upper_skin"] = [1.0, 2.0, 3.0]
    prob.run_model()
    np.testing.assert_array_equal(prob["t_upper_skin_station"], [1.0, 1.0, 2.0, 3.0])
    assert_check_partials(prob.check_partials(method="fd", out_stream=None), atol=1e-8, rtol=1e-8)


def test_station_map_must_cover_every_design_index():
    prob = om.Problem(reports=False)
    prob.model.add_subsystem("m", StationMap(station_map=[0, 2], names=("t",)))
    with pytest.raises(ValueError, match="every design index"):
        prob.setup()
