"""Refinement of a singularity map to exact curves: crossing location and curve tracing (issue 8).

A map fixes two position-level *axis coordinates* ``a(q) = (x, y)`` of a mechanism with
``F`` degrees of freedom; the remaining ``F − 2`` coordinates are *held*.  With the
closure ``Φ(q) = 0`` this leaves, at each axis point, a square position problem (the
map's grid), and with one more equation ``T(q) = 0`` a 1-D solution set: a singular
curve.  ``T`` is one of the signed DKP test functions of the one analysis core,
``det[J_S; P̂] / sqrt(det(J_S J_Sᵀ))`` for the input rows (``DKP-input``, type 2, eq. 12)
or the output rows (``DKP-output``, type 1, eq. 16), taken as a CasADi expression from
the ``indicators`` Function of :mod:`symkin.numeric.evaluators` (no copy of it here).

Contract with the map engine
----------------------------
:func:`refine` ``(system, grid, mode, tolerances, box)`` returns ``(curves, points, stats)``.

``system``
    the map's :class:`symkin.workspace.system.MapSystem` (its ``constraints`` and ``axes``
    Functions, ``hold_values``, ``evaluators``), or a :class:`LocusSystem` built from it
    (:meth:`LocusSystem.of`): an SX symbol ``q`` of the ``nf`` free coordinates,
    ``constraints`` (SX, dimensionless: ``Φ_S/ℓ`` and the held coordinates, ``nf − 2``
    rows), ``axes`` (SX, 2 rows, in *axis values*: the user's unit, model lengths or
    degrees / radians as the map's ``unit``) and ``axis_scale`` (axis values per
    dimensionless unit: ``ℓ`` for a length axis, one radian in the user's unit for an
    angle), ``ℓ`` the model's length scale.
``grid`` (:class:`GridData`)
    ``xs`` (nx,), ``ys`` (ny,) axis values in the user's unit (as ``axes``); arrays of shape ``(ny, nx)`` indexed
    ``[j, i]`` ↔ ``(xs[i], ys[j])``: ``assembled`` (bool), ``dkp_input``, ``dkp_output``,
    ``im_indicator`` and ``trace`` (NaN where not assembled), and ``q`` (``(ny, nx, nf)``)
    or a callable ``configuration(j, i) -> q | None`` when configurations are not stored.
``box``
    ``((x_lo, x_hi), (y_lo, y_hi))`` in axis values (default: the grid's extent).

Algorithm
---------
1. **Crossings** — every grid edge whose two assembled ends have opposite signs of a DKP
   test function brackets a crossing.  The root is searched along the edge (Brent's
   method on ``T`` of the square problem solved at interpolated axis values, warm-started
   from the nearer end), then polished by Gauss–Newton on the extended system
   ``(Φ/ℓ, holds, a(q)/axis_scale − (a₀ + s·d), T) = 0`` in ``(q/ℓ, s)``.
2. **Folds** — an edge from an assembled to an unassembled end brackets the mode's
   workspace boundary (a fold of the square problem).  Bisection on "the square problem
   still solves from the assembled neighbour" narrows it; the same extended system with
   the DKP test function that vanishes there (``DKP-output`` in a workspace map,
   ``DKP-input`` in a joint-space map: the smaller of the two) polishes it.
3. **Tracing** — from a located point, pseudo-arclength continuation
   (:func:`symkin.paths.continuation.continue_curve`) of ``(Φ/ℓ, holds, T) = 0`` in
   ``y = q/ℓ`` with both axis coordinates free, in both directions, until the curve
   *closes* (passes its start again in the same direction), *leaves the box* (the last
   point is solved onto the box edge), *meets the workspace boundary* of the mode (the
   other DKP test function changes sign: located by
   :func:`symkin.paths.events.locate_sign_change`), meets another locus at a branch point
   (``det[H'; tᵀ]`` changes sign), nears an IM configuration (the relative IM indicator
   ``sqrt(λ_{F+1}/tr G)`` at a point, or its located minimum between points
   (:func:`symkin.paths.events.locate_minimum`), below :attr:`Tolerances.near_branch`:
   ``T`` is not defined at IM; the IM configuration is then refined as in step 4) or
   cannot be continued.  On the way, a **cusp** of the curve's image in the axes (the axis
   velocity ``∂A/∂y · t`` reverses between two points) is located along the curve and kept
   when the relative axis speed there is at most :attr:`Tolerances.event_threshold`
   (:func:`locate_cusp`); it neither stops nor splits the curve.  A crossing that lies on a curve already traced (configuration
   within a few cell sizes of its polyline in ``q``) is not traced again.
4. **IM points** — at each grid node whose IM indicator is below its eight neighbours,
   the cells around it are subdivided (:func:`symkin.workspace.quadtree.subdivide` with the
   IM indicator as ``T``: it has no sign change, so the quadtree descends to the finest cell
   holding its smallest value), and from there (then from the node)
   :func:`symkin.paths.events.refine_rank_drop` looks for a nearby configuration where
   the constraints lose rank; the core decides whether it is IM (it is then reported).
5. **Dips, quadtree, double zeros** — a grid point whose ``|T|`` is a near-zero minimum along
   a grid line (:func:`symkin.workspace.quadtree.dips`) starts an adaptive subdivision of the
   cells around it (:func:`symkin.workspace.quadtree.subdivide`, to :data:`~symkin.workspace.quadtree.DEPTH`):
   its finest sign changes are located as in step 1 (two crossings in one cell, a small
   closed curve), its finest minima by :func:`locate_double_zero` (``T = 0`` with
   ``∂T/∂n = 0``); a double zero the core confirms is traced by :func:`trace_double_zero`.
6. **Points** — where a curve ends on the mode boundary or near IM, the end
   configuration is classified by the core (:meth:`Evaluators.indicators_at`) and
   reported as a :class:`SingularPoint` (``kind`` ``"IM"`` when IM, else ``"meeting"``
   when it has two or more types, else its type); a cusp inside the box is reported with
   ``kind`` ``"cusp"`` and the core's types.

Accuracy: every located and traced point satisfies ``‖(Φ/ℓ, holds, T)‖ ≤ 1e-12``
(Newton's tolerance), i.e. it lies on its locus to ~1e-12 relative to ``ℓ`` where the
locus is regular; crossings are polished until the Gauss–Newton step is below 1e-10
relative (``‖Δ(q/ℓ)‖``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import casadi as ca
import numpy as np
from scipy.linalg import null_space
from scipy.optimize import brentq

from symkin.analysis.batch import Evaluators
from symkin.errors import NotConvergedError, SymkinError
from symkin.numeric.evaluators import INDICATOR_NAMES
from symkin.numeric.sx_linalg import givens_qr
from symkin.paths.continuation import CurvePoint, Settings, continue_curve, newton, tangent
from symkin.paths.events import TestFunction, locate_minimum, locate_sign_change, refine_rank_drop
from symkin.tolerances import DEFAULT, Tolerances
from symkin.workspace import quadtree

__all__ = ["LocusSystem", "GridData", "Curve", "SingularPoint", "RefineStats", "refine",
           "locate_crossing", "locate_fold", "locate_double_zero", "locate_cusp", "trace_locus", "trace_double_zero",
           "KINDS"]

#: curve kinds and the indicator output that defines each
KINDS = {"DKP-input": "dkp_input", "DKP-output": "dkp_output"}
_OTHER = {"DKP-input": "DKP-output", "DKP-output": "DKP-input"}
#: Gauss–Newton tolerance of located points (residual, dimensionless)
_NEWTON_TOL = 1e-12
#: relative step at which a located point counts as polished (the issue's 1e-10)
_POLISH = 1e-10
#: relative displacement at which a 0/0 derivative of the indicator kernel is re-evaluated
_JACOBIAN_BUMP = 1e-12


# ---------------------------------------------------------------------- inputs
@dataclass(eq=False)
class LocusSystem:
    """The map's position problem as SX expressions (see the module docstring)."""

    evaluators: Evaluators
    q: ca.SX
    constraints: ca.SX
    axes: ca.SX
    axis_scale: tuple[float, float]

    @property
    def scale(self) -> float:
        return float(self.evaluators.mech.length_scale)

    @property
    def nf(self) -> int:
        return int(self.q.numel())

    @classmethod
    def of(cls, system: Any) -> "LocusSystem":
        """The locus problem of a map position problem (a :class:`symkin.workspace.system.MapSystem`).

        ``constraints`` are the system's ``constraints`` Function (closure rows ``Φ_S/ℓ`` and
        the held coordinates at ``hold_values``), ``axes`` its ``axes`` Function converted to
        the user's unit (:meth:`MapSystem.to_user`: model lengths, degrees or radians), and
        ``axis_scale`` is ``ℓ`` for a length axis and one radian in the user's unit for an
        angle.  A :class:`LocusSystem` is returned as it is.

        >>> from symkin.model.catalogue import get
        >>> from symkin.workspace.system import map_system
        >>> mech = get("rrr_3")
        >>> ls = LocusSystem.of(map_system(mech, "velocity:C1.x", "rotation:platform", hold=["velocity:C1.y"]))
        >>> ls.nf, ls.constraints.numel(), ls.axis_scale[0] == mech.length_scale, round(ls.axis_scale[1], 4)
        (12, 10, True, 57.2958)
        """
        if isinstance(system, LocusSystem):
            return system
        try:
            fn, ev = system.functions, system.evaluators
            q = ca.SX.sym("q", ev.nf)
            cons = fn["constraints"](q, ca.DM(np.asarray(system.hold_values, float)))[0]
            factors = np.asarray(system.to_user(np.ones(2)), float)  # user units per internal unit
            axes = fn["axes"](q)[0] * ca.DM(factors)
            ell = float(ev.mech.length_scale)
            scale = tuple(ell if c.kind == "length" else float(f) for c, f in zip(system.axes, factors))
        except (AttributeError, KeyError, TypeError) as exc:
            raise SymkinError(f"refinement needs a map position problem (symkin.workspace.system.MapSystem), "
                              f"got {type(system).__name__} ({exc})") from None
        return cls(ev, q, cons, axes, scale)


