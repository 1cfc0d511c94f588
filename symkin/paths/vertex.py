"""Former home of the branch-point locator and the half-branches: both live in :mod:`symkin.curves`.

Kept for the callers outside the paths stage (``symkin.solutions.circuits``,
``papers_examples/check_double_butterfly.py``): :func:`locate_branch_point` is
:func:`symkin.curves.locate.locate_singular_point` with ``drop = 1``.
"""
from __future__ import annotations

from symkin.curves.branches import HALF_BRANCH_RADIUS, HALF_BRANCH_SAMPLES, half_branches
from symkin.curves.locate import MAX_DEFLATIONS, SingularPoint, locate_singular_point

__all__ = ["BranchPoint", "half_branches", "locate_branch_point", "HALF_BRANCH_RADIUS", "HALF_BRANCH_SAMPLES",
           "MAX_DEFLATIONS"]

BranchPoint = SingularPoint
locate_branch_point = locate_singular_point
