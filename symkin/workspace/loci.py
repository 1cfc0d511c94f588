"""Refinement of a singularity map to exact curves: crossing location and curve tracing (issue 8).

A map fixes two position-level *axis coordinates* ``a(q) = (x, y)`` of a mechanism with
``F`` degrees of freedom; the remaining ``F − 2`` coordinates are *held*.  With the
closure ``Φ(q) = 0`` this leaves, at each axis point, a square position problem (the
map's grid), and with one more equation ``T(q) = 0`` a 1-D solution set: a singular
curve.  ``T`` is one of the signed DKP test functions of the one analysis core,
``det[J_S; P̂] / sqrt(det(J_S J_Sᵀ))`` for the input rows (``DKP-input``, type 2, eq. 12)
or the output rows (``DKP-output``, type 1, eq. 16), taken as a CasADi expression from
the ``indicators`` Function of :mod:`symkin.numeric.evaluators` (no copy of it here).

Contract with the map engine
----------------------------
:func:`refine` ``(system, grid, mode, tolerances, box)`` returns ``(curves, points, stats)``.

``system``
    the map's :class:`symkin.workspace.system.MapSystem` (its ``constraints`` and ``axes``
    Functions, ``hold_values``, ``evaluators``), or a :class:`LocusSystem` built from it
    (:meth:`LocusSystem.of`): an SX symbol ``q`` of the ``nf`` free coordinates,
    ``constraints`` (SX, dimensionless: ``Φ_S/ℓ`` and the held coordinates, ``nf − 2``
    rows), ``axes`` (SX, 2 rows, in *axis values*: the user's unit, model lengths or
    degrees / radians as the map's ``unit``) and ``axis_scale`` (axis values per
    dimensionless unit: ``ℓ`` for a length axis, one radian in the user's unit for an
    angle), ``ℓ`` the model's length scale.
``grid`` (:class:`GridData`)
    ``xs`` (nx,), ``ys`` (ny,) axis values in the user's unit (as ``axes``); arrays of shape ``(ny, nx)`` indexed
    ``[j, i]`` ↔ ``(xs[i], ys[j])``: ``assembled`` (bool), ``dkp_input``, ``dkp_output``,
    ``im_indicator`` and ``trace`` (NaN where not assembled), and ``q`` (``(ny, nx, nf)``)
    or a callable ``configuration(j, i) -> q | None`` when configurations are not stored.
``box``
    ``((x_lo, x_hi), (y_lo, y_hi))`` in axis values (default: the grid's extent).

Algorithm
---------
1. **Crossings** — every grid edge whose two assembled ends have opposite signs of a DKP
   test function brackets a crossing.  The roots of all brackets of a kind are searched
   together along their edges (:func:`locate_crossings`: regula falsi on ``T`` of the square
   problem solved at interpolated axis values, warm-started from the nearer end, each step
   one batched solve), then polished together by Gauss–Newton on the extended system
   ``(Φ/ℓ, holds, a(q)/axis_scale − (a₀ + s·d), T) = 0`` in ``(q/ℓ, s)`` (one batch).
2. **Folds** — an edge from an assembled to an unassembled end brackets the mode's
   workspace boundary (a fold of the square problem).  Bisection on "the square problem
   still solves from the assembled neighbour" narrows it; the same extended system with
   the DKP test function that vanishes there (``DKP-output`` in a workspace map,
   ``DKP-input`` in a joint-space map: the smaller of the two) polishes it.
3. **Tracing** — from a located point, the one tracer (:func:`symkin.curves.tracer.trace_curve`,
   pseudo-arclength continuation) follows ``(Φ/ℓ, holds, T) = 0`` in ``y = q/ℓ`` with both
   axis coordinates free, in both directions; the map's events and stop rules are objects
   (:mod:`symkin.workspace.locus_events`).  A curve ends where it *leaves the mode* (the
   other DKP test function changes sign: located by sign change), meets another locus at a
   branch point (``det[H'; tᵀ]`` changes sign), *leaves the box* (the curves' ``LeftBox``;
   the last point is solved onto the box edge), nears an IM configuration (the relative IM
   indicator ``sqrt(λ_{F+1}/tr G)`` at a point, or its located minimum between points,
   below :attr:`Tolerances.near_branch`: ``T`` is not defined at IM; the IM configuration is
   then refined as in step 4), runs into a family of configurations over one map point (its
   image stays put over two steps: end ``"point"``) or cannot be continued; it is *closed*
   when it crosses its start's normal plane near its start (the curves' ``Closed`` rule).
   On the way, a **cusp** of the curve's image in the axes (the axis velocity ``∂A/∂y · t``
   reverses between two points) is located along the curve and kept when the relative axis
   speed there is at most :attr:`Tolerances.event_threshold` (:func:`locate_cusp`); it
   neither stops nor splits the curve.  A "curve" whose whole image is one map point (a
   leg of zero length turning about its pivot) is no curve: it is reported as one point
   (classified by the core), seeds nothing, and the points recorded at that map point are
   one (:func:`symkin.workspace.singular_points.one_per_family`).  A crossing that lies on a curve already traced (configuration
   within a few cell sizes of its polyline in ``q``) is not traced again.
4. **IM points** — at each grid node whose IM indicator is below its eight neighbours
   (:func:`symkin.workspace.im_points.im_candidates`), the cells around it are subdivided
   (:func:`symkin.workspace.quadtree.subdivide_many` with the IM indicator as ``T``: it has no
   sign change, so the quadtree descends to the finest cell holding its smallest value) — all
   minima together, each level's new points of every minimum solved in one batch
   (:meth:`LocusProblems.solve_square_many`: :func:`symkin.curves.corrector.gauss_newton_batch`
   on a CasADi ``Function.map`` of the square problem).  **Screen**: every start (the finest
   points, then the node) takes one batched Gauss–Newton polish towards a rank drop of the
   constraints (:meth:`LocusProblems.polish_rank_drop_many`), and a minimum is refined only when
   the smallest relative IM indicator reached is at most :attr:`Tolerances.event_threshold`;
   then :func:`symkin.curves.locate.locate_singular_point` looks for a nearby configuration where
   the constraints lose rank (:func:`symkin.workspace.im_points.locate_im`); the core decides
   whether it is IM (it is then reported).

   **4b. LIM points** (F ≥ 2) — at each grid node whose relative LIM indicator (the grid's
   ``lim_indicator``: the smallest over the links turning about a fixed pivot) is a minimum along
   a grid line, every pivoted link takes one batched Gauss–Newton polish towards
   ``(Φ_S/ℓ, J_Sᵀψ + u) = 0`` (:meth:`LocusProblems.polish_lim_many`); a start converged on the
   slice, in the box, whose link indicator is at most :attr:`Tolerances.event_threshold` is reported as a point of
   kind ``"LIM"`` when :func:`symkin.analyze` there says LIM with that link locked
   (:mod:`symkin.workspace.lim_points`).
5. **Dips, quadtree, double zeros** — a grid point whose ``|T|`` is a near-zero minimum along
   a grid line (:func:`symkin.workspace.quadtree.dips`) starts an adaptive subdivision of the
   cells around it (to :data:`~symkin.workspace.quadtree.DEPTH`; every dip of a kind not next
   to a curve traced so far subdivided together, one batch per level and sub-step, as in step 4):
   its finest sign changes are located as in step 1, in one batch per dip (two crossings in one cell, a small
   closed curve), its finest minima by :func:`locate_double_zero` (``T = 0`` with
   ``∂T/∂n = 0``); a double zero the core confirms is traced by :func:`trace_double_zero`.
   Dips are taken in grid order; one that a curve traced from an earlier dip passes is skipped.
6. **Points** — where a curve ends on the mode boundary or near IM, the end
   configuration is classified by the core (:meth:`Evaluators.indicators_at`) and
   reported as a :class:`SingularPoint` (``kind`` ``"IM"`` when IM, else ``"meeting"``
   when it has two or more types, else its type); a cusp inside the box is reported with
   ``kind`` ``"cusp"`` and the core's types.

Where it lives: the problems on a locus (:mod:`~symkin.workspace.locus_problems`), the grid and the
results (:mod:`~symkin.workspace.refine_data`), locating crossings, folds and double zeros
(:mod:`~symkin.workspace.locate`), IM points (:mod:`~symkin.workspace.im_points`), re-solving a
grid configuration from the seed (:mod:`~symkin.workspace.reseed`), cusps
(:mod:`~symkin.workspace.cusps`), the events and stop rules of a traced locus
(:mod:`~symkin.workspace.locus_events`), tracing (:mod:`~symkin.workspace.tracing`), classifying and
recording points (:mod:`~symkin.workspace.singular_points`); this module is the driver.

Accuracy: every located and traced point satisfies ``‖(Φ/ℓ, holds, T)‖ ≤ 1e-12``
(Newton's tolerance), i.e. it lies on its locus to ~1e-12 relative to ``ℓ`` where the
locus is regular; crossings are polished until the Gauss–Newton step is below 1e-10
relative (``‖Δ(q/ℓ)‖``).
"""
from __future__ import annotations

