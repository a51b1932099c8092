"""The CRM with stiffened panels (`wingmdao size crm --panels stiffened`, docs/panels.md): the
analysis of the starting design, with the physics a stress engineer expects of a transport wing
at +2.5 g / -1 g. The full sizing (about 150 s of CPU) is the figure of docs/panels.md."""

import numpy as np
import pytest

from wingmdao.cases import crm
from wingmdao.sizing import size_case, span_coordinate


@pytest.fixture(scope="module")
def analysis():
    setup = crm.build(panels="stiffened")
    setup.options.disp = False
    _, res = size_case(setup, optimize=False, comm=False)
    return setup, res


def test_crm_stiffened_upper_skin_more_critical_inboard(analysis):
    """Same skins top and bottom: at +2.5 g the upper skin is compressed, the lower one only at
    -1 g (0.4 of the load), so every compression mode of the upper skin is more critical than the
    lower skin's over the inboard half span; the centre box's panels are one of its four 0.74 m
    bays long, not the 2.95 m from the centreline to the root rib."""
    setup, res = analysis
    p = res["panels"]
    inboard = slice(1, setup.geometry.num_nodes // 2)
    for mode in ("skin_buckling", "panel_buckling", "stiffener_column"):
        up = np.asarray(p["upper_skin"]["factored_ratio"][mode])[inboard]
        lo = np.asarray(p["lower_skin"]["factored_ratio"][mode])[inboard]
        assert np.all(up > 1.5 * lo), mode
    lengths = setup.panels.panel_lengths(span_coordinate(setup.geometry))
    assert lengths[0] == pytest.approx(crm.PLANFORM.station_y()[1] / 4, rel=1e-12)
    assert sum(res["mass_breakdown_kg"].values()) == pytest.approx(res["mass_kg"], rel=1e-12)
    assert len(res["ribs"]["positions_m"]) == 37
