"""What refinement reads and returns: a mode's grid (:class:`GridData`), the traced curves (:class:`Curve`),
the isolated singular points (:class:`SingularPoint`) and the cost (:class:`RefineStats`).

See :mod:`symkin.workspace.loci` for the contract.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from symkin.errors import SymkinError

__all__ = ["GridData", "Curve", "SingularPoint", "RefineStats"]


@dataclass(frozen=True, eq=False)
class GridData:
    """Grid values of one mode (arrays ``(ny, nx)`` indexed ``[j, i]`` ↔ ``(xs[i], ys[j])``)."""

    xs: np.ndarray
    ys: np.ndarray
    assembled: np.ndarray
    dkp_input: np.ndarray
    dkp_output: np.ndarray
    im_indicator: np.ndarray | None = None
    trace: np.ndarray | None = None
    q: np.ndarray | None = None
    configuration: Callable[[int, int], np.ndarray | None] | None = None
    #: the mode's seed configuration: where no configuration was kept (an IM-indicator minimum
    #: of a grid without stored configurations), one is re-solved along assembled grid points from it
    seed: np.ndarray | None = None
    #: the smallest relative LIM indicator over the pivoted links (:mod:`symkin.workspace.lim_points`), or None
    lim_indicator: np.ndarray | None = None

    def config(self, j: int, i: int) -> np.ndarray | None:
        """The configuration at ``[j, i]``: from ``q`` when stored there, else from ``configuration``; or None."""
        if not self.assembled[j, i]:
            return None
        if self.q is not None:
            q = np.asarray(self.q[j, i], float)
            if np.all(np.isfinite(q)):
                return q
        if self.configuration is not None:
            q = self.configuration(j, i)
            return None if q is None or not np.all(np.isfinite(q)) else np.asarray(q, float)
        if self.q is None:
            raise SymkinError("refinement needs the grid's configurations (q) or a way to re-solve them")
        return None

    def at(self, j: int, i: int) -> np.ndarray:
        return np.array([self.xs[i], self.ys[j]], float)



# ---------------------------------------------------------------------- results
@dataclass(frozen=True, eq=False)
class Curve:
    """A traced singular curve of one mode.

    ``points`` (N, 2) in axis values, ordered along the curve (a closed curve's last point
    joins its first, which is not repeated); ``configurations`` (N, nf) the free
    coordinates there; ``ends`` why each end stopped (``"closed"``, ``"box"``,
    ``"boundary"``, ``"branch"``, ``"IM"``, ``"point"`` — it ran into a family of configurations
    over one map point —, ``"left"`` — a double-zero curve left the double zero —, ``"stalled"``,
    ``"steps"``).
    """

    kind: str
    mode: Any
    closed: bool
    points: np.ndarray = field(repr=False)
    configurations: np.ndarray = field(repr=False)
    ends: tuple[str, ...] = ()
    evaluations: int = 0

    def to_dict(self) -> dict:
        return {"kind": self.kind, "mode": self.mode, "closed": bool(self.closed),
                "points": [[float(a), float(b)] for a, b in self.points]}


@dataclass(frozen=True, eq=False)
class SingularPoint:
    """An isolated singular point (an IM point, where a curve meets the mode boundary, a cusp), classified by the core."""

    kind: str
    mode: Any
    at: np.ndarray
    types: tuple[str, ...]
    configuration: np.ndarray = field(repr=False, default=None)
    #: the core's locked links (a LIM point)
    locked_links: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        out = {"kind": self.kind, "mode": self.mode, "at": [float(v) for v in self.at], "types": list(self.types)}
        if self.locked_links:
            out["locked_links"] = list(self.locked_links)
        return out


@dataclass
class RefineStats:
    """What refinement cost: brackets seen, located points, skipped duplicates, evaluations.

    ``located`` crossings and folds located on the grid, ``seeded`` interior curves started
    from meeting points on boundary curves, ``duplicates`` brackets or seeds that lay on a
    curve already traced; ``dips`` grid dips subdivided, ``subdivided`` points the quadtree
    solved, ``double_zeros`` double zeros located; ``im_candidates`` IM-indicator minima refined to an
    IM configuration, ``im_screened`` minima left after the batched screen; ``lim_candidates`` LIM-indicator minima polished,
    ``lim_screened`` (start, link) pairs left after the LIM screen, ``lim_points`` LIM points recorded;
    ``*_evaluations`` count
    residual-and-Jacobian evaluations.
    """

    crossings: int = 0
    folds: int = 0
    located: int = 0
    seeded: int = 0
    im_candidates: int = 0
    im_screened: int = 0
    lim_candidates: int = 0
    lim_screened: int = 0
    lim_points: int = 0
    duplicates: int = 0
    failed: int = 0
    locate_evaluations: int = 0
    trace_evaluations: int = 0
    traced_points: int = 0
    dips: int = 0
    subdivided: int = 0
    double_zeros: int = 0

    @property
    def evaluations_per_located_point(self) -> float:
        return self.locate_evaluations / self.located if self.located else math.nan

