"""Flutter problems of the benchmark wings: the aeroelastic beam (:mod:`wingmdao.aero`) of a case's
beam and aerodynamic data, with ``params_at(V)`` for a speed sweep."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: cases with beam + aerodynamic data (module in wingmdao.cases with beam_params and aero_data)
FLUTTER_CASES = ("goland", "hale")
#: sparse shift-invert settings: shift near the flutter frequency, eigenvalues kept, Arnoldi basis
EIG_OPTIONS = {"goland": {"method": "sparse", "sigma": 60j, "count": 16},
               "hale": {"method": "sparse", "sigma": 20j, "count": 16, "ncv": 60}}
#: default speed sweeps (V0, V1, N), m/s
SWEEPS = {"goland": (20.0, 300.0, 15), "hale": (2.0, 40.0, 12)}


@dataclass
class FlutterProblem:
    name: str
    num_nodes: int
    beam: dict
    aero: dict
    system: object
    published: dict
    eig_options: dict

    @property
    def speeds(self):
        """Default sweep (m/s)."""
        return np.linspace(*SWEEPS[self.name])

    def params_at(self, V):
        """Packed (p, q) at airspeed V (m/s): clamped root, no gravity, zero angle of attack."""
        from wingmdao.aero.system import aero_forcing_specs, aero_parameters
        from wingmdao.beam.residual import forcing_specs as beam_forcing_specs
        from wingmdao.beam.static import beam_forcing
        from wingmdao.timemarch.system import pack

        n = self.num_nodes
        a = aero_parameters(n, chord=self.aero["chord"], ref_point=self.aero["ref_point"],
                            lift_slope=self.aero["lift_slope"], airspeed=V, density=self.aero["density"])
        p = pack(self.system.param_specs, {**self.beam, **a})
        qv = beam_forcing(n)
        qv.update({s.name: np.zeros(s.shape) for s in aero_forcing_specs(n)})
        q = pack(self.system.forcing_specs, qv)
        return p, q

    def beam_weights(self):
        """MAC weights: the beam's displacement and rotation states only."""
        w = np.zeros(self.system.state_shape)
        w[:, 0:6] = 1.0
        return w.ravel()


def flutter_problem(name: str, num_nodes: int = 21) -> FlutterProblem:
    """The aeroelastic flutter problem of case ``name`` (one of :data:`FLUTTER_CASES`)."""
    import importlib

    if name not in FLUTTER_CASES:
        raise ValueError(f"case {name!r} has no aerodynamic (flutter) data; allowed: {list(FLUTTER_CASES)}")
    if int(num_nodes) < 3:
        raise ValueError(f"num_nodes must be >= 3, got {num_nodes}")
    from wingmdao.aero.system import cached_aeroelastic_system

    mod = importlib.import_module(f"wingmdao.cases.{name}")
    return FlutterProblem(name, int(num_nodes), mod.beam_params(int(num_nodes)), mod.aero_data(),
                          cached_aeroelastic_system(int(num_nodes)), mod.PUBLISHED,
                          dict(EIG_OPTIONS[name]))
