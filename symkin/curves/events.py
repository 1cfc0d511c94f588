"""Event types and stop rules of a traced curve: how to test, how to locate, what kind to report.

An :class:`EventType` says

* how to **test** at every accepted point: ``value(y, t)`` (``t`` the oriented unit
  tangent); a *signed* value is watched for a sign change, a *non-negative* one (a singular
  value) for a local minimum below ``detect``;
* how to **locate**: :meth:`EventType.locate` — Brent's method on the sign change
  (:func:`~symkin.curves.locate.locate_sign_change`, a root accepted where the value falls
  below ``ROOT`` of the bracket's values, unless ``any_root``) or bounded minimisation
  (:func:`~symkin.curves.locate.locate_minimum`, accepted at most ``threshold``), then
  its own ``refine`` (e.g. :class:`SingularEvent`: onto the branch point);
* how to **classify**: ``kind``, the :class:`~symkin.kinds.Kind` it reports.

A :class:`StopRule` says when a trace ends: :class:`ParameterReached` (the curve's parameter,
e.g. a path's input, reaches its target: located like an event, kind ``end``),
:class:`Closed` (back on the start), :class:`ArclengthLimit`, :class:`LeftBox` (a point
outside a box of the curve's coordinates, for maps), and a caller's :class:`StepRule` (decided
on a step, first, e.g. a curve that leaves a region through a located end).  The tracer
(:mod:`symkin.curves.tracer`) applies them.

>>> import numpy as np
>>> height = EventType("height", lambda y, t: float(y[1]), kind=Kind.END)
>>> height.signed, str(height.kind)
(True, 'end')
>>> from symkin.curves.stepper import CurvePoint
>>> ArclengthLimit(2.0).reached(CurvePoint(np.zeros(2), np.ones(2), 2.5), 0.0)
True
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from symkin.curves.locate import CurveEvent, locate_minimum, locate_sign_change, refine_singular
from symkin.curves.stepper import CurvePoint, CurveProblem
from symkin.kinds import Kind
from symkin.tolerances import DEFAULT

__all__ = ["EventType", "SingularEvent", "StopRule", "ParameterReached", "Closed", "ArclengthLimit", "StepBudget",
           "LeftBox", "StepRule", "StepEnd", "TestFunction", "FLAT", "ROOT", "DETECT"]

#: a signed test below this at both ends of a step is identically zero there: no isolated root
#: (the curve runs along such a configuration, e.g. a locked input link)
FLAT = DEFAULT.flat
#: a located root must bring the test below this fraction of its bracket values (else the sign
#: changed through a jump, not a zero)
ROOT = DEFAULT.root
#: a local minimum of a non-negative test below this is refined (and accepted below ``threshold``);
#: singular values of the dimensionless Jacobian are O(1) away from singularities
DETECT = 0.05


@dataclass(frozen=True)
class EventType:
    """A test along a curve, its locator and the kind it reports (see the module docstring).

    ``f(y, t)`` is the test; ``signed`` ones are located by sign change, others by minimum
    (an event when the minimum is at most ``threshold``).  ``any_root``: every located sign
    change is an event (a determinant that changes sign through a branch point, where the
    located value need not be small).  ``near``: a non-negative event type (the IM test)
    whose value below ``near_threshold`` at a located root says the root sits at a branch
    point; the event is then relocated by ``near`` and reported as ``near``'s kind.  ``flat``:
    a signed test at most this at both ends of a step is identically zero there (no isolated root).
    ``isolated``: the test must exceed ``flat`` (signed) or ``threshold`` (a minimum) at *both*
    ends of its bracket: where it falls to zero and stays there (a curve entering a branch on
    which a link stays locked) there is no isolated event.
    """

    __test__ = False  # not a pytest test class

    name: str
    f: Callable[[np.ndarray, np.ndarray], float]
    signed: bool = True
    threshold: float = DEFAULT.event_threshold
    kind: Kind | None = None
    detect: float = DETECT
    any_root: bool = False
    near: "EventType | None" = field(default=None, repr=False)
    near_threshold: float = DEFAULT.near_branch
    flat: float = FLAT
    isolated: bool = False

    def value(self, y: np.ndarray, t: np.ndarray) -> float:
        """The test's value at ``y`` (tangent ``t``)."""
        return self.f(y, t)

    def brackets_root(self, fa: float, fb: float) -> bool:
        """Whether values ``fa`` and ``fb`` at two consecutive points bracket an isolated root."""
        ends = (min if self.isolated else max)(abs(fa), abs(fb))
        return self.signed and np.sign(fa) * np.sign(fb) < 0 and ends > self.flat

    def brackets_minimum(self, fa: float, fb: float, fc: float) -> bool:
        """Whether values at three consecutive points bracket a local minimum worth locating.

        Not where the test is at most ``threshold`` at all three points: the curve runs along
        such configurations (e.g. a branch on which a link stays locked), the minima of
        rounding noise are no isolated events.
        """
        return (not self.signed and fb < self.detect and fb <= fa and fb <= fc
                and (min if self.isolated else max)(fa, fc) > self.threshold)

    def locate(self, problem: CurveProblem, a: CurvePoint, b: CurvePoint, c: CurvePoint | None = None,
               rank: float = DEFAULT.rank) -> tuple[Kind | None, CurveEvent] | None:
        """Locate the event bracketed by ``a``, ``b`` (sign change) or ``a``, ``b``, ``c`` (minimum at ``b``).

        Returns ``(kind, located event)`` or None when the bracket holds no event.
        """
        if self.signed:
            ev = locate_sign_change(problem, self, a, b)
            fa, fb = self.value(a.y, a.t), self.value(b.y, b.t)
            if not (self.any_root or abs(ev.value) <= ROOT * max(abs(fa), abs(fb))):
                return None
            lo, hi = a, b
        else:
            ev = locate_minimum(problem, self, a, b, c)
            if ev is None:
                return None
            lo, hi = a, c
        if self.near is not None and self.near.value(ev.y, ev.t) < self.near_threshold:
            moved = locate_minimum(problem, self.near, lo, CurvePoint(ev.y, ev.t, ev.s), hi)
            if moved is not None:
                ev = CurveEvent(ev.name, ev.kind, moved.y, moved.t, moved.s, ev.value,
                                ev.evaluations + moved.evaluations)
            return self.near.refine(problem, ev, lo, hi, rank)
        return self.refine(problem, ev, lo, hi, rank)

    def refine(self, problem: CurveProblem, ev: CurveEvent, lo: CurvePoint, hi: CurvePoint,
               rank: float = DEFAULT.rank) -> tuple[Kind | None, CurveEvent]:
        """This type's own refinement of a located event (none: the event as located)."""
        return self.kind, ev


