"""Former home of the continuation: it lives in :mod:`symkin.curves.stepper`.

Kept for the callers outside the paths stage (``symkin.workspace``, ``symkin.solutions.circuits``).
"""
from __future__ import annotations

from symkin.curves.stepper import (CurvePoint, CurveProblem, NonFiniteError, Settings, SteppingError, continue_curve,
                                   point_at, tangent)

__all__ = ["CurveProblem", "Settings", "CurvePoint", "tangent", "continue_curve", "point_at", "SteppingError",
           "NonFiniteError"]
