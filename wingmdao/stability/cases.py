"""Flutter problems of the benchmark wings: the aeroelastic beam (:mod:`wingmdao.aero`) of a case's
beam and aerodynamic data, with ``params_at(V)`` for a speed sweep."""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field

import numpy as np

from wingmdao.aero.strip import check_aero_inputs
from wingmdao.stability.eigen import critical_speeds, sweep
from wingmdao.timemarch.system import layout, pack
from wingmdao.aero import system as aero_system
from wingmdao.aero.system import cached_aeroelastic_system
from wingmdao.beam.static import beam_forcing
from wingmdao.names import FLUTTER_CASES  # cases with beam + aerodynamic data (module in wingmdao.cases)

#: sparse shift-invert settings: shift near the flutter frequency, eigenvalues kept, Arnoldi basis
EIG_OPTIONS = {"goland": {"method": "sparse", "sigma": 60j, "count": 16},
               "hale": {"method": "sparse", "sigma": 20j, "count": 16, "ncv": 60},
               "pegasus": {"method": "sparse", "sigma": 120j, "count": 40, "ncv": 100}}
#: default speed sweeps (V0, V1, N), m/s
SWEEPS = {"goland": (20.0, 300.0, 15), "hale": (2.0, 40.0, 12), "pegasus": (20.0, 300.0, 15)}
#: default number of beam nodes per case (PEGASUS: the 20-station sizing mesh)
DEFAULT_NODES = {"goland": 21, "hale": 21, "pegasus": 20}


@dataclass
class FlutterProblem:
    """The clamped aeroelastic wing of a flutter case: beam, aerodynamics, residual system and the
    case's published values.

    Parameters
    ----------
    name : str
        Case name.
    num_nodes : int
        Beam nodes.
    beam : dict
        Beam parameters.
    aero : dict
        Aerodynamic data of the strips.
    system : ResidualSystem
        The aeroelastic residual system.
    published : dict
        Published reference values of the case.
    eig_options : dict
        Eigen solver options.
    aero_theory : str, optional
        Quasi-steady lift theory (``strip``, ``lifting-line``, ``vlm``).
    """

    name: str
    num_nodes: int
    beam: dict
    aero: dict
    system: object
    published: dict
    eig_options: dict
    aero_theory: str = "strip"  # wingmdao.aero.coupled.AERO_THEORY_CHOICES
    _packed: tuple = field(default=None, init=False, repr=False, compare=False)   # (p, q, layout, theory parameters of a Mach number) of params_at

    @property
    def dive_speed(self):
        """Design dive speed V_D (TAS, m/s) of the case, None when it has none (benchmark wings)."""
        return self.aero.get("dive_speed")

    @property
    def speeds(self):
        """Default sweep (m/s)."""
        return np.linspace(*SWEEPS[self.name])

    def params_at(self, V):
        """Packed (p, q) at airspeed V (m/s): clamped root, no gravity, zero angle of attack.
        Only the airspeed and Mach number depend on V: the first call packs everything, later ones
        copy that and set those two entries (new arrays each call).

        Parameters
        ----------
        V : float
            Airspeed (m/s).

        Returns
        -------
        tuple
            (p, q).
        """
        if self._packed is None:
            self._packed = self._pack_at(V)
        p, q, lay, theory_parameters = self._packed
        V = float(V)
        mach = self.mach_at(V)
        check_aero_inputs(airspeed=V, mach=mach)
        p = p.copy()
        p[lay["airspeed"]] = V
        p[lay["mach"]] = mach
        if self.aero_theory == "vlm":  # the lattice at this Mach number (cached by planform and Mach)
            for k, v in theory_parameters(mach).items():
                p[lay[k]] = np.ravel(v)
        return p, q.copy()

    def _pack_at(self, V):
        n = self.num_nodes
        a = aero_system.aero_parameters(n, chord=self.aero["chord"], ref_point=self.aero["ref_point"],
                                        lift_slope=self.aero["lift_slope"], airspeed=V, density=self.aero["density"],
                                        mach=self.mach_at(V))

        def theory_parameters(mach):  # the theory's parameters at a Mach number (the lattice: cached)
            return aero_system.three_dimensional_parameters(self.aero_theory, self.beam["node_positions"],
                                                            np.broadcast_to(self.aero["chord"], (n,)),
                                                            np.broadcast_to(self.aero["ref_point"], (n,)), mach)

        a.update(theory_parameters(a["mach"]))
        p = pack(self.system.param_specs, {**self.beam, **a})
        qv = beam_forcing(n)
        qv.update({s.name: np.zeros(s.shape) for s in aero_system.aero_forcing_specs(n)})
        q = pack(self.system.forcing_specs, qv)
        return p, q, layout(self.system.param_specs), theory_parameters

    def mach_at(self, V):
        """Mach number at airspeed V (m/s): V / a when the case has a speed of sound, else 0 (incompressible).

        Parameters
        ----------
        V : float
            Airspeed (m/s).

        Returns
        -------
        float
            Mach number (-).
        """
        a = self.aero.get("speed_of_sound")
        return 0.0 if a is None else float(V) / float(a)

    def aero_mask(self):
        """1 on the aerodynamic lag states, 0 on the beam's (which modes the air loads)."""
        return self.system.layout.mask("aero")

    def beam_weights(self):
        """MAC weights: the beam's displacement and rotation states only."""
        w = np.zeros(self.system.n_state)
        w[self.system.layout.beam[:, 0:6].ravel()] = 1.0   # r, theta
        return w


