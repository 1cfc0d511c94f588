"""Workspace and joint-space singularity maps: :func:`workspace_map` and the frozen :class:`WorkspaceMap`.

``symkin.workspace_map(mech, x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4", n=201)``
builds the map's position problem (:mod:`symkin.workspace.system`), the modes
(:mod:`symkin.workspace.modes`), continues each mode over the grid and evaluates the
indicators of the one analysis core on it (:mod:`symkin.workspace.grid`) and, with
``refine=True``, refines to exact curves with :func:`symkin.workspace.loci.refine`
``(system, GridData, mode_id, tolerances) -> (curves, points, stats)`` when
that module is installed (otherwise the map says so in :attr:`WorkspaceMap.notes`).

:meth:`WorkspaceMap.to_dict` is the ``symkin map --json`` object::

    {"model", "unit", "hold": [{label, value}], "tolerance",
     "axes":   [{label, lo, hi, n}, {…}],
     "modes":  [{id, seed, assembled, rejected, branch_changes, note}],
     "curves": [{kind, mode, closed, points: [[x, y], …]}],
     "points": [{kind, mode, at: [x, y], types}],   # kind: "IM", "LIM", "meeting", "cusp", or the one type
                                                    # (a "LIM" point also has "locked_links": [link, …])
     "counts": {"<mode id>": {"DKP-input": k, "DKP-output": k, "IM": k}},   # curves + points per kind
     "notes":  [...]}

Isolated points (``points``) are classified by the core (``types``); their ``kind`` is ``"IM"``
at an IM configuration, ``"meeting"`` where a curve ends on another locus (two or more types),
``"cusp"`` where a traced curve's image in the axes turns back (its axis velocity vanishes while
it moves in configuration space; :func:`symkin.workspace.loci.locate_cusp`; the curve goes on
through it), ``"LIM"`` at an isolated configuration where a link turning about a fixed pivot cannot
move for any motion (:mod:`symkin.workspace.lim_points`; the core's ``locked_links`` with it), else
the one type of a curve's end.  ``counts`` has a ``"LIM"`` entry for a mode with such points.

Axis values are in the user's units (angles in ``unit``).  :meth:`WorkspaceMap.save` writes
an ``.npz`` (grid arrays per mode, curves, the header as JSON text; no pickles) that
:func:`load_map` reads back.

For the plots (``symkin map --plot FILE.png``) the CLI calls
``symkin.plots.maps.save_map_figure(workspace_map, path) -> path`` when that module exists; it
reads only this object (``axes``, ``modes[k]`` grid arrays ``(ny, nx)`` indexed ``[j, i]`` ↔
``(xs[i], ys[j])``, ``curves``, ``points``).
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from symkin.kinds import LOCUS_KINDS
from symkin.errors import SymkinError
from symkin.model.mechanism import Mechanism
from symkin.tolerances import Tolerances
from symkin.workspace.grid import GRID_ARRAYS, Axis, ModeArrays, ModeGrid, continue_mode, make_axes
from symkin.workspace.modes import model_modes
from symkin.workspace.system import map_system, window_note

__all__ = ["MapCurve", "MapPoint", "ModeMap", "WorkspaceMap", "workspace_map", "load_map", "KINDS"]

#: kinds of curves and points, in the order of ``counts``
KINDS = LOCUS_KINDS


@dataclass(frozen=True, eq=False)
class MapCurve:
    """A traced singular curve: ``kind`` (``DKP-input``, ``DKP-output``, ``IM``), mode id, closed, points (N, 2)."""

    kind: str
    mode: int
    closed: bool
    points: np.ndarray = field(repr=False)

    def to_dict(self) -> dict:
        return {"kind": self.kind, "mode": int(self.mode), "closed": bool(self.closed),
                "points": [[float(a), float(b)] for a, b in np.asarray(self.points)]}


@dataclass(frozen=True)
class MapPoint:
    """An isolated singular point: ``kind``, mode id, ``at`` (x, y), the core's ``types``."""

    kind: str
    mode: int
    at: tuple[float, float]
    types: tuple[str, ...]
    #: the core's locked links at a point of kind ``"LIM"`` (empty otherwise; then not in the JSON)
    locked_links: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        out = {"kind": self.kind, "mode": int(self.mode), "at": [float(v) for v in self.at],
               "types": list(self.types)}
        if self.locked_links:
            out["locked_links"] = list(self.locked_links)
        return out


