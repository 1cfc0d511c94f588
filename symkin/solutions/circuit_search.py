"""The circuit search of :func:`symkin.singularities`: traced branches, located branch points, half-branches.

Steps 2–4 of :mod:`symkin.solutions.circuits`: :class:`CircuitSearch` traces a branch through
every seed that no traced branch passes through (:func:`_on_path`), locates every branch point of
nullity 2 met on the way and traces every half-branch that leaves it; :func:`components` groups
the branches into circuits.
"""
from __future__ import annotations

import math
from dataclasses import replace
from typing import Callable

import numpy as np

from symkin.analysis.classification import analyze
from symkin.errors import NotConvergedError, SymkinError
from symkin.kinds import Kind
from symkin.model.mechanism import Mechanism
from symkin.curves.stepper import CurvePoint, point_at, tangent
from symkin.curves.events import TestFunction
from symkin.curves.locate import locate_sign_change, locate_singular_point
from symkin.paths.system import make_curve
from symkin.paths.trace import Path, trace
from symkin.curves.branches import HALF_BRANCH_RADIUS, half_branches
from symkin.solutions.frame_coordinates import CoordinateValue, flat_coordinates, format_value, free_coordinates, wrap
from symkin.solutions.seeding import cluster
from symkin.tolerances import Tolerances

__all__ = ["CircuitSearch", "MAX_ANGLE_STEP", "RETURNED", "components"]

#: largest input change per continuation step of a circuit (radians), so that the plot is smooth
MAX_ANGLE_STEP = math.radians(2.0)
#: stop reason of a branch cut where it passes a branch point a second time in the same direction
RETURNED = "returned"
#: a branch passes a branch point "in the same direction" again when the cosine of its two tangents there is at
#: least this: along the same half-branch (a tangent contact passed again), not along the other branch that
#: crosses there at an angle (the change-point four-bar's one branch, which crosses itself at its flat IM point)
RETURN_COSINE = 0.999


def _path_inputs(path: Path, offset: float) -> np.ndarray:
    """Inputs of the path's points in the model's frame, unwrapped along the path."""
    return np.array([p.input for p in path.points], float) + offset


def _crossings(path: Path, inputs: np.ndarray, value: float, kind: str):
    """Indices ``k`` where the path's input crosses ``value`` (mod 2π for angles) between points k and k + 1."""
    out = []
    for k in range(len(inputs) - 1):
        a, b = inputs[k], inputs[k + 1]
        if kind == "angle":
            lo, hi = min(a, b), max(a, b)
            turns = range(math.ceil((lo - value) / (2 * math.pi)), math.floor((hi - value) / (2 * math.pi)) + 1)
            for t in turns:
                out.append((k, value + 2 * math.pi * t))
        elif min(a, b) <= value <= max(a, b):
            out.append((k, value))
    return out


def _on_path(path: Path, inputs: np.ndarray, offset: float, value: float, q: np.ndarray, kind: str,
             scale: float, tol: Tolerances) -> bool:
    """Whether the path passes through the configuration ``q`` (free coordinates) of input ``value``."""
    curve = path.curve
    mech = path.mechanism
    for k, target in _crossings(path, inputs, value, kind):
        xa, xb = path.points[k].coordinates, path.points[k + 1].coordinates
        # cheap filter: the chord of a continuation step is within a step length of the curve
        qa, qb = free_coordinates(mech, xa), free_coordinates(mech, xb)
        if min(np.linalg.norm(qa - q), np.linalg.norm(qb - q)) > np.linalg.norm(qb - qa) + 1e-3 * scale:
            continue
        ya, yb = curve.y_of(qa), curve.y_of(qb)
        try:
            ta = tangent(curve, ya, yb - ya)
            tb = tangent(curve, yb, yb - ya)
            rel = target - offset
            test = TestFunction("input", lambda y, t, rel=rel: (curve.input_value(y) - rel) if kind != "angle"
                                else math.remainder(curve.input_value(y) - rel, 2 * math.pi))
            ev = locate_sign_change(curve, test, CurvePoint(ya, ta, 0.0), CurvePoint(yb, tb, 1.0))
        except NotConvergedError:
            continue
        if np.linalg.norm(curve.q_of(ev.y) - q) <= tol.same_configuration * scale:
            return True
    return False


