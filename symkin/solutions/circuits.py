"""Every singular configuration of a 1-DOF mechanism (``symkin.singularities``, issue 9 §2).

The configuration curve of a 1-DOF mechanism splits into *circuits* (connected smooth
components: the two assembly modes of a Grashof crank-rocker are two circuits, a
non-Grashof four-bar has one).  The paper's procedure finds the singular configurations
on the paths it simulates; this module makes the search global:

1. **Critical points.**  The square system "closure + DKP-input test function = 0"
   (:mod:`symkin.solutions.dkp_system`) is solved by homotopy continuation: its real
   solutions are every configuration where the input is stationary along the curve
   (DKP-input, paper §III) and every branch point (IM).  The same is done for the
   output when the model has one scalar output (DKP-output and IM), and for the rotation of
   every rocker (a planar link with one fixed node, :mod:`symkin.solutions.lim_systems`) other
   than the input's and the output's: its real solutions are every configuration where that
   link is locked (LIM, paper §V; check ``LIM:<link>``) and every IM point.
2. **Seeds.**  :func:`symkin.solve_all` at one input value (the middle of the interval
   between critical values that holds the model's input), and every real solution of step 1:
   a circuit on which the input turns fully crosses every input value; on any other circuit
   the input sweeps an interval whose two ends are critical points, solutions of step 1.
3. **Branches.**  Each seed not yet on a traced branch is traced by :func:`symkin.trace` (the
   existing pseudo-arclength continuation with its event location) until the path closes
   on itself; a seed is on a traced branch when the path passes through it: the crossing
   of its input value is located on the path (:func:`~symkin.curves.locate.locate_sign_change`)
   and is within :attr:`Tolerances.same_configuration` (units of the length scale) of it.
   A critical point seeds the two half-branches that leave it (curve points
   :data:`~symkin.curves.branches.HALF_BRANCH_RADIUS` away, traced outwards).
   **Branch points.**  Every IM event of nullity 2 that a trace locates is located again,
   to rounding, by :func:`~symkin.curves.locate.locate_singular_point` (deflated Newton: also
   where two branches are *tangent*, as at the double butterfly's contacts with its LIM
   branch, where the trace's own event is 1e-6 to 1e-3 off), and every half-branch that
   leaves it (:func:`~symkin.curves.branches.half_branches`: 4 for two branches) is traced
   outwards unless a traced branch already passes through it.  At a tangent contact the
   continuation may go on along either branch; the half-branches make the search
   complete whichever it took, and the answer independent of it.
4. **Singular configurations and circuits.**  Every event that the traces locate (DKP-input,
   DKP-output, IM, LIM), classified by :func:`symkin.analyze`, and every real solution of a LIM system
   (kind ``LIM``: it joins the configuration at the same place, or is listed on the traced branch
   through it); one configuration met by several
   branches is one entry, and every IM event at a located branch point is that point (an IM
   event whose own location failed joins a branch point within ``√same_configuration``).
   Branches that share a configuration (a branch point, IM) are one circuit: a circuit is a
   connected component.  At the change point of a four-bar (``s + l = p + q``) the
   continuation goes straight through the flat IM configuration, so its one branch turns the
   crank twice (once in each assembly mode) and crosses itself there: one circuit, where the
   Grashof four-bars on either side have two or one.
5. **Cross-check.**  The real solutions of step 1 must be exactly the traced configurations
   of the kinds they detect (DKP-input or IM; DKP-output or IM), each matched within
   ``same_configuration``.  Both counts are reported; a disagreement is a field
   (``agree = False``, the unmatched configurations) and a warning, never silent.  A LIM
   system's traced side is the traced LIM events where its link is locked (and IM), located by
   :func:`symkin.trace`'s per-link LIM tests.

**Beyond the homotopy.**  A square system whose homotopy would track more than ``max_paths``
paths (its total degree, summed over the factors of the determinant) is solved exactly instead
when msolve is installed (the extra ``symkin[exact]``, :mod:`symkin.solutions.exact`: the system
rebuilt in rational arithmetic, a Gröbner basis, certified real roots; ``solver = "msolve"``).
The double butterfly of ``papers_examples/`` is this case: 768 homotopy paths for a factor of
degree 6 (Bertini had not finished after 100 minutes here), 2 s for msolve, whose 18 real
solutions are exactly the traced 16 crank turning points and the two tangent contacts.

**Without the square system.**  Otherwise (no msolve, or a mechanism the exact system does not
cover: sliders, spatial, redundant constraints) the system is not solved: its :class:`CrossCheck` is ``skipped`` (``agree`` None, also for the whole result
unless another check disagrees) and a :class:`SingularitiesWarning` says that those
configurations are not cross-checked.  Without the DKP-input system the seeds are placed in
rounds: solve_all at the model's input, trace, then at the middle of every interval between
consecutive traced critical input values (DKP-input events and branch points) that holds no
sample yet, and of every gap between samples and critical values wider than
:data:`MAX_SAMPLE_GAP` (30° for an angle input, 1/12 of the critical range for a length),
until none is left.  Every circuit whose input range holds a traced critical value, or is
wider than the gap, then lies on a traced branch; a narrower circuit between two samples can
be missed: only the square system rules that out.  ``samples=`` replaces these seeds by the
caller's input values.  Without msolve the double butterfly takes this way (25 solve_all
calls) to the same answer, which ``tests/solutions/test_double_butterfly.py`` also checks
against an independent root search.

Not covered: a circuit on which the input is locked (constant), whose points are all
critical (not isolated solutions of step 1) and which no seed at another input value meets;
branch points where the nullity exceeds 2 (located, reported, their branches not enumerated);
a link locked along a whole branch (the double butterfly's LIM branch): its LIM system is not
zero-dimensional, its check is ``skipped`` (msolve says why).
"""
from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from symkin.analysis.classification import analyze
from symkin.errors import SymkinError
from symkin.kinds import Kind
from symkin.model.mechanism import Mechanism
from symkin.numeric.coordinates import InputCoordinate, input_coordinates
from symkin.solutions.circuit_search import RETURNED, CircuitSearch, components
from symkin.solutions.cross_check import compare
from symkin.solutions.dkp_system import dkp_system
from symkin.solutions.frame_coordinates import (CoordinateValue, as_dict, flat_coordinates, format_value,
                                                free_coordinates, output_coordinate, wrap)
