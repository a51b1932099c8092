"""CalculiX (``ccx``) driver: find the solver, write Abaqus-style decks, run them in a temporary
folder and read the ``.dat`` results.

CalculiX: G. Dhondt, "CalculiX CrunchiX User's Manual", version 2.20, 2022 (the input keywords
used here: ``*NODE``, ``*ELEMENT``, ``*NSET``, ``*ELSET``, ``*MATERIAL``/``*ELASTIC``/``*DENSITY``,
``*SHELL SECTION``, ``*SOLID SECTION``, ``*MASS``, ``*BOUNDARY``, ``*EQUATION``, ``*STEP[, NLGEOM]``,
``*STATIC``, ``*FREQUENCY``, ``*BUCKLE``, ``*CLOAD``, ``*NODE PRINT``).
The solver is an optional dependency: a missing ``ccx`` raises :class:`CalculixNotFound` with
the install command and nothing is imported at package import time.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
import time

import numpy as np

INSTALL_HINT = "install with: apt-get install -y calculix-ccx"


class CalculixNotFound(RuntimeError):
    """The CalculiX solver ``ccx`` is not on PATH."""


class CalculixError(RuntimeError):
    """ccx ran but reported an error or wrote no results."""


def find_ccx() -> str:
    """Path of ``ccx`` (``$WINGMDAO_CCX`` if set, else PATH); CalculixNotFound otherwise."""
    exe = os.environ.get("WINGMDAO_CCX") or shutil.which("ccx")
    if not exe or not (os.path.isfile(exe) or shutil.which(exe)):
        raise CalculixNotFound(f"the CalculiX solver 'ccx' was not found on PATH; {INSTALL_HINT}")
    return exe


def run_deck(deck: str, job: str = "job", keep_dir: str | None = None, timeout: float = 1800.0) -> dict:
    """Run ``ccx -i job`` on the deck text in a temporary folder (or ``keep_dir``).

    Returns ``{"dat": text of job.dat, "log": solver output, "time": wall seconds, "dir": folder
    or None}``. CalculixError when ccx fails or prints ``*ERROR``.

    Parameters
    ----------
    deck : str
        Input deck text.
    job : str, optional
        Job name (file stem).
    keep_dir : str, path-like or None, optional
        Folder to keep the CalculiX files in; None for a temporary one.
    timeout : float, optional
        Wall-clock limit (s).

    Returns
    -------
    dict
        ``dat``, ``log``, ``time`` (s) and ``dir``.
    """
    exe = find_ccx()
    tmp = None
    if keep_dir is None:
        tmp = tempfile.TemporaryDirectory(prefix="wingmdao-ccx-")
        folder = tmp.name
    else:
        folder = keep_dir
        os.makedirs(folder, exist_ok=True)
    try:
        with open(os.path.join(folder, job + ".inp"), "w", encoding="ascii") as fh:
            fh.write(deck)
        env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "1"))
        t0 = time.perf_counter()
        proc = subprocess.run([exe, "-i", job], cwd=folder, capture_output=True, text=True,
                              timeout=timeout, env=env)
        elapsed = time.perf_counter() - t0
        log = proc.stdout + proc.stderr
        dat_path = os.path.join(folder, job + ".dat")
        if proc.returncode != 0 or "*ERROR" in log or not os.path.exists(dat_path):
            tail = "\n".join(log.strip().splitlines()[-25:])
            raise CalculixError(f"ccx failed (exit {proc.returncode}) on {job}.inp:\n{tail}")
        with open(dat_path, encoding="ascii", errors="replace") as fh:
            dat = fh.read()
    finally:
        if tmp is not None:
            tmp.cleanup()
    return {"dat": dat, "log": log, "time": elapsed, "dir": keep_dir}


_FLOAT = r"[-+]?\d*\.?\d+(?:[eE][-+]?\d+)?"


def parse_dat(text: str) -> dict:
    """Read a ccx ``.dat`` file: ``{"displacements": {NSET: {node: (ux, uy, uz)}},
    "stresses": {element: (points, 6) array sxx, syy, szz, sxy, sxz, syz (Pa)},
    "frequencies_hz": array, "buckling_factors": array (in mode order)}`` (the last time of
    each set when a step prints several).

    Parameters
    ----------
    text : str
        Contents of a ccx ``.dat`` file.

    Returns
    -------
    dict
        ``displacements``, ``stresses``, ``frequencies_hz`` and ``buckling_factors``.
    """
    disp: dict = {}
    stress: dict = {}
    freqs: list = []
    factors: list = []
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if re.match(r"\s*stresses \(elem, integ.pnt.,sxx,syy,szz,sxy,sxz,syz\) for set", line):
            i = _read_stress_block(lines, i + 1, stress)
            continue
        m = re.match(r"\s*displacements \(vx,vy,vz\) for set (\S+) and time", line)
        if m:
            disp[m.group(1).upper()], i = _vector_block(lines, i + 1)
            continue
        if "E I G E N V A L U E   O U T P U T" in line:
            i += 1
            # header lines, then rows: mode, eigenvalue, omega (rad/time), f (cycles/time), imag
            while i < len(lines) and not re.match(r"\s*\d+\s+" + _FLOAT, lines[i]):
                i += 1
            while i < len(lines) and re.match(r"\s*\d+\s+" + _FLOAT, lines[i]):
                parts = lines[i].split()
                freqs.append(float(parts[3]))
                i += 1
            continue
        if "B U C K L I N G   F A C T O R   O U T P U T" in line:
            i += 1
            # header lines (MODE NO, BUCKLING FACTOR), then rows: mode, factor
            while i < len(lines) and not re.match(r"\s*\d+\s+" + _FLOAT + r"\s*$", lines[i]):
                i += 1
            while i < len(lines) and re.match(r"\s*\d+\s+" + _FLOAT + r"\s*$", lines[i]):
                factors.append(float(lines[i].split()[1]))
                i += 1
            continue
        i += 1
    return {"displacements": disp, "stresses": {e: np.array(v) for e, v in stress.items()},
            "frequencies_hz": np.array(freqs), "buckling_factors": np.array(factors)}


def mode_displacements(dat_text: str, mode: int, nset: str) -> dict:
    """``{node: (ux, uy, uz)}`` of the node set ``nset`` in eigenmode ``mode`` (1-based) of a
    ``*BUCKLE`` or ``*FREQUENCY`` step: the .dat prints each mode's blocks after the line
    'E I G E N V A L U E   N U M B E R  k' (a ``*BUCKLE`` step prints the pre-buckling state first).
    Empty when the mode or the set is not printed.

    Parameters
    ----------
    dat_text : str
        Contents of a ccx ``.dat`` file.
    mode : int
        Mode number, 1-based.
    nset : str
        Node set name.

    Returns
    -------
    dict
        Node id -> (ux, uy, uz) (m, mode-shape scale).
    """
    lines = dat_text.splitlines()
    head = f"displacements (vx,vy,vz) for set {nset}".lower()
    i = next((k for k, line in enumerate(lines)
              if re.match(r"\s*E I G E N V A L U E\s+N U M B E R\s+" + str(int(mode)) + r"\s*$", line)), None)
    out: dict = {}
    if i is None:
        return out
    i += 1
    while i < len(lines) and not lines[i].strip().lower().startswith(head):
        if re.match(r"\s*E I G E N V A L U E\s+N U M B E R\s+\d+\s*$", lines[i]):
            return out      # the next mode began: this one printed no such set
        i += 1
    out.update(_vector_block(lines, i + 1)[0])
    return out


def _vector_block(lines, i):
    """``({node: (x, y, z)}, next line index)``: the rows of node ids and three values of a .dat
    block whose header is the line before ``i`` (blank lines first, then rows until a blank line)."""
    block = {}
    while i < len(lines) and not lines[i].strip():
        i += 1
    while i < len(lines) and lines[i].strip():
        parts = lines[i].split()
        try:
            block[int(parts[0])] = tuple(float(v) for v in parts[1:4])
        except (ValueError, IndexError):
            break
        i += 1
    return block, i


def _read_stress_block(lines, i, out) -> int:
    """Rows 'elem, integration point, sxx, syy, szz, sxy, sxz, syz' of an *EL PRINT S block into
    ``out[elem]`` (a later time replaces an earlier one); returns the next line index."""
    while i < len(lines) and not lines[i].strip():
        i += 1
    seen = set()
    while i < len(lines) and lines[i].strip():
        parts = lines[i].split()
        try:
            e, vals = int(parts[0]), [float(v) for v in parts[2:8]]
        except (ValueError, IndexError):
            break
        if e not in seen:
            out[e] = []
            seen.add(e)
        out[e].append(vals)
        i += 1
    return i


# --------------------------------------------------------------------------- deck writing
def _rows(values, per_line=8):
    vals = list(values)
    return "\n".join(", ".join(str(v) for v in vals[k:k + per_line]) for k in range(0, len(vals), per_line))


def _element_line(eid, conn) -> str:
    """An element data line; more than 15 nodes continue on the next line (at most 16 entries
    per line, the manual's *ELEMENT rule)."""
    vals = [str(eid)] + [str(n) for n in conn]
    return ",\n".join(", ".join(vals[k:k + 16]) for k in range(0, len(vals), 16))


def distributing_forces(points, weights, centre, force, moment) -> np.ndarray:
    """Nodal forces (n, 3) of a distributing coupling: the force and moment at ``centre`` spread
    over the coupling nodes in proportion to the weights, ``f_i = w_i [F / W + (J^-1 M') x r_i]``,
    r_i from the weighted centroid, ``J = sum w_i (|r_i|^2 I - r_i r_i^T)``, ``M' = M + (c - x_c) x F``.
    This is the distributing-coupling law of Abaqus ("Coupling constraints", Abaqus Analysis
    User's Guide 2016, Sec. 35.3.2): the nodal forces are statically equivalent to (F, M).

    Parameters
    ----------
    points : array_like
        (n, 3) coupling node positions (m).
    weights : array_like
        (n,) node weights.
    centre : array_like
        (3,) reference point of the load (m).
    force : array_like
        (3,) force (N).
    moment : array_like
        (3,) moment about ``centre`` (N m).

    Returns
    -------
    numpy.ndarray
        (n, 3) nodal forces (N).
    """
    p = np.asarray(points, float)
    w = np.asarray(weights, float)
    W = w.sum()
    xc = (w[:, None] * p).sum(0) / W
    r = p - xc
    F, M = np.asarray(force, float), np.asarray(moment, float)
    Mc = M + np.cross(np.asarray(centre, float) - xc, F)
    J = sum(wi * (ri @ ri * np.eye(3) - np.outer(ri, ri)) for wi, ri in zip(w, r))
    # a planar ring has J regular; guard a degenerate (collinear) set with a pseudo-inverse
    a = np.linalg.pinv(J) @ Mc
    return w[:, None] * (F / W + np.cross(a, r))


class Deck:
    """A small Abaqus/CalculiX input builder (nodes 1-based, SI units).

    Parameters
    ----------
    heading : str, optional
        ``*HEADING`` text.
    """

    def __init__(self, heading="wingmdao"):
        self.heading = heading
        self.nodes: dict[int, tuple] = {}
        self.elements: list[tuple[str, str, dict]] = []   # (type, elset, {id: conn})
        self.nsets: dict[str, list] = {}
        self.elsets: dict[str, list] = {}
        self.sections: list[str] = []
        self.materials: list[str] = []
        self.boundary: list[tuple] = []
        self.model_extra: list[str] = []

    def add_nodes(self, coords, start=None) -> np.ndarray:
        """Add nodes and return their ids.

        Parameters
        ----------
        coords : array_like
            (k, 3) node coordinates (m).
        start : int or None, optional
            First node id; None continues after the largest id.

        Returns
        -------
        numpy.ndarray
            The new node ids.
        """
        start = (max(self.nodes) + 1) if (start is None and self.nodes) else (start or 1)
        ids = np.arange(start, start + len(coords))
        for i, c in zip(ids, np.asarray(coords, float)):
            self.nodes[int(i)] = tuple(c)
        return ids

    def next_element_id(self):
        """The next free element id.

        Returns
        -------
        int
            One more than the largest element id (1 for an empty deck).
        """
        ids = [max(b) for _, _, b in self.elements if b]
        return (max(ids) + 1) if ids else 1

    def add_elements(self, etype, elset, conns) -> list:
        """Add a block of elements of one type to an element set.

        Parameters
        ----------
        etype : str
            Element type, e.g. ``"S8R"``.
        elset : str
            Element set name.
        conns : sequence of sequence of int
            Node ids of each element.

        Returns
        -------
        list of int
            The new element ids.
        """
        e0 = self.next_element_id()
        block = {e0 + k: tuple(int(n) for n in c) for k, c in enumerate(conns)}
        self.elements.append((etype, elset, block))
        return list(block)

    def material(self, name, material):
        """An isotropic ``*MATERIAL`` from a :class:`wingmdao.materials.Material`.

        Parameters
        ----------
        name : str
            Material name in the deck.
        material : Material
            Isotropic material (E, nu, rho).
        """
        self.isotropic(name, material.E, material.nu, material.rho)

    def isotropic(self, name, E, nu, rho=None):
        """An isotropic linear elastic ``*MATERIAL`` (Pa); ``*DENSITY`` (kg/m^3) only when ``rho`` is given.

        Parameters
        ----------
        name : str
            Material name in the deck.
        E : float
            Young's modulus (Pa).
        nu : float
            Poisson's ratio (-).
        rho : float or None, optional
            Density (kg/m^3).
        """
        text = f"*MATERIAL, NAME={name}\n*ELASTIC\n{E:.10g}, {nu:.10g}"
        if rho is not None:
            text += f"\n*DENSITY\n{rho:.10g}"
        self.materials.append(text)

    def text(self, steps: list[str]) -> str:
        """The deck's text: model data, then ``steps``.

        Parameters
        ----------
        steps : list of str
            Step blocks (:func:`static_step`, :func:`frequency_step`, :func:`buckle_step`).

        Returns
        -------
        str
            The deck text.
        """
        out = [f"*HEADING\n{self.heading}", "*NODE"]
        out += [f"{i}, {c[0]:.12g}, {c[1]:.12g}, {c[2]:.12g}" for i, c in sorted(self.nodes.items())]
        for etype, elset, block in self.elements:
            out.append(f"*ELEMENT, TYPE={etype}, ELSET={elset}")
            out += [_element_line(e, c) for e, c in block.items()]
        for name, ids in self.nsets.items():
            out.append(f"*NSET, NSET={name}\n{_rows(ids)}")
        for name, ids in self.elsets.items():
            out.append(f"*ELSET, ELSET={name}\n{_rows(ids)}")
        out += self.materials + self.sections + self.model_extra
        if self.boundary:
            out.append("*BOUNDARY")
            out += [f"{n}, {a}, {b}" for n, a, b in self.boundary]
        out += steps
        return "\n".join(out) + "\n"


def static_step(cloads, print_nsets, nlgeom=False, increments=None, stress_elsets=()) -> str:
    """A ``*STATIC`` step with nodal loads [(node, dof, value)], ``*NODE PRINT`` U of the node sets and
    ``*EL PRINT`` S (integration-point stresses) of the element sets.

    Parameters
    ----------
    cloads : sequence of tuple
        ``(node, dof, value)`` nodal loads (N).
    print_nsets : sequence of str
        Node sets whose displacements are printed.
    nlgeom : bool, optional
        Geometrically nonlinear step.
    increments : int or None, optional
        Fixed increments of a nonlinear step; None for the default.
    stress_elsets : sequence of str, optional
        Element sets whose stresses are printed.

    Returns
    -------
    str
        The step text.
    """
    head = "*STEP" + (", NLGEOM, INC=1000" if nlgeom else "")
    s = [head, "*STATIC" if not (nlgeom and increments) else f"*STATIC\n{1.0 / increments:g}, 1.0"]
    if cloads:
        s.append("*CLOAD")
        s += [f"{n}, {d}, {v:.12g}" for n, d, v in cloads if v != 0.0]
    s += [f"*NODE PRINT, NSET={n}\nU" for n in print_nsets]
    s += [f"*EL PRINT, ELSET={e}\nS" for e in stress_elsets]
    s.append("*END STEP")
    return "\n".join(s)


def frequency_step(modes: int) -> str:
    """A ``*FREQUENCY`` step extracting the lowest ``modes`` eigenfrequencies (printed to .dat).

    Parameters
    ----------
    modes : int
        Number of eigenfrequencies.

    Returns
    -------
    str
        The step text.
    """
    return f"*STEP\n*FREQUENCY\n{int(modes)}\n*END STEP"


def buckle_step(modes: int, cloads, print_nsets=()) -> str:
    """A ``*BUCKLE`` step: the lowest ``modes`` buckling factors of the nodal loads [(node, dof,
    value)] (printed to .dat), with ``*NODE PRINT`` U of the node sets (the mode shapes).

    Parameters
    ----------
    modes : int
        Number of buckling factors.
    cloads : sequence of tuple
        ``(node, dof, value)`` nodal loads (N).
    print_nsets : sequence of str, optional
        Node sets whose mode shapes are printed.

    Returns
    -------
    str
        The step text.
    """
    s = [f"*STEP\n*BUCKLE\n{int(modes)}", "*CLOAD"]
    s += [f"{n}, {d}, {v:.12g}" for n, d, v in cloads if v != 0.0]
    s += [f"*NODE PRINT, NSET={n}\nU" for n in print_nsets]
    s.append("*END STEP")
    return "\n".join(s)


def quadratic_edge_forces(coords, intensity) -> np.ndarray:
    """Consistent nodal forces of a line load along a row of quadratic element edges: ``coords``
    (2n+1,) positions along the line (end, mid, end, mid, ...), ``intensity`` (n,) load per length,
    constant on each edge; each edge of length L gives L q (1, 4, 1) / 6 to its three nodes.

    Parameters
    ----------
    coords : array_like
        (2 n + 1,) node positions along the line (m).
    intensity : array_like
        (n,) load per length on each edge (N/m).

    Returns
    -------
    numpy.ndarray
        (2 n + 1,) nodal forces (N).
    """
    s = np.asarray(coords, float)
    q = np.broadcast_to(np.asarray(intensity, float), ((len(s) - 1) // 2,))
    f = np.zeros(len(s))
    for k, qk in enumerate(q):
        L = s[2 * k + 2] - s[2 * k]
        f[2 * k:2 * k + 3] += L * qk * np.array([1.0, 4.0, 1.0]) / 6.0
    return f