# ---------------------------------------------------------------------- steps 2-4: the traced branches
class CircuitSearch:
    """The traced branches and located vertices of :func:`symkin.singularities` (steps 2–4 of
    :mod:`symkin.solutions.circuits`).

    Parameters
    ----------
    mech : Mechanism
        F = 1, at its configuration.
    tol : Tolerances
    in_value : CoordinateValue
        The input, measured from the model's configuration.
    kind : {"angle", "length"}
        The input's kind.
    turns : int
        Turns of an angle input (else 1) after which a trace stops.
    max_arclength : float or None
        Arclength limit of a trace (length scales; default 100 per turn).
    label, unit : str
        The input's label and the unit of the notes' angles.
    notes : list of str
        Appended to: what the search could not do (a branch that did not close...).
    progress : callable, optional
        Called with a description before each trace.

    Attributes
    ----------
    ``paths`` holds ``(Path, offset, inputs)`` per traced branch (inputs unwrapped, in the model's
    frame); ``vertices`` every branch point located exactly (:func:`symkin.curves.locate.locate_singular_point`): its
    coordinates, its analysis, its half-branch points and the branches through it; ``groups``
    lists branches known to be one circuit (a forward and a backward trace from one seed).
    """

    def __init__(self, mech: Mechanism, tol: Tolerances, in_value: CoordinateValue, kind: str, turns: int,
                 max_arclength: float | None, label: str, unit: str, notes: list[str],
                 progress: Callable[[str], None] | None = None):
        self.mech, self.tol, self.in_value, self.kind = mech, tol, in_value, kind
        self.progress = progress
        self.turns, self.max_arclength, self.label, self.unit, self.notes = turns, max_arclength, label, unit, notes
        self.scale = mech.length_scale
        self.curve = make_curve(mech)
        self.radius = _half_branch_radius(mech)
        self.paths: list[tuple[Path, float, np.ndarray]] = []
        self.vertices: list[dict] = []
        self.stations: list[dict] = []
        self.event_vertex: dict[tuple[int, int], int] = {}
        self.groups: list[list[int]] = []

    # ------------------------------------------------------------------ is a point on a traced branch?
    def covering(self, value: float, q: np.ndarray) -> int | None:
        """Index (from 1) of a traced branch through the configuration ``q`` of input ``value``, or None."""
        for index, (p, off, ins) in enumerate(self.paths, 1):
            if _on_path(p, ins, off, value, q, self.kind, self.scale, self.tol):
                return index
        return None

    # ------------------------------------------------------------------ tracing
    def trace_from(self, x: np.ndarray, direction: float, origin: str) -> int:
        """Trace the branch through the configuration ``x`` (all nodes) with the input moving along ``direction``."""
        stop = 2 * math.pi * self.turns if self.kind == "angle" else 1e6 * self.scale
        steps = int(math.ceil(stop / MAX_ANGLE_STEP)) if self.kind == "angle" else None
        arclength = self.max_arclength if self.max_arclength is not None else 100.0 * self.turns
        if self.progress is not None:
            self.progress(f"trace {len(self.paths) + 1} ({origin})")
        x = np.asarray(x, float).reshape(len(self.mech.nodes), self.mech.dim)
        path = trace(self.mech.with_coordinates(x), stop=math.copysign(stop, direction), steps=steps,
                     max_arclength=arclength, tol=self.tol)
        offset = self.in_value(x)
        self.paths.append((path, offset, _path_inputs(path, offset)))
        index = len(self.paths)
        self._vertices_on(index)
        path = self._cut_at_return(index)
        if path.stop_reason not in (Kind.CLOSED, "unreachable", RETURNED):
            why = path.message
            if any(k == index for k, _ in self.event_vertex):
                why += ("; it passed a branch point, where the continuation may go on along another branch "
                        "(every half-branch of a branch point is traced on its own)")
            self.notes.append(f"branch {index} ({origin}) did not close: {why}")
        return index

    def seed(self, value: float, conf: dict) -> None:
        """Trace the branch through a real assembly mode at input ``value`` unless a traced branch passes through it."""
        q = free_coordinates(self.mech, conf)
        if self.covering(value, q) is not None:
            return
        x = flat_coordinates(self.mech, conf)
        origin = f"seed at {self.label} = {format_value(value, self.kind, self.unit)}"
        first = self.trace_from(x, 1.0, origin)
        path = self.paths[first - 1][0]
        passed_vertex = any(k == first for k, _ in self.event_vertex)
        if path.stop_reason not in (Kind.CLOSED, "unreachable") and not passed_vertex:
            # a trace that neither closed nor met a vertex (it hit a limit) leaves the seed's other side
            second = self.trace_from(x, -1.0, origin + ", backward")
            self.groups.append([first, second])
        self.resolve()

    def critical_point(self, conf: dict) -> None:
        """A real solution of a square DKP system: its vertex (nullity 2) or its two half-branches, traced."""
        q = free_coordinates(self.mech, conf)
        y = self.curve.y_of(q)
        if self.located(q):
            return  # a traced branch passes through it (and on both sides of it: a regular point)
        if self.vertex_at(y) is None:
            x = self.curve.x_of(y)
            if self.singular(y):
                self.notes.append(f"the critical point at {self.label} = {format_value(self.in_value(x), self.kind, self.unit)}"
                                  " is a singular point of the curve that could not be located as a branch point "
                                  "of nullity 2: no trace starts from it")
            else:
                t = tangent(self.curve, y)
                halves = [point_at(self.curve, CurvePoint(y, sign * t, 0.0), self.radius) for sign in (1.0, -1.0)]
                halves = [h for h in halves if float(np.max(np.abs(self.curve.residual(h)))) <= 1e-10]
                self.stations.append({"y": y, "input": self.in_value(x), "halves": halves, "resolved": {},
                                      "paths": set(), "what": "critical point"})
        self.resolve()

    def located(self, q: np.ndarray) -> bool:
        """Whether a traced branch has located an event at the configuration ``q`` (a critical point).

        At a turning point of the input a path does not cross the point's input value, it
        touches it: the crossing test of :meth:`covering` cannot see it, the located event can.
        """
        radius = self.tol.same_configuration * self.scale
        return any(float(np.linalg.norm(free_coordinates(self.mech, e.coordinates) - q)) <= radius
                   for p, _, _ in self.paths for e in p.singular_events())

    def resolve(self) -> None:
        """Trace, outwards, every half-branch of every station that no traced branch passes through yet."""
        k = 0
        while k < len(self.vertices) + len(self.stations):
            v = self.vertices[k] if k < len(self.vertices) else self.stations[k - len(self.vertices)]
            for h, y in enumerate(v["halves"]):
                if h in v["resolved"]:
                    continue
                xh = self.curve.x_of(y)
                value = self.in_value(xh)
                index = self.covering(value, self.curve.q_of(y))
                if index is None:
                    t = tangent(self.curve, y)
                    if float(t @ (y - v["y"])) < 0:
                        t = -t
                    direction = 1.0 if self.curve.drive_rate(y, t) >= 0 else -1.0
                    what = f"half-branch {h + 1} of the {v['what']} at {self.label} = " \
                           f"{format_value(v['input'], self.kind, self.unit)}"
                    try:
                        index = self.trace_from(xh, direction, what)
                    except (SymkinError, NotConvergedError) as exc:
                        self.notes.append(f"{what} could not be traced: {exc}")
                v["resolved"][h] = index
                if index is not None:
                    v["paths"].add(index)
            k += 1

    # ------------------------------------------------------------------ vertices
    def _vertices_on(self, index: int) -> None:
        """Locate exactly every IM event of nullity 2 on branch ``index`` and register its vertex."""
        path = self.paths[index - 1][0]
        for e_index, e in enumerate(path.singular_events()):
            a = e.analysis
            if a is None or Kind.IM not in a.types or a.dof != self.mech.mobility_value + 1:
                continue
            k = self.vertex_at(self.curve.y_of(free_coordinates(self.mech, e.coordinates)))
            if k is not None:
                self.event_vertex[(index, e_index)] = k
                self.vertices[k]["paths"].add(index)

    def _cut_at_return(self, index: int) -> Path:
        """Branch ``index`` ended where it passes a branch point a second time in the same direction.

        From there on the continuation retraces what it has traced (the LIM branch of the double
        butterfly, round and round from a tangent contact): the rest is dropped, with its events,
        and the branch ends with ``stop_reason`` ``"returned"``.
        """
        path, offset, _ = self.paths[index - 1]
        events = path.singular_events()
        seen: dict[int, np.ndarray] = {}
        for e_index, e in enumerate(events):
            k = self.event_vertex.get((index, e_index))
            if k is None or e.t is None:
                continue
            if k in seen and _cosine(seen[k], e.t) >= RETURN_COSINE:
                cut = e.s
                kept = tuple(ev for ev in path.events if ev.s <= cut and ev.kind != Kind.END)
                message = (f"the path came back to the branch point at {self.label} = "
                           f"{format_value(self.vertices[k]['input'], self.kind, self.unit)} in the direction it passed "
                           "it before: from there on it retraces itself")
                path = replace(path, points=tuple(p for p in path.points if p.s <= cut), events=kept,
                               stop_reason=RETURNED, message=message)
                for key in [key for key in self.event_vertex if key[0] == index and key[1] >= len(kept)]:
                    del self.event_vertex[key]
                self.paths[index - 1] = (path, offset, _path_inputs(path, offset))
                break
            seen.setdefault(k, e.t)
        return path

    def singular(self, y: np.ndarray) -> bool:
        """Whether the curve's Jacobian has lost a rank at ``y`` (or is near it: relative ``√rank``)."""
        sv = np.linalg.svd(self.curve.jacobian(y), compute_uv=False)
        return sv.size >= y.size - 1 and sv[y.size - 2] <= math.sqrt(self.tol.rank) * max(sv[0], 1.0)

    def vertex_at(self, y0: np.ndarray) -> int | None:
        """The vertex (branch point of nullity 2) located from ``y0``, registered if new; None when there is none."""
        if not self.singular(y0):
            return None  # a regular point of the curve (a DKP configuration)
        bp = locate_singular_point(self.curve, y0)
        if not bp.converged or bp.residual > 1e-12:
            return None
        q = self.curve.q_of(bp.y)
        for k, v in enumerate(self.vertices):
            if np.linalg.norm(v["q"] - q) <= self.tol.same_configuration * self.scale:
                return k
        x = self.curve.x_of(bp.y)
        analysis = analyze(self.mech.with_coordinates(x), tol=self.tol)
        if analysis.dof != self.mech.mobility_value + 1 or Kind.IM not in analysis.types:
            return None
        halves = half_branches(self.curve, bp.y, radius=self.radius, rank=self.tol.rank)
        if halves is None:
            self.notes.append(f"the branch point at {self.label} = {format_value(self.in_value(x), self.kind, self.unit)} "
                              "has a nullity other than 2: its branches are not enumerated")
        self.vertices.append({"y": bp.y, "q": q, "x": x, "input": self.in_value(x), "analysis": analysis,
                              "deflations": bp.deflations, "halves": halves or [], "resolved": {},
                              "paths": set(), "what": "branch point"})
        return len(self.vertices) - 1

    def vertex_of(self, q: np.ndarray) -> int | None:
        """The vertex within ``√same_configuration`` of ``q`` (an IM event whose own refinement failed), or None."""
        radius = math.sqrt(self.tol.same_configuration) * self.scale
        near = [(float(np.linalg.norm(v["q"] - q)), k) for k, v in enumerate(self.vertices)]
        best = min(near, default=(math.inf, None))
        return best[1] if best[0] <= radius else None

    def critical_values(self) -> list[float]:
        """Input values (model frame, wrapped) of every traced DKP-input event and vertex, clustered."""
        values = [v["input"] for v in self.vertices]
        for p, _, _ in self.paths:
            values += [self.in_value(e.coordinates) for e in p.singular_events()
                       if e.analysis is not None and Kind.DKP_INPUT in e.analysis.types]
        return cluster([wrap(v, self.kind) for v in values], self.tol.same_configuration)


