"""Every real solution of the position problem (``symkin.solve_all``): assembly and working modes.

The polynomial system of :mod:`symkin.solutions.system` (reduced by its linear equations)
is solved by homotopy continuation (:mod:`symkin.solutions.homotopy`, Bertini 2).  Every
finite endpoint is sorted, in the dimensionless coordinates ``u = (x − c) / L`` of the
model's length scale ``L`` (so the decisions do not depend on the unit of length):

* **real** when ``max |Im u| <= imaginary`` (default ``1e-8``) and Newton's method on the
  *original* equations (least-squares steps, so an overconstrained system is fine), started
  from ``Re u``, reaches a residual ``<= 1e-12`` (accepted up to ``1e-10``); it is then verified:
  the closure residual of the evaluators (:func:`symkin.evaluators`, relative to ``L``), the
  prescribed values recomputed by :mod:`symkin.numeric.coordinates`, and the half-line filters
  of prescribed angles (a solution on the opposite half-line is counted in ``filtered``);
* **near-real** when ``imaginary < max |Im u| <= near_real`` (default ``1e-4``): counted, not
  returned;
* **rejected** when it is real but Newton on the original equations does not bring the residual
  below ``1e-10`` or moves it by more than ``near_real`` (a solution of the squared-up system
  only, which Newton's least-squares steps carry to a true one): counted, not returned;
* **complex** otherwise: complex Newton on the original equations (the real form of twice the
  size, :func:`symkin.curves.corrector.real_form`) must reach a residual ``<= 1e-10`` without
  moving more than ``near_real``, else the endpoint is **rejected** (a solution of the squared-up
  or reduced system only); ``complex`` counts the distinct verified complex solutions
  (conjugates are distinct);
* **at infinity** when the homogenising coordinate vanishes (counted).

Every endpoint, real or complex, is refined by complex Newton on the original equations first.
``failed`` counts paths that did not reach ``t = 1`` (parameter homotopy).
``near_real``, ``rejected``, ``at_infinity`` and ``filtered`` count paths; ``complex`` counts distinct
endpoints; paths ending at one real solution are its ``multiplicity``.

A real solution whose closure residual or prescribed-value error exceeds ``VERIFY`` after
Newton is dropped and counted in ``unverified`` (a bug if it ever happens).

Real solutions closer than :attr:`Tolerances.same_configuration` (relative to ``L``) are one;
each is labelled by the signs of the DKP test functions (:meth:`Evaluators.batch`:
``+1``/``-1``, ``0`` at a DKP configuration, ``None`` where undefined) and, with
``analyze=True``, analysed by :func:`symkin.analyze`.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy as sp

from symkin.analysis.batch import BatchResult, evaluators_for, exact_indicators
from symkin.curves.corrector import gauss_newton, real_form
from symkin.errors import SymkinError
from symkin.model.mechanism import Mechanism
from symkin.solutions.homotopy import estimate_seconds, require_solver, square_up, total_degree, track
from symkin.solutions.progress import as_progress, format_seconds
from symkin.solutions.system import PolynomialSystem, configuration, position_system, prescribed_coordinates
from symkin.tolerances import Tolerances

if TYPE_CHECKING:  # imported where it is used: ``modes`` without --analyze does not pay for it
    from symkin.analysis.classification import Analysis

__all__ = ["Endpoints", "Solution", "Solutions", "solve_all", "sort_endpoints"]

#: the ways of solving: a parameter homotopy from cached generic solutions, or Bertini's total-degree homotopy
METHODS = ("auto", "parameter", "total-degree")
#: ``method="auto"`` takes the parameter homotopy when its start solutions are cached, or when the
#: total-degree homotopy would track more paths than this (benchmarks/README.md, solve_all section)
AUTO_PATHS = 1024
#: largest relative distance of a query's coefficients from the parameter family (rounding of the samples)
SPAN_OFF = 1e-8
#: two solutions of the original equations are one when closer than this (max-norm, dimensionless)
DISTINCT = 1e-6
#: the parameter homotopy's first solve checks its start solutions by a total-degree solve of at most this
#: many paths (a Bertini path costs milliseconds, 16 in about 0.2 s on a four-bar: the check must not dominate)
FIRST_CHECK_PATHS = 1024
#: Newton's target and the largest residual accepted (dimensionless, relative to the length scale)
NEWTON_TARGET = 1e-12
NEWTON_ACCEPT = 1e-10
#: Newton stops when a step is below this relative to ``max(1, ‖u‖)`` (the rounding level of ``u`` = O(1))
NEWTON_STEP = 1e-15
#: largest closure residual (relative) and prescribed-value error (rad, or relative) of a verified solution
VERIFY = 1e-8


@dataclass(frozen=True)
class Solution:
    """One real configuration with the prescribed values.

    Attributes
    ----------
    configuration : dict
        Node → coordinates (model units), every node.
    signs : dict
        ``{"dkp_input": s, "dkp_output": s}`` with ``s`` in ``{+1, -1, 0, None}``: the sign of the
        signed DKP test function, 0 at a DKP configuration, None where it is undefined (no
        such parameters, or an IM configuration).
    residual : float
        Largest residual of the original polynomial equations after Newton (dimensionless).
    closure : float
        Largest closure residual of the evaluators, divided by the length scale.
    types : tuple of str
        IM / DKP types decided by :meth:`Evaluators.batch`.
    multiplicity : int
        Number of homotopy paths that ended at this solution (2 or more at a singular
        solution, e.g. the two assembly modes of a four-bar meeting at a dead centre).
    analysis : Analysis or None
        :func:`symkin.analyze` at the configuration, with ``analyze=True``.
    """

    configuration: dict
    signs: dict
    residual: float
    closure: float
    types: tuple = ()
    multiplicity: int = 1
    analysis: Analysis | None = field(default=None, compare=False)

    def to_dict(self) -> dict:
        out: dict[str, Any] = {"configuration": {n: list(x) for n, x in self.configuration.items()},
                               "signs": dict(self.signs), "residual": self.residual,
                               "closure": self.closure, "types": list(self.types),
                               "multiplicity": self.multiplicity}
        if self.analysis is not None:
            out["analysis"] = {"types": list(self.analysis.types), "dof": self.analysis.dof}
        return out


@dataclass(frozen=True)
class Solutions:
    """All solutions of a position problem (see the module docstring for the counts).

    ``paths`` is the number of homotopy paths tracked; ``unknowns`` and ``equations`` the size
    of the system given to the solver (after elimination; ``equations > unknowns`` before
    squaring up when the model is overconstrained); ``seconds`` the wall time of
    :func:`solve_all`, ``track_seconds`` that of the homotopy alone.
    """

    mechanism: Mechanism
    values: dict
    unit: str
    solutions: tuple[Solution, ...]
    complex: int
    near_real: int
    at_infinity: int
    filtered: int
    rejected: int
    unverified: int
    paths: int
    unknowns: int
    equations: int
    seconds: float
    track_seconds: float
    failed: int = 0
    method: str = "total-degree"

    def __len__(self) -> int:
        return len(self.solutions)

    def mechanisms(self) -> tuple[Mechanism, ...]:
        """The mechanism at each solution."""
        return tuple(self.mechanism.with_coordinates(s.configuration) for s in self.solutions)

    def to_dict(self) -> dict:
        """``{"solutions": [...], "complex": k, "paths": total, ...}`` (the ``--json`` of ``symkin modes``)."""
        return {"solutions": [s.to_dict() for s in self.solutions], "complex": self.complex, "paths": self.paths,
                "real": len(self.solutions), "near_real": self.near_real, "at_infinity": self.at_infinity,
                "filtered": self.filtered, "rejected": self.rejected, "unverified": self.unverified,
                "failed": self.failed, "method": self.method, "unknowns": self.unknowns, "equations": self.equations,
                "values": dict(self.values), "unit": self.unit, "seconds": self.seconds,
                "track_seconds": self.track_seconds}


def _newton(f, jac, u: np.ndarray, max_iterations: int = 30) -> tuple[np.ndarray, float]:
    """Least-squares Gauss–Newton (:func:`symkin.curves.corrector.gauss_newton`, max-norm) on the original
    equations from ``u``; returns the point (the best one seen when it does not converge) and its residual."""
    if not u.size:
        return u, 0.0
    c = gauss_newton(lambda z: (f(z), jac(z)), u, tol=NEWTON_TARGET, max_iterations=max_iterations,
                     step_tol=NEWTON_STEP, norm="max")
    return c.z, c.residual


def _jacobian(eqs: list, unknowns: list) -> sp.Matrix:
    """``∂eqs/∂unknowns``: each equation as a polynomial in the unknowns it contains, differentiated
    as such (a Gough–Stewart's 39 × 39 in 0.4 s, where ``Matrix.jacobian`` takes 1.3-3 s of
    sympy's expression derivatives on its 1,521 entries)."""
    index = {s: k for k, s in enumerate(unknowns)}
    entries = {}
    for i, e in enumerate(eqs):
        gens = [s for s in unknowns if s in e.free_symbols]
        if not gens:
            continue
        try:
            p = sp.Poly(e, *gens)
        except sp.PolynomialError:  # not polynomial in them: sympy's derivative
            entries.update({(i, index[s]): e.diff(s) for s in gens})
            continue
        entries.update({(i, index[s]): p.diff(s).as_expr() for s in gens})
    return sp.Matrix(sp.SparseMatrix(len(eqs), len(unknowns), entries))


#: bump when the cached source of the equations changes form
_CHECKS_FORMAT = 1


def _lambdified(eqs: list, u: list):
    """``(f, jac)``: the equations and their Jacobian as NumPy functions of the vector ``u``."""
    f = sp.lambdify([u], eqs or [sp.Integer(0)], "numpy", docstring_limit=0)  # no docstring: a third of the time
    j = sp.lambdify([u], _jacobian(eqs, u) if eqs else sp.zeros(1, len(u)), "numpy", docstring_limit=0)
    return f, j


def _compiled_equations(system: PolynomialSystem, cache: bool, tol: Tolerances | None = None):
    """``(f, jac)`` of the system's original equations, NumPy functions of the unknowns' vector.

    The equations that do not depend on the prescribed values (every owner but ``value:…``) are
    the same at every query of a model: with ``cache`` their generated source is kept in the
    artefact cache (:func:`symkin.solutions.query.checks_file`, keyed by the model's content, the
    tolerances and the source of the modules that make the equations) and read back at a later
    query; the value equations are made each time.  On the general 6-6 Gough–Stewart the cached
    part is 33 of its 39 equations.
    """
    import inspect

    u = list(system.unknowns)
    owned = list(system.equations)
    base = [k for k, (o, _) in enumerate(owned) if not str(o).startswith("value:")]
    rest = [k for k in range(len(owned)) if k not in set(base)]
    fb = jb = None
    path = None
    if cache and base:
        from symkin.solutions.query import checks_file, load_checks

        path = checks_file(system.mechanism, Tolerances.of(tol))
        if path.exists():
            fb, jb = load_checks(path) or (None, None)
    if fb is None:
        fb, jb = _lambdified([owned[k][1] for k in base], u)
        if path is not None:
            from symkin.numeric.codegen import write_atomic

            try:
                source = (inspect.getsource(fb).replace("def _lambdifygenerated(", "def equations(", 1) + "\n\n"
                          + inspect.getsource(jb).replace("def _lambdifygenerated(", "def jacobian(", 1))
                path.parent.mkdir(parents=True, exist_ok=True)
                write_atomic(path, source)
            except (OSError, TypeError):
                pass  # no cache: the next query builds them again
    return _with_values(fb, jb, base, [owned[k][1] for k in rest], rest, u)


def _with_values(fb, jb, base: list, value_eqs: list, rest: list, u: list):
    """``(f, jac)`` of the value-free equations ``fb, jb`` (rows ``base``) with the value equations (rows ``rest``)."""
    if not rest:
        return fb, jb
    fv, jv = _lambdified(value_eqs, u)
    order = np.argsort(base + rest)

    def f(v):
        return np.concatenate([np.ravel(fb(v)), np.ravel(fv(v))])[order]

    def j(v):
        return np.vstack([np.reshape(jb(v), (len(base), len(u))), np.reshape(jv(v), (len(rest), len(u)))])[order]

    return f, j


class _Checks:
    """Newton, filters and the prescribed values of one system's original equations, compiled once.

    ``f, j`` the original equations and their Jacobian (NumPy functions of ``u``, ``n_equations``
    rows), ``filters`` the ``(owner, expr)`` half-line conditions; :meth:`of` makes them from a
    :class:`PolynomialSystem`.
    """

    def __init__(self, mech: Mechanism, center, scale: float, unknowns, f, j, n_equations: int, filters,
                 prescribed):
        u = list(unknowns)
        self.f = lambda v: np.array(f(v), float).ravel()
        self.jac = lambda v: np.array(j(v), float).reshape(n_equations, len(u))
        self.fc = lambda v: np.array(f(v), complex).ravel()
        self.jc = lambda v: np.array(j(v), complex).reshape(n_equations, len(u))
        self.filters = sp.lambdify([u], [e for _, e in filters] or [sp.Integer(1)], "numpy", docstring_limit=0)
        self.filters_c = lambda v: np.array(self.filters(v), complex)
        self.prescribed = prescribed
        self.mechanism, self.center, self.scale = mech, center, scale
        import casadi as ca

        x = ca.SX.sym("x", len(mech.nodes) * mech.dim)
        x0 = np.array([c for _, c in mech.nodes], float)
        self.values = ca.Function("values", [x], [ca.vertcat(*[c.expression(mech, x, x0) for c, _ in prescribed])])

    @classmethod
    def of(cls, system: PolynomialSystem, prescribed, cache: bool = False, tol: Tolerances | None = None
           ) -> "_Checks":
        """The checks of ``system``'s original equations (the value-free ones cached with ``cache``)."""
        f, j = _compiled_equations(system, cache, tol)
        return cls(system.mechanism, system.center, system.scale, system.unknowns, f, j, len(system.equations),
                   system.filters, prescribed)

    def coordinates(self, u: np.ndarray) -> dict[str, list[float]]:
        """Node → coordinates (model units) at the dimensionless free vector ``u``."""
        return configuration(self.mechanism, self.center, self.scale, u)

    def value_error(self, coords: dict) -> float:
        """Largest difference between the prescribed and the recomputed values (rad, or lengths / L)."""
        mech = self.mechanism
        x = np.concatenate([coords[n] for n in mech.node_names])
        got = np.array(self.values(x)).ravel()
        err = 0.0
        for (c, target), v in zip(self.prescribed, got):
            d = v - target
            if c.kind == "angle":
                d = math.remainder(d, 2 * math.pi)
            else:
                d = d / self.scale
            err = max(err, abs(d))
        return err


def solve_all(mech: Mechanism, values: dict, unit: str = "rad", tol: float | Tolerances | None = None,
              analyze: bool = False, imaginary: float = 1e-8, near_real: float = 1e-4, seed: int = 0,
              max_paths: int = 5000, method: str = "auto", cache: bool = True,
              progress=None) -> Solutions:
    """Every real configuration of ``mech`` with the input coordinates ``values`` (``symkin.solve_all``).

    The assembly modes when inputs are prescribed (forward problem), the working modes when
    outputs are (inverse problem).  Needs the optional extra ``symkin[global]`` (Bertini 2).

    Parameters
    ----------
    values : dict
        Exactly F labels (``rotation:crank``, ``slide:S``, ``velocity:P.x``, ``joint:L1-L2``; see
        :func:`symkin.numeric.coordinates.parse_input_label`) → values measured from the model's
        configuration (angles in ``unit``, lengths in model units), as for
        :func:`symkin.paths.position.solve_position`.
    tol : float or Tolerances
        Rank tolerance of the DKP labels and the analysis; ``same_configuration`` merges duplicates.
    analyze : bool
        Also run :func:`symkin.analyze` at every solution (``Solution.analysis``).
    imaginary, near_real : float
        Thresholds on ``max |Im u|`` in units of the length scale (module docstring).
    seed : int
        Seed of the random combinations that square up an overconstrained system.
    method : {"auto", "parameter", "total-degree"}
        ``"parameter"``: the parameter homotopy from cached start solutions (made by monodromy on
        the first solve; falls back to total degree when it does not apply; module docstring of
        :mod:`symkin.solutions.monodromy`).  ``"total-degree"``: Bertini's total-degree homotopy.
        Default ``"auto"``: the parameter homotopy when its start solutions are cached or when the
        total-degree homotopy would track more than :data:`AUTO_PATHS` paths, else total degree
        (a first solve of a small model: Bertini's few paths cost less than the monodromy).
    cache : bool
        Read and write the parameter homotopy's start solutions in the artefact cache.
    progress : Progress or callable, optional
        A :class:`symkin.solutions.progress.Progress` (a bar over the paths of each homotopy
        and over the monodromy loops; summary lines without a terminal), or ``progress(message)``
        told each stage (module :mod:`symkin.solutions.progress`).
    max_paths : int
        Refuse (with a :class:`SymkinError` that gives the count and the time it would take,
        estimated from the first paths: :func:`symkin.solutions.homotopy.estimate_seconds`) a
        total-degree homotopy of more paths than this rather than run for minutes (the total
        degree of what is left after elimination, e.g. 8192 for the 13 quadratics of the Pratt
        truss of the catalogue).  The parameter homotopy's first solve skips its total-degree
        check above it.

    Returns
    -------
    Solutions

    Raises
    ------
    SymkinError
        Unknown label, a number of values other than F, an unsupported value, or the solver
        is not installed (the message names the extra).

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> result = solve_all(get("fourbar_appendix"), {"rotation:crank": 30}, unit="deg")  # doctest: +SKIP
    >>> len(result.solutions), result.paths  # doctest: +SKIP
    (2, 4)
    """
    start = time.perf_counter()
    if method not in METHODS:
        raise SymkinError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    tol = Tolerances.of(tol)
    progress = as_progress(progress)
    do_analyze = bool(analyze)
    prescribed = prescribed_coordinates(mech, values, unit)
    system = None
    if method == "auto":
        from symkin.solutions.monodromy import cache_file

        if not values:
            method = "total-degree"  # no parameter to move
        elif cache and cache_file(mech, list(values), tol).exists():
            method = "parameter"
        else:
            system = position_system(mech, values, unit, tol)
            n = len(system.solve_for)
            degree = total_degree(square_up(system.reduced, n, seed=seed), list(system.solve_for)) if n else 1
            method = "parameter" if degree > AUTO_PATHS else "total-degree"
    if method == "parameter":
        result = _solve_parameter(mech, values, unit, prescribed, tol, do_analyze, imaginary, near_real,
                                  seed, cache, start, progress, max_paths)
        if result is not None:
            return result
    if system is None:
        system = position_system(mech, values, unit, tol)
    require_solver()
    n = len(system.solve_for)
    eqs = square_up(system.reduced, n, seed=seed)
    degree = total_degree(eqs, list(system.solve_for)) if n else 1
    if degree > max_paths:
        progress.stage(f"estimating the time of {degree} paths", total=None)
        per_path, measured = estimate_seconds(eqs, list(system.solve_for), seed=seed)
        raise SymkinError(f"{mech.name}: after elimination {n} unknowns and {len(eqs)} equations are left; "
                          f"the total-degree homotopy would track {degree} paths, more than max_paths = "
                          f"{max_paths}: about {format_seconds(per_path * degree)} (estimated from its first "
                          f"{measured} paths, {per_path:.2g} s each); raise max_paths to track them")
    progress.stage("total-degree homotopy", total=degree, unit="path")
    t0 = time.perf_counter()
    if n:
        ends = track(eqs, list(system.solve_for))
    else:
        ends = np.ones((1, 1), complex)
    progress.advance(degree)
    track_seconds = time.perf_counter() - t0
    checks = _Checks.of(system, prescribed)
    points, infinite = [], 0
    for v in ends:
        h = v[0]
        if abs(h) <= 1e-10 * max(1.0, float(np.max(np.abs(v)))):
            infinite += 1
            continue
        w = v[1:] / h
        if not np.all(np.isfinite(w)) or float(np.max(np.abs(w), initial=0.0)) > 1e8:
            infinite += 1
            continue
        points.append(system.recover(w))
    sorted_ = sort_endpoints(checks, points, tol, imaginary, near_real)
    return _result(mech, values, unit, (len(system.solve_for), len(system.reduced)), checks, sorted_, tol, do_analyze,
                   paths=int(len(ends)) if n else 0, at_infinity=infinite, failed=0,
                   seconds=time.perf_counter() - start, track_seconds=track_seconds, method="total-degree")


def _solve_parameter(mech, values, unit, prescribed, tol, do_analyze, imaginary, near_real, seed, cache,
                     start, progress, max_paths) -> "Solutions | None":
    """The parameter homotopy from the cached (or monodromy) start solutions; None when it does not apply.

    The query builds the original equations and the leg-reduced ones of the family
    (:func:`symkin.solutions.system.leg_reduced_equations`), not the fully reduced system of
    :func:`~symkin.solutions.system.position_system` (seconds of sympy on a Gough–Stewart); a later
    query builds only those that depend on the values and reads the rest back from the artefact
    cache (:mod:`symkin.solutions.query`).
    """
    from symkin.solutions.monodromy import start_solutions
    from symkin.solutions.parameter_homotopy import track_parameters
    from symkin.solutions.system import value_equations

    if not mech.free_nodes or not values:
        return None
    ve = value_equations(mech, values, unit, tol)
    try:
        starts = start_solutions(mech, list(values), tol, seed=seed, cache=cache, progress=progress)
    except SymkinError:
        return None
    if starts is None or not starts.family.rank:
        return None  # no first solution, or nothing to loop around (no prescribed value)
    family = starts.family
    query = _planned_query(mech, values, tol, family, ve, prescribed) if cache and starts.cached else None
    if query is None:
        query = _full_query(mech, values, unit, tol, family, ve, prescribed, cache)
    if query is None:
        return None
    c, recover, checks, sizes, kept, reduced = query
    lam, off = family.parameters_of(c)
    if off > SPAN_OFF:
        return None  # the query is not in the sampled family (a degenerate sample): total degree
    lam = lam.astype(complex)

    def track(starts_):
        progress.stage("parameter homotopy", total=len(starts_.u), unit="path")
        tr = track_parameters(starts_.family, starts_.u, starts_.lam, lam, np.random.default_rng(seed),
                              progress=progress.advance)
        return tr, [recover(v) for v in tr.u[tr.ok]]

    t0 = time.perf_counter()
    tracked, points = track(starts)
    track_seconds = time.perf_counter() - t0
    sorted_ = sort_endpoints(checks, points, tol, imaginary, near_real)
    if not starts.cached and bertini_available():
        # first solve: monodromy reaches one component of the incidence variety only; the
        # total-degree solve at this query finds a solution on every component
        # the fully reduced system costs seconds of sympy on a large model: first a Bézout bound from the
        # leg-reduced equations (a linear substitution never raises a degree)
        limit = min(max_paths, FIRST_CHECK_PATHS)
        degrees = sorted((sp.Poly(e, *[ve.unknowns[k] for k in kept]).total_degree() for _, e in reduced),
                         reverse=True)
        degree = math.prod(degrees[:len(kept)])
        if degree <= limit:
            full = position_system(mech, values, unit, tol)
            n = len(full.solve_for)
            degree = total_degree(square_up(full.reduced, n, seed=seed), list(full.solve_for)) if n else 1
        if degree > limit:
            progress.note(f"the total-degree check of the first solve (at most {degree} paths > {limit}) is skipped: "
                          "monodromy searched the component of the model's configuration only")
        else:
            progress.stage("total-degree check of the first solve", total=degree, unit="path")
            found = _original_solutions(checks, points)
            every = _original_solutions(checks, _total_degree_points(full, seed))
            progress.advance(degree)
            missing = [u for u in every if _duplicate(u, found, DISTINCT) is None]
            if missing:
                from symkin.solutions.monodromy import augment

                starts = augment(starts, [u[family.kept] for u in missing], lam, mech, list(values), tol, seed=seed,
                                 cache=cache, progress=progress)
                tracked, points = track(starts)
                track_seconds = time.perf_counter() - t0
                sorted_ = sort_endpoints(checks, points, tol, imaginary, near_real)
    return _result(mech, values, unit, sizes, checks, sorted_, tol, do_analyze, paths=int(len(starts.u)),
                   at_infinity=0, failed=int(np.sum(~tracked.ok)), seconds=time.perf_counter() - start,
                   track_seconds=track_seconds, method="parameter")


def _full_query(mech, values, unit, tol, family, ve, prescribed, cache):
    """``(c, recover, checks, sizes, kept, reduced)`` of a query from all its equations (and, with ``cache``, the
    :class:`~symkin.solutions.query.QueryPlan` of the later ones); None when the family does not fit."""
    from symkin.solutions.system import leg_reduced_equations, original_equations

    unknowns, equations, filters, center, scale = original_equations(mech, values, unit, tol)
    kept, reduced, recover = leg_reduced_equations(mech, values, unit, tol)
    if family.kept is None or list(kept) != [int(k) for k in family.kept]:
        return None
    c = family.coefficient_matrix(reduced, [unknowns[k] for k in kept])
    if c is None:
        return None
    system = PolynomialSystem(mech, center, scale, tuple(unknowns), tuple(equations), tuple(filters), (), (), None)
    checks = _Checks.of(system, prescribed, cache=cache, tol=tol)
    if cache:
        from symkin.solutions.query import QueryPlan, plan_file, save_plan

        fixed = len(reduced) - len(ve.reduced)
        base = len(equations) - len(ve.original)
        # the plan keeps what does not depend on the values; made by the same code as the value equations' rest
        if ([o for o, _ in reduced[fixed:]] == [o for o, _ in ve.reduced]
                and [o for o, _ in equations[base:]] == [o for o, _ in ve.original]
                and all(not str(o).startswith(("value:", "leg:")) for o, _ in reduced[:fixed])
                and all(not str(o).startswith("value:") for o, _ in equations[:base])
                and list(ve.kept) == list(kept) and len(filters) == len(ve.filters)):
            save_plan(plan_file(mech, list(values), tol),
                      QueryPlan(c[:fixed].copy(), tuple(o for o, _ in ve.reduced), tuple(ve.legs), tuple(ve.kept),
                                base, tuple(o for o, _ in ve.original)))
    return c, recover, checks, (len(unknowns), len(equations)), kept, reduced


def _planned_query(mech, values, tol, family, ve, prescribed):
    """``(c, recover, checks, sizes, kept, reduced)`` of a later query from its
    :class:`~symkin.solutions.system.ValueEquations` and what the first query kept (:mod:`symkin.solutions.query`);
    None when nothing is kept or it does not fit (``reduced`` is None: only the first solve needs it)."""
    from symkin.solutions.query import checks_file, load_checks, load_plan, plan_file

    plan = load_plan(plan_file(mech, list(values), tol))
    if plan is None or not plan.base or family.kept is None or list(plan.kept) != [int(k) for k in family.kept]:
        return None
    c = plan.coefficients(family, ve)
    if c is None:
        return None
    kept_checks = load_checks(checks_file(mech, tol))
    if kept_checks is None:
        return None
    u = list(ve.unknowns)
    n_equations = plan.base + len(ve.original)
    f, j = _with_values(*kept_checks, list(range(plan.base)), [e for _, e in ve.original],
                        list(range(plan.base, n_equations)), u)
    checks = _Checks(mech, ve.center, ve.scale, u, f, j, n_equations, ve.filters, prescribed)
    return c, ve.recover, checks, (len(u), n_equations), list(ve.kept), None


def bertini_available() -> bool:
    """Whether the total-degree solver (the extra ``symkin[global]``) is installed."""
    try:
        require_solver()
    except SymkinError:
        return False
    return True


def _total_degree_points(system: PolynomialSystem, seed: int) -> list:
    """Finite endpoints (full ``u``) of Bertini's total-degree homotopy on the reduced, squared-up system."""
    n = len(system.solve_for)
    if not n:  # every unknown eliminated: one solution
        return [system.recover(np.zeros(0, complex))]
    ends = track(square_up(system.reduced, n, seed=seed), list(system.solve_for))
    out = []
    for v in ends:
        if abs(v[0]) <= 1e-10 * max(1.0, float(np.max(np.abs(v)))):
            continue
        w = v[1:] / v[0]
        if np.all(np.isfinite(w)):
            out.append(system.recover(w))
    return out


def _original_solutions(checks: "_Checks", points) -> list:
    """The distinct points that complex Newton carries onto the original equations (no filter, no sorting)."""
    out = []
    for u in points:
        uc, res = _complex_newton(checks, np.asarray(u, complex))
        if res <= NEWTON_ACCEPT and _duplicate(uc, out, DISTINCT) is None:
            out.append(uc)
    return out


@dataclass
class Endpoints:
    """Endpoints sorted by :func:`sort_endpoints` (see the module docstring for the classes)."""

    real: list = field(default_factory=list)
    residuals: list = field(default_factory=list)
    counts: list = field(default_factory=list)
    complex: list = field(default_factory=list)
    near_real: int = 0
    filtered: int = 0
    rejected: int = 0


def sort_endpoints(checks: "_Checks", points, tol: Tolerances, imaginary: float,
                   near_real: float) -> Endpoints:
    """Refine every finite endpoint by Newton on the original equations, then sort it (module docstring).

    Parameters
    ----------
    checks : _Checks
        The original equations (real and complex), filters and prescribed values of one system.
    points : sequence of ndarray
        Full dimensionless vectors ``u`` (complex) of the endpoints.
    tol : Tolerances
    imaginary, near_real : float
        Thresholds on ``max |Im u|``.

    Returns
    -------
    Endpoints
        Real solutions (refined, deduplicated, with multiplicities), distinct verified complex
        solutions, and the counts of near-real, filtered and rejected endpoints.
    """
    out = Endpoints()
    for u in points:
        u = np.asarray(u, complex)
        # complex Newton on the original (not squared-up, not reduced) equations, in real form
        uc, res = _complex_newton(checks, u)
        if res > NEWTON_ACCEPT or float(np.max(np.abs(uc - u), initial=0.0)) > near_real * max(
                1.0, float(np.max(np.abs(u), initial=0.0))):
            out.rejected += 1  # e.g. a solution of the squared-up system only
            continue
        im = float(np.max(np.abs(uc.imag), initial=0.0))
        if im > near_real:
            # a half-line filter is real (± a product of fixed lengths) at a complex solution too:
            # a complex solution on the opposite half-line is not one of the problem's
            if any(float(np.real(fv)) <= tol.geometry for fv in np.atleast_1d(checks.filters_c(uc))):
                out.filtered += 1
                continue
            if _duplicate(uc, out.complex, tol.same_configuration) is None:
                out.complex.append(uc)
            continue
        if im > imaginary:
            out.near_real += 1
            continue
        ur, res = _newton(checks.f, checks.jac, np.array(uc.real, float))
        if res > NEWTON_ACCEPT or float(np.max(np.abs(ur - uc.real), initial=0.0)) > near_real:
            out.rejected += 1
            continue
        same = _duplicate(ur, out.real, tol.same_configuration)
        if same is not None:
            out.counts[same] += 1
            continue
        if any(float(fv) <= tol.geometry for fv in np.atleast_1d(checks.filters(ur))):
            out.filtered += 1
            continue
        out.real.append(ur)
        out.residuals.append(res)
        out.counts.append(1)
    return out


def _complex_newton(checks: "_Checks", u: np.ndarray) -> tuple[np.ndarray, float]:
    """Gauss–Newton on the original equations at a complex point (real form of twice the size)."""
    if not u.size:
        return u, 0.0
    n = u.size
    c = gauss_newton(real_form(lambda x: (checks.fc(x), checks.jc(x))), np.concatenate([u.real, u.imag]),
                     tol=NEWTON_TARGET, max_iterations=30, step_tol=NEWTON_STEP, norm="max")
    return c.z[:n] + 1j * c.z[n:], c.residual


def _result(mech, values, unit, sizes, checks, e: Endpoints, tol, do_analyze, *, paths, at_infinity, failed,
            seconds, track_seconds, method) -> "Solutions":
    """The :class:`Solutions`; ``sizes`` the unknowns and equations given to the solver."""
    ev = evaluators_for(mech, tol)
    coords = [checks.coordinates(u) for u in e.real]
    sols = _label(mech, ev, coords, e.residuals, e.counts, checks, tol, do_analyze)
    sols.sort(key=lambda s: [c for n in mech.free_nodes for c in s.configuration[n]])
    return Solutions(mech, dict(values), unit, tuple(sols), len(e.complex), e.near_real, at_infinity, e.filtered,
                     e.rejected, len(coords) - len(sols), paths, *sizes, seconds, track_seconds, failed, method)


def _duplicate(u, seen, distance: float) -> int | None:
    """Index of the first of ``seen`` within ``distance`` (max norm) of ``u``, else None."""
    for k, s in enumerate(seen):
        if float(np.max(np.abs(u - s))) <= distance:
            return k
    return None


def _sign(value: float, decided: bool):
    if decided:
        return 0
    if not math.isfinite(value):
        return None
    return 1 if value > 0 else -1


def _label(mech, ev, coords, residuals, counts, checks: _Checks, tol: Tolerances, do_analyze: bool) -> list[Solution]:
    if not coords:
        return []
    q = np.array([[c[n][a] for n in mech.free_nodes for a in range(mech.dim)] for c in coords])
    if _kernel_ready(ev):
        result = ev.batch(q, tol=tol)
    else:
        # the batch's own exact path (stacked SVD; the same J_S rows, signs and decisions), milliseconds,
        # where building the batch kernel takes seconds on a large model (5 s on the 6-6 Gough–Stewart)
        ex = exact_indicators(ev, q, tol)
        result = BatchResult(**ex, path=np.full(len(q), 2, dtype=np.int8), tol=Tolerances.of(tol).rank)
    out = []
    scale = checks.scale
    if do_analyze:
        from symkin.analysis.classification import analyze as _analyze
    for k, c in enumerate(coords):
        phi = np.array(ev("closure", q[k])["phi"], float).ravel()
        closure = float(np.max(np.abs(phi), initial=0.0)) / scale
        err = checks.value_error(c)
        if err > VERIFY or closure > VERIFY:
            continue  # counted as unverified by the caller
        signs = {"dkp_input": _sign(float(result.dkp_input[k]), bool(result.is_dkp_input[k])),
                 "dkp_output": _sign(float(result.dkp_output[k]), bool(result.is_dkp_output[k]))}
        analysis = _analyze(mech.with_coordinates(c), tol=tol) if do_analyze else None
        out.append(Solution(c, signs, float(residuals[k]), closure, result.types(k), counts[k], analysis))
    return out



def _kernel_ready(ev) -> bool:
    """Whether the evaluators' batch kernel is built (its lazy builder has run or was never needed)."""
    return getattr(ev.functions, "_build", None) is None

