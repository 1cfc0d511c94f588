"""Tiled continuation of the map's modes, in one process or on a Dask cluster (issue 8, part 4b).

The grid is cut into *tiles* (``tile × tile`` grid points; a last tile narrower than two
points joins its neighbour).  A **coarse sweep** — :func:`symkin.workspace.grid.continue_mode`
of the mode on the sub-grid of every tile's corner points, configurations kept — gives each
tile its *seeds*: the assembled coarse points on the tile's closure (its own corner first, then
the corners it shares with the next tiles), and the mode's own seed for the tile nearest it.
:func:`run_tile` then continues the mode inside the tile from its first seed (paper §VI: the
indicators of the one analysis core, through ``continue_mode``), and from a further seed only
where the earlier ones did not reach; it returns the tile's grid arrays, its branch changes and
the configurations on its edge ring and at its brackets (what refinement needs).

**One definition, two schedulers.**  :func:`run_tile` is the only tile function: the serial
path (``client=None``) calls it tile after tile in this process, the Dask path submits the same
calls to the workers.  Every call builds (or finds in its process's cache) the map's position
problem from plain data — :meth:`Mechanism.to_dict`, axis labels, holds, unit, tolerances
(:class:`MapSpec`) — so the compiled evaluators come from each worker's own artefact cache
(process-safe: :mod:`symkin.numeric.codegen`).  Same inputs, same floating-point operations: the
grid arrays of a Dask run are *identical* to those of the serial tiled run, and curve tracing
(:func:`on_system`, one task per mode, run where that mode's crossings are) gives the same curves.

Memory stays bounded: a tile holds the configurations of its ``tile²`` points only while it
runs; the map keeps its grid arrays and the configurations on tile edges and at brackets
(``O(n² / tile)``), every configuration only with ``keep_configurations=True``.

Dask is an optional extra (``pip install -e ".[dask]"``); it is imported only inside
:func:`dask_client` and :func:`_map_tasks`, and no cluster starts at import time (worker
processes re-import the caller's main module).
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass, field

import numpy as np

from symkin.errors import SymkinError
from symkin.model.mechanism import Mechanism
from symkin.tolerances import Tolerances
from symkin.workspace.grid import ModeGrid, continue_mode, continue_modes
from symkin.workspace.lim_points import LimIndicator
from symkin.workspace.system import MapSystem, map_system

__all__ = ["MapSpec", "TileResult", "DASK_EXTRA", "TILE", "tile_bounds", "coarse_seeds", "run_tile", "run_tiles",
           "tiled_mode", "on_system", "dask_client", "system_of"]

#: the message part that names the optional extra
DASK_EXTRA = 'the dask extra: pip install -e ".[dask]" (dask[distributed])'
#: default tile side, in grid points
TILE = 256


# ---------------------------------------------------------------------- the map's problem as plain data
@dataclass(frozen=True)
class MapSpec:
    """What a worker needs to build the map's :class:`MapSystem`: plain, picklable data.

    ``mech`` is :meth:`Mechanism.to_dict`; ``hold`` the holds as the user gave them
    (labels, ``LABEL=VALUE`` strings or ``(label, value)`` pairs); ``windows`` the axes'
    ranges (angle axes are measured modulo a turn on them: :func:`~symkin.workspace.system.map_system`).
    """

    mech: dict
    x: str
    y: str
    hold: tuple = ()
    unit: str = "deg"
    tolerances: Tolerances = field(default_factory=Tolerances)
    windows: tuple | None = None

    @classmethod
    def of(cls, mech: Mechanism, x: str, y: str, hold=(), unit: str = "deg", tolerances=None,
           windows=None) -> "MapSpec":
        hold = tuple(h if isinstance(h, str) else (str(h[0]), None if h[1] is None else float(h[1])) for h in hold)
        windows = None if windows is None else tuple((float(lo), float(hi)) for lo, hi in windows)
        return cls(mech.to_dict(), x, y, hold, unit, Tolerances.of(tolerances), windows)

    @property
    def key(self) -> str:
        return repr(self)


_SYSTEMS: dict[str, MapSystem] = {}


def system_of(spec: MapSpec) -> MapSystem:
    """The map's position problem of ``spec``, built once per process (evaluators from the artefact cache)."""
    key = spec.key
    if key not in _SYSTEMS:
        mech = Mechanism.from_dict(spec.mech)
        _SYSTEMS[key] = map_system(mech, spec.x, spec.y, hold=spec.hold, unit=spec.unit,
                                   tolerances=spec.tolerances, windows=spec.windows)
    return _SYSTEMS[key]