@dataclass(frozen=True, eq=False)
class GridData:
    """Grid values of one mode (arrays ``(ny, nx)`` indexed ``[j, i]`` ↔ ``(xs[i], ys[j])``)."""

    xs: np.ndarray
    ys: np.ndarray
    assembled: np.ndarray
    dkp_input: np.ndarray
    dkp_output: np.ndarray
    im_indicator: np.ndarray | None = None
    trace: np.ndarray | None = None
    q: np.ndarray | None = None
    configuration: Callable[[int, int], np.ndarray | None] | None = None
    #: the mode's seed configuration: where no configuration was kept (an IM-indicator minimum
    #: of a grid without stored configurations), one is re-solved along assembled grid points from it
    seed: np.ndarray | None = None

    def config(self, j: int, i: int) -> np.ndarray | None:
        """The configuration at ``[j, i]``: from ``q`` when stored there, else from ``configuration``; or None."""
        if not self.assembled[j, i]:
            return None
        if self.q is not None:
            q = np.asarray(self.q[j, i], float)
            if np.all(np.isfinite(q)):
                return q
        if self.configuration is not None:
            q = self.configuration(j, i)
            return None if q is None or not np.all(np.isfinite(q)) else np.asarray(q, float)
        if self.q is None:
            raise SymkinError("refinement needs the grid's configurations (q) or a way to re-solve them")
        return None

    def at(self, j: int, i: int) -> np.ndarray:
        return np.array([self.xs[i], self.ys[j]], float)


# ---------------------------------------------------------------------- results
@dataclass(frozen=True, eq=False)
class Curve:
    """A traced singular curve of one mode.

    ``points`` (N, 2) in axis values, ordered along the curve (a closed curve's last point
    joins its first, which is not repeated); ``configurations`` (N, nf) the free
    coordinates there; ``ends`` why each end stopped (``"closed"``, ``"box"``,
    ``"boundary"``, ``"branch"``, ``"IM"``, ``"stalled"``, ``"steps"``).
    """

    kind: str
    mode: Any
    closed: bool
    points: np.ndarray = field(repr=False)
    configurations: np.ndarray = field(repr=False)
    ends: tuple[str, ...] = ()
    evaluations: int = 0

    def to_dict(self) -> dict:
        return {"kind": self.kind, "mode": self.mode, "closed": bool(self.closed),
                "points": [[float(a), float(b)] for a, b in self.points]}


@dataclass(frozen=True, eq=False)
class SingularPoint:
    """An isolated singular point (an IM point, where a curve meets the mode boundary, a cusp), classified by the core."""

    kind: str
    mode: Any
    at: np.ndarray
    types: tuple[str, ...]
    configuration: np.ndarray = field(repr=False, default=None)

    def to_dict(self) -> dict:
        return {"kind": self.kind, "mode": self.mode, "at": [float(v) for v in self.at], "types": list(self.types)}


@dataclass
class RefineStats:
    """What refinement cost: brackets seen, located points, skipped duplicates, evaluations.

    ``located`` crossings and folds located on the grid, ``seeded`` interior curves started
    from meeting points on boundary curves, ``duplicates`` brackets or seeds that lay on a
    curve already traced; ``dips`` grid dips subdivided, ``subdivided`` points the quadtree
    solved, ``double_zeros`` double zeros located; ``*_evaluations`` count
    residual-and-Jacobian evaluations.
    """

    crossings: int = 0
    folds: int = 0
    located: int = 0
    seeded: int = 0
    im_candidates: int = 0
    duplicates: int = 0
    failed: int = 0
    locate_evaluations: int = 0
    trace_evaluations: int = 0
    traced_points: int = 0
    dips: int = 0
    subdivided: int = 0
    double_zeros: int = 0

    @property
    def evaluations_per_located_point(self) -> float:
        return self.locate_evaluations / self.located if self.located else math.nan


# ---------------------------------------------------------------------- CasADi problems
class _Counted:
    """Calls of the residual/Jacobian Functions (one count per evaluation)."""

    n = 0