@dataclass(frozen=True)
class SingularEvent(EventType):
    """An event at a singular point of the curve (IM): located, then moved onto the branch point.

    :func:`~symkin.curves.locate.refine_singular` — the one singular-point locator, or the
    point of higher nullity next to it within the bracket.
    """

    def refine(self, problem, ev, lo, hi, rank=DEFAULT.rank):
        y, t = refine_singular(problem, ev.y, ev.t, float(np.linalg.norm(hi.y - lo.y)), rank)
        return self.kind, CurveEvent(ev.name, ev.kind, y, t, ev.s, ev.value, ev.evaluations)


TestFunction = EventType
"""The former name of :class:`EventType` (``name``, ``f``, ``signed``, ``threshold``)."""


# ---------------------------------------------------------------------- stop rules
class StopRule:
    """A reason to end a trace: ``reached(point, parameter)`` after each accepted point.

    ``reason`` and ``message`` say why; a rule with ``located = True`` is located like a
    signed event (:meth:`value`) between the last two points and ends the trace there,
    before the point past it is recorded.
    """

    reason: str = ""
    message: str = ""
    located: bool = False

    def reached(self, point: CurvePoint | None, parameter: float) -> bool:  # pragma: no cover - interface
        raise NotImplementedError


@dataclass(frozen=True)
class ParameterReached(StopRule):
    """The curve's parameter (a path's input) reaches ``target`` moving in ``direction``; ``scale`` makes it dimensionless."""

    target: float
    direction: float
    parameter: Callable[[np.ndarray, float], float] = field(repr=False)
    scale: float = 1.0
    reason: str = "reached"
    message: str = "the input reached its target value"
    located: bool = True
    kind: Kind = Kind.END

    def reached(self, point, parameter) -> bool:
        return (parameter - self.target) * self.direction >= 0

    def before(self, parameter: float) -> bool:
        """Whether ``parameter`` is short of the target."""
        return (parameter - self.target) * self.direction < 0

    def test(self, reference: float) -> EventType:
        """The signed test ``(parameter(y) − target) / scale``, the parameter continued from ``reference``."""
        return EventType(str(self.kind), lambda y, t: (self.parameter(y, reference) - self.target) / self.scale,
                         kind=self.kind)


