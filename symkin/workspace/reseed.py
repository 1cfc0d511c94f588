"""A grid configuration that was not kept, re-solved from the mode's seed along assembled grid nodes.

See :mod:`symkin.workspace.loci` (steps 4 and 5: IM minima and dips of a grid without stored configurations).
"""
from __future__ import annotations

import numpy as np

from symkin.errors import NotConvergedError
from symkin.workspace.locus_problems import LocusProblems
from symkin.workspace.refine_data import GridData

__all__ = ["grid_path", "resolve_from_seed"]


def grid_path(asm: np.ndarray, start: tuple[int, int], goal: tuple[int, int]) -> list[tuple[int, int]] | None:
    """A shortest path of 8-neighbouring assembled grid nodes from ``start`` to ``goal`` (breadth first)."""
    ny, nx = asm.shape
    prev = {start: None}
    front = [start]
    while front and goal not in prev:
        nxt = []
        for j, i in front:
            for dj in (-1, 0, 1):
                for di in (-1, 0, 1):
                    p = (j + dj, i + di)
                    if 0 <= p[0] < ny and 0 <= p[1] < nx and asm[p] and p not in prev:
                        prev[p] = (j, i)
                        nxt.append(p)
        front = nxt
    if goal not in prev:
        return None
    path = [goal]
    while prev[path[-1]] is not None:
        path.append(prev[path[-1]])
    return path[::-1]


def resolve_from_seed(pb: LocusProblems, grid: GridData, scale: np.ndarray, target: tuple[int, int],
                      substeps: int = 4) -> np.ndarray | None:
    """The mode's configuration ``y`` at grid node ``target``, re-solved from the seed.

    Newton on the square problem (:meth:`LocusProblems.solve_square`) in ``substeps`` steps per
    cell: from the seed to the nearest assembled node, then node to node along a shortest
    path of assembled nodes (the grid's own continuation, for one node).  None without a
    seed or when a step does not converge.
    """
    if grid.seed is None:
        return None
    asm = np.asarray(grid.assembled, bool)
    y = np.asarray(grid.seed, float) / pb.scale
    a = pb.axes(y)
    nodes = np.argwhere(asm)
    pts = np.column_stack([np.asarray(grid.xs)[nodes[:, 1]], np.asarray(grid.ys)[nodes[:, 0]]]) / scale
    start = tuple(int(v) for v in nodes[int(np.argmin(np.linalg.norm(pts - a, axis=1)))])
    path = grid_path(asm, start, target)
    if path is None:
        return None
    try:
        for node in path:
            b = grid.at(*node) / scale
            for t in np.linspace(0.0, 1.0, substeps + 1)[1:]:
                y = pb.solve_square(a + t * (b - a), y)
            a = b
    except NotConvergedError:
        return None
    return y
