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
2. **Seeds.**  :func:`symkin.solve_all` at the input values midway between consecutive
   critical input values (and at the model's input value when there is no critical
   value): every circuit on which the input moves contains one of them, since on a circuit
   the input either takes every value or sweeps an interval between two critical values.
3. **Branches.**  Each seed not yet on a traced branch is traced by :func:`symkin.trace` (the
   existing pseudo-arclength continuation with its event location) until the path closes
   on itself; a seed is on a traced branch when the path passes through it: the crossing
   of its input value is located on the path (:func:`~symkin.paths.events.locate_sign_change`)
   and is within :attr:`Tolerances.same_configuration` (units of the length scale) of it.
4. **Singular configurations and circuits.**  Every event that the traces locate (DKP-input,
   DKP-output, IM), classified by :func:`symkin.analyze`; one configuration met by several
   branches is one entry.  Branches that share a configuration (a branch point, IM) are one
   circuit: a circuit is a connected component.  At the change point of a four-bar
   (``s + l = p + q``) the continuation goes straight through the flat IM configuration, so
   its one branch turns the crank twice (once in each assembly mode) and crosses itself
   there: one circuit, where the Grashof four-bars on either side have two or one.
5. **Cross-check.**  The real solutions of step 1 must be exactly the traced configurations
   of the kinds they detect (DKP-input or IM; DKP-output or IM), each matched within
   ``same_configuration``.  Both counts are reported; a disagreement is a field
   (``agree = False``, the unmatched configurations) and a warning, never silent.

