"""The real solutions of the square systems "closure + test function = 0" (step 1 of :func:`symkin.singularities`).

By homotopy continuation (:func:`real_roots`, Bertini 2: one homotopy per factor of the
determinant) or, beyond ``max_paths``, exactly (:func:`exact_roots`, msolve on the system rebuilt
in rational arithmetic, :mod:`symkin.solutions.exact`); :func:`is_singular` filters the extra
roots of a squared-up (redundant) closure.
"""
from __future__ import annotations

import numpy as np

from symkin.errors import SymkinError
from symkin.kinds import Kind
from symkin.model.mechanism import Mechanism
from symkin.numeric.coordinates import InputCoordinate
from symkin.solutions.dkp_system import DkpSystem, polish
from symkin.solutions.homotopy import track
from symkin.solutions.solve_all import NEWTON_ACCEPT
from symkin.tolerances import Tolerances

__all__ = ["NEAR_REAL", "exact_roots", "is_singular", "real_roots"]

#: a homotopy endpoint with ``max |Im v|`` above this (length scales) is complex
NEAR_REAL = 1e-4
#: a homotopy endpoint whose homogenising coordinate is below this relative to its largest coordinate is at infinity
AT_INFINITY = 1e-10


def real_roots(system: DkpSystem, tol: Tolerances) -> tuple[list[dict], int]:
    """Distinct real solutions of the square systems (configurations) and the number of paths tracked.

    One homotopy per factor of ``D`` (:meth:`DkpSystem.systems`); an endpoint is kept when
    ``max |Im v| <= NEAR_REAL`` and Gauss–Newton on the real system from its real part
    (:func:`~symkin.solutions.dkp_system.polish`) reaches a residual ``<= NEWTON_ACCEPT`` without
    moving more than ``NEAR_REAL``.

    Parameters
    ----------
    system : DkpSystem
        The square system of one coordinate (DKP-input, DKP-output or a link's LIM system).
    tol : Tolerances
        ``same_configuration`` merges endpoints (dimensionless coordinates).

    Returns
    -------
    list of dict
        The distinct real solutions as configurations (node → coordinates, model units).
    int
        The number of homotopy paths tracked.
    """
    closure = system.closure
    found: list[np.ndarray] = []
    paths = 0
    for equations in system.systems():
        ends = track(list(equations), list(system.unknowns), endgame="power_series")
        paths += int(len(ends))
        for v in ends:
            h = v[0]
            if abs(h) <= AT_INFINITY * max(1.0, float(np.max(np.abs(v)))):
                continue  # at infinity
            w = v[1:] / h
            if not np.all(np.isfinite(w)) or float(np.max(np.abs(w.imag), initial=0.0)) > NEAR_REAL:
                continue
            vr, res = polish(equations, system.unknowns, np.array(w.real, float))
            if res > NEWTON_ACCEPT or float(np.max(np.abs(vr - w.real))) > NEAR_REAL:
                continue  # a complex solution close to the real space, or a failed polish
            u = closure.recover(vr)
            if all(float(np.linalg.norm(u - f)) > tol.same_configuration for f in found):
                found.append(u)
    return [closure.coordinates(u) for u in found], paths


def is_singular(mech: Mechanism, conf: dict, kind: str, tol: Tolerances, link: str | None = None) -> bool:
    """For a squared-up system: whether a real solution is a configuration of the kind it looks for, or IM.

    Parameters
    ----------
    mech : Mechanism
    conf : dict
        The solution (node → coordinates).
    kind : Kind
        ``Kind.DKP_INPUT`` or ``Kind.DKP_OUTPUT`` (that type), or ``Kind.LIM`` (that type with
        ``link`` among the locked links).
    tol : Tolerances
    link : str, optional
        The link of a LIM system.

    Returns
    -------
    bool
        By :func:`symkin.analyze` at the configuration.
    """
    from symkin.analysis.classification import analyze

    a = analyze(mech.with_coordinates(conf), tol=tol)
    if Kind.IM in a.types:
        return True
    if kind == Kind.LIM:
        return Kind.LIM in a.types and link in a.locked_links
    return kind in a.types


def exact_roots(mech: Mechanism, c: InputCoordinate) -> list[dict] | str:
    """Real solutions (configurations) of the exact square systems of coordinate ``c`` by msolve, or why there are none.

    Parameters
    ----------
    mech : Mechanism
    c : InputCoordinate
        The input, the output or a link's rotation (:mod:`symkin.solutions.lim_systems`).

    Returns
    -------
    list of dict or str
        The configurations, or the reason msolve could not give them (not installed, a system
        it cannot build or that is not zero-dimensional).
    """
    from symkin.solutions.exact import exact_dkp_system, msolve_executable, real_solutions

    if msolve_executable() is None:
        from symkin.solutions.exact import EXTRA

        return f"msolve is not installed ({EXTRA})"
    try:
        system = exact_dkp_system(mech, c)
        found = []
        for equations in system.systems():
            found += [system.place(v) for v, _ in real_solutions(list(equations), system.unknowns)]
    except SymkinError as exc:
        return str(exc)
    return found