from typing import Any

import numpy as np

from symkin.errors import NotConvergedError
from symkin.curves.stepper import Settings
from symkin.kinds import Kind
from symkin.tolerances import DEFAULT, Tolerances
from symkin.workspace import quadtree
from symkin.workspace.cusps import locate_cusp
from symkin.workspace.im_points import im_candidates, locate_im_many
from symkin.workspace.lim_points import LimIndicator, add_lim_point, line_minima, locate_lim_many
from symkin.workspace.locate import locate_crossing, locate_crossings, locate_double_zero, locate_fold
from symkin.workspace.locus_problems import KINDS, OTHER_KIND, LocusProblems, LocusSystem
from symkin.workspace.refine_data import Curve, GridData, RefineStats, SingularPoint
from symkin.workspace.reseed import resolve_from_seed
from symkin.workspace.singular_points import add_point, one_per_family
from symkin.workspace.locus_events import END_POINT
from symkin.workspace.tracing import polyline_distance, trace_double_zero, trace_locus

__all__ = ["LocusSystem", "GridData", "Curve", "SingularPoint", "RefineStats", "refine",
           "locate_crossing", "locate_fold", "locate_double_zero", "locate_cusp", "trace_locus", "trace_double_zero",
           "KINDS"]


def _boundary(grid: GridData, signs: list) -> tuple[str, float]:
    """The test function whose zero set bounds the mode (no sign change on the grid) and its sign there.

    In a workspace map the square problem is singular exactly where ``DKP-output``
    vanishes, so that function keeps one sign over a mode and the mode ends where it
    vanishes (a fold); in a joint-space map the same holds for ``DKP-input``.  When
    neither changes sign on the grid, ``DKP-output`` (a workspace map) is assumed.
    """
    changing = {k for k, _, _ in signs}
    asm = np.asarray(grid.assembled, bool)
    for kind in (Kind.DKP_OUTPUT, Kind.DKP_INPUT):
        if kind in changing:
            continue
        v = np.asarray(getattr(grid, KINDS[kind]), float)[asm]
        v = v[np.isfinite(v)]
        if v.size:
            return kind, float(np.sign(np.median(v))) or 1.0
    return Kind.DKP_OUTPUT, 1.0


