"""Branch switching at bifurcation points of a curve ``H(y) = 0`` (IM configurations).

At a simple bifurcation the Jacobian ``J`` of ``H`` loses one rank: its null space ``N``
is 2-dimensional and its left null space contains a vector ``ψ`` it did not have.  A
branch tangent ``v = N c`` must satisfy the second-order condition
``ψᵀ H''[v, v] = 0`` — a quadratic form in ``c`` (the algebraic bifurcation equation)
built from the constraint Hessians.  Two real roots give the two branch directions;
a zero discriminant (tangent branches, as in the paper's Fig. 4, or a cusp) is
*degenerate*: the second-order analysis cannot tell the branches apart, and we say so.
With several left null vectors (redundant constraints) all forms must vanish together.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from symkin.curves.stepper import CurveProblem
from symkin.tolerances import DEFAULT

__all__ = ["Bifurcation", "branch_directions", "second_derivative"]


@dataclass(frozen=True)
class Bifurcation:
    """Result of the second-order analysis at ``y``.

    ``directions`` are unit tangents (one per branch, each sign gives the two halves);
    ``status`` is ``"simple"``, ``"degenerate"`` (tangent branches / higher order),
    ``"isolated"`` (no real branch through the point besides none), or ``"regular"`` (no
    rank loss: not a bifurcation).
    """

    status: str
    directions: tuple[np.ndarray, ...] = field(repr=False)
    nullity: int
    discriminant: float | None
    message: str


def second_derivative(problem: CurveProblem, y: np.ndarray, v: np.ndarray, eps: float = 1e-5) -> np.ndarray:
    """``H''(y)[v, v]`` by a central difference of the Jacobian (exact for quadratic ``H``).

    A problem may provide ``second_derivative(y, v)`` itself (e.g. from CasADi Hessians);
    it is used when present.
    """
    own = getattr(problem, "second_derivative", None)
    if own is not None:
        return own(y, v)
    return (problem.jacobian(y + eps * v) - problem.jacobian(y - eps * v)) @ v / (2 * eps)


def branch_directions(problem: CurveProblem, y: np.ndarray, rank_tol: float | None = None,
                      degenerate_tol: float = 1e-6) -> Bifurcation:
    """Tangent directions of the branches through ``y`` (see module docstring).

    ``rank_tol`` (relative to the largest singular value) defaults to the path events'
    threshold, :attr:`Tolerances.event_threshold <symkin.tolerances.Tolerances.event_threshold>`.
    """
    if rank_tol is None:
        rank_tol = DEFAULT.event_threshold
    j = problem.jacobian(y)
    n = j.shape[1]
    _, s, vt = np.linalg.svd(j, full_matrices=True)
    s_full = np.zeros(n)
    s_full[: s.size] = s
    scale = s_full.max() if s_full.size else 1.0
    rank = int(np.count_nonzero(s_full > rank_tol * scale))
    nullity = n - rank
    if nullity <= 1:
        return Bifurcation("regular", (vt[-1],), nullity, None, "the Jacobian has full rank: a regular point")
    if nullity > 2:
        return Bifurcation("degenerate", (), nullity, None,
                           f"the null space has dimension {nullity}: more than one extra motion; "
                           "the quadratic branch equations are not solved for this case")
    basis = vt[rank:].T  # (n, 2)
    u, _, _ = np.linalg.svd(j, full_matrices=True)
    left = u[:, rank:]  # left null vectors
    forms = []
    for psi in left.T:
        q11 = psi @ second_derivative(problem, y, basis[:, 0])
        q22 = psi @ second_derivative(problem, y, basis[:, 1])
        qp = psi @ second_derivative(problem, y, basis[:, 0] + basis[:, 1])
        qm = psi @ second_derivative(problem, y, basis[:, 0] - basis[:, 1])
        forms.append((q11, (qp - qm) / 4.0, q22))
    forms = np.array(forms)
    size = np.abs(forms).max()
    if size == 0.0:
        return Bifurcation("degenerate", (), 2, 0.0, "the second-order terms vanish: higher-order analysis needed")
    forms /= size
    if len(forms) == 1:
        a, b, c = forms[0]
        disc = b * b - a * c
        if disc < -degenerate_tol:
            return Bifurcation("isolated", (), 2, float(disc), "no real branch: an isolated point of the curve")
        if disc <= degenerate_tol:
            return Bifurcation("degenerate", (), 2, float(disc),
                               "tangent branches (zero discriminant of the second-order equation): "
                               "the branches share their tangent and cannot be separated at second order")
        roots = _quadratic_directions(a, b, c, disc)
    else:
        roots = _common_directions(forms, degenerate_tol)
        disc = None
        if len(roots) < 2:
            return Bifurcation("degenerate", tuple(basis @ r for r in roots), 2, None,
                               "fewer than two distinct branch directions satisfy every second-order equation")
    dirs = tuple((basis @ r) / np.linalg.norm(basis @ r) for r in roots)
    return Bifurcation("simple", dirs, 2, None if disc is None else float(disc),
                       "two branches cross transversally")


def _quadratic_directions(a: float, b: float, c: float, disc: float) -> list[np.ndarray]:
    """Unit vectors (α, β) solving a α² + 2 b αβ + c β² = 0."""
    r = math.sqrt(disc)
    if abs(a) >= abs(c):
        return [np.array([(-b + r), a]) if a != 0 else np.array([1.0, 0.0]),
                np.array([(-b - r), a]) if a != 0 else np.array([-c, 2 * b])]
    return [np.array([c, -b + r]), np.array([c, -b - r])]


def _common_directions(forms: np.ndarray, tol: float) -> list[np.ndarray]:
    """Directions on the half circle where every quadratic form vanishes (sampled and refined)."""
    from scipy.optimize import minimize_scalar

    def total(p):
        c, s = math.cos(p), math.sin(p)
        return float(sum((a * c * c + 2 * b * c * s + cc * s * s) ** 2 for a, b, cc in forms))

    phis = np.linspace(0.0, math.pi, 721)
    vals = [total(p) for p in phis]
    found = []
    for k in range(1, len(phis) - 1):
        if vals[k] <= vals[k - 1] and vals[k] <= vals[k + 1]:
            res = minimize_scalar(total, bounds=(phis[k - 1], phis[k + 1]), method="bounded",
                                  options={"xatol": 1e-12})
            if res.fun < tol * tol:
                found.append(np.array([math.cos(res.x), math.sin(res.x)]))
    return found
