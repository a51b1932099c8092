"""Load cases distributed over MPI ranks, without PETSc.

OpenMDAO's ``ParallelGroup`` needs PETSc (petsc4py) for its data transfers as soon as a
problem's communicator has more than one rank, and PETSc has no binary wheel on PyPI. A
sizing problem has a simple structure that makes PETSc unnecessary: the load cases share
only the design variables, and each case returns a few KS values. So under ``mpirun -n P``

* every rank runs the same serial OpenMDAO problem (``OPENMDAO_USE_MPI=0``, set by
  :func:`wingmdao._mpi_environment` before OpenMDAO is imported): section, mass, driver;
* the load cases are split over the ranks (longest march first onto the least loaded rank);
  each rank owns a serial sub-problem with only its cases;
* in the main problem ``cases.<name>`` is a proxy group with the same output names as
  :class:`~wingmdao.groups.wing.WingStructure` (``ks_<family>``, ``stress.g_<family>``,
  ``internal_loads.F_csn``/``M_csn``); its values and its KS derivatives with respect to the
  design variables (the sub-problem's adjoint totals) are exchanged with one ``allgather`` per
  design point, so every rank's driver sees identical numbers and takes identical steps.

The results equal the serial run's to round-off (the same adjoint, the same chain rule). Only
rank 0 records and writes files (:func:`is_root`).
"""

from __future__ import annotations

import copy

import numpy as np
import openmdao.api as om

from wingmdao.groups.load_case import LoadCase
from wingmdao.utils.mpi_env import launched_ranks  # noqa: F401 - part of this module's API
from wingmdao.groups.wing import SECTION_KINDS, WingSizing, stress_points



def world_comm():
    """``MPI.COMM_WORLD`` when run under ``mpirun -n P`` with P > 1, else None (mpi4py imported lazily)."""
    if launched_ranks() <= 1:
        return None
    try:
        from mpi4py import MPI
    except ImportError as exc:  # pragma: no cover - depends on the install
        raise ImportError("running under mpirun needs mpi4py: pip install 'wingmdao[mpi]'") from exc
    return MPI.COMM_WORLD if MPI.COMM_WORLD.size > 1 else None


def rank() -> int:
    """This process's rank in ``MPI.COMM_WORLD`` (0 in a serial run).

    Returns
    -------
    int
        The rank.
    """
    comm = world_comm()
    return 0 if comm is None else comm.rank


def is_root() -> bool:
    """True on rank 0 (and in serial runs): the rank that prints, records and writes files."""
    return rank() == 0


def assign_cases(load_cases, size: int) -> list:
    """Case indices per rank: longest march first onto the least loaded rank (cost ~ time steps).

    Raises ValueError when there are more ranks than load cases (a rank would sit idle).

    Parameters
    ----------
    load_cases : sequence of LoadCase
        The load cases.
    size : int
        Number of ranks.

    Returns
    -------
    list of list of int
        Case indices of each rank.
    """
    n = len(load_cases)
    if size > n:
        raise ValueError(f"MPI: {size} ranks but only {n} load case(s); the cases can use at most {n} "
                         f"rank(s) (one case per rank): run with mpirun -n {n} or fewer, or add load cases")
    cost = [max(1, int(c.num_times)) for c in load_cases]
    order = sorted(range(n), key=lambda i: (-cost[i], i))
    owned = [[] for _ in range(size)]
    load = [0] * size
    for i in order:
        r = min(range(size), key=lambda k: (load[k], k))
        owned[r].append(i)
        load[r] += cost[i]
    return [sorted(o) for o in owned]