class _Problems:
    """The CasADi Functions refinement evaluates, in ``y = q/ℓ`` and dimensionless axes ``A = a/axis_scale``."""

    def __init__(self, system: LocusSystem, tolerances: Tolerances = DEFAULT):
        self.system = system
        ev = system.evaluators
        if not ev.fast:
            raise SymkinError(f"{ev.mech.name}: the DKP test functions need the indicator kernel "
                              "(nf - F independent constraint rows); refinement is not available")
        self.scale = system.scale
        self.counter = _Counted()
        q = system.q
        y = ca.SX.sym("y", system.nf)
        qy = self.scale * y
        ind = ev.symbolic_function("indicators")(q)
        named = dict(zip(INDICATOR_NAMES, ind))
        g = ca.substitute(system.constraints, q, qy)
        ax = ca.substitute(system.axes / ca.DM(np.array(system.axis_scale)), q, qy)
        tests = {k: ca.substitute(named[v], q, qy) for k, v in KINDS.items()}
        rel_im = ca.sqrt(ca.fmax(ca.substitute(named["im"] / named["trace"], q, qy), 0))
        # the entry pairs of the kernel's Givens QR of J_Sᵀ (the same rows, the same rotations): where
        # both entries of a pair vanish the QR is not differentiable (see :meth:`degenerate`)
        js = ca.substitute(ev.symbolic_function("J")(q)[1], q, qy)[list(ev.basis_rows), :]
        pairs: list = []
        givens_qr([[js[j, i] for j in range(js.shape[0])] for i in range(js.shape[1])], js.shape[0], pairs)
        pv = ca.vertcat(*[ca.vertcat(a, b) for a, b in pairs]) if pairs else ca.SX(0, 1)
        self._pairs = ca.Function("givens_pairs", [y], [pv, ca.jacobian(pv, y)])
        self._rank = float(Tolerances.of(tolerances).rank)
        self.n_constraints = int(g.numel())
        self._axes = ca.Function("axes", [y], [ax, ca.jacobian(ax, y)])
        self._tests = ca.Function("tests", [y], [tests["DKP-input"], tests["DKP-output"], rel_im])
        self._curve = {k: ca.Function(f"locus_{KINDS[k]}", [y], [ca.vertcat(g, t), ca.jacobian(ca.vertcat(g, t), y)])
                       for k, t in tests.items()}
        self._constraints = ca.Function("constraints", [y], [g, ca.jacobian(g, y)])
        target = ca.SX.sym("target", 2)
        sq = ca.vertcat(g, ax - target)
        self._square = ca.Function("square", [y, target], [sq, ca.jacobian(sq, y)])
        s = ca.SX.sym("s")
        a0, d = ca.SX.sym("a0", 2), ca.SX.sym("d", 2)
        z = ca.vertcat(y, s)
        self._extended = {}
        for k, t in tests.items():
            e = ca.vertcat(g, ax - (a0 + s * d), t)
            self._extended[k] = ca.Function(f"extended_{KINDS[k]}", [z, a0, d], [e, ca.jacobian(e, z)])

        self._slopes: dict = {}

    def _slope_functions(self, kind: str):
        """``∂T/∂n`` on the solution surface, ``n`` a direction of the dimensionless axes (built on first use).

        ``G(y; n) = ∇_y T · w``, ``w`` the surface direction with ``∂A/∂y · w = n`` (the square
        problem's Jacobian solved for ``(0, n)``); the curve Function ``(y, n) ↦ ((Φ/ℓ, holds, G),
        ∂/∂y)`` and the extended one ``(z = (y, s), a0, d, n) ↦ ((Φ/ℓ, holds, A − (a0 + s·d), G), ∂/∂z)``.
        Second derivatives of ``T`` come from CasADi's AD of the indicator kernel (MX graph).
        """
        if kind in self._slopes:
            return self._slopes[kind]
        nf, nc = self.system.nf, self.n_constraints
        z = ca.MX.sym("z", nf + 1)
        y, s = z[:nf], z[nf]
        n, a0, d = ca.MX.sym("n", 2), ca.MX.sym("a0", 2), ca.MX.sym("d", 2)
        r, jr = self._curve[kind](y)
        g, grad_t = r[:nc], jr[nc, :]
        jsq = self._square(y, ca.MX.zeros(2))[1]
        rhs = ca.vertcat(ca.MX.zeros(nc, 1), n)
        w = ca.solve(jsq, rhs) if nc + 2 == nf else ca.solve(ca.mtimes(jsq.T, jsq), ca.mtimes(jsq.T, rhs))
        slope = ca.mtimes(grad_t, w)
        h = ca.vertcat(g, slope)
        ax = self._axes(y)[0]
        e = ca.vertcat(g, ax - (a0 + s * d), slope)
        yy = ca.MX.sym("y", nf)
        h_y = ca.substitute(h, z, ca.vertcat(yy, 0))
        curve = ca.Function(f"slope_{KINDS[kind]}", [yy, n], [h_y, ca.jacobian(h_y, yy)])
        ext = ca.Function(f"slope_extended_{KINDS[kind]}", [z, a0, d, n], [e, ca.jacobian(e, z)])
        value = ca.Function(f"slope_value_{KINDS[kind]}", [yy, n], [ca.substitute(slope, z, ca.vertcat(yy, 0))])
        self._slopes[kind] = (curve, ext, value)
        return self._slopes[kind]

    def slope(self, kind: str, y, n) -> float:
        """``∂T/∂n`` at ``y`` along the dimensionless axis direction ``n`` (see :meth:`_slope_functions`)."""
        self.counter.n += 1
        try:
            return float(self._slope_functions(kind)[2](y, ca.DM(np.asarray(n, float))))
        except RuntimeError as exc:  # CasADi: the square problem's Jacobian is singular at y (a fold, IM)
            raise NotConvergedError(f"∂T/∂n ({kind}) is not defined here: the square problem is singular",
                                    y=np.asarray(y, float).ravel()) from exc

    def slope_curve(self, kind: str, n) -> "_Curve":
        """The curve ``(Φ/ℓ, holds, ∂T/∂n) = 0``: through a double zero of ``T`` it follows that locus."""
        return _Curve(self._slope_functions(kind)[0], self.counter, (ca.DM(np.asarray(n, float)),),
                      degenerate=self.degenerate)

    def slope_extended(self, kind: str, a0, d) -> "_Fn":
        n = np.asarray(d, float) / np.linalg.norm(d)
        return _Fn(self._slope_functions(kind)[1], self.counter, (ca.DM(a0), ca.DM(d), ca.DM(n)),
                   degenerate=lambda z: self.degenerate(np.asarray(z, float)[:-1]))

    # numbers
    def axes(self, y) -> np.ndarray:
        return np.array(self._axes(y)[0]).ravel()

    def tests(self, y) -> dict[str, float]:
        a, b, c = (float(v) for v in self._tests(y))
        return {"DKP-input": a, "DKP-output": b, "im": c}

    def degenerate(self, y) -> bool:
        """Whether the kernel's derivative at ``y`` is one-sided: a Givens pair ``(a, b) = (0, 0)``
        whose entries do not stay 0 on the solution surface ``(Φ_S/ℓ, holds) = 0`` through ``y``.

        There the radius ``hypot(a, b)`` is not differentiable and the kernel's derivative
        (finite, :func:`symkin.numeric.sx_linalg.root`) is right only along directions that
        keep the pair at zero.  When the pair stays zero along the surface (a bar kept
        parallel to an axis: a slice at constant orientation) it is the right derivative on
        the surface; otherwise (a five-bar's locus crossing its symmetry line) the caller
        takes the Jacobian a rounding step away.  "Stays zero": the pair's gradients along
        an orthonormal basis of the surface's tangent space are at most ``Tolerances.rank``
        (``y`` and the rows are dimensionless).
        """
        v, jac = self._pairs(y)
        v = np.array(v).ravel()
        if v.size == 0:
            return False
        both = np.flatnonzero((v[0::2] == 0.0) & (v[1::2] == 0.0))
        if both.size == 0:
            return False
        jac = np.array(jac)
        rows = np.concatenate([2 * both, 2 * both + 1])
        tangent_space = null_space(np.array(self._constraints(y)[1]))
        return bool(np.max(np.abs(jac[rows] @ tangent_space), initial=0.0) > self._rank)

    def curve(self, kind: str) -> "_Curve":
        return _Curve(self._curve[kind], self.counter, degenerate=self.degenerate)

    def constraints(self) -> "_Fn":
        """The 2-D solution surface ``(Φ_S/ℓ, holds)(y) = 0`` (axes free)."""
        return _Fn(self._constraints, self.counter)

    def solve_square(self, target: np.ndarray, y0: np.ndarray) -> np.ndarray:
        """Free coordinates ``y`` at dimensionless axis values ``target`` (Newton from ``y0``)."""
        return newton(_Fn(self._square, self.counter, (ca.DM(target),)), y0, tol=_NEWTON_TOL, max_iterations=25)[0]

    def square_singular(self, y: np.ndarray, tol: Tolerances) -> bool:
        """Whether the square position problem is singular at ``y``: ``σ_min ≤ event_threshold · σ_max``.

        Its rows are dimensionless, so the relative test is scale invariant; the threshold
        is the core's path-event threshold (:attr:`Tolerances.event_threshold`).
        """
        jac = np.array(self._square(y, ca.DM.zeros(2))[1])
        sv = np.linalg.svd(jac, compute_uv=False)
        return bool(sv[-1] <= tol.event_threshold * sv[0])

    def extended(self, kind: str, a0: np.ndarray, d: np.ndarray) -> "_Fn":
        return _Fn(self._extended[kind], self.counter, (ca.DM(a0), ca.DM(d)),
                   degenerate=lambda z: self.degenerate(np.asarray(z, float)[:-1]))


class _Fn:
    """A CurveProblem-like wrapper of a CasADi Function ``(z, *params) -> (r, J)`` that counts calls."""

    def __init__(self, fn, counter, params=(), degenerate=None):
        self.fn, self.counter, self.params, self.degenerate = fn, counter, params, degenerate

    def residual_and_jacobian(self, z):
        self.counter.n += 1
        try:
            r, j = self.fn(z, *self.params)
        except RuntimeError as exc:  # CasADi: an evaluation failed (a kernel step not defined there)
            raise NotConvergedError(f"{self.fn.name()} could not be evaluated here",
                                    y=np.asarray(z, float).ravel()) from exc
        r, j = np.array(r).ravel(), np.array(j)
        if np.all(np.isfinite(r)) and (not np.all(np.isfinite(j)) or
                                       (self.degenerate is not None and self.degenerate(np.asarray(z, float)))):
            j = self._nearby_jacobian(np.asarray(z, float))
        return r, j

    def _nearby_jacobian(self, z):
        """The Jacobian a rounding step away, where the kernel is not differentiable (see below).

        The indicator kernel's Givens rotations take ``hypot(a, b)`` of two entries of the
        constraint rows; where both vanish exactly (a bar exactly parallel to an axis, e.g.
        on a symmetry line) the value is right and its derivative finite
        (:func:`symkin.numeric.sx_linalg.root`) but one-sided: right only along directions
        that keep the entries zero (a slice at constant orientation), not across them (a
        five-bar's locus through its symmetry line).  The Jacobian at ``z + δ``,
        ``|δ| ~ 1e-12`` relative, is then used (it differs by ~1e-12).
        """
        bump = _JACOBIAN_BUMP * np.maximum(1.0, np.abs(z)) * np.cos(np.arange(z.size) + 0.5)
        for k in range(1, 4):
            j = np.array(self.fn(z + k * bump, *self.params)[1])
            if np.all(np.isfinite(j)):
                return j
        return j

    def residual(self, z):
        return self.residual_and_jacobian(z)[0]

    def jacobian(self, z):
        return self.residual_and_jacobian(z)[1]