def flutter_problem(name: str, num_nodes: int | None = None, thickness: dict | None = None,
                    panels=None, aero_theory: str = "strip") -> FlutterProblem:
    """The aeroelastic flutter problem of case ``name`` (one of :data:`FLUTTER_CASES`).

    ``num_nodes``: beam nodes (default :data:`DEFAULT_NODES`). ``thickness`` (PEGASUS only):
    ``{wall: (num_nodes,) m}`` wall thicknesses per node (default: the sizing's initial design),
    e.g. the ``thickness`` block of a ``wingmdao size pegasus`` JSON; with ``panels`` (a stiffened
    design's PanelLayout) it also holds the stiffener variables. ``aero_theory``
    (:data:`wingmdao.aero.coupled.AERO_THEORY_CHOICES`): the quasi-steady lift of the strips, of
    Prandtl's lifting line or of the vortex lattice (the Wagner lag per station in every case).

    Parameters
    ----------
    name : str
        Case name.
    num_nodes : int or None, optional
        Beam nodes; None for :data:`DEFAULT_NODES`.
    thickness : dict or None, optional
        Wall name -> (num_nodes,) thicknesses (m), PEGASUS only.
    panels : PanelLayout or None, optional
        Panel layout of a stiffened design.
    aero_theory : str, optional
        Quasi-steady lift theory.

    Returns
    -------
    FlutterProblem
        The problem.
    """
    if name not in FLUTTER_CASES:
        raise ValueError(f"case {name!r} has no aerodynamic (flutter) data; allowed: {list(FLUTTER_CASES)}")
    n = DEFAULT_NODES[name] if num_nodes is None else int(num_nodes)
    if n < 3:
        raise ValueError(f"num_nodes must be >= 3, got {num_nodes}")
    if thickness is not None and name != "pegasus":
        raise ValueError(f"thickness applies to the sized PEGASUS wing only, not to case {name!r}")

    mod = importlib.import_module(f"wingmdao.cases.{name}")
    if name == "pegasus":
        beam, aero = mod.beam_params(n, thickness, panels), mod.aero_data(n)
    else:
        beam, aero = mod.beam_params(n), mod.aero_data()
    system = cached_aeroelastic_system(n, aero_theory="vlm" if aero_theory == "vlm" else "strip")
    return FlutterProblem(name, n, beam, aero, system, mod.PUBLISHED, dict(EIG_OPTIONS[name]), aero_theory)


#: fractions of F V_D at which the sizing constraint checks the damping (the first picks the modes)
CONSTRAINT_SPEED_FRACTIONS = (0.25, 0.5, 0.75, 1.0)
#: most flutter margin F accepted by the sizing constraint (25.629 asks for 1.15)
MAX_FLUTTER_MARGIN = 3.0