def _cosine(a: np.ndarray, b: np.ndarray) -> float:
    return float(a @ b) / max(float(np.linalg.norm(a) * np.linalg.norm(b)), 1e-300)


def _half_branch_radius(mech: Mechanism) -> float:
    """Distance (length scales) of the half-branch points from their vertex: :data:`HALF_BRANCH_RADIUS`,
    or a tenth of the shortest bar when that is smaller (the local picture must hold on the circle)."""
    x = dict(mech.nodes)
    bars = [float(np.linalg.norm(np.subtract(x[a], x[b]))) for _, ns in mech.links
            for i, a in enumerate(ns) for b in ns[i + 1:]]
    shortest = min((b for b in bars if b > 0.0), default=mech.length_scale)
    return min(HALF_BRANCH_RADIUS, 0.1 * shortest / mech.length_scale)


def components(n: int, groups: list[list[int]]) -> dict[int, int]:
    """Branch (1..n) → circuit number (from 1, in order of the first branch): branches in one group are one circuit.

    Parameters
    ----------
    n : int
        The number of branches.
    groups : list of list of int
        Branches known to be on one circuit (those through one configuration, a forward and
        a backward trace from one seed).

    Returns
    -------
    dict
        Branch → circuit: the connected components of the groups' union.

    Examples
    --------
    >>> components(3, [[1], [2, 3]])
    {1: 1, 2: 2, 3: 2}
    """
    parent = list(range(n + 1))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for g in groups:
        for other in g[1:]:
            parent[find(other)] = find(g[0])
    numbers: dict[int, int] = {}
    out = {}
    for i in range(1, n + 1):
        out[i] = numbers.setdefault(find(i), len(numbers) + 1)
    return out