from symkin.solutions.homotopy import require_solver, total_degree
from symkin.solutions.lim_systems import lim_coordinates
from symkin.solutions.seeding import MAX_SEED_ROUNDS, cluster, sample_gap, sample_near_zero, uncovered
from symkin.solutions.singularities_result import (Branch, Circuit, CrossCheck, SingularConfiguration, Singularities,
                                                   SingularitiesWarning)
from symkin.solutions.solve_all import solve_all
from symkin.solutions.square_solutions import exact_roots, is_singular
from symkin.solutions.square_solutions import real_roots as _real_roots  # a module global: tests replace it
from symkin.solutions.system import closure_system
from symkin.tolerances import Tolerances

__all__ = ["Branch", "Circuit", "CrossCheck", "SingularConfiguration", "Singularities", "SingularitiesWarning",
           "singularities"]

#: default ``max_paths`` of one square DKP system: the Watt six-bar's track 64 each (a few seconds), the
#: double butterfly's 768 (a degree-6 factor of 2295 terms: not finished after 19 min; its crank block, a
#: constant on the curve, is dropped by :func:`~symkin.solutions.dkp_system.dkp_system`)
MAX_PATHS = 600


def singularities(mech: Mechanism, *, tol: float | Tolerances | None = None, unit: str = "rad",
                  max_turns: int = 4, max_arclength: float | None = None, max_paths: int = MAX_PATHS,
                  seed: int = 0, samples: list[float] | None = None,
                  progress: Callable[[str], None] | None = None) -> Singularities:
    """Every circuit of a 1-DOF mechanism and every DKP-input, DKP-output, IM and LIM configuration on it.

    See the module docstring for the method.  Needs the optional extra ``symkin[global]``
    (Bertini 2) for :func:`symkin.solve_all` and the square DKP and LIM systems.

    Parameters
    ----------
    mech : Mechanism
        F = 1, driven by its first input (a planar rotation, a joint angle, a rotation about a
        fixed axis, a slide on a fixed line or a node coordinate); its first output, when it is
        one scalar coordinate, gives the DKP-output system and the plot's vertical axis.
    tol : float or Tolerances
        Rank tolerance of the events and their classification; ``same_configuration`` decides
        whether two located configurations (or a seed and a path) are one.
    unit : {"rad", "deg"}
        Unit of the reported angles (``input``, ``output``, ``samples``).
    max_turns : int
        A circuit is traced for at most this many turns of an angle input before it is
        reported as not closed.
    max_arclength : float, optional
        Arclength limit of each trace in units of the length scale (default 100 per turn).
    max_paths : int
        A square system whose homotopy would track more paths than this (its total degree;
        default :data:`MAX_PATHS`) is not solved: its :class:`CrossCheck` is ``skipped`` and a
        :class:`SingularitiesWarning` says that those configurations are not cross-checked.
    seed : int
        Seed of the random combinations that square up a redundant closure.
    samples : list of float, optional
        Input values (in ``unit``, from the model's configuration) at which :func:`symkin.solve_all`
        seeds the search, *instead of* the default ones: the middle of the interval that holds
        the model's input (with the square DKP-input system), or the rounds between traced
        critical values (without it; module docstring).  Faster when the rounds would need
        many samples; a circuit whose input range holds none of the values and no critical
        point of the square systems is then missed.
    progress : callable, optional
        Called with a short description before each homotopy and each trace (for a progress bar).

    Returns
    -------
    Singularities

    Raises
    ------
    SymkinError
        Not 1-DOF, no input, an unsupported input, or the solver not installed (the message
        names the extra).

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> r = singularities(get("fourbar_appendix"), unit="deg")  # doctest: +SKIP
    >>> len(r.circuits), [s.types for s in r.singularities], r.agree  # doctest: +SKIP
    (2, [('DKP-output', 'LIM'), ('DKP-output', 'LIM'), ('DKP-output', 'LIM'), ('DKP-output', 'LIM')], True)
    """
    start = time.perf_counter()
    tolerances = Tolerances.of(tol)
    if unit not in ("rad", "deg"):
        raise SymkinError(f"unit must be 'rad' or 'deg', got {unit!r}")
    f = mech.mobility_value
    if f != 1:
        raise SymkinError(f"{mech.name}: symkin singularities needs a 1-DOF mechanism, this one has F = {f} "
                          "(its configurations form a set of dimension F, not a curve of circuits); fix F - 1 "
                          "inputs in a model of the sub-mechanism, or use symkin map for F = 2")
    coords = input_coordinates(mech)
    if not coords:
        raise SymkinError(f"{mech.name}: the model has no input; add one (e.g. inputs = [{{rotation = \"crank\"}}])")
    drive = coords[0]
    output = output_coordinate(mech)
    require_solver()
    scale = mech.length_scale
    kind = drive.kind
    in_value = CoordinateValue(mech, drive)
    out_value = CoordinateValue(mech, output) if output is not None else None
    notes: list[str] = []

    # 1. critical points of the input (and of the output) from the square DKP systems; the LIM systems
    closure = closure_system(mech, tolerances)
    systems = [_Square(str(Kind.DKP_INPUT), Kind.DKP_INPUT, drive)]
    if output is not None:
        systems.append(_Square(str(Kind.DKP_OUTPUT), Kind.DKP_OUTPUT, output))
    systems += [_Square(f"{Kind.LIM}:{c.parameter.target[0]}", Kind.LIM, c, c.parameter.target[0])
                for c in lim_coordinates(mech, output)]
    roots: dict[str, tuple[list[dict], int, int, float]] = {}
    skipped: dict[str, tuple[int, int, float, str]] = {}
    solvers: dict[str, str] = {}
    for sq in systems:
        name, c = sq.name, sq.coordinate
        t0 = time.perf_counter()
        if progress is not None:
            progress(f"square {name} system")
        try:
            system = dkp_system(mech, c, tolerances, closure=closure, seed=seed)
        except SymkinError as exc:
            if sq.kind != Kind.LIM:
                raise
            if "is constant on the configuration space" in str(exc):
                roots[name] = ([], 0, 0, time.perf_counter() - t0)  # the link turns without stopping: never locked
            else:
                skipped[name] = (0, 0, time.perf_counter() - t0, str(exc))
                _warn(notes, f"{mech.name}: the square {name} system is not available ({exc}): the traced "
                             f"configurations where {sq.link} is locked (LIM) are NOT cross-checked")
            continue
        paths = sum(total_degree(list(e), list(system.unknowns)) for e in system.systems())
        if paths > max_paths:
            by_msolve = exact_roots(mech, c)
            if isinstance(by_msolve, list):
                roots[name] = (by_msolve, paths, system.degree, time.perf_counter() - t0)
                solvers[name] = "msolve"
                continue
            why = f"{paths} paths > max_paths = {max_paths}; exact: {by_msolve}"
            skipped[name] = (paths, system.degree, time.perf_counter() - t0, why)
            if sq.kind == Kind.LIM:
                what = (f"the traced configurations where {sq.link} is locked (LIM) are NOT cross-checked"
                        + (" (a system that is not zero-dimensional: the link may be locked along a whole branch)"
                           if "not zero-dimensional" in by_msolve else ""))
            else:
                what = (f"the traced {name}/IM configurations are NOT cross-checked"
                        + ("" if name != Kind.DKP_INPUT or samples is not None else
                           ", and the seeds are placed in rounds between the traced critical values instead (module "
                           "docstring, 'Without the square system')"))
            _warn(notes, f"{mech.name}: the square {name} system (closure + det = 0, degree {system.degree}) needs "
                         f"{paths} homotopy paths, more than max_paths = {max_paths} (raise it with --max-paths), "
                         f"and its exact solution is not available ({by_msolve}): not solved, so {what}")
            continue
        found, tracked = _real_roots(system, tolerances)
        if system.squared:
            found = [c_ for c_ in found if is_singular(mech, c_, sq.kind, tolerances, sq.link)]
        roots[name] = (found, tracked, system.degree, time.perf_counter() - t0)

    # 2-3. seeds (solve_all between consecutive critical input values), the branches through them and
    # through every half-branch of every vertex
    search = CircuitSearch(mech, tolerances, in_value, kind, max_turns if kind == "angle" else 1, max_arclength,
                           drive.label, unit, notes, progress)
    exact = Kind.DKP_INPUT in roots
    sampled: list[float] = []
    seeds = 0

    def sample(v: float) -> None:
        nonlocal seeds
        sampled.append(v)
        if progress is not None:
            progress(f"solve_all at {drive.label} = {format_value(v, kind, unit)}")
        # several seeds (rounds between the traced critical values, or given samples): the parameter
        # homotopy, whose start solutions are made once; one seed: whichever solve_all finds cheaper
        repeated = not exact or (samples is not None and len(samples) > 1)
        sol = solve_all(mech, {drive.label: v}, unit="rad", tol=tolerances, seed=seed,
                        method="parameter" if repeated else "auto")
        seeds += len(sol.solutions)
        for s_ in sol.solutions:
            search.seed(v, s_.configuration)

    to_input = math.pi / 180.0 if (unit == "deg" and kind == "angle") else 1.0
    if samples is not None:
        for v in samples:
            sample(wrap(float(v) * to_input, kind))
    if exact:
        # every circuit on which the input turns fully crosses one input value; every other one has
        # its extreme input values among the square systems' solutions: trace from those
        critical = cluster([wrap(in_value(flat_coordinates(mech, c)), kind) for c in roots[Kind.DKP_INPUT][0]], 1e-12)
        if samples is None:
            sample(sample_near_zero(critical, kind))
        for name in roots:
            for conf in roots[name][0]:
                search.critical_point(conf)
    elif samples is None:
        critical: list[float] = []
        for _ in range(MAX_SEED_ROUNDS):
            todo = uncovered(critical, sampled, kind, sample_gap(critical, kind))
            if not todo:
                break
            for v in todo:
                sample(v)
            critical = search.critical_values()
        else:
            if uncovered(critical, sampled, kind, sample_gap(critical, kind)):
                notes.append(f"the seeds did not settle after {MAX_SEED_ROUNDS} rounds of input values")
    if not exact:
        for sq in systems:  # a LIM configuration on no traced branch seeds its own
            for conf in roots.get(sq.name, ([],))[0] if sq.kind == Kind.LIM else []:
                search.critical_point(conf)

    # 4. singular configurations on the branches, merged; branches through one configuration are one circuit
    entries: list[dict] = [{"q": v["q"], "x": v["x"], "branches": sorted(v["paths"]), "kinds": [],
                            "analysis": v["analysis"], "s": 0.0, "vertex": k} for k, v in enumerate(search.vertices)]
    for index, (path, _, _) in enumerate(search.paths, 1):
        for e_index, e in enumerate(path.singular_events()):
            q = free_coordinates(mech, e.coordinates)
            k = search.event_vertex.get((index, e_index))
            if k is None and e.analysis is not None and Kind.IM in e.analysis.types:
                k = search.vertex_of(q)
            if k is not None:
                item = entries[k]
                item["branches"].append(index)
                item["kinds"] += [kk for kk in e.kinds if kk not in item["kinds"]]
                if not item["s"]:
                    item["s"] = e.s
                continue
            for item in entries:
                if item.get("vertex") is None and np.linalg.norm(item["q"] - q) <= tolerances.same_configuration * scale:
                    item["branches"].append(index)
                    item["kinds"] += [kk for kk in e.kinds if kk not in item["kinds"]]
                    break
            else:
                entries.append({"q": q, "x": e.coordinates, "branches": [index], "kinds": list(e.kinds),
                                "analysis": e.analysis, "s": e.s, "vertex": None})
    for item in entries:
        if not item["kinds"]:
            item["kinds"] = [Kind.IM]  # a vertex met only by the traces of its half-branches

    # 5. cross-check: each square system against the traced configurations of the kinds it detects
    same = tolerances.same_configuration * scale
    checks = []
    for sq in systems:
        if sq.kind == Kind.LIM:
            traced = _traced_lim(mech, entries, sq.link)
        else:
            traced = [as_dict(mech, it["x"]) for it in entries if sq.kind in it["kinds"] or Kind.IM in it["kinds"]]
        if sq.name in skipped:
            paths, degree, seconds, why = skipped[sq.name]
            checks.append(CrossCheck(sq.kind, sq.coordinate.label, 0, len(traced), 0, paths, degree, (), (), seconds,
                                     skipped=why, link=sq.link))
            continue
        found, tracked, degree, seconds = roots[sq.name]
        checks.append(replace(compare(mech, sq.kind, sq.coordinate.label, found, traced, tracked, degree, seconds,
                                      scale, tolerances), solver=solvers.get(sq.name, "bertini"), link=sq.link))
    for ch in checks:
        if ch.agree is False:
            what = (f"{ch.name}/IM configuration(s)" if ch.kind != Kind.LIM
                    else f"configuration(s) where {ch.link} is locked, or IM")
            _warn(notes, f"{mech.name}: the square {ch.name} system has {ch.homotopy} real solution(s), the traced "
                         f"circuits {ch.traced} {what}; {len(ch.unmatched_homotopy)} found only by the homotopy, "
                         f"{len(ch.unmatched_traced)} only by the traces")

    # 4 (end). the LIM systems' solutions join the configuration at the same place, or are new ones
    for sq in systems:
        if sq.kind == Kind.LIM and sq.name in roots:
            _add_lim(mech, search, in_value, entries, roots[sq.name][0], same)
    component = components(len(search.paths), [item["branches"] for item in entries] + search.groups)
    conv = 180.0 / math.pi if (unit == "deg" and kind == "angle") else 1.0
    out_conv = 180.0 / math.pi if (output is not None and unit == "deg" and output.kind == "angle") else 1.0
    result_sing = []
    for item in sorted(entries, key=lambda it: (component[it["branches"][0]], wrap(in_value(it["x"]), kind))):
        a = item["analysis"]
        result_sing.append(SingularConfiguration(
            as_dict(mech, item["x"]), tuple(a.types) if a else (), a.dof if a else -1,
            component[item["branches"][0]], tuple(sorted(set(item["branches"]))),
            wrap(in_value(item["x"]), kind) * conv,
            None if out_value is None else wrap(out_value(item["x"]), output.kind) * out_conv,
            tuple(item["kinds"]), item["s"], a, tuple(a.locked_links) if a else ()))

    branches = []
    for index, (path, offset, ins) in enumerate(search.paths, 1):
        outs = None if out_value is None else np.unwrap([out_value(p.coordinates) for p in path.points]) \
            if output.kind == "angle" else np.array([out_value(p.coordinates) for p in path.points])
        span = float(np.max(ins) - np.min(ins)) if ins.size else 0.0
        closed = path.stop_reason in (Kind.CLOSED, "unreachable", RETURNED)
        branches.append(Branch(index, as_dict(mech, path.points[0].coordinates), ins, outs, closed,
                               kind == "angle" and span >= 2 * math.pi - 1e-9, path.stop_reason, path))
    circuit_objs = [Circuit(k, tuple(b for b in branches if component[b.index] == k))
                    for k in sorted(set(component.values()))]
    return Singularities(mech, drive.label, None if output is None else output.label, unit, kind,
                         tuple(circuit_objs), tuple(result_sing), tuple(checks), tuple(sampled), seeds,
                         tuple(notes), time.perf_counter() - start)


