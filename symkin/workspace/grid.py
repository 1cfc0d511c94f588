"""The map's grid and the continuation of one working mode over it (paper §VI).

A mode is continued from its seed configuration over the grid in *waves* (breadth first:
wave ``d`` holds the grid points ``d`` neighbour steps from the seed's grid point), each
wave solved in one batched Newton call of :meth:`symkin.workspace.system.MapSystem.solve`
from a neighbouring solved point of the previous wave.  Every wave's indicators come from
the one analysis core, ``system.evaluators.batch(q)`` (IM indicator ``λ_{F+1}``, signed
DKP-input / DKP-output values, decisions).

Guards (as ``trace`` guards its steps):

* **predictor distance** — the Newton start is the tangent predictor
  ``q_N + (∂q/∂a)(a − a_N)`` from the neighbour ``N`` (``∂q/∂a`` from ``dS/dq`` at ``N``); a
  solution farther from it than ``jump · ‖predictor step‖`` (:data:`JUMP`; distances in
  units of the length scale) is not accepted.  It is re-solved from the neighbour in 4
  sub-steps; when every attempt fails the point is marked ``rejected`` (a converged but
  untrusted solution) or not assembled (Newton does not converge: outside the mode's
  workspace).  Nothing is guessed.
* **sign pattern** — a point whose signs of the DKP test functions differ from its
  neighbour's is re-solved in 4 sub-steps from it; a different configuration means the
  step jumped to another mode (marked ``rejected``), the same means a crossing of a
  singular locus between the two.
* **branch change** — a point that two solved neighbours predict differently is
  re-solved from the second; two different configurations at one grid point reached by
  two routes are reported in :attr:`ModeGrid.branch_changes`.

Memory stays bounded: only two waves of configurations are held while continuing; the
configurations at *bracket* points (a neighbour with another DKP sign pattern, or not
assembled, or a near-zero minimum of a DKP test function: :func:`symkin.workspace.quadtree.dips`) are kept for refinement (:mod:`symkin.workspace.loci`), all of them only with
``keep_configurations=True``.

Arrays of a mode are ``(ny, nx)``, indexed ``[j, i]`` ↔ ``(xs[i], ys[j])``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from symkin.kinds import Kind
from symkin.errors import SymkinError
from symkin.tolerances import Tolerances
from symkin.workspace.lim_points import LimIndicator
from symkin.workspace.quadtree import dips
from symkin.workspace.system import NEWTON_TOL, MapSystem

__all__ = ["Axis", "parse_axis", "make_axes", "GRID_ARRAYS", "ModeArrays", "ModeGrid", "continue_mode", "continue_modes", "JUMP", "TYPE_BITS", "type_names"]

#: a solution may lie at most this fraction of the predictor's step from the tangent predictor.
#: Near a quadratic fold (the mode's workspace boundary, where q ~ sqrt(distance)) the tangent
#: predictor's error reaches its own step as the point nears the fold, so 1.0 accepts every
#: point of the mode and refuses a jump to a configuration farther away than one step.
JUMP = 1.0
#: bits of :attr:`ModeGrid.types`
TYPE_BITS = {Kind.IM: 1, Kind.DKP_INPUT: 2, Kind.DKP_OUTPUT: 4}
#: sub-step counts tried after a rejected or failed full step
_SUBSTEPS = (4,)


def type_names(bits: int) -> tuple[str, ...]:
    """The types in a :attr:`ModeGrid.types` entry (``5`` → ``("IM", "DKP-output")``)."""
    return tuple(name for name, b in TYPE_BITS.items() if int(bits) & b)


# ---------------------------------------------------------------------- axes
@dataclass(frozen=True)
class Axis:
    """One axis of a map: label, range ``[lo, hi]`` in user units (angles in the map's unit), ``n`` points."""

    label: str
    lo: float
    hi: float
    n: int

    @property
    def values(self) -> np.ndarray:
        return np.linspace(self.lo, self.hi, self.n)

    def to_dict(self) -> dict:
        return {"label": self.label, "lo": float(self.lo), "hi": float(self.hi), "n": int(self.n)}


def parse_axis(text: str, option: str = "--x") -> tuple[str, float, float]:
    """``"LABEL=LO:HI"`` → ``(label, lo, hi)``; a :class:`SymkinError` naming the option otherwise.

    >>> parse_axis("velocity:P.x=-3.5:3.5")
    ('velocity:P.x', -3.5, 3.5)
    """
    label, eq, rng = str(text).rpartition("=")
    parts = rng.split(":")
    if not eq or not label or len(parts) != 2:
        raise SymkinError(f"{option} {text!r}: expected LABEL=LO:HI, e.g. velocity:P.x=-3.5:3.5")
    try:
        lo, hi = float(parts[0]), float(parts[1])
    except ValueError:
        raise SymkinError(f"{option} {text!r}: LO and HI must be numbers") from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo >= hi:
        raise SymkinError(f"{option} {text!r}: LO must be less than HI")
    return label.strip(), lo, hi


def make_axes(x: str, y: str, n) -> tuple[tuple[str, float, float], tuple[str, float, float], tuple[int, int]]:
    """Parse both axes and the number of points per axis (``n`` or ``(nx, ny)``, each >= 2)."""
    ax, ay = parse_axis(x, "--x"), parse_axis(y, "--y")
    ns = (n, n) if np.ndim(n) == 0 else tuple(n)
    if len(ns) != 2 or any(int(k) != k or int(k) < 2 for k in ns):
        raise SymkinError(f"--n {n!r}: the number of grid points per axis must be an integer >= 2")
    return ax, ay, (int(ns[0]), int(ns[1]))


# ---------------------------------------------------------------------- result of one mode
#: the grid arrays of a mode (:class:`ModeArrays` attributes; ``.npz`` entries ``mode<id>_<name>``)
GRID_ARRAYS = ("assembled", "rejected", "im_indicator", "dkp_input", "dkp_output", "types")


@dataclass(frozen=True, eq=False)
class ModeArrays:
    """A working mode's seed and grid arrays ``(ny, nx)`` (NaN where not assembled): the one definition
    that :class:`ModeGrid` (the continuation's result) and :class:`symkin.workspace.maps.ModeMap`
    (a mode of a map) share.

    Attributes
    ----------
    seed_q : (nf,) the seed configuration; ``assembled`` bool; ``rejected`` bool (converged
    solutions not accepted by the jump checks); ``im_indicator``, ``dkp_input``,
    ``dkp_output`` (the core's values); ``types`` int8 bits (:data:`TYPE_BITS`).
    """

    seed_q: np.ndarray = field(repr=False)
    assembled: np.ndarray = field(repr=False)
    rejected: np.ndarray = field(repr=False)
    im_indicator: np.ndarray = field(repr=False)
    dkp_input: np.ndarray = field(repr=False)
    dkp_output: np.ndarray = field(repr=False)
    types: np.ndarray = field(repr=False)

    @property
    def fraction(self) -> float:
        """Assembled fraction of the grid points."""
        return float(np.count_nonzero(self.assembled)) / self.assembled.size

    def type_mask(self, kind: str) -> np.ndarray:
        """Grid points the core decides to be of type ``kind`` (``IM``, ``DKP-input``, ``DKP-output``)."""
        return (self.types & TYPE_BITS[kind]) != 0

    def arrays(self) -> dict:
        """``{name: array}`` of :data:`GRID_ARRAYS` and ``seed_q``."""
        return {"seed_q": self.seed_q, **{name: getattr(self, name) for name in GRID_ARRAYS}}


@dataclass(frozen=True, eq=False)
class ModeGrid(ModeArrays):
    """One working mode continued over the grid: :class:`ModeArrays` and what continuation found.

    Attributes
    ----------
    branch_changes : pairs of grid indices ``((j, i), (j2, i2))`` where the two routes give
        different configurations; ``configurations`` ``{(j, i): q}`` at bracket points; ``q``
        ``(ny, nx, nf)`` (NaN where not assembled) only with ``keep_configurations``.
    """

    branch_changes: tuple = ()
    configurations: dict = field(default_factory=dict, repr=False)
    q: np.ndarray | None = field(default=None, repr=False)
    note: str = ""
    #: the smallest relative LIM indicator over the pivoted links (:class:`symkin.workspace.lim_points.LimIndicator`),
    #: NaN where not assembled; None when the mechanism has no such link
    lim_indicator: np.ndarray | None = field(default=None, repr=False)

    def config(self, j: int, i: int) -> np.ndarray | None:
        """The configuration at grid point ``[j, i]`` when it was kept (None otherwise)."""
        if self.q is not None:
            return None if not self.assembled[j, i] else self.q[j, i].copy()
        q = self.configurations.get((int(j), int(i)))
        return None if q is None else q.copy()


# ---------------------------------------------------------------------- continuation
def _minima(values: np.ndarray, solved: np.ndarray, j: np.ndarray, i: np.ndarray, region: np.ndarray) -> np.ndarray:
    """Which points ``(j[k], i[k])`` have ``values`` at most those of both solved neighbours along x or along y
    (in their region): :func:`symkin.workspace.lim_points.line_minima` while the grid is continued."""
    ny, nx = values.shape
    low = np.zeros(len(j), bool)
    for (dj, di) in ((0, 1), (1, 0)):
        line = solved[j, i].copy()
        for s in (1, -1):
            jn, in_ = j + s * dj, i + s * di
            inside = (jn >= 0) & (jn < ny) & (in_ >= 0) & (in_ < nx)
            jn, in_ = np.clip(jn, 0, ny - 1), np.clip(in_, 0, nx - 1)
            line &= inside & (region[jn, in_] == region[j, i]) & solved[jn, in_] & (values[j, i] <= values[jn, in_])
        low |= line
    return low


def _tangents(system: MapSystem, q: np.ndarray, a: np.ndarray, jac: np.ndarray | None = None) -> np.ndarray:
    """``∂q/∂a`` (N, nf, 2) at solved configurations ``q`` with axis values ``a`` (internal units).

    ``jac``: the square problem's Jacobian there when known (from the Newton solve that found
    ``q``: :meth:`MapSystem.solve` ``return_jacobian``; it does not depend on ``a``).
    """
    if jac is None:
        _, jac = system.evaluate("square", q, system.targets(a))
    nf = system.nf
    scale = system.axis_scale
    rhs = np.zeros((nf, 2))
    rhs[nf - 2, 0], rhs[nf - 1, 1] = 1.0 / scale[0], 1.0 / scale[1]
    try:
        return np.linalg.solve(jac, np.broadcast_to(rhs, (q.shape[0], nf, 2)))
    except np.linalg.LinAlgError:  # per point: a singular one does not change the others' (bit-for-bit)
        out = np.zeros((q.shape[0], nf, 2))
        for k in range(q.shape[0]):
            try:
                out[k] = np.linalg.solve(jac[k], rhs)
            except np.linalg.LinAlgError:
                out[k] = np.linalg.lstsq(jac[k], rhs, rcond=None)[0]
        return out


def _march(system: MapSystem, q: np.ndarray, a: np.ndarray, a_dst: np.ndarray, steps: int, jump: float,
           jac: np.ndarray | None = None, tangent: np.ndarray | None = None):
    """Continue N configurations from axis values ``a`` to ``a_dst`` in ``steps`` equal sub-steps.

    ``jac`` (N, nf, nf) or ``tangent`` (N, nf, 2): the square problem's Jacobian or
    ``∂q/∂a`` at the starting ``q`` when known (else evaluated); later sub-steps take it
    from the Newton solve of the one before.  Returns ``(q, converged, accepted, jac)``:
    ``converged`` Newton converged at ``a_dst`` (the last sub-step was reached),
    ``accepted`` also within ``jump`` of every predictor; ``jac`` the Jacobian at the
    returned ``q`` where accepted.
    """
    q = np.array(q, dtype=float)
    n = q.shape[0]
    ell = system.ell
    conv = np.zeros(n, bool)
    acc = np.zeros(n, bool) if steps < 1 else np.ones(n, bool)
    jac_q = np.full((n, system.nf, system.nf), np.nan) if jac is None else np.array(jac, float)
    known = jac is not None
    live = np.arange(n)
    for s in range(1, steps + 1):
        if live.size == 0:
            break
        a0 = a[live] + (a_dst[live] - a[live]) * ((s - 1) / steps)
        a1 = a[live] + (a_dst[live] - a[live]) * (s / steps)
        if s == 1 and tangent is not None:
            t = np.asarray(tangent, float)[live]
        else:
            t = _tangents(system, q[live], a0, jac_q[live] if known or s > 1 else None)
        dq = np.einsum("nij,nj->ni", t, a1 - a0)
        pred = q[live] + dq
        sol, ok, _, _, jac_sol = system.solve(pred, a1, return_jacobian=True)
        dist = np.linalg.norm(sol - pred, axis=1) / ell
        good = ok & (dist <= jump * np.linalg.norm(dq, axis=1) / ell + 1e3 * NEWTON_TOL)
        if s == steps:
            conv[live[ok]] = True
        acc[live[~good]] = False
        q[live[good]] = sol[good]
        jac_q[live[good]] = jac_sol[good]
        live = live[good]
    return q, conv, acc, jac_q


def _signs(res, k: np.ndarray) -> np.ndarray:
    """Sign pattern (N, 2) of the DKP values (0 where undefined)."""
    return np.column_stack([np.nan_to_num(np.sign(res.dkp_input[k])), np.nan_to_num(np.sign(res.dkp_output[k]))])


_NEIGHBOURS = ((0, 1), (0, -1), (1, 0), (-1, 0))


def continue_mode(system: MapSystem, xs: np.ndarray, ys: np.ndarray, seed_q: np.ndarray,
                  tolerances: Tolerances | float | None = None, keep_configurations: bool = False,
                  jump: float = JUMP, progress=None, blocked: np.ndarray | None = None) -> ModeGrid:
    """Continue the mode of ``seed_q`` over the grid ``xs × ys`` (internal units) and evaluate the indicators.

    Parameters
    ----------
    system : MapSystem
    xs, ys : (nx,), (ny,) axis values in internal units (radians, model lengths).
    seed_q : (nf,) a configuration of the mode (on the held values).
    tolerances : the core's tolerances (decisions; ``same_configuration`` separates two
        configurations in the branch-change and sign-pattern checks).
    keep_configurations : keep every configuration (``ModeGrid.q``, ``(ny, nx, nf)``).
    jump : the predictor-distance ratio (:data:`JUMP`).
    progress : optional callable ``progress(k)`` told the number of points done per wave.
    blocked : (ny, nx) bool, optional
        Grid points not to continue over (already solved from another seed): they are neither
        solved nor passed through, and come out not assembled.
    """
    region = (0, len(ys), 0, len(xs), seed_q)
    return continue_modes(system, xs, ys, [region], tolerances, keep_configurations, jump, progress, blocked)[0]


def continue_modes(system: MapSystem, xs: np.ndarray, ys: np.ndarray, regions: list,
                   tolerances: Tolerances | float | None = None, keep_configurations: bool = False,
                   jump: float = JUMP, progress=None, blocked: np.ndarray | None = None,
                   keep: np.ndarray | None = None) -> list[ModeGrid]:
    """Continue a seed in each of several disjoint grid regions at once: one wave of every region per batch.

    ``regions`` ``[(j0, j1, i0, i1, seed_q), …]`` are index ranges of the grid ``xs × ys``
    (the tiles of :mod:`symkin.workspace.parallel`); no step, neighbour check or bracket test
    crosses a region's edge, and every computation is per point (batched Newton, stacked
    LAPACK solves, the core's batch), so each region's result is the one
    :func:`continue_mode` gives on its own sub-grid ``xs[i0:i1] × ys[j0:j1]``: only the
    batches are bigger (fewer waves, the per-wave cost shared).  ``keep`` (``(ny, nx)`` bool)
    marks points whose configurations are kept as well as the brackets'.  Returns one
    :class:`ModeGrid` per region, on its sub-grid (local indices).
    """
    tol = Tolerances.of(tolerances)
    ev = system.evaluators
    ell = system.ell
    nx, ny, nf = len(xs), len(ys), system.nf
    shape = (ny, nx)
    region = np.full(shape, -1, np.int32)
    for r, (j0, j1, i0, i1, _) in enumerate(regions):
        region[j0:j1, i0:i1] = r
    status = np.zeros(shape, np.int8)  # 0 untried, 1 solved, 2 failed, 3 rejected, 4 blocked (or in no region)
    status[region < 0] = 4
    if blocked is not None:
        status[np.asarray(blocked, bool)] = 4
    im = np.full(shape, np.nan)
    types = np.zeros(shape, np.int8)
    dkp = np.full((2,) + shape, np.nan)  # the DKP-input and DKP-output values, stacked
    d_in, d_out = dkp[0], dkp[1]
    signs = np.zeros(shape + (2,), np.int8)
    full_q = np.full(shape + (nf,), np.nan) if keep_configurations else None
    lim_of = LimIndicator(ev)
    lim = np.full(shape, np.nan) if lim_of else None
    kept: dict = {}
    branches: list = [[] for _ in regions]
    notes = [""] * len(regions)
    axis_scale = system.axis_scale

    def at(j, i):
        return np.array([xs[i], ys[j]])

    def points_at(idx: list) -> np.ndarray:
        """Axis values (N, 2) of grid indices ``[(j, i), ...]``."""
        ji = np.array(idx, np.intp).reshape(-1, 2)
        return np.column_stack([xs[ji[:, 1]], ys[ji[:, 0]]])

    def record(idx: list, q: np.ndarray, res=None, sel=None):
        if res is None:
            res, sel = ev.batch(q, tol), np.arange(len(idx))
        jj = np.array([p[0] for p in idx])
        ii = np.array([p[1] for p in idx])
        im[jj, ii] = res.im_indicator[sel]
        d_in[jj, ii] = res.dkp_input[sel]
        d_out[jj, ii] = res.dkp_output[sel]
        types[jj, ii] = (res.im[sel] * 1 + res.is_dkp_input[sel] * 2 + res.is_dkp_output[sel] * 4).astype(np.int8)
        signs[jj, ii] = _signs(res, sel)
        status[jj, ii] = 1
        if lim is not None:
            lim[jj, ii] = lim_of.smallest(q)
        if full_q is not None:
            full_q[jj, ii] = q
        if keep is not None:
            for k in np.flatnonzero(keep[jj, ii]):
                kept[(int(jj[k]), int(ii[k]))] = q[k].copy()

    # -- each region's seed grid point, reached by marching from its seed (region by region, as alone)
    wave: dict = {}
    wave_jac: dict = {}  # the square problem's Jacobian at each wave point (from the Newton solve there)
    seeds = []
    for r, (j0, j1, i0, i1, seed_q) in enumerate(regions):
        seed_q = np.asarray(seed_q, float).ravel()
        seeds.append(seed_q)
        xs_r, ys_r = xs[i0:i1], ys[j0:j1]
        a_seed = system.axis_values(seed_q[None])[0]
        cell = min(np.min(np.abs(np.diff(xs_r))) / axis_scale[0], np.min(np.abs(np.diff(ys_r))) / axis_scale[1])
        # the grid points nearest the seed (its cell's corners first), batched: the first one reached starts
        near_i = i0 + np.argsort(np.abs(xs_r - a_seed[0]), kind="stable")[:3]
        near_j = j0 + np.argsort(np.abs(ys_r - a_seed[1]), kind="stable")[:3]
        starts = sorted(((int(j), int(i)) for j in near_j for i in near_i if status[j, i] != 4),
                        key=lambda p: float(np.linalg.norm((at(*p) - a_seed) / axis_scale)))
        if not starts:
            notes[r] = "the grid points next to the seed are blocked"
            continue
        dst = np.array([at(*p) for p in starts])
        dist = float(np.max(np.linalg.norm((dst - a_seed) / axis_scale, axis=1)))
        steps = max(1, int(math.ceil(2 * dist / cell)))
        ok = np.zeros(len(starts), bool)
        for refine_steps in (1, 4, 16):  # finer sub-steps when the seed is near a singularity
            q_all, _, ok, jac_all = _march(system, np.repeat(seed_q[None], len(starts), 0),
                                           np.repeat(a_seed[None], len(starts), 0), dst, steps * refine_steps, jump)
            if ok.any():
                break
        if not ok.any():
            notes[r] = "the mode does not reach the box from its seed"
            continue
        first = int(np.flatnonzero(ok)[0])
        record([starts[first]], q_all[first: first + 1])
        wave[starts[first]] = q_all[first]
        wave_jac[starts[first]] = jac_all[first]
        if progress:
            progress(1)

    def keep_brackets(points: dict):
        """Keep the configurations of ``points`` with a neighbour not assembled or of another DKP sign pattern."""
        if not points:
            return
        idx = np.array(list(points))
        j, i = idx[:, 0], idx[:, 1]
        bracket = np.zeros(len(idx), bool)
        for dj, di in _NEIGHBOURS:
            jn, in_ = j + dj, i + di
            inside = (jn >= 0) & (jn < ny) & (in_ >= 0) & (in_ < nx)
            jn, in_ = np.clip(jn, 0, ny - 1), np.clip(in_, 0, nx - 1)
            inside &= region[jn, in_] == region[j, i]
            st = status[jn, in_]
            other = (st == 1) & np.any(signs[jn, in_] != signs[j, i], axis=1)
            bracket |= inside & ((st == 2) | (st == 3) | other)
        # near-zero minima of |T|: the quadtree starts there (double zeros, curves narrower than a cell)
        bracket |= dips(dkp, status == 1, j, i, region=region)
        if lim is not None:  # minima of the LIM indicator: refinement polishes them (lim_points)
            bracket |= _minima(lim, status == 1, j, i, region)
        for k in np.flatnonzero(bracket):
            p = (int(j[k]), int(i[k]))
            kept[p] = points[p]

    while wave:
        # candidates: untried or failed neighbours of the wave in its region, each with its solved wave neighbours
        sources: dict = {}
        for (j, i) in wave:
            r = region[j, i]
            for dj, di in _NEIGHBOURS:
                p = (j + dj, i + di)
                if 0 <= p[0] < ny and 0 <= p[1] < nx and status[p] in (0, 2) and region[p] == r:
                    sources.setdefault(p, []).append((j, i))
        busy = {int(region[p]) for p in sources}
        done = {p: q for p, q in wave.items() if int(region[p]) not in busy}
        if done:  # regions whose continuation ends here
            keep_brackets(done)
            wave = {p: q for p, q in wave.items() if int(region[p]) in busy}
        if not sources:
            break
        cand = list(sources)
        src = [sources[p][0] for p in cand]
        # ∂q/∂a once per wave point (a source of several candidates, and of the branch checks)
        w_idx = {p: k for k, p in enumerate(wave)}
        w_list = list(wave)
        w_tan = _tangents(system, np.array([wave[p] for p in w_list]), points_at(w_list),
                          np.array([wave_jac[p] for p in w_list]))
        s_idx = np.array([w_idx[p] for p in src])
        q_src = np.array([wave[s] for s in src])
        jac_src = np.array([wave_jac[s] for s in src])
        a_src, a_dst = points_at(src), points_at(cand)
        q_new, conv, acc, jac_new = _march(system, q_src, a_src, a_dst, 1, jump, tangent=w_tan[s_idx])
        for k_sub in _SUBSTEPS:
            redo = np.flatnonzero(~acc)
            if redo.size == 0:
                break
            q2, c2, a2, j2 = _march(system, q_src[redo], a_src[redo], a_dst[redo], k_sub, jump,
                                    jac=jac_src[redo], tangent=w_tan[s_idx[redo]])
            q_new[redo], acc[redo], jac_new[redo] = q2, a2, j2
            conv[redo] |= c2
        for k in np.flatnonzero(~acc):
            status[cand[k]] = 3 if conv[k] else 2
        good = np.flatnonzero(acc)
        # branch changes: a second solved neighbour that predicts another configuration
        check = [(k, s2) for k in good for s2 in sources[cand[k]][1:]]
        if check:
            kk = np.array([c[0] for c in check])
            q2_src = np.array([wave[c[1]] for c in check])
            a2_src = points_at([c[1] for c in check])
            t = w_tan[[w_idx[c[1]] for c in check]]
            dq = np.einsum("nij,nj->ni", t, a_dst[kk] - a2_src)
            far = np.linalg.norm(q_new[kk] - (q2_src + dq), axis=1) > jump * np.linalg.norm(dq, axis=1) + \
                1e3 * NEWTON_TOL * ell
            if np.any(far):
                sel = np.flatnonzero(far)
                c_idx = np.array([w_idx[check[m][1]] for m in sel])
                q3, _, a3, _ = _march(system, q2_src[sel], a2_src[sel], a_dst[kk[sel]], 4, jump,
                                      jac=np.array([wave_jac[w_list[m]] for m in c_idx]), tangent=w_tan[c_idx])
                differ = a3 & (np.linalg.norm(q3 - q_new[kk[sel]], axis=1) > tol.same_configuration * ell)
                for m in np.flatnonzero(differ):
                    p = cand[kk[sel[m]]]
                    branches[region[p]].append((p, check[sel[m]][1]))
        # indicators, and the sign-pattern check against the source neighbour
        if good.size:
            res = ev.batch(q_new[good], tol)
            sg = _signs(res, np.arange(good.size))
            src_sg = np.array([signs[src[k]] for k in good])
            changed = np.flatnonzero(np.any(sg != src_sg, axis=1) & np.all(sg != 0, axis=1)
                                     & np.all(src_sg != 0, axis=1))
            keep_ok = np.ones(good.size, bool)
            if changed.size:
                kg = good[changed]
                q4, _, a4, _ = _march(system, q_src[kg], a_src[kg], a_dst[kg], 4, jump, jac=jac_src[kg],
                                      tangent=w_tan[s_idx[kg]])
                same = a4 & (np.linalg.norm(q4 - q_new[kg], axis=1) <= tol.same_configuration * ell)
                for m in np.flatnonzero(~same):
                    status[cand[kg[m]]] = 3
                keep_ok[changed[~same]] = False
            good, sel = good[keep_ok], np.flatnonzero(keep_ok)
            if good.size:
                record([cand[k] for k in good], q_new[good], res, sel)
        keep_brackets(wave)
        wave = {cand[k]: q_new[k] for k in good}
        wave_jac = {cand[k]: jac_new[k] for k in good}
        if progress:
            progress(len(cand))
    out = []
    for r, (j0, j1, i0, i1, _) in enumerate(regions):
        sl = (slice(j0, j1), slice(i0, i1))
        local = {(j - j0, i - i0): q for (j, i), q in kept.items() if region[j, i] == r}
        br = tuple(((a[0] - j0, a[1] - i0), (b[0] - j0, b[1] - i0)) for a, b in branches[r])
        out.append(ModeGrid(seeds[r], status[sl] == 1, status[sl] == 3, im[sl], d_in[sl], d_out[sl], types[sl], br,
                            local, None if full_q is None else full_q[sl], notes[r],
                            lim_indicator=None if lim is None else lim[sl]))
    return out
