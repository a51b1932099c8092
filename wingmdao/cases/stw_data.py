"""Data of the Simple Transonic Wing (STW) of the MDO Aeroelastic Benchmark, as typed constants.

Source: the GitHub repository ``MDOBenchmarks/MDOAeroelasticBenchmark`` (commit
``9cee993e10ef0cf5f931eadd5ad4be0ebcea208d``), cited below as "the benchmark". Every value
names the file it comes from; values *derived* here from the benchmark's data (not stated in
it) say so. SI units (m, kg, s, N, Pa); angles in degrees where the name says ``_DEG``.

Files cited:

* ``docs/source/model.rst``: geometry description, wingbox layout, ply properties, layups,
  loads ("no non-structural masses"), safety factor.
* ``docs/source/opt_problem.rst``: aircraft specifications, flight conditions, objectives,
  structural parameterisation, sizing rules and constraints.
* ``docs/source/required_results.rst``: baseline panel sizing and the results to report.
* ``STW-Files/geometry/wingGeometry.py``: planform and wingbox definition ("single source of
  truth" of the geometry).
* ``STW-Files/geometry/rae2822.dat``: the airfoil coordinates.
* ``STW-Files/AircraftSpecs/STWFlightPoints.py``, ``STW-Files/AircraftSpecs/STWSpecs.py``:
  flight points and aircraft/mission specifications as code.
* ``STW-Files/struct/wingbox-L4-Order2.bdf``: the coarsest shell mesh (rib positions and spar
  corner coordinates used as a check).

Not in the benchmark (hence not here): ply thickness, allowable strains, knock-down factors,
engine or fuel masses on the wing (the benchmark leaves all non-structural masses out), and a
file layout for submitted results.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

REPOSITORY = "MDOBenchmarks/MDOAeroelasticBenchmark"
COMMIT = "9cee993e10ef0cf5f931eadd5ad4be0ebcea208d"

# ==============================================================================================
# Planform (STW-Files/geometry/wingGeometry.py, "OML Definition"; docs/source/opt_problem.rst,
# table "Aircraft and mission specifications")
# ==============================================================================================
#: Nominal semi-span, m (wingGeometry.py ``semiSpan``; opt_problem.rst: b = 14 m).
SEMI_SPAN = 14.0
#: Root chord at the symmetry plane, m (wingGeometry.py ``sectionChord[0]``; opt_problem.rst 5 m).
ROOT_CHORD = 5.0
#: Tip chord at the nominal semi-span, m (wingGeometry.py ``sectionChord[1]``; opt_problem.rst 1.5 m).
TIP_CHORD = 1.5
#: Chordwise (x) offset of the tip leading edge from the root leading edge, m
#: (wingGeometry.py ``sectionChordwiseOffset``).
TIP_LE_OFFSET = 7.5
#: Vertical offsets of the root and tip sections, m: zero, i.e. **no dihedral**
#: (wingGeometry.py ``sectionVerticalOffset``).
DIHEDRAL_DEG = 0.0
#: Section twist at the root and the tip, deg: zero, **untwisted** (wingGeometry.py
#: ``sectionTwist``; model.rst: "a constant, untwisted RAE2822 cross-section").
TWIST_DEG = (0.0, 0.0)
#: Spanwise positions (eta = y / SEMI_SPAN) of the two defining sections (wingGeometry.py ``sectionEta``).
SECTION_ETA = (0.0, 1.0)
#: Leading-edge sweep, deg, **derived**: atan(TIP_LE_OFFSET / SEMI_SPAN) = 28.18 deg. The
#: benchmark states the offset, not the angle.
LE_SWEEP_DEG = math.degrees(math.atan(TIP_LE_OFFSET / SEMI_SPAN))
#: Trailing-edge thickness (blunt trailing edge, 1/4 inch), m (wingGeometry.py ``teHeight``).
TE_HEIGHT = 0.25 * 0.0254
#: Rounded tip cap beyond the nominal semi-span, m (model.rst: "a further 42.5 mm"); not part of
#: the planform area or of the wingbox.
TIP_CAP_LENGTH = 0.0425
#: Stated planform area of one wing, m^2 (opt_problem.rst: 45.5 m^2; wingGeometry.py computes
#: semiSpan (c_root + c_tip) / 2).
PLANFORM_AREA = 45.5
#: Stated mean aerodynamic chord, m (opt_problem.rst: 3.56 m; wingGeometry.py computes
#: 2/3 (c_r + c_t - c_r c_t / (c_r + c_t)) = 3.5641 m, also ``refChord`` in STWSpecs.py).
MAC = 3.56
#: Aspect ratio, **derived** as in wingGeometry.py: 2 b^2 / S (both wings) = 8.615.
ASPECT_RATIO = 2.0 * SEMI_SPAN**2 / (SEMI_SPAN * (ROOT_CHORD + TIP_CHORD) / 2.0)
#: Taper ratio c_tip / c_root = 0.3 (wingGeometry.py ``taperRatio``).
TAPER_RATIO = TIP_CHORD / ROOT_CHORD

# ==============================================================================================
# Airfoil (model.rst; STW-Files/geometry/rae2822.dat)
# ==============================================================================================
#: The one airfoil of the whole span: RAE 2822, untwisted, cut on planes normal to the global
#: y axis (streamwise sections), model.rst.
AIRFOIL = "RAE2822"
#: Maximum thickness-to-chord of the RAE 2822 coordinates, **derived** from rae2822.dat (the
#: difference of the linearly interpolated surfaces): 0.1211 at x/c = 0.379, the same at every
#: spanwise station (constant section).
THICKNESS_TO_CHORD = 0.1211
#: RAE 2822 coordinates (x/c, z/c), unit chord, from STW-Files/geometry/rae2822.dat: trailing
#: edge -> upper surface -> leading edge -> lower surface -> trailing edge.
RAE2822_COORDINATES = (
    (1, 0), (0.999398, 0.000128), (0.997592, 0.00051), (0.994588, 0.001137), (0.990393, 0.002001),
    (0.985016, 0.003092), (0.97847, 0.004401), (0.970772, 0.005915), (0.96194, 0.007622),
    (0.951995, 0.009508), (0.940961, 0.011562), (0.928864, 0.013769), (0.915735, 0.016113),
    (0.901604, 0.01858), (0.886505, 0.021153), (0.870476, 0.023817), (0.853553, 0.026554),
    (0.835779, 0.029347), (0.817197, 0.032176), (0.79785, 0.035017), (0.777785, 0.037847),
    (0.757051, 0.040641), (0.735698, 0.043377), (0.713778, 0.046029), (0.691342, 0.048575),
    (0.668445, 0.050993), (0.645142, 0.053258), (0.62149, 0.055344), (0.597545, 0.057218),
    (0.573365, 0.058845), (0.549009, 0.060194), (0.524534, 0.061254), (0.5, 0.062029),
    (0.475466, 0.06253), (0.450991, 0.062774), (0.426635, 0.062779), (0.402455, 0.062562),
    (0.37851, 0.062133), (0.354858, 0.061497), (0.331555, 0.06066), (0.308658, 0.059629),
    (0.286222, 0.058414), (0.264302, 0.057026), (0.242949, 0.05547), (0.222215, 0.053753),
    (0.20215, 0.051885), (0.182803, 0.049874), (0.164221, 0.047729), (0.146447, 0.045457),
    (0.129524, 0.043071), (0.113495, 0.040585), (0.098396, 0.038011), (0.084265, 0.03536),
    (0.071136, 0.032644), (0.059039, 0.029874), (0.048005, 0.027062), (0.03806, 0.024219),
    (0.029228, 0.021348), (0.02153, 0.018441), (0.014984, 0.015489), (0.009607, 0.01248),
    (0.005412, 0.009416), (0.002408, 0.006306), (0.000602, 0.003165), (0, 0), (0.000602, -0.00316),
    (0.002408, -0.006308), (0.005412, -0.009443), (0.009607, -0.012559), (0.014984, -0.015649),
    (0.02153, -0.018707), (0.029228, -0.021722), (0.03806, -0.024685), (0.048005, -0.027586),
    (0.059039, -0.030416), (0.071136, -0.03317), (0.084265, -0.035843), (0.098396, -0.038431),
    (0.113495, -0.040929), (0.129524, -0.043326), (0.146447, -0.04561), (0.164221, -0.047773),
    (0.182803, -0.049805), (0.20215, -0.051694), (0.222215, -0.053427), (0.242949, -0.054994),
    (0.264302, -0.056376), (0.286222, -0.057547), (0.308658, -0.058459), (0.331555, -0.059046),
    (0.354858, -0.059236), (0.37851, -0.058974), (0.402455, -0.058224), (0.426635, -0.056979),
    (0.450991, -0.055257), (0.475466, -0.053099), (0.5, -0.050563), (0.524534, -0.047719),
    (0.549009, -0.044642), (0.573365, -0.041397), (0.597545, -0.038043), (0.62149, -0.034631),
    (0.645142, -0.031207), (0.668445, -0.027814), (0.691342, -0.024495), (0.713778, -0.021289),
    (0.735698, -0.018232), (0.757051, -0.015357), (0.777785, -0.01269), (0.79785, -0.010244),
    (0.817197, -0.008027), (0.835779, -0.006048), (0.853553, -0.004314), (0.870476, -0.002829),
    (0.886505, -0.001592), (0.901604, -0.0006), (0.915735, 0.000157), (0.928864, 0.000694),
    (0.940961, 0.001033), (0.951995, 0.001197), (0.96194, 0.001212), (0.970772, 0.001112),
    (0.97847, 0.000935), (0.985016, 0.000719), (0.990393, 0.000497), (0.994588, 0.000296),
    (0.997592, 0.000137), (0.999398, 3.5e-05), (1, 0),
)

# ==============================================================================================
# Wingbox layout (STW-Files/geometry/wingGeometry.py, "Wingbox Definition"; model.rst)
# ==============================================================================================
#: Side-of-body (SOB) break, spanwise coordinate, m (wingGeometry.py ``SOB``; model.rst y = 1.5 m).
#: Inboard of it the wingbox is unswept (a centre box, model.rst).
SOB_Y = 1.5
#: Front (leading-edge) spar chord fraction outboard of the SOB (wingGeometry.py ``LESparFrac``;
#: model.rst "from 15 to 65% of the chord").
FRONT_SPAR_FRACTION = 0.15
#: Rear (trailing-edge) spar chord fraction outboard of the SOB (wingGeometry.py ``TESparFrac``).
REAR_SPAR_FRACTION = 0.65
#: Number of spars (front and rear only), wingGeometry.py ``numSpars``.
NUM_SPARS = 2
#: Ribs between the centreline and the SOB, both included (wingGeometry.py ``numRibsCentrebody``;
#: model.rst: "Four of the ribs are evenly spaced between the centerline and the SOB").
NUM_RIBS_CENTRE = 4
#: Ribs outboard of the SOB, evenly spaced, the last at the tip (wingGeometry.py ``numRibsOuter``).
NUM_RIBS_OUTER = 19
#: Total rib count (wingGeometry.py ``numRibs``; model.rst "23 ribs").
NUM_RIBS = NUM_RIBS_CENTRE + NUM_RIBS_OUTER
#: Offset of the wingbox root and tip from the OML root and tip in the benchmark's meshes, m
#: (wingGeometry.py: "shift the tip/root of the wingbox slightly ... so that pylayout's
#: projections work"). A meshing device: the beam model of wingmdao uses the nominal ends.
MESH_END_OFFSET = 1e-3
#: Rib planes (constant y, i.e. streamwise ribs), m, as in the shell mesh
#: STW-Files/struct/wingbox-L4-Order2.bdf (the ``$XSUPER`` corner records, families
#: ``RIBS/RIB.00`` .. ``RIB.22``): 4 from 0.001 to 1.5 and 19 from the SOB to 13.999, evenly spaced.
RIB_Y_MESH = tuple([0.001 + k * (SOB_Y - 0.001) / 3 for k in range(3)] + [SOB_Y]
                   + [SOB_Y + k * (13.999 - SOB_Y) / 19 for k in range(1, 20)])
#: Spar corner z coordinates of the root rib in the same mesh, m: (front upper, front lower,
#: rear upper, rear lower) at y = 0.001 and x = 1.497321 (front) / 3.809821 (rear). Used as a
#: check of the box height (the mesh's skins lie on the OML).
ROOT_SPAR_CORNERS_Z_MESH = (0.2957332151, -0.2905577682, 0.1999139465, -0.07368507329)
#: Boundary conditions of the benchmark's wingbox (model.rst): symmetry at the centreline, and
#: fixed in the chordwise and vertical directions at the SOB.
BOUNDARY_CONDITIONS = "symmetry at y = 0; x and z displacements fixed at the side of body (y = 1.5 m)"

# ==============================================================================================
# Material: composite ply properties (model.rst, table "Composite ply properties", from Brooks
# et al. 2020)
# ==============================================================================================


@dataclass(frozen=True)
class PlyProperties:
    """Orthotropic ply data, SI (Pa, kg/m^3).

    Parameters
    ----------
    E11, E22 : float
        Moduli along and across the fibres (Pa).
    G12, G13, G23 : float
        Shear moduli (Pa).
    nu12 : float
        Major Poisson's ratio (-).
    rho : float
        Density (kg/m^3).
    T1, C1 : float
        Fibre-direction tensile and compressive strengths (Pa).
    T2, C2 : float
        Transverse tensile and compressive strengths (Pa).
    S12 : float
        In-plane shear strength (Pa).
    """

    E11: float  # fibre-direction modulus
    E22: float  # transverse modulus
    G12: float  # in-plane shear modulus
    G13: float  # transverse shear modulus
    G23: float  # transverse shear modulus
    nu12: float  # major Poisson's ratio
    rho: float  # density
    T1: float  # fibre-direction tensile strength
    C1: float  # fibre-direction compressive strength
    T2: float  # transverse tensile strength
    C2: float  # transverse compressive strength
    S12: float  # in-plane shear strength


#: The one ply material of the whole wingbox (model.rst). Ply thickness and allowable strains
#: are not given by the benchmark.
PLY = PlyProperties(E11=117.7e9, E22=9.7e9, G12=4.8e9, G13=4.8e9, G23=4.8e9, nu12=0.35, rho=1550.0,
                    T1=1648e6, C1=1034e6, T2=64e6, C2=228e6, S12=71e6)
#: Ply angles of every laminate (shells and stiffeners), deg (model.rst).
PLY_ANGLES_DEG = (0.0, -45.0, 45.0, 90.0)
#: Ply fractions for PLY_ANGLES_DEG in the upper and lower skins and in all stiffeners: 0 deg
#: biased (model.rst, after Dillinger et al. 2014).
PLY_FRACTIONS_SKIN = (0.4441, 0.222, 0.222, 0.1119)
#: The same for all stiffeners (model.rst: "In the upper and lower skin shells and in all stiffeners").
PLY_FRACTIONS_STIFFENER = PLY_FRACTIONS_SKIN
#: Ply fractions in the spar and rib shells: near-isotropic (model.rst).
PLY_FRACTIONS_SPAR_RIB = (0.10, 0.35, 0.35, 0.20)
#: Ply orientation reference (model.rst): in the skins the stiffeners and 0 deg plies are
#: aligned with the trailing-edge (rear) spar; in the spars and ribs they are vertical.
PLY_REFERENCE = {"skin": "rear spar", "stiffener": "rear spar", "spar": "vertical", "rib": "vertical"}

# ==============================================================================================
# Stiffened panels and sizing rules (model.rst; opt_problem.rst "Structural Variables",
# "Structural Constraints"; required_results.rst "Panel variables")
# ==============================================================================================
#: Stiffener cross-section shape (model.rst: "T-shaped cross section").
STIFFENER_TYPE = "T"
#: Stiffener pitch on all panels, m (opt_problem.rst: 150 mm; required_results.rst 0.15 m).
STIFFENER_PITCH = 0.150
#: Recommended link between flange width and web height if the stiffener cross-section is
#: parameterised: w_stiff = h_stiff (opt_problem.rst, a recommendation, not a rule).
FLANGE_WIDTH_OVER_HEIGHT = 1.0
#: Panels with their own sizing variables (opt_problem.rst): each rib, and each skin and spar
#: segment between a pair of ribs: 23 ribs + 22 bays x (upper skin, lower skin, front spar,
#: rear spar) = 111 panels (the BDF's component families agree).
NUM_PANELS = NUM_RIBS + 4 * (NUM_RIBS - 1)
#: Safety factor on material failure and on buckling (model.rst; opt_problem.rst: strength
#: ratio SR <= 1 / 1.5 in both maneuvers).
SAFETY_FACTOR = 1.5


@dataclass(frozen=True)
class SizingRules:
    """The benchmark's panel sizing rules (opt_problem.rst, after Kassapoglou 2013), m.

    Parameters
    ----------
    min_skin_thickness, min_stiffener_thickness, min_stiffener_height, min_flange_width : float, optional
        Minimum gauges (m).
    min_web_aspect, max_web_aspect : float, optional
        Bounds of the stiffener web's height over thickness (-).
    max_stiffener_over_panel_thickness : float, optional
        Largest stiffener thickness over panel thickness (-).
    max_panel_thickness_step, max_stiffener_thickness_step, max_stiffener_height_step : float, optional
        Largest change between adjacent panels (m).
    """

    min_skin_thickness: float = 0.6e-3  # skin (panel) thickness >= 0.6 mm
    min_stiffener_thickness: float = 0.6e-3  # stiffener thickness >= 0.6 mm
    min_stiffener_height: float = 18e-3  # stiffener height >= 18 mm
    min_flange_width: float = 25.4e-3  # stiffener flange width >= 25.4 mm
    min_web_aspect: float = 5.0  # h_stiff / t_stiff >= 5
    max_web_aspect: float = 30.0  # h_stiff / t_stiff <= 30
    max_stiffener_over_panel_thickness: float = 15.0  # t_stiff <= 15 t_panel
    # flange width < stiffener pitch (no overlapping flanges): w_stiff <= p_stiff
    max_panel_thickness_step: float = 2.5e-3  # |t_panel,i - t_panel,j| between adjacent skin (or spar) panels
    max_stiffener_thickness_step: float = 2.5e-3  # |t_stiff,i - t_stiff,j| likewise
    max_stiffener_height_step: float = 10e-3  # |h_stiff,i - h_stiff,j| likewise
    # adjacency: between two adjacent skin panels or two adjacent spar panels, not skin-spar


SIZING_RULES = SizingRules()


@dataclass(frozen=True)
class PanelSizing:
    """Sizing of one stiffened panel, m.

    Parameters
    ----------
    stiffener_pitch : float
        Stiffener pitch (m).
    panel_thickness : float
        Skin thickness (m).
    stiffener_height : float
        Stiffener height (m).
    stiffener_thickness : float
        Stiffener thickness (m).
    """

    stiffener_pitch: float
    panel_thickness: float
    stiffener_height: float
    stiffener_thickness: float


#: Baseline sizing of every panel for the benchmark analyses (required_results.rst, "Panel variables").
BASELINE_PANEL = PanelSizing(stiffener_pitch=0.15, panel_thickness=0.0065, stiffener_height=0.05,
                             stiffener_thickness=0.006)

# ==============================================================================================
# Aircraft masses and mission (opt_problem.rst table "Aircraft and mission specifications";
# STWSpecs.py). The maneuvers are flown at the landing gross mass (LGM), which contains the
# wing mass and so the wingbox mass being sized.
# ==============================================================================================
PAYLOAD_MASS = 14.5e3  # kg, opt_problem.rst / STWSpecs.py PAYLOAD_MASS
AIRFRAME_MASS = 25e3  # kg, operating empty mass minus the wings, opt_problem.rst / STWSpecs.py
RESERVE_FUEL_MASS = 2e3  # kg, opt_problem.rst / STWSpecs.py
#: Wing mass regression M_wing = 10.147 M_wingbox^0.8162 (one wing, kg; opt_problem.rst, after
#: Mariens et al. 2013).
WING_MASS_COEFFICIENT = 10.147
WING_MASS_EXPONENT = 0.8162


def wing_mass(wingbox_mass: float) -> float:
    """Total mass of one wing from its wingbox mass, kg (opt_problem.rst regression).

    Parameters
    ----------
    wingbox_mass : float
        Wingbox mass (kg).

    Returns
    -------
    float
        Wing mass (kg).
    """
    if not (math.isfinite(wingbox_mass) and wingbox_mass > 0):
        raise ValueError(f"wingbox_mass = {wingbox_mass!r} kg; must be finite and > 0")
    return WING_MASS_COEFFICIENT * wingbox_mass**WING_MASS_EXPONENT


def landing_gross_mass(wingbox_mass: float) -> float:
    """LGM = M_payload + M_frame + M_fuel,res + 2 M_wing, kg (opt_problem.rst, "Objectives").

    Parameters
    ----------
    wingbox_mass : float
        Wingbox mass of one wing (kg).

    Returns
    -------
    float
        LGM (kg).
    """
    return PAYLOAD_MASS + AIRFRAME_MASS + RESERVE_FUEL_MASS + 2.0 * wing_mass(wingbox_mass)


#: Mission data used by the fuel-burn objective of Cases 2 and 3 (opt_problem.rst). Where the
#: code of STWSpecs.py differs, the comment gives its value; the documentation values are kept.
RANGE = 3815e3  # m, nominal range
CLIMB_RANGE = 290e3  # m (STWSpecs.py: 180 miles = 289.68 km)
CLIMB_SPEED_MPH = 350.0  # mph, average climb speed (STWSpecs.py converts it as 350 / 2.25 m/s)
CLIMB_ANGLE_DEG = 2.054  # deg, opt_problem.rst (atan(10400 m / climb range))
AIRFRAME_DRAG_COEFFICIENT = 0.01508  # C_D,frame (fuselage + tail + nacelle) on the single-wing area S
TANK_FRACTION = 0.85  # k_tank, fraction of the wingbox volume available for fuel
AUX_FUEL_VOLUME = 2.763  # m^3, auxiliary tanks
TSFC = 18e-6  # kg/(N s), opt_problem.rst (STWSpecs.py: 18.1e-6 * 9.81 in its own units)
FUEL_DENSITY = 804.0  # kg/m^3
MAX_WING_LOADING = 600.0  # kg/m^2, TOGM / 2S, Case 3 only
REFERENCE_MTOW = 55e3  # kg, STWSpecs.py REF_MTOW (code only; not used by the problem statement)

#: Non-structural masses on the wing: none. model.rst: "the structural model is subject to
#: aerodynamic forces and the wingbox's self-weight ... we do not include any inertial forces due
#: to non-structural masses such as fuel, or leading and trailing edge devices". The maneuvers
#: carry no fuel (STWFlightPoints.py MANEUVER_FUEL_LOAD_FRACTION = 0); the engines are not on
#: the wing (only their nacelle drag enters C_D,frame, STWSpecs.py).
NONSTRUCTURAL_MASS = 0.0

# ==============================================================================================
# Flight conditions (opt_problem.rst table "Flight conditions"; STWFlightPoints.py)
# ==============================================================================================


@dataclass(frozen=True)
class FlightCondition:
    """One flight condition of the STW benchmark (``STWFlightPoints.py``).

    Parameters
    ----------
    name : str
        Flight point name of the benchmark's ``STWFlightPoints.py``.
    altitude : float
        Altitude (m).
    mach : float
        Mach number (-).
    load_factor : float
        Load factor (-).
    mass : {"LGM", "mid-cruise"}
        Aircraft mass case.
    fuel_fraction : float
        Fraction of the fuel carried (-).
    failure_groups : tuple
        Component groups whose failure is constrained.
    cases : tuple
        Benchmark cases using it.
    """
    name: str  # the flight point name used in STWFlightPoints.py
    altitude: float  # m
    mach: float
    load_factor: float
    mass: str  # which aircraft mass: "LGM" or "mid-cruise" (sqrt(M_cruise,start x LGM))
    fuel_fraction: float  # fraction of the fuel carried (STWFlightPoints.py)
    failure_groups: tuple  # component groups whose failure is constrained (STWFlightPoints.py)
    cases: tuple  # benchmark cases using it


#: 2.5 g pull-up at sea level, M 0.458, at the LGM. opt_problem.rst gives M 0.458;
#: STWFlightPoints.py computes 0.398 x 1.15 = 0.4577 (263 KCAS at sea level plus 15 % "so that
#: we're not trying to simulate the aircraft right at CL max").
PULL_UP = FlightCondition("mnver_sealevel_va_pullup", 0.0, 0.458, 2.5, "LGM", 0.0,
                          ("l_skin", "u_skin", "spar", "rib"), (1, 2, 3))
#: -1 g push-down at sea level, M 0.458, at the LGM; STWFlightPoints.py constrains the lower
#: skin only in this case.
PUSH_DOWN = FlightCondition("mnver_sealevel_va_pushdown", 0.0, 0.458, -1.0, "LGM", 0.0, ("l_skin",), (1, 2, 3))
#: Cruise at 10 400 m, n = 1, at the mid-cruise mass (Cases 2 and 3). The Mach number differs
#: between the files: opt_problem.rst table 0.7, STWFlightPoints.py CRUISE_MACH = 0.77. The
#: table value is kept here (see docs/cases.md).
CRUISE = FlightCondition("cruise", 10400.0, 0.7, 1.0, "mid-cruise", 1.0, (), (2, 3))
CRUISE_MACH_CODE = 0.77  # STWFlightPoints.py
#: The two load cases of Case 1 (structural mass minimisation at fixed geometry).
CASE1_CONDITIONS = (PULL_UP, PUSH_DOWN)

# ==============================================================================================
# Benchmark analyses and results to report (required_results.rst)
# ==============================================================================================
#: Benchmark structural analysis: uniform pressure on the lower skin of the wingbox, Pa, plus
#: 2.5 g self-weight, baseline panel sizing.
BENCHMARK_PRESSURE = 30e3
BENCHMARK_PRESSURE_LOAD_FACTOR = 2.5
#: Benchmark aeroelastic analysis: cruise at this angle of attack, deg, with 1 g self-weight.
BENCHMARK_CRUISE_ALPHA_DEG = 3.25
#: Benchmark aerodynamic analysis: C_L and C_D in cruise at 0..5 deg in steps of at most 1 deg.
BENCHMARK_POLAR_ALPHA_DEG = (0.0, 1.0, 2.0, 3.0, 4.0, 5.0)
#: Tip deflection and twist from the top corners of the tip rib (required_results.rst, figure
#: TipDispEquations.png): points 1 (front spar) and 2 (rear spar),
#: dz_tip = (dz1 + dz2) / 2 and dtheta_y = atan((z2 + dz2 - z1 - dz1) / (x2 + dx2 - x1 - dx1))
#: - atan((z2 - z1) / (x2 - x1)).
TIP_RESULT_POINTS = ("front spar, upper corner, tip rib", "rear spar, upper corner, tip rib")
#: Results of Case 1 (required_results.rst). The benchmark lists these items but prescribes no
#: file or column layout; the spanwise distributions are requested as plots.
CASE1_RESULTS = (
    "wall time and CPU hours, hardware",
    "convergence history: objective, constraint violation, optimality",
    "spanwise lift distribution, initial and optimised, every flight condition",
    "spanwise equivalent axial thickness t_eq = t_panel + A_stiff / p_stiff of upper skin, lower skin, "
    "front spar, rear spar",
    "wingbox structural mass",
    "wing total mass",
    "landing gross mass",
    "angle of attack in each maneuver",
)
#: Added for Case 2 (and 3): twist distributions in flight, Cp at these semi-span fractions, ...
CASE2_SECTION_ETA = (0.1, 0.3, 0.5, 0.7, 0.9)


def equivalent_thickness(panel_thickness: float, stiffener_area: float, pitch: float = STIFFENER_PITCH) -> float:
    """t_eq = t_panel + A_stiff / p_stiff, m (required_results.rst, Case 1 sizing plots).

    Parameters
    ----------
    panel_thickness : float
        Skin thickness (m).
    stiffener_area : float
        Stiffener cross-section area (m^2).
    pitch : float, optional
        Stiffener pitch (m).

    Returns
    -------
    float
        t_eq (m).
    """
    if not pitch > 0:
        raise ValueError(f"pitch = {pitch!r} m; must be > 0")
    return panel_thickness + stiffener_area / pitch
