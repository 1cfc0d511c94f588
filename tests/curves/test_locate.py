"""The one singular-point locator: exact CasADi derivatives, or central differences for a plain problem."""
from __future__ import annotations

import casadi as ca
import numpy as np

from symkin.curves.locate import as_casadi, locate_singular_point, nullity


def lines_function() -> ca.Function:
    """H(y) = y0² − y1² (two lines through the origin) and a regular third equation y2 = y0."""
    y = ca.SX.sym("y", 3)
    h = ca.vertcat(y[0] ** 2 - y[1] ** 2, y[2] - y[0])
    return ca.Function("lines", [y], [h, ca.jacobian(h, y)])


class Plain:
    """The same curve as a numeric problem (no CasADi Function)."""

    def residual(self, y):
        return np.array([y[0] ** 2 - y[1] ** 2, y[2] - y[0]])

    def jacobian(self, y):
        return np.array([[2 * y[0], -2 * y[1], 0.0], [-1.0, 0.0, 1.0]])


def test_the_branch_point_exact_and_by_central_differences():
    start = np.array([0.01, -0.02, 0.015])
    exact = locate_singular_point(lines_function(), start)
    assert exact.converged and exact.deflations == 0 and float(np.max(np.abs(exact.y))) <= 1e-14
    plain = locate_singular_point(Plain(), start)
    assert plain.converged and float(np.max(np.abs(plain.y))) <= 1e-12
    assert nullity(Plain(), exact.y) == 2 and nullity(Plain(), start) == 1


def test_as_casadi_prefers_the_problems_own_function():
    class WithFunction(Plain):
        casadi_function = lines_function()

    assert as_casadi(WithFunction(), np.zeros(3)) is WithFunction.casadi_function
    f = as_casadi(Plain(), np.zeros(3))
    h, j = (np.array(v, float) for v in f(np.array([1.0, 2.0, 3.0])))
    np.testing.assert_allclose(h.ravel(), [-3.0, 2.0])
    np.testing.assert_allclose(j, Plain().jacobian(np.array([1.0, 2.0, 3.0])))
