"""Tracing a map's singular curves from a located point, both ways, to their ends (closed, box, boundary,
branch, IM, point); curves of double zeros through the slope of the test function.

The mechanism layer over the one tracer, :func:`symkin.curves.tracer.trace_curve`: the
events and stop rules are the objects of :mod:`symkin.workspace.locus_events`, the closed-curve
rule is the curves' :class:`~symkin.curves.events.Closed`.

See :mod:`symkin.workspace.loci` (step 3).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from symkin.curves.events import Closed, StopRule
from symkin.curves.stepper import CurvePoint, Settings, tangent
from symkin.curves.tracer import TracedCurve, trace_curve
from symkin.kinds import Kind
from symkin.tolerances import DEFAULT, Tolerances
from symkin.workspace.locus_events import (END_POINT, IMMinimum, LeavesBoundaryAt, LeavesDoubleZero, LeavesRegion,
                                           NearIM, OnBox, PointImage, PointTests, cusp_event, meeting_event)
from symkin.workspace.locus_problems import OTHER_KIND, LocusProblems

__all__ = ["segment_distance", "polyline_distance", "trace_locus", "trace_double_zero", "HalfCurve",
           "CLOSED_ARCLENGTH", "CLOSED_RADIUS"]

#: a map curve is closed only past this many (maximal) steps of arclength
CLOSED_ARCLENGTH = 3.0
#: ... when it crosses its start's normal plane within this many (maximal) steps of its start
CLOSED_RADIUS = 1.0


# ---------------------------------------------------------------------- tracing
def segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    ab = b - a
    den = float(ab @ ab)
    u = 0.0 if den == 0 else min(1.0, max(0.0, float((p - a) @ ab) / den))
    return float(np.linalg.norm(p - (a + u * ab)))


def polyline_distance(p: np.ndarray, poly: np.ndarray, closed: bool) -> float:
    if len(poly) == 1:
        return float(np.linalg.norm(p - poly[0]))
    a, b = poly[:-1], poly[1:]
    if closed:
        a, b = np.vstack([a, poly[-1:]]), np.vstack([b, poly[:1]])
    ab = b - a
    den = np.einsum("ij,ij->i", ab, ab)
    u = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.where(den > 0, den, 1), 0, 1)
    return float(np.min(np.linalg.norm(p - (a + u[:, None] * ab), axis=1)))



@dataclass
class HalfCurve:
    ys: list
    end: str
    end_y: np.ndarray | None = None
    meetings: list = field(default_factory=list)
    cusps: list = field(default_factory=list)


#: the tracer's stop reasons in a map curve's ends
_REASONS = {"max_steps": "steps", "stuck": "stalled", str(Kind.CLOSED): Kind.CLOSED}


def _closed(y0: np.ndarray, t0: np.ndarray, settings: Settings, travelled: float = 0.0) -> Closed:
    """The curves' closed-curve rule for a map curve started at ``y0`` along ``t0``.

    Closed once past :data:`CLOSED_ARCLENGTH` steps (``travelled`` already behind, for a
    curve traced in pieces) and within :data:`CLOSED_RADIUS` steps of its start.
    """
    return Closed(np.array(y0, float), np.array(t0, float), CLOSED_ARCLENGTH * settings.max_step - travelled,
                  CLOSED_RADIUS * settings.max_step)


def _half(traced: TracedCurve, first: int = 0) -> tuple[list, str, np.ndarray | None]:
    """The recorded points from ``first``, the end's name and end configuration of one traced piece."""
    ys = [np.array(p.point.y, float) for p in traced.points[first:]]
    stop = traced.stop
    end, end_y = _REASONS.get(stop.reason, stop.reason), None
    if stop.data is not None:
        ys.extend(stop.data.tail)
        end_y = stop.data.end_y
    return ys, end, end_y


