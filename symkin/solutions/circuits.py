"""Every singular configuration of a 1-DOF mechanism (``symkin.singularities``, issue 9 §2).

The configuration curve of a 1-DOF mechanism splits into *circuits* (connected smooth
components: the two assembly modes of a Grashof crank-rocker are two circuits, a
non-Grashof four-bar has one).  The paper's procedure finds the singular configurations
on the paths it simulates; this module makes the search global:

1. **Critical points.**  The square system "closure + DKP-input test function = 0"
   (:mod:`symkin.solutions.dkp_system`) is solved by homotopy continuation: its real
   solutions are every configuration where the input is stationary along the curve
   (DKP-input, paper §III) and every branch point (IM).  The same is done for the
   output when the model has one scalar output (DKP-output and IM).
2. **Seeds.**  :func:`symkin.solve_all` at one input value (the middle of the interval
   between critical values that holds the model's input), and every real solution of step 1:
   a circuit on which the input turns fully crosses every input value; on any other circuit
   the input sweeps an interval whose two ends are critical points, solutions of step 1.
3. **Branches.**  Each seed not yet on a traced branch is traced by :func:`symkin.trace` (the
   existing pseudo-arclength continuation with its event location) until the path closes
   on itself; a seed is on a traced branch when the path passes through it: the crossing
   of its input value is located on the path (:func:`~symkin.paths.events.locate_sign_change`)
   and is within :attr:`Tolerances.same_configuration` (units of the length scale) of it.
   A critical point seeds the two half-branches that leave it (curve points
   :data:`~symkin.paths.vertex.HALF_BRANCH_RADIUS` away, traced outwards).
   **Branch points.**  Every IM event of nullity 2 that a trace locates is located again,
   to rounding, by :func:`~symkin.paths.vertex.locate_branch_point` (deflated Newton: also
   where two branches are *tangent*, as at the double butterfly's contacts with its LIM
   branch, where the trace's own event is 1e-6 to 1e-3 off), and every half-branch that
   leaves it (:func:`~symkin.paths.vertex.half_branches`: 4 for two branches) is traced
   outwards unless a traced branch already passes through it.  At a tangent contact the
   continuation may go on along either branch; the half-branches make the search
   complete whichever it took, and the answer independent of it.
4. **Singular configurations and circuits.**  Every event that the traces locate (DKP-input,
   DKP-output, IM), classified by :func:`symkin.analyze`; one configuration met by several
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
   (``agree = False``, the unmatched configurations) and a warning, never silent.

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
branch points where the nullity exceeds 2 (located, reported, their branches not enumerated).
"""
from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from symkin.analysis.classification import Analysis, analyze
from symkin.errors import NotConvergedError, SymkinError
from symkin.model.mechanism import Mechanism
from symkin.paths.continuation import CurvePoint, point_at, tangent
from symkin.numeric.coordinates import InputCoordinate, input_coordinates
from symkin.paths.events import TestFunction, locate_sign_change
from symkin.paths.system import make_curve
from symkin.paths.trace import Path, trace
from symkin.paths.vertex import HALF_BRANCH_RADIUS, half_branches, locate_branch_point
from symkin.solutions.dkp_system import DkpSystem, dkp_system, polish
from symkin.solutions.homotopy import require_solver, total_degree, track
from symkin.solutions.solve_all import NEWTON_ACCEPT, solve_all
from symkin.solutions.system import closure_system
from symkin.tolerances import Tolerances

__all__ = ["Branch", "Circuit", "CrossCheck", "SingularConfiguration", "Singularities", "SingularitiesWarning",
           "singularities"]

#: largest input change per continuation step of a circuit (radians), so that the plot is smooth
MAX_ANGLE_STEP = math.radians(2.0)
#: default ``max_paths`` of one square DKP system: the Watt six-bar's track 64 each (a few seconds), the
#: double butterfly's 768 (a degree-6 factor of 2295 terms: not finished after 19 min; its crank block, a
#: constant on the curve, is dropped by :func:`~symkin.solutions.dkp_system.dkp_system`)
MAX_PATHS = 600
#: at most this many rounds of seeds placed between the traced critical values (no square DKP-input system)
MAX_SEED_ROUNDS = 8
#: without the square DKP-input system, no two consecutive samples of an angle input are farther apart than this
MAX_SAMPLE_GAP = math.radians(30.0)
#: stop reason of a branch cut where it passes a branch point a second time in the same direction
RETURNED = "returned"
#: a homotopy endpoint with ``max |Im v|`` above this (length scales) is complex
NEAR_REAL = 1e-4


