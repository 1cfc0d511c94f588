"""The half-branches that leave a vertex of a curve (a branch point of nullity 2), one point each.

:func:`half_branches` finds the branches through a located vertex ``X`` (see
:func:`symkin.curves.locate.locate_singular_point`): on the circle
``X + ρ (cos α e₁ + sin α e₂) + w`` of radius ``ρ`` in the null plane ``span(e₁, e₂)``, ``w``
in its orthogonal complement solves the ``n − 2`` equations of ``H`` that stay regular
(Lyapunov–Schmidt reduction, by the one corrector); the one that remains,
``g(α) = ψ₀ · H``, vanishes exactly where a branch crosses the circle.  Its sign changes
over a fine grid of ``α``, refined by Brent's method, give one point per half-branch: 4 at a
simple branch point or a tangent contact of two branches (two of them ``Δκ ρ / 2`` apart in
``α``), 2 at a cusp, 0 at an isolated real point.
"""
from __future__ import annotations

import math

import numpy as np

from symkin.curves.corrector import gauss_newton
from symkin.curves.locate import as_casadi
from symkin.tolerances import DEFAULT

__all__ = ["half_branches", "HALF_BRANCH_RADIUS", "HALF_BRANCH_SAMPLES"]

#: radius of the circle of :func:`half_branches`, in units of the length scale (``y`` is dimensionless)
HALF_BRANCH_RADIUS = 0.02
#: points of the grid in the angle of that circle (tangent branches 1.8e-2 rad apart at the double
#: butterfly's contacts are 4 grid cells apart)
HALF_BRANCH_SAMPLES = 1440
#: the reduced unknown ``w`` stays small next to the circle (O(ρ²)); beyond this the correction left it
MAX_OFFSET = 1.0
#: Newton on ``w`` and Brent on ``α`` stop at a step of this (:attr:`Tolerances.branch_step`)
STEP_TOL = DEFAULT.branch_step
#: iterations of the corrector on ``w`` (quadratic from the warm start of the previous grid angle)
ITERATIONS = 30


def half_branches(curve, x: np.ndarray, radius: float = HALF_BRANCH_RADIUS, samples: int = HALF_BRANCH_SAMPLES,
                  rank: float = DEFAULT.rank) -> list[np.ndarray] | None:
    """One curve point per half-branch leaving the vertex ``x`` (module docstring), sorted by angle.

    Returns None when the nullity of ``J`` at ``x`` (relative ``rank``) is not 2: the
    reduction to one scalar equation on a circle needs exactly one extra left null vector.
    """
    f = as_casadi(curve, x)
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
        base = x + radius * (plane @ np.array([math.cos(alpha), math.sin(alpha)]))

        def reduced(w):
            hh, jj = (np.array(v, float) for v in f(base + comp @ w))
            return ur.T @ hh.ravel(), ur.T @ jj @ comp

        w0 = warm.get(key, np.zeros(n - 2)) if key is not None else np.zeros(n - 2)
        c = gauss_newton(reduced, w0, tol=STEP_TOL, max_iterations=ITERATIONS, step_tol=STEP_TOL, norm="max")
        if not (np.all(np.isfinite(c.z)) and float(np.max(np.abs(c.z), initial=0.0)) <= MAX_OFFSET):
            return math.nan, None
        if key is not None:
            warm[key] = c.z
        y = base + comp @ c.z
        return float(u0 @ np.array(f(y)[0], float).ravel()), y

    from scipy.optimize import brentq  # here: importing scipy.optimize costs 0.1-0.3 s (issue 17)

    grid = np.linspace(0.0, 2 * math.pi, samples, endpoint=False)
    values = [point(a, 0)[0] for a in grid]
    out = []
    for k in range(samples):
        a, ga, gb = grid[k], values[k], values[(k + 1) % samples]
        if not (math.isfinite(ga) and math.isfinite(gb)) or ga * gb > 0 or (ga == 0 and k and values[k - 1] == 0):
            continue
        root = a if ga == 0 else brentq(lambda t: point(t)[0], a, a + 2 * math.pi / samples, xtol=STEP_TOL)
        y = point(root)[1]
        if y is not None:
            out.append(y)
    return out