class CaseExchange:
    """This rank's sub-problem and the gathered values/derivatives of all cases at one design.

    Parameters
    ----------
    geometry : WingGeometry
        The wing.
    load_cases : sequence of LoadCase
        Every load case.
    material : Material
        The material.
    options : SizingOptions
        The sizing options.
    section : str
        Section kind.
    comm : mpi4py.MPI.Comm
        The communicator.
    design_vars : sequence of str
        Design variable names.
    build_problem : callable
        :func:`wingmdao.sizing.build_problem`, which builds this rank's sub-problem.
    """

    def __init__(self, geometry, load_cases, material, options, section, comm, design_vars, *, build_problem):
        """``build_problem``: :func:`wingmdao.sizing.build_problem`, which builds this rank's sub-problem."""
        self.comm = comm
        self.cases = list(load_cases)
        self.owned = assign_cases(self.cases, comm.size)
        self.mine = [self.cases[i] for i in self.owned[comm.rank]]
        self.design_vars = tuple(design_vars)
        sub = copy.copy(options)
        sub.recording, sub.progress = None, False
        self.prob, _ = build_problem(geometry, self.mine, material, sub, driver=False, parallel=False,
                                     section=section, comm=False)
        self.of = [f"cases.{c.name}.ks_{f}" for c in self.mine for f in c.families]
        self._vkey = self._jkey = None
        self.values = {}
        self.jac = {}

    def _key(self, x):
        return b"".join(np.ascontiguousarray(x[d], dtype=float).tobytes() for d in self.design_vars)

    def _gather(self, local):
        """allgather of (error or payload); every rank raises the same AnalysisError on a failure."""
        parts = self.comm.allgather(local)
        errors = [p["error"] for p in parts if "error" in p]
        if errors:
            raise om.AnalysisError("; ".join(errors))
        merged = {}
        for p in parts:
            merged.update(p["data"])
        return merged

    def evaluate(self, x):
        """Run this rank's cases at design ``x`` and gather every case's values (cached for the same ``x``); a failure on any rank is reported on all.

        Parameters
        ----------
        x : dict
            Design variable name -> value.

        Returns
        -------
        dict
            Case name -> KS values, stress constraints and internal loads, gathered from every rank.
        """
        key = self._key(x)
        if key == self._vkey:
            return self.values
        try:
            for d in self.design_vars:
                self.prob.set_val(d, x[d])
            self.prob.run_model()
            data = {}
            for c in self.mine:
                p = f"cases.{c.name}"
                data[c.name] = {**{f"ks_{f}": np.array(self.prob.get_val(f"{p}.ks_{f}")) for f in c.families},
                                **{f"g_{f}": np.array(self.prob.get_val(f"{p}.stress.g_{f}")) for f in c.families},
                                "F_csn": np.array(self.prob.get_val(f"{p}.{c.loads_path}.F_csn")),
                                "M_csn": np.array(self.prob.get_val(f"{p}.{c.loads_path}.M_csn"))}
            local = {"data": data}
        except Exception as exc:  # noqa: BLE001 - every rank must reach the allgather
            local = {"error": f"rank {self.comm.rank}: {type(exc).__name__}: {exc}"}
        self._vkey = None
        self.values = self._gather(local)
        self._vkey = key
        return self.values

    def derivatives(self, x):
        """Adjoint totals of this rank's KS values at design ``x``, gathered from every rank (cached for the same ``x``).

        Parameters
        ----------
        x : dict
            Design variable name -> value.

        Returns
        -------
        dict
            Case name -> KS name -> design variable -> total derivative, gathered from every rank.
        """
        key = self._key(x)
        if key == self._jkey:
            return self.jac
        self.evaluate(x)
        try:
            tot = self.prob.compute_totals(of=self.of, wrt=list(self.design_vars), return_format="dict") \
                if self.of else {}
            data = {}
            for c in self.mine:
                data[c.name] = {f"ks_{f}": {d: np.array(tot[f"cases.{c.name}.ks_{f}"][d]) for d in self.design_vars}
                                for f in c.families}
            local = {"data": data}
        except Exception as exc:  # noqa: BLE001
            local = {"error": f"rank {self.comm.rank}: {type(exc).__name__}: {exc}"}
        self._jkey = None
        self.jac = self._gather(local)
        self._jkey = key
        return self.jac


class _ProxyBase(om.ExplicitComponent):
    def initialize(self):
        self.options.declare("exchange", types=CaseExchange, recordable=False,
                             desc="the load-case exchange between the ranks")
        self.options.declare("case", types=LoadCase, recordable=False, desc="wingmdao.groups.load_case.LoadCase")
        self.options.declare("dv_size", types=int, desc="number of design-variable values per wall")

    def _add_design_inputs(self):
        for d in self.options["exchange"].design_vars:
            self.add_input(d, val=np.ones(self.options["dv_size"]), units="m", desc=f"design variable {d}")


class CaseKS(_ProxyBase):
    """KS values of one load case computed on its rank; partials = that rank's adjoint totals (dense in t)."""

    def setup(self):
        self._add_design_inputs()
        for f in self.options["case"].families:
            self.add_output(f"ks_{f}", shape=(1,), desc=f"KS aggregate of the {f} constraints (<= 0 feasible)")
            self.declare_partials(f"ks_{f}", list(self.options["exchange"].design_vars))

    def compute(self, inputs, outputs):
        vals = self.options["exchange"].evaluate(inputs)[self.options["case"].name]
        for f in self.options["case"].families:
            outputs[f"ks_{f}"] = vals[f"ks_{f}"]

    def compute_partials(self, inputs, partials):
        jac = self.options["exchange"].derivatives(inputs)[self.options["case"].name]
        for f in self.options["case"].families:
            for d in self.options["exchange"].design_vars:
                partials[f"ks_{f}", d] = jac[f"ks_{f}"][d]