def on_system(spec: MapSpec, fn, *args):
    """``fn(system_of(spec), *args)``: a task that needs the map's problem (e.g. refining one mode)."""
    return fn(system_of(spec), *args)


# ---------------------------------------------------------------------- tiles
def tile_bounds(n: int, tile: int) -> list[int]:
    """Start indices of the tiles along an axis of ``n`` points, and ``n``; every tile has >= 2 points.

    >>> tile_bounds(41, 10), tile_bounds(20, 10), tile_bounds(5, 64)
    ([0, 10, 20, 30, 41], [0, 10, 20], [0, 5])
    """
    tile = max(2, int(tile))
    b = list(range(0, n, tile)) + [n]
    if len(b) > 2 and b[-1] - b[-2] < 2:
        del b[-2]
    return b


@dataclass(frozen=True, eq=False)
class TileResult:
    """One tile of one mode: its index ranges and grid arrays (``(j1 − j0, i1 − i0)``).

    ``configurations`` ``{(j, i): q}`` (global indices) on the tile's edge ring and at its
    brackets; ``q`` every configuration of the tile with ``keep_configurations``.
    """

    j0: int
    j1: int
    i0: int
    i1: int
    assembled: np.ndarray
    rejected: np.ndarray
    im_indicator: np.ndarray
    dkp_input: np.ndarray
    dkp_output: np.ndarray
    types: np.ndarray
    branch_changes: tuple
    configurations: dict
    q: np.ndarray | None = None
    lim_indicator: np.ndarray | None = None


def run_tile(spec: MapSpec, xs: np.ndarray, ys: np.ndarray, j0: int, i0: int, seeds: list,
             keep_configurations: bool = False, previous: TileResult | None = None) -> TileResult:
    """Continue a mode over one tile (``xs``, ``ys``: the tile's axis values, internal units) from its seeds.

    The first seed is continued over the whole tile with :func:`continue_mode`; a further
    seed only when the tile's grid point nearest it is not assembled yet, and only over the
    points still unassembled (the assembled ones are ``blocked``: not solved again).
    ``(j0, i0)`` is the tile's first grid index (for the global indices of the results).
    With ``previous`` (this tile's earlier result) the tile continues from that state:
    seeds whose grid point it already assembled are skipped.  One tile of :func:`run_tiles`
    (a Dask task).
    """
    return run_tiles(spec, xs, ys, [(0, len(ys), 0, len(xs), seeds, previous)], keep_configurations,
                     offset=(j0, i0))[0]


