"""Locating a map's singular points from grid brackets: sign changes of a DKP test function (crossings), the
mode's workspace boundary (folds) and touching zeros (double zeros), polished on the extended system.

See :mod:`symkin.workspace.loci` (steps 1, 2 and 5).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from symkin.errors import NotConvergedError
from symkin.curves.corrector import gauss_newton
from symkin.tolerances import DEFAULT, Tolerances
from symkin.workspace.locus_problems import KINDS, LOCUS_NEWTON_TOL, POLISH_ITERATIONS, POLISH_STEP, LocusProblems

__all__ = ["locate_crossing", "locate_fold", "locate_double_zero"]


# ---------------------------------------------------------------------- location
def _polish(pb: LocusProblems, kind: str, a0: np.ndarray, d: np.ndarray, y: np.ndarray, s: float
            ) -> tuple[np.ndarray, float]:
    """Gauss–Newton on the extended system in ``(y, s)``; raises NotConvergedError."""
    problem = pb.extended(kind, a0, d)
    z = gauss_newton(problem.residual_and_jacobian, np.append(y, s), tol=LOCUS_NEWTON_TOL,
                     max_iterations=POLISH_ITERATIONS).raise_unless_converged("crossing").z
    # polished: one more Newton step is below the relative target
    r, j = problem.residual_and_jacobian(z)
    step = np.linalg.lstsq(j, -r, rcond=None)[0]
    if np.linalg.norm(step) > POLISH_STEP * max(1.0, float(np.linalg.norm(z[:-1]))):
        raise NotConvergedError("crossing not polished", y=z[:-1], residual=float(np.linalg.norm(r)))
    return z[:-1], float(z[-1])


def locate_crossing(pb: LocusProblems, kind: str, a_a: np.ndarray, y_a: np.ndarray, a_b: np.ndarray,
                    y_b: np.ndarray) -> tuple[np.ndarray, float]:
    """Root of ``T`` (``kind``) on the segment from dimensionless axis values ``a_a`` to ``a_b``.

    ``y_a``, ``y_b`` are the configurations of the same mode at the ends, with opposite
    signs of ``T``.  Brent's method on ``T(solve(a_a + s·d))``, warm-started from the nearer
    end, then the extended system polishes ``(y, s)``.  Returns ``(y, s)``.
    """
    d = a_b - a_a
    ta, tb = pb.tests(y_a)[kind], pb.tests(y_b)[kind]
    cache = {}

    def t_of(s):
        y0 = y_a if s <= 0.5 else y_b
        y = pb.solve_square(a_a + s * d, y0 if not cache else cache[min(cache, key=lambda k: abs(k - s))])
        cache[s] = y
        return pb.tests(y)[kind]

    # a coarse bracket is enough: the extended system polishes it quadratically
    s = brentq(lambda s: ta if s == 0 else tb if s == 1 else t_of(s), 0.0, 1.0, xtol=1e-6)
    y0 = cache.get(s, y_a if s <= 0.5 else y_b)
    return _polish(pb, kind, a_a, d, y0, s)


def locate_fold(pb: LocusProblems, a_a: np.ndarray, y_a: np.ndarray, a_b: np.ndarray,
                bisections: int = 16, tol: Tolerances = DEFAULT) -> tuple[str, np.ndarray, float]:
    """The mode's workspace boundary on the segment from assembled ``a_a`` (config ``y_a``) to ``a_b``.

    Bisection on whether the square problem solves from the last assembled point (a
    Newton step that does not converge, or that moves farther than the bracket allows,
    counts as not assembled), then the extended system with the DKP test function that is
    smaller there polishes the fold; it is accepted when the square problem is singular
    there (:meth:`LocusProblems.square_singular`), else the other function is tried.  Returns
    ``(kind, y, s)``; raises NotConvergedError when neither gives a fold (a map whose axes
    mix inputs and outputs: its folds are neither locus).
    """
    d = a_b - a_a
    lo, hi, y_lo = 0.0, 1.0, np.array(y_a, float)
    for _ in range(bisections):
        mid = 0.5 * (lo + hi)
        try:
            y = pb.solve_square(a_a + mid * d, y_lo)
        except NotConvergedError:
            hi = mid
            continue
        lo, y_lo = mid, y
    t = pb.tests(y_lo)
    tried = sorted(KINDS, key=lambda k: abs(t[k]) if math.isfinite(t[k]) else math.inf)
    for kind in tried:
        try:
            y, s = _polish(pb, kind, a_a, d, y_lo, lo)
        except NotConvergedError:
            continue
        if pb.square_singular(y, tol):
            return kind, y, s
    raise NotConvergedError("the mode's boundary here is not a zero of a DKP test function "
                            "(the square position problem stays regular where they vanish)", y=y_lo)


def locate_double_zero(pb: LocusProblems, kind: str, a0: np.ndarray, y0: np.ndarray, d: np.ndarray,
                       tol: Tolerances = DEFAULT) -> tuple[np.ndarray, float]:
    """A double zero of ``T`` (``kind``) on the line ``a0 + s·d``, ``|s| ≤ 1``, through a dip at ``a0``.

    Where ``T`` touches zero without changing sign (``T ≈ c·d²``) it has no root to bracket;
    its derivative along the line, ``∂T/∂n`` (:meth:`LocusProblems.slope`, ``n = d/|d|``), changes
    sign there instead (a simple zero).  Brent's method on ``∂T/∂n`` of the square problem
    solved along the line (from ``y0``, the dip's configuration), then Gauss–Newton on the
    extended system ``(Φ/ℓ, holds, A − (a0 + s·d), ∂T/∂n) = 0`` in ``(y, s)`` polishes it.
    The point is a double zero when ``|T|`` there is at most :attr:`Tolerances.event_threshold`
    (a located minimum of an unsigned DKP test, as a path event); the caller asks the core.
    Returns ``(y, s)``; raises NotConvergedError (no sign change of the slope on the line, a
    minimum that is not zero, or no polished point).
    """
    d = np.asarray(d, float)
    n = d / np.linalg.norm(d)
    sign = math.copysign(1.0, pb.tests(y0)[kind])
    cache = {0.0: np.asarray(y0, float)}

    def y_of(s):
        near = min(cache, key=lambda k: abs(k - s))
        y = cache[near]
        for u in np.linspace(near, s, 3)[1:]:
            y = pb.solve_square(a0 + u * d, y)
        cache[s] = y
        return y

    def g(s):
        return sign * pb.slope(kind, y_of(s), n)

    ends = [(-1.0, 0.0), (0.0, 1.0)]
    vals = {s: g(s) for s in (-1.0, 0.0, 1.0)}
    bracket = next(((lo, hi) for lo, hi in ends if vals[lo] <= 0.0 <= vals[hi]), None)
    if bracket is None:
        raise NotConvergedError("no minimum of |T| on the line through the dip")
    s = brentq(g, *bracket, xtol=1e-9)
    y = cache[min(cache, key=lambda k: abs(k - s))]
    z = gauss_newton(pb.slope_extended(kind, a0, d).residual_and_jacobian, np.append(y, s), tol=LOCUS_NEWTON_TOL,
                     max_iterations=POLISH_ITERATIONS).raise_unless_converged("double zero").z
    if not abs(z[-1]) <= 1.0 + 1e-9 or abs(pb.tests(z[:-1])[kind]) > tol.event_threshold:
        raise NotConvergedError("the minimum of |T| on the line is not a zero", y=z[:-1])
    return z[:-1], float(z[-1])
