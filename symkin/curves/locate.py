"""Location on a curve: roots and minima of a test along it, and the one singular-point locator.

A *test* is any object with a ``name``, a ``value(y, t) -> float`` (``t`` the oriented unit
tangent) and, for minima, a ``threshold`` (:class:`symkin.curves.events.EventType` is one).

* :func:`locate_sign_change` — between two accepted points a sign change of a *signed* test
  brackets a root, refined by Brent's method on the curve parametrised by the projection
  ``σ`` on the first point's tangent (each trial point is a Newton projection onto the
  curve, :func:`symkin.curves.stepper.point_at`);
* :func:`locate_minimum` — a *non-negative* test (a singular value, which touches zero
  without changing sign) is refined by bounded Brent minimisation;
* :func:`locate_singular_point` — THE singular-point locator: where the curve's Jacobian
  ``J`` (``m × n``, generic rank ``n − 1``) has ``drop`` more left null vectors, i.e.

      H(y) = 0,   J(y)ᵀ ψ_i = 0,   ψ_i · ψ⁰_j = δ_ij,   Zᵀ ψ_i = 0     (i, j = 1..drop)    (1)

  in the unknowns ``(y, ψ_1, …, ψ_drop)`` (``ψ⁰_j`` the left singular vectors of the ``drop``
  smallest generic singular values at the start, ``Z`` the left null vectors of redundant
  equations).  ``drop = 1`` is a branch point (IM configuration of a 1-DOF mechanism);
  ``drop = 2`` an isolated point of a family of singular configurations where the rank drops
  once more (the flattened Peaucellier–Lipkin inversor).  Every derivative is CasADi's,
  exact.  Where (1) is itself singular at the point Newton reaches (two tangent branches:
  the double butterfly's contact with its LIM branch, paper Figs. 3(b), 4), Newton converges
  only linearly, to about ``√ε``; the locator then *deflates* (Leykin, Verschelde & Zhao,
  Theor. Comput. Sci. 2006), appending ``DF(z) ξ = 0, ξ₀ · ξ = 1`` in the unknowns
  ``(z, ξ)``, whose solution is regular again;
* :func:`refine_singular` — a located IM event moved onto its branch point, or onto the
  isolated point of higher nullity next to it; :func:`polish` — a located point projected
  onto the closure ``H(y) = 0`` without sliding along a family of singular configurations.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from symkin.curves.corrector import gauss_newton
from symkin.curves.stepper import CurvePoint, CurveProblem, point_at, tangent
from symkin.errors import NotConvergedError
from symkin.tolerances import DEFAULT

__all__ = ["CurveEvent", "SingularPoint", "locate_sign_change", "locate_minimum", "locate_singular_point",
           "as_casadi", "nullity", "polish", "refine_singular", "MAX_DEFLATIONS"]

#: Brent's tolerance on the projection σ of a sign change (dimensionless: a few roundings of |y| ~ 1)
SIGN_CHANGE_XTOL = DEFAULT.sign_change_xtol
#: Brent's tolerance on σ of a minimum (a minimum is flat: σ is determined to ~√ε of the test only)
MINIMUM_XTOL = DEFAULT.minimum_xtol
#: Brent's iterations at most (bisection of a unit bracket to ~1e-14 takes ~47)
BRENT_ITERATIONS = 200
#: at most this many deflations (each doubles the unknowns; the double butterfly's tangent contacts need 2,
#: and on a family of singular points, e.g. Peaucellier–Lipkin with A = B, no number of deflations helps)
MAX_DEFLATIONS = 2
#: the system (1) counts as singular where the smallest singular value of its Jacobian is below this
#: fraction of the largest (rounding of the Newton-reached point is ~1e-8 relative there: 1e-7 is above it)
DEFLATE_SINGULAR = DEFAULT.deflate_singular
#: a next singular value of ``J`` below this fraction of the largest may hide a point of higher nullity
HIGHER_NULLITY = 0.05
#: nullity of a curve's Jacobian at a branch point (a curve's generic nullity is 1)
BRANCH_NULLITY = 2
#: iterations of the closure polish (quadratic convergence from a located point takes 1–3)
POLISH_ITERATIONS = 8


@dataclass(frozen=True)
class CurveEvent:
    """A located event: which test, how (``"sign change"`` or ``"minimum"``), where (``y``, ``t``, arclength ``s``), its value."""

    name: str
    kind: str
    y: np.ndarray = field(repr=False)
    t: np.ndarray = field(repr=False)
    s: float
    value: float
    evaluations: int


@dataclass(frozen=True)
class SingularPoint:
    """Result of :func:`locate_singular_point`: ``y`` and its left null vectors ``psi`` ((m,) for ``drop = 1``, else (m, drop)).

    ``deflations`` counts how many times system (1) of the module docstring was deflated
    because it was singular there (0 at a simple branch point, 2 at the double butterfly's
    tangent contacts); ``converged`` is the corrector's verdict on the last system;
    ``residual`` is ``max |H(y)|``.
    """

    y: np.ndarray = field(repr=False)
    psi: np.ndarray = field(repr=False)
    deflations: int
    converged: bool
    residual: float
    iterations: int


class _Counter:
    def __init__(self, fn):
        self.fn, self.n = fn, 0

    def __call__(self, x):
        self.n += 1
        return self.fn(x)


def _chord(p: CurvePoint, y: np.ndarray) -> float:
    return float(np.linalg.norm(y - p.y))


def locate_sign_change(problem: CurveProblem, test, a: CurvePoint, b: CurvePoint,
                       xtol: float = SIGN_CHANGE_XTOL) -> CurveEvent:
    """Refine the root of ``test`` between accepted points ``a`` and ``b``."""
    sigma_b = float(a.t @ (b.y - a.y))

    def at(sigma):
        if sigma == 0.0:
            return a.y, a.t
        y = point_at(problem, a, sigma)
        return y, tangent(problem, y, a.t)

    fa, fb = test.value(a.y, a.t), test.value(b.y, b.t)

    def value(sg):
        # the bracket's ends keep the values seen at the accepted points (recomputing them at
        # a re-projected point with a re-oriented tangent could lose the sign change)
        if sg == 0.0:
            return fa
        if sg == sigma_b:
            return fb
        return test.value(*at(sg))

    f = _Counter(value)
    if fa == 0.0:
        root = 0.0
    elif fb == 0.0:
        root = sigma_b
    else:
        try:
            from scipy.optimize import brentq  # here: importing scipy.optimize costs 0.1-0.3 s (issue 17)

            root = brentq(f, 0.0, sigma_b, xtol=xtol, rtol=4 * np.finfo(float).eps, maxiter=BRENT_ITERATIONS)
        except NotConvergedError:
            # the curve cannot be projected inside the bracket: a branch point lies there.  Return
            # the end with the smaller test value; the caller refines branch points on their own.
            root = 0.0 if abs(fa) <= abs(fb) else sigma_b
    y, t = at(root) if root not in (0.0, sigma_b) else ((a.y, a.t) if root == 0.0 else (b.y, b.t))
    return CurveEvent(test.name, "sign change", y, t, a.s + _chord(a, y), test.value(y, t), f.n + 2)


def locate_minimum(problem: CurveProblem, test, a: CurvePoint, b: CurvePoint, c: CurvePoint,
                   xtol: float = MINIMUM_XTOL) -> CurveEvent | None:
    """Refine a local minimum of ``test`` bracketed by ``a``, ``b``, ``c`` (``b`` the lowest).

    Returns ``None`` when the refined minimum is above ``test.threshold``.
    """
    lo, hi = float(b.t @ (a.y - b.y)), float(b.t @ (c.y - b.y))

    def at(sigma):
        y = point_at(problem, b, sigma) if sigma != 0.0 else b.y
        return y, tangent(problem, y, b.t)

    f = _Counter(lambda sg: test.value(*at(sg)))
    from scipy.optimize import minimize_scalar

    res = minimize_scalar(f, bounds=(min(lo, hi), max(lo, hi)), method="bounded",
                          options={"xatol": xtol, "maxiter": BRENT_ITERATIONS})
    y, t = at(float(res.x))
    value = test.value(y, t)
    if not value <= test.threshold:
        return None
    return CurveEvent(test.name, "minimum", y, t, b.s + math.copysign(_chord(b, y), float(res.x)), value, f.n + 1)


# ---------------------------------------------------------------------- singular points
class _ProblemCallback(ca.Callback):
    """A numeric problem (``residual_and_jacobian`` or ``residual`` / ``jacobian``) as a CasADi Function.

    Its derivatives are CasADi's central finite differences: the locator's exact derivatives
    need a ``casadi_function``; this is for problems that have none.
    """

    def __init__(self, problem, n: int, m: int):
        ca.Callback.__init__(self)
        self.problem, self.n, self.m = problem, n, m
        self.construct("problem", {"enable_fd": True, "fd_method": "central"})

    def get_n_in(self):
        return 1

    def get_n_out(self):
        return 2

    def get_sparsity_in(self, i):
        return ca.Sparsity.dense(self.n, 1)

    def get_sparsity_out(self, i):
        return ca.Sparsity.dense(self.m, 1) if i == 0 else ca.Sparsity.dense(self.m, self.n)

    def eval(self, arg):
        y = np.array(arg[0], float).ravel()
        both = getattr(self.problem, "residual_and_jacobian", None)
        h, j = both(y) if both is not None else (self.problem.residual(y), self.problem.jacobian(y))
        return [ca.DM(np.asarray(h, float).reshape(self.m, 1)), ca.DM(np.asarray(j, float))]


def as_casadi(problem, y0: np.ndarray) -> ca.Function:
    """``y ↦ (H, J)`` of ``problem`` as a CasADi Function: its ``casadi_function`` when it has one."""
    if isinstance(problem, ca.Function):
        return problem
    own = getattr(problem, "casadi_function", None)
    if own is not None:
        return own
    j = np.asarray(problem.jacobian(np.asarray(y0, float)), float)
    return _ProblemCallback(problem, j.shape[1], j.shape[0])


def _singular_system(f: ca.Function, y0: np.ndarray, drop: int):
    """Unknowns ``z = (y, ψ_1..ψ_drop)``, system (1) of the module docstring and its start ``z0``."""
    n = y0.size
    h0, j0 = (np.array(v, float) for v in f(y0))
    m = j0.shape[0]
    u, _, _ = np.linalg.svd(j0, full_matrices=True)
    r = min(m, n - 1)  # a curve's generic rank; columns past it span the redundant equations
    psi0, zred = u[:, r - drop: r], u[:, r:]
    sym = ca.SX if f.is_a("SXFunction") else ca.MX
    y, psi = sym.sym("y", n), sym.sym("psi", m, drop)
    h, j = f(y)
    parts = [h]
    for i in range(drop):
        parts.append(ca.mtimes(j.T, psi[:, i]))
        parts.append(ca.mtimes(ca.DM(psi0).T, psi[:, i]) - ca.DM(np.eye(drop)[:, i]))
        if zred.shape[1]:
            parts.append(ca.mtimes(ca.DM(zred).T, psi[:, i]))
    z = ca.vertcat(y, ca.vec(psi))
    return z, ca.vertcat(*parts), np.concatenate([y0, psi0.T.ravel()]), sym


def locate_singular_point(problem, y0: np.ndarray, drop: int = 1, tol: float = DEFAULT.locate,
                          max_iterations: int = 30, singular: float = DEFLATE_SINGULAR,
                          max_deflations: int = MAX_DEFLATIONS) -> SingularPoint:
    """The point next to ``y0`` where ``J`` loses ``drop`` more ranks: Newton on (1), deflated where (1) is singular.

    ``problem`` is a CasADi Function ``y ↦ (H, J)`` or a problem with a ``casadi_function``
    (:class:`symkin.paths.system.MechanismCurve`); any other problem gets central-difference
    second derivatives (:func:`as_casadi`).  Newton is the one corrector
    (:func:`~symkin.curves.corrector.gauss_newton`) with ``step_tol = tol``
    (``Tolerances.locate``): the system need not reach a residual of ``tol`` in floating
    point.  ``singular`` is the relative size of the smallest singular value of ``DF``
    below which (1) counts as singular at the point Newton reached (its null vector starts
    ξ); ``max_deflations = 0`` is plain Newton on (1).

    Examples
    --------
    A flattened change-point four-bar (a simple branch point, no deflation) and the double
    butterfly's tangent contacts (two deflations): ``tests/curves/test_locate.py``.
    """
    f = as_casadi(problem, y0)
    y0 = np.asarray(y0, float)
    n = y0.size
    w, G, start, sym = _singular_system(f, y0, drop)
    size = int(w.numel())
    deflations, iters = 0, 0
    while True:
        dG = ca.jacobian(G, w)
        fun = ca.Function("singular_point", [w], [G, dG])
        if sym is ca.MX:
            try:
                fun = fun.expand()
            except RuntimeError:  # a callback inside: stays an MX Function
                pass
        c = gauss_newton(lambda v: tuple(np.array(a, float) for a in fun(v)), start, tol=tol,
                         max_iterations=max_iterations, step_tol=tol)
        iters += c.iterations
        if deflations >= max_deflations:
            break
        dg = np.array(fun(c.z)[1], float)
        s = np.linalg.svd(dg, compute_uv=False)
        if s[-1] > singular * s[0]:
            break
        # singular: append DG ξ = 0, ξ₀ · ξ = 1 (ξ₀ its null vector here) and solve again
        xi0 = np.linalg.svd(dg, full_matrices=False)[2][-1]
        xi = sym.sym(f"xi{deflations}", xi0.size)
        G = ca.vertcat(G, ca.mtimes(dG, xi), ca.dot(ca.DM(xi0), xi) - 1)
        w, start = ca.vertcat(w, xi), np.concatenate([c.z, xi0])
        deflations += 1
    z = c.z[:size]
    y = z[:n]
    res = float(np.max(np.abs(np.array(f(y)[0], float)), initial=0.0))
    psi = z[n:].reshape(drop, -1).T
    return SingularPoint(y, psi[:, 0] if drop == 1 else psi, deflations, c.converged, res, iters)


def nullity(problem: CurveProblem, y: np.ndarray, rank: float = DEFAULT.rank) -> int:
    """Nullity of the curve's Jacobian at ``y``: singular values at most ``rank`` times the largest count as zero."""
    j = problem.jacobian(y)
    s = np.linalg.svd(j, compute_uv=False)
    top = float(s.max()) if s.size else 0.0
    return j.shape[1] - int(np.count_nonzero(s > rank * top))


