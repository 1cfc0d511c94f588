"""IM points of a map: the grid's IM-indicator minima, screened, subdivided and refined to a rank drop.

See :mod:`symkin.workspace.loci` (step 4).
"""
from __future__ import annotations

import numpy as np

from symkin.paths.events import refine_rank_drop
from symkin.tolerances import DEFAULT, Tolerances
from symkin.workspace import quadtree
from symkin.workspace.locus_problems import LOCUS_NEWTON_TOL, LocusProblems
from symkin.workspace.refine_data import GridData, RefineStats

__all__ = ["im_candidates", "locate_im", "im_through_quadtree"]


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

    :func:`symkin.paths.events.refine_rank_drop` (Gauss–Newton on the constraints, a left
    null vector ``ψ`` of their Jacobian and its normalisation) from the grid configuration
    of an IM-indicator minimum.  Where the IM configurations at that point form a family
    (Fig. 14: with P on the common pivot the collapsed rhombus turns freely about it) the
    Gauss–Newton steps need not vanish, only their component across the family; the point
    it settles on is then accepted when it closes (residual at Newton's tolerance) and its
    relative ``σ_{F+1}`` is at most :attr:`Tolerances.event_threshold` (as a path event).
    None otherwise.  The caller asks the core whether the configuration is IM.
    """
    y, ok = refine_rank_drop(pb.constraints(), y0, 1)
    if not np.all(np.isfinite(y)):
        return None
    if not ok:
        closes = float(np.linalg.norm(pb.constraints().residual(y))) <= 10 * LOCUS_NEWTON_TOL
        if not (closes and pb.tests(y)["im"] <= tol.event_threshold):
            return None
    return y


def im_through_quadtree(pb: LocusProblems, a_c: np.ndarray, y_c: np.ndarray, cell: np.ndarray, box_d: np.ndarray,
                         tol: Tolerances, stats: "RefineStats") -> np.ndarray | None:
    """An IM configuration near the grid's IM-indicator minimum at ``a_c`` (config ``y_c``), through the quadtree.

    The IM indicator (the relative ``σ_{F+1}``, §V) is positive, so it has no sign change to
    bracket: the cells around the minimum are subdivided (:func:`symkin.workspace.quadtree.subdivide`
    with the IM indicator as ``T``) down to the finest cell holding the smallest value, and
    :func:`locate_im` starts from that cell's point (an IM point between grid points that the
    coarse grid does not resolve, Fig. 14), then from the grid point itself.  The finest
    points are tried nearest to zero first; the first located configuration is returned
    (None when none is: the core decides afterwards whether it is IM).
    """
    def sample(a, y0):
        y = pb.solve_square(a, y0)
        return y, pb.tests(y)["im"]

    sub = quadtree.subdivide(sample, a_c, y_c, pb.tests(y_c)["im"], cell, box_d[:, 0], box_d[:, 1])
    stats.subdivided += sub.samples
    starts = [y for _, y, _ in sorted(sub.dips, key=lambda d: pb.tests(d[1])["im"])] + [np.asarray(y_c, float)]
    for y0 in starts:
        y = locate_im(pb, y0, tol)
        if y is not None:
            return y
    return None

