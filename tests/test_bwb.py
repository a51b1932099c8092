"""Su's blended-wing-body flying wing as a free half stick model (wingmdao.cases.bwb) against the
UM/NAST results for the same aircraft (trim, modes and body-freedom flutter at sea level),
tabulated in AeroBeams.jl test/referenceData/BWB (docs/stick-model.md, "Blended-wing-body
aircraft of Su")."""

import numpy as np
import pytest

from wingmdao.aero.joined import build_joined_aeroelastic_system, lift_total, pack_aero_forcing
from wingmdao.beam.joints import Beam, Joint
from wingmdao.cases import bwb

REF = bwb.REFERENCE


@pytest.fixture(scope="module")
def aircraft():
    return bwb.build()


def _ref(key, speed):
    return REF[key][REF["airspeed_m_s"].index(float(speed))]


@pytest.mark.slow
def test_flutter_speed_and_frequency_within_5_percent_of_um_nast(aircraft):
    """The issue's bar: the body-freedom flutter of the free aircraft (trimmed at each speed,
    linearised with the trim held) within 5 % of UM/NAST's 137.7 m/s and 47.5 rad/s."""
    f = bwb.flutter(aircraft, [120.0, 130.0, 140.0])
    assert f["speed"] == pytest.approx(REF["flutter_speed_m_s"], rel=0.05)
    assert f["frequency"] == pytest.approx(REF["flutter_frequency_rad_s"], rel=0.05)
    # stable below: the bisection found the first crossing above 130 m/s
    assert f["real"][0] < 0.0 and 130.0 < f["speed"] < 140.0


@pytest.mark.slow
def test_streamwise_strips_flutter_too_early():
    """Strips on the full airspeed (lift per beam length q c_n 2 pi alpha, no sweep theory)
    stiffen the coalescing mode faster: flutter more than 10 % below the reference (docs: 116.0 m/s)."""
    f = bwb.flutter(bwb.build(num_body_nodes=4, num_wing_nodes=9, sweep="streamwise"), [100.0, 110.0, 120.0])
    assert f["speed"] < 0.9 * REF["flutter_speed_m_s"]


def test_trim_and_low_speed_modes_against_um_nast(aircraft):
    """Trim (centreline angle of attack, elevon) at 40, 90, 140 m/s (at 40 m/s the elevon is
    deflected 8.5 deg by UM/NAST and 13.7 deg here: the swept wing's lift per angle of attack,
    a cos(sweep), carries more of the lift aft of the body's, and the thin-airfoil flap against
    UM/NAST's tabulated one; docs/stick-model.md), and at 30 m/s the two symmetric modes that
    later coalesce (3.26 and 7.89 Hz) with the damping of the second."""
    x = None
    for V, tol_aoa, tol_elevon in ((40.0, 1.0, 5.5), (90.0, 0.4, 0.7), (140.0, 0.3, 0.4)):
        t = bwb.trim(aircraft, V, x0=x)
        x = t["x"]
        assert t["root_aoa_deg"] == pytest.approx(_ref("trim_root_aoa_deg", V), abs=tol_aoa)
        assert t["elevon_deg"] == pytest.approx(_ref("trim_elevon_deg", V), abs=tol_elevon)
        s = aircraft.system
        p = bwb.parameters(aircraft, V)
        q = pack_aero_forcing(s, trim_active=1.0, gravity=[0.0, 0.0, -bwb.GRAVITY])
        # trimmed: the strips' vertical force is the weight of the masses (independent sum)
        assert lift_total(s, x, 0 * x, p, q, vertical=True) == pytest.approx(aircraft.mass * bwb.GRAVITY, rel=1e-6)
    t = bwb.trim(aircraft, 30.0)
    lam = bwb.modes(aircraft, 30.0, t["x"]).eigenvalues
    hz = np.abs(lam.imag) / (2 * np.pi)
    for ref_hz, tol in ((_ref("coalescing_mode_hz", 30.0), 0.02), (_ref("flutter_mode_hz", 30.0), 0.01)):
        k = int(np.argmin(np.abs(hz - ref_hz)))
        assert hz[k] == pytest.approx(ref_hz, rel=tol)
    k = int(np.argmin(np.abs(hz - _ref("flutter_mode_hz", 30.0))))
    assert lam[k].real == pytest.approx(_ref("flutter_mode_real", 30.0), rel=0.05)


def test_bad_input_is_refused_before_any_build():
    with pytest.raises(ValueError, match="num_wing_nodes = 10"):
        bwb.build(num_wing_nodes=10)
    with pytest.raises(ValueError, match="sweep = 'oblique'"):
        bwb.build(sweep="oblique")
    with pytest.raises(ValueError, match="damping_time = -1"):
        bwb.build(damping_time=-1.0)
    beams = [Beam("wing", 3, root="free"), Beam("tail", 3, root="free")]
    joints = [Joint("wing", 0, "tail", 0)]
    sup = (("wing", 0, "x"), ("wing", 0, "z"), ("wing", -1, "z"))
    with pytest.raises(ValueError, match="an elevon needs tail=None"):
        build_joined_aeroelastic_system(beams, joints, supports=sup, elevon={"wing": [1]})
    with pytest.raises(ValueError, match="elevon node 3 of beam 'wing' does not exist"):
        build_joined_aeroelastic_system(beams, joints, tail=None, supports=sup, elevon={"wing": [3]})
    with pytest.raises(ValueError, match="elevon_hinge = 1.2"):
        build_joined_aeroelastic_system(beams, joints, tail=None, supports=sup, elevon={"wing": [1]},
                                        elevon_hinge=1.2)