def sizing_flutter_options(name: str, num_nodes: int, factor: float, *, rho_ks: float = 100.0,
                           decay: float = 0.0) -> dict:
    """Options of :class:`wingmdao.components.flutter.FlutterDamping` for "flutter speed >= F V_D"
    on sizing case ``name`` (F = ``factor``): the damping constraint Re(lambda) + ``decay`` <= 0
    (KS, 1/s) at the speeds F V_D x :data:`CONSTRAINT_SPEED_FRACTIONS`. ValueError (before any solve) for a case without
    aerodynamic data or V_D, or F outside (0, :data:`MAX_FLUTTER_MARGIN`].

    Parameters
    ----------
    name : str
        Case name.
    num_nodes : int
        Beam nodes.
    factor : float
        F, the required flutter speed over V_D (-).
    rho_ks : float, optional
        KS aggregation parameter.
    decay : float, optional
        Decay rate added to Re(lambda) (1/s).

    Returns
    -------
    dict
        The component's options.
    """
    if name not in FLUTTER_CASES or not hasattr(importlib.import_module(f"wingmdao.cases.{name}"), "flight_point"):
        allowed = [c for c in FLUTTER_CASES if hasattr(importlib.import_module(f"wingmdao.cases.{c}"), "flight_point")]
        raise ValueError(f"--flutter-margin: case {name!r} has no aerodynamic data or dive speed V_D; "
                         f"the flutter constraint applies to: {', '.join(allowed)}")
    F = float(factor)
    if not (np.isfinite(F) and 0.0 < F <= MAX_FLUTTER_MARGIN):
        raise ValueError(f"--flutter-margin = {factor}; allowed range (0, {MAX_FLUTTER_MARGIN:g}] "
                         "(a factor on V_D; 14 CFR 25.629: 1.15)")
    mod = importlib.import_module(f"wingmdao.cases.{name}")
    aero = mod.aero_data(int(num_nodes))
    top = F * aero["dive_speed"]
    a = aero.get("speed_of_sound")
    if a is not None and not top < a:
        raise ValueError(f"--flutter-margin = {factor}: F V_D = {top:.1f} m/s is not subsonic (a = {a:.1f} m/s); "
                         f"allowed range (0, {a / aero['dive_speed']:.3f})")
    return {"aero": aero, "speeds": top * np.asarray(CONSTRAINT_SPEED_FRACTIONS),
            "rho_ks": float(rho_ks), "margin": float(decay), "measure": "sigma",
            "eig_options": dict(EIG_OPTIONS[name])}


def flutter_search(name: str, num_nodes: int | None = None, thickness: dict | None = None, speeds=None,
                   n_modes: int = 4, panels=None) -> dict:
    """Sweep and refined flutter / divergence speeds of case ``name`` (thicknesses: PEGASUS);
    returns ``{"flutter_speed", "flutter_frequency", "divergence_speed", "sweep_max_speed", "sweep"}``
    (speeds None when not reached below the sweep's end ``sweep_max_speed``, m/s).

    Parameters
    ----------
    name : str
        Case name.
    num_nodes : int or None, optional
        Beam nodes.
    thickness : dict or None, optional
        Wall name -> thicknesses (m), PEGASUS only.
    speeds : array_like or None, optional
        Sweep (m/s); None for the case's default.
    n_modes : int, optional
        Modes tracked.
    panels : PanelLayout or None, optional
        Panel layout of a stiffened design.

    Returns
    -------
    dict
        The speeds and the sweep.
    """
    prob = flutter_problem(name, num_nodes, thickness, panels)
    v = prob.speeds if speeds is None else np.asarray(speeds, dtype=float)
    res = sweep(prob.system, prob.params_at, v, n_track=int(n_modes), weights=prob.beam_weights(),
                **prob.eig_options)
    crit = critical_speeds(res)
    return {"flutter_speed": crit["flutter_speed"], "flutter_frequency": crit["flutter_frequency"],
            "divergence_speed": crit["divergence_speed"], "sweep_max_speed": float(v[-1]),
            "dive_speed": prob.dive_speed, "sweep": res}
