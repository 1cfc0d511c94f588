"""Event location along a continued curve: sign changes and near-zero minima of test functions.

A test function is ``f(y, t) -> float`` (``t`` the oriented unit tangent).  Between two
accepted points a sign change of a *signed* test function brackets a root, which is
refined by Brent's method on the curve parametrised by the projection ``σ`` on the
first point's tangent (each trial point is a Newton projection onto the curve, see
:func:`symkin.paths.continuation.point_at`).  A *non-negative* test function (a singular
value, which touches zero without changing sign) is watched for a local minimum below a
threshold, refined by bounded Brent minimisation.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from symkin.errors import NotConvergedError
from symkin.paths.continuation import CurvePoint, CurveProblem, point_at, tangent

__all__ = ["TestFunction", "CurveEvent", "locate_sign_change", "locate_minimum", "refine_rank_drop"]


@dataclass(frozen=True)
class TestFunction:
    """A named test function; ``signed`` ones are located by sign change, others by minimum."""

    __test__ = False  # not a pytest test class

    name: str
    f: Callable[[np.ndarray, np.ndarray], float]
    signed: bool = True
    threshold: float = 1e-6  # non-negative functions: a minimum below this is an event (trace sets it from Tolerances)


@dataclass(frozen=True)
class CurveEvent:
    """A located event: which test function, where (``y``, ``t``, arclength ``s``), its value."""

    name: str
    kind: str  # "sign change" or "minimum"
    y: np.ndarray = field(repr=False)
    t: np.ndarray = field(repr=False)
    s: float
    value: float
    evaluations: int


class _Counter:
    def __init__(self, fn):
        self.fn, self.n = fn, 0

    def __call__(self, x):
        self.n += 1
        return self.fn(x)


def locate_sign_change(problem: CurveProblem, test: TestFunction, a: CurvePoint, b: CurvePoint,
                       xtol: float = 1e-14) -> CurveEvent:
    """Refine the root of ``test`` between accepted points ``a`` and ``b``."""
    sigma_b = float(a.t @ (b.y - a.y))

    def at(sigma):
        if sigma == 0.0:
            return a.y, a.t
        y = point_at(problem, a, sigma)
        return y, tangent(problem, y, a.t)

    fa, fb = test.f(a.y, a.t), test.f(b.y, b.t)

    def value(sg):
        # the bracket's ends keep the values seen at the accepted points (recomputing them at
        # a re-projected point with a re-oriented tangent could lose the sign change)
        if sg == 0.0:
            return fa
        if sg == sigma_b:
            return fb
        return test.f(*at(sg))

    f = _Counter(value)
    if fa == 0.0:
        root = 0.0
    elif fb == 0.0:
        root = sigma_b
    else:
        try:
            root = brentq(f, 0.0, sigma_b, xtol=xtol, rtol=4 * np.finfo(float).eps, maxiter=200)
        except NotConvergedError:
            # the curve cannot be projected inside the bracket: a branch point lies there.  Return
            # the end with the smaller test value; the caller refines branch points on their own.
            root = 0.0 if abs(fa) <= abs(fb) else sigma_b
    y, t = at(root) if root not in (0.0, sigma_b) else ((a.y, a.t) if root == 0.0 else (b.y, b.t))
    return CurveEvent(test.name, "sign change", y, t, a.s + _chord(a, y), test.f(y, t), f.n + 2)


def locate_minimum(problem: CurveProblem, test: TestFunction, a: CurvePoint, b: CurvePoint,
                   c: CurvePoint, xtol: float = 1e-13) -> CurveEvent | None:
    """Refine a local minimum of ``test`` bracketed by ``a``, ``b``, ``c`` (``b`` the lowest).

    Returns ``None`` when the refined minimum is above ``test.threshold``.
    """
    lo, hi = float(b.t @ (a.y - b.y)), float(b.t @ (c.y - b.y))

    def at(sigma):
        y = point_at(problem, b, sigma) if sigma != 0.0 else b.y
        return y, tangent(problem, y, b.t)

    f = _Counter(lambda sg: test.f(*at(sg)))
    res = minimize_scalar(f, bounds=(min(lo, hi), max(lo, hi)), method="bounded",
                          options={"xatol": xtol, "maxiter": 200})
    y, t = at(float(res.x))
    value = test.f(y, t)
    if not value <= test.threshold:
        return None
    return CurveEvent(test.name, "minimum", y, t, b.s + math.copysign(_chord(b, y), float(res.x)), value, f.n + 1)


def _chord(p: CurvePoint, y: np.ndarray) -> float:
    return float(np.linalg.norm(y - p.y))


def refine_rank_drop(problem: CurveProblem, y0: np.ndarray, drop: int, tol: float = 1e-14,
                     max_iterations: int = 30) -> tuple[np.ndarray, bool]:
    """The nearby point where the curve's Jacobian ``J`` has ``drop`` more left null vectors than it generically has.

    Gauss–Newton on ``H(y) = 0``, ``J(y)ᵀ ψ_i = 0``, ``ψ_i · ψ⁰_j = δ_ij`` (``i, j = 1..drop``)
    in the unknowns ``(y, ψ_1, …, ψ_drop)``; ``ψ⁰_j`` are the left singular vectors of the
    ``drop`` smallest singular values at ``y0``.  With ``drop = 1`` this is a simple branch
    point (see :func:`symkin.paths.branching.refine_singular_point`); with ``drop = 2`` it
    finds an isolated point of a family of singular configurations where the rank drops
    once more (paper §IV-A: the IM indicator's next eigenvalue vanishes too), e.g. the
    flattened Peaucellier–Lipkin inversor, whose A = B configurations are all IM but only
    one of which lies on the inversor's regular motion.  The term ``∂(Jᵀψ)/∂y`` is a
    central difference of the Jacobian.

    Returns ``(y, converged)``; ``converged`` is False when the steps did not settle.
    """
    y = np.array(y0, float)
    j = problem.jacobian(y)
    m, n = j.shape
    u, _, _ = np.linalg.svd(j, full_matrices=True)
    # a curve's Jacobian has rank n − 1: the left singular vectors of the ``drop`` smallest of
    # its n − 1 generic singular values (columns past n − 1 span the redundant equations)
    r = min(m, n - 1)
    psi0 = u[:, r - drop: r]
    psi = psi0.copy()
    eps = 1e-6
    for _ in range(max_iterations):
        h, j = problem.residual(y), problem.jacobian(y)
        rows = [np.hstack([j, np.zeros((m, m * drop))])]
        res = [h]
        for i in range(drop):
            hess = np.empty((n, n))
            for k in range(n):
                e = np.zeros(n)
                e[k] = eps
                hess[:, k] = (problem.jacobian(y + e).T @ psi[:, i] - problem.jacobian(y - e).T @ psi[:, i]) / (2 * eps)
            block = np.zeros((n, m * drop))
            block[:, m * i: m * (i + 1)] = j.T
            rows.append(np.hstack([hess, block]))
            res.append(j.T @ psi[:, i])
            for jj in range(drop):
                norm_row = np.zeros(n + m * drop)
                norm_row[n + m * i: n + m * (i + 1)] = psi0[:, jj]
                rows.append(norm_row[None, :])
                res.append([psi[:, i] @ psi0[:, jj] - (1.0 if i == jj else 0.0)])
        step = np.linalg.lstsq(np.vstack(rows), -np.concatenate(res), rcond=None)[0]
        y = y + step[:n]
        psi = psi + step[n:].reshape(drop, m).T
        if np.linalg.norm(step) <= tol * max(1.0, float(np.linalg.norm(y))):
            return y, True
    return y, False