class CaseHistory(_ProxyBase):
    """Time histories of one load case gathered from its rank, for plots and presizing.

    Post-processing outputs: no derivatives are declared (they feed no constraint or objective).
    """

    def initialize(self):
        super().initialize()
        self.options.declare("outputs", types=dict, desc="{name: (shape, units, desc)}")

    def setup(self):
        self._add_design_inputs()
        for name, (shape, units, desc) in self.options["outputs"].items():
            self.add_output(name, shape=shape, units=units, desc=desc)

    def compute(self, inputs, outputs):
        vals = self.options["exchange"].evaluate(inputs)[self.options["case"].name]
        for name in self.options["outputs"]:
            outputs[name] = vals[name]


def add_case_proxies(cases, exchange, geometry, material, section, n_dv, add_constraints=False):
    """``<name>`` proxy groups (ks, stress, internal_loads) in group ``cases`` for every load case.

    Parameters
    ----------
    cases : openmdao.api.Group
        The ``cases`` group.
    exchange : CaseExchange
        The exchange.
    geometry : WingGeometry
        The wing.
    material : Material
        The material.
    section : str
        Section kind.
    n_dv : int
        Design variable size per wall.
    add_constraints : bool, optional
        Add the KS constraints.
    """
    design = list(SECTION_KINDS[section]["design_vars"])
    n = geometry.num_nodes
    for case in exchange.cases:
        grp = cases.add_subsystem(case.name, om.Group(), promotes_inputs=design)
        kw = dict(exchange=exchange, case=case, dv_size=n_dv)
        grp.add_subsystem("ks", CaseKS(**kw), promotes_inputs=design, promotes_outputs=["*"])
        if add_constraints:  # as WingStructure(add_constraints=True) does
            for fam in case.families:
                grp.add_constraint(f"ks_{fam}", upper=0.0)
        nt = case.num_stress_times   # both wings of a case combined with a symmetric one
        shapes = {f: (nt, n, k) for f, k in stress_points(section, case.families).items()}
        grp.add_subsystem("stress", CaseHistory(outputs={f"g_{f}": (shapes[f], None, f"{f} stress constraints")
                                                         for f in case.families}, **kw),
                          promotes_inputs=design)
        grp.add_subsystem(case.loads_path, CaseHistory(outputs={
            "F_csn": ((nt, n, 3), "N", "internal force, csn frame"),
            "M_csn": ((nt, n, 3), "N*m", "internal moment, csn frame")}, **kw),
            promotes_inputs=design)


def distributed_wing_sizing(geometry, load_cases, material, options, section, comm, *, build_problem, **wing_kwargs):
    """A :class:`~wingmdao.groups.wing.WingSizing` whose ``cases`` group holds proxies of the
    load cases, each computed on its rank (:class:`CaseExchange`, its sub-problem from ``build_problem``).

    Parameters
    ----------
    geometry : WingGeometry
        The wing.
    load_cases : sequence of LoadCase
        Every load case.
    material : Material
        The material.
    options : SizingOptions
        The sizing options.
    section : str
        Section kind.
    comm : mpi4py.MPI.Comm
        The communicator.
    build_problem : callable
        :func:`wingmdao.sizing.build_problem`.
    **wing_kwargs
        Passed to :class:`~wingmdao.groups.wing.WingSizing`.

    Returns
    -------
    WingSizing
        The group.
    """
    design = SECTION_KINDS[section]["design_vars"]
    exchange = CaseExchange(geometry, load_cases, material, options, section, comm, design,
                            build_problem=build_problem)
    n = geometry.num_nodes
    n_dv = n if geometry.station_map is None else int(np.max(geometry.station_map)) + 1

    class DistributedWingSizing(WingSizing):
        def setup(self):
            super().setup()
            add_case_proxies(self.cases_group, exchange, geometry, material, section, n_dv,
                             add_constraints=self.options["add_constraints"])

    group = DistributedWingSizing(num_nodes=n, load_cases=[], material=material, parallel=False, proxy_cases=True,
                                  section=section, station_map=geometry.station_map, **wing_kwargs)
    return group, exchange


def set_shared_geometry(prob, geometry, section="box"):
    """:func:`wingmdao.sizing.set_geometry` for a main problem whose cases live in sub-problems.

    Parameters
    ----------
    prob : openmdao.api.Problem
        The main problem.
    geometry : WingGeometry
        The wing.
    section : str, optional
        Section kind.
    """
    prob.set_val("node_positions", geometry.node_positions, units="m")
    # the jig Euler angles only enter the beams, which live in the cases' sub-problems
    if section == "box":
        prob.set_val("width", geometry.width, units="m")
        prob.set_val("height", geometry.height, units="m")