class SingularitiesWarning(UserWarning):
    """The traced circuits and the square DKP systems do not give the same singular configurations."""


@dataclass(frozen=True)
class SingularConfiguration:
    """One singular configuration on the circuits.

    Attributes
    ----------
    configuration : dict
        Node → coordinates (model units).
    types : tuple of str
        :func:`symkin.analyze`'s types at the configuration (``IM``, ``DKP-input``, ``DKP-output``, ``LIM``...).
    dof : int
        Instantaneous DOF ``L`` (``analyze``).
    circuit : int
        The circuit (connected component, numbered from 1) it lies on.
    branches : tuple of int
        The traced branches (numbered from 1 over all circuits) that pass through it (two
        at a branch point where two traced branches cross; one branch that crosses itself
        there, as at the change point of a four-bar, is located once).
    input, output : float
        The input and output coordinates, measured from the model's configuration
        (angles in ``unit``, in (−180°, 180°] / (−π, π]; lengths in model units); output None without one.
    kinds : tuple of str
        The trace's test functions that located it.
    arclength : float
        Its arclength along the first branch that located it (for a plot without an output).
    """

    configuration: dict
    types: tuple
    dof: int
    circuit: int
    branches: tuple
    input: float
    output: float | None
    kinds: tuple
    arclength: float = field(default=0.0, compare=False)
    analysis: Analysis | None = field(default=None, compare=False, repr=False)

    def to_dict(self) -> dict:
        return {"configuration": {n: list(x) for n, x in self.configuration.items()}, "types": list(self.types),
                "circuit": self.circuit, "input": self.input, "output": self.output, "dof": self.dof,
                "branches": list(self.branches), "kinds": list(self.kinds)}


@dataclass(frozen=True)
class Branch:
    """One traced loop: its seed, its points in input–output space and how its trace ended.

    ``inputs`` / ``outputs`` are unwrapped along the trace (radians or model units, measured from
    the model's configuration); ``full_turn`` says that the input takes every value (a crank);
    ``closed`` that the trace closed on itself, or came back to a branch point it had passed in
    the same direction (``stop_reason`` ``"returned"``: from there on it would retrace itself).
    """

    index: int
    seed: dict
    inputs: np.ndarray = field(repr=False)
    outputs: np.ndarray | None = field(repr=False)
    closed: bool
    full_turn: bool
    stop_reason: str
    path: Path | None = field(default=None, repr=False, compare=False)

    def to_dict(self, conv: float) -> dict:
        return {"branch": self.index, "closed": self.closed, "full_turn": self.full_turn,
                "stop_reason": self.stop_reason, "points": int(len(self.inputs)),
                "input_range": [float(np.min(self.inputs)) * conv, float(np.max(self.inputs)) * conv],
                "seed": {n: list(x) for n, x in self.seed.items()}}


@dataclass(frozen=True)
class Circuit:
    """A connected component of the configuration curve: its traced branches (usually one).

    Branches that share a configuration (a branch point, IM) are one circuit.
    """

    index: int
    branches: tuple[Branch, ...]

    @property
    def closed(self) -> bool:
        return all(b.closed for b in self.branches)

    @property
    def full_turn(self) -> bool:
        return any(b.full_turn for b in self.branches)

    def to_dict(self, conv: float) -> dict:
        return {"circuit": self.index, "closed": self.closed, "full_turn": self.full_turn,
                "branches": [b.to_dict(conv) for b in self.branches]}


@dataclass(frozen=True)
class CrossCheck:
    """The square system ``closure + D = 0`` of one parameter against the traced configurations.

    ``homotopy`` counts its distinct real solutions, ``traced`` the traced configurations whose
    kinds it detects (``kind`` or IM); ``unmatched_homotopy`` / ``unmatched_traced`` the
    configurations found by one side only.  ``paths`` is the number of homotopy paths (tracked,
    or that would have been tracked when the system was solved exactly or not at all).
    ``solver`` is ``"bertini"`` (the homotopy) or ``"msolve"`` (beyond ``max_paths``: the exact
    system of :mod:`symkin.solutions.exact`, Gröbner basis and certified real roots);
    ``skipped`` says why neither solved it.
    """

    kind: str
    label: str
    homotopy: int
    traced: int
    matched: int
    paths: int
    degree: int
    unmatched_homotopy: tuple = ()
    unmatched_traced: tuple = ()
    seconds: float = 0.0
    skipped: str = ""
    solver: str = "bertini"

    @property
    def agree(self) -> bool | None:
        """Both sides found the same configurations; None when the square system was not solved (``skipped``)."""
        if self.skipped:
            return None
        return not self.unmatched_homotopy and not self.unmatched_traced

    def to_dict(self) -> dict:
        return {"kind": self.kind, "label": self.label, "homotopy": self.homotopy, "traced": self.traced,
                "matched": self.matched, "agree": self.agree, "paths": self.paths, "degree": self.degree,
                "skipped": self.skipped, "solver": self.solver,
                "unmatched_homotopy": [{n: list(x) for n, x in c.items()} for c in self.unmatched_homotopy],
                "unmatched_traced": [{n: list(x) for n, x in c.items()} for c in self.unmatched_traced],
                "seconds": self.seconds}


