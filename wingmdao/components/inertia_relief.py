"""Static equilibrium of a free joined structure with inertia relief as an OpenMDAO implicit component.

:class:`InertiaRelief` wraps :func:`wingmdao.beam.joints.solve_inertia_relief`: the free structure
(a :class:`~wingmdao.beam.joints.JoinedBeamSystem`, e.g. the stick model of a half aircraft) is in
equilibrium in body axes that accelerate uniformly, the accelerations (``accelerations``, keys of
:data:`~wingmdao.beam.joints.FRAME_ACCELERATIONS`) being unknowns beside the states, held by as
many statically determinate ``supports`` (``(beam, node, "x" | "y" | "z")``, that body-axes
displacement of the node at the jig). Residuals::

    R(x, 0, p, q(a)) = 0,          C x - C x_jig(p) = 0,

the structure's static residual with the accelerations ``a`` in its forcing, and one support row
per acceleration (docs/stick-model.md, Free flight). Inputs are the system's parameter blocks and
its forcing blocks under the system's names (``wing_stiffness_csn``, ``lumped_mass``,
``wing_point_force``, ``gravity``, ...) except ``frame_acceleration`` and
``frame_angular_acceleration`` (their components other than the unknowns are zero); outputs the
state ``states`` and one output per acceleration (``frame_ax``, ``frame_az``, ``frame_alpha_y``).
Partials are the system's CasADi Jacobians (exact sparsity of ``jacobian_patterns``); the Newton
solve and the linear solves (forward and reverse) use one sparse LU of the bordered matrix
``[[dR/dx, dR/da], [C, 0]]``.
"""

from __future__ import annotations

import numpy as np
import openmdao.api as om
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wingmdao.beam.joints import FRAME_ACCELERATIONS, HALF_AIRCRAFT_ACCELERATIONS, solve_inertia_relief
from wingmdao.beam.residual import STATE_BLOCKS
from wingmdao.timemarch.system import ResidualSystem, layout

#: The forcing blocks whose components are the inertia-relief unknowns (not inputs).
FRAME_ACCELERATION_BLOCKS = ("frame_acceleration", "frame_angular_acceleration")
_XYZ = "xyz"


def acceleration_output(name: str) -> str:
    """The output name of the acceleration ``name`` (a key of ``FRAME_ACCELERATIONS``).

    Parameters
    ----------
    name : str
        ``"ax"``, ``"az"``, ``"alpha_y"``, ...

    Returns
    -------
    str
        ``"frame_<name>"``.
    """
    return f"frame_{name}"


def support_matrices(system, supports):
    """The support rows of :func:`~wingmdao.beam.joints.solve_inertia_relief`.

    Parameters
    ----------
    system : JoinedBeamSystem
        The joined structure.
    supports : sequence of (str, int, str)
        ``(beam, node, component)``, component ``"x"``, ``"y"`` or ``"z"`` (body axes).

    Returns
    -------
    C : scipy.sparse.csr_matrix
        (k, n_state): the supports' body-axes displacement components of the state.
    Cp : scipy.sparse.csr_matrix
        (k, n_param): the same components of the jig positions (``<beam>_node_positions``), so that
        ``C x_jig(p) = Cp p``.
    """
    play = layout(system.param_specs)
    rows, cols, pcols, vals = [], [], [], []
    for k, (name, node, comp) in enumerate(supports):
        if comp not in _XYZ:
            raise ValueError(f"support {(name, node, comp)}: component must be 'x', 'y' or 'z' (body axes), "
                             f"got {comp!r}")
        beam = system.beam(name)
        i = int(node) % beam.num_nodes
        i0 = system.node_index(name, i) + STATE_BLOCKS["r"].start
        direction = np.asarray(beam.rotation, dtype=float) @ np.eye(3)[_XYZ.index(comp)]
        for c in range(3):
            if direction[c] != 0.0:
                rows.append(k)
                cols.append(i0 + c)
                pcols.append(play[f"{name}_node_positions"].start + 3 * i + c)
                vals.append(direction[c])
    k = len(supports)
    return (sp.csr_matrix((vals, (rows, cols)), shape=(k, system.n_state)),
            sp.csr_matrix((vals, (rows, pcols)), shape=(k, system.n_param)))


