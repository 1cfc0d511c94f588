"""The isolated singular points of a map: a configuration classified by the core and recorded once.

See :mod:`symkin.workspace.loci` (step 6).
"""
from __future__ import annotations

import numpy as np

from symkin.kinds import Kind
from symkin.workspace.locus_problems import LocusProblems, LocusSystem
from symkin.workspace.refine_data import SingularPoint

__all__ = ["add_point", "one_per_family"]


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


def one_per_family(points: list, families: list, scale, tol) -> list:
    """The points with one per map point of ``families`` (axis values over which a family of configurations lies).

    Every configuration of such a family is singular and maps to the same axis values: the
    points recorded there (ends of curves running into the family, the family itself) are one
    point of the map, the first recorded that is not a cusp (else the first).  Same axis
    values: within :attr:`Tolerances.same_configuration` relative to the axis scale.
    """
    scale = np.asarray(scale, float)
    keep, taken = [], set()
    for p in points:
        fam = next((k for k, a in enumerate(families)
                    if np.linalg.norm((np.asarray(p.at) - a) / scale) <= tol.same_configuration), None)
        if fam is None:
            keep.append(p)
        elif fam not in taken:
            at_family = [q for q in points if np.linalg.norm((np.asarray(q.at) - families[fam]) / scale)
                         <= tol.same_configuration]
            keep.append(next((q for q in at_family if q.kind != Kind.CUSP), at_family[0]))
            taken.add(fam)
    return keep
