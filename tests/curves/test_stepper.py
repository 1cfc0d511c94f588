"""Continuation, event location and branch switching on curves with known answers."""
from __future__ import annotations

import math

import numpy as np
import pytest

from symkin.paths.branching import branch_directions
from symkin.curves.stepper import Settings, continue_curve, correct
from symkin.curves.events import EventType as TestFunction
from symkin.curves.locate import locate_minimum, locate_sign_change


class Circle:
    """x² + y² − 1 = 0, given twice (a redundant equation must not hurt)."""

    def residual(self, y):
        r = y @ y - 1.0
        return np.array([r, 2 * r])

    def jacobian(self, y):
        return np.array([2 * y, 4 * y])


class Lemniscate:
    """(x² + y²)² − 2(x² − y²) = 0: a figure eight crossing itself at the origin with slopes ±1."""

    def residual(self, y):
        x, z = y
        return np.array([(x * x + z * z) ** 2 - 2 * (x * x - z * z)])

    def jacobian(self, y):
        x, z = y
        q = x * x + z * z
        return np.array([[4 * x * q - 4 * x, 4 * z * q + 4 * z]])


class TangentParabolas:
    """(z − x²)(z + x²) = 0: two branches tangent at the origin (the paper's Fig. 4 situation)."""

    def residual(self, y):
        x, z = y
        return np.array([z * z - x ** 4])

    def jacobian(self, y):
        x, z = y
        return np.array([[-4 * x ** 3, 2 * z]])


def test_full_loop_of_a_circle_with_redundant_equations():
    prob = Circle()
    points = []
    for p in continue_curve(prob, np.array([1.0, 0.0]), np.array([0.0, 1.0]), Settings(step=0.1, max_step=0.3)):
        points.append(p)
        if p.s > 2 * math.pi + 0.5:
            break
    radii = [np.linalg.norm(p.y) for p in points]
    assert max(abs(r - 1.0) for r in radii) < 1e-12
    angles = np.unwrap([math.atan2(p.y[1], p.y[0]) for p in points])
    assert np.all(np.diff(angles) > 0) and angles[-1] > 2 * math.pi


def test_turning_point_is_located_to_machine_precision():
    """Counter-clockwise along the circle, dx/ds = −sin θ changes sign at θ = π: locate (−1, 0)."""
    prob = Circle()
    test = TestFunction("dx/ds", lambda y, t: float(t[0]))
    points = []
    start = np.array([math.cos(0.3), math.sin(0.3)])
    for p in continue_curve(prob, start, np.array([0.0, 1.0]), Settings(step=0.07)):
        points.append(p)
        if len(points) >= 2 and np.sign(test.f(points[-2].y, points[-2].t)) != np.sign(test.f(p.y, p.t)):
            break
    a, b = points[-2], points[-1]
    ev = locate_sign_change(prob, test, a, b)
    np.testing.assert_allclose(ev.y, [-1.0, 0.0], atol=1e-13)
    assert ev.evaluations < 40


def test_lemniscate_bifurcation_directions():
    bif = branch_directions(Lemniscate(), np.array([0.0, 0.0]))
    assert bif.status == "simple" and bif.nullity == 2
    slopes = sorted(d[1] / d[0] for d in bif.directions)
    assert slopes == pytest.approx([-1.0, 1.0], abs=1e-8)


def test_tangent_branches_are_reported_degenerate():
    bif = branch_directions(TangentParabolas(), np.array([0.0, 0.0]))
    assert bif.status == "degenerate" and "tangent" in bif.message


def test_regular_point_is_not_a_bifurcation():
    assert branch_directions(Circle(), np.array([0.6, 0.8])).status == "regular"


def test_minimum_of_a_nonnegative_test_function():
    """distance to the point (0, 2) along the circle is smallest (=1) at (0, 1)."""
    prob = Circle()
    test = TestFunction("gap", lambda y, t: float(np.linalg.norm(y - [0.0, 2.0]) - 1.0), signed=False,
                        threshold=1e-9)
    pts = list(p for _, p in zip(range(40), continue_curve(prob, np.array([1.0, 0.0]), np.array([0.0, 1.0]),
                                                             Settings(step=0.1, max_step=0.1))))
    vals = [test.f(p.y, p.t) for p in pts]
    k = int(np.argmin(vals))
    ev = locate_minimum(prob, test, pts[k - 1], pts[k], pts[k + 1])
    assert ev is not None
    np.testing.assert_allclose(ev.y, [0.0, 1.0], atol=1e-6)


def test_newton_reports_how_close_it_got():
    from symkin.errors import NotConvergedError

    class NoRoot:
        def residual(self, y):
            return np.array([y @ y + 1.0])

        def jacobian(self, y):
            return np.array([2 * y])

    with pytest.raises(NotConvergedError) as info:
        correct(NoRoot(), np.array([0.3, 0.2]), max_iterations=15)
    assert info.value.data["residual"] >= 1.0


def test_generated_corrector_matches_the_least_squares_corrector():
    """Compiled Newton steps and tangents give the same curve points as the NumPy corrector."""
    from symkin.model import catalogue
    from symkin.paths.system import make_curve

    curve = make_curve(catalogue.get("rrr_3"), "rotation:crank1")
    fast = curve.fast_corrector
    assert fast is not None and fast.compiled
    y0 = curve.y0()
    t0 = np.linalg.svd(curve.jacobian(y0))[2][-1]
    pred = y0 + 0.05 * t0
    y_fast, _, t_fast = fast.correct(pred, t0, 1e-12, 10)

    def hyperplane(y):
        return np.array([t0 @ (y - pred)]), t0[None, :]

    y_ref, _, _ = correct(curve, pred, extra=hyperplane)
    np.testing.assert_allclose(y_fast, y_ref, atol=1e-13)
    from symkin.curves.stepper import tangent
    np.testing.assert_allclose(t_fast, tangent(curve, y_fast, t0), atol=1e-12)
