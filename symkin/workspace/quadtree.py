"""Near-zero minima of the DKP test functions on the grid and the adaptive subdivision (quadtree) of their cells.

A singular curve shows on the map's grid as a sign change of its signed test function ``T``
between two neighbouring grid points (located on that edge, :mod:`symkin.workspace.loci`).
Three kinds of curves show no sign change (issue 8, "cells where a signed test function
changes sign, or the IM indicator has a near-zero minimum, are subdivided"):

* a **double zero** of ``T`` (``T ≈ c·d²`` at distance ``d`` from the curve): the five-bar's
  circle of coincident elbows when its crank circles touch (catalogue ``five_bar``);
* **two crossings within one cell** (a curve narrower than a cell crosses one grid line twice
  between two grid points);
* a **small closed curve** inside one cell.

Each leaves a *dip* on the grid: a grid point whose ``|T|`` is a near-zero local minimum
along a grid row or column (:func:`dips`).  The cells around a dip are subdivided (a
quadtree, :func:`subdivide`): a cell is cut into four while it shows a sign change of ``T``
among its corners or holds the dip's smallest ``|T|``, down to cells of side
``1 / 2**DEPTH`` of the grid's (:data:`DEPTH`).  Its finest cells return the edges with a sign
change (crossings, located and traced as the grid's own) and the dip points (located as
double zeros by :func:`symkin.workspace.loci.locate_double_zero`: ``T = 0`` together with
``∂T/∂n = 0`` along the line through the dip).

Only plain NumPy here: the square position problem and the test function come from the caller,
batched (``solve(A, Y0) -> (Y, converged)``, ``value(Y) -> T``): every level of every subdivision
is solved as one batch.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np


__all__ = ["DIP_RATIO", "DEPTH", "dips", "dip_mask", "Subdivision", "subdivide", "subdivide_many"]

#: the near-zero test of a grid minimum of ``|T|``: the parabola through ``|T|`` at the point and
#: its two neighbours on a grid line has its minimum at most ``DIP_RATIO`` times its rise over
#: one cell (a double zero: minimum ≈ 0; two crossings in the cell: minimum < 0; a valley of
#: ``|T|`` that stays away from zero by more than its rise over a cell is no dip).  It only
#: selects the cells to subdivide: whether a point is singular is decided by the core.
DIP_RATIO = 1.0
#: subdivision depth: a flagged cell is cut down to cells of side ``1 / 2**DEPTH`` of the grid's
DEPTH = 3
#: relative slack of the box test of a subdivision point (``a_centre + fine·p`` on the box edge, rounded)
_BOX_SLACK = 1e-12
#: sub-steps per finest cell when a subdivision point is solved from its nearest solved point
_MARCH = 2


#: ``solve(A (k, 2), Y0 (k, nf)) -> (Y (k, nf), converged (k,))``: the square problem at k axis points, one batch
Solve = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]
#: ``value(Y (k, nf)) -> T (k,)``: the signed test function at k configurations, one batch
Value = Callable[[np.ndarray], np.ndarray]


def dips(values: np.ndarray, assembled: np.ndarray, j, i, region: np.ndarray | None = None) -> np.ndarray:
    """Whether each grid point ``(j[k], i[k])`` is a near-zero minimum of ``|values|`` (see :data:`DIP_RATIO`).

    A dip is a point whose ``|T|`` is at most that of its two neighbours along a grid row or
    column, all three assembled and of one sign (no sign change: that is a crossing), with
    the parabola's minimum through the three values at most ``DIP_RATIO`` times its rise.
    ``values`` may stack several functions, ``(m, ny, nx)``: a dip of any of them counts.
    With ``region`` (int, ``(ny, nx)``) only neighbours of the same region count (tiles).

    >>> t = np.array([[4.0, 1.0, 0.01, 1.0, 4.0], [5.0, 3.0, 2.5, 3.0, 5.0]])  # a double zero; a valley
    >>> dips(t, np.ones(t.shape, bool), np.array([0, 1]), np.array([2, 2])).tolist()
    [True, False]
    """
    v = np.asarray(values, float)
    asm = np.asarray(assembled, bool)
    j, i = np.atleast_1d(np.asarray(j, np.intp)), np.atleast_1d(np.asarray(i, np.intp))
    ny, nx = v.shape[-2:]
    out = np.zeros(j.shape, bool)
    with np.errstate(invalid="ignore", divide="ignore"):
        f0 = np.where(asm[j, i], v[..., j, i], np.nan)
        for dj, di in ((0, 1), (1, 0)):
            inside = (j >= dj) & (i >= di) & (j + dj < ny) & (i + di < nx)
            if not inside.any():
                continue
            ja, ia = np.maximum(j - dj, 0), np.maximum(i - di, 0)
            jb, ib = np.minimum(j + dj, ny - 1), np.minimum(i + di, nx - 1)
            if region is not None:
                inside &= (region[ja, ia] == region[j, i]) & (region[jb, ib] == region[j, i])
            fa = np.where(asm[ja, ia], v[..., ja, ia], np.nan)
            fb = np.where(asm[jb, ib], v[..., jb, ib], np.nan)
            # one sign (NaN where not assembled fails every comparison) and |f0| the smallest of the three
            same = (f0 * fa > 0) & (f0 * fb > 0)
            a0, aa, ab = np.abs(f0), np.abs(fa), np.abs(fb)
            rise = 0.5 * (aa + ab) - a0
            ok = same & (a0 <= aa) & (a0 <= ab) & (rise > 0)
            low = a0 - (ab - aa) ** 2 / (16.0 * np.where(rise > 0, rise, 1.0))
            hit = ok & (low <= DIP_RATIO * rise)
            out |= inside & (hit.any(axis=0) if hit.ndim > 1 else hit)
    return out


def dip_mask(values: np.ndarray, assembled: np.ndarray) -> np.ndarray:
    """:func:`dips` at every grid point, as a mask of the grid's shape."""
    v = np.asarray(values, float)
    j, i = np.indices(v.shape)
    return dips(v, assembled, j.ravel(), i.ravel()).reshape(v.shape)


