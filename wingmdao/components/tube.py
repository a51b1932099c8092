"""Thin-walled circular tube (a fuselage shell) per station: its beam data and its stress
constraints over (time, station), from :mod:`wingmdao.section.tube`. Pointwise CasADi
components: exact, block-diagonal partials."""

from __future__ import annotations

import numbers

import casadi as ca
import numpy as np

from wingmdao.components.pointwise import PointwiseCasadiComponent, Var
from wingmdao.components.stress import declare_stress_grid_options
from wingmdao.materials import Material
from wingmdao.section.tube import TUBE_POINTS, tube_properties, tube_stresses, validate_tube


def _declare_tube_options(options):
    options.declare("radius", types=numbers.Real, desc="midline radius R of the tube (m)")
    options.declare("fraction", default=1.0, types=numbers.Real,
                    desc="share of the whole tube the beam carries (1/2 on a half model's plane of symmetry)")


class TubeSection(PointwiseCasadiComponent):
    """Beam data of a thin circular tube at ``num_stations`` stations (:func:`wingmdao.section.tube.tube_properties`).

    Inputs (per station): ``t_wall`` (m), ``nonstructural_mass_per_length`` (kg/m, the beam's share).
    Outputs: ``A`` (m^2), ``stiffness_csn`` (3, 3), ``compliance_csn`` (3,), ``mass_per_length``
    (kg/m), the beam's share (option ``fraction``).
    """

    def initialize(self):
        super().initialize()
        self.options.declare("num_stations", types=int, lower=1, desc="number of beam stations")
        self.options.declare("material", types=Material, desc="wingmdao.materials.Material (E, G, rho)")
        _declare_tube_options(self.options)

    def point_grid(self):
        """Leading shape of every variable: (num_stations,).

        Returns
        -------
        tuple
            The grid shape.
        """
        return (self.options["num_stations"],)

    def expression_options(self):
        """The expressions depend on the material, radius and fraction (persisted)."""
        o = self.options
        return (o["material"], float(o["radius"]), float(o["fraction"]))

    def pointwise_inputs(self):
        """The per-point inputs: the wall thickness and the nonstructural mass per length.

        Returns
        -------
        list of Var
            The inputs.
        """
        return [Var("t_wall", (), "m", "tube wall thickness (smeared skin and stringers)", 3e-3),
                Var("nonstructural_mass_per_length", (), "kg/m", "nonstructural mass per length (beam's share)", 0.0)]

    def pointwise_outputs(self):
        """The per-point outputs: area, stiffness, compliance and mass per length (the beam's share).

        Returns
        -------
        list of Var
            The outputs.
        """
        return [Var("A", (), "m**2", "material area 2 pi R t (beam's share)"),
                Var("stiffness_csn", (3, 3), "N*m**2", "moment/curvature stiffness diag(EI, GJ, EI), csn"),
                Var("compliance_csn", (3,), "1/N", "diagonal of S: 1/GK, 1/EA, 1/GK"),
                Var("mass_per_length", (), "kg/m", "mass per length incl. nonstructural mass")]

    def pointwise_expressions(self, sym):
        """The outputs at one point as CasADi expressions (:func:`wingmdao.section.tube.tube_properties`).

        Parameters
        ----------
        sym : dict
            Input name -> SX symbol of the input's shape at one point.

        Returns
        -------
        dict
            Output name -> SX expression.
        """
        o = self.options
        p = tube_properties(o["radius"], sym["t_wall"], o["material"], o["fraction"],
                            sym["nonstructural_mass_per_length"])
        return {"A": p["A"], "stiffness_csn": ca.vertcat(*[ca.horzcat(*row) for row in p["stiffness_csn"]]),
                "compliance_csn": ca.vertcat(*p["compliance_csn"]), "mass_per_length": p["mass_per_length"]}

    def check_inputs(self, inputs):
        """Raise ``ValueError`` naming the station and allowed range of a wall thickness.

        Parameters
        ----------
        inputs : dict-like
            The component's inputs.
        """
        validate_tube(self.options["radius"], inputs["t_wall"], source=f"{self.pathname or 'TubeSection'}: ")


class TubeStress(PointwiseCasadiComponent):
    """Von Mises stress constraints ``g_vm = sigma_vm / sigma_y - 1`` of a thin tube at its
    :data:`~wingmdao.section.tube.TUBE_POINTS` over (num_times, num_stations)
    (:func:`wingmdao.section.tube.tube_stresses`).

    Inputs ``F_csn``, ``M_csn`` (nt, n, 3) in N, N*m (the beam's share, csn, about the centre);
    ``t_wall`` (n,) m. Output ``g_vm`` (nt, n, 8).
    """

    @staticmethod
    def points_per_station(family: str = "vm") -> int:
        """Constraint points per station (the last axis of ``g_vm``).

        Parameters
        ----------
        family : str
            Constraint family name (``vm``).

        Returns
        -------
        int
            Points per station.
        """
        return len(TUBE_POINTS)

    def initialize(self):
        super().initialize()
        declare_stress_grid_options(self.options)
        _declare_tube_options(self.options)

    def point_grid(self):
        """Leading shape of every variable: (num_times, num_stations).

        Returns
        -------
        tuple
            The grid shape.
        """
        return (self.options["num_times"], self.options["num_stations"])

    def expression_options(self):
        """The expressions depend on the material, radius and fraction (persisted)."""
        o = self.options
        return (o["material"], float(o["radius"]), float(o["fraction"]))

    def pointwise_inputs(self):
        """The per-point inputs: internal force and moment (csn) and the wall thickness per station.

        Returns
        -------
        list of Var
            The inputs.
        """
        return [Var("F_csn", (3,), "N", "internal force [F_c, F_s (axial), F_n] on the inboard part, csn", 0.0),
                Var("M_csn", (3,), "N*m", "internal moment [M_c, M_s (torsion), M_n] about the tube centre, csn", 0.0),
                Var("t_wall", (), "m", "tube wall thickness", 3e-3, per_last_axis=True)]

    def pointwise_outputs(self):
        """The per-point outputs: the von Mises constraints ``g_vm``.

        Returns
        -------
        list of Var
            The outputs.
        """
        return [Var("g_vm", (len(TUBE_POINTS),), None, "wall von Mises sigma_vm/sigma_y - 1 at the tube's points")]

    def pointwise_expressions(self, sym):
        """The outputs at one point as CasADi expressions.

        Parameters
        ----------
        sym : dict
            Input name -> SX symbol of the input's shape at one point.

        Returns
        -------
        dict
            Output name -> SX expression.
        """
        o = self.options
        s = tube_stresses(sym["F_csn"], sym["M_csn"], o["radius"], sym["t_wall"], o["fraction"])
        return {"g_vm": ca.vertcat(*s["sigma_vm"]) / o["material"].sigma_y - 1.0}

    def check_inputs(self, inputs):
        """Raise ``ValueError`` naming the station and allowed range of a wall thickness, or a load
        that is not finite.

        Parameters
        ----------
        inputs : dict-like
            The component's inputs.
        """
        source = f"{self.pathname or 'TubeStress'}: "
        validate_tube(self.options["radius"], inputs["t_wall"], source=source)
        for name in ("F_csn", "M_csn"):
            v = np.asarray(inputs[name])
            bad = np.argwhere(~np.isfinite(v))
            if bad.size:
                t, i, k = bad[0]
                raise ValueError(f"{source}{name}[{t}, {i}, {k}] = {v[t, i, k]} at time index {t}, station {i}; "
                                 "allowed range (-inf, inf) (finite)")
