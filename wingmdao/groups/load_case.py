"""Load cases: what one WingStructure analyses (static maneuver or dynamic time history)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from wingmdao.beam.residual import StrainRateDamping
from wingmdao.aero.coupled import AERO_FORCING_SHAPES, CoupledAero
from wingmdao.aero.modal_design import ModalGust
from wingmdao.section.box import WALL_NAMES
from wingmdao.stress.box_stress import SECTION_PROPERTIES

STRESS_FAMILIES = ("vm", "ss_tension", "ss_compression", "cent_pos", "cent_neg")
#: shorthands accepted by every ``--families`` list: both signs of a family
FAMILY_GROUPS = {"ss": ("ss_tension", "ss_compression"), "cent": ("cent_pos", "cent_neg")}


def parse_families(text, option: str = "--families") -> tuple:
    """Stress families of a comma list of :data:`STRESS_FAMILIES` names and :data:`FAMILY_GROUPS`
    shorthands (``vm,ss`` = vm, ss_tension, ss_compression), in order, without repeats; ValueError
    naming ``option`` and the valid names otherwise.

    Parameters
    ----------
    text : str
        Comma-separated family names and shorthands.
    option : str
        The command-line option named in the error message.

    Returns
    -------
    tuple of str
        The stress families.
    """
    names = [t.strip() for t in str(text).split(",") if t.strip()]
    bad = [t for t in names if t not in STRESS_FAMILIES and t not in FAMILY_GROUPS]
    if bad or not names:
        raise ValueError(f"{option}: unknown {bad or 'empty list'}; valid: "
                         f"{', '.join((*STRESS_FAMILIES, *FAMILY_GROUPS))}")
    fams = []
    for t in names:
        fams += [f for f in FAMILY_GROUPS.get(t, (t,)) if f not in fams]
    return tuple(fams)

#: Forcing inputs of the beam, with their shape per instant (n = number of nodes) and units.
FORCING_SHAPES = {
    "force_per_length": ("n", 3),
    "moment_per_length": ("n", 3),
    "point_force": ("n", 3),
    "point_moment": ("n", 3),
    "gravity": (3,),
    "frame_acceleration": (3,),
    "frame_angular_velocity": (3,),
    "frame_angular_acceleration": (3,),
}


@dataclass
class LoadCase:
    """One certification load case on the beam mesh.

    ``time`` is the time grid (s, ``time[0] = 0``); a single entry means a static solve.
    ``forcing`` maps beam forcing names (see :data:`FORCING_SHAPES`) to arrays shaped
    ``(n_time, ...)`` in SI units; missing ones are zero. ``families`` are the stress
    constraint families aggregated by KS for this case. ``damping``: optional structural
    damping of the beam (:class:`wingmdao.beam.residual.StrainRateDamping`, Alg. 6), e.g.
    ``StrainRateDamping.from_damping_ratio(0.02, f_first_bending)``; none by default.

    Parameters
    ----------
    name : str
        The case's name (its subsystem ``cases.NAME``).
    time : numpy.ndarray
        Time grid (s), ``time[0] = 0``; one entry: a static solve.
    forcing : dict
        ``{forcing name: (n_time, ...) array}`` in SI units; missing names are zero.
    families : tuple of str
        Stress constraint families aggregated by KS.
    description : str
        Free text for reports.
    damping : wingmdao.beam.residual.StrainRateDamping or None
        Structural damping of the beam; None: undamped.
    aero : wingmdao.aero.coupled.CoupledAero or None
        Aeroelastic coupling; None: the case runs on the structural beam.
    modal_dlm : wingmdao.aero.modal_design.ModalGust or None
        Dynamic increment on the modal doublet-lattice wing, added to the static first instant.
    symmetric : LoadCase or None
        A static structural case (no aero) whose internal loads are superposed on this case's
        antisymmetric increments with both signs, ``symmetric ± increment(t)`` (the two wings of
        a 14 CFR 25.349(a) rolling condition at 2/3 n_lim); None: the increments alone.
    """

    name: str
    time: np.ndarray = field(default_factory=lambda: np.zeros(1))
    forcing: dict = field(default_factory=dict)
    families: tuple = ("vm",)
    description: str = ""
    damping: object = None
    #: optional :class:`wingmdao.aero.coupled.CoupledAero`: the case runs on the aeroelastic beam
    aero: object = None
    #: optional :class:`wingmdao.aero.modal_design.ModalGust`: the case's dynamic increment on the modal
    #: doublet-lattice wing, added to the static first instant of the beam (``aero``: the trimmed 1 g state)
    modal_dlm: object = None
    #: optional static :class:`LoadCase`: superposed as ``symmetric ± increment(t)`` (the two wings)
    symmetric: object = None

    def __post_init__(self):
        self.time = np.atleast_1d(np.asarray(self.time, dtype=float))
        if not self.name.isidentifier():
            raise ValueError(f"load case name {self.name!r} must be a Python identifier (used in variable paths)")
        if self.time[0] != 0.0:
            raise ValueError(f"load case {self.name}: time must start at 0 s, got {self.time[0]} s")
        if self.time.size > 1 and np.any(np.diff(self.time) <= 0):
            raise ValueError(f"load case {self.name}: time must be strictly increasing")
        bad = [f for f in self.families if f not in STRESS_FAMILIES]
        if bad:
            raise ValueError(f"load case {self.name}: unknown stress families {bad}; valid: {', '.join(STRESS_FAMILIES)}")
        if self.damping is not None:
            if not isinstance(self.damping, StrainRateDamping):
                raise ValueError(f"load case {self.name}: damping must be a StrainRateDamping, got {self.damping!r}")
        if self.aero is not None:
            if not isinstance(self.aero, CoupledAero):
                raise ValueError(f"load case {self.name}: aero must be a CoupledAero, got {type(self.aero).__name__}")
        if self.modal_dlm is not None:
            if not isinstance(self.modal_dlm, ModalGust):
                raise ValueError(f"load case {self.name}: modal_dlm must be a ModalGust, got {type(self.modal_dlm).__name__}")
            if np.shape(self.modal_dlm.gust) != (self.num_times, 3):
                raise ValueError(f"load case {self.name}: modal_dlm.gust has shape {np.shape(self.modal_dlm.gust)}, "
                                 f"expected ({self.num_times}, 3)")
        if self.symmetric is not None:
            sym = self.symmetric
            if not isinstance(sym, LoadCase) or not sym.is_static or sym.aero is not None or sym.modal_dlm is not None \
                    or sym.symmetric is not None:
                raise ValueError(f"load case {self.name}: symmetric must be a static structural LoadCase (one time, "
                                 f"no aero, modal_dlm or symmetric of its own), got {sym!r:.80}")
            if self.modal_dlm is not None:
                raise ValueError(f"load case {self.name}: symmetric goes with the beam's increments, not modal_dlm")
        unknown = [k for k in self.forcing if k not in self._forcing_shapes()]
        if unknown:
            raise ValueError(f"load case {self.name}: unknown forcing {unknown}; valid: {', '.join(FORCING_SHAPES)}")

    @property
    def num_times(self) -> int:
        return int(self.time.size)

    @property
    def loads_path(self) -> str:
        """The subsystem of the case's WingStructure whose ``F_csn``, ``M_csn`` the stress reads:
        ``combined_loads`` (2 n_time instants, both wings) with ``symmetric``, else ``internal_loads``."""
        return "combined_loads" if self.symmetric is not None else "internal_loads"

    @property
    def num_stress_times(self) -> int:
        """Instants of the stress and KS: 2 n_time with ``symmetric`` (both wings), else n_time."""
        return (2 if self.symmetric is not None else 1) * self.num_times

    @property
    def is_static(self) -> bool:
        return self.num_times == 1

    def _forcing_shapes(self) -> dict:
        if self.aero is None:
            return FORCING_SHAPES

        controls = getattr(self.aero, "controls", None)
        extra = {"surface_command": (controls.n_surfaces,)} if controls is not None else {}
        return {**FORCING_SHAPES, **AERO_FORCING_SHAPES, **extra}

    def static_case(self, num_nodes: int) -> LoadCase:
        """The case's first instant alone (a static solve; no ``modal_dlm``): the beam part of a
        case with a modal doublet-lattice increment.

        Parameters
        ----------
        num_nodes : int
            Number of beam nodes.

        Returns
        -------
        LoadCase
            The static case.
        """
        forcing = {k: self.forcing_array(k, num_nodes)[:1] for k in self.forcing}
        return replace(self, time=self.time[:1], forcing=forcing, modal_dlm=None, families=())

    def forcing_array(self, name: str, num_nodes: int) -> np.ndarray:
        """The full (n_time, ...) array of forcing ``name`` (zeros when not given), validated.

        Parameters
        ----------
        name : str
            A beam forcing name (:data:`FORCING_SHAPES`).
        num_nodes : int
            Number of beam nodes.

        Returns
        -------
        numpy.ndarray
            The forcing history, shape (n_time, ...).
        """
        shape = (self.num_times,) + tuple(num_nodes if d == "n" else d for d in self._forcing_shapes()[name])
        if name not in self.forcing:
            return np.zeros(shape)
        arr = np.asarray(self.forcing[name], dtype=float)
        if arr.shape == shape[1:]:  # constant in time
            arr = np.broadcast_to(arr, shape).copy()
        if arr.shape != shape:
            raise ValueError(f"load case {self.name}: forcing {name} has shape {arr.shape}, expected {shape}")
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"load case {self.name}: forcing {name} has non-finite values")
        return arr


@dataclass
class StickCase:
    """A load case of the stick model: its ``name``, the joined aeroelastic ``system``
    (:func:`wingmdao.cases.pegasus_stick.aeroelastic_system`), the ``time`` grid (s), the packed
    parameters ``p`` (the wing's blocks are replaced by the group's inputs) and forcing history
    ``forcing`` (n_time, n_forcing), the stress ``families`` and the name of the wing beam.

    Parameters
    ----------
    name : str
        The case's name.
    system : wingmdao.timemarch.system.ResidualSystem
        The joined aeroelastic system.
    time : numpy.ndarray
        Time grid (s).
    p : numpy.ndarray
        Packed parameters; the wing's blocks are replaced by the group's inputs.
    forcing : numpy.ndarray
        Packed forcing history, shape (n_time, n_forcing).
    families : tuple of str
        Stress constraint families aggregated by KS.
    wing : str
        Name of the wing beam in ``system``.
    """

    name: str
    system: object
    time: np.ndarray
    p: np.ndarray
    forcing: np.ndarray
    families: tuple = ("vm",)
    wing: str = "wing"
    #: no lone-wing ``CoupledAero`` (the joined system holds its aerodynamics): read as LoadCase.aero is
    aero = None

    @property
    def num_times(self) -> int:
        return int(np.asarray(self.time).size)


#: the beam parameters a sized section feeds, per section kind (the rest stay data of the case)
SIZED_BEAM_INPUTS = {"box": ("stiffness_csn", "compliance_csn", "mass_per_length", "inertia_per_length",
                             "tension_axis", "shear_center", "mass_center"),
                     "tube": ("stiffness_csn", "compliance_csn", "mass_per_length")}
#: the per-station inputs of a sized section (besides its walls), per kind
SIZED_SECTION_DATA = {"box": ("width", "height", "nonstructural_mass_per_length"),
                 "tube": ("nonstructural_mass_per_length",)}


@dataclass
class SizedBeam:
    """A beam of the stick model other than the wing whose section is sized with the wing's walls
    (:class:`StickSizing` option ``sized_beams``): a box (walls ``<name>_t_upper_skin``, ...; the
    wing's :class:`~wingmdao.components.section.BoxSection` and ``vm`` stress) or a thin circular
    tube (wall ``<name>_t_wall``; :class:`~wingmdao.components.tube.TubeSection`, ``TubeStress``).

    Parameters
    ----------
    name : str
        The beam's name in the joined system.
    kind : str
        ``"box"`` or ``"tube"``.
    node_positions : numpy.ndarray
        (n, 3) jig node positions (m; the beam's own axes), for its mass.
    data : dict
        Per-station section data: box ``width``, ``height`` (m), tube ``radius`` (m, a number) and
        ``fraction`` (its share of the whole tube); both ``nonstructural_mass_per_length`` (kg/m).
    initial : float
        Initial wall thickness (m).
    lower, upper : float
        Bounds of the wall thickness (m).
    """

    name: str
    kind: str
    node_positions: np.ndarray
    data: dict = field(default_factory=dict)
    initial: float = 3e-3
    lower: float = 1e-3
    upper: float = 0.05

    def __post_init__(self):
        if self.kind not in SIZED_BEAM_INPUTS:
            raise ValueError(f"SizedBeam {self.name!r}: kind = {self.kind!r}; allowed: {', '.join(SIZED_BEAM_INPUTS)}")
        if not 0.0 < self.lower <= self.initial <= self.upper:
            raise ValueError(f"SizedBeam {self.name!r}: need 0 < lower <= initial <= upper, got {self.lower}, "
                             f"{self.initial}, {self.upper} m")

    @property
    def num_nodes(self) -> int:
        """Number of nodes (stations)."""
        return int(np.asarray(self.node_positions).shape[0])

    @property
    def walls(self) -> tuple:
        """The section's wall names (unprefixed)."""
        return WALL_NAMES if self.kind == "box" else ("t_wall",)

    @property
    def design_vars(self) -> tuple:
        """The design variables: ``<name>_<wall>``."""
        return tuple(f"{self.name}_{w}" for w in self.walls)

    @property
    def beam_inputs(self) -> tuple:
        """The joined system's parameters the section feeds: ``<name>_stiffness_csn``, ..."""
        return tuple(f"{self.name}_{k}" for k in SIZED_BEAM_INPUTS[self.kind])

    @property
    def stress_inputs(self) -> tuple:
        """The (prefixed) per-station inputs of the beam's stress component besides the loads."""
        if self.kind == "box":
            return tuple(f"{self.name}_{k}" for k in ("width", "height", *WALL_NAMES, *SECTION_PROPERTIES))
        return (f"{self.name}_t_wall",)