class _Curve(_Fn):
    """The locus ``(Φ/ℓ, holds, T)(y) = 0`` as a :class:`~symkin.paths.continuation.CurveProblem`."""


# ---------------------------------------------------------------------- location
def _polish(pb: _Problems, kind: str, a0: np.ndarray, d: np.ndarray, y: np.ndarray, s: float
            ) -> tuple[np.ndarray, float]:
    """Gauss–Newton on the extended system in ``(y, s)``; raises NotConvergedError."""
    problem = pb.extended(kind, a0, d)
    z, _, _ = newton(problem, np.append(y, s), tol=_NEWTON_TOL, max_iterations=30)
    # polished: one more Newton step is below the relative target
    r, j = problem.residual_and_jacobian(z)
    step = np.linalg.lstsq(j, -r, rcond=None)[0]
    if np.linalg.norm(step) > _POLISH * max(1.0, float(np.linalg.norm(z[:-1]))):
        raise NotConvergedError("crossing not polished", y=z[:-1], residual=float(np.linalg.norm(r)))
    return z[:-1], float(z[-1])


def locate_crossing(pb: _Problems, kind: str, a_a: np.ndarray, y_a: np.ndarray, a_b: np.ndarray,
                    y_b: np.ndarray) -> tuple[np.ndarray, float]:
    """Root of ``T`` (``kind``) on the segment from dimensionless axis values ``a_a`` to ``a_b``.

    ``y_a``, ``y_b`` are the configurations of the same mode at the ends, with opposite
    signs of ``T``.  Brent's method on ``T(solve(a_a + s·d))``, warm-started from the nearer
    end, then the extended system polishes ``(y, s)``.  Returns ``(y, s)``.
    """
    d = a_b - a_a
    ta, tb = pb.tests(y_a)[kind], pb.tests(y_b)[kind]
    cache = {}

    def t_of(s):
        y0 = y_a if s <= 0.5 else y_b
        y = pb.solve_square(a_a + s * d, y0 if not cache else cache[min(cache, key=lambda k: abs(k - s))])
        cache[s] = y
        return pb.tests(y)[kind]

    # a coarse bracket is enough: the extended system polishes it quadratically
    s = brentq(lambda s: ta if s == 0 else tb if s == 1 else t_of(s), 0.0, 1.0, xtol=1e-6)
    y0 = cache.get(s, y_a if s <= 0.5 else y_b)
    return _polish(pb, kind, a_a, d, y0, s)


def locate_fold(pb: _Problems, a_a: np.ndarray, y_a: np.ndarray, a_b: np.ndarray,
                bisections: int = 16, tol: Tolerances = DEFAULT) -> tuple[str, np.ndarray, float]:
    """The mode's workspace boundary on the segment from assembled ``a_a`` (config ``y_a``) to ``a_b``.

    Bisection on whether the square problem solves from the last assembled point (a
    Newton step that does not converge, or that moves farther than the bracket allows,
    counts as not assembled), then the extended system with the DKP test function that is
    smaller there polishes the fold; it is accepted when the square problem is singular
    there (:meth:`_Problems.square_singular`), else the other function is tried.  Returns
    ``(kind, y, s)``; raises NotConvergedError when neither gives a fold (a map whose axes
    mix inputs and outputs: its folds are neither locus).
    """
    d = a_b - a_a
    lo, hi, y_lo = 0.0, 1.0, np.array(y_a, float)
    for _ in range(bisections):
        mid = 0.5 * (lo + hi)
        try:
            y = pb.solve_square(a_a + mid * d, y_lo)
        except NotConvergedError:
            hi = mid
            continue
        lo, y_lo = mid, y
    t = pb.tests(y_lo)
    tried = sorted(KINDS, key=lambda k: abs(t[k]) if math.isfinite(t[k]) else math.inf)
    for kind in tried:
        try:
            y, s = _polish(pb, kind, a_a, d, y_lo, lo)
        except NotConvergedError:
            continue
        if pb.square_singular(y, tol):
            return kind, y, s
    raise NotConvergedError("the mode's boundary here is not a zero of a DKP test function "
                            "(the square position problem stays regular where they vanish)", y=y_lo)


def locate_double_zero(pb: _Problems, kind: str, a0: np.ndarray, y0: np.ndarray, d: np.ndarray,
                       tol: Tolerances = DEFAULT) -> tuple[np.ndarray, float]:
    """A double zero of ``T`` (``kind``) on the line ``a0 + s·d``, ``|s| ≤ 1``, through a dip at ``a0``.

    Where ``T`` touches zero without changing sign (``T ≈ c·d²``) it has no root to bracket;
    its derivative along the line, ``∂T/∂n`` (:meth:`_Problems.slope`, ``n = d/|d|``), changes
    sign there instead (a simple zero).  Brent's method on ``∂T/∂n`` of the square problem
    solved along the line (from ``y0``, the dip's configuration), then Gauss–Newton on the
    extended system ``(Φ/ℓ, holds, A − (a0 + s·d), ∂T/∂n) = 0`` in ``(y, s)`` polishes it.
    The point is a double zero when ``|T|`` there is at most :attr:`Tolerances.event_threshold`
    (a located minimum of an unsigned DKP test, as a path event); the caller asks the core.
    Returns ``(y, s)``; raises NotConvergedError (no sign change of the slope on the line, a
    minimum that is not zero, or no polished point).
    """
    d = np.asarray(d, float)
    n = d / np.linalg.norm(d)
    sign = math.copysign(1.0, pb.tests(y0)[kind])
    cache = {0.0: np.asarray(y0, float)}

    def y_of(s):
        near = min(cache, key=lambda k: abs(k - s))
        y = cache[near]
        for u in np.linspace(near, s, 3)[1:]:
            y = pb.solve_square(a0 + u * d, y)
        cache[s] = y
        return y

    def g(s):
        return sign * pb.slope(kind, y_of(s), n)

    ends = [(-1.0, 0.0), (0.0, 1.0)]
    vals = {s: g(s) for s in (-1.0, 0.0, 1.0)}
    bracket = next(((lo, hi) for lo, hi in ends if vals[lo] <= 0.0 <= vals[hi]), None)
    if bracket is None:
        raise NotConvergedError("no minimum of |T| on the line through the dip")
    s = brentq(g, *bracket, xtol=1e-9)
    y = cache[min(cache, key=lambda k: abs(k - s))]
    z, _, _ = newton(pb.slope_extended(kind, a0, d), np.append(y, s), tol=_NEWTON_TOL, max_iterations=30)
    if not abs(z[-1]) <= 1.0 + 1e-9 or abs(pb.tests(z[:-1])[kind]) > tol.event_threshold:
        raise NotConvergedError("the minimum of |T| on the line is not a zero", y=z[:-1])
    return z[:-1], float(z[-1])


def _im_candidates(grid: GridData) -> list[tuple[int, int]]:
    """Grid nodes whose IM indicator is a minimum among its eight assembled neighbours (to refine).

    Ties count: an IM point at the centre of a cell (Fig. 14: the origin of an even grid, by
    symmetry) gives four equal minima at the cell's corners; one of them is taken (the first,
    row-major: a tie with an earlier candidate among the neighbours is skipped; the located
    point is the same).  A flat block (all nine equal) is no minimum.
    """
    if grid.im_indicator is None:
        return []
    im = np.asarray(grid.im_indicator, float)
    asm = np.asarray(grid.assembled, bool) & np.isfinite(im)
    ny, nx = im.shape
    out = []
    taken = set()
    for j in range(1, ny - 1):
        for i in range(1, nx - 1):
            block, ok = im[j - 1:j + 2, i - 1:i + 2], asm[j - 1:j + 2, i - 1:i + 2]
            if not ok.all() or im[j, i] > block.min() or im[j, i] == block.max():
                continue
            if any((j + dj, i + di) in taken for dj in (-1, 0, 1) for di in (-1, 0, 1)):
                continue  # a tie next to a candidate already taken
            out.append((j, i))
            taken.add((j, i))
    return out


