"""Newton solver: converges on a nonlinear system, raises AnalysisError with diagnostics."""

import numpy as np
import openmdao.api as om
import pytest
import scipy.sparse as sp

from wingmdao.timemarch.newton import newton_solve


def test_converges_quadratically_on_nonlinear_system():
    # x0^3 + x1 = 10, x1^2 = 4 (x1 > 0)  ->  x1 = 2, x0 = 2
    res = lambda x: np.array([x[0] ** 3 + x[1] - 10.0, x[1] ** 2 - 4.0])
    jac = lambda x: sp.csc_matrix(np.array([[3 * x[0] ** 2, 1.0], [0.0, 2 * x[1]]]))
    x, info = newton_solve(res, jac, [5.0, 5.0], atol=1e-12)
    np.testing.assert_allclose(x, [2.0, 2.0], rtol=1e-12)
    assert info.converged and info.iterations < 15


def test_failure_raises_analysis_error_naming_worst_equation():
    res = lambda x: np.array([x[0] ** 2 + 1.0])  # no real root
    jac = lambda x: sp.csc_matrix(np.array([[2 * x[0] + 1e-3]]))
    with pytest.raises(om.AnalysisError, match=r"step 7.*max \|residual\| = \d\.\d{3}e[+-]\d+, worst: lift balance"):
        newton_solve(res, jac, [1.0], max_iter=8, label="step 7", describe=lambda i: "lift balance")