@dataclass(frozen=True, eq=False)
class ModeMap(ModeArrays):
    """One mode of a map: the grid arrays of :class:`~symkin.workspace.grid.ModeArrays` (seed
    configuration, ``assembled`` / ``rejected``, indicators, ``types``), its ``id`` and ``seed``
    label (keywords), ``branch_changes`` (pairs of grid indices), ``q`` (configurations, when kept).
    """

    id: int = field(kw_only=True)
    seed: str = field(kw_only=True)
    branch_changes: tuple = ()
    q: np.ndarray | None = field(default=None, repr=False)
    note: str = ""

    @classmethod
    def of(cls, grid: ModeGrid, id: int, seed: str, keep_configurations: bool = False) -> "ModeMap":
        """The map's mode ``id`` from its continued grid."""
        return cls(**grid.arrays(), id=id, seed=seed, branch_changes=grid.branch_changes,
                   q=grid.q if keep_configurations else None, note=grid.note)

    def to_dict(self) -> dict:
        return {"id": int(self.id), "seed": self.seed, "assembled": self.fraction,
                "rejected": int(np.count_nonzero(self.rejected)),
                "branch_changes": [[list(map(int, a)), list(map(int, b))] for a, b in self.branch_changes],
                "note": self.note}


@dataclass(frozen=True, eq=False)
class WorkspaceMap:
    """A singularity map (see the module docstring): axes, modes with grid arrays, curves, points.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> m = workspace_map(get("five_bar"), x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4", n=21,
    ...                   refine=False)
    >>> [a.label for a in m.axes], len(m.modes), round(m.modes[0].fraction, 3)
    (['velocity:P.x', 'velocity:P.y'], 1, 0.156)
    >>> sorted(m.to_dict())
    ['axes', 'counts', 'curves', 'hold', 'model', 'modes', 'notes', 'points', 'tolerance', 'unit']
    """

    model: str
    axes: tuple[Axis, Axis]
    unit: str
    hold: tuple[tuple[str, float], ...]
    modes: tuple[ModeMap, ...]
    curves: tuple[MapCurve, ...] = ()
    points: tuple[MapPoint, ...] = ()
    tolerance: float = Tolerances().rank
    notes: tuple[str, ...] = ()

    @property
    def xs(self) -> np.ndarray:
        return self.axes[0].values

    @property
    def ys(self) -> np.ndarray:
        return self.axes[1].values

    @property
    def assembled_anywhere(self) -> bool:
        return any(bool(m.assembled.any()) for m in self.modes)

    def counts(self) -> dict:
        """Curves and points per mode and kind: ``{"<mode id>": {kind: k}}``."""
        out = {str(m.id): {k: 0 for k in KINDS} for m in self.modes}
        for c in self.curves + self.points:
            out.setdefault(str(c.mode), {k: 0 for k in KINDS})
            out[str(c.mode)][c.kind] = out[str(c.mode)].get(c.kind, 0) + 1
        return out

    def to_dict(self) -> dict:
        """The ``--json`` object (module docstring)."""
        return {"model": self.model, "unit": self.unit,
                "hold": [{"label": lab, "value": float(v)} for lab, v in self.hold],
                "tolerance": float(self.tolerance),
                "axes": [a.to_dict() for a in self.axes],
                "modes": [m.to_dict() for m in self.modes],
                "curves": [c.to_dict() for c in self.curves],
                "points": [p.to_dict() for p in self.points],
                "counts": self.counts(),
                "notes": list(self.notes)}

    def save(self, path) -> Path:
        """Write the map as ``.npz`` (no pickles): the header JSON, grid arrays per mode, curve points."""
        path = Path(path)
        head = self.to_dict()
        for c in head["curves"]:
            c["points"] = []
        arrays = {"header": np.array(json.dumps(head))}
        for m in self.modes:
            for name in GRID_ARRAYS:
                arrays[f"mode{m.id}_{name}"] = getattr(m, name)
            arrays[f"mode{m.id}_seed_q"] = m.seed_q
            if m.q is not None:
                arrays[f"mode{m.id}_q"] = m.q
        for k, c in enumerate(self.curves):
            arrays[f"curve{k}_points"] = np.asarray(c.points, float).reshape(-1, 2)
        with open(path, "wb") as fh:
            np.savez_compressed(fh, **arrays)
        return path

    def to_xarray(self):
        """The grid arrays as an ``xarray.Dataset`` (dims ``mode``, ``y``, ``x``); needs xarray."""
        try:
            import xarray as xr
        except ImportError:
            raise SymkinError("WorkspaceMap.to_xarray needs xarray (pip install xarray)") from None
        data = {name: (("mode", "y", "x"), np.stack([getattr(m, name) for m in self.modes]))
                for name in GRID_ARRAYS}
        return xr.Dataset(data, coords={"mode": [m.id for m in self.modes], "x": self.xs, "y": self.ys,
                                        "seed": ("mode", [m.seed for m in self.modes])},
                          attrs={"model": self.model, "x_label": self.axes[0].label,
                                 "y_label": self.axes[1].label, "unit": self.unit})


