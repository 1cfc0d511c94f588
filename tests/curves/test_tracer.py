"""The one tracer on curves with known answers: events located, merged, classified by kind; stop rules."""
from __future__ import annotations

import math

import numpy as np

from symkin.curves.events import (ArclengthLimit, Closed, EventType, LeftBox, ParameterReached, SingularEvent, StepEnd,
                                  StepRule)
from symkin.curves.stepper import Settings
from symkin.curves.tracer import trace_curve
from symkin.kinds import Kind


class Circle:
    """x² + y² = 1."""

    def residual(self, y):
        return np.array([y @ y - 1.0])

    def jacobian(self, y):
        return 2.0 * y[None, :]


Y0, T0 = np.array([1.0, 0.0]), np.array([0.0, 1.0])


def angle(y, reference):
    return reference + math.remainder(math.atan2(y[1], y[0]) - reference, 2 * math.pi)


def test_sign_changes_and_minima_located_and_merged_by_kind_priority():
    crossing = EventType("x", lambda y, t: float(y[0]), kind=Kind.DKP_INPUT)
    also = EventType("x again", lambda y, t: float(y[0]) ** 3, kind=Kind.LIM)
    touch = EventType("|x| if y > 0", lambda y, t: abs(float(y[0])) if y[1] > 0 else 1.0, signed=False,
                      threshold=1e-7, kind=Kind.IM)
    out = trace_curve(Circle(), Y0, T0, events=[also, crossing, touch],
                      stops=[Closed(Y0, T0, 0.2, 0.4), ArclengthLimit(10.0)], parameter=angle,
                      priority=(Kind.IM, Kind.DKP_INPUT, Kind.LIM))
    assert out.stop.reason == "closed"
    # x = 0 at 90° (also the minimum of the unsigned test: one event of kind IM) and at 270°
    assert [e.kind for e in out.events] == [Kind.IM, Kind.DKP_INPUT]
    assert [round(math.degrees(e.p), 6) for e in out.events] == [90.0, 270.0]
    assert set(out.events[0].tests) == {"x", "x again", "|x| if y > 0"}
    assert set(out.events[1].tests) == {"x", "x again"}
    for e in out.events:
        assert abs(float(e.y @ e.y) - 1.0) <= 1e-13


def test_parameter_reached_is_located_and_ends_the_trace():
    stop = ParameterReached(math.radians(100.0), 1.0, angle)
    out = trace_curve(Circle(), Y0, T0, stops=[stop, ArclengthLimit(10.0)], parameter=angle)
    assert out.stop.reason == "reached" and out.stop.event is not None
    assert abs(math.degrees(math.atan2(out.stop.event.y[1], out.stop.event.y[0])) - 100.0) <= 1e-10
    assert all(p.p < math.radians(100.0) for p in out.points)


def test_leaving_a_box_and_the_arclength_limit():
    box = LeftBox(np.array([-2.0, -2.0]), np.array([2.0, 0.5]), lambda y: y)
    out = trace_curve(Circle(), Y0, T0, stops=[box, ArclengthLimit(10.0)])
    assert out.stop.reason == "box" and out.points[-1].point.y[1] > 0.5
    out = trace_curve(Circle(), Y0, T0, stops=[ArclengthLimit(1.0)], settings=Settings(max_step=0.1))
    assert out.stop.reason == "max_arclength" and 1.0 < out.points[-1].point.s < 1.2


def test_a_curve_that_comes_back_meets_its_events_again():
    crossing = EventType("x", lambda y, t: float(y[0]), kind=Kind.DKP_INPUT)
    out = trace_curve(Circle(), Y0, T0, events=[crossing], stops=[ArclengthLimit(4 * math.pi + 0.1)],
                      parameter=angle)
    assert [round(math.degrees(e.p), 6) for e in out.events] == [90.0, 270.0, 450.0, 630.0]


class Lines:
    """(y0 − y1)(y0 + y1) = 0: two lines crossing at the origin, a simple branch point."""

    def residual(self, y):
        return np.array([y[0] ** 2 - y[1] ** 2])

    def jacobian(self, y):
        return np.array([[2 * y[0], -2 * y[1]]])


def test_a_singular_event_is_moved_onto_the_branch_point():
    start = np.array([-1.0, -1.0]) / math.sqrt(2)
    det = SingularEvent("det", lambda y, t: float(np.linalg.det(np.vstack([Lines().jacobian(y), t]))),
                        kind=Kind.IM, any_root=True)
    out = trace_curve(Lines(), start, np.array([1.0, 1.0]) / math.sqrt(2), events=[det],
                      stops=[ArclengthLimit(2.0)], priority=(Kind.IM,))
    assert [e.kind for e in out.events] == [Kind.IM]
    assert float(np.max(np.abs(out.events[0].y))) <= 1e-12


class LeavesUpperHalf(StepRule):
    """A caller's step rule: the step crosses ``y = 0`` downwards (the step's point kept when ``keep``)."""

    reason, message = "lower half", "left the upper half plane"

    def __init__(self, keep: bool):
        self.keep = keep

    def check(self, problem, history, point):
        if history[-1].y[1] >= 0 > point.y[1]:
            return StepEnd(self.reason, keep=self.keep, data=("found", float(point.y[1])))
        return None


def test_step_rule_ends_the_trace_before_the_step_events_and_passes_its_data():
    for keep in (False, True):
        x_axis = EventType("y", lambda y, t: float(y[1]), kind=Kind.DKP_INPUT)
        out = trace_curve(Circle(), Y0, T0, events=[x_axis],
                          stops=[LeavesUpperHalf(keep), Closed(Y0, T0, 0.2, 0.4), ArclengthLimit(10.0)])
        assert out.stop.reason == "lower half" and out.stop.data[0] == "found"
        assert out.stop.data[1] < 0 and out.stop.point.point.y[1] < 0
        # the crossing of y = 0 at 180° is on the step that ended the trace: not located
        assert not out.events
        last = out.points[-1].point.y
        assert (last[1] < 0) == keep and abs(last[0] + 1.0) < 0.5
