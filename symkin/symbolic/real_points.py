"""Whether a plane curve ``f(x, y) = 0`` has a real curve, or only isolated real points (issue 17 §4).

An irreducible real polynomial whose zero set contains a nonsingular real point changes sign
there; one that never changes sign is ``≥ 0`` (or ``≤ 0``) everywhere, so that its real zeros
are global extrema: real *critical points* (``f_x = f_y = 0``) where ``f`` vanishes, finitely
many for an irreducible ``f``.  So:

1. the signs of ``f`` at its real critical points and on a few circles of sample points: both
   signs → a real curve;
2. otherwise the real zero set is the critical points where ``f`` vanishes (relative to the sum
   of the absolute values of its terms, :data:`ZERO`): none (no real point, a trivial factor)
   or a few isolated points — the "circle of radius 0" of a point, for any degree.

The critical points come from the resultant ``Res_x(f_x, f_y)`` (its real roots ``y``, then
the common real roots ``x``), numerically; beyond :data:`MAX_DEGREE` the test is not made
(the factor is taken as a curve).
"""
from __future__ import annotations

import math

import numpy as np
import sympy as sp

__all__ = ["isolated_real_points", "MAX_DEGREE", "ZERO"]

#: highest total degree tested (the resultant of the two partial derivatives has degree ≤ (d − 1)²)
MAX_DEGREE = 8
#: a value of ``f`` (over the sum of the absolute values of its terms) at most this is a zero
ZERO = 1e-9
#: a numerical root is real, and a gradient component zero, at most this (relative; roots of the
#: resultant of a degree-8 curve are accurate to about the square root of the rounding)
ROOT = 1e-6
#: a floor that keeps a relative comparison defined at zero
_FLOOR = 1e-300


def _relative(p: sp.Poly, x: float, y: float) -> tuple[float, float]:
    """``f(x, y)`` and the sum of the absolute values of its terms there."""
    val = mag = 0.0
    for (i, j), c in p.terms():
        t = float(c) * x ** i * y ** j
        val += t
        mag += abs(t)
    return val, mag


def _real_roots(p: sp.Poly) -> list[float]:
    """The (numerically) real roots of a univariate polynomial, by its companion matrix."""
    exact = p.all_coeffs()
    big = max(abs(c) for c in exact)  # scaled exactly first: long integer coefficients overflow a float
    coeffs = np.array([float(c / big) for c in exact])
    return [float(r.real) for r in np.roots(coeffs) if abs(r.imag) <= ROOT * (1 + abs(r))]


def _critical_points(p: sp.Poly) -> list[tuple[float, float]] | None:
    """The real solutions of ``f_x = f_y = 0`` (None when they are not finitely many)."""
    x, y = p.gens
    fx, fy = p.diff(x), p.diff(y)
    if fx.is_zero or fy.is_zero:
        return None
    res = sp.Poly(sp.resultant(fx.as_expr(), fy.as_expr(), x), y)
    if res.is_zero:
        return None
    ys = [0.0] if res.degree() <= 0 else _real_roots(res)
    points = []
    for yv in sorted(set(round(v, 12) for v in ys)):
        gx = sp.Poly(fx.as_expr().subs(y, yv), x)
        xs = [0.0] if gx.degree() <= 0 else _real_roots(gx)
        for xv in xs:
            gxv, gxm = _relative(fx, xv, yv)
            gyv, gym = _relative(fy, xv, yv)
            if abs(gxv) <= ROOT * max(gxm, _FLOOR) and abs(gyv) <= ROOT * max(gym, _FLOOR):
                points.append((xv, yv))
    return points


def isolated_real_points(f: sp.Expr, xs) -> list[tuple[float, float]] | None:
    """The real points of ``f = 0`` when they are isolated, else None (a real curve, or not tested).

    >>> x, y = sp.symbols("x y", real=True)
    >>> isolated_real_points(x**2 + y**2 + 1, (x, y)), isolated_real_points((x - 1)**2 + 2*y**2, (x, y))
    ([], [(1.0, 0.0)])
    >>> isolated_real_points(x**6 + y**6 + 14*x**4 + 49*x**2 + 45*y**2, (x, y)), isolated_real_points(x**2 - y, (x, y))
    ([(0.0, 0.0)], None)
    """
    p = sp.Poly(f, *xs)
    d = p.total_degree()
    if d < 1 or d > MAX_DEGREE:
        return None
    crit = _critical_points(p)
    if crit is None:
        return None
    radius = 1.0 + max((abs(float(c)) for c in p.coeffs()), default=1.0) / max(
        abs(float(c)) for m, c in p.terms() if sum(m) == d)
    samples = [(r * math.cos(a), r * math.sin(a)) for r in (0.1 * radius, radius, 10 * radius)
               for a in np.linspace(0.0, 2 * math.pi, 37)[:-1]]
    signs, zeros = set(), []
    for px, py in crit + samples:
        val, mag = _relative(p, px, py)
        if abs(val) <= ZERO * max(mag, _FLOOR):
            if (px, py) in crit:
                zeros.append((px, py))
            continue
        signs.add(val > 0)
    if len(signs) > 1:
        return None
    out = []
    for px, py in zeros:
        if all(math.hypot(px - qx, py - qy) > ZERO * (1 + math.hypot(px, py)) for qx, qy in out):
            out.append((round(px, 12) + 0.0, round(py, 12) + 0.0))
    return out
