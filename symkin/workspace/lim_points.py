"""LIM points of a map (F ≥ 2): where a link turning about a fixed pivot cannot move for any motion.

The rule (paper §III-B.3, §IV-C).  A link is in LIM where every kinematic parameter of its
motion is null whatever the inputs: its free nodes' rows of an orthonormal motion-space basis
``V`` (``F`` columns, the null space of the independent constraint rows ``J_S``) vanish, as
the core decides it (``locked_links`` of :func:`symkin.analyze`).  For a planar link turning
about a fixed pivot that is one parameter, its angular rate ``ω``: its unit row
``u = (−r_y, r_x)/|r|`` at a free node (``r`` from the pivot, the definition of
:func:`symkin.analysis.indicators.link_rate`) is null on every motion exactly when it lies in
the row space of ``J_S``, ``J_Sᵀψ + u = 0`` for some ``ψ``: ``F`` conditions on the
``F``-dimensional configuration space.  A 2-D map (``F − 2`` coordinates held) meets that set
in isolated points when ``F = 2``, and generically not at all when ``F > 2``.

What a map does (:func:`symkin.workspace.loci.refine`, step 4b):

1. **Indicator** — per pivoted link, the relative LIM indicator is the norm of its free
   nodes' rows of ``V`` (:func:`symkin.analysis.indicators.link_speed` of those rows:
   dimensionless, zero exactly where the core's node speeds are), evaluated by the grid for
   every wave in one batch (:class:`LimIndicator`); the grid keeps the smallest over the links
   (``lim_indicator``) and the configurations at its minima.
2. **Candidates** — the grid nodes where it is a minimum along a grid line, against both
   assembled neighbours in x or in y (:func:`line_minima`).  Not only the minima among the eight
   neighbours: the indicator is the norm of ``F`` rates that vanish on ``F`` curves, so near its
   zero it is a cone that a nearly tangent pair of curves stretches into a narrow valley, whose
   floor the grid samples off its line and may see sloping straight through the zero.
3. **Screen and locate** — every candidate and every pivoted link take one batched
   Gauss–Newton polish (:meth:`LocusProblems.polish_lim_many`, the one corrector) of the
   square system ``(Φ_S/ℓ, J_Sᵀψ + u) = 0`` in ``(q/ℓ, ψ)`` from the grid configuration; a
   start is kept when it converged onto the map's slice (the held coordinates at their
   values: always when ``F = 2``), its axis values lie in the box and the link's indicator
   there is at most :attr:`~symkin.tolerances.Tolerances.event_threshold`.
4. **Classify** — a kept configuration is reported (kind ``"LIM"``) only when
   :func:`symkin.analyze` there has ``"LIM"`` in its types with the link in ``locked_links``;
   points at the same configuration or axis values are one.

Not detected: links without a fixed pivot (a coupler locks only where all its free nodes
stop: more than ``F`` conditions, no isolated points of a generic slice), pivoted links of
spatial mechanisms, and LIM sets that meet a slice (``F > 2``) in curves.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from symkin.analysis.classification import analyze
from symkin.analysis.indicators import link_speed
from symkin.kinds import Kind
from symkin.tolerances import Tolerances
from symkin.workspace.locus_problems import LocusProblems, LocusSystem
from symkin.workspace.refine_data import RefineStats, SingularPoint

__all__ = ["PivotedLink", "pivoted_links", "LimIndicator", "line_minima", "locate_lim_many", "add_lim_point",
           "LIM_ITERATIONS"]

#: Gauss–Newton steps of the batched LIM polish (:func:`locate_lim_many`): the system is square and
#: regular at an isolated LIM point, so a start within a grid cell converges quadratically in a few steps
LIM_ITERATIONS = 15


@dataclass(frozen=True)
class PivotedLink:
    """A moving planar link with one fixed node: its name, the pivot, its free nodes' columns in ``q``.

    ``columns`` (k, 2) the indices in ``q`` of each free node's coordinates; ``far`` the row of
    ``columns`` of the node farthest from the pivot in the model's configuration (its ``ω`` row
    is the best conditioned).
    """

    name: str
    pivot: np.ndarray
    columns: np.ndarray
    far: int


def pivoted_links(ev) -> tuple[PivotedLink, ...]:
    """The links of ``ev.mech`` whose LIM points a map locates (see the module docstring).

    >>> from symkin.model.catalogue import get
    >>> from symkin.analysis.batch import evaluators
    >>> [p.name for p in pivoted_links(evaluators(get("five_bar")))]
    ['crank1', 'crank2']
    """
    mech = ev.mech
    if mech.dim != 2:
        return ()
    where = {int(c): k for k, c in enumerate(np.flatnonzero(np.asarray(ev.free)))}
    index = mech.node_index()
    coords = mech.coordinates()
    fixed = set(mech.fixed)
    out = []
    for name in mech.moving_links:
        nodes = mech.link_nodes(name)
        pivots = [n for n in nodes if n in fixed]
        free = [n for n in nodes if n not in fixed]
        cols = [[where.get(index[n] * 2 + c) for c in range(2)] for n in free]
        if len(pivots) != 1 or not free or any(c is None for cc in cols for c in cc):
            continue
        pivot = np.asarray(coords[pivots[0]], float)
        far = int(np.argmax([np.linalg.norm(np.asarray(coords[n], float) - pivot) for n in free]))
        out.append(PivotedLink(name, pivot, np.array(cols, int), far))
    return tuple(out)


class LimIndicator:
    """The relative LIM indicator of every pivoted link at N configurations (one batch).

    ``V`` is an orthonormal basis of the null space of ``J_S`` (the core's independent rows, from
    one mapped evaluation of ``J``; a batched complete QR of ``J_Sᵀ``); a link's value is :func:`~symkin.analysis.indicators.link_speed`
    of its free nodes' rows of ``V`` (their velocities over an orthonormal basis of motions).
    """

    def __init__(self, ev):
        self.ev = ev
        self.links = pivoted_links(ev)
        self.rows = list(ev.basis_rows) if ev.basis_rows is not None else None

    def __bool__(self) -> bool:
        return bool(self.links) and self.rows is not None

    def many(self, q: np.ndarray) -> np.ndarray:
        """Values (N, number of links) at the rows of ``q`` (N, nf)."""
        q = np.atleast_2d(np.asarray(q, float))
        js = self.ev.map("J", q)["J_free"][:, self.rows, :]
        # complete QR of J_Sᵀ: its last F columns are an orthonormal basis of the motions (the null space
        # of J_S; where J_S loses rank, an IM configuration, F of its motions)
        v = np.swapaxes(np.linalg.qr(np.swapaxes(js, 1, 2), mode="complete")[0][:, :, len(self.rows):], 1, 2)
        out = np.empty((len(q), len(self.links)))
        for k, link in enumerate(self.links):
            rows = v[:, :, link.columns]  # (N, F, k, 2)
            out[:, k] = link_speed(rows.reshape(len(q), -1, 2))
        return out

    def smallest(self, q: np.ndarray) -> np.ndarray:
        """The smallest value over the links at each row of ``q`` (what the grid keeps)."""
        return self.many(q).min(axis=1)


def line_minima(values: np.ndarray, assembled: np.ndarray) -> list[tuple[int, int]]:
    """Grid nodes ``(j, i)`` where ``values`` is at most both assembled neighbours along x or along y.

    A valley whose floor slopes along y (no minimum among eight neighbours inside the grid):
    every node of its floor is one.

    >>> j, i = np.mgrid[0:4, 0:5]
    >>> line_minima((i - 2.0) ** 2 + 0.1 * j, np.ones((4, 5), bool))
    [(0, 2), (1, 2), (2, 2), (3, 2)]
    """
    v = np.asarray(values, float)
    ok = np.asarray(assembled, bool) & np.isfinite(v)
    low = np.zeros(v.shape, bool)
    low[:, 1:-1] |= ok[:, 1:-1] & ok[:, :-2] & ok[:, 2:] & (v[:, 1:-1] <= v[:, :-2]) & (v[:, 1:-1] <= v[:, 2:])
    low[1:-1, :] |= ok[1:-1, :] & ok[:-2, :] & ok[2:, :] & (v[1:-1, :] <= v[:-2, :]) & (v[1:-1, :] <= v[2:, :])
    return [(int(j), int(i)) for j, i in zip(*np.nonzero(low))]


def locate_lim_many(pb: LocusProblems, indicator: LimIndicator, starts: list, box_d: np.ndarray,
                    tol: Tolerances, stats: RefineStats) -> list[tuple[np.ndarray, PivotedLink]]:
    """Located LIM configurations from the grid configurations ``starts`` (``[y]``), every link at once.

    One batched polish of every start and link (:meth:`LocusProblems.polish_lim_many`); a
    result is kept when it converged, its axis values are in the box (``box_d``,
    dimensionless) and the link's indicator there is at most ``tol.event_threshold``.
    Returns ``[(y, link)]`` (the core classifies them afterwards).
    """
    if not starts or not indicator:
        return []
    y0 = np.array(starts, float)
    out = []
    lo, hi = box_d[:, 0], box_d[:, 1]
    for k, link in enumerate(indicator.links):
        y, ok = pb.polish_lim_many(link, y0, LIM_ITERATIONS)
        good = np.flatnonzero(ok)
        value = np.full(len(y0), np.inf)
        if good.size:
            value[good] = indicator.many(y[good] * pb.scale)[:, k]
        for m in range(len(y0)):
            a = pb.axes(y[m]) if ok[m] else None
            if a is None or not (value[m] <= tol.event_threshold and np.all(a >= lo) and np.all(a <= hi)):
                stats.lim_screened += 1
                continue
            if not any(l is link and np.linalg.norm(y[m] - v) <= tol.same_configuration for v, l in out):
                out.append((y[m], link))  # many starts along a valley reach the same point: once
    return out


def add_lim_point(points: list, pb: LocusProblems, system: LocusSystem, y: np.ndarray, link: PivotedLink, mode,
                  scale, tol: Tolerances) -> bool:
    """Record ``y`` as a point of kind ``"LIM"`` when the core says LIM with ``link`` locked (True if recorded).

    The types and ``locked_links`` are :func:`symkin.analyze`'s at the configuration; a point
    already recorded at the same configuration or axis values (within
    :attr:`Tolerances.same_configuration`) is not recorded again.
    """
    q = y * pb.scale
    res = analyze(system.evaluators.mechanism_at(q), tol)
    if Kind.LIM not in res.types or link.name not in res.locked_links:
        return False
    at = pb.axes(y) * scale
    for p in points:
        if (np.linalg.norm((p.configuration - q) / pb.scale) <= tol.same_configuration
                or np.linalg.norm((p.at - at) / scale) <= tol.same_configuration):
            return False
    points.append(SingularPoint(str(Kind.LIM), mode, at, tuple(str(t) for t in res.types), q,
                                tuple(res.locked_links)))
    return True