class InertiaRelief(om.ImplicitComponent):
    """Inertia-relief equilibrium of a free joined structure (module docstring).

    Options: ``system`` (the joined structure), ``supports``, ``accelerations``, ``param_values``
    and ``forcing_values`` (packed defaults of the inputs), ``state_name``, ``rtol``, ``max_iter``.
    """

    def initialize(self):
        self.options.declare("system", types=ResidualSystem, recordable=False,
                             desc="the free joined structure (wingmdao.beam.joints.JoinedBeamSystem)")
        self.options.declare("supports", types=(list, tuple),
                             desc="statically determinate supports (beam, node, 'x'|'y'|'z'), one per acceleration")
        self.options.declare("accelerations", default=HALF_AIRCRAFT_ACCELERATIONS, types=(list, tuple),
                             desc="unknown accelerations of the body axes (keys of FRAME_ACCELERATIONS)")
        self.options.declare("param_values", default=None, allow_none=True, types=np.ndarray,
                             desc="packed parameters: the inputs' default values (None: zeros)")
        self.options.declare("forcing_values", default=None, allow_none=True, types=np.ndarray,
                             desc="packed forcing: the inputs' default values (None: zeros)")
        self.options.declare("state_name", default="states", types=str, desc="name of the state output")
        self.options.declare("rtol", default=1e-10, lower=0.0, types=float, desc="Newton tolerance relative to the first residual")
        self.options.declare("max_iter", default=30, types=int, lower=1, desc="Newton iterations at most")

    def setup(self):
        s = self.options["system"]
        acc = tuple(self.options["accelerations"])
        bad = [a for a in acc if a not in FRAME_ACCELERATIONS]
        if bad or len(set(acc)) != len(acc):
            raise ValueError(f"{self.msginfo}: accelerations must be distinct names of {list(FRAME_ACCELERATIONS)}, "
                             f"got {list(acc)}")
        if len(self.options["supports"]) != len(acc):
            raise ValueError(f"{self.msginfo}: {len(self.options['supports'])} supports for {len(acc)} accelerations; "
                             "a statically determinate support has one per acceleration")
        self._C, self._Cp = support_matrices(s, self.options["supports"])
        p0 = self.options["param_values"]
        q0 = self.options["forcing_values"]
        p0 = np.zeros(s.n_param) if p0 is None else np.asarray(p0, dtype=float)
        q0 = np.zeros(s.n_forcing) if q0 is None else np.asarray(q0, dtype=float)
        if p0.size != s.n_param or q0.size != s.n_forcing:
            raise ValueError(f"{self.msginfo}: param_values has {p0.size} entries, forcing_values {q0.size}; the "
                             f"system has {s.n_param} parameters and {s.n_forcing} forcing entries")
        self._play, self._qlay = layout(s.param_specs), layout(s.forcing_specs)
        self._pins = [sp_ for sp_ in s.param_specs if sp_.size > 0]
        self._qins = [sp_ for sp_ in s.forcing_specs if sp_.size > 0 and sp_.name not in FRAME_ACCELERATION_BLOCKS]
        for spec in self._pins:
            self.add_input(spec.name, val=p0[self._play[spec.name]].reshape(spec.shape or (1,)), units=spec.units,
                           desc=spec.desc or spec.name)
        for spec in self._qins:
            self.add_input(spec.name, val=q0[self._qlay[spec.name]].reshape(spec.shape or (1,)), units=spec.units,
                           desc=spec.desc or spec.name)
        name = self.options["state_name"]
        self.add_output(name, val=s.jig_state(p0), units=None,
                        desc="joined state: every beam's r, theta, F, M, u, omega per node, joint and symmetry loads (SI)")
        self._acc_cols = [self._qlay[FRAME_ACCELERATIONS[a][0]].start + FRAME_ACCELERATIONS[a][1] for a in acc]
        for a in acc:
            block = FRAME_ACCELERATIONS[a][0]
            self.add_output(acceleration_output(a), val=0.0, units="m/s**2" if block == "frame_acceleration"
                            else "rad/s**2", desc=f"body axes' {block.replace('_', ' ')} component {a}")
        self._lu = None

    def setup_partials(self):
        s = self.options["system"]
        pat = s.jacobian_patterns()
        name = self.options["state_name"]
        rx, cx, _ = pat["x"]
        self.declare_partials(name, name, rows=rx, cols=cx)
        rq, cq, _ = pat["q"]
        for specs, lay, (r, c) in ((self._pins, self._play, pat["p"][:2]), (self._qins, self._qlay, (rq, cq))):
            for spec in specs:
                sl = lay[spec.name]
                m = (c >= sl.start) & (c < sl.stop)
                rows, cols = np.asarray(r)[m], np.asarray(c)[m] - sl.start
                if rows.size:
                    self.declare_partials(name, spec.name, rows=rows, cols=cols)
        for a, col in zip(self.options["accelerations"], self._acc_cols):
            m = np.asarray(cq) == col
            self.declare_partials(name, acceleration_output(a), rows=np.asarray(rq)[m], cols=np.zeros(int(m.sum()), int))
        for k, a in enumerate(self.options["accelerations"]):
            ck = self._C[k].tocoo()
            self.declare_partials(acceleration_output(a), name, rows=np.zeros(ck.nnz, int), cols=ck.col, val=ck.data)
            for spec in self._pins:
                cp = self._Cp[k, self._play[spec.name]].tocoo()
                if cp.nnz:
                    self.declare_partials(acceleration_output(a), spec.name, rows=np.zeros(cp.nnz, int), cols=cp.col,
                                          val=-cp.data)

    def _get_missing_partials(self, missing):
        """Nothing is missing: every output depends on every input through the coupled solve (the
        support rows have no partials with respect to most inputs, but the accelerations depend on
        them through the states; OpenMDAO's relevance graph would otherwise drop those paths)."""
        return

    # ---- packing -------------------------------------------------------------------------
    def _pack(self, inputs, outputs):
        s = self.options["system"]
        p = np.zeros(s.n_param)
        q = np.zeros(s.n_forcing)
        for spec in self._pins:
            p[self._play[spec.name]] = np.asarray(inputs[spec.name]).ravel()
        for spec in self._qins:
            q[self._qlay[spec.name]] = np.asarray(inputs[spec.name]).ravel()
        for a, col in zip(self.options["accelerations"], self._acc_cols):
            q[col] = float(np.asarray(outputs[acceleration_output(a)]).ravel()[0])
        return p, q

    def apply_nonlinear(self, inputs, outputs, residuals):
        s = self.options["system"]
        p, q = self._pack(inputs, outputs)
        x = np.asarray(outputs[self.options["state_name"]])
        residuals[self.options["state_name"]] = s.residual(x, np.zeros(s.n_state), p, q)
        c = self._C @ x - self._Cp @ p
        for k, a in enumerate(self.options["accelerations"]):
            residuals[acceleration_output(a)] = c[k]

    def solve_nonlinear(self, inputs, outputs):
        s = self.options["system"]
        p, q = self._pack(inputs, outputs)
        x0 = np.asarray(outputs[self.options["state_name"]], dtype=float)
        if not np.all(np.isfinite(x0)) or not np.any(x0):
            x0 = None
        try:
            x, acc = solve_inertia_relief(s, p, q, self.options["supports"], self.options["accelerations"], x0=x0,
                                          rtol=self.options["rtol"], max_iter=self.options["max_iter"])
        except ValueError as exc:
            raise om.AnalysisError(f"{self.msginfo}: {exc}") from None
        outputs[self.options["state_name"]] = x
        for a in self.options["accelerations"]:
            outputs[acceleration_output(a)] = acc[a]

    def linearize(self, inputs, outputs, partials):
        s = self.options["system"]
        name = self.options["state_name"]
        p, q = self._pack(inputs, outputs)
        x = np.asarray(outputs[name], dtype=float)
        xd = np.zeros(s.n_state)
        jx = s.jac_state(x, xd, p, q)[0].tocsr()
        jp, jq = (j.tocsr() for j in s.jac_inputs(x, xd, p, q))
        pat = s.jacobian_patterns()
        rx, cx, _ = pat["x"]
        partials[name, name] = np.asarray(jx[rx, cx]).ravel()
        for specs, lay, J, (r, c, _) in ((self._pins, self._play, jp, pat["p"]), (self._qins, self._qlay, jq, pat["q"])):
            r, c = np.asarray(r), np.asarray(c)
            for spec in specs:
                sl = lay[spec.name]
                m = (c >= sl.start) & (c < sl.stop)
                if m.any():
                    partials[name, spec.name] = np.asarray(J[r[m], c[m]]).ravel()
        rq, cq = np.asarray(pat["q"][0]), np.asarray(pat["q"][1])
        for a, col in zip(self.options["accelerations"], self._acc_cols):
            m = cq == col
            partials[name, acceleration_output(a)] = np.asarray(jq[rq[m], cq[m]]).ravel()
        K = sp.bmat([[jx, jq[:, self._acc_cols]], [self._C, None]], format="csc")
        self._lu = spla.splu(K)

    def solve_linear(self, d_outputs, d_residuals, mode):
        names = [self.options["state_name"]] + [acceleration_output(a) for a in self.options["accelerations"]]
        if mode == "fwd":
            rhs = np.concatenate([np.asarray(d_residuals[k]).ravel() for k in names])
            sol = self._lu.solve(rhs)
            out = d_outputs
        else:
            rhs = np.concatenate([np.asarray(d_outputs[k]).ravel() for k in names])
            sol = self._lu.solve(rhs, trans="T")
            out = d_residuals
        i = 0
        for k in names:
            size = np.asarray(out[k]).size
            out[k] = sol[i:i + size]
            i += size
