"""The App. D.1 box on the OpenMDAO sizing chain (section -> beam -> internal loads -> stress -> KS
of :class:`wingmdao.groups.wing.WingSizing`) with one tip-load case: used by ``wingmdao run
wing-box`` and by the Sec. 4.7.2 sizing studies (:mod:`wingmdao.cases.wing_box.sizing`).

Design variables are the four wall thicknesses of the *beam-normal* section at every beam node
(the default mesh of one element per segment puts the nodes at CS1..CS4).
"""

from __future__ import annotations

import numpy as np

from wingmdao.beam.geometry import WingGeometry, polyline_beam
from wingmdao.cases.wing_box.geometry import HEIGHTS, geometry_data, section_centres
from wingmdao.cases import check_step_count
from wingmdao.groups.load_case import LoadCase


def wing_geometry(name: str, elements_per_segment=(1, 1, 1)):
    """The box as a :class:`wingmdao.sizing.WingGeometry` (beam-normal width/height per node).

    Parameters
    ----------
    name : str
        Table D.2 geometry (a key of ``GEOMETRIES``).
    elements_per_segment : sequence of 3 int, optional
        Beam elements in each of the three segments CS1-CS2, CS2-CS3, CS3-CS4.

    Returns
    -------
    geometry : wingmdao.sizing.WingGeometry
        Nodes (m), orientations and beam-normal width and height (m) per node.
    key_nodes : list of int
        Node indices of CS1..CS4.
    cos_sweep, cos_dihedral : ndarray
        Per node, the factors that take streamwise-cut chordwise/vertical dimensions to the
        normal cut (:func:`streamwise_to_normal`).
    """
    g = geometry_data(name)
    geo = polyline_beam(section_centres(name), elements_per_segment)
    T = geo.csn_axes()
    s = T[:, 1]
    cos_sweep, cos_dih = np.hypot(s[:, 1], s[:, 2]), np.hypot(s[:, 0], s[:, 1])
    width = geo.interpolate(g["widths"]) * cos_sweep
    height = geo.interpolate(HEIGHTS) * cos_dih
    wg = WingGeometry(node_positions=geo.node_positions, node_euler_angles=geo.node_euler_angles,
                      width=width, height=height, span_coordinate=geo.node_positions[:, 1])
    return wg, geo.key_nodes, cos_sweep, cos_dih


def tip_load_case(name: str, num_nodes: int, tip_force, tip_moment, families, *, time=None,
                  gravity=False, ramp_time=0.0):
    """A :class:`LoadCase` with a tip force/moment (body axes) at the last node.

    Parameters
    ----------
    name : str
        Load case name.
    num_nodes : int
        Beam nodes.
    tip_force : sequence of 3 float
        Tip force (N), body axes.
    tip_moment : sequence of 3 float
        Tip moment (N m), body axes.
    families : sequence of str
        Stress families constrained.
    time : ndarray, optional
        Time grid (s); None: a static case. Otherwise the load is zero at ``time[0]`` (the
        static initial state is the unloaded jig) and applied suddenly for t > 0
        (``ramp_time`` = 0), or raised linearly over ``ramp_time``, then held constant.
    gravity : bool or float, optional
        Self weight: False none, True 9.81 m/s^2, a number that gravity (m/s^2) along -z.
    ramp_time : float, optional
        Time over which a dynamic load rises to its full value (s).

    Returns
    -------
    wingmdao.groups.load_case.LoadCase
        The load case.
    """
    if not (np.isfinite(ramp_time) and ramp_time >= 0):
        raise ValueError(f"ramp time = {ramp_time} s; allowed range [0, inf) s")
    t = np.zeros(1) if time is None else np.asarray(time, dtype=float)
    if t.size == 1:
        on = np.ones(1)
    elif ramp_time > 0:
        on = np.clip(t / ramp_time, 0.0, 1.0)
    else:
        on = (t > 0.0).astype(float)
    pf = np.zeros((t.size, num_nodes, 3))
    pm = np.zeros((t.size, num_nodes, 3))
    pf[:, -1] = np.outer(on, tip_force)
    pm[:, -1] = np.outer(on, tip_moment)
    forcing = {"point_force": pf, "point_moment": pm}
    if gravity is not None and gravity is not False:  # True: 9.81 m/s^2; a number: that gravity (m/s^2)
        forcing["gravity"] = np.array([0.0, 0.0, -(9.81 if gravity is True else float(gravity))])
    kind = ("static" if t.size == 1 else f"ramped over {ramp_time:g} s, {t[-1]:g} s" if ramp_time > 0
            else f"suddenly applied, {t[-1]:g} s")
    return LoadCase(name, t, forcing, tuple(families), f"tip load {list(tip_force)} N, "
                    f"{list(tip_moment)} N*m ({kind})")


def time_grid(t_final: float, dt: float) -> np.ndarray:
    """Uniform time grid from 0 to ``t_final``.

    Parameters
    ----------
    t_final : float
        End time (s).
    dt : float
        Time step (s), 0 < dt <= t_final / 2.

    Returns
    -------
    ndarray
        The times (s).

    Raises
    ------
    ValueError
        Values outside the range, or too many steps (:func:`wingmdao.cases.check_step_count`).
    """
    if not (np.isfinite(t_final) and np.isfinite(dt) and t_final > 0 and 0 < dt <= t_final / 2):
        raise ValueError(f"--t-final ({t_final} s) and --dt ({dt} s): allowed 0 < dt <= t_final / 2")

    check_step_count(t_final, dt)
    return np.arange(0.0, t_final + 0.5 * dt, dt)
