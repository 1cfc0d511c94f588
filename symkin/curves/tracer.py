"""THE tracer: follow a curve, test every event type at each accepted point, locate, merge, stop.

:func:`trace_curve` drives the stepper (:func:`symkin.curves.stepper.continue_curve`); at
each accepted point it evaluates every :class:`~symkin.curves.events.EventType`'s test,
locates the events its values bracket with the type's own locator, merges events closer
than ``same_configuration`` (one event carrying every test that located it, of the kind
that comes first in ``priority``), and applies the stop rules.  It returns a plain
:class:`TracedCurve`: the accepted points, the located events (sorted by arclength) and
why it stopped.  What the points and events *mean* (a mechanism's input, its
classification) is the caller's: the tracer knows only ``y``, ``t``, ``s`` and the curve's
*parameter* ``p`` (e.g. a path's input), ``parameter(y, reference) -> p`` continued from the
previous point's value (unwrapping angles).

>>> import numpy as np
>>> from symkin.curves.events import ArclengthLimit, Closed, EventType
>>> from symkin.curves.stepper import Settings
>>> class Circle:
...     def residual(self, y): return np.array([y @ y - 1.0])
...     def jacobian(self, y): return 2 * y[None, :]
>>> y0, t0 = np.array([1.0, 0.0]), np.array([0.0, 1.0])
>>> crossing = EventType("x = 0", lambda y, t: float(y[0]), kind="crossing")
>>> out = trace_curve(Circle(), y0, t0, events=[crossing],
...                   stops=[Closed(y0, t0, 0.2, 0.4), ArclengthLimit(10.0)], settings=Settings())
>>> out.stop.reason, [round(abs(float(e.y[1])), 12) for e in out.events]
('closed', [1.0, 1.0])
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any, Callable, Sequence

import numpy as np

from symkin.curves.events import Closed, EventType, ParameterReached, StepBudget, StepRule, StopRule
from symkin.curves.locate import CurveEvent, locate_sign_change, polish
from symkin.curves.stepper import CurvePoint, CurveProblem, Settings, SteppingError, continue_curve
from symkin.errors import NotConvergedError
from symkin.kinds import Kind
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["TracedPoint", "LocatedEvent", "Stop", "TracedCurve", "trace_curve"]


@dataclass(frozen=True)
class TracedPoint:
    """An accepted point and its parameter ``p``."""

    point: CurvePoint
    p: float


@dataclass(frozen=True)
class LocatedEvent:
    """A located (and merged) event: its kind, where, the parameter there, every test that located it.

    ``where`` is the located event of the first test of ``kind`` (its ``y`` polished onto the
    curve); ``value`` is the value of the first test that located the configuration and
    ``evaluations`` the test evaluations of all of them.
    """

    kind: Kind | str | None
    where: CurveEvent = field(repr=False)
    p: float
    value: float
    evaluations: int
    tests: tuple[str, ...]

    @property
    def y(self) -> np.ndarray:
        return self.where.y

    @property
    def t(self) -> np.ndarray:
        return self.where.t

    @property
    def s(self) -> float:
        return self.where.s


@dataclass(frozen=True)
class Stop:
    """Why the trace ended: ``reason``, ``message``; ``event`` the located end (a :class:`ParameterReached`).

    ``point`` is the accepted point at which the rule fired (not among the recorded points
    when the rule is located or :class:`Closed`, nor for a :class:`StepRule` unless its end
    says ``keep``); ``data`` what a :class:`StepRule` handed back.
    """

    reason: str
    message: str
    event: CurveEvent | None = field(default=None, repr=False)
    rule: StopRule | None = field(default=None, repr=False)
    point: TracedPoint | None = field(default=None, repr=False)
    data: Any = field(default=None, repr=False)


@dataclass(frozen=True)
class TracedCurve:
    """Result of :func:`trace_curve`: accepted points, located events (by arclength) and the stop."""

    points: tuple[TracedPoint, ...] = field(repr=False)
    events: tuple[LocatedEvent, ...]
    stop: Stop


class _Merged:
    """Located events merged by configuration (mutable while tracing; frozen into :class:`LocatedEvent`)."""

    def __init__(self, distance: float, priority: Sequence, window: float):
        self.distance, self.priority, self.window, self.items = distance, tuple(priority), window, []

    def _rank(self, kind) -> int:
        return self.priority.index(kind) if kind in self.priority else len(self.priority)

    def add(self, kind, ev: CurveEvent, p: float) -> None:
        """Record ``ev`` (``y`` polished), or merge it into the event of the same configuration and passage."""
        for item in self.items:
            where = item["where"]
            if np.linalg.norm(where.y - ev.y) < self.distance and abs(where.s - ev.s) <= self.window:
                item["tests"].append(ev.name)
                if self._rank(kind) < self._rank(item["kind"]):
                    item.update(kind=kind, where=ev, p=p)
                item["evaluations"] += ev.evaluations
                return
        self.items.append({"kind": kind, "where": ev, "p": p, "value": ev.value, "evaluations": ev.evaluations,
                           "tests": [ev.name]})

    def drop_repeats_after(self, s: float) -> None:
        """Forget the events past arclength ``s`` that repeat an event before it (a closed curve's end
        meets its first events again); an event at the start itself, met only on the way back, stays."""
        before = [it for it in self.items if it["where"].s <= s]
        self.items = before + [it for it in self.items if it["where"].s > s and not any(
            np.linalg.norm(b["where"].y - it["where"].y) < self.distance for b in before)]

    def events(self) -> tuple[LocatedEvent, ...]:
        return tuple(LocatedEvent(it["kind"], it["where"], it["p"], it["value"], it["evaluations"],
                                  tuple(dict.fromkeys(it["tests"])))
                     for it in sorted(self.items, key=lambda i: i["where"].s))


def _back_on_start(problem: CurveProblem, rule: Closed, a: CurvePoint, b: CurvePoint,
                   tolerances: Tolerances) -> CurveEvent | None:
    """The start, located on the step ``a → b`` that crosses its normal plane near it, or None.

    The crossing is located on the curve and compared with the start as configurations are
    (``tolerances.same_configuration``): a curve that comes back only near its start — a screw
    advanced by one lead shorter than the rule's radius — is not closed (None).  Where the
    crossing cannot be located (the corrector fails inside the step), the rule's own test
    decides, as it did alone: closed at ``b``.
    """
    plane = EventType("start plane", lambda y, t: float(rule.t0 @ (y - rule.y0)))
    try:
        at = locate_sign_change(problem, plane, a, b)
    except (SteppingError, NotConvergedError):
        return CurveEvent(plane.name, "sign change", b.y, b.t, b.s, plane.value(b.y, b.t), 0)
    return at if float(np.linalg.norm(at.y - rule.y0)) < tolerances.same_configuration else None


def trace_curve(problem: CurveProblem, y0: np.ndarray, t0: np.ndarray, *, events: Sequence[EventType] = (),
                stops: Sequence[StopRule] = (), settings: Settings = Settings(),
                parameter: Callable[[np.ndarray, float], float] | None = None, p0: float = 0.0,
                guard: Callable[[CurvePoint, np.ndarray], bool] | None = None,
                on_point: Callable[[TracedPoint], None] | None = None,
                priority: Sequence = (), tolerances: Tolerances = DEFAULT) -> TracedCurve:
    """Follow ``problem``'s curve from ``y0`` along ``t0``; locate ``events``; stop by ``stops``.

    Parameters
    ----------
    events : sequence of EventType
        Tested at every accepted point; signed ones located by sign change, others by minimum.
        Every located event is polished onto the curve (:func:`~symkin.curves.locate.polish`
        at ``tolerances.closure``, ``rcond = tolerances.rank``).
    stops : sequence of StopRule
        Checked in this order at each step: the :class:`~symkin.curves.events.StepRule` rules first
        (in the order given, before the step's events are located), then, after the events, a
        located rule (:class:`ParameterReached`) and :class:`Closed` before the new point is
        recorded, the others after it.  :class:`Closed` ends the trace only when its crossing
        of the start's normal plane, located on the curve, is the start itself (to
        ``tolerances.same_configuration``); events located on that last step past the start
        that repeat the loop's first ones (the same configuration) are dropped.
    parameter, p0 : callable, float
        ``parameter(y, reference)`` the curve's parameter at ``y`` continued from
        ``reference`` (default 0 everywhere); ``p0`` its value at ``y0``.
    guard : callable, optional
        ``guard(previous, y)`` may reject a corrected point (:func:`~symkin.curves.stepper.continue_curve`).
    on_point : callable, optional
        Called with each recorded point.
    priority : sequence of Kind
        Kinds in merging order: a merged event takes the first kind of its tests.
    tolerances : Tolerances
        ``same_configuration`` merges events (located on the same passage: at most
        ``settings.max_step`` apart in arclength; a curve that comes back to a configuration
        meets it again), ``closure`` and ``rank`` polish them.

    A :class:`~symkin.curves.stepper.SteppingError` or a corrector failure ends the trace
    with reason ``"stuck"`` and the error's message; a stepper that took its
    ``settings.max_steps`` accepted steps before any rule fired ends it with reason
    ``"max_steps"`` (:class:`~symkin.curves.events.StepBudget`).
    """
    param = parameter if parameter is not None else (lambda y, ref: 0.0)
    merged = _Merged(tolerances.same_configuration, priority, settings.max_step)
    points: list[TracedPoint] = []
    history: list[tuple[CurvePoint, dict, float]] = []
    located = [r for r in stops if isinstance(r, ParameterReached)]
    closed = [r for r in stops if isinstance(r, Closed)]
    on_step = [r for r in stops if isinstance(r, StepRule)]
    after = [r for r in stops if not isinstance(r, (ParameterReached, Closed, StepRule))]

    def record(result, reference: float) -> None:
        if result is None:
            return
        kind, ev = result
        ev = replace(ev, y=polish(problem, ev.y, tolerances.closure, tolerances.rank))
        merged.add(kind, ev, param(ev.y, reference))

    def keep(cp: CurvePoint, vals: dict, p: float) -> None:
        tp = TracedPoint(cp, p)
        points.append(tp)
        history.append((cp, vals, p))
        history[:] = history[-2:]
        if on_point is not None:
            on_point(tp)

    try:
        for cp in continue_curve(problem, y0, t0, settings, guard=guard):
            p = param(cp.y, history[-1][2] if history else p0)
            if history and on_step:
                before = tuple(h[0] for h in history)
                ended, rule = None, None
                for rule in on_step:
                    ended = rule.check(problem, before, cp)
                    if ended is not None:
                        break
                if ended is not None:
                    if ended.keep:
                        keep(cp, {}, p)
                    stop = Stop(ended.reason, ended.message or rule.message, ended.event, rule, TracedPoint(cp, p),
                                ended.data)
                    break
            vals = {e.name: e.value(cp.y, cp.t) for e in events}
            if history:
                pcp, pvals, pp = history[-1]
                for e in events:
                    if e.brackets_root(pvals[e.name], vals[e.name]):
                        record(e.locate(problem, pcp, cp, rank=tolerances.rank), pp)
                if len(history) >= 2:
                    (a, av, _), (b, bv, bp) = history
                    for e in events:
                        if e.brackets_minimum(av[e.name], bv[e.name], vals[e.name]):
                            record(e.locate(problem, a, b, cp, rank=tolerances.rank), bp)
                rule = next((r for r in located if r.before(pp) and r.reached(cp, p)), None)
                if rule is not None:
                    stop = Stop(rule.reason, rule.message, locate_sign_change(problem, rule.test(pp), pcp, cp), rule,
                                TracedPoint(cp, p))
                    break
                rule = next((r for r in closed if r.crossed(pcp, cp)), None)
                back = None if rule is None else _back_on_start(problem, rule, pcp, cp, tolerances)
                if back is not None:
                    merged.drop_repeats_after(back.s)  # the loop's first events, located again past the start
                    stop = Stop(rule.reason, rule.message, None, rule, TracedPoint(cp, p))
                    break
            keep(cp, vals, p)
            rule = next((r for r in after if r.reached(cp, p)), None)
            if rule is not None:
                stop = Stop(rule.reason, rule.message, None, rule, TracedPoint(cp, p))
                break
        else:  # the stepper took its last step: no rule ended the trace
            budget = StepBudget(settings.max_steps)
            stop = Stop(budget.reason, budget.message, None, budget, points[-1] if points else None)
    except (SteppingError, NotConvergedError) as exc:
        stop = Stop("stuck", str(exc))
    return TracedCurve(tuple(points), merged.events(), stop)
