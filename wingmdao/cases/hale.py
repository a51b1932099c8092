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

SEMI_SPAN = 16.0
CHORD = 1.0
ELASTIC_AXIS = 0.5
EI_FLAP = 2.0e4
EI_LAG = 4.0e6
GJ = 1.0e4
MASS = 0.75
INERTIA = 0.1
DENSITY = 0.0889

#: published values (Patil, Hodges & Cesnik 2001, Tables 2-3), quoted in docs/flutter.md
PUBLISHED = {
    "source": "Patil, Hodges & Cesnik, J. Aircraft 38(1), 2001",
    "natural_frequencies_rad_s": [2.243, 14.056, 31.046, 31.718],  # flap 1, flap 2, torsion 1, lag 1 (exact)
    "flutter_speed_m_s": 32.21, "flutter_frequency_rad_s": 22.61,
    "divergence_speed_m_s": 37.29,
}


def beam_params(num_nodes: int = 21) -> dict:
    """Beam parameter dict (``wingmdao.beam.residual.param_specs``) of the HALE wing, SI."""
    from wingmdao.beam.static import beam_parameters, straight_beam

    if int(num_nodes) < 3:
        raise ValueError(f"num_nodes must be >= 3, got {num_nodes}")
    r0, th0 = straight_beam(int(num_nodes), SEMI_SPAN)
    i_flap = INERTIA * EI_FLAP / EI_LAG
    return beam_parameters(r0, th0, EI_cc=EI_FLAP, GJ=GJ, EI_nn=EI_LAG, EA=1e12, mass_per_length=MASS,
                           inertia_per_length=np.diag([i_flap, INERTIA, INERTIA - i_flap]))


def aero_data() -> dict:
    """Aerodynamic data: chord (m), beam-axis position (fraction of chord), density (kg/m^3)."""
    return {"chord": CHORD, "ref_point": ELASTIC_AXIS, "lift_slope": 2 * np.pi, "density": DENSITY}
