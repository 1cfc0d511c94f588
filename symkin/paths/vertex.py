"""Branch points of a configuration curve, located to rounding even where branches are tangent, and the half-branches that leave them.

A branch point (IM configuration of a 1-DOF mechanism, a *vertex* of the configuration
curve) is where the curve's Jacobian ``J`` (``m × n``, generic rank ``n − 1``) loses one
more rank.  :func:`locate_branch_point` solves

    H(y) = 0,   J(y)ᵀ ψ = 0,   ψ₀ · ψ = 1,   Zᵀ ψ = 0            (1)

(``ψ₀`` the left singular vector that vanishes there, ``Z`` the generic left null vectors of
redundant equations) by Gauss–Newton.  At a *simple* branch point (two transversal branches)
the solution of (1) is regular and Newton converges quadratically.  Where two branches are
tangent (the double butterfly's contact with its LIM branch, paper Figs. 3(b), 4) the
quadratic form of the branch directions is degenerate, the Jacobian ``DF`` of (1) has a null
vector ``ξ`` and Newton on (1) converges only linearly, to about ``√ε``: the trace's events
there are off by 1e-6 to 1e-3 of the length scale.  The function then *deflates* (Leykin,
Verschelde & Zhao, Theor. Comput. Sci. 2006): it appends

    DF(z) ξ = 0,   ξ₀ · ξ = 1                                  (2)

in the unknowns ``(z, ξ)``, ``z = (y, ψ)``, whose solution is regular again, and Newton on
(1)+(2) converges quadratically to the branch point.  Every derivative is CasADi's, exact.

:func:`half_branches` finds the branches through a located vertex ``X`` of nullity 2: on the
circle ``X + ρ (cos α e₁ + sin α e₂) + w`` of radius ``ρ`` in the null plane ``span(e₁, e₂)``,
``w`` in its orthogonal complement solves the ``n − 2`` equations of ``H`` that stay regular
(Lyapunov–Schmidt reduction); the one that remains, ``g(α) = ψ₀ · H``, vanishes exactly
where a branch crosses the circle.  Its sign changes over a fine grid of ``α``, refined by
Brent's method, give one point per half-branch: 4 at a simple branch point or a tangent
contact of two branches (two of them ``Δκ ρ / 2`` apart in ``α``), 2 at a cusp, 0 at an
isolated real point.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import casadi as ca
import numpy as np
from scipy.optimize import brentq

__all__ = ["BranchPoint", "half_branches", "locate_branch_point", "HALF_BRANCH_RADIUS"]

#: radius of the circle of :func:`half_branches`, in units of the length scale (``y`` is dimensionless)
HALF_BRANCH_RADIUS = 0.02
#: points of the grid in the angle of that circle (tangent branches 1.8e-2 rad apart at the double
#: butterfly's contacts are 4 grid cells apart)
HALF_BRANCH_SAMPLES = 1440
#: at most this many deflations (each doubles the unknowns)
MAX_DEFLATIONS = 3


@dataclass(frozen=True)
class BranchPoint:
    """A located branch point: ``y`` (dimensionless free coordinates), its left null vector ``psi``.

    ``deflations`` counts how many times system (1) of the module docstring was deflated
    because it was singular there (0 at a simple branch point, 2 at the double butterfly's
    tangent contacts); ``converged`` that the last Newton
    step was below the tolerance; ``residual`` is ``max |H(y)|``.
    """

    y: np.ndarray = field(repr=False)
    psi: np.ndarray = field(repr=False)
    deflations: int
    converged: bool
    residual: float
    iterations: int


def _gauss_newton(fun, z: np.ndarray, tol: float, max_iterations: int) -> tuple[np.ndarray, bool, int]:
    """Gauss–Newton (least squares steps) on ``fun: z ↦ (G, DG)`` until the step is below ``tol·max(1, |z|)``."""
    for k in range(1, max_iterations + 1):
        g, dg = (np.array(v, float) for v in fun(z))
        step = np.linalg.lstsq(dg, -g.ravel(), rcond=None)[0]
        if not np.all(np.isfinite(step)):
            return z, False, k
        z = z + step
        if np.linalg.norm(step) <= tol * max(1.0, float(np.linalg.norm(z))):
            return z, True, k
    return z, False, max_iterations


def locate_branch_point(curve, y0: np.ndarray, tol: float = 1e-14, max_iterations: int = 30,
                        singular: float = 1e-7) -> BranchPoint:
    """The branch point next to ``y0``: Newton on system (1), deflated by (2) where (1) is singular.

    ``singular`` is the relative size of the smallest singular value of ``DF`` below which
    (1) counts as singular at the point Newton reached (its null vector starts ξ).

    Examples
    --------
    The crossing of the two branches of a flattened four-bar (its change point) is simple:
    see ``tests/paths/test_vertex.py``; the double butterfly's tangent contacts need the
    deflation.
    """
    f = curve.casadi_function
    y0 = np.asarray(y0, float)
    n = y0.size
    h0, j0 = (np.array(v, float) for v in f(y0))
    m = j0.shape[0]
    u, _, _ = np.linalg.svd(j0, full_matrices=True)
    psi0, zred = u[:, n - 2], u[:, n - 1:]
    y, psi = ca.SX.sym("y", n), ca.SX.sym("psi", m)
    h, j = f(y)
    z = ca.vertcat(y, psi)
    F = ca.vertcat(h, ca.mtimes(j.T, psi), ca.dot(ca.DM(psi0), psi) - 1, ca.mtimes(ca.DM(zred).T, psi))
    w, G, start = z, F, np.concatenate([y0, psi0])
    deflations, iters, converged = 0, 0, False
    while True:
        dG = ca.jacobian(G, w)
        fun = ca.Function("branch_point", [w], [G, dG])
        w_k, converged, more = _gauss_newton(fun, start, tol, max_iterations)
        iters += more
        _, s, vt = np.linalg.svd(np.array(fun(w_k)[1], float), full_matrices=False)
        if s[-1] > singular * s[0] or deflations == MAX_DEFLATIONS:
            break
        # singular: append DG ξ = 0, ξ₀ · ξ = 1 (ξ₀ its null vector here) and solve again
        xi0 = vt[-1]
        xi = ca.SX.sym(f"xi{deflations}", xi0.size)
        G = ca.vertcat(G, ca.mtimes(dG, xi), ca.dot(ca.DM(xi0), xi) - 1)
        w, start = ca.vertcat(w, xi), np.concatenate([w_k, xi0])
        deflations += 1
    z_k = w_k[: n + m]
    y_k = z_k[:n]
    res = float(np.max(np.abs(np.array(f(y_k)[0], float)), initial=0.0))
    return BranchPoint(y_k, z_k[n:], deflations, converged, res, iters)


def half_branches(curve, x: np.ndarray, radius: float = HALF_BRANCH_RADIUS, samples: int = HALF_BRANCH_SAMPLES,
                  rank: float = 1e-8) -> list[np.ndarray] | None:
    """One curve point per half-branch leaving the vertex ``x`` (module docstring), sorted by angle.

    Returns None when the nullity of ``J`` at ``x`` (relative ``rank``) is not 2: the
    reduction to one scalar equation on a circle needs exactly one extra left null vector.
    """
    f = curve.casadi_function
    x = np.asarray(x, float)
    n = x.size
    jx = np.array(f(x)[1], float)
    u, s, vt = np.linalg.svd(jx, full_matrices=True)
    sv = np.concatenate([s, np.zeros(max(0, n - s.size))])
    if not (sv[n - 2] <= rank * max(sv[0], 1.0) < sv[n - 3]):
        return None
    plane, comp = vt[n - 2:].T, vt[: n - 2].T
    ur, u0 = u[:, : n - 2], u[:, n - 2]
    warm: dict[int, np.ndarray] = {}

    def point(alpha: float, key: int | None = None):
        d = plane @ np.array([math.cos(alpha), math.sin(alpha)])
        w = warm.get(key, np.zeros(n - 2)) if key is not None else np.zeros(n - 2)
        for _ in range(30):
            y = x + radius * d + comp @ w
            hh, jj = (np.array(v, float) for v in f(y))
            try:
                step = np.linalg.solve(ur.T @ jj @ comp, -(ur.T @ hh.ravel()))
            except np.linalg.LinAlgError:
                return math.nan, None
            w = w + step
            if not np.all(np.isfinite(w)) or float(np.max(np.abs(w))) > 1.0:
                return math.nan, None
            if float(np.max(np.abs(step))) <= 1e-15:
                break
        if key is not None:
            warm[key] = w
        y = x + radius * d + comp @ w
        return float(u0 @ np.array(f(y)[0], float).ravel()), y

    grid = np.linspace(0.0, 2 * math.pi, samples, endpoint=False)
    values = [point(a, 0)[0] for a in grid]
    out = []
    for k in range(samples):
        a, ga, gb = grid[k], values[k], values[(k + 1) % samples]
        if not (math.isfinite(ga) and math.isfinite(gb)) or ga * gb > 0 or (ga == 0 and k and values[k - 1] == 0):
            continue
        root = a if ga == 0 else brentq(lambda t: point(t)[0], a, a + 2 * math.pi / samples, xtol=1e-15)
        y = point(root)[1]
        if y is not None:
            out.append(y)
    return out