@dataclass
class Subdivision:
    """What :func:`subdivide` found in the cells around one dip (dimensionless axis values ``a``).

    ``crossings`` ``[(a_a, y_a, a_b, y_b)]``: finest edges with a sign change of ``T``;
    ``dips`` ``[(a, y, h)]``: the finest points of smallest ``|T|`` with no sign change
    around them (``h`` the finest cell's side per axis); ``samples`` the number of points solved.
    """

    crossings: list = field(default_factory=list)
    dips: list = field(default_factory=list)
    samples: int = 0


def subdivide(solve: Solve, value: Value, a_centre: np.ndarray, y_centre: np.ndarray, t_centre: float,
              cell: np.ndarray, lo: np.ndarray, hi: np.ndarray, depth: int | None = None) -> Subdivision:
    """Subdivide the (up to four) grid cells around one dip at ``a_centre``: :func:`subdivide_many` of one."""
    return subdivide_many(solve, value, [(a_centre, y_centre, t_centre)], cell, lo, hi, depth)[0]


def subdivide_many(solve: Solve, value: Value, centres, cell: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                   depth: int | None = None) -> list[Subdivision]:
    """Subdivide the (up to four) grid cells around each dip of ``centres`` (see the module docstring).

    Parameters
    ----------
    solve : callable
        ``solve(A, Y0) -> (Y, converged)``: the square position problem solved at the
        dimensionless axis values of each row of ``A`` (k, 2) from the rows of ``Y0`` — one
        batch (a batched Gauss–Newton on a mapped Function, never a loop of scalar solves);
        ``converged`` (k,) is False where the mode does not assemble.
    value : callable
        ``value(Y) -> T`` (k,): the signed test function at the rows of ``Y``, one batch.
    centres : sequence of ``(a_centre, y_centre, t_centre)``
        Each dip's axis values, configuration and ``T``.
    cell : (2,) the grid's cell sides (dimensionless).
    lo, hi : (2,) the box; cells outside it are not subdivided.
    depth : int, optional
        Finest cells have side ``cell / 2**depth`` (default :data:`DEPTH`).

    All trees advance one level at a time, and each level's new points of every tree are
    solved in one batch.  A point is solved from the nearest point of its tree solved
    before, in ``_MARCH`` sub-steps per finest cell (a short continuation: no jump to
    another mode over a large step; one batch per sub-step).  A cell is cut while it has a
    sign change among its corners, or holds the smallest ``|T|`` of its parent's nine
    points (the dip); a cell with a corner that does not assemble is left (its boundary is
    a fold, located from the grid).  Returns one :class:`Subdivision` per centre.
    """
    m = 2 ** int(DEPTH if depth is None else depth)
    fine = np.asarray(cell, float) / m
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    trees = [_Tree(np.asarray(a, float), {(0, 0): (np.asarray(y, float), float(t))}, Subdivision())
             for a, y, t in centres]

    def inside(tree, p):
        a = tree.a_of(p, fine)
        return bool(np.all(a >= lo - _BOX_SLACK * np.abs(lo)) and np.all(a <= hi + _BOX_SLACK * np.abs(hi)))

    top = [((u, v), m) for u in (-m, 0) for v in (-m, 0)]
    for tree in trees:
        tree.todo = [(c, True) for c in top if all(inside(tree, p) for p in _corners(c))]
    while any(tree.todo for tree in trees):
        _solve_points(solve, value, fine, [(t, [p for c, _ in t.todo for p in _corners(c)]) for t in trees])
        cut = []
        for tree in trees:
            pending = []
            for c, dip in tree.todo:
                vals = [tree.pts[p] for p in _corners(c)]
                if any(y is None or not math.isfinite(t) for y, t in vals):
                    continue
                sg = [math.copysign(1.0, t) for _, t in vals]
                change = len(set(sg)) > 1
                if not (change or dip):
                    continue
                if c[1] == 1:  # finest cell
                    ps = _corners(c)
                    if change:
                        for ka, kb in ((0, 1), (0, 2), (1, 3), (2, 3)):
                            if sg[ka] != sg[kb]:
                                tree.out.crossings.append((tree.a_of(ps[ka], fine), vals[ka][0],
                                                           tree.a_of(ps[kb], fine), vals[kb][0]))
                    else:
                        k = int(np.argmin([abs(t) for _, t in vals]))
                        tree.out.dips.append((tree.a_of(ps[k], fine), vals[k][0], fine.copy()))
                    continue
                pending.append((c, dip))
            cut.append(pending)
        _solve_points(solve, value, fine, [(t, [p for c, _ in pending for kid in _kids(c) for p in _corners(kid)])
                                           for t, pending in zip(trees, cut)])
        for tree, pending in zip(trees, cut):
            nxt = []
            for c, dip in pending:
                kids = _kids(c)
                nine = {p: tree.pts[p] for kid in kids for p in _corners(kid)}
                finite = {p: abs(t) for p, (y, t) in nine.items() if y is not None and math.isfinite(t)}
                low = min(finite.values()) if finite else math.inf
                for kid in kids:
                    holds_min = dip and any(finite.get(p, math.inf) == low for p in _corners(kid))
                    nxt.append((kid, holds_min))
            tree.todo = nxt
    for tree in trees:
        tree.out.crossings = _unique_edges(tree.out.crossings)
        tree.out.dips = _unique_points(tree.out.dips)
    return [tree.out for tree in trees]


