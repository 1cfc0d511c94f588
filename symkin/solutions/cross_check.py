"""The cross-check of :func:`symkin.singularities`: a square system's real solutions against the traced configurations."""
from __future__ import annotations

import math

import numpy as np

from symkin.solutions.frame_coordinates import free_coordinates
from symkin.solutions.singularities_result import CrossCheck
from symkin.tolerances import Tolerances

__all__ = ["compare"]


def compare(mech, kind, label, found, traced, paths, degree, seconds, scale, tol: Tolerances) -> CrossCheck:
    """Match a square system's real solutions with the traced configurations, one to one.

    Each solution is matched with the nearest traced configuration not matched yet when
    their free coordinates are within ``tol.same_configuration · scale`` (Euclidean norm).

    Parameters
    ----------
    mech : Mechanism
    kind : Kind
        The check's kind (``DKP-input``, ``DKP-output``, ``LIM``).
    label : str
        Its coordinate's label.
    found : list of dict
        The square system's real solutions (configurations).
    traced : list of dict
        The traced configurations of the kinds the system detects (node → coordinates).
    paths, degree : int
        Homotopy paths and total degree of the system (reported).
    seconds : float
        Time spent solving it (reported).
    scale : float
        The model's length scale.
    tol : Tolerances

    Returns
    -------
    CrossCheck
        Counts, matches and the configurations found by one side only.
    """
    qs = [free_coordinates(mech, c) for c in found]
    qt = [free_coordinates(mech, c) for c in traced]
    used = set()
    matched = 0
    only_h = []
    for c, q in zip(found, qs):
        d = [np.linalg.norm(q - t) if k not in used else math.inf for k, t in enumerate(qt)]
        k = int(np.argmin(d)) if d else -1
        if k >= 0 and d[k] <= tol.same_configuration * scale:
            used.add(k)
            matched += 1
        else:
            only_h.append(c)
    only_t = [c for k, c in enumerate(traced) if k not in used]
    return CrossCheck(kind, label, len(found), len(traced), matched, paths, degree, tuple(only_h), tuple(only_t),
                      seconds)
