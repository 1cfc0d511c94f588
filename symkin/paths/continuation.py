"""Pseudo-arclength continuation of a curve ``H(y) = 0``, ``H: Rⁿ → Rᵐ`` with a 1-D solution set.

Mechanism-agnostic (like pacopy): a :class:`CurveProblem` gives the residual ``H`` and its
Jacobian; :func:`continue_curve` walks the curve with adaptive steps and yields points.
Redundant equations (``m > n − 1``, overconstrained mechanisms) are fine: every linear
solve is a least-squares (SVD) solve.

Step control and guards against jumping to another branch: a step is rejected and halved
when the corrector does not converge within ``max_corrector_iterations``, when the
corrected point is farther than ``max_corrector_distance·h`` from the predictor, or when
the tangent turns by more than ``max_turn`` radians.  Easy steps grow the step by 1.5.

All quantities are dimensionless: the caller scales ``y`` (e.g. by the model's length
scale) so that the default settings make sense.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Iterator, Protocol

import numpy as np

from symkin.errors import NotConvergedError

__all__ = ["CurveProblem", "Settings", "CurvePoint", "newton", "tangent", "continue_curve",
           "point_at", "SteppingError"]


class CurveProblem(Protocol):
    """What the continuation needs: residual and Jacobian of ``H`` (dimensionless)."""

    def residual(self, y: np.ndarray) -> np.ndarray: ...

    def jacobian(self, y: np.ndarray) -> np.ndarray: ...


@dataclass(frozen=True)
class Settings:
    """Continuation settings (dimensionless units of ``y``)."""

    step: float = 0.05
    min_step: float = 1e-9
    max_step: float = 0.2
    tol: float = 1e-12
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


class NonFiniteError(NotConvergedError):
    """The residual or the Jacobian is not finite (NaN or inf) where the solver evaluates it."""


def _finite(y: np.ndarray, r: np.ndarray, j: np.ndarray) -> None:
    """Raise :class:`NonFiniteError` (with ``y``) unless ``r`` and ``j`` are finite.

    LAPACK's SVD would stop with ``LinAlgError: SVD did not converge`` on a NaN; a solver
    that meets one has not converged, and says where.

    >>> _finite(np.zeros(2), np.zeros(1), np.array([[1.0, np.nan]]))
    Traceback (most recent call last):
    ...
    symkin.paths.continuation.NonFiniteError: the Jacobian is not finite (NaN or inf) at y = [0. 0.]
    """
    for name, v in (("residual", r), ("Jacobian", j)):
        if not np.all(np.isfinite(v)):
            raise NonFiniteError(f"the {name} is not finite (NaN or inf) at y = {np.asarray(y)}", y=np.asarray(y))


def _lstsq(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        raise NonFiniteError("a least-squares system is not finite (NaN or inf)")
    return np.linalg.lstsq(a, b, rcond=None)[0]


def newton(problem: CurveProblem, y0: np.ndarray, extra=None, tol: float = 1e-12,
           max_iterations: int = 20, floor: float | None = None) -> tuple[np.ndarray, int, float]:
    """Gauss–Newton on ``H(y) = 0`` (plus optional extra equations ``extra(y) -> (r, J)``).

    Least-squares steps make redundant equations harmless.  A residual at or below ``floor``
    (default ``10·tol``) that a step can no longer reduce is accepted (a near-singular
    Jacobian at the rounding level).  Returns ``(y, iterations, residual norm)``; raises :class:`NotConvergedError` (with ``y`` and the residual reached)
    when it does not converge.
    """
    y = np.array(y0, dtype=float)
    res, step = math.inf, math.inf
    both = getattr(problem, "residual_and_jacobian", None)

    def full(yy):
        """Residual and Jacobian (one call when the problem offers it), extra equations appended."""
        if both is not None:
            r, j = both(yy)
        else:
            r, j = problem.residual(yy), problem.jacobian(yy)
        if extra is not None:
            re, je = extra(yy)
            r, j = np.concatenate([r, re]), np.vstack([j, je])
        _finite(yy, r, j)
        return r, j

    k = 0
    r, j = full(y)
    res = float(np.linalg.norm(r))
    best = res
    for k in range(1, max_iterations + 1):
        # converged: residual at the tolerance and the last step small (quadratic convergence), or
        # a residual at rounding level (near singular points Newton converges only linearly)
        if (res <= tol and step <= math.sqrt(tol)) or res <= 1e-3 * tol:
            return y, k - 1, res
        dy = _lstsq(j, -r)
        y_new = y + dy
        if not np.all(np.isfinite(y_new)):
            break
        r_new, j_new = full(y_new)
        res_new = float(np.linalg.norm(r_new))
        if res <= (10 * tol if floor is None else floor) and res_new >= res:
            # at the rounding floor already and a (near-)singular Jacobian cannot improve it: done
            return y, k - 1, res
        y, r, j, res, step = y_new, r_new, j_new, res_new, float(np.linalg.norm(dy))
        best = min(best, res)
        if res > 1e6:
            break
    if res <= tol and step <= math.sqrt(tol):
        return y, k, res
    raise NotConvergedError(f"Newton did not converge (residual {res:.3g} after {k} iterations; "
                            f"smallest {best:.3g})", y=y, residual=res, best_residual=best, iterations=k)


def tangent(problem: CurveProblem, y: np.ndarray, previous: np.ndarray | None = None) -> np.ndarray:
    """Unit tangent of the curve at ``y``, oriented along ``previous`` when given.

    Without ``previous``: the right singular vector of the smallest singular value of the
    Jacobian.  With it: the solution of ``[J; previousᵀ] t = [0; 1]``, normalised.
    """
    j = problem.jacobian(y)
    _finite(y, np.zeros(0), j)
    if previous is None:
        t = np.linalg.svd(j, full_matrices=True)[2][-1]
    else:
        a = np.vstack([j, previous[None, :]])
        b = np.zeros(a.shape[0])
        b[-1] = 1.0
        t = _lstsq(a, b)
    t = t / np.linalg.norm(t)
    if previous is not None and float(t @ previous) < 0:
        t = -t
    return t


def point_at(problem: CurveProblem, base: CurvePoint, sigma: float, tol: float = 1e-12) -> np.ndarray:
    """The curve point whose projection on ``base``'s tangent is ``sigma`` (for event location).

    Next to a branch point Newton converges only linearly; up to 50 iterations are allowed
    and a residual that stops improving below ``1e3·tol`` is accepted there.
    """
    def hyperplane(y):
        return np.array([base.t @ (y - base.y) - sigma]), base.t[None, :]

    y, _, _ = newton(problem, base.y + sigma * base.t, extra=hyperplane, tol=tol, max_iterations=50,
                     floor=1e3 * tol)
    return y


def continue_curve(problem: CurveProblem, y0: np.ndarray, t0: np.ndarray,
                   settings: Settings = Settings(),
                   stop: Callable[[CurvePoint], bool] | None = None,
                   guard: Callable[[CurvePoint, np.ndarray], bool] | None = None) -> Iterator[CurvePoint]:
    """Yield points along the curve from ``y0`` in the direction of ``t0``.

    ``y0`` must be on the curve (see :func:`newton`).  Iteration ends when ``stop(point)``
    is true, after ``settings.max_steps``, or by the caller; a problem with a
    ``fast_corrector`` (:mod:`symkin.paths.generated`) has its Newton steps and tangents
    computed by generated code.  Raises :class:`SteppingError`
    when the step falls below ``settings.min_step``.  ``guard(previous, y)`` may reject a
    corrected point (the step is then halved), e.g. to bound the input change per step.
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
            predictor = point.y + h * point.t

            def hyperplane(y, p=predictor, tt=point.t):
                return np.array([tt @ (y - p)]), tt[None, :]

            try:
                y = None
                if fast is not None:
                    try:
                        y, iters, t_new = fast.correct(predictor, point.t, settings.tol,
                                                       settings.max_corrector_iterations)
                    except NotConvergedError:
                        y = None  # try the least-squares corrector before shrinking the step
                if y is None:
                    y, iters, _ = newton(problem, predictor, extra=hyperplane, tol=settings.tol,
                                         max_iterations=settings.max_corrector_iterations)
                    t_new = None
            except NotConvergedError:
                h *= 0.5
                continue
            if np.linalg.norm(y - predictor) > settings.max_corrector_distance * h:
                h *= 0.5
                continue
            if guard is not None and not guard(point, y):
                h *= 0.5
                continue
            if t_new is None:
                try:
                    t_new = tangent(problem, y, point.t)
                except NonFiniteError:  # a Jacobian that is not finite there: a shorter step
                    h *= 0.5
                    continue
            elif float(t_new @ point.t) < 0:
                t_new = -t_new
            if math.acos(max(-1.0, min(1.0, float(t_new @ point.t)))) > settings.max_turn:
                h *= 0.5
                continue
            accepted = CurvePoint(y, t_new, point.s + float(np.linalg.norm(y - point.y)), iters)
        point = accepted
        yield point
        if stop is not None and stop(point):
            return
        if point.corrector_iterations <= 3:
            h = min(1.5 * h, settings.max_step)