def _grid_path(asm: np.ndarray, start: tuple[int, int], goal: tuple[int, int]) -> list[tuple[int, int]] | None:
    """A shortest path of 8-neighbouring assembled grid nodes from ``start`` to ``goal`` (breadth first)."""
    ny, nx = asm.shape
    prev = {start: None}
    front = [start]
    while front and goal not in prev:
        nxt = []
        for j, i in front:
            for dj in (-1, 0, 1):
                for di in (-1, 0, 1):
                    p = (j + dj, i + di)
                    if 0 <= p[0] < ny and 0 <= p[1] < nx and asm[p] and p not in prev:
                        prev[p] = (j, i)
                        nxt.append(p)
        front = nxt
    if goal not in prev:
        return None
    path = [goal]
    while prev[path[-1]] is not None:
        path.append(prev[path[-1]])
    return path[::-1]


def resolve_from_seed(pb: _Problems, grid: GridData, scale: np.ndarray, target: tuple[int, int],
                      substeps: int = 4) -> np.ndarray | None:
    """The mode's configuration ``y`` at grid node ``target``, re-solved from the seed.

    Newton on the square problem (:meth:`_Problems.solve_square`) in ``substeps`` steps per
    cell: from the seed to the nearest assembled node, then node to node along a shortest
    path of assembled nodes (the grid's own continuation, for one node).  None without a
    seed or when a step does not converge.
    """
    if grid.seed is None:
        return None
    asm = np.asarray(grid.assembled, bool)
    y = np.asarray(grid.seed, float) / pb.scale
    a = pb.axes(y)
    nodes = np.argwhere(asm)
    pts = np.column_stack([np.asarray(grid.xs)[nodes[:, 1]], np.asarray(grid.ys)[nodes[:, 0]]]) / scale
    start = tuple(int(v) for v in nodes[int(np.argmin(np.linalg.norm(pts - a, axis=1)))])
    path = _grid_path(asm, start, target)
    if path is None:
        return None
    try:
        for node in path:
            b = grid.at(*node) / scale
            for t in np.linspace(0.0, 1.0, substeps + 1)[1:]:
                y = pb.solve_square(a + t * (b - a), y)
            a = b
    except NotConvergedError:
        return None
    return y


def locate_im(pb: _Problems, y0: np.ndarray, tol: Tolerances = DEFAULT) -> np.ndarray | None:
    """An IM configuration near ``y0``: where the surface ``(Φ_S/ℓ, holds) = 0`` loses rank.

    :func:`symkin.paths.events.refine_rank_drop` (Gauss–Newton on the constraints, a left
    null vector ``ψ`` of their Jacobian and its normalisation) from the grid configuration
    of an IM-indicator minimum.  Where the IM configurations at that point form a family
    (Fig. 14: with P on the common pivot the collapsed rhombus turns freely about it) the
    Gauss–Newton steps need not vanish, only their component across the family; the point
    it settles on is then accepted when it closes (residual at Newton's tolerance) and its
    relative ``σ_{F+1}`` is at most :attr:`Tolerances.event_threshold` (as a path event).
    None otherwise.  The caller asks the core whether the configuration is IM.
    """
    y, ok = refine_rank_drop(pb.constraints(), y0, 1)
    if not np.all(np.isfinite(y)):
        return None
    if not ok:
        closes = float(np.linalg.norm(pb.constraints().residual(y))) <= 10 * _NEWTON_TOL
        if not (closes and pb.tests(y)["im"] <= tol.event_threshold):
            return None
    return y


def _im_through_quadtree(pb: _Problems, a_c: np.ndarray, y_c: np.ndarray, cell: np.ndarray, box_d: np.ndarray,
                         tol: Tolerances, stats: "RefineStats") -> np.ndarray | None:
    """An IM configuration near the grid's IM-indicator minimum at ``a_c`` (config ``y_c``), through the quadtree.

    The IM indicator (the relative ``σ_{F+1}``, §V) is positive, so it has no sign change to
    bracket: the cells around the minimum are subdivided (:func:`symkin.workspace.quadtree.subdivide`
    with the IM indicator as ``T``) down to the finest cell holding the smallest value, and
    :func:`locate_im` starts from that cell's point (an IM point between grid points that the
    coarse grid does not resolve, Fig. 14), then from the grid point itself.  The finest
    points are tried nearest to zero first; the first located configuration is returned
    (None when none is: the core decides afterwards whether it is IM).
    """
    def sample(a, y0):
        y = pb.solve_square(a, y0)
        return y, pb.tests(y)["im"]

    sub = quadtree.subdivide(sample, a_c, y_c, pb.tests(y_c)["im"], cell, box_d[:, 0], box_d[:, 1])
    stats.subdivided += sub.samples
    starts = [y for _, y, _ in sorted(sub.dips, key=lambda d: pb.tests(d[1])["im"])] + [np.asarray(y_c, float)]
    for y0 in starts:
        y = locate_im(pb, y0, tol)
        if y is not None:
            return y
    return None


# ---------------------------------------------------------------------- tracing
def _segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    ab = b - a
    den = float(ab @ ab)
    u = 0.0 if den == 0 else min(1.0, max(0.0, float((p - a) @ ab) / den))
    return float(np.linalg.norm(p - (a + u * ab)))


def _polyline_distance(p: np.ndarray, poly: np.ndarray, closed: bool) -> float:
    if len(poly) == 1:
        return float(np.linalg.norm(p - poly[0]))
    a, b = poly[:-1], poly[1:]
    if closed:
        a, b = np.vstack([a, poly[-1:]]), np.vstack([b, poly[:1]])
    ab = b - a
    den = np.einsum("ij,ij->i", ab, ab)
    u = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.where(den > 0, den, 1), 0, 1)
    return float(np.min(np.linalg.norm(p - (a + u[:, None] * ab), axis=1)))


def axis_velocity(pb: _Problems, y: np.ndarray, t: np.ndarray) -> np.ndarray:
    """``dA/ds = ∂A/∂y · t``: the velocity of the dimensionless axes along the curve's unit tangent ``t``."""
    return np.array(pb._axes(y)[1]) @ np.asarray(t, float)


def relative_axis_speed(pb: _Problems, y: np.ndarray, t: np.ndarray) -> float:
    """``‖∂A/∂y · t‖ / ‖∂A/∂y‖₂``: how fast the axes move along the curve, relative to how fast they can.

    ``y = q/ℓ`` and ``A = a/axis_scale`` are dimensionless and ``t`` is a unit vector, so the
    ratio is the same for a model in millimetres and in metres (and under rigid motions).  It is
    zero exactly where the projection of the configuration-space curve onto the axes stops: a cusp.
    """
    ja = np.array(pb._axes(y)[1])
    return float(np.linalg.norm(ja @ np.asarray(t, float)) / np.linalg.norm(ja, 2))


def locate_cusp(pb: _Problems, problem: _Curve, a: CurvePoint, b: CurvePoint, v_a: np.ndarray,
                tol: Tolerances = DEFAULT) -> np.ndarray | None:
    """A cusp of the curve's projection onto the axes between accepted curve points ``a`` and ``b``.

    A singular curve is smooth in configuration space; its image in the axes has a cusp where
    the axis velocity ``v = ∂A/∂y · t`` (:func:`axis_velocity`) vanishes while the curve moves
    (``t`` is a unit tangent): ``v`` turns back there, ``v(s) ≈ (s − s₀)·w``.  The caller
    brackets it by ``v(a) · v(b) < 0``; the root of the signed scalar ``v(s) · v(a)/‖v(a)‖`` is
    located along the curve (:func:`symkin.paths.events.locate_sign_change`: Brent's method on
    the arclength of the Newton-projected curve, to ``1e-14``), where both components of ``v``
    vanish at a cusp.  It is a cusp when the relative axis speed there
    (:func:`relative_axis_speed`, scale invariant) is at most :attr:`Tolerances.event_threshold`
    (the core's threshold for a located zero of a path test, ``1e-7`` by default; a located cusp
    has ~1e-13, a curve that merely turns sharply within a step has a speed of order one).
    Returns the configuration ``y`` (dimensionless) or None.
    """
    v_a = np.asarray(v_a, float)
    u = v_a / np.linalg.norm(v_a)
    test = TestFunction("cusp", lambda yy, tt: float(axis_velocity(pb, yy, tt) @ u))
    try:
        ev = locate_sign_change(problem, test, a, b)
    except (NotConvergedError, ValueError):
        return None
    if relative_axis_speed(pb, ev.y, ev.t) <= tol.event_threshold:
        return np.asarray(ev.y, float)
    return None


@dataclass
class _Half:
    ys: list
    end: str
    end_y: np.ndarray | None = None
    meetings: list = field(default_factory=list)
    cusps: list = field(default_factory=list)


