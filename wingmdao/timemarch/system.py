"""Residual systems R(x, xdot, p, q) = 0 for one time instant, and their sparse Jacobians.

A *residual system* is the unit the time marcher, the static solver and the discrete
adjoint work on (Sec. 3.5.2): ``x`` is the state at one instant, ``xdot`` its time
derivative, ``p`` the time-invariant parameters (design-dependent data such as section
stiffness and geometry) and ``q`` the forcing at that instant (loads). The layouts of ``p``
and ``q`` are described by :class:`VarSpec` lists so that an OpenMDAO component can
expose each piece as a named, unit-carrying input.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np
import scipy.sparse as sp


@dataclass(frozen=True)
class VarSpec:
    """A named block of a flat parameter or forcing vector (shape, units, description)."""

    name: str
    shape: tuple = ()
    units: str | None = None
    desc: str = ""

    @property
    def size(self) -> int:
        return int(np.prod(self.shape)) if self.shape else 1


def layout(specs) -> dict[str, slice]:
    """Slices of each :class:`VarSpec` in the flat vector made by concatenating them in order."""
    out, start = {}, 0
    for s in specs:
        out[s.name] = slice(start, start + s.size)
        start += s.size
    return out


def pack(specs, values: dict) -> np.ndarray:
    """Flatten ``{name: array}`` into one vector in the order of ``specs``."""
    if not specs:
        return np.zeros(0)
    return np.concatenate([np.asarray(values[s.name], dtype=float).reshape(s.size) for s in specs])


class ResidualSystem:
    """Interface of a first-order implicit system R(x, xdot, p, q) = 0 at one instant.

    Attributes set by implementations: ``n_state``, ``state_shape`` (how the flat state is
    shown to users, e.g. ``(n_node, 18)``), ``param_specs`` and ``forcing_specs`` (lists of
    :class:`VarSpec`), ``n_param``, ``n_forcing``.
    """

    n_state: int
    state_shape: tuple
    param_specs: list
    forcing_specs: list

    @property
    def n_param(self) -> int:
        return sum(s.size for s in self.param_specs)

    @property
    def n_forcing(self) -> int:
        return sum(s.size for s in self.forcing_specs)

    def residual(self, x, xdot, p, q) -> np.ndarray:
        raise NotImplementedError

    def jac_state(self, x, xdot, p, q) -> tuple[sp.csc_matrix, sp.csc_matrix]:
        """(dR/dx, dR/dxdot), sparse."""
        raise NotImplementedError

    def jac_inputs(self, x, xdot, p, q) -> tuple[sp.csc_matrix, sp.csc_matrix]:
        """(dR/dp, dR/dq), sparse."""
        raise NotImplementedError

    def describe_equation(self, index: int) -> str:
        """Human-readable name of residual ``index`` (used in convergence diagnostics)."""
        return f"equation {index}"


class _SparseJacobian:
    """Evaluate a CasADi Jacobian into a scipy CSC matrix with a fixed sparsity pattern."""

    def __init__(self, fun: ca.Function, expr, wrt, args, tag: str):
        jac = ca.jacobian(expr, wrt)
        spty = jac.sparsity()
        colind, row = spty.get_ccs()
        self.shape = (spty.size1(), spty.size2())
        self.indptr = np.asarray(colind, dtype=np.int64)
        self.indices = np.asarray(row, dtype=np.int64)
        self.nnz = spty.nnz()
        self.fun = ca.Function(f"{fun.name()}_jac_{tag}", args, [jac])

    def __call__(self, *vals) -> sp.csc_matrix:
        data = np.asarray(self.fun(*vals).nonzeros(), dtype=float)
        return sp.csc_matrix((data, self.indices, self.indptr), shape=self.shape)


class CasadiResidualSystem(ResidualSystem):
    """A :class:`ResidualSystem` from symbolic CasADi expressions.

    ``x, xdot, p, q`` are CasADi symbols (SX or MX column vectors) and ``R`` the residual
    expression. Jacobians are exact (CasADi AD) and sparse; their patterns are fixed once.
    """

    def __init__(self, x, xdot, p, q, R, *, param_specs, forcing_specs, state_shape=None,
                 name="residual", describe=None):
        self.n_state = int(x.numel())
        self.state_shape = tuple(state_shape) if state_shape else (self.n_state,)
        self.param_specs = list(param_specs)
        self.forcing_specs = list(forcing_specs)
        if self.n_param != p.numel() or self.n_forcing != q.numel():
            raise ValueError("parameter/forcing specs do not match the sizes of p and q")
        if R.numel() != self.n_state:
            raise ValueError(f"residual has {R.numel()} equations for {self.n_state} states")
        args = [x, xdot, p, q]
        self._R = ca.Function(name, args, [R])
        self._dx = _SparseJacobian(self._R, R, x, args, "x")
        self._dxdot = _SparseJacobian(self._R, R, xdot, args, "xdot")
        self._dp = _SparseJacobian(self._R, R, p, args, "p")
        self._dq = _SparseJacobian(self._R, R, q, args, "q")
        self._describe = describe

    def residual(self, x, xdot, p, q):
        return np.asarray(self._R(x, xdot, p, q)).ravel()

    def jac_state(self, x, xdot, p, q):
        return self._dx(x, xdot, p, q), self._dxdot(x, xdot, p, q)

    def jac_inputs(self, x, xdot, p, q):
        return self._dp(x, xdot, p, q), self._dq(x, xdot, p, q)

    def describe_equation(self, index):
        return self._describe(index) if self._describe else super().describe_equation(index)