# ---------------------------------------------------------------------- refine
def _brackets(grid: GridData):
    """Grid edges ``((j, i), (j2, i2))``: sign changes per kind, and assembled/unassembled pairs."""
    asm = np.asarray(grid.assembled, bool)
    ny, nx = asm.shape
    signs, folds = [], []
    for dj, di in ((0, 1), (1, 0)):
        a = (slice(0, ny - dj), slice(0, nx - di))
        b = (slice(dj, ny), slice(di, nx))
        for kind, arr in ((Kind.DKP_INPUT, grid.dkp_input), (Kind.DKP_OUTPUT, grid.dkp_output)):
            if arr is None:
                continue
            v = np.asarray(arr, float)
            with np.errstate(invalid="ignore"):
                hit = asm[a] & asm[b] & (np.sign(v[a]) * np.sign(v[b]) < 0)
            for j, i in zip(*np.nonzero(hit)):
                signs.append((kind, (j, i), (j + dj, i + di)))
        for j, i in zip(*np.nonzero(asm[a] != asm[b])):
            pa, pb_ = (j, i), (j + dj, i + di)
            folds.append((pa, pb_) if asm[pa] else (pb_, pa))
    return signs, folds


def _crossings(pb: LocusProblems, grid: GridData, signs: list, dim_axes, stats: RefineStats) -> list:
    """The sign changes ``signs`` located in batches, one per kind (:func:`locate_crossings`).

    Per bracket: ``False`` where a grid end has no configuration (skipped), None where the
    location failed, else ``(y, s)``.  The evaluations count as locating.
    """
    out: list = [False] * len(signs)
    before = pb.counter.n
    for kind in KINDS:
        rows, ends = [], []
        for k, (kd, pa, pb_) in enumerate(signs):
            qa, qb = grid.config(*pa), grid.config(*pb_)
            if kd == kind and qa is not None and qb is not None:
                rows.append(k)
                ends.append((dim_axes(*pa), qa / pb.scale, dim_axes(*pb_), qb / pb.scale))
        if rows:
            found = locate_crossings(pb, kind, *(np.array([e[i] for e in ends]) for i in range(4)))
            for k, f in zip(rows, found):
                out[k] = f
    stats.locate_evaluations += pb.counter.n - before
    return out


