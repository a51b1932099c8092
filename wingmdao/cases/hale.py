"""The Patil-Hodges-Cesnik HALE wing (beam data only; no sizing).

Data: M. J. Patil, D. H. Hodges, C. E. S. Cesnik, "Nonlinear aeroelasticity and flight dynamics of
high-altitude long-endurance aircraft", J. Aircraft 38(1), 2001, Table 1: half span 16 m, chord
1 m, elastic axis and centre of gravity at 50 % chord, EI_flap 2e4 N m^2, EI_lag (edgewise)
4e6 N m^2, GJ 1e4 N m^2, mass 0.75 kg/m, rotary inertia 0.1 kg m (torsion), air density
0.0889 kg/m^3 (20 km). The split of the section inertia into flap and lag rotary inertia follows
the ratio of the bending stiffnesses (as in the AeroBeams.jl model of this wing): I_flap = 0.1 x
EI_flap / EI_lag, I_lag = 0.1 - I_flap.
"""

from __future__ import annotations

import numpy as np

from wingmdao.beam.static import beam_parameters, straight_beam

SEMI_SPAN = 16.0
CHORD = 1.0
ELASTIC_AXIS = 0.5
EI_FLAP = 2.0e4
EI_LAG = 4.0e6
GJ = 1.0e4
MASS = 0.75
INERTIA = 0.1
DENSITY = 0.0889
#: gravity of the deformed-state (nonlinear) flutter study, m/s^2 (the undeformed benchmark has none)
GRAVITY = 9.807

#: published values (Patil, Hodges & Cesnik 2001, Tables 2-3), quoted in docs/flutter.md
PUBLISHED = {
    "source": "Patil, Hodges & Cesnik, J. Aircraft 38(1), 2001",
    "natural_frequencies_rad_s": [2.243, 14.056, 31.046, 31.718],  # flap 1, flap 2, torsion 1, lag 1 (exact)
    "flutter_speed_m_s": 32.21, "flutter_frequency_rad_s": 22.61,
    "divergence_speed_m_s": 37.29,
}


def beam_params(num_nodes: int = 21, stiffness_factor: float = 1.0) -> dict:
    """Beam parameter dict (``wingmdao.beam.residual.param_specs``) of the HALE wing.

    Parameters
    ----------
    num_nodes : int, optional
        Beam nodes, >= 3.
    stiffness_factor : float, optional
        Multiplies the bending and torsion stiffness (> 0).

    Returns
    -------
    dict
        The beam parameters (SI: m, N, kg).
    """
    if int(num_nodes) < 3:
        raise ValueError(f"num_nodes must be >= 3, got {num_nodes}")
    if not (np.isfinite(stiffness_factor) and stiffness_factor > 0.0):
        raise ValueError(f"stiffness_factor must be a finite number > 0, got {stiffness_factor}")
    r0, th0 = straight_beam(int(num_nodes), SEMI_SPAN)
    i_flap = INERTIA * EI_FLAP / EI_LAG
    f = float(stiffness_factor)
    return beam_parameters(r0, th0, EI_cc=f * EI_FLAP, GJ=f * GJ, EI_nn=f * EI_LAG, EA=1e12, mass_per_length=MASS,
                           inertia_per_length=np.diag([i_flap, INERTIA, INERTIA - i_flap]))


def aero_data() -> dict:
    """Aerodynamic data: chord (m), beam-axis position (fraction of chord), density (kg/m^3)."""
    return {"chord": CHORD, "ref_point": ELASTIC_AXIS, "lift_slope": 2 * np.pi, "density": DENSITY}


#: Published nonlinear-flutter curves of this wing (Patil, Hodges & Cesnik 2001: flutter about the
#: static state at a root angle of attack, with gravity; and flutter speed vs static tip
#: displacement set by a tip load), as digitised from the paper's figures in AeroBeams.jl
#: (github.com/luizpancini/AeroBeams.jl, test/referenceData/SMW/flutterSpeedVsRootAoA.txt,
#: flutterFreqVsRootAoA.txt, flutterTipDispVsRootAoA.txt, flutterSpeedVsTipDisp.txt). Root angles
#: from 0.63 deg up (below it the drooping wing flutters on another branch at ~23 m/s); digitising
#: error ~1 %.
PUBLISHED_DEFORMED = {
    "source": "Patil, Hodges & Cesnik, J. Aircraft 38(1), 2001 (figures; digitised in AeroBeams.jl "
              "test/referenceData/SMW)",
    "speed_vs_root_aoa": {  # root angle of attack (deg) -> flutter speed (m/s)
        "root_aoa_deg": [0.629, 0.806, 1.002, 1.248, 1.542, 1.876, 2.200, 2.564, 2.908, 3.261, 3.625,
                         3.949, 4.204, 4.479],
        "flutter_speed_m_s": [30.32, 29.36, 28.40, 27.23, 26.06, 25.03, 24.07, 23.24, 22.49, 21.80,
                              21.18, 20.70, 20.35, 19.94]},
    "frequency_vs_root_aoa": {  # root angle of attack (deg) -> flutter frequency (rad/s)
        "root_aoa_deg": [0.629, 0.884, 1.110, 1.474, 1.837, 2.269, 2.721, 3.212, 3.674, 4.067, 4.479],
        "flutter_frequency_rad_s": [21.52, 20.84, 20.15, 19.32, 18.70, 18.22, 17.67, 17.26, 16.78,
                                    16.64, 16.30]},
    "tip_vs_root_aoa": {  # root angle of attack (deg) -> static tip displacement at flutter (m)
        "root_aoa_deg": [0.648, 0.827, 1.124, 1.541, 1.868, 2.344, 2.869, 3.365, 3.801, 4.138, 4.484],
        "tip_deflection_m": [0.535, 0.704, 0.892, 1.101, 1.219, 1.368, 1.506, 1.595, 1.694, 1.733,
                             1.762]},
    "speed_vs_tip_load_deflection": {  # static tip displacement (m, by a tip load) -> flutter speed
        "tip_deflection_m": [0.005, 0.149, 0.298, 0.471, 0.633, 0.800, 0.955, 1.134, 1.307, 1.456,
                             1.600, 1.731],
        "flutter_speed_m_s": [32.15, 31.94, 31.67, 30.70, 29.52, 28.41, 27.16, 25.77, 24.38, 23.41,
                              22.51, 22.31]},
}