def run_tiles(spec: MapSpec, xs: np.ndarray, ys: np.ndarray, tiles: list, keep_configurations: bool = False,
              offset: tuple[int, int] = (0, 0), progress=None) -> list[TileResult]:
    """Several tiles of one mode at once: ``tiles`` ``[(j0, j1, i0, i1, seeds, previous), …]`` (indices of ``xs``, ``ys``).

    Round ``k`` continues the ``k``-th seed of every tile that still needs it in one
    :func:`symkin.workspace.grid.continue_modes` call (the tiles' waves batched together;
    each tile's result is the one :func:`run_tile` gives it alone, see there).  ``offset`` is
    added to the indices of the results (global grid indices); ``progress(k)`` is told the
    points tried per wave.
    """
    system = system_of(spec)
    tol = spec.tolerances
    scale = system.axis_scale
    oj, oi = offset
    state = []
    for j0, j1, i0, i1, seeds, previous in tiles:
        shape = (j1 - j0, i1 - i0)
        out = {"assembled": np.zeros(shape, bool), "rejected": np.zeros(shape, bool),
               "im_indicator": np.full(shape, np.nan), "dkp_input": np.full(shape, np.nan),
               "dkp_output": np.full(shape, np.nan), "types": np.zeros(shape, np.int8)}
        if LimIndicator(system.evaluators):
            out["lim_indicator"] = np.full(shape, np.nan)
        q_all = np.full(shape + (system.nf,), np.nan) if keep_configurations else None
        branches: list = []
        kept: dict = {}
        if previous is not None:
            for name in out:
                out[name] = getattr(previous, name).copy()
            branches, kept = list(previous.branch_changes), dict(previous.configurations)
            if previous.q is not None and q_all is not None:
                q_all = previous.q.copy()
        state.append((out, q_all, branches, kept))
    ring = np.zeros((len(ys), len(xs)), bool)  # configurations kept on every tile's edge ring
    for j0, j1, i0, i1, _, _ in tiles:
        ring[[j0, j1 - 1], i0:i1] = ring[j0:j1, [i0, i1 - 1]] = True
    for k in range(max((len(t[4]) for t in tiles), default=0)):
        todo, regions = [], []
        blocked = np.zeros(ring.shape, bool)
        for t, (j0, j1, i0, i1, seeds, _) in enumerate(tiles):
            if k >= len(seeds):
                continue
            out = state[t][0]
            a = system.axis_values(np.asarray(seeds[k], float)[None])[0]
            i_near = int(np.argmin(np.abs(xs[i0:i1] - a[0]) / scale[0]))
            j_near = int(np.argmin(np.abs(ys[j0:j1] - a[1]) / scale[1]))
            if out["assembled"][j_near, i_near]:
                continue
            todo.append(t)
            regions.append((j0, j1, i0, i1, seeds[k]))
            blocked[j0:j1, i0:i1] = out["assembled"]
        if not todo:
            continue
        grids = continue_modes(system, xs, ys, regions, tol, keep_configurations=keep_configurations,
                               blocked=blocked, keep=ring, progress=progress)
        for t, g in zip(todo, grids):
            j0, i0 = tiles[t][0], tiles[t][2]
            out, q_all, branches, kept = state[t]
            new = g.assembled & ~out["assembled"]
            for name in ("im_indicator", "dkp_input", "dkp_output", "types", "lim_indicator"):
                if name in out:
                    out[name][new] = getattr(g, name)[new]
            if q_all is not None:
                q_all[new] = g.q[new]
            out["rejected"] |= g.rejected & ~out["assembled"] & ~new
            out["assembled"] |= new
            out["rejected"] &= ~out["assembled"]
            branches += [((a_[0] + j0 + oj, a_[1] + i0 + oi), (b_[0] + j0 + oj, b_[1] + i0 + oi))
                         for a_, b_ in g.branch_changes]
            for (j, i), q in g.configurations.items():
                if new[j, i]:
                    kept[(j + j0 + oj, i + i0 + oi)] = q
    return [TileResult(j0 + oj, j1 + oj, i0 + oi, i1 + oi, **out, branch_changes=tuple(branches),
                       configurations=kept, q=q_all)
            for (j0, j1, i0, i1, _, _), (out, q_all, branches, kept) in zip(tiles, state)]


def coarse_seeds(system: MapSystem, xs: np.ndarray, ys: np.ndarray, seed_q: np.ndarray, bx: list, by: list,
                 tolerances=None) -> dict:
    """The seeds of every tile from a coarse sweep: ``{(tj, ti): [q, …]}`` (see the module docstring).

    The coarse sweep continues the mode over the tiles' corner points (``bx``, ``by`` from
    :func:`tile_bounds`, the last grid point included); tile ``(tj, ti)`` gets the assembled
    corners of its closure in the order (own corner, right, top, top-right), and the mode's
    seed goes first to the tile nearest it.
    """
    ci = sorted(set(bx[:-1]) | {len(xs) - 1})
    cj = sorted(set(by[:-1]) | {len(ys) - 1})
    coarse = continue_mode(system, xs[ci], ys[cj], seed_q, tolerances, keep_configurations=True)
    where_i = {g: k for k, g in enumerate(ci)}
    where_j = {g: k for k, g in enumerate(cj)}
    seeds: dict = {}
    a = system.axis_values(np.asarray(seed_q, float)[None])[0]
    ti0 = int(np.clip(np.searchsorted(bx, int(np.argmin(np.abs(xs - a[0]))), "right") - 1, 0, len(bx) - 2))
    tj0 = int(np.clip(np.searchsorted(by, int(np.argmin(np.abs(ys - a[1]))), "right") - 1, 0, len(by) - 2))
    for tj in range(len(by) - 1):
        for ti in range(len(bx) - 1):
            lst = [np.asarray(seed_q, float)] if (tj, ti) == (tj0, ti0) else []
            for gj, gi in ((by[tj], bx[ti]), (by[tj], bx[ti + 1]), (by[tj + 1], bx[ti]), (by[tj + 1], bx[ti + 1])):
                gi, gj = min(gi, len(xs) - 1), min(gj, len(ys) - 1)
                q = coarse.config(where_j[gj], where_i[gi])
                if q is not None:
                    lst.append(q)
            seeds[(tj, ti)] = lst
    return seeds