def _trace_half(pb: LocusProblems, kind: str, y0: np.ndarray, t0: np.ndarray, box: np.ndarray,
                settings: Settings, tol: Tolerances, start: CurvePoint, boundary: tuple[str, float]) -> HalfCurve:
    """Continue from ``y0`` along ``t0`` until closed / box / boundary / branch / IM / stalled (the one tracer).

    ``boundary = (kind_b, sign_b)``: the test function whose zero set is the mode's
    workspace boundary and its sign inside the mode.  An interior curve (``kind ≠ kind_b``)
    stops where ``T_b`` leaves ``sign_b``; along a boundary curve the sign changes of the
    interior test function are *meeting points* (located, returned in ``meetings``: an
    interior curve starts there).  The events and rules: :mod:`symkin.workspace.locus_events`.
    """
    problem = pb.curve(kind)
    at = PointTests(pb, problem)
    kind_b, _ = boundary
    events = [cusp_event(at, tol)]
    if kind == kind_b:
        events.insert(0, meeting_event(at, OTHER_KIND[kind_b]))
    stops = [LeavesRegion(at, kind, boundary, box, tol), OnBox(at, box), NearIM(at, tol),
             IMMinimum(at, tol, settings.max_step), PointImage(at, tol), _closed(start.y, start.t, settings)]
    traced = trace_curve(problem, np.array(y0, float), t0, events=events, stops=stops, settings=settings,
                         priority=(Kind.MEETING, Kind.CUSP), tolerances=tol)
    ys, end, end_y = _half(traced)
    if end == END_POINT:
        # the image stopped: keep one point over the final axis point (the curve's end, classified by the caller)
        a_end = at.axes(ys[-1])
        while len(ys) > 1 and np.linalg.norm(at.axes(ys[-2]) - a_end) <= tol.same_configuration:
            ys.pop()
        end_y = ys[-1]
    meetings = [e.y for e in traced.events if str(Kind.MEETING) in e.tests]
    cusps = [e.y for e in traced.events if str(Kind.CUSP) in e.tests]
    return HalfCurve(ys, end, end_y, meetings, cusps)


def trace_locus(pb: LocusProblems, kind: str, y0: np.ndarray, box: np.ndarray, settings: Settings,
                tol: Tolerances = DEFAULT, boundary: tuple[str, float] = (Kind.DKP_OUTPUT, 1.0)
                ) -> tuple[np.ndarray, bool, tuple[str, ...], list, list, list]:
    """Trace the locus ``kind`` through ``y0`` both ways.

    Returns ``(ys, closed, ends, end points, meeting points, cusps)`` in ``y = q/ℓ`` (see
    :func:`_trace_half` for ``boundary``, :func:`locate_cusp` for the cusps: located on the
    way, they neither stop nor split the curve).  A "curve" whose image in the axes is one
    point (:class:`~symkin.workspace.locus_events.PointImage`) returns ``([y0], False,
    ("point",), [y0], [], [])``: the caller reports one point; a curve that runs into such a
    family ends there (end ``"point"``, its end point the first configuration over that map point).
    """
    problem = pb.curve(kind)
    t0 = tangent(problem, y0)
    start = CurvePoint(np.array(y0, float), t0, 0.0)
    fwd = _trace_half(pb, kind, y0, t0, box, settings, tol, start, boundary)
    if fwd.end == END_POINT and len(fwd.ys) == 1:  # one point of the map, not a curve: nothing located is kept
        return np.array([y0], float), False, (END_POINT,), [np.array(y0, float)], [], []
    if fwd.end == Kind.CLOSED:
        if _one_point(pb, np.array(fwd.ys), tol):
            return np.array([y0], float), False, (END_POINT,), [np.array(y0, float)], [], []
        return np.array(fwd.ys), True, (Kind.CLOSED,), [], fwd.meetings, fwd.cusps
    bwd = _trace_half(pb, kind, y0, -t0, box, settings, tol, CurvePoint(start.y, -t0, 0.0), boundary)
    ys = np.array(bwd.ys[:0:-1] + fwd.ys)
    ends = (bwd.end, fwd.end)
    if _one_point(pb, ys, tol, END_POINT in ends):  # a family of configurations over one map point
        return np.array([y0], float), False, (END_POINT,), [np.array(y0, float)], [], []
    return (ys, False, ends, [h.end_y for h in (bwd, fwd) if h.end_y is not None], bwd.meetings + fwd.meetings,
            bwd.cusps + fwd.cusps)


def _one_point(pb: LocusProblems, ys: np.ndarray, tol: Tolerances, family: bool = False) -> bool:
    """Whether the curve points ``ys`` are a family over one map point: distinct configurations, one image.

    Both within :attr:`Tolerances.same_configuration` (dimensionless): the image in the axes
    is one point while the configurations are not one (a curve that leaves the box at once
    on both sides has one image and one configuration: it is no family), or ``family`` (a
    half ended on such a family: its points over the map point were trimmed to one).
    """
    ys = np.asarray(ys, float)
    a = np.array([pb.axes(y) for y in ys])
    return bool(np.all(np.linalg.norm(a - a[0], axis=1) <= tol.same_configuration)
                and (family or np.max(np.linalg.norm(ys - ys[0], axis=1)) > tol.same_configuration))


