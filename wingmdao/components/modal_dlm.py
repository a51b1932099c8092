"""OpenMDAO components of the modal doublet-lattice wing of a changing design.

``ModalProjectionComp``: beam parameters -> modal mass, stiffness and inertia station loads on a
fixed basis (:mod:`wingmdao.aero.modal_design`; CasADi partials). ``ModalStationLoads``: the
marched modal states (:func:`wingmdao.aero.rfa_system.modal_rfa_system` with ``design=True``)
-> internal force and moment at every beam node in the jig's csn frames by force summation
(:mod:`wingmdao.aero.modal_loads`), the inputs of the box stress recovery; matrix-free analytic
products (the loads are linear in the states; the modal accelerations come from the equations of
motion with the design's modal mass and stiffness).
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import openmdao.api as om

from wingmdao.aero.modal_design import DESIGN_INPUTS, ModalProjection
from wingmdao.beam.rotations import body_to_csn
from wingmdao.stability.modal import ModalDLMWing
from wingmdao.timemarch.bdf import state_rates


_MASS = ("mass_per_length", "mass_center", "inertia_per_length")
_STIFFNESS = ("stiffness_csn", "compliance_csn", "tension_axis", "shear_center")
#: the (output, input) pairs that depend on each other
_DEPENDS = {(o, i) for o in ("modal_mass", "modal_inertia") for i in _MASS} | {("modal_stiffness", i) for i in _STIFFNESS}


class ModalProjectionComp(om.ExplicitComponent):
    """Beam parameters (:data:`wingmdao.aero.modal_design.DESIGN_INPUTS`) -> ``modal_mass``,
    ``modal_stiffness`` (modes, modes) and ``modal_inertia`` (n, 6, modes; N, N m per unit modal
    acceleration, body axes) on the fixed basis of the ``projection`` option."""

    def initialize(self):
        self.options.declare("projection", types=ModalProjection, desc="the fixed basis's projection (modal_projection)")

    def setup(self):
        P = self.options["projection"]
        n, m = P.n_nodes, P.n_modes
        for name, (shape, units) in DESIGN_INPUTS.items():
            self.add_input(name, val=1.0, shape=(n,) + shape, units=units, desc=f"beam parameter {name} per node")
        self.add_output("modal_mass", shape=(m, m), desc="modal mass on the fixed basis (kg m^2 per modal units squared)")
        self.add_output("modal_stiffness", shape=(m, m),
                        desc="modal stiffness on the fixed basis (N m per modal units squared)")
        self.add_output("modal_inertia", shape=(n, 6, m),
                        desc="internal force (N) and moment (N m) per unit modal acceleration, body axes")
        for out, name in _DEPENDS:
            self.declare_partials(out, name)

    def compute(self, inputs, outputs):
        P = self.options["projection"]
        res = P.function(*[inputs[k].ravel() for k in DESIGN_INPUTS])
        for out, val in zip(("modal_mass", "modal_stiffness", "modal_inertia"), res):
            outputs[out] = np.asarray(val).reshape(outputs[out].shape)

    def compute_partials(self, inputs, partials):
        P = self.options["projection"]
        jac = P.jacobian(*[inputs[k].ravel() for k in DESIGN_INPUTS])
        i = 0
        for out in ("modal_mass", "modal_stiffness", "modal_inertia"):
            for name in DESIGN_INPUTS:
                if (out, name) in _DEPENDS:
                    partials[out, name] = np.asarray(ca.DM(jac[i]))
                i += 1


class ModalStationLoads(om.ExplicitComponent):
    """``states`` (nt, modal states) of the design's modal doublet-lattice march -> ``F_csn``,
    ``M_csn`` (nt, n, 3): internal force (N) and moment (N m) at every beam node in the jig's csn
    frames (the convention of :class:`wingmdao.components.beam_loads.BeamInternalLoads`).

    Options: ``wing`` (:class:`wingmdao.stability.modal.ModalDLMWing`: its approximation, station-
    load coefficients and damping), ``node_euler_angles`` (n, 3) of the jig, the flight condition
    ``airspeed`` (m/s) and ``density`` (kg/m^3), ``gust`` (nt, 3): the march's gust velocity, rate
    and acceleration. Inputs ``modal_mass``, ``modal_stiffness``, ``modal_inertia`` (the design's,
    :class:`ModalProjectionComp`). The aerodynamic part of the loads is the panel force summation,
    fixed data of the planform and basis. A wing with control surfaces (``wing.controls``, the
    flap modes of :mod:`wingmdao.aero.modal_controls`) adds the flaps' loads and generalized forces
    of the deflection, rate, flap lag states and flap acceleration (the BDF rate of the actuator
    rate state on the march's ``time_step``, as the march's residual has it).
    """

    def initialize(self):
        self.options.declare("wing", types=ModalDLMWing, recordable=False, desc="the ModalDLMWing (approximation, station-load model, damping)")
        self.options.declare("node_euler_angles", types=np.ndarray, desc="jig Euler angles (n, 3), rad")
        self.options.declare("airspeed", types=float, desc="true airspeed (m/s)")
        self.options.declare("density", types=float, desc="air density (kg/m^3)")
        self.options.declare("gust", types=np.ndarray, desc="(nt, 3) gust velocity (m/s), rate, acceleration")
        self.options.declare("time_step", default=0.0, types=float,
                             desc="the march's time step (s): the flap accelerations of a wing with control surfaces")

    def setup(self):
        wing = self.options["wing"]
        rfa, model, ctl = wing.rfa, wing.loads, wing.controls
        gust = np.asarray(self.options["gust"], dtype=float)
        nt = gust.shape[0]
        m, L = rfa.A.shape[1], rfa.n_lags
        n = model.inertia.shape[0]
        base = 2 * m + L * m + L
        nsf = 0 if ctl is None else ctl.n_surfaces
        ns = base + (0 if ctl is None else ctl.spec.n_states + L * nsf)
        if ctl is not None and nt > 1 and not self.options["time_step"] > 0.0:
            raise ValueError("ModalStationLoads: a wing with control surfaces needs the march's time_step > 0 "
                             "(the flap accelerations are the BDF rates of the actuator states)")
        self._dims = (nt, n, m, L, ns)
        V, rho, b = self.options["airspeed"], self.options["density"], float(rfa.b_ref)
        qd = 0.5 * rho * V ** 2
        A, G, S, Sg = rfa.A, rfa.gust, model.motion.reshape(3 + L, n * 6, m), model.gust.reshape(3 + L, n * 6)
        C = np.asarray(wing.structure.damping, dtype=float)
        # rhs of the modal equations: R0 x + Rd xdot + rhs_f (the stiffness column added with the design's K)
        Rx = np.zeros((m, ns))
        Rx[:, :m] = qd * A[0]
        Rx[:, m:2 * m] = -(C - 0.5 * rho * V * b * A[1])
        for l in range(L):
            Rx[:, 2 * m + l * m:2 * m + (l + 1) * m] = qd * A[3 + l]
            Rx[:, 2 * m + L * m + l] = qd * G[3 + l]
        g, g1, g2 = gust[:, 0] / V, gust[:, 1] / V, gust[:, 2] / V
        self._rhs_f = qd * (np.outer(g, G[0]) + np.outer((b / V) * g1, G[1]) + np.outer((b / V) ** 2 * g2, G[2]))
        Px = np.zeros((n * 6, ns))
        Px[:, :m] = qd * S[0]
        Px[:, m:2 * m] = qd * (b / V) * S[1]
        for l in range(L):
            Px[:, 2 * m + l * m:2 * m + (l + 1) * m] = qd * S[3 + l]
            Px[:, 2 * m + L * m + l] = qd * Sg[3 + l]
        # the flap modes (wingmdao.aero.modal_controls): deflection, rate, rate' (an xdot column), lag states
        Rd, Pd = np.zeros((m, ns)), np.zeros((n * 6, ns))
        if ctl is not None:
            Fl = ctl.flap_loads.reshape(3 + L, n * 6, nsf)
            nsc = ctl.spec.n_states
            for k in range(nsf):
                i_d, i_r = base + 2 * k, base + 2 * k + 1
                Rx[:, i_d], Px[:, i_d] = qd * ctl.flap[0][:, k], qd * Fl[0][:, k]
                Rx[:, i_r], Px[:, i_r] = qd * (b / V) * ctl.flap[1][:, k], qd * (b / V) * Fl[1][:, k]
                Rd[:, i_r], Pd[:, i_r] = qd * (b / V) ** 2 * ctl.flap[2][:, k], qd * (b / V) ** 2 * Fl[2][:, k]
                for l in range(L):
                    j = base + nsc + l * nsf + k
                    Rx[:, j], Px[:, j] = qd * ctl.flap[3 + l][:, k], qd * Fl[3 + l][:, k]
        self._Rd, self._Pd, self._rates = Rd, Pd, ctl is not None
        self._aero_f = qd * (np.outer(g, Sg[0]) + np.outer((b / V) * g1, Sg[1]) + np.outer((b / V) ** 2 * g2, Sg[2]))
        self._R0, self._Px = Rx, Px
        self._Qaero = qd * (b / V) ** 2 * S[2]                          # (n6, m)
        self._Waero = 0.5 * rho * b ** 2 * A[2]
        th = np.asarray(self.options["node_euler_angles"], dtype=float)
        T = np.array([np.asarray(ca.DM(body_to_csn(th[s])), dtype=float) for s in range(n)])
        rot = np.zeros((n * 6, n * 6))
        for s in range(n):
            rot[6 * s:6 * s + 3, 6 * s:6 * s + 3] = T[s]
            rot[6 * s + 3:6 * s + 6, 6 * s + 3:6 * s + 6] = T[s]
        self._rot = rot
        self.add_input("states", shape=(nt, ns), desc="modal states q, v, lag states (modal_rfa_system)")
        self.add_input("modal_mass", val=np.eye(m), desc="modal mass (kg m^2 per modal units squared)")
        self.add_input("modal_stiffness", val=np.eye(m), desc="modal stiffness (N m per modal units squared)")
        self.add_input("modal_inertia", shape=(n, 6, m), desc="internal loads per unit modal acceleration, body axes")
        self.add_output("F_csn", shape=(nt, n, 3), units="N", desc="internal force [F_c, F_s axial, F_n], csn")
        self.add_output("M_csn", shape=(nt, n, 3), units="N*m", desc="internal moment [M_c, M_s torsion, M_n], csn")

    def _xdot(self, X):
        """BDF rates of a state history (the march's; zero when the wing has no control surfaces)."""
        return state_rates(X, self.options["time_step"]) if self._rates else np.zeros_like(X)

    def _xdot_transpose(self, Y):
        """Transpose of :meth:`_xdot`'s linear map applied to ``Y`` (nt, states)."""
        out = np.zeros_like(Y)
        if not self._rates:
            return out
        dt, nt = self.options["time_step"], Y.shape[0]
        if nt > 1:
            out[1] += Y[1] / dt
            out[0] -= Y[1] / dt
        if nt > 2:
            out[2:] += 1.5 * Y[2:] / dt
            out[1:-1] -= 2.0 * Y[2:] / dt
            out[:-2] += 0.5 * Y[2:] / dt
        return out

    def _operators(self, inputs):
        """(Rx, W^-1, Qa) of the current design."""
        nt, n, m, L, ns = self._dims
        W = inputs["modal_mass"] - self._Waero
        Rx = self._R0.copy()
        Rx[:, :m] -= inputs["modal_stiffness"]
        Winv = np.linalg.inv(W)
        Qa = self._Qaero + inputs["modal_inertia"].reshape(n * 6, m)
        return Rx, Winv, Qa

    def _accelerations(self, inputs, Rx, Winv, Xd):
        X = inputs["states"]
        return (X @ Rx.T + Xd @ self._Rd.T + self._rhs_f) @ Winv.T      # (nt, m)

    def body_loads(self, inputs) -> tuple[np.ndarray, np.ndarray]:
        """``(total, aerodynamic)`` station loads (nt, n, 6) in body axes (N, N m) of ``inputs``
        (a mapping of this component's input names): the force summation and its panel-force share
        (whose root force z is the half-wing's lift increment).

        Parameters
        ----------
        inputs : mapping
            This component's inputs by name.

        Returns
        -------
        tuple
            (total, aerodynamic) station loads (nt, n, 6).
        """
        nt, n, m, L, ns = self._dims
        Rx, Winv, Qa = self._operators(inputs)
        Xd = self._xdot(inputs["states"])
        a = self._accelerations(inputs, Rx, Winv, Xd)
        aero = inputs["states"] @ self._Px.T + Xd @ self._Pd.T + self._aero_f + a @ self._Qaero.T
        total = aero + a @ inputs["modal_inertia"].reshape(n * 6, m).T
        return total.reshape(nt, n, 6), aero.reshape(nt, n, 6)

    def compute(self, inputs, outputs):
        nt, n, m, L, ns = self._dims
        Rx, Winv, Qa = self._operators(inputs)
        Xd = self._xdot(inputs["states"])
        a = self._accelerations(inputs, Rx, Winv, Xd)
        loads = inputs["states"] @ self._Px.T + Xd @ self._Pd.T + self._aero_f + a @ Qa.T
        loads = (loads @ self._rot.T).reshape(nt, n, 6)
        outputs["F_csn"] = loads[:, :, :3]
        outputs["M_csn"] = loads[:, :, 3:]

    def compute_jacvec_product(self, inputs, d_inputs, d_outputs, mode):
        nt, n, m, L, ns = self._dims
        Rx, Winv, Qa = self._operators(inputs)
        a = self._accelerations(inputs, Rx, Winv, self._xdot(inputs["states"]))
        q = inputs["states"][:, :m]
        QW = Qa @ Winv                                                   # (n6, m)
        Jx = self._Px + QW @ Rx
        Jd = self._Pd + QW @ self._Rd
        if mode == "fwd":
            dL = np.zeros((nt, n * 6))
            if "states" in d_inputs:
                dL += d_inputs["states"] @ Jx.T
                if self._rates:
                    dL += self._xdot(d_inputs["states"]) @ Jd.T
            if "modal_stiffness" in d_inputs:
                dL -= (q @ d_inputs["modal_stiffness"].T) @ QW.T
            if "modal_mass" in d_inputs:
                dL -= (a @ d_inputs["modal_mass"].T) @ QW.T
            if "modal_inertia" in d_inputs:
                dL += a @ d_inputs["modal_inertia"].reshape(n * 6, m).T
            dL = (dL @ self._rot.T).reshape(nt, n, 6)
            if "F_csn" in d_outputs:
                d_outputs["F_csn"] += dL[:, :, :3]
            if "M_csn" in d_outputs:
                d_outputs["M_csn"] += dL[:, :, 3:]
        else:
            dout = np.zeros((nt, n, 6))
            if "F_csn" in d_outputs:
                dout[:, :, :3] = d_outputs["F_csn"]
            if "M_csn" in d_outputs:
                dout[:, :, 3:] = d_outputs["M_csn"]
            dL = dout.reshape(nt, n * 6) @ self._rot                     # body-axis adjoint
            Y = dL @ QW                                                  # (nt, m)
            if "states" in d_inputs:
                d_inputs["states"] += dL @ Jx
                if self._rates:
                    d_inputs["states"] += self._xdot_transpose(dL @ Jd)
            if "modal_stiffness" in d_inputs:
                d_inputs["modal_stiffness"] -= Y.T @ q
            if "modal_mass" in d_inputs:
                d_inputs["modal_mass"] -= Y.T @ a
            if "modal_inertia" in d_inputs:
                d_inputs["modal_inertia"] += (dL.T @ a).reshape(n, 6, m)


class ModalLoadSum(om.ExplicitComponent):
    """``F_csn``, ``M_csn`` (nt, n, 3) = the static first instant ``static_F_csn``, ``static_M_csn``
    (1, n, 3; e.g. the trimmed 1 g beam) + the dynamic increment ``dynamic_F_csn``,
    ``dynamic_M_csn`` (nt, n, 3) at every instant."""

    def initialize(self):
        self.options.declare("num_times", types=int, lower=1, desc="number of time instants")
        self.options.declare("num_nodes", types=int, lower=2, desc="number of beam nodes")

    def setup(self):
        nt, n = self.options["num_times"], self.options["num_nodes"]
        size = nt * n * 3
        cols = np.tile(np.arange(n * 3), nt)
        for k, units, what in (("F_csn", "N", "internal force"), ("M_csn", "N*m", "internal moment")):
            self.add_input(f"static_{k}", shape=(1, n, 3), units=units, desc=f"static {what}, csn")
            self.add_input(f"dynamic_{k}", shape=(nt, n, 3), units=units, desc=f"dynamic increment of the {what}, csn")
            self.add_output(k, shape=(nt, n, 3), units=units, desc=f"{what}, csn (static + increment)")
            self.declare_partials(k, f"static_{k}", rows=np.arange(size), cols=cols, val=1.0)
            self.declare_partials(k, f"dynamic_{k}", rows=np.arange(size), cols=np.arange(size), val=1.0)

    def compute(self, inputs, outputs):
        for k in ("F_csn", "M_csn"):
            outputs[k] = inputs[f"static_{k}"] + inputs[f"dynamic_{k}"]