def _merge(results, shape: tuple, nf: int, keep_configurations: bool, seed_q: np.ndarray) -> ModeGrid:
    """Assemble the tiles of one mode into its :class:`ModeGrid` (consumes the results one by one)."""
    grid = {"assembled": np.zeros(shape, bool), "rejected": np.zeros(shape, bool),
            "im_indicator": np.full(shape, np.nan), "dkp_input": np.full(shape, np.nan),
            "dkp_output": np.full(shape, np.nan), "types": np.zeros(shape, np.int8)}
    q = np.full(shape + (nf,), np.nan) if keep_configurations else None
    lim = None
    branches: list = []
    kept: dict = {}
    for r in results:
        sl = (slice(r.j0, r.j1), slice(r.i0, r.i1))
        for name in grid:
            grid[name][sl] = getattr(r, name)
        if r.lim_indicator is not None:
            lim = np.full(shape, np.nan) if lim is None else lim
            lim[sl] = r.lim_indicator
        branches += list(r.branch_changes)
        kept.update(r.configurations)
        if q is not None:
            q[sl] = r.q
    note = "" if grid["assembled"].any() else "the mode does not reach the box from its seed"
    return ModeGrid(np.asarray(seed_q, float), grid["assembled"], grid["rejected"], grid["im_indicator"],
                    grid["dkp_input"], grid["dkp_output"], grid["types"], tuple(sorted(branches)), kept, q, note,
                    lim_indicator=lim)


def tiled_mode(spec: MapSpec, xs: np.ndarray, ys: np.ndarray, seed_q: np.ndarray, tile: int = TILE,
               client=None, keep_configurations: bool = False, progress=None) -> ModeGrid:
    """One mode continued over the grid ``xs × ys`` (internal units) tile by tile.

    Serial when ``client`` is None, else each :func:`run_tile` call is a task on the Dask
    ``client``'s workers; the two give identical grid arrays (module docstring).

    Examples
    --------
    >>> import numpy as np
    >>> from symkin.model.catalogue import get
    >>> mech = get("five_bar")
    >>> spec = MapSpec.of(mech, "velocity:P.x", "velocity:P.y")
    >>> xs, ys = np.linspace(-3.5, 3.5, 21), np.linspace(0.2, 4.4, 21)
    >>> g = tiled_mode(spec, xs, ys, system_of(spec).q0, tile=8)
    >>> round(g.fraction, 3)  # the same fraction as one continuation over the whole grid
    0.156
    """
    system = system_of(spec)
    bx, by = tile_bounds(len(xs), tile), tile_bounds(len(ys), tile)
    seeds = coarse_seeds(system, xs, ys, seed_q, bx, by, spec.tolerances)
    tiles = [(tj, ti) for tj in range(len(by) - 1) for ti in range(len(bx) - 1)]
    of_start = {(by[tj], bx[ti]): (tj, ti) for tj, ti in tiles}
    results: dict = {}
    used: dict = {k: set() for k in tiles}
    pending = [k for k in tiles if seeds[k]]
    first = True
    total, told = len(xs) * len(ys), [0]

    def tell(k: int):  # progress in grid points, never past the grid's size
        k = min(int(k), total - told[0])
        if progress and k > 0:
            told[0] += k
            progress(k)

    while pending:
        if client is None:  # here: every pending tile in one batched continuation (the same per-tile results)
            done = run_tiles(spec, xs, ys, [(by[tj], by[tj + 1], bx[ti], bx[ti + 1], seeds[(tj, ti)],
                                             results.get((tj, ti))) for tj, ti in pending], keep_configurations,
                             progress=tell if first else None)
        else:
            calls = [(spec, xs[bx[ti]:bx[ti + 1]], ys[by[tj]:by[tj + 1]], by[tj], bx[ti], seeds[(tj, ti)],
                      keep_configurations, results.get((tj, ti))) for tj, ti in pending]
            done = _map_tasks(client, run_tile, calls)
        for r in done:
            results[of_start[(r.j0, r.i0)]] = r
            if first and client is not None:
                tell(r.assembled.size)
        first = False
        pending = _halo_seeds(results, seeds, used, bx, by)
    tell(total)  # the rest: points no wave reached
    return _merge((results[k] for k in tiles if k in results), (len(ys), len(xs)), system.nf,
                  keep_configurations, seed_q)


