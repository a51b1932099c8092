"""The Goland wing: a uniform cantilever flutter benchmark (beam data only; no sizing).

Data: M. Goland, "The flutter of a uniform cantilever wing", J. Applied Mechanics 12(4), 1945,
as tabulated by M. J. Patil, D. H. Hodges, C. E. S. Cesnik, "Nonlinear aeroelastic analysis of
complete aircraft in subsonic flow", J. Aircraft 37(5), 2000, and by R. Palacios, B. Epureanu,
"An intrinsic description of the nonlinear aeroelasticity of very flexible wings", AIAA 2011-1917:
semi-span 20 ft (6.096 m), chord 6 ft (1.8288 m), elastic axis at 33 % chord, centre of gravity at
43 % chord, EI = 23.65e6 lb ft^2 (9.77e6 N m^2), GJ = 2.39e6 lb ft^2 (0.988e6 N m^2),
m = 0.746 slug/ft (35.71 kg/m), I = 1.943 slug ft^2/ft (8.64 kg m). Goland gives I about the
elastic axis (``inertia_axis="ea"``, the default: radius of gyration 25 % chord about the centre
of gravity plus m d^2); some later tables label the same number "about the CG" (``"cg"``), which
lowers the torsion frequency by 7 %;
sea-level air density 1.225 kg/m^3 (strip-theory divergence at it, q_D = (pi/2)^2 GJ / (e c a L^2),
is 252.4 m/s, the published 252.8 m/s).
The in-plane (edgewise) stiffness and the extensional and shear stiffnesses are not part of the
benchmark; they are set high (``EDGE_FACTOR`` x EI, rigid in extension and shear) so those modes
stay out of the frequency range of interest.
"""

from __future__ import annotations

import numpy as np

from wingmdao.beam.static import beam_parameters, straight_beam
from wingmdao.units import FT, LBF, SLUG

SEMI_SPAN = 20.0 * FT
CHORD = 6.0 * FT
ELASTIC_AXIS = 0.33          # fraction of chord aft of the leading edge
MASS_CENTRE = 0.43
EI_FLAP = 23.65e6 * LBF * FT**2
GJ = 2.39e6 * LBF * FT**2
MASS = 0.746 * SLUG / FT
INERTIA = 1.943 * SLUG * FT  # slug ft^2 / ft -> kg m
DENSITY = 1.225
EDGE_FACTOR = 100.0

#: gravity of the deformed-state flutter study (the Goland benchmark has none), m/s^2
GRAVITY = 0.0
#: in vacuo 1st bending, 1st torsion, 2nd bending (rad/s) of the exact coupled bending-torsion
#: solution of these data (its transcendental frequency equation, solved in
#: tests/test_flutter_cases.py): 7.66 / 15.23 / 38.80 Hz
EXACT_FREQUENCIES_RAD_S = (48.16, 95.72, 243.77)

#: values quoted in the comparison docs (docs/flutter.md); not confirmed against the papers
#: themselves (not available here): see the table there
PUBLISHED = {
    "source": "Patil, Hodges & Cesnik, J. Aircraft 37(5), 2000; Palacios & Epureanu, AIAA 2011-1917 "
              "(as quoted); flutter point reproduced by an exact-Theodorsen Galerkin solution of the "
              "tabulated data (137.0 m/s, 70.03 rad/s), divergence by the closed form",
    "natural_frequencies_rad_s": [49.6, 97.0, 248.9],   # as quoted; the exact solution: EXACT_FREQUENCIES_RAD_S
    "flutter_speed_m_s": 137.2, "flutter_frequency_rad_s": 70.7,
    "divergence_speed_m_s": 252.8,
}

#: air density of the three-dimensional (lifting-surface) Goland flutter results in the literature,
#: kg/m^3: the same beam and planform data as above, flown at 1.02 kg/m^3, incompressible
DENSITY_3D = 1.02
#: published three-dimensional flutter points of the clean wing at DENSITY_3D (docs/aerodynamics-3d.md)
PUBLISHED_3D = {
    "density_kg_m3": DENSITY_3D,
    # SHARPy (linear UVLM, 16 chordwise x 32 spanwise panels, 4 modes; its Goland template has these
    # EI, GJ, m, I about the elastic axis and axes): tests/linear/goland_wing/test_goland_flutter.py
    # of github.com/ImperialCollegeLondon/sharpy asserts 166 m/s within 1 %
    "sharpy_uvlm_flutter_speed_m_s": 166.0,
    # Murua, Palacios & Graham, AIAA 2010-8226, Table 2, as quoted in github.com/JonasEiche/FlutterWing
    # docs/TUTORIAL.md (the paper itself not read here): UVLM 165 m/s; Wang, Chen, Liu, Mook & Patil,
    # AIAA 2006-1640: UVLM 163.8 m/s, ZAERO 174.3 m/s
    "murua_uvlm_flutter_speed_m_s": 165.0,
    "wang_uvlm_flutter_speed_m_s": 163.8,
    "wang_zaero_flutter_speed_m_s": 174.3,
    # FlutterWing (doublet lattice 5 x 10 panels, 10 beam elements, 5 modes, Mach 0, p-k), docs/TUTORIAL.md
    "flutterwing_dlm_flutter_speed_m_s": 164.5, "flutterwing_dlm_flutter_frequency_rad_s": 2 * np.pi * 11.34,
}


def beam_params(num_nodes: int = 21, *, inertia_axis: str = "ea") -> dict:
    """Beam parameter dict (``wingmdao.beam.residual.param_specs``) of the Goland wing, SI.

    Beam axis = elastic axis, along +y from the clamped root; mass centre 10 % chord aft of it.

    Parameters
    ----------
    num_nodes : int, optional
        Beam nodes, >= 3.
    inertia_axis : str, optional
        The axis Goland's I = 8.64 kg m is taken about: ``"ea"`` the elastic axis (Goland's
        reading), ``"cg"`` the centre of gravity (some later tables).

    Returns
    -------
    dict
        The beam parameters (SI: m, N, kg).
    """
    if inertia_axis not in ("cg", "ea"):
        raise ValueError(f'inertia_axis must be "cg" or "ea", got {inertia_axis!r}')
    if int(num_nodes) < 3:
        raise ValueError(f"num_nodes must be >= 3, got {num_nodes}")
    d = (MASS_CENTRE - ELASTIC_AXIS) * CHORD
    i_ss = INERTIA if inertia_axis == "cg" else INERTIA - MASS * d**2
    r0, th0 = straight_beam(int(num_nodes), SEMI_SPAN)
    small = 1e-6 * i_ss
    return beam_parameters(r0, th0, EI_cc=EI_FLAP, GJ=GJ, EI_nn=EDGE_FACTOR * EI_FLAP, EA=1e12,
                           mass_per_length=MASS, mass_center=(d, 0.0),
                           inertia_per_length=np.diag([small, i_ss, small]))


def aero_data() -> dict:
    """Aerodynamic data: chord (m), beam-axis position (fraction of chord), density (kg/m^3)."""
    return {"chord": CHORD, "ref_point": ELASTIC_AXIS, "lift_slope": 2 * np.pi, "density": DENSITY}
