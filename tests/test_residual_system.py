"""CasadiResidualSystem: residual and sparse Jacobians against central differences."""

import casadi as ca
import numpy as np

from wingmdao.timemarch.system import CasadiResidualSystem, VarSpec, layout, pack


def _system():
    x, xd = ca.SX.sym("x", 2), ca.SX.sym("xdot", 2)
    p, q = ca.SX.sym("p", 2), ca.SX.sym("q", 1)
    # nonlinear oscillator: x0' = x1, m x1' + c x1 + k sin(x0) = f
    R = ca.vertcat(xd[0] - x[1], p[0] * xd[1] + 0.3 * x[1] + p[1] * ca.sin(x[0]) - q[0])
    return CasadiResidualSystem(x, xd, p, q, R,
                                param_specs=[VarSpec("mass", (), "kg"), VarSpec("stiffness", (), "N/m")],
                                forcing_specs=[VarSpec("force", (), "N")])


def test_jacobians_match_central_differences():
    sysm = _system()
    rng = np.random.default_rng(1)
    args = [rng.normal(size=2), rng.normal(size=2), rng.uniform(1, 2, 2), rng.normal(size=1)]
    analytic = list(sysm.jac_state(*args)) + list(sysm.jac_inputs(*args))
    for k in range(4):
        n = args[k].size
        fd = np.zeros((2, n))
        for j in range(n):
            hi = [a.copy() for a in args]
            lo = [a.copy() for a in args]
            hi[k][j] += 1e-6
            lo[k][j] -= 1e-6
            fd[:, j] = (sysm.residual(*hi) - sysm.residual(*lo)) / 2e-6
        np.testing.assert_allclose(analytic[k].toarray(), fd, atol=1e-8)


def test_layout_and_pack():
    specs = [VarSpec("a", (2, 3)), VarSpec("b", ())]
    sl = layout(specs)
    v = pack(specs, {"a": np.arange(6).reshape(2, 3), "b": 7.0})
    np.testing.assert_array_equal(v[sl["a"]], np.arange(6))
    assert v[sl["b"]][0] == 7.0