def load_map(path) -> WorkspaceMap:
    """Read a map written by :meth:`WorkspaceMap.save` (``symkin.load_map``).

    Raises
    ------
    SymkinError
        Naming the file, when it is missing, truncated, or not a map written by symkin.
    """
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as data:
            files = dict(data.items())
    except Exception as exc:  # noqa: BLE001 - OSError, ValueError, BadZipFile, zlib.error, EOFError ...
        raise SymkinError(f"{path}: not a symkin map file ({type(exc).__name__}: {exc})") from None
    if "header" not in files:
        raise SymkinError(f"{path}: not a symkin map file (no header)")
    try:
        head = json.loads(str(files["header"]))
        axes = tuple(Axis(a["label"], a["lo"], a["hi"], a["n"]) for a in head["axes"])
        modes = []
        for m in head["modes"]:
            k = m["id"]
            modes.append(ModeMap(files[f"mode{k}_seed_q"], *(files[f"mode{k}_{name}"] for name in GRID_ARRAYS),
                                 id=k, seed=m["seed"],
                                 branch_changes=tuple((tuple(a), tuple(b)) for a, b in m["branch_changes"]),
                                 q=files.get(f"mode{k}_q"), note=m.get("note", "")))
        curves = tuple(MapCurve(c["kind"], c["mode"], c["closed"], files[f"curve{k}_points"])
                       for k, c in enumerate(head["curves"]))
        points = tuple(MapPoint(p["kind"], p["mode"], tuple(p["at"]), tuple(p["types"]),
                                tuple(p.get("locked_links", ()))) for p in head["points"])
        return WorkspaceMap(head["model"], axes, head["unit"],
                            tuple((h["label"], h["value"]) for h in head["hold"]),
                            tuple(modes), curves, points, head["tolerance"], tuple(head["notes"]))
    except (KeyError, TypeError, ValueError, AttributeError, IndexError) as exc:
        what = f"missing entry {exc}" if isinstance(exc, KeyError) else f"{type(exc).__name__}: {exc}"
        raise SymkinError(f"{path}: not a symkin map file, or written by another version ({what})") from None


# ---------------------------------------------------------------------- refinement
def _loci():
    """The refinement module, or None while it is not installed."""
    try:
        from symkin.workspace import loci
    except ImportError:
        return None
    return loci if hasattr(loci, "refine") else None