def _halo_seeds(results: dict, seeds: dict, used: dict, bx: list, by: list) -> list:
    """Add to ``seeds`` the assembled configurations across a tile's edge next to its unassembled edge points.

    A region of the mode that no coarse point of a tile reaches inside that tile is entered
    from its neighbour tile (whose edge-ring configurations are kept); returns the tiles to
    run again, in tile order.  Each neighbour point seeds a tile once, so the passes end.
    """
    shape = (by[-1], bx[-1])
    assembled = np.zeros(shape, bool)
    kept: dict = {}
    for r in results.values():
        assembled[r.j0:r.j1, r.i0:r.i1] = r.assembled
        kept.update(r.configurations)
    again = []
    for key in sorted(used):
        j0, j1, i0, i1 = by[key[0]], by[key[0] + 1], bx[key[1]], bx[key[1] + 1]
        new = []
        ring = set()
        for j in range(j0, j1):
            ring.update({(j, i0), (j, i1 - 1)})
        for i in range(i0, i1):
            ring.update({(j0, i), (j1 - 1, i)})
        for (j, i) in sorted(ring):
            if assembled[j, i]:
                continue
            for dj, di in ((0, 1), (0, -1), (1, 0), (-1, 0)):
                pj, pi = j + dj, i + di
                inside = j0 <= pj < j1 and i0 <= pi < i1
                if inside or not (0 <= pj < shape[0] and 0 <= pi < shape[1]) or not assembled[pj, pi]:
                    continue
                if (pj, pi) in used[key] or (pj, pi) not in kept:
                    continue
                used[key].add((pj, pi))
                new.append(kept[(pj, pi)])
        if new:
            seeds[key] = list(seeds[key]) + new
            again.append(key)
    return again


# ---------------------------------------------------------------------- schedulers
def _map_tasks(client, fn, calls):
    """``fn(*c)`` for every call: here, one after the other, or on ``client``'s workers as they complete."""
    if client is None:
        for c in calls:
            yield fn(*c)
        return
    from distributed import as_completed

    futures = [client.submit(fn, *c, pure=False) for c in calls]
    for fut in as_completed(futures):
        r = fut.result()
        fut.release()
        yield r


def run_tasks(client, fn, calls) -> list:
    """``[fn(*c) for c in calls]`` in order, serial or on ``client`` (results gathered)."""
    if client is None:
        return [fn(*c) for c in calls]
    futures = [client.submit(fn, *c, pure=False) for c in calls]
    return client.gather(futures)


def _distributed():
    try:
        import distributed
    except ImportError:
        distributed = None
    if distributed is None:
        raise SymkinError(f"--workers / --scheduler / client= need {DASK_EXTRA}")
    return distributed


@contextlib.contextmanager
def dask_client(workers: int | None = None, scheduler: str | None = None, client=None):
    """The Dask client to run on: ``client`` as given, one connected to ``scheduler``, or a local cluster.

    ``workers=N`` starts ``LocalCluster(n_workers=N, threads_per_worker=1, processes=True,
    dashboard_address=None)`` and closes it on exit; nothing (None) when none of the three is
    given.  Without the dask extra a :class:`SymkinError` names it.
    """
    if workers is not None and int(workers) < 1:
        raise SymkinError(f"--workers {workers}: the number of workers must be at least 1")
    if client is not None:
        yield client
        return
    if not workers and scheduler is None:
        yield None
        return
    distributed = _distributed()
    if scheduler is not None:
        try:
            c = distributed.Client(scheduler, timeout=10)
        except (OSError, TimeoutError, ValueError) as exc:
            raise SymkinError(f"--scheduler {scheduler}: cannot connect to a Dask scheduler ({exc})") from None
        try:
            yield c
        finally:
            c.close()
        return
    cluster = distributed.LocalCluster(n_workers=int(workers), threads_per_worker=1, processes=True,
                                       dashboard_address=None)
    try:
        c = distributed.Client(cluster)
        try:
            yield c
        finally:
            c.close()
    finally:
        cluster.close()
