"""Homotopy continuation through Bertini 2's Python package (the optional extra ``symkin[global]``).

``bertini`` (GPL-3) is imported here only, inside :func:`track`, so every other part of
symkin works without it.  Its zero-dimensional algorithm tracks one path per solution of
a total-degree start system (products of the equations' degrees) with the Cauchy endgame
in double precision; it has no multihomogeneous start system, so the number of paths is
kept down by eliminating linear equations before (:mod:`symkin.solutions.system`).
"""
from __future__ import annotations

import math

import numpy as np
import sympy as sp

from symkin.errors import SymkinError

__all__ = ["require_solver", "square_up", "track", "total_degree"]

EXTRA = 'pip install -e ".[global]"'


def require_solver():
    """The ``bertini`` module, or a :class:`SymkinError` naming the extra to install."""
    try:
        import bertini
    except ImportError:
        raise SymkinError("all solutions of the position problem need the homotopy-continuation solver "
                          f"Bertini 2 (package 'bertini', GPL-3), an optional extra: {EXTRA} "
                          "(or pip install 'symkin[global]')") from None
    return bertini


def square_up(equations, n: int, seed: int = 0):
    """``n`` random linear combinations of ``equations`` (fixed seed), as numerical algebraic geometry does.

    Every isolated solution of the original system is a solution of the squared-up one;
    the converse fails, so the caller checks every solution against the original equations.
    Equations are sorted by degree and the combination is triangular (the ``i``-th keeps
    equation ``i`` with weight 1 and adds random multiples of the ones after ``n``), so
    the total degree does not grow beyond the product of the first ``n`` degrees.
    """
    eqs = sorted(equations, key=lambda e: -sp.Poly(e).total_degree())
    if len(eqs) <= n:
        return list(eqs)
    rng = np.random.default_rng(seed)
    head, tail = eqs[:n], eqs[n:]
    w = rng.standard_normal((n, len(tail)))
    return [sp.expand(h + sum(float(w[i, j]) * t for j, t in enumerate(tail))) for i, h in enumerate(head)]


def total_degree(equations, unknowns) -> int:
    """Number of paths of the total-degree homotopy: the product of the degrees."""
    return math.prod(sp.Poly(e, *unknowns).total_degree() for e in equations)


def _to_bertini(bertini, poly: sp.Poly, variables):
    Float = bertini.multiprec.Float
    expr = None
    for monom, coeff in poly.terms():
        term = Float(repr(float(coeff)))
        for v, e in zip(variables, monom):
            for _ in range(e):
                term = term * v
        expr = term if expr is None else expr + term
    return expr


#: solves of one system before a Bertini failure is reported
RETRIES = 3

ENDGAMES = {"cauchy": "ZeroDimCauchyDoublePrecisionTotalDegree",
            "power_series": "ZeroDimPowerSeriesDoublePrecisionTotalDegree"}


def track(equations, unknowns, endgame: str = "cauchy") -> np.ndarray:
    """Every endpoint of the total-degree homotopy for the square system ``equations = 0``.

    ``endgame`` is Bertini's Cauchy (default) or power-series endgame; the power-series one
    stops the paths that diverge (most paths of a system whose Bézout number far exceeds its
    finite solutions, e.g. :mod:`symkin.solutions.dkp_system`) much sooner, leaving them as
    large affine points that the caller's Newton check rejects.

    Returns a complex (paths, n + 1) array of projective endpoints: column 0 is the
    homogenising coordinate (near 0 for a path that diverges to infinity), the affine
    point is ``v[1:] / v[0]``.
    """
    bertini = require_solver()
    if len(equations) != len(unknowns):
        raise ValueError("track needs a square system")
    names = [bertini.Variable(f"v{k}") for k in range(len(unknowns))]
    system = bertini.System()
    for e in equations:
        system.add_function(_to_bertini(bertini, sp.Poly(e, *unknowns), names))
    system.add_variable_group(bertini.VariableGroup(names))
    for attempt in range(1, RETRIES + 1):
        alg = getattr(bertini.nag_algorithm, ENDGAMES[endgame])(system)
        try:
            alg.solve()
            break
        except RuntimeError as exc:
            # Bertini 2 (double precision) now and then aborts the whole solve on one failed path
            # ("number of input variables (0) doesn't match ..."); its start system is random, so a
            # new solve is a new homotopy
            if attempt == RETRIES:
                raise SymkinError(f"the homotopy solver failed {RETRIES} times on a system of {len(unknowns)} "
                                  f"equations: {exc}") from None
    # a path that failed can come back as a vector of another length: it has no endpoint
    ends = [[complex(c) for c in v] for v in alg.solutions()]
    return np.array([v for v in ends if len(v) == len(unknowns) + 1], dtype=complex).reshape(
        -1, len(unknowns) + 1)


#: paths tracked (one at a time) to estimate the time of a large total-degree homotopy
ESTIMATE_PATHS = 4


def estimate_seconds(equations, unknowns, paths: int = ESTIMATE_PATHS, seed: int = 0,
                     clock=None) -> tuple[float, int]:
    """Seconds per path of the total-degree homotopy of ``equations``, measured on its first ``paths`` paths.

    The same homotopy (start system ``u_i^{d_i} = 1``, straight line to ``equations`` with a
    random complex γ) is tracked one path at a time by symkin's tracker
    (:func:`symkin.solutions.parameter_homotopy.track_parameters`, which has no endgame and stops
    a path going to infinity at its divergence bound), so the figure is an estimate of the order
    of Bertini's time, not a promise.

    Returns
    -------
    (float, int)
        The mean wall time of one path (``clock`` seconds, default :func:`time.perf_counter`) and
        the number of paths measured.
    """
    import time

    from symkin.solutions.parameter_homotopy import ParameterFamily, track_parameters

    clock = time.perf_counter if clock is None else clock
    unknowns = list(unknowns)
    n = len(unknowns)
    polys = [sp.Poly(e, *unknowns) for e in equations]
    degrees = [max(1, p.total_degree()) for p in polys]
    target = [p.as_dict() for p in polys]
    start = [{tuple(d if j == i else 0 for j in range(n)): 1.0, (0,) * n: -1.0} for i, d in enumerate(degrees)]
    monomials = sorted({m for eq in target + start for m in eq})
    index = {m: k for k, m in enumerate(monomials)}
    g = np.zeros((n, len(monomials)))
    f = np.zeros((n, len(monomials)))
    for i in range(n):
        for m, c in start[i].items():
            g[i, index[m]] = c
        for m, c in target[i].items():
            f[i, index[m]] = float(c)
    direction = (f - g).ravel()
    norm = float(np.linalg.norm(direction)) or 1.0
    family = ParameterFamily((), np.array(monomials, int).reshape(len(monomials), n), g,
                             (direction / norm)[None], np.eye(n, dtype=complex), np.zeros(n))
    rng = np.random.default_rng(seed)
    t0 = clock()
    for _ in range(paths):
        u0 = np.exp(2j * np.pi * rng.integers(0, degrees) / np.array(degrees))
        track_parameters(family, u0[None], np.zeros(1), np.array([norm]), rng)
    return (clock() - t0) / max(paths, 1), paths