@dataclass(frozen=True)
class Singularities:
    """Result of :func:`singularities`: the circuits and every singular configuration on them."""

    mechanism: Mechanism = field(repr=False)
    input: str
    output: str | None
    unit: str
    kind: str
    circuits: tuple[Circuit, ...]
    singularities: tuple[SingularConfiguration, ...]
    checks: tuple[CrossCheck, ...]
    samples: tuple[float, ...]
    seeds: int
    warnings: tuple[str, ...]
    seconds: float

    @property
    def agree(self) -> bool | None:
        """The traced circuits and every square DKP system give the same configurations.

        False when one check disagrees; None when none disagrees but a square system was not
        solved (:attr:`CrossCheck.skipped`): the traced answer is then not cross-checked.
        """
        values = [c.agree for c in self.checks]
        if False in values:
            return False
        return None if None in values else True

    def to_dict(self) -> dict:
        """``{"circuits": n, "singularities": [...], ...}``: the ``--json`` of ``symkin singularities``.

        Each singularity's ``input`` / ``output`` are relative to the model, in (−180°, 180°];
        ``input_absolute`` / ``output_absolute`` the absolute angles in [0°, 360°) (None for a
        length or a spatial rotation), in ``unit``: :func:`symkin.paths.trace.relative_angle`.
        """
        from symkin.paths.trace import CoordinateValues

        conv = self._conv()
        labels = [self.input] + ([] if self.output is None else [self.output])
        values = CoordinateValues(self.mechanism, labels)
        singular = []
        for s in self.singularities:  # the absolute angles too, as every command gives them
            at = values(s.configuration, self.unit)
            singular.append({**s.to_dict(), "input_absolute": at[self.input]["absolute"],
                             **({} if self.output is None else {"output_absolute": at[self.output]["absolute"]})})
        return {"mechanism": self.mechanism.name, "circuits": len(self.circuits),
                "singularities": singular,
                "input_label": self.input, "output_label": self.output, "unit": self.unit,
                "agree": self.agree, "cross_check": [c.to_dict() for c in self.checks],
                "circuit_list": [c.to_dict(conv) for c in self.circuits],
                "samples": [v * conv for v in self.samples], "seeds": self.seeds,
                "warnings": list(self.warnings), "seconds": self.seconds}

    def _conv(self) -> float:
        return 180.0 / math.pi if (self.unit == "deg" and self.kind == "angle") else 1.0


# ---------------------------------------------------------------------- coordinates in the model's frame
class _Values:
    """A coordinate (input or output) measured from the *model's* configuration, at any configuration."""

    def __init__(self, mech: Mechanism, c: InputCoordinate):
        import casadi as ca

        x = ca.SX.sym("x", len(mech.nodes) * mech.dim)
        x0 = np.array([p for _, p in mech.nodes], float)
        self.c, self.kind = c, c.kind
        self.f = ca.Function("value", [x], [c.expression(mech, x, x0)])

    def __call__(self, x: np.ndarray) -> float:
        return float(self.f(np.asarray(x, float).ravel()))


def _wrap(v: float, kind: str) -> float:
    return math.remainder(v, 2 * math.pi) if kind == "angle" else v


def _free(mech: Mechanism, configuration) -> np.ndarray:
    """Free nodal coordinates (flat) of a configuration given as a dict or an (n, dim) array."""
    if isinstance(configuration, dict):
        return np.concatenate([np.asarray(configuration[n], float) for n in mech.free_nodes])
    idx = mech.node_index()
    x = np.asarray(configuration, float).reshape(len(mech.nodes), mech.dim)
    return np.concatenate([x[idx[n]] for n in mech.free_nodes])


