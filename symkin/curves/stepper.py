"""Pseudo-arclength continuation of a curve ``H(y) = 0``, ``H: Rⁿ → Rᵐ`` with a 1-D solution set.

Mechanism-agnostic (like pacopy): a :class:`CurveProblem` gives the residual ``H`` and its
Jacobian; :func:`continue_curve` walks the curve with adaptive steps and yields points.
Redundant equations (``m > n − 1``, overconstrained mechanisms) are fine: every linear
solve is a least-squares (SVD) solve, and every correction is a call of the one corrector
(:func:`symkin.curves.corrector.gauss_newton`) through :func:`correct`.

Step control and guards against jumping to another branch: a step is rejected and halved
when the corrector does not converge within ``max_corrector_iterations``, when the
corrected point is farther than ``max_corrector_distance·h`` from the predictor, or when
the tangent turns by more than ``max_turn`` radians.  Easy steps grow the step by 1.5.

A problem may offer a ``fast_corrector`` (an object whose ``correct(y_pred, t, tol,
max_iterations)`` returns ``(y, iterations, tangent)`` or raises
:class:`~symkin.errors.NotConvergedError`, e.g. generated code for a mechanism's square
augmented system); it is tried first on every step.

All quantities are dimensionless: the caller scales ``y`` (e.g. by the model's length
scale) so that the default settings make sense.

>>> import numpy as np
>>> class Circle:
...     def residual(self, y): return np.array([y @ y - 1.0])
...     def jacobian(self, y): return 2 * y[None, :]
>>> pts = list(continue_curve(Circle(), np.array([1.0, 0.0]), np.array([0.0, 1.0]),
...                           Settings(max_steps=200), stop=lambda p: p.s > 1.0))
>>> round(float(pts[-1].y @ pts[-1].y), 12), pts[-1].s > 1.0
(1.0, True)
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Iterator, Protocol

import numpy as np

from symkin.curves.corrector import NonFiniteError, gauss_newton, least_squares_step
from symkin.errors import NotConvergedError
from symkin.tolerances import DEFAULT

__all__ = ["CurveProblem", "Settings", "CurvePoint", "SteppingError", "NonFiniteError", "correct", "tangent",
           "point_at", "continue_curve"]

#: iterations allowed to :func:`point_at`: next to a branch point Newton converges only linearly
POINT_AT_ITERATIONS = 50
#: :func:`point_at` accepts a residual that stops improving below this multiple of its tolerance
#: (the rounding floor of a near-singular Jacobian next to a branch point)
POINT_AT_FLOOR = 1e3
#: a step that converged within this many corrector iterations was easy: the next one is longer
EASY_STEP = 3
#: factor by which an easy step grows
GROWTH = 1.5


class CurveProblem(Protocol):
    """What the continuation needs: residual and Jacobian of ``H`` (dimensionless)."""

    def residual(self, y: np.ndarray) -> np.ndarray: ...

    def jacobian(self, y: np.ndarray) -> np.ndarray: ...


@dataclass(frozen=True)
class Settings:
    """Continuation settings (dimensionless units of ``y``: lengths over the model's length scale).

    ``step`` the first step (1/20 of the length scale: a crank of unit length turns ~3° per
    step); ``min_step`` the step below which the curve cannot be followed (``SteppingError``:
    ~1e-9 is where a predictor no longer differs from the corrected point by more than the
    corrector's rounding); ``max_step`` the longest step (1/5: event brackets stay short
    enough for one sign change of each test); ``tol`` the corrector's residual
    (``Tolerances.newton``); ``max_corrector_iterations`` before a step is halved (a good
    predictor converges in 2–4); ``max_corrector_distance`` the largest move of the
    corrector relative to ``h`` (beyond it the corrector may have jumped to another
    branch); ``max_turn`` the largest tangent turn per step (0.35 rad, 20°: the same
    guard); ``max_steps`` accepted steps at most (a budget: when it runs out the stepper ends,
    and :func:`symkin.curves.tracer.trace_curve` says so with the stop reason ``"max_steps"``).
    """

    step: float = 0.05
    min_step: float = 1e-9
    max_step: float = 0.2
    tol: float = DEFAULT.newton
    max_corrector_iterations: int = 10
    max_corrector_distance: float = 0.25
    max_turn: float = 0.35
    max_steps: int = 20000


class SteppingError(NotConvergedError):
    """The step size fell below ``min_step``: the curve cannot be followed further here."""


@dataclass(frozen=True)
class CurvePoint:
    """An accepted point: position ``y``, unit tangent ``t`` and arclength ``s`` from the start."""

    y: np.ndarray = field(repr=False)
    t: np.ndarray = field(repr=False)
    s: float
    corrector_iterations: int = 0


def _residual_and_jacobian(problem: CurveProblem, extra=None) -> Callable:
    """``y ↦ (H, J)`` of ``problem`` (one call when it offers ``residual_and_jacobian``), ``extra`` rows appended."""
    both = getattr(problem, "residual_and_jacobian", None)

    def fun(y):
        r, j = both(y) if both is not None else (problem.residual(y), problem.jacobian(y))
        if extra is not None:
            re, je = extra(y)
            r, j = np.concatenate([np.asarray(r, float).ravel(), re]), np.vstack([j, je])
        return r, j
    return fun


def correct(problem: CurveProblem, y0: np.ndarray, extra=None, tol: float = DEFAULT.newton,
            max_iterations: int = 20, floor: float | None = None) -> tuple[np.ndarray, int, float]:
    """Project ``y0`` onto ``H(y) = 0`` (plus optional extra equations ``extra(y) -> (r, J)``).

    One call of :func:`~symkin.curves.corrector.gauss_newton` (its stopping rule; ``floor``
    as there).  Returns ``(y, iterations, residual norm)``; raises
    :class:`~symkin.errors.NotConvergedError` (with ``y`` and the residual reached) when it
    does not converge.

    >>> import numpy as np
    >>> class Line:
    ...     def residual(self, y): return np.array([y[0] + y[1] - 1.0])
    ...     def jacobian(self, y): return np.array([[1.0, 1.0]])
    >>> y, k, res = correct(Line(), np.array([0.0, 0.0]))
    >>> np.round(y, 12).tolist(), k
    ([0.5, 0.5], 1)
    """
    fun = _residual_and_jacobian(problem, extra)
    c = gauss_newton(fun, y0, tol=tol, max_iterations=max_iterations, floor=floor)
    if not c.converged and c.iterations == 0 and not math.isfinite(c.residual):
        _raise_non_finite(y0, *fun(np.asarray(y0, float)))
    c.raise_unless_converged("Newton")
    return c.z, c.iterations, c.residual


def _raise_non_finite(y: np.ndarray, r: np.ndarray, j: np.ndarray) -> None:
    """Raise :class:`NonFiniteError` (with ``y``) naming what is not finite at the start: the residual or the Jacobian.

    LAPACK's SVD would stop with ``LinAlgError: SVD did not converge`` on a NaN; a solver
    that meets one has not converged, and says where.
    """
    for name, v in (("residual", r), ("Jacobian", j)):
        if not np.all(np.isfinite(v)):
            raise NonFiniteError(f"the {name} is not finite (NaN or inf) at y = {np.asarray(y)}", y=np.asarray(y))


def tangent(problem: CurveProblem, y: np.ndarray, previous: np.ndarray | None = None) -> np.ndarray:
    """Unit tangent of the curve at ``y``, oriented along ``previous`` when given.

    Without ``previous``: the right singular vector of the smallest singular value of the
    Jacobian.  With it: the solution of ``[J; previousᵀ] t = [0; 1]``, normalised.
    Raises :class:`NonFiniteError` where the Jacobian is not finite.
    """
    j = np.asarray(problem.jacobian(y), float)
    _raise_non_finite(y, np.zeros(0), j)
    if previous is None:
        t = np.linalg.svd(j, full_matrices=True)[2][-1]
    else:
        a = np.vstack([j, previous[None, :]])
        b = np.zeros(a.shape[0])
        b[-1] = 1.0
        t = -least_squares_step(a, b)
    t = t / np.linalg.norm(t)
    if previous is not None and float(t @ previous) < 0:
        t = -t
    return t


def point_at(problem: CurveProblem, base: CurvePoint, sigma: float, tol: float = DEFAULT.newton) -> np.ndarray:
    """The curve point whose projection on ``base``'s tangent is ``sigma`` (for event location).

    Next to a branch point Newton converges only linearly; up to
    :data:`POINT_AT_ITERATIONS` iterations are allowed and a residual that stops improving
    below ``POINT_AT_FLOOR·tol`` is accepted there.
    """
    def hyperplane(y):
        return np.array([base.t @ (y - base.y) - sigma]), base.t[None, :]

    y, _, _ = correct(problem, base.y + sigma * base.t, extra=hyperplane, tol=tol,
                      max_iterations=POINT_AT_ITERATIONS, floor=POINT_AT_FLOOR * tol)
    return y


def _step(problem: CurveProblem, point: CurvePoint, h: float, settings: Settings, fast, guard
          ) -> CurvePoint | None:
    """One predictor–corrector step of length ``h`` from ``point``; None when it must be halved."""
    predictor = point.y + h * point.t

    def hyperplane(y, p=predictor, tt=point.t):
        return np.array([tt @ (y - p)]), tt[None, :]

    y = t_new = None
    if fast is not None:
        try:
            y, iters, t_new = fast.correct(predictor, point.t, settings.tol, settings.max_corrector_iterations)
        except NotConvergedError:
            y = None  # try the least-squares corrector before shrinking the step
    if y is None:
        try:
            y, iters, _ = correct(problem, predictor, extra=hyperplane, tol=settings.tol,
                                  max_iterations=settings.max_corrector_iterations)
        except NotConvergedError:
            return None
        t_new = None
    if np.linalg.norm(y - predictor) > settings.max_corrector_distance * h:
        return None
    if guard is not None and not guard(point, y):
        return None
    if t_new is None:
        try:
            t_new = tangent(problem, y, point.t)
        except NonFiniteError:  # a Jacobian that is not finite there: a shorter step
            return None
    elif float(t_new @ point.t) < 0:
        t_new = -t_new
    if math.acos(max(-1.0, min(1.0, float(t_new @ point.t)))) > settings.max_turn:
        return None
    return CurvePoint(y, t_new, point.s + float(np.linalg.norm(y - point.y)), iters)


def continue_curve(problem: CurveProblem, y0: np.ndarray, t0: np.ndarray,
                   settings: Settings = Settings(),
                   stop: Callable[[CurvePoint], bool] | None = None,
                   guard: Callable[[CurvePoint, np.ndarray], bool] | None = None) -> Iterator[CurvePoint]:
    """Yield points along the curve from ``y0`` in the direction of ``t0``.

    ``y0`` must be on the curve (see :func:`correct`).  Iteration ends when ``stop(point)``
    is true, after ``settings.max_steps`` accepted steps (the budget ran out: the generator
    simply ends), or by the caller; a problem with a
    ``fast_corrector`` (module docstring) has its Newton steps and tangents computed by it.
    Raises :class:`SteppingError` when the step falls below ``settings.min_step``.
    ``guard(previous, y)`` may reject a corrected point (the step is then halved), e.g. to
    bound the input change per step.
    """
    t = tangent(problem, y0, t0)
    point = CurvePoint(np.array(y0, float), t, 0.0)
    fast = getattr(problem, "fast_corrector", None)
    yield point
    h = settings.step
    for _ in range(settings.max_steps):
        accepted = None
        while accepted is None:
            if h < settings.min_step:
                raise SteppingError(f"step size fell below {settings.min_step:g} at arclength {point.s:.6g}",
                                    y=point.y, s=point.s)
            accepted = _step(problem, point, h, settings, fast, guard)
            if accepted is None:
                h *= 0.5
        point = accepted
        yield point
        if stop is not None and stop(point):
            return
        if point.corrector_iterations <= EASY_STEP:
            h = min(GROWTH * h, settings.max_step)
