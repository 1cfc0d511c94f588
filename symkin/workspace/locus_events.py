"""The events and stop rules of a map's singular curve, for the one tracer (:func:`symkin.curves.tracer.trace_curve`).

A traced locus (:meth:`LocusProblems.curve`) or double-zero curve (:meth:`LocusProblems.slope_curve`)
ends, in this order of precedence on a step,

* where it leaves the mode's assembled region — the boundary test ``T_b`` leaves its sign
  inside the mode (a fold) — or meets another locus of the same equations (a simple branch
  point: ``det[H'; tᵀ]`` changes sign), :class:`LeavesRegion`, located by sign change; an
  end next to IM is the IM point, an end outside the box is moved onto the box;
* where it leaves the box of the axes (:class:`OnBox`, the curves' :class:`LeftBox` rule,
  the last point moved onto the box edge);
* next to IM (:class:`NearIM`: the relative IM indicator below ``near_branch``, or a test
  that is not finite), the IM configuration refined from there;
* at a near-zero local minimum of the IM indicator (:class:`IMMinimum`: loci meeting at IM);
* a double-zero curve also where ``|T|`` grows past ``event_threshold`` (:class:`LeavesDoubleZero`);

and it is closed when it comes back onto its start (the curves' :class:`Closed` rule).  Along
the way, the tracer locates :func:`meeting_event` (a boundary curve crossing the interior
locus: an interior curve starts there) and :class:`CuspEvent` (the image in the axes turns
back).  :class:`PointTests` caches the tests at the recorded points, so that each is
evaluated once per point.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from symkin.curves.corrector import gauss_newton
from symkin.curves.events import EventType, LeftBox, StepEnd, StepRule
from symkin.curves.locate import CurveEvent, locate_minimum, locate_sign_change
from symkin.curves.stepper import CurvePoint
from symkin.errors import NotConvergedError
from symkin.kinds import Kind
from symkin.tolerances import Tolerances
from symkin.workspace.cusps import axis_velocity, locate_cusp_event
from symkin.workspace.im_points import locate_im
from symkin.workspace.locus_problems import KINDS, LOCUS_NEWTON_TOL, POLISH_ITERATIONS, CurveFunction, LocusProblems

__all__ = ["PointTests", "LeavesRegion", "OnBox", "NearIM", "IMMinimum", "LeavesDoubleZero", "CuspEvent",
           "LeavesBoundaryAt", "cusp_event",
           "meeting_event", "im_end", "onto_box", "outside", "branch_test", "END_BOUNDARY", "END_BRANCH", "END_LEFT",
           "END_POINT", "PointImage"]

#: end of a curve that leaves the mode's assembled region (a fold of the mode's workspace)
END_BOUNDARY = "boundary"
#: end of a curve that meets another locus of the same equations (a simple branch point)
END_BRANCH = "branch"
#: end of a double-zero curve whose slope's zero set leaves the double zero
END_LEFT = "left"
#: end of a "curve" whose image in the axes is one point (:class:`PointImage`)
END_POINT = "point"
#: points whose tests :class:`PointTests` keeps (the tracer looks back at most two points)
_CACHED_POINTS = 8


class PointTests:
    """The tests of a locus at the points of one trace, each evaluated once: ``T`` (:meth:`LocusProblems.tests`),
    the branch test and the axis velocity (they need the tangent)."""

    def __init__(self, pb: LocusProblems, problem: CurveFunction):
        self.pb, self.problem, self._tests, self._branch, self._velocity = pb, problem, {}, {}, {}

    @staticmethod
    def _remember(cache: dict, key, value):
        cache[key] = value
        if len(cache) > _CACHED_POINTS:
            cache.pop(next(iter(cache)))
        return value

    def tests(self, y: np.ndarray) -> dict:
        key = np.asarray(y, float).tobytes()
        hit = self._tests.get(key)
        return hit if hit is not None else self._remember(self._tests, key, self.pb.tests(y))

    def branch(self, y: np.ndarray, t: np.ndarray) -> float:
        key = (np.asarray(y, float).tobytes(), np.asarray(t, float).tobytes())
        hit = self._branch.get(key)
        return hit if hit is not None else self._remember(self._branch, key, branch_test(self.problem, y, t))

    def axes(self, y: np.ndarray) -> np.ndarray:
        key = ("axes", np.asarray(y, float).tobytes())
        hit = self._tests.get(key)
        return hit if hit is not None else self._remember(self._tests, key, np.asarray(self.pb.axes(y), float))

    def velocity(self, y: np.ndarray, t: np.ndarray) -> np.ndarray:
        key = (np.asarray(y, float).tobytes(), np.asarray(t, float).tobytes())
        hit = self._velocity.get(key)
        return hit if hit is not None else self._remember(self._velocity, key, axis_velocity(self.pb, y, t))


def branch_test(problem: CurveFunction, y: np.ndarray, t: np.ndarray) -> float:
    """``det[H'(y); tᵀ]``: changes sign at a simple branch point of the continued curve.

    Where the traced locus crosses another locus of the same equations (a fold curve
    meeting the other leg's fold: the corner of the mode's workspace), the orientation of
    the tangent relative to the curve's Jacobian flips.  Only for ``n − 1`` equations.
    """
    j = problem.jacobian(y)
    if j.shape[0] != j.shape[1] - 1:
        return 1.0
    return float(np.linalg.det(np.vstack([j, t[None, :]])))


def im_end(pb: LocusProblems, y: np.ndarray) -> np.ndarray:
    """The end of a curve next to IM: the IM configuration refined from ``y`` (:func:`locate_im`), else ``y``."""
    exact = locate_im(pb, y)
    return y if exact is None else exact


def outside(pb: LocusProblems, y: np.ndarray, box: np.ndarray) -> bool:
    """Whether ``y``'s dimensionless axes lie outside ``box`` (2, 2)."""
    a = pb.axes(y)
    return bool(np.any(a < box[:, 0]) or np.any(a > box[:, 1]))


def onto_box(pb: LocusProblems, problem: CurveFunction, y_in: np.ndarray, y_out: np.ndarray,
             box: np.ndarray) -> np.ndarray:
    """The curve point on the box edge between ``y_in`` (inside) and ``y_out`` (outside)."""
    a_in, a_out = pb.axes(y_in), pb.axes(y_out)
    best, which, edge = 2.0, None, None
    for k in range(2):
        for side in (0, 1):
            e = box[k, side]
            if (a_out[k] - e) * (a_in[k] - e) < 0:
                u = (e - a_in[k]) / (a_out[k] - a_in[k])
                if u < best:
                    best, which, edge = u, k, e
    if which is None:
        return y_in
    guess = y_in + best * (y_out - y_in)

    def with_edge(y, k=which, e=edge):
        r, j = problem.residual_and_jacobian(y)
        a, ja = pb.axes_and_jacobian(y)
        return np.append(r, float(a[k]) - e), np.vstack([j, np.asarray(ja)[k:k + 1, :]])

    try:
        return gauss_newton(with_edge, guess, tol=LOCUS_NEWTON_TOL,
                            max_iterations=POLISH_ITERATIONS).raise_unless_converged("box edge").z
    except NotConvergedError:
        return y_in


@dataclass(frozen=True)
class _Ending:
    """What the map layer makes of a step rule's end: the last curve points to add and the end configuration."""

    tail: tuple = ()
    end_y: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class LeavesRegion(StepRule):
    """The curve leaves the mode (``T_b`` leaves ``sign_b``; not along the boundary itself) or meets another locus.

    Located by sign change (:func:`~symkin.curves.locate.locate_sign_change`); an end where
    the IM indicator is below ``near_branch`` is the IM point (:func:`locate_im`); an end
    outside the box is moved onto the box.  A curve that starts on the boundary and leaves
    the mode at once ends at its start (nothing to add).
    """

    at: PointTests = field(repr=False)
    kind: str
    boundary: tuple
    box: np.ndarray = field(repr=False)
    tol: Tolerances = field(repr=False)
    message: str = "the curve left the mode or met another locus"

    def check(self, problem, history, point):
        prev = history[-1]
        kind_b, sign_b = self.boundary
        crossed = self.kind != kind_b and math.copysign(1.0, self.at.tests(point.y)[kind_b]) != sign_b
        branched = self.at.branch(point.y, point.t) * self.at.branch(prev.y, prev.t) < 0
        if not (crossed or branched):
            return None
        pb = self.at.pb
        reason = END_BOUNDARY if crossed else END_BRANCH
        if crossed and self.at.tests(prev.y)[kind_b] * sign_b <= 0:
            return StepEnd(reason, data=_Ending((), prev.y))
        if crossed:
            test = EventType(str(kind_b), lambda yy, tt: pb.tests(yy)[kind_b])
        else:
            test = EventType(END_BRANCH, lambda yy, tt: branch_test(problem, yy, tt))
        try:
            end_y = locate_sign_change(problem, test, prev, point).y
        except (NotConvergedError, ValueError):
            end_y = prev.y
        if pb.tests(end_y)["im"] < self.tol.near_branch:
            exact = locate_im(pb, end_y)  # an event next to IM is the IM point (Tolerances.near_branch)
            if exact is not None:
                return StepEnd(str(Kind.IM), data=_Ending((end_y,), exact))
        if outside(pb, end_y, self.box):
            return StepEnd(str(Kind.BOX), data=_Ending((onto_box(pb, problem, prev.y, end_y, self.box),), None))
        return StepEnd(reason, data=_Ending((end_y,), end_y))


@dataclass(frozen=True, eq=False)
class OnBox(StepRule):
    """The curves' :class:`~symkin.curves.events.LeftBox` on a step: the last point is moved onto the box edge."""

    at: PointTests = field(repr=False)
    box: np.ndarray = field(repr=False)
    reason: str = str(Kind.BOX)
    message: str = "the curve left the box"

    @property
    def rule(self) -> LeftBox:
        return LeftBox(self.box[:, 0], self.box[:, 1], self.at.pb.axes)

    def check(self, problem, history, point):
        if not self.rule.reached(point, 0.0):
            return None
        return StepEnd(self.reason, data=_Ending((onto_box(self.at.pb, problem, history[-1].y, point.y, self.box),)))


@dataclass(frozen=True, eq=False)
class NearIM(StepRule):
    """The curve reached IM (``T`` is not defined there): the IM indicator below ``near_branch``, or a test not finite."""

    at: PointTests = field(repr=False)
    tol: Tolerances = field(repr=False)
    reason: str = str(Kind.IM)
    message: str = "the curve reached IM"

    def check(self, problem, history, point):
        t = self.at.tests(point.y)
        if t["im"] < self.tol.near_branch or not all(math.isfinite(t[k]) for k in KINDS):
            return StepEnd(self.reason, keep=True, data=_Ending((), im_end(self.at.pb, point.y)))
        return None


@dataclass(frozen=True, eq=False)
class IMMinimum(StepRule):
    """A local minimum of the relative IM indicator ``σ_{F+1}`` within about a step of zero: loci meeting at IM.

    It changes by about the step over a step, so a minimum below ``max_step`` is located
    (:func:`~symkin.curves.locate.locate_minimum`, accepted below ``near_branch``).
    """

    at: PointTests = field(repr=False)
    tol: Tolerances = field(repr=False)
    max_step: float
    reason: str = str(Kind.IM)
    message: str = "the curve met IM"

    def check(self, problem, history, point):
        if len(history) < 2:
            return None
        a, b = history[-2:]
        ra, rb, rc = (self.at.tests(p.y)["im"] for p in (a, b, point))
        if not (rb < ra and rb < rc and rb <= self.max_step):
            return None
        pb = self.at.pb
        test = EventType("im", lambda yy, tt: pb.tests(yy)["im"], signed=False, threshold=self.tol.near_branch)
        ev = locate_minimum(problem, test, a, b, point)
        if ev is None:
            return None
        return StepEnd(self.reason, data=_Ending((ev.y,), im_end(pb, ev.y)))


@dataclass(frozen=True, eq=False)
class LeavesBoundaryAt(StepRule):
    """A double-zero curve leaves the mode: ends at the last point (not located)."""

    at: PointTests = field(repr=False)
    kind: str
    boundary: tuple
    reason: str = END_BOUNDARY
    message: str = "the curve left the mode"

    def check(self, problem, history, point):
        kind_b, sign_b = self.boundary
        if self.kind != kind_b and math.copysign(1.0, self.at.tests(point.y)[kind_b]) != sign_b:
            return StepEnd(self.reason, data=_Ending((), history[-1].y))
        return None


@dataclass(frozen=True, eq=False)
class LeavesDoubleZero(StepRule):
    """The slope's zero set leaves the double zero: ``|T| > event_threshold`` (another branch); ends at the last point."""

    at: PointTests = field(repr=False)
    kind: str
    tol: Tolerances = field(repr=False)
    reason: str = END_LEFT
    message: str = "the curve left the double zero"

    def check(self, problem, history, point):
        if not abs(self.at.tests(point.y)[self.kind]) <= self.tol.event_threshold:
            return StepEnd(self.reason, data=_Ending((), history[-1].y))
        return None


@dataclass(frozen=True, eq=False)
class PointImage(StepRule):
    """The curve's image in the axes is one point: over two steps in a row the axes stay put while ``y`` moves.

    Each step's axis displacement is at most :attr:`Tolerances.same_configuration` times its
    configuration displacement (both dimensionless; independent of the step size).  A regular
    curve's image moves by a fraction of order one of the step (near a cusp by about the
    step times the distance to it; a cusp is an isolated stop), so an image that stays put
    over two steps stays put on the whole (analytic) curve: a family of configurations over
    one map point (e.g. a leg of zero length turning freely about its pivot).  Ends
    :data:`END_POINT`; the caller reports one point there, not a curve.
    """

    at: PointTests = field(repr=False)
    tol: Tolerances = field(repr=False)
    reason: str = END_POINT
    message: str = "the curve's image in the axes is one point"

    def check(self, problem, history, point):
        if len(history) < 2:
            return None
        pts = (*history[-2:], point)
        a = [self.at.axes(p.y) for p in pts]
        if all(np.linalg.norm(a[k + 1] - a[k]) <= self.tol.same_configuration * np.linalg.norm(pts[k + 1].y - pts[k].y)
               for k in (0, 1)):
            return StepEnd(self.reason, data=_Ending((), None))
        return None


def meeting_event(at: PointTests, interior: str) -> EventType:
    """The interior test's sign change along a boundary curve: a meeting point (every located root)."""
    return _Robust(str(Kind.MEETING), lambda y, t: at.tests(y)[interior], kind=Kind.MEETING, any_root=True)


@dataclass(frozen=True)
class _Robust(EventType):
    """An event type whose failed location is no event (not the end of the trace)."""

    def locate(self, problem, a, b, c=None, rank=Tolerances().rank):
        try:
            return super().locate(problem, a, b, c, rank)
        except (NotConvergedError, ValueError):
            return None


@dataclass(frozen=True)
class CuspEvent(EventType):
    """The axis velocity turns back within a step (``v(a) · v(b) < 0``): a cusp of the curve's image, if located.

    The value is the axis velocity (a vector); located by :func:`locate_cusp_event`.
    """

    at: PointTests | None = field(default=None, repr=False)
    tol: Tolerances = field(default_factory=Tolerances, repr=False)

    def brackets_root(self, fa, fb) -> bool:
        return float(np.asarray(fa) @ np.asarray(fb)) < 0.0

    def brackets_minimum(self, fa, fb, fc) -> bool:
        return False

    def locate(self, problem, a: CurvePoint, b: CurvePoint, c=None, rank=Tolerances().rank):
        ev = locate_cusp_event(self.at.pb, problem, a, b, self.at.velocity(a.y, a.t), self.tol)
        return None if ev is None else (self.kind, CurveEvent(self.name, ev.kind, ev.y, ev.t, ev.s, ev.value,
                                                              ev.evaluations))


def cusp_event(at: PointTests, tol: Tolerances) -> CuspEvent:
    """The cusp event type of a trace (:class:`CuspEvent`)."""
    return CuspEvent(str(Kind.CUSP), lambda y, t: at.velocity(y, t), kind=Kind.CUSP, at=at, tol=tol)