@dataclass(frozen=True)
class Closed(StopRule):
    """The curve is back on its start ``y0``: it crosses the start's normal plane (tangent ``t0``) close to it.

    Closed once past ``min_arclength`` and within ``radius`` of ``y0`` (dimensionless).
    """

    y0: np.ndarray = field(repr=False)
    t0: np.ndarray = field(repr=False)
    min_arclength: float = 0.0
    radius: float = 0.0
    reason: str = str(Kind.CLOSED)
    message: str = "the path closed on its start (a full loop)"

    def crossed(self, previous: CurvePoint, point: CurvePoint) -> bool:
        """Whether the step ``previous → point`` crosses the start's normal plane close to the start."""
        return (float(self.t0 @ (previous.y - self.y0)) < 0 <= float(self.t0 @ (point.y - self.y0))
                and point.s > self.min_arclength and float(np.linalg.norm(point.y - self.y0)) < self.radius)

    def reached(self, point, parameter) -> bool:
        return False  # decided on a step by :meth:`crossed`


@dataclass(frozen=True)
class ArclengthLimit(StopRule):
    """The arclength passed ``limit`` (units of ``y``)."""

    limit: float
    reason: str = "max_arclength"

    @property
    def message(self) -> str:
        return f"arclength limit {self.limit:g} (units of the model's length scale) reached"

    def reached(self, point, parameter) -> bool:
        return point.s > self.limit


@dataclass(frozen=True)
class StepBudget(StopRule):
    """The stepper's budget of ``steps`` accepted steps (``Settings.max_steps``) ran out.

    Decided by the stepper, not per point (:meth:`reached` is always false): the tracer ends
    with this rule when :func:`~symkin.curves.stepper.continue_curve` has taken its last step.

    >>> StepBudget(20000).reason
    'max_steps'
    """

    steps: int
    reason: str = "max_steps"

    @property
    def message(self) -> str:
        return (f"the step budget ran out: {self.steps} accepted steps (Settings.max_steps) were taken before the "
                "curve reached any other stop; raise it with settings=Settings(max_steps=...)")

    def reached(self, point, parameter) -> bool:
        return False  # decided by the stepper running out of steps


@dataclass(frozen=True)
class LeftBox(StopRule):
    """A point's ``coordinates(y)`` left the box ``[lower, upper]`` (e.g. a map's axes)."""

    lower: np.ndarray = field(repr=False)
    upper: np.ndarray = field(repr=False)
    coordinates: Callable[[np.ndarray], np.ndarray] = field(repr=False)
    reason: str = str(Kind.BOX)
    message: str = "the curve left the box"

    def reached(self, point, parameter) -> bool:
        c = np.asarray(self.coordinates(point.y), float)
        return bool(np.any(c < self.lower) or np.any(c > self.upper))


@dataclass(frozen=True)
class StepEnd:
    """What a :class:`StepRule` found on a step: why the trace ends, where, and whether the step's point is kept.

    ``event`` is the located end (or None), ``keep`` whether the step's new point is recorded
    before the trace ends, ``data`` anything the rule's caller wants back (the tracer only
    passes it on, in :attr:`symkin.curves.tracer.Stop.data`).
    """

    reason: str
    event: CurveEvent | None = field(default=None, repr=False)
    keep: bool = False
    message: str = ""
    data: Any = field(default=None, repr=False)


class StepRule(StopRule):
    """A stop rule decided on a step ``history[-1] → point`` (``history``: the last recorded points, oldest first).

    The tracer checks its step rules first at each step, in the order given, before the
    step's events are located: the first :meth:`check` that returns a :class:`StepEnd` ends
    the trace (events past the end are not on the traced piece).
    """

    def check(self, problem: CurveProblem, history: tuple[CurvePoint, ...],
              point: CurvePoint) -> StepEnd | None:  # pragma: no cover - interface
        raise NotImplementedError

    def reached(self, point, parameter) -> bool:
        return False  # decided on a step by :meth:`check`