def _perp(v: np.ndarray) -> np.ndarray:
    return np.array([-v[1], v[0]]) / np.linalg.norm(v)


def _axis_tangent(pb: LocusProblems, y: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The curve's tangent ``t`` (in ``y``) as a direction of the dimensionless axes."""
    v = np.array(pb.axes_and_jacobian(y)[1]) @ t
    return v / np.linalg.norm(v)


#: a double-zero curve is followed as ``∂T/∂n = 0`` with ``n`` frozen while it stays within this angle
#: of the curve's normal (``∂T/∂n`` is a regular equation of the curve while ``n`` is not along it)
_NORMAL_TURN = math.radians(30.0)


@dataclass(frozen=True, eq=False)
class _Turned(StopRule):
    """The double-zero curve turned by more than :data:`_NORMAL_TURN` from the frozen normal ``n``: restart."""

    pb: LocusProblems = field(repr=False)
    n: np.ndarray = field(repr=False)
    reason: str = "turned"
    message: str = "the curve turned away from the frozen normal"

    def reached(self, point, parameter) -> bool:
        return abs(float(_perp(_axis_tangent(self.pb, point.y, point.t)) @ self.n)) < math.cos(_NORMAL_TURN)


def _trace_double_half(pb: LocusProblems, kind: str, y0: np.ndarray, t0: np.ndarray, box: np.ndarray,
                       settings: Settings, tol: Tolerances, boundary: tuple[str, float]) -> HalfCurve:
    """One direction of a double-zero curve (see :func:`trace_double_zero`): pieces of the one tracer."""
    out = [np.array(y0, float)]
    y, t_prev, travelled = np.array(y0, float), np.array(t0, float), 0.0
    while True:
        n = _perp(_axis_tangent(pb, y, t_prev))
        problem = pb.slope_curve(kind, n)
        at = PointTests(pb, problem)
        stops = [LeavesBoundaryAt(at, kind, boundary), OnBox(at, box), NearIM(at, tol), LeavesDoubleZero(at, kind, tol),
                 _closed(y0, t0, settings, travelled), _Turned(pb, n)]
        traced = trace_curve(problem, y, t_prev, stops=stops, settings=settings, tolerances=tol)
        ys, end, end_y = _half(traced, first=1)
        out.extend(ys)
        if end != "turned":
            return HalfCurve(out, end, end_y, [])
        last = traced.points[-1].point
        y, t_prev, travelled = last.y, last.t, travelled + last.s


def trace_double_zero(pb: LocusProblems, kind: str, y0: np.ndarray, box: np.ndarray, settings: Settings,
                      tol: Tolerances = DEFAULT, boundary: tuple[str, float] = (Kind.DKP_OUTPUT, 1.0)
                      ) -> tuple[np.ndarray, bool, tuple[str, ...], list, list, list]:
    """Trace a curve of double zeros of ``T`` (``kind``) through ``y0`` both ways.

    ``(Φ/ℓ, holds, T) = 0`` is singular along such a curve (``∇T = 0`` on the surface), so
    the curve is continued as ``(Φ/ℓ, holds, ∂T/∂n) = 0`` (:meth:`LocusProblems.slope_curve`,
    regular there), with ``n`` the curve's normal in the dimensionless axes, renewed when
    the curve turns by more than 30° from it.  Each point must keep ``|T| ≤``
    :attr:`Tolerances.event_threshold` (else the slope's zero set has left the double zero:
    end ``"left"``); ends as :func:`trace_locus` (closed, box, boundary, IM, stalled).
    Returns what :func:`trace_locus` returns.
    """
    problem = pb.slope_curve(kind, np.array([1.0, 0.0]))
    t0 = tangent(problem, y0)
    n0 = _perp(_axis_tangent(pb, y0, t0))
    t0 = tangent(pb.slope_curve(kind, n0), y0, t0)
    fwd = _trace_double_half(pb, kind, y0, t0, box, settings, tol, boundary)
    if fwd.end == Kind.CLOSED:
        if _one_point(pb, np.array(fwd.ys), tol):
            return np.array([y0], float), False, (END_POINT,), [np.array(y0, float)], [], []
        return np.array(fwd.ys), True, (Kind.CLOSED,), [], [], []
    bwd = _trace_double_half(pb, kind, y0, -t0, box, settings, tol, boundary)
    ys = np.array(bwd.ys[:0:-1] + fwd.ys)
    return ys, False, (bwd.end, fwd.end), [h.end_y for h in (bwd, fwd) if h.end_y is not None], [], []