Not covered: a circuit on which the input is locked (constant), whose points are all
critical (not isolated solutions of step 1) and which no seed at another input value meets;
and square systems beyond ``max_paths`` (the double butterfly of ``papers_examples/``, whose
DKP-input determinant has a factor of degree 6 with 2295 terms: a clear error, not a wait).
"""
from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from symkin.analysis.classification import Analysis
from symkin.errors import NotConvergedError, SymkinError
from symkin.model.mechanism import Mechanism
from symkin.paths.continuation import CurvePoint, tangent
from symkin.paths.coordinates import InputCoordinate, input_coordinates
from symkin.paths.events import TestFunction, locate_sign_change
from symkin.paths.trace import Path, trace
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
    the model's configuration); ``full_turn`` says that the input takes every value (a crank).
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
    configurations found by one side only.  ``paths`` is the number of homotopy paths.
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

    @property
    def agree(self) -> bool:
        return not self.unmatched_homotopy and not self.unmatched_traced

    def to_dict(self) -> dict:
        return {"kind": self.kind, "label": self.label, "homotopy": self.homotopy, "traced": self.traced,
                "matched": self.matched, "agree": self.agree, "paths": self.paths, "degree": self.degree,
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
    def agree(self) -> bool:
        """The traced circuits and every square DKP system give the same configurations."""
        return all(c.agree for c in self.checks)

    def to_dict(self) -> dict:
        """``{"circuits": n, "singularities": [...], ...}``: the ``--json`` of ``symkin singularities``."""
        conv = self._conv()
        return {"mechanism": self.mechanism.name, "circuits": len(self.circuits),
                "singularities": [s.to_dict() for s in self.singularities],
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


# ---------------------------------------------------------------------- the entry point
def singularities(mech: Mechanism, *, tol: float | Tolerances | None = None, unit: str = "rad",
                  max_turns: int = 4, max_arclength: float | None = None, max_paths: int = MAX_PATHS,
                  seed: int = 0) -> Singularities:
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
        Refuse, with a :class:`SymkinError` that gives the count, a square system whose homotopy
        tracks more paths than this (its total degree; default :data:`MAX_PATHS`).
    seed : int
        Seed of the random combinations that square up a redundant closure.

    Returns
    -------
    Singularities

    Raises
    ------
    SymkinError
        Not 1-DOF, no input, an unsupported input, the solver not installed (the message names the
        extra), or a homotopy larger than ``max_paths``.

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
    for name, c in systems:
        t0 = time.perf_counter()
        system = dkp_system(mech, c, tolerances, closure=closure, seed=seed)
        paths = max(total_degree(list(e), list(system.unknowns)) for e in system.systems())
        if paths > max_paths:
            raise SymkinError(f"{mech.name}: a factor of the square {name} system needs a homotopy of {paths} "
                              f"paths (total degree), more than max_paths = {max_paths}; it may run for tens of "
                              "minutes: raise max_paths (--max-paths) to track it")
        found, tracked = _real_roots(system, tolerances)
        if system.squared:
            found = [c_ for c_ in found if _is_singular(mech, c_, name, tolerances)]
        roots[name] = (found, tracked, system.degree, time.perf_counter() - t0)

    # 2. seeds: solve_all midway between consecutive critical input values
    critical = sorted({round(_wrap(in_value(_flat(mech, c)), kind), 12) for c in roots["DKP-input"][0]})
    samples = _samples(critical, kind)
    seeds: list[tuple[float, dict]] = []
    for v in samples:
        sol = solve_all(mech, {drive.label: v}, unit="rad", tol=tolerances, seed=seed)
        seeds += [(v, s.configuration) for s in sol.solutions]

    # 3. circuits
    circuits: list[tuple[Path, float, np.ndarray]] = []
    turns = max_turns if kind == "angle" else 1
    for value, conf in seeds:
        q = _free(mech, conf)
        if any(_on_path(p, ins, off, value, q, kind, scale, tolerances) for p, off, ins in circuits):
            continue
        m = mech.with_coordinates(conf)
        stop = 2 * math.pi * turns if kind == "angle" else 1e6 * scale
        steps = int(math.ceil(stop / MAX_ANGLE_STEP)) if kind == "angle" else None
        arclength = max_arclength if max_arclength is not None else 100.0 * turns
        path = trace(m, stop=stop, steps=steps, max_arclength=arclength, tol=tolerances)
        offset = in_value(_flat(mech, conf))
        circuits.append((path, offset, _points(path, offset)))
        if path.stop_reason not in ("closed", "unreachable"):
            notes.append(f"branch {len(circuits)} (seed at {drive.label} = {_fmt(value, kind, unit)}) did not "
                         f"close: {path.message}")

    # 4. singular configurations on the branches, merged; branches through one configuration are one circuit
    entries: list[dict] = []
    for index, (path, _, _) in enumerate(circuits, 1):
        for e in path.singular_events():
            q = _free(mech, e.coordinates)
            for item in entries:
                if np.linalg.norm(item["q"] - q) <= tolerances.same_configuration * scale:
                    item["branches"].append(index)
                    item["kinds"] += [k for k in e.kinds if k not in item["kinds"]]
                    break
            else:
                entries.append({"q": q, "x": e.coordinates, "branches": [index], "kinds": list(e.kinds),
                                "analysis": e.analysis, "s": e.s})
    component = _components(len(circuits), [item["branches"] for item in entries])
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
        found, tracked, degree, seconds = roots[name]
        traced = [s for s in result_sing if name in s.kinds or "IM" in s.kinds]
        checks.append(_compare(mech, name, c.label, found, traced, tracked, degree, seconds, scale, tolerances))
    for ch in checks:
        if not ch.agree:
            msg = (f"{mech.name}: the square {ch.kind} system has {ch.homotopy} real solution(s), the traced "
                   f"circuits {ch.traced} {ch.kind}/IM configuration(s); {len(ch.unmatched_homotopy)} found only by "
                   f"the homotopy, {len(ch.unmatched_traced)} only by the traces")
            notes.append(msg)
            warnings.warn(msg, SingularitiesWarning, stacklevel=2)

    branches = []
    for index, (path, offset, ins) in enumerate(circuits, 1):
        outs = None if out_value is None else np.unwrap([out_value(p.coordinates) for p in path.points]) \
            if output.kind == "angle" else np.array([out_value(p.coordinates) for p in path.points])
        span = float(np.max(ins) - np.min(ins)) if ins.size else 0.0
        closed = path.stop_reason in ("closed", "unreachable")
        branches.append(Branch(index, _as_dict(mech, path.points[0].coordinates), ins, outs, closed,
                               kind == "angle" and span >= 2 * math.pi - 1e-9, path.stop_reason, path))
    circuit_objs = [Circuit(k, tuple(b for b in branches if component[b.index] == k))
                    for k in sorted(set(component.values()))]
    return Singularities(mech, drive.label, None if output is None else output.label, unit, kind,
                         tuple(circuit_objs), tuple(result_sing), tuple(checks), tuple(samples), len(seeds),
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


def _is_singular(mech: Mechanism, conf: dict, name: str, tol: Tolerances) -> bool:
    """For a squared-up system: whether a real solution is a DKP (``name``) or IM configuration."""
    from symkin.analysis.classification import analyze

    types = analyze(mech.with_coordinates(conf), tol=tol).types
    return name in types or "IM" in types


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
