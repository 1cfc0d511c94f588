"""IM points of a map: the grid's IM-indicator minima, screened, subdivided and refined to a rank drop.

See :mod:`symkin.workspace.loci` (step 4).
"""
from __future__ import annotations

import numpy as np

from symkin.curves.locate import locate_singular_point
from symkin.tolerances import DEFAULT, Tolerances
from symkin.workspace import quadtree
from symkin.workspace.locus_problems import LOCUS_NEWTON_TOL, LocusProblems
from symkin.workspace.refine_data import GridData, RefineStats

__all__ = ["im_candidates", "locate_im", "locate_im_many", "IM_SCREEN_ITERATIONS"]

#: Gauss–Newton steps of the batched screen of IM-indicator minima (:func:`locate_im_many`): from a start
#: within a finest quadtree cell of an IM point the rank-drop system converges quadratically in a few
#: steps, while a minimum with no rank drop near stays orders of magnitude above the event threshold
IM_SCREEN_ITERATIONS = 12


def im_candidates(grid: GridData) -> list[tuple[int, int]]:
    """Grid nodes whose IM indicator is a minimum among its eight assembled neighbours (to refine).

    Ties count: an IM point at the centre of a cell (Fig. 14: the origin of an even grid, by
    symmetry) gives four equal minima at the cell's corners; one of them is taken (the first,
    row-major: a tie with an earlier candidate among the neighbours is skipped; the located
    point is the same).  A flat block (all nine equal) is no minimum.
    """
    if grid.im_indicator is None:
        return []
    im = np.asarray(grid.im_indicator, float)
    asm = np.asarray(grid.assembled, bool) & np.isfinite(im)
    ny, nx = im.shape
    out = []
    taken = set()
    for j in range(1, ny - 1):
        for i in range(1, nx - 1):
            block, ok = im[j - 1:j + 2, i - 1:i + 2], asm[j - 1:j + 2, i - 1:i + 2]
            if not ok.all() or im[j, i] > block.min() or im[j, i] == block.max():
                continue
            if any((j + dj, i + di) in taken for dj in (-1, 0, 1) for di in (-1, 0, 1)):
                continue  # a tie next to a candidate already taken
            out.append((j, i))
            taken.add((j, i))
    return out


def locate_im(pb: LocusProblems, y0: np.ndarray, tol: Tolerances = DEFAULT) -> np.ndarray | None:
    """An IM configuration near ``y0``: where the surface ``(Φ_S/ℓ, holds) = 0`` loses rank.

    :func:`symkin.curves.locate.locate_singular_point` without deflation (Gauss–Newton on the constraints, a left
    null vector ``ψ`` of their Jacobian and its normalisation) from the grid configuration
    of an IM-indicator minimum.  Where the IM configurations at that point form a family
    (Fig. 14: with P on the common pivot the collapsed rhombus turns freely about it) the
    Gauss–Newton steps need not vanish, only their component across the family; the point
    it settles on is then accepted when it closes (residual at Newton's tolerance) and its
    relative ``σ_{F+1}`` is at most :attr:`Tolerances.event_threshold` (as a path event).
    None otherwise.  The caller asks the core whether the configuration is IM.
    """
    found = locate_singular_point(pb.constraints(), y0, 1, max_deflations=0)
    y, ok = found.y, found.converged
    if not np.all(np.isfinite(y)):
        return None
    if not ok:
        closes = float(np.linalg.norm(pb.constraints().residual(y))) <= 10 * LOCUS_NEWTON_TOL
        if not (closes and pb.tests(y)["im"] <= tol.event_threshold):
            return None
    return y


def locate_im_many(pb: LocusProblems, centres: list, cell: np.ndarray, box_d: np.ndarray, tol: Tolerances,
                   stats: RefineStats) -> list[np.ndarray | None]:
    """IM configurations near the grid's IM-indicator minima ``centres`` (``[(a_c, y_c)]``), in one batch each step.

    The IM indicator (the relative ``σ_{F+1}``, §V) is positive, so it has no sign change to
    bracket: the cells around every minimum are subdivided at once
    (:func:`symkin.workspace.quadtree.subdivide_many` with the IM indicator as ``T``) down to
    the finest cell holding the smallest value.  Each minimum's starts are its finest points,
    nearest to zero first, then the grid point itself (an IM point between grid points that
    the coarse grid does not resolve, Fig. 14).

    **Screen**: every start of every minimum takes ``IM_SCREEN_ITERATIONS`` batched
    Gauss–Newton steps towards a rank drop (:meth:`LocusProblems.polish_rank_drop_many`),
    and a minimum is refined further only when the smallest IM indicator reached is at most
    :attr:`Tolerances.event_threshold` (the core's threshold of a located zero of a path
    test): a mechanism without IM points in the box (the 3-RPR at constant orientation)
    costs one batch.  A minimum that passes is refined by :func:`locate_im` from its starts
    in order; the first located configuration is returned for it (None when none is, or
    when it was screened out: the core decides afterwards whether it is IM).
    """
    if not centres:
        return []
    lo, hi = box_d[:, 0], box_d[:, 1]

    def im(y):
        return pb.tests_many(y)["im"]

    y_c = np.array([y for _, y in centres], float)
    subs = quadtree.subdivide_many(pb.solve_square_many, im, [(a, y, t) for (a, y), t in zip(centres, im(y_c))],
                                   cell, lo, hi)
    starts = []
    for sub, y in zip(subs, y_c):
        stats.subdivided += sub.samples
        finest = np.array([d[1] for d in sub.dips], float).reshape(-1, y_c.shape[1])
        order = np.argsort(im(finest), kind="stable") if len(finest) else np.zeros(0, int)
        starts.append(np.vstack([finest[order], y[None]]))
    flat = np.vstack(starts)
    reached = np.fmin.reduce(np.vstack([im(pb.polish_rank_drop_many(flat, IM_SCREEN_ITERATIONS)), im(flat)]), axis=0)
    reached = np.where(np.isfinite(reached), reached, np.inf)
    out: list[np.ndarray | None] = []
    first = 0
    for ys in starts:
        best = float(reached[first:first + len(ys)].min())
        first += len(ys)
        if not best <= tol.event_threshold:
            stats.im_screened += 1
            out.append(None)
            continue
        out.append(next((y for y in (locate_im(pb, y0, tol) for y0 in ys) if y is not None), None))
    return out