def polish(problem: CurveProblem, y: np.ndarray, tol: float = DEFAULT.closure, rank: float = DEFAULT.rank,
           max_iterations: int = POLISH_ITERATIONS) -> np.ndarray:
    """Project a located point onto the closure ``H(y) = 0`` (paper eq. 5, made dimensionless).

    Gauss–Newton (the one corrector) with minimum-norm steps on the well-conditioned part of
    the Jacobian (singular values above ``rank`` relative to the largest): at a singular
    configuration the near-null directions are left alone, so the point moves by the least
    amount that closes the loop, and it does not slide along a family of singular
    configurations.  Stops at ``|H| <= tol`` (``Tolerances.closure``) or where a step no
    longer reduces ``|H|``.
    """
    def fun(z):
        return problem.residual(z), problem.jacobian(z)

    return gauss_newton(fun, y, tol=tol, max_iterations=max_iterations, floor=math.inf, rcond=rank).z


def _higher_rank_drop(problem: CurveProblem, y: np.ndarray, radius: float, rank: float) -> np.ndarray:
    """The isolated point of higher nullity next to a branch point ``y``, when there is one.

    When the next singular value of the Jacobian is small as well (below
    :data:`HIGHER_NULLITY` relative to the largest) the branch point may lie on a family of
    singular configurations that the curve crosses at a point of higher nullity
    (Peaucellier–Lipkin with A = B).  It is accepted only when the locator converged within
    ``radius`` of ``y`` and its nullity at ``rank`` is larger.
    """
    j = problem.jacobian(y)
    n = j.shape[1]
    s = np.sort(np.concatenate([np.linalg.svd(j, compute_uv=False), np.zeros(max(0, n - j.shape[0]))]))
    base = nullity(problem, y, rank)
    if base < 2 or base + 1 > s.size or s[base] > HIGHER_NULLITY * s[-1]:
        return y
    hi = locate_singular_point(problem, y, base, max_deflations=0)
    if hi.converged and np.linalg.norm(hi.y - y) <= radius and nullity(problem, hi.y, rank) > base:
        return hi.y
    return y


def refine_singular(problem: CurveProblem, y: np.ndarray, t: np.ndarray, radius: float,
                    rank: float = DEFAULT.rank) -> tuple[np.ndarray, np.ndarray]:
    """A located IM event ``(y, t)`` moved onto its branch point, or the point of higher nullity next to it.

    The branch point (:func:`locate_singular_point`, ``drop = 1``) is kept where the
    Jacobian is rank-deficient there at ``rank`` (nullity at least :data:`BRANCH_NULLITY`)
    and no less than at ``y``: on a family of singular configurations (e.g. the
    Peaucellier–Lipkin inversor with A = B) system (1) slides along the family away from the
    point the curve crosses, and where the curve's Jacobian keeps its generic rank (an
    over-constrained linkage's IM test dipping without a branch point)
    system (1) has no solution nearby and Newton wanders off.  ``radius`` bounds the move to a point of higher nullity
    (the length of the continuation step that bracketed the event).
    """
    bp = locate_singular_point(problem, y)
    if nullity(problem, bp.y, rank) >= max(nullity(problem, y, rank), BRANCH_NULLITY):
        y, t = bp.y, tangent(problem, bp.y, t)
    return _higher_rank_drop(problem, y, radius, rank), t
