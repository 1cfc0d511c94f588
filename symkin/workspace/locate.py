"""Locating a map's singular points from grid brackets: sign changes of a DKP test function (crossings), the
mode's workspace boundary (folds) and touching zeros (double zeros), polished on the extended system.

See :mod:`symkin.workspace.loci` (steps 1, 2 and 5).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from symkin.errors import NotConvergedError
from symkin.curves.corrector import gauss_newton, gauss_newton_batch, stacked_steps
from symkin.tolerances import DEFAULT, Tolerances
from symkin.workspace.locus_problems import KINDS, LOCUS_NEWTON_TOL, POLISH_ITERATIONS, POLISH_STEP, LocusProblems

__all__ = ["locate_crossing", "locate_crossings", "locate_fold", "locate_double_zero", "CROSSING_STEPS",
           "CROSSING_XTOL"]

#: regula-falsi (Illinois) steps of the batched crossing locator, at most (each one batched square solve)
CROSSING_STEPS = 40
#: a bracket of the batched locator is done when its root estimate moves less than this (fraction of the
#: grid edge; as the single locator's Brent tolerance: the extended system polishes it quadratically)
CROSSING_XTOL = 1e-6


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
    s = brentq(lambda s: ta if s == 0 else tb if s == 1 else t_of(s), 0.0, 1.0, xtol=CROSSING_XTOL)
    y0 = cache.get(s, y_a if s <= 0.5 else y_b)
    return _polish(pb, kind, a_a, d, y0, s)


def locate_crossings(pb: LocusProblems, kind: str, a_a: np.ndarray, y_a: np.ndarray, a_b: np.ndarray,
                     y_b: np.ndarray) -> list[tuple[np.ndarray, float] | None]:
    """:func:`locate_crossing` on N grid edges at once (rows of the arguments): ``(y, s)`` or None per edge.

    Regula falsi (the Illinois variant) on ``T(solve(a_a + s·d))`` for every bracket at once:
    each step is one batched solve of the square problem (:meth:`LocusProblems.solve_square_many`,
    warm-started from the bracket's nearer end) and one batched evaluation of ``T``; a bracket
    is done when its estimate moves less than :data:`CROSSING_XTOL`.  Then one batched
    Gauss–Newton polishes all of them on the extended system (:meth:`LocusProblems.extended_many`),
    accepted where one more step is below ``POLISH_STEP`` (as :func:`locate_crossing`).  None
    where the square problem does not solve inside the bracket or the polish fails.
    """
    a_a, a_b = np.atleast_2d(np.asarray(a_a, float)), np.atleast_2d(np.asarray(a_b, float))
    ylo, yhi = np.array(np.atleast_2d(y_a), float), np.array(np.atleast_2d(y_b), float)
    n = len(a_a)
    if n == 0:
        return []
    d = a_b - a_a
    t = pb.tests_many(np.vstack([ylo, yhi]))[kind]
    fa, fb = t[:n].copy(), t[n:].copy()
    lo, hi = np.zeros(n), np.ones(n)
    s, y = np.where(np.abs(fa) <= np.abs(fb), 0.0, 1.0), np.where((np.abs(fa) <= np.abs(fb))[:, None], ylo, yhi)
    ok = np.isfinite(fa) & np.isfinite(fb) & (np.sign(fa) * np.sign(fb) <= 0)
    active = ok & (fa != 0) & (fb != 0)
    side, last = np.zeros(n), np.full(n, np.nan)
    for _ in range(CROSSING_STEPS):
        idx = np.nonzero(active)[0]
        if idx.size == 0:
            break
        sn = np.clip((lo[idx] * fb[idx] - hi[idx] * fa[idx]) / (fb[idx] - fa[idx]), lo[idx], hi[idx])
        start = np.where((sn - lo[idx] <= hi[idx] - sn)[:, None], ylo[idx], yhi[idx])
        yy, conv = pb.solve_square_many(a_a[idx] + sn[:, None] * d[idx], start)
        ft = np.full(idx.size, np.nan)
        if np.any(conv):
            ft[conv] = pb.tests_many(yy[conv])[kind]
        bad = ~conv | ~np.isfinite(ft)
        ok[idx[bad]] = active[idx[bad]] = False
        i, sn, yy, ft = idx[~bad], sn[~bad], yy[~bad], ft[~bad]
        s[i], y[i] = sn, yy
        low = np.sign(ft) == np.sign(fa[i])
        for sel, cur, other, sgn in ((low, (lo, fa, ylo), fb, -1.0), (~low, (hi, fb, yhi), fa, 1.0)):
            j = i[sel]
            cur[0][j], cur[1][j], cur[2][j] = sn[sel], ft[sel], yy[sel]
            again = side[j] == sgn
            other[j[again]] *= 0.5  # Illinois: the end kept twice in a row has its value halved
            side[j] = sgn
        done = (np.abs(sn - last[i]) < CROSSING_XTOL) | (ft == 0)
        last[i] = sn
        active[i[done]] = False
    idx = np.nonzero(ok)[0]
    out: list = [None] * n
    if idx.size == 0:
        return out

    def fun(z, rows):
        return pb.extended_many(kind, z, a_a[idx[rows]], d[idx[rows]])

    res = gauss_newton_batch(fun, np.hstack([y[idx], s[idx, None]]), tol=LOCUS_NEWTON_TOL,
                             max_iterations=POLISH_ITERATIONS, norm="2")
    good = np.nonzero(res.converged)[0]
    if good.size:
        z = res.z[good]
        r, j = fun(z, good)
        r = np.asarray(r, float).reshape(len(z), -1)
        step = stacked_steps(np.asarray(j, float).reshape(len(z), r.shape[1], z.shape[1]), r)
        size = np.linalg.norm(step, axis=1)
        polished = size <= POLISH_STEP * np.maximum(1.0, np.linalg.norm(z[:, :-1], axis=1))
        for k, zz, keep in zip(idx[good], z, polished):
            if keep:
                out[k] = (zz[:-1].copy(), float(zz[-1]))
    return out


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