def _as_dict(mech: Mechanism, x: np.ndarray) -> dict:
    x = np.asarray(x, float).reshape(len(mech.nodes), mech.dim)
    return {n: [float(v) for v in x[k]] for k, n in enumerate(mech.node_names)}


def _output_coordinate(mech: Mechanism) -> InputCoordinate | None:
    """The model's output as one scalar coordinate, or None (no output, a twist, several scalars)."""
    if not mech.outputs:
        return None
    try:
        coords = input_coordinates(mech, mech.outputs)
    except SymkinError:
        return None
    return coords[0] if len(coords) == 1 else None


# ---------------------------------------------------------------------- step 1: the square DKP systems
def _real_roots(system: DkpSystem, tol: Tolerances) -> tuple[list[dict], int]:
    """Distinct real solutions of the square systems (configurations) and the number of paths tracked.

    One homotopy per factor of ``D`` (:meth:`DkpSystem.systems`); an endpoint is kept when
    ``max |Im v| <= NEAR_REAL`` and Gauss–Newton on the real system from its real part reaches a
    residual ``<= NEWTON_ACCEPT`` without moving more than ``NEAR_REAL``.
    """
    closure = system.closure
    found: list[np.ndarray] = []
    paths = 0
    for equations in system.systems():
        ends = track(list(equations), list(system.unknowns), endgame="power_series")
        paths += int(len(ends))
        for v in ends:
            h = v[0]
            if abs(h) <= 1e-10 * max(1.0, float(np.max(np.abs(v)))):
                continue  # at infinity
            w = v[1:] / h
            if not np.all(np.isfinite(w)) or float(np.max(np.abs(w.imag), initial=0.0)) > NEAR_REAL:
                continue
            vr, res = polish(equations, system.unknowns, np.array(w.real, float))
            if res > NEWTON_ACCEPT or float(np.max(np.abs(vr - w.real))) > NEAR_REAL:
                continue  # a complex solution close to the real space, or a failed polish
            u = closure.recover(vr)
            if all(float(np.linalg.norm(u - f)) > tol.same_configuration for f in found):
                found.append(u)
    return [closure.coordinates(u) for u in found], paths


