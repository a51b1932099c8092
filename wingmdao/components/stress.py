"""Box-section stress recovery and constraints over (time, station) (Sec. 4.4.2)."""

from __future__ import annotations

import casadi as ca
import numpy as np

from wingmdao.components.pointwise import PointwiseCasadiComponent, Var
from wingmdao.components.section import CombinedJacobianMixin
from wingmdao.section.box import WALL_NAMES, validate_box
from wingmdao.components.section import SECTION_OUTPUTS
from wingmdao.stress.box_stress import (FAMILIES, SECTION_PROPERTIES, box_stresses, check_families,
                                       stress_constraints)
from wingmdao import DISSERTATION
from wingmdao.materials import Material

_FAMILY_DESC = {
    "vm": "mid-corner von Mises sigma_vm/sigma_y - 1, 8 points (Eq. 4.26)",
    "ss_tension": "corner axial +sigma/sigma_y - 1, 4 corners (Eq. 4.27)",
    "ss_compression": "corner axial -sigma/sigma_y - 1, 4 corners (Eq. 4.27)",
    "cent_pos": "flange-centre shear +tau/sigma_y - 1, 4 flanges (Eq. 4.28)",
    "cent_neg": "flange-centre shear -tau/sigma_y - 1, 4 flanges (Eq. 4.28)",
}


#: Defaults of the section-property inputs (nonzero where the stress divides by them).
SECTION_DEFAULTS = {"A": 1e-2, "Ixx": 1e-4, "Izz": 1e-3, "Qx": 1e-3, "Qz": 1e-3}


def declare_stress_grid_options(options) -> None:
    """The options every stress component declares: its (num_times, num_stations) grid and material.

    Parameters
    ----------
    options : openmdao.utils.options_dictionary.OptionsDictionary
        The component's options.
    """
    options.declare("num_times", types=int, lower=1, desc="number of time steps")
    options.declare("num_stations", types=int, lower=1, desc="number of beam stations")
    options.declare("material", types=Material, desc="wingmdao.materials.Material (sigma_y used)")