@dataclass(frozen=True)
class _Square:
    """One square system of :func:`singularities`: its check's name, its kind, its coordinate and (LIM) its link."""

    name: str
    kind: Kind
    coordinate: InputCoordinate
    link: str = ""


def _warn(notes: list[str], msg: str) -> None:
    notes.append(msg)
    warnings.warn(msg, SingularitiesWarning, stacklevel=3)


def _traced_lim(mech: Mechanism, entries: list[dict], link: str) -> list[dict]:
    """The traced side of a LIM check: the traced configurations where ``link`` is locked, located as LIM
    events by :func:`symkin.trace` (its per-link LIM tests, F = 1), and the IM ones."""
    return [as_dict(mech, it["x"]) for it in entries if Kind.IM in it["kinds"] or (
        Kind.LIM in it["kinds"] and it["analysis"] is not None and link in it["analysis"].locked_links)]


def _entry_at(entries: list[dict], q: np.ndarray, same: float) -> dict | None:
    """The first configuration of ``entries`` within ``same`` of the free coordinates ``q``, or None."""
    return next((it for it in entries if float(np.linalg.norm(it["q"] - q)) <= same), None)


def _branch_through(mech: Mechanism, search: CircuitSearch, in_value: CoordinateValue, conf: dict) -> int | None:
    """The traced branch (from 1) through the configuration ``conf``, or None."""
    return search.covering(in_value(flat_coordinates(mech, conf)), free_coordinates(mech, conf))


def _add_lim(mech: Mechanism, search: CircuitSearch, in_value: CoordinateValue, entries: list[dict],
             found: list[dict], same: float) -> None:
    """Each LIM solution joins the entry at its place (kind ``LIM`` added) or is a new entry on its traced branch.

    A solution on no traced branch is left out (its check says so: found only by the homotopy).
    """
    for conf in found:
        q = free_coordinates(mech, conf)
        near = _entry_at(entries, q, same)
        if near is not None:
            if Kind.LIM not in near["kinds"]:
                near["kinds"].append(Kind.LIM)
            continue
        index = _branch_through(mech, search, in_value, conf)
        if index is None:
            continue
        x = flat_coordinates(mech, conf)
        path = search.paths[index - 1][0]
        nearest = min(path.points, key=lambda p: float(np.linalg.norm(free_coordinates(mech, p.coordinates) - q)))
        entries.append({"q": q, "x": x, "branches": [index], "kinds": [Kind.LIM], "vertex": None, "s": nearest.s,
                        "analysis": analyze(mech.with_coordinates(conf), tol=search.tol)})