def _trace_half(pb: _Problems, kind: str, y0: np.ndarray, t0: np.ndarray, box: np.ndarray,
                settings: Settings, tol: Tolerances, start: CurvePoint, boundary: tuple[str, float]) -> _Half:
    """Continue from ``y0`` along ``t0`` until closed / box / boundary / branch / IM / stalled.

    ``boundary = (kind_b, sign_b)``: the test function whose zero set is the mode's
    workspace boundary and its sign inside the mode.  An interior curve (``kind ≠ kind_b``)
    stops where ``T_b`` leaves ``sign_b``; along a boundary curve the sign changes of the
    interior test function are *meeting points* (located, returned in ``meetings``: an
    interior curve starts there).
    """
    problem = pb.curve(kind)
    kind_b, sign_b = boundary
    interior = _OTHER[kind_b]
    out = [np.array(y0, float)]
    prev = None
    end, end_y, meetings = "steps", None, []
    branch = TestFunction("branch", lambda yy, tt: _branch_test(problem, yy, tt))
    b_prev = branch.f(y0, t0)
    i_prev = pb.tests(y0)[interior]
    im_test = TestFunction("im", lambda yy, tt: pb.tests(yy)["im"], signed=False, threshold=tol.near_branch)
    pprev, r_pprev, r_prev = None, math.inf, pb.tests(y0)["im"]
    cusps: list = []
    v_prev = axis_velocity(pb, y0, t0)
    try:
        for point in continue_curve(problem, y0, t0, settings):
            if prev is None:
                prev = point
                continue
            a = pb.axes(point.y)
            t = pb.tests(point.y)
            b_now = branch.f(point.y, point.t)
            crossed = kind != kind_b and math.copysign(1.0, t[kind_b]) != sign_b
            branched = b_now * b_prev < 0
            outside = bool(np.any(a < box[:, 0]) or np.any(a > box[:, 1]))
            if crossed or branched:
                # the mode's boundary or another locus between prev and point (checked before the box: a step
                # may cross both, and past the boundary the curve belongs to another mode)
                test = TestFunction(kind_b, lambda yy, tt: pb.tests(yy)[kind_b]) if crossed else branch
                end = "boundary" if crossed else "branch"
                if crossed and pb.tests(prev.y)[kind_b] * sign_b <= 0:
                    end_y = prev.y  # started on the boundary and left the mode at once: nothing to add
                    break
                try:
                    end_y = locate_sign_change(problem, test, prev, point).y
                except (NotConvergedError, ValueError):
                    end_y = prev.y
                if pb.tests(end_y)["im"] < tol.near_branch:
                    # an event next to IM is the IM point (as ``trace`` does, Tolerances.near_branch)
                    exact = locate_im(pb, end_y)
                    if exact is not None:
                        out.append(end_y)
                        end, end_y = "IM", exact
                        break
                ae = pb.axes(end_y)
                if np.any(ae < box[:, 0]) or np.any(ae > box[:, 1]):
                    out.append(_onto_box(pb, problem, prev.y, end_y, box))
                    end, end_y = "box", None
                else:
                    out.append(end_y)
                break
            if outside:
                out.append(_onto_box(pb, problem, prev.y, point.y, box))
                end = "box"
                break
            if t["im"] < tol.near_branch or not all(math.isfinite(t[k]) for k in KINDS):
                # T is not defined at IM: the curve ends here; the IM configuration is refined
                end, end_y = "IM", point.y
                out.append(point.y)
                exact = locate_im(pb, point.y)
                if exact is not None:
                    end_y = exact
                break
            if pprev is not None and r_prev < r_pprev and r_prev < t["im"] and r_prev <= settings.max_step:
                # a local minimum of the relative IM indicator σ_{F+1}, within about a step of zero (it changes
                # by about the step over a step): an IM point where loci meet?
                ev_im = locate_minimum(problem, im_test, pprev, prev, point)
                if ev_im is not None:
                    end, end_y = "IM", ev_im.y
                    out.append(ev_im.y)
                    exact = locate_im(pb, ev_im.y)
                    if exact is not None:
                        end_y = exact
                    break
            if kind == kind_b and t[interior] * i_prev < 0:
                test = TestFunction(interior, lambda yy, tt: pb.tests(yy)[interior])
                try:
                    meetings.append(locate_sign_change(problem, test, prev, point).y)
                except (NotConvergedError, ValueError):
                    pass
            v_now = axis_velocity(pb, point.y, point.t)
            if float(v_now @ v_prev) < 0.0:
                # the axis velocity turned back within the step: a cusp of the curve's projection?
                cusp = locate_cusp(pb, problem, prev, point, v_prev, tol)
                if cusp is not None:
                    cusps.append(cusp)
            b_prev, i_prev, v_prev = b_now, t[interior], v_now
            pprev, r_pprev, r_prev = prev, r_prev, t["im"]
            if point.s > 3 * settings.max_step and float(point.t @ start.t) > 0.5 and \
                    _segment_distance(start.y, prev.y, point.y) <= 0.25 * float(np.linalg.norm(point.y - prev.y)):
                end = "closed"
                break
            out.append(point.y)
            prev = point
    except NotConvergedError:  # SteppingError, or a residual/Jacobian that is not finite
        end = "stalled"
    return _Half(out, end, end_y, meetings, cusps)


def _branch_test(problem: _Curve, y: np.ndarray, t: np.ndarray) -> float:
    """``det[H'(y); tᵀ]``: changes sign at a simple branch point of the continued curve.

    Where the traced locus crosses another locus of the same equations (a fold curve
    meeting the other leg's fold: the corner of the mode's workspace), the orientation of
    the tangent relative to the curve's Jacobian flips.  Only for ``n − 1`` equations.
    """
    j = problem.jacobian(y)
    if j.shape[0] != j.shape[1] - 1:
        return 1.0
    return float(np.linalg.det(np.vstack([j, t[None, :]])))


def _onto_box(pb: _Problems, problem: _Curve, y_in: np.ndarray, y_out: np.ndarray, box: np.ndarray) -> np.ndarray:
    """The curve point on the box edge between ``y_in`` (inside) and ``y_out`` (outside)."""
    a_in, a_out = pb.axes(y_in), pb.axes(y_out)
    best, which, edge = 2.0, None, None
    for k in range(2):
        for side in (0, 1):
            e = box[k, side]
            if (a_out[k] - e) * (a_in[k] - e) < 0:
                u = (e - a_in[k]) / (a_out[k] - a_in[k])
                if u < best:
                    best, which, edge = u, k, e
    if which is None:
        return y_in
    guess = y_in + best * (y_out - y_in)

    def on_edge(y, k=which, e=edge):
        a, ja = pb._axes(y)
        return np.array([float(a[k]) - e]), np.array(ja)[k:k + 1, :]

    try:
        return newton(problem, guess, extra=on_edge, tol=_NEWTON_TOL, max_iterations=30)[0]
    except NotConvergedError:
        return y_in


def trace_locus(pb: _Problems, kind: str, y0: np.ndarray, box: np.ndarray, settings: Settings,
                tol: Tolerances = DEFAULT, boundary: tuple[str, float] = ("DKP-output", 1.0)
                ) -> tuple[np.ndarray, bool, tuple[str, ...], list, list, list]:
    """Trace the locus ``kind`` through ``y0`` both ways.

    Returns ``(ys, closed, ends, end points, meeting points, cusps)`` in ``y = q/ℓ`` (see
    :func:`_trace_half` for ``boundary``, :func:`locate_cusp` for the cusps: located on the
    way, they neither stop nor split the curve).
    """
    problem = pb.curve(kind)
    t0 = tangent(problem, y0)
    start = CurvePoint(np.array(y0, float), t0, 0.0)
    fwd = _trace_half(pb, kind, y0, t0, box, settings, tol, start, boundary)
    if fwd.end == "closed":
        return np.array(fwd.ys), True, ("closed",), [], fwd.meetings, fwd.cusps
    bwd = _trace_half(pb, kind, y0, -t0, box, settings, tol, CurvePoint(start.y, -t0, 0.0), boundary)
    ys = np.array(bwd.ys[:0:-1] + fwd.ys)
    ends = (bwd.end, fwd.end)
    return (ys, False, ends, [h.end_y for h in (bwd, fwd) if h.end_y is not None], bwd.meetings + fwd.meetings,
            bwd.cusps + fwd.cusps)


def _perp(v: np.ndarray) -> np.ndarray:
    return np.array([-v[1], v[0]]) / np.linalg.norm(v)


