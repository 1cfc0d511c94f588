"""Former home of event location along a curve: it lives in :mod:`symkin.curves.locate` and :mod:`symkin.curves.events`.

Kept for the callers outside the paths stage (``symkin.workspace.loci``,
``symkin.solutions.circuits``).  :func:`refine_rank_drop` is the one singular-point locator
(:func:`symkin.curves.locate.locate_singular_point`) without deflation, returning
``(y, converged)`` as before.
"""
from __future__ import annotations

import numpy as np

from symkin.curves.events import TestFunction
from symkin.curves.locate import CurveEvent, locate_minimum, locate_sign_change, locate_singular_point
from symkin.tolerances import DEFAULT

__all__ = ["TestFunction", "CurveEvent", "locate_sign_change", "locate_minimum", "refine_rank_drop"]


def refine_rank_drop(problem, y0: np.ndarray, drop: int, tol: float = DEFAULT.locate,
                     max_iterations: int = 30) -> tuple[np.ndarray, bool]:
    """The nearby point where the curve's Jacobian has ``drop`` more left null vectors: ``(y, converged)``."""
    found = locate_singular_point(problem, y0, drop, tol=tol, max_iterations=max_iterations, max_deflations=0)
    return found.y, found.converged
