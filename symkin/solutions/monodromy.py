"""Start solutions of a model's parameter homotopy, by monodromy, cached with the model's artefacts.

:func:`start_solutions` returns the family (:class:`~symkin.solutions.parameter_homotopy.ParameterFamily`)
of a model with the labels prescribed, generic complex parameters ``λ*`` and every solution
there.  Made once and kept in the artefact cache (:func:`symkin.numeric.codegen.cache_directory`,
``parameter-homotopy/<model content hash>_<labels hash>.npz``).

Monodromy: the model's configuration solves the family at ``λ = 0`` (all values 0); it is
tracked to ``λ*``.  Then, in each loop, two random complex parameter points ``λ₁``, ``λ₂`` are
drawn and all solutions known at ``λ*`` are tracked around the triangle ``λ* → λ₁ → λ₂ → λ*``
(each leg with its own γ); the endpoints that solve the original equations at ``λ*``
(:data:`VERIFY`) and are new (:data:`DISTINCT`) are added.  **Stopping rule:** the consecutive
loops without a new solution have tracked ``STALL_PATHS`` = 400 paths (each of the ``N`` known
solutions tracked around a loop is one chance to land on a missing one; a loop misses a given one
with a probability that falls geometrically), i.e. ``S = clip(⌈400 / N⌉, MIN_STALL_LOOPS = 10,
STALL_LOOPS = 20)`` loops: 20 for the four-bar with a prescribed crank angle (5 and 10 loops were
too few there, its two half-lines are exchanged only by loops about ``cos² + sin² = 0``) and for
the 3-RPR's 6 solutions, 10 for the general Gough–Stewart's 40 (5 stopped at 39 of 40 once); or
``MAX_LOOPS`` loops.  No trace test (the parameters enter the equations' coefficients, not as
linear slices, so the traces are not linear along a line of parameters): the counts are checked
against closed forms and independent solvers in the tests.
"""
from __future__ import annotations

import hashlib
import sys
import time
from dataclasses import dataclass

import numpy as np

from symkin.model.mechanism import Mechanism
from symkin.solutions.parameter_homotopy import ParameterFamily, track_parameters
from symkin.solutions.progress import as_progress
from symkin.tolerances import Tolerances

__all__ = ["STALL_LOOPS", "StartSolutions", "augment", "stall_loops", "start_solutions"]

#: monodromy stops when the loops since the last new solution tracked at least STALL_PATHS paths, and at
#: least MIN_STALL_LOOPS loops (module docstring)
STALL_PATHS = 400
MIN_STALL_LOOPS = 10
#: the stall rule's largest number of loops (a model with one or two solutions)
STALL_LOOPS = 20
MAX_LOOPS = 200
#: a point solves the family when the original equations' max-norm is below this (dimensionless)
VERIFY = 1e-8
#: two solutions are one when closer than this (max-norm, dimensionless)
DISTINCT = 1e-6
#: bump when the cached arrays change meaning
FORMAT = "2"


@dataclass(frozen=True, eq=False)
class StartSolutions:
    """A family, generic parameters ``lam`` (r,) complex and all solutions ``u`` (N, n) there.

    ``loops`` and ``seconds`` describe how they were made (0 when read from the cache).
    """

    family: ParameterFamily
    lam: np.ndarray
    u: np.ndarray
    loops: int
    seconds: float
    cached: bool


def _key(mech: Mechanism, labels, tol: Tolerances) -> str:
    text = "|".join([FORMAT, *labels, repr(tol)])
    return f"{mech.content_hash()[:20]}_{hashlib.sha256(text.encode()).hexdigest()[:12]}"


def cache_file(mech: Mechanism, labels, tol: Tolerances, cache_dir=None):
    """Path of the cached start solutions of ``mech`` with ``labels`` prescribed."""
    from symkin.numeric.codegen import cache_directory

    return cache_directory(cache_dir) / "parameter-homotopy" / f"{_key(mech, labels, tol)}.npz"