def _axis_tangent(pb: _Problems, y: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The curve's tangent ``t`` (in ``y``) as a direction of the dimensionless axes."""
    v = np.array(pb._axes(y)[1]) @ t
    return v / np.linalg.norm(v)


#: a double-zero curve is followed as ``∂T/∂n = 0`` with ``n`` frozen while it stays within this angle
#: of the curve's normal (``∂T/∂n`` is a regular equation of the curve while ``n`` is not along it)
_NORMAL_TURN = math.radians(30.0)


def _trace_double_half(pb: _Problems, kind: str, y0: np.ndarray, t0: np.ndarray, box: np.ndarray,
                       settings: Settings, tol: Tolerances, boundary: tuple[str, float]) -> _Half:
    """One direction of a double-zero curve (see :func:`trace_double_zero`)."""
    kind_b, sign_b = boundary
    out = [np.array(y0, float)]
    start_t, y, t_prev = np.array(t0, float), np.array(y0, float), np.array(t0, float)
    arclength = 0.0
    end, end_y = "steps", None
    try:
        while True:
            n = _perp(_axis_tangent(pb, y, t_prev))
            problem = pb.slope_curve(kind, n)
            prev, restart = None, False
            for point in continue_curve(problem, y, t_prev, settings):
                if prev is None:
                    prev = point
                    continue
                arclength += float(np.linalg.norm(point.y - prev.y))
                a = pb.axes(point.y)
                t = pb.tests(point.y)
                if kind != kind_b and math.copysign(1.0, t[kind_b]) != sign_b:
                    end, end_y = "boundary", prev.y
                    break
                if np.any(a < box[:, 0]) or np.any(a > box[:, 1]):
                    out.append(_onto_box(pb, problem, prev.y, point.y, box))
                    end = "box"
                    break
                if t["im"] < tol.near_branch:
                    end, end_y = "IM", point.y
                    exact = locate_im(pb, point.y)
                    if exact is not None:
                        end_y = exact
                    out.append(point.y)
                    break
                if not abs(t[kind]) <= tol.event_threshold:
                    end, end_y = "left", prev.y  # the slope's zero set leaves the double zero (another branch)
                    break
                if arclength > 3 * settings.max_step and float(point.t @ start_t) > 0.5 and \
                        _segment_distance(y0, prev.y, point.y) <= 0.25 * float(np.linalg.norm(point.y - prev.y)):
                    end = "closed"
                    break
                out.append(point.y)
                prev = point
                if abs(float(_perp(_axis_tangent(pb, point.y, point.t)) @ n)) < math.cos(_NORMAL_TURN):
                    y, t_prev, restart = point.y, point.t, True
                    break
            if not restart:
                break
    except NotConvergedError:
        end = "stalled"
    return _Half(out, end, end_y, [])


def trace_double_zero(pb: _Problems, kind: str, y0: np.ndarray, box: np.ndarray, settings: Settings,
                      tol: Tolerances = DEFAULT, boundary: tuple[str, float] = ("DKP-output", 1.0)
                      ) -> tuple[np.ndarray, bool, tuple[str, ...], list, list, list]:
    """Trace a curve of double zeros of ``T`` (``kind``) through ``y0`` both ways.

    ``(Φ/ℓ, holds, T) = 0`` is singular along such a curve (``∇T = 0`` on the surface), so
    the curve is continued as ``(Φ/ℓ, holds, ∂T/∂n) = 0`` (:meth:`_Problems.slope_curve`,
    regular there), with ``n`` the curve's normal in the dimensionless axes, renewed when
    the curve turns by more than 30° from it.  Each point must keep ``|T| ≤``
    :attr:`Tolerances.event_threshold` (else the slope's zero set has left the double zero:
    end ``"left"``); ends as :func:`trace_locus` (closed, box, boundary, IM, stalled).
    Returns what :func:`trace_locus` returns.
    """
    problem = pb.slope_curve(kind, np.array([1.0, 0.0]))
    t0 = tangent(problem, y0)
    n0 = _perp(_axis_tangent(pb, y0, t0))
    t0 = tangent(pb.slope_curve(kind, n0), y0, t0)
    fwd = _trace_double_half(pb, kind, y0, t0, box, settings, tol, boundary)
    if fwd.end == "closed":
        return np.array(fwd.ys), True, ("closed",), [], [], []
    bwd = _trace_double_half(pb, kind, y0, -t0, box, settings, tol, boundary)
    ys = np.array(bwd.ys[:0:-1] + fwd.ys)
    return ys, False, (bwd.end, fwd.end), [h.end_y for h in (bwd, fwd) if h.end_y is not None], [], []


def _boundary(grid: GridData, signs: list) -> tuple[str, float]:
    """The test function whose zero set bounds the mode (no sign change on the grid) and its sign there.

    In a workspace map the square problem is singular exactly where ``DKP-output``
    vanishes, so that function keeps one sign over a mode and the mode ends where it
    vanishes (a fold); in a joint-space map the same holds for ``DKP-input``.  When
    neither changes sign on the grid, ``DKP-output`` (a workspace map) is assumed.
    """
    changing = {k for k, _, _ in signs}
    asm = np.asarray(grid.assembled, bool)
    for kind in ("DKP-output", "DKP-input"):
        if kind in changing:
            continue
        v = np.asarray(getattr(grid, KINDS[kind]), float)[asm]
        v = v[np.isfinite(v)]
        if v.size:
            return kind, float(np.sign(np.median(v))) or 1.0
    return "DKP-output", 1.0


# ---------------------------------------------------------------------- refine
def _brackets(grid: GridData):
    """Grid edges ``((j, i), (j2, i2))``: sign changes per kind, and assembled/unassembled pairs."""
    asm = np.asarray(grid.assembled, bool)
    ny, nx = asm.shape
    signs, folds = [], []
    for dj, di in ((0, 1), (1, 0)):
        a = (slice(0, ny - dj), slice(0, nx - di))
        b = (slice(dj, ny), slice(di, nx))
        for kind, arr in (("DKP-input", grid.dkp_input), ("DKP-output", grid.dkp_output)):
            if arr is None:
                continue
            v = np.asarray(arr, float)
            with np.errstate(invalid="ignore"):
                hit = asm[a] & asm[b] & (np.sign(v[a]) * np.sign(v[b]) < 0)
            for j, i in zip(*np.nonzero(hit)):
                signs.append((kind, (j, i), (j + dj, i + di)))
        for j, i in zip(*np.nonzero(asm[a] != asm[b])):
            pa, pb_ = (j, i), (j + dj, i + di)
            folds.append((pa, pb_) if asm[pa] else (pb_, pa))
    return signs, folds


def refine(system, grid: GridData, mode: Any = 0, tolerances: Tolerances = DEFAULT, box=None,
           settings: Settings | None = None) -> tuple[list[Curve], list[SingularPoint], RefineStats]:
    """Locate and trace a mode's singular curves from its grid (see the module docstring).

    Parameters
    ----------
    system : LocusSystem or an object with its attributes
    grid : GridData
    mode : any
        The mode's id, copied into the results.
    tolerances : Tolerances
        ``near_branch`` stops a curve near IM; ``rank`` classifies end points (core).
    box : ((x_lo, x_hi), (y_lo, y_hi)), optional
        In axis values; default the grid's extent.
    settings : continuation Settings, optional
        Default: steps of half a cell, at most two cells (dimensionless).

    Returns
    -------
    curves : list of Curve
    points : list of SingularPoint
    stats : RefineStats

    Examples
    --------
    The catalogue five-bar (|A_i B_i| = 1, |B_i P| = 2, A = (∓1, 0)) over a coarse grid: the
    mode's workspace boundary is the four circles |P − A_i| = 1, 3 (type 1, ``DKP-output``);
    the outer ones end where they meet, at P = (0, √8), a corner of the workspace.

    >>> import numpy as np
    >>> from symkin.model.catalogue import get
    >>> from symkin.workspace.system import map_system
    >>> from symkin.workspace.grid import continue_mode
    >>> s = map_system(get("five_bar"), "velocity:P.x", "velocity:P.y")
    >>> xs, ys = np.linspace(-3.5, 3.5, 15), np.linspace(0.2, 4.4, 10)
    >>> g = continue_mode(s, xs, ys, s.q0, keep_configurations=True)
    >>> grid = GridData(xs, ys, g.assembled, g.dkp_input, g.dkp_output, g.im_indicator, q=g.q)
    >>> curves, points, stats = refine(s, grid)
    >>> sorted(c.ends for c in curves)
    [('box', 'box'), ('box', 'box'), ('box', 'branch'), ('box', 'branch')]
    >>> err = [min(abs(np.hypot(*(c.points - (a, 0)).T) - r).max() for a in (-1, 1) for r in (1, 3)) for c in curves]
    >>> bool(max(err) < 1e-9)
    True
    >>> [(pt.kind, (abs(pt.at) + 0.0).round(9).tolist()) for pt in points]
    [('DKP-output', [0.0, 2.828427125])]
    """
    sys_ = LocusSystem.of(system)
    tol = Tolerances.of(tolerances)
    pb = _Problems(sys_, tol)
    scale = np.array(sys_.axis_scale, float)
    if box is None:
        box = ((float(np.min(grid.xs)), float(np.max(grid.xs))), (float(np.min(grid.ys)), float(np.max(grid.ys))))
    box_d = np.array(box, float) / scale[:, None]
    cell = min(abs(float(np.diff(grid.xs).min())) / scale[0], abs(float(np.diff(grid.ys).min())) / scale[1])
    if settings is None:
        settings = Settings(step=0.5 * cell, max_step=2.0 * cell, min_step=1e-6 * cell)
    stats = RefineStats()
    curves: list[Curve] = []
    traced: list = []  # (kind, ys, closed, dimensionless axis points)
    points: list[SingularPoint] = []
    dup_radius = 1.5 * cell

    def on_traced(kind, y, radius):
        return any(k == kind and _polyline_distance(y, ys, c) <= radius for k, ys, c, _ in traced)

    def near_traced(kinds, a):
        """Pre-check on the grid: the bracket's axis point within ``dup_radius`` of a traced curve."""
        return any(k in kinds and _polyline_distance(a, ax, c) <= dup_radius for k, _, c, ax in traced)

    def dim_axes(j, i):
        return grid.at(j, i) / scale

    def take(kind, y, tracer=None):
        before = pb.counter.n
        ys, closed, ends, end_ys, meets, cusps = (tracer or trace_locus)(pb, kind, y, box_d, settings, tol, boundary)
        seeds.extend(meets)
        end_ys = end_ys + meets
        stats.trace_evaluations += pb.counter.n - before
        stats.traced_points += len(ys)
        ax = np.array([pb.axes(v) for v in ys])
        traced.append((kind, ys, closed, ax))
        pts = ax * scale
        qs = ys * pb.scale
        curves.append(Curve(kind, mode, closed, pts, qs, ends, pb.counter.n - before))
        for ye in end_ys:
            _add_point(points, pb, sys_, ye, mode, scale, tol)
        for yc in cusps:
            if np.all(pb.axes(yc) >= box_d[:, 0]) and np.all(pb.axes(yc) <= box_d[:, 1]):
                _add_point(points, pb, sys_, yc, mode, scale, tol, kind="cusp")

    signs, folds = _brackets(grid)
    stats.crossings, stats.folds = len(signs), len(folds)
    boundary = _boundary(grid, signs)
    seeds: list = []  # meeting points found along boundary curves: interior curves start there
    def locate_and_take(kinds, pa, pb_, locate, errors, mid=None) -> None:
        """Locate one crossing or fold between grid points ``pa``, ``pb_`` and trace from it.

        ``mid`` (dimensionless axis values) replaces the grid pre-check: a crossing of the
        quadtree is checked only once located (it may lie within a cell of a traced curve).
        """
        if mid is None and near_traced(kinds, 0.5 * (dim_axes(*pa) + dim_axes(*pb_))):
            stats.duplicates += 1
            return
        before = pb.counter.n
        try:
            kind, y = locate()
        except errors:
            stats.failed += 1
            return
        stats.locate_evaluations += pb.counter.n - before
        stats.located += 1
        if on_traced(kind, y, 0.5 * settings.max_step):
            stats.duplicates += 1
            return
        take(kind, y)

    for kind, pa, pb_ in signs:
        qa, qb = grid.config(*pa), grid.config(*pb_)
        if qa is None or qb is None:
            continue
        ya, yb = qa / pb.scale, qb / pb.scale
        locate_and_take((kind,), pa, pb_,
                        lambda: (kind, locate_crossing(pb, kind, dim_axes(*pa), ya, dim_axes(*pb_), yb)[0]),
                        (NotConvergedError, ValueError))
    for pa, pb_ in folds:
        qa = grid.config(*pa)
        if qa is None:
            continue
        ya = qa / pb.scale
        # the grid pre-check against the boundary's kind only: a fold next to an interior curve of the
        # other kind (the Delta's type-2 curve runs within a cell of its reach boundary) is still located
        locate_and_take((boundary[0],), pa, pb_,
                        lambda: locate_fold(pb, dim_axes(*pa), ya, dim_axes(*pb_), tol=tol)[:2],
                        NotConvergedError)
    steps = np.array([abs(float(grid.xs[1] - grid.xs[0])) / scale[0], abs(float(grid.ys[1] - grid.ys[0])) / scale[1]])
    for j, i in _im_candidates(grid):
        before = pb.counter.n
        qa = grid.config(j, i)
        ya = qa / pb.scale if qa is not None else resolve_from_seed(pb, grid, scale, (j, i))
        if ya is None:
            stats.failed += 1
            continue
        y = _im_through_quadtree(pb, dim_axes(j, i), ya, steps, box_d, tol, stats)
        stats.locate_evaluations += pb.counter.n - before
        if y is None:
            stats.failed += 1
            continue
        stats.im_candidates += 1
        _add_point(points, pb, sys_, y, mode, scale, tol, only_im=True)
    interior = _OTHER[boundary[0]]
    while seeds:
        y = seeds.pop(0)
        if on_traced(interior, y, 0.5 * settings.max_step):
            stats.duplicates += 1
            continue
        stats.seeded += 1
        take(interior, y)

    def refine_dip(kind, j, i):
        """Subdivide the cells around a dip of ``T`` (:mod:`symkin.workspace.quadtree`); locate and trace."""
        a_c = dim_axes(j, i)
        if any(k == kind and _polyline_distance(a_c, ax, c) <= cell for k, _, c, ax in traced):
            stats.duplicates += 1
            return
        q = grid.config(j, i)
        y_c = q / pb.scale if q is not None else resolve_from_seed(pb, grid, scale, (j, i))
        if y_c is None:
            stats.failed += 1
            return
        stats.dips += 1
        before = pb.counter.n

        def sample(a, y0):
            y = pb.solve_square(a, y0)
            return y, pb.tests(y)[kind]

        sub = quadtree.subdivide(sample, a_c, y_c, pb.tests(y_c)[kind], steps, box_d[:, 0], box_d[:, 1])
        stats.subdivided += sub.samples
        stats.locate_evaluations += pb.counter.n - before
        for aa, ya, ab, yb in sub.crossings:
            locate_and_take((kind,), None, None,
                            lambda: (kind, locate_crossing(pb, kind, aa, ya, ab, yb)[0]),
                            (NotConvergedError, ValueError), mid=0.5 * (aa + ab))
        for a, y, h in sub.dips:
            before = pb.counter.n
            found = None
            for d in (np.array([2 * h[0], 0.0]), np.array([0.0, 2 * h[1]])):
                try:
                    found = locate_double_zero(pb, kind, a, y, d, tol)[0]
                    break
                except (NotConvergedError, ValueError):
                    continue
            stats.locate_evaluations += pb.counter.n - before
            if found is None:
                continue
            if on_traced(kind, found, 0.5 * settings.max_step):
                stats.duplicates += 1
                continue
            res = sys_.evaluators.indicators_at(found * pb.scale, tol)
            if not res["is_" + KINDS[kind]]:
                continue
            stats.located += 1
            stats.double_zeros += 1
            take(kind, found, trace_double_zero)

    for kind, name in KINDS.items():
        values = getattr(grid, name)
        if values is None:
            continue
        for j, i in zip(*np.nonzero(quadtree.dip_mask(values, grid.assembled))):
            refine_dip(kind, int(j), int(i))
    return curves, points, stats


def _add_point(points: list, pb: _Problems, system: LocusSystem, y: np.ndarray, mode, scale, tol,
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
        if same_q or (res["im"] and "IM" in p.types and same_at):
            return
    types = tuple(name for name, flag in (("IM", res["im"]), ("DKP-input", res["is_dkp_input"]),
                                           ("DKP-output", res["is_dkp_output"])) if flag)
    if kind is None:
        kind = "IM" if "IM" in types else ("meeting" if len(types) >= 2 else (types[0] if types else "end"))
    points.append(SingularPoint(kind, mode, at, types, q))