def _refine(system, grid: ModeGrid, mode_id: int, xs, ys, tol: Tolerances):
    """Curves and points of one mode from :func:`symkin.workspace.loci.refine`, as map records."""
    loci = _loci()
    data = loci.GridData(xs=xs, ys=ys, assembled=grid.assembled, dkp_input=grid.dkp_input,
                         dkp_output=grid.dkp_output, im_indicator=grid.im_indicator, q=grid.q,
                         configuration=grid.config, seed=grid.seed_q, lim_indicator=grid.lim_indicator)
    out = loci.refine(system, data, mode_id, tol)
    curves, points = out[0], out[1]
    return ([MapCurve(c.kind, mode_id, bool(c.closed), np.asarray(c.points, float)) for c in curves],
            [MapPoint(p.kind, mode_id, tuple(float(v) for v in p.at), tuple(p.types), tuple(p.locked_links))
             for p in points])


def _same_mode(a: ModeGrid, b: ModeGrid) -> bool:
    """Two seeds that continue to the same configurations everywhere are one mode."""
    if not np.array_equal(a.assembled, b.assembled) or not a.assembled.any():
        return False
    sel = a.assembled
    return all(np.allclose(getattr(a, k)[sel], getattr(b, k)[sel], rtol=1e-8, atol=1e-10, equal_nan=True)
               for k in ("im_indicator", "dkp_input", "dkp_output"))


