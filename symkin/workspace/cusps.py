"""Cusps of a traced locus' image in the map's axes: the axis velocity along the curve and its zeros.

See :mod:`symkin.workspace.loci` (step 3).
"""
from __future__ import annotations

import numpy as np

from symkin.errors import NotConvergedError
from symkin.curves.events import EventType as TestFunction
from symkin.curves.locate import CurveEvent, locate_sign_change
from symkin.curves.stepper import CurvePoint
from symkin.kinds import Kind
from symkin.tolerances import DEFAULT, Tolerances
from symkin.workspace.locus_problems import CurveFunction, LocusProblems

__all__ = ["axis_velocity", "relative_axis_speed", "locate_cusp", "locate_cusp_event"]


def axis_velocity(pb: LocusProblems, y: np.ndarray, t: np.ndarray) -> np.ndarray:
    """``dA/ds = ∂A/∂y · t``: the velocity of the dimensionless axes along the curve's unit tangent ``t``."""
    return np.array(pb.axes_and_jacobian(y)[1]) @ np.asarray(t, float)


def relative_axis_speed(pb: LocusProblems, y: np.ndarray, t: np.ndarray) -> float:
    """``‖∂A/∂y · t‖ / ‖∂A/∂y‖₂``: how fast the axes move along the curve, relative to how fast they can.

    ``y = q/ℓ`` and ``A = a/axis_scale`` are dimensionless and ``t`` is a unit vector, so the
    ratio is the same for a model in millimetres and in metres (and under rigid motions).  It is
    zero exactly where the projection of the configuration-space curve onto the axes stops: a cusp.
    """
    ja = np.array(pb.axes_and_jacobian(y)[1])
    return float(np.linalg.norm(ja @ np.asarray(t, float)) / np.linalg.norm(ja, 2))


def locate_cusp(pb: LocusProblems, problem: CurveFunction, a: CurvePoint, b: CurvePoint, v_a: np.ndarray,
                tol: Tolerances = DEFAULT) -> np.ndarray | None:
    """A cusp of the curve's projection onto the axes between accepted curve points ``a`` and ``b``.

    A singular curve is smooth in configuration space; its image in the axes has a cusp where
    the axis velocity ``v = ∂A/∂y · t`` (:func:`axis_velocity`) vanishes while the curve moves
    (``t`` is a unit tangent): ``v`` turns back there, ``v(s) ≈ (s − s₀)·w``.  The caller
    brackets it by ``v(a) · v(b) < 0``; the root of the signed scalar ``v(s) · v(a)/‖v(a)‖`` is
    located along the curve (:func:`symkin.curves.locate.locate_sign_change`: Brent's method on
    the arclength of the Newton-projected curve, to ``1e-14``), where both components of ``v``
    vanish at a cusp.  It is a cusp when the relative axis speed there
    (:func:`relative_axis_speed`, scale invariant) is at most :attr:`Tolerances.event_threshold`
    (the core's threshold for a located zero of a path test, ``1e-7`` by default; a located cusp
    has ~1e-13, a curve that merely turns sharply within a step has a speed of order one).
    Returns the configuration ``y`` (dimensionless) or None.
    """
    ev = locate_cusp_event(pb, problem, a, b, v_a, tol)
    return None if ev is None else np.asarray(ev.y, float)


def locate_cusp_event(pb: LocusProblems, problem: CurveFunction, a: CurvePoint, b: CurvePoint, v_a: np.ndarray,
                      tol: Tolerances = DEFAULT) -> CurveEvent | None:
    """:func:`locate_cusp` as the located curve event (``y``, tangent, arclength), or None."""
    v_a = np.asarray(v_a, float)
    u = v_a / np.linalg.norm(v_a)
    test = TestFunction(Kind.CUSP, lambda yy, tt: float(axis_velocity(pb, yy, tt) @ u))
    try:
        ev = locate_sign_change(problem, test, a, b)
    except (NotConvergedError, ValueError):
        return None
    if relative_axis_speed(pb, ev.y, ev.t) <= tol.event_threshold:
        return ev
    return None