def start_solutions(mech: Mechanism, labels, tol: Tolerances, seed: int = 0, cache: bool = True,
                    progress=None) -> StartSolutions | None:
    """The cached start solutions, else monodromy (module docstring); None when no first solution is found.

    Parameters
    ----------
    mech : Mechanism
    labels : sequence of str
        The prescribed labels (their order fixes the family's).
    tol : Tolerances
    seed : int
        Seed of the random parameters, squaring-up matrix and γ's.
    cache : bool
        Read and write the artefact cache.
    progress : Progress or callable, optional
        Told the monodromy loops (:func:`symkin.solutions.progress.as_progress`).
    """
    labels = tuple(labels)
    path = cache_file(mech, labels, tol)
    if cache and path.exists():
        try:
            with np.load(path, allow_pickle=False) as data:
                family = ParameterFamily.from_arrays(data)
                return StartSolutions(family, data["lam"], data["u"], int(data["loops"]), 0.0, True)
        except (OSError, KeyError, ValueError):
            pass  # a damaged cache file is made again
    t0 = time.perf_counter()
    rng = np.random.default_rng(seed)
    family = ParameterFamily.build(mech, labels, tol, seed=seed)
    r = family.rank
    lam = rng.standard_normal(r) + 1j * rng.standard_normal(r)
    if float(family.residual(family.start[None], np.zeros(r))[0]) > VERIFY:
        return None
    first = track_parameters(family, family.start[None], np.zeros(r), lam, rng)
    known = _new(family, lam, first.u[first.ok], np.zeros((0, family.start.size), complex))
    if not len(known):
        return None
    known, loops = _loops(family, lam, known, rng, progress)
    out = StartSolutions(family, lam, known, loops, time.perf_counter() - t0, False)
    if cache:
        _save(out, mech, labels, tol)
    return out


def augment(starts: StartSolutions, points, lam_query, mech: Mechanism, labels, tol: Tolerances, seed: int = 0,
            cache: bool = True, progress=None) -> StartSolutions:
    """Add solutions found at a query (e.g. by the total-degree solve) to the start solutions, then loop again.

    Monodromy reaches only the component of the incidence variety that holds its first
    solution; a model whose configuration curve is reducible (a change-point four-bar: the
    parallelogram and anti-parallelogram branches) needs a solution on every component.  The
    points (full ``u`` at the query's parameters) are tracked to the generic parameters, and
    the new ones seed more loops.
    """
    t0 = time.perf_counter()
    rng = np.random.default_rng(seed + 1)
    family, lam = starts.family, starts.lam
    pts = np.array(points, complex).reshape(-1, family.start.size)
    if not len(pts):
        return starts
    back = track_parameters(family, pts, np.asarray(lam_query, complex), lam, rng)
    new = _new(family, lam, back.u[back.ok], starts.u)
    if not len(new):
        return starts
    known, loops = _loops(family, lam, np.vstack([starts.u, new]), rng, progress)
    out = StartSolutions(family, lam, known, starts.loops + loops, starts.seconds + time.perf_counter() - t0, False)
    if cache:
        _save(out, mech, labels, tol)
    return out


def _loops(family: ParameterFamily, lam, known, rng, progress) -> tuple[np.ndarray, int]:
    """Monodromy loops from ``known`` until the stopping rule (module docstring)."""
    r = family.rank
    stalled, loops = 0, 0
    progress = as_progress(progress)
    progress.stage(f"monodromy ({len(known)} solutions)", total=None, unit="loop")
    while stalled < stall_loops(len(known)) and loops < MAX_LOOPS:
        loops += 1
        l1 = rng.standard_normal(r) + 1j * rng.standard_normal(r)
        l2 = rng.standard_normal(r) + 1j * rng.standard_normal(r)
        u = known
        for a, b in ((lam, l1), (l1, l2), (l2, lam)):
            res = track_parameters(family, u, a, b, rng)
            u = res.u[res.ok]
            if not len(u):
                break
        before = len(known)
        known = np.vstack([known, _new(family, lam, u, known)])
        stalled = stalled + 1 if len(known) == before else 0
        progress.describe(f"monodromy loop {loops}: {len(known)} solutions ({stalled} loops without a new one)")
        progress.advance(1)
    return known, loops


def stall_loops(found: int) -> int:
    """Loops without a new solution after which monodromy stops, with ``found`` solutions (module docstring)."""
    return int(min(STALL_LOOPS, max(MIN_STALL_LOOPS, -(-STALL_PATHS // max(found, 1)))))


def _save(out: StartSolutions, mech, labels, tol) -> None:
    path = cache_file(mech, labels, tol)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(".tmp.npz")
        np.savez(tmp, lam=out.lam, u=out.u, loops=out.loops, **out.family.to_arrays())
        tmp.replace(path)
    except OSError as exc:
        print(f"symkin: could not cache the start solutions in {path}: {exc}", file=sys.stderr)


def _new(family: ParameterFamily, lam, u, known) -> np.ndarray:
    """The rows of ``u`` that solve the original equations at ``lam`` and are not in ``known`` (nor repeated)."""
    out = []
    if not len(u):
        return np.zeros((0, known.shape[1]), complex)
    ok = family.residual(u, lam) <= VERIFY
    for x in u[ok]:
        if all(float(np.max(np.abs(x - k))) > DISTINCT for k in list(known) + out):
            out.append(x)
    return np.array(out, complex).reshape(-1, known.shape[1])
