"""Former home of the continuation: it lives in :mod:`symkin.curves.stepper`.

Kept for the callers outside the paths stage (``symkin.workspace.loci``,
``symkin.solutions.circuits``); ``newton`` is :func:`symkin.curves.stepper.correct`.
"""
from __future__ import annotations

from symkin.curves.stepper import (CurvePoint, CurveProblem, NonFiniteError, Settings, SteppingError, continue_curve,
                                   correct, point_at, tangent)

__all__ = ["CurveProblem", "Settings", "CurvePoint", "newton", "tangent", "continue_curve", "point_at",
           "SteppingError", "NonFiniteError"]

newton = correct
