"""Tracing a map's singular curves from a located point, both ways, to their ends (closed, box, boundary,
branch, IM); curves of double zeros through the slope of the test function.

See :mod:`symkin.workspace.loci` (step 3).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from symkin.errors import NotConvergedError
from symkin.curves.corrector import gauss_newton
from symkin.paths.continuation import CurvePoint, Settings, continue_curve, tangent
from symkin.paths.events import TestFunction, locate_minimum, locate_sign_change
from symkin.kinds import Kind
from symkin.tolerances import DEFAULT, Tolerances
from symkin.workspace.cusps import axis_velocity, locate_cusp
from symkin.workspace.im_points import locate_im
from symkin.workspace.locus_problems import (KINDS, LOCUS_NEWTON_TOL, OTHER_KIND, POLISH_ITERATIONS, CurveFunction,
                                             LocusProblems)

__all__ = ["segment_distance", "polyline_distance", "trace_locus", "trace_double_zero", "HalfCurve"]


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


def _trace_half(pb: LocusProblems, kind: str, y0: np.ndarray, t0: np.ndarray, box: np.ndarray,
                settings: Settings, tol: Tolerances, start: CurvePoint, boundary: tuple[str, float]) -> HalfCurve:
    """Continue from ``y0`` along ``t0`` until closed / box / boundary / branch / IM / stalled.

    ``boundary = (kind_b, sign_b)``: the test function whose zero set is the mode's
    workspace boundary and its sign inside the mode.  An interior curve (``kind ≠ kind_b``)
    stops where ``T_b`` leaves ``sign_b``; along a boundary curve the sign changes of the
    interior test function are *meeting points* (located, returned in ``meetings``: an
    interior curve starts there).
    """
    problem = pb.curve(kind)
    kind_b, sign_b = boundary
    interior = OTHER_KIND[kind_b]
    out = [np.array(y0, float)]
    prev = None
    end, end_y, meetings = "steps", None, []
    branch = TestFunction("branch", lambda yy, tt: _branch_test(problem, yy, tt))
    b_prev = branch.f(y0, t0)
    i_prev = pb.tests(y0)[interior]
    im_test = TestFunction("im", lambda yy, tt: pb.tests(yy)["im"], signed=False, threshold=tol.near_branch)
    pprev, r_pprev, r_prev = None, math.inf, pb.tests(y0)["im"]
    cusps: list = []
    v_prev = axis_velocity(pb, y0, t0)
    try:
        for point in continue_curve(problem, y0, t0, settings):
            if prev is None:
                prev = point
                continue
            a = pb.axes(point.y)
            t = pb.tests(point.y)
            b_now = branch.f(point.y, point.t)
            crossed = kind != kind_b and math.copysign(1.0, t[kind_b]) != sign_b
            branched = b_now * b_prev < 0
            outside = bool(np.any(a < box[:, 0]) or np.any(a > box[:, 1]))
            if crossed or branched:
                # the mode's boundary or another locus between prev and point (checked before the box: a step
                # may cross both, and past the boundary the curve belongs to another mode)
                test = TestFunction(kind_b, lambda yy, tt: pb.tests(yy)[kind_b]) if crossed else branch
                end = "boundary" if crossed else "branch"
                if crossed and pb.tests(prev.y)[kind_b] * sign_b <= 0:
                    end_y = prev.y  # started on the boundary and left the mode at once: nothing to add
                    break
                try:
                    end_y = locate_sign_change(problem, test, prev, point).y
                except (NotConvergedError, ValueError):
                    end_y = prev.y
                if pb.tests(end_y)["im"] < tol.near_branch:
                    # an event next to IM is the IM point (as ``trace`` does, Tolerances.near_branch)
                    exact = locate_im(pb, end_y)
                    if exact is not None:
                        out.append(end_y)
                        end, end_y = Kind.IM, exact
                        break
                ae = pb.axes(end_y)
                if np.any(ae < box[:, 0]) or np.any(ae > box[:, 1]):
                    out.append(_onto_box(pb, problem, prev.y, end_y, box))
                    end, end_y = Kind.BOX, None
                else:
                    out.append(end_y)
                break
            if outside:
                out.append(_onto_box(pb, problem, prev.y, point.y, box))
                end = Kind.BOX
                break
            if t["im"] < tol.near_branch or not all(math.isfinite(t[k]) for k in KINDS):
                # T is not defined at IM: the curve ends here; the IM configuration is refined
                end, end_y = Kind.IM, _im_end(pb, point.y)
                out.append(point.y)
                break
            if pprev is not None and r_prev < r_pprev and r_prev < t["im"] and r_prev <= settings.max_step:
                # a local minimum of the relative IM indicator σ_{F+1}, within about a step of zero (it changes
                # by about the step over a step): an IM point where loci meet?
                ev_im = locate_minimum(problem, im_test, pprev, prev, point)
                if ev_im is not None:
                    end, end_y = Kind.IM, _im_end(pb, ev_im.y)
                    out.append(ev_im.y)
                    break
            if kind == kind_b and t[interior] * i_prev < 0:
                test = TestFunction(interior, lambda yy, tt: pb.tests(yy)[interior])
                try:
                    meetings.append(locate_sign_change(problem, test, prev, point).y)
                except (NotConvergedError, ValueError):
                    pass
            v_now = axis_velocity(pb, point.y, point.t)
            if float(v_now @ v_prev) < 0.0:
                # the axis velocity turned back within the step: a cusp of the curve's projection?
                cusp = locate_cusp(pb, problem, prev, point, v_prev, tol)
                if cusp is not None:
                    cusps.append(cusp)
            b_prev, i_prev, v_prev = b_now, t[interior], v_now
            pprev, r_pprev, r_prev = prev, r_prev, t["im"]
            if point.s > 3 * settings.max_step and float(point.t @ start.t) > 0.5 and \
                    segment_distance(start.y, prev.y, point.y) <= 0.25 * float(np.linalg.norm(point.y - prev.y)):
                end = Kind.CLOSED
                break
            out.append(point.y)
            prev = point
    except NotConvergedError:  # SteppingError, or a residual/Jacobian that is not finite
        end = "stalled"
    return HalfCurve(out, end, end_y, meetings, cusps)


def _im_end(pb: LocusProblems, y: np.ndarray) -> np.ndarray:
    """The end of a curve next to IM: the IM configuration refined from ``y`` (:func:`locate_im`), else ``y``."""
    exact = locate_im(pb, y)
    return y if exact is None else exact


def _branch_test(problem: CurveFunction, y: np.ndarray, t: np.ndarray) -> float:
    """``det[H'(y); tᵀ]``: changes sign at a simple branch point of the continued curve.

    Where the traced locus crosses another locus of the same equations (a fold curve
    meeting the other leg's fold: the corner of the mode's workspace), the orientation of
    the tangent relative to the curve's Jacobian flips.  Only for ``n − 1`` equations.
    """
    j = problem.jacobian(y)
    if j.shape[0] != j.shape[1] - 1:
        return 1.0
    return float(np.linalg.det(np.vstack([j, t[None, :]])))


def _onto_box(pb: LocusProblems, problem: CurveFunction, y_in: np.ndarray, y_out: np.ndarray, box: np.ndarray) -> np.ndarray:
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


def trace_locus(pb: LocusProblems, kind: str, y0: np.ndarray, box: np.ndarray, settings: Settings,
                tol: Tolerances = DEFAULT, boundary: tuple[str, float] = (Kind.DKP_OUTPUT, 1.0)
                ) -> tuple[np.ndarray, bool, tuple[str, ...], list, list, list]:
    """Trace the locus ``kind`` through ``y0`` both ways.

    Returns ``(ys, closed, ends, end points, meeting points, cusps)`` in ``y = q/ℓ`` (see
    :func:`_trace_half` for ``boundary``, :func:`locate_cusp` for the cusps: located on the
    way, they neither stop nor split the curve).
    """
    problem = pb.curve(kind)
    t0 = tangent(problem, y0)
    start = CurvePoint(np.array(y0, float), t0, 0.0)
    fwd = _trace_half(pb, kind, y0, t0, box, settings, tol, start, boundary)
    if fwd.end == Kind.CLOSED:
        return np.array(fwd.ys), True, (Kind.CLOSED,), [], fwd.meetings, fwd.cusps
    bwd = _trace_half(pb, kind, y0, -t0, box, settings, tol, CurvePoint(start.y, -t0, 0.0), boundary)
    ys = np.array(bwd.ys[:0:-1] + fwd.ys)
    ends = (bwd.end, fwd.end)
    return (ys, False, ends, [h.end_y for h in (bwd, fwd) if h.end_y is not None], bwd.meetings + fwd.meetings,
            bwd.cusps + fwd.cusps)


def _perp(v: np.ndarray) -> np.ndarray:
    return np.array([-v[1], v[0]]) / np.linalg.norm(v)


def _axis_tangent(pb: LocusProblems, y: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The curve's tangent ``t`` (in ``y``) as a direction of the dimensionless axes."""
    v = np.array(pb.axes_and_jacobian(y)[1]) @ t
    return v / np.linalg.norm(v)


#: a double-zero curve is followed as ``∂T/∂n = 0`` with ``n`` frozen while it stays within this angle
#: of the curve's normal (``∂T/∂n`` is a regular equation of the curve while ``n`` is not along it)
_NORMAL_TURN = math.radians(30.0)


def _trace_double_half(pb: LocusProblems, kind: str, y0: np.ndarray, t0: np.ndarray, box: np.ndarray,
                       settings: Settings, tol: Tolerances, boundary: tuple[str, float]) -> HalfCurve:
    """One direction of a double-zero curve (see :func:`trace_double_zero`)."""
    kind_b, sign_b = boundary
    out = [np.array(y0, float)]
    start_t, y, t_prev = np.array(t0, float), np.array(y0, float), np.array(t0, float)
    arclength = 0.0
    end, end_y = "steps", None
    try:
        while True:
            n = _perp(_axis_tangent(pb, y, t_prev))
            problem = pb.slope_curve(kind, n)
            prev, restart = None, False
            for point in continue_curve(problem, y, t_prev, settings):
                if prev is None:
                    prev = point
                    continue
                arclength += float(np.linalg.norm(point.y - prev.y))
                a = pb.axes(point.y)
                t = pb.tests(point.y)
                if kind != kind_b and math.copysign(1.0, t[kind_b]) != sign_b:
                    end, end_y = "boundary", prev.y
                    break
                if np.any(a < box[:, 0]) or np.any(a > box[:, 1]):
                    out.append(_onto_box(pb, problem, prev.y, point.y, box))
                    end = Kind.BOX
                    break
                if t["im"] < tol.near_branch:
                    end, end_y = Kind.IM, _im_end(pb, point.y)
                    out.append(point.y)
                    break
                if not abs(t[kind]) <= tol.event_threshold:
                    end, end_y = "left", prev.y  # the slope's zero set leaves the double zero (another branch)
                    break
                if arclength > 3 * settings.max_step and float(point.t @ start_t) > 0.5 and \
                        segment_distance(y0, prev.y, point.y) <= 0.25 * float(np.linalg.norm(point.y - prev.y)):
                    end = Kind.CLOSED
                    break
                out.append(point.y)
                prev = point
                if abs(float(_perp(_axis_tangent(pb, point.y, point.t)) @ n)) < math.cos(_NORMAL_TURN):
                    y, t_prev, restart = point.y, point.t, True
                    break
            if not restart:
                break
    except NotConvergedError:
        end = "stalled"
    return HalfCurve(out, end, end_y, [])


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
        return np.array(fwd.ys), True, (Kind.CLOSED,), [], [], []
    bwd = _trace_double_half(pb, kind, y0, -t0, box, settings, tol, boundary)
    ys = np.array(bwd.ys[:0:-1] + fwd.ys)
    return ys, False, (bwd.end, fwd.end), [h.end_y for h in (bwd, fwd) if h.end_y is not None], [], []