# ---------------------------------------------------------------------- the map
def workspace_map(mech: Mechanism, x: str = "velocity:P.x=-3.5:3.5", y: str = "velocity:P.y=0.2:4.4",
                  n=201, hold=(), seeds=(), modes: str = "model", refine: bool = True, client=None,
                  unit: str = "deg", tol: Tolerances | float | None = None, keep_configurations: bool = False,
                  workers: int | None = None, progress=None, tile: int | None = None,
                  _tiled=None) -> WorkspaceMap:
    """A workspace or joint-space singularity map of ``mech`` (``symkin.workspace_map``; ``symkin map``).

    Parameters
    ----------
    mech : Mechanism
    x, y : str
        ``LABEL=LO:HI`` (angles in ``unit``), labels as ``symkin path --input`` takes them.
    n : int or (int, int)
        Grid points per axis (>= 2).
    hold : sequence
        The ``F − 2`` held coordinates: ``"LABEL"``, ``"LABEL=VALUE"`` or ``(label, value)``.
    seeds : sequence of model paths or Mechanism
        Further working modes (same mechanism, another configuration).
    modes : ``"model"`` or ``"all"``
    refine : bool
        Refine to exact curves (:mod:`symkin.workspace.loci`, when installed).
    client, workers :
        Dask (:mod:`symkin.workspace.parallel`, the ``dask`` extra): an existing
        ``distributed.Client``, or ``workers=N`` to start a local cluster of N processes for
        this call.  The grid is continued tile by tile on the workers and each mode is
        refined on one.
    tile : int, optional
        Tile side in grid points, default :data:`symkin.workspace.parallel.TILE`.  **One
        process and Dask give the same result**: both continue every mode over the same
        tiles, seeded by the same coarse sweep (:func:`symkin.workspace.parallel.tiled_mode`),
        so the grid arrays are identical and the curves equal (to 1e-9) whatever the
        scheduler.  A map of at most ``tile`` points per axis is one tile: one continuation
        over the whole grid from the seed.  ``tile=0`` (one process only) continues over the
        whole grid whatever its size (the route of the continuation differs from the tiles',
        so points next to a fold may differ from a Dask run).
    unit : ``"deg"`` or ``"rad"``
    tol : Tolerances or float
        The core's rank tolerance.
    keep_configurations : bool
        Keep every grid configuration (``ModeMap.q``); off by default to bound memory.
    progress : callable, optional
        ``progress(k)`` told the number of grid points processed (e.g. a tqdm ``update``).
    """
    tolerances = Tolerances.of(tol)
    if tile is not None and (int(tile) != tile or int(tile) < 0 or int(tile) == 1):
        raise SymkinError(f"tile={tile!r}: the tile side must be an integer >= 2 (0: no tiles, one process)")
    untiled = tile is not None and int(tile) == 0
    if untiled and (client is not None or workers):
        raise SymkinError("tile=0 (one continuation over the whole grid) runs in one process only, "
                          "not with client= or workers=")
    if not untiled and _tiled is None:  # ---- tiled, here or on Dask (symkin.workspace.parallel)
        from symkin.workspace import parallel

        with parallel.dask_client(workers=workers, client=client) as dask:
            return workspace_map(mech, x=x, y=y, n=n, hold=hold, seeds=seeds, modes=modes, refine=refine,
                                 unit=unit, tol=tolerances, keep_configurations=keep_configurations,
                                 progress=progress, _tiled=(parallel, dask, int(tile or parallel.TILE)))
    (lx, x_lo, x_hi), (ly, y_lo, y_hi), (nx, ny) = make_axes(x, y, n)
    if _tiled is not None:  # the process's one copy of the problem, as every worker builds it from plain data
        spec = _tiled[0].MapSpec.of(mech, lx, ly, hold, unit, tolerances, windows=((x_lo, x_hi), (y_lo, y_hi)))
        system = _tiled[0].system_of(spec)
    else:
        system = map_system(mech, lx, ly, hold=hold, unit=unit, tolerances=tolerances,
                            windows=((x_lo, x_hi), (y_lo, y_hi)))
    axes = (Axis(system.axes[0].label, x_lo, x_hi, nx), Axis(system.axes[1].label, y_lo, y_hi, ny))
    xs_user, ys_user = axes[0].values, axes[1].values
    xs = system.to_internal(np.column_stack([xs_user, np.zeros(nx)]))[:, 0]
    ys = system.to_internal(np.column_stack([np.zeros(ny), ys_user]))[:, 1]
    seeds_q, merged = model_modes(system, seeds, modes, tolerances)
    notes: list[str] = list(merged) + [w for w in (window_note(c, a.lo, a.hi, unit) for c, a in zip(system.axes, axes))
                                       if w is not None]
    mode_maps: list[ModeMap] = []
    grids: list[ModeGrid] = []
    if _tiled is not None:  # ---- tiled / Dask path: every worker builds the problem from plain data
        parallel, dask, tile_side = _tiled
    for label, q in seeds_q:
        if _tiled is not None:
            g = parallel.tiled_mode(spec, xs, ys, q, tile_side, dask, keep_configurations, progress)
        else:
            g = continue_mode(system, xs, ys, q, tolerances, keep_configurations=keep_configurations,
                              progress=progress)
        dup = next((k for k, h in enumerate(grids) if _same_mode(h, g)), None)
        if dup is not None:
            notes.append(f"seed {label} continues to the same configurations as mode {mode_maps[dup].id} "
                         f"({mode_maps[dup].seed}): merged")
            continue
        grids.append(g)
        mode_maps.append(ModeMap.of(g, len(mode_maps), label, keep_configurations))
    curves: list[MapCurve] = []
    points: list[MapPoint] = []
    if refine:
        if _loci() is None:
            notes.append("refinement to exact curves is not available yet (symkin.workspace.loci): grid only")
        else:
            todo = [(m, g) for m, g in zip(mode_maps, grids) if g.assembled.any()]
            if _tiled is not None:  # ---- one refinement task per mode (on a worker with Dask)
                found = parallel.run_tasks(dask, parallel.on_system,
                                           [(spec, _refine, g, m.id, xs_user, ys_user, tolerances) for m, g in todo])
            else:
                found = [_refine(system, g, m.id, xs_user, ys_user, tolerances) for m, g in todo]
            for c, p in found:
                curves += c
                points += p
    if not any(g.assembled.any() for g in grids):
        notes.append("no mode assembles anywhere in the box")
    hold_user = tuple((c.label, float(v)) for c, v in zip(system.holds, system.to_user(system.hold_values,
                                                                                          "holds")))
    return WorkspaceMap(mech.name, axes, unit, hold_user, tuple(mode_maps), tuple(curves), tuple(points),
                        tolerances.rank, tuple(notes))
