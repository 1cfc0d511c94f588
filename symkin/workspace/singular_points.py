"""The isolated singular points of a map: a configuration classified by the core and recorded once.

See :mod:`symkin.workspace.loci` (step 6).
"""
from __future__ import annotations

import numpy as np

from symkin.kinds import Kind
from symkin.workspace.locus_problems import LocusProblems, LocusSystem
from symkin.workspace.refine_data import SingularPoint

__all__ = ["add_point"]


def add_point(points: list, pb: LocusProblems, system: LocusSystem, y: np.ndarray, mode, scale, tol,
               only_im: bool = False, kind: str | None = None) -> None:
    """Classify the configuration ``y`` with the core and record it.

    A point is merged with one already recorded at the same configuration, or, for IM
    points (whose configuration need not be unique: a leg folded onto its pivot turns
    freely), at the same axis values (both within :attr:`Tolerances.same_configuration`,
    relative to the length scale / axis scale).
    ``only_im`` records it only when the core says IM; ``kind`` (``"cusp"``) replaces the kind
    the types give (the types stay the core's).
    """
    q = y * pb.scale
    at = pb.axes(y) * scale
    res = system.evaluators.indicators_at(q, tol)
    if only_im and not res["im"]:
        return
    for p in points:
        same_q = np.linalg.norm((p.configuration - q) / pb.scale) <= tol.same_configuration
        same_at = np.linalg.norm((p.at - at) / scale) <= tol.same_configuration
        if same_q or (res["im"] and Kind.IM in p.types and same_at):
            return
    types = tuple(name for name, flag in ((Kind.IM, res["im"]), (Kind.DKP_INPUT, res["is_dkp_input"]),
                                           (Kind.DKP_OUTPUT, res["is_dkp_output"])) if flag)
    if kind is None:
        kind = Kind.IM if Kind.IM in types else (Kind.MEETING if len(types) >= 2 else (types[0] if types else Kind.END))
    points.append(SingularPoint(str(kind), mode, at, tuple(str(t) for t in types), q))
