"""The continuation meets a NaN/inf: a NotConvergedError that says so, never LAPACK's LinAlgError."""
from __future__ import annotations

import numpy as np
import pytest

from symkin.errors import NotConvergedError
from symkin.curves.stepper import NonFiniteError, Settings, continue_curve, correct, tangent


class _Circle:
    """x² + y² = 1, with a Jacobian that is NaN for x > x_bad (a 0/0 derivative)."""

    def __init__(self, x_bad=np.inf, residual_bad=False):
        self.x_bad, self.residual_bad = x_bad, residual_bad

    def residual(self, y):
        r = np.array([y @ y - 1.0])
        return r * np.nan if self.residual_bad else r

    def jacobian(self, y):
        j = 2.0 * y[None, :]
        return j * np.nan if y[0] > self.x_bad else j


def test_newton_on_a_nan_jacobian_raises_not_converged():
    with pytest.raises(NonFiniteError, match="Jacobian is not finite") as info:
        correct(_Circle(x_bad=-10.0), np.array([1.1, 0.0]))
    assert isinstance(info.value, NotConvergedError)
    np.testing.assert_array_equal(info.value.data["y"], [1.1, 0.0])


def test_newton_on_a_nan_residual_raises_not_converged():
    with pytest.raises(NonFiniteError, match="residual is not finite"):
        correct(_Circle(residual_bad=True), np.array([1.1, 0.0]))


def test_tangent_on_a_nan_jacobian_raises_not_converged():
    with pytest.raises(NonFiniteError):
        tangent(_Circle(x_bad=-10.0), np.array([1.0, 0.0]))


def test_continuation_stops_where_the_jacobian_turns_nan():
    """From (0, 1) to the left the circle is followed; to the right it stops before x > 0.5."""
    settings = Settings(step=0.05, max_step=0.1, min_step=1e-6, max_steps=200)
    problem = _Circle(x_bad=0.5)
    y0 = np.array([0.0, 1.0])
    with pytest.raises(NotConvergedError):
        points = list(continue_curve(problem, y0, np.array([1.0, 0.0]), settings))
        assert False, points  # the step shrinks below min_step: SteppingError
    left = []
    for p in continue_curve(problem, y0, np.array([-1.0, 0.0]), settings):
        left.append(p.y)
        if len(left) > 20:
            break
    left = np.array(left)
    assert np.all(np.abs(np.hypot(left[:, 0], left[:, 1]) - 1.0) < 1e-10) and left[-1, 0] < -0.5