@dataclass
class _Tree:
    """One dip's subdivision: its centre, the points solved (``(u, v)`` in finest cells → ``(y, T)``)."""

    a_centre: np.ndarray
    pts: dict
    out: Subdivision
    todo: list = field(default_factory=list)

    def a_of(self, p, fine: np.ndarray) -> np.ndarray:
        return self.a_centre + fine * np.array(p, float)


def _corners(c):
    (u, v), s = c
    return [(u, v), (u + s, v), (u, v + s), (u + s, v + s)]


def _kids(c):
    (u, v), s = c
    h = s // 2
    return [((u + du, v + dv), h) for du in (0, h) for dv in (0, h)]


def _solve_points(solve: Solve, value: Value, fine: np.ndarray, wanted) -> None:
    """Solve the points ``wanted`` (``[(tree, [p, ...])]``) not solved yet, all trees in one batch per sub-step.

    Each from the nearest point of its tree solved before (``(None, nan)`` when that one did
    not assemble), in ``_MARCH`` sub-steps per finest cell.
    """
    jobs = []  # (tree, p, y_start, a_start, a_end, steps)
    for tree, ps in wanted:
        known = list(tree.pts)
        for p in dict.fromkeys(ps):
            if p in tree.pts:
                continue
            near = min(known, key=lambda k: (abs(k[0] - p[0]) + abs(k[1] - p[1]), k))
            y = tree.pts[near][0]
            if y is None:
                tree.pts[p] = (None, math.nan)
                continue
            steps = max(1, int(math.ceil(max(abs(near[0] - p[0]), abs(near[1] - p[1])) * _MARCH)))
            jobs.append((tree, p, y, tree.a_of(near, fine), tree.a_of(p, fine), steps))
            tree.pts[p] = None  # reserved: solved below
    if not jobs:
        return
    y = np.array([j[2] for j in jobs], float)
    a0, a1 = np.array([j[3] for j in jobs]), np.array([j[4] for j in jobs])
    steps = np.array([j[5] for j in jobs])
    ok = np.ones(len(jobs), bool)
    for k in range(1, int(steps.max()) + 1):
        act = np.flatnonzero(ok & (steps >= k))
        if act.size == 0:
            break
        target = a0[act] + (a1[act] - a0[act]) * (k / steps[act])[:, None]
        y_new, conv = solve(target, y[act])
        y[act] = y_new
        ok[act[~np.asarray(conv, bool)]] = False
    t = np.full(len(jobs), math.nan)
    if ok.any():
        t[ok] = np.asarray(value(y[ok]), float)
    for k, (tree, p, *_rest) in enumerate(jobs):
        tree.pts[p] = (y[k].copy(), float(t[k])) if ok[k] else (None, math.nan)
        tree.out.samples += 1


def _unique_edges(edges: list) -> list:
    seen, keep = set(), []
    for e in edges:
        key = tuple(np.round(np.concatenate([e[0], e[2]]), 15))
        rkey = tuple(np.round(np.concatenate([e[2], e[0]]), 15))
        if key not in seen and rkey not in seen:
            seen.add(key)
            keep.append(e)
    return keep


def _unique_points(points: list) -> list:
    seen, keep = set(), []
    for p in points:
        key = tuple(np.round(p[0], 15))
        if key not in seen:
            seen.add(key)
            keep.append(p)
    return keep