# ---------------------------------------------------------------------- step 3: is a seed on a traced path?
def _points(path: Path, offset: float) -> np.ndarray:
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
        qa, qb = _free(mech, xa), _free(mech, xb)
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
class _Search:
    """The traced branches and located vertices of :func:`singularities` (steps 2–4 of the module docstring).

    ``paths`` holds ``(Path, offset, inputs)`` per traced branch (inputs unwrapped, in the model's
    frame); ``vertices`` every branch point located exactly (:mod:`symkin.paths.vertex`): its
    coordinates, its analysis, its half-branch points and the branches through it; ``groups``
    lists branches known to be one circuit (a forward and a backward trace from one seed).
    """

    def __init__(self, mech: Mechanism, tol: Tolerances, in_value: _Values, kind: str, turns: int,
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
        self.paths.append((path, offset, _points(path, offset)))
        index = len(self.paths)
        self._vertices_on(index)
        path = self._cut_at_return(index)
        if path.stop_reason not in ("closed", "unreachable", RETURNED):
            why = path.message
            if any(k == index for k, _ in self.event_vertex):
                why += ("; it passed a branch point, where the continuation may go on along another branch "
                        "(every half-branch of a branch point is traced on its own)")
            self.notes.append(f"branch {index} ({origin}) did not close: {why}")
        return index

    def seed(self, value: float, conf: dict) -> None:
        """Trace the branch through a real assembly mode at input ``value`` unless a traced branch passes through it."""
        q = _free(self.mech, conf)
        if self.covering(value, q) is not None:
            return
        x = _flat(self.mech, conf)
        origin = f"seed at {self.label} = {_fmt(value, self.kind, self.unit)}"
        first = self.trace_from(x, 1.0, origin)
        path = self.paths[first - 1][0]
        passed_vertex = any(k == first for k, _ in self.event_vertex)
        if path.stop_reason not in ("closed", "unreachable") and not passed_vertex:
            # a trace that neither closed nor met a vertex (it hit a limit) leaves the seed's other side
            second = self.trace_from(x, -1.0, origin + ", backward")
            self.groups.append([first, second])
        self.resolve()

    def critical_point(self, conf: dict) -> None:
        """A real solution of a square DKP system: its vertex (nullity 2) or its two half-branches, traced."""
        q = _free(self.mech, conf)
        y = self.curve.y_of(q)
        if self.located(q):
            return  # a traced branch passes through it (and on both sides of it: a regular point)
        if self.vertex_at(y) is None:
            x = self.curve.x_of(y)
            if self.singular(y):
                self.notes.append(f"the critical point at {self.label} = {_fmt(self.in_value(x), self.kind, self.unit)}"
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
        return any(float(np.linalg.norm(_free(self.mech, e.coordinates) - q)) <= radius
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
                           f"{_fmt(v['input'], self.kind, self.unit)}"
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
            if a is None or "IM" not in a.types or a.dof != self.mech.mobility_value + 1:
                continue
            k = self.vertex_at(self.curve.y_of(_free(self.mech, e.coordinates)))
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
            if k in seen and float(seen[k] @ e.t) > 0:
                cut = e.s
                kept = tuple(ev for ev in path.events if ev.s <= cut and ev.kind != "end")
                message = (f"the path came back to the branch point at {self.label} = "
                           f"{_fmt(self.vertices[k]['input'], self.kind, self.unit)} in the direction it passed "
                           "it before: from there on it retraces itself")
                path = replace(path, points=tuple(p for p in path.points if p.s <= cut), events=kept,
                               stop_reason=RETURNED, message=message)
                for key in [key for key in self.event_vertex if key[0] == index and key[1] >= len(kept)]:
                    del self.event_vertex[key]
                self.paths[index - 1] = (path, offset, _points(path, offset))
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
        bp = locate_branch_point(self.curve, y0)
        if not bp.converged or bp.residual > 1e-12:
            return None
        q = self.curve.q_of(bp.y)
        for k, v in enumerate(self.vertices):
            if np.linalg.norm(v["q"] - q) <= self.tol.same_configuration * self.scale:
                return k
        x = self.curve.x_of(bp.y)
        analysis = analyze(self.mech.with_coordinates(x), tol=self.tol)
        if analysis.dof != self.mech.mobility_value + 1 or "IM" not in analysis.types:
            return None
        halves = half_branches(self.curve, bp.y, radius=self.radius, rank=self.tol.rank)
        if halves is None:
            self.notes.append(f"the branch point at {self.label} = {_fmt(self.in_value(x), self.kind, self.unit)} "
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
                       if e.analysis is not None and "DKP-input" in e.analysis.types]
        return _cluster([_wrap(v, self.kind) for v in values], self.tol.same_configuration)


def _half_branch_radius(mech: Mechanism) -> float:
    """Distance (length scales) of the half-branch points from their vertex: :data:`HALF_BRANCH_RADIUS`,
    or a tenth of the shortest bar when that is smaller (the local picture must hold on the circle)."""
    x = dict(mech.nodes)
    bars = [float(np.linalg.norm(np.subtract(x[a], x[b]))) for _, ns in mech.links
            for i, a in enumerate(ns) for b in ns[i + 1:]]
    shortest = min((b for b in bars if b > 0.0), default=mech.length_scale)
    return min(HALF_BRANCH_RADIUS, 0.1 * shortest / mech.length_scale)


# ---------------------------------------------------------------------- the entry point
def singularities(mech: Mechanism, *, tol: float | Tolerances | None = None, unit: str = "rad",
                  max_turns: int = 4, max_arclength: float | None = None, max_paths: int = MAX_PATHS,
                  seed: int = 0, samples: list[float] | None = None,
                  progress: Callable[[str], None] | None = None) -> Singularities:
    """Every circuit of a 1-DOF mechanism and every DKP-input, DKP-output and IM configuration on it.

    See the module docstring for the method.  Needs the optional extra ``symkin[global]``
    (Bertini 2) for :func:`symkin.solve_all` and the square DKP systems.

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
    output = _output_coordinate(mech)
    require_solver()
    scale = mech.length_scale
    kind = drive.kind
    in_value = _Values(mech, drive)
    out_value = _Values(mech, output) if output is not None else None
    notes: list[str] = []

    # 1. critical points of the input (and of the output) from the square DKP systems
    closure = closure_system(mech, tolerances)
    systems = [("DKP-input", drive)] + ([("DKP-output", output)] if output is not None else [])
    roots: dict[str, tuple[list[dict], int, int, float]] = {}
    skipped: dict[str, tuple[int, int, float, str]] = {}
    solvers: dict[str, str] = {}
    for name, c in systems:
        t0 = time.perf_counter()
        if progress is not None:
            progress(f"square {name} system")
        system = dkp_system(mech, c, tolerances, closure=closure, seed=seed)
        paths = sum(total_degree(list(e), list(system.unknowns)) for e in system.systems())
        if paths > max_paths:
            by_msolve = _exact_roots(mech, c)
            if isinstance(by_msolve, list):
                roots[name] = (by_msolve, paths, system.degree, time.perf_counter() - t0)
                solvers[name] = "msolve"
                continue
            why = f"{paths} paths > max_paths = {max_paths}; exact: {by_msolve}"
            skipped[name] = (paths, system.degree, time.perf_counter() - t0, why)
            msg = (f"{mech.name}: the square {name} system (closure + det = 0, degree {system.degree}) needs "
                   f"{paths} homotopy paths, more than max_paths = {max_paths} (raise it with --max-paths), and "
                   f"its exact solution is not available ({by_msolve}): not solved, so the traced {name}/IM "
                   "configurations are NOT cross-checked"
                   + ("" if name != "DKP-input" or samples is not None else
                      ", and the seeds are placed in rounds between the traced critical values instead (module "
                      "docstring, 'Without the square system')"))
            notes.append(msg)
            warnings.warn(msg, SingularitiesWarning, stacklevel=2)
            continue
        found, tracked = _real_roots(system, tolerances)
        if system.squared:
            found = [c_ for c_ in found if _is_singular(mech, c_, name, tolerances)]
        roots[name] = (found, tracked, system.degree, time.perf_counter() - t0)

    # 2-3. seeds (solve_all between consecutive critical input values), the branches through them and
    # through every half-branch of every vertex
    search = _Search(mech, tolerances, in_value, kind, max_turns if kind == "angle" else 1, max_arclength,
                     drive.label, unit, notes, progress)
    exact = "DKP-input" in roots
    sampled: list[float] = []
    seeds = 0

    def sample(v: float) -> None:
        nonlocal seeds
        sampled.append(v)
        if progress is not None:
            progress(f"solve_all at {drive.label} = {_fmt(v, kind, unit)}")
        sol = solve_all(mech, {drive.label: v}, unit="rad", tol=tolerances, seed=seed)
        seeds += len(sol.solutions)
        for s_ in sol.solutions:
            search.seed(v, s_.configuration)

    to_input = math.pi / 180.0 if (unit == "deg" and kind == "angle") else 1.0
    if samples is not None:
        for v in samples:
            sample(_wrap(float(v) * to_input, kind))
    if exact:
        # every circuit on which the input turns fully crosses one input value; every other one has
        # its extreme input values among the square systems' solutions: trace from those
        critical = _cluster([_wrap(in_value(_flat(mech, c)), kind) for c in roots["DKP-input"][0]], 1e-12)
        if samples is None:
            sample(_sample_near_zero(critical, kind))
        for name in roots:
            for conf in roots[name][0]:
                search.critical_point(conf)
    elif samples is None:
        critical: list[float] = []
        for _ in range(MAX_SEED_ROUNDS):
            todo = _uncovered(critical, sampled, kind, _gap(critical, kind))
            if not todo:
                break
            for v in todo:
                sample(v)
            critical = search.critical_values()
        else:
            if _uncovered(critical, sampled, kind, _gap(critical, kind)):
                notes.append(f"the seeds did not settle after {MAX_SEED_ROUNDS} rounds of input values")

    # 4. singular configurations on the branches, merged; branches through one configuration are one circuit
    entries: list[dict] = [{"q": v["q"], "x": v["x"], "branches": sorted(v["paths"]), "kinds": [],
                            "analysis": v["analysis"], "s": 0.0, "vertex": k} for k, v in enumerate(search.vertices)]
    for index, (path, _, _) in enumerate(search.paths, 1):
        for e_index, e in enumerate(path.singular_events()):
            q = _free(mech, e.coordinates)
            k = search.event_vertex.get((index, e_index))
            if k is None and e.analysis is not None and "IM" in e.analysis.types:
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
            item["kinds"] = ["IM"]  # a vertex met only by the traces of its half-branches
    component = _components(len(search.paths), [item["branches"] for item in entries] + search.groups)
    conv = 180.0 / math.pi if (unit == "deg" and kind == "angle") else 1.0
    out_conv = 180.0 / math.pi if (output is not None and unit == "deg" and output.kind == "angle") else 1.0
    result_sing = []
    for item in sorted(entries, key=lambda it: (component[it["branches"][0]], _wrap(in_value(it["x"]), kind))):
        a = item["analysis"]
        result_sing.append(SingularConfiguration(
            _as_dict(mech, item["x"]), tuple(a.types) if a else (), a.dof if a else -1,
            component[item["branches"][0]], tuple(sorted(set(item["branches"]))),
            _wrap(in_value(item["x"]), kind) * conv,
            None if out_value is None else _wrap(out_value(item["x"]), output.kind) * out_conv,
            tuple(item["kinds"]), item["s"], a))

    # 5. cross-check
    checks = []
    for name, c in systems:
        traced = [s for s in result_sing if name in s.kinds or "IM" in s.kinds]
        if name in skipped:
            paths, degree, seconds, why = skipped[name]
            checks.append(CrossCheck(name, c.label, 0, len(traced), 0, paths, degree, (), (), seconds, skipped=why))
            continue
        found, tracked, degree, seconds = roots[name]
        checks.append(replace(_compare(mech, name, c.label, found, traced, tracked, degree, seconds, scale, tolerances),
                              solver=solvers.get(name, "bertini")))
    for ch in checks:
        if ch.agree is False:
            msg = (f"{mech.name}: the square {ch.kind} system has {ch.homotopy} real solution(s), the traced "
                   f"circuits {ch.traced} {ch.kind}/IM configuration(s); {len(ch.unmatched_homotopy)} found only by "
                   f"the homotopy, {len(ch.unmatched_traced)} only by the traces")
            notes.append(msg)
            warnings.warn(msg, SingularitiesWarning, stacklevel=2)

    branches = []
    for index, (path, offset, ins) in enumerate(search.paths, 1):
        outs = None if out_value is None else np.unwrap([out_value(p.coordinates) for p in path.points]) \
            if output.kind == "angle" else np.array([out_value(p.coordinates) for p in path.points])
        span = float(np.max(ins) - np.min(ins)) if ins.size else 0.0
        closed = path.stop_reason in ("closed", "unreachable", RETURNED)
        branches.append(Branch(index, _as_dict(mech, path.points[0].coordinates), ins, outs, closed,
                               kind == "angle" and span >= 2 * math.pi - 1e-9, path.stop_reason, path))
    circuit_objs = [Circuit(k, tuple(b for b in branches if component[b.index] == k))
                    for k in sorted(set(component.values()))]
    return Singularities(mech, drive.label, None if output is None else output.label, unit, kind,
                         tuple(circuit_objs), tuple(result_sing), tuple(checks), tuple(sampled), seeds,
                         tuple(notes), time.perf_counter() - start)


def _components(n: int, groups: list[list[int]]) -> dict[int, int]:
    """Branch (1..n) → circuit number (from 1, in order of the first branch): branches in one group are one circuit.

    >>> _components(3, [[1], [2, 3]])
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


def _flat(mech: Mechanism, conf: dict) -> np.ndarray:
    return np.concatenate([np.asarray(conf[n], float) for n in mech.node_names])


def _fmt(value: float, kind: str, unit: str) -> str:
    if kind != "angle":
        return f"{value:.10g}"
    return f"{math.degrees(value):.10g}°" if unit == "deg" else f"{value:.10g} rad"


def _gap(critical: list[float], kind: str) -> float:
    """Widest gap between samples without the square system: :data:`MAX_SAMPLE_GAP` for angles, 1/12 of the critical range for lengths."""
    if kind == "angle":
        return MAX_SAMPLE_GAP
    return (max(critical) - min(critical)) / 12.0 if len(critical) >= 2 else math.inf


def _sample_near_zero(critical: list[float], kind: str) -> float:
    """The middle of the interval between consecutive critical values that holds the model's input 0.

    >>> _sample_near_zero([], "angle"), _sample_near_zero([-1.0, 3.0], "length")
    (0.0, 1.0)
    >>> round(_sample_near_zero([1.0, 2.0], "angle"), 6)  # the interval (2, 1 + 2π) wraps round through 0
    -1.641593
    """
    if not critical:
        return 0.0
    if kind != "angle":
        inside = [0.5 * (a + b) for a, b in zip(critical, critical[1:]) if a < 0.0 < b]
        return inside[0] if inside else 0.0
    bounds = list(zip(critical, critical[1:])) + [(critical[-1], critical[0] + 2 * math.pi)]
    for a, b in bounds:
        if a < a + (0.0 - a) % (2 * math.pi) < b:
            return _wrap(0.5 * (a + b), kind)
    return _wrap(critical[0] + math.pi, kind)


def _samples(critical: list[float], kind: str) -> list[float]:
    """Input values midway between consecutive critical values (the model's value 0 when there is none)."""
    if not critical:
        return [0.0]
    if len(critical) == 1:
        return [_wrap(critical[0] + math.pi, kind)] if kind == "angle" else [0.0]
    mids = [0.5 * (a + b) for a, b in zip(critical, critical[1:])]
    if kind == "angle":
        mids.append(_wrap(0.5 * (critical[-1] + critical[0] + 2 * math.pi), kind))
    return mids


def _cluster(values: list[float], radius: float) -> list[float]:
    """Sorted values with runs of neighbours closer than ``radius`` replaced by their mean.

    >>> _cluster([0.0, 1.0, 1.0625, 3.0], 0.1)
    [0.0, 1.03125, 3.0]
    """
    groups: list[list[float]] = []
    for v in sorted(values):
        if groups and v - groups[-1][-1] <= radius:
            groups[-1].append(v)
        else:
            groups.append([v])
    return [sum(g) / len(g) for g in groups]


def _uncovered(critical: list[float], samples: list[float], kind: str, gap: float = math.inf) -> list[float]:
    """Input values still to sample: the middle of every interval between consecutive critical values
    that holds no sample yet, and of every gap between consecutive critical values and samples
    wider than ``gap``.

    Angles are taken mod 2π (the last interval wraps round); the first sample is 0 (the model's
    input).  A length input's circuits are bounded, each has its least and greatest value among
    the critical ones: only the intervals between them count.

    >>> _uncovered([], [], "angle"), _uncovered([], [0.0], "angle"), _uncovered([], [0.0], "angle", gap=4.0)
    ([0.0], [], [3.141592653589793])
    >>> [round(v, 6) for v in _uncovered([-1.0, 1.0], [0.0], "angle")]
    [3.141593]
    >>> [round(v, 6) for v in _uncovered([-1.0, 1.0], [0.0, 3.0], "angle", gap=2.0)]
    [-2.141593]
    """
    if not samples:
        return [0.0]
    if kind != "angle":
        bounds = list(zip(critical, critical[1:]))
    elif critical:
        bounds = list(zip(critical, critical[1:])) + [(critical[-1], critical[0] + 2 * math.pi)]
    else:
        first = sorted(samples)[0]
        bounds = [(first, first + 2 * math.pi)]  # one interval, from a sample round to itself
    out = []
    for a, b in bounds:
        inside = sorted(a + (s_ - a) % (2 * math.pi) if kind == "angle" else s_ for s_ in samples)
        inside = [v for v in inside if a < v < b]
        if critical and not inside:
            out.append(0.5 * (a + b))
            continue
        points = [a] + inside + [b]
        out += [0.5 * (p + q) for p, q in zip(points, points[1:]) if q - p > gap]
    return [_wrap(v, kind) for v in out]


def _is_singular(mech: Mechanism, conf: dict, name: str, tol: Tolerances) -> bool:
    """For a squared-up system: whether a real solution is a DKP (``name``) or IM configuration."""
    from symkin.analysis.classification import analyze

    types = analyze(mech.with_coordinates(conf), tol=tol).types
    return name in types or "IM" in types


def _exact_roots(mech: Mechanism, c: InputCoordinate) -> list[dict] | str:
    """Real solutions (configurations) of the exact square DKP systems by msolve, or why there are none."""
    from symkin.solutions.exact import exact_dkp_system, msolve_executable, real_solutions

    if msolve_executable() is None:
        from symkin.solutions.exact import EXTRA

        return f"msolve is not installed ({EXTRA})"
    try:
        system = exact_dkp_system(mech, c)
        found = []
        for equations in system.systems():
            found += [system.place(v) for v, _ in real_solutions(list(equations), system.unknowns)]
    except SymkinError as exc:
        return str(exc)
    return found


def _compare(mech, name, label, found, traced, paths, degree, seconds, scale, tol: Tolerances) -> CrossCheck:
    qs = [_free(mech, c) for c in found]
    qt = [_free(mech, s.configuration) for s in traced]
    used = set()
    matched = 0
    only_h = []
    for c, q in zip(found, qs):
        d = [np.linalg.norm(q - t) if k not in used else math.inf for k, t in enumerate(qt)]
        k = int(np.argmin(d)) if d else -1
        if k >= 0 and d[k] <= tol.same_configuration * scale:
            used.add(k)
            matched += 1
        else:
            only_h.append(c)
    only_t = [s.configuration for k, s in enumerate(traced) if k not in used]
    return CrossCheck(name, label, len(found), len(traced), matched, paths, degree, tuple(only_h), tuple(only_t),
                      seconds)