class BoxStress(CombinedJacobianMixin, PointwiseCasadiComponent):
    """Stresses and stress constraints of box sections on the grid (num_times, num_stations).

    Inputs: ``F_csn``, ``M_csn`` (nt, n, 3) in N and N*m (csn, about the box centre);
    per station (n,) in m: ``width``, ``height``, ``t_upper_skin``, ``t_lower_skin``,
    ``t_front_spar``, ``t_rear_spar``; with ``section_rotation=True`` also ``section_to_csn``
    (n, 3, 3), default identity (otherwise the section axes are the csn axes); with
    ``section_properties=True`` also the station's ``A``, ``c_ea``, ``n_ea``, ``Ixx``, ``Izz``,
    ``Ixz``, ``c_sc``, ``n_sc``, ``Qx``, ``Qz`` (the BoxSection outputs), which are then not
    recomputed at every time step.
    Outputs: ``g_<family>`` for each selected family (points: see wingmdao.stress.box_stress)
    and, unless ``output_stresses=False``, ``sigma_corner`` (nt, n, 4), ``sigma_vm`` (nt, n, 8),
    ``tau_cent`` (nt, n, 4) in Pa.
    """

    @staticmethod
    def points_per_station(family: str) -> int:
        """Constraint points per station of stress family ``family`` (last axis of ``g_<family>``).

        Parameters
        ----------
        family : str
            Constraint family name.

        Returns
        -------
        int
            Points per station.
        """
        return FAMILIES[family]

    def initialize(self):
        super().initialize()
        self.cite = DISSERTATION  # OpenMDAO lists it in its citations report
        declare_stress_grid_options(self.options)
        self.options.declare("families", default=tuple(FAMILIES), types=tuple,
                             desc=f"constraint families to output, from {', '.join(FAMILIES)}")
        self.options.declare("output_stresses", default=True, types=bool,
                             desc="also output sigma_corner, sigma_vm, tau_cent (Pa); False halves the Jacobian")
        self.options.declare("section_properties", default=False, types=bool,
                             desc="take A, c_ea, n_ea, Ixx, Izz, Ixz, c_sc, n_sc, Qx, Qz per station as inputs "
                                  "(the BoxSection outputs) instead of recomputing them at every time step")
        self.options.declare("section_rotation", default=False, types=bool,
                             desc="add the input section_to_csn and rotate the loads to the section axes")

    def point_grid(self):
        """Leading shape of every variable: (num_times, num_stations).

        Returns
        -------
        tuple
            The grid shape.
        """
        return (self.options["num_times"], self.options["num_stations"])

    def setup(self):
        check_families(self.options["families"])
        super().setup()

    def expression_options(self):
        """Options the expressions depend on (persisted, wingmdao.utils.function_store)."""
        o = self.options
        return (o["material"], tuple(o["families"]), o["output_stresses"], o["section_properties"],
                o["section_rotation"])

    def pointwise_inputs(self):
        """The per-point inputs: internal force and moment (csn) per time and station, box dimensions and wall thicknesses per station.

        Returns
        -------
        list of Var
            The inputs.
        """
        n = self.options["num_stations"]
        eye = np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
        return [
            Var("F_csn", (3,), "N", "internal force [F_c, F_s (axial), F_n] on the inboard part, csn", 0.0),
            Var("M_csn", (3,), "N*m", "internal moment [M_c, M_s (torsion), M_n] about the box centre, csn", 0.0),
            Var("width", (), "m", "box outer width (chordwise)", per_last_axis=True),
            Var("height", (), "m", "box outer height (normal)", 0.3, per_last_axis=True),
            Var("t_upper_skin", (), "m", "upper skin thickness", 0.01, per_last_axis=True),
            Var("t_lower_skin", (), "m", "lower skin thickness", 0.01, per_last_axis=True),
            Var("t_front_spar", (), "m", "front spar web thickness", 0.01, per_last_axis=True),
            Var("t_rear_spar", (), "m", "rear spar web thickness", 0.01, per_last_axis=True),
        ] + ([Var("section_to_csn", (3, 3), None, "rotation R from the section axes to csn", eye, per_last_axis=True)]
             if self.options["section_rotation"] else []) + (
            [Var(name, (), units, desc, SECTION_DEFAULTS.get(name, 0.0), per_last_axis=True)
             for name, _, units, desc in SECTION_OUTPUTS if name in SECTION_PROPERTIES]
            if self.options["section_properties"] else [])

    def pointwise_outputs(self):
        """The per-point outputs: the stresses (with ``output_stresses``) and the constraints ``g_<family>``.

        Returns
        -------
        list of Var
            The outputs.
        """
        out = [
            Var("sigma_corner", (4,), "Pa", "outer-corner axial stress (Eq. 4.19 generalised)"),
            Var("sigma_vm", (8,), "Pa", "mid-corner von Mises stress, skin then spar per corner"),
            Var("tau_cent", (4,), "Pa", "flange-centre shear: upper, lower skin, front, rear spar"),
        ] if self.options["output_stresses"] else []
        return out + [Var(f"g_{f}", (FAMILIES[f],), None, _FAMILY_DESC[f]) for f in self.options["families"]]

    def pointwise_expressions(self, sym):
        """The outputs at one point as CasADi expressions: stresses and constraints of :func:`wingmdao.stress.box_stress.box_stresses`.

        Parameters
        ----------
        sym : dict
            Input name -> SX symbol of the input's shape at one point.

        Returns
        -------
        dict
            Output name -> SX expression.
        """
        stresses = box_stresses(sym["F_csn"], sym["M_csn"], sym["width"], sym["height"],
                                *(sym[k] for k in WALL_NAMES), section_to_csn=sym.get("section_to_csn"),
                                section={k: sym[k] for k in SECTION_PROPERTIES} if self.options["section_properties"] else None)
        g = stress_constraints(stresses, self.options["material"].sigma_y, self.options["families"])
        out = {k: ca.vertcat(*v) for k, v in stresses.items()} if self.options["output_stresses"] else {}
        out.update({f"g_{f}": ca.vertcat(*v) for f, v in g.items()})
        return out

    def check_inputs(self, inputs):
        """Raise ``ValueError`` naming the input, point and allowed range when a box dimension is invalid or an internal load is not finite.

        Parameters
        ----------
        inputs : dict-like
            The component's inputs.
        """
        source = f"{self.pathname or 'BoxStress'}: "
        validate_box(inputs["width"], inputs["height"], *(inputs[k] for k in WALL_NAMES), source=source)
        for name, units in (("F_csn", "N"), ("M_csn", "N*m")):
            v = np.asarray(inputs[name])
            bad = np.argwhere(~np.isfinite(v))
            if bad.size:
                t, i, k = bad[0]
                raise ValueError(f"{source}{name}[{t}, {i}, {k}] = {v[t, i, k]} {units} at time index {t}, "
                                 f"station {i}; allowed range (-inf, inf) {units} (finite)")