def _found(found) -> np.ndarray:
    """The configuration of a crossing located in a batch (raises NotConvergedError where it failed)."""
    if found is None:
        raise NotConvergedError("crossing not located")
    return found[0]


def _lim_points(pb: LocusProblems, sys_: LocusSystem, grid: GridData, scale, box_d, tol: Tolerances,
                stats: RefineStats, points: list, mode) -> None:
    """Step 4b: LIM points at the grid's LIM-indicator minima (:mod:`symkin.workspace.lim_points`)."""
    if grid.lim_indicator is None:
        return
    indicator = LimIndicator(sys_.evaluators)
    starts = []
    for j, i in line_minima(grid.lim_indicator, grid.assembled):
        qa = grid.config(j, i)
        ya = qa / pb.scale if qa is not None else resolve_from_seed(pb, grid, scale, (j, i))
        if ya is None:
            stats.failed += 1
            continue
        starts.append(ya)
    stats.lim_candidates += len(starts)
    for y, link in locate_lim_many(pb, indicator, starts, box_d, tol, stats):  # one batch per link, screened
        stats.lim_points += add_lim_point(points, pb, sys_, y, link, mode, scale, tol)


def refine(system, grid: GridData, mode: Any = 0, tolerances: Tolerances = DEFAULT, box=None,
           settings: Settings | None = None) -> tuple[list[Curve], list[SingularPoint], RefineStats]:
    """Locate and trace a mode's singular curves from its grid (see the module docstring).

    Parameters
    ----------
    system : LocusSystem or an object with its attributes
    grid : GridData
    mode : any
        The mode's id, copied into the results.
    tolerances : Tolerances
        ``near_branch`` stops a curve near IM; ``rank`` classifies end points (core).
    box : ((x_lo, x_hi), (y_lo, y_hi)), optional
        In axis values; default the grid's extent.
    settings : continuation Settings, optional
        Default: steps of half a cell, at most two cells (dimensionless).

    Returns
    -------
    curves : list of Curve
    points : list of SingularPoint
    stats : RefineStats

    Examples
    --------
    The catalogue five-bar (|A_i B_i| = 1, |B_i P| = 2, A = (∓1, 0)) over a coarse grid: the
    mode's workspace boundary is the four circles |P − A_i| = 1, 3 (type 1, ``DKP-output``);
    the outer ones end where they meet, at P = (0, √8), a corner of the workspace.

    >>> import numpy as np
    >>> from symkin.model.catalogue import get
    >>> from symkin.workspace.system import map_system
    >>> from symkin.workspace.grid import continue_mode
    >>> s = map_system(get("five_bar"), "velocity:P.x", "velocity:P.y")
    >>> xs, ys = np.linspace(-3.5, 3.5, 15), np.linspace(0.2, 4.4, 10)
    >>> g = continue_mode(s, xs, ys, s.q0, keep_configurations=True)
    >>> grid = GridData(xs, ys, g.assembled, g.dkp_input, g.dkp_output, g.im_indicator, q=g.q)
    >>> curves, points, stats = refine(s, grid)
    >>> sorted(c.ends for c in curves)
    [('box', 'box'), ('box', 'box'), ('box', 'branch'), ('box', 'branch')]
    >>> err = [min(abs(np.hypot(*(c.points - (a, 0)).T) - r).max() for a in (-1, 1) for r in (1, 3)) for c in curves]
    >>> bool(max(err) < 1e-9)
    True
    >>> [(pt.kind, (abs(pt.at) + 0.0).round(9).tolist()) for pt in points]
    [('DKP-output', [0.0, 2.828427125])]
    """
    sys_ = LocusSystem.of(system)
    tol = Tolerances.of(tolerances)
    pb = LocusProblems(sys_, tol)
    scale = np.array(sys_.axis_scale, float)
    if box is None:
        box = ((float(np.min(grid.xs)), float(np.max(grid.xs))), (float(np.min(grid.ys)), float(np.max(grid.ys))))
    box_d = np.array(box, float) / scale[:, None]
    cell = min(abs(float(np.diff(grid.xs).min())) / scale[0], abs(float(np.diff(grid.ys).min())) / scale[1])
    if settings is None:
        settings = Settings(step=0.5 * cell, max_step=2.0 * cell, min_step=1e-6 * cell)
    stats = RefineStats()
    curves: list[Curve] = []
    traced: list = []  # (kind, ys, closed, dimensionless axis points)
    points: list[SingularPoint] = []
    dup_radius = 1.5 * cell

    point_images: list = []  # (kind, [y]): "curves" whose image is one point (reported as a point)
    families: list = []  # their axis points: one singular point each

    def on_traced(kind, y, radius):
        return (any(k == kind and polyline_distance(y, ys, c) <= radius for k, ys, c, _ in traced)
                or any(k == kind and polyline_distance(y, ys, False) <= radius for k, ys in point_images))

    def near_traced(kinds, a):
        """Pre-check on the grid: the bracket's axis point within ``dup_radius`` of a traced curve."""
        return any(k in kinds and polyline_distance(a, ax, c) <= dup_radius for k, _, c, ax in traced)

    def dim_axes(j, i):
        return grid.at(j, i) / scale

    def take(kind, y, tracer=None):
        before = pb.counter.n
        ys, closed, ends, end_ys, meets, cusps = (tracer or trace_locus)(pb, kind, y, box_d, settings, tol, boundary)
        if ends == (END_POINT,):
            # a family of configurations over one map point: one singular point, no curve, no seeds
            stats.trace_evaluations += pb.counter.n - before
            point_images.append((kind, ys))
            families.append(pb.axes(ys[0]) * scale)
            add_point(points, pb, sys_, ys[0], mode, scale, tol)
            return
        seeds.extend(meets)
        end_ys = end_ys + meets
        stats.trace_evaluations += pb.counter.n - before
        stats.traced_points += len(ys)
        ax = np.array([pb.axes(v) for v in ys])
        traced.append((kind, ys, closed, ax))
        pts = ax * scale
        qs = ys * pb.scale
        # plain strings in the results (a Kind is its string): their reprs and JSON stay as they were
        curves.append(Curve(str(kind), mode, closed, pts, qs, tuple(str(e) for e in ends), pb.counter.n - before))
        for ye in end_ys:
            add_point(points, pb, sys_, ye, mode, scale, tol)
        for yc in cusps:
            if np.all(pb.axes(yc) >= box_d[:, 0]) and np.all(pb.axes(yc) <= box_d[:, 1]):
                add_point(points, pb, sys_, yc, mode, scale, tol, kind=Kind.CUSP)

    signs, folds = _brackets(grid)
    stats.crossings, stats.folds = len(signs), len(folds)
    boundary = _boundary(grid, signs)
    seeds: list = []  # meeting points found along boundary curves: interior curves start there
    def locate_and_take(kinds, pa, pb_, locate, errors, mid=None) -> None:
        """Locate one crossing or fold between grid points ``pa``, ``pb_`` and trace from it.

        ``mid`` (dimensionless axis values) replaces the grid pre-check: a crossing of the
        quadtree is checked only once located (it may lie within a cell of a traced curve).
        """
        if mid is None and near_traced(kinds, 0.5 * (dim_axes(*pa) + dim_axes(*pb_))):
            stats.duplicates += 1
            return
        before = pb.counter.n
        try:
            kind, y = locate()
        except errors:
            stats.failed += 1
            return
        stats.locate_evaluations += pb.counter.n - before
        stats.located += 1
        if on_traced(kind, y, 0.5 * settings.max_step):
            stats.duplicates += 1
            return
        take(kind, y)

    located = _crossings(pb, grid, signs, dim_axes, stats)  # every sign change located at once, per kind
    for (kind, pa, pb_), found in zip(signs, located):
        if found is False:
            continue
        locate_and_take((kind,), pa, pb_, lambda found=found, kind=kind: (kind, _found(found)), NotConvergedError)
    for pa, pb_ in folds:
        qa = grid.config(*pa)
        if qa is None:
            continue
        ya = qa / pb.scale
        # the grid pre-check against the boundary's kind only: a fold next to an interior curve of the
        # other kind (the Delta's type-2 curve runs within a cell of its reach boundary) is still located
        locate_and_take((boundary[0],), pa, pb_,
                        lambda: locate_fold(pb, dim_axes(*pa), ya, dim_axes(*pb_), tol=tol)[:2],
                        NotConvergedError)
    steps = np.array([abs(float(grid.xs[1] - grid.xs[0])) / scale[0], abs(float(grid.ys[1] - grid.ys[0])) / scale[1]])
    before = pb.counter.n
    centres = []
    for j, i in im_candidates(grid):
        qa = grid.config(j, i)
        ya = qa / pb.scale if qa is not None else resolve_from_seed(pb, grid, scale, (j, i))
        if ya is None:
            stats.failed += 1
            continue
        centres.append((dim_axes(j, i), ya))
    for y in locate_im_many(pb, centres, steps, box_d, tol, stats):  # one batch per level, screened
        if y is None:
            stats.failed += 1
            continue
        stats.im_candidates += 1
        add_point(points, pb, sys_, y, mode, scale, tol, only_im=True)
    _lim_points(pb, sys_, grid, scale, box_d, tol, stats, points, mode)
    stats.locate_evaluations += pb.counter.n - before
    interior = OTHER_KIND[boundary[0]]
    while seeds:
        y = seeds.pop(0)
        if on_traced(interior, y, 0.5 * settings.max_step):
            stats.duplicates += 1
            continue
        stats.seeded += 1
        take(interior, y)

    def near_traced_dip(kind, a_c):
        return any(k == kind and polyline_distance(a_c, ax, c) <= cell for k, _, c, ax in traced)

    def dip_configuration(j, i):
        q = grid.config(j, i)
        return q / pb.scale if q is not None else resolve_from_seed(pb, grid, scale, (j, i))

    def refine_dip(kind, j, i, y_c, sub):
        """Locate and trace what the subdivision ``sub`` around a dip of ``T`` found (:mod:`symkin.workspace.quadtree`)."""
        if near_traced_dip(kind, dim_axes(j, i)):  # a curve traced from an earlier dip passes here
            stats.duplicates += 1
            return
        if y_c is None:
            stats.failed += 1
            return
        stats.dips += 1
        stats.subdivided += sub.samples
        if sub.crossings:  # the subdivision's sign changes located at once (each is checked once located)
            before = pb.counter.n
            located_here = locate_crossings(pb, kind, *(np.array([c[i] for c in sub.crossings]) for i in range(4)))
            stats.locate_evaluations += pb.counter.n - before
            for (aa, ya, ab, yb), found in zip(sub.crossings, located_here):
                locate_and_take((kind,), None, None, lambda found=found: (kind, _found(found)),
                                NotConvergedError, mid=0.5 * (aa + ab))
        for a, y, h in sub.dips:
            before = pb.counter.n
            found = None
            for d in (np.array([2 * h[0], 0.0]), np.array([0.0, 2 * h[1]])):
                try:
                    found = locate_double_zero(pb, kind, a, y, d, tol)[0]
                    break
                except (NotConvergedError, ValueError):
                    continue
            stats.locate_evaluations += pb.counter.n - before
            if found is None:
                continue
            if on_traced(kind, found, 0.5 * settings.max_step):
                stats.duplicates += 1
                continue
            res = sys_.evaluators.indicators_at(found * pb.scale, tol)
            if not res["is_" + KINDS[kind]]:
                continue
            stats.located += 1
            stats.double_zeros += 1
            take(kind, found, trace_double_zero)

    for kind, name in KINDS.items():
        values = getattr(grid, name)
        if values is None:
            continue
        # every dip of this kind not next to a curve traced so far is subdivided in one batch per level; then
        # each is located and traced in grid order (one next to a curve traced from an earlier dip is skipped)
        found_dips = [(int(j), int(i)) for j, i in zip(*np.nonzero(quadtree.dip_mask(values, grid.assembled)))]
        todo = {d: dip_configuration(*d) for d in found_dips if not near_traced_dip(kind, dim_axes(*d))}
        ready = [(d, y) for d, y in todo.items() if y is not None]
        before = pb.counter.n
        if ready:
            y0 = np.array([y for _, y in ready])
            subs = quadtree.subdivide_many(pb.solve_square_many, lambda y, k=kind: pb.tests_many(y)[k],
                                           [(dim_axes(*d), y, t) for (d, y), t in zip(ready, pb.tests_many(y0)[kind])],
                                           steps, box_d[:, 0], box_d[:, 1])
        else:
            subs = []
        stats.locate_evaluations += pb.counter.n - before
        subdivision = {d: sub for (d, _), sub in zip(ready, subs)}
        for d in found_dips:
            refine_dip(kind, *d, todo.get(d), subdivision.get(d))
    return curves, one_per_family(points, families, scale, tol), stats
